//! The journal `journal.log`: every accepted change, appended as a framed record and fsynced
//! before the operator is told it was accepted. Its first record, `novanc-journal 1 GEN`, names
//! the snapshot generation it continues; a journal of an older generation is already in the
//! snapshot and is ignored.

use super::frame;
use super::fsutil::write_atomic;
use super::record::Record;
use std::fs::{File, OpenOptions};
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
}

/// The header payload of a journal continuing generation `gen`.
fn header(gen: u64) -> String {
    format!("novanc-journal 1 {gen}")
}

impl Journal {
    /// Creates an empty journal continuing generation `gen` (atomically replacing any old one).
    pub fn create(dir: &Path, gen: u64) -> io::Result<Journal> {
        let path = dir.join(JOURNAL);
        write_atomic(&path, &frame::encode(header(gen).as_bytes()))?;
        Journal::open_append(&path)
    }

    /// Opens an existing journal for appending after its last byte.
    pub fn open_append(path: &Path) -> io::Result<Journal> {
        let file = OpenOptions::new().append(true).open(path)?;
        let len = file.metadata()?.len();
        Ok(Journal {
            file,
            len,
            records: 0,
        })
    }

    /// Appends one record and waits until it is on disk. On failure the file is cut back to
    /// its good length, so a half-written record never hides the ones that follow.
    pub fn append(&mut self, rec: &Record) -> io::Result<()> {
        let bytes = frame::encode(rec.encode().as_bytes());
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
                let _ = self.file.set_len(self.len);
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
    /// The records that checked, in order.
    pub records: Vec<Record>,
    /// Where and why reading stopped early, in the operator's words.
    pub damage: Option<String>,
}

/// Reads the journal in `dir`; None if there is none.
pub fn read(dir: &Path) -> io::Result<Option<JournalRead>> {
    let data = match std::fs::read(dir.join(JOURNAL)) {
        Ok(d) => d,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e),
    };
    let d = frame::decode(&data);
    let mut out = JournalRead::default();
    let skipped = data.len() - d.good_len;
    let mut recs = d.records.iter();
    let head = recs.next().and_then(|h| std::str::from_utf8(h).ok());
    let gen = head.and_then(|h| h.strip_prefix("novanc-journal 1 ")?.parse::<u64>().ok());
    if gen.is_none() {
        out.damage = Some(format!(
            "the journal header is unreadable; all {} bytes of it were skipped",
            data.len()
        ));
        return Ok(Some(out));
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
                return Ok(Some(out));
            }
        }
    }
    if let Some(dmg) = d.damage {
        out.damage = Some(format!(
            "journal record {} at byte {} is damaged ({}); it and the {} bytes after it were skipped",
            dmg.record.max(1),
            dmg.offset,
            dmg.reason,
            skipped
        ));
    }
    Ok(Some(out))
}
