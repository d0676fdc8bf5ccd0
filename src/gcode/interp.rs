//! The interpreter's state and the execution of one read line, in LinuxCNC's order of
//! execution (docs/gcode.md "Order of execution"): F, S, T, M06, M03/M04/M05, M08/M09, G04,
//! plane, units, cutter compensation, tool length, coordinate system, distance mode, retract
//! mode, G10/G28/G53, motion, then the stops.

use super::canon::Canon;
use super::comp::Comp;
use super::moves::{arc, g10, g28, move_to, target};
pub use super::words::{sort_words, Codes, Words};
use super::{OffsetChange, WorkOffsets};
use crate::block::{Plane, TranslateError};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;

/// The motion mode in force (modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// G00.
    Rapid,
    /// G01.
    Feed,
    /// G02.
    Cw,
    /// G03.
    Ccw,
    /// A canned cycle (G73, G81–G89).
    Cycle(u8),
    /// G80.
    None,
}

/// What a line asks of the program flow after it has executed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on with the next line.
    Next,
    /// M98 P L: call O-number `o`, `l` times.
    Call { o: u32, l: u32, col: u32 },
    /// M99: return from the subprogram.
    Return { col: u32 },
    /// M02 or M30: the program ends.
    End,
}

/// The interpreter's modal state and machine, all lengths in mm.
#[derive(Clone, Debug)]
pub struct State {
    /// Where the spindle's gauge line is, machine mm.
    pub cur: [f64; 3],
    /// G20 in force.
    pub inch: bool,
    /// G91 in force.
    pub incremental: bool,
    /// Arc plane.
    pub plane: Plane,
    /// Motion mode.
    pub mode: Mode,
    /// Feed, mm/min (0 = none given yet).
    pub feed: f64,
    /// Spindle speed S, rpm.
    pub speed: f64,
    /// T code selected by the last T word.
    pub selected: Option<u32>,
    /// T code in the spindle.
    pub tool: Option<u32>,
    /// Spindle: 1 forward, −1 reverse, 0 stopped.
    pub spindle: i8,
    /// Tool length offset in force (G43), mm.
    pub tlo: f64,
    /// Work offsets and the system in force (0 = G54).
    pub offsets: WorkOffsets,
    /// The coordinate system in force, 0 = G54 … 5 = G59.
    pub cs: usize,
    /// G99 (retract to R) in force, else G98; G99 at the start, as in rs274 2.9.
    pub retract_r: bool,
    /// Canned cycles: the initial level (program Z, mm) of the series, sticky R, Z, P, Q.
    pub cycle_il: Option<f64>,
    /// The cycle whose R and Z are kept.
    pub cycle_kind: Option<u8>,
    /// Sticky R of the cycles (program Z, mm).
    pub cycle_r: Option<f64>,
    /// Sticky Z of the cycles.
    pub cycle_z: Option<f64>,
    /// Sticky P (dwell, s).
    pub cycle_p: f64,
    /// Sticky Q (peck, mm).
    pub cycle_q: Option<f64>,
    /// Cutter radius compensation.
    pub comp: Comp,
}

impl State {
    /// The length factor of the units in force (25.4 for inches).
    pub fn factor(&self) -> f64 {
        if self.inch {
            25.4
        } else {
            1.0
        }
    }

    /// The machine offset of the program frame: work offset plus tool length on Z.
    pub fn frame(&self) -> [f64; 3] {
        let o = self.offsets.0[self.cs];
        [o[0], o[1], o[2] + self.tlo]
    }

    /// The current point in program coordinates, mm.
    pub fn prog(&self) -> [f64; 3] {
        let f = self.frame();
        [self.cur[0] - f[0], self.cur[1] - f[1], self.cur[2] - f[2]]
    }

    /// A program point (mm) in machine coordinates.
    pub fn machine(&self, p: [f64; 3]) -> [f64; 3] {
        let f = self.frame();
        [p[0] + f[0], p[1] + f[1], p[2] + f[2]]
    }
}

