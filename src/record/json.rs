//! The small JSON encoder of the recorder (no serde): strings with correct escaping, fast
//! integers for the pulse time arrays, millimetre floats, and one encoder per docs/recording.md topic.
//!
//! Everything appends to a caller-owned `Vec<u8>` so the recorder thread reuses one buffer for
//! every message. The output is always valid UTF-8 JSON.

use super::Event;
#[cfg(test)]
use super::Switches;
use crate::block::Axes;

/// Two ASCII digits for every value 0..100, for the integer formatter.
const DIGIT_PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Appends the decimal digits of `v`.
#[inline]
pub fn push_u64(out: &mut Vec<u8>, mut v: u64) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    while v >= 10_000 {
        let rem = (v % 10_000) as usize;
        v /= 10_000;
        let hi = (rem / 100) * 2;
        let lo = (rem % 100) * 2;
        i -= 4;
        buf[i] = DIGIT_PAIRS[hi];
        buf[i + 1] = DIGIT_PAIRS[hi + 1];
        buf[i + 2] = DIGIT_PAIRS[lo];
        buf[i + 3] = DIGIT_PAIRS[lo + 1];
    }
    let mut v = v as usize;
    if v >= 100 {
        let lo = (v % 100) * 2;
        v /= 100;
        i -= 2;
        buf[i] = DIGIT_PAIRS[lo];
        buf[i + 1] = DIGIT_PAIRS[lo + 1];
    }
    if v >= 10 {
        let d = v * 2;
        i -= 2;
        buf[i] = DIGIT_PAIRS[d];
        buf[i + 1] = DIGIT_PAIRS[d + 1];
    } else {
        i -= 1;
        buf[i] = b'0' + v as u8;
    }
    out.extend_from_slice(&buf[i..]);
}

/// Writes the `digits` decimal digits of `v` into `buf[..digits]` (`digits` ≥ the digit count).
#[inline(always)]
fn put_digits(buf: &mut [u8], mut v: u64, digits: usize) {
    let mut i = digits;
    while i >= 2 {
        let d = (v % 100) as usize * 2;
        v /= 100;
        i -= 2;
        buf[i] = DIGIT_PAIRS[d];
        buf[i + 1] = DIGIT_PAIRS[d + 1];
    }
    if i == 1 {
        buf[0] = b'0' + (v % 10) as u8;
    }
}

/// Number of decimal digits of `v` (1 for 0).
#[inline(always)]
fn digit_count(v: u64) -> usize {
    match v.checked_ilog10() {
        Some(l) => l as usize + 1,
        None => 1,
    }
}

/// Writes `v` < 10^8 as exactly 8 digits into `buf[..8]` (leading zeros kept).
#[inline(always)]
fn put8(buf: &mut [u8], v: u32) {
    let (a, b) = ((v / 10_000) as usize, (v % 10_000) as usize);
    let pairs = [(a / 100) * 2, (a % 100) * 2, (b / 100) * 2, (b % 100) * 2];
    for (k, d) in pairs.into_iter().enumerate() {
        buf[2 * k] = DIGIT_PAIRS[d];
        buf[2 * k + 1] = DIGIT_PAIRS[d + 1];
    }
}

