//! The front-panel controls drawn with egui: rotary selectors, the relay-panel buttons with
//! their lamps, the feed-override knob, the handwheel (manual pulse generator 12b), the jog
//! buttons and the position readout (the data keys are in `keys`).
//! Each widget only draws the `PanelView` and turns the operator's clicks, drags, scrolls and
//! keys into `PanelEvent`s; the console decides what they mean.

use crate::panel_model::{Axis, PanelEvent, PanelView};
use egui::{
    pos2, vec2, Align2, Color32, FontId, Pos2, Rect, Response, Sense, Stroke, StrokeKind, Ui,
};
use std::f32::consts::PI;

/// Panel paint: the grey enamel of the cabinet.
pub const ENAMEL: Color32 = Color32::from_rgb(58, 62, 66);
/// Legend paint on the panel.
pub const LEGEND: Color32 = Color32::from_rgb(225, 225, 215);
/// The RUN lamp.
pub const LAMP_RUN: Color32 = Color32::from_rgb(110, 230, 60);
/// The feed-hold lamp.
pub const LAMP_HOLD: Color32 = Color32::from_rgb(255, 190, 40);
/// The e-stop and alarm lamps.
pub const LAMP_RED: Color32 = Color32::from_rgb(255, 50, 40);

/// What the operator's hands hold between frames: shift latched, the handwheel axis switch,
/// half-turned detents, a held jog button, scroll not yet worth a notch.
#[derive(Debug)]
pub struct HandState {
    /// SHIFT (15c) latched for the next data key.
    pub shift: bool,
    /// Handwheel axis selector position.
    pub wheel_axis: Axis,
    /// Handwheel angle not yet a whole detent, radians.
    pub wheel_rest: f32,
    /// Handwheel dimple angle, radians (drawn).
    pub wheel_angle: f32,
    /// Mouse-wheel scroll of this frame, in notches (positive turns clockwise / up).
    pub scroll: f32,
    /// The jog button held down, if any.
    pub jog_held: Option<(Axis, i8)>,
    /// The axis key held down for a CONTINUOUS jog, if any.
    pub key_jog: Option<egui::Key>,
    /// A JOG button held long enough to jog continuously (`HOLD_TO_JOG`).
    pub jog_continuous: bool,
    /// When the JOG button held now was pressed.
    pub jog_since: std::time::Instant,
}

impl Default for HandState {
    fn default() -> Self {
        HandState {
            shift: false,
            wheel_axis: Axis::X,
            wheel_rest: 0.0,
            wheel_angle: 0.0,
            scroll: 0.0,
            jog_held: None,
            key_jog: None,
            jog_continuous: false,
            jog_since: std::time::Instant::now(),
        }
    }
}

/// Detents per handwheel turn.
pub const DETENTS_PER_TURN: f32 = 100.0;

/// Takes the whole notches of this frame's scroll for a hovered widget.
fn take_scroll(hand: &mut HandState, hovered: bool) -> i32 {
    if !hovered {
        return 0;
    }
    let n = hand.scroll.trunc();
    hand.scroll -= n;
    n as i32
}

/// Angle (radians, 0 = up, clockwise positive) of position `i` of `n` on a rotary switch
/// whose positions span `sweep` radians.
fn position_angle(i: usize, n: usize, sweep: f32) -> f32 {
    if n <= 1 {
        return 0.0;
    }
    -sweep / 2.0 + sweep * i as f32 / (n - 1) as f32
}

fn at_angle(c: Pos2, r: f32, a: f32) -> Pos2 {
    pos2(c.x + r * a.sin(), c.y - r * a.cos())
}

