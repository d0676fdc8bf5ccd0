//! The lathe window's panels (docs/window.md, "The lathe window"): the title and summary lines
//! on top, one column per channel with its readout and backplot, and the operator's panel at
//! the bottom (the selected channel's plasma display, the relay buttons, the channel and mode
//! selectors, FAULT and TARGET, the switches and the data keys). Each control only draws the
//! `LatheView` and hands the operator's action back as an [`Act`]; the console decides.

use super::plot::{self, Trail};
use crate::lathe::console::view::ChanView;
use crate::lathe::console::LatheView;
use crate::lathe::desc::LatheDesc;
use crate::panel_model::{OpMode, Page, PanelEvent};
use crate::window::controls::{self, HandState};
use egui::{vec2, Color32, Rect, RichText, Sense, Stroke, StrokeKind, Ui};
use novanc_panel::Key;

/// The title line's colour.
pub const LIT: Color32 = Color32::from_rgb(255, 220, 60);
/// Text on the panel.
pub const TEXT: Color32 = Color32::from_rgb(210, 212, 205);
/// FAULT, ALARM, ESTOP.
pub const RED: Color32 = Color32::from_rgb(255, 70, 60);

/// An operator action from the window.
#[derive(Clone, Debug, PartialEq)]
pub enum Act {
    /// An event for `LatheConsole::handle`.
    Ev(PanelEvent),
    /// A key for `LatheConsole::press` (FAULT and TARGET take the typed line).
    Press(Key),
    /// Clear every channel's backplot.
    ClearPaths,
}

/// The colour of a state word.
pub fn state_colour(state: &str) -> Color32 {
    match state {
        "FAULT" | "ALARM" | "ESTOP" => RED,
        "RUN" => controls::LAMP_RUN,
        "WAIT" | "HOLD" | "STOP" => controls::LAMP_HOLD,
        "DONE" => Color32::from_rgb(120, 180, 255),
        _ => Color32::from_rgb(160, 160, 160),
    }
}

fn mono(t: impl Into<String>, size: f32, c: Color32) -> RichText {
    RichText::new(t).monospace().size(size).color(c)
}

/// The title and one summary line per channel: the selected one lit and marked, a faulted,
/// alarmed or stopped one red. Clicking a line selects its channel.
pub fn summary(ui: &mut Ui, v: &LatheView, out: &mut Vec<Act>) {
    ui.label(mono(&v.title, 16.0, LIT).strong());
    for (i, l) in v.summary.iter().enumerate() {
        let state = v.channels.get(i).map_or("", |c| c.state.as_str());
        let colour = match state {
            "FAULT" | "ALARM" | "ESTOP" => RED,
            _ if i == v.selected => LIT,
            _ => TEXT,
        };
        let mut t = mono(l.trim_end(), 14.0, colour);
        if i == v.selected {
            t = t.strong().background_color(Color32::from_rgb(40, 44, 30));
        }
        let r = ui.add(egui::Label::new(t).sense(Sense::click()));
        if r.clicked() && i != v.selected {
            out.push(Act::Ev(PanelEvent::Channel(i)));
        }
    }
}

/// Millimetres of `p` pulses, three decimals.
fn mm(p: i64, pulse_mm: f64) -> String {
    format!("{:9.3}", p as f64 * pulse_mm)
}

