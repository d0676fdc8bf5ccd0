//! The velocity strip (issue 12): each axis's velocity against time for the running block,
//! drawn in its own strip under the backplot, so the DDA's KT ramps and the error-proportional
//! interpolator's exponential tail can be seen as the machine runs (docs/window.md). The
//! velocities are the axis counters' differences between frames over the machine time between
//! them; the trace starts afresh when a block starts and stays up after it ends.

use egui::{pos2, Align2, Color32, FontId, Painter, Rect, Shape, Stroke};

/// The axes' colours (none of them the backplot's executed-path or tool colour).
pub const AXIS_COLOURS: [Color32; 3] = [
    Color32::from_rgb(255, 170, 60),
    Color32::from_rgb(110, 170, 255),
    Color32::from_rgb(235, 235, 90),
];

/// Samples kept; beyond this every other one is dropped (a long block keeps its shape).
const MAX_SAMPLES: usize = 4096;

/// The samples of the block running (or last run): machine time and axis counters.
#[derive(Default)]
pub struct VelocityTrace {
    block: Option<u32>,
    samples: Vec<(u64, [i64; 3])>,
    /// Machine time the axes have stood still within the block (a hold, an E-STOP), ns: taken
    /// off the samples' times, so the strip's clock stops with the machine.
    paused_ns: u64,
    /// When the axes came to rest, while they stand still.
    rest_since: Option<u64>,
}

impl VelocityTrace {
    /// One frame's sample: the block executing (None between blocks), the machine time (ns),
    /// the axis counters (pulses), and whether the axes are moving. While they stand still
    /// (a feed hold, a dwell, an E-STOP) nothing is added and the strip's clock stops.
    pub fn sample(&mut self, block: Option<u32>, t_ns: u64, pos: [i64; 3], moving: bool) {
        let Some(b) = block else {
            return;
        };
        if self.block != Some(b) {
            self.paused_ns = 0;
            self.rest_since = None;
        }
        if !moving {
            if self.block == Some(b) && self.rest_since.is_none() {
                self.rest_since = Some(t_ns);
            }
            return;
        }
        if let Some(r) = self.rest_since.take() {
            self.paused_ns += t_ns.saturating_sub(r);
        }
        let t_ns = t_ns.saturating_sub(self.paused_ns);
        if self.block != Some(b) || self.samples.last().is_some_and(|s| s.0 > t_ns) {
            self.block = Some(b);
            self.samples.clear();
            self.paused_ns = 0;
        }
        if self.samples.last().is_some_and(|s| s.0 == t_ns) {
            return;
        }
        if self.samples.len() >= MAX_SAMPLES {
            let mut i = 0;
            self.samples.retain(|_| {
                i += 1;
                i % 2 == 1
            });
        }
        self.samples.push((t_ns, pos));
    }

    /// Each axis's velocity (mm/min) between successive samples, at the middle of each
    /// interval, seconds from the first sample.
    pub fn velocities(&self, pulse_mm: f64) -> Vec<(f64, [f64; 3])> {
        let Some(first) = self.samples.first() else {
            return Vec::new();
        };
        self.samples
            .windows(2)
            .filter(|w| w[1].0 > w[0].0)
            .map(|w| {
                let dt = (w[1].0 - w[0].0) as f64 * 1e-9;
                let mid = ((w[0].0 + w[1].0) / 2 - first.0) as f64 * 1e-9;
                let v = [0, 1, 2].map(|a| (w[1].1[a] - w[0].1[a]) as f64 * pulse_mm / dt * 60.0);
                (mid, v)
            })
            .collect()
    }

