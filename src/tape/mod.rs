//! Tape reader 13 of the patent's panel (docs/tape.md): 8-channel punched tape images in the
//! ISO 840 and EIA RS-244 codes, with parity, as a pure library (no I/O): the codes, the reader
//! (whole images, or incrementally for a console that shows the tape passing), and the punch.
//!
//! A tape image is a file of frames, one byte per frame: channel n is bit n − 1.

mod code;
mod error;
mod punch;
mod reader;

pub use code::{Code, Frame, Meaning, EIA_CHARS};
pub use error::{ErrorKind, TapeError};
pub use punch::{draw, punch, PunchError, PunchOptions, DEFAULT_LEADER, MAX_LEADER};
pub use reader::Reader;

/// How to read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Check that every block has an even number of characters, its end of block included
    /// (docs/tape.md, "Block parity").
    pub block_parity: bool,
}

/// A tape read to its end without error.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tape {
    /// The code recognized; `None` for a plain text file.
    pub code: Option<Code>,
    /// The label: the text before the first end of block (empty if none).
    pub label: String,
    /// The text: one line per block, each ended by `\n`.
    pub text: String,
    /// Blocks read.
    pub blocks: u64,
    /// Frames read, up to the closing rewind stop (bytes, for a text file).
    pub frames: u64,
}

/// Whether an image is a plain text file rather than a tape image (docs/tape.md, "Text
/// files"): its first byte is not a blank frame (every punched tape starts with leader), it
/// is UTF-8, and it has no control character but tab, line feed and carriage return.
pub fn is_plain_text(image: &[u8]) -> bool {
    match image.first() {
        None | Some(0) => false,
        Some(_) => {
            !image
                .iter()
                .any(|&b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r') || b == 0x7F)
                && std::str::from_utf8(image).is_ok()
        }
    }
}

/// Reads a whole image: a plain text file is taken as it is; a tape image is decoded (the
/// code recognized at the first end of block, every frame's parity checked, up to the closing
/// rewind stop). Nothing is returned on error.
pub fn read_image(image: &[u8], opts: ReadOptions) -> Result<Tape, TapeError> {
    if is_plain_text(image) {
        let text = String::from_utf8_lossy(image).into_owned();
        return Ok(Tape {
            code: None,
            label: String::new(),
            blocks: text.lines().count() as u64,
            text,
            frames: image.len() as u64,
        });
    }
    reader::decode(image, opts)
}
