//! The lathe window's backplot (docs/window.md, "The lathe window"): one channel's tool-tip
//! path in the Z–X plane, Z to the right and X (the radius) up at equal scale, inside the
//! channel's travel box. The path is the trail of positions the window sampled after every step
//! of the machine: bounded (`TRAIL_POINTS`), each point tagged with the work in the spindle,
//! drawn in that work's colour — the work now in the spindle bright and thick, earlier works
//! dimmed, moves with an empty spindle grey.

use crate::lathe::desc::ChannelDesc;
use egui::{pos2, vec2, Align2, Color32, FontId, Painter, Pos2, Rect, Shape, Stroke, StrokeKind};
use std::collections::VecDeque;

/// Points kept per channel; the oldest go first.
pub const TRAIL_POINTS: usize = 20_000;
/// Kept points are at least this far apart (mm); the last point always follows the tip.
pub const TRAIL_STEP_MM: f64 = 0.05;

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

/// One sampled tool-tip position: pulses [X radius, Z], and the work in the spindle then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrailPt {
    /// Pulses [X radius, Z].
    pub pos: [i64; 2],
    /// The work in the spindle.
    pub work: Option<u32>,
}

/// A channel's bounded trail of tool-tip positions.
#[derive(Clone, Debug)]
pub struct Trail {
    pts: VecDeque<TrailPt>,
    step: i64,
    cap: usize,
}

impl Trail {
    /// An empty trail keeping at most `cap` points at least `step` pulses apart.
    pub fn new(step: i64, cap: usize) -> Trail {
        Trail {
            pts: VecDeque::new(),
            step: step.max(1),
            cap: cap.max(2),
        }
    }

    /// Takes a sample. The last point follows the tip; it is kept for good once it is `step`
    /// (or more) from the point before, or when the work in the spindle changes.
    pub fn push(&mut self, pos: [i64; 2], work: Option<u32>) {
        let p = TrailPt { pos, work };
        let n = self.pts.len();
        if let Some(last) = self.pts.back() {
            if *last == p {
                return;
            }
            if n >= 2 && last.work == work {
                let prev = self.pts[n - 2];
                let d = (last.pos[0] - prev.pos[0])
                    .abs()
                    .max((last.pos[1] - prev.pos[1]).abs());
                if prev.work == work && d < self.step {
                    if let Some(b) = self.pts.back_mut() {
                        *b = p;
                    }
                    return;
                }
            }
        }
        self.pts.push_back(p);
        if self.pts.len() > self.cap {
            self.pts.pop_front();
        }
    }

    /// The points, oldest first.
    pub fn points(&self) -> impl Iterator<Item = &TrailPt> {
        self.pts.iter()
    }

    /// How many points are kept.
    pub fn len(&self) -> usize {
        self.pts.len()
    }

    /// No points.
    pub fn is_empty(&self) -> bool {
        self.pts.is_empty()
    }
}

/// Maps the channel's travel (mm) into a plot rectangle at equal scale, Z right, X up.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The travel box on screen.
    pub rect: Rect,
    /// Points per mm.
    pub scale: f32,
    z0: f64,
    x0: f64,
}

impl Frame {
    /// The largest travel box of `ch` that fits `area` less `margin` on every side, centred.
    pub fn fit(area: Rect, margin: f32, ch: &ChannelDesc) -> Frame {
        let [xt, zt] = [ch.axes[0].travel, ch.axes[1].travel];
        let zspan = (zt[1] - zt[0]).max(1e-3) as f32;
        let xspan = (xt[1] - xt[0]).max(1e-3) as f32;
        let inner = area.shrink(margin);
        let scale = (inner.width() / zspan)
            .min(inner.height() / xspan)
            .max(1e-3);
        let size = vec2(zspan * scale, xspan * scale);
        Frame {
            rect: Rect::from_center_size(inner.center(), size),
            scale,
            z0: zt[0],
            x0: xt[0],
        }
    }

    /// The screen point of (X radius, Z) in mm.
    pub fn at(&self, x_mm: f64, z_mm: f64) -> Pos2 {
        pos2(
            self.rect.min.x + ((z_mm - self.z0) as f32) * self.scale,
            self.rect.max.y - ((x_mm - self.x0) as f32) * self.scale,
        )
    }
}

/// Draws channel `ch`'s plot into `area`: background, travel box, centreline and work face,
/// the trail (`current` is the work in the spindle now), the tip at `tip` (pulses), and the
/// frame's legends. Returns the travel box on screen.
pub fn draw(
    p: &Painter,
    area: Rect,
    ch: &ChannelDesc,
    pulse_mm: f64,
    trail: &Trail,
    current: Option<u32>,
    tip: [i64; 2],
) -> Rect {
    p.rect_filled(area, 4.0, PLOT_BG);
    let f = Frame::fit(area, 18.0, ch);
    let r = f.rect;
    let small = FontId::monospace(10.0);
    // The centreline (X = 0) dashed, and the work face (Z = 0) dotted, where the travel has them.
    let [xt, zt] = [ch.axes[0].travel, ch.axes[1].travel];
    if xt[0] <= 0.0 && 0.0 <= xt[1] {
        let y = f.at(0.0, 0.0).y;
        p.extend(Shape::dashed_line(
            &[pos2(r.min.x, y), pos2(r.max.x, y)],
            Stroke::new(1.0, AXIS_LINE),
            10.0,
            4.0,
        ));
    }
    if zt[0] <= 0.0 && 0.0 <= zt[1] {
        let x = f.at(0.0, 0.0).x;
        p.extend(Shape::dashed_line(
            &[pos2(x, r.min.y), pos2(x, r.max.y)],
            Stroke::new(1.0, AXIS_LINE),
            2.0,
            3.0,
        ));
    }
    p.rect_stroke(r, 0.0, Stroke::new(1.0, FRAME), StrokeKind::Outside);
    let legend = |pos: Pos2, a: Align2, t: String| {
        p.text(pos, a, t, small.clone(), FRAME);
    };
    legend(
        pos2(r.min.x, r.max.y + 2.0),
        Align2::LEFT_TOP,
        format!("Z{}", zt[0]),
    );
    legend(
        pos2(r.max.x, r.max.y + 2.0),
        Align2::RIGHT_TOP,
        format!("Z{} →", zt[1]),
    );
    legend(
        pos2(r.min.x, r.min.y - 2.0),
        Align2::LEFT_BOTTOM,
        format!("↑ X radius {}..{} mm", xt[0], xt[1]),
    );

    let clip = p.with_clip_rect(r.expand(1.0));
    draw_trail(&clip, &f, pulse_mm, trail, current);
    let t = f.at(tip[0] as f64 * pulse_mm, tip[1] as f64 * pulse_mm);
    let s = Stroke::new(1.5, TIP);
    clip.line_segment([t - vec2(7.0, 0.0), t + vec2(7.0, 0.0)], s);
    clip.line_segment([t - vec2(0.0, 7.0), t + vec2(0.0, 7.0)], s);
    r
}

