//! Recording a lathe run (docs/recording.md "Lathe recordings"): the same MCAP topics as the
//! machining centre, every message of a channel carrying `channel` (1-based), and one more
//! topic, `/lathe/event`, for what a lathe does besides moving: transfers, thread pass starts,
//! cuts started, parts counted, waits, faults and alarms. Readers that ignore unknown fields
//! read it as they read a centre's recording.
//!
//! The lathe simulator runs in the thread that records, so the writer is synchronous: nothing
//! is ever dropped. The file is kept readable as the centre's is (`crate::record::file`): chunks
//! are closed and committed at 4 MB, after a second, or when a stop signal was noted. A lathe recording has no `/nc/pulses`: the simulator counts pulses per
//! tick, not their times; the counters on `/nc/position` are exact.

use crate::record::file::{
    mcap_options, recording_metadata, CommitClock, RecordFile, RecordOutput, CHUNK_BYTES,
    MESSAGE_RECORD_OVERHEAD,
};
use crate::record::json::{push_i64, push_mm, push_str, push_u64};
use crate::record::topic::Topic;
use crate::record::writer::cause;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The lathe's extra topic.
pub const EVENT_TOPIC: &str = "/lathe/event";

/// The schema of `/lathe/event`: the one recorder's (`crate::record::topic`).
const EVENT_SCHEMA: &str = crate::record::topic::LATHE_EVENT_SCHEMA;

/// Topic slots of a lathe recording.
const BLOCK: usize = 0;
const POSITION: usize = 1;
const STATE: usize = 2;
const DISPLAY: usize = 3;
const PANEL: usize = 4;
const EVENT: usize = 5;
const TOPICS: usize = 6;

/// Messages written per topic: /nc/block, /nc/position, /nc/state, /panel/display,
/// /panel/event, /lathe/event.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LatheRecordSummary {
    /// The file.
    pub path: PathBuf,
    /// Messages per topic, in the order above.
    pub messages: [u64; TOPICS],
    /// The first write error, if any (the recording is then incomplete).
    pub error: Option<String>,
}

impl LatheRecordSummary {
    /// The summary line `novanc run` prints.
    pub fn line(&self) -> String {
        let total: u64 = self.messages.iter().sum();
        match &self.error {
            None => format!(
                "recording: {} complete, {total} messages",
                self.path.display()
            ),
            Some(e) => format!("recording: {} INCOMPLETE: {e}", self.path.display()),
        }
    }
}

/// One channel's state for `/nc/state`.
#[derive(Clone, Debug, PartialEq)]
pub struct StateMsg<'a> {
    /// 1 while the channel runs its program, else 0.
    pub run: u8,
    /// The console's operation mode (`AUTO`, `MDI`, `DATA`).
    pub op_mode: &'a str,
    /// The channel's state word (`RUN`, `WAIT`, `FAULT`, ...), written as `data_mode`.
    pub state: &'a str,
    /// Feed override, percent.
    pub feed_override: u32,
    /// Tool number, 0 none.
    pub tool: u32,
    /// Spindle rpm, signed (negative = M04).
    pub spindle: i64,
    /// The channel's part count.
    pub parts: u32,
}

/// The writer of a lathe recording.
pub struct LatheRecorder {
    mcap: Option<mcap::Writer<RecordFile>>,
    /// Bytes of the open chunk's messages.
    open_bytes: u64,
    clock: CommitClock,
    ids: [u16; TOPICS],
    seq: [u32; TOPICS],
    pulse_mm: f64,
    buf: Vec<u8>,
    sum: LatheRecordSummary,
}