/// A rotary selector with `labels.len()` positions (empty labels are unmarked detents).
/// Click a position (or near it) to turn there; scroll over it to turn one detent; drag the knob.
/// Returns the newly chosen position.
pub fn rotary(
    ui: &mut Ui,
    title: &str,
    labels: &[&str],
    selected: usize,
    size: egui::Vec2,
    hand: &mut HandState,
) -> Option<usize> {
    let n = labels.len();
    let (rect, resp) = ui.allocate_exact_size(size, Sense::click_and_drag());
    if n == 0 {
        return None;
    }
    let p = ui.painter_at(rect);
    let c = pos2(rect.center().x, rect.min.y + rect.height() * 0.56);
    let knob_r = rect.height() * 0.2;
    let label_r = knob_r * 2.0;
    let sweep = if n > 9 { 1.5 * PI } else { 1.35 * PI };
    p.text(
        pos2(rect.center().x, rect.min.y + 2.0),
        Align2::CENTER_TOP,
        title,
        FontId::proportional(12.0),
        LEGEND,
    );
    for (i, l) in labels.iter().enumerate() {
        let a = position_angle(i, n, sweep);
        let col = if i == selected { LAMP_HOLD } else { LEGEND };
        p.line_segment(
            [at_angle(c, knob_r * 1.08, a), at_angle(c, knob_r * 1.3, a)],
            Stroke::new(1.5, col),
        );
        if !l.is_empty() {
            p.text(
                at_angle(c, label_r, a),
                Align2::CENTER_CENTER,
                *l,
                FontId::proportional(11.0),
                col,
            );
        }
    }
    p.circle_filled(c, knob_r, Color32::from_rgb(25, 25, 28));
    p.circle_stroke(
        c,
        knob_r,
        Stroke::new(2.0, Color32::from_rgb(120, 120, 125)),
    );
    let a = position_angle(selected.min(n.saturating_sub(1)), n, sweep);
    p.line_segment(
        [at_angle(c, knob_r * 0.2, a), at_angle(c, knob_r * 0.95, a)],
        Stroke::new(4.0, Color32::WHITE),
    );
    let nearest = |pt: Pos2| -> usize {
        let v = pt - c;
        let ang = v.x.atan2(-v.y);
        (0..n)
            .min_by(|&i, &j| {
                let di = (position_angle(i, n, sweep) - ang).abs();
                let dj = (position_angle(j, n, sweep) - ang).abs();
                di.total_cmp(&dj)
            })
            .unwrap_or(selected)
    };
    let mut chosen = None;
    if resp.clicked() || resp.dragged() {
        if let Some(pt) = resp.interact_pointer_pos() {
            chosen = Some(nearest(pt));
        }
    }
    let notches = take_scroll(hand, resp.hovered());
    if notches != 0 {
        let to = (selected as i64 + notches as i64).clamp(0, n as i64 - 1) as usize;
        chosen = Some(to);
    }
    chosen.filter(|&i| i != selected && i < n)
}

/// The operation mode selector (17), every window's: a rotary with its seven positions (the
/// centre's and a lathe's are the same selector). The position newly turned to, if any.
pub fn op_selector(
    ui: &mut Ui,
    mode: crate::panel_model::OpMode,
    size: egui::Vec2,
    hand: &mut HandState,
) -> Option<crate::panel_model::OpMode> {
    use crate::panel_model::OpMode;
    let sel = OpMode::ALL.iter().position(|m| *m == mode).unwrap_or(0);
    let labels = OpMode::ALL.map(|m| m.names().short);
    rotary(ui, "OPERATION MODE", &labels, sel, size, hand).map(|i| OpMode::ALL[i])
}

/// The feed override switch, every window's: 0 to 150 % in 10 % steps. The percentage newly
/// turned to, if any.
pub fn override_switch(
    ui: &mut Ui,
    pct: u32,
    size: egui::Vec2,
    hand: &mut HandState,
) -> Option<u32> {
    let labels: Vec<String> = (0..=15)
        .map(|i| {
            if i % 5 == 0 {
                format!("{}", i * 10)
            } else {
                String::new()
            }
        })
        .collect();
    let refs: Vec<&str> = labels.iter().map(String::as_str).collect();
    let title = format!("FEED OVERRIDE {pct} %");
    let sel = (pct / 10).min(15) as usize;
    rotary(ui, &title, &refs, sel, size, hand).map(|i| i as u32 * 10)
}

