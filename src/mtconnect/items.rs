//! The data items and their values, derived from the pulse core's status snapshot and the
//! console's modes (the mapping is in docs/mtconnect.md).

use super::Key;
use crate::panel_model::OpMode;
use crate::pulse_core::{EndCause, Status};

/// What the adapter needs from the console for one path besides the core's status.
#[derive(Clone, Debug)]
pub struct Modes {
    /// The ControllerMode value of the mode selector ([`controller_mode`], both machines').
    pub mode: &'static str,
    /// The program in program memory.
    pub program: String,
    /// Runs that reached the end of their program (M02/M30) since the console opened (the
    /// lathe: the channel's part count).
    pub partcount: u64,
    /// The `wpo` table ([`wpo_table`]): formatted once per change of the offsets, not at
    /// every change of state. None: the path has no work offsets (the lathe).
    pub wpo: Option<String>,
    /// A program that does not translate: its message (the `logic_program` condition).
    pub program_alarm: Option<String>,
    /// mm per pulse.
    pub pulse_mm: f64,
    /// What is subtracted from the axis position (machine mm, a rotary axis's degrees) to give
    /// the work position POS shows: the active system's zero with G92, and on Z the tool length
    /// in force (`console::pages::pos::work_origin`, `rotary_work_offset`), X Y Z A B C.
    pub work_origin: [f64; crate::block::MAX_AXES],
    /// The rotary axes the path has besides X Y Z (`MachineSettings::rotary_mask`: A 1, B 2,
    /// C 4): each has its `act` and `mach` items, in degrees.
    pub rotary_mask: u8,
    /// The `tooloffsets` table ([`tool_table`]). None: not sent (the lathe).
    pub tooloffsets: Option<String>,
    /// The path stands at a sync point waiting for another (a lathe channel): Execution WAIT.
    pub waiting: bool,
    /// A fault of the path besides the core's alarm (a lathe channel's injected fault): the
    /// `motion_program` condition, and Execution STOPPED.
    pub fault: Option<String>,
    /// The controller's `message`: the operator's message line as the console shows it, the
    /// lathe's as the centre's (None: no console, `novanc run`). Before stop 51 the centre sent
    /// the pulse core's latest notice there, a lathe its console's message line.
    pub message: Option<String>,
}

/// The keys of one path's data items: the mill's names, prefixed `pN_` on a device of several
/// paths (the lathe's channels), and the axes it has.
#[derive(Clone, Debug)]
pub struct PathKeys {
    prefix: String,
    /// Index into the status's axes, and the axis letter of the keys (`Xact`, `Xmach`; a rotary
    /// axis's `Aact`, `Amach` in degrees).
    axes: &'static [(usize, &'static str)],
}

/// The mill's axes for each set of rotary axes (A 1, B 2, C 4): made once, so that a snapshot
/// allocates no key list.
const MILL_AXES: [&[(usize, &str)]; 8] = [
    &[(0, "X"), (1, "Y"), (2, "Z")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (3, "A")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (4, "B")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (3, "A"), (4, "B")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (5, "C")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (3, "A"), (5, "C")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (4, "B"), (5, "C")],
    &[(0, "X"), (1, "Y"), (2, "Z"), (3, "A"), (4, "B"), (5, "C")],
];

impl PathKeys {
    /// The mill's one path: X, Y, Z and the rotary axes of `rotary_mask` (A 1, B 2, C 4),
    /// keys unprefixed.
    pub fn mill(rotary_mask: u8) -> PathKeys {
        PathKeys {
            prefix: String::new(),
            axes: MILL_AXES[usize::from(rotary_mask & 7)],
        }
    }

    /// Path `n` (1-based) of a lathe: X and Z, every key prefixed `pN_`.
    pub fn lathe(n: usize) -> PathKeys {
        PathKeys {
            prefix: format!("p{n}_"),
            axes: &[(0, "X"), (2, "Z")],
        }
    }

    /// The path's axes: index into the status's axes, and letter.
    pub fn axes(&self) -> &[(usize, &'static str)] {
        self.axes
    }

    /// The prefix of the path's keys (`p2_`; the mill's none).
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    fn key(&self, k: &'static str) -> Key {
        if self.prefix.is_empty() {
            Key::Borrowed(k)
        } else {
            Key::Owned(format!("{}{k}", self.prefix))
        }
    }

    fn axis_key(&self, axis: &str, what: &str) -> Key {
        Key::Owned(format!("{}{axis}{what}", self.prefix))
    }
}

const WPO: [&str; 6] = ["G54", "G55", "G56", "G57", "G58", "G59"];

/// A condition value, appended to `out`: `LEVEL|native_code|native_severity|qualifier|message`,
/// each field escaped.
fn condition(out: &mut String, fault: Option<(&str, &str)>) {
    match fault {
        None => out.push_str("NORMAL||||"),
        Some((code, msg)) => {
            out.push_str("FAULT|");
            out.push_str(&super::shdr::escape(code));
            out.push_str("|||");
            out.push_str(&super::shdr::escape(msg));
        }
    }
}

/// The MTConnect Execution of the snapshot.
pub fn execution(s: &Status) -> &'static str {
    if s.estop || s.alarm.is_some() {
        return "STOPPED";
    }
    if s.hold && s.run != 0 {
        return "FEED_HOLD";
    }
    if s.run != 0 {
        if s.single_block && !s.in_block && !s.moving && s.job.is_some() {
            return "INTERRUPTED";
        }
        return "ACTIVE";
    }
    if s.job.is_some() {
        return "INTERRUPTED";
    }
    match s.last_end.as_ref().map(|e| &e.cause) {
        Some(EndCause::ProgramEnd) if s.program_end => "PROGRAM_COMPLETED",
        _ => "READY",
    }
}

