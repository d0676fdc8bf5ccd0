//! The workpiece on the table (docs/gcode.md "Probing"): boxes of stock in machine
//! coordinates, and the one geometric question probing asks of them: where a stylus moving in
//! a straight line first touches the stock, or leaves it.
//!
//! The stylus is a sphere of the tool's radius centred on the tool tip (the gauge line less
//! the tool's length), or a point with no tool. It touches a box when the distance from its
//! centre to the box is at most its radius: the box grown by the radius (a box with rounded
//! edges and corners). Along a straight move the squared distance to one box is a convex
//! function of the way along, quadratic between the points where a coordinate crosses a face's
//! plane, so the first point of contact is found exactly, piece by piece. The machine's own
//! check (`pulse_core`) asks [`Workpiece::contact`] at every step of the probe move.
//!
//! Everything here is plain arithmetic on the numbers given: machine millimetres for the
//! interpreter's simulation, whole pulses (as floats) for the pulse core.

/// One box of stock, axis-aligned: `min` and `max` corners, X Y Z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    /// The lowest X, Y and Z of the box.
    pub min: [f64; 3],
    /// The highest X, Y and Z of the box.
    pub max: [f64; 3],
}

impl Cuboid {
    /// The box between two corners, in any order on each axis.
    pub fn new(a: [f64; 3], b: [f64; 3]) -> Cuboid {
        Cuboid {
            min: [a[0].min(b[0]), a[1].min(b[1]), a[2].min(b[2])],
            max: [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])],
        }
    }

    /// The squared distance from `p` to the box (0 inside or on it).
    pub fn dist2(&self, p: [f64; 3]) -> f64 {
        (0..3)
            .map(|a| {
                let d = (self.min[a] - p[a]).max(p[a] - self.max[a]).max(0.0);
                d * d
            })
            .sum()
    }

    /// The box with each coordinate multiplied by `k` (millimetres to pulses: `1 / pulse`),
    /// rounded to whole units.
    pub fn scaled(&self, k: f64) -> Cuboid {
        let s = |v: [f64; 3]| [(v[0] * k).round(), (v[1] * k).round(), (v[2] * k).round()];
        Cuboid {
            min: s(self.min),
            max: s(self.max),
        }
    }

    /// The first fraction t of the way from `a` to `b` (0 to 1) at which a sphere of radius
    /// `r` centred on the moving point touches the box; `None` if it never does.
    pub fn first_touch(&self, a: [f64; 3], b: [f64; 3], r: f64) -> Option<f64> {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let r2 = r * r;
        // The points where a coordinate crosses a face's plane cut the way into pieces on
        // which each coordinate stays below, inside or above the box's extent.
        let mut cuts = [0.0; 8];
        let mut n = 0;
        cuts[n] = 0.0;
        n += 1;
        for k in 0..3 {
            if d[k] != 0.0 {
                for edge in [self.min[k], self.max[k]] {
                    let t = (edge - a[k]) / d[k];
                    if t > 0.0 && t < 1.0 {
                        cuts[n] = t;
                        n += 1;
                    }
                }
            }
        }
        cuts[n] = 1.0;
        n += 1;
        let cuts = &mut cuts[..n];
        cuts.sort_by(f64::total_cmp);
        for w in cuts.windows(2) {
            let (s, e) = (w[0], w[1]);
            if e < s {
                continue;
            }
            // On this piece the squared distance is A t² + B t + C: the coordinates outside
            // the box's extent at the piece's middle contribute (a + d t − face)².
            let m = 0.5 * (s + e);
            let (mut qa, mut qb, mut qc) = (0.0, 0.0, -r2);
            for k in 0..3 {
                let p = a[k] + d[k] * m;
                let face = if p < self.min[k] {
                    self.min[k]
                } else if p > self.max[k] {
                    self.max[k]
                } else {
                    continue;
                };
                let c = a[k] - face;
                qa += d[k] * d[k];
                qb += 2.0 * c * d[k];
                qc += c * c;
            }
            let q = |t: f64| (qa * t + qb) * t + qc;
            if q(s) <= 0.0 {
                return Some(s);
            }
            if qa == 0.0 {
                continue;
            }
            let mut disc = qb * qb - 4.0 * qa * qc;
            if disc < 0.0 {
                // A tangent (a graze) lands here within rounding: it touches at one point.
                if disc < -1e-9 * qb * qb {
                    continue;
                }
                disc = 0.0;
            }
            // The smaller root, computed without cancellation.
            let sq = disc.sqrt();
            let h = -0.5 * (qb + qb.signum() * sq);
            let (r1, r2) = (h / qa, if h != 0.0 { qc / h } else { h / qa });
            let t = r1.min(r2);
            if t >= s && t <= e {
                return Some(t);
            }
        }
        None
    }
}

