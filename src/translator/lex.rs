//! The statement scanner: splits one source statement into keywords, numbers and the unit
//! separators `,` `/` `=` and parentheses (patent lines 283–290: units separated by `,` `/` `=`;
//! a comma inside parentheses does not separate units).
//!
//! A keyword is a run of letters (`DA`, `PAT`, `SDP`); the number that follows it (`DA1`,
//! `DP20`) is a separate token, so `PAT1` and `PAT 1` read the same. Letters are read without
//! regard to case. `;` ends the statement (the rest is a comment).

use super::TranslateError;
use crate::input_text::{describe_char, quote};

pub use crate::input_text::{number, MAX_NUMBER};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A keyword (letters only, upper case).
    Word(String),
    /// A number, with sign and decimal point.
    Num(f64),
    /// `,`
    Comma,
    /// `/`
    Slash,
    /// `=`
    Eq,
    /// `(`
    LParen,
    /// `)`
    RParen,
}

/// A token and the 1-based column where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// The token.
    pub tok: Tok,
    /// 1-based column (characters) in the source line.
    pub col: u32,
}

impl Tok {
    /// How the token reads in a message.
    pub fn describe(&self) -> String {
        match self {
            Tok::Word(w) => quote(w),
            Tok::Num(n) => format!("the number {n}"),
            Tok::Comma => "','".to_string(),
            Tok::Slash => "'/'".to_string(),
            Tok::Eq => "'='".to_string(),
            Tok::LParen => "'('".to_string(),
            Tok::RParen => "')'".to_string(),
        }
    }
}

/// Scans one statement (a source line) into `out`. Errors carry the statement's line.
pub fn scan(text: &str, line: u32, out: &mut Vec<Token>) -> Result<(), TranslateError> {
    out.clear();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    let mut depth = 0i32;
    while i < chars.len() {
        let c = chars[i];
        let col = i as u32 + 1;
        if c == ';' {
            break;
        }
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_alphabetic() {
            let mut w = String::new();
            while i < chars.len() && chars[i].is_ascii_alphabetic() {
                w.push(chars[i].to_ascii_uppercase());
                i += 1;
            }
            out.push(Token {
                tok: Tok::Word(w),
                col,
            });
            continue;
        }
        let starts_number = c.is_ascii_digit()
            || c == '.'
            || ((c == '-' || c == '+')
                && chars
                    .get(i + 1)
                    .is_some_and(|d| d.is_ascii_digit() || *d == '.'));
        if starts_number {
            let start = i;
            i += 1;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // No keyword starts with E, so a number followed by E is written with an exponent.
            if chars.get(i).is_some_and(|e| matches!(e, 'e' | 'E')) {
                let mut end = i + 1;
                if chars.get(end).is_some_and(|c| matches!(c, '+' | '-')) {
                    end += 1;
                }
                while end < chars.len() && chars[end].is_ascii_alphanumeric() {
                    end += 1;
                }
                let s: String = chars[start..end].iter().collect();
                return Err(TranslateError {
                    line,
                    col,
                    message: number(&s).err().unwrap_or_default(),
                });
            }
            let s: String = chars[start..i].iter().collect();
            let v = number(&s).map_err(|message| TranslateError { line, col, message })?;
            out.push(Token {
                tok: Tok::Num(v),
                col,
            });
            continue;
        }
        let tok = match c {
            ',' => Tok::Comma,
            '/' => Tok::Slash,
            '=' => Tok::Eq,
            '(' => {
                depth += 1;
                Tok::LParen
            }
            ')' => {
                depth -= 1;
                if depth < 0 {
                    return Err(TranslateError {
                        line,
                        col,
                        message: "')' without a matching '('".to_string(),
                    });
                }
                Tok::RParen
            }
            _ => {
                return Err(TranslateError {
                    line,
                    col,
                    message: format!("{} is not part of the language", describe_char(c)),
                })
            }
        };
        out.push(Token { tok, col });
        i += 1;
    }
    if depth > 0 {
        return Err(TranslateError {
            line,
            col: chars.len() as u32 + 1,
            message: "a '(' is not closed".to_string(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        let mut v = Vec::new();
        scan(s, 1, &mut v).unwrap();
        v.into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn splits_keywords_numbers_and_separators() {
        assert_eq!(
            toks("BOR, 610/DP35, SDP/DA1, P1 ; comment"),
            vec![
                Tok::Word("BOR".into()),
                Tok::Comma,
                Tok::Num(610.0),
                Tok::Slash,
                Tok::Word("DP".into()),
                Tok::Num(35.0),
                Tok::Comma,
                Tok::Word("SDP".into()),
                Tok::Slash,
                Tok::Word("DA".into()),
                Tok::Num(1.0),
                Tok::Comma,
                Tok::Word("P".into()),
                Tok::Num(1.0),
            ]
        );
        assert_eq!(toks("l1 = p1, a-30.5"), toks("L1=P1,A -30.5"));
        assert_eq!(toks("(.5, -2.)")[1], Tok::Num(0.5));
    }

    #[test]
    fn reports_bad_characters_and_parentheses_with_columns() {
        let mut v = Vec::new();
        let e = scan("P1 = (1, 2#)", 7, &mut v).unwrap_err();
        assert_eq!((e.line, e.col), (7, 11));
        assert!(scan("P1 = (1, 2", 1, &mut v).is_err());
        assert!(scan("P1 = 1, 2)", 1, &mut v).is_err());
        assert!(scan("P1 = (1.2.3, 2)", 1, &mut v).is_err());
        let big = format!("GO, {}, 0, 0", "9".repeat(400));
        assert!(scan(&big, 1, &mut v).is_err());
        let e = scan("GD, 1000000001, 0, 0", 1, &mut v).unwrap_err();
        assert!(e.message.contains("too large"), "{e}");
        let e = scan("GO, 1e5, 0, 0", 1, &mut v).unwrap_err();
        assert_eq!(
            (e.col, e.message.as_str()),
            (
                5,
                "'1e5' is not a number (digits with at most one decimal point, no exponent)"
            )
        );
        let e = scan("GO, 2.5E-3, 0, 0", 1, &mut v).unwrap_err();
        assert!(e.message.starts_with("'2.5E-3' is not a number"), "{e}");
    }
}
