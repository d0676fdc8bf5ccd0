//! STEP on the lathe console (docs/lathe.md "STEP: moving a tool post by hand"): the jog keys
//! move the selected channel's tool post one increment on the one kernel, as the centre's
//! STEP does; every refusal says why and moves nothing; E-STOP latches until RESET, with or
//! without a cycle loaded; a cycle starts where the tool posts stand.

mod common;

use novanc::lathe::console::{LatheConsole, RunUntil};
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{Axis, OpMode, PanelEvent};
use novanc_panel::Key;

use common::open_citizen as open;

/// The Citizen's console with its kernel in real time, as at a terminal.
fn open_real_time(state: &std::path::Path) -> LatheConsole {
    let clock = novanc::pulse_core::ClockMode::RealTime;
    LatheConsole::open_on(LatheDesc::citizen(), state, (20, 60), None, clock)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// Turns the selector with `k` and finds the mode's word ending the display's first line.
fn turn_to(c: &mut LatheConsole, k: Key, word: &str) {
    c.press(k);
    let top = c.view().display[0].clone();
    assert!(top.trim_end().ends_with(word), "{top:?}");
}

/// Every channel's tool post, pulses [X radius, Z].
fn posts(c: &LatheConsole) -> Vec<[i64; 2]> {
    c.tips().into_iter().map(|t| t.0).collect()
}

#[test]
fn step_moves_the_selected_tool_post_one_increment_and_nothing_else() {
    let dir = common::temp_dir("lathe-step");
    let mut c = open(&dir);
    let home = posts(&c);
    // Not in STEP: refused, nothing moves.
    c.press(Key::Down);
    assert!(c.message().contains("or STEP (Alt+6)"), "{}", c.message());
    assert_eq!(posts(&c), home);
    c.handle(PanelEvent::Op(OpMode::Step));
    c.handle(PanelEvent::WheelScale(100));
    assert!(c.message().contains("0.100 mm (x100)"), "{}", c.message());
    // Down is X-, Left is Z-: 100 pulses each, on CH1 only.
    c.press(Key::Down);
    assert!(
        c.message().contains("STEP CH1 X- 0.100 mm"),
        "{}",
        c.message()
    );
    // The channel's program is still the one shown (no program runs for a manual move).
    assert!(
        c.view().display[0].contains("SYSTEM-1 SYSTEM1.NGC STEP"),
        "{:?}",
        c.view().display[0]
    );
    c.press(Key::Left);
    c.press(Key::Left);
    c.handle(PanelEvent::Wait);
    let mut want = home.clone();
    want[0] = [home[0][0] - 100, home[0][1] - 200];
    assert_eq!(posts(&c), want);
    // Each channel starts at the top of its travel: X+ past it is refused, and says so.
    c.press(Key::Up);
    c.handle(PanelEvent::Wait);
    c.press(Key::Up);
    assert!(
        c.message().contains("X (a radius) would go to") && c.message().contains("outside travel"),
        "{}",
        c.message()
    );
    want[0][0] = home[0][0];
    assert_eq!(posts(&c), want);
    // The channel selector: CH2's tool post, Z+ refused at its end, Z- moves.
    c.press(Key::Tab);
    c.handle(PanelEvent::WheelScale(1000));
    c.press(Key::Right);
    assert!(c.message().contains("outside travel"), "{}", c.message());
    c.press(Key::PageDown);
    c.handle(PanelEvent::Wait);
    want[1][1] -= 1000;
    assert_eq!(posts(&c), want);
    // The lathe has no Y: the script's word is refused before anything runs, a key says so.
    assert!(novanc::lathe::console::events::takes(&PanelEvent::Jog(
        novanc::panel_model::Axis::Y,
        1
    ))
    .is_err());
    // E-STOP latches, a cycle loaded or not: no jog and no START until RESET.
    c.handle(PanelEvent::EStop);
    c.press(Key::Down);
    assert!(c.message().contains("EMERGENCY STOP"), "{}", c.message());
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert!(c.message().contains("START refused"), "{}", c.message());
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c), want, "nothing moved in E-STOP");
    c.handle(PanelEvent::Reset);
    // A cycle starts where the tool posts stand; while it runs, STEP is refused.
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.run_for(500_000_000, RunUntil::Time, || false);
    c.handle(PanelEvent::Op(OpMode::Step));
    let before = posts(&c);
    c.press(Key::Down);
    assert!(c.message().starts_with("STEP refused"), "{}", c.message());
    assert_eq!(posts(&c), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The keys of STEP as the help screen gives them, and the mode as the display names it.
#[test]
fn the_step_mode_and_its_keys_are_on_the_screen() {
    let dir = common::temp_dir("lathe-step-screen");
    let mut c = open(&dir);
    turn_to(&mut c, Key::Alt('6'), "STEP");
    assert!(novanc::console::help::LATHE_KEYS
        .iter()
        .any(|l| l.contains("Alt+6 STEP")));
    assert!(novanc::console::help::LATHE_HELP
        .iter()
        .any(|l| l.starts_with("Alt+1/5/6") && l.contains("STEP")));
    assert!(novanc::console::help::LATHE_HELP
        .iter()
        .any(|l| l.contains("Alt+w increment")));
    let _ = std::fs::remove_dir_all(&dir);
}

/// E-STOP holds until RESET on a console with no cycle loaded too: START after it is refused
/// and nothing moves (the console began a cycle here before).
#[test]
fn estop_with_no_cycle_loaded_holds_until_reset() {
    let dir = common::temp_dir("lathe-estop-latch");
    let mut c = open(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Start);
    assert!(
        c.message().starts_with("START refused: EMERGENCY STOP"),
        "{}",
        c.message()
    );
    c.run_for(2_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c), home);
    // Shown on every channel while it holds (the summary said IDLE before stop 40).
    assert!(c.view().summary.iter().all(|l| l.contains("ESTOP")));
    c.handle(PanelEvent::Reset);
    assert!(c.view().summary.iter().all(|l| l.contains("IDLE")));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.run_for(2_000_000_000, RunUntil::Time, || false);
    assert_ne!(posts(&c), home, "the cycle runs after RESET");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn after_an_estop_each_channels_listing_stays_at_the_block_it_stopped_in_until_reset() {
    // Before stop 47 the pointer went to the program's start at the E-STOP, as if RESET had
    // been pressed, while the tools stood where the cut stopped.
    let dir = common::temp_dir("lathe-estop-line");
    let mut c = open(&dir);
    c.handle(PanelEvent::Start);
    c.run_for(6_000_000_000, RunUntil::Time, || false);
    let before: Vec<u32> = c.view().channels.iter().map(|v| v.line).collect();
    assert!(before[0] > 0, "CH1 is in a block: {before:?}");
    c.handle(PanelEvent::EStop);
    let stopped: Vec<u32> = c.view().channels.iter().map(|v| v.line).collect();
    assert_eq!(stopped[0], before[0], "CH1's listing where it stopped");
    assert!(c.view().display.iter().any(|l| l.starts_with('>')));
    c.handle(PanelEvent::Reset);
    let reset: Vec<u32> = c.view().channels.iter().map(|v| v.line).collect();
    assert!(
        reset[0] < before[0],
        "RESET: back to the start: {reset:?} {before:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// HANDLE: each detent of the handwheel moves the selected channel's tool post one increment
/// on the wheel's axis (a jog key turns it on its own axis); the wheel is refused, and moves
/// nothing, in another mode.
#[test]
fn handle_moves_an_increment_a_detent_on_the_wheels_axis() {
    let dir = common::temp_dir("lathe-handle");
    let mut c = open(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Step));
    c.handle(PanelEvent::Wheel(Axis::Z, -1));
    assert!(c
        .message()
        .contains("turn the operation selector to HANDLE"));
    assert_eq!(posts(&c), home);
    turn_to(&mut c, Key::Alt('5'), "HANDLE");
    c.handle(PanelEvent::WheelScale(10));
    // A jog key is a detent on its axis: Down is X- (a radius).
    c.press(Key::Down);
    assert!(
        c.message().contains("HANDLE CH1 X- 0.010 mm"),
        "{}",
        c.message()
    );
    // Three detents of Z-, then the wheel keys turn it on Z, the axis last turned.
    c.handle(PanelEvent::Wheel(Axis::Z, -3));
    assert!(c.message().contains("3 × 0.010 mm"), "{}", c.message());
    c.press(Key::Alt(','));
    c.handle(PanelEvent::Wait);
    let mut want = home.clone();
    want[0] = [home[0][0] - 10, home[0][1] - 40];
    assert_eq!(posts(&c), want);
    // Past the travel: refused whole, nothing moves.
    c.handle(PanelEvent::Wheel(Axis::X, 5));
    assert!(c.message().contains("outside travel"), "{}", c.message());
    assert_eq!(posts(&c), want);
    let _ = std::fs::remove_dir_all(&dir);
}

/// CONTINUOUS: a jog runs until released, the summary line says JOG while the tool post
/// moves, a mode turned or E-STOP lets it go; in virtual time a key is a tap (one increment).
#[test]
fn continuous_jogs_until_released_and_the_screen_says_so() {
    let dir = common::temp_dir("lathe-continuous");
    let mut c = open(&dir);
    let home = posts(&c);
    turn_to(&mut c, Key::Alt('1'), "CONTINUOUS");
    c.handle(PanelEvent::WheelScale(100));
    // A key in virtual time (a script's `key Left`) is a tap.
    c.press(Key::Left);
    assert!(
        c.message().contains("CONTINUOUS CH1 Z- 0.100 mm"),
        "{}",
        c.message()
    );
    assert_eq!(posts(&c)[0], [home[0][0], home[0][1] - 100]);
    // A jog: Z- at jog feed until released.
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    assert!(c.message().contains("jogging"), "{}", c.message());
    c.run_for(300_000_000, RunUntil::Time, || false);
    let v = c.view();
    assert_eq!(v.channels[0].state, "JOG", "{:?}", v.summary[0]);
    assert!(v.summary[0].contains("JOG"), "{:?}", v.summary[0]);
    let moved = posts(&c)[0][1];
    assert!(
        moved < home[0][1] - 1_000,
        "jogged well past a tap: {moved}"
    );
    c.handle(PanelEvent::JogRelease);
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    let stopped = posts(&c)[0];
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c)[0], stopped, "at rest once released");
    assert_eq!(c.view().channels[0].state, "IDLE");
    // Only CH1 moved.
    assert_eq!(posts(&c)[1..], home[1..]);
    // A mode turned lets a jog go.
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    c.run_for(100_000_000, RunUntil::Time, || false);
    c.press(Key::Alt('6'));
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    let p = posts(&c)[0];
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c)[0], p, "the mode turned stopped the jog");
    // E-STOP stops a jog at once and latches: no jog until RESET.
    c.press(Key::Alt('1'));
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    c.run_for(100_000_000, RunUntil::Time, || false);
    c.handle(PanelEvent::EStop);
    let p = posts(&c)[0];
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c)[0], p, "E-STOP stopped the jog");
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    assert!(c.message().contains("EMERGENCY STOP"), "{}", c.message());
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c)[0], p);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A held key at a terminal in real time: the axis jogs while the key repeats and stops by
/// itself once the repeats stop (no key release comes from a terminal), the centre's rule.
#[test]
fn a_held_key_jogs_in_real_time_until_it_stops_repeating() {
    use std::time::{Duration, Instant};
    let dir = common::temp_dir("lathe-held");
    let mut c = open_real_time(&dir);
    let home = posts(&c);
    c.press(Key::Alt('1'));
    c.handle(PanelEvent::WheelScale(1));
    // 600 ms of auto-repeat, a key every 30 ms, the console ticking between them.
    let t0 = Instant::now();
    let mut last = Instant::now();
    let mut said = false;
    while t0.elapsed() < Duration::from_millis(600) {
        c.press(Key::Left);
        c.tick(0);
        // The summary and the message line say what the tool post does (under load a
        // repeat may come late and count as a new tap: looked for, not required each time).
        said |= c.view().channels[0].state == "JOG" && c.message().starts_with("JOG");
        std::thread::sleep(Duration::from_millis(30));
        last = Instant::now();
    }
    assert!(
        said,
        "JOG on the summary and the message line while the key is held"
    );
    // Let go: ticks only. The console releases the jog after its release time.
    let mut rest_at = None;
    let mut prev = posts(&c)[0];
    while last.elapsed() < Duration::from_secs(3) {
        std::thread::sleep(Duration::from_millis(20));
        c.tick(0);
        let p = posts(&c)[0];
        if p == prev && rest_at.is_none() && last.elapsed() > Duration::from_millis(200) {
            rest_at = Some(p);
        }
        prev = p;
    }
    let end = posts(&c)[0];
    assert!(
        home[0][1] - end[1] > 50,
        "a held key jogs past one increment: {} pulses",
        home[0][1] - end[1]
    );
    assert_eq!(Some(end), rest_at, "it came to rest and stayed");
    assert_eq!(end[0], home[0][0], "X did not move");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A front end that freezes with a jog key held (no repeat, no tick, no release): the kernel
/// stops the jog by itself within its deadman, in its own thread (docs/panel.md "The jog
/// deadman"), as on the centre.
#[test]
fn a_frozen_front_end_cannot_keep_a_jog_going() {
    use std::time::Duration;
    let dir = common::temp_dir("lathe-frozen");
    let mut c = open_real_time(&dir);
    c.press(Key::Alt('1'));
    c.handle(PanelEvent::WheelScale(1));
    // The key held until the tool post jogs (a few repeats; more when the machine is loaded).
    let t0 = std::time::Instant::now();
    while c.view().channels[0].state != "JOG" && t0.elapsed() < Duration::from_secs(5) {
        c.press(Key::Left);
        c.tick(0);
        std::thread::sleep(Duration::from_millis(30));
    }
    c.press(Key::Left);
    c.tick(0);
    let last = posts(&c)[0];
    assert_eq!(c.view().channels[0].state, "JOG");
    // Frozen: nothing from the front end for 1.5 s.
    std::thread::sleep(Duration::from_millis(1_500));
    c.tick(0);
    let a = posts(&c)[0];
    std::thread::sleep(Duration::from_millis(300));
    c.tick(0);
    assert_eq!(posts(&c)[0], a, "at rest");
    // 1000 mm/min is 16.7 mm/s: the deadman (250 ms) and the deceleration stop it within a
    // few millimetres; a runaway jog would have gone 25 mm.
    let ran = last[1] - a[1];
    assert!(
        (0..8_000).contains(&ran),
        "ran {ran} pulses after the last key"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// In DATA the arrows, PgUp/PgDn, Home/End and Delete are the editor's cursor keys on the
/// selected channel's program, the centre's (`console::entry::cursor_command`): each is the
/// editor command it stands for, stored like a typed one; the typed line stays on the entry
/// line; a cycle under way refuses them, and nothing moves.
#[test]
fn in_data_the_arrows_are_the_editors_cursor_keys() {
    let dir = common::temp_dir("lathe-cursor");
    let mut c = open(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Data));
    let line_of = |c: &LatheConsole| {
        c.view()
            .display
            .iter()
            .find_map(|l| l.strip_prefix('>').map(|r| r[..4].to_string()))
    };
    c.handle(PanelEvent::Key('Z'));
    c.press(Key::Down);
    c.press(Key::Down);
    assert_eq!(
        line_of(&c).as_deref(),
        Some("0003"),
        "{:?}",
        c.view().display
    );
    assert_eq!(c.message(), "");
    c.press(Key::Up);
    assert_eq!(line_of(&c).as_deref(), Some("0002"));
    // Nothing moved, and the typed line is still there.
    assert_eq!(posts(&c), home);
    assert!(
        c.frame_text().lines().any(|l| l.trim_end() == "> Z"),
        "{}",
        c.frame_text()
    );
    // Line 3 is a comment: Home, Right, then Delete takes its second character, stored.
    c.press(Key::Down);
    c.press(Key::Home);
    c.press(Key::Right);
    let before = c.programs()[0].text.clone();
    c.press(Key::Delete);
    let after = c.programs()[0].text.clone();
    assert_eq!(after.len() + 1, before.len());
    assert!(after.contains("\n(eed 004"), "{after}");
    // At the first line, Up says why and changes nothing.
    c.press(Key::PageUp);
    c.press(Key::Up);
    assert!(
        c.message()
            .starts_with("Up: the pointer is on the first line"),
        "{}",
        c.message()
    );
    // With a cycle under way: refused, said.
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Op(OpMode::Data));
    assert!(!c.cycle().is_over(), "{}", c.message());
    c.press(Key::Down);
    assert!(
        c.message().contains("the programs are in use"),
        "{}",
        c.message()
    );
    c.handle(PanelEvent::EStop);
    drop(c);
    assert_eq!(open(&dir).programs()[0].text, after, "stored");
    let _ = std::fs::remove_dir_all(&dir);
}

/// STOP on a manual move is the centre's rule (`console::relay::stop`, one for every console):
/// the tool post brakes to rest short of the increments asked, and the message says so. Before
/// stop 43 the lathe said "the cycle is already stopped" of a handwheel move braking, and a
/// STOP after it said nothing of the machine standing still.
#[test]
fn stop_brings_a_manual_move_to_rest_and_says_so() {
    let dir = common::temp_dir("lathe-stop-manual");
    let mut c = open_real_time(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Handle));
    c.handle(PanelEvent::WheelScale(1000));
    c.handle(PanelEvent::Wheel(Axis::Z, -20));
    assert!(c.message().contains("20 × 1.000 mm"), "{}", c.message());
    std::thread::sleep(std::time::Duration::from_millis(60));
    c.tick(0);
    assert!(!c.at_rest(), "the tool post moves: {}", c.message());
    c.handle(PanelEvent::Stop);
    assert_eq!(c.message(), "STOP: the manual move decelerates to rest");
    let t0 = std::time::Instant::now();
    while !c.at_rest() && t0.elapsed() < std::time::Duration::from_secs(5) {
        std::thread::sleep(std::time::Duration::from_millis(10));
        c.tick(0);
    }
    assert!(c.at_rest(), "at rest after STOP");
    let moved = home[0][1] - posts(&c)[0][1];
    assert!(
        moved > 0 && moved < 20_000,
        "stopped short of the 20 mm asked: {moved} pulses"
    );
    std::thread::sleep(std::time::Duration::from_millis(200));
    c.tick(0);
    assert_eq!(home[0][1] - posts(&c)[0][1], moved, "and stays");
    c.handle(PanelEvent::Stop);
    assert_eq!(c.message(), "STOP: the machine is not running");
    let _ = std::fs::remove_dir_all(&dir);
}

