//! The plasma display (14): the console's display frame rasterized as orange glowing dots on
//! black, 5×7 characters in 6×9 cells. The image is rebuilt only when the frame or the dot
//! pitch changes, and shown pixel for pixel, so the dots stay crisp (and readable back from a
//! screenshot).

use super::font::{glyph, CELL_H, CELL_W};
use egui::{Color32, ColorImage, TextureHandle, TextureOptions};

/// A lit dot's core colour.
pub const DOT_ON: Color32 = Color32::from_rgb(255, 136, 24);
/// An unlit dot: the faint grid of a plasma panel.
pub const DOT_OFF: Color32 = Color32::from_rgb(34, 10, 2);
/// The panel glass behind the dots.
pub const GLASS: Color32 = Color32::from_rgb(6, 2, 0);

/// The rendered display: the frame it shows, the dot pitch and the texture.
pub struct Plasma {
    lines: Vec<String>,
    pitch: usize,
    texture: Option<TextureHandle>,
}

impl Default for Plasma {
    fn default() -> Self {
        Plasma::new()
    }
}

impl Plasma {
    /// An empty display (nothing rendered yet).
    pub fn new() -> Plasma {
        Plasma {
            lines: Vec::new(),
            pitch: 0,
            texture: None,
        }
    }

    /// The pixel size of a frame of `rows`×`cols` characters at dot `pitch` (pixels per dot).
    pub fn image_size(rows: usize, cols: usize, pitch: usize) -> [usize; 2] {
        [cols * CELL_W * pitch + pitch, rows * CELL_H * pitch + pitch]
    }

    /// The texture for this frame at this pitch, rebuilt only if either changed.
    pub fn texture(
        &mut self,
        ctx: &egui::Context,
        lines: &[String],
        pitch: usize,
    ) -> &TextureHandle {
        let stale = self.texture.is_none() || self.pitch != pitch || self.lines != lines;
        if stale {
            let img = rasterize(lines, pitch);
            match &mut self.texture {
                Some(t) if self.pitch == pitch => t.set(img, TextureOptions::NEAREST),
                _ => self.texture = Some(ctx.load_texture("plasma", img, TextureOptions::NEAREST)),
            }
            self.lines = lines.to_vec();
            self.pitch = pitch;
        }
        // The texture was set just above if it was missing.
        self.texture.get_or_insert_with(|| {
            ctx.load_texture("plasma", rasterize(lines, pitch), TextureOptions::NEAREST)
        })
    }
}

impl Plasma {
    /// Draws `lines` pixel for pixel at the largest whole dot pitch (physical pixels, 1 to
    /// `most`) that fits `max` points. Returns its rectangle and the pitch.
    pub fn show_fit(
        &mut self,
        ui: &mut egui::Ui,
        lines: &[String],
        max: egui::Vec2,
        most: usize,
    ) -> (egui::Rect, usize) {
        let cols = lines.iter().map(|l| l.chars().count()).max().unwrap_or(40);
        let rows = lines.len().max(1);
        let ppp = ui.ctx().pixels_per_point();
        let fit_w = (max.x * ppp) / (cols * super::font::CELL_W + 1) as f32;
        let fit_h = (max.y * ppp) / (rows * super::font::CELL_H + 1) as f32;
        let pitch = fit_w.min(fit_h).floor().clamp(1.0, most as f32) as usize;
        (self.show(ui, lines, pitch), pitch)
    }

    /// Shows the frame at `pitch` in the next space of `ui`, snapped to whole physical pixels
    /// so each dot is drawn pixel for pixel; returns where it went (points).
    pub fn show(&mut self, ui: &mut egui::Ui, lines: &[String], pitch: usize) -> egui::Rect {
        let ppp = ui.ctx().pixels_per_point();
        let tex = self.texture(ui.ctx(), lines, pitch);
        let size = tex.size_vec2() / ppp;
        let id = tex.id();
        let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
        let min = (rect.min.to_vec2() * ppp).round() / ppp;
        let rect = egui::Rect::from_min_size(min.to_pos2(), size);
        ui.painter().image(
            id,
            rect,
            egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
            Color32::WHITE,
        );
        rect
    }
}

