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
/// whole (no seeking back into the file), no CRC of the data section (the file holds records
/// the MCAP writer does not see: `RecordFile`), the library named.
pub fn mcap_options() -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(None)
        .chunk_size(None)
        .disable_seeking(true)
        .calculate_data_section_crc(false)
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

/// Where a `RecordFile` puts its bytes: the file, or (in tests) a log of every write.
pub trait Disk {
    /// Writes all of `buf` at byte `at` (past the end: the gap reads as zeros).
    fn write_at(&mut self, buf: &[u8], at: u64) -> io::Result<()>;
    /// Cuts (or extends) the file to `len` bytes.
    fn set_len(&mut self, len: u64) -> io::Result<()>;
}

impl Disk for File {
    fn write_at(&mut self, buf: &[u8], at: u64) -> io::Result<()> {
        self.write_all_at(buf, at)
    }

    fn set_len(&mut self, len: u64) -> io::Result<()> {
        File::set_len(self, len)
    }
}

/// The size of a page: the unit in which Linux copies a write into a file, and so the unit in
/// which SIGKILL can cut one short. A write that stays inside one page is done whole or not at
/// all (the kernel tests for a fatal signal before each page it copies).
pub const PAGE: u64 = 4096;

/// The opcode a provisional end takes once the next commit is in place: a private record
/// (opcodes 0x80–0xFF), which every MCAP reader skips by its length.
pub const SKIPPED_END: u8 = 0x80;

/// An MCAP file that ends with a footer at every moment (see the module's documentation),
/// even when a stop signal cuts one of its writes short. What the MCAP writer writes between
/// two commits (a chunk, its message indexes) is kept in memory, and a commit (`flush`) puts
/// it in the file in three writes, each of which may be cut:
///
/// 1. the new provisional end, after where the chunk will end, placed (by a padding record
///    before it) inside one page, so that this write is whole or absent;
/// 2. the chunk (and the padding) between the old provisional end and the new one;
/// 3. the old provisional end's first 9 bytes (its opcode and length, again inside one page)
///    turned into the header of a `SKIPPED_END` record as long as it was.
///
/// Until the third write the file reads as the last commit left it: a reader from the start
/// stops at the old end's footer, and a reader that starts from the file's last bytes finds
/// the new end's footer, which has no summary and sends it to read from the start. After it,
/// both read the new chunk. (Before, one write put the chunk and the new end over the old end;
/// SIGKILL during it left a file that ended inside a chunk.) The skipped ends stay in the
/// file, about 170 bytes per commit; the data section has no CRC (`mcap_options`), since the
/// MCAP writer does not see them.
#[derive(Debug)]
pub struct RecordFile<D: Disk = File> {
    disk: D,
    /// The provisional end in force: where it starts and its length (none before the first
    /// commit).
    end: Option<(u64, u64)>,
    /// Bytes of the MCAP stream written so far (the stream's position): the file's through
    /// the provisional end in force (which stays in the stream as a skipped record), and
    /// `pending` after them.
    written: u64,
    /// What was written since the last commit, not yet in the file.
    pending: Vec<u8>,
    /// Where what the last commit wrote ends, before the padding and the provisional end.
    content_end: u64,
}

impl RecordFile {
    /// Creates (or empties) the file.
    pub fn create(path: &Path) -> io::Result<RecordFile> {
        Ok(RecordFile::on(File::create(path)?))
    }
}

impl<D: Disk> RecordFile<D> {
    /// A recording written to `disk`, which is empty.
    pub fn on(disk: D) -> RecordFile<D> {
        RecordFile {
            disk,
            end: None,
            written: 0,
            pending: Vec::new(),
            content_end: 0,
        }
    }

    /// Where the stream's bytes in the file end: after the provisional end in force.
    fn placed(&self) -> u64 {
        self.end.map_or(0, |(at, len)| at + len)
    }

    /// Writes the provisional end `end` where it will stay, after `pending` and a padding
    /// record that keeps it inside one page; returns where it starts. `pending` gains the
    /// padding.
    fn place_end(&mut self, end: &[u8]) -> io::Result<u64> {
        let from = self.written;
        let pad = padding(from, end.len() as u64);
        push_padding(&mut self.pending, pad);
        let at = from + pad;
        self.disk.write_at(end, at)?;
        Ok(at)
    }

    /// The provisional end in force turned into a record readers skip (the commit after it is
    /// in place).
    fn skip_old_end(&mut self) -> io::Result<()> {
        if let Some((at, len)) = self.end {
            let mut header = [0u8; 9];
            header[0] = SKIPPED_END;
            header[1..].copy_from_slice(&(len - 9).to_le_bytes());
            self.disk.write_at(&header, at)?;
        }
        Ok(())
    }

