//! The backplot panel: the programmed path (rapids dashed, feeds solid, arcs true), the
//! executed path drawn live from the axis pulse counters, and the tool position, in an XY or
//! XZ view with zoom (scroll, about the pointer) and pan (drag). The geometry is
//! `crate::backplot`; this file only draws it.

use crate::backplot::{Backplot, Bounds, PathKind, Plane, Trail, ViewTransform};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use egui::epaint::{Mesh, Tessellator};
use egui::{pos2, Align2, Color32, FontId, Pos2, Rect, Sense, Shape, Stroke, Ui};
use std::hash::{Hash, Hasher};
use std::sync::{mpsc, Arc};

/// The plot's background.
pub const PLOT_BG: Color32 = Color32::from_rgb(8, 12, 20);
/// Rapid moves of the programmed path (dashed).
pub const RAPID: Color32 = Color32::from_rgb(190, 180, 90);
/// Feed moves of the programmed path (solid).
pub const FEED: Color32 = Color32::from_rgb(100, 150, 255);
/// Arcs of the programmed path (solid, true circle).
pub const ARC: Color32 = Color32::from_rgb(170, 120, 255);
/// The executed path. No other part of the plot uses this colour (the window test looks for it).
pub const EXECUTED: Color32 = Color32::from_rgb(0, 255, 140);
/// The tool position marker.
pub const TOOL: Color32 = Color32::from_rgb(255, 70, 70);
const GRID: Color32 = Color32::from_rgb(28, 34, 46);

/// One piece of the programmed path ready to draw: its kind, its points (mm) and its box.
struct Piece {
    kind: PathKind,
    points: Vec<[f64; 3]>,
    bounds: Bounds,
}

/// A translation for the backplot running on its own thread (so that a long program never
/// holds up a frame): the key of what it translates, and where the result arrives.
struct Job {
    rx: mpsc::Receiver<(u64, Option<Backplot>)>,
}

/// What the tessellated programmed path was made for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct MeshKey {
    plane: usize,
    view: [f64; 3],
    rect: [f32; 4],
    version: u64,
    ppp: f32,
}

/// Trail points per frozen chunk of the executed path's drawing.
const TRAIL_CHUNK: usize = 256;

/// The executed path tessellated in chunks for one view and one trail epoch.
#[derive(Default)]
struct TrailMesh {
    /// The view (and path version) and the trail epoch the chunks were made for.
    key: Option<(MeshKey, u64)>,
    chunks: Vec<Arc<Mesh>>,
    /// Points `0..=frozen_to` are in `chunks` (0 when there are none).
    frozen_to: usize,
}

/// A drawn stretch of path in half-pixel steps, the same whichever way it is travelled.
fn seg_key(kind: PathKind, a: Pos2, b: Pos2) -> (PathKind, [i32; 4]) {
    let q = |v: f32| (v * 2.0).round() as i32;
    let (a, b) = ([q(a.x), q(a.y)], [q(b.x), q(b.y)]);
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    (kind, [lo[0], lo[1], hi[0], hi[1]])
}

/// What a backplot translation needs: program text, magazine, settings, start (pulses).
type Request = (String, Magazine, MachineSettings, [i64; 3]);

/// The backplot's state: the path of the loaded program, the executed trail, the view.
pub struct PlotState {
    /// The plane shown.
    pub plane: Plane,
    /// The view of each plane (set by fit, zoom and pan).
    xf: [ViewTransform; 2],
    /// Whether each plane's view still follows the drawing (no zoom or pan by the operator yet).
    auto_fit: [bool; 2],
    /// The programmed path.
    pub backplot: Backplot,
    pieces: Vec<Piece>,
    path_bounds: Option<Bounds>,
    program_key: Option<u64>,
    job: Option<Job>,
    queued: Option<Request>,
    /// Bumped when the programmed path changes.
    path_version: u64,
    /// The programmed path tessellated for one view.
    mesh: Option<(MeshKey, Arc<Mesh>)>,
    /// The executed path's frozen chunks tessellated for one view.
    trail_mesh: TrailMesh,
    /// The executed path.
    trail: Trail,
    trail_bounds: Option<Bounds>,
}

impl Default for PlotState {
    fn default() -> Self {
        PlotState::new()
    }
}

