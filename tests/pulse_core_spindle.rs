//! The spindle as a kernel object (issue 22; docs/pulse-core.md, "The spindle"): the speed
//! ramp, the encoder and its index, the wait for the spindle at speed, feed per revolution
//! (G95), constant surface speed (G96) and thread passes (G33), on `Machine` directly, against
//! the figures the lathe simulator gave where it had the same thing (the simulator was the
//! oracle until issue 22 deleted it; its figures are kept below with their provenance).

use novanc::block::{Block, Css, FeedMode, Motion, Tap};
use novanc::lathe::testkit::pt;
use novanc::pulse_core::{Command, Machine, PulseRec, RunKind, VecSource};
use novanc::settings::MachineSettings;

const MINUTE: u64 = 60_000_000_000;
const X: usize = 0;
const Z: usize = 2;

/// A lathe channel's numbers as the lathe test machine has them (`lathe::testkit::citizen_like`):
/// 6000 rpm, 8000 rpm/s, 1000 lines, 3000 mm/s², 24 m/min; the spindle starts with no
/// fixed delay (its ramp is its time).
fn lathe_settings() -> MachineSettings {
    MachineSettings {
        spindle_max_rpm: 6_000.0,
        spindle_accel_rpm_s: 8_000.0,
        spindle_encoder_lines: 1_000,
        spindle_ns: 0,
        accel_mm_s2: 3_000.0,
        rapid_mm_min: 24_000.0,
        travel_min_mm: [-1.0, -1.0, -80.0].into(),
        travel_max_mm: [60.0, 1.0, 60.0].into(),
        ..MachineSettings::builtin()
    }
}

/// A machine with `s` at X20 Z5 (the lathe simulator's tests' start), capturing pulses.
fn machine(s: MachineSettings) -> Machine {
    let mut m = Machine::new(s);
    assert!(m.set_position([20_000, 0, 5_000]));
    m.set_recording(None, true);
    m
}

/// X, Z in mm to machine pulses.
fn at(x: f64, z: f64) -> [i64; 3] {
    let p = pt(x, z);
    [p[0], 0, p[1]]
}

/// A block of `motion` to `end` (its amounts are taken from where the machine is).
fn mv(seq: u32, motion: Motion, end: [i64; 3]) -> Block {
    let mut b = Block::aux(seq, seq, end);
    b.motion = motion;
    b
}

/// A machine of [`lathe_settings`] with its spindle at S600 forward and the tool at X8 Z2,
/// where the thread passes of these tests start.
fn at_the_thread() -> Machine {
    let mut m = machine(lathe_settings());
    run(
        &mut m,
        vec![
            m3(1, at(20.0, 5.0), 600),
            mv(2, Motion::Rapid, at(8.0, 2.0)),
        ],
    );
    m
}

/// A pass of two thread blocks at 2 mm/rev from X8 Z2 (to Z-20, then out of the groove over
/// 2 mm of Z to X9 Z-22), the first marked to go on in the second if `goes_on`, and then the
/// retract to X12 if `retract`.
fn two_block_pass(goes_on: bool, retract: bool) -> Vec<Block> {
    let mut first = pass(3, at(8.0, -20.0), 2.0);
    if goes_on {
        first.tap = Tap::Part;
    }
    let mut v = vec![first, pass(4, at(9.0, -22.0), 2.0)];
    if retract {
        v.push(mv(5, Motion::Rapid, at(12.0, -22.0)));
    }
    v
}

/// M3 S`s` where the machine will be.
fn m3(seq: u32, end: [i64; 3], s: u32) -> Block {
    let mut b = Block::aux(seq, seq, end);
    b.m = Some(3);
    b.s = Some(s);
    b
}

/// A thread pass to `end`, `lead` mm/rev.
fn pass(seq: u32, end: [i64; 3], lead: f64) -> Block {
    let mut b = mv(seq, Motion::Linear, end);
    b.thread = Some(lead);
    b
}

