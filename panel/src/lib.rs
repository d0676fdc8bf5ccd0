//! The terminal front panel: raw mode and the alternate screen through libc, a cell buffer
//! with diff rendering, key decoding, and drawing helpers for panel devices (rotary switches,
//! buttons, lamps). It knows cells, keys and frames, not NC semantics: the console lays the
//! panel out and maps keys to panel events.
//!
//! OWNER: front panel work (issue 5).

pub mod draw;
pub mod input;
pub mod render;
pub mod screen;
pub mod term;

pub use input::{Decoder, Key};
pub use render::Renderer;
pub use screen::{Cell, Color, Screen, Style};
pub use term::Terminal;
