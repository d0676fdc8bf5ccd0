//! The lathe console in real time runs on the one kernel's thread, not on its screen loop
//! (issue 22: "the lathe's real time is the screen loop"): with the front end frozen (no
//! `tick` for a while), the machine still moves; E-STOP then stops every channel, and RESET
//! and START begin a new cycle from each program's start.

mod common;

use novanc::lathe::console::{LatheConsole, RunUntil};
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::ClockMode;
use std::time::{Duration, Instant};

fn console() -> LatheConsole {
    let dir = common::temp_dir("lathe-realtime");
    let (c, _) = LatheConsole::open_on(
        LatheDesc::citizen(),
        &dir,
        (12, 40),
        None,
        ClockMode::RealTime,
    )
    .unwrap();
    c
}

/// Ticks (in real time: takes the kernel's state) until `done` or `patience` passes.
fn until(c: &mut LatheConsole, patience: Duration, done: impl Fn(&LatheConsole) -> bool) -> bool {
    let end = Instant::now() + patience;
    while Instant::now() < end {
        c.tick(0);
        if done(c) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

#[test]
fn the_machine_keeps_its_clock_while_the_screen_is_frozen() {
    let mut c = console();
    c.handle(PanelEvent::Start);
    assert!(
        until(&mut c, Duration::from_secs(20), |c| c.machine_ns() > 0),
        "the kernel started"
    );
    let t0 = c.machine_ns();
    let pos0 = c.view().channels[0].pos;
    // The front end freezes: no tick, no key, for 400 ms of wall time.
    std::thread::sleep(Duration::from_millis(400));
    let frozen_t = c.machine_ns();
    assert_eq!(
        frozen_t, t0,
        "the console's own view does not move without a tick"
    );
    c.tick(0);
    let t1 = c.machine_ns();
    // The machine went on meanwhile (at least 200 ms of machine time: the machine is shared,
    // so the thread may have been slow to get a core, but it does not wait for the screen).
    assert!(
        t1 >= t0 + 200_000_000,
        "machine time {t0} -> {t1} ns while the screen was frozen 400 ms"
    );
    assert_ne!(c.view().channels[0].pos, pos0, "CH1 moved meanwhile");
}

#[test]
fn estop_then_reset_and_start_begin_a_new_cycle_in_real_time() {
    let mut c = console();
    c.handle(PanelEvent::Start);
    assert!(
        until(&mut c, Duration::from_secs(30), |c| c
            .view()
            .channels
            .iter()
            .any(|ch| ch.state == "RUN" && ch.line > 10)),
        "CH1 is into its program: {:?}",
        c.view().summary
    );
    c.handle(PanelEvent::EStop);
    let v = c.view();
    assert!(
        v.channels.iter().all(|ch| ch.state == "ESTOP"),
        "every channel in E-STOP at once: {:?}",
        v.summary
    );
    let pos: Vec<[i64; 2]> = v.channels.iter().map(|ch| ch.pos).collect();
    std::thread::sleep(Duration::from_millis(200));
    c.tick(0);
    let after: Vec<[i64; 2]> = c.view().channels.iter().map(|ch| ch.pos).collect();
    assert_eq!(after, pos, "nothing moves after E-STOP");
    c.handle(PanelEvent::Reset);
    assert!(
        c.view().channels.iter().all(|ch| ch.state == "IDLE"),
        "RESET returns every channel to its program start: {:?}",
        c.view().summary
    );
    c.handle(PanelEvent::Start);
    // The new cycle begins at each program's first block, none resumed mid-way.
    let first = c.view().channels[0].line;
    assert!(
        first <= 10,
        "CH1 begins again at its start (line {first}), not inside the interrupted block"
    );
}

#[test]
fn a_cycle_goes_on_from_the_consoles_machine_time() {
    // One time base for the console and its recording: a cycle started at 1 s of machine
    // time runs from 1 s, not from 0 (virtual time, as a script).
    let dir = common::temp_dir("lathe-timebase");
    let (mut c, _) = LatheConsole::open(LatheDesc::citizen(), &dir, 12, 40, None).unwrap();
    c.tick(1_000_000_000);
    c.handle(PanelEvent::Start);
    assert_eq!(c.machine_ns(), 1_000_000_000);
    c.run_for(100_000_000, RunUntil::Time, || false);
    assert_eq!(c.machine_ns(), 1_100_000_000);
    assert!(c.view().title.ends_with("1.100 s"), "{}", c.view().title);
}

/// A real-time recording holds every pulse once, in about as many batches as the same run in
/// virtual time: a moving axis's batch fills across the kernel's 100 µs slices and goes out
/// every 10 ms of machine time (it went out at every slice: 197,020 batches for one Citizen
/// part against 3,232 in virtual time, 27.9 MB against 10.7).
#[test]
fn a_real_time_recording_batches_the_pulses_as_virtual_time_does() {
    let mut runs = Vec::new();
    for clock in [ClockMode::Virtual, ClockMode::RealTime] {
        let dir = common::temp_dir("lathe-rt-record");
        let rec = dir.join("run.mcap");
        let (mut c, _) =
            LatheConsole::open_on(LatheDesc::citizen(), &dir, (12, 40), Some(&rec), clock).unwrap();
        c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
        // About 0.7 s of moves on X and Z.
        for l in ["G0 X30 Z50", "G1 X20 Z20 F2500", "G0 X34 Z58"] {
            c.handle(PanelEvent::Type(l.into()));
        }
        c.handle(PanelEvent::Start);
        if clock == ClockMode::Virtual {
            c.handle(PanelEvent::Wait);
        } else {
            assert!(until(&mut c, Duration::from_secs(20), |c| c
                .cycle()
                .is_over()));
        }
        let summary = c.finish().expect("finished").expect("a recording");
        // "... N pulses in M batches ..."
        let words: Vec<&str> = summary.split_whitespace().collect();
        let at = words.iter().position(|w| *w == "batches,").expect(&summary);
        let batches: u64 = words[at - 1].parse().unwrap();
        let pulses: u64 = words[at - 4].parse().unwrap();
        runs.push((pulses, batches));
        let _ = std::fs::remove_dir_all(&dir);
    }
    let [(vp, vb), (rp, rb)] = [runs[0], runs[1]];
    assert!(vp > 30_000, "{runs:?}");
    assert_eq!(rp, vp, "every pulse once, in both clocks: {runs:?}");
    assert!(
        rb <= vb * 2 + 8,
        "real-time batches {rb} against {vb} in virtual time"
    );
}
