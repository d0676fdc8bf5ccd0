//! The lathe window's backplot (docs/window.md, "The lathe window"): one channel's tool-tip
//! path in the Z–X plane, Z to the right and X (the radius) up at equal scale, inside the
//! channel's travel box. The path is the trail of positions the window sampled after every step
//! of the machine, the centre's executed path (`crate::backplot::Trail`) with each point tagged
//! with the work in the spindle, drawn in that work's colour — the work now in the spindle bright and thick, earlier works
//! dimmed, moves with an empty spindle grey.

use crate::lathe::desc::ChannelDesc;
/// The programmed path's colours: the centre's backplot's.
pub use crate::window::pathdraw::{ARC, FEED, RAPID};
use egui::{pos2, vec2, Align2, Color32, FontId, Painter, Pos2, Rect, Shape, Stroke, StrokeKind};

/// A channel's trail: its tool tip's positions, mm [X radius, 0, Z], each with the work in the
/// spindle then.
pub type Trail = crate::backplot::Trail<Option<u32>>;

/// The plot's background.
pub const PLOT_BG: Color32 = Color32::from_rgb(8, 12, 20);
/// The travel box.
pub const FRAME: Color32 = Color32::from_rgb(150, 155, 165);
/// The spindle centreline (X = 0) and the work face (Z = 0).
pub const AXIS_LINE: Color32 = Color32::from_rgb(70, 78, 92);
/// Moves with an empty spindle.
pub const EMPTY: Color32 = Color32::from_rgb(120, 120, 130);
/// The tool tip's cross-hair.
pub const TIP: Color32 = Color32::from_rgb(255, 70, 70);
/// The works' colours, work N taking colour (N − 1) mod 6.
pub const WORK_COLOURS: [Color32; 6] = [
    Color32::from_rgb(0, 255, 140),
    Color32::from_rgb(80, 190, 255),
    Color32::from_rgb(255, 210, 40),
    Color32::from_rgb(255, 110, 220),
    Color32::from_rgb(160, 255, 60),
    Color32::from_rgb(255, 150, 60),
];

/// The colour of work `w`.
pub fn work_colour(w: u32) -> Color32 {
    WORK_COLOURS[(w.saturating_sub(1) % WORK_COLOURS.len() as u32) as usize]
}

/// An earlier work's colour: half as bright, opaque (the latest work drawn over the others).
pub fn dim(c: Color32) -> Color32 {
    Color32::from_rgb(c.r() / 2, c.g() / 2, c.b() / 2)
}

/// A box in the Z–X plane, mm: X (radius) from `x[0]` to `x[1]`, Z from `z[0]` to `z[1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Box2 {
    /// X (radius) range, mm.
    pub x: [f64; 2],
    /// Z range, mm.
    pub z: [f64; 2],
}

impl Box2 {
    /// The channel's travel box.
    pub fn travel(ch: &ChannelDesc) -> Box2 {
        Box2 {
            x: ch.axes[0].travel,
            z: ch.axes[1].travel,
        }
    }
}

/// Maps a box of the Z–X plane (mm) into a plot rectangle at equal scale, Z right, X up.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The box on screen.
    pub rect: Rect,
    /// Points per mm.
    pub scale: f32,
    z0: f64,
    x0: f64,
}

impl Frame {
    /// The largest picture of `b` that fits `area` less `margin` on every side, centred.
    pub fn fit(area: Rect, margin: f32, b: Box2) -> Frame {
        let zspan = (b.z[1] - b.z[0]).max(1e-3) as f32;
        let xspan = (b.x[1] - b.x[0]).max(1e-3) as f32;
        let inner = area.shrink(margin);
        let scale = (inner.width() / zspan)
            .min(inner.height() / xspan)
            .max(1e-3);
        let size = vec2(zspan * scale, xspan * scale);
        Frame {
            rect: Rect::from_center_size(inner.center(), size),
            scale,
            z0: b.z[0],
            x0: b.x[0],
        }
    }

    /// The screen point of (X radius, Z) in mm.
    pub fn at(&self, x_mm: f64, z_mm: f64) -> Pos2 {
        pos2(
            self.rect.min.x + ((z_mm - self.z0) as f32) * self.scale,
            self.rect.max.y - ((x_mm - self.x0) as f32) * self.scale,
        )
    }

    /// The box this frame shows (its rectangle's edges, mm).
    pub fn shown(&self) -> Box2 {
        let s = f64::from(self.scale);
        Box2 {
            x: [self.x0, self.x0 + f64::from(self.rect.height()) / s],
            z: [self.z0, self.z0 + f64::from(self.rect.width()) / s],
        }
    }
}

