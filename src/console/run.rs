//! Running the machine from the console: START of AUTO, MDI and SINGLE BLOCK runs (the core
//! decides whether START resumes or begins a run; a new run's program source translates from
//! the machine's actual state), the program alarm, jog/STEP/HANDLE, the
//! script's waits (a tape read in progress runs to its end first), and the session recording.

use super::manual::SCALES;
use super::wait::{WaitFor, WAIT_LIMIT_NS};
use super::{Console, ProgramAlarm};
use crate::block::MachineState;
use crate::gcode::{GcodeSource, InterpState, Switches, WorkOffsets};
use crate::panel_model::OpMode;
use crate::pulse_core::{Command, EndCause, MakeRun, Reached, RunKind, StatementIter};
use crate::settings::MachineSettings;
use crate::store::Target;
use crate::tooldata::Magazine;
use crate::translator::Translator;
use std::sync::Arc;

/// What a program source is made from at START.
#[derive(Clone)]
pub struct RunSource {
    /// The text to run.
    pub text: Arc<str>,
    /// The text is ISO G-code (docs/gcode.md), not the source language.
    pub gcode: bool,
    /// MDI: G-code text need not end with M02, M30 or `%`.
    pub mdi: bool,
    /// MDI in the source language: program memory, whose definitions the MDI text may use.
    pub definitions: Option<Arc<str>>,
    /// SEARCH: start at this source line, restoring the state before it.
    pub resume_at: Option<u32>,
    /// The tool data.
    pub magazine: Magazine,
    /// The machine settings.
    pub settings: MachineSettings,
    /// G-code: the work offsets G54 to G59 in force (when no interpreter state is given).
    pub offsets: WorkOffsets,
    /// G-code: the interpreter's state to read from (the console's); the position, the tool
    /// and the spindle are then the machine's.
    pub interp: Option<InterpState>,
    /// G-code: the BLOCK DELETE and OPTIONAL STOP switches.
    pub switches: Switches,
    /// G-code: where the run hands back what it reads (None: it is dropped).
    pub feed: Option<super::gcode_run::RunFeed>,
    /// G-code: the programs and folders where `o<name> call` finds `name.ngc`.
    pub subroutines: Option<Arc<crate::gcode::SubPrograms>>,
    /// G-code: the part counter, parts made and required (Fanuc's #3901/#3902).
    pub parts: Option<(u64, u64)>,
}

impl RunSource {
    /// A whole program named `name` (its name or first line decides the language), from the
    /// start, with zero work offsets and both switches off.
    pub fn program(
        name: &str,
        text: Arc<str>,
        magazine: Magazine,
        settings: MachineSettings,
    ) -> RunSource {
        RunSource {
            gcode: crate::gcode::is_gcode(name, &text),
            text,
            mdi: false,
            definitions: None,
            resume_at: None,
            magazine,
            settings,
            offsets: WorkOffsets::default(),
            interp: None,
            switches: Switches::default(),
            feed: None,
            subroutines: None,
            parts: None,
        }
    }

    /// The statements of this source, in its language, from the machine's actual state.
    pub fn statements(self, state: MachineState) -> StatementIter {
        if !self.gcode {
            return Box::new(self.translator(state));
        }
        let feed = self.feed.clone();
        let Some(g) = self.gcode_source(state) else {
            return Box::new(std::iter::empty());
        };
        match feed {
            Some(feed) => Box::new(super::gcode_run::Feeding {
                src: g,
                feed,
                handed: false,
            }),
            None => Box::new(g),
        }
    }

    /// The G-code source of this source (None when it is in the source language), from the
    /// machine's actual state: the interpreter's state given, or the work offsets.
    pub fn gcode_source(self, state: MachineState) -> Option<GcodeSource> {
        if !self.gcode {
            return None;
        }
        let pulse_mm = self.settings.pulse_mm;
        let mut g = match self.interp {
            Some(mut st) => {
                // The spindle is the machine's, as the position and the tool are.
                st.modal.spindle = state.spindle.signum() as i8;
                if state.spindle != 0 {
                    st.modal.speed = state.spindle.unsigned_abs() as f64;
                }
                GcodeSource::with_state(
                    self.text,
                    self.magazine,
                    self.settings,
                    state,
                    st,
                    self.switches,
                )
            }
            None => GcodeSource::new(
                self.text,
                self.magazine,
                self.settings,
                state,
                self.offsets,
                self.switches,
            ),
        };
        if self.mdi {
            g = g.mdi();
        }
        if let Some(l) = self.resume_at {
            g = g.resume_at(l);
        }
        if let Some((made, required)) = self.parts {
            g = g.part_counter(made, required);
        }
        if let Some(f) = self.subroutines {
            g = g.subroutines(Box::new(f));
        }
        // Probes are answered by the pulse core running this source (issue 21).
        if let Some(m) = super::answers::RunMachine::here(pulse_mm) {
            g = g.machine(Box::new(m));
        }
        Some(g)
    }

