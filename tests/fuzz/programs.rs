//! Part programs, by grammar and by mutation of the samples, and the checks on what the
//! translator makes of them (docs/language.md): an error is one short line naming a line and
//! column, after which nothing comes; a translated statement keeps every limit (blocks per
//! statement, slowest feed, longest dwell, travel) and prints as valid ISO words.

use super::harness::{note, Ctx};
use super::rng::Rng;
use novanc::block::Motion;
use novanc::input_text::decode;
use novanc::settings::MachineSettings;
use novanc::tooldata::{sample_magazine, Magazine};
use novanc::translator::{iso_line, Translator, MAX_BLOCKS, MAX_DWELL_S, MIN_FEED};

/// The tools of the sample magazine for each cycle, and numbers that are not tools there.
const DRILLS: &[&str] = &["106", "105", "101", "107", "109", "110", "104", "108"];
const TAPS: &[&str] = &["208", "206", "209", "205"];
const REAMERS: &[&str] = &["301", "303"];
const BARS: &[&str] = &["610", "603"];
const MILLS: &[&str] = &["402", "404", "406", "502"];
const NOT_TOOLS: &[&str] = &["00106", "102", "99999", "0", "100000", "1.5"];

/// Numbers a part programmer would not write, or should not.
const ODD_NUMBERS: &[&str] = &[
    "0",
    "-0",
    ".5",
    "+2.",
    "1000000000",
    "-1000000000",
    "0.0000001",
    "999999999.999",
    "1000000000.0001",
    "1e5",
    ".",
    "-",
    "+",
    "00000000000000000000001",
    "0.0005",
    "0.0004999",
    "1.",
    "-.0",
    "360",
    "-720",
    "1000",
    "1000.001",
    "0.999",
    "10000",
    "10001",
];

/// The names defined so far, per kind.
#[derive(Default)]
struct Names {
    da: Vec<u32>,
    p: Vec<u32>,
    l: Vec<u32>,
    c: Vec<u32>,
    pat: Vec<u32>,
    mac: Vec<u32>,
}

/// A program generator: mostly well-formed programs that translate far, with odd values,
/// undefined names and misused words at the rate `odd` (0 for a clean program).
struct Gen<'r> {
    rng: &'r mut Rng,
    odd: f64,
    n: Names,
}

