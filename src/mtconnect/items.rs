//! The data items and their values, derived from the pulse core's status snapshot and the
//! console's modes (the mapping is in docs/mtconnect.md).

use crate::panel_model::OpMode;
use crate::pulse_core::{EndCause, Status};

/// What the adapter needs from the console besides the core's status.
#[derive(Clone, Debug)]
pub struct Modes {
    /// The operation mode selector.
    pub op: OpMode,
    /// The program in program memory.
    pub program: String,
    /// Runs that reached the end of their program (M02/M30) since the console opened.
    pub partcount: u64,
    /// The `wpo` table ([`wpo_table`]): formatted once per change of the offsets, not at
    /// every change of state.
    pub wpo: String,
    /// A program that does not translate: its message (the `logic_program` condition).
    pub program_alarm: Option<String>,
    /// mm per pulse.
    pub pulse_mm: f64,
    /// What is subtracted from the axis position (machine mm) to give the work position POS
    /// shows: the active system's zero with G92, and on Z the tool length in force
    /// (`console::pages::pos::work_origin`).
    pub work_origin: [f64; 3],
    /// The `tooloffsets` table ([`tool_table`]).
    pub tooloffsets: String,
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

/// Every data item of the mill's one path and its value, in a fixed order.
pub fn items(s: &Status, m: &Modes) -> Vec<(&'static str, String)> {
    let mm = |p: i64| format!("{:.3}", p as f64 * m.pulse_mm);
    let (block, line) = match &s.executing {
        Some(e) => (e.stmt.text.clone(), e.stmt.line.to_string()),
        None => ("UNAVAILABLE".into(), "UNAVAILABLE".into()),
    };
    let core_alarm = s.alarm.as_deref();
    let work = |a: usize| format!("{:.3}", s.pos[a] as f64 * m.pulse_mm - m.work_origin[a]);
    vec![
        ("avail", "AVAILABLE".into()),
        ("estop", if s.estop { "TRIGGERED" } else { "ARMED" }.into()),
        ("mode", controller_mode(m.op).into()),
        ("exec", execution(s).into()),
        (
            "program",
            if m.program.is_empty() {
                "UNAVAILABLE".into()
            } else {
                m.program.clone()
            },
        ),
        ("block", block),
        ("line", line),
        // The tool tip in the active work system (as POS shows it), and the axes in machine
        // coordinates.
        ("Xact", work(0)),
        ("Yact", work(1)),
        ("Zact", work(2)),
        ("Xmach", mm(s.pos[0])),
        ("Ymach", mm(s.pos[1])),
        ("Zmach", mm(s.pos[2])),
        // MTConnect's PathFeedrate is in MILLIMETER/SECOND.
        ("path_feedrate", format!("{:.3}", s.speed_mm_min / 60.0)),
        ("Fovr", s.feed_override.to_string()),
        // The rapid override's F0 is sent as 0 (MTConnect's RapidOverride is a percentage).
        ("Rovr", s.switches.rapid_override.to_string()),
        // The switch's position, as /nc/state records it (held at 100 % during a tap, when
        // Srpm shows the programmed speed: docs/pulse-core.md "Tapping").
        ("Sovr", s.switches.spindle_override.to_string()),
        ("Srpm", s.spindle.unsigned_abs().to_string()),
        (
            "tool",
            s.tool
                .map(|t| t.to_string())
                .unwrap_or_else(|| "UNAVAILABLE".into()),
        ),
        ("partcount", m.partcount.to_string()),
        ("wpo", m.wpo.clone()),
        ("tooloffsets", m.tooloffsets.clone()),
        (
            "system",
            condition(core_alarm.filter(|_| s.estop).map(|a| ("ESTOP", a))),
        ),
        (
            "motion_program",
            condition(core_alarm.filter(|_| !s.estop).map(|a| ("CORE", a))),
        ),
        (
            "logic_program",
            condition(m.program_alarm.as_deref().map(|a| ("PROGRAM", a))),
        ),
        (
            "message",
            format!(
                "|{}",
                super::shdr::escape(s.notice.as_deref().unwrap_or(""))
            ),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pulse_core::{RunEnd, RunKind};

    fn modes() -> Modes {
        Modes {
            op: OpMode::Auto,
            program: "O0001".into(),
            partcount: 0,
            wpo: wpo_table(&[[0.0; 3]; 6]),
            program_alarm: None,
            pulse_mm: 0.001,
            work_origin: [0.0; 3],
            tooloffsets: String::new(),
        }
    }

    fn value(items: &[(&str, String)], k: &str) -> String {
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
        m.tooloffsets = tool_table(&[(1, [150.0, 5.0, -0.02, 0.01]), (3, [90.5, 3.0, 0.0, 0.0])]);
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
        m.op = OpMode::Single;
        assert_eq!(value(&items(&s, &m), "mode"), "SEMI_AUTOMATIC");
    }
}
