//! Executing one line (docs/gcode.md "Order of execution"), in LinuxCNC 2.9's order: the
//! comments, the feed mode, F, S, T, the I/O codes M62–M68, the tool change, the spindle,
//! M70–M73, coolant, the override switches, G04, the plane, the units, cutter compensation,
//! tool length, the coordinate system, path control, the distance modes, the retract mode,
//! the non-modal codes (G10, G28, G30, G53, G92), the motion, then the stops.
//!
//! Every word on a line is used by something on it, or the line is refused (as rs274's
//! `check_other_codes` refuses it): nothing is dropped in silence.

use super::canon::{Canon, Io};
use super::comp::Comp;
use super::moves;
use super::read::{Comment, CommentKind};
use super::state::{CompSide, FeedMode, InterpState, Motion, PathMode, Saved};
use super::words::Words;
use crate::block::{Plane, TranslateError};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;

/// What the machine must answer before reading can go on (LinuxCNC's queue busters,
/// docs/gcode.md "Probing" and "Inputs and outputs"). A source asks once the line's blocks
/// have been handed on: in a run the machine answers when it has executed them.
pub trait Machine {
    /// A probe move from `from` to `to` (machine mm, the gauge line) with a stylus of
    /// `radius` mm at `length` below the gauge line, seeking contact (`toward`: G38.2, G38.3)
    /// or its loss (G38.4, G38.5): where the machine stopped, and whether it found what it
    /// sought.
    fn probe(
        &mut self,
        from: [f64; 3],
        to: [f64; 3],
        length: f64,
        radius: f64,
        toward: bool,
    ) -> Result<Probed, String>;
    /// M66: the value of input `index` (digital: 0 or 1), after waiting as `mode` says
    /// (0 immediate, 1 rise, 2 fall, 3 high, 4 low) at most `timeout` s; `None` on a timeout.
    fn input(
        &mut self,
        digital: bool,
        index: u32,
        mode: u32,
        timeout: f64,
    ) -> Result<Option<f64>, String>;
    /// Whether this machine runs the blocks handed on and can say its clocks when it reaches
    /// a line (a run's pulse core); where none does, Fanuc's #3001/#3002 are refused.
    fn keeps_time(&self) -> bool {
        false
    }
    /// The machine's clocks when it reached the clocks block handed on last (after every
    /// block before it).
    fn clocks(&mut self) -> Result<Clocks, String> {
        Err("no machine runs this program here".into())
    }
}

/// The machine's clocks when it reached a line (Fanuc's #3001 and #3002), ns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Clocks {
    /// Machine time since the machine was switched on (the console's start).
    pub machine_ns: u64,
    /// Machine time with the cycle-start lamp lit (a run going, not held).
    pub cycle_ns: u64,
}

/// A probe move's outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probed {
    /// Where the machine stopped, machine mm (the gauge line): where the probe tripped (or
    /// came free), else the move's end.
    pub at: [f64; 3],
    /// The probe found what it sought (contact, or for G38.4/G38.5 its loss).
    pub tripped: bool,
    /// It was so already at the start: nothing moved.
    pub at_start: bool,
}

/// M66 on an input that stays low (0): L0 and L4 read 0 at once, the others time out.
pub fn low_input(mode: u32) -> Option<f64> {
    (mode == 0 || mode == 4).then_some(0.0)
}

/// A question a line asks of the machine (G38.x, M66, a clocks read), answered before the
/// next line is read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ask {
    /// A probe move (G38.2 … G38.5 ×10 in `g`) from `from` to `to` (machine mm, the gauge
    /// line) with the tool in the spindle's `length` and `radius`.
    Probe {
        /// 382 … 385.
        g: u16,
        /// The column of the G code.
        col: u32,
        /// Where the move starts.
        from: [f64; 3],
        /// Where it ends if nothing trips.
        to: [f64; 3],
        /// The tool's length, mm.
        length: f64,
        /// The tool's radius, mm.
        radius: f64,
    },
    /// M66: wait on input `index` as `mode` says, at most `timeout` s; the value goes to #5399.
    Input {
        /// The column of M66.
        col: u32,
        /// Digital (P) or analog (E).
        digital: bool,
        /// The input, 0 to 63.
        index: u32,
        /// L: 0 immediate, 1 rise, 2 fall, 3 high, 4 low.
        mode: u32,
        /// Q, seconds.
        timeout: f64,
    },
    /// Fanuc's #3001/#3002 read or written on a line in a run: the machine's clocks once it
    /// has executed every block before the line (its clocks block, `Canon::Clocks`); the line
    /// is read again with them.
    Clocks {
        /// The column of the variable.
        col: u32,
    },
}

/// Something a line did that its caller keeps or shows, besides the moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// A persistent parameter changed (G10 L2/L20, G28.1, G30.1, G92, a program's `#5221=`).
    Param(usize, f64),
    /// The tool data of T code `t` changed (G10 L1, L10, L11): its length and diameter, mm.
    Tool {
        /// The T code.
        t: u32,
        /// The new tool length, mm.
        length: f64,
        /// The new diameter, mm.
        diameter: f64,
    },
    /// A program set a tool offset (Fanuc's #2001–#2800, #10001–#13999): T code `t`'s data
    /// as it now is, mm.
    ToolOffsets {
        /// The T code (the offset number).
        t: u32,
        /// The set length.
        length: f64,
        /// The diameter.
        diameter: f64,
        /// The length wear.
        wear_length: f64,
        /// The diameter wear.
        wear_diameter: f64,
    },
    /// An operator message: `(MSG,...)`, `(DEBUG,...)`, `(PRINT,...)`, `(LOG,...)`.
    Message {
        /// The kind (`MSG`, `DEBUG`, `PRINT`, `LOG`).
        kind: &'static str,
        /// The text, parameters substituted.
        text: String,
    },
    /// A probe's result (#5061–#5070), in the coordinates of the system in force.
    Probe {
        /// Where it tripped (program units), or where it stopped.
        at: [f64; 3],
        /// Whether it tripped.
        tripped: bool,
    },
}

/// What a line asks of the program flow after it has executed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on with the next line.
    Next,
    /// M98 P L: call O-number `o`, `l` times.
    Call {
        /// The O number.
        o: u32,
        /// L, if given.
        l: Option<u32>,
        /// The column of M98.
        col: u32,
    },
    /// M6 or another M code remapped (docs/gcode.md "Remapping M6 and other M codes"): call
    /// the machine's subroutine; the line's steps after the code run when it returns.
    Remap {
        /// The code (6, or one of modal group 10).
        m: u32,
        /// Its column.
        col: u32,
    },
    /// M99: return from the subprogram.
    Return {
        /// The column of M99.
        col: u32,
    },
    /// M02 or M30: the program ends.
    End,
}

/// The code of modal group 10 on the line that the machine description remaps, with its
/// column (at most one: group 10 takes one code a line). Inside a remap subroutine it has no
/// meaning of its own to fall back on, and is refused.
fn remapped_m(x: &Exec, w: &Words) -> Result<Option<(u32, u32)>, TranslateError> {
    let Some((m, col)) =
        (x.settings.remap_m.iter()).find_map(|r| w.has_m(r.code).map(|c| (r.code, c)))
    else {
        return Ok(None);
    };
    if !x.remap_free {
        return Err(x.err(
            col,
            format!(
                "M{m} inside a remap subroutine: it is remapped by the machine description and novanc has no M{m} of its own"
            ),
        ));
    }
    Ok(Some((m, col)))
}

/// One line's execution context: what it produced and what it may use.
pub struct Exec<'a> {
    /// The line number.
    pub n: u32,
    /// Canonical actions with their line and column.
    pub out: Vec<(Canon, u32, u32)>,
    /// What else the line did.
    pub events: Vec<Event>,
    /// The machine's settings (travel, pulse).
    pub settings: &'a MachineSettings,
    /// The tool data (G10 L1 changes it).
    pub magazine: &'a mut Magazine,
    /// OPTIONAL STOP is on.
    pub optional_stop: bool,
    /// What the line asks of the machine, in order (its answers come before the next line).
    pub asks: Vec<Ask>,
    /// M6 calls the machine's remap subroutine (it is remapped, and no remap runs now:
    /// inside the remap, at any depth, M6 is the built-in change, as in LinuxCNC).
    pub remap_m6: bool,
    /// No remap subroutine runs now: a remapped M code of modal group 10 calls its own
    /// (inside one, it has no built-in meaning to fall back on, and is refused).
    pub remap_free: bool,
    /// The line's remapped code has run: execute only its steps after it (6: after M6, 10:
    /// after modal group 10's code; 0: the whole line).
    pub after: u8,
}