/// A push button with a lamp above it; returns the button's response.
pub fn lamp_button(
    ui: &mut Ui,
    label: &str,
    face: Color32,
    lamp: Option<(bool, Color32)>,
) -> Response {
    let (rect, resp) = ui.allocate_exact_size(vec2(74.0, 70.0), Sense::click());
    let p = ui.painter_at(rect);
    if let Some((on, col)) = lamp {
        let lc = pos2(rect.center().x, rect.min.y + 9.0);
        let fill = if on { col } else { col.gamma_multiply(0.18) };
        if on {
            p.circle_filled(lc, 10.0, col.gamma_multiply(0.25));
        }
        p.circle_filled(lc, 6.0, fill);
    }
    let b = Rect::from_min_max(
        pos2(rect.min.x + 4.0, rect.min.y + 22.0),
        pos2(rect.max.x - 4.0, rect.max.y - 2.0),
    );
    let down = resp.is_pointer_button_down_on();
    let f = if down {
        face.gamma_multiply(0.7)
    } else if resp.hovered() {
        face.gamma_multiply(1.15)
    } else {
        face
    };
    p.rect_filled(b, 6.0, f);
    p.rect_stroke(b, 6.0, Stroke::new(1.0, Color32::BLACK), StrokeKind::Inside);
    p.text(
        b.center(),
        Align2::CENTER_CENTER,
        label,
        FontId::proportional(13.0),
        Color32::WHITE,
    );
    resp
}

/// The relay panel's START, STOP and RESET with their lamps lit by `lit` (RUN green, feed
/// hold amber, alarm red) and the E-STOP (ringed red while `lit[3]`), side by side, as both
/// machines have them: the button clicked, as the panel event it is.
pub fn relay_buttons(ui: &mut Ui, lit: [bool; 4]) -> Option<crate::panel_model::PanelEvent> {
    use crate::panel_model::PanelEvent as E;
    let mut out = None;
    ui.horizontal(|ui| {
        let buttons = [
            ("START", Color32::from_rgb(30, 120, 40), LAMP_RUN, E::Start),
            ("STOP", Color32::from_rgb(150, 110, 20), LAMP_HOLD, E::Stop),
            ("RESET", Color32::from_rgb(60, 70, 110), LAMP_RED, E::Reset),
        ];
        for ((label, face, lamp, ev), on) in buttons.into_iter().zip(lit) {
            if lamp_button(ui, label, face, Some((on, lamp))).clicked() {
                out = Some(ev);
            }
        }
        if estop_button(ui, lit[3]).clicked() {
            out = Some(E::EStop);
        }
    });
    out
}

/// The emergency stop: a red mushroom head on a yellow collar, with its lamp.
pub fn estop_button(ui: &mut Ui, on: bool) -> Response {
    let (rect, resp) = ui.allocate_exact_size(vec2(84.0, 84.0), Sense::click());
    let p = ui.painter_at(rect);
    let c = rect.center();
    p.circle_filled(c, 40.0, Color32::from_rgb(230, 190, 20));
    let head = if resp.is_pointer_button_down_on() || on {
        Color32::from_rgb(150, 10, 10)
    } else {
        Color32::from_rgb(210, 20, 20)
    };
    p.circle_filled(c, 30.0, head);
    p.text(
        c,
        Align2::CENTER_CENTER,
        "E-STOP",
        FontId::proportional(12.0),
        Color32::WHITE,
    );
    if on {
        p.circle_stroke(c, 38.0, Stroke::new(3.0, LAMP_RED));
    }
    resp
}

