//! The recorder writes SPEC §7 MCAP: every topic, every field, every pulse exactly once, read
//! back both with the `mcap` crate and with Python's `mcap` reader (`tests/mcap_check.py`).

use novanc::record::{Event, Recorder};
use novanc::settings::MachineSettings;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

// ---------------------------------------------------------------- a small JSON reader (no serde)

#[derive(Clone, Debug, PartialEq)]
enum Json {
    Null,
    Bool(bool),
    /// Integers keep their exact text; floats are parsed.
    Int(i128),
    Num(f64),
    Str(String),
    Arr(Vec<Json>),
    Obj(BTreeMap<String, Json>),
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn parse(text: &str) -> Result<Json, String> {
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
        };
        let v = p.value()?;
        p.ws();
        if p.i != p.s.len() {
            return Err(format!("trailing text at {}", p.i));
        }
        Ok(v)
    }

    fn ws(&mut self) {
        while self.i < self.s.len() && b" \t\r\n".contains(&self.s[self.i]) {
            self.i += 1;
        }
    }

    fn eat(&mut self, lit: &str) -> Result<(), String> {
        if self.s[self.i..].starts_with(lit.as_bytes()) {
            self.i += lit.len();
            Ok(())
        } else {
            Err(format!("expected {lit} at {}", self.i))
        }
    }

    fn value(&mut self) -> Result<Json, String> {
        self.ws();
        match self.s.get(self.i).copied() {
            Some(b'{') => {
                self.i += 1;
                let mut m = BTreeMap::new();
                self.ws();
                if self.s.get(self.i) == Some(&b'}') {
                    self.i += 1;
                    return Ok(Json::Obj(m));
                }
                loop {
                    self.ws();
                    let Json::Str(k) = self.string()? else {
                        unreachable!()
                    };
                    self.ws();
                    self.eat(":")?;
                    let v = self.value()?;
                    if m.insert(k.clone(), v).is_some() {
                        return Err(format!("duplicate key {k}"));
                    }
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Obj(m));
                        }
                        _ => return Err(format!("bad object at {}", self.i)),
                    }
                }
            }
            Some(b'[') => {
                self.i += 1;
                let mut a = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b']') {
                    self.i += 1;
                    return Ok(Json::Arr(a));
                }
                loop {
                    a.push(self.value()?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Arr(a));
                        }
                        _ => return Err(format!("bad array at {}", self.i)),
                    }
                }
            }
            Some(b'"') => self.string(),
            Some(b't') => self.eat("true").map(|_| Json::Bool(true)),
            Some(b'f') => self.eat("false").map(|_| Json::Bool(false)),
            Some(b'n') => self.eat("null").map(|_| Json::Null),
            Some(_) => self.number(),
            None => Err("unexpected end".into()),
        }
    }

    fn number(&mut self) -> Result<Json, String> {
        let start = self.i;
        while self.i < self.s.len() && b"+-0123456789.eE".contains(&self.s[self.i]) {
            self.i += 1;
        }
        let text = std::str::from_utf8(&self.s[start..self.i]).map_err(|e| e.to_string())?;
        let digits = text.strip_prefix('-').unwrap_or(text);
        if digits.len() > 1 && digits.starts_with('0') && !digits.starts_with("0.") {
            return Err(format!("leading zero in {text}"));
        }
        if let Ok(i) = text.parse::<i128>() {
            return Ok(Json::Int(i));
        }
        text.parse::<f64>()
            .map(Json::Num)
            .map_err(|_| format!("bad number {text:?} at {start}"))
    }

    fn string(&mut self) -> Result<Json, String> {
        self.eat("\"")?;
        let mut out = String::new();
        loop {
            let rest = std::str::from_utf8(&self.s[self.i..]).map_err(|e| e.to_string())?;
            let mut chars = rest.chars();
            let c = chars.next().ok_or("unterminated string")?;
            self.i += c.len_utf8();
            match c {
                '"' => return Ok(Json::Str(out)),
                '\\' => {
                    let e = self.s.get(self.i).copied().ok_or("bad escape")?;
                    self.i += 1;
                    match e {
                        b'"' => out.push('"'),
                        b'\\' => out.push('\\'),
                        b'/' => out.push('/'),
                        b'n' => out.push('\n'),
                        b'r' => out.push('\r'),
                        b't' => out.push('\t'),
                        b'b' => out.push('\u{8}'),
                        b'f' => out.push('\u{c}'),
                        b'u' => {
                            let hex = std::str::from_utf8(&self.s[self.i..self.i + 4])
                                .map_err(|e| e.to_string())?;
                            let code = u32::from_str_radix(hex, 16).map_err(|e| e.to_string())?;
                            self.i += 4;
                            out.push(char::from_u32(code).ok_or("surrogate escape")?);
                        }
                        _ => return Err(format!("bad escape \\{}", e as char)),
                    }
                }
                c if (c as u32) < 0x20 => return Err("raw control character in string".into()),
                c => out.push(c),
            }
        }
    }
}

