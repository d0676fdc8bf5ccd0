//! Unit tests of the simulator (docs/lathe-sim.md): motion ends, pulse totals, alarms before
//! any pulse, G96, waiting codes and deadlock, E-STOP, hold, M00, thread re-synchronisation.

use super::testkit::*;
use super::*;
use crate::lathe::ops::Feed;

const MINUTE: u64 = 60_000_000_000;

/// A one-channel lathe running `ops` (after an M10 from the bar feeder if `work`), from the
/// tool position (20, 5) mm.
fn one(ops: Vec<Op>, work: bool) -> Lathe {
    let mut all = Vec::new();
    if work {
        all.push(Op::ChuckClose);
    }
    all.extend(ops);
    let mut l = match Lathe::new(citizen_like(1), vec![program("t", all)], 1) {
        Ok(l) => l,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(l.set_position(0, pt(20.0, 5.0)), Ok(()));
    l
}

fn st(l: &Lathe, ch: usize) -> ChannelStatus {
    l.channel(ch).expect("a channel of the test machine")
}

#[test]
fn every_block_ends_on_its_point_and_pulses_equal_net_motion() {
    let pts = [
        (12.0, 0.5),
        (3.25, -7.125),
        (3.25, -30.0),
        (17.003, -29.999),
        (0.0, 10.0),
        (20.0, 5.0),
    ];
    let mut ops = vec![rpm(1500.0)];
    for (k, (x, z)) in pts.iter().enumerate() {
        ops.push(if k % 2 == 0 {
            rapid(*x, *z)
        } else {
            Op::Line {
                end: pt(*x, *z),
                feed: Feed::PerMin(900.0),
            }
        });
    }
    let mut l = one(ops.clone(), true);
    l.start();
    let mut last_step = st(&l, 0).step;
    let mut ends = 0;
    for _ in 0..10_000_000 {
        l.tick();
        let s = st(&l, 0);
        if s.step != last_step {
            // ops[k] is step k+1 (after the M10).
            if let Some(end) = last_step.checked_sub(1).and_then(|k| ops[k].end()) {
                assert_eq!(s.pos, end, "step {last_step} ended off its point");
                ends += 1;
            }
            last_step = s.step;
        }
        if s.state == ChState::Done {
            break;
        }
    }
    assert_eq!(ends, pts.len());
    let mut net = [0u64; 2];
    let mut at = pt(20.0, 5.0);
    for (x, z) in pts {
        let p = pt(x, z);
        net[0] += (p[0] - at[0]).unsigned_abs();
        net[1] += (p[1] - at[1]).unsigned_abs();
        at = p;
    }
    assert_eq!(l.stats().channels[0].pulses, net);
}

#[test]
fn an_arc_ends_exactly_and_its_pulses_follow_the_circle() {
    // A half circle of radius 5 mm about (10, -10), ccw from (10, -5) over +X to (10, -15).
    let ops = vec![
        rpm(1000.0),
        rapid(10.0, -5.0),
        Op::Arc {
            end: pt(10.0, -15.0),
            centre: pt(10.0, -10.0),
            ccw: true,
            feed: Feed::PerMin(600.0),
        },
    ];
    let mut l = one(ops, true);
    l.start();
    let mut top = i64::MIN;
    let mut evs = Vec::new();
    while st(&l, 0).state != ChState::Done {
        l.tick();
        if st(&l, 0).step == 3 {
            top = top.max(st(&l, 0).pos[0]);
        }
        evs.extend(l.drain_events());
        assert!(l.machine_time_ns() < MINUTE);
    }
    assert_eq!(st(&l, 0).pos, pt(10.0, -15.0));
    // ccw from +Z towards +X: the arc bulges to X 15, not X 5.
    assert_eq!(top, pt(15.0, 0.0)[0]);
    // X goes out 5 and back 5 mm on the arc after the rapid's 10; Z 10 mm on the arc + 10.
    assert_eq!(l.stats().channels[0].pulses, [20_000, 20_000]);
}

#[test]
fn travel_and_arc_alarms_move_nothing() {
    let mut l = one(vec![rpm(1000.0), rapid(70.0, 0.0)], true);
    l.start();
    match l.run_until_idle(MINUTE) {
        Outcome::Alarm { ch: 0, msg } => assert!(msg.contains("travel"), "{msg}"),
        o => panic!("{o:?}"),
    }
    assert_eq!(st(&l, 0).pos, pt(20.0, 5.0));
    assert_eq!(l.stats().channels[0].pulses, [0, 0]);

    // An arc whose end is 0.01 mm off the circle.
    let bad = Op::Arc {
        end: pt(10.01, -15.0),
        centre: pt(10.0, -10.0),
        ccw: true,
        feed: Feed::PerMin(600.0),
    };
    let mut l = one(vec![rpm(1000.0), bad], true);
    l.start();
    match l.run_until_idle(MINUTE) {
        Outcome::Alarm { msg, .. } => assert!(msg.contains("radius"), "{msg}"),
        o => panic!("{o:?}"),
    }
    assert_eq!(l.stats().channels[0].pulses, [0, 0]);

    // An arc whose bulge leaves the travel though both ends are inside (X up to 62 mm).
    let out = Op::Arc {
        end: pt(50.0, -24.0),
        centre: pt(50.0, -12.0),
        ccw: true,
        feed: Feed::PerMin(600.0),
    };
    let mut l = one(vec![rpm(1000.0), rapid(50.0, 0.0), out], true);
    l.start();
    match l.run_until_idle(MINUTE) {
        Outcome::Alarm { msg, .. } => assert!(msg.contains("travel"), "{msg}"),
        o => panic!("{o:?}"),
    }
    assert_eq!(st(&l, 0).pos, pt(50.0, 0.0));
}

#[test]
fn a_cut_on_an_empty_spindle_is_an_alarm_never_a_cut() {
    let mut l = one(vec![rpm(1000.0), line_rev(10.0, 5.0, 0.1)], false);
    l.start();
    match l.run_until_idle(MINUTE) {
        Outcome::Alarm { ch: 0, msg } => assert!(msg.contains("empty spindle"), "{msg}"),
        o => panic!("{o:?}"),
    }
    assert_eq!(l.stats().empty_cut_alarms, 1);
    assert_eq!(l.stats().channels[0].pulses, [0, 0]);
    let evs = l.drain_events();
    assert!(!evs.iter().any(|e| matches!(e, Event::CutStart { .. })));
    // RESET and START retry the block: an alarm again, still nothing cut.
    assert_eq!(l.reset(0), Ok(()));
    l.start();
    assert!(matches!(l.run_until_idle(MINUTE), Outcome::Alarm { .. }));
    assert_eq!(l.stats().empty_cut_alarms, 2);
    assert_eq!(st(&l, 0).pos, pt(20.0, 5.0));
}

#[test]
fn css_holds_the_surface_speed_then_the_limit() {
    let (v, limit) = (150.0, 4000.0);
    let mut l = one(
        vec![css(v, limit), rapid(12.0, 0.0), line_rev(0.0, 0.0, 0.1)],
        true,
    );
    l.set_recording(true, 1_000_000);
    l.start();
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
    let (mut in_css, mut at_limit) = (0, 0);
    let mut facing = false;
    for e in l.drain_events() {
        match e {
            Event::Block { line, .. } => facing = line == 4,
            Event::Sample { pos, rpm, .. } if facing && pos[0] > 0 && pos[0] < mm(12.0) => {
                let r = pos[0] as f64 / 1000.0;
                let want = 1000.0 * v / (std::f64::consts::TAU * r);
                if want < limit * 0.99 {
                    let surface = std::f64::consts::TAU * r * rpm / 1000.0;
                    assert!((surface - v).abs() <= 0.01 * v, "r {r}: {surface} m/min");
                    in_css += 1;
                } else if want > limit * 1.01 {
                    assert!((rpm - limit).abs() <= 0.01 * limit, "r {r}: {rpm} rpm");
                    at_limit += 1;
                }
            }
            _ => {}
        }
    }
    assert!(in_css > 50 && at_limit > 50, "{in_css} {at_limit}");
}

#[test]
fn waiting_codes_meet_and_a_deadlock_is_reported() {
    let two = |a: Vec<Op>, b: Vec<Op>| {
        let mut l = Lathe::new(citizen_like(2), vec![program("a", a), program("b", b)], 1)
            .expect("a valid two-channel lathe");
        l.start();
        l
    };
    // Channel 2 dwells 50 ms before M100: channel 1 leaves M100 only then.
    let mut l = two(
        vec![Op::Wait { m: 100, with: 3 }, Op::Dwell { ns: 1 }],
        vec![Op::Dwell { ns: 50_000_000 }, Op::Wait { m: 100, with: 3 }],
    );
    let mut seen_wait = false;
    while st(&l, 0).step == 0 {
        l.tick();
        let s = st(&l, 0);
        if s.step == 0 {
            assert_eq!(
                (s.state, s.waits_on),
                (ChState::Wait, Some(WaitOn::Channel(1)))
            );
            seen_wait = true;
        }
    }
    assert!(seen_wait);
    assert!(l.machine_time_ns() >= 50_000_000);
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });

    // M100 against M101: neither can ever go on.
    let mut l = two(
        vec![Op::Wait { m: 100, with: 3 }],
        vec![Op::Wait { m: 101, with: 3 }],
    );
    assert_eq!(
        l.run_until_idle(MINUTE),
        Outcome::Deadlock {
            waits: vec![(0, WaitOn::Channel(1)), (1, WaitOn::Channel(0))]
        }
    );
    assert!(l.machine_time_ns() < 1_000_000);

    // A wait with a channel that has finished: a deadlock too.
    let mut l = two(
        vec![Op::Dwell { ns: 1 }],
        vec![Op::Wait { m: 100, with: 3 }],
    );
    assert_eq!(
        l.run_until_idle(MINUTE),
        Outcome::Deadlock {
            waits: vec![(1, WaitOn::Channel(0))]
        }
    );
}

