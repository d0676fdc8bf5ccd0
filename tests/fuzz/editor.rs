//! Editor command lines, on an editor buffer directly and on the stores (program memory, the
//! MDI buffer, the tool file, tapes and T-code settings), and the checks (docs/editor.md,
//! docs/stores.md): a refused command line leaves the buffer and its pointer as they were, a
//! refused store operation leaves memory and every file of the state directory byte for byte
//! the same, and what was accepted is there again after the stores are reopened.

use super::harness::{note, Ctx};
use super::programs::{by_grammar, mutate};
use super::rng::Rng;
use novanc::store::{Stores, Target};
use novanc::tooldata::Magazine;
use novanc_editor::{Buffer, ExecOptions};
use std::collections::BTreeMap;
use std::path::Path;

/// A count as typed before L M K D Y: none, small, signed, or at the ends of the range.
fn count(rng: &mut Rng) -> String {
    match rng.below(12) {
        0..=3 => String::new(),
        4 => rng
            .pick(&[
                "-9223372036854775808",
                "9223372036854775807",
                "9223372036854775808",
                "-9223372036854775809",
                "0",
                "-0",
                "+",
                "-",
                "99999999999999999999999",
            ])
            .to_string(),
        5 => format!("-{}", rng.range(1, 30)),
        _ => rng.range(0, 30).to_string(),
    }
}

/// Text for I, S and C: program text, `*` for EOB, escapes, and odd characters.
fn text_arg(rng: &mut Rng, sample: &str) -> String {
    match rng.below(6) {
        0 => {
            // A piece of the sample, so searches find something.
            let chars: Vec<char> = sample.chars().collect();
            let a = rng.below(chars.len() + 1);
            let b = (a + rng.below(12)).min(chars.len());
            chars[a..b]
                .iter()
                .map(|&c| if c == '\n' { '*' } else { c })
                .filter(|&c| c != '$' && c != '\\')
                .collect()
        }
        1 => rng
            .pick(&[
                "\\*", "\\$", "\\\\", "\\q", "**", "\u{0}", "\u{feff}", "é€", "\r", "\t",
            ])
            .to_string(),
        2 if rng.chance(0.05) => "N10 G00 X1*".repeat(rng.range(10, 2000) as usize),
        _ => rng
            .pick(&[
                "N10 G00*", "X10", "DRL", "106", "P1", " ", "DP20", "00106", "6.2", "DR", "T02",
            ])
            .to_string(),
    }
}

/// A command line from the grammar of docs/editor.md, sometimes mutated.
pub fn command_line(rng: &mut Rng, sample: &str) -> String {
    let mut s = String::new();
    for _ in 0..rng.range(0, 5) {
        let sep = *rng.pick(&["", " ", "$", "  ", "\t"]);
        s.push_str(sep);
        match rng.below(9) {
            0..=4 => {
                s.push_str(&count(rng));
                let l = *rng.pick(&["L", "M", "K", "D", "Y", "l", "d"]);
                s.push_str(l);
            }
            5 => s.push_str(&format!("I{}$", text_arg(rng, sample))),
            6 => s.push_str(&format!("S{}$", text_arg(rng, sample))),
            7 => s.push_str(&format!(
                "C{}${}$",
                text_arg(rng, sample),
                text_arg(rng, sample)
            )),
            _ => s.push_str(rng.pick::<&str>(&["Q", "3", "3I", "C", "Cx", "S$", "\u{0}", "é"])),
        }
    }
    if rng.chance(0.15) {
        s = mutate(rng, &s, "I*$");
    }
    s
}

/// Family `editor`: command lines on a buffer; a refused one changes neither text nor pointer.
pub fn editor_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let sample = match rng.below(3) {
        0 => ctx.tape.clone(),
        1 => by_grammar(rng),
        _ => rng.pick(&ctx.programs).clone(),
    };
    let mut buf = Buffer::from_text(&sample);
    buf.set_pointer(rng.below(buf.len() + 1));
    let refuse_x = |b: &Buffer| {
        if b.text().contains('X') {
            Err("no X".to_string())
        } else {
            Ok(())
        }
    };
    let mut lines = Vec::new();
    for _ in 0..rng.range(1, 12) {
        let line = command_line(rng, &sample);
        lines.push(line.clone());
        note(
            "buffer, then command lines",
            &format!("{sample}\n---\n{}", lines.join("\n")),
        );
        let opts = ExecOptions {
            y_max_lines: if rng.chance(0.5) {
                Some(rng.below(20))
            } else {
                None
            },
            validator: if rng.chance(0.2) {
                Some(&refuse_x)
            } else {
                None
            },
        };
        let (text, ptr) = (buf.text(), buf.pointer());
        match buf.execute(&line, &opts) {
            Ok(_) => {
                if buf.pointer() > buf.len() {
                    return Err(format!(
                        "pointer {} past the end {}",
                        buf.pointer(),
                        buf.len()
                    ));
                }
            }
            Err(e) => {
                let m = e.to_string();
                if m.contains('\n') || m.len() > 400 {
                    return Err(format!("bad message: {m:?}"));
                }
                if buf.text() != text || buf.pointer() != ptr {
                    return Err(format!("'{line}' was refused ({m}) but changed the buffer"));
                }
            }
        }
    }
    Ok(())
}

/// What the stores hold, as an operator can see it.
#[derive(Debug, PartialEq)]
struct Seen {
    programs: BTreeMap<String, String>,
    current: String,
    buffers: Vec<(String, usize)>,
    magazine: Magazine,
}

