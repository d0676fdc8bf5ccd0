//! Every kind of tape error (docs/tape.md, "Errors"): each stops the read with an alarm naming
//! the frame, the block, the character position and the frame's holes, and returns no text;
//! and the incremental reader the console will use gives the same results, frame by frame.

use novanc::pulse_core::testkit::Rng;
use novanc::tape::{self, Code, ErrorKind, PunchOptions, ReadOptions, Reader, TapeError};
use std::path::Path;

fn tableb() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/tableb.ap"))
        .unwrap()
}

fn punched(code: Code) -> Vec<u8> {
    let o = PunchOptions {
        code,
        leader: 10,
        label: Some("TABLE B".into()),
    };
    tape::punch(&tableb(), &o).unwrap()
}

fn read(image: &[u8]) -> Result<tape::Tape, TapeError> {
    tape::read_image(image, ReadOptions::default())
}

/// Index of the `n`-th frame (0-based) of block `b` (1-based) of a punched image: the blocks
/// start after the opening rewind stop's end of block.
fn frame_in_block(image: &[u8], code: Code, b: usize, n: usize) -> usize {
    let eob = code.eob().0;
    let eobs: Vec<usize> = image
        .iter()
        .enumerate()
        .filter(|(_, &f)| f == eob)
        .map(|(i, _)| i)
        .collect();
    eobs[b - 1] + 1 + n
}

#[test]
fn a_single_bit_error_in_every_channel_is_a_parity_error_naming_frame_block_character_and_holes() {
    for code in [Code::Iso, Code::Eia] {
        let good = punched(code);
        // Block 1 is `DA1 = (200, 0, -450)`; its 7th character is `(`.
        let at = frame_in_block(&good, code, 1, 6);
        assert_eq!(
            code.meaning(tape::Frame(good[at])),
            tape::Meaning::Char('(')
        );
        for ch in 1..=8u8 {
            let mut bad = good.clone();
            bad[at] ^= 1 << (ch - 1);
            let e = read(&bad).expect_err("a flipped bit");
            assert_eq!(e.kind, ErrorKind::Parity, "{code:?} channel {ch}: {e}");
            assert_eq!(e.frame, at as u64 + 1);
            assert_eq!((e.block, e.position), (1, 7), "{e}");
            assert_eq!(e.holes, tape::Frame(bad[at]));
            assert_eq!(e.code, Some(code));
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!(
                    "TAPE PARITY ERROR at frame {} (block 1, character 7): holes {}",
                    at + 1,
                    tape::Frame(bad[at]).channels()
                )),
                "{msg}"
            );
            let want = if code == Code::Iso { "even" } else { "odd" };
            assert!(
                msg.ends_with(&format!(
                    "the {} code wants an {want} number of holes",
                    code.name()
                )),
                "{msg}"
            );
        }
    }
}

#[test]
fn a_character_not_in_the_code_is_refused() {
    // ISO: SOH with its parity bit (channels 1 and 8: even, but a control character). EIA:
    // channels 1 2 3 4 7, a free odd pattern.
    for (code, frame) in [(Code::Iso, 0x81u8), (Code::Eia, 0x4F)] {
        let mut bad = punched(code);
        let at = frame_in_block(&bad, code, 3, 4);
        bad[at] = frame;
        let e = read(&bad).unwrap_err();
        assert_eq!(e.kind, ErrorKind::NotInCode, "{e}");
        assert_eq!((e.frame, e.block, e.position), (at as u64 + 1, 3, 5));
        assert!(
            e.to_string()
                .contains(&format!("is not a character of the {} code", code.name())),
            "{e}"
        );
    }
}

#[test]
fn a_tape_that_ends_inside_a_block_is_missing_its_end_of_block() {
    for code in [Code::Iso, Code::Eia] {
        let good = punched(code);
        // Cut in the middle of block 4, then blank trailer.
        let at = frame_in_block(&good, code, 4, 10);
        let mut bad = good[..at].to_vec();
        bad.extend([0u8; 10]);
        let e = read(&bad).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingEob, "{e}");
        assert_eq!((e.frame, e.block, e.position), (at as u64, 4, 10), "{e}");
        assert!(
            e.to_string().ends_with("the block has no end of block"),
            "{e}"
        );
        // The last block's end of block rubbed out: the closing rewind stop comes inside it.
        let mut bad = good.clone();
        let last_eob = bad.iter().rposition(|&f| f == code.eob().0).unwrap();
        bad[last_eob] = if code == Code::Iso { 0xFF } else { 0x7F };
        let e = read(&bad).unwrap_err();
        assert_eq!((e.kind, e.block), (ErrorKind::MissingEob, 9), "{e}");
        assert_eq!(e.holes, code.rewind_stop());
    }
}