#[test]
fn bad_machines_and_programs_are_refused() {
    let e = Lathe::new(citizen_like(3), vec![system1()], 5).err();
    assert!(e.is_some_and(|e| e.contains("one program per channel")));
    let p = program("w", vec![Op::Wait { m: 100, with: 2 }]);
    let e = Lathe::new(citizen_like(2), vec![p, program("b", vec![])], 5).err();
    assert!(e.is_some_and(|e| e.contains("own channel")));
    let p = program(
        "w",
        vec![Op::Wait {
            m: 100,
            with: 0b101,
        }],
    );
    let e = Lathe::new(citizen_like(2), vec![p, program("b", vec![])], 5).err();
    assert!(e.is_some_and(|e| e.contains("has not")));
    let mut l = sample_lathe(1).expect("the sample lathe");
    assert!(l.fault(7, "x").is_err());
    assert!(l.reset(3).is_err());
    assert!(l.channel(3).is_none());
}

#[test]
fn estop_stops_everything_until_reset() {
    let mut l = sample_lathe(5).expect("the sample lathe");
    l.start();
    for _ in 0..40_000 {
        l.tick();
    }
    l.estop();
    let before: Vec<_> = (0..3).map(|c| st(&l, c).pos).collect();
    for _ in 0..1000 {
        l.tick();
    }
    for (c, pos) in before.iter().enumerate() {
        let s = st(&l, c);
        assert_eq!(s.state, ChState::Estop);
        assert_eq!(s.rpm, 0.0);
        assert_eq!(s.pos, *pos);
    }
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Estop);
    l.start();
    assert_eq!(
        l.run_until_idle(MINUTE),
        Outcome::Estop,
        "START alone does not clear"
    );
    for c in 0..3 {
        assert_eq!(l.reset(c), Ok(()));
    }
    l.start();
    assert_eq!(
        l.run_until_idle(10 * MINUTE),
        Outcome::Finished { parts: 5 }
    );
    for w in 1..=5 {
        assert_eq!(l.machined(w), vec![1, 1, 1], "work {w}");
    }
}

