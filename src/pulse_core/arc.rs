//! Circular interpolation in the XY plane by integer circle stepping (the "equivalent integer
//! method" the docs allow in place of the Pratt & Whitney chord-and-perpendicular method).
//!
//! The arc is stepped in a canonical counter-clockwise frame (a clockwise arc is mirrored in Y).
//! Each step moves one pulse along the tangent direction (−y, x): the candidates are the
//! X step, the Y step and the diagonal step toward the tangent, and the one that keeps the
//! residual F = x² + y² − R² smallest in magnitude is taken (a Bresenham-style digital
//! differential analyser, all in integers). Every step strictly advances the angle, so quadrant
//! crossings are counted exactly; once the arc has made the crossings its end needs, the end
//! radius replaces the start radius as the reference, and when the end is within one step (or
//! the angle has reached the end's) the last pulses go straight to the end point, which is thus
//! hit exactly. Full circles (start = end) make four crossings.

/// The four quadrants, half-open so that every point but the centre has exactly one:
/// 0: x > 0, y ≥ 0; 1: x ≤ 0, y > 0; 2: x < 0, y ≤ 0; 3: x ≥ 0, y < 0.
fn quadrant(x: i64, y: i64) -> u32 {
    if x > 0 && y >= 0 {
        0
    } else if x <= 0 && y > 0 {
        1
    } else if x < 0 && y <= 0 {
        2
    } else {
        3
    }
}

/// An integer circle stepper, one pulse step at a time.
#[derive(Clone, Debug)]
pub struct ArcStepper {
    /// Current point relative to the centre, canonical (CCW) frame.
    x: i64,
    y: i64,
    /// End point relative to the centre, canonical frame.
    ex: i64,
    ey: i64,
    /// Residual x² + y² − R² against the reference radius in force.
    f: i64,
    /// Squared end radius.
    r2_end: i64,
    /// Quadrant crossings made and needed.
    crossings: u32,
    needed: u32,
    /// Going straight to the end point.
    tail: bool,
    /// Steps left before the safety cap forces the tail.
    cap: u64,
    /// Clockwise arc: canonical Y is machine −Y.
    mirror: bool,
    /// 1 / start radius, for the path length of a step.
    inv_r: f64,
}

/// One step of an arc: the pulses of X and Y (−1, 0, +1) and the path length it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcStep {
    /// X pulse direction, 0 for none.
    pub dx: i8,
    /// Y pulse direction, 0 for none.
    pub dy: i8,
    /// Length along the circle, pulses: R·Δθ = (x·dy − y·dx) / R, so that the steps of an
    /// arc add up to its true length (a straight step to the end point counts its own length).
    pub ds: f64,
}

/// Why an arc block cannot be run.
#[derive(Clone, Debug, PartialEq)]
pub enum ArcError {
    /// The start point is on (or next to) the centre.
    TooSmall,
    /// The radius is beyond what the stepper handles.
    TooLarge,
    /// Start and end radii differ by more than 2 pulses.
    EndNotOnCircle {
        /// Start radius, pulses.
        r_start: f64,
        /// End radius, pulses.
        r_end: f64,
    },
}

impl ArcStepper {
    /// An arc from the start (relative to the centre `rel_start`) to `rel_end`, both in
    /// machine axes relative to the centre; `ccw` for G03.
    pub fn new(rel_start: [i64; 2], rel_end: [i64; 2], ccw: bool) -> Result<ArcStepper, ArcError> {
        let m = if ccw { 1 } else { -1 };
        let (x, y) = (rel_start[0], rel_start[1] * m);
        let (ex, ey) = (rel_end[0], rel_end[1] * m);
        let lim = 100_000_000;
        if [x, y, ex, ey].iter().any(|v| v.abs() > lim) {
            return Err(ArcError::TooLarge);
        }
        let r2 = x * x + y * y;
        let r2_end = ex * ex + ey * ey;
        if r2 < 4 {
            return Err(ArcError::TooSmall);
        }
        let (rs, re) = ((r2 as f64).sqrt(), (r2_end as f64).sqrt());
        if (rs - re).abs() > 2.0 {
            return Err(ArcError::EndNotOnCircle {
                r_start: rs,
                r_end: re,
            });
        }
        let (qs, qe) = (quadrant(x, y), quadrant(ex, ey));
        let mut needed = (qe + 4 - qs) % 4;
        if needed == 0 && ((x, y) == (ex, ey) || x * ey - y * ex < 0) {
            needed = 4;
        }
        let mut st = ArcStepper {
            x,
            y,
            ex,
            ey,
            f: 0,
            r2_end,
            crossings: 0,
            needed,
            tail: false,
            cap: (16.0 * (rs + 2.0)) as u64 + 16,
            mirror: !ccw,
            inv_r: 1.0 / rs,
        };
        if needed == 0 {
            st.f = r2 - r2_end;
        }
        Ok(st)
    }

