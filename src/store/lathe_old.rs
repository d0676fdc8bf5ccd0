//! The lathe's old store, read once to migrate it (docs/lathe.md "Stores"): before the lathe's
//! programs, tools and part counter were journaled (`store::lathe`), `STATE/lathe-NAME/` held
//! them as whole files, `chN.prog` (the name line, then the text), `chN.tools` (description
//! `tool` lines) and `parts` (`target N`, `counts ...`). When a lathe directory has no
//! journaled store yet, `store::lathe::LatheStore::open` reads these here; their contents
//! become the first snapshot, and they are not read again. A file that cannot be read or does
//! not parse is damage, never "missing": it is kept aside and said, and its channel starts
//! empty (a program), on the description's tools, or at 0 of 5 parts in its place.

use super::fsutil::Aside;
use super::lathe::{parse_tools, Counter, LatheState, Program, MAX_NAME, MAX_PROGRAM};
use crate::lathe::desc::LatheDesc;
use std::path::Path;

/// What an old lathe directory held.
pub struct Old {
    /// Its programs, tools and counter (what was missing: the defaults).
    pub state: LatheState,
    /// Damage found, each file kept aside.
    pub warnings: Vec<String>,
}

/// A file of the old store as read.
enum Read<T> {
    /// There is none.
    Missing,
    /// It read.
    Good(T),
    /// It could not be read, or did not parse: why.
    Damaged(String),
}

/// Reads the file `name` of `dir` and parses it. Only a file that is not there is missing;
/// every other failure (no permission, not a file, a byte that is not UTF-8) is damage.
fn read<T>(dir: &Path, name: &str, parse: impl FnOnce(&str) -> Result<T, String>) -> Read<T> {
    match std::fs::read(dir.join(name)) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Read::Missing,
        Err(e) => Read::Damaged(format!("it cannot be read: {e}")),
        Ok(b) => match crate::input_text::decode(&b) {
            Err(e) => Read::Damaged(e.to_string()),
            Ok(t) => match parse(t) {
                Ok(v) => Read::Good(v),
                Err(e) => Read::Damaged(e),
            },
        },
    }
}

/// Reads the old store of `dir` onto `base` (the defaults); None if it holds none of its files
/// (a new directory). Damaged files are kept aside as `NAME.bad-SECONDS` (or, if they cannot
/// be, left where they are: the journaled store never writes these names).
pub fn read_old(dir: &Path, desc: &LatheDesc, base: &LatheState) -> Option<Old> {
    let n = desc.channels.len();
    let names: Vec<String> = (1..=n)
        .flat_map(|c| [format!("ch{c}.prog"), format!("ch{c}.tools")])
        .chain(["parts".to_string()])
        .collect();
    if names
        .iter()
        .all(|f| std::fs::symlink_metadata(dir.join(f)).is_err())
    {
        return None;
    }
    let mut aside = Aside::default();
    let mut warnings = Vec::new();
    let mut damaged = |what: String, name: &str, why: String, instead: &str| {
        let kept = match aside.keep(dir, name) {
            Ok(k) => format!("it is kept as {k}"),
            Err(e) => format!("it could not be kept aside ({e}), and is left as it is"),
        };
        warnings.push(format!(
            "{what} {name} is damaged ({why}); {kept}; {instead}"
        ));
    };
    let mut state = base.clone();
    for ch in 0..n {
        let name = format!("ch{}.prog", ch + 1);
        match read(dir, &name, split_program) {
            Read::Good(p) => state.programs[ch] = p,
            Read::Missing => {}
            Read::Damaged(why) => {
                let what = format!("channel {}: its program file", ch + 1);
                damaged(what, &name, why, "the channel starts empty");
                state.programs[ch] = Program::empty(ch);
            }
        }
        let name = format!("ch{}.tools", ch + 1);
        match read(dir, &name, parse_tools) {
            Read::Good(v) => state.tools[ch] = Some(v),
            Read::Missing => {}
            Read::Damaged(why) => {
                let what = format!("channel {}: its tool file", ch + 1);
                let instead = "the description's tools apply until a tool is revised: check the offsets on the OFS page before START";
                damaged(what, &name, why, instead);
            }
        }
    }
    match read(dir, "parts", |t| parse_counter(t, n)) {
        Read::Good(c) => state.counter = c,
        Read::Missing => {}
        Read::Damaged(why) => {
            let what = "the part counter file".to_string();
            damaged(what, "parts", why, "the counter starts at 0 of 5");
        }
    }
    Some(Old { state, warnings })
}

/// Reads a `parts` file: a `target` line (1 to 999999, as the console takes it) and a `counts`
/// line with one count per channel, each exactly once.
fn parse_counter(text: &str, channels: usize) -> Result<Counter, String> {
    let mut target = None;
    let mut counts = None;
    for (i, line) in text.lines().enumerate() {
        let ln = i + 1;
        let mut w = line.split_whitespace();
        match w.next() {
            Some("target") if target.is_none() => {
                let t = w.next().and_then(|t| t.parse::<u32>().ok());
                match t {
                    Some(t) if (1..=999_999).contains(&t) && w.next().is_none() => target = Some(t),
                    _ => {
                        return Err(format!(
                            "line {ln}: the target is not a number of parts from 1 to 999999"
                        ))
                    }
                }
            }
            Some("counts") if counts.is_none() => {
                let v: Option<Vec<u32>> = w.map(|s| s.parse().ok()).collect();
                match v {
                    Some(v) if v.len() == channels => counts = Some(v),
                    _ => {
                        return Err(format!(
                            "line {ln}: the counts are not {channels} whole numbers"
                        ))
                    }
                }
            }
            _ => {
                return Err(format!(
                    "line {ln} is not one 'target N' and one 'counts ...' line"
                ))
            }
        }
    }
    match (target, counts) {
        (Some(target), Some(counts)) => Ok(Counter { target, counts }),
        _ => Err("it lacks its 'target' or its 'counts' line".into()),
    }
}

/// Reads a program file: its name on the first line, then the text.
fn split_program(t: &str) -> Result<Program, String> {
    let (name, text) = t
        .split_once('\n')
        .ok_or("it has no name line".to_string())?;
    if name.is_empty() || name.len() > MAX_NAME {
        return Err(format!(
            "line 1: the name is empty or longer than {MAX_NAME} bytes"
        ));
    }
    if text.len() > MAX_PROGRAM {
        return Err(format!("the program is longer than {MAX_PROGRAM} bytes"));
    }
    Ok(Program {
        name: name.to_string(),
        text: text.to_string(),
        dialect: None,
    })
}
