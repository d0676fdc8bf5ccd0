//! The console: the panel state, the rules of `docs/panel.md`, and the display program. Every
//! front end (terminal, window, panel script) drives the same `Console`.
//!
//! The console owns the two selectors (operation mode 17, data-processing mode 16), the data
//! keys' entry line, the tape reader, the feed override, the help screen and the SEARCH point;
//! it enforces which key is valid in which mode (editing only in DATA INPUT with RUN = 0;
//! switching to DATA INPUT clears RUN), and drives the editor on the stores and the pulse core
//! (NCBR/PGEN) in its own thread. The run itself (what is executing, where the machine is, the
//! tool in the spindle) belongs to the pulse core: START hands it a program source that
//! translates from the machine's actual state, and the display shows what the core reports.
//! Every command to the core waits until the core has applied it, so what the display shows
//! after a key is the core's answer to that key.

mod answers;
pub(crate) mod book;
mod config;
pub(crate) mod display;
pub(crate) mod entry;
pub(crate) mod front;
mod gcode_run;
pub mod help;
pub mod keys;
pub(crate) mod manual;
mod memory;
pub mod pages;
mod panel;
mod posmem;
pub(crate) mod punch;
pub mod recording;
pub(crate) mod relay;
mod run;
mod script_line;
pub mod search;
pub(crate) mod selector;
pub(crate) mod shell;
pub(crate) mod side;
pub(crate) mod state;
pub(crate) mod switches;
pub mod tape;
pub mod tcode;
pub(crate) mod wait;

pub use config::ConsoleConfig;
pub use gcode_run::mdi_is_gcode;
pub(crate) use gcode_run::switch_message;
pub use memory::{default_state_dir, ReadReport, TextWindow};
pub use panel::Panel;
pub use run::RunSource;
pub(crate) use run::{
    deadman_ms, machine_switch_message, next_rapid, next_spindle, rapid_override_message,
    spindle_override_message, switch_words,
};
pub use script_line::script_line;
pub use wait::WAIT_LIMIT_NS;

use crate::block::TranslateError;
use crate::panel_model::{DataMode, OpMode, PanelEvent, PanelView};
use crate::pulse_core::{ClockMode, Command, PulseCore, RunKind, Status};
use crate::settings::MachineSettings;
use crate::store::Target;
use crate::tooldata::Magazine;
use memory::Memory;
use std::path::PathBuf;

/// How long an operator message lives (docs/panel.md, "Messages"), on every console. The
/// centre's console uses the first two; a lathe's channel panel, whose machine is several
/// channels, says how long by what the channels do.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum MsgLife {
    /// Until the next operator action (a key, a script word other than `wait` and `show`).
    #[default]
    NextKey,
    /// While the block executing when it was said (the run's completed-block count then)
    /// still executes and the run goes on (a START ignored during a block), and at most until
    /// the next operator action.
    WhileBlock(u64),
    /// While a channel runs (RUN, or WAIT on one that is not stopped) or jogs (JOG), and the
    /// next action at most: not while every channel stands stopped between blocks.
    WhileRunning,
}

/// A program that would not translate: shown with the ALARM lamp until the program (or the
/// tool data) changes and translates, or RESET.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramAlarm {
    /// The text START would run: program memory (AUTO) or the MDI buffer (MDI).
    pub kind: RunKind,
    /// The error.
    pub error: TranslateError,
    /// The memory revision it was found at.
    rev: u64,
}

