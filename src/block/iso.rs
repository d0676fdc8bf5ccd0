//! Printing blocks as ISO 6983 word-address lines (docs/pulse-core.md): absolute millimetres with three
//! decimals, words in the order `N G X Y Z I J K P F S T M`, at most one M per line (no `N` on a
//! block with sequence number 0: the restore blocks of a SEARCH). Arc centres
//! are incremental (I J K from the start point), the standard default. An arc outside the XY
//! plane says its plane on its own line (`G18 G02 X Z I K`, `G19 G03 Y Z J K`), with the third
//! axis when it is a helix; in a whole program an XY arc after one of those says `G17`.

use super::{Block, Css, FeedMode, Io, Motion, Plane, Statement, Sync};
use crate::settings::MachineSettings;
use std::io::Write;

/// The program preamble: metric, absolute, XY plane, feed per minute, no cutter-radius or
/// tool-length compensation, no canned cycle.
pub const PREAMBLE: &str = "G21 G90 G17 G94 G40 G49 G80";

/// A lathe program's preamble (`novanc translate --machine LATHE`): metric, absolute, the
/// turning plane ZX, X a radius (LinuxCNC's G8), feed per minute, no nose-radius
/// compensation, no canned cycle.
pub const LATHE_PREAMBLE: &str = "G21 G90 G18 G8 G94 G40 G80";

/// The program end.
pub const END: &str = "M30";

/// Decimal digits packed little-endian in an integer (the first character in the lowest
/// byte): a word of up to 16 characters is made in a register and appended in one copy of
/// 16 bytes, then the vector's length set back to the word's ([`push_packed`]). Pushed a
/// character at a time, each cost a capacity check; copied by the length of the number, a
/// call of the library's `memcpy`.
const fn packed_table(trim: bool, point: bool) -> [u32; 1000] {
    let mut t = [0u32; 1000];
    let mut i = 0;
    while i < 1000 {
        let d = [
            (b'0' + (i / 100) as u8) as u32,
            (b'0' + (i / 10 % 10) as u8) as u32,
            (b'0' + (i % 10) as u8) as u32,
        ];
        t[i] = if point {
            b'.' as u32 | d[0] << 8 | d[1] << 16 | d[2] << 24
        } else if !trim || i >= 100 {
            d[0] | d[1] << 8 | d[2] << 16
        } else if i >= 10 {
            d[1] | d[2] << 8
        } else {
            d[2]
        };
        i += 1;
    }
    t
}

/// "0" to "999", packed, without leading zeros.
const SMALL: [u32; 1000] = packed_table(true, false);
/// "000" to "999", packed.
const THREE: [u32; 1000] = packed_table(false, false);
/// ".000" to ".999", packed.
const DECIMALS: [u32; 1000] = packed_table(false, true);

/// `v` in decimal, packed, and its number of digits; `None` from 10^12 (more than 12 digits).
#[inline]
fn packed(mut v: u64) -> Option<(u128, u32)> {
    let mut groups = [0usize; 3];
    let mut k = 0;
    while v >= 1000 && k < 3 {
        groups[k] = (v % 1000) as usize;
        v /= 1000;
        k += 1;
    }
    let lead = v as usize;
    let mut x = u128::from(*SMALL.get(lead)?);
    let mut n = 1 + u32::from(lead >= 10) + u32::from(lead >= 100);
    while k > 0 {
        k -= 1;
        x |= u128::from(THREE[groups[k]]) << (8 * n);
        n += 3;
    }
    Some((x, n))
}

/// Appends the first `len` (at most 16) bytes of `x`, packed.
#[inline]
fn push_packed(out: &mut Vec<u8>, x: u128, len: u32) {
    let at = out.len();
    out.extend_from_slice(&x.to_le_bytes());
    out.truncate(at + len as usize);
}

/// Appends `v` in decimal.
fn push_uint(out: &mut Vec<u8>, v: u64) {
    match packed(v) {
        Some((x, n)) => push_packed(out, x, n),
        None => {
            push_uint(out, v / 1_000_000);
            let low = v % 1_000_000;
            let x = u128::from(THREE[(low / 1000) as usize])
                | u128::from(THREE[(low % 1000) as usize]) << 24;
            push_packed(out, x, 6);
        }
    }
}

