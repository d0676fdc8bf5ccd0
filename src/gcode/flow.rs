//! Program flow (docs/gcode.md "O-words"): where the next line comes from. The program's
//! files, the call stack with each call's local parameters, the O-word labels already met,
//! and LinuxCNC 2.9's way of moving between them: a false `if`, a `while` that ends, a `break`
//! or a subroutine's definition make the reader skip forward, without evaluating anything,
//! to the next O-word line with the same label; a loop's end and a call jump back to where
//! the label was met; a call to a subroutine not yet met looks for a file of that name in
//! the subroutine path, then searches forward.
//!
//! Labels inside a subroutine are its own (LinuxCNC names them `sub#label`); a subroutine's
//! name is global.

use super::read::{OKind, OLine, MAX_ARGS};
use super::state::InterpState;
use std::collections::HashMap;
use std::sync::Arc;

/// The deepest call nesting (LinuxCNC's INTERP_SUB_ROUTINE_LEVELS − 1).
pub const MAX_CALL_DEPTH: usize = 9;

/// One file of the program: the main program, or a subroutine file found by name. It is read
/// with a cursor (a byte position), as LinuxCNC reads a file: no index of its lines is kept,
/// so memory follows the program's content, not its count of lines (docs/limits.md).
#[derive(Clone, Debug)]
pub struct Unit {
    /// The name the messages use (`drill.ngc`); empty for the main program.
    pub name: String,
    /// The text.
    pub text: Arc<str>,
}

impl Unit {
    /// A unit of `text`.
    pub fn new(name: String, text: Arc<str>) -> Unit {
        Unit { name, text }
    }

    /// The line that starts at byte `at` (without its line end) and where the next one
    /// starts; `None` at the end.
    pub fn line_at(&self, at: usize) -> Option<(&str, usize)> {
        line_at(&self.text, at)
    }

    /// Line `i` (0-based), found by reading from the start.
    pub fn nth_line(&self, i: usize) -> Option<&str> {
        self.text
            .split('\n')
            .nth(i)
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
    }
}

/// The line of `text` that starts at byte `at` (without its line end) and where the next one
/// starts; `None` at the end.
pub fn line_at(text: &str, at: usize) -> Option<(&str, usize)> {
    let rest = text.get(at..)?;
    if rest.is_empty() {
        return None;
    }
    // A plain loop: a program's lines are short, and the library's search is made for long
    // texts (it costs three times as much on a line of 25 bytes).
    let (body, next) = match rest.bytes().position(|c| c == b'\n') {
        Some(e) => (&rest[..e], at + e + 1),
        None => (rest, text.len()),
    };
    Some((body.strip_suffix('\r').unwrap_or(body), next))
}

/// The characters of `raw` that the reader reads: outside comments, spaces and tabs dropped.
fn significant(raw: &str) -> impl Iterator<Item = u8> + '_ {
    raw.bytes()
        .take_while(|&c| c != b'(' && c != b';')
        .filter(|c| !c.is_ascii_whitespace())
}

/// If `raw` is an O-word line (after an optional `/` and N number), the bytes after its `o`
/// (spaces and comments left in); cheap, for skipping without reading.
pub fn o_label(raw: &str) -> Option<&str> {
    let b = raw.as_bytes();
    let mut i = 0;
    let skip_ws = |i: &mut usize| {
        while *i < b.len() && b[*i].is_ascii_whitespace() {
            *i += 1;
        }
    };
    skip_ws(&mut i);
    if b.get(i) == Some(&b'/') {
        i += 1;
        skip_ws(&mut i);
    }
    if matches!(b.get(i), Some(b'n' | b'N')) {
        i += 1;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.' || b[i].is_ascii_whitespace()) {
            i += 1;
        }
    }
    match b.get(i) {
        Some(b'o' | b'O') => raw.get(i + 1..),
        // ISO's program number (Fanuc's `:0100`, read as `O0100`).
        Some(b':') if b.get(i + 1).is_some_and(u8::is_ascii_digit) => raw.get(i + 1..),
        _ => None,
    }
}

/// Whether the label after an `o` (from [`o_label`]) is `name` (lower case, no spaces): the
/// digits of `o100` compared as a number, the name of `o<name>` ignoring case and spaces.
fn label_is(rest: &str, name: &str) -> bool {
    let mut it = significant(rest).peekable();
    if it.peek() == Some(&b'<') {
        it.next();
        let mut want = name.bytes();
        for c in it {
            if c == b'>' {
                return want.next().is_none();
            }
            if Some(c.to_ascii_lowercase()) != want.next() {
                return false;
            }
        }
        return false;
    }
    let Ok(want) = name.parse::<u64>() else {
        return false;
    };
    let mut v: u64 = 0;
    let mut digits = 0;
    for c in it {
        if !c.is_ascii_digit() {
            break;
        }
        v = v.saturating_mul(10).saturating_add(u64::from(c - b'0'));
        digits += 1;
    }
    digits > 0 && v == want
}

