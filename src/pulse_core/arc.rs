//! Circular interpolation in any plane, and helices, by integer circle stepping (the
//! "equivalent integer method" the docs allow in place of the Pratt & Whitney
//! chord-and-perpendicular method; docs/pulse-core.md).
//!
//! The circle is stepped in a canonical counter-clockwise frame (u, v) of the arc's plane: the
//! plane's axes in turning order (X→Y for G17, Z→X for G18, Y→Z for G19), a clockwise arc
//! mirrored in v. Each step moves one pulse along the tangent direction (−v, u): the candidates
//! are the u step, the v step and the diagonal step toward the tangent, and the one that keeps
//! the residual F = u² + v² − R² smallest in magnitude is taken (a Bresenham-style digital
//! differential analyser, all in integers). Every step strictly advances the angle, so quadrant
//! crossings are counted exactly; once the arc has made the crossings its end needs, the end
//! radius replaces the start radius as the reference, and when the end is within one step (or
//! the angle has reached the end's) the last pulses go straight to the end point, which is thus
//! hit exactly. Full circles (start = end) make four crossings.
//!
//! A helix adds pulses of the plane's normal axis, spread over the turn by angle: the k-th of
//! N normal pulses is taken when the circle point's angle passes (k − ½)/N of the sweep, each as
//! its own step between circle steps, so the normal axis is within half a pulse of where the
//! true helix has it at the angle the tool stands at; the last ones are taken before the
//! circle's end, so the end point is exact.

use crate::block::Plane;

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

/// The integer circle stepper in the canonical frame, one pulse step at a time.
#[derive(Clone, Debug)]
struct Circle {
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
    /// Clockwise arc: canonical v is the plane's −v.
    mirror: bool,
    /// 1 / start radius, for the path length of a step.
    inv_r: f64,
}

/// The most start and end radii may differ, pulses: the translator's rounding (up to 2), and
/// the spiral arcs LinuxCNC accepts from G-code (docs/gcode.md "Arcs"), which the stepper
/// turns into the end radius on the way, every point between the two radii.
pub const MAX_RADIUS_DIFF: i64 = 30;

/// One step of an arc: the pulses of X, Y and Z (−1, 0, +1) and the path length it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcStep {
    /// X pulse direction, 0 for none.
    pub dx: i8,
    /// Y pulse direction, 0 for none.
    pub dy: i8,
    /// Z pulse direction, 0 for none.
    pub dz: i8,
    /// Length along the path, pulses. In a plane: R·Δθ = (u·dv − v·du) / R, so that the steps
    /// of an arc add up to its true length (a straight step to the end point counts its own
    /// length). On a helix: the step's share of the helix length, by angle.
    pub ds: f64,
}

/// A step of the canonical circle: the pulses of u and v in the plane's turning order.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PlaneStep {
    du: i8,
    dv: i8,
    ds: f64,
}

/// Why an arc block cannot be run.
#[derive(Clone, Debug, PartialEq)]
pub enum ArcError {
    /// The start point is on (or next to) the centre.
    TooSmall,
    /// The radius is beyond what the stepper handles.
    TooLarge,
    /// Start and end radii differ by more than [`MAX_RADIUS_DIFF`] pulses.
    EndNotOnCircle {
        /// Start radius, pulses.
        r_start: f64,
        /// End radius, pulses.
        r_end: f64,
    },
}

