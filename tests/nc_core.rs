//! The pulse core thread (`PulseCore`) on virtual time: B1 filled concurrently by the translator
//! thread, commands, `wait_idle`, determinism through the thread, recording every pulse.

use novanc::pulse_core::testkit::{polyline, Rng};
use novanc::pulse_core::{
    ClockMode, Command, EndCause, Machine, MakeRun, PulseCore, RunKind, VecSource,
};
use novanc::record::{Event, EventSink};
use novanc::settings::MachineSettings;
use novanc::translator::{Statement, TranslateError};
use std::time::Duration;

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const WAIT: Duration = Duration::from_secs(60);

fn program(n: usize, seed: u64) -> (Vec<Statement>, [i64; 3]) {
    let mut rng = Rng::new(seed);
    let mut p = MID;
    let mut pts = vec![p];
    for _ in 0..n {
        p = [
            p[0] + rng.range(-3_000, 3_000),
            p[1] + rng.range(-3_000, 3_000),
            p[2] + rng.range(-1_000, 1_000),
        ];
        pts.push(p);
    }
    // three blocks per statement
    let blocks = polyline(&pts, 2400.0);
    let stmts = blocks
        .chunks(3)
        .enumerate()
        .map(|(i, c)| Statement {
            line: i as u32 + 1,
            text: format!("statement {}", i + 1),
            blocks: c.to_vec(),
        })
        .collect();
    (stmts, p)
}

fn small_b1() -> MachineSettings {
    MachineSettings {
        b1_capacity: 2,
        ..MachineSettings::default()
    }
}

/// A program source of these statements.
fn make(stmts: Vec<Statement>) -> Option<MakeRun> {
    make_items(stmts.into_iter().map(Ok).collect())
}

/// A program source of these statements and errors.
fn make_items(items: Vec<Result<Statement, TranslateError>>) -> Option<MakeRun> {
    Some(Box::new(move |_| Box::new(items.into_iter())))
}

#[test]
fn runs_a_program_through_a_small_b1_to_its_end() {
    let (stmts, end) = program(300, 1);
    let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, None);
    core.set_position(MID);
    core.start(RunKind::Auto, make(stmts));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.run, 0);
    assert!(st.program_end);
    assert_eq!(st.blocks_done, 300);
    assert_eq!(st.pos, end);
    assert!(st.alarm.is_none());
    let end = st.last_end.expect("the run's end");
    assert_eq!((end.cause, end.blocks), (EndCause::ProgramEnd, 300));
    assert!(
        st.job.is_none() && st.executing.is_none(),
        "nothing loaded after the end"
    );
}

fn recorded_pulses(rx: &std::sync::mpsc::Receiver<Event>) -> Vec<(u8, i8, u64)> {
    let mut v = vec![];
    while let Ok(ev) = rx.try_recv() {
        if let Event::Pulses { axis, dir, t_ns } = ev {
            v.extend(t_ns.into_iter().map(|t| (axis, dir, t)));
        }
    }
    v.sort_by_key(|p| (p.2, p.0));
    v
}

#[test]
fn the_thread_gives_the_same_pulse_times_as_the_machine_and_records_each_once() {
    let (stmts, _) = program(120, 2);
    // direct
    let mut m = Machine::new(small_b1());
    m.set_position(MID);
    m.set_recording(None, true);
    let mut src = VecSource::from_statements(stmts.clone().into_iter().map(Ok));
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, u64::MAX / 4);
    let mut direct: Vec<(u8, i8, u64)> = m
        .take_pulses()
        .into_iter()
        .map(|p| (p.axis, p.dir, p.t_ns))
        .collect();
    direct.sort_by_key(|p| (p.2, p.0));
    // through the thread, recorded, twice
    for _ in 0..2 {
        let (tx, rx) = std::sync::mpsc::sync_channel(1 << 20);
        let sink = EventSink::new(tx);
        let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, Some(sink.clone()));
        core.set_position(MID);
        core.start(RunKind::Auto, make(stmts.clone()));
        let st = core.wait_idle(WAIT).expect("idle");
        drop(core);
        assert!(!sink.is_incomplete());
        let got = recorded_pulses(&rx);
        assert_eq!(got.len() as u64, st.pulses.iter().sum::<u64>());
        assert_eq!(got, direct);
    }
}

