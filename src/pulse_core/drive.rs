//! The seam between the machine and its interpolators: a block's motion is a [`Drive`], the
//! DDA (`motion.rs`, LINE/PCHK with KT ramps, and `arc.rs`) or the error-proportional
//! interpolator (`ep/`), chosen by `MachineSettings::interpolator` when the block's motion
//! starts. The machine only calls the methods below (docs/pulse-core.md).

use super::arc::ArcStepper;
use super::ep::arc::ArcPlan;
use super::ep::EpMotion;
use super::motion::{Anchor, Motion, Progress, ThreadMotion};
use super::pulse_out::PulseOut;
use super::spindle::Spindle;
use crate::block::{Axes, Block};
use crate::settings::{Interpolator, MachineSettings};

/// One block's motion, by either interpolator.
#[derive(Clone, Debug)]
pub enum Drive {
    /// LINE/PCHK or integer circle stepping, with the KT ramp.
    Dda(Motion),
    /// Pulse trains proportional to the remaining errors (seed 001).
    Ep(EpMotion),
    /// A thread pass: LINE/PCHK timed by the spindle encoder (either interpolator).
    Thread(ThreadMotion),
}

impl Drive {
    /// A line or rapid of `delta` pulses at path speed `speed` (pulses/ns), starting at `t0`,
    /// no axis of it moving faster than its own rate (`settings.axis_rate`).
    pub fn linear(s: &MachineSettings, delta: Axes, speed: f64, accel: f64, t0: u64) -> Drive {
        match s.interpolator {
            Interpolator::Dda => Drive::dda_linear(s, delta, speed, accel, t0),
            Interpolator::ErrorProportional => {
                let (cap, _) = Drive::caps(s, &delta);
                Drive::Ep(EpMotion::linear(
                    delta.xyz(),
                    speed.min(cap),
                    s.ep_l_pulses,
                    t0,
                ))
            }
        }
    }

    /// The path speed and acceleration (pulses/ns, pulses/ns²) the axes of `delta` allow, each
    /// held to its own rate and acceleration (`motion::axis_limits`).
    fn caps(s: &MachineSettings, delta: &Axes) -> (f64, f64) {
        let rate = s
            .axis_rate
            .map(|r| super::motion::speed_pulses_ns(r, s.pulse_mm));
        let acc = s
            .axis_accel
            .map(|a| super::motion::accel_pulses_ns2(a, s.pulse_mm));
        super::motion::axis_limits(delta, &rate, &acc)
    }

    /// A line of `delta` pulses by the DDA (a rapid, a feed, a jog or a return), no axis of it
    /// moving faster than its own rate or accelerating harder than its own acceleration
    /// (`settings.axis_rate`, `axis_accel`).
    pub fn dda_linear(s: &MachineSettings, delta: Axes, speed: f64, accel: f64, t0: u64) -> Drive {
        let caps = Drive::caps(s, &delta);
        Drive::Dda(Motion::linear_within(delta, speed, accel, t0, caps))
    }

    /// A thread pass of `delta` pulses, `lead_mm` per revolution along its major axis, geared
    /// to `spindle` from where `anchor` says: the first index at or after `t0`, where the
    /// encoder stands at `t0` (a rigid tap), or where the pass before it ended.
    pub fn thread(
        s: &MachineSettings,
        delta: Axes,
        lead_mm: f64,
        spindle: &Spindle,
        t0: u64,
        anchor: Anchor,
    ) -> Drive {
        let lead = lead_mm / s.pulse_mm;
        Drive::Thread(ThreadMotion::new(delta, lead, spindle.clone(), t0, anchor))
    }

