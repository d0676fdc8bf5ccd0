//! Reading one line of G-code (docs/gcode.md "Words", "Parameters and expressions",
//! "O-words"), as LinuxCNC 2.9's reader does: spaces and case are insignificant outside
//! comments, a value is a number, a parameter (`#5`, `#<name>`, `##2`), a bracket expression
//! or a unary function, and parameter settings on a line take effect after the whole line has
//! been read (every read on the line sees the old values).
//!
//! The reader evaluates as it reads, against an [`Env`] that resolves parameters: the
//! interpreter's state for the mill, a plain parameter table for the lathe. It knows nothing of
//! what the words mean; `words` sorts them and `exec` executes them.

use super::words::{self, Seen, Words};
use crate::block::TranslateError;
use crate::input_text::describe_char;

/// The highest numbered parameter (LinuxCNC's `RS274NGC_MAX_PARAMETERS` − 1).
/// 10^0 … 10^22, each exact in an f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

pub const MAX_PARAM: usize = 5602;

/// The deepest nesting of brackets, signs and parameter references in one value.
pub const MAX_NESTING: u32 = 64;

/// The most arguments an `O... call` passes (#1 to #30).
pub const MAX_ARGS: usize = 30;

/// Two values compare EQ when they differ by less than this (LinuxCNC's TOLERANCE_EQUAL).
pub const TOLERANCE_EQUAL: f64 = 1e-6;

/// Where a line's parameter references are resolved.
pub trait Env {
    /// The value of `#n` (`n` already checked to be 1 to [`MAX_PARAM`]), or why it cannot be
    /// read here.
    fn numbered(&self, n: usize) -> Result<f64, String>;
    /// The value of the named parameter `#<name>` (`name` in lower case, without spaces), or
    /// `None` if it is not defined.
    fn named(&self, name: &str) -> Result<Option<f64>, String>;
    /// Fanuc: whether local `#n` (1–33) is a G65 argument given without a decimal point on a
    /// length address (so in least increments: what ADP undoes).
    fn unpointed(&self, _n: usize) -> bool {
        false
    }
}

/// One word: its letter (upper case), value and 1-based column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The letter, upper case (`@` and `^` are the polar words).
    pub letter: char,
    /// The value.
    pub value: f64,
    /// Column of the letter.
    pub col: u32,
}

/// A parameter a line sets.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// `#n`.
    Numbered(usize),
    /// `#<name>` (lower case, without spaces).
    Named(String),
}

/// What kind of comment a comment is (LinuxCNC's active comments).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommentKind {
    /// An ordinary comment.
    Plain,
    /// `(MSG, text)`: a message to the operator.
    Msg,
    /// `(PRINT, text)`: printed, parameters substituted.
    Print,
    /// `(DEBUG, text)`: a message, parameters substituted.
    Debug,
    /// `(ABORT, text)`: stops the program with the text as its error.
    Abort,
    /// `(LOGOPEN, file)`, `(LOGAPPEND, file)`, `(LOGCLOSE)`, `(LOG, text)`.
    Log,
    /// `(PROBEOPEN file)`, `(PROBECLOSE)`.
    ProbeLog,
}

/// One comment of a line.
#[derive(Clone, Debug, PartialEq)]
pub struct Comment {
    /// Its kind.
    pub kind: CommentKind,
    /// The keyword as written, upper case (`LOGOPEN`), for the kinds that have one.
    pub keyword: String,
    /// The text after the keyword and its comma (the whole text for a plain comment), as
    /// written (case kept).
    pub text: String,
    /// Column of its `(` or `;`.
    pub col: u32,
}

/// The keyword of an O-word line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OKind {
    /// `O... sub`.
    Sub,
    /// `O... endsub [value]`.
    Endsub,
    /// `O... call [args]`.
    Call,
    /// `O... return [value]`.
    Return,
    /// `O... do`.
    Do,
    /// `O... while [cond]`.
    While,
    /// `O... endwhile`.
    Endwhile,
    /// `O... repeat [count]`.
    Repeat,
    /// `O... endrepeat`.
    Endrepeat,
    /// `O... if [cond]`.
    If,
    /// `O... elseif [cond]`.
    Elseif,
    /// `O... else`.
    Else,
    /// `O... endif`.
    Endif,
    /// `O... break`.
    Break,
    /// `O... continue`.
    Continue,
    /// A bare `O123`: a program number, or a subprogram's start (M98/M99).
    Bare,
}

impl OKind {
    /// The keyword as written.
    pub fn name(self) -> &'static str {
        match self {
            OKind::Sub => "sub",
            OKind::Endsub => "endsub",
            OKind::Call => "call",
            OKind::Return => "return",
            OKind::Do => "do",
            OKind::While => "while",
            OKind::Endwhile => "endwhile",
            OKind::Repeat => "repeat",
            OKind::Endrepeat => "endrepeat",
            OKind::If => "if",
            OKind::Elseif => "elseif",
            OKind::Else => "else",
            OKind::Endif => "endif",
            OKind::Break => "break",
            OKind::Continue => "continue",
            OKind::Bare => "",
        }
    }

    /// Whether the line carries an expression that is evaluated only when the line is not
    /// skipped (LinuxCNC evaluates no condition of a line it skips).
    fn has_condition(self) -> bool {
        matches!(
            self,
            OKind::While | OKind::Repeat | OKind::If | OKind::Elseif
        )
    }
}

/// The keywords in the order they are tried (a longer one before its prefix).
const O_KEYWORDS: [OKind; 15] = [
    OKind::Sub,
    OKind::Endsub,
    OKind::Call,
    OKind::Do,
    OKind::While,
    OKind::Repeat,
    OKind::If,
    OKind::Elseif,
    OKind::Else,
    OKind::Endif,
    OKind::Break,
    OKind::Continue,
    OKind::Endwhile,
    OKind::Endrepeat,
    OKind::Return,
];

/// An O-word line: `O<label> keyword ...`.
#[derive(Clone, Debug, PartialEq)]
pub struct OLine {
    /// The label as written, lower case: the digits of `O100` (`"100"`), or the name of
    /// `O<name>`.
    pub label: String,
    /// The keyword.
    pub kind: OKind,
    /// The condition or count (while, if, elseif, repeat) or the return value (endsub,
    /// return), if read.
    pub value: Option<f64>,
    /// The arguments of a call.
    pub args: Vec<f64>,
    /// Column of the `O`.
    pub col: u32,
}

/// A line read into its parts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Line {
    /// The line starts with `/`.
    pub block_delete: bool,
    /// The N word's value, if any.
    pub n: Option<f64>,
    /// Words in the order written (N and O excluded).
    pub words: Vec<Word>,
    /// Parameter settings, applied after the line is read, in order.
    pub assigns: Vec<(Target, f64, u32)>,
    /// The line is a lone `%`.
    pub percent: bool,
    /// The O-word, if the line is an O-word line.
    pub o: Option<OLine>,
    /// The comments, in order.
    pub comments: Vec<Comment>,
    /// A Fanuc Custom Macro B flow statement (GOTO, a true IF's GOTO, WHILE, DO, END).
    pub fanuc: Option<Macro>,
    /// Fanuc dialect: the letters ([`letter_bit`]) whose value is a number written plainly,
    /// not an expression or a variable.
    pub plain: u32,
    /// Fanuc dialect: the letters whose plain number has a decimal point, or is read as if it
    /// had one (calculator-type input).
    pub pointed: u32,
    /// Fanuc dialect: the letters whose plain number was written with a decimal point, as
    /// written whatever the input type (a lathe's words that Fanuc takes in increments only).
    pub dotted: u32,
    /// The words are also sorted, in `sorted_words` ([`ReadOpts::sort`]).
    pub sorted: bool,
    /// The words sorted in the mill's dialect as they were read, when `sorted`.
    pub sorted_words: Words,
}

/// A Fanuc Custom Macro B flow statement (docs/gcode.md "Fanuc dialect"). An `IF [..] GOTO n`
/// whose condition is false is no statement; an `IF [..] THEN` whose condition is true leaves
/// its assignment in the line's assignments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Macro {
    /// `GOTO n` (or a true `IF [..] GOTO n`): to the line with sequence number `n`.
    Goto {
        /// The sequence number.
        n: i64,
        /// Column of GOTO (or IF).
        col: u32,
    },
    /// `WHILE [cond] DOm`.
    While {
        /// The condition's value.
        test: bool,
        /// The loop number, 1 to 3.
        m: u8,
        /// Column of WHILE.
        col: u32,
    },
    /// `DOm` without WHILE: a loop without end.
    Do {
        /// The loop number, 1 to 3.
        m: u8,
        /// Column of DO.
        col: u32,
    },
    /// `ENDm`.
    End {
        /// The loop number, 1 to 3.
        m: u8,
        /// Column of END.
        col: u32,
    },
}

