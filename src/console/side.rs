//! What a console's machine side gives the one console's rules: the operator's side of the
//! panel (`Front`), every channel's machine (the machining centre's one, a lathe's N) and the
//! commands told to all of them. The key pipeline (`keys::press`) and the panel's switches
//! (`switches::turn`) are written once over it, so a rule means the same on every machine
//! (issue 22: each console had its own before stops 40 and 43).

use super::front::Front;
use super::Console;
use crate::pulse_core::{Command, Status};
use crate::record::Switches;
use crate::settings::MachineSettings;

/// A console's machine side (the centre's `Console`, a lathe's `LatheConsole`).
pub(crate) trait Side {
    /// The operator's side of the console: the selector, the help page, the screen fit, the
    /// message, the panel switches, the feed override and the handwheel.
    fn front(&mut self) -> &mut Front;
    /// The machine's switches (rapid and spindle override, DRY RUN, MACHINE LOCK, Z NEGLECT),
    /// the same on every channel.
    fn machine_switches(&self) -> Switches;
    /// Takes the machine's state after an action, and shows it.
    fn refresh(&mut self);
    /// Tells every channel's machine `cmd`, and takes their state.
    fn command_all(&mut self, cmd: Command);
    /// Every channel's machine's state as last taken: its switches, run, motion and latest
    /// notice (why it refused a command).
    fn channels(&self) -> Vec<Status>;
    /// The settings the selected channel's manual moves are measured in (the increment's).
    fn axis_settings(&self) -> MachineSettings;
}

/// The machining centre: a machine of one channel.
impl Side for Console {
    fn front(&mut self) -> &mut Front {
        &mut self.front
    }
    fn machine_switches(&self) -> Switches {
        self.status.switches
    }
    fn refresh(&mut self) {
        Console::refresh(self)
    }
    fn command_all(&mut self, cmd: Command) {
        self.command(cmd)
    }
    fn channels(&self) -> Vec<Status> {
        vec![self.status.clone()]
    }
    fn axis_settings(&self) -> MachineSettings {
        self.cfg.settings.clone()
    }
}
