//! Executing lathe lines (docs/lathe-gcode.md "Order of execution"): the modal state and one
//! line's words, in LinuxCNC's order: feed mode and F, spindle speed, T, M03–M05, chuck, waits,
//! dwell, plane, units, diameter mode, compensation, distance mode, motion, stops.

use super::out::{self, Feed, Kind, Mv, Out};
use super::{cycles, drilling, grooving, ReadOptions, LATHE, LATHE_A};
use crate::block::{Css, FeedMode, Sync, TranslateError};
use crate::gcode::flow::Pos;
use crate::gcode::words::{sort_words_in, Words};
use crate::gcode::{read, Lines, Motion, Then};
use crate::lathe::desc::{ChannelDesc, LatheDesc, ToolDesc};
use std::collections::HashMap;

/// The modal state of a lathe program.
#[derive(Clone, Debug)]
pub struct State {
    /// The motion mode ×10 (G00 = 0, G01 = 10, G02, G03, G33 = 330), if one was given.
    pub motion: Option<u32>,
    /// G90 (true) or G91.
    pub absolute: bool,
    /// G07 diameter mode (true, the default) or G08 radius mode.
    pub diameter: bool,
    /// G20 inches.
    pub inch: bool,
    /// G95 feed per revolution.
    pub per_rev: bool,
    /// The F word in force, mm (per minute or per revolution).
    pub feed: Option<f64>,
    /// The spindle's direction as its M code: 3 clockwise, 4 counter-clockwise, 5 stopped.
    pub dir: u8,
    /// G96 constant surface speed.
    pub css: bool,
    /// The S word in force (rpm, or m/min under G96).
    pub s: f64,
    /// The G96 speed limit, rpm.
    pub limit: f64,
    /// G71's depth of cut and retract (from its first block), mm radius.
    pub g71: Option<(f64, f64)>,
    /// G73's relief `[Z, X radius]` mm and number of passes (from its first block).
    pub g73: Option<([f64; 2], u32)>,
    /// G74/G75's return after each peck (their first block's R), mm.
    pub peck_return: f64,
    /// Fanuc's G76 first block (`G76 P Q R`), kept for the second.
    pub g76: Option<FanucG76>,
    /// M24: G76 leaves the thread without its chamfer, until M23 (a Haas's codes, and many a
    /// Fanuc lathe builder's; docs/lathe-gcode.md "G76, Fanuc's one-block form").
    pub no_chamfer: bool,
    /// G83 or G84 in force (Fanuc's face drilling and tapping; G80 or a group 01 code
    /// cancels it): the cycle, the series' initial level, R, Q and P.
    pub drill: Option<drilling::Drill>,
    /// G99 in G code system B: G83 and G84 return to the R level; else (G98, the default) to
    /// the initial level. System A has no such choice: they return to the initial level.
    pub drill_to_r: bool,
    /// How far a `G50 X Z` (system A) or `G92 X Z` (system B, LinuxCNC) has moved the
    /// program's zero from the work offset's, `[Z, X]` mm (X a radius): LinuxCNC's G92
    /// offset, on top of the work system in force.
    pub origin: [f64; 2],
    /// The work coordinate system in force: 0 for G54 to 5 for G59 (docs/lathe-gcode.md
    /// "Work offsets").
    pub work: usize,
    /// System A's single cycle (G90, G92, G94) last given: its end `[Z, X]` and taper R, kept
    /// for the lines after it (Fanuc: X, Z and R are modal in the cycle).
    pub single: Option<[f64; 3]>,
}

/// What Fanuc's first G76 block keeps (0i-T: parameters 5140–5143 otherwise): the finishing
/// passes m, the chamfer r in leads, the tool's angle a (degrees), the least cut Δdmin and
/// the finishing allowance d, mm radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanucG76 {
    /// m: the passes at the full depth, 1 to 99.
    pub m: u32,
    /// r: the chamfer, in leads (r / 10).
    pub chamfer: f64,
    /// a: the tool's angle, 0 to 80 degrees.
    pub angle: f64,
    /// Δdmin: the least cut, mm.
    pub step: f64,
    /// d: the finishing allowance, mm.
    pub allowance: f64,
}

impl Default for FanucG76 {
    /// What a first block that gives nothing keeps: one finishing pass, no chamfer, the tool
    /// straight in (angle 0), no least cut, no allowance.
    fn default() -> FanucG76 {
        FanucG76 {
            m: 1,
            chamfer: 0.0,
            angle: 0.0,
            step: 0.0,
            allowance: 0.0,
        }
    }
}

impl State {
    /// The state at the start of a program (G18 G7 G21 G90 G94 G97 G40, spindle stopped).
    pub fn new(desc: &LatheDesc, ch: usize) -> State {
        let max = desc.channels.get(ch).map_or(0.0, |c| c.max_rpm);
        State {
            motion: None,
            absolute: true,
            diameter: true,
            inch: false,
            per_rev: false,
            feed: None,
            dir: 5,
            css: false,
            s: 0.0,
            limit: max,
            g71: None,
            g73: None,
            peck_return: 0.0,
            g76: None,
            no_chamfer: false,
            drill: None,
            drill_to_r: false,
            origin: [0.0, 0.0],
            work: 0,
            single: None,
        }
    }

    /// mm per program unit.
    pub fn factor(&self) -> f64 {
        if self.inch {
            25.4
        } else {
            1.0
        }
    }

    /// The feed in force, per minute or per revolution.
    pub fn feed_of(&self) -> Option<Feed> {
        let f = self.feed?;
        Some(if self.per_rev {
            (f, FeedMode::PerRev)
        } else {
            (f, FeedMode::PerMin)
        })
    }

    /// Whether the spindle is stopped (M05, or no M03/M04 yet).
    pub fn stopped(&self) -> bool {
        self.dir == 5
    }
}

/// What a line asks of the reading loop.
pub enum Flow {
    /// Go on with the next line.
    Next,
    /// Go on at this line index (after a G71 and its profile).
    Jump(usize),
    /// M02/M30: stop reading.
    End,
    /// M98 P L: call subprogram O`o`.
    Call {
        /// The program number.
        o: u32,
        /// The repeats.
        l: Option<u32>,
        /// The column of M98.
        col: u32,
    },
    /// M99: back from a subprogram.
    Return {
        /// The column of M99.
        col: u32,
    },
    /// An M code the machine description remaps: its subroutine is called, then the rest of
    /// the line runs (`Reader::after_remap`).
    Remap {
        /// The M code.
        m: u32,
        /// Its column.
        col: u32,
    },
}

