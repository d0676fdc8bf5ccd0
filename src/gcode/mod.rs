//! ISO 6983 G-code programs (issue 10; docs/gcode.md): the subset shop programs use, read
//! with LinuxCNC 2.9's RS274NGC semantics where it covers the word and Fanuc 0i's otherwise,
//! expanded into machine instruction blocks.
//!
//! [`GcodeSource`] is, like the source-language `translator::Translator`, an iterator of
//! statements: one ISO line is one source statement, with the blocks generated from it
//! (canned cycles expanded, work offsets, tool length and cutter compensation applied), in
//! absolute machine pulses. After an error it yields nothing more.

pub mod canon;
pub mod comp;
pub mod cycles;
pub mod expr;
pub mod geom;
pub mod interp;
pub mod moves;
pub mod search;
pub mod words;

pub use search::translate_all;

use crate::block::{MachineState, Statement, TranslateError};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use canon::{Canon, Emitter};
use expr::Params;
use interp::{Exec, Flow, Mode, State};
use std::collections::HashMap;
use std::sync::Arc;

/// The deepest subprogram call (M98 inside subprograms), as Fanuc 0i allows.
pub const MAX_DEPTH: usize = 4;
/// The bounds of a program's work (docs/limits.md): the most repeats an L word asks for, the
/// most lines a program may execute (every line read, every repeat counted), the most blocks
/// one line and one program may make.
pub use crate::limits::{MAX_BLOCKS, MAX_LINES, MAX_PROGRAM_BLOCKS, MAX_REPEATS};

/// The work offsets G54 to G59 (index 0 to 5), machine mm of each system's zero.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorkOffsets(pub [[f64; 3]; 6]);

/// A work offset a program changed (G10 L2 or L20), for the caller to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OffsetChange {
    /// The system, 0 = G54 … 5 = G59.
    pub system: usize,
    /// Its new zero, machine mm.
    pub offset: [f64; 3],
}

/// The panel switches a program reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Switches {
    /// BLOCK DELETE: lines starting with `/` are skipped.
    pub block_delete: bool,
    /// OPTIONAL STOP: M01 stops.
    pub optional_stop: bool,
}

/// Whether a program is G-code: by its file name (`.ngc`, `.nc`, `.iso`) or by its first
/// line (`%`, or `O` and a number).
pub fn is_gcode(file_name: &str, text: &str) -> bool {
    let lower = file_name.to_ascii_lowercase();
    if [".ngc", ".nc", ".iso"].iter().any(|e| lower.ends_with(e)) {
        return true;
    }
    let Some(first) = text.lines().map(str::trim).find(|l| !l.is_empty()) else {
        return false;
    };
    if first == "%" {
        return true;
    }
    let mut c = first.chars();
    matches!(c.next(), Some('O' | 'o')) && c.next().is_some_and(|d| d.is_ascii_digit())
}

/// The text of the statement that restores the machine before a SEARCH point.
pub fn restore_text(line: u32) -> String {
    format!("(SEARCH: restore for line {line})")
}

/// A place in the program: the 0-based index of a line and the byte where it starts. The
/// reader walks the text with it instead of keeping an index of every line, so that memory
/// follows the program's content, not its count of lines (docs/limits.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct At {
    line: usize,
    byte: usize,
}

#[derive(Clone, Copy, Debug)]
struct Frame {
    o: u32,
    ret: At,
    start: At,
    left: u32,
}

/// A G-code program as an iterator of statements.
pub struct GcodeSource {
    source: Arc<str>,
    /// Each subprogram's O line: where its first line starts.
    subs: HashMap<u32, At>,
    called: std::collections::HashSet<u32>,
    /// The 0-based index of the next line to read.
    pc: usize,
    /// Where that line starts in `source`.
    pc_byte: usize,
    stack: Vec<Frame>,
    st: State,
    params: Params,
    magazine: Magazine,
    settings: MachineSettings,
    switches: Switches,
    emitter: Emitter,
    start: MachineState,
    resume_at: Option<u32>,
    /// SEARCH: a line before the SEARCH point moved Z from where the machine stood.
    z_moved: bool,
    held: Option<Statement>,
    changes: Vec<OffsetChange>,
    executed: u64,
    max_lines: u64,
    /// Blocks made so far, and the most the program may make.
    made: u64,
    max_blocks: u64,
    first_code: Option<usize>,
    scratch: expr::Scratch,
    line_buf: expr::Line,
    out_buf: Vec<(Canon, u32, u32)>,
    mdi: bool,
    done: bool,
}