/// The handwheel: drag round it or scroll over it; emits `Wheel(axis, detents)`.
pub fn handwheel(ui: &mut Ui, hand: &mut HandState, out: &mut Vec<PanelEvent>) {
    let (rect, resp) = ui.allocate_exact_size(vec2(130.0, 130.0), Sense::drag());
    let p = ui.painter_at(rect);
    let c = rect.center();
    let r = 58.0;
    p.circle_filled(c, r, Color32::from_rgb(30, 30, 34));
    for k in 0..DETENTS_PER_TURN as usize {
        let a = hand.wheel_angle + k as f32 * 2.0 * PI / DETENTS_PER_TURN;
        let len = if k % 10 == 0 { 9.0 } else { 4.0 };
        p.line_segment(
            [at_angle(c, r - len, a), at_angle(c, r, a)],
            Stroke::new(1.0, LEGEND),
        );
    }
    p.circle_filled(c, r * 0.55, Color32::from_rgb(70, 70, 76));
    p.circle_filled(at_angle(c, r * 0.72, hand.wheel_angle), 7.0, Color32::BLACK);
    let mut detents = 0i32;
    if resp.dragged() {
        if let Some(pt) = resp.interact_pointer_pos() {
            let prev = pt - resp.drag_delta();
            let a1 = (pt - c).x.atan2(-(pt - c).y);
            let a0 = (prev - c).x.atan2(-(prev - c).y);
            let mut d = a1 - a0;
            if d > PI {
                d -= 2.0 * PI;
            } else if d < -PI {
                d += 2.0 * PI;
            }
            hand.wheel_rest += d;
            let step = 2.0 * PI / DETENTS_PER_TURN;
            let whole = (hand.wheel_rest / step).trunc();
            hand.wheel_rest -= whole * step;
            detents += whole as i32;
        }
    }
    detents += take_scroll(hand, resp.hovered());
    if detents != 0 {
        hand.wheel_angle += detents as f32 * 2.0 * PI / DETENTS_PER_TURN;
        out.push(PanelEvent::Wheel(hand.wheel_axis, detents));
    }
}

/// The handwheel's axis (one of `axes`) and the ×1/×10/×100/×1000 increment selector (also
/// STEP's), `scale` lit: every machine's.
pub fn wheel_selectors(
    ui: &mut Ui,
    axes: &[Axis],
    scale: u32,
    hand: &mut HandState,
    out: &mut Vec<PanelEvent>,
) {
    ui.horizontal(|ui| {
        for &a in axes {
            if ui
                .selectable_label(hand.wheel_axis == a, a.letter().to_string())
                .clicked()
            {
                // The console's selector too (the terminal's Alt+a): its Alt+, and Alt+. act on
                // it, a detent in HANDLE, a jog in CONTINUOUS and STEP.
                hand.wheel_axis = a;
                out.push(PanelEvent::Wheel(a, 0));
            }
        }
    });
    // Two axes (a lathe's): the increments in two rows, as the jog buttons, to keep the
    // manual column inside the default window (×1000 was cut off its edge).
    let per_row = if axes.len() > 2 { 4 } else { 2 };
    for row in [1u32, 10, 100, 1000].chunks(per_row) {
        ui.horizontal(|ui| {
            for &s in row {
                if ui.selectable_label(scale == s, format!("×{s}")).clicked() && scale != s {
                    out.push(PanelEvent::WheelScale(s));
                }
            }
        });
    }
}

/// The jog buttons of `axes` (CONTINUOUS, `continuous`: move while held; STEP: one increment
/// per press): a press is the console's key for the axis direction (`key`), so that a press
/// does what the keyboard's does; held past [`HOLD_TO_JOG`] in CONTINUOUS, a jog until let go.
/// A rotary axis's press selects it on the handwheel's selector and is Alt+, or Alt+. (the
/// keyboard's jog of the selected axis), as an operator with a pendant does.
pub fn jog_buttons(
    ui: &mut Ui,
    axes: &[Axis],
    continuous: bool,
    key: fn(Axis, i8) -> novanc_panel::Key,
    hand: &mut HandState,
    out: &mut Vec<PanelEvent>,
) {
    let mut held_now = None;
    let mut buttons = |ui: &mut Ui, axes: &[Axis]| {
        for &a in axes {
            for dir in [-1i8, 1] {
                let sign = if dir < 0 { '−' } else { '+' };
                let r = ui.add(
                    egui::Button::new(format!("{}{sign}", a.letter()))
                        .min_size(vec2(30.0, 24.0))
                        .sense(Sense::click_and_drag()),
                );
                if r.is_pointer_button_down_on() {
                    held_now = Some((a, dir));
                }
            }
        }
    };
    if axes.len() > 2 {
        // X Y Z on a row, the rotary axes on the next.
        for row in axes.chunks(3) {
            ui.horizontal(|ui| buttons(ui, row));
        }
    } else {
        // Two axes (a lathe's X and Z): one row each, so that the manual column is no wider
        // than the handwheel (at the default 1400-point window, Z+ was cut off the edge).
        for a in axes.chunks(1) {
            ui.horizontal(|ui| buttons(ui, a));
        }
    }
    if held_now != hand.jog_held {
        if hand.jog_held.is_some() && hand.jog_continuous {
            out.push(PanelEvent::JogRelease);
        }
        hand.jog_continuous = false;
        hand.jog_since = std::time::Instant::now();
        if let Some((a, d)) = held_now {
            // The press is the terminal's key: one increment (docs/panel.md, "Jogging").
            if a.index() >= crate::block::FIRST_ROTARY {
                hand.wheel_axis = a;
                out.push(PanelEvent::Wheel(a, 0));
                out.push(PanelEvent::Press(novanc_panel::Key::Alt(if d < 0 {
                    ','
                } else {
                    '.'
                })));
            } else {
                out.push(PanelEvent::Press(key(a, d)));
            }
        }
        hand.jog_held = held_now;
    } else if let Some((a, d)) = held_now {
        // Held past HOLD_TO_JOG in CONTINUOUS: jog until the button is let go.
        if !hand.jog_continuous && continuous && hand.jog_since.elapsed() > HOLD_TO_JOG {
            out.push(PanelEvent::Jog(a, d));
            hand.jog_continuous = true;
        }
    }
}

