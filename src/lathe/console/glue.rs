//! The lathe console's cycle: the channel programs read, the one kernel running them in the
//! pulse core thread (`PulseCore::spawn_kernel`, docs/pulse-core.md "Channels"), and what it
//! publishes turned into the display's views and the operator's messages.
//!
//! The kernel runs in its own thread: in real time (the terminal, the window) it keeps its
//! NCBR clock whatever the screen does, and E-STOP acts from that thread; in virtual time
//! (scripts, `novanc run`, tests) machine time passes only in [`Cycle::run`]. Every view is
//! derived from the kernel's published state (its snapshot), never from the console's memory
//! of what it asked for.

use super::view::ChanView;
use crate::lathe::desc::LatheDesc;
use crate::lathe::gcode::{read_kept, Kept, ReadOptions};
use crate::pulse_core::{
    ChannelStatus, ClockMode, Command, Kernel, KernelEvent, PulseCore, Reached,
};
use crate::record::EventSink;
use crate::store::lathe::Program;

/// Where each channel's tool post starts the first cycle: the top of its travel (X and Z at
/// their maxima), clear of any work, where the reader takes a program to start. Later cycles
/// start where the last one left it.
pub fn home(desc: &LatheDesc, ch: usize) -> [i64; 2] {
    crate::lathe::gcode::home(desc, ch)
}

/// What [`Cycle::run`] runs until, besides the machine time it is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunUntil {
    /// Only the time.
    Time,
    /// Every channel at rest ([`Cycle::at_rest`]): `novanc run`.
    Rest,
    /// Block `.1` of channel `.0`'s program starts (its sequence number, the N of the
    /// listing, as the centre's `wait block N`), or every channel is at rest. In virtual
    /// time every channel then stands at the end of the NCBR tick it started in
    /// (`Kernel::run_until`); in real time its start is seen in the kernel's published state.
    Block(usize, u32),
}

/// A cycle (AUTO: every channel to the part target) or an MDI run of one channel.
pub struct Cycle {
    core: PulseCore,
    /// True for an MDI run of channel `only`.
    pub mdi: bool,
    /// Made for manual moves (STEP) of channel `only`, with nothing run.
    manual: bool,
    only: usize,
    started_ns: u64,
    message: Option<String>,
    /// The source lines of each channel's program, for the block texts.
    lines: Vec<Vec<String>>,
    /// Each program's first block's line.
    first: Vec<u32>,
    /// The kernel's last published state, per channel, and its machine time.
    snap: Vec<ChannelStatus>,
    t: u64,
    clock: ClockMode,
    /// Each channel's messages (`(msg,)`, `(print,)`...): the block they come before, by its
    /// number (`u32::MAX`: after the last block), and the text shown.
    msgs: Vec<Vec<(u32, String)>>,
    /// Each channel's next message to show and the block it last saw executing (a lower one:
    /// the program runs again, for the next part).
    msg_at: Vec<(usize, u32)>,
    /// The messages shown since the console last took them: channel and text.
    said: Vec<(usize, u64, String)>,
    /// The kernel's events taken and not yet given to the console (the block starts it
    /// marked are taken here: they say the messages).
    events: Vec<KernelEvent>,
    /// What each channel's program was read from, to read it again with revised tools
    /// ([`Cycle::reread`]); None for a channel with no program of the cycle.
    reread: Vec<Option<Reread>>,
    /// How the programs were read, and the machine they were read for.
    opts: ReadOptions,
    desc: LatheDesc,
    /// Each channel's work system and program zero by block ([`zero_table`]).
    zeros: Vec<ZeroTable>,
    /// The parts each channel had made before this cycle, added to the kernel's (a SEARCH's
    /// part goes on with the batch: [`Cycle::count_from`]); empty: none.
    base: Vec<u32>,
    /// The cycle is a SEARCH's one part.
    search_part: bool,
}

/// What a channel's blocks are measured from on the display as they run: from each block
/// sequence number on (ascending), the work system, the zero and the tool's offsets
/// (`lathe::gcode::Datum`).
pub type ZeroTable = Vec<(u32, crate::lathe::gcode::Datum)>;

/// The zero table of a program as read: each statement's datum from its first block on, a
/// change where it changes.
fn zero_table(
    statements: &[crate::block::Statement],
    zeros: &[crate::lathe::gcode::Datum],
) -> ZeroTable {
    let mut t: ZeroTable = Vec::new();
    for (s, &d) in statements.iter().zip(zeros) {
        let Some(b) = s.blocks.first() else {
            continue;
        };
        if t.last().is_none_or(|l| l.1 != d) {
            t.push((b.seq, d));
        }
    }
    t
}

/// A channel's program as the cycle read it: its name and text, the state and place its read
/// began from.
#[derive(Clone, Debug)]
struct Reread {
    name: String,
    text: String,
    from: Kept,
    at: Option<[i64; 2]>,
}

/// Every channel's program of a cycle as read ([`read_cycle`]): the kernel's statements,
/// each program's source lines and first line, each channel's state after its read (None: not
/// read), its messages, what to read again with revised tools, and the blocks whose starts
/// the kernel reports (the messages' blocks, each program's first and last).
struct ReadCycle {
    progs: Vec<Vec<crate::block::Statement>>,
    zeros: Vec<ZeroTable>,
    lines: Vec<Vec<String>>,
    first: Vec<u32>,
    after: Vec<Option<Kept>>,
    msgs: Vec<Vec<(u32, String)>>,
    rereads: Vec<Option<Reread>>,
    starts: Vec<Vec<u32>>,
}

/// What is loaded into the kernel ([`Cycle::load`]), built once by whoever starts it (the
/// console's START, RESET and opening, `novanc run`).
#[derive(Clone, Debug)]
pub struct CycleSpec {
    /// Each channel's program: name and text (an MDI run: the run channel's lines, empty
    /// texts for the others).
    pub texts: Vec<(String, String)>,
    /// How the programs are read (BLOCK DELETE, OPTIONAL STOP).
    pub opts: ReadOptions,
    /// The part target.
    pub target: u32,
    /// An MDI run of this channel (None: AUTO, every channel to the part target).
    pub mdi: Option<usize>,
    /// Nothing loaded: the kernel stands with no program, for manual moves (STEP, CONTINUOUS,
    /// HANDLE).
    pub manual: bool,
    /// SINGLE BLOCK: every channel stops after each block until the next START.
    pub single_block: bool,
    /// The operation selector's position, as `/nc/state` records it (`op_mode`).
    pub op_mode: crate::panel_model::OpMode,
    /// SEARCH (docs/lathe.md "SEARCH"): channel 1's program runs from the first block at or
    /// after this source line, after the restore blocks ([`restart_from`]), for one part.
    pub search: Option<u32>,
}

