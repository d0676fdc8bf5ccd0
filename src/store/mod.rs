//! The stores the controller remembers across restarts: program memory, the MDI buffer, the
//! tool file and the T-code table (patent Table A; docs/stores.md), and, in a lathe's directory,
//! each channel's program and tools and the part counter (`lathe`). Every accepted change is
//! journaled and fsynced before it is acknowledged, and replayed at start (see `docs/stores.md`).

mod frame;
pub mod fsutil;
pub mod history;
mod journal;
pub mod lathe;
mod lathe_old;
mod names;
pub mod params;
mod record;
mod recover;
mod snapshot;
pub mod stamps;
mod state;
pub mod toolfile;

pub use fsutil::write_atomic;
pub use names::{program_name, program_name_from_file, FileProgramName};
pub use state::TABLEB;

use crate::tooldata::{parse_tape, parse_tcodes, Magazine, TapeError};
use fsutil::DirLock;
use journal::Journal;
use novanc_editor::{Buffer, EditError, Outcome};
use record::{EditTarget, Record};
use recover::Loaded;
use state::{Base, Refusal, State};
use std::fmt;
use std::path::{Path, PathBuf};

/// The snapshot file name in the state directory.
const SNAPSHOT: &str = "state.snap";
/// Journal records after which the journal is compacted into a new snapshot.
const JOURNAL_RECORDS: usize = 4096;
/// Journal bytes after which the journal is compacted into a new snapshot.
const JOURNAL_BYTES: u64 = 4 << 20;

/// Which buffer an edit applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The current part program in program memory (PROGRAM REVISION).
    Program,
    /// The MDI buffer (MDI).
    Mdi,
    /// The tool file, one T code per line (TOOL DATA REVISION).
    ToolFile,
}

/// A store failure (I/O, or a refused edit), with the operator's message.
#[derive(Clone, Debug, PartialEq)]
pub struct StoreError {
    /// What happened.
    pub message: String,
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for StoreError {}

/// A StoreError from a message.
fn serr(message: impl Into<String>) -> StoreError {
    StoreError {
        message: message.into(),
    }
}

/// Why an edit was not accepted. In every case the buffer and its pointer are unchanged.
#[derive(Clone, Debug, PartialEq)]
pub enum EditFailure {
    /// The command line failed, or the tool-file validator refused its result.
    Command(EditError),
    /// The edit could not be saved (disk full, I/O error), so it was not accepted.
    Store(StoreError),
}

impl fmt::Display for EditFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EditFailure::Command(e) => e.fmt(f),
            EditFailure::Store(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for EditFailure {}

/// What TOOL DATA READ did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ToolReadReport {
    /// The T codes whose data was loaded from the tape, in T-code order.
    pub loaded: Vec<u32>,
    /// Tape records skipped because no T code holds their tool.
    pub skipped: usize,
    /// (T code, tool) assigned but not on the tape; their data is unchanged.
    pub missing: Vec<(u32, u32)>,
}

impl ToolReadReport {
    /// One line for the display, e.g. `20 tools loaded, 22 skipped (not in the magazine)`.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "{} tools loaded, {} skipped (not in the magazine)",
            self.loaded.len(),
            self.skipped
        );
        if !self.missing.is_empty() {
            let list: Vec<String> = self
                .missing
                .iter()
                .map(|(t, n)| format!("T{t:02} {n:05}"))
                .collect();
            s.push_str(&format!("; not on the tape: {}", list.join(", ")));
        }
        s
    }
}

/// What PROGRAM READ of a tape file did (`Stores::program_read_file`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramReadReport {
    /// The program name given to the tape (`program_name_from_file`).
    pub name: String,
    /// The characters of the file name changed to make it, e.g. `ü → U` (empty if none).
    pub changes: Vec<String>,
    /// Whether a program of that name was replaced (the same tape read again).
    pub replaced: bool,
}