/// How a line is read: LinuxCNC's language (the default), or Fanuc's Custom Macro B
/// (docs/gcode.md "Fanuc dialect").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReadOpts {
    /// Fanuc: GOTO, IF, WHILE, DO, END, `#0` null, BIN and BCD, and numbers without a decimal
    /// point on the length addresses in least increments.
    pub fanuc: bool,
    /// The least increment in program units (0.001 mm under G21, 0.0001 inch under G20).
    pub increment: f64,
    /// Fanuc: calculator-type decimal point input (parameter 3401#0 DPI = 1): a number
    /// without a point is in mm, inches, degrees or seconds as written, not in increments.
    pub calculator: bool,
    /// The usual line (words of a letter and a number, nothing else) read in one pass over
    /// its bytes, each word sorted in the mill's dialect ([`words::MILL`]) as it is read, into
    /// [`Line::sorted_words`]: no list of words sorted afterwards. Any other line, one with an
    /// A word (the dialects with an A axis accept it) and one whose words are refused are read
    /// and sorted as before, so that the same error is given at the same place.
    pub sort: bool,
}

/// The addresses whose value, written without a decimal point, is in least increments in the
/// Fanuc dialect: the axes, the arc centre, R and Q (docs/gcode.md "Fanuc dialect").
pub const FANUC_INCREMENT_LETTERS: &[u8] = b"XYZABCUVWIJKRQ";

/// A value that is Fanuc's null (`#0`, a vacant variable): NaN inside the reader.
pub fn is_null(v: f64) -> bool {
    v.is_nan()
}

/// Null in arithmetic is 0 (Fanuc).
fn nz(v: f64) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        v
    }
}

impl Line {
    fn clear(&mut self) {
        self.block_delete = false;
        self.n = None;
        self.words.clear();
        self.assigns.clear();
        self.percent = false;
        self.o = None;
        self.comments.clear();
        self.fanuc = None;
        self.plain = 0;
        self.pointed = 0;
        self.dotted = 0;
        self.sorted = false;
    }
}

/// The digits of a number, with at most one decimal point: what `Reader::number` and
/// [`read_plain`] read.
struct Digits {
    /// The first 19 digits as an integer.
    mant: u64,
    /// How many digits.
    digits: u32,
    /// How many of them after the point.
    decimals: i32,
    /// How many bytes (digits and point).
    len: usize,
    /// A decimal point was read.
    point: bool,
}

impl Digits {
    #[inline]
    fn read(rest: &[u8]) -> Digits {
        // Digits into an integer mantissa: exact, and correctly rounded by one division
        // while it stays below 2^53 with at most 22 decimals (else the standard parser).
        let (mut mant, mut digits, mut decimals) = (0u64, 0u32, 0i32);
        let mut k = 0;
        let mut point = false;
        // The digits before the point, then those after it.
        for part in 0..2 {
            while let Some(&c) = rest.get(k) {
                let d = c.wrapping_sub(b'0');
                if d > 9 {
                    break;
                }
                if digits < 19 {
                    mant = mant * 10 + u64::from(d);
                }
                digits += 1;
                decimals += part;
                k += 1;
            }
            if part == 1 || rest.get(k) != Some(&b'.') {
                point = part == 1;
                break;
            }
            k += 1;
        }
        Digits {
            mant,
            digits,
            decimals,
            len: k,
            point,
        }
    }

    /// The value, when the integer holds every digit (at most 19) with at most 22 decimals;
    /// `None` for the standard parser (or, without digits, for an error).
    #[inline]
    fn value(&self) -> Option<f64> {
        // Up to 15 digits the division is correctly rounded. CAM output's 17 digits: the
        // mantissa is exact in u64; one rounding to f64 and one division leave at most an
        // ulp (1e-16 of the value), far below any machine's resolution, and skip the general
        // parser.
        (self.digits > 0 && self.digits <= 19 && self.decimals <= 22)
            .then(|| self.mant as f64 / POW10[self.decimals as usize])
    }
}

/// Reusable buffers for reading lines without allocating per line.
#[derive(Debug, Default)]
pub struct Scratch {
    bytes: Vec<u8>,
    cols: Vec<u32>,
    /// How many of `bytes` and `cols` are the line's: the buffers only grow, so a line is
    /// written over the last without clearing them first.
    len: usize,
}

/// The reader over one normalised line.
struct Reader<'a> {
    /// The line's characters (ASCII, lower case outside comments) and their columns, spaces
    /// outside comments removed.
    b: &'a [u8],
    cols: &'a [u32],
    i: usize,
    line: u32,
    env: &'a dyn Env,
    end_col: u32,
    /// Nesting of values being read (brackets, signs, parameters), bounded.
    depth: u32,
    /// Fanuc's Custom Macro B.
    fanuc: bool,
    /// The last number read had a decimal point.
    point: bool,
    /// The least increment in program units (Fanuc's numbers without a point).
    increment: f64,
}