    /// The source-language translator for this source, from the machine's actual state.
    pub fn translator(self, state: MachineState) -> Translator {
        let mut t = Translator::from_state(self.text, self.magazine, self.settings, state);
        if let Some(p) = &self.definitions {
            t = t.with_definitions_from(p);
        }
        if let Some(l) = self.resume_at {
            t = t.resume_at(l);
        }
        t
    }

    /// The program source the pulse core starts a new run with.
    pub fn make_run(self) -> MakeRun {
        Box::new(move |state| -> StatementIter { self.statements(state) })
    }
}

/// The program source START would begin a new run of `kind` with.
pub(super) fn run_source(c: &mut Console, kind: RunKind) -> RunSource {
    let (text, gcode, definitions, resume_at) = match kind {
        RunKind::Auto => (
            c.mem.text_shared(Target::Program),
            c.mem.program_is_gcode(),
            None,
            c.search.as_ref().map(|s| s.line),
        ),
        RunKind::Mdi => {
            let text = c.mem.text_shared(Target::Mdi);
            let gcode = super::gcode_run::mdi_is_gcode(&text);
            let defs = (!gcode).then(|| c.mem.text_shared(Target::Program));
            (text, gcode, defs, None)
        }
    };
    if gcode {
        super::gcode_run::before_read(c);
    }
    // AUTO reads the program in the dialect it was stored in; MDI in the machine's
    // (docs/gcode.md "Fanuc dialect": the programs a run calls are read in the run's).
    let settings = c.run_settings_for(kind == RunKind::Auto);
    RunSource {
        text,
        gcode,
        mdi: kind == RunKind::Mdi,
        definitions,
        resume_at,
        magazine: c.mem.magazine(),
        settings,
        offsets: c.mem.work_offsets(),
        interp: gcode.then(|| c.interp.clone()),
        switches: c.shell.front.switches,
        feed: None,
        subroutines: gcode.then(|| Arc::new(c.mem.subroutines())),
        parts: Some((c.shell.book.counters.parts, c.shell.book.counters.target)),
    }
}

/// START in AUTO, SINGLE BLOCK (kind Auto) or MDI (kind Mdi): the core resumes the run loaded,
/// or begins a new one from the program source, or says why it cannot.
pub(super) fn start_program(c: &mut Console, kind: RunKind) {
    let single = c.shell.front.op == OpMode::Single;
    if c.status.job.is_none() {
        if let Some(why) = super::posmem::refusal(c) {
            c.shell.front.message = why;
            return;
        }
    }
    if kind == RunKind::Auto && c.status.job.is_none() {
        if let Some(why) = super::book::target_refusal(c) {
            c.shell.front.message = why;
            return;
        }
    }
    // The position file says the axes move before they can (`posmem.rs`); if it cannot,
    // nothing is made or started.
    if let Err(e) = super::posmem::before_motion(c) {
        c.shell.front.message = format!("START refused: {e}");
        return;
    }
    // The single-block switch is told only when START can act: a START ignored while a block
    // executes changes nothing, not even whether the run stops after that block.
    let st = &c.status;
    if st.job.is_none() || st.hold || (st.run == 0 && !st.in_block) {
        c.command(Command::SingleBlock(single));
    }
    let make = if c.status.job.is_none() {
        c.core.set_magazine(c.mem.magazine());
        note_run_end(c);
        super::gcode_run::before_run(c);
        let mut src = run_source(c, kind);
        if src.gcode {
            let feed = super::gcode_run::RunFeed::default();
            src.feed = Some(feed.clone());
            c.run_feed = Some(feed);
            c.feed_keep = false;
        }
        Some(src.make_run())
    } else {
        None
    };
    let runs_before = c.status.runs;
    c.status = c.core.start(kind, make);
    c.notice_seen = c.status.notice.clone();
    if let Some(n) = &c.status.notice {
        c.shell.front.message = n.clone();
        if n.starts_with("START ignored") {
            // It speaks of the block executing: it goes when that block ends.
            c.shell.front.life = super::MsgLife::WhileBlock(c.status.blocks_done);
        }
        return;
    }
    c.start_single = single;
    if c.status.runs > runs_before {
        // A new run took the program as it is now: what it finds decides the alarm.
        c.program_alarm = None;
        if kind == RunKind::Auto {
            if let Some(sp) = c.search.take() {
                c.shell.front.message = format!("running from line {} (SEARCH)", sp.line);
            }
        }
        note_run_end(c);
    }
    // Resumed: a return to where the run stopped is said by the display while it lasts.
}

