//! ISO 6983 G-code programs (docs/gcode.md): LinuxCNC 2.9's language for a three-axis mill,
//! read by an interpreter whose state lives as long as the machine.
//!
//! [`GcodeSource`] is, like the source-language `translator::Translator`, an iterator of
//! statements: one executed line is one statement, with the blocks generated from it (canned
//! cycles expanded, offsets, tool length and cutter compensation applied), in absolute
//! machine pulses. After an error it yields nothing more.
//!
//! The house: `state` (the interpreter's state) depends on nothing of the rest; `read` reads a
//! line against it, `flow` moves between lines (O-words, calls), `exec` executes a line in
//! LinuxCNC's order with `moves`, `cycles`, `comp`, `probe` and `spline`, and `canon` turns
//! the result into blocks.

pub mod canon;
pub mod comp;
pub mod cycles;
pub mod exec;
pub mod flow;
pub mod geom;
pub mod moves;
pub mod probe;
pub mod read;
pub mod search;
pub mod spline;
pub mod state;
pub mod sysvars;
pub mod words;

pub use exec::{Ask, Clocks, Event, Machine, Probed};
pub use flow::{NoFiles, SubFinder};
pub use probe::SimMachine;
pub use search::translate_all;
pub use state::InterpState;

use crate::block::{MachineState, Statement, TranslateError};
use crate::settings::{Dialect, MachineSettings};
use crate::tooldata::Magazine;
use canon::{Canon, Emitter};
use comp::Comp;
use exec::{Exec, Flow as LineFlow};
use flow::{Flow, Pos};
use read::{Env, Target};
use std::path::PathBuf;
use std::sync::Arc;

/// The bounds of a program's work (docs/limits.md): the most repeats an L word asks for, the
/// most lines a program may execute (every line read, every repeat counted), the most blocks
/// one line and one program may make.
pub use crate::limits::{MAX_BLOCKS, MAX_LINES, MAX_PROGRAM_BLOCKS, MAX_REPEATS};

/// The work offsets G54 to G59 (index 0 to 5), machine mm of each system's zero.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorkOffsets(pub [[f64; 3]; 6]);

/// A work offset a program changed (G10 L2 or L20), for the caller to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OffsetChange {
    /// The system, 0 = G54 … 5 = G59.
    pub system: usize,
    /// Its new zero, machine mm.
    pub offset: [f64; 3],
}

/// The panel switches a program reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Switches {
    /// BLOCK DELETE: lines starting with `/` are skipped.
    pub block_delete: bool,
    /// OPTIONAL STOP: M01 stops.
    pub optional_stop: bool,
}

/// The file extensions of G-code programs (LinuxCNC's `.ngc`, `.nc`, ISO `.iso`, and what
/// CAM posts write: `.tap`, `.gcode`, `.cnc`).
pub const GCODE_EXTENSIONS: [&str; 6] = ["ngc", "nc", "iso", "tap", "gcode", "cnc"];

/// Whether a program is G-code: by its file name (`GCODE_EXTENSIONS`) or by its first line
/// (`%`, or `O` and a number).
pub fn is_gcode(file_name: &str, text: &str) -> bool {
    let lower = file_name.to_ascii_lowercase();
    if let Some((_, ext)) = lower.rsplit_once('.') {
        if GCODE_EXTENSIONS.contains(&ext) {
            return true;
        }
    }
    let Some(first) = text.lines().map(str::trim).find(|l| !l.is_empty()) else {
        return false;
    };
    if first == "%" {
        return true;
    }
    let mut c = first.chars();
    matches!(c.next(), Some('O' | 'o')) && c.next().is_some_and(|d| d.is_ascii_digit())
}

/// The text of the statement that restores the machine before a SEARCH point.
pub fn restore_text(line: u32) -> String {
    format!("(SEARCH: restore for line {line})")
}

/// Finds subroutine files `name.ngc` in a list of folders (the subroutine path).
#[derive(Debug)]
pub struct SubPath(pub Vec<PathBuf>);

impl SubFinder for SubPath {
    fn find(&self, name: &str) -> Result<Option<(String, Arc<str>)>, String> {
        if name.contains(['/', '\\']) || name.starts_with('.') {
            return Err(format!("o<{name}>: a subroutine name cannot be a path"));
        }
        for dir in &self.0 {
            let file = format!("{name}.ngc");
            let p = dir.join(&file);
            match std::fs::read(&p) {
                Ok(b) => {
                    let text = crate::input_text::decode(&b)
                        .map_err(|e| format!("{}:{e}", p.display()))?;
                    return Ok(Some((file, text.into())));
                }
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Err(e) => return Err(format!("cannot read {}: {e}", p.display())),
            }
        }
        Ok(None)
    }
}

/// Subroutines kept as programs (the console's program memory, `NAME.NGC`), then files of a
/// subroutine path: what `o<name> call` finds at the console.
#[derive(Debug)]
pub struct SubPrograms {
    /// Program name (upper case, with its extension) and text.
    pub programs: Vec<(String, Arc<str>)>,
    /// Then these folders.
    pub path: SubPath,
}

impl SubFinder for SubPrograms {
    fn find(&self, name: &str) -> Result<Option<(String, Arc<str>)>, String> {
        let want = format!("{}.NGC", name.to_ascii_uppercase());
        // A program number (M98/G65 P9010) is also program O9010.NGC, as a Fanuc DNC file's
        // programs are stored (docs/gcode.md "Fanuc dialect").
        let numbered = name
            .bytes()
            .all(|c| c.is_ascii_digit())
            .then(|| format!("O{want}"));
        if let Some((n, t)) = self
            .programs
            .iter()
            .find(|(n, _)| *n == want || Some(n) == numbered.as_ref())
        {
            return Ok(Some((n.clone(), t.clone())));
        }
        self.path.find(name)
    }
}

/// Parameters as a line sees them: the interpreter's state and the running subroutine's
/// locals.
struct ParamEnv<'a> {
    st: &'a InterpState,
    flow: &'a Flow,
    /// The Fanuc dialect: its system variables (`sysvars`) are read.
    fanuc: bool,
    /// The mill's tool data (`None` on a back end's lines: the lathe keeps its own).
    magazine: Option<&'a Magazine>,
    parts: Option<(u64, u64)>,
    first_code: Option<usize>,
    adp: &'a [u64],
    /// The machine's clocks at this line, once it has answered (Fanuc's #3001, #3002).
    clocks: Option<exec::Clocks>,
    /// The clock the line read without them.
    wants_clocks: &'a std::cell::Cell<Option<usize>>,
    /// A motion back end other than the mill's executes the words (the lathe's): the
    /// system variables and parameters that report a machine's state are its to answer
    /// ([`Motion::param`]), else refused ([`lathe_refuses`]). `None` for the mill.
    back: Option<&'a dyn Motion>,
}

impl ParamEnv<'_> {
    /// The number of the program running now: the subprogram's or macro's, else the main
    /// program's `O` (Fanuc's #4115).
    fn program_number(&self) -> Option<f64> {
        let name = match self.flow.sub_name() {
            Some(n) if self.flow.level() > 0 => n.to_string(),
            _ => {
                let l = self.flow.units[0].nth_line(self.first_code?)?;
                let t = l.trim_start();
                let t = t.strip_prefix(['O', 'o'])?;
                t.chars().take_while(char::is_ascii_digit).collect()
            }
        };
        name.parse::<u32>().ok().map(f64::from)
    }
}

/// LinuxCNC's predefined named parameters the one reader keeps for every machine (the last N,
/// a subroutine's returned value, the call level, the interpreter's version): a back end's
/// lines read them as the mill's do.
const READER_NAMES: [&str; 7] = [
    "_line",
    "_value",
    "_value_returned",
    "_call_level",
    "_task",
    "_vmajor",
    "_vminor",
];

/// Fanuc's argument specification I: the letters G65 takes and the local variable each
/// sets (A→#1, B→#2, C→#3, I→#4, J→#5, K→#6, D→#7, E→#8, F→#9, H→#11, M→#13, Q→#17,
/// R→#18, S→#19, T→#20, U→#21, V→#22, W→#23, X→#24, Y→#25, Z→#26).
pub const G65_ARGUMENTS: [(char, usize); 21] = [
    ('A', 1),
    ('B', 2),
    ('C', 3),
    ('I', 4),
    ('J', 5),
    ('K', 6),
    ('D', 7),
    ('E', 8),
    ('F', 9),
    ('H', 11),
    ('M', 13),
    ('Q', 17),
    ('R', 18),
    ('S', 19),
    ('T', 20),
    ('U', 21),
    ('V', 22),
    ('W', 23),
    ('X', 24),
    ('Y', 25),
    ('Z', 26),
];

impl ParamEnv<'_> {
    /// A back end's machine state `#n` (the lathe's): the one reader's modal items and part
    /// counter, else the back end's answer; `None` if neither has it.
    fn back_param(&self, back: &dyn Motion, n: usize) -> Option<Result<f64, String>> {
        if self.fanuc {
            if let Some(m) = back.modal() {
                let program = if matches!(n, 4115 | 4315) {
                    self.program_number()
                } else {
                    None
                };
                if let Some(r) = sysvars::modal_info(n, self.st, program, m) {
                    return Some(r);
                }
            }
            if matches!(n, 3901 | 3902) {
                return Some(sysvars::parts(n, self.parts));
            }
        }
        back.param(n, self.fanuc)
    }
}