/// How long a JOG button must be held in CONTINUOUS before the axis jogs continuously (a
/// shorter press is one increment), about a keyboard's repeat delay.
pub const HOLD_TO_JOG: std::time::Duration = std::time::Duration::from_millis(300);

/// The row of page keys beside the selectors (docs/panel.md, "Pages"): POS, PROG, OFS, MSG,
/// MODAL, I/O, MACRO, the one shown lit; a click is the page key (Ctrl-P/D/O/E/G/T/U).
pub fn page_keys(ui: &mut Ui, view: &PanelView, out: &mut Vec<PanelEvent>) {
    ui.horizontal(|ui| {
        for (page, ch) in crate::panel_model::Page::KEYS
            .iter()
            .zip(['p', 'd', 'o', 'e', 'g', 't', 'u'])
        {
            let b = egui::Button::new(egui::RichText::new(page.label()).monospace())
                .min_size(vec2(48.0, 24.0))
                .selected(view.page == *page);
            if ui.add(b).clicked() {
                out.push(PanelEvent::Press(novanc_panel::Key::Ctrl(ch)));
            }
        }
    });
}

/// The position readout: axis positions, tool tip, tool, spindle, feed override, RUN, time.
pub fn readout(ui: &mut Ui, view: &PanelView) {
    let big = FontId::monospace(20.0);
    // The terminal's heading: degrees named when the machine has a rotary axis.
    let title = if view.rotary_deg.is_empty() {
        "POSITION mm"
    } else {
        "POSITION mm, deg"
    };
    ui.label(egui::RichText::new(title).small().color(LEGEND));
    let rows = ['X', 'Y', 'Z'].iter().zip(view.axis_mm);
    for (a, v) in rows.chain(view.rotary_deg.iter().map(|(r, d)| (r, *d))) {
        ui.add(
            egui::Label::new(
                egui::RichText::new(format!("{a}{v:>10.3}"))
                    .font(big.clone())
                    .color(Color32::from_rgb(140, 255, 200)),
            )
            .extend(),
        );
    }
    let small = |ui: &mut Ui, s: String| {
        ui.add(egui::Label::new(egui::RichText::new(s).monospace().color(LEGEND)).extend());
    };
    small(ui, format!("tip Z {:>10.3}", view.tip_mm[2]));
    let tool = view.tool.map_or("T--".to_string(), |t| format!("T{t:02}"));
    small(ui, format!("{tool}  S {}", view.spindle));
    small(
        ui,
        format!(
            "RUN {}  F {}%  {:.1} s",
            view.run,
            view.feed_override,
            view.machine_ns as f64 / 1e9
        ),
    );
}