impl Exec<'_> {
    /// An error at column `col` of this line.
    pub fn err(&self, col: u32, message: impl Into<String>) -> TranslateError {
        TranslateError {
            line: self.n,
            col,
            message: message.into(),
        }
    }

    /// Adds a canonical action charged to `col`.
    pub fn push(&mut self, c: Canon, col: u32) {
        self.out.push((c, self.n, col));
    }

    /// Adds canonical actions all charged to `col`, growing the line's list once (a cycle line
    /// may make up to `MAX_BLOCKS`: doubling would hold three times their size at its peak).
    pub fn push_all(&mut self, cs: Vec<Canon>, col: u32) {
        self.out.reserve_exact(cs.len());
        let n = self.n;
        self.out.extend(cs.into_iter().map(|c| (c, n, col)));
    }

    /// The tool data of T code `t`: (length, diameter), mm.
    pub fn tool_data(&self, t: u32, col: u32, what: &str) -> Result<(f64, f64), TranslateError> {
        self.magazine
            .tools
            .get(t)
            .map(|r| (r.length(), r.cutting_diameter()))
            .ok_or_else(|| {
                self.err(
                    col,
                    format!("{what}{t} names T code {t}, which has no tool data in the tool file"),
                )
            })
    }
}

/// A whole number word between `lo` and `hi`.
pub fn int_word(
    x: &Exec,
    w: &Words,
    c: char,
    lo: f64,
    hi: f64,
) -> Result<Option<u32>, TranslateError> {
    match (w.get(c), w.col(c)) {
        (Some(v), Some(col)) => {
            let r = v.round();
            if (v - r).abs() > 1e-4 || r < lo || r > hi {
                return Err(x.err(
                    col,
                    format!(
                        "{c}{} must be a whole number from {lo} to {hi}",
                        crate::input_text::short_number(v)
                    ),
                ));
            }
            Ok(Some(r as u32))
        }
        _ => Ok(None),
    }
}

fn aux(m: u8) -> Canon {
    Canon::Aux {
        s: None,
        t: None,
        m: Some(m),
    }
}

/// The motion this line executes (LinuxCNC's `motion_to_be`), with its column.
fn motion_to_be(
    st: &InterpState,
    x: &Exec,
    w: &Words,
) -> Result<Option<(Motion, u32)>, TranslateError> {
    let mut given = None;
    for &(g, col) in w.g.as_slice() {
        let m = match g {
            0 => Motion::Rapid,
            10 => Motion::Feed,
            20 => Motion::Cw,
            30 => Motion::Ccw,
            50 | 51 if fanuc_look_ahead(x, w, g).is_some() => continue,
            50..=52 => Motion::Spline(g as u16),
            330 => Motion::Thread,
            331 => Motion::RigidTap,
            // G31 (Fanuc's skip: only its dialect's words have it) probes as G38.3 does.
            310 | 382..=385 => Motion::Probe(g as u16),
            // G76: Fanuc's fine boring (only its dialect's words have it).
            730 | 740 | 760 | 810..=890 => Motion::Cycle(g as u16),
            800 => Motion::None,
            _ => continue,
        };
        given = Some((m, col));
    }
    let axis =
        w.has_axis() || w.get('@').is_some() || w.get('^').is_some() || first_rotary(w).is_some();
    let covets = [100, 280, 300, 520, 680, 920]
        .iter()
        .find_map(|&g| w.has_g(g));
    if let Some((m, col)) = given {
        if m == Motion::None {
            if axis && covets.is_none() {
                return Err(x.err(col, "G80 cancels the motion mode: it takes no X, Y or Z"));
            }
        } else {
            if let Some(c) = covets {
                return Err(x.err(
                    c,
                    "two G codes that both use the axis words on one line (G10, G28, G30, G52 or G92 with a motion)",
                ));
            }
            if !axis
                && !matches!(
                    m,
                    Motion::Rapid | Motion::Feed | Motion::Cw | Motion::Ccw | Motion::Spline(52)
                )
            {
                return Err(x.err(col, "this motion needs at least one of X, Y and Z"));
            }
        }
        return Ok(Some((m, col)));
    }
    if covets.is_some() {
        return Ok(None);
    }
    if let Some(col) = w.has_g(530).filter(|_| fanuc_g53(x, w)) {
        // Fanuc's G53 positions at rapid whatever the motion in force (one shot).
        return Ok(Some((Motion::Rapid, col)));
    }
    let ijk = ['I', 'J', 'K'].iter().any(|&c| w.get(c).is_some());
    if axis {
        if st.modal.motion == Motion::None && w.has_g(431).is_none() {
            // The first axis word, named at its place (a rotary one too).
            let (l, col) = ['X', 'Y', 'Z', '@', '^', 'A', 'B', 'C']
                .into_iter()
                .filter_map(|l| Some((l, w.col(l)?)))
                .min_by_key(|&(_, c)| c)
                .unwrap_or(('X', 1));
            return Err(x.err(
                col,
                format!("{l} with no motion in force (G80): give G00, G01, G02, G03 or a cycle"),
            ));
        }
        if w.has_g(431).is_none() {
            let col = w
                .col('X')
                .or(w.col('Y'))
                .or(w.col('Z'))
                .or(w.col('@'))
                .or(w.col('^'))
                .unwrap_or(1);
            return Ok(Some((st.modal.motion, col)));
        }
    } else if ijk && matches!(st.modal.motion, Motion::Cw | Motion::Ccw) {
        let col = w.col('I').or(w.col('J')).or(w.col('K')).unwrap_or(1);
        return Ok(Some((st.modal.motion, col)));
    }
    Ok(None)
}