impl Env for ParamEnv<'_> {
    fn numbered(&self, n: usize) -> Result<f64, String> {
        if let Some(back) = self.back {
            if let Some(r) = self.back_param(back, n) {
                return r;
            }
            if lathe_refuses(self.fanuc, n) {
                return Err(lathe_refusal(self.fanuc, n));
            }
            return Ok(self.st.param(n));
        }
        if let (true, Some(magazine)) = (self.fanuc, self.magazine) {
            let e = sysvars::SysEnv {
                st: self.st,
                magazine,
                parts: self.parts,
                program: if matches!(n, 4115 | 4315) {
                    self.program_number()
                } else {
                    None
                },
                clocks: self.clocks,
                wants_clocks: self.wants_clocks,
            };
            if let Some(r) = sysvars::read(n, &e) {
                return r;
            }
        }
        if (5420..=5428).contains(&n) && self.st.modal.comp != state::CompSide::Off {
            return Err(format!(
                "#{n} (the current position) cannot be read with cutter radius compensation on"
            ));
        }
        Ok(self.st.param(n))
    }

    fn named(&self, name: &str) -> Result<Option<f64>, String> {
        if let Some(back) = self.back.filter(|_| name.starts_with('_')) {
            if let Some(r) = back.named_param(name) {
                return r.map(Some);
            }
            if self.st.predefined(name).is_some() && !READER_NAMES.contains(&name) {
                return Err(format!(
                    "#<{name}> reports the mill's interpreter state: the lathe reader does not give it (docs/lathe-gcode.md \"System variables\")"
                ));
            }
        }
        if matches!(name, "_x" | "_y" | "_z") && self.st.modal.comp != state::CompSide::Off {
            return Err(format!("#<{name}> (the current position) cannot be read with cutter radius compensation on"));
        }
        Ok(self.st.named_value(name, self.flow.locals()))
    }

    fn unpointed(&self, n: usize) -> bool {
        let level = self.flow.g65_level();
        level > 0 && self.adp.get(level).is_some_and(|m| m & (1 << n) != 0)
    }
}

/// A machine's own execution of a line's words behind the one reader (docs/lathe-gcode.md
/// "One reader"): [`GcodeSource`] reads the lines, runs the program's flow (O-words, M98/M99,
/// the Fanuc dialect's GOTO, IF, WHILE/DO/END, G65/G66 calls), sets the parameters, runs the
/// messages and keeps the bounds; each line left with words to execute is handed to the back
/// end ([`GcodeSource::next_with`]), which makes its own blocks. The mill's back end is the
/// source's own (`exec`, `canon`); the lathe's is `lathe::gcode`'s reader.
pub trait Motion {
    /// Executes the words of the line at `at` (its number `at.line + 1`): its parameters
    /// are set and its flow is done. `lines` reads other lines of the program for it (a
    /// G70/G71 profile).
    fn words(
        &mut self,
        line: &read::Line,
        at: Pos,
        lines: &mut dyn Lines,
    ) -> Result<Then, TranslateError>;

    /// A stop with a message (Fanuc's `#3006`) at line `n`, column `col`: as M00.
    fn stop(&mut self, n: u32, col: u32) -> Result<(), TranslateError>;

    /// The machine state `#n` this back end keeps, read at the line being read: a Fanuc
    /// system variable (`fanuc`) or one of LinuxCNC's parameters; its value, or why it
    /// cannot be read. `None`: the back end keeps no such one (the reader refuses it,
    /// [`lathe_refuses`]). The modal information and the part counter are the reader's
    /// ([`Motion::modal`]).
    fn param(&self, n: usize, fanuc: bool) -> Option<Result<f64, String>> {
        let _ = (n, fanuc);
        None
    }

    /// LinuxCNC's predefined named parameter `#<name>` (`_x`, `_metric`, …) as this back end
    /// keeps it; `None`: it keeps no such one.
    fn named_param(&self, name: &str) -> Option<Result<f64, String>> {
        let _ = name;
        None
    }

    /// Fanuc's modal information (#4001–, #4201–) of this back end's groups, if it keeps any.
    fn modal(&self) -> Option<&dyn sysvars::Modal> {
        None
    }

    /// A write of `#n`, one of the back end's ([`Motion::param`]): done, or why not.
    /// `None`: the reader refuses it ([`lathe_refuses`]).
    fn write_param(&mut self, n: usize, v: f64, fanuc: bool) -> Option<Result<(), String>> {
        let _ = (n, v, fanuc);
        None
    }

    /// The next line this back end executes is the rest of a line whose remapped M code
    /// ([`Then::Remap`]) has called its subroutine, now returned: only its steps after that
    /// code run.
    fn after_remap(&mut self) {}
}

/// What a back end's line asks of the program's flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Then {
    /// Go on with the next line.
    Next,
    /// M98 P`o` L`l`: call subprogram O`o`.
    Call {
        /// The program number.
        o: u32,
        /// The repeats.
        l: Option<u32>,
        /// The column of M98.
        col: u32,
    },
    /// M99: return from a subprogram.
    Return {
        /// The column of M99.
        col: u32,
    },
    /// M02/M30: the program ends.
    End,
    /// Go on at this line, further on in the same unit (past a G71's profile).
    Skip(Pos),
    /// An M code the machine description remaps (modal group 10), at column `col`: call its
    /// subroutine; on the return the back end runs the rest of the line
    /// ([`Motion::after_remap`]).
    Remap {
        /// The M code.
        m: u32,
        /// Its column.
        col: u32,
    },
}

/// What a back end may ask of the reader while it executes a line.
pub trait Lines {
    /// Reads line `raw`, numbered `n`, of the program with its parameters, as a line the
    /// program runs (its assignments set, its messages run, counted against the bound on the
    /// lines a program executes); its words are the back end's to execute. A line of flow
    /// (an O-word, GOTO, WHILE, a macro call) or `#3006` is refused: it cannot run inside
    /// another line.
    /// `back` is the back end asking (it answers the system variables the line reads).
    fn read_line(
        &mut self,
        raw: &str,
        n: u32,
        back: &mut dyn Motion,
    ) -> Result<read::Line, TranslateError>;

    /// The program's units from here on (G20 `inch`, or G21), as the back end keeps them:
    /// the Fanuc dialect's least increment follows them (0.0001 inch, 0.001 mm).
    fn units(&mut self, inch: bool);

    /// A remap subroutine runs now (its M code, called inside it, has no meaning of its
    /// own: docs/gcode.md "Remapping M6 and other M codes").
    fn in_remap(&self) -> bool;
}

/// Whether parameter `n` is refused by a lathe back end when neither it nor the reader
/// answers for it ([`Motion::param`], [`Motion::modal`]): in the Fanuc dialect the system
/// variables (#1000 and above, but for #3000 and #3006, which are messages), in LinuxCNC's
/// the parameters from #5000 on (offsets, positions, the tool: the mill's state).
pub fn lathe_refuses(fanuc: bool, n: usize) -> bool {
    if fanuc {
        n >= 1000 && !matches!(n, 3000 | 3006)
    } else {
        n >= 5000
    }
}

fn lathe_refusal(fanuc: bool, n: usize) -> String {
    if fanuc {
        format!("#{n}: the lathe keeps no such system variable (docs/lathe-gcode.md \"System variables\" lists those it has)")
    } else {
        format!("#{n}: parameters from #5000 report the mill's state; the lathe keeps #1 to #4999 and those docs/lathe-gcode.md \"System variables\" lists")
    }
}

/// The parameters as the line being read sees them (a macro over the source's fields, so
/// that its scratch stays free to borrow).
macro_rules! param_env {
    ($s:ident, $clocks:expr, $wants:expr, $back:expr) => {
        ParamEnv {
            st: &$s.st,
            flow: &$s.flow,
            fanuc: $s.settings.dialect == Dialect::Fanuc,
            magazine: Some(&$s.magazine),
            parts: $s.parts,
            first_code: $s.first_code,
            adp: &$s.adp,
            clocks: $clocks,
            wants_clocks: $wants,
            back: $back,
        }
    };
}

/// One line's execution context over the source's fields (a macro, so that the other
/// fields stay free to borrow).
macro_rules! ctx {
    ($s:ident, $n:expr) => {
        Exec {
            n: $n,
            out: std::mem::take(&mut $s.out_buf),
            events: Vec::new(),
            settings: &$s.settings,
            magazine: &mut $s.magazine,
            optional_stop: $s.switches.optional_stop,
            asks: Vec::new(),
            remap_m6: $s.settings.remap_m6.is_some() && $s.remap.is_none(),
            remap_free: $s.remap.is_none(),
            after: 0,
        }
    };
}

/// The most blocks a statement handed back to [`GcodeSource::recycle`] may have room for to be
/// kept for the next line.
const SPARE_BLOCKS: usize = 64;

/// A G-code program as an iterator of statements.
pub struct GcodeSource {
    flow: Flow,
    st: InterpState,
    comp: Comp,
    magazine: Magazine,
    settings: MachineSettings,
    switches: Switches,
    emitter: Emitter,
    start: MachineState,
    resume_at: Option<u32>,
    /// SEARCH: a line before the SEARCH point moved Z from where the machine stood.
    z_moved: bool,
    held: Option<Statement>,
    /// A statement handed back by [`GcodeSource::recycle`], its memory reused.
    spare: Option<Statement>,
    events: Vec<Event>,
    executed: u64,
    max_lines: u64,
    /// Blocks made so far, and the most the program may make.
    made: u64,
    max_blocks: u64,
    first_code: Option<usize>,
    /// The main program's first line that is not blank: where its opening `%` may be
    /// (LinuxCNC skips blank lines before it).
    first_line: usize,
    scratch: read::Scratch,
    /// The line being read, boxed: taken out and put back each line (a pointer moved, not
    /// the line).
    line_buf: Option<Box<read::Line>>,
    out_buf: Vec<(Canon, u32, u32)>,
    /// The sorted words of the line being executed (kept, not returned: a kilobyte).
    words_buf: Option<Box<words::Words>>,
    mdi: bool,
    done: bool,
    machine: Box<dyn Machine>,
    /// What the last line asked of the machine, and the line: answered before the next line
    /// is read (docs/gcode.md "Probing").
    pending: (Vec<exec::Ask>, u32),
    /// The machine's clocks when it reached the line read next (a Fanuc #3001/#3002 line
    /// read again once the machine has answered), for that line only.
    clocks: Option<exec::Clocks>,
    /// SEARCH is running the lines before its point: the settings' machine answers.
    pub(crate) searching: bool,
    finder: Box<dyn SubFinder>,
    /// A remapped code's line (M6's, or modal group 10's), while its subroutine runs: the rest
    /// of the line executes when the call level falls below `level` (docs/gcode.md
    /// "Remapping M6 and other M codes").
    remap: Option<RemapLine>,
    /// The console's part counter, parts made and required (Fanuc's #3901/#3902).
    parts: Option<(u64, u64)>,
    /// By G65 call level: the locals (bit n for #n) given without a decimal point on a length
    /// address, which ADP reads as if with one.
    adp: Vec<u64>,
    /// Fanuc's G66 modal call in force (docs/gcode.md "Fanuc dialect").
    modal_call: Option<ModalCall>,
    /// The line being executed has a move and a modal call is in force: the macro is called
    /// after it.
    modal_due: bool,
    /// Statements carry their source line's text ([`GcodeSource::without_texts`]).
    texts: bool,
}