    /// After a write error: the file put back as the last commit left it (its chunks and a
    /// provisional end, now naming the error), as far as the disk allows.
    fn put_back(&mut self, e: &io::Error) {
        let end = provisional_end(&format!("not closed: writing the file failed: {e}"));
        let at = self.end.map_or(0, |(at, _)| at);
        let _ = self.disk.set_len(at);
        if self.disk.write_at(&end, at).is_ok() && self.end.is_some() {
            self.end = Some((at, end.len() as u64));
        }
        self.written = self.placed();
        self.pending.clear();
    }

    /// The three writes of a commit (see the type's documentation).
    fn commit(&mut self) -> io::Result<()> {
        let end = provisional_end(super::recorder::interrupted().unwrap_or(NOT_CLOSED));
        let at = self.place_end(&end)?;
        self.disk.write_at(&self.pending, self.placed())?;
        self.skip_old_end()?;
        self.end = Some((at, end.len() as u64));
        self.content_end = self.written;
        self.written = self.placed();
        self.pending.clear();
        Ok(())
    }
}

/// The bytes of padding record that put a provisional end of `len` bytes (under a page),
/// written at `from` or after, inside one page: none if it fits where it is, else to the
/// next page, and at least 9 (a record's opcode and length).
fn padding(from: u64, len: u64) -> u64 {
    let room = PAGE - from % PAGE;
    if len <= room {
        0
    } else {
        room.max(9)
    }
}

/// A padding record of `n` bytes (none for 0): a `SKIPPED_END` record of zeros.
fn push_padding(out: &mut Vec<u8>, n: u64) {
    if n == 0 {
        return;
    }
    out.push(SKIPPED_END);
    out.extend_from_slice(&(n - 9).to_le_bytes());
    out.resize(out.len() + (n - 9) as usize, 0);
}

impl<D: Disk> Write for RecordFile<D> {
    /// Keeps `buf` for the next commit.
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.pending.extend_from_slice(buf);
        self.written += buf.len() as u64;
        Ok(buf.len())
    }

    /// A commit (the MCAP writer flushes its output after it closed a chunk): what was
    /// written, then a new provisional end.
    fn flush(&mut self) -> io::Result<()> {
        self.commit().inspect_err(|e| self.put_back(e))
    }
}

