//! The translator (automatic programming, AP): source statements to machine instruction
//! blocks (patent lines 283–357, Figs. 10–13, Tables 1, B and C; docs/language.md, docs/pulse-core.md).
//!
//! The translator reads one statement at a time (Fig. 10A step (2)). Definitions fill the point
//! table and the DA table ([`defs`]); cutting statements look their tool up through the T-code
//! table, fill a cycle table per point ([`cycle`], [`mill`]) and output it as blocks for B1
//! ([`emit`]). Each statement's blocks are checked against the travel limits before the
//! statement is handed out, so an error never leaves a partial move. The language is described
//! for part programmers in `docs/language.md`.

pub mod ast;
pub mod cycle;
pub mod defs;
pub mod emit;
pub mod geom;
pub mod lex;
pub mod mill;
pub mod parse;

pub use crate::block::{iso_line, iso_program, Statement, TranslateError};

use crate::block::{Block, MachineState};
use crate::settings::MachineSettings;
use crate::tooldata::{Magazine, ToolKind};
use cycle::Cycle;
use defs::{Item, Tables};
use emit::{Loaded, Machine, Out, Spindle};
use mill::{Elem, V3};
use parse::{Cut, CycleKind, Stmt};
use std::sync::Arc;

/// The text of the statement the translator adds after the last line (see `end_of_program`).
pub const END_OF_PROGRAM: &str = "(end of program)";

/// The text of the statement that restores the machine's state before a SEARCH point.
pub fn restore_text(line: u32) -> String {
    format!("(SEARCH: restore for line {line})")
}

pub use defs::{MAX_COORD_MM, MAX_DESIGNATIONS, MAX_HOLES};
pub use lex::MAX_NUMBER;

/// The bounds the translator keeps, shared with the G-code readers (docs/limits.md): the
/// longest line, the blocks of one statement, the longest dwell `DW`, the slowest feed (`FR` or
/// the tool file's), the pecks of a `DH` cycle per hole and the highest spindle speed.
pub use crate::limits::{MAX_BLOCKS, MAX_DWELL_S, MAX_LINE_CHARS, MAX_PECKS, MAX_SPEED, MIN_FEED};

/// The translator as an iterator: one statement's blocks at a time, so that it can keep B1
/// full concurrently with execution. After an error it yields nothing more.
pub struct Translator {
    source: Arc<str>,
    next_byte: usize,
    line: u32,
    magazine: Magazine,
    settings: MachineSettings,
    tables: Tables,
    machine: Machine,
    /// The machine's actual state where the translation started.
    start: Machine,
    /// SEARCH: statements before this line are translated for their state, not run.
    resume_at: Option<u32>,
    /// SEARCH went past the program's last statement (the error said so).
    past_end: Option<PastEnd>,
    /// The statement a SEARCH restore was emitted before, translated next.
    held: Option<(u32, String)>,
    /// A cutting statement has been translated.
    cut: bool,
    done: bool,
    toks: Vec<lex::Token>,
    items: Vec<Item>,
    /// Blocks made so far, and the most the program may make.
    made: u64,
    max_blocks: u64,
}

impl Translator {
    /// A translator for `source`, looking tools up in `magazine`, starting with the machine at
    /// `start` (pulses), no tool in the spindle and the spindle stopped.
    pub fn new(
        source: &str,
        magazine: Magazine,
        settings: MachineSettings,
        start: [i64; 3],
    ) -> Translator {
        Translator::from_state(source.into(), magazine, settings, MachineState::at(start))
    }

    /// A translator for `source` starting from the machine's actual state: where the axes are,
    /// the tool in the spindle (its set length from `magazine`) and the spindle.
    pub fn from_state(
        source: Arc<str>,
        magazine: Magazine,
        settings: MachineSettings,
        state: MachineState,
    ) -> Translator {
        let tool = state.tool.map(|tcode| Loaded {
            tcode,
            set: magazine
                .tools
                .get(tcode)
                .map_or(0, |r| settings.to_pulses(r.length())),
        });
        let spindle = match state.spindle {
            0 => Spindle::Stopped,
            s if s > 0 => Spindle::Forward(s.min(u32::MAX as i64) as u32),
            _ => Spindle::Reverse,
        };
        let machine = Machine {
            pos: state.pos.xyz(),
            abc: state.pos.rotary(),
            tool,
            spindle,
            clear: None,
            seq: 0,
        };
        Translator {
            // A leading byte order mark is not part of the text (PROGRAM READ keeps it, and a
            // file from some editors starts with one); columns count from after it.
            next_byte: if source.starts_with(crate::input_text::BOM) {
                crate::input_text::BOM.len_utf8()
            } else {
                0
            },
            source,
            line: 0,
            magazine,
            settings,
            tables: Tables::default(),
            machine,
            start: machine,
            resume_at: None,
            past_end: None,
            held: None,
            cut: false,
            done: false,
            toks: Vec::new(),
            items: Vec::new(),
            made: 0,
            max_blocks: crate::limits::MAX_PROGRAM_BLOCKS,
        }
    }