/// Refuses a word no code on the line uses (rs274's `check_other_codes`).
fn check_words(x: &Exec, w: &Words, motion: Option<Motion>) -> Result<(), TranslateError> {
    let mo = motion.map(|m| m.code()).unwrap_or(u16::MAX);
    let is = |codes: &[u16]| codes.contains(&mo);
    let cycle = matches!(motion, Some(Motion::Cycle(_)));
    let g = |c: u32| w.has_g(c).is_some();
    let m = |c: u32| w.has_m(c).is_some();
    // A remapped M code's argspec takes its letters (docs/gcode.md "Remapping M6 and other M
    // codes").
    let remap = (x.settings.remap_m.iter()).find(|r| w.has_m(r.code).is_some());
    let refuse = |c: char, msg: &str| -> Result<(), TranslateError> {
        if remap.is_some_and(|r| r.takes(c)) {
            return Ok(());
        }
        Err(x.err(
            w.col(c).unwrap_or(1),
            format!("{c} word with no {msg} to use it"),
        ))
    };
    // Asked last, only where a P or Q would otherwise be refused.
    let look_ahead = || {
        [50, 51, 80]
            .iter()
            .any(|&c| fanuc_look_ahead(x, w, c).is_some())
    };
    if w.get('D').is_some() && !(g(410) || g(420) || g(411) || g(421) || is(&[730, 830])) {
        refuse('D', "G41, G41.1, G42, G42.1, G73 or G83")?;
    }
    if w.get('E').is_some() && !(m(66) || m(67) || m(68)) {
        refuse('E', "M66, M67 or M68")?;
    }
    if w.get('H').is_some() && !(g(430) || g(432)) {
        refuse('H', "G43 or G43.2")?;
    }
    if w.get('I').is_some() && !(is(&[20, 30, 50, 51, 331, 870]) || g(100)) {
        refuse('I', "G2, G3, G5, G5.1, G10, G33.1 or G87")?;
    }
    if w.get('J').is_some() && !(is(&[20, 30, 50, 51, 870]) || g(100)) {
        refuse('J', "G2, G3, G5, G5.1, G10 or G87")?;
    }
    // Fanuc 0i's K repeats a canned cycle.
    let fanuc = x.settings.dialect == crate::settings::Dialect::Fanuc;
    if w.get('K').is_some() && !(is(&[20, 30, 330, 331, 870]) || (fanuc && cycle)) {
        refuse('K', "G2, G3, G33, G33.1 or G87")?;
    }
    if w.get('L').is_some()
        && !(cycle || is(&[52]) || g(100) || g(410) || g(420) || g(411) || g(421) || m(66) || m(98))
    {
        refuse('L', "G10, cutter compensation, canned cycle, M66 or M98")?;
    }
    if w.get('P').is_some()
        && !(g(100)
            || g(40)
            || g(640)
            || is(&[820, 860, 880, 890, 50, 52, 20, 30, 740, 760, 840])
            || (50..=53).any(m)
            || (62..=66).any(m)
            || m(19)
            || m(98)
            || look_ahead())
    {
        refuse(
            'P',
            "G2 G3 G4 G5 G5.2 G10 G64 G74 G82 G84 G86 G88 G89, M19, M50–M53, M62–M66 or M98",
        )?;
    }
    if let (Some(p), Some(col)) = (w.get('P'), w.col('P')) {
        if is(&[20, 30]) || m(19) {
            if (p - p.round()).abs() > 0.001 {
                return Err(x.err(col, "P must be a whole number with G2, G3 or M19"));
            }
            if is(&[20, 30]) && p.round() < 1.0 {
                return Err(x.err(col, "P (turns) must be 1 or more with G2 or G3"));
            }
        }
    }
    if w.get('Q').is_some()
        && !(is(&[830, 730, 760, 50])
            || (66..=68).any(m)
            || g(100)
            || m(61)
            || g(640)
            || m(19)
            || look_ahead())
    {
        refuse('Q', "G5, G10, G64, G73, G83, M19, M61, M66, M67 or M68")?;
    }
    if w.get('R').is_some()
        && !(is(&[20, 30, 730, 740]) || cycle || g(100) || g(680) || m(19) || look_ahead())
    {
        refuse('R', "G2, G3, a canned cycle, G10 or M19")?;
    }
    if w.get('S').is_none() && g(960) {
        return Err(x.err(1, "G96 needs S"));
    }
    if let Some(m @ (Motion::RigidTap | Motion::Thread)) = motion {
        let name = if m == Motion::Thread { "G33" } else { "G33.1" };
        if w.get('K').is_none() {
            return Err(x.err(1, format!("{name} needs K, the pitch")));
        }
        if w.get('F').is_some() {
            return Err(x.err(
                w.col('F').unwrap_or(1),
                format!("{name} takes no F: the feed follows the spindle"),
            ));
        }
    }
    if (w.get('@').is_some() || w.get('^').is_some())
        && (w.get('X').is_some() || w.get('Y').is_some())
    {
        let c = if w.get('X').is_some() { 'X' } else { 'Y' };
        return Err(x.err(
            w.col(c).unwrap_or(1),
            "polar coordinates (@ ^) and X or Y on one line",
        ));
    }
    Ok(())
}

/// Substitutes `#n` and `#<name>` in a PRINT or DEBUG text with their values (`%lf`-style,
/// six decimals, as LinuxCNC prints them).
pub fn substitute(text: &str, lookup: &dyn Fn(&str) -> Option<f64>) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'#' {
            if b.get(i + 1) == Some(&b'<') {
                if let Some(end) = text[i + 2..].find('>') {
                    let name: String = text[i + 2..i + 2 + end]
                        .chars()
                        .filter(|c| !c.is_whitespace())
                        .collect::<String>()
                        .to_ascii_lowercase();
                    match lookup(&name) {
                        Some(v) => out.push_str(&format!("{v:.6}")),
                        None => out.push_str("######"),
                    }
                    i += end + 3;
                    continue;
                }
            } else {
                let digits: String = text[i + 1..]
                    .chars()
                    .take_while(|c| c.is_ascii_digit())
                    .collect();
                if !digits.is_empty() {
                    match lookup(&digits) {
                        Some(v) => out.push_str(&format!("{v:.6}")),
                        None => out.push_str("######"),
                    }
                    i += 1 + digits.len();
                    continue;
                }
            }
        }
        let ch = text[i..].chars().next().unwrap_or(' ');
        out.push(ch);
        i += ch.len_utf8();
    }
    out
}

/// The comments of a line, first of all: messages go to the operator, ABORT stops.
pub fn comments(
    x: &mut Exec,
    cs: &[Comment],
    lookup: &dyn Fn(&str) -> Option<f64>,
    debug_on: bool,
) -> Result<(), TranslateError> {
    for c in cs {
        match c.kind {
            CommentKind::Plain => {}
            CommentKind::Msg => x.events.push(Event::Message {
                kind: "MSG",
                text: c.text.trim().to_string(),
            }),
            CommentKind::Debug if debug_on => x.events.push(Event::Message {
                kind: "DEBUG",
                text: substitute(&c.text, lookup),
            }),
            CommentKind::Debug => {}
            CommentKind::Print => x.events.push(Event::Message {
                kind: "PRINT",
                text: substitute(&c.text, lookup),
            }),
            CommentKind::Log if c.keyword == "LOG" => x.events.push(Event::Message {
                kind: "LOG",
                text: substitute(&c.text, lookup),
            }),
            // A program writes no file on the machine: the operator is told where the lines
            // go instead (docs/gcode.md "Messages").
            CommentKind::Log => x.events.push(Event::Message {
                kind: "LOG",
                text: format!(
                    "({}{}): novanc writes no log file; LOG lines go to the MSG page and the recording",
                    c.keyword,
                    if c.text.trim().is_empty() { String::new() } else { format!(",{}", c.text.trim()) }
                ),
            }),
            CommentKind::ProbeLog => x.events.push(Event::Message {
                kind: "LOG",
                text: format!(
                    "({}): novanc writes no probe file; probe results go to the recording",
                    c.keyword
                ),
            }),
            CommentKind::Abort => {
                return Err(x.err(
                    c.col,
                    format!("(ABORT) {}", substitute(&c.text, lookup).trim()),
                ));
            }
        }
    }
    Ok(())
}

