//! `novanc run` (SPEC §8).

/// Runs `novanc run`; returns the exit code.
pub fn main(_argv: &[String]) -> i32 {
    super::usage_error("'run' is not built yet")
}
