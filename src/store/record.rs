//! The changes the journal records, one per accepted operator action, and their payload text.
//! A payload is a header line (`edit P NAME`, `tcode 5 106`, ...) and, for the changes that
//! carry text, a body after the first `\n`.

use crate::settings::Dialect;

/// Which buffer an edit record applies to; a program is named so replay does not depend on
/// which program was current.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EditTarget {
    /// A named program in program memory.
    Program(String),
    /// The MDI buffer.
    Mdi,
    /// The tool file.
    ToolFile,
}

/// One accepted change.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Record {
    /// An editor command line that was accepted.
    Edit {
        /// The buffer.
        target: EditTarget,
        /// The command line as typed.
        line: String,
    },
    /// SEARCH: another program made current.
    Select(String),
    /// A new empty program, made current.
    NewProgram {
        /// The program name.
        name: String,
        /// The G-code dialect it is written in (the machine's when it was made); None in a
        /// record written before programs kept their dialect: the machine's at each run.
        dialect: Option<Dialect>,
    },
    /// PROGRAM READ: a program added or replaced from tape, made current.
    ProgramRead {
        /// The program name.
        name: String,
        /// Its text.
        text: String,
        /// The G-code dialect it is written in (the machine's when it was read); None in a
        /// record written before programs kept their dialect: the machine's at each run.
        dialect: Option<Dialect>,
    },
    /// TOOL DATA READ: the tool file replaced (tool-file text).
    ToolFile(String),
    /// A T-code table file read: the whole table replaced (T-code table text).
    TCodes(String),
    /// A program deleted from program memory.
    Delete(String),
    /// A program copied under a new name (the copy is made current).
    Copy {
        /// The program copied.
        from: String,
        /// The new name.
        to: String,
    },
    /// A program renamed (it stays current if it was).
    Rename {
        /// The old name.
        from: String,
        /// The new name.
        to: String,
    },
    /// The MDI buffer emptied.
    ClearMdi,
    /// T-CODE SETTING by tool: a tool moved to a pocket, with its data, out of any other.
    Move {
        /// The tool number.
        tool: u32,
        /// The pocket it goes to.
        t: u32,
    },
    /// Persistent parameters of the G-code interpreter set together (#5161–#5390: the work
    /// offsets from the OFS page or a G10, G92, the selected system, the G28/G30 homes), each
    /// in millionths of its unit (nanometres, or micro-degrees for a rotation). The old
    /// record `offset G5n X Y Z` reads as the three parameters of that system's zero.
    Params(Vec<(u16, i64)>),
    /// T-CODE SETTING: a T code given a tool, or emptied.
    TCode {
        /// The T code.
        t: u32,
        /// The tool number, or None for an empty pocket.
        tool: Option<u32>,
    },
    /// A lathe channel's program, whole (an edit at the DATA page; `store::lathe`).
    ChannelProgram {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// The name the display shows.
        name: String,
        /// The text.
        text: String,
        /// The G-code dialect it is written in (the channel's when it was stored); None in a
        /// record written before lathe programs kept their dialect: the channel's at each run.
        dialect: Option<Dialect>,
    },
    /// A lathe channel's tools as revised at the OFS page, one description `tool` line each;
    /// None: the machine description's tools.
    ChannelTools {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// The tool lines.
        text: Option<String>,
    },
    /// A lathe channel's kept parameters set together (the Fanuc dialect's #500–#999: docs/
    /// stores.md "A lathe's stores"), each in millionths; 0 (vacant) removes one.
    ChannelParams {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// Parameter number and value in millionths.
        params: Vec<(u16, i64)>,
    },
    /// A lathe channel's MDI buffer, whole: the lines typed in MDI that START has not run yet
    /// (docs/stores.md "A lathe's stores"); empty when cleared.
    ChannelMdi {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// The lines, each ended by a line break.
        text: String,
    },
    /// A lathe channel's editor pointer in its program, characters from the start (a DATA
    /// line that moved it; docs/stores.md "A lathe's stores").
    ChannelPointer {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// Characters from the program's start.
        at: usize,
    },
    /// A lathe channel's jog feed chosen on POS (`JOG 500`, `JOG RAPID`; docs/stores.md "A
    /// lathe's stores").
    ChannelJog {
        /// The channel, 0-based (written 1-based).
        ch: usize,
        /// The feed, millionths of a mm/min (None: the machine's).
        feed: Option<i64>,
        /// Rapid jog.
        rapid: bool,
    },
    /// A lathe's tool posts (its position memory, docs/stores.md "A lathe's stores"): each
    /// channel's, in order, moving or at rest, and where.
    Posts(Vec<super::lathe::Post>),
    /// A lathe's part counter: the target and each channel's count.
    Parts {
        /// The number of parts to make.
        target: u32,
        /// Works each channel has finished in this batch.
        counts: Vec<u32>,
    },
}