/// A word's start, packed: a space, its letter and a minus sign when `neg`.
#[inline]
fn word_start(word: u8, neg: bool) -> (u128, u32) {
    let x = u128::from(b' ') | u128::from(word) << 8;
    if neg {
        (x | u128::from(b'-') << 16, 3)
    } else {
        (x, 2)
    }
}

/// Appends the word `start` (packed, `len` bytes) followed by the whole number `v` and then
/// `tail` (packed, `tail_len` bytes, at most 4).
#[inline]
fn push_word(out: &mut Vec<u8>, (start, len): (u128, u32), v: u64, tail: u32, tail_len: u32) {
    match packed(v) {
        Some((d, n)) if len + n + tail_len <= 16 => {
            // A tail of no bytes may start at the 17th: shifted out, not over the edge.
            let tail = u128::from(tail).checked_shl(8 * (len + n)).unwrap_or(0);
            let x = start | d << (8 * len) | tail;
            push_packed(out, x, len + n + tail_len);
        }
        _ => {
            push_packed(out, start, len);
            push_uint(out, v);
            push_packed(out, u128::from(tail), tail_len);
        }
    }
}

/// Appends ` {word}{mm:.3}` for `pulses` in millimetres.
fn mm(out: &mut Vec<u8>, word: u8, pulses: i64, st: &MachineSettings) {
    if st.pulse_mm == 0.001 {
        // Whole pulses of 0.001 mm are exactly three decimals: print the integer (the same
        // text as formatting the float, several times faster).
        let p = pulses.unsigned_abs();
        let decimals = DECIMALS[(p % 1000) as usize];
        push_word(out, word_start(word, pulses < 0), p / 1000, decimals, 4);
        return;
    }
    let _ = write!(out, " {}{:.3}", word as char, st.to_mm(pulses));
}

/// Appends ` {word}{v}` with at most three decimals, trailing zeros dropped.
fn number(out: &mut Vec<u8>, word: u8, v: f64) {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        push_word(out, word_start(word, v < 0.0), v.abs() as u64, 0, 0);
        return;
    }
    // Thousandths far from a half-way case round as `{:.3}` does: print the integer.
    let k = v.abs() * 1000.0;
    let r = k.round();
    if k < 1e15 && (k - k.floor() - 0.5).abs() > 1e-6 {
        let t = r as u64;
        let f = t % 1000;
        // The point and the decimals but trailing zeros (none when all are).
        let keep = if f == 0 {
            0
        } else if !f.is_multiple_of(10) {
            4
        } else if !f.is_multiple_of(100) {
            3
        } else {
            2
        };
        let decimals = DECIMALS[f as usize];
        push_word(out, word_start(word, v < 0.0), t / 1000, decimals, keep);
        return;
    }
    number_fmt(out, word, v);
}

/// `number` by the formatter: three decimals, trailing zeros dropped.
fn number_fmt(out: &mut Vec<u8>, word: u8, v: f64) {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    let _ = write!(out, " {}{s}", word as char);
}

