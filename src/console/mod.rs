//! The console: the panel state, the rules of docs/panel.md, and the display program. Every front
//! end (terminal, window, panel script) drives the same `Console`.
//!
//! The console owns the two selectors (operation mode 17, data-processing mode 16), the data
//! keys' entry line, the tape reader and the feed override; it enforces which key is valid in
//! which mode (editing only in DATA INPUT with RUN = 0; switching to DATA INPUT clears RUN), and
//! drives the editor on the stores, the translator (AP) and the pulse core (NCBR/PGEN) that
//! runs in its own thread. `tick` polls the pulse core's status at display rate and refreshes
//! the plasma display.

mod config;
mod display;
mod memory;
mod run;
pub mod search;
pub mod tcode;

pub use config::ConsoleConfig;
pub use memory::{default_state_dir, ReadReport, TextWindow};

use crate::panel_model::{Axis, DataMode, Lamps, OpMode, PanelEvent, PanelView};
use crate::pulse_core::{ClockMode, Command, PulseCore, RunKind, Status};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use memory::Memory;
use std::path::PathBuf;

/// The console: panel state plus the controller behind it.
pub struct Console {
    cfg: ConsoleConfig,
    mem: Memory,
    core: PulseCore,
    op: OpMode,
    data: DataMode,
    /// The line being typed on the data keys.
    entry: String,
    /// The last command line entered (EOB).
    last_line: String,
    /// The result or error of the last action.
    message: String,
    /// A fault shown with the alarm lamp until RESET (translation error, travel limit, ...).
    alarm: Option<String>,
    /// `Y` output of the last editor command line, shown instead of the text window.
    y_output: Option<String>,
    feed_override: u32,
    wheel: (Axis, u32),
    status: Status,
    display: Vec<String>,
    tape: Option<PathBuf>,
    /// Where SEARCH positioned the program (AUTO starts there).
    search: Option<search::SearchPoint>,
    /// The run loaded in the pulse core and not finished (held, single-blocked or running).
    loaded: Option<RunKind>,
    /// First line of the statement the run started from (SEARCH), for the display.
    started_at: Option<u32>,
    /// The T code the tool displays centre on.
    tool_focus: u32,
    /// Lines of the last TOOL DATA READ report.
    read_report: Vec<String>,
    jogging: bool,
    /// The selector positions last told to the pulse core (for `/nc/state`).
    modes_told: Option<(OpMode, DataMode)>,
    /// The last pulse-core notice shown.
    notice_seen: Option<String>,
    recorder: run::Recording,
}

impl Console {
    /// Opens the console: the stores in `cfg.state_dir`, the pulse core thread, the recorder.
    /// Returns the console and the warnings to show the operator.
    pub fn open(cfg: ConsoleConfig) -> Result<(Console, Vec<String>), String> {
        cfg.check()?;
        let (mem, mut warnings) = Memory::open(&cfg.state_dir, cfg.settings.magazine_capacity)?;
        let recorder = run::Recording::start(cfg.record.as_deref(), &cfg.settings)?;
        let core = PulseCore::spawn(cfg.settings.clone(), cfg.clock, recorder.sink());
        core.set_magazine(mem.magazine());
        let status = core.status();
        let mut c = Console {
            cfg,
            mem,
            core,
            op: OpMode::Data,
            data: DataMode::Revise,
            entry: String::new(),
            last_line: String::new(),
            message: String::new(),
            alarm: None,
            y_output: None,
            feed_override: 100,
            wheel: (Axis::X, 1),
            status,
            display: Vec::new(),
            tape: None,
            search: None,
            loaded: None,
            started_at: None,
            tool_focus: 1,
            read_report: Vec::new(),
            jogging: false,
            modes_told: None,
            notice_seen: None,
            recorder,
        };
        if let Some(w) = warnings.first() {
            c.message = w.clone();
        }
        warnings.retain(|w| !w.is_empty());
        c.refresh();
        Ok((c, warnings))
    }