impl Record {
    /// The payload text.
    pub fn encode(&self) -> String {
        match self {
            Record::Edit { target, line } => match target {
                EditTarget::Program(n) => format!("edit P {n}\n{line}"),
                EditTarget::Mdi => format!("edit M\n{line}"),
                EditTarget::ToolFile => format!("edit T\n{line}"),
            },
            Record::Select(n) => format!("select {n}"),
            Record::NewProgram { name, dialect } => {
                format!("new {name}{}", dialect_field(*dialect))
            }
            Record::ProgramRead {
                name,
                text,
                dialect,
            } => format!("read {name}{}\n{text}", dialect_field(*dialect)),
            Record::ToolFile(text) => format!("tools\n{text}"),
            Record::TCodes(text) => format!("tcodes\n{text}"),
            Record::Delete(n) => format!("delete {n}"),
            Record::Copy { from, to } => format!("copy {from} {to}"),
            Record::Rename { from, to } => format!("rename {from} {to}"),
            Record::ClearMdi => "clear M".to_string(),
            Record::Move { tool, t } => format!("move {tool} {t}"),
            Record::TCode { t, tool: Some(n) } => format!("tcode {t} {n}"),
            Record::TCode { t, tool: None } => format!("tcode {t} -"),
            Record::Params(ps) => {
                let mut t = String::from("param");
                for (n, v) in ps {
                    t.push_str(&format!(" {n} {v}"));
                }
                t
            }
            Record::ChannelProgram {
                ch,
                name,
                text,
                dialect,
            } => {
                format!(
                    "chprog {}{}\n{name}\n{text}",
                    ch + 1,
                    dialect_field(*dialect)
                )
            }
            Record::ChannelTools { ch, text: Some(t) } => format!("chtools {}\n{t}", ch + 1),
            Record::ChannelTools { ch, text: None } => format!("chtools {} -", ch + 1),
            Record::ChannelParams { ch, params } => {
                let mut t = format!("chparam {}", ch + 1);
                for (n, v) in params {
                    t.push_str(&format!(" {n} {v}"));
                }
                t
            }
            Record::ChannelMdi { ch, text } => format!("chmdi {}\n{text}", ch + 1),
            Record::ChannelPointer { ch, at } => format!("chptr {} {at}", ch + 1),
            Record::ChannelJog { ch, feed, rapid } => format!(
                "chjog {} {}{}",
                ch + 1,
                feed.map_or("default".to_string(), |f| f.to_string()),
                if *rapid { " rapid" } else { "" }
            ),
            Record::Posts(posts) => {
                let mut t = "posts".to_string();
                for p in posts {
                    let state = if p.moving { "moving" } else { "rest" };
                    t += &format!(" {state} {} {}", p.pos[0], p.pos[1]);
                }
                t
            }
            Record::Parts { target, counts } => {
                let mut t = format!("parts {target}");
                for c in counts {
                    t.push_str(&format!(" {c}"));
                }
                t
            }
        }
    }

