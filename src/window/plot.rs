//! The backplot panel: the programmed path (rapids dashed, feeds solid, arcs true), the
//! executed path drawn live from the axis pulse counters, and the tool position, in an XY or
//! XZ view with zoom (scroll, about the pointer) and pan (drag). The geometry is
//! `crate::backplot`; this file only draws it.

use crate::backplot::{Backplot, PathKind, Plane, Trail, ViewTransform};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use egui::{pos2, Align2, Color32, FontId, Pos2, Rect, Sense, Shape, Stroke, Ui};

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
    polylines: Vec<(PathKind, Vec<[f64; 3]>)>,
    program_key: Option<u64>,
    /// The executed path.
    pub trail: Trail,
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

impl PlotState {
    /// An empty plot in the XY plane.
    pub fn new() -> PlotState {
        PlotState {
            plane: Plane::XY,
            xf: [ViewTransform::default(); 2],
            auto_fit: [true; 2],
            backplot: Backplot::default(),
            polylines: Vec::new(),
            program_key: None,
            trail: Trail::new(),
        }
    }

    /// Recomputes the programmed path if the program or the tool data changed (the same
    /// translator as the machine, from machine position `start`, pulses). Returns whether it did.
    pub fn update_program(
        &mut self,
        text: &str,
        magazine: &Magazine,
        settings: &MachineSettings,
        start: [i64; 3],
    ) -> bool {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        text.hash(&mut h);
        format!("{magazine:?}{settings:?}").hash(&mut h);
        let key = h.finish();
        if self.program_key == Some(key) {
            return false;
        }
        self.program_key = Some(key);
        self.backplot = if text.trim().is_empty() {
            Backplot::default()
        } else {
            Backplot::from_program(text, magazine, settings, start)
        };
        self.polylines = self
            .backplot
            .segments
            .iter()
            .map(|s| (s.kind, s.points()))
            .collect();
        self.trail.clear();
        self.auto_fit = [true; 2];
        true
    }

    /// Fits both views to the drawing again.
    pub fn fit(&mut self) {
        self.auto_fit = [true; 2];
    }

    fn fitted(&self, plane: Plane, tool: [f64; 3], size: [f64; 2]) -> ViewTransform {
        let mut lo = plane.project(tool);
        let mut hi = lo;
        let pts = self
            .polylines
            .iter()
            .flat_map(|(_, p)| p.iter())
            .chain(self.trail.points().iter());
        for p in pts {
            let q = plane.project(*p);
            for a in 0..2 {
                lo[a] = lo[a].min(q[a]);
                hi[a] = hi[a].max(q[a]);
            }
        }
        ViewTransform::fit(lo, hi, size, 24.0)
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
                self.trail.clear();
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
        for (kind, pts) in &self.polylines {
            let px: Vec<Pos2> = pts.iter().map(to_px).collect();
            // A cut straight into the plane (a drill plunge seen from above) is a ring.
            let span = px
                .iter()
                .fold(Rect::NOTHING, |r, p| r.union(Rect::from_pos(*p)));
            if *kind != PathKind::Rapid && span.width() < 1.0 && span.height() < 1.0 {
                painter.circle_stroke(span.center(), 4.0, Stroke::new(1.5, FEED));
                continue;
            }
            match kind {
                PathKind::Rapid => {
                    painter.extend(Shape::dashed_line(&px, Stroke::new(1.0, RAPID), 6.0, 4.0))
                }
                PathKind::Feed => {
                    painter.add(Shape::line(px, Stroke::new(1.5, FEED)));
                }
                PathKind::Arc => {
                    painter.add(Shape::line(px, Stroke::new(1.5, ARC)));
                }
            };
        }
        let trail: Vec<Pos2> = self.trail.points().iter().map(to_px).collect();
        if trail.len() >= 2 {
            painter.add(Shape::line(trail, Stroke::new(3.0, EXECUTED)));
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