/// The machine a kernel is made for ([`Cycle::idle`]), as it stands when the kernel is made.
#[derive(Clone, Debug)]
pub struct KernelSpec {
    /// Where each channel's tool post stands, pulses [X radius, Z] (the spindles stand
    /// still, the coolant off).
    pub pos: Vec<[i64; 2]>,
    /// The kernel's clock: real time (a terminal, the window) or virtual (scripts, `run`).
    pub clock: ClockMode,
    /// The machine time the kernel's clock begins at, ns (one time base for a console's
    /// recording).
    pub now_ns: u64,
    /// Feed override, percent, of every channel's feed moves.
    pub feed_override: u32,
    /// The centre's switches on every channel: rapid override (F0 (0), 25, 50, 100), spindle
    /// override (50 to 120) and DRY RUN (feed moves at the jog feed times the feed override;
    /// thread passes and taps stay geared to their spindle).
    pub switches: crate::record::Switches,
    /// The operation selector's position, as `/nc/state` records it (`op_mode`).
    pub op_mode: crate::panel_model::OpMode,
    /// How late a wait may end past what it waits for, ns (`Kernel::set_look_ns`; 0: the
    /// kernel's thousand NCBR periods, `novanc run`'s, which ends with the machine at rest).
    pub look_ns: u64,
    /// Where the kernel records.
    pub sink: Option<EventSink>,
}

/// The state channel `ch`'s program is read from at START: what its last program or MDI left
/// (docs/lathe-gcode.md "What a channel keeps"); for a cycle (not `mdi`) the program zero at
/// the work's, since a G92 (or G50) shift an MDI run or the last cycle left does not move the
/// next cycle unasked (docs/lathe-gcode.md "G50 (system A)"; MDI runs keep it until RESET or
/// G92.1); the spindle as the machine turns it (`dir`: 1 forward, -1 reverse; none or 0:
/// stopped).
fn start_state(desc: &LatheDesc, kept: &[Kept], ch: usize, mdi: bool, dir: Option<i8>) -> Kept {
    let mut from = kept
        .get(ch)
        .cloned()
        .unwrap_or_else(|| Kept::power_on(desc, ch, None));
    if !mdi {
        from.modal.origin = [0.0, 0.0];
        from.modal.work = 0;
    }
    from.modal.dir = match dir.unwrap_or(0) {
        1 => 3,
        -1 => 4,
        _ => 5,
    };
    from
}

/// Channel `ch`'s program `text` of `desc` read as START reads it (`read_cycle`): from the
/// state `kept` says, the tool post at `at`, with `opts`; a cycle's program with the spindle
/// stopped, an MDI program (`mdi`: the spindle's direction) with the spindle as it turns. What
/// the window's backplot draws as the programmed path (docs/window.md "The lathe window").
pub fn preview(
    desc: &LatheDesc,
    (ch, text): (usize, &str),
    opts: &ReadOptions,
    kept: &[Kept],
    at: Option<[i64; 2]>,
    mdi: Option<i8>,
) -> Result<Vec<crate::block::Statement>, crate::block::TranslateError> {
    let from = start_state(desc, kept, ch, mdi.is_some(), mdi);
    read_kept(text, desc, ch, opts, None, &from, at).map(|r| r.statements)
}

/// Every channel's program of a cycle of `desc` as `spec` describes it, each read from the
/// state `kept` says, the tool post where `pos` says, the spindle turning as `dirs` says (1
/// forward, -1 reverse, 0 stopped). Any error names the channel, the
/// program and the line.
fn read_cycle(
    desc: &LatheDesc,
    spec: &CycleSpec,
    kept: &[Kept],
    pos: &[[i64; 2]],
    dirs: &[i8],
) -> Result<ReadCycle, String> {
    let mut progs = Vec::new();
    let mut zeros = Vec::new();
    let mut lines = Vec::new();
    let mut after = Vec::new();
    let mut msgs = Vec::new();
    let mut rereads = Vec::new();
    for (ch, (name, text)) in spec.texts.iter().enumerate() {
        if spec.manual || spec.mdi.is_some_and(|only| ch != only) {
            // The other channels stand still with no program during an MDI run (and every
            // channel with no program loaded).
            progs.push(Vec::new());
            zeros.push(Vec::new());
            lines.push(Vec::new());
            after.push(None);
            msgs.push(Vec::new());
            rereads.push(None);
            continue;
        }
        let from = start_state(desc, kept, ch, spec.mdi.is_some(), dirs.get(ch).copied());
        let r = read_kept(
            text,
            desc,
            ch,
            &spec.opts,
            None,
            &from,
            pos.get(ch).copied(),
        )
        .map_err(|e| format!("CH{} {name}:{e}", ch + 1))?;
        rereads.push(spec.mdi.is_none().then(|| Reread {
            name: name.clone(),
            text: text.clone(),
            from,
            at: pos.get(ch).copied(),
        }));
        let mut p = r.statements;
        let mut datums = r.zeros;
        if spec.mdi.is_none() && p.is_empty() {
            return Err(format!("CH{} {name}: the program is empty", ch + 1));
        }
        // SEARCH: from the statement it found, after the restore blocks; the messages of the
        // lines before it are not said.
        let mut skipped = 0;
        if let Some(line) = spec.search.filter(|_| ch == 0 && spec.mdi.is_none()) {
            let at = pos.get(ch).copied().unwrap_or_else(|| home(desc, ch));
            let (k, restore) =
                restart_from(&p, line, at).map_err(|e| format!("CH{} {name}: {e}", ch + 1))?;
            let keep = datums.get(k).copied();
            let mut tail = p.split_off(k);
            let mut d = datums.split_off(k);
            p = vec![restore];
            p.append(&mut tail);
            datums = keep.into_iter().chain(d.drain(..)).collect();
            skipped = k;
            // The tool revised during it is taken from the next START: this read is not
            // the program's from its start.
            if let Some(last) = rereads.last_mut() {
                *last = None;
            }
        }
        // A message is shown when the first block of the statement after it begins (after a
        // SEARCH, the statement's place is one on: the restore statement stands first).
        let seq_of = |i: usize| {
            p.iter()
                .skip(if skipped > 0 { i + 1 - skipped } else { i })
                .find_map(|s| s.blocks.first())
                .map_or(u32::MAX, |b| b.seq)
        };
        msgs.push(
            r.messages
                .iter()
                .filter(|m| m.before >= skipped)
                .map(|m| {
                    (
                        seq_of(m.before),
                        format!("CH{} {}: {}", ch + 1, m.kind, m.text),
                    )
                })
                .collect(),
        );
        after.push(Some(r.kept));
        zeros.push(zero_table(&p, &datums));
        progs.push(p);
        lines.push(text.lines().map(str::to_string).collect());
    }
    // The blocks each channel says a message at, and its first and last blocks (a program
    // that starts again for the next part says what it had left first), marked in its
    // machine: their starts come back as `KernelEvent::BlockStart`, each with its machine
    // time, however long the kernel ran at a time.
    let starts: Vec<Vec<u32>> = progs
        .iter()
        .zip(&msgs)
        .map(|(p, m)| {
            if m.is_empty() {
                return Vec::new();
            }
            let first = p.iter().find_map(|s| s.blocks.first()).map(|b| b.seq);
            let last = p.iter().rev().find_map(|s| s.blocks.last()).map(|b| b.seq);
            m.iter()
                .map(|x| x.0)
                .filter(|&s| s != u32::MAX)
                .chain(first)
                .chain(last)
                .collect()
        })
        .collect();
    // Where each program starts: the pointer of a channel not yet running (or RESET).
    let first = progs
        .iter()
        .map(|st| st.iter().find(|s| s.line > 0).map_or(0, |s| s.line))
        .collect();
    Ok(ReadCycle {
        progs,
        zeros,
        lines,
        first,
        after,
        msgs,
        rereads,
        starts,
    })
}