impl Reader<'_> {
    fn err(&self, col: u32, message: impl Into<String>) -> TranslateError {
        TranslateError {
            line: self.line,
            col,
            message: message.into(),
        }
    }

    fn col(&self) -> u32 {
        self.cols.get(self.i).copied().unwrap_or(self.end_col)
    }

    fn peek(&self) -> Option<char> {
        self.b.get(self.i).map(|&x| x as char)
    }

    fn at(&self, k: usize) -> Option<u8> {
        self.b.get(self.i + k).copied()
    }

    fn eat(&mut self, ch: char) -> bool {
        if self.peek() == Some(ch) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    /// Whether the next characters spell `name` (lower case ASCII); consumes them if so.
    fn eat_name(&mut self, name: &str) -> bool {
        let n = name.len();
        match self.b.get(self.i..self.i + n) {
            Some(next) if next == name.as_bytes() => {
                self.i += n;
                true
            }
            _ => false,
        }
    }

    fn number(&mut self) -> Result<f64, TranslateError> {
        let start = self.i;
        let d = Digits::read(self.b.get(start..).unwrap_or(&[]));
        self.point = d.point;
        self.i = start + d.len;
        let col = self.cols.get(start).copied().unwrap_or(self.end_col);
        if d.digits == 0 {
            self.i = start;
            let what = self
                .peek()
                .map_or("the end of the line".to_string(), describe_char);
            return Err(self.err(col, format!("a number was expected, not {what}")));
        }
        if let Some(v) = d.value() {
            return Ok(v);
        }
        // Only ASCII digits and one point were read: the standard parser rounds them exactly.
        let text = std::str::from_utf8(&self.b[start..self.i]).unwrap_or("0");
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(
                col,
                format!(
                    "{} is too large for a number",
                    crate::input_text::quote_plain(text)
                ),
            )),
        }
    }

    /// A real value: number, parameter, bracket expression or unary function, with sign.
    fn value(&mut self) -> Result<f64, TranslateError> {
        self.depth += 1;
        let r = if self.depth > MAX_NESTING {
            Err(self.err(
                self.col(),
                format!("brackets, signs or # nested more than {MAX_NESTING} deep"),
            ))
        } else {
            self.value_inner()
        };
        self.depth -= 1;
        r
    }

    fn value_inner(&mut self) -> Result<f64, TranslateError> {
        if self.eat('-') {
            return Ok(-nz(self.value()?));
        }
        if self.eat('+') {
            return self.value();
        }
        match self.peek() {
            Some('[') => self.bracket(),
            Some('#') => self.param(),
            Some(c) if c.is_ascii_alphabetic() => self.function(),
            _ => self.number(),
        }
    }

    /// An integer value (a parameter number, an O number): within 0.0001 of a whole number,
    /// as LinuxCNC's `read_integer_value` takes it.
    fn integer(&mut self, what: &str) -> Result<(i64, u32), TranslateError> {
        let col = self.col();
        let v = self.value()?;
        let n = v.round();
        if (v - n).abs() > 1e-4 || n.abs() > 1e15 {
            return Err(self.err(
                col,
                format!(
                    "{what} {} is not a whole number",
                    crate::input_text::short_number(v)
                ),
            ));
        }
        Ok((n as i64, col))
    }

    /// `<name>` after `#` or `O`: the name, lower case, spaces already gone.
    fn name(&mut self) -> Result<String, TranslateError> {
        let col = self.col();
        self.i += 1; // '<'
        let start = self.i;
        while let Some(c) = self.at(0) {
            if c == b'>' {
                let name = String::from_utf8_lossy(&self.b[start..self.i]).into_owned();
                self.i += 1;
                if name.is_empty() {
                    return Err(self.err(col, "an empty name <>"));
                }
                return Ok(name);
            }
            self.i += 1;
        }
        Err(self.err(col, "a name '<' is not closed by '>'"))
    }

    /// After `#`: a numbered parameter's number, or a named parameter's name.
    fn param_ref(&mut self) -> Result<(Target, u32), TranslateError> {
        let col = self.col();
        match self.param_or_number()? {
            Ok(t) => Ok((t, col)),
            Err(n) => Err(self.err(col, format!("parameter number {n} is not 1 to {MAX_PARAM}"))),
        }
    }

    /// The parameter a `#` names, or the number after it when that names none.
    fn param_or_number(&mut self) -> Result<Result<Target, i64>, TranslateError> {
        self.i += 1; // '#'
        if self.peek() == Some('<') {
            return Ok(Ok(Target::Named(self.name()?)));
        }
        let (n, _) = self.integer("parameter number")?;
        let fanuc_only =
            n == 0 || (n > MAX_PARAM as i64 && n <= super::sysvars::MAX_FANUC_VAR as i64);
        // Fanuc's #0 and its tool offsets #10001–#13999 (docs/gcode.md "Fanuc dialect").
        if (self.fanuc && fanuc_only) || (1..=MAX_PARAM as i64).contains(&n) {
            return Ok(Ok(Target::Numbered(n as usize)));
        }
        Ok(Err(n))
    }

    fn param(&mut self) -> Result<f64, TranslateError> {
        let (t, col) = self.param_ref()?;
        self.lookup(&t, col)
    }

    fn lookup(&self, t: &Target, col: u32) -> Result<f64, TranslateError> {
        match t {
            Target::Numbered(0) => Ok(f64::NAN),
            Target::Numbered(n) => self.env.numbered(*n).map_err(|m| self.err(col, m)),
            Target::Named(name) => match self.env.named(name) {
                Ok(Some(v)) => Ok(v),
                Ok(None) => Err(self.err(col, format!("named parameter #<{name}> is not defined"))),
                Err(m) => Err(self.err(col, m)),
            },
        }
    }

    fn bracket(&mut self) -> Result<f64, TranslateError> {
        let col = self.col();
        self.i += 1; // '['
        let v = self.expr(0)?;
        if !self.eat(']') {
            return Err(self.err(
                self.col(),
                format!("']' expected to close the '[' at column {col}"),
            ));
        }
        Ok(v)
    }

    fn function(&mut self) -> Result<f64, TranslateError> {
        let col = self.col();
        const NAMES: [&str; 14] = [
            "abs", "acos", "asin", "atan", "cos", "exists", "exp", "fix", "fup", "ln", "round",
            "sin", "sqrt", "tan",
        ];
        const FANUC_NAMES: [&str; 3] = ["adp", "bcd", "bin"];
        let fanuc_names: &[&str] = if self.fanuc { &FANUC_NAMES } else { &[] };
        let Some(name) = NAMES.iter().chain(fanuc_names).find(|n| self.eat_name(n)) else {
            let mut word = String::new();
            let mut k = 0;
            while let Some(c) = self.at(k).filter(|c| c.is_ascii_alphabetic()) {
                word.push(c.to_ascii_uppercase() as char);
                k += 1;
            }
            return Err(self.err(
                col,
                format!("unknown function or word '{word}' in an expression"),
            ));
        };
        let upper = name.to_ascii_uppercase();
        if self.peek() != Some('[') {
            return Err(self.err(
                self.col(),
                format!("{upper} needs its argument in brackets: {upper}[...]"),
            ));
        }
        if *name == "exists" {
            // EXISTS[#<name>]: 1 if the named parameter is defined; EXISTS[#n], as
            // LinuxCNC's: 1 if n names a parameter of the machine (EXISTS[#99999] is 0).
            self.i += 1;
            if self.peek() != Some('#') {
                return Err(self.err(self.col(), "EXISTS takes a parameter: EXISTS[#<name>]"));
            }
            let t = self.param_or_number()?;
            if !self.eat(']') {
                return Err(self.err(self.col(), "']' expected after EXISTS[#<name>"));
            }
            return Ok(match t {
                Ok(Target::Numbered(_)) => 1.0,
                Ok(Target::Named(n)) => match self.env.named(&n) {
                    Ok(Some(_)) => 1.0,
                    _ => 0.0,
                },
                Err(_) => 0.0,
            });
        }
        if *name == "adp" {
            // ADP[#n]: a G65 argument given without a decimal point, as if it had one.
            self.i += 1;
            let (t, pcol) = if self.peek() == Some('#') {
                self.param_ref()?
            } else {
                (Target::Numbered(0), self.col())
            };
            let n = match t {
                Target::Numbered(n @ 1..=33) => n,
                _ => return Err(self.err(pcol, "ADP takes a local variable: ADP[#1] to ADP[#33]")),
            };
            if !self.eat(']') {
                return Err(self.err(self.col(), "']' expected after ADP[#n"));
            }
            let v = self.lookup(&Target::Numbered(n), pcol)?;
            if is_null(v) || !self.env.unpointed(n) {
                return Ok(v);
            }
            return Ok((v / self.increment).round());
        }
        // Fanuc 30i's ATAN[y,x]: the two arguments in one bracket.
        let mut fanuc_atan2 = None;
        let a = if self.fanuc && *name == "atan" {
            let open = self.col();
            self.i += 1; // '['
            let y = self.expr(0)?;
            if self.eat(',') {
                fanuc_atan2 = Some(nz(self.expr(0)?));
            }
            if !self.eat(']') {
                return Err(self.err(
                    self.col(),
                    format!("']' expected to close the '[' at column {open}"),
                ));
            }
            y
        } else {
            self.bracket()?
        };
        // Null in arithmetic is 0 (Fanuc; nothing is null in LinuxCNC's language).
        let a = nz(a);
        let dom = |ok: bool, what: &str| -> Result<(), TranslateError> {
            if ok {
                Ok(())
            } else {
                Err(TranslateError {
                    line: self.line,
                    col,
                    message: format!("domain error: {upper}[{a}] {what}"),
                })
            }
        };
        let r = match *name {
            "abs" => a.abs(),
            "acos" => {
                dom((-1.0..=1.0).contains(&a), "needs -1 to 1")?;
                a.acos().to_degrees()
            }
            "asin" => {
                dom((-1.0..=1.0).contains(&a), "needs -1 to 1")?;
                a.asin().to_degrees()
            }
            "atan" => {
                let b = if let Some(b) = fanuc_atan2 {
                    b
                } else {
                    if !self.eat('/') || self.peek() != Some('[') {
                        let m = if self.fanuc {
                            "ATAN is written ATAN[y]/[x] or ATAN[y,x]"
                        } else {
                            "ATAN is written ATAN[y]/[x]"
                        };
                        return Err(self.err(self.col(), m));
                    }
                    nz(self.bracket()?)
                };
                let t = a.atan2(b).to_degrees();
                // Fanuc's ATAN answers 0 to 360 degrees (parameter 6004#0 = 0).
                if self.fanuc && t < 0.0 {
                    t + 360.0
                } else {
                    t
                }
            }
            "bin" | "bcd" => {
                dom(
                    a >= 0.0 && a.fract() == 0.0 && a < 1e15,
                    "needs a whole number not below 0",
                )?;
                bin_bcd(*name == "bin", a as u64).map_err(|m| self.err(col, m))? as f64
            }
            "cos" => a.to_radians().cos(),
            "sin" => a.to_radians().sin(),
            "tan" => {
                let t = a.to_radians().tan();
                dom(t.is_finite() && t.abs() < 1e15, "is infinite")?;
                t
            }
            "exp" => a.exp(),
            // Fanuc's FIX drops the fraction and FUP raises it away from zero (FIX[-1.2] is
            // -1, FUP[-1.2] is -2); LinuxCNC's are floor and ceiling.
            "fix" if self.fanuc => a.trunc(),
            "fup" if self.fanuc => a.signum() * a.abs().ceil(),
            "fix" => a.floor(),
            "fup" => a.ceil(),
            "ln" => {
                dom(a > 0.0, "needs a number greater than 0")?;
                a.ln()
            }
            "round" => a.round(),
            _ => {
                dom(a >= 0.0, "needs a number not below 0")?;
                a.sqrt()
            }
        };
        if !r.is_finite() {
            return Err(self.err(col, format!("{upper}[{a}] is not a finite number")));
        }
        Ok(r)
    }

    /// Binary operators by precedence level: 0 logical, 1 relational, 2 additive,
    /// 3 multiplicative, 4 power.
    fn op(&mut self, level: u8) -> Option<&'static str> {
        // Most values are followed by ']' or the next word: no operator starts with those.
        let first = self.at(0)?;
        if !matches!(
            first,
            b'+' | b'-' | b'*' | b'/' | b'a' | b'o' | b'x' | b'e' | b'n' | b'g' | b'l' | b'm'
        ) {
            return None;
        }
        let table: &[&'static str] = match level {
            0 => &["and", "or", "xor"],
            1 => &["eq", "ne", "gt", "ge", "lt", "le"],
            2 => &["+", "-"],
            3 => &["*", "/", "mod"],
            _ => &["**"],
        };
        table.iter().copied().find(|o| self.eat_name(o))
    }

    fn expr(&mut self, level: u8) -> Result<f64, TranslateError> {
        if level > 4 {
            return self.value();
        }
        let mut a = self.expr(level + 1)?;
        loop {
            // '*' must not take the first star of '**'.
            if level == 3 && self.at(0) == Some(b'*') && self.at(1) == Some(b'*') {
                return Ok(a);
            }
            let col = self.col();
            let Some(op) = self.op(level) else {
                return Ok(a);
            };
            let b = self.expr(level + 1)?;
            let t = |x: bool| if x { 1.0 } else { 0.0 };
            if a.is_nan() || b.is_nan() {
                // Fanuc's null: EQ and NE tell it from every number (`#0 EQ #0` is true,
                // `#0 EQ 0` false); everywhere else it is 0.
                match op {
                    "eq" => {
                        a = t(a.is_nan() && b.is_nan());
                        continue;
                    }
                    "ne" => {
                        a = t(a.is_nan() != b.is_nan());
                        continue;
                    }
                    _ => {}
                }
            }
            let (a0, b) = (nz(a), nz(b));
            a = a0;
            a = match op {
                "+" => a + b,
                "-" => a - b,
                "*" => a * b,
                "/" => {
                    if b == 0.0 {
                        return Err(self.err(col, "division by zero"));
                    }
                    a / b
                }
                "mod" => {
                    if b == 0.0 {
                        return Err(self.err(col, "division by zero (MOD 0)"));
                    }
                    a.rem_euclid(b)
                }
                "**" => {
                    if a < 0.0 && b.floor() != b {
                        return Err(self.err(
                            col,
                            format!("{a} ** {b}: a negative number to a power that is not whole"),
                        ));
                    }
                    a.powf(b)
                }
                "eq" => t((a - b).abs() < TOLERANCE_EQUAL),
                "ne" => t((a - b).abs() >= TOLERANCE_EQUAL),
                "gt" => t(a > b),
                "ge" => t((a - b).abs() < TOLERANCE_EQUAL || a >= b),
                "lt" => t(a < b),
                "le" => t((a - b).abs() < TOLERANCE_EQUAL || a <= b),
                "and" | "or" | "xor" if self.fanuc => bitwise(op, a, b)
                    .ok_or_else(|| {
                        self.err(
                            col,
                            format!(
                                "{a} {} {b}: in the Fanuc dialect AND, OR and XOR work bit by bit on whole numbers 0 or above",
                                op.to_uppercase()
                            ),
                        )
                    })?,
                "and" => t(a != 0.0 && b != 0.0),
                "or" => t(a != 0.0 || b != 0.0),
                _ => t((a != 0.0) != (b != 0.0)),
            };
            if !a.is_finite() {
                return Err(self.err(
                    col,
                    format!("the result of {} is not a finite number", op.to_uppercase()),
                ));
            }
        }
    }

    /// A bracketed expression where one is required (`while [..]`).
    fn required_bracket(&mut self, what: &str) -> Result<f64, TranslateError> {
        if self.peek() != Some('[') {
            return Err(self.err(self.col(), format!("'[' expected after '{what}'")));
        }
        self.bracket()
    }
}

