//! Drawing the backplot's geometry with egui shapes: the programmed path for one view (what
//! is in view, joined into long lines, repeated passes drawn once, plunges as rings) and the
//! grid. `plot` keeps the state and caches the tessellated result.

use crate::backplot::{Bounds, PathKind, Plane, Segment, ViewTransform};
use egui::{pos2, Align2, Color32, FontId, Pos2, Rect, Shape, Stroke};

/// Rapid moves of the programmed path (dashed).
pub const RAPID: Color32 = Color32::from_rgb(190, 180, 90);
/// Feed moves of the programmed path (solid).
pub const FEED: Color32 = Color32::from_rgb(100, 150, 255);
/// Arcs of the programmed path (solid, true circle).
pub const ARC: Color32 = Color32::from_rgb(170, 120, 255);
const GRID: Color32 = Color32::from_rgb(28, 34, 46);

/// One piece of the programmed path ready to draw: its kind, its points (mm) and its box.
pub(super) struct Piece {
    pub(super) kind: PathKind,
    pub(super) points: Vec<[f64; 3]>,
    pub(super) bounds: Bounds,
}

impl Piece {
    /// The piece of one programmed segment (its points as drawn, and their box).
    pub(super) fn of(s: &Segment) -> Piece {
        let points = s.points();
        let mut bounds = Bounds::point(points[0]);
        for p in &points {
            bounds.include(*p);
        }
        Piece {
            kind: s.kind,
            points,
            bounds,
        }
    }
}

/// A drawn stretch of path in half-pixel steps, the same whichever way it is travelled.
fn seg_key(kind: PathKind, a: Pos2, b: Pos2) -> (PathKind, [i32; 4]) {
    let q = |v: f32| (v * 2.0).round() as i32;
    let (a, b) = ([q(a.x), q(a.y)], [q(b.x), q(b.y)]);
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    (kind, [lo[0], lo[1], hi[0], hi[1]])
}

/// The programmed path as shapes for this view: pieces wholly outside the plot skipped,
/// consecutive pieces of one kind joined into one line, points closer than half a pixel
/// to the last one dropped, plunges into the plane drawn as rings.
pub(super) fn path_shapes(
    pieces: &[Piece],
    rect: Rect,
    xf: &ViewTransform,
    plane: Plane,
) -> Vec<Shape> {
    let c = rect.center();
    let to_px = |p: &[f64; 3]| -> Pos2 {
        let s = xf.to_screen(plane.project(*p));
        pos2(c.x + s[0] as f32, c.y + s[1] as f32)
    };
    let lo = xf.to_plane([(rect.min.x - c.x) as f64, (rect.max.y - c.y) as f64]);
    let hi = xf.to_plane([(rect.max.x - c.x) as f64, (rect.min.y - c.y) as f64]);
    let mut shapes = Vec::new();
    let mut run: Option<(PathKind, Vec<Pos2>)> = None;
    let mut seen = std::collections::HashSet::new();
    let flush = |run: &mut Option<(PathKind, Vec<Pos2>)>, shapes: &mut Vec<Shape>| {
        if let Some((kind, px)) = run.take() {
            if px.len() < 2 {
                return;
            }
            match kind {
                PathKind::Rapid => {
                    shapes.extend(Shape::dashed_line(&px, Stroke::new(1.0, RAPID), 6.0, 4.0))
                }
                PathKind::Feed => shapes.push(Shape::line(px, Stroke::new(1.5, FEED))),
                PathKind::Arc => shapes.push(Shape::line(px, Stroke::new(1.5, ARC))),
            }
        }
    };
    for piece in pieces {
        let (bmin, bmax) = (
            plane.project(piece.bounds.min),
            plane.project(piece.bounds.max),
        );
        if bmax[0] < lo[0] || bmin[0] > hi[0] || bmax[1] < lo[1] || bmin[1] > hi[1] {
            flush(&mut run, &mut shapes);
            continue;
        }
        let (pmin, pmax) = (to_px(&piece.bounds.min), to_px(&piece.bounds.max));
        let plunge = (pmax.x - pmin.x).abs() < 1.0 && (pmax.y - pmin.y).abs() < 1.0;
        if plunge && piece.kind != PathKind::Rapid {
            flush(&mut run, &mut shapes);
            shapes.push(Shape::circle_stroke(
                to_px(&piece.points[0]),
                4.0,
                Stroke::new(1.5, FEED),
            ));
            continue;
        }
        let first = to_px(&piece.points[0]);
        let joins = matches!(&run, Some((k, px)) if *k == piece.kind
            && px.last().is_some_and(|l| l.distance(first) < 0.5));
        if !joins {
            flush(&mut run, &mut shapes);
            run = Some((piece.kind, vec![first]));
        }
        let n = piece.points.len();
        let mut last = first;
        for (i, p) in piece.points.iter().enumerate().skip(1) {
            let q = to_px(p);
            if last.distance(q) < 0.5 && i + 1 < n {
                continue;
            }
            // A stretch already drawn (another pass over the same place, e.g. the same
            // contour at the next depth seen from above) is not drawn again.
            if !seen.insert(seg_key(piece.kind, last, q)) {
                flush(&mut run, &mut shapes);
                run = Some((piece.kind, vec![q]));
            } else if let Some((_, px)) = &mut run {
                px.push(q);
            }
            last = q;
        }
    }
    flush(&mut run, &mut shapes);
    shapes
}