    /// The most blocks this program may make (default `limits::MAX_PROGRAM_BLOCKS`).
    pub fn block_limit(mut self, blocks: u64) -> Translator {
        self.max_blocks = blocks;
        self
    }

    /// SEARCH: the statements before source line `line` are translated for the state they
    /// leave (tool, spindle, position, definitions) but yield no blocks; the first statement at
    /// or after `line` is preceded by a restore statement that brings the machine from its
    /// actual state to that state: a tool change if the spindle holds another tool, the
    /// spindle, then Z up to machine zero before any X Y rapid, X Y, then Z down. A cutting
    /// statement there changes its own tool and approaches its first point itself: it is
    /// translated from the actual state after Z has risen to machine zero (`docs/operator.md`,
    /// SEARCH).
    pub fn resume_at(mut self, line: u32) -> Translator {
        self.resume_at = Some(line);
        self
    }

    /// MDI: the definitions (DA, P, L, C, PAT, MAC, and the inline points of cutting
    /// statements) of `program` may be used by name. A line of `program` that does not
    /// translate defines nothing; a name the MDI text defines again is the MDI text's.
    pub fn with_definitions_from(mut self, program: &str) -> Translator {
        self.tables.set_base(true);
        for (i, raw) in program.lines().enumerate() {
            let line = i as u32 + 1;
            let code = raw.split(';').next().unwrap_or("");
            if code.trim().is_empty() {
                continue;
            }
            let mut toks = std::mem::take(&mut self.toks);
            let r = lex::scan(raw, line, &mut toks)
                .and_then(|()| parse::parse(&toks, line, raw.chars().count() as u32 + 1));
            self.toks = toks;
            match r {
                Ok(Stmt::Cut(cut)) => {
                    let mut items = Vec::new();
                    let _ = self.tables.resolve(&cut.desigs, line, &mut items);
                }
                Ok(def) => {
                    let _ = self.tables.define(&def, line);
                }
                Err(_) => {}
            }
        }
        self.tables.set_base(false);
        self
    }

    /// Whether the line is a cutting statement.
    fn is_cut(&mut self, line: u32, raw: &str) -> bool {
        let mut toks = std::mem::take(&mut self.toks);
        let r = lex::scan(raw, line, &mut toks)
            .and_then(|()| parse::parse(&toks, line, raw.chars().count() as u32 + 1));
        self.toks = toks;
        matches!(r, Ok(Stmt::Cut(_)))
    }

    /// Before a cutting statement at the SEARCH point: the statement puts its own tool in the
    /// spindle, starts the spindle over its first point and moves there safely, so it is
    /// translated from the machine's actual state; the restore only raises Z to machine zero
    /// first, so no X Y rapid happens below it.
    fn restore_for_cut(&mut self, line: u32) -> Result<Statement, TranslateError> {
        let seq = self.machine.seq;
        let mut o = Out::new(self.start, line, &self.settings);
        o.rapid_home(None);
        let mut blocks = o.blocks;
        for b in &mut blocks {
            b.seq = 0;
        }
        self.machine = Machine {
            seq,
            clear: None,
            ..o.m
        };
        Ok(Statement {
            line,
            text: restore_text(line),
            blocks,
        })
    }

