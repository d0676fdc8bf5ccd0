//! The lathe G-code reader (docs/lathe-gcode.md): one channel's ISO program, read with
//! LinuxCNC 2.9's lathe-mode semantics (Fanuc 0i-T's for G71/G70 and the U/W words), into the
//! kernel's statements and blocks (`crate::block`, the one interface between the language
//! readers and the kernel) of the imaginary tool tip P.
//!
//! The program is read by the one G-code reader (`crate::gcode::GcodeSource`, the mill's): its
//! lines, flow (O-words, M98/M99, the Fanuc dialect's GOTO, WHILE, G65), parameters, messages
//! and bounds, in the channel's dialect; the lathe's reader ([`exec::Reader`], a
//! `crate::gcode::Motion` back end) executes each line's words, sorted by `sort_words_in`
//! with the lathe's own letters and codes ([`LATHE`]).
//!
//! - [`exec`]: one line's words executed against the modal state.
//! - [`moves`]: end points, feeds, arcs and G33.
//! - [`out`]: the emitter: tool offsets, nose-radius compensation, travel, pulses, blocks.
//! - [`comp`]: the tip chart (P from the nose centre) and LinuxCNC's orientation numbers; the
//!   compensation itself is the mill's (`crate::gcode::comp`), driven by [`out`].
//! - [`cycles`]: G76 threading and G71/G70 roughing and finishing.
//! - [`grooving`]: Fanuc's G74/G75 peck cycles; [`drilling`]: Fanuc's G83 face drilling and
//!   G84 face tapping.
//! - [`sysvars`]: the machine state a program reads: Fanuc's system variables, LinuxCNC's
//!   parameters from #5000 and predefined named parameters.

pub mod comp;
pub mod cycles;
pub mod drilling;
pub mod exec;
pub mod grooving;
pub mod moves;
pub mod out;
pub mod sysvars;

#[cfg(test)]
mod tests;

use crate::block::{Statement, TranslateError};
use crate::gcode::words::Dialect;
use crate::lathe::desc::LatheDesc;
use std::collections::HashMap;

/// The bounds on a lathe program's work (docs/limits.md): the most blocks one program may
/// produce (cycles included), the most lines it may have and execute (G70 repeats of its
/// profile lines counted), the most passes of one G71 or G76 cycle.
pub use crate::limits::{LATHE_MAX_LINES as MAX_LINES, LATHE_MAX_STEPS as MAX_STEPS, MAX_PASSES};

/// The panel switches a lathe program reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// BLOCK DELETE: lines starting with `/` are skipped.
    pub block_delete: bool,
    /// OPTIONAL STOP: M01 stops (else it is dropped).
    pub optional_stop: bool,
    /// The console's part counter when the program is read (Fanuc's #3901/#3902); `None`:
    /// no counter (the reader refuses them).
    pub parts: Option<Parts>,
}

/// The lathe's part counter as a program reads it (Fanuc's #3901 parts machined, #3902
/// required): each channel's count of finished works and the target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Parts {
    /// Works each channel has finished (channels past the machine's read 0).
    pub counts: [u32; crate::lathe::desc::MAX_CHANNELS],
    /// The number of parts to make.
    pub target: u32,
}

impl Parts {
    /// The counter of `counts` (one a channel) and `target`.
    pub fn new(counts: &[u32], target: u32) -> Parts {
        let mut p = Parts {
            counts: Default::default(),
            target,
        };
        for (to, from) in p.counts.iter_mut().zip(counts) {
            *to = *from;
        }
        p
    }
}

const LATHE_LETTERS: &str = "ADEFHIJKLNPQRSTUWXZ";

/// The lathe dialect: letters and codes by modal group (docs/lathe-gcode.md "Words").
pub const LATHE: Dialect = Dialect {
    letters: LATHE_LETTERS,
    letter_bits: crate::gcode::words::letter_bits(LATHE_LETTERS),
    g_group: lathe_g_group,
    m_group: lathe_m_group,
    g_why: lathe_g_why,
    letter_hint: " (the lathe has the axes X and Z; U and W are incremental X and Z)",
    m_remap: [0; 4],
};

