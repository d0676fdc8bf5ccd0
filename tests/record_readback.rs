//! Read-back with the `mcap` crate: every event comes back on its topic with every field, in
//! order, with non-decreasing log times, and every pulse appears exactly once.

mod common;

use novanc::record::testkit::synthetic_run;
use novanc::record::{Event, Recorder, Topic, TOPICS};
use novanc::settings::MachineSettings;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
/// The `pulses` counters of a message, checking that its `x`, `y`, `z` are them in mm.
fn place(obj: &Json) -> [i64; 3] {
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
    [p[0], p[1], p[2]]
}

fn flag(v: &Json) -> bool {
    match v {
        Json::Bool(b) => *b,
        v => panic!("not a boolean: {v:?}"),
    }
}

fn decode(topic: &str, publish_ns: u64, obj: &Json) -> Event {
    let t_ns = publish_ns;
    match topic {
        "/nc/block" => Event::Block {
            t_ns,
            seq: int(field(obj, "seq")) as u32,
            stmt: int(field(obj, "stmt")) as u32,
            text: text(field(obj, "text")),
        },
        "/nc/position" => Event::Position {
            t_ns,
            pulses: place(obj).into(),
            // The counters and x, y, z agree (`place` checks it): nothing held back.
            held: Default::default(),
            speed_mm_min: num(field(obj, "speed")),
        },
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
            switches: novanc::record::Switches {
                rapid_override: int(field(obj, "rapid_override")) as u32,
                spindle_override: int(field(obj, "spindle_override")) as u32,
                dry_run: flag(field(obj, "dry_run")),
                machine_lock: flag(field(obj, "machine_lock")),
                z_neglect: flag(field(obj, "z_neglect")),
                override_locked: flag(field(obj, "override_locked")),
            },
        },
        "/panel/display" => Event::Display {
            t_ns,
            lines: arr(field(obj, "lines")).iter().map(text).collect(),
        },
        "/panel/event" => Event::PanelEvent {
            t_ns,
            event: text(field(obj, "event")),
        },
        "/nc/io" => Event::Io {
            t_ns,
            seq: int(field(obj, "seq")) as u32,
            stmt: int(field(obj, "stmt")) as u32,
            digital: text(field(obj, "kind")) == "digital",
            index: int(field(obj, "index")) as u8,
            value: num(field(obj, "value")),
            synced: match field(obj, "synced") {
                Json::Bool(b) => *b,
                v => panic!("synced is not a boolean: {v:?}"),
            },
            // `dir` is on inputs only ("in"); an output has none.
            input: match obj {
                Json::Obj(m) => match m.get("dir") {
                    None => false,
                    Some(d) => match text(d).as_str() {
                        "in" => true,
                        v => panic!("dir is not \"in\": {v}"),
                    },
                },
                _ => false,
            },
        },
        "/nc/probe" => {
            let flag = |k: &str| match field(obj, k) {
                Json::Bool(b) => *b,
                v => panic!("{k} is not a boolean: {v:?}"),
            };
            Event::Probe {
                t_ns,
                seq: int(field(obj, "seq")) as u32,
                stmt: int(field(obj, "stmt")) as u32,
                pulses: place(obj).into(),
                tripped: flag("tripped"),
                at_start: flag("at_start"),
            }
        }
        "/foxglove/log" => {
            let time = field(obj, "timestamp");
            assert_eq!(
                int(field(time, "sec")) as u64 * 1_000_000_000 + int(field(time, "nsec")) as u64,
                t_ns,
                "the timestamp is the log time"
            );
            Event::Log {
                t_ns,
                level: int(field(obj, "level")) as u8,
                name: text(field(obj, "name")),
                message: text(field(obj, "message")),
                file: text(field(obj, "file")),
                line: int(field(obj, "line")) as u32,
            }
        }
        other => panic!("unexpected topic {other}"),
    }
}

fn temp_path(name: &str) -> PathBuf {
    common::temp_path(&format!("{name}.mcap"))
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
    assert_eq!(
        summary.channels.len(),
        TOPICS + novanc::record::foxglove::DERIVED,
        "one channel per topic, and the derived Foxglove ones"
    );
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

    // Per topic: the same events, in the order they were sent; log time = the event's machine
    // time, non-decreasing on every topic but /nc/pulses (batches of different axes interleave).
    let mut sent: BTreeMap<&str, Vec<Event>> = BTreeMap::new();
    for ev in &evs {
        sent.entry(Topic::of(ev).name())
            .or_default()
            .push(ev.clone());
    }
    let mut got: BTreeMap<&str, Vec<Event>> = BTreeMap::new();
    let mut last_log: BTreeMap<String, u64> = BTreeMap::new();
    let mut out_of_order = 0;
    let derived = |t: &str| {
        novanc::record::foxglove::Derived::ALL
            .iter()
            .any(|d| d.name() == t)
    };
    for (topic, log, publish, json) in msgs.iter().filter(|m| !derived(&m.0)) {
        let last = last_log.entry(topic.clone()).or_insert(0);
        if topic == "/nc/pulses" {
            if *log < *last {
                out_of_order += 1;
            }
        } else {
            assert!(*log >= *last, "{topic}: log time goes back");
        }
        assert_eq!(*log, *publish, "log time is the event's machine time");
        *last = *log;
        let t: &str = sent
            .keys()
            .find(|k| **k == topic.as_str())
            .expect("a sent topic");
        got.entry(t)
            .or_default()
            .push(decode(topic, *publish, json));
    }
    assert_eq!(sent.len(), TOPICS, "the synthetic run covers every topic");
    for (topic, evs) in &sent {
        assert_eq!(Some(evs), got.get(topic), "{topic}");
        assert_eq!(summary.count(topic), evs.len() as u64, "{topic}");
    }
    assert!(
        out_of_order > 0,
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