/// A G66 modal call in force: the macro, its arguments and where it was given.
struct ModalCall {
    p: u32,
    args: [f64; flow::LOCALS],
    /// The arguments given without a decimal point (ADP).
    unpointed: u64,
    /// The G66 line.
    line: u32,
    /// The call level of the program that gave G66: moves at that level or outside it call
    /// the macro, moves in the macro (or deeper) do not.
    level: usize,
}

/// The line of a remapped code whose subroutine is running.
struct RemapLine {
    /// The call level of the remap subroutine.
    level: usize,
    at: Pos,
    n: u32,
    raw: String,
    /// The line's words (None until the line has executed up to the remapped code).
    words: Option<Box<words::Words>>,
    /// A back end's line (the lathe's), read: its back end executes the rest of it on the
    /// return (`Motion::after_remap`).
    line: Option<Box<read::Line>>,
    /// The steps of the line still to run on the return: after M6 (6) or after modal group
    /// 10 (10).
    after: u8,
}

impl GcodeSource {
    /// A program `source` for the machine in `state` (position, tool in the spindle,
    /// spindle), with the work offsets in force (G54 active) and the panel switches.
    pub fn new(
        source: Arc<str>,
        magazine: Magazine,
        settings: MachineSettings,
        state: MachineState,
        offsets: WorkOffsets,
        switches: Switches,
    ) -> GcodeSource {
        let mut persistent = Vec::new();
        for (cs, o) in offsets.0.iter().enumerate() {
            for (a, &v) in o.iter().enumerate() {
                persistent.push((state::system_base(cs) + 1 + a, v));
            }
        }
        let pos = [
            settings.to_mm(state.pos[0]),
            settings.to_mm(state.pos[1]),
            settings.to_mm(state.pos[2]),
        ];
        let mut st = InterpState::with_persistent(&persistent, pos, state.tool);
        st.modal.speed = state.spindle.unsigned_abs() as f64;
        st.modal.spindle = state.spindle.signum() as i8;
        GcodeSource::with_state(source, magazine, settings, state, st, switches)
    }

    /// A program `source` read from the interpreter state `st` (the machine's, kept between
    /// runs), the machine standing as `machine` says.
    pub fn with_state(
        source: Arc<str>,
        magazine: Magazine,
        settings: MachineSettings,
        machine: MachineState,
        mut st: InterpState,
        switches: Switches,
    ) -> GcodeSource {
        st.pos = [
            settings.to_mm(machine.pos[0]),
            settings.to_mm(machine.pos[1]),
            settings.to_mm(machine.pos[2]),
        ];
        st.abc = machine.pos.rotary().map(|p| settings.to_mm(p));
        st.rotaries = std::array::from_fn(|r| {
            let a = crate::block::FIRST_ROTARY + r;
            settings.rotary(a).then(|| settings.wrapped(a))
        });
        // An offset kept for a rotary axis the machine has not (its description changed)
        // turns nothing.
        for r in (0..3).filter(|&r| st.rotaries[r].is_none()) {
            st.origin_abc[r] = 0.0;
            st.g92_abc[r] = 0.0;
        }
        st.tool = machine.tool;
        // The coolant is the machine's, as LinuxCNC's interpreter takes it at each start
        // (its synch): after RESET it is off (docs/gcode.md "SEARCH").
        st.modal.mist = machine.mist;
        st.modal.flood = machine.flood;
        st.call_level = 0;
        st.remap_level = 0;
        // A NURBS is begun and ended within one program (or one MDI text).
        st.nurbs = None;
        if settings.dialect == Dialect::Fanuc {
            st.fanuc_power_on();
        } else if st.fanuc_vacant {
            // A LinuxCNC-dialect run after a Fanuc one (each program keeps its dialect):
            // LinuxCNC has no null, its parameters start at 0, so a vacant one reads 0.
            for v in st.params.iter_mut().filter(|v| v.is_nan()) {
                *v = 0.0;
            }
        }
        let first_code = source.split('\n').position(|l| {
            let t = l.trim();
            !(t.is_empty() || t == "%" || t.starts_with('(') || t.starts_with(';'))
        });
        let sim = Box::new(probe::SimMachine::new(&settings));
        let first_line = source
            .split('\n')
            .position(|l| !l.trim().is_empty())
            .unwrap_or(0);
        GcodeSource {
            flow: Flow::new(source),
            st,
            comp: Comp::default(),
            magazine,
            settings,
            switches,
            emitter: Emitter::new(machine.pos, 0, crate::block::Tap::No),
            start: machine,
            resume_at: None,
            z_moved: false,
            held: None,
            spare: None,
            events: Vec::new(),
            executed: 0,
            max_lines: MAX_LINES,
            made: 0,
            max_blocks: MAX_PROGRAM_BLOCKS,
            first_code,
            first_line,
            scratch: read::Scratch::default(),
            line_buf: None,
            out_buf: Vec::new(),
            words_buf: None,
            mdi: false,
            done: false,
            machine: sim,
            pending: (Vec::new(), 0),
            clocks: None,
            searching: false,
            finder: Box::new(NoFiles),
            remap: None,
            parts: None,
            adp: Vec::new(),
            modal_call: None,
            modal_due: false,
            texts: true,
        }
    }

    /// Statements without their source line's text (empty): for a reader whose statements
    /// are only printed as blocks (`novanc translate`), which then neither trims nor copies
    /// each line.
    pub fn without_texts(mut self) -> GcodeSource {
        self.texts = false;
        self
    }

    /// The most lines this program may execute (default [`MAX_LINES`]).
    pub fn line_limit(mut self, lines: u64) -> GcodeSource {
        self.max_lines = lines;
        self
    }

    /// The most blocks this program may make, every repeat counted (default
    /// [`MAX_PROGRAM_BLOCKS`]).
    pub fn block_limit(mut self, blocks: u64) -> GcodeSource {
        self.max_blocks = blocks;
        self
    }

    /// MDI: the text need not end with M02, M30 or `%`.
    pub fn mdi(mut self) -> GcodeSource {
        self.mdi = true;
        self
    }

    /// The machine that answers probes and inputs.
    pub fn machine(mut self, m: Box<dyn Machine>) -> GcodeSource {
        self.machine = m;
        self
    }

    /// The part counter the program reads (Fanuc's #3901 parts machined, #3902 required).
    pub fn part_counter(mut self, made: u64, required: u64) -> GcodeSource {
        self.parts = Some((made, required));
        self
    }

    /// Where `o<name> call` finds subroutine files.
    pub fn subroutines(mut self, f: Box<dyn SubFinder>) -> GcodeSource {
        self.finder = f;
        self
    }

    /// SEARCH: the lines before source line `line` are executed for the state they leave
    /// (modes, offsets, tool, spindle, position) but yield no blocks; the first line at or
    /// after `line` is preceded by a restore statement that brings the machine from its actual
    /// state there.
    pub fn resume_at(mut self, line: u32) -> GcodeSource {
        self.resume_at = Some(line);
        self
    }

    /// The interpreter's state as the program has left it so far.
    pub fn state(&self) -> &InterpState {
        &self.st
    }

    /// The interpreter's state, taken (the source is spent).
    pub fn into_state(self) -> InterpState {
        self.st
    }

    /// The work offsets G54–G59 as the program has left them so far.
    pub fn offsets(&self) -> WorkOffsets {
        let mut o = WorkOffsets::default();
        for (cs, v) in o.0.iter_mut().enumerate() {
            *v = self.st.system_offset(cs);
        }
        o
    }

    /// What the lines did besides the moves since the last call (parameters kept, tool data,
    /// messages, probe results), in order.
    pub fn take_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    /// The G10 changes of G54–G59 made since the last call, in order (the other events are
    /// kept for `take_events`).
    pub fn take_offset_changes(&mut self) -> Vec<OffsetChange> {
        let mut out: Vec<OffsetChange> = Vec::new();
        for e in &self.events {
            if let Event::Param(n, _) = e {
                if (5221..=5330).contains(n) && (n - 5221) % 20 < 3 {
                    let system = (n - 5221) / 20;
                    let offset = self.st.system_offset(system);
                    match out.last_mut() {
                        Some(l) if l.system == system => l.offset = offset,
                        _ => out.push(OffsetChange { system, offset }),
                    }
                }
            }
        }
        self.events
            .retain(|e| !matches!(e, Event::Param(n, _) if (5221..=5330).contains(n) && (n - 5221) % 20 < 3));
        out
    }

    fn fail(&mut self, e: TranslateError) -> Option<Result<Statement, TranslateError>> {
        self.done = true;
        // A refused line asks the machine nothing: its probe did not move (the fuzzer found a
        // refused G38.2 answered after its refusal as a second error).
        self.pending = Default::default();
        Some(Err(e))
    }

    /// An error at `line`:`col` of unit `unit`: in a subroutine file, charged to the main
    /// program's line that called it, naming the file.
    fn error_at(&self, unit: usize, line: u32, col: u32, message: String) -> TranslateError {
        if unit == 0 {
            return TranslateError { line, col, message };
        }
        let name = &self.flow.units[unit].name;
        TranslateError {
            line: self.flow.main_line() as u32,
            col: 1,
            message: format!("in {name} line {line}:{col}: {message}"),
        }
    }

    /// The machine's answers to what the last line asked (its blocks have been handed on):
    /// the parameters and position they set, or the error of a probe that did not trip.
    pub(crate) fn answer_pending(&mut self) -> Result<(), TranslateError> {
        if self.pending.0.is_empty() {
            return Ok(());
        }
        let (asks, n) = std::mem::take(&mut self.pending);
        for ask in &asks {
            let m: &mut dyn Machine = if self.searching {
                &mut probe::SimMachine::new(&self.settings)
            } else {
                self.machine.as_mut()
            };
            if let Ask::Clocks { col } = *ask {
                let c = m.clocks().map_err(|message| TranslateError {
                    line: n,
                    col,
                    message,
                })?;
                self.clocks = Some(c);
                continue;
            }
            if let Some(at) = probe::answer(&mut self.st, m, ask, n, &mut self.events)? {
                let abc = self.emitter.pos.rotary();
                self.emitter.pos =
                    crate::block::Axes::with_rotary(at.map(|v| self.settings.to_pulses(v)), abc);
            }
        }
        Ok(())
    }

