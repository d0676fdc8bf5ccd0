//! The tool tape: one record per line, `TOOLNO KIND DIAMETER SETLEN EFFLEN SPEED FEED DEPTH`,
//! with `;` comments (patent Fig. 8: a 5-digit tool number heads each CR-separated record).

use super::{ToolKind, ToolRecord};
use crate::input_text::{number as language_number, quote, tape_lines};
use std::collections::HashSet;
use std::fmt;

/// A bad tool tape record: `FILE:LINE: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct TapeError {
    /// Tape file name as given.
    pub file: String,
    /// 1-based line of the record.
    pub line: u32,
    /// What is wrong, in the operator's words.
    pub message: String,
}

impl fmt::Display for TapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.message)
    }
}

impl std::error::Error for TapeError {}

/// Parses one record (no comment, not blank). The error is the message alone. Each number is
/// read as the part-program language reads it (`input_text::number`: digits with at most
/// one decimal point, no exponent, at most 1,000,000,000), so a tape holds nothing a part
/// program could not write.
pub fn parse_record(text: &str) -> Result<ToolRecord, String> {
    let text = text.split(';').next().unwrap_or("");
    let fields: Vec<&str> = text.split_whitespace().collect();
    if fields.len() != 8 && fields.len() != 10 {
        return Err(format!(
            "a tool record has 8 fields (TOOLNO KIND DIAMETER SETLEN EFFLEN SPEED FEED DEPTH), and the tool file may add the wear (WEARLEN WEARDIA), this one has {}",
            fields.len()
        ));
    }
    let no = fields[0];
    if no.is_empty() || no.len() > 5 || !no.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!("tool number {} is not 1 to 5 digits", quote(no)));
    }
    let number: u32 = no.parse().map_err(|_| format!("bad tool number '{no}'"))?;
    if number == 0 {
        return Err("tool number 00000 is not a tool".to_string());
    }
    let kind = ToolKind::from_code(fields[1]).ok_or_else(|| {
        format!(
            "unknown tool kind {} (kinds: DR CD TP RM EM FM BB)",
            quote(fields[1])
        )
    })?;
    let names = [
        "diameter",
        "set length",
        "effective length",
        "spindle speed",
        "feed rate",
        "normal depth",
    ];
    let mut v = [0.0f64; 6];
    for (i, name) in names.iter().enumerate() {
        let s = fields[2 + i];
        let x = language_number(s).map_err(|e| format!("{name} {e}"))?;
        if x < 0.0 {
            return Err(format!("{name} {s} is negative"));
        }
        v[i] = x;
    }
    if v[0] <= 0.0 {
        return Err(format!("diameter {} must be greater than 0", fields[2]));
    }
    let mut wear = [0.0f64; 2];
    for (i, name) in ["length wear", "diameter wear"].iter().enumerate() {
        let Some(s) = fields.get(8 + i) else { break };
        let x = language_number(s).map_err(|e| format!("{name} {e}"))?;
        if x.abs() > super::MAX_WEAR_MM {
            return Err(format!(
                "{name} {s} is more than {} mm either way",
                super::MAX_WEAR_MM
            ));
        }
        wear[i] = x;
    }
    if v[0] + wear[1] <= 0.0 {
        return Err(format!(
            "the diameter wear {} leaves no diameter (diameter {})",
            fields[9], fields[2]
        ));
    }
    Ok(ToolRecord {
        number,
        kind,
        diameter: v[0],
        set_length: v[1],
        effective_length: v[2],
        speed: v[3],
        feed: v[4],
        depth: v[5],
        wear_length: wear[0],
        wear_diameter: wear[1],
    })
}

/// Parses a whole tape. Any bad record fails the whole tape, with the first error. Records end
/// with CR, CR LF or LF (the patent's tape separates records with CR); a leading byte order
/// mark is skipped. Numbers are read as the part-program language reads them.
pub fn parse_tape(text: &str, file: &str) -> Result<Vec<ToolRecord>, TapeError> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for (i, raw) in tape_lines(text).enumerate() {
        let line = (i + 1) as u32;
        let body = raw.split(';').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let rec = parse_record(body).map_err(|message| TapeError {
            file: file.to_string(),
            line,
            message,
        })?;
        if !seen.insert(rec.number) {
            return Err(TapeError {
                file: file.to_string(),
                line,
                message: format!("duplicate tool number {:05}", rec.number),
            });
        }
        out.push(rec);
    }
    Ok(out)
}

/// Formats a record as one tape line, in the column layout of the sample tape.
pub fn format_record(r: &ToolRecord) -> String {
    let mut s = format!(
        "{:05}  {}  {:>7}  {:>7}  {:>7}  {:>6}  {:>6}  {:>6}",
        r.number,
        r.kind.code(),
        num(r.diameter),
        num(r.set_length),
        num(r.effective_length),
        num(r.speed),
        num(r.feed),
        num(r.depth)
    );
    if r.wear_length != 0.0 || r.wear_diameter != 0.0 {
        s.push_str(&format!(
            "  {:>6}  {:>6}",
            num(r.wear_length),
            num(r.wear_diameter)
        ));
    }
    s
}

/// A number with at least one decimal and no more than it needs to read back as the same
/// value: `150.0`, `6.2`, `0.0004` (a tape value with more than 3 decimals is kept, not rounded,
/// so the tool file, which is kept as this text, holds what the tape held).
fn num(x: f64) -> String {
    if x.fract() == 0.0 {
        format!("{x:.1}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_spec_example() {
        let r = parse_record("00106  DR   6.2      150.0  40.0   1200  120  3.0").unwrap();
        assert_eq!(r.number, 106);
        assert_eq!(r.kind, ToolKind::Drill);
        assert_eq!(r.set_length, 150.0);
        assert_eq!(parse_record(&format_record(&r)).unwrap(), r);
    }

    /// Found by the fuzz command (tape:0xd4262d85334ed688): a diameter of 0.0004 printed as
    /// `0.0`, which does not read back, so the tool file could not be revised.
    #[test]
    fn every_value_prints_so_that_it_reads_back_the_same() {
        let r = parse_record("00001 CD 0.0004 1453 369.119 139.47 145.5049 0.1234567").unwrap();
        let line = format_record(&r);
        assert_eq!(
            line,
            "00001  CD   0.0004   1453.0  369.119  139.47  145.5049  0.1234567"
        );
        assert_eq!(parse_record(&line).unwrap(), r);
    }

    #[test]
    fn rejects_bad_records_with_line() {
        let e = parse_tape(
            "; c\n00106 DR 6.2 150 40 1200 120 3\n00107 XX 1 1 1 1 1 1\n",
            "t.tt",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.tt:3: unknown tool kind 'XX' (kinds: DR CD TP RM EM FM BB)"
        );
        let e = parse_tape("00106 DR 6.2 150 40 1200 120\n", "t").unwrap_err();
        assert!(e.message.contains("8 fields"), "{e}");
        let e = parse_tape("00106 DR 6.2 -150 40 1200 120 3\n", "t").unwrap_err();
        assert!(e.message.contains("negative"), "{e}");
        let e = parse_tape("00106 DR 6.2 abc 40 1200 120 3\n", "t").unwrap_err();
        assert!(e.message.contains("not a number"), "{e}");
        let e = parse_tape("00106 DR 6 1 1 1 1 1\n00106 DR 6 1 1 1 1 1\n", "t").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("duplicate"), "{e}");
    }
}