impl GcodeSource {
    /// A program `source` for the machine in `state` (position, tool in the spindle,
    /// spindle), with the work offsets in force (G54 active) and the panel switches.
    pub fn new(
        source: Arc<str>,
        magazine: Magazine,
        settings: MachineSettings,
        state: MachineState,
        offsets: WorkOffsets,
        switches: Switches,
    ) -> GcodeSource {
        let params = Params::default();
        let mut subs = HashMap::new();
        let mut first_code = None;
        let bytes = source.as_bytes();
        let (mut a, mut i) = (0, 0);
        while a < bytes.len() {
            // Only the first byte that is not a space matters here; a blank line costs a
            // byte or two.
            let mut k = a;
            while k < bytes.len() && bytes[k] != b'\n' && bytes[k].is_ascii_whitespace() {
                k += 1;
            }
            let b = match bytes.get(k) {
                Some(b'\n') => k + 1,
                None => k,
                Some(_) => source[k..].find('\n').map_or(bytes.len(), |e| k + e + 1),
            };
            let (l, first) = (&source[a..b], bytes.get(k).copied());
            a = b;
            i += 1;
            let next = At { line: i, byte: b };
            let i = i - 1;
            let c = match first {
                None | Some(b'\n') => continue,
                Some(c) => c,
            };
            if c == b'(' || c == b';' {
                continue;
            }
            let t = l.trim();
            if first_code.is_none() && t != "%" {
                first_code = Some(i);
            }
            if c != b'O' && c != b'o' {
                continue;
            }
            if let Ok(l) = expr::read_line(t, i as u32 + 1, &params) {
                if let Some((o, _)) = l.o_number {
                    subs.entry(o).or_insert(next);
                }
            }
        }
        let pulse = |p: i64| settings.to_mm(p);
        let st = State {
            cur: [
                pulse(state.pos[0]),
                pulse(state.pos[1]),
                pulse(state.pos[2]),
            ],
            inch: false,
            incremental: false,
            plane: crate::block::Plane::XY,
            mode: Mode::None,
            feed: 0.0,
            speed: state.spindle.unsigned_abs() as f64,
            selected: state.tool,
            tool: state.tool,
            spindle: state.spindle.signum() as i8,
            tlo: 0.0,
            offsets,
            cs: 0,
            retract_r: true,
            cycle_il: None,
            cycle_kind: None,
            cycle_r: None,
            cycle_z: None,
            cycle_p: 0.0,
            cycle_q: None,
            comp: comp::Comp::default(),
        };
        GcodeSource {
            source,
            subs,
            called: Default::default(),
            pc: 0,
            pc_byte: 0,
            stack: Vec::new(),
            st,
            params,
            magazine,
            settings,
            switches,
            emitter: Emitter {
                pos: state.pos,
                seq: 0,
            },
            start: state,
            resume_at: None,
            z_moved: false,
            held: None,
            changes: Vec::new(),
            executed: 0,
            max_lines: MAX_LINES,
            made: 0,
            max_blocks: MAX_PROGRAM_BLOCKS,
            first_code,
            scratch: expr::Scratch::default(),
            line_buf: expr::Line::default(),
            out_buf: Vec::new(),
            mdi: false,
            done: false,
        }
    }

    /// The most lines this program may execute (default [`MAX_LINES`]).
    pub fn line_limit(mut self, lines: u64) -> GcodeSource {
        self.max_lines = lines;
        self
    }

    /// The most blocks this program may make, every repeat counted (default
    /// [`MAX_PROGRAM_BLOCKS`]).
    pub fn block_limit(mut self, blocks: u64) -> GcodeSource {
        self.max_blocks = blocks;
        self
    }

    /// MDI: the text need not end with M02, M30 or `%`.
    pub fn mdi(mut self) -> GcodeSource {
        self.mdi = true;
        self
    }

    /// SEARCH: the lines before source line `line` are executed for the state they leave
    /// (modes, offsets, tool, spindle, position) but yield no blocks; the first line at or
    /// after `line` is preceded by a restore statement that brings the machine from its actual
    /// state there: Z up to machine zero before any X Y move, the tool, the spindle, X Y, then
    /// Z.
    pub fn resume_at(mut self, line: u32) -> GcodeSource {
        self.resume_at = Some(line);
        self
    }

    /// The work offsets as the program has left them so far.
    pub fn offsets(&self) -> WorkOffsets {
        self.st.offsets
    }

    /// The G10 changes made since the last call, in order.
    pub fn take_offset_changes(&mut self) -> Vec<OffsetChange> {
        std::mem::take(&mut self.changes)
    }

    fn fail(&mut self, e: TranslateError) -> Option<Result<Statement, TranslateError>> {
        self.done = true;
        Some(Err(e))
    }

