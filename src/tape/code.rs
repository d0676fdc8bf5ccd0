//! The two tape codes (docs/tape.md, "The codes"): ISO 840 (ISO 646 with even parity in
//! channel 8) and EIA RS-244 (odd parity in channel 5, end of block in channel 8 alone), as
//! 256-entry tables built at compile time, so that decoding a frame is one lookup.
//!
//! A frame is one byte: channel n is bit n − 1.

use std::fmt;

/// One frame of 8-channel tape: channel n punched when bit n − 1 is set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Frame(pub u8);

impl Frame {
    /// Whether channel `ch` (1–8) is punched.
    pub fn has(self, ch: u8) -> bool {
        (1..=8).contains(&ch) && self.0 & (1 << (ch - 1)) != 0
    }

    /// How many holes the frame has.
    pub fn holes(self) -> u32 {
        self.0.count_ones()
    }

    /// The punched channels, ascending, as `1 3 6 8` (`blank` for none).
    pub fn channels(self) -> String {
        let chs: Vec<String> = (1..=8)
            .filter(|&c| self.has(c))
            .map(|c| c.to_string())
            .collect();
        if chs.is_empty() {
            "blank".to_string()
        } else {
            chs.join(" ")
        }
    }

    /// The frame drawn as a row of tape, channel 8 on the left, the sprocket hole between
    /// channels 4 and 3: `●·●··•●·●` (`●` hole, `·` none, `•` sprocket).
    pub fn row(self) -> String {
        let mut s = String::with_capacity(9 * 3);
        for ch in (1..=8).rev() {
            s.push(if self.has(ch) { '●' } else { '·' });
            if ch == 4 {
                s.push('•');
            }
        }
        s
    }
}

impl fmt::Display for Frame {
    /// `holes 1 3 6 8 (●·●··•●·●)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "holes {} ({})", self.channels(), self.row())
    }
}

/// A tape code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Code {
    /// ISO 840: ISO 646 characters, even parity in channel 8, end of block LF.
    Iso,
    /// EIA RS-244: odd parity in channel 5, end of block channel 8 alone.
    Eia,
}

impl Code {
    /// The name the operator sees: `ISO` or `EIA`.
    pub fn name(self) -> &'static str {
        match self {
            Code::Iso => "ISO",
            Code::Eia => "EIA",
        }
    }

    /// The code for a name (`iso`, `ISO`, `eia`, `EIA`).
    pub fn from_name(s: &str) -> Option<Code> {
        match s.to_ascii_lowercase().as_str() {
            "iso" => Some(Code::Iso),
            "eia" => Some(Code::Eia),
            _ => None,
        }
    }

    /// Whether a frame has this code's parity (ISO: an even number of holes; EIA: odd).
    pub fn parity_ok(self, f: Frame) -> bool {
        match self {
            Code::Iso => f.holes().is_multiple_of(2),
            Code::Eia => f.holes() % 2 == 1,
        }
    }

    /// What a frame means in this code.
    pub fn meaning(self, f: Frame) -> Meaning {
        let t = self.table();
        let c = t.ch[f.0 as usize];
        match t.action[f.0 as usize] {
            A_CHAR | A_LETTER => Meaning::Char(c as char),
            A_BLANK => Meaning::Blank,
            A_RUBOUT => Meaning::RubOut,
            A_SKIP => Meaning::PassedOver(if c == b'\r' { "CR" } else { "BS" }),
            A_EOB => Meaning::EndOfBlock,
            A_RS => Meaning::RewindStop,
            A_UPPER => Meaning::UpperCase,
            A_LOWER => Meaning::LowerCase,
            _ if !self.parity_ok(f) => Meaning::ParityError,
            _ => Meaning::NotInCode,
        }
    }

    /// The frame that punches `c` in this code (for EIA, a letter's case is carried by the
    /// case shifts, see `punch`); `None` if the code has no such character.
    pub fn frame_of(self, c: char) -> Option<Frame> {
        if !c.is_ascii() {
            return None;
        }
        let f = match self {
            Code::Iso => ISO_ENCODE[c as usize],
            Code::Eia => EIA_ENCODE[c as usize],
        };
        (f != NONE).then_some(Frame(f))
    }

    /// The end-of-block frame: ISO LF, EIA channel 8.
    pub fn eob(self) -> Frame {
        match self {
            Code::Iso => Frame(0x0A),
            Code::Eia => Frame(0x80),
        }
    }

    /// The rewind-stop frame: ISO `%`, EIA ER.
    pub fn rewind_stop(self) -> Frame {
        match self {
            Code::Iso => Frame(0xA5),
            Code::Eia => Frame(EIA_ER),
        }
    }

    /// The frame the punch adds to a block with an odd number of characters, which the reader
    /// passes over but counts (docs/tape.md, "Block parity"): ISO CR, EIA BS.
    pub fn pad(self) -> Frame {
        match self {
            Code::Iso => Frame(0x8D),
            Code::Eia => Frame(EIA_BS),
        }
    }

    /// EIA's case shifts (upper, lower); `None` for ISO, which has both cases.
    pub fn case_shifts(self) -> Option<(Frame, Frame)> {
        match self {
            Code::Iso => None,
            Code::Eia => Some((Frame(EIA_UC), Frame(EIA_LC))),
        }
    }

    /// The decoding table.
    pub(crate) fn table(self) -> &'static Table {
        match self {
            Code::Iso => &ISO_TABLE,
            Code::Eia => &EIA_TABLE,
        }
    }
}

