//! The rapid and spindle overrides on the lathe console (docs/lathe.md "Keys"): the centre's
//! switches, on every channel of the one kernel, with the centre's keys, words and limits; kept
//! across cycles; a whole Citizen part is made under both.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::panel_model::{OpMode, PanelEvent};
use novanc_panel::Key;

use common::open_citizen as open;

/// CH1's spindle speed as the display shows it, rpm.
fn rpm(c: &LatheConsole) -> f64 {
    c.view().channels[0].rpm
}

/// Runs `line` as CH1's MDI program and waits for the machine to come to rest; the machine
/// time it took, ns.
fn mdi(c: &mut LatheConsole, line: &str) -> u64 {
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type(line.into()));
    let t0 = c.machine_ns();
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(c.wait_error().is_none(), "{:?}", c.wait_error());
    c.machine_ns() - t0
}

#[test]
fn the_spindle_override_turns_the_spindles_at_s_times_the_override() {
    let dir = common::temp_dir("lathe-sov");
    let mut c = open(&dir);
    c.handle(PanelEvent::SpindleOverride(120));
    assert!(
        c.message().starts_with("spindle override 120 %"),
        "{}",
        c.message()
    );
    mdi(&mut c, "G97 S1000 M3");
    c.handle(PanelEvent::WaitMs(3000));
    assert!((rpm(&c) - 1200.0).abs() < 1.0, "{}", rpm(&c));
    assert!(c.view().title.ends_with("SOV120%"), "{:?}", c.view());
    // Turned back with the spindle on: the spindle follows.
    c.press(Key::Alt('['));
    c.press(Key::Alt('['));
    assert_eq!(c.rapid_spindle(), (100, 100));
    c.handle(PanelEvent::WaitMs(3000));
    assert!((rpm(&c) - 1000.0).abs() < 1.0, "{}", rpm(&c));
    assert!(!c.view().title.contains("SOV"), "{:?}", c.view());
    // Past its range: refused with the machine's words, nothing changed.
    c.handle(PanelEvent::SpindleOverride(130));
    assert!(
        c.message().contains("refused: 50 to 120 in steps of 10"),
        "{}",
        c.message()
    );
    assert_eq!(c.rapid_spindle(), (100, 100));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_rapid_override_slows_every_rapid_and_is_kept_for_the_next_cycle() {
    let dir = common::temp_dir("lathe-rpd");
    let mut c = open(&dir);
    let full = mdi(&mut c, "G0 X20 Z10");
    mdi(&mut c, "G0 X70 Z60");
    // Alt+f steps it down, as on the centre: 100 → 50.
    c.press(Key::Alt('f'));
    assert_eq!(c.rapid_spindle(), (50, 100));
    assert!(
        c.message().starts_with("rapid override 50 %"),
        "{}",
        c.message()
    );
    let half = mdi(&mut c, "G0 X20 Z10");
    assert!(
        half as f64 > 1.5 * full as f64,
        "the same rapid took {half} ns at 50 %, {full} ns at 100 %"
    );
    // A cycle begun now runs every channel at the override.
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::WaitMs(100));
    let cyc = c.cycle();
    for ch in cyc.channels() {
        assert_eq!(ch.status.switches.rapid_override, 50);
    }
    // FAULT moved to Alt+x: Alt+f is the rapid override on every console.
    c.press(Key::Alt('x'));
    assert!(c.message().contains("CH1 FAULT"), "{}", c.message());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_citizen_part_is_made_under_both_overrides() {
    let dir = common::temp_dir("lathe-ovr-part");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::SpindleOverride(80));
    c.handle(PanelEvent::RapidOverride(25));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(c.wait_error().is_none(), "{:?}", c.wait_error());
    let v = c.view();
    for ch in &v.channels {
        assert_eq!((ch.state.as_str(), ch.parts), ("DONE", 1), "{v:?}");
    }
    assert!(v.title.contains("1/1"), "{}", v.title);
    let _ = std::fs::remove_dir_all(&dir);
}