/// Executes one sorted line on the state.
pub fn execute(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<Flow, TranslateError> {
    let motion = motion_to_be(st, x, w)?;
    check_words(x, w, motion.map(|m| m.0))?;
    let mut inverse_feed = None;
    // The feed mode, then F.
    for (g, mode) in [
        (930, FeedMode::InverseTime),
        (940, FeedMode::PerMinute),
        (950, FeedMode::PerRevolution),
    ] {
        if let Some(col) = w.has_g(g) {
            if comp.active() && mode != st.modal.feed_mode {
                let _ = col;
            }
            st.modal.feed_mode = mode;
        }
    }
    if let Some(f) = w.get('F') {
        let col = w.col('F').unwrap_or(1);
        if f < 0.0 {
            return Err(x.err(col, "a negative F"));
        }
        // F0 is no feed (a feed move then asks for one); a feed per minute that is not 0 is
        // at least the slowest (docs/limits.md).
        if st.modal.feed_mode == FeedMode::PerMinute
            && f > 0.0
            && f * st.factor() < crate::limits::MIN_FEED
        {
            let text = if st.modal.inch {
                format!(
                    "F{} ({:.3} mm/min)",
                    crate::input_text::short_number(f),
                    f * st.factor()
                )
            } else {
                format!("F{}", crate::input_text::short_number(f))
            };
            return Err(x.err(col, crate::limits::feed_too_slow(&text)));
        }
        if st.modal.feed_mode == FeedMode::InverseTime {
            inverse_feed = Some(f);
        } else {
            st.modal.feed = f * st.factor();
        }
    }
    if st.modal.feed_mode == FeedMode::InverseTime {
        if let Some((m, col)) = motion {
            if matches!(
                m,
                Motion::Feed
                    | Motion::Cw
                    | Motion::Ccw
                    | Motion::Cycle(_)
                    | Motion::Spline(50 | 51)
            ) && inverse_feed.is_none()
            {
                return Err(x.err(
                    col,
                    "inverse time feed (G93): each feed move needs its own F",
                ));
            }
        }
    }
    // Everything but the motion (a plain move has none of it: `Words::plain`).
    if !w.plain() {
        // S and T.
        let mut aux_s = None;
        // S, T and the I/O codes ran before a remapped M6 called its subroutine; up to the
        // override codes, before a remapped code of modal group 10 called its own.
        let before_m6 = x.after < 6;
        let before_m10 = x.after < 10;
        if let Some(s) = w.get('S').filter(|_| before_m6) {
            if !(0.0..=crate::translator::MAX_SPEED).contains(&s) {
                return Err(x.err(
                    w.col('S').unwrap_or(1),
                    format!(
                        "spindle speed S{} is not usable (0 to {} rpm)",
                        crate::input_text::short_number(s),
                        crate::translator::MAX_SPEED
                    ),
                ));
            }
            st.modal.speed = s;
            aux_s = Some(s.round() as u32);
        }
        let mut aux_t = None;
        if let Some(t) = int_word(x, w, 'T', 0.0, 999.0)?.filter(|_| before_m6) {
            let col = w.col('T').unwrap_or(1);
            if t != 0 {
                x.tool_data(t, col, "T")?;
            }
            st.selected = Some(t);
            aux_t = Some(t);
        }
        // I/O.
        if before_m6 {
            io_codes(st, comp, x, w)?;
        }
        // The tool change.
        if let Some(col) = w.has_m(6).filter(|_| before_m6) {
            let t = st
                .selected
                .ok_or_else(|| x.err(col, "M06 without a T word before it: which tool?"))?;
            if st.modal.comp != CompSide::Off {
                return Err(x.err(
                    col,
                    "cannot change tools with cutter radius compensation on",
                ));
            }
            if x.remap_m6 {
                // The machine's subroutine changes the tool; T (and S) are selected first.
                if aux_t.is_some() || aux_s.is_some() {
                    comp.aux(
                        x,
                        Canon::Aux {
                            s: aux_s,
                            t: aux_t,
                            m: None,
                        },
                        w.col('T').or(w.col('S')).unwrap_or(col),
                    );
                }
                return Ok(Flow::Remap { m: 6, col });
            }
            tool_change(st, comp, x, t, col);
            aux_t = None;
        }
        // M61 to the override codes: done before a remapped code of modal group 10 called its
        // subroutine.
        if before_m10 {
            if let Some(col) = w.has_m(61) {
                let q = int_word(x, w, 'Q', 0.0, 999.0)?
                    .ok_or_else(|| x.err(col, "M61 needs Q, the tool now in the spindle"))?;
                if q != 0 {
                    x.tool_data(q, w.col('Q').unwrap_or(col), "Q")?;
                }
                st.tool = (q != 0).then_some(q);
                st.params[5400] = f64::from(q);
            }
            let spindle_m = [3u32, 4, 5]
                .into_iter()
                .find_map(|m| w.has_m(m).map(|c| (m, c)));
            if aux_t.is_some() || (aux_s.is_some() && spindle_m.is_none()) {
                comp.aux(
                    x,
                    Canon::Aux {
                        s: aux_s.take(),
                        t: aux_t,
                        m: None,
                    },
                    w.col('T').or(w.col('S')).unwrap_or(1),
                );
            }
            if let Some((m, col)) = spindle_m {
                st.modal.spindle = match m {
                    3 => 1,
                    4 => -1,
                    _ => 0,
                };
                let s = if m == 5 {
                    aux_s
                } else {
                    Some(aux_s.unwrap_or(st.modal.speed.round() as u32))
                };
                comp.aux(
                    x,
                    Canon::Aux {
                        s,
                        t: None,
                        m: Some(m as u8),
                    },
                    col,
                );
            }
            if let Some(col) = w.has_m(29) {
                // Fanuc's rigid tapping mode (only its dialect reads M29): the S on the line or in
                // force is the tap's speed.
                if st.modal.speed < 1.0 {
                    return Err(x.err(col, "M29 (rigid tapping) needs S, the tap's rpm: M29 S500"));
                }
                st.cycle.rigid = true;
            }
            if let Some(col) = w.has_m(19) {
                st.modal.spindle = 0;
                let angle = w.get('R').unwrap_or(0.0);
                if !(0.0..=360.0).contains(&angle) {
                    return Err(x.err(
                        w.col('R').unwrap_or(col),
                        "M19 R (the angle) must be 0 to 360",
                    ));
                }
                if let Some(q) = w.get('Q') {
                    if q <= 0.0 {
                        return Err(x.err(
                            w.col('Q').unwrap_or(col),
                            "M19 Q (the time allowed) must be greater than 0",
                        ));
                    }
                }
                let dir = int_word(x, w, 'P', 0.0, 2.0)?.unwrap_or(0);
                comp.aux(
                    x,
                    Canon::Io(Io::Orient {
                        angle,
                        dir: dir as u8,
                    }),
                    col,
                );
            }
            modal_state_codes(st, x, w)?;
            for (m, mist, flood) in [
                (7u32, Some(true), None),
                (8, None, Some(true)),
                (9, Some(false), Some(false)),
            ] {
                if let Some(col) = w.has_m(m) {
                    if let Some(v) = mist {
                        st.modal.mist = v;
                    }
                    if let Some(v) = flood {
                        st.modal.flood = v;
                    }
                    comp.aux(x, aux(m as u8), col);
                }
            }
            override_codes(st, comp, x, w)?;
            // A code of modal group 10 the machine description remaps calls its subroutine;
            // the line's steps after it (G4, the plane, ..., the motion) run on its return.
            if let Some((m, col)) = remapped_m(x, w)? {
                return Ok(Flow::Remap { m, col });
            }
        }
        // G04.
        if let Some(col) = w.has_g(40) {
            let p = w
                .get('P')
                .ok_or_else(|| x.err(col, "G04 needs P, the dwell in seconds"))?;
            if p < 0.0 {
                return Err(x.err(w.col('P').unwrap_or(col), "a negative dwell P"));
            }
            if p > crate::limits::MAX_DWELL_S {
                return Err(x.err(
                    w.col('P').unwrap_or(col),
                    crate::limits::dwell_too_long(&format!(
                        "P{}",
                        crate::input_text::short_number(p)
                    )),
                ));
            }
            if matches!(motion, Some((Motion::Cw | Motion::Ccw, _))) {
                return Err(x.err(col, "G4 and G2/G3 on one line both use P"));
            }
            comp.aux(x, Canon::Dwell(p), col);
        }
        // The plane.
        for (g, p) in [(170, Plane::XY), (180, Plane::XZ), (190, Plane::YZ)] {
            if let Some(col) = w.has_g(g) {
                if comp.active() && p != st.modal.plane {
                    return Err(x.err(
                        col,
                        "cannot change the plane with cutter radius compensation on",
                    ));
                }
                st.modal.plane = p;
            }
        }
        // Units.
        for (g, inch) in [(200, true), (210, false)] {
            if w.has_g(g).is_some() {
                st.modal.inch = inch;
            }
        }
        // Compensation's tolerances are in the program's units, as LinuxCNC's (which lets
        // the units change under compensation).
        comp.set_inch(st.modal.inch);
        cutter_comp(st, comp, x, w)?;
        tool_length(st, comp, x, w)?;
        for (i, g) in [540u32, 550, 560, 570, 580, 590, 591, 592, 593]
            .into_iter()
            .enumerate()
        {
            if let Some(col) = w.has_g(g) {
                if comp.active() {
                    return Err(x.err(
                        col,
                        "cannot change the coordinate system with cutter radius compensation on",
                    ));
                }
                st.select_system(i);
            }
        }
        path_control(st, comp, x, w)?;
        if w.has_g(900).is_some() {
            st.modal.incremental = false;
        }
        if w.has_g(910).is_some() {
            st.modal.incremental = true;
        }
        if w.has_g(901).is_some() {
            st.modal.ijk_absolute = true;
        }
        if w.has_g(911).is_some() {
            st.modal.ijk_absolute = false;
        }
        coordinate_rotation(st, comp, x, w)?;
        if let Some(col) = w.has_g(980).or(w.has_g(990)) {
            if comp.active() {
                return Err(x.err(
                    col,
                    "cannot change the retract mode (G98, G99) with cutter radius compensation on",
                ));
            }
            st.modal.retract_r = w.has_g(990).is_some();
        }
        // The non-modal codes.
        if let Some(col) = w.has_g(100) {
            moves::g10(st, comp, x, w, col)?;
        } else if let Some(col) = w.has_g(280).or(w.has_g(300)) {
            if comp.active() {
                return Err(x.err(
                    col,
                    "G28 and G30 cannot be used with cutter radius compensation on",
                ));
            }
            let rotary = rotary_words(st, x, w)?;
            moves::home(st, x, w, w.has_g(300).is_some(), col, rotary)?;
        } else if let Some(col) = w.has_g(281).or(w.has_g(301)) {
            if comp.active() {
                return Err(x.err(
                    col,
                    "cannot set a reference point with cutter radius compensation on",
                ));
            }
            let base = if w.has_g(281).is_some() { 5161 } else { 5181 };
            for a in 0..3 {
                st.params[base + a] = st.pos[a];
                x.events.push(Event::Param(base + a, st.pos[a]));
            }
            // The rotary axes the machine has, as LinuxCNC stores every axis.
            for r in (0..3).filter(|&r| st.rotaries[r].is_some()) {
                st.params[base + 3 + r] = st.abc[r];
                x.events.push(Event::Param(base + 3 + r, st.abc[r]));
            }
        } else if let Some(col) = w
            .has_g(920)
            .or(w.has_g(520))
            .or(w.has_g(921))
            .or(w.has_g(922))
            .or(w.has_g(923))
        {
            moves::g92(st, comp, x, w, col)?;
        } else if let Some(col) = w.has_g(53) {
            let m = motion.map(|m| m.0);
            super::spline::end_nurbs(st, comp, x, w, m, col, inverse_feed)?;
        }
        if let Some(col) = w.has_g(530) {
            match motion {
                Some((Motion::Rapid | Motion::Feed, _)) => {}
                _ => return Err(x.err(col, "G53 moves with G00 or G01 (on its line or in force)")),
            }
            if st.modal.incremental {
                return Err(x.err(col, "G53 cannot be used in incremental mode (G91)"));
            }
            if comp.offsetting() {
                return Err(x.err(col, "G53 cannot be used with cutter radius compensation on"));
            }
        }
    }
    // A rotary axis word moves with G00 or G01 only (docs/gcode.md "Rotary axes").
    if let Some(r) = first_rotary(w) {
        rotary_allowed(comp, x, w, motion.map(|m| m.0), r)?;
    }
    // The motion.
    if let Some((m, col)) = motion {
        if m != Motion::Spline(52) {
            super::spline::unfinished(st, x.n, col, "this motion")?;
        }
        if !matches!(m, Motion::Cycle(_)) {
            st.cycle.il = None;
        }
        if w.has_g(530).is_some() {
            let k = st.factor();
            let mut e = st.pos;
            for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                if let Some(v) = w.get(c) {
                    e[i] = v * k;
                }
            }
            if first_rotary(w).is_some() {
                // The rotary axes' machine position is their program position.
                rotary_move(st, x, inverse_feed, m, e, w)?;
            } else {
                let feed = feed_for(st, x, inverse_feed, m, e, col)?;
                comp.line(x, st.pos, e, m == Motion::Rapid, feed, col)?;
                st.pos = e;
            }
            if !fanuc_g53(x, w) {
                st.modal.motion = m;
            }
        } else {
            motion_line(st, comp, x, w, m, col, inverse_feed)?;
        }
    }
    if w.m.as_slice().is_empty() {
        return Ok(Flow::Next);
    }
    // Stops and program flow, last. A stop first emits what compensation holds (LinuxCNC's
    // convert_stop), whether or not M01 stops.
    if let Some(col) = w.has_m(0).or(w.has_m(1)).or(w.has_m(60)) {
        comp.flush(x, col)?;
    }
    if let Some(col) = w.has_m(0) {
        comp.aux(x, aux(0), col);
    }
    if let Some(col) = w.has_m(1) {
        if x.optional_stop {
            comp.aux(x, aux(1), col);
        }
    }
    if let Some(col) = w.has_m(60) {
        comp.aux(x, aux(0), col);
    }
    if let Some(col) = w.has_m(98) {
        let p = int_word(x, w, 'P', 0.0, 99_999_999.0)?
            .ok_or_else(|| x.err(col, "M98 needs P, the O number of the subprogram"))?;
        let l = int_word(x, w, 'L', 0.0, super::MAX_REPEATS as f64)?;
        return Ok(Flow::Call { o: p, l, col });
    }
    if let Some(col) = w.has_m(99) {
        return Ok(Flow::Return { col });
    }
    if let Some(col) = w.has_m(2).or(w.has_m(30)) {
        super::spline::unfinished(st, x.n, col, "the program's end")?;
        return Ok(Flow::End);
    }
    Ok(Flow::Next)
}