/// A feed per revolution to `end`.
fn per_rev(seq: u32, end: [i64; 3], f: f64) -> Block {
    let mut b = mv(seq, Motion::Linear, end);
    b.feed = f;
    b.feed_mode = FeedMode::PerRev;
    b
}

fn run(m: &mut Machine, blocks: Vec<Block>) -> Vec<PulseRec> {
    let mut src = VecSource::from_blocks(blocks);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, 10 * MINUTE);
    let st = m.status();
    assert!(st.alarm.is_none(), "{:?}", st.alarm);
    assert!(m.is_idle());
    m.take_pulses()
}

/// Runs `blocks` one NCBR tick at a time, calling `each` after every tick.
fn tick_run(m: &mut Machine, blocks: Vec<Block>, mut each: impl FnMut(&Machine)) {
    let mut src = VecSource::from_blocks(blocks);
    m.command(Command::Start(RunKind::Auto));
    while !m.is_idle() {
        m.tick(&mut src);
        each(m);
        assert!(m.now() < 10 * MINUTE, "never idle");
    }
    assert!(m.status().alarm.is_none(), "{:?}", m.status().alarm);
}

#[test]
fn the_ramp_takes_delta_rpm_over_accel_and_the_cut_waits_for_the_speed() {
    let mut m = machine(lathe_settings());
    let mut first_full = None;
    let mut seen = Vec::new();
    tick_run(
        &mut m,
        vec![m3(1, at(20.0, 5.0), 3000), {
            let mut b = mv(2, Motion::Linear, at(20.0, 4.0));
            b.feed = 300.0;
            b
        }],
        |m| {
            let s = m.status().spindle;
            seen.push((m.now(), s));
            if s == 3000 && first_full.is_none() {
                first_full = Some(m.now());
            }
        },
    );
    // M3 at t = 0: 3000 rpm at 8000 rpm/s is 375 ms, the tick (5 ms) it ends in.
    assert_eq!(first_full, Some(375_000_000), "{:?}", &seen[..5]);
    for &(t, s) in &seen {
        if t <= 375_000_000 {
            assert_eq!(s, (t as f64 * 8e-6).round() as i64, "at {t} ns");
        }
    }
    // The cut starts at speed (within 1 %: 30 rpm, 3.75 ms before the ramp's end).
    let p = m.take_pulses();
    let t_first = p.first().map_or(0, |p| p.t_ns);
    assert!(
        t_first > 371_250_000 && t_first < 371_250_000 + 10_000_000,
        "{t_first}"
    );
    // The encoder is ∫rpm: 3000/2 rpm over 0.375 s, then 3000 rpm.
    let sp = m.spindle();
    let t = m.now();
    let revs = 1500.0 / 60.0 * 0.375 + 3000.0 / 60.0 * (t as f64 * 1e-9 - 0.375);
    assert_eq!(sp.count_at(t), (revs * 1000.0).floor() as i64);
    assert_eq!(sp.rpm_at(t), 3000.0);
}

#[test]
fn a_spindle_without_a_ramp_is_at_speed_at_once_as_on_the_centre() {
    // The centre's settings: the spindle's acceleration 0, so a cut never waits.
    let s = MachineSettings::default();
    assert_eq!(s.spindle_accel_rpm_s, 0.0);
    let mut m = Machine::new(s);
    assert!(m.set_position([500_000, 400_000, -300_000]));
    m.set_recording(None, true);
    let mut cut = mv(2, Motion::Linear, [501_000, 400_000, -300_000]);
    cut.feed = 600.0;
    let p = run(&mut m, vec![m3(1, [500_000, 400_000, -300_000], 1200), cut]);
    // M3 takes spindle_ns (1 s); the cut is read at the next NCBR tick (1.005 s) and its
    // first step comes after √(2/a) = 1.41 ms, with no wait for the speed.
    assert_eq!(p[0].t_ns, 1_005_000_000 + 1_414_213, "{}", p[0].t_ns);
    assert_eq!(m.status().spindle, 1200);
}

/// The phase of the machine's encoder at `t` (valid while the spindle holds its target).
fn phase(m: &Machine, t: u64) -> f64 {
    m.spindle().phase_at(t)
}