/// The trail as polylines of one work each: earlier works and empty-spindle moves first,
/// dimmed and thin; the work in the spindle now last, bright and thick. Points closer than
/// half a pixel to the last one drawn are skipped.
fn draw_trail(p: &Painter, f: &Frame, pulse_mm: f64, trail: &Trail, current: Option<u32>) {
    let mut runs: Vec<(Option<u32>, Vec<Pos2>)> = Vec::new();
    let mut last: Option<TrailPt> = None;
    for pt in trail.points() {
        let s = f.at(pt.pos[0] as f64 * pulse_mm, pt.pos[1] as f64 * pulse_mm);
        match runs.last_mut() {
            Some((w, v)) if *w == pt.work => {
                if v.last().is_none_or(|q| q.distance(s) >= 0.5) {
                    v.push(s);
                }
            }
            _ => {
                // A new run starts where the last one ended, so the path has no gap.
                let mut v = Vec::new();
                if let Some(l) = last {
                    v.push(f.at(l.pos[0] as f64 * pulse_mm, l.pos[1] as f64 * pulse_mm));
                }
                v.push(s);
                runs.push((pt.work, v));
            }
        }
        last = Some(*pt);
    }
    // The tip's latest position ends its run even if it is under half a pixel away.
    if let (Some(l), Some((_, v))) = (last, runs.last_mut()) {
        let s = f.at(l.pos[0] as f64 * pulse_mm, l.pos[1] as f64 * pulse_mm);
        if v.last() != Some(&s) {
            v.push(s);
        }
    }
    let stroke = |w: Option<u32>| match w {
        Some(w) if Some(w) == current => Stroke::new(2.0, work_colour(w)),
        Some(w) => Stroke::new(1.0, work_colour(w).gamma_multiply(0.45)),
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
    fn the_trail_keeps_points_a_step_apart_and_follows_the_tip() {
        let mut t = Trail::new(50, 100);
        t.push([0, 0], None);
        for z in 1..=120 {
            t.push([0, -z], Some(1));
        }
        let pts: Vec<[i64; 2]> = t.points().map(|p| p.pos).collect();
        // The first point, the first with the work, then every 50 pulses, and the tip.
        assert_eq!(pts, [[0, 0], [0, -1], [0, -51], [0, -101], [0, -120]]);
        // The same sample again adds nothing.
        t.push([0, -120], Some(1));
        assert_eq!(t.len(), 5);
        // A new work starts a point at once.
        t.push([0, -121], Some(2));
        assert_eq!(t.points().last().map(|p| p.work), Some(Some(2)));
        assert_eq!(t.len(), 6);
    }

    #[test]
    fn the_trail_is_bounded_and_drops_the_oldest() {
        let mut t = Trail::new(1, 10);
        for z in 0..25 {
            t.push([0, z * 10], Some(1));
        }
        assert_eq!(t.len(), 10);
        assert_eq!(t.points().next().map(|p| p.pos), Some([0, 150]));
    }

    #[test]
    fn the_frame_is_at_equal_scale_z_right_x_up() {
        let d = crate::lathe::desc::LatheDesc::citizen();
        let ch = &d.channels[0];
        let area = Rect::from_min_size(pos2(0.0, 0.0), vec2(500.0, 300.0));
        let f = Frame::fit(area, 10.0, ch);
        let [xt, zt] = [ch.axes[0].travel, ch.axes[1].travel];
        // Equal scale: the box has the travel's proportions, and fits.
        let ratio = f.rect.width() / f.rect.height();
        let want = ((zt[1] - zt[0]) / (xt[1] - xt[0])) as f32;
        assert!((ratio - want).abs() < 1e-3, "{ratio} vs {want}");
        assert!(area.shrink(10.0).contains_rect(f.rect.shrink(0.01)));
        // Z grows to the right, X up; the travel's corners are the box's.
        assert_eq!(f.at(xt[0], zt[0]), f.rect.left_bottom());
        let tr = f.at(xt[1], zt[1]);
        assert!((tr - f.rect.right_top()).length() < 1e-3);
    }

    #[test]
    fn works_take_their_colours_in_turn() {
        assert_eq!(work_colour(1), WORK_COLOURS[0]);
        assert_eq!(work_colour(7), WORK_COLOURS[0]);
        assert_eq!(work_colour(3), WORK_COLOURS[2]);
    }
}
