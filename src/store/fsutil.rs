//! The one write path for every file novanc writes (docs/stores.md "How novanc writes a
//! file"): atomic replacement (a temporary file created with `O_CREAT|O_EXCL|O_NOFOLLOW`,
//! fsync, rename, fsync of the directory), the locked read-modify-write of an operator's file
//! (`novanc edit --write`, outputs named on the command line: through symlinks, keeping hard
//! links), appends that follow no symlink, the lock that keeps two consoles off one state
//! directory, and keeping damaged files aside.

use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Seek, Write};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::os::unix::io::AsRawFd;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The directory holding `path` (`.` for a bare file name).
fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The last component of `path`, or an error for a path that names no file (`/`, `..`).
fn name_of(path: &Path) -> io::Result<&OsStr> {
    path.file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))
}

/// Flushes a directory's entries (a rename or a new file) to disk.
pub fn fsync_dir(dir: &Path) -> io::Result<()> {
    File::open(dir)?.sync_all()
}

/// `.NAME.KIND-PID`: the name of a temporary file of process `pid` beside `name`.
fn temp_name(name: &OsStr, kind: &str, pid: u32) -> OsString {
    let mut t = OsString::from(".");
    t.push(name);
    t.push(format!(".{kind}-{pid}"));
    t
}

/// Whether process `pid` exists (on this machine).
fn alive(pid: u32) -> bool {
    let Ok(p) = libc::pid_t::try_from(pid) else {
        return false;
    };
    // SAFETY: kill with signal 0 only checks that the process exists; no memory is passed.
    let r = unsafe { libc::kill(p, 0) };
    r == 0 || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// The files `.NAME.KIND-PID` beside `name` in `dir` of other processes, as (path, pid).
fn temps(dir: &Path, name: &OsStr, kind: &str) -> Vec<(PathBuf, u32)> {
    let mut prefix = b".".to_vec();
    prefix.extend_from_slice(name.as_bytes());
    prefix.extend_from_slice(format!(".{kind}-").as_bytes());
    let Ok(entries) = fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<(PathBuf, u32)> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let n = e.file_name();
            let digits = n.as_bytes().strip_prefix(prefix.as_slice())?;
            let pid: u32 = std::str::from_utf8(digits).ok()?.parse().ok()?;
            (pid != std::process::id()).then(|| (dir.join(&n), pid))
        })
        .collect();
    v.sort();
    v
}

/// The temporary files `.NAME.KIND-PID` beside `name` in `dir` whose process is gone (killed
/// while writing).
fn dead_temps(dir: &Path, name: &OsStr, kind: &str) -> Vec<PathBuf> {
    temps(dir, name, kind)
        .into_iter()
        .filter(|(_, pid)| !alive(*pid))
        .map(|(p, _)| p)
        .collect()
}

/// Opens `path` with `opts`, never following a symlink at its last component (`O_NOFOLLOW`:
/// a link there fails with ELOOP, said as such) and never blocking on a special file.
fn open_nofollow(path: &Path, opts: &mut OpenOptions) -> io::Result<File> {
    match opts
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
        .open(path)
    {
        Err(e) if e.raw_os_error() == Some(libc::ELOOP) => Err(io::Error::new(
            e.kind(),
            format!(
                "{} is a symbolic link, which novanc does not follow here",
                path.display()
            ),
        )),
        r => r,
    }
}

/// Opens the file `path` for appending (creating it if `create`), following no symlink; a
/// special file is refused. The journal and the message history are appended this way.
pub fn open_append(path: &Path, create: bool) -> io::Result<File> {
    let f = open_nofollow(path, OpenOptions::new().append(true).create(create))?;
    if !f.metadata()?.is_file() {
        return Err(io::Error::other(format!(
            "{} is not a regular file",
            path.display()
        )));
    }
    Ok(f)
}