fn field<'a>(obj: &'a Json, key: &str) -> &'a Json {
    match obj {
        Json::Obj(m) => m
            .get(key)
            .unwrap_or_else(|| panic!("no field {key} in {obj:?}")),
        _ => panic!("not an object: {obj:?}"),
    }
}

fn int(v: &Json) -> i128 {
    match v {
        Json::Int(i) => *i,
        _ => panic!("not an integer: {v:?}"),
    }
}

fn text(v: &Json) -> String {
    match v {
        Json::Str(s) => s.clone(),
        _ => panic!("not a string: {v:?}"),
    }
}

fn num(v: &Json) -> f64 {
    match v {
        Json::Int(i) => *i as f64,
        Json::Num(f) => *f,
        _ => panic!("not a number: {v:?}"),
    }
}

fn arr(v: &Json) -> &[Json] {
    match v {
        Json::Arr(a) => a,
        _ => panic!("not an array: {v:?}"),
    }
}

/// Turns a recorded message back into the event it came from (`t_ns` from the publish time).
fn decode(topic: &str, publish_ns: u64, obj: &Json) -> Event {
    let t_ns = publish_ns;
    match topic {
        "/nc/block" => Event::Block {
            t_ns,
            seq: int(field(obj, "seq")) as u32,
            stmt: int(field(obj, "stmt")) as u32,
            text: text(field(obj, "text")),
        },
        "/nc/position" => {
            let p: Vec<i64> = arr(field(obj, "pulses"))
                .iter()
                .map(|v| int(v) as i64)
                .collect();
            assert_eq!(p.len(), 3);
            for (i, key) in ["x", "y", "z"].iter().enumerate() {
                let mm = num(field(obj, key));
                assert!(
                    (mm - p[i] as f64 * 0.001).abs() < 1e-9,
                    "{key} {mm} vs {}",
                    p[i]
                );
            }
            Event::Position {
                t_ns,
                pulses: [p[0], p[1], p[2]],
            }
        }
        "/nc/pulses" => {
            let axis = match text(field(obj, "axis")).as_str() {
                "X" => 0,
                "Y" => 1,
                "Z" => 2,
                a => panic!("bad axis {a}"),
            };
            let times: Vec<u64> = arr(field(obj, "t_ns"))
                .iter()
                .map(|v| int(v) as u64)
                .collect();
            assert_eq!(
                times.first().copied(),
                Some(t_ns),
                "publish time = first pulse"
            );
            Event::Pulses {
                axis,
                dir: int(field(obj, "dir")) as i8,
                t_ns: times,
            }
        }
        "/nc/state" => Event::State {
            t_ns,
            run: int(field(obj, "run")) as u8,
            op_mode: text(field(obj, "op_mode")),
            data_mode: text(field(obj, "data_mode")),
            feed_override: int(field(obj, "feed_override")) as u32,
            tool: int(field(obj, "tool")) as u32,
            spindle: int(field(obj, "spindle")) as i64,
        },
        "/panel/display" => Event::Display {
            t_ns,
            lines: arr(field(obj, "lines")).iter().map(text).collect(),
        },
        "/panel/event" => Event::PanelEvent {
            t_ns,
            event: text(field(obj, "event")),
        },
        other => panic!("unexpected topic {other}"),
    }
}

