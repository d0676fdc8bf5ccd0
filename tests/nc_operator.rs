//! Operator commands on the pulse core, on virtual time: single block, feed hold, e-stop,
//! reset, travel limits, translation errors, override, jog and the relay logic.

use novanc::block::{Block, Motion};
use novanc::pulse_core::testkit::{arc, linear, polyline};
use novanc::pulse_core::{Command, EndCause, Machine, RunKind, VecSource};
use novanc::settings::MachineSettings;
use novanc::translator::{Statement, TranslateError};

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const HOUR: u64 = 3_600_000_000_000;
const TICK: u64 = 5_000_000;

fn machine() -> Machine {
    let mut m = Machine::new(MachineSettings::default());
    assert!(m.set_position(MID));
    m.set_recording(None, true);
    m
}

fn square() -> (Vec<Block>, Vec<[i64; 3]>) {
    let pts = vec![
        MID,
        [MID[0] + 10_000, MID[1], MID[2]],
        [MID[0] + 10_000, MID[1] + 5_000, MID[2] - 2_000],
        [MID[0], MID[1] + 5_000, MID[2]],
        MID,
    ];
    (polyline(&pts, 1200.0), pts)
}

#[test]
fn single_block_runs_one_block_per_start() {
    let (blocks, pts) = square();
    let mut src = VecSource::from_blocks(blocks);
    let mut m = machine();
    m.command(Command::SingleBlock(true));
    for (i, p) in pts.iter().enumerate().skip(1) {
        m.command(Command::Start(RunKind::Auto));
        assert_eq!(m.run_flag(), 1);
        m.run_until_idle(&mut src, HOUR);
        assert_eq!(m.run_flag(), 0, "RUN cleared after block {i}");
        assert_eq!(m.blocks_done(), i as u64);
        assert_eq!(m.pos(), *p);
        // nothing more happens without START
        m.advance_to(m.now() + 100 * TICK, &mut src);
        assert_eq!(m.blocks_done(), i as u64);
        assert_eq!(m.pos(), *p);
    }
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m.status().program_end);
    assert_eq!(m.blocks_done(), 4);
}

#[test]
fn mdi_start_sets_run_2() {
    let mut src = VecSource::from_blocks(vec![linear(1, MID, [1000, 0, 0], 500.0)]);
    let mut m = machine();
    m.command(Command::Start(RunKind::Mdi));
    m.tick(&mut src);
    assert_eq!(m.status().run, 2);
    m.run_until_idle(&mut src, HOUR);
    assert_eq!(m.pos()[0], MID[0] + 1000);
}

#[test]
fn feed_hold_mid_block_then_resume_loses_no_pulse() {
    let delta = [80_000, -30_000, 10_000];
    let reference = {
        let mut m = machine();
        let mut src = VecSource::from_blocks(vec![linear(1, MID, delta, 3000.0)]);
        m.command(Command::Start(RunKind::Auto));
        m.run_until_idle(&mut src, HOUR);
        m.take_pulses()
    };
    let mut m = machine();
    let mut src = VecSource::from_blocks(vec![linear(1, MID, delta, 3000.0)]);
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(100 * TICK, &mut src);
    let before = m.pos();
    assert!(before != MID && before[0] < MID[0] + delta[0], "mid-block");
    m.command(Command::Stop);
    m.run_until_idle(&mut src, HOUR);
    let st = m.status();
    assert!(st.hold && !st.moving && st.run == 1);
    let held = m.pos();
    assert!(held[0] < MID[0] + delta[0], "stopped before the end");
    // it stays put while held
    m.advance_to(m.now() + 200 * TICK, &mut src);
    assert_eq!(m.pos(), held);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    let pulses = m.take_pulses();
    assert_eq!(pulses.len(), reference.len());
    assert_eq!(
        m.pos(),
        [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]]
    );
    assert_eq!(m.status().pulses, [80_000, 30_000, 10_000]);
    assert_eq!(m.blocks_done(), 1);
}

#[test]
fn emergency_stop_stops_pulses_at_once_and_needs_reset() {
    let (blocks, _) = square();
    let mut src = VecSource::from_blocks(blocks);
    let mut m = machine();
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(50 * TICK, &mut src);
    assert!(m.status().moving);
    let t_stop = m.now();
    m.command(Command::EStop);
    let p = m.pos();
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert_eq!(m.pos(), p);
    assert!(m.take_pulses().iter().all(|r| r.t_ns < t_stop));
    let st = m.status();
    assert!(st.estop && st.run == 0 && st.alarm.is_some());
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert_eq!(m.pos(), p, "START refused until RESET");
    m.command(Command::Reset);
    let st = m.status();
    assert!(!st.estop && st.alarm.is_none() && st.run == 0);
}