/// Appends `v0,v1,...` (no brackets): the pulse-time fast path. It sizes the output once and
/// writes each number in place. A time ≥ 10^8 ns is written as its leading digits, kept from
/// the previous number while they do not change (pulse times are ascending), and 8 fixed
/// digits.
pub fn push_u64_list(out: &mut Vec<u8>, values: &[u64]) {
    const LOW: u64 = 100_000_000;
    let start = out.len();
    // 20 digits + a comma is the most any u64 needs.
    out.resize(start + values.len() * 21, 0);
    let buf = &mut out[start..];
    let mut p = 0;
    let mut hi_value = 0u64;
    let mut hi_digits = [0u8; 12];
    let mut hi_len = 0usize;
    for &v in values {
        if v < LOW {
            let n = digit_count(v);
            put_digits(&mut buf[p..p + n], v, n);
            p += n;
        } else {
            let hi = v / LOW;
            if hi != hi_value || hi_len == 0 {
                hi_value = hi;
                hi_len = digit_count(hi);
                put_digits(&mut hi_digits[..hi_len], hi, hi_len);
            }
            buf[p..p + hi_len].copy_from_slice(&hi_digits[..hi_len]);
            p += hi_len;
            put8(&mut buf[p..p + 8], (v % LOW) as u32);
            p += 8;
        }
        buf[p] = b',';
        p += 1;
    }
    // Drop the last comma.
    out.truncate(start + p.saturating_sub(1));
}

/// Appends a signed integer.
#[inline]
pub fn push_i64(out: &mut Vec<u8>, v: i64) {
    if v < 0 {
        out.push(b'-');
    }
    push_u64(out, v.unsigned_abs());
}

/// Appends a length in millimetres rounded to 6 decimals, without trailing zeros
/// (`12.5`, `-0.003`, `0`). A non-finite value (never expected) is written as `null`.
pub fn push_mm(out: &mut Vec<u8>, mm: f64) {
    push_decimal(out, mm, 6);
}

/// Appends `v` rounded to `decimals` (at most 9) decimals, without trailing zeros; a
/// non-finite value (never expected) as `null`.
pub fn push_decimal(out: &mut Vec<u8>, v: f64, decimals: u32) {
    if !v.is_finite() {
        out.extend_from_slice(b"null");
        return;
    }
    let decimals = decimals.min(9);
    let unit = 10u64.pow(decimals);
    // Whole units of the last decimal as an integer: exact digits, no float noise.
    let scaled = (v * unit as f64).round();
    if scaled.abs() >= 9.0e18 {
        // Beyond any machine's travel; fall back to Rust's shortest round-trip form.
        out.extend_from_slice(format!("{v:e}").as_bytes());
        return;
    }
    let n = scaled as i64;
    if n < 0 {
        out.push(b'-');
    }
    let a = n.unsigned_abs();
    push_u64(out, a / unit);
    let mut frac = a % unit;
    if frac != 0 {
        out.push(b'.');
        let mut digits = decimals as usize;
        while frac.is_multiple_of(10) {
            frac /= 10;
            digits -= 1;
        }
        let start = out.len();
        push_u64(out, frac);
        let written = out.len() - start;
        // Leading zeros of the fraction (0.003 → "003").
        for _ in written..digits {
            out.insert(start, b'0');
        }
    }
}

/// Appends a JSON string literal: quotes, backslash and control characters escaped, everything
/// else (including non-ASCII UTF-8) copied as is.
pub fn push_str(out: &mut Vec<u8>, s: &str) {
    out.push(b'"');
    let bytes = s.as_bytes();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        let esc: &[u8] = match b {
            b'"' => b"\\\"",
            b'\\' => b"\\\\",
            b'\n' => b"\\n",
            b'\r' => b"\\r",
            b'\t' => b"\\t",
            0x08 => b"\\b",
            0x0c => b"\\f",
            0x00..=0x1f => b"",
            _ => continue,
        };
        out.extend_from_slice(&bytes[start..i]);
        if esc.is_empty() {
            const HEX: &[u8; 16] = b"0123456789abcdef";
            out.extend_from_slice(b"\\u00");
            out.push(HEX[(b >> 4) as usize]);
            out.push(HEX[(b & 0xf) as usize]);
        } else {
            out.extend_from_slice(esc);
        }
        start = i + 1;
    }
    out.extend_from_slice(&bytes[start..]);
    out.push(b'"');
}