/// E-STOP during a CONTINUOUS jog, and a jog released, are one rule on both machines
/// (`console::relay`): the jog stops where E-STOP found it and is forgotten (after RESET
/// nothing goes on moving), and `jogrelease` is told to the machine and said on both (the
/// centre said nothing before stop 43).
#[test]
fn estop_stops_a_jog_and_a_released_jog_is_said_on_both_machines() {
    let dir = common::temp_dir("lathe-estop-jog");
    let mut c = open(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    c.run_for(100_000_000, RunUntil::Time, || false);
    let at = posts(&c);
    assert_ne!(at, home, "the jog moves: {}", c.message());
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Reset);
    c.run_for(1_000_000_000, RunUntil::Time, || false);
    assert_eq!(posts(&c), at, "the jog stopped at E-STOP");
    c.handle(PanelEvent::JogRelease);
    assert_eq!(c.message(), "jog released");
    let _ = std::fs::remove_dir_all(&dir);

    let mut m = common::open("centre-estop-jog");
    m.handle(PanelEvent::Op(OpMode::Continuous));
    m.handle(PanelEvent::Jog(Axis::X, 1));
    let home = m.view().axis_mm;
    m.handle(PanelEvent::WaitMs(100));
    let at = m.view().axis_mm;
    assert_ne!(at, home, "the jog moves: {}", m.message());
    m.handle(PanelEvent::EStop);
    m.handle(PanelEvent::Reset);
    m.handle(PanelEvent::WaitMs(1000));
    assert_eq!(m.view().axis_mm, at, "the jog stopped at E-STOP");
    m.handle(PanelEvent::JogRelease);
    assert_eq!(m.message(), "jog released");
}