/// Where a probe move stops, as a fraction of the way from its start to its end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Touch {
    /// The stylus is already in the state the probe seeks at the start (touching, for G38.2
    /// and G38.3; clear of the stock, for G38.4 and G38.5).
    AtStart,
    /// It reaches that state at this fraction of the way (0 < t ≤ 1).
    At(f64),
    /// It never does on the way.
    Never,
}

/// The stock on the table: boxes in machine coordinates of the tool tip (a tool of length 0
/// at the gauge line), mm.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Workpiece {
    /// The boxes; the stock is their union.
    pub boxes: Vec<Cuboid>,
}

impl Workpiece {
    /// Whether a stylus of radius `r` centred on `c` touches the stock.
    pub fn contact(&self, c: [f64; 3], r: f64) -> bool {
        let r2 = r * r;
        self.boxes.iter().any(|b| b.dist2(c) <= r2)
    }

    /// Where a stylus of radius `r` moving in a straight line from `a` to `b` first touches
    /// the stock (`toward`: G38.2, G38.3), or first leaves it (G38.4, G38.5). Leaving means
    /// leaving every box: the stylus slides from one box onto a box that touches it without
    /// losing contact.
    pub fn probe(&self, a: [f64; 3], b: [f64; 3], r: f64, toward: bool) -> Touch {
        let in_contact = self.contact(a, r);
        if toward {
            if in_contact {
                return Touch::AtStart;
            }
            return match self
                .boxes
                .iter()
                .filter_map(|x| x.first_touch(a, b, r))
                .min_by(f64::total_cmp)
            {
                Some(t) => Touch::At(t),
                None => Touch::Never,
            };
        }
        if !in_contact {
            return Touch::AtStart;
        }
        // Each box is touched on one stretch of the way (the squared distance is convex);
        // contact holds from the start to the end of the chain of stretches that begins there.
        let spans: Vec<(f64, f64)> = self
            .boxes
            .iter()
            .filter_map(|x| {
                let t0 = x.first_touch(a, b, r)?;
                let t1 = 1.0 - x.first_touch(b, a, r)?;
                Some((t0, t1))
            })
            .collect();
        let mut end = 0.0;
        loop {
            let further = spans
                .iter()
                .filter(|&&(t0, t1)| t0 <= end && t1 > end)
                .map(|&(_, t1)| t1)
                .fold(end, f64::max);
            if further <= end {
                break;
            }
            end = further;
        }
        if end >= 1.0 {
            Touch::Never
        } else {
            Touch::At(end)
        }
    }
}

