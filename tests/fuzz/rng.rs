//! The project's seeded PRNG (`novanc::pulse_core::testkit::Rng`) and the seeds of the
//! fuzz cases.

pub use novanc::pulse_core::testkit::Rng;

/// The seed of case `index` of a run whose base seed is `base` (well spread, so neighbouring
/// cases are unrelated).
pub fn case_seed(base: u64, index: u64) -> u64 {
    Rng::new(base ^ index.wrapping_mul(0xD129_0F4B_6D3A_47C5)).next_u64()
}
