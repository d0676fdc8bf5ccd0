//! The data items and their values, derived from the pulse core's status snapshot and the
//! console's modes (the mapping is in docs/mtconnect.md).

use super::Key;
use crate::lathe::console::events::Mode as LatheMode;
use crate::panel_model::OpMode;
use crate::pulse_core::{EndCause, Status};

/// What the adapter needs from the console for one path besides the core's status.
#[derive(Clone, Debug)]
pub struct Modes {
    /// The ControllerMode value of the mode selector ([`controller_mode`], [`lathe_mode`]).
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
    /// What is subtracted from the axis position (machine mm) to give the work position POS
    /// shows: the active system's zero with G92, and on Z the tool length in force
    /// (`console::pages::pos::work_origin`).
    pub work_origin: [f64; 3],
    /// The `tooloffsets` table ([`tool_table`]). None: not sent (the lathe).
    pub tooloffsets: Option<String>,
    /// The path stands at a sync point waiting for another (a lathe channel): Execution WAIT.
    pub waiting: bool,
    /// A fault of the path besides the core's alarm (a lathe channel's injected fault): the
    /// `motion_program` condition, and Execution STOPPED.
    pub fault: Option<String>,
}

/// The keys of one path's data items: the mill's names, prefixed `pN_` on a device of several
/// paths (the lathe's channels), and the axes it has.
#[derive(Clone, Debug)]
pub struct PathKeys {
    prefix: String,
    /// Index into the status's axes, and the axis letter of the keys (`Xact`, `Xmach`).
    axes: &'static [(usize, &'static str)],
}

impl PathKeys {
    /// The mill's one path: X, Y, Z, keys unprefixed.
    pub fn mill() -> PathKeys {
        PathKeys {
            prefix: String::new(),
            axes: &[(0, "X"), (1, "Y"), (2, "Z")],
        }
    }