/// The Z pulses of a capture as (time, Z travelled in pulses).
fn z_steps(p: &[PulseRec]) -> Vec<(u64, i64)> {
    p.iter()
        .filter(|r| r.axis as usize == Z)
        .scan(0i64, |z, r| {
            *z += 1;
            Some((r.t_ns, *z))
        })
        .collect()
}

#[test]
fn a_thread_pass_starts_at_the_index_and_follows_the_encoder() {
    let mut m = at_the_thread();
    let lead = 2.0;
    let p = run(&mut m, vec![pass(3, at(8.0, -30.0), lead)]);
    assert_eq!(m.pos(), at(8.0, -30.0));
    let z = z_steps(&p);
    assert_eq!(z.len(), 32_000);
    let lines = 1000.0;
    // The index the pass started at: the encoder count at its first Z pulse is a whole number
    // of revolutions, plus what one Z pulse takes (half a count at 2 mm/rev).
    let p1 = phase(&m, z[0].0);
    let index = (p1 / lines).floor() * lines;
    assert!(p1 - index <= 0.5 + 1e-6 && p1 - index >= 0.5 - 1e-3, "{p1}");
    // Every Z pulse k is where lead × revolutions since the index says, within one pulse.
    for &(t, k) in &z {
        let by_encoder = (phase(&m, t) - index) / lines * lead * 1000.0;
        assert!((by_encoder - k as f64).abs() <= 1.0, "{k}: {by_encoder}");
    }
    // 16 revolutions at 600 rpm: 1.6 s from the index to the end (as the simulator had it, below).
    let t_index = m.spindle().time_at_phase(index).unwrap_or(0.0);
    let took = z[z.len() - 1].0 as f64 - t_index;
    assert!((took - 1.6e9).abs() < 10.0, "{took}");
}

/// A thread pass that goes on in the next block (`Tap::Part`: a G76 taper into or out of
/// the groove, a Fanuc chamfer): the next block starts where the encoder stands at its end,
/// not at the next index, so the whole pass is one helix; a block not so marked waits for
/// the index (a new pass). Before stop 50 every thread block waited for an index: a pass of
/// two blocks stood still at their junction for up to a revolution, turning a ring into the
/// groove.
#[test]
fn a_pass_of_several_blocks_is_one_helix_from_its_index() {
    for goes_on in [true, false] {
        let mut m = at_the_thread();
        // Out of the groove over the last 2 mm of Z, 1 mm of radius: Z the longer axis, at
        // the same lead.
        let p = run(&mut m, two_block_pass(goes_on, false));
        assert_eq!(m.pos(), at(9.0, -22.0));
        let z = z_steps(&p);
        assert_eq!(z.len(), 24_000);
        let lines = 1000.0;
        let index = (phase(&m, z[0].0) / lines).floor() * lines;
        // Z pulse k of the first block (22 mm: 11 revolutions) and of the second: where lead
        // × revolutions since the index says, within one pulse, or (a new pass) since the
        // next index after the first block's end, a revolution on.
        let after = if goes_on { 0.0 } else { 1000.0 };
        for &(t, k) in &z {
            let since = phase(&m, t) - index - if k > 22_000 { after } else { 0.0 };
            let by_encoder = since / lines * 2.0 * 1000.0;
            assert!(
                (by_encoder - k as f64).abs() <= 1.0,
                "goes on {goes_on}, pulse {k}: {by_encoder}"
            );
        }
    }
}

/// SINGLE BLOCK does not stop between the blocks of one pass (a Fanuc's single block waits
/// for the end of consecutive threading blocks): START runs the whole pass, still one helix,
/// and the run stops after its last block; the next START runs the retract.
#[test]
fn single_block_stops_after_the_whole_pass() {
    let mut m = at_the_thread();
    m.command(Command::SingleBlock(true));
    let mut src = VecSource::from_blocks(two_block_pass(true, true));
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, MINUTE);
    assert_eq!(
        m.pos(),
        at(9.0, -22.0),
        "stopped after the pass, not inside it"
    );
    let z = z_steps(&m.take_pulses());
    assert_eq!(z.len(), 24_000);
    let index = (phase(&m, z[0].0) / 1000.0).floor() * 1000.0;
    for &(t, k) in &z {
        let by_encoder = (phase(&m, t) - index) / 1000.0 * 2.0 * 1000.0;
        assert!(
            (by_encoder - k as f64).abs() <= 1.0,
            "pulse {k}: {by_encoder}"
        );
    }
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, MINUTE);
    assert_eq!(m.pos(), at(12.0, -22.0));
}