impl Gen<'_> {
    fn odd(&mut self) -> bool {
        let p = self.odd;
        self.rng.chance(p)
    }

    /// A number: sensible for the place (`lo..=hi`), or odd.
    fn num(&mut self, lo: i64, hi: i64) -> String {
        if self.odd() {
            return self.rng.pick(ODD_NUMBERS).to_string();
        }
        let whole = self.rng.range(lo, hi);
        match self.rng.below(4) {
            0 => format!("{whole}"),
            1 => format!("{whole}.{}", self.rng.below(10)),
            2 => format!("{whole}.{:03}", self.rng.below(1000)),
            _ => format!("{whole}.0"),
        }
    }

    /// A unit separator, with spaces as people type them.
    fn sep(&mut self) -> &'static str {
        self.rng
            .pick::<&str>(&[", ", ",", " , ", "/", " / ", ",  "])
    }

    /// A name to define: the next one, or (odd) one already defined or an odd number.
    fn new_name(&mut self, pick: fn(&mut Names) -> &mut Vec<u32>) -> String {
        let odd = self.odd();
        let which = self.rng.below(2);
        let list = pick(&mut self.n);
        let n = match (odd, which) {
            (true, 0) if !list.is_empty() => list[list.len() / 2],
            (true, _) => [0, 999_999, 1_000_000, 4_294_967_295][list.len() % 4],
            _ => list.last().map_or(1, |l| l.saturating_add(1)),
        };
        pick(&mut self.n).push(n);
        n.to_string()
    }

    /// A name to use: one defined, or (odd, or none defined) one that is not.
    fn use_name(&mut self, pick: fn(&mut Names) -> &mut Vec<u32>) -> String {
        let odd = self.odd();
        let list = pick(&mut self.n).clone();
        if list.is_empty() || odd {
            return self.rng.range(1, 40).to_string();
        }
        self.rng.pick(&list).to_string()
    }

    /// Two different names to use, where there are two.
    fn two(&mut self, pick: fn(&mut Names) -> &mut Vec<u32>) -> (String, String) {
        let a = self.use_name(pick);
        for _ in 0..8 {
            let b = self.use_name(pick);
            if b != a {
                return (a, b);
            }
        }
        (a.clone(), a)
    }

    fn coords(&mut self, three: bool) -> String {
        let (x, y) = (self.num(0, 200), self.num(0, 200));
        if three || self.rng.chance(0.3) {
            let z = self.num(-12, 0);
            format!("({x}, {y}, {z})")
        } else {
            format!("({x}, {y})")
        }
    }

    fn sel(&mut self) -> &'static str {
        self.rng.pick::<&str>(&["XL", "XS", "YL", "YS"])
    }

    fn point_expr(&mut self) -> String {
        match self.rng.below(8) {
            0..=3 => self.coords(false),
            4 | 5 => {
                let (b, dx, dy) = (
                    self.use_name(|n| &mut n.p),
                    self.num(-30, 30),
                    self.num(-30, 30),
                );
                format!("P{b}({dx}, {dy})")
            }
            6 if self.n.l.len() >= 2 => {
                let (a, b) = self.two(|n| &mut n.l);
                format!("L{a}, L{b}")
            }
            6 => self.coords(false),
            _ if self.n.l.is_empty() || self.n.c.is_empty() => self.coords(false),
            _ => {
                let (l, c, s) = (
                    self.use_name(|n| &mut n.l),
                    self.use_name(|n| &mut n.c),
                    self.sel(),
                );
                if self.rng.chance(0.5) {
                    format!("L{l}, C{c}, {s}")
                } else {
                    let (c, c2) = self.two(|n| &mut n.c);
                    format!("C{c}, C{c2}, {s}")
                }
            }
        }
    }

    fn designations(&mut self, mil: bool) -> String {
        let mut v = Vec::new();
        if !self.odd() {
            v.push(format!("DA{}", self.use_name(|n| &mut n.da)));
        }
        for _ in 0..self.rng.range(if mil { 2 } else { 1 }, 6) {
            let d = match self.rng.below(10) {
                0..=3 => format!("P{}", self.use_name(|n| &mut n.p)),
                4 if !self.n.pat.is_empty() || self.odd() => {
                    format!("PAT{}", self.use_name(|n| &mut n.pat))
                }
                5 if !self.n.mac.is_empty() || self.odd() => {
                    format!("MAC{}", self.use_name(|n| &mut n.mac))
                }
                6 if mil && !self.n.c.is_empty() => format!("C{}", self.use_name(|n| &mut n.c)),
                7 => {
                    let (b, dx, dy) = (
                        self.use_name(|n| &mut n.p),
                        self.num(-9, 9),
                        self.num(-9, 9),
                    );
                    let name = self.new_name(|n| &mut n.p);
                    format!("(P{b}({dx}, {dy})=P{name})")
                }
                _ => self.coords(false),
            };
            v.push(d);
        }
        let s = self.sep();
        v.join(s)
    }

    fn cut(&mut self) -> String {
        let (kw, tools, mods): (&str, &[&str], &[&str]) = match self.rng.below(5) {
            0 => ("DRL", DRILLS, &["FR", "SS", "SCL", "SDP", "DW", "DH"]),
            1 => ("TAP", TAPS, &["FR", "SS", "SCL", "SDP"]),
            2 => ("REM", REAMERS, &["FR", "SS", "SCL", "SDP", "DW"]),
            3 => ("BOR", BARS, &["FR", "SS", "SCL", "SDP", "DW"]),
            _ => ("MIL", MILLS, &["FR", "SS", "SCL", "RGT", "LFT"]),
        };
        let tool = if self.odd() {
            self.rng.pick(NOT_TOOLS)
        } else {
            self.rng.pick(tools)
        };
        let mut ms = Vec::new();
        let chamfer = kw == "DRL" && self.rng.chance(0.1);
        if chamfer {
            ms.push(format!("DI{}", self.num(1, 3)));
        }
        if !self.odd() && !chamfer {
            ms.push(format!("DP{}", self.num(8, 30)));
        }
        for _ in 0..self.rng.below(3) {
            let w = if self.odd() {
                *self.rng.pick(&["DI", "DW", "DH", "RGT", "LFT", "DP", "XX"])
            } else {
                *self.rng.pick(mods)
            };
            let m = match w {
                "RGT" | "LFT" => w.to_string(),
                "SDP" if self.rng.chance(0.2) => w.to_string(),
                "SDP" => format!("SDP{}", self.num(0, 1)),
                "SS" => format!("SS{}", self.num(100, 5000)),
                "FR" => format!("FR{}", self.num(1, 800)),
                "DW" => format!("DW{}", self.num(0, 3)),
                "DH" => format!("DH{}", self.num(1, 8)),
                "DI" => format!("DI{}", self.num(1, 3)),
                _ => format!("{w}{}", self.num(0, 12)),
            };
            if !ms.iter().any(|x: &String| x.starts_with(w)) || self.odd() {
                ms.push(m);
            }
        }
        let m = if ms.is_empty() {
            String::new()
        } else {
            let s = self.sep();
            format!("/{}", ms.join(s))
        };
        let d = self.designations(kw == "MIL");
        format!("{kw}, {tool}{m}/{d}")
    }

    fn statement(&mut self) -> String {
        match self.rng.below(16) {
            0 => {
                let base = self.use_name(|n| &mut n.da);
                let name = self.new_name(|n| &mut n.da);
                if self.n.da.len() > 1 && self.rng.chance(0.3) {
                    let v = self.coords(true);
                    format!("DA{name} = DA{base}, {v}")
                } else {
                    let (x, y, z) = (self.num(100, 500), self.num(100, 400), self.num(-480, -300));
                    format!("DA{name} = ({x}, {y}, {z})")
                }
            }
            1..=3 => {
                let e = self.point_expr();
                format!("P{} = {e}", self.new_name(|n| &mut n.p))
            }
            4 => {
                let (a, b) = self.two(|n| &mut n.p);
                let b = if self.rng.chance(0.5) {
                    format!("A{}", self.num(-180, 360))
                } else {
                    format!("P{b}")
                };
                format!("L{} = P{a}, {b}", self.new_name(|n| &mut n.l))
            }
            5 => {
                let (a, b) = self.two(|n| &mut n.p);
                let rest = if self.rng.chance(0.6) {
                    format!("R{}", self.num(5, 80))
                } else {
                    let mut c = self.use_name(|n| &mut n.p);
                    for _ in 0..8 {
                        if c != a && c != b {
                            break;
                        }
                        c = self.use_name(|n| &mut n.p);
                    }
                    format!("P{b}, P{c}")
                };
                format!("C{} = P{a}, {rest}", self.new_name(|n| &mut n.c))
            }
            6 => {
                let nh = if self.rng.chance(0.03) {
                    self.rng
                        .pick(&["1000", "5000", "10000", "9999"])
                        .to_string()
                } else {
                    self.num(1, 24)
                };
                let mut w = vec![
                    format!("NH{nh}"),
                    format!("P{}", self.use_name(|n| &mut n.p)),
                    format!("R{}", self.num(5, 90)),
                ];
                if self.rng.chance(0.9) {
                    w.push(format!("DA{}", self.use_name(|n| &mut n.da)));
                }
                if self.rng.chance(0.5) {
                    w.push(format!("SA{}", self.num(-90, 360)));
                }
                if self.rng.chance(0.4) {
                    w.push(format!("IA{}", self.num(1, 40)));
                }
                for i in (1..w.len()).rev() {
                    let j = self.rng.below(i + 1);
                    w.swap(i, j);
                }
                format!("PAT{} = {}", self.new_name(|n| &mut n.pat), w.join(", "))
            }
            7 => {
                let d = self.designations(false);
                format!("MAC{} = {d}", self.new_name(|n| &mut n.mac))
            }
            8 => {
                let da = if self.rng.chance(0.5) {
                    format!("DA{}, ", self.use_name(|n| &mut n.da))
                } else {
                    String::new()
                };
                let (x, y) = (self.num(0, 500), self.num(0, 400));
                let z = if da.is_empty() {
                    self.num(-420, -250)
                } else {
                    self.num(20, 100)
                };
                format!("GO, {da}{x}, {y}, {z}")
            }
            9 => {
                let (x, y, z) = (self.num(-50, 50), self.num(-50, 50), self.num(-20, 5));
                format!("GD, {x}, {y}, {z}")
            }
            10 => "CL".to_string(),
            11 if !self.n.mac.is_empty() && self.rng.chance(0.3) => {
                // Macros of macros, which double what they stand for.
                let (a, b) = (self.use_name(|n| &mut n.mac), self.use_name(|n| &mut n.mac));
                format!("MAC{} = MAC{a}, MAC{b}", self.new_name(|n| &mut n.mac))
            }
            _ => self.cut(),
        }
    }
}

