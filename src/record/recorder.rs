//! The recorder thread: it drains a bounded event queue into a `RecordWriter`, so file I/O
//! never stalls the pulse core (its PGEN loop only ever does a `try_send`).
//!
//! Timing: the thread blocks on the queue and wakes at least every `POLL` to see whether
//! `finish` was called while some producer still holds a sink, and to commit the open chunk
//! once it is due (a second old, or a stop signal noted: `super::file`). A full queue drops the event
//! (counted, recording marked incomplete); a disk error marks the recording incomplete at once
//! and the thread keeps draining, so producers never notice.

use super::foxglove::DERIVED;
use super::writer::{RecordWriter, WriterOutcome};
use super::{Event, EventSink, RecordingInfo, SinkFlags, Topic, TOPICS};
use crate::settings::MachineSettings;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError};
use std::sync::{Arc, OnceLock};
use std::thread::JoinHandle;
use std::time::Duration;

/// Queue capacity of `Recorder::start`, in events (a pulse batch is one event).
pub const DEFAULT_QUEUE_EVENTS: usize = 32_768;

/// How often the idle recorder thread looks at the finish request.
const POLL: Duration = Duration::from_millis(10);

/// Why this process is stopping early, once `interrupt_all` was called.
static INTERRUPTED: OnceLock<String> = OnceLock::new();

/// Marks every recording of this process finished from now on as interrupted (a stop signal,
/// docs/recording.md): its closing metadata says `complete: false` and `interrupted: WHY`.
/// Process-wide because a signal is; the first reason given stays.
pub fn interrupt_all(why: &str) {
    let _ = INTERRUPTED.set(why.to_string());
}

/// Why this process is stopping early, if `interrupt_all` was called.
pub fn interrupted() -> Option<&'static str> {
    INTERRUPTED.get().map(String::as_str)
}

/// A running recording: the file, the queue and the thread that writes it.
pub struct Recorder {
    sink: Option<EventSink>,
    flags: SinkFlags,
    closing: Arc<AtomicBool>,
    thread: Option<JoinHandle<WriterOutcome>>,
    path: PathBuf,
    capacity: usize,
}

impl Recorder {
    /// Creates the MCAP file and starts the recorder thread with a queue of
    /// `DEFAULT_QUEUE_EVENTS` events. Fails if the file cannot be created.
    pub fn start(path: &Path, settings: &MachineSettings) -> Result<Recorder, String> {
        Recorder::start_with_capacity(path, settings, DEFAULT_QUEUE_EVENTS)
    }

    /// As `start`, with a queue of `capacity` events (at least 1); small ones are for tests.
    pub fn start_with_capacity(
        path: &Path,
        settings: &MachineSettings,
        capacity: usize,
    ) -> Result<Recorder, String> {
        Recorder::start_with(path, settings, &RecordingInfo::default(), capacity)
    }

    /// As `start`, the file beginning with the run's program and data (attachments and the
    /// `novanc.program` metadata), and the tools' sizes drawn in the scene.
    pub fn start_with_info(
        path: &Path,
        settings: &MachineSettings,
        info: &RecordingInfo,
    ) -> Result<Recorder, String> {
        Recorder::start_with(path, settings, info, DEFAULT_QUEUE_EVENTS)
    }

    /// The body of the `start` functions.
    fn start_with(
        path: &Path,
        settings: &MachineSettings,
        info: &RecordingInfo,
        capacity: usize,
    ) -> Result<Recorder, String> {
        let capacity = capacity.max(1);
        let writer = RecordWriter::create_with(path, settings, info)?;
        let (tx, rx) = sync_channel(capacity);
        let sink = EventSink::new(tx);
        let flags = sink.flags();
        let closing = Arc::new(AtomicBool::new(false));
        let thread = {
            let flags = flags.clone();
            let closing = Arc::clone(&closing);
            std::thread::Builder::new()
                .name("recorder".to_string())
                .spawn(move || drain(rx, writer, &flags, &closing, capacity))
                .map_err(|e| format!("cannot start the recorder thread: {e}"))?
        };
        Ok(Recorder {
            sink: Some(sink),
            flags,
            closing,
            thread: Some(thread),
            path: path.to_path_buf(),
            capacity,
        })
    }

    /// A sending side for one more producer (pulse core, console).
    pub fn sink(&self) -> EventSink {
        match &self.sink {
            Some(sink) => sink.clone(),
            // Only reachable during `finish`/`drop`; a sink on a closed channel drops everything.
            None => EventSink::new(sync_channel(0).0),
        }
    }

