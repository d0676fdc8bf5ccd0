//! The snapshot file `state.snap`: the whole state at one journal generation, as framed
//! records (see `frame`). Records, in order:
//!
//! ```text
//! novanc-state 1 GEN CAPACITY     header: format version, generation, magazine capacity
//! current NAME                    the current program
//! program NAME POINTER\n<text>    one per program in program memory
//! mdi POINTER\n<text>             the MDI buffer
//! tcodes\n<text>                  the T-code table, one `Tnn TOOLNO` per line
//! tools POINTER\n<text>           the tool file, one T code per line
//! end                             written last: a snapshot without it is incomplete
//! ```

use super::frame;
use super::state::{set_pointer, State};
use super::toolfile::parse_tool_text;
use crate::tooldata::parse_tcodes;
use novanc_editor::Buffer;
use std::collections::BTreeMap;

/// The snapshot of `s` at generation `gen`, as file bytes.
pub fn encode(s: &State, gen: u64) -> Vec<u8> {
    let mut out = Vec::new();
    let mut put = |p: String| out.extend(frame::encode(p.as_bytes()));
    put(format!("novanc-state 1 {gen} {}", s.tcodes.capacity()));
    put(format!("current {}", s.current));
    for (name, b) in &s.programs {
        put(format!("program {name} {}\n{}", b.pointer(), b.text()));
    }
    put(format!("mdi {}\n{}", s.mdi.pointer(), s.mdi.text()));
    put(format!("tcodes\n{}", s.tcodes.to_text()));
    put(format!(
        "tools {}\n{}",
        s.tool_buf.pointer(),
        s.tool_buf.text()
    ));
    put("end".to_string());
    out
}

/// A buffer holding `text` with its pointer at `p`.
fn buffer_at(text: &str, p: &str) -> Result<Buffer, String> {
    let p: usize = p.parse().map_err(|_| format!("bad pointer '{p}'"))?;
    let mut b = Buffer::from_text(text);
    set_pointer(&mut b, p);
    Ok(b)
}

/// Reads a snapshot: (generation, capacity, state). Any damage is an error saying what.
pub fn decode(data: &[u8]) -> Result<(u64, u32, State), String> {
    let d = frame::decode(data);
    if let Some(dmg) = &d.damage {
        return Err(format!(
            "record {} at byte {}: {}",
            dmg.record + 1,
            dmg.offset,
            dmg.reason
        ));
    }
    let mut recs = d.records.iter().map(|r| std::str::from_utf8(r));
    let head = recs
        .next()
        .ok_or("the file is empty")?
        .map_err(|_| "the header is not text")?;
    let h: Vec<&str> = head.split(' ').collect();
    let (gen, cap) = match h.as_slice() {
        ["novanc-state", "1", g, c] => (
            g.parse::<u64>().map_err(|_| "bad generation")?,
            c.parse::<u32>()
                .ok()
                .filter(|&c| c >= 1)
                .ok_or("bad capacity")?,
        ),
        _ => return Err(format!("not a novanc state file (header '{head}')")),
    };
    let mut programs = BTreeMap::new();
    let (mut current, mut mdi, mut tcodes, mut tools, mut end) = (None, None, None, None, false);
    for r in recs {
        let r = r.map_err(|_| "a record is not text")?;
        let (head, body) = r.split_once('\n').unwrap_or((r, ""));
        let f: Vec<&str> = head.split(' ').collect();
        match f.as_slice() {
            ["current", n] => current = Some(n.to_string()),
            ["program", n, p] => {
                programs.insert(n.to_string(), buffer_at(body, p)?);
            }
            ["mdi", p] => mdi = Some(buffer_at(body, p)?),
            ["tcodes"] => {
                tcodes = Some(
                    parse_tcodes(body, "state.snap", cap)
                        .map_err(|e| format!("T-code table: {}", e.message))?,
                )
            }
            ["tools", p] => tools = Some((body.to_string(), p.to_string())),
            ["end"] => end = true,
            _ => return Err(format!("unknown record '{head}'")),
        }
    }
    if !end {
        return Err("the file is incomplete (no end record)".to_string());
    }
    let current = current.ok_or("no current program")?;
    if !programs.contains_key(&current) {
        return Err(format!("current program {current} is missing"));
    }
    let tcodes = tcodes.ok_or("no T-code table")?;
    let (ttext, tp) = tools.ok_or("no tool file")?;
    let tool_file = parse_tool_text(&ttext, &tcodes).map_err(|e| format!("tool file: {e}"))?;
    let s = State {
        programs,
        current,
        mdi: mdi.ok_or("no MDI buffer")?,
        tool_buf: buffer_at(&ttext, &tp)?,
        tcodes,
        tools: tool_file,
    };
    Ok((gen, cap, s))
}