/// The text an ISO printer made (ASCII, and the formatter's UTF-8 where it printed).
fn text(v: Vec<u8>) -> String {
    String::from_utf8(v).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The modal words a reader has in force before a line: those of the preamble (G17, G94,
/// G97) at the start of a program or of a single line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Modes {
    plane: Plane,
    feed_mode: FeedMode,
    css: Option<Css>,
    /// A lathe's program: an arc says its plane only when it changes.
    turning: bool,
    /// The last N word printed: its number, its text packed and its length (0: none).
    n: (u32, u128, u32),
}

/// The N word of sequence number `seq` (not 0), packed, and its length: the last one printed
/// (`last`) counted on by one in its text when `seq` follows it, as it does from block to
/// block (a tenth of what making it anew costs), else made anew.
#[inline]
fn n_word(last: (u32, u128, u32), seq: u32) -> (u128, u32) {
    let (n, mut x, len) = last;
    if len > 1 && n.checked_add(1) == Some(seq) {
        // From the last digit: 9s become 0s until a digit takes the carry.
        for k in (1..len).rev() {
            let shift = 8 * k;
            let d = (x >> shift) as u8;
            x &= !(0xffu128 << shift);
            if d != b'9' {
                return (x | u128::from(d + 1) << shift, len);
            }
            x |= u128::from(b'0') << shift;
        }
    }
    match packed(u64::from(seq)) {
        Some((d, k)) => (u128::from(b'N') | d << 8, k + 1),
        None => (0, 0),
    }
}

/// Appends one block's ISO line (no newline) to `out`.
pub fn write_line(out: &mut Vec<u8>, b: &Block, st: &MachineSettings) {
    let mut modes = Modes::default();
    write_line_in(out, b, st, &mut modes);
}

/// Appends one block's ISO line to `out`, with `modes` what a reader has in force before it
/// (updated): an arc in another plane prints its G17, G18 or G19; a change of feed mode its
/// G94 or G95; a change of constant surface speed `G96 … S.. D..` or G97. A block the mill's
/// sources make has none of these, so its line is as it always was.
fn write_line_in(out: &mut Vec<u8>, b: &Block, st: &MachineSettings, modes: &mut Modes) {
    let plane = &mut modes.plane;
    let start = out.len();
    // A block the console or the core made (a SEARCH restore) has no N number.
    if b.seq != 0 {
        let (x, len) = n_word(modes.n, b.seq);
        push_packed(out, x, len);
        modes.n = (b.seq, x, len);
    }
    let arc = matches!(b.motion, Motion::ArcCw | Motion::ArcCcw);
    // Every arc outside XY says its plane; on a lathe (`turning`) only a change of it.
    let said = if modes.turning {
        b.plane != *plane
    } else {
        b.plane != Plane::XY || *plane != Plane::XY
    };
    if arc && said {
        out.push(b' ');
        out.extend_from_slice(b.plane.g_code().as_bytes());
        *plane = b.plane;
    }
    // The feed mode as the feed moves have it (a rapid's is not printed).
    let feeds = matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw);
    let feed_mode = (feeds && modes.feed_mode != b.feed_mode).then_some(b.feed_mode);
    if feeds {
        modes.feed_mode = b.feed_mode;
    }
    match feed_mode {
        Some(FeedMode::PerRev) => out.extend_from_slice(b" G95"),
        Some(FeedMode::PerMin) => out.extend_from_slice(b" G94"),
        None => {}
    }
    let css = (modes.css != b.css).then_some(b.css);
    modes.css = b.css;
    match css {
        Some(Some(_)) => out.extend_from_slice(b" G96"),
        Some(None) => out.extend_from_slice(b" G97"),
        None => {}
    }
    // Each code its own copy of a length the compiler knows (no call of `memcpy`).
    match b.motion {
        Motion::Rapid => out.extend_from_slice(b" G00"),
        Motion::Linear if b.probe.is_some() => match b.probe {
            Some(383) => out.extend_from_slice(b" G38.3"),
            Some(384) => out.extend_from_slice(b" G38.4"),
            Some(385) => out.extend_from_slice(b" G38.5"),
            Some(310) => out.extend_from_slice(b" G31"),
            _ => out.extend_from_slice(b" G38.2"),
        },
        Motion::Linear if b.thread.is_some() => out.extend_from_slice(b" G33"),
        Motion::Linear => out.extend_from_slice(b" G01"),
        Motion::ArcCw => out.extend_from_slice(b" G02"),
        Motion::ArcCcw => out.extend_from_slice(b" G03"),
        Motion::Dwell => out.extend_from_slice(b" G04"),
        Motion::Aux => {}
    }
    match b.motion {
        Motion::Rapid | Motion::Linear => {
            let all = b.delta == [0; 3];
            for (i, w) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
                if all || b.delta[i] != 0 {
                    mm(out, w, b.end[i], st);
                }
            }
            // The rotary axes, in degrees, when they move (docs/gcode.md "Rotary axes").
            for (i, w) in [b'A', b'B', b'C'].into_iter().enumerate() {
                if b.delta[3 + i] != 0 {
                    mm(out, w, b.end[3 + i], st);
                }
            }
        }
        Motion::ArcCw | Motion::ArcCcw => {
            let [a0, a1, normal] = b.plane.axes();
            for (i, w) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
                if i != normal || b.delta[i] != 0 {
                    mm(out, w, b.end[i], st);
                }
            }
            let c = b.center.unwrap_or([0, 0]);
            let names = [b'I', b'J', b'K'];
            mm(out, names[a0], c[0], st);
            mm(out, names[a1], c[1], st);
        }
        Motion::Dwell => {
            let _ = write!(out, " P{:.3}", b.dwell_ns as f64 / 1e9);
        }
        Motion::Aux => {}
    }
    if let (Motion::Linear, Some(lead)) = (b.motion, b.thread) {
        number(out, b'K', lead);
    } else if matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw) {
        number(out, b'F', b.feed);
    }
    if let Some(Some(c)) = css {
        number(out, b'S', c.m_per_min);
        number(out, b'D', c.limit_rpm);
    }
    if let Some(s) = b.s {
        let _ = write!(out, " S{s}");
    }
    if let Some(t) = b.t {
        let _ = write!(out, " T{t:02}");
    }
    if let Some(m) = b.m {
        let _ = write!(out, " M{m:02}");
    }
    if let Some(io) = b.io {
        write_io(out, io);
    }
    match b.sync {
        Some(Sync::Wait { m, with }) => {
            // The channels that meet, as a P word lists them (P12: channels 1 and 2).
            let _ = write!(out, " M{m} P");
            for ch in (0..8).filter(|i| with & (1 << i) != 0) {
                let _ = write!(out, "{}", ch + 1);
            }
        }
        Some(Sync::ChuckClose) => out.extend_from_slice(b" M10"),
        Some(Sync::ChuckOpen) => out.extend_from_slice(b" M11"),
        None => {}
    }
    if b.seq == 0 && out.get(start) == Some(&b' ') {
        out.remove(start);
    }
}

