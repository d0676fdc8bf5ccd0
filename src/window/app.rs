//! The eframe application: each frame it ticks the console, draws its `PanelView` (plasma,
//! selectors, relay panel, data keys, readout, backplot) and hands the operator's actions back
//! as `PanelEvent`s. It also plays a panel script, takes a screenshot and measures frames when
//! asked (headless runs under Xvfb). No NC logic lives here.

use super::bench::Bench;
use super::controls::{self, HandState};
use super::plasma::Plasma;
use super::plot::PlotState;
use super::shot::{rect_px, Shot};
use super::tapestrip::{self, StripLayout};
use super::Machine;
use crate::panel_model::{DataMode, OpMode, PanelEvent, PanelView};
use egui::{vec2, Color32, Rect};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What a headless run asks of the window (all optional).
#[derive(Debug, Default)]
pub struct Drive {
    /// Panel events to play, in order (`--script FILE`).
    pub script: VecDeque<PanelEvent>,
    /// Where to write a screenshot once the script has been played (`--screenshot OUT`).
    pub screenshot: Option<PathBuf>,
    /// Frames to measure, then print the figures and close (`--bench-frames N`).
    pub bench_frames: Option<u64>,
    /// Longest a script `wait` may take before the run is abandoned.
    pub wait_limit: Duration,
}

/// What a script wait is waiting for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Waiting {
    /// `wait`: the machine idle.
    Idle,
    /// `wait block N`: block N executing, or the machine idle.
    Block(u32),
    /// `wait ms T`: machine time at or past this, ns.
    Until(u64),
}

/// The screen rectangles a test needs to read a screenshot (physical pixels).
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    plasma: Option<Rect>,
    pitch: usize,
    plot: Option<Rect>,
    /// The velocity strip, when shown.
    velocity: Option<Rect>,
    tape: Option<StripLayout>,
}

/// The window application.
pub struct App {
    machine: Option<Box<dyn Machine>>,
    view: PanelView,
    /// The tape read on display, if any (the tape strip).
    tape: Option<crate::console::tape::TapeView>,
    plasma: Plasma,
    plot: PlotState,
    /// Each axis's velocity against time for the running block (docs/window.md).
    velocity: super::velocity::VelocityTrace,
    /// The pulse length and the interpolator's name, for the velocity strip.
    vel_units: Option<(f64, &'static str)>,
    hand: HandState,
    drive: Drive,
    waiting: Option<(Instant, u32, Waiting)>,
    shot: Shot,
    bench: Option<Bench>,
    frames: u64,
    layout: Layout,
    exit: Arc<AtomicI32>,
    status: String,
    /// A panel event may have changed program memory or tool data since the last look.
    program_dirty: bool,
    /// The frame of the last look.
    program_checked: u64,
    /// A backplot translation is running.
    translating: bool,
    /// The MTConnect adapter (`--mtconnect`): the state is published once a frame.
    feed: Option<crate::cli::mtconnect::Feed>,
}

impl App {
    /// The application around an opened console. `exit` receives the exit code.
    pub fn new(machine: Box<dyn Machine>, drive: Drive, exit: Arc<AtomicI32>) -> App {
        let view = machine.view();
        let wheel_axis = view.wheel.0;
        let bench = drive.bench_frames.map(|_| Bench::default());
        App {
            machine: Some(machine),
            view,
            tape: None,
            plasma: Plasma::new(),
            plot: PlotState::new(),
            velocity: Default::default(),
            vel_units: None,
            hand: HandState {
                wheel_axis,
                ..HandState::default()
            },
            drive,
            waiting: None,
            shot: Shot::Idle,
            bench,
            frames: 0,
            layout: Layout::default(),
            exit,
            status: String::new(),
            program_dirty: true,
            program_checked: 0,
            translating: false,
            feed: None,
        }
    }

