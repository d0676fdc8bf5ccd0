//! The topics Foxglove draws (docs/recording.md, "Foxglove topics"): the tool path as
//! `foxglove.SceneUpdate` line strips and the tool as a cylinder, the spindle as a
//! `foxglove.FrameTransform` from `machine` to `tool`, and the operator's messages and alarms
//! as `foxglove.Log` (an event of its own, `Event::Log`, encoded by `json`).
//!
//! The scene and the transform are derived by the recorder thread from the events it writes
//! anyway (`/nc/block`, `/nc/position`, `/nc/state`), so the pulse core sends nothing more.
//! The schemas are Foxglove's published JSON Schemas, copied from the `@foxglove/schemas`
//! npm package by `tools/foxglove-schemas.sh`; `tests/record_foxglove.rs` checks the copies and
//! every message against the package itself.

use super::json::{push_decimal, push_str, push_u64};
use super::Event;

/// `foxglove.SceneUpdate`, as published.
pub const SCENE_UPDATE_SCHEMA: &str = include_str!("foxglove/SceneUpdate.json");
/// `foxglove.FrameTransform`, as published.
pub const FRAME_TRANSFORM_SCHEMA: &str = include_str!("foxglove/FrameTransform.json");
/// `foxglove.Log`, as published.
pub const LOG_SCHEMA: &str = include_str!("foxglove/Log.json");

/// The fixed frame: machine coordinates, metres (Foxglove's unit).
pub const MACHINE_FRAME: &str = "machine";
/// The spindle's frame: its origin is the position `/nc/position` records (the gauge line).
pub const TOOL_FRAME: &str = "tool";

/// How far apart a kernel's channels are laid out along the machine frame's X, m: channel N's
/// frame `channelN` stands at X = (N − 1) × this, so that the channels' paths (each in its own
/// X/Z, the tool post's coordinates) lie side by side (docs/recording.md "Foxglove topics").
pub const CHANNEL_SPACING_M: f64 = 0.2;

/// `foxglove.Log` levels.
pub mod level {
    /// An operator or program message.
    pub const INFO: u8 = 2;
    /// A refused operator action.
    pub const WARNING: u8 = 3;
    /// An alarm: the run stopped.
    pub const ERROR: u8 = 4;
}

/// The source line an alarm of the pulse core names (`line 12: N5 X TRAVEL LIMIT`), 0 for
/// none.
pub fn alarm_line(alarm: &str) -> u32 {
    alarm
        .strip_prefix("line ")
        .and_then(|r| r.split(':').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or(0)
}

/// How many derived channels there are.
pub const DERIVED: usize = 2;

/// The channels the recorder derives from other events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Derived {
    /// `/foxglove/scene`: the path and the tool.
    Scene,
    /// `/foxglove/tool`: where the spindle is.
    Tool,
}

impl Derived {
    /// Every derived channel, in channel order (after `Topic::ALL`).
    pub const ALL: [Derived; DERIVED] = [Derived::Scene, Derived::Tool];

    /// The MCAP topic name.
    pub fn name(self) -> &'static str {
        match self {
            Derived::Scene => "/foxglove/scene",
            Derived::Tool => "/foxglove/tool",
        }
    }

    /// The schema name.
    pub fn schema_name(self) -> &'static str {
        match self {
            Derived::Scene => "foxglove.SceneUpdate",
            Derived::Tool => "foxglove.FrameTransform",
        }
    }

    /// The JSON Schema.
    pub fn schema(self) -> &'static str {
        match self {
            Derived::Scene => SCENE_UPDATE_SCHEMA,
            Derived::Tool => FRAME_TRANSFORM_SCHEMA,
        }
    }

    /// Index 0..[`DERIVED`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Appends a Foxglove time `{"sec":S,"nsec":N}` of `t_ns`.
pub fn push_time(out: &mut Vec<u8>, t_ns: u64) {
    out.extend_from_slice(b"{\"sec\":");
    push_u64(out, t_ns / 1_000_000_000);
    out.extend_from_slice(b",\"nsec\":");
    push_u64(out, t_ns % 1_000_000_000);
    out.push(b'}');
}

/// What a block's path is drawn as, by its motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stroke {
    /// G00.
    Rapid,
    /// G01, G02, G03: cutting feed.
    Feed,
    /// Anything else: a block with no motion word (M06's move to the tool change height),
    /// jogs and returns before the first block.
    Other,
}