/// A handwheel turned faster than the tool post moves: every detent is taken, queued by the
/// machine as the centre's are, and the tool post ends where the detents add up to (before
/// stop 43 the lathe refused each detent after the first while the tool post moved: `HANDLE
/// refused: the machine is moving`).
#[test]
fn detents_turned_while_the_tool_post_moves_are_all_taken() {
    let dir = common::temp_dir("lathe-fast-wheel");
    let mut c = open_real_time(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Handle));
    c.handle(PanelEvent::WheelScale(1000));
    for _ in 0..5 {
        c.handle(PanelEvent::Wheel(Axis::Z, -1));
        assert!(!c.message().contains("refused"), "{}", c.message());
    }
    let t0 = std::time::Instant::now();
    loop {
        std::thread::sleep(std::time::Duration::from_millis(20));
        c.tick(0);
        if (c.at_rest() && posts(&c) != home) || t0.elapsed() > std::time::Duration::from_secs(10) {
            break;
        }
    }
    let mut want = home.clone();
    want[0][1] -= 5_000;
    assert_eq!(posts(&c), want, "five detents of 1 mm");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A manual move is one rule on both machines (stop 44, `console::manual`): a STEP says what
/// it moved (the centre said nothing before) and moves at the next wait in a script, so that
/// E-STOP can stop it half way (a lathe ran it to rest at once before); a CONTINUOUS jog
/// says so while it moves, and not after it stops at its travel limit; an increment queued behind others that
/// the machine refuses when its turn comes is said (a lathe said nothing of it before).
#[test]
fn manual_moves_are_said_and_timed_alike_on_both_machines() {
    // The lathe: a STEP of 1 mm, E-STOP 5 ms into it.
    let dir = common::temp_dir("lathe-step-said");
    let mut c = open(&dir);
    let home = posts(&c);
    c.handle(PanelEvent::Op(OpMode::Step));
    c.handle(PanelEvent::WheelScale(1000));
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    assert_eq!(c.message(), "STEP CH1 Z- 1.000 mm (x1000)");
    assert_eq!(posts(&c), home, "a STEP moves at the next wait");
    c.handle(PanelEvent::WaitMs(5));
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Wait);
    let z = home[0][1] - posts(&c)[0][1];
    assert!(
        z > 0 && z < 1000,
        "E-STOP stopped the STEP half way: {z} pulses"
    );
    c.handle(PanelEvent::Reset);
    // Two STEPs of X- then three of X+ from the top of X: the third X+ is the machine's to
    // refuse when its turn comes, and it is said.
    for d in [-1, -1] {
        c.handle(PanelEvent::Jog(Axis::X, d));
    }
    c.handle(PanelEvent::Wait);
    for _ in 0..3 {
        c.handle(PanelEvent::Jog(Axis::X, 1));
    }
    c.handle(PanelEvent::Wait);
    assert!(
        c.message().starts_with("CH1 X jog refused:") && c.message().contains("travel limit"),
        "{}",
        c.message()
    );
    assert_eq!(
        posts(&c)[0][0],
        home[0][0],
        "X is back at the top of its travel"
    );
    // A CONTINUOUS jog says so while it moves, and not once it has stopped.
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    assert_eq!(c.message(), "CONTINUOUS CH1 Z-: jogging");
    c.handle(PanelEvent::WaitMs(50));
    assert_eq!(c.message(), "CONTINUOUS CH1 Z-: jogging");
    // It runs to the travel limit: no operator action since, and the jog is not said.
    c.handle(PanelEvent::Wait);
    assert!(!c.message().contains("jogging"), "{}", c.message());
    let _ = std::fs::remove_dir_all(&dir);

    // The centre: the same words without a channel, and the same timing.
    let mut m = common::open("centre-step-said");
    m.handle(PanelEvent::Op(OpMode::Step));
    m.handle(PanelEvent::WheelScale(1000));
    let home = m.view().axis_mm;
    m.handle(PanelEvent::Jog(Axis::Z, -1));
    assert_eq!(m.message(), "STEP Z- 1.000 mm (x1000)");
    assert_eq!(m.view().axis_mm, home, "a STEP moves at the next wait");
    m.handle(PanelEvent::WaitMs(5));
    m.handle(PanelEvent::EStop);
    m.handle(PanelEvent::Wait);
    let z = home[2] - m.view().axis_mm[2];
    assert!(
        z > 0.0 && z < 1.0,
        "E-STOP stopped the STEP half way: {z} mm"
    );
    m.handle(PanelEvent::Reset);
    m.handle(PanelEvent::Op(OpMode::Continuous));
    m.handle(PanelEvent::Jog(Axis::X, 1));
    assert_eq!(m.message(), "CONTINUOUS X+: jogging");
    m.handle(PanelEvent::WaitMs(50));
    assert_eq!(m.message(), "CONTINUOUS X+: jogging");
    m.handle(PanelEvent::Wait);
    assert!(!m.message().contains("jogging"), "{}", m.message());
}

