//! novanc: a CNC operator console after the 1978 Toyoda computer NC. This library is the
//! embedded controller core; the terminal, the window, the command line and the tests all drive
//! it through the same `Console`.

pub mod backplot;
pub mod block;
pub mod cli;
pub mod console;
pub mod crc32;
pub mod gcode;
pub mod input_text;
pub mod lathe;
pub mod limits;
pub mod mtconnect;
pub mod panel_model;
pub mod pulse_core;
pub mod record;
pub mod settings;
pub mod signals;
pub mod store;
pub mod tape;
pub mod terminal;
pub mod tooldata;
pub mod translator;
#[cfg(feature = "window")]
pub mod window;
pub mod workpiece;
