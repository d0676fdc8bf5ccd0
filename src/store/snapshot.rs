//! The snapshot file `state.snap`: the whole state at one journal generation, as framed
//! records (see `frame`), each written twice in a row (format 2). Records, in order:
//!
//! ```text
//! novanc-state 2 GEN CAPACITY     header: format version, generation, magazine capacity
//! current NAME                    the current program
//! program NAME POINTER [DIALECT]\n<text>
//!                                 one per program in program memory; DIALECT (`fanuc`,
//!                                 `linuxcnc`) the one it was stored in, absent when not
//!                                 recorded (written before programs kept it)
//! mdi POINTER\n<text>             the MDI buffer
//! tcodes\n<text>                  the T-code table, one `Tnn TOOLNO` per line
//! tools POINTER\n<text>           the tool file, one T code per line
//! params\n<text>                  the G-code interpreter's persistent parameters, one `N V`
//!                                 line each (V in millionths), those not zero; written only
//!                                 when there is one
//! offsets\n<text>                 (read only, from before `params`) G54..G59, one `X Y Z`
//!                                 line each in nanometres
//! end                             written last: a snapshot without it is incomplete
//! ```
//!
//! Format 1 (one copy of each record) is still read. Reading salvages what it can from a
//! snapshot damaged in both copies of a record, and says what was lost (docs/stores.md
//! "Damage").

use super::frame;
use super::record::EditTarget;
use super::state::{set_pointer, tape_text, Base, State, TABLEB};
use super::toolfile::{parse_tool_text, tool_text};
use crate::tooldata::{parse_tcodes, Magazine, TCodeTable, ToolFile};
use novanc_editor::Buffer;
use std::collections::BTreeMap;