/// The rotary axes' letters, A B C (their words on a line: `rotary_words`).
pub(super) const ROTARY_LETTERS: [char; 3] = ['A', 'B', 'C'];

/// The first rotary axis word on the line (A, B or C), with its letter and column.
fn first_rotary(w: &Words) -> Option<(char, u32)> {
    ROTARY_LETTERS
        .into_iter()
        .filter_map(|l| Some((l, w.col(l)?)))
        .min_by_key(|&(_, c)| c)
}

/// The rotary axis words of a line the machine has (A, B, C: value and column each); a word
/// of an axis it has not is refused at its place.
pub(super) fn rotary_given(
    st: &InterpState,
    x: &Exec,
    w: &Words,
) -> Result<[Option<(f64, u32)>; 3], TranslateError> {
    let mut given = [None; 3];
    for (r, l) in ROTARY_LETTERS.into_iter().enumerate() {
        let (Some(v), Some(col)) = (w.get(l), w.col(l)) else {
            continue;
        };
        if st.rotaries[r].is_none() {
            return Err(x.err(
                col,
                format!("unknown word {l} (novanc has the axes {})", st.axes_named()),
            ));
        }
        given[r] = Some((v, col));
    }
    Ok(given)
}

/// The rotary axis words of a line: where they take A, B, C (machine degrees, as a G00 would:
/// the axes not named stay), and which are named. G28 and G30 take them as their intermediate
/// point. A word is a program position (its axis's offsets added, LinuxCNC's order), or with
/// G53 a machine position.
fn rotary_words(
    st: &InterpState,
    x: &Exec,
    w: &Words,
) -> Result<([f64; 3], [bool; 3]), TranslateError> {
    let (mut mid, mut named) = (st.abc, [false; 3]);
    let (off, at) = (st.abc_offset(), st.prog_abc());
    let g53 = w.has_g(530).is_some();
    for (r, given) in rotary_given(st, x, w)?.into_iter().enumerate() {
        let Some((v, col)) = given else {
            continue;
        };
        let wrapped = st.rotaries[r] == Some(true);
        // With G53 the word is where the axis goes on the machine: LinuxCNC takes it to the
        // program frame and unwraps it there.
        let commanded = if g53 { v - off[r] } else { v };
        let l = ROTARY_LETTERS[r];
        let to = rotary_target(
            x,
            st.modal.incremental,
            wrapped,
            at[r],
            (l, v, commanded, col),
        )?;
        mid[r] = to + off[r];
        named[r] = true;
    }
    Ok((mid, named))
}

/// Refuses a rotary axis word (A, B or C) anywhere but on a G00 or G01 move without cutter
/// compensation (G53 among them), G28 or G30, or the offsets that take it: G10 L2 and L20,
/// G92 and G52 (their own functions refuse it where it is not theirs).
fn rotary_allowed(
    comp: &Comp,
    x: &Exec,
    w: &Words,
    motion: Option<Motion>,
    (l, col): (char, u32),
) -> Result<(), TranslateError> {
    // Refused here, at its place, rather than by the kernel at the block: a kernel's refusal
    // came after the line had been read, and the run's modes stood as if it had moved (found
    // by the operator sequences on a trunnion, stop 53).
    if x.settings.interpolator != crate::settings::Interpolator::Dda {
        return Err(x.err(
            col,
            format!(
                "{l} is run by the DDA interpolator only (this machine runs the {} one)",
                x.settings.interpolator.name()
            ),
        ));
    }
    if [280, 300, 100, 920, 520]
        .iter()
        .any(|&g| w.has_g(g).is_some())
    {
        // G28 and G30 take the axis words (the motion in force does not), and so do the
        // offsets.
        return Ok(());
    }
    for (g, what) in [
        (40, "G4"),
        (281, "G28.1"),
        (301, "G30.1"),
        (921, "G92.1"),
        (922, "G92.2"),
        (923, "G92.3"),
    ] {
        if w.has_g(g).is_some() {
            return Err(x.err(col, format!("{l} cannot be given with {what}")));
        }
    }
    if !matches!(motion, Some(Motion::Rapid | Motion::Feed)) {
        return Err(x.err(
            col,
            format!("{l} moves with G00 or G01 only (arcs, cycles, probes and splines are X Y Z)"),
        ));
    }
    if comp.active() {
        return Err(x.err(
            col,
            format!("{l} cannot move with cutter radius compensation on"),
        ));
    }
    Ok(())
}