// ---------------------------------------------------------------- synthetic runs

/// xorshift64*, seeded.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

fn topic_of(ev: &Event) -> &'static str {
    match ev {
        Event::Block { .. } => "/nc/block",
        Event::Position { .. } => "/nc/position",
        Event::Pulses { .. } => "/nc/pulses",
        Event::State { .. } => "/nc/state",
        Event::Display { .. } => "/panel/display",
        Event::PanelEvent { .. } => "/panel/event",
    }
}

/// A run of `slices` NCBR ticks (5 ms): a block now and then, pulses of every axis in each tick
/// (sent Z, Y, X, so a later axis can start earlier than the batch before it), a position per
/// tick, states, display frames with unicode and characters that need escaping, panel events.
fn synthetic_run(seed: u64, slices: u64) -> Vec<Event> {
    let mut rng = Rng(seed | 1);
    let mut evs = Vec::new();
    let mut pos = [0i64; 3];
    let tick = 5_000_000u64;
    evs.push(Event::PanelEvent {
        t_ns: 0,
        event: "key START".into(),
    });
    evs.push(Event::State {
        t_ns: 0,
        run: 1,
        op_mode: "AUTO".into(),
        data_mode: "RUN".into(),
        feed_override: 100,
        tool: 0,
        spindle: 0,
    });
    for s in 0..slices {
        let t0 = s * tick;
        if s % 7 == 0 {
            evs.push(Event::Block {
                t_ns: t0,
                seq: (s / 7) as u32,
                stmt: (s / 7 + 1) as u32,
                text: format!("N{} G01 X{}. Y-2.5 F300 (\"quoted\" \\ path)", s / 7, s),
            });
        }
        for axis in [2u8, 1, 0] {
            let n = rng.below(400);
            if n == 0 {
                continue;
            }
            let dir: i8 = if rng.below(2) == 0 { 1 } else { -1 };
            let start = t0 + rng.below(tick / 2);
            let step = (tick / 2) / n;
            let times: Vec<u64> = (0..n).map(|k| start + k * step).collect();
            pos[axis as usize] += dir as i64 * n as i64;
            evs.push(Event::Pulses {
                axis,
                dir,
                t_ns: times,
            });
        }
        evs.push(Event::Position {
            t_ns: t0 + tick,
            pulses: pos,
        });
        if s % 10 == 0 {
            evs.push(Event::Display {
                t_ns: t0,
                lines: vec![
                    format!(
                        "X {:>10.3}  Y {:>10.3}",
                        pos[0] as f64 / 1e3,
                        pos[1] as f64 / 1e3
                    ),
                    "ÄÖÜ ß Ø20 ±0.01 µm → «ok» 工具 🛠".into(),
                    "tab\there \"q\" back\\slash \u{1} bell\u{7}".into(),
                    String::new(),
                ],
            });
            evs.push(Event::State {
                t_ns: t0,
                run: 1,
                op_mode: "AUTO".into(),
                data_mode: "RUN".into(),
                feed_override: (s % 150) as u32,
                tool: (s % 24) as u32,
                spindle: if s % 20 == 0 { -1200 } else { 800 },
            });
        }
        if s % 13 == 0 {
            evs.push(Event::PanelEvent {
                t_ns: t0 + 1,
                event: format!("override {}", s % 150),
            });
        }
    }
    evs
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("novanc-{name}-{}.mcap", std::process::id()))
}