/// What one frame is in a code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Meaning {
    /// No holes: leader, trailer, tape feed. Passed over.
    Blank,
    /// The all-holes frame, a punched-over error (DEL, rub-out). Passed over.
    RubOut,
    /// A control the reader passes over but counts in the block (ISO CR, EIA BS).
    PassedOver(&'static str),
    /// End of block.
    EndOfBlock,
    /// The rewind stop (ISO `%`, EIA ER).
    RewindStop,
    /// EIA upper case: letters after it are capitals (until lower case or the end of block).
    UpperCase,
    /// EIA lower case: letters after it are small letters (until upper case or the end of
    /// block).
    LowerCase,
    /// A character of the text (an EIA letter as a capital; its case is the shift's).
    Char(char),
    /// The frame has the wrong parity for the code.
    ParityError,
    /// The parity is right but the code has no such character.
    NotInCode,
}

// Frame actions in the decoding tables.
pub(crate) const A_INVALID: u8 = 0;
pub(crate) const A_CHAR: u8 = 1;
pub(crate) const A_LETTER: u8 = 2;
pub(crate) const A_BLANK: u8 = 3;
pub(crate) const A_RUBOUT: u8 = 4;
pub(crate) const A_SKIP: u8 = 5;
pub(crate) const A_EOB: u8 = 6;
pub(crate) const A_RS: u8 = 7;
pub(crate) const A_UPPER: u8 = 8;
pub(crate) const A_LOWER: u8 = 9;

/// A decoding table: for every frame, its action and its ASCII character.
pub(crate) struct Table {
    /// What the reader does with the frame (`A_*`); `A_INVALID` for a parity error or a
    /// character the code lacks.
    pub action: [u8; 256],
    /// The character of an `A_CHAR`/`A_LETTER`/`A_SKIP` frame.
    pub ch: [u8; 256],
}

/// "No frame" in the encoding tables (a blank frame is never a character).
const NONE: u8 = 0;

/// Channels to a frame byte, at compile time.
const fn ch(list: &[u8]) -> u8 {
    let mut v = 0u8;
    let mut i = 0;
    while i < list.len() {
        v |= 1 << (list[i] - 1);
        i += 1;
    }
    v
}

/// EIA end of record (rewind stop): channels 3, 4, 6 (docs/tape.md: not checked against the
/// standard's text; '%''s card code 0-8-4, mapped as RS-244 maps its own characters).
const EIA_ER: u8 = ch(&[3, 4, 6]);
/// EIA backspace: channels 2, 4, 6.
const EIA_BS: u8 = ch(&[2, 4, 6]);
/// EIA upper case: channels 3, 4, 5, 6, 7.
const EIA_UC: u8 = ch(&[3, 4, 5, 6, 7]);
/// EIA lower case: channels 2, 3, 4, 6, 7.
const EIA_LC: u8 = ch(&[2, 3, 4, 6, 7]);

