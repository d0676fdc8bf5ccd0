//! `novanc tape read` and `novanc tape punch` (docs/tape.md): the command line makes the golden
//! images, reads them back, prints nothing but the alarm on a bad tape, and refuses bad usage.

mod common;

use common::novanc;

use std::path::Path;

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn file(p: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join(p)).unwrap()
}

#[test]
fn punch_makes_the_golden_images_and_read_gives_back_the_files() {
    for (src, label, name) in [
        ("programs/tableb.ap", "TABLE B", "tableb"),
        ("tooldata/tools.tt", "TOOL TAPE", "tools"),
    ] {
        for code in ["iso", "eia"] {
            let out = common::temp_path(&format!("{name}.{code}"));
            let o = novanc(&[
                "tape",
                "punch",
                src,
                "--code",
                code,
                "--leader",
                "20",
                "--label",
                label,
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{}", text(&o.stderr));
            let image = std::fs::read(&out).unwrap();
            assert!(
                image == file(&format!("tests/golden/{name}.{code}.tape")),
                "{name} {code}"
            );
            assert!(text(&o.stderr).contains(&format!(
                "{} frames in the {} code",
                image.len(),
                code.to_uppercase()
            )));
            let r = novanc(&["tape", "read", out.to_str().unwrap()]);
            let _ = std::fs::remove_file(&out);
            assert!(r.status.success(), "{}", text(&r.stderr));
            assert!(r.stdout == file(src), "{name} {code}: the text differs");
            let err = text(&r.stderr);
            assert!(
                err.contains(&format!(
                    "{} code, label '{label}', {} blocks",
                    code.to_uppercase(),
                    text(&file(src)).lines().count()
                )),
                "{err}"
            );
        }
    }
}

#[test]
fn a_bad_tape_prints_the_alarm_and_no_text() {
    let mut image = file("tests/golden/tableb.iso.tape");
    image[40] ^= 0x04;
    let p = common::temp_path("bad.iso");
    std::fs::write(&p, &image).unwrap();
    let o = novanc(&["tape", "read", p.to_str().unwrap()]);
    let _ = std::fs::remove_file(&p);
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stdout.is_empty(), "no partial text: {}", text(&o.stdout));
    let err = text(&o.stderr);
    assert!(
        err.starts_with(&format!(
            "{}: TAPE PARITY ERROR at frame 41 (block 1, character 12): holes",
            p.display()
        )),
        "{err}"
    );
}

#[test]
fn block_parity_is_checked_on_request() {
    // Table B's block 1 has 20 characters: punched with a pad. Without it the count is odd.
    let image = file("tests/golden/tableb.iso.tape");
    let pad = image.iter().position(|&f| f == 0x8D).unwrap();
    let mut odd = image.clone();
    odd.remove(pad);
    let p = common::temp_path("odd.iso");
    std::fs::write(&p, &odd).unwrap();
    let lenient = novanc(&["tape", "read", p.to_str().unwrap()]);
    let strict = novanc(&["tape", "read", p.to_str().unwrap(), "--block-parity"]);
    let _ = std::fs::remove_file(&p);
    assert!(lenient.status.success());
    assert_eq!(lenient.stdout, file("programs/tableb.ap"));
    assert_eq!(strict.status.code(), Some(1));
    assert!(text(&strict.stderr).contains("TAPE BLOCK PARITY ERROR"));
    assert!(strict.stdout.is_empty());
}

#[test]
fn a_plain_text_file_reads_as_it_is() {
    let o = novanc(&["tape", "read", "programs/tableb.ap"]);
    assert!(o.status.success());
    assert_eq!(o.stdout, file("programs/tableb.ap"));
    assert!(text(&o.stderr).contains("a plain text file"));
}

#[test]
fn holes_draws_every_frame() {
    let o = novanc(&["tape", "read", "tests/golden/tableb.eia.tape", "--holes"]);
    assert!(o.status.success());
    let out = text(&o.stdout);
    assert_eq!(
        out.lines().count(),
        file("tests/golden/tableb.eia.tape").len()
    );
    assert!(out.contains("     28  ··●·●•●··  rewind stop\n"), "{out}");
    assert!(out.contains("     29  ●····•···  EOB\n"), "{out}");
    assert!(out.contains("     30  ·●●··•●··  D\n"), "{out}");
}

#[test]
fn bad_usage_and_unpunchable_text_are_refused_and_write_nothing() {
    let out = common::temp_path("never");
    let o = out.to_str().unwrap();
    for (args, code, msg) in [
        (
            vec!["tape", "punch", "programs/tableb.ap", "-o", o],
            2,
            "which code?",
        ),
        (
            vec![
                "tape",
                "punch",
                "programs/tableb.ap",
                "--code",
                "ascii",
                "-o",
                o,
            ],
            2,
            "the codes are iso and eia",
        ),
        (
            vec!["tape", "punch", "programs/tableb.ap", "--code", "iso"],
            2,
            "-o IMAGE",
        ),
        (
            vec![
                "tape",
                "punch",
                "programs/tableb.ap",
                "--code",
                "iso",
                "--leader",
                "0",
                "-o",
                o,
            ],
            2,
            "from 1 to 10000",
        ),
        (
            vec![
                "tape",
                "punch",
                "programs/tableb.ap",
                "--code",
                "eia",
                "--label",
                "50%",
                "-o",
                o,
            ],
            1,
            "programs/tableb.ap:label:3: '%' has no code in EIA",
        ),
        (vec!["tape", "read"], 2, "which image?"),
        (vec!["tape", "rewind"], 2, "unknown action 'rewind'"),
        (
            vec!["tape", "read", "/nonexistent/x.tape"],
            1,
            "cannot read /nonexistent/x.tape",
        ),
    ] {
        let r = novanc(&args);
        assert_eq!(r.status.code(), Some(code), "{args:?}: {}", text(&r.stderr));
        assert!(
            text(&r.stderr).contains(msg),
            "{args:?}: {}",
            text(&r.stderr)
        );
        assert!(!out.exists(), "{args:?} wrote an image");
    }
    let src = common::temp_path("prog.ap");
    std::fs::write(&src, "P1 = (1, 2)\nP2 = (3, 4) ; größer\n").unwrap();
    let r = novanc(&[
        "tape",
        "punch",
        src.to_str().unwrap(),
        "--code",
        "iso",
        "-o",
        o,
    ]);
    let _ = std::fs::remove_file(&src);
    assert_eq!(r.status.code(), Some(1));
    assert_eq!(
        text(&r.stderr).trim(),
        format!(
            "{}:2:17: 'ö' has no code in ISO (docs/tape.md)",
            src.display()
        )
    );
    assert!(!out.exists());
    let help = novanc(&["--help"]);
    assert!(text(&help.stdout).contains("novanc tape punch FILE --code iso|eia"));
}