/// The words of an I/O action (`M62 P3`, `M67 E1 Q2.5`, `M66 P0 L3 Q5`, `M19 R90 P0`,
/// `M50 P0 M51 P1`).
fn write_io(out: &mut Vec<u8>, io: Io) {
    match io {
        Io::Digital { index, on, synced } => {
            let m = match (synced, on) {
                (true, true) => 62,
                (true, false) => 63,
                (false, true) => 64,
                (false, false) => 65,
            };
            let _ = write!(out, " M{m} P{index}");
        }
        Io::Analog {
            index,
            value,
            synced,
        } => {
            let _ = write!(out, " M{} E{index}", if synced { 67 } else { 68 });
            number(out, b'Q', value);
        }
        Io::Wait {
            digital,
            index,
            mode,
            timeout,
        } => {
            let _ = write!(
                out,
                " M66 {}{index} L{mode}",
                if digital { 'P' } else { 'E' }
            );
            if timeout > 0.0 {
                number(out, b'Q', timeout);
            }
        }
        Io::Orient { angle, dir } => {
            out.extend_from_slice(b" M19");
            number(out, b'R', angle);
            let _ = write!(out, " P{dir}");
        }
        Io::Overrides { feed, speed } => {
            let _ = write!(out, " M50 P{} M51 P{}", u8::from(feed), u8::from(speed));
        }
    }
}

/// One block as an ISO 6983 word-address line in absolute mm with 3 decimals.
pub fn iso_line(block: &Block, settings: &MachineSettings) -> String {
    let mut s = Vec::with_capacity(48);
    write_line(&mut s, block, settings);
    text(s)
}

/// The whole program: the preamble, one line per block, then `M30` unless the last block
/// already is the translator's end-of-program `M30`.
pub fn iso_program(statements: &[Statement], settings: &MachineSettings) -> String {
    let mut s = Vec::new();
    let mut w = IsoWriter::new(&mut s);
    for st in statements {
        w.statement(&mut s, st, settings);
    }
    w.finish(&mut s);
    text(s)
}

/// Prints a program statement by statement (the same text as [`iso_program`]), so that a
/// long program need not be held whole. It appends bytes (ASCII text) to a `Vec<u8>`, which
/// a writer takes as it is: a `String` would have its every character checked on the way.
#[derive(Clone, Copy, Debug)]
pub struct IsoWriter {
    modes: Modes,
    last_m: Option<u8>,
}

impl IsoWriter {
    /// Starts a program: appends the preamble to `out`.
    pub fn new(out: &mut Vec<u8>) -> IsoWriter {
        IsoWriter::after(out, PREAMBLE)
    }