/// The EIA characters of the text, as (character, frame): RS-244's digits, letters and
/// signs, then novanc's additions (docs/tape.md lists where each comes from). Three odd
/// patterns of channels 1–7 stay free: "not in the code".
pub const EIA_CHARS: [(char, u8); 56] = [
    ('0', ch(&[6])),
    ('1', ch(&[1])),
    ('2', ch(&[2])),
    ('3', ch(&[1, 2, 5])),
    ('4', ch(&[3])),
    ('5', ch(&[1, 3, 5])),
    ('6', ch(&[2, 3, 5])),
    ('7', ch(&[1, 2, 3])),
    ('8', ch(&[4])),
    ('9', ch(&[1, 4, 5])),
    ('A', ch(&[1, 6, 7])),
    ('B', ch(&[2, 6, 7])),
    ('C', ch(&[1, 2, 5, 6, 7])),
    ('D', ch(&[3, 6, 7])),
    ('E', ch(&[1, 3, 5, 6, 7])),
    ('F', ch(&[2, 3, 5, 6, 7])),
    ('G', ch(&[1, 2, 3, 6, 7])),
    ('H', ch(&[4, 6, 7])),
    ('I', ch(&[1, 4, 5, 6, 7])),
    ('J', ch(&[1, 5, 7])),
    ('K', ch(&[2, 5, 7])),
    ('L', ch(&[1, 2, 7])),
    ('M', ch(&[3, 5, 7])),
    ('N', ch(&[1, 3, 7])),
    ('O', ch(&[2, 3, 7])),
    ('P', ch(&[1, 2, 3, 5, 7])),
    ('Q', ch(&[4, 5, 7])),
    ('R', ch(&[1, 4, 7])),
    ('S', ch(&[2, 5, 6])),
    ('T', ch(&[1, 2, 6])),
    ('U', ch(&[3, 5, 6])),
    ('V', ch(&[1, 3, 6])),
    ('W', ch(&[2, 3, 6])),
    ('X', ch(&[1, 2, 3, 5, 6])),
    ('Y', ch(&[4, 5, 6])),
    ('Z', ch(&[1, 4, 6])),
    (' ', ch(&[5])),
    ('-', ch(&[7])),
    ('+', ch(&[5, 6, 7])),
    ('/', ch(&[1, 5, 6])),
    ('.', ch(&[1, 2, 4, 6, 7])),
    (',', ch(&[1, 2, 4, 5, 6])),
    ('\t', ch(&[2, 3, 4, 5, 6])),
    // Control out / control in of EIA readers (Fanuc, Yaskawa: "2-4-5" and "2-4-7").
    ('(', ch(&[2, 4, 5])),
    (')', ch(&[2, 4, 7])),
    // novanc additions: the IBM card code of the character, mapped to channels as RS-244
    // maps its own signs (zone 12 → 7 6, zone 11 → 7, zone 0 → 6, rows 1–9 and 8 → binary
    // in channels 1–4, parity in 5).
    ('$', ch(&[1, 2, 4, 5, 7])),
    ('*', ch(&[3, 4, 7])),
    (';', ch(&[2, 3, 4, 5, 7])),
    ('_', ch(&[1, 3, 4, 5, 6])),
    ('?', ch(&[1, 2, 3, 4, 6])),
    ('#', ch(&[1, 2, 4])),
    ('@', ch(&[3, 4, 5])),
    ('\'', ch(&[1, 3, 4])),
    ('=', ch(&[2, 3, 4])),
    ('"', ch(&[1, 2, 3, 4, 5])),
    // novanc's choice (the card code 8-2 is taken by '('): 12-8-2.
    (':', ch(&[2, 4, 5, 6, 7])),
];

const fn iso_table() -> Table {
    let mut t = Table {
        action: [A_INVALID; 256],
        ch: [0; 256],
    };
    let mut b = 0usize;
    while b < 256 {
        let byte = b as u8;
        if byte.count_ones().is_multiple_of(2) {
            let c = byte & 0x7F;
            t.ch[b] = c;
            t.action[b] = match c {
                0x00 => A_BLANK,
                0x7F => A_RUBOUT,
                0x0A => A_EOB,
                b'%' => A_RS,
                0x0D | 0x08 => A_SKIP,
                0x09 | 0x20..=0x7E => A_CHAR,
                _ => A_INVALID,
            };
        }
        b += 1;
    }
    t
}

const fn eia_table() -> Table {
    let mut t = Table {
        action: [A_INVALID; 256],
        ch: [0; 256],
    };
    t.action[0x00] = A_BLANK;
    t.action[0x7F] = A_RUBOUT;
    // All eight holes: a rub-out too, although its parity is even (docs/tape.md).
    t.action[0xFF] = A_RUBOUT;
    t.action[0x80] = A_EOB;
    t.action[EIA_ER as usize] = A_RS;
    t.action[EIA_BS as usize] = A_SKIP;
    t.ch[EIA_BS as usize] = 0x08;
    t.action[EIA_UC as usize] = A_UPPER;
    t.action[EIA_LC as usize] = A_LOWER;
    let mut i = 0;
    while i < EIA_CHARS.len() {
        let (c, f) = EIA_CHARS[i];
        t.ch[f as usize] = c as u8;
        t.action[f as usize] = if c.is_ascii_uppercase() {
            A_LETTER
        } else {
            A_CHAR
        };
        i += 1;
    }
    t
}

