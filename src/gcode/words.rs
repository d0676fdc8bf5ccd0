//! Sorting a read line's words (docs/gcode.md "Words"): G and M codes by modal group, one
//! value per other letter; unknown letters and codes, a letter twice and two codes of one modal
//! group are refused.

use super::read::{Line, Word};
use crate::block::TranslateError;

/// The letters a mill line may hold, besides G and M (`@` and `^` are the polar words, E the
/// analog output of M67/M68).
const LETTERS: &str = "DEFHIJKLPQRSTXYZ@^";

/// What one G-code dialect accepts: its letters and its G and M codes by modal group. The mill
/// reader uses [`MILL`]; the lathe reader (docs/lathe-gcode.md) has its own.
#[derive(Clone, Copy, Debug)]
pub struct Dialect {
    /// M codes a machine description remaps (M0–M255, bit m), read in modal group 10 though
    /// the dialect does not define them (docs/gcode.md "Remapping M6 and other M codes").
    pub m_remap: [u64; 4],
    /// The letters a line may hold, besides G and M.
    pub letters: &'static str,
    /// The same letters as bits (`letter_bits(letters)`), tested once per word.
    pub letter_bits: u32,
    /// The modal group (0–12) of a G code ×10, or `None` for an unknown code.
    pub g_group: fn(u32) -> Option<u8>,
    /// The modal group (0–10) of an M code, or `None` for an unknown code.
    pub m_group: fn(u32) -> Option<u8>,
    /// Why a G code (×10) is unknown, appended to the message ("" for no reason).
    pub g_why: fn(u32) -> &'static str,
    /// Appended to the message for an unknown letter.
    pub letter_hint: &'static str,
}

/// The mill dialect (docs/gcode.md "Words").
pub const MILL: Dialect = Dialect {
    letters: LETTERS,
    letter_bits: letter_bits(LETTERS),
    g_group,
    m_group,
    g_why: mill_g_why,
    letter_hint: " (novanc has the axes X, Y and Z)",
    m_remap: [0; 4],
};

impl Dialect {
    /// Whether a machine description remaps M code `m` ([`Dialect::m_remap`]).
    pub fn remapped(&self, m: u32) -> bool {
        m < 256 && self.m_remap[(m / 64) as usize] >> (m % 64) & 1 == 1
    }

    /// This dialect with the M codes `codes` remapped.
    pub fn with_remaps(&self, codes: impl Iterator<Item = u32>) -> Dialect {
        let mut d = *self;
        for m in codes.filter(|&m| m < 256) {
            d.m_remap[(m / 64) as usize] |= 1 << (m % 64);
        }
        d
    }
}

/// Whether novanc's mill defines M code `m` in either dialect (a machine description may
/// remap only one it does not: docs/gcode.md "Remapping M6 and other M codes").
pub fn m_code_known(m: u32) -> bool {
    m_group(m).is_some() || fanuc_m_group(m).is_some()
}

/// `base` on a machine with rotary axes: their letters `letters` (all of a line's letters)
/// and the hint `hint`.
const fn with_rotary(base: Dialect, letters: &'static str, hint: &'static str) -> Dialect {
    Dialect {
        letters,
        letter_bits: letter_bits(letters),
        letter_hint: hint,
        ..base
    }
}

/// A mill's letters and hint with each set of rotary axes, by mask (bit 0 A, bit 1 B, bit 2 C).
const ROTARY_LETTERS: [(&str, &str); 8] = [
    (LETTERS, " (novanc has the axes X, Y and Z)"),
    (
        "ADEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z and A)",
    ),
    (
        "BDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z and B)",
    ),
    (
        "ABDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z, A and B)",
    ),
    (
        "CDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z and C)",
    ),
    (
        "ACDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z, A and C)",
    ),
    (
        "BCDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z, B and C)",
    ),
    (
        "ABCDEFHIJKLPQRSTXYZ@^",
        " (novanc has the axes X, Y, Z, A, B and C)",
    ),
];

/// The mill dialects, LinuxCNC's and Fanuc's, on a machine with each set of rotary axes.
static MILLS: [[Dialect; 8]; 2] = {
    let mut out = [[MILL; 8], [FANUC; 8]];
    let mut i = 0;
    while i < 8 {
        let (l, h) = ROTARY_LETTERS[i];
        out[0][i] = with_rotary(MILL, l, h);
        out[1][i] = with_rotary(FANUC, l, h);
        i += 1;
    }
    out
};

