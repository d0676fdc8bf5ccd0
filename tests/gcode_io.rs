//! M66 in a run (docs/gcode.md "Inputs and outputs"): the pulse core reads its simulated
//! inputs, which a panel script's `input` sets; a wait (L1–L4) lasts up to Q seconds of machine
//! time, the value going to #5399 (-1 on a timeout).

use novanc::panel_model::PanelEvent;

mod common;

/// Runs `script` (panel-script text; `PROG` stands for the program's path) on a fresh console
/// with `prog` as the tape: the machine X where the run ended (mm), the machine time at the
/// end (s), and the frame.
fn run_script(name: &str, prog: &str, script: &str) -> (f64, f64, String) {
    let mut c = common::open(name);
    let f = common::temp_dir(&format!("{name}-prog")).join("io.ngc");
    std::fs::write(&f, prog).unwrap();
    let text = script.replace("PROG", &f.display().to_string());
    for ev in PanelEvent::parse_script(&text).unwrap() {
        c.handle(ev);
    }
    let ends = common::audit(&c);
    let x = ends.last().map_or(f64::NAN, |e| e.end[0] as f64 / 1000.0);
    (x, c.status().machine_ns as f64 / 1e9, c.frame_text())
}

/// The wait then a move that depends on #5399: X140 when the input came on (1), X60 on a
/// timeout (-1).
const WAIT_HIGH: &str = "G21 G90\nG0 X10 Y10 Z-10\nM66 P3 L3 Q10\nG0 X[100 + 40 * #5399]\nM30\n";

/// `input P3 on` two seconds into a ten-second wait for P3 high: the run goes on with #5399 = 1
/// before the timeout.
#[test]
fn m66_waits_for_an_input_the_script_sets() {
    let (x, t, frame) = run_script(
        "io-high",
        WAIT_HIGH,
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait ms 2000\ninput P3 on\nwait\n",
    );
    assert_eq!(x, 140.0, "{frame}");
    // It waited for the input (2 s), not for the timeout (10 s).
    assert!((2.0..10.0).contains(&t), "{t} s");
}

/// Nobody sets P3: the wait ends after Q seconds of machine time with #5399 = -1 and the run
/// goes on.
#[test]
fn m66_times_out_with_minus_one() {
    let (x, t, frame) = run_script(
        "io-timeout",
        WAIT_HIGH,
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait\n",
    );
    assert_eq!(x, 60.0, "{frame}");
    assert!(t >= 10.0, "the wait ended after {t} s, before its timeout");
}

/// L0 reads at once, an analog input as set; a rise needs the input low then high.
#[test]
fn m66_reads_an_analog_input_and_waits_for_a_rise() {
    let (x, t, frame) = run_script(
        "io-analog",
        "G21 G90\nM66 E1 L0\n#1=#5399\nM66 P5 L1 Q5\nG0 X[#1 * 10 + #5399]\nM30\n",
        "input E1 2.5\ninput P5 on\nop DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\n\
         wait ms 1000\ninput P5 off\nwait ms 1000\ninput P5 on\nwait\n",
    );
    assert_eq!(x, 26.0, "{frame}");
    // The rise came after the input went off (1 s) and on again (2 s).
    assert!(t >= 2.0, "{t} s");
}

/// RESET during a wait abandons the run; the next run of the program goes through.
#[test]
fn reset_during_an_input_wait_abandons_the_run() {
    let (x, _, frame) = run_script(
        "io-reset",
        WAIT_HIGH,
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait ms 2000\nreset\nwait\n\
         input P3 on\nop AUTO\nstart\nwait\n",
    );
    assert_eq!(x, 140.0, "{frame}");
}

/// The script word's errors.
#[test]
fn the_input_word_refuses_what_is_not_an_input() {
    for (line, want) in [
        ("input P64 on", "not P0-P63 or E0-E63"),
        ("input Q1 on", "not P0-P63 or E0-E63"),
        ("input P1 2", "takes on or off"),
        ("input E1 x", "is not a number"),
        ("input P1", "'input' takes"),
    ] {
        let e = PanelEvent::parse_script_line(line).unwrap_err();
        assert!(e.contains(want), "{line}: {e}");
    }
}
