//! What the pulse core's status snapshot says, derived each time it is asked for: the lamps
//! and what the machine is doing (docs/panel.md, "Messages"). Nothing here is kept, so nothing
//! here can outlive what it describes. The display program formats it; the console's view
//! reads the lamps from here, not from the display.

use super::Console;
use crate::panel_model::{Lamps, OpMode};
use crate::pulse_core::RunKind;
use novanc_panel::Key;

/// The key that acknowledges a message that lives until acknowledged (RESET acknowledges it
/// too, as a Fanuc's RESET clears its operator message).
pub(crate) const ACKNOWLEDGE: Key = Key::Esc;

/// The tape reader key: the typed line names the tape (recorded as the key, which takes it).
pub(crate) const TAPE_KEY: Key = Key::Alt('t');

/// The punch key: the typed line names the image (recorded as the key, which takes it).
pub(super) const PUNCH_KEY: Key = Key::Alt('u');

/// Whether a program's message of `kind` lives until acknowledged rather than until the next
/// key (docs/panel.md, "Messages"): `MSG`, the program's message to the operator (Fanuc's
/// #3006 kind, LinuxCNC's `(MSG,...)` notification, which stays until dismissed), and `NOT
/// KEPT` (a value the program set that the stores could not keep). A program speaks while
/// the operator's hands are on other keys; those would otherwise clear it unread. `PRINT`,
/// `DEBUG` and `LOG` are diagnostics and live until the next key.
pub(crate) fn until_acknowledged(kind: &str) -> bool {
    matches!(kind, "MSG" | "NOT KEPT")
}

/// The lamps, from the status snapshot: HOLD is a feed hold at rest or braking, not the
/// return after a manual intervention (the machine moves; RUN is lit).
pub(super) fn lamps(c: &Console) -> Lamps {
    let s = &c.status;
    let returning = s.job.as_ref().is_some_and(|j| j.returning);
    Lamps {
        run: s.run != 0,
        hold: s.hold && !returning,
        estop: s.estop,
        alarm: c.alarm_lit(),
    }
}

/// The message line while the machine is in EMERGENCY STOP, on every console.
/// A program message that lives until acknowledged, as the message line shows it (the newest,
/// and how many are before it), on every console.
pub(crate) fn unacknowledged_line(msgs: &[String]) -> Option<String> {
    let m = msgs.last()?;
    Some(match msgs.len() - 1 {
        0 => format!("{m} (Esc acknowledges)"),
        n => format!("{m} (and {n} before it; Esc acknowledges)"),
    })
}

pub(crate) const ESTOP_NOTE: &str = "EMERGENCY STOP: pulses stopped; press RESET";

/// The message line while an axis moves by hand with no run loaded (the centre's).
pub(crate) const JOG_NOTE: &str = "JOG: an axis moves by hand";

/// The message line while a run is held by STOP (the selector runs it), on every console.
pub(crate) const HOLD_NOTE: &str = "feed hold: press START to resume, RESET to abandon";

/// What the machine is doing, for the message line, derived from the status snapshot when the
/// frame is drawn (never kept), so that it cannot outlive what it describes: an emergency stop,
/// a feed hold, the end of a block START was given for in SINGLE BLOCK, a run waiting for
/// START. The return after a manual intervention and a program stop have their own notes
/// (`display::jogged_note`, `gcode_run::program_stop_note`).
pub(super) fn machine_note(c: &Console) -> Option<String> {
    let s = &c.status;
    if s.estop {
        return Some(ESTOP_NOTE.into());
    }
    let Some(job) = s.job.as_ref() else {
        // No run: what moves is HOME's reference return or moved by hand (a jog, STEP or
        // handwheel increments); said by the state while it lasts, as a lathe says a jog (stop
        // 44: the centre said nothing, and a held key's repeats cleared the jog's own message).
        // The jog's own message (`CONTINUOUS X+: jogging`) says it while it lives.
        let said =
            c.shell.front.life == super::MsgLife::WhileRunning && !c.shell.front.message.is_empty();
        return match (s.moving || !s.idle, super::posmem::homing(c)) {
            (false, _) => None,
            (true, true) => Some(super::posmem::HOMING.into()),
            (true, false) => (!said).then(|| JOG_NOTE.into()),
        };
    };
    if job.returning {
        return None;
    }
    let runs_it = match job.kind {
        RunKind::Auto => matches!(c.shell.front.op, OpMode::Auto | OpMode::Single),
        RunKind::Mdi => c.shell.front.op == OpMode::Mdi,
    };
    if s.hold {
        return Some(if runs_it {
            HOLD_NOTE.into()
        } else {
            format!(
                "feed hold: the {} run is held (RESET abandons it)",
                job.kind.name()
            )
        });
    }
    if s.run != 0 && s.in_block && s.single_block {
        return match c.shell.front.op {
            OpMode::Auto => Some(
                "AUTO: this block was started in SINGLE BLOCK; the run stops after it, START then runs on"
                    .into(),
            ),
            OpMode::Single if !c.start_single => {
                Some("SINGLE BLOCK: the machine stops after this block".into())
            }
            _ => None,
        };
    }
    let waiting = s.run == 0 && !s.in_block && !s.moving;
    if waiting && runs_it && super::gcode_run::program_stop_note(c).is_none() {
        return Some(format!(
            "{}: press START to continue",
            c.shell.front.op.name()
        ));
    }
    None
}
