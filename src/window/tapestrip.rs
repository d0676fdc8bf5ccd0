//! The tape strip (docs/window.md): while PROGRAM READ or TOOL DATA READ reads, the last frames
//! of the tape as a strip of oiled paper passing the read head from left to right. Each frame is
//! a column of eight channels, channel 8 at the top and the smaller sprocket hole between
//! channels 4 and 3 (as `Frame::row` draws a frame, turned a quarter); the frame under the read
//! head is the last on the right, framed; a read an error stopped draws that frame's holes red.

use crate::console::tape::{TapeView, STRIP_FRAMES};
use egui::{vec2, Color32, Rect, Stroke, Ui};

/// The paper.
const PAPER: Color32 = Color32::from_rgb(222, 196, 120);
/// A punched hole: the dark panel behind the tape shows through.
const HOLE: Color32 = Color32::from_rgb(24, 24, 26);
/// The holes of the frame in error.
const BAD: Color32 = Color32::from_rgb(220, 40, 30);
/// The read head's frame.
const HEAD: Color32 = Color32::from_rgb(255, 60, 40);

/// Where a strip was drawn, for a screenshot's reader (points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripLayout {
    /// The rectangle of the frame columns (the paper without its margins).
    pub rect: Rect,
    /// Distance between frames and between channels, points.
    pub pitch: f32,
    /// The number (0-based in the image) of the first frame drawn.
    pub first: u64,
    /// Frames drawn.
    pub count: usize,
}

/// The row of channel `ch` (1–8) in a frame column, 0 at the top: 8 7 6 5 4 • 3 2 1.
pub fn channel_row(ch: u8) -> usize {
    if ch >= 4 {
        (8 - ch) as usize
    } else {
        (9 - ch) as usize
    }
}

/// The row of the sprocket hole.
pub const SPROCKET_ROW: usize = 5;

/// Draws the strip for `t` across `width` points; returns where the frames are.
pub fn show(ui: &mut Ui, t: &TapeView, width: f32) -> StripLayout {
    let pitch = (width / (STRIP_FRAMES as f32 + 2.0))
        .floor()
        .clamp(6.0, 14.0);
    let margin = pitch;
    let size = vec2(
        STRIP_FRAMES as f32 * pitch + 2.0 * margin,
        9.0 * pitch + 2.0 * margin,
    );
    let (outer, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let p = ui.painter_at(outer);
    p.rect_filled(outer, 2.0, PAPER);
    // The frames fill the strip from the right, the newest under the read head.
    let inner = outer.shrink(margin);
    let n = t.frames.len().min(STRIP_FRAMES);
    let x0 = inner.max.x - n as f32 * pitch;
    for (i, f) in t.frames.iter().rev().take(n).rev().enumerate() {
        let cx = x0 + (i as f32 + 0.5) * pitch;
        let last = i + 1 == n;
        let colour = if last && t.failed { BAD } else { HOLE };
        for ch in 1..=8u8 {
            if f.has(ch) {
                let cy = inner.min.y + (channel_row(ch) as f32 + 0.5) * pitch;
                p.circle_filled(egui::pos2(cx, cy), pitch * 0.36, colour);
            }
        }
        let cy = inner.min.y + (SPROCKET_ROW as f32 + 0.5) * pitch;
        p.circle_filled(egui::pos2(cx, cy), pitch * 0.18, HOLE);
    }
    // The read head over the last frame.
    if n > 0 {
        let head = Rect::from_min_max(
            egui::pos2(inner.max.x - pitch, outer.min.y + 1.0),
            egui::pos2(inner.max.x, outer.max.y - 1.0),
        );
        p.rect_stroke(head, 1.0, Stroke::new(2.0, HEAD), egui::StrokeKind::Inside);
    }
    let code = t
        .code
        .map_or(if t.plain { "text" } else { "code ?" }, |c| c.name());
    let block = match t.block {
        0 => "label".to_string(),
        b => format!("block {b}"),
    };
    let state = if t.failed { "  STOPPED: ALARM" } else { "" };
    ui.label(
        egui::RichText::new(format!(
            "{} {}  {code}  frame {}/{}  {block}{state}",
            t.target.name(),
            t.file,
            t.frame,
            t.total
        ))
        .monospace()
        .color(super::controls::LEGEND),
    );
    StripLayout {
        rect: Rect::from_min_max(egui::pos2(x0, inner.min.y), inner.max),
        pitch,
        first: t.first + (t.frames.len() - n) as u64,
        count: n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channels_sit_in_the_order_frame_row_draws_them() {
        let rows: Vec<usize> = (1..=8u8).rev().map(channel_row).collect();
        assert_eq!(rows, vec![0, 1, 2, 3, 4, 6, 7, 8]);
        assert_eq!(SPROCKET_ROW, 5);
    }
}