    /// The restore statement before source line `line` (see [`Translator::resume_at`]); it
    /// leaves the translator's machine where the restore ends.
    fn restore(&mut self, line: u32) -> Result<Statement, TranslateError> {
        let target = self.machine;
        let mut o = Out::new(self.start, line, &self.settings);
        if let Some(t) = target.tool {
            if o.m.tool.map(|x| x.tcode) != Some(t.tcode) {
                cycle::tool_change(&mut o, t.tcode, t.set);
            }
        }
        o.m.tool = target.tool;
        match target.spindle {
            Spindle::Forward(s) => o.spindle_forward(s),
            Spindle::Reverse => {
                if o.m.spindle != Spindle::Reverse {
                    o.aux(None, None, Some(4));
                }
            }
            Spindle::Stopped => {
                if o.m.spindle != Spindle::Stopped {
                    o.aux(None, None, Some(5));
                }
            }
        }
        o.m.spindle = target.spindle;
        // Never back down into a hole: at least the clearance plane the tool last left.
        let mut to = target.pos;
        if let Some(clear) = target.clear {
            to[2] = to[2].max(clear + target.set());
        }
        let pos = o.m.pos;
        if to[0] != pos[0] || to[1] != pos[1] {
            o.rapid_home(Some([to[0], to[1]]));
        }
        o.rapid(to);
        o.check_travel(self.start.pos)?;
        let mut blocks = o.blocks;
        for b in &mut blocks {
            b.seq = 0;
        }
        self.machine.pos = to;
        self.machine.clear = target.clear.filter(|&c| to[2] - target.set() < c);
        Ok(Statement {
            line,
            text: restore_text(line),
            blocks,
        })
    }

    /// The end of the program, after the last line: when the program has cut and the spindle
    /// turns, a tool still in a hole rises to its clearance plane, the spindle stops and Z
    /// returns to machine zero (so the tool does not sit turning above the part), then `M30`.
    /// A program that only positions (for example an MDI `GO`) gets just `M30`, so the tool
    /// stays where it was sent.
    fn end_of_program(&mut self) -> Statement {
        let line = self.line + 1;
        let mut o = Out::new(self.machine, line, &self.settings);
        if self.cut && o.m.spindle != Spindle::Stopped {
            if let Some(clear) = o.m.clear {
                if o.m.tip() < clear {
                    o.rapid_tip(clear);
                }
            }
            o.aux(None, None, Some(5));
            o.m.spindle = Spindle::Stopped;
            o.rapid_home(None);
            o.m.clear = None;
        }
        o.aux(None, None, Some(30));
        self.machine = o.m;
        Statement {
            line,
            text: END_OF_PROGRAM.to_string(),
            blocks: o.blocks,
        }
    }

    /// Translates one statement (a source line with something on it).
    fn statement(&mut self, line: u32, raw: &str) -> Result<Vec<Block>, TranslateError> {
        let mut toks = std::mem::take(&mut self.toks);
        let r = lex::scan(raw, line, &mut toks)
            .and_then(|()| parse::parse(&toks, line, raw.chars().count() as u32 + 1));
        self.toks = toks;
        let stmt = r?;
        let settings = &self.settings;
        let mut o = Out::new(self.machine, line, settings);
        match &stmt {
            Stmt::Cut(cut) => {
                self.cut = true;
                let mut items = std::mem::take(&mut self.items);
                items.clear();
                let r = cutting(&mut o, &mut self.tables, &self.magazine, cut, &mut items);
                self.items = items;
                r?;
            }
            Stmt::Go { da, v } => {
                let origin = match da {
                    Some(d) => self.tables.origin(*d, line)?,
                    None => V3::zeros(),
                };
                let p = origin + V3::new(v[0], v[1], v[2]);
                let z = o.p(p.z) + o.m.set();
                let end = [o.p(p.x), o.p(p.y), z];
                position(&mut o, end);
            }
            Stmt::Gd { v } => {
                let pos = o.m.pos;
                let end = [pos[0] + o.p(v[0]), pos[1] + o.p(v[1]), pos[2] + o.p(v[2])];
                position(&mut o, end);
            }
            Stmt::Cl => {
                o.rapid_home(Some([0, 0]));
                o.m.clear = None;
            }
            def => self.tables.define(def, line)?,
        }
        o.check_travel(self.machine.pos)?;
        self.machine = o.m;
        Ok(o.blocks)
    }
}