#[test]
fn block_parity_catches_a_block_with_an_odd_number_of_characters() {
    for code in [Code::Iso, Code::Eia] {
        let good = punched(code);
        // Remove the pad of the first padded block: the text is the same, the count is odd.
        let pad = good.iter().position(|&f| f == code.pad().0).unwrap();
        let mut bad = good.clone();
        bad.remove(pad);
        let lenient = read(&bad).expect("without block parity the tape reads");
        assert_eq!(lenient.text, tableb());
        let e = tape::read_image(&bad, ReadOptions { block_parity: true }).unwrap_err();
        assert_eq!(e.kind, ErrorKind::BlockParity, "{e}");
        assert_eq!(e.frame, pad as u64 + 1, "the end of block after the pad");
        assert_eq!(e.position % 2, 1);
        assert!(
            e.to_string().contains("block parity wants an even number"),
            "{e}"
        );
        assert!(tape::read_image(&good, ReadOptions { block_parity: true }).is_ok());
    }
}

#[test]
fn an_empty_image_and_a_blank_tape_have_nothing_to_read() {
    let e = read(&[]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Empty);
    assert_eq!(
        e.to_string(),
        "TAPE ERROR: the tape image is empty (no frames)"
    );
    let e = read(&[0u8; 300]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NoEob);
    assert_eq!(
        e.to_string(),
        "TAPE ERROR: no end of block in 300 frames, so the code (ISO or EIA) cannot be recognized"
    );
}

#[test]
fn images_of_random_bytes_are_refused() {
    let mut s = Rng::new(7);
    for case in 0..500 {
        let len = 64 + (s.next_u64() % 4000) as usize;
        let image: Vec<u8> = (0..len).map(|_| s.next_u64() as u8).collect();
        let e = read(&image).expect_err("random bytes read as a tape");
        assert!(e.frame >= 1 && e.frame <= len as u64, "case {case}: {e}");
        assert_ne!(e.kind, ErrorKind::Empty);
        // The incremental reader, fed in odd chunks, says the same.
        let mut r = Reader::new(ReadOptions::default());
        for chunk in image.chunks(1 + case % 37) {
            if r.feed(chunk).is_err() {
                break;
            }
        }
        assert_eq!(r.finish().unwrap_err(), e, "case {case}");
    }
}

#[test]
fn a_blank_frame_inside_eia_data_is_a_lost_hole() {
    // `1` is channel 1 alone: without its hole it would silently vanish.
    let mut bad = punched(Code::Eia);
    let at = frame_in_block(&bad, Code::Eia, 1, 2);
    assert_eq!(bad[at], 0x01);
    bad[at] = 0;
    let e = read(&bad).unwrap_err();
    assert_eq!(e.kind, ErrorKind::BlankInData);
    assert_eq!((e.frame, e.block, e.position), (at as u64 + 1, 1, 3));
    assert!(
        e.to_string().starts_with(&format!(
            "TAPE ERROR at frame {} (block 1, character 3): holes blank (·····•···), a blank frame inside the data",
            at + 1
        )),
        "{e}"
    );
    // Blank tape after the last end of block is trailer, even with no closing rewind stop.
    let good = punched(Code::Eia);
    let last_eob = good.iter().rposition(|&f| f == 0x80).unwrap();
    let mut no_rs = good[..=last_eob].to_vec();
    no_rs.extend([0u8; 30]);
    assert_eq!(read(&no_rs).unwrap().text, tableb());
    // ISO passes NUL over anywhere.
    let mut iso = punched(Code::Iso);
    let at = frame_in_block(&iso, Code::Iso, 1, 2);
    iso.insert(at, 0);
    assert_eq!(read(&iso).unwrap().text, tableb());
}

#[test]
fn rub_outs_are_passed_over() {
    for (code, del) in [(Code::Iso, 0xFFu8), (Code::Eia, 0x7F)] {
        let mut image = punched(code);
        let at = frame_in_block(&image, code, 2, 3);
        image.insert(at, del);
        image.insert(at, del);
        let t = tape::read_image(&image, ReadOptions { block_parity: true }).unwrap();
        assert_eq!(t.text, tableb());
    }
}