/// The console: panel state plus the controller behind it.
pub struct Console {
    cfg: ConsoleConfig,
    mem: Memory,
    core: PulseCore,
    /// What every console holds beside its machine (`shell.rs`): the operator's side
    /// (selector, entry line, message, help, switches, override, wheel), the log book (the
    /// alarm and message history and the counters), the recording, the page shown and the MDI
    /// recall.
    shell: shell::Shell,
    data: DataMode,
    /// The last command line entered (EOB).
    last_line: String,
    /// The front end saves the counters after it has written the frame ([`Console::frame_written`]).
    saves_after_frame: bool,
    /// The counters changed since they were last saved (with `saves_after_frame`).
    counters_unsaved: bool,
    /// Position memory: the machine position and tool kept across a restart, and whether
    /// the reference return is owed (`posmem.rs`).
    posmem: posmem::PosMem,
    /// Whether the last START that set the run going was given in SINGLE BLOCK (a turn to
    /// AUTO during that block then lets the block end and waits for START).
    start_single: bool,
    /// A program that does not translate (see [`ProgramAlarm`]).
    program_alarm: Option<ProgramAlarm>,
    status: Status,
    display: Vec<String>,
    tape: Option<PathBuf>,
    /// The tape read in progress (docs/tape.md, "At the console").
    tape_read: Option<tape::TapeRead>,
    /// The read an error stopped, shown until RESET, a selector turn or another read.
    tape_stopped: Option<tape::TapeRead>,
    /// The alarm of the read an error stopped (RESET clears it; START is refused until then).
    tape_alarm: Option<String>,
    /// Where SEARCH positioned the program (the next new AUTO run starts there).
    search: Option<search::SearchPoint>,
    /// The restore plan shown for the SEARCH point, for the state it was made in.
    plan: search::PlanCache,
    /// The restore plan on display, if there is a SEARCH point.
    plan_shown: Option<Result<search::Plan, String>>,
    /// The T code the tool displays centre on.
    tool_focus: u32,
    /// Lines of the last TOOL DATA READ report.
    read_report: Vec<String>,
    /// The operator pages (POS, PROG, OFS, MSG), the history and the counters.
    pages: pages::Pages,
    /// The selector positions last told to the pulse core (for `/nc/state`).
    modes_told: Option<(OpMode, DataMode)>,
    /// The last pulse-core notice shown.
    notice_seen: Option<String>,
    /// The last run whose end has been reported.
    end_seen: u64,
    /// The G-code interpreter's state (docs/gcode.md "The interpreter's state"): every G-code
    /// run (AUTO, MDI, SINGLE BLOCK, SEARCH) starts from it and hands it back as read.
    interp: crate::gcode::InterpState,
    /// What the last G-code run has read and the console has not yet taken (until its state
    /// has come back).
    run_feed: Option<gcode_run::RunFeed>,
    /// The last G-code run's reading is kept (it moved, or ended without a refusal).
    feed_keep: bool,
    /// The last G-code run's state has come back (its feed is let go at its end).
    feed_back: bool,
    /// RESET since the last G-code run began: its state, when it comes back, is reset.
    reset_seen: bool,
}

impl Console {
    /// The part counter the POS page shows (runs of program memory that reached their end,
    /// kept across restarts) and the last run end the console has counted: MTConnect's
    /// `partcount` (docs/mtconnect.md).
    pub fn part_count(&self) -> (u64, u64) {
        (self.shell.book.counters.parts, self.end_seen)
    }

    /// Opens the console: the stores in `cfg.state_dir`, the pulse core thread, the recorder.
    /// Returns the console and the warnings to show the operator.
    pub fn open(cfg: ConsoleConfig) -> Result<(Console, Vec<String>), String> {
        cfg.check()?;
        let (mem, mut warnings) = Memory::open(
            &cfg.state_dir,
            cfg.settings.magazine_capacity,
            cfg.settings.dialect,
        )?;
        let (book, more) = book::Book::open(&cfg.state_dir);
        warnings.extend(more);
        // What the recording starts from (docs/recording.md, "Attachments"): copied only when
        // there is a file to write it to.
        let info = match cfg.record {
            Some(_) => crate::record::RecordingInfo {
                program_name: mem.program_name(),
                program_text: mem.text(crate::store::Target::Program),
                magazine: Some(mem.magazine()),
                work_offsets: std::array::from_fn(|cs| mem.system_offset_all(cs)),
                ..Default::default()
            },
            None => Default::default(),
        };
        let recorder = recording::Recording::start(
            cfg.record.as_deref(),
            cfg.sink.clone(),
            &cfg.settings,
            &info,
        )?;
        let core = PulseCore::spawn(
            cfg.settings.clone(),
            cfg.clock,
            recorder.sink().map(|s| s.with_pulses(cfg.record_pulses)),
        );
        let scale = run::default_scale(&cfg.settings);
        core.set_magazine(mem.magazine());
        if let Some(f) = cfg.interrupt {
            core.set_interrupt(f);
        }
        let status = core.status();
        let mem_params = mem.params();
        let mut c = Console {
            cfg,
            mem,
            core,
            shell: shell::Shell::new(front::Front::new(OpMode::Data, scale), book, recorder, 1),
            data: DataMode::Revise,
            last_line: String::new(),
            start_single: false,
            saves_after_frame: false,
            counters_unsaved: false,
            posmem: Default::default(),
            program_alarm: None,
            status,
            display: Vec::new(),
            tape: None,
            tape_read: None,
            tape_stopped: None,
            tape_alarm: None,
            search: None,
            plan: search::PlanCache::default(),
            plan_shown: None,
            tool_focus: 1,
            read_report: Vec::new(),
            pages: pages::Pages::new(),
            modes_told: None,
            notice_seen: None,
            end_seen: 0,
            interp: crate::gcode::InterpState::with_persistent(&mem_params, [0.0; 3], None),
            run_feed: None,
            feed_keep: false,
            feed_back: false,
            reset_seen: false,
        };
        if let Some(w) = warnings.first() {
            c.shell.front.message = w.clone();
        }
        // Fanuc's power-on: the locals and #100–#199 vacant (the MACRO page shows them so
        // before the first run, as that run would make them).
        if c.cfg.settings.dialect == crate::settings::Dialect::Fanuc {
            c.interp.fanuc_power_on();
        }
        warnings.retain(|w| !w.is_empty());
        posmem::restore(&mut c);
        c.refresh();
        Ok((c, warnings))
    }