/// The mill's dialect, Fanuc's language or LinuxCNC's, on a machine with the rotary axes of
/// `mask` (bit 0 A, bit 1 B, bit 2 C; docs/gcode.md "Rotary axes").
pub fn mill_with(mask: u8, fanuc: bool) -> &'static Dialect {
    &MILLS[usize::from(fanuc)][usize::from(mask & 7)]
}

/// The mill dialect read in Fanuc's language (docs/gcode.md "Fanuc dialect"): G31 (skip) is
/// a motion and M29 (rigid tapping) a spindle code besides LinuxCNC's codes.
pub const FANUC: Dialect = Dialect {
    g_group: fanuc_g_group,
    m_group: fanuc_m_group,
    g_why: fanuc_g_why,
    ..MILL
};

fn fanuc_m_group(m: u32) -> Option<u8> {
    if m == 29 {
        return Some(7);
    }
    m_group(m)
}

fn fanuc_g_group(g: u32) -> Option<u8> {
    match g {
        310 => Some(1),
        // G08 P1: Fanuc's AI advanced preview (the mill's G08 is no lathe radius mode here);
        // G09, exact stop for one block: every block here ends at rest on its end anyway.
        80 | 90 => Some(0),
        // G68/G69: Fanuc's coordinate rotation (its group 16).
        680 | 690 => Some(16),
        // G76: Fanuc's fine boring, a canned cycle.
        760 => Some(1),
        _ => g_group(g),
    }
}

/// Why a G code is unknown in the Fanuc dialect: Fanuc's own mill codes that novanc does not
/// read say what they are (a G76 there is fine boring, not LinuxCNC's lathe threading).
fn fanuc_g_why(g: u32) -> &'static str {
    match g {
        150 | 160 => {
            " (Fanuc's polar coordinate command is not read: the @ and ^ words give polar points)"
        }
        501 | 511 => " (Fanuc's programmable mirror image is not read)",
        500 | 510 => " (Fanuc's scaling is not read)",
        541 => " (Fanuc's additional work systems G54.1 P1–P48: novanc has G54–G59.3)",
        620 => " (Fanuc's automatic corner override is not read: the feed at inside corners is the programmed one here)",
        630 => " (Fanuc's tapping mode is not read: tap with G84, or with M29 and G84)",
        370 => " (Fanuc's automatic tool length measurement needs a tool setter: not on this machine)",
        120 | 130 => " (circle cutting is an option some Fanuc machines add: program the circle with G02 or G03)",
        _ => mill_g_why(g),
    }
}

fn mill_g_why(g: u32) -> &'static str {
    match g {
        70 | 80 => " (G07/G08 diameter and radius mode are the lathe's)",
        700..=729 | 760 => " (G70–G72 and G76 are lathe cycles)",
        960 => " (G96 constant surface speed is the lathe's)",
        171 | 181 | 191 => " (the UV, UW and VW planes need U, V and W axes)",
        _ => "",
    }
}

/// A short list of codes with their columns (one per modal group at most).
#[derive(Clone, Copy, Debug, Default)]
pub struct Codes {
    v: [(u32, u32); 17],
    n: usize,
}

impl Codes {
    fn push(&mut self, c: (u32, u32)) {
        if self.n < self.v.len() {
            self.v[self.n] = c;
            self.n += 1;
        }
    }

    fn remove(&mut self, code: u32) {
        if let Some(i) = self.v[..self.n].iter().position(|c| c.0 == code) {
            self.v.copy_within(i + 1..self.n, i);
            self.n -= 1;
        }
    }

    /// The codes in the order written.
    pub fn as_slice(&self) -> &[(u32, u32)] {
        &self.v[..self.n]
    }

    /// The first code.
    pub fn first(&self) -> Option<&(u32, u32)> {
        self.as_slice().first()
    }

    fn iter(&self) -> std::slice::Iter<'_, (u32, u32)> {
        self.as_slice().iter()
    }
}

impl PartialEq for Codes {
    /// The codes given (the slots past them keep an earlier line's).
    fn eq(&self, o: &Codes) -> bool {
        self.as_slice() == o.as_slice()
    }
}