/// Finds a subroutine's file by the subroutine's name (`o<name> call` looks for `name.ngc`
/// in the subroutine path).
pub trait SubFinder {
    /// The file for subroutine `name` (lower case): its display name and text.
    fn find(&self, name: &str) -> Result<Option<(String, Arc<str>)>, String>;
}

/// A finder shared between threads (the console's run and the window's backplot) finds what
/// it finds.
impl<T: SubFinder + ?Sized> SubFinder for Arc<T> {
    fn find(&self, name: &str) -> Result<Option<(String, Arc<str>)>, String> {
        (**self).find(name)
    }
}

/// No subroutine files.
pub struct NoFiles;

impl SubFinder for NoFiles {
    fn find(&self, _name: &str) -> Result<Option<(String, Arc<str>)>, String> {
        Ok(None)
    }
}

/// A place in the program: a line of a unit, by its number and the byte where it starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pos {
    /// The unit (0 = the main program).
    pub unit: usize,
    /// The line, 0-based.
    pub line: usize,
    /// The byte where the line starts.
    pub byte: usize,
}

impl Pos {
    /// The start of unit `unit`.
    pub fn start(unit: usize) -> Pos {
        Pos {
            unit,
            line: 0,
            byte: 0,
        }
    }
}

/// How a subroutine was called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CallType {
    /// `O... call`.
    Oword,
    /// `M98 P...` (Fanuc style).
    M98,
    /// `G65 P... L...` with arguments (Fanuc's Custom Macro B): local #1–#33 of its own.
    G65,
    /// The macro of a `G66 P...` modal call, called after a move: as G65.
    G66,
}

/// Fanuc's local variables, #1 to #33: each G65 call level has its own.
pub const LOCALS: usize = 33;

/// Fanuc's deepest WHILE/DO nesting (DO1 to DO3).
pub const MAX_LOOPS: usize = 3;

#[derive(Clone, Debug)]
struct Label {
    kind: OKind,
    pos: Pos,
    repeat_count: i64,
}

#[derive(Clone, Debug)]
struct Frame {
    /// The subroutine's name (global label).
    name: String,
    call_type: CallType,
    /// Where to go back to.
    ret: Pos,
    /// The caller's #1 … #30 (o-word call) or #1 … #33 (G65).
    saved_args: [f64; LOCALS],
    /// The subroutine's local named parameters.
    locals: HashMap<String, f64>,
    /// M98 L: repeats of this frame's M98 line still to run (−1: none under way).
    m98_left: i64,
    /// Fanuc's open WHILE/DO loops of this program: number and the WHILE (DO) line.
    loops: Vec<(u8, Pos)>,
}

/// What a control line asks of the caller.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Go on reading.
    Next,
    /// A subroutine returned (its M73 state may need restoring: done here).
    Returned,
}

/// The program's files, the call stack and the skipping state.
pub struct Flow {
    /// The units; 0 is the main program.
    pub units: Vec<Unit>,
    /// The next line to read.
    pub pc: Pos,
    labels: HashMap<String, Label>,
    frames: Vec<Frame>,
    /// Skipping forward to the next O-line of this (full) name.
    skipping: Option<String>,
    /// Skipping forward to this subroutine's `sub` line.
    skipping_to_sub: Option<String>,
    defining_sub: Option<String>,
    executed_if: bool,
    doing_break: bool,
    doing_continue: bool,
    /// The frame the pending M98 loop counter belongs to (see `call`).
    m98_main_left: i64,
    /// A loop or a call went back to a line already read (so the lines executed are more
    /// than the file's).
    jumped: bool,
    /// Where the line that started the current skip is (a call searching forward, a
    /// definition skipped over), for the error at the end of the program.
    skip_from: Option<Pos>,
    /// Fanuc's open WHILE/DO loops of the main program.
    main_loops: Vec<(u8, Pos)>,
    /// Where a sequence number was found by GOTO: (unit, the byte of the GOTO line, n) → the
    /// line.
    seq_cache: HashMap<(usize, usize, i64), Pos>,
    /// The line after the ENDm that closes the WHILE at (unit, byte).
    end_cache: HashMap<(usize, usize), Pos>,
}

impl Flow {
    /// The flow of a program `text`, starting at its first line.
    pub fn new(text: Arc<str>) -> Flow {
        Flow {
            units: vec![Unit::new(String::new(), text)],
            pc: Pos::start(0),
            labels: HashMap::new(),
            frames: Vec::new(),
            skipping: None,
            skipping_to_sub: None,
            defining_sub: None,
            executed_if: false,
            doing_break: false,
            doing_continue: false,
            m98_main_left: -1,
            skip_from: None,
            jumped: false,
            main_loops: Vec::new(),
            seq_cache: HashMap::new(),
            end_cache: HashMap::new(),
        }
    }

    /// Whether a loop or a call has gone back to a line already read.
    pub fn jumped(&self) -> bool {
        self.jumped || !self.frames.is_empty()
    }

    /// A line has been read again without a jump of the flow's own (a lathe G70 runs its
    /// profile's lines where it stands): the lines executed are more than the file's.
    pub fn read_again(&mut self) {
        self.jumped = true;
    }