/// STOP in the first block of a pass that goes on holds at the end of the pass, not between
/// its blocks (Fanuc: after the last of consecutive threading blocks).
#[test]
fn a_feed_hold_waits_for_the_last_block_of_the_pass() {
    let mut m = at_the_thread();
    let mut src = VecSource::from_blocks(two_block_pass(true, true));
    m.command(Command::Start(RunKind::Auto));
    while m.pos()[Z] > -10_000 {
        m.tick(&mut src);
        assert!(m.now() < MINUTE);
    }
    m.command(Command::Stop);
    m.run_until_idle(&mut src, MINUTE);
    assert!(m.status().hold, "held");
    assert_eq!(
        m.pos(),
        at(9.0, -22.0),
        "out of the groove, the retract not begun"
    );
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, MINUTE);
    assert_eq!(m.pos(), at(12.0, -22.0));
}

#[test]
fn two_passes_of_one_thread_start_at_the_same_angle() {
    let mut m = machine(lathe_settings());
    let lead = 1.5;
    run(&mut m, vec![m3(1, at(20.0, 5.0), 900)]);
    let mut starts = Vec::new();
    for (k, x) in [9.6, 9.4].into_iter().enumerate() {
        let seq = 10 * k as u32;
        // Different approaches, so the passes start at different encoder phases.
        let _ = run(
            &mut m,
            vec![
                mv(seq + 1, Motion::Rapid, at(12.0 + k as f64 * 3.7, 3.0)),
                mv(seq + 2, Motion::Rapid, at(x, 3.0)),
            ],
        );
        let p = run(&mut m, vec![pass(seq + 3, at(x, -20.0), lead)]);
        let z = z_steps(&p);
        let t0 = z[0].0;
        // The angle of the spindle at the first Z pulse, and the offsets of the first 50.
        let a = phase(&m, t0).rem_euclid(1000.0);
        let rel: Vec<u64> = z[..50].iter().map(|s| s.0 - t0).collect();
        starts.push((a, rel, phase(&m, t0)));
    }
    assert!((starts[0].0 - starts[1].0).abs() < 1e-3, "{starts:?}");
    // The same times from the first pulse, to the ns (truncation).
    for (a, b) in starts[0].1.iter().zip(&starts[1].1) {
        assert!(a.abs_diff(*b) <= 1, "{a} {b}");
    }
    // They did start at different encoder counts (not a trivially equal case).
    assert!((starts[0].2 - starts[1].2).abs() > 1000.0);
}

#[test]
fn constant_surface_speed_follows_the_radius_then_the_limit() {
    let (v, limit) = (150.0, 4000.0);
    let mut m = machine(lathe_settings());
    let g96 = Some(Css {
        m_per_min: v,
        limit_rpm: limit,
    });
    let mut start = m3(1, at(20.0, 5.0), 0);
    start.s = None;
    start.css = g96;
    let mut approach = mv(2, Motion::Rapid, at(12.0, 0.0));
    approach.css = g96;
    let mut face = per_rev(3, at(0.0, 0.0), 0.1);
    face.css = g96;
    let (mut in_css, mut at_limit) = (0, 0);
    tick_run(&mut m, vec![start, approach, face], |m| {
        let st = m.status();
        let x = st.pos[X];
        if st.executed.as_ref().is_some_and(|b| b.seq == 3) && x > 0 && x < 12_000 {
            let r = x as f64 / 1000.0;
            let want = 1000.0 * v / (std::f64::consts::TAU * r);
            let rpm = st.spindle as f64;
            if want < limit * 0.99 {
                let surface = std::f64::consts::TAU * r * rpm / 1000.0;
                assert!((surface - v).abs() <= 0.01 * v, "r {r}: {surface} m/min");
                in_css += 1;
            } else if want > limit * 1.01 {
                assert!((rpm - limit).abs() <= 0.01 * limit, "r {r}: {rpm} rpm");
                at_limit += 1;
            }
        }
    });
    assert!(in_css > 50 && at_limit > 50, "{in_css} {at_limit}");
    assert_eq!(m.pos(), at(0.0, 0.0));
}