/// What one line produced.
pub struct Exec<'a> {
    /// The line number.
    pub n: u32,
    /// Canonical actions with their column.
    pub out: Vec<(Canon, u32, u32)>,
    /// Work offsets changed by G10.
    pub changes: Vec<OffsetChange>,
    /// The settings.
    pub settings: &'a MachineSettings,
    /// The tool data.
    pub magazine: &'a Magazine,
    /// OPTIONAL STOP is on.
    pub optional_stop: bool,
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

    fn tool_data(
        &self,
        t: u32,
        col: u32,
        what: &str,
    ) -> Result<&crate::tooldata::ToolRecord, TranslateError> {
        self.magazine.tools.get(t).ok_or_else(|| {
            self.err(
                col,
                format!("{what}{t} names T code {t}, which has no tool data in the tool file"),
            )
        })
    }
}

fn int_word(x: &Exec, w: &Words, c: char, lo: f64, hi: f64) -> Result<Option<u32>, TranslateError> {
    match (w.get(c), w.col(c)) {
        (Some(v), Some(col)) => {
            if v.fract() != 0.0 || v < lo || v > hi {
                return Err(x.err(
                    col,
                    format!(
                        "{c}{} must be a whole number from {lo} to {hi}",
                        crate::input_text::short_number(v)
                    ),
                ));
            }
            Ok(Some(v as u32))
        }
        _ => Ok(None),
    }
}