/// The words of one line sorted out: G and M codes, one value per other letter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Words {
    /// G codes ×10 (G04 = 40, G43.1 = 431) with columns.
    pub g: Codes,
    /// M codes with columns.
    pub m: Codes,
    vals: [Option<(f64, u32)>; 28],
    /// Bit g/10 for each whole G code, bit m for each M code below 128.
    g_bits: u128,
    m_bits: u128,
    /// Bit g/10 for each G code, whole or not (G43.1 sets bit 43).
    g_any: u128,
    /// Bit n for each letter given (A = 0 … Z = 25, `@` 26, `^` 27).
    letters: u32,
}

impl Words {
    /// The value of a letter's word, if given.
    pub fn get(&self, c: char) -> Option<f64> {
        self.vals[slot(c)].map(|v| v.0)
    }

    /// The column of a letter's word, if given.
    pub fn col(&self, c: char) -> Option<u32> {
        self.vals[slot(c)].map(|v| v.1)
    }

    /// Whether a G code (×10) is on the line, and its column. Inlined: the executor asks for
    /// a dozen constant codes a line, each then a test of a constant bit.
    #[inline(always)]
    pub fn has_g(&self, g: u32) -> Option<u32> {
        if g < 1280 {
            let bits = if g.is_multiple_of(10) {
                self.g_bits
            } else {
                self.g_any
            };
            if bits & (1u128 << (g / 10)) == 0 {
                return None;
            }
        }
        self.g.iter().find(|x| x.0 == g).map(|x| x.1)
    }

    /// Whether an M code is on the line, and its column.
    #[inline(always)]
    pub fn has_m(&self, m: u32) -> Option<u32> {
        if m < 128 && self.m_bits & (1u128 << m) == 0 {
            return None;
        }
        self.m.iter().find(|x| x.0 == m).map(|x| x.1)
    }

    /// Whether the line is a plain move: no M code, no G code but G00–G03, and no letter but
    /// the axes, I J K R F and the polar words. Such a line sets nothing but the motion and F,
    /// so the executor can go straight to its motion.
    pub fn plain(&self) -> bool {
        const MOTION_ONLY: u128 = (1 << 0) | (1 << 1) | (1 << 2) | (1 << 3);
        const LETTERS: u32 = (1 << (b'X' - b'A'))
            | (1 << (b'Y' - b'A'))
            | (1 << (b'Z' - b'A'))
            | (1 << (b'I' - b'A'))
            | (1 << (b'J' - b'A'))
            | (1 << (b'K' - b'A'))
            | (1 << (b'R' - b'A'))
            | (1 << (b'F' - b'A'))
            | (1 << 26)
            | (1 << 27);
        self.m.n == 0
            && self.g_any & !MOTION_ONLY == 0
            && self.g.as_slice().iter().all(|c| c.0 % 10 == 0)
            && self.letters & !LETTERS == 0
    }

    /// Empties the words: only the slots of the letters given are touched (the whole is a
    /// kilobyte, and a reader sorts every line into the same one).
    pub(crate) fn clear(&mut self) {
        let mut given = self.letters;
        while given != 0 {
            self.vals[given.trailing_zeros() as usize] = None;
            given &= given - 1;
        }
        self.g.n = 0;
        self.m.n = 0;
        self.g_bits = 0;
        self.m_bits = 0;
        self.g_any = 0;
        self.letters = 0;
    }

    /// Whether any of X, Y, Z is given.
    pub fn has_axis(&self) -> bool {
        ['X', 'Y', 'Z'].iter().any(|&c| self.get(c).is_some())
    }
}

/// The slot of a letter in `Words::vals`: A–Z, then `@` and `^`.
/// Bit `slot(c)` for each letter of `letters` (A–Z, `@`, `^`).
pub const fn letter_bits(letters: &str) -> u32 {
    let b = letters.as_bytes();
    let mut bits = 0u32;
    let mut i = 0;
    while i < b.len() {
        bits |= match b[i] {
            b'@' => 1 << 26,
            b'^' => 1 << 27,
            c @ b'A'..=b'Z' => 1 << (c - b'A'),
            _ => 0,
        };
        i += 1;
    }
    bits
}

/// Whether `c` is one of the letters of `bits` (`letter_bits`).
fn letter_in(bits: u32, c: char) -> bool {
    (c.is_ascii_uppercase() || c == '@' || c == '^') && bits & (1 << slot(c)) != 0
}