    /// Applies one operator action. Never fails: a key that is not valid in the current mode
    /// gets a message on the display and changes nothing.
    pub fn handle(&mut self, ev: PanelEvent) {
        self.status = self.core.status();
        self.recorder.panel_event(&ev, self.status.machine_ns);
        self.apply(ev);
        self.refresh();
    }

    /// Polls the pulse core and refreshes the display; call at display rate.
    pub fn tick(&mut self) {
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
        let mut tip_mm = axis_mm;
        tip_mm[2] -= self.status.tool_set_length;
        PanelView {
            display: self.display.clone(),
            op_mode: self.op,
            data_mode: self.data,
            run: self.status.run,
            lamps: Lamps {
                run: self.status.run != 0,
                hold: self.status.hold,
                estop: self.status.estop,
                alarm: self.alarm.is_some() || self.status.alarm.is_some(),
            },
            feed_override: self.feed_override,
            axis_mm,
            tip_mm,
            tool: self.status.tool,
            spindle: self.status.spindle,
            wheel: self.wheel,
            entry: self.entry.clone(),
            machine_ns: self.status.machine_ns,
        }
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

    /// The current program in program memory.
    pub fn program_text(&self) -> String {
        self.mem.text(crate::store::Target::Program)
    }

    /// The text START runs in the current operation mode: the MDI buffer in MDI, program memory
    /// otherwise (what a backplot should draw).
    pub fn run_text(&self) -> String {
        if self.op == OpMode::Mdi {
            self.mem.text(crate::store::Target::Mdi)
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

    /// Whether the machine is idle: RUN = 0 and no axis moving.
    pub fn is_idle(&self) -> bool {
        self.status.idle
    }

    /// Waits until the machine is idle (RUN = 0, no motion, the last command taken up), then
    /// refreshes the display. In real time this waits for the machine; in virtual time it
    /// returns as soon as the pulse core has caught up.
    pub fn wait_idle(&mut self) {
        run::wait_idle(self);
        self.refresh();
    }

    /// The tape reader key: the line typed on the data keys names the tape file to put in
    /// the reader (the line is used up).
    pub fn tape_from_entry(&mut self) {
        let path = std::mem::take(&mut self.entry);
        let path = path.trim();
        if path.is_empty() {
            self.message = "tape reader: type the tape's file path first, then the tape key".into();
            self.refresh();
            return;
        }
        self.handle(PanelEvent::Tape(PathBuf::from(path)));
    }

    /// The latest pulse-core status snapshot.
    pub fn status(&self) -> &Status {
        &self.status
    }

    /// The configuration the console was opened with.
    pub fn config(&self) -> &ConsoleConfig {
        &self.cfg
    }

    /// Ends the session: stops the machine and closes the recording. Returns the recording's
    /// summary, if one was made.
    pub fn finish(self) -> Result<Option<String>, String> {
        self.core.command(Command::Reset);
        self.recorder.finish()
    }

    /// Polls the status, keeps the run bookkeeping, recomposes the display and records it.
    fn refresh(&mut self) {
        self.status = self.core.status();
        // A finished run (the loaded program taken up to its end) is no longer held.
        if self.status.run == 0
            && !self.status.moving
            && self.status.program_end
            && self.loaded.take().is_some()
            && self.status.alarm.is_none()
        {
            self.message = format!(
                "program end: {} blocks in {:.1} s",
                self.status.blocks_done,
                self.status.machine_ns as f64 / 1e9
            );
        }
        if let Some(a) = &self.status.alarm {
            if self.alarm.as_ref() != Some(a) {
                self.alarm = Some(a.clone());
            }
        }
        if self.status.notice != self.notice_seen {
            if let Some(n) = &self.status.notice {
                self.message = n.clone();
            }
            self.notice_seen = self.status.notice.clone();
        }
        let lines = display::compose(self);
        if lines != self.display {
            self.display = lines;
            self.recorder.display(&self.display, self.status.machine_ns);
        }
        let modes = (self.op, self.data);
        if self.modes_told != Some(modes) {
            self.core.set_panel_modes(self.op.word(), self.data.word());
            self.modes_told = Some(modes);
        }
    }

    /// Whether the machine is running or moving.
    fn running(&self) -> bool {
        self.status.run != 0 || self.status.moving
    }

    /// Dispatches one event (the rules of docs/panel.md).
    fn apply(&mut self, ev: PanelEvent) {
        match ev {
            PanelEvent::Op(m) => self.turn_op(m),
            PanelEvent::Data(d) => {
                if d != self.data {
                    self.data = d;
                    self.entry.clear();
                    self.y_output = None;
                    self.message.clear();
                    self.last_line.clear();
                }
            }
            PanelEvent::Key(ch) => {
                if self.may_enter(&format!("key '{ch}'")) {
                    if self.entry.chars().count() < 240 {
                        self.entry.push(ch);
                    } else {
                        self.message = "the command line is full (240 characters)".into();
                    }
                }
            }
            PanelEvent::Rubout => {
                if self.may_enter("RUBOUT") {
                    self.entry.pop();
                }
            }
            PanelEvent::Eob => {
                if self.may_enter("EOB") {
                    let line = std::mem::take(&mut self.entry);
                    self.enter_line(line);
                }
            }
            PanelEvent::Type(text) => {
                if self.may_enter(&format!("'{text}'")) {
                    self.entry.clear();
                    self.enter_line(text);
                }
            }
            PanelEvent::Tape(path) => {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| path.display().to_string());
                self.message = match (self.op, self.data) {
                    (OpMode::Data, DataMode::Read | DataMode::ToolRead) => {
                        format!("tape {name} in the reader: press START")
                    }
                    _ => format!("tape {name} in the reader"),
                };
                self.tape = Some(path);
            }
            PanelEvent::Start => self.start(),
            PanelEvent::Stop => {
                if self.running() {
                    self.core.command(Command::Stop);
                    self.message = "feed hold: press START to resume, RESET to abandon".into();
                } else {
                    self.message = "STOP: the machine is not running".into();
                }
            }
            PanelEvent::Reset => {
                self.core.command(Command::Reset);
                self.loaded = None;
                self.alarm = None;
                self.started_at = None;
                self.jogging = false;
                self.message = "reset: machine idle, block buffer empty".into();
            }
            PanelEvent::EStop => {
                self.core.command(Command::EStop);
                self.jogging = false;
                self.message = "EMERGENCY STOP: pulses stopped; press RESET".into();
            }
            PanelEvent::Override(p) => {
                if p <= 150 && p % 10 == 0 {
                    self.feed_override = p;
                    self.core.command(Command::Override(p));
                } else {
                    self.message = format!("override {p} % is not 0 to 150 in 10 % steps");
                }
            }
            PanelEvent::WheelScale(s) => {
                if [1, 10, 100].contains(&s) {
                    self.wheel.1 = s;
                } else {
                    self.message = format!("handwheel scale x{s}: only x1, x10, x100");
                }
            }
            PanelEvent::Wheel(axis, n) => run::wheel(self, axis, n),
            PanelEvent::Jog(axis, dir) => run::jog(self, axis, dir),
            PanelEvent::JogRelease => {
                if self.jogging {
                    self.core.command(Command::JogRelease);
                    self.jogging = false;
                }
            }
            PanelEvent::Wait => run::wait_idle(self),
            PanelEvent::Show => {}
        }
    }

    /// Turns the operation mode selector 17.
    fn turn_op(&mut self, m: OpMode) {
        if m == self.op {
            return;
        }
        if self.jogging {
            self.core.command(Command::JogRelease);
            self.jogging = false;
        }
        let was = self.op;
        self.op = m;
        self.entry.clear();
        if m == OpMode::Data {
            // Lines 441–443: DATA INPUT clears RUN. A run in progress is held and abandoned.
            if self.running() || self.loaded.is_some() {
                self.core.command(Command::Stop);
                self.core.command(Command::Reset);
                self.loaded = None;
                self.started_at = None;
                self.message = "DATA INPUT: RUN cleared, the run was abandoned".into();
            } else {
                self.message.clear();
            }
            return;
        }
        let runs = |o: OpMode| matches!(o, OpMode::Auto | OpMode::Single);
        if runs(was) && runs(m) {
            self.core.command(Command::SingleBlock(m == OpMode::Single));
            self.message = if m == OpMode::Single {
                "SINGLE BLOCK: the machine stops after this block".into()
            } else if self.loaded.is_some() {
                "AUTO: press START to continue".into()
            } else {
                String::new()
            };
            return;
        }
        if self.running() {
            self.core.command(Command::Stop);
            self.message = format!(
                "feed hold: mode changed to {} while running",
                display::op_name(m)
            );
        } else {
            self.message.clear();
        }
    }

    /// Whether the data keys may be used now; if not, says why on the display.
    fn may_enter(&mut self, what: &str) -> bool {
        if self.op != OpMode::Data {
            self.message = format!(
                "{what} refused: data keys work in DATA INPUT only (now {})",
                display::op_name(self.op)
            );
            return false;
        }
        if self.running() {
            self.message = format!("{what} refused: the machine is running");
            return false;
        }
        true
    }

    /// A command line ended with EOB, in DATA INPUT with RUN = 0.
    fn enter_line(&mut self, line: String) {
        use crate::store::Target;
        self.last_line = line.clone();
        self.y_output = None;
        let target = match self.data {
            DataMode::Revise => Target::Program,
            DataMode::Mdi => Target::Mdi,
            DataMode::ToolRevise => Target::ToolFile,
            DataMode::TCode => return tcode::enter(self, &line),
            DataMode::Search => return search::enter(self, &line),
            DataMode::Read | DataMode::ToolRead => {
                self.message = "put the tape in the reader and press START to read it".into();
                return;
            }
        };
        let rows = display::text_rows(self.cfg.rows);
        match self.mem.edit(target, &line, Some(rows)) {
            Ok(y) => {
                if !y.is_empty() {
                    self.y_output = Some(y);
                }
                self.message = "ok".into();
                if target == Target::Program && self.search.take().is_some() {
                    self.message = "ok; SEARCH point cleared (program changed)".into();
                }
            }
            Err(e) => self.message = e,
        }
    }

    /// START: run, resume, or read the tape, by mode.
    fn start(&mut self) {
        if self.status.estop {
            self.message = "START refused: EMERGENCY STOP in force, press RESET".into();
            return;
        }
        match self.op {
            OpMode::Auto | OpMode::Single => run::start_program(self, RunKind::Auto),
            OpMode::Mdi => run::start_program(self, RunKind::Mdi),
            OpMode::Data => match self.data {
                DataMode::Read => run::read_program_tape(self),
                DataMode::ToolRead => run::read_tool_tape(self),
                _ => {
                    self.message = "START in DATA INPUT reads a tape (PROGRAM READ, TOOL DATA READ); turn to AUTO, MDI or SINGLE BLOCK to run".into();
                }
            },
            OpMode::Continuous | OpMode::Step | OpMode::Handle => {
                self.message = format!(
                    "START refused in {}: use AUTO, MDI or SINGLE BLOCK",
                    display::op_name(self.op)
                );
            }
        }
    }
}

/// A clock choice for scripts and tests: virtual time.
pub fn virtual_clock(mut cfg: ConsoleConfig) -> ConsoleConfig {
    cfg.clock = ClockMode::Virtual;
    cfg
}