    /// Draws the strip in `rect`, its own place under the backplot (it once covered the
    /// backplot's lower left); before any motion it says so.
    pub fn show(&self, painter: &Painter, rect: Rect, pulse_mm: f64, what: &str) -> Rect {
        let v = self.velocities(pulse_mm);
        painter.rect_filled(rect, 3.0, Color32::from_rgba_unmultiplied(0, 0, 0, 210));
        painter.rect_stroke(
            rect,
            3.0,
            Stroke::new(1.0, Color32::from_gray(110)),
            egui::StrokeKind::Inside,
        );
        let font = FontId::monospace(11.0);
        if v.len() < 2 {
            painter.text(
                pos2(rect.min.x + 6.0, rect.min.y + 2.0),
                Align2::LEFT_TOP,
                format!("velocity: no block has moved yet {what}"),
                font,
                Color32::from_gray(150),
            );
            return rect;
        }
        let plot = rect.shrink2(egui::vec2(6.0, 16.0));
        let t_end = v.last().map_or(1.0, |s| s.0).max(1e-6);
        let vmax = v
            .iter()
            .flat_map(|s| s.1)
            .fold(1.0f64, |m, x| m.max(x.abs()));
        let map = |t: f64, x: f64| {
            pos2(
                plot.min.x + (t / t_end) as f32 * plot.width(),
                plot.center().y - (x / vmax) as f32 * plot.height() * 0.5,
            )
        };
        painter.line_segment(
            [map(0.0, 0.0), map(t_end, 0.0)],
            Stroke::new(1.0, Color32::from_gray(80)),
        );
        for (a, &colour) in AXIS_COLOURS.iter().enumerate() {
            let pts: Vec<_> = v.iter().map(|s| map(s.0, s.1[a])).collect();
            painter.add(Shape::line(pts, Stroke::new(1.5, colour)));
        }
        let block = self.block.map_or(String::new(), |b| format!("N{b} "));
        painter.text(
            pos2(rect.min.x + 6.0, rect.min.y + 2.0),
            Align2::LEFT_TOP,
            format!("{block}velocity ±{vmax:.0} mm/min {t_end:.2} s {what}"),
            font.clone(),
            Color32::from_gray(210),
        );
        for (a, name) in ["X", "Y", "Z"].iter().enumerate() {
            painter.text(
                pos2(rect.max.x - 40.0 + 12.0 * a as f32, rect.max.y - 2.0),
                Align2::LEFT_BOTTOM,
                *name,
                font.clone(),
                AXIS_COLOURS[a],
            );
        }
        rect
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocities_are_counter_differences_over_machine_time_per_block() {
        let mut t = VelocityTrace::default();
        t.sample(None, 0, [0, 0, 0], true);
        assert!(t.velocities(0.001).is_empty());
        t.sample(Some(3), 1_000_000_000, [0, 0, 0], true);
        t.sample(Some(3), 1_500_000_000, [500, -250, 0], true);
        t.sample(Some(3), 1_500_000_000, [600, -250, 0], true);
        t.sample(Some(3), 2_000_000_000, [1000, -500, 10], true);
        let v = t.velocities(0.001);
        assert_eq!(v.len(), 2);
        assert!((v[0].0 - 0.25).abs() < 1e-9);
        assert!((v[0].1[0] - 60.0).abs() < 1e-9 && (v[0].1[1] + 30.0).abs() < 1e-9);
        assert!((v[1].1[2] - 1.2).abs() < 1e-9);
        // A new block starts a new trace; a pause between blocks keeps the last one.
        t.sample(None, 2_100_000_000, [1000, -500, 10], true);
        assert_eq!(t.block, Some(3));
        t.sample(Some(4), 2_200_000_000, [1000, -500, 10], true);
        assert_eq!(t.block, Some(4));
        assert!(t.velocities(0.001).is_empty());
    }

    #[test]
    fn a_long_block_keeps_its_shape_in_bounded_samples() {
        let mut t = VelocityTrace::default();
        for k in 0..20_000u64 {
            t.sample(Some(1), k * 1_000_000, [k as i64, 0, 0], true);
        }
        assert!(t.samples.len() <= MAX_SAMPLES);
        let v = t.velocities(0.001);
        assert!(v.iter().all(|s| (s.1[0] - 60.0).abs() < 1e-6));
        assert!(v.last().is_some_and(|s| s.0 > 19.0));
    }

    #[test]
    fn the_clock_stops_while_the_axes_stand_still() {
        let mut t = VelocityTrace::default();
        t.sample(Some(5), 0, [0, 0, 0], true);
        t.sample(Some(5), 1_000_000_000, [1000, 0, 0], true);
        // E-STOP (or a hold) at 1 s; ten seconds pass with the axes at rest.
        for k in 1..=10u64 {
            t.sample(Some(5), (1 + k) * 1_000_000_000, [1000, 0, 0], false);
        }
        let v = t.velocities(0.001);
        assert_eq!(v.len(), 1, "nothing is added at rest");
        assert!(v.last().unwrap().0 < 1.0, "the clock stopped");
        // Resumed at 11 s: the strip goes on from 1 s, not from 11 s.
        t.sample(Some(5), 12_000_000_000, [2000, 0, 0], true);
        let v = t.velocities(0.001);
        assert!(v.last().unwrap().0 < 2.0, "{:?}", v.last());
        assert!((v.last().unwrap().1[0] - 60.0).abs() < 1e-6, "{v:?}");
    }
}