    fn end_error(&self, line: u32) -> TranslateError {
        TranslateError {
            line,
            col: 1,
            message: match self.stack.last() {
                Some(f) => format!("subprogram O{} ends without M99", f.o),
                None => "the program ends without M02, M30 or a closing %".to_string(),
            },
        }
    }

    /// Executes the next line; `None` when there is nothing more to do.
    fn step(&mut self) -> Option<Result<Statement, TranslateError>> {
        loop {
            if self.done {
                return None;
            }
            let n = self.pc as u32 + 1;
            let a = self.pc_byte;
            if a >= self.source.len() {
                if self.mdi && self.stack.is_empty() {
                    self.done = true;
                    let mut x = ctx(
                        n,
                        &self.settings,
                        &self.magazine,
                        self.switches,
                        std::mem::take(&mut self.out_buf),
                    );
                    self.st.comp.flush(&mut x);
                    let out = x.out;
                    return self.finish(n, String::new(), out, true);
                }
                let e = self.end_error(n);
                return self.fail(e);
            }
            let b = match self.source.as_bytes()[a] {
                b'\n' => a + 1,
                _ => self.source[a..]
                    .find('\n')
                    .map_or(self.source.len(), |i| a + i + 1),
            };
            self.pc += 1;
            self.pc_byte = b;
            let source = Arc::clone(&self.source);
            let raw = source[a..b].trim_end_matches(['\n', '\r']);
            if self.switches.block_delete && raw.trim_start().starts_with('/') {
                continue;
            }
            self.executed += 1;
            if self.executed > self.max_lines {
                let max = self.max_lines;
                // Without a call, every line read was a line of the file.
                let message = if self.called.is_empty() {
                    format!("the program has more than {max} lines (the most a program may have)")
                } else {
                    format!("the program executes more than {max} lines, counting each line of a subprogram each time it runs: refused")
                };
                return self.fail(TranslateError {
                    line: n,
                    col: 1,
                    message,
                });
            }
            if let Some(e) = crate::limits::line_too_long(raw, n, "") {
                return self.fail(e);
            }
            // A blank line (the spaces the line reader skips): nothing to read.
            if raw.bytes().all(|c| matches!(c, b' ' | b'\t' | b'\r')) {
                continue;
            }
            let mut line = std::mem::take(&mut self.line_buf);
            let r = expr::read_into(&mut self.scratch, &mut line, raw, n, &self.params);
            let r = r.and_then(|()| self.line_of(n, raw, &line));
            self.line_buf = line;
            match r {
                Ok(Some(s)) => return s,
                Ok(None) => continue,
                Err(e) => return self.fail(e),
            }
        }
    }

