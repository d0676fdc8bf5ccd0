//! The checks NCBR makes on a block before any of its pulses: travel limits (including the
//! bulge of an arc), arc geometry and feed.

use crate::block::{Axes, Block, FeedMode, Motion as Kind};
use crate::pulse_core::arc::{ArcError, ArcStepper};
use crate::settings::MachineSettings;

/// Travel limits, arc geometry and feed of a block, before any of its pulses.
pub fn check_block(settings: &MachineSettings, pos: Axes, b: &Block) -> Result<(), String> {
    // Never drop a word: what this kernel does not yet run is refused before any pulse.
    if let Some(c) = b.css {
        // The limit may be infinite (none); NaN fails every comparison.
        let ok = c.m_per_min.is_finite() && c.m_per_min > 0.0 && c.limit_rpm > 0.0;
        if !ok {
            return Err(format!(
                "constant surface speed G96 S{} D{}: both must be positive",
                c.m_per_min, c.limit_rpm
            ));
        }
    }
    if let Some(lead) = b.thread {
        if b.motion != Kind::Linear {
            return Err("a thread pass (G33) must be a straight move".into());
        }
        if !(lead.is_finite() && lead >= settings.pulse_mm) {
            return Err(format!(
                "thread lead {lead} mm/rev: at least one pulse ({} mm) a revolution",
                settings.pulse_mm
            ));
        }
    }
    if b.feed_mode == FeedMode::PerRev && !b.feed.is_finite() {
        return Err(format!("feed {} mm/rev is not a number", b.feed));
    }
    // A rotary axis moves in straight blocks, by the DDA (docs/pulse-core.md, "Axes").
    for a in crate::block::FIRST_ROTARY..crate::block::MAX_AXES {
        if b.delta[a] == 0 {
            continue;
        }
        let l = axis_name(a);
        if !settings.has_axis(a) {
            return Err(format!("axis {l}: this machine has no {l} axis"));
        }
        if matches!(b.motion, Kind::ArcCw | Kind::ArcCcw) {
            return Err(format!(
                "axis {l} does not move in an arc: give it in a G00 or G01"
            ));
        }
        if settings.interpolator != crate::settings::Interpolator::Dda {
            return Err(format!("axis {l} is run by the DDA interpolator only"));
        }
    }
    let to = Axes::from_fn(|a| pos[a] + b.delta[a]);
    let limit = |p: Axes| -> Result<(), String> {
        for (a, &v) in p.iter().enumerate().filter(|(a, _)| settings.has_axis(*a)) {
            if settings.wrapped(a) {
                continue;
            }
            let (lo, hi) = settings.travel_pulses(a);
            if v < lo || v > hi {
                let lim = if v < lo { lo } else { hi };
                return Err(format!(
                    "travel limit: {} would go to {:.3} {unit}, beyond {:.3} {unit}",
                    axis_name(a),
                    settings.to_mm(v),
                    settings.to_mm(lim),
                    unit = settings.unit(a)
                ));
            }
        }
        Ok(())
    };
    match b.motion {
        Kind::Rapid | Kind::Linear => {
            limit(to)?;
            if b.motion == Kind::Linear && b.delta != [0; 3] && b.thread.is_none() && b.feed <= 0.0
            {
                return Err("no feed rate".into());
            }
        }
        Kind::ArcCw | Kind::ArcCcw => {
            limit(to)?;
            if b.feed <= 0.0 {
                return Err("no feed rate".into());
            }
            let st = arc_stepper(b)?;
            // The normal axis of a helix moves linearly between two points within the limits.
            let c = arc_centre(b, pos);
            let r = arc_radius(b) + 1;
            for p in st.extremes(r) {
                limit(Axes::from_fn(|a| c[a] + p.get(a).copied().unwrap_or(0)))?;
            }
        }
        Kind::Dwell | Kind::Aux => {}
    }
    Ok(())
}

/// "X", "Y", "Z", "A", "B" or "C".
pub fn axis_name(a: usize) -> &'static str {
    ["X", "Y", "Z", "A", "B", "C"]
        .get(a)
        .copied()
        .unwrap_or("?")
}

/// The arc's centre in machine axes, pulses (the start's coordinate along the normal).
pub fn arc_centre(b: &Block, pos: Axes) -> Axes {
    let c = b.centre3().unwrap_or([0; 3]);
    Axes::from_fn(|a| pos[a] + c.get(a).copied().unwrap_or(0))
}

/// The arc's start radius, pulses, rounded up.
pub fn arc_radius(b: &Block) -> i64 {
    let c = b.center.unwrap_or([0, 0]);
    ((c[0] as f64).hypot(c[1] as f64)).ceil() as i64
}

/// The stepper of an arc block in its plane (a helix with a move along the normal).
pub fn arc_stepper(b: &Block) -> Result<ArcStepper, String> {
    let Some(c) = b.center else {
        return Err("arc without a centre".into());
    };
    let [a0, a1, normal] = b.plane.axes();
    let rel_start = [-c[0], -c[1]];
    let rel_end = [b.delta[a0] - c[0], b.delta[a1] - c[1]];
    let ccw = b.motion == Kind::ArcCcw;
    ArcStepper::in_plane(b.plane, rel_start, rel_end, ccw, b.delta[normal]).map_err(|e| match e {
        ArcError::TooSmall => "arc radius too small".to_string(),
        ArcError::TooLarge => "arc radius too large".to_string(),
        ArcError::EndNotOnCircle { r_start, r_end } => format!(
            "arc end point is not on the circle (radius {r_start:.1} at the start, {r_end:.1} at the end, pulses)"
        ),
    })
}