/// The detail view's box: what the trail covered with a work in the spindle (the cuts) and
/// the tip, 12 % and 1 mm more on every side, at least 4 mm across, kept inside the travel.
/// `None` before anything was cut.
pub fn detail_box(trail: &Trail, tip: [i64; 2], pulse_mm: f64, travel: Box2) -> Option<Box2> {
    let mut b: Option<Box2> = None;
    let mut take = |x: f64, z: f64| {
        let n = b.get_or_insert(Box2 {
            x: [x, x],
            z: [z, z],
        });
        n.x = [n.x[0].min(x), n.x[1].max(x)];
        n.z = [n.z[0].min(z), n.z[1].max(z)];
    };
    let mut cut = false;
    for (p, _) in trail.tagged().filter(|(_, w)| w.is_some()) {
        take(p[0], p[2]);
        cut = true;
    }
    if !cut {
        return None;
    }
    take(tip[0] as f64 * pulse_mm, tip[1] as f64 * pulse_mm);
    b.map(|b| grown(b, travel))
}

/// `b` 12 % and 1 mm more on every side, at least 4 mm across, kept inside `travel`.
fn grown(b: Box2, travel: Box2) -> Box2 {
    let grow = |r: [f64; 2], lim: [f64; 2]| {
        let m = (r[1] - r[0]) * 0.12 + 1.0;
        let (mut lo, mut hi) = (r[0] - m, r[1] + m);
        if hi - lo < 4.0 {
            let c = (lo + hi) / 2.0;
            (lo, hi) = (c - 2.0, c + 2.0);
        }
        [lo.max(lim[0]), hi.min(lim[1])]
    };
    Box2 {
        x: grow(b.x, travel.x),
        z: grow(b.z, travel.z),
    }
}

/// The grid's background lines.
const GRID: Color32 = Color32::from_rgb(26, 32, 44);

/// A round grid step (1, 2 or 5 × 10ⁿ mm) giving about `n` lines over `span` mm.
pub fn grid_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1e-6);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

/// What one plot shows.
pub struct PlotData<'a> {
    /// The channel (its travel).
    pub ch: &'a ChannelDesc,
    /// mm per pulse.
    pub pulse_mm: f64,
    /// The trail.
    pub trail: &'a Trail,
    /// The programmed path: the channel's program as the next START would read it.
    pub programmed: &'a [crate::backplot::Segment],
    /// The work in the spindle now.
    pub current: Option<u32>,
    /// The tip now, pulses [X radius, Z].
    pub tip: [i64; 2],
    /// The work system in force and its zero, pulses [X radius, Z] from the machine's zero: the
    /// detail's grid is labelled in its coordinates, as the readout is (docs/lathe-gcode.md
    /// "Work offsets").
    pub system: (usize, [i64; 2]),
}

/// Draws the overview: the whole travel box with the trail and the tip, and the detail view's
/// box dashed. Returns the travel box on screen.
pub fn draw_overview(p: &Painter, area: Rect, d: &PlotData, detail: Option<Box2>) -> Rect {
    p.rect_filled(area, 4.0, PLOT_BG);
    let travel = Box2::travel(d.ch);
    let f = Frame::fit(area, 16.0, travel);
    let r = f.rect;
    centre_lines(p, &f, travel);
    p.rect_stroke(r, 0.0, Stroke::new(1.0, FRAME), StrokeKind::Outside);
    let small = FontId::monospace(10.0);
    let legend = |pos: Pos2, a: Align2, t: String| {
        p.text(pos, a, t, small.clone(), FRAME);
    };
    legend(
        pos2(r.min.x, r.max.y + 2.0),
        Align2::LEFT_TOP,
        format!("Z{}", travel.z[0]),
    );
    legend(
        pos2(r.max.x, r.max.y + 2.0),
        Align2::RIGHT_TOP,
        format!("Z{} →", travel.z[1]),
    );
    legend(
        pos2(r.min.x, r.min.y - 2.0),
        Align2::LEFT_BOTTOM,
        format!("↑ X radius {}..{} mm   travel", travel.x[0], travel.x[1]),
    );
    if let Some(b) = detail {
        let q = Rect::from_two_pos(f.at(b.x[0], b.z[0]), f.at(b.x[1], b.z[1]));
        p.extend(Shape::dashed_line(
            &[
                q.left_top(),
                q.right_top(),
                q.right_bottom(),
                q.left_bottom(),
                q.left_top(),
            ],
            Stroke::new(1.0, FRAME.gamma_multiply(0.6)),
            4.0,
            3.0,
        ));
    }
    let clip = p.with_clip_rect(r.expand(1.0));
    draw_programmed(&clip, &f, d.programmed);
    draw_trail(&clip, &f, d.trail, d.current);
    tip_mark(&clip, &f, d.pulse_mm, d.tip);
    r
}