/// Reports a run's end once: the message, and the program alarm for a source error.
pub(super) fn note_run_end(c: &mut Console) {
    let Some(end) = c.status.last_end.clone() else {
        return;
    };
    if end.id <= c.end_seen {
        return;
    }
    c.end_seen = end.id;
    let nothing_moved = matches!(
        end.cause,
        EndCause::Error {
            nothing_moved: true,
            ..
        }
    );
    super::gcode_run::end_run(c, nothing_moved);
    super::gcode_run::keep_hour_clock(c, end.lamp_ns);
    let done = end.cause == EndCause::ProgramEnd;
    super::book::count_run(c, end.kind == RunKind::Auto, done, end.machine_ns);
    let secs = end.machine_ns as f64 / 1e9;
    match end.cause {
        EndCause::ProgramEnd => {
            c.shell.front.message = format!("program end: {} blocks in {secs:.1} s", end.blocks);
            let k = c.shell.book.counters;
            if end.kind == RunKind::Auto && k.target > 0 && k.parts >= k.target {
                c.shell.front.message = format!(
                    "{}; part count target reached ({}/{}): the next AUTO START waits for PARTS 0 or a new TARGET",
                    c.shell.front.message, k.parts, k.target
                );
            }
        }
        EndCause::Error {
            error,
            nothing_moved,
        } => {
            let what = if nothing_moved {
                "START refused, nothing moved"
            } else {
                "the run stopped before the statement in error"
            };
            c.shell.front.message = format!(
                "{what}: line {}:{}: {}",
                error.line, error.col, error.message
            );
            c.program_alarm = Some(ProgramAlarm {
                kind: end.kind,
                error,
                rev: c.mem.rev(),
            });
        }
        EndCause::Abandoned | EndCause::Alarm => {}
    }
    if let Some(m) = c.shell.book.program_msg.take() {
        if c.shell.front.message.is_empty() {
            c.shell.front.message = m;
        } else if !c.shell.front.message.contains(&m) {
            c.shell.front.message = format!("{m}; {}", c.shell.front.message);
        }
    }
}

/// After a change to memory: a program alarm whose text now translates is cleared; one that
/// still fails shows the error it fails with now.
pub(super) fn recheck_program_alarm(c: &mut Console) {
    let Some(a) = &c.program_alarm else { return };
    if a.rev == c.mem.rev() {
        return;
    }
    let kind = a.kind;
    let mut src = run_source(c, kind);
    src.resume_at = None;
    let state = c.status.machine_state();
    let found = src.statements(state).find_map(|r| r.err());
    match found {
        None => {
            c.program_alarm = None;
            c.shell
                .front
                .message
                .push_str("; the program alarm is cleared (the program translates)");
        }
        Some(error) => {
            c.program_alarm = Some(ProgramAlarm {
                kind,
                error,
                rev: c.mem.rev(),
            });
        }
    }
}

/// The centre's part of a script's wait (`wait::wait`): the machine runs (virtual time) or
/// is waited for (real time) until the condition, at most [`WAIT_LIMIT_NS`] of machine time;
/// a tape read in progress runs to its end first, and `wait ms` moves the tape.
pub(super) fn run_wait(c: &mut Console, w: WaitFor) -> Reached {
    if let WaitFor::Ms(t) = w {
        // The tape moves with machine time (docs/tape.md, "At the console").
        if super::tape::reading(c) {
            let (r, st) = c.core.run_for(t.saturating_mul(1_000_000));
            c.status = st;
            super::tape::advance(c);
            return r;
        }
    } else {
        wait_tape(c);
    }
    let (r, st) = match w {
        WaitFor::Idle => c.core.run_until_idle(WAIT_LIMIT_NS),
        WaitFor::Block(n) => c.core.run_until_block(0, n, WAIT_LIMIT_NS),
        WaitFor::Ms(t) => c.core.run_for(t.saturating_mul(1_000_000)),
    };
    c.status = st;
    note_run_end(c);
    r
}

/// Lets the tape read in progress, if any, run to its end (a script's `wait` or `wait block`):
/// the machine time it takes passes.
fn wait_tape(c: &mut Console) {
    while let Some(ns) = super::tape::remaining_ns(c) {
        let (r, st) = c.core.run_for(ns.max(1));
        c.status = st;
        super::tape::advance(c);
        if r == Reached::Interrupted {
            break;
        }
    }
}

