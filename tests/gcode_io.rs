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

/// Outputs in a recorded run: each on `/nc/io` after its block's `/nc/block` and before the
/// next block's, M64/M68 at once and M62 with the motion; the file passes the Python reader's
/// check with the new topic.
#[test]
fn a_run_records_the_outputs() {
    let dir = common::temp_dir("io-rec");
    let prog = dir.join("out.ngc");
    std::fs::write(
        &prog,
        "G21 G90\nM64 P1\nG1 X10 F1000 M62 P2\nM68 E3 Q2.5\nM65 P1\nG0 X0\nM30\n",
    )
    .unwrap();
    let rec = dir.join("out.mcap");
    let out = common::novanc_command()
        .arg("run")
        .arg(&prog)
        .arg("--record")
        .arg(&rec)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let bytes = std::fs::read(&rec).unwrap();
    let mut seen = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let topic = m.channel.topic.clone();
        if topic == "/nc/block" || topic == "/nc/io" {
            seen.push(String::from_utf8(m.data.to_vec()).unwrap());
        }
    }
    let io = |seq: u32, stmt: u32, kind: &str, index: u32, value: &str, synced: bool| {
        format!(
            r#"{{"seq":{seq},"stmt":{stmt},"kind":"{kind}","index":{index},"value":{value},"synced":{synced}}}"#
        )
    };
    let blocks: Vec<&String> = seen.iter().filter(|m| m.contains("\"text\"")).collect();
    let at = |s: &str| seen.iter().position(|m| *m == s).unwrap_or(usize::MAX);
    let after = |text: &str| {
        seen.iter()
            .position(|m| m.contains("\"text\"") && m.contains(text))
            .unwrap_or_else(|| panic!("no block {text}: {blocks:?}"))
    };
    assert_eq!(
        at(&io(1, 2, "digital", 1, "1", false)),
        after("M64 P1") + 1,
        "{seen:?}"
    );
    assert_eq!(
        at(&io(2, 3, "digital", 2, "1", true)),
        after("M62 P2") + 1,
        "{seen:?}"
    );
    assert_eq!(
        at(&io(4, 4, "analog", 3, "2.5", false)),
        after("M68 E3") + 1,
        "{seen:?}"
    );
    assert_eq!(
        at(&io(5, 5, "digital", 1, "0", false)),
        after("M65 P1") + 1,
        "{seen:?}"
    );
    assert_eq!(seen.len(), blocks.len() + 4, "{seen:?}");
    if let Some((ok, text)) = common::python_check(&rec, &["--expect-topics", "/nc/io"]) {
        assert!(ok, "{text}");
    }
}

/// The outputs are in the status snapshot after a run at the console.
#[test]
fn the_status_holds_the_outputs() {
    let mut c = common::open("io-status");
    let f = common::temp_dir("io-status-prog").join("o.ngc");
    std::fs::write(&f, "G21 G90\nM64 P1\nM62 P2\nM67 E3 Q-1.25\nM65 P1\nM30\n").unwrap();
    let text = format!(
        "op DATA\ndata READ\ntape {}\nstart\nwait\nop AUTO\nstart\nwait\n",
        f.display()
    );
    for ev in PanelEvent::parse_script(&text).unwrap() {
        c.handle(ev);
    }
    let o = c.status().outputs;
    assert_eq!(o.digital, 1 << 2, "{}", c.frame_text());
    assert_eq!(o.analog[3], -1.25);
    // The POS page shows them, and an input a script set, under the axes.
    for ev in PanelEvent::parse_script("input P3 on\nkey Ctrl+P\n").unwrap() {
        c.handle(ev);
    }
    let frame = c.frame_text();
    assert!(frame.contains("I/O OUT P2 E3=-1.25 IN P3"), "{frame}");
}

