//! The MCAP side of the recorder: one JSON-schema schema and one JSON channel per docs/recording.md
//! topic, uncompressed chunks (the `mcap` crate is built without zstd/lz4), and the bookkeeping
//! the operator's summary needs (messages per topic, pulses, bytes, the first disk error).
//!
//! Synchronous and single-threaded: the recorder thread owns one `RecordWriter`; the benchmark
//! drives one directly. After the first write error the MCAP writer is dropped and every later
//! event is only counted, so the caller can keep draining its queue at full speed.
//!
//! The counts are of what is on disk (docs/recording.md, "Incomplete recordings"): the writer
//! closes each chunk itself once it holds `CHUNK_BYTES` and flushes it to the file, and only then
//! adds the chunk's messages and pulses to the outcome. The messages of a chunk that a disk error
//! cut short are counted as lost, not written.

use super::file::{
    mcap_options, recording_metadata, CommitClock, RecordFile, RecordOutput, CHUNK_BYTES,
    MESSAGE_RECORD_OVERHEAD,
};
use super::foxglove::{Derived, Scene, DERIVED};
use super::info::RecordingInfo;
use super::json::encode_event_axes;
use super::topic::{Topic, ALL_TOPICS, TOPICS};
use super::Event;
use crate::settings::MachineSettings;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Channel slots: one per topic (`/lathe/event` last), then the derived Foxglove ones.
const CHANNELS: usize = ALL_TOPICS + DERIVED;

/// The environment variable that leaves the derived Foxglove topics (`/foxglove/scene`,
/// `/foxglove/tool`) out when set to `off`: for measuring what they cost
/// (docs/recording.md, "Foxglove topics").
pub const SCENE_ENV: &str = "NOVANC_FOXGLOVE_SCENE";

/// What a finished `RecordWriter` reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WriterOutcome {
    /// Messages on disk per topic (in chunks flushed to the file), in `Topic::ALL` order.
    pub messages: [u64; TOPICS],
    /// Messages on disk on `/lathe/event` (a kernel's channels).
    pub lathe_events: u64,
    /// Pulses on disk in `/nc/pulses` batches.
    pub pulses: u64,
    /// Derived messages on disk per Foxglove channel, in `Derived::ALL` order.
    pub foxglove: [u64; DERIVED],
    /// Events not in the file because of a disk error: those of the chunk it cut short, and
    /// every later one.
    pub lost_to_disk_error: u64,
    /// Size of the file, bytes (0 when unknown, e.g. after a disk error).
    pub bytes: u64,
    /// The first disk error, with the file name.
    pub disk_error: Option<String>,
    /// Why the recording was cut short (a stop signal), if it was.
    pub interrupted: Option<String>,
}

/// Writes events as docs/recording.md MCAP messages to one file (or any seekable output, for tests).
pub struct RecordWriter<W: RecordOutput = RecordFile> {
    /// `None` once a write failed (or after finish).
    mcap: Option<mcap::Writer<W>>,
    path: PathBuf,
    pulse_mm: f64,
    /// The machine's rotary axes (`MachineSettings::rotary_mask`): positions carry `a`, `b`,
    /// `c` for them.
    rotary: u8,
    /// The MCAP channel id of each slot (None: not declared yet; only `/lathe/event` waits
    /// for its first message).
    channels: [Option<u16>; CHANNELS],
    sequence: [u32; CHANNELS],
    /// Derives the Foxglove scene and tool transform, one scene per channel (index 0: a
    /// single machine's; N: a kernel's channel N, made at its first message). None: left
    /// out, `SCENE_ENV`.
    scenes: Option<Vec<Option<Scene>>>,
    /// The tools' sizes drawn in the scenes.
    tool_sizes: Vec<(u32, f64, f64)>,
    out: WriterOutcome,
    /// Messages and pulses of the chunk still open (not yet flushed to the file).
    pending: Pending,
    /// Size at which the open chunk is closed and flushed, bytes.
    chunk_bytes: u64,
    /// When the open chunk is to be closed for its age or a stop signal.
    clock: CommitClock,
    buf: Vec<u8>,
}

/// What the open chunk holds: counted in the outcome only once the chunk is on disk.
#[derive(Clone, Copy, Debug, Default)]
struct Pending {
    messages: [u64; CHANNELS],
    pulses: u64,
    bytes: u64,
}

