//! One block's motion on a lathe channel (docs/lathe-sim.md "Motion" and "Threads"): a path
//! (line or Z–X arc) followed with a trapezoidal speed along the path, and a thread pass whose
//! position is a function of the spindle encoder. Positions are integer pulses; the last step of
//! a block lands exactly on its end point and no step goes past it.

use crate::lathe::desc::{AxisDesc, LatheDesc};

/// The geometry of a path move.
#[derive(Clone, Debug)]
pub(crate) enum Path {
    /// A straight line, pulses [X, Z].
    Line { start: [i64; 2], end: [i64; 2] },
    /// An arc about `centre` ([X, Z], pulses) of radius `r` from angle `th0` (from +Z towards
    /// +X), sweeping `sweep` radians (positive = counter-clockwise).
    Arc {
        centre: [f64; 2],
        r: f64,
        th0: f64,
        sweep: f64,
        end: [i64; 2],
    },
}

impl Path {
    /// The path length, pulses.
    pub(crate) fn len(&self) -> f64 {
        match self {
            Path::Line { start, end } => {
                let dx = (end[0] - start[0]) as f64;
                let dz = (end[1] - start[1]) as f64;
                dx.hypot(dz)
            }
            Path::Arc { r, sweep, .. } => r * sweep.abs(),
        }
    }

    /// The end point.
    pub(crate) fn end(&self) -> [i64; 2] {
        match self {
            Path::Line { end, .. } | Path::Arc { end, .. } => *end,
        }
    }

    /// The point `s` pulses along the path (the end point exactly at or past the length).
    fn at(&self, s: f64, len: f64) -> [i64; 2] {
        if s >= len {
            return self.end();
        }
        let f = if len > 0.0 { s / len } else { 1.0 };
        match self {
            Path::Line { start, end } => [
                start[0] + ((end[0] - start[0]) as f64 * f).round() as i64,
                start[1] + ((end[1] - start[1]) as f64 * f).round() as i64,
            ],
            Path::Arc {
                centre,
                r,
                th0,
                sweep,
                ..
            } => {
                let th = th0 + sweep * f;
                [
                    (centre[0] + r * th.sin()).round() as i64,
                    (centre[1] + r * th.cos()).round() as i64,
                ]
            }
        }
    }

    /// The extreme points the path reaches (its ends and, for an arc, the quadrant points
    /// inside its sweep), for the travel check.
    pub(crate) fn extremes(&self, start: [i64; 2]) -> Vec<[i64; 2]> {
        let mut pts = vec![start, self.end()];
        if let Path::Arc {
            centre,
            r,
            th0,
            sweep,
            ..
        } = self
        {
            for k in 0..4 {
                let q = k as f64 * std::f64::consts::FRAC_PI_2;
                // The angle of q measured from th0 in the sweep's direction, in [0, 2π).
                let d = if *sweep >= 0.0 { q - th0 } else { th0 - q };
                let d = d.rem_euclid(std::f64::consts::TAU);
                if d <= sweep.abs() {
                    pts.push([
                        (centre[0] + r * q.sin()).round() as i64,
                        (centre[1] + r * q.cos()).round() as i64,
                    ]);
                }
            }
        }
        pts
    }
}

/// Builds the arc from `start` to `end` about `centre` ([X, Z] pulses), or an alarm message if
/// the start and end radii differ by more than `tol` pulses or the radius is zero.
pub(crate) fn arc(
    start: [i64; 2],
    end: [i64; 2],
    centre: [i64; 2],
    ccw: bool,
    tol: f64,
) -> Result<Path, String> {
    let c = [centre[0] as f64, centre[1] as f64];
    let rel = |p: [i64; 2]| [p[0] as f64 - c[0], p[1] as f64 - c[1]];
    let (s, e) = (rel(start), rel(end));
    let (rs, re) = (s[0].hypot(s[1]), e[0].hypot(e[1]));
    if rs < 0.5 {
        return Err("arc: zero radius".to_string());
    }
    if (rs - re).abs() > tol {
        return Err(format!(
            "arc: start radius {rs:.0} and end radius {re:.0} pulses differ by more than {tol:.0}"
        ));
    }
    let th0 = s[0].atan2(s[1]);
    let th1 = e[0].atan2(e[1]);
    let tau = std::f64::consts::TAU;
    let mut sweep = if ccw {
        (th1 - th0).rem_euclid(tau)
    } else {
        -(th0 - th1).rem_euclid(tau)
    };
    if start == end {
        sweep = if ccw { tau } else { -tau };
    }
    Ok(Path::Arc {
        centre: c,
        r: rs,
        th0,
        sweep,
        end,
    })
}

