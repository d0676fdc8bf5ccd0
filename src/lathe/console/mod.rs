//! The lathe console (docs/lathe.md "The panel"): the operator's panel of a lathe with one or
//! more channels. A channel selector chooses the channel the plasma display, the data keys and
//! the editor act on; a summary line shows every channel's state, current block, whom it waits
//! for and its part count. START, STOP and E-STOP act on the whole machine, RESET on the
//! selected channel (after an E-STOP, on the machine).
//!
//! The machine is the one kernel in the pulse core thread (`PulseCore::spawn_kernel`, every
//! channel on one NCBR clock): in real time (the terminal, the window) it runs on its own
//! clock whatever the screen does, and `tick` only takes its state; in virtual time (scripts)
//! `tick` advances it by the machine time given.

mod entry;
pub mod events;
mod glue;
mod jog;
mod ofs;
mod posts;
pub mod view;

pub use glue::{home, recording_info, Cycle, CycleSpec, KernelSpec, RunUntil};

use super::desc::LatheDesc;
use crate::console::book::Book;
use crate::console::front::Front;
use crate::console::keys::Action;
use crate::console::recording::Recording;
use crate::console::shell::Shell;
use crate::console::state::{ESTOP_NOTE, HOLD_NOTE};
use crate::console::wait::{WaitFor, WAIT_LIMIT_NS};
use crate::console::MsgLife;
use crate::panel_model::{OpMode, Page, PanelEvent};
use crate::pulse_core::{ClockMode, Command, Reached};
use crate::store::lathe::{Counter, LatheStore, Program};
use novanc_panel::Key;
use std::path::Path;
use view::ChanView;

/// How late a script's wait may end past what it waits for (rest, a block's start): the
/// kernel looks at its channels this often, in machine time (`Kernel::set_look_ns`), as the
/// console's 10 ms steps did before the wait ran in the kernel's thread.
pub(crate) const WAIT_LOOK_NS: u64 = 10_000_000;

/// The lathe console.
pub struct LatheConsole {
    /// What every console holds beside its machine (`crate::console::shell`): the operator's
    /// side (selector, AUTO at power-on; entry line, message, help, switches, feed override,
    /// handwheel); the page up over the mode display (OFS, where the data keys revise the
    /// selected channel's tools, `T1 X0.02 Z-0.01 R0.8 P3`; MSG, the alarm and message
    /// history; MACRO, the selected channel's variables; MODAL; POS); the log book in the
    /// lathe's state directory (the history, kept across restarts; the counters: parts
    /// delivered at the unloader in every batch, the last cycle's time from the part before it,
    /// the first from START, and the machine time with a cycle or an MDI run under way, the
    /// batch's target and counts being the part counter's, `counter`; the programs' messages
    /// that live until acknowledged); each channel's MDI recall; the recording.
    shell: Shell,
    desc: LatheDesc,
    store: LatheStore,
    programs: Vec<Program>,
    pointers: Vec<usize>,
    /// The editor pointer's line (1-based), per channel.
    edit_line: Vec<usize>,
    mdi: Vec<Vec<String>>,
    counter: Counter,
    sel: usize,
    /// The OFS page's cursor: the selected channel's tool (its row) and column
    /// (`ofs::COLUMNS`).
    ofs_cell: (usize, usize),
    /// Each channel's relative position's origin, pulses [X radius, Z] (the POS page's REL,
    /// the centre's: `X`, `X12.5`, `XZ` INPUT on POS).
    rel: Vec<[i64; 2]>,
    /// Each channel's jog feed chosen on POS (`JOG 500`, `JOG RAPID`, the centre's words),
    /// kept in the stores (docs/lathe.md "POS").
    jog: Vec<crate::console::manual::JogChoice>,
    /// When the last part was delivered in this batch, machine time.
    last_part_ns: Option<u64>,
    /// The machine time each channel's latest fault or alarm came at (the kernel's event).
    alarm_at: Vec<Option<u64>>,
    /// The channel the message just said speaks of, when not the selected one (a script's
    /// `fault 2 ...`): the history files it under that channel's program.
    msg_of: Option<usize>,
    /// The one kernel of the machine, in the pulse core thread from the console's opening to
    /// its close, and the cycle, MDI program or nothing loaded into it (every view of the
    /// machine is the kernel's published state: where each tool post stands, what each
    /// spindle does, E-STOP). Before stop 42 a kernel was spawned at each START, and between
    /// cycles the screen was drawn from the console's memory of the last one.
    cycle: glue::Cycle,
    rows: usize,
    cols: usize,
    last_display: Vec<String>,
    /// Machine time since the console opened, ns (cycles follow one another on it).
    now_ns: u64,
    /// A partial batch found at open: START begins a new batch from 0.
    stale_counts: bool,
    /// Each channel's interpreter state, as its last program or MDI left it
    /// (docs/lathe-gcode.md "What a channel keeps").
    kept: Vec<super::gcode::Kept>,
    /// Asked between the steps of a script's wait (a stop signal ends it).
    interrupt: Option<fn() -> bool>,
    /// SEARCH (docs/lathe.md "SEARCH"): the source line channel 1's next AUTO START runs
    /// from, for one part, on a lathe of one channel loaded by hand.
    search: Option<u32>,
    /// The position memory (`posts.rs`): where each tool post was last kept, whether it
    /// owes the reference return, and each HOME under way.
    posts: posts::Posts,
}

/// What the terminal or the window draws.
#[derive(Clone, Debug, PartialEq)]
pub struct LatheView {
    /// The title line: machine, mode, switches, parts, machine time.
    pub title: String,
    /// One summary line per channel.
    pub summary: Vec<String>,
    /// The plasma display of the selected channel.
    pub display: Vec<String>,
    /// Every channel as the display sees it (the window's side-by-side view).
    pub channels: Vec<ChanView>,
    /// The selected channel, 0-based.
    pub selected: usize,
    /// The help screen is up.
    pub help: bool,
    /// Machine time, ns.
    pub machine_ns: u64,
}

impl LatheConsole {
    /// Opens the console of `desc` on the state directory (programs and part counter in
    /// `lathe-NAME/`), with a `rows`×`cols` plasma display, recording to `record` if given.
    pub fn open(
        desc: LatheDesc,
        state: &Path,
        rows: usize,
        cols: usize,
        record: Option<&Path>,
    ) -> Result<(LatheConsole, Vec<String>), String> {
        LatheConsole::open_on(desc, state, (rows, cols), record, ClockMode::Virtual)
    }