/// Rapid positioning (GO, GD) to an axis position. A tool still inside a hole (after SDP)
/// first rises to the hole's clearance plane. Then when the move goes up, Z first then X Y;
/// when it goes down, X Y first then Z; so the tool never moves sideways below where it was.
fn position(o: &mut Out, end: [i64; 3]) {
    if let Some(clear) = o.m.clear {
        if o.m.tip() < clear {
            o.rapid_tip(clear);
        }
    }
    let pos = o.m.pos;
    if end[2] >= pos[2] {
        o.rapid([pos[0], pos[1], end[2]]);
        o.rapid(end);
    } else {
        o.rapid([end[0], end[1], pos[2]]);
        o.rapid(end);
    }
    o.m.clear = None;
}

/// A modifier that the cycle does not use is an error.
fn refuse(o: &Out, c: &Cut, col: Option<u32>, what: &str) -> Result<(), TranslateError> {
    match col {
        Some(col) => Err(o.err(col, format!("{what} has no meaning in {}", c.kind.word()))),
        None => Ok(()),
    }
}

fn col_of(v: &parse::Valued) -> Option<u32> {
    v.map(|(_, c)| c)
}

/// A cutting statement: tool lookup (AP10), the cycle conditions, then the cycle per point.
fn cutting(
    o: &mut Out,
    tables: &mut Tables,
    magazine: &Magazine,
    c: &Cut,
    items: &mut Vec<Item>,
) -> Result<(), TranslateError> {
    let (tool, tcol) = c.tool;
    let (tcode, rec) = magazine
        .find(tool)
        .map_err(|e| o.err(tcol, e.to_string()))?;
    let m = &c.mods;
    let kind = c.kind;
    if kind != CycleKind::Mil {
        refuse(o, c, m.rgt, "RGT")?;
        refuse(o, c, m.lft, "LFT")?;
    }
    if let (Some(_), Some(col)) = (m.rgt, m.lft) {
        return Err(o.err(col, "give RGT or LFT, not both".to_string()));
    }
    if kind != CycleKind::Drl {
        refuse(o, c, col_of(&m.dh), "DH (peck step)")?;
        refuse(o, c, col_of(&m.di), "DI (chamfer diameter)")?;
    }
    if matches!(kind, CycleKind::Tap | CycleKind::Mil) {
        refuse(o, c, col_of(&m.dw), "DW (dwell)")?;
    }
    let positive = |v: &parse::Valued, what: &str| -> Result<Option<f64>, TranslateError> {
        match *v {
            Some((x, col)) if x.is_nan() || x <= 0.0 => {
                Err(o.err(col, format!("{what} must be greater than 0, not {x}")))
            }
            Some((x, _)) => Ok(Some(x)),
            None => Ok(None),
        }
    };
    let dp = positive(&m.dp, "the depth DP")?;
    let di = positive(&m.di, "the chamfer diameter DI")?;
    let depth = match (dp, di) {
        (Some(_), Some(_)) => {
            return Err(o.err(
                col_of(&m.di).unwrap_or(1),
                "give the depth DP or the chamfer DI, not both".to_string(),
            ))
        }
        (Some(d), None) => d,
        (None, Some(d)) => {
            let col = col_of(&m.di).unwrap_or(1);
            let half_angle: f64 = match rec.kind {
                ToolKind::CentreDrill => 45.0,
                ToolKind::Drill => 59.0,
                k => {
                    return Err(o.err(
                        col,
                        format!("DI chamfers with the point of a centre drill (CD) or drill (DR), and tool {tool:05} is {k}"),
                    ))
                }
            };
            if rec.kind == ToolKind::Drill && d > rec.diameter {
                return Err(o.err(
                    col,
                    format!(
                        "the chamfer diameter DI{d} is larger than the tool (diameter {})",
                        rec.diameter
                    ),
                ));
            }
            d / 2.0 / half_angle.to_radians().tan()
        }
        (None, None) => {
            return Err(o.err(
                1,
                format!("{} needs a depth: give DP (for example DP10)", kind.word()),
            ));
        }
    };
    let feed = positive(&m.fr, "the feed rate FR")?.unwrap_or(rec.feed);
    if let Some((f, col)) = m.fr {
        if f < MIN_FEED {
            return Err(o.err(
                col,
                crate::limits::feed_too_slow(&format!("the feed rate FR{f}")),
            ));
        }
    }
    let speed = positive(&m.ss, "the spindle speed SS")?.unwrap_or(rec.speed);
    if !(1.0..=MAX_SPEED).contains(&speed.round()) {
        let col = col_of(&m.ss).unwrap_or(tcol);
        return Err(o.err(
            col,
            format!("spindle speed {speed} rpm is not usable (1 to {MAX_SPEED} rpm); give SS"),
        ));
    }
    if feed <= 0.0 {
        return Err(o.err(
            tcol,
            format!("tool {tool:05} has no feed rate in the tool file; give FR"),
        ));
    }
    if feed < MIN_FEED {
        return Err(o.err(
            tcol,
            format!(
                "tool {tool:05} has a feed rate of {feed} mm/min in the tool file, below the slowest feed, {MIN_FEED} mm/min; give FR or revise the tool"
            ),
        ));
    }
    let scl = match m.scl {
        Some((x, col)) if x.is_nan() || x < 0.0 => {
            return Err(o.err(
                col,
                format!("the clearance SCL must not be negative, not {x}"),
            ))
        }
        Some((x, _)) => x,
        None => o.settings.clearance_mm,
    };
    let sdp = match m.sdp {
        Some((v, col)) => {
            let d = v.unwrap_or(rec.depth);
            if d.is_nan() || d < 0.0 || d >= depth {
                return Err(o.err(
                    col,
                    format!("the rapid-feed depth SDP{d} must be from 0 up to less than the depth {depth}"),
                ));
            }
            Some(d)
        }
        None => None,
    };
    let dwell = match m.dw {
        Some((x, col)) if x.is_nan() || x < 0.0 => {
            return Err(o.err(col, format!("the dwell DW must not be negative, not {x}")))
        }
        Some((x, col)) if x > MAX_DWELL_S => {
            return Err(o.err(col, crate::limits::dwell_too_long(&format!("DW{x}"))))
        }
        v => v.map(|(x, _)| x),
    };
    let peck = positive(&m.dh, "the peck step DH")?;
    if let (Some(step), Some((_, col))) = (peck, m.dh) {
        if (depth + scl) / step > f64::from(MAX_PECKS) {
            return Err(o.err(
                col,
                format!("DH{step} would make more than {MAX_PECKS} pecks"),
            ));
        }
    }
    let cycle = Cycle {
        kind,
        tcode,
        set: o.p(rec.length()),
        feed,
        speed: speed.round() as u32,
        depth,
        scl,
        sdp,
        dwell,
        peck,
    };
    let radius = rec.cutting_diameter() / 2.0;
    let side = match (m.rgt, m.lft) {
        (Some(_), _) => 1.0,
        (_, Some(_)) => -1.0,
        _ => 0.0,
    };
    tables.resolve(&c.desigs, o.line, items)?;
    let mut origin = V3::zeros();
    let mut elems: Vec<Elem> = Vec::new();
    tables.each(items, |it, col| {
        match it {
            Item::Origin(v) => origin = *v,
            Item::Point(p, _) => elems.push(Elem::Pt { p: origin + p, col }),
            Item::Holes(h, _) => elems.extend((0..h.k).map(|i| Elem::Pt { p: h.hole(i), col })),
            Item::Circle(ci, z, _) => {
                if kind != CycleKind::Mil {
                    return Err(o.err(
                        col,
                        format!(
                            "a circle is a milling contour; {} machines points",
                            kind.word()
                        ),
                    ));
                }
                elems.push(Elem::Circle {
                    c: origin + V3::new(ci.c.x, ci.c.y, *z),
                    r: ci.r,
                    col,
                });
            }
            Item::Macro(..) => {}
        }
        Ok(())
    })?;
    if elems.is_empty() {
        return Err(o.err(
            tcol,
            format!(
                "{} has nothing to machine: designate points (P, PAT, MAC or an inline point)",
                kind.word()
            ),
        ));
    }
    o.col = tcol;
    cycle::tool_change(o, cycle.tcode, cycle.set);
    if kind == CycleKind::Mil {
        mill::mill(o, &cycle, side, radius, &elems)?;
        return too_many_blocks(o);
    }
    for e in &elems {
        if let Elem::Pt { p, col } = *e {
            o.col = col;
            let (x, y) = (o.p(p.x), o.p(p.y));
            cycle::hole(o, &cycle, x, y, p.z);
            too_many_blocks(o)?;
        }
    }
    Ok(())
}