    /// Executes the next line; `None` when there is nothing more to do.
    fn step(&mut self) -> Option<Result<Statement, TranslateError>> {
        self.step_in(None)
    }

    /// Executes the next line with `motion` executing the words of each line ([`Motion`]):
    /// the statement yielded has no blocks (the back end keeps its own); `None` when the
    /// program is done. Errors are placed as the source's own.
    pub fn next_with(
        &mut self,
        motion: &mut dyn Motion,
    ) -> Option<Result<Statement, TranslateError>> {
        self.step_in(Some(motion))
    }

    fn step_in<'m>(
        &mut self,
        mut motion: Option<&mut (dyn Motion + 'm)>,
    ) -> Option<Result<Statement, TranslateError>> {
        if let Err(e) = self.answer_pending() {
            return self.fail(e);
        }
        loop {
            if self.done {
                return None;
            }
            if self
                .remap
                .as_ref()
                .is_some_and(|r| self.flow.level() < r.level)
            {
                if let Some(RemapLine {
                    at,
                    n,
                    raw,
                    words,
                    line,
                    after,
                    ..
                }) = self.remap.take()
                {
                    self.st.remap_level = 0;
                    let r = match (words, line, motion.as_deref_mut()) {
                        (Some(words), _, _) => {
                            let r = self.run_words(at, n, &raw, &words, after);
                            // The rest of an M6 line may call a remapped code of modal group
                            // 10: its words are kept again for the steps after that one.
                            if let Some(r) = self.remap.as_mut().filter(|r| r.words.is_none()) {
                                r.words = Some(words);
                            }
                            r
                        }
                        // A back end's line: it runs the steps after the remapped code.
                        (None, Some(line), Some(m)) => {
                            m.after_remap();
                            self.run_motion(m, at, n, &raw, &line)
                        }
                        // Never in the reader's own use; said rather than the rest of the
                        // line dropped.
                        _ => Err(TranslateError {
                            line: n,
                            col: 1,
                            message: "the rest of the line after its remapped M code has no reader to run it: the line is refused".into(),
                        }),
                    };
                    match r {
                        Ok(Some(s)) => return s,
                        Ok(None) => continue,
                        Err(e) => {
                            let e = self.error_at(at.unit, e.line, e.col, e.message);
                            return self.fail(e);
                        }
                    }
                }
            }
            let at = self.flow.pc;
            let n = at.line as u32 + 1;
            let text = Arc::clone(&self.flow.units[at.unit].text);
            let Some((raw, next)) = flow::line_at(&text, at.byte) else {
                if at.unit == 0 && self.mdi && self.flow.level() == 0 && !self.flow.skipping() {
                    self.done = true;
                    let mut x = ctx!(self, n);
                    let r = self.comp.flush(&mut x, 1);
                    let out = x.out;
                    if let Err(e) = r {
                        self.out_buf = out;
                        return self.fail(e);
                    }
                    return self.finish(n, "", out, false);
                }
                let msg = self.flow.end_error();
                // Charged to the line that started the skip (the call, the definition).
                let (unit, line) = match self.flow.skip_from() {
                    Some(p) if self.flow.skipping() => (p.unit, p.line as u32 + 1),
                    _ => (at.unit, n),
                };
                let e = self.error_at(unit, line, 1, msg);
                return self.fail(e);
            };
            self.flow.pc = Pos {
                unit: at.unit,
                line: at.line + 1,
                byte: next,
            };
            if let Err(message) = self.count_line() {
                let e = self.error_at(at.unit, n, 1, message);
                return self.fail(e);
            }
            // A blank line: nothing to read (it counts as a line all the same).
            if raw.bytes().all(|c| matches!(c, b' ' | b'\t' | b'\r')) {
                continue;
            }
            // Skipping (a false `if`, a subroutine's definition): only an O-word line can stop
            // it, and nothing else is read (LinuxCNC evaluates nothing it skips).
            // (A byte loop: the library's search is made for long texts.)
            if self.flow.skipping()
                && flow::o_label(raw).is_none()
                && !raw.bytes().any(|c| c == b'%')
            {
                continue;
            }
            if let Some(e) = crate::limits::line_too_long(raw, n, "") {
                let e = self.error_at(at.unit, e.line, e.col, e.message);
                return self.fail(e);
            }
            if self.switches.block_delete
                && !self.flow.skipping()
                && raw.trim_start().starts_with('/')
            {
                continue;
            }
            match self.line(at, n, raw, motion.as_deref_mut()) {
                Ok(Some(s)) => return s,
                Ok(None) => continue,
                Err(e) => {
                    let e = self.error_at(at.unit, e.line, e.col, e.message);
                    return self.fail(e);
                }
            }
        }
    }

    /// One more line executed: refused past the bound on the lines a program executes.
    #[inline]
    fn count_line(&mut self) -> Result<(), String> {
        self.executed += 1;
        if self.executed <= self.max_lines {
            return Ok(());
        }
        Err(self.too_many_lines())
    }

    /// The refusal of the line past the bound.
    #[cold]
    fn too_many_lines(&self) -> String {
        let max = self.max_lines;
        // Without a call or a loop, every line read was a line of the file.
        if self.flow.jumped() {
            format!("the program executes more than {max} lines, counting each line of a loop or subroutine each time it runs: refused")
        } else {
            format!("the program has more than {max} lines (the most a program may have)")
        }
    }

    /// M98's program and repeats: Fanuc 0i's M98 P with more than four digits and no L
    /// gives the program number in its last four digits and the repeats above them (P30010:
    /// O0010 three times; docs/gcode.md "Fanuc dialect").
    fn m98_program(&self, o: u32, l: Option<u32>) -> (u32, Option<u32>) {
        match l {
            None if o > 9999 && self.settings.dialect == Dialect::Fanuc => {
                (o % 10_000, Some(o / 10_000))
            }
            _ => (o, l),
        }
    }

    /// How the line being read reads its numbers.
    #[inline]
    fn read_opts(&self) -> read::ReadOpts {
        read::ReadOpts {
            fanuc: self.settings.dialect == Dialect::Fanuc,
            increment: if self.st.modal.inch { 0.0001 } else { 0.001 },
            calculator: self.settings.fanuc.calculator,
            sort: false,
        }
    }

    /// Reads and executes one line: `None` to go on to the next, or what to yield.
    #[allow(clippy::type_complexity)]
    fn line<'m>(
        &mut self,
        at: Pos,
        n: u32,
        raw: &str,
        motion: Option<&mut (dyn Motion + 'm)>,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        let mut line = self.line_buf.take().unwrap_or_default();
        let clocks = self.clocks.take();
        let wants_clocks = std::cell::Cell::new(None);
        let r = {
            let env = param_env!(self, clocks, &wants_clocks, motion.as_deref());
            let flow = &self.flow;
            let skip = |label: &str, kind: read::OKind| flow.reads_while_skipping(label, kind);
            let skipping: Option<&dyn Fn(&str, read::OKind) -> bool> =
                if flow.skipping() { Some(&skip) } else { None };
            // The mill's usual line is sorted into its words as it is read (a back end reads
            // its own letters: the lathe's are sorted by its executor).
            let mill = motion.is_none();
            let p_seconds = self.settings.fanuc.p_point_seconds;
            let opts = read::ReadOpts {
                sort: mill,
                ..self.read_opts()
            };
            read::read_into_opts(&mut self.scratch, &mut line, raw, n, &env, skipping, opts)
                .and_then(|()| {
                    if opts.fanuc {
                        fanuc_dwell(&mut line, n, opts.increment, p_seconds)?;
                        fanuc_mode_q(&mut line, opts.increment);
                        if mill {
                            fanuc_cycle_p(&line, n, self.st.modal.motion)?;
                            fanuc_cycle_k(&mut line, opts.increment, self.st.modal.motion);
                        }
                    }
                    Ok(())
                })
        };
        // A Fanuc clock read or written: the machine's clocks at this line first.
        let clock_at = match &r {
            Err(e) => wants_clocks.get().map(|v| (e.col, v)),
            Ok(()) if clocks.is_none() && self.settings.dialect == Dialect::Fanuc => {
                line.assigns.iter().find_map(|(t, _, col)| match t {
                    Target::Numbered(p @ (3001 | 3002)) => Some((*col, *p)),
                    _ => None,
                })
            }
            _ => None,
        };
        let out = match clock_at {
            Some((col, v)) => self.ask_clocks(at, n, raw, col, v),
            None => {
                self.clocks = clocks;
                let out = r.and_then(|()| self.execute_line(at, n, raw, &line, motion));
                self.clocks = None;
                out
            }
        };
        self.line_buf = Some(line);
        out
    }

    /// A line that reads or writes Fanuc's clock `#v` (at `col`) before the machine has
    /// answered for it: a clocks block is handed on and the line is read again once the
    /// machine has run it, every block before it done (LinuxCNC's queue buster, as a probe's
    /// answer). Refused with the reason where no machine can answer for the line.
    #[allow(clippy::type_complexity)]
    fn ask_clocks(
        &mut self,
        at: Pos,
        n: u32,
        raw: &str,
        col: u32,
        v: usize,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        let why = if self.searching || !self.machine.keeps_time() {
            Some("the clocks are the machine's, and no machine runs the program here (novanc translate, the window's plot, the lines before a SEARCH point)")
        } else if self.comp.active() {
            Some("cannot be read or set with cutter radius compensation on (the compensated move is held back until the next move is known: the machine has not reached the line)")
        } else if self.st.nurbs.is_some() {
            Some("cannot be read or set between G5.2 and G5.3 (the curve is made at G5.3: the machine has not reached the line)")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(TranslateError {
                line: n,
                col,
                message: format!("{}: {why}", sysvars::clock_name(v)),
            });
        }
        self.flow.pc = at;
        self.executed = self.executed.saturating_sub(1);
        self.pending = (vec![Ask::Clocks { col }], n);
        Ok(Some(self.finish(
            n,
            trimmed(raw),
            vec![(Canon::Clocks, n, col)],
            false,
        )))
    }

