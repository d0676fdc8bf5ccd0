//! The interactive terminal console: the thin loop between the terminal panel (`novanc-panel`)
//! and the `Console`.

/// Runs the terminal panel; returns the exit code.
pub fn main(_argv: &[String]) -> i32 {
    crate::cli::usage_error("the terminal panel is not built yet")
}
