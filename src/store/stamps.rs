//! When each program last changed, for the PROG page (docs/stores.md, "History and counters").
//!
//! The file `program-times` holds one line per program, `NAME UNIX_SECONDS`. It is rewritten
//! (temporary file, rename) when a change lands in a later second than the stamp it replaces,
//! without an fsync: the programs themselves are journaled, and a power cut that loses a stamp
//! only shows an older time. A program with no stamp (the embedded one, or one changed before
//! the file existed) shows none. A damaged line is skipped.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// The stamps file in the state directory.
pub const STAMPS: &str = "program-times";

/// The last-change times of the programs, in seconds since 1970 (UTC).
#[derive(Debug)]
pub struct Stamps {
    path: PathBuf,
    times: BTreeMap<String, u64>,
}

/// Now, in whole seconds since 1970.
pub fn now_s() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

impl Stamps {
    /// Reads the stamps of `dir` (none if the file is missing or unreadable).
    pub fn open(dir: &Path) -> Stamps {
        let path = dir.join(STAMPS);
        let mut times = BTreeMap::new();
        if let Ok(text) = std::fs::read_to_string(&path) {
            for l in text.lines() {
                if let Some((name, t)) = l.rsplit_once(' ') {
                    if let Ok(t) = t.parse::<u64>() {
                        if !name.is_empty() {
                            times.insert(name.to_string(), t);
                        }
                    }
                }
            }
        }
        Stamps { path, times }
    }

    /// When `name` last changed, if known.
    pub fn get(&self, name: &str) -> Option<u64> {
        self.times.get(name).copied()
    }

    /// `name` changed at `t`.
    pub fn touch(&mut self, name: &str, t: u64) {
        if self.times.get(name) != Some(&t) {
            self.times.insert(name.to_string(), t);
            self.save();
        }
    }

    /// `from` is now called `to`: the stamp goes with the text.
    pub fn rename(&mut self, from: &str, to: &str) {
        if let Some(t) = self.times.remove(from) {
            self.times.insert(to.to_string(), t);
            self.save();
        }
    }

    /// `name` was deleted.
    pub fn remove(&mut self, name: &str) {
        if self.times.remove(name).is_some() {
            self.save();
        }
    }

    /// Writes the file (`fsutil::write_atomic`); a failure is ignored (the stamps are not
    /// operator data).
    fn save(&self) {
        let mut text = String::new();
        for (n, t) in &self.times {
            text.push_str(&format!("{n} {t}\n"));
        }
        let _ = super::fsutil::write_atomic(&self.path, text.as_bytes());
    }
}

/// A time in seconds since 1970 as `YYYY-MM-DD HH:MM` in the machine's local time (the
/// `TZ` of the process), or in UTC if the C library cannot say.
pub fn format_local(t: u64) -> String {
    let [y, mo, d, h, mi, _] = local(t);
    format!("{y:04}-{mo:02}-{d:02} {h:02}:{mi:02}")
}

/// A time in seconds since 1970 as `YYYY-MM-DD HH:MM:SS` in the machine's local time, or in
/// UTC if the C library cannot say.
pub fn format_local_seconds(t: u64) -> String {
    let [y, mo, d, h, mi, s] = local(t);
    format!("{y:04}-{mo:02}-{d:02} {h:02}:{mi:02}:{s:02}")
}

/// A time in seconds since 1970 as `YYYY-MM-DD HH:MM` in UTC.
pub fn format_utc(t: u64) -> String {
    let [y, mo, d, h, mi, _] = utc(t);
    format!("{y:04}-{mo:02}-{d:02} {h:02}:{mi:02}")
}

/// Year, month, day, hour, minute, second of `t` in local time (UTC if unknown).
fn local(t: u64) -> [i64; 6] {
    let Ok(tt) = libc::time_t::try_from(t) else {
        return utc(t);
    };
    // SAFETY: localtime_r writes only into `tm`, which lives for the call; `tt` is a valid
    // time_t.
    let mut tm: libc::tm = unsafe { std::mem::zeroed() };
    let ok = unsafe { !libc::localtime_r(&tt, &mut tm).is_null() };
    if !ok {
        return utc(t);
    }
    [
        i64::from(tm.tm_year) + 1900,
        i64::from(tm.tm_mon) + 1,
        i64::from(tm.tm_mday),
        i64::from(tm.tm_hour),
        i64::from(tm.tm_min),
        i64::from(tm.tm_sec),
    ]
}

/// Year, month, day, hour, minute, second of `t` in UTC (the civil calendar from days, after
/// Howard Hinnant's `civil_from_days`).
fn utc(t: u64) -> [i64; 6] {
    let days = (t / 86_400) as i64;
    let secs = (t % 86_400) as i64;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    [y, m, d, secs / 3600, secs % 3600 / 60, secs % 60]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_the_civil_calendar() {
        assert_eq!(format_utc(0), "1970-01-01 00:00");
        assert_eq!(format_utc(951_782_400), "2000-02-29 00:00");
        assert_eq!(format_utc(1_795_388_400), "2026-11-22 23:00");
        assert_eq!(format_utc(4_107_542_399), "2100-02-28 23:59");
        assert_eq!(format_local_seconds(12).len(), "1970-01-01 00:00:12".len());
    }

    #[test]
    fn stamps_survive_a_reopen_and_follow_renames() {
        let dir = std::env::temp_dir().join(format!("novanc-stamps-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut s = Stamps::open(&dir);
        s.touch("A", 100);
        s.touch("B C", 200);
        s.rename("A", "D");
        s.remove("B C");
        s.touch("E", 300);
        let r = Stamps::open(&dir);
        assert_eq!(r.get("D"), Some(100));
        assert_eq!(r.get("A"), None);
        assert_eq!(r.get("B C"), None);
        assert_eq!(r.get("E"), Some(300));
        std::fs::write(dir.join(STAMPS), "junk\nF x\nG 5\n").unwrap();
        assert_eq!(Stamps::open(&dir).get("G"), Some(5));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