    /// Applies one event of the panel grammar (`keys::handle`, every console's one
    /// dispatch). Never fails: a key that is not valid in the current mode gets a message on
    /// the display and changes nothing.
    pub fn handle(&mut self, ev: PanelEvent) {
        keys::handle(self, ev)
    }

    /// Polls the pulse core and refreshes the display; call at display rate.
    pub fn tick(&mut self) {
        manual::keep(self);
        self.refresh();
    }

    /// Everything a front end draws.
    pub fn view(&self) -> PanelView {
        let s = &self.cfg.settings;
        let axis_mm = [
            s.to_mm(self.status.pos[0]),
            s.to_mm(self.status.pos[1]),
            s.to_mm(self.status.pos[2]),
        ];
        // The tip takes the length POS's WORK Z takes (the tool file's with no run loaded,
        // the one in force while a revised one is pending).
        let mut tip_mm = axis_mm;
        tip_mm[2] -= pages::length_in_force(self).0;
        let rotary_deg = (s.axis_list().skip(3))
            .map(|a| (crate::settings::AXIS_NAMES[a], s.to_mm(self.status.pos[a])))
            .collect();
        PanelView {
            display: self.display.clone(),
            op_mode: self.shell.front.op,
            data_mode: self.data,
            run: self.status.run,
            lamps: state::lamps(self),
            feed_override: self.shell.front.feed_override,
            switches: self.status.switches,
            program_switches: self.shell.front.switches,
            axis_mm,
            tip_mm,
            rotary_deg,
            tool: self.status.tool,
            spindle: self.status.spindle,
            wheel: self.shell.front.wheel,
            entry: self.shell.front.entry.clone(),
            machine_ns: self.status.machine_ns,
            help: self.shell.front.help,
            page: self.shell.shown.page,
            ignored: self.shell.front.screen.ignored().map(str::to_string),
        }
    }

    /// Whether the ALARM lamp is lit: a fault in the core (RESET clears it) or a program that
    /// does not translate (fixing it or RESET clears it).
    pub fn alarm_lit(&self) -> bool {
        self.status.alarm.is_some() || self.program_alarm.is_some() || self.tape_alarm.is_some()
    }

    /// The program alarm in force, if any.
    pub fn program_alarm(&self) -> Option<&ProgramAlarm> {
        self.program_alarm.as_ref()
    }