/// Fanuc's BIN (BCD to binary) and BCD (binary to BCD) of a whole number.
fn bin_bcd(bin: bool, a: u64) -> Result<u64, String> {
    let (mut v, mut out, mut shift) = (a, 0u64, 0u32);
    while v > 0 {
        let d = if bin { v & 0xf } else { v % 10 };
        if bin && d > 9 {
            return Err(format!(
                "BIN[{a}]: {a} is not a BCD number (a nibble above 9)"
            ));
        }
        let place = if bin {
            10u64.checked_pow(shift)
        } else {
            1u64.checked_shl(4 * shift)
        };
        out = place
            .and_then(|p| p.checked_mul(d))
            .and_then(|x| out.checked_add(x))
            .ok_or_else(|| format!("BCD[{a}]: too large"))?;
        v = if bin { v >> 4 } else { v / 10 };
        shift += 1;
    }
    Ok(out)
}

/// Fanuc's AND, OR, XOR: bit by bit on whole numbers from 0 to 2^53 (a condition's 1 or 0
/// gives the logical answer); `None` for any other number.
fn bitwise(op: &str, a: f64, b: f64) -> Option<f64> {
    let whole = |v: f64| {
        (v.fract() == 0.0 && (0.0..=9_007_199_254_740_992.0).contains(&v)).then_some(v as u64)
    };
    let (a, b) = (whole(a)?, whole(b)?);
    Some(match op {
        "and" => a & b,
        "or" => a | b,
        _ => a ^ b,
    } as f64)
}

/// What the plain-line pass of [`normalise`] makes of each byte: [`BLANK`] (a space, a tab, a
/// CR: dropped), [`OTHER`] (a comment's `(` or `;`, a control character, a byte outside
/// ASCII: the line is read character by character), or the byte in lower case.
const PLAIN: [u8; 256] = {
    let mut t = [OTHER; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        if b == b' ' || b == b'\t' || b == b'\r' {
            t[c] = BLANK;
        } else if b.is_ascii_graphic() && b != b'(' && b != b';' {
            t[c] = b.to_ascii_lowercase();
        }
        c += 1;
    }
    t
};
const BLANK: u8 = 0;
const OTHER: u8 = 0xff;

/// Splits `raw` into the reader's buffer (lower case, spaces gone, outside comments) and the
/// line's comments.
fn normalise(
    scratch: &mut Scratch,
    out: &mut Line,
    raw: &str,
    line: u32,
) -> Result<u32, TranslateError> {
    let (bytes, cols) = (&mut scratch.bytes, &mut scratch.cols);
    scratch.len = 0;
    // The usual line: ASCII words, no comment. One pass over its bytes, each column its
    // byte's place, written by index (the buffers sized once); anything else (a comment, a
    // character outside ASCII) starts again below, character by character.
    let rb = raw.as_bytes();
    if bytes.len() < rb.len() {
        bytes.resize(rb.len(), 0);
        cols.resize(rb.len(), 0);
    }
    let mut k = 0;
    let mut plain = true;
    for (i, &c) in rb.iter().enumerate() {
        match PLAIN[c as usize] {
            BLANK => continue,
            OTHER => {
                plain = false;
                break;
            }
            lower => {
                bytes[k] = lower;
                cols[k] = i as u32 + 1;
                k += 1;
            }
        }
    }
    if plain {
        scratch.len = k;
        return Ok(raw.len() as u32 + 1);
    }
    bytes.clear();
    cols.clear();
    let mut col = 0u32;
    let mut comment: Option<(u32, String)> = None;
    for ch in raw.chars() {
        col += 1;
        if let Some((_, text)) = comment.as_mut() {
            if ch == ')' {
                if let Some((at, text)) = comment.take() {
                    out.comments.push(classify(text, at));
                }
            } else if ch == '(' {
                return Err(TranslateError {
                    line,
                    col,
                    message: "a comment may not hold '(' (comments do not nest)".into(),
                });
            } else {
                text.push(ch);
            }
            continue;
        }
        match ch {
            '(' => comment = Some((col, String::new())),
            ';' => {
                let rest: String = raw.chars().skip(col as usize).collect();
                out.comments.push(Comment {
                    kind: CommentKind::Plain,
                    keyword: String::new(),
                    text: rest,
                    col,
                });
                scratch.len = bytes.len();
                return Ok(col + 1);
            }
            ' ' | '\t' | '\r' | '\n' => {}
            c if c.is_ascii() && !c.is_ascii_control() => {
                bytes.push(c.to_ascii_lowercase() as u8);
                cols.push(col);
            }
            c => {
                return Err(TranslateError {
                    line,
                    col,
                    message: format!(
                        "{} is not part of the language (outside a comment)",
                        describe_char(c)
                    ),
                })
            }
        }
    }
    if let Some((at, _)) = comment {
        return Err(TranslateError {
            line,
            col: at,
            message: "comment '(' not closed on its line".into(),
        });
    }
    scratch.len = bytes.len();
    Ok(col + 1)
}

/// A comment's kind by its keyword: `(MSG, ...)`, `(print, ...)`, ... (case-insensitive,
/// spaces before the keyword allowed).
fn classify(text: String, col: u32) -> Comment {
    let t = text.trim_start();
    let word: String = t
        .chars()
        .take_while(|c| c.is_ascii_alphabetic())
        .collect::<String>()
        .to_ascii_uppercase();
    let after = t[word.len()..].trim_start();
    let with_comma = after.strip_prefix(',');
    let kind = match (word.as_str(), with_comma.is_some()) {
        ("MSG", true) => CommentKind::Msg,
        ("PRINT", true) => CommentKind::Print,
        ("DEBUG", true) => CommentKind::Debug,
        ("ABORT", true) => CommentKind::Abort,
        ("LOGOPEN" | "LOGAPPEND" | "LOG", true) | ("LOGCLOSE", _) => CommentKind::Log,
        ("PROBEOPEN", _) | ("PROBECLOSE", _) => CommentKind::ProbeLog,
        _ => CommentKind::Plain,
    };
    match kind {
        CommentKind::Plain => Comment {
            kind,
            keyword: String::new(),
            text,
            col,
        },
        _ => Comment {
            kind,
            text: with_comma.unwrap_or(after).to_string(),
            keyword: word,
            col,
        },
    }
}

