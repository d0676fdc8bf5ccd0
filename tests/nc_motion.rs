//! Pulse core motion on virtual time, driving `Machine` directly: pulse exactness of linear
//! moves, arcs, feed, determinism.

use novanc::block::Motion;
use novanc::pulse_core::testkit::{arc, linear, Rng};
use novanc::pulse_core::{Command, Machine, PulseRec, RunKind, VecSource};
use novanc::settings::MachineSettings;

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const HOUR: u64 = 3_600_000_000_000;

fn machine() -> Machine {
    let mut m = Machine::new(MachineSettings::default());
    assert!(m.set_position(MID));
    m.set_recording(None, true);
    m
}

fn run(m: &mut Machine, blocks: Vec<novanc::block::Block>) -> Vec<PulseRec> {
    let mut src = VecSource::from_blocks(blocks);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m.is_idle());
    m.take_pulses()
}

/// Groups pulses by time (one PGEN step each) and returns the position after each step.
fn positions(start: [i64; 3], pulses: &[PulseRec]) -> Vec<[i64; 3]> {
    novanc::pulse_core::testkit::steps(start, pulses)
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

#[test]
fn linear_moves_give_exact_pulses_and_stay_on_the_line() {
    let mut rng = Rng::new(4);
    for case in 0..60 {
        let n_axes = case % 3 + 1;
        let mut delta = [0i64; 3];
        let mut axes = [0usize, 1, 2];
        // pick n_axes distinct axes
        for k in 0..3 {
            let j = rng.range(k as i64, 2) as usize;
            axes.swap(k, j);
        }
        for &a in &axes[..n_axes] {
            delta[a] = rng.range(-40_000, 40_000);
        }
        let mut m = machine();
        let pulses = run(&mut m, vec![linear(1, MID, delta, 3000.0)]);
        let mut count = [0i64; 3];
        for p in &pulses {
            count[p.axis as usize] += 1;
            assert_eq!(p.dir as i64, delta[p.axis as usize].signum(), "direction");
        }
        for a in 0..3 {
            assert_eq!(count[a], delta[a].abs(), "axis {a} of {delta:?}");
        }
        assert_eq!(
            m.pos(),
            [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]]
        );
        let major = (0..3).max_by_key(|&a| (delta[a].abs(), 3 - a)).unwrap_or(0);
        for p in positions(MID, &pulses) {
            let k = (p[major] - MID[major]).abs() as f64;
            for a in 0..3 {
                if a == major || delta[a] == 0 {
                    continue;
                }
                let ideal = k * delta[a] as f64 / delta[major].abs() as f64;
                let got = (p[a] - MID[a]) as f64;
                assert!((got - ideal).abs() < 1.0 + 1e-9, "{delta:?} at {p:?}");
            }
        }
        // pulse times ascend
        assert!(pulses.windows(2).all(|w| w[0].t_ns <= w[1].t_ns));
    }
}

fn check_arc(rng: &mut Rng, ccw: bool, full: bool) {
    let r = rng.range(500, 150_000) as f64;
    let a0 = rng.unit() * std::f64::consts::TAU;
    let sweep = if full {
        0.0
    } else {
        (0.05 + rng.unit() * 0.9) * std::f64::consts::TAU
    };
    let a1 = if ccw { a0 + sweep } else { a0 - sweep };
    let c = [MID[0], MID[1]];
    let s = [
        c[0] + (r * a0.cos()).round() as i64,
        c[1] + (r * a0.sin()).round() as i64,
    ];
    let e = if full {
        s
    } else {
        [
            c[0] + (r * a1.cos()).round() as i64,
            c[1] + (r * a1.sin()).round() as i64,
        ]
    };
    let start = [s[0], s[1], MID[2]];
    let mut m = machine();
    assert!(m.set_position(start));
    let b = arc(
        1,
        start,
        [e[0] - s[0], e[1] - s[1]],
        [c[0] - s[0], c[1] - s[1]],
        ccw,
        2000.0,
    );
    let pulses = run(&mut m, vec![b]);
    assert_eq!(
        m.pos(),
        [e[0], e[1], MID[2]],
        "end exact (r {r}, ccw {ccw}, full {full})"
    );
    let rs = (((s[0] - c[0]).pow(2) + (s[1] - c[1]).pow(2)) as f64).sqrt();
    let re = (((e[0] - c[0]).pow(2) + (e[1] - c[1]).pow(2)) as f64).sqrt();
    let (lo, hi) = (rs.min(re) - 1.0, rs.max(re) + 1.0);
    let pts = positions(start, &pulses);
    assert!(
        pts.len() as f64 > if full { std::f64::consts::TAU } else { sweep } * r * 0.7,
        "it moved along the arc: {} steps, r {r}, sweep {sweep}, alarm {:?}",
        pts.len(),
        m.status().alarm
    );
    let mut turned = 0.0;
    let mut prev = (s[1] - c[1]) as f64;
    let mut prevx = (s[0] - c[0]) as f64;
    for p in &pts {
        let (x, y) = ((p[0] - c[0]) as f64, (p[1] - c[1]) as f64);
        let d = x.hypot(y);
        assert!(
            d >= lo && d <= hi,
            "off the circle: {d} not in [{lo}, {hi}]"
        );
        let cross = prevx * y - prev * x;
        let dot = prevx * x + prev * y;
        turned += cross.atan2(dot);
        prev = y;
        prevx = x;
    }
    let want = if full { std::f64::consts::TAU } else { sweep };
    let got = if ccw { turned } else { -turned };
    assert!(
        (got - want).abs() < 0.01,
        "turned {got} for {want} (ccw {ccw})"
    );
}