/// SEARCH's restart of a program read whole, `p` (docs/lathe.md "SEARCH"): the index of the
/// first statement at or after source line `line` that makes a block, and the statement that
/// restores before it what the program had set by then and takes the tool there from `at`
/// (pulses [X radius, Z], where the tool post stands): the tool in place, the spindle, the
/// coolant (each the last block the program made for it before that statement), then
/// rapids, first out in X (never in), then along Z, then in X to where that statement
/// starts. Its blocks are numbered 0, as the centre's SEARCH restore (`wait block 0` is
/// not the lathe's: its blocks count from 1), on line 0.
pub(crate) fn restart_from(
    p: &[crate::block::Statement],
    line: u32,
    at: [i64; 2],
) -> Result<(usize, crate::block::Statement), String> {
    use crate::block::{Block, Motion};
    let k = p
        .iter()
        .position(|s| s.line >= line && !s.blocks.is_empty())
        .ok_or_else(|| format!("SEARCH: the program makes no block at or after line {line}"))?;
    let (mut tool, mut spindle) = (None, None);
    let (mut mist, mut flood) = (false, false);
    let mut start = [at[0], at[1]];
    for b in p[..k].iter().flat_map(|s| &s.blocks) {
        if b.t.is_some() {
            tool = Some(b.clone());
        }
        match b.m {
            Some(3..=5) => spindle = Some(b.clone()),
            Some(7) => mist = true,
            Some(8) => flood = true,
            Some(9) => (mist, flood) = (false, false),
            _ => {}
        }
        start = [b.end[0], b.end[2]];
    }
    let here = |b: Block| Block {
        seq: 0,
        stmt: 0,
        end: [at[0], 0, at[1]].into(),
        delta: Default::default(),
        ..b
    };
    let css = spindle.as_ref().and_then(|b| b.css);
    let mut blocks: Vec<Block> = tool.into_iter().chain(spindle).map(here).collect();
    for (on, m) in [(mist, 7), (flood, 8)] {
        if on {
            blocks.push(here(crate::lathe::gcode::out::m(m)));
        }
    }
    // Out in X first (never in), then along Z, then in X.
    let mut from = at;
    for to in [
        [from[0].max(start[0]), from[1]],
        [from[0].max(start[0]), start[1]],
        start,
    ] {
        if to != from {
            blocks.push(Block {
                motion: Motion::Rapid,
                end: [to[0], 0, to[1]].into(),
                delta: [to[0] - from[0], 0, to[1] - from[1]].into(),
                css,
                ..Block::aux(0, 0, [to[0], 0, to[1]])
            });
            from = to;
        }
    }
    Ok((
        k,
        crate::block::Statement {
            line: 0,
            text: format!("(SEARCH restore: line {})", p[k].line),
            blocks,
        },
    ))
}

/// The kernel of `desc` with no program loaded, its machines as `spec` describes them, each
/// turret at the tool `kept` says.
fn make_kernel(desc: &LatheDesc, spec: &KernelSpec, kept: &[Kept]) -> Result<Kernel, String> {
    let (chans, _) = desc.kernel_channels(vec![Vec::new(); desc.channels.len()])?;
    let mut k = Kernel::new(chans, None, 1)?;
    k.set_look_ns(spec.look_ns);
    for (ch, p) in spec.pos.iter().enumerate().take(k.channels()) {
        k.set_position(ch, [p[0], 0, p[1]])?;
    }
    let sw = spec.switches;
    for ch in 0..k.channels() {
        k.command(ch, Command::Override(spec.feed_override))?;
        if sw.rapid_override != 100 {
            k.command(ch, Command::RapidOverride(sw.rapid_override))?;
        }
        if sw.spindle_override != 100 {
            k.command(ch, Command::SpindleOverride(sw.spindle_override))?;
        }
        if sw.dry_run {
            k.command(ch, Command::DryRun(true))?;
        }
        if sw.machine_lock {
            k.command(ch, Command::MachineLock(true))?;
        }
    }
    // Each turret stands at the tool its reader keeps, if it keeps one (every load sets it
    // again); else where it is.
    for (ch, kept) in kept.iter().enumerate().take(k.channels()) {
        if let Some((t, _)) = kept.tool {
            k.command(ch, Command::SetTool(Some(t)))?;
        }
    }
    // One time base for a console's cycles (and its recording): the kernel's clock goes on
    // from the machine time given.
    k.set_clock(spec.now_ns)?;
    Ok(k)
}

/// What a recording of `desc` says before its first message (docs/recording.md,
/// "Attachments"): the machine's name, and each channel's name, program (`programs[i]`: name
/// and text), description and tool post.
pub fn recording_info(
    desc: &LatheDesc,
    programs: &[(String, String)],
    kept: &[Kept],
) -> crate::record::RecordingInfo {
    let channels = desc
        .channels
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let (program_name, program_text) = programs.get(i).cloned().unwrap_or_default();
            Some(crate::record::ChannelInfo {
                name: c.name.clone(),
                program_name,
                program_text,
                settings: crate::settings::MachineSettings::lathe_channel(desc, i)?,
                tools: c
                    .tools
                    .iter()
                    .map(|t| (t.number, t.radius, t.tip, t.offset))
                    .collect(),
                work_offsets: kept.get(i).map_or([[0.0; 2]; 6], |k| {
                    crate::lathe::gcode::work_offsets(&k.params.params).map(|[z, x]| [x, z])
                }),
            })
        })
        .collect();
    crate::record::RecordingInfo {
        machine_name: desc.name.clone(),
        channels,
        ..Default::default()
    }
}