/// A program from the grammar of docs/language.md: half are clean (they should translate to
/// the end, unless geometry or travel refuses them), half carry odd values and names.
pub fn by_grammar(rng: &mut Rng) -> String {
    let odd = if rng.chance(0.5) { 0.0 } else { 0.02 };
    let mut g = Gen {
        rng,
        odd,
        n: Names::default(),
    };
    let mut out = String::new();
    if g.rng.chance(0.95) {
        out.push_str("DA1 = (200, 150, -450)\nP1 = (40, 30)\nP2 = (120, 30, -2)\nP3 = (80, 90)\n");
        g.n.da.push(1);
        g.n.p.extend([1, 2, 3]);
    }
    for _ in 0..g.rng.range(1, 30) {
        let st = g.statement();
        let st = if g.rng.chance(0.03) {
            st.to_lowercase()
        } else {
            st
        };
        out.push_str(&st);
        if g.rng.chance(0.1) {
            out.push_str(" ; a comment");
        }
        out.push('\n');
    }
    out
}

/// Characters that break things: controls, a byte order mark, separators, letters, digits,
/// non-ASCII, invisible ones.
const ODD_CHARS: &[char] = &[
    '\0', '\u{7}', '\u{1b}', '\t', '\r', '\n', '\u{feff}', '\u{200b}', '\u{a0}', ',', '/', '=',
    '(', ')', ';', '.', '-', '+', 'é', '€', '𝕏', 'P', 'A', 'C', 'D', 'L', '0', '9', ' ', '*', '$',
    '#',
];