/// The lathe dialect in Fanuc's G code system A (a channel's `gcode system A`,
/// docs/lathe-gcode.md "G code systems"): G90, G92 and G94 are the single cycles of group 1,
/// G98/G99 the feeds, G50 the spindle limit; G91 and G95 do not exist.
pub const LATHE_A: Dialect = Dialect {
    g_group: lathe_a_g_group,
    g_why: lathe_a_g_why,
    ..LATHE
};

fn lathe_a_g_group(g: u32) -> Option<u8> {
    match g {
        900 | 920 | 940 => Some(1),
        921..=923 => None,
        980 | 990 => Some(5),
        500 => Some(0),
        910 | 950 => None,
        _ => lathe_g_group(g),
    }
}

fn lathe_a_g_why(g: u32) -> &'static str {
    match g {
        910 => " (G code system A has no G91: U and W are the increments, X and Z absolute)",
        950 => " (in G code system A the feeds are G98 per minute and G99 per revolution)",
        921..=923 => " (G92 is the threading cycle in G code system A)",
        930 => " (inverse-time feed is not supported: G98 or G99)",
        _ => lathe_g_why(g),
    }
}

fn lathe_g_group(g: u32) -> Option<u8> {
    Some(match g {
        0 | 10 | 20 | 30 | 320 | 330 | 700 | 710 | 720 | 730 | 740 | 750 | 760 => 1,
        170 | 180 | 190 => 2,
        900 | 910 => 3,
        70 | 80 => 4,
        940 | 950 => 5,
        200 | 210 => 6,
        400 | 410 | 420 | 411 | 421 => 7,
        960 | 970 => 8,
        40 | 100 | 280 | 530 | 920 | 921 | 922 => 0,
        800 | 830 | 840 => 9,
        430 | 490 => 10,
        // System B's return levels of G83 and G84 (initial level, R); `exec` refuses them on a
        // line without either and out of their mode, with [`G98_G99_FEEDS`].
        980 | 990 => 11,
        540 | 550 | 560 | 570 | 580 | 590 => 12,
        610 | 611 | 640 => 13,
        // LinuxCNC's arc-centre distance mode: I and K from the arc's start, the only one the
        // lathe reads (G90.1 is refused, `lathe_g_why`).
        911 => 14,
        _ => return None,
    })
}

fn lathe_m_group(m: u32) -> Option<u8> {
    Some(match m {
        0 | 1 | 2 | 30 => 4,
        10 | 11 => 5,
        3..=5 => 7,
        6 => 6,
        7..=9 => 8,
        // The thread chamfer on and off (a Haas's, many a Fanuc lathe builder's).
        23 | 24 => 2,
        // A digital output on and off with the motion or at once, an analog output with the
        // motion or at once (LinuxCNC's, the mill's; M62, M63, M67, M68 since stop 60).
        62..=65 | 67 | 68 => 1,
        100..=199 => 9,
        // Not 10: a code a machine description remaps is read in group 10, and may stand
        // beside M98 (the lathe's own codes are in no group LinuxCNC numbers 10).
        98 | 99 => 3,
        _ => return None,
    })
}

/// Whether the lathe defines M code `m` (a machine description may remap only one it does
/// not: docs/lathe-gcode.md "A machine builder's M codes").
pub fn m_code_known(m: u32) -> bool {
    lathe_m_group(m).is_some()
}

/// A channel's work offsets G54 to G59, `[Z, X]` mm from the machine's zero (X a radius): the
/// machine's zero is the work face's of a channel whose offsets are 0 (docs/lathe-gcode.md
/// "Work offsets").
pub type WorkOffsets = [[f64; 2]; 6];

/// The largest a work offset may be, mm, either axis.
pub const MAX_WORK_OFFSET_MM: f64 = 10_000.0;

/// Where the channel keeps work offset `work`'s Z and X: LinuxCNC's parameters, where the
/// centre keeps its own (`crate::gcode::state::system_base`: #5221 + 20 × (P − 1) X, a
/// radius; +2 Z), mm.
pub fn work_params(work: usize) -> [usize; 2] {
    let base = crate::gcode::state::system_base(work);
    [base + 3, base + 1]
}

/// Every parameter the work offsets are kept in.
pub fn all_work_params() -> impl Iterator<Item = usize> {
    (0..6).flat_map(work_params)
}

