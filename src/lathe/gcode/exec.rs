//! Executing lathe lines (docs/lathe-gcode.md "Order of execution"): the modal state and one
//! line's words, in LinuxCNC's order: feed mode and F, spindle speed, T, M03–M05, chuck, waits,
//! dwell, plane, units, diameter mode, compensation, distance mode, motion, stops.

use super::out::{Kind, Mv, Out};
use super::{cycles, read_line, ReadOptions, LATHE, MAX_LINES};
use crate::block::TranslateError;
use crate::gcode::expr::Params;
use crate::gcode::geom::{self, ArcFault};
use crate::gcode::words::{sort_words_in, Words};
use crate::lathe::desc::{ChannelDesc, LatheDesc};
use crate::lathe::ops::{Feed, Op, SpeedMode, SpindleDir};
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
    /// The spindle's direction.
    pub dir: SpindleDir,
    /// G96 constant surface speed.
    pub css: bool,
    /// The S word in force (rpm, or m/min under G96).
    pub s: f64,
    /// The G96 speed limit, rpm.
    pub limit: f64,
    /// G71's depth of cut and retract (from its first block), mm radius.
    pub g71: Option<(f64, f64)>,
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
            dir: SpindleDir::Stop,
            css: false,
            s: 0.0,
            limit: max,
            g71: None,
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

    /// The feed in force as an operation's feed.
    pub fn feed_of(&self) -> Option<Feed> {
        let f = self.feed?;
        Some(if self.per_rev {
            Feed::PerRev(f)
        } else {
            Feed::PerMin(f)
        })
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
    /// The numbered parameters.
    pub params: Params,
    /// The modal state.
    pub st: State,
    /// The emitter.
    pub out: Out<'a>,
    /// Lines executed so far.
    pub executed: u64,
    /// Inside a G70 or G71 profile.
    pub in_cycle: bool,
    /// M02/M30 was read.
    pub ended: bool,
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

impl Reader<'_> {
    /// Runs lines `from..to` (indices).
    pub fn run_range(&mut self, from: usize, to: usize) -> Result<(), TranslateError> {
        let mut i = from;
        while i < to.min(self.lines.len()) && !self.ended {
            let n = (i + 1) as u32;
            self.executed += 1;
            if self.executed > MAX_LINES {
                return Err(err(
                    n,
                    1,
                    format!("the program executes more than {MAX_LINES} lines"),
                ));
            }
            match self.line(i)? {
                Flow::Next => i += 1,
                Flow::Jump(j) => i = j,
                Flow::End => {
                    self.ended = true;
                    break;
                }
            }
        }
        Ok(())
    }

    fn line(&mut self, i: usize) -> Result<Flow, TranslateError> {
        let n = (i + 1) as u32;
        let raw = self.lines[i];
        let l = read_line(raw, n, &self.params)?;
        if l.block_delete && self.opts.block_delete {
            return Ok(Flow::Next);
        }
        if l.percent {
            return Ok(Flow::Next);
        }
        for &(p, v) in &l.assigns {
            self.params.set(p, v);
        }
        let w = sort_words_in(&l, n, &LATHE)?;
        self.execute(&w, n, i)
    }

    fn execute(&mut self, w: &Words, n: u32, idx: usize) -> Result<Flow, TranslateError> {
        let col = |c: char| w.col(c).unwrap_or(1);
        let mut used: u32 = 1 << (b'N' - b'A');
        let mut use_ = |c: char| used |= 1 << (c as u8 - b'A');
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
                200 => self.st.inch = true,
                210 => self.st.inch = false,
                70 => self.st.diameter = true,
                80 => self.st.diameter = false,
                940 => self.st.per_rev = false,
                950 => self.st.per_rev = true,
                _ => {}
            }
        }
        let f = self.st.factor();
        if let Some(v) = w.get('F') {
            use_('F');
            if !(v > 0.0 && v.is_finite()) {
                return Err(err(n, col('F'), format!("F{v}: the feed must be above 0")));
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
        if let Some(d) = w.get('D') {
            use_('D');
            if !(d > 0.0 && d <= self.chan.max_rpm) {
                return Err(err(
                    n,
                    col('D'),
                    format!(
                        "D{d}: the G96 speed limit must be above 0 and at most the spindle's maximum {} rpm",
                        self.chan.max_rpm
                    ),
                ));
            }
            self.st.limit = d;
            spindle = true;
        }
        if let Some(s) = w.get('S') {
            use_('S');
            if !(s >= 0.0 && s.is_finite()) {
                return Err(err(
                    n,
                    col('S'),
                    format!("S{s}: the speed must not be negative"),
                ));
            }
            if !self.st.css && s > self.chan.max_rpm {
                return Err(err(
                    n,
                    col('S'),
                    format!(
                        "S{s}: above channel {}'s spindle maximum of {} rpm",
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
            self.tool(t, n, col('T'))?;
        }
        for &(m, _) in w.m.as_slice() {
            match m {
                3 => self.st.dir = SpindleDir::Cw,
                4 => self.st.dir = SpindleDir::Ccw,
                5 => self.st.dir = SpindleDir::Stop,
                _ => continue,
            }
            spindle = true;
        }
        if spindle {
            let mode = if self.st.css {
                let k = if self.st.inch { 0.3048 } else { 1.0 };
                SpeedMode::Css {
                    m_per_min: self.st.s * k,
                    limit_rpm: self.st.limit,
                }
            } else {
                if self.st.s > self.chan.max_rpm {
                    return Err(err(
                        n,
                        1,
                        format!(
                            "S{}: above channel {}'s spindle maximum of {} rpm (G97)",
                            self.st.s,
                            self.ch + 1,
                            self.chan.max_rpm
                        ),
                    ));
                }
                SpeedMode::Rpm(self.st.s)
            };
            self.out.op(
                n,
                1,
                Op::Spindle {
                    dir: self.st.dir,
                    mode,
                },
            )?;
        }
        // Chuck and waiting codes.
        for &(m, c) in w.m.as_slice() {
            match m {
                10 => self.out.op(n, c, Op::ChuckClose)?,
                11 => self.out.op(n, c, Op::ChuckOpen)?,
                100..=199 => {
                    use_('P');
                    let with = self.wait_channels(w.get('P'), n, col('P'))?;
                    self.out.op(n, c, Op::Wait { m, with })?;
                }
                _ => {}
            }
        }
        // Dwell.
        if let Some(c) = w.has_g(40) {
            use_('P');
            let Some(p) = w.get('P') else {
                return Err(err(n, c, "G04 needs P, the dwell in seconds"));
            };
            if !(0.0..=86_400.0).contains(&p) {
                return Err(err(
                    n,
                    col('P'),
                    format!("G04 P{p}: the dwell must be 0 to 86400 seconds"),
                ));
            }
            self.out.op(
                n,
                c,
                Op::Dwell {
                    ns: (p * 1e9).round() as u64,
                },
            )?;
        }
        // Compensation and distance mode.
        for &(g, c) in w.g.as_slice() {
            match g {
                400 => self.out.comp_stop(),
                410 => self.out.comp_start(true, n, c)?,
                420 => self.out.comp_start(false, n, c)?,
                900 => self.st.absolute = true,
                910 => self.st.absolute = false,
                _ => {}
            }
        }
        // Motion.
        let motion_code =
            w.g.as_slice()
                .iter()
                .find(|x| matches!(x.0, 0 | 10 | 20 | 30 | 330 | 700 | 710 | 760))
                .copied();
        let mut flow = Flow::Next;
        let axes = ['X', 'Z', 'U', 'W'].iter().any(|&c| w.get(c).is_some());
        match motion_code {
            Some((700, c)) | Some((710, c)) | Some((760, c)) => {
                for l in [
                    'P', 'Q', 'U', 'W', 'R', 'X', 'Z', 'I', 'J', 'K', 'H', 'E', 'L',
                ] {
                    use_(l);
                }
                let g = motion_code.map_or(0, |m| m.0);
                if self.in_cycle {
                    return Err(err(n, c, format!("G{} inside a G70/G71 profile", g / 10)));
                }
                flow = match g {
                    760 => {
                        cycles::g76(self, w, n, c)?;
                        Flow::Next
                    }
                    710 => cycles::g71(self, w, n, c, idx)?,
                    _ => cycles::g70(self, w, n, c)?,
                };
            }
            _ => {
                if let Some((g, c)) = motion_code {
                    self.st.motion = Some(g);
                    if !axes {
                        // A motion code alone sets the mode (LinuxCNC refuses G01 alone
                        // only when nothing else is on the line; novanc takes it as modal).
                        let _ = c;
                    }
                }
                if axes {
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
                        _ => {}
                    }
                    self.motion(g, w, n, mc)?;
                } else if w.get('I').is_some() || w.get('K').is_some() || w.get('R').is_some() {
                    let c = w.col('I').or(w.col('K')).or(w.col('R')).unwrap_or(1);
                    return Err(err(n, c, "I, K or R without an X or Z end point"));
                }
            }
        }
        // Stops and the end.
        for &(m, c) in w.m.as_slice() {
            match m {
                0 => self.out.op(n, c, Op::Stop { optional: false })?,
                1 if self.opts.optional_stop => self.out.op(n, c, Op::Stop { optional: true })?,
                2 | 30 => {
                    if self.in_cycle {
                        return Err(err(n, c, format!("M{m:02} inside a G70/G71 profile")));
                    }
                    self.out.op(n, c, Op::End { m30: m == 30 })?;
                    flow = Flow::End;
                }
                _ => {}
            }
        }
        // Words nothing used.
        for c in "DEFHIJKLPQRSTUWXZ".chars() {
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
        self.out.op(n, c, Op::Tool { tool })
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
                format!("P{p}: a waiting code's P lists channels by their digits (P12, P123)"),
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

    /// The end point of a move from X/U and Z/W, `[Z, X]` mm (X a radius).
    pub fn target(&self, w: &Words, n: u32) -> Result<[f64; 2], TranslateError> {
        let f = self.st.factor();
        let dia = if self.st.diameter { 2.0 } else { 1.0 };
        let mut p = self.out.pos;
        if let (Some(_), Some(c)) = (w.get('X'), w.col('U')) {
            return Err(err(
                n,
                c,
                "X and U on one line: give one (U is incremental X)",
            ));
        }
        if let (Some(_), Some(c)) = (w.get('Z'), w.col('W')) {
            return Err(err(
                n,
                c,
                "Z and W on one line: give one (W is incremental Z)",
            ));
        }
        if let Some(x) = w.get('X') {
            let v = x * f / dia;
            p[1] = if self.st.absolute { v } else { p[1] + v };
        }
        if let Some(u) = w.get('U') {
            p[1] += u * f / dia;
        }
        if let Some(z) = w.get('Z') {
            let v = z * f;
            p[0] = if self.st.absolute { v } else { p[0] + v };
        }
        if let Some(wv) = w.get('W') {
            p[0] += wv * f;
        }
        if !(p[0].is_finite() && p[1].is_finite() && p[0].abs() < 1e6 && p[1].abs() < 1e6) {
            return Err(err(n, 1, "the end point is not a reasonable number"));
        }
        Ok(p)
    }

    fn feed(&self, n: u32, c: u32) -> Result<Feed, TranslateError> {
        let Some(feed) = self.st.feed_of() else {
            return Err(err(n, c, "a feed move without a feed: give F"));
        };
        if self.st.per_rev && self.st.dir == SpindleDir::Stop {
            return Err(err(
                n,
                c,
                "a feed per revolution (G95) with the spindle stopped: give M03 or M04",
            ));
        }
        Ok(feed)
    }

    fn motion(&mut self, g: u32, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
        let end = self.target(w, n)?;
        let kind = match g {
            0 => Kind::Rapid,
            10 => Kind::Line(self.feed(n, c)?),
            20 | 30 => {
                let feed = self.feed(n, c)?;
                let ccw = g == 30;
                let f = self.st.factor();
                let s = self.out.pos;
                let centre = match (w.get('R'), w.get('I').is_some() || w.get('K').is_some()) {
                    (Some(_), true) => {
                        return Err(err(n, c, "an arc with both R and I/K: give one"));
                    }
                    (Some(r), false) => {
                        let tol = if self.st.inch {
                            geom::R_TOLERANCE_INCH * 25.4
                        } else {
                            geom::R_TOLERANCE_MM
                        };
                        geom::centre_r(s, end, r * f, !ccw, tol).map_err(|e| arc_err(e, n, c))?
                    }
                    (None, true) => {
                        let ctr = [
                            s[0] + w.get('K').unwrap_or(0.0) * f,
                            s[1] + w.get('I').unwrap_or(0.0) * f,
                        ];
                        let tol = if self.st.inch {
                            geom::IJK_ABS_TOLERANCE_INCH * 25.4
                        } else {
                            geom::IJK_ABS_TOLERANCE_MM
                        };
                        geom::check_ijk(s, end, ctr, tol).map_err(|e| arc_err(e, n, c))?;
                        ctr
                    }
                    (None, false) => {
                        return Err(err(
                            n,
                            c,
                            "an arc needs its centre (I and K, I always a radius) or R",
                        ))
                    }
                };
                Kind::Arc {
                    c: centre,
                    ccw,
                    feed,
                }
            }
            _ => {
                // G33.
                let Some(k) = w.get('K') else {
                    return Err(err(n, c, "G33 needs K, the lead in mm per revolution"));
                };
                let lead = k * self.st.factor();
                if !(lead > 0.0 && lead <= 100.0) {
                    return Err(err(
                        n,
                        w.col('K').unwrap_or(c),
                        format!("G33 K{k}: the lead must be above 0 and at most 100 mm"),
                    ));
                }
                if self.st.dir == SpindleDir::Stop {
                    return Err(err(n, c, "G33 with the spindle stopped: give M03 or M04"));
                }
                if (end[0] - self.out.pos[0]).abs() < 1e-9 {
                    return Err(err(n, c, "G33 needs a Z move (K is the lead along Z)"));
                }
                Kind::Thread(lead)
            }
        };
        self.out.motion(Mv {
            kind,
            start: self.out.pos,
            end,
            line: n,
            col: c,
        })
    }
}

fn arc_err(e: ArcFault, n: u32, c: u32) -> TranslateError {
    let m = match e {
        ArcFault::RTooSmall { half, r } => format!(
            "R {r:.4} is too small: the end point is {:.4} mm away, more than 2·R",
            2.0 * half
        ),
        ArcFault::RFullCircle => "an R arc cannot end where it starts".to_string(),
        ArcFault::NotOnCircle { r0, r1 } => format!(
            "the end point is not on the arc: radius {r0:.4} at the start, {r1:.4} at the end"
        ),
        ArcFault::ZeroRadius => "the arc's radius is zero".to_string(),
    };
    err(n, c, m)
}