impl LatheRecorder {
    /// Creates the file: header, the `novanc.settings` metadata (pulse size, tick, machine,
    /// channels), schemas and channels.
    pub fn create(
        path: &Path,
        machine: &str,
        channels: usize,
        pulse_mm: f64,
        tick_ns: u64,
    ) -> Result<LatheRecorder, String> {
        let file = RecordFile::create(path)
            .map_err(|e| format!("cannot create recording {}: {e}", path.display()))?;
        let mut w = mcap_options()
            .create(file)
            .map_err(|e| format!("recording {}: {}", path.display(), cause(&e)))?;
        let mut ids = [0u16; TOPICS];
        let declare = |w: &mut mcap::Writer<RecordFile>, ids: &mut [u16; TOPICS]| {
            let meta = BTreeMap::from([
                ("pulse_mm".to_string(), pulse_mm.to_string()),
                ("ncbr_period_ns".to_string(), tick_ns.to_string()),
                ("machine".to_string(), machine.to_string()),
                ("channels".to_string(), channels.to_string()),
                (
                    "time".to_string(),
                    "machine time, ns since the run started".to_string(),
                ),
            ]);
            w.write_metadata(&mcap::records::Metadata {
                name: "novanc.settings".into(),
                metadata: meta,
            })?;
            let none = BTreeMap::new();
            for (slot, t) in [
                (BLOCK, Topic::Block),
                (POSITION, Topic::Position),
                (STATE, Topic::State),
                (DISPLAY, Topic::Display),
                (PANEL, Topic::PanelEvent),
            ] {
                let s = w.add_schema(t.schema_name(), "jsonschema", t.schema().as_bytes())?;
                ids[slot] = w.add_channel(s, t.name(), "json", &none)?;
            }
            let s = w.add_schema("novanc.LatheEvent", "jsonschema", EVENT_SCHEMA.as_bytes())?;
            ids[EVENT] = w.add_channel(s, EVENT_TOPIC, "json", &none)?;
            // Committed at once: the file is a (still empty) recording from the start.
            w.flush()
        };
        declare(&mut w, &mut ids)
            .map_err(|e| format!("recording {}: {}", path.display(), cause(&e)))?;
        Ok(LatheRecorder {
            mcap: Some(w),
            open_bytes: 0,
            clock: CommitClock::default(),
            ids,
            seq: [0; TOPICS],
            pulse_mm,
            buf: Vec::with_capacity(4096),
            sum: LatheRecordSummary {
                path: path.to_path_buf(),
                ..Default::default()
            },
        })
    }

    fn put(&mut self, slot: usize, t_ns: u64) {
        self.keep_readable();
        let Some(w) = self.mcap.as_mut() else { return };
        let h = mcap::records::MessageHeader {
            channel_id: self.ids[slot],
            sequence: self.seq[slot],
            log_time: t_ns,
            publish_time: t_ns,
        };
        match w.write_to_known_channel(&h, &self.buf) {
            Ok(()) => {
                self.seq[slot] = self.seq[slot].wrapping_add(1);
                self.sum.messages[slot] += 1;
                self.open_bytes += self.buf.len() as u64 + MESSAGE_RECORD_OVERHEAD;
                self.clock.wrote();
            }
            Err(e) => self.fail(e),
        }
    }

    /// Keeps the first error and lets go of the file, which ends where its last commit left
    /// it (a finished MCAP file: `crate::record::file`).
    fn fail(&mut self, e: mcap::McapError) {
        self.sum.error = Some(format!(
            "writing {}: {}",
            self.sum.path.display(),
            cause(&e)
        ));
        if let Some(w) = self.mcap.take() {
            drop(w.into_inner());
        }
    }

    /// Closes and commits the open chunk if it is due (4 MB, a second old, or a stop signal
    /// noted since the last commit). The console calls it as time passes, so the file keeps up
    /// with the machine even when no message comes.
    pub fn keep_readable(&mut self) {
        let Some(w) = self.mcap.as_mut() else { return };
        if self.clock.due(self.open_bytes, CHUNK_BYTES) {
            match w.flush() {
                Ok(()) => {
                    self.open_bytes = 0;
                    self.clock.committed();
                }
                Err(e) => self.fail(e),
            }
        }
    }

    /// Starts a channel's message in the buffer: `{"channel":N` (1-based).
    fn begin(&mut self, ch: usize) -> &mut Vec<u8> {
        self.buf.clear();
        self.buf.extend_from_slice(b"{\"channel\":");
        push_u64(&mut self.buf, ch as u64 + 1);
        &mut self.buf
    }

    /// `/nc/block`: a block of channel `ch` (0-based) starts.
    pub fn block(&mut self, t_ns: u64, ch: usize, seq: u32, line: u32, text: &str) {
        let b = self.begin(ch);
        b.extend_from_slice(b",\"seq\":");
        push_u64(b, u64::from(seq));
        b.extend_from_slice(b",\"stmt\":");
        push_u64(b, u64::from(line));
        b.extend_from_slice(b",\"text\":");
        push_str(b, text);
        b.push(b'}');
        self.put(BLOCK, t_ns);
    }