/// The work offsets as the parameters `p` keep them (a vacant one: 0).
pub fn work_offsets(p: &[f64]) -> WorkOffsets {
    std::array::from_fn(|w| {
        work_params(w).map(|n| p.get(n).copied().filter(|v| v.is_finite()).unwrap_or(0.0))
    })
}

/// The work offsets into the parameters `p`.
pub fn set_work_offsets(p: &mut [f64], work: &WorkOffsets) {
    for (w, zx) in work.iter().enumerate() {
        for (n, v) in work_params(w).into_iter().zip(zx) {
            if let Some(slot) = p.get_mut(n) {
                *slot = *v;
            }
        }
    }
}

/// Why G98 or G99 is refused in G code system B out of G83's mode (and in LinuxCNC's dialect).
pub const G98_G99_FEEDS: &str = "G98 and G99 are the feeds of Fanuc's G code system A: in system B, G94 per minute and G95 per revolution (and with G83 or G84, in the Fanuc dialect, G98 returns to the initial level, G99 to R)";

fn lathe_g_why(g: u32) -> &'static str {
    match g {
        923 => " (the lathe keeps no G92 parameters to restore: give G92 X Z)",
        901 => " (the lathe reads arc centres I and K from the arc's start only: G91.1)",
        930 => " (inverse-time feed is not supported: G94 or G95)",
        810..=890 => " (the lathe's drilling cycles are G83 and G84, on the centre line, in the Fanuc dialect)",
        591..=593 => " (the lathe's work systems are G54 to G59)",
        500 => " (G50 is Fanuc's G code system A: 'gcode system A' in the channel's description; in system B the G96 limit is G92 S in Fanuc's dialect, D in LinuxCNC's)",
        _ => "",
    }
}

/// The point the reader takes the tool to stand at when a program starts, pulses [X, Z]: the
/// channel's reference position, the top of both travels (docs/lathe-gcode.md "Start").
pub fn home(desc: &LatheDesc, ch: usize) -> [i64; 2] {
    match desc.channels.get(ch) {
        Some(c) => [
            desc.pulses(c.axes[0].travel[1]),
            desc.pulses(c.axes[1].travel[1]),
        ],
        None => [0, 0],
    }
}

/// Reads one channel's lathe program into the kernel's statements (docs/lathe-gcode.md), one
/// per source line that makes blocks, the blocks numbered from 1 and starting where
/// [`home`] says. `ch` is the 0-based channel whose tools, spindle and travel apply.
pub fn read_program(
    text: &str,
    desc: &LatheDesc,
    ch: usize,
    opts: &ReadOptions,
) -> Result<Vec<Statement>, TranslateError> {
    read_program_in(text, desc, ch, opts, None)
}

/// [`read_program`] in the program's own `dialect` (a stored program keeps the one it was
/// stored in); `None` reads it in the channel's ([`ChannelDesc::dialect`], else LinuxCNC's).
///
/// [`ChannelDesc::dialect`]: crate::lathe::desc::ChannelDesc::dialect
pub fn read_program_in(
    text: &str,
    desc: &LatheDesc,
    ch: usize,
    opts: &ReadOptions,
    dialect: Option<crate::settings::Dialect>,
) -> Result<Vec<Statement>, TranslateError> {
    let kept = Kept::power_on(desc, ch, dialect);
    read_kept(text, desc, ch, opts, dialect, &kept, None).map(|r| r.statements)
}

/// What a channel keeps from one read to the next, as a control keeps its interpreter's state
/// between programs and MDI (docs/lathe-gcode.md "What a channel keeps"): the modal state, the
/// tool in place and the one reader's parameters.
#[derive(Clone, Debug)]
pub struct Kept {
    /// The modal state (G20/G21, G90/G91, G07/G08, G94/G95, G96/G97, F, S, D, the motion
    /// mode, G71's depth of cut). The spindle's direction is the machine's: kept here as
    /// stopped, and set at START from the spindle as the kernel turns it (`Cycle::load`).
    pub modal: exec::State,
    /// The tool in place, by number, and whether its offsets apply (T0101 or T0100).
    pub tool: Option<(u32, bool)>,
    /// The one reader's state: the parameters, named globals and the Fanuc dialect's vacancy.
    pub params: crate::gcode::InterpState,
}