impl<D: Disk> Seek for RecordFile<D> {
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

impl<D: Disk> RecordOutput for RecordFile<D> {
    /// Ends the file with the real end (the MCAP writer's `finish` wrote it into `pending`):
    /// a provisional end after where it will end (the file's end while the real one is
    /// written), the real end after the provisional end in force, that end skipped, and the
    /// file cut after the real end.
    fn close(&mut self) -> io::Result<u64> {
        if let Err(e) = self.write_real_end() {
            self.put_back(&e);
            return Err(e);
        }
        self.pending.clear();
        self.end = None;
        Ok(self.written)
    }
}

impl<D: Disk> RecordFile<D> {
    /// `close`'s writes. When the last commit wrote the real end (the MCAP writer's `finish`
    /// flushes), the provisional end after it is cut off.
    fn write_real_end(&mut self) -> io::Result<()> {
        if self.pending.is_empty() && self.end.is_some() {
            self.written = self.content_end;
            return self.disk.set_len(self.written);
        }
        if self.end.is_some() {
            let end = provisional_end(super::recorder::interrupted().unwrap_or(NOT_CLOSED));
            let from = self.written;
            self.disk
                .write_at(&end, from + padding(from, end.len() as u64))?;
        }
        self.disk.write_at(&self.pending, self.placed())?;
        self.skip_old_end()?;
        self.disk.set_len(self.written)
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

    /// A recording on `out` with one channel (`/panel/event`), committed once: the writer
    /// and the channel.
    fn panel_recording<D: Disk>(out: RecordFile<D>) -> (mcap::Writer<RecordFile<D>>, u16) {
        let mut w = mcap_options().create(out).unwrap();
        let s = w
            .add_schema("novanc.PanelEvent", "jsonschema", b"{}")
            .unwrap();
        let ch = w
            .add_channel(s, "/panel/event", "json", &BTreeMap::new())
            .unwrap();
        w.flush().unwrap();
        (w, ch)
    }

    fn message<D: Disk>(w: &mut mcap::Writer<RecordFile<D>>, ch: u16, i: u32) {
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
        let (mut w, ch) = panel_recording(RecordFile::create(&path).unwrap());
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

    /// A disk that logs its writes, so that a test can replay them cut anywhere.
    #[derive(Default)]
    struct Log {
        ops: std::rc::Rc<std::cell::RefCell<Vec<Op>>>,
    }

    #[derive(Clone)]
    enum Op {
        Write(u64, Vec<u8>),
        SetLen(u64),
    }

    impl Disk for Log {
        fn write_at(&mut self, buf: &[u8], at: u64) -> io::Result<()> {
            self.ops.borrow_mut().push(Op::Write(at, buf.to_vec()));
            Ok(())
        }
        fn set_len(&mut self, len: u64) -> io::Result<()> {
            self.ops.borrow_mut().push(Op::SetLen(len));
            Ok(())
        }
    }

    fn apply(file: &mut Vec<u8>, op: &Op) {
        match op {
            Op::Write(at, buf) => {
                let at = *at as usize;
                if file.len() < at + buf.len() {
                    file.resize(at + buf.len(), 0);
                }
                file[at..at + buf.len()].copy_from_slice(buf);
            }
            Op::SetLen(len) => file.resize(*len as usize, 0),
        }
    }

    /// What a reader gets out of `bytes` from the start (checking chunk CRCs and the end
    /// magic) and from the end (the footer, then the summary it points to): the messages, or
    /// why it cannot.
    fn readable(bytes: &[u8]) -> Result<usize, String> {
        let n = mcap::MessageStream::new_with_options(
            bytes,
            mcap::read::Options::ValidateChunkCrcs.into(),
        )
        .map_err(|e| e.to_string())?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?
        .len();
        mcap::Summary::read(bytes).map_err(|e| format!("from the end: {e}"))?;
        Ok(n)
    }

    #[test]
    fn a_write_cut_at_any_page_leaves_a_readable_file() {
        // A recording of several commits of chunks larger than a page, then closed; its writes
        // replayed, each one also cut at every page boundary it crosses (where SIGKILL can cut
        // a write): every state of the file reads, from the start and from the end, with at
        // least the messages of the last whole commit.
        let log = Log::default();
        let ops = log.ops.clone();
        let (mut w, ch) = panel_recording(RecordFile::on(log));
        let mut committed = vec![(ops.borrow().len(), 0)];
        let mut n = 0;
        for size in [3, 1, 150, 400, 7, 260] {
            for _ in 0..size {
                message(&mut w, ch, n);
                n += 1;
            }
            let before = ops.borrow().len();
            w.flush().unwrap();
            committed.push((ops.borrow().len() - before, n as usize));
        }
        w.write_metadata(&recording_metadata(true, Some(0), None))
            .unwrap();
        w.finish().unwrap();
        w.into_inner().close().unwrap();
        let ops = ops.borrow().clone();
        let mut file = Vec::new();
        let mut states = 0;
        let mut least = 0;
        let mut whole_commits = 0;
        let mut ops_done = 0;
        let mut commit_ops = committed.iter().skip(1);
        let mut next_commit = None;
        for op in &ops {
            // Before the first commit there is no file to read (as before the recording).
            if whole_commits == 0 {
                apply(&mut file, op);
                ops_done += 1;
                if ops_done == committed[0].0 {
                    ops_done = 0;
                    whole_commits = 1;
                    next_commit = commit_ops.next().copied();
                }
                continue;
            }
            if let Op::Write(at, buf) = op {
                let first_page = at / PAGE + 1;
                let last = (at + buf.len() as u64).div_ceil(PAGE);
                for page in first_page..last {
                    let cut = (page * PAGE - at) as usize;
                    let mut torn = file.clone();
                    apply(&mut torn, &Op::Write(*at, buf[..cut].to_vec()));
                    let got = readable(&torn).unwrap_or_else(|e| {
                        panic!("cut at byte {} of a write at {at}: {e}", page * PAGE)
                    });
                    assert!(got >= least, "cut: {got} messages, {least} committed");
                    states += 1;
                }
            }
            apply(&mut file, op);
            ops_done += 1;
            if let Some((k, msgs)) = next_commit {
                if ops_done == k {
                    ops_done = 0;
                    least = msgs;
                    whole_commits += 1;
                    next_commit = commit_ops.next().copied();
                }
            }
            let got = readable(&file).unwrap_or_else(|e| panic!("after a write: {e}"));
            assert!(got >= least);
            states += 1;
        }
        assert_eq!(whole_commits, 7);
        assert_eq!(readable(&file), Ok(n as usize));
        let summary = mcap::Summary::read(&file).unwrap().expect("a summary");
        assert_eq!(summary.stats.unwrap().message_count, u64::from(n));
        assert!(states > 30, "{states} states tried");
    }

    #[test]
    fn a_provisional_end_is_padded_into_one_page() {
        let len = provisional_end(NOT_CLOSED).len() as u64;
        assert!(len < 300, "{len}");
        for from in (0..3 * PAGE).chain([PAGE - 1, PAGE - 8, PAGE - 9, 2 * PAGE + 5]) {
            let pad = padding(from, len);
            let at = from + pad;
            assert!(pad == 0 || pad >= 9, "from {from}: pad {pad}");
            assert_eq!(at / PAGE, (at + len - 1) / PAGE, "from {from}: pad {pad}");
            assert!(pad <= len.max(9), "from {from}: pad {pad}");
        }
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
