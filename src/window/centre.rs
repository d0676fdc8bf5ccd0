//! The machining centre's part of the window (docs/window.md, "What it shows"): each frame it
//! takes the console's `PanelView`, draws the plasma display, selectors, relay panel, data
//! keys, readout, backplot and velocity strip, and hands the operator's actions back as
//! `PanelEvent`s. The one application (`app::App`) drives it as a [`Front`].

use super::app::{Front, Wait};
use super::controls::{self, HandState};
use super::plasma::Plasma;
use super::plot::PlotState;
use super::shot::rect_px;
use super::tapestrip::{self, StripLayout};
use crate::console::Console;
use crate::mtconnect::feed::Feed;
use crate::panel_model::{Axis, DataMode, OpMode, PanelEvent, PanelView};
use egui::{vec2, Color32, Rect};
use std::sync::Arc;
use std::time::Instant;

/// The screen rectangles a test needs to read a screenshot (points).
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    plasma: Option<Rect>,
    pitch: usize,
    plot: Option<Rect>,
    /// The velocity strip, when shown.
    velocity: Option<Rect>,
    tape: Option<StripLayout>,
}

/// The machining centre's console in the window.
pub struct Centre {
    console: Console,
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
    layout: Layout,
    status: String,
    frames: u64,
    /// A panel event may have changed program memory or tool data since the last look.
    program_dirty: bool,
    /// The frame of the last look.
    program_checked: u64,
    /// A backplot translation is running.
    translating: bool,
    /// A script wait begun in this frame: it is first looked at in the next, after the
    /// console's tick has taken the pulse core's state.
    wait_fresh: bool,
    /// Frames the machine has been idle in a row during a `wait`.
    idle_frames: u32,
}

impl Centre {
    /// The window's part around an opened console.
    pub fn new(console: Console) -> Centre {
        let view = console.view();
        let wheel_axis = view.wheel.0;
        Centre {
            console,
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
            layout: Layout::default(),
            status: String::new(),
            frames: 0,
            program_dirty: true,
            program_checked: 0,
            translating: false,
            wait_fresh: false,
            idle_frames: 0,
        }
    }

    /// The N number of the block executing now, if one is.
    fn block_executing(&self) -> Option<u32> {
        let st = self.console.status();
        st.executing
            .as_ref()
            .filter(|_| st.in_block)
            .and_then(|e| e.block())
            .map(|b| b.seq)
    }

    /// What the frame shows: the view, the tape strip, the velocity strip's sample, and the
    /// backplot's program looked at again after events.
    fn look(&mut self) {
        let c = &self.console;
        let was = self.view.wheel.0;
        self.view = c.view();
        self.tape = c.tape_view();
        let st = c.status();
        let (t_ns, pos, moving) = (st.machine_ns, st.pos.xyz(), st.moving && !st.estop);
        // The strip's clock stops with the machine (a hold, a dwell, an E-STOP).
        let block = self.block_executing();
        self.velocity.sample(block, t_ns, pos, moving);
        if self.vel_units.is_none() {
            let s = self.console.settings();
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
            let c = &self.console;
            // Read as START reads it: in the program's own dialect.
            let s = c.run_settings_for(!c.run_text_is_mdi());
            let start = self.view.axis_mm.map(|mm| s.to_pulses(mm));
            let gcode = c
                .run_text_is_gcode()
                .then(|| super::plot::GcodeStart::State {
                    state: Box::new(c.interp_state().clone()),
                    mdi: c.run_text_is_mdi(),
                    subs: Some(Arc::new(c.subroutines())),
                });
            self.plot
                .request_program(c.run_text(), c.magazine(), s, start, gcode);
            self.program_dirty = false;
            self.program_checked = self.frames;
        }
        self.translating = self.plot.poll();
        self.plot.record(self.view.axis_mm);
    }
}

impl Front for Centre {
    type Ev = PanelEvent;