    #[allow(clippy::type_complexity)]
    fn execute_line<'m>(
        &mut self,
        at: Pos,
        n: u32,
        raw: &str,
        line: &read::Line,
        mut motion: Option<&mut (dyn Motion + 'm)>,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        if line.percent {
            if motion.is_some() {
                // The lathe's `%` is a tape mark, read over wherever it stands
                // (docs/lathe-gcode.md).
                return Ok(None);
            }
            if self.flow.skipping() || at.unit != 0 {
                return Ok(None);
            }
            if at.line == self.first_line {
                // The tape's leading % (after blank lines, if any).
                return Ok(None);
            }
            if !self.flow.units[0]
                .nth_line(self.first_line)
                .is_some_and(|l| l.trim_start().starts_with('%'))
            {
                return Err(TranslateError {
                    line: n,
                    col: 1,
                    message: "'%' ends a program only when the program's first line that is not blank is '%' (as in LinuxCNC)".into(),
                });
            }
            if self.flow.level() > 0 {
                return Err(TranslateError {
                    line: n,
                    col: 1,
                    message: self.flow.end_error(),
                });
            }
            // The closing %: the program ends.
            spline::unfinished(&self.st, n, 1, "the program's end")?;
            return Ok(Some(self.end(n, raw, Vec::new(), None)));
        }
        if let Some(o) = &line.o {
            if o.kind == read::OKind::Bare && !self.flow.skipping() {
                if at.unit == 0 && Some(at.line) == self.first_code && self.flow.level() == 0 {
                    // The main program's number.
                    return Ok(None);
                }
                // Further on in the main program (after subroutine definitions, say) it is a
                // program number too: LinuxCNC reads on into what follows. An M99 there ends
                // nothing in novanc ("M99 outside a subprogram").
                if self.flow.level() > 0 && self.flow.sub_name() != Some(o.label.as_str()) {
                    return Err(TranslateError {
                        line: n,
                        col: o.col,
                        message: format!(
                            "subprogram O{} runs into O{} without M99",
                            self.flow.sub_name().unwrap_or(""),
                            o.label
                        ),
                    });
                }
            }
            self.flow
                .control(o, at, &mut self.st, self.finder.as_ref())
                .map_err(|m| TranslateError {
                    line: n,
                    col: o.col,
                    message: m,
                })?;
            if !self.flow.skipping() && !line.comments.is_empty() {
                self.comments(n, &line.comments, motion.as_deref())?;
            }
            return Ok(None);
        }
        if self.flow.skipping() {
            return Ok(None);
        }
        if line.block_delete && self.switches.block_delete {
            return Ok(None);
        }
        if let Some(v) = line.n {
            self.st.line_number = v;
        }
        let fanuc = self.settings.dialect == Dialect::Fanuc;
        // Parameters take their new values before the words execute.
        let stop = if line.assigns.is_empty() {
            None
        } else {
            self.assign(n, line, motion.as_deref_mut())?
        };
        if let Some(col) = stop {
            // #3006: a stop with its message, as M00.
            if !line.words.is_empty() {
                return Err(TranslateError {
                    line: n,
                    col,
                    message: "#3006 stands on a block of its own (no words with it)".into(),
                });
            }
            if let Some(m) = motion {
                m.stop(n, col)?;
                return Ok(Some(self.finish(n, raw, Vec::new(), false)));
            }
            let mut x = ctx!(self, n);
            let r = self.comp.flush(&mut x, col);
            if r.is_ok() {
                let m0 = Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(0),
                };
                self.comp.aux(&mut x, m0, col);
            }
            let out = x.out;
            if let Err(e) = r {
                self.out_buf = out;
                return Err(e);
            }
            return Ok(Some(self.finish(n, raw, out, false)));
        }
        self.comments(n, &line.comments, motion.as_deref())?;
        if let Some(m) = line.fanuc {
            let (r, col) = match m {
                read::Macro::Goto { n: seq, col } => (self.flow.goto(seq, at), col),
                read::Macro::While { test, m, col } => (self.flow.fanuc_do(Some(test), m, at), col),
                read::Macro::Do { m, col } => (self.flow.fanuc_do(None, m, at), col),
                read::Macro::End { m, col } => (self.flow.fanuc_end(m), col),
            };
            r.map_err(|message| TranslateError {
                line: n,
                col,
                message,
            })?;
            return Ok(None);
        }
        if fanuc {
            let g = line
                .words
                .iter()
                .find(|w| w.letter == 'G' && matches!(w.value, 65.0 | 66.0 | 67.0));
            match g.map(|w| w.value as u8) {
                Some(65) => {
                    self.g65(at, n, line)?;
                    return Ok(Some(self.finish(n, raw, Vec::new(), false)));
                }
                Some(66) => {
                    self.g66(n, line)?;
                    return Ok(Some(self.finish(n, raw, Vec::new(), false)));
                }
                Some(_) => {
                    self.g67(n, line)?;
                    return Ok(Some(self.finish(n, raw, Vec::new(), false)));
                }
                None => {}
            }
            // A move: an axis word (the lathe's U and W too).
            let lathe = motion.is_some();
            self.modal_due = self.modal_call.is_some()
                && line.words.iter().any(|w| {
                    matches!(w.letter, 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C')
                        || (lathe && matches!(w.letter, 'U' | 'W'))
                });
        }
        if line.words.is_empty() {
            if line.assigns.is_empty() && line.comments.is_empty() {
                return Ok(None);
            }
            return Ok(Some(self.finish(n, raw, Vec::new(), false)));
        }
        if fanuc {
            // #4113: the last M code read.
            if let Some(m) = line.words.iter().rev().find(|w| w.letter == 'M') {
                self.st.fanuc_m = m.value;
            }
        }
        if let Some(m) = motion {
            return self.run_motion(m, at, n, raw, line);
        }
        if line.sorted {
            // Sorted as read, in the mill's dialect or Fanuc's (which a line without A reads
            // the same with an A axis).
            let r = self.run_words(at, n, raw, &line.sorted_words, 0);
            if let Some(r) = self.remap.as_mut().filter(|r| r.words.is_none()) {
                r.words = Some(Box::new(line.sorted_words.clone()));
            }
            return r;
        }
        let mut words = self.words_buf.take().unwrap_or_default();
        let mask = (0..3).fold(0, |m, r| m | (u8::from(self.st.rotaries[r].is_some()) << r));
        let remapped;
        let mut dialect = words::mill_with(mask, fanuc);
        if !self.settings.remap_m.is_empty() {
            // The M codes the machine description remaps are read in modal group 10.
            remapped = dialect.with_remaps(self.settings.remap_m.iter().map(|r| r.code));
            dialect = &remapped;
        }
        let sorted = match fanuc {
            false => words::refuse_configuration_words(line_words(line), n, dialect),
            true => Ok(()),
        }
        .and_then(|()| words::sort_words_into(line_words(line), n, dialect, &mut words));
        let r = sorted.and_then(|()| self.run_words(at, n, raw, &words, 0));
        match self.remap.as_mut() {
            // The line of a remapped M6 just called: kept to finish when the call returns.
            Some(r) if r.words.is_none() => r.words = Some(words),
            _ => self.words_buf = Some(words),
        }
        r
    }

    /// Sets line `n`'s parameters (`line.assigns`), before its words execute; `back`: a
    /// back end other than the mill's executes them (the lathe's), and answers for the
    /// machine state it keeps. The column of a `#3006` stop, if the line gives one.
    fn assign<'m>(
        &mut self,
        n: u32,
        line: &read::Line,
        mut back: Option<&mut (dyn Motion + 'm)>,
    ) -> Result<Option<u32>, TranslateError> {
        let fanuc = self.settings.dialect == Dialect::Fanuc;
        let mut stop = None;
        for (t, v, col) in &line.assigns {
            match t {
                Target::Numbered(p @ (3000 | 3006)) if fanuc => {
                    self.fanuc_message(n, *p, *v, *col, &line.comments)?;
                    stop = Some(*col);
                }
                Target::Numbered(p) if back.is_some() && lathe_refuses(fanuc, *p) => {
                    // The back end's machine state, else the reader's read-only variables
                    // (modal information, part counter), else none it keeps.
                    let r = back
                        .as_deref_mut()
                        .and_then(|b| b.write_param(*p, *v, fanuc));
                    r.unwrap_or_else(|| {
                        let reader = fanuc && (3901..=4330).contains(p);
                        let ro = if reader { sysvars::read_only(*p) } else { None };
                        Err(ro.unwrap_or_else(|| lathe_refusal(fanuc, *p)))
                    })
                    .map_err(|message| TranslateError {
                        line: n,
                        col: *col,
                        message,
                    })?;
                }
                Target::Numbered(p @ (3001 | 3002)) if fanuc => {
                    // `line` read the machine's clocks for this line first.
                    let c = self.clocks.ok_or_else(|| sysvars::clock_name(*p));
                    c.and_then(|c| sysvars::set_clock(*p, *v, c, &mut self.st))
                        .map_err(|m| TranslateError {
                            line: n,
                            col: *col,
                            message: m,
                        })?;
                }
                Target::Numbered(p)
                    if fanuc
                        && (*p > read::MAX_PARAM
                            || sysvars::tool_var(*p).is_some()
                            || (3001..=5048).contains(p)
                            || (5081..=5088).contains(p)
                            || (5201..=5206).contains(p)) =>
                {
                    let r = sysvars::write(*p, *v, &self.st, &mut self.magazine, &mut self.events);
                    if let Some(Err(m)) = r {
                        return Err(TranslateError {
                            line: n,
                            col: *col,
                            message: m,
                        });
                    }
                    if r.is_none() {
                        self.st.params[*p] = *v;
                    }
                }
                Target::Numbered(p) if fanuc && state::is_fanuc_kept(*p) => {
                    self.st.params[*p] = *v;
                    // Kept by the stores; a vacant one is kept as nothing (0).
                    let kept = if read::is_null(*v) { 0.0 } else { *v };
                    self.events.push(Event::Param(*p, kept));
                }
                Target::Numbered(p) => {
                    self.st.writable(*p).map_err(|m| TranslateError {
                        line: n,
                        col: *col,
                        message: m,
                    })?;
                    self.st.params[*p] = *v;
                    if state::is_persistent(*p) {
                        self.events.push(Event::Param(*p, *v));
                    }
                    // Fanuc: a changed work offset of the system in force acts at once.
                    let b = state::system_base(self.st.modal.cs);
                    if fanuc && (b + 1..=b + 3).contains(p) {
                        self.st.select_system(self.st.modal.cs);
                    }
                }
                Target::Named(name) => {
                    if name.starts_with('_') {
                        if self.st.predefined(name).is_some() {
                            return Err(TranslateError {
                                line: n,
                                col: *col,
                                message: format!(
                                    "#<{name}> is read-only (it reports the interpreter's state)"
                                ),
                            });
                        }
                        self.st.named.insert(name.clone(), *v);
                    } else {
                        self.flow.set_local(&mut self.st, name, *v);
                    }
                }
            }
        }
        Ok(stop)
    }

    /// Line `n`'s words executed by a back end, and what it asks of the flow.
    #[allow(clippy::type_complexity)]
    fn run_motion(
        &mut self,
        m: &mut dyn Motion,
        at: Pos,
        n: u32,
        raw: &str,
        line: &read::Line,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        let modal_due = std::mem::take(&mut self.modal_due);
        let placed = |col: u32, message: String| TranslateError {
            line: n,
            col,
            message,
        };
        match m.words(line, at, self)? {
            Then::Next => {
                if modal_due {
                    self.modal_call_after_move(at, n)?;
                }
            }
            Then::Call { o, l, col } => {
                let (o, l) = self.m98_program(o, l);
                let r = self
                    .flow
                    .call_m98(o, l, at, &mut self.st, self.finder.as_ref());
                r.map_err(|m| placed(col, m))?;
            }
            Then::Return { col } => {
                let r = self.flow.return_m99(&mut self.st);
                r.map_err(|m| placed(col, m))?;
            }
            Then::End => {
                self.modal_call = None;
                self.st.program_end_reset();
                self.done = true;
            }
            Then::Skip(to) => self.flow.pc = to,
            Then::Remap { m, col } => {
                let word = |c: char| {
                    let w = line.words.iter().rev().find(|w| w.letter == c);
                    w.map(|w| w.value)
                };
                self.remap_call(at, n, raw, (m, col), &word)?;
                if let Some(r) = self.remap.as_mut() {
                    r.line = Some(Box::new(line.clone()));
                }
            }
        }
        Ok(Some(self.finish(n, raw, Vec::new(), false)))
    }

    /// Executes a line's sorted words (`after`: 0, or only its steps after a remapped M6 (6)
    /// or a remapped code of modal group 10 (10)).
    #[allow(clippy::type_complexity)]
    fn run_words(
        &mut self,
        at: Pos,
        n: u32,
        raw: &str,
        words: &words::Words,
        after: u8,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        let end_m = if words.has_m(2).is_some() { 2 } else { 30 };
        let mut x = ctx!(self, n);
        x.after = after;
        let r = exec::execute(&mut self.st, &mut self.comp, &mut x, words);
        let Exec {
            out, events, asks, ..
        } = x;
        self.events.extend(events);
        self.pending = (asks, n);
        let flow = match r {
            Ok(f) => f,
            Err(e) => {
                self.out_buf = out;
                return Err(e);
            }
        };
        let modal_due = std::mem::take(&mut self.modal_due);
        match flow {
            LineFlow::Next => {
                if modal_due {
                    self.modal_call_after_move(at, n)?;
                }
                Ok(Some(self.finish(n, raw, out, false)))
            }
            LineFlow::Call { o, l, col } => {
                let (o, l) = self.m98_program(o, l);
                let r = self
                    .flow
                    .call_m98(o, l, at, &mut self.st, self.finder.as_ref());
                r.map_err(|m| TranslateError {
                    line: n,
                    col,
                    message: m,
                })?;
                Ok(Some(self.finish(n, raw, out, false)))
            }
            LineFlow::Return { col } => {
                self.flow
                    .return_m99(&mut self.st)
                    .map_err(|m| TranslateError {
                        line: n,
                        col,
                        message: m,
                    })?;
                Ok(Some(self.finish(n, raw, out, false)))
            }
            LineFlow::Remap { m, col } => {
                self.remap_call(at, n, raw, (m, col), &|c| words.get(c))?;
                Ok(Some(self.finish(n, raw, out, false)))
            }
            LineFlow::End => {
                // M02/M30 cancel a G66 in force, as on Fanuc.
                self.modal_call = None;
                Ok(Some(self.end(n, raw, out, Some(end_m))))
            }
        }
    }

    /// A remapped M`m` (M6, or a code of modal group 10) at `n`:`col`: calls the machine's
    /// subroutine, M6's with the tool selected and the tool in the spindle as its
    /// `#<selected_tool>` and `#<tool_in_spindle>` (what LinuxCNC's change_prolog gives),
    /// another's with the words of the line its argspec names as `#<p>` ...; the rest of the
    /// line waits for its return.
    fn remap_call(
        &mut self,
        at: Pos,
        n: u32,
        raw: &str,
        (m, col): (u32, u32),
        word: &dyn Fn(char) -> Option<f64>,
    ) -> Result<(), TranslateError> {
        let remap = (self.settings.remap_m.iter()).find(|r| r.code == m);
        let argspec = remap.map(|r| r.argspec.clone()).unwrap_or_default();
        let name = match m {
            6 => self.settings.remap_m6.clone(),
            _ => remap.map(|r| r.ngc.clone()),
        }
        .unwrap_or_default();
        let err = |e: String| TranslateError {
            line: n,
            col,
            message: format!("M{m} (remapped to o<{name}> by the machine description): {e}"),
        };
        self.flow
            .call(
                &name,
                flow::CallType::Oword,
                &[],
                at,
                &mut self.st,
                self.finder.as_ref(),
            )
            .map_err(err)?;
        // The argspec's words, as LinuxCNC's add_parameters gives them: a capital letter
        // missing from the line is an error of the code.
        let missing: Vec<char> = (argspec.chars())
            .filter(|c| c.is_ascii_uppercase() && word(*c).is_none())
            .collect();
        if !missing.is_empty() {
            let list: Vec<String> = missing.iter().map(char::to_string).collect();
            let e = format!(
                "its subroutine needs {} on the line (argspec={argspec})",
                list.join(", ")
            );
            return Err(err(e));
        }
        for c in argspec.chars() {
            if let Some(v) = word(c.to_ascii_uppercase()) {
                let name = c.to_ascii_lowercase().to_string();
                self.flow.set_local(&mut self.st, &name, v);
            }
        }
        if m == 6 {
            let selected = self.st.selected.map_or(-1.0, f64::from);
            let in_spindle = self.st.tool.map_or(0.0, f64::from);
            self.flow.set_local(&mut self.st, "selected_tool", selected);
            self.flow
                .set_local(&mut self.st, "tool_in_spindle", in_spindle);
        }
        self.st.remap_level = 1;
        self.remap = Some(RemapLine {
            level: self.flow.level(),
            at,
            n,
            raw: raw.to_string(),
            words: None,
            line: None,
            after: if m == 6 { 6 } else { 10 },
        });
        Ok(())
    }

    /// Fanuc's `G65 P L` and its arguments (specification I, [`G65_ARGUMENTS`]): calls macro
    /// program O`P` with local variables #1–#33 of its own.
    fn g65(&mut self, at: Pos, n: u32, line: &read::Line) -> Result<(), TranslateError> {
        let (p, l, args, g_col, unpointed) = macro_call_words(65, n, line)?;
        self.call_macro(p, l, flow::CallType::G65, &args, unpointed, at)
            .map_err(|message| TranslateError {
                line: n,
                col: g_col,
                message,
            })
    }

    /// Calls macro O`p` (G65, or G66's modal call) with its locals, noting for ADP which of
    /// them were given without a decimal point at the call level it opens.
    fn call_macro(
        &mut self,
        p: u32,
        l: Option<u32>,
        kind: flow::CallType,
        args: &[f64; flow::LOCALS],
        unpointed: u64,
        at: Pos,
    ) -> Result<(), String> {
        let before = self.flow.level();
        self.flow
            .call_numbered(p, l, kind, args, at, &mut self.st, self.finder.as_ref())?;
        let level = self.flow.level();
        if level > before {
            if self.adp.len() <= level {
                self.adp.resize(level + 1, 0);
            }
            self.adp[level] = unpointed;
        }
        Ok(())
    }

    /// Fanuc's `G66 P L` and its arguments: the modal call of macro O`P`, made after each
    /// move until G67. One G66 is in force at a time; L is 1 (or 0: no calls).
    fn g66(&mut self, n: u32, line: &read::Line) -> Result<(), TranslateError> {
        let (p, l, args, g_col, unpointed) = macro_call_words(66, n, line)?;
        let err = |message: String| TranslateError {
            line: n,
            col: g_col,
            message,
        };
        if let Some(m) = &self.modal_call {
            return Err(err(format!(
                "G66 while the modal call G66 P{} of line {} is in force: G67 first (novanc keeps one modal call)",
                m.p, m.line
            )));
        }
        match l {
            Some(0) => return Ok(()),
            Some(l) if l > 1 => {
                return Err(err(format!(
                    "G66 L{l}: novanc calls a modal macro once after each move (L1, or L0 for none)"
                )))
            }
            _ => {}
        }
        self.modal_call = Some(ModalCall {
            p,
            args,
            unpointed,
            line: n,
            level: self.flow.level(),
        });
        Ok(())
    }

    /// Fanuc's `G67`: cancels the G66 modal call (none in force: nothing to do, as Fanuc).
    fn g67(&mut self, n: u32, line: &read::Line) -> Result<(), TranslateError> {
        if let Some(w) = line
            .words
            .iter()
            .find(|w| !(w.letter == 'G' && w.value == 67.0))
        {
            return Err(TranslateError {
                line: n,
                col: w.col,
                message: "G67 stands alone on its block".into(),
            });
        }
        self.modal_call = None;
        Ok(())
    }

    /// The move of line `n` has been made with a G66 in force: its macro is called, unless
    /// the move is in the macro itself (or deeper).
    fn modal_call_after_move(&mut self, at: Pos, n: u32) -> Result<(), TranslateError> {
        let Some(m) = &self.modal_call else {
            return Ok(());
        };
        if self.flow.level() > m.level {
            return Ok(());
        }
        let (p, args, unpointed, given) = (m.p, m.args, m.unpointed, m.line);
        self.call_macro(p, None, flow::CallType::G66, &args, unpointed, at)
            .map_err(|message| TranslateError {
                line: n,
                col: 1,
                message: format!("{message} (the modal call of line {given})"),
            })
    }

    /// Fanuc's `#3000 = n (MESSAGE)`: macro alarm 3000 + n, the run stops there; `#3006 = n
    /// (MESSAGE)`: a stop with the message (as M00), the run goes on at CYCLE START.
    fn fanuc_message(
        &mut self,
        n: u32,
        p: usize,
        v: f64,
        col: u32,
        comments: &[read::Comment],
    ) -> Result<(), TranslateError> {
        let text = comments
            .first()
            .map_or(String::new(), |c| c.text.trim().to_string());
        let k = if read::is_null(v) { 0.0 } else { v.round() };
        if !(0.0..=999.0).contains(&k) {
            return Err(TranslateError {
                line: n,
                col,
                message: format!("#{p} = {v}: the number is 0 to 999"),
            });
        }
        if p == 3000 {
            return Err(TranslateError {
                line: n,
                col,
                message: format!("MACRO ALARM {}: {text} (#3000 = {k})", 3000 + k as u32),
            });
        }
        self.events.push(Event::Message {
            kind: "MSG",
            text: format!("#3006 STOP {k}: {text}"),
        });
        Ok(())
    }

    /// M2, M30 (`endm`) or the closing % (`None`): flushes compensation, stops the spindle
    /// for M2 as LinuxCNC does, resets what M2/M30 reset.
    fn end(
        &mut self,
        n: u32,
        text: &str,
        mut out: Vec<(Canon, u32, u32)>,
        endm: Option<u8>,
    ) -> Option<Result<Statement, TranslateError>> {
        let mut x = ctx!(self, n);
        let r = self.comp.flush(&mut x, 1);
        let mut tail = std::mem::take(&mut x.out);
        if let Err(e) = r {
            return self.fail(e);
        }
        let aux = |m: u8| {
            (
                Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(m),
                },
                n,
                1,
            )
        };
        if let Some(m) = endm {
            if m == 2 && self.st.modal.spindle != 0 {
                tail.push(aux(5));
            }
            tail.push(aux(m));
        }
        out.append(&mut tail);
        self.st.program_end_reset();
        self.done = true;
        self.finish(n, text, out, true)
    }

    /// Runs a line's comments (MSG, PRINT, DEBUG, LOG, ABORT), their messages kept as events.
    /// Runs line `n`'s messages; `back`: a back end other than the mill's executes the line,
    /// and a message prints the machine state it keeps as the line reads it (`#5001`,
    /// `#<_x>`), `######` for what it refuses.
    fn comments(
        &mut self,
        n: u32,
        comments: &[read::Comment],
        back: Option<&dyn Motion>,
    ) -> Result<(), TranslateError> {
        if comments.is_empty() {
            return Ok(());
        }
        let mut x = ctx!(self, n);
        let wants_clocks = std::cell::Cell::new(None);
        let env = back.map(|b| ParamEnv {
            st: &self.st,
            flow: &self.flow,
            fanuc: self.settings.dialect == Dialect::Fanuc,
            magazine: None,
            parts: self.parts,
            first_code: self.first_code,
            adp: &self.adp,
            clocks: None,
            wants_clocks: &wants_clocks,
            back: Some(b),
        });
        let (st, flow) = (&self.st, &self.flow);
        let lk = |name: &str| match &env {
            None => lookup(st, flow, name),
            Some(e) => match name.parse::<usize>() {
                Ok(n) if n <= sysvars::MAX_FANUC_VAR => e.numbered(n).ok(),
                Ok(_) => None,
                Err(_) => e.named(name).ok().flatten(),
            },
        };
        let c = exec::comments(&mut x, comments, &lk, st.params[5599] > 0.0);
        self.events.append(&mut x.events);
        self.out_buf = x.out;
        c
    }

    fn finish(
        &mut self,
        n: u32,
        text: &str,
        mut out: Vec<(Canon, u32, u32)>,
        _end: bool,
    ) -> Option<Result<Statement, TranslateError>> {
        // A statement handed back (`recycle`) lends its text and blocks' memory.
        let (mut blocks, mut buf) = match self.spare.take() {
            Some(s) => (s.blocks, s.text),
            None => (Vec::new(), String::new()),
        };
        blocks.clear();
        // At most one block an action: room for exactly that many (no doubling) once the
        // first action has made its block; a line refused at its first block (a point beyond
        // the travel, say) never reserves room for the rest.
        blocks.reserve_exact(out.len().min(1));
        let r = self.emitter.emit(&out, &self.settings, &mut blocks);
        out.clear();
        if out.capacity() > self.out_buf.capacity() {
            self.out_buf = out;
        }
        if let Err(e) = r {
            return self.fail(e);
        }
        self.made += blocks.len() as u64;
        if self.made > self.max_blocks {
            let max = self.max_blocks;
            return self.fail(TranslateError {
                line: n,
                col: 1,
                message: format!(
                    "the program makes more than {max} blocks (the most a program may make)"
                ),
            });
        }
        buf.clear();
        if self.texts {
            buf.push_str(trimmed(text));
        }
        Some(Ok(Statement {
            line: n,
            text: buf,
            blocks,
        }))
    }

    /// Hands back a statement its reader is done with: the next statement is made in its
    /// memory (its text and blocks), so a caller that drops each statement once used (`novanc
    /// translate`) allocates nothing per line.
    pub fn recycle(&mut self, st: Statement) {
        // A statement of many blocks (a canned cycle's) is let go: what is kept for the next
        // line stays small.
        if st.blocks.capacity() <= SPARE_BLOCKS {
            self.spare = Some(st);
        }
    }
}