    /// Parses a payload; the error says what is wrong.
    pub fn decode(payload: &str) -> Result<Record, String> {
        let (head, body) = match payload.split_once('\n') {
            Some((h, b)) => (h, Some(b)),
            None => (payload, None),
        };
        let f: Vec<&str> = head.split(' ').collect();
        let body_of = |b: Option<&str>| {
            b.map(str::to_string)
                .ok_or_else(|| format!("record '{head}' has no text"))
        };
        let rec = match f.as_slice() {
            ["edit", "P", n] => Record::Edit {
                target: EditTarget::Program(n.to_string()),
                line: body_of(body)?,
            },
            ["edit", "M"] => Record::Edit {
                target: EditTarget::Mdi,
                line: body_of(body)?,
            },
            ["edit", "T"] => Record::Edit {
                target: EditTarget::ToolFile,
                line: body_of(body)?,
            },
            ["select", n] => Record::Select(n.to_string()),
            ["new", n, d @ ..] if d.len() <= 1 => Record::NewProgram {
                name: n.to_string(),
                dialect: dialect_of(d.first(), head)?,
            },
            ["read", n, d @ ..] if d.len() <= 1 => Record::ProgramRead {
                name: n.to_string(),
                text: body_of(body)?,
                dialect: dialect_of(d.first(), head)?,
            },
            ["tools"] => Record::ToolFile(body_of(body)?),
            ["tcodes"] => Record::TCodes(body_of(body)?),
            ["delete", n] => Record::Delete(n.to_string()),
            ["copy", a, b] => Record::Copy {
                from: a.to_string(),
                to: b.to_string(),
            },
            ["rename", a, b] => Record::Rename {
                from: a.to_string(),
                to: b.to_string(),
            },
            ["clear", "M"] => Record::ClearMdi,
            ["move", n, t] => Record::Move {
                tool: n.parse().map_err(|_| format!("bad tool in '{head}'"))?,
                t: t.parse().map_err(|_| format!("bad T code in '{head}'"))?,
            },
            ["tcode", t, n] => Record::TCode {
                t: t.parse().map_err(|_| format!("bad T code in '{head}'"))?,
                tool: match *n {
                    "-" => None,
                    n => Some(n.parse().map_err(|_| format!("bad tool in '{head}'"))?),
                },
            },
            ["offset", g, x, y, z] => {
                // Written before the parameters were kept: a work offset G54..G59.
                let bad = || format!("bad work offset in '{head}'");
                let system = match g.strip_prefix('G').and_then(|n| n.parse::<usize>().ok()) {
                    Some(n @ 54..=59) => n - 54,
                    _ => return Err(bad()),
                };
                let v = |s: &str| s.parse::<i64>().map_err(|_| bad());
                let b = crate::gcode::state::system_base(system) as u16;
                Record::Params(vec![(b + 1, v(x)?), (b + 2, v(y)?), (b + 3, v(z)?)])
            }
            ["param", rest @ ..] if !rest.is_empty() && rest.len() % 2 == 0 => {
                Record::Params(param_pairs(rest, head)?)
            }
            ["chprog", c, d @ ..] if d.len() <= 1 => {
                let (name, text) = body_of(body)?
                    .split_once('\n')
                    .map(|(n, t)| (n.to_string(), t.to_string()))
                    .ok_or_else(|| format!("record '{head}' has no name line"))?;
                Record::ChannelProgram {
                    ch: channel(c, head)?,
                    name,
                    text,
                    dialect: dialect_of(d.first(), head)?,
                }
            }
            ["chtools", c] => Record::ChannelTools {
                ch: channel(c, head)?,
                text: Some(body_of(body)?),
            },
            ["chtools", c, "-"] if body.is_none() => Record::ChannelTools {
                ch: channel(c, head)?,
                text: None,
            },
            ["chparam", c, rest @ ..] if !rest.is_empty() && rest.len() % 2 == 0 => {
                Record::ChannelParams {
                    ch: channel(c, head)?,
                    params: param_pairs(rest, head)?,
                }
            }
            ["chptr", c, at] => Record::ChannelPointer {
                ch: channel(c, head)?,
                at: at.parse().map_err(|_| format!("bad pointer in '{head}'"))?,
            },
            ["chjog", c, f, rest @ ..] if matches!(rest, [] | ["rapid"]) => Record::ChannelJog {
                ch: channel(c, head)?,
                feed: match *f {
                    "default" => None,
                    f => Some(f.parse().map_err(|_| format!("bad jog feed in '{head}'"))?),
                },
                rapid: !rest.is_empty(),
            },
            ["posts", rest @ ..] if !rest.is_empty() && rest.len() % 3 == 0 => Record::Posts(
                rest.chunks(3)
                    .map(|p| {
                        let moving = match p[0] {
                            "moving" => true,
                            "rest" => false,
                            _ => return Err(format!("bad tool post state in '{head}'")),
                        };
                        let at =
                            |v: &str| v.parse().map_err(|_| format!("bad position in '{head}'"));
                        Ok(super::lathe::Post {
                            moving,
                            pos: [at(p[1])?, at(p[2])?],
                        })
                    })
                    .collect::<Result<_, String>>()?,
            ),
            ["chmdi", c] => Record::ChannelMdi {
                ch: channel(c, head)?,
                text: body.unwrap_or_default().to_string(),
            },
            ["parts", t, counts @ ..] if !counts.is_empty() => {
                let bad = || format!("bad part counter record '{head}'");
                Record::Parts {
                    target: t.parse().map_err(|_| bad())?,
                    counts: counts
                        .iter()
                        .map(|c| c.parse().map_err(|_| bad()))
                        .collect::<Result<_, _>>()?,
                }
            }
            _ => return Err(format!("unknown record '{head}'")),
        };
        Ok(rec)
    }
}

