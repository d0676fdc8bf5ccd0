//! The tool file as text, for TOOL DATA REVISION: one line per T code, in T-code order.
//!
//! ```text
//! T01 00610  BB     40.0    220.0     80.0   400.0    60.0    25.0
//! T20 00108                          (tool assigned, no data read yet)
//! T21                                (empty pocket)
//! ```
//!
//! A line is `Tnn`, then the tape record (docs/stores.md field order) of the tool the T-code table puts
//! in that pocket. The validator refuses any result that adds, removes, reorders or renumbers a
//! line, that is not a valid record, or whose tool number is not the one the T-code table
//! assigns (that is changed in T-CODE SETTING).

use crate::tooldata::{format_record, parse_record, Magazine, TCodeTable, ToolFile, ToolRecord};

/// One line of the tool file, formatted.
pub fn format_line(t: u32, tool: Option<u32>, rec: Option<&ToolRecord>) -> String {
    match (tool, rec) {
        (Some(n), Some(r)) if r.number == n => format!("T{t:02} {}", format_record(r)),
        (Some(n), _) => format!("T{t:02} {n:05}"),
        (None, _) => format!("T{t:02}"),
    }
}

/// The whole tool file as text: one line per T code, each ended by an end of block.
pub fn tool_text(m: &Magazine) -> String {
    let mut s = String::new();
    for t in 1..=m.tcodes.capacity() {
        s.push_str(&format_line(t, m.tcodes.tool_in(t), m.tools.get(t)));
        s.push('\n');
    }
    s
}

/// The tool file as text, keeping each line of `old` (its spacing as typed) whose tool and data
/// are unchanged in `m`; only the lines that changed are formatted anew (docs/stores.md).
pub fn tool_text_keeping(old: &str, m: &Magazine) -> String {
    let mut old_lines = old.split_terminator('\n');
    let mut s = String::new();
    for t in 1..=m.tcodes.capacity() {
        let tool = m.tcodes.tool_in(t);
        let rec = m.tools.get(t).filter(|r| Some(r.number) == tool);
        match old_lines.next() {
            Some(line) if parse_line(t, line) == Ok((tool, rec.cloned())) => s.push_str(line),
            _ => s.push_str(&format_line(t, tool, rec)),
        }
        s.push('\n');
    }
    s
}

/// What one line says: the tool number and, if given, its data.
type Line = (Option<u32>, Option<ToolRecord>);

/// Parses the line for T code `t` (without its end of block).
fn parse_line(t: u32, line: &str) -> Result<Line, String> {
    let want = format!("T{t:02}");
    let mut fields = line.split_whitespace();
    let head = fields.next().unwrap_or("");
    let head_t = head
        .strip_prefix('T')
        .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|d| d.parse::<u32>().ok());
    if head_t != Some(t) {
        return Err(format!(
            "line {t} must start with {want} (found {}); lines cannot be renumbered or reordered",
            crate::input_text::quote(head)
        ));
    }
    if line.contains(';') {
        return Err(format!("{want}: comments are not kept in the tool file"));
    }
    let rest: Vec<&str> = fields.collect();
    match rest.len() {
        0 => Ok((None, None)),
        1 => {
            let no = rest[0];
            let n = no
                .parse::<u32>()
                .ok()
                .filter(|&n| n > 0 && no.len() <= 5 && no.bytes().all(|b| b.is_ascii_digit()))
                .ok_or_else(|| format!("{want}: tool number '{no}' is not 1 to 5 digits"))?;
            Ok((Some(n), None))
        }
        _ => {
            let r = parse_record(&rest.join(" ")).map_err(|m| format!("{want}: {m}"))?;
            Ok((Some(r.number), Some(r)))
        }
    }
}

