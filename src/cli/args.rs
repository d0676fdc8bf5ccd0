//! A small command-line parser: positional arguments, `--flag`, `--opt VALUE` (or
//! `--opt=VALUE`), and repeatable options such as `-c CMD`; and the machine every subcommand
//! takes (`--machine`, `--dialect`).

use crate::lathe::desc::{load, LatheDesc, MachineDesc};
use crate::settings::{Dialect, MachineSettings};
use std::collections::HashMap;

/// How one option is spelled and whether it takes a value.
#[derive(Clone, Copy, Debug)]
pub struct Opt {
    /// The spelling, with its dashes: `--tools`, `-c`.
    pub name: &'static str,
    /// Whether a value follows.
    pub takes_value: bool,
}

impl Opt {
    /// An option that takes a value (`--tools TAPE`).
    pub const fn value(name: &'static str) -> Opt {
        Opt {
            name,
            takes_value: true,
        }
    }

    /// A flag, with no value (`--write`).
    pub const fn flag(name: &'static str) -> Opt {
        Opt {
            name,
            takes_value: false,
        }
    }
}

/// The value of option `name`: given inline (`--opt=V`) or the next argument (`--opt V`, which
/// moves `i` past it).
fn value_of(
    argv: &[String],
    i: &mut usize,
    name: &str,
    inline: Option<String>,
) -> Result<String, String> {
    if let Some(v) = inline {
        return Ok(v);
    }
    let v = argv
        .get(*i)
        .ok_or_else(|| format!("option '{name}' needs a value"))?;
    *i += 1;
    Ok(v.clone())
}