/// The error once a statement has generated more than `MAX_BLOCKS` blocks, charged to the
/// designation being machined. Checked after each hole, so at most one hole's blocks
/// (a few thousand with pecks) are made past the limit.
fn too_many_blocks(o: &Out) -> Result<(), TranslateError> {
    if o.blocks.len() <= MAX_BLOCKS {
        return Ok(());
    }
    Err(o.err(
        o.col,
        format!(
            "this statement makes more than {MAX_BLOCKS} blocks (the most one statement may make); split the work over several statements"
        ),
    ))
}

/// A SEARCH to a line after the program's last statement: nothing to resume at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PastEnd {
    /// The line searched to.
    pub line: u32,
    /// The program's lines.
    pub lines: u32,
}

impl std::fmt::Display for PastEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "no statement at or after line {} (the program has {} lines)",
            self.line, self.lines
        )
    }
}

impl Translator {
    /// Whether the translation ended because its SEARCH point lies past the program's last
    /// statement (the error it gave then), as a value.
    pub fn past_end(&self) -> Option<PastEnd> {
        self.past_end
    }
}

impl Iterator for Translator {
    type Item = Result<Statement, TranslateError>;

    fn next(&mut self) -> Option<Self::Item> {
        if let Some((line, raw)) = self.held.take() {
            return Some(self.translate_line(line, &raw));
        }
        while !self.done {
            let rest = &self.source[self.next_byte..];
            if rest.is_empty() {
                self.done = true;
                if let Some(at) = self.resume_at {
                    let past = PastEnd {
                        line: at,
                        lines: self.line,
                    };
                    self.past_end = Some(past);
                    return Some(Err(TranslateError {
                        line: at,
                        col: 1,
                        message: past.to_string(),
                    }));
                }
                return Some(Ok(self.end_of_program()));
            }
            let (raw, used) = match rest.find('\n') {
                Some(i) => (&rest[..i], i + 1),
                None => (rest, rest.len()),
            };
            self.next_byte += used;
            self.line += 1;
            let raw = raw.strip_suffix('\r').unwrap_or(raw);
            if let Some(e) = crate::limits::line_too_long(
                raw,
                self.line,
                " (split the statement: a MAC can hold part of a list)",
            ) {
                self.done = true;
                return Some(Err(e));
            }
            let code = raw.split(';').next().unwrap_or("");
            if code.trim().is_empty() {
                continue;
            }
            let line = self.line;
            // Borrow juggling: the raw line lives in self.source.
            let raw = raw.to_string();
            match self.resume_at {
                Some(at) if line < at => {
                    // Before the SEARCH point: its state counts, its blocks are not run.
                    if let Err(e) = self.statement(line, &raw) {
                        self.done = true;
                        return Some(Err(e));
                    }
                    continue;
                }
                Some(_) => {
                    self.resume_at = None;
                    let restored = if self.is_cut(line, &raw) {
                        self.restore_for_cut(line)
                    } else {
                        self.restore(line)
                    };
                    match restored {
                        Ok(r) if !r.blocks.is_empty() => {
                            self.held = Some((line, raw));
                            return Some(Ok(r));
                        }
                        Ok(_) => {}
                        Err(e) => {
                            self.done = true;
                            return Some(Err(e));
                        }
                    }
                }
                None => {}
            }
            return Some(self.translate_line(line, &raw));
        }
        None
    }
}

impl Translator {
    fn translate_line(&mut self, line: u32, raw: &str) -> Result<Statement, TranslateError> {
        let text = raw.trim().to_string();
        match self.statement(line, raw) {
            Ok(blocks) => {
                self.made += blocks.len() as u64;
                if self.made > self.max_blocks {
                    self.done = true;
                    return Err(TranslateError {
                        line,
                        col: 1,
                        message: format!(
                            "the program makes more than {} blocks (the most a program may make)",
                            self.max_blocks
                        ),
                    });
                }
                Ok(Statement { line, text, blocks })
            }
            Err(e) => {
                self.done = true;
                Err(e)
            }
        }
    }
}

/// Translates a whole program; the first error fails it.
pub fn translate_all(
    source: &str,
    magazine: &Magazine,
    settings: &MachineSettings,
    start: [i64; 3],
) -> Result<Vec<Statement>, TranslateError> {
    Translator::new(source, magazine.clone(), settings.clone(), start).collect()
}