#[test]
fn feed_hold_slows_every_channel_to_a_stop_and_start_resumes() {
    let mut l = sample_lathe(3).expect("the sample lathe");
    l.start();
    for _ in 0..25_000 {
        l.tick();
    }
    l.hold();
    // Slowing down takes at most v/a: 400 mm/s / 3000 mm/s² < 0.2 s; a thread pass < 1 s.
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Stopped);
    let before: Vec<_> = (0..3).map(|c| st(&l, c).pos).collect();
    for _ in 0..5000 {
        l.tick();
    }
    for (c, pos) in before.iter().enumerate() {
        assert_eq!(st(&l, c).pos, *pos);
        assert!(matches!(st(&l, c).state, ChState::Hold | ChState::Done));
    }
    l.start();
    assert_eq!(
        l.run_until_idle(10 * MINUTE),
        Outcome::Finished { parts: 3 }
    );
}

#[test]
fn m00_stops_the_channel_until_start() {
    let mut l = one(
        vec![
            rapid(10.0, 0.0),
            Op::Stop { optional: false },
            rapid(5.0, 0.0),
        ],
        false,
    );
    l.start();
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Stopped);
    let s = st(&l, 0);
    assert_eq!((s.state, s.pos), (ChState::Stop, pt(10.0, 0.0)));
    l.start();
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
    assert_eq!(st(&l, 0).pos, pt(5.0, 0.0));
    // M01 is skipped with OPTIONAL STOP off (the default).
    let mut l = one(vec![Op::Stop { optional: true }, rapid(5.0, 0.0)], false);
    l.start();
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
}