    /// [`LatheConsole::open`], its kernel on `clock` for the console's life: real time (the
    /// terminal, the window: the kernel keeps the wall clock on its own) or virtual (scripts:
    /// machine time passes in `tick` and `run_for`).
    pub fn open_on(
        desc: LatheDesc,
        state: &Path,
        (rows, cols): (usize, usize),
        record: Option<&Path>,
        clock: ClockMode,
    ) -> Result<(LatheConsole, Vec<String>), String> {
        let o = LatheStore::open(state, &desc)?;
        let mut desc = desc;
        for (ch, t) in o.tools.iter().enumerate() {
            if let (Some(t), Some(c)) = (t, desc.channels.get_mut(ch)) {
                c.tools = t.clone();
            }
        }
        let n = desc.channels.len();
        let settings = crate::settings::MachineSettings::lathe_channel(&desc, 0)
            .ok_or("the machine has no channel")?;
        let programs: Vec<(String, String)> = o
            .programs
            .iter()
            .map(|p| (p.name.clone(), p.text.clone()))
            .collect();
        // #500–#999 and the work offsets as the stores kept them (docs/lathe-gcode.md "What a
        // channel keeps").
        let kept: Vec<_> = (0..n)
            .map(|ch| {
                let stored = o.params.get(ch).map_or(&[][..], |v| &v[..]);
                super::gcode::Kept::from_stores(&desc, ch, stored)
            })
            .collect();
        let info = glue::recording_info(&desc, &programs, &kept);
        let recorder = Recording::start(record, None, &settings, &info)?;
        let stale = o
            .counter
            .counts
            .iter()
            .any(|&c| c > 0 && c < o.counter.target);
        // The editor's line in each program, from the pointer the stores kept.
        let edit_line = o
            .programs
            .iter()
            .zip(&o.pointers)
            .map(|(p, &at)| 1 + p.text.chars().take(at).filter(|&c| c == '\n').count())
            .collect();
        let (book, damaged) = Book::open(o.store.dir());
        let mut warnings = o.warnings;
        warnings.extend(damaged);
        let front = Front::new(OpMode::Auto, 10);
        // The machine from power-on: every tool post where the position memory kept it (at
        // the top of its travel at the first opening), the spindles stopped, on the front
        // end's clock.
        let (posts, pos, posts_said) = posts::Posts::restore(&desc, o.posts);
        let cycle = glue::Cycle::idle(
            &desc,
            &kept,
            glue::KernelSpec {
                pos,
                clock,
                now_ns: 0,
                feed_override: front.feed_override,
                switches: Default::default(),
                op_mode: front.op,
                look_ns: WAIT_LOOK_NS,
                sink: recorder.sink(),
            },
        )?;
        let mut c = LatheConsole {
            programs: o.programs,
            edit_line,
            pointers: o.pointers.clone(),
            mdi: o.mdi.clone(),
            counter: o.counter,
            store: o.store,
            desc,
            shell: Shell::new(front, book, recorder, n),
            sel: 0,
            ofs_cell: (0, ofs::FIRST_COLUMN),
            rel: vec![[0, 0]; n],
            jog: (o.jogs.iter())
                .map(|&(feed, rapid)| crate::console::manual::JogChoice { feed, rapid })
                .collect(),
            last_part_ns: None,
            alarm_at: vec![None; n],
            msg_of: None,
            cycle,
            rows,
            cols,
            last_display: Vec::new(),
            now_ns: 0,
            stale_counts: stale,
            kept,
            interrupt: None,
            search: None,
            posts,
        };
        // Each channel's jog feed as the stores kept it, on its machine from power-on.
        for ch in 0..n {
            if c.jog[ch] != Default::default() {
                let s = c.channel_settings(ch);
                let f = c.jog[ch].rate(s.jog_mm_min, s.rapid_mm_min);
                c.cycle.manual(ch, Command::JogFeed(f));
            }
        }
        if let Some(w) = warnings.first() {
            // Damage found at open is the first thing the operator sees (docs/lathe.md).
            c.shell.front.message = match warnings.len() {
                1 => w.clone(),
                n => format!("{w} (and {} more warnings)", n - 1),
            };
        } else if let Some(said) = posts_said {
            c.shell.front.message = said;
        } else if stale {
            c.shell.front.message = format!(
                "last batch stopped at {} of {}: START begins anew",
                c.counter
                    .counts
                    .iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join("/"),
                c.counter.target
            );
        }
        c.after();
        Ok((c, warnings))
    }

    /// Opens the console with a launcher's configuration: its state directory, display size,
    /// recording, clock and the interrupt a script's waits ask (`ConsoleConfig::interrupt`).
    pub fn open_config(
        desc: LatheDesc,
        cfg: &crate::console::ConsoleConfig,
    ) -> Result<(LatheConsole, Vec<String>), String> {
        let (mut c, w) = LatheConsole::open_on(
            desc,
            &cfg.state_dir,
            (cfg.rows, cfg.cols),
            cfg.record.as_deref(),
            cfg.clock,
        )?;
        c.set_interrupt(cfg.interrupt);
        Ok((c, w))
    }

    /// The machine description.
    pub fn desc(&self) -> &LatheDesc {
        &self.desc
    }

    /// The selected channel, 0-based.
    pub fn selected(&self) -> usize {
        self.sel
    }

    /// Each channel's program as the console holds it (stored before it is taken).
    pub fn programs(&self) -> &[Program] {
        &self.programs
    }

    /// Channel `ch`'s editor pointer, characters from its program's start.
    pub fn pointer(&self, ch: usize) -> usize {
        self.pointers.get(ch).copied().unwrap_or(0)
    }

    /// Channel `ch`'s MDI buffer: the lines typed and not yet run.
    pub fn mdi_lines(&self, ch: usize) -> &[String] {
        self.mdi.get(ch).map_or(&[], |l| &l[..])
    }

    /// The part counter.
    pub fn counter(&self) -> &Counter {
        &self.counter
    }

    /// The last cycle's time, ns (the title's `CYCLE`): from the part delivered before it, or
    /// from the batch's START for its first part, to the part delivered at the unloader.
    pub fn cycle_time_ns(&self) -> Option<u64> {
        Some(self.shell.book.counters.last_cycle_ns).filter(|&t| t > 0)
    }

    /// The counters kept across restarts: parts delivered in every batch, the last cycle's
    /// time and the run time.
    pub fn counters(&self) -> crate::store::history::Counters {
        self.shell.book.counters
    }

    /// The message line: the operator message while it lives ([`MsgLife`]), else what the
    /// machine is doing that needs the operator (E-STOP, a feed hold), derived from the
    /// channels' states.
    pub fn message(&self) -> &str {
        self.message_with(&self.chan_views())
    }

    /// The message line as the plasma shows it (MTConnect's `message`, as the centre's
    /// `Console::message_line`).
    pub fn message_line(&self) -> String {
        self.message_line_of(&self.chan_views())
    }

    /// The message line as the plasma shows it: the newest program message that lives until
    /// acknowledged (the centre's words), then what [`LatheConsole::message`] says.
    fn message_line_of(&self, chans: &[ChanView]) -> String {
        let said = self.message_with(chans);
        match crate::console::state::unacknowledged_line(&self.shell.book.unacknowledged) {
            Some(m) if said.is_empty() => m,
            Some(m) => format!("{m} / {said}"),
            None => said.to_string(),
        }
    }

    /// The program messages on the message line until acknowledged (newest last).
    pub fn unacknowledged(&self) -> &[String] {
        &self.shell.book.unacknowledged
    }

    fn message_with(&self, chans: &[ChanView]) -> &str {
        let any = |w: &[&str]| chans.iter().any(|c| w.contains(&c.state.as_str()));
        // (The lathe says nothing for the life of a block.)
        let lives = (self.shell.front).message_lives(self.now_ns, view::runs(chans), |_| false);
        if lives && !self.shell.front.message.is_empty() {
            &self.shell.front.message
        } else if any(&["ESTOP"]) {
            ESTOP_NOTE
        } else if any(&["HOLD"]) {
            HOLD_NOTE
        } else if any(&["STOP"]) && self.shell.front.op == OpMode::Single {
            "SINGLE BLOCK: a channel stops after each block; START runs the next"
        } else if any(&["STOP"]) {
            "STOP: a program stop; START goes on"
        } else if any(&["HOME"]) {
            "HOME: a tool post makes its reference return, X first, then Z (the summary line says which)"
        } else if any(&["JOG"]) {
            "JOG: a tool post moves by hand (the summary line says which)"
        } else {
            ""
        }
    }

