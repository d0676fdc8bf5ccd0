//! Tape reader 13 and the punch at the console (docs/tape.md, "At the console").
//!
//! START in PROGRAM READ or TOOL DATA READ puts the tape in motion: the reader takes
//! `MachineSettings::tape_chars_per_s` frames a second of machine time, so in real time the
//! read takes that long and the display shows the tape passing under the read head, and in
//! virtual time (scripts, tests) the read's frames pass when the script waits (`wait` lets it
//! finish, `wait ms T` lets T ms of it pass). The result is stored only when the whole tape has
//! been read without error; STOP, RESET, E-STOP or a turned selector abandon the read, and an
//! error stops it with the ALARM lamp lit (RESET clears it): in every such case program memory
//! and the tool file are unchanged. Keys other than those are refused while the tape moves.
//!
//! The punch key is in `punch.rs`.

use super::script_line::script_line;
use super::Console;
use crate::panel_model::PanelEvent;
use crate::tape::{self, Code, Frame, Meaning, ReadOptions, Reader, Tape, TapeError};
use std::path::Path;

/// The largest tape image the reader takes: 4 MiB, about 10 km of tape and almost 4 hours at
/// 300 characters/s (a 1,000-foot roll holds 120,000 frames).
pub const MAX_TAPE_BYTES: u64 = 4 << 20;

/// The largest plain text file PROGRAM READ takes (a file or each file of a memory card
/// folder): 64 MiB. A text file is not a tape: it is read at file speed.
pub const MAX_TEXT_BYTES: u64 = 64 << 20;

/// How many of the last frames a front end is given to draw (the window's strip).
pub const STRIP_FRAMES: usize = 48;

/// What a read stores: program memory (PROGRAM READ) or the tool file (TOOL DATA READ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReadTarget {
    /// PROGRAM READ.
    Program,
    /// TOOL DATA READ.
    Tools,
}

impl ReadTarget {
    /// The data-processing mode's name: `PROGRAM READ`, `TOOL DATA READ`.
    pub fn name(self) -> &'static str {
        match self {
            ReadTarget::Program => "PROGRAM READ",
            ReadTarget::Tools => "TOOL DATA READ",
        }
    }
}

/// A tape read in progress (or stopped by an error, kept for the display until RESET).
pub(super) struct TapeRead {
    target: ReadTarget,
    /// The file name, for messages.
    file: String,
    image: Vec<u8>,
    /// What the whole read gives (decoded at START, as `novanc tape read` does); it is stored
    /// or alarmed only when the tape has passed the read head up to `stop`.
    outcome: Result<Tape, TapeError>,
    /// Frames the reader takes before it stops: the closing rewind stop, the frame in error,
    /// or the end of the image.
    stop: usize,
    /// The frame-by-frame reader the display shows (`None` for a plain text file).
    reader: Option<Reader>,
    /// Frames (bytes, for a text file) passed under the read head so far.
    fed: usize,
    start_ns: u64,
    chars_per_s: u64,
    /// The error, once the read has stopped on it.
    failed: Option<TapeError>,
}

impl TapeRead {
    /// Machine time from the start until frame `n` has passed the read head.
    fn ns_for(&self, n: usize) -> u64 {
        let ns = (n as u128 * 1_000_000_000).div_ceil(self.chars_per_s as u128);
        ns.min(u64::MAX as u128) as u64
    }

    /// Frames due at machine time `now`.
    fn due(&self, now: u64) -> usize {
        let n =
            now.saturating_sub(self.start_ns) as u128 * self.chars_per_s as u128 / 1_000_000_000;
        n.min(self.stop as u128) as usize
    }

    /// Feeds the frames due to the display's reader.
    fn feed_to(&mut self, due: usize) {
        if due <= self.fed {
            return;
        }
        if let Some(r) = &mut self.reader {
            let _ = r.feed(&self.image[self.fed..due]);
        }
        self.fed = due;
    }

    /// `frame 40 of 312`.
    fn at(&self) -> String {
        format!("frame {} of {}", self.fed, self.image.len())
    }
}

