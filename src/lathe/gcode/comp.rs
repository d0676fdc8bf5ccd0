//! Tool-nose radius compensation G41/G42 in the Z–X plane (docs/lathe-gcode.md "Nose-radius
//! compensation"; seed 003 lines 2682–2698: the control needs the nose radius and the
//! position of the imaginary tip P relative to the nose centre C).
//!
//! The nose centre C runs one radius to the left (G41) or right (G42) of the programmed
//! profile, looking along the direction of travel with Z to the right and X up. The
//! controlled point is P = C + R·v(tip) ([`tip_vector`], Fanuc's chart). The joins are the
//! mill's (src/gcode/comp.rs, LinuxCNC 2.9): an arc of the nose radius about an outside
//! corner, the crossing of the two offset paths at an inside corner; the entry move ends one
//! radius off its end point square to its direction; the exit move runs to its programmed
//! end point. The mill's code is bound to its XY canonical moves, so this is a second,
//! batch implementation of the same rules on a whole run (entry to exit) of moves.

use super::out::{Kind, Mv};
use crate::block::Block;
use crate::block::TranslateError;
use crate::gcode::geom::{circle_circle, dist, line_circle, sub, unit};
use std::f64::consts::TAU;

/// A corner turning by less than this (radians) is tangent: no join.
const TANGENT: f64 = 1e-7;

/// The moves held from the entry move on.
#[derive(Clone, Debug)]
pub struct Run {
    /// G41.
    pub left: bool,
    /// Nose radius, mm.
    pub radius: f64,
    /// Tip position 0–9.
    pub tip: u8,
    /// The programmed moves, the entry move first.
    pub segs: Vec<Mv>,
    /// Blocks without motion and their lines, each after the first `n` moves.
    pub aux: Vec<(usize, u32, Block)>,
}

/// The direction from the nose centre C to the imaginary tip P for a tip position, `[Z, X]`
/// (Fanuc's chart with Z to the right and X up; 0 and 9 are the centre itself):
///
/// ```text
///        +X
///    2   6   1
///    7  0/9  5   +Z
///    3   8   4
/// ```
pub fn tip_vector(tip: u8) -> [f64; 2] {
    match tip {
        1 => [1.0, 1.0],
        2 => [-1.0, 1.0],
        3 => [-1.0, -1.0],
        4 => [1.0, -1.0],
        5 => [1.0, 0.0],
        6 => [0.0, 1.0],
        7 => [-1.0, 0.0],
        8 => [0.0, -1.0],
        _ => [0.0, 0.0],
    }
}

/// LinuxCNC's orientation (its tool table's Q, #5411) of the tool whose tip position is `tip`
/// in Fanuc's chart: LinuxCNC draws its chart with +X down (`latheorigin_x`/`_z` in its
/// `interp_queue.cc`), so its 2 is the usual outside turning tool, Fanuc's 3
/// (docs/lathe-gcode.md "Nose-radius compensation").
pub fn linuxcnc_orientation(tip: u8) -> u8 {
    [0, 4, 3, 2, 1, 5, 8, 7, 6, 9]
        .get(usize::from(tip))
        .copied()
        .unwrap_or(0)
}

/// The angle an arc from `s` to `e` about `c` sweeps, in (0, 2π] (a full circle when `s` is
/// `e`).
pub fn sweep(c: [f64; 2], s: [f64; 2], e: [f64; 2], ccw: bool) -> f64 {
    let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
    let a1 = (e[1] - c[1]).atan2(e[0] - c[0]);
    let d = if ccw { a1 - a0 } else { a0 - a1 };
    let d = d.rem_euclid(TAU);
    if d < 1e-12 {
        TAU
    } else {
        d
    }
}

/// The unit tangent of a move at point `p` on it.
fn tangent(m: &Mv, p: [f64; 2]) -> [f64; 2] {
    match m.kind {
        Kind::Arc { c, ccw, .. } => {
            let r = unit(sub(p, c));
            if ccw {
                [-r[1], r[0]]
            } else {
                [r[1], -r[0]]
            }
        }
        _ => unit(sub(m.end, m.start)),
    }
}

/// The left normal of a tangent.
fn left_of(t: [f64; 2]) -> [f64; 2] {
    [-t[1], t[0]]
}

fn err(m: &Mv, message: impl Into<String>) -> TranslateError {
    TranslateError {
        line: m.line,
        col: m.col,
        message: message.into(),
    }
}