#[test]
fn a_plain_text_file_is_still_accepted() {
    let t = read(tableb().as_bytes()).unwrap();
    assert_eq!(t.code, None);
    assert_eq!(t.text, tableb());
    assert!(!tape::is_plain_text(&punched(Code::Iso)));
    assert!(!tape::is_plain_text(&punched(Code::Eia)));
    // UTF-8 comments are text; a leading blank frame, a control character or bad UTF-8 is not.
    assert!(tape::is_plain_text("P1 = (1, 2) ; prüf\n".as_bytes()));
    assert!(!tape::is_plain_text(b"\0P1\n"));
    assert!(!tape::is_plain_text(b"P1\x01\n"));
    assert!(!tape::is_plain_text(b"P1 \xff\n"));
}

#[test]
fn the_label_ends_at_the_rewind_stop_and_only_an_end_of_block_may_follow_it() {
    let code = Code::Iso;
    let f = |c: char| code.frame_of(c).unwrap().0;
    let (rs, eob) = (code.rewind_stop().0, code.eob().0);
    // leader, "AB", %, "C", LF: a character between the rewind stop and the end of block.
    let image = [0, f('A'), f('B'), rs, f('C'), eob, f('N'), eob, rs];
    let e = read(&image).unwrap_err();
    assert_eq!(e.kind, ErrorKind::AfterRewindStop, "{e}");
    assert_eq!((e.frame, e.block), (5, 0));
    assert!(e.to_string().contains("(the label, character 4)"), "{e}");
    // A label without a rewind stop: the program opens at the first one after it.
    let image = [0, f('A'), eob, rs, eob, f('N'), eob, rs, f('X')];
    let t = read(&image).unwrap();
    assert_eq!((t.label.as_str(), t.text.as_str()), ("A", "N\n"));
    assert_eq!(t.frames, 8, "the reader stops at the closing rewind stop");
    // No rewind stop at all: the tape simply ends after its last block.
    let t = read(&[0, eob, f('N'), f('1'), eob, 0, 0]).unwrap();
    assert_eq!((t.label.as_str(), t.text.as_str()), ("", "N1\n"));
}

#[test]
fn the_incremental_reader_shows_the_tape_passing_and_agrees_with_the_whole_read() {
    for code in [Code::Iso, Code::Eia] {
        let image = punched(code);
        let whole = read(&image).unwrap();
        let mut r = Reader::new(ReadOptions { block_parity: true });
        let mut saw_code_at = None;
        let mut stopped = false;
        for (i, &frame) in image.iter().enumerate() {
            stopped = r.feed(&[frame]).unwrap();
            assert_eq!(r.frames().len(), i + 1);
            if saw_code_at.is_none() && r.code().is_some() {
                saw_code_at = Some(i);
                assert_eq!(r.label(), Some("TABLE B"));
                assert_eq!(r.block(), 1);
            }
            // The text so far is always a prefix of the whole text.
            assert!(whole.text.starts_with(r.text()), "{code:?} frame {i}");
            if stopped {
                break;
            }
        }
        assert!(stopped, "the closing rewind stop was read");
        assert_eq!(
            saw_code_at,
            Some(image.iter().position(|&f| f == code.eob().0).unwrap())
        );
        assert!(r.is_stopped());
        // Frames after the closing rewind stop are not read.
        assert!(r.feed(&[0, 0, 0]).unwrap());
        assert_eq!(r.frames().len() as u64, whole.frames);
        assert_eq!(r.finish().unwrap(), whole);
    }
}

#[test]
fn the_incremental_reader_keeps_its_error_and_gives_no_text() {
    let mut bad = punched(Code::Iso);
    let at = frame_in_block(&bad, Code::Iso, 5, 0);
    bad[at] ^= 0x10;
    let whole = read(&bad).unwrap_err();
    let mut r = Reader::new(ReadOptions::default());
    let mut err = None;
    for chunk in bad.chunks(7) {
        if let Err(e) = r.feed(chunk) {
            err = Some(e);
            break;
        }
    }
    let e = err.expect("the reader stops");
    assert_eq!(e, whole);
    assert_eq!(
        r.frames().len(),
        at + 1,
        "the bad frame is the last one read"
    );
    assert_eq!(r.error(), Some(&whole));
    assert_eq!(r.feed(&[0]).unwrap_err(), whole, "it stays stopped");
    assert!(!r.text().is_empty(), "the text so far is there for display");
    assert_eq!(r.finish().unwrap_err(), whole, "but no result");
}