#[test]
fn hold_resume_reset_and_estop_through_the_thread() {
    let (stmts, end) = program(60, 3);
    let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, None);
    core.set_position(MID);
    core.command(Command::SingleBlock(true));
    core.start(RunKind::Auto, make(stmts.clone()));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!((st.blocks_done, st.run), (1, 0));
    core.command(Command::SingleBlock(false));
    // the single-blocked run resumes: the source offered now is not used
    core.start(RunKind::Auto, make(vec![]));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.pos, end);
    assert_eq!(st.blocks_done, 60);
    // RESET mid-program abandons the run and empties B1
    core.command(Command::SingleBlock(true));
    let (more, _) = program(10, 9);
    let more: Vec<Statement> = more
        .into_iter()
        .map(|mut s| {
            for b in &mut s.blocks {
                for a in 0..3 {
                    b.end[a] += end[a] - MID[a];
                }
            }
            s
        })
        .collect();
    core.start(RunKind::Auto, make(more));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.blocks_done, 1);
    let st = core.command(Command::Reset);
    assert!(st.job.is_none());
    assert_eq!(core.b1_len(), 0);
    let at = st.pos;
    core.command(Command::SingleBlock(false));
    core.start(RunKind::Auto, None);
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.pos, at, "nothing of the abandoned run ran after RESET");
    // e-stop: refused START until RESET
    core.command(Command::EStop);
    let st = core.wait_idle(WAIT).expect("idle");
    assert!(st.estop && st.alarm.is_some());
    core.command(Command::Reset);
    let st = core.wait_idle(WAIT).expect("idle");
    assert!(!st.estop && st.alarm.is_none());
}

#[test]
fn a_translation_error_stops_after_the_blocks_before_it() {
    let (stmts, _) = program(9, 4);
    let first: Vec<Statement> = stmts[..2].to_vec();
    let end = first[1].blocks[2].end;
    let mut items: Vec<Result<Statement, TranslateError>> = first.into_iter().map(Ok).collect();
    items.push(Err(TranslateError {
        line: 3,
        col: 7,
        message: "no such point P9".into(),
    }));
    items.extend(stmts[2..].iter().cloned().map(Ok));
    let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, None);
    core.set_position(MID);
    core.start(RunKind::Auto, make_items(items));
    let st = core.wait_idle(WAIT).expect("idle");
    assert!(st.alarm.is_none());
    let e = st.last_end.expect("the run ended");
    match e.cause {
        EndCause::Error {
            error,
            nothing_moved,
        } => {
            assert_eq!(error.to_string(), "3:7: no such point P9");
            assert!(!nothing_moved);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(st.blocks_done, 6);
    assert_eq!(st.pos, end);
}

#[test]
fn real_time_follows_the_wall_clock() {
    let s = MachineSettings::default();
    let core = PulseCore::spawn(s, ClockMode::RealTime, None);
    core.set_position(MID);
    // 6 mm at 1200 mm/min: 0.3 s plus ramps
    let stmt = Statement {
        line: 1,
        text: "GD, 6, 0, 0".into(),
        blocks: vec![novanc::pulse_core::testkit::linear(
            1,
            MID,
            [6_000, 0, 0],
            1200.0,
        )],
    };
    let t0 = std::time::Instant::now();
    core.start(RunKind::Auto, make(vec![stmt]));
    let st = core.wait_idle(WAIT).expect("idle");
    let wall = t0.elapsed().as_secs_f64();
    assert_eq!(st.pos[0], MID[0] + 6_000);
    assert!(wall > 0.28, "not faster than the machine: {wall}");
    assert!(wall < 2.0, "{wall}");
    let rt = core.realtime_stats();
    assert!(!rt.lateness_ns.is_empty());
}

#[test]
fn a_recorder_that_falls_behind_never_holds_up_the_machine() {
    // real time: a queue of 1 event that nobody reads; the move still takes its real time
    let (tx, _rx) = std::sync::mpsc::sync_channel(1);
    let sink = EventSink::new(tx);
    let core = PulseCore::spawn(
        MachineSettings::default(),
        ClockMode::RealTime,
        Some(sink.clone()),
    );
    core.set_position(MID);
    let stmt = Statement {
        line: 1,
        text: "GD, 6, 0, 0".into(),
        blocks: vec![novanc::pulse_core::testkit::linear(
            1,
            MID,
            [6_000, 0, 0],
            1200.0,
        )],
    };
    let t0 = std::time::Instant::now();
    core.start(RunKind::Auto, make(vec![stmt]));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.pos[0], MID[0] + 6_000);
    assert!(t0.elapsed().as_secs_f64() < 2.0);
    assert!(
        sink.is_incomplete() && sink.dropped() > 0,
        "the operator is told"
    );
    drop(core);

    // virtual time: a stuck recorder is waited for once (2 s), then the run goes on lossy
    let (tx, _rx) = std::sync::mpsc::sync_channel(1);
    let sink = EventSink::new(tx);
    let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, Some(sink.clone()));
    core.set_position(MID);
    let (stmts, end) = program(30, 5);
    let t0 = std::time::Instant::now();
    core.start(RunKind::Auto, make(stmts));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(st.pos, end);
    assert!(t0.elapsed().as_secs_f64() < 10.0);
    assert!(sink.is_incomplete());
}

