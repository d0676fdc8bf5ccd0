//! Property test: random command lines on random buffers, checked against a naive model
//! (a `Vec<char>` and a pointer), with an in-repo seeded PRNG. Failing lines are included and
//! must leave the buffer exactly as it was.

use novanc_editor::{Buffer, Command, ExecOptions};

/// splitmix64: a small seeded generator, enough for test data.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn chance(&mut self, percent: usize) -> bool {
        self.below(100) < percent
    }
}

const ALPHABET: &[char] = &[
    'a', 'b', 'X', '1', ' ', '\n', '\n', 'é', '€', '*', '$', '\\', 'Q',
];

fn random_text(rng: &mut Rng, max: usize) -> String {
    let n = rng.below(max + 1);
    (0..n)
        .map(|_| ALPHABET[rng.below(ALPHABET.len())])
        .collect()
}

/// The naive model of a buffer.
#[derive(Clone, Debug, PartialEq)]
struct Model {
    chars: Vec<char>,
    ptr: usize,
}

impl Model {
    fn line_start(&self, pos: usize) -> usize {
        let mut i = pos;
        while i > 0 && self.chars[i - 1] != '\n' {
            i -= 1;
        }
        i
    }
    fn after_eobs(&self, pos: usize, n: u64) -> usize {
        let mut seen = 0;
        for i in pos..self.chars.len() {
            if self.chars[i] == '\n' {
                seen += 1;
                if seen == n {
                    return i + 1;
                }
            }
        }
        self.chars.len()
    }
    fn lines_back(&self, pos: usize, n: u64) -> usize {
        let mut s = self.line_start(pos);
        for _ in 0..n {
            if s == 0 {
                break;
            }
            s = self.line_start(s - 1);
        }
        s
    }
    fn find(&self, from: usize, pat: &[char]) -> Option<usize> {
        (from..self.chars.len()).find(|&i| {
            i + pat.len() <= self.chars.len()
                && self.chars[i..i + pat.len()]
                    .iter()
                    .zip(pat)
                    .all(|(a, b)| a.eq_ignore_ascii_case(b))
        })
    }
    /// Runs one command; Ok(whether text changed).
    fn run(&mut self, c: &Command, ymax: Option<usize>, y: &mut String) -> Result<bool, ()> {
        let p = self.ptr;
        let len = self.chars.len();
        match c {
            Command::L(n) => {
                self.ptr = if *n > 0 {
                    self.after_eobs(p, *n as u64)
                } else {
                    self.lines_back(p, n.unsigned_abs())
                };
                Ok(false)
            }
            Command::M(m) => {
                let t = p as i64 + m;
                if t < 0 || t > len as i64 {
                    return Err(());
                }
                self.ptr = t as usize;
                Ok(false)
            }
            Command::K(n) => {
                let (s, e) = if *n > 0 {
                    (p, self.after_eobs(p, *n as u64))
                } else {
                    (self.lines_back(p, n.unsigned_abs()), p)
                };
                self.chars.drain(s..e);
                self.ptr = s;
                Ok(e > s)
            }
            Command::D(n) => {
                let (s, e) = if *n >= 0 {
                    (p, p + *n as usize)
                } else {
                    (p.checked_sub(n.unsigned_abs() as usize).ok_or(())?, p)
                };
                if e > len {
                    return Err(());
                }
                self.chars.drain(s..e);
                self.ptr = s;
                Ok(e > s)
            }
            Command::I(t) => {
                let t: Vec<char> = t.chars().collect();
                self.chars.splice(p..p, t.iter().cloned());
                self.ptr = p + t.len();
                Ok(!t.is_empty())
            }
            Command::S(t) => {
                let t: Vec<char> = t.chars().collect();
                let s = self.find(p, &t).ok_or(())?;
                self.ptr = s + t.len();
                Ok(false)
            }
            Command::C(old, new) => {
                let old: Vec<char> = old.chars().collect();
                let new: Vec<char> = new.chars().collect();
                let s = self.find(p, &old).ok_or(())?;
                self.chars.splice(s..s + old.len(), new.iter().cloned());
                self.ptr = s + new.len();
                Ok(true)
            }
            Command::Y(n) => {
                let (s, mut e) = if *n > 0 {
                    (p, self.after_eobs(p, *n as u64))
                } else {
                    (self.lines_back(p, n.unsigned_abs()), p)
                };
                if let Some(m) = ymax {
                    e = if m == 0 {
                        s
                    } else {
                        e.min(self.after_eobs(s, m as u64))
                    };
                }
                let shown: String = self.chars[s..e].iter().collect();
                y.push_str(&shown);
                if !shown.is_empty() && !shown.ends_with('\n') {
                    y.push('\n');
                }
                Ok(false)
            }
        }
    }
}

/// How a text argument is typed: EOB as `*`, literal `*`, `$`, `\` escaped.
fn typed_text(t: &str) -> String {
    let mut s = String::new();
    for c in t.chars() {
        match c {
            '\n' => s.push('*'),
            '*' | '$' | '\\' => {
                s.push('\\');
                s.push(c);
            }
            _ => s.push(c),
        }
    }
    s
}

fn typed_count(rng: &mut Rng, n: i64) -> String {
    match n {
        1 if rng.chance(50) => String::new(),
        1 if rng.chance(50) => "+".into(),
        -1 if rng.chance(50) => "-".into(),
        n if n > 0 && rng.chance(30) => format!("+{n}"),
        n => n.to_string(),
    }
}

