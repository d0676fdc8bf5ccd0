//! The splines checked against their curves evaluated independently of the chord-making code:
//! de Casteljau's repeated interpolation for the Bézier curves of G5 and G5.1, and the
//! Cox–de Boor recursion of the basis functions for the NURBS of G5.2, with LinuxCNC's knots
//! written out here again. Every chord end must be a point of the curve, every point of the
//! curve between two chord ends must be within the tolerance of their chord, and the last end
//! must be the programmed end exactly.

use super::curve::{self, ChordEnd};
use super::{MAX_CHORDS, MAX_ORDER};
use crate::block::{Block, Motion};
use crate::gcode::geom::dist;
use crate::gcode::{translate_all, WorkOffsets};
use crate::pulse_core::testkit::Rng;
use crate::settings::MachineSettings;
use crate::tooldata::sample_magazine;

/// Curve points checked between two chord ends.
const SAMPLES: usize = 48;

fn lerp2(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
}

/// The distance from `q` to the segment `a`–`b`, written for the tests.
fn off_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    if l2 == 0.0 {
        return dist(q, a);
    }
    let s = (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0);
    dist(q, lerp2(a, b, s))
}

/// de Casteljau: the point at `t` of the Bézier curve of `p`.
fn de_casteljau(p: &[[f64; 2]], t: f64) -> [f64; 2] {
    let mut w = p.to_vec();
    for level in 1..w.len() {
        for i in 0..w.len() - level {
            w[i] = lerp2(w[i], w[i + 1], t);
        }
    }
    w[0]
}

/// LinuxCNC's knots for `count` points of order `k`: k zeros, 1 … n − k + 1, then k times
/// n − k + 2 (n = count − 1), as its `knot_vector_creator` defines them.
fn linuxcnc_knots(count: usize, k: usize) -> Vec<f64> {
    let n = count - 1;
    (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i - k + 1) as f64
            } else {
                (n + 2 - k) as f64
            }
        })
        .collect()
}

/// Cox–de Boor: the basis function N(i, k) (order k) at `u`; spans half-open, the last one
/// closed at the end of the parameter.
fn basis(i: usize, k: usize, u: f64, t: &[f64]) -> f64 {
    if k == 1 {
        let end = t[t.len() - 1];
        let inside = (t[i] <= u && u < t[i + 1]) || (u == end && t[i] < end && t[i + 1] == end);
        return if inside { 1.0 } else { 0.0 };
    }
    let mut v = 0.0;
    if t[i + k - 1] > t[i] {
        v += (u - t[i]) / (t[i + k - 1] - t[i]) * basis(i, k - 1, u, t);
    }
    if t[i + k] > t[i + 1] {
        v += (t[i + k] - u) / (t[i + k] - t[i + 1]) * basis(i + 1, k - 1, u, t);
    }
    v
}

/// The NURBS point at `u`: Σ N·w·P / Σ N·w.
fn nurbs_at(p: &[[f64; 2]], w: &[f64], k: usize, u: f64) -> [f64; 2] {
    let t = linuxcnc_knots(p.len(), k);
    let (mut x, mut y, mut d) = (0.0, 0.0, 0.0);
    for i in 0..p.len() {
        let b = basis(i, k, u, &t) * w[i];
        x += b * p[i][0];
        y += b * p[i][1];
        d += b;
    }
    [x / d, y / d]
}

/// Checks chords against the curve `at` over parameters `u0`..`u1`.
fn check(at: &dyn Fn(f64) -> [f64; 2], u0: f64, u1: f64, chords: &[ChordEnd], tol: f64) {
    assert!(!chords.is_empty());
    let (mut from, mut u) = (at(u0), u0);
    for (i, c) in chords.iter().enumerate() {
        assert!(c.u > u, "chord {i}: parameter {} after {u}", c.u);
        let on = at(c.u);
        assert!(
            dist(on, c.at) < 1e-9 * (1.0 + on[0].abs() + on[1].abs()),
            "chord {i} ends at {:?}, the curve is at {on:?}",
            c.at
        );
        for s in 1..SAMPLES {
            let q = at(u + (c.u - u) * s as f64 / SAMPLES as f64);
            let d = off_segment(q, from, c.at);
            assert!(
                d <= tol * (1.0 + 1e-9) + 1e-12,
                "chord {i}: {d} mm off (tolerance {tol})"
            );
        }
        (from, u) = (c.at, c.u);
    }
    assert_eq!(u, u1, "the chords end at the curve's end");
}

fn random_points(r: &mut Rng, n: usize, size: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|_| [(r.unit() - 0.5) * size, (r.unit() - 0.5) * size])
        .collect()
}