impl Cycle {
    /// The kernel of `desc`, with no program loaded, in the pulse core thread on `spec.clock`
    /// (a console's from its opening to its close, `novanc run`'s): each tool post, spindle,
    /// override and switch as `spec` says, each turret at the tool `kept` says, recording into
    /// `spec.sink`. Each cycle, MDI program or manual move is loaded into it
    /// ([`Cycle::load`]) and started ([`Cycle::start`]).
    pub fn idle(desc: &LatheDesc, kept: &[Kept], spec: KernelSpec) -> Result<Cycle, String> {
        let k = make_kernel(desc, &spec, kept)?;
        let started_ns = k.now();
        let n = k.channels();
        let clock = spec.clock;
        let core = PulseCore::spawn_kernel(k, clock, spec.sink);
        let mut c = Cycle {
            core,
            mdi: true,
            manual: true,
            only: 0,
            started_ns,
            message: None,
            lines: vec![Vec::new(); n],
            first: vec![0; n],
            snap: Vec::new(),
            t: 0,
            clock,
            msgs: vec![Vec::new(); n],
            msg_at: vec![(0, 0); n],
            said: Vec::new(),
            events: Vec::new(),
            reread: vec![None; n],
            opts: ReadOptions::default(),
            desc: desc.clone(),
            zeros: vec![Vec::new(); n],
            base: Vec::new(),
            search_part: false,
        };
        c.set_modes(spec.op_mode);
        c.refresh();
        Ok(c)
    }

    /// Loads a new cycle (AUTO), an MDI program or nothing (`spec.manual`: the machine stands
    /// for manual moves) into this cycle's kernel, which goes on with every tool post, spindle,
    /// turret, override and switch as they are, on the same clock and recording (a real
    /// control loads a program into the machine it has). Each channel's program is read from
    /// the state `kept` says, and its tool post where the kernel has it. A cycle (AUTO) starts
    /// with every spindle and coolant stopped: its programs work the chucks and command the
    /// spindles around them themselves (a bar must not be received into a spindle an MDI run
    /// left turning); an MDI run goes on with them. Nothing starts: [`Cycle::start`] does.
    /// Refused, nothing changed, while a channel runs or moves, a channel to run has an alarm
    /// in force (RESET first, as on the centre), or a read fails (the error names the
    /// channel, program and line); once loaded, `kept` holds the state each read left.
    pub fn load(
        &mut self,
        desc: &LatheDesc,
        spec: CycleSpec,
        kept: &mut [Kept],
    ) -> Result<(), String> {
        self.refresh();
        // The programs are read from where the axes stand (after a run under MACHINE LOCK the
        // program position is still the program's: the next run starts from the axes).
        let pos = self.axes();
        let auto = spec.mdi.is_none() && !spec.manual;
        // The spindles as they turn (the commanded direction: under G96 no rpm is programmed,
        // and a spindle coasting down after M05 is stopped); a cycle stops them.
        let dirs: Vec<i8> = if auto {
            Vec::new()
        } else {
            self.snap.iter().map(|c| c.status.spindle_dir).collect()
        };
        let mut read = read_cycle(desc, &spec, kept, &pos, &dirs)?;
        let flow = auto.then(|| desc.work_flow());
        let progs = std::mem::take(&mut read.progs);
        let starts = std::mem::take(&mut read.starts);
        let tools: Vec<Option<u32>> = kept.iter().map(|k| k.tool.map(|t| t.0)).collect();
        let to_run: Vec<usize> = match (spec.manual, spec.mdi) {
            (true, _) => Vec::new(),
            (false, Some(ch)) => vec![ch],
            (false, None) => (0..progs.len()).collect(),
        };
        let (target, single) = (spec.target, spec.single_block);
        self.core.edit_kernel(move |k| {
            for &ch in &to_run {
                if k.machine(ch).is_some_and(|m| m.alarm().is_some()) {
                    return Err(format!(
                        "CH{} START refused: alarm in force, press RESET",
                        ch + 1
                    ));
                }
            }
            k.load(progs, flow, target, starts)?;
            for (ch, t) in tools.into_iter().enumerate().take(k.channels()) {
                if auto {
                    if let Some(m) = k.machine_mut(ch) {
                        m.preset_spindle(0, 0, None, 0.0, (false, false));
                    }
                }
                // Each turret at the tool its reader keeps; after a RESET, which cancels the
                // reader's offsets, where it stands (it does not turn at RESET).
                if t.is_some() {
                    k.command(ch, Command::SetTool(t))?;
                }
                k.command(ch, Command::SingleBlock(single))?;
            }
            Ok(())
        })?;
        for (k, a) in kept.iter_mut().zip(read.after) {
            if let Some(a) = a {
                *k = a;
            }
        }
        let n = read.msgs.len();
        self.mdi = spec.mdi.is_some();
        self.manual = spec.manual;
        self.only = spec.mdi.unwrap_or(0);
        self.message = None;
        self.lines = read.lines;
        self.first = read.first;
        self.msgs = read.msgs;
        self.zeros = read.zeros;
        self.base = Vec::new();
        self.search_part = false;
        self.msg_at = vec![(0, 0); n];
        self.reread = read.rereads;
        self.opts = spec.opts;
        self.desc = desc.clone();
        self.set_modes(spec.op_mode);
        self.refresh();
        self.started_ns = self.t;
        Ok(())
    }

    /// Whether a cycle or an MDI program is loaded (false: the kernel stands with no program,
    /// for manual moves).
    pub fn loaded(&self) -> bool {
        !self.manual
    }

    /// The kernel's clock, chosen when it was made: real time or virtual.
    pub fn clock(&self) -> ClockMode {
        self.clock
    }

    /// Each channel's tool post as the kernel last published it, pulses [X radius, Z]: its
    /// program position, what the screen shows.
    pub fn tool_posts(&self) -> Vec<[i64; 2]> {
        self.snap
            .iter()
            .map(|c| [c.status.pos[0], c.status.pos[2]])
            .collect()
    }

    /// Where each channel's axes stand, pulses [X radius, Z]: the tool post, except after a
    /// run under MACHINE LOCK, whose program position the axes did not follow.
    pub fn axes(&self) -> Vec<[i64; 2]> {
        self.snap
            .iter()
            .map(|c| [c.status.machine_pos[0], c.status.machine_pos[2]])
            .collect()
    }

    /// The operation selector turned to `op`: every channel's `/nc/state` records it as
    /// `op_mode`, and `data_mode` `MEMORY` (the lathe has no data-processing selector; its
    /// programs run from memory, Fanuc's MEM, as `novanc run` records the centre's).
    pub fn set_modes(&mut self, op: crate::panel_model::OpMode) {
        self.core.set_panel_modes(op.word(), "MEMORY");
    }

    /// Virtual time: `w` is told every channel's state at every change of one of them
    /// (`PulseCore::set_watch`); None stops it.
    pub fn set_watch(&mut self, w: Option<crate::pulse_core::Watcher>) {
        self.core.set_watch(w);
    }

