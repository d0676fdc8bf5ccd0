//! The recording's file, readable at every moment (docs/recording.md, "Interrupted runs").
//!
//! The MCAP writer builds each chunk in memory and writes it whole when it closes it, with its
//! message indexes; at once after that comes a commit: a **provisional end** written after them,
//! a `novanc.recording` metadata record saying `complete: false` and why, a data-end record and a
//! footer with no summary section. The next chunk is written over that end, and followed by a
//! new one; `close` ends the file after the real end (closing metadata, summary, footer). So a process
//! that dies at any moment (a second stop signal, SIGKILL, a crash) leaves a finished MCAP file
//! holding every committed chunk, which Python's `make_reader`, `mcap info` and the `mcap` crate
//! open as they are (a reader without a summary section reads the file from the start).
//!
//! The writers close a chunk (and so commit) when it holds `CHUNK_BYTES`, when it is
//! `CHUNK_AGE` old, and at once when a stop signal was noted (`interrupt_all`), so that the file
//! names the signal even if a second one ends the process before the recording is closed.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, Seek, SeekFrom, Write};
use std::os::unix::fs::FileExt;
use std::path::Path;
use std::time::{Duration, Instant};

/// Target uncompressed size of one MCAP chunk.
pub const CHUNK_BYTES: u64 = 4 * 1024 * 1024;

/// The oldest a chunk with messages gets before it is closed and committed: a process killed
/// outright loses at most this much of its recording (and what was still queued).
pub const CHUNK_AGE: Duration = Duration::from_secs(1);

/// Bytes of an MCAP Message record besides its data: opcode, length, channel id, sequence,
/// log time, publish time.
pub const MESSAGE_RECORD_OVERHEAD: u64 = 1 + 8 + 2 + 4 + 8 + 8;

/// What the provisional end says when no stop signal was noted: the process ended (killed,
/// crashed, the machine lost power) before it closed the recording.
pub const NOT_CLOSED: &str = "not closed: the process ended while recording";

/// The options of every novanc MCAP file: no compression, no automatic chunks (the writers
/// close them, so that they know what reached the file), chunks built in memory and written
/// whole (no seeking back into the file), the library named.
pub fn mcap_options() -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(None)
        .chunk_size(None)
        .disable_seeking(true)
        .profile("")
        .library(concat!("novanc ", env!("CARGO_PKG_VERSION")))
}

/// The `novanc.recording` metadata record (docs/recording.md, "Metadata records"): `complete`,
/// `dropped_events` when known, `interrupted` when the recording was cut short.
pub fn recording_metadata(
    complete: bool,
    dropped: Option<u64>,
    interrupted: Option<&str>,
) -> mcap::records::Metadata {
    let mut metadata = BTreeMap::from([("complete".to_string(), complete.to_string())]);
    if let Some(n) = dropped {
        metadata.insert("dropped_events".to_string(), n.to_string());
    }
    if let Some(why) = interrupted {
        metadata.insert("interrupted".to_string(), why.to_string());
    }
    mcap::records::Metadata {
        name: "novanc.recording".to_string(),
        metadata,
    }
}

/// Where a `RecordWriter` writes: a `RecordFile`, or (in tests) any seekable output.
pub trait RecordOutput: Write + Seek {
    /// Writes what is left and ends the output there; its length in bytes.
    fn close(&mut self) -> io::Result<u64> {
        self.flush()?;
        self.stream_position()
    }
}

/// An MCAP file that ends with a footer at every moment (see the module's documentation),
/// but for the moment of one write system call: what the MCAP writer writes between two
/// commits (a chunk, its message indexes) is kept in memory, and the commit (`flush`) writes
/// it with the new provisional end in one positioned write over the old end. (It was written
/// as it came, and a process killed between the chunk's write and the commit, a window that
/// a loaded machine's scheduler stretches, left a file cut inside a chunk.)
#[derive(Debug)]
pub struct RecordFile {
    file: File,
    /// Bytes of the MCAP stream in the file as of the last commit.
    committed: u64,
    /// Bytes of the MCAP stream written so far (the stream's position): the file's, and
    /// `pending` after them.
    written: u64,
    /// What was written since the last commit, not yet in the file.
    pending: Vec<u8>,
}

