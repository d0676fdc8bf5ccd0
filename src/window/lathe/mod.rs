//! The lathe's part of the window (`novanc --window --machine citizen`, docs/window.md
//! "The lathe window"): every channel side by side with its readout and a backplot of its tool
//! tip in the Z–X plane, the selected channel's plasma display and the operator's panel. The
//! one application (`app::App`) drives it as a [`Front`], as it drives the centre's: each frame
//! it advances the same `LatheConsole` as the terminal's (by wall time, or by a script's waits
//! in virtual time), draws `LatheView`, and hands keys and clicks back as
//! `LatheConsole::press` / `LatheConsole::handle`.

mod panel;
pub mod plot;

use super::app::{Front, Wait};
use super::controls::{self, HandState};
use super::plasma::Plasma;
use super::shot::rect_px;
use crate::lathe::console::{LatheConsole, LatheView, RunUntil};
use crate::mtconnect::feed::Feed;
use crate::panel_model::PanelEvent;
use egui::{Color32, Rect};
use panel::Act;
use plot::Trail;
use std::time::Instant;

/// Machine time of one step of the clock, ns: the backplot samples every tip after each.
pub const STEP_NS: u64 = 2_000_000;

/// The rectangles a test needs to read a screenshot.
#[derive(Clone, Debug, Default)]
struct Layout {
    plasma: Option<Rect>,
    pitch: usize,
    /// Each channel's travel box and detail box.
    plots: Vec<(Rect, Rect)>,
    /// The operator's panel along the bottom (plasma, relay, data keys, manual controls), as
    /// laid out: wider than the window, it scrolls sideways.
    panel: Option<Rect>,
}

/// A channel's programmed path as the backplot draws it (the centre's `backplot::Segment`s),
/// and what it was read from.
#[derive(Default)]
struct Programmed {
    /// A hash of the program text, the channel's tools, the switches and the last load it
    /// was read with: read again when one of them changes (looked at every frame, so no
    /// text is formatted for it).
    key: Option<u64>,
    path: Vec<crate::backplot::Segment>,
}

/// The lathe's console in the window.
pub struct Lathe {
    console: LatheConsole,
    view: LatheView,
    trails: Vec<Trail>,
    /// Each channel's program as the next START would read it (`LatheConsole::programmed`).
    programmed: Vec<Programmed>,
    plasma: Plasma,
    hand: HandState,
    layout: Layout,
}

impl Lathe {
    /// The window's part around an opened console.
    pub fn new(console: LatheConsole) -> Lathe {
        let mut l = Lathe {
            view: console.view(),
            trails: Vec::new(),
            programmed: Vec::new(),
            console,
            plasma: Plasma::new(),
            hand: HandState::default(),
            layout: Layout::default(),
        };
        l.clear_paths();
        l.sample();
        l
    }

    /// Reads again each channel's program (the selected channel's MDI lines in MDI) whose
    /// text, tools, switches or last load changed, for the backplot's programmed path. A program that does not read draws no path (START
    /// says why).
    fn look_programs(&mut self) {
        let c = &self.console;
        let n = c.desc().channels.len();
        self.programmed.resize_with(n, Default::default);
        for (ch, p) in self.programmed.iter_mut().enumerate() {
            let key = {
                use std::hash::{Hash, Hasher};
                let mut h = std::collections::hash_map::DefaultHasher::new();
                c.program_to_run(ch).hash(&mut h);
                for t in &c.desc().channels[ch].tools {
                    (
                        t.number,
                        t.tip,
                        t.radius.to_bits(),
                        t.offset.map(f64::to_bits),
                    )
                        .hash(&mut h);
                }
                (c.switches(), c.cycle().started_ns()).hash(&mut h);
                Some(h.finish())
            };
            if key == p.key {
                continue;
            }
            p.key = key;
            let Some(settings) = crate::settings::MachineSettings::lathe_channel(c.desc(), ch)
            else {
                continue;
            };
            p.path = match c.programmed(ch) {
                Some(Ok(st)) => {
                    crate::backplot::Backplot::from_statements(st.into_iter().map(Ok), &settings)
                        .segments
                }
                _ => Vec::new(),
            };
        }
    }

    /// Empties every channel's trail.
    fn clear_paths(&mut self) {
        self.trails = vec![Trail::default(); self.console.desc().channels.len()];
    }

    /// Takes every channel's tip into its trail.
    fn sample(&mut self) {
        let mm = self.console.desc().pulse_mm;
        for (t, (pos, work)) in self.trails.iter_mut().zip(self.console.tips()) {
            t.push_tagged([pos[0] as f64 * mm, 0.0, pos[1] as f64 * mm], work);
        }
    }

    /// Advances the machine `ns` in steps of `STEP_NS`, sampling after each.
    fn advance(&mut self, ns: u64) {
        self.advance_until(ns, RunUntil::Time);
    }

