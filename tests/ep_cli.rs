//! The interpolator setting at the command line: `novanc run --interpolator` and `--ep-l`,
//! bad values refused with nothing run, and the console (`novanc script`) showing EP on its
//! state line. docs/cli.md, docs/pulse-core.md.

mod common;

fn novanc(args: &[&str]) -> (i32, String, String) {
    let o = common::novanc(args);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn line<'a>(out: &'a str, start: &str) -> &'a str {
    out.lines().find(|l| l.starts_with(start)).unwrap_or("")
}

#[test]
fn run_with_either_interpolator_ends_on_the_same_point_with_the_same_pulses() {
    let (c1, dda, e1) = novanc(&["run", "programs/bracket.ap"]);
    assert_eq!(c1, 0, "{e1}");
    let (c2, ep, e2) = novanc(&[
        "run",
        "programs/bracket.ap",
        "--interpolator",
        "error-proportional",
        "--ep-l",
        "5000",
    ]);
    assert_eq!(c2, 0, "{e2}");
    assert_eq!(
        line(&ep, "interpolator:"),
        "interpolator: error-proportional (L 5000 pulses)"
    );
    assert_eq!(
        line(&dda, "interpolator:"),
        "",
        "the DDA is the default, unnamed"
    );
    for l in ["blocks executed:", "final position:"] {
        assert_eq!(line(&dda, l), line(&ep, l));
        assert!(!line(&dda, l).is_empty());
    }
    // The same pulses as the DDA here; an arc may add a pulse and its return where an axis
    // turns round at a quadrant point (docs/pulse-core.md): a few in millions.
    let counts = |s: &str| -> Vec<u64> {
        line(s, "pulses:")
            .split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    let (a, b) = (counts(&dda), counts(&ep));
    assert_eq!(a.len(), 3);
    for (x, y) in a.iter().zip(&b) {
        assert!(
            y >= x && (y - x) % 2 == 0 && y - x <= x / 100_000,
            "{a:?} {b:?}"
        );
    }
    assert_ne!(line(&dda, "machine time:"), line(&ep, "machine time:"));
}

#[test]
fn bad_interpolator_settings_are_usage_errors_and_nothing_runs() {
    for (args, msg) in [
        (
            vec!["run", "programs/bracket.ap", "--interpolator", "pid"],
            "--interpolator: interpolator 'pid' is not dda or error-proportional",
        ),
        (
            vec!["run", "programs/bracket.ap", "--ep-l", "-3"],
            "--ep-l: L '-3' is not a whole number of pulses from 1 to 100000000",
        ),
    ] {
        let (code, out, err) = novanc(&args);
        assert_eq!(code, 2);
        assert!(err.contains(msg), "{err}");
        assert!(!out.contains("blocks executed"), "{out}");
    }
}

#[test]
fn the_console_shows_ep_on_its_state_line() {
    let dir = common::temp_dir("ep-cli");
    let script = dir.join("s.txt");
    // The POS page (Ctrl+P) carries the state line.
    std::fs::write(&script, "key Ctrl+P\nshow\n").expect("script");
    let state = dir.join("state");
    let s = state.to_string_lossy().to_string();
    let sc = script.to_string_lossy().to_string();
    let (c, out, err) = novanc(&["script", &sc, "--state", &s, "--interpolator", "ep"]);
    assert_eq!(c, 0, "{err}");
    let st = out.lines().find(|l| l.starts_with("RUN 0 ")).unwrap_or("");
    assert!(st.ends_with(" EP"), "{out}");
    let (c, out, err) = novanc(&["script", &sc, "--state", &s]);
    assert_eq!(c, 0, "{err}");
    let st = out.lines().find(|l| l.starts_with("RUN 0 ")).unwrap_or("");
    assert!(!st.is_empty() && !st.contains(" EP"), "{out}");
    let (c, _, err) = novanc(&["script", &sc, "--state", &s, "--interpolator", "x"]);
    assert_ne!(c, 0);
    assert!(err.contains("--interpolator"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
