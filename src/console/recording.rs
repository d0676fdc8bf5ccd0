//! The recording of a console session (docs/recording.md): every console's, the centre's and
//! the lathe's. The console's own events (panel events as their script lines, display frames,
//! the messages on `/foxglove/log`) go through it; the machine (the pulse core) gets its sink.

use crate::panel_model::PanelEvent;
use crate::record::{Event, EventSink, Recorder, RecordingInfo};
use crate::settings::MachineSettings;
use std::path::Path;

/// The recording of a session (docs/recording.md): panel events and display frames go to the recorder;
/// the pulse core gets the same sink for blocks, positions, pulses and `/nc/state` (the
/// console tells it the selector positions).
pub struct Recording {
    recorder: Option<Recorder>,
    sink: Option<EventSink>,
}

impl Recording {
    /// Starts recording to `path`, if given, the file beginning with `info` (the program in
    /// memory, the tool data, the work offsets); else to `sink`, if given.
    pub fn start(
        path: Option<&Path>,
        sink: Option<EventSink>,
        settings: &MachineSettings,
        info: &RecordingInfo,
    ) -> Result<Recording, String> {
        let recorder = match path {
            Some(p) => Some(Recorder::start_with_info(p, settings, info)?),
            None => None,
        };
        Ok(Recording {
            sink: recorder.as_ref().map(|r| r.sink()).or(sink),
            recorder,
        })
    }

    /// Whether anything is recorded.
    pub fn on(&self) -> bool {
        self.sink.is_some()
    }

    /// The sink for the pulse core.
    pub fn sink(&self) -> Option<EventSink> {
        self.sink.clone()
    }

    /// Records an operator action as its script line.
    pub fn panel_event(&mut self, ev: &PanelEvent, t_ns: u64) {
        if let Some(s) = &self.sink {
            s.send(Event::PanelEvent {
                t_ns,
                event: super::script_line::script_line(ev),
            });
        }
    }

    /// Records a message or an alarm of the MSG history on `/foxglove/log`.
    pub fn log(&mut self, t_ns: u64, level: u8, message: &str, file: &str, line: u32) {
        if let Some(s) = &self.sink {
            s.send(Event::Log {
                t_ns,
                level,
                name: "console".into(),
                message: message.to_string(),
                file: file.to_string(),
                line,
            });
        }
    }

    /// The display as it now stands (`lines`), every console's rule: recorded on
    /// `/nc/display` when it differs from the frame before, `last`, which it then becomes.
    pub fn frame(&mut self, last: &mut Vec<String>, lines: Vec<String>, t_ns: u64) {
        if lines == *last {
            return;
        }
        if let Some(s) = &self.sink {
            s.send(Event::Display {
                t_ns,
                lines: lines.iter().map(|l| l.trim_end().to_string()).collect(),
            });
        }
        *last = lines;
    }

    /// Closes the recording; its summary.
    pub fn finish(self) -> Result<Option<String>, String> {
        drop(self.sink);
        match self.recorder {
            Some(r) => r.finish().map(|s| Some(s.to_string())),
            None => Ok(None),
        }
    }
}