    /// [`Lathe::advance`], ending with the step in which `until` holds (`LatheConsole::step`):
    /// whether it does.
    fn advance_until(&mut self, ns: u64, until: RunUntil) -> bool {
        let mut left = ns;
        while left > 0 {
            let n = left.min(STEP_NS);
            let reached = self.console.step(n, until);
            self.sample();
            if reached {
                return true;
            }
            left -= n;
        }
        false
    }

    fn panels(&mut self, ui: &mut egui::Ui, out: &mut Vec<Act>) {
        let v = self.view.clone();
        let c = &self.console;
        let frame = egui::Frame::new().fill(controls::ENAMEL).inner_margin(8.0);
        egui::Panel::top("lathe-summary")
            .frame(frame.fill(Color32::from_rgb(30, 32, 36)))
            .show(ui, |ui| panel::summary(ui, &v, out));
        egui::Panel::bottom("lathe-panel")
            .frame(frame.fill(Color32::from_rgb(48, 52, 56)))
            .show(ui, |ui| {
                // A window narrower than the panel scrolls it sideways: no control is out of
                // the operator's reach.
                let width = ui.available_width();
                egui::ScrollArea::horizontal().show(ui, |ui| {
                    let row = ui.horizontal_top(|ui| {
                        ui.vertical(|ui| {
                            let max = egui::vec2(width * 0.4, 330.0);
                            let (r, pitch) = self.plasma.show_fit(ui, &v.display, max, 4);
                            self.layout.plasma = Some(r);
                            self.layout.pitch = pitch;
                        });
                        ui.add_space(8.0);
                        ui.vertical(|ui| {
                            let (modes, sw) = ((c.mode(), c.page()), c.switches());
                            let hand = &mut self.hand;
                            let ovr = (sw, c.feed_override(), c.machine_switches());
                            panel::relay(ui, &v, modes, ovr, hand, out)
                        });
                        ui.add_space(8.0);
                        ui.vertical(|ui| panel::data_keys(ui, &mut self.hand, out));
                        ui.add_space(8.0);
                        ui.vertical(|ui| {
                            panel::manual(ui, c.mode(), c.increment(), &mut self.hand, out)
                        });
                    });
                    self.layout.panel = Some(row.response.rect);
                });
            });
        egui::CentralPanel::default().frame(frame).show(ui, |ui| {
            if v.help {
                panel::help(ui);
                self.layout.plots.clear();
            } else {
                let target = c.counter().target;
                let paths: Vec<&[crate::backplot::Segment]> =
                    self.programmed.iter().map(|p| &p.path[..]).collect();
                self.layout.plots =
                    panel::channels(ui, &v, c.desc(), (&self.trails, &paths), target, out);
            }
        });
    }
}

impl Front for Lathe {
    type Ev = PanelEvent;