/// The snapshot of `s` at generation `gen`, as file bytes (format 2: every record twice).
pub fn encode(s: &State, gen: u64) -> Vec<u8> {
    if let Some(l) = &s.lathe {
        return super::lathe::encode_snapshot(l, gen);
    }
    let mut out = Vec::new();
    let mut put = |p: String| out.extend(frame::encode_pair(p.as_bytes()));
    put(format!("novanc-state 2 {gen} {}", s.tcodes.capacity()));
    put(format!("current {}", s.current));
    for (name, b) in &s.programs {
        let dialect = s.dialects.get(name).map_or("", |d| d.name());
        let sep = if dialect.is_empty() { "" } else { " " };
        put(format!(
            "program {name} {}{sep}{dialect}\n{}",
            b.pointer(),
            b.text()
        ));
    }
    put(format!("mdi {}\n{}", s.mdi.pointer(), s.mdi.text()));
    put(format!("tcodes\n{}", s.tcodes.to_text()));
    put(format!(
        "tools {}\n{}",
        s.tool_buf.pointer(),
        s.tool_buf.text()
    ));
    if !s.params.is_empty() {
        let lines: Vec<String> = s.params.iter().map(|(n, v)| format!("{n} {v}")).collect();
        put(format!("params\n{}", lines.join("\n")));
    }
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

/// What reading a snapshot found.
#[derive(Debug)]
pub struct SnapRead {
    /// The generation in the header (None if the header could not be read).
    pub gen: Option<u64>,
    /// The state read (whole, or salvaged around damage).
    pub state: State,
    /// Whether the file is format 1 (records not written twice).
    pub old_format: bool,
    /// Damaged copies whose other copy was used (nothing lost), e.g. `record 3 at byte 120:
    /// record checksum does not match`.
    pub repaired: Vec<String>,
    /// Damage nothing could make good, then what was lost or rebuilt because of it.
    pub lost: Vec<String>,
    /// Whether no record at all could be read (the state is the embedded defaults).
    pub nothing: bool,
    /// Buffers that hold a stand-in for what was lost (journal edits of them cannot be
    /// replayed).
    pub stand_ins: Vec<EditTarget>,
}

/// `record N at byte X: reason` for a damaged record.
fn where_(d: &frame::Damage) -> String {
    format!("record {} at byte {}: {}", d.record + 1, d.offset, d.reason)
}

/// The T-code table a tool-file text describes (each line `Tnn TOOLNO ...`).
fn tcodes_from_tool_text(text: &str, capacity: u32) -> TCodeTable {
    let mut tc = TCodeTable::new(capacity);
    for (i, line) in text.lines().enumerate() {
        if let Some(n) = line.split_whitespace().nth(1).and_then(|n| n.parse().ok()) {
            let _ = tc.assign(i as u32 + 1, Some(n));
        }
    }
    tc
}

/// Reads the snapshot of the store `base` says: the centre's (`read`) or a lathe's
/// (`lathe::read_snapshot`, its state put in a `SnapRead` with nothing of the centre's).
pub fn read_base(data: &[u8], base: &Base) -> SnapRead {
    match base {
        Base::Centre(capacity) => read(data, *capacity),
        Base::Lathe(l) => {
            let r = super::lathe::read_snapshot(data, l);
            SnapRead {
                gen: r.gen,
                state: State::lathe(r.state),
                old_format: false,
                repaired: r.repaired,
                lost: r.lost,
                nothing: r.nothing,
                stand_ins: Vec::new(),
            }
        }
    }
}

/// Reads a snapshot. Never fails: damage in one copy of a record is made good by the other;
/// damage in both is reported in `lost`, and the state is salvaged from the records that read
/// (a missing MDI buffer is empty, a missing T-code table is rebuilt from the tool file, ...).
/// `capacity` is used when the header cannot be read.
pub fn read(data: &[u8], capacity: u32) -> SnapRead {
    let old_format = frame::first_record(data).is_some_and(|r| r.starts_with(b"novanc-state 1 "));
    let mut repaired = Vec::new();
    let mut lost = Vec::new();
    let records: Vec<&[u8]> = if old_format {
        let d = frame::decode(data);
        if let Some(dmg) = &d.damage {
            lost.push(format!(
                "{} (format 1 keeps one copy; nothing after it could be read)",
                where_(dmg)
            ));
        }
        d.records
    } else {
        let d = frame::decode_paired(data);
        repaired.extend(d.repaired.iter().map(where_));
        if let Some(dmg) = &d.damage {
            let after = if d.after.is_empty() {
                "nothing after it could be read".to_string()
            } else {
                format!("{} records after it were read", d.after.len())
            };
            lost.push(format!("{}, in both copies; {after}", where_(dmg)));
        }
        let mut r = d.records;
        r.extend(d.after);
        r
    };
    let damaged = !lost.is_empty();
    let nothing = records.is_empty();
    let mut gen = None;
    let mut cap = capacity;
    let mut programs = BTreeMap::new();
    let (mut current, mut mdi, mut tcodes_text, mut tools, mut end) =
        (None, None, None, None, false);
    let mut params = BTreeMap::new();
    let mut dialects = BTreeMap::new();
    for r in &records {
        let Ok(r) = std::str::from_utf8(r) else {
            lost.push("a record that is not text".to_string());
            continue;
        };
        let (head, body) = r.split_once('\n').unwrap_or((r, ""));
        let f: Vec<&str> = head.split(' ').collect();
        match f.as_slice() {
            ["novanc-state", "1" | "2", g, c] if gen.is_none() => {
                match (g.parse::<u64>(), c.parse::<u32>()) {
                    (Ok(g), Ok(c)) if c >= 1 => {
                        gen = Some(g);
                        cap = c;
                    }
                    _ => lost.push(format!("the header '{head}' does not read")),
                }
            }
            ["current", n] => current = Some(n.to_string()),
            ["program", n, p, d @ ..] if d.len() <= 1 => {
                let dialect = match d.first() {
                    None => Ok(None),
                    Some(d) => crate::settings::Dialect::parse(d).map(Some),
                };
                match (buffer_at(body, p), dialect) {
                    (Ok(b), Ok(d)) => {
                        programs.insert(n.to_string(), b);
                        if let Some(d) = d {
                            dialects.insert(n.to_string(), d);
                        }
                    }
                    (Err(e), _) | (_, Err(e)) => lost.push(format!("program {n} ({e})")),
                }
            }
            ["mdi", p] => match buffer_at(body, p) {
                Ok(b) => mdi = Some(b),
                Err(e) => lost.push(format!("the MDI buffer record ({e})")),
            },
            ["tcodes"] => tcodes_text = Some(body.to_string()),
            ["tools", p] => tools = Some((body.to_string(), p.to_string())),
            ["params"] => match read_params(body) {
                Some(p) => params.extend(p),
                None => lost.push(
                    "the interpreter's parameters (work offsets, G92, G28/G30 homes: now all zero)"
                        .to_string(),
                ),
            },
            ["offsets"] => match read_offsets(body) {
                Some(p) => params.extend(p),
                None => lost.push("the work offsets (now all zero)".to_string()),
            },
            ["end"] => end = true,
            _ => lost.push(format!("an unknown record '{head}'")),
        }
    }
    if nothing {
        return SnapRead {
            gen,
            state: State::defaults(capacity),
            old_format,
            repaired,
            lost,
            nothing,
            stand_ins: Vec::new(),
        };
    }
    if gen.is_none() {
        lost.push(format!(
            "the header (its generation is unknown; the magazine is taken as {cap} pockets)"
        ));
    }
    if !end && !damaged {
        lost.push("the end of the file (it is cut short)".to_string());
    }
    let mut stand_ins = Vec::new();
    if programs.is_empty() {
        stand_ins.push(EditTarget::Program("TABLEB".to_string()));
        lost.push("every program (program memory holds Table B again)".to_string());
        programs.insert("TABLEB".to_string(), Buffer::from_text(&tape_text(TABLEB)));
    }
    let first = programs.keys().next().cloned().unwrap_or_default();
    let current = match current {
        Some(c) if programs.contains_key(&c) => c,
        Some(c) => {
            lost.push(format!("program {c}, which was current (now {first})"));
            first
        }
        None => {
            lost.push(format!("which program was current (now {first})"));
            first
        }
    };
    let mdi = mdi.unwrap_or_else(|| {
        lost.push("the MDI buffer (now empty)".to_string());
        stand_ins.push(EditTarget::Mdi);
        Buffer::new()
    });
    let tcodes = match tcodes_text.map(|t| parse_tcodes(&t, "state.snap", cap)) {
        Some(Ok(tc)) => Some(tc),
        Some(Err(e)) => {
            lost.push(format!("the T-code table ({})", e.message));
            None
        }
        None => None,
    };
    let (tcodes, tools_file, tool_buf) = match (tcodes, tools) {
        (Some(tc), Some((text, p))) => match (parse_tool_text(&text, &tc), buffer_at(&text, &p)) {
            (Ok(tf), Ok(b)) => (tc, tf, b),
            (Err(e), _) | (_, Err(e)) => {
                lost.push(format!("the tool data ({e}); read the tool tape again"));
                stand_ins.push(EditTarget::ToolFile);
                no_data(tc)
            }
        },
        (None, Some((text, p))) => {
            let tc = tcodes_from_tool_text(&text, cap);
            lost.push("the T-code table (rebuilt from the tool file)".to_string());
            match (parse_tool_text(&text, &tc), buffer_at(&text, &p)) {
                (Ok(tf), Ok(b)) => (tc, tf, b),
                (Err(e), _) | (_, Err(e)) => {
                    lost.push(format!("the tool data ({e}); read the tool tape again"));
                    stand_ins.push(EditTarget::ToolFile);
                    no_data(tc)
                }
            }
        }
        (Some(tc), None) => {
            lost.push("the tool data (the T-code table is kept; read the tool tape again)".into());
            stand_ins.push(EditTarget::ToolFile);
            no_data(tc)
        }
        (None, None) => {
            lost.push("the T-code table and the tool file (now the embedded samples)".into());
            stand_ins.push(EditTarget::ToolFile);
            let d = State::defaults(cap);
            (d.tcodes, d.tools, d.tool_buf)
        }
    };
    SnapRead {
        gen,
        state: State {
            programs,
            dialects,
            current,
            mdi,
            tcodes,
            tools: tools_file,
            tool_buf,
            params,
            lathe: None,
        },
        old_format,
        repaired,
        lost,
        nothing,
        stand_ins,
    }
}

/// The parameters record's text: one `N V` line per parameter kept (whole numbers).
fn read_params(body: &str) -> Option<BTreeMap<u16, i64>> {
    body.lines()
        .map(|l| {
            let (n, v) = l.split_once(' ')?;
            let n: u16 = n.parse().ok()?;
            crate::gcode::state::is_kept(usize::from(n)).then_some(())?;
            Some((n, v.parse().ok()?))
        })
        .collect()
}

/// The old work offsets record's text (before `params`): six lines of three whole numbers,
/// G54 to G59, as the parameters of those systems' zeros.
fn read_offsets(body: &str) -> Option<BTreeMap<u16, i64>> {
    let lines: Vec<&str> = body.lines().collect();
    if lines.len() != 6 {
        return None;
    }
    let mut out = BTreeMap::new();
    for (cs, l) in lines.into_iter().enumerate() {
        let v: Vec<i64> = l
            .split(' ')
            .map(|n| n.parse().ok())
            .collect::<Option<_>>()?;
        let v: [i64; 3] = v.try_into().ok()?;
        let b = crate::gcode::state::system_base(cs) as u16;
        for (a, nm) in v.into_iter().enumerate() {
            if nm != 0 {
                out.insert(b + 1 + a as u16, nm);
            }
        }
    }
    Some(out)
}

/// A T-code table with no tool data, and its tool-file text.
fn no_data(tc: TCodeTable) -> (TCodeTable, ToolFile, Buffer) {
    let m = Magazine {
        tools: ToolFile::new(tc.capacity()),
        tcodes: tc,
    };
    let b = Buffer::from_text(&tool_text(&m));
    (m.tcodes, m.tools, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parameters_round_trip_and_an_old_offsets_record_reads_as_parameters() {
        let mut s = State::defaults(24);
        s.params.insert(5211, -2_500_000);
        s.params.insert(5220, 8_000_000);
        s.params.insert(5230, 45_000_000);
        let back = read(&encode(&s, 7), 24);
        assert!(back.lost.is_empty(), "{:?}", back.lost);
        assert_eq!(back.state.params, s.params);
        // A snapshot written before the parameters: `offsets`, six lines of G54..G59.
        let mut old = Vec::new();
        let mut put = |p: &str| old.extend(frame::encode_pair(p.as_bytes()));
        put("novanc-state 2 3 24");
        put("current TABLEB");
        put("program TABLEB 0\nCL\n");
        put("mdi 0\n");
        put(&format!("tcodes\n{}", s.tcodes.to_text()));
        put(&format!("tools 0\n{}", s.tool_buf.text()));
        put("offsets\n1 2 3\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 -450000000");
        put("end");
        let r = read(&old, 24);
        assert!(r.lost.is_empty(), "{:?}", r.lost);
        let want: BTreeMap<u16, i64> = [(5221, 1), (5222, 2), (5223, 3), (5323, -450_000_000)]
            .into_iter()
            .collect();
        assert_eq!(r.state.params, want);
    }
}