#[test]
fn arcs_stay_within_one_pulse_and_end_exactly() {
    let mut rng = Rng::new(11);
    for i in 0..40 {
        check_arc(&mut rng, i % 2 == 0, i % 5 == 0);
    }
}

#[test]
fn arc_full_circles_both_directions() {
    let mut rng = Rng::new(12);
    for i in 0..8 {
        check_arc(&mut rng, i % 2 == 0, true);
    }
}

/// Path speed over the middle third of a long move.
fn cruise_speed_mm_min(pulses: &[PulseRec], delta: [i64; 3], s: &MachineSettings) -> f64 {
    let pts = positions(MID, pulses);
    let times: Vec<u64> = {
        let mut t: Vec<u64> = pulses.iter().map(|p| p.t_ns).collect();
        t.dedup();
        t
    };
    let n = pts.len();
    let (i0, i1) = (n / 3, 2 * n / 3);
    let major = (0..3).max_by_key(|&a| delta[a].abs()).unwrap_or(0);
    let len = ((delta[0].pow(2) + delta[1].pow(2) + delta[2].pow(2)) as f64).sqrt();
    let ds = len / delta[major].abs() as f64;
    let dist = (i1 - i0) as f64 * ds * s.pulse_mm;
    let dt = (times[i1] - times[i0]) as f64 * 1e-9;
    dist / dt * 60.0
}

#[test]
fn path_speed_after_acceleration_is_feed_times_override() {
    let s = MachineSettings::default();
    for (ovr, delta) in [
        (100, [200_000, 0, 0]),
        (50, [120_000, -90_000, 0]),
        (150, [-60_000, 100_000, -40_000]),
        (30, [0, 0, -50_000]),
    ] {
        let mut m = machine();
        m.command(Command::Override(ovr));
        let pulses = run(&mut m, vec![linear(1, MID, delta, 2000.0)]);
        let v = cruise_speed_mm_min(&pulses, delta, &s);
        let want = 2000.0 * ovr as f64 / 100.0;
        assert!((v - want).abs() <= want * 0.01, "{v} mm/min for {want}");
    }
}

#[test]
fn rapid_runs_at_the_rapid_rate_and_ignores_override() {
    let s = MachineSettings::default();
    let delta = [300_000, 0, 0];
    let mut m = machine();
    m.command(Command::Override(10));
    let b = novanc::pulse_core::testkit::block(1, Motion::Rapid, MID, delta, 0.0);
    let pulses = run(&mut m, vec![b]);
    let v = cruise_speed_mm_min(&pulses, delta, &s);
    assert!((v - s.rapid_mm_min).abs() <= s.rapid_mm_min * 0.01, "{v}");
}