/// Where a rotary axis word `l``v` (degrees) takes its axis from `at` (program frame): G91 by
/// `v`; G90 to `commanded` (`v`, or with G53 `v` in the program frame), on a wrapped axis by
/// LinuxCNC's WRAPPED_ROTARY rule (|v| below 360, the position modulo 360 that of
/// |commanded|, and v's sign the direction of the turn).
fn rotary_target(
    x: &Exec,
    incremental: bool,
    wrapped: bool,
    at: f64,
    (l, v, commanded, col): (char, f64, f64, u32),
) -> Result<f64, TranslateError> {
    let to = if incremental {
        at + v
    } else if wrapped {
        if v.abs() >= 360.0 {
            return Err(x.err(
                col,
                format!("{l}{v}: a wrapped rotary axis takes an absolute position within ±360 (its sign the direction)"),
            ));
        }
        // LinuxCNC's unwrap_rotary: the nearest position ≡ |commanded| (mod 360) in the
        // direction of v's sign (A-0 turns backwards).
        let base = (at / 360.0).floor() * 360.0 + commanded.abs();
        if v.is_sign_negative() {
            if base > at {
                base - 360.0
            } else {
                base
            }
        } else if base < at {
            base + 360.0
        } else {
            base
        }
    } else {
        commanded
    };
    if !to.is_finite() || to.abs() > 1e9 {
        return Err(x.err(col, format!("{l}{v}: out of all range")));
    }
    Ok(to)
}

/// A G00 or G01 to `e` (machine mm) with the rotary axis words of `w` (A, B, C, degrees;
/// [`rotary_target`]). The feed is along X Y Z; a move of rotary axes alone is fed in degrees
/// per minute along their combined turn (LinuxCNC's rule).
fn rotary_move(
    st: &mut InterpState,
    x: &mut Exec,
    inverse: Option<f64>,
    m: Motion,
    e: [f64; 3],
    w: &Words,
) -> Result<(), TranslateError> {
    let (to, _) = rotary_words(st, x, w)?;
    let feed = if m == Motion::Rapid {
        0.0
    } else {
        let d =
            ((e[0] - st.pos[0]).powi(2) + (e[1] - st.pos[1]).powi(2) + (e[2] - st.pos[2]).powi(2))
                .sqrt();
        let turn = (0..3)
            .map(|r| (to[r] - st.abc[r]).powi(2))
            .sum::<f64>()
            .sqrt();
        let d = if d > 0.0 { d } else { turn };
        let col = first_rotary(w).map_or(0, |(_, c)| c);
        feed_rate(st, x, inverse, d, col)?
    };
    let col = first_rotary(w).map_or(0, |(_, c)| c);
    x.push(
        Canon::Turn {
            end: e,
            abc: to,
            feed: (m == Motion::Feed).then_some(feed),
        },
        col,
    );
    st.pos = e;
    st.abc = to;
    Ok(())
}

/// The feed of a feed move to `e`: F in force, or under G93 the length over the time, or
/// under G95 F × S.
fn feed_for(
    st: &InterpState,
    x: &Exec,
    inverse: Option<f64>,
    m: Motion,
    e: [f64; 3],
    col: u32,
) -> Result<f64, TranslateError> {
    if m == Motion::Rapid {
        return Ok(0.0);
    }
    let d = ((e[0] - st.pos[0]).powi(2) + (e[1] - st.pos[1]).powi(2) + (e[2] - st.pos[2]).powi(2))
        .sqrt();
    feed_rate(st, x, inverse, d, col)
}

/// The feed (mm/min) of a feed move `length` mm long: F in force (G94), F × S (G95), or under
/// G93 the length over the time the line's F (`inverse`, 1/min) gives.
pub fn feed_rate(
    st: &InterpState,
    x: &Exec,
    inverse: Option<f64>,
    length: f64,
    col: u32,
) -> Result<f64, TranslateError> {
    match st.modal.feed_mode {
        FeedMode::InverseTime => {
            let f = inverse.unwrap_or(0.0);
            if f <= 0.0 {
                return Err(x.err(col, "inverse time feed (G93) needs F greater than 0"));
            }
            Ok(length * f)
        }
        FeedMode::PerRevolution => {
            if st.modal.speed <= 0.0 || st.modal.spindle == 0 {
                return Err(x.err(
                    col,
                    "feed per revolution (G95) needs the spindle turning (S and M03/M04)",
                ));
            }
            Ok(st.modal.feed * st.modal.speed)
        }
        FeedMode::PerMinute => {
            if st.modal.feed <= 0.0 {
                return Err(x.err(
                    col,
                    "a feed move without F: give F (mm/min, or in/min under G20)",
                ));
            }
            Ok(st.modal.feed)
        }
    }
}

fn motion_line(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
    m: Motion,
    col: u32,
    inverse: Option<f64>,
) -> Result<(), TranslateError> {
    match m {
        Motion::None => {
            st.modal.motion = Motion::None;
            st.cycle.rigid = false;
            Ok(())
        }
        Motion::Rapid | Motion::Feed => {
            st.modal.motion = m;
            st.cycle.rigid = false;
            // G00 or G01 without axis words (given on the line, or there is no motion) moves
            // to the programmed point, as LinuxCNC's: nowhere, or after G40 off the last
            // offset point; right after G41/G42 it is an entry move too short.
            let e = if w.has_axis() || w.get('@').is_some() || w.get('^').is_some() {
                moves::target(st, x, w)?
            } else {
                st.pos
            };
            if first_rotary(w).is_some() {
                return rotary_move(st, x, inverse, m, e, w);
            }
            let feed = feed_for(st, x, inverse, m, e, col)?;
            comp.line(x, st.pos, e, m == Motion::Rapid, feed, col)?;
            st.pos = e;
            Ok(())
        }
        Motion::Cw | Motion::Ccw => {
            st.modal.motion = m;
            st.cycle.rigid = false;
            if !(w.has_axis()
                || ['I', 'J', 'K', 'R', '@', '^']
                    .iter()
                    .any(|&c| w.get(c).is_some()))
            {
                return Ok(());
            }
            moves::arc(st, comp, x, w, col, inverse)
        }
        Motion::Cycle(g) => {
            if st.modal.feed_mode == FeedMode::InverseTime {
                return Err(x.err(
                    col,
                    "canned cycles cannot be used in inverse time feed (G93)",
                ));
            }
            if comp.active() {
                return Err(x.err(
                    col,
                    "canned cycles cannot be used with cutter radius compensation on",
                ));
            }
            super::cycles::cycle(st, x, w, g, col)?;
            st.modal.motion = m;
            Ok(())
        }
        Motion::Probe(g) => {
            // Fanuc's G31 is one-shot (group 00): the motion mode stays as it was.
            if g != 310 {
                st.modal.motion = m;
            }
            super::probe::probe(st, comp, x, w, g, col)
        }
        Motion::Spline(g) => {
            // G5 and G5.1 leave the motion mode as it was, as LinuxCNC 2.9's do: the next line
            // of X Y alone is a move of that mode. G5.2 stays in force until G5.3.
            if g == 52 {
                st.modal.motion = m;
            }
            super::spline::spline(st, comp, x, w, g, col, inverse)
        }
        Motion::RigidTap => {
            super::cycles::rigid_tap(st, comp.active(), x, w, col)?;
            st.modal.motion = m;
            Ok(())
        }
        Motion::Thread => {
            super::cycles::thread(st, comp.active(), x, w, col)?;
            st.modal.motion = m;
            Ok(())
        }
    }
}