/// The innermost cause of an error: what the operator needs ("No space left on device"), not
/// the MCAP writer's wrapping of it ("I/O error from writing, or reading a compression
/// stream"). Both machines' recorders word their errors with it.
pub fn cause<'a>(
    e: &'a (dyn std::error::Error + 'static),
) -> &'a (dyn std::error::Error + 'static) {
    let mut cause = e;
    while let Some(s) = cause.source() {
        cause = s;
    }
    cause
}

impl RecordWriter {
    /// Creates the file and writes the MCAP header, the schemas, the channels and the machine
    /// settings as metadata. Fails only if the file cannot be created; a write error here is
    /// kept and reported by `finish` like any later disk error.
    pub fn create(path: &Path, settings: &MachineSettings) -> Result<RecordWriter, String> {
        RecordWriter::create_with(path, settings, &RecordingInfo::default())
    }

    /// As `create`, with the run's program and data as attachments and metadata.
    pub fn create_with(
        path: &Path,
        settings: &MachineSettings,
        info: &RecordingInfo,
    ) -> Result<RecordWriter, String> {
        let file = RecordFile::create(path)
            .map_err(|e| format!("cannot create recording {}: {e}", path.display()))?;
        Ok(RecordWriter::with_output_info(file, path, settings, info))
    }
}

impl<W: RecordOutput> RecordWriter<W> {
    /// As `create`, on an output already open; `path` only names it in error messages.
    pub fn with_output(output: W, path: &Path, settings: &MachineSettings) -> RecordWriter<W> {
        RecordWriter::with_output_info(output, path, settings, &RecordingInfo::default())
    }

    /// As `create_with`, on an output already open.
    pub fn with_output_info(
        output: W,
        path: &Path,
        settings: &MachineSettings,
        info: &RecordingInfo,
    ) -> RecordWriter<W> {
        let scene_on = std::env::var(SCENE_ENV).map_or(true, |v| v != "off");
        let mut w = RecordWriter {
            mcap: None,
            path: path.to_path_buf(),
            pulse_mm: settings.pulse_mm,
            rotary: settings.rotary_mask(),
            channels: [None; CHANNELS],
            sequence: [0; CHANNELS],
            scenes: scene_on.then(Vec::new),
            tool_sizes: info.tool_sizes(),
            out: WriterOutcome::default(),
            pending: Pending::default(),
            chunk_bytes: CHUNK_BYTES,
            clock: CommitClock::default(),
            buf: Vec::with_capacity(64 * 1024),
        };
        if let Err(e) = w.open(output, settings, info) {
            w.fail(e);
        }
        w
    }

    /// Header, settings metadata (before any chunk), schemas, channels; committed at once, so
    /// that the file is a (still empty) recording from the start.
    fn open(
        &mut self,
        file: W,
        settings: &MachineSettings,
        info: &RecordingInfo,
    ) -> Result<(), mcap::McapError> {
        // No automatic chunk size: `write` closes chunks itself, so that it knows which
        // messages reached the file.
        let mut mcap = mcap_options().create(file)?;
        match Self::declare(&mut mcap, settings, info, &mut self.channels)
            .and_then(|()| mcap.flush())
        {
            Ok(()) => {
                self.mcap = Some(mcap);
                Ok(())
            }
            Err(e) => {
                // No finish attempt on a half-written file (see `fail`).
                drop(mcap.into_inner());
                Err(e)
            }
        }
    }

