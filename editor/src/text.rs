//! The text store under a buffer: a list of chunks of a few KiB, each knowing its character
//! and end-of-block counts, so that a position or a line number is found by skipping whole
//! chunks and an edit shifts at most one chunk (the patent's routines (ii) and (iii) shifted the
//! whole memory). Positions are in characters; the chunks hold UTF-8.

use crate::EOB;

/// A chunk is split in two when it grows beyond this many bytes.
#[cfg(not(test))]
const MAX: usize = 16 * 1024;
/// Size of the chunks a text is cut into.
#[cfg(not(test))]
const TARGET: usize = 8 * 1024;
/// A chunk smaller than this is merged with a neighbour when they fit together.
#[cfg(not(test))]
const MIN: usize = 2 * 1024;
/// Room added when a chunk must grow, so that typing does not reallocate on every character.
#[cfg(not(test))]
const SLACK: usize = 256;
/// Tiny chunks in unit tests, so that every test crosses chunk boundaries.
#[cfg(test)]
const MAX: usize = 16;
/// Tiny chunks in unit tests.
#[cfg(test)]
const TARGET: usize = 8;
/// Tiny chunks in unit tests.
#[cfg(test)]
const MIN: usize = 3;
/// Tiny chunks in unit tests.
#[cfg(test)]
const SLACK: usize = 4;
/// The EOB as a byte (it is ASCII).
const EOB_BYTE: u8 = EOB as u8;

/// A piece of the text with its counts.
#[derive(Clone, Debug, Default)]
struct Chunk {
    /// The characters.
    s: String,
    /// Number of characters in `s`.
    chars: usize,
    /// Number of EOBs in `s`.
    eobs: usize,
}

/// The first place `pat` occurs in `hay`, ASCII letters matching either case. A match starts
/// on a character boundary: the pattern's first byte is a whole ASCII character or a UTF-8
/// lead byte, never a continuation byte.
fn find_folded(hay: &[u8], pat: &[u8]) -> Option<usize> {
    let (&first, _) = pat.split_first()?;
    let last = hay.len().checked_sub(pat.len())?;
    // A letter matches in either case: b | 0x20 is its lower case, and no other byte maps
    // there. Any other first byte must match exactly.
    let (mask, want) = if first.is_ascii_alphabetic() {
        (0x20u8, first.to_ascii_lowercase())
    } else {
        (0, first)
    };
    let hit = |b: u8| (b | mask) == want;
    const LANES: usize = 32;
    let mut i = 0;
    while i <= last {
        let end = (i + LANES).min(last + 1);
        // Whole lanes are looked at without an early exit, so the compiler can use vectors.
        if hay[i..end].iter().fold(false, |acc, &b| acc | hit(b)) {
            for j in i..end {
                if hit(hay[j]) && hay[j..j + pat.len()].eq_ignore_ascii_case(pat) {
                    return Some(j);
                }
            }
        }
        i = end;
    }
    None
}

/// Number of EOBs in some bytes.
fn count_eobs(b: &[u8]) -> usize {
    b.iter().filter(|&&c| c == EOB_BYTE).count()
}

/// Number of characters in some UTF-8 bytes (the bytes that do not continue a character).
fn count_chars(b: &[u8]) -> usize {
    b.iter().filter(|&&c| (c & 0xC0) != 0x80).count()
}

impl Chunk {
    /// A chunk holding `s`, with its counts.
    fn new(s: String) -> Chunk {
        Chunk {
            chars: count_chars(s.as_bytes()),
            eobs: count_eobs(s.as_bytes()),
            s,
        }
    }

    /// Whether every character is one byte (then character and byte offsets agree).
    fn ascii(&self) -> bool {
        self.chars == self.s.len()
    }

    /// Byte offset of character `off` (the end if past it).
    fn byte_of(&self, off: usize) -> usize {
        self.byte_after(0, off)
    }