fn slot(c: char) -> usize {
    match c {
        '@' => 26,
        '^' => 27,
        c => (c as u8).wrapping_sub(b'A').min(25) as usize,
    }
}

/// The modal group of a G code (×10), or `None` for one novanc does not know: LinuxCNC 2.9's
/// groups (group 16, G92.2/G92.3, is folded into group 0, as in 2.9).
fn g_group(g: u32) -> Option<u8> {
    Some(match g {
        0 | 10 | 20 | 30 | 50 | 51 | 52 | 330 | 331 | 382..=385 | 730 | 740 | 800..=890 => 1,
        170 | 180 | 190 => 2,
        900 | 910 => 3,
        901 | 911 => 4,
        930 | 940 | 950 => 5,
        200 | 210 => 6,
        400 | 410 | 411 | 420 | 421 => 7,
        430 | 431 | 432 | 490 => 8,
        980 | 990 => 10,
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => 12,
        610 | 611 | 640 => 13,
        970 => 14,
        40 | 53 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920..=923 => 0,
        _ => return None,
    })
}

/// The modal group of an M code, or `None` for one novanc does not know: LinuxCNC 2.9's.
fn m_group(m: u32) -> Option<u8> {
    Some(match m {
        0 | 1 | 2 | 30 | 60 => 4,
        62..=68 => 5,
        6 | 61 => 6,
        3..=5 | 19 | 70..=73 => 7,
        7..=9 => 8,
        48..=53 => 9,
        98 | 99 => 10,
        _ => return None,
    })
}

/// Refuses the words of LinuxCNC's language that name what a LinuxCNC configuration has and
/// this machine has not (M100–M199, `$`), with that reason: the mill's reader in LinuxCNC's
/// dialect asks this before it sorts a line's words. (Until stop 51 this sat in a sorting
/// function no reader called, and M101 was refused as "unknown or unsupported".)
pub fn refuse_configuration_words(line: &Line, n: u32, d: &Dialect) -> Result<(), TranslateError> {
    for w in &line.words {
        let message = match w.letter {
            'M' if (100.0..200.0).contains(&w.value)
                && w.value.fract() == 0.0
                && !d.remapped(w.value as u32) =>
            {
                format!(
                "M{}: M100–M199 run the user programs of a LinuxCNC configuration (its USER_M_PATH): novanc has none (a machine description may remap one to a subroutine)",
                w.value
            )
            }
            '$' => "$ selects one of several spindles (LinuxCNC's multi-spindle machines): novanc has one".into(),
            _ => continue,
        };
        return Err(TranslateError {
            line: n,
            col: w.col,
            message,
        });
    }
    Ok(())
}

/// Sorts a line's words in a dialect, refusing unknown letters and codes, a letter twice, and
/// two codes of one modal group.
pub fn sort_words_in(line: &Line, n: u32, d: &Dialect) -> Result<Words, TranslateError> {
    let mut w = Words::default();
    sort_words_into(line, n, d, &mut w)?;
    Ok(w)
}

/// [`sort_words_in`] into `w`, which is cleared first (a reader keeps one: the sorted words
/// are a kilobyte, copied twice a line when returned).
pub fn sort_words_into(
    line: &Line,
    n: u32,
    d: &Dialect,
    w: &mut Words,
) -> Result<(), TranslateError> {
    w.clear();
    let mut seen = Seen::default();
    for &word in &line.words {
        w.add(word, n, d, &mut seen)?;
    }
    Ok(())
}

/// The codes of each modal group a line's words have given so far (what [`Words::add`]
/// checks a code against), with their columns.
#[derive(Clone, Copy, Debug, Default)]
pub struct Seen {
    g: [Option<(u32, u32)>; 17],
    m: [Option<(u32, u32)>; 11],
}

impl Words {
    /// Sorts in one more word of line `n` (the words written before it already in, `seen`
    /// their modal groups): refused as [`sort_words_in`] refuses it. The reader sorts each
    /// word so as it reads it (`read::ReadOpts::sort`), `sort_words_into` a line's words.
    #[inline]
    pub fn add(
        &mut self,
        word: Word,
        n: u32,
        d: &Dialect,
        seen: &mut Seen,
    ) -> Result<(), TranslateError> {
        match word.letter {
            'G' | 'M' => self.add_code(word, n, d, seen),
            c if letter_in(d.letter_bits, c) => {
                // The usual word, made short: its errors are made out of line.
                let s = slot(c);
                self.letters |= 1 << s;
                if self.vals[s].is_some() {
                    return Err(refused(
                        n,
                        word.col,
                        format_args!("two {c} words on one line"),
                    ));
                }
                self.vals[s] = Some((word.value, word.col));
                Ok(())
            }
            c => Err(refused(
                n,
                word.col,
                format_args!("unknown word {c}{}", d.letter_hint),
            )),
        }
    }