impl Lines for GcodeSource {
    fn units(&mut self, inch: bool) {
        self.st.modal.inch = inch;
    }

    fn in_remap(&self) -> bool {
        self.remap.is_some()
    }

    fn read_line(
        &mut self,
        raw: &str,
        n: u32,
        back: &mut dyn Motion,
    ) -> Result<read::Line, TranslateError> {
        let placed = |message: String| TranslateError {
            line: n,
            col: 1,
            message,
        };
        // A line run by another line (a G70's profile) is read again.
        self.flow.read_again();
        self.count_line().map_err(placed)?;
        if let Some(e) = crate::limits::line_too_long(raw, n, "") {
            return Err(e);
        }
        let mut line = read::Line::default();
        let wants_clocks = std::cell::Cell::new(None);
        let opts = self.read_opts();
        {
            let env = param_env!(self, None, &wants_clocks, Some(&*back));
            read::read_into_opts(&mut self.scratch, &mut line, raw, n, &env, None, opts)?;
        }
        if opts.fanuc {
            fanuc_dwell(
                &mut line,
                n,
                opts.increment,
                self.settings.fanuc.p_point_seconds,
            )?;
            fanuc_mode_q(&mut line, opts.increment);
        }
        let flow = match (&line.o, &line.fanuc) {
            (Some(o), _) if o.kind != read::OKind::Bare => Some(o.col),
            (_, Some(read::Macro::Goto { col, .. } | read::Macro::While { col, .. })) => Some(*col),
            (_, Some(read::Macro::Do { col, .. } | read::Macro::End { col, .. })) => Some(*col),
            _ => line
                .words
                .iter()
                .find(|w| w.letter == 'G' && matches!(w.value, 65.0 | 66.0 | 67.0))
                .filter(|_| opts.fanuc)
                .map(|w| w.col),
        };
        if let Some(col) = flow {
            return Err(TranslateError {
                line: n,
                col,
                message: "program flow (an O-word, GOTO, WHILE/DO/END, a macro call) cannot stand in a line another line runs (a G70/G71 profile)".into(),
            });
        }
        if let Some(col) = self.assign(n, &line, Some(back))? {
            return Err(TranslateError {
                line: n,
                col,
                message: "#3006 cannot stand in a line another line runs (a G70/G71 profile)"
                    .into(),
            });
        }
        self.comments(n, &line.comments, Some(&*back))?;
        Ok(line)
    }
}