/// While O-word flow skips lines: whether an O-line of a label and kind is read.
pub type Skipping<'a> = &'a dyn Fn(&str, OKind) -> bool;

/// Reads one line (without its newline) into `out` (cleared first), against `env`. While
/// `skipping`, only an O-word line's label and keyword are read; `skipping(label, kind)` says
/// whether that O-line's expressions are read too (its label is the one being skipped to).
pub fn read_into(
    scratch: &mut Scratch,
    out: &mut Line,
    raw: &str,
    line: u32,
    env: &dyn Env,
    skipping: Option<Skipping>,
) -> Result<(), TranslateError> {
    read_into_opts(scratch, out, raw, line, env, skipping, ReadOpts::default())
}

/// In the Fanuc dialect `;` is the end of block (EOB) that Fanuc prints at the end of each
/// block, not LinuxCNC's comment to the end of the line: a `;` may end a line, followed only by
/// blanks, more `;` and comments in parentheses. Anything else after it would be a second
/// block on the line, which novanc does not drop unread: it is refused at its place.
fn eob_ends_the_line(out: &Line, raw: &str, line: u32) -> Result<(), TranslateError> {
    for c in &out.comments {
        if raw.chars().nth((c.col as usize).saturating_sub(1)) != Some(';') {
            continue;
        }
        let mut depth = 0;
        for (i, ch) in c.text.chars().enumerate() {
            match ch {
                '(' => depth += 1,
                ')' if depth > 0 => depth -= 1,
                ';' | ' ' | '\t' | '\r' => {}
                _ if depth > 0 => {}
                _ => {
                    return Err(TranslateError {
                        line,
                        col: c.col + 1 + i as u32,
                        message: "a block after ';' on the same line: ';' ends a block in the \
                                  Fanuc dialect (EOB); put the next block on a line of its own"
                            .into(),
                    })
                }
            }
        }
    }
    Ok(())
}

/// [`read_into`] in a dialect (`opts`).
pub fn read_into_opts(
    scratch: &mut Scratch,
    out: &mut Line,
    raw: &str,
    line: u32,
    env: &dyn Env,
    skipping: Option<Skipping>,
    opts: ReadOpts,
) -> Result<(), TranslateError> {
    out.clear();
    if opts.sort && skipping.is_none() {
        // One copy of the pass for each dialect: LinuxCNC's pays nothing for Fanuc's numbers.
        let plain = if opts.fanuc {
            read_plain::<true>(out, raw, line, opts)
        } else {
            read_plain::<false>(out, raw, line, opts)
        };
        if plain {
            out.sorted = true;
            return Ok(());
        }
        out.clear();
    }
    let end_col = normalise(scratch, out, raw, line)?;
    if opts.fanuc && !out.comments.is_empty() {
        eob_ends_the_line(out, raw, line)?;
    }
    let n = scratch.len;
    let (bytes, cols) = (&scratch.bytes[..n], &scratch.cols[..n]);
    if bytes == b"%" || (opts.fanuc && percent_and_number(bytes)) {
        // (Fanuc: a tape's `%O1200` is the leader and the program's number on one line; the
        // number names the program, as a bare O line does, and is read over.)
        out.percent = true;
        return Ok(());
    }
    let mut r = Reader {
        b: bytes,
        cols,
        i: 0,
        line,
        env,
        end_col,
        depth: 0,
        fanuc: opts.fanuc,
        point: false,
        increment: opts.increment,
    };
    if r.eat('/') {
        out.block_delete = true;
    }
    if r.peek() == Some('n') {
        let col = r.col();
        r.i += 1;
        let v = r
            .number()
            .map_err(|_| r.err(col, "N needs a line number"))?;
        out.n = Some(v);
    }
    if r.peek() == Some('o') {
        return read_o(&mut r, out, skipping);
    }
    if r.fanuc && r.peek() == Some(':') && r.at(1).is_some_and(|c| c.is_ascii_digit()) {
        // ISO's address of the program number (Fanuc: `:0100` is `O0100`).
        let col = r.col();
        read_o(&mut r, out, skipping)?;
        if out.o.as_ref().is_some_and(|o| o.kind != OKind::Bare) {
            return Err(r.err(col, "':' is ISO's program number: a number alone"));
        }
        return Ok(());
    }
    if skipping.is_some() {
        // Nothing but O-words is read while skipping (LinuxCNC does not evaluate them).
        return Ok(());
    }
    while let Some(ch) = r.peek() {
        let col = r.col();
        if ch == '#' {
            let (t, _) = r.param_ref()?;
            if !r.eat('=') {
                let what = match &t {
                    Target::Numbered(n) => format!("#{n}"),
                    Target::Named(n) => format!("#<{n}>"),
                };
                return Err(r.err(
                    r.col(),
                    format!("'=' expected after {what} (a parameter alone is not a word)"),
                ));
            }
            if t == Target::Numbered(0) {
                return Err(r.err(col, "#0 is null: it cannot be set"));
            }
            // Fanuc's right-hand side is an expression (`#1=#2+1`); LinuxCNC's a value.
            let v = if r.fanuc { r.expr(0)? } else { r.value()? };
            out.assigns.push((t, v, col));
            continue;
        }
        if !(ch.is_ascii_alphabetic() || ch == '@' || ch == '^' || ch == '$') {
            return Err(r.err(
                col,
                format!("a word letter was expected, not {}", describe_char(ch)),
            ));
        }
        let letter = ch.to_ascii_uppercase();
        if r.fanuc && r.at(1).is_some_and(|c| c.is_ascii_alphabetic()) && fanuc_keyword(&r) {
            fanuc_statement(&mut r, out)?;
            return Ok(());
        }
        // A keyword is letters on letters; a word's letter is followed by its value.
        let keywords: &[&str] = if r.at(1).is_some_and(|c| c.is_ascii_alphabetic()) {
            &["goto", "if", "while", "then", "do", "end"]
        } else {
            &[]
        };
        for kw in keywords {
            let after = r.at(kw.len());
            if r.b[r.i..].starts_with(kw.as_bytes())
                && !after.is_some_and(|c| c.is_ascii_alphabetic())
                && !(*kw == "do" && after.is_none())
            {
                return Err(r.err(
                    col,
                    format!(
                        "{} is Fanuc Custom Macro B, not LinuxCNC's language: write loops and tests as O-words (o100 while [...], o100 if [...])",
                        kw.to_ascii_uppercase()
                    ),
                ));
            }
        }
        if letter == 'O' {
            return Err(r.err(col, "an O-word must start its line (after N)"));
        }
        if letter == 'N' {
            return Err(r.err(col, "N (the line number) must start its line"));
        }
        r.i += 1;
        // A number, or a minus and a number: read straight (what `value` does with them).
        let value = if r.fanuc {
            let increment = (!opts.calculator).then_some(opts.increment);
            let (v, plain) = fanuc_word_value(&mut r, letter, increment)?;
            if is_null(v) {
                // A word whose value is null is as if it were not written (Fanuc).
                continue;
            }
            if let Some(point) = plain {
                out.plain |= letter_bit(letter);
                if point {
                    out.pointed |= letter_bit(letter);
                }
                if r.point {
                    out.dotted |= letter_bit(letter);
                }
            }
            v
        } else {
            match (r.at(0), r.at(1)) {
                (Some(b'0'..=b'9' | b'.'), _) => r.number()?,
                (Some(b'-'), Some(b'0'..=b'9' | b'.')) => {
                    r.i += 1;
                    -r.number()?
                }
                _ => r.value()?,
            }
        };
        out.words.push(Word { letter, value, col });
    }
    Ok(())
}