    /// The line that started the skip that reached the end of a unit (a call that searched
    /// forward, a definition with no end), if any.
    pub fn skip_from(&self) -> Option<Pos> {
        self.skip_from
    }

    /// The call level (0 in the main program).
    pub fn level(&self) -> usize {
        self.frames.len()
    }

    /// The main program's line (1-based) that called into the subroutine running now (or
    /// the line being read, in the main program).
    pub fn main_line(&self) -> usize {
        self.frames
            .iter()
            .find(|f| f.ret.unit == 0)
            .map_or(self.pc.line, |f| f.ret.line)
    }

    /// Whether lines are being skipped (nothing but O-lines is read).
    pub fn skipping(&self) -> bool {
        self.skipping.is_some() || self.skipping_to_sub.is_some()
    }

    /// Whether a subroutine's definition is being skipped over.
    pub fn defining(&self) -> bool {
        self.defining_sub.is_some()
    }

    /// The name of the subroutine being run (or defined), if any.
    pub fn sub_name(&self) -> Option<&str> {
        match self.frames.last() {
            Some(f) => Some(&f.name),
            None => self.defining_sub.as_deref(),
        }
    }

    /// The call level of the innermost macro call (G65, or G66's modal call: each has #1–#33
    /// of its own), whose locals the running program reads (an M98 subprogram shares its
    /// caller's); 0 for the main program's.
    pub fn g65_level(&self) -> usize {
        self.frames
            .iter()
            .rposition(|f| matches!(f.call_type, CallType::G65 | CallType::G66))
            .map_or(0, |i| i + 1)
    }

    /// The local named parameters of the running subroutine (None at level 0).
    pub fn locals(&self) -> Option<&HashMap<String, f64>> {
        self.frames.last().map(|f| &f.locals)
    }

    /// Sets a local named parameter of the running subroutine, or of the main program
    /// (kept in the interpreter's state at level 0).
    pub fn set_local(&mut self, st: &mut InterpState, name: &str, v: f64) {
        match self.frames.last_mut() {
            Some(f) => {
                f.locals.insert(name.to_string(), v);
            }
            None => {
                st.named.insert(name.to_string(), v);
            }
        }
    }

    /// The full name of an O-line's label: a subroutine's name is global; other labels are
    /// the subroutine's own.
    pub fn full_name(&self, o: &OLine) -> String {
        match o.kind {
            OKind::Sub | OKind::Endsub | OKind::Call | OKind::Return | OKind::Bare => {
                o.label.clone()
            }
            _ => format!("{}#{}", self.sub_name().unwrap_or(""), o.label),
        }
    }

    /// Whether an O-line met while skipping is to be read in full (its label is the one
    /// skipped to).
    pub fn reads_while_skipping(&self, label: &str, kind: OKind) -> bool {
        if kind == OKind::Call {
            return false;
        }
        if kind == OKind::Sub && self.defining_sub.is_some() {
            // A definition inside the one being skipped over: refused (`control`).
            return true;
        }
        let o = OLine {
            label: label.to_string(),
            kind,
            value: None,
            args: Vec::new(),
            col: 0,
        };
        let name = self.full_name(&o);
        self.skipping.as_deref() == Some(name.as_str())
            || (matches!(kind, OKind::Sub | OKind::Bare)
                && self.skipping_to_sub.as_deref() == Some(name.as_str()))
    }

    fn define(&mut self, name: &str, kind: OKind, at: Pos) -> Result<(), String> {
        if let Some(l) = self.labels.get(name) {
            if l.pos == at {
                return Err(format!(
                    "{} {}: found in an illegal place",
                    short(name),
                    kind.name()
                ));
            }
            return Err(twice(name, l.pos));
        }
        self.labels.insert(
            name.to_string(),
            Label {
                kind,
                pos: at,
                repeat_count: -1,
            },
        );
        Ok(())
    }

    /// Label `name` met at `at`: defined there the first time, taken again there (a loop
    /// coming round), refused anywhere else.
    fn define_here(&mut self, name: &str, kind: OKind, at: Pos) -> Result<(), String> {
        match self.labels.get(name) {
            Some(l) if l.pos != at => Err(twice(name, l.pos)),
            Some(_) => Ok(()),
            None => self.define(name, kind, at),
        }
    }