/// Draws the frame: each lit dot a `pitch`-sized square (the last row and column of the pitch
/// dark, so the dots stand apart), unlit dots faint, and a soft glow around the lit ones.
pub fn rasterize(lines: &[String], pitch: usize) -> ColorImage {
    let pitch = pitch.max(1);
    let rows = lines.len();
    let cols = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let [w, h] = Plasma::image_size(rows, cols, pitch);
    // Dot intensity map: 1.0 lit, 0.0 unlit, per pixel, before glow.
    let mut lit = vec![0f32; w * h];
    let mut grid = vec![false; w * h];
    let core = if pitch >= 3 { pitch - 1 } else { pitch };
    for (r, line) in lines.iter().enumerate() {
        for (c, ch) in line.chars().enumerate() {
            let g = glyph(ch);
            for (dy, bits) in g.iter().enumerate() {
                for dx in 0..5 {
                    let on = bits & (0x10 >> dx) != 0;
                    let x0 = pitch + (c * CELL_W + dx) * pitch;
                    let y0 = pitch + (r * CELL_H + dy) * pitch;
                    for y in y0..(y0 + core).min(h) {
                        for x in x0..(x0 + core).min(w) {
                            grid[y * w + x] = true;
                            if on {
                                lit[y * w + x] = 1.0;
                            }
                        }
                    }
                }
            }
        }
    }
    let glow = box_blur(&lit, w, h, pitch);
    let mut img = ColorImage::filled([w, h], GLASS);
    for i in 0..w * h {
        img.pixels[i] = if lit[i] > 0.0 {
            DOT_ON
        } else {
            let base = if grid[i] { DOT_OFF } else { GLASS };
            let g = (glow[i] * 0.9).min(1.0);
            mix(base, Color32::from_rgb(255, 96, 0), g)
        };
    }
    img
}

fn mix(a: Color32, b: Color32, t: f32) -> Color32 {
    let l = |x: u8, y: u8| (x as f32 + (y as f32 - x as f32) * t).round() as u8;
    Color32::from_rgb(l(a.r(), b.r()), l(a.g(), b.g()), l(a.b(), b.b()))
}

/// A separable box blur of radius `r` (the glow around lit dots).
fn box_blur(src: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let r = r.max(1);
    let norm = 1.0 / (2 * r + 1) as f32;
    let mut tmp = vec![0f32; w * h];
    for y in 0..h {
        let row = &src[y * w..(y + 1) * w];
        let mut acc: f32 = row.iter().take(r + 1).sum();
        for x in 0..w {
            tmp[y * w + x] = acc * norm;
            if x + r + 1 < w {
                acc += row[x + r + 1];
            }
            if x >= r {
                acc -= row[x - r];
            }
        }
    }
    let mut out = vec![0f32; w * h];
    for x in 0..w {
        let mut acc: f32 = (0..=r.min(h.saturating_sub(1)))
            .map(|y| tmp[y * w + x])
            .sum();
        for y in 0..h {
            out[y * w + x] = acc * norm;
            if y + r + 1 < h {
                acc += tmp[(y + r + 1) * w + x];
            }
            if y >= r {
                acc -= tmp[(y - r) * w + x];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lit_dots_are_orange_and_their_positions_read_back_as_the_text() {
        let lines = vec!["A> ".to_string(), "  9".to_string()];
        let p = 3;
        let img = rasterize(&lines, p);
        assert_eq!(img.size, Plasma::image_size(2, 3, p));
        // Read each cell back the way the screenshot test does: sample each dot's core.
        let read = |r: usize, c: usize| -> [u8; 7] {
            let mut g = [0u8; 7];
            for (dy, row) in g.iter_mut().enumerate() {
                for dx in 0..5 {
                    let x = p + (c * CELL_W + dx) * p;
                    let y = p + (r * CELL_H + dy) * p;
                    if img.pixels[y * img.size[0] + x] == DOT_ON {
                        *row |= 0x10 >> dx;
                    }
                }
            }
            g
        };
        assert_eq!(read(0, 0), glyph('A'));
        assert_eq!(read(0, 1), glyph('>'));
        assert_eq!(read(0, 2), glyph(' '));
        assert_eq!(read(1, 2), glyph('9'));
        // Glow: a pixel next to a lit dot is brighter than an unlit dot far from any.
        let far = img.pixels[(img.size[1] - 1) * img.size[0]];
        assert!(far.r() < 40);
    }

    #[test]
    fn empty_frame_is_just_glass() {
        let img = rasterize(&[], 2);
        assert_eq!(img.size, [2, 2]);
        assert!(img.pixels.iter().all(|p| *p == GLASS));
    }
}