fn plane_index(p: Plane) -> usize {
    match p {
        Plane::XY => 0,
        Plane::XZ => 1,
    }
}

/// The key of a translation request: a hash of everything the path depends on.
fn request_key(r: &Request) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    r.0.hash(&mut h);
    format!("{:?}{:?}", r.1, r.2).hash(&mut h);
    h.finish()
}

impl PlotState {
    /// An empty plot in the XY plane.
    pub fn new() -> PlotState {
        PlotState {
            plane: Plane::XY,
            xf: [ViewTransform::default(); 2],
            auto_fit: [true; 2],
            backplot: Backplot::default(),
            pieces: Vec::new(),
            path_bounds: None,
            program_key: None,
            job: None,
            queued: None,
            path_version: 0,
            mesh: None,
            trail_mesh: TrailMesh::default(),
            trail: Trail::new(),
            trail_bounds: None,
        }
    }

    /// Asks for the programmed path of this program (the same translator as the machine, from
    /// machine position `start`, pulses). The translation runs on its own thread and only if
    /// the program, the tool data or the settings changed; `poll` takes the result.
    pub fn request_program(
        &mut self,
        text: String,
        magazine: Magazine,
        settings: MachineSettings,
        start: [i64; 3],
    ) {
        self.queued = Some((text, magazine, settings, start));
        self.poll();
    }

    /// Takes a finished translation and starts the queued one; true while one is running.
    pub fn poll(&mut self) -> bool {
        if let Some(job) = &self.job {
            match job.rx.try_recv() {
                Ok((key, result)) => {
                    self.job = None;
                    if let Some(bp) = result {
                        // A changed program starts a fresh executed path; the first one
                        // loaded keeps what the machine did meanwhile.
                        if self.program_key.is_some() {
                            self.clear_trail();
                        }
                        self.program_key = Some(key);
                        self.set_backplot(bp);
                    }
                }
                Err(mpsc::TryRecvError::Empty) => return true,
                Err(mpsc::TryRecvError::Disconnected) => self.job = None,
            }
        }
        if let Some(req) = self.queued.take() {
            let known = self.program_key;
            let (tx, rx) = mpsc::channel();
            let spawned = std::thread::Builder::new()
                .name("backplot".into())
                .spawn(move || {
                    let key = request_key(&req);
                    let result = (known != Some(key)).then(|| {
                        let (text, mag, settings, start) = &req;
                        if text.trim().is_empty() {
                            Backplot::default()
                        } else {
                            Backplot::from_program(text, mag, settings, *start)
                        }
                    });
                    let _ = tx.send((key, result));
                });
            if spawned.is_ok() {
                self.job = Some(Job { rx });
                return true;
            }
        }
        false
    }

    fn set_backplot(&mut self, bp: Backplot) {
        self.pieces = bp
            .segments
            .iter()
            .map(|s| {
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
            })
            .collect();
        self.path_bounds = self.pieces.iter().map(|p| p.bounds).reduce(|mut a, b| {
            a.include(b.min);
            a.include(b.max);
            a
        });
        self.backplot = bp;
        self.path_version += 1;
        self.auto_fit = [true; 2];
    }

    /// Records an axis position sampled from the pulse counters (the executed path).
    pub fn record(&mut self, p: [f64; 3]) {
        self.trail.push(p);
        match &mut self.trail_bounds {
            Some(b) => b.include(p),
            None => self.trail_bounds = Some(Bounds::point(p)),
        }
    }

    /// Forgets the executed path.
    pub fn clear_trail(&mut self) {
        self.trail.clear();
        self.trail_bounds = None;
    }

    /// Fits both views to the drawing again.
    pub fn fit(&mut self) {
        self.auto_fit = [true; 2];
    }

    fn fitted(&self, plane: Plane, tool: [f64; 3], size: [f64; 2]) -> ViewTransform {
        let mut b = Bounds::point(tool);
        for bb in self.path_bounds.iter().chain(self.trail_bounds.iter()) {
            b.include(bb.min);
            b.include(bb.max);
        }
        ViewTransform::fit(plane.project(b.min), plane.project(b.max), size, 24.0)
    }