    /// Executes an O-word line read at `at` (the line just read). `st` gets the arguments
    /// and return values.
    pub fn control(
        &mut self,
        o: &OLine,
        at: Pos,
        st: &mut InterpState,
        finder: &dyn SubFinder,
    ) -> Result<Outcome, String> {
        let name = self.full_name(o);
        if let (OKind::Sub, Some(d)) = (o.kind, &self.defining_sub) {
            // LinuxCNC refuses it too ("Nested subroutine definition"), even in a subroutine
            // that is never called.
            return Err(format!(
                "'{} sub' inside the definition of {}: a subroutine cannot be defined inside another",
                label(o),
                short(d)
            ));
        }
        if let Some(s) = &self.skipping {
            // A call never ends a skip (LinuxCNC's too): a subroutine calling itself by the
            // name being skipped over (its definition) is not run there.
            if *s != name || o.kind == OKind::Call {
                return Ok(Outcome::Next);
            }
        }
        if let Some(s) = &self.skipping_to_sub {
            if !(matches!(o.kind, OKind::Sub | OKind::Bare) && *s == name) {
                return Ok(Outcome::Next);
            }
        }
        match o.kind {
            OKind::Bare => {
                // A Fanuc-style program number: a subprogram's start (reached by M98), or
                // the main program's number.
                if self.skipping_to_sub.is_some() {
                    self.skipping = None;
                    self.skipping_to_sub = None;
                    if !self.labels.contains_key(&name) {
                        self.define(&name, OKind::Bare, at)?;
                    }
                }
                Ok(Outcome::Next)
            }
            OKind::Sub => {
                if let Some(f) = self.frames.last() {
                    if f.call_type != CallType::Oword {
                        return Err(format!(
                            "'o{} sub' must be called with 'o{} call', not M98",
                            o.label, o.label
                        ));
                    }
                }
                if self.skipping_to_sub.is_some() {
                    // Found the subroutine being called: define it and run it.
                    self.skipping = None;
                    self.skipping_to_sub = None;
                    if !self.labels.contains_key(&name) {
                        self.define(&name, OKind::Sub, at)?;
                    }
                    return Ok(Outcome::Next);
                }
                if let Some(f) = self.frames.last() {
                    if f.name != name {
                        return Err(format!(
                            "a subroutine definition '{} sub' inside the running subroutine {}",
                            label(o),
                            short(&f.name)
                        ));
                    }
                    // The call has arrived at its subroutine: run it.
                    return Ok(Outcome::Next);
                }
                // A definition met in the main program: note it and skip over it.
                self.define(&name, OKind::Sub, at)?;
                self.skip_from = Some(at);
                self.skipping = Some(name.clone());
                self.defining_sub = Some(name);
                Ok(Outcome::Next)
            }
            OKind::Endsub | OKind::Return => {
                if let Some(f) = self.frames.last() {
                    if f.call_type != CallType::Oword {
                        return Err(
                            "a subprogram called by M98 ends with M99, not endsub or return".into(),
                        );
                    }
                }
                match o.value {
                    Some(v) => {
                        st.return_value = v;
                        st.value_returned = true;
                    }
                    None => {
                        st.return_value = 0.0;
                        st.value_returned = false;
                    }
                }
                if self.frames.is_empty() {
                    if o.kind == OKind::Return && self.defining_sub.is_none() {
                        return Err(format!("{} return: not in a subroutine", label(o)));
                    }
                    if o.kind == OKind::Endsub {
                        if self.defining_sub.is_none() {
                            return Err(format!(
                                "{} endsub: not in a subroutine definition",
                                label(o)
                            ));
                        }
                        self.skipping = None;
                        self.defining_sub = None;
                    }
                    return Ok(Outcome::Next);
                }
                self.skipping = None;
                self.ret(st);
                Ok(Outcome::Returned)
            }
            OKind::Call => {
                let args = o.args.clone();
                self.call(&name, CallType::Oword, &args, at, st, finder)?;
                Ok(Outcome::Next)
            }
            OKind::Do => {
                self.skipping = None;
                if !self.labels.contains_key(&name) {
                    self.define(&name, OKind::Do, at)?;
                }
                Ok(Outcome::Next)
            }
            OKind::Repeat => {
                self.define_here(&name, OKind::Repeat, at)?;
                self.skipping = None;
                let count = o.value.unwrap_or(0.0);
                let l = self.labels.get_mut(&name).ok_or("label lost")?;
                if l.repeat_count == -1 {
                    l.repeat_count = count.round() as i64;
                }
                if l.repeat_count > 0 {
                    l.repeat_count -= 1;
                } else {
                    l.repeat_count = -1;
                    self.skipping = Some(name);
                }
                Ok(Outcome::Next)
            }
            OKind::While => {
                let known = self.labels.get(&name).cloned();
                if let Some(l) = &known {
                    if l.kind != OKind::Do && l.pos != at {
                        return Err(twice(&name, l.pos));
                    }
                }
                self.skipping = None;
                let test = o.value.unwrap_or(0.0) != 0.0;
                match known {
                    Some(l) if l.kind == OKind::Do => {
                        // The end of a do … while.
                        if test && !self.doing_break {
                            self.pc = l.pos;
                            self.jumped = true;
                        } else {
                            self.doing_break = false;
                        }
                    }
                    _ => {
                        if known.is_none() {
                            self.define(&name, OKind::While, at)?;
                        }
                        if !test {
                            self.skipping = Some(name);
                        }
                    }
                }
                Ok(Outcome::Next)
            }
            OKind::If => {
                self.define_here(&name, OKind::If, at)?;
                if o.value.unwrap_or(0.0) != 0.0 {
                    self.skipping = None;
                    self.executed_if = true;
                } else {
                    self.skipping = Some(name);
                    self.executed_if = false;
                }
                Ok(Outcome::Next)
            }
            OKind::Elseif | OKind::Else => {
                self.expect(&name, o, &[OKind::If])?;
                if self.executed_if {
                    self.skipping = Some(name);
                    return Ok(Outcome::Next);
                }
                if o.kind == OKind::Else || o.value.unwrap_or(0.0) != 0.0 {
                    self.skipping = None;
                    self.executed_if = true;
                }
                Ok(Outcome::Next)
            }
            OKind::Endif => {
                self.expect(&name, o, &[OKind::If])?;
                self.skipping = None;
                self.executed_if = true;
                Ok(Outcome::Next)
            }
            OKind::Break => {
                self.expect(&name, o, &[OKind::While, OKind::Do, OKind::Repeat])?;
                self.skipping = Some(name);
                self.doing_break = true;
                Ok(Outcome::Next)
            }
            OKind::Continue => {
                self.expect(&name, o, &[OKind::While, OKind::Do, OKind::Repeat])?;
                if self.skipping.as_deref() == Some(name.as_str()) {
                    return Ok(Outcome::Next);
                }
                self.skipping = Some(name);
                self.doing_continue = true;
                Ok(Outcome::Next)
            }
            OKind::Endwhile | OKind::Endrepeat => {
                let want = if o.kind == OKind::Endwhile {
                    OKind::While
                } else {
                    OKind::Repeat
                };
                let l = self.expect(&name, o, &[want])?;
                if self.skipping.as_deref() == Some(name.as_str()) {
                    self.skipping = None;
                    if self.doing_continue {
                        self.doing_continue = false;
                        self.pc = l.pos;
                        self.jumped = true;
                    } else {
                        self.doing_break = false;
                    }
                } else {
                    self.pc = l.pos;
                    self.jumped = true;
                }
                Ok(Outcome::Next)
            }
        }
    }