impl Stroke {
    /// The stroke of a block by its `/nc/block` line (the ISO line names every motion's G
    /// code: `N2 G00 X350.000`, docs/recording.md).
    pub fn of(text: &str) -> Stroke {
        for w in text.split_ascii_whitespace() {
            match w {
                "G00" | "G0" => return Stroke::Rapid,
                "G01" | "G1" | "G02" | "G2" | "G03" | "G3" => return Stroke::Feed,
                _ => {}
            }
        }
        Stroke::Other
    }

    /// The word in the entity's metadata.
    pub fn name(self) -> &'static str {
        match self {
            Stroke::Rapid => "rapid",
            Stroke::Feed => "feed",
            Stroke::Other => "other",
        }
    }

    /// RGBA: rapids orange, feeds blue, the rest grey.
    fn color(self) -> &'static [u8] {
        match self {
            Stroke::Rapid => b"{\"r\":1,\"g\":0.5,\"b\":0,\"a\":1}",
            Stroke::Feed => b"{\"r\":0.1,\"g\":0.45,\"b\":1,\"a\":1}",
            Stroke::Other => b"{\"r\":0.6,\"g\":0.6,\"b\":0.6,\"a\":1}",
        }
    }
}

/// Positions of one strip before it is written as its own entity (10 ms apart while moving:
/// a long block shows up a second at a time).
pub const STRIP_POINTS: usize = 100;

/// The most positions a strip's point stands for: a point is dropped when the segment past it
/// passes within `THIN_PULSES` of it and of every position dropped before it, up to this many.
pub const THIN_RUN: usize = 16;

/// How far from the drawn segment a dropped position may lie, pulses.
pub const THIN_PULSES: f64 = 1.0;

/// The least machine time between two tool transforms while moving, ns (Foxglove
/// interpolates between them); a position at rest always gets one.
pub const TOOL_PERIOD_NS: u64 = 40_000_000;

/// The tool drawn when the recording has no data for the T code in the spindle: diameter
/// and length, mm.
pub const UNKNOWN_TOOL_MM: (f64, f64) = (10.0, 50.0);

const IDENTITY: &[u8] = b"{\"x\":0,\"y\":0,\"z\":0,\"w\":1}";

/// Derives `/foxglove/scene` and `/foxglove/tool` from the events of a run.
#[derive(Clone, Debug)]
pub struct Scene {
    pulse_mm: f64,
    /// (T code, cutting diameter, length), mm.
    tools: Vec<(u32, f64, f64)>,
    stroke: Stroke,
    /// The block the strip belongs to, and its line.
    seq: u32,
    text: String,
    /// How many strips this block has written.
    part: u32,
    /// Program positions, pulses; the first is where the strip starts, the last the latest
    /// position.
    points: Vec<[i64; 3]>,
    /// The positions dropped between the last two points.
    dropped: Vec<[i64; 3]>,
    /// Positions since the strip started.
    count: usize,
    /// The time of the last position.
    last_t: u64,
    /// The time of the last tool transform.
    tool_t: Option<u64>,
    /// The T code drawn (None: not drawn yet).
    tool: Option<u32>,
    /// A kernel's channel (1-based): its messages carry `"channel"` first, its path is drawn
    /// in frame `channelN`, its tool post in `channelN/tool`, its entities' ids begin with
    /// `channelN/`. None: the single machine (`machine`, `tool`, no prefix).
    channel: Option<u16>,
    frame: String,
    tool_frame: String,
    prefix: String,
    /// The channel's frame has been placed in `machine` (its first message).
    placed: bool,
    buf: Vec<u8>,
}

impl Scene {
    /// A scene with the tools' sizes (T code, cutting diameter, length, mm).
    pub fn new(pulse_mm: f64, tools: Vec<(u32, f64, f64)>) -> Scene {
        Scene::on(pulse_mm, tools, None)
    }

    /// The scene of a kernel's channel `channel` (1-based; None: the single machine's).
    pub fn on(pulse_mm: f64, tools: Vec<(u32, f64, f64)>, channel: Option<u16>) -> Scene {
        let (frame, tool_frame, prefix) = match channel {
            Some(n) => (
                format!("channel{n}"),
                format!("channel{n}/tool"),
                format!("channel{n}/"),
            ),
            None => (MACHINE_FRAME.into(), TOOL_FRAME.into(), String::new()),
        };
        Scene {
            channel,
            frame,
            tool_frame,
            prefix,
            placed: channel.is_none(),
            pulse_mm,
            tools,
            stroke: Stroke::Other,
            seq: 0,
            text: String::new(),
            part: 0,
            points: Vec::new(),
            dropped: Vec::new(),
            count: 0,
            last_t: 0,
            tool_t: None,
            tool: None,
            buf: Vec::with_capacity(16 * 1024),
        }
    }