/// Executes one sorted line on the state.
pub fn execute(st: &mut State, x: &mut Exec, w: &Words) -> Result<Flow, TranslateError> {
    let line_col =
        w.g.first()
            .map(|g| g.1)
            .or(w.m.first().map(|m| m.1))
            .unwrap_or(1);
    // Units first, so that the line's lengths are read in the new units (LinuxCNC converts
    // lengths at execution).
    if w.has_g(200).is_some() {
        st.inch = true;
    }
    if w.has_g(210).is_some() {
        st.inch = false;
    }
    let k = st.factor();
    if let Some(f) = w.get('F') {
        let fc = w.col('F').unwrap_or(1);
        if f < 0.0 {
            return Err(x.err(fc, "a negative F"));
        }
        // F0 is no feed (a feed move then asks for one); a feed that is not 0 is at least the
        // slowest (docs/limits.md).
        if f > 0.0 && f * k < crate::limits::MIN_FEED {
            let text = if st.inch {
                format!(
                    "F{} ({:.3} mm/min)",
                    crate::input_text::short_number(f),
                    f * k
                )
            } else {
                format!("F{}", crate::input_text::short_number(f))
            };
            return Err(x.err(fc, crate::limits::feed_too_slow(&text)));
        }
        st.feed = f * k;
    }
    // S and T, then M06, then the spindle.
    let mut aux_s = None;
    if let Some(s) = w.get('S') {
        if !(0.0..=crate::translator::MAX_SPEED).contains(&s) {
            return Err(x.err(
                w.col('S').unwrap_or(1),
                format!(
                    "spindle speed S{} is not usable",
                    crate::input_text::short_number(s)
                ),
            ));
        }
        st.speed = s;
        aux_s = Some(s.round() as u32);
    }
    let mut aux_t = None;
    if let Some(t) = int_word(x, w, 'T', 0.0, 999.0)? {
        let col = w.col('T').unwrap_or(1);
        if t != 0 {
            x.tool_data(t, col, "T")?;
        }
        st.selected = Some(t);
        aux_t = Some(t);
    }
    let m6 = w.has_m(6);
    if let Some(col) = m6 {
        let t = st
            .selected
            .ok_or_else(|| x.err(col, "M06 without a T word before it: which tool?"))?;
        st.tool = if t == 0 { None } else { Some(t) };
        st.comp.aux(
            x,
            Canon::Aux {
                s: None,
                t: Some(t),
                m: Some(6),
            },
            col,
        );
        aux_t = None;
        // LinuxCNC stops the spindle for the change.
        st.spindle = 0;
    }
    let spindle_m = [3u32, 4, 5]
        .into_iter()
        .find_map(|m| w.has_m(m).map(|c| (m, c)));
    if aux_t.is_some() || (aux_s.is_some() && spindle_m.is_none()) {
        st.comp.aux(
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
        st.spindle = match m {
            3 => 1,
            4 => -1,
            _ => 0,
        };
        let s = if m == 5 {
            aux_s
        } else {
            Some(aux_s.unwrap_or(st.speed.round() as u32))
        };
        st.comp.aux(
            x,
            Canon::Aux {
                s,
                t: None,
                m: Some(m as u8),
            },
            col,
        );
    }
    for m in [8u32, 9] {
        if let Some(col) = w.has_m(m) {
            st.comp.aux(
                x,
                Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(m as u8),
                },
                col,
            );
        }
    }
    if let Some(col) = w.has_g(40) {
        let p = w
            .get('P')
            .ok_or_else(|| x.err(col, "G04 needs P, the dwell in seconds"))?;
        let pc = w.col('P').unwrap_or(col);
        if p < 0.0 {
            return Err(x.err(pc, "a negative dwell P"));
        }
        if p > crate::limits::MAX_DWELL_S {
            return Err(x.err(
                pc,
                crate::limits::dwell_too_long(&format!("P{}", crate::input_text::short_number(p))),
            ));
        }
        st.comp.aux(x, Canon::Dwell(p), col);
    }
    for (g, p) in [(170, Plane::XY), (180, Plane::XZ), (190, Plane::YZ)] {
        if let Some(col) = w.has_g(g) {
            if st.comp.active() && p != Plane::XY {
                return Err(x.err(
                    col,
                    "cannot change the plane with cutter radius compensation on",
                ));
            }
            st.plane = p;
        }
    }
    // Cutter radius compensation.
    if let Some(col) = w.has_g(400) {
        st.comp.off(col);
    }
    for (g, left) in [(410, true), (420, false)] {
        if let Some(col) = w.has_g(g) {
            if st.comp.active() {
                return Err(x.err(col, "cutter radius compensation is already on: G40 first"));
            }
            if st.plane != Plane::XY {
                return Err(x.err(
                    col,
                    "cutter radius compensation works in the XY plane (G17)",
                ));
            }
            let t = match int_word(x, w, 'D', 0.0, 999.0)? {
                Some(d) => Some(d),
                None => st.tool,
            };
            let d_col = w.col('D').unwrap_or(col);
            let radius = match t {
                Some(0) | None => 0.0,
                Some(t) => x.tool_data(t, d_col, "D")?.diameter / 2.0,
            };
            let min = super::comp::MIN_RADIUS_PULSES * x.settings.pulse_mm;
            if radius > 0.0 && radius < min {
                return Err(x.err(
                    d_col,
                    format!(
                        "cutter compensation with a tool radius of {radius:.4} mm would round corners on arcs too small to cut (at least {min:.4} mm): D0 compensates nothing"
                    ),
                ));
            }
            st.comp.on(left, radius, col);
        }
    }
    if w.get('D').is_some() && w.has_g(410).is_none() && w.has_g(420).is_none() {
        return Err(x.err(
            w.col('D').unwrap_or(1),
            "D is the tool of G41/G42: give it with G41 or G42",
        ));
    }
    // Tool length.
    if let Some(col) = w.has_g(430) {
        let h = match int_word(x, w, 'H', 0.0, 999.0)? {
            Some(h) => Some(h),
            None => st.tool,
        };
        let new = match h {
            Some(0) | None => 0.0,
            Some(h) => x.tool_data(h, w.col('H').unwrap_or(col), "H")?.set_length,
        };
        st.tlo = new;
    } else if w.get('H').is_some() {
        return Err(x.err(
            w.col('H').unwrap_or(1),
            "H is the tool of G43: give it with G43",
        ));
    }
    if w.has_g(490).is_some() {
        st.tlo = 0.0;
    }
    for (i, g) in [540u32, 550, 560, 570, 580, 590].into_iter().enumerate() {
        if let Some(col) = w.has_g(g) {
            if st.comp.active() {
                return Err(x.err(
                    col,
                    "cannot change the coordinate system with cutter radius compensation on",
                ));
            }
            st.cs = i;
        }
    }
    if w.has_g(900).is_some() {
        st.incremental = false;
    }
    if w.has_g(910).is_some() {
        st.incremental = true;
    }
    if w.has_g(980).is_some() {
        st.retract_r = false;
    }
    if w.has_g(990).is_some() {
        st.retract_r = true;
    }
    // The motion mode this line sets.
    let mut mode_col = None;
    for &(g, col) in w.g.as_slice() {
        let m = match g {
            0 => Mode::Rapid,
            10 => Mode::Feed,
            20 => Mode::Cw,
            30 => Mode::Ccw,
            800 => Mode::None,
            730 | 810 | 820 | 830 | 840 | 850 | 860 | 890 => Mode::Cycle((g / 10) as u8),
            _ => continue,
        };
        if m == Mode::None && w.has_axis() {
            return Err(x.err(col, "G80 cancels the canned cycle: it takes no X, Y or Z"));
        }
        if let Mode::Cycle(_) = m {
            if !matches!(st.mode, Mode::Cycle(_)) {
                st.cycle_il = None;
                st.cycle_kind = None;
            }
        }
        st.mode = m;
        mode_col = Some(col);
    }
    let non_modal = w.has_g(100).or(w.has_g(280)).or(w.has_g(530));
    if let Some(col) = w.has_g(100) {
        g10(st, x, w, col)?;
    } else if let Some(col) = w.has_g(280) {
        if st.comp.active() {
            return Err(x.err(col, "G28 cannot be used with cutter radius compensation on"));
        }
        g28(st, x, w, col);
    } else if let Some(col) = w.has_g(530) {
        if !matches!(st.mode, Mode::Rapid | Mode::Feed) || mode_col.is_none() {
            return Err(x.err(col, "G53 moves with G00 or G01 on its line"));
        }
        if st.comp.active() {
            return Err(x.err(col, "G53 cannot be used with cutter radius compensation on"));
        }
        if st.incremental {
            return Err(x.err(col, "G53 cannot be used in incremental mode (G91)"));
        }
        let mut e = st.cur;
        for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = w.get(c) {
                e[i] = v * k;
            }
        }
        move_to(st, x, e, mode_col.unwrap_or(col), w)?;
    }
    if non_modal.is_none() {
        let col = mode_col
            .or(w.col('X'))
            .or(w.col('Y'))
            .or(w.col('Z'))
            .unwrap_or(line_col);
        let arc_words = ['I', 'J', 'K', 'R'].iter().any(|&c| w.get(c).is_some());
        match st.mode {
            Mode::Cycle(kind) if w.has_axis() || mode_col.is_some() => {
                super::cycles::cycle(st, x, w, kind, col)?;
            }
            Mode::Rapid | Mode::Feed
                if w.has_axis() || (mode_col.is_some() && st.comp.pending_exit()) =>
            {
                let e = target(st, w);
                if st.mode == Mode::Feed && st.feed <= 0.0 {
                    return Err(x.err(
                        col,
                        "a feed move without F: give F (mm/min, or in/min under G20)",
                    ));
                }
                move_to(st, x, e, col, w)?;
            }
            Mode::Cw | Mode::Ccw if w.has_axis() || arc_words => {
                if st.feed <= 0.0 {
                    return Err(x.err(
                        col,
                        "a feed move without F: give F (mm/min, or in/min under G20)",
                    ));
                }
                arc(st, x, w, col)?;
            }
            _ => {
                if w.has_axis() {
                    return Err(x.err(
                        w.col('X').or(w.col('Y')).or(w.col('Z')).unwrap_or(col),
                        "X, Y or Z with no motion in force (G80): give G00, G01, G02, G03 or a cycle",
                    ));
                }
            }
        }
    }
    // Stops and program flow, last.
    if let Some(col) = w.has_m(0) {
        st.comp.aux(
            x,
            Canon::Aux {
                s: None,
                t: None,
                m: Some(0),
            },
            col,
        );
    }
    if let Some(col) = w.has_m(1) {
        if x.optional_stop {
            st.comp.aux(
                x,
                Canon::Aux {
                    s: None,
                    t: None,
                    m: Some(1),
                },
                col,
            );
        }
    }
    if let Some(col) = w.has_m(98) {
        let p = int_word(x, w, 'P', 0.0, 99_999.0)?
            .ok_or_else(|| x.err(col, "M98 needs P, the O number of the subprogram"))?;
        let l = int_word(x, w, 'L', 0.0, super::MAX_REPEATS as f64)
            .map_err(|e| {
                x.err(
                    e.col,
                    format!("{} (the most repeats is {})", e.message, super::MAX_REPEATS),
                )
            })?
            .unwrap_or(1);
        return Ok(Flow::Call { o: p, l, col });
    }
    if let Some(col) = w.has_m(99) {
        return Ok(Flow::Return { col });
    }
    if w.has_m(2).is_some() || w.has_m(30).is_some() {
        return Ok(Flow::End);
    }
    Ok(Flow::Next)
}
