//! The console: the panel state, the rules of SPEC §1, and the display program. Every front
//! end (terminal, window, panel script) drives the same `Console`.
//!
//! OWNER: front panel work (issue 5).

/// The interactive console (no subcommand): terminal panel, or the window with `--window`.
pub fn main(_argv: &[String]) -> i32 {
    crate::cli::usage_error("the console is not built yet")
}
