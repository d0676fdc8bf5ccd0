//! STEP on the lathe console (docs/lathe.md "STEP: moving a tool post by hand"): the jog keys
//! move the selected channel's tool post one increment on the one kernel, as the centre's
//! STEP does; every refusal says why and moves nothing; E-STOP latches until RESET, with or
//! without a cycle loaded; a cycle starts where the tool posts stand.

mod common;

use novanc::lathe::console::{LatheConsole, RunUntil};
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{OpMode, PanelEvent};
use novanc_panel::Key;

fn open(state: &std::path::Path) -> LatheConsole {
    LatheConsole::open(LatheDesc::citizen(), state, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
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
    assert!(c.message().contains("turn to STEP"), "{}", c.message());
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
    let mut want = home.clone();
    want[0] = [home[0][0] - 100, home[0][1] - 200];
    assert_eq!(posts(&c), want);
    // Each channel starts at the top of its travel: X+ past it is refused, and says so.
    c.press(Key::Up);
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
    assert!(c.message().starts_with("jog refused"), "{}", c.message());
    assert_eq!(posts(&c), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The keys of STEP as the help screen gives them, and the mode as the display names it.
#[test]
fn the_step_mode_and_its_keys_are_on_the_screen() {
    let dir = common::temp_dir("lathe-step-screen");
    let mut c = open(&dir);
    c.press(Key::Alt('6'));
    let v = c.view();
    assert!(v.display[0].trim_end().ends_with("STEP"), "{:?}", v.display);
    assert!(novanc::lathe::console::view::LATHE_KEYS
        .iter()
        .any(|l| l.contains("Alt+6 STEP")));
    assert!(novanc::lathe::console::view::LATHE_HELP
        .iter()
        .any(|l| l.starts_with("Alt+6 STEP") && l.contains("Alt+w")));
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
    assert!(c.view().summary.iter().all(|l| l.contains("IDLE")));
    c.handle(PanelEvent::Reset);
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.run_for(2_000_000_000, RunUntil::Time, || false);
    assert_ne!(posts(&c), home, "the cycle runs after RESET");
    let _ = std::fs::remove_dir_all(&dir);
}