/// What a front end draws of a read: the last frames and the counters.
#[derive(Clone, Debug, PartialEq)]
pub struct TapeView {
    /// PROGRAM READ or TOOL DATA READ.
    pub target: ReadTarget,
    /// The tape's file name.
    pub file: String,
    /// The code, once the reader has recognized it; `None` before, and for a text file.
    pub code: Option<Code>,
    /// A plain text file rather than a tape image.
    pub plain: bool,
    /// The last frames read (at most [`STRIP_FRAMES`]), oldest first: the last one is under
    /// the read head. Empty for a text file.
    pub frames: Vec<Frame>,
    /// The number (0-based in the image) of the first frame in `frames`.
    pub first: u64,
    /// Frames passed under the read head.
    pub frame: u64,
    /// Frames on the image.
    pub total: u64,
    /// The block being read (0: the label).
    pub block: u64,
    /// The read stopped on an error (the last frame is the one in error, or just after it).
    pub failed: bool,
}

/// The read in progress, or the one an error stopped, for the display.
fn shown(c: &Console) -> Option<&TapeRead> {
    c.tape_read.as_ref().or(c.tape_stopped.as_ref())
}

/// The view of the read on display, if one is.
pub(super) fn view(c: &Console) -> Option<TapeView> {
    let r = shown(c)?;
    let (code, frames, first, block) = match &r.reader {
        Some(rd) => {
            let f = rd.frames();
            let from = f.len().saturating_sub(STRIP_FRAMES);
            (
                rd.code(),
                f[from..].iter().map(|&b| Frame(b)).collect(),
                from as u64,
                rd.block(),
            )
        }
        None => (
            None,
            Vec::new(),
            0,
            r.image[..r.fed].iter().filter(|&&b| b == b'\n').count() as u64 + 1,
        ),
    };
    Some(TapeView {
        target: r.target,
        file: r.file.clone(),
        code,
        plain: r.reader.is_none(),
        frames,
        first,
        frame: r.fed as u64,
        total: r.image.len() as u64,
        block,
        failed: r.failed.is_some(),
    })
}

/// Whether the tape is moving.
pub(super) fn reading(c: &Console) -> bool {
    c.tape_read.is_some()
}

impl Console {
    /// The alarm of the tape read an error stopped, until RESET.
    pub fn tape_alarm(&self) -> Option<&str> {
        self.tape_alarm.as_deref()
    }

    /// The tape read in progress, or the one an error stopped, for a front end to draw.
    pub fn tape_view(&self) -> Option<TapeView> {
        view(self)
    }

    /// Whether the tape reader is reading (the tape is moving).
    pub fn tape_reading(&self) -> bool {
        reading(self)
    }

    /// The punch key (docs/panel.md): in PROGRAM READ the typed line names the image to punch
    /// program memory to (`PATH`, or `PATH EIA` for the EIA code).
    pub fn punch_from_entry(&mut self) {
        // Recorded as the key, which takes the typed line (the tape reader key's rule).
        self.status = self.core.status();
        self.shell.recorder.panel_event(
            &PanelEvent::Press(super::state::PUNCH_KEY),
            self.status.machine_ns,
        );
        super::punch::punch_from_entry(self);
        self.refresh();
    }
}

/// START in PROGRAM READ or TOOL DATA READ: the tape in the reader starts moving. A plain
/// text file, or a memory card folder of them, is no tape: it is read at file speed and stored
/// at once.
pub(super) fn start_read(c: &mut Console, target: ReadTarget) {
    let what = target.name();
    let Some(path) = c.tape.clone() else {
        c.shell.front.message = "the tape reader is empty: put a tape in (tape PATH)".into();
        return;
    };
    let file = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if path.is_dir() {
        read_folder(c, target, &path, &file);
        return;
    }
    let image = match load(&path) {
        Ok(i) => i,
        Err(e) => {
            c.shell.front.message = format!("{what}: tape {file} cannot be read: {e}");
            return;
        }
    };
    let plain = tape::is_plain_text(&image);
    if !plain && image.len() as u64 > MAX_TAPE_BYTES {
        c.shell.front.message = format!(
            "{what}: tape {file} cannot be read: it is longer than the {} MiB the reader takes",
            MAX_TAPE_BYTES >> 20
        );
        return;
    }
    let outcome = tape::read_image(&image, ReadOptions::default());
    let stop = stop_frame(&image, &outcome);
    let chars_per_s = u64::from(c.cfg.settings.tape_chars_per_s.max(1));
    c.tape_stopped = None;
    let r = TapeRead {
        target,
        file: file.clone(),
        reader: (!plain).then(|| Reader::new(ReadOptions::default())),
        image,
        outcome,
        stop,
        fed: if plain { stop } else { 0 },
        start_ns: c.status.machine_ns,
        chars_per_s,
        failed: None,
    };
    if plain {
        complete(c, r);
        return;
    }
    c.tape_read = Some(r);
    c.shell.front.message =
        format!("reading at {chars_per_s} characters/s: STOP or RESET abandons the read");
    advance(c);
}

