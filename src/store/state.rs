//! The stores in memory (patent Table A): program memory, the MDI buffer, the T-code table and
//! the tool file, and how one journal record changes them. The same `apply` serves a live
//! operator action and the replay of the journal at start, so both give the same result.

use super::lathe::LatheState;
use super::names::program_name;
use super::record::{EditTarget, Record};
use super::toolfile::{parse_tool_text, tool_text, tool_text_keeping};
use crate::settings::Dialect;
use crate::tooldata::{
    parse_tape, parse_tcodes, Magazine, TCodeTable, ToolFile, SAMPLE_TAPE, SAMPLE_TCODES,
};
use novanc_editor::{Buffer, EditError, ExecOptions, Outcome};
use std::collections::BTreeMap;

/// Table B, the embedded default part program (docs/language.md).
pub const TABLEB: &str = include_str!("../../programs/tableb.ap");

/// Why a change was not applied (nothing changed).
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The editor refused the command line (or the tool-file validator did).
    Edit(EditError),
    /// Anything else, with the operator's message.
    Other(String),
}

impl Refusal {
    /// The operator's message.
    pub fn text(self) -> String {
        match self {
            Refusal::Edit(e) => e.to_string(),
            Refusal::Other(m) => m,
        }
    }
}

/// What a store holds when nothing is saved, and so which machine's store it is: the centre's
/// embedded defaults for a magazine of so many pockets, or a lathe's (`store::lathe`).
#[derive(Clone, Debug)]
pub enum Base {
    /// The machining centre's stores, with a magazine of this many pockets.
    Centre(u32),
    /// A lathe's stores, starting as this state.
    Lathe(LatheState),
}

impl Base {
    /// The state of a store with nothing saved.
    pub fn defaults(&self) -> State {
        match self {
            Base::Centre(capacity) => State::defaults(*capacity),
            Base::Lathe(l) => State::lathe(l.clone()),
        }
    }

    /// The magazine capacity (a lathe's store has no magazine: 1).
    pub fn capacity(&self) -> u32 {
        match self {
            Base::Centre(capacity) => *capacity,
            Base::Lathe(_) => 1,
        }
    }
}

/// Program memory, MDI buffer, T-code table and tool file; on a lathe, instead, each channel's
/// program and tools and the part counter (`lathe`).
#[derive(Clone, Debug)]
pub struct State {
    /// Part programs by name.
    pub programs: BTreeMap<String, Buffer>,
    /// The G-code dialect each program was stored in (docs/gcode.md "Fanuc dialect"), by
    /// name: the machine's when it was read or made, a copy's from its original. A program
    /// not here (stored before programs kept their dialect, or by a store that was told no
    /// machine dialect) is read in the machine's dialect of the day.
    pub dialects: BTreeMap<String, Dialect>,
    /// The current program's name (always a key of `programs`).
    pub current: String,
    /// The MDI buffer.
    pub mdi: Buffer,
    /// Which tool sits in which pocket.
    pub tcodes: TCodeTable,
    /// The tool file as the operator sees and edits it (one T code per line).
    pub tool_buf: Buffer,
    /// The tool file parsed from `tool_buf`.
    pub tools: ToolFile,
    /// The G-code interpreter's persistent parameters (#5161–#5390, LinuxCNC's parameter
    /// file: the G28/G30 homes, G92, the selected system, the nine systems' zeros and
    /// rotations), in millionths of their unit (nanometres, micro-degrees). A parameter not
    /// here is 0 (#5220, the system in force, is then 1: G54).
    pub params: BTreeMap<u16, i64>,
    /// A lathe's stores. When set, this is a lathe's store: the centre's fields above stay
    /// empty, are not written, and their records are refused (and the other way round).
    pub lathe: Option<LatheState>,
}

/// The largest work offset, nanometres (100 m): an INPUT beyond it is refused.
pub const OFFSET_LIMIT_NM: i64 = 100_000_000_000;

/// The largest persistent parameter, millionths (1,000,000 mm or degrees: a G10 rotation may
/// be that large): a record beyond it is refused.
pub const PARAM_LIMIT: i64 = 1_000_000_000_000;

/// Tape text with its record separators (CR, CR LF) made end-of-block characters.
pub fn tape_text(text: &str) -> String {
    text.replace("\r\n", "\n").replace('\r', "\n")
}

/// Moves a buffer's pointer to `p` (clamped to the buffer).
pub fn set_pointer(b: &mut Buffer, p: usize) {
    b.set_pointer(p);
}