/// Creates the temporary file `.NAME.tmp-PID` beside `path`, exclusively (`O_CREAT|O_EXCL|
/// O_NOFOLLOW`): whatever was planted at that name (a symlink, a file) is removed, never
/// written through. Temporary files of earlier writers that were killed (their process is
/// gone) are removed first.
fn create_temp(path: &Path) -> io::Result<(File, PathBuf)> {
    let dir = parent_of(path);
    let name = name_of(path)?;
    for stale in dead_temps(&dir, name, "tmp") {
        let _ = fs::remove_file(stale);
    }
    let tmp = dir.join(temp_name(name, "tmp", std::process::id()));
    let mut last = None;
    for _ in 0..3 {
        match open_nofollow(&tmp, OpenOptions::new().write(true).create_new(true)) {
            Ok(f) => return Ok((f, tmp)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                // Only this process writes this name: what is there is left over or planted.
                fs::remove_file(&tmp)?;
                last = Some(e);
            }
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| io::Error::other("cannot create a temporary file")))
}

/// Writes `data` to a new temporary file beside `path` (`create_temp`), with the permissions
/// of the regular file at `path` if there is one, and fsyncs it. Returns its path.
fn write_temp(path: &Path, data: &[u8]) -> io::Result<PathBuf> {
    let (mut f, tmp) = create_temp(path)?;
    let result = (|| {
        if let Ok(meta) = fs::symlink_metadata(path) {
            if meta.is_file() {
                f.set_permissions(meta.permissions())?;
            }
        }
        f.write_all(data)?;
        f.sync_all()
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Replaces `path` with `data` atomically: a reader (or a crash) sees the old file or the new
/// one, never a mix. Writes a temporary file `.NAME.tmp-PID` beside it (`create_temp`: created
/// exclusively, following no symlink), fsyncs it, renames it over `path` and fsyncs the
/// directory. Keeps the old file's permissions. `path` itself is replaced: a symlink there is
/// replaced by the file, never followed (the stores want that; an operator's file goes through
/// `lock_file` instead).
pub fn write_atomic(path: &Path, data: &[u8]) -> io::Result<()> {
    let tmp = write_temp(path, data)?;
    let result = fs::rename(&tmp, path).and_then(|_| fsync_dir(&parent_of(path)));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// How an operator's file was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rewrite {
    /// Replaced by rename: a crash leaves the old text or the new one.
    Atomic,
    /// Rewritten in place because it has other hard links (docs/stores.md "novanc edit").
    InPlace,
}

/// Why writing an operator's file failed.
#[derive(Debug)]
pub struct RewriteError {
    /// The I/O error.
    pub error: io::Error,
    /// None: the file is unchanged. Some: the copy in place failed part way, so the file may
    /// be torn; the whole new text is in this file, and the next `lock_file` finishes the copy.
    pub torn: Option<PathBuf>,
}

impl std::fmt::Display for RewriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.torn {
            None => write!(f, "{}", self.error),
            Some(p) => write!(
                f,
                "{} while rewriting it in place; it may be cut short, and the whole new text is in {}",
                self.error,
                p.display()
            ),
        }
    }
}

/// `flock(op)` on a file we own, retried when a signal interrupts it.
fn flock(f: &File, op: libc::c_int) -> io::Result<()> {
    loop {
        // SAFETY: flock on a file descriptor we own; no memory is passed.
        if unsafe { libc::flock(f.as_raw_fd(), op) } == 0 {
            return Ok(());
        }
        let e = io::Error::last_os_error();
        if e.kind() != io::ErrorKind::Interrupted {
            return Err(e);
        }
    }
}

/// How long `lock_file` waits for another writer of the same file.
const LOCK_WAIT: Duration = Duration::from_secs(60);

/// An operator's file (`novanc edit`'s FILE, an output named on the command line) held under
/// an exclusive advisory lock (`flock`) from before it is read until after it is written, so
/// that two writers of one file take turns and neither's change is lost. Dropping it releases
/// the lock.
#[derive(Debug)]
pub struct LockedFile {
    file: File,
    /// The file the path names, symlinks resolved.
    target: PathBuf,
}

/// Locks the regular file `path` names (a symlink is followed). Waits (up to a minute) while
/// another process holds it; once locked, checks that the path still names the locked file
/// (another writer may have renamed a new one over it meanwhile) and starts again if not.
pub fn lock_file(path: &Path) -> io::Result<LockedFile> {
    let start = Instant::now();
    let mut pause = Duration::from_millis(1);
    loop {
        let target = fs::canonicalize(path)?;
        let file = open_nofollow(&target, OpenOptions::new().read(true))?;
        let meta = file.metadata()?;
        if !meta.is_file() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "not a regular file",
            ));
        }
        match flock(&file, libc::LOCK_EX | libc::LOCK_NB) {
            Ok(()) => {}
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                if start.elapsed() > LOCK_WAIT {
                    return Err(io::Error::new(
                        io::ErrorKind::WouldBlock,
                        "another process has held it locked for a minute (a 'novanc edit' still running?)",
                    ));
                }
                std::thread::sleep(pause);
                pause = (pause * 2).min(Duration::from_millis(20));
                continue;
            }
            Err(e) => return Err(e),
        }
        let same = fs::canonicalize(path)
            .ok()
            .filter(|t| *t == target)
            .and_then(|t| fs::symlink_metadata(t).ok())
            .is_some_and(|m| m.dev() == meta.dev() && m.ino() == meta.ino());
        if same {
            return Ok(LockedFile { file, target });
        }
    }
}