/// Program memory, MDI buffer, tool file and T-code table, persisted in a state directory.
pub struct Stores {
    dir: PathBuf,
    /// Whose stores these are (the centre's, with its magazine capacity, or a lathe's).
    base: Base,
    state: State,
    gen: u64,
    /// None after a failed compaction: a new journal is created before the next append.
    journal: Option<Journal>,
    /// Memory holds more than the files say in a way the journal cannot record (a compaction
    /// at open that failed, or a journal that could not be cut back): the next change writes a
    /// whole snapshot instead of a journal record.
    unsaved: bool,
    /// Damaged files not yet kept aside; no compaction overwrites them before they are.
    aside: fsutil::Aside,
    /// Why nothing may be written at all: the directory is read-only and could not be locked.
    read_only: Option<String>,
    journal_limit: usize,
    /// The machine's G-code dialect, recorded with each program read or made (None: none
    /// recorded, as before programs kept their dialect; `set_dialect`).
    dialect: Option<crate::settings::Dialect>,
    /// When each program last changed (`program-times`, not operator data).
    stamps: stamps::Stamps,
    _lock: DirLock,
}

/// Reads the snapshot and the journal of `dir` and builds the state (docs/stores.md).
pub(crate) fn load(dir: &Path, base: &Base) -> Result<Loaded, StoreError> {
    let io = |what: &Path, e: std::io::Error| serr(format!("cannot read {}: {e}", what.display()));
    let snap_path = dir.join(SNAPSHOT);
    let snap = match std::fs::read(&snap_path) {
        Ok(b) => Some(b),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(io(&snap_path, e)),
    };
    let jour = journal::read(dir).map_err(|e| io(&dir.join(journal::JOURNAL), e))?;
    Ok(recover::recover(
        snap.as_deref(),
        jour,
        base,
        (SNAPSHOT, journal::JOURNAL),
    ))
}

/// One program of program memory, as the PROG page lists it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProgramInfo {
    /// Its name.
    pub name: String,
    /// Its size in characters.
    pub chars: usize,
    /// Its lines.
    pub lines: usize,
    /// Its first line (at most 80 characters).
    pub first_line: String,
    /// When it last changed, in seconds since 1970, if known (`stamps`).
    pub changed_s: Option<u64>,
}

/// What the command line reads of a console's memory (`novanc translate --state`, `novanc run
/// --state`): read without locking or writing the directory, so a console may have it open.
#[derive(Clone, Debug)]
pub struct MemoryView {
    /// The current program's name.
    pub current: String,
    /// Every program by name.
    pub programs: std::collections::BTreeMap<String, String>,
    /// The T-code table and the tool file.
    pub magazine: Magazine,
    /// The work offsets G54 to G59.
    pub offsets: crate::gcode::WorkOffsets,
    /// The G-code interpreter's persistent parameters that are not zero (number, value).
    pub params: Vec<(usize, f64)>,
    /// The G-code dialect each program was stored in, where one was recorded.
    pub dialects: std::collections::BTreeMap<String, crate::settings::Dialect>,
    /// What the reading found (a damaged file read around, a journal tail skipped).
    pub warnings: Vec<String>,
}

impl MemoryView {
    /// Reads the memory kept in `dir` (which must exist) as a console would open it, without
    /// changing a byte of it.
    pub fn read(dir: &Path, capacity: u32) -> Result<MemoryView, StoreError> {
        if !dir.is_dir() {
            return Err(serr(format!(
                "{} is not a state directory (a console's memory)",
                dir.display()
            )));
        }
        let l = load(dir, &Base::Centre(capacity))?;
        Ok(MemoryView {
            current: l.state.current.clone(),
            programs: l
                .state
                .programs
                .iter()
                .map(|(n, b)| (n.clone(), b.text()))
                .collect(),
            magazine: l.state.magazine(),
            offsets: params::offsets_of(&l.state.params),
            params: params::params_of(&l.state.params),
            dialects: l.state.dialects.clone(),
            warnings: l.notes.into_iter().map(|n| n.text).collect(),
        })
    }
}