    /// The arc or helix block `b` (by `st` for the DDA) at path speed `speed`, starting at
    /// `t0` (docs/pulse-core.md).
    pub fn arc(
        s: &MachineSettings,
        b: &Block,
        st: ArcStepper,
        speed: f64,
        accel: f64,
        t0: u64,
    ) -> Drive {
        let [a0, a1, normal] = b.plane.axes();
        match (s.interpolator, b.center) {
            (Interpolator::ErrorProportional, Some(c)) => {
                let start = b.start().xyz();
                let centre = [start[a0] + c[0], start[a1] + c[1]];
                // Turning order (u → v counter-clockwise).
                let axes = b.plane.turn_axes();
                let uv = |p: [i64; 3]| [p[axes[0]], p[axes[1]]];
                let centre_uv = if axes[0] == a0 {
                    centre
                } else {
                    [centre[1], centre[0]]
                };
                let ccw = b.motion == crate::block::Motion::ArcCcw;
                let helix =
                    (b.delta[normal] != 0).then_some((normal, start[normal], b.end[normal]));
                let plan = ArcPlan::new(axes, uv(start), uv(b.end.xyz()), centre_uv, ccw, helix);
                Drive::Ep(EpMotion::arc(plan, start, speed, s.ep_l_pulses, t0))
            }
            _ => Drive::Dda(Motion::arc(st, speed, accel, t0)),
        }
    }

    /// Distributes pulses until done, at rest, or the next pulse falls at or after `horizon`.
    #[inline]
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        match self {
            Drive::Dda(m) => m.run(horizon, out),
            Drive::Ep(m) => m.run(horizon, out),
            Drive::Thread(m) => m.run(horizon, out),
        }
    }

    /// Sets the programmed speed (feed × override), pulses/ns.
    pub fn set_target(&mut self, speed: f64) {
        match self {
            Drive::Dda(m) => m.set_target(speed),
            Drive::Ep(m) => m.set_target(speed),
            // Geared to the spindle: the feed override does not act.
            Drive::Thread(_) => {}
        }
    }

    /// Feed hold on or off.
    pub fn set_hold(&mut self, hold: bool) {
        match self {
            Drive::Dda(m) => m.set_hold(hold),
            Drive::Ep(m) => m.set_hold(hold),
            // The machine defers a hold to the end of the pass.
            Drive::Thread(_) => {}
        }
    }

    /// After a rest, the motion goes on from time `t`.
    pub fn resume_at(&mut self, t: u64) {
        match self {
            Drive::Dda(m) => m.resume_at(t),
            Drive::Ep(m) => m.resume_at(t),
            Drive::Thread(_) => {}
        }
    }

    /// Whether a feed hold is in force.
    pub fn is_held(&self) -> bool {
        match self {
            Drive::Dda(m) => m.is_held(),
            Drive::Ep(m) => m.is_held(),
            Drive::Thread(_) => false,
        }
    }

    /// Whether the motion stands still.
    pub fn at_rest(&self) -> bool {
        match self {
            Drive::Dda(m) => m.at_rest(),
            Drive::Ep(m) => m.at_rest(),
            Drive::Thread(_) => false,
        }
    }

    /// Commanded path speed, mm/min.
    pub fn speed_mm_min(&self, pulse_mm: f64) -> f64 {
        match self {
            Drive::Dda(m) => m.speed_mm_min(pulse_mm),
            Drive::Ep(m) => m.speed_mm_min(pulse_mm),
            Drive::Thread(m) => m.speed_mm_min(pulse_mm),
        }
    }

    /// Time of the last pulse (or of coming to rest), ns.
    pub fn last_t(&self) -> u64 {
        match self {
            Drive::Dda(m) => m.last_t(),
            Drive::Ep(m) => m.last_t(),
            Drive::Thread(m) => m.last_t(),
        }
    }

    /// The time (ns) of the step the last `run` stopped before (`Progress::Pending`), if the
    /// interpolator knows it: the DDA's (`Motion::pending_step_at`).
    pub fn pending_step_at(&self) -> Option<f64> {
        match self {
            Drive::Dda(m) => m.pending_step_at(),
            Drive::Ep(_) | Drive::Thread(_) => None,
        }
    }

    /// A thread pass's motion (to follow a change of the spindle's target).
    pub fn as_thread(&mut self) -> Option<&mut ThreadMotion> {
        match self {
            Drive::Thread(m) => Some(m),
            _ => None,
        }
    }
}