    /// The derived messages of one event, each given to `emit` (channel, log time, JSON).
    pub fn derive(&mut self, ev: &Event, emit: &mut dyn FnMut(Derived, u64, &[u8])) {
        if !self.placed {
            if let Event::Block { t_ns, .. }
            | Event::Position { t_ns, .. }
            | Event::State { t_ns, .. } = ev
            {
                self.place(*t_ns, emit);
            }
        }
        match ev {
            Event::Block {
                t_ns, seq, text, ..
            } => {
                self.flush(*t_ns, emit);
                self.stroke = Stroke::of(text);
                self.seq = *seq;
                self.text.clear();
                self.text.push_str(text);
                self.part = 0;
            }
            Event::Position {
                t_ns,
                pulses,
                speed_mm_min,
                ..
            } => {
                let due = self
                    .tool_t
                    .is_none_or(|t| t_ns.saturating_sub(t) >= TOOL_PERIOD_NS);
                if due || *speed_mm_min == 0.0 {
                    self.buf.clear();
                    // The scene is X Y Z; a rotary axis is not drawn.
                    self.transform(*t_ns, &pulses.xyz());
                    emit(Derived::Tool, *t_ns, &self.buf);
                    self.tool_t = Some(*t_ns);
                }
                self.add_point(pulses.xyz());
                self.last_t = *t_ns;
                if self.count >= STRIP_POINTS {
                    self.flush(*t_ns, emit);
                }
            }
            Event::State { t_ns, tool, .. } if self.tool != Some(*tool) => {
                self.tool = Some(*tool);
                self.buf.clear();
                self.tool_entity(*t_ns, *tool);
                emit(Derived::Scene, *t_ns, &self.buf);
            }
            _ => {}
        }
    }

    /// A channel's frame placed in `machine`, once, at its first message.
    fn place(&mut self, t_ns: u64, emit: &mut dyn FnMut(Derived, u64, &[u8])) {
        self.placed = true;
        let n = self.channel.map_or(1, u64::from);
        self.buf.clear();
        self.open();
        self.buf.extend_from_slice(b"\"timestamp\":");
        push_time(&mut self.buf, t_ns);
        self.buf
            .extend_from_slice(b",\"parent_frame_id\":\"machine\",\"child_frame_id\":");
        let frame = std::mem::take(&mut self.frame);
        push_str(&mut self.buf, &frame);
        self.frame = frame;
        self.buf.extend_from_slice(b",\"translation\":{\"x\":");
        push_decimal(&mut self.buf, (n - 1) as f64 * CHANNEL_SPACING_M, 9);
        self.buf
            .extend_from_slice(b",\"y\":0,\"z\":0},\"rotation\":");
        self.buf.extend_from_slice(IDENTITY);
        self.buf.push(b'}');
        emit(Derived::Tool, t_ns, &self.buf);
    }

    /// Opens a message: `{`, and a channel's `"channel":N,` first.
    fn open(&mut self) {
        self.buf.push(b'{');
        if let Some(n) = self.channel {
            self.buf.extend_from_slice(b"\"channel\":");
            push_u64(&mut self.buf, u64::from(n));
            self.buf.push(b',');
        }
    }

    /// Appends `s` as a JSON string.
    fn push_owned(&mut self, s: &str) {
        push_str(&mut self.buf, s);
    }

    /// Adds a position to the strip: the last point is replaced when the segment to `p`
    /// passes within `THIN_PULSES` of it and of the positions it already stood for (a straight
    /// move needs no point between its ends; an arc keeps one wherever the chord would leave the
    /// path by more than a pulse).
    fn add_point(&mut self, p: [i64; 3]) {
        if self.points.last() == Some(&p) {
            return;
        }
        self.count += 1;
        let n = self.points.len();
        if n >= 2 && self.dropped.len() < THIN_RUN {
            let (a, b) = (self.points[n - 2], self.points[n - 1]);
            if near(a, p, b) && self.dropped.iter().all(|&q| near(a, p, q)) {
                self.dropped.push(b);
                self.points[n - 1] = p;
                return;
            }
        }
        self.dropped.clear();
        self.points.push(p);
    }

