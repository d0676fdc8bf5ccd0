//! The tape reader (docs/tape.md, "Reading a tape"): it passes over the leader, takes the text
//! before the first end of block as the label, recognizes the code at that end of block, checks
//! the parity of every frame (and, if asked, that every block has an even number of
//! characters), and stops at the rewind stop that ends the program.
//!
//! `Decoder` is the state machine; `read_image` runs it over a whole image in one pass (one
//! table lookup a frame, no copy of the frames), and `Reader` feeds it a few frames at a time
//! for a console that shows the tape passing the read head.

use super::code::{
    Code, A_BLANK, A_CHAR, A_EOB, A_INVALID, A_LETTER, A_LOWER, A_RS, A_RUBOUT, A_SKIP, A_UPPER,
};
use super::error::{ErrorKind, TapeError};
use super::{ReadOptions, Tape};

/// The reader's state between frames.
#[derive(Clone, Debug)]
struct Decoder {
    opts: ReadOptions,
    code: Option<Code>,
    label: Vec<u8>,
    text: Vec<u8>,
    /// The block being read, 1-based (0 while in the label).
    block: u64,
    /// Characters of the current block (or label) so far.
    count: u64,
    /// EIA: letters are small letters (after LC, until UC or the end of block).
    lower: bool,
    /// A rewind stop has opened the program.
    start_seen: bool,
    /// Only an end of block may come next (after the opening rewind stop).
    expect_eob: bool,
    /// EIA: the first blank frame since the last character (frame, position), an error as
    /// soon as another character follows it (then it was inside the data, not trailer).
    blank_at: Option<(u64, u64)>,
    /// The closing rewind stop was read: later frames are not.
    stopped: bool,
    /// Frames examined.
    seen: u64,
}

impl Decoder {
    fn new(opts: ReadOptions) -> Decoder {
        Decoder {
            opts,
            code: None,
            label: Vec::new(),
            text: Vec::new(),
            block: 0,
            count: 0,
            lower: false,
            start_seen: false,
            expect_eob: false,
            blank_at: None,
            stopped: false,
            seen: 0,
        }
    }

    /// The error for frame `i` (0-based in the image) with the frame's own action.
    fn frame_error(&self, code: Code, i: u64, b: u8) -> TapeError {
        let kind = if code.parity_ok(super::Frame(b)) {
            ErrorKind::NotInCode
        } else {
            ErrorKind::Parity
        };
        TapeError::at(kind, i + 1, self.block, self.count + 1, b, Some(code))
    }

    /// The label: the frames before the first end of block (`label`, from frame 0), read in
    /// `code`, which that end of block (frame `label.len()`) revealed.
    fn start(&mut self, code: Code, label: &[u8]) -> Result<(), TapeError> {
        self.code = Some(code);
        let t = code.table();
        for (i, &b) in label.iter().enumerate() {
            let a = t.action[b as usize];
            match a {
                A_BLANK | A_RUBOUT => continue,
                A_INVALID => return Err(self.frame_error(code, i as u64, b)),
                A_SKIP => {}
                A_RS if !self.start_seen => self.start_seen = true,
                _ if self.start_seen => {
                    return Err(TapeError::at(
                        ErrorKind::AfterRewindStop,
                        i as u64 + 1,
                        0,
                        self.count + 1,
                        b,
                        Some(code),
                    ))
                }
                A_UPPER => self.lower = false,
                A_LOWER => self.lower = true,
                A_LETTER if self.lower => self.label.push(t.ch[b as usize] | 0x20),
                _ => self.label.push(t.ch[b as usize]),
            }
            self.count += 1;
        }
        self.block = 1;
        self.count = 0;
        self.lower = false;
        self.seen = label.len() as u64 + 1;
        Ok(())
    }