impl RecordFile {
    /// Creates (or empties) the file.
    pub fn create(path: &Path) -> io::Result<RecordFile> {
        Ok(RecordFile {
            file: File::create(path)?,
            committed: 0,
            written: 0,
            pending: Vec::new(),
        })
    }

    /// After a write error: the file put back as the last commit left it (its chunks and a
    /// provisional end, now naming the error), as far as the disk allows.
    fn put_back(&mut self, e: &io::Error) {
        let end = provisional_end(&format!("not closed: writing the file failed: {e}"));
        let _ = self.file.set_len(self.committed);
        let _ = self.file.write_all_at(&end, self.committed);
        self.written = self.committed;
        self.pending.clear();
    }
}

impl Write for RecordFile {
    /// Keeps `buf` for the next commit, which writes it over the provisional end.
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.pending.extend_from_slice(buf);
        self.written += buf.len() as u64;
        Ok(buf.len())
    }

    /// A commit (the MCAP writer flushes its output after it closed a chunk): the provisional
    /// end after what was written.
    fn flush(&mut self) -> io::Result<()> {
        let end = provisional_end(super::recorder::interrupted().unwrap_or(NOT_CLOSED));
        let n = self.pending.len();
        self.pending.extend_from_slice(&end);
        let r = self.file.write_all_at(&self.pending, self.committed);
        self.pending.truncate(n);
        match r {
            Ok(()) => {
                self.committed = self.written;
                self.pending.clear();
                Ok(())
            }
            Err(e) => {
                self.put_back(&e);
                Err(e)
            }
        }
    }
}

impl Seek for RecordFile {
    /// Only tells the position (the MCAP writer asks it for its indexes); it never seeks back.
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        match pos {
            SeekFrom::Current(0) => Ok(self.written),
            _ => Err(io::Error::new(
                io::ErrorKind::Unsupported,
                "a recording is written front to back",
            )),
        }
    }
}

impl RecordOutput for RecordFile {
    /// Ends the file after the real end (the MCAP writer's `finish` wrote it over the
    /// provisional one): cuts what a provisional end left beyond.
    fn close(&mut self) -> io::Result<u64> {
        if let Err(e) = self.file.write_all_at(&self.pending, self.committed) {
            self.put_back(&e);
            return Err(e);
        }
        self.pending.clear();
        self.file.set_len(self.written)?;
        self.committed = self.written;
        Ok(self.written)
    }
}

/// The provisional end: `novanc.recording` (`complete: false`, `interrupted: why`), a data end
/// (CRC 0: not computed), a footer with no summary section, and the magic.
pub fn provisional_end(why: &str) -> Vec<u8> {
    let meta = recording_metadata(false, None, Some(why));
    let mut body = Vec::new();
    push_string(&mut body, &meta.name);
    let mut map = Vec::new();
    for (k, v) in &meta.metadata {
        push_string(&mut map, k);
        push_string(&mut map, v);
    }
    body.extend_from_slice(&(map.len() as u32).to_le_bytes());
    body.extend_from_slice(&map);
    let mut out = Vec::with_capacity(body.len() + 64);
    push_record(&mut out, mcap::records::op::METADATA, &body);
    push_record(&mut out, mcap::records::op::DATA_END, &0u32.to_le_bytes());
    push_record(&mut out, mcap::records::op::FOOTER, &[0u8; 20]);
    out.extend_from_slice(mcap::MAGIC);
    out
}

fn push_string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

fn push_record(out: &mut Vec<u8>, op: u8, body: &[u8]) {
    out.push(op);
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
}

/// When the writers close their open chunk: it holds the size given, it is `CHUNK_AGE` old,
/// or a stop signal was noted since the last commit.
#[derive(Clone, Copy, Debug, Default)]
pub struct CommitClock {
    /// When the open chunk got its first message.
    opened: Option<Instant>,
    /// Whether the last commit's provisional end named the stop signal.
    told_interrupt: bool,
}