/// The rapid override (each click one step down, as Alt+f) and the spindle override (− and +,
/// as Alt+[ and Alt+]), every window's: each button sends what the terminal key does.
pub fn override_buttons(
    ui: &mut egui::Ui,
    (rapid, spindle): (u32, u32),
    out: &mut Vec<PanelEvent>,
) {
    let label = match rapid {
        0 => "RAPID F0".to_string(),
        p => format!("RAPID {p} %"),
    };
    if ui.button(label).clicked() {
        out.push(PanelEvent::Press(novanc_panel::Key::Alt('f')));
    }
    ui.horizontal(|ui| {
        if ui.small_button("-").clicked() {
            out.push(PanelEvent::Press(novanc_panel::Key::Alt('[')));
        }
        ui.label(format!("SPINDLE {spindle} %"));
        if ui.small_button("+").clicked() {
            out.push(PanelEvent::Press(novanc_panel::Key::Alt(']')));
        }
    });
}

/// A switch's event, given the position it is turned to.
type Turn = fn(bool) -> PanelEvent;

/// The rapid and spindle overrides and the DRY RUN, MACHINE LOCK, Z NEGLECT, BLOCK DELETE and
/// OPTIONAL STOP switches: each button sends what the terminal key does (docs/window.md). Before
/// stop 49 the centre's window had no BLOCK DELETE or OPTIONAL STOP button (the lathe's had).
pub fn switches(ui: &mut egui::Ui, view: &PanelView, out: &mut Vec<PanelEvent>) {
    ui.vertical(|ui| {
        ui.label(
            egui::RichText::new("OVERRIDES / SWITCHES")
                .small()
                .color(LEGEND),
        );
        let sw = &view.switches;
        override_buttons(ui, (sw.rapid_override, sw.spindle_override), out);
        let p = &view.program_switches;
        let rows: [(bool, &str, Turn); 5] = [
            (sw.dry_run, "DRY RUN", PanelEvent::DryRun),
            (sw.machine_lock, "MACHINE LOCK", PanelEvent::MachineLock),
            (sw.z_neglect, "Z NEGLECT", PanelEvent::ZNeglect),
            (p.block_delete, "BLOCK DELETE", PanelEvent::BlockDelete),
            (p.optional_stop, "OPTIONAL STOP", PanelEvent::OptionalStop),
        ];
        for (on, name, ev) in rows {
            if ui.selectable_label(on, name).clicked() {
                out.push(ev(!on));
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_span_the_sweep_symmetrically() {
        let s = 1.35 * PI;
        assert_eq!(position_angle(0, 7, s), -s / 2.0);
        assert!((position_angle(6, 7, s) - s / 2.0).abs() < 1e-6);
        assert!(position_angle(3, 7, s).abs() < 1e-6);
        assert_eq!(position_angle(0, 1, s), 0.0);
    }

    #[test]
    fn scroll_is_taken_in_whole_notches_by_the_hovered_widget_only() {
        let mut h = HandState {
            scroll: 2.5,
            ..HandState::default()
        };
        assert_eq!(take_scroll(&mut h, false), 0);
        assert_eq!(take_scroll(&mut h, true), 2);
        assert!((h.scroll - 0.5).abs() < 1e-6);
    }

    /// One egui frame with these input events, the widget at the top left of a 400×300 screen.
    fn frame(ctx: &egui::Context, t: f64, events: Vec<egui::Event>, mut f: impl FnMut(&mut Ui)) {
        let raw = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, vec2(400.0, 300.0))),
            time: Some(t),
            events,
            ..Default::default()
        };
        ctx.run_ui(raw, |ui| f(ui)).drop_without_applying_deltas();
    }

    fn press(pos: Pos2, pressed: bool) -> egui::Event {
        egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        }
    }

    const LABELS: [&str; 7] = ["A", "B", "C", "D", "E", "F", "G"];

    #[test]
    fn clicking_a_position_of_a_rotary_selector_turns_it_there() {
        let ctx = egui::Context::default();
        let mut hand = HandState::default();
        let size = vec2(240.0, 170.0);
        // The knob centre and the label radius, as `rotary` lays them out at the top left.
        let c = pos2(size.x / 2.0, size.y * 0.56);
        let target = at_angle(c, size.y * 0.2 * 2.0, position_angle(5, 7, 1.35 * PI));
        let mut got = Vec::new();
        let evs = [
            vec![egui::Event::PointerMoved(target)],
            vec![press(target, true)],
            vec![press(target, false)],
            vec![],
        ];
        for (i, e) in evs.into_iter().enumerate() {
            frame(&ctx, i as f64 * 0.05, e, |ui| {
                got.push(rotary(ui, "T", &LABELS, 1, size, &mut hand));
            });
        }
        assert!(got.contains(&Some(5)), "{got:?}");
        assert!(!got.iter().any(|g| matches!(g, Some(i) if *i != 5)));
    }

    #[test]
    fn scrolling_over_a_rotary_selector_turns_it_one_detent_per_notch_within_its_ends() {
        let ctx = egui::Context::default();
        let mut hand = HandState::default();
        let size = vec2(240.0, 170.0);
        let over = pos2(120.0, 95.0);
        let mut got = None;
        for (i, (notches, sel)) in [(0.0, 3), (2.0, 3), (-9.0, 1)].into_iter().enumerate() {
            hand.scroll = notches;
            frame(
                &ctx,
                i as f64 * 0.05,
                vec![egui::Event::PointerMoved(over)],
                |ui| {
                    got = rotary(ui, "T", &LABELS, sel, size, &mut hand);
                },
            );
            match i {
                1 => assert_eq!(got, Some(5)),
                2 => assert_eq!(got, Some(0), "clamped at the first position"),
                _ => {}
            }
        }
        // Scroll with the pointer elsewhere turns nothing.
        hand.scroll = 1.0;
        frame(
            &ctx,
            1.0,
            vec![egui::Event::PointerMoved(pos2(390.0, 290.0))],
            |ui| {
                got = rotary(ui, "T", &LABELS, 3, size, &mut hand);
            },
        );
        assert_eq!(got, None);
    }

    /// On a trunnion the JOG buttons have a row for B and C (stop 55; before, a mouse could turn
    /// the table only with the handwheel in HANDLE): a press selects the axis on the
    /// handwheel's selector and is the keyboard's Alt+, or Alt+., one increment.
    #[test]
    fn a_rotary_axis_s_jog_buttons_select_it_and_press_its_jog_key() {
        let ctx = egui::Context::default();
        let mut hand = HandState::default();
        let axes = [Axis::X, Axis::Y, Axis::Z, Axis::B, Axis::C];
        let mut pressed = Vec::new();
        let mut t = 0.0;
        // Press and let go at every point across the second row, in turn.
        for x in (2..300).step_by(4) {
            let at = pos2(x as f32, 42.0);
            let mut out = Vec::new();
            for e in [
                vec![egui::Event::PointerMoved(at)],
                vec![press(at, true)],
                vec![press(at, false)],
            ] {
                t += 0.05;
                frame(&ctx, t, e, |ui| {
                    jog_buttons(
                        ui,
                        &axes,
                        true,
                        |_, _| novanc_panel::Key::Up,
                        &mut hand,
                        &mut out,
                    )
                });
            }
            match out.as_slice() {
                [] => {}
                [PanelEvent::Wheel(a, 0), PanelEvent::Press(novanc_panel::Key::Alt(k))] => {
                    let d = if *k == '.' { 1 } else { -1 };
                    if pressed.last() != Some(&(*a, d)) {
                        pressed.push((*a, d));
                    }
                }
                other => panic!("at x {x}: {other:?}"),
            }
        }
        assert_eq!(
            pressed,
            [(Axis::B, -1), (Axis::B, 1), (Axis::C, -1), (Axis::C, 1)]
        );
        assert_eq!(hand.wheel_axis, Axis::C);
    }

    #[test]
    fn the_handwheel_turns_by_scroll_on_the_selected_axis() {
        let ctx = egui::Context::default();
        let mut hand = HandState {
            wheel_axis: Axis::Z,
            ..HandState::default()
        };
        let mut out = Vec::new();
        frame(
            &ctx,
            0.0,
            vec![egui::Event::PointerMoved(pos2(65.0, 65.0))],
            |ui| {
                handwheel(ui, &mut hand, &mut out);
            },
        );
        hand.scroll = -3.0;
        frame(
            &ctx,
            0.1,
            vec![egui::Event::PointerMoved(pos2(65.0, 65.0))],
            |ui| {
                handwheel(ui, &mut hand, &mut out);
            },
        );
        assert_eq!(out, vec![PanelEvent::Wheel(Axis::Z, -3)]);
    }
}