    /// The number of quadrant boundaries (axis points at ±R) the arc passes, with the axis
    /// point each one passes, in machine axes relative to the centre, for the travel check.
    pub fn extremes(&self, r: i64) -> Vec<[i64; 2]> {
        let m = if self.mirror { -1 } else { 1 };
        let q0 = quadrant(self.x, self.y);
        (0..self.needed)
            .map(|k| {
                let p = match (q0 + k) % 4 {
                    0 => [0, r],
                    1 => [-r, 0],
                    2 => [0, -r],
                    _ => [r, 0],
                };
                [p[0], p[1] * m]
            })
            .collect()
    }

    /// The next step in machine axes, or `None` at the end point.
    #[inline]
    pub fn next_step(&mut self) -> Option<ArcStep> {
        if self.crossings >= self.needed {
            if (self.x, self.y) == (self.ex, self.ey) {
                return None;
            }
            let (dx, dy) = (self.ex - self.x, self.ey - self.y);
            if self.tail
                || self.crossings > self.needed
                || (dx.abs() <= 1 && dy.abs() <= 1)
                || self.x * self.ey - self.y * self.ex <= 0
            {
                self.tail = true;
                return Some(self.straight(dx.signum(), dy.signum()));
            }
        }
        if self.cap == 0 {
            self.crossings = self.needed.max(self.crossings);
            self.tail = true;
            let (dx, dy) = (self.ex - self.x, self.ey - self.y);
            if (dx, dy) == (0, 0) {
                return None;
            }
            return Some(self.straight(dx.signum(), dy.signum()));
        }
        self.cap -= 1;
        let (x, y, f) = (self.x, self.y, self.f);
        let sx = -y.signum();
        let sy = x.signum();
        // F after a step (dx, dy): F + 2x·dx + dx² + 2y·dy + dy².
        let fx = f + 2 * x * sx + sx * sx;
        let fy = f + 2 * y * sy + sy * sy;
        let fd = fx + 2 * y * sy + sy * sy;
        let (mut best, mut bf) = ((0i64, 0i64), i64::MAX);
        if sx != 0 && sy != 0 && fd.abs() < bf {
            best = (sx, sy);
            bf = fd.abs();
        }
        if sx != 0 && fx.abs() < bf {
            best = (sx, 0);
            bf = fx.abs();
        }
        if sy != 0 && fy.abs() < bf {
            best = (0, sy);
        }
        let q = quadrant(x, y);
        let turn = (x * best.1 - y * best.0) as f64 * self.inv_r;
        let (sx, sy) = self.apply(best.0, best.1);
        let step = ArcStep {
            dx: sx,
            dy: sy,
            ds: turn,
        };
        self.f = match best {
            (a, 0) if a != 0 => fx,
            (0, _) => fy,
            _ => fd,
        };
        if quadrant(self.x, self.y) != q {
            self.crossings += 1;
            if self.crossings == self.needed {
                // The final quadrant: aim at the end point's radius.
                self.f = self.x * self.x + self.y * self.y - self.r2_end;
            }
        }
        Some(step)
    }

    fn straight(&mut self, dx: i64, dy: i64) -> ArcStep {
        let (sx, sy) = self.apply(dx, dy);
        ArcStep {
            dx: sx,
            dy: sy,
            ds: ((dx * dx + dy * dy) as f64).sqrt(),
        }
    }

    fn apply(&mut self, dx: i64, dy: i64) -> (i8, i8) {
        self.x += dx;
        self.y += dy;
        let m = if self.mirror { -1 } else { 1 };
        (dx as i8, (dy * m) as i8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(s: [i64; 2], e: [i64; 2], ccw: bool) -> Vec<[i64; 2]> {
        let mut st = ArcStepper::new(s, e, ccw).unwrap();
        let mut p = s;
        let mut v = vec![p];
        while let Some(a) = st.next_step() {
            p = [p[0] + a.dx as i64, p[1] + a.dy as i64];
            v.push(p);
            assert!(v.len() < 10_000_000);
        }
        v
    }

    #[test]
    fn full_circle_ends_on_start_and_stays_on_circle() {
        for ccw in [true, false] {
            let pts = run([1000, 0], [1000, 0], ccw);
            assert_eq!(*pts.last().unwrap(), [1000, 0]);
            assert!(pts.len() > 5000);
            for p in &pts {
                let r = ((p[0] * p[0] + p[1] * p[1]) as f64).sqrt();
                assert!((r - 1000.0).abs() <= 1.0, "{p:?}");
            }
        }
    }

    #[test]
    fn quarter_arc_direction() {
        let pts = run([100, 0], [0, 100], true);
        assert!(pts.iter().all(|p| p[0] >= 0 && p[1] >= 0));
        let pts = run([100, 0], [0, 100], false);
        assert!(pts.iter().any(|p| p[1] < -50));
        assert_eq!(*pts.last().unwrap(), [0, 100]);
    }

    #[test]
    fn refuses_end_off_circle() {
        assert!(matches!(
            ArcStepper::new([100, 0], [0, 110], true),
            Err(ArcError::EndNotOnCircle { .. })
        ));
    }
}