#[test]
fn a_thread_pass_resumed_after_a_fault_stays_on_its_helix() {
    let lead = 2.0;
    let mut l = one(
        vec![rpm(600.0), rapid(8.0, 2.0), thread(8.0, -30.0, lead)],
        true,
    );
    l.start();
    // Run until the pass is under way, 10 mm along.
    while st(&l, 0).pos[1] > mm(-8.0) {
        l.tick();
        assert!(l.machine_time_ns() < MINUTE);
    }
    assert_eq!(l.fault(0, "tool breakage"), Ok(()));
    let z_stop = st(&l, 0).pos[1];
    for _ in 0..10_000 {
        l.tick();
    }
    assert_eq!(st(&l, 0).pos[1], z_stop, "a faulted channel does not move");
    assert_eq!(l.reset(0), Ok(()));
    l.start();
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
    assert_eq!(st(&l, 0).pos, pt(8.0, -30.0));
    let passes: Vec<_> = l
        .drain_events()
        .into_iter()
        .filter_map(|e| match e {
            Event::ThreadPass {
                index,
                encoder,
                resumed,
                ..
            } => Some((index, encoder, resumed)),
            _ => None,
        })
        .collect();
    assert_eq!(passes.len(), 2, "{passes:?}");
    let n = 1000u64;
    for (index, _, _) in &passes {
        assert_eq!(index % n, 0, "anchored on an index");
    }
    // The pass starts within a tick's counts of its index (600 rpm: 1 count per tick).
    assert!(passes[0].1 - passes[0].0 <= 2);
    // Resumed: the counts since the index match the Z reached, to within a count's Z.
    let (index, enc, resumed) = passes[1];
    assert!(resumed);
    let z_done = (mm(2.0) - z_stop) as f64;
    let z_by_encoder = (enc - index) as f64 * lead * 1000.0 / n as f64;
    assert!(
        (z_by_encoder - z_done).abs() <= 2.0 * lead + 1.0,
        "{z_by_encoder} {z_done}"
    );
}

#[test]
fn the_target_can_change_until_it_would_strand_a_work() {
    let mut l = sample_lathe(5).expect("the sample lathe");
    l.start();
    // Until channel 1 has taken its third work.
    while l.stats().supplied < 3 {
        l.tick();
        assert!(l.machine_time_ns() < MINUTE);
    }
    let e = l.set_target(2).err();
    assert!(e.is_some_and(|e| e.contains("already supplied 3")));
    assert_eq!(l.target(), 5);
    assert_eq!(l.set_target(3), Ok(()));
    assert_eq!(
        l.run_until_idle(10 * MINUTE),
        Outcome::Finished { parts: 3 }
    );
    assert_eq!(l.stats().supplied, 3);
    assert!(l.set_target(4).is_err(), "the channels have finished");
    assert_eq!(
        l.summary(),
        "CH1 DONE N10 3/3 | CH2 DONE N11 3/3 | CH3 DONE N18 3/3"
    );
}

