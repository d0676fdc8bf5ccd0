//! The seam between the machine and its interpolators: a block's motion is a [`Drive`], the
//! DDA (`motion.rs`, LINE/PCHK with KT ramps, and `arc.rs`) or the error-proportional
//! interpolator (`ep/`), chosen by `MachineSettings::interpolator` when the block's motion
//! starts. The machine only calls the methods below (docs/pulse-core.md).

use super::arc::ArcStepper;
use super::ep::EpMotion;
use super::motion::{Motion, Progress};
use super::pulse_out::PulseOut;
use crate::settings::{Interpolator, MachineSettings};

/// One block's motion, by either interpolator.
#[derive(Clone, Debug)]
pub enum Drive {
    /// LINE/PCHK or integer circle stepping, with the KT ramp.
    Dda(Motion),
    /// Pulse trains proportional to the remaining errors (seed 001).
    Ep(EpMotion),
}

impl Drive {
    /// A line or rapid of `delta` pulses at path speed `speed` (pulses/ns), starting at `t0`.
    pub fn linear(s: &MachineSettings, delta: [i64; 3], speed: f64, accel: f64, t0: u64) -> Drive {
        match s.interpolator {
            Interpolator::Dda => Drive::Dda(Motion::linear(delta, speed, accel, t0)),
            Interpolator::ErrorProportional => {
                Drive::Ep(EpMotion::linear(delta, speed, s.ep_l_pulses, t0))
            }
        }
    }

    /// An arc by `st` at path speed `speed`, starting at `t0`.
    pub fn arc(_s: &MachineSettings, st: ArcStepper, speed: f64, accel: f64, t0: u64) -> Drive {
        Drive::Dda(Motion::arc(st, speed, accel, t0))
    }

    /// Distributes pulses until done, at rest, or the next pulse falls at or after `horizon`.
    #[inline]
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        match self {
            Drive::Dda(m) => m.run(horizon, out),
            Drive::Ep(m) => m.run(horizon, out),
        }
    }

    /// Sets the programmed speed (feed × override), pulses/ns.
    pub fn set_target(&mut self, speed: f64) {
        match self {
            Drive::Dda(m) => m.set_target(speed),
            Drive::Ep(m) => m.set_target(speed),
        }
    }

    /// Feed hold on or off.
    pub fn set_hold(&mut self, hold: bool) {
        match self {
            Drive::Dda(m) => m.set_hold(hold),
            Drive::Ep(m) => m.set_hold(hold),
        }
    }

    /// After a rest, the motion goes on from time `t`.
    pub fn resume_at(&mut self, t: u64) {
        match self {
            Drive::Dda(m) => m.resume_at(t),
            Drive::Ep(m) => m.resume_at(t),
        }
    }

    /// Whether a feed hold is in force.
    pub fn is_held(&self) -> bool {
        match self {
            Drive::Dda(m) => m.is_held(),
            Drive::Ep(m) => m.is_held(),
        }
    }

    /// Whether the motion stands still.
    pub fn at_rest(&self) -> bool {
        match self {
            Drive::Dda(m) => m.at_rest(),
            Drive::Ep(m) => m.at_rest(),
        }
    }

    /// Commanded path speed, mm/min.
    pub fn speed_mm_min(&self, pulse_mm: f64) -> f64 {
        match self {
            Drive::Dda(m) => m.speed_mm_min(pulse_mm),
            Drive::Ep(m) => m.speed_mm_min(pulse_mm),
        }
    }

    /// Time of the last pulse (or of coming to rest), ns.
    pub fn last_t(&self) -> u64 {
        match self {
            Drive::Dda(m) => m.last_t(),
            Drive::Ep(m) => m.last_t(),
        }
    }
}