/// Options taken out of a command line: each spelling with its value, in order.
pub type Taken = Vec<(&'static str, String)>;

/// Takes the options `names` (each with a value, `--opt V` or `--opt=V`) out of `argv`, before
/// a subcommand's own parse sees the rest: the options every subcommand shares
/// (`--mtconnect`). Returns them in order, and the other arguments.
pub fn take_values(
    argv: &[String],
    names: &[&'static str],
) -> Result<(Taken, Vec<String>), String> {
    let mut taken = Vec::new();
    let mut rest = Vec::new();
    let mut i = 0;
    while i < argv.len() {
        let a = &argv[i];
        i += 1;
        let (spelled, inline) = match a.split_once('=') {
            Some((n, v)) => (n, Some(v.to_string())),
            None => (a.as_str(), None),
        };
        match names.iter().find(|n| **n == spelled) {
            Some(name) => taken.push((*name, value_of(argv, &mut i, name, inline)?)),
            None => rest.push(a.clone()),
        }
    }
    Ok((taken, rest))
}

/// The machine a command acts on (docs/cli.md): `--machine NAME|FILE` and `--dialect
/// fanuc|linuxcnc`, taken out of its arguments the same way by every subcommand and both
/// front ends.
#[derive(Clone, Debug)]
// Made once when a command starts: a mill's settings inline cost nothing worth a box.
#[allow(clippy::large_enum_variant)]
pub enum Machine {
    /// The machining centre: its description's settings when `--machine` named one (else the
    /// built-in centre), and the dialect asked for.
    Centre(Option<MachineSettings>, Option<Dialect>),
    /// A lathe, `--dialect` given to each channel whose description says no dialect.
    Lathe(LatheDesc),
}

impl Machine {
    /// The centre's settings: the description's (else the defaults), in the dialect asked for.
    pub fn settings(&self) -> MachineSettings {
        let mut s = MachineSettings::default();
        if let Machine::Centre(Some(m), _) = self {
            s = m.clone();
        }
        if let Machine::Centre(_, Some(d)) = self {
            s.dialect = *d;
        }
        s
    }

    /// Puts the centre's description (`settings`, the settings `novanc run` and `translate`
    /// take) and the dialect asked for into a console's settings, keeping what the console's
    /// own options chose: the interpolator and its L (`--interpolator`, `--ep-l`). Nothing for
    /// a lathe. Until stop 54 it copied the description field by field and forgot what was
    /// added since: the rotary axes until stop 53 (a console on `--machine centre4` had no A),
    /// their own rates at stop 54 (a console's table turned as fast as X Y Z went, where
    /// `novanc run`'s kept to its rate: seen in the window).
    pub fn apply(&self, s: &mut MachineSettings) {
        let Machine::Centre(desc, dialect) = self else {
            return;
        };
        if let Some(m) = desc {
            let own = (s.interpolator, s.ep_l_pulses);
            *s = m.clone();
            (s.interpolator, s.ep_l_pulses) = own;
        }
        if let Some(d) = dialect {
            s.dialect = *d;
        }
    }
}

/// Takes `--dialect fanuc|linuxcnc` (docs/gcode.md "Fanuc dialect") and `--machine NAME|FILE`
/// (`citizen`, `centre`, `centre4` or a description file: docs/lathe.md "Machine
/// description") out of `argv`: the machine, and the other arguments.
pub fn take_machine(argv: &[String]) -> Result<(Machine, Vec<String>), String> {
    let (taken, rest) = take_values(argv, &["--dialect"])?;
    let dialect = match taken.last() {
        Some((_, v)) => Some(Dialect::parse(v).map_err(|e| format!("--{e}"))?),
        None => None,
    };
    let (taken, rest) = take_values(&rest, &["--machine"])
        .map_err(|_| "--machine needs a value: citizen, centre or a description file")?;
    let Some((_, name)) = taken.last() else {
        return Ok((Machine::Centre(None, dialect), rest));
    };
    let machine = match load(name).map_err(|e| format!("--machine: {e}"))? {
        MachineDesc::Mill(s) => Machine::Centre(Some(s), dialect),
        MachineDesc::Lathe(mut d) => {
            // `--dialect` says it for the channels whose description does not.
            for ch in &mut d.channels {
                ch.dialect = ch.dialect.or(dialect);
            }
            Machine::Lathe(d)
        }
    };
    Ok((machine, rest))
}

/// Parsed arguments.
#[derive(Clone, Debug, Default)]
pub struct Args {
    /// Positional arguments, in order.
    pub positional: Vec<String>,
    values: HashMap<&'static str, Vec<String>>,
    flags: Vec<&'static str>,
}

impl Args {
    /// Parses `argv` (without the program and subcommand names) against `opts`.
    pub fn parse(argv: &[String], opts: &[Opt]) -> Result<Args, String> {
        let mut a = Args::default();
        let mut i = 0;
        let mut only_positional = false;
        while i < argv.len() {
            let s = &argv[i];
            i += 1;
            if only_positional || !s.starts_with('-') || s == "-" {
                a.positional.push(s.clone());
                continue;
            }
            if s == "--" {
                only_positional = true;
                continue;
            }
            let (name, inline) = match s.split_once('=') {
                Some((n, v)) if n.starts_with("--") => (n, Some(v.to_string())),
                _ => (s.as_str(), None),
            };
            let opt = opts
                .iter()
                .find(|o| o.name == name)
                .ok_or_else(|| format!("unknown option '{name}' (see --help)"))?;
            if opt.takes_value {
                let v = value_of(argv, &mut i, name, inline)?;
                a.values.entry(opt.name).or_default().push(v);
            } else {
                if inline.is_some() {
                    return Err(format!("option '{name}' takes no value"));
                }
                a.flags.push(opt.name);
            }
        }
        Ok(a)
    }

    /// Whether a flag was given.
    pub fn flag(&self, name: &str) -> bool {
        self.flags.contains(&name)
    }

    /// The last value of an option.
    pub fn value(&self, name: &str) -> Option<&str> {
        self.values.get(name)?.last().map(|s| s.as_str())
    }

    /// Every value of a repeatable option, in order.
    pub fn values(&self, name: &str) -> &[String] {
        self.values.get(name).map(|v| v.as_slice()).unwrap_or(&[])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn shared_options_are_taken_out_before_the_subcommands_parse() {
        let (taken, rest) = take_values(
            &v(&["prog.ap", "--m", "7878", "--record=x", "--w=2", "--m=9"]),
            &["--m", "--w"],
        )
        .unwrap();
        assert_eq!(
            taken,
            vec![
                ("--m", "7878".into()),
                ("--w", "2".into()),
                ("--m", "9".into())
            ]
        );
        assert_eq!(rest, v(&["prog.ap", "--record=x"]));
        assert_eq!(
            take_values(&v(&["a", "--m"]), &["--m"]).unwrap_err(),
            "option '--m' needs a value"
        );
    }

    #[test]
    fn parses_positional_values_and_flags() {
        let opts = [
            Opt {
                name: "-c",
                takes_value: true,
            },
            Opt {
                name: "--write",
                takes_value: false,
            },
            Opt {
                name: "--tools",
                takes_value: true,
            },
        ];
        let a = Args::parse(
            &v(&["f", "-c", "1L", "--write", "-c", "I*", "--tools=t.tt"]),
            &opts,
        )
        .unwrap();
        assert_eq!(a.positional, v(&["f"]));
        assert_eq!(a.values("-c"), &v(&["1L", "I*"])[..]);
        assert!(a.flag("--write"));
        assert_eq!(a.value("--tools"), Some("t.tt"));
        assert!(Args::parse(&v(&["--bogus"]), &opts)
            .unwrap_err()
            .contains("unknown option"));
        assert!(Args::parse(&v(&["-c"]), &opts)
            .unwrap_err()
            .contains("needs a value"));
    }
}