/// A random NURBS of order `k`: k to k + `extra` control points within `size` mm, weights
/// 0.2 to 5.
fn random_nurbs(r: &mut Rng, k: usize, extra: i64, size: f64) -> (usize, Vec<[f64; 2]>, Vec<f64>) {
    let count = k + r.range(0, extra) as usize;
    let p = random_points(r, count, size);
    let w = (0..count).map(|_| 0.2 + 4.8 * r.unit()).collect();
    (k, p, w)
}

#[test]
fn bezier_chords_lie_on_the_curve_and_within_the_tolerance() {
    let mut r = Rng::new(5);
    for case in 0..60 {
        let n = if case % 2 == 0 { 4 } else { 3 };
        let p = random_points(&mut r, n, 200.0);
        let tol = [0.001, 0.01, 0.1][case % 3];
        let chords = curve::flatten(&[curve::bezier(&p)], tol, MAX_CHORDS).expect("chords");
        check(&|t| de_casteljau(&p, t), 0.0, 1.0, &chords, tol);
        assert_eq!(chords[chords.len() - 1].at, p[n - 1]);
    }
}

#[test]
fn a_straight_bezier_is_one_chord_and_a_point_one_chord_of_no_length() {
    let line = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]];
    let c = curve::flatten(&[curve::bezier(&line)], 0.001, MAX_CHORDS).unwrap();
    assert_eq!(c.len(), 1);
    let dot = [[5.0, 5.0]; 4];
    let c = curve::flatten(&[curve::bezier(&dot)], 0.001, MAX_CHORDS).unwrap();
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].at, [5.0, 5.0]);
}

#[test]
fn a_loop_that_returns_to_its_start_is_followed_round() {
    // Start and end meet; the control points pull the curve 75 mm away and back.
    let p = [[0.0, 0.0], [100.0, 100.0], [-100.0, 100.0], [0.0, 0.0]];
    let chords = curve::flatten(&[curve::bezier(&p)], 0.001, MAX_CHORDS).unwrap();
    assert!(chords.len() > 50, "{} chords", chords.len());
    check(&|t| de_casteljau(&p, t), 0.0, 1.0, &chords, 0.001);
}

#[test]
fn the_knots_are_linuxcncs() {
    assert_eq!(
        curve::knots(5, 3),
        vec![0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]
    );
    for (count, order) in [(3, 3), (7, 4), (12, 6), (9, 9)] {
        assert_eq!(curve::knots(count, order), linuxcnc_knots(count, order));
    }
}

#[test]
fn nurbs_pieces_are_the_curve_of_cox_de_boor() {
    let mut r = Rng::new(11);
    for case in 0..40 {
        let (k, p, w) = random_nurbs(&mut r, 3 + case % 4, 9, 100.0);
        let count = p.len();
        let pieces = curve::nurbs(&p, &w, k);
        assert_eq!(pieces.len(), count + 1 - k, "one piece per knot span");
        for piece in &pieces {
            for s in [0.0, 0.125, 0.5, 0.8, 1.0] {
                // The rational Bézier piece by de Casteljau on the weighted points.
                let wx: Vec<[f64; 2]> = piece.hom.iter().map(|h| [h[0], h[1]]).collect();
                let ww: Vec<[f64; 2]> = piece.hom.iter().map(|h| [h[2], 0.0]).collect();
                let (num, den) = (de_casteljau(&wx, s), de_casteljau(&ww, s)[0]);
                let got = [num[0] / den, num[1] / den];
                let u = piece.u0 + s * (piece.u1 - piece.u0);
                let want = nurbs_at(&p, &w, k, u);
                assert!(
                    dist(got, want) < 1e-9,
                    "case {case} u {u}: {got:?} {want:?}"
                );
            }
        }
    }
}

#[test]
fn nurbs_chords_lie_on_the_curve_and_within_the_tolerance() {
    let mut r = Rng::new(23);
    for case in 0..24 {
        let (k, p, w) = random_nurbs(&mut r, 3 + case % 3, 6, 60.0);
        let count = p.len();
        let tol = [0.001, 0.005, 0.05][case % 3];
        let chords = curve::flatten(&curve::nurbs(&p, &w, k), tol, MAX_CHORDS).unwrap();
        let end = (count + 1 - k) as f64;
        check(&|u| nurbs_at(&p, &w, k, u), 0.0, end, &chords, tol);
        assert!(dist(chords[chords.len() - 1].at, p[count - 1]) < 1e-9);
    }
}