    /// Writes the settings metadata, the program metadata and the attachments, the schemas and
    /// the channels; fills in the channel ids.
    fn declare(
        mcap: &mut mcap::Writer<W>,
        settings: &MachineSettings,
        info: &RecordingInfo,
        channels: &mut [Option<u16>; CHANNELS],
    ) -> Result<(), mcap::McapError> {
        let mut metadata = BTreeMap::from([
            ("pulse_mm".to_string(), settings.pulse_mm.to_string()),
            (
                "ncbr_period_ns".to_string(),
                settings.ncbr_period_ns.to_string(),
            ),
            (
                "interpolator".to_string(),
                settings.interpolator.name().to_string(),
            ),
            ("ep_l_pulses".to_string(), settings.ep_l_pulses.to_string()),
            (
                "time".to_string(),
                "machine time, ns since the run started".to_string(),
            ),
        ]);
        metadata.extend(info.settings_metadata());
        mcap.write_metadata(&mcap::records::Metadata {
            name: "novanc.settings".to_string(),
            metadata,
        })?;
        for m in info.metadata() {
            mcap.write_metadata(&m)?;
        }
        for (name, media_type, data) in info.attachments(settings) {
            mcap.attach(&mcap::Attachment {
                log_time: 0,
                create_time: 0,
                name,
                media_type: media_type.to_string(),
                data: data.into(),
            })?;
        }
        let no_metadata = BTreeMap::new();
        // `/lathe/event` is declared with its first message (`declare_late`): a centre's
        // file is as it was before the lathe recorded through this writer.
        let declared = Topic::ALL
            .iter()
            .map(|t| {
                (
                    t.index(),
                    t.schema_name(),
                    t.schema_for(settings.rotary_mask()),
                    t.name(),
                )
            })
            .chain(Derived::ALL.iter().map(|d| {
                let slot = ALL_TOPICS + d.index();
                (slot, d.schema_name(), d.schema().into(), d.name())
            }));
        for (i, schema_name, schema, topic) in declared {
            let schema = mcap.add_schema(schema_name, "jsonschema", schema.as_bytes())?;
            channels[i] = Some(mcap.add_channel(schema, topic, "json", &no_metadata)?);
        }
        Ok(())
    }

    /// Declares topic slot `i`'s schema and channel before its first message, if not yet.
    fn declare_late(&mut self, i: usize) -> Result<u16, ()> {
        if let Some(id) = self.channels.get(i).copied().flatten() {
            return Ok(id);
        }
        let (Some(mcap), Some(t)) = (self.mcap.as_mut(), Topic::EVERY.get(i)) else {
            return Err(());
        };
        let r = mcap
            .add_schema(
                t.schema_name(),
                "jsonschema",
                t.schema_for(self.rotary).as_bytes(),
            )
            .and_then(|s| mcap.add_channel(s, t.name(), "json", &BTreeMap::new()));
        match r {
            Ok(id) => {
                self.channels[i] = Some(id);
                Ok(id)
            }
            Err(e) => {
                self.fail(e);
                Err(())
            }
        }
    }

    /// Keeps the first error, lets go of the MCAP writer, and from now on only counts events.
    fn fail(&mut self, e: impl std::error::Error + 'static) {
        // The open chunk never got its length and CRC: its messages are not readable.
        let lost = std::mem::take(&mut self.pending);
        self.out.lost_to_disk_error += lost.messages[..ALL_TOPICS].iter().sum::<u64>();
        if self.out.disk_error.is_none() {
            self.out.disk_error = Some(format!("writing {}: {}", self.path.display(), cause(&e)));
        }
        // `into_inner` hands the file back without another write attempt (dropping the MCAP
        // writer would try to finish a file in an unknown state); what it held uncommitted is
        // dropped with it, and the file ends where its last commit left it.
        if let Some(mcap) = self.mcap.take() {
            drop(mcap.into_inner());
        }
    }

    /// Whether a disk error has happened.
    pub fn failed(&self) -> bool {
        self.out.disk_error.is_some()
    }

    /// Writes one event as a message on its topic. Log and publish time are the event's machine
    /// time (the first pulse's for a batch; docs/recording.md). Pulse batches of different axes may reach
    /// the file slightly out of time order, which MCAP allows: readers sort by log time.
    /// An empty pulse batch is not written. Returns false if the event could not be written
    /// (this one or, when a chunk was being flushed, earlier ones: see `WriterOutcome`).
    pub fn write(&mut self, ev: &Event) -> bool {
        if self.mcap.is_none() {
            self.out.lost_to_disk_error += 1;
            return false;
        }
        if let Event::Pulses { t_ns, .. } = ev.inner() {
            if t_ns.is_empty() {
                return true;
            }
        }
        let i = Topic::of(ev).index();
        self.buf.clear();
        let t = encode_event_axes(&mut self.buf, ev, self.pulse_mm, self.rotary);
        let pulses = match ev.inner() {
            Event::Pulses { t_ns, .. } => t_ns.len() as u64,
            _ => 0,
        };
        let buf = std::mem::take(&mut self.buf);
        let written = self.emit(i, t, &buf, pulses);
        self.buf = buf;
        if !written {
            return false;
        }
        // Each channel's messages draw its own scene.
        let ch = ev.channel();
        let k = ch.map_or(0, usize::from);
        let Some(scenes) = self.scenes.as_mut() else {
            return true;
        };
        if scenes.len() <= k {
            scenes.resize_with(k + 1, || None);
        }
        let mut scene = scenes[k]
            .take()
            .unwrap_or_else(|| Scene::on(self.pulse_mm, self.tool_sizes.clone(), ch));
        scene.derive(ev.inner(), &mut |d, t, data| {
            self.emit(ALL_TOPICS + d.index(), t, data, 0);
        });
        if let Some(s) = self.scenes.as_mut().and_then(|s| s.get_mut(k)) {
            *s = Some(scene);
        }
        true
    }