    /// Reads program frames (`frames[0]` is frame `base` of the image). Returns the index in
    /// `frames` of the closing rewind stop, if it came.
    fn program(&mut self, frames: &[u8], base: u64) -> Result<Option<usize>, TapeError> {
        let Some(code) = self.code else {
            return Ok(None);
        };
        if self.stopped {
            return Ok(Some(0));
        }
        let t = code.table();
        self.text.reserve(frames.len());
        let mut i = 0;
        while i < frames.len() {
            // The common case first: a run of characters of the text, copied in one go.
            if !self.expect_eob && self.blank_at.is_none() {
                let run = char_run(t, &frames[i..], self.lower);
                if run > 0 {
                    self.text
                        .extend(frames[i..i + run].iter().map(|&b| t.ch[b as usize]));
                    self.count += run as u64;
                    i += run;
                    continue;
                }
            }
            let b = frames[i];
            let a = t.action[b as usize];
            let at = base + i as u64;
            i += 1;
            // In EIA every character has a hole: a blank frame followed by anything but blank
            // tape (the trailer) or rub-outs is a character that lost its hole (docs/tape.md,
            // "Errors"). ISO passes NUL over anywhere.
            if let (Some((frame, position)), false) =
                (self.blank_at, matches!(a, A_BLANK | A_RUBOUT))
            {
                self.seen = at + 1;
                return Err(TapeError::at(
                    ErrorKind::BlankInData,
                    frame,
                    self.block,
                    position,
                    0,
                    Some(code),
                ));
            }
            match a {
                A_BLANK if code == Code::Eia => {
                    self.blank_at = Some((at + 1, self.count + 1));
                }
                A_BLANK | A_RUBOUT => {}
                A_INVALID => {
                    self.seen = at + 1;
                    return Err(self.frame_error(code, at, b));
                }
                A_SKIP => self.count += 1,
                A_EOB if self.expect_eob => {
                    self.expect_eob = false;
                    self.count = 0;
                    self.lower = false;
                }
                A_EOB => {
                    self.count += 1;
                    if self.opts.block_parity && self.count % 2 == 1 {
                        self.seen = at + 1;
                        return Err(TapeError::at(
                            ErrorKind::BlockParity,
                            at + 1,
                            self.block,
                            self.count,
                            b,
                            Some(code),
                        ));
                    }
                    self.text.push(b'\n');
                    self.block += 1;
                    self.count = 0;
                    self.lower = false;
                }
                A_RS if self.count > 0 || self.expect_eob => {
                    self.seen = at + 1;
                    return Err(TapeError::at(
                        ErrorKind::MissingEob,
                        at + 1,
                        self.block,
                        self.count + 1,
                        b,
                        Some(code),
                    ));
                }
                A_RS if !self.start_seen && self.block == 1 => {
                    self.start_seen = true;
                    self.expect_eob = true;
                }
                A_RS => {
                    self.stopped = true;
                    self.seen = at + 1;
                    return Ok(Some(i - 1));
                }
                _ if self.expect_eob => {
                    self.seen = at + 1;
                    return Err(TapeError::at(
                        ErrorKind::AfterRewindStop,
                        at + 1,
                        self.block,
                        1,
                        b,
                        Some(code),
                    ));
                }
                A_UPPER => {
                    self.lower = false;
                    self.count += 1;
                }
                A_LOWER => {
                    self.lower = true;
                    self.count += 1;
                }
                A_LETTER => {
                    let c = t.ch[b as usize];
                    self.text.push(if self.lower { c | 0x20 } else { c });
                    self.count += 1;
                }
                _ => {
                    // A_CHAR: the runs above take them; this arm is for completeness.
                    self.text.push(t.ch[b as usize]);
                    self.count += 1;
                }
            }
        }
        self.seen = base + frames.len() as u64;
        Ok(None)
    }

    /// The end of the tape (`seen` are the frames examined): the result, or why there is none.
    fn finish(self, seen: &[u8]) -> Result<Tape, TapeError> {
        let Some(code) = self.code else {
            return Err(if seen.is_empty() {
                TapeError::at(ErrorKind::Empty, 0, 0, 0, 0, None)
            } else {
                TapeError::at(ErrorKind::NoEob, seen.len() as u64, 0, 0, 0, None)
            });
        };
        if !self.stopped && (self.count > 0 || self.expect_eob) {
            // The last frame that is not blank or rubbed out.
            let t = code.table();
            let last = seen
                .iter()
                .rposition(|&b| !matches!(t.action[b as usize], A_BLANK | A_RUBOUT))
                .unwrap_or(0);
            return Err(TapeError::at(
                ErrorKind::MissingEob,
                last as u64 + 1,
                self.block,
                self.count.max(1),
                seen.get(last).copied().unwrap_or(0),
                Some(code),
            ));
        }
        Ok(Tape {
            code: Some(code),
            label: ascii(self.label),
            text: ascii(self.text),
            blocks: self.block.saturating_sub(1),
            frames: self.seen,
        })
    }
}

/// How many frames at the start of `frames` are characters of the text that decode as the
/// table has them: `A_CHAR`, and `A_LETTER` unless EIA's lower case is on.
fn char_run(t: &super::code::Table, frames: &[u8], lower: bool) -> usize {
    let last = if lower { A_CHAR } else { A_LETTER };
    frames
        .iter()
        .position(|&b| {
            let a = t.action[b as usize];
            a == A_INVALID || a > last
        })
        .unwrap_or(frames.len())
}