    /// Byte offset `n` characters after byte offset `b0` (the end if past it).
    fn byte_after(&self, b0: usize, n: usize) -> usize {
        if self.ascii() {
            return (b0 + n).min(self.s.len());
        }
        match self.s.get(b0..) {
            Some(rest) => rest
                .char_indices()
                .nth(n)
                .map_or(self.s.len(), |(b, _)| b0 + b),
            None => self.s.len(),
        }
    }

    /// Characters before byte offset `b`.
    fn chars_before(&self, b: usize) -> usize {
        if self.ascii() {
            b
        } else {
            count_chars(&self.s.as_bytes()[..b.min(self.s.len())])
        }
    }

    /// Byte offset just after the k-th EOB (1-based) of the chunk, or the end.
    fn after_eob(&self, k: usize) -> usize {
        let mut seen = 0;
        for (i, &c) in self.s.as_bytes().iter().enumerate() {
            if c == EOB_BYTE {
                seen += 1;
                if seen == k {
                    return i + 1;
                }
            }
        }
        self.s.len()
    }
}

/// Cuts `s` into chunks of about TARGET bytes, on character boundaries, without spare capacity.
fn pieces(s: &str) -> Vec<Chunk> {
    let count = s.len().div_ceil(TARGET).max(1);
    let size = s.len().div_ceil(count).max(1);
    let mut out = Vec::with_capacity(count);
    let mut start = 0;
    while start < s.len() {
        let mut end = (start + size).min(s.len());
        while !s.is_char_boundary(end) {
            end += 1;
        }
        out.push(Chunk::new(s[start..end].to_string()));
        start = end;
    }
    out
}

/// Where a character position falls: chunk index, offset in it, and counts before the chunk.
struct Place {
    /// Index of the chunk.
    chunk: usize,
    /// Character offset inside the chunk (may equal its length).
    off: usize,
    /// Characters before the chunk.
    chars_before: usize,
    /// EOBs before the chunk.
    eobs_before: usize,
}

/// The characters of a buffer.
#[derive(Clone, Debug, Default)]
pub struct Text {
    /// The chunks, in order; none is empty.
    chunks: Vec<Chunk>,
    /// Total characters.
    len: usize,
    /// Total EOBs.
    eobs: usize,
}

impl Text {
    /// A text holding `s`.
    pub fn from_str(s: &str) -> Text {
        let chunks = if s.is_empty() { Vec::new() } else { pieces(s) };
        Text {
            len: chunks.iter().map(|c| c.chars).sum(),
            eobs: chunks.iter().map(|c| c.eobs).sum(),
            chunks,
        }
    }

    /// Length in characters.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Number of end-of-block characters.
    pub fn eob_count(&self) -> usize {
        self.eobs
    }

    /// Bytes of memory held by the store (chunk text capacity plus the chunk list).
    pub fn heap_bytes(&self) -> usize {
        self.chunks.capacity() * std::mem::size_of::<Chunk>()
            + self.chunks.iter().map(|c| c.s.capacity()).sum::<usize>()
    }

    /// Finds the chunk holding character position `pos` (clamped); a position on a boundary
    /// falls at the end of the earlier chunk.
    fn locate(&self, pos: usize) -> Place {
        let mut place = Place {
            chunk: 0,
            off: 0,
            chars_before: 0,
            eobs_before: 0,
        };
        for (i, c) in self.chunks.iter().enumerate() {
            place.chunk = i;
            if pos <= place.chars_before + c.chars {
                place.off = pos - place.chars_before;
                return place;
            }
            if i + 1 < self.chunks.len() {
                place.chars_before += c.chars;
                place.eobs_before += c.eobs;
            } else {
                place.off = c.chars;
            }
        }
        place
    }