#[test]
fn linuxcncs_documentation_nurbs() {
    // docs/gcode.md "Splines": the start and four control points, the last weighing 2.
    let p = [[0.0, 0.0], [0.0, 1.0], [2.0, 2.0], [2.0, 0.0], [0.0, 0.0]];
    let w = [1.0, 1.0, 1.0, 1.0, 2.0];
    let chords = curve::flatten(&curve::nurbs(&p, &w, 3), 0.001, MAX_CHORDS).unwrap();
    check(&|u| nurbs_at(&p, &w, 3, u), 0.0, 3.0, &chords, 0.001);
}

#[test]
fn more_chords_than_the_limit_is_an_error() {
    let p = [[0.0, 0.0], [100.0, 100.0], [-100.0, 100.0], [0.0, 0.0]];
    let pieces = [curve::bezier(&p)];
    assert_eq!(
        curve::flatten(&pieces, 1e-6, 100),
        Err(curve::TooManyChords)
    );
    assert!(curve::flatten(&pieces, 1e-6, MAX_CHORDS).is_ok());
}

// The splines as the interpreter reads them: blocks in whole pulses (0.001 mm) of the sample
// machine, its work zero set at X500 Y400 Z-300.

const ZERO: [f64; 2] = [500.0, 400.0];

fn blocks(body: &str) -> Result<Vec<Block>, String> {
    let src = format!("G21 G17 G90\nG10 L2 P1 X500 Y400 Z-300\nG54\n{body}\nM2\n");
    let stmts = translate_all(
        &src,
        &sample_magazine(),
        &MachineSettings::default(),
        [0, 0, 0],
        WorkOffsets::default(),
    )
    .map_err(|e| e.to_string())?;
    Ok(stmts.into_iter().flat_map(|s| s.blocks).collect())
}

fn mm(b: &Block) -> [f64; 2] {
    [b.end[0] as f64 / 1000.0, b.end[1] as f64 / 1000.0]
}

/// The feed blocks of source line `line`.
fn of_line(bs: &[Block], line: u32) -> Vec<Block> {
    bs.iter()
        .filter(|b| b.stmt == line && b.motion == Motion::Linear)
        .cloned()
        .collect()
}

/// Checks that every block of `line` ends within rounding of the curve `at` (program
/// coordinates, u over `u0..u1`) and the last at `end` exactly; returns their number.
fn on_curve(
    bs: &[Block],
    line: u32,
    at: &dyn Fn(f64) -> [f64; 2],
    u1: f64,
    end: [f64; 2],
) -> usize {
    let dense: Vec<[f64; 2]> = (0..=20_000)
        .map(|i| {
            let q = at(u1 * i as f64 / 20_000.0);
            [q[0] + ZERO[0], q[1] + ZERO[1]]
        })
        .collect();
    let mine = of_line(bs, line);
    assert!(!mine.is_empty(), "line {line} made no feed block");
    for b in &mine {
        let e = mm(b);
        let d = dense
            .windows(2)
            .map(|s| off_segment(e, s[0], s[1]))
            .fold(f64::MAX, f64::min);
        assert!(
            d < 0.0008,
            "a block of line {line} ends {d} mm off the curve"
        );
    }
    let last = mm(&mine[mine.len() - 1]);
    assert_eq!(last, [end[0] + ZERO[0], end[1] + ZERO[1]]);
    mine.len()
}

#[test]
fn g5_moves_along_its_cubic_and_continues_its_tangent_without_i_j() {
    let bs = blocks("G0 X0 Y0\nF500\nG5 I10 J0 P-10 Q0 X30 Y10\nG5 P0 Q-10 X50 Y50").unwrap();
    let first = [[0.0, 0.0], [10.0, 0.0], [20.0, 10.0], [30.0, 10.0]];
    let n = on_curve(&bs, 6, &|t| de_casteljau(&first, t), 1.0, [30.0, 10.0]);
    assert!(n > 10, "{n} blocks");
    // Without I J: the first control point mirrors the previous second one (-P, -Q).
    let second = [[30.0, 10.0], [40.0, 10.0], [50.0, 40.0], [50.0, 50.0]];
    on_curve(&bs, 7, &|t| de_casteljau(&second, t), 1.0, [50.0, 50.0]);
    assert!(of_line(&bs, 7).iter().all(|b| b.feed == 500.0));
}