    fn tick(&mut self, _wall_ns: Option<u64>) {
        // The pulse core keeps its own clock: the tick takes its state.
        self.frames += 1;
        self.console.tick();
    }
    fn event(&mut self, ev: PanelEvent) {
        self.program_dirty = true;
        self.console.handle(ev);
    }
    fn machine_ns(&self) -> u64 {
        self.console.status().machine_ns
    }
    fn begin_wait(&mut self, _w: Wait) {
        self.wait_fresh = true;
        self.idle_frames = 0;
    }
    fn pursue(&mut self, w: Wait, _deadline: Instant) -> bool {
        if std::mem::take(&mut self.wait_fresh) {
            return false;
        }
        let idle = self.console.is_idle();
        let done = match w {
            Wait::Rest => idle && self.idle_frames >= 2,
            Wait::Block(n) => idle || self.block_executing() == Some(n),
            Wait::Until(t) => self.machine_ns() >= t,
        };
        self.idle_frames = if idle { self.idle_frames + 1 } else { 0 };
        done
    }
    fn show(&self) -> String {
        self.console.view().display.join("\n")
    }
    fn stuck(&self) -> Option<String> {
        let s = self.console.status();
        s.stalled
            .then(|| crate::console::wait::stalled_note(s.feed_override))
    }
    fn moving(&self) -> bool {
        !self.console.is_idle()
    }
    fn settling(&self) -> bool {
        self.translating || self.program_dirty
    }
    fn draw(&mut self, ui: &mut egui::Ui, events: &[egui::Event]) -> bool {
        self.look();
        let ctx = ui.ctx().clone();
        self.hand.scroll += ctx.input(|i| scroll_notches(&i.events));
        let jogs = super::keys::holds_jog(self.view.op_mode, self.view.page);
        let (mut out, quit) = super::keys::keyboard(events, jogs, &mut self.hand);
        self.panels(ui, &mut out);
        // Whole notches nobody under the pointer took are dropped.
        self.hand.scroll = self.hand.scroll.fract();
        for ev in out {
            self.program_dirty = true;
            self.status = format!("{ev:?}");
            self.console.handle(ev);
        }
        quit
    }
    fn layout(&self, ppp: f32) -> String {
        let r = |o: Option<Rect>| rect_px(o, ppp);
        let tape = self.layout.tape.map_or("none".to_string(), |t| {
            format!(
                "{} strip {} first {} count {}",
                r(Some(t.rect)),
                (t.pitch * ppp).round(),
                t.first,
                t.count
            )
        });
        format!(
            "plasma {} pitch {} plot {} tape {tape} velocity {}",
            r(self.layout.plasma),
            self.layout.pitch,
            r(self.layout.plot),
            r(self.layout.velocity)
        )
    }
    fn pulses(&self) -> u64 {
        self.console.status().pulses.iter().sum()
    }
    fn publish(&self, feed: &mut Feed) {
        feed.publish(&self.console)
    }
    fn close(self, interrupted: Option<&str>) {
        crate::console::Panel::Centre(Box::new(self.console)).close_saying(interrupted)
    }
}

/// X Y Z and the machine's rotary axes, as the readout shows them.
fn machine_axes(view: &PanelView) -> Vec<Axis> {
    let rotary = view.rotary_deg.iter();
    [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .chain(rotary.filter_map(|(r, _)| Axis::from_word(&r.to_string())))
        .collect()
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

impl Centre {
    fn panels(&mut self, ui: &mut egui::Ui, out: &mut Vec<PanelEvent>) {
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
        // The largest whole dot pitch (physical pixels) that fits 760 points across.
        let max = vec2(760.0, f32::INFINITY);
        let rect = if view.help > 0 {
            // The help screen (F8, Alt+H), the terminal's pages: every key of the panel, then
            // the editor's commands and the pages. Any other key closes it and acts.
            let lines = match view.help {
                2 => crate::console::help::HELP_EDITOR,
                _ => crate::console::help::HELP,
            };
            let r = egui::Frame::new().fill(Color32::BLACK).show(ui, |ui| {
                ui.set_width(max.x);
                for l in lines {
                    let t = egui::RichText::new(*l).monospace().size(11.5);
                    ui.label(t.color(Color32::from_rgb(255, 150, 40)));
                }
            });
            r.response.rect
        } else {
            let (rect, pitch) = self.plasma.show_fit(ui, &view.display, max, 6);
            self.layout.pitch = pitch;
            rect
        };
        self.layout.plasma = Some(rect);
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
            ui.vertical(|ui| super::keys::data_keys(ui, &mut self.hand, out));
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
            let size = vec2(240.0, 170.0);
            if let Some(m) = controls::op_selector(ui, view.op_mode, size, &mut self.hand) {
                out.push(PanelEvent::Op(m));
            }
            ui.vertical(|ui| {
                let l = &view.lamps;
                out.extend(controls::relay_buttons(
                    ui,
                    [l.run, l.hold, l.alarm, l.estop],
                ));
                ui.label(egui::RichText::new("JOG").small().color(controls::LEGEND));
                // X Y Z, and the machine's rotary axes on a row of their own.
                controls::jog_buttons(
                    ui,
                    &machine_axes(view),
                    view.op_mode == OpMode::Continuous,
                    super::keys::arrow_key,
                    &mut self.hand,
                    out,
                );
                ui.label(
                    egui::RichText::new("PAGES  ^P ^D ^O ^E")
                        .small()
                        .color(controls::LEGEND),
                );
                controls::page_keys(ui, view, out);
            });
            let size = vec2(170.0, 170.0);
            if let Some(p) = controls::override_switch(ui, view.feed_override, size, &mut self.hand)
            {
                out.push(PanelEvent::Override(p));
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
                    ui.vertical(|ui| {
                        let axes = machine_axes(view);
                        controls::wheel_selectors(ui, &axes, view.wheel.1, &mut self.hand, out)
                    });
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