    /// Says `text` on the message line for as long as `life`.
    fn say(&mut self, text: impl Into<String>, life: MsgLife) {
        self.shell.front.say(text, life, self.now_ns)
    }

    /// The rapid override and the spindle override, percent (the centre's switches).
    pub fn rapid_spindle(&self) -> (u32, u32) {
        let sw = self.machine_switches();
        (sw.rapid_override, sw.spindle_override)
    }

    /// Whether DRY RUN is on (the centre's switch, on every channel).
    pub fn dry_run(&self) -> bool {
        self.machine_switches().dry_run
    }

    /// The centre's switches the lathe takes (rapid and spindle override, DRY RUN, MACHINE
    /// LOCK), as the machine has them: every channel's are the same (`switches::turn` turns
    /// them on every channel or on none), so channel 1's.
    pub fn machine_switches(&self) -> crate::record::Switches {
        (self.cycle.channels().first()).map_or_else(Default::default, |c| c.status.switches)
    }

    /// The operation selector's position.
    pub fn mode(&self) -> OpMode {
        self.shell.front.op
    }

    /// The page up over the mode display (`Page::Mode`: none).
    pub fn page(&self) -> Page {
        self.shell.shown.page
    }

    /// The alarm and message history, oldest first (the MSG page shows it newest first).
    pub fn history(&self) -> &[crate::store::history::Entry] {
        self.shell.book.log.history.entries()
    }

    /// The feed override, percent.
    pub fn feed_override(&self) -> u32 {
        self.shell.front.feed_override
    }

    /// The switches: OPTIONAL STOP, BLOCK DELETE.
    pub fn switches(&self) -> (bool, bool) {
        (
            self.shell.front.switches.optional_stop,
            self.shell.front.switches.block_delete,
        )
    }

    /// Channel `ch`'s program as START would read it ([`LatheConsole::program_to_run`]: the
    /// MDI lines of the selected channel in MDI): a stored program in the dialect it was
    /// stored in, from the state the channel keeps, the tool post where its axes stand, with
    /// the panel's switches (the window's backplot draws it, docs/window.md "The lathe
    /// window"). None: no such channel.
    pub fn programmed(
        &self,
        ch: usize,
    ) -> Option<Result<Vec<crate::block::Statement>, crate::block::TranslateError>> {
        let (text, mdi) = self.program_to_run(ch)?;
        let at = self.cycle.axes().get(ch).copied();
        let opts = self.read_options();
        Some(if mdi {
            let dir = (self.cycle.channels().get(ch)).map_or(0, |c| c.status.spindle_dir);
            glue::preview(&self.desc, (ch, &text), &opts, &self.kept, at, Some(dir))
        } else {
            let desc = self.stored_dialects();
            glue::preview(&desc, (ch, &text), &opts, &self.kept, at, None)
        })
    }

    /// What START runs on channel `ch` in the selector's position, as the centre's backplot
    /// draws the MDI buffer in MDI: the selected channel's MDI lines in MDI (those of the MDI
    /// run under way once START has cleared the buffer), and whether they are; else its stored
    /// program. None: no such channel.
    pub fn program_to_run(&self, ch: usize) -> Option<(String, bool)> {
        let p = self.programs.get(ch)?;
        if self.shell.front.op != OpMode::Mdi || ch != self.sel {
            return Some((p.text.clone(), false));
        }
        let running = Some(&self.cycle).filter(|c| !c.is_over() && c.mdi);
        let lines = match (self.mdi.get(ch), running.and_then(|c| c.mdi_lines(ch))) {
            (Some(l), Some(run)) if l.is_empty() => run,
            (Some(l), _) => &l[..],
            (None, _) => &[],
        };
        Some((lines.join("\n") + "\n", true))
    }

    /// How START reads the channels' programs: with the panel's BLOCK DELETE and OPTIONAL
    /// STOP, and the part counter as Fanuc's #3901/#3902 read it.
    fn read_options(&self) -> super::gcode::ReadOptions {
        super::gcode::ReadOptions {
            block_delete: self.shell.front.switches.block_delete,
            optional_stop: self.shell.front.switches.optional_stop,
            parts: Some(super::gcode::Parts::new(
                &self.counter.counts,
                self.counter.target,
            )),
        }
    }

    /// The machine with each channel's dialect the one its stored program was stored in (one
    /// stored before programs kept theirs: its channel's), as START reads the programs.
    fn stored_dialects(&self) -> LatheDesc {
        let mut desc = self.desc.clone();
        for (c, p) in desc.channels.iter_mut().zip(&self.programs) {
            c.dialect = p.dialect.or(c.dialect);
        }
        desc
    }

    /// The machine's kernel and what is loaded into it: a cycle, an MDI program or nothing
    /// (`Cycle::loaded`); its state as the kernel published it.
    pub fn cycle(&self) -> &glue::Cycle {
        &self.cycle
    }

    /// Machine time, ns.
    pub fn machine_ns(&self) -> u64 {
        self.now_ns
    }

    /// Each channel's tool tip, pulses [X radius, Z], and the work in its spindle, as the last
    /// tick left them (the window's backplot samples these after every step).
    pub fn tips(&self) -> Vec<([i64; 2], Option<u32>)> {
        let mut works = vec![None; self.desc.channels.len()];
        self.cycle.works(&mut works);
        self.cycle.tool_posts().into_iter().zip(works).collect()
    }

    /// Nothing moves or can move without the operator: nothing loaded, or every channel finished,
    /// stopped, waiting on a stopped channel, faulted or in E-STOP (what a script's `wait`
    /// waits for), as the last tick found it: after START, tick before asking.
    pub fn at_rest(&self) -> bool {
        self.cycle.at_rest()
    }

    /// The machine stands still at feed override 0 with a feed move in progress: a wait
    /// would never end (the centre's `wait` says so too).
    pub fn stalled(&self) -> bool {
        self.cycle.stalled()
    }

    /// Each channel's jog feed chosen on POS, mm/min (None: the machine's), and rapid jog.
    pub fn jogs(&self) -> Vec<(Option<f64>, bool)> {
        self.jog.iter().map(|j| (j.feed, j.rapid)).collect()
    }

    /// The settings channel `ch`'s machine runs on (its rapid rate, its jog feed...).
    pub(crate) fn channel_settings(&self, ch: usize) -> crate::settings::MachineSettings {
        crate::settings::MachineSettings::lathe_channel(&self.desc, ch).unwrap_or_default()
    }