#[test]
fn travel_limit_refuses_the_block_before_any_pulse() {
    let s = MachineSettings::default();
    let (_, hi) = s.travel_pulses(0);
    let mut stmt = Statement {
        line: 7,
        text: "GO, 1200, 10, -5".into(),
        blocks: vec![linear(3, MID, [hi - MID[0] + 1, 0, 0], 1000.0)],
    };
    stmt.blocks[0].stmt = 7;
    let ok = Statement {
        line: 6,
        text: "GD, 1, 0, 0".into(),
        blocks: vec![linear(2, MID, [1000, 0, 0], 1000.0)],
    };
    let mut m = machine();
    let mut src = VecSource::from_statements(vec![Ok(ok), Ok(stmt)]);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    let st = m.status();
    let alarm = st.alarm.unwrap_or_default();
    assert!(alarm.starts_with("line 7: N3 travel limit: X"), "{alarm}");
    assert!(st.job.is_none(), "the run is over; RESET clears the alarm");
    assert_eq!(st.run, 0);
    assert_eq!(st.blocks_done, 1);
    assert_eq!(m.pos(), [MID[0] + 1000, MID[1], MID[2]]);
    assert_eq!(m.take_pulses().len(), 1000, "only the first block moved");
}

#[test]
fn an_arc_bulging_over_a_limit_is_refused() {
    let s = MachineSettings::default();
    let (_, yhi) = s.travel_pulses(1);
    // a half circle from (x, yhi - 1000) around a centre 5000 below: its top is 4000 over
    let start = [MID[0], yhi - 1000, MID[2]];
    let b = arc(1, start, [10_000, 0], [5_000, 0], false, 1000.0);
    let mut m = machine();
    assert!(m.set_position(start));
    let mut src = VecSource::from_blocks(vec![b]);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m
        .status()
        .alarm
        .unwrap_or_default()
        .contains("travel limit: Y"));
    assert_eq!(m.pos(), start);
    assert!(m.take_pulses().is_empty());
}

#[test]
fn translation_error_runs_the_blocks_before_it_then_alarms() {
    let a = Statement {
        line: 1,
        text: "GD, 1, 0, 0".into(),
        blocks: vec![linear(1, MID, [1000, 0, 0], 1000.0)],
    };
    let e = TranslateError {
        line: 2,
        col: 5,
        message: "unknown keyword".into(),
    };
    let mut src = VecSource::from_statements(vec![Ok(a), Err(e)]);
    let mut m = machine();
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    let st = m.status();
    assert!(st.alarm.is_none(), "a program error is not a machine fault");
    let end = st.last_end.expect("the run ended");
    assert_eq!(
        end.cause,
        EndCause::Error {
            error: TranslateError {
                line: 2,
                col: 5,
                message: "unknown keyword".into()
            },
            nothing_moved: false
        }
    );
    assert_eq!(st.blocks_done, 1);
    assert_eq!(m.pos()[0], MID[0] + 1000);
}

#[test]
fn override_takes_effect_at_the_next_tick() {
    let mut m = machine();
    let mut src = VecSource::from_blocks(vec![linear(1, MID, [500_000 - 1, 0, 0], 1000.0)]);
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(200 * TICK, &mut src);
    assert!((m.status().speed_mm_min - 1000.0).abs() < 1.0);
    m.command(Command::Override(150));
    m.advance_to(m.now() + TICK - 1, &mut src);
    // the tick boundary has not been crossed yet... one more tick applies it
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert!((m.status().speed_mm_min - 1500.0).abs() < 1.0);
    m.command(Command::Override(0));
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert!(!m.status().moving);
    let p = m.pos();
    assert!(m.is_stalled());
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert_eq!(m.pos(), p);
    m.command(Command::Override(100));
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert!(m.pos()[0] > p[0]);
}

#[test]
fn jog_continuous_step_and_handle() {
    let s = MachineSettings::default();
    let mut src = VecSource::default();
    let mut m = machine();
    m.command(Command::Jog { axis: 1, dir: -1 });
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert!(m.pos()[1] < MID[1]);
    // a second jog while one moves is refused; the first goes on
    m.command(Command::Jog { axis: 0, dir: 1 });
    assert_eq!(m.status().notice.as_deref(), Some("jog in progress"));
    let y = m.pos()[1];
    m.advance_to(m.now() + 10 * TICK, &mut src);
    assert!(m.pos()[1] < y);
    assert_eq!(m.pos()[0], MID[0]);
    m.command(Command::JogRelease);
    m.run_until_idle(&mut src, HOUR);
    let p = m.pos();
    assert!(m.is_idle());
    m.advance_to(m.now() + 10 * TICK, &mut src);
    assert_eq!(m.pos(), p);
    // STEP: one increment; HANDLE: detents × 100
    m.command(Command::Increment {
        axis: 0,
        pulses: s.to_pulses(s.step_mm),
    });
    m.command(Command::Increment {
        axis: 0,
        pulses: -300,
    });
    m.run_until_idle(&mut src, HOUR);
    assert_eq!(m.pos()[0], p[0] + 100 - 300);
    // beyond the limit: refused, nothing moves
    m.command(Command::Increment {
        axis: 2,
        pulses: 400_000,
    });
    m.run_until_idle(&mut src, HOUR);
    assert_eq!(m.pos()[2], p[2]);
    assert!(m
        .status()
        .notice
        .unwrap_or_default()
        .contains("travel limit"));
    // continuous jog stops at the travel limit
    m.command(Command::Jog { axis: 2, dir: 1 });
    m.run_until_idle(&mut src, HOUR);
    assert_eq!(m.pos()[2], s.travel_pulses(2).1);
}