    /// Writes the strip so far (if it has a segment) at `t_ns`; the next one starts where it
    /// ended.
    pub fn flush(&mut self, t_ns: u64, emit: &mut dyn FnMut(Derived, u64, &[u8])) {
        if self.points.len() >= 2 {
            self.buf.clear();
            self.strip(t_ns.max(self.last_t));
            emit(Derived::Scene, t_ns.max(self.last_t), &self.buf);
            self.part += 1;
        }
        if let Some(&last) = self.points.last() {
            self.points.clear();
            self.points.push(last);
        }
        self.dropped.clear();
        self.count = 0;
    }

    /// Appends a length of `pulses` in metres (9 decimals: a nanometre).
    fn push_m(&mut self, pulses: i64) {
        push_decimal(&mut self.buf, pulses as f64 * self.pulse_mm / 1000.0, 9);
    }

    fn push_xyz(&mut self, p: &[i64; 3]) {
        self.buf.extend_from_slice(b"{\"x\":");
        self.push_m(p[0]);
        self.buf.extend_from_slice(b",\"y\":");
        self.push_m(p[1]);
        self.buf.extend_from_slice(b",\"z\":");
        self.push_m(p[2]);
        self.buf.push(b'}');
    }

    /// `foxglove.FrameTransform`: `tool` at the position, in `machine`.
    fn transform(&mut self, t_ns: u64, p: &[i64; 3]) {
        self.open();
        self.buf.extend_from_slice(b"\"timestamp\":");
        push_time(&mut self.buf, t_ns);
        self.buf.extend_from_slice(b",\"parent_frame_id\":");
        let (frame, tool) = (self.frame.clone(), self.tool_frame.clone());
        self.push_owned(&frame);
        self.buf.extend_from_slice(b",\"child_frame_id\":");
        self.push_owned(&tool);
        self.buf.extend_from_slice(b",\"translation\":");
        self.push_xyz(p);
        self.buf.extend_from_slice(b",\"rotation\":");
        self.buf.extend_from_slice(IDENTITY);
        self.buf.push(b'}');
    }

