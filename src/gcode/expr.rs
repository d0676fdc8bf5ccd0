//! Reading one ISO line: block delete, comments, words, numbered parameters and bracket
//! expressions (docs/gcode.md "Words", "Parameters and expressions").
//!
//! Spaces are insignificant outside comments (as in LinuxCNC). Letters are case-insensitive.
//! A word's value is a number, `#n`, `#[expr]` or `[expr]`; a unary `-` or `+` may precede
//! any of them. Trigonometric functions work in degrees. Parameter assignments `#n=expr` take
//! effect after the whole line has been read, so every read on the line sees the old values.

use crate::block::TranslateError;
use crate::input_text::{describe_char, quote_plain};

/// The highest numbered parameter.
pub const MAX_PARAM: usize = 5400;

/// One word: its letter (upper case), value and 1-based column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The letter, upper case.
    pub letter: char,
    /// The value.
    pub value: f64,
    /// Column of the letter.
    pub col: u32,
}

/// A line read into its parts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Line {
    /// The line starts with `/`.
    pub block_delete: bool,
    /// Words in the order written (N and O included).
    pub words: Vec<Word>,
    /// Parameter assignments `#n=value`, applied after the line is read.
    pub assigns: Vec<(usize, f64)>,
    /// The line is a lone `%`.
    pub percent: bool,
    /// An `O` word with its number, if the line has one (first word).
    pub o_number: Option<(u32, u32)>,
    /// The line has a comment.
    pub comment: bool,
}

/// The parameters `#1` to `#5400`, all 0 at the start.
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

/// Reusable buffers for reading lines without allocating per line.
#[derive(Debug, Default)]
pub struct Scratch {
    bytes: Vec<u8>,
    cols: Vec<u32>,
}

struct Reader<'a> {
    /// The line's characters (ASCII) and their columns, spaces outside comments removed.
    b: &'a [u8],
    cols: &'a [u32],
    i: usize,
    line: u32,
    params: &'a Params,
    end_col: u32,
    /// Nesting of values being read (brackets, signs, parameters), bounded.
    depth: u32,
}

/// The deepest nesting of brackets, signs and parameter references in one value.
pub const MAX_NESTING: u32 = 64;

