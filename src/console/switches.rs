//! The panel's switches, every console's one rule (docs/panel.md "Switches", docs/lathe.md
//! "The panel"): the machining centre's console and a lathe's channel panel both turn them
//! here, the centre being a machine of one channel.
//!
//! - The feed override (0 to 150 % in 10 % steps), BLOCK DELETE, OPTIONAL STOP and the
//!   increment switch (x1 to x1000) are the console's (`Front`): kept, said, and the override
//!   told to every channel's machine.
//! - The machine's own switches, rapid override, spindle override, DRY RUN, MACHINE LOCK and
//!   Z NEGLECT, are every channel's machine's: each is told at once, and the switch is taken
//!   by every channel or by none. A refusal (MACHINE LOCK with a run loaded, say) is said in
//!   the machine's words, and a channel that took it before another refused is turned back,
//!   so no channel is ever left locked alone.
//!
//! Before stop 43 each console turned them with code of its own: the same rules written twice,
//! in different words (the centre's feed override said nothing, the lathe's did).

use super::side::Side;
use crate::panel_model::PanelEvent;
use crate::pulse_core::Command;
use crate::record::Switches;

/// Turns the switch `ev` names, if it names one: whether it did. What was done, or why it was
/// refused, is on the message line.
pub(crate) fn turn<C: Side>(c: &mut C, ev: &PanelEvent) -> bool {
    if c.front().switch(ev) {
        return true;
    }
    if let PanelEvent::WheelScale(scale) = *ev {
        let said = match super::manual::set_scale(&c.axis_settings(), scale) {
            Ok(m) => {
                c.front().wheel.1 = scale;
                m
            }
            Err(e) => e,
        };
        c.front().message = said;
        return true;
    }
    let said = |name: &str, on: bool| super::machine_switch_message(name, on);
    let checked = |m: Result<String, String>, cmd: Command| m.map(|m| (cmd, m));
    let asked = match *ev {
        PanelEvent::Override(p) => match c.front().set_override(p) {
            true => Ok((Command::Override(p), format!("feed override {p} %"))),
            false => return true,
        },
        PanelEvent::RapidOverride(p) => {
            checked(super::rapid_override_message(p), Command::RapidOverride(p))
        }
        PanelEvent::SpindleOverride(p) => checked(
            super::spindle_override_message(p),
            Command::SpindleOverride(p),
        ),
        PanelEvent::DryRun(on) => Ok((Command::DryRun(on), said("DRY RUN", on))),
        PanelEvent::MachineLock(on) => Ok((Command::MachineLock(on), said("MACHINE LOCK", on))),
        PanelEvent::ZNeglect(on) => Ok((Command::ZNeglect(on), said("Z NEGLECT", on))),
        _ => return false,
    };
    let (cmd, said) = match asked {
        Ok(a) => a,
        Err(e) => {
            c.front().message = e;
            return true;
        }
    };
    let before = c.machine_switches();
    c.command_all(cmd.clone());
    let chans = c.channels();
    if chans.iter().all(|s| holds(&s.switches, &cmd)) {
        c.front().message = said;
        return true;
    }
    let why = (chans.iter())
        .filter(|s| !holds(&s.switches, &cmd))
        .find_map(|s| s.notice.clone())
        .unwrap_or_else(|| "refused by the machine".into());
    if chans.iter().any(|s| holds(&s.switches, &cmd)) && !holds(&before, &cmd) {
        // Taken by some channels and refused by another: none keeps it.
        c.command_all(undo(&cmd, &before));
    }
    c.front().message = why;
    true
}

/// Whether a machine's switches `sw` are as `cmd` sets them.
fn holds(sw: &Switches, cmd: &Command) -> bool {
    match *cmd {
        Command::RapidOverride(p) => sw.rapid_override == p,
        Command::SpindleOverride(p) => sw.spindle_override == p,
        Command::DryRun(on) => sw.dry_run == on,
        Command::MachineLock(on) => sw.machine_lock == on,
        Command::ZNeglect(on) => sw.z_neglect == on,
        _ => true,
    }
}

/// The command that sets `cmd`'s switch back to where it stood (`before`).
fn undo(cmd: &Command, before: &Switches) -> Command {
    match *cmd {
        Command::RapidOverride(_) => Command::RapidOverride(before.rapid_override),
        Command::SpindleOverride(_) => Command::SpindleOverride(before.spindle_override),
        Command::DryRun(_) => Command::DryRun(before.dry_run),
        Command::MachineLock(_) => Command::MachineLock(before.machine_lock),
        Command::ZNeglect(_) => Command::ZNeglect(before.z_neglect),
        ref c => c.clone(),
    }
}
