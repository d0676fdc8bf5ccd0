//! The relay panel's STOP, RESET and E-STOP, and a jog released: every console's one rule
//! (docs/panel.md "Rules", docs/lathe.md "Keys"), the machining centre being a machine of one
//! channel. STOP is a feed hold on every channel that runs, and a manual move brought to rest;
//! what it did is said by the machine's state while it lasts (the feed hold note), or on the
//! message line: the machine's own words (a thread pass or a tap holds at its end), a manual
//! move braking, a run already stopped, or nothing running. STOP and E-STOP always act: each is
//! told to every channel whatever the console thinks is running.

use super::side::Side;
use crate::panel_model::OpMode;
use crate::pulse_core::Command;

/// START's rules before the machine's own: refused, and said, in the selector's manual
/// positions (START runs in AUTO, MDI and SINGLE BLOCK), and in E-STOP until RESET in those.
/// DATA INPUT is each machine's own: the centre's START reads a tape (in E-STOP too: nothing
/// moves), a lathe's refuses it. Whether START goes on.
pub(crate) fn start_allowed<C: Side>(c: &mut C) -> bool {
    let op = c.front().op;
    let why = if matches!(op, OpMode::Continuous | OpMode::Handle | OpMode::Step) {
        format!(
            "START refused in {}: use AUTO, MDI or SINGLE BLOCK",
            op.name()
        )
    } else if op != OpMode::Data && c.channels().iter().any(|s| s.estop) {
        "START refused: EMERGENCY STOP in force, press RESET".to_string()
    } else {
        return true;
    };
    c.front().message = why;
    false
}

/// STOP.
pub(crate) fn stop<C: Side>(c: &mut C) {
    let had_run = c.channels().iter().any(|s| s.job.is_some());
    c.command_all(Command::Stop);
    let after = c.channels();
    let said = if after.iter().any(|s| s.hold) {
        // The feed hold is said by the state while it lasts.
        String::new()
    } else if let Some(n) = after.iter().find_map(|s| s.notice.clone()) {
        n
    } else if after.iter().any(|s| s.moving && s.job.is_none()) {
        "STOP: the manual move decelerates to rest".into()
    } else if had_run {
        "STOP: the run is already stopped (START continues, RESET abandons)".into()
    } else {
        "STOP: the machine is not running".into()
    };
    c.front().message = said;
}

/// E-STOP: every channel's run abandoned, every axis stopped where it stands and every spindle
/// and the coolant stopped (the drives cut), from the pulse core's thread, loaded or not; the
/// jog it stopped forgotten. Said while it is in force, derived from the state, and kept once
/// in the history as an alarm.
pub(crate) fn estop<C: Side>(c: &mut C) {
    c.command_all(Command::EStop);
    c.front().forget_jog();
}

/// RESET: the jog in progress forgotten, then the machine's own RESET (`Side::reset`: the
/// centre's run abandoned, a lathe's channel or, after E-STOP, every channel), which says
/// what it did. The line being typed stays on the entry line on every machine (before stop 45
/// a lathe's RESET with nothing loaded cleared it).
pub(crate) fn reset<C: Side>(c: &mut C) {
    c.front().forget_jog();
    let said = c.reset();
    c.front().message = said;
}

/// A jog released (`jogrelease`, a jog button let go): told to the machine whether or not the
/// console knows of a jog (one it lost track of must still stop), and said.
pub(crate) fn jog_release<C: Side>(c: &mut C) {
    super::manual::release(c, true);
    c.front().message = "jog released".into();
}