/// The M codes of `range` on the line with their columns, in order; refused under cutter
/// compensation (LinuxCNC refuses I/O and override codes there: they would flush its queue).
fn m_codes_without_comp(
    range: std::ops::RangeInclusive<u32>,
    comp: &Comp,
    x: &Exec,
    w: &Words,
) -> Result<Vec<(u32, u32)>, TranslateError> {
    if w.m.as_slice().is_empty() {
        return Ok(Vec::new());
    }
    let on: Vec<(u32, u32)> = range.filter_map(|m| w.has_m(m).map(|c| (m, c))).collect();
    match on.first() {
        Some(&(m, col)) if comp.active() => Err(x.err(
            col,
            format!("M{m} cannot be used with cutter radius compensation on"),
        )),
        _ => Ok(on),
    }
}

fn io_codes(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    for (m, col) in m_codes_without_comp(62..=68, comp, x, w)? {
        match m {
            62..=65 => {
                let p = int_word(x, w, 'P', 0.0, 63.0)?
                    .ok_or_else(|| x.err(col, format!("M{m} needs P, the output 0 to 63")))?;
                let on = m == 62 || m == 64;
                st.digital_out[p as usize] = on;
                x.push(
                    Canon::Io(Io::Digital {
                        index: p as u8,
                        on,
                        synced: m <= 63,
                    }),
                    col,
                );
            }
            66 => {
                if w.get('P').is_some() && w.get('E').is_some() {
                    return Err(x.err(
                        col,
                        "M66 waits on a digital input (P) or an analog one (E), not both",
                    ));
                }
                let l = int_word(x, w, 'L', 0.0, 4.0)?.unwrap_or(0);
                let q = w.get('Q').unwrap_or(0.0);
                if l > 0 && q <= 0.0 {
                    return Err(x.err(
                        col,
                        "M66 with a wait mode L needs a timeout Q greater than 0",
                    ));
                }
                let (digital, index) = match (
                    int_word(x, w, 'P', 0.0, 63.0)?,
                    int_word(x, w, 'E', 0.0, 63.0)?,
                ) {
                    (Some(p), _) => (true, p),
                    (None, Some(e)) => {
                        if l != 0 {
                            return Err(
                                x.err(col, "M66 on an analog input (E) reads at once: L0 only")
                            );
                        }
                        (false, e)
                    }
                    (None, None) => {
                        return Err(x.err(col, "M66 needs P (a digital input) or E (an analog one)"))
                    }
                };
                comp.flush(x, col)?;
                x.push(
                    Canon::Io(Io::Wait {
                        digital,
                        index: index as u8,
                        mode: l as u8,
                        timeout: q,
                    }),
                    col,
                );
                x.asks.push(Ask::Input {
                    col,
                    digital,
                    index,
                    mode: l,
                    timeout: q,
                });
            }
            _ => {
                let e = int_word(x, w, 'E', 0.0, 63.0)?.ok_or_else(|| {
                    x.err(col, format!("M{m} needs E, the analog output 0 to 63"))
                })?;
                let q = w.get('Q').unwrap_or(0.0);
                st.analog_out[e as usize] = q;
                x.push(
                    Canon::Io(Io::Analog {
                        index: e as u8,
                        value: q,
                        synced: m == 67,
                    }),
                    col,
                );
            }
        }
    }
    Ok(())
}

/// M70 save, M71 invalidate, M72 restore, M73 save and restore on return.
fn modal_state_codes(st: &mut InterpState, x: &mut Exec, w: &Words) -> Result<(), TranslateError> {
    let level = st.call_level;
    if st.saved.len() <= level {
        st.saved.resize(level + 1, None);
    }
    if w.has_m(70).is_some() || w.has_m(73).is_some() {
        st.saved[level] = Some(Saved {
            modal: st.modal,
            auto_restore: w.has_m(73).is_some() && level > 0,
        });
    }
    if w.has_m(71).is_some() {
        st.saved[level] = None;
    }
    if let Some(col) = w.has_m(72) {
        let Some(s) = st.saved[level].clone() else {
            return Err(x.err(col, "M72: no state saved by M70 or M73 at this call level"));
        };
        st.modal = s.modal;
        st.select_system(s.modal.cs);
    }
    Ok(())
}

fn override_codes(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    for (m, col) in m_codes_without_comp(48..=53, comp, x, w)? {
        let on = w.get('P').is_none_or(|p| p != 0.0);
        match m {
            48 => {
                st.modal.feed_override = true;
                st.modal.speed_override = true;
            }
            49 => {
                st.modal.feed_override = false;
                st.modal.speed_override = false;
            }
            50 => st.modal.feed_override = on,
            51 => st.modal.speed_override = on,
            52 => st.modal.adaptive_feed = on,
            _ => st.modal.feed_hold = on,
        }
        x.push(
            Canon::Io(Io::Overrides {
                feed: st.modal.feed_override,
                speed: st.modal.speed_override,
            }),
            col,
        );
    }
    Ok(())
}

fn cutter_comp(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    if let Some(col) = w.has_g(400) {
        comp.off(x, col)?;
        st.modal.comp = CompSide::Off;
        st.comp_radius = 0.0;
        st.comp_tool = None;
    }
    for (g, left) in [(410, true), (420, false), (411, true), (421, false)] {
        let Some(col) = w.has_g(g) else {
            continue;
        };
        let dynamic = g % 10 == 1;
        if comp.active() {
            return Err(x.err(col, "cutter radius compensation is already on: G40 first"));
        }
        if st.modal.plane == Plane::YZ {
            return Err(x.err(
                col,
                "cutter radius compensation works in the XY (G17) and XZ (G18) planes, not in YZ (G19)",
            ));
        }
        let d_col = w.col('D').unwrap_or(col);
        let (radius, t) = if dynamic {
            // G41.1/G42.1: D is the tool's diameter itself (L, the lathe orientation, is not
            // for a mill).
            if let Some(lc) = w.col('L') {
                return Err(x.err(lc, "L (the tool orientation) of G41.1/G42.1 is the lathe's"));
            }
            let d = w
                .get('D')
                .ok_or_else(|| x.err(col, "G41.1 and G42.1 need D, the tool's diameter"))?;
            (d * st.factor() / 2.0, None)
        } else {
            let t = match int_word(x, w, 'D', 0.0, 999.0)? {
                Some(d) => Some(d),
                None => st.tool,
            };
            let radius = match t {
                Some(0) | None => 0.0,
                Some(t) => x.tool_data(t, d_col, "D")?.1 / 2.0,
            };
            (radius, t)
        };
        // A negative radius (G41.1 D-4) puts the tool on the other side, as in LinuxCNC.
        let (left, radius) = if radius < 0.0 {
            (!left, -radius)
        } else {
            (left, radius)
        };
        comp.on(left, radius, st.modal.plane);
        st.modal.comp = if left {
            CompSide::Left
        } else {
            CompSide::Right
        };
        st.comp_radius = radius;
        st.comp_tool = t;
    }
    Ok(())
}

fn tool_length(
    st: &mut InterpState,
    comp: &mut Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    let g43 = w
        .has_g(430)
        .or(w.has_g(431))
        .or(w.has_g(432))
        .or(w.has_g(490));
    let Some(col) = g43 else {
        return Ok(());
    };
    if comp.active() {
        return Err(x.err(
            col,
            "cannot change the tool length offset with cutter radius compensation on",
        ));
    }
    let k = st.factor();
    if w.has_g(490).is_some() {
        st.tlo = [0.0; 3];
        st.tlo_tool = None;
    } else if w.has_g(430).is_some() {
        let h = match int_word(x, w, 'H', 0.0, 999.0)? {
            Some(h) => Some(h),
            None => st.tool,
        };
        st.tlo = [
            0.0,
            0.0,
            match h {
                Some(0) | None => 0.0,
                Some(h) => x.tool_data(h, w.col('H').unwrap_or(col), "H")?.0,
            },
        ];
        st.tlo_tool = h.filter(|&h| h != 0);
    } else if w.has_g(431).is_some() {
        if w.get('X').is_some() || w.get('Y').is_some() {
            return Err(x.err(col, "G43.1 on this machine offsets Z only"));
        }
        if let Some(z) = w.get('Z') {
            st.tlo = [0.0, 0.0, z * k];
        }
        st.tlo_tool = None;
    } else {
        // G43.2: adds another offset.
        match (int_word(x, w, 'H', 0.0, 999.0)?, w.get('Z')) {
            (Some(_), Some(_)) => return Err(x.err(col, "G43.2 takes H or axis words, not both")),
            (Some(h), None) => {
                if h != 0 {
                    st.tlo[2] += x.tool_data(h, w.col('H').unwrap_or(col), "H")?.0;
                }
            }
            (None, Some(z)) => st.tlo[2] += z * k,
            (None, None) => return Err(x.err(col, "G43.2 needs H or Z")),
        }
        if w.get('X').is_some() || w.get('Y').is_some() {
            return Err(x.err(col, "G43.2 on this machine offsets Z only"));
        }
    }
    Ok(())
}