/// The point `t` of the way from `a` to `b`.
pub fn along(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 100 × 60 × 40 block, X 0..100, Y 0..60, Z −40..0.
    fn block() -> Workpiece {
        Workpiece {
            boxes: vec![Cuboid::new([0.0, 0.0, -40.0], [100.0, 60.0, 0.0])],
        }
    }

    fn stop(w: &Workpiece, a: [f64; 3], b: [f64; 3], r: f64, toward: bool) -> Option<[f64; 3]> {
        match w.probe(a, b, r, toward) {
            Touch::At(t) => Some(along(a, b, t)),
            _ => None,
        }
    }

    fn near(p: Option<[f64; 3]>, want: [f64; 3]) {
        let p = p.unwrap_or_else(|| panic!("no touch, want {want:?}"));
        for k in 0..3 {
            assert!((p[k] - want[k]).abs() < 1e-9, "{p:?} vs {want:?}");
        }
    }

    #[test]
    fn a_point_stylus_touches_every_face_where_its_line_crosses_it() {
        let w = block();
        // Down onto the top, up onto the bottom.
        near(
            stop(&w, [50.0, 30.0, 20.0], [50.0, 30.0, -20.0], 0.0, true),
            [50.0, 30.0, 0.0],
        );
        near(
            stop(&w, [50.0, 30.0, -90.0], [50.0, 30.0, -20.0], 0.0, true),
            [50.0, 30.0, -40.0],
        );
        // From each side.
        near(
            stop(&w, [-30.0, 30.0, -10.0], [50.0, 30.0, -10.0], 0.0, true),
            [0.0, 30.0, -10.0],
        );
        near(
            stop(&w, [130.0, 30.0, -10.0], [50.0, 30.0, -10.0], 0.0, true),
            [100.0, 30.0, -10.0],
        );
        near(
            stop(&w, [50.0, -5.0, -10.0], [50.0, 10.0, -10.0], 0.0, true),
            [50.0, 0.0, -10.0],
        );
        near(
            stop(&w, [50.0, 75.0, -10.0], [50.0, 10.0, -10.0], 0.0, true),
            [50.0, 60.0, -10.0],
        );
        // Slanting onto the top: z reaches 0 half way.
        near(
            stop(&w, [10.0, 10.0, 10.0], [30.0, 20.0, -10.0], 0.0, true),
            [20.0, 15.0, 0.0],
        );
    }

    #[test]
    fn a_ball_touches_a_radius_before_each_face() {
        let w = block();
        let r = 2.5;
        near(
            stop(&w, [50.0, 30.0, 20.0], [50.0, 30.0, -20.0], r, true),
            [50.0, 30.0, 2.5],
        );
        near(
            stop(&w, [-30.0, 30.0, -10.0], [50.0, 30.0, -10.0], r, true),
            [-2.5, 30.0, -10.0],
        );
        near(
            stop(&w, [130.0, 30.0, -10.0], [50.0, 30.0, -10.0], r, true),
            [102.5, 30.0, -10.0],
        );
        near(
            stop(&w, [50.0, -20.0, -10.0], [50.0, 10.0, -10.0], r, true),
            [50.0, -2.5, -10.0],
        );
        near(
            stop(&w, [50.0, 99.0, -10.0], [50.0, 10.0, -10.0], r, true),
            [50.0, 62.5, -10.0],
        );
        near(
            stop(&w, [50.0, 30.0, -90.0], [50.0, 30.0, 0.0], r, true),
            [50.0, 30.0, -42.5],
        );
    }

    #[test]
    fn a_ball_meets_an_edge_and_a_corner_on_their_rounding() {
        let w = block();
        // Down past the edge X = 100 (the top's), 3 mm beside it: the ball (r 5) meets the edge
        // where its centre is 5 from it, 4 above the top (3² + 4² = 5²).
        near(
            stop(&w, [103.0, 30.0, 20.0], [103.0, 30.0, -20.0], 5.0, true),
            [103.0, 30.0, 4.0],
        );
        // Down past the corner X 100 Y 60 Z 0, 3 and 4 mm beside it in X and Y (5 away in
        // the plane), with r 13: it meets the corner 12 above (5² + 12² = 13²).
        near(
            stop(&w, [103.0, 64.0, 50.0], [103.0, 64.0, -20.0], 13.0, true),
            [103.0, 64.0, 12.0],
        );
        // Along X, 3 beside the face Y = 60 and 4 above the top: the nearest point of the
        // block is its corner X 0 Y 60 Z 0 (distance √(x² + 3² + 4²) > 5) until x reaches 0,
        // then the top edge, exactly 5 away: the ball (r 5) grazes it from x = 0 on.
        near(
            stop(&w, [-20.0, 63.0, 4.0], [50.0, 63.0, 4.0], 5.0, true),
            [0.0, 63.0, 4.0],
        );
    }

    #[test]
    fn grazing_touches_and_missing_by_a_hair_does_not() {
        let w = block();
        // Along the top face exactly (a point stylus): touches where it reaches the block.
        near(
            stop(&w, [-10.0, 30.0, 0.0], [50.0, 30.0, 0.0], 0.0, true),
            [0.0, 30.0, 0.0],
        );
        // A ball of radius 2 passing 2 above the top: it grazes the top edge X = 0.
        near(
            stop(&w, [-10.0, 30.0, 2.0], [50.0, 30.0, 2.0], 2.0, true),
            [0.0, 30.0, 2.0],
        );
        // A hair higher: it never touches.
        assert_eq!(
            w.probe([-10.0, 30.0, 2.001], [50.0, 30.0, 2.001], 2.0, true),
            Touch::Never
        );
        // Down beside the face X = 100, 10 away: a ball of radius 10 grazes the top edge
        // as it comes level with the top; one a hair smaller never touches.
        near(
            stop(&w, [110.0, 30.0, 20.0], [110.0, 30.0, -60.0], 10.0, true),
            [110.0, 30.0, 0.0],
        );
        assert_eq!(
            w.probe([110.0, 30.0, 20.0], [110.0, 30.0, -60.0], 9.999, true),
            Touch::Never
        );
    }

    #[test]
    fn missing_starting_inside_and_short_moves() {
        let w = block();
        // Stops short of the top.
        assert_eq!(
            w.probe([50.0, 30.0, 20.0], [50.0, 30.0, 1.0], 0.0, true),
            Touch::Never
        );
        // Beside the block.
        assert_eq!(
            w.probe([150.0, 30.0, 20.0], [150.0, 30.0, -60.0], 1.0, true),
            Touch::Never
        );
        // Already touching (on the top) or inside: nothing to seek.
        assert_eq!(
            w.probe([50.0, 30.0, 0.0], [50.0, 30.0, -5.0], 0.0, true),
            Touch::AtStart
        );
        assert_eq!(
            w.probe([50.0, 30.0, -5.0], [50.0, 30.0, -15.0], 0.0, true),
            Touch::AtStart
        );
        // Ending exactly on the face touches at the end.
        assert_eq!(
            w.probe([50.0, 30.0, 10.0], [50.0, 30.0, 0.0], 0.0, true),
            Touch::At(1.0)
        );
        // A move of zero length.
        assert_eq!(
            w.probe([50.0, 30.0, 10.0], [50.0, 30.0, 10.0], 0.0, true),
            Touch::Never
        );
    }

    #[test]
    fn leaving_contact_finds_where_the_stylus_comes_free() {
        let w = block();
        // Up off the top from inside it: free at the top face.
        near(
            stop(&w, [50.0, 30.0, -5.0], [50.0, 30.0, 10.0], 0.0, false),
            [50.0, 30.0, 0.0],
        );
        // A ball resting on the top, moved sideways off the edge X = 100: free as soon as its
        // centre passes over the edge (beyond it the edge is farther than r).
        near(
            stop(&w, [90.0, 30.0, 3.0], [120.0, 30.0, 3.0], 3.0, false),
            [100.0, 30.0, 3.0],
        );
        // Against the side X = 100 and moved up along it: free as its centre rises past the
        // top (above it, the edge is farther than r).
        near(
            stop(&w, [103.0, 30.0, -10.0], [103.0, 30.0, 10.0], 3.0, false),
            [103.0, 30.0, 0.0],
        );
        // Not touching at the start: already clear.
        assert_eq!(
            w.probe([50.0, 30.0, 5.0], [50.0, 30.0, 20.0], 0.0, false),
            Touch::AtStart
        );
        // Still touching at the end.
        assert_eq!(
            w.probe([50.0, 30.0, -5.0], [60.0, 30.0, -5.0], 0.0, false),
            Touch::Never
        );
    }

    #[test]
    fn several_boxes_the_nearest_first_and_contact_kept_across_a_join() {
        let mut w = block();
        // A second block on top of the first, X 40..60, 10 high.
        w.boxes
            .push(Cuboid::new([40.0, 20.0, 0.0], [60.0, 40.0, 10.0]));
        near(
            stop(&w, [50.0, 30.0, 30.0], [50.0, 30.0, -30.0], 0.0, true),
            [50.0, 30.0, 10.0],
        );
        near(
            stop(&w, [20.0, 30.0, 30.0], [20.0, 30.0, -30.0], 0.0, true),
            [20.0, 30.0, 0.0],
        );
        // Sliding along the top of the first into the side of the second (point stylus on
        // the top face): contact never breaks, then it ends inside the second.
        assert_eq!(
            w.probe([10.0, 30.0, 0.0], [45.0, 30.0, 0.0], 0.0, false),
            Touch::Never
        );
        // Up through the second: free at its top.
        near(
            stop(&w, [50.0, 30.0, -5.0], [50.0, 30.0, 30.0], 0.0, false),
            [50.0, 30.0, 10.0],
        );
        assert!(w.contact([50.0, 30.0, 10.0], 0.0));
        assert!(!w.contact([50.0, 30.0, 10.000001], 0.0));
    }
}