/// One channel's readout: name and state, whom it waits for (or the fault), the current
/// block, X as a diameter and Z, rpm and tool, the work and chuck, the part count.
fn readout(ui: &mut Ui, i: usize, c: &ChanView, pulse_mm: f64, target: u32) {
    ui.horizontal_wrapped(|ui| {
        ui.label(mono(format!("CH{} {}", i + 1, c.name), 15.0, TEXT).strong());
        ui.label(mono(&c.state, 15.0, state_colour(&c.state)).strong());
    });
    // Whom it waits for, or the fault or alarm, else the program's name.
    let (what, colour) = if !c.waits.is_empty() {
        (format!("waits for {}", c.waits), controls::LAMP_HOLD)
    } else if !c.note.is_empty() {
        let red = matches!(c.state.as_str(), "FAULT" | "ALARM" | "ESTOP");
        (c.note.clone(), if red { RED } else { controls::LAMP_HOLD })
    } else {
        (format!("program {}", c.program), Color32::GRAY)
    };
    ui.label(mono(what, 13.0, colour));
    let block = if c.line > 0 {
        format!("{:04} {}", c.line, c.text.trim())
    } else {
        String::new()
    };
    ui.label(mono(block, 13.0, TEXT));
    // The program's coordinates, as the plasma's (docs/lathe-gcode.md "Work offsets").
    let at = c.work_pos();
    ui.label(mono(
        format!(
            "X{} (dia)  Z{}  G{}",
            mm(at[0] * 2, pulse_mm),
            mm(at[1], pulse_mm),
            54 + c.system.map_or(0, |s| s.0)
        ),
        14.0,
        Color32::WHITE,
    ));
    let work = match c.work {
        Some(w) => format!("W{w}"),
        None => "EMPTY".into(),
    };
    // Wrapped in a narrow column (a window 1000 points wide): the chuck and the part count
    // go to a line of their own rather than over the next channel's readout.
    ui.horizontal_wrapped(|ui| {
        ui.label(mono(
            format!("S{:6.0} rpm  T{:02}  ", c.rpm, c.tool),
            13.0,
            TEXT,
        ));
        let wc = c.work.map_or(plot::EMPTY, plot::work_colour);
        ui.label(mono(work, 13.0, wc).strong());
        ui.label(mono(
            format!(
                " CHUCK {}{}  parts {}/{}",
                if c.chuck { "CLOSED" } else { "OPEN" },
                c.aux_text(),
                c.parts,
                target
            ),
            13.0,
            TEXT,
        ));
    });
}

/// The channels side by side, each its readout over its backplot: the whole travel box, and
/// under it the detail of the cuts. Returns each channel's travel box and detail box on
/// screen.
pub fn channels(
    ui: &mut Ui,
    v: &LatheView,
    desc: &LatheDesc,
    (trails, programmed): (&[Trail], &[&[crate::backplot::Segment]]),
    target: u32,
    out: &mut Vec<Act>,
) -> Vec<(Rect, Rect)> {
    let n = v.channels.len().max(1);
    let mut boxes = vec![(Rect::NOTHING, Rect::NOTHING); n];
    ui.columns(n, |cols| {
        for (i, ui) in cols.iter_mut().enumerate() {
            let (Some(c), Some(ch), Some(trail)) =
                (v.channels.get(i), desc.channels.get(i), trails.get(i))
            else {
                continue;
            };
            let top = ui.cursor().min;
            readout(ui, i, c, desc.pulse_mm, target);
            ui.add_space(4.0);
            let programmed = programmed.get(i).copied().unwrap_or(&[]);
            let d = plot::PlotData {
                ch,
                pulse_mm: desc.pulse_mm,
                trail,
                programmed,
                current: c.work,
                tip: c.pos,
                system: c.system.unwrap_or((0, [0, 0])),
            };
            let travel = plot::Box2::travel(ch);
            let detail = plot::detail_of(&d, travel);
            // The overview as tall as the travel box at the column's width needs, at most
            // 40 % of the room; the detail takes the rest.
            let w = ui.available_width();
            let room = ui.available_height().max(140.0);
            let span = ((travel.x[1] - travel.x[0]) / (travel.z[1] - travel.z[0]).max(1e-3)) as f32;
            let over_h = ((w - 32.0) * span + 32.0).min(room * 0.4).max(60.0);
            let (over, r1) = ui.allocate_exact_size(vec2(w, over_h), Sense::click());
            ui.add_space(4.0);
            let det_h = ui.available_height().max(80.0);
            let (det, r2) = ui.allocate_exact_size(vec2(w, det_h), Sense::click());
            let b1 = plot::draw_overview(ui.painter(), over, &d, detail);
            let b2 = plot::draw_detail(ui.painter(), det, &d, detail.unwrap_or(travel));
            boxes[i] = (b1, b2);
            // The selected channel's column is framed; a click on a column selects it.
            let col = Rect::from_min_max(top - vec2(3.0, 3.0), det.max + vec2(3.0, 3.0));
            if i == v.selected {
                ui.painter()
                    .rect_stroke(col, 4.0, Stroke::new(2.0, LIT), StrokeKind::Outside);
            }
            if (r1.clicked() || r2.clicked()) && i != v.selected {
                out.push(Act::Ev(PanelEvent::Channel(i)));
            }
        }
    });
    boxes
}

/// The help screen, in place of the channels.
pub fn help(ui: &mut Ui) {
    for (i, l) in crate::console::help::LATHE_HELP.iter().enumerate() {
        let c = if i == 0 { LIT } else { TEXT };
        ui.label(mono(*l, 14.0, c));
    }
}

