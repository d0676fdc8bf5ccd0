//! MIL: contours of points joined by straight cuts and full circles cut with circular
//! interpolation, optionally offset by the tool radius to the right (RGT) or left (LFT) of the
//! direction of travel (patent subroutine AP13; docs/language.md).
//!
//! Offsets are exact: each line moves sideways by the radius; at an inside corner the two offset
//! lines are cut off where they meet; at an outside corner the tool rolls round the corner on an
//! arc of the tool radius about the corner point, so the corner stays sharp on the part.

use super::cycle::{approach, Cycle};
use super::emit::Out;
use super::geom::{cross, line_line, Line, EPS, V2};
use super::TranslateError;
use nalgebra::Vector3;

/// A 3-D point, mm.
pub type V3 = Vector3<f64>;

/// One item of a contour, in machine coordinates (Z is the surface, tool tip).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Elem {
    /// A point of a polyline.
    Pt {
        /// The point; z is the surface.
        p: V3,
        /// Column of its designation.
        col: u32,
    },
    /// A full circle about `c` (z the surface) of radius `r`.
    Circle {
        /// Centre; z is the surface.
        c: V3,
        /// Radius, mm.
        r: f64,
        /// Column of its designation.
        col: u32,
    },
}

/// One cutting move of a contour (tool-centre path; z is tool-tip Z, mm).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mv {
    Line(V3),
    Arc {
        to: V3,
        c: V2,
        ccw: bool,
        full: bool,
    },
}

fn xy(p: V3) -> V2 {
    V2::new(p.x, p.y)
}

fn at(p: V2, z: f64) -> V3 {
    V3::new(p.x, p.y, z)
}

/// Mills the designated contours. `side` is +1 for RGT, -1 for LFT, 0 for none; `radius` is
/// the tool radius.
pub fn mill(
    o: &mut Out,
    c: &Cycle,
    side: f64,
    radius: f64,
    elems: &[Elem],
) -> Result<(), TranslateError> {
    let mut run: Vec<(V3, u32)> = Vec::new();
    for e in elems {
        match *e {
            Elem::Pt { p, col } => run.push((p, col)),
            Elem::Circle { c: centre, r, col } => {
                polyline(o, c, side, radius, &run)?;
                run.clear();
                let rr = r + side * radius;
                if rr <= EPS {
                    return Err(o.err(
                        col,
                        format!(
                            "the tool (diameter {:.3}) does not fit inside the circle of radius {r:.3}",
                            2.0 * radius
                        ),
                    ));
                }
                let zb = centre.z - c.depth;
                let start = V3::new(centre.x + rr, centre.y, zb);
                let mv = [Mv::Arc {
                    to: start,
                    c: xy(centre),
                    ccw: true,
                    full: true,
                }];
                o.col = col;
                cut(o, c, start, &mv, centre.z);
            }
        }
    }
    polyline(o, c, side, radius, &run)
}

/// Cuts one contour: approach above `start`, plunge at the feed, the moves, rapid retract.
/// `zs_hi` is the highest surface of the contour (mm): Za and the clearance plane follow it.
fn cut(o: &mut Out, c: &Cycle, start: V3, moves: &[Mv], zs_hi: f64) {
    let h = c.heights(o, zs_hi);
    let set = o.m.set();
    let (sx, sy) = (o.p(start.x), o.p(start.y));
    approach(o, sx, sy, h.za, h.clear, c.speed);
    o.feed([sx, sy, o.p(start.z) + set], c.feed);
    for mv in moves {
        match *mv {
            Mv::Line(p) => o.feed([o.p(p.x), o.p(p.y), o.p(p.z) + set], c.feed),
            Mv::Arc {
                to,
                c: centre,
                ccw,
                full,
            } => {
                let end = [o.p(to.x), o.p(to.y), o.p(to.z) + set];
                if !full && end[0] == o.m.pos[0] && end[1] == o.m.pos[1] {
                    o.feed(end, c.feed);
                    continue;
                }
                o.arc(end, [o.p(centre.x), o.p(centre.y)], ccw, c.feed);
            }
        }
    }
    o.rapid_tip(h.zc);
    o.m.clear = Some(h.clear);
}

