//! `novanc translate PROG [--tools TAPE] [--magazine TCODES]` (docs/cli.md): the printed program on
//! stdout, errors on stderr as `PROG:LINE:COL: message` or `FILE:LINE: message`, exit 1.

mod common;

use common::{novanc, temp_file};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn table_b_prints_the_golden_program() {
    let out = novanc(&["translate", "programs/tableb.ap"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), include_str!("golden/tableb.iso"));
    assert!(out.stderr.is_empty());
}

#[test]
fn explicit_sample_files_give_the_same_program() {
    let out = novanc(&[
        "translate",
        "programs/tableb.ap",
        "--tools",
        "tooldata/tools.tt",
        "--magazine=tooldata/magazine.tc",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), include_str!("golden/tableb.iso"));
}

#[test]
fn a_program_error_goes_to_stderr_with_prog_line_col() {
    let p = temp_file("bad.ap", "DA1 = (200, 0, -450)\nDRL, 106/DP20/DA1, P9\n");
    let ps = p.to_string_lossy().into_owned();
    let out = novanc(&["translate", &ps]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "no partial program on stdout");
    assert_eq!(
        text(&out.stderr),
        format!("{ps}:2:20: P9 is not defined (define it on an earlier line)\n")
    );
}

#[test]
fn bad_tool_tape_and_t_code_table_are_errors() {
    let tape = temp_file("bad.tt", "00106 DR 6.2 150.0 40.0 1200 120\n");
    let ts = tape.to_string_lossy().into_owned();
    let out = novanc(&["translate", "programs/tableb.ap", "--tools", &ts]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.starts_with(&format!("{ts}:1: a tool record has 8 fields")),
        "{err}"
    );
    assert!(out.stdout.is_empty());

    let tc = temp_file("bad.tc", "T01 00610\nT99 00106\n");
    let cs = tc.to_string_lossy().into_owned();
    let out = novanc(&["translate", "programs/tableb.ap", "--magazine", &cs]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).starts_with(&format!("{cs}:2: ")),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn a_magazine_without_the_tool_names_the_tool() {
    let tc = temp_file("small.tc", "T01 00610\n");
    let cs = tc.to_string_lossy().into_owned();
    let out = novanc(&["translate", "programs/tableb.ap", "--magazine", &cs]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr),
        "programs/tableb.ap:5:6: tool 00106 is not in the magazine (no T code holds it)\n"
    );
}

#[test]
fn help_and_usage() {
    let out = novanc(&["translate", "--help"]);
    assert_eq!(out.status.code(), Some(0));
    let h = text(&out.stdout);
    assert!(h.contains("--tools TAPE") && h.contains("--magazine TCODES"));
    assert!(h.contains("G-code"));
    assert_eq!(novanc(&["translate"]).status.code(), Some(2));
    assert_eq!(novanc(&["translate", "a", "b"]).status.code(), Some(2));
    assert_eq!(
        novanc(&["translate", "x.ap", "--bogus"]).status.code(),
        Some(2)
    );
    let out = novanc(&["translate", "/nonexistent/prog.ap"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("cannot read /nonexistent/prog.ap"));
}

/// `--state DIR` translates the console's own memory (its selected program and tool file)
/// without changing a byte of it.
#[test]
fn state_uses_the_consoles_memory_and_leaves_it_alone() {
    use novanc::store::{Stores, Target};
    let dir = common::temp_dir("trstate");
    {
        let (mut s, _) = Stores::open(&dir, 24).unwrap();
        // T02's set length 150 -> 155 (TOOL DATA REVISION).
        s.edit(Target::ToolFile, "1LS150.0$-5DI155.0", None)
            .unwrap();
    }
    let files = |d: &std::path::Path| -> Vec<(String, Vec<u8>)> {
        let mut v: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| {
                (
                    e.file_name().to_string_lossy().into_owned(),
                    std::fs::read(e.path()).unwrap_or_default(),
                )
            })
            .collect();
        v.sort();
        v
    };
    let before = files(&dir);
    let out = common::novanc_command()
        .args(["translate", "--state"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // Drill 106 (T02) goes to tip -470: axis -470 + 155.
    assert!(text.contains("G01 Z-315.000 F120"), "{text}");
    assert!(!text.contains("G01 Z-320.000 F120"), "{text}");
    let out = common::novanc_command()
        .args(["translate", "NOSUCH", "--state"])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("NOSUCH is neither a program in"));
    assert_eq!(files(&dir), before, "the memory is read, never changed");
    let _ = std::fs::remove_dir_all(&dir);
}
