//! A lathe's position memory and reference return (docs/lathe.md "Position memory"): each tool
//! post is kept in the stores where it stands, and `moving` before anything can move it; a
//! restart puts it back there; a console that died while a post moved owes that channel's
//! reference return (HOME: X out to the top of the travel first, then Z), and AUTO and that
//! channel's MDI are refused until it is made.

mod common;

use common::open_citizen as open;
use novanc::lathe::console::{LatheConsole, RunUntil};
use novanc::panel_model::{Axis, OpMode, PanelEvent};

/// Channel `ch`'s tool post, pulses [X radius, Z].
fn post(c: &LatheConsole, ch: usize) -> [i64; 2] {
    c.tips()[ch].0
}

/// The top of the Citizen's travel, every channel's: X 35 mm (a radius), Z 60 mm.
const TOP: [i64; 2] = [35_000, 60_000];

/// Jogs the selected channel's post along `axis` for `ms` of machine time, then lets go and
/// runs it to rest.
fn jog(c: &mut LatheConsole, axis: Axis, dir: i8, ms: u64) {
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.handle(PanelEvent::Jog(axis, dir));
    assert!(c.message().contains("jogging"), "{}", c.message());
    c.tick(ms * 1_000_000);
    c.handle(PanelEvent::JogRelease);
    c.step(2_000_000_000, RunUntil::Rest);
}

#[test]
fn a_restart_puts_every_tool_post_where_it_was_left() {
    let dir = common::temp_dir("lathe-pos-kept");
    let mut c = open(&dir);
    assert_eq!(post(&c, 1), TOP, "the first opening: the top of the travel");
    c.handle(PanelEvent::Channel(1));
    jog(&mut c, Axis::X, -1, 500);
    jog(&mut c, Axis::Z, -1, 300);
    let left = post(&c, 1);
    assert!(left[0] < TOP[0] && left[1] < TOP[1], "{left:?}");
    c.close(None).unwrap();
    let mut c = open(&dir);
    assert_eq!(post(&c, 1), left, "CH2 where it was left");
    assert_eq!(post(&c, 0), TOP);
    assert_eq!(c.home_owed(), &[false, false, false]);
    // Nothing owed: a cycle starts, and its programs are read from where the posts stand.
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
}

#[test]
fn a_console_killed_while_a_post_moved_owes_that_channels_home_until_it_is_made() {
    let dir = common::temp_dir("lathe-pos-killed");
    let mut c = open(&dir);
    c.handle(PanelEvent::Channel(2));
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.handle(PanelEvent::Jog(Axis::X, -1));
    c.tick(300_000_000);
    assert!(c.cycle().channels()[2].status.moving);
    let guess = post(&c, 2);
    // Dropped with the post moving, as kill -9 leaves the stores (no close, no last write).
    drop(c);
    let mut c = open(&dir);
    assert_eq!(c.home_owed(), &[false, false, true]);
    assert!(
        c.message()
            .starts_with("the console stopped while CH3 moved: the position is not known"),
        "{}",
        c.message()
    );
    // The best guess: where the stores last had it (before the jog began).
    assert_eq!(post(&c, 2), TOP, "{guess:?}");
    // AUTO runs every channel: refused, naming the one that owes HOME; MDI on another
    // channel runs.
    c.handle(PanelEvent::Start);
    assert!(
        c.message()
            .starts_with("START refused: CH3's position is not known since the restart"),
        "{}",
        c.message()
    );
    assert!(!c.cycle().loaded());
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type("G0 X60 Z50".into()));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "MDI CH1 runs");
    c.step(5_000_000_000, RunUntil::Rest);
    c.handle(PanelEvent::Channel(2));
    c.handle(PanelEvent::Type("G0 X60 Z50".into()));
    c.handle(PanelEvent::Start);
    assert!(
        c.message().starts_with("START refused: CH3's"),
        "{}",
        c.message()
    );
    // A jog is allowed (the operator sees the post), and a second restart before HOME still
    // owes it.
    jog(&mut c, Axis::Z, -1, 400);
    jog(&mut c, Axis::X, -1, 400);
    c.close(None).unwrap();
    let mut c = open(&dir);
    assert_eq!(c.home_owed(), &[false, false, true]);
    c.handle(PanelEvent::Channel(2));
    let from = post(&c, 2);
    assert!(from[0] < TOP[0] && from[1] < TOP[1], "{from:?}");
    // HOME: X out first, then Z, at the channel's own rates.
    c.handle(PanelEvent::Home);
    assert_eq!(c.message(), "CH3 HOME: reference return, X first, then Z");
    let mut x_first = false;
    c.tick(10_000_000);
    // The summary line says what the post does.
    assert_eq!(c.view().channels[2].state, "HOME");
    assert!(
        c.view().summary[2].contains("CH3 HOME"),
        "{:?}",
        c.view().summary
    );
    for _ in 0..400 {
        c.tick(10_000_000);
        let p = post(&c, 2);
        if p[1] == from[1] && p[0] > from[0] {
            x_first = true;
        }
        assert!(
            p[1] == from[1] || p[0] == TOP[0],
            "Z moved before X was out: {p:?}"
        );
        if !c.cycle().channels()[2].status.moving && p == TOP {
            break;
        }
    }
    c.tick(10_000_000);
    assert!(x_first, "X did not move first");
    assert_eq!(post(&c, 2), TOP);
    assert_eq!(c.home_owed(), &[false, false, false]);
    assert_eq!(
        c.message(),
        "CH3 HOME: the reference return is made; the position is known"
    );
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    drop(c);
    // Killed mid-cycle: every channel was in the cycle, and owes HOME.
    let c = open(&dir);
    assert_eq!(c.home_owed(), &[true, true, true]);
}

#[test]
fn home_is_refused_with_a_cycle_under_way_in_e_stop_and_under_machine_lock() {
    let dir = common::temp_dir("lathe-pos-refused");
    let mut c = open(&dir);
    c.handle(PanelEvent::MachineLock(true));
    c.handle(PanelEvent::Home);
    assert_eq!(c.message(), "CH1 HOME refused: MACHINE LOCK is on");
    c.handle(PanelEvent::MachineLock(false));
    c.handle(PanelEvent::Start);
    c.tick(100_000_000);
    c.handle(PanelEvent::Home);
    assert_eq!(
        c.message(),
        "CH1 HOME refused: a cycle is under way (RESET it first)"
    );
    c.handle(PanelEvent::EStop);
    c.tick(1_000_000);
    c.handle(PanelEvent::Home);
    assert!(
        c.message().starts_with("CH1 HOME refused") && c.message().contains("EMERGENCY STOP"),
        "{}",
        c.message()
    );
    assert_eq!(c.home_owed(), &[false, false, false]);
}