    /// Path `n` (1-based) of a lathe: X and Z, every key prefixed `pN_`.
    pub fn lathe(n: usize) -> PathKeys {
        PathKeys {
            prefix: format!("p{n}_"),
            axes: &[(0, "X"), (2, "Z")],
        }
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

/// A condition value: `LEVEL|native_code|native_severity|qualifier|message`, each field escaped.
fn condition(fault: Option<(&str, &str)>) -> String {
    match fault {
        None => "NORMAL||||".into(),
        Some((code, msg)) => format!(
            "FAULT|{}|||{}",
            super::shdr::escape(code),
            super::shdr::escape(msg)
        ),
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

/// The MTConnect ControllerMode of the lathe's mode selector: AUTO `AUTOMATIC`, MDI
/// `MANUAL_DATA_INPUT`, DATA and OFS (entering programs and offsets) `EDIT`.
pub fn lathe_mode(m: LatheMode) -> &'static str {
    match m {
        LatheMode::Auto => "AUTOMATIC",
        LatheMode::Mdi => "MANUAL_DATA_INPUT",
        LatheMode::Data | LatheMode::Ofs => "EDIT",
    }
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

/// The `wpo` table of the work offsets G54–G59 (machine mm): `G54={X=… Y=… Z=…} G55=…`.
pub fn wpo_table(offsets: &[[f64; 3]; 6]) -> String {
    WPO.iter()
        .zip(offsets.iter())
        .map(|(n, o)| format!("{n}={{X={:.3} Y={:.3} Z={:.3}}}", o[0], o[1], o[2]))
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
    let mut v = controller_items(s.estop, s.alarm.as_deref(), s.notice.as_deref());
    v.extend(path_items(s, m, &PathKeys::mill()));
    v
}

/// The controller's data items, once per device: `avail`, `estop`, the `system` condition
/// (E-STOP's alarm while it is in force) and the operator `message`.
pub fn controller_items(
    estop: bool,
    alarm: Option<&str>,
    message: Option<&str>,
) -> Vec<(Key, String)> {
    vec![
        (Key::Borrowed("avail"), "AVAILABLE".into()),
        (
            Key::Borrowed("estop"),
            if estop { "TRIGGERED" } else { "ARMED" }.into(),
        ),
        (
            Key::Borrowed("system"),
            condition(alarm.filter(|_| estop).map(|a| ("ESTOP", a))),
        ),
        (
            Key::Borrowed("message"),
            format!("|{}", super::shdr::escape(message.unwrap_or(""))),
        ),
    ]
}

/// Every data item of one path and its value, in a fixed order, keyed by `k`.
pub fn path_items(s: &Status, m: &Modes, k: &PathKeys) -> Vec<(Key, String)> {
    let (block, line) = match &s.executing {
        Some(e) => (e.stmt.text.clone(), e.stmt.line.to_string()),
        None => ("UNAVAILABLE".into(), "UNAVAILABLE".into()),
    };
    let core_alarm = s.alarm.as_deref();
    let mut v = vec![
        (k.key("mode"), m.mode.into()),
        (k.key("exec"), path_execution(s, m).into()),
        (
            k.key("program"),
            if m.program.is_empty() {
                "UNAVAILABLE".into()
            } else {
                m.program.clone()
            },
        ),
        (k.key("block"), block),
        (k.key("line"), line),
    ];
    // The tool tip in the active work system (as POS shows it), and the axes in machine
    // coordinates.
    for &(a, name) in k.axes {
        let mm = s.pos[a] as f64 * m.pulse_mm;
        v.push((
            k.axis_key(name, "act"),
            format!("{:.3}", mm - m.work_origin[a]),
        ));
    }
    for &(a, name) in k.axes {
        let mm = s.pos[a] as f64 * m.pulse_mm;
        v.push((k.axis_key(name, "mach"), format!("{mm:.3}")));
    }
    v.extend([
        // MTConnect's PathFeedrate is in MILLIMETER/SECOND.
        (
            k.key("path_feedrate"),
            format!("{:.3}", s.speed_mm_min / 60.0),
        ),
        (k.key("Fovr"), s.feed_override.to_string()),
        // The rapid override's F0 is sent as 0 (MTConnect's RapidOverride is a percentage).
        (k.key("Rovr"), s.switches.rapid_override.to_string()),
        // The switch's position, as /nc/state records it (held at 100 % during a tap, when
        // Srpm shows the programmed speed: docs/pulse-core.md "Tapping").
        (k.key("Sovr"), s.switches.spindle_override.to_string()),
        (k.key("Srpm"), s.spindle.unsigned_abs().to_string()),
        (
            k.key("tool"),
            s.tool
                .map(|t| t.to_string())
                .unwrap_or_else(|| "UNAVAILABLE".into()),
        ),
        (k.key("partcount"), m.partcount.to_string()),
    ]);
    if let Some(w) = &m.wpo {
        v.push((k.key("wpo"), w.clone()));
    }
    if let Some(t) = &m.tooloffsets {
        v.push((k.key("tooloffsets"), t.clone()));
    }
    let motion = core_alarm
        .filter(|_| !s.estop)
        .map(|a| ("CORE", a))
        .or(m.fault.as_deref().map(|f| ("FAULT", f)));
    v.push((k.key("motion_program"), condition(motion)));
    v.push((
        k.key("logic_program"),
        condition(m.program_alarm.as_deref().map(|a| ("PROGRAM", a))),
    ));
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pulse_core::{RunEnd, RunKind};

    fn modes() -> Modes {
        Modes {
            mode: controller_mode(OpMode::Auto),
            program: "O0001".into(),
            partcount: 0,
            wpo: Some(wpo_table(&[[0.0; 3]; 6])),
            program_alarm: None,
            pulse_mm: 0.001,
            work_origin: [0.0; 3],
            tooloffsets: Some(String::new()),
            waiting: false,
            fault: None,
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
        m.work_origin = [10.0, -5.0, 150.0];
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
        m.mode = lathe_mode(LatheMode::Ofs);
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
}
