//! Arcs in every plane (G17, G18, G19) and helices, on the pulse core in virtual time: every
//! pulse within 1 pulse of the true curve, the end point exact, the turn as programmed
//! (the same properties `nc_motion.rs` checks for XY arcs; docs/pulse-core.md).

use novanc::block::{Block, Motion, Plane};
use novanc::pulse_core::testkit::{arc_angles, arc_ends, Rng};
use novanc::pulse_core::{Command, Machine, PulseRec, RunKind, VecSource};
use novanc::settings::MachineSettings;
use std::f64::consts::TAU;

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const HOUR: u64 = 3_600_000_000_000;

fn run(start: [i64; 3], b: Block) -> (Machine, Vec<PulseRec>) {
    let mut m = Machine::new(MachineSettings::default());
    assert!(m.set_position(start));
    m.set_recording(None, true);
    let mut src = VecSource::from_blocks(vec![b]);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m.is_idle());
    let p = m.take_pulses();
    (m, p)
}

/// Positions after each PGEN step (pulses grouped by time), the start first.
fn positions(start: [i64; 3], pulses: &[PulseRec]) -> Vec<[i64; 3]> {
    std::iter::once(start)
        .chain(
            novanc::pulse_core::testkit::steps(start, pulses)
                .into_iter()
                .map(|(_, p)| p),
        )
        .collect()
}

/// One random arc or helix in `plane`; `normal` pulses along the plane's normal.
fn check(rng: &mut Rng, plane: Plane, ccw: bool, full: bool, normal: i64, r_max: i64) {
    check_spiral(rng, plane, ccw, full, normal, r_max, 0);
}

/// The same with the end radius `dr` pulses off the start radius (a spiral, as G-code allows).
fn check_spiral(
    rng: &mut Rng,
    plane: Plane,
    ccw: bool,
    full: bool,
    normal: i64,
    r_max: i64,
    dr: i64,
) {
    let [u, v] = plane.turn_axes();
    let n = plane.axes()[2];
    let r = rng.range(300, r_max) as f64;
    let (th0, th1, sweep) = arc_angles(rng, full, ccw);
    let c = MID;
    let (s, mut e) = arc_ends(plane, c, (r, th0), (r + dr as f64, th1), full);
    e[n] = s[n] + normal;
    let b = novanc::pulse_core::testkit::plane_arc(plane, s, e, c, ccw, 2000.0);
    let (m, pulses) = run(s, b);
    let what = format!("{plane:?} r {r} ccw {ccw} full {full} normal {normal}");
    assert_eq!(m.status().alarm, None, "{what}");
    assert_eq!(m.pos(), e, "end exact: {what}");
    let rad = |p: [i64; 3]| ((p[u] - c[u]) as f64).hypot((p[v] - c[v]) as f64);
    let (lo, hi) = (rad(s).min(rad(e)) - 1.0, rad(s).max(rad(e)) + 1.0);
    let pts = positions(s, &pulses);
    // The angle progress of every point, unwrapped, in the turning direction.
    let mut prog = Vec::with_capacity(pts.len());
    let mut turned = 0.0f64;
    let mut prev = [(s[u] - c[u]) as f64, (s[v] - c[v]) as f64];
    for p in &pts {
        let d = rad(*p);
        assert!(
            d >= lo && d <= hi,
            "off the circle: {d} not in [{lo}, {hi}]: {what}"
        );
        let q = [(p[u] - c[u]) as f64, (p[v] - c[v]) as f64];
        let cross = prev[0] * q[1] - prev[1] * q[0];
        let dot = prev[0] * q[0] + prev[1] * q[1];
        turned += cross.atan2(dot);
        prev = q;
        prog.push(if ccw { turned } else { -turned });
    }
    let got = *prog.last().unwrap_or(&0.0);
    assert!(
        (got - sweep).abs() < 0.01,
        "turned {got} for {sweep}: {what}"
    );
    if normal != 0 {
        // Along the normal: within 1 pulse of the true helix between the angles of the circle
        // points the tool stands between.
        let ideal = |a: f64| s[n] as f64 + normal as f64 * (a / got).clamp(0.0, 1.0);
        let mut next_angle = vec![got; pts.len()];
        for i in (0..pts.len().saturating_sub(1)).rev() {
            let moved = pts[i + 1][u] != pts[i][u] || pts[i + 1][v] != pts[i][v];
            next_angle[i] = if moved {
                prog[i + 1]
            } else {
                next_angle[i + 1]
            };
        }
        for (i, p) in pts.iter().enumerate() {
            let (z0, z1) = (ideal(prog[i]), ideal(next_angle[i]));
            let (lo, hi) = (z0.min(z1) - 1.0, z0.max(z1) + 1.0);
            let z = p[n] as f64;
            assert!(
                z >= lo && z <= hi,
                "normal axis {z} not in [{lo}, {hi}] at {i}: {what}"
            );
        }
    }
}

#[test]
fn arcs_in_every_plane_stay_within_one_pulse_and_end_exactly() {
    let mut rng = Rng::new(21);
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..16 {
            check(&mut rng, plane, i % 2 == 0, i % 5 == 0, 0, 120_000);
        }
    }
}

#[test]
fn helices_in_every_plane_follow_the_curve_and_end_exactly() {
    let mut rng = Rng::new(22);
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..16 {
            // Shallow, steep (more normal pulses than circle steps) and one-pulse helices.
            let normal = match i % 4 {
                0 => rng.range(-30_000, 30_000),
                1 => rng.range(150_000, 250_000) * if i % 3 == 0 { -1 } else { 1 },
                2 => {
                    if i % 2 == 0 {
                        1
                    } else {
                        -1
                    }
                }
                _ => rng.range(-3_000, 3_000),
            };
            let r_max = if i % 4 == 1 { 20_000 } else { 120_000 };
            check(&mut rng, plane, i % 2 == 1, i % 3 == 0, normal, r_max);
        }
    }
}

#[test]
fn spirals_within_30_pulses_end_exactly_between_their_radii() {
    let mut rng = Rng::new(23);
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..8 {
            let dr = rng.range(-28, 28);
            let normal = if i % 2 == 0 {
                0
            } else {
                rng.range(-5_000, 5_000)
            };
            check_spiral(&mut rng, plane, i % 3 == 0, false, normal, 60_000, dr);
        }
    }
}

#[test]
fn a_helix_is_timed_along_its_length() {
    // A full XY circle of radius 10 mm rising 20 mm at F600: the helix is
    // sqrt((2π·10)² + 20²) = 65.94 mm long, so about 6.6 s plus the ramps.
    let s = [MID[0] + 10_000, MID[1], MID[2]];
    let mut b = Block::aux(1, 1, [s[0], s[1], s[2] + 20_000]);
    b.motion = Motion::ArcCcw;
    b.delta = [0, 0, 20_000].into();
    b.center = Some([-10_000, 0]);
    b.feed = 600.0;
    let (m, pulses) = run(s, b);
    assert_eq!(m.pos(), [s[0], s[1], s[2] + 20_000]);
    let last = pulses.last().map_or(0, |p| p.t_ns) as f64 / 1e9;
    let len = (TAU * 10.0).hypot(20.0);
    assert!(
        last > len / 10.0 && last < len / 10.0 + 0.1,
        "took {last} s"
    );
}