/// The axis letter of a pulse batch; anything but 0, 1, 2 is written as `"?"` (never expected).
fn axis_letter(axis: u8) -> &'static [u8] {
    match axis {
        0 => b"\"X\"",
        1 => b"\"Y\"",
        2 => b"\"Z\"",
        3 => b"\"A\"",
        4 => b"\"B\"",
        5 => b"\"C\"",
        _ => b"\"?\"",
    }
}

/// Appends the JSON message of `ev` to `out` and returns its machine time in ns (for a pulse
/// batch, the first pulse's time; 0 for an empty batch): [`encode_event_axes`] for X Y Z.
pub fn encode_event(out: &mut Vec<u8>, ev: &Event, pulse_mm: f64) -> u64 {
    encode_event_axes(out, ev, pulse_mm, 0)
}

/// [`encode_event`] on a machine with the rotary axes of `rotary` (a mask: bit 0 A, bit 1 B,
/// bit 2 C; `MachineSettings::rotary_mask`): positions carry `a`, `b`, `c` (degrees) and a
/// counter each after Z's for the rotary axes the machine has, and only those.
pub fn encode_event_axes(out: &mut Vec<u8>, ev: &Event, pulse_mm: f64, rotary: u8) -> u64 {
    match ev {
        Event::Block {
            t_ns,
            seq,
            stmt,
            text,
        } => {
            out.extend_from_slice(b"{\"seq\":");
            push_u64(out, u64::from(*seq));
            out.extend_from_slice(b",\"stmt\":");
            push_u64(out, u64::from(*stmt));
            out.extend_from_slice(b",\"text\":");
            push_str(out, text);
            out.push(b'}');
            *t_ns
        }
        Event::Position {
            t_ns,
            pulses,
            held,
            speed_mm_min,
        } => {
            out.push(b'{');
            push_place(out, pulses, held, pulse_mm, rotary);
            out.extend_from_slice(b",\"speed\":");
            push_mm(out, *speed_mm_min);
            out.push(b'}');
            *t_ns
        }
        Event::Pulses { axis, dir, t_ns } => {
            out.reserve(40 + t_ns.len() * 15);
            out.extend_from_slice(b"{\"axis\":");
            out.extend_from_slice(axis_letter(*axis));
            out.extend_from_slice(if *dir < 0 {
                b",\"dir\":-1,\"t_ns\":["
            } else {
                b",\"dir\":1,\"t_ns\":["
            });
            push_u64_list(out, t_ns);
            out.extend_from_slice(b"]}");
            t_ns.first().copied().unwrap_or(0)
        }
        Event::State {
            t_ns,
            run,
            op_mode,
            data_mode,
            feed_override,
            tool,
            spindle,
            switches,
        } => {
            out.extend_from_slice(b"{\"run\":");
            push_u64(out, u64::from(*run));
            out.extend_from_slice(b",\"op_mode\":");
            push_str(out, op_mode);
            out.extend_from_slice(b",\"data_mode\":");
            push_str(out, data_mode);
            out.extend_from_slice(b",\"feed_override\":");
            push_u64(out, u64::from(*feed_override));
            out.extend_from_slice(b",\"tool\":");
            push_u64(out, u64::from(*tool));
            out.extend_from_slice(b",\"spindle\":");
            push_i64(out, *spindle);
            out.extend_from_slice(b",\"rapid_override\":");
            push_u64(out, u64::from(switches.rapid_override));
            out.extend_from_slice(b",\"spindle_override\":");
            push_u64(out, u64::from(switches.spindle_override));
            for (key, on) in [
                (&b",\"dry_run\":"[..], switches.dry_run),
                (b",\"machine_lock\":", switches.machine_lock),
                (b",\"z_neglect\":", switches.z_neglect),
                (b",\"override_locked\":", switches.override_locked),
            ] {
                out.extend_from_slice(key);
                out.extend_from_slice(if on { b"true" } else { b"false" });
            }
            out.push(b'}');
            *t_ns
        }
        Event::Display { t_ns, lines } => {
            out.extend_from_slice(b"{\"lines\":[");
            for (i, line) in lines.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                push_str(out, line);
            }
            out.extend_from_slice(b"]}");
            *t_ns
        }
        Event::PanelEvent { t_ns, event } => {
            out.extend_from_slice(b"{\"event\":");
            push_str(out, event);
            out.push(b'}');
            *t_ns
        }
        Event::Probe {
            t_ns,
            seq,
            stmt,
            pulses,
            tripped,
            at_start,
        } => {
            out.extend_from_slice(b"{\"seq\":");
            push_u64(out, u64::from(*seq));
            out.extend_from_slice(b",\"stmt\":");
            push_u64(out, u64::from(*stmt));
            out.push(b',');
            push_place(out, pulses, &Axes::default(), pulse_mm, rotary);
            out.extend_from_slice(b",\"tripped\":");
            out.extend_from_slice(if *tripped { b"true" } else { b"false" });
            out.extend_from_slice(b",\"at_start\":");
            out.extend_from_slice(if *at_start { b"true" } else { b"false" });
            out.push(b'}');
            *t_ns
        }
        Event::Io {
            t_ns,
            seq,
            stmt,
            digital,
            index,
            value,
            synced,
            input,
        } => {
            out.extend_from_slice(b"{\"seq\":");
            push_u64(out, u64::from(*seq));
            out.extend_from_slice(b",\"stmt\":");
            push_u64(out, u64::from(*stmt));
            out.extend_from_slice(if *digital {
                &b",\"kind\":\"digital\",\"index\":"[..]
            } else {
                b",\"kind\":\"analog\",\"index\":"
            });
            push_u64(out, u64::from(*index));
            out.extend_from_slice(b",\"value\":");
            push_mm(out, *value);
            out.extend_from_slice(b",\"synced\":");
            out.extend_from_slice(if *synced { b"true" } else { b"false" });
            // An input says so; an output is as it was before inputs were recorded.
            out.extend_from_slice(if *input { b",\"dir\":\"in\"}" } else { b"}" });
            *t_ns
        }
        Event::Log {
            t_ns,
            level,
            name,
            message,
            file,
            line,
        } => {
            out.extend_from_slice(b"{\"timestamp\":");
            super::foxglove::push_time(out, *t_ns);
            out.extend_from_slice(b",\"level\":");
            push_u64(out, u64::from(*level));
            out.extend_from_slice(b",\"message\":");
            push_str(out, message);
            out.extend_from_slice(b",\"name\":");
            push_str(out, name);
            out.extend_from_slice(b",\"file\":");
            push_str(out, file);
            out.extend_from_slice(b",\"line\":");
            push_u64(out, u64::from(*line));
            out.push(b'}');
            *t_ns
        }
        Event::Lathe {
            t_ns,
            channel,
            event,
            work,
            value,
            text,
        } => {
            out.extend_from_slice(b"{\"channel\":");
            push_u64(out, u64::from(*channel));
            out.extend_from_slice(b",\"event\":");
            push_str(out, event);
            if let Some(w) = work {
                out.extend_from_slice(b",\"work\":");
                push_u64(out, u64::from(*w));
            }
            if let Some(v) = value {
                out.extend_from_slice(b",\"value\":");
                push_i64(out, *v);
            }
            out.extend_from_slice(b",\"text\":");
            push_str(out, text);
            out.push(b'}');
            *t_ns
        }
        Event::OnChannel { channel, ev } => {
            // `{"channel":N,` then the event's own fields: its encoding less its `{`.
            out.extend_from_slice(b"{\"channel\":");
            push_u64(out, u64::from(*channel));
            out.push(b',');
            let at = out.len();
            let t = encode_event_axes(out, ev, pulse_mm, rotary);
            if out.get(at) == Some(&b'{') {
                out.remove(at);
            }
            t
        }
    }
}