#[test]
fn acceleration_is_bounded_and_each_block_ends_at_rest() {
    let s = MachineSettings::default();
    let mut m = machine();
    let pulses = run(&mut m, vec![linear(1, MID, [50_000, 0, 0], 6000.0)]);
    let t: Vec<f64> = pulses.iter().map(|p| p.t_ns as f64 * 1e-9).collect();
    // speeds between successive pulses, mm/s
    let v: Vec<f64> = t.windows(2).map(|w| s.pulse_mm / (w[1] - w[0])).collect();
    assert!(
        v[0] < 5.0 && *v.last().unwrap() < 5.0,
        "starts and ends slow"
    );
    let vmax = v.iter().cloned().fold(0.0, f64::max);
    assert!(
        (vmax - 100.0).abs() < 1.0,
        "cruise 6000 mm/min = 100 mm/s, got {vmax}"
    );
    // time to reach cruise ≈ v / a = 0.1 s
    let reach = v.iter().position(|&x| x > 99.0).unwrap();
    let t_reach = t[reach] - t[0];
    assert!((t_reach - 0.1).abs() < 0.01, "{t_reach}");
}

#[test]
fn same_program_gives_the_same_pulse_times() {
    let mk = || {
        let mut rng = Rng::new(99);
        let mut p = MID;
        let mut pts = vec![p];
        for _ in 0..20 {
            p = [
                p[0] + rng.range(-20_000, 20_000),
                p[1] + rng.range(-20_000, 20_000),
                p[2] + rng.range(-5_000, 5_000),
            ];
            pts.push(p);
        }
        let mut bl = novanc::pulse_core::testkit::polyline(&pts, 1500.0);
        let last = *pts.last().unwrap();
        bl.push(arc(30, last, [0, 0], [10_000, 0], true, 1000.0));
        bl
    };
    let mut m1 = machine();
    let a = run(&mut m1, mk());
    let mut m2 = machine();
    let b = run(&mut m2, mk());
    assert!(a.len() > 100_000);
    assert_eq!(a, b);
    assert_eq!(m1.now(), m2.now());
}

#[test]
fn small_arcs_in_every_quadrant() {
    let mut rng = Rng::new(13);
    for i in 0..300 {
        let c = [MID[0], MID[1]];
        let r = rng.range(3, 60);
        // start and end on lattice points near the circle, often on the axes
        let pick = |rng: &mut Rng| -> [i64; 2] {
            if rng.range(0, 3) == 0 {
                let k = rng.range(0, 3);
                [[r, 0], [0, r], [-r, 0], [0, -r]][k as usize]
            } else {
                let a = rng.unit() * std::f64::consts::TAU;
                [
                    (r as f64 * a.cos()).round() as i64,
                    (r as f64 * a.sin()).round() as i64,
                ]
            }
        };
        let s = pick(&mut rng);
        let e = if i % 7 == 0 { s } else { pick(&mut rng) };
        let start = [c[0] + s[0], c[1] + s[1], MID[2]];
        let mut m = machine();
        assert!(m.set_position(start));
        let ccw = i % 2 == 0;
        let pulses = run(
            &mut m,
            vec![arc(
                1,
                start,
                [e[0] - s[0], e[1] - s[1]],
                [-s[0], -s[1]],
                ccw,
                500.0,
            )],
        );
        assert_eq!(
            m.pos(),
            [c[0] + e[0], c[1] + e[1], MID[2]],
            "r {r} {s:?} -> {e:?} ccw {ccw}"
        );
        let rs = ((s[0] * s[0] + s[1] * s[1]) as f64).sqrt();
        let re = ((e[0] * e[0] + e[1] * e[1]) as f64).sqrt();
        for p in positions(start, &pulses) {
            let d = ((p[0] - c[0]) as f64).hypot((p[1] - c[1]) as f64);
            assert!(
                d >= rs.min(re) - 1.0 && d <= rs.max(re) + 1.0,
                "r {r} {s:?}->{e:?}: {d}"
            );
        }
        if s == e {
            assert!(pulses.len() as f64 > 4.0 * r as f64, "a full circle");
        }
    }
}

#[test]
fn tiny_and_empty_moves_complete() {
    for delta in [
        [1, 0, 0],
        [0, -1, 0],
        [1, 1, 1],
        [2, -1, 0],
        [0, 0, 0],
        [3, 0, -2],
    ] {
        let mut m = machine();
        let pulses = run(&mut m, vec![linear(1, MID, delta, 1000.0)]);
        assert_eq!(
            m.pos(),
            [MID[0] + delta[0], MID[1] + delta[1], MID[2] + delta[2]]
        );
        assert_eq!(
            pulses.len() as i64,
            delta.iter().map(|d| d.abs()).sum::<i64>()
        );
        assert_eq!(m.blocks_done(), 1);
    }
}

