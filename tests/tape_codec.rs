//! The tape codes and the punch (docs/tape.md): the golden images of Table B and the sample
//! tool tape in both codes are what the punch makes, their hole patterns follow the code tables
//! of docs/tape.md frame by frame, they read back to the same text, and every single-bit error
//! of every frame is caught or changes nothing.

use novanc::pulse_core::testkit::Rng;
use novanc::tape::{self, Code, PunchOptions, ReadOptions};
use std::collections::HashMap;
use std::path::Path;

fn repo(p: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(p);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn golden(name: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The four golden images: (image file, source file, label, code).
const GOLDEN: [(&str, &str, &str, Code); 4] = [
    (
        "tableb.iso.tape",
        "programs/tableb.ap",
        "TABLE B",
        Code::Iso,
    ),
    (
        "tableb.eia.tape",
        "programs/tableb.ap",
        "TABLE B",
        Code::Eia,
    ),
    (
        "tools.iso.tape",
        "tooldata/tools.tt",
        "TOOL TAPE",
        Code::Iso,
    ),
    (
        "tools.eia.tape",
        "tooldata/tools.tt",
        "TOOL TAPE",
        Code::Eia,
    ),
];

/// The golden images' leader (and trailer), frames.
const LEADER: usize = 20;

fn opts(code: Code, label: &str) -> PunchOptions {
    PunchOptions {
        code,
        leader: LEADER,
        label: Some(label.to_string()),
    }
}

#[test]
fn golden_images_are_what_the_punch_makes() {
    for (img, src, label, code) in GOLDEN {
        let punched = tape::punch(&repo(src), &opts(code, label)).expect("punch");
        assert!(
            punched == golden(img),
            "{img}: the punch no longer makes the golden image \
             (novanc tape punch {src} --code {} --leader {LEADER} --label '{label}' -o tests/golden/{img})",
            code.name()
        );
    }
}

#[test]
fn golden_images_read_back_to_their_text_and_label() {
    for (img, src, label, code) in GOLDEN {
        let t = tape::read_image(&golden(img), ReadOptions { block_parity: true })
            .unwrap_or_else(|e| panic!("{img}: {e}"));
        assert_eq!(t.code, Some(code), "{img}");
        assert_eq!(t.label, label, "{img}");
        assert!(
            t.text == repo(src),
            "{img}: the text read differs from {src}"
        );
        assert_eq!(t.blocks as usize, repo(src).lines().count(), "{img}");
    }
}

// ---------------------------------------------------------------- the tables of the docs

/// Channels `1 2 5` (or `—`) to a frame byte.
fn frame_of_channels(cell: &str) -> u8 {
    cell.split_whitespace()
        .filter_map(|c| c.parse::<u8>().ok())
        .fold(0, |f, c| f | 1 << (c - 1))
}

/// The rows `| character | channels | … |` of one `## ` section of docs/tape.md, keyed by the
/// character (the text between the first backticks) or the name (`EOB`, `SP`, `ER`, …).
fn docs_table(section: &str) -> HashMap<String, u8> {
    let docs = repo("docs/tape.md");
    let start = docs
        .find(&format!("## {section}"))
        .unwrap_or_else(|| panic!("no section '{section}' in docs/tape.md"));
    let body = &docs[start + 3..];
    let body = &body[..body.find("\n## ").unwrap_or(body.len())];
    let mut t = HashMap::new();
    for line in body.lines().filter(|l| l.starts_with("| ")) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let (key, chans) = (cells[1], cells[2]);
        if key == "character" || key == "frame" || key.starts_with("---") {
            continue;
        }
        let key = match key.strip_prefix('`') {
            Some(rest) => rest.split('`').next().unwrap_or("").to_string(),
            None => key.to_string(),
        };
        if chans.chars().all(|c| c.is_ascii_digit() || c == ' ') || chans == "—" {
            t.insert(key, frame_of_channels(chans));
        }
    }
    t
}

/// The frame the docs give a character (or named frame) in a code. ISO: the special rows of
/// the docs' table, else the character's ASCII value with even parity in channel 8.
fn docs_frame(code: Code, tables: &HashMap<String, u8>, key: &str) -> u8 {
    if let Some(&f) = tables.get(key) {
        return f;
    }
    match code {
        Code::Iso => {
            let c = key.chars().next().expect("a character") as u8;
            if c.count_ones() % 2 == 1 {
                c | 0x80
            } else {
                c
            }
        }
        Code::Eia => {
            let upper = key.to_ascii_uppercase();
            *tables
                .get(&upper)
                .unwrap_or_else(|| panic!("docs/tape.md has no EIA frame for {key:?}"))
        }
    }
}

/// The frames docs/tape.md's layout and tables give a text, built here independently of the
/// punch: leader, label, rewind stop, EOB, blocks (EIA case shifts, pad to an even count),
/// rewind stop, trailer.
fn expected_image(code: Code, label: &str, text: &str) -> Vec<(u8, String)> {
    let tables = match code {
        Code::Iso => docs_table("The ISO code"),
        Code::Eia => docs_table("The EIA code"),
    };
    let key = |k: &str| (docs_frame(code, &tables, k), k.to_string());
    let (eob, rs, pad) = match code {
        Code::Iso => (key("LF"), key("%"), key("CR")),
        Code::Eia => (key("EOB"), key("ER"), key("BS")),
    };
    let line = |s: &str| -> Vec<(u8, String)> {
        let mut out = Vec::new();
        let mut lower = false;
        for c in s.chars() {
            if code == Code::Eia && c.is_ascii_alphabetic() && c.is_ascii_lowercase() != lower {
                lower = c.is_ascii_lowercase();
                out.push(key(if lower { "LC" } else { "UC" }));
            }
            out.push(match c {
                ' ' => key("SP"),
                '\t' if code == Code::Eia => key("TAB"),
                '\t' => key("HT"),
                c => key(&c.to_string()),
            });
        }
        out
    };
    let blank = (0u8, "blank".to_string());
    let mut v = vec![blank.clone(); LEADER];
    v.extend(line(label));
    v.push(rs.clone());
    v.push(eob.clone());
    for l in text.lines() {
        let b = line(l);
        let odd_with_eob = (b.len() + 1) % 2 == 1;
        v.extend(b);
        if odd_with_eob {
            v.push(pad.clone());
        }
        v.push(eob.clone());
    }
    v.push(rs);
    v.extend(vec![blank; LEADER]);
    v
}

#[test]
fn golden_hole_patterns_follow_the_code_tables_of_the_docs() {
    for (img, src, label, code) in GOLDEN {
        let image = golden(img);
        let want = expected_image(code, label, &repo(src));
        assert_eq!(image.len(), want.len(), "{img}: frame count");
        for (i, (&got, (frame, what))) in image.iter().zip(&want).enumerate() {
            assert!(
                got == *frame,
                "{img} frame {}: {what:?} should be {} but the image has {}",
                i + 1,
                tape::Frame(*frame),
                tape::Frame(got)
            );
            let parity_ok = got == 0 || got == 0xFF || code.parity_ok(tape::Frame(got));
            assert!(parity_ok, "{img} frame {}: parity", i + 1);
        }
    }
}

#[test]
fn the_docs_eia_table_is_the_code_table() {
    let docs = docs_table("The EIA code");
    for (c, f) in tape::EIA_CHARS {
        let key = match c {
            ' ' => "SP".to_string(),
            '\t' => "TAB".to_string(),
            c => c.to_string(),
        };
        assert_eq!(docs.get(&key), Some(&f), "{key:?}");
        assert_eq!(Code::Eia.frame_of(c), Some(tape::Frame(f)), "{key:?}");
    }
    assert_eq!(docs["EOB"], Code::Eia.eob().0);
    assert_eq!(docs["ER"], Code::Eia.rewind_stop().0);
    assert_eq!(docs["BS"], Code::Eia.pad().0);
    let (uc, lc) = Code::Eia.case_shifts().unwrap();
    assert_eq!((docs["UC"], docs["LC"]), (uc.0, lc.0));
    assert_eq!(docs["DEL"], 0x7F);
    assert_eq!(Code::Eia.meaning(tape::Frame(0x7F)), tape::Meaning::RubOut);
    // Every row of the docs is a code frame with odd parity.
    assert_eq!(docs.len(), tape::EIA_CHARS.len() + 6);
    for (k, f) in &docs {
        assert_eq!(f.count_ones() % 2, 1, "{k}");
    }
}

// ---------------------------------------------------------------- round trips

/// Every character a code can punch.
fn charset(code: Code) -> Vec<char> {
    (0u8..128)
        .map(char::from)
        .filter(|&c| code.frame_of(c).is_some())
        .collect()
}

#[test]
fn random_texts_round_trip_in_both_codes() {
    let mut rng = Rng::new(11);
    for code in [Code::Iso, Code::Eia] {
        let chars = charset(code);
        for case in 0..300 {
            let lines = rng.below(20);
            let mut text = String::new();
            for _ in 0..lines {
                for _ in 0..rng.below(40) {
                    text.push(chars[rng.below(chars.len())]);
                }
                text.push('\n');
            }
            let label: String = (0..rng.below(8))
                .map(|_| chars[rng.below(chars.len())])
                .collect();
            let o = PunchOptions {
                code,
                leader: 1 + rng.below(30),
                label: Some(label.clone()),
            };
            let image = tape::punch(&text, &o).unwrap();
            let t = tape::read_image(&image, ReadOptions { block_parity: true })
                .unwrap_or_else(|e| panic!("{code:?} case {case}: {e}\n{text:?}"));
            assert_eq!(t.text, text, "{code:?} case {case}");
            assert_eq!(t.label, label, "{code:?} case {case}");
            assert_eq!(t.code, Some(code));
        }
    }
}

#[test]
fn a_file_without_its_last_newline_reads_back_with_one() {
    for code in [Code::Iso, Code::Eia] {
        let image = tape::punch("N1 G0\nN2 G1", &opts(code, "")).unwrap();
        let t = tape::read_image(&image, ReadOptions::default()).unwrap();
        assert_eq!(t.text, "N1 G0\nN2 G1\n");
        let empty = tape::punch("", &opts(code, "")).unwrap();
        let t = tape::read_image(&empty, ReadOptions::default()).unwrap();
        assert_eq!((t.text.as_str(), t.blocks), ("", 0));
    }
}

#[test]
fn the_punch_refuses_what_the_code_lacks_and_says_where() {
    let e = tape::punch(
        "DA1 = (0, 0, 0)\nP1 = (1, 2) ; prüf\n",
        &opts(Code::Iso, ""),
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "2:17: 'ü' has no code in ISO (docs/tape.md)");
    let e = tape::punch("G0 X1\nN2 %\n", &opts(Code::Iso, "")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "2:4: '%' is the rewind stop; it cannot be punched inside a block"
    );
    let e = tape::punch("N1 G0 X1 & Y2\n", &opts(Code::Eia, "")).unwrap_err();
    assert_eq!(e.to_string(), "1:10: '&' has no code in EIA (docs/tape.md)");
    let e = tape::punch("N1\r\nN2\r\n", &opts(Code::Iso, "")).unwrap_err();
    assert!(e.to_string().starts_with("1:3: a carriage return"), "{e}");
    let e = tape::punch("N1\n", &opts(Code::Iso, "50%")).unwrap_err();
    assert!(e.to_string().starts_with("label:3: '%'"), "{e}");
}

// ---------------------------------------------------------------- single-bit errors

/// Index of the first end of block of a good image.
fn first_eob(image: &[u8]) -> usize {
    image.iter().position(|&b| b == 0x0A || b == 0x80).unwrap()
}

/// Index of the closing rewind stop of a good image (the last non-blank frame).
fn closing_rs(image: &[u8]) -> usize {
    image.iter().rposition(|&b| b != 0).unwrap()
}

/// A good image and what it reads as.
struct Good {
    image: Vec<u8>,
    tape: tape::Tape,
    /// Frames before this one are leader and label.
    first_eob: usize,
    /// Frames after this one are trailer.
    closing_rs: usize,
}

impl Good {
    fn new(image: Vec<u8>) -> Good {
        let tape = tape::read_image(&image, ReadOptions::default()).unwrap();
        Good {
            first_eob: first_eob(&image),
            closing_rs: closing_rs(&image),
            image,
            tape,
        }
    }
}

/// Reads the good image with one bit flipped and classifies the outcome; panics if the text
/// changed without an error, or if a change was let through anywhere but in the leader or
/// trailer.
fn flip_and_read(g: &Good, at: usize, bit: u8, what: &str) -> Outcome {
    let (image, good) = (&g.image, &g.tape);
    let mut bad = image.to_vec();
    bad[at] ^= 1 << bit;
    match tape::read_image(&bad, ReadOptions::default()) {
        Err(e) => {
            assert!(e.frame >= 1, "{what}: {e}");
            Outcome::Detected
        }
        Ok(t) => {
            assert!(
                t.text == good.text,
                "{what}: frame {} channel {} changed the text without an error",
                at + 1,
                bit + 1
            );
            let in_leader = at < g.first_eob;
            let in_trailer = at > g.closing_rs;
            assert!(
                in_leader || in_trailer,
                "{what}: frame {} channel {} was let through inside the data",
                at + 1,
                bit + 1
            );
            if t.label == good.label {
                Outcome::Harmless
            } else {
                Outcome::LabelOnly
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    Detected,
    Harmless,
    LabelOnly,
}

#[test]
fn every_single_bit_error_of_every_golden_frame_is_caught_or_harmless() {
    for (img, _, _, code) in GOLDEN {
        let g = Good::new(golden(img));
        let image = &g.image;
        let mut counts = [0usize; 3];
        for at in 0..image.len() {
            for bit in 0..8 {
                let o = flip_and_read(&g, at, bit, img);
                counts[o as usize] += 1;
                let data = at >= g.first_eob && at <= g.closing_rs;
                if data {
                    assert_eq!(o, Outcome::Detected, "{img} frame {} bit {bit}", at + 1);
                }
            }
        }
        eprintln!(
            "{img} ({code:?}): {} flips: {} detected, {} harmless (leader/trailer), {} changed only the label",
            image.len() * 8,
            counts[0],
            counts[1],
            counts[2]
        );
        assert_eq!(counts.iter().sum::<usize>(), image.len() * 8);
    }
}

#[test]
fn thousands_of_random_single_frame_corruptions_of_a_long_tape() {
    // A generated program of 400 blocks; 5,000 random (frame, channel) flips per code.
    let mut rng = Rng::new(2024);
    let mut text = String::new();
    for n in 1..=400 {
        text.push_str(&format!(
            "N{n} G01 X{}.{:03} Y-{}.5 F{} ; pass {n}\n",
            rng.below(500),
            rng.below(1000),
            rng.below(300),
            50 + rng.below(900)
        ));
    }
    for code in [Code::Iso, Code::Eia] {
        let g = Good::new(tape::punch(&text, &opts(code, "LONG")).unwrap());
        assert_eq!(g.tape.text, text);
        let mut counts = [0usize; 3];
        for _ in 0..5_000 {
            let at = rng.below(g.image.len());
            let bit = rng.below(8) as u8;
            counts[flip_and_read(&g, at, bit, code.name()) as usize] += 1;
        }
        eprintln!(
            "{code:?}: 5000 random flips over {} frames: {} detected, {} harmless, {} label only",
            g.image.len(),
            counts[0],
            counts[1],
            counts[2]
        );
        assert!(counts[0] > 4_500, "{counts:?}");
    }
}