/// Fanuc's G68 X Y R (the Fanuc dialect, docs/gcode.md "Fanuc dialect"): program points turn
/// by R degrees counter-clockwise about X Y (the program frame; the current point where they
/// are left out), until G69, M02/M30 or RESET. G17 only, R needed, under G90; refused with
/// cutter compensation on, as a Fanuc refuses it.
fn coordinate_rotation(
    st: &mut InterpState,
    comp: &Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    let Some(col) = w.has_g(680).or(w.has_g(690)) else {
        return Ok(());
    };
    if comp.active() {
        return Err(x.err(
            col,
            "G68 and G69 cannot be given with cutter radius compensation on: G40 first",
        ));
    }
    if w.has_g(690).is_some() {
        st.g68 = None;
        return Ok(());
    }
    if st.modal.plane != Plane::XY {
        return Err(x.err(col, "G68 turns the XY plane only here: give G17 first"));
    }
    if st.modal.incremental {
        return Err(x.err(
            col,
            "G68 under G91: give its centre and angle under G90 (a Fanuc's incremental angle depends on a parameter)",
        ));
    }
    if let Some(c) = w.col('Z') {
        return Err(x.err(
            c,
            "G68 in G17 takes X and Y, the centre: Z is not in its plane",
        ));
    }
    let Some(r) = w.get('R') else {
        return Err(x.err(col, "G68 needs R, the angle in degrees"));
    };
    if !r.is_finite() || r.abs() > 360.0 {
        return Err(x.err(
            w.col('R').unwrap_or(col),
            "G68 R: the angle is -360 to 360 degrees",
        ));
    }
    // The centre in the program frame as it stands (under a G68 already in force, the new one
    // replaces it: its centre is read in the frame without it).
    st.g68 = None;
    let k = st.factor();
    let here = st.prog();
    let c = [
        w.get('X').map_or(here[0], |v| v * k),
        w.get('Y').map_or(here[1], |v| v * k),
    ];
    st.g68 = Some((c, r));
    Ok(())
}

fn path_control(
    st: &mut InterpState,
    comp: &Comp,
    x: &mut Exec,
    w: &Words,
) -> Result<(), TranslateError> {
    if let Some(col) = w.has_g(610).or(w.has_g(611)).or(w.has_g(640)) {
        if comp.active() {
            return Err(x.err(
                col,
                "cannot change the path control mode (G61, G61.1, G64) with cutter radius compensation on",
            ));
        }
    }
    if w.has_g(610).is_some() {
        st.modal.path = PathMode::ExactPath;
    }
    if w.has_g(611).is_some() {
        st.modal.path = PathMode::ExactStop;
    }
    if let Some(col) = w.has_g(640) {
        let k = st.factor();
        let p = w.get('P');
        let q = w.get('Q');
        for (c, v) in [('P', p), ('Q', q)] {
            if let Some(v) = v {
                if v < 0.0 {
                    return Err(x.err(
                        w.col(c).unwrap_or(col),
                        format!("G64 {c} (a tolerance) must not be negative"),
                    ));
                }
            }
        }
        // Q alone is LinuxCNC's too: its naive-CAM tolerance with the default P (rs274's
        // SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0)).
        st.modal.path = PathMode::Blend {
            p: p.map(|v| v * k),
            q: q.map(|v| v * k),
        };
    }
    for g in [50, 51, 80] {
        let Some((letter, values, says)) = fanuc_look_ahead(x, w, g) else {
            continue;
        };
        let col = w.has_g(g).unwrap_or(1);
        let v = w.get(letter);
        if v.is_none_or(|v| !values.contains(&v)) {
            let name = crate::input_text::short_number(f64::from(g) / 10.0);
            return Err(x.err(
                w.col(letter).unwrap_or(col),
                format!("G{name} switches Fanuc's look-ahead with {says}"),
            ));
        }
        // G05.1's R: AI contour control's precision level, 1 to 10.
        if let (51, Some(r)) = (g, w.get('R')) {
            if !(r.fract() == 0.0 && (1.0..=10.0).contains(&r)) {
                return Err(x.err(
                    w.col('R').unwrap_or(col),
                    "G5.1 R: AI contour control's precision level is a whole number 1 to 10",
                ));
            }
        }
    }
    Ok(())
}

/// Fanuc's look-ahead switches, read in its dialect only (docs/gcode.md "Fanuc dialect"):
/// G05 P10000 (high-precision contour control), G05.1 Q1 (AI contour control), G08 P1 (AI
/// advanced preview) and their P0 / Q0. They change how a Fanuc blends and slows at corners;
/// the pulse core ends every block at rest on its programmed end, so here they change
/// nothing and are read, as G64 is. Some((the letter, its values, what they are)) when `g`
/// (×10) is on the line as one of them: G05 and G05.1 with their letter and no X Y Z I J (else
/// they are LinuxCNC's splines, which the dialect keeps), G08 always. G05.1 also takes Q2
/// (nano smoothing), Q3 (smooth tolerance control) and R1–R10 (the precision level), as
/// Fanuc 30i posts write them.
fn fanuc_look_ahead(x: &Exec, w: &Words, g: u32) -> Option<(char, &'static [f64], &'static str)> {
    if x.settings.dialect != crate::settings::Dialect::Fanuc || w.has_g(g).is_none() {
        return None;
    }
    let spline = w.has_axis() || w.get('I').is_some() || w.get('J').is_some();
    match g {
        50 if !spline && w.get('P').is_some() => {
            Some(('P', &[0.0, 10000.0], "P10000 (on) or P0 (off)"))
        }
        51 if !spline && w.get('Q').is_some() => Some((
            'Q',
            &[0.0, 1.0, 2.0, 3.0],
            "Q1 (AI contour control), Q2 (nano smoothing), Q3 (smooth tolerance control) or Q0 (off)",
        )),
        80 => Some(('P', &[0.0, 1.0], "P1 (on) or P0 (off)")),
        _ => None,
    }
}

/// A Fanuc G53 line without a motion code (the Fanuc dialect): the move is at rapid whatever
/// the motion in force, and leaves it as it was (a Fanuc's G53 is one-shot positioning at
/// rapid traverse; LinuxCNC's takes the G00 or G01 in force). Before stop 48 the Fanuc
/// dialect read it as LinuxCNC's: a `G53 Z0.` after G01 fed up at the cutting feed, and after
/// G80 or an arc it was refused.
fn fanuc_g53(x: &Exec, w: &Words) -> bool {
    x.settings.dialect == crate::settings::Dialect::Fanuc
        && w.has_g(530).is_some()
        && [0, 10, 20, 30].iter().all(|&g| w.has_g(g).is_none())
}

/// M06: the machine's tool change. The spindle stops, the coolant goes off, Z rises to the
/// tool-change height (machine Z 0), then the tool is changed; the program starts the
/// spindle again itself (docs/gcode.md "M06").
pub fn tool_change(st: &mut InterpState, comp: &mut Comp, x: &mut Exec, t: u32, col: u32) {
    if st.modal.spindle != 0 {
        comp.aux(x, aux(5), col);
        st.modal.spindle = 0;
    }
    if st.modal.mist || st.modal.flood {
        comp.aux(x, aux(9), col);
        st.modal.mist = false;
        st.modal.flood = false;
    }
    let up = [st.pos[0], st.pos[1], x.settings.tool_change_z()];
    if up != st.pos {
        x.push(Canon::Rapid(up), col);
        st.pos = up;
    }
    comp.aux(
        x,
        Canon::Aux {
            s: None,
            t: Some(t),
            m: Some(6),
        },
        col,
    );
    st.tool = if t == 0 { None } else { Some(t) };
    st.params[5400] = f64::from(t);
}