    /// Asked between the slices of machine time a wait runs in the kernel's thread: a true
    /// answer ends the wait early (a stop signal), as on the centre.
    pub fn set_interrupt(&mut self, f: fn() -> bool) {
        self.core.set_interrupt(f);
    }

    /// Takes the kernel's latest published state; an alarm that appeared since is the
    /// operator's message.
    pub(super) fn refresh(&mut self) {
        let snap = self.core.channels();
        for (i, s) in snap.iter().enumerate() {
            let before = self.snap.get(i).and_then(|b| b.status.alarm.clone());
            // An E-STOP is the machine's, not a channel's: the console says it, and puts it in
            // the history once, as the centre does (before stop 40 it was said as the last
            // channel's alarm, `CH3 ALARM: EMERGENCY STOP`).
            if s.status.estop {
                continue;
            }
            if let (Some(a), None) = (&s.status.alarm, before) {
                let line = s.status.executing.as_ref().map_or(0, |e| e.stmt.line);
                self.message = Some(if line > 0 {
                    format!("CH{} ALARM line {line}: {a}", i + 1)
                } else {
                    format!("CH{} ALARM: {a}", i + 1)
                });
            }
        }
        self.snap = snap;
        self.t = self.core.status().machine_ns;
        for e in self.core.take_events() {
            match e {
                KernelEvent::BlockStart { ch, t, seq } => self.block_started(ch, t, seq),
                e => self.events.push(e),
            }
        }
        self.say_at_ends();
    }

    /// Says channel `ch`'s messages up to block `upto` (`u32::MAX`: all it has left), in
    /// order, at machine time `t`.
    fn say_upto(&mut self, ch: usize, upto: u32, t: u64) {
        let Some(msgs) = self.msgs.get(ch) else {
            return;
        };
        let next = &mut self.msg_at[ch].0;
        while let Some((_, text)) = msgs.get(*next).filter(|m| m.0 <= upto) {
            self.said.push((ch, t, text.clone()));
            *next += 1;
        }
    }

    /// A block channel `ch` said a message at (or its first) started at `t`: the messages up
    /// to it are said, each once per part; a program begun again (the next part) first says
    /// what it had left.
    fn block_started(&mut self, ch: usize, t: u64, seq: u32) {
        let Some(&(_, last)) = self.msg_at.get(ch) else {
            return;
        };
        if seq < last {
            self.say_upto(ch, u32::MAX, t);
            self.msg_at[ch].0 = 0;
        }
        self.msg_at[ch].1 = seq;
        self.say_upto(ch, seq, t);
    }

    /// The messages after a program's last block, said once its channel has finished it (an
    /// MDI run: it ran a block and stands idle again).
    fn say_at_ends(&mut self) {
        for ch in 0..self.snap.len() {
            let c = &self.snap[ch];
            let last = self.msg_at.get(ch).map_or(0, |m| m.1);
            let st = &c.status;
            let ended = st.program_end
                || c.sync.as_ref().is_some_and(|v| v.done)
                || (st.run == 0 && st.idle && last > 0);
            if ended {
                self.say_upto(ch, u32::MAX, self.t);
            }
        }
    }

    /// The lines of the MDI program this cycle runs on channel `ch`, if it is one (what the
    /// MDI display lists while it runs: the buffer is cleared at START).
    pub fn mdi_lines(&self, ch: usize) -> Option<&[String]> {
        (self.mdi && !self.manual && ch == self.only)
            .then(|| self.lines.get(ch).map(|l| &l[..]))
            .flatten()
    }

    /// Every channel's state as the kernel last published it.
    pub fn channels(&self) -> &[ChannelStatus] {
        &self.snap
    }

    /// How many times each channel cut work `id` (1-based), from the kernel's sync table.
    pub fn machined(&self, id: u32) -> Vec<u32> {
        self.core
            .inspect_kernel(move |k| k.table().machined(id))
            .unwrap_or_default()
    }

    /// When the cycle began, in the console's machine time.
    pub fn started_ns(&self) -> u64 {
        self.started_ns
    }

    /// The console's machine time now: the kernel's, which began at the cycle's start.
    pub fn now_ns(&self) -> u64 {
        self.t
    }

    /// The channels this cycle runs (every channel in AUTO, the selected one in MDI; with no
    /// program loaded, every channel stands for manual moves and RESET).
    fn runs(&self, ch: usize) -> bool {
        !self.mdi || self.manual || ch == self.only
    }

    /// Every channel finished (AUTO), or the MDI program ran out.
    pub fn is_over(&self) -> bool {
        self.snap.iter().enumerate().all(|(i, c)| {
            if !self.runs(i) {
                return true;
            }
            match (&c.sync, self.mdi) {
                (Some(v), false) => v.done,
                _ => c.status.run == 0 && c.status.idle,
            }
        })
    }

    /// Nothing moves or can move without the operator: every channel finished, stopped,
    /// waiting at a sync point, faulted or in E-STOP, and no manual move moving or queued.
    /// The kernel's own predicate (`Kernel::progressing`, what its waits and its idle step go
    /// by), as it published it with the state shown: before stop 45 the console derived its
    /// own from the published state, and the two disagreed once (stop 44: a STEP after the
    /// batch ended a wait half done).
    pub fn at_rest(&self) -> bool {
        !self.snap.iter().any(|c| match &c.sync {
            Some(v) => v.progressing,
            None => !c.status.idle,
        })
    }

    /// Feed override 0 holds the machine still for good: every channel that would go on
    /// stands mid-block in a feed move at override 0 (a thread pass keeps 100 %), and one does
    /// (`Kernel::stalled`, which ends a wait too). Nothing but the operator can change that: a
    /// wait would never end.
    pub fn stalled(&self) -> bool {
        self.core.inspect_kernel(|k| k.stalled()).unwrap_or(false)
    }