impl LockedFile {
    /// The file's contents now.
    pub fn read(&self) -> io::Result<Vec<u8>> {
        let mut f = &self.file;
        f.seek(io::SeekFrom::Start(0))?;
        let mut v = Vec::new();
        f.read_to_end(&mut v)?;
        Ok(v)
    }

    /// The locked file, opened again for writing in place (checked to be the same file).
    fn open_for_writing(&self) -> io::Result<File> {
        let f = open_nofollow(&self.target, OpenOptions::new().write(true))?;
        let (a, b) = (f.metadata()?, self.file.metadata()?);
        if a.dev() != b.dev() || a.ino() != b.ino() {
            return Err(io::Error::other(
                "the file was replaced while it was locked",
            ));
        }
        Ok(f)
    }

    /// Copies `data` over the file in place: the blocks it needs are reserved first (so a full
    /// disk shows before a byte changes), then it is written, cut to length and fsynced.
    fn copy_in_place(&self, data: &[u8], full: Option<&Path>) -> Result<(), RewriteError> {
        let unchanged = |error| RewriteError { error, torn: None };
        let mut f = self.open_for_writing().map_err(unchanged)?;
        reserve(&f, data.len() as u64).map_err(unchanged)?;
        f.write_all(data)
            .and_then(|_| f.set_len(data.len() as u64))
            .and_then(|_| f.sync_all())
            .map_err(|error| RewriteError {
                error,
                torn: full.map(Path::to_path_buf),
            })
    }

    /// Finishes a rewrite in place that an earlier writer was killed in the middle of: its
    /// `.NAME.rewrite-PID` holds the whole text it was writing. If the file differs from that
    /// text (it may be cut short), what the file holds is first kept as `NAME.bad-SECONDS`
    /// beside it, then the text is copied in. Returns what the operator should be told.
    pub fn settle(&self) -> io::Result<Option<String>> {
        let dir = parent_of(&self.target);
        let mut notes = Vec::new();
        // Under the lock no other writer of this file is at work: every one is left over.
        for (left, name, pid) in self.rewrites_left(&dir)? {
            let whole = fs::read(&left)?;
            let now = self.read()?;
            if whole != now {
                let kept = keep_copy(&dir, &name, &now)?;
                self.copy_in_place(&whole, None)
                    .map_err(|e| io::Error::new(e.error.kind(), e.to_string()))?;
                notes.push(format!(
                    "an earlier 'novanc edit --write' (process {pid}) was killed while rewriting {} in place; the whole text it was writing ({}) is now in the file, and what the file held is kept as {kept}",
                    self.target.display(),
                    left.display()
                ));
            }
            fs::remove_file(&left)?;
            fsync_dir(&dir)?;
        }
        Ok((!notes.is_empty()).then(|| notes.join("; ")))
    }