    /// The whole text in one shared allocation, copied once from the chunks (a long program
    /// handed to a translator thread at START).
    pub fn to_shared(&self) -> std::sync::Arc<str> {
        let total: usize = self.chunks.iter().map(|c| c.s.len()).sum();
        let mut bytes = std::sync::Arc::<[u8]>::new_uninit_slice(total);
        let Some(buf) = std::sync::Arc::get_mut(&mut bytes) else {
            return std::sync::Arc::from(self.slice(0, self.len));
        };
        let mut off = 0;
        for c in &self.chunks {
            for (dst, &b) in buf[off..off + c.s.len()].iter_mut().zip(c.s.as_bytes()) {
                dst.write(b);
            }
            off += c.s.len();
        }
        // SAFETY: every one of the `total` bytes was written just above.
        let bytes = unsafe { bytes.assume_init() };
        // SAFETY: the bytes are the chunks' strings one after the other, so valid UTF-8 (every
        // chunk holds whole characters); `str` and `[u8]` have the same layout.
        unsafe { std::sync::Arc::from_raw(std::sync::Arc::into_raw(bytes) as *const str) }
    }

    /// Characters `start..end`, clamped.
    pub fn slice(&self, start: usize, end: usize) -> String {
        let end = end.min(self.len);
        let start = start.min(end);
        if start == end {
            return String::new();
        }
        let place = self.locate(start);
        let mut out = String::with_capacity(end - start);
        let mut remaining = end - start;
        let mut off = place.off;
        for c in &self.chunks[place.chunk..] {
            if remaining == 0 {
                break;
            }
            let take = (c.chars - off).min(remaining);
            let b0 = c.byte_of(off);
            out.push_str(&c.s[b0..c.byte_after(b0, take)]);
            remaining -= take;
            off = 0;
        }
        out
    }

    /// Inserts `s` at `pos` (clamped); returns the number of characters inserted.
    pub fn insert(&mut self, pos: usize, s: &str) -> usize {
        if s.is_empty() {
            return 0;
        }
        let n = count_chars(s.as_bytes());
        let e = count_eobs(s.as_bytes());
        if self.chunks.is_empty() {
            self.chunks = pieces(s);
        } else {
            let place = self.locate(pos);
            let c = &mut self.chunks[place.chunk];
            let b = c.byte_of(place.off);
            if c.s.len() + s.len() <= MAX {
                if c.s.capacity() < c.s.len() + s.len() {
                    c.s.reserve_exact(s.len() + SLACK);
                }
                c.s.insert_str(b, s);
                c.chars += n;
                c.eobs += e;
            } else {
                let mut whole = String::with_capacity(c.s.len() + s.len());
                whole.push_str(&c.s[..b]);
                whole.push_str(s);
                whole.push_str(&c.s[b..]);
                self.chunks
                    .splice(place.chunk..=place.chunk, pieces(&whole));
            }
        }
        self.len += n;
        self.eobs += e;
        #[cfg(test)]
        self.check();
        n
    }

    /// Removes characters `start..end` (clamped) and returns them.
    pub fn remove(&mut self, start: usize, end: usize) -> String {
        let end = end.min(self.len);
        let start = start.min(end);
        if start == end {
            return String::new();
        }
        let place = self.locate(start);
        let mut out = String::new();
        let mut remaining = end - start;
        let mut off = place.off;
        let mut i = place.chunk;
        let mut emptied = false;
        while remaining > 0 && i < self.chunks.len() {
            let c = &mut self.chunks[i];
            let take = (c.chars - off).min(remaining);
            if take == c.chars {
                out.push_str(&c.s);
                *c = Chunk::default();
                emptied = true;
            } else if take > 0 {
                let b0 = c.byte_of(off);
                let b1 = c.byte_after(b0, take);
                let piece = &c.s[b0..b1];
                out.push_str(piece);
                c.eobs -= count_eobs(piece.as_bytes());
                c.chars -= take;
                c.s.replace_range(b0..b1, "");
            }
            remaining -= take;
            off = 0;
            i += 1;
        }
        if emptied {
            self.chunks.retain(|c| c.chars > 0);
        }
        self.len -= end - start;
        self.eobs -= count_eobs(out.as_bytes());
        self.tidy(place.chunk);
        #[cfg(test)]
        self.check();
        out
    }

