//! The text store under a buffer: characters addressed by position, with end-of-block counts.
//!
//! This is the simple version (a `Vec<char>`); positions are in characters.

use crate::EOB;

/// The characters of a buffer.
#[derive(Clone, Debug, Default)]
pub struct Text {
    chars: Vec<char>,
}

impl Text {
    /// A text holding `s`.
    pub fn from_str(s: &str) -> Text {
        Text {
            chars: s.chars().collect(),
        }
    }

    /// Length in characters.
    pub fn len(&self) -> usize {
        self.chars.len()
    }

    /// Number of end-of-block characters.
    pub fn eob_count(&self) -> usize {
        self.chars.iter().filter(|&&c| c == EOB).count()
    }

    /// Characters `start..end`, clamped.
    pub fn slice(&self, start: usize, end: usize) -> String {
        let end = end.min(self.len());
        let start = start.min(end);
        self.chars[start..end].iter().collect()
    }

    /// Inserts `s` at `pos` (clamped); returns the number of characters inserted.
    pub fn insert(&mut self, pos: usize, s: &str) -> usize {
        let pos = pos.min(self.len());
        let new: Vec<char> = s.chars().collect();
        let n = new.len();
        self.chars.splice(pos..pos, new);
        n
    }

    /// Removes characters `start..end` (clamped) and returns them.
    pub fn remove(&mut self, start: usize, end: usize) -> String {
        let end = end.min(self.len());
        let start = start.min(end);
        self.chars.drain(start..end).collect()
    }

    /// Start of the first occurrence of `pat` at or after `from`.
    pub fn find(&self, from: usize, pat: &str) -> Option<usize> {
        let pat: Vec<char> = pat.chars().collect();
        if pat.is_empty() || from > self.len() {
            return None;
        }
        (from..=self.len().saturating_sub(pat.len()))
            .find(|&i| i + pat.len() <= self.len() && self.chars[i..i + pat.len()] == pat[..])
    }

    /// Position just after the n-th EOB at or after `pos` (n ≥ 1), or the end.
    pub fn after_eobs(&self, pos: usize, n: usize) -> usize {
        let mut seen = 0;
        for i in pos.min(self.len())..self.len() {
            if self.chars[i] == EOB {
                seen += 1;
                if seen == n {
                    return i + 1;
                }
            }
        }
        self.len()
    }

    /// Start of the line holding `pos` (just after the last EOB before it).
    pub fn line_start_at(&self, pos: usize) -> usize {
        let pos = pos.min(self.len());
        match self.chars[..pos].iter().rposition(|&c| c == EOB) {
            Some(i) => i + 1,
            None => 0,
        }
    }

    /// Start of the n-th line before the line holding `pos` (n ≥ 0), stopping at 0.
    pub fn lines_back(&self, pos: usize, n: usize) -> usize {
        let line = self.line_of(pos);
        self.line_start(line.saturating_sub(n))
    }

    /// 0-based line index of `pos`: the number of EOBs before it.
    pub fn line_of(&self, pos: usize) -> usize {
        let pos = pos.min(self.len());
        self.chars[..pos].iter().filter(|&&c| c == EOB).count()
    }

    /// Position of the start of line `line` (just after its preceding EOB), or the end.
    pub fn line_start(&self, line: usize) -> usize {
        if line == 0 {
            return 0;
        }
        let mut seen = 0;
        for (i, &c) in self.chars.iter().enumerate() {
            if c == EOB {
                seen += 1;
                if seen == line {
                    return i + 1;
                }
            }
        }
        self.len()
    }
}
