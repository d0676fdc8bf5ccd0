//! The alarm and message history and the counters, kept in the state directory beside the
//! stores (docs/stores.md, "History and counters").
//!
//! - `messages.log`: one framed record per message (`@ LEN CRC32`, as the journal), the payload
//!   `MACHINE_NS@WALL_S KIND TEXT` (machine time in ns, the wall clock in seconds since 1970;
//!   files written before the wall clock was kept have `MACHINE_NS` alone); appended and fdatasynced as each message is shown, so the history
//!   survives a restart and a kill. When it passes [`MAX_BYTES`] it is rewritten (atomically)
//!   with its newest [`KEEP`] messages. A damaged tail is read around, as the journal's is.
//! - `counters`: the part counter, its target, the last cycle time and the run hours, one line of
//!   numbers written atomically (temporary file, fsync, rename) at each change.
//!
//! These are not operator data: a write that fails is reported, never fatal, and never blocks
//! the machine.

use super::frame;
use super::fsutil;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The history file in the state directory.
pub const MESSAGES: &str = "messages.log";
/// The counters file in the state directory.
pub const COUNTERS: &str = "counters";
/// The history is rewritten with its newest [`KEEP`] messages once it passes this size.
pub const MAX_BYTES: u64 = 1 << 20;
/// Messages kept when the history is rewritten.
pub const KEEP: usize = 1000;

/// What kind of message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A fault: E-STOP, a travel limit, a program that does not translate.
    Alarm,
    /// Anything else shown on the message line.
    Message,
}

/// One entry of the history.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Machine time when it was shown, ns.
    pub machine_ns: u64,
    /// The wall clock when it was shown, seconds since 1970 (None in old files).
    pub wall_s: Option<u64>,
    /// Alarm or message.
    pub kind: Kind,
    /// The full text.
    pub text: String,
}

impl Entry {
    fn encode(&self) -> String {
        let k = match self.kind {
            Kind::Alarm => "A",
            Kind::Message => "M",
        };
        match self.wall_s {
            Some(w) => format!("{}@{w} {k} {}", self.machine_ns, self.text),
            None => format!("{} {k} {}", self.machine_ns, self.text),
        }
    }

    fn decode(payload: &[u8]) -> Option<Entry> {
        let s = std::str::from_utf8(payload).ok()?;
        let (t, rest) = s.split_once(' ')?;
        let (k, text) = rest.split_once(' ').unwrap_or((rest, ""));
        let (machine, wall) = match t.split_once('@') {
            Some((m, w)) => (m, Some(w.parse().ok()?)),
            None => (t, None),
        };
        Some(Entry {
            machine_ns: machine.parse().ok()?,
            wall_s: wall,
            kind: match k {
                "A" => Kind::Alarm,
                "M" => Kind::Message,
                _ => return None,
            },
            text: text.to_string(),
        })
    }
}

/// The alarm and message history of a state directory.
#[derive(Debug)]
pub struct History {
    path: PathBuf,
    entries: Vec<Entry>,
    bytes: u64,
    /// The last write failed: the next failures are not said again until one succeeds.
    failing: bool,
}

impl History {
    /// Reads the history kept in `dir` (none yet: empty). Returns it and a warning if part of
    /// the file could not be read.
    pub fn open(dir: &Path) -> (History, Option<String>) {
        let path = dir.join(MESSAGES);
        let data = std::fs::read(&path).unwrap_or_default();
        let d = frame::decode(&data);
        let entries: Vec<Entry> = d.records.iter().filter_map(|r| Entry::decode(r)).collect();
        let warning = d.damage.map(|dmg| {
            format!(
                "the message history {} is damaged after {} messages ({}); the rest was not read",
                path.display(),
                dmg.record,
                dmg.reason
            )
        });
        let bytes = d.good_len as u64;
        let mut h = History {
            path,
            entries,
            bytes,
            failing: false,
        };
        if warning.is_some() {
            // Keep what was read; the damaged tail is written over.
            let _ = h.rewrite();
        }
        (h, warning)
    }

    /// The entries, oldest first.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// Appends an entry and makes it durable; the error says why it could not be kept. Of
    /// failures in a row only the first is an error (it is shown to the operator once, not
    /// after every message, on a read-only or full disk).
    pub fn push(&mut self, e: Entry) -> Result<(), String> {
        let r = self.append(e);
        let first = !self.failing;
        self.failing = r.is_err();
        match r {
            Err(e) if first => Err(e),
            _ => Ok(()),
        }
    }

    fn append(&mut self, e: Entry) -> Result<(), String> {
        let rec = frame::encode(e.encode().as_bytes());
        self.entries.push(e);
        if self.bytes + rec.len() as u64 > MAX_BYTES {
            let from = self.entries.len().saturating_sub(KEEP);
            self.entries.drain(..from);
            return self.rewrite();
        }
        let Ok(mut f) = fsutil::open_append(&self.path, true) else {
            // Not a file that can be appended to (a symlink, a special file): replaced whole.
            return self.rewrite();
        };
        let r = f.write_all(&rec).and_then(|_| f.sync_data());
        if r.is_err() {
            // A record cut short would hide the ones appended after it.
            let _ = f.set_len(self.bytes);
        }
        match r {
            Ok(()) => {
                self.bytes += rec.len() as u64;
                Ok(())
            }
            Err(e) => Err(format!("the message history was not saved: {e}")),
        }
    }