    /// The `.NAME.rewrite-PID` files in `dir` of any name of this file there (a hard link in
    /// the same directory counts; one in another directory is not seen), as (path, the name it
    /// was for, pid).
    fn rewrites_left(&self, dir: &Path) -> io::Result<Vec<(PathBuf, String, u32)>> {
        let me = self.file.metadata()?;
        let mut v = Vec::new();
        // In a directory that cannot be listed, what a writer left there cannot be found.
        let Ok(entries) = fs::read_dir(dir) else {
            return Ok(v);
        };
        for e in entries {
            let n = e?.file_name();
            let Some(rest) = n.as_bytes().strip_prefix(b".") else {
                continue;
            };
            let Some(at) = rest.windows(9).rposition(|w| w == b".rewrite-") else {
                continue;
            };
            let (of, digits) = (&rest[..at], &rest[at + 9..]);
            let Some(pid) = std::str::from_utf8(digits)
                .ok()
                .and_then(|d| d.parse::<u32>().ok())
            else {
                continue;
            };
            let same = fs::symlink_metadata(dir.join(OsStr::from_bytes(of)))
                .is_ok_and(|m| m.dev() == me.dev() && m.ino() == me.ino());
            if same && pid != std::process::id() {
                v.push((dir.join(&n), String::from_utf8_lossy(of).into_owned(), pid));
            }
        }
        v.sort();
        Ok(v)
    }

    /// Gives the file the contents `data`:
    /// - a file with one link is replaced atomically (`write_atomic` on the file the path
    ///   names: a symlink stays a link);
    /// - a file with several hard links is rewritten in place, so that every link sees the
    ///   new text: the new text is first written whole and fsynced as `.NAME.rewrite-PID`,
    ///   then copied over the file, which is fsynced, then that copy is removed. A kill during
    ///   the copy can leave the file torn; the whole new text is then in `.NAME.rewrite-PID`,
    ///   and the next `settle` copies it in.
    pub fn write(&self, data: &[u8]) -> Result<Rewrite, RewriteError> {
        let unchanged = |error| RewriteError { error, torn: None };
        if self.file.metadata().map_err(unchanged)?.nlink() <= 1 {
            write_atomic(&self.target, data).map_err(unchanged)?;
            return Ok(Rewrite::Atomic);
        }
        let dir = parent_of(&self.target);
        let name = name_of(&self.target).map_err(unchanged)?;
        let tmp = write_temp(&self.target, data).map_err(unchanged)?;
        let full = dir.join(temp_name(name, "rewrite", std::process::id()));
        if let Err(e) = fs::rename(&tmp, &full).and_then(|_| fsync_dir(&dir)) {
            let _ = fs::remove_file(&tmp);
            return Err(unchanged(e));
        }
        if let Err(e) = self.copy_in_place(data, Some(&full)) {
            if e.torn.is_none() {
                let _ = fs::remove_file(&full);
            }
            return Err(e);
        }
        let _ = fs::remove_file(&full).and_then(|_| fsync_dir(&dir));
        Ok(Rewrite::InPlace)
    }
}

/// Gives the operator's file at `path` the contents `data` under its lock (`lock_file`,
/// `LockedFile::settle`, `LockedFile::write`).
pub fn rewrite_file(path: &Path, data: &[u8]) -> Result<Rewrite, RewriteError> {
    let unchanged = |error| RewriteError { error, torn: None };
    let f = lock_file(path).map_err(unchanged)?;
    f.settle().map_err(unchanged)?;
    f.write(data)
}

/// Writes an output the operator named (a punched tape image, a screenshot): a new file is
/// created atomically; an existing regular file is rewritten under its lock as `novanc edit
/// --write` does (through a symlink, keeping hard links); a special file (`/dev/null`, a
/// terminal, a pipe) is written as it is.
pub fn write_output(path: &Path, data: &[u8]) -> Result<(), String> {
    match fs::metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            if fs::symlink_metadata(path).is_ok() {
                return Err("it is a symbolic link to nothing".into());
            }
            write_atomic(path, data).map_err(|e| e.to_string())
        }
        Err(e) => Err(e.to_string()),
        Ok(m) if m.is_dir() => Err("it is a directory".into()),
        Ok(m) if m.is_file() => rewrite_file(path, data)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        Ok(_) => OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(data))
            .map_err(|e| e.to_string()),
    }
}

