//! The egui window: the same console drawn as a desktop front panel with a backplot.
//!
//! OWNER: window work (issue 6).

/// Opens the console in a window (`novanc --window`); returns the exit code.
pub fn run(_argv: &[String]) -> i32 {
    crate::cli::usage_error("the window is not built yet")
}