#[test]
fn feed_per_revolution_takes_length_over_feed_times_rpm() {
    // An instant spindle, so the speed is the programmed one from the start.
    let s = MachineSettings {
        spindle_accel_rpm_s: 0.0,
        ..lathe_settings()
    };
    let mut m = machine(s);
    run(&mut m, vec![m3(1, at(20.0, 5.0), 1000)]);
    let t0 = m.now();
    // 10 mm at 0.1 mm/rev × 1000 rpm = 100 mm/min: 6 s, plus the ramp at 3000 mm/s²
    // (v/a = 0.56 ms).
    let p = run(&mut m, vec![per_rev(2, at(20.0, -5.0), 0.1)]);
    let took = (p[p.len() - 1].t_ns - t0) as f64 * 1e-9;
    let want = 10.0 / (0.1 * 1000.0) * 60.0;
    assert!((took - want).abs() < 0.002, "{took} s, want {want} s");
    // The spindle override scales the speed, so the feed: 120 % → 5 s.
    m.command(Command::SpindleOverride(120));
    let t1 = m.now();
    let p = run(&mut m, vec![per_rev(3, at(20.0, 5.0), 0.1)]);
    let took = (p[p.len() - 1].t_ns - t1) as f64 * 1e-9;
    assert!((took - want / 1.2).abs() < 0.007, "{took} s");
}

#[test]
fn per_revolution_and_threads_are_refused_with_the_spindle_stopped() {
    for (b, what) in [
        (per_rev(1, at(20.0, 0.0), 0.1), "feed per revolution"),
        (pass(1, at(20.0, 0.0), 1.0), "a thread pass"),
    ] {
        let mut m = machine(lathe_settings());
        let mut src = VecSource::from_blocks(vec![b]);
        m.command(Command::Start(RunKind::Auto));
        m.run_until_idle(&mut src, MINUTE);
        let alarm = m.status().alarm.unwrap_or_default();
        assert!(
            alarm.starts_with("line 1: N1 ") && alarm.contains(what) && alarm.contains("stopped"),
            "{alarm}"
        );
        assert_eq!(m.pos(), at(20.0, 5.0), "nothing moved");
    }
    // A lead below one pulse a revolution (it would never end), and a pass that is not a line.
    let mut arc = pass(2, at(20.0, 5.0), 1.0);
    arc.motion = Motion::ArcCw;
    arc.center = Some([-1_000, 0]);
    for (b, what) in [
        (pass(2, at(20.0, 0.0), 1e-9), "at least one pulse"),
        (arc, "must be a straight move"),
    ] {
        let mut m = machine(lathe_settings());
        let mut src = VecSource::from_blocks(vec![m3(1, at(20.0, 5.0), 600), b]);
        m.command(Command::Start(RunKind::Auto));
        m.run_until_idle(&mut src, MINUTE);
        let alarm = m.status().alarm.unwrap_or_default();
        assert!(
            alarm.starts_with("line 2: N2 ") && alarm.contains(what),
            "{alarm}"
        );
    }
}

