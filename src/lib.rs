//! novanc: a CNC operator console after the 1978 Toyoda computer NC. This library is the
//! embedded controller core; the terminal, the window, the command line and the tests all drive
//! it through the same `Console`.

pub mod ap;
pub mod backplot;
pub mod block;
pub mod cli;
pub mod console;
pub mod nc;
pub mod panel_model;
pub mod record;
pub mod settings;
pub mod store;
pub mod tooldata;
#[cfg(feature = "window")]
pub mod window;