fn seen(s: &Stores) -> Seen {
    Seen {
        programs: s
            .program_names()
            .into_iter()
            .map(|n| (n.clone(), s.program_text(&n).unwrap_or_default()))
            .collect(),
        current: s.current_program().to_string(),
        buffers: [Target::Program, Target::Mdi, Target::ToolFile]
            .iter()
            .map(|&t| (s.buffer(t).text(), s.buffer(t).pointer()))
            .collect(),
        magazine: s.magazine(),
    }
}

/// Every file of the state directory, byte for byte.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| {
                    let n = e.file_name().to_string_lossy().into_owned();
                    (n, std::fs::read(e.path()).unwrap_or_default())
                })
                .collect()
        })
        .unwrap_or_default()
}

/// A program name: mostly valid, sometimes not.
fn program_name(rng: &mut Rng) -> String {
    rng.pick(&[
        "TABLEB",
        "A1",
        "prog",
        "P-2.x",
        "",
        " ",
        "prüf",
        "TOO_LONG_NAME_OF_MORE_THAN_32_CHARS",
        "a/b",
        "X\u{0}",
        "NEW",
    ])
    .to_string()
}

/// Family `stores`: operations on fresh stores; each refused one leaves memory and the files
/// unchanged; at the end, the stores reopened hold what they held.
pub fn stores_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let dir = ctx.tmp.join(format!("stores-{:x}", rng.next_u64()));
    let _ = std::fs::remove_dir_all(&dir);
    let r = stores_in(rng, ctx, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    r
}

fn stores_in(rng: &mut Rng, ctx: &Ctx, dir: &Path) -> Result<(), String> {
    let (mut s, _) = Stores::open(dir, 24).map_err(|e| format!("open: {e}"))?;
    if rng.chance(0.3) {
        s.set_journal_limit(rng.range(1, 8) as usize);
    }
    let mut log = Vec::new();
    for _ in 0..rng.range(1, 20) {
        let before = (seen(&s), files(dir));
        let sample = s.buffer(Target::Program).text();
        let (what, r): (String, Result<(), String>) = match rng.below(12) {
            0..=5 => {
                let t = *rng.pick(&[Target::Program, Target::Mdi, Target::ToolFile]);
                let src = if t == Target::ToolFile {
                    s.buffer(t).text()
                } else {
                    sample
                };
                let line = command_line(rng, &src);
                let r = s
                    .edit(t, &line, None)
                    .map(|_| ())
                    .map_err(|e| e.to_string());
                (format!("edit {t:?} {line:?}"), r)
            }
            6 => {
                let name = program_name(rng);
                let base = rng.pick(&ctx.programs).clone();
                let text = mutate(rng, &base, "");
                let r = s.program_read(&name, &text).map_err(|e| e.to_string());
                (format!("program read {name:?}"), r)
            }
            7 => {
                let tape = mutate(rng, &ctx.tape, "00106 DR 1e308 1 1 1 1 1\n");
                let r = s
                    .tool_read(&tape, "t.tt")
                    .map(|_| ())
                    .map_err(|e| e.to_string());
                (format!("tool read {tape:?}"), r)
            }
            8 => {
                let text = mutate(rng, &ctx.tcodes, "T25 00106\n");
                let r = s.tcode_read(&text, "m.tc").map_err(|e| e.to_string());
                (format!("T-code read {text:?}"), r)
            }
            9 => {
                let t = rng.range(0, 30) as u32;
                let tool = if rng.chance(0.2) {
                    None
                } else {
                    Some(rng.range(0, 700) as u32)
                };
                (format!("T-code set T{t} {tool:?}"), s.set_tcode(t, tool))
            }
            10 => {
                let (tool, t) = (rng.range(0, 700) as u32, rng.range(0, 30) as u32);
                (format!("move tool {tool} to T{t}"), s.move_tool(tool, t))
            }
            _ => {
                let name = program_name(rng);
                let r = match rng.below(3) {
                    0 => s.select_program(&name),
                    1 => s.new_program(&name),
                    _ => s.delete_program(&name),
                };
                (
                    format!("program op on {name:?}"),
                    r.map_err(|e| e.to_string()),
                )
            }
        };
        log.push(format!("{what} -> {r:?}"));
        note("store operations", &log.join("\n"));
        if let Err(m) = r {
            if m.contains('\n') || m.len() > 600 {
                return Err(format!("bad message: {m:?}"));
            }
            if seen(&s) != before.0 {
                return Err(format!(
                    "{what} was refused ({m}) but changed the stores in memory"
                ));
            }
            if files(dir) != before.1 {
                return Err(format!("{what} was refused ({m}) but changed a file"));
            }
        }
    }
    let last = seen(&s);
    drop(s);
    let (s, warnings) = Stores::open(dir, 24).map_err(|e| format!("reopen: {e}"))?;
    if !warnings.is_empty() {
        return Err(format!("reopening warned: {warnings:?}"));
    }
    let again = seen(&s);
    let texts = |v: &Seen| (v.buffers[0].0.clone(), v.buffers[1].0.clone());
    if again.programs != last.programs
        || again.current != last.current
        || again.magazine != last.magazine
        || texts(&again) != texts(&last)
    {
        return Err("the reopened stores differ from what was acknowledged".to_string());
    }
    Ok(())
}