#[test]
fn a_feed_hold_during_a_thread_pass_comes_at_its_end() {
    let mut m = at_the_thread();
    let mut src = VecSource::from_blocks(vec![
        pass(3, at(8.0, -30.0), 2.0),
        mv(4, Motion::Rapid, at(12.0, -30.0)),
    ]);
    m.command(Command::Start(RunKind::Auto));
    while m.pos()[Z] > -10_000 {
        m.tick(&mut src);
        assert!(m.now() < MINUTE);
    }
    m.command(Command::Stop);
    assert!(m
        .status()
        .notice
        .unwrap_or_default()
        .contains("thread pass"));
    m.run_until_idle(&mut src, MINUTE);
    // Held at the end of the pass, not in the groove, and the retract not begun.
    let st = m.status();
    assert!(st.hold, "held");
    assert_eq!(m.pos(), at(8.0, -30.0));
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, MINUTE);
    assert_eq!(m.pos(), at(12.0, -30.0));
}

/// The thread pass of `the_thread_pass_and_the_facing_time_are_the_simulators`, from its
/// index to its end, as the lathe simulator gave it (deleted in issue 22): M3 S600, G0 X8 Z2,
/// G33 Z-30 F2 on its test machine (`citizen_like(1)`, 1000-line encoder, 100 µs tick) from
/// X20 Z5: 1.6000 s, the 16 revolutions at 600 rpm, to its tick (it counted whole encoder
/// lines each 100 µs).
const SIMULATOR_THREAD_PASS_NS: f64 = 1_600_000_000.0;

/// The facing block of the same test, G96 S150 (limit 4000 rpm), G0 X12 Z0, G95 G1 X0 F0.1,
/// as the simulator gave it: 2.4019 s (a trapezoid per 100 µs tick and the rpm re-targeted
/// every tick, the block timed from its start event to the tick it reached X0).
const SIMULATOR_FACING_NS: f64 = 2_401_900_000.0;

#[test]
fn the_thread_pass_and_the_facing_time_are_the_simulators() {
    // Thread: the kernel's pass from its index to its end against the simulator's figure.
    let mut m = at_the_thread();
    let p = run(&mut m, vec![pass(3, at(8.0, -30.0), 2.0)]);
    let z = z_steps(&p);
    let index = (phase(&m, z[0].0) / 1000.0).floor() * 1000.0;
    let kernel_pass = z[z.len() - 1].0 as f64 - m.spindle().time_at_phase(index).unwrap_or(0.0);
    // Both 1.6 s (the kernel's to the ns); the simulator's to its 100 µs tick.
    assert!(
        (SIMULATOR_THREAD_PASS_NS - kernel_pass).abs() <= 200_000.0,
        "{kernel_pass}"
    );

    // Facing at G96: the simulator (trapezoid per 100 µs tick, rpm per tick) gave 2.4019 s;
    // the kernel (DDA, feed per revolution retargeted each 5 ms NCBR tick) gives 2.3853 s:
    // the same time within 1 %.
    let g96 = Some(Css {
        m_per_min: 150.0,
        limit_rpm: 4000.0,
    });
    let mut m = machine(lathe_settings());
    let mut start = m3(1, at(20.0, 5.0), 0);
    (start.s, start.css) = (None, g96);
    let mut approach = mv(2, Motion::Rapid, at(12.0, 0.0));
    approach.css = g96;
    run(&mut m, vec![start, approach]);
    let t0 = m.now();
    let mut face = per_rev(3, at(0.0, 0.0), 0.1);
    face.css = g96;
    let p = run(&mut m, vec![face]);
    let kernel_face = (p[p.len() - 1].t_ns - t0) as f64;
    eprintln!(
        "thread pass: simulator {:.4} s, kernel {:.4} s; facing: simulator {:.4} s, kernel {:.4} s",
        SIMULATOR_THREAD_PASS_NS * 1e-9,
        kernel_pass * 1e-9,
        SIMULATOR_FACING_NS * 1e-9,
        kernel_face * 1e-9
    );
    assert!(
        (SIMULATOR_FACING_NS - kernel_face).abs() <= 0.01 * SIMULATOR_FACING_NS,
        "{kernel_face}"
    );
}