#[test]
fn g5_1_moves_along_its_quadratic_in_inches_and_increments_alike() {
    let bs = blocks("G0 X10 Y10\nF300\nG91 G5.1 I20 J20 X40 Y0\nG90").unwrap();
    let q = [[10.0, 10.0], [30.0, 30.0], [50.0, 10.0]];
    on_curve(&bs, 6, &|t| de_casteljau(&q, t), 1.0, [50.0, 10.0]);
    let mm_blocks = of_line(&bs, 6);
    let inch =
        blocks("G0 X10 Y10\nF300\nG20 G91 G5.1 I[20/25.4] J[20/25.4] X[40/25.4] Y0\nG21 G90")
            .unwrap();
    let ends = |v: &[Block]| v.iter().map(|b| b.end).collect::<Vec<_>>();
    assert_eq!(ends(&of_line(&inch, 6)), ends(&mm_blocks));
}

#[test]
fn g5_2_moves_along_its_nurbs_to_the_last_control_point() {
    let bs =
        blocks("G0 X0 Y0\nF100\nG5.2 P1 L3\nX0 Y1 P1\nX2 Y2 P1\nX2 Y0 P1\nX0 Y0 P2\nG5.3\nG1 X5")
            .unwrap();
    let p = [[0.0, 0.0], [0.0, 1.0], [2.0, 2.0], [2.0, 0.0], [0.0, 0.0]];
    let w = [1.0, 1.0, 1.0, 1.0, 2.0];
    // The G5.2 lines move nothing; G5.3 (line 11) moves.
    assert!((6..=10).all(|l| of_line(&bs, l).is_empty()));
    let n = on_curve(&bs, 11, &|u| nurbs_at(&p, &w, 3, u), 3.0, [0.0, 0.0]);
    assert!(n > 20, "{n} blocks");
    assert_eq!(of_line(&bs, 12).len(), 1, "the G1 after it");
}

#[test]
fn g64_p_sets_the_tolerance() {
    let prog = |g64: &str| format!("{g64}\nG0 X0 Y0\nF100\nG5.1 I20 J40 X40 Y0");
    let fine = of_line(&blocks(&prog("G64")).unwrap(), 7).len();
    let coarse = of_line(&blocks(&prog("G64 P0.05")).unwrap(), 7).len();
    assert!(
        coarse * 3 < fine,
        "G64 P0.05: {coarse} chords, one pulse: {fine}"
    );
    // The quadratic's chords at 0.05 mm: their ends on the curve, every point of the curve
    // within 0.05 mm (and the pulse rounding) of the path.
    let bs = blocks(&prog("G64 P0.05")).unwrap();
    let q = [[0.0, 0.0], [20.0, 40.0], [40.0, 0.0]];
    on_curve(&bs, 7, &|t| de_casteljau(&q, t), 1.0, [40.0, 0.0]);
    let mut path = vec![ZERO];
    path.extend(of_line(&bs, 7).iter().map(mm));
    for i in 0..=2000 {
        let c = de_casteljau(&q, i as f64 / 2000.0);
        let c = [c[0] + ZERO[0], c[1] + ZERO[1]];
        let d = path
            .windows(2)
            .map(|s| off_segment(c, s[0], s[1]))
            .fold(f64::MAX, f64::min);
        assert!(d <= 0.0508, "the curve is {d} mm from the path");
    }
}

#[test]
fn the_feed_modes_share_out_over_the_chords() {
    // G93: F2 is half a minute for the whole curve.
    let bs = blocks("G0 X0 Y0\nG93 G5.1 I20 J40 X40 Y0 F2\nG94").unwrap();
    let chords = of_line(&bs, 5);
    let feed = chords[0].feed;
    assert!(chords.iter().all(|b| b.feed == feed));
    let length: f64 = chords
        .iter()
        .map(|b| (b.delta[0] as f64).hypot(b.delta[1] as f64) / 1000.0)
        .sum();
    assert!((length / feed - 0.5).abs() < 1e-4, "{} min", length / feed);
    // G95: F × S.
    let bs = blocks("G0 X0 Y0\nS1000 M3\nG95 F0.2 G5.1 I20 J40 X40 Y0\nG94").unwrap();
    assert!(of_line(&bs, 6).iter().all(|b| b.feed == 200.0));
}

fn error(body: &str) -> String {
    match blocks(body) {
        Ok(_) => panic!("no error in {body}"),
        Err(e) => e,
    }
}