/// The offset (nose centre) moves of a run, grouped per programmed move (the corner join
/// before a move belongs to it), then the exit move's group. The bool marks a point that is
/// P itself (the exit move's end), not a centre.
pub fn offset_path(run: &Run, exit: Option<&Mv>) -> Result<Vec<Vec<(Mv, bool)>>, TranslateError> {
    let side = if run.left { 1.0 } else { -1.0 };
    let r = run.radius;
    // Offset each move by its own normals.
    let mut off: Vec<Mv> = Vec::with_capacity(run.segs.len());
    for (i, m) in run.segs.iter().enumerate() {
        let mut o = *m;
        let ns = left_of(tangent(m, m.start));
        let ne = left_of(tangent(m, m.end));
        o.start = [m.start[0] + side * r * ns[0], m.start[1] + side * r * ns[1]];
        o.end = [m.end[0] + side * r * ne[0], m.end[1] + side * r * ne[1]];
        if i == 0 {
            o.start = m.start;
        }
        if let Kind::Arc { c, ccw, .. } = m.kind {
            let rc = dist(m.start, c);
            let ro = if ccw { rc - side * r } else { rc + side * r };
            if ro <= 1e-6 {
                return Err(err(
                    m,
                    format!(
                        "the arc's radius ({rc:.3} mm) is not larger than the nose radius ({r} mm) on the inside of the arc"
                    ),
                ));
            }
        }
        off.push(o);
    }
    // Corners.
    let mut corners: Vec<Option<Mv>> = vec![None; off.len()];
    for i in 0..off.len().saturating_sub(1) {
        let (a, b) = (&run.segs[i], &run.segs[i + 1]);
        let q = a.end;
        let t1 = tangent(a, q);
        let t2 = tangent(b, q);
        let cross = t1[0] * t2[1] - t1[1] * t2[0];
        let dot = t1[0] * t2[0] + t1[1] * t2[1];
        let angle = cross.atan2(dot);
        if angle.abs() < TANGENT {
            off[i + 1].start = off[i].end;
            continue;
        }
        if side * angle < 0.0 || (dot < 0.0 && cross.abs() < 1e-9) {
            // Outside corner: an arc of the nose radius about the corner.
            let kind = match (b.kind, a.kind) {
                (Kind::Line(f), _) | (Kind::Arc { feed: f, .. }, _) => Kind::Arc {
                    c: q,
                    ccw: side < 0.0,
                    feed: f,
                },
                (_, Kind::Line(f)) | (_, Kind::Arc { feed: f, .. }) => Kind::Arc {
                    c: q,
                    ccw: side < 0.0,
                    feed: f,
                },
                _ => Kind::Rapid,
            };
            corners[i + 1] = Some(Mv {
                kind,
                start: off[i].end,
                end: off[i + 1].start,
                line: b.line,
                col: b.col,
            });
        } else {
            // Inside corner: where the two offset paths cross, nearest the corner.
            let near = [
                (off[i].end[0] + off[i + 1].start[0]) / 2.0,
                (off[i].end[1] + off[i + 1].start[1]) / 2.0,
            ];
            // The entry move runs from where the tool stands, but its side of the corner is
            // the line through its end parallel to the programmed move, as LinuxCNC's
            // convert_arc_comp2 and convert_straight_comp2 take it (the entry's direction
            // is the programmed one): its crossing with the next offset move is there.
            let mut before = off[i];
            if i == 0 && matches!(before.kind, Kind::Line(_) | Kind::Rapid) {
                let back = sub(a.start, a.end);
                before.start = [before.end[0] + back[0], before.end[1] + back[1]];
            }
            let x = crossing(&before, &off[i + 1], near).ok_or_else(|| {
                err(
                    b,
                    format!("the nose (radius {r} mm) cannot follow this inside corner: a move next to it is too short"),
                )
            })?;
            off[i].end = x;
            off[i + 1].start = x;
        }
    }
    // Gouges: a trimmed move that runs backwards or an arc that sweeps further.
    for (i, (o, m)) in off.iter().zip(&run.segs).enumerate() {
        let bad = match (o.kind, m.kind) {
            (Kind::Arc { c, ccw, .. }, _) => {
                // The offset arc keeps the centre; trimmed at an inside corner it may only
                // sweep less than the programmed arc.
                dist(o.start, o.end) > 1e-9
                    && sweep(c, o.start, o.end, ccw) > sweep(c, m.start, m.end, ccw) + 1e-6
            }
            _ => {
                let d = sub(m.end, m.start);
                let e = sub(o.end, o.start);
                i > 0 && d[0] * e[0] + d[1] * e[1] < -1e-9
            }
        };
        if bad {
            return Err(err(
                m,
                format!("the nose (radius {r} mm) would gouge the profile here: this move is shorter than the nose radius allows at its corner"),
            ));
        }
    }
    let mut groups: Vec<Vec<(Mv, bool)>> = Vec::with_capacity(off.len() + 1);
    for (i, o) in off.into_iter().enumerate() {
        let mut g = Vec::new();
        if let Some(c) = corners[i] {
            if dist(c.start, c.end) > 1e-9 {
                g.push((c, false));
            }
        }
        if dist(o.start, o.end) > 1e-9 || matches!(o.kind, Kind::Arc { .. }) && i > 0 {
            g.push((o, false));
        }
        groups.push(g);
    }
    if let Some(e) = exit {
        groups.push(vec![(*e, true)]);
    }
    Ok(groups)
}

/// The crossing of two offset moves (lines or arcs, extended) nearest `near`.
fn crossing(a: &Mv, b: &Mv, near: [f64; 2]) -> Option<[f64; 2]> {
    let pts: Vec<[f64; 2]> = match (a.kind, b.kind) {
        (Kind::Arc { c: c0, .. }, Kind::Arc { c: c1, .. }) => {
            circle_circle(c0, dist(a.end, c0), c1, dist(b.start, c1))
        }
        (Kind::Arc { c, .. }, _) => {
            let d = unit(sub(b.end, b.start));
            line_circle(b.start, d, c, dist(a.end, c))
                .into_iter()
                .map(|t| [b.start[0] + t * d[0], b.start[1] + t * d[1]])
                .collect()
        }
        (_, Kind::Arc { c, .. }) => {
            let d = unit(sub(a.end, a.start));
            line_circle(a.start, d, c, dist(b.start, c))
                .into_iter()
                .map(|t| [a.start[0] + t * d[0], a.start[1] + t * d[1]])
                .collect()
        }
        _ => {
            let d1 = sub(a.end, a.start);
            let d2 = sub(b.end, b.start);
            let den = d1[0] * d2[1] - d1[1] * d2[0];
            if den.abs() < 1e-15 {
                return None;
            }
            let w = sub(b.start, a.start);
            let t = (w[0] * d2[1] - w[1] * d2[0]) / den;
            vec![[a.start[0] + t * d1[0], a.start[1] + t * d1[1]]]
        }
    };
    pts.into_iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .min_by(|p, q| dist(*p, near).total_cmp(&dist(*q, near)))
}