impl State {
    /// The embedded defaults: Table B as `TABLEB`, an empty MDI buffer, the sample T-code table
    /// and the tool file read from the sample tape.
    pub fn defaults(capacity: u32) -> State {
        let tape = parse_tape(SAMPLE_TAPE, "tools.tt").unwrap_or_default();
        let tcodes = parse_tcodes(SAMPLE_TCODES, "magazine.tc", capacity).unwrap_or_else(|_| {
            let mut t = TCodeTable::new(capacity);
            if let Ok(s) = parse_tcodes(SAMPLE_TCODES, "magazine.tc", 99) {
                for (tc, n) in s.iter() {
                    let _ = t.assign(tc, Some(n));
                }
            }
            t
        });
        let m = Magazine::load(tcodes, &tape);
        let mut programs = BTreeMap::new();
        programs.insert("TABLEB".to_string(), Buffer::from_text(&tape_text(TABLEB)));
        State {
            programs,
            current: "TABLEB".to_string(),
            mdi: Buffer::new(),
            tool_buf: Buffer::from_text(&tool_text(&m)),
            tcodes: m.tcodes,
            tools: m.tools,
            params: BTreeMap::new(),
            dialects: BTreeMap::new(),
            lathe: None,
        }
    }

    /// A lathe's store holding `l`.
    pub fn lathe(l: LatheState) -> State {
        State {
            programs: BTreeMap::new(),
            current: String::new(),
            mdi: Buffer::new(),
            tcodes: TCodeTable::new(1),
            tool_buf: Buffer::new(),
            tools: ToolFile::new(1),
            params: BTreeMap::new(),
            dialects: BTreeMap::new(),
            lathe: Some(l),
        }
    }

    /// The magazine the translator gets.
    pub fn magazine(&self) -> Magazine {
        Magazine {
            tcodes: self.tcodes.clone(),
            tools: self.tools.clone(),
        }
    }

    /// Rebuilds the tool-file text from the T-code table and tool file, keeping the lines that
    /// did not change as typed and the pointer at the start of the same line.
    fn refresh_tool_buf(&mut self) {
        let line = self.tool_buf.line_of(self.tool_buf.pointer());
        let text = tool_text_keeping(&self.tool_buf.text(), &self.magazine());
        if text == self.tool_buf.text() {
            return;
        }
        let mut b = Buffer::from_text(&text);
        let start = b.line_start(line);
        b.set_pointer(start);
        self.tool_buf = b;
    }

    /// Changes the magazine capacity, dropping (with a warning) pockets beyond it.
    pub fn resize(&mut self, capacity: u32) -> Vec<String> {
        let mut warnings = Vec::new();
        if capacity == self.tcodes.capacity() {
            return warnings;
        }
        let mut tc = TCodeTable::new(capacity);
        let mut tools = ToolFile::new(capacity);
        for (t, n) in self.tcodes.iter() {
            if tc.assign(t, Some(n)).is_err() {
                warnings.push(format!(
                    "T{t:02} (tool {n:05}) is beyond the magazine's {capacity} pockets; it was removed from the T-code table"
                ));
                continue;
            }
            tools.set(t, self.tools.get(t).cloned());
        }
        self.tcodes = tc;
        self.tools = tools;
        self.refresh_tool_buf();
        warnings
    }

    /// Records program `name`'s dialect (None: not recorded, the machine's at each run).
    fn set_dialect(&mut self, name: &str, dialect: Option<Dialect>) {
        match dialect {
            Some(d) => self.dialects.insert(name.to_string(), d),
            None => self.dialects.remove(name),
        };
    }

    /// The buffer an edit record names.
    fn buffer_mut(&mut self, target: &EditTarget) -> Result<&mut Buffer, Refusal> {
        match target {
            EditTarget::Program(n) => self
                .programs
                .get_mut(n)
                .ok_or_else(|| Refusal::Other(format!("no program {n} in program memory"))),
            EditTarget::Mdi => Ok(&mut self.mdi),
            EditTarget::ToolFile => Ok(&mut self.tool_buf),
        }
    }

