//! SHDR lines: `TIMESTAMP|key|value|key|value…`, LF-terminated, the timestamp UTC ISO 8601
//! with milliseconds. Conditions, messages and tables go on lines of their own (their values
//! have several fields or spaces), plain samples and events share one line.

use std::borrow::Cow;
use std::time::{SystemTime, UNIX_EPOCH};

/// A value as SHDR carries it: line breaks become spaces; a value with a `|` or beginning
/// with a `"` is quoted, and inside the quotes every `|`, `"` and `\` is preceded by `\`.
/// Checked against the reference agent's tokenizer (cppagent `ShdrTokenizer::tokenize`): in a
/// quoted field a bare `|` still ends the field, and a backslash takes the next character as
/// it is; its tests read `"a\|b"` as `a|b`.
pub fn escape(v: &str) -> Cow<'_, str> {
    let v = if v.contains(['\n', '\r']) {
        Cow::Owned(v.replace(['\n', '\r'], " "))
    } else {
        Cow::Borrowed(v)
    };
    if !v.contains('|') && !v.trim_start().starts_with('"') {
        return v;
    }
    Cow::Owned(quote(&v))
}

/// `v` in quotes, every `|`, `"` and `\` inside preceded by `\`.
fn quote(v: &str) -> String {
    let mut out = String::with_capacity(v.len() + 2);
    out.push('"');
    for c in v.chars() {
        if c == '"' || c == '\\' || c == '|' {
            out.push('\\');
        }
        out.push(c);
    }
    out.push('"');
    out
}

/// The timestamp of `t`: `2026-11-26T23:04:05.123Z`.
pub fn timestamp(t: SystemTime) -> String {
    let d = t.duration_since(UNIX_EPOCH).unwrap_or_default();
    let secs = d.as_secs();
    let ms = d.subsec_millis();
    let days = (secs / 86400) as i64;
    let rem = secs % 86400;
    let (y, m, dd) = civil(days);
    format!(
        "{y:04}-{m:02}-{dd:02}T{:02}:{:02}:{:02}.{ms:03}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Days since 1970-01-01 to (year, month, day) (the proleptic Gregorian calendar).
fn civil(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// Whether the item's value has fields of its own (condition, message, table): it goes on its
/// own line.
pub fn own_line(key: &str) -> bool {
    matches!(
        base_key(key),
        "system" | "logic_program" | "motion_program" | "message" | "wpo" | "tooloffsets"
    )
}

/// The mill's name of a path's key: `exec` for `p2_exec` (a path of a device of several,
/// docs/mtconnect.md "The lathe"), the key itself otherwise.
pub fn base_key(key: &str) -> &str {
    let Some(rest) = key.strip_prefix('p') else {
        return key;
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    match rest[digits..].strip_prefix('_') {
        Some(base) if digits > 0 => base,
        _ => key,
    }
}

/// The SHDR text (one or more lines) for `items` at time `ts`; empty for no items.
pub fn lines<K: AsRef<str>>(ts: &str, items: &[(K, String)]) -> String {
    lines_of(ts, items.iter().map(|(k, v)| (k.as_ref(), v.as_str())))
}

/// [`lines`] of items given as (key, value) pairs.
pub fn lines_of<'a>(ts: &str, items: impl IntoIterator<Item = (&'a str, &'a str)>) -> String {
    let mut out = String::new();
    let mut shared = String::new();
    for (k, v) in items {
        if own_line(k) {
            // Multi-field values are pre-escaped field by field by `items`.
            for part in [ts, "|", k, "|", v, "\n"] {
                out.push_str(part);
            }
        } else {
            for part in ["|", k, "|", &escape(v)] {
                shared.push_str(part);
            }
        }
    }
    if shared.is_empty() {
        out
    } else {
        let mut all = String::with_capacity(ts.len() + shared.len() + 1 + out.len());
        for part in [ts, &shared, "\n", &out] {
            all.push_str(part);
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn timestamps_are_iso_8601_utc_with_milliseconds() {
        assert_eq!(timestamp(UNIX_EPOCH), "1970-01-01T00:00:00.000Z");
        let t = UNIX_EPOCH + Duration::from_millis(951_782_400_123); // 2000-02-29
        assert_eq!(timestamp(t), "2000-02-29T00:00:00.123Z");
        let t = UNIX_EPOCH + Duration::from_secs(1_798_761_599); // 2026-12-31 23:59:59
        assert_eq!(timestamp(t), "2026-12-31T23:59:59.000Z");
    }

    #[test]
    fn values_are_escaped() {
        assert_eq!(escape("G01 X1"), "G01 X1");
        assert_eq!(escape("a|b"), "\"a\\|b\"");
        assert_eq!(escape("|b|"), "\"\\|b\\|\"");
        assert_eq!(escape("\"q\\"), "\"\\\"q\\\\\"");
        assert_eq!(escape("a\nb"), "a b");
    }

    #[test]
    fn conditions_and_tables_get_their_own_lines() {
        let items = vec![
            ("exec", "ACTIVE".to_string()),
            ("system", "NORMAL||||".to_string()),
            ("Xact", "1.000".to_string()),
        ];
        assert_eq!(
            lines("T", &items),
            "T|exec|ACTIVE|Xact|1.000\nT|system|NORMAL||||\n"
        );
        let none: &[(&str, String)] = &[];
        assert_eq!(lines("T", none), "");
        // A path's conditions too, whatever its number; a prefix alone is not one.
        assert_eq!(
            lines("T", &[("p12_motion_program", "NORMAL||||".to_string())]),
            "T|p12_motion_program|NORMAL||||\n"
        );
        assert_eq!(base_key("p3_wpo"), "wpo");
        assert_eq!(base_key("path_feedrate"), "path_feedrate");
        assert_eq!(base_key("p_wpo"), "p_wpo");
    }
}