    /// The programmed path as shapes for this view: pieces wholly outside the plot skipped,
    /// consecutive pieces of one kind joined into one line, points closer than half a pixel
    /// to the last one dropped, plunges into the plane drawn as rings.
    fn path_shapes(&self, rect: Rect, xf: &ViewTransform, plane: Plane) -> Vec<Shape> {
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
        for piece in &self.pieces {
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

    /// Draws the plot in the space left in `ui`, handling zoom and pan. `scroll` is this
    /// frame's mouse-wheel notches (taken if the pointer is over the plot). Returns the plot's
    /// screen rectangle.
    pub fn show(&mut self, ui: &mut Ui, tool: [f64; 3], scroll: &mut f32) -> Rect {
        ui.horizontal(|ui| {
            for p in [Plane::XY, Plane::XZ] {
                let (h, v) = p.axes();
                if ui
                    .selectable_label(self.plane == p, format!("{h}{v}"))
                    .clicked()
                {
                    self.plane = p;
                }
            }
            if ui.button("Fit").clicked() {
                self.fit();
            }
            if ui.button("Clear path").clicked() {
                self.clear_trail();
            }
            ui.label(
                egui::RichText::new("scroll: zoom · drag: pan")
                    .small()
                    .color(Color32::GRAY),
            );
        });
        let size = ui.available_size();
        let (resp, painter) = ui.allocate_painter(size, Sense::drag());
        let rect = resp.rect;
        painter.rect_filled(rect, 0.0, PLOT_BG);
        let pi = plane_index(self.plane);
        let sz = [rect.width() as f64, rect.height() as f64];
        if self.auto_fit[pi] {
            self.xf[pi] = self.fitted(self.plane, tool, sz);
        }
        // Zoom about the pointer, pan by dragging.
        if let Some(hp) = resp.hover_pos() {
            let notches = scroll.trunc();
            *scroll -= notches;
            let pinch = ui.input(|i| i.zoom_delta()) as f64;
            let factor = 1.2f64.powf(notches as f64) * pinch;
            if factor != 1.0 {
                let at = [
                    (hp.x - rect.center().x) as f64,
                    (hp.y - rect.center().y) as f64,
                ];
                self.xf[pi].zoom(factor, at);
                self.auto_fit[pi] = false;
            }
        }
        if resp.dragged() {
            let d = resp.drag_delta();
            self.xf[pi].pan([d.x as f64, d.y as f64]);
            self.auto_fit[pi] = false;
        }
        let xf = self.xf[pi];
        let plane = self.plane;
        let c = rect.center();
        let to_px = |p: &[f64; 3]| -> Pos2 {
            let s = xf.to_screen(plane.project(*p));
            pos2(c.x + s[0] as f32, c.y + s[1] as f32)
        };
        let painter = painter.with_clip_rect(rect);
        draw_grid(&painter, rect, &xf, plane);
        // The programmed path changes only with the program or the view: it is tessellated
        // once into a mesh and that mesh is drawn again each frame.
        let key = MeshKey {
            plane: pi,
            view: [xf.center[0], xf.center[1], xf.scale],
            rect: [rect.min.x, rect.min.y, rect.max.x, rect.max.y],
            version: self.path_version,
            ppp: ui.ctx().pixels_per_point(),
        };
        let mesh = match &self.mesh {
            Some((k, m)) if *k == key => m.clone(),
            _ => {
                let opts = ui.ctx().tessellation_options(|o| *o);
                let mut tess = Tessellator::new(key.ppp, opts, [1, 1], Vec::new());
                tess.set_clip_rect(rect);
                let mut mesh = Mesh::default();
                for shape in self.path_shapes(rect, &xf, plane) {
                    tess.tessellate_shape(shape, &mut mesh);
                }
                let m = Arc::new(mesh);
                self.mesh = Some((key, m.clone()));
                m
            }
        };
        painter.add(Shape::mesh(mesh));
        // The executed path: frozen chunks tessellated once (for this view), the live tail
        // drawn each frame.
        let tkey = (key, self.trail.epoch());
        if self.trail_mesh.key != Some(tkey) {
            self.trail_mesh = TrailMesh {
                key: Some(tkey),
                ..TrailMesh::default()
            };
        }
        let pts = self.trail.points();
        // Every point but the last is final; freeze whole chunks of them.
        while pts.len() >= self.trail_mesh.frozen_to + TRAIL_CHUNK + 2 {
            let from = self.trail_mesh.frozen_to;
            let to = from + TRAIL_CHUNK;
            let line: Vec<Pos2> = pts[from..=to].iter().map(to_px).collect();
            let opts = ui.ctx().tessellation_options(|o| *o);
            let mut tess = Tessellator::new(key.ppp, opts, [1, 1], Vec::new());
            tess.set_clip_rect(rect);
            let mut mesh = Mesh::default();
            tess.tessellate_shape(Shape::line(line, Stroke::new(3.0, EXECUTED)), &mut mesh);
            self.trail_mesh.chunks.push(Arc::new(mesh));
            self.trail_mesh.frozen_to = to;
        }
        for m in &self.trail_mesh.chunks {
            painter.add(Shape::mesh(m.clone()));
        }
        let tail: Vec<Pos2> = pts[self.trail_mesh.frozen_to.min(pts.len())..]
            .iter()
            .map(to_px)
            .collect();
        if tail.len() >= 2 {
            painter.add(Shape::line(tail, Stroke::new(3.0, EXECUTED)));
        }
        let t = to_px(&tool);
        painter.circle_stroke(t, 6.0, Stroke::new(2.0, TOOL));
        painter.line_segment(
            [t - egui::vec2(10.0, 0.0), t + egui::vec2(10.0, 0.0)],
            Stroke::new(1.0, TOOL),
        );
        painter.line_segment(
            [t - egui::vec2(0.0, 10.0), t + egui::vec2(0.0, 10.0)],
            Stroke::new(1.0, TOOL),
        );
        let mut note = format!("{} view", {
            let (h, v) = plane.axes();
            format!("{h}{v}")
        });
        if let Some(e) = &self.backplot.error {
            note = format!("{note} · program stops at line {}: {}", e.line, e.message);
        }
        if self.backplot.truncated {
            note.push_str(" · path cut short");
        }
        painter.text(
            rect.left_top() + egui::vec2(6.0, 4.0),
            Align2::LEFT_TOP,
            note,
            FontId::proportional(12.0),
            Color32::from_rgb(170, 180, 200),
        );
        rect
    }
}

/// A grid at a round spacing (1, 2 or 5 × 10ⁿ mm) at least 40 pixels apart, with the scale.
fn draw_grid(p: &egui::Painter, rect: Rect, xf: &ViewTransform, plane: Plane) {
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
    use crate::block::{Block, Motion};

    fn line(seq: u32, motion: Motion, from: [i64; 3], to: [i64; 3]) -> Block {
        let mut b = Block::aux(seq, 1, to);
        b.motion = motion;
        b.delta = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
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

    fn plot_of(blocks: &[Block]) -> PlotState {
        let mut p = PlotState::new();
        p.set_backplot(Backplot::from_blocks(blocks, &MachineSettings::default()));
        p
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
        let a = one.path_shapes(rect, &xf, Plane::XY);
        let b = both.path_shapes(rect, &xf, Plane::XY);
        assert_eq!(a.len(), 1, "one closed square is one line");
        assert_eq!(drawn_points(&a), 5);
        assert_eq!(
            drawn_points(&b),
            drawn_points(&a),
            "the second pass is not drawn again"
        );
        // From the front (XZ) the two depths are different lines: both are drawn.
        let xz = ViewTransform::fit([0.0, -3.0], [10.0, 0.0], [200.0, 200.0], 10.0);
        assert!(drawn_points(&both.path_shapes(rect, &xz, Plane::XZ)) > 2);
        assert!(
            both.path_shapes(rect, &xz, Plane::XZ).len() >= 2,
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
        let shapes = p.path_shapes(rect, &xf, Plane::XY);
        let rings = shapes
            .iter()
            .filter(|s| matches!(s, Shape::Circle(_)))
            .count();
        assert_eq!(rings, 1, "the plunge seen from above is a ring");
        // A view far away from everything draws nothing.
        let far = ViewTransform::fit([0.0, 500.0], [10.0, 510.0], [200.0, 200.0], 10.0);
        assert!(p.path_shapes(rect, &far, Plane::XY).is_empty());
    }
}