    /// Starts a lathe program: appends [`LATHE_PREAMBLE`] to `out`; arcs are in its plane ZX
    /// unless they say otherwise.
    pub fn lathe(out: &mut Vec<u8>) -> IsoWriter {
        let mut w = IsoWriter::after(out, LATHE_PREAMBLE);
        w.modes.plane = Plane::XZ;
        w.modes.turning = true;
        w
    }

    fn after(out: &mut Vec<u8>, preamble: &str) -> IsoWriter {
        out.extend_from_slice(preamble.as_bytes());
        out.push(b'\n');
        IsoWriter {
            modes: Modes::default(),
            last_m: None,
        }
    }

    /// Appends the lines of one statement's blocks.
    pub fn statement(&mut self, out: &mut Vec<u8>, st: &Statement, settings: &MachineSettings) {
        for b in &st.blocks {
            write_line_in(out, b, settings, &mut self.modes);
            out.push(b'\n');
            self.last_m = b.m;
        }
    }

    /// Ends the program: `M30` unless the last block was one.
    pub fn finish(self, out: &mut Vec<u8>) {
        if self.last_m != Some(30) {
            out.extend_from_slice(END.as_bytes());
            out.push(b'\n');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The integer path of `number` prints what the formatter prints, for every kind of value
    /// a word holds: whole, thousandths, half-way cases, tiny, negative, large.
    #[test]
    fn numbers_print_as_the_formatter_prints_them() {
        let mut rng = crate::pulse_core::testkit::Rng::new(7);
        let mut values = vec![
            0.0, -0.0, 0.0004, -0.0004, 0.0005, -0.0005, 1.0005, 2.5e-4, 9.9996,
        ];
        values.extend([
            12.3455,
            120.0,
            0.1,
            0.7,
            1e14 + 0.5,
            -3.25,
            99_999.999_5,
            1e16 + 0.5,
        ]);
        for _ in 0..200_000 {
            let scale = [1e-3, 1.0, 1e3, 1e6, 1e12][rng.range(0, 4) as usize];
            let v = (rng.unit() - 0.5) * scale;
            values.extend([
                v,
                (v * 1000.0).round() / 1000.0,
                (v * 2000.0).round() / 2000.0,
            ]);
        }
        for v in values {
            let (mut fast, mut slow) = (Vec::new(), Vec::new());
            number(&mut fast, b'F', v);
            number_fmt(&mut slow, b'F', v);
            let (fast, slow) = (text(fast), text(slow));
            if v.fract() != 0.0 || v.abs() >= 1e15 {
                assert_eq!(fast, slow, "{v:e}");
            }
        }
    }

    #[test]
    fn prints_words_in_order_with_three_decimals() {
        let st = MachineSettings::default();
        let mut b = Block::aux(12, 1, [406_292, 162_500, -485_000]);
        b.motion = Motion::Linear;
        b.delta = [0, 0, -10_000].into();
        b.feed = 120.0;
        assert_eq!(iso_line(&b, &st), "N12 G01 Z-485.000 F120");
        b.motion = Motion::ArcCcw;
        b.center = Some([-5_000, 0]);
        b.feed = 62.5;
        b.delta = [0; 3].into();
        assert_eq!(
            iso_line(&b, &st),
            "N12 G03 X406.292 Y162.500 I-5.000 J0.000 F62.5"
        );
        let mut a = Block::aux(3, 1, [0, 0, 0]);
        a.t = Some(2);
        a.m = Some(6);
        assert_eq!(iso_line(&a, &st), "N3 T02 M06");
        a.t = None;
        a.s = Some(1200);
        a.m = Some(3);
        assert_eq!(iso_line(&a, &st), "N3 S1200 M03");
        let mut d = Block::aux(4, 1, [0, 0, 0]);
        d.motion = Motion::Dwell;
        d.dwell_ns = 1_500_000_000;
        assert_eq!(iso_line(&d, &st), "N4 G04 P1.500");
    }

    #[test]
    fn millimetres_print_as_the_float_would() {
        let st = MachineSettings::default();
        for p in [
            0i64,
            1,
            -1,
            5,
            -5,
            999,
            -999,
            1000,
            -1000,
            123_456,
            -485_000,
            1 << 40,
        ] {
            let mut a = Vec::new();
            mm(&mut a, b'X', p, &st);
            assert_eq!(text(a), format!(" X{:.3}", st.to_mm(p)), "{p}");
        }
    }

    #[test]
    fn arcs_outside_xy_say_their_plane_and_ijk_from_the_start() {
        let st = MachineSettings::default();
        let mut b = Block::aux(5, 1, [10_000, 20_000, -5_000]);
        b.motion = Motion::ArcCw;
        b.plane = Plane::XZ;
        b.center = Some([-2_000, 1_500]);
        b.delta = [4_000, 0, -3_000].into();
        b.feed = 100.0;
        assert_eq!(
            iso_line(&b, &st),
            "N5 G18 G02 X10.000 Z-5.000 I-2.000 K1.500 F100"
        );
        b.plane = Plane::YZ;
        b.motion = Motion::ArcCcw;
        b.delta = [1_000, 4_000, -3_000].into();
        assert_eq!(
            iso_line(&b, &st),
            "N5 G19 G03 X10.000 Y20.000 Z-5.000 J-2.000 K1.500 F100"
        );
        // In a program, the XY arc after a G19 arc says G17; the next XY arc need not.
        let mut xy = b.clone();
        xy.plane = Plane::XY;
        xy.seq = 6;
        let mut xy2 = xy.clone();
        xy2.seq = 7;
        let stmt = Statement {
            line: 1,
            text: String::new(),
            blocks: vec![b, xy, xy2],
        };
        let prog = iso_program(&[stmt], &st);
        let lines: Vec<&str> = prog.lines().collect();
        assert!(lines[2].starts_with("N6 G17 G03 X10.000 Y20.000 Z-5.000 I-2.000 J1.500"));
        assert!(lines[3].starts_with("N7 G03 "));
    }

    #[test]
    fn lathe_words_print_only_when_they_change() {
        let st = MachineSettings::default();
        let mk = |seq: u32, z: i64| {
            let mut b = Block::aux(seq, 1, [8_000, 0, z]);
            b.motion = Motion::Linear;
            b.delta = [0, 0, -1_000].into();
            b
        };
        let css = Some(Css {
            m_per_min: 150.0,
            limit_rpm: 4000.0,
        });
        let mut a = mk(1, -1_000);
        (a.feed_mode, a.feed, a.css) = (FeedMode::PerRev, 0.1, css);
        let mut b = mk(2, -2_000);
        (b.feed_mode, b.feed, b.css) = (FeedMode::PerRev, 0.1, css);
        let mut c = mk(3, -30_000);
        c.thread = Some(2.0);
        let mut d = mk(4, -31_000);
        d.feed = 100.0;
        assert_eq!(iso_line(&a, &st), "N1 G95 G96 G01 Z-1.000 F0.1 S150 D4000");
        assert_eq!(iso_line(&c, &st), "N3 G33 Z-30.000 K2");
        let stmt = Statement {
            line: 1,
            text: String::new(),
            blocks: vec![a, b, c, d],
        };
        let prog = iso_program(&[stmt], &st);
        let lines: Vec<&str> = prog.lines().collect();
        assert_eq!(
            &lines[1..5],
            [
                "N1 G95 G96 G01 Z-1.000 F0.1 S150 D4000",
                "N2 G01 Z-2.000 F0.1",
                "N3 G94 G97 G33 Z-30.000 K2",
                "N4 G01 Z-31.000 F100",
            ]
        );
    }

    /// An N word counted on from the last one prints what making it anew prints: through
    /// every carry (9 to 10, 999 to 1000, 99,999 to 100,000), after jumps and a SEARCH's
    /// blocks without N, up to the largest sequence number.
    #[test]
    fn n_words_counted_on_are_made_anew() {
        let seqs = (1..=120_000u32)
            .chain([
                5, 6, 999, 1000, 1001, 99_999, 100_000, 9_999_999, 10_000_000,
            ])
            .chain([u32::MAX - 1, u32::MAX, 1, 2]);
        let mut last = (0, 0, 0);
        for seq in seqs {
            let (x, len) = n_word(last, seq);
            let mut out = Vec::new();
            push_packed(&mut out, x, len);
            assert_eq!(out, format!("N{seq}").as_bytes(), "after {}", last.0);
            last = (seq, x, len);
        }
    }
}