/// PROGRAM READ of a memory card folder: every file in it, in name order, becomes a program
/// named after the file, the first one current. Every file must be plain text (a tape image
/// goes through the reader, one at a time) and every name must make a program name; if one
/// does not, nothing is stored.
fn read_folder(c: &mut Console, target: ReadTarget, dir: &Path, name: &str) {
    let what = target.name();
    if target == ReadTarget::Tools {
        c.shell.front.message = format!(
            "{what}: {name} is a folder; TOOL DATA READ takes one tool tape, tool file unchanged"
        );
        return;
    }
    let files = match folder_files(dir) {
        Ok(f) => f,
        Err(e) => {
            c.shell.front.message =
                format!("{what} refused, program memory unchanged: folder {name}: {e}");
            return;
        }
    };
    let mut names = Vec::with_capacity(files.len());
    for (file, _) in &files {
        match crate::store::program_name_from_file(file) {
            Ok(n) if names.contains(&n.name) => {
                c.shell.front.message = format!(
                    "{what} refused, program memory unchanged: {file} would be program {} as well as another file of {name}",
                    n.name
                );
                return;
            }
            Ok(n) => names.push(n.name),
            Err(e) => {
                c.shell.front.message =
                    format!("{what} refused, program memory unchanged: {file}: {e}");
                return;
            }
        }
    }
    let mut lines = 0;
    let mut stored = Vec::new();
    for (file, text) in &files {
        match c.mem.program_read_file(file, text) {
            Ok(r) => {
                lines += text.lines().count();
                stored.push(r.name);
            }
            Err(e) => {
                c.shell.front.message = format!(
                    "{what} stopped at {file}: {e}; stored before it: {}",
                    if stored.is_empty() {
                        "none".to_string()
                    } else {
                        stored.join(" ")
                    }
                );
                return;
            }
        }
    }
    c.search = None;
    if let Some(first) = stored.first() {
        if let Err(e) = c.mem.select_program(first) {
            c.shell.front.message =
                format!("read folder {name}, but program {first} cannot be made current: {e}");
            return;
        }
    }
    c.shell.front.message = format!(
        "read folder {name}: {} programs ({}), {lines} lines; {} is current",
        stored.len(),
        stored.join(" "),
        stored.first().map_or("none", |s| s.as_str())
    );
}

/// The files of a memory card folder, in name order, each read as text. Sub-folders and
/// hidden files (a leading dot) are passed over; a file that is not plain text, or too large,
/// refuses the folder.
fn folder_files(dir: &Path) -> Result<Vec<(String, String)>, String> {
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| e.to_string())?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().map(|t| t.is_file()).unwrap_or(false))
        .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.path())
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err("it holds no file".into());
    }
    let mut out = Vec::with_capacity(paths.len());
    for p in paths {
        let file = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let image = load(&p).map_err(|e| format!("{file}: {e}"))?;
        if !tape::is_plain_text(&image) {
            return Err(format!(
                "{file} is not a plain text file (a tape image is read on its own: tape PATH)"
            ));
        }
        let text = String::from_utf8(image).map_err(|e| format!("{file}: {e}"))?;
        out.push((file, text));
    }
    Ok(out)
}

/// Reads a tape file or a text file, at most [`MAX_TEXT_BYTES`] (a tape image is held to
/// [`MAX_TAPE_BYTES`] once it is known to be one). A lathe's PROGRAM READ loads its file here
/// too (`lathe::console::LatheConsole`'s `program_read`).
pub(crate) fn load(path: &Path) -> Result<Vec<u8>, String> {
    let f = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let meta = f.metadata().map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("it is a directory".into());
    }
    let mut image = Vec::new();
    std::io::Read::read_to_end(&mut std::io::Read::take(f, MAX_TEXT_BYTES + 1), &mut image)
        .map_err(|e| e.to_string())?;
    if image.len() as u64 > MAX_TEXT_BYTES {
        return Err(format!(
            "it is longer than the {} MiB a program file may be",
            MAX_TEXT_BYTES >> 20
        ));
    }
    Ok(image)
}