/// Draws the detail view of box `b` (a grid of round millimetres, labelled), with the trail
/// and the tip. Returns the box on screen.
pub fn draw_detail(p: &Painter, area: Rect, d: &PlotData, b: Box2) -> Rect {
    p.rect_filled(area, 4.0, PLOT_BG);
    let f = Frame::fit(area, 18.0, b);
    let r = f.rect;
    let shown = f.shown();
    let step = grid_step((shown.z[1] - shown.z[0]).max(shown.x[1] - shown.x[0]), 8.0);
    let small = FontId::monospace(10.0);
    let clip = p.with_clip_rect(r);
    // Round millimetres of the program's coordinates: the grid stands on the work's zero.
    let (system, zero) = d.system;
    let zero = zero.map(|v| v as f64 * d.pulse_mm);
    let mut z = ((shown.z[0] - zero[1]) / step).ceil() * step;
    while z + zero[1] <= shown.z[1] {
        let x = f.at(0.0, z + zero[1]).x;
        clip.line_segment([pos2(x, r.min.y), pos2(x, r.max.y)], Stroke::new(1.0, GRID));
        p.text(
            pos2(x, r.max.y + 2.0),
            Align2::CENTER_TOP,
            fmt_mm(z),
            small.clone(),
            FRAME,
        );
        z += step;
    }
    let mut x = ((shown.x[0] - zero[0]) / step).ceil() * step;
    while x + zero[0] <= shown.x[1] {
        let y = f.at(x + zero[0], 0.0).y;
        clip.line_segment([pos2(r.min.x, y), pos2(r.max.x, y)], Stroke::new(1.0, GRID));
        p.text(
            pos2(r.min.x - 2.0, y),
            Align2::RIGHT_CENTER,
            fmt_mm(x),
            small.clone(),
            FRAME,
        );
        x += step;
    }
    centre_lines(&clip, &f, shown);
    p.rect_stroke(r, 0.0, Stroke::new(1.0, FRAME), StrokeKind::Outside);
    p.text(
        pos2(r.min.x, r.min.y - 2.0),
        Align2::LEFT_BOTTOM,
        format!(
            "detail: the cuts, grid {} mm, X radius, G{}",
            fmt_mm(step),
            54 + system
        ),
        small,
        FRAME,
    );
    draw_programmed(&clip, &f, d.programmed);
    draw_trail(&clip, &f, d.trail, d.current);
    tip_mark(&clip, &f, d.pulse_mm, d.tip);
    r
}

/// The programmed path under the trail, in the centre's backplot colours
/// (`pathdraw::{RAPID, FEED, ARC}`): rapids dashed, feeds and arcs solid and thin.
fn draw_programmed(p: &Painter, f: &Frame, path: &[crate::backplot::Segment]) {
    use crate::backplot::PathKind;
    for s in path {
        let pts: Vec<Pos2> = s.points().iter().map(|q| f.at(q[0], q[2])).collect();
        match s.kind {
            PathKind::Rapid => {
                p.extend(Shape::dashed_line(&pts, Stroke::new(1.0, RAPID), 5.0, 4.0))
            }
            PathKind::Feed => {
                p.add(Shape::line(pts, Stroke::new(1.0, FEED)));
            }
            PathKind::Arc => {
                p.add(Shape::line(pts, Stroke::new(1.0, ARC)));
            }
        }
    }
}

/// The box of a programmed path's cuts (its feed moves and arcs), 12 % and 1 mm more on
/// every side, at least 4 mm across, inside the travel: the detail view before anything is
/// cut. `None` for a path with no cut.
pub fn cuts_box(path: &[crate::backplot::Segment], travel: Box2) -> Option<Box2> {
    let mut b: Option<Box2> = None;
    for s in path
        .iter()
        .filter(|s| s.kind != crate::backplot::PathKind::Rapid)
    {
        for q in s.points() {
            let e = b.get_or_insert(Box2 {
                x: [q[0], q[0]],
                z: [q[2], q[2]],
            });
            e.x = [e.x[0].min(q[0]), e.x[1].max(q[0])];
            e.z = [e.z[0].min(q[2]), e.z[1].max(q[2])];
        }
    }
    b.map(|b| grown(b, travel))
}