    /// Advances the machine by at most `ns` of machine time (virtual time), or less when
    /// `until` holds first; in real time the kernel keeps its own clock and this only takes
    /// its state. Whether `until` holds (never for [`RunUntil::Time`]).
    pub fn run(&mut self, ns: u64, until: RunUntil) -> bool {
        let virt = self.clock == ClockMode::Virtual && ns > 0;
        let notices: Vec<Option<String>> = (self.snap.iter())
            .map(|c| c.status.notice.clone())
            .collect();
        let started = match until {
            RunUntil::Time if virt => {
                self.core.run_for(ns);
                false
            }
            RunUntil::Rest if virt => {
                self.core.run_until_idle(ns);
                false
            }
            RunUntil::Block(ch, seq) if virt => {
                self.core.run_until_block(ch, seq, ns).0 == Reached::BlockStart
            }
            _ => false,
        };
        self.refresh();
        // A notice that came while the machine ran is a refusal of its own (an increment the
        // operator queued that would leave the travel when its turn came): said, as the
        // centre's console says it (a command's refusal is said by its command).
        for (i, c) in self.snap.iter().enumerate() {
            if c.status.notice.is_some() && notices.get(i) != Some(&c.status.notice) {
                let n = c.status.notice.as_deref().unwrap_or_default();
                self.message = Some(format!("CH{} {n}", i + 1));
            }
        }
        match until {
            RunUntil::Time => false,
            RunUntil::Rest => self.at_rest(),
            RunUntil::Block(ch, seq) => {
                // Real time: the block executes in the kernel's published state (as the
                // centre's real-time wait sees it).
                let executes = |c: &ChannelStatus| {
                    c.status.in_block
                        && c.status
                            .executing
                            .as_ref()
                            .and_then(|e| e.block())
                            .map(|b| b.seq)
                            == Some(seq)
                };
                let real = self.clock == ClockMode::RealTime;
                started || (real && self.snap.get(ch).is_some_and(executes)) || self.at_rest()
            }
        }
    }

    /// A manual move of channel `ch`'s machine (a jog, an increment, its keep-alive or
    /// release), and the kernel's state after it: a refusal is in the channel's notice, which
    /// the one manual-move rule reads (`console::manual`).
    pub fn manual(&mut self, ch: usize, cmd: Command) {
        // A channel that does not exist refuses in the runner's words; the console only names
        // its own channels.
        let _ = self.core.channel_command(Some(ch), cmd);
        self.refresh();
    }

    /// START: every channel of the cycle resumes (a held or stopped one) and a waiting
    /// one goes on when it can. The refusals, if any.
    pub fn start(&mut self) -> Result<(), String> {
        let ch = Some(self.only).filter(|_| self.mdi);
        // An MDI program's run is an MDI run (`/nc/state` records `run` 2), as the centre's.
        let kind = if self.mdi {
            crate::pulse_core::RunKind::Mdi
        } else {
            crate::pulse_core::RunKind::Auto
        };
        let r = self.core.channel_command(ch, Command::Start(kind));
        self.refresh();
        r
    }

    /// STOP: feed hold on every channel.
    pub fn hold(&mut self) {
        let _ = self.core.channel_command(None, Command::Stop);
        self.refresh();
    }

    /// E-STOP: every channel's run is abandoned, from the kernel thread, in one tick.
    pub fn estop(&mut self) {
        let _ = self.core.channel_command(None, Command::EStop);
        self.refresh();
    }

    /// Channel `ch`'s program read again with its tools now `tools` (revised on the OFS page),
    /// from the state and place its read in this cycle began from: the channel takes it at
    /// its next tool call not yet read in the part it is in (a real lathe takes a wear offset
    /// at the next T), else from its next part (or RESET). The line of that tool call, if in
    /// this part. Refused for a channel with no program of the cycle (MDI, manual moves), a
    /// read that fails (a revised offset that takes the tool past its travel), or other
    /// waiting codes; the cycle then runs on as read.
    pub fn reread(
        &mut self,
        ch: usize,
        tools: &[crate::lathe::desc::ToolDesc],
    ) -> Result<Option<u32>, String> {
        let r = self
            .reread
            .get(ch)
            .and_then(Option::as_ref)
            .ok_or("no program of a cycle runs on this channel")?;
        let mut desc = self.desc.clone();
        desc.channels.get_mut(ch).ok_or("no such channel")?.tools = tools.to_vec();
        let read = read_kept(&r.text, &desc, ch, &self.opts, None, &r.from, r.at)
            .map_err(|e| format!("{}:{e}", r.name))?;
        let zeros = zero_table(&read.statements, &read.zeros);
        let at = self.core.replace_program(ch, read.statements)?;
        if let Some(z) = self.zeros.get_mut(ch) {
            *z = zeros;
        }
        self.desc = desc;
        Ok(at)
    }

    /// SINGLE BLOCK on or off for every channel: on, each stops after the block it is in.
    pub fn set_single_block(&mut self, on: bool) {
        let _ = self.core.channel_command(None, Command::SingleBlock(on));
        self.refresh();
    }

    /// A switch of every channel's machine (rapid override, spindle override): its refusal,
    /// if any.
    pub fn command_all(&mut self, cmd: Command) -> Result<(), String> {
        let r = self.core.channel_command(None, cmd);
        self.refresh();
        r
    }

    /// RESET of channel `ch` (None: every channel) with nothing loaded: its spindle and
    /// coolant stop and its alarm clears. Its turret stays at the tool it is indexed to, as
    /// the centre's spindle keeps its tool (the reader's offsets are what RESET cancels).
    pub fn reset_channels(&mut self, ch: Option<usize>) -> Result<(), String> {
        let r = self.core.channel_command(ch, Command::Reset);
        self.refresh();
        r
    }

    /// The part target (refused below what a channel has finished).
    pub fn set_target(&mut self, n: u32) -> Result<(), String> {
        let r = self.core.set_target(n);
        self.refresh();
        r
    }

    /// RESET of the console's channel `ch`: clears its fault or alarm; after an E-STOP,
    /// every channel's, each back at the start of its program (the run is abandoned, START
    /// begins a new cycle and no interrupted block is resumed). Returns the message.
    pub fn reset(&mut self, ch: usize) -> String {
        let estop = self.snap.iter().any(|c| c.status.estop);
        if estop {
            let _ = self.core.channel_command(None, Command::Reset);
            self.refresh();
            return "RESET: E-STOP released; every channel back at its program start, START begins a new cycle".into();
        }
        if !self.runs(ch) {
            return format!("RESET CH{}: it is not in this MDI run", ch + 1);
        }
        let before = self.snap.get(ch).cloned();
        let r = self.core.channel_command(Some(ch), Command::Reset);
        self.refresh();
        if let Err(e) = r {
            return e;
        }
        match before {
            Some(b)
                if b.sync.as_ref().is_some_and(|v| v.fault.is_some())
                    && b.status.alarm.is_none() =>
            {
                format!(
                    "RESET CH{}: cleared; START resumes where it stopped",
                    ch + 1
                )
            }
            Some(b) if b.status.alarm.is_some() => format!(
                "RESET CH{}: alarm cleared; the channel is back at its program start",
                ch + 1
            ),
            Some(b) if b.status.run != 0 => format!(
                "RESET CH{}: the run is abandoned; the channel is back at its program start",
                ch + 1
            ),
            _ => format!("RESET CH{}: nothing to clear", ch + 1),
        }
    }

    /// A fault in the console's channel `ch`.
    pub fn fault(&mut self, ch: usize, why: &str) -> Result<(), String> {
        if !self.runs(ch) {
            return Err("it is not in this MDI run".into());
        }
        let r = self.core.fault(ch, why);
        self.refresh();
        r
    }