/// What the relay buttons' lamps show: the machine runs (`view::runs`: not while every
/// channel stands stopped between blocks or waits on one that does), some channel holds or
/// stands stopped, is faulted or alarmed, or the machine is in E-STOP.
fn lamps(v: &LatheView) -> [bool; 4] {
    let any = |w: &[&str]| v.channels.iter().any(|c| w.contains(&c.state.as_str()));
    [
        crate::lathe::console::view::runs(&v.channels),
        any(&["HOLD", "STOP"]),
        any(&["FAULT", "ALARM"]),
        any(&["ESTOP"]),
    ]
}

/// The relay buttons, the channel selector and the OFS and MSG page keys, the operation selector and
/// the feed override (the centre's, `controls::op_selector`, `controls::override_switch`),
/// FAULT, TARGET and the switches.
pub fn relay(
    ui: &mut Ui,
    v: &LatheView,
    (mode, page): (OpMode, Page),
    (switches, feed_override, set): ((bool, bool), u32, crate::record::Switches),
    hand: &mut HandState,
    out: &mut Vec<Act>,
) {
    out.extend(controls::relay_buttons(ui, lamps(v)).and_then(lathe_ev));
    let key = |ui: &mut Ui, label: &str, lit: bool, w: f32| {
        let fill = if lit {
            Color32::from_rgb(150, 120, 30)
        } else {
            Color32::from_rgb(78, 84, 92)
        };
        ui.add(
            egui::Button::new(RichText::new(label).size(13.0).color(Color32::WHITE))
                .min_size(vec2(w, 26.0))
                .fill(fill)
                .stroke(Stroke::new(1.0, Color32::BLACK)),
        )
    };
    ui.add_space(4.0);
    ui.horizontal(|ui| {
        ui.label(mono("CHANNEL", 12.0, controls::LEGEND));
        for i in 0..v.channels.len() {
            let r = key(ui, &format!("CH{}", i + 1), i == v.selected, 52.0)
                .on_hover_text("the channel selector (Tab)");
            if r.clicked() && i != v.selected {
                out.push(Act::Ev(PanelEvent::Channel(i)));
            }
        }
        // The tool offsets page over the selector (lit while it is up): the page key again,
        // or a mode turned, leaves it.
        let r =
            key(ui, "OFS", page == Page::Ofs, 52.0).on_hover_text("the tool offsets page (Ctrl+O)");
        if r.clicked() {
            out.push(Act::Press(Key::Ctrl('o')));
        }
        let r = key(ui, "MSG", page == Page::Msg, 52.0)
            .on_hover_text("the alarm and message history (Ctrl+E)");
        if r.clicked() {
            out.push(Act::Press(Key::Ctrl('e')));
        }
    });
    ui.horizontal(|ui| {
        if let Some(m) = controls::op_selector(ui, mode, vec2(160.0, 110.0), hand) {
            out.push(Act::Ev(PanelEvent::Op(m)));
        }
        if let Some(p) = controls::override_switch(ui, feed_override, vec2(120.0, 110.0), hand) {
            out.push(Act::Ev(PanelEvent::Override(p)));
        }
    });
    // Under the rotaries, so that the panel is no wider than the selector and the override.
    ui.horizontal(|ui| {
        let mut evs = Vec::new();
        controls::override_buttons(ui, (set.rapid_override, set.spindle_override), &mut evs);
        out.extend(evs.into_iter().map(|e| match e {
            PanelEvent::Press(k) => Act::Press(k),
            e => Act::Ev(e),
        }));
        // (Here, where the row has room: the rows below are as wide as the panel allows.)
        if key(ui, "HOME", false, 48.0)
            .on_hover_text(
                "the selected channel's reference return: X out to the top, then Z (Alt+0)",
            )
            .clicked()
        {
            out.push(Act::Ev(PanelEvent::Home));
        }
    });
    ui.horizontal(|ui| {
        if key(ui, "FAULT", false, 60.0)
            .on_hover_text("stop the selected channel with the typed reason (Alt+X)")
            .clicked()
        {
            out.push(Act::Press(Key::Alt('x')));
        }
        if key(ui, "TARGET", false, 60.0)
            .on_hover_text("the typed number is the part target (Alt+N)")
            .clicked()
        {
            out.push(Act::Press(Key::Alt('n')));
        }
        if key(ui, "M01", switches.0, 44.0)
            .on_hover_text("OPTIONAL STOP (Alt+O)")
            .clicked()
        {
            out.push(Act::Ev(PanelEvent::OptionalStop(!switches.0)));
        }
        if key(ui, "/DEL", switches.1, 44.0)
            .on_hover_text("BLOCK DELETE (Alt+B)")
            .clicked()
        {
            out.push(Act::Ev(PanelEvent::BlockDelete(!switches.1)));
        }
        if key(ui, "DRY", set.dry_run, 44.0)
            .on_hover_text("DRY RUN: feed moves at the jog feed (Alt+D)")
            .clicked()
        {
            out.push(Act::Ev(PanelEvent::DryRun(!set.dry_run)));
        }
        if key(ui, "MLK", set.machine_lock, 44.0)
            .on_hover_text("MACHINE LOCK: the programs run, the axes stay (Alt+L)")
            .clicked()
        {
            out.push(Act::Press(Key::Alt('l')));
        }
    });
    ui.horizontal(|ui| {
        if key(ui, "HELP", v.help, 60.0)
            .on_hover_text("the key list (F8)")
            .clicked()
        {
            out.push(Act::Press(Key::F(8)));
        }
        if key(ui, "CLEAR PATHS", false, 96.0)
            .on_hover_text("clear every backplot")
            .clicked()
        {
            out.push(Act::ClearPaths);
        }
        // The other pages over the selector, lit while up (the page key again leaves one).
        for (label, p, k, tip) in [
            (
                "POS",
                Page::Pos,
                'p',
                "the channel's position and distance to go (Ctrl+P)",
            ),
            (
                "MACRO",
                Page::Macro,
                'u',
                "the channel's variables (Ctrl+U)",
            ),
            (
                "MODAL",
                Page::Modal,
                'g',
                "the channel's modal state (Ctrl+G)",
            ),
        ] {
            if key(ui, label, page == p, 60.0).on_hover_text(tip).clicked() {
                out.push(Act::Press(Key::Ctrl(k)));
            }
        }
    });
}