/// The I/O page (Ctrl-T) by its keys: `P3 ON` INPUT two seconds into the M66 wait ends the
/// wait as the script word `input P3 on` does; `E2 4.5` sets an analog input; the page shows
/// both, with the outputs the program set; a word that is not an input is refused with the
/// reason and stays on the entry line.
#[test]
fn the_io_page_sets_inputs_by_its_keys() {
    let (x, t, _) = run_script(
        "io-page-keys",
        "G21 G90\nM64 P17\nG0 X10 Y10 Z-10\nM66 P3 L3 Q10\nG0 X[100 + 40 * #5399]\nM30\n",
        "op DATA\ndata READ\ntape PROG\nstart\nwait\nop AUTO\nstart\nwait ms 2000\n\
         key Ctrl+T\ntype P3 ON\nwait\n",
    );
    assert_eq!(x, 140.0);
    assert!(t < 5.0, "{t}");
    let mut c = common::open("io-page");
    common::keys(&mut c, &["Ctrl+T"]);
    assert!(common::shows(&c, "I/O"), "{}", c.frame_text());
    // Each character on its key, then INPUT (Enter) or +INPUT (Tab).
    let key_in = |c: &mut novanc::console::Console, line: &str, end: &str| {
        for ch in line.chars() {
            common::keys(c, &[ch.to_string().as_str()]);
        }
        common::keys(c, &[end]);
    };
    for (line, end) in [("p5 on", "Enter"), ("E2 4.5", "Enter"), ("P63 ON", "Tab")] {
        key_in(&mut c, line, end);
    }
    let i = c.status().inputs;
    assert_eq!(i.digital, 1 << 5 | 1 << 63, "{}", c.frame_text());
    assert_eq!(i.analog[2], 4.5);
    assert!(
        common::shows(&c, " 0 ........ ........  .....1.. ........"),
        "{}",
        c.frame_text()
    );
    assert!(
        common::shows(&c, "48 ........ ........  ........ .......1"),
        "{}",
        c.frame_text()
    );
    assert!(common::shows(&c, "IN E M66 E2=4.5"), "{}", c.frame_text());
    assert!(common::shows(&c, "I/O: input P63 on"), "{}", c.frame_text());
    key_in(&mut c, "P3 2", "Enter");
    assert!(
        common::shows(&c, "I/O: refused: input P3: takes on or off, not '2'"),
        "{}",
        c.frame_text()
    );
    assert_eq!(c.view().entry, "P3 2");
    assert_eq!(c.status().inputs.digital, 1 << 5 | 1 << 63);
}

/// Input changes are recorded on `/nc/io` with `"dir":"in"`, from the I/O page and from the
/// script word alike, the same value again not written; the file passes the Python reader.
#[test]
fn input_changes_are_recorded() {
    let dir = common::temp_dir("io-rec-in");
    let (rec, _) = common::recorded_script(
        &dir,
        "key Ctrl+T\ntype P3 ON\ntype E2 4.5\ninput P3 on\ninput P3 off\n",
    );
    let io: Vec<String> = common::recorded(&rec, "/nc/io")
        .into_iter()
        .map(|(_, t)| t)
        .collect();
    let input = |kind: &str, index: u32, value: &str| {
        format!(
            r#"{{"seq":0,"stmt":0,"kind":"{kind}","index":{index},"value":{value},"synced":false,"dir":"in"}}"#
        )
    };
    assert_eq!(
        io,
        [
            input("digital", 3, "1"),
            input("analog", 2, "4.5"),
            input("digital", 3, "0")
        ]
    );
    if let Some((ok, text)) = common::python_check(&rec, &["--expect-topics", "/nc/io"]) {
        assert!(ok, "{text}");
    }
}

/// M19 in a run: the turning spindle stops (the M5 time), then stands oriented at R; POS and
/// MODAL show it; M5 ends it.
#[test]
fn m19_stops_the_spindle_and_orients_it() {
    let mut c = common::open("io-m19");
    let f = common::temp_dir("io-m19-prog").join("o.ngc");
    std::fs::write(&f, "G21 G90\nS1000 M3\nM19 R90 Q5\nM0\nM5\nM30\n").unwrap();
    let text = format!(
        "op DATA\ndata READ\ntape {}\nstart\nwait\nop AUTO\nstart\nwait\nkey Ctrl+P\n",
        f.display()
    );
    for ev in PanelEvent::parse_script(&text).unwrap() {
        c.handle(ev);
    }
    let s = c.status();
    assert_eq!((s.spindle, s.orient), (0, Some(90.0)), "{}", c.frame_text());
    // M3's start and M19's stop, one second each (and the blocks' NCBR ticks).
    assert!(
        (2_000_000_000..2_100_000_000).contains(&s.machine_ns),
        "{}",
        s.machine_ns
    );
    assert!(
        common::shows(&c, "S 0 oriented M19 R90"),
        "{}",
        c.frame_text()
    );
    common::keys(&mut c, &["Ctrl+G"]);
    assert!(
        common::shows(&c, "S0 ORIENTED M19 R90"),
        "{}",
        c.frame_text()
    );
    for ev in PanelEvent::parse_script("start\nwait\n").unwrap() {
        c.handle(ev);
    }
    assert_eq!(c.status().orient, None);
    assert!(!common::shows(&c, "ORIENTED"), "{}", c.frame_text());
}