    /// The start of a `foxglove.SceneUpdate` with one entity, up to its metadata.
    fn entity_head(&mut self, t_ns: u64, frame: &str, id: &str, frame_locked: bool) {
        self.open();
        self.buf
            .extend_from_slice(b"\"deletions\":[],\"entities\":[{\"timestamp\":");
        push_time(&mut self.buf, t_ns);
        self.buf.extend_from_slice(b",\"frame_id\":");
        push_str(&mut self.buf, frame);
        self.buf.extend_from_slice(b",\"id\":");
        push_str(&mut self.buf, id);
        self.buf
            .extend_from_slice(b",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":");
        self.buf
            .extend_from_slice(if frame_locked { b"true" } else { b"false" });
    }

    /// A strip entity: `N<seq>` (its first strip) or `N<seq>.<part>`.
    fn strip(&mut self, t_ns: u64) {
        let id = if self.part == 0 {
            format!("{}N{}", self.prefix, self.seq)
        } else {
            format!("{}N{}.{}", self.prefix, self.seq, self.part)
        };
        let frame = self.frame.clone();
        self.entity_head(t_ns, &frame, &id, false);
        self.buf
            .extend_from_slice(b",\"metadata\":[{\"key\":\"block\",\"value\":");
        let text = std::mem::take(&mut self.text);
        push_str(&mut self.buf, &text);
        self.text = text;
        self.buf
            .extend_from_slice(b"},{\"key\":\"motion\",\"value\":\"");
        self.buf.extend_from_slice(self.stroke.name().as_bytes());
        self.buf.extend_from_slice(
            b"\"}],\"arrows\":[],\"cubes\":[],\"spheres\":[],\"cylinders\":[],\"lines\":[{\"type\":0,\"pose\":{\"position\":{\"x\":0,\"y\":0,\"z\":0},\"orientation\":",
        );
        self.buf.extend_from_slice(IDENTITY);
        self.buf
            .extend_from_slice(b"},\"thickness\":2,\"scale_invariant\":true,\"points\":[");
        let points = std::mem::take(&mut self.points);
        for (i, p) in points.iter().enumerate() {
            if i > 0 {
                self.buf.push(b',');
            }
            self.push_xyz(p);
        }
        self.points = points;
        self.buf.extend_from_slice(b"],\"color\":");
        self.buf.extend_from_slice(self.stroke.color());
        self.buf.extend_from_slice(
            b",\"colors\":[],\"indices\":[]}],\"triangles\":[],\"texts\":[],\"models\":[]}]}",
        );
    }

    /// The tool in the spindle: a cylinder hanging from the gauge line by the tool's length
    /// (entity `tool`, in frame `tool`, following it); none for T0 (a deletion). A channel's
    /// tool (a lathe's tool post) is the same cylinder lying along +X from the tip, in
    /// `channelN/tool` (entity `channelN/tool`).
    fn tool_entity(&mut self, t_ns: u64, t: u32) {
        let id = format!("{}tool", self.prefix);
        if t == 0 {
            self.open();
            self.buf
                .extend_from_slice(b"\"deletions\":[{\"timestamp\":");
            push_time(&mut self.buf, t_ns);
            self.buf.extend_from_slice(b",\"type\":0,\"id\":");
            self.push_owned(&id);
            self.buf.extend_from_slice(b"}],\"entities\":[]}");
            return;
        }
        let (dia, len) = self
            .tools
            .iter()
            .find(|(n, ..)| *n == t)
            .map(|&(_, d, l)| (d, l))
            .filter(|&(d, l)| d > 0.0 && l > 0.0 && d.is_finite() && l.is_finite())
            .unwrap_or(UNKNOWN_TOOL_MM);
        let frame = self.tool_frame.clone();
        self.entity_head(t_ns, &frame, &id, true);
        self.buf
            .extend_from_slice(b",\"metadata\":[{\"key\":\"T\",\"value\":\"");
        push_u64(&mut self.buf, t as u64);
        self.buf.extend_from_slice(
            b"\"}],\"arrows\":[],\"cubes\":[],\"spheres\":[],\"cylinders\":[{\"pose\":{\"position\":{\"x\":",
        );
        if self.channel.is_some() {
            // Along +X: the cylinder's axis (its Z) turned 90° about Y.
            push_decimal(&mut self.buf, len / 2000.0, 9);
            self.buf.extend_from_slice(
                b",\"y\":0,\"z\":0},\"orientation\":{\"x\":0,\"y\":0.707106781,\"z\":0,\"w\":0.707106781}",
            );
        } else {
            self.buf.extend_from_slice(b"0,\"y\":0,\"z\":");
            push_decimal(&mut self.buf, -len / 2000.0, 9);
            self.buf.extend_from_slice(b"},\"orientation\":");
            self.buf.extend_from_slice(IDENTITY);
        }
        self.buf.extend_from_slice(b"},\"size\":{\"x\":");
        push_decimal(&mut self.buf, dia / 1000.0, 9);
        self.buf.extend_from_slice(b",\"y\":");
        push_decimal(&mut self.buf, dia / 1000.0, 9);
        self.buf.extend_from_slice(b",\"z\":");
        push_decimal(&mut self.buf, len / 1000.0, 9);
        self.buf.extend_from_slice(
            b"},\"bottom_scale\":1,\"top_scale\":1,\"color\":{\"r\":0.8,\"g\":0.8,\"b\":0.85,\"a\":0.9}}],\"lines\":[],\"triangles\":[],\"texts\":[],\"models\":[]}]}",
        );
    }
}

/// Whether `q` lies within `THIN_PULSES` of the segment from `a` to `b` (pulses).
fn near(a: [i64; 3], b: [i64; 3], q: [i64; 3]) -> bool {
    let d = |u: [i64; 3], v: [i64; 3]| {
        [
            (v[0] - u[0]) as f64,
            (v[1] - u[1]) as f64,
            (v[2] - u[2]) as f64,
        ]
    };
    let (ab, aq) = (d(a, b), d(a, q));
    let len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    if len2 == 0.0 {
        return false;
    }
    let t = ((aq[0] * ab[0] + aq[1] * ab[1] + aq[2] * ab[2]) / len2).clamp(0.0, 1.0);
    let e = [aq[0] - t * ab[0], aq[1] - t * ab[1], aq[2] - t * ab[2]];
    e[0] * e[0] + e[1] * e[1] + e[2] * e[2] <= THIN_PULSES * THIN_PULSES
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alarm_lines() {
        assert_eq!(alarm_line("line 12: N5 X TRAVEL LIMIT"), 12);
        assert_eq!(alarm_line("EMERGENCY STOP: pulses stopped; press RESET"), 0);
        assert_eq!(alarm_line("line x: what"), 0);
    }

    #[test]
    fn strokes_by_the_blocks_motion_word() {
        assert_eq!(Stroke::of("N2 G00 X350.000 Y130.000"), Stroke::Rapid);
        assert_eq!(Stroke::of("N5 G01 Z-265.000 F60"), Stroke::Feed);
        assert_eq!(Stroke::of("N7 G17 G02 X1. Y2. I0 J1. F100"), Stroke::Feed);
        assert_eq!(Stroke::of("N1 T01 M06"), Stroke::Other);
        assert_eq!(Stroke::of("N9 G04 P1.000"), Stroke::Other);
    }

    #[test]
    fn strips_join_and_follow_the_positions() {
        let mut s = Scene::new(0.001, vec![(1, 20.0, 100.0)]);
        let mut out: Vec<(Derived, u64, String)> = Vec::new();
        let mut emit =
            |d: Derived, t: u64, b: &[u8]| out.push((d, t, String::from_utf8(b.to_vec()).unwrap()));
        let pos = |t_ns, x| Event::Position {
            t_ns,
            pulses: [x, 0, -1].into(),
            held: [0; 3].into(),
            speed_mm_min: 0.0,
        };
        s.derive(
            &Event::Block {
                t_ns: 0,
                seq: 1,
                stmt: 1,
                text: "N1 G00 X1.".into(),
            },
            &mut emit,
        );
        for i in 0..=(STRIP_POINTS as i64) {
            s.derive(&pos(i as u64 * 10, i * 10), &mut emit);
        }
        s.flush(5_000_000_000, &mut emit);
        let scenes: Vec<_> = out.iter().filter(|m| m.0 == Derived::Scene).collect();
        assert_eq!(scenes.len(), 2, "{scenes:?}");
        assert!(scenes[0].2.contains("\"id\":\"N1\""));
        assert!(scenes[1].2.contains("\"id\":\"N1.1\""));
        // The second strip starts where the first ended: x = 99 × 10 µm.
        assert!(scenes[1]
            .2
            .contains("\"points\":[{\"x\":0.00099,\"y\":0,\"z\":-0.000001}"));
        assert_eq!(scenes[1].1, 5_000_000_000);
        let tools = out.iter().filter(|m| m.0 == Derived::Tool).count();
        assert_eq!(
            tools,
            STRIP_POINTS + 1,
            "at rest (speed 0) every position has one"
        );
        assert!(out[1]
            .2
            .starts_with("{\"timestamp\":{\"sec\":0,\"nsec\":10},"));
        // A straight move: a point for every THIN_RUN + 1 positions, the ends kept.
        let points = scenes[0].2.split("\"points\":").nth(1).unwrap();
        assert_eq!(points.matches("{\"x\":").count(), 7, "{points}");
    }

    #[test]
    fn an_arc_keeps_every_position_within_a_pulse_and_moving_tools_are_thinned() {
        let mut s = Scene::new(0.001, Vec::new());
        let r = 10_000.0;
        let circle: Vec<[i64; 3]> = (0..=90)
            .map(|k| {
                let a = (k as f64).to_radians() * 0.5;
                [
                    (r * a.cos()).round() as i64,
                    (r * a.sin()).round() as i64,
                    0,
                ]
            })
            .collect();
        let mut tools = 0;
        for (k, p) in circle.iter().enumerate() {
            s.derive(
                &Event::Position {
                    t_ns: k as u64 * 10_000_000,
                    pulses: (*p).into(),
                    held: [0; 3].into(),
                    speed_mm_min: 600.0,
                },
                &mut |d, _, _| tools += usize::from(d == Derived::Tool),
            );
        }
        // One transform per 40 ms of motion: 91 positions 10 ms apart.
        assert_eq!(tools, 23);
        let kept = s.points.clone();
        assert!(
            kept.len() > 2 && kept.len() < circle.len(),
            "{}",
            kept.len()
        );
        assert_eq!((kept[0], kept[kept.len() - 1]), (circle[0], circle[90]));
        for q in &circle {
            assert!(
                kept.windows(2).any(|w| near(w[0], w[1], *q)),
                "{q:?} is more than a pulse from the strip"
            );
        }
    }
}
