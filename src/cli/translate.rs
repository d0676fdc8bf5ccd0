//! `novanc translate` (SPEC §8).

/// Runs `novanc translate`; returns the exit code.
pub fn main(_argv: &[String]) -> i32 {
    super::usage_error("'translate' is not built yet")
}
