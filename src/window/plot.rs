//! The backplot panel: the programmed path (rapids dashed, feeds solid, arcs true), the
//! executed path drawn live from the axis pulse counters, and the tool position, in an XY or
//! XZ view with zoom (scroll, about the pointer) and pan (drag). The geometry is
//! `crate::backplot`; this file only draws it.

use super::pathdraw::{draw_grid, path_shapes, Piece};
use crate::backplot::{Backplot, Bounds, Plane, Trail, ViewTransform};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use egui::epaint::{Mesh, Tessellator};
use egui::{pos2, Align2, Color32, FontId, Pos2, Rect, Sense, Shape, Stroke, Ui};
use std::hash::{Hash, Hasher};
use std::sync::{mpsc, Arc};

/// The plot's background.
pub const PLOT_BG: Color32 = Color32::from_rgb(8, 12, 20);
/// The executed path. No other part of the plot uses this colour (the window test looks for it).
pub const EXECUTED: Color32 = Color32::from_rgb(0, 255, 140);
/// The tool position marker.
pub const TOOL: Color32 = Color32::from_rgb(255, 70, 70);

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

/// Where a G-code backplot starts reading.
#[derive(Clone, Debug)]
pub enum GcodeStart {
    /// From the defaults with these work offsets.
    Offsets(crate::gcode::WorkOffsets),
    /// From the console's interpreter state (G91, G92, the tool length... as the lines before
    /// left them), as START would read it; `mdi`: the MDI buffer (no M30 needed).
    State {
        /// The console's state.
        state: Box<crate::gcode::InterpState>,
        /// The text is the MDI buffer.
        mdi: bool,
        /// Where the subroutines and macros it calls are found, as START finds them.
        subs: Option<Arc<crate::gcode::SubPrograms>>,
    },
}

impl GcodeStart {
    /// What the path depends on, for the request's key (not the whole state: the modes, the
    /// offsets, the tool and the persistent parameters).
    fn key(&self) -> String {
        match self {
            GcodeStart::Offsets(o) => format!("{o:?}"),
            GcodeStart::State { state, mdi, subs } => format!(
                "{:?}{:?}{:?}{:?}{:?}{mdi}{:?}{:?}",
                state.modal,
                state.g92,
                state.tlo,
                state.tool,
                state.comp_radius,
                state.params[5161..=5390]
                    .iter()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>(),
                // A macro or subroutine in memory revised: the path may change.
                subs.as_ref().map(|s| s
                    .programs
                    .iter()
                    .map(|(n, t)| (n.as_str(), crate::crc32::crc32(t.as_bytes())))
                    .collect::<Vec<_>>())
            ),
        }
    }
}

/// What a backplot translation needs: the program, its tool data, the settings, the start
/// (pulses) and, for G-code, where reading starts.
type Request = (
    String,
    Magazine,
    MachineSettings,
    [i64; 3],
    Option<GcodeStart>,
);

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
    format!("{:?}{:?}{:?}", r.1, r.2, r.4.as_ref().map(GcodeStart::key)).hash(&mut h);
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
        gcode: Option<GcodeStart>,
    ) {
        self.queued = Some((text, magazine, settings, start, gcode));
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
                        let (text, mag, settings, start, gcode) = &req;
                        if text.trim().is_empty() {
                            Backplot::default()
                        } else if let Some(g) = gcode {
                            let machine = crate::block::MachineState::at(*start);
                            let sw = crate::gcode::Switches::default();
                            let src = match g {
                                GcodeStart::Offsets(o) => crate::gcode::GcodeSource::new(
                                    text.as_str().into(),
                                    mag.clone(),
                                    settings.clone(),
                                    machine,
                                    *o,
                                    sw,
                                ),
                                GcodeStart::State { state, mdi, subs } => {
                                    let mut g = crate::gcode::GcodeSource::with_state(
                                        text.as_str().into(),
                                        mag.clone(),
                                        settings.clone(),
                                        machine,
                                        (**state).clone(),
                                        sw,
                                    );
                                    if let Some(f) = subs {
                                        g = g.subroutines(Box::new(f.clone()));
                                    }
                                    if *mdi {
                                        g.mdi()
                                    } else {
                                        g
                                    }
                                }
                            };
                            Backplot::from_statements(src, settings)
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
        self.pieces = bp.segments.iter().map(Piece::of).collect();
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
                for shape in path_shapes(&self.pieces, rect, &xf, plane) {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn plotted(gcode: Option<GcodeStart>) -> Backplot {
        plotted_from(
            "G10 L2 P1 X100\nG54 G0 X10 Y5\nG1 Z-5 F100\nM30\n",
            [0; 3],
            gcode,
        )
    }

    fn plotted_from(text: &str, start: [i64; 3], gcode: Option<GcodeStart>) -> Backplot {
        let mut p = PlotState::new();
        let s = MachineSettings::default();
        let text = text.to_string();
        p.request_program(text, crate::tooldata::sample_magazine(), s, start, gcode);
        let t = std::time::Instant::now();
        while p.poll() && t.elapsed().as_secs() < 20 {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        p.backplot.clone()
    }

    #[test]
    fn a_gcode_program_is_plotted_through_the_gcode_source() {
        let bp = plotted(Some(GcodeStart::Offsets(Default::default())));
        assert!(bp.error.is_none(), "{:?}", bp.error);
        assert_eq!(bp.segments.len(), 2);
        // The source language refuses the same text.
        assert!(plotted(None).error.is_some());
    }

    /// A program that calls a subroutine kept in program memory is plotted through it, as
    /// START reads it (the plot once said the subroutine was not in the program).
    #[test]
    fn a_subroutine_in_program_memory_is_plotted() {
        let text = "G10 L2 P1 X100\nG54\no<square> call\nM30\n";
        let subs = crate::gcode::SubPrograms {
            programs: vec![(
                "SQUARE.NGC".into(),
                "o<square> sub\nG0 X10\nG0 Y10\no<square> endsub\nM2\n".into(),
            )],
            path: crate::gcode::SubPath(Vec::new()),
        };
        let start = |subs| GcodeStart::State {
            state: Box::default(),
            mdi: false,
            subs,
        };
        let without = plotted_from(text, [0; 3], Some(start(None)));
        assert!(without.error.is_some(), "no finder, no subroutine");
        let bp = plotted_from(text, [0; 3], Some(start(Some(Arc::new(subs)))));
        assert!(bp.error.is_none(), "{:?}", bp.error);
        assert_eq!(bp.segments.len(), 2, "{:?}", bp.segments);
        assert!((bp.segments[1].to[1] - 10.0).abs() < 1e-9);
    }

    /// MDI G-code is plotted as START will read it: from the console's state (here G91), and
    /// without the M30 a program needs.
    #[test]
    fn mdi_gcode_is_plotted_from_the_consoles_state() {
        let mut state = crate::gcode::InterpState::default();
        state.modal.incremental = true;
        let g = GcodeStart::State {
            state: Box::new(state),
            mdi: true,
            subs: None,
        };
        let bp = plotted_from("G0 X5\n", [10_000, 0, 0], Some(g));
        assert!(bp.error.is_none(), "{:?}", bp.error);
        assert_eq!(bp.segments.len(), 1);
        assert!(
            (bp.segments[0].to[0] - 15.0).abs() < 1e-9,
            "{:?}",
            bp.segments[0]
        );
    }
}
