//! What stops a tape read, and how the alarm names it (docs/tape.md, "Errors"): the frame
//! number, the block number, the character position and the frame's holes.

use super::code::{Code, Frame};
use std::fmt;

/// Why a read stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The frame's parity is wrong for the code (a hole missing or one too many).
    Parity,
    /// The parity is right but the code has no such character.
    NotInCode,
    /// The block has an odd number of characters (block parity check on).
    BlockParity,
    /// The tape ends (or reaches the rewind stop) in the middle of a block: its end of
    /// block is missing.
    MissingEob,
    /// The image has no frames at all.
    Empty,
    /// No end of block anywhere on the tape: the code cannot be recognized.
    NoEob,
    /// Characters between a rewind stop and the end of block that must follow it.
    AfterRewindStop,
    /// EIA: a blank frame inside the data (every EIA character has a hole, so a blank is a
    /// character that lost its only hole).
    BlankInData,
}

/// A tape read error. Block 0 is the label (the text before the first end of block).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TapeError {
    /// What went wrong.
    pub kind: ErrorKind,
    /// The frame, 1-based from the start of the image (0 when there is none).
    pub frame: u64,
    /// The block, 1-based; 0 is the label.
    pub block: u64,
    /// The character's position in its block (or the label), 1-based; blank and rub-out frames
    /// do not count. For a block-parity error, the number of characters in the block.
    pub position: u64,
    /// The frame's holes.
    pub holes: Frame,
    /// The code recognized, if it was by then.
    pub code: Option<Code>,
}

impl TapeError {
    /// An error at a frame.
    pub(crate) fn at(
        kind: ErrorKind,
        frame: u64,
        block: u64,
        position: u64,
        holes: u8,
        code: Option<Code>,
    ) -> TapeError {
        TapeError {
            kind,
            frame,
            block,
            position,
            holes: Frame(holes),
            code,
        }
    }

    /// Where, for the message: `frame 123 (block 4, character 7)`.
    fn place(&self) -> String {
        let block = if self.block == 0 {
            "the label".to_string()
        } else {
            format!("block {}", self.block)
        };
        format!(
            "frame {} ({block}, character {})",
            self.frame, self.position
        )
    }
}

impl fmt::Display for TapeError {
    /// The alarm, e.g. `TAPE PARITY ERROR at frame 123 (block 4, character 7): holes 1 3 6
    /// (··●··•●·●); the ISO code wants an even number of holes`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let code = self.code.map_or("the tape", |c| c.name());
        match self.kind {
            ErrorKind::Parity => {
                let want = match self.code {
                    Some(Code::Eia) => "an odd",
                    _ => "an even",
                };
                write!(
                    f,
                    "TAPE PARITY ERROR at {}: {}; the {code} code wants {want} number of holes",
                    self.place(),
                    self.holes
                )
            }
            ErrorKind::NotInCode => write!(
                f,
                "TAPE CHARACTER ERROR at {}: {} is not a character of the {code} code",
                self.place(),
                self.holes
            ),
            ErrorKind::BlockParity => write!(
                f,
                "TAPE BLOCK PARITY ERROR at frame {} (block {}): the block has {} characters with its end of block; block parity wants an even number",
                self.frame, self.block, self.position
            ),
            ErrorKind::MissingEob => write!(
                f,
                "TAPE ERROR at {}: {}; the block has no end of block",
                self.place(),
                self.holes
            ),
            ErrorKind::Empty => write!(f, "TAPE ERROR: the tape image is empty (no frames)"),
            ErrorKind::NoEob => write!(
                f,
                "TAPE ERROR: no end of block in {} frames, so the code (ISO or EIA) cannot be recognized",
                self.frame
            ),
            ErrorKind::BlankInData => write!(
                f,
                "TAPE ERROR at {}: {}, a blank frame inside the data; every EIA character has a hole",
                self.place(),
                self.holes
            ),
            ErrorKind::AfterRewindStop => write!(
                f,
                "TAPE ERROR at {}: {}; only an end of block may follow the rewind stop",
                self.place(),
                self.holes
            ),
        }
    }
}

impl std::error::Error for TapeError {}