/// The detail view's box for a plot (`PlotData`): the programmed path's cuts ([`cuts_box`]);
/// with no programmed cut (a program that does not read, an empty one), what the trail cut
/// ([`detail_box`]). Until stop 52 the trail came first: on a lathe loaded by hand the work
/// is in the spindle from START to the end, so its returns to the top of the travel counted
/// as cuts and the detail was the whole travel.
pub fn detail_of(d: &PlotData, travel: Box2) -> Option<Box2> {
    cuts_box(d.programmed, travel).or_else(|| detail_box(d.trail, d.tip, d.pulse_mm, travel))
}

/// `v` mm without needless decimals.
fn fmt_mm(v: f64) -> String {
    let v = if v.abs() < 1e-9 { 0.0 } else { v };
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The spindle centreline (X = 0) dashed and the work face (Z = 0) dotted, where `b` has them.
fn centre_lines(p: &Painter, f: &Frame, b: Box2) {
    let r = f.rect;
    if b.x[0] <= 0.0 && 0.0 <= b.x[1] {
        let y = f.at(0.0, 0.0).y;
        p.extend(Shape::dashed_line(
            &[pos2(r.min.x, y), pos2(r.max.x, y)],
            Stroke::new(1.0, AXIS_LINE),
            10.0,
            4.0,
        ));
    }
    if b.z[0] <= 0.0 && 0.0 <= b.z[1] {
        let x = f.at(0.0, 0.0).x;
        p.extend(Shape::dashed_line(
            &[pos2(x, r.min.y), pos2(x, r.max.y)],
            Stroke::new(1.0, AXIS_LINE),
            2.0,
            3.0,
        ));
    }
}

/// The tip's cross-hair.
fn tip_mark(p: &Painter, f: &Frame, pulse_mm: f64, tip: [i64; 2]) {
    let t = f.at(tip[0] as f64 * pulse_mm, tip[1] as f64 * pulse_mm);
    let s = Stroke::new(1.5, TIP);
    p.line_segment([t - vec2(7.0, 0.0), t + vec2(7.0, 0.0)], s);
    p.line_segment([t - vec2(0.0, 7.0), t + vec2(0.0, 7.0)], s);
}

/// The trail as polylines of one work each: earlier works and empty-spindle moves first,
/// oldest first, dimmed and thin; the work in the spindle now last, bright and thick. Points closer than
/// half a pixel to the last one drawn are skipped.
fn draw_trail(p: &Painter, f: &Frame, trail: &Trail, current: Option<u32>) {
    let mut runs: Vec<(Option<u32>, Vec<Pos2>)> = Vec::new();
    let mut last: Option<Pos2> = None;
    for (pt, work) in trail.tagged() {
        let s = f.at(pt[0], pt[2]);
        match runs.last_mut() {
            Some((w, v)) if *w == work => {
                if v.last().is_none_or(|q| q.distance(s) >= 0.5) {
                    v.push(s);
                }
            }
            _ => {
                // A new run starts where the last one ended, so the path has no gap.
                runs.push((work, last.into_iter().chain([s]).collect()));
            }
        }
        last = Some(s);
    }
    // The tip's latest position ends its run even if it is under half a pixel away.
    if let (Some(s), Some((_, v))) = (last, runs.last_mut()) {
        if v.last() != Some(&s) {
            v.push(s);
        }
    }
    let stroke = |w: Option<u32>| match w {
        Some(w) if Some(w) == current => Stroke::new(2.0, work_colour(w)),
        Some(w) => Stroke::new(1.0, dim(work_colour(w))),
        None => Stroke::new(1.0, EMPTY),
    };
    let (now, before): (Vec<_>, Vec<_>) = runs
        .into_iter()
        .partition(|(w, _)| w.is_some() && *w == current);
    for (w, v) in before.into_iter().chain(now) {
        if v.len() >= 2 {
            p.add(Shape::line(v, stroke(w)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_is_at_equal_scale_z_right_x_up() {
        let d = crate::lathe::desc::LatheDesc::citizen();
        let t = Box2::travel(&d.channels[0]);
        let area = Rect::from_min_size(pos2(0.0, 0.0), vec2(500.0, 300.0));
        let f = Frame::fit(area, 10.0, t);
        // Equal scale: the box has the travel's proportions, and fits.
        let ratio = f.rect.width() / f.rect.height();
        let want = ((t.z[1] - t.z[0]) / (t.x[1] - t.x[0])) as f32;
        assert!((ratio - want).abs() < 1e-3, "{ratio} vs {want}");
        assert!(area.shrink(10.0).contains_rect(f.rect.shrink(0.01)));
        // Z grows to the right, X up; the travel's corners are the box's.
        assert_eq!(f.at(t.x[0], t.z[0]), f.rect.left_bottom());
        let tr = f.at(t.x[1], t.z[1]);
        assert!((tr - f.rect.right_top()).length() < 1e-3);
        let s = f.shown();
        assert!((s.z[1] - t.z[1]).abs() < 1e-3 && (s.x[1] - t.x[1]).abs() < 1e-3);
    }

    #[test]
    fn the_detail_box_holds_the_cuts_and_the_tip_inside_the_travel() {
        let travel = Box2 {
            x: [-2.0, 35.0],
            z: [-60.0, 60.0],
        };
        let mut t = Trail::default();
        assert_eq!(detail_box(&t, [0, 0], 0.001, travel), None);
        t.push_tagged([35.0, 0.0, 60.0], None); // home: not a cut
        t.push_tagged([11.0, 0.0, 1.0], Some(1));
        t.push_tagged([-0.5, 0.0, -20.0], Some(1));
        let b = detail_box(&t, [20_000, 10_000], 0.001, travel).unwrap();
        // The cuts and the tip inside, with a margin; the rapid from home outside.
        assert!(b.x[0] < -0.5 && b.x[1] > 20.0 && b.z[0] < -20.0 && b.z[1] > 10.0);
        assert!(b.x[1] < 35.0 && b.z[1] < 60.0, "{b:?}");
        // Never past the travel.
        assert!(b.x[0] >= -2.0, "{b:?}");
        // A single point still gives a 4 mm box.
        let mut one = Trail::default();
        one.push_tagged([5.0, 0.0, -5.0], Some(2));
        let b = detail_box(&one, [5_000, -5_000], 0.001, travel).unwrap();
        assert!((b.z[1] - b.z[0] - 4.0).abs() < 1e-9, "{b:?}");
    }

    #[test]
    fn the_detail_is_the_programs_cuts_not_a_return_made_with_a_work_in_the_spindle() {
        use crate::backplot::{PathKind, Segment};
        let desc = crate::lathe::testkit::citizen_like(1);
        let ch = &desc.channels[0];
        let travel = Box2::travel(ch);
        let seg = |kind, from: [f64; 3], to: [f64; 3]| Segment {
            kind,
            stmt: 1,
            seq: 1,
            from,
            to,
            arc: None,
        };
        // A cut near the work, then G28 to the top of the travel, at rapid.
        let programmed = [
            seg(PathKind::Feed, [10.0, 0.0, 1.0], [10.0, 0.0, -10.0]),
            seg(
                PathKind::Rapid,
                [10.0, 0.0, -10.0],
                [travel.x[1], 0.0, travel.z[1]],
            ),
        ];
        // The trail made the same moves with the work in the spindle all along (loaded by hand).
        let mut trail = Trail::default();
        for p in [
            [10.0, 0.0, 1.0],
            [10.0, 0.0, -10.0],
            [travel.x[1], 0.0, travel.z[1]],
        ] {
            trail.push_tagged(p, Some(1));
        }
        let mut d = PlotData {
            ch,
            pulse_mm: desc.pulse_mm,
            trail: &trail,
            programmed: &programmed,
            current: Some(1),
            tip: [0, 0],
            system: (0, [0, 0]),
        };
        let b = detail_of(&d, travel).unwrap();
        assert!(
            b.z[1] < 5.0 && b.x[1] < 15.0,
            "the return is not a cut: {b:?}"
        );
        // No programmed cut: what the trail covered.
        d.programmed = &[];
        let t = detail_of(&d, travel).unwrap();
        assert!(t.x[1] >= travel.x[1] - 1e-9, "{t:?}");
    }

    #[test]
    fn grid_steps_are_round() {
        assert_eq!(grid_step(37.0, 8.0), 5.0);
        assert_eq!(grid_step(10.0, 8.0), 2.0);
        assert!((grid_step(0.8, 8.0) - 0.1).abs() < 1e-12);
        assert_eq!(fmt_mm(-2.5), "-2.5");
        assert_eq!(fmt_mm(10.0), "10");
    }

    #[test]
    fn works_take_their_colours_in_turn() {
        assert_eq!(work_colour(1), WORK_COLOURS[0]);
        assert_eq!(work_colour(7), WORK_COLOURS[0]);
        assert_eq!(work_colour(3), WORK_COLOURS[2]);
    }
}