/// Checks tool-file text against the T-code table and returns the tool file it describes.
/// This is the TOOL DATA REVISION validator: the error is the operator's message.
pub fn parse_tool_text(text: &str, tcodes: &TCodeTable) -> Result<ToolFile, String> {
    let cap = tcodes.capacity();
    if !text.is_empty() && !text.ends_with('\n') {
        return Err(format!(
            "the last line (T{cap:02}) lost its end of block; lines cannot be joined"
        ));
    }
    let lines: Vec<&str> = text.split_terminator('\n').collect();
    let n = lines.len() as u32;
    if n > cap {
        return Err(format!(
            "the tool file has one line per T code (T01 to T{cap:02}); a line cannot be added"
        ));
    }
    let mut tools = ToolFile::new(cap);
    for (i, line) in lines.iter().enumerate() {
        let t = i as u32 + 1;
        let (tool, rec) = parse_line(t, line)?;
        match (tcodes.tool_in(t), tool) {
            (Some(a), Some(b)) if a != b => {
                return Err(format!(
                    "T{t:02} holds tool {a:05}, not {b:05}; change it in T-CODE SETTING"
                ))
            }
            (Some(a), None) => {
                return Err(format!(
                    "T{t:02} holds tool {a:05}; a pocket is emptied in T-CODE SETTING"
                ))
            }
            (None, Some(b)) => {
                return Err(format!(
                    "T{t:02} is an empty pocket; assign tool {b:05} to it in T-CODE SETTING"
                ))
            }
            _ => {}
        }
        tools.set(t, rec);
    }
    if n < cap {
        return Err(format!(
            "the tool file has one line per T code (T01 to T{cap:02}); a line cannot be removed"
        ));
    }
    Ok(tools)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tooldata::sample_magazine;

    #[test]
    fn sample_round_trips() {
        let m = sample_magazine();
        let text = tool_text(&m);
        assert_eq!(text.lines().count(), 24);
        assert!(text.starts_with("T01 00610  BB"), "{text}");
        assert!(text.contains("\nT21\n"));
        let tools = parse_tool_text(&text, &m.tcodes).unwrap();
        assert_eq!(tools, m.tools);
    }

    #[test]
    fn only_changed_lines_are_formatted_anew() {
        let mut m = sample_magazine();
        let text = tool_text(&m);
        let typed = text.replacen(
            text.lines().nth(1).unwrap(),
            "T02 00106 DR 6.2 150 40 1200 120 3",
            1,
        );
        assert_eq!(tool_text_keeping(&typed, &m), typed);
        m.tcodes.assign(21, Some(999)).unwrap();
        m.tools.set(1, None);
        let got = tool_text_keeping(&typed, &m);
        let want = typed
            .replacen(text.lines().next().unwrap(), "T01 00610", 1)
            .replacen("\nT21\n", "\nT21 00999\n", 1);
        assert_eq!(got, want);
    }

    #[test]
    fn refuses_bad_lines_with_reasons() {
        let m = sample_magazine();
        let text = tool_text(&m);
        let t = &m.tcodes;
        let swap = text.replacen("T02 00106", "T02 00107", 1);
        assert_eq!(
            parse_tool_text(&swap, t).unwrap_err(),
            "T02 holds tool 00106, not 00107; change it in T-CODE SETTING"
        );
        let bad = text.replacen("T02 00106  DR", "T02 00106  XX", 1);
        assert!(parse_tool_text(&bad, t)
            .unwrap_err()
            .starts_with("T02: unknown tool kind 'XX'"));
        let extra = format!("{text}T25\n");
        assert!(parse_tool_text(&extra, t)
            .unwrap_err()
            .contains("cannot be added"));
        let fewer = text.replacen("T21\n", "", 1);
        assert!(parse_tool_text(&fewer, t).unwrap_err().contains("T21"));
        let filled = text.replacen("T21\n", "T21 00999\n", 1);
        assert_eq!(
            parse_tool_text(&filled, t).unwrap_err(),
            "T21 is an empty pocket; assign tool 00999 to it in T-CODE SETTING"
        );
        let joined = text.trim_end_matches('\n');
        assert!(parse_tool_text(joined, t)
            .unwrap_err()
            .contains("end of block"));
        // Dropping the data of a tool leaves it assigned with no data: allowed.
        let line = text.lines().nth(1).unwrap();
        let nodata = text.replacen(line, "T02 00106", 1);
        let tools = parse_tool_text(&nodata, t).unwrap();
        assert!(tools.get(2).is_none());
    }
}