    /// Applies one change atomically. Returns what the editor produced and whether anything
    /// (text or pointer) changed, so that nothing-changing lines need no journal record.
    pub fn apply(
        &mut self,
        rec: &Record,
        y_max_lines: Option<usize>,
    ) -> Result<(Outcome, bool), Refusal> {
        let lathe_rec = matches!(
            rec,
            Record::ChannelProgram { .. }
                | Record::ChannelTools { .. }
                | Record::ChannelParams { .. }
                | Record::ChannelMdi { .. }
                | Record::ChannelPointer { .. }
                | Record::ChannelJog { .. }
                | Record::Posts(_)
                | Record::Parts { .. }
        );
        match (self.lathe.as_mut(), lathe_rec) {
            (Some(l), _) => return l.apply(rec),
            (None, true) => {
                return Err(Refusal::Other(
                    "a lathe's record (a channel's program or tools, the part counter) is not kept in the centre's stores".to_string(),
                ))
            }
            (None, false) => {}
        }
        match rec {
            Record::Edit { target, line } => {
                if *target == EditTarget::ToolFile {
                    let tcodes = &self.tcodes;
                    let check = |b: &Buffer| parse_tool_text(&b.text(), tcodes).map(|_| ());
                    let opts = ExecOptions {
                        y_max_lines,
                        validator: Some(&check),
                    };
                    let before = self.tool_buf.pointer();
                    let out = self.tool_buf.execute(line, &opts).map_err(Refusal::Edit)?;
                    if out.changed {
                        if let Ok(tools) = parse_tool_text(&self.tool_buf.text(), &self.tcodes) {
                            self.tools = tools;
                        }
                    }
                    let moved = out.changed || self.tool_buf.pointer() != before;
                    return Ok((out, moved));
                }
                let b = self.buffer_mut(target)?;
                let before = b.pointer();
                let opts = ExecOptions {
                    y_max_lines,
                    validator: None,
                };
                let out = b.execute(line, &opts).map_err(Refusal::Edit)?;
                let moved = out.changed || b.pointer() != before;
                Ok((out, moved))
            }
            Record::Select(name) => {
                let n = program_name(name).map_err(Refusal::Other)?;
                if !self.programs.contains_key(&n) {
                    return Err(Refusal::Other(format!("no program {n} in program memory")));
                }
                let moved = self.current != n;
                self.current = n;
                Ok((Outcome::default(), moved))
            }
            Record::NewProgram { name, dialect } => {
                let n = program_name(name).map_err(Refusal::Other)?;
                if self.programs.contains_key(&n) {
                    return Err(Refusal::Other(format!(
                        "program {n} is already in program memory"
                    )));
                }
                self.programs.insert(n.clone(), Buffer::new());
                self.set_dialect(&n, *dialect);
                self.current = n;
                Ok((Outcome::default(), true))
            }
            Record::ProgramRead {
                name,
                text,
                dialect,
            } => {
                let n = program_name(name).map_err(Refusal::Other)?;
                self.programs
                    .insert(n.clone(), Buffer::from_text(&tape_text(text)));
                self.set_dialect(&n, *dialect);
                self.current = n;
                Ok((Outcome::default(), true))
            }
            Record::ToolFile(text) => {
                let tools = parse_tool_text(text, &self.tcodes).map_err(Refusal::Other)?;
                self.tools = tools;
                self.tool_buf = Buffer::from_text(text);
                Ok((Outcome::default(), true))
            }
            Record::TCodes(text) => {
                let cap = self.tcodes.capacity();
                let new = parse_tcodes(text, "T-code table", cap)
                    .map_err(|e| Refusal::Other(e.to_string()))?;
                for t in 1..=cap {
                    if new.tool_in(t) != self.tcodes.tool_in(t) {
                        self.tools.set(t, None);
                    }
                }
                let changed = new != self.tcodes;
                self.tcodes = new;
                self.refresh_tool_buf();
                Ok((Outcome::default(), changed))
            }
            Record::Move { tool, t } => {
                let old = self.tcodes.tcode_of(*tool);
                if old == Some(*t) {
                    return Ok((Outcome::default(), false));
                }
                let mut tc = self.tcodes.clone();
                if let Some(o) = old {
                    tc.assign(o, None).map_err(Refusal::Other)?;
                }
                tc.assign(*t, Some(*tool)).map_err(Refusal::Other)?;
                let data = old.and_then(|o| self.tools.get(o).cloned());
                if let Some(o) = old {
                    self.tools.set(o, None);
                }
                self.tools.set(*t, data);
                self.tcodes = tc;
                self.refresh_tool_buf();
                Ok((Outcome::default(), true))
            }
            Record::ClearMdi => {
                let changed = !self.mdi.is_empty();
                self.mdi = Buffer::new();
                Ok((Outcome::default(), changed))
            }
            Record::Delete(name) => {
                let n = program_name(name).map_err(Refusal::Other)?;
                if !self.programs.contains_key(&n) {
                    return Err(Refusal::Other(format!("no program {n} in program memory")));
                }
                if self.programs.len() == 1 {
                    return Err(Refusal::Other(format!(
                        "{n} is the only program; program memory keeps at least one"
                    )));
                }
                self.programs.remove(&n);
                self.dialects.remove(&n);
                if self.current == n {
                    if let Some(first) = self.programs.keys().next() {
                        self.current = first.clone();
                    }
                }
                Ok((Outcome::default(), true))
            }
            Record::Copy { from, to } | Record::Rename { from, to } => {
                let a = program_name(from).map_err(Refusal::Other)?;
                let b = program_name(to).map_err(Refusal::Other)?;
                let Some(text) = self.programs.get(&a).map(|buf| buf.text()) else {
                    return Err(Refusal::Other(format!("no program {a} in program memory")));
                };
                if self.programs.contains_key(&b) {
                    return Err(Refusal::Other(format!(
                        "program memory already holds a program {b}; delete or rename it first"
                    )));
                }
                let rename = matches!(rec, Record::Rename { .. });
                let buf = if rename {
                    self.programs.remove(&a).unwrap_or_default()
                } else {
                    Buffer::from_text(&text)
                };
                let dialect = self.dialects.get(&a).copied();
                if rename {
                    self.dialects.remove(&a);
                }
                self.set_dialect(&b, dialect);
                self.programs.insert(b.clone(), buf);
                if !rename || self.current == a {
                    self.current = b;
                }
                Ok((Outcome::default(), true))
            }
            Record::Params(ps) => {
                for &(n, v) in ps {
                    if !crate::gcode::state::is_kept(usize::from(n)) {
                        return Err(Refusal::Other(format!(
                            "#{n} is not a parameter the controller keeps (#500-#999, #3002, #5161-#5169, #5181-#5189, #5210-#5390)"
                        )));
                    }
                    if v.abs() > PARAM_LIMIT {
                        return Err(Refusal::Other(format!(
                            "#{n} = {} is beyond {}",
                            v as f64 / 1e6,
                            PARAM_LIMIT / 1_000_000
                        )));
                    }
                }
                let mut changed = false;
                for &(n, v) in ps {
                    let old = self.params.get(&n).copied().unwrap_or(0);
                    changed |= old != v;
                    if v == 0 {
                        self.params.remove(&n);
                    } else {
                        self.params.insert(n, v);
                    }
                }
                Ok((Outcome::default(), changed))
            }
            Record::ChannelProgram { .. }
            | Record::ChannelTools { .. }
            | Record::ChannelParams { .. }
            | Record::ChannelMdi { .. }
            | Record::ChannelPointer { .. }
            | Record::ChannelJog { .. }
            | Record::Posts(_)
            | Record::Parts { .. } => Err(Refusal::Other(
                "not a record of the centre's stores".to_string(),
            )),
            Record::TCode { t, tool } => {
                if self.tcodes.tool_in(*t) == *tool && *t >= 1 && *t <= self.tcodes.capacity() {
                    return Ok((Outcome::default(), false));
                }
                self.tcodes.assign(*t, *tool).map_err(Refusal::Other)?;
                self.tools.set(*t, None);
                self.refresh_tool_buf();
                Ok((Outcome::default(), true))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tape_text_ends_blocks() {
        assert_eq!(tape_text("A\r\nB\rC\n"), "A\nB\nC\n");
    }

    #[test]
    fn a_program_keeps_its_dialect_through_edits_copies_renames_and_the_snapshot() {
        let mut s = State::defaults(24);
        let read = |name: &str, dialect| Record::ProgramRead {
            name: name.into(),
            text: "G0 X1\n".into(),
            dialect,
        };
        let ok = |s: &mut State, r: Record| s.apply(&r, None).map(|_| ()).unwrap();
        ok(&mut s, read("F.NGC", Some(Dialect::Fanuc)));
        ok(&mut s, read("L.NGC", Some(Dialect::LinuxCnc)));
        ok(&mut s, read("OLD.NGC", None));
        ok(
            &mut s,
            Record::Edit {
                target: EditTarget::Program("F.NGC".into()),
                line: "IG0 Y2*".into(),
            },
        );
        let copy = |from: &str, to: &str| Record::Copy {
            from: from.into(),
            to: to.into(),
        };
        ok(&mut s, copy("F.NGC", "F2.NGC"));
        ok(
            &mut s,
            Record::Rename {
                from: "L.NGC".into(),
                to: "L2.NGC".into(),
            },
        );
        ok(
            &mut s,
            Record::NewProgram {
                name: "N.NGC".into(),
                dialect: Some(Dialect::Fanuc),
            },
        );
        ok(&mut s, Record::Delete("N.NGC".into()));
        let want: BTreeMap<String, Dialect> = [
            ("F.NGC", Dialect::Fanuc),
            ("F2.NGC", Dialect::Fanuc),
            ("L2.NGC", Dialect::LinuxCnc),
        ]
        .into_iter()
        .map(|(n, d)| (n.to_string(), d))
        .collect();
        assert_eq!(s.dialects, want);
        // A program read again takes the dialect of that read (none: none recorded).
        ok(&mut s, read("F2.NGC", None));
        ok(&mut s, read("OLD.NGC", Some(Dialect::LinuxCnc)));
        let snap = super::super::snapshot::encode(&s, 7);
        let back = super::super::snapshot::read(&snap, 24);
        assert!(back.lost.is_empty(), "{:?}", back.lost);
        let want: BTreeMap<String, Dialect> = [
            ("F.NGC", Dialect::Fanuc),
            ("L2.NGC", Dialect::LinuxCnc),
            ("OLD.NGC", Dialect::LinuxCnc),
        ]
        .into_iter()
        .map(|(n, d)| (n.to_string(), d))
        .collect();
        assert_eq!(back.state.dialects, want);
        assert_eq!(back.state.programs.len(), 5);
    }

    #[test]
    fn refused_changes_leave_the_state_alone() {
        let mut s = State::defaults(24);
        let tool_text = s.tool_buf.text();
        let bad = [
            Record::TCode {
                t: 3,
                tool: Some(106),
            },
            Record::Move { tool: 106, t: 30 },
            Record::ToolFile("T01\n".into()),
            Record::TCodes("T01 1\nT02 1\n".into()),
            Record::Select("NONE".into()),
            Record::Delete("TABLEB".into()),
            Record::Params(vec![(5221, 1), (5400, 1)]),
            Record::Params(vec![(5221, 1), (5222, PARAM_LIMIT + 1)]),
            Record::Edit {
                target: EditTarget::Program("NONE".into()),
                line: "IX".into(),
            },
        ];
        for r in &bad {
            assert!(s.apply(r, None).is_err(), "{r:?}");
            assert_eq!(s.tool_buf.text(), tool_text, "{r:?}");
            assert_eq!(s.magazine(), crate::tooldata::sample_magazine(), "{r:?}");
            assert_eq!(s.program_names_for_test(), ["TABLEB"]);
            assert!(s.params.is_empty());
        }
    }

    #[test]
    fn a_lathes_store_and_the_centres_refuse_each_others_records_and_bad_lathe_records() {
        let lathe_recs = [
            Record::ChannelProgram {
                ch: 0,
                name: "A".into(),
                text: "G0 X1\n".into(),
                dialect: None,
            },
            Record::Parts {
                target: 5,
                counts: vec![1, 1, 1],
            },
        ];
        let mut centre = State::defaults(24);
        for r in &lathe_recs {
            assert!(centre.apply(r, None).is_err(), "{r:?}");
        }
        assert!(centre.lathe.is_none());
        let desc = crate::lathe::desc::LatheDesc::citizen();
        let l = LatheState::defaults(&desc);
        let mut s = State::lathe(l.clone());
        let bad = [
            Record::Select("TABLEB".into()),
            Record::ClearMdi,
            Record::ChannelProgram {
                ch: 3,
                name: "A".into(),
                text: "".into(),
                dialect: None,
            },
            Record::ChannelProgram {
                ch: 0,
                name: "".into(),
                text: "".into(),
                dialect: None,
            },
            Record::ChannelProgram {
                ch: 0,
                name: "A".into(),
                text: "x".repeat(super::super::lathe::MAX_PROGRAM + 1),
                dialect: None,
            },
            Record::ChannelTools {
                ch: 1,
                text: Some("tool 1 radius x\n".into()),
            },
            Record::Parts {
                target: 0,
                counts: vec![0, 0, 0],
            },
            Record::Parts {
                target: 5,
                counts: vec![0, 0],
            },
        ];
        for r in &bad {
            assert!(s.apply(r, None).is_err(), "{r:?}");
            assert_eq!(s.lathe.as_ref(), Some(&l), "{r:?}");
        }
        for r in &lathe_recs {
            assert_eq!(s.apply(r, None).map(|o| o.1), Ok(true), "{r:?}");
        }
        assert_eq!(s.lathe.as_ref().unwrap().counter.counts, [1, 1, 1]);
    }

    impl State {
        fn program_names_for_test(&self) -> Vec<&str> {
            self.programs.keys().map(|k| k.as_str()).collect()
        }
    }
}
