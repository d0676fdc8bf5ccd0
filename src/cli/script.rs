//! `novanc script` (SPEC §8).

/// Runs `novanc script`; returns the exit code.
pub fn main(_argv: &[String]) -> i32 {
    super::usage_error("'script' is not built yet")
}