fn record(path: &Path, evs: &[Event]) -> novanc::record::RecordSummary {
    let rec = Recorder::start(path, &MachineSettings::default()).expect("start the recorder");
    let sink = rec.sink();
    for ev in evs {
        sink.send(ev.clone());
    }
    rec.finish().expect("finish the recording")
}

/// (topic, log time, publish time, JSON) of every message in file order, with CRCs checked.
fn read_back(path: &Path) -> Vec<(String, u64, u64, Json)> {
    let bytes = std::fs::read(path).expect("read the recording");
    let summary = mcap::Summary::read(&bytes)
        .expect("summary readable")
        .expect("a summary section");
    for ch in summary.channels.values() {
        assert_eq!(ch.message_encoding, "json", "{}", ch.topic);
        let schema = ch.schema.as_ref().expect("every channel has a schema");
        assert_eq!(schema.encoding, "jsonschema", "{}", ch.topic);
        Parser::parse(std::str::from_utf8(&schema.data).unwrap()).expect("schema is JSON");
    }
    assert_eq!(summary.channels.len(), 6, "one channel per topic");
    let stream = mcap::MessageStream::new_with_options(
        &bytes,
        mcap::read::Options::ValidateChunkCrcs.into(),
    )
    .expect("message stream");
    let mut out = Vec::new();
    for m in stream {
        let m = m.expect("a readable message with a good CRC");
        let text = std::str::from_utf8(&m.data).expect("UTF-8 message");
        let json = Parser::parse(text).unwrap_or_else(|e| panic!("{e}: {text}"));
        out.push((m.channel.topic.clone(), m.log_time, m.publish_time, json));
    }
    let stats = summary.stats.expect("statistics");
    assert_eq!(stats.message_count, out.len() as u64);
    out
}

#[test]
fn every_event_reads_back_on_its_topic_and_every_pulse_exactly_once() {
    let path = temp_path("record-readback");
    let evs = synthetic_run(42, 600);
    let summary = record(&path, &evs);
    let msgs = read_back(&path);
    let _ = std::fs::remove_file(&path);

    assert!(!summary.incomplete, "{summary}");
    assert_eq!(summary.dropped, 0);
    assert_eq!(summary.total_messages(), evs.len() as u64);

    // Per topic: the same events, in the order they were sent, with non-decreasing log times.
    let mut sent: BTreeMap<&str, Vec<Event>> = BTreeMap::new();
    for ev in &evs {
        sent.entry(topic_of(ev)).or_default().push(ev.clone());
    }
    let mut got: BTreeMap<&str, Vec<Event>> = BTreeMap::new();
    let mut last_log: BTreeMap<String, u64> = BTreeMap::new();
    let mut clamped = 0;
    for (topic, log, publish, json) in &msgs {
        let last = last_log.entry(topic.clone()).or_insert(0);
        assert!(*log >= *last, "{topic}: log time goes back");
        assert!(*log >= *publish, "log time is never before the event");
        if log > publish {
            clamped += 1;
        }
        *last = *log;
        let t: &str = sent
            .keys()
            .find(|k| **k == topic.as_str())
            .expect("a sent topic");
        got.entry(t)
            .or_default()
            .push(decode(topic, *publish, json));
    }
    assert_eq!(sent.len(), 6, "the synthetic run covers every topic");
    for (topic, evs) in &sent {
        assert_eq!(Some(evs), got.get(topic), "{topic}");
        assert_eq!(summary.count(topic), evs.len() as u64, "{topic}");
    }
    assert!(
        clamped > 0,
        "the run exercises a batch starting before the previous one"
    );

    // Every pulse exactly once: the multiset of (axis, dir, time) is what was sent.
    let pulses = |evs: &[Event]| {
        let mut v: Vec<(u8, i8, u64)> = evs
            .iter()
            .flat_map(|e| match e {
                Event::Pulses { axis, dir, t_ns } => {
                    t_ns.iter().map(|t| (*axis, *dir, *t)).collect::<Vec<_>>()
                }
                _ => Vec::new(),
            })
            .collect();
        v.sort_unstable();
        v
    };
    let sent_pulses = pulses(&sent["/nc/pulses"]);
    assert!(sent_pulses.len() > 50_000, "thousands of pulses");
    assert_eq!(pulses(&got["/nc/pulses"]), sent_pulses);
    assert_eq!(summary.pulses, sent_pulses.len() as u64);
}