/// The reader of one program.
pub struct Reader<'a> {
    /// The machine.
    pub desc: &'a LatheDesc,
    /// The channel, 0-based.
    pub ch: usize,
    /// The channel's description.
    pub chan: &'a ChannelDesc,
    /// The panel switches.
    pub opts: ReadOptions,
    /// The program's lines.
    pub lines: &'a [&'a str],
    /// N number to line index.
    pub n_lines: HashMap<u32, usize>,
    /// The byte where each line starts (for going on after a G71's profile).
    pub starts: Vec<usize>,
    /// The modal state.
    pub st: State,
    /// The emitter.
    pub out: Out<'a>,
    /// Inside a G70 or G71 profile.
    pub in_cycle: bool,
    /// M02/M30 was read.
    pub ended: bool,
    /// The program is read in Fanuc's dialect (G76 is Fanuc's two-block form).
    pub fanuc: bool,
    /// Fanuc's G code system A (docs/lathe-gcode.md "G code systems").
    pub system_a: bool,
    /// Fanuc's calculator-type input (`decimal calculator`): the one reader leaves a number
    /// written without a point as written, in program units.
    pub calculator: bool,
    /// Fanuc's dialect: the letters of the line being executed whose number was written
    /// without a decimal point, so read in least increments where the letter is a length
    /// unless the input is calculator-type (`read::Line::plain` less `dotted`).
    pub unpointed: u32,
    /// Fanuc's dialect: the letters of the line being executed written as plain numbers with
    /// a decimal point (`read::Line::plain` and `dotted`).
    pub pointed: u32,
    /// The channel's dialect with the M codes its description remaps (read in modal group
    /// 10); `None`: it remaps none.
    pub remapped: Option<crate::gcode::words::Dialect>,
    /// The line being executed is the rest of one whose remapped M code has called its
    /// subroutine, now returned: only its steps after that code run (docs/lathe-gcode.md "A
    /// machine builder's M codes").
    pub after_remap: bool,
    /// The first line (P, an index) of the G71–G73 profile being read, and whether it names Z
    /// or W (Fanuc's type II G71), as its words are read; `None` before that line is read.
    pub profile_first: Option<usize>,
    /// See `profile_first`.
    pub profile_names_z: Option<bool>,
    /// The channel's work offsets G54 to G59, `[Z, X]` mm (X a radius) from the machine's
    /// zero: as the channel keeps them at the read's start, changed by G10 L2/L20 and by a
    /// program's `#5221=` for the rest of the read (docs/lathe-gcode.md "Work offsets").
    pub work: super::WorkOffsets,
}

/// An error at a line and column.
pub fn err(line: u32, col: u32, message: impl Into<String>) -> TranslateError {
    TranslateError {
        line,
        col,
        message: message.into(),
    }
}

fn is_int(v: f64) -> bool {
    v.fract() == 0.0 && v.is_finite()
}

/// The lathe's execution of a line's words behind the one reader (`crate::gcode::Motion`):
/// the reader has done the line's flow and parameters.
impl Motion for Reader<'_> {
    fn words(
        &mut self,
        line: &read::Line,
        at: Pos,
        lines: &mut dyn Lines,
    ) -> Result<Then, TranslateError> {
        let n = at.line as u32 + 1;
        let w = sort_words_in(line, n, self.dialect())?;
        self.unpointed = line.plain & !line.dotted;
        self.pointed = line.plain & line.dotted;
        let flow = self.execute(&w, n, at.line, lines);
        lines.units(self.st.inch);
        Ok(match flow? {
            Flow::Next => Then::Next,
            Flow::Jump(j) => Then::Skip(Pos {
                unit: at.unit,
                line: j,
                byte: self.starts.get(j).copied().unwrap_or(usize::MAX),
            }),
            Flow::End => {
                self.ended = true;
                Then::End
            }
            Flow::Call { o, l, col } => Then::Call { o, l, col },
            Flow::Return { col } => Then::Return { col },
            Flow::Remap { m, col } => Then::Remap { m, col },
        })
    }

    fn stop(&mut self, n: u32, col: u32) -> Result<(), TranslateError> {
        self.out.op(n, col, out::m(0))
    }

    // The machine state a program reads (docs/lathe-gcode.md "System variables").
    fn param(&self, n: usize, fanuc: bool) -> Option<Result<f64, String>> {
        super::sysvars::read(self, n, fanuc)
    }

    fn named_param(&self, name: &str) -> Option<Result<f64, String>> {
        super::sysvars::named(self, name)
    }

    fn modal(&self) -> Option<&dyn crate::gcode::sysvars::Modal> {
        Some(self)
    }

    fn after_remap(&mut self) {
        self.after_remap = true;
    }

    fn write_param(&mut self, n: usize, v: f64, fanuc: bool) -> Option<Result<(), String>> {
        if let Some(done) = super::sysvars::write_work(self, n, v, fanuc) {
            return Some(done);
        }
        super::sysvars::write(self, n, fanuc).map(Err)
    }
}