    /// [`Words::add`] for a G or M code.
    fn add_code(
        &mut self,
        Word { letter, value, col }: Word,
        n: u32,
        d: &Dialect,
        seen: &mut Seen,
    ) -> Result<(), TranslateError> {
        let err = |col: u32, message: String| TranslateError {
            line: n,
            col,
            message,
        };
        let w = self;
        let (g_seen, m_seen) = (&mut seen.g, &mut seen.m);
        match letter {
            'G' => {
                // Rounded without the library call where the integer holds it exactly.
                let g10 = if (value * 10.0).abs() < 1e15 {
                    let t = value * 10.0;
                    let i = t as i64 as f64;
                    if t - i >= 0.5 {
                        i + 1.0
                    } else if t - i <= -0.5 {
                        i - 1.0
                    } else {
                        i
                    }
                } else {
                    (value * 10.0).round()
                };
                if (value * 10.0 - g10).abs() > 1e-6 || g10 < 0.0 {
                    return Err(err(
                        col,
                        format!("unknown code G{}", crate::input_text::short_number(value)),
                    ));
                }
                let g = g10 as u32;
                // Only an error needs the code's name.
                let name = || {
                    if g.is_multiple_of(10) {
                        format!("G{:02}", g / 10)
                    } else {
                        format!("G{}.{}", g / 10, g % 10)
                    }
                };
                let Some(grp) = (d.g_group)(g).filter(|&x| x < 17) else {
                    let why = (d.g_why)(g);
                    return Err(err(
                        col,
                        format!("unknown or unsupported code {}{why}", name()),
                    ));
                };
                if grp == 1 && g == 800 && g_seen[1].is_some() {
                    // G80 beside another motion code gives way to it (LinuxCNC reads a
                    // safe-start line `G0 G80 ...` so).
                    return Ok(());
                }
                if grp == 1 && g_seen[1].is_some_and(|(o, _)| o == 800) {
                    w.g.remove(800);
                    g_seen[1] = None;
                }
                if let Some((other, _)) = g_seen[grp as usize] {
                    let on = if other.is_multiple_of(10) {
                        format!("G{:02}", other / 10)
                    } else {
                        format!("G{}.{}", other / 10, other % 10)
                    };
                    return Err(err(
                        col,
                        format!("{} and {on} are in the same modal group: give one", name()),
                    ));
                }
                g_seen[grp as usize] = Some((g, col));
                w.g.push((g, col));
                if g.is_multiple_of(10) && g < 1280 {
                    w.g_bits |= 1u128 << (g / 10);
                }
                if g < 1280 {
                    w.g_any |= 1u128 << (g / 10);
                }
            }
            'M' => {
                if value.fract() != 0.0 || value < 0.0 {
                    return Err(err(
                        col,
                        format!("unknown code M{}", crate::input_text::short_number(value)),
                    ));
                }
                let m = value as u32;
                let Some(grp) = (d.m_group)(m)
                    .or_else(|| d.remapped(m).then_some(10))
                    .filter(|&x| x < 11)
                else {
                    return Err(err(col, format!("unknown or unsupported code M{m:02}")));
                };
                if let Some((other, _)) = m_seen[grp as usize] {
                    return Err(err(
                        col,
                        format!("M{m:02} and M{other:02} are in the same modal group: give one"),
                    ));
                }
                m_seen[grp as usize] = Some((m, col));
                w.m.push((m, col));
                if m < 128 {
                    w.m_bits |= 1u128 << m;
                }
            }
            _ => {}
        }
        Ok(())
    }
}

/// A word of line `n` at `col` refused: the error, made out of line (cold).
#[cold]
#[inline(never)]
fn refused(n: u32, col: u32, message: std::fmt::Arguments) -> TranslateError {
    TranslateError {
        line: n,
        col,
        message: message.to_string(),
    }
}