    fn rewrite(&mut self) -> Result<(), String> {
        let mut data = Vec::new();
        for e in &self.entries {
            data.extend(frame::encode(e.encode().as_bytes()));
        }
        fsutil::write_atomic(&self.path, &data)
            .map_err(|e| format!("the message history was not saved: {e}"))?;
        self.bytes = data.len() as u64;
        Ok(())
    }
}

/// The counters: parts made, the target, the last cycle time and the run hours.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Parts made: runs of program memory that reached their end.
    pub parts: u64,
    /// The part counter's target (0: none).
    pub target: u64,
    /// Machine time of the last run that reached its end, ns.
    pub last_cycle_ns: u64,
    /// Machine time with a run in progress, in total, ns.
    pub run_ns: u64,
}

impl Counters {
    /// `ns` of machine time with a run under way, added to the run hours.
    pub fn ran(&mut self, ns: u64) {
        self.run_ns = self.run_ns.saturating_add(ns);
    }

    /// One part made, in a cycle of `cycle_ns` of machine time (at least 1: 0 means none).
    pub fn made(&mut self, cycle_ns: u64) {
        self.parts += 1;
        self.last_cycle_ns = cycle_ns.max(1);
    }

    /// The last cycle and the run hours as every console's POS page shows them:
    /// `CYCLE 12.345 s RUN 0.01 h`.
    pub fn times(&self) -> String {
        format!(
            "CYCLE {:.3} s RUN {:.2} h",
            self.last_cycle_ns as f64 * 1e-9,
            self.run_ns as f64 / 3.6e12
        )
    }

    /// Reads the counters kept in `dir` (zero if there are none; a damaged file says so).
    pub fn open(dir: &Path) -> (Counters, Option<String>) {
        let path = dir.join(COUNTERS);
        let Ok(text) = std::fs::read_to_string(&path) else {
            return (Counters::default(), None);
        };
        let n: Vec<u64> = text
            .split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect();
        match n.as_slice() {
            [parts, target, last, run] => (
                Counters {
                    parts: *parts,
                    target: *target,
                    last_cycle_ns: *last,
                    run_ns: *run,
                },
                None,
            ),
            _ => (
                Counters::default(),
                Some(format!(
                    "the counters {} could not be read; they start again at 0",
                    path.display()
                )),
            ),
        }
    }

    /// Writes the counters to `dir` atomically.
    pub fn save(&self, dir: &Path) -> Result<(), String> {
        let text = format!(
            "{} {} {} {}\n",
            self.parts, self.target, self.last_cycle_ns, self.run_ns
        );
        fsutil::write_atomic(&dir.join(COUNTERS), text.as_bytes())
            .map_err(|e| format!("the counters were not saved: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("novanc-hist-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn the_history_survives_a_reopen_and_a_damaged_tail() {
        let d = dir("reopen");
        let (mut h, w) = History::open(&d);
        assert!(w.is_none() && h.entries().is_empty());
        for i in 0..5 {
            h.push(Entry {
                machine_ns: i,
                wall_s: (i > 1).then_some(1_790_000_000 + i),
                kind: if i % 2 == 0 {
                    Kind::Alarm
                } else {
                    Kind::Message
                },
                text: format!("message {i} with spaces"),
            })
            .unwrap();
        }
        let (h2, _) = History::open(&d);
        assert_eq!(h2.entries(), h.entries());
        let mut data = std::fs::read(d.join(MESSAGES)).unwrap();
        let n = data.len();
        data.truncate(n - 3);
        std::fs::write(d.join(MESSAGES), &data).unwrap();
        let (h3, w) = History::open(&d);
        assert_eq!(h3.entries().len(), 4);
        assert!(w.unwrap().contains("damaged"));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_history_that_is_a_symlink_is_replaced_not_written_through() {
        let d = dir("link");
        let outside = d.join("outside");
        std::fs::write(&outside, b"").unwrap(); // a valid, empty history
        std::os::unix::fs::symlink(&outside, d.join(MESSAGES)).unwrap();
        let (mut h, _) = History::open(&d);
        for i in 0..3 {
            h.push(Entry {
                machine_ns: i,
                wall_s: None,
                kind: Kind::Message,
                text: format!("m{i}"),
            })
            .unwrap();
        }
        assert_eq!(std::fs::read(&outside).unwrap(), b"");
        let (h2, _) = History::open(&d);
        assert_eq!(h2.entries().len(), 3);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_long_history_keeps_its_newest_messages() {
        let d = dir("long");
        let (mut h, _) = History::open(&d);
        let text = "x".repeat(900);
        for i in 0..1300 {
            h.push(Entry {
                machine_ns: i,
                wall_s: Some(1_790_000_000),
                kind: Kind::Message,
                text: text.clone(),
            })
            .unwrap();
        }
        assert!(std::fs::metadata(d.join(MESSAGES)).unwrap().len() <= MAX_BYTES);
        let (h2, _) = History::open(&d);
        assert_eq!(h2.entries().last().map(|e| e.machine_ns), Some(1299));
        assert!(h2.entries().len() <= 1300 && h2.entries().len() >= KEEP);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn counters_round_trip() {
        let d = dir("counters");
        let c = Counters {
            parts: 7,
            target: 100,
            last_cycle_ns: 226_000_000_000,
            run_ns: 1_000_000_000_000,
        };
        c.save(&d).unwrap();
        assert_eq!(Counters::open(&d), (c, None));
        std::fs::write(d.join(COUNTERS), "garbage").unwrap();
        let (z, w) = Counters::open(&d);
        assert_eq!(z, Counters::default());
        assert!(w.is_some());
        let _ = std::fs::remove_dir_all(&d);
    }
}