const fn iso_encode() -> [u8; 128] {
    let mut e = [NONE; 128];
    let mut c = 0usize;
    while c < 128 {
        let byte = c as u8;
        let ok = matches!(byte, 0x09 | 0x20..=0x7E) && byte != b'%';
        if ok {
            e[c] = if byte.count_ones() % 2 == 1 {
                byte | 0x80
            } else {
                byte
            };
        }
        c += 1;
    }
    e
}

const fn eia_encode() -> [u8; 128] {
    let mut e = [NONE; 128];
    let mut i = 0;
    while i < EIA_CHARS.len() {
        let (c, f) = EIA_CHARS[i];
        e[c as usize] = f;
        if (c as u8).is_ascii_uppercase() {
            e[(c as u8).to_ascii_lowercase() as usize] = f;
        }
        i += 1;
    }
    e
}

static ISO_TABLE: Table = iso_table();
static EIA_TABLE: Table = eia_table();
static ISO_ENCODE: [u8; 128] = iso_encode();
static EIA_ENCODE: [u8; 128] = eia_encode();

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_eia_character_has_odd_parity_and_its_own_frame() {
        let mut seen = std::collections::HashSet::new();
        let specials = [0x80, EIA_ER, EIA_BS, EIA_UC, EIA_LC, 0x7F];
        for (c, f) in EIA_CHARS.iter() {
            assert_eq!(f.count_ones() % 2, 1, "{c:?}");
            assert!(seen.insert(*f), "{c:?} shares frame {f:#04x}");
            assert!(!specials.contains(f), "{c:?}");
        }
        for f in specials {
            assert_eq!(f.count_ones() % 2, 1, "{f:#04x}");
            assert!(seen.insert(f), "{f:#04x}");
        }
        // 64 odd patterns of channels 1–7, plus EOB in channel 8; three left free.
        assert_eq!(seen.len(), 64 - 3 + 1);
    }

    #[test]
    fn iso_is_ascii_with_even_parity_in_channel_8() {
        assert_eq!(Code::Iso.frame_of('A'), Some(Frame(0x41)));
        assert_eq!(Code::Iso.frame_of('C'), Some(Frame(0xC3)));
        assert_eq!(Code::Iso.frame_of('%'), None);
        assert_eq!(Code::Iso.rewind_stop(), Frame(0xA5));
        assert_eq!(Code::Iso.meaning(Frame(0xC3)), Meaning::Char('C'));
        assert_eq!(Code::Iso.meaning(Frame(0x43)), Meaning::ParityError);
        assert_eq!(Code::Iso.meaning(Frame(0x81)), Meaning::NotInCode);
        assert_eq!(Code::Iso.meaning(Frame(0xFF)), Meaning::RubOut);
        assert_eq!(Code::Iso.meaning(Frame(0x00)), Meaning::Blank);
        assert_eq!(Code::Iso.meaning(Frame(0x8D)), Meaning::PassedOver("CR"));
    }

    #[test]
    fn eia_letters_are_single_case_and_decode_as_capitals() {
        assert_eq!(Code::Eia.frame_of('g'), Code::Eia.frame_of('G'));
        assert_eq!(Code::Eia.meaning(Frame(0x67)), Meaning::Char('G'));
        assert_eq!(Code::Eia.meaning(Frame(0x80)), Meaning::EndOfBlock);
        assert_eq!(Code::Eia.meaning(Frame(0x0A)), Meaning::ParityError);
        assert_eq!(Code::Eia.meaning(Frame(0x4F)), Meaning::NotInCode);
        assert_eq!(Code::Eia.meaning(Frame(0xFF)), Meaning::RubOut);
        assert_eq!(Code::Eia.frame_of('%'), None);
        assert_eq!(Code::Eia.frame_of('§'), None);
    }

    #[test]
    fn frames_draw_channel_8_on_the_left_and_the_sprocket_between_4_and_3() {
        let f = Frame(0xA5);
        assert_eq!(f.channels(), "1 3 6 8");
        assert_eq!(f.row(), "●·●··•●·●");
        assert_eq!(Frame(0).channels(), "blank");
        assert_eq!(f.to_string(), "holes 1 3 6 8 (●·●··•●·●)");
    }
}
