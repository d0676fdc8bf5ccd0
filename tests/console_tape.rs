//! Tape reader 13 and the punch at the console (docs/tape.md, "At the console"): PROGRAM READ
//! and TOOL DATA READ of 8-channel images at the reader's speed in machine time, the alarms
//! (every store byte for byte unchanged), STOP/RESET/E-STOP/selector abandoning a read, keys
//! refused while the tape moves, and the punch key (Alt+u) with its round trip.

mod common;

use common::{keys, open, shows, temp_dir, type_line};
use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::{DataMode, OpMode, PanelEvent as E};
use novanc::pulse_core::testkit::Rng;
use novanc::pulse_core::ClockMode;
use novanc::tape::{self, Code, PunchOptions, ReadOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// Every file under the state directory, with its bytes.
/// Every store file of a state directory, byte for byte; the message history and counters are
/// left out, since they are meant to record the alarm (docs/stores.md).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else if !p.ends_with(novanc::store::history::MESSAGES)
                && !p.ends_with(novanc::store::history::COUNTERS)
            {
                out.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// Puts `path` in the reader with the data selector on `mode` (DATA INPUT).
fn load(c: &mut Console, mode: DataMode, path: &Path) {
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(mode));
    c.handle(E::Tape(path.to_path_buf()));
}

/// Writes `bytes` to a fresh file named `name`.
fn file(name: &str, bytes: &[u8]) -> PathBuf {
    let p = temp_dir("tape-img").join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn punched(text: &str, code: Code) -> Vec<u8> {
    let o = PunchOptions {
        code,
        leader: 20,
        label: Some("TEST".into()),
    };
    tape::punch(text, &o).unwrap()
}

fn tableb() -> String {
    std::fs::read_to_string(repo("programs/tableb.ap")).unwrap()
}

#[test]
fn iso_and_eia_images_read_at_the_console_as_the_codec_reads_them() {
    for f in [
        "tests/golden/tableb.iso.tape",
        "tests/golden/tableb.eia.tape",
    ] {
        let mut c = open("tape-read");
        let image = std::fs::read(repo(f)).unwrap();
        let want = tape::read_image(&image, ReadOptions::default()).unwrap();
        load(&mut c, DataMode::Read, &repo(f));
        let t0 = c.status().machine_ns;
        c.handle(E::Start);
        assert!(c.tape_reading(), "{f}: START starts the tape");
        assert!(
            !c.is_idle(),
            "{f}: the console is busy while the tape moves"
        );
        c.handle(E::WaitMs(100));
        let v = c.tape_view().unwrap();
        assert_eq!(v.frame, 30, "{f}: 100 ms at 300 characters/s");
        assert_eq!(v.total, image.len() as u64);
        assert_eq!(v.plain, want.code.is_none());
        c.handle(E::Wait);
        assert!(!c.tape_reading() && c.is_idle(), "{f}");
        assert_eq!(c.program_text(), want.text, "{f}");
        let took = c.status().machine_ns - t0;
        let frames = want.frames;
        let ideal = frames * 1_000_000_000 / 300;
        assert!(
            took >= ideal && took < ideal + 10_000_000,
            "{f}: {frames} frames took {took} ns of machine time, not {ideal}"
        );
        let how = match want.code {
            Some(code) => format!("({} tape, {frames} frames)", code.name()),
            None => "(text file)".into(),
        };
        assert!(shows(&c, &how), "{f}:\n{}", c.frame_text());
        assert!(!c.view().lamps.alarm);
    }
}

/// A plain text file is no tape: START reads it at file speed (until issue 23 it passed at the
/// reader's 300 characters/s, so a 3 MB CAM file took about three hours).
#[test]
fn a_text_file_is_read_at_file_speed_not_at_the_readers() {
    let f = "tests/golden/frames/drill2.ap";
    let mut c = open("tape-text");
    let image = std::fs::read(repo(f)).unwrap();
    let want = tape::read_image(&image, ReadOptions::default()).unwrap();
    assert!(want.code.is_none());
    load(&mut c, DataMode::Read, &repo(f));
    let t0 = c.status().machine_ns;
    c.handle(E::Start);
    assert!(!c.tape_reading(), "a text file does not move like a tape");
    assert_eq!(c.program_text(), want.text);
    assert_eq!(c.status().machine_ns, t0, "no machine time passes");
    assert!(shows(&c, "(text file)"), "{}", c.frame_text());

    // A large CAM-sized file (3 MB) is stored whole at once.
    let mut big = String::from("%\nG21 G90 G17\n");
    let mut i = 0u64;
    while big.len() < 3 << 20 {
        big.push_str(&format!(
            "G1 X{}.{:03} Y{}.{:03} F600\n",
            i % 400,
            i % 997,
            (i / 7) % 300,
            i % 89
        ));
        i += 1;
    }
    big.push_str("M30\n%\n");
    let p = file("CAM3MB.NGC", big.as_bytes());
    load(&mut c, DataMode::Read, &p);
    c.handle(E::Start);
    assert!(!c.tape_reading());
    assert!(shows(&c, "CAM3MB"), "{}", c.frame_text());
    assert_eq!(c.program_text().lines().count(), big.lines().count());
    assert!(c.program_text().starts_with("%\nG21 G90 G17"));
    assert!(c.program_text().contains("M30"));
}

/// PROGRAM READ of a memory card folder: each file a program named after it, the first one
/// current; a folder with one file that is not text stores nothing.
#[test]
fn a_memory_card_folder_gives_a_program_per_file_or_nothing() {
    let dir = temp_dir("card");
    std::fs::write(dir.join("B2.NGC"), "G0 X1\nM30\n").unwrap();
    std::fs::write(dir.join("A1.NGC"), "G0 X2\nM30\n").unwrap();
    std::fs::write(dir.join(".hidden"), [0u8, 1, 2]).unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    let mut c = open("tape-card");
    load(&mut c, DataMode::Read, &dir);
    c.handle(E::Start);
    assert!(!c.tape_reading());
    assert!(shows(&c, "2 programs"), "{}", c.frame_text());
    assert_eq!(c.program_text(), "G0 X2\nM30\n");

    // One punched image among the files: the folder is refused and memory is unchanged.
    let bad = temp_dir("card-bad");
    std::fs::write(bad.join("C3.NGC"), "G0 X3\nM30\n").unwrap();
    std::fs::write(bad.join("D4.TAPE"), punched("G0 X4\n", Code::Iso)).unwrap();
    load(&mut c, DataMode::Read, &bad);
    c.handle(E::Start);
    assert!(shows(&c, "program memory unchanged"), "{}", c.frame_text());
    assert_eq!(c.program_text(), "G0 X2\nM30\n");

    // TOOL DATA READ takes one tool tape, not a folder.
    load(&mut c, DataMode::ToolRead, &dir);
    c.handle(E::Start);
    assert!(shows(&c, "tool file unchanged"), "{}", c.frame_text());
}

#[test]
fn the_reader_speed_is_the_machine_setting() {
    let mut cfg = ConsoleConfig::new(temp_dir("tape-speed"));
    cfg.clock = ClockMode::Virtual;
    cfg.settings.tape_chars_per_s = 1000;
    let mut c = Console::open(cfg).unwrap().0;
    load(
        &mut c,
        DataMode::Read,
        &repo("tests/golden/tableb.iso.tape"),
    );
    c.handle(E::Start);
    c.handle(E::WaitMs(100));
    assert_eq!(c.tape_view().unwrap().frame, 100);
    assert!(
        shows(&c, "reading at 1000 characters/s"),
        "{}",
        c.frame_text()
    );
}

#[test]
fn tool_data_read_of_an_image_stores_what_the_text_tape_stores() {
    let mut by_text = open("tape-tools-text");
    load(&mut by_text, DataMode::ToolRead, &repo("tooldata/tools.tt"));
    by_text.handle(E::Start);
    by_text.handle(E::Wait);
    for f in ["tests/golden/tools.iso.tape", "tests/golden/tools.eia.tape"] {
        let mut c = open("tape-tools");
        load(&mut c, DataMode::ToolRead, &repo(f));
        c.handle(E::Start);
        c.handle(E::WaitMs(1000));
        assert!(
            c.frame_text().contains("│"),
            "the strip:\n{}",
            c.frame_text()
        );
        c.handle(E::Wait);
        assert_eq!(c.magazine(), by_text.magazine(), "{f}");
        assert!(shows(&c, "T codes loaded"), "{}", c.frame_text());
    }
}

/// The corruptions of a good image the reader must stop on, each with the words its alarm must
/// hold.
fn corruptions(good: &[u8], code: Code) -> Vec<(String, Vec<u8>, Vec<String>)> {
    let eob = code.eob().0;
    let eobs: Vec<usize> = (0..good.len()).filter(|&i| good[i] == eob).collect();
    // Block 2's third character: after the opening rewind stop's EOB (eobs[0]) and block 1.
    let at = eobs[1] + 3;
    let mut out = Vec::new();
    for ch in 0..8 {
        let mut img = good.to_vec();
        img[at] ^= 1 << ch;
        let e = tape::read_image(&img, ReadOptions::default()).unwrap_err();
        out.push((
            format!("channel {} flipped", ch + 1),
            img,
            vec![
                format!("frame {}", e.frame),
                format!("block {}", e.block),
                format!("character {}", e.position),
                format!("{}", e.holes),
            ],
        ));
    }
    // A frame with the right parity that is no character of the code.
    let unknown = (1..=255u8)
        .find(|&b| {
            code.parity_ok(tape::Frame(b))
                && code.meaning(tape::Frame(b)) == tape::Meaning::NotInCode
        })
        .unwrap();
    let mut img = good.to_vec();
    img[at] = unknown;
    out.push((
        "a character not in the code".into(),
        img,
        vec![
            "CHARACTER ERROR".into(),
            format!("frame {}", at + 1),
            "block 2".into(),
            "character 3".into(),
        ],
    ));
    // The tape torn in the middle of a block: its end of block is missing.
    out.push((
        "a missing end of block".into(),
        good[..at].to_vec(),
        vec!["no end of block".into(), "block 2".into()],
    ));
    out.push(("an empty image".into(), Vec::new(), vec!["empty".into()]));
    let mut rng = Rng::new(11);
    let mut noise: Vec<u8> = (0..600).map(|_| rng.range(0, 255) as u8).collect();
    noise[0] = 0;
    out.push(("random bytes".into(), noise, vec!["TAPE".into()]));
    out
}

#[test]
fn every_read_error_stops_with_its_alarm_and_leaves_every_store_byte_for_byte_unchanged() {
    let mut cases = 0;
    for code in [Code::Iso, Code::Eia] {
        for (target, text) in [
            (DataMode::Read, tableb()),
            (
                DataMode::ToolRead,
                std::fs::read_to_string(repo("tooldata/tools.tt")).unwrap(),
            ),
        ] {
            let good = punched(&text, code);
            for (what, img, words) in corruptions(&good, code) {
                cases += 1;
                let mut c = open("tape-err");
                let dir = c.config().state_dir.clone();
                let path = file("bad.tape", &img);
                load(&mut c, target, &path);
                let before = snapshot(&dir);
                let program = c.program_text();
                let magazine = c.magazine();
                c.handle(E::Start);
                c.handle(E::Wait);
                let ctx = format!("{} {:?} {what}:\n{}", code.name(), target, c.frame_text());
                let alarm = c.tape_alarm().unwrap_or_else(|| panic!("no alarm: {ctx}"));
                for w in &words {
                    assert!(alarm.contains(w.as_str()), "{w:?} not in {alarm:?}: {ctx}");
                }
                assert!(c.view().lamps.alarm, "{ctx}");
                assert!(shows(&c, "unchanged"), "{ctx}");
                assert_eq!(snapshot(&dir), before, "a store file changed: {ctx}");
                assert_eq!(c.program_text(), program, "{ctx}");
                assert_eq!(c.magazine(), magazine, "{ctx}");
                // START is refused until RESET; one RESET clears the lamp.
                let runs = c.status().runs;
                c.handle(E::Op(OpMode::Auto));
                c.handle(E::Start);
                assert_eq!(
                    c.status().runs,
                    runs,
                    "START acted with a tape alarm: {ctx}"
                );
                assert!(shows(&c, "TAPE ALARM"), "{ctx}");
                c.handle(E::Reset);
                assert!(!c.view().lamps.alarm && c.tape_alarm().is_none(), "{ctx}");
                assert_eq!(snapshot(&dir), before, "{ctx}");
            }
        }
    }
    assert_eq!(cases, 2 * 2 * 12);
}

#[test]
fn stop_reset_estop_and_a_selector_turn_abandon_a_read_with_nothing_stored() {
    let stops = [
        E::Stop,
        E::Reset,
        E::EStop,
        E::Op(OpMode::Auto),
        E::Data(DataMode::Revise),
    ];
    for ev in stops {
        let mut c = open("tape-stop");
        let dir = c.config().state_dir.clone();
        load(
            &mut c,
            DataMode::Read,
            &repo("tests/golden/tableb.eia.tape"),
        );
        let before = snapshot(&dir);
        let program = c.program_text();
        c.handle(E::Start);
        c.handle(E::WaitMs(500));
        c.handle(ev.clone());
        let ctx = format!("{ev:?}:\n{}", c.frame_text());
        assert!(!c.tape_reading(), "{ctx}");
        assert!(shows(&c, "abandoned by"), "{ctx}");
        assert!(shows(&c, "nothing stored"), "{ctx}");
        c.handle(E::Wait);
        assert_eq!(c.program_text(), program, "{ctx}");
        assert_eq!(snapshot(&dir), before, "{ctx}");
    }
}

#[test]
fn other_keys_are_refused_while_the_tape_moves_and_the_read_goes_on() {
    let mut c = open("tape-keys");
    load(
        &mut c,
        DataMode::Read,
        &repo("tests/golden/tableb.iso.tape"),
    );
    c.handle(E::Start);
    c.handle(E::WaitMs(200));
    let program = c.program_text();
    for k in [
        "x",
        "Enter",
        "Backspace",
        "F9",
        "Alt+t",
        "Alt+u",
        "Left",
        "Alt+.",
    ] {
        keys(&mut c, &[k]);
        assert!(
            shows(&c, "refused: the tape reader is reading tableb.iso.tape"),
            "{k}:\n{}",
            c.frame_text()
        );
        assert!(c.tape_reading(), "{k}");
        assert_eq!(c.view().entry, "", "{k}");
    }
    type_line(&mut c, "-999L");
    assert!(shows(&c, "refused"), "{}", c.frame_text());
    assert_eq!(c.program_text(), program, "nothing stored before the end");
    // The feed override and the help screen still work.
    keys(&mut c, &["Alt+-"]);
    assert_eq!(c.view().feed_override, 90);
    c.handle(E::Wait);
    let want = tape::read_image(
        &std::fs::read(repo("tests/golden/tableb.iso.tape")).unwrap(),
        ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(c.program_text(), want.text);
}

/// Types `line` on the data keys without EOB.
fn type_keys(c: &mut Console, line: &str) {
    for ch in line.chars() {
        c.handle(E::Key(ch));
    }
}

#[test]
fn the_punch_key_punches_program_memory_in_iso_or_eia_and_it_reads_back() {
    let out = temp_dir("tape-punch");
    for (suffix, code) in [("", Code::Iso), (" eia", Code::Eia), (" ISO", Code::Iso)] {
        let mut c = open("tape-punch");
        let path = out.join(format!("p{}.tape", suffix.trim()));
        c.handle(E::Op(OpMode::Data));
        c.handle(E::Data(DataMode::Read));
        type_keys(&mut c, &format!("{}{suffix}", path.display()));
        keys(&mut c, &["Alt+u"]);
        let ctx = c.frame_text();
        assert!(shows(&c, &format!("in the {} code", code.name())), "{ctx}");
        assert_eq!(c.view().entry, "", "the line is used up");
        let image = std::fs::read(&path).unwrap();
        let want = tape::punch(
            &c.program_text(),
            &PunchOptions {
                code,
                leader: tape::DEFAULT_LEADER,
                label: Some("TABLEB".into()),
            },
        )
        .unwrap();
        assert_eq!(image, want, "{ctx}");
        // Read it back on a fresh console: the same program text.
        let program = c.program_text();
        let mut d = open("tape-punch-back");
        load(&mut d, DataMode::Read, &path);
        d.handle(E::Start);
        d.handle(E::Wait);
        assert_eq!(d.program_text(), program);
        assert!(
            shows(&d, &format!("({} tape", code.name())),
            "{}",
            d.frame_text()
        );
    }
}

#[test]
fn the_punch_key_is_refused_outside_program_read_and_writes_nothing_on_error() {
    let out = temp_dir("tape-punch-bad");
    let mut c = open("tape-punch-bad");
    let path = out.join("x.tape");
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Revise));
    type_keys(&mut c, &path.display().to_string());
    keys(&mut c, &["Alt+u"]);
    assert!(shows(&c, "punch refused"), "{}", c.frame_text());
    assert!(!path.exists());
    // No path typed.
    c.handle(E::Data(DataMode::Read));
    keys(&mut c, &["Alt+u"]);
    assert!(
        shows(&c, "type the image's file path first"),
        "{}",
        c.frame_text()
    );
    // A directory that does not exist.
    let missing = out.join("no/such/dir/x.tape");
    type_keys(&mut c, &missing.display().to_string());
    keys(&mut c, &["Alt+u"]);
    assert!(shows(&c, "cannot write"), "{}", c.frame_text());
    assert!(!missing.exists());
    // A character EIA has no code for: refused, nothing written.
    assert!(Code::Eia.frame_of('!').is_none());
    c.handle(E::Data(DataMode::Revise));
    type_line(&mut c, "I; by hand!*");
    assert!(shows(&c, "ok"), "{}", c.frame_text());
    c.handle(E::Data(DataMode::Read));
    type_keys(&mut c, &format!("{} EIA", path.display()));
    keys(&mut c, &["Alt+u"]);
    assert!(
        shows(&c, "punch refused, nothing written"),
        "{}",
        c.frame_text()
    );
    assert!(shows(&c, "line 1:"), "{}", c.frame_text());
    assert!(!path.exists());
    let leftovers: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert!(
        leftovers.is_empty(),
        "no temporary file is left: {leftovers:?}"
    );
}

#[test]
fn in_real_time_the_tape_moves_at_its_speed_between_display_ticks() {
    let mut cfg = ConsoleConfig::new(temp_dir("tape-rt"));
    cfg.clock = ClockMode::RealTime;
    cfg.settings.tape_chars_per_s = 300;
    let mut c = Console::open(cfg).unwrap().0;
    let path = repo("tests/golden/tableb.iso.tape");
    load(&mut c, DataMode::Read, &path);
    let started = std::time::Instant::now();
    c.handle(E::Start);
    let mut seen = std::collections::BTreeSet::new();
    while c.tape_reading() && started.elapsed() < std::time::Duration::from_secs(10) {
        std::thread::sleep(std::time::Duration::from_millis(20));
        c.tick();
        if let Some(v) = c.tape_view() {
            seen.insert(v.frame);
        }
    }
    let took = started.elapsed();
    assert!(!c.tape_reading(), "the read ends on its own");
    // 276 frames at 300 a second: 0.92 s, shown part way at several ticks (even with the
    // display ticking slowly on a loaded machine).
    assert!(took.as_millis() >= 900, "{took:?}");
    assert!(seen.len() >= 3, "the display moved: {seen:?}");
    let want = tape::read_image(&std::fs::read(&path).unwrap(), ReadOptions::default()).unwrap();
    assert_eq!(c.program_text(), want.text);
    let _ = c.finish();
}

/// Issue 20: the punch writes through the one write path: a symlink named as the image is
/// followed (the link stays, its file gets the image), as `novanc edit --write` does.
#[test]
fn the_punch_writes_through_a_symlink_and_keeps_it() {
    let out = temp_dir("tape-punch-link");
    let real = out.join("real.tape");
    std::fs::write(&real, b"old").unwrap();
    let link = out.join("link.tape");
    std::os::unix::fs::symlink("real.tape", &link).unwrap();
    let mut c = open("tape-punch-link");
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    type_keys(&mut c, &link.display().to_string());
    keys(&mut c, &["Alt+u"]);
    assert!(shows(&c, "in the ISO code"), "{}", c.frame_text());
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(&real).unwrap(), std::fs::read(&link).unwrap());
    assert_ne!(std::fs::read(&real).unwrap(), b"old");
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        2,
        "a temporary file is left"
    );
}
