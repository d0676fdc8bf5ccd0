//! The lathe console's stores (docs/lathe.md "Stores"): each channel's program and tools and
//! the part counter, kept under the state directory in `lathe-NAME/`. Every change is written
//! at once and atomically through the centre's write path (`store::fsutil`: a kill leaves the
//! old file or the new one, never a mix). A file that cannot be read or does not parse is
//! damage, never "missing": it is kept aside, said, and nothing the operator did not choose is
//! written over it.

use super::desc::{parse_tool, tool_line, LatheDesc, ToolDesc};
use crate::store::fsutil::{self, lock_dir, make_dir, write_atomic, Aside, DirLock};
use std::path::{Path, PathBuf};

/// The embedded sample programs of the Citizen lathe, one per channel.
pub const CITIZEN_PROGRAMS: [(&str, &str); 3] = [
    (
        "SYSTEM1.NGC",
        include_str!("../../programs/citizen/system1.ngc"),
    ),
    (
        "SYSTEM2.NGC",
        include_str!("../../programs/citizen/system2.ngc"),
    ),
    (
        "SYSTEM3.NGC",
        include_str!("../../programs/citizen/system3.ngc"),
    ),
];

/// Longest program a channel keeps, bytes.
pub const MAX_PROGRAM: usize = 1 << 20;

/// The part counter: a target set at the console and each channel's count of finished works.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counter {
    /// The number of parts to make.
    pub target: u32,
    /// Works each channel has finished in this batch.
    pub counts: Vec<u32>,
}

impl Counter {
    fn text(&self) -> String {
        let c: Vec<String> = self.counts.iter().map(|c| c.to_string()).collect();
        format!("target {}\ncounts {}\n", self.target, c.join(" "))
    }