/// Frames the reader takes before it stops: up to the closing rewind stop on a good tape; up
/// to the frame in error; to the end of the image for errors only the end reveals (no end of
/// block anywhere, a block that never ends).
fn stop_frame(image: &[u8], outcome: &Result<Tape, TapeError>) -> usize {
    use tape::ErrorKind as K;
    let n = match outcome {
        Ok(t) => t.frames as usize,
        Err(e) => match e.kind {
            K::Empty | K::NoEob => image.len(),
            K::MissingEob if Some(e.holes) != e.code.map(|c| c.rewind_stop()) => image.len(),
            // EIA's blank in the data shows only when the next character comes.
            K::BlankInData => next_hole(image, e.frame as usize),
            _ => e.frame as usize,
        },
    };
    n.min(image.len())
}

/// The frame count up to and including the first frame with holes at or after frame `from`
/// (0-based index `from`).
fn next_hole(image: &[u8], from: usize) -> usize {
    image
        .iter()
        .skip(from)
        .position(|&b| b != 0)
        .map_or(image.len(), |i| from + i + 1)
}

/// Machine time until the read in progress stops, if one is.
pub(super) fn remaining_ns(c: &Console) -> Option<u64> {
    let r = c.tape_read.as_ref()?;
    let end = r.start_ns.saturating_add(r.ns_for(r.stop));
    Some(end.saturating_sub(c.status.machine_ns))
}

/// Moves the tape to where machine time has taken it; at the stop frame, stores the result
/// or raises the alarm.
pub(super) fn advance(c: &mut Console) {
    let now = c.status.machine_ns;
    let Some(r) = &mut c.tape_read else { return };
    let due = r.due(now);
    r.feed_to(due);
    if r.fed < r.stop {
        return;
    }
    if let Some(r) = c.tape_read.take() {
        complete(c, r);
    }
}

/// The tape has stopped: the whole result is stored, or the alarm says why nothing was.
fn complete(c: &mut Console, mut r: TapeRead) {
    let what = r.target.name();
    let file = r.file.clone();
    let tape = match std::mem::replace(&mut r.outcome, Ok(empty_tape())) {
        Ok(t) => t,
        Err(e) => {
            let unchanged = match r.target {
                ReadTarget::Program => "program memory unchanged",
                ReadTarget::Tools => "tool file unchanged",
            };
            c.shell.front.message = format!("{what} stopped, {unchanged}: {e}");
            c.tape_alarm = Some(e.to_string());
            r.failed = Some(e);
            c.tape_stopped = Some(r);
            return;
        }
    };
    let how = match tape.code {
        Some(code) => format!("{} tape, {} frames", code.name(), r.fed),
        None => "text file".to_string(),
    };
    match r.target {
        ReadTarget::Program => store_program(c, &file, &tape.text, &how),
        ReadTarget::Tools => store_tools(c, &file, &tape.text, &how),
    }
}

fn empty_tape() -> Tape {
    Tape {
        code: None,
        label: String::new(),
        text: String::new(),
        blocks: 0,
        frames: 0,
    }
}

/// PROGRAM READ's end: the text becomes a program in program memory (named after the file)
/// and the current one.
fn store_program(c: &mut Console, file: &str, text: &str, how: &str) {
    if c.cfg.settings.dialect == crate::settings::Dialect::Fanuc {
        let programs = crate::gcode::flow::dnc_programs(text);
        if !programs.is_empty() {
            c.shell.front.message = match c.mem.program_read_dnc(file, &programs) {
                Ok(names) => {
                    c.search = None;
                    format!(
                        "read {file} ({how}): {} programs: {}",
                        names.len(),
                        names.join(" ")
                    )
                }
                Err(e) => format!("PROGRAM READ refused: {e}"),
            };
            return;
        }
    }
    match c.mem.program_read_file(file, text) {
        Ok(r) => {
            let n = text.lines().count();
            c.search = None;
            let named = if r.changes.is_empty() {
                String::new()
            } else {
                format!(" (name: {})", r.changes.join(", "))
            };
            let again = if r.replaced {
                ", replacing the old one"
            } else {
                ""
            };
            c.shell.front.message = format!(
                "read {file} ({how}): program {}{named}, {n} lines{again}",
                r.name
            );
        }
        Err(e) => c.shell.front.message = format!("PROGRAM READ refused: {e}"),
    }
}