impl Reader<'_> {
    /// The letters and codes the program is read with: system B's, or system A's.
    fn dialect(&self) -> &crate::gcode::words::Dialect {
        match &self.remapped {
            Some(d) => d,
            None if self.system_a => &LATHE_A,
            None => &LATHE,
        }
    }

    /// Runs lines `from..to` (indices) of a G70/G71 profile, each read by `lines` (the one
    /// reader: parameters, messages, the bound on lines executed).
    pub fn run_range(
        &mut self,
        from: usize,
        to: usize,
        lines: &mut dyn Lines,
    ) -> Result<(), TranslateError> {
        let mut i = from;
        while i < to.min(self.lines.len()) && !self.ended {
            match self.line(i, lines)? {
                Flow::Next => i += 1,
                Flow::Jump(j) => i = j,
                Flow::End => {
                    self.ended = true;
                    break;
                }
                Flow::Call { col, .. } | Flow::Return { col } => {
                    return Err(err(
                        (i + 1) as u32,
                        col,
                        "M98 or M99 inside a G70/G71 profile",
                    ))
                }
                Flow::Remap { m, col } => {
                    return Err(err(
                        (i + 1) as u32,
                        col,
                        format!(
                            "M{m} (remapped by the machine description) inside a G70/G71 profile"
                        ),
                    ))
                }
            }
        }
        Ok(())
    }

    /// The least increment, program units (Fanuc's numbers without a point).
    pub fn increment(&self) -> f64 {
        if self.st.inch {
            0.0001
        } else {
            0.001
        }
    }

    /// Whether letter `l` of the line was written as a plain number without a decimal point
    /// (Fanuc's dialect only).
    pub fn written_without_point(&self, l: char) -> bool {
        self.unpointed & read::letter_bit(l) != 0
    }

    /// Whether letter `l` of the line was written with a decimal point (Fanuc's dialect only).
    pub fn written_with_point(&self, l: char) -> bool {
        self.pointed & read::letter_bit(l) != 0
    }

    /// Letter `l`'s value as written: where the one reader took a number without a point in
    /// least increments (X, Z, U, W, I, K, R, Q in Fanuc's dialect), the number itself (a G70
    /// or G71 `Q20` is N20, not 0.020).
    pub fn as_written(&self, l: char, v: f64) -> f64 {
        if !self.calculator
            && self.written_without_point(l)
            && read::FANUC_INCREMENT_LETTERS.contains(&(l as u8))
        {
            (v / self.increment()).round()
        } else {
            v
        }
    }

    /// Letter `l`'s value, program units, where Fanuc takes it in least increments only, with
    /// no point (G74/G75 Q, G76 Q, G83 Q): the one reader has scaled a number written without
    /// a point, unless calculator-type input left it as written; then it is scaled here, as a
    /// Fanuc with DPI = 1 still reads these words in increments.
    pub fn in_increments(&self, l: char, v: f64) -> f64 {
        if self.calculator && self.written_without_point(l) {
            v * self.increment()
        } else {
            v
        }
    }

    /// Where the program's zero lies now, `[Z, X]` mm from the machine's zero (X a radius):
    /// the work offset in force and a G50/G92 shift on top of it.
    pub fn zero(&self) -> [f64; 2] {
        let w = self.work[self.st.work];
        [w[0] + self.st.origin[0], w[1] + self.st.origin[1]]
    }

    /// What the blocks made now are measured from on the display ([`super::Datum`]).
    pub fn datum(&self) -> super::Datum {
        super::Datum {
            work: self.st.work,
            zero: self.zero(),
            offset: self.out.offset(),
        }
    }

    fn line(&mut self, i: usize, lines: &mut dyn Lines) -> Result<Flow, TranslateError> {
        let n = (i + 1) as u32;
        let raw = self.lines[i];
        if self.opts.block_delete && raw.trim_start().starts_with('/') {
            // Skipped unread, as in LinuxCNC: a deleted line cannot stop the program.
            return Ok(Flow::Next);
        }
        if raw.bytes().all(|c| matches!(c, b' ' | b'\t' | b'\r')) {
            return Ok(Flow::Next);
        }
        let l = lines.read_line(raw, n, self)?;
        if l.percent || l.words.is_empty() {
            return Ok(Flow::Next);
        }
        let w = sort_words_in(&l, n, self.dialect())?;
        if self.in_cycle && self.profile_first == Some(i) {
            // A G71 profile's first line (its P), as read: whether it names Z or W (type II).
            self.profile_names_z = Some(w.get('Z').is_some() || w.get('W').is_some());
        }
        self.unpointed = l.plain & !l.dotted;
        self.pointed = l.plain & l.dotted;
        let flow = self.execute(&w, n, i, lines);
        lines.units(self.st.inch);
        flow
    }

    fn execute(
        &mut self,
        w: &Words,
        n: u32,
        idx: usize,
        lines: &mut dyn Lines,
    ) -> Result<Flow, TranslateError> {
        let col = |c: char| w.col(c).unwrap_or(1);
        let mut used: u32 = 1 << (b'N' - b'A');
        let mut use_ = |c: char| used |= 1 << (c as u8 - b'A');
        // The rest of a line whose remapped M code has called its subroutine: the steps
        // before that code ran before the call (the modes below are set again, as they were).
        let after = std::mem::take(&mut self.after_remap);
        // Plane, units, diameter mode, feed mode: they change how the rest is read.
        for &(g, c) in w.g.as_slice() {
            match g {
                170 | 190 => {
                    return Err(err(
                        n,
                        c,
                        format!(
                            "G{} selects a plane the lathe does not have: the lathe works in G18 (Z–X) only",
                            g / 10
                        ),
                    ))
                }
                200 | 210 => {
                    self.st.inch = g == 200;
                    self.out.set_inch(self.st.inch);
                }
                70 => self.st.diameter = true,
                80 => self.st.diameter = false,
                540 | 550 | 560 | 570 | 580 | 590 => {
                    let work = (g / 10 - 54) as usize;
                    if work != self.st.work && self.out.comp_on() {
                        return Err(err(
                            n,
                            c,
                            format!("G{} under nose-radius compensation: give G40 first", g / 10),
                        ));
                    }
                    self.st.work = work;
                }
                // In system A, G94 is the facing cycle (G95 is refused by its dialect).
                940 if !self.system_a => self.st.per_rev = false,
                950 => self.st.per_rev = true,
                980 if self.system_a => self.st.per_rev = false,
                990 if self.system_a => self.st.per_rev = true,
                _ => {}
            }
        }
        // G10 L2/L20: a work offset set (after the work system is chosen, before G92, as
        // LinuxCNC orders them).
        if let Some(c) = w.has_g(100) {
            for l in ['L', 'P', 'X', 'Z', 'U', 'W', 'R'] {
                use_(l);
            }
            if !after {
                self.g10(w, n, c)?;
            }
        }
        // System B's G92, G92.1, G92.2 (in system A, G92 is the threading cycle).
        let g92 =
            w.g.as_slice()
                .iter()
                .find(|x| !self.system_a && matches!(x.0, 920..=922))
                .copied();
        let f = self.st.factor();
        if let Some(v) = w.get('F') {
            use_('F');
            if !(v > 0.0 && v.is_finite()) {
                return Err(err(
                    n,
                    col('F'),
                    format!(
                        "F{}: the feed must be above 0",
                        crate::input_text::short_number(v)
                    ),
                ));
            }
            self.st.feed = Some(v * f);
        }
        // Spindle speed and mode.
        let mut spindle = false;
        if w.has_g(960).is_some() {
            self.st.css = true;
            spindle = true;
        }
        if w.has_g(970).is_some() {
            self.st.css = false;
            spindle = true;
        }
        // G41.1/G42.1's D is the nose's diameter (below), G71/G72's the depth of cut of their
        // one-block form (`cycles::rough`), G74/G75's the relief of theirs (`grooving`);
        // another line's D is G96's limit.
        let dynamic = w.has_g(411).or(w.has_g(421)).is_some();
        let roughing = (w.has_g(710).or(w.has_g(720)))
            .or(w.has_g(740).or(w.has_g(750)))
            .or(w.has_g(760))
            .is_some();
        if let Some(d) = w.get('D').filter(|_| !dynamic && !roughing) {
            use_('D');
            if !(d > 0.0 && d <= self.chan.max_rpm) {
                return Err(err(
                    n,
                    col('D'),
                    format!(
                        "D{}: the G96 speed limit must be above 0 and at most the spindle's maximum {} rpm",
                        crate::input_text::short_number(d),
                        self.chan.max_rpm
                    ),
                ));
            }
            self.st.limit = d;
            spindle = true;
        }
        // Fanuc's G92 in system B is system A's G50: X Z set the coordinate system, S the
        // spindle limit (a Fanuc 0i-T's `G92 S3000`; LinuxCNC's G92 takes no S).
        let g92_as_g50 = self.fanuc && matches!(g92, Some((920, _)));
        if let Some((g, c)) = g92.filter(|_| !g92_as_g50) {
            for l in ['X', 'Z', 'U', 'W'] {
                use_(l);
            }
            if !after {
                self.g92(w, n, g, c)?;
            }
        }
        let g50 = (w.has_g(500).map(|c| ("G50", c)))
            .or(g92.filter(|_| g92_as_g50).map(|(_, c)| ("G92", c)));
        if let Some((name, c)) = g50 {
            // System A's G50: S is the G96 spindle limit, as D (Fanuc 0i-T); X Z set the
            // coordinate system.
            for l in ['S', 'X', 'Z', 'U', 'W'] {
                use_(l);
            }
            if !after {
                self.g50(w, n, c, name)?;
            }
            spindle = w.get('S').is_some();
        } else if let Some(s) = w.get('S') {
            use_('S');
            if !(s >= 0.0 && s.is_finite()) {
                return Err(err(
                    n,
                    col('S'),
                    format!(
                        "S{}: the speed must not be negative",
                        crate::input_text::short_number(s)
                    ),
                ));
            }
            if !self.st.css && s > self.chan.max_rpm {
                return Err(err(
                    n,
                    col('S'),
                    format!(
                        "S{}: above channel {}'s spindle maximum of {} rpm",
                        crate::input_text::short_number(s),
                        self.ch + 1,
                        self.chan.max_rpm
                    ),
                ));
            }
            self.st.s = s;
            spindle = true;
        }
        // T: tool change and offsets.
        if let Some(t) = w.get('T') {
            use_('T');
            if !after {
                self.tool(t, n, col('T'))?;
            }
        }
        // M06: the turret indexed at the T word (a lathe's tool changes at once); M06 is read
        // as LinuxCNC's `T1 M6` asks, and needs a tool.
        if let Some(c) = w.m.as_slice().iter().find(|x| x.0 == 6).map(|x| x.1) {
            if self.out.tool().is_none() && w.get('T') != Some(0.0) {
                return Err(err(n, c, "M06 without a tool: give T (T1 M6, or T0101)"));
            }
        }
        for &(m, _) in w.m.as_slice() {
            if (3..=5).contains(&m) {
                self.st.dir = m as u8;
                spindle = true;
            }
        }
        if spindle && !after {
            let css = if self.st.css {
                let k = if self.st.inch { 0.3048 } else { 1.0 };
                Some(Css {
                    m_per_min: self.st.s * k,
                    limit_rpm: self.st.limit,
                })
            } else {
                if self.st.s > self.chan.max_rpm {
                    return Err(err(
                        n,
                        1,
                        format!(
                            "S{}: above channel {}'s spindle maximum of {} rpm (G97)",
                            crate::input_text::short_number(self.st.s),
                            self.ch + 1,
                            self.chan.max_rpm
                        ),
                    ));
                }
                None
            };
            self.out.spindle(n, 1, self.st.dir, self.st.s, css)?;
        }
        // Coolant: the channel's (the kernel keeps it; M09, M02, M30, RESET and E-STOP stop it).
        for &(m, c) in w.m.as_slice() {
            if (7..=9).contains(&m) && !after {
                self.out.op(n, c, out::m(m as u8))?;
            }
            if matches!(m, 62..=65) {
                // A digital output with the motion (M62, M63) or at once (M64, M65): the mill's
                // codes (docs/gcode.md "Inputs and outputs"); the kernel's channel keeps it and
                // records it on /nc/io.
                use_('P');
                if !after {
                    self.output(m, ('P', w.get('P'), col('P')), None, (n, c))?;
                }
            }
            if matches!(m, 67 | 68) {
                // An analog output E to Q, with the motion (M67) or at once (M68).
                use_('E');
                use_('Q');
                if !after {
                    self.output(m, ('E', w.get('E'), col('E')), w.get('Q'), (n, c))?;
                }
            }
            if matches!(m, 23 | 24) && !after {
                if !self.fanuc {
                    return Err(err(
                        n,
                        c,
                        format!("M{m}: the thread chamfer on and off (M23, M24) is a Fanuc lathe's code: read the program in the Fanuc dialect"),
                    ));
                }
                self.st.no_chamfer = m == 24;
            }
        }
        // Chuck and waiting codes.
        for &(m, c) in w.m.as_slice() {
            match m {
                10 if !after => self.out.op(n, c, out::sync(Sync::ChuckClose))?,
                11 if !after => self.out.op(n, c, out::sync(Sync::ChuckOpen))?,
                100..=199 => {
                    use_('P');
                    if !after {
                        let with = self.wait_channels(w.get('P'), n, col('P'))?;
                        self.out.op(n, c, out::sync(Sync::Wait { m, with }))?;
                    }
                }
                _ => {}
            }
        }
        // A machine builder's M code (modal group 10): its subroutine is called here, the
        // rest of the line runs on the return (LinuxCNC's order: after the coolant, before the
        // dwell). Its argspec's words are the subroutine's.
        if let Some((r, c)) = (self.chan.remap_m.iter()).find_map(|r| {
            w.m.as_slice()
                .iter()
                .find(|x| x.0 == r.code)
                .map(|x| (r, x.1))
        }) {
            r.argspec.chars().for_each(|l| use_(l.to_ascii_uppercase()));
            if !after {
                return self.remap(r.code, n, c, lines);
            }
        }
        // Dwell.
        if let Some(c) = w.has_g(40) {
            use_('P');
            let Some(p) = w.get('P') else {
                return Err(err(n, c, "G04 needs P, the dwell in seconds"));
            };
            if p < 0.0 {
                return Err(err(
                    n,
                    col('P'),
                    format!(
                        "G04 P{}: the dwell must not be negative",
                        crate::input_text::short_number(p)
                    ),
                ));
            }
            if p > crate::limits::MAX_DWELL_S {
                return Err(err(
                    n,
                    col('P'),
                    crate::limits::dwell_too_long(&format!(
                        "P{}",
                        crate::input_text::short_number(p)
                    )),
                ));
            }
            let dwell = crate::block::Block {
                motion: crate::block::Motion::Dwell,
                dwell_ns: (p * 1e9).round() as u64,
                ..out::aux()
            };
            self.out.op(n, c, dwell)?;
        }
        // Compensation, the tool's offsets, path control and distance mode.
        for &(g, c) in w.g.as_slice() {
            match g {
                430 | 490 => {
                    if self.out.comp_on() {
                        return Err(err(
                            n,
                            c,
                            format!(
                                "G{} with nose-radius compensation in force: give G40 first",
                                g / 10
                            ),
                        ));
                    }
                    if g == 430 {
                        use_('H');
                        let have = self.out.tool().cloned();
                        if let (Some(h), Some(t)) = (w.get('H'), have) {
                            if h != t.number as f64 {
                                // LinuxCNC's G43 H of another tool (its nc_files/lathecomp.ngc,
                                // `T7 M6 G43 H9`): that tool's offsets on the tool in place,
                                // whose nose radius and tip stay its own, as LinuxCNC's
                                // compensation takes them. Until the next T.
                                let other = (is_int(h) && (1.0..=99.0).contains(&h))
                                    .then(|| self.chan.tool(h as u32))
                                    .flatten();
                                let Some(o) = other else {
                                    return Err(err(
                                        n,
                                        col('H'),
                                        format!(
                                            "G43 H{}: no tool {} on channel {}'s tool post",
                                            crate::input_text::short_number(h),
                                            crate::input_text::short_number(h),
                                            self.ch + 1
                                        ),
                                    ));
                                };
                                let offset = o.offset;
                                self.out.set_tool(ToolDesc { offset, ..t }, true);
                            }
                        }
                    }
                    if !self.out.set_offsets(g == 430) && g == 430 {
                        return Err(err(n, c, "G43 without a tool in place: give T first"));
                    }
                }
                640 => {
                    // The tolerance the path may leave its line by: every lathe block ends at
                    // rest on its programmed end, so the path is within any tolerance.
                    for l in ['P', 'Q'] {
                        use_(l);
                        if let Some(v) = w.get(l).filter(|v| !(*v >= 0.0 && v.is_finite())) {
                            return Err(err(
                                n,
                                col(l),
                                format!(
                                    "G64 {l}{}: a tolerance is not negative",
                                    crate::input_text::short_number(v)
                                ),
                            ));
                        }
                    }
                }
                400 => self.out.comp_stop(n, c)?,
                410 => self.out.comp_start(true, n, c)?,
                420 => self.out.comp_start(false, n, c)?,
                411 | 421 => {
                    // LinuxCNC's dynamic compensation: D the nose's diameter, L its
                    // orientation in LinuxCNC's numbering (docs/lathe-gcode.md).
                    use_('D');
                    use_('L');
                    let Some(d) = w.get('D') else {
                        return Err(err(n, c, "G41.1/G42.1 needs D, the nose's diameter"));
                    };
                    if !(0.0..=100.0).contains(&d) {
                        return Err(err(
                            n,
                            col('D'),
                            format!(
                                "D{}: the nose's diameter must be 0 to 100 mm",
                                crate::input_text::short_number(d)
                            ),
                        ));
                    }
                    let l = w.get('L').unwrap_or(0.0);
                    if !(l.fract() == 0.0 && (0.0..=9.0).contains(&l)) {
                        return Err(err(
                            n,
                            col('L'),
                            format!(
                                "L{}: the orientation is 0 to 9 (LinuxCNC's numbering)",
                                crate::input_text::short_number(l)
                            ),
                        ));
                    }
                    let tip = super::comp::linuxcnc_orientation(l as u8);
                    let radius = d * self.st.factor() / 2.0;
                    self.out.comp_start_dynamic(g == 411, radius, tip, n, c)?;
                }
                900 if !self.system_a => self.st.absolute = true,
                910 => self.st.absolute = false,
                _ => {}
            }
        }
        // Motion.
        let motion_code =
            w.g.as_slice()
                .iter()
                .find(|x| {
                    matches!(
                        x.0,
                        0 | 10 | 20 | 30 | 320 | 330 | 700 | 710 | 720 | 730 | 740 | 750 | 760
                    ) || (self.system_a && matches!(x.0, 900 | 920 | 940))
                })
                .copied();
        let mut flow = Flow::Next;
        // G50's and G92's X and Z set the coordinate system: nothing moves.
        let axes = w.has_g(500).is_none()
            && w.has_g(100).is_none()
            && g92.is_none()
            && ['X', 'Z', 'U', 'W'].iter().any(|&c| w.get(c).is_some());
        // G83 or G84, its mode and its return level (docs/lathe-gcode.md "G83 face drilling",
        // "G84 face tapping").
        let given =
            w.g.as_slice()
                .iter()
                .find(|x| matches!(x.0, 830 | 840))
                .map(|&(g, c)| (g / 10, c));
        if !self.system_a {
            if let Some(&(g, c)) = w.g.as_slice().iter().find(|x| matches!(x.0, 980 | 990)) {
                if !self.fanuc || (given.is_none() && self.st.drill.is_none()) {
                    return Err(err(n, c, super::G98_G99_FEEDS));
                }
                self.st.drill_to_r = g == 990;
            }
        }
        if w.has_g(800).is_some() {
            self.st.drill = None;
        }
        if let (Some((code, c)), Some((g, _))) = (given, motion_code) {
            return Err(err(
                n,
                c,
                format!(
                    "G{code} and G{:02} on one line: the drilling cycle and a motion code of group 01 exclude each other",
                    g / 10
                ),
            ));
        }
        if motion_code.is_some() {
            // A group 01 code ends G83's or G84's mode (Fanuc: as G80).
            self.st.drill = None;
        }
        let drill_here = given.or_else(|| {
            let code = self.st.drill.map(|d| d.code)?;
            (axes && w.has_g(280).is_none() && w.has_g(530).is_none())
                .then(|| ['X', 'U', 'Z', 'W'].iter().filter_map(|&l| w.col(l)).min())
                .flatten()
                .map(|c| (code, c))
        });
        if let Some((code, c)) = drill_here {
            for l in ['P', 'Q', 'R', 'K', 'X', 'Z', 'U', 'W'] {
                use_(l);
            }
            flow = drilling::cycle(self, w, n, c, code)?;
        }
        match motion_code {
            Some((g @ (740 | 750), c)) => {
                for l in ['P', 'Q', 'U', 'W', 'R', 'X', 'Z', 'I', 'K', 'D'] {
                    use_(l);
                }
                if self.in_cycle {
                    return Err(err(n, c, format!("G{} inside a G70/G71 profile", g / 10)));
                }
                flow = grooving::g74_75(self, w, n, c, g)?;
            }
            Some((700, c)) | Some((710, c)) | Some((720, c)) | Some((730, c)) | Some((760, c)) => {
                for l in [
                    'P', 'Q', 'U', 'W', 'R', 'X', 'Z', 'I', 'J', 'K', 'H', 'E', 'L', 'D', 'A',
                ] {
                    use_(l);
                }
                let g = motion_code.map_or(0, |m| m.0);
                if self.in_cycle {
                    return Err(err(n, c, format!("G{} inside a G70/G71 profile", g / 10)));
                }
                flow = match g {
                    760 if self.fanuc => {
                        cycles::g76_fanuc(self, w, n, c)?;
                        Flow::Next
                    }
                    760 => {
                        cycles::g76(self, w, n, c)?;
                        Flow::Next
                    }
                    710 => cycles::g71(self, w, n, c, idx, lines)?,
                    720 => cycles::g72(self, w, n, c, idx, lines)?,
                    730 => cycles::g73(self, w, n, c, idx, lines)?,
                    _ => cycles::g70(self, w, n, c, lines)?,
                };
            }
            _ => {
                if let Some((g, c)) = motion_code {
                    if g == 320 && !self.fanuc {
                        return Err(err(n, c, "G32 is Fanuc's thread cutting (its F the lead); LinuxCNC's is G33 K: read the program in the Fanuc dialect (`dialect fanuc`)"));
                    }
                    if self.st.motion != Some(g) {
                        // A single cycle's kept end and taper last while its code is in force.
                        self.st.single = None;
                    }
                    self.st.motion = Some(g);
                    if !axes {
                        // A motion code alone sets the mode (LinuxCNC refuses G01 alone
                        // only when nothing else is on the line; novanc takes it as modal).
                        let _ = c;
                    }
                }
                if drill_here.is_some() {
                    // G83 or G84 made its moves above.
                } else if let Some(c) = w.has_g(280) {
                    // G28 takes the line's axis words; a motion code beside it only sets the
                    // mode (`G28 G00 U0 W0`, as on a Fanuc).
                    for l in ['X', 'Z', 'U', 'W'] {
                        use_(l);
                    }
                    self.g28(w, n, c)?;
                } else if let Some(c) = w.has_g(530) {
                    for l in ['X', 'Z', 'U', 'W'] {
                        use_(l);
                    }
                    self.g53(w, n, c)?;
                } else if axes {
                    for l in ['X', 'Z', 'U', 'W'] {
                        use_(l);
                    }
                    let Some(g) = self.st.motion else {
                        return Err(err(
                            n,
                            1,
                            "X or Z without a motion mode: give G00, G01, G02, G03 or G33",
                        ));
                    };
                    let mc = motion_code.map_or(1, |m| m.1);
                    match g {
                        20 | 30 => ['I', 'K', 'R'].into_iter().for_each(&mut use_),
                        330 => use_('K'),
                        900 | 920 | 940 => use_('R'),
                        _ => {}
                    }
                    if matches!(g, 900 | 920 | 940) {
                        cycles::single(self, g, w, n, mc)?;
                    } else {
                        self.motion(g, w, n, mc)?;
                    }
                } else if w.get('I').is_some() || w.get('K').is_some() || w.get('R').is_some() {
                    let c = w.col('I').or(w.col('K')).or(w.col('R')).unwrap_or(1);
                    return Err(err(n, c, "I, K or R without an X or Z end point"));
                }
            }
        }
        // Stops and the end.
        for &(m, c) in w.m.as_slice() {
            match m {
                0 => self.out.op(n, c, out::m(0))?,
                1 if self.opts.optional_stop => self.out.op(n, c, out::m(1))?,
                2 | 30 => {
                    if self.in_cycle {
                        return Err(err(n, c, format!("M{m:02} inside a G70/G71 profile")));
                    }
                    self.out.op(n, c, out::m(m as u8))?;
                    flow = Flow::End;
                }
                98 => {
                    use_('P');
                    use_('L');
                    flow = self.m98(w, n, c)?;
                }
                99 => flow = Flow::Return { col: c },
                _ => {}
            }
        }
        // Words nothing used.
        for c in "ADEFHIJKLPQRSTUWXZ".chars() {
            if w.get(c).is_some() && used & (1 << (c as u8 - b'A')) == 0 {
                return Err(err(
                    n,
                    col(c),
                    format!("the {c} word is not used by anything on this line"),
                ));
            }
        }
        Ok(flow)
    }

    /// G28: a rapid to the intermediate point the axis words give (X/U, Z/W, as a move
    /// reads them), then a rapid of the axes named to the channel's reference position, the
    /// slide where the program started (docs/lathe-gcode.md "The reference position"). An axis
    /// not named does not move. With no axis word, LinuxCNC's dialect returns both axes (its
    /// G28 without axes goes to the stored position, here the reference) and Fanuc's refuses
    /// the line, where a Fanuc moves nothing, unless the channel's description says `g28
    /// alone all` (a Haas returns every axis).
    fn g28(&mut self, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
        if self.in_cycle {
            return Err(err(n, c, "G28 inside a G70/G71 profile"));
        }
        if self.out.comp_on() {
            return Err(err(
                n,
                c,
                "G28 under nose-radius compensation: give G40 first (the reference position is the slide's, not the nose's)",
            ));
        }
        let mut x = w.get('X').is_some() || w.get('U').is_some();
        let mut z = w.get('Z').is_some() || w.get('W').is_some();
        if !x && !z {
            if self.fanuc && self.chan.g28_all != Some(true) {
                return Err(err(
                    n,
                    c,
                    "G28 names no axis: give the axes to return, U0 W0 (a Fanuc returns only the axes named; a description's 'g28 alone all' returns both, as a Haas does)",
                ));
            }
            (x, z) = (true, true);
        }
        let mid = self.target(w, n)?;
        let start = self.out.pos;
        let rapid = |start, end| Mv {
            kind: Kind::Rapid,
            start,
            end,
            line: n,
            col: c,
        };
        if mid != start {
            // `U0 W0` names the point where the tool stands: no move (not even the offsets
            // of a tool selected since, which the move to the reference takes up).
            self.out.motion(rapid(start, mid))?;
        }
        // The reference in programmed coordinates: the slide at the top of both travels, less
        // the offsets the emitter adds to every programmed point.
        let off = self.out.offset();
        let mut end = mid;
        if z {
            end[0] = self.chan.axes[1].travel[1] - off[0];
        }
        if x {
            end[1] = self.chan.axes[0].travel[1] - off[1];
        }
        self.out.motion(rapid(mid, end))
    }

    /// M62–M65 P (digital output P, 0 to 63, on with M62 and M64, off with M63 and M65) or
    /// M67/M68 E Q (analog output E, 0 to 63, to Q: 0 if not written, as LinuxCNC reads it),
    /// M`code` at `n`:`c`, its index word `(letter, value, column)`: with the block's motion
    /// (M62, M63, M67) or at once (M64, M65, M68), a block of its own.
    fn output(
        &mut self,
        code: u32,
        (letter, index, ic): (char, Option<f64>, u32),
        q: Option<f64>,
        (n, c): (u32, u32),
    ) -> Result<(), TranslateError> {
        let what = if letter == 'P' { "digital" } else { "analog" };
        let Some(i) = index else {
            return Err(err(
                n,
                c,
                format!("M{code} needs {letter}, the {what} output 0 to 63"),
            ));
        };
        if !(i.fract() == 0.0 && (0.0..64.0).contains(&i)) {
            return Err(err(
                n,
                ic,
                format!(
                    "M{code} {letter}{}: the {what} output is a whole number 0 to 63",
                    crate::input_text::short_number(i)
                ),
            ));
        }
        let (index, synced) = (i as u8, matches!(code, 62 | 63 | 67));
        let io = match code {
            67 | 68 => crate::block::Io::Analog {
                index,
                value: q.unwrap_or(0.0),
                synced,
            },
            _ => crate::block::Io::Digital {
                index,
                on: matches!(code, 62 | 64),
                synced,
            },
        };
        let b = crate::block::Block {
            io: Some(io),
            ..out::aux()
        };
        self.out.op(n, c, b)
    }

    /// A remapped M code at `n`:`c`: its subroutine is called (by the one reader), unless the
    /// line is in a G70/G71 profile or a remap subroutine runs.
    fn remap(&self, m: u32, n: u32, c: u32, lines: &dyn Lines) -> Result<Flow, TranslateError> {
        if self.in_cycle {
            return Err(err(
                n,
                c,
                format!("M{m} (remapped by the machine description) inside a G70/G71 profile"),
            ));
        }
        if lines.in_remap() {
            return Err(err(
                n,
                c,
                format!("M{m} inside a remap subroutine: it is remapped by the machine description and the lathe has no M{m} of its own"),
            ));
        }
        Ok(Flow::Remap { m, col: c })
    }

    /// G53: a move to X and Z in machine coordinates (docs/lathe-gcode.md "G53"): the slide's
    /// position, without the tool's offsets and the G50 shift, X a diameter in G07. LinuxCNC
    /// moves in the G00 or G01 in force, and refuses any other mode, incremental distance
    /// and compensation; a Fanuc moves at rapid whatever the mode, and ignores G53 in
    /// incremental distance, where novanc refuses it as LinuxCNC does.
    fn g53(&mut self, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
        if self.in_cycle {
            return Err(err(n, c, "G53 inside a G70/G71 profile"));
        }
        if self.out.comp_on() {
            return Err(err(
                n,
                c,
                "G53 under nose-radius compensation: give G40 first (machine coordinates are the slide's, not the nose's)",
            ));
        }
        if let Some(col) = w.col('U').or(w.col('W')) {
            return Err(err(
                n,
                col,
                "G53 takes X and Z, machine positions: U and W are increments",
            ));
        }
        if !self.st.absolute {
            return Err(err(n, c, "G53 in incremental distance (G91): give G90"));
        }
        if w.get('X').is_none() && w.get('Z').is_none() {
            return Err(err(
                n,
                c,
                "G53 names no axis: give X or Z, machine positions",
            ));
        }
        let kind = match self.st.motion {
            _ if self.fanuc => Kind::Rapid,
            Some(0) => Kind::Rapid,
            Some(10) => Kind::Line(self.feed_in_force(n, c)?),
            _ => {
                return Err(err(
                    n,
                    c,
                    "G53 moves in G00 or G01 only: give one on the line",
                ))
            }
        };
        let f = self.st.factor();
        let dia = if self.st.diameter { 2.0 } else { 1.0 };
        // The machine position less the offsets the emitter adds to every programmed point.
        let off = self.out.offset();
        let mut end = self.out.pos;
        if let Some(z) = w.get('Z') {
            end[0] = z * f - off[0];
        }
        if let Some(x) = w.get('X') {
            end[1] = x * f / dia - off[1];
        }
        super::moves::reasonable(end, n)?;
        self.out.motion(super::cycles::mv(kind, end, n, c))
    }

    /// `G10 L2 P X Z`: work offset P (1 to 6, G54 to G59; in LinuxCNC's dialect P0 the one
    /// in force) set to X Z, from the machine's zero (X a diameter under G07), either word
    /// alone; `G10 L20 P X Z`: set so that the point where the tool stands (before the tool's
    /// offsets, with a G92 shift) is X Z in it. It is in force for the rest of the read at once
    /// (docs/lathe-gcode.md "Work offsets").
    fn g10(&mut self, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
        if self.in_cycle {
            return Err(err(n, c, "G10 inside a G70/G71 profile"));
        }
        let col = |l: char| w.col(l).unwrap_or(c);
        let short = crate::input_text::short_number;
        let l = match w.get('L') {
            Some(v) if v == 20.0 && self.fanuc => {
                // Fanuc's L20 is another thing (the mill's reader refuses it so too).
                return Err(err(
                    n,
                    col('L'),
                    "G10 L20 sets Fanuc's additional work systems (G54.1 P1–P48): the lathe has G54–G59, set with G10 L2 P1–P6, or measured at OFS (Z0 INPUT on a work offset's row)",
                ));
            }
            Some(v) if v == 2.0 || v == 20.0 => v as u32,
            None if self.fanuc => {
                return Err(err(
                    n,
                    c,
                    "G10 P X Z without L is Fanuc's tool offset setting: a lathe program cannot set a tool offset (the lathe reads its program whole at START): set it at OFS; G10 L2 P1–P6 sets a work offset",
                ))
            }
            None => {
                return Err(err(
                    n,
                    c,
                    "G10 needs L: L2 (a work offset) or L20 (a work offset from where the tool stands)",
                ))
            }
            Some(v) if v == 1.0 || v == 10.0 || v == 11.0 => {
                return Err(err(
                    n,
                    col('L'),
                    format!("G10 L{}: a lathe program cannot set a tool offset (the lathe reads its program whole at START): set it at OFS", short(v)),
                ))
            }
            Some(v) => {
                return Err(err(
                    n,
                    col('L'),
                    format!("G10 L{}: the lathe has G10 L2 and L20, its work offsets", short(v)),
                ))
            }
        };
        let name = format!("G10 L{l}");
        for (letter, why) in [
            (
                'U',
                "G10 takes X and Z, the offset's values: U and W are increments",
            ),
            (
                'W',
                "G10 takes X and Z, the offset's values: U and W are increments",
            ),
            (
                'R',
                "G10 R turns a mill's work system: a lathe's is not turned",
            ),
        ] {
            if let Some(cl) = w.col(letter) {
                return Err(err(n, cl, why));
            }
        }
        let p = w.get('P');
        let work = match p {
            Some(v) if v == 0.0 && !self.fanuc => self.st.work,
            Some(0.0) => {
                return Err(err(
                    n,
                    col('P'),
                    format!("{name} P0: Fanuc's external work offset (shifting every work system) is not on this lathe: set G54–G59 with P1–P6"),
                ))
            }
            Some(v) if v.fract() == 0.0 && (1.0..=6.0).contains(&v) => v as usize - 1,
            Some(v) => {
                return Err(err(
                    n,
                    col('P'),
                    format!("{name} P{}: the lathe's work systems are G54 to G59, P1 to P6", short(v)),
                ))
            }
            None => {
                return Err(err(
                    n,
                    c,
                    format!("{name} needs P, the work system: P1 (G54) to P6 (G59)"),
                ))
            }
        };
        if w.get('X').is_none() && w.get('Z').is_none() {
            return Err(err(n, c, format!("{name} names no axis: give X or Z")));
        }
        if work == self.st.work && self.out.comp_on() {
            return Err(err(
                n,
                c,
                format!("{name} of the work system in force under nose-radius compensation: give G40 first"),
            ));
        }
        let f = self.st.factor();
        let dia = if self.st.diameter { 2.0 } else { 1.0 };
        let mut set = self.work[work];
        for (i, letter) in [(0, 'Z'), (1, 'X')] {
            if let Some(v) = w.get(letter) {
                let v = v * f / if letter == 'X' { dia } else { 1.0 };
                let o = if l == 2 {
                    v
                } else {
                    self.out.pos[i] - v - self.st.origin[i]
                };
                if !(o.is_finite() && o.abs() <= super::MAX_WORK_OFFSET_MM) {
                    return Err(err(
                        n,
                        col(letter),
                        format!(
                            "{name}: the work offset's {letter} would be {} mm, beyond the {} mm an offset may be",
                            short(o * if letter == 'X' { 2.0 } else { 1.0 }),
                            super::MAX_WORK_OFFSET_MM
                        ),
                    ));
                }
                set[i] = o;
            }
        }
        self.work[work] = set;
        Ok(())
    }

    /// System A's `G50 X Z` and system B's `G92 X Z` (Fanuc 0i-T's coordinate system setting,
    /// LinuxCNC's G92 offset): the point where the tool stands (before the tool's offsets)
    /// becomes X Z, X a diameter under G07; either word alone. `code` names it in messages.
    fn set_origin(&mut self, w: &Words, n: u32, c: u32, code: &str) -> Result<(), TranslateError> {
        for l in ['U', 'W'] {
            if let Some(col) = w.col(l) {
                return Err(err(
                    n,
                    col,
                    format!("{code} {l}: shifting the coordinate system by increments is not supported: give {code} X Z, where the tool stands"),
                ));
            }
        }
        let f = self.st.factor();
        let dia = if self.st.diameter { 2.0 } else { 1.0 };
        for (i, l) in [(0, 'Z'), (1, 'X')] {
            if let Some(v) = w.get(l) {
                let v = v * f / if l == 'X' { dia } else { 1.0 };
                let o = self.out.pos[i] - v - self.work[self.st.work][i];
                if !(o.is_finite() && o.abs() < 1e6) {
                    return Err(err(
                        n,
                        w.col(l).unwrap_or(c),
                        format!("the {code} point is not a reasonable number"),
                    ));
                }
                self.st.origin[i] = o;
            }
        }
        Ok(())
    }

    /// System B's G92 (docs/lathe-gcode.md "G92 and G50"): `G92 X Z` as G50 X Z; G92.1 and
    /// G92.2 put the program zero back where the channel's work coordinates have it.
    fn g92(&mut self, w: &Words, n: u32, g: u32, c: u32) -> Result<(), TranslateError> {
        if self.out.comp_on() {
            return Err(err(
                n,
                c,
                "G92 under nose-radius compensation: give G40 first",
            ));
        }
        if g == 920 {
            if w.get('X').is_none() && w.get('Z').is_none() && w.col('U').or(w.col('W')).is_none() {
                return Err(err(
                    n,
                    c,
                    "G92 needs X or Z: what the point where the tool stands is to be",
                ));
            }
            return self.set_origin(w, n, c, "G92");
        }
        if let Some(col) = ['X', 'Z', 'U', 'W'].iter().find_map(|&l| w.col(l)) {
            return Err(err(n, col, format!("G92.{} takes no axis word", g - 920)));
        }
        self.st.origin = [0.0, 0.0];
        Ok(())
    }

    /// System A's G50 (Fanuc 0i-T): `G50 S` limits the spindle under G96, as LinuxCNC's D;
    /// `G50 X Z` sets the coordinate system: the point where the tool stands becomes X Z.
    fn g50(&mut self, w: &Words, n: u32, c: u32, name: &str) -> Result<(), TranslateError> {
        if self.out.comp_on() && name == "G92" {
            return Err(err(
                n,
                c,
                "G92 under nose-radius compensation: give G40 first",
            ));
        }
        self.set_origin(w, n, c, name)?;
        let Some(s) = w.get('S') else {
            if w.get('X').is_some() || w.get('Z').is_some() {
                return Ok(());
            }
            return Err(err(
                n,
                c,
                format!("{name} needs S (the spindle limit under G96, rpm) or X Z (the point where the tool stands)"),
            ));
        };
        if !(s > 0.0 && s <= self.chan.max_rpm) {
            return Err(err(
                n,
                w.col('S').unwrap_or(c),
                format!(
                    "{name} S{}: the G96 speed limit must be above 0 and at most the spindle's maximum {} rpm",
                    crate::input_text::short_number(s),
                    self.chan.max_rpm
                ),
            ));
        }
        self.st.limit = s;
        Ok(())
    }

    /// M98 P L: the call of subprogram O`P`, `L` times (the mill's bounds).
    fn m98(&self, w: &Words, n: u32, c: u32) -> Result<Flow, TranslateError> {
        let whole = |l: char, max: f64| -> Result<Option<u32>, TranslateError> {
            match w.get(l) {
                None => Ok(None),
                Some(v) if is_int(v) && (0.0..=max).contains(&v) => Ok(Some(v as u32)),
                Some(v) => Err(err(
                    n,
                    w.col(l).unwrap_or(c),
                    format!(
                        "M98 {l}{}: a whole number 0 to {max}",
                        crate::input_text::short_number(v)
                    ),
                )),
            }
        };
        let o = whole('P', 99_999_999.0)?
            .ok_or_else(|| err(n, c, "M98 needs P, the O number of the subprogram"))?;
        let l = whole('L', crate::limits::MAX_REPEATS as f64)?;
        Ok(Flow::Call { o, l, col: c })
    }

    fn tool(&mut self, t: f64, n: u32, c: u32) -> Result<(), TranslateError> {
        if !(is_int(t) && (0.0..=9999.0).contains(&t)) {
            return Err(err(
                n,
                c,
                format!("T{t}: a tool is T and 1 to 4 digits (T0101)"),
            ));
        }
        let t = t as u32;
        let (tool, offset) = if t >= 100 { (t / 100, t % 100) } else { (t, t) };
        if tool == 0 && offset == 0 {
            // T0 (T00, T0000): no tool indexed; the offsets of the tool in place are cancelled,
            // as a Fanuc's T0000, and LinuxCNC's `T0 M6` (its empty pocket) leaves none. The
            // turret stays where it stands.
            if let Some(cur) = self.out.tool().cloned() {
                self.out.set_tool(cur, false);
            }
            return Ok(());
        }
        if self.out.comp_on() {
            return Err(err(
                n,
                c,
                "change tools with nose-radius compensation off: give G40 first",
            ));
        }
        let Some(td) = self.chan.tool(tool) else {
            let have: Vec<String> = self
                .chan
                .tools
                .iter()
                .map(|t| t.number.to_string())
                .collect();
            return Err(err(
                n,
                c,
                format!(
                    "tool {tool} is not on channel {}'s tool post (it has {})",
                    self.ch + 1,
                    if have.is_empty() {
                        "none".to_string()
                    } else {
                        have.join(", ")
                    }
                ),
            ));
        };
        if offset != 0 && offset != tool {
            return Err(err(
                n,
                c,
                format!(
                    "T{t:04}: offset {offset} is not tool {tool}'s: each tool has its own offsets (T{tool:02}{tool:02}, or T{tool:02}00 for none)"
                ),
            ));
        }
        self.out.set_tool(td.clone(), offset != 0);
        let b = crate::block::Block {
            t: Some(tool),
            ..out::aux()
        };
        self.out.op(n, c, b)
    }

    fn wait_channels(&self, p: Option<f64>, n: u32, c: u32) -> Result<u8, TranslateError> {
        let count = self.desc.channels.len().min(8);
        let all = if count >= 8 { 0xff } else { (1u8 << count) - 1 };
        let own = 1u8 << self.ch.min(7);
        let Some(p) = p else {
            return Ok(all);
        };
        if !(is_int(p) && p > 0.0 && p < 1e9) {
            return Err(err(
                n,
                c,
                format!(
                    "P{}: a waiting code's P lists channels by their digits (P12, P123)",
                    crate::input_text::short_number(p)
                ),
            ));
        }
        let mut with = 0u8;
        for d in (p as u64).to_string().bytes() {
            let k = (d - b'0') as usize;
            if k == 0 || k > count {
                return Err(err(
                    n,
                    c,
                    format!(
                        "P{p}: channel {k} does not exist (the machine has channels 1 to {count})"
                    ),
                ));
            }
            with |= 1 << (k - 1);
        }
        if with & own == 0 {
            return Err(err(
                n,
                c,
                format!(
                    "P{p}: a waiting code must list its own channel {}",
                    self.ch + 1
                ),
            ));
        }
        Ok(with)
    }
}