/// A program record's dialect field: ` fanuc` or ` linuxcnc`, nothing when not recorded.
fn dialect_field(d: Option<Dialect>) -> String {
    d.map_or(String::new(), |d| format!(" {}", d.name()))
}

/// A program record's dialect field read back (absent: not recorded, an older record).
fn dialect_of(d: Option<&&str>, head: &str) -> Result<Option<Dialect>, String> {
    match d {
        None => Ok(None),
        Some(&"fanuc") => Ok(Some(Dialect::Fanuc)),
        Some(&"linuxcnc") => Ok(Some(Dialect::LinuxCnc)),
        Some(_) => Err(format!("bad dialect in '{head}'")),
    }
}

/// A channel number as a record writes it (1 to 99), 0-based.
/// A parameter record's `N V` pairs (`param`, `chparam`), whole numbers as journaled.
fn param_pairs(rest: &[&str], head: &str) -> Result<Vec<(u16, i64)>, String> {
    let bad = || format!("bad parameter record '{head}'");
    rest.chunks(2)
        .map(|pair| {
            let n = pair[0].parse::<u16>().map_err(|_| bad())?;
            let v = pair[1].parse::<i64>().map_err(|_| bad())?;
            Ok((n, v))
        })
        .collect()
}

fn channel(c: &str, head: &str) -> Result<usize, String> {
    match c.parse::<usize>() {
        Ok(n @ 1..=99) => Ok(n - 1),
        _ => Err(format!("bad channel in '{head}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_record_round_trips() {
        let all = [
            Record::Edit {
                target: EditTarget::Program("TABLEB".into()),
                line: "2LIG00*".into(),
            },
            Record::Edit {
                target: EditTarget::Mdi,
                line: "".into(),
            },
            Record::Edit {
                target: EditTarget::ToolFile,
                line: "Sx$\ny".into(),
            },
            Record::Select("A".into()),
            Record::NewProgram {
                name: "B".into(),
                dialect: None,
            },
            Record::NewProgram {
                name: "O1.NGC".into(),
                dialect: Some(Dialect::Fanuc),
            },
            Record::ProgramRead {
                name: "C".into(),
                text: "P1 = (1, 2)\nDRL\n".into(),
                dialect: None,
            },
            Record::ProgramRead {
                name: "O1000.NGC".into(),
                text: "G65 P9010\nM30\n".into(),
                dialect: Some(Dialect::Fanuc),
            },
            Record::ProgramRead {
                name: "D.NGC".into(),
                text: "G0 X1\n".into(),
                dialect: Some(Dialect::LinuxCnc),
            },
            Record::ToolFile("T01\nT02\n".into()),
            Record::TCodes("T01 00106\n".into()),
            Record::Delete("OLD".into()),
            Record::ClearMdi,
            Record::TCode {
                t: 5,
                tool: Some(106),
            },
            Record::TCode { t: 7, tool: None },
            Record::Params(vec![(5321, -1), (5322, 100_000_000), (5220, 2_000_000)]),
            Record::ChannelProgram {
                ch: 2,
                name: "SYSTEM 3.NGC".into(),
                text: "G0 X1\n\nM30\n".into(),
                dialect: Some(Dialect::Fanuc),
            },
            Record::ChannelProgram {
                ch: 0,
                name: "E".into(),
                text: "".into(),
                dialect: None,
            },
            Record::ChannelTools {
                ch: 1,
                text: Some("tool 1 radius 0.4 tip 3 offset 0 0\n".into()),
            },
            Record::ChannelTools { ch: 0, text: None },
            Record::ChannelMdi {
                ch: 1,
                text: "G0 X30 Z20\nG0 X36\n".into(),
            },
            Record::ChannelMdi {
                ch: 0,
                text: String::new(),
            },
            Record::ChannelPointer { ch: 2, at: 417 },
            Record::ChannelJog {
                ch: 1,
                feed: Some(512_500_000),
                rapid: false,
            },
            Record::ChannelJog {
                ch: 0,
                feed: None,
                rapid: true,
            },
            Record::Posts(vec![
                super::super::lathe::Post {
                    moving: false,
                    pos: [35_000, 60_000],
                },
                super::super::lathe::Post {
                    moving: true,
                    pos: [-1_250, -59_999],
                },
            ]),
            Record::Parts {
                target: 5,
                counts: vec![1, 0, 2],
            },
        ];
        for r in all {
            assert_eq!(Record::decode(&r.encode()), Ok(r));
        }
        assert!(Record::decode("frobnicate").is_err());
        assert!(Record::decode("edit M").is_err());
        assert!(Record::decode("offset G60 0 0 0").is_err());
        assert!(Record::decode("offset G54 0 0.5 0").is_err());
        assert!(Record::decode("param").is_err());
        assert!(Record::decode("param 5221").is_err());
        assert!(Record::decode("param 5221 1.5").is_err());
        assert!(Record::decode("chprog 0\nA\n").is_err());
        assert!(Record::decode("chprog 1\nno name line").is_err());
        assert!(Record::decode("chtools x\n").is_err());
        assert!(Record::decode("chmdi 0\nG0 X1\n").is_err());
        assert!(Record::decode("chptr 1 -3").is_err());
        assert!(Record::decode("parts 5").is_err());
        assert!(Record::decode("read A fanu\nG0").is_err());
        assert!(Record::decode("new A fanuc linuxcnc").is_err());
        assert!(Record::decode("parts 5 1 -1").is_err());
    }

    #[test]
    fn a_program_record_written_before_the_dialect_was_kept_reads_without_one() {
        assert_eq!(
            Record::decode("read O1.NGC\nG0 X1\n"),
            Ok(Record::ProgramRead {
                name: "O1.NGC".into(),
                text: "G0 X1\n".into(),
                dialect: None
            })
        );
        assert_eq!(
            Record::decode("new P"),
            Ok(Record::NewProgram {
                name: "P".into(),
                dialect: None
            })
        );
        // A lathe channel's program likewise.
        assert_eq!(
            Record::decode("chprog 2\nA.NGC\nG0 X1\n"),
            Ok(Record::ChannelProgram {
                ch: 1,
                name: "A.NGC".into(),
                text: "G0 X1\n".into(),
                dialect: None
            })
        );
        assert!(Record::decode("chprog 2 fanuc x\nA.NGC\nG0 X1\n").is_err());
    }

    #[test]
    fn an_old_work_offset_record_reads_as_its_systems_parameters() {
        assert_eq!(
            Record::decode("offset G55 1 -2 3"),
            Ok(Record::Params(vec![(5241, 1), (5242, -2), (5243, 3)]))
        );
    }
}