    /// Whether an event has been lost so far (queue full or disk error), for the display.
    pub fn is_incomplete(&self) -> bool {
        self.flags.is_incomplete()
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The queue capacity, events.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Closes the queue, writes what is still in it, then the summary section and the footer,
    /// and returns the summary. Fails with the operator's summary line (`RECORDING INCOMPLETE
    /// …: DISK ERROR …`) when a disk error left the file unfinished, and when the recorder
    /// thread itself was lost; `close` returns the summary in the first case. Producers that
    /// still hold a sink afterwards have their events dropped and counted by the sink.
    pub fn finish(mut self) -> Result<RecordSummary, String> {
        let sum = self.close_file()?;
        match sum.disk_error {
            Some(_) => Err(sum.to_string()),
            None => Ok(sum),
        }
    }

    /// As `finish`, but a disk error is only reported in the summary (`disk_error`,
    /// `incomplete`, the counts of what is on disk). Fails only if the recorder thread was lost.
    pub fn close(mut self) -> Result<RecordSummary, String> {
        self.close_file()
    }

    /// The body of `finish` and `close` (also run by `drop`).
    fn close_file(&mut self) -> Result<RecordSummary, String> {
        self.sink = None;
        self.closing.store(true, Ordering::Release);
        let Some(thread) = self.thread.take() else {
            return Err(format!(
                "recording {} was already finished",
                self.path.display()
            ));
        };
        let out = thread.join().map_err(|_| {
            self.flags.mark_incomplete();
            format!(
                "the recorder thread stopped unexpectedly; recording {} is incomplete",
                self.path.display()
            )
        })?;
        if out.disk_error.is_some() {
            self.flags.mark_incomplete();
        }
        Ok(RecordSummary {
            path: self.path.clone(),
            messages: out.messages,
            lathe_events: out.lathe_events,
            foxglove: out.foxglove,
            pulses: out.pulses,
            bytes: out.bytes,
            incomplete: self.flags.is_incomplete(),
            dropped: self.flags.dropped(),
            lost_to_disk_error: out.lost_to_disk_error,
            disk_error: out.disk_error,
            interrupted: out.interrupted,
        })
    }
}

impl Drop for Recorder {
    /// An unfinished recording is still closed properly (summary and footer written).
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.close_file();
        }
    }
}

/// The recorder thread: write every event until every sink is gone or `finish` was called,
/// then drain at most one queue's worth more (so a producer that keeps sending cannot keep the
/// thread alive) and close the file.
fn drain(
    rx: Receiver<Event>,
    mut writer: RecordWriter,
    flags: &SinkFlags,
    closing: &AtomicBool,
    capacity: usize,
) -> WriterOutcome {
    let write = |ev: Event, writer: &mut RecordWriter| {
        if !writer.write(&ev) {
            flags.mark_incomplete();
        }
    };
    loop {
        match rx.recv_timeout(POLL) {
            Ok(ev) => {
                write(ev, &mut writer);
                if closing.load(Ordering::Acquire) {
                    break;
                }
            }
            Err(RecvTimeoutError::Timeout) => {
                if closing.load(Ordering::Acquire) {
                    break;
                }
                // Nothing comes: commit what the open chunk holds once it is due, so that the
                // file keeps up with the run even when the process is killed outright.
                if !writer.keep_readable() {
                    flags.mark_incomplete();
                }
            }
            Err(RecvTimeoutError::Disconnected) => break,
        }
    }
    for _ in 0..capacity {
        match rx.try_recv() {
            Ok(ev) => write(ev, &mut writer),
            Err(_) => break,
        }
    }
    drop(rx);
    if writer.failed() {
        flags.mark_incomplete();
    }
    if let Some(why) = INTERRUPTED.get() {
        flags.mark_incomplete();
        writer.note_interrupted(why);
    }
    writer.finish(flags.is_incomplete(), flags.dropped())
}

/// What the operator is told when a recording ends.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordSummary {
    /// The MCAP file.
    pub path: PathBuf,
    /// Messages written per topic, in `Topic::ALL` order.
    pub messages: [u64; TOPICS],
    /// Messages written on `/lathe/event` (a kernel's channels).
    pub lathe_events: u64,
    /// Derived Foxglove messages written (`/foxglove/scene`, `/foxglove/tool`).
    pub foxglove: [u64; DERIVED],
    /// Pulses written in `/nc/pulses`.
    pub pulses: u64,
    /// File size, bytes (0 after a disk error).
    pub bytes: u64,
    /// Whether any event is missing from the file.
    pub incomplete: bool,
    /// Events dropped because the queue was full (the recorder fell behind) or closed.
    pub dropped: u64,
    /// Events that reached the recorder after a disk error, hence not in the file.
    pub lost_to_disk_error: u64,
    /// The disk error, if one happened.
    pub disk_error: Option<String>,
    /// Why the recording was cut short (a stop signal, `interrupt_all`), if it was.
    pub interrupted: Option<String>,
}

impl RecordSummary {
    /// Messages written on a topic, by its name (`"/nc/pulses"`, `"/foxglove/scene"`); 0 for
    /// an unknown topic.
    pub fn count(&self, topic: &str) -> u64 {
        if let Some(d) = super::foxglove::Derived::ALL
            .iter()
            .find(|d| d.name() == topic)
        {
            return self.foxglove[d.index()];
        }
        if topic == Topic::LatheEvent.name() {
            return self.lathe_events;
        }
        Topic::ALL
            .iter()
            .find(|t| t.name() == topic)
            .map_or(0, |t| self.messages[t.index()])
    }

    /// Messages written on every topic together.
    pub fn total_messages(&self) -> u64 {
        self.messages.iter().sum::<u64>() + self.lathe_events
    }
}