impl Circle {
    /// A circle arc from `rel_start` to `rel_end` (relative to the centre, in turning order).
    fn new(rel_start: [i64; 2], rel_end: [i64; 2], ccw: bool) -> Result<Circle, ArcError> {
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
        if (rs - re).abs() > MAX_RADIUS_DIFF as f64 {
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
        let mut st = Circle {
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

    /// The axis points at ±R the arc passes, in turning order relative to the centre.
    fn extremes(&self, r: i64) -> Vec<[i64; 2]> {
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

    /// The next step in turning order, or `None` at the end point.
    #[inline]
    fn next_step(&mut self) -> Option<PlaneStep> {
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
        let step = PlaneStep {
            du: sx,
            dv: sy,
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

    fn straight(&mut self, dx: i64, dy: i64) -> PlaneStep {
        let (sx, sy) = self.apply(dx, dy);
        PlaneStep {
            du: sx,
            dv: sy,
            ds: ((dx * dx + dy * dy) as f64).sqrt(),
        }
    }

    /// The angle of the current point in the canonical frame (it grows along the arc), radians.
    fn angle(&self) -> f64 {
        (self.y as f64).atan2(self.x as f64)
    }

    /// The sweep from the start to the end in the canonical frame, radians in (0, 2π], from the
    /// crossings the arc makes.
    fn sweep(&self) -> f64 {
        use std::f64::consts::TAU;
        let a0 = self.angle();
        let a1 = (self.ey as f64).atan2(self.ex as f64);
        let d = (a1 - a0).rem_euclid(TAU);
        if self.needed == 4 && d < 1e-12 {
            TAU
        } else if self.needed == 0 && d > std::f64::consts::PI {
            // An end a pulse behind the start on the same quadrant: no turn at all.
            0.0
        } else {
            d
        }
    }

    fn apply(&mut self, dx: i64, dy: i64) -> (i8, i8) {
        self.x += dx;
        self.y += dy;
        let m = if self.mirror { -1 } else { 1 };
        (dx as i8, (dy * m) as i8)
    }
}

/// The spreading of the normal axis's pulses over a helix, by angle.
#[derive(Clone, Debug)]
struct Helix {
    /// Normal axis and its direction.
    axis: usize,
    dir: i8,
    /// Normal pulses in all and taken.
    total: u64,
    taken: u64,
    /// The circle's sweep, radians, and its angle at the start.
    sweep: f64,
    a0: f64,
    /// The circle point's angle progress from the start (unwrapped), radians.
    done: f64,
    /// A circle step taken from the stepper but not yet handed out, with its angle progress.
    pending: Option<(PlaneStep, f64)>,
    circle_done: bool,
    /// Path progress (0..1) already handed out, and the helix length, pulses.
    param: f64,
    length: f64,
}

/// An arc or helix stepper for one block, in machine axes.
#[derive(Clone, Debug)]
pub struct ArcStepper {
    circle: Circle,
    /// The machine axes of u and v.
    map: [usize; 2],
    helix: Option<Box<Helix>>,
}

impl ArcStepper {
    /// An arc in the XY plane from the start (relative to the centre `rel_start`) to `rel_end`,
    /// both in machine axes relative to the centre; `ccw` for G03.
    pub fn new(rel_start: [i64; 2], rel_end: [i64; 2], ccw: bool) -> Result<ArcStepper, ArcError> {
        ArcStepper::in_plane(Plane::XY, rel_start, rel_end, ccw, 0)
    }

    /// An arc in `plane` from `rel_start` to `rel_end` (relative to the centre, in the plane's
    /// two axes in X Y Z order, as `Block::center`), `ccw` for G03, with `normal` pulses along
    /// the plane's normal axis (a helix when not 0).
    pub fn in_plane(
        plane: Plane,
        rel_start: [i64; 2],
        rel_end: [i64; 2],
        ccw: bool,
        normal: i64,
    ) -> Result<ArcStepper, ArcError> {
        let map = plane.turn_axes();
        let [a0, _, axis] = plane.axes();
        // Centre components come in X Y Z order; the circle wants turning order.
        let swap = map[0] != a0;
        let order = |p: [i64; 2]| if swap { [p[1], p[0]] } else { p };
        let circle = Circle::new(order(rel_start), order(rel_end), ccw)?;
        if normal.abs() > 100_000_000 {
            return Err(ArcError::TooLarge);
        }
        let helix = if normal != 0 {
            let sweep = circle.sweep();
            let mut dry = circle.clone();
            let mut s = 0.0;
            while let Some(st) = dry.next_step() {
                s += st.ds;
            }
            let total = normal.unsigned_abs();
            Some(Box::new(Helix {
                axis,
                dir: normal.signum() as i8,
                total,
                taken: 0,
                sweep,
                a0: circle.angle(),
                done: 0.0,
                pending: None,
                circle_done: false,
                param: 0.0,
                length: s.hypot(total as f64),
            }))
        } else {
            None
        };
        Ok(ArcStepper { circle, map, helix })
    }

    /// The axis points at ±R (in the arc's plane) the arc passes, in machine axes relative to
    /// the centre (0 along the normal), for the travel check.
    pub fn extremes(&self, r: i64) -> Vec<[i64; 3]> {
        self.circle
            .extremes(r)
            .into_iter()
            .map(|p| {
                let mut v = [0; 3];
                v[self.map[0]] = p[0];
                v[self.map[1]] = p[1];
                v
            })
            .collect()
    }

    fn machine_step(&self, p: PlaneStep, ds: f64) -> ArcStep {
        let mut d = [0i8; 3];
        d[self.map[0]] = p.du;
        d[self.map[1]] = p.dv;
        ArcStep {
            dx: d[0],
            dy: d[1],
            dz: d[2],
            ds,
        }
    }

    /// The next step in machine axes, or `None` at the end point.
    #[inline]
    pub fn next_step(&mut self) -> Option<ArcStep> {
        if self.helix.is_none() {
            let p = self.circle.next_step()?;
            return Some(self.machine_step(p, p.ds));
        }
        self.helix_step()
    }

    fn helix_step(&mut self) -> Option<ArcStep> {
        use std::f64::consts::{PI, TAU};
        let h = self.helix.as_mut()?;
        if h.pending.is_none() && !h.circle_done {
            match self.circle.next_step() {
                Some(p) => {
                    let raw = (self.circle.angle() - h.a0).rem_euclid(TAU);
                    let turns = ((h.done - raw) / TAU).round().max(0.0);
                    let mut a = raw + turns * TAU;
                    if a < h.done - PI {
                        a += TAU;
                    }
                    h.pending = Some((p, a));
                }
                None => h.circle_done = true,
            }
        }
        let due = if h.taken < h.total {
            let at = (h.taken as f64 + 0.5) / h.total as f64 * h.sweep;
            match h.pending {
                Some((_, a)) => at <= a,
                None => true,
            }
        } else {
            false
        };
        if due {
            h.taken += 1;
            let at = if h.pending.is_some() && h.sweep > 0.0 {
                ((h.taken as f64 - 0.5) / h.total as f64).min(1.0)
            } else {
                1.0
            };
            let q = at.max(h.param);
            let ds = (q - h.param) * h.length;
            h.param = q;
            let mut d = [0i8; 3];
            d[h.axis] = h.dir;
            return Some(ArcStep {
                dx: d[0],
                dy: d[1],
                dz: d[2],
                ds,
            });
        }
        let (p, a) = h.pending.take()?;
        h.done = h.done.max(a);
        let q = if h.sweep <= 0.0 {
            1.0
        } else {
            (a / h.sweep).clamp(h.param, 1.0)
        };
        let ds = (q - h.param) * h.length;
        h.param = q;
        Some(self.machine_step(p, ds))
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
            ArcStepper::new([100, 0], [0, 131], true),
            Err(ArcError::EndNotOnCircle { .. })
        ));
    }

    #[test]
    fn a_spiral_within_the_limit_ends_exactly_between_its_radii() {
        for (s, e, ccw) in [
            ([1000, 0], [0, 1030], true),
            ([1000, 0], [0, -970], false),
            ([0, 500], [-470, 10], true),
            ([700, 0], [729, 0], true),
        ] {
            let pts = run(s, e, ccw);
            assert_eq!(*pts.last().unwrap(), e);
            let r = |p: [i64; 2]| ((p[0] * p[0] + p[1] * p[1]) as f64).sqrt();
            let (lo, hi) = (r(s).min(r(e)) - 1.0, r(s).max(r(e)) + 1.0);
            for p in &pts {
                assert!(r(*p) >= lo && r(*p) <= hi, "{p:?} of {s:?} -> {e:?}");
            }
        }
    }
}