    /// The programs' messages said since the last call: channel, the machine time its block
    /// started at, and text (`CH1 MSG: text`).
    pub fn take_said(&mut self) -> Vec<(usize, u64, String)> {
        std::mem::take(&mut self.said)
    }

    /// A message for the operator, once.
    pub fn take_message(&mut self) -> Option<String> {
        self.message.take()
    }

    /// The kernel's events since the last call (for the recording and the messages).
    pub fn take_events(&mut self) -> Vec<KernelEvent> {
        std::mem::take(&mut self.events)
    }

    /// Each channel's work in the spindle now.
    pub fn works(&self, out: &mut [Option<u32>]) {
        for (o, c) in out.iter_mut().zip(&self.snap) {
            *o = c.sync.as_ref().and_then(|v| v.work);
        }
    }

    /// Each channel's part count now (AUTO; an MDI run counts none).
    pub fn counts(&self, counts: &[u32]) -> Vec<u32> {
        if self.mdi {
            return counts.to_vec();
        }
        self.snap
            .iter()
            .zip(counts)
            .enumerate()
            .map(|(i, (c, &old))| {
                let base = self.base.get(i).copied().unwrap_or(0);
                c.sync.as_ref().map_or(old, |v| base + v.parts)
            })
            .collect()
    }

    /// The cycle just loaded counts its parts on from `base`: a SEARCH's one part
    /// (`search_part`), or the batch going on after it, from the program's top.
    pub fn count_from(&mut self, base: Vec<u32>, search_part: bool) {
        self.base = base;
        self.search_part = search_part;
    }

    /// The cycle loaded is a SEARCH's one part ([`Cycle::count_from`]): its target is 1
    /// whatever the batch's.
    pub fn searching(&self) -> bool {
        self.search_part
    }

    /// The cycle loaded counts on from parts made before it: a SEARCH's part or the batch
    /// after it ([`Cycle::count_from`]).
    pub fn counts_on(&self) -> bool {
        !self.base.is_empty()
    }

    /// The parts the batch had made before this cycle began (0 for a new batch).
    pub fn made_before(&self) -> u32 {
        self.base.iter().copied().max().unwrap_or(0)
    }

    /// The machine's target for the batch's target `n`: less the parts made before this cycle
    /// (at least 1: a cycle makes a part).
    pub fn machine_target(&self, n: u32) -> u32 {
        n.saturating_sub(self.made_before()).max(1)
    }

    /// How a cycle at rest stands, for `novanc run`: `Ok(true)` every channel finished,
    /// `Ok(false)` a channel stopped (M00, M01: START goes on), or what stops it (E-STOP, a
    /// fault, an alarm, channels waiting on each other).
    pub fn outcome(&self) -> Result<bool, String> {
        if self
            .snap
            .iter()
            .all(|c| c.sync.as_ref().is_some_and(|v| v.done))
        {
            return Ok(true);
        }
        if self.snap.iter().any(|c| c.status.estop) {
            return Err("E-STOP".into());
        }
        for (i, c) in self.snap.iter().enumerate() {
            if let Some(f) = c.sync.as_ref().and_then(|v| v.fault.as_ref()) {
                return Err(format!("CH{} FAULT: {f}", i + 1));
            }
        }
        for (i, c) in self.snap.iter().enumerate() {
            if let Some(a) = &c.status.alarm {
                return Err(format!("CH{} ALARM: {a}", i + 1));
            }
        }
        let waits: Vec<String> = self
            .snap
            .iter()
            .enumerate()
            .filter_map(|(i, c)| {
                let w = c.sync.as_ref()?.waits_on?;
                Some(format!("CH{} waits {w}", i + 1))
            })
            .collect();
        if waits.is_empty() || self.snap.iter().any(|c| c.status.hold) {
            return Ok(false);
        }
        Err(format!("deadlock: {}", waits.join(", ")))
    }

    /// When the last channel reached the part target, in the console's machine time (None
    /// until every channel has).
    pub fn finished_ns(&self) -> Option<u64> {
        self.snap
            .iter()
            .map(|c| c.sync.as_ref().and_then(|v| v.done_at))
            .try_fold(0, |a, d| d.map(|d| a.max(d)))
    }

    /// Channel `ch`'s totals since the cycle began: blocks, pulses X and Z, parts.
    pub fn totals(&self, ch: usize) -> (u64, [u64; 2], u32) {
        self.snap
            .get(ch)
            .and_then(|c| c.sync.as_ref())
            .map_or((0, [0; 2], 0), |v| {
                (
                    v.total_blocks,
                    [v.total_pulses[0], v.total_pulses[2]],
                    v.parts,
                )
            })
    }