/// TOOL DATA READ's end: only the tape records of tools assigned to T codes are stored.
fn store_tools(c: &mut Console, file: &str, text: &str, how: &str) {
    match c.mem.tool_read(text, file) {
        Ok(r) => {
            c.shell.front.message = format!(
                "read {file} ({how}): {} T codes loaded, {} skipped",
                r.loaded.len(),
                r.skipped
            );
            let mut lines = Vec::new();
            if !r.missing.is_empty() {
                let m: Vec<String> = r.missing.iter().map(|t| format!("{t:05}")).collect();
                lines.push(format!("not on tape: {}", m.join(" ")));
            }
            c.read_report = lines;
            c.tool_focus = r.loaded.first().copied().unwrap_or(1);
        }
        Err(e) => {
            c.shell.front.message = format!("TOOL DATA READ refused, tool file unchanged: {e}")
        }
    }
}

/// One operator action under the tape rules ([`gate`]): a turned selector or RESET also takes
/// a stopped read off the display; a note that the read was abandoned follows the event's
/// own message.
pub(super) fn apply(c: &mut Console, ev: PanelEvent) {
    let note = match gate(c, &ev) {
        Gate::Done => return,
        Gate::Pass(note) => note,
    };
    let turned = match &ev {
        PanelEvent::Op(m) => *m != c.shell.front.op,
        PanelEvent::Data(d) => *d != c.data,
        PanelEvent::Reset => true,
        _ => false,
    };
    if turned {
        c.tape_stopped = None;
    }
    c.apply_event(ev);
    if let Some(n) = note {
        c.shell.front.message = if c.shell.front.message.is_empty() {
            n
        } else {
            format!("{}; {n}", c.shell.front.message)
        };
    }
}

/// What an event does while the tape moves.
pub(super) enum Gate {
    /// The event acts as usual; the note (the read was abandoned) goes after its message.
    Pass(Option<String>),
    /// The event has been dealt with here (refused, or STOP abandoned the read).
    Done,
}

/// The console's rules while the tape moves: STOP, RESET and E-STOP abandon the read (RESET
/// and E-STOP then act as always), turning a selector abandons it, the feed override, the
/// handwheel scale and the waits act, and every other event is refused with the reason.
pub(super) fn gate(c: &mut Console, ev: &PanelEvent) -> Gate {
    let Some(r) = &c.tape_read else {
        return Gate::Pass(None);
    };
    let abandoned = |by: &str, r: &TapeRead| {
        format!(
            "{} of {} abandoned by {by} at {}: nothing stored",
            r.target.name(),
            r.file,
            r.at()
        )
    };
    match ev {
        PanelEvent::Stop => {
            c.shell.front.message = abandoned("STOP", r);
            c.tape_read = None;
            Gate::Done
        }
        PanelEvent::Reset | PanelEvent::EStop => {
            let by = if matches!(ev, PanelEvent::Reset) {
                "RESET"
            } else {
                "E-STOP"
            };
            let note = abandoned(by, r);
            c.tape_read = None;
            Gate::Pass(Some(note))
        }
        PanelEvent::Op(m) if *m != c.shell.front.op => {
            let note = abandoned(&format!("turning to {}", m.name()), r);
            c.tape_read = None;
            Gate::Pass(Some(note))
        }
        PanelEvent::Data(d) if *d != c.data => {
            let note = abandoned(&format!("turning to {}", d.name()), r);
            c.tape_read = None;
            Gate::Pass(Some(note))
        }
        PanelEvent::Op(_)
        | PanelEvent::Data(_)
        | PanelEvent::Override(_)
        | PanelEvent::RapidOverride(_)
        | PanelEvent::SpindleOverride(_)
        | PanelEvent::DryRun(_)
        | PanelEvent::MachineLock(_)
        | PanelEvent::ZNeglect(_)
        | PanelEvent::WheelScale(_)
        | PanelEvent::BlockDelete(_)
        | PanelEvent::OptionalStop(_)
        | PanelEvent::Input { .. }
        | PanelEvent::Press(_)
        | PanelEvent::Wait
        | PanelEvent::WaitBlock(_)
        | PanelEvent::WaitMs(_)
        | PanelEvent::Show => Gate::Pass(None),
        other => {
            c.shell.front.message = refusal(&script_line(other), r);
            Gate::Done
        }
    }
}

/// `WHAT refused: the tape reader is reading FILE (frame N of M); STOP or RESET abandons
/// the read`.
fn refusal(what: &str, r: &TapeRead) -> String {
    format!(
        "{what} refused: the tape reader is reading {} ({}); STOP or RESET abandons the read",
        r.file,
        r.at()
    )
}