#[test]
fn a_waiting_code_names_every_channel_not_yet_arrived() {
    let w = || Op::Wait {
        m: 150,
        with: 0b111,
    };
    let progs = vec![
        program("a", vec![w()]),
        program("b", vec![Op::Dwell { ns: 20_000_000 }, w()]),
        program("c", vec![Op::Dwell { ns: 40_000_000 }, w()]),
    ];
    let mut l = Lathe::new(citizen_like(3), progs, 1).expect("a valid lathe");
    l.start();
    l.tick();
    let s = st(&l, 0);
    assert_eq!((s.state, s.waits_for), (ChState::Wait, vec![1, 2]));
    while st(&l, 1).step == 0 {
        l.tick();
    }
    l.tick();
    assert_eq!(st(&l, 0).waits_for, vec![2]);
    assert_eq!(st(&l, 1).waits_for, vec![2]);
    assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
    assert!(l.machine_time_ns() >= 40_000_000);
}

#[test]
fn mdi_loads_and_starts_one_channel() {
    let mut l = sample_lathe(5).expect("the sample lathe");
    let mdi = program("mdi", vec![rapid(10.0, 2.0)]);
    assert_eq!(l.load(1, mdi), Ok(()));
    assert_eq!(l.start_channel(1), Ok(()));
    assert_eq!(
        l.run_until_idle(MINUTE),
        Outcome::Stopped,
        "channels 1 and 3 idle"
    );
    assert_eq!(st(&l, 1).pos, pt(10.0, 2.0));
    assert_eq!(st(&l, 1).state, ChState::Done);
    assert_eq!(
        (st(&l, 0).state, st(&l, 0).pos),
        (ChState::Idle, pt(20.0, 5.0))
    );
    // A running channel cannot be loaded; a bad waiting code is refused.
    l.start();
    l.tick();
    assert!(l.load(0, program("x", vec![])).is_err());
    let bad = program("x", vec![Op::Wait { m: 100, with: 0b1 }]);
    assert!(l.load(1, bad).is_err_and(|e| e.contains("channel 2")));
}

#[test]
fn feed_override_scales_the_feed_and_zero_feed_is_an_alarm() {
    let time = |pct: u32| {
        let mut l = one(
            vec![
                rpm(1000.0),
                rapid(10.0, 0.0),
                Op::Line {
                    end: pt(10.0, -20.0),
                    feed: Feed::PerMin(600.0),
                },
            ],
            true,
        );
        assert_eq!(l.set_feed_override(pct), Ok(()));
        l.start();
        assert_eq!(l.run_until_idle(MINUTE), Outcome::Finished { parts: 0 });
        l.machine_time_ns()
    };
    let (full, half) = (time(100), time(50));
    // 20 mm at 10 mm/s is 2 s; at 5 mm/s, 4 s (the rapid and ramps are the same).
    let d = half as f64 - full as f64;
    assert!((d - 2.0e9).abs() < 0.01e9, "{full} {half}");
    let mut l = one(vec![rpm(1000.0), line_rev(10.0, 0.0, 0.0)], true);
    assert!(l.set_feed_override(201).is_err());
    l.start();
    match l.run_until_idle(MINUTE) {
        Outcome::Alarm { msg, .. } => assert!(msg.contains("feed 0"), "{msg}"),
        o => panic!("{o:?}"),
    }
    // The machine's RESET clears every channel.
    l.estop();
    assert!(l.estopped());
    l.reset_all();
    assert!(!l.estopped());
    assert_eq!(st(&l, 0).state, ChState::Stop);
}

#[test]
fn the_display_reads_the_program_and_the_description() {
    let l = sample_lathe(5).expect("the sample lathe");
    assert_eq!(l.channels(), 3);
    assert_eq!(l.desc().channels[1].name, "SYS2");
    assert_eq!(l.program(2).map(|p| p.name.as_str()), Some("sys3"));
    assert!(l.program(3).is_none());
    assert_eq!(st(&l, 0).line, 1);
}