/// Allocates the blocks a file needs to hold `len` bytes without changing its size, so that
/// a full disk shows before a rewrite in place changes a byte (where the file system can).
fn reserve(f: &File, len: u64) -> io::Result<()> {
    #[cfg(target_os = "linux")]
    {
        let len = libc::off_t::try_from(len).map_err(|_| io::Error::other("file too large"))?;
        // SAFETY: fallocate on a file descriptor we own; no memory is passed.
        let r = unsafe { libc::fallocate(f.as_raw_fd(), libc::FALLOC_FL_KEEP_SIZE, 0, len) };
        if r != 0 {
            let e = io::Error::last_os_error();
            if !matches!(
                e.raw_os_error(),
                Some(libc::EOPNOTSUPP) | Some(libc::ENOSYS) | Some(libc::EINVAL)
            ) {
                return Err(e);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (f, len);
    Ok(())
}

/// Finds a free name `NAME.bad-SECONDS` (or `NAME.bad-SECONDS-N`) in `dir` and makes it with
/// `make`, which fails with AlreadyExists if the name was taken meanwhile.
fn aside_name(
    dir: &Path,
    name: &str,
    mut make: impl FnMut(&Path) -> io::Result<()>,
) -> io::Result<String> {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    for i in 0..100 {
        let bad = match i {
            0 => format!("{name}.bad-{secs}"),
            i => format!("{name}.bad-{secs}-{i}"),
        };
        if fs::symlink_metadata(dir.join(&bad)).is_ok() {
            continue;
        }
        match make(&dir.join(&bad)) {
            Ok(()) => return Ok(bad),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other("no name free"))
}

/// Keeps a damaged file for inspection as `NAME.bad-SECONDS` (a hard link, so it needs no
/// space even on a full disk; a copy where links are not possible). Returns the new name.
pub fn keep_aside(dir: &Path, name: &str) -> io::Result<String> {
    let from = dir.join(name);
    aside_name(dir, name, |bad| match fs::hard_link(&from, bad) {
        Err(e) if e.kind() != io::ErrorKind::AlreadyExists => {
            let data = fs::read(&from).map_err(|_| e)?;
            copy_new(bad, &data)
        }
        r => r,
    })
}

/// Keeps `data` (what a file held) as a new file `NAME.bad-SECONDS` in `dir`. Returns its name.
fn keep_copy(dir: &Path, name: &str, data: &[u8]) -> io::Result<String> {
    aside_name(dir, name, |bad| copy_new(bad, data))
}

/// Creates `path` exclusively with `data`, fsynced; removed again if it cannot be written.
fn copy_new(path: &Path, data: &[u8]) -> io::Result<()> {
    let mut f = open_nofollow(path, OpenOptions::new().write(true).create_new(true))?;
    let r = f.write_all(data).and_then(|_| f.sync_all());
    if r.is_err() {
        let _ = fs::remove_file(path);
    }
    r
}

/// The damaged files of a directory that could not be kept aside yet: none of them may be
/// overwritten until it is (docs/stores.md "Damage"). Both machines' stores use it.
#[derive(Debug, Default)]
pub struct Aside {
    pending: Vec<String>,
}

impl Aside {
    /// Keeps the damaged file `name` of `dir` aside now (`keep_aside`); if that fails, it is
    /// remembered and `before_overwrite` refuses until it can be. Returns the name it is kept
    /// as, or why it could not be.
    pub fn keep(&mut self, dir: &Path, name: &str) -> Result<String, String> {
        keep_aside(dir, name).map_err(|e| {
            if !self.pending.iter().any(|p| p == name) {
                self.pending.push(name.to_string());
            }
            e.to_string()
        })
    }

    /// Before `name` (None: any file of the directory) is overwritten: keeps it aside if it is
    /// a damaged file still waiting for that. An error means it must not be overwritten yet.
    pub fn before_overwrite(&mut self, dir: &Path, name: Option<&str>) -> io::Result<()> {
        while let Some(i) = self
            .pending
            .iter()
            .position(|p| name.is_none_or(|n| n == p))
        {
            let f = &self.pending[i];
            keep_aside(dir, f)
                .map_err(|e| io::Error::other(format!("cannot keep the damaged {f} aside: {e}")))?;
            self.pending.remove(i);
        }
        Ok(())
    }

    /// Whether no damaged file waits to be kept aside.
    pub fn is_empty(&self) -> bool {
        self.pending.is_empty()
    }
}

/// Checks a name that becomes a file or directory name in the state directory (a machine's
/// name, in `lathe-NAME/`): 1 to 32 of `A-Z a-z 0-9 _ - .`, not starting with `.`, so that it
/// can name nothing outside the state directory (`..`, `a/../b`) and no hidden file.
pub fn check_file_name(name: &str) -> Result<(), String> {
    let ok = !name.is_empty()
        && name.len() <= 32
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if ok {
        Ok(())
    } else {
        Err(format!(
            "'{}' cannot name a file: 1 to 32 of letters, digits, _ - . (not starting with .)",
            name.escape_debug()
        ))
    }
}

/// Creates the state directory if missing; a path that exists but is not a directory (or
/// lies under a file) is refused saying so.
pub fn make_dir(dir: &Path) -> Result<(), String> {
    if dir.is_dir() {
        return Ok(());
    }
    for a in dir.ancestors().filter(|a| !a.as_os_str().is_empty()) {
        if let Ok(m) = fs::metadata(a) {
            if m.is_dir() {
                break;
            }
            let what = if m.is_file() {
                "a regular file"
            } else {
                "a special file"
            };
            return Err(format!("{} is {what}, not a directory", a.display()));
        }
    }
    fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
        let _ = fsync_dir(parent);
    }
    Ok(())
}

/// An exclusive lock on a state directory, held while the file stays open (released by the
/// kernel when the process ends, even by `kill -9`).
#[derive(Debug)]
pub struct DirLock {
    _file: Option<File>,
    read_only: Option<String>,
}

impl DirLock {
    /// Why no lock could be taken: the directory is read-only and has no lock file. Nothing may
    /// then be written in it (docs/stores.md "Where state lives").
    pub fn read_only(&self) -> Option<&str> {
        self.read_only.as_deref()
    }
}

/// Whether an error says the file system or the directory does not let us write.
pub fn is_read_only(e: &io::Error) -> bool {
    matches!(
        e.raw_os_error(),
        Some(libc::EACCES) | Some(libc::EROFS) | Some(libc::EPERM)
    )
}

/// Takes the lock file `lock` in `dir` (created if missing; never through a symlink); fails at
/// once if another process holds it. In a directory that cannot be written the lock file is
/// opened for reading (a lock needs no more); if there is none, the directory is open
/// unlocked and read-only (`DirLock::read_only`). Every error names the lock file.
pub fn lock_dir(dir: &Path) -> Result<DirLock, String> {
    let path = dir.join("lock");
    let named = |e: io::Error| format!("cannot open the lock file {}: {e}", path.display());
    let file = match open_nofollow(
        &path,
        OpenOptions::new().read(true).write(true).create(true),
    ) {
        Ok(f) => f,
        Err(e) if is_read_only(&e) => match open_nofollow(&path, OpenOptions::new().read(true)) {
            Ok(f) => f,
            Err(e2) if e2.kind() == io::ErrorKind::NotFound => {
                return Ok(DirLock {
                    _file: None,
                    read_only: Some(format!(
                        "cannot create the lock file {}: {e}",
                        path.display()
                    )),
                })
            }
            Err(e2) => return Err(named(e2)),
        },
        Err(e) => return Err(named(e)),
    };
    if !file.metadata().map_err(named)?.is_file() {
        return Err(format!(
            "the lock file {} is not a regular file",
            path.display()
        ));
    }
    match flock(&file, libc::LOCK_EX | libc::LOCK_NB) {
        Ok(()) => Ok(DirLock {
            _file: Some(file),
            read_only: None,
        }),
        Err(e) if e.kind() == io::ErrorKind::WouldBlock => Err(format!(
            "{}: another novanc is using this state directory",
            dir.display()
        )),
        Err(e) => Err(format!("cannot lock {}: {e}", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmpdir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("novanc-fsutil-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp() {
        let d = tmpdir("aw");
        let p = d.join("f.txt");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn temps_of_killed_writers_are_removed_and_live_ones_kept() {
        let d = tmpdir("stale");
        let p = d.join("f.ap");
        // A process that has ended: its pid is free.
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let dead = c.id();
        c.wait().unwrap();
        let stale = d.join(format!(".f.ap.tmp-{dead}"));
        let live = d.join(format!(".f.ap.tmp-{}", std::os::unix::process::parent_id()));
        let other = d.join(format!(".g.ap.tmp-{dead}"));
        for f in [&stale, &live, &other] {
            fs::write(f, b"partial").unwrap();
        }
        write_atomic(&p, b"new").unwrap();
        assert!(!stale.exists(), "a dead writer's temp is removed");
        assert!(live.exists(), "a live writer's temp is kept");
        assert!(other.exists(), "another file's temp is not touched");
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn rewrite_follows_symlinks_and_keeps_hard_links() {
        let d = tmpdir("rw");
        let real = d.join("real.ap");
        fs::write(&real, b"old").unwrap();
        let link = d.join("link.ap");
        std::os::unix::fs::symlink("real.ap", &link).unwrap();
        assert_eq!(rewrite_file(&link, b"one").unwrap(), Rewrite::Atomic);
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&real).unwrap(), b"one");
        let hard = d.join("hard.ap");
        fs::hard_link(&real, &hard).unwrap();
        assert_eq!(
            rewrite_file(&link, b"two, longer").unwrap(),
            Rewrite::InPlace
        );
        assert_eq!(rewrite_file(&hard, b"3").unwrap(), Rewrite::InPlace);
        assert_eq!(fs::read(&real).unwrap(), b"3");
        assert_eq!(
            fs::metadata(&hard).unwrap().ino(),
            fs::metadata(&real).unwrap().ino()
        );
        assert_eq!(
            fs::read_dir(&d).unwrap().count(),
            3,
            "no temporary file left"
        );
        // A rewrite killed during its copy leaves the whole text aside; the next writer
        // copies it in, keeping what the file held.
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let dead = c.id();
        c.wait().unwrap();
        let left = d.join(format!(".real.ap.rewrite-{dead}"));
        fs::write(&left, b"the whole new text").unwrap();
        fs::write(&real, b"the whole").unwrap();
        let l = lock_file(&link).unwrap();
        let note = l.settle().unwrap().unwrap();
        assert!(note.contains("killed while rewriting"), "{note}");
        assert_eq!(l.read().unwrap(), b"the whole new text");
        drop(l);
        assert!(!left.exists(), "the finished copy's text is removed");
        let kept: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.starts_with("real.ap.bad-"))
            .collect();
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(fs::read(d.join(&kept[0])).unwrap(), b"the whole");
        // One that had finished its copy is removed quietly.
        fs::write(&left, b"the whole new text").unwrap();
        assert_eq!(lock_file(&hard).unwrap().settle().unwrap(), None);
        assert!(!left.exists());
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_symlink_planted_at_the_temp_path_is_not_followed() {
        let d = tmpdir("plant");
        let victim = d.join("victim");
        fs::write(&victim, b"precious").unwrap();
        let p = d.join("f.txt");
        fs::write(&p, b"old").unwrap();
        let tmp = d.join(format!(".f.txt.tmp-{}", std::process::id()));
        std::os::unix::fs::symlink(&victim, &tmp).unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(
            fs::read(&victim).unwrap(),
            b"precious",
            "the link's target is untouched"
        );
        assert!(!fs::symlink_metadata(&p).unwrap().file_type().is_symlink());
        assert_eq!(fs::read(&p).unwrap(), b"new");
        assert!(
            fs::symlink_metadata(&tmp).is_err(),
            "the planted link is gone"
        );
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn second_lock_is_refused() {
        let d = tmpdir("lk");
        let l = lock_dir(&d).unwrap();
        let e = lock_dir(&d).unwrap_err();
        assert!(e.contains("another novanc"), "{e}");
        drop(l);
        assert!(lock_dir(&d).is_ok());
        let _ = fs::remove_dir_all(&d);
    }
}
