//! Reading a command line into commands (docs/editor.md): counts with sign and default, text arguments
//! with `*` for EOB, `$` as the terminator and `\` to take `*`, `$` or `\` literally.

use crate::{Command, EditError, EOB};

/// One command with the text the operator typed for it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Typed {
    /// The command.
    pub command: Command,
    /// The command as typed (without surrounding spaces).
    pub typed: String,
}

/// Parses a command line, keeping what was typed for each command (for error messages).
pub fn parse_typed(line: &str) -> Result<Vec<Typed>, EditError> {
    let chars: Vec<char> = line.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    loop {
        while i < chars.len() && is_blank(chars[i]) {
            i += 1;
        }
        if i >= chars.len() {
            return Ok(out);
        }
        let start = i;
        let index = out.len();
        let fail = |end: usize, reason: String| EditError {
            index,
            command: chars[start..end.min(chars.len())].iter().collect(),
            reason,
        };
        // Count: optional sign, optional digits. The sign is read with the digits, so the
        // whole 64-bit range is a count, -9223372036854775808 included.
        let mut sign = 1i64;
        let mut has_count = false;
        if chars[i] == '+' || chars[i] == '-' {
            if chars[i] == '-' {
                sign = -1;
            }
            has_count = true;
            i += 1;
        }
        let digits_start = i;
        while i < chars.len() && chars[i].is_ascii_digit() {
            i += 1;
        }
        let count = if i > digits_start {
            has_count = true;
            let mut digits: String = if sign < 0 { "-".into() } else { String::new() };
            digits.extend(&chars[digits_start..i]);
            match digits.parse::<i64>() {
                Ok(v) => v,
                Err(_) => {
                    let what = if sign < 0 { "small" } else { "large" };
                    return Err(fail(
                        i,
                        format!(
                            "count too {what}: {} (counts go from {} to {})",
                            cut(&digits),
                            i64::MIN,
                            i64::MAX
                        ),
                    ));
                }
            }
        } else {
            sign
        };
        if i >= chars.len() {
            return Err(fail(i, "count without a command letter".to_string()));
        }
        let letter = chars[i].to_ascii_uppercase();
        i += 1;
        let command = match letter {
            'L' => Command::L(count),
            'M' => Command::M(count),
            'K' => Command::K(count),
            'D' => Command::D(count),
            'Y' => Command::Y(count),
            'I' | 'S' | 'C' => {
                if has_count {
                    return Err(fail(i, format!("{letter} takes no count")));
                }
                let (text, ended) = text_arg(&chars, &mut i);
                match letter {
                    'I' => Command::I(text),
                    'S' if text.is_empty() => {
                        return Err(fail(i, "search text is empty".to_string()))
                    }
                    'S' => Command::S(text),
                    _ => {
                        if !ended {
                            return Err(fail(i, "C needs old$new: no $ after the old text".into()));
                        }
                        if text.is_empty() {
                            return Err(fail(i, "search text is empty".to_string()));
                        }
                        let (new, _) = text_arg(&chars, &mut i);
                        Command::C(text, new)
                    }
                }
            }
            other if is_blank(other) => {
                return Err(fail(i - 1, "count without a command letter".to_string()));
            }
            other => {
                return Err(fail(i, format!("unknown command {}", shown_char(other))));
            }
        };
        out.push(Typed {
            command,
            typed: chars[start..i].iter().collect(),
        });
    }
}

/// The most characters of typed text a message quotes; longer text is cut with `…`.
pub const QUOTE_CHARS: usize = 40;

/// Typed text for a message: control or invisible characters shown as `\u{..}`, cut once
/// `QUOTE_CHARS` characters are shown, with `…(N characters)`, so a message stays one short line.
pub fn cut(s: &str) -> String {
    let mut out = String::new();
    let mut width = 0;
    for c in s.chars() {
        let shown = if invisible(c) {
            format!("\\u{{{:x}}}", c as u32)
        } else {
            c.to_string()
        };
        width += shown.chars().count();
        if width > QUOTE_CHARS {
            out.push_str(&format!("…({} characters)", s.chars().count()));
            break;
        }
        out.push_str(&shown);
    }
    out
}

fn invisible(c: char) -> bool {
    c != ' '
        && (c.is_control()
            || c.is_whitespace()
            || matches!(c, '\u{feff}' | '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{206f}'))
}

/// A command letter for a message: `'Q'`, or `U+0000` for an invisible character.
fn shown_char(c: char) -> String {
    if invisible(c) {
        format!("U+{:04X}", c as u32)
    } else {
        format!("'{c}'")
    }
}

/// Parses a command line into commands.
pub fn parse(line: &str) -> Result<Vec<Command>, EditError> {
    Ok(parse_typed(line)?.into_iter().map(|t| t.command).collect())
}

/// Blanks (and a stray `$`, as in TECO) separate commands; they are literal inside text.
fn is_blank(c: char) -> bool {
    c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '$'
}