impl CommitClock {
    /// A message went into the open chunk.
    pub fn wrote(&mut self) {
        self.opened.get_or_insert_with(Instant::now);
    }

    /// Whether to close the open chunk, holding `bytes`, now.
    pub fn due(&self, bytes: u64, limit: u64) -> bool {
        bytes >= limit
            || self.opened.is_some_and(|t| t.elapsed() >= CHUNK_AGE)
            || (!self.told_interrupt && super::recorder::interrupted().is_some())
    }

    /// The open chunk was closed and committed.
    pub fn committed(&mut self) {
        self.opened = None;
        self.told_interrupt = super::recorder::interrupted().is_some();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("novanc-file-{name}-{}.mcap", std::process::id()))
    }

    /// The `novanc.recording` metadata and the message count a reader gets out of `bytes`,
    /// checking that the file ends with a footer (no `IgnoreEndMagic`).
    fn read(bytes: &[u8]) -> (BTreeMap<String, String>, usize) {
        let n = mcap::MessageStream::new_with_options(
            bytes,
            mcap::read::Options::ValidateChunkCrcs.into(),
        )
        .unwrap()
        .collect::<Result<Vec<_>, _>>()
        .unwrap()
        .len();
        let meta = mcap::read::LinearReader::new(bytes)
            .unwrap()
            .filter_map(|r| match r.unwrap() {
                mcap::records::Record::Metadata(m) if m.name == "novanc.recording" => {
                    Some(m.metadata)
                }
                _ => None,
            })
            .last()
            .unwrap();
        (meta, n)
    }

    fn message(w: &mut mcap::Writer<RecordFile>, ch: u16, i: u32) {
        let h = mcap::records::MessageHeader {
            channel_id: ch,
            sequence: i,
            log_time: u64::from(i),
            publish_time: u64::from(i),
        };
        w.write_to_known_channel(&h, b"{\"event\":\"key START\"}")
            .unwrap();
    }

    #[test]
    fn the_file_is_a_finished_mcap_after_every_commit_and_only_then() {
        let path = temp("commits");
        let mut w = mcap_options()
            .create(RecordFile::create(&path).unwrap())
            .unwrap();
        let s = w
            .add_schema("novanc.PanelEvent", "jsonschema", b"{}")
            .unwrap();
        let ch = w
            .add_channel(s, "/panel/event", "json", &BTreeMap::new())
            .unwrap();
        w.flush().unwrap();
        let (meta, n) = read(&std::fs::read(&path).unwrap());
        assert_eq!((meta["complete"].as_str(), n), ("false", 0));
        assert_eq!(meta["interrupted"], NOT_CLOSED);
        for i in 0..10 {
            message(&mut w, ch, i);
        }
        // Not committed: the file still ends where the last commit left it.
        assert_eq!(read(&std::fs::read(&path).unwrap()).1, 0);
        w.flush().unwrap();
        assert_eq!(read(&std::fs::read(&path).unwrap()).1, 10);
        message(&mut w, ch, 10);
        w.flush().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(read(&bytes).1, 11);
        assert_eq!(mcap::Summary::read(&bytes).unwrap(), None);
        // The real end replaces the provisional one.
        w.write_metadata(&recording_metadata(true, Some(0), None))
            .unwrap();
        w.finish().unwrap();
        let len = w.into_inner().close().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(bytes.len() as u64, len);
        let (meta, n) = read(&bytes);
        assert_eq!((meta["complete"].as_str(), n), ("true", 11));
        assert!(!meta.contains_key("interrupted"));
        let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
        assert_eq!(summary.stats.unwrap().message_count, 11);
    }

    #[test]
    fn a_chunk_is_due_at_its_size_or_its_age() {
        let mut c = CommitClock::default();
        assert!(!c.due(0, 100));
        assert!(c.due(100, 100));
        c.wrote();
        assert!(!c.due(10, 100));
        c.opened = Instant::now().checked_sub(CHUNK_AGE);
        assert!(c.due(10, 100));
        c.committed();
        assert!(!c.due(10, 100));
    }
}