    /// The plasma display's size: (rows, columns).
    pub fn display_size(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// The line being typed on the data keys (the centre's `PanelView::entry`).
    pub fn entry(&self) -> &str {
        &self.shell.front.entry
    }

    /// A key of the terminal, on the one key map (`events::map_key`), with the centre's
    /// rules: STOP, RESET and E-STOP act on every screen; with the help screen up any other
    /// key closes it and acts (F8 closes it); while the terminal is too small every other key
    /// is ignored and the notice says which; a key that does nothing here says so.
    pub fn press(&mut self, k: novanc_panel::Key) {
        crate::console::keys::press(self, k);
        // What the key said, and the faults it found, in the history (`after` puts what the
        // machine said).
        self.log_book();
    }

    /// The MSG, MACRO and MODAL page keys (Ctrl+E, Ctrl+U, Ctrl+G: the centre's) and, with MSG
    /// or MACRO up,
    /// the cursor keys that scroll the history or move the variable cursor (the arrows move no
    /// tool post under a page, as on the centre): whether `k` was one of them.
    fn page_key(&mut self, k: novanc_panel::Key) -> bool {
        let page = match crate::console::pages::page_of_key(k) {
            Some(p @ (Page::Msg | Page::Macro | Page::Modal | Page::Pos)) => p,
            _ if crate::console::keys::is_cursor_key(k) => {
                if self.shell.shown.page == Page::Ofs {
                    let tools = &self.desc.channels[self.sel].tools;
                    self.ofs_cell = ofs::cursor_moved(tools, self.ofs_cell, k);
                    return true;
                }
                let n = self.shell.book.log.history.entries().len();
                return (self.shell.shown).cursor(k, n, self.rows.saturating_sub(6));
            }
            // (Tab with a value typed on a page is +INPUT on every machine: `keys::tab_adds`.)
            _ => return false,
        };
        // The page key again leaves it (the centre's rule); the line being typed stays.
        self.shell.shown.key(page);
        self.shell.front.y_output = None;
        true
    }

    /// Puts in the history (the MSG page, the recording's `/foxglove/log`) the message shown,
    /// if it is new, and each channel's fault or alarm when it comes: the centre's rule. A
    /// history that cannot be saved is said after the message, never in its place.
    fn log_book(&mut self) {
        let t = self.now_ns;
        // Slot 0: the E-STOP, once, the machine's (the centre's entry: `ALARM EMERGENCY STOP:
        // ...`), from the press or the kernel's state, until RESET releases it. Then one slot
        // a channel: its FAULT or ALARM (`book::Log::alarms`, the centre's rule).
        let mut now = vec![None; 1 + self.desc.channels.len()];
        if self.estop() {
            let file = self.programs.get(self.sel).map_or("", |p| p.name.as_str());
            now[0] = Some((ESTOP_NOTE.to_string(), (t, file, 0)));
        }
        let c = &self.cycle;
        let chans = if c.any_state(&["FAULT", "ALARM"]) {
            c.views(&self.desc, &self.programs, &self.counter.counts)
        } else {
            Vec::new()
        };
        for (i, ch) in chans.iter().enumerate() {
            if matches!(ch.state.as_str(), "FAULT" | "ALARM") && i + 1 < now.len() {
                let text = format!("CH{} {}: {}", i + 1, ch.state, ch.note);
                let when = self.alarm_at.get(i).copied().flatten().unwrap_or(t);
                now[i + 1] = Some((text, (when, ch.program.as_str(), ch.line)));
            }
        }
        let of = self.msg_of.take().unwrap_or(self.sel);
        let file = self.programs.get(of).map_or("", |p| p.name.as_str());
        let chans: Vec<_> = (self.cycle.channels().iter())
            .map(|c| c.status.clone())
            .collect();
        let at = (t, file, 0);
        self.shell.log(&now, at, &chans);
    }

    /// One event of the panel grammar (the centre's and the lathe's alike), by every
    /// console's one dispatch (`crate::console::keys::handle`): recorded on `/panel/event`; a
    /// script's waits run in machine time as the centre's ([`LatheConsole::wait_error`] says
    /// why one could not end); a refusal, and an event the lathe has no use for, says why on
    /// the message line and changes nothing.
    pub fn handle(&mut self, ev: PanelEvent) {
        crate::console::keys::handle(self, ev)
    }

    /// An operator action, recorded already (by `handle` as its event, or by `press` as the
    /// key when the key took the typed line: FAULT's reason, TARGET's number, so that a replay
    /// of the recording takes the same line off the entry line). The caller takes the
    /// machine's state after it (`after`).
    fn act(&mut self, ev: PanelEvent) {
        if let Err(e) = events::takes(&ev) {
            self.shell.front.message = e;
            return;
        }
        crate::console::side::words(self, ev);
    }

    /// The lathe's own words of the panel grammar (`Side::own_word`): OFS, the channel
    /// selector, FAULT and TARGET (`events::takes` let only these through besides the words
    /// every console means alike).
    fn own_word(&mut self, ev: PanelEvent) {
        match ev {
            PanelEvent::OfsMode => {
                self.shell.shown.page = Page::Ofs;
                self.shell.front.y_output = None;
                // The line being typed stays, as under every page key (stop 41).
                self.shell.front.message = format!(
                    "OFS: CH{}'s tools; a value, Enter INPUT, Tab +INPUT (or T1 X.. Z.. R.. P..)",
                    self.sel + 1
                );
            }
            PanelEvent::Home => self.home(),
            PanelEvent::Channel(c) if c < self.desc.channels.len() => self.select(c),
            PanelEvent::Channel(c) => {
                self.shell.front.message = format!("there is no channel {}", c + 1)
            }
            PanelEvent::Fault(ch, why) if ch < self.desc.channels.len() && self.cycle.loaded() => {
                // Filed in the history under the faulted channel's program.
                self.msg_of = Some(ch);
                self.shell.front.message = match self.cycle.fault(ch, &why) {
                    Ok(()) => format!("CH{} FAULT: {why}", ch + 1),
                    Err(e) => format!("fault CH{}: {e}", ch + 1),
                };
            }
            PanelEvent::Fault(ch, _) => {
                self.shell.front.message = format!("fault CH{}: no cycle runs", ch + 1)
            }
            PanelEvent::Target(n) => {
                self.shell.front.message = match self.set_target(n) {
                    Ok(said) | Err(said) => said,
                }
            }
            PanelEvent::Tape(path) => {
                self.shell.front.message = match self.program_read(&path) {
                    Ok(said) => said,
                    Err(e) => format!(
                        "PROGRAM READ refused: {e}; CH{}'s program unchanged",
                        self.sel + 1
                    ),
                }
            }
            _ => {}
        }
    }

    /// The lathe's part of a script's wait (`crate::console::wait`): runs the machine as
    /// [`LatheConsole::run_for`] does, and says how it ended.
    fn run_wait(&mut self, w: WaitFor) -> Reached {
        let (limit_ns, until) = match w {
            WaitFor::Idle => (WAIT_LIMIT_NS, RunUntil::Rest),
            WaitFor::Block(n) => (WAIT_LIMIT_NS, RunUntil::Block(self.sel, n)),
            WaitFor::Ms(ms) => (ms.saturating_mul(1_000_000), RunUntil::Time),
        };
        let stop = self.interrupt.unwrap_or(|| false);
        let used = self.run_for(limit_ns, until, stop);
        if stop() {
            Reached::Interrupted
        } else if until == RunUntil::Time {
            Reached::Time
        } else if self.stalled() {
            Reached::Stalled
        } else if used >= limit_ns && !self.at_rest() {
            Reached::Limit
        } else {
            Reached::Idle
        }
    }

    /// Why the last script wait could not end, if it could not.
    pub fn wait_error(&self) -> Option<&str> {
        self.shell.front.wait_error.as_deref()
    }

    /// Asked between the steps of a script's wait: a true answer ends it early (a stop
    /// signal), as the centre's `ConsoleConfig::interrupt`.
    pub fn set_interrupt(&mut self, f: Option<fn() -> bool>) {
        if let Some(f) = f {
            self.cycle.set_interrupt(f);
        }
        self.interrupt = f;
    }

    fn select(&mut self, c: usize) {
        if c != self.sel {
            // The channel selector turned lets the last channel's jog go.
            crate::console::manual::release(self, false);
        }
        self.sel = c;
        self.shell.front.y_output = None;
        // The line being typed stays (nothing typed is lost): it is the next channel's now, as
        // the display and the entry box say. Before stop 47 the turn cleared it.
        self.shell.front.message = format!("channel {} {}", c + 1, self.desc.channels[c].name);
    }

    /// Sets the part target. It is taken only once stored: a target that cannot be stored
    /// (a full disk) leaves the old one, on the display and in the machine. During a cycle the
    /// machine takes it for the batch under way; with the cycle over (the batch done, as START
    /// then says: `set a new target (Alt+n) to run again`) it begins a new batch from 0, as
    /// with nothing loaded. Until stop 52 the finished cycle refused it (`a channel has already
    /// finished`), and only a RESET first let the operator run again.
    fn set_target(&mut self, n: u32) -> Result<String, String> {
        let mut next = self.counter.clone();
        next.target = n;
        if self.cycle.loaded() && !self.cycle.mdi && self.cycle.is_over() {
            // The finished cycle is cleared, as RESET clears it: its counts are the old batch's
            // (an MDI run that has ended stays: its spindle may turn on into the next).
            self.clear_cycle();
        }
        if self.cycle.loaded() && !self.cycle.is_over() {
            let c = &mut self.cycle;
            let most = self.counter.counts.iter().copied().max().unwrap_or(0);
            if n < most.max(1) {
                return Err(format!("target {n}: a channel has already finished {most}"));
            }
            // A cycle that goes on with a batch makes one part at least: a target the parts
            // made before it already reach would be passed (found by the random operator
            // sequences, byhand seed 335: 2 of 1).
            let before = c.made_before();
            if !c.searching() && before > 0 && n <= before {
                return Err(format!(
                    "target {n}: {before} made before this cycle, which makes one more (RESET it first)"
                ));
            }
            // A SEARCH's part runs once whatever the batch's target (the machine's stays 1);
            // it makes one more part.
            if c.searching() && n < most + 1 {
                return Err(format!(
                    "target {n}: the part SEARCH runs makes {}",
                    most + 1
                ));
            }
            let old = self.counter.target;
            let told = (!c.searching()).then(|| c.set_target(c.machine_target(n)));
            told.unwrap_or(Ok(()))?;
            if let Err(e) = self.store.save_counter(&next) {
                // The machine took `n` just now, so it takes its old target back.
                if !c.searching() {
                    let _ = c.set_target(c.machine_target(old));
                }
                return Err(format!("{e}: the target is not changed"));
            }
        } else {
            next.counts.iter_mut().for_each(|c| *c = 0);
            if let Err(e) = self.store.save_counter(&next) {
                return Err(format!("{e}: the target is not changed"));
            }
            self.stale_counts = false;
        }
        self.counter = next;
        Ok(format!("part target {n}"))
    }

    fn start(&mut self) {
        let op = self.shell.front.op;
        if op == OpMode::Data {
            // The centre's words: START runs in AUTO, MDI and SINGLE BLOCK only (before stop
            // 42 a lathe cycle held by a mode turn resumed on START in any mode); the lathe
            // has no tape reader to start.
            self.shell.front.message = format!(
                "START refused in {}: use AUTO, MDI or SINGLE BLOCK",
                op.name()
            );
            return;
        }
        // The reference return owed since a restart: AUTO runs every channel, MDI the
        // selected one.
        let runs: Vec<usize> = match op {
            OpMode::Mdi => vec![self.sel],
            _ => (0..self.desc.channels.len()).collect(),
        };
        if let Some(why) = self.home_refusal(runs.iter().copied()) {
            self.shell.front.message = why;
            return;
        }
        // A SEARCH point (AUTO or SINGLE BLOCK) loads its own run, whatever stands loaded at
        // rest (a cycle RESET at its start); with a run loaded, or a tool post moving, START
        // is refused and the point kept: it is the operator's, never dropped unsaid.
        let auto = matches!(op, OpMode::Auto | OpMode::Single);
        if let (Some(n), true, false) = (self.search, auto, self.at_rest_unloaded()) {
            self.shell.front.message = format!(
                "START refused: a run is loaded or a tool post moves; SEARCH line {n} is kept (wait for the move to end, or RESET the run)"
            );
            return;
        }
        // After a SEARCH's part (ended, or RESET), the batch goes on from the program's top:
        // a new load, whatever the SEARCH run left loaded.
        let search =
            auto && (self.search.is_some() || self.cycle.counts_on()) && self.at_rest_unloaded();
        {
            let c = &mut self.cycle;
            if !c.is_over() && !search {
                if c.loaded() && c.mdi != (op == OpMode::Mdi) {
                    // A cycle held in MDI mode, or an MDI run in AUTO: the machine's words.
                    let kind = if c.mdi { "MDI" } else { "AUTO" };
                    self.shell.front.message =
                        format!("START refused: an {kind} run is loaded; press RESET first");
                    return;
                }
                if !c.mdi {
                    c.set_single_block(op == OpMode::Single);
                }
                if let Err(e) = self.before_motion(&runs) {
                    self.shell.front.message = format!("START refused: {e}");
                    return;
                }
                let c = &mut self.cycle;
                match c.start() {
                    Ok(()) => self.say("START", MsgLife::WhileRunning),
                    Err(e) => self.shell.front.message = e,
                }
                return;
            }
        }
        match op {
            OpMode::Data | OpMode::Continuous | OpMode::Handle | OpMode::Step => {}
            OpMode::Auto | OpMode::Single => {
                if self
                    .counter
                    .counts
                    .iter()
                    .all(|&c| c >= self.counter.target)
                    && !self.stale_counts
                {
                    self.shell.front.message = format!(
                        "the target of {} parts is reached: set a new target (Alt+n) to run again",
                        self.counter.target
                    );
                    return;
                }
                let texts: Vec<(String, String)> = self
                    .programs
                    .iter()
                    .map(|p| (p.name.clone(), p.text.clone()))
                    .collect();
                self.begin(texts, &runs);
            }
            OpMode::Mdi => {
                if self.mdi[self.sel].is_empty() {
                    self.shell.front.message =
                        "MDI: the buffer is empty; type lines, then START".into();
                    return;
                }
                let mut texts = vec![(String::new(), String::new()); self.desc.channels.len()];
                texts[self.sel] = (
                    format!("MDI CH{}", self.sel + 1),
                    self.mdi[self.sel].join("\n") + "\n",
                );
                self.begin(texts, &runs);
            }
        }
    }

    /// Loads and starts `texts`: every channel's cycle, or (`runs` the selected channel
    /// alone, in MDI) its MDI program.
    fn begin(&mut self, texts: Vec<(String, String)>, runs: &[usize]) {
        let mdi = self.shell.front.op == OpMode::Mdi;
        let opts = self.read_options();
        // A SEARCH runs one part, which goes on with the batch (its count is kept); after it,
        // the batch goes on from the program's top to its target.
        let search = self.search.filter(|_| !mdi);
        let resume = !mdi && search.is_none() && self.cycle.counts_on();
        let most = self.counter.counts.iter().copied().max().unwrap_or(0);
        let target = if mdi || search.is_some() {
            1
        } else if resume {
            self.counter.target.saturating_sub(most).max(1)
        } else {
            self.counter.target
        };
        // Each stored program is read in the dialect it was stored in; MDI in the channel's.
        let desc = if mdi {
            self.desc.clone()
        } else {
            self.stored_dialects()
        };
        let spec = self.spec(texts, opts, target, mdi.then_some(self.sel));
        if let Err(e) = self.cycle.load(&desc, spec, &mut self.kept) {
            self.shell.front.message = e;
            return;
        }
        // A new cycle: its channels' faults are new to the history.
        self.shell.book.log.forget_alarms();
        if search.is_some() || resume {
            self.cycle
                .count_from(self.counter.counts.clone(), search.is_some());
            self.search = None;
        } else if !mdi {
            let mut next = self.counter.clone();
            next.counts.iter_mut().for_each(|c| *c = 0);
            if let Err(e) = self.store.save_counter(&next) {
                // Loaded and not started: nothing is left loaded either.
                self.clear_cycle();
                self.shell.front.message = format!("{e}: the cycle does not start");
                return;
            }
            self.counter = next;
            self.stale_counts = false;
            // A new batch: its first cycle is timed from this START.
            self.last_part_ns = None;
        }
        if let Err(e) = self.before_motion(runs) {
            self.clear_cycle();
            self.shell.front.message = format!("START refused: {e}");
            return;
        }
        if let Err(e) = self.cycle.start() {
            self.shell.front.message = e;
            return;
        }
        // The buffer is cleared once it runs; if the clear cannot be stored, the buffer stays
        // (in memory as on disk) and the message says so.
        let cleared = if mdi {
            self.set_mdi(Vec::new())
        } else {
            Ok(())
        };
        let said = match (mdi, &cleared) {
            (false, _) if search.is_some() => {
                format!("cycle start from line {}: one part", search.unwrap_or(0))
            }
            (false, _) => "cycle start".into(),
            (true, Ok(())) => format!("MDI CH{} runs", self.sel + 1),
            (true, Err(e)) => format!("MDI CH{} runs; {e}: the buffer is kept", self.sel + 1),
        };
        let cleared = cleared.is_ok();
        // The store's refusal lives as a message of its own would.
        let life = if cleared {
            MsgLife::WhileRunning
        } else {
            MsgLife::NextKey
        };
        self.say(said, life);
        self.keep_params();
    }

    /// What a load into the kernel takes (`Cycle::load`): the programs `texts` read with
    /// `opts`, to the part target, of one channel's MDI (`mdi`) or every channel (None), with
    /// the panel's switches (no texts and `mdi` Some: nothing loaded, manual moves).
    fn spec(
        &self,
        texts: Vec<(String, String)>,
        opts: super::gcode::ReadOptions,
        target: u32,
        mdi: Option<usize>,
    ) -> glue::CycleSpec {
        glue::CycleSpec {
            manual: texts.is_empty(),
            texts: if texts.is_empty() {
                vec![(String::new(), String::new()); self.desc.channels.len()]
            } else {
                texts
            },
            opts,
            target,
            mdi,
            single_block: mdi.is_none() && self.shell.front.op == OpMode::Single,
            op_mode: self.shell.front.op,
            search: self.search.filter(|_| mdi.is_none()),
        }
    }

    /// Nothing loaded any more: every channel's RESET (its spindle and coolant stop, its
    /// alarm clears), and the kernel stands with no program, for manual moves.
    fn clear_cycle(&mut self) {
        let _ = self.cycle.command_all(Command::Reset);
        let spec = self.spec(Vec::new(), Default::default(), 1, Some(self.sel));
        if let Err(e) = self.cycle.load(&self.desc, spec, &mut self.kept) {
            self.shell.front.message = e;
        }
        self.shell.book.log.forget_alarms();
    }

    /// Sets the selected channel's MDI buffer, stored first (the stores keep it across a
    /// restart, as the centre's): whether it was stored. Not stored, the buffer stays as it
    /// was and the message line says why.
    fn set_mdi(&mut self, lines: Vec<String>) -> Result<(), String> {
        if lines != self.mdi[self.sel] {
            self.store.save_mdi(self.sel, &lines)?;
            self.mdi[self.sel] = lines;
        }
        Ok(())
    }

    /// Journals the channels' #500–#999 that their reads changed (the reads the cycle just
    /// started: once per START, not once per part). A value the stores refuse is said on the
    /// message line and left out.
    fn keep_params(&mut self) {
        for (ch, k) in self.kept.iter().enumerate() {
            let kept: std::collections::HashMap<usize, f64> =
                self.store.params(ch).into_iter().collect();
            let changed: Vec<(usize, f64)> = crate::store::lathe::kept_params()
                .filter_map(|n| {
                    let v = *k.params.params.get(n)?;
                    let was = kept.get(&n).copied().unwrap_or(0.0);
                    let now = if v.is_nan() { 0.0 } else { v };
                    ((now - was).abs() > 0.5e-6).then_some((n, v))
                })
                .collect();
            if changed.is_empty() {
                continue;
            }
            if self.store.save_params(ch, &changed).is_err() {
                for &p in &changed {
                    if let Err(e) = self.store.save_params(ch, &[p]) {
                        self.shell.front.say(
                            format!("NOT KEPT: CH{} #{}: {e}", ch + 1, p.0),
                            MsgLife::NextKey,
                            self.now_ns,
                        );
                    }
                }
            }
        }
    }

    /// Saves the counters (`counters`) atomically; a failure is said on the message line.
    fn save_counters(&mut self) {
        if let Err(e) = self.shell.book.counters.save(self.store.dir()) {
            self.shell.front.say_failure(&e, self.now_ns);
        }
    }

    /// E-STOP is in force: pressed and not yet released by RESET (the kernel's state).
    fn estop(&self) -> bool {
        self.cycle.channels().iter().any(|s| s.status.estop)
    }

    /// The lathe's RESET (`crate::console::relay::reset`): the selected channel's, or after an
    /// E-STOP every channel's; what it did.
    fn reset(&mut self) -> String {
        // RESET returns the channel's interpreter state to power-on (after an E-STOP, every
        // channel's): docs/lathe-gcode.md "What a channel keeps". A SEARCH point is let go.
        self.search = None;
        let all = self.estop();
        // It acknowledges that channel's program messages (after an E-STOP, every one), as a
        // Fanuc's RESET clears its path's operator message (the centre's rule).
        let of = format!("CH{} ", self.sel + 1);
        self.shell
            .book
            .unacknowledged
            .retain(|m| !all && !m.starts_with(&of));
        for (ch, k) in self.kept.iter_mut().enumerate() {
            if all || ch == self.sel {
                k.reset(&self.desc, ch);
            }
        }
        if !self.cycle.loaded() {
            // Nothing loaded: the channel's RESET (after an E-STOP, the machine's) stops its
            // spindle and coolant, and clears its MDI buffer.
            let ch = (!all).then_some(self.sel);
            let _ = self.cycle.reset_channels(ch);
            // It says what it did, as the centre's RESET does (before stop 46 it said only
            // `RESET CH1`, after an E-STOP too, which released every channel).
            return match self.set_mdi(Vec::new()) {
                Ok(()) if all => {
                    "RESET: E-STOP released; every channel's spindle and coolant stopped".into()
                }
                Ok(()) => format!(
                    "RESET CH{}: spindle and coolant stopped, MDI buffer cleared",
                    self.sel + 1
                ),
                Err(e) => e,
            };
        }
        if self.cycle.is_over() {
            // With the cycle cleared nothing shows a spindle: every one stops, and the coolant.
            self.clear_cycle();
            return "RESET: the cycle is cleared".into();
        }
        self.cycle.reset(self.sel)
    }

    /// Virtual time: `w` is told every channel's state at every change of one of them, in
    /// this cycle and every later one (`PulseCore::set_watch`); None stops it.
    pub fn set_watch(&mut self, w: Option<crate::pulse_core::Watcher>) {
        self.cycle.set_watch(w);
    }

    /// Advances the machine by `ns` of machine time (whole ticks), records what happened and
    /// stores the part counter as it counts.
    pub fn tick(&mut self, ns: u64) {
        crate::console::manual::keep(self);
        self.step(ns, RunUntil::Time);
    }

    /// [`LatheConsole::tick`], ending early when `until` holds (`Cycle::run`): whether it
    /// does (never for [`RunUntil::Time`]).
    pub fn step(&mut self, ns: u64, until: RunUntil) -> bool {
        let running = self.cycle.loaded() && !self.cycle.is_over();
        let reached = self.cycle.run(ns, until);
        let t = self.cycle.now_ns();
        if running {
            // The run hours: machine time with a cycle or an MDI run under way.
            self.shell.book.counters.ran(t.saturating_sub(self.now_ns));
        }
        self.now_ns = t;
        self.after();
        reached
    }

    /// Runs the machine for `limit_ns` of machine time, recording as it goes (a script's
    /// `wait ms T`), or only until `until` holds: [`RunUntil::Rest`], every channel at rest
    /// (finished, stopped, waiting on a stopped channel, faulted or in E-STOP: a script's
    /// `wait`); [`RunUntil::Block`], the block's start (a script's `wait block N`). In virtual
    /// time it is one run of the kernel in its thread, as the centre's wait is: the kernel
    /// ends it at feed override 0 with a feed move standing still (`Kernel::stalled`) and, in
    /// slices, on a stop signal (`set_interrupt`); what it did (parts, messages at the starts
    /// of their blocks, alarms) comes back with its machine times. Before stop 40 the console
    /// stepped it 10 ms at a time to see those. `stop` is asked first. Returns the machine
    /// time given.
    pub fn run_for(&mut self, limit_ns: u64, until: RunUntil, stop: impl Fn() -> bool) -> u64 {
        if (until == RunUntil::Rest && self.at_rest()) || stop() {
            // Nothing to wait for: no machine time passes (the centre's wait).
            return 0;
        }
        let t0 = self.now_ns;
        crate::console::manual::keep(self);
        self.step(limit_ns, until);
        self.now_ns - t0
    }

    /// Takes what the machine reported: records it, counts parts into the stores.
    fn after(&mut self) {
        let mut counted = false;
        {
            let c = &mut self.cycle;
            // The kernel's events are in the recording already (the pulse core writes them);
            // taken here so that they do not pile up in the core for the console's lifetime.
            // A part delivered times the cycle: from the part before it, the first from START.
            for e in c.take_events() {
                use crate::pulse_core::KernelEvent as E;
                match e {
                    E::Part { ch, t, .. } if ch == self.desc.unloader && !c.mdi => {
                        let from = self.last_part_ns.unwrap_or(c.started_ns());
                        self.shell.book.counters.made(t.saturating_sub(from));
                        self.last_part_ns = Some(t);
                        counted = true;
                    }
                    // When a channel's fault or alarm came, for the history (a wait runs the
                    // kernel for as long as it lasts, and the console looks at its end).
                    E::Fault { ch, t, .. } | E::Alarm { ch, t, .. } => {
                        if let Some(a) = self.alarm_at.get_mut(ch) {
                            *a = Some(t);
                        }
                    }
                    _ => {}
                }
            }
            if counted {
                self.save_counters();
            }
            let c = &mut self.cycle;
            let counts = c.counts(&self.counter.counts);
            if !c.mdi && counts != self.counter.counts {
                self.counter.counts = counts;
                if let Err(e) = self.store.save_counter(&self.counter) {
                    self.shell.front.say_failure(&e, self.now_ns);
                }
            }
            if let Some(m) = c.take_message() {
                self.shell.front.say(m, MsgLife::NextKey, self.now_ns);
            }
            // The programs' messages: on the message line (the last one), each in the
            // recording's log as the centre's (docs/recording.md `/foxglove/log`).
            let mut failed = None;
            for (ch, t, text) in c.take_said() {
                let file = if c.mdi {
                    format!("MDI CH{}", ch + 1)
                } else {
                    self.programs
                        .get(ch)
                        .map(|p| p.name.clone())
                        .unwrap_or_default()
                };
                // Each one in the history at the time its block started, however many a step
                // gives (the centre's rule).
                let at = (t, file.as_str(), 0);
                // `CH1 MSG: text`: the kind is the word after the channel.
                let kind = text.split([' ', ':']).nth(1).unwrap_or("").to_string();
                let r = self.shell.program_message(at, &kind, text);
                failed = failed.or(r.err());
            }
            if let Some(e) = failed {
                self.shell.front.say_failure(&e, self.now_ns);
                self.shell.book.log.shown(&self.shell.front.message);
            }
        }
        self.track_posts();
        self.log_book();
        self.record_display();
    }

    fn record_display(&mut self) {
        if !self.shell.recorder.on() {
            return;
        }
        let d = self.view().display;
        (self.shell.recorder).frame(&mut self.last_display, d, self.now_ns);
    }

    fn chan_views(&self) -> Vec<ChanView> {
        let mut v = self
            .cycle
            .views(&self.desc, &self.programs, &self.counter.counts);
        for (ch, (c, k)) in v.iter_mut().zip(&self.kept).enumerate() {
            if c.system.is_none() {
                // No program of this channel runs: what its next MDI run starts from.
                c.set_datum(&self.desc, &k.datum(&self.desc, ch));
            }
        }
        v
    }

    /// The frame as text, as `show` prints it (the mill console's `frame_text`): the title,
    /// the summary lines, then the plasma display.
    pub fn frame_text(&self) -> String {
        let v = self.view();
        let mut lines = vec![v.title];
        lines.extend(v.summary);
        lines.extend(v.display);
        lines
            .iter()
            .map(|l| l.trim_end())
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// The view to draw.
    pub fn view(&self) -> LatheView {
        let chans = self.chan_views();
        let w = self.cols;
        let summary = chans
            .iter()
            .enumerate()
            .map(|(i, c)| view::summary_line(i, c, self.counter.target, i == self.sel, w))
            .collect();
        let c = &chans[self.sel];
        // The listing's room is what the message leaves (`view::plasma`'s rule).
        let message = self.message_line_of(&chans);
        let said = crate::console::display::wrap(&message, w, (self.rows / 3).max(1)).len();
        let listing = self.listing(c, self.rows.saturating_sub(4 + said));
        let mode = match self.shell.shown.page {
            Page::Mode => self.shell.front.op.word(),
            p => p.label(),
        };
        // The switches are the machine's, every channel's: on the title line, where the
        // plasma's 40 columns do not cut them off.
        let sw = self.machine_switches();
        let feed = match self.shell.front.feed_override {
            100 => String::new(),
            f => format!("  F{f}%"),
        };
        let switches = feed + &crate::console::switch_words(&self.shell.front.switches, &sw);
        let display = view::plasma(
            self.sel,
            c,
            mode,
            self.desc.pulse_mm,
            &listing,
            &message,
            &self.shell.front.entry,
            self.rows,
            w,
        );
        let done: u32 = self
            .counter
            .counts
            .get(self.desc.unloader)
            .copied()
            .unwrap_or(0);
        let cycle = self.cycle_time_ns().map_or(String::new(), |t| {
            format!("  CYCLE {:.3} s", t as f64 * 1e-9)
        });
        LatheView {
            title: format!(
                "{} {} CHANNELS  PARTS {}/{}  {:.3} s{cycle}{switches}",
                self.desc.name.to_uppercase(),
                self.desc.channels.len(),
                done,
                self.counter.target,
                self.now_ns as f64 * 1e-9
            ),
            summary,
            display,
            channels: chans,
            selected: self.sel,
            help: self.shell.front.help_shown(),
            machine_ns: self.now_ns,
        }
    }

    /// Ends the session and closes the recording: the recording's summary line for the
    /// operator, if one was made; `Err` when the file could not be finished (a disk error).
    /// The centre's `Console::finish`.
    pub fn finish(self) -> Result<Option<String>, String> {
        self.close(None)
    }

    /// [`LatheConsole::finish`]; `interrupted` names a stop signal, if one cut the session
    /// short: the machine is then stopped first (E-STOP), and the recording says `complete:
    /// false` and why. The centre's `Console::close`: one shape for both (before stop 46 the
    /// lathe's returned `Option<Result<..>>` under the centre's `finish` name).
    pub fn close(mut self, interrupted: Option<&str>) -> Result<Option<String>, String> {
        if interrupted.is_some() {
            self.stop_machine();
        }
        // The run time since the last part (a failure to save is not the recording's).
        self.save_counters();
        // The kernel's thread holds a sink: it ends first, so everything it sent is written.
        let LatheConsole { cycle, shell, .. } = self;
        drop(cycle);
        shell.recorder.finish()
    }

    /// E-STOP for a stop signal, as the centre's: every channel stops at once, spindles too,
    /// and one tick of machine time records it (`/nc/state` ESTOP, `EMERGENCY STOP` in the
    /// history). Not an operator action: no `/panel/event`. Until stop 48 only a cycle still
    /// running was stopped: a spindle an MDI run had left turning was recorded turning to the
    /// end, with no E-STOP.
    fn stop_machine(&mut self) {
        self.cycle.estop();
        let tick = self.desc.tick_ns.max(1);
        self.tick(tick);
    }
}

/// The lathe's part of the one key pipeline (`crate::console::keys::press`): its key map, its
/// pages' and editor's keys, and its own keys (the channel selector, FAULT, TARGET).
impl crate::console::keys::Keyed for LatheConsole {
    const HELP_PAGES: u8 = 1;
    fn action(&self, k: Key) -> Action {
        events::map_key(k)
    }
    fn page_keys(&mut self, k: Key, action: &Action) -> bool {
        if self.page_key(k) {
            return true;
        }
        if *action != Action::Event(PanelEvent::OfsMode) || self.shell.shown.page != Page::Ofs {
            return false;
        }
        // The page key again: back to the mode's display (the centre's rule).
        self.shell.shown.page = Page::Mode;
        self.shell.front.message = format!("{} mode", self.shell.front.op.word());
        true
    }
    fn own_key(&mut self, k: Key, action: &Action) -> bool {
        match action {
            Action::NextChannel => {
                self.record_key(k);
                self.select((self.sel + 1) % self.desc.channels.len());
                self.after();
            }
            Action::Fault => {
                self.record_key(k);
                let why = std::mem::take(&mut self.shell.front.entry);
                let why = if why.trim().is_empty() {
                    "operator".to_string()
                } else {
                    why.trim().to_lowercase()
                };
                self.act(PanelEvent::Fault(self.sel, why));
                self.after();
            }
            Action::Tape => {
                // The typed line names the file; recorded as the key, which takes the line (a
                // replay types the same path), as on the centre.
                self.record_key(k);
                let path = std::mem::take(&mut self.shell.front.entry);
                let path = path.trim();
                if path.is_empty() {
                    self.shell.front.message =
                        "PROGRAM READ: type the program file's path first, then the tape key"
                            .into();
                } else {
                    self.act(PanelEvent::Tape(path.into()));
                }
                self.after();
            }
            Action::Punch => {
                self.record_key(k);
                self.shell.front.message = self.punch();
                self.after();
            }
            Action::Target => {
                self.record_key(k);
                let typed = std::mem::take(&mut self.shell.front.entry);
                match typed.trim().parse::<u32>() {
                    Ok(n) if (1..=999_999).contains(&n) => {
                        self.act(PanelEvent::Target(n));
                        self.after();
                    }
                    _ => {
                        self.shell.front.message = format!("target: type the part count (1 to 999999), then Alt+n; '{typed}' is not one");
                        self.shell.front.entry = typed;
                    }
                }
            }
            _ => return false,
        }
        true
    }
}

/// The lathe's machine side for the one console's rules (`crate::console::side`): its
/// channels, every one told a switch at once.
impl crate::console::side::Side for LatheConsole {
    fn shell(&mut self) -> &mut Shell {
        &mut self.shell
    }
    fn shell_ref(&self) -> &Shell {
        &self.shell
    }
    fn machine_switches(&self) -> crate::record::Switches {
        LatheConsole::machine_switches(self)
    }
    fn refresh(&mut self) {
        self.after();
    }
    fn command_all(&mut self, cmd: Command) {
        // Every channel takes it or says why not, in its notice (`channels`).
        let _ = self.cycle.command_all(cmd);
    }
    fn channels(&self) -> Vec<crate::pulse_core::Status> {
        (self.cycle.channels().iter())
            .map(|c| c.status.clone())
            .collect()
    }
    fn axis_settings(&self) -> crate::settings::MachineSettings {
        self.channel_settings(self.sel)
    }
    fn channel_runs(&self) -> bool {
        self.cycle.any_state(&["RUN"])
    }
    fn selected(&self) -> usize {
        self.sel
    }
    fn manual_target(
        &mut self,
        axis: crate::panel_model::Axis,
        what: &str,
    ) -> Result<crate::console::manual::ManualTarget, String> {
        LatheConsole::manual_target(self, axis, what)
    }
    fn tell(&mut self, ch: usize, cmd: Command) {
        // A refusal is in the channel's notice (`Side::channels`).
        self.cycle.manual(ch, cmd);
    }
    fn clock(&self) -> crate::pulse_core::ClockMode {
        self.cycle.clock()
    }
    fn now_ns(&self) -> u64 {
        self.now_ns
    }
    fn settle(&mut self, ch: usize) {
        LatheConsole::settle(self, ch)
    }
    fn run_wait(&mut self, w: WaitFor) -> crate::pulse_core::Reached {
        LatheConsole::run_wait(self, w)
    }
    fn act(&mut self, ev: PanelEvent) {
        LatheConsole::act(self, ev)
    }
    fn takes_keys(&self, _to: crate::console::entry::To) -> Result<(), String> {
        // Every position has a use for a line: TARGET and FAULT take it in any mode.
        Ok(())
    }
    fn enter_line(
        &mut self,
        to: crate::console::entry::To,
        line: &str,
        add: bool,
    ) -> Result<(), String> {
        LatheConsole::enter_line(self, to, line, add)
    }
    fn cursor_command(
        &self,
        k: novanc_panel::Key,
    ) -> Option<(&'static str, Result<String, String>)> {
        LatheConsole::cursor_command(self, k)
    }
    fn edit(&mut self, command: &str) -> Result<String, String> {
        LatheConsole::edit(self, command).map(|()| String::new())
    }
    fn reset(&mut self) -> String {
        LatheConsole::reset(self)
    }
    fn start(&mut self) {
        LatheConsole::start(self)
    }
    fn own_word(&mut self, ev: PanelEvent) {
        LatheConsole::own_word(self, ev)
    }
    fn turned(&mut self, _was: OpMode) -> bool {
        let m = self.shell.front.op;
        let c = &mut self.cycle;
        if !c.mdi && !c.is_over() && m == OpMode::Single {
            // SINGLE BLOCK turned on in a cycle: the block each channel is in is its last
            // until START. Turned off, the blocks started in SINGLE BLOCK still end and
            // wait: START in AUTO runs on (the centre's rule, docs/panel.md).
            c.set_single_block(true);
        }
        // Every channel's machine is on the same panel (`/nc/state`).
        c.set_modes(m);
        false
    }
}