/// Text the tables produced (ASCII only) as a `String`.
fn ascii(v: Vec<u8>) -> String {
    String::from_utf8(v).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The first end of block in `frames`, in either code: ISO LF (0x0A) or EIA channel 8 (0x80).
/// Each is a parity error in the other code, so the first one found decides.
fn first_eob(frames: &[u8]) -> Option<(usize, Code)> {
    let i = frames.iter().position(|&b| b == 0x0A || b == 0x80)?;
    Some((
        i,
        if frames[i] == 0x0A {
            Code::Iso
        } else {
            Code::Eia
        },
    ))
}

/// Decodes a whole tape image (not a plain text file: see `super::read_image`).
pub(crate) fn decode(image: &[u8], opts: ReadOptions) -> Result<Tape, TapeError> {
    let mut d = Decoder::new(opts);
    let Some((eob, code)) = first_eob(image) else {
        return d.finish(image);
    };
    d.start(code, &image[..eob])?;
    let rest = &image[eob + 1..];
    let end = match d.program(rest, eob as u64 + 1)? {
        Some(i) => eob + 1 + i + 1,
        None => image.len(),
    };
    d.finish(&image[..end])
}

/// An incremental tape reader, for a console that shows the tape passing under the read head
/// at a given speed: feed it frames as they pass (one or a chunk at a time); it exposes the
/// frames seen so far, the code once recognized, the label, the text decoded so far, and the
/// block and character it is at. Only `finish` gives the result, and only if the whole tape
/// read without error (docs/tape.md: nothing partial is stored).
#[derive(Clone, Debug)]
pub struct Reader {
    dec: Decoder,
    frames: Vec<u8>,
    error: Option<TapeError>,
}

impl Reader {
    /// A reader at the start of a tape.
    pub fn new(opts: ReadOptions) -> Reader {
        Reader {
            dec: Decoder::new(opts),
            frames: Vec::new(),
            error: None,
        }
    }

    /// Reads the next frames. Returns whether the reader has stopped at the closing rewind stop
    /// (later frames are then not read, and not added to `frames`), or the error that stopped
    /// it (every later call returns it again).
    pub fn feed(&mut self, chunk: &[u8]) -> Result<bool, TapeError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        if self.dec.stopped {
            return Ok(true);
        }
        let r = self.feed_inner(chunk);
        if let Err(e) = &r {
            self.error = Some(e.clone());
        }
        r
    }

    fn feed_inner(&mut self, chunk: &[u8]) -> Result<bool, TapeError> {
        let mut chunk = chunk;
        if self.dec.code.is_none() {
            let Some((j, code)) = first_eob(chunk) else {
                self.frames.extend_from_slice(chunk);
                self.dec.seen = self.frames.len() as u64;
                return Ok(false);
            };
            self.frames.extend_from_slice(&chunk[..=j]);
            let label_end = self.frames.len() - 1;
            let label = std::mem::take(&mut self.frames);
            let r = self.dec.start(code, &label[..label_end]);
            self.frames = label;
            r?;
            chunk = &chunk[j + 1..];
        }
        let base = self.frames.len() as u64;
        match self.dec.program(chunk, base) {
            Ok(Some(i)) => {
                self.frames.extend_from_slice(&chunk[..=i]);
                Ok(true)
            }
            Ok(None) => {
                self.frames.extend_from_slice(chunk);
                Ok(false)
            }
            Err(e) => {
                let upto = (e.frame.saturating_sub(base) as usize).min(chunk.len());
                self.frames.extend_from_slice(&chunk[..upto]);
                Err(e)
            }
        }
    }

    /// The frames read so far (the last one is under the read head).
    pub fn frames(&self) -> &[u8] {
        &self.frames
    }

    /// The code, once recognized (at the first end of block).
    pub fn code(&self) -> Option<Code> {
        self.dec.code
    }

    /// The label, once the first end of block has been read.
    pub fn label(&self) -> Option<&str> {
        self.dec
            .code
            .map(|_| std::str::from_utf8(&self.dec.label).unwrap_or(""))
    }

    /// The text decoded so far, the block being read included (for display only).
    pub fn text(&self) -> &str {
        std::str::from_utf8(&self.dec.text).unwrap_or("")
    }

    /// The block being read, 1-based (0 while in the label).
    pub fn block(&self) -> u64 {
        self.dec.block
    }

    /// Characters read so far in the current block (or the label).
    pub fn position(&self) -> u64 {
        self.dec.count
    }

    /// Whether the closing rewind stop has been read.
    pub fn is_stopped(&self) -> bool {
        self.dec.stopped
    }

    /// The error that stopped the read, if one did.
    pub fn error(&self) -> Option<&TapeError> {
        self.error.as_ref()
    }

    /// The end of the tape: the whole result, or the error (the first one, if a feed failed).
    pub fn finish(self) -> Result<Tape, TapeError> {
        if let Some(e) = self.error {
            return Err(e);
        }
        self.dec.finish(&self.frames)
    }
}