/// A control the two machines' panels share, if the lathe has a use for it.
fn lathe_ev(e: PanelEvent) -> Option<Act> {
    crate::lathe::console::events::takes(&e)
        .is_ok()
        .then_some(Act::Ev(e))
}

/// The manual controls, the centre's on the lathe's axes: the jog buttons (X up and down, Z
/// along the spindle), the handwheel, its axis and the increment.
pub fn manual(ui: &mut Ui, mode: OpMode, increment: u32, hand: &mut HandState, out: &mut Vec<Act>) {
    let axes = [crate::panel_model::Axis::X, crate::panel_model::Axis::Z];
    let mut evs = Vec::new();
    ui.label(mono("JOG", 12.0, controls::LEGEND));
    controls::jog_buttons(
        ui,
        &axes,
        mode == OpMode::Continuous,
        crate::lathe::console::events::jog_key,
        hand,
        &mut evs,
    );
    ui.label(mono("MANUAL PULSE GENERATOR", 12.0, controls::LEGEND));
    controls::handwheel(ui, hand, &mut evs);
    controls::wheel_selectors(ui, &axes, increment, hand, &mut evs);
    out.extend(evs.into_iter().filter_map(|e| match e {
        PanelEvent::Press(k) => Some(Act::Press(k)),
        e => lathe_ev(e),
    }));
}

/// The data keys (the mill's, without the tape keys), as lathe events.
pub fn data_keys(ui: &mut Ui, hand: &mut HandState, out: &mut Vec<Act>) {
    let mut evs = Vec::new();
    crate::window::keys::data_keys(ui, hand, &mut evs);
    out.extend(evs.into_iter().filter_map(lathe_ev));
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lamps_follow_the_channels_states() {
        let ch = |s: &str| ChanView {
            state: s.into(),
            ..Default::default()
        };
        let mut v = LatheView {
            title: String::new(),
            summary: vec![],
            display: vec![],
            channels: vec![ch("RUN"), ch("WAIT"), ch("IDLE")],
            selected: 0,
            help: false,
            machine_ns: 0,
        };
        assert_eq!(lamps(&v), [true, false, false, false]);
        v.channels[0] = ch("FAULT");
        v.channels[1] = ch("HOLD");
        assert_eq!(lamps(&v), [false, true, true, false]);
        // SINGLE BLOCK: one channel stopped between blocks, the others waiting on it.
        v.channels = vec![ch("STOP"), ch("WAIT"), ch("WAIT")];
        assert_eq!(lamps(&v), [false, true, false, false]);
        v.channels = vec![ch("ESTOP"); 3];
        assert_eq!(lamps(&v), [false, false, false, true]);
        assert_eq!(state_colour("ESTOP"), RED);
    }
}