impl Kept {
    /// Channel `ch`'s state at power-on: the initial modes (docs/lathe-gcode.md "Start,
    /// modes and coordinates"), the feed mode the channel's `feed` line says, else its
    /// dialect's (`dialect`, else the channel's: Fanuc's G95, LinuxCNC's G94), no tool,
    /// every parameter 0 (vacant in the Fanuc dialect).
    pub fn power_on(
        desc: &LatheDesc,
        ch: usize,
        dialect: Option<crate::settings::Dialect>,
    ) -> Kept {
        Kept {
            modal: power_on_modes(desc, ch, dialect),
            tool: None,
            params: crate::gcode::InterpState::with_persistent(&[], [0.0; 3], None),
        }
    }

    /// What channel `ch`'s next read starts measured from (its work system, zero and tool
    /// offsets in force; [`Datum`]).
    pub fn datum(&self, desc: &LatheDesc, ch: usize) -> Datum {
        let m = &self.modal;
        let w = work_offsets(&self.params.params)[m.work];
        let offset = match self.tool {
            Some((t, true)) => desc
                .channels
                .get(ch)
                .and_then(|c| c.tool(t))
                .map_or([0.0; 2], |t| [t.offset[1], t.offset[0]]),
            _ => [0.0; 2],
        };
        Datum {
            work: m.work,
            zero: [w[0] + m.origin[0], w[1] + m.origin[1]],
            offset,
        }
    }

    /// Channel `ch`'s state at power-on with the parameters its stores kept, (number, value):
    /// #500–#999 and the work offsets (docs/lathe-gcode.md "What a channel keeps"), as the
    /// console opens it and `novanc run --state` reads it.
    pub fn from_stores(desc: &LatheDesc, ch: usize, stored: &[(usize, f64)]) -> Kept {
        let mut k = Kept::power_on(desc, ch, None);
        for &(p, v) in stored {
            if let Some(slot) = k.params.params.get_mut(p) {
                *slot = v;
            }
        }
        k
    }

    /// RESET of the channel (docs/lathe-gcode.md "What a channel keeps"): the modal state and
    /// the tool's offsets back to power-on (Fanuc's RESET with parameter CLR = 1); in the
    /// Fanuc dialect the locals #1–#33 vacant, and the common variables #100–#199 too unless
    /// the channel keeps them (`common keep`). Every other parameter stays.
    pub fn reset(&mut self, desc: &LatheDesc, ch: usize) {
        self.modal = power_on_modes(desc, ch, None);
        self.tool = None;
        let keep_common = desc
            .channels
            .get(ch)
            .and_then(|c| c.keep_common)
            .unwrap_or(false);
        let p = &mut self.params;
        if p.fanuc_vacant {
            for n in 1..=33 {
                p.params[n] = f64::NAN;
            }
            if !keep_common {
                p.fanuc_reset();
            }
        }
        p.call_level = 0;
    }
}

/// The modal state at power-on: [`exec::State::new`]'s, in the feed mode of the channel's
/// `feed` line, else of the dialect (`dialect`, else the channel's): a Fanuc 0i-T powers on
/// in feed per revolution (G99 in system A, G95 in system B; parameter 3402#4 FPM = 0),
/// LinuxCNC in G94.
fn power_on_modes(
    desc: &LatheDesc,
    ch: usize,
    dialect: Option<crate::settings::Dialect>,
) -> exec::State {
    let mut st = exec::State::new(desc, ch);
    if let Some(c) = desc.channels.get(ch) {
        let d = dialect.or(c.dialect).unwrap_or_default();
        st.per_rev = c.per_rev.unwrap_or(d == crate::settings::Dialect::Fanuc);
    }
    st
}

/// A message a program gave (`(msg,)`, `(print,)`, `(debug,)`, `(log,)`), to be shown when
/// the block after it begins.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    /// The index of the statement it comes before (the statement count: after the last one).
    pub before: usize,
    /// `MSG`, `PRINT`, `DEBUG` or `LOG`.
    pub kind: &'static str,
    /// The text, parameters substituted.
    pub text: String,
}