/// What a lathe's `/nc/state` records is what the console does: an MDI program's run is `run`
/// 2 in `op_mode` MDI (it was 1, AUTO, whatever the selector), the selector's later turns, the
/// rapid override turned, and `data_mode` MEMORY (the lathe has no data-processing selector;
/// it recorded the centre's SEARCH).
#[test]
fn the_lathe_records_its_runs_modes_and_switches_as_they_are() {
    let dir = common::temp_dir("lathe-rec-modes");
    let script = dir.join("s.panel");
    std::fs::write(
        &script,
        "op MDI\ntype G0 X20\nstart\nwait\nop SINGLE\nrapidoverride 50\n",
    )
    .unwrap();
    let mcap = dir.join("r.mcap");
    let out = common::novanc_command()
        .arg("script")
        .arg(&script)
        .args(["--machine", "citizen", "--record"])
        .arg(&mcap)
        .arg("--state")
        .arg(dir.join("state"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let states: Vec<String> = common::recorded(&mcap, "/nc/state")
        .into_iter()
        .map(|(_, s)| s)
        .filter(|s| s.starts_with("{\"channel\":1,"))
        .collect();
    let has = |s: &String, w: &[&str]| w.iter().all(|w| s.contains(w));
    // The kernel is the machine's from the console's opening (stop 42): the recording has it
    // at rest in AUTO first, then the selector turned to MDI, then the MDI run.
    assert!(
        has(&states[0], &["\"run\":0", "\"op_mode\":\"AUTO\""]),
        "{states:?}"
    );
    let run = states
        .iter()
        .find(|s| !s.contains("\"run\":0"))
        .expect("a run is recorded");
    assert!(
        has(
            run,
            &[
                "\"run\":2",
                "\"op_mode\":\"MDI\"",
                "\"data_mode\":\"MEMORY\""
            ]
        ),
        "{states:?}"
    );
    assert!(
        states.iter().any(|s| has(
            s,
            &[
                "\"run\":0",
                "\"op_mode\":\"SINGLE\"",
                "\"rapid_override\":50"
            ]
        )),
        "{states:?}"
    );
    assert!(!states.iter().any(|s| s.contains("SEARCH")), "{states:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// DRY RUN, the centre's switch (Alt+d), on every channel: a slow feed move runs at the jog
/// feed, and the switch is on the title line and kept for the next run.
#[test]
fn dry_run_moves_a_feed_at_the_jog_feed() {
    let dir = common::temp_dir("lathe-dry");
    let mut c = open(&dir);
    // 10 mm at 10 mm/min: a minute.
    let slow = mdi(&mut c, "G94 G1 Z50 F10");
    assert!(slow > 59_000_000_000, "{slow} ns");
    mdi(&mut c, "G0 Z60");
    c.press(Key::Alt('d'));
    assert!(c.dry_run());
    assert!(c.message().starts_with("DRY RUN on"), "{}", c.message());
    assert!(c.view().title.ends_with(" DRY"), "{}", c.view().title);
    let dry = mdi(&mut c, "G94 G1 Z50 F10");
    assert!(dry * 5 < slow, "{dry} ns under DRY RUN against {slow} ns");
    c.handle(PanelEvent::DryRun(false));
    assert!(!c.dry_run() && !c.view().title.contains("DRY"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The feed override is the centre's rotary switch on the lathe too (`console::front`): 0 to
/// 150 % in 10 % steps. Before stop 41 the lathe clamped any value (`override 75` ran at 75 %,
/// the centre refused it); a refused position now says why and leaves the override as it was,
/// on both machines, and a taken one is told to the cycle under way.
#[test]
fn the_feed_override_takes_the_rotarys_positions_only_on_both_machines() {
    let dir = common::temp_dir("lathe-fov");
    let mut c = open(&dir);
    c.handle(PanelEvent::Override(70));
    assert_eq!(c.feed_override(), 70);
    assert_eq!(c.message(), "feed override 70 %");
    for bad in [75, 151, 155] {
        c.handle(PanelEvent::Override(bad));
        assert_eq!(c.feed_override(), 70, "override {bad}");
        assert_eq!(
            c.message(),
            format!("override {bad} % is not 0 to 150 in 10 % steps")
        );
    }
    let mut m = common::open("centre-fov");
    m.handle(PanelEvent::Override(70));
    // Said on the centre as on the lathe (one rule, `console::switches`; before stop 43 the
    // centre said nothing).
    assert_eq!(m.message(), "feed override 70 %");
    m.handle(PanelEvent::Override(75));
    assert_eq!(m.view().feed_override, 70);
    assert_eq!(m.message(), "override 75 % is not 0 to 150 in 10 % steps");
}

/// MACHINE LOCK, the centre's switch (Alt+l), on every channel (stop 42; the lathe refused it
/// before): an MDI program runs and takes its time, the screen follows the program, and the
/// axes stay; the switch changes only with no run loaded, on every channel or none; the next
/// run starts from where the axes stand, not from where the locked program left the screen.
#[test]
fn machine_lock_runs_the_program_with_the_axes_standing() {
    let dir = common::temp_dir("lathe-mlk");
    let mut c = open(&dir);
    let axes = |c: &LatheConsole| c.cycle().axes()[0];
    let at = axes(&c);
    c.press(Key::Alt('l'));
    assert!(c.machine_switches().machine_lock, "{}", c.message());
    assert!(
        c.message().starts_with("MACHINE LOCK on"),
        "{}",
        c.message()
    );
    assert!(c.view().title.contains(" MLK"), "{}", c.view().title);
    assert!(c
        .cycle()
        .channels()
        .iter()
        .all(|s| s.status.switches.machine_lock));
    let took = mdi(&mut c, "G0 X30 Z50");
    assert!(
        took > 10_000_000,
        "the locked rapid takes its time: {took} ns"
    );
    assert_eq!(
        c.view().channels[0].pos,
        [15_000, 50_000],
        "the screen follows"
    );
    assert_eq!(axes(&c), at, "the axes stay");
    // With a run loaded the switch is refused, on every channel.
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type("G4 P5".into()));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::WaitMs(1000));
    c.press(Key::Alt('l'));
    assert!(
        c.message()
            .starts_with("MACHINE LOCK refused: a run is loaded"),
        "{}",
        c.message()
    );
    assert!(c
        .cycle()
        .channels()
        .iter()
        .all(|s| s.status.switches.machine_lock));
    c.handle(PanelEvent::Wait);
    c.press(Key::Alt('l'));
    assert!(!c.machine_switches().machine_lock, "{}", c.message());
    assert!(!c.view().title.contains("MLK"));
    // The next run starts from the axes: 10 mm less on the diameter is 5 mm of radius.
    mdi(&mut c, "G91 G0 X-10");
    assert_eq!(axes(&c), [at[0] - 5_000, at[1]]);
    assert_eq!(c.view().channels[0].pos, axes(&c));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The switches on the state line, one function on both machines (stop 49): the same words in
/// the same order, BLOCK DELETE and OPTIONAL STOP first. Before, the lathe's title wrote them
/// last, in the other order.
#[test]
fn both_machines_write_the_switches_in_one_order() {
    let (dir, mut lathe, mut centre) = common::both_machines("lathe-switch-words");
    for ev in [
        PanelEvent::BlockDelete(true),
        PanelEvent::OptionalStop(true),
        PanelEvent::DryRun(true),
    ] {
        lathe.handle(ev.clone());
        centre.handle(ev);
    }
    let want = " /DEL M01 DRY";
    assert!(lathe.view().title.ends_with(want), "{}", lathe.view().title);
    // The centre's state line is its run pages' (40 columns: the overrides would be cut).
    centre.handle(PanelEvent::Op(OpMode::Auto));
    let frame = centre.frame_text();
    assert!(frame.contains(want), "{frame}");
    lathe.handle(PanelEvent::RapidOverride(50));
    lathe.handle(PanelEvent::SpindleOverride(110));
    let title = lathe.view().title;
    assert!(title.ends_with(" /DEL M01 RPD50% SOV110% DRY"), "{title}");
    let _ = std::fs::remove_dir_all(&dir);
}