/// `"x":..,"y":..,"z":..,"pulses":[..]`: a position in mm from the counters, and the counters.
/// `x`, `y`, `z` (mm) of the program position `pulses`, and `pulses`, the axis counters: the
/// same less what MACHINE LOCK `held` back.
fn push_place(out: &mut Vec<u8>, pulses: &Axes, held: &Axes, pulse_mm: f64, rotary: u8) {
    let keys = [
        &b"\"x\":"[..],
        b",\"y\":",
        b",\"z\":",
        b",\"a\":",
        b",\"b\":",
        b",\"c\":",
    ];
    let has = |i: usize| i < 3 || rotary & (1 << (i - 3)) != 0;
    for (i, key) in keys.iter().enumerate().filter(|(i, _)| has(*i)) {
        out.extend_from_slice(key);
        push_mm(out, pulses[i] as f64 * pulse_mm);
    }
    out.extend_from_slice(b",\"pulses\":[");
    for i in (0..crate::block::MAX_AXES).filter(|&i| has(i)) {
        if i > 0 {
            out.push(b',');
        }
        push_i64(out, pulses[i] - held[i]);
    }
    out.push(b']');
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(f: impl FnOnce(&mut Vec<u8>)) -> String {
        let mut out = Vec::new();
        f(&mut out);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn integers_match_std_formatting() {
        let mut rng = crate::pulse_core::testkit::Rng::new(0x9E37_79B9_7F4A_7C15);
        let mut cases = vec![0, 1, 9, 10, 99, 100, 999, 1000, 9999, 10_000, 123_456_789];
        cases.extend([u64::MAX, u64::MAX - 1, 10u64.pow(19), 10u64.pow(19) - 1]);
        for _ in 0..10_000 {
            let x = rng.next_u64();
            cases.push(x >> (x % 64));
        }
        let joined = cases
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(",");
        assert_eq!(s(|o| push_u64_list(o, &cases)), joined);
        for v in cases {
            assert_eq!(s(|o| push_u64(o, v)), v.to_string());
            let i = v as i64;
            assert_eq!(s(|o| push_i64(o, i)), i.to_string());
        }
        assert_eq!(s(|o| push_i64(o, i64::MIN)), i64::MIN.to_string());
    }

    #[test]
    fn integer_lists_match_std_formatting() {
        let cases: Vec<u64> = vec![0, 7, 10, 99, 100, 12_345, 60_000_000_123, u64::MAX, 1];
        let want = cases
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(",");
        assert_eq!(s(|o| push_u64_list(o, &cases)), want);
        assert_eq!(s(|o| push_u64_list(o, &[])), "");
        // Ascending runs that share leading digits, across digit-count and 10^8 boundaries.
        for base in [
            0u64,
            99_999_990,
            9_999_999_990,
            60_000_000_000,
            99_999_999_999_999_990,
        ] {
            let run: Vec<u64> = (0..40).map(|k| base + k * 3).chain([u64::MAX]).collect();
            let want = run
                .iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(",");
            assert_eq!(s(|o| push_u64_list(o, &run)), want);
        }
        let mut o = b"[".to_vec();
        push_u64_list(&mut o, &[5]);
        assert_eq!(o, b"[5");
    }

    #[test]
    fn millimetres_have_at_most_six_decimals_and_no_noise() {
        assert_eq!(s(|o| push_mm(o, 0.0)), "0");
        assert_eq!(s(|o| push_mm(o, -0.0)), "0");
        assert_eq!(s(|o| push_mm(o, 12.5)), "12.5");
        assert_eq!(s(|o| push_mm(o, 3.0 * 0.001)), "0.003");
        assert_eq!(s(|o| push_mm(o, -0.003)), "-0.003");
        assert_eq!(s(|o| push_mm(o, 0.1 + 0.2)), "0.3");
        assert_eq!(s(|o| push_mm(o, 123_456.000_001)), "123456.000001");
        assert_eq!(s(|o| push_mm(o, -1.000_000_4)), "-1");
        assert_eq!(s(|o| push_mm(o, 0.010_2)), "0.0102");
        assert_eq!(s(|o| push_mm(o, f64::NAN)), "null");
        assert_eq!(s(|o| push_mm(o, f64::INFINITY)), "null");
        for p in -5000i64..5000 {
            let text = s(|o| push_mm(o, p as f64 * 0.001));
            let back: f64 = text.parse().unwrap();
            assert!((back - p as f64 * 0.001).abs() < 1e-9, "{p} -> {text}");
        }
    }

    #[test]
    fn strings_escape_quotes_backslash_and_control_characters() {
        assert_eq!(s(|o| push_str(o, "")), r#""""#);
        assert_eq!(s(|o| push_str(o, r#"a"b\c"#)), r#""a\"b\\c""#);
        assert_eq!(s(|o| push_str(o, "l1\nl2\r\t")), r#""l1\nl2\r\t""#);
        assert_eq!(
            s(|o| push_str(o, "\u{0}\u{1}\u{8}\u{c}\u{1f}\u{7f}")),
            "\"\\u0000\\u0001\\b\\f\\u001f\u{7f}\""
        );
        assert_eq!(s(|o| push_str(o, "Ø 20 µm → ÷")), "\"Ø 20 µm → ÷\"");
    }

    #[test]
    fn every_topic_encodes_its_fields() {
        let enc = |ev: Event| {
            let mut out = Vec::new();
            let t = encode_event(&mut out, &ev, 0.001);
            (t, String::from_utf8(out).unwrap())
        };
        assert_eq!(
            enc(Event::Block {
                t_ns: 5,
                seq: 3,
                stmt: 12,
                text: "N3 G01 X10.\"".into()
            }),
            (5, r#"{"seq":3,"stmt":12,"text":"N3 G01 X10.\""}"#.into())
        );
        assert_eq!(
            enc(Event::Position {
                t_ns: 7,
                pulses: [12_500, -3, 0].into(),
                held: [0; 3].into(),
                speed_mm_min: 1234.5
            }),
            (
                7,
                r#"{"x":12.5,"y":-0.003,"z":0,"pulses":[12500,-3,0],"speed":1234.5}"#.into()
            )
        );
        assert_eq!(
            enc(Event::Pulses {
                axis: 1,
                dir: -1,
                t_ns: vec![100, 200, 1_000_000_000_000]
            }),
            (
                100,
                r#"{"axis":"Y","dir":-1,"t_ns":[100,200,1000000000000]}"#.into()
            )
        );
        assert_eq!(
            enc(Event::Pulses {
                axis: 2,
                dir: 1,
                t_ns: vec![]
            }),
            (0, r#"{"axis":"Z","dir":1,"t_ns":[]}"#.into())
        );
        assert_eq!(
            enc(Event::State {
                t_ns: 9,
                run: 1,
                op_mode: "AUTO".into(),
                data_mode: "RUN".into(),
                feed_override: 100,
                tool: 4,
                spindle: -1200,
                switches: Switches {
                    rapid_override: 0,
                    machine_lock: true,
                    ..Switches::default()
                }
            }),
            (
                9,
                r#"{"run":1,"op_mode":"AUTO","data_mode":"RUN","feed_override":100,"tool":4,"spindle":-1200,"rapid_override":0,"spindle_override":100,"dry_run":false,"machine_lock":true,"z_neglect":false,"override_locked":false}"#
                    .into()
            )
        );
        assert_eq!(
            enc(Event::Display {
                t_ns: 1,
                lines: vec!["A".into(), "Ø\"".into()]
            }),
            (1, r#"{"lines":["A","Ø\""]}"#.into())
        );
        assert_eq!(
            enc(Event::PanelEvent {
                t_ns: 2,
                event: "key START".into()
            }),
            (2, r#"{"event":"key START"}"#.into())
        );
    }
}
