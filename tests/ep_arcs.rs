//! Arcs by the error-proportional interpolator (seed 001's chord and perpendicular method,
//! docs/pulse-core.md) in every plane and direction, full circles included: the end exact, the
//! turn as programmed, the tool near the circle, pulse totals equal to the counters, and the
//! path speed along the arc the feed away from the end.

use novanc::block::{Block, Motion, Plane};
use novanc::pulse_core::testkit::{arc_angles, arc_ends, Rng};
use novanc::pulse_core::{Command, Machine, PulseRec, RunKind, VecSource};
use novanc::settings::{Interpolator, MachineSettings};
use std::f64::consts::TAU;

const MID: [i64; 3] = [500_000, 400_000, -300_000];
const HOUR: u64 = 3_600_000_000_000;

fn run(start: [i64; 3], b: Block) -> (Machine, Vec<PulseRec>) {
    let mut m = Machine::new(MachineSettings {
        interpolator: Interpolator::ErrorProportional,
        ..MachineSettings::default()
    });
    assert!(m.set_position(start));
    m.set_recording(None, true);
    let mut src = VecSource::from_blocks(vec![b]);
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, HOUR);
    assert!(m.is_idle());
    let p = m.take_pulses();
    (m, p)
}

/// The worst distance from the circle of the programmed radius, and from the block's own arc
/// (its start and end are whole pulses, off that circle by up to 0.7 pulses: the radius goes
/// from the start's to the end's in proportion to the angle turned), pulses; the pulses made
/// against those the arc needs; the radius.
fn check(rng: &mut Rng, plane: Plane, ccw: bool, full: bool, feed: f64) -> (f64, f64, f64, f64) {
    let [u, v] = plane.turn_axes();
    let r = rng.range(2_000, 120_000) as f64;
    let (th0, th1, sweep) = arc_angles(rng, full, ccw);
    let c = MID;
    let (s, e) = arc_ends(plane, c, (r, th0), (r, th1), full);
    let b = novanc::pulse_core::testkit::plane_arc(plane, s, e, c, ccw, feed);
    let (m, pulses) = run(s, b);
    let what = format!("{plane:?} r {r} ccw {ccw} full {full}");
    assert_eq!(m.status().alarm, None, "{what}");
    assert_eq!(m.pos(), e, "end exact: {what}");
    let mut n = [0i64; 3];
    for p in &pulses {
        n[p.axis as usize] += 1;
    }
    for (a, &na) in n.iter().enumerate() {
        assert_eq!(
            m.status().pulses[a] as i64,
            na,
            "counter of axis {a}: {what}"
        );
    }
    let rad = |p: [i64; 3]| ((p[u] - c[u]) as f64).hypot((p[v] - c[v]) as f64);
    let mut p = s;
    let mut worst = 0.0f64;
    let (r0, r1) = (rad(s), rad(e));
    let mut worst_own = 0.0f64;
    let mut turned = 0.0f64;
    let mut prev = [(s[u] - c[u]) as f64, (s[v] - c[v]) as f64];
    let mut i = 0;
    while i < pulses.len() {
        let t = pulses[i].t_ns;
        while i < pulses.len() && pulses[i].t_ns == t {
            p[pulses[i].axis as usize] += pulses[i].dir as i64;
            i += 1;
        }
        worst = worst.max((rad(p) - r).abs());
        let q = [(p[u] - c[u]) as f64, (p[v] - c[v]) as f64];
        turned += (prev[0] * q[1] - prev[1] * q[0]).atan2(prev[0] * q[0] + prev[1] * q[1]);
        prev = q;
        let own = r0 + (r1 - r0) * (turned.abs() / sweep).min(1.0);
        worst_own = worst_own.max((rad(p) - own).abs());
    }
    let got = if ccw { turned } else { -turned };
    assert!(
        (got - sweep).abs() < 0.01,
        "turned {got} for {sweep}: {what}"
    );
    // The pulses the arc needs (each axis's total travel along the true arc), against those
    // made.
    let k = 100_000;
    let dir = if ccw { 1.0 } else { -1.0 };
    let (mut ideal, mut q0) = (0.0, [th0.cos(), th0.sin()]);
    for j in 1..=k {
        let a = th0 + dir * sweep * j as f64 / k as f64;
        let q = [a.cos(), a.sin()];
        ideal += r * ((q[0] - q0[0]).abs() + (q[1] - q0[1]).abs());
        q0 = q;
    }
    let made = (n[u] + n[v]) as f64;
    // No pulse back and forth: an axis reverses only where the arc crosses the other axis's
    // line through the centre (u at 0° and 180°, v at 90° and 270°).
    let mut last = [0i8; 3];
    let mut reversals = 0;
    for p in &pulses {
        let a = p.axis as usize;
        if last[a] == -p.dir {
            reversals += 1;
        }
        last[a] = p.dir;
    }
    let quarter = std::f64::consts::FRAC_PI_2;
    let (lo, hi) = if ccw {
        (th0, th0 + sweep)
    } else {
        (th0 - sweep, th0)
    };
    let crossings = ((lo / quarter).floor() as i64 + 1..=(hi / quarter).ceil() as i64 - 1)
        .filter(|&k| (k as f64 * quarter - lo) > 1e-9 && (hi - k as f64 * quarter) > 1e-9)
        .count();
    assert!(
        reversals <= crossings,
        "{reversals} reversals where the arc crosses {crossings} axes: {what}"
    );
    (worst, worst_own, made / ideal, r)
}