    /// Keeps chunks near `i` from getting small or holding much spare room after a removal.
    fn tidy(&mut self, i: usize) {
        for j in [i.saturating_sub(1), i] {
            if j + 1 < self.chunks.len()
                && self.chunks[j].s.len() < MIN
                && self.chunks[j].s.len() + self.chunks[j + 1].s.len() <= MAX
            {
                let next = self.chunks.remove(j + 1);
                let c = &mut self.chunks[j];
                c.s.push_str(&next.s);
                c.chars += next.chars;
                c.eobs += next.eobs;
            }
            if let Some(c) = self.chunks.get_mut(j) {
                if c.s.capacity() > 2 * c.s.len() + SLACK {
                    c.s.shrink_to(c.s.len() + SLACK);
                }
            }
        }
    }

    /// Start of the first occurrence of `pat` at or after `from`, ASCII letters matching
    /// without regard to case (as TECO's search does by default; docs/editor.md).
    pub fn find(&self, from: usize, pat: &str) -> Option<usize> {
        if pat.is_empty() || from > self.len || self.chunks.is_empty() {
            return None;
        }
        let m = pat.len();
        let fold = pat.bytes().any(|b| b.is_ascii_alphabetic());
        // A one-character pattern is searched as a char (a fast byte scan).
        let mut it = pat.chars();
        let single = match (it.next(), it.next()) {
            (Some(ch), None) if !fold => Some(ch),
            _ => None,
        };
        let place = self.locate(from);
        let mut before = place.chars_before;
        let mut bo = self.chunks[place.chunk].byte_of(place.off);
        for ci in place.chunk..self.chunks.len() {
            let c = &self.chunks[ci];
            let hit = match single {
                Some(ch) => c.s[bo..].find(ch),
                None if fold => find_folded(&c.s.as_bytes()[bo..], pat.as_bytes()),
                None => c.s[bo..].find(pat),
            };
            if let Some(x) = hit {
                return Some(before + c.chars_before(bo + x));
            }
            // A match that starts near the end of this chunk and runs into the next ones.
            if m > 1 && ci + 1 < self.chunks.len() {
                let tail_start = bo.max(c.s.len().saturating_sub(m - 1));
                let mut window = c.s.as_bytes()[tail_start..].to_vec();
                let tail = window.len();
                for next in &self.chunks[ci + 1..] {
                    let need = tail + m - 1 - window.len();
                    if need == 0 {
                        break;
                    }
                    let nb = next.s.as_bytes();
                    window.extend_from_slice(&nb[..need.min(nb.len())]);
                }
                if let Some(x) = window
                    .windows(m)
                    .position(|w| w.eq_ignore_ascii_case(pat.as_bytes()))
                {
                    if x < tail {
                        return Some(before + c.chars_before(tail_start + x));
                    }
                }
            }
            before += c.chars;
            bo = 0;
        }
        None
    }

    /// 0-based line index of `pos`: the number of EOBs before it.
    pub fn line_of(&self, pos: usize) -> usize {
        if self.chunks.is_empty() {
            return 0;
        }
        let place = self.locate(pos);
        let c = &self.chunks[place.chunk];
        place.eobs_before + count_eobs(&c.s.as_bytes()[..c.byte_of(place.off)])
    }

    /// Position of the start of line `line` (just after its preceding EOB), or the end.
    pub fn line_start(&self, line: usize) -> usize {
        if line == 0 {
            return 0;
        }
        if line > self.eobs {
            return self.len;
        }
        let mut eobs = 0;
        let mut chars = 0;
        for c in &self.chunks {
            if eobs + c.eobs >= line {
                return chars + c.chars_before(c.after_eob(line - eobs));
            }
            eobs += c.eobs;
            chars += c.chars;
        }
        self.len
    }