const CONTROL: [&str; 8] = [
    "IF", "WHILE", "GOTO", "SUB", "ENDSUB", "DO", "REPEAT", "CALL",
];

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

    fn upper_at(&self, k: usize) -> Option<char> {
        self.b
            .get(self.i + k)
            .map(|&x| (x as char).to_ascii_uppercase())
    }

    fn eat(&mut self, ch: char) -> bool {
        if self.peek() == Some(ch) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    /// Whether the next characters spell `name` (upper case ASCII), and consumes them if so.
    fn eat_name(&mut self, name: &str) -> bool {
        let n = name.len();
        let Some(next) = self.b.get(self.i..self.i + n) else {
            return false;
        };
        if next.eq_ignore_ascii_case(name.as_bytes()) {
            self.i += n;
            true
        } else {
            false
        }
    }

    fn number(&mut self) -> Result<f64, TranslateError> {
        let col = self.col();
        let start = self.i;
        // Digits into an integer mantissa: exact, and correctly rounded by one division
        // while it stays below 2^53 with at most 22 decimals (else the standard parser).
        let (mut mant, mut digits, mut decimals, mut dot) = (0u64, 0u32, 0i32, false);
        while let Some(&c) = self.b.get(self.i) {
            if c.is_ascii_digit() {
                if digits < 19 {
                    mant = mant * 10 + u64::from(c - b'0');
                }
                digits += 1;
                if dot {
                    decimals += 1;
                }
            } else if c == b'.' && !dot {
                dot = true;
            } else {
                break;
            }
            self.i += 1;
        }
        if digits == 0 {
            self.i = start;
            let what = self
                .peek()
                .map_or("the end of the line".to_string(), describe_char);
            return Err(self.err(col, format!("a number was expected, not {what}")));
        }
        if digits <= 15 && decimals <= 22 {
            return Ok(mant as f64 / 10f64.powi(decimals));
        }
        let text = std::str::from_utf8(&self.b[start..self.i]).unwrap_or("0");
        // Digits and one point always parse; too many of them read as infinity, which no
        // word may carry (docs/limits.md).
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.err(
                col,
                format!("{} is too large for a number", quote_plain(text)),
            )),
            Err(_) => Err(self.err(col, format!("bad number {}", quote_plain(text)))),
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
            return Ok(-self.value()?);
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

    fn param_number(&mut self) -> Result<(usize, u32), TranslateError> {
        let col = self.col();
        self.i += 1; // '#'
        if self.peek() == Some('<') {
            return Err(self.err(
                col,
                "named parameters #<...> are not supported; use numbered parameters #1 to #5400",
            ));
        }
        let v = self.value()?;
        let n = v.round();
        if (v - n).abs() > 1e-4 || !(1.0..=MAX_PARAM as f64).contains(&n) {
            return Err(self.err(
                col,
                format!(
                    "parameter number {} is not 1 to {MAX_PARAM}",
                    crate::input_text::short_number(v)
                ),
            ));
        }
        Ok((n as usize, col))
    }

    fn param(&mut self) -> Result<f64, TranslateError> {
        let (n, _) = self.param_number()?;
        Ok(self.params.get(n))
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
            "ABS", "ACOS", "ASIN", "ATAN", "COS", "EXP", "FIX", "FUP", "LN", "ROUND", "SIN",
            "SQRT", "TAN", "EXISTS",
        ];
        let Some(name) = NAMES.iter().find(|n| self.eat_name(n)) else {
            let mut word = String::new();
            let mut k = 0;
            while let Some(c) = self.upper_at(k).filter(|c| c.is_ascii_alphabetic()) {
                word.push(c);
                k += 1;
            }
            return Err(self.err(
                col,
                format!("unknown function or word '{word}' in an expression"),
            ));
        };
        if *name == "EXISTS" {
            return Err(self.err(col, "EXISTS is not supported (named parameters are not)"));
        }
        if self.peek() != Some('[') {
            return Err(self.err(
                self.col(),
                format!("{name} needs its argument in brackets: {name}[...]"),
            ));
        }
        let a = self.bracket()?;
        let dom = |ok: bool, what: &str| -> Result<(), TranslateError> {
            if ok {
                Ok(())
            } else {
                Err(TranslateError {
                    line: self.line,
                    col,
                    message: format!(
                        "domain error: {name}[{}] {what}",
                        crate::input_text::short_number(a)
                    ),
                })
            }
        };
        let r = match *name {
            "ABS" => a.abs(),
            "ACOS" => {
                dom((-1.0..=1.0).contains(&a), "needs -1 to 1")?;
                a.acos().to_degrees()
            }
            "ASIN" => {
                dom((-1.0..=1.0).contains(&a), "needs -1 to 1")?;
                a.asin().to_degrees()
            }
            "ATAN" => {
                if !self.eat('/') || self.peek() != Some('[') {
                    return Err(self.err(self.col(), "ATAN is written ATAN[y]/[x]"));
                }
                let b = self.bracket()?;
                a.atan2(b).to_degrees()
            }
            "COS" => a.to_radians().cos(),
            "SIN" => a.to_radians().sin(),
            "TAN" => {
                let t = a.to_radians().tan();
                dom(t.is_finite() && t.abs() < 1e15, "is infinite")?;
                t
            }
            "EXP" => a.exp(),
            "FIX" => a.floor(),
            "FUP" => a.ceil(),
            "LN" => {
                dom(a > 0.0, "needs a number greater than 0")?;
                a.ln()
            }
            "ROUND" => a.round(),
            _ => {
                dom(a >= 0.0, "needs a number not below 0")?;
                a.sqrt()
            }
        };
        if !r.is_finite() {
            return Err(self.err(
                col,
                format!(
                    "{name}[{}] is not a finite number",
                    crate::input_text::short_number(a)
                ),
            ));
        }
        Ok(r)
    }

    /// Binary operators by precedence level: 0 logical, 1 relational, 2 additive,
    /// 3 multiplicative, 4 power.
    fn op(&mut self, level: u8) -> Option<&'static str> {
        // Most values are followed by ']' or the next word: no operator starts with those.
        let first = self.upper_at(0)?;
        if !matches!(
            first,
            '+' | '-' | '*' | '/' | 'A' | 'O' | 'X' | 'E' | 'N' | 'G' | 'L' | 'M'
        ) {
            return None;
        }
        let table: &[&'static str] = match level {
            0 => &["AND", "OR", "XOR"],
            1 => &["EQ", "NE", "GT", "GE", "LT", "LE"],
            2 => &["+", "-"],
            3 => &["*", "/", "MOD"],
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
            if level == 3 && self.peek() == Some('*') && self.b.get(self.i + 1) == Some(&b'*') {
                return Ok(a);
            }
            let col = self.col();
            let Some(op) = self.op(level) else {
                return Ok(a);
            };
            let b = self.expr(level + 1)?;
            let t = |x: bool| if x { 1.0 } else { 0.0 };
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
                "MOD" => {
                    if b == 0.0 {
                        return Err(self.err(col, "division by zero (MOD 0)"));
                    }
                    a.rem_euclid(b)
                }
                "**" => {
                    let r = a.powf(b);
                    if !r.is_finite() {
                        return Err(self.err(
                            col,
                            format!(
                                "domain error: {} ** {}",
                                crate::input_text::short_number(a),
                                crate::input_text::short_number(b)
                            ),
                        ));
                    }
                    r
                }
                "EQ" => t(a == b),
                "NE" => t(a != b),
                "GT" => t(a > b),
                "GE" => t(a >= b),
                "LT" => t(a < b),
                "LE" => t(a <= b),
                "AND" => t(a != 0.0 && b != 0.0),
                "OR" => t(a != 0.0 || b != 0.0),
                _ => t((a != 0.0) != (b != 0.0)),
            };
            if !a.is_finite() {
                return Err(self.err(col, format!("the result of {op} is not a finite number")));
            }
        }
    }
}