/// How many arcs per plane: `NOVANC_EP_ARCS` (default 12). The long run:
/// `NOVANC_EP_ARCS=400 cargo test --release --test ep_arcs arcs_in -- --nocapture`.
fn arc_count() -> usize {
    std::env::var("NOVANC_EP_ARCS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12)
}

#[test]
fn arcs_in_every_plane_end_exactly_and_stay_near_the_circle() {
    let mut rng = Rng::new(21);
    let mut worst = 0.0f64;
    let mut worst_own = 0.0f64;
    let mut extra = 0.0f64;
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..arc_count() {
            let feed = [500.0, 2000.0, 6000.0][i % 3];
            let (w, own, x, r) = check(&mut rng, plane, i % 2 == 0, i % 4 == 0, feed);
            worst = worst.max(w);
            worst_own = worst_own.max(own);
            extra = extra.max(x);
            // docs/pulse-core.md, "Arcs by the chord and the perpendicular": the issue's
            // 1 pulse from the block's own arc (whose whole-pulse ends lie off the programmed
            // circle by up to 0.7 pulses), 1.5 from the programmed circle.
            assert!(own <= 1.0, "{own} pulses off the arc ({plane:?}, case {i})");
            assert!(w <= 1.5, "{w} pulses off the circle ({plane:?}, case {i})");
            assert!(x <= 1.001 + 4.0 / r, "{x} times the pulses the arc needs");
        }
    }
    eprintln!(
        "arcs: largest distance from the circle {worst:.3} pulses ({worst_own:.3} from the block's own arc); at most {:.2} % more pulses than the arc needs",
        (extra - 1.0) * 100.0
    );
}

/// A quarter circle of 50 mm radius at F1000 takes the time the feed regulator gives it
/// (Equation II's estimate of the speed, G + 0.4 M, against the true √(G² + M²)) plus the
/// tail, as a line does: the chord method is regulated as a line is.
#[test]
fn an_arc_runs_at_the_feed() {
    use novanc::settings::{EP_CYCLE_NS, EP_L_DEFAULT};
    let r = 50_000i64;
    let s = [MID[0] + r, MID[1], MID[2]];
    let e = [MID[0], MID[1] + r, MID[2]];
    let mut b = Block::aux(1, 1, e);
    b.motion = Motion::ArcCcw;
    b.delta = [e[0] - s[0], e[1] - s[1], 0].into();
    b.center = Some([-r, 0]);
    b.feed = 1000.0;
    let (m, p) = run(s, b);
    assert_eq!(m.pos(), e);
    let t = p.last().map_or(0.0, |p| p.t_ns as f64 * 1e-9);
    let f = 1000.0 / 60.0 / 0.001;
    let k = 10_000;
    let mut eq2 = 0.0;
    for j in 0..k {
        let a = (j as f64 + 0.5) / k as f64 * std::f64::consts::FRAC_PI_2;
        let (x, y) = (a.sin(), a.cos());
        eq2 += (x.max(y) + 0.4 * x.min(y)) * std::f64::consts::FRAC_PI_2 / k as f64;
    }
    let regulated = r as f64 * eq2 / f;
    // The tail: from E_sat = F·L/(f_r − F) on, pulse n takes (L + n)/n cycles.
    let (l, f_r) = (EP_L_DEFAULT as f64, 1e9 / EP_CYCLE_NS as f64);
    let e_sat = (f * l / (f_r - f)) as i64;
    let tail: f64 = (1..=e_sat)
        .map(|n| (l + n as f64) / n as f64 / f_r)
        .sum::<f64>()
        - e_sat as f64 / f;
    let want = regulated + tail;
    let at_feed = r as f64 * std::f64::consts::FRAC_PI_2 / f;
    eprintln!(
        "quarter circle R50 at F1000: {t:.3} s; at the feed {at_feed:.3} s, as regulated {regulated:.3} s + tail {tail:.3} s = {want:.3} s"
    );
    assert!((t / want - 1.0).abs() < 0.02, "{t} vs {want}");
}