/// Tokens to insert.
const TOKENS: &[&str] = &[
    "DA",
    "P",
    "L",
    "C",
    "PAT",
    "MAC",
    "GO",
    "GD",
    "CL",
    "DRL",
    "TAP",
    "REM",
    "MIL",
    "BOR",
    "RGT",
    "LFT",
    "DP",
    "DI",
    "FR",
    "SS",
    "SCL",
    "SDP",
    "DW",
    "DH",
    "NH",
    "SA",
    "IA",
    "R",
    "A",
    "XL",
    "YS",
    "1000000000",
    "0.0000001",
    "IA0",
    "NH10000",
    "((((",
    "))",
    "=P999",
    "MAC1, MAC1",
];

/// Mutates `text`: a few edits of characters, tokens, numbers and lines, sometimes splicing in
/// a line of `other`. Works on characters, so the result is text.
pub fn mutate(rng: &mut Rng, text: &str, other: &str) -> String {
    let mut s: Vec<char> = text.chars().collect();
    for _ in 0..rng.range(1, 6) {
        let at = rng.below(s.len() + 1);
        match rng.below(10) {
            0 if !s.is_empty() => {
                let i = at.min(s.len() - 1);
                s[i] = *rng.pick(ODD_CHARS);
            }
            1 => {
                let t = rng.pick(TOKENS);
                s.splice(at..at, t.chars());
            }
            2 if !s.is_empty() => {
                let end = (at + rng.below(20)).min(s.len());
                s.drain(at.min(end)..end);
            }
            3 | 4 => {
                // Repeat a line, or a number, many times.
                let text: String = s.iter().collect();
                let lines: Vec<&str> = text.lines().collect();
                if let Some(l) = lines.get(rng.below(lines.len().max(1))) {
                    let times = if rng.chance(0.2) {
                        rng.range(50, 400)
                    } else {
                        rng.range(1, 4)
                    };
                    let rep = format!("{l}\n").repeat(times as usize);
                    s.splice(at..at, rep.chars());
                }
            }
            5 => {
                // A number made huge, tiny or odd.
                let text: String = s.iter().collect();
                let digits: Vec<usize> = text
                    .chars()
                    .enumerate()
                    .filter(|(_, c)| c.is_ascii_digit())
                    .map(|(i, _)| i)
                    .collect();
                if let Some(&i) = digits.get(rng.below(digits.len().max(1))) {
                    let n = rng.pick(ODD_NUMBERS);
                    s.splice(i..i + 1, n.chars());
                }
            }
            6 => {
                let lines: Vec<&str> = other.lines().collect();
                if let Some(l) = lines.get(rng.below(lines.len().max(1))) {
                    let l = format!("{l}\n");
                    s.splice(at..at, l.chars());
                }
            }
            7 => {
                let t = *rng.pick(&["\r\n", "\r", "\u{feff}", "\n\n", ";", "(", ")"]);
                s.splice(at..at, t.chars());
            }
            8 if !s.is_empty() => {
                s.truncate(at);
            }
            _ => {
                let c = *rng.pick(ODD_CHARS);
                s.insert(at, c);
            }
        }
    }
    s.into_iter().collect()
}

