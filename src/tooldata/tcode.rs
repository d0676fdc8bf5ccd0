//! The T-code table: which tool number sits in which magazine pocket (T code).
//! File format: one `Tnn TOOLNO` per line, `;` or `#` comments. Two T codes never hold the
//! same tool.

use super::tape::TapeError;

/// Tool numbers by T code, pockets 1..=capacity.
#[derive(Clone, Debug, PartialEq)]
pub struct TCodeTable {
    slots: Vec<Option<u32>>,
}

impl TCodeTable {
    /// An empty table of `capacity` pockets.
    pub fn new(capacity: u32) -> TCodeTable {
        TCodeTable {
            slots: vec![None; capacity as usize],
        }
    }

    /// Number of pockets.
    pub fn capacity(&self) -> u32 {
        self.slots.len() as u32
    }

    /// The tool number in T code `t`.
    pub fn tool_in(&self, t: u32) -> Option<u32> {
        let i = (t as usize).checked_sub(1)?;
        *self.slots.get(i)?
    }

    /// The T code holding tool number `tool`.
    pub fn tcode_of(&self, tool: u32) -> Option<u32> {
        self.slots
            .iter()
            .position(|s| *s == Some(tool))
            .map(|i| i as u32 + 1)
    }

    /// Assigns `tool` to T code `t` (None unassigns). Refuses a pocket outside the magazine,
    /// a tool number outside 1..=99999, and a tool already held by another T code.
    pub fn assign(&mut self, t: u32, tool: Option<u32>) -> Result<(), String> {
        let cap = self.capacity();
        if t == 0 || t > cap {
            return Err(format!(
                "T{t:02} is not a pocket (the magazine has T01 to T{cap:02})"
            ));
        }
        if let Some(n) = tool {
            if n == 0 || n > 99_999 {
                return Err(format!("tool number {n} is not 1 to 5 digits"));
            }
            if let Some(other) = self.tcode_of(n) {
                if other != t {
                    return Err(format!("tool {n:05} is already in T{other:02}"));
                }
            }
        }
        self.slots[(t - 1) as usize] = tool;
        Ok(())
    }

    /// (T code, tool number) for every assigned pocket, in T-code order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.map(|n| (i as u32 + 1, n)))
    }

    /// The table as file text, one `Tnn TOOLNO` per assigned pocket.
    pub fn to_text(&self) -> String {
        self.iter()
            .map(|(t, n)| format!("T{t:02} {n:05}\n"))
            .collect()
    }
}

/// Parses a T-code table file for a magazine of `capacity` pockets.
pub fn parse_tcodes(text: &str, file: &str, capacity: u32) -> Result<TCodeTable, TapeError> {
    let mut table = TCodeTable::new(capacity);
    for (i, raw) in crate::input_text::tape_lines(text).enumerate() {
        let line = (i + 1) as u32;
        let err = |message: String| TapeError {
            file: file.to_string(),
            line,
            message,
        };
        let body = raw.split([';', '#']).next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let fields: Vec<&str> = body.split_whitespace().collect();
        if fields.len() != 2 {
            return Err(err(format!(
                "expected 'Tnn TOOLNO', found {}",
                crate::input_text::quote(body)
            )));
        }
        let t = fields[0]
            .strip_prefix(['T', 't'])
            .filter(|d| d.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|d| d.parse::<u32>().ok())
            .ok_or_else(|| {
                err(format!(
                    "{} is not a T code like T05",
                    crate::input_text::quote(fields[0])
                ))
            })?;
        let n = fields[1]
            .parse::<u32>()
            .ok()
            .filter(|_| fields[1].len() <= 5 && fields[1].bytes().all(|b| b.is_ascii_digit()))
            .ok_or_else(|| {
                err(format!(
                    "{} is not a tool number of 1 to 5 digits",
                    crate::input_text::quote(fields[1])
                ))
            })?;
        if table.tool_in(t).is_some() {
            return Err(err(format!("T{t:02} is assigned twice")));
        }
        table.assign(t, Some(n)).map_err(err)?;
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_refuses_duplicates() {
        let t = parse_tcodes("# m\nT01 00106\nT02 208 ; tap\n", "m.tc", 24).unwrap();
        assert_eq!(t.tcode_of(208), Some(2));
        assert_eq!(t.tool_in(1), Some(106));
        let e = parse_tcodes("T01 106\nT02 106\n", "m.tc", 24).unwrap_err();
        assert_eq!(e.to_string(), "m.tc:2: tool 00106 is already in T01");
        let e = parse_tcodes("T25 106\n", "m.tc", 24).unwrap_err();
        assert!(e.message.contains("not a pocket"));
    }
}