impl fmt::Display for RecordSummary {
    /// One line for the operator, e.g. `recording run.mcap: 12 blocks, 40 positions,
    /// 1234567 pulses in 620 batches, 5 states, 3 displays, 2 panel events, 17.2 MB`, led by
    /// `RECORDING INCOMPLETE` and the reason when anything is missing; `, 2 probes` after the
    /// panel events when there were any.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.incomplete {
            write!(f, "RECORDING INCOMPLETE {}:", self.path.display())?;
            let mut sep = "";
            if let Some(why) = &self.interrupted {
                write!(f, " {why}")?;
                sep = ";";
            }
            if self.dropped > 0 {
                write!(
                    f,
                    "{sep} {} events dropped (the recorder fell behind)",
                    self.dropped
                )?;
                sep = ";";
            }
            if let Some(e) = &self.disk_error {
                write!(f, "{sep} DISK ERROR {e}")?;
                if self.lost_to_disk_error > 0 {
                    write!(f, ", {} events not written", self.lost_to_disk_error)?;
                }
                sep = ";";
            }
            if sep.is_empty() {
                write!(f, " events were lost")?;
            }
            write!(f, "; in the file:")?;
        } else {
            write!(f, "recording {}:", self.path.display())?;
        }
        let m = &self.messages;
        write!(
            f,
            " {} blocks, {} positions, {} pulses in {} batches, {} states, {} displays, {} panel events",
            m[0], m[1], self.pulses, m[2], m[3], m[4], m[5]
        )?;
        if m[6] > 0 {
            write!(f, ", {} probes", m[6])?;
        }
        if m[Topic::Log.index()] > 0 {
            write!(f, ", {} log messages", m[Topic::Log.index()])?;
        }
        if self.lathe_events > 0 {
            write!(f, ", {} lathe events", self.lathe_events)?;
        }
        if self.disk_error.is_none() {
            write!(f, ", {:.1} MB", self.bytes as f64 / 1e6)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary() -> RecordSummary {
        RecordSummary {
            path: PathBuf::from("run.mcap"),
            messages: [12, 40, 620, 5, 3, 2, 0, 0, 0],
            lathe_events: 0,
            foxglove: [0, 0],
            pulses: 1_234_567,
            bytes: 17_200_000,
            incomplete: false,
            dropped: 0,
            lost_to_disk_error: 0,
            disk_error: None,
            interrupted: None,
        }
    }

    #[test]
    fn complete_summary_line_counts_every_topic() {
        let s = summary();
        assert_eq!(
            s.to_string(),
            "recording run.mcap: 12 blocks, 40 positions, 1234567 pulses in 620 batches, \
             5 states, 3 displays, 2 panel events, 17.2 MB"
        );
        assert_eq!(s.count("/nc/pulses"), 620);
        assert_eq!(s.count("/panel/event"), 2);
        assert_eq!(s.count("/nope"), 0);
        assert_eq!(s.total_messages(), 682);
    }

    #[test]
    fn incomplete_summary_line_says_why() {
        let mut s = summary();
        s.incomplete = true;
        s.dropped = 17;
        let line = s.to_string();
        assert!(
            line.starts_with("RECORDING INCOMPLETE run.mcap: 17 events dropped"),
            "{line}"
        );
        s.dropped = 0;
        s.disk_error = Some("writing /dev/full: No space left on device".into());
        s.lost_to_disk_error = 3;
        let line = s.to_string();
        assert!(
            line.contains(
                "DISK ERROR writing /dev/full: No space left on device, 3 events not written"
            ),
            "{line}"
        );
        assert!(!line.contains("MB"), "{line}");
    }

    #[test]
    fn interrupted_summary_line_leads_with_the_signal() {
        let mut s = summary();
        s.incomplete = true;
        s.interrupted = Some("interrupted by SIGTERM".into());
        let line = s.to_string();
        assert!(
            line.starts_with(
                "RECORDING INCOMPLETE run.mcap: interrupted by SIGTERM; in the file: 12 blocks"
            ),
            "{line}"
        );
        s.dropped = 4;
        let line = s.to_string();
        assert!(
            line.contains("interrupted by SIGTERM; 4 events dropped"),
            "{line}"
        );
    }

    #[test]
    fn finish_after_every_event_writes_them_all() {
        let path =
            std::env::temp_dir().join(format!("novanc-rec-unit-{}.mcap", std::process::id()));
        let rec = Recorder::start(&path, &MachineSettings::default()).unwrap();
        let sink = rec.sink();
        for i in 0..100u64 {
            sink.send(Event::Pulses {
                axis: (i % 3) as u8,
                dir: 1,
                t_ns: vec![i * 10, i * 10 + 1],
            });
        }
        // The producer keeps its sink: finish must not wait for it.
        let s = rec.finish().unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(s.count("/nc/pulses"), 100);
        assert_eq!(s.pulses, 200);
        assert!(!s.incomplete);
        sink.send(Event::PanelEvent {
            t_ns: 0,
            event: "late".into(),
        });
        assert!(
            sink.is_incomplete(),
            "an event after finish is lost and said so"
        );
    }
}