/// Cuts a run of points (if any) as one polyline contour.
fn polyline(
    o: &mut Out,
    c: &Cycle,
    side: f64,
    radius: f64,
    run: &[(V3, u32)],
) -> Result<(), TranslateError> {
    let mut pts: Vec<(V3, u32)> = Vec::with_capacity(run.len());
    for &(p, col) in run {
        if pts
            .last()
            .is_none_or(|q: &(V3, u32)| (xy(q.0) - xy(p)).norm() > EPS)
        {
            pts.push((p, col));
        }
    }
    let Some(&(first, col0)) = pts.first() else {
        return Ok(());
    };
    let zs_hi = pts.iter().map(|p| p.0.z).fold(f64::MIN, f64::max);
    o.col = col0;
    let cutz: Vec<V3> = pts
        .iter()
        .map(|&(p, _)| V3::new(p.x, p.y, p.z - c.depth))
        .collect();
    if pts.len() == 1 {
        if side != 0.0 {
            return Err(o.err(
                col0,
                "RGT or LFT needs a contour of at least two points".to_string(),
            ));
        }
        cut(o, c, cutz[0], &[], first.z);
        return Ok(());
    }
    let (start, moves) = if side == 0.0 {
        (cutz[0], cutz[1..].iter().map(|&p| Mv::Line(p)).collect())
    } else {
        offset(&cutz, side, radius).map_err(|(i, msg)| o.err(pts[i].1, msg))?
    };
    cut(o, c, start, &moves, zs_hi);
    Ok(())
}

/// Where the offset path leaves segment `a` and enters segment `b` at their common vertex,
/// and the arc round an outside corner, if any.
fn corner(v: V3, ua: V2, ub: V2, side: f64, radius: f64) -> Result<(V3, V3, Option<Mv>), String> {
    let right = |u: V2| V2::new(u.y, -u.x) * (side * radius);
    let (oa, ob) = (right(ua), right(ub));
    let vv = xy(v);
    let turn = cross(ua, ub);
    let straight = turn.abs() < 1e-12;
    if straight && ua.dot(&ub) > 0.0 {
        let p = at(vv + oa, v.z);
        return Ok((p, p, None));
    }
    let outside = side * turn > 0.0 || straight;
    if outside {
        let (ea, sb) = (at(vv + oa, v.z), at(vv + ob, v.z));
        let ccw = if straight { side > 0.0 } else { turn > 0.0 };
        let arc = Mv::Arc {
            to: sb,
            c: vv,
            ccw,
            full: false,
        };
        return Ok((ea, sb, Some(arc)));
    }
    let la = Line { p: vv + oa, d: ua };
    let lb = Line { p: vv + ob, d: ub };
    let q = line_line(&la, &lb)?;
    let p = at(q, v.z);
    Ok((p, p, None))
}