/// Helices in every plane: the end exact, the circle kept, and the normal axis where the
/// angle turned puts it (reconstruction: its error is gated in proportion to the angle left).
#[test]
fn helices_in_every_plane_keep_their_pitch_and_end_exactly() {
    let mut rng = Rng::new(33);
    let (mut worst_r, mut worst_z) = (0.0f64, 0.0f64);
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..6 {
            let [u, v] = plane.turn_axes();
            let n = plane.axes()[2];
            let ccw = i % 2 == 0;
            let r = rng.range(5_000, 60_000) as f64;
            let th0 = rng.unit() * TAU;
            let sweep = if i % 3 == 0 {
                TAU
            } else {
                (0.1 + rng.unit() * 0.85) * TAU
            };
            let normal = rng.range(-40_000, 40_000);
            let c = MID;
            let mut s = c;
            s[u] += (r * th0.cos()).round() as i64;
            s[v] += (r * th0.sin()).round() as i64;
            let th1 = if ccw { th0 + sweep } else { th0 - sweep };
            let mut e = if i % 3 == 0 { s } else { c };
            if i % 3 != 0 {
                e[u] += (r * th1.cos()).round() as i64;
                e[v] += (r * th1.sin()).round() as i64;
            }
            e[n] = s[n] + normal;
            let b = novanc::pulse_core::testkit::plane_arc(plane, s, e, c, ccw, 1500.0);
            let (m, pulses) = run(s, b);
            let what = format!("{plane:?} r {r} ccw {ccw} normal {normal}");
            assert_eq!(m.status().alarm, None, "{what}");
            assert_eq!(m.pos(), e, "end exact: {what}");
            let mut p = s;
            let mut turned = 0.0f64;
            let mut prev = [(s[u] - c[u]) as f64, (s[v] - c[v]) as f64];
            for q in &pulses {
                p[q.axis as usize] += q.dir as i64;
                let d = [(p[u] - c[u]) as f64, (p[v] - c[v]) as f64];
                worst_r = worst_r.max((d[0].hypot(d[1]) - r).abs());
                turned += (prev[0] * d[1] - prev[1] * d[0]).atan2(prev[0] * d[0] + prev[1] * d[1]);
                prev = d;
                let a = if ccw { turned } else { -turned };
                let z = s[n] as f64 + normal as f64 * (a / sweep).clamp(0.0, 1.0);
                worst_z = worst_z.max((p[n] as f64 - z).abs());
            }
        }
    }
    eprintln!(
        "helices: largest distance from the circle {worst_r:.2} pulses, normal axis off the pitch {worst_z:.2} pulses"
    );
    assert!(worst_r <= 2.0, "{worst_r}");
    assert!(worst_z <= 2.0, "{worst_z}");
}

/// Tiny arcs and full circles (radius 2 to 40 pulses) in every plane end exactly and in a
/// bounded time: the chord method near its limits.
#[test]
fn tiny_arcs_end_exactly() {
    let mut rng = Rng::new(44);
    for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
        for i in 0..30 {
            let [u, v] = plane.turn_axes();
            let r = rng.range(2, 40) as f64;
            let full = i % 4 == 0;
            let ccw = i % 2 == 0;
            let (th0, th1, _) = arc_angles(&mut rng, full, ccw);
            let c = MID;
            let (s, e) = arc_ends(plane, c, (r, th0), (r, th1), full);
            let rs = (((s[u] - c[u]).pow(2) + (s[v] - c[v]).pow(2)) as f64).sqrt();
            let re = (((e[u] - c[u]).pow(2) + (e[v] - c[v]).pow(2)) as f64).sqrt();
            if rs < 2.0 || re < 2.0 {
                continue;
            }
            let b = novanc::pulse_core::testkit::plane_arc(plane, s, e, c, ccw, 1000.0);
            let (m, p) = run(s, b);
            assert_eq!(m.status().alarm, None, "{plane:?} r {r} case {i}");
            assert_eq!(m.pos(), e, "{plane:?} r {r} case {i}");
            assert!(p.len() < 2000, "{} pulses for r {r}", p.len());
            assert!(m.now() < 60_000_000_000, "{} ns", m.now());
        }
    }
}