/// Reads a text argument from `chars[*i..]`; returns it and whether a `$` ended it.
fn text_arg(chars: &[char], i: &mut usize) -> (String, bool) {
    let mut text = String::new();
    while *i < chars.len() {
        let c = chars[*i];
        *i += 1;
        match c {
            '$' => return (text, true),
            '*' => text.push(EOB),
            '\\' if *i < chars.len() && matches!(chars[*i], '*' | '$' | '\\') => {
                text.push(chars[*i]);
                *i += 1;
            }
            _ => text.push(c),
        }
    }
    (text, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_take_sign_and_default() {
        assert_eq!(
            parse("L -L +3L -2L 0L 12m").unwrap(),
            vec![
                Command::L(1),
                Command::L(-1),
                Command::L(3),
                Command::L(-2),
                Command::L(0),
                Command::M(12)
            ]
        );
    }

    #[test]
    fn lowercase_commands_are_accepted() {
        assert_eq!(
            parse("2k-d y").unwrap(),
            vec![Command::K(2), Command::D(-1), Command::Y(1)]
        );
    }

    #[test]
    fn text_arguments_end_at_dollar_or_line_end() {
        assert_eq!(
            parse("IG01*$Sabc$CX1$X2$2L").unwrap(),
            vec![
                Command::I("G01\n".into()),
                Command::S("abc".into()),
                Command::C("X1".into(), "X2".into()),
                Command::L(2)
            ]
        );
        assert_eq!(parse("I a b ").unwrap(), vec![Command::I(" a b ".into())]);
        assert_eq!(
            parse("CX$").unwrap(),
            vec![Command::C("X".into(), String::new())]
        );
        assert_eq!(
            parse("CX$Y").unwrap(),
            vec![Command::C("X".into(), "Y".into())]
        );
    }

    #[test]
    fn backslash_takes_star_dollar_backslash_literally() {
        assert_eq!(
            parse(r"I\*\$\\\q$").unwrap(),
            vec![Command::I(r"*$\\q".into())]
        );
    }

    #[test]
    fn a_stray_dollar_between_commands_is_a_separator() {
        assert_eq!(
            parse("$IX$$ $L$").unwrap(),
            vec![Command::I("X".into()), Command::L(1)]
        );
    }

    #[test]
    fn empty_line_is_no_commands() {
        assert_eq!(parse("").unwrap(), vec![]);
        assert_eq!(parse("   ").unwrap(), vec![]);
    }

    #[test]
    fn bad_lines_name_the_command() {
        let e = parse("L 3Q").unwrap_err();
        assert_eq!((e.index, e.command.as_str()), (1, "3Q"));
        assert_eq!(e.to_string(), "command 2 '3Q': unknown command 'Q'");
        let e = parse("L S$").unwrap_err();
        assert_eq!(e.to_string(), "command 2 'S$': search text is empty");
        assert_eq!(
            parse("3").unwrap_err().reason,
            "count without a command letter"
        );
        assert_eq!(parse("3IX").unwrap_err().reason, "I takes no count");
        assert_eq!(
            parse("99999999999999999999L").unwrap_err().reason,
            "count too large: 99999999999999999999 (counts go from -9223372036854775808 to 9223372036854775807)"
        );
        assert!(parse("-9223372036854775809L")
            .unwrap_err()
            .reason
            .starts_with("count too small: -9223372036854775809"));
        assert!(parse("Cabc").unwrap_err().reason.contains("no $"));
        assert_eq!(parse("C$x").unwrap_err().reason, "search text is empty");
    }

    #[test]
    fn the_whole_64_bit_range_is_a_count() {
        assert_eq!(
            parse("-9223372036854775808M 9223372036854775807L -0D").unwrap(),
            vec![Command::M(i64::MIN), Command::L(i64::MAX), Command::D(0)]
        );
    }

    #[test]
    fn messages_cut_long_text_and_show_control_characters() {
        let e = parse("\u{0}").unwrap_err();
        assert_eq!(e.reason, "unknown command U+0000");
        let long = format!("{}L", "9".repeat(100_000));
        let r = parse(&long).unwrap_err().reason;
        assert!(r.len() < 200, "{r}");
        assert!(r.contains("…(100000 characters)"), "{r}");
        assert_eq!(cut("a\u{7}b"), "a\\u{7}b");
        // Found by the fuzz command (editor:0x16ac78ff448fc923): escapes counted as one
        // character each made a 700-character message; the cut counts what is shown.
        let mut b = crate::Buffer::from_text("x\n");
        let line = format!("S{}", "\u{200b}\n\t".repeat(150));
        let e = b
            .execute(&line, &crate::ExecOptions::default())
            .unwrap_err();
        assert!(e.to_string().len() < 200, "{e}");
        let shown = cut(&"\u{200b}".repeat(100));
        assert_eq!(shown, format!("{}…(100 characters)", "\\u{200b}".repeat(5)));
    }

    #[test]
    fn non_ascii_never_panics() {
        assert_eq!(parse("Iñé€*").unwrap(), vec![Command::I("ñé€\n".into())]);
        assert!(parse("é").is_err());
        assert!(parse("3€").is_err());
    }
}
