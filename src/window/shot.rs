//! The `--screenshot OUT` mechanism shared by the mill's and the lathe's windows
//! (docs/window.md, "Running headless"): once the window says it is ready, a few frames to
//! settle, then egui's screenshot of the window, written as PNG or PPM by `window::image`.

use egui::Rect;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// Frames drawn between "ready" and the request, so the last changes are on screen.
const SETTLE_FRAMES: u32 = 3;

/// Where a screenshot stands.
#[derive(Default)]
pub enum Shot {
    /// Not asked for yet.
    #[default]
    Idle,
    /// Ready: this many frames still to draw before asking.
    Settling(u32),
    /// Asked; the image arrives in the slot.
    Requested(Arc<Mutex<Option<Arc<egui::ColorImage>>>>),
    /// Written.
    Done,
}

impl Shot {
    /// One frame's step towards a screenshot to `path`, begun once `ready`. Returns the image
    /// size when it has been written (the caller prints its layout and closes the window), or
    /// why it could not be.
    pub fn step(
        &mut self,
        ctx: &egui::Context,
        path: &Path,
        ready: bool,
    ) -> Option<Result<[usize; 2], String>> {
        match self {
            Shot::Idle if ready => *self = Shot::Settling(SETTLE_FRAMES),
            Shot::Settling(0) => {
                let slot = Arc::new(Mutex::new(None));
                let s2 = slot.clone();
                let c2 = ctx.clone();
                ctx.request_screenshot(move |img| {
                    if let Ok(mut g) = s2.lock() {
                        *g = Some(img);
                    }
                    c2.request_repaint();
                });
                *self = Shot::Requested(slot);
            }
            Shot::Settling(n) => *self = Shot::Settling(*n - 1),
            Shot::Requested(slot) => {
                let img = slot.lock().ok().and_then(|mut g| g.take())?;
                let [w, h] = img.size;
                let rgb: Vec<u8> = img
                    .pixels
                    .iter()
                    .flat_map(|p| [p.r(), p.g(), p.b()])
                    .collect();
                *self = Shot::Done;
                return Some(
                    super::image::write(path, w, h, &rgb)
                        .map(|()| [w, h])
                        .map_err(|e| format!("cannot write {}: {e}", path.display())),
                );
            }
            _ => {}
        }
        None
    }
}

/// A rectangle in physical pixels as the screenshot line prints it: `X Y W H`, or `none`.
pub fn rect_px(r: Option<Rect>, ppp: f32) -> String {
    r.map_or("none".to_string(), |r| {
        format!(
            "{} {} {} {}",
            (r.min.x * ppp).round(),
            (r.min.y * ppp).round(),
            (r.width() * ppp).round(),
            (r.height() * ppp).round()
        )
    })
}