#[test]
fn real_time_emergency_stop_stops_the_pulses_within_one_period() {
    let (tx, rx) = std::sync::mpsc::sync_channel(1 << 20);
    let sink = EventSink::new(tx);
    let spawned = std::time::Instant::now();
    let core = PulseCore::spawn(
        MachineSettings::default(),
        ClockMode::RealTime,
        Some(sink.clone()),
    );
    core.set_position(MID);
    // 100 mm at 6000 mm/min: 100,000 pulses/s, a pulse every 10 µs once at speed
    let stmt = Statement {
        line: 1,
        text: "GD, 100, 0, 0".into(),
        blocks: vec![novanc::pulse_core::testkit::linear(
            1,
            MID,
            [100_000, 0, 0],
            6000.0,
        )],
    };
    core.start(RunKind::Auto, make(vec![stmt]));
    std::thread::sleep(Duration::from_millis(400));
    core.command(Command::EStop);
    let st = core.wait_idle(WAIT).expect("idle");
    let returned_ns = spawned.elapsed().as_nanos() as u64;
    assert!(st.estop);
    std::thread::sleep(Duration::from_millis(50));
    let st2 = core.status();
    drop(core);
    assert_eq!(st2.pos, st.pos, "nothing moves after the e-stop");
    let evs: Vec<Event> = rx.try_iter().collect();
    // the e-stop's own position record is the last one: its time is the e-stop's
    let (mw, stop_pos) = evs
        .iter()
        .filter_map(|e| match e {
            Event::Position { t_ns, pulses, .. } => Some((*t_ns, *pulses)),
            _ => None,
        })
        .max_by_key(|p| p.0)
        .expect("positions");
    assert_eq!(stop_pos, st.pos);
    let mut pulses: Vec<u64> = evs
        .iter()
        .filter_map(|e| match e {
            Event::Pulses { t_ns, .. } => Some(t_ns.clone()),
            _ => None,
        })
        .flatten()
        .collect();
    pulses.sort_unstable();
    assert!(pulses.iter().all(|&t| t < mw), "no pulse after the e-stop");
    let last = pulses.last().copied().unwrap_or(0);
    assert!(
        mw - last <= 11_000,
        "the last pulse is within one period: {} ns",
        mw - last
    );
    assert_eq!(
        pulses.len() as i64,
        st.pos[0] - MID[0],
        "recorded = counted"
    );
    assert_eq!(st.pulses[0], pulses.len() as u64);
    assert!(st.pos[0] < MID[0] + 100_000, "stopped mid-move");
    // it took effect when it arrived (machine time = wall clock, which started after
    // `spawned`), not at the end of the slices already queued ahead of the wall clock (5 to
    // 10 ms later)
    assert!(
        mw <= returned_ns,
        "{mw} is ahead of the wall clock ({returned_ns})"
    );
    assert!(!sink.is_incomplete());
}

#[test]
fn m00_and_m01_stop_the_run_after_their_block_and_start_continues() {
    let (mut stmts, end) = program(9, 3);
    stmts[0].blocks[2].m = Some(0);
    stmts[1].blocks[1].m = Some(1);
    let core = PulseCore::spawn(small_b1(), ClockMode::Virtual, None);
    core.set_position(MID);
    core.start(RunKind::Auto, make(stmts));
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(
        (st.run, st.blocks_done),
        (0, 3),
        "M00 on block 3 stops after it"
    );
    assert!(st.job.is_some() && !st.program_end && !st.hold);
    let st = core.start(RunKind::Auto, None);
    assert_eq!(st.run, 1, "START continues");
    let st = core.wait_idle(WAIT).expect("idle");
    assert_eq!(
        (st.run, st.blocks_done),
        (0, 5),
        "M01 on block 5 stops after it"
    );
    core.start(RunKind::Auto, None);
    let st = core.wait_idle(WAIT).expect("idle");
    assert!(st.program_end && st.job.is_none());
    assert_eq!((st.blocks_done, st.pos.xyz()), (9, end));
}
