//! The MCAP side of the recorder: one JSON-schema schema and one JSON channel per docs/recording.md
//! topic, uncompressed chunks (the `mcap` crate is built without zstd/lz4), and the bookkeeping
//! the operator's summary needs (messages per topic, pulses, bytes, the first disk error).
//!
//! Synchronous and single-threaded: the recorder thread owns one `RecordWriter`; the benchmark
//! drives one directly. After the first write error the MCAP writer is dropped and every later
//! event is only counted, so the caller can keep draining its queue at full speed.

use super::json::encode_event;
use super::topic::Topic;
use super::Event;
use crate::settings::MachineSettings;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

/// Target uncompressed size of one MCAP chunk.
const CHUNK_BYTES: u64 = 4 * 1024 * 1024;

/// Size of the file buffer in front of the MCAP writer.
const FILE_BUFFER_BYTES: usize = 1024 * 1024;

/// What a finished `RecordWriter` reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WriterOutcome {
    /// Messages written per topic, in `Topic::ALL` order.
    pub messages: [u64; 6],
    /// Pulses written in `/nc/pulses` batches.
    pub pulses: u64,
    /// Events received after a disk error, hence not in the file.
    pub lost_to_disk_error: u64,
    /// Size of the file, bytes (0 when unknown, e.g. after a disk error).
    pub bytes: u64,
    /// The first disk error, with the file name.
    pub disk_error: Option<String>,
}

/// Writes events as docs/recording.md MCAP messages to one file (or any seekable output, for tests).
pub struct RecordWriter<W: Write + Seek = BufWriter<File>> {
    /// `None` once a write failed (or after finish).
    mcap: Option<mcap::Writer<W>>,
    path: PathBuf,
    pulse_mm: f64,
    channels: [u16; 6],
    sequence: [u32; 6],
    out: WriterOutcome,
    buf: Vec<u8>,
}

impl RecordWriter {
    /// Creates the file and writes the MCAP header, the schemas, the channels and the machine
    /// settings as metadata. Fails only if the file cannot be created; a write error here is
    /// kept and reported by `finish` like any later disk error.
    pub fn create(path: &Path, settings: &MachineSettings) -> Result<RecordWriter, String> {
        let file = File::create(path)
            .map_err(|e| format!("cannot create recording {}: {e}", path.display()))?;
        Ok(RecordWriter::with_output(
            BufWriter::with_capacity(FILE_BUFFER_BYTES, file),
            path,
            settings,
        ))
    }
}

impl<W: Write + Seek> RecordWriter<W> {
    /// As `create`, on an output already open; `path` only names it in error messages.
    pub fn with_output(output: W, path: &Path, settings: &MachineSettings) -> RecordWriter<W> {
        let mut w = RecordWriter {
            mcap: None,
            path: path.to_path_buf(),
            pulse_mm: settings.pulse_mm,
            channels: [0; 6],
            sequence: [0; 6],
            out: WriterOutcome::default(),
            buf: Vec::with_capacity(64 * 1024),
        };
        if let Err(e) = w.open(output, settings) {
            w.fail(e);
        }
        w
    }