/// A grid at a round spacing (1, 2 or 5 × 10ⁿ mm) at least 40 pixels apart, with the scale.
pub(super) fn draw_grid(p: &egui::Painter, rect: Rect, xf: &ViewTransform, plane: Plane) {
    let raw = 40.0 / xf.scale;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let c = rect.center();
    let lo = xf.to_plane([(rect.min.x - c.x) as f64, (rect.max.y - c.y) as f64]);
    let hi = xf.to_plane([(rect.max.x - c.x) as f64, (rect.min.y - c.y) as f64]);
    let stroke = Stroke::new(1.0, GRID);
    let mut x = (lo[0] / step).floor() * step;
    let mut n = 0;
    while x <= hi[0] && n < 400 {
        let s = xf.to_screen([x, 0.0]);
        let sx = c.x + s[0] as f32;
        p.line_segment([pos2(sx, rect.min.y), pos2(sx, rect.max.y)], stroke);
        x += step;
        n += 1;
    }
    let mut y = (lo[1] / step).floor() * step;
    n = 0;
    while y <= hi[1] && n < 400 {
        let s = xf.to_screen([0.0, y]);
        let sy = c.y + s[1] as f32;
        p.line_segment([pos2(rect.min.x, sy), pos2(rect.max.x, sy)], stroke);
        y += step;
        n += 1;
    }
    let (h, v) = plane.axes();
    p.text(
        rect.right_bottom() - egui::vec2(6.0, 4.0),
        Align2::RIGHT_BOTTOM,
        format!("grid {step} mm · {h} right, {v} up"),
        FontId::proportional(11.0),
        Color32::from_rgb(120, 130, 150),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backplot::Backplot;
    use crate::block::{Block, Motion};
    use crate::settings::MachineSettings;

    fn line(seq: u32, motion: Motion, from: [i64; 3], to: [i64; 3]) -> Block {
        let mut b = Block::aux(seq, 1, to);
        b.motion = motion;
        b.delta = [to[0] - from[0], to[1] - from[1], to[2] - from[2]].into();
        b
    }

    /// Points drawn by the shapes (dashed rapids count each dash).
    fn drawn_points(shapes: &[Shape]) -> usize {
        shapes
            .iter()
            .map(|s| match s {
                Shape::Path(p) => p.points.len(),
                Shape::LineSegment { .. } => 2,
                _ => 1,
            })
            .sum()
    }

    fn plot_of(blocks: &[Block]) -> Vec<Piece> {
        Backplot::from_blocks(blocks, &MachineSettings::default())
            .segments
            .iter()
            .map(Piece::of)
            .collect()
    }

    #[test]
    fn a_second_pass_over_the_same_place_draws_nothing_more_from_above() {
        // A square at Z −1, then the same square at Z −2: from above (XY) the same lines.
        let sq = |z: i64, seq: u32| -> Vec<Block> {
            let c = [[0, 0], [10_000, 0], [10_000, 10_000], [0, 10_000], [0, 0]];
            c.windows(2)
                .enumerate()
                .map(|(i, w)| {
                    line(
                        seq + i as u32,
                        Motion::Linear,
                        [w[0][0], w[0][1], z],
                        [w[1][0], w[1][1], z],
                    )
                })
                .collect()
        };
        let one = plot_of(&sq(-1_000, 1));
        let mut both_blocks = sq(-1_000, 1);
        both_blocks.extend(sq(-2_000, 10));
        let both = plot_of(&both_blocks);
        let rect = Rect::from_min_size(Pos2::ZERO, egui::vec2(200.0, 200.0));
        let xf = ViewTransform::fit([0.0, 0.0], [10.0, 10.0], [200.0, 200.0], 10.0);
        let a = path_shapes(&one, rect, &xf, Plane::XY);
        let b = path_shapes(&both, rect, &xf, Plane::XY);
        assert_eq!(a.len(), 1, "one closed square is one line");
        assert_eq!(drawn_points(&a), 5);
        assert_eq!(
            drawn_points(&b),
            drawn_points(&a),
            "the second pass is not drawn again"
        );
        // From the front (XZ) the two depths are different lines: both are drawn.
        let xz = ViewTransform::fit([0.0, -3.0], [10.0, 0.0], [200.0, 200.0], 10.0);
        assert!(drawn_points(&path_shapes(&both, rect, &xz, Plane::XZ)) > 2);
        assert!(
            path_shapes(&both, rect, &xz, Plane::XZ).len() >= 2,
            "the two depths are separate lines"
        );
    }

    #[test]
    fn pieces_outside_the_view_are_skipped_and_plunges_are_rings() {
        let blocks = vec![
            line(1, Motion::Rapid, [0, 0, 0], [5_000, 5_000, 0]),
            line(2, Motion::Linear, [5_000, 5_000, 0], [5_000, 5_000, -3_000]),
            line(
                3,
                Motion::Linear,
                [5_000, 5_000, -3_000],
                [900_000, 5_000, -3_000],
            ),
        ];
        let p = plot_of(&blocks);
        let rect = Rect::from_min_size(Pos2::ZERO, egui::vec2(200.0, 200.0));
        // A view of the first 10 mm only: the long feed reaches into it, so it is drawn.
        let xf = ViewTransform::fit([0.0, 0.0], [10.0, 10.0], [200.0, 200.0], 10.0);
        let shapes = path_shapes(&p, rect, &xf, Plane::XY);
        let rings = shapes
            .iter()
            .filter(|s| matches!(s, Shape::Circle(_)))
            .count();
        assert_eq!(rings, 1, "the plunge seen from above is a ring");
        // A view far away from everything draws nothing.
        let far = ViewTransform::fit([0.0, 500.0], [10.0, 510.0], [200.0, 200.0], 10.0);
        assert!(path_shapes(&p, rect, &far, Plane::XY).is_empty());
    }
}