/// A path move being followed: trapezoidal speed along the path.
#[derive(Clone, Debug)]
pub(crate) struct Move {
    /// The geometry.
    pub path: Path,
    /// Length, pulses.
    pub len: f64,
    /// Done so far, pulses along the path.
    pub s: f64,
    /// Current path speed, pulses/s.
    pub v: f64,
    /// Path acceleration, pulses/s².
    pub accel: f64,
    /// The fastest the axes allow along this path (their rapid rates), pulses/s.
    pub vcap: f64,
}

impl Move {
    /// A move along `path` from `start` for a channel with axes `axes` [X, Z].
    pub(crate) fn new(path: Path, start: [i64; 2], axes: &[AxisDesc; 2], desc: &LatheDesc) -> Move {
        let len = path.len();
        let per_s = |mm_min: f64| mm_min / 60.0 / desc.pulse_mm;
        let per_s2 = |mm_s2: f64| mm_s2 / desc.pulse_mm;
        let (mut vcap, mut accel) = (f64::INFINITY, f64::INFINITY);
        match &path {
            Path::Line { end, .. } if len > 0.0 => {
                for (k, ax) in axes.iter().enumerate() {
                    let u = ((end[k] - start[k]) as f64 / len).abs();
                    if u > 1e-12 {
                        vcap = vcap.min(per_s(ax.rapid) / u);
                        accel = accel.min(per_s2(ax.accel) / u);
                    }
                }
            }
            _ => {
                for ax in axes {
                    vcap = vcap.min(per_s(ax.rapid));
                    accel = accel.min(per_s2(ax.accel));
                }
            }
        }
        if !vcap.is_finite() || vcap <= 0.0 {
            vcap = 1.0;
        }
        if !accel.is_finite() || accel <= 0.0 {
            accel = 1.0;
        }
        Move {
            path,
            len,
            s: 0.0,
            v: 0.0,
            accel,
            vcap,
        }
    }

    /// Advances one tick of `dt` s towards the speed `vmax` (pulses/s; 0 = feed hold, slow to
    /// a stop). Returns the new position and true when the end point is reached.
    pub(crate) fn step(&mut self, vmax: f64, dt: f64) -> ([i64; 2], bool) {
        let vmax = vmax.min(self.vcap).max(0.0);
        let a = self.accel;
        let rem = (self.len - self.s).max(0.0);
        let mut v = if self.v > vmax {
            (self.v - a * dt).max(vmax)
        } else {
            (self.v + a * dt).min(vmax)
        };
        // Brake so as to stop on the end point; creep at least a*dt so the block ends.
        v = v.min((2.0 * a * rem).sqrt());
        if vmax > 0.0 {
            v = v.max((a * dt).min(vmax));
        }
        self.v = v;
        self.s += v * dt;
        if self.s >= self.len - 1e-9 {
            self.s = self.len;
            return (self.path.end(), true);
        }
        (self.path.at(self.s, self.len), false)
    }
}

/// A thread pass: Z (and X in proportion) follows the spindle encoder from an index.
#[derive(Clone, Debug)]
pub(crate) struct ThreadMove {
    /// Start point, pulses.
    pub start: [i64; 2],
    /// End point, pulses.
    pub end: [i64; 2],
    /// Length along the longer axis, pulses.
    pub major: f64,
    /// Lead, pulses per revolution.
    pub lead: f64,
    /// Encoder counts done since the pass's index (kept across a fault).
    pub done: u64,
    /// The encoder count of the index the pass is anchored to (`None` = not yet
    /// synchronised, at the start or after a stop).
    pub anchor: Option<u64>,
    /// True once the axes follow the encoder from `anchor` (the pass event recorded).
    pub synced: bool,
    /// True once the pass has started (its first synchronisation recorded).
    pub started: bool,
}

impl ThreadMove {
    /// The point `counts` encoder counts after the index, with `lines` counts per revolution,
    /// and true when it is the end point.
    pub(crate) fn at(&self, counts: u64, lines: u32) -> ([i64; 2], bool) {
        let u = self.lead * counts as f64 / f64::from(lines.max(1));
        if self.major <= 0.0 || u >= self.major {
            return (self.end, true);
        }
        let f = u / self.major;
        (
            [
                self.start[0] + ((self.end[0] - self.start[0]) as f64 * f).round() as i64,
                self.start[1] + ((self.end[1] - self.start[1]) as f64 * f).round() as i64,
            ],
            false,
        )
    }

    /// The index to anchor to when the encoder stands at `enc`: the first index at which the
    /// counts already done fall at or after `enc` (the same helix as before, docs/lathe-sim.md
    /// "Threads").
    pub(crate) fn next_anchor(&self, enc: u64, lines: u32) -> u64 {
        let n = u64::from(lines.max(1));
        let base = enc.saturating_sub(self.done);
        base.div_ceil(n) * n
    }
}
