//! T-CODE SETTING at the data keys: assign tool numbers to T codes (magazine pockets), or
//! T codes to tool numbers (patent lines 197–203; docs/stores.md).
//!
//! Command lines (one per EOB):
//! - `T5=206` (or `T05 206`): pocket T5 holds tool 206. Refused if another pocket holds it.
//! - `T5=` or `T5=0`: pocket T5 is emptied.
//! - `206=T5`: tool 206 goes to pocket T5, leaving the pocket it was in.

use super::Console;

/// One T-code setting command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// Pocket `t` holds `tool` (None: empty).
    Pocket { t: u32, tool: Option<u32> },
    /// Tool `tool` moves to pocket `t`.
    Tool { tool: u32, t: u32 },
}

/// Parses `Tn=tool`, `Tn tool`, `Tn=`, `tool=Tn`.
pub fn parse(line: &str) -> Result<Setting, String> {
    let l = line.trim().to_ascii_uppercase();
    let (a, b) = match l.split_once('=') {
        Some((a, b)) => (a.trim().to_string(), b.trim().to_string()),
        None => match l.split_once(char::is_whitespace) {
            Some((a, b)) => (a.trim().to_string(), b.trim().to_string()),
            None => (l.clone(), String::new()),
        },
    };
    let tcode = |s: &str| -> Option<u32> { s.strip_prefix('T')?.parse().ok() };
    let tool = |s: &str| -> Result<u32, String> {
        let n: u32 = s
            .parse()
            .map_err(|_| format!("'{s}' is not a tool number"))?;
        if n == 0 || n > 99_999 {
            return Err(format!("tool number {s} is not 1 to 99999"));
        }
        Ok(n)
    };
    if let Some(t) = tcode(&a) {
        let tool = if b.is_empty() || b.chars().all(|c| c == '0') {
            None
        } else {
            Some(tool(&b)?)
        };
        return Ok(Setting::Pocket { t, tool });
    }
    if let Some(t) = tcode(&b) {
        return Ok(Setting::Tool { tool: tool(&a)?, t });
    }
    Err(format!(
        "'{}' is not a T-code setting: type T5=206, T5= or 206=T5",
        line.trim()
    ))
}

/// A command line entered in T-CODE SETTING.
pub(super) fn enter(c: &mut Console, line: &str) -> Result<(), String> {
    let set = parse(line)?;
    let cap = c.cfg.settings.magazine_capacity;
    let t = match set {
        Setting::Pocket { t, .. } | Setting::Tool { t, .. } => t,
    };
    if t == 0 || t > cap {
        return Err(format!("T{t} refused: the magazine has T01 to T{cap:02}"));
    }
    let result = match set {
        Setting::Pocket { t, tool } => c.mem.set_tcode(t, tool),
        Setting::Tool { tool, t } => c.mem.assign_tool(tool, t),
    };
    result.map_err(|e| format!("refused: {e}"))?;
    c.tool_focus = t;
    let m = c.mem.magazine();
    c.shell.front.message = match m.tcodes.tool_in(t) {
        Some(n) => match m.tools.get(t) {
            Some(r) if r.number == n => format!("T{t:02} holds tool {n:05}"),
            _ => format!("T{t:02} holds tool {n:05}: read its data (TOOL DATA READ)"),
        },
        None => format!("T{t:02} is empty"),
    };
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_both_directions() {
        assert_eq!(
            parse("T5=206").unwrap(),
            Setting::Pocket {
                t: 5,
                tool: Some(206)
            }
        );
        assert_eq!(
            parse("t05 00206").unwrap(),
            Setting::Pocket {
                t: 5,
                tool: Some(206)
            }
        );
        assert_eq!(parse("T5=").unwrap(), Setting::Pocket { t: 5, tool: None });
        assert_eq!(parse("206=T7").unwrap(), Setting::Tool { tool: 206, t: 7 });
        assert!(parse("hello").unwrap_err().contains("not a T-code setting"));
        assert!(parse("T5=123456").unwrap_err().contains("1 to 99999"));
    }
}