    /// The state word of channel `ch` (docs/lathe.md "The panel"), derived from the kernel's
    /// state: ESTOP, FAULT, ALARM, DONE, WAIT, HOLD, STOP (stopped between blocks: M00, M01,
    /// single block), RUN, IDLE.
    fn state_word(&self, ch: usize) -> &'static str {
        let Some(c) = self.snap.get(ch) else {
            return "IDLE";
        };
        let st = &c.status;
        let v = c.sync.as_ref();
        if st.estop {
            "ESTOP"
        } else if v.is_some_and(|v| v.fault.is_some()) {
            "FAULT"
        } else if st.alarm.is_some() {
            "ALARM"
        } else if v.is_some_and(|v| v.done) {
            "DONE"
        } else if v.is_some_and(|v| v.waits_on.is_some()) {
            "WAIT"
        } else if st.run != 0 && st.hold {
            "HOLD"
        } else if st.run != 0 && st.idle {
            "STOP"
        } else if st.run != 0 {
            "RUN"
        } else if st.job.is_some() && !st.moving {
            // Its run loaded and stopped between two blocks (SINGLE BLOCK): START goes on.
            "STOP"
        } else if st.returning && st.job.is_none() {
            // The reference return (HOME): no program runs, and the post goes to the top.
            "HOME"
        } else if st.moving {
            // A manual move: no program runs, and an axis moves (CONTINUOUS, HANDLE, STEP).
            "JOG"
        } else {
            "IDLE"
        }
    }

    /// Whether a channel's state word is one of `words`, as [`Cycle::views`] would say (without
    /// making the views).
    pub fn any_state(&self, words: &[&str]) -> bool {
        (0..self.snap.len()).any(|ch| self.runs(ch) && words.contains(&self.state_word(ch)))
    }

    /// Every console channel as the display shows it.
    pub fn views(&self, desc: &LatheDesc, programs: &[Program], counts: &[u32]) -> Vec<ChanView> {
        (0..desc.channels.len())
            .map(|ch| {
                let mut v = ChanView {
                    name: desc.channels[ch].name.clone(),
                    // A kernel loaded for manual moves runs no program: the channel's own
                    // is still the one shown.
                    program: if self.mdi && ch == self.only && !self.manual {
                        "MDI".into()
                    } else {
                        programs[ch].name.clone()
                    },
                    state: "IDLE".into(),
                    parts: counts[ch],
                    ..Default::default()
                };
                let Some(c) = self.snap.get(ch) else {
                    return v;
                };
                let st = &c.status;
                v.state = self.state_word(ch).into();
                // What the channel's machine is doing, whether or not this cycle runs its
                // program: a spindle an earlier MDI left turning turns on while another
                // channel's MDI runs, and E-STOP is every channel's (before stop 41 a channel
                // outside an MDI run showed IDLE and S 0 whatever its machine did).
                v.pos = [st.pos[0], st.pos[2]];
                v.rpm = st.spindle as f64;
                v.tool = st.tool.unwrap_or(0);
                v.coolant = st.coolant;
                v.outputs = st.outputs.digital;
                if !self.runs(ch) {
                    v.note = st.alarm.clone().unwrap_or_default();
                    return v;
                }
                v.line = st.executing.as_ref().map_or(0, |e| e.stmt.line);
                // While its run is loaded (running, held, between blocks): the zero of the
                // block executing (or last executed; before the first, the program's first).
                // Ended, the console shows what the next run starts from.
                let seq = st.executing.as_ref().and_then(|e| e.block()).map(|b| b.seq);
                let datum = self.zeros.get(ch).filter(|_| st.run != 0).and_then(|t| {
                    let i = seq.map_or(0, |s| t.partition_point(|z| z.0 <= s).saturating_sub(1));
                    t.get(i).map(|z| z.1)
                });
                if let Some(d) = datum {
                    v.set_datum(desc, &d);
                }
                if v.line == 0 && st.run == 0 && !st.program_end {
                    // An alarm or an E-STOP stops the channel at its block, and the listing
                    // stays there until RESET (an E-STOP's before stop 47 went to the
                    // program's start at once); not begun, or RESET: the pointer at the
                    // program's start.
                    v.line = st
                        .alarm
                        .as_deref()
                        .map(crate::record::foxglove::alarm_line)
                        .filter(|&l| l > 0)
                        .or(st.estop_at.map(|(_, l)| l).filter(|&l| l > 0))
                        .unwrap_or_else(|| self.first.get(ch).copied().unwrap_or(0));
                }
                v.text = self
                    .lines
                    .get(ch)
                    .and_then(|l| l.get((v.line as usize).wrapping_sub(1)))
                    .cloned()
                    .unwrap_or_default();
                if let Some(s) = &c.sync {
                    v.waits = s.waits_on.map(|w| w.to_string()).unwrap_or_default();
                    v.work = s.work;
                    v.chuck = s.closed;
                    if !self.mdi {
                        // The batch's count, as the title's (`counts`): a cycle going on with a
                        // batch after a SEARCH counts on from the parts made before it (the
                        // summary said `parts 4/5` beside the title's `PARTS 5/5`).
                        v.parts = self.base.get(ch).copied().unwrap_or(0) + s.parts;
                    }
                    v.note = s.fault.clone().unwrap_or_default();
                }
                if v.note.is_empty() {
                    v.note = st.alarm.clone().unwrap_or_default();
                }
                if let Some(b) = st.executing.as_ref().and_then(|e| e.block()) {
                    if st.in_block {
                        v.to_go = [b.end[0] - st.pos[0], b.end[2] - st.pos[2]];
                    }
                }
                v
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::restart_from;
    use crate::block::Motion;
    use crate::lathe::desc::{parse, LatheDesc, MachineDesc};
    use crate::lathe::gcode::{read_program, ReadOptions};

    fn shop() -> LatheDesc {
        let text = "machine shop\nkind lathe\npulse 0.001\ntick 100\nloading manual\n\
                    dialect fanuc\nchannel PATH-1\ngcode system A\n\
                    x travel -5 200 rapid 18000 accel 3000\nz travel -600 100 rapid 24000 accel 3000\n\
                    spindle max 6000 accel 3000 encoder 1024\ntool 1 radius 0 tip 3\n";
        match parse(text) {
            Ok(MachineDesc::Lathe(d)) => d,
            other => panic!("{other:?}"),
        }
    }

    const PROGRAM: &str = "G21 G99 G18\nT0101\nG97 S800 M03\nG00 X40. Z5. M08\nG01 Z-20. F0.2\n\
                           G00 X45.\nZ5.\nX36.\nG01 Z-20.\nG00 X45.\nZ5.\nM09\nM30\n";

    /// SEARCH's restart (docs/lathe.md "SEARCH"), worked by hand: from line 8 (`X36.`), the
    /// tool T01, the spindle at 800 rpm forward and the flood coolant the lines before it set,
    /// then the tool from where it stands to where line 8 starts (X45 Z5: radius 22.5): out in
    /// X first, never in; along Z; in X. From inside the part's diameter (X10 at Z-5) it goes
    /// out to X45 before it moves along Z.
    #[test]
    fn search_restores_what_the_lines_before_set_and_approaches_out_along_in() {
        let p = read_program(PROGRAM, &shop(), 0, &ReadOptions::default()).unwrap();
        let (k, r) = restart_from(&p, 8, [200_000, 100_000]).unwrap();
        assert_eq!(p[k].line, 8);
        let b = &r.blocks;
        assert_eq!((r.line, b.len()), (0, 5), "{b:#?}");
        assert_eq!(b[0].t, Some(1));
        assert_eq!((b[1].m, b[1].s), (Some(3), Some(800)));
        assert_eq!(b[2].m, Some(8));
        let ends: Vec<[i64; 2]> = b[3..].iter().map(|b| [b.end[0], b.end[2]]).collect();
        assert_eq!(ends, [[200_000, 5_000], [22_500, 5_000]]);
        assert!(b[3..].iter().all(|b| b.motion == Motion::Rapid));
        assert!(b.iter().all(|b| b.seq == 0 && b.stmt == 0));
        // From inside: out in X to the start's X, along Z, (in X: already there).
        let (_, r) = restart_from(&p, 8, [5_000, -5_000]).unwrap();
        let ends: Vec<[i64; 2]> = (r.blocks.iter())
            .filter(|b| b.motion == Motion::Rapid)
            .map(|b| [b.end[0], b.end[2]])
            .collect();
        assert_eq!(ends, [[22_500, -5_000], [22_500, 5_000]]);
        // The coolant off (M09) before the line: none restored; past the last block: refused.
        let (_, r) = restart_from(&p, 13, [22_500, 5_000]).unwrap();
        assert!(r.blocks.iter().all(|b| b.m != Some(8)), "{:#?}", r.blocks);
        let e = restart_from(&p, 14, [0, 0]).unwrap_err();
        assert_eq!(e, "SEARCH: the program makes no block at or after line 14");
    }
}