/// The usual line read straight into its sorted words ([`ReadOpts::sort`]): an optional N, then
/// words of an upper- or lower-case letter followed at once by a number (`-`, digits, at most
/// one point), blanks between them. One pass over the bytes: no normalised copy, no list of
/// words sorted afterwards. `false` for any other line (a comment, a parameter, an
/// expression, a blank inside a word, an A word) and for one whose words are refused: `out`
/// is then read again by the general reader, which gives the error, if any, at its place.
/// What it reads is what the general reader reads (`Line::words`, `n`, each column the
/// byte's place) and what `words::sort_words_into` sorts them into.
///
/// In the Fanuc dialect (`FANUC`, `opts.fanuc`) the same, with its reading of a number: without a
/// decimal point on a length address in least increments (as written with calculator-type
/// input), and the letters noted in `plain`, `pointed` and `dotted` as the general reader
/// notes them; the words sorted in its dialect ([`words::FANUC`]). Where the reader rewrites a
/// line's words after reading (G04's dwell, G05.1's Q and R, a cycle's K), it sorts the line
/// again from them (`Line::sorted` false). Before stop 48 every Fanuc line went the general
/// way: 1.18 times LinuxCNC's reading.
fn read_plain<const FANUC: bool>(out: &mut Line, raw: &str, line: u32, opts: ReadOpts) -> bool {
    let b = raw.as_bytes();
    let blank = |c: u8| matches!(c, b' ' | b'\t' | b'\r');
    let mut i = 0;
    while i < b.len() && blank(b[i]) {
        i += 1;
    }
    let w = &mut out.sorted_words;
    w.clear();
    let mut seen = Seen::default();
    if i < b.len() && b[i] | 0x20 == b'n' {
        let d = Digits::read(&b[i + 1..]);
        let Some(v) = d.value() else {
            return false;
        };
        out.n = Some(v);
        i += 1 + d.len;
    }
    loop {
        while i < b.len() && blank(b[i]) {
            i += 1;
        }
        let Some(&c) = b.get(i) else {
            return true;
        };
        let letter = c.to_ascii_uppercase();
        // N and O out of place are errors; A is a word only with an A axis.
        if !letter.is_ascii_uppercase() || matches!(letter, b'A' | b'N' | b'O') {
            return false;
        }
        let col = i as u32 + 1;
        i += 1;
        let neg = b.get(i) == Some(&b'-');
        i += usize::from(neg);
        let d = Digits::read(b.get(i..).unwrap_or(&[]));
        let Some(v) = d.value() else {
            return false;
        };
        i += d.len;
        // A letter, a blank or the end after the number (`X1-2`, `X1.2.3`: an error).
        if b.get(i)
            .is_some_and(|&c| !blank(c) && !c.is_ascii_alphabetic())
        {
            return false;
        }
        let mut value = if neg { -v } else { v };
        let dialect = if FANUC {
            let bit = letter_bit(letter as char);
            out.plain |= bit;
            if d.point {
                out.dotted |= bit;
            }
            let increments = FANUC_INCREMENT_LETTERS.contains(&letter);
            if d.point || (increments && opts.calculator) {
                out.pointed |= bit;
            }
            if increments && !d.point && !opts.calculator {
                value *= opts.increment;
            }
            &words::FANUC
        } else {
            &words::MILL
        };
        let word = Word {
            letter: letter as char,
            value,
            col,
        };
        if w.add(word, line, dialect, &mut seen).is_err() {
            return false;
        }
        out.words.push(word);
    }
}

/// A word's value in the Fanuc dialect: a number written without a decimal point on a
/// length address ([`FANUC_INCREMENT_LETTERS`]) is in least increments (`X10` is 0.010 mm),
/// or, with calculator-type input (`increment` None), as written, as if with its point
/// (`X10` is 10 mm). With the value: `Some(point)` for a number written plainly (with a
/// decimal point or not), `None` for an expression or a variable.
fn fanuc_word_value(
    r: &mut Reader,
    letter: char,
    increment: Option<f64>,
) -> Result<(f64, Option<bool>), TranslateError> {
    let sign = match (r.at(0), r.at(1)) {
        (Some(b'-'), Some(b'0'..=b'9' | b'.')) => -1.0,
        (Some(b'+'), Some(b'0'..=b'9' | b'.')) => 1.0,
        (Some(b'0'..=b'9' | b'.'), _) => 0.0,
        _ => return Ok((r.value()?, None)),
    };
    if sign != 0.0 {
        r.i += 1;
    }
    let v = r.number()?;
    let sign = if sign == 0.0 { 1.0 } else { sign };
    if !r.point && FANUC_INCREMENT_LETTERS.contains(&(letter as u8)) {
        return Ok(match increment {
            Some(increment) => (sign * v * increment, Some(false)),
            None => (sign * v, Some(true)),
        });
    }
    Ok((sign * v, Some(r.point)))
}

/// A letter's bit in [`Line::pointed`] and [`Line::plain`] (A = bit 0 … Z = bit 25).
pub fn letter_bit(letter: char) -> u32 {
    match letter {
        'A'..='Z' => 1 << (letter as u32 - 'A' as u32),
        _ => 0,
    }
}

/// Whether a Fanuc statement's keyword starts at the reader's place: GOTO, IF [, WHILE [,
/// DO and END with their number (`X SIN[30]`, `I FIX[..]` are words).
fn fanuc_keyword(r: &Reader) -> bool {
    let rest = &r.b[r.i..];
    let next = |k: usize| rest.get(k).copied();
    let number = |c: Option<u8>| matches!(c, Some(b'0'..=b'9' | b'#' | b'['));
    (rest.starts_with(b"goto") && !next(4).is_some_and(|c| c.is_ascii_alphabetic()))
        || (rest.starts_with(b"if") && next(2) == Some(b'['))
        || (rest.starts_with(b"while") && next(5) == Some(b'['))
        || (rest.starts_with(b"do") && number(next(2)))
        || (rest.starts_with(b"end") && number(next(3)))
}

/// A Fanuc flow statement at the reader's place (letters on letters): GOTO, IF, WHILE, DO,
/// END; nothing more is read on the line. An `IF [..] THEN` whose condition holds leaves its
/// assignment in the line's assignments.
fn fanuc_statement(r: &mut Reader, out: &mut Line) -> Result<bool, TranslateError> {
    let col = r.col();
    let alone = |r: &Reader, out: &Line, what: &str| -> Result<(), TranslateError> {
        if out.words.is_empty() && out.assigns.is_empty() {
            Ok(())
        } else {
            Err(r.err(col, format!("{what} must begin its block (after N)")))
        }
    };
    let loop_number = |r: &mut Reader, what: &str| -> Result<u8, TranslateError> {
        let (m, mcol) = r.integer(&format!("{what}'s loop number"))?;
        if !(1..=3).contains(&m) {
            return Err(r.err(mcol, format!("{what}{m}: the loop number is 1 to 3")));
        }
        Ok(m as u8)
    };
    let goto = |r: &mut Reader| -> Result<i64, TranslateError> {
        let (n, ncol) = r.integer("GOTO's sequence number")?;
        if !(1..=99_999).contains(&n) {
            return Err(r.err(ncol, format!("GOTO {n}: a sequence number is 1 to 99999")));
        }
        Ok(n)
    };
    let ended = |r: &Reader, what: &str| -> Result<bool, TranslateError> {
        match r.peek() {
            None => Ok(true),
            Some(c) => Err(r.err(
                r.col(),
                format!("unexpected {} after {what}", describe_char(c)),
            )),
        }
    };
    if r.eat_name("goto") {
        alone(r, out, "GOTO")?;
        let n = goto(r)?;
        out.fanuc = Some(Macro::Goto { n, col });
        return ended(r, "GOTO n");
    }
    if r.eat_name("if") {
        alone(r, out, "IF")?;
        let test = nz(r.required_bracket("IF")?) != 0.0;
        if r.eat_name("goto") {
            let n = goto(r)?;
            if test {
                out.fanuc = Some(Macro::Goto { n, col });
            }
            return ended(r, "IF [...] GOTO n");
        }
        if r.eat_name("then") {
            if r.peek() != Some('#') {
                return Err(r.err(r.col(), "IF [...] THEN takes an assignment: #i=expression"));
            }
            if !test {
                // The assignment is not made, nor read.
                return Ok(true);
            }
            let (t, acol) = r.param_ref()?;
            if t == Target::Numbered(0) {
                return Err(r.err(acol, "#0 is null: it cannot be set"));
            }
            if !r.eat('=') {
                return Err(r.err(r.col(), "'=' expected after THEN's parameter"));
            }
            let v = r.expr(0)?;
            out.assigns.push((t, v, acol));
            return ended(r, "IF [...] THEN #i=expression");
        }
        return Err(r.err(
            r.col(),
            "IF [...] is followed by GOTO n or THEN #i=expression",
        ));
    }
    if r.eat_name("while") {
        alone(r, out, "WHILE")?;
        let test = nz(r.required_bracket("WHILE")?) != 0.0;
        if !r.eat_name("do") {
            return Err(r.err(r.col(), "WHILE [...] is followed by DOm (m = 1 to 3)"));
        }
        let m = loop_number(r, "DO")?;
        out.fanuc = Some(Macro::While { test, m, col });
        return ended(r, "WHILE [...] DOm");
    }
    if r.eat_name("do") {
        alone(r, out, "DO")?;
        let m = loop_number(r, "DO")?;
        out.fanuc = Some(Macro::Do { m, col });
        return ended(r, "DOm");
    }
    if r.eat_name("end") {
        alone(r, out, "END")?;
        let m = loop_number(r, "END")?;
        out.fanuc = Some(Macro::End { m, col });
        return ended(r, "ENDm");
    }
    let mut word = String::new();
    while let Some(c) = r.at(word.len()).filter(|c| c.is_ascii_alphabetic()) {
        word.push(c.to_ascii_uppercase() as char);
    }
    Err(r.err(
        col,
        format!("'{word}' is not a word: a word is a letter and its value (Fanuc's statements are GOTO, IF, WHILE, DO, END)"),
    ))
}