/// The MTConnect Execution of a path: [`execution`], and STOPPED for a fault, WAIT at a sync
/// point (a feed hold there is FEED_HOLD).
pub fn path_execution(s: &Status, m: &Modes) -> &'static str {
    let e = execution(s);
    if m.fault.is_some() && e != "STOPPED" {
        return "STOPPED";
    }
    if m.waiting && matches!(e, "ACTIVE" | "INTERRUPTED") {
        return "WAIT";
    }
    e
}

/// The MTConnect ControllerMode of the selector.
pub fn controller_mode(op: OpMode) -> &'static str {
    match op {
        OpMode::Auto => "AUTOMATIC",
        OpMode::Single => "SEMI_AUTOMATIC",
        OpMode::Mdi => "MANUAL_DATA_INPUT",
        OpMode::Data => "EDIT",
        OpMode::Continuous | OpMode::Handle | OpMode::Step => "MANUAL",
    }
}

/// The `wpo` table of the work offsets G54–G59 (machine mm, a rotary axis's degrees) on the
/// machine's `axes` (indices into X Y Z A B C): `G54={X=… Y=… Z=…} G55=…`, `G54={X=… Y=… Z=…
/// C=…}` on a machine with C (since stop 54).
pub fn wpo_table(offsets: &[[f64; crate::block::MAX_AXES]; 6], axes: &[usize]) -> String {
    WPO.iter()
        .zip(offsets.iter())
        .map(|(n, o)| {
            let cells: Vec<String> = axes
                .iter()
                .map(|&a| format!("{}={:.3}", crate::settings::AXIS_NAMES[a], o[a]))
                .collect();
            format!("{n}={{{}}}", cells.join(" "))
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The `tooloffsets` table of the tool file by T code (set length, radius, length wear, radius
/// wear, mm): `T1={LENGTH=… RADIUS=… LENGTH_WEAR=… RADIUS_WEAR=…} T2=…`.
pub fn tool_table(tools: &[(u32, [f64; 4])]) -> String {
    tools
        .iter()
        .map(|(t, [len, rad, wl, wr])| {
            format!(
                "T{t}={{LENGTH={len:.3} RADIUS={rad:.3} LENGTH_WEAR={wl:.3} RADIUS_WEAR={wr:.3}}}"
            )
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Every data item of the mill (the controller's and its one path's) and its value.
pub fn items(s: &Status, m: &Modes) -> Vec<(Key, String)> {
    let mut v = controller_items(s.estop, s.alarm.as_deref(), m.message.as_deref());
    v.extend(path_items(s, m, &PathKeys::mill(m.rotary_mask)));
    v
}

/// The controller's data items, once per device: `avail`, `estop`, the `system` condition
/// (E-STOP's alarm while it is in force) and the operator `message`.
pub fn controller_items(
    estop: bool,
    alarm: Option<&str>,
    message: Option<&str>,
) -> Vec<(Key, String)> {
    let c = Controller {
        estop,
        alarm,
        message,
    };
    CONTROLLER
        .iter()
        .map(|it| {
            let mut v = String::new();
            it.write(&c, &mut v);
            (Key::Borrowed(it.key()), v)
        })
        .collect()
}

/// Every data item of one path and its value, in a fixed order, keyed by `k`.
pub fn path_items(s: &Status, m: &Modes, k: &PathKeys) -> Vec<(Key, String)> {
    PathItem::list(k, m)
        .into_iter()
        .map(|it| {
            let mut v = String::new();
            it.write(s, m, k, &mut v);
            (it.key(k), v)
        })
        .collect()
}

/// What the controller's items are made of.
struct Controller<'a> {
    estop: bool,
    alarm: Option<&'a str>,
    message: Option<&'a str>,
}

/// A data item of the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ControllerItem {
    Avail,
    Estop,
    System,
    Message,
}

/// The controller's items in the order sent.
const CONTROLLER: [ControllerItem; 4] = [
    ControllerItem::Avail,
    ControllerItem::Estop,
    ControllerItem::System,
    ControllerItem::Message,
];

impl ControllerItem {
    fn key(self) -> &'static str {
        match self {
            ControllerItem::Avail => "avail",
            ControllerItem::Estop => "estop",
            ControllerItem::System => "system",
            ControllerItem::Message => "message",
        }
    }

    /// Appends the item's value to `out`.
    fn write(self, c: &Controller, out: &mut String) {
        match self {
            ControllerItem::Avail => out.push_str("AVAILABLE"),
            ControllerItem::Estop => out.push_str(if c.estop { "TRIGGERED" } else { "ARMED" }),
            ControllerItem::System => {
                condition(out, c.alarm.filter(|_| c.estop).map(|a| ("ESTOP", a)))
            }
            ControllerItem::Message => {
                out.push('|');
                out.push_str(&super::shdr::escape(c.message.unwrap_or("")));
            }
        }
    }
}

/// Where a path's data item stands in the device model (`devices::xml`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Place {
    /// Under the path's axis (its place in `PathKeys::axes`).
    Axis(usize),
    /// Under the path's spindle.
    Spindle,
    /// Under the path itself.
    Path,
}

/// A path's data items for the device file: where each stands, its id (the key sent) and its
/// element's other attributes, in the order sent; `tables`: with `wpo` and `tooloffsets`.
pub(super) fn device_items(k: &PathKeys, tables: bool) -> Vec<(Place, Key, &'static str)> {
    PathItem::list_with(k, tables, tables)
        .into_iter()
        .map(|it| {
            let (place, attrs) = it.device(k);
            (place, it.key(k), attrs)
        })
        .collect()
}

/// The controller's data items for the device file: the device's (`avail`) first, then the
/// controller's, each with its id and other attributes.
pub(super) fn device_controller_items() -> Vec<(&'static str, &'static str)> {
    CONTROLLER
        .iter()
        .map(|it| {
            let attrs = match it {
                ControllerItem::Avail => r#"category="EVENT" type="AVAILABILITY""#,
                ControllerItem::Estop => r#"category="EVENT" type="EMERGENCY_STOP""#,
                ControllerItem::Message => r#"category="EVENT" type="MESSAGE""#,
                ControllerItem::System => r#"category="CONDITION" type="SYSTEM""#,
            };
            (it.key(), attrs)
        })
        .collect()
}

/// A data item of a path. An axis's items hold its place in the path's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PathItem {
    Mode,
    Exec,
    Program,
    Block,
    Line,
    Act(usize),
    Mach(usize),
    Feedrate,
    Fovr,
    Rovr,
    Sovr,
    Srpm,
    Tool,
    Partcount,
    Wpo,
    ToolOffsets,
    Motion,
    Logic,
}

impl PathItem {
    /// The path's items in the order sent: the tables only when the modes have them.
    fn list(k: &PathKeys, m: &Modes) -> Vec<PathItem> {
        PathItem::list_with(k, m.wpo.is_some(), m.tooloffsets.is_some())
    }

    /// The path's items in the order sent, with the tables asked for.
    fn list_with(k: &PathKeys, wpo: bool, tooloffsets: bool) -> Vec<PathItem> {
        use PathItem::*;
        let mut v = vec![Mode, Exec, Program, Block, Line];
        v.extend((0..k.axes.len()).map(Act));
        v.extend((0..k.axes.len()).map(Mach));
        v.extend([Feedrate, Fovr, Rovr, Sovr, Srpm, Tool, Partcount]);
        if wpo {
            v.push(Wpo);
        }
        if tooloffsets {
            v.push(ToolOffsets);
        }
        v.extend([Motion, Logic]);
        v
    }

    /// Where the item stands in the device model, and its `DataItem` element's attributes
    /// after the id (docs/mtconnect/Devices.xml: the schema's names).
    fn device(self, k: &PathKeys) -> (Place, &'static str) {
        use PathItem::*;
        let rotary = |i: usize| k.axes[i].0 >= crate::block::FIRST_ROTARY;
        match self {
            Act(i) if rotary(i) => (
                Place::Axis(i),
                r#"category="SAMPLE" type="ANGLE" subType="ACTUAL" units="DEGREE" coordinateSystem="WORK""#,
            ),
            Mach(i) if rotary(i) => (
                Place::Axis(i),
                r#"category="SAMPLE" type="ANGLE" subType="ACTUAL" units="DEGREE" coordinateSystem="MACHINE""#,
            ),
            Act(i) => (
                Place::Axis(i),
                r#"category="SAMPLE" type="POSITION" subType="ACTUAL" units="MILLIMETER" coordinateSystem="WORK""#,
            ),
            Mach(i) => (
                Place::Axis(i),
                r#"category="SAMPLE" type="POSITION" subType="ACTUAL" units="MILLIMETER" coordinateSystem="MACHINE""#,
            ),
            Srpm => (
                Place::Spindle,
                r#"category="SAMPLE" type="ROTARY_VELOCITY" subType="ACTUAL" units="REVOLUTION/MINUTE""#,
            ),
            Sovr => (
                Place::Spindle,
                r#"category="EVENT" type="ROTARY_VELOCITY_OVERRIDE" units="PERCENT""#,
            ),
            Mode => (Place::Path, r#"category="EVENT" type="CONTROLLER_MODE""#),
            Exec => (Place::Path, r#"category="EVENT" type="EXECUTION""#),
            Program => (Place::Path, r#"category="EVENT" type="PROGRAM""#),
            Block => (Place::Path, r#"category="EVENT" type="BLOCK""#),
            Line => (
                Place::Path,
                r#"category="EVENT" type="LINE_NUMBER" subType="ABSOLUTE""#,
            ),
            Feedrate => (
                Place::Path,
                r#"category="SAMPLE" type="PATH_FEEDRATE" subType="ACTUAL" units="MILLIMETER/SECOND""#,
            ),
            Fovr => (
                Place::Path,
                r#"category="EVENT" type="PATH_FEEDRATE_OVERRIDE" subType="PROGRAMMED" units="PERCENT""#,
            ),
            Rovr => (
                Place::Path,
                r#"category="EVENT" type="PATH_FEEDRATE_OVERRIDE" subType="RAPID" units="PERCENT""#,
            ),
            Tool => (Place::Path, r#"category="EVENT" type="TOOL_NUMBER""#),
            Partcount => (
                Place::Path,
                r#"category="EVENT" type="PART_COUNT" subType="ALL""#,
            ),
            Wpo => (
                Place::Path,
                r#"category="EVENT" type="WORK_OFFSET" representation="TABLE""#,
            ),
            ToolOffsets => (
                Place::Path,
                r#"category="EVENT" type="TOOL_OFFSET" representation="TABLE""#,
            ),
            Logic => (Place::Path, r#"category="CONDITION" type="LOGIC_PROGRAM""#),
            Motion => (Place::Path, r#"category="CONDITION" type="MOTION_PROGRAM""#),
        }
    }

    fn key(self, k: &PathKeys) -> Key {
        use PathItem::*;
        match self {
            Act(i) => k.axis_key(k.axes[i].1, "act"),
            Mach(i) => k.axis_key(k.axes[i].1, "mach"),
            Mode => k.key("mode"),
            Exec => k.key("exec"),
            Program => k.key("program"),
            Block => k.key("block"),
            Line => k.key("line"),
            Feedrate => k.key("path_feedrate"),
            Fovr => k.key("Fovr"),
            Rovr => k.key("Rovr"),
            Sovr => k.key("Sovr"),
            Srpm => k.key("Srpm"),
            Tool => k.key("tool"),
            Partcount => k.key("partcount"),
            Wpo => k.key("wpo"),
            ToolOffsets => k.key("tooloffsets"),
            Motion => k.key("motion_program"),
            Logic => k.key("logic_program"),
        }
    }

    /// The value when it is a text the status or modes hold as it is sent (compared before it
    /// is copied).
    fn text<'a>(self, s: &'a Status, m: &'a Modes) -> Option<&'a str> {
        match self {
            PathItem::Mode => Some(m.mode),
            PathItem::Exec => Some(path_execution(s, m)),
            PathItem::Program if m.program.is_empty() => Some("UNAVAILABLE"),
            PathItem::Program => Some(&m.program),
            PathItem::Block => Some(
                s.executing
                    .as_ref()
                    .map_or("UNAVAILABLE", |e| e.stmt.text.as_str()),
            ),
            PathItem::Wpo => m.wpo.as_deref(),
            PathItem::ToolOffsets => m.tooloffsets.as_deref(),
            _ => None,
        }
    }

    /// What a number's value is made of: equal inputs make the same value, which is then not
    /// formatted again. None: not a number.
    fn input(self, s: &Status, m: &Modes, k: &PathKeys) -> Option<[u64; 3]> {
        let pos = |i: usize| s.pos[k.axes[i].0] as u64;
        Some(match self {
            PathItem::Line => match &s.executing {
                Some(e) => [1, u64::from(e.stmt.line), 0],
                None => [0; 3],
            },
            PathItem::Act(i) => [
                pos(i),
                m.pulse_mm.to_bits(),
                m.work_origin[k.axes[i].0].to_bits(),
            ],
            PathItem::Mach(i) => [pos(i), m.pulse_mm.to_bits(), 0],
            PathItem::Feedrate => [s.speed_mm_min.to_bits(), 0, 0],
            PathItem::Fovr => [u64::from(s.feed_override), 0, 0],
            PathItem::Rovr => [u64::from(s.switches.rapid_override), 0, 0],
            PathItem::Sovr => [u64::from(s.switches.spindle_override), 0, 0],
            PathItem::Srpm => [s.spindle.unsigned_abs(), 0, 0],
            PathItem::Tool => match s.tool {
                Some(t) => [1, u64::from(t), 0],
                None => [0; 3],
            },
            PathItem::Partcount => [m.partcount, 0, 0],
            _ => return None,
        })
    }

    /// Appends the item's value to `out`.
    fn write(self, s: &Status, m: &Modes, k: &PathKeys, out: &mut String) {
        use std::fmt::Write;
        if let Some(t) = self.text(s, m) {
            out.push_str(t);
            return;
        }
        let mm = |i: usize| s.pos[k.axes[i].0] as f64 * m.pulse_mm;
        // A count, as `to_string` writes it (writing to a String cannot fail).
        let count = |out: &mut String, v: u64| {
            let _ = write!(out, "{v}");
        };
        match self {
            PathItem::Line => match &s.executing {
                Some(e) => count(out, u64::from(e.stmt.line)),
                None => out.push_str("UNAVAILABLE"),
            },
            // The tool tip in the active work system (as POS shows it), and the axes in
            // machine coordinates.
            PathItem::Act(i) => fixed3(out, mm(i) - m.work_origin[k.axes[i].0]),
            PathItem::Mach(i) => fixed3(out, mm(i)),
            // MTConnect's PathFeedrate is in MILLIMETER/SECOND.
            PathItem::Feedrate => fixed3(out, s.speed_mm_min / 60.0),
            PathItem::Fovr => count(out, u64::from(s.feed_override)),
            // The rapid override's F0 is sent as 0 (MTConnect's RapidOverride is a percentage).
            PathItem::Rovr => count(out, u64::from(s.switches.rapid_override)),
            // The switch's position, as /nc/state records it (held at 100 % during a tap, when
            // Srpm shows the programmed speed: docs/pulse-core.md "Tapping").
            PathItem::Sovr => count(out, u64::from(s.switches.spindle_override)),
            PathItem::Srpm => count(out, s.spindle.unsigned_abs()),
            PathItem::Tool => match s.tool {
                Some(t) => count(out, u64::from(t)),
                None => out.push_str("UNAVAILABLE"),
            },
            PathItem::Partcount => count(out, m.partcount),
            PathItem::Motion => {
                let motion = s
                    .alarm
                    .as_deref()
                    .filter(|_| !s.estop)
                    .map(|a| ("CORE", a))
                    .or(m.fault.as_deref().map(|f| ("FAULT", f)));
                condition(out, motion)
            }
            PathItem::Logic => condition(out, m.program_alarm.as_deref().map(|a| ("PROGRAM", a))),
            // Texts, written above.
            PathItem::Mode
            | PathItem::Exec
            | PathItem::Program
            | PathItem::Block
            | PathItem::Wpo
            | PathItem::ToolOffsets => {}
        }
    }
}

/// `format!("{x:.3}")` appended to `out`, without the float formatter (it was most of the
/// adapter's cost): the binary value rounded exactly to thousandths, a tie to even, the sign
/// of a negative value kept when it rounds to zero (`-0.000`), as Rust's formatting does.
fn fixed3(out: &mut String, x: f64) {
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1 << 52) - 1);
    // x = ±m·2^e
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, exp - 1075)
    };
    // Infinities, NaN and values past 2^64 thousandths: the formatter's own way.
    if exp == 0x7ff || e > 0 {
        use std::fmt::Write;
        let _ = write!(out, "{x:.3}");
        return;
    }
    let n = u128::from(m) * 1000;
    let k = e.unsigned_abs();
    let q = if k >= 120 {
        0 // below 2^-67: n < 2^63 is less than half a unit
    } else {
        let q = n >> k;
        let r = n - (q << k);
        let half = if k == 0 { 0 } else { 1u128 << (k - 1) };
        if k > 0 && (r > half || (r == half && q & 1 == 1)) {
            q + 1
        } else {
            q
        }
    };
    if bits >> 63 == 1 {
        out.push('-');
    }
    // q < 2^53·1000 < 2^63.
    let q = q as u64;
    let mut digits = [0u8; 24];
    let mut i = digits.len();
    let mut v = q;
    loop {
        i -= 1;
        digits[i] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 && i <= digits.len() - 4 {
            break;
        }
    }
    let int_end = digits.len() - 3;
    for &d in &digits[i..int_end] {
        out.push(char::from(d));
    }
    out.push('.');
    for &d in &digits[int_end..] {
        out.push(char::from(d));
    }
}

/// The current value of every data item of a device, and what the mill's were made from: a
/// new snapshot formats only the items whose inputs changed, and copies only the values that
/// differ (the adapter's cost at every change of state, docs/mtconnect.md "Figures").
#[derive(Debug, Default)]
pub struct Current {
    /// Every item and its value, in the order sent.
    pub values: Vec<(Key, String)>,
    /// The indices in `values` of the items the last update changed.
    pub changed: Vec<usize>,
    /// The mill's rotary axes (its `rotary_mask`) and its path items `values` follow after the
    /// controller's (None: set by `replace`).
    mill: Option<(u8, Vec<PathItem>)>,
    /// For each item, what its value was made from when it is a number.
    inputs: Vec<Option<[u64; 3]>>,
    scratch: String,
    /// Numbers formatted by `update_mill` so far (what the input comparison saves, tested).
    numbers_made: u64,
}

impl Current {
    /// Takes the values of any device (the lathe's): the items that changed are noted. The
    /// items come in a fixed order: compared pairwise, or by key when the keys differ.
    pub fn replace(&mut self, items: Vec<(Key, String)>) {
        self.changed.clear();
        let same_keys = items.len() == self.values.len()
            && items.iter().zip(&self.values).all(|(a, b)| a.0 == b.0);
        if same_keys {
            self.changed.extend(
                items
                    .iter()
                    .zip(&self.values)
                    .enumerate()
                    .filter(|(_, (a, b))| a.1 != b.1)
                    .map(|(i, _)| i),
            );
        } else {
            let old = &self.values;
            self.changed.extend(
                items
                    .iter()
                    .enumerate()
                    .filter(|(_, (k, v))| !old.iter().any(|(ok, ov)| ok == k && ov == v))
                    .map(|(i, _)| i),
            );
        }
        self.values = items;
        self.mill = None;
    }

    /// Takes the mill's snapshot: the same values as [`items`], made only where they changed.
    pub fn update_mill(&mut self, s: &Status, m: &Modes) {
        let k = PathKeys::mill(m.rotary_mask);
        let fits = self.mill.as_ref().is_some_and(|(mask, p)| {
            *mask == m.rotary_mask
                && p.contains(&PathItem::Wpo) == m.wpo.is_some()
                && p.contains(&PathItem::ToolOffsets) == m.tooloffsets.is_some()
        });
        if !fits {
            self.replace(items(s, m));
            let path = PathItem::list(&k, m);
            self.inputs = CONTROLLER
                .iter()
                .map(|_| None)
                .chain(path.iter().map(|it| it.input(s, m, &k)))
                .collect();
            self.mill = Some((m.rotary_mask, path));
            return;
        }
        self.changed.clear();
        let c = Controller {
            estop: s.estop,
            alarm: s.alarm.as_deref(),
            message: m.message.as_deref(),
        };
        let Current {
            values,
            changed,
            mill: Some((_, path)),
            inputs,
            scratch,
            numbers_made,
        } = self
        else {
            return;
        };
        for (i, it) in CONTROLLER.iter().enumerate() {
            scratch.clear();
            it.write(&c, scratch);
            if *scratch != values[i].1 {
                std::mem::swap(scratch, &mut values[i].1);
                changed.push(i);
            }
        }
        for (j, it) in path.iter().enumerate() {
            let i = CONTROLLER.len() + j;
            let value = &mut values[i].1;
            if let Some(t) = it.text(s, m) {
                if value != t {
                    value.clear();
                    value.push_str(t);
                    changed.push(i);
                }
                continue;
            }
            let input = it.input(s, m, &k);
            if input.is_some() {
                if input == inputs[i] {
                    continue;
                }
                inputs[i] = input;
                *numbers_made += 1;
            }
            scratch.clear();
            it.write(s, m, &k, scratch);
            if scratch != value {
                std::mem::swap(scratch, value);
                changed.push(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Statement;
    use crate::pulse_core::testkit::Rng;
    use crate::pulse_core::{BlockEntry, RunEnd, RunKind};
    use std::sync::Arc;

    fn modes() -> Modes {
        Modes {
            mode: controller_mode(OpMode::Auto),
            program: "O0001".into(),
            partcount: 0,
            wpo: Some(wpo_table(&[[0.0; 6]; 6], &[0, 1, 2])),
            program_alarm: None,
            pulse_mm: 0.001,
            work_origin: [0.0; 6],
            rotary_mask: 0,
            tooloffsets: Some(String::new()),
            waiting: false,
            fault: None,
            message: None,
        }
    }

    #[test]
    fn the_mill_s_axes_are_x_y_z_and_the_rotary_axes_of_its_mask() {
        for mask in 0..8u8 {
            let want: Vec<(usize, &str)> = [(0, "X"), (1, "Y"), (2, "Z")]
                .into_iter()
                .chain(
                    [(3, "A"), (4, "B"), (5, "C")]
                        .into_iter()
                        .filter(|&(a, _)| mask & (1 << (a - 3)) != 0),
                )
                .collect();
            assert_eq!(PathKeys::mill(mask).axes(), want.as_slice(), "mask {mask}");
        }
    }

    fn value(items: &[(Key, String)], k: &str) -> String {
        items.iter().find(|(n, _)| *n == k).unwrap().1.clone()
    }

    #[test]
    fn positions_in_work_and_machine_coordinates_and_the_tool_table() {
        let s = Status {
            pos: [1000, -2500, -100_000].into(),
            ..Status::default()
        };
        let mut m = modes();
        m.work_origin = [10.0, -5.0, 150.0, 0.0, 0.0, 0.0];
        m.tooloffsets = Some(tool_table(&[
            (1, [150.0, 5.0, -0.02, 0.01]),
            (3, [90.5, 3.0, 0.0, 0.0]),
        ]));
        let it = items(&s, &m);
        assert_eq!(value(&it, "Xact"), "-9.000");
        assert_eq!(value(&it, "Yact"), "2.500");
        assert_eq!(value(&it, "Zact"), "-250.000");
        assert_eq!(value(&it, "Xmach"), "1.000");
        assert_eq!(value(&it, "Ymach"), "-2.500");
        assert_eq!(value(&it, "Zmach"), "-100.000");
        assert_eq!(
            value(&it, "tooloffsets"),
            "T1={LENGTH=150.000 RADIUS=5.000 LENGTH_WEAR=-0.020 RADIUS_WEAR=0.010} \
             T3={LENGTH=90.500 RADIUS=3.000 LENGTH_WEAR=0.000 RADIUS_WEAR=0.000}"
        );
    }

    #[test]
    fn execution_follows_the_run() {
        let mut s = Status::default();
        assert_eq!(execution(&s), "READY");
        s.run = 1;
        assert_eq!(execution(&s), "ACTIVE");
        s.hold = true;
        assert_eq!(execution(&s), "FEED_HOLD");
        s.hold = false;
        s.run = 0;
        s.program_end = true;
        s.last_end = Some(RunEnd {
            id: 1,
            kind: RunKind::Auto,
            blocks: 3,
            machine_ns: 1,
            lamp_ns: 1,
            cause: EndCause::ProgramEnd,
        });
        assert_eq!(execution(&s), "PROGRAM_COMPLETED");
        s.estop = true;
        s.alarm = Some("EMERGENCY STOP".into());
        assert_eq!(execution(&s), "STOPPED");
    }

    #[test]
    fn items_carry_positions_modes_and_conditions() {
        let mut s = Status {
            pos: [1000, -2500, 0].into(),
            feed_override: 80,
            ..Status::default()
        };
        let it = items(&s, &modes());
        assert_eq!(value(&it, "Xact"), "1.000");
        assert_eq!(value(&it, "Yact"), "-2.500");
        assert_eq!(value(&it, "Fovr"), "80");
        assert_eq!(value(&it, "mode"), "AUTOMATIC");
        assert_eq!(value(&it, "estop"), "ARMED");
        assert_eq!(value(&it, "system"), "NORMAL||||");
        assert!(value(&it, "wpo").starts_with("G54={X=0.000 Y=0.000 Z=0.000} G55="));
        s.alarm = Some("X TRAVEL LIMIT|+".into());
        let it = items(&s, &modes());
        assert_eq!(
            value(&it, "motion_program"),
            "FAULT|CORE|||\"X TRAVEL LIMIT\\|+\""
        );
        assert_eq!(value(&it, "system"), "NORMAL||||");
        let mut m = modes();
        m.mode = controller_mode(OpMode::Single);
        assert_eq!(value(&items(&s, &m), "mode"), "SEMI_AUTOMATIC");
    }

    #[test]
    fn a_lathe_path_is_prefixed_waits_and_faults() {
        let mut s = Status {
            pos: [20_000, 0, -5_000].into(),
            run: 1,
            ..Status::default()
        };
        let mut m = modes();
        m.wpo = None;
        m.tooloffsets = None;
        m.mode = controller_mode(OpMode::Data);
        let it = path_items(&s, &m, &PathKeys::lathe(2));
        let keys: Vec<&str> = it.iter().map(|(k, _)| k.as_ref()).collect();
        assert!(keys.iter().all(|k| k.starts_with("p2_")), "{keys:?}");
        assert!(!keys.contains(&"p2_Yact") && !keys.contains(&"p2_wpo"));
        assert_eq!(value(&it, "p2_Xact"), "20.000");
        assert_eq!(value(&it, "p2_Zmach"), "-5.000");
        assert_eq!(value(&it, "p2_mode"), "EDIT");
        assert_eq!(value(&it, "p2_exec"), "ACTIVE");
        m.waiting = true;
        assert_eq!(
            value(&path_items(&s, &m, &PathKeys::lathe(2)), "p2_exec"),
            "WAIT"
        );
        s.hold = true;
        assert_eq!(path_execution(&s, &m), "FEED_HOLD");
        m.fault = Some("chuck".into());
        let it = path_items(&s, &m, &PathKeys::lathe(2));
        assert_eq!(value(&it, "p2_exec"), "STOPPED");
        assert_eq!(value(&it, "p2_motion_program"), "FAULT|FAULT|||chuck");
    }

    #[test]
    fn thousandths_are_written_as_the_float_formatter_writes_them() {
        let mut rng = Rng::new(25);
        let mut xs = vec![
            0.0,
            -0.0,
            0.0625, // ties: to even
            0.1875,
            -0.3125,
            0.0005,
            -0.0001,
            1.0005,
            4503599627370495.5,
            9007199254740993.0,
            1e20,
            -1e300,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for _ in 0..20_000 {
            // Positions as the adapter makes them, sixteenths (exact ties), and any bits.
            let pulses = rng.range(-2_000_000_000, 2_000_000_000);
            xs.push(pulses as f64 * 0.001 - rng.range(-500, 500) as f64 * 0.1);
            xs.push(pulses as f64 * 0.0001);
            xs.push(rng.range(-1_000_000, 1_000_000) as f64 / 16.0);
            xs.push(rng.unit() * 8000.0 / 60.0);
            xs.push(f64::from_bits(rng.next_u64()));
        }
        for x in xs {
            let mut out = String::from("x");
            fixed3(&mut out, x);
            assert_eq!(out, format!("x{x:.3}"), "{x:e}");
        }
    }

    /// A status at step `i` of a made-up run: positions, feed, block, tool, alarms and
    /// messages changing at their own paces.
    fn varied(rng: &mut Rng, i: u64, s: &mut Status, m: &mut Modes) {
        let a = rng.range(0, 2) as usize;
        if rng.range(0, 3) == 0 {
            s.pos[a] += rng.range(-3, 3);
        }
        s.pos[2] += rng.range(-1000, 1000);
        s.speed_mm_min = [0.0, 120.0, rng.unit() * 6000.0][rng.range(0, 2) as usize];
        s.run = (i / 7 % 2) as u8;
        s.hold = i.is_multiple_of(11);
        if i.is_multiple_of(5) {
            s.executing = Some(BlockEntry {
                stmt: Arc::new(Statement {
                    line: (i / 5 % 4) as u32,
                    text: format!("G01 Z{}|\"", i % 3),
                    blocks: Vec::new(),
                }),
                index: 0,
            });
        }
        if i.is_multiple_of(17) {
            s.executing = None;
        }
        s.feed_override = [100, 80][(i / 13 % 2) as usize];
        s.switches.rapid_override = [100, 0][(i / 19 % 2) as usize];
        s.spindle = [1200, -1200, 0][(i / 3 % 3) as usize];
        s.tool = [None, Some(2), Some(12)][(i / 23 % 3) as usize];
        s.estop = i % 29 == 3;
        // Some(`text`) every other `n` steps.
        let some = |n: u64, text: &str| (i / n % 2 == 1).then(|| text.to_string());
        s.alarm = some(31, "X TRAVEL LIMIT|+").or(s.estop.then(|| "EMERGENCY STOP".into()));
        s.notice = some(37, "check\nchuck");
        m.mode = [
            controller_mode(OpMode::Auto),
            controller_mode(OpMode::Single),
        ][(i / 41 % 2) as usize];
        m.program = ["O0001", "", "P2"][(i / 43 % 3) as usize].into();
        m.partcount = i / 47;
        m.work_origin[2] = [0.0, 150.0][(i / 53 % 2) as usize];
        m.pulse_mm = [0.001, 0.0001][(i / 59 % 2) as usize];
        m.program_alarm = some(61, "bad word");
        m.fault = some(67, "chuck");
        m.wpo = match i / 71 % 3 {
            0 => Some(wpo_table(&[[0.0; 6]; 6], &[0, 1, 2])),
            1 => None,
            _ => Some("G54={X=1.000}".into()),
        };
        m.tooloffsets = some(73, "");
    }

    #[test]
    fn the_mill_updated_in_place_has_the_values_and_changes_of_the_items_made_whole() {
        let mut rng = Rng::new(7);
        let (mut s, mut m) = (Status::default(), modes());
        let (mut fast, mut whole) = (Current::default(), Current::default());
        let mut any_changed = 0;
        for i in 0..5_000 {
            varied(&mut rng, i, &mut s, &mut m);
            fast.update_mill(&s, &m);
            whole.replace(items(&s, &m));
            assert_eq!(fast.values, whole.values, "step {i}");
            assert_eq!(fast.changed, whole.changed, "step {i}");
            any_changed += fast.changed.len();
        }
        assert!(any_changed > 5_000, "{any_changed}");
    }

    #[test]
    fn the_mill_formats_only_the_numbers_whose_inputs_changed() {
        let mut s = Status::default();
        let m = modes();
        let mut c = Current::default();
        c.update_mill(&s, &m);
        let made = c.numbers_made;
        for z in 1..=100 {
            s.pos[2] = -z;
            c.update_mill(&s, &m);
            let keys: Vec<&str> = c.changed.iter().map(|&i| c.values[i].0.as_ref()).collect();
            assert_eq!(keys, ["Zact", "Zmach"]);
        }
        assert_eq!(c.numbers_made - made, 200);
    }
}