/// Reads one line (without its newline) against the parameters in force.
pub fn read_line(raw: &str, line: u32, params: &Params) -> Result<Line, TranslateError> {
    let mut out = Line::default();
    read_into(&mut Scratch::default(), &mut out, raw, line, params)?;
    Ok(out)
}

/// Reads one line into `out` (cleared first), with reusable buffers.
pub fn read_into(
    scratch: &mut Scratch,
    out: &mut Line,
    raw: &str,
    line: u32,
    params: &Params,
) -> Result<(), TranslateError> {
    out.block_delete = false;
    out.words.clear();
    out.assigns.clear();
    out.percent = false;
    out.o_number = None;
    out.comment = false;
    let (bytes, cols) = (&mut scratch.bytes, &mut scratch.cols);
    bytes.clear();
    cols.clear();
    let mut in_comment: Option<u32> = None;
    let mut col = 0u32;
    if raw.is_ascii() {
        // The usual case: one byte per column.
        for &c in raw.as_bytes() {
            col += 1;
            if in_comment.is_some() {
                if c == b')' {
                    in_comment = None;
                }
                continue;
            }
            match c {
                b'(' => {
                    in_comment = Some(col);
                    out.comment = true;
                }
                b';' => {
                    out.comment = true;
                    break;
                }
                b' ' | b'\t' | b'\r' => {}
                _ => {
                    bytes.push(c);
                    cols.push(col);
                }
            }
        }
    }
    let chars = if raw.is_ascii() {
        "".chars()
    } else {
        raw.chars()
    };
    for ch in chars {
        col += 1;
        if in_comment.is_some() {
            if ch == ')' {
                in_comment = None;
            }
            continue;
        }
        match ch {
            '(' => {
                in_comment = Some(col);
                out.comment = true;
            }
            ';' => {
                out.comment = true;
                break;
            }
            ' ' | '\t' | '\r' => {}
            c if c.is_ascii() => {
                bytes.push(c as u8);
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
    if let Some(at) = in_comment {
        return Err(TranslateError {
            line,
            col: at,
            message: "comment '(' not closed on its line".into(),
        });
    }
    if bytes.len() == 1 && bytes[0] == b'%' {
        out.percent = true;
        return Ok(());
    }
    let mut r = Reader {
        b: bytes,
        cols,
        i: 0,
        line,
        params,
        end_col: col + 1,
        depth: 0,
    };
    if r.eat('/') {
        out.block_delete = true;
    }
    while let Some(ch) = r.peek() {
        let col = r.col();
        if ch == '#' {
            let (n, _) = r.param_number()?;
            if !r.eat('=') {
                return Err(r.err(
                    r.col(),
                    format!("'=' expected after #{n} (a parameter alone is not a word)"),
                ));
            }
            let v = r.value()?;
            out.assigns.push((n, v));
            continue;
        }
        if !ch.is_ascii_alphabetic() {
            return Err(r.err(
                col,
                format!("a word letter was expected, not {}", describe_char(ch)),
            ));
        }
        let letter = ch.to_ascii_uppercase();
        // Control flow words of other dialects.
        for w in CONTROL {
            if r.eat_name(w) {
                return Err(r.err(
                    col,
                    format!("control flow ({w}) is not supported: only M98/M99 subprograms are"),
                ));
            }
        }
        r.i += 1;
        if letter == 'O' && r.peek() == Some('<') {
            return Err(r.err(col, "O<name> control flow (sub, if, while, call) is not supported: only O-number subprograms with M98/M99 are"));
        }
        let value = r.value()?;
        if letter == 'O' {
            // O100 sub, O100 if ...: O-word control flow.
            if r.peek().is_some_and(|c| c.is_ascii_alphabetic()) {
                let save = r.i;
                let mut w = String::new();
                while let Some(c) = r.peek().filter(|c| c.is_ascii_alphabetic()) {
                    w.push(c.to_ascii_uppercase());
                    r.i += 1;
                }
                if [
                    "SUB",
                    "ENDSUB",
                    "IF",
                    "ELSE",
                    "ELSEIF",
                    "ENDIF",
                    "WHILE",
                    "ENDWHILE",
                    "DO",
                    "CALL",
                    "RETURN",
                    "REPEAT",
                    "ENDREPEAT",
                    "BREAK",
                    "CONTINUE",
                ]
                .contains(&w.as_str())
                {
                    return Err(r.err(col, format!("O-word control flow ({w}) is not supported: only O-number subprograms with M98/M99 are")));
                }
                r.i = save;
            }
            if !out.words.is_empty() || out.o_number.is_some() {
                return Err(r.err(col, "an O program number must start its line"));
            }
            if value < 0.0 || value.fract() != 0.0 || value > 99_999.0 {
                return Err(r.err(
                    col,
                    format!(
                        "bad program number O{}",
                        crate::input_text::short_number(value)
                    ),
                ));
            }
            out.o_number = Some((value as u32, col));
            continue;
        }
        out.words.push(Word { letter, value, col });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(s: &str) -> Result<f64, String> {
        let p = Params::default();
        read_line(&format!("X{s}"), 1, &p)
            .map(|l| l.words[0].value)
            .map_err(|e| e.to_string())
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
        assert_eq!(eval("[2 GT 1]").unwrap(), 1.0);
    }

    #[test]
    fn errors_name_the_column() {
        assert_eq!(eval("[1/0]").unwrap_err(), "1:4: division by zero");
        assert_eq!(
            eval("SQRT[-1]").unwrap_err(),
            "1:2: domain error: SQRT[-1] needs a number not below 0"
        );
        assert_eq!(
            eval("LN[0]").unwrap_err(),
            "1:2: domain error: LN[0] needs a number greater than 0"
        );
    }

    #[test]
    fn assignments_see_old_values_and_comments_are_skipped() {
        let mut p = Params::default();
        p.set(1, 5.0);
        let l = read_line("#1=2 #2=#1 G1 (cut) X#1 ; rest", 3, &p).unwrap();
        assert_eq!(l.assigns, vec![(1, 2.0), (2, 5.0)]);
        assert_eq!(l.words.len(), 2);
        assert_eq!(l.words[1].value, 5.0);
        assert!(l.comment);
        let l = read_line("/ g 0 x 1 0", 1, &p).unwrap();
        assert!(l.block_delete);
        assert_eq!(l.words[1].value, 10.0);
    }
}