    /// Position just after the n-th EOB at or after `pos` (n ≥ 1), or the end.
    pub fn after_eobs(&self, pos: usize, n: usize) -> usize {
        self.line_start(self.line_of(pos).saturating_add(n))
    }

    /// Start of the line holding `pos` (just after the last EOB before it).
    pub fn line_start_at(&self, pos: usize) -> usize {
        self.line_start(self.line_of(pos))
    }

    /// Start of the n-th line before the line holding `pos` (n ≥ 0), stopping at 0.
    pub fn lines_back(&self, pos: usize, n: usize) -> usize {
        self.line_start(self.line_of(pos).saturating_sub(n))
    }
}

#[cfg(test)]
impl Text {
    /// Panics if a count is wrong, a chunk is empty or too big.
    fn check(&self) {
        for c in &self.chunks {
            assert!(
                !c.s.is_empty() && c.s.len() <= MAX,
                "chunk size {}",
                c.s.len()
            );
            assert_eq!(c.chars, c.s.chars().count());
            assert_eq!(c.eobs, c.s.matches(EOB).count());
        }
        assert_eq!(self.len, self.chunks.iter().map(|c| c.chars).sum::<usize>());
        assert_eq!(self.eobs, self.chunks.iter().map(|c| c.eobs).sum::<usize>());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// splitmix64.
    fn next(state: &mut u64) -> usize {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as usize
    }

    fn random_text(state: &mut u64, max: usize) -> String {
        const A: &[char] = &['a', 'b', 'a', '\n', 'é', '€', 'x'];
        let n = next(state) % (max + 1);
        (0..n).map(|_| A[next(state) % A.len()]).collect()
    }

    #[test]
    fn the_shared_text_is_the_text() {
        let mut t = Text::from_str("héllo*wörld*\n");
        t.insert(3, "ABCDEFGHIJKLMNOPQRSTUVWXYZ ñ");
        assert_eq!(&*t.to_shared(), t.slice(0, t.len()).as_str());
        assert_eq!(&*Text::from_str("").to_shared(), "");
    }

    #[test]
    fn long_edits_and_searches_across_many_chunks_match_a_plain_string() {
        let mut st = 7u64;
        for _ in 0..300 {
            let init = random_text(&mut st, 200);
            let mut t = Text::from_str(&init);
            let mut m: Vec<char> = init.chars().collect();
            for _ in 0..20 {
                let len = m.len();
                let a = next(&mut st) % (len + 1);
                let b = a + next(&mut st) % (len + 1 - a);
                match next(&mut st) % 4 {
                    0 => {
                        let s = random_text(&mut st, 60);
                        assert_eq!(t.insert(a, &s), s.chars().count());
                        m.splice(a..a, s.chars());
                    }
                    1 => {
                        let want: String = m.drain(a..b).collect();
                        assert_eq!(t.remove(a, b), want);
                    }
                    2 => {
                        let pat: String = if b > a && !next(&mut st).is_multiple_of(3) {
                            m[a..b.min(a + 20)].iter().collect()
                        } else {
                            random_text(&mut st, 5)
                        };
                        let p: Vec<char> = pat.chars().collect();
                        let from = next(&mut st) % (len + 1);
                        let want = if p.is_empty() {
                            None
                        } else {
                            (from..len).find(|&i| i + p.len() <= len && m[i..i + p.len()] == p[..])
                        };
                        assert_eq!(t.find(from, &pat), want, "{pat:?} from {from}");
                    }
                    _ => {
                        let line = m[..a].iter().filter(|&&c| c == EOB).count();
                        assert_eq!(t.line_of(a), line);
                        assert_eq!(
                            t.line_start_at(a),
                            a - m[..a].iter().rev().take_while(|&&c| c != EOB).count()
                        );
                        assert_eq!(t.slice(a, b), m[a..b].iter().collect::<String>());
                    }
                }
                assert_eq!(t.slice(0, usize::MAX), m.iter().collect::<String>());
            }
        }
    }
}