    /// Reads a `parts` file: a `target` line (1 to 999999, as the console takes it) and a
    /// `counts` line with one count per channel, each exactly once.
    fn parse(text: &str, channels: usize) -> Result<Counter, String> {
        let mut target = None;
        let mut counts = None;
        for (i, line) in text.lines().enumerate() {
            let ln = i + 1;
            let mut w = line.split_whitespace();
            match w.next() {
                Some("target") if target.is_none() => {
                    let t = w.next().and_then(|t| t.parse::<u32>().ok());
                    match t {
                        Some(t) if (1..=999_999).contains(&t) && w.next().is_none() => {
                            target = Some(t)
                        }
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
}

/// One channel's program: its name and text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    /// The name the display shows (`SYSTEM1.NGC`).
    pub name: String,
    /// The text.
    pub text: String,
}

/// The lathe stores of one machine.
#[derive(Debug)]
pub struct LatheStore {
    dir: PathBuf,
    /// Damaged files not yet kept aside: none is overwritten before it is.
    aside: Aside,
    _lock: DirLock,
}

/// What the stores held when opened.
#[derive(Debug)]
pub struct Opened {
    /// The stores.
    pub store: LatheStore,
    /// Each channel's program.
    pub programs: Vec<Program>,
    /// The part counter.
    pub counter: Counter,
    /// Each channel's tools as last revised at the console (`None`: the description's).
    pub tools: Vec<Option<Vec<ToolDesc>>>,
    /// What the operator should know (a file that could not be read, set aside).
    pub warnings: Vec<String>,
}

/// A file of the store as read at open.
enum Read<T> {
    /// There is none (a new store).
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

impl LatheStore {
    /// Opens (creating) `STATE/lathe-NAME/`. A channel with no program file gets the embedded
    /// sample (the Citizen's) or an empty one, and a store with no counter starts at 0 of 5.
    /// A file that cannot be read or is damaged is kept aside as `NAME.bad-SECONDS` and said;
    /// a program starts empty, the tools are the description's and the counter starts at 0 of
    /// 5 in its place, and nothing is written until the operator changes it. A machine name
    /// that could name a path outside the state directory is refused.
    pub fn open(state: &Path, desc: &LatheDesc) -> Result<Opened, String> {
        fsutil::check_file_name(&desc.name).map_err(|e| format!("machine name {e}"))?;
        let dir = state.join(format!("lathe-{}", desc.name));
        make_dir(&dir)?;
        let lock = lock_dir(&dir)?;
        let mut warnings = Vec::new();
        if let Some(why) = lock.read_only() {
            warnings.push(format!(
                "the state directory {} is read-only ({why}): the programs, tools and part counter are shown as they were read, and every change is refused",
                dir.display()
            ));
        }
        let mut store = LatheStore {
            dir,
            aside: Aside::default(),
            _lock: lock,
        };
        let n = desc.channels.len();
        let mut programs = Vec::new();
        for ch in 0..n {
            let name = format!("ch{}.prog", ch + 1);
            let empty = Program {
                name: format!("CH{}.NGC", ch + 1),
                text: String::new(),
            };
            programs.push(match read(&store.dir, &name, split_program) {
                Read::Good(p) => p,
                Read::Damaged(why) => {
                    let what = format!("channel {}: its program file", ch + 1);
                    warnings.push(store.damaged(what, &name, why, "the channel starts empty"));
                    empty
                }
                Read::Missing => {
                    let p = match (desc.name.as_str(), CITIZEN_PROGRAMS.get(ch)) {
                        ("citizen", Some((n, t))) => Program {
                            name: n.to_string(),
                            text: t.to_string(),
                        },
                        _ => empty,
                    };
                    if store.read_only().is_none() {
                        if let Err(e) = store.save_program(ch, &p) {
                            warnings.push(e);
                        }
                    }
                    p
                }
            });
        }
        let fresh = Counter {
            target: 5,
            counts: vec![0; n],
        };
        let counter = match read(&store.dir, "parts", |t| Counter::parse(t, n)) {
            Read::Good(c) => c,
            Read::Missing => fresh,
            Read::Damaged(why) => {
                let what = "the part counter file".to_string();
                warnings.push(store.damaged(what, "parts", why, "the counter starts at 0 of 5"));
                fresh
            }
        };
        let mut tools = Vec::new();
        for ch in 0..n {
            let name = format!("ch{}.tools", ch + 1);
            let parse = |t: &str| {
                t.lines()
                    .enumerate()
                    .map(|(i, l)| parse_tool(l).map_err(|e| format!("line {}: {e}", i + 1)))
                    .collect::<Result<Vec<_>, _>>()
            };
            tools.push(match read(&store.dir, &name, parse) {
                Read::Good(v) => Some(v),
                Read::Missing => None,
                Read::Damaged(why) => {
                    let what = format!("channel {}: its tool file", ch + 1);
                    let instead = "the description's tools apply until a tool is revised: check the offsets on the OFS page before START";
                    warnings.push(store.damaged(what, &name, why, instead));
                    None
                }
            });
        }
        Ok(Opened {
            store,
            programs,
            counter,
            tools,
            warnings,
        })
    }

    /// Keeps the damaged file `name` aside (or notes it cannot be, so nothing overwrites it)
    /// and words the warning: `WHAT NAME is damaged (WHY); it is kept as ...; INSTEAD`.
    fn damaged(&mut self, what: String, name: &str, why: String, instead: &str) -> String {
        let kept = match self.aside.keep(&self.dir, name) {
            Ok(k) => format!("it is kept as {k}"),
            Err(e) => format!(
                "it could not be kept aside ({e}), so nothing will be written over {name} until it can"
            ),
        };
        format!("{what} {name} is damaged ({why}); {kept}; {instead}")
    }

    /// Why nothing can be written: the directory is read-only and could not be locked.
    fn read_only(&self) -> Option<&str> {
        self._lock.read_only()
    }

    /// Writes the file `name` whole (`fsutil::write_atomic`), unless the directory is
    /// read-only or a damaged file of that name still waits to be kept aside.
    fn write(&mut self, name: &str, data: &[u8]) -> Result<(), String> {
        if let Some(why) = self.read_only() {
            return Err(format!("the state directory is read-only ({why})"));
        }
        self.aside
            .before_overwrite(&self.dir, Some(name))
            .and_then(|_| write_atomic(&self.dir.join(name), data))
            .map_err(|e| e.to_string())
    }

    /// Writes channel `ch`'s program (name line, then the text).
    pub fn save_program(&mut self, ch: usize, p: &Program) -> Result<(), String> {
        let data = format!("{}\n{}", p.name, p.text);
        self.write(&format!("ch{}.prog", ch + 1), data.as_bytes())
            .map_err(|e| format!("channel {}: the program could not be stored: {e}", ch + 1))
    }

    /// Writes channel `ch`'s tools.
    pub fn save_tools(&mut self, ch: usize, tools: &[ToolDesc]) -> Result<(), String> {
        let text: String = tools.iter().map(|t| tool_line(t) + "\n").collect();
        self.write(&format!("ch{}.tools", ch + 1), text.as_bytes())
            .map_err(|e| format!("channel {}: the tools could not be stored: {e}", ch + 1))
    }

    /// Writes the part counter.
    pub fn save_counter(&mut self, c: &Counter) -> Result<(), String> {
        self.write("parts", c.text().as_bytes())
            .map_err(|e| format!("the part counter could not be stored: {e}"))
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

/// Reads a program file: its name on the first line, then the text.
fn split_program(t: &str) -> Result<Program, String> {
    let (name, text) = t
        .split_once('\n')
        .ok_or("it has no name line".to_string())?;
    if name.is_empty() || name.len() > 64 {
        return Err("line 1: the name is empty or longer than 64 bytes".into());
    }
    if text.len() > MAX_PROGRAM {
        return Err(format!("the program is longer than {MAX_PROGRAM} bytes"));
    }
    Ok(Program {
        name: name.to_string(),
        text: text.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("novanc-lathe-store-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn programs_and_counter_survive_a_reopen() {
        let d = tmp("reopen");
        let desc = LatheDesc::citizen();
        let mut o = LatheStore::open(&d, &desc).unwrap();
        assert_eq!(o.programs[2].name, "SYSTEM3.NGC");
        assert_eq!(
            o.counter,
            Counter {
                target: 5,
                counts: vec![0; 3]
            }
        );
        let p = Program {
            name: "X.NGC".into(),
            text: "G0 X1\n".into(),
        };
        o.store.save_program(1, &p).unwrap();
        o.store
            .save_counter(&Counter {
                target: 7,
                counts: vec![3, 2, 1],
            })
            .unwrap();
        drop(o);
        let o = LatheStore::open(&d, &desc).unwrap();
        assert_eq!(o.programs[1], p);
        assert_eq!(
            o.counter,
            Counter {
                target: 7,
                counts: vec![3, 2, 1]
            }
        );
        assert!(o.warnings.is_empty());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_damaged_counter_is_set_aside_and_said() {
        let d = tmp("damaged");
        let desc = LatheDesc::citizen();
        drop(LatheStore::open(&d, &desc).unwrap());
        std::fs::write(d.join("lathe-citizen/parts"), "target five\n").unwrap();
        let o = LatheStore::open(&d, &desc).unwrap();
        assert_eq!(o.counter.target, 5);
        assert!(
            o.warnings[0].contains("part counter file parts is damaged"),
            "{:?}",
            o.warnings
        );
        // A second console on the same state is refused while the first holds it.
        assert!(LatheStore::open(&d, &desc)
            .unwrap_err()
            .contains("another novanc"));
        drop(o);
        let _ = std::fs::remove_dir_all(&d);
    }
}