    /// Writes one message on channel slot `i` (a topic's, or after them a derived one's),
    /// closing the chunk first if it is due. A lost event (not a derived message) counts in
    /// `lost_to_disk_error`.
    fn emit(&mut self, i: usize, t: u64, data: &[u8], pulses: u64) -> bool {
        let lost = u64::from(i < ALL_TOPICS);
        if self.clock.due(self.pending.bytes, self.chunk_bytes) && !self.flush_chunk() {
            self.out.lost_to_disk_error += lost;
            return false;
        }
        let Ok(channel_id) = self.declare_late(i) else {
            self.out.lost_to_disk_error += lost;
            return false;
        };
        let Some(mcap) = self.mcap.as_mut() else {
            self.out.lost_to_disk_error += lost;
            return false;
        };
        let header = mcap::records::MessageHeader {
            channel_id,
            sequence: self.sequence[i],
            log_time: t,
            publish_time: t,
        };
        match mcap.write_to_known_channel(&header, data) {
            Ok(()) => {
                self.sequence[i] = self.sequence[i].wrapping_add(1);
                self.clock.wrote();
                self.pending.messages[i] += 1;
                self.pending.bytes += data.len() as u64 + MESSAGE_RECORD_OVERHEAD;
                self.pending.pulses += pulses;
                true
            }
            Err(e) => {
                self.out.lost_to_disk_error += lost;
                self.fail(e);
                false
            }
        }
    }

    /// Closes the open chunk (length, CRC, message indexes) and flushes it to the file; its
    /// messages then count as written. False after a disk error (kept by `fail`).
    fn flush_chunk(&mut self) -> bool {
        let Some(mcap) = self.mcap.as_mut() else {
            return false;
        };
        match mcap.flush() {
            Ok(()) => {
                self.commit();
                true
            }
            Err(e) => {
                self.fail(e);
                false
            }
        }
    }

    /// Closes and commits the open chunk if it is due (`CHUNK_AGE` old, or a stop signal was
    /// noted since the last commit): for the recorder thread while no event comes. False
    /// after a disk error.
    pub fn keep_readable(&mut self) -> bool {
        if self.mcap.is_none() {
            return false;
        }
        !self.clock.due(self.pending.bytes, self.chunk_bytes) || self.flush_chunk()
    }

    /// Adds what the chunk just flushed holds to the outcome.
    fn commit(&mut self) {
        self.clock.committed();
        let p = std::mem::take(&mut self.pending);
        for (n, m) in self.out.messages.iter_mut().zip(p.messages) {
            *n += m;
        }
        self.out.lathe_events += p.messages[Topic::LatheEvent.index()];
        for (n, m) in self.out.foxglove.iter_mut().zip(&p.messages[ALL_TOPICS..]) {
            *n += m;
        }
        self.out.pulses += p.pulses;
    }

    /// Notes that the process was interrupted (a stop signal, docs/recording.md): `finish` then
    /// writes `interrupted` with this reason in the closing metadata, and `complete: false`.
    pub fn note_interrupted(&mut self, why: &str) {
        self.out.interrupted = Some(why.to_string());
    }

    /// Writes a closing `novanc.recording` metadata record (complete or not, events dropped,
    /// the interruption if any), the summary section and the footer, and flushes the file.
    /// The last chunk is flushed first, so its messages count as written even if the summary
    /// section then fails to fit on the disk.
    pub fn finish(mut self, incomplete: bool, dropped: u64) -> WriterOutcome {
        // The path since each channel's last block's start.
        for mut scene in self.scenes.take().into_iter().flatten().flatten() {
            scene.flush(0, &mut |d, t, data| {
                self.emit(ALL_TOPICS + d.index(), t, data, 0);
            });
        }
        if !self.flush_chunk() {
            return self.out;
        }
        if let Some(mut mcap) = self.mcap.take() {
            let incomplete = incomplete || self.out.interrupted.is_some();
            let closed = mcap
                .write_metadata(&recording_metadata(
                    !incomplete,
                    Some(dropped),
                    self.out.interrupted.as_deref(),
                ))
                .and_then(|()| mcap.finish().map(|_| ()));
            match closed {
                Ok(()) => match mcap.into_inner().close() {
                    Ok(len) => self.out.bytes = len,
                    Err(e) => self.fail(e),
                },
                Err(e) => {
                    drop(mcap.into_inner());
                    self.fail(e);
                }
            }
        }
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Seek, Write};