/// A line that is `%` and a program number (`%o1200`, `%:1200`), as normalised.
fn percent_and_number(b: &[u8]) -> bool {
    matches!(b, [b'%', b'o' | b':', d @ ..] if !d.is_empty() && d.iter().all(u8::is_ascii_digit))
}

fn read_o(
    r: &mut Reader,
    out: &mut Line,
    skipping: Option<Skipping>,
) -> Result<(), TranslateError> {
    let col = r.col();
    r.i += 1; // 'o'
    let computed = matches!(r.peek(), Some('[' | '#'));
    if computed && skipping.is_some() {
        // A computed label is evaluated on a call only, and a call never ends a skip.
        return Ok(());
    }
    let label = if r.peek() == Some('<') {
        r.name()?
    } else {
        // A number, or (on a call, as in LinuxCNC) an expression or parameter giving one.
        let (n, ncol) = r.integer("O number")?;
        if !(0..=99_999_999).contains(&n) {
            return Err(r.err(ncol, format!("bad O number {n}")));
        }
        n.to_string()
    };
    let kind = O_KEYWORDS
        .iter()
        .copied()
        .find(|k| r.eat_name(k.name()))
        .unwrap_or(OKind::Bare);
    if kind == OKind::Bare && r.peek().is_some() {
        if skipping.is_some() {
            return Ok(());
        }
        let mut word = String::new();
        while let Some(c) = r.at(word.len()).filter(|c| c.is_ascii_alphabetic()) {
            word.push(c as char);
        }
        return Err(r.err(
            r.col(),
            format!("unknown O-word keyword '{word}' (sub, endsub, call, return, do, while, endwhile, repeat, endrepeat, if, elseif, else, endif, break, continue)"),
        ));
    }
    if computed && kind != OKind::Call {
        return Err(r.err(
            col + 1,
            "an O-word's label is computed ([...] or #) on a call only: give the number here",
        ));
    }
    let evaluate = match skipping {
        None => true,
        Some(f) => f(&label, kind),
    };
    let mut o = OLine {
        label,
        kind,
        value: None,
        args: Vec::new(),
        col,
    };
    if evaluate {
        match kind {
            k if k.has_condition() => o.value = Some(r.required_bracket(k.name())?),
            OKind::Endsub | OKind::Return if r.peek() == Some('[') => o.value = Some(r.bracket()?),
            OKind::Call => {
                while r.peek() == Some('[') {
                    if o.args.len() >= MAX_ARGS {
                        return Err(
                            r.err(r.col(), format!("more than {MAX_ARGS} arguments to a call"))
                        );
                    }
                    o.args.push(r.bracket()?);
                }
            }
            _ => {}
        }
        if r.peek().is_some() {
            return Err(r.err(
                r.col(),
                format!(
                    "unexpected {} after 'o{} {}': an O-word line holds nothing else",
                    describe_char(r.peek().unwrap_or(' ')),
                    o.label,
                    kind.name()
                ),
            ));
        }
    }
    out.o = Some(o);
    Ok(())
}

/// A plain numbered-parameter table, `#1` to `#5602`, all 0 at the start; named parameters
/// are not defined. The lathe reader uses it.
#[derive(Clone, Debug)]
pub struct Params {
    v: Vec<f64>,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            v: vec![0.0; MAX_PARAM + 1],
        }
    }
}

impl Params {
    /// The value of `#n` (0 for a parameter never set).
    pub fn get(&self, n: usize) -> f64 {
        self.v.get(n).copied().unwrap_or(0.0)
    }

    /// Sets `#n`; false if `n` is out of range.
    pub fn set(&mut self, n: usize, x: f64) -> bool {
        match self.v.get_mut(n) {
            Some(p) if n > 0 => {
                *p = x;
                true
            }
            _ => false,
        }
    }
}

impl Env for Params {
    fn numbered(&self, n: usize) -> Result<f64, String> {
        Ok(self.get(n))
    }

    fn named(&self, _name: &str) -> Result<Option<f64>, String> {
        Err("named parameters #<...> are not supported here; use numbered parameters".into())
    }
}