    fn expect(&self, name: &str, o: &OLine, kinds: &[OKind]) -> Result<Label, String> {
        let Some(l) = self.labels.get(name) else {
            return Err(format!(
                "{} {}: no '{} {}' before it",
                label(o),
                o.kind.name(),
                label(o),
                kinds[0].name()
            ));
        };
        if !kinds.contains(&l.kind) {
            return Err(format!(
                "{} {}: the label {} is a '{}' (line {}), not a '{}'",
                label(o),
                o.kind.name(),
                label(o),
                l.kind.name(),
                l.pos.line + 1,
                kinds[0].name()
            ));
        }
        Ok(l.clone())
    }

    /// Calls subroutine `name` (global) from the line at `at`.
    pub fn call(
        &mut self,
        name: &str,
        call_type: CallType,
        args: &[f64],
        at: Pos,
        st: &mut InterpState,
        finder: &dyn SubFinder,
    ) -> Result<(), String> {
        if self.frames.len() >= MAX_CALL_DEPTH {
            return Err(match call_type {
                CallType::M98 => {
                    format!("M98 P{name}: subprogram calls nested more than {MAX_CALL_DEPTH} deep")
                }
                CallType::G65 | CallType::G66 => {
                    format!("G65 P{name}: macro calls nested more than {MAX_CALL_DEPTH} deep")
                }
                CallType::Oword => format!(
                    "{} call: calls nested more than {MAX_CALL_DEPTH} deep",
                    short(name)
                ),
            });
        }
        let (to, search) = self.locate(name, call_type, finder)?;
        let mut saved = [0.0; LOCALS];
        // An o-word call's #1–#30 are its arguments, 0 when not given; a G65 call's #1–#33,
        // null (vacant) when not given.
        let (locals, absent) = match call_type {
            CallType::Oword => (MAX_ARGS, 0.0),
            CallType::G65 | CallType::G66 => (LOCALS, f64::NAN),
            CallType::M98 => (0, 0.0),
        };
        for (i, s) in saved.iter_mut().enumerate().take(locals) {
            *s = st.params[i + 1];
            st.params[i + 1] = args.get(i).copied().unwrap_or(absent);
        }
        self.skipping = None;
        self.skip_from = Some(at);
        self.frames.push(Frame {
            name: name.to_string(),
            call_type,
            ret: self.pc,
            saved_args: saved,
            locals: HashMap::new(),
            m98_left: -1,
            loops: Vec::new(),
        });
        st.call_level = self.frames.len();
        self.pc = to;
        if search {
            self.skipping = Some(name.to_string());
            self.skipping_to_sub = Some(name.to_string());
        }
        Ok(())
    }

    /// M98 P L: a Fanuc-style call, repeated L times (L0: not called).
    pub fn call_m98(
        &mut self,
        p: u32,
        l: Option<u32>,
        at: Pos,
        st: &mut InterpState,
        finder: &dyn SubFinder,
    ) -> Result<(), String> {
        self.call_numbered(p, l, CallType::M98, &[], at, st, finder)
    }