    fn tick(&mut self, wall_ns: Option<u64>) {
        if let Some(ns) = wall_ns {
            self.advance(ns);
        }
    }
    fn event(&mut self, ev: PanelEvent) {
        self.console.handle(ev);
        self.sample();
    }
    fn machine_ns(&self) -> u64 {
        self.console.machine_ns()
    }
    fn begin_wait(&mut self, w: Wait) {
        // The machine knows it is busy only once it has ticked (after a START, say), so a
        // wait takes one step first, as `novanc script`'s does.
        if w != Wait::Rest {
            return;
        }
        self.advance(STEP_NS);
    }
    fn pursue(&mut self, w: Wait, deadline: Instant) -> bool {
        if let Wait::Block(n) = w {
            // The selected channel's block N: each step runs to its start at most, so the
            // wait ends with the tick it starts in (or at rest), as `novanc script`'s.
            let until = RunUntil::Block(self.console.selected(), n);
            while Instant::now() <= deadline {
                if self.advance_until(16 * STEP_NS, until) {
                    return true;
                }
            }
            return false;
        }
        loop {
            let done = match w {
                Wait::Until(t) => self.console.machine_ns() >= t,
                Wait::Rest | Wait::Block(_) => self.console.at_rest(),
            };
            if done {
                return true;
            }
            if Instant::now() > deadline {
                return false;
            }
            for _ in 0..16 {
                let n = match w {
                    Wait::Until(t) => t.saturating_sub(self.console.machine_ns()).min(STEP_NS),
                    _ => STEP_NS,
                };
                if n == 0 || (w == Wait::Rest && self.console.at_rest()) {
                    break;
                }
                self.advance(n);
            }
        }
    }
    fn show(&self) -> String {
        self.console.frame_text()
    }
    fn stuck(&self) -> Option<String> {
        self.console
            .stalled()
            .then(|| crate::console::wait::stalled_note(0))
    }
    fn moving(&self) -> bool {
        !self.console.at_rest()
    }
    fn draw(&mut self, ui: &mut egui::Ui, events: &[egui::Event]) -> bool {
        self.view = self.console.view();
        self.look_programs();
        let jogs = super::keys::holds_jog(self.console.mode(), self.console.page());
        let (evs, quit) = super::keys::keyboard(events, jogs, &mut self.hand);
        let mut acts: Vec<Act> = (evs.into_iter())
            .map(|e| match e {
                PanelEvent::Press(k) => Act::Press(k),
                e => Act::Ev(e),
            })
            .collect();
        self.panels(ui, &mut acts);
        for a in acts {
            match a {
                Act::Ev(ev) => self.console.handle(ev),
                Act::Press(k) => self.console.press(k),
                Act::ClearPaths => self.clear_paths(),
            }
            self.sample();
        }
        quit
    }
    fn layout(&self, ppp: f32) -> String {
        let plots: Vec<String> = self
            .layout
            .plots
            .iter()
            .enumerate()
            .map(|(i, (t, d))| {
                format!(
                    "plot{} {} detail{} {}",
                    i + 1,
                    rect_px(Some(*t), ppp),
                    i + 1,
                    rect_px(Some(*d), ppp)
                )
            })
            .collect();
        format!(
            "plasma {} pitch {} {} panel {}",
            rect_px(self.layout.plasma, ppp),
            self.layout.pitch,
            plots.join(" "),
            rect_px(self.layout.panel, ppp)
        )
    }
    fn pulses(&self) -> u64 {
        // Every channel's axes since the kernel began (`--bench-frames`).
        let c = self.console.cycle();
        (0..self.console.desc().channels.len())
            .map(|ch| c.totals(ch).1.iter().sum::<u64>())
            .sum()
    }
    fn publish(&self, feed: &mut Feed) {
        feed.publish_lathe(&self.console)
    }
    fn close(self, interrupted: Option<&str>) {
        crate::console::Panel::Lathe(Box::new(self.console)).close_saying(interrupted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lathe::desc::LatheDesc;
    use crate::window::app::{tests::play_all, App, Drive, Step};
    use std::path::PathBuf;
    use std::sync::atomic::AtomicI32;
    use std::sync::Arc;

    fn app(name: &str, steps: Vec<Step<PanelEvent>>) -> (App<Lathe>, PathBuf) {
        let d =
            std::env::temp_dir().join(format!("novanc-lathe-window-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        let (c, _) = LatheConsole::open(LatheDesc::citizen(), &d, 12, 40, None).unwrap();
        let drive = Drive {
            script: steps.into(),
            scripted: true,
            ..Drive::default()
        };
        let a = App::new(Lathe::new(c), drive, Arc::new(AtomicI32::new(0)), None);
        (a, d)
    }

    #[test]
    fn a_script_wait_after_start_runs_the_cycle_to_rest_in_virtual_time() {
        let (mut a, d) = app(
            "wait",
            vec![Step::Ev(PanelEvent::Start), Step::Wait(Wait::Rest)],
        );
        let l = play_all(&mut a);
        let c = &l.console;
        assert!(c.at_rest());
        assert_eq!(
            c.counter().counts,
            vec![5, 5, 5],
            "the 5-part run, all of it"
        );
        assert!(c.machine_ns() > 60_000_000_000, "{} ns", c.machine_ns());
        // Every channel's trail holds its cuts, tagged with the works 1 to 5.
        for t in &l.trails {
            let works: std::collections::BTreeSet<u32> =
                t.tagged().filter_map(|(_, w)| w).collect();
            assert_eq!(works.into_iter().collect::<Vec<_>>(), vec![1, 2, 3, 4, 5]);
        }
        let _ = std::fs::remove_dir_all(d);
    }

    #[test]
    fn a_script_wait_block_ends_with_the_selected_channels_block_executing() {
        // Block 12 of CH2's program (system2.ngc as read) is its line 18, the arc.
        let evs = crate::console::Panel::read_script(
            Some(&LatheDesc::citizen()),
            "channel 2\nstart\nwait block 12\n",
        )
        .unwrap();
        let steps = crate::window::app::script_steps(evs);
        let (mut a, d) = app("waitblock", steps);
        let l = play_all(&mut a);
        let v = l.console.view();
        assert_eq!(v.selected, 1);
        let ch2 = &v.channels[1];
        assert_eq!(
            (ch2.state.as_str(), ch2.line, ch2.text.as_str()),
            ("RUN", 18, "G2 X16 Z-7 R3"),
            "{ch2:?}"
        );
        assert!(!l.console.at_rest(), "the cycle runs on");
        let _ = std::fs::remove_dir_all(d);
    }

    #[test]
    fn a_script_wait_ms_lets_exactly_that_machine_time_pass() {
        let (mut a, d) = app(
            "waitms",
            vec![Step::Ev(PanelEvent::Start), Step::WaitMs(1_234)],
        );
        let l = play_all(&mut a);
        assert_eq!(l.console.machine_ns(), 1_234_000_000);
        assert!(!l.console.at_rest(), "the cycle runs on");
        let _ = std::fs::remove_dir_all(d);
    }
}
