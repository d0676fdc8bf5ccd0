//! Sorting a read line's words (docs/gcode.md "Words"): G and M codes by modal group, one
//! value per other letter; unknown letters and codes, a letter twice and two codes of one modal
//! group are refused.

use super::expr::{Line, Word};
use crate::block::TranslateError;

/// The letters a mill line may hold, besides G and M.
const LETTERS: &str = "DFHIJKLNPQRSTXYZ";

/// What one G-code dialect accepts: its letters and its G and M codes by modal group. The mill
/// reader uses [`MILL`]; the lathe reader (docs/lathe-gcode.md) has its own.
#[derive(Clone, Copy, Debug)]
pub struct Dialect {
    /// The letters a line may hold, besides G and M.
    pub letters: &'static str,
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
    g_group,
    m_group,
    g_why: mill_g_why,
    letter_hint: " (novanc has the axes X, Y and Z)",
};

fn mill_g_why(g: u32) -> &'static str {
    match g {
        920..=923 => " (G92 offsets are not supported: use G54–G59 with G10)",
        930 => " (inverse-time feed is not supported: G94 only)",
        870 | 880 => " (G87 and G88 are not supported)",
        _ => "",
    }
}

/// A short list of codes with their columns (one per modal group at most).
#[derive(Clone, Copy, Debug, Default)]
pub struct Codes {
    v: [(u32, u32); 13],
    n: usize,
}

impl Codes {
    fn push(&mut self, c: (u32, u32)) {
        if self.n < self.v.len() {
            self.v[self.n] = c;
            self.n += 1;
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

/// The words of one line sorted out: G and M codes, one value per other letter.
#[derive(Clone, Debug, Default)]
pub struct Words {
    /// G codes ×10 (G04 = 40, G43.1 = 431) with columns.
    pub g: Codes,
    /// M codes with columns.
    pub m: Codes,
    vals: [Option<(f64, u32)>; 26],
    /// Bit g/10 for each whole G code, bit m for each M code below 128.
    g_bits: u128,
    m_bits: u128,
}

impl Words {
    /// The value of a letter's word, if given.
    pub fn get(&self, c: char) -> Option<f64> {
        self.vals[(c as u8 - b'A') as usize].map(|v| v.0)
    }

    /// The column of a letter's word, if given.
    pub fn col(&self, c: char) -> Option<u32> {
        self.vals[(c as u8 - b'A') as usize].map(|v| v.1)
    }

    /// Whether a G code (×10) is on the line, and its column.
    #[inline]
    pub fn has_g(&self, g: u32) -> Option<u32> {
        if g.is_multiple_of(10) && g < 1280 && self.g_bits & (1u128 << (g / 10)) == 0 {
            return None;
        }
        self.g.iter().find(|x| x.0 == g).map(|x| x.1)
    }

    /// Whether an M code is on the line, and its column.
    #[inline]
    pub fn has_m(&self, m: u32) -> Option<u32> {
        if m < 128 && self.m_bits & (1u128 << m) == 0 {
            return None;
        }
        self.m.iter().find(|x| x.0 == m).map(|x| x.1)
    }

    /// Whether any of X, Y, Z is given.
    pub fn has_axis(&self) -> bool {
        ['X', 'Y', 'Z'].iter().any(|&c| self.get(c).is_some())
    }
}

/// The modal group of a G code (×10), or `None` for one novanc does not know.
fn g_group(g: u32) -> Option<u8> {
    Some(match g {
        0 | 10 | 20 | 30 | 730 | 800 | 810 | 820 | 830 | 840 | 850 | 860 | 890 => 1,
        170 | 180 | 190 => 2,
        900 | 910 => 3,
        940 => 5,
        200 | 210 => 6,
        400 | 410 | 420 => 7,
        430 | 490 => 8,
        980 | 990 => 10,
        540 | 550 | 560 | 570 | 580 | 590 => 12,
        40 | 100 | 280 | 530 => 0,
        _ => return None,
    })
}

/// The modal group of an M code, or `None` for one novanc does not know.
fn m_group(m: u32) -> Option<u8> {
    Some(match m {
        0 | 1 | 2 | 30 => 4,
        6 => 6,
        3..=5 => 7,
        8 | 9 => 8,
        98 | 99 => 10,
        _ => return None,
    })
}

/// Sorts a line's words, refusing unknown letters and codes, a letter twice, and two codes of
/// one modal group.
pub fn sort_words(line: &Line, n: u32) -> Result<Words, TranslateError> {
    sort_words_in(line, n, &MILL)
}

/// Sorts a line's words in a dialect (see [`sort_words`]).
pub fn sort_words_in(line: &Line, n: u32, d: &Dialect) -> Result<Words, TranslateError> {
    let err = |col: u32, message: String| TranslateError {
        line: n,
        col,
        message,
    };
    let mut w = Words::default();
    let mut g_seen: [Option<(u32, u32)>; 13] = [None; 13];
    let mut m_seen: [Option<(u32, u32)>; 11] = [None; 11];
    for &Word { letter, value, col } in &line.words {
        match letter {
            'G' => {
                let g10 = (value * 10.0).round();
                if (value * 10.0 - g10).abs() > 1e-6 || g10 < 0.0 {
                    return Err(err(
                        col,
                        format!("unknown code G{}", crate::input_text::short_number(value)),
                    ));
                }
                let g = g10 as u32;
                let name = if g.is_multiple_of(10) {
                    format!("G{:02}", g / 10)
                } else {
                    format!("G{}.{}", g / 10, g % 10)
                };
                let Some(grp) = (d.g_group)(g).filter(|&x| x < 13) else {
                    let why = (d.g_why)(g);
                    return Err(err(col, format!("unknown or unsupported code {name}{why}")));
                };
                if let Some((other, _)) = g_seen[grp as usize] {
                    let on = if other.is_multiple_of(10) {
                        format!("G{:02}", other / 10)
                    } else {
                        format!("G{}.{}", other / 10, other % 10)
                    };
                    return Err(err(
                        col,
                        format!("{name} and {on} are in the same modal group: give one"),
                    ));
                }
                g_seen[grp as usize] = Some((g, col));
                w.g.push((g, col));
                if g.is_multiple_of(10) && g < 1280 {
                    w.g_bits |= 1u128 << (g / 10);
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
                let Some(grp) = (d.m_group)(m).filter(|&x| x < 11) else {
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
            c if d.letters.as_bytes().contains(&(c as u8)) => {
                let slot = &mut w.vals[(c as u8 - b'A') as usize];
                if slot.is_some() {
                    return Err(err(col, format!("two {c} words on one line")));
                }
                *slot = Some((value, col));
            }
            c => return Err(err(col, format!("unknown word {c}{}", d.letter_hint))),
        }
    }
    Ok(w)
}