    /// Streams to MTConnect agents through `feed` (once a frame, after the tick).
    pub fn with_feed(mut self, feed: Option<crate::cli::mtconnect::Feed>) -> App {
        self.feed = feed;
        self
    }

    fn fail(&mut self, ctx: &egui::Context, msg: String) {
        eprintln!("novanc: {msg}");
        self.exit.store(1, Ordering::SeqCst);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// Plays script events until a `wait` that is not yet satisfied.
    fn play_script(&mut self, m: &mut dyn Machine, ctx: &egui::Context) {
        if let Some((since, idle_frames, what)) = self.waiting {
            let idle = m.is_idle();
            let done = match what {
                Waiting::Idle => idle && idle_frames >= 2,
                Waiting::Block(n) => idle || m.block_executing() == Some(n),
                Waiting::Until(t) => m.view().machine_ns >= t,
            };
            self.waiting = if done {
                None
            } else if idle {
                Some((since, idle_frames + 1, what))
            } else {
                Some((since, 0, what))
            };
            if self.waiting.is_some() && since.elapsed() > self.drive.wait_limit {
                self.fail(
                    ctx,
                    format!(
                        "script 'wait': not done after {} s",
                        self.drive.wait_limit.as_secs()
                    ),
                );
                self.drive.script.clear();
                self.waiting = None;
            }
            if self.waiting.is_some() {
                return;
            }
        }
        while let Some(ev) = self.drive.script.pop_front() {
            match ev {
                PanelEvent::Wait => {
                    self.waiting = Some((Instant::now(), 0, Waiting::Idle));
                    return;
                }
                PanelEvent::WaitBlock(n) => {
                    self.waiting = Some((Instant::now(), 0, Waiting::Block(n)));
                    return;
                }
                PanelEvent::WaitMs(t) => {
                    let at = m
                        .view()
                        .machine_ns
                        .saturating_add(t.saturating_mul(1_000_000));
                    self.waiting = Some((Instant::now(), 0, Waiting::Until(at)));
                    return;
                }
                PanelEvent::Show => {
                    super::say(&format!(
                        "--- display\n{}\n---",
                        m.view().display.join("\n")
                    ));
                }
                other => {
                    self.program_dirty = true;
                    m.handle(other);
                }
            }
        }
    }

    fn script_done(&self) -> bool {
        self.drive.script.is_empty() && self.waiting.is_none()
    }

    fn screenshot(&mut self, ctx: &egui::Context) {
        let Some(path) = self.drive.screenshot.clone() else {
            return;
        };
        let ready = self.script_done()
            && !self.translating
            && !self.program_dirty
            && (self.bench.is_none() || self.drive.bench_frames.is_none());
        match self.shot.step(ctx, &path, ready) {
            None => {}
            Some(Err(e)) => self.fail(ctx, e),
            Some(Ok([w, h])) => {
                let r = |o: Option<Rect>| rect_px(o, ctx.pixels_per_point());
                let ppp = ctx.pixels_per_point();
                let tape = self.layout.tape.map_or("none".to_string(), |t| {
                    format!(
                        "{} strip {} first {} count {}",
                        r(Some(t.rect)),
                        (t.pitch * ppp).round(),
                        t.first,
                        t.count
                    )
                });
                super::say(&format!(
                    "screenshot {} {w}x{h} plasma {} pitch {} plot {} tape {tape} velocity {}",
                    path.display(),
                    r(self.layout.plasma),
                    self.layout.pitch,
                    r(self.layout.plot),
                    r(self.layout.velocity)
                ));
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    fn measure(&mut self, m: &mut dyn Machine, ctx: &egui::Context, frame: &eframe::Frame) {
        let (Some(b), Some(n)) = (self.bench.as_mut(), self.drive.bench_frames) else {
            return;
        };
        if !self.drive.script.is_empty() {
            return;
        }
        let cpu = frame.info().cpu_usage;
        if let Some(report) = b.frame(n, self.view.machine_ns, cpu, m.pulses()) {
            super::say(&report);
            self.drive.bench_frames = None;
            // With a screenshot asked for too, it is taken now, and that closes the window.
            if self.drive.screenshot.is_none() {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    /// One frame: tick the console, play the script, draw, hand the operator's actions over.
    fn frame(&mut self, m: &mut dyn Machine, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        // A stop signal closes the window as closing it does (`on_exit`: the machine stopped,
        // the recording closed); `caught` marks the recording interrupted first.
        if crate::cli::signals::caught().is_some() {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        self.frames += 1;
        m.tick();
        self.play_script(m, &ctx);
        if let Some(f) = self.feed.as_mut() {
            m.publish(f);
        }
        let was = self.view.wheel.0;
        self.view = m.view();
        self.tape = m.tape();
        let (t_ns, pos, moving) = m.motion_sample();
        // The strip's clock stops with the machine (a hold, a dwell, an E-STOP).
        self.velocity.sample(m.block_executing(), t_ns, pos, moving);
        if self.vel_units.is_none() {
            let s = m.settings();
            let what = match s.interpolator {
                crate::settings::Interpolator::Dda => "DDA",
                crate::settings::Interpolator::ErrorProportional => "EP",
            };
            self.vel_units = Some((s.pulse_mm, what));
        }
        // The handwheel axis turned by another input (a script) shows on the selector too.
        if self.view.wheel.0 != was {
            self.hand.wheel_axis = self.view.wheel.0;
        }
        // Program memory and tool data change only through panel events: look again (on the
        // backplot's own thread) after events, at most every 15 frames.
        if self.program_dirty
            && (self.program_checked == 0 || self.frames >= self.program_checked + 15)
        {
            // Read as START reads it: in the program's own dialect.
            let s = m.run_settings();
            let start = self.view.axis_mm.map(|mm| s.to_pulses(mm));
            let gcode = m.gcode_start();
            self.plot
                .request_program(m.program_text(), m.magazine(), s, start, gcode);
            self.program_dirty = false;
            self.program_checked = self.frames;
        }
        self.translating = self.plot.poll();
        self.plot.record(self.view.axis_mm);
        self.hand.scroll += ctx.input(|i| scroll_notches(&i.events));
        let mut out = Vec::new();
        let events = ctx.input(|i| i.events.clone());
        super::keys::keyboard(&events, &self.view, &mut self.hand, &mut out);
        self.draw(ui, &mut out);
        // Whole notches nobody under the pointer took are dropped.
        self.hand.scroll = self.hand.scroll.fract();
        if std::mem::take(&mut self.hand.tape_requested) {
            self.program_dirty = true;
            m.tape_from_entry();
        }
        if std::mem::take(&mut self.hand.punch_requested) {
            m.punch_from_entry();
        }
        if std::mem::take(&mut self.hand.quit_requested) {
            // The terminal's quit keys (Ctrl-C, Alt+q) close the window as closing it does.
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        for ev in out {
            self.program_dirty = true;
            self.status = format!("{ev:?}");
            m.handle(ev);
        }
        self.screenshot(&ctx);
        self.measure(m, &ctx, frame);
        let headless_busy =
            !self.script_done() || self.translating || self.bench.is_some() || self.shot.busy();
        super::schedule_repaint(&ctx, headless_busy, !m.is_idle());
    }
}

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        // The console is taken out for the frame (and put back), so that it can be finished
        // when the window closes.
        let Some(mut m) = self.machine.take() else {
            return;
        };
        self.frame(&mut *m, ui, frame);
        self.machine = Some(m);
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        // Stop the machine and close the recording, as the terminal panel does on quitting.
        if let Some(m) = self.machine.take() {
            match m.finish() {
                Ok(Some(summary)) => eprintln!("novanc: {summary}"),
                Ok(None) => {}
                Err(e) => eprintln!("novanc: recording: {e}"),
            }
        }
    }
    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        controls::ENAMEL.to_normalized_gamma_f32()
    }
}

/// Mouse-wheel movement in notches (one line = one notch, 40 points = one notch), positive up.
fn scroll_notches(events: &[egui::Event]) -> f32 {
    events
        .iter()
        .map(|e| match e {
            egui::Event::MouseWheel { unit, delta, .. } => match unit {
                egui::MouseWheelUnit::Line => delta.y,
                egui::MouseWheelUnit::Point => delta.y / 40.0,
                egui::MouseWheelUnit::Page => delta.y * 10.0,
            },
            _ => 0.0,
        })
        .sum()
}

impl App {
    fn draw(&mut self, ui: &mut egui::Ui, out: &mut Vec<PanelEvent>) {
        let view = self.view.clone();
        let frame = egui::Frame::new().fill(controls::ENAMEL).inner_margin(8.0);
        egui::Panel::bottom("relay")
            .resizable(false)
            .frame(frame.fill(Color32::from_rgb(48, 52, 56)))
            .show(ui, |ui| self.relay_panel(ui, &view, out));
        egui::Panel::left("nc")
            .resizable(false)
            .frame(frame)
            .show(ui, |ui| self.nc_panel(ui, &view, out));
        egui::CentralPanel::default().frame(frame).show(ui, |ui| {
            // The velocity strip has its own place under the backplot, which it once covered.
            let full = ui.available_rect_before_wrap();
            let strip_h = (full.height() * 0.22).clamp(60.0, 140.0);
            let plot_area =
                Rect::from_min_max(full.min, egui::pos2(full.max.x, full.max.y - strip_h - 6.0));
            let strip = Rect::from_min_max(egui::pos2(full.min.x, full.max.y - strip_h), full.max);
            let tool = view.axis_mm;
            let mut scroll = self.hand.scroll;
            let r = ui
                .scope_builder(egui::UiBuilder::new().max_rect(plot_area), |ui| {
                    self.plot.show(ui, tool, &mut scroll)
                })
                .inner;
            self.hand.scroll = scroll;
            self.layout.plot = Some(r);
            let (pulse_mm, what) = self.vel_units.unwrap_or((0.001, "DDA"));
            self.layout.velocity = Some(self.velocity.show(ui.painter(), strip, pulse_mm, what));
        });
    }

    /// The NC panel (11): plasma display, data-processing mode selector, data keys, readout.
    fn nc_panel(&mut self, ui: &mut egui::Ui, view: &PanelView, out: &mut Vec<PanelEvent>) {
        let rows = view.display.len().max(1);
        let cols = view
            .display
            .iter()
            .map(|l| l.chars().count())
            .max()
            .unwrap_or(40)
            .max(1);
        let ppp = ui.ctx().pixels_per_point();
        // The largest whole dot pitch (physical pixels) that fits 760 points across.
        let pitch = ((760.0 * ppp) / (cols * super::font::CELL_W + 1) as f32)
            .floor()
            .clamp(1.0, 6.0) as usize;
        let rect = self.plasma.show(ui, &view.display, pitch);
        self.layout.plasma = Some(rect);
        self.layout.pitch = pitch;
        let _ = rows;
        // The tape passing the read head, while a read is shown (docs/window.md).
        self.layout.tape = match &self.tape {
            Some(t) => {
                ui.add_space(4.0);
                Some(tapestrip::show(ui, t, rect.width()))
            }
            None => None,
        };
        ui.add_space(6.0);
        ui.horizontal(|ui| {
            let sel = DataMode::ALL
                .iter()
                .position(|m| *m == view.data_mode)
                .unwrap_or(0);
            ui.vertical(|ui| {
                if let Some(i) = controls::rotary(
                    ui,
                    "DATA PROCESSING MODE",
                    &DataMode::ALL.map(|m| m.names().short),
                    sel,
                    vec2(240.0, 170.0),
                    &mut self.hand,
                ) {
                    out.push(PanelEvent::Data(DataMode::ALL[i]));
                }
            });
            ui.vertical(|ui| super::keys::data_keys(ui, &mut self.hand, out, true));
            ui.vertical(|ui| controls::readout(ui, view));
        });
        ui.label(
            egui::RichText::new(format!("entry: {}", view.entry))
                .monospace()
                .color(controls::LEGEND),
        );
    }

    /// The relay panel (12): operation mode selector, buttons and lamps, feed override,
    /// handwheel, jog.
    fn relay_panel(&mut self, ui: &mut egui::Ui, view: &PanelView, out: &mut Vec<PanelEvent>) {
        ui.horizontal(|ui| {
            let sel = OpMode::ALL
                .iter()
                .position(|m| *m == view.op_mode)
                .unwrap_or(0);
            if let Some(i) = controls::rotary(
                ui,
                "OPERATION MODE",
                &OpMode::ALL.map(|m| m.names().short),
                sel,
                vec2(240.0, 170.0),
                &mut self.hand,
            ) {
                out.push(PanelEvent::Op(OpMode::ALL[i]));
            }
            ui.vertical(|ui| {
                ui.horizontal(|ui| {
                    let l = &view.lamps;
                    if controls::lamp_button(
                        ui,
                        "START",
                        Color32::from_rgb(30, 120, 40),
                        Some((l.run, controls::LAMP_RUN)),
                    )
                    .clicked()
                    {
                        out.push(PanelEvent::Start);
                    }
                    if controls::lamp_button(
                        ui,
                        "STOP",
                        Color32::from_rgb(150, 110, 20),
                        Some((l.hold, controls::LAMP_HOLD)),
                    )
                    .clicked()
                    {
                        out.push(PanelEvent::Stop);
                    }
                    if controls::lamp_button(
                        ui,
                        "RESET",
                        Color32::from_rgb(60, 70, 110),
                        Some((l.alarm, controls::LAMP_RED)),
                    )
                    .clicked()
                    {
                        out.push(PanelEvent::Reset);
                    }
                    if controls::estop_button(ui, l.estop).clicked() {
                        out.push(PanelEvent::EStop);
                    }
                });
                ui.label(egui::RichText::new("JOG").small().color(controls::LEGEND));
                controls::jog_buttons(ui, view, &mut self.hand, out);
                ui.label(
                    egui::RichText::new("PAGES  ^P ^D ^O ^E")
                        .small()
                        .color(controls::LEGEND),
                );
                controls::page_keys(ui, view, out);
            });
            let ov_labels: Vec<String> = (0..=15)
                .map(|i| {
                    if i % 5 == 0 {
                        format!("{}", i * 10)
                    } else {
                        String::new()
                    }
                })
                .collect();
            let ov_refs: Vec<&str> = ov_labels.iter().map(String::as_str).collect();
            let sel = (view.feed_override / 10).min(15) as usize;
            if let Some(i) = controls::rotary(
                ui,
                &format!("FEED OVERRIDE {} %", view.feed_override),
                &ov_refs,
                sel,
                vec2(170.0, 170.0),
                &mut self.hand,
            ) {
                out.push(PanelEvent::Override(i as u32 * 10));
            }
            controls::switches(ui, view, out);
            ui.vertical(|ui| {
                ui.label(
                    egui::RichText::new("MANUAL PULSE GENERATOR")
                        .small()
                        .color(controls::LEGEND),
                );
                ui.horizontal(|ui| {
                    controls::handwheel(ui, &mut self.hand, out);
                    ui.vertical(|ui| controls::wheel_selectors(ui, view, &mut self.hand, out));
                });
            });
        });
        if !self.status.is_empty() {
            ui.label(
                egui::RichText::new(format!("last action: {}", self.status))
                    .small()
                    .color(Color32::GRAY),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scroll_is_counted_in_notches() {
        let evs = vec![egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Line,
            delta: vec2(0.0, 2.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: Default::default(),
        }];
        assert_eq!(scroll_notches(&evs), 2.0);
    }
}