#[test]
fn a_tap_on_a_spindle_with_a_ramp_follows_its_encoder() {
    // The centre with a spindle that ramps (2000 rpm/s): a tap's feed (G84, TAP) is geared
    // to the encoder, at the pitch = feed / programmed speed (375 / 300 = 1.25 mm/rev).
    let s = MachineSettings {
        spindle_accel_rpm_s: 2_000.0,
        ..MachineSettings::default()
    };
    let mid = [500_000, 400_000, -300_000];
    let mut m = Machine::new(s);
    assert!(m.set_position(mid));
    m.set_recording(None, true);
    let bottom = [mid[0], mid[1], mid[2] - 10_000];
    let mut feed_in = mv(2, Motion::Linear, bottom);
    feed_in.feed = 375.0;
    feed_in.tap = novanc::block::Tap::Part;
    let p = run(&mut m, vec![m3(1, mid, 300), feed_in]);
    assert_eq!(m.pos(), bottom);
    let z = z_steps(&p);
    assert_eq!(z.len(), 10_000);
    // Pulse k falls when the encoder has turned k / 1250 revolutions since the start: the
    // anchor is one step's counts before the first pulse.
    let lines = f64::from(m.spindle().lines());
    let per_step = lines / 1250.0;
    let anchor = phase(&m, z[0].0) - per_step;
    for &(t, k) in &z {
        let by_encoder = (phase(&m, t) - anchor) / lines * 1250.0;
        assert!((by_encoder - k as f64).abs() <= 1.0, "{k}: {by_encoder}");
    }
    // It started at speed (within 1 %, still ramping: the feed followed the actual speed).
    let first = m.spindle().rpm_at(z[0].0);
    assert!((297.0..300.0).contains(&first), "{first}");
    assert_eq!(m.spindle().rpm_at(z[z.len() - 1].0), 300.0);
}

#[test]
fn a_thread_pass_is_the_same_run_whole_or_tick_by_tick() {
    // A spindle without a ramp lets the machine run a pass whole; it must give the pulses,
    // to the ns, that tick-by-tick running gives (PGEN's rule, docs/pulse-core.md "Timing").
    let s = MachineSettings {
        spindle_accel_rpm_s: 0.0,
        ..lathe_settings()
    };
    let blocks = || {
        vec![
            m3(1, at(20.0, 5.0), 750),
            mv(2, Motion::Rapid, at(8.0, 2.0)),
            pass(3, at(7.5, -25.0), 1.75),
            mv(4, Motion::Rapid, at(12.0, -25.0)),
        ]
    };
    let mut whole = machine(s.clone());
    let a = run(&mut whole, blocks());
    let mut ticked = machine(s);
    tick_run(&mut ticked, blocks(), |_| {});
    let b = ticked.take_pulses();
    assert_eq!(a.len(), b.len());
    assert!(a.iter().zip(&b).all(|(p, q)| p == q));
    assert_eq!(whole.pos(), ticked.pos());
}

#[test]
fn estop_stops_the_spindle_at_once_and_reset_lets_it_run_down() {
    let mut m = machine(lathe_settings());
    run(&mut m, vec![m3(1, at(20.0, 5.0), 2000)]);
    let mut src = VecSource::from_blocks(vec![]);
    m.advance_to(m.now() + 1_000_000_000, &mut src);
    assert_eq!(m.status().spindle, 2000);
    // RESET: the spindle is told to stop and runs down at its acceleration (2000 rpm at
    // 8000 rpm/s: 250 ms).
    m.command(Command::Reset);
    let t = m.now();
    assert_eq!(m.spindle().target(), 0.0);
    assert!((m.spindle().rpm_at(t + 125_000_000) - 1000.0).abs() < 1e-6);
    assert_eq!(m.spindle().rpm_at(t + 250_000_000), 0.0);
    // E-STOP cuts the drive: 0 at once, the encoder keeps its count.
    run(&mut m, vec![m3(2, at(20.0, 5.0), 2000)]);
    m.advance_to(m.now() + 1_000_000_000, &mut src);
    let before = m.spindle().count_at(m.now());
    m.command(Command::EStop);
    assert_eq!(m.spindle().rpm_at(m.now()), 0.0);
    assert_eq!(m.status().spindle, 0);
    assert_eq!(m.spindle().count_at(m.now() + 1_000_000_000), before);
}
