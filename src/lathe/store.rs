//! The lathe console's stores (docs/lathe.md "Stores"): each channel's program and the part
//! counter, kept under the state directory in `lathe-NAME/`. Every change is written at once
//! and atomically (a kill leaves the old file or the new one, never a mix).

use super::desc::{parse_tool, tool_line, LatheDesc, ToolDesc};
use crate::store::fsutil::{lock_dir, make_dir, write_atomic, DirLock};
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

    fn parse(text: &str, channels: usize) -> Option<Counter> {
        let mut c = Counter {
            target: 0,
            counts: vec![0; channels],
        };
        for line in text.lines() {
            let mut w = line.split_whitespace();
            match w.next() {
                Some("target") => c.target = w.next()?.parse().ok()?,
                Some("counts") => {
                    let v: Vec<u32> = w.map(|s| s.parse().ok()).collect::<Option<_>>()?;
                    if v.len() != channels {
                        return None;
                    }
                    c.counts = v;
                }
                _ => return None,
            }
        }
        Some(c)
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

impl LatheStore {
    /// Opens (creating) `STATE/lathe-NAME/`. A channel with no program gets the embedded
    /// sample (the Citizen's) or an empty one; a damaged counter file is set aside and the
    /// counter starts at 0 of the default target 5.
    pub fn open(state: &Path, desc: &LatheDesc) -> Result<Opened, String> {
        let dir = state.join(format!("lathe-{}", desc.name));
        make_dir(&dir)?;
        let lock = lock_dir(&dir)?;
        let store = LatheStore { dir, _lock: lock };
        let mut warnings = Vec::new();
        let mut programs = Vec::new();
        for ch in 0..desc.channels.len() {
            let path = store.program_path(ch);
            let p = match std::fs::read(&path) {
                Ok(b) => match split_program(&b) {
                    Some(p) => p,
                    None => {
                        let aside = crate::store::fsutil::keep_aside(
                            &store.dir,
                            &format!("ch{}.prog", ch + 1),
                        )
                        .unwrap_or_default();
                        warnings.push(format!(
                            "channel {}: its program file was damaged and is kept as {aside}; the channel starts empty",
                            ch + 1
                        ));
                        Program {
                            name: format!("CH{}.NGC", ch + 1),
                            text: String::new(),
                        }
                    }
                },
                Err(_) => {
                    let p = match (desc.name.as_str(), CITIZEN_PROGRAMS.get(ch)) {
                        ("citizen", Some((n, t))) => Program {
                            name: n.to_string(),
                            text: t.to_string(),
                        },
                        _ => Program {
                            name: format!("CH{}.NGC", ch + 1),
                            text: String::new(),
                        },
                    };
                    store.save_program(ch, &p)?;
                    p
                }
            };
            programs.push(p);
        }
        let n = desc.channels.len();
        let counter = match std::fs::read_to_string(store.dir.join("parts")) {
            Ok(t) => match Counter::parse(&t, n) {
                Some(c) => c,
                None => {
                    let aside =
                        crate::store::fsutil::keep_aside(&store.dir, "parts").unwrap_or_default();
                    warnings.push(format!("the part counter file was damaged and is kept as {aside}; the counter starts at 0 of 5"));
                    Counter {
                        target: 5,
                        counts: vec![0; n],
                    }
                }
            },
            Err(_) => Counter {
                target: 5,
                counts: vec![0; n],
            },
        };
        let mut tools = Vec::new();
        for ch in 0..n {
            let name = format!("ch{}.tools", ch + 1);
            tools.push(match std::fs::read_to_string(store.dir.join(&name)) {
                Err(_) => None,
                Ok(t) => match t.lines().map(parse_tool).collect::<Result<Vec<_>, _>>() {
                    Ok(v) => Some(v),
                    Err(e) => {
                        let aside = crate::store::fsutil::keep_aside(&store.dir, &name)
                            .unwrap_or_default();
                        warnings.push(format!(
                            "channel {}: its tool file was damaged ({e}) and is kept as {aside}; the description's tools apply",
                            ch + 1
                        ));
                        None
                    }
                },
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

    fn program_path(&self, ch: usize) -> PathBuf {
        self.dir.join(format!("ch{}.prog", ch + 1))
    }

    /// Writes channel `ch`'s program (name line, then the text).
    pub fn save_program(&self, ch: usize, p: &Program) -> Result<(), String> {
        let data = format!("{}\n{}", p.name, p.text);
        write_atomic(&self.program_path(ch), data.as_bytes())
            .map_err(|e| format!("channel {}: the program could not be stored: {e}", ch + 1))
    }

    /// Writes channel `ch`'s tools.
    pub fn save_tools(&self, ch: usize, tools: &[ToolDesc]) -> Result<(), String> {
        let text: String = tools.iter().map(|t| tool_line(t) + "\n").collect();
        write_atomic(
            &self.dir.join(format!("ch{}.tools", ch + 1)),
            text.as_bytes(),
        )
        .map_err(|e| format!("channel {}: the tools could not be stored: {e}", ch + 1))
    }

    /// Writes the part counter.
    pub fn save_counter(&self, c: &Counter) -> Result<(), String> {
        write_atomic(&self.dir.join("parts"), c.text().as_bytes())
            .map_err(|e| format!("the part counter could not be stored: {e}"))
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

fn split_program(b: &[u8]) -> Option<Program> {
    let t = std::str::from_utf8(b).ok()?;
    let (name, text) = t.split_once('\n')?;
    if name.is_empty() || name.len() > 64 || text.len() > MAX_PROGRAM {
        return None;
    }
    Some(Program {
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
        let o = LatheStore::open(&d, &desc).unwrap();
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
            o.warnings[0].contains("part counter file was damaged"),
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