/// A piece of the buffer to search for (so that searches often succeed), or random text.
fn needle(rng: &mut Rng, m: &Model) -> String {
    if !m.chars.is_empty() && rng.chance(70) {
        let s = rng.below(m.chars.len());
        let n = 1 + rng.below(3.min(m.chars.len() - s));
        m.chars[s..s + n].iter().collect()
    } else {
        let t = random_text(rng, 3);
        if t.is_empty() {
            "a".into()
        } else {
            t
        }
    }
}

/// A random command and how it is typed.
fn random_command(rng: &mut Rng, m: &Model, last: bool) -> (Command, String) {
    let n = rng.below(11) as i64 - 5;
    let letter = |rng: &mut Rng, c: char| {
        if rng.chance(30) {
            c.to_ascii_lowercase()
        } else {
            c
        }
    };
    let end = |rng: &mut Rng| if last && rng.chance(50) { "" } else { "$" };
    match rng.below(8) {
        0 => (
            Command::L(n),
            format!("{}{}", typed_count(rng, n), letter(rng, 'L')),
        ),
        1 => (
            Command::M(n),
            format!("{}{}", typed_count(rng, n), letter(rng, 'M')),
        ),
        2 => (
            Command::K(n),
            format!("{}{}", typed_count(rng, n), letter(rng, 'K')),
        ),
        3 => (
            Command::D(n),
            format!("{}{}", typed_count(rng, n), letter(rng, 'D')),
        ),
        4 => (
            Command::Y(n),
            format!("{}{}", typed_count(rng, n), letter(rng, 'Y')),
        ),
        5 => {
            let t = random_text(rng, 4);
            let typed = format!("{}{}{}", letter(rng, 'I'), typed_text(&t), end(rng));
            (Command::I(t), typed)
        }
        6 => {
            let t = needle(rng, m);
            let typed = format!("{}{}{}", letter(rng, 'S'), typed_text(&t), end(rng));
            (Command::S(t), typed)
        }
        _ => {
            let old = needle(rng, m);
            let new = random_text(rng, 3);
            let typed = format!(
                "{}{}${}{}",
                letter(rng, 'C'),
                typed_text(&old),
                typed_text(&new),
                end(rng)
            );
            (Command::C(old, new), typed)
        }
    }
}

#[test]
fn random_command_lines_match_the_naive_model() {
    let failures = check(0x4E4F_5641_4E43, 20_000, 30);
    assert!(failures > 5_000, "too few failing lines: {failures}");
}

#[test]
fn long_buffers_spanning_many_chunks_match_the_naive_model() {
    check(0x5350_414E, 100, 50_000);
}

/// Runs `cases` random buffers of up to `max_len` characters, four random lines on each;
/// returns how many lines failed (as the model also said).
fn check(seed: u64, cases: usize, max_len: usize) -> usize {
    let mut rng = Rng(seed);
    let no_qq = |b: &Buffer| {
        if b.text().contains("QQ") {
            Err("QQ is not a record".to_string())
        } else {
            Ok(())
        }
    };
    let mut failures = 0;
    for case in 0..cases {
        let text = random_text(&mut rng, max_len);
        let mut buf = Buffer::from_text(&text);
        let mut model = Model {
            chars: text.chars().collect(),
            ptr: 0,
        };
        let at = rng.below(model.chars.len() + 1);
        buf.set_pointer(at);
        model.ptr = at;
        // Several lines on the same buffer, so that edits build on each other.
        for _ in 0..4 {
            let count = 1 + rng.below(4);
            let mut typed = String::new();
            let mut commands = Vec::new();
            let mut scratch = model.clone();
            for i in 0..count {
                let (c, t) = random_command(&mut rng, &scratch, i + 1 == count);
                if !typed.is_empty() && rng.chance(30) {
                    typed.push(' ');
                }
                typed.push_str(&t);
                let _ = scratch.run(&c, None, &mut String::new());
                commands.push(c);
            }
            let ymax = if rng.chance(50) {
                None
            } else {
                Some(rng.below(4))
            };
            let with_validator = rng.chance(30);
            let opts = ExecOptions {
                y_max_lines: ymax,
                validator: if with_validator { Some(&no_qq) } else { None },
            };
            assert_eq!(
                novanc_editor::parse(&typed).as_ref(),
                Ok(&commands),
                "case {case}: parse of {typed:?}"
            );
            // The model's answer.
            let mut next = model.clone();
            let mut y = String::new();
            let mut want_err = None;
            let mut last_change = None;
            for (i, c) in commands.iter().enumerate() {
                match next.run(c, ymax, &mut y) {
                    Ok(true) => last_change = Some(i),
                    Ok(false) => {}
                    Err(()) => {
                        want_err = Some(i);
                        break;
                    }
                }
            }
            if want_err.is_none() && with_validator {
                if let Some(i) = last_change {
                    if next.chars.windows(2).any(|w| w == ['Q', 'Q']) {
                        want_err = Some(i);
                    }
                }
            }
            let got = buf.execute(&typed, &opts);
            match (want_err, got) {
                (None, Ok(out)) => {
                    model = next;
                    assert_eq!(out.y_output, y, "case {case}: Y of {typed:?}");
                    assert_eq!(out.changed, last_change.is_some(), "case {case}: {typed:?}");
                }
                (Some(i), Err(e)) => {
                    failures += 1;
                    assert_eq!(e.index, i, "case {case}: {typed:?}: {e}");
                }
                (want, got) => {
                    panic!("case {case}: {typed:?} on {model:?}: want {want:?}, got {got:?}")
                }
            }
            let text: String = model.chars.iter().collect();
            assert_eq!(buf.text(), text, "case {case}: text after {typed:?}");
            assert_eq!(
                buf.pointer(),
                model.ptr,
                "case {case}: pointer after {typed:?}"
            );
            assert_eq!(buf.len(), model.chars.len());
        }
    }
    failures
}
