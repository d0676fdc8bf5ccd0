//! Text an operator or a file supplies, made safe for messages and checked on the way in
//! (docs/language.md, *Limits*): UTF-8 decoding that names the line and byte of a bad byte,
//! tape line endings (CR, CR LF, LF) read as PROGRAM READ reads them, and quoting that escapes
//! control and invisible characters and cuts long text, so that no message is longer than a line;
//! and the number syntax the part-program language and the tool tape share.

use std::fmt;
use std::path::Path;

/// The most characters of a token or argument quoted in a message; longer ones are cut with `…`.
pub const QUOTE_CHARS: usize = 40;

/// The byte order mark U+FEFF, which some editors put at the start of a UTF-8 file.
pub const BOM: char = '\u{feff}';

/// A byte sequence that is not UTF-8, and where it is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NotUtf8 {
    /// 1-based line (CR, CR LF and LF end a line).
    pub line: u32,
    /// 1-based column in characters.
    pub col: u32,
    /// 0-based offset of the first bad byte in the file.
    pub offset: usize,
    /// The first bad byte.
    pub byte: u8,
}

impl fmt::Display for NotUtf8 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: the file is not UTF-8 text: byte 0x{:02X} at byte offset {} (save it as UTF-8)",
            self.line, self.col, self.byte, self.offset
        )
    }
}

impl std::error::Error for NotUtf8 {}

/// The largest number a statement or a tool tape may hold (mm, degrees, rpm, mm/min, seconds).
pub const MAX_NUMBER: f64 = 1e9;

/// Reads a number as the language writes it: an optional sign, digits with at most one decimal
/// point (`12`, `-3.5`, `.5`, `+2.`), no exponent, at most `MAX_NUMBER` in size. The tool tape
/// reads its numbers with the same rule. The error is the message alone.
pub fn number(s: &str) -> Result<f64, String> {
    let body = s.strip_prefix(['+', '-']).unwrap_or(s);
    let digits = body.bytes().filter(u8::is_ascii_digit).count();
    let dots = body.bytes().filter(|&b| b == b'.').count();
    if digits == 0 || dots > 1 || digits + dots != body.len() {
        return Err(format!(
            "{} is not a number (digits with at most one decimal point, no exponent)",
            quote(s)
        ));
    }
    match s.parse::<f64>() {
        Ok(v) if v.abs() <= MAX_NUMBER => Ok(v),
        _ => Err(format!(
            "{} is too large (numbers go up to {MAX_NUMBER})",
            quote_plain(s)
        )),
    }
}

/// A number for a message as it would be written, or with an exponent when that is long (a
/// value of 300 digits, or a denormal of 320 decimals): `2.5`, `1e300`, `1e-320`.
pub fn short_number(v: f64) -> String {
    let s = v.to_string();
    if s.len() <= 24 {
        s
    } else {
        format!("{v:e}")
    }
}

/// A length, time or speed for a message with `decimals` decimals, or with an exponent once it
/// is too large for that to be short: `12.500`, `1.000e17`.
pub fn fixed(v: f64, decimals: usize) -> String {
    if v.abs() < 1e9 {
        format!("{v:.decimals$}")
    } else {
        format!("{v:.decimals$e}")
    }
}

/// Decodes UTF-8, or says where the first bad byte is (line, column and byte offset).
pub fn decode(bytes: &[u8]) -> Result<&str, NotUtf8> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s),
        Err(e) => {
            let offset = e.valid_up_to();
            // The part before the bad byte is valid UTF-8 by construction.
            let good = std::str::from_utf8(&bytes[..offset]).unwrap_or("");
            let mut line = 1u32;
            let mut col = 1u32;
            let mut prev_cr = false;
            for c in good.chars() {
                match c {
                    '\n' if prev_cr => {}
                    '\n' | '\r' => {
                        line += 1;
                        col = 1;
                    }
                    _ => col += 1,
                }
                prev_cr = c == '\r';
            }
            Err(NotUtf8 {
                line,
                col,
                offset,
                byte: bytes[offset],
            })
        }
    }
}

/// Tape text with its record separators (CR, CR LF) made end-of-block characters (LF), as
/// PROGRAM READ stores a tape.
pub fn tape_line_ends(text: &str) -> String {
    if text.contains('\r') {
        text.replace("\r\n", "\n").replace('\r', "\n")
    } else {
        text.to_string()
    }
}

/// The lines of a tape or table (a leading byte order mark skipped; CR, CR LF and LF each end a
/// line), as PROGRAM READ and TOOL DATA READ count them.
pub fn tape_lines(text: &str) -> impl Iterator<Item = &str> {
    let text = text.strip_prefix(BOM).unwrap_or(text);
    let text = text.strip_suffix('\n').unwrap_or(text);
    let text = text.strip_suffix('\r').unwrap_or(text);
    let mut rest = Some(text).filter(|t| !t.is_empty());
    std::iter::from_fn(move || {
        let t = rest?;
        match t.find(['\r', '\n']) {
            Some(i) => {
                let skip = if t[i..].starts_with("\r\n") { 2 } else { 1 };
                rest = Some(&t[i + skip..]);
                Some(&t[..i])
            }
            None => {
                rest = None;
                Some(t)
            }
        }
    })
}