/// A STEP after the cycle has finished moves at the next wait: a finished channel with a
/// manual move queued is not at rest (stop 44: the random sequences found the console's
/// `wait` ending at once with the increment still queued, and this test then found the
/// kernel's `progressing` leaving the move out too, so that the wait ended with 0.12 mm of a
/// 1 mm STEP done).
#[test]
fn a_step_after_the_cycle_has_finished_moves_at_the_next_wait() {
    let dir = common::temp_dir("lathe-step-after-cycle");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert!(
        c.view().channels.iter().all(|ch| ch.state == "DONE"),
        "{:?}",
        c.view()
            .channels
            .iter()
            .map(|ch| &ch.state)
            .collect::<Vec<_>>()
    );
    c.handle(PanelEvent::Op(OpMode::Step));
    c.handle(PanelEvent::WheelScale(1000));
    let before = posts(&c);
    c.handle(PanelEvent::Jog(Axis::Z, -1));
    assert!(c.message().starts_with("STEP CH1 Z-"), "{}", c.message());
    c.handle(PanelEvent::Wait);
    assert_eq!(posts(&c)[0][1], before[0][1] - 1000, "{}", c.message());
    let _ = std::fs::remove_dir_all(&dir);
}

/// START's refusals are one rule on both machines (stop 44, `console::relay::start_allowed`):
/// in a manual position the selector's words first, E-STOP's in a running position (before,
/// a lathe in CONTINUOUS under E-STOP said E-STOP's and the centre the selector's).
#[test]
fn start_is_refused_in_the_same_words_on_both_machines() {
    let (dir, mut c, mut m) = common::both_machines("start-words");
    let mut said = Vec::new();
    for op in [OpMode::Auto, OpMode::Continuous, OpMode::Mdi, OpMode::Step] {
        c.handle(PanelEvent::EStop);
        m.handle(PanelEvent::EStop);
        c.handle(PanelEvent::Op(op));
        m.handle(PanelEvent::Op(op));
        c.handle(PanelEvent::Start);
        m.handle(PanelEvent::Start);
        assert_eq!(c.message(), m.message(), "{op:?}");
        said.push(m.message().to_string());
    }
    assert_eq!(
        said,
        [
            "START refused: EMERGENCY STOP in force, press RESET",
            "START refused in CONTINUOUS: use AUTO, MDI or SINGLE BLOCK",
            "START refused: EMERGENCY STOP in force, press RESET",
            "START refused in STEP: use AUTO, MDI or SINGLE BLOCK",
        ]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A line entered in AUTO goes nowhere, and stays for TARGET and FAULT, which take the typed
/// line in any mode (stop 44: the message said `turn to MDI or DATA`, and the turn cleared
/// the line it advised keeping).
#[test]
fn a_line_entered_in_auto_stays_for_target() {
    let dir = common::temp_dir("lathe-auto-line");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Type("12".into()));
    assert_eq!(
        c.message(),
        "AUTO takes no line; it stays for TARGET (Alt+n) or FAULT (Alt+x)"
    );
    c.press(Key::Alt('n'));
    assert_eq!(c.message(), "part target 12");
    assert_eq!(c.counter().target, 12);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The one entry rule (stop 45): a line the machine refuses stays on the entry line beside the
/// reason, on both machines, to be entered again or corrected; before, the centre dropped a
/// refused editor or MDI line (only its pages kept one), and a lathe's RESET cleared the line.
#[test]
fn a_refused_line_stays_on_the_entry_line_on_both_machines() {
    use novanc::panel_model::DataMode;
    let (dir, mut c, mut m) = common::both_machines("refused-line");
    let lathe_line = |c: &LatheConsole| c.view().display.last().map(|l| l.trim_end().to_string());
    // An editor command line that fails: the program is unchanged, the line stays.
    m.handle(PanelEvent::Op(OpMode::Data));
    m.handle(PanelEvent::Data(DataMode::Revise));
    c.handle(PanelEvent::Op(OpMode::Data));
    let before = c.view().display.clone();
    m.handle(PanelEvent::Type("SNOTHERE99".into()));
    c.handle(PanelEvent::Type("SNOTHERE99".into()));
    assert!(m.message().contains("not found"), "{}", m.message());
    assert!(c.message().contains("not found"), "{}", c.message());
    assert_eq!(m.view().entry, "SNOTHERE99");
    assert_eq!(lathe_line(&c).as_deref(), Some("> SNOTHERE99"));
    assert_eq!(
        c.view().display[..before.len() - 2],
        before[..before.len() - 2]
    );
    // Corrected with RUBOUT and entered again: it acts, and the line is gone.
    for _ in 0.."NOTHERE99".len() {
        m.handle(PanelEvent::Rubout);
        c.handle(PanelEvent::Rubout);
    }
    m.handle(PanelEvent::Key('L'));
    c.handle(PanelEvent::Key('L'));
    m.handle(PanelEvent::Eob);
    c.handle(PanelEvent::Eob);
    assert_eq!(m.message(), "ok");
    assert_eq!(m.view().entry, "");
    assert_eq!(c.message(), "ok");
    assert_eq!(
        lathe_line(&c).as_deref(),
        Some(">"),
        "{:?}",
        c.view().display
    );
    // The centre's T-CODE SETTING out of the magazine: refused, and kept.
    m.handle(PanelEvent::Data(DataMode::TCode));
    m.handle(PanelEvent::Type("T99=5".into()));
    assert!(m.message().starts_with("T99 refused"), "{}", m.message());
    assert_eq!(m.view().entry, "T99=5");
    // MDI: an empty line says what to do on both machines; a line refused stays.
    m.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    m.handle(PanelEvent::Eob);
    c.handle(PanelEvent::Eob);
    assert!(m.message().starts_with("MDI: type"), "{}", m.message());
    assert_eq!(c.message(), "MDI: type a block, Enter, then START");
    m.handle(PanelEvent::Type("G0 X10".into()));
    m.handle(PanelEvent::Start);
    m.handle(PanelEvent::Stop);
    m.handle(PanelEvent::Type("G0 X20".into()));
    assert!(
        m.message().starts_with("MDI refused: a run is loaded"),
        "{}",
        m.message()
    );
    assert_eq!(m.view().entry, "G0 X20");
    // RESET keeps the line being typed, on both machines (a lathe's cleared it before).
    for ch in "G0X5".chars() {
        c.handle(PanelEvent::Key(ch));
    }
    c.handle(PanelEvent::Reset);
    m.handle(PanelEvent::Reset);
    assert_eq!(
        c.message(),
        "RESET CH1: spindle and coolant stopped, MDI buffer cleared"
    );
    // After an E-STOP, RESET releases the machine, and says so.
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Reset);
    assert_eq!(
        c.message(),
        "RESET: E-STOP released; every channel's spindle and coolant stopped"
    );
    assert_eq!(lathe_line(&c).as_deref(), Some("> G0X5"));
    assert_eq!(m.view().entry, "G0 X20");
    // The centre still refuses each data key where it has no use for a line, and says so.
    m.handle(PanelEvent::Op(OpMode::Auto));
    m.handle(PanelEvent::Key('G'));
    assert!(m
        .message()
        .starts_with("key 'G' refused: data keys work in DATA INPUT"));
    assert_eq!(m.view().entry, "");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The editor's cursor keys are one rule on both machines (stop 45): on the mode display in
/// DATA they move the pointer, and Delete at the end of the program says so in the same words;
/// with a page up they do not edit what the page hides (the centre's Down moved its pointer
/// under the POS page before).
#[test]
fn the_editor_cursor_keys_are_one_rule() {
    use novanc::panel_model::DataMode;
    let (dir, mut c, mut m) = common::both_machines("cursor-keys");
    m.handle(PanelEvent::Op(OpMode::Data));
    m.handle(PanelEvent::Data(DataMode::Revise));
    c.handle(PanelEvent::Op(OpMode::Data));
    let header = |m: &novanc::console::Console| m.view().display[0].clone();
    assert!(header(&m).ends_with("L1/9"), "{}", header(&m));
    m.press(Key::Ctrl('p'));
    m.press(Key::Down);
    m.press(Key::Ctrl('p'));
    assert!(header(&m).ends_with("L1/9"), "under POS: {}", header(&m));
    m.press(Key::Down);
    assert!(header(&m).ends_with("L2/9"), "{}", header(&m));
    // To the end of each program, then Delete.
    m.handle(PanelEvent::Type("99999L".into()));
    c.handle(PanelEvent::Type("99999L".into()));
    m.press(Key::Delete);
    c.press(Key::Delete);
    for said in [m.message(), c.message()] {
        assert!(
            said.starts_with("Delete: nothing after the pointer"),
            "{said}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The batch done, START says to set a new target (Alt+n); the new target begins a new batch
/// from 0 and START runs it. Until stop 52 the finished cycle refused the target (`target 2: a
/// channel has already finished`): the operator was told to do what the console refused.
#[test]
fn a_new_target_after_the_batch_is_done_lets_start_run_again() {
    let dir = common::temp_dir("lathe-target-after-batch");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert_eq!(c.counter().counts, [1, 1, 1]);
    c.handle(PanelEvent::Start);
    assert!(
        c.message().contains("set a new target (Alt+n)"),
        "{}",
        c.message()
    );
    c.handle(PanelEvent::Target(2));
    assert_eq!(c.message(), "part target 2");
    assert_eq!(
        (c.counter().target, c.counter().counts.clone()),
        (2, vec![0, 0, 0])
    );
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.handle(PanelEvent::Wait);
    assert_eq!(c.counter().counts, [2, 2, 2], "{}", c.message());
    // The target kept across a restart.
    drop(c);
    assert_eq!(open(&dir).counter().target, 2);
}

/// `JOG 120` typed on POS (the centre's words): the selected channel's jog feed, on its
/// machine at once and kept across a cycle; the other channels keep theirs. Before stop 60
/// the kernel's jog feed command reached its first channel only and the lathe's POS refused
/// `JOG`. Stored, it holds across a restart.
#[test]
fn pos_jog_sets_the_selected_channels_jog_feed() {
    let dir = common::temp_dir("lathe-pos-jog");
    let mut c = open(&dir);
    let mm = LatheDesc::citizen().pulse_mm;
    // Z- for one second of machine time on channel `ch` in CONTINUOUS: how far, mm.
    let jog_one_second = |c: &mut LatheConsole, ch: usize| {
        c.handle(PanelEvent::Channel(ch));
        c.handle(PanelEvent::Op(OpMode::Continuous));
        let z = posts(c)[ch][1];
        c.handle(PanelEvent::Jog(Axis::Z, -1));
        c.run_for(1_000_000_000, RunUntil::Time, || false);
        c.handle(PanelEvent::JogRelease);
        c.run_for(1_000_000_000, RunUntil::Time, || false);
        (z - posts(c)[ch][1]) as f64 * mm
    };
    let shows = |c: &LatheConsole, text: &str| c.view().display.iter().any(|l| l.contains(text));
    let default = jog_one_second(&mut c, 0);
    c.handle(PanelEvent::Channel(1));
    c.press(Key::Ctrl('p'));
    c.handle(PanelEvent::Type("JOG 120".into()));
    assert_eq!(c.message(), "CH2 jog feed 120 mm/min");
    assert!(shows(&c, "JOG 120 mm/min"), "{:#?}", c.view().display);
    // A feed past the rapid rate, or none: refused, kept on the entry line, nothing changed.
    c.handle(PanelEvent::Type("JOG 0".into()));
    assert!(c.message().contains("JOG refused"), "{}", c.message());
    assert_eq!(c.entry(), "JOG 0");
    c.press(Key::Ctrl('p'));
    let slow = jog_one_second(&mut c, 1);
    // 120 mm/min is 2 mm a second, less what the ramps take; the machine's 1000 mm/min
    // on channel 1 went about 16.
    assert!((1.5..=2.05).contains(&slow), "CH2 jogged {slow} mm");
    assert!(default > 10.0, "CH1 jogged {default} mm");
    assert!((jog_one_second(&mut c, 0) - default).abs() < 0.01);
    // Kept across an MDI run on the channel.
    c.handle(PanelEvent::Channel(1));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type("G4 P0.1".into()));
    c.handle(PanelEvent::Start);
    c.run_for(2_000_000_000, RunUntil::Rest, || false);
    assert!((jog_one_second(&mut c, 1) - slow).abs() < 0.01);
    // JOG RAPID: the channel's rapid rate; JOG: back to its feed.
    c.press(Key::Ctrl('p'));
    c.handle(PanelEvent::Type("JOG RAPID".into()));
    assert!(
        c.message().starts_with("CH2 rapid jog: "),
        "{}",
        c.message()
    );
    c.handle(PanelEvent::Type("JOG".into()));
    assert_eq!(c.message(), "CH2 jog feed 120 mm/min");
    // Kept across a restart (the stores' `chjog`), on the channel's machine from power-on;
    // CH3's rapid jog too.
    c.handle(PanelEvent::Channel(2));
    c.handle(PanelEvent::Type("JOG RAPID".into()));
    assert!(
        c.message().starts_with("CH3 rapid jog: "),
        "{}",
        c.message()
    );
    assert!(c.finish().is_ok());
    let mut c = open(&dir);
    assert!((jog_one_second(&mut c, 1) - slow).abs() < 0.01);
    assert!(
        jog_one_second(&mut c, 2) > default,
        "CH3 jogs at its rapid rate"
    );
    c.handle(PanelEvent::Channel(1));
    c.press(Key::Ctrl('p'));
    assert!(shows(&c, "JOG 120 mm/min"), "{:#?}", c.view().display);
    let _ = std::fs::remove_dir_all(&dir);
}