#[test]
fn tool_change_and_spindle_take_machine_time() {
    let s = MachineSettings::default();
    let mut tc = Block::aux(1, 1, MID);
    tc.t = Some(3);
    tc.m = Some(6);
    let mut sp = Block::aux(2, 1, MID);
    sp.s = Some(1200);
    sp.m = Some(3);
    let mv = linear(3, MID, [1000, 0, 0], 600.0);
    let mut stop = Block::aux(4, 2, [MID[0] + 1000, MID[1], MID[2]]);
    stop.m = Some(5);
    let mut dw = Block::aux(5, 2, [MID[0] + 1000, MID[1], MID[2]]);
    dw.motion = Motion::Dwell;
    dw.dwell_ns = 500_000_000;
    let mut src = VecSource::from_blocks(vec![tc, sp, mv, stop, dw]);
    let mut m = machine();
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(s.tool_change_ns - TICK, &mut src);
    assert_eq!(m.status().tool, None, "still changing");
    m.advance_to(s.tool_change_ns + 2 * TICK, &mut src);
    assert_eq!(m.status().tool, Some(3));
    m.advance_to(s.tool_change_ns + s.spindle_ns + 3 * TICK, &mut src);
    assert_eq!(m.status().spindle, 1200);
    m.run_until_idle(&mut src, HOUR);
    let st = m.status();
    assert_eq!(st.spindle, 0);
    assert_eq!(st.blocks_done, 5);
    assert!(st.program_end);
    let t_move = 1000.0 / (600.0 / 60.0 / 0.001) * 1e9;
    let min = s.tool_change_ns + 2 * s.spindle_ns + 500_000_000 + t_move as u64;
    assert!(
        m.now() >= min && m.now() < min + 1_000_000_000,
        "{} vs {min}",
        m.now()
    );
}

#[test]
fn reset_abandons_the_run() {
    let (blocks, _) = square();
    let mut src = VecSource::from_blocks(blocks);
    let mut m = machine();
    m.command(Command::Start(RunKind::Auto));
    m.advance_to(50 * TICK, &mut src);
    m.command(Command::Reset);
    let p = m.pos();
    assert!(m.is_idle());
    m.advance_to(m.now() + 100 * TICK, &mut src);
    assert_eq!(m.pos(), p);
    assert_eq!(m.status().run, 0);
}

/// The jog deadman (docs/pulse-core.md): a held-key jog kept alive by `JogAlive` decelerates on
/// its own when the keep-alives stop, as a frozen front end's would; a jog without one goes on.
#[test]
fn a_jog_whose_keepalives_stop_decelerates_on_its_own() {
    let mut src = VecSource::default();
    let mut m = machine();
    m.command(Command::Jog { axis: 1, dir: -1 });
    m.command(Command::JogAlive(250));
    // Kept alive every 30 ms for 0.6 s: it jogs all along.
    for _ in 0..20 {
        m.advance_to(m.now() + 30_000_000, &mut src);
        m.command(Command::JogAlive(250));
    }
    assert!(m.status().moving);
    let kept = m.pos()[1];
    // The front end stops: no more keep-alives. The jog stops within the deadline and its
    // deceleration, without any JogRelease.
    m.advance_to(m.now() + 2_000_000_000, &mut src);
    assert!(!m.status().moving, "the jog went on without keep-alives");
    assert!(m.is_idle());
    let coast = kept - m.pos()[1];
    // 250 ms at the jog feed (at most the rapid rate of the defaults) plus braking: well under
    // the 2 s it would otherwise have run.
    let s = MachineSettings::default();
    let feed_pulses_per_ms = s.to_pulses(s.jog_mm_min) as f64 / 60_000.0;
    assert!(
        (coast as f64) < feed_pulses_per_ms * 1000.0,
        "coasted {coast} pulses"
    );
    // A jog never kept alive (a script's, the window's) has no deadline.
    m.command(Command::Jog { axis: 1, dir: 1 });
    m.advance_to(m.now() + 1_000_000_000, &mut src);
    assert!(m.status().moving);
    m.command(Command::JogRelease);
    m.run_until_idle(&mut src, HOUR);
    assert!(m.is_idle());
}
