//! `novanc edit` (SPEC §8).

/// Runs `novanc edit`; returns the exit code.
pub fn main(_argv: &[String]) -> i32 {
    super::usage_error("'edit' is not built yet")
}