/// The increment the console starts with: the configured STEP length when it is one of
/// [`SCALES`], else 0.1 mm's worth (x100).
pub(super) fn default_scale(s: &MachineSettings) -> u32 {
    let p = s.to_pulses(s.step_mm);
    SCALES
        .iter()
        .copied()
        .find(|&k| i64::from(k) == p)
        .unwrap_or(100)
}

/// A rapid override as the operator reads it: "F0" or "25 %".
pub(super) fn rapid_override_text(p: u32) -> String {
    if p == 0 {
        "F0".into()
    } else {
        format!("{p} %")
    }
}

/// The rapid override switch turned to `p`, on every console: what it does, or why the
/// machine refuses it (its positions are F0, 25, 50 and 100 %, as `Machine` takes them).
pub(crate) fn rapid_override_message(p: u32) -> Result<String, String> {
    if matches!(p, 0 | 25 | 50 | 100) {
        Ok(format!(
            "rapid override {}: rapids, jogs and returns",
            rapid_override_text(p)
        ))
    } else {
        Err(format!(
            "rapid override {p} % refused: F0 (0), 25, 50 or 100"
        ))
    }
}

/// The spindle override turned to `p`, on every console: what it does, or why the machine
/// refuses it (50 to 120 % in steps of 10, as `Machine` takes it).
pub(crate) fn spindle_override_message(p: u32) -> Result<String, String> {
    if (50..=120).contains(&p) && p.is_multiple_of(10) {
        Ok(format!(
            "spindle override {p} %: the spindle turns at S x {p} %"
        ))
    } else {
        Err(format!(
            "spindle override {p} % refused: 50 to 120 in steps of 10"
        ))
    }
}

/// The rapid override key's next position (Alt+f): one step down, 100 → 50 → 25 → F0 → 100.
pub(crate) fn next_rapid(p: u32) -> u32 {
    match p {
        100 => 50,
        50 => 25,
        25 => 0,
        _ => 100,
    }
}

/// The spindle override keys (Alt+[ and Alt+]): `d` percent from `p`, inside 50 to 120 %.
pub(crate) fn next_spindle(p: u32, d: i32) -> u32 {
    (p as i32 + d).clamp(50, 120) as u32
}

/// The switches as a state line writes them, on every console and in one order: BLOCK DELETE
/// and OPTIONAL STOP (` /DEL M01`), the overrides away from 100 % (` RPD50%`, ` RPDF0`,
/// ` SOV110%`), ` DRY`, and ` MLK` or else ` ZNG`. Before stop 49 the lathe wrote /DEL and M01
/// last, in the other order.
pub(crate) fn switch_words(
    program: &crate::gcode::Switches,
    m: &crate::record::Switches,
) -> String {
    let mut s = String::new();
    if program.block_delete {
        s.push_str(" /DEL");
    }
    if program.optional_stop {
        s.push_str(" M01");
    }
    if m.rapid_override != 100 {
        let r = rapid_override_text(m.rapid_override).replace(' ', "");
        s.push_str(&format!(" RPD{r}"));
    }
    if m.spindle_override != 100 {
        s.push_str(&format!(" SOV{}%", m.spindle_override));
    }
    if m.dry_run {
        s.push_str(" DRY");
    }
    if m.machine_lock {
        s.push_str(" MLK");
    } else if m.z_neglect {
        s.push_str(" ZNG");
    }
    s
}

/// What DRY RUN, MACHINE LOCK or Z NEGLECT does, as the message of turning it over.
pub(crate) fn machine_switch_message(name: &str, on: bool) -> String {
    if !on {
        return match name {
            "DRY RUN" => "DRY RUN off: feed moves at their programmed F".into(),
            _ => format!(
                "{name} off: the axes move; RESET or the next run brings the position back to them"
            ),
        };
    }
    match name {
        "DRY RUN" => "DRY RUN on: feed moves at the jog feed times the feed override".into(),
        "MACHINE LOCK" => {
            "MACHINE LOCK on: the program runs, the axes stay; RESET brings the position back"
                .into()
        }
        _ => "Z NEGLECT on: Z stays, its program position moves; RESET brings it back".into(),
    }
}

/// The jog deadman: a held jog decelerates on its own in the pulse core when the front end
/// has not kept it alive for this long (a key's repeat, a window frame while its button is
/// held; the console's own release of a key, `front::JOG_RELEASE`, comes first): for a front
/// end that has stopped running (docs/pulse-core.md, "The jog deadman").
pub const JOG_DEADMAN: std::time::Duration = std::time::Duration::from_millis(250);

/// [`JOG_DEADMAN`] in milliseconds.
pub(crate) fn deadman_ms() -> u32 {
    JOG_DEADMAN.as_millis() as u32
}
