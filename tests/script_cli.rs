//! `novanc script` on the command line: a bad script line is reported with its line number
//! before anything runs; `--record` writes an MCAP file; `show` frames are deterministic.

mod common;

use common::novanc;

#[test]
fn a_bad_line_fails_the_script_before_anything_runs() {
    let d = common::temp_dir("bad");
    let script = d.join("s.script");
    std::fs::write(
        &script,
        "op DATA\ndata REVISE\ntype 99LIGO, 1, 1, -1*\nshow\nwheel Q 3\n",
    )
    .unwrap();
    let state = d.join("state");
    let out = novanc(&[
        "script",
        script.to_str().unwrap(),
        "--state",
        state.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("s.script:5: unknown axis 'Q'"), "{err}");
    assert!(out.stdout.is_empty(), "nothing may run");
    // The edit on line 3 never happened: a fresh console still has Table B unchanged.
    let show = d.join("show.script");
    std::fs::write(&show, "op DATA\ndata REVISE\ntype 99L-1L\nshow\n").unwrap();
    let out = novanc(&[
        "script",
        show.to_str().unwrap(),
        "--state",
        state.to_str().unwrap(),
    ]);
    let frame = String::from_utf8_lossy(&out.stdout);
    assert!(frame.contains("TAP, 206/DP12/DA1, P2, P3, P4*"), "{frame}");
    assert!(!frame.contains("GO, 1, 1, -1"), "{frame}");
}

#[test]
fn frames_are_deterministic_and_recorded() {
    let d = common::temp_dir("rec");
    let script = d.join("run.script");
    std::fs::write(&script, "op AUTO\nstart\nwait\nshow\n").unwrap();
    let mut frames = Vec::new();
    for i in 0..2 {
        let rec = d.join(format!("run{i}.mcap"));
        let out = novanc(&[
            "script",
            script.to_str().unwrap(),
            "--record",
            rec.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("3 panel events"), "{err}");
        let bytes = std::fs::read(&rec).unwrap();
        assert!(bytes.starts_with(b"\x89MCAP0\r\n"), "not an MCAP file");
        frames.push(String::from_utf8_lossy(&out.stdout).into_owned());
    }
    assert_eq!(frames[0], frames[1]);
    assert!(frames[0].contains("RUN 0 AUTO"), "{}", frames[0]);
}

#[test]
fn usage_errors_exit_2() {
    let out = novanc(&["script"]);
    assert_eq!(out.status.code(), Some(2));
    let out = novanc(&["script", "x.script", "--rows", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--rows 2"));
}

/// Runs a script given as text on a fresh state; its output and exit code.
fn script_text(name: &str, text: &str) -> (Option<i32>, String, String) {
    let d = common::temp_dir(name);
    let script = d.join("s.script");
    std::fs::write(&script, text).unwrap();
    let out = novanc(&["script", script.to_str().unwrap()]);
    let _ = std::fs::remove_dir_all(&d);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Issue 15, defect 3: STOP right after START holds the run; nothing runs to its end.
#[test]
fn stop_right_after_start_holds_the_run() {
    let (code, out, err) = script_text("stopstart", "op AUTO\nstart\nstop\nwait\nshow\n");
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("feed hold: press START to resume"), "{out}");
    assert!(out.contains("HOLD"), "{out}");
    assert!(!out.contains("program end"), "{out}");
    assert!(!out.contains("not running"), "{out}");
}

/// Issue 15, defect 6: a wait that can never end (override 0 with a feed in progress) stops the
/// script with a clear error at once, instead of sleeping forever.
#[test]
fn a_wait_at_override_zero_ends_with_an_error() {
    let t = std::time::Instant::now();
    let (code, _out, err) = script_text(
        "ovr0",
        "op AUTO\nstart\nwait block 5\noverride 0\nwait\nshow\n",
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("wait: the machine stands still at feed override 0 %; raise the override"),
        "{err}"
    );
    assert!(t.elapsed().as_secs() < 30);
}

/// Issue 20: a number too large for its word is said to be too large, not "not a whole
/// number" (docs/cli.md, "The panel script").
#[test]
fn a_script_number_out_of_range_is_said_to_be_so() {
    use novanc::panel_model::PanelEvent;
    for (line, message) in [
        (
            "wheel X 2147483648",
            "detents 2147483648 is out of range (-2147483648 to 2147483647)",
        ),
        (
            "wheel X -99999999999999999999",
            "detents -99999999999999999999 is out of range (-2147483648 to 2147483647)",
        ),
        ("wheel X 1.5", "detents '1.5' is not a whole number"),
        (
            "wait ms 99999999999999999999",
            "wait ms: 99999999999999999999 is more than 360000000 ms (100 hours)",
        ),
    ] {
        assert_eq!(
            PanelEvent::parse_script_line(line).err().as_deref(),
            Some(message),
            "{line}"
        );
    }
    assert!(PanelEvent::parse_script_line("wheel X -2147483648").is_ok());
}