/// Translates `src` with `magazine` and checks every statement and the error, if any.
pub fn check(src: &str, magazine: &Magazine) -> Result<(), String> {
    let st = MachineSettings::default();
    let mut t = Translator::new(src, magazine.clone(), st.clone(), [0, 0, 0]);
    let mut seq = 0u32;
    let last_line = src.split('\n').count() as u32 + 1;
    while let Some(r) = t.next() {
        match r {
            Ok(s) => {
                if s.blocks.len() > MAX_BLOCKS {
                    return Err(format!("line {}: {} blocks", s.line, s.blocks.len()));
                }
                for b in &s.blocks {
                    if b.seq != seq + 1 {
                        return Err(format!("block N{} after N{seq}", b.seq));
                    }
                    seq = b.seq;
                    let cutting =
                        matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw);
                    if cutting && !(b.feed >= MIN_FEED && b.feed.is_finite()) {
                        return Err(format!("line {}: feed {}", s.line, b.feed));
                    }
                    if b.dwell_ns as f64 > MAX_DWELL_S * 1e9 {
                        return Err(format!("line {}: dwell {} ns", s.line, b.dwell_ns));
                    }
                    if !st.within_travel(b.end) {
                        return Err(format!("line {}: {:?} beyond travel", s.line, b.end));
                    }
                    let iso = iso_line(b, &st);
                    if iso.contains("NaN")
                        || iso.contains("inf")
                        || iso.split(' ').any(|w| w == "F0")
                    {
                        return Err(format!("line {}: bad ISO '{iso}'", s.line));
                    }
                }
            }
            Err(e) => {
                let m = e.to_string();
                if m.contains('\n') || m.len() > 400 || e.line == 0 || e.col == 0 {
                    return Err(format!("bad message: {m:?}"));
                }
                if e.line > last_line {
                    return Err(format!("line {} past the end ({last_line}): {m}", e.line));
                }
                if t.next().is_some() {
                    return Err(format!("the translator went on after {m}"));
                }
                return Ok(());
            }
        }
    }
    Ok(())
}

/// Family `program-grammar`: a program from the grammar, translated and checked.
pub fn grammar_case(rng: &mut Rng, _ctx: &Ctx) -> Result<(), String> {
    let src = by_grammar(rng);
    note("program", &src);
    check(&src, &sample_magazine())
}

/// Family `program-mutation`: a sample (or a grammar program) mutated, as bytes too, decoded
/// as `novanc translate` decodes a file, then translated and checked.
pub fn mutation_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let base = if rng.chance(0.3) {
        by_grammar(rng)
    } else {
        rng.pick(&ctx.programs).clone()
    };
    let other = rng.pick(&ctx.programs).clone();
    let mut src = mutate(rng, &base, &other);
    if rng.chance(0.1) {
        // A byte that is not UTF-8 somewhere: the decoder must name it.
        let mut bytes = src.clone().into_bytes();
        let at = rng.below(bytes.len() + 1);
        bytes.insert(at, *rng.pick(&[0xff, 0xe9, 0xc3, 0x80]));
        note("program bytes", &String::from_utf8_lossy(&bytes));
        match decode(&bytes) {
            Ok(s) => src = s.to_string(),
            Err(e) => {
                // The bad byte may join the bytes after it into a character for a moment, so
                // the first bad byte is within a character's length of where it went in.
                if e.offset > at + 4 || e.line == 0 || e.col == 0 {
                    return Err(format!("bad byte inserted at {at}, reported {e:?}"));
                }
                return Ok(());
            }
        }
    }
    note("program", &src);
    check(&src, &sample_magazine())
}
