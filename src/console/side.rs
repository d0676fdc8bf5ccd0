//! What a console's machine side gives the one console's rules: the operator's side of the
//! panel (`Front`), every channel's machine (the machining centre's one, a lathe's N) and the
//! commands told to all of them. The key pipeline (`keys::press`) and the panel's switches
//! (`switches::turn`) are written once over it, so a rule means the same on every machine
//! (issue 22: each console had its own before stops 40 and 43).

use super::front::Front;
use super::Console;
use crate::panel_model::OpMode;
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
    /// A channel runs a program (RUN: not held, not stopped between blocks, not waiting for
    /// another channel): a selector turn holds it.
    fn channel_runs(&self) -> bool;
    /// Leaves the page up over the mode display.
    fn leave_page(&mut self);
    /// Lets a CONTINUOUS jog go: the machine is told when one was begun, or `always` (a jog
    /// the console lost track of must still stop).
    fn let_go_jog(&mut self, always: bool);
    /// Forgets the jog E-STOP has stopped (nothing is left to let go).
    fn forget_jog(&mut self);
    /// The machine's own rule for the selector turned from `was` to `front().op` (after the
    /// console's, `selector::turn`): whether it has said all the turn does.
    fn turned(&mut self, was: OpMode) -> bool;
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
    fn channel_runs(&self) -> bool {
        self.status.run != 0 && !self.status.hold
    }
    fn leave_page(&mut self) {
        self.pages.page = crate::panel_model::Page::Mode;
    }
    fn let_go_jog(&mut self, always: bool) {
        if always || self.jogging {
            self.command(Command::JogRelease);
        }
        self.jogging = false;
    }
    fn forget_jog(&mut self) {
        self.jogging = false;
    }
    fn turned(&mut self, was: OpMode) -> bool {
        let m = self.front.op;
        if m == OpMode::Data {
            // Lines 441–443: DATA INPUT clears RUN. A run in progress is abandoned (an e-stop
            // stays in force).
            // Running or moving (the console's own `running`), or a run loaded.
            let had_run = self.status.job.is_some() || Console::running(self);
            self.command(Command::Abandon);
            if had_run {
                self.front.message = "DATA INPUT: RUN cleared, the run was abandoned".into();
            }
            return true;
        }
        if super::selector::runs(was) && super::selector::runs(m) {
            // SINGLE BLOCK on: the block in progress is the last. Off: a run set going by a
            // START in SINGLE BLOCK still ends the block START was given for and waits for
            // START (docs/panel.md, "Rules and choices"); what the machine does is said by the
            // display (state::machine_note).
            let keep_single = m == OpMode::Auto && self.start_single && self.status.job.is_some();
            if !keep_single {
                self.command(Command::SingleBlock(m == OpMode::Single));
            }
        }
        false
    }
}