    /// The display frame as text (what `show` prints between `--- display` and `---`): the
    /// display lines with trailing blanks removed, joined by newlines.
    pub fn frame_text(&self) -> String {
        self.display
            .iter()
            .map(|l| l.trim_end())
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// The name of the current program in program memory.
    pub fn program_name(&self) -> String {
        self.mem.program_name()
    }

    /// Whether the current program is ISO G-code (by its name or first line).
    pub fn program_is_gcode(&self) -> bool {
        self.mem.program_is_gcode()
    }

    /// Whether [`Console::run_text`] is ISO G-code.
    pub fn run_text_is_gcode(&self) -> bool {
        if self.shell.front.op == OpMode::Mdi {
            mdi_is_gcode(&self.mem.text(Target::Mdi))
        } else {
            self.program_is_gcode()
        }
    }

    /// The zero of coordinate system `cs` (0 = G54) in the stores on every axis: X Y Z (machine
    /// mm), then A B C (degrees).
    pub fn system_offset_all(&self, cs: usize) -> [f64; crate::block::MAX_AXES] {
        self.mem.system_offset_all(cs)
    }

    /// The work offsets G54 to G59 in the stores, machine mm.
    pub fn work_offsets(&self) -> crate::gcode::WorkOffsets {
        self.mem.work_offsets()
    }

    /// The current program in program memory.
    pub fn program_text(&self) -> String {
        self.mem.text(Target::Program)
    }

    /// Whether START runs the MDI buffer (the operation mode is MDI).
    pub fn run_text_is_mdi(&self) -> bool {
        self.shell.front.op == OpMode::Mdi
    }

    /// The settings a run reads its text with: in AUTO (`auto`) the program's own dialect
    /// (docs/gcode.md "Fanuc dialect"), in MDI the machine's.
    pub fn run_settings_for(&self, auto: bool) -> crate::settings::MachineSettings {
        let mut s = self.cfg.settings.clone();
        if auto {
            s.dialect = self
                .mem
                .program_dialect(&self.mem.program_name(), s.dialect);
        }
        s
    }

    /// The text START runs in the current operation mode: the MDI buffer in MDI, program memory
    /// otherwise (what a backplot should draw).
    pub fn run_text(&self) -> String {
        if self.shell.front.op == OpMode::Mdi {
            self.mem.text(Target::Mdi)
        } else {
            self.program_text()
        }
    }

    /// The magazine (T-code table and tool file) the next translation uses.
    pub fn magazine(&self) -> Magazine {
        self.mem.magazine()
    }

    /// The machine settings in force.
    pub fn settings(&self) -> &MachineSettings {
        &self.cfg.settings
    }

    /// Whether the machine is idle: RUN = 0, no axis moving and the tape reader not reading.
    pub fn is_idle(&self) -> bool {
        self.status.idle && !tape::reading(self)
    }

    /// Waits until the machine is idle (RUN = 0, no motion, the last command taken up), then
    /// refreshes the display. In real time this waits for the machine; in virtual time the
    /// machine runs until then (at most [`WAIT_LIMIT_NS`] of machine time).
    pub fn wait_idle(&mut self) {
        wait::wait(self, wait::WaitFor::Idle);
        self.refresh();
    }

    /// The operator message: what the last action did or why not (empty: nothing said; the
    /// machine's own notes are derived when the frame is drawn).
    pub fn message(&self) -> &str {
        &self.shell.front.message
    }

    /// The message line as the display shows it, unwrapped: a note on a jogged run, what the
    /// machine is doing, the alarm, a program message waiting to be acknowledged, the operator
    /// message (MTConnect's `message`, docs/mtconnect.md).
    pub fn message_line(&self) -> String {
        display::message_text(self)
    }

    /// Why the last script `wait` ended before its condition, if it did.
    pub fn wait_error(&self) -> Option<&str> {
        self.shell.front.wait_error.as_deref()
    }

    /// The tape reader key: the line typed on the data keys names the tape file to put in
    /// the reader (the line is used up).
    pub fn tape_from_entry(&mut self) {
        // Recorded as the key, which takes the typed line: a replay of the recording types
        // the same path and takes it off the entry line (a `tape PATH` event would leave it).
        self.status = self.core.status();
        self.shell
            .recorder
            .panel_event(&PanelEvent::Press(state::TAPE_KEY), self.status.machine_ns);
        if tape::refuse_key(self, "the tape reader key") {
            self.refresh();
            return;
        }
        let path = std::mem::take(&mut self.shell.front.entry);
        let path = path.trim();
        if path.is_empty() {
            self.shell.front.message =
                "tape reader: type the tape's file path first, then the tape key".into();
            self.refresh();
            return;
        }
        self.shell.front.new_action();
        tape::apply(self, PanelEvent::Tape(PathBuf::from(path)));
        self.refresh();
    }

    /// The latest pulse-core status snapshot.
    pub fn status(&self) -> &Status {
        &self.status
    }

    /// The G-code interpreter's state as the console keeps it (docs/gcode.md "The
    /// interpreter's state").
    pub fn interp_state(&self) -> &crate::gcode::InterpState {
        &self.interp
    }

    /// Where a G-code run finds the subroutines and macros it calls (program memory, then the
    /// state directory's `subroutines` folder): what START reads them from, for a preview.
    pub fn subroutines(&self) -> crate::gcode::SubPrograms {
        self.mem.subroutines()
    }

    /// What is subtracted from the axis position (machine mm, a rotary axis's degrees) to give
    /// the work position POS shows: the active system's zero with G92, and the tool length in
    /// force on Z; X Y Z A B C.
    pub fn work_origin(&self) -> [f64; crate::block::MAX_AXES] {
        let (o, r) = (pages::work_origin(self).1, pages::rotary_work_offset(self));
        [o[0], o[1], o[2], r[0], r[1], r[2]]
    }

    /// The pulse core (tests read its audit of block ends).
    pub fn core(&self) -> &PulseCore {
        &self.core
    }

    /// The configuration the console was opened with.
    pub fn config(&self) -> &ConsoleConfig {
        &self.cfg
    }

    /// Makes the counters (written to the stores at each run's end) wait until the front end
    /// has written the frame and calls [`Console::frame_written`]: the terminal does, so that
    /// a key's answer (RESET ending a run) is on the screen before the disk is waited for.
    pub fn set_saves_after_frame(&mut self, on: bool) {
        self.saves_after_frame = on;
    }

    /// The front end has written a frame: the saves [`Console::set_saves_after_frame`] held
    /// back are made now (a failure is said on the next frame).
    pub fn frame_written(&mut self) {
        if self.counters_unsaved {
            book::save_counters(self);
        }
    }

    /// Ends the session: stops the machine (RESET) and closes the recording. Returns the
    /// recording's summary, if one was made.
    pub fn finish(self) -> Result<Option<String>, String> {
        self.close(None)
    }

    /// [`Console::finish`]; `interrupted` names a stop signal that cut the session short:
    /// the machine is then stopped by E-STOP, as a lathe's is (every channel at once), and the
    /// history and the recording say EMERGENCY STOP; it is not an operator action, so no
    /// `/panel/event`. Before stop 46 the centre was RESET on a signal and a lathe E-STOPped.
    pub fn close(mut self, interrupted: Option<&str>) -> Result<Option<String>, String> {
        if interrupted.is_some() {
            self.core.command(Command::EStop);
            // The alarm into the history and `/foxglove/log`, the frame into the recording.
            self.refresh();
        } else {
            self.core.command(Command::Reset);
        }
        self.status = self.core.status();
        posmem::track(&mut self);
        run::note_run_end(&mut self);
        self.frame_written();
        let Console { core, shell, .. } = self;
        // The pulse core thread ends first: in real time it goes on publishing, and an event
        // sent after the recording closed would be counted as dropped (RECORDING INCOMPLETE).
        drop(core);
        shell.recorder.finish()
    }

    /// Polls the status, reports what the core did on its own (a run's end, a refusal),
    /// recomposes the display and records it.
    fn refresh(&mut self) {
        self.status = self.core.status();
        posmem::track(self);
        tape::advance(self);
        let s = &self.status;
        // Not idle: a jog just begun has not moved yet, but it is the machine's.
        let runs = s.moving || !s.idle;
        let block_over = |done| s.run == 0 || s.hold || s.blocks_done != done;
        if !(self.shell.front).message_lives(s.machine_ns, runs, block_over) {
            self.shell.front.message.clear();
            self.shell.front.life = MsgLife::NextKey;
        }
        run::note_run_end(self);
        gcode_run::keep_read(self);
        self.plan_shown = search::current_plan(self);
        if self.status.notice != self.notice_seen {
            if let Some(n) = &self.status.notice {
                self.shell.front.message = n.clone();
            }
            self.notice_seen = self.status.notice.clone();
        }
        let alarm = self
            .status
            .alarm
            .clone()
            .or_else(|| self.program_alarm.as_ref().map(|a| a.error.to_string()))
            .or_else(|| self.tape_alarm.clone());
        book::log(self, alarm);
        let lines = display::compose(self);
        (self.shell.recorder).frame(&mut self.display, lines, self.status.machine_ns);
        self.shell.book.program_msg = None;
        let modes = (self.shell.front.op, self.data);
        if self.modes_told != Some(modes) {
            self.core
                .set_panel_modes(self.shell.front.op.word(), self.data.word());
            self.modes_told = Some(modes);
        }
    }

    /// Whether the machine is running or moving (by the latest status).
    fn running(&self) -> bool {
        self.status.run != 0 || self.status.moving
    }

    /// Sends a command to the core and takes its answer as the status.
    fn command(&mut self, c: Command) {
        // The core keeps its notice across these (they answer no operator action of their
        // own): forgetting it was shown would show it again, after what it spoke of.
        let keeps_notice = c.keeps_notice();
        // (Every operator action that can move is refused before it comes here when the
        // position cannot be kept; this catches any other.)
        if posmem::can_move(&c) {
            if let Err(e) = posmem::before_motion(self) {
                self.shell.front.message = format!("{} ({e})", self.shell.front.message);
            }
        }
        self.status = self.core.command(c);
        if !keeps_notice {
            self.notice_seen = None;
        }
    }

    /// Dispatches one event the tape rules let through: every console's meaning of the word
    /// (`side::words`), the centre's own below.
    fn apply_event(&mut self, ev: PanelEvent) {
        side::words(self, ev)
    }

    /// The centre's own words of the panel grammar (`Side::own_word`).
    fn own_word(&mut self, ev: PanelEvent) {
        match ev {
            PanelEvent::Data(d) => {
                self.shell.shown.page = pages::Page::Mode;
                if d != self.data {
                    let was = std::mem::replace(&mut self.data, d);
                    let typed = std::mem::take(&mut self.shell.front.entry);
                    self.shell.front.y_output = None;
                    self.last_line.clear();
                    // Typed in the MDI position of the operation selector, an MDI line.
                    let mdi = self.shell.front.op == OpMode::Mdi;
                    selector::cleared(self, typed, was.name(), mdi);
                }
            }
            PanelEvent::Tape(path) => {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| path.display().to_string());
                self.shell.front.message = match (self.shell.front.op, self.data) {
                    (OpMode::Data, DataMode::Read | DataMode::ToolRead) => {
                        format!("tape {name} in the reader: press START")
                    }
                    _ => format!("tape {name} in the reader"),
                };
                self.tape = Some(path);
            }
            PanelEvent::Input {
                digital,
                index,
                value,
            } => {
                self.command(Command::Input {
                    digital,
                    index,
                    value,
                });
            }
            PanelEvent::Home => posmem::home(self),
            // The words of a machine with several channels: refused on the centre's one.
            ev @ (PanelEvent::Channel(_)
            | PanelEvent::Fault(..)
            | PanelEvent::Target(_)
            | PanelEvent::OfsMode) => {
                self.shell.front.message = format!(
                    "{}: this machine has one channel and no work flow",
                    script_line::script_line(&ev)
                );
            }
            // The words every console means alike (`side::words`), and those the one dispatch
            // (`keys::handle`) takes before the machine side.
            _ => {}
        }
    }