/// What a read makes: the statements, the messages by the statement they come before, and the
/// channel's state as the read leaves it.
#[derive(Debug)]
pub struct Reading {
    /// The statements, as [`read_program`]'s.
    pub statements: Vec<Statement>,
    /// Each statement's work system and program zero, and the offsets of the tool in place,
    /// as in force when its blocks were made: what the POS page's work position is measured
    /// from while it runs.
    pub zeros: Vec<Datum>,
    /// The messages, in the order they were read.
    pub messages: Vec<Message>,
    /// The channel's state after the program.
    pub kept: Kept,
}

/// What a block's tip is measured from on the display (docs/lathe-gcode.md "Work offsets"):
/// the work system in force (0 for G54), the program's zero from the machine's, and the
/// offsets of the tool in place (what the reader added to the programmed point), `[Z, X]` mm,
/// X a radius. The programmed point is the tip less the zero and the offsets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Datum {
    /// The work system, 0 (G54) to 5 (G59).
    pub work: usize,
    /// The program's zero: the work offset and a G50/G92 shift.
    pub zero: [f64; 2],
    /// The tool's offsets in force (zero after T0100, or with no tool).
    pub offset: [f64; 2],
}

/// Reads a program from the state `kept` the channel's last read left, the tool post at `at`
/// (pulses [X, Z]; `None`: at [`home`]). A read refused gives no state: the channel keeps
/// `kept`.
pub fn read_kept(
    text: &str,
    desc: &LatheDesc,
    ch: usize,
    opts: &ReadOptions,
    dialect: Option<crate::settings::Dialect>,
    kept: &Kept,
    at: Option<[i64; 2]>,
) -> Result<Reading, TranslateError> {
    // Counted before anything is kept for them: the program is held whole, a line at a time.
    let count = text.lines().count();
    if count as u64 > MAX_LINES {
        return Err(TranslateError {
            line: MAX_LINES as u32 + 1,
            col: 1,
            message: format!(
                "the program has {count} lines, more than the {MAX_LINES} a lathe program may have"
            ),
        });
    }
    let lines: Vec<&str> = text.lines().collect();
    let Some(chan) = desc.channels.get(ch) else {
        return Err(TranslateError {
            line: 1,
            col: 1,
            message: format!(
                "channel {} does not exist (the machine has {})",
                ch + 1,
                desc.channels.len()
            ),
        });
    };
    if !(desc.pulse_mm.is_finite() && desc.pulse_mm > 0.0) {
        return Err(TranslateError {
            line: 1,
            col: 1,
            message: "the machine's pulse size is not a positive number".into(),
        });
    }
    // N numbers to line indices, for G70/G71 P and Q (the first line with each number).
    let mut n_lines: HashMap<u32, usize> = HashMap::new();
    let mut starts = Vec::with_capacity(lines.len());
    let mut byte = 0;
    for (i, raw) in text.split_inclusive('\n').enumerate() {
        starts.push(byte);
        byte += raw.len();
        if let Some(n) = n_number(raw) {
            n_lines.entry(n).or_insert(i);
        }
    }
    let dialect = dialect.or(chan.dialect).unwrap_or_default();
    // The spindle's direction is the machine's: the caller says it in `kept.modal.dir` (the
    // console: as the last cycle left the spindle; else stopped, as `Kept` keeps it).
    let st = kept.modal.clone();
    let mut out = out::Out::new(desc, ch);
    if let Some((t, offsets)) = kept.tool {
        if let Some(td) = chan.tool(t) {
            out.set_tool(td.clone(), offsets);
        }
    }
    if let Some(at) = at {
        out.start_at(at);
    }
    if !st.stopped() {
        // Turning already: the feeds per revolution go on from its speed.
        let css = st.css.then(|| {
            let k = if st.inch { 0.3048 } else { 1.0 };
            crate::block::Css {
                m_per_min: st.s * k,
                limit_rpm: st.limit,
            }
        });
        out.set_speed(st.s, css);
    }
    let mut r = exec::Reader {
        desc,
        ch,
        chan,
        opts: *opts,
        lines: &lines,
        n_lines,
        starts,
        st,
        out,
        in_cycle: false,
        ended: false,
        fanuc: dialect == crate::settings::Dialect::Fanuc,
        // System A is Fanuc's: a program kept in LinuxCNC's dialect reads system B.
        system_a: chan.system_a && dialect == crate::settings::Dialect::Fanuc,
        calculator: chan.calculator.unwrap_or(false) && dialect == crate::settings::Dialect::Fanuc,
        unpointed: 0,
        pointed: 0,
        remapped: None,
        after_remap: false,
        profile_first: None,
        profile_names_z: None,
        work: work_offsets(&kept.params.params),
    };
    if !chan.remap_m.is_empty() {
        let base = if r.system_a { &LATHE_A } else { &LATHE };
        r.remapped = Some(base.with_remaps(chan.remap_m.iter().map(|m| m.code)));
    }
    if r.system_a {
        r.out.feed_codes = ("G98", "G99");
    }
    // The one reader (`crate::gcode`) runs the program's flow and parameters, in the
    // channel's dialect; the lathe's reader executes each line's words.
    let settings = crate::settings::MachineSettings {
        dialect,
        fanuc: crate::settings::FanucSettings {
            calculator: r.calculator,
            p_point_seconds: chan.p_point_seconds.unwrap_or(false),
            ..Default::default()
        },
        remap_m: chan.remap_m.clone(),
        ..Default::default()
    };
    let magazine = crate::tooldata::Magazine::load(crate::tooldata::TCodeTable::new(0), &[]);
    let switches = crate::gcode::Switches {
        block_delete: opts.block_delete,
        optional_stop: opts.optional_stop,
    };
    let mut source = crate::gcode::GcodeSource::with_state(
        std::sync::Arc::from(text),
        magazine,
        settings,
        crate::block::MachineState::at([0, 0, 0]),
        kept.params.clone(),
        switches,
    )
    .mdi()
    .without_texts()
    .line_limit(MAX_LINES);
    if let Some(p) = opts.parts {
        let made = p.counts.get(ch).copied().unwrap_or(0);
        source = source.part_counter(u64::from(made), u64::from(p.target));
    }
    if !chan.subroutines.is_empty() {
        // The channel's subroutine path (docs/lathe-gcode.md "One reader, two dialects").
        source = source.subroutines(Box::new(crate::gcode::SubPath(chan.subroutines.clone())));
    }
    let mut messages = Vec::new();
    let mut zeros = Vec::new();
    loop {
        let before = r.out.statements.len();
        let Some(s) = source.next_with(&mut r) else {
            break;
        };
        s?;
        zeros.resize(r.out.statements.len(), r.datum());
        for e in source.take_events() {
            if let crate::gcode::Event::Message { kind, text } = e {
                messages.push(Message { before, kind, text });
            }
        }
    }
    r.out.finish()?;
    let mut statements = std::mem::take(&mut r.out.statements);
    for s in &mut statements {
        s.text = lines
            .get((s.line as usize).wrapping_sub(1))
            .map_or_else(String::new, |l| l.to_string());
    }
    let mut modal = r.st.clone();
    if r.ended && dialect == crate::settings::Dialect::LinuxCnc {
        // LinuxCNC's M2/M30 (`convert_stop`), as the centre's: G90, G94, F0, G40, G1, the
        // spindle stopped; the units, the diameter mode and the parameters stay. Fanuc's
        // end of program keeps the modal state.
        modal.absolute = true;
        modal.per_rev = false;
        modal.feed = None;
        modal.motion = Some(10);
        // ... and the work system G54, the G92 shift let go (as G92.2).
        modal.work = 0;
        modal.origin = [0.0, 0.0];
    }
    modal.dir = 5;
    if r.ended {
        // M02/M30 reset a Fanuc, and a reset cancels the drilling cycle (G80): the next
        // program's first X or Z must not drill.
        modal.drill = None;
    }
    let tool = r.out.tool_in_place();
    let mut params = source.into_state();
    set_work_offsets(&mut params.params, &r.work);
    // (A statement `finish` added: the zero the read ended in.)
    zeros.resize(statements.len(), r.datum());
    Ok(Reading {
        statements,
        zeros,
        messages,
        kept: Kept {
            modal,
            tool,
            params,
        },
    })
}

/// The N number a line starts with (after an optional `/`), if any: a cheap scan used only to
/// index lines for G70/G71 (the line itself is read properly when executed).
fn n_number(raw: &str) -> Option<u32> {
    let t = raw.trim_start();
    let t = t.strip_prefix('/').unwrap_or(t).trim_start();
    let rest = t.strip_prefix(['N', 'n'])?;
    let digits: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .take(9)
        .collect();
    digits.parse().ok()
}