#[test]
fn arc_path_speed_is_the_feed_in_every_direction() {
    // a full circle of radius 50 mm at 1200 mm/min (and 50 % override): over each eighth of
    // the middle of the circle the speed along the circle is the feed within 1 %
    for ovr in [100, 50] {
        let r = 50_000i64;
        let start = [MID[0] + r, MID[1], MID[2]];
        let mut m = machine();
        assert!(m.set_position(start));
        m.command(Command::Override(ovr));
        let pulses = run(&mut m, vec![arc(1, start, [0, 0], [-r, 0], true, 1200.0)]);
        assert_eq!(m.pos(), start);
        let pts = positions(start, &pulses);
        let mut times: Vec<u64> = pulses.iter().map(|p| p.t_ns).collect();
        times.dedup();
        let ang = |p: [i64; 3]| ((p[1] - MID[1]) as f64).atan2((p[0] - MID[0]) as f64);
        let want = 1200.0 * ovr as f64 / 100.0;
        let n = pts.len();
        for k in 1..7 {
            let (i0, i1) = (n * k / 8, n * (k + 1) / 8 - 1);
            let mut da = ang(pts[i1]) - ang(pts[i0]);
            if da < 0.0 {
                da += std::f64::consts::TAU;
            }
            let len_mm = da * r as f64 * 0.001;
            let secs = (times[i1] - times[i0]) as f64 * 1e-9;
            let v = len_mm / secs * 60.0;
            assert!(
                (v - want).abs() <= want * 0.01,
                "octant {k}: {v} mm/min for {want}"
            );
        }
    }
}

/// Stop 58: each axis keeps its own rate. On a machine whose X rapids at 30,000 mm/min and Z
/// at 6,000, a Z rapid cruises at Z's rate and an X rapid at X's; the rapid override is a share
/// of that held rate (50 % halves each), and a jog at a feed above an axis's rate is held to it
/// and halved by the same override.
#[test]
fn each_axis_keeps_its_own_rate_and_the_rapid_override_is_a_share_of_it() {
    let s = MachineSettings {
        rapid_mm_min: 30_000.0,
        axis_rate: novanc::settings::own_rates(&[(0, 30_000.0), (1, 30_000.0), (2, 6_000.0)]),
        ..MachineSettings::default()
    };
    let fresh = || {
        let mut m = Machine::new(s.clone());
        assert!(m.set_position(MID));
        m.set_recording(None, true);
        m
    };
    for (pct, delta, want) in [
        (100, [0, 0, -200_000], 6_000.0),
        (50, [0, 0, -200_000], 3_000.0),
        (100, [400_000, 0, 0], 30_000.0),
        (50, [400_000, 0, 0], 15_000.0),
    ] {
        let mut m = fresh();
        m.command(Command::RapidOverride(pct));
        let b = novanc::pulse_core::testkit::block(1, Motion::Rapid, MID, delta, 0.0);
        let pulses = run(&mut m, vec![b]);
        let v = cruise_speed_mm_min(&pulses, delta, &s);
        assert!((v - want).abs() <= want * 0.01, "{pct} % {delta:?}: {v}");
    }
    for (pct, want) in [(100, 6_000.0), (50, 3_000.0)] {
        let mut m = fresh();
        m.set_jog_feed(30_000.0);
        m.command(Command::RapidOverride(pct));
        let mut src = VecSource::default();
        m.command(Command::Jog { axis: 2, dir: -1 });
        // Past its ramp (at most 0.2 s at the default 1,000 mm/s²), 0.5 s of cruise.
        m.advance_to(m.now() + 400_000_000, &mut src);
        let z0 = m.pos()[2];
        m.advance_to(m.now() + 500_000_000, &mut src);
        let v = (z0 - m.pos()[2]) as f64 * s.pulse_mm / 0.5 * 60.0;
        assert!(
            (v - want).abs() <= want * 0.02,
            "jog at {pct} %: {v} mm/min"
        );
        m.command(Command::JogRelease);
    }
}