    /// The centre's use of a line entered at `to` (`Side::enter_line`; with `add`, +INPUT on
    /// a page); Err: why it is refused.
    fn enter_at(&mut self, to: entry::To, line: &str, add: bool) -> Result<(), String> {
        match to {
            entry::To::Page(_) => {
                self.shell.front.message = pages::enter(self, line, add)?;
                Ok(())
            }
            entry::To::Mdi => entry::mdi_line(self, line),
            entry::To::Data => entry::data_line(self, line),
            entry::To::Other => Err(format!("{} takes no line", self.shell.front.op.name())),
        }
    }

    /// START (after every console's refusals, `relay::start_allowed`): run, resume, or read
    /// the tape, by mode.
    fn start(&mut self) {
        if self.tape_alarm.is_some() {
            self.shell.front.message = "START refused: TAPE ALARM in force, press RESET".into();
            return;
        }
        match self.shell.front.op {
            OpMode::Auto | OpMode::Single => run::start_program(self, RunKind::Auto),
            OpMode::Mdi => run::start_program(self, RunKind::Mdi),
            OpMode::Data => match self.data {
                DataMode::Read => tape::start_read(self, tape::ReadTarget::Program),
                DataMode::ToolRead => tape::start_read(self, tape::ReadTarget::Tools),
                _ => {
                    self.shell.front.message = "START in DATA INPUT reads a tape (PROGRAM READ, TOOL DATA READ); turn to AUTO, MDI or SINGLE BLOCK to run".into();
                }
            },
            // `relay::start_allowed` refused these.
            OpMode::Continuous | OpMode::Step | OpMode::Handle => {}
        }
    }
}

/// A clock choice for scripts and tests: virtual time.
pub fn virtual_clock(mut cfg: ConsoleConfig) -> ConsoleConfig {
    cfg.clock = ClockMode::Virtual;
    cfg
}
