//! Key decoding: the bytes a terminal sends (UTF-8 text, control characters, ESC sequences of
//! xterm/VT220 style) turned into keys. An ESC alone is only known to be the Esc key once no
//! more bytes follow (`Decoder::flush`, called when input goes quiet).

/// One key press.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// A printable character.
    Char(char),
    /// Enter / Return.
    Enter,
    /// Backspace / Delete-left.
    Backspace,
    /// Tab.
    Tab,
    /// Esc alone.
    Esc,
    /// Arrow up.
    Up,
    /// Arrow down.
    Down,
    /// Arrow left.
    Left,
    /// Arrow right.
    Right,
    /// Page Up.
    PageUp,
    /// Page Down.
    PageDown,
    /// Home.
    Home,
    /// End.
    End,
    /// Insert.
    Insert,
    /// Delete (forward).
    Delete,
    /// Function key F1..F12.
    F(u8),
    /// Alt (Meta) with a character: ESC then the character.
    Alt(char),
    /// Control with a letter (lower case): Ctrl-A is `Ctrl('a')`.
    Ctrl(char),
    /// A sequence this decoder does not know.
    Unknown,
}

/// Turns terminal input bytes into keys, keeping an incomplete sequence for the next read.
#[derive(Debug, Default)]
pub struct Decoder {
    pending: Vec<u8>,
}

impl Decoder {
    /// A decoder with nothing pending.
    pub fn new() -> Decoder {
        Decoder::default()
    }

    /// Decodes `bytes` (after anything pending); an incomplete sequence at the end is kept.
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<Key> {
        self.pending.extend_from_slice(bytes);
        let mut keys = Vec::new();
        let mut i = 0;
        while i < self.pending.len() {
            match decode(&self.pending[i..]) {
                Some((k, n)) => {
                    keys.push(k);
                    i += n;
                }
                None => break,
            }
        }
        self.pending.drain(..i);
        keys
    }

    /// Input went quiet: whatever is pending is complete (a lone ESC is the Esc key).
    pub fn flush(&mut self) -> Vec<Key> {
        let mut keys = Vec::new();
        let rest = std::mem::take(&mut self.pending);
        let mut i = 0;
        while i < rest.len() {
            match decode(&rest[i..]) {
                Some((k, n)) => {
                    keys.push(k);
                    i += n;
                }
                None => {
                    keys.push(if rest[i] == 0x1b {
                        Key::Esc
                    } else {
                        Key::Unknown
                    });
                    i += 1;
                }
            }
        }
        keys
    }
}

/// Decodes one key from the start of `b`: the key and the bytes it used, or None if `b`
/// is an incomplete sequence.
fn decode(b: &[u8]) -> Option<(Key, usize)> {
    let first = *b.first()?;
    match first {
        0x1b => decode_escape(b),
        b'\r' | b'\n' => Some((Key::Enter, 1)),
        0x7f | 0x08 => Some((Key::Backspace, 1)),
        b'\t' => Some((Key::Tab, 1)),
        0x01..=0x1a => Some((Key::Ctrl((b'a' + first - 1) as char), 1)),
        0x00 | 0x1c..=0x1f => Some((Key::Unknown, 1)),
        _ => decode_utf8(b),
    }
}

/// One UTF-8 character.
fn decode_utf8(b: &[u8]) -> Option<(Key, usize)> {
    let n = match b[0] {
        0x00..=0x7f => 1,
        0xc0..=0xdf => 2,
        0xe0..=0xef => 3,
        0xf0..=0xf7 => 4,
        _ => return Some((Key::Unknown, 1)),
    };
    if b.len() < n {
        return None;
    }
    match std::str::from_utf8(&b[..n])
        .ok()
        .and_then(|s| s.chars().next())
    {
        Some(c) => Some((Key::Char(c), n)),
        None => Some((Key::Unknown, 1)),
    }
}

/// An ESC sequence: CSI (`ESC [`), SS3 (`ESC O`), or Alt with a character.
fn decode_escape(b: &[u8]) -> Option<(Key, usize)> {
    let second = *b.get(1)?;
    match second {
        b'[' => decode_csi(b),
        b'O' => {
            let third = *b.get(2)?;
            let k = final_letter(third).unwrap_or(Key::Unknown);
            Some((k, 3))
        }
        0x1b => Some((Key::Esc, 1)),
        0x20..=0x7e => Some((Key::Alt(second as char), 2)),
        b'\r' => Some((Key::Alt('\r'), 2)),
        _ => Some((Key::Esc, 1)),
    }
}

/// The key of a final letter shared by `ESC O x` (SS3) and `ESC [ params x` (CSI): arrows,
/// Home, End and F1–F4.
fn final_letter(c: u8) -> Option<Key> {
    Some(match c {
        b'A' => Key::Up,
        b'B' => Key::Down,
        b'C' => Key::Right,
        b'D' => Key::Left,
        b'H' => Key::Home,
        b'F' => Key::End,
        b'P' => Key::F(1),
        b'Q' => Key::F(2),
        b'R' => Key::F(3),
        b'S' => Key::F(4),
        _ => return None,
    })
}

/// `ESC [ params final`.
fn decode_csi(b: &[u8]) -> Option<(Key, usize)> {
    let mut i = 2;
    while i < b.len() && (0x30..=0x3f).contains(&b[i]) {
        i += 1;
    }
    let fin = *b.get(i)?;
    if i > 40 {
        return Some((Key::Unknown, i + 1));
    }
    let params = std::str::from_utf8(&b[2..i]).unwrap_or("");
    let first: u32 = params
        .split(';')
        .next()
        .and_then(|p| p.parse().ok())
        .unwrap_or(0);
    let k = match (final_letter(fin), fin) {
        (Some(k), _) => k,
        (None, b'~') => match first {
            1 | 7 => Key::Home,
            2 => Key::Insert,
            3 => Key::Delete,
            4 | 8 => Key::End,
            5 => Key::PageUp,
            6 => Key::PageDown,
            11..=15 => Key::F((first - 10) as u8),
            17..=21 => Key::F((first - 11) as u8),
            23 | 24 => Key::F((first - 12) as u8),
            _ => Key::Unknown,
        },
        _ => Key::Unknown,
    };
    Some((k, i + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_text_controls_and_sequences() {
        let mut d = Decoder::new();
        let keys = d.feed(b"a\xc3\xa9\r\x7f\x03\x1b[A\x1bOP\x1b[15~\x1b[24~\x1b[5~\x1b4");
        assert_eq!(
            keys,
            vec![
                Key::Char('a'),
                Key::Char('é'),
                Key::Enter,
                Key::Backspace,
                Key::Ctrl('c'),
                Key::Up,
                Key::F(1),
                Key::F(5),
                Key::F(12),
                Key::PageUp,
                Key::Alt('4'),
            ]
        );
    }

    #[test]
    fn keeps_an_incomplete_sequence_and_flushes_a_lone_escape() {
        let mut d = Decoder::new();
        assert_eq!(d.feed(b"\x1b[1"), vec![]);
        assert_eq!(d.feed(b"7~x"), vec![Key::F(6), Key::Char('x')]);
        assert_eq!(d.feed(b"\x1b"), vec![]);
        assert_eq!(d.flush(), vec![Key::Esc]);
        assert_eq!(d.feed(b"\x1b[1;3D"), vec![Key::Left]);
    }
}