impl Stores {
    /// The state directory: `NOVANC_STATE`, else `$XDG_STATE_HOME/novanc`, else
    /// `~/.local/state/novanc` (`./novanc-state` if there is no home directory).
    pub fn default_dir() -> PathBuf {
        let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty());
        if let Some(d) = var("NOVANC_STATE") {
            return PathBuf::from(d);
        }
        if let Some(d) = var("XDG_STATE_HOME").map(PathBuf::from) {
            if d.is_absolute() {
                return d.join("novanc");
            }
        }
        match var("HOME") {
            Some(h) => PathBuf::from(h).join(".local/state/novanc"),
            None => PathBuf::from("novanc-state"),
        }
    }

    /// Opens (or creates, on the embedded defaults) the stores in `dir`, replaying the journal.
    /// Returns warnings to show the operator (for example a corrupt journal tail skipped).
    /// `capacity` is the magazine's number of pockets (the setting; 24 by default).
    pub fn open(dir: &Path, capacity: u32) -> Result<(Stores, Vec<String>), StoreError> {
        if capacity == 0 || capacity > 999 {
            return Err(serr(format!(
                "magazine capacity {capacity} must be 1 to 999 pockets"
            )));
        }
        Stores::open_base(dir, Base::Centre(capacity))
    }

    /// Whether `dir` holds no store yet (neither a snapshot nor a journal, nor anything at
    /// those names).
    pub fn is_new(dir: &Path) -> bool {
        [SNAPSHOT, journal::JOURNAL].iter().all(|f| {
            std::fs::symlink_metadata(dir.join(f))
                .is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound)
        })
    }

    /// Opens the stores of `base` (the centre's or a lathe's) in `dir`, as `open`.
    fn open_base(dir: &Path, base: Base) -> Result<(Stores, Vec<String>), StoreError> {
        fsutil::make_dir(dir).map_err(serr)?;
        let lock = fsutil::lock_dir(dir).map_err(serr)?;
        let l = load(dir, &base)?;
        let mut s = Stores {
            dir: dir.to_path_buf(),
            base,
            state: l.state,
            gen: l.gen,
            journal: None,
            unsaved: false,
            aside: fsutil::Aside::default(),
            read_only: lock.read_only().map(str::to_string),
            journal_limit: JOURNAL_RECORDS,
            dialect: None,
            stamps: stamps::Stamps::open(dir),
            _lock: lock,
        };
        if let Some(why) = &s.read_only {
            // Not even locked: nothing is kept aside, compacted or written (docs/stores.md).
            s.unsaved = true;
            let mut warnings: Vec<String> = l.notes.into_iter().map(|n| n.text).collect();
            warnings.push(format!(
                "the state directory {} is read-only ({why}): the stores are shown as they were read, and every change is refused; make it writable and start novanc again",
                dir.display()
            ));
            return Ok((s, warnings));
        }
        // Keep the damaged files aside first, then word the notes with their new names.
        let mut kept: Vec<(&str, Result<String, String>)> = Vec::new();
        for f in l.notes.iter().filter_map(|n| n.file) {
            if kept.iter().all(|(k, _)| *k != f) {
                kept.push((f, s.aside.keep(dir, f)));
            }
        }
        let mut warnings: Vec<String> = l
            .notes
            .into_iter()
            .map(|n| match kept.iter().find(|(k, _)| Some(*k) == n.file) {
                Some((_, Ok(name))) => format!("{}. It is kept as {name}", n.text),
                Some((f, Err(e))) => format!(
                    "{}. It could not be kept aside ({e}); novanc will not overwrite {f} until it can",
                    n.text
                ),
                None => n.text,
            })
            .collect();
        // A journal that cannot be appended to (a symlink, a file made read-only) is replaced
        // by the compaction, as one with records to replay is.
        let opened = if l.compact {
            s.compact()
        } else {
            match Journal::open_append(&dir.join(journal::JOURNAL)) {
                Ok(j) => {
                    s.journal = Some(j);
                    Ok(())
                }
                Err(_) => s.compact(),
            }
        };
        if let Err(e) = opened {
            // A full disk (or a read-only one): the state read is all there, and stays
            // readable; changes are refused until it can be saved (docs/stores.md).
            s.unsaved = true;
            warnings.push(if fsutil::is_read_only(&e) {
                format!(
                    "cannot save to {} ({e}): it is read-only; the stores are open as they were read, nothing is lost, and every change is refused until it can be written",
                    dir.display()
                )
            } else {
                format!(
                    "cannot save to {} ({e}): the stores are open as they were read, nothing is lost, and changes are refused until there is room to save them",
                    dir.display()
                )
            });
        }
        Ok((s, warnings))
    }

    /// Writes the whole state as a new snapshot and starts an empty journal. Damaged files
    /// are kept aside first (a compaction never overwrites one that is not). Once the
    /// snapshot is written the state is saved, even if the new journal cannot be created
    /// (the next change creates it).
    fn compact(&mut self) -> std::io::Result<()> {
        if let Some(why) = &self.read_only {
            return Err(std::io::Error::new(
                std::io::ErrorKind::PermissionDenied,
                format!("the state directory is read-only: {why}"),
            ));
        }
        self.aside.before_overwrite(&self.dir, None)?;
        let gen = self.gen + 1;
        write_atomic(
            &self.dir.join(SNAPSHOT),
            &snapshot::encode(&self.state, gen),
        )?;
        self.gen = gen;
        self.unsaved = false;
        self.journal = Journal::create(&self.dir, gen).ok();
        Ok(())
    }

    /// Sets after how many journal records the journal is compacted (default 4096).
    pub fn set_journal_limit(&mut self, records: usize) {
        self.journal_limit = records.max(1);
    }

    /// Notes the time of a change that landed in a program's text or name.
    fn stamp(&mut self, rec: &Record) {
        let now = stamps::now_s();
        match rec {
            Record::Edit {
                target: EditTarget::Program(name),
                ..
            } => self.stamps.touch(name, now),
            Record::NewProgram { name, .. } | Record::ProgramRead { name, .. } => {
                self.stamps.touch(name, now)
            }
            Record::Copy { to, .. } => self.stamps.touch(to, now),
            Record::Rename { from, to } => self.stamps.rename(from, to),
            Record::Delete(name) => self.stamps.remove(name),
            _ => {}
        }
    }

    /// Applies a change, journals it (fsynced) if it changed anything (or, for a change as
    /// large as a journal may grow, writes the whole state), and only then returns.
    fn commit(&mut self, rec: Record, y_max_lines: Option<usize>) -> Result<Outcome, EditFailure> {
        let (out, changed) = self.state.apply(&rec, y_max_lines).map_err(|e| match e {
            Refusal::Edit(e) => EditFailure::Command(e),
            Refusal::Other(m) => EditFailure::Store(serr(m)),
        })?;
        if !changed {
            return Ok(out);
        }
        let saved = if self.unsaved || rec_is_large(&rec) {
            // The files hold less than memory did before this change, or the change is as
            // large as a journal may grow (a CAM program read from a file): write it all,
            // once, rather than journal it and then compact at once.
            self.compact()
        } else {
            match self.journal.as_mut() {
                Some(j) => j.append(&rec),
                None => Journal::create(&self.dir, self.gen)
                    .and_then(|mut j| j.append(&rec).map(|_| j))
                    .map(|j| self.journal = Some(j)),
            }
        };
        if let Err(e) = saved {
            if self.journal.as_ref().is_some_and(|j| j.broken) {
                self.journal = None;
                self.unsaved = true;
            }
            // Memory is ahead of the disk: go back to what the disk holds.
            let back = load(&self.dir, &self.base).map(|l| self.state = l.state);
            let note = if back.is_ok() {
                "nothing was changed"
            } else {
                "restart novanc"
            };
            let e = match fsutil::is_read_only(&e) && self.read_only.is_none() {
                true => format!("{} is read-only: {e}", self.dir.display()),
                false => e.to_string(),
            };
            return Err(EditFailure::Store(serr(format!("not saved ({e}); {note}"))));
        }
        self.stamp(&rec);
        if let Some(j) = &self.journal {
            if j.records >= self.journal_limit || j.len >= JOURNAL_BYTES {
                // A failed compaction loses nothing: the journal still holds every change.
                let _ = self.compact();
            }
        }
        Ok(out)
    }

    /// The state directory in use.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The magazine capacity (number of T codes).
    pub fn capacity(&self) -> u32 {
        self.base.capacity()
    }

    /// A lathe's stores (None: these are the centre's).
    pub fn lathe(&self) -> Option<&lathe::LatheState> {
        self.state.lathe.as_ref()
    }

    /// Applies one record and journals it, as every change (`commit`); for a lathe's stores.
    fn commit_record(&mut self, rec: Record) -> Result<(), StoreError> {
        self.commit(rec, None).map(|_| ()).map_err(to_store)
    }

    /// The names of the programs in program memory, in order.
    pub fn program_names(&self) -> Vec<String> {
        self.state.programs.keys().cloned().collect()
    }

    /// The machine's G-code dialect: each program read or made from now on is stored as
    /// written in it (docs/gcode.md "Fanuc dialect"). Without it, none is recorded.
    pub fn set_dialect(&mut self, d: crate::settings::Dialect) {
        self.dialect = Some(d);
    }

    /// The G-code dialect program `name` was stored in, if one was recorded.
    pub fn program_dialect(&self, name: &str) -> Option<crate::settings::Dialect> {
        let n = program_name(name).ok()?;
        self.state.dialects.get(&n).copied()
    }

    /// The name of the current program (the one PROGRAM REVISION and AUTO use).
    pub fn current_program(&self) -> &str {
        &self.state.current
    }

    /// The text of a program in program memory.
    pub fn program_text(&self, name: &str) -> Option<String> {
        let n = program_name(name).ok()?;
        self.state.programs.get(&n).map(Buffer::text)
    }

    /// SEARCH: makes another program current (names are case-insensitive).
    pub fn select_program(&mut self, name: &str) -> Result<(), StoreError> {
        let n = program_name(name).map_err(serr)?;
        self.commit(Record::Select(n), None)
            .map(|_| ())
            .map_err(to_store)
    }

    /// Creates an empty program and makes it current.
    pub fn new_program(&mut self, name: &str) -> Result<(), StoreError> {
        let n = program_name(name).map_err(serr)?;
        self.commit(
            Record::NewProgram {
                name: n,
                dialect: self.dialect,
            },
            None,
        )
        .map(|_| ())
        .map_err(to_store)
    }

    /// PROGRAM READ: adds `text` (a tape file; CR and CR LF become end of block) as program
    /// `name`, replacing a program of that name, and makes it current.
    pub fn program_read(&mut self, name: &str, text: &str) -> Result<(), StoreError> {
        let n = program_name(name).map_err(serr)?;
        self.commit(
            Record::ProgramRead {
                name: n,
                text: text.to_string(),
                dialect: self.dialect,
            },
            None,
        )
        .map(|_| ())
        .map_err(to_store)
    }

    /// PROGRAM READ of the tape file `file` (its name as given; only the file name part is
    /// used): the program is named by `program_name_from_file`, added or replaced, and made
    /// current. A program of the same name is replaced only when the file's name gives it
    /// without change beyond upper case (the same tape read again): when characters had to be
    /// changed (`prüf.ap` gives PRUF, as `pruf.ap` does) and a PRUF exists, the read is refused,
    /// saying so, and nothing changes.
    pub fn program_read_file(
        &mut self,
        file: &str,
        text: &str,
    ) -> Result<ProgramReadReport, StoreError> {
        let n = program_name_from_file(file).map_err(serr)?;
        let replaced = self.state.programs.contains_key(&n.name);
        if replaced && !n.changes.is_empty() {
            return Err(serr(format!(
                "tape {file} is named {} ({}), and program memory already holds a program {}: it is not replaced, since the names match only because the file name was changed; rename the file, or delete {} first",
                n.name,
                n.changes.join(", "),
                n.name,
                n.name
            )));
        }
        self.program_read(&n.name, text)?;
        Ok(ProgramReadReport {
            name: n.name,
            changes: n.changes,
            replaced,
        })
    }

    /// The buffer of a target, for the display.
    pub fn buffer(&self, target: Target) -> &Buffer {
        match target {
            Target::Program => self
                .state
                .programs
                .get(&self.state.current)
                .unwrap_or(&self.state.mdi),
            Target::Mdi => &self.state.mdi,
            Target::ToolFile => &self.state.tool_buf,
        }
    }

    /// Runs one editor command line on a target, atomically. The tool file is checked by its
    /// validator. When this returns Ok the edit is on disk (journaled and fsynced).
    pub fn edit(
        &mut self,
        target: Target,
        cmdline: &str,
        y_max_lines: Option<usize>,
    ) -> Result<Outcome, EditFailure> {
        let target = match target {
            Target::Program => EditTarget::Program(self.state.current.clone()),
            Target::Mdi => EditTarget::Mdi,
            Target::ToolFile => EditTarget::ToolFile,
        };
        self.commit(
            Record::Edit {
                target,
                line: cmdline.to_string(),
            },
            y_max_lines,
        )
    }

    /// TOOL DATA READ: loads the records of `tape_text` whose tools are assigned to a T code,
    /// each into its T code's slot. A bad tape (any bad record) changes nothing.
    pub fn tool_read(
        &mut self,
        tape_text: &str,
        file_name: &str,
    ) -> Result<ToolReadReport, TapeError> {
        let tape = parse_tape(tape_text, file_name)?;
        let mut m = self.state.magazine();
        let mut report = ToolReadReport::default();
        for rec in &tape {
            match m.tcodes.tcode_of(rec.number) {
                Some(t) => {
                    m.tools.set(t, Some(rec.clone()));
                    report.loaded.push(t);
                }
                None => report.skipped += 1,
            }
        }
        report.loaded.sort_unstable();
        report.missing = m
            .tcodes
            .iter()
            .filter(|(t, _)| !report.loaded.contains(t))
            .collect();
        let text = toolfile::tool_text_keeping(&self.state.tool_buf.text(), &m);
        self.commit(Record::ToolFile(text), None)
            .map_err(|e| TapeError {
                file: file_name.to_string(),
                line: 0,
                message: format!("the tool file was not changed: {e}"),
            })?;
        Ok(report)
    }

    /// T-CODE SETTING by T code: puts `tool` in pocket `t`, or empties it (None). The pocket's
    /// tool data is cleared when its tool changes (read the tape again, or enter it in TOOL
    /// DATA REVISION). Two T codes never hold the same tool.
    pub fn set_tcode(&mut self, t: u32, tool: Option<u32>) -> Result<(), String> {
        self.commit(Record::TCode { t, tool }, None)
            .map(|_| ())
            .map_err(|e| e.to_string())
    }

    /// T-CODE SETTING by tool number: puts `tool` in pocket `t`, or (None) takes it out of
    /// whichever pocket holds it.
    pub fn assign_tool(&mut self, tool: u32, t: Option<u32>) -> Result<(), String> {
        match t {
            Some(t) => self.set_tcode(t, Some(tool)),
            None => match self.state.tcodes.tcode_of(tool) {
                Some(t) => self.set_tcode(t, None),
                None => Err(format!("tool {tool:05} is in no T code")),
            },
        }
    }

    /// T-CODE SETTING from a T-code table file (`Tnn TOOLNO` lines): replaces the whole table.
    /// Pockets whose tool changes lose their tool data. A bad file changes nothing.
    pub fn tcode_read(&mut self, text: &str, file_name: &str) -> Result<(), TapeError> {
        parse_tcodes(text, file_name, self.capacity())?;
        self.commit(Record::TCodes(text.to_string()), None)
            .map(|_| ())
            .map_err(|e| TapeError {
                file: file_name.to_string(),
                line: 0,
                message: format!("the T-code table was not changed: {e}"),
            })
    }

    /// Deletes a program from program memory (not the last one). If it was current, the
    /// first remaining program (by name) becomes current.
    pub fn delete_program(&mut self, name: &str) -> Result<(), StoreError> {
        let n = program_name(name).map_err(serr)?;
        self.commit(Record::Delete(n), None)
            .map(|_| ())
            .map_err(to_store)
    }

    /// Copies program `from` as `to` and makes the copy current (journaled).
    pub fn copy_program(&mut self, from: &str, to: &str) -> Result<(), StoreError> {
        self.commit(
            Record::Copy {
                from: from.to_string(),
                to: to.to_string(),
            },
            None,
        )
        .map(|_| ())
        .map_err(to_store)
    }

    /// Renames program `from` to `to` (journaled); it stays current if it was.
    pub fn rename_program(&mut self, from: &str, to: &str) -> Result<(), StoreError> {
        self.commit(
            Record::Rename {
                from: from.to_string(),
                to: to.to_string(),
            },
            None,
        )
        .map(|_| ())
        .map_err(to_store)
    }

    /// Each program's name, size in characters, lines, and its first line (for the language).
    pub fn program_list(&self) -> Vec<ProgramInfo> {
        self.state
            .programs
            .iter()
            .map(|(name, b)| ProgramInfo {
                name: name.clone(),
                chars: b.len(),
                lines: b.line_count(),
                first_line: b
                    .slice(0, b.len().min(80))
                    .lines()
                    .next()
                    .unwrap_or("")
                    .to_string(),
                changed_s: self.stamps.get(name),
            })
            .collect()
    }

    /// Empties the MDI buffer (for example after its blocks ran).
    pub fn clear_mdi(&mut self) -> Result<(), StoreError> {
        self.commit(Record::ClearMdi, None)
            .map(|_| ())
            .map_err(to_store)
    }

    /// T-CODE SETTING by tool number, as one change: moves `tool` into pocket `t` together with
    /// its tool data, out of the pocket that held it (if any). A tool that was in pocket `t`
    /// leaves the magazine (its data with it).
    pub fn move_tool(&mut self, tool: u32, t: u32) -> Result<(), String> {
        self.commit(Record::Move { tool, t }, None)
            .map(|_| ())
            .map_err(|e| e.to_string())
    }

    /// The magazine (T-code table and tool file) the translator gets.
    pub fn magazine(&self) -> Magazine {
        self.state.magazine()
    }
}

/// An edit failure as a StoreError (for the operations that are not editor command lines).
fn to_store(e: EditFailure) -> StoreError {
    match e {
        EditFailure::Store(e) => e,
        EditFailure::Command(e) => serr(e.to_string()),
    }
}

/// A change that alone fills the journal: a program read whole ([`JOURNAL_BYTES`] of text or
/// more). Writing it to the journal would be followed at once by a compaction.
fn rec_is_large(rec: &Record) -> bool {
    matches!(rec, Record::ProgramRead { text, .. } if text.len() as u64 >= JOURNAL_BYTES)
}