    /// Executes one read line: `None` to go on to the next, or what to yield.
    #[allow(clippy::type_complexity)]
    fn line_of(
        &mut self,
        n: u32,
        raw: &str,
        line: &expr::Line,
    ) -> Result<Option<Option<Result<Statement, TranslateError>>>, TranslateError> {
        if line.percent {
            if Some(self.pc - 1) < self.first_code || self.first_code.is_none() {
                return Ok(None);
            }
            if !self.stack.is_empty() {
                let e = self.end_error(n);
                return Err(e);
            }
            // The closing %: the program ends.
            self.done = true;
            let mut x = ctx(
                n,
                &self.settings,
                &self.magazine,
                self.switches,
                std::mem::take(&mut self.out_buf),
            );
            self.st.comp.flush(&mut x);
            let out = x.out;
            return Ok(Some(self.finish(n, raw.trim().to_string(), out, true)));
        }
        if let Some((o, col)) = line.o_number {
            if Some(self.pc - 1) == self.first_code && self.stack.is_empty() {
                // The main program's number.
                return Ok(None);
            }
            return Err(TranslateError {
                    line: n,
                    col,
                    message: match self.stack.last() {
                        Some(f) => format!("subprogram O{} runs into O{o} without M99", f.o),
                        None => format!("the main program runs into subprogram O{o}: end it with M30 (or M02) first"),
                    },
                });
        }
        if line.block_delete && self.switches.block_delete {
            return Ok(None);
        }
        for &(p, v) in &line.assigns {
            self.params.set(p, v);
        }
        if line.words.is_empty() {
            if line.assigns.is_empty() && !line.comment {
                return Ok(None);
            }
            return Ok(Some(self.finish(
                n,
                raw.trim().to_string(),
                Vec::new(),
                false,
            )));
        }
        let words = interp::sort_words(line, n)?;
        let mut x = ctx(
            n,
            &self.settings,
            &self.magazine,
            self.switches,
            std::mem::take(&mut self.out_buf),
        );
        let flow = interp::execute(&mut self.st, &mut x, &words)?;
        let mut out = std::mem::take(&mut x.out);
        self.changes.append(&mut x.changes);
        let mut end = false;
        match flow {
            Flow::Next => {}
            Flow::Call { o, l, col } => {
                // rs274 finds a subprogram by searching forward from the call, or one it
                // has called before.
                let found = self
                    .subs
                    .get(&o)
                    .copied()
                    .filter(|at| at.line > self.pc || self.called.contains(&o));
                let Some(at) = found else {
                    if self.subs.contains_key(&o) {
                        return Err(TranslateError {
                                line: n,
                                col,
                                message: format!("M98 P{o}: subprogram O{o} is above this call and was not called before (subprograms are found by searching forward from the call, as in LinuxCNC)"),
                            });
                    }
                    return Err(TranslateError {
                        line: n,
                        col,
                        message: format!("M98 P{o}: subprogram O{o} is not in the program"),
                    });
                };
                if self.stack.len() >= MAX_DEPTH {
                    return Err(TranslateError {
                        line: n,
                        col,
                        message: format!(
                            "M98 P{o}: subprogram calls nested more than {MAX_DEPTH} deep"
                        ),
                    });
                }
                self.called.insert(o);
                if l > 0 {
                    self.stack.push(Frame {
                        o,
                        ret: At {
                            line: self.pc,
                            byte: self.pc_byte,
                        },
                        start: at,
                        left: l,
                    });
                    self.goto(at);
                }
            }
            Flow::Return { col } => match self.stack.last_mut() {
                None => {
                    return Err(TranslateError {
                        line: n,
                        col,
                        message: "M99 outside a subprogram (novanc does not loop the main program)"
                            .into(),
                    })
                }
                Some(f) => {
                    f.left -= 1;
                    let to = if f.left > 0 {
                        f.start
                    } else {
                        let ret = f.ret;
                        self.stack.pop();
                        ret
                    };
                    self.goto(to);
                }
            },
            Flow::End => {
                let mut x = ctx(
                    n,
                    &self.settings,
                    &self.magazine,
                    self.switches,
                    std::mem::take(&mut self.out_buf),
                );
                self.st.comp.flush(&mut x);
                let mut tail = x.out;
                // The end function after the held compensation move.
                let endm = out.iter().rposition(|(c, _, _)| {
                    matches!(
                        c,
                        Canon::Aux {
                            m: Some(2 | 30),
                            ..
                        }
                    )
                });
                if endm.is_none() {
                    let m = if words.has_m(2).is_some() { 2 } else { 30 };
                    if m == 2 && self.st.spindle != 0 {
                        tail.push((
                            Canon::Aux {
                                s: None,
                                t: None,
                                m: Some(5),
                            },
                            n,
                            1,
                        ));
                    }
                    tail.push((
                        Canon::Aux {
                            s: None,
                            t: None,
                            m: Some(m),
                        },
                        n,
                        1,
                    ));
                }
                out.append(&mut tail);
                self.done = true;
                end = true;
            }
        }
        Ok(Some(self.finish(n, raw.trim().to_string(), out, end)))
    }

    /// Goes on reading at `at`.
    fn goto(&mut self, at: At) {
        self.pc = at.line;
        self.pc_byte = at.byte;
    }

    fn finish(
        &mut self,
        n: u32,
        text: String,
        mut out: Vec<(Canon, u32, u32)>,
        _end: bool,
    ) -> Option<Result<Statement, TranslateError>> {
        let mut blocks = Vec::with_capacity(out.len());
        let r = self.emitter.emit(&out, &self.settings, &mut blocks);
        out.clear();
        if out.capacity() > self.out_buf.capacity() {
            self.out_buf = out;
        }
        if let Err(e) = r {
            return self.fail(e);
        }
        self.made += blocks.len() as u64;
        if self.made > self.max_blocks {
            let max = self.max_blocks;
            return self.fail(TranslateError {
                line: n,
                col: 1,
                message: format!(
                    "the program makes more than {max} blocks (the most a program may make)"
                ),
            });
        }
        Some(Ok(Statement {
            line: n,
            text,
            blocks,
        }))
    }
}

fn ctx<'a>(
    n: u32,
    settings: &'a MachineSettings,
    magazine: &'a Magazine,
    sw: Switches,
    out: Vec<(Canon, u32, u32)>,
) -> Exec<'a> {
    Exec {
        n,
        out,
        changes: Vec::new(),
        settings,
        magazine,
        optional_stop: sw.optional_stop,
    }
}