    /// `/nc/position`: channel `ch`'s tool tip, pulses [X radius, Z]; `speed` mm/min; the
    /// spindle's rpm (signed).
    pub fn position(&mut self, t_ns: u64, ch: usize, pulses: [i64; 2], speed: f64, rpm: f64) {
        let mm = self.pulse_mm;
        let b = self.begin(ch);
        b.extend_from_slice(b",\"x\":");
        push_mm(b, pulses[0] as f64 * mm);
        b.extend_from_slice(b",\"y\":0,\"z\":");
        push_mm(b, pulses[1] as f64 * mm);
        b.extend_from_slice(b",\"pulses\":[");
        push_i64(b, pulses[0]);
        b.extend_from_slice(b",0,");
        push_i64(b, pulses[1]);
        b.extend_from_slice(b"],\"speed\":");
        push_mm(b, speed);
        b.extend_from_slice(b",\"rpm\":");
        push_mm(b, rpm);
        b.push(b'}');
        self.put(POSITION, t_ns);
    }

    /// `/nc/state`: channel `ch`'s state changed.
    pub fn state(&mut self, t_ns: u64, ch: usize, s: &StateMsg) {
        let b = self.begin(ch);
        b.extend_from_slice(b",\"run\":");
        push_u64(b, u64::from(s.run));
        b.extend_from_slice(b",\"op_mode\":");
        push_str(b, s.op_mode);
        b.extend_from_slice(b",\"data_mode\":");
        push_str(b, s.state);
        b.extend_from_slice(b",\"feed_override\":");
        push_u64(b, u64::from(s.feed_override));
        b.extend_from_slice(b",\"tool\":");
        push_u64(b, u64::from(s.tool));
        b.extend_from_slice(b",\"spindle\":");
        push_i64(b, s.spindle);
        b.extend_from_slice(b",\"parts\":");
        push_u64(b, u64::from(s.parts));
        b.push(b'}');
        self.put(STATE, t_ns);
    }

    /// `/lathe/event`: channel `ch`'s event `kind`, with its work piece and number if any.
    pub fn event(
        &mut self,
        t_ns: u64,
        ch: usize,
        kind: &str,
        work: Option<u32>,
        value: Option<i64>,
        text: &str,
    ) {
        let b = self.begin(ch);
        b.extend_from_slice(b",\"event\":");
        push_str(b, kind);
        if let Some(w) = work {
            b.extend_from_slice(b",\"work\":");
            push_u64(b, u64::from(w));
        }
        if let Some(v) = value {
            b.extend_from_slice(b",\"value\":");
            push_i64(b, v);
        }
        b.extend_from_slice(b",\"text\":");
        push_str(b, text);
        b.push(b'}');
        self.put(EVENT, t_ns);
    }

    /// `/panel/display`: the display changed.
    pub fn display(&mut self, t_ns: u64, lines: &[String]) {
        let b = &mut self.buf;
        b.clear();
        b.extend_from_slice(b"{\"lines\":[");
        for (i, l) in lines.iter().enumerate() {
            if i > 0 {
                b.push(b',');
            }
            push_str(b, l);
        }
        b.extend_from_slice(b"]}");
        self.put(DISPLAY, t_ns);
    }

    /// `/panel/event`: an operator action, as a panel-script line.
    pub fn panel_event(&mut self, t_ns: u64, event: &str) {
        let b = &mut self.buf;
        b.clear();
        b.extend_from_slice(b"{\"event\":");
        push_str(b, event);
        b.push(b'}');
        self.put(PANEL, t_ns);
    }

    /// Writes the closing `novanc.recording` metadata (`complete`, `interrupted` if given) and
    /// the summary, and closes the file.
    pub fn finish(mut self, interrupted: Option<&str>) -> LatheRecordSummary {
        if let Some(mut w) = self.mcap.take() {
            let complete = interrupted.is_none() && self.sum.error.is_none();
            let r = w
                .write_metadata(&recording_metadata(complete, Some(0), interrupted))
                .and_then(|_| w.finish());
            let r = match r {
                Ok(_) => w.into_inner().close().map_err(mcap::McapError::from),
                Err(e) => {
                    drop(w.into_inner());
                    Err(e)
                }
            };
            if let Err(e) = r {
                self.sum.error = Some(format!(
                    "writing {}: {}",
                    self.sum.path.display(),
                    cause(&e)
                ));
            }
        }
        if let Some(why) = interrupted {
            if self.sum.error.is_none() {
                self.sum.error = Some(why.to_string());
            }
        }
        self.sum.clone()
    }
}