/// Reads one line against a plain parameter table (the lathe's reader).
pub fn read_line(raw: &str, line: u32, params: &Params) -> Result<Line, TranslateError> {
    let mut out = Line::default();
    read_into(&mut Scratch::default(), &mut out, raw, line, params, None)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    struct TestEnv {
        p: Params,
        named: HashMap<String, f64>,
    }

    impl Env for TestEnv {
        fn numbered(&self, n: usize) -> Result<f64, String> {
            Ok(self.p.get(n))
        }
        fn named(&self, name: &str) -> Result<Option<f64>, String> {
            Ok(self.named.get(name).copied())
        }
    }

    fn env() -> TestEnv {
        let mut named = HashMap::new();
        named.insert("depth".to_string(), 2.5);
        named.insert("_global".to_string(), 7.0);
        TestEnv {
            p: Params::default(),
            named,
        }
    }

    fn read(s: &str) -> Result<Line, String> {
        let mut out = Line::default();
        read_into(&mut Scratch::default(), &mut out, s, 1, &env(), None)
            .map(|()| out)
            .map_err(|e| e.to_string())
    }

    fn eval(s: &str) -> Result<f64, String> {
        read(&format!("X{s}")).map(|l| l.words[0].value)
    }

    #[test]
    fn expressions_follow_precedence_and_functions_work_in_degrees() {
        assert_eq!(eval("[1+2*3]").unwrap(), 7.0);
        assert_eq!(eval("[2**3*2]").unwrap(), 16.0);
        assert_eq!(eval("[[1+2]*3]").unwrap(), 9.0);
        assert!((eval("SIN[30]").unwrap() - 0.5).abs() < 1e-12);
        assert!((eval("ATAN[1]/[1]").unwrap() - 45.0).abs() < 1e-12);
        assert_eq!(eval("FIX[-1.5]").unwrap(), -2.0);
        assert_eq!(eval("FUP[1.2]").unwrap(), 2.0);
        assert_eq!(eval("ROUND[2.5]").unwrap(), 3.0);
        assert_eq!(eval("-[2]").unwrap(), -2.0);
        assert_eq!(eval("[7 MOD 3]").unwrap(), 1.0);
        assert_eq!(eval("[-7 MOD 3]").unwrap(), 2.0);
        assert_eq!(eval("[2 GT 1]").unwrap(), 1.0);
        assert_eq!(eval("[1 EQ 1.0000001]").unwrap(), 1.0);
        assert_eq!(eval("[1 NE 1.0000001]").unwrap(), 0.0);
        assert_eq!(eval("[1 LE 1.0000001]").unwrap(), 1.0);
    }

    #[test]
    fn named_parameters_and_exists() {
        assert_eq!(eval("#<depth>").unwrap(), 2.5);
        assert_eq!(
            eval("#<De Pth>").unwrap(),
            2.5,
            "case and spaces do not count"
        );
        assert_eq!(eval("[#<_global>*2]").unwrap(), 14.0);
        assert_eq!(eval("EXISTS[#<depth>]").unwrap(), 1.0);
        assert_eq!(eval("EXISTS[#<nope>]").unwrap(), 0.0);
        // A number, as LinuxCNC's tests/interp/exists: 1 for a parameter, 0 past the last.
        assert_eq!(eval("EXISTS[#5220]").unwrap(), 1.0);
        assert_eq!(eval("EXISTS[#99999]").unwrap(), 0.0);
        assert_eq!(eval("EXISTS[#[99999+1]]").unwrap(), 0.0);
        assert_eq!(
            eval("#<nope>").unwrap_err(),
            "1:2: named parameter #<nope> is not defined"
        );
        let l = read("#<a>=1 #<_b>=#<depth> #3=4").unwrap();
        assert_eq!(
            l.assigns,
            vec![
                (Target::Named("a".into()), 1.0, 1),
                (Target::Named("_b".into()), 2.5, 8),
                (Target::Numbered(3), 4.0, 23)
            ]
        );
    }

    #[test]
    fn errors_name_the_column() {
        assert_eq!(eval("[1/0]").unwrap_err(), "1:4: division by zero");
        assert_eq!(
            eval("SQRT[-1]").unwrap_err(),
            "1:2: domain error: SQRT[-1] needs a number not below 0"
        );
        assert_eq!(
            eval("[-2**0.5]").unwrap_err(),
            "1:5: -2 ** 0.5: a negative number to a power that is not whole"
        );
        let big = format!("X{}", "9".repeat(309));
        assert!(
            read(&big).unwrap_err().contains("too large"),
            "literals stay finite"
        );
        assert!(read("X[1e]").is_err());
    }

    #[test]
    fn o_words_are_read_with_their_keyword_and_values() {
        let l = read("o100 sub").unwrap();
        assert_eq!(
            l.o.as_ref().map(|o| (o.label.as_str(), o.kind)),
            Some(("100", OKind::Sub))
        );
        let l = read("O<Drill Hole> call [1] [2+3] (comment)").unwrap();
        let o = l.o.unwrap();
        assert_eq!(o.label, "drillhole");
        assert_eq!(o.kind, OKind::Call);
        assert_eq!(o.args, vec![1.0, 5.0]);
        assert_eq!(l.comments.len(), 1);
        let l = read("o101 while [#<depth> LT 3]").unwrap();
        assert_eq!(l.o.unwrap().value, Some(1.0));
        let l = read("o101 endwhile").unwrap();
        assert_eq!(l.o.unwrap().kind, OKind::Endwhile);
        let l = read("o1 endsub [7]").unwrap();
        assert_eq!(l.o.unwrap().value, Some(7.0));
        let l = read("O1000").unwrap();
        assert_eq!(l.o.unwrap().kind, OKind::Bare);
        assert!(read("o1 while 3").unwrap_err().contains("'[' expected"));
        assert!(read("o1 if [1] G0")
            .unwrap_err()
            .contains("holds nothing else"));
        assert!(read("o1 frobnicate")
            .unwrap_err()
            .contains("unknown O-word keyword"));
        assert!(read("G0 o1 sub")
            .unwrap_err()
            .contains("must start its line"));
    }

    #[test]
    fn skipping_reads_only_o_lines_and_evaluates_only_the_one_skipped_to() {
        let e = env();
        let mut out = Line::default();
        let only_7 = |l: &str, _k: OKind| l == "7";
        // An undefined parameter on a skipped line is not an error.
        read_into(
            &mut Scratch::default(),
            &mut out,
            "G1 X#<undefined>",
            1,
            &e,
            Some(&only_7),
        )
        .unwrap();
        assert!(out.words.is_empty());
        read_into(
            &mut Scratch::default(),
            &mut out,
            "o5 if [#<undefined>]",
            1,
            &e,
            Some(&only_7),
        )
        .unwrap();
        assert_eq!(
            out.o.as_ref().map(|o| (o.kind, o.value)),
            Some((OKind::If, None))
        );
        read_into(
            &mut Scratch::default(),
            &mut out,
            "o7 elseif [#<depth>]",
            1,
            &e,
            Some(&only_7),
        )
        .unwrap();
        assert_eq!(out.o.as_ref().map(|o| o.value), Some(Some(2.5)));
    }

    #[test]
    fn active_comments_are_classified() {
        let l = read("(MSG, Change the tool) (print,x=#<_x>) (debug, d) (abort,stop) (logopen,f.txt) (plain)").unwrap();
        let kinds: Vec<_> = l.comments.iter().map(|c| c.kind).collect();
        assert_eq!(
            kinds,
            vec![
                CommentKind::Msg,
                CommentKind::Print,
                CommentKind::Debug,
                CommentKind::Abort,
                CommentKind::Log,
                CommentKind::Plain
            ]
        );
        assert_eq!(l.comments[0].text, " Change the tool");
        assert_eq!(l.comments[1].text, "x=#<_x>");
    }

    #[test]
    fn assignments_see_old_values_and_block_delete_and_n_are_read() {
        let mut e = env();
        e.p.set(1, 5.0);
        let mut l = Line::default();
        read_into(
            &mut Scratch::default(),
            &mut l,
            "#1=2 #2=#1 G1 (cut) X#1 ; rest",
            3,
            &e,
            None,
        )
        .unwrap();
        assert_eq!(l.assigns.len(), 2);
        assert_eq!(l.assigns[1].1, 5.0);
        assert_eq!(l.words.len(), 2);
        assert_eq!(l.words[1].value, 5.0);
        assert_eq!(l.comments.len(), 2);
        let l = read("/ n 10.5 g 0 x 1 0").unwrap();
        assert!(l.block_delete);
        assert_eq!(l.n, Some(10.5));
        assert_eq!(l.words[1].value, 10.0);
        let l = read("G1 @5 ^30").unwrap();
        assert_eq!(l.words[1].letter, '@');
        assert_eq!(l.words[2].letter, '^');
    }

    /// The reader's buffers are written over, not cleared: a line read after a longer one, or
    /// after one with a comment, reads as it does alone.
    #[test]
    fn a_line_reads_the_same_after_any_other() {
        let lines = [
            "G01 X-0.3089 Y1.5993 Z-0.125 F20  ",
            "X1",
            "G1 (cut) X2 ; rest",
            "%",
            "Y3.5",
            "#1=2 G0 X#1",
            "",
            "G2 X1 Y1 I0.5 J0.5",
        ];
        let mut scratch = Scratch::default();
        for (i, first) in lines.iter().enumerate() {
            for then in &lines[i..] {
                let mut after = Line::default();
                read_into(&mut scratch, &mut after, first, 1, &env(), None).unwrap();
                read_into(&mut scratch, &mut after, then, 2, &env(), None).unwrap();
                let mut alone = Line::default();
                read_into(&mut Scratch::default(), &mut alone, then, 2, &env(), None).unwrap();
                assert_eq!(after, alone, "{then:?} after {first:?}");
            }
        }
    }

    /// The usual line is read in one pass and sorted as read (`ReadOpts::sort`): the same
    /// words, N, errors and sorted words as reading the general way and sorting afterwards,
    /// on lines of every shape (blanks inside words, signs, points, long numbers, letters
    /// twice, codes of one group, A, N and O out of place, comments, parameters).
    #[test]
    fn the_usual_line_is_sorted_as_it_is_read() {
        // LinuxCNC's dialect, Fanuc's with least increments, Fanuc's with calculator-type
        // input (the Fanuc dialect reads the usual line so since stop 48).
        for (fanuc, calculator) in [(false, false), (true, false), (true, true)] {
            usual_lines(fanuc, calculator);
        }
    }

    fn usual_lines(fanuc: bool, calculator: bool) {
        let mut rng = crate::pulse_core::testkit::Rng::new(33);
        const PIECES: [&str; 40] = [
            "G",
            "g",
            "M",
            "X",
            "x",
            "Y",
            "Z",
            "I",
            "J",
            "K",
            "F",
            "S",
            "T",
            "P",
            "R",
            "Q",
            "D",
            "H",
            "L",
            "E",
            "A",
            "N",
            "n",
            "O",
            "B",
            " ",
            "  ",
            "\t",
            "-",
            ".",
            "1",
            "0",
            "25",
            "3.5",
            "-0.8925",
            "17.123456789012345",
            "12345678901234567890.5",
            "#1=2",
            "(c)",
            "+",
        ];
        const CODES: [&str; 12] = [
            "G0", "G1", "G01", "G2", "G3", "G80", "G81", "G17", "G90", "M3", "M5", "G91.1",
        ];
        let (mut sorted, mut general) = (0, 0);
        for i in 0..20_000 {
            let mut line = String::new();
            if i % 5 == 0 {
                line.push_str(["N10 ", "n5", " N1.5", "N", "/"][rng.range(0, 4) as usize]);
            }
            for _ in 0..rng.range(0, 6) {
                if fanuc && rng.unit() < 0.1 {
                    const FANUC: [&str; 6] = ["G4", "G5.1", "G31", "G68", "M29", "G9"];
                    line.push_str(FANUC[rng.range(0, 5) as usize]);
                    line.push(' ');
                } else if rng.unit() < 0.5 {
                    line.push_str(CODES[rng.range(0, 11) as usize]);
                    line.push(' ');
                } else {
                    line.push_str(PIECES[rng.range(0, 39) as usize]);
                }
            }
            let opts = |sort| ReadOpts {
                sort,
                fanuc,
                calculator,
                increment: 0.001,
            };
            let mut a = Line::default();
            let ra = read_into_opts(
                &mut Scratch::default(),
                &mut a,
                &line,
                7,
                &env(),
                None,
                opts(false),
            );
            let mut b = Line::default();
            let rb = read_into_opts(
                &mut Scratch::default(),
                &mut b,
                &line,
                7,
                &env(),
                None,
                opts(true),
            );
            assert_eq!(ra, rb, "{line:?}");
            assert!(!a.sorted, "{line:?}");
            assert_eq!((&a.words, a.n), (&b.words, b.n), "{line:?}");
            assert_eq!(
                (a.plain, a.pointed, a.dotted),
                (b.plain, b.pointed, b.dotted),
                "{line:?}"
            );
            if b.sorted {
                let dialect = if fanuc { &words::FANUC } else { &words::MILL };
                let w = super::words::sort_words_in(&a, 7, dialect);
                assert_eq!(w.as_ref(), Ok(&b.sorted_words), "{line:?}");
                sorted += 1;
            } else {
                general += 1;
            }
        }
        assert!(sorted > 2_000 && general > 2_000, "{sorted} {general}");
    }
}
