//! Durable file operations: atomic replacement (temporary file, fsync, rename, fsync of the
//! directory), the safe rewrite `novanc edit --write` uses (through symlinks, keeping hard
//! links), and the lock that keeps two consoles off one state directory (docs/stores.md).

use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::MetadataExt;
use std::os::unix::io::AsRawFd;
use std::path::{Path, PathBuf};

/// The directory holding `path` (`.` for a bare file name).
fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
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

/// The temporary files `.NAME.KIND-PID` beside `name` in `dir` whose process is gone (killed
/// while writing), as (path, pid).
fn dead_temps(dir: &Path, name: &OsStr, kind: &str) -> Vec<PathBuf> {
    let mut prefix = b".".to_vec();
    prefix.extend_from_slice(name.as_bytes());
    prefix.extend_from_slice(format!(".{kind}-").as_bytes());
    let Ok(entries) = fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let n = e.file_name();
            let digits = n.as_bytes().strip_prefix(prefix.as_slice())?;
            let pid: u32 = std::str::from_utf8(digits).ok()?.parse().ok()?;
            (pid != std::process::id() && !alive(pid)).then(|| dir.join(&n))
        })
        .collect()
}

/// Writes `data` to a new temporary file `.NAME.tmp-PID` beside `path` and fsyncs it, first
/// removing the ones earlier killed writers left. Returns its path.
fn write_temp(path: &Path, data: &[u8]) -> io::Result<PathBuf> {
    let dir = parent_of(path);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
    for stale in dead_temps(&dir, name, "tmp") {
        let _ = fs::remove_file(stale);
    }
    let tmp = dir.join(temp_name(name, "tmp", std::process::id()));
    let result = (|| {
        let mut f = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&tmp)?;
        if let Ok(meta) = fs::metadata(path) {
            f.set_permissions(meta.permissions())?;
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
/// one, never a mix. Writes a temporary file `.NAME.tmp-PID` beside it, fsyncs it, renames it
/// over `path` and fsyncs the directory. Keeps the old file's permissions. Temporary files of
/// earlier writers that were killed (their process is gone) are removed first. `path` itself
/// is replaced: a symlink becomes a file (the stores want that; see `rewrite_file`).
pub fn write_atomic(path: &Path, data: &[u8]) -> io::Result<()> {
    let tmp = write_temp(path, data)?;
    let result = fs::rename(&tmp, path).and_then(|_| fsync_dir(&parent_of(path)));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// How `rewrite_file` wrote a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rewrite {
    /// Replaced by rename: a crash leaves the old text or the new one.
    Atomic,
    /// Rewritten in place because it has other hard links (docs/stores.md "novanc edit").
    InPlace,
}

/// Gives the file at `path` the contents `data`, as `novanc edit --write` does:
/// - a symlink is followed: its target is written, the link stays;
/// - a file with one link is replaced atomically (`write_atomic`);
/// - a file with several hard links is rewritten in place, so that every link sees the new
///   text: the new text is first written whole and fsynced as `.NAME.rewrite-PID`, then copied
///   over the file, which is fsynced, then that copy is removed. A crash during the copy can
///   leave the file torn, but the whole new text is then in `.NAME.rewrite-PID`, which
///   `interrupted_rewrite` finds.
pub fn rewrite_file(path: &Path, data: &[u8]) -> Result<Rewrite, RewriteError> {
    let unchanged = |error| RewriteError { error, torn: None };
    let target = fs::canonicalize(path).map_err(unchanged)?;
    if fs::metadata(&target).map_err(unchanged)?.nlink() <= 1 {
        write_atomic(&target, data).map_err(unchanged)?;
        return Ok(Rewrite::Atomic);
    }
    let dir = parent_of(&target);
    let name = target.file_name().ok_or_else(|| {
        unchanged(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a file name",
        ))
    })?;
    let tmp = write_temp(&target, data).map_err(unchanged)?;
    let full = dir.join(temp_name(name, "rewrite", std::process::id()));
    if let Err(e) = fs::rename(&tmp, &full).and_then(|_| fsync_dir(&dir)) {
        let _ = fs::remove_file(&tmp);
        return Err(unchanged(e));
    }
    let mut f = match OpenOptions::new().write(true).open(&target) {
        Ok(f) => f,
        Err(e) => {
            let _ = fs::remove_file(&full);
            return Err(unchanged(e));
        }
    };
    if let Err(e) = reserve(&f, data.len() as u64) {
        let _ = fs::remove_file(&full);
        return Err(unchanged(e));
    }
    let copied = f
        .write_all(data)
        .and_then(|_| f.set_len(data.len() as u64))
        .and_then(|_| f.sync_all());
    if let Err(error) = copied {
        return Err(RewriteError {
            error,
            torn: Some(full),
        });
    }
    let _ = fs::remove_file(&full).and_then(|_| fsync_dir(&dir));
    Ok(Rewrite::InPlace)
}

/// Why `rewrite_file` failed.
#[derive(Debug)]
pub struct RewriteError {
    /// The I/O error.
    pub error: io::Error,
    /// None: the file is unchanged. Some: the copy in place failed part way, so the file may
    /// be torn; the whole new text is in this file.
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

/// A rewrite in place of `path` that a killed `novanc edit --write` left unfinished: the
/// `.NAME.rewrite-PID` holding the whole text it was writing, if it differs from the file
/// (the file may be torn). One that matches the file (the copy had finished) is removed.
pub fn interrupted_rewrite(path: &Path) -> Option<PathBuf> {
    let target = fs::canonicalize(path).ok()?;
    let name = target.file_name()?;
    let now = fs::read(&target).ok();
    for p in dead_temps(&parent_of(&target), name, "rewrite") {
        if now.is_some() && fs::read(&p).ok() == now {
            let _ = fs::remove_file(&p);
        } else {
            return Some(p);
        }
    }
    None
}

/// Keeps a damaged file for inspection as `NAME.bad-SECONDS` (a hard link, so it needs no
/// space even on a full disk; a copy where links are not possible). Returns the new name.
pub fn keep_aside(dir: &Path, name: &str) -> io::Result<String> {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let mut last = io::Error::other("no name free");
    for i in 0..100 {
        let bad = match i {
            0 => format!("{name}.bad-{secs}"),
            i => format!("{name}.bad-{secs}-{i}"),
        };
        if dir.join(&bad).exists() {
            continue;
        }
        match fs::hard_link(dir.join(name), dir.join(&bad)) {
            Ok(()) => return Ok(bad),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(_) => match fs::copy(dir.join(name), dir.join(&bad)) {
                Ok(_) => return Ok(bad),
                Err(e) => {
                    let _ = fs::remove_file(dir.join(&bad));
                    last = e;
                    break;
                }
            },
        }
    }
    Err(last)
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
    _file: File,
}

/// Takes the lock file `lock` in `dir`; fails at once if another process holds it.
pub fn lock_dir(dir: &Path) -> io::Result<DirLock> {
    let file = OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(dir.join("lock"))?;
    // SAFETY: flock on a file descriptor we own; no memory is passed.
    let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if r != 0 {
        let e = io::Error::last_os_error();
        if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
            return Err(io::Error::new(
                io::ErrorKind::WouldBlock,
                "another novanc is using this state directory",
            ));
        }
        return Err(e);
    }
    Ok(DirLock { _file: file })
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
        // A rewrite killed during its copy leaves the whole text aside; found until settled.
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let dead = c.id();
        c.wait().unwrap();
        let left = d.join(format!(".real.ap.rewrite-{dead}"));
        fs::write(&left, b"the whole new text").unwrap();
        assert_eq!(interrupted_rewrite(&link), Some(left.clone()));
        fs::write(&real, b"the whole new text").unwrap();
        assert_eq!(interrupted_rewrite(&link), None);
        assert!(!left.exists(), "a finished copy's text is removed");
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn second_lock_is_refused() {
        let d = tmpdir("lk");
        let l = lock_dir(&d).unwrap();
        let e = lock_dir(&d).unwrap_err();
        assert!(e.to_string().contains("another novanc"), "{e}");
        drop(l);
        assert!(lock_dir(&d).is_ok());
        let _ = fs::remove_dir_all(&d);
    }
}
