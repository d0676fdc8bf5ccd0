//! The plane curves of the splines and their chords (docs/gcode.md "Splines").
//!
//! Every curve is held as rational Bézier pieces whose control points are homogeneous,
//! (w·x, w·y, w): one de Casteljau subdivision then serves the polynomial curves of G5 and
//! G5.1 (all weights 1) and the rational pieces of a G5.2 NURBS alike. A NURBS becomes one
//! piece per knot span, each piece's control points being values of the curve's blossom
//! (its polar form), computed by de Boor's recurrence with a separate argument at each level.
//!
//! Flattening halves a piece's parameter interval until every control point of the half lies
//! within the tolerance of the chord that joins the half's two ends. A curve whose weights
//! are all positive stays inside the convex hull of its control points, and every point of
//! that hull lies within the tolerance of the chord when its corners do: so the whole half
//! of the curve is then within the tolerance of its chord. The chord ends are points of the
//! curve (de Casteljau's split points are), each given with its parameter.

/// A homogeneous control point: (w·x, w·y, w).
type Hom = [f64; 3];

/// Deeper than this, a half is taken as its chord whatever its hull (2⁻⁵² of its piece's
/// parameter interval: the parameter itself cannot be halved further in f64).
const MAX_DEPTH: u32 = 52;

/// One rational Bézier piece of a curve, over the interval `[u0, u1]` of the curve's own
/// parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// The control points, homogeneous; the degree is their number less one.
    pub hom: Vec<Hom>,
    /// The curve's parameter at the piece's start.
    pub u0: f64,
    /// The curve's parameter at the piece's end.
    pub u1: f64,
}

/// The end of one chord: a point of the curve and the curve's parameter there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChordEnd {
    /// The point, in the plane.
    pub at: [f64; 2],
    /// The curve's parameter at it.
    pub u: f64,
}

/// A curve needs more chords than the limit allows within its tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooManyChords;

/// The polynomial Bézier curve of `points` (a G5 cubic or a G5.1 quadratic), over [0, 1].
pub fn bezier(points: &[[f64; 2]]) -> Piece {
    Piece {
        hom: points.iter().map(|p| [p[0], p[1], 1.0]).collect(),
        u0: 0.0,
        u1: 1.0,
    }
}

/// LinuxCNC's knot vector for `count` control points and `order` (degree + 1): clamped and
/// uniform, `order` zeros, then 1, 2, … and `order` times the last value, `count − order + 1`.
/// The curve's parameter runs from 0 to that last value; each unit is one piece.
pub fn knots(count: usize, order: usize) -> Vec<f64> {
    let last = (count + 1).saturating_sub(order) as f64;
    (0..count + order)
        .map(|i| {
            if i < order {
                0.0
            } else if i < count {
                (i + 1 - order) as f64
            } else {
                last
            }
        })
        .collect()
}

/// The NURBS of `points` with `weights` (all greater than 0) and `order` (2 or more, at most
/// the number of points) over LinuxCNC's knots ([`knots`]), as one rational Bézier piece per
/// knot span, in order.
pub fn nurbs(points: &[[f64; 2]], weights: &[f64], order: usize) -> Vec<Piece> {
    let n = points.len();
    if order < 2 || n < order || weights.len() != n {
        return Vec::new();
    }
    let t = knots(n, order);
    let p = order - 1;
    let hom: Vec<Hom> = points
        .iter()
        .zip(weights)
        .map(|(q, &w)| [q[0] * w, q[1] * w, w])
        .collect();
    (p..n)
        .map(|j| {
            let (a, b) = (t[j], t[j + 1]);
            let mut args = vec![a; p];
            let mut pts = Vec::with_capacity(p + 1);
            for m in 0..=p {
                if m > 0 {
                    args[p - m] = b;
                }
                pts.push(blossom(&hom[j - p..=j], &t, j, &args));
            }
            Piece {
                hom: pts,
                u0: a,
                u1: b,
            }
        })
        .collect()
}