// ---------------------------------------------------------------- Python's mcap reader

/// Runs `tests/mcap_check.py`; `None` if python3 or its `mcap` module is missing (a test
/// failure when `CI=true`).
fn python_check(path: &Path, extra: &[&str]) -> Option<(bool, String)> {
    let has_mcap = Command::new("python3")
        .args(["-c", "import mcap"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !has_mcap {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!("python3 with the `mcap` module is required in CI (pip install mcap)");
        }
        eprintln!(
            "\n!!!!! SKIPPED: python3 or its `mcap` module is missing; \
             `python3 -m pip install mcap` to run the Python reader check !!!!!\n"
        );
        return None;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/mcap_check.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(path)
        .args(extra)
        .output()
        .expect("run mcap_check.py");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    Some((out.status.success(), text))
}

const ALL_TOPICS: [&str; 7] = [
    "--expect-topics",
    "/nc/block",
    "/nc/position",
    "/nc/pulses",
    "/nc/state",
    "/panel/display",
    "/panel/event",
];

#[test]
fn python_mcap_reader_accepts_the_recording() {
    let path = temp_path("record-python");
    let evs = synthetic_run(7, 400);
    let summary = record(&path, &evs);
    assert!(!summary.incomplete, "{summary}");
    let mut args = ALL_TOPICS.to_vec();
    args.push("--expect-complete");
    let result = python_check(&path, &args);
    let _ = std::fs::remove_file(&path);
    let Some((ok, text)) = result else { return };
    assert!(ok, "mcap_check.py failed:\n{text}");
    eprintln!("{text}");
    let pulses = summary.pulses;
    assert!(text.contains("OK "), "{text}");
    // The script's per-topic counts match the recorder's.
    for topic in &ALL_TOPICS[1..] {
        let line = text
            .lines()
            .find(|l| l.starts_with(topic) && l.ends_with("messages"))
            .unwrap_or_else(|| panic!("no count for {topic}:\n{text}"));
        let n: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert_eq!(n, summary.count(topic), "{topic}");
    }
    let axes = text.lines().find(|l| l.starts_with("pulses")).unwrap();
    let total: u64 = axes
        .split_whitespace()
        .filter_map(|w| w.parse::<u64>().ok())
        .sum();
    assert_eq!(total, pulses);
}

#[test]
fn python_check_fails_on_a_corrupted_chunk_and_a_missing_topic() {
    let path = temp_path("record-corrupt");
    let evs = synthetic_run(9, 50);
    record(&path, &evs);
    // A missing topic is reported.
    let result = python_check(&path, &["--expect-topics", "/nc/nothing"]);
    let Some((ok, text)) = result else {
        let _ = std::fs::remove_file(&path);
        return;
    };
    assert!(!ok && text.contains("no message on /nc/nothing"), "{text}");
    // One flipped digit inside a pulse time breaks the chunk CRC.
    let mut bytes = std::fs::read(&path).unwrap();
    let at = bytes
        .windows(6)
        .position(|w| w == b"t_ns\":")
        .expect("a pulse message")
        + 8;
    bytes[at] = if bytes[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(&path, &bytes).unwrap();
    let (ok, text) = python_check(&path, &[]).unwrap();
    let _ = std::fs::remove_file(&path);
    assert!(!ok, "a corrupted file passed:\n{text}");
    assert!(text.to_lowercase().contains("crc"), "{text}");
}
