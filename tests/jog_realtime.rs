//! CONTINUOUS jogging in real time, as a terminal delivers the keys (docs/panel.md,
//! "Jogging"): a tap moves exactly one increment; a held key (the terminal's auto-repeat, a
//! press every ~30 ms) jogs continuously; when the repeats stop the axis stops within the
//! release time and its deceleration, and no other axis moves.

mod common;

use common::{keys, temp_dir};
use novanc::console::keys::{JOG_DEADMAN, JOG_RELEASE, REPEAT_GAP};
use novanc::console::{Console, ConsoleConfig};
use novanc::pulse_core::ClockMode;
use std::time::{Duration, Instant};

/// A console on the defaults in real time, in CONTINUOUS.
fn open(name: &str) -> Console {
    let mut cfg = ConsoleConfig::new(temp_dir(name));
    cfg.clock = ClockMode::RealTime;
    let mut c = Console::open(cfg).unwrap().0;
    keys(&mut c, &["Alt+1"]);
    c
}

/// Display ticks (as the terminal loop makes them every ~20 ms) for `ms` milliseconds.
fn ticks(c: &mut Console, ms: u64) {
    let end = Instant::now() + Duration::from_millis(ms);
    while Instant::now() < end {
        c.tick();
        std::thread::sleep(Duration::from_millis(10));
    }
    c.tick();
}

/// Ticks until the machine has been at rest for 300 ms (at most 10 s).
fn settle(c: &mut Console) -> [i64; 3] {
    let t0 = Instant::now();
    let mut last = c.status().pos;
    let mut still = Instant::now();
    while t0.elapsed() < Duration::from_secs(10) {
        ticks(c, 20);
        let now = c.status().pos;
        if now != last || c.status().moving {
            last = now;
            still = Instant::now();
        } else if still.elapsed() > Duration::from_millis(300) {
            break;
        }
    }
    last.xyz()
}

#[test]
fn a_tap_moves_exactly_one_increment() {
    let mut c = open("jog-tap");
    let before = settle(&mut c);
    keys(&mut c, &["Right"]);
    let after = settle(&mut c);
    // The default increment is x100 pulses of 0.001 mm: 0.100 mm.
    assert_eq!(after[0] - before[0], 100, "{}", c.frame_text());
    assert_eq!(after[1..], before[1..]);
    // A second tap, slower than auto-repeat, is another increment, not a jog.
    std::thread::sleep(REPEAT_GAP * 2);
    keys(&mut c, &["Left"]);
    let back = settle(&mut c);
    assert_eq!(back, before);
}

#[test]
fn a_held_key_jogs_and_stops_when_it_is_released() {
    let mut c = open("jog-hold");
    let before = settle(&mut c);
    // Auto-repeat: a press every 20-30 ms for 1.2 s.
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_millis(1200) {
        keys(&mut c, &["Up"]);
        ticks(&mut c, 20);
    }
    let at_release = c.status().pos;
    // While it jogs the screen says so, from the machine's state (stop 44: the centre's said
    // nothing, and each repeat cleared the jog's own message).
    let said = c.frame_text();
    assert!(said.contains("JOG: an axis moves by hand"), "{said}");
    let moved = at_release[1] - before[1];
    // A held key is a continuous jog, far more than one increment (the jog feed is about
    // 1000 mm/min: some 15 mm in a second).
    assert!(moved > 2_000, "a held key moved only {moved} pulses");
    let after = settle(&mut c);
    let coast = after[1] - at_release[1];
    eprintln!("held 1.2 s: {moved} pulses; after the last repeat: {coast} pulses");
    // It stops within the release time plus its deceleration: at 1000 mm/min the release
    // time is under 3 mm; the deceleration adds less.
    let release_mm = JOG_RELEASE.as_secs_f64() * 1000.0 / 60.0;
    assert!(
        (0..=((release_mm + 3.0) * 1000.0) as i64).contains(&coast),
        "after the last repeat the axis went on {coast} pulses"
    );
    assert_eq!([after[0], after[2]], [before[0], before[2]], "only Y moves");
    assert!(!c.status().moving);
    // At rest, it no longer says so.
    let said = c.frame_text();
    assert!(
        !said.contains("JOG:") && !said.contains("jogging"),
        "{said}"
    );
}

/// A frozen front end (docs/panel.md, "The jog deadman"): the console stops running in the
/// middle of a held key's jog — no more keys, no display ticks, so its own release never comes —
/// and the pulse core stops the axis on its own within the deadman time and its deceleration.
#[test]
fn a_frozen_console_does_not_leave_an_axis_jogging() {
    let mut c = open("jog-frozen");
    let before = settle(&mut c);
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_millis(800) {
        keys(&mut c, &["Up"]);
        ticks(&mut c, 20);
    }
    let frozen_at = c.core().status().pos;
    assert!(
        frozen_at[1] - before[1] > 2_000,
        "the held key did not jog: {before:?} -> {frozen_at:?}\n{}",
        c.frame_text()
    );
    // Frozen: nothing from the console for 1.5 s.
    std::thread::sleep(Duration::from_millis(1500));
    let s = c.core().status();
    assert!(!s.moving, "the axis still jogs with the console frozen");
    let coast = s.pos[1] - frozen_at[1];
    // The deadman at 1000 mm/min is about 4.2 mm; the deceleration adds less than 3 mm.
    let deadman_mm = JOG_DEADMAN.as_secs_f64() * 1000.0 / 60.0;
    eprintln!("frozen console: the axis went on {coast} pulses");
    assert!(
        (0..=((deadman_mm + 3.0) * 1000.0) as i64).contains(&coast),
        "with the console frozen the axis went on {coast} pulses"
    );
}

/// The window's held JOG button (a `PanelEvent::Jog` until its release): each display tick
/// keeps the jog alive, so it jogs as long as the front end runs, and stops on its own when
/// the front end freezes before the release.
#[test]
fn a_held_button_jogs_while_the_front_end_runs_and_stops_when_it_freezes() {
    use novanc::panel_model::{Axis, PanelEvent};
    let mut c = open("jog-button");
    let before = settle(&mut c);
    c.handle(PanelEvent::Jog(Axis::Y, 1));
    ticks(&mut c, 800);
    let s = c.core().status();
    assert!(
        s.moving,
        "the held button's jog stopped while the front end ran"
    );
    let frozen_at = s.pos;
    assert!(frozen_at[1] - before[1] > 8_000, "moved {:?}", frozen_at);
    std::thread::sleep(Duration::from_millis(1500));
    let s = c.core().status();
    assert!(!s.moving, "the axis still jogs with the window frozen");
    let deadman_mm = JOG_DEADMAN.as_secs_f64() * 1000.0 / 60.0;
    let coast = s.pos[1] - frozen_at[1];
    assert!(
        (0..=((deadman_mm + 3.0) * 1000.0) as i64).contains(&coast),
        "with the window frozen the axis went on {coast} pulses"
    );
}
