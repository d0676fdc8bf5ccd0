//! What a console's machine side gives the one console's rules: the operator's side of the
//! panel (`Front`), every channel's machine (the machining centre's one, a lathe's N) and the
//! commands told to all of them. The key pipeline (`keys::press`) and the panel's switches
//! (`switches::turn`) are written once over it, so a rule means the same on every machine
//! (issue 22: each console had its own before stops 40 and 43).

use super::entry::To;
use super::front::Front;
use super::manual::ManualTarget;
use super::shell::Shell;
use super::wait::WaitFor;
use super::Console;
use crate::panel_model::{Axis, OpMode, PanelEvent};
use crate::pulse_core::{ClockMode, Command, Reached, Status};
use crate::record::Switches;
use crate::settings::MachineSettings;

/// A console's machine side (the centre's `Console`, a lathe's `LatheConsole`).
pub(crate) trait Side {
    /// What every console holds beside its machine (`shell::Shell`): the operator's side, the
    /// log book, the recording, the page shown, the MDI recall.
    fn shell(&mut self) -> &mut Shell;
    /// The same, to read.
    fn shell_ref(&self) -> &Shell;
    /// The operator's side of the console: the selector, the help page, the screen fit, the
    /// message, the panel switches, the feed override and the handwheel.
    fn front(&mut self) -> &mut Front {
        &mut self.shell().front
    }
    /// The log book (`book::Book`): the history, the counters and the program messages
    /// waiting to be acknowledged, every console's.
    fn book(&mut self) -> &mut super::book::Book {
        &mut self.shell().book
    }
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
    fn leave_page(&mut self) {
        self.shell().shown.page = crate::panel_model::Page::Mode;
    }
    /// The channel the panel's manual moves act on (the selected one; the centre's 0).
    fn selected(&self) -> usize;
    /// The machine's own refusal of a manual move of `axis` now (after E-STOP, which the one
    /// rule checks: `manual::motion`), named `what`; else where the selected channel's axes
    /// stand, and how its channel is named on the message line.
    fn manual_target(&mut self, axis: Axis, what: &str) -> Result<ManualTarget, String>;
    /// Tells channel `ch`'s machine `cmd` (a manual move, its keep-alive or release) and takes
    /// its state: a refusal is in that channel's notice (`channels`).
    fn tell(&mut self, ch: usize, cmd: Command);
    /// The clock the machine runs on.
    fn clock(&self) -> ClockMode;
    /// The machine's time now, ns.
    fn now_ns(&self) -> u64;
    /// Virtual time: runs the machine until channel `ch`'s manual move is at rest (a
    /// CONTINUOUS tap, docs/panel.md "Jogging").
    fn settle(&mut self, ch: usize);
    /// Records `ev` on `/panel/event` as the operator's (a tapped key, a key let go), at the
    /// machine's time.
    fn record(&mut self, ev: &PanelEvent) {
        let t = self.now_ns();
        self.shell().recorder.panel_event(ev, t);
    }
    /// Runs the machine for a script's wait (`wait::wait`): how the wait ended.
    fn run_wait(&mut self, w: WaitFor) -> Reached;
    /// An operator action, recorded already (`keys::handle`): the machine side's own gate
    /// (the centre's tape reader while it reads, a lathe's refusal of the centre's own
    /// words), then the rules written once and the machine's own.
    fn act(&mut self, ev: PanelEvent);
    /// The page up over the mode display.
    fn page(&self) -> crate::panel_model::Page {
        self.shell_ref().shown.page
    }
    /// The machine's refusal of the data keys where they would type now (`entry::To`): why,
    /// if it has no use for a line there (`entry::key`, written once, says it per key).
    fn takes_keys(&self, to: To) -> Result<(), String>;
    /// The machine's use of a line entered at `to` (with `add`: +INPUT on a page); Err: why it
    /// is refused (the line then stays on the entry line: `entry::enter`).
    fn enter_line(&mut self, to: To, line: &str, add: bool) -> Result<(), String>;
    /// The editor command cursor key `k` stands for on the buffer the DATA editor acts on now
    /// (the centre's data mode's buffer; a lathe's selected channel's program), worked out
    /// there by `entry::cursor_command` with a page of that machine's lines: its name and the
    /// command, or why the pointer cannot move. None: no such buffer, or not such a key.
    fn cursor_command(
        &self,
        k: novanc_panel::Key,
    ) -> Option<(&'static str, Result<String, String>)>;
    /// Runs an editor command on that buffer and stores it: a note to say, or why it is
    /// refused (nothing changed).
    fn edit(&mut self, command: &str) -> Result<String, String>;
    /// The selected channel's MDI lines last typed, for recall with Up and Down.
    fn recall(&mut self) -> &mut super::entry::Recall {
        let ch = self.selected();
        &mut self.shell().recall[ch]
    }
    /// The machine's own START (after the one rule's refusals, `relay::start_allowed`).
    fn start(&mut self);
    /// A word of the panel grammar that is the machine's own (the centre's data selector,
    /// tape, HOME and inputs; a lathe's channel selector, FAULT, TARGET and OFS), or that it
    /// refuses: every other word means the same on every machine ([`words`]).
    fn own_word(&mut self, ev: PanelEvent);
    /// The machine's own RESET (after the one rule's, `relay::reset`): what it did, said.
    fn reset(&mut self) -> String;
    /// The machine's own rule for the selector turned from `was` to `front().op` (after the
    /// console's, `selector::turn`): whether it has said all the turn does.
    fn turned(&mut self, was: OpMode) -> bool;
}

/// What a word of the panel grammar does, on every machine (after the machine side's own gate,
/// `Side::act`): the panel's switches, the operation selector, the manual moves, the data keys
/// and the relay panel are the rules written once; the rest is the machine's own
/// (`Side::own_word`). Before stop 45 each console had this match of its own.
pub(crate) fn words<C: Side>(c: &mut C, ev: PanelEvent) {
    use super::{entry, manual, relay, selector};
    if super::switches::turn(c, &ev) {
        return;
    }
    match ev {
        PanelEvent::Op(m) => selector::turn(c, m),
        PanelEvent::Jog(axis, dir) => manual::jog(c, axis, dir),
        PanelEvent::Wheel(axis, n) => manual::turn_wheel(c, axis, n),
        PanelEvent::JogRelease => relay::jog_release(c),
        PanelEvent::Key(ch) => entry::key(c, ch),
        PanelEvent::Rubout => entry::rubout(c),
        PanelEvent::Eob => entry::eob(c),
        PanelEvent::PlusInput => entry::plus_input(c),
        PanelEvent::Type(text) => entry::typed(c, &text),
        PanelEvent::Start => {
            if relay::start_allowed(c) {
                c.start();
            }
        }
        PanelEvent::Stop => relay::stop(c),
        PanelEvent::Reset => relay::reset(c),
        PanelEvent::EStop => relay::estop(c),
        ev => c.own_word(ev),
    }
}

/// The machining centre: a machine of one channel.
impl Side for Console {
    fn shell(&mut self) -> &mut Shell {
        &mut self.shell
    }
    fn shell_ref(&self) -> &Shell {
        &self.shell
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
    fn selected(&self) -> usize {
        0
    }
    fn manual_target(&mut self, _axis: Axis, what: &str) -> Result<ManualTarget, String> {
        // A run held (or stopped between blocks) may be left by hand: START first returns
        // to where it stood (manual intervention, docs/pulse-core.md).
        if self.status.run != 0 && !self.status.hold {
            return Err(format!("{what} refused: a program is running (STOP first)"));
        }
        // The position file says the axes move before they can (`posmem.rs`).
        super::posmem::before_motion(self).map_err(|e| format!("{what} refused: {e}"))?;
        Ok(ManualTarget {
            ch: 0,
            pos: self.status.machine_state().pos,
            label: String::new(),
            x_radius: false,
        })
    }
    fn tell(&mut self, _ch: usize, cmd: Command) {
        self.command(cmd);
        // Said by the rule (`manual::motion`), not again by the next refresh.
        self.notice_seen = self.status.notice.clone();
    }
    fn clock(&self) -> ClockMode {
        self.cfg.clock
    }
    fn now_ns(&self) -> u64 {
        self.status.machine_ns
    }
    fn settle(&mut self, _ch: usize) {
        self.core.run_until_idle(super::manual::SETTLE_LIMIT_NS);
        self.status = self.core.status();
    }
    fn run_wait(&mut self, w: WaitFor) -> Reached {
        super::run::run_wait(self, w)
    }
    fn act(&mut self, ev: PanelEvent) {
        self.status = self.core.status();
        super::tape::apply(self, ev);
    }
    fn start(&mut self) {
        Console::start(self)
    }
    fn own_word(&mut self, ev: PanelEvent) {
        Console::own_word(self, ev)
    }
    fn reset(&mut self) -> String {
        self.command(Command::Reset);
        self.shell.book.acknowledge();
        self.reset_seen = true;
        super::gcode_run::reset_state(&mut self.interp, &self.cfg.settings);
        self.program_alarm = None;
        self.tape_alarm = None;
        "reset: machine idle, block buffer empty".into()
    }
    fn takes_keys(&self, to: To) -> Result<(), String> {
        super::entry::centre_takes_keys(self, to)
    }
    fn enter_line(&mut self, to: To, line: &str, add: bool) -> Result<(), String> {
        Console::enter_at(self, to, line, add)
    }
    fn cursor_command(
        &self,
        k: novanc_panel::Key,
    ) -> Option<(&'static str, Result<String, String>)> {
        super::entry::centre_cursor_command(self, k)
    }
    fn edit(&mut self, command: &str) -> Result<String, String> {
        super::entry::centre_edit(self, command)
    }
    fn turned(&mut self, was: OpMode) -> bool {
        let m = self.shell.front.op;
        if m == OpMode::Data {
            // Lines 441–443: DATA INPUT clears RUN. A run in progress is abandoned (an e-stop
            // stays in force).
            // Running or moving (the console's own `running`), or a run loaded.
            let had_run = self.status.job.is_some() || Console::running(self);
            self.command(Command::Abandon);
            if had_run {
                self.shell.front.message = "DATA INPUT: RUN cleared, the run was abandoned".into();
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