    /// Header, settings metadata (before any chunk), schemas, channels.
    fn open(&mut self, file: W, settings: &MachineSettings) -> Result<(), mcap::McapError> {
        let options = mcap::WriteOptions::new()
            .compression(None)
            .chunk_size(Some(CHUNK_BYTES))
            .profile("")
            .library(concat!("novanc ", env!("CARGO_PKG_VERSION")));
        let mut mcap = options.create(file)?;
        match Self::declare(&mut mcap, settings, &mut self.channels) {
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

    /// Writes the settings metadata, the schemas and the channels; fills in the channel ids.
    fn declare(
        mcap: &mut mcap::Writer<W>,
        settings: &MachineSettings,
        channels: &mut [u16; 6],
    ) -> Result<(), mcap::McapError> {
        let metadata = BTreeMap::from([
            ("pulse_mm".to_string(), settings.pulse_mm.to_string()),
            (
                "ncbr_period_ns".to_string(),
                settings.ncbr_period_ns.to_string(),
            ),
            (
                "time".to_string(),
                "machine time, ns since the run started".to_string(),
            ),
        ]);
        mcap.write_metadata(&mcap::records::Metadata {
            name: "novanc.settings".to_string(),
            metadata,
        })?;
        let no_metadata = BTreeMap::new();
        for topic in Topic::ALL {
            let schema =
                mcap.add_schema(topic.schema_name(), "jsonschema", topic.schema().as_bytes())?;
            channels[topic.index()] =
                mcap.add_channel(schema, topic.name(), "json", &no_metadata)?;
        }
        Ok(())
    }

    /// Keeps the first error, lets go of the MCAP writer, and from now on only counts events.
    fn fail(&mut self, e: impl std::error::Error + 'static) {
        if self.out.disk_error.is_none() {
            // The innermost cause says what the operator needs ("No space left on device").
            let mut cause: &dyn std::error::Error = &e;
            while let Some(s) = cause.source() {
                cause = s;
            }
            self.out.disk_error = Some(format!("writing {}: {cause}", self.path.display()));
        }
        // `into_inner` hands the file back without another write attempt (dropping the MCAP
        // writer would try to finish a file in an unknown state); the buffer's own drop makes
        // one last, silent attempt to write what it holds.
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
    /// An empty pulse batch is not written. Returns false if the event could not be written.
    pub fn write(&mut self, ev: &Event) -> bool {
        let Some(mcap) = self.mcap.as_mut() else {
            self.out.lost_to_disk_error += 1;
            return false;
        };
        let topic = Topic::of(ev);
        let i = topic.index();
        if let Event::Pulses { t_ns, .. } = ev {
            if t_ns.is_empty() {
                return true;
            }
        }
        self.buf.clear();
        let t = encode_event(&mut self.buf, ev, self.pulse_mm);
        let log_time = t;
        let header = mcap::records::MessageHeader {
            channel_id: self.channels[i],
            sequence: self.sequence[i],
            log_time,
            publish_time: t,
        };
        match mcap.write_to_known_channel(&header, &self.buf) {
            Ok(()) => {
                self.sequence[i] = self.sequence[i].wrapping_add(1);
                self.out.messages[i] += 1;
                if let Event::Pulses { t_ns, .. } = ev {
                    self.out.pulses += t_ns.len() as u64;
                }
                true
            }
            Err(e) => {
                self.out.lost_to_disk_error += 1;
                self.fail(e);
                false
            }
        }
    }

    /// Writes a closing `novanc.recording` metadata record (complete or not, events dropped),
    /// the summary section and the footer, and flushes the file.
    pub fn finish(mut self, incomplete: bool, dropped: u64) -> WriterOutcome {
        if let Some(mut mcap) = self.mcap.take() {
            let metadata = BTreeMap::from([
                ("complete".to_string(), (!incomplete).to_string()),
                ("dropped_events".to_string(), dropped.to_string()),
            ]);
            let closed = mcap
                .write_metadata(&mcap::records::Metadata {
                    name: "novanc.recording".to_string(),
                    metadata,
                })
                .and_then(|()| mcap.finish().map(|_| ()));
            match closed {
                Ok(()) => {
                    let mut file = mcap.into_inner();
                    match file.flush().and_then(|()| file.stream_position()) {
                        Ok(len) => self.out.bytes = len,
                        Err(e) => self.fail(e),
                    }
                }
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

    /// An output whose disk fills up after `limit` bytes.
    struct FillsUp {
        inner: std::io::Cursor<Vec<u8>>,
        limit: u64,
    }

    impl Write for FillsUp {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.inner.position() + buf.len() as u64 > self.limit {
                return Err(std::io::Error::other("No space left on device"));
            }
            self.inner.write(buf)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Seek for FillsUp {
        fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
            self.inner.seek(pos)
        }
    }

    #[test]
    fn disk_filling_up_mid_recording_is_kept_and_later_events_are_counted() {
        let out = FillsUp {
            inner: std::io::Cursor::new(Vec::new()),
            limit: 200_000,
        };
        let mut w =
            RecordWriter::with_output(out, Path::new("full.mcap"), &MachineSettings::default());
        assert!(!w.failed(), "the header fits");
        let batch = |i: u64| Event::Pulses {
            axis: 0,
            dir: 1,
            t_ns: (i * 1000..i * 1000 + 1000).collect(),
        };
        let mut written = 0;
        while w.write(&batch(written)) {
            written += 1;
            assert!(written < 1000, "the output never filled up");
        }
        assert!(w.failed());
        for i in 0..5 {
            assert!(!w.write(&batch(written + 1 + i)));
        }
        let out = w.finish(true, 0);
        assert_eq!(out.messages[Topic::Pulses.index()], written);
        assert_eq!(out.lost_to_disk_error, 6);
        let err = out.disk_error.unwrap();
        assert!(
            err.contains("full.mcap") && err.contains("No space"),
            "{err}"
        );
    }

    #[test]
    fn disk_full_before_the_channels_are_written_is_kept_not_panicked() {
        for limit in [0, 10, 100, 1_000] {
            let out = FillsUp {
                inner: std::io::Cursor::new(Vec::new()),
                limit,
            };
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
            let out = FillsUp {
                inner: std::io::Cursor::new(Vec::new()),
                limit,
            };
            let mut w =
                RecordWriter::with_output(out, Path::new("end.mcap"), &MachineSettings::default());
            for i in 0..10u64 {
                assert!(w.write(&Event::Position {
                    t_ns: i,
                    pulses: [i as i64, 0, 0]
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
        assert_eq!(out.messages, [0, 0, 1, 0, 0, 1]);
        assert_eq!(out.pulses, 3);
        assert_eq!(out.disk_error, None);
        assert!(out.bytes > 0);
    }
}
