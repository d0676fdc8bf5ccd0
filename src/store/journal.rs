//! The journal `journal.log`: every accepted change, appended as a framed record and fsynced
//! before the operator is told it was accepted. Its first record, `novanc-journal 2 GEN`, names
//! the snapshot generation it continues; a journal of an older generation is already in the
//! snapshot and is ignored. Format 2 writes every record twice in a row, so one damaged copy
//! loses nothing; format 1 journals (one copy) are still read (docs/stores.md).

use super::frame;
use super::fsutil::{open_append, write_atomic};
use super::record::Record;
use std::fs::File;
use std::io::{self, Write};
use std::path::Path;

/// The journal file name in the state directory.
pub const JOURNAL: &str = "journal.log";

/// An open journal, appending.
#[derive(Debug)]
pub struct Journal {
    file: File,
    /// Length of the good part (where the next record goes).
    pub len: u64,
    /// Records appended since the journal was created or opened.
    pub records: usize,
    /// Set when a failed append could not be cut back: nothing more may go after it.
    pub broken: bool,
}

/// The header payload of a journal continuing generation `gen`.
fn header(gen: u64) -> String {
    format!("novanc-journal 2 {gen}")
}

impl Journal {
    /// Creates an empty journal continuing generation `gen` (atomically replacing any old one).
    pub fn create(dir: &Path, gen: u64) -> io::Result<Journal> {
        let path = dir.join(JOURNAL);
        write_atomic(&path, &frame::encode_pair(header(gen).as_bytes()))?;
        Journal::open_append(&path)
    }

    /// Opens an existing journal for appending after its last byte.
    pub fn open_append(path: &Path) -> io::Result<Journal> {
        let file = open_append(path, false)?;
        let len = file.metadata()?.len();
        Ok(Journal {
            file,
            len,
            records: 0,
            broken: false,
        })
    }

    /// Appends one record (both copies) and waits until it is on disk. On failure the file is
    /// cut back to its good length, so a half-written record never hides the ones that follow;
    /// if even that fails, the journal is marked `broken`.
    pub fn append(&mut self, rec: &Record) -> io::Result<()> {
        if self.broken {
            return Err(io::Error::other("the journal needs rewriting"));
        }
        let bytes = frame::encode_pair(rec.encode().as_bytes());
        let r = self
            .file
            .write_all(&bytes)
            .and_then(|_| self.file.sync_data());
        match r {
            Ok(()) => {
                self.len += bytes.len() as u64;
                self.records += 1;
                Ok(())
            }
            Err(e) => {
                if self
                    .file
                    .set_len(self.len)
                    .and_then(|_| self.file.sync_data())
                    .is_err()
                {
                    self.broken = true;
                }
                Err(e)
            }
        }
    }
}

/// What was found in a journal file.
#[derive(Debug, Default)]
pub struct JournalRead {
    /// The generation its header names (None if the header is unreadable).
    pub gen: Option<u64>,
    /// Whether it is format 1 (one copy of each record).
    pub old_format: bool,
    /// The records that read, in order, up to the first that could not be read.
    pub records: Vec<Record>,
    /// Damaged copies whose other copy was used: nothing lost.
    pub repaired: Vec<String>,
    /// Where and why reading stopped early, in the operator's words.
    pub damage: Option<String>,
    /// Records found after the damage: they exist, but follow one that is lost, so they
    /// cannot be replayed (their edits are lost).
    pub lost_after: usize,
}

/// Reads a journal's bytes.
pub fn parse(data: &[u8]) -> JournalRead {
    let mut out = JournalRead::default();
    let old = frame::first_record(data).is_some_and(|r| r.starts_with(b"novanc-journal 1 "));
    let (recs, damage, good_len, after) = if old {
        let d = frame::decode(data);
        (d.records, d.damage, d.good_len, 0)
    } else {
        let d = frame::decode_paired(data);
        out.repaired = d
            .repaired
            .iter()
            .map(|r| {
                let which = match r.record {
                    0 => "the journal header".to_string(),
                    n => format!("journal record {n}"),
                };
                if r.reason.starts_with("its second copy") {
                    format!(
                        "{which}: {} (at byte {}); its first copy was used, nothing is lost",
                        r.reason, r.offset
                    )
                } else {
                    format!(
                        "{which} at byte {} was damaged ({}); its second copy was used, nothing is lost",
                        r.offset, r.reason
                    )
                }
            })
            .collect();
        (d.records, d.damage, d.good_len, d.after.len())
    };
    out.old_format = old;
    let skipped = data.len() - good_len;
    let mut recs = recs.iter();
    let head = recs.next().and_then(|h| std::str::from_utf8(h).ok());
    let prefix = if old {
        "novanc-journal 1 "
    } else {
        "novanc-journal 2 "
    };
    let gen = head.and_then(|h| h.strip_prefix(prefix)?.parse::<u64>().ok());
    if gen.is_none() {
        let n = recs.len() + after;
        out.damage = Some(format!(
            "the journal header is unreadable; all {} bytes of it were skipped ({n} records in it are lost)",
            data.len()
        ));
        out.lost_after = n;
        return out;
    }
    out.gen = gen;
    for (i, r) in recs.enumerate() {
        match std::str::from_utf8(r)
            .map_err(|_| "it is not text".to_string())
            .and_then(Record::decode)
        {
            Ok(rec) => out.records.push(rec),
            Err(e) => {
                out.damage = Some(format!(
                    "journal record {} cannot be read ({e}); it and the records after it were skipped",
                    i + 1
                ));
                return out;
            }
        }
    }
    if let Some(dmg) = damage {
        let what = if after > 0 {
            out.lost_after = after;
            format!(
                "in both copies; it and the {after} records after it cannot be replayed (their edits are lost)"
            )
        } else {
            format!("it and the {skipped} bytes after it were skipped")
        };
        out.damage = Some(format!(
            "journal record {} at byte {} is damaged ({}); {what}",
            dmg.record.max(1),
            dmg.offset,
            dmg.reason
        ));
    }
    out
}

/// Reads the journal in `dir`; None if there is none.
pub fn read(dir: &Path) -> io::Result<Option<JournalRead>> {
    match std::fs::read(dir.join(JOURNAL)) {
        Ok(d) => Ok(Some(parse(&d))),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}