#[test]
fn bad_spline_words_are_refused_with_their_line_and_column() {
    let pre = "G0 X0 Y0\nF100\n";
    for (body, want) in [
        ("G18 G5 I1 J0 P1 Q0 X3 Y1", "6:5: splines work in the XY plane (G17) only"),
        ("G5 I1 J0 P1 Q0 X3 Y1 Z1", "6:22: a spline moves in X and Y only"),
        ("G5.1 I1 X3 Y1", "6:1: G5.1 needs both I and J"),
        ("G5 I1 X3 Y1 P1 Q1", "6:1: G5 takes both I and J, or neither"),
        ("G5 I1 J1 X3 Y1 P1", "6:1: G5 needs both P and Q"),
        ("G5 I1 J1 P1 Q1", "6:1: this motion needs at least one of X, Y and Z"),
        ("G5.1 I1 J1 X3 Y1 P1", "6:18: P word with no"),
        ("G5.2 X1 Y1 P1 Q1\nX2 Y0 P1\nG5.3", "6:15: Q word with no"),
        ("G5.2 X1 P1", "6:1: a G5.2 control point needs both X and Y"),
        ("G5.2 X1 Y1 L3", "6:1: every control point needs its weight P"),
        ("G5.2 X1 Y1 P0", "6:12: P0: a control point's weight must be greater than 0"),
        ("G5.2 X1 Y1 P1 L2", "6:15: L2: a NURBS's order is 3 (quadratic) to 16"),
        ("G5.2 X1 Y1 P1\nX2 Y2 P1 L4", "7:10: L (the NURBS's order) is given on its first"),
        ("G5.2 P1\nL4 X1 Y1 P1\nG5.3", "7:1: L (the NURBS's order)"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P0", "7:7: P0: a control point's weight"),
        ("G5.3", "6:1: G5.3 without G5.2 first"),
        ("G5.2 X1 Y1 P1 L4\nX2 Y0 P1\nG5.3", "8:1: the NURBS has 3 control points (the start included): its order L4 needs at least 4"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P1\nG1 X3", "8:1: this motion before G5.3: the NURBS begun on line 6"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P1\nG5.3 X4 Y4", "8:1: G5.3 takes no X or Y"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P1\nG1 G5.3", "8:4: between G5.2 and G5.3 only more G5.2 lines"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P1\nG28\nG5.3", "9:1: the machine has moved since the NURBS began on line 6"),
        ("G5.2 X1 Y1 P1\nX2 Y0 P1\nG18\nG5.3", "9:1: splines work in the XY plane"),
        ("G41 D0\nG5 I1 J0 P1 Q0 X3 Y1", "7:1: splines (G5, G5.1, G5.2) cannot be used with cutter radius compensation on"),
        ("G93 G5 I1 J0 P1 Q0 X3 Y1", "6:5: inverse time feed (G93): each feed move needs its own F"),
        ("G93 G5.2 X1 Y1 P1\nX2 Y0 P1\nG5.3", "8:1: inverse time feed (G93) needs F"),
        ("G5.1 I1 J1 X3 Y1 F0", "6:1: a feed move without F"),
        ("G5.1 I[1000000*1000000] J1 X3 Y1", "6:6: I is out of all range"),
    ] {
        let got = error(&format!("{pre}{body}"));
        assert!(got.starts_with(want), "{body}: {got}");
    }
    let got = error("G0 X0 Y0\nF100\nG5.2 X1 Y1 P1\nX2 Y0 P1");
    assert!(
        got.starts_with("8:1: the program's end before G5.3: the NURBS begun on line 6"),
        "{got}"
    );
}

#[test]
fn a_nurbs_ended_then_begun_on_one_line_and_its_limits() {
    // G5.3 ends the first NURBS before the line's G5.2 begins the next (LinuxCNC's order).
    let bs =
        blocks("G0 X0 Y0\nF100\nG5.2 X10 Y10 P1\nX20 Y0 P1\nG5.3 G5.2 X30 Y10 P1\nX40 Y0 P1\nG5.3")
            .unwrap();
    assert_eq!(mm(&of_line(&bs, 8).pop().unwrap()), [520.0, 400.0]);
    assert_eq!(mm(&of_line(&bs, 10).pop().unwrap()), [540.0, 400.0]);
    let order = format!("G0 X0 Y0\nF100\nG5.2 X1 Y1 P1 L{}", MAX_ORDER + 1);
    assert!(error(&order).contains("a NURBS's order is 3 (quadratic) to 16"));
}

#[test]
fn after_g40_the_exit_move_goes_to_the_curves_start() {
    let bs =
        blocks("T1 M6\nG0 X-50 Y-50\nF100\nG41\nG1 X10 Y0\nG1 X80 Y10\nG40\nG5.1 I10 J10 X100 Y0")
            .unwrap();
    let mine = of_line(&bs, 11);
    assert_eq!(
        mm(&mine[0]),
        [580.0, 410.0],
        "the exit move ends at the start"
    );
    let q = [[80.0, 10.0], [90.0, 20.0], [100.0, 0.0]];
    on_curve(&bs, 11, &|t| de_casteljau(&q, t), 1.0, [100.0, 0.0]);
}