    /// M98 or G65 P L: a call of program number `p`, repeated L times (L0: not called); the
    /// line at `at` runs again for each repeat. `args` are G65's #1–#33 (NaN: not given).
    #[allow(clippy::too_many_arguments)]
    pub fn call_numbered(
        &mut self,
        p: u32,
        l: Option<u32>,
        call_type: CallType,
        args: &[f64],
        at: Pos,
        st: &mut InterpState,
        finder: &dyn SubFinder,
    ) -> Result<(), String> {
        let name = p.to_string();
        let mut again = false;
        if let Some(l) = l {
            let left = match self.frames.last_mut() {
                Some(f) => &mut f.m98_left,
                None => &mut self.m98_main_left,
            };
            if *left == -1 {
                *left = i64::from(l);
            }
            *left -= 1;
            if *left > 0 {
                again = true;
            } else {
                *left = -1;
            }
            if l == 0 {
                return Ok(());
            }
        }
        self.call(&name, call_type, args, at, st, finder)?;
        if again {
            if let Some(f) = self.frames.last_mut() {
                f.ret = at;
            }
        }
        Ok(())
    }

    /// M99: returns from a Fanuc-style subprogram.
    pub fn return_m99(&mut self, st: &mut InterpState) -> Result<(), String> {
        match self.frames.last() {
            None => Err("M99 outside a subprogram (novanc does not loop the main program)".into()),
            Some(f) if f.call_type == CallType::Oword => Err(format!(
                "{} sub ends with '{} endsub', not M99",
                short(&f.name),
                short(&f.name)
            )),
            Some(_) => {
                self.ret(st);
                Ok(())
            }
        }
    }

    fn ret(&mut self, st: &mut InterpState) {
        let Some(f) = self.frames.pop() else {
            return;
        };
        let locals = match f.call_type {
            CallType::Oword => MAX_ARGS,
            CallType::G65 | CallType::G66 => LOCALS,
            CallType::M98 => 0,
        };
        for (i, v) in f.saved_args.iter().enumerate().take(locals) {
            st.params[i + 1] = *v;
        }
        self.pc = f.ret;
        self.jumped = true;
        st.call_level = self.frames.len();
        // M73: the state saved in this subroutine comes back on its return.
        let level = self.frames.len() + 1;
        if let Some(Some(s)) = st.saved.get(level).cloned() {
            if s.auto_restore {
                st.modal = s.modal;
                st.select_system(s.modal.cs);
            }
        }
        if let Some(slot) = st.saved.get_mut(level) {
            *slot = None;
        }
    }

    /// Where subroutine `name` is: where it was met (go there), else the start of the file of
    /// its name, or the line after the call in this file (skip forward from there). Refused
    /// at once when no such label lies ahead, so that a call to a missing subroutine is an
    /// error of its own line.
    fn locate(
        &mut self,
        name: &str,
        call_type: CallType,
        finder: &dyn SubFinder,
    ) -> Result<(Pos, bool), String> {
        if let Some(l) = self.labels.get(name) {
            return Ok((l.pos, false));
        }
        let file = format!("{name}.ngc");
        let unit = match self.units.iter().position(|u| u.name == file) {
            Some(i) => Some(i),
            None => match finder.find(name)? {
                Some((f, text)) => {
                    self.units.push(Unit::new(f, text));
                    Some(self.units.len() - 1)
                }
                None => None,
            },
        };
        let from = match unit {
            Some(u) => Pos::start(u),
            None => self.pc,
        };
        if !self.label_ahead(name, from) {
            return Err(match call_type {
                CallType::M98 => format!(
                    "M98 P{name}: subprogram O{name} is not in the program (searched forward from the call, as LinuxCNC does)"
                ),
                CallType::G65 | CallType::G66 => format!(
                    "{} P{name}: macro O{name} is not in the program (searched forward from the call) nor a file {file} in the subroutine path",
                    if call_type == CallType::G65 { "G65" } else { "G66" }
                ),
                CallType::Oword => format!(
                    "subroutine {} not found (not in this program, and no file {file} in the subroutine path)",
                    short(name)
                ),
            });
        }
        Ok((from, true))
    }

    /// Whether an O-line labelled `name` (global) lies at or after `from` in its unit.
    fn label_ahead(&self, name: &str, from: Pos) -> bool {
        let Some(unit) = self.units.get(from.unit) else {
            return false;
        };
        let mut at = from.byte;
        while let Some((raw, next)) = unit.line_at(at) {
            if o_label(raw).is_some_and(|l| label_is(l, name)) {
                return true;
            }
            at = next;
        }
        false
    }

    /// The open Fanuc loops of the program running now.
    fn loops(&mut self) -> &mut Vec<(u8, Pos)> {
        match self.frames.last_mut() {
            Some(f) => &mut f.loops,
            None => &mut self.main_loops,
        }
    }

    /// Where the program running now starts: its O line (a called one's), or its unit's
    /// first line.
    fn program_start(&self) -> Pos {
        self.frames
            .last()
            .and_then(|f| self.labels.get(&f.name))
            .map(|l| l.pos)
            .filter(|p| p.unit == self.pc.unit)
            .unwrap_or(Pos::start(self.pc.unit))
    }