/// The blossom of the NURBS at `args` (one per degree) over knot span `j`, from the span's
/// control points `d` (points j − p … j): de Boor's recurrence, level r using `args[r − 1]`.
fn blossom(d: &[Hom], t: &[f64], j: usize, args: &[f64]) -> Hom {
    let p = args.len();
    let mut d = d.to_vec();
    for r in 1..=p {
        let u = args[r - 1];
        for i in (r..=p).rev() {
            let g = j - p + i;
            let alpha = (u - t[g]) / (t[g + p + 1 - r] - t[g]);
            d[i] = lerp(d[i - 1], d[i], alpha);
        }
    }
    d[p]
}

fn lerp(a: Hom, b: Hom, t: f64) -> Hom {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

/// A homogeneous point in the plane.
fn point(h: Hom) -> [f64; 2] {
    [h[0] / h[2], h[1] / h[2]]
}

/// The distance from `q` to the segment from `a` to `b`.
pub fn to_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let s = if len2 > 0.0 {
        (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q[0] - a[0] - s * dx).hypot(q[1] - a[1] - s * dy)
}

/// Whether the piece with control points `h` lies within `tol` of the chord joining its ends.
///
/// Its points are convex combinations of the control points (the weights are positive), so
/// the piece is within the largest distance of a control point from the chord. When every
/// control point also projects onto the chord (not beyond its ends) and all weights are equal
/// (a polynomial piece of degree n), the two end points' shares are at least 2·2⁻ⁿ of every
/// point of the curve (at its middle), which have no distance: the bound is then
/// (1 − 2¹⁻ⁿ) times the largest distance from the chord's line (½ for a quadratic).
fn flat(h: &[Hom], tol: f64) -> bool {
    let n = h.len() - 1;
    let (a, b) = (point(h[0]), point(h[n]));
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    let polynomial = h.iter().all(|c| c[2] == h[0][2]);
    if len > 0.0 && polynomial {
        let mut within = true;
        let mut most: f64 = 0.0;
        for &c in &h[1..n] {
            let q = point(c);
            let (qx, qy) = (q[0] - a[0], q[1] - a[1]);
            let along = (qx * dx + qy * dy) / (len * len);
            within &= (0.0..=1.0).contains(&along);
            most = most.max((qx * dy - qy * dx).abs() / len);
        }
        if within {
            return most * (1.0 - 0.5f64.powi(n as i32 - 1)) <= tol;
        }
    }
    h[1..n].iter().all(|&c| to_segment(point(c), a, b) <= tol)
}

/// De Casteljau's split of a piece at the middle of its parameter interval.
fn halves(h: &[Hom]) -> (Vec<Hom>, Vec<Hom>) {
    let mut work = h.to_vec();
    let n = work.len();
    let mut left = Vec::with_capacity(n);
    let mut right = Vec::with_capacity(n);
    left.push(work[0]);
    right.push(work[n - 1]);
    for level in 1..n {
        for i in 0..n - level {
            work[i] = lerp(work[i], work[i + 1], 0.5);
        }
        left.push(work[0]);
        right.push(work[n - 1 - level]);
    }
    right.reverse();
    (left, right)
}

/// The chords of `pieces` within `tol` of the curve, in order along it: the end of each
/// chord (the start of the first is the curve's start). More than `max` chords is an error.
pub fn flatten(pieces: &[Piece], tol: f64, max: usize) -> Result<Vec<ChordEnd>, TooManyChords> {
    let mut out = Vec::new();
    let mut stack: Vec<(Vec<Hom>, f64, f64, u32)> = Vec::new();
    for piece in pieces {
        if piece.hom.len() < 2 {
            continue;
        }
        stack.push((piece.hom.clone(), piece.u0, piece.u1, 0));
        while let Some((h, a, b, depth)) = stack.pop() {
            if depth >= MAX_DEPTH || flat(&h, tol) {
                if out.len() == max {
                    return Err(TooManyChords);
                }
                out.push(ChordEnd {
                    at: point(h[h.len() - 1]),
                    u: b,
                });
                continue;
            }
            let mid = 0.5 * (a + b);
            let (l, r) = halves(&h);
            stack.push((r, mid, b, depth + 1));
            stack.push((l, a, mid, depth + 1));
        }
    }
    Ok(out)
}