/// A key that is not a panel event (the tape reader key, the punch key) while the tape moves:
/// refused with the reason. Returns whether it was.
pub(super) fn refuse_key(c: &mut Console, what: &str) -> bool {
    match &c.tape_read {
        Some(r) => {
            c.shell.front.message = refusal(what, r);
            true
        }
        None => false,
    }
}

/// The data page of PROGRAM READ and TOOL DATA READ while a read is shown: a counters line,
/// then the last frames as rows of holes (the read head on the last, marked `>`) beside the
/// text decoded so far. `None` when no read is shown.
pub(super) fn page_body(c: &Console, n: usize, cols: usize) -> Option<Vec<String>> {
    let r = shown(c)?;
    let mut body = Vec::with_capacity(n);
    let Some(rd) = &r.reader else {
        body.push(format!(
            "text file: character {} of {}",
            r.fed,
            r.image.len()
        ));
        let text = String::from_utf8_lossy(&r.image[..r.fed]);
        let lines: Vec<&str> = text.split('\n').collect();
        let k = n.saturating_sub(1);
        let from = lines.len().saturating_sub(k);
        body.extend(lines[from..].iter().map(|l| format!(" {l}")));
        return Some(body);
    };
    let code = rd.code().map_or("code ?", |c| c.name());
    let block = match rd.block() {
        0 => "label".to_string(),
        b => format!("block {b}"),
    };
    body.push(format!("{code} frame {}/{} {block}", r.fed, r.image.len()));
    let k = n.saturating_sub(1);
    if k == 0 {
        return Some(body);
    }
    let frames = rd.frames();
    let from = frames.len().saturating_sub(k);
    let mut rows: Vec<String> = frames[from..]
        .iter()
        .map(|&b| format!(" {} {:<3}", Frame(b).row(), meaning(rd.code(), b)))
        .collect();
    if let Some(last) = rows.last_mut() {
        last.replace_range(0..1, if r.failed.is_some() { "!" } else { ">" });
    }
    while rows.len() < k {
        rows.insert(0, String::new());
    }
    // The text decoded so far, its last lines beside the strip (the block being read last).
    let text = rd.text();
    let lines: Vec<&str> = text.split('\n').collect();
    let tfrom = lines.len().saturating_sub(k);
    let mut tl: Vec<&str> = lines[tfrom..].to_vec();
    while tl.len() < k {
        tl.insert(0, "");
    }
    let strip_w: usize = 1 + 9 + 1 + 3;
    for (row, t) in rows.iter().zip(tl) {
        let pad = strip_w.saturating_sub(row.chars().count());
        let line = format!("{row}{}│{t}", " ".repeat(pad));
        body.push(line.chars().take(cols).collect());
    }
    Some(body)
}

/// A frame's meaning in three characters (`?` before the code is recognized).
fn meaning(code: Option<Code>, b: u8) -> String {
    let Some(code) = code else {
        return if b == 0 { String::new() } else { "?".into() };
    };
    match code.meaning(Frame(b)) {
        Meaning::Char('\t') => "TAB".into(),
        Meaning::Char(' ') => "SP".into(),
        Meaning::Char(ch) => ch.to_string(),
        Meaning::Blank => String::new(),
        Meaning::RubOut => "DEL".into(),
        Meaning::PassedOver(s) => s.into(),
        Meaning::EndOfBlock => "EOB".into(),
        Meaning::RewindStop => "RS".into(),
        Meaning::UpperCase => "UC".into(),
        Meaning::LowerCase => "LC".into(),
        Meaning::ParityError | Meaning::NotInCode => "ERR".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tape::PunchOptions;

    #[test]
    fn the_stop_frame_is_where_the_reader_stops() {
        let image = tape::punch(
            "N1 G00\n",
            &PunchOptions {
                code: Code::Iso,
                leader: 5,
                label: None,
            },
        )
        .unwrap();
        let ok = tape::read_image(&image, ReadOptions::default());
        let t = ok.as_ref().unwrap();
        assert_eq!(stop_frame(&image, &ok), t.frames as usize);
        assert!(t.frames < image.len() as u64, "the trailer is not read");
        let mut bad = image.clone();
        bad[8] ^= 0x02;
        let e = tape::read_image(&bad, ReadOptions::default());
        assert_eq!(stop_frame(&bad, &e), 9);
        let empty = tape::read_image(&[], ReadOptions::default());
        assert_eq!(stop_frame(&[], &empty), 0);
    }
}