    /// An output whose disk fills up after `limit` bytes; the bytes stay readable through
    /// `disk` after the writer is gone.
    struct FillsUp {
        disk: std::rc::Rc<std::cell::RefCell<std::io::Cursor<Vec<u8>>>>,
        limit: u64,
    }

    impl FillsUp {
        fn new(limit: u64) -> FillsUp {
            FillsUp {
                disk: Default::default(),
                limit,
            }
        }
    }

    impl Write for FillsUp {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            let mut disk = self.disk.borrow_mut();
            if disk.position() + buf.len() as u64 > self.limit {
                return Err(std::io::Error::other("No space left on device"));
            }
            disk.write(buf)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Seek for FillsUp {
        fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
            self.disk.borrow_mut().seek(pos)
        }
    }

    impl RecordOutput for FillsUp {}

    /// Messages and pulses a reader gets out of what reached the disk (the finished chunks of
    /// a file that may have no footer), stopping at the first unreadable record.
    fn readable(bytes: &[u8]) -> (u64, u64) {
        let (mut messages, mut pulses) = (0, 0);
        let Ok(stream) = mcap::MessageStream::new_with_options(
            bytes,
            mcap::read::Options::IgnoreEndMagic | mcap::read::Options::ValidateChunkCrcs,
        ) else {
            return (0, 0);
        };
        for m in stream {
            let Ok(m) = m else { break };
            messages += 1;
            // `{"axis":"X","dir":1,"t_ns":[…]}`: two commas before the times, n - 1 among them.
            pulses += m.data.iter().filter(|&&b| b == b',').count() as u64 - 1;
        }
        (messages, pulses)
    }

    fn batch(i: u64) -> Event {
        Event::Pulses {
            axis: 0,
            dir: 1,
            t_ns: (i * 1000..i * 1000 + 1000).collect(),
        }
    }

    #[test]
    fn disk_filling_up_mid_recording_counts_only_the_chunks_on_disk() {
        // Regression (issue 15, item 5): messages of a chunk the disk error cut short were
        // counted as written although no reader can get them.
        let out = FillsUp::new(200_000);
        let disk = std::rc::Rc::clone(&out.disk);
        let mut w =
            RecordWriter::with_output(out, Path::new("full.mcap"), &MachineSettings::default());
        w.chunk_bytes = 30_000;
        assert!(!w.failed(), "the header fits");
        let mut sent = 0;
        while w.write(&batch(sent)) {
            sent += 1;
            assert!(sent < 1000, "the output never filled up");
        }
        sent += 1;
        assert!(w.failed());
        for i in 0..5 {
            assert!(!w.write(&batch(sent + i)));
        }
        sent += 5;
        let out = w.finish(true, 0);
        let on_disk = out.messages[Topic::Pulses.index()];
        assert!(
            on_disk > 0,
            "some chunks were flushed before the disk filled"
        );
        assert_eq!(on_disk + out.lost_to_disk_error, sent);
        let (messages, pulses) = readable(&disk.borrow().get_ref()[..]);
        assert_eq!((messages, pulses), (on_disk, out.pulses));
        assert_eq!(out.pulses, on_disk * 1000);
        let err = out.disk_error.unwrap();
        assert!(
            err.contains("full.mcap") && err.contains("No space"),
            "{err}"
        );
    }

    #[test]
    fn a_disk_filling_up_in_the_first_chunk_leaves_nothing_counted() {
        // The 64 KiB tmpfs: header and settings fit, the first chunk does not.
        let out = FillsUp::new(64 * 1024);
        let disk = std::rc::Rc::clone(&out.disk);
        let mut w =
            RecordWriter::with_output(out, Path::new("tiny.mcap"), &MachineSettings::default());
        let mut sent = 0;
        while w.write(&batch(sent)) {
            sent += 1;
        }
        let out = w.finish(true, 0);
        assert_eq!(out.messages, [0; TOPICS]);
        assert_eq!(out.pulses, 0);
        assert_eq!(out.lost_to_disk_error, sent + 1);
        assert_eq!(readable(&disk.borrow().get_ref()[..]), (0, 0));
    }