/// Reads a text file as a tape: UTF-8 (a bad byte is named as `PATH:LINE:COL: ...`), CR and
/// CR LF made LF. Errors are whole messages, starting with `novanc: ` or the path.
pub fn read_tape_file(path: &str) -> Result<String, String> {
    let bytes = std::fs::read(Path::new(path))
        .map_err(|e| format!("novanc: cannot read {}: {e}", quote_plain(path)))?;
    let text = decode(&bytes).map_err(|e| format!("{path}:{e}"))?;
    Ok(tape_line_ends(text))
}

/// What a character is called in a message: `'x'` for a visible one; for a control, format or
/// blank character its code point and name, e.g. `U+0000 (a control character)`.
pub fn describe_char(c: char) -> String {
    let name = match c {
        BOM => Some("a byte order mark"),
        '\t' => Some("a tab"),
        '\r' => Some("a carriage return"),
        '\u{a0}' => Some("a no-break space"),
        '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{206f}' => {
            Some("an invisible formatting character")
        }
        c if c.is_control() => Some("a control character"),
        c if c.is_whitespace() => Some("a space character"),
        _ => None,
    };
    match name {
        Some(n) => format!("U+{:04X} ({n})", c as u32),
        None => format!("'{c}'"),
    }
}

/// Whether a character is shown escaped in a message (control, format or odd blank).
fn needs_escape(c: char) -> bool {
    c != ' ' && (c.is_control() || c.is_whitespace() || describe_char(c).starts_with("U+"))
}

/// `c` as a message shows it: escaped as `\u{..}` if it would be invisible or move the cursor.
fn shown(c: char) -> String {
    if needs_escape(c) {
        format!("\\u{{{:x}}}", c as u32)
    } else {
        c.to_string()
    }
}

/// Text for a message, without quotes: control and invisible characters escaped as `\u{..}`,
/// and cut once `QUOTE_CHARS` characters are shown, with `…(N characters)` (N of the text).
pub fn quote_plain(s: &str) -> String {
    let mut out = String::new();
    let mut width = 0;
    for c in s.chars() {
        let sc = shown(c);
        width += sc.chars().count();
        if width > QUOTE_CHARS {
            out.push_str(&format!("…({} characters)", s.chars().count()));
            return out;
        }
        out.push_str(&sc);
    }
    out
}

/// Text for a message in single quotes, escaped and cut as [`quote_plain`] does.
pub fn quote(s: &str) -> String {
    format!("'{}'", quote_plain(s))
}

/// Raw bytes (an argument that is not UTF-8) for a message: the UTF-8 parts as [`quote_plain`]
/// shows them, each bad byte as `\xHH`.
pub fn escape_bytes(b: &[u8]) -> String {
    let mut out = String::new();
    for chunk in b.utf8_chunks() {
        for c in chunk.valid().chars() {
            out.push_str(&shown(c));
        }
        for byte in chunk.invalid() {
            out.push_str(&format!("\\x{byte:02X}"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_names_line_column_and_offset() {
        let e = decode(b"DA1 = (1,2,3)\r\nP1=(1,\xff2)").unwrap_err();
        assert_eq!((e.line, e.col, e.offset, e.byte), (2, 7, 21, 0xff));
        assert_eq!(
            e.to_string(),
            "2:7: the file is not UTF-8 text: byte 0xFF at byte offset 21 (save it as UTF-8)"
        );
        let e = decode(b"a\rb\xe9").unwrap_err();
        assert_eq!((e.line, e.col, e.offset), (2, 2, 3));
        assert_eq!(decode("café".as_bytes()), Ok("café"));
    }

    #[test]
    fn quoting_escapes_and_cuts() {
        assert_eq!(quote("AB"), "'AB'");
        assert_eq!(quote("a\0b"), "'a\\u{0}b'");
        assert_eq!(quote("\u{feff}X"), "'\\u{feff}X'");
        let long = "9".repeat(1_000_000);
        let q = quote(&long);
        assert!(q.len() < 80, "{q}");
        assert!(q.ends_with("…(1000000 characters)'"), "{q}");
        assert_eq!(
            quote(&"x".repeat(QUOTE_CHARS)),
            format!("'{}'", "x".repeat(40))
        );
        assert_eq!(describe_char('\0'), "U+0000 (a control character)");
        assert_eq!(describe_char(BOM), "U+FEFF (a byte order mark)");
        assert_eq!(describe_char('#'), "'#'");
        assert_eq!(describe_char('é'), "'é'");
        assert_eq!(escape_bytes(b"caf\xe9.ap"), "caf\\xE9.ap");
        assert_eq!(escape_bytes(b"I\xff\n"), "I\\xFF\\u{a}");
    }

    #[test]
    fn tape_line_ends_are_lf() {
        assert_eq!(tape_line_ends("A\r\nB\rC\n"), "A\nB\nC\n");
        let lines = |t| tape_lines(t).collect::<Vec<_>>();
        assert_eq!(lines("\u{feff}A\r\nB\rC\n\nD"), ["A", "B", "C", "", "D"]);
        assert_eq!(lines("A\r"), ["A"]);
        assert_eq!(lines("A\n\n"), ["A", ""]);
        assert!(lines("").is_empty());
    }
}