/// Fanuc's canned-cycle P (the dwell at the bottom, docs/gcode.md "Fanuc dialect") takes no
/// decimal point, as Fanuc 0i's (alarm PS0007, illegal use of decimal point): a `P1500.` on a
/// line with a cycle's G code, or repeating the cycle in force (an axis word or R, and no
/// G04, G10, G65, G66 or M98 of its own P), is refused at the P.
fn fanuc_cycle_p(line: &read::Line, n: u32, motion: state::Motion) -> Result<(), TranslateError> {
    if line.pointed & read::letter_bit('P') == 0 {
        return Ok(());
    }
    let g_on_line = cycle_on_line(line);
    let own_p = line.words.iter().any(|w| {
        (w.letter == 'G' && [4.0, 10.0, 65.0, 66.0].contains(&w.value))
            || (w.letter == 'M' && w.value == 98.0)
    });
    let repeats = matches!(motion, state::Motion::Cycle(_))
        && !own_p
        && line.words.iter().any(|w| "XYZRABC".contains(w.letter));
    let g = match (g_on_line, motion) {
        (Some(g), _) => g,
        (None, state::Motion::Cycle(g)) if repeats => f64::from(g) / 10.0,
        _ => return Ok(()),
    };
    // A P with a fraction is refused as such by the cycle (`G82 P1.5: ...`).
    let Some(p) = line
        .words
        .iter()
        .find(|w| w.letter == 'P' && w.value.fract() == 0.0)
    else {
        return Ok(());
    };
    Err(TranslateError {
        line: n,
        col: p.col,
        message: format!(
            "G{g:02} P{}.: P is a whole number of milliseconds written without a decimal point in the Fanuc dialect (P1500 is 1.5 s; a Fanuc 0i raises alarm PS0007, illegal use of decimal point)",
            crate::input_text::short_number(p.value)
        ),
    })
}

/// Fanuc's G05.1 Q1 R5 (AI contour control on at precision level 5; Q0 off): its Q and R are
/// numbers of a mode, not lengths, so written without a decimal point they are read as
/// written, not in least increments (`Q1` is 1, not 0.001 mm).
fn fanuc_mode_q(line: &mut read::Line, increment: f64) {
    let bits = read::letter_bit('Q') | read::letter_bit('R');
    if line.plain & bits == 0 || !line.words.iter().any(|w| w.letter == 'G' && w.value == 5.1) {
        return;
    }
    as_written(line, 'Q', increment);
    as_written(line, 'R', increment);
}