    /// The first line at or after `from` in its unit that `want` picks, before `stop` (a
    /// byte; with `usize::MAX`, before another program's O line too); the line's place.
    fn scan(&self, from: Pos, stop: usize, want: impl Fn(&str) -> bool) -> Option<Pos> {
        let unit = self.units.get(from.unit)?;
        let mut at = from;
        while at.byte < stop {
            let (raw, next) = unit.line_at(at.byte)?;
            if want(raw) {
                return Some(at);
            }
            if stop == usize::MAX && at != from && starts_program(raw) {
                return None;
            }
            at = Pos {
                unit: at.unit,
                line: at.line + 1,
                byte: next,
            };
        }
        None
    }

    /// Fanuc's `GOTO n` read at `at`: on to the line whose sequence number is `n` in the
    /// program running now, searched forward from the next line, then from the program's
    /// start. Loops the jump leaves are closed.
    pub fn goto(&mut self, n: i64, at: Pos) -> Result<(), String> {
        let start = self.program_start();
        let key = (at.unit, at.byte, n);
        let to = match self.seq_cache.get(&key) {
            Some(&p) => p,
            None => {
                let is_n = |raw: &str| seq_number(raw) == Some(n);
                let found = self
                    .scan(self.pc, usize::MAX, is_n)
                    .or_else(|| self.scan(start, self.pc.byte, is_n))
                    .ok_or_else(|| {
                        format!("GOTO {n}: no block N{n} in this program (searched forward, then from its start)")
                    })?;
                self.seq_cache.insert(key, found);
                found
            }
        };
        // The loops whose lines the jump leaves are over.
        while let Some(&(_, w)) = self.loops().last() {
            let end = self.loop_end(w).map_or(usize::MAX, |e| e.byte);
            if w.byte < to.byte && to.byte < end {
                break;
            }
            self.loops().pop();
        }
        if to.byte <= at.byte {
            self.jumped = true;
        }
        self.pc = to;
        Ok(())
    }

    /// The line after the ENDm that closes the loop opened at `w` (None: there is none).
    fn loop_end(&mut self, w: Pos) -> Option<Pos> {
        if let Some(&p) = self.end_cache.get(&(w.unit, w.byte)) {
            return Some(p);
        }
        let unit = self.units.get(w.unit)?;
        let (raw, next) = unit.line_at(w.byte)?;
        let m = loop_start_number(raw)?;
        let after = Pos {
            unit: w.unit,
            line: w.line + 1,
            byte: next,
        };
        let end = self.scan(after, usize::MAX, |raw| loop_end_number(raw) == Some(m))?;
        let (_, past) = unit.line_at(end.byte)?;
        let p = Pos {
            unit: w.unit,
            line: end.line + 1,
            byte: past,
        };
        self.end_cache.insert((w.unit, w.byte), p);
        Some(p)
    }

    /// Fanuc's `WHILE [test] DOm` (`while_test` None: a `DOm` alone) read at `at`: a true
    /// test opens the loop; a false one goes on after its ENDm.
    pub fn fanuc_do(&mut self, while_test: Option<bool>, m: u8, at: Pos) -> Result<(), String> {
        if while_test == Some(false) {
            let after = self
                .loop_end(at)
                .ok_or_else(|| format!("WHILE [...] DO{m}: no END{m} after it in this program"))?;
            self.pc = after;
            return Ok(());
        }
        let loops = self.loops();
        if let Some(&(_, p)) = loops.iter().find(|(k, _)| *k == m) {
            return Err(format!(
                "DO{m} inside the loop DO{m} of line {}: nested loops need different numbers",
                p.line + 1
            ));
        }
        if loops.len() >= MAX_LOOPS {
            return Err(format!(
                "DO{m}: loops nested more than {MAX_LOOPS} deep (DO1 to DO3)"
            ));
        }
        loops.push((m, at));
        Ok(())
    }

    /// Fanuc's `ENDm`: back to the WHILE (or DO) of loop `m`, which must be the innermost
    /// one open.
    pub fn fanuc_end(&mut self, m: u8) -> Result<(), String> {
        match self.loops().last().copied() {
            None => Err(format!("END{m} without a DO{m} before it")),
            Some((k, p)) if k != m => Err(format!(
                "END{m} where the loop DO{k} of line {} is still open: loops may nest, not cross",
                p.line + 1
            )),
            Some((_, p)) => {
                self.loops().pop();
                self.pc = p;
                self.jumped = true;
                Ok(())
            }
        }
    }