    #[test]
    fn disk_full_before_the_channels_are_written_is_kept_not_panicked() {
        for limit in [0, 10, 100, 1_000] {
            let out = FillsUp::new(limit);
            let mut w =
                RecordWriter::with_output(out, Path::new("tiny.mcap"), &MachineSettings::default());
            assert!(w.failed(), "limit {limit}");
            assert!(!w.write(&Event::PanelEvent {
                t_ns: 0,
                event: "key START".into()
            }));
            let out = w.finish(true, 0);
            assert_eq!(out.lost_to_disk_error, 1);
            assert!(out.disk_error.is_some());
        }
    }

    #[test]
    fn disk_filling_up_while_closing_is_reported_not_panicked() {
        let run = |limit: u64| {
            let out = FillsUp::new(limit);
            let mut w =
                RecordWriter::with_output(out, Path::new("end.mcap"), &MachineSettings::default());
            for i in 0..10u64 {
                assert!(w.write(&Event::Position {
                    t_ns: i,
                    pulses: [i as i64, 0, 0].into(),
                    held: [0; 3].into(),
                    speed_mm_min: 0.0,
                }));
            }
            w.finish(false, 0)
        };
        let whole = run(u64::MAX);
        assert_eq!(whole.disk_error, None);
        for cut in [1, 30, 200, 400] {
            let out = run(whole.bytes - cut);
            assert!(out.disk_error.is_some(), "cut {cut}: {out:?}");
            assert_eq!(out.bytes, 0);
        }
    }

    #[test]
    fn an_interrupted_recording_is_finished_and_says_so() {
        let out = FillsUp::new(u64::MAX);
        let disk = std::rc::Rc::clone(&out.disk);
        let mut w =
            RecordWriter::with_output(out, Path::new("sig.mcap"), &MachineSettings::default());
        assert!(w.write(&batch(0)));
        w.note_interrupted("interrupted by SIGINT");
        let out = w.finish(false, 0);
        assert_eq!(out.disk_error, None);
        assert_eq!(out.interrupted.as_deref(), Some("interrupted by SIGINT"));
        let bytes = disk.borrow().get_ref().clone();
        let n = mcap::MessageStream::new_with_options(
            &bytes,
            mcap::read::Options::ValidateChunkCrcs.into(),
        )
        .unwrap()
        .collect::<Result<Vec<_>, _>>()
        .unwrap()
        .len();
        assert_eq!(n, 1);
        let closing = mcap::read::LinearReader::new(&bytes)
            .unwrap()
            .filter_map(|r| match r.unwrap() {
                mcap::records::Record::Metadata(m) if m.name == "novanc.recording" => {
                    Some(m.metadata)
                }
                _ => None,
            })
            .next()
            .expect("the closing metadata");
        assert_eq!(closing["complete"], "false");
        assert_eq!(closing["interrupted"], "interrupted by SIGINT");
    }

    #[test]
    fn unwritable_path_is_an_error_naming_the_file() {
        let path = Path::new("/nonexistent-dir-novanc/x.mcap");
        let err = match RecordWriter::create(path, &MachineSettings::default()) {
            Ok(_) => panic!("created a file in a missing directory"),
            Err(e) => e,
        };
        assert!(err.contains("/nonexistent-dir-novanc/x.mcap"), "{err}");
    }

    #[test]
    fn counts_messages_and_pulses_and_skips_empty_batches() {
        let path = std::env::temp_dir().join(format!("novanc-writer-{}.mcap", std::process::id()));
        let mut w = RecordWriter::create(&path, &MachineSettings::default()).unwrap();
        assert!(w.write(&Event::Pulses {
            axis: 0,
            dir: 1,
            t_ns: vec![1, 2, 3]
        }));
        assert!(w.write(&Event::Pulses {
            axis: 0,
            dir: 1,
            t_ns: vec![]
        }));
        assert!(w.write(&Event::PanelEvent {
            t_ns: 0,
            event: "key START".into()
        }));
        let out = w.finish(false, 0);
        let _ = std::fs::remove_file(&path);
        assert_eq!(out.messages, [0, 0, 1, 0, 0, 1, 0, 0, 0]);
        assert_eq!(out.pulses, 3);
        assert_eq!(out.disk_error, None);
        assert!(out.bytes > 0);
    }
}