/// Fanuc 0i's K on a canned cycle's line (the cycle's G code on it, or the cycle in force
/// repeated by an axis word or R) is the number of repeats, not a length: written without a
/// decimal point it is read as written, not in least increments (`K5` is 5 holes). The line
/// is then sorted again from its words.
fn fanuc_cycle_k(line: &mut read::Line, increment: f64, motion: state::Motion) {
    if line.plain & read::letter_bit('K') == 0 {
        return;
    }
    let repeats = matches!(motion, state::Motion::Cycle(_))
        && line.words.iter().any(|w| "XYZRABC".contains(w.letter));
    if cycle_on_line(line).is_some() || repeats {
        as_written(line, 'K', increment);
    }
}

/// A canned cycle's G code on the line (G73, G74, G76, G81–G89), if any.
fn cycle_on_line(line: &read::Line) -> Option<f64> {
    let is_cycle = |g: f64| g == 73.0 || g == 74.0 || g == 76.0 || (81.0..=89.0).contains(&g);
    (line.words.iter())
        .find(|w| w.letter == 'G' && is_cycle(w.value))
        .map(|w| w.value)
}

/// `letter`'s word read as written where it was written without a decimal point (the Fanuc
/// dialect had read it in least increments): a count or a mode number, not a length. The line
/// is then sorted again from its words, as after every rewrite of them.
fn as_written(line: &mut read::Line, letter: char, increment: f64) {
    let bit = read::letter_bit(letter);
    if line.plain & bit == 0 || line.pointed & bit != 0 || increment <= 0.0 {
        return;
    }
    for w in line.words.iter_mut().filter(|w| w.letter == letter) {
        w.value = (w.value / increment).round();
    }
    line.sorted = false;
}

/// Fanuc's G04 (docs/gcode.md "Fanuc dialect"): `X` or `U` in seconds (without a decimal
/// point in least increments of 0.001 s), `P` in milliseconds written without a decimal
/// point (with one, seconds where the machine says so, `p_point_seconds`: a Haas's reading;
/// else refused); made LinuxCNC's `P` in seconds for the line's execution.
fn fanuc_dwell(
    line: &mut read::Line,
    n: u32,
    increment: f64,
    p_point_seconds: bool,
) -> Result<(), TranslateError> {
    if !line.words.iter().any(|w| w.letter == 'G' && w.value == 4.0) {
        return Ok(());
    }
    let err = |col: u32, message: String| TranslateError {
        line: n,
        col,
        message,
    };
    let mut dwell = None;
    for (i, w) in line.words.iter().enumerate() {
        if !matches!(w.letter, 'X' | 'U' | 'P') {
            continue;
        }
        if dwell.is_some() {
            return Err(err(
                w.col,
                "G04 takes one dwell: X or U in seconds, or P in milliseconds".into(),
            ));
        }
        dwell = Some(i);
    }
    let Some(i) = dwell else {
        let col = line
            .words
            .iter()
            .find(|w| w.letter == 'G' && w.value == 4.0)
            .map_or(1, |w| w.col);
        return Err(err(
            col,
            "G04 needs its dwell: X or U in seconds (X1.5), or P in milliseconds (P1500)".into(),
        ));
    };
    let w = line.words[i];
    let bit = read::letter_bit(w.letter);
    let plain = line.plain & bit != 0;
    let pointed = line.pointed & bit != 0;
    let seconds = if w.letter == 'P' && pointed && p_point_seconds {
        // A Haas's G04 P10. is ten seconds (P10, ten milliseconds).
        w.value
    } else if w.letter == 'P' {
        if pointed {
            return Err(err(w.col, format!(
                "G04 P{}: P is in milliseconds and takes no decimal point (P1500 is 1.5 s; X1.5 gives seconds; a Haas's P with a point is seconds: `g04 p point seconds` in its description)",
                crate::input_text::short_number(w.value)
            )));
        }
        if w.value.fract() != 0.0 {
            return Err(err(
                w.col,
                format!(
                    "G04 P{}: P is a whole number of milliseconds",
                    crate::input_text::short_number(w.value)
                ),
            ));
        }
        w.value / 1000.0
    } else if plain && !pointed {
        // Least increments: the count read, in milliseconds.
        (w.value / increment).round() / 1000.0
    } else {
        w.value
    };
    line.words[i] = read::Word {
        letter: 'P',
        value: seconds,
        col: w.col,
    };
    // Sorted again from its words (the one-pass reader sorted X or U, in other units).
    line.sorted = false;
    Ok(())
}

/// `raw.trim()`, the usual line (ASCII letters and digits at both ends, perhaps with ASCII
/// blanks around them, as CAM output ends its lines) without the search for Unicode spaces.
fn trimmed(raw: &str) -> &str {
    // ASCII blanks are spaces to `trim` too; past them, an ASCII graphic at both ends is
    // where `trim` stops.
    let blank = |c: &u8| matches!(c, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c);
    let b = raw.as_bytes();
    let from = b.iter().position(|c| !blank(c)).unwrap_or(b.len());
    let to = b.iter().rposition(|c| !blank(c)).map_or(from, |i| i + 1);
    match raw.get(from..to) {
        Some(t) if t.is_empty() || (b[from].is_ascii_graphic() && b[to - 1].is_ascii_graphic()) => {
            t
        }
        _ => raw.trim(),
    }
}

/// The words of a Fanuc macro call block, `G65` or `G66` (`g`) with P, L and the arguments of
/// specification I ([`G65_ARGUMENTS`]): the program number, L, #1–#33 (NaN: not given) and
/// the G's column.
#[allow(clippy::type_complexity)]
fn macro_call_words(
    g: u8,
    n: u32,
    line: &read::Line,
) -> Result<(u32, Option<u32>, [f64; flow::LOCALS], u32, u64), TranslateError> {
    let err = |col: u32, message: String| TranslateError {
        line: n,
        col,
        message,
    };
    let g_col = line
        .words
        .iter()
        .find(|w| w.letter == 'G')
        .map_or(1, |w| w.col);
    let mut args = [f64::NAN; flow::LOCALS];
    // The locals given without a decimal point on a length address (ADP reads them as if
    // with one).
    let mut unpointed = 0u64;
    let (mut p, mut l) = (None, None);
    for w in &line.words {
        match w.letter {
            'G' if w.value == f64::from(g) && w.col == g_col => {}
            'G' => {
                return Err(err(
                    w.col,
                    format!("G{g} stands alone on its block: no other G code with it"),
                ))
            }
            'P' | 'L' => {
                let v = w.value.round();
                // L is bounded as M98's is (docs/limits.md).
                let max = if w.letter == 'P' {
                    99_999_999.0
                } else {
                    MAX_REPEATS as f64
                };
                if (w.value - v).abs() > 1e-4 || !(0.0..=max).contains(&v) {
                    return Err(err(
                        w.col,
                        format!("G{g} {}: a whole number 0 to {max}", w.letter),
                    ));
                }
                let slot = if w.letter == 'P' { &mut p } else { &mut l };
                if slot.is_some() {
                    return Err(err(w.col, format!("G{g}: {} is given twice", w.letter)));
                }
                *slot = Some(v as u32);
            }
            c => {
                let Some(&(_, k)) = G65_ARGUMENTS.iter().find(|(a, _)| *a == c) else {
                    return Err(err(
                            w.col,
                            format!("G{g}: {c} is not an argument (A B C D E F H I J K M Q R S T U V W X Y Z)"),
                        ));
                };
                if !args[k - 1].is_nan() {
                    return Err(err(w.col, format!("G{g}: argument {c} is given twice")));
                }
                args[k - 1] = w.value;
                let bit = read::letter_bit(c);
                if line.plain & bit != 0
                    && line.pointed & bit == 0
                    && read::FANUC_INCREMENT_LETTERS.contains(&(c as u8))
                {
                    unpointed |= 1 << k;
                }
            }
        }
    }
    let Some(p) = p else {
        return Err(err(
            g_col,
            format!("G{g} needs P, the macro's program number"),
        ));
    };
    Ok((p, l, args, g_col, unpointed))
}

/// The words of a line, as `words::sort_words_into` takes them.
fn line_words(l: &read::Line) -> &read::Line {
    l
}

/// A parameter for PRINT and DEBUG texts: `5` for #5, `name` for #<name>.
fn lookup(st: &InterpState, flow: &Flow, name: &str) -> Option<f64> {
    if let Ok(n) = name.parse::<usize>() {
        return (n <= read::MAX_PARAM).then(|| st.param(n));
    }
    st.named_value(name, flow.locals())
}

#[cfg(test)]
mod trim_tests {
    use super::trimmed;

    /// A reader without texts makes the same blocks, and statements whose text is empty.
    #[test]
    fn without_texts_the_blocks_are_the_same() {
        let src = "G0 X1 Y2  \n(a comment)\nG1 Z-1 F100\n G2 X3 Y2 I1 J0\nM30\n";
        let make = || {
            super::GcodeSource::new(
                src.into(),
                crate::tooldata::sample_magazine(),
                crate::settings::MachineSettings::default(),
                crate::block::MachineState::at([0, 0, 0]),
                Default::default(),
                Default::default(),
            )
        };
        let with: Vec<_> = make().map(|r| r.unwrap()).collect();
        let without: Vec<_> = make().without_texts().map(|r| r.unwrap()).collect();
        assert_eq!(with.len(), without.len());
        assert!(with.iter().any(|s| s.text == "G0 X1 Y2"));
        for (a, b) in with.iter().zip(&without) {
            assert_eq!(a.blocks, b.blocks);
            assert_eq!((a.line, b.text.as_str()), (b.line, ""));
        }
    }

    /// `trimmed` is `trim` without its Unicode search on the usual lines: ASCII blanks around
    /// ASCII words (CAM output's trailing spaces), and the same as `trim` on anything else.
    #[test]
    fn trimmed_is_trim() {
        for raw in [
            "G01 X1 Y2",
            "G01 X-0.3089 Y1.5993  ",
            "\t N10 G0 X1\r",
            "   ",
            "",
            "\u{b}G1 X1\u{c}",
            "G1 X1 (é)",
            "(é) G1 X1 \u{a0}",
            "\u{2003}G1 X1",
            " \u{a0} ",
            "G1 X1 \u{85}",
            "é",
        ] {
            assert_eq!(trimmed(raw), raw.trim(), "{raw:?}");
        }
    }
}