    /// The error for reaching the end of a unit: while skipping to a label, or in a
    /// subroutine without its end.
    pub fn end_error(&self) -> String {
        if let Some(s) = &self.skipping_to_sub {
            match self.frames.last().map(|f| f.call_type) {
                Some(CallType::M98) => return format!("M98 P{s}: subprogram O{s} is not in the program (searched forward from the call, as LinuxCNC does)"),
                Some(CallType::G65) => return format!("G65 P{s}: macro O{s} is not in the program"),
                Some(CallType::G66) => return format!("G66 P{s}: macro O{s} is not in the program"),
                _ => {}
            }
            let file = s.rsplit('#').next().unwrap_or(s);
            return format!("subroutine {} not found (not in this program, and no file {file}.ngc in the subroutine path)", short(s));
        }
        if let Some(d) = &self.defining_sub {
            return format!("subroutine {} has no '{} endsub'", short(d), short(d));
        }
        if let Some(s) = &self.skipping {
            return format!(
                "the end of the program was reached looking for o{}",
                short(s)
            );
        }
        match self.frames.last() {
            Some(f) if f.call_type == CallType::M98 => {
                format!("subprogram O{} ends without M99", f.name)
            }
            Some(f) if matches!(f.call_type, CallType::G65 | CallType::G66) => {
                format!("macro O{} ends without M99", f.name)
            }
            Some(f) => format!(
                "subroutine o{} ends without endsub or return",
                short(&f.name)
            ),
            None => "the program ends without M02, M30 or a closing %".to_string(),
        }
    }
}

/// A label as the programmer wrote it, without its subroutine prefix: `o100`, `o<name>`.
fn short(name: &str) -> String {
    let l = name.rsplit('#').next().unwrap_or(name);
    if l.bytes().all(|b| b.is_ascii_digit()) {
        format!("o{l}")
    } else {
        format!("o<{l}>")
    }
}

/// An O-line's label as written: `o100`, `o<name>`.
/// Why label `name` cannot be defined again: where it was first.
fn twice(name: &str, first: Pos) -> String {
    format!(
        "{} is defined twice (first at line {})",
        short(name),
        first.line + 1
    )
}

fn label(o: &OLine) -> String {
    short(&o.label)
}

/// The letters and digits of a line after an optional `/` and its N word (spaces and
/// comments gone, lower case), and the N word's digits.
fn block_body(raw: &str) -> (Vec<u8>, Option<Vec<u8>>) {
    let b: Vec<u8> = significant(raw).map(|c| c.to_ascii_lowercase()).collect();
    let mut i = usize::from(b.first() == Some(&b'/'));
    let mut n = None;
    if b.get(i) == Some(&b'n') {
        let start = i + 1;
        i = start;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        n = Some(b[start..i].to_vec());
    }
    (b[i..].to_vec(), n)
}

/// The sequence number of a line (`N120 ...`: 120), if it has one that is whole.
pub fn seq_number(raw: &str) -> Option<i64> {
    let b = raw.trim_start().as_bytes();
    if !matches!(b.first(), Some(b'n' | b'N' | b'/')) {
        return None;
    }
    let (body, n) = block_body(raw);
    let digits = n?;
    if digits.is_empty() || digits.len() > 9 || body.first() == Some(&b'.') {
        return None;
    }
    std::str::from_utf8(&digits).ok()?.parse().ok()
}

/// Whether a line starts a program: `O` and a number, and nothing else.
fn starts_program(raw: &str) -> bool {
    let Some(rest) = o_label(raw) else {
        return false;
    };
    let mut it = significant(rest).peekable();
    it.peek().is_some_and(u8::is_ascii_digit) && it.all(|c| c.is_ascii_digit())
}

/// The program number of a line that starts a Fanuc program (`O1000`, nothing else but a
/// comment).
pub fn program_number(raw: &str) -> Option<u32> {
    if !starts_program(raw) {
        return None;
    }
    let digits: Vec<u8> = significant(o_label(raw)?).collect();
    std::str::from_utf8(&digits).ok()?.parse().ok()
}

/// The programs of a Fanuc DNC file holding several (`O1000 ... M30 O9010 ... M99 %`): each
/// one's number, the line of its `O` (from 1) and its lines (the first with the lines before
/// its `O`, such as the opening `%`). Empty when the file holds fewer than two.
pub fn dnc_programs(text: &str) -> Vec<(u32, usize, String)> {
    let mut out: Vec<(u32, usize, String)> = Vec::new();
    let mut head = String::new();
    for (i, raw) in text.split_inclusive('\n').enumerate() {
        match program_number(raw.trim_end_matches(['\r', '\n'])) {
            Some(n) => out.push((n, i + 1, std::mem::take(&mut head) + raw)),
            None => match out.last_mut() {
                Some(p) => p.2.push_str(raw),
                None => head.push_str(raw),
            },
        }
    }
    if out.len() < 2 {
        out.clear();
    }
    out
}

/// The loop number of a `WHILE [...] DOm` or `DOm` line./// The loop number of a `WHILE [...] DOm` or `DOm` line.
fn loop_start_number(raw: &str) -> Option<u8> {
    let (body, _) = block_body(raw);
    let tail = if body.starts_with(b"while") {
        let k = body.windows(2).rposition(|w| w == b"do")?;
        &body[k..]
    } else {
        &body[..]
    };
    let d = tail.strip_prefix(b"do")?;
    match d {
        [c @ b'1'..=b'3'] => Some(c - b'0'),
        _ => None,
    }
}

/// The loop number of an `ENDm` line.
fn loop_end_number(raw: &str) -> Option<u8> {
    let (body, _) = block_body(raw);
    match body.strip_prefix(b"end")? {
        [c @ b'1'..=b'3'] => Some(c - b'0'),
        _ => None,
    }
}