/// The tool-centre path of a polyline offset by `radius` to the right (`side` +1) or left (-1).
/// A polyline whose last point is its first is closed, and its closing corner is treated like
/// the others. The error names the index of the vertex where the tool does not fit.
fn offset(pts: &[V3], side: f64, radius: f64) -> Result<(V3, Vec<Mv>), (usize, String)> {
    let n = pts.len();
    let segs = n - 1;
    let u: Vec<V2> = (0..segs)
        .map(|i| (xy(pts[i + 1]) - xy(pts[i])).normalize())
        .collect();
    let closed = n >= 3 && (xy(pts[0]) - xy(pts[n - 1])).norm() <= EPS;
    let mut entry = vec![V3::zeros(); segs];
    let mut exit = vec![V3::zeros(); segs];
    let mut arcs: Vec<Option<Mv>> = vec![None; n];
    let right = |u: V2| V2::new(u.y, -u.x) * (side * radius);
    entry[0] = at(xy(pts[0]) + right(u[0]), pts[0].z);
    exit[segs - 1] = at(xy(pts[n - 1]) + right(u[segs - 1]), pts[n - 1].z);
    for j in 1..segs {
        let (ea, sb, arc) = corner(pts[j], u[j - 1], u[j], side, radius).map_err(|m| (j, m))?;
        exit[j - 1] = ea;
        entry[j] = sb;
        arcs[j] = arc;
    }
    if closed {
        let (ea, sb, arc) = corner(pts[0], u[segs - 1], u[0], side, radius).map_err(|m| (0, m))?;
        exit[segs - 1] = ea;
        entry[0] = sb;
        arcs[0] = arc;
    }
    for i in 0..segs {
        if (xy(exit[i]) - xy(entry[i])).dot(&u[i]) < -EPS {
            let at_vertex = if i + 1 == segs && closed { 0 } else { i + 1 };
            return Err((
                at_vertex,
                format!(
                    "the tool (diameter {:.3}) is too large for the inside corner here: the offset path would cut back over itself",
                    2.0 * radius
                ),
            ));
        }
    }
    let mut moves = Vec::with_capacity(2 * segs);
    for (i, &e) in exit.iter().enumerate() {
        moves.push(Mv::Line(e));
        let j = if i + 1 == segs { 0 } else { i + 1 };
        if i + 1 < segs || closed {
            if let Some(a) = arcs[j] {
                moves.push(a);
            }
        }
    }
    Ok((entry[0], moves))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> V3 {
        V3::new(x, y, 0.0)
    }

    fn ends(moves: &[Mv]) -> Vec<(f64, f64)> {
        moves
            .iter()
            .map(|m| match m {
                Mv::Line(q) => (q.x, q.y),
                Mv::Arc { to, .. } => (to.x, to.y),
            })
            .map(|(x, y)| ((x * 1e6).round() / 1e6, (y * 1e6).round() / 1e6))
            .collect()
    }

    #[test]
    fn closed_square_left_offset_inside_is_cut_off_at_corners() {
        // A 10 mm square travelled counter-clockwise: LFT puts the tool inside, so every corner
        // is an inside corner and the centre path is the square shrunk by the radius 1.
        let sq = [
            p(0.0, 0.0),
            p(10.0, 0.0),
            p(10.0, 10.0),
            p(0.0, 10.0),
            p(0.0, 0.0),
        ];
        let (start, moves) = offset(&sq, -1.0, 1.0).unwrap();
        assert_eq!((start.x, start.y), (1.0, 1.0));
        assert_eq!(
            ends(&moves),
            vec![(9.0, 1.0), (9.0, 9.0), (1.0, 9.0), (1.0, 1.0)]
        );
    }

    #[test]
    fn closed_square_right_offset_rolls_round_outside_corners() {
        // The same square with RGT: the tool is outside; at each corner an arc of radius 1
        // about the corner joins the two offset sides.
        let sq = [
            p(0.0, 0.0),
            p(10.0, 0.0),
            p(10.0, 10.0),
            p(0.0, 10.0),
            p(0.0, 0.0),
        ];
        let (start, moves) = offset(&sq, 1.0, 1.0).unwrap();
        assert_eq!((start.x, start.y), (0.0, -1.0));
        assert_eq!(
            ends(&moves),
            vec![
                (10.0, -1.0),
                (11.0, 0.0),
                (11.0, 10.0),
                (10.0, 11.0),
                (0.0, 11.0),
                (-1.0, 10.0),
                (-1.0, 0.0),
                (0.0, -1.0)
            ]
        );
        assert!(matches!(moves[1], Mv::Arc { ccw: true, .. }));
    }

    #[test]
    fn open_polyline_and_a_tool_too_big_for_an_inside_corner() {
        let l = [p(0.0, 0.0), p(10.0, 0.0), p(10.0, 10.0)];
        let (start, moves) = offset(&l, -1.0, 1.0).unwrap();
        assert_eq!((start.x, start.y), (0.0, 1.0));
        assert_eq!(ends(&moves), vec![(9.0, 1.0), (9.0, 10.0)]);
        let short = [p(0.0, 0.0), p(10.0, 0.0), p(10.0, 1.0), p(0.0, 1.0)];
        let e = offset(&short, -1.0, 1.0).unwrap_err();
        assert!(e.1.contains("too large"), "{}", e.1);
    }
}
