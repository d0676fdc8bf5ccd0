//! The interpreter's state (docs/gcode.md "The interpreter's state"): the modal groups, the
//! numbered and named parameters, the offsets (G5x with their rotation, G92, tool length),
//! the tool and the position, as LinuxCNC 2.9 keeps them. It lives as long as the machine:
//! AUTO, MDI and SEARCH read from the same state, and a program's end resets only what M2/M30
//! reset in LinuxCNC.
//!
//! This module depends on nothing of motion, cycles or compensation; they depend on it.
//! Lengths are kept in millimetres (machine units); the program's units (G20/G21) are applied
//! where words are read and where parameters report positions.

use super::read::MAX_PARAM;
use crate::block::Plane;
use std::collections::HashMap;

/// The coordinate systems G54 to G59.3.
pub const SYSTEMS: usize = 9;

/// The names of the coordinate systems, G54 to G59.3.
pub const SYSTEM_NAMES: [&str; SYSTEMS] = [
    "G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3",
];

/// Millimetres per inch.
pub const MM_PER_INCH: f64 = 25.4;

/// The persistent parameters (LinuxCNC's parameter file): G28 and G30 homes, G92, the
/// coordinate system in force and the nine systems with their rotation.
pub fn is_persistent(n: usize) -> bool {
    (5161..=5169).contains(&n) || (5181..=5189).contains(&n) || (5210..=5390).contains(&n)
}

/// The first parameter of coordinate system `cs` (0 = G54): X at +1, Y +2, Z +3, R +10.
pub fn system_base(cs: usize) -> usize {
    5200 + 20 * (cs + 1)
}

/// The motion mode in force (modal group 1), as its G number ×10.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// G00.
    Rapid,
    /// G01.
    Feed,
    /// G02.
    Cw,
    /// G03.
    Ccw,
    /// G38.2–G38.5 (×10: 382 … 385).
    Probe(u16),
    /// G05, G05.1, G05.2 (×10: 50, 51, 52).
    Spline(u16),
    /// G33 spindle-synchronised motion, a thread pass (×10: 330).
    Thread,
    /// G33.1 rigid tapping (×10: 331).
    RigidTap,
    /// A canned cycle: G73, G74, G81–G89 (×10).
    Cycle(u16),
    /// G80: none.
    None,
}

impl Motion {
    /// The G number ×10 (`#<_motion_mode>`).
    pub fn code(self) -> u16 {
        match self {
            Motion::Rapid => 0,
            Motion::Feed => 10,
            Motion::Cw => 20,
            Motion::Ccw => 30,
            Motion::Probe(g) | Motion::Spline(g) | Motion::Cycle(g) => g,
            Motion::Thread => 330,
            Motion::RigidTap => 331,
            Motion::None => 800,
        }
    }
}

/// The feed mode (modal group 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedMode {
    /// G94: units per minute.
    PerMinute,
    /// G93: inverse time (each feed move's F is 1 / minutes).
    InverseTime,
    /// G95: units per revolution of the spindle.
    PerRevolution,
}

/// Path control (modal group 13).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathMode {
    /// G61: exact path.
    ExactPath,
    /// G61.1: exact stop.
    ExactStop,
    /// G64 with its P (blending tolerance) and Q (naive CAM tolerance), program units → mm.
    Blend {
        /// P: how far the path may leave the programmed corner, mm (None: as fast as possible).
        p: Option<f64>,
        /// Q: collinear moves within this are merged, mm.
        q: Option<f64>,
    },
}

/// Cutter radius compensation's side (modal group 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompSide {
    /// G40.
    Off,
    /// G41.
    Left,
    /// G42.
    Right,
}

/// The modal groups and settings M70 saves and M72 restores, and that MDI and AUTO share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Modal {
    /// Group 1.
    pub motion: Motion,
    /// Group 2.
    pub plane: Plane,
    /// Group 3: G91 in force.
    pub incremental: bool,
    /// Group 4: G90.1 (arc centres absolute) in force; G91.1 (incremental) is the default.
    pub ijk_absolute: bool,
    /// Group 5.
    pub feed_mode: FeedMode,
    /// Group 6: G20 in force.
    pub inch: bool,
    /// Group 7.
    pub comp: CompSide,
    /// Group 10: G99 (retract to R) in force, else G98.
    pub retract_r: bool,
    /// Group 12: the coordinate system in force, 0 = G54 … 8 = G59.3.
    pub cs: usize,
    /// Group 13.
    pub path: PathMode,
    /// F in force, mm/min (G94), mm/rev (G95) or 1/min (G93; then in force for one line).
    pub feed: f64,
    /// S in force, rpm.
    pub speed: f64,
    /// The spindle: 1 forward (M03), −1 reverse (M04), 0 stopped (M05).
    pub spindle: i8,
    /// M07.
    pub mist: bool,
    /// M08.
    pub flood: bool,
    /// M48/M49: feed and speed overrides enabled (M50 and M51 each).
    pub feed_override: bool,
    /// M51.
    pub speed_override: bool,
    /// M52.
    pub adaptive_feed: bool,
    /// M53.
    pub feed_hold: bool,
}

impl Default for Modal {
    /// LinuxCNC's state at start: G80 G17 G90 G91.1 G94 G21 G40 G99 G54 G64, F0 S0, M05 M09
    /// M48.
    fn default() -> Self {
        Modal {
            motion: Motion::None,
            plane: Plane::XY,
            incremental: false,
            ijk_absolute: false,
            feed_mode: FeedMode::PerMinute,
            inch: false,
            comp: CompSide::Off,
            retract_r: true,
            cs: 0,
            path: PathMode::Blend { p: None, q: None },
            feed: 0.0,
            speed: 0.0,
            spindle: 0,
            mist: false,
            flood: false,
            feed_override: true,
            speed_override: true,
            adaptive_feed: false,
            feed_hold: true,
        }
    }
}

impl Modal {
    /// The length factor of the units in force (25.4 for inches).
    pub fn factor(&self) -> f64 {
        if self.inch {
            MM_PER_INCH
        } else {
            1.0
        }
    }
}

/// What canned cycles keep from one line to the next (their sticky words).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CycleMemory {
    /// The initial level of the series (machine coordinate along the plane's normal, mm).
    pub il: Option<f64>,
    /// R, program units converted to mm, program frame.
    pub r: Option<f64>,
    /// The hole bottom along the normal (mm, program frame).
    pub z: Option<f64>,
    /// P (dwell, s).
    pub p: f64,
    /// Q (peck, mm).
    pub q: Option<f64>,
    /// Fanuc's rigid tapping mode (M29 S, the Fanuc dialect): the next G84 or G74 turns the
    /// spindle itself, from stopped if need be; until G80, a G00–G03, M02/M30 or RESET.
    pub rigid: bool,
}

/// The M70 … M73 saved states (one per call level).
#[derive(Clone, Debug, PartialEq)]
pub struct Saved {
    /// The modal groups.
    pub modal: Modal,
    /// M73: restore on return from the subroutine that saved it.
    pub auto_restore: bool,
}

/// A NURBS being given by G5.2 lines, until G5.3 moves along it (docs/gcode.md "Splines").
#[derive(Clone, Debug, PartialEq)]
pub struct PendingNurbs {
    /// The control points, machine mm (XY); the first is where the machine stood at the first
    /// G5.2 line.
    pub points: Vec<[f64; 2]>,
    /// Their weights (P), each greater than 0.
    pub weights: Vec<f64>,
    /// The order L (the degree + 1), 3 or more.
    pub order: usize,
    /// The line of the first G5.2, for messages.
    pub line: u32,
}

/// The interpreter's state: everything that outlives one line.
#[derive(Clone, Debug)]
pub struct InterpState {
    /// The modal groups and settings.
    pub modal: Modal,
    /// `#1` … `#5602`.
    pub params: Vec<f64>,
    /// Global named parameters `#<_name>`, and the main program's local ones (call level 0),
    /// by name in lower case.
    pub named: HashMap<String, f64>,
    /// Where the spindle's gauge line is, machine mm.
    pub pos: [f64; 3],
    /// Where the rotary axes A, B and C stand, machine degrees (one the machine has not stays
    /// 0). Their program position is this less `origin_abc` and `g92_abc`.
    pub abc: [f64; 3],
    /// The rotary axes A, B and C the machine has: `Some(wrapped)` each (docs/gcode.md
    /// "Rotary axes").
    pub rotaries: [Option<bool>; 3],
    /// The offset of the coordinate system in force (machine mm of its zero), as selected;
    /// a change to its parameters takes effect when it is selected again (as in LinuxCNC).
    pub origin: [f64; 3],
    /// The rotary axes' part of that offset (A, B, C, degrees: the system's #5xx4–#5xx6; a run
    /// takes 0 for an axis the machine has not, `GcodeSource::with_state`). As LinuxCNC's, it is added to a program position; the
    /// XY rotation does not turn it (docs/gcode.md "Rotary axes").
    pub origin_abc: [f64; 3],
    /// The XY rotation of the coordinate system in force, degrees.
    pub rotation: f64,
    /// Fanuc's coordinate rotation in force (G68, the Fanuc dialect; G69 cancels): its centre
    /// in the program frame (mm) and its angle (degrees, counter-clockwise), applied to
    /// program points before the work offsets.
    pub g68: Option<([f64; 2], f64)>,
    /// The G92 offset in force, mm (zero when none).
    pub g92: [f64; 3],
    /// The G92 offset of the rotary axes A, B, C in force, degrees (#5214–#5216).
    pub g92_abc: [f64; 3],
    /// The tool length offset in force (G43, G43.1, G43.2), mm, per axis.
    pub tlo: [f64; 3],
    /// The tool whose length G43 applied (for the display), if any.
    pub tlo_tool: Option<u32>,
    /// The tool in the spindle (0 or None: none).
    pub tool: Option<u32>,
    /// The tool the last T word selected.
    pub selected: Option<u32>,
    /// Cutter compensation's radius (mm) and the D that gave it.
    pub comp_radius: f64,
    /// The D word of G41/G42, if any.
    pub comp_tool: Option<u32>,
    /// Canned cycles' sticky words.
    pub cycle: CycleMemory,
    /// The last `endsub`/`return` value (`#<_value>`) and whether one was given.
    pub return_value: f64,
    /// `#<_value_returned>`.
    pub value_returned: bool,
    /// The current line's N number (`#<_line>`).
    pub line_number: f64,
    /// The call level (`#<_call_level>`), set by the flow.
    pub call_level: usize,
    /// `#<_remap_level>`: 1 while a remapped M6's subroutine runs, else 0.
    pub remap_level: usize,
    /// M70/M73 saved states by call level.
    pub saved: Vec<Option<Saved>>,
    /// Digital outputs P0–P63 (M62–M65).
    pub digital_out: [bool; 64],
    /// Analog outputs E0–E63 (M67/M68).
    pub analog_out: [f64; 64],
    /// The NURBS the G5.2 lines are giving, until G5.3.
    pub nurbs: Option<PendingNurbs>,
    /// The first control point of a G5 without I J, from its start (program frame, mm): the
    /// last G5's P Q negated (LinuxCNC's `cycle_i`, `cycle_j`), so that it continues that
    /// curve's tangent.
    pub g5_tangent: [f64; 2],
    /// The Fanuc dialect's variables have been made vacant (null) once: #1–#33, #100–#199
    /// and the #500–#999 not kept (docs/gcode.md "Fanuc dialect").
    pub fanuc_vacant: bool,
    /// The last M code read (Fanuc's #4113), null until one is.
    pub fanuc_m: f64,
    /// What a program wrote to Fanuc's clocks #3001 and #3002 moved them by, ms: each reads
    /// the machine's clock plus this (docs/gcode.md "Fanuc dialect").
    pub clock_offset_ms: [f64; 2],
}

/// Fanuc's common variables kept across a restart (#500–#999), journaled with the
/// parameters in the Fanuc dialect.
pub fn is_fanuc_kept(n: usize) -> bool {
    (500..=999).contains(&n)
}

/// Where the stores keep Fanuc's hour clock #3002 (hours), which Fanuc keeps through
/// power-off: journaled at the end of each run in the Fanuc dialect, and read back into the
/// clock (never into parameter #3002, which is LinuxCNC's own).
pub const HOUR_CLOCK: usize = 3002;

/// The parameters the stores keep: LinuxCNC's persistent ones, Fanuc's #500–#999 and the
/// hour clock [`HOUR_CLOCK`].
pub fn is_kept(n: usize) -> bool {
    is_persistent(n) || is_fanuc_kept(n) || n == HOUR_CLOCK
}

/// Fanuc's common variables cleared by RESET (#100–#199).
pub const FANUC_COMMON: std::ops::RangeInclusive<usize> = 100..=199;

impl Default for InterpState {
    fn default() -> Self {
        let mut params = vec![0.0; MAX_PARAM + 1];
        params[5220] = 1.0;
        params[5599] = 1.0;
        InterpState {
            modal: Modal::default(),
            params,
            named: HashMap::new(),
            pos: [0.0; 3],
            abc: [0.0; 3],
            rotaries: [None; 3],
            origin: [0.0; 3],
            origin_abc: [0.0; 3],
            rotation: 0.0,
            g68: None,
            g92: [0.0; 3],
            g92_abc: [0.0; 3],
            tlo: [0.0; 3],
            tlo_tool: None,
            tool: None,
            selected: None,
            comp_radius: 0.0,
            comp_tool: None,
            cycle: CycleMemory::default(),
            return_value: 0.0,
            value_returned: false,
            line_number: 0.0,
            call_level: 0,
            remap_level: 0,
            saved: Vec::new(),
            digital_out: [false; 64],
            analog_out: [0.0; 64],
            nurbs: None,
            g5_tangent: [0.0; 2],
            fanuc_vacant: false,
            fanuc_m: f64::NAN,
            clock_offset_ms: [0.0; 2],
        }
    }
}

/// Rotates (x, y) by `deg` degrees counter-clockwise.
pub fn rotate(p: [f64; 2], deg: f64) -> [f64; 2] {
    if deg == 0.0 {
        return p;
    }
    let (s, c) = deg.to_radians().sin_cos();
    [p[0] * c - p[1] * s, p[0] * s + p[1] * c]
}

impl InterpState {
    /// A state whose coordinate systems, G28/G30 homes and G92 come from `persistent`
    /// (parameter number, value) and whose machine stands at `pos`, with `tool` in the
    /// spindle: the state a console starts with.
    pub fn with_persistent(persistent: &[(usize, f64)], pos: [f64; 3], tool: Option<u32>) -> Self {
        let mut s = InterpState::default();
        for &(n, v) in persistent {
            if (is_persistent(n) || is_fanuc_kept(n)) && v.is_finite() {
                s.params[n] = v;
            } else if n == HOUR_CLOCK && v.is_finite() {
                // The hour clock kept: the new session's lamp time counts on from it.
                s.clock_offset_ms[1] = (v * 3.6e6).round();
            }
        }
        let cs = s.params[5220].round();
        s.modal.cs = if (1.0..=9.0).contains(&cs) {
            cs as usize - 1
        } else {
            0
        };
        s.params[5220] = (s.modal.cs + 1) as f64;
        s.select_system(s.modal.cs);
        if s.params[5210] != 0.0 {
            s.g92 = [s.params[5211], s.params[5212], s.params[5213]];
            s.g92_abc = [s.params[5214], s.params[5215], s.params[5216]];
        }
        s.pos = pos;
        s.tool = tool;
        s.selected = tool;
        s.params[5400] = tool.map_or(0.0, f64::from);
        s
    }

    /// The Fanuc dialect's power-on: the local variables #1–#33 and the common variables
    /// #100–#199 vacant (null), and #500–#999 vacant where nothing is kept (a kept variable
    /// is never 0: the stores keep no zero). Done once for a state.
    pub fn fanuc_power_on(&mut self) {
        if self.fanuc_vacant {
            return;
        }
        self.fanuc_vacant = true;
        for n in (1..=33).chain(FANUC_COMMON) {
            self.params[n] = f64::NAN;
        }
        for n in 500..=999 {
            if self.params[n] == 0.0 {
                self.params[n] = f64::NAN;
            }
        }
    }

    /// RESET in the Fanuc dialect: the common variables #100–#199 vacant again (Fanuc's
    /// parameter 6001#6 CCV = 0; the console does not call it under `common keep`).
    pub fn fanuc_reset(&mut self) {
        if self.fanuc_vacant {
            for n in FANUC_COMMON {
                self.params[n] = f64::NAN;
            }
        }
    }

    /// The persistent parameters that differ from zero (and #5220), for the stores.
    pub fn persistent(&self) -> Vec<(usize, f64)> {
        (5161..=5390)
            .filter(|&n| is_persistent(n) && (self.params[n] != 0.0 || n == 5220))
            .map(|n| (n, self.params[n]))
            .collect()
    }

    /// Makes coordinate system `cs` (0 = G54) the one in force, from its parameters.
    pub fn select_system(&mut self, cs: usize) {
        let b = system_base(cs);
        self.modal.cs = cs;
        self.params[5220] = (cs + 1) as f64;
        self.origin = [self.params[b + 1], self.params[b + 2], self.params[b + 3]];
        self.origin_abc = [self.params[b + 4], self.params[b + 5], self.params[b + 6]];
        self.rotation = self.params[b + 10];
    }

    /// What is added to the rotary axes' program positions to give their machine positions:
    /// the system's offset and G92's, degrees.
    pub fn abc_offset(&self) -> [f64; 3] {
        std::array::from_fn(|r| self.origin_abc[r] + self.g92_abc[r])
    }

    /// The G92 offset in force on every axis: X Y Z (mm), then A B C (degrees).
    pub fn g92_all(&self) -> [f64; crate::block::MAX_AXES] {
        let (l, r) = (self.g92, self.g92_abc);
        [l[0], l[1], l[2], r[0], r[1], r[2]]
    }

    /// Where the rotary axes stand in the program frame, degrees (#5423–#5425).
    pub fn prog_abc(&self) -> [f64; 3] {
        let o = self.abc_offset();
        std::array::from_fn(|r| self.abc[r] - o[r])
    }

    /// The work offset of system `cs` as its parameters hold it (machine mm).
    pub fn system_offset(&self, cs: usize) -> [f64; 3] {
        let b = system_base(cs);
        [self.params[b + 1], self.params[b + 2], self.params[b + 3]]
    }

    /// The length factor of the units in force.
    pub fn factor(&self) -> f64 {
        self.modal.factor()
    }

    /// The machine's axes as a message names them: `X, Y, Z`, `X, Y, Z and A`, `X, Y, Z, A
    /// and C` ...
    pub fn axes_named(&self) -> String {
        let mut names = vec!["X, Y, Z"];
        for (r, l) in ["A", "B", "C"].into_iter().enumerate() {
            if self.rotaries[r].is_some() {
                names.push(l);
            }
        }
        match names.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
            _ => names.join(""),
        }
    }

    /// A program point (mm, the program frame: after units, before offsets) in machine
    /// coordinates: G92, then the rotation about the system's zero, then the system's offset
    /// and the tool length (LinuxCNC's order).
    pub fn to_machine(&self, p: [f64; 3]) -> [f64; 3] {
        let p = self.g68_rotated(p, 1.0);
        let q = [p[0] + self.g92[0], p[1] + self.g92[1], p[2] + self.g92[2]];
        let r = rotate([q[0], q[1]], self.rotation);
        [
            r[0] + self.origin[0] + self.tlo[0],
            r[1] + self.origin[1] + self.tlo[1],
            q[2] + self.origin[2] + self.tlo[2],
        ]
    }

    /// A machine point in the program frame (mm): the inverse of `to_machine`.
    pub fn to_program(&self, m: [f64; 3]) -> [f64; 3] {
        let q = [
            m[0] - self.origin[0] - self.tlo[0],
            m[1] - self.origin[1] - self.tlo[1],
            m[2] - self.origin[2] - self.tlo[2],
        ];
        let r = rotate([q[0], q[1]], -self.rotation);
        self.g68_rotated(
            [r[0] - self.g92[0], r[1] - self.g92[1], q[2] - self.g92[2]],
            -1.0,
        )
    }

    /// `p` turned by G68 about its centre (`sign` -1: back), or `p` without G68.
    fn g68_rotated(&self, p: [f64; 3], sign: f64) -> [f64; 3] {
        let Some((c, deg)) = self.g68 else {
            return p;
        };
        let r = rotate([p[0] - c[0], p[1] - c[1]], sign * deg);
        [r[0] + c[0], r[1] + c[1], p[2]]
    }

    /// A machine point in the work coordinates with the tool length offset included (the
    /// gauge line's work position: Fanuc's #5041), mm.
    pub fn work_with_tool(&self, m: [f64; 3]) -> [f64; 3] {
        let q = [
            m[0] - self.origin[0],
            m[1] - self.origin[1],
            m[2] - self.origin[2],
        ];
        let r = rotate([q[0], q[1]], -self.rotation);
        self.g68_rotated(
            [r[0] - self.g92[0], r[1] - self.g92[1], q[2] - self.g92[2]],
            -1.0,
        )
    }

    /// Where the machine is, in the program frame, mm.
    pub fn prog(&self) -> [f64; 3] {
        self.to_program(self.pos)
    }

    /// The position in program units (`#5420`–`#5422`, `#<_x>`).
    pub fn prog_units(&self) -> [f64; 3] {
        let k = self.factor();
        let p = self.prog();
        [p[0] / k, p[1] / k, p[2] / k]
    }

    /// The value of `#n` as a line reads it: the parameters that report the state (#5400 the
    /// tool, #5420–#5428 the position in program units) are worked out when read, which is what
    /// LinuxCNC's update of them at each read amounts to.
    pub fn param(&self, n: usize) -> f64 {
        match n {
            5400 => self.tool.map_or(0.0, f64::from),
            5420..=5422 => self.prog_units()[n - 5420],
            5423..=5425 => self.prog_abc()[n - 5423],
            5426..=5428 => 0.0,
            _ => self.params.get(n).copied().unwrap_or(0.0),
        }
    }

    /// The value of a predefined named parameter (`_x`, `_metric`, ...), if `name` is one.
    pub fn predefined(&self, name: &str) -> Option<f64> {
        let m = &self.modal;
        let b = |x: bool| if x { 1.0 } else { 0.0 };
        let k = self.factor();
        let v = match name {
            "_line" => self.line_number,
            "_motion_mode" => f64::from(m.motion.code()),
            "_plane" => match m.plane {
                Plane::XY => 170.0,
                Plane::XZ => 180.0,
                Plane::YZ => 190.0,
            },
            "_ccomp" => match m.comp {
                CompSide::Off => 400.0,
                CompSide::Left => 410.0,
                CompSide::Right => 420.0,
            },
            "_metric" => b(!m.inch),
            "_imperial" => b(m.inch),
            "_absolute" => b(!m.incremental),
            "_incremental" => b(m.incremental),
            "_inverse_time" => b(m.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => b(m.feed_mode == FeedMode::PerMinute),
            "_units_per_rev" => b(m.feed_mode == FeedMode::PerRevolution),
            "_coord_system" => match m.cs {
                cs @ 0..=5 => 540.0 + 10.0 * cs as f64,
                cs => 584.0 + cs as f64,
            },
            "_tool_offset" => b(self.tlo.iter().any(|&v| v != 0.0)),
            "_retract_r_plane" => b(m.retract_r),
            "_retract_old_z" => b(!m.retract_r),
            "_spindle_rpm_mode" => 1.0,
            "_spindle_css_mode" => 0.0,
            "_ijk_absolute_mode" => b(m.ijk_absolute),
            "_lathe_diameter_mode" => 0.0,
            "_lathe_radius_mode" => 1.0,
            "_spindle_on" => b(m.spindle != 0),
            "_spindle_cw" => b(m.spindle == 1),
            "_mist" => b(m.mist),
            "_flood" => b(m.flood),
            "_speed_override" => b(m.speed_override),
            "_feed_override" => b(m.feed_override),
            "_adaptive_feed" => b(m.adaptive_feed),
            "_feed_hold" => b(m.feed_hold),
            "_feed" => m.feed / k,
            "_rpm" => m.speed,
            "_current_tool" => self.tool.map_or(0.0, f64::from),
            "_selected_tool" => self.selected.map_or(-1.0, f64::from),
            "_current_pocket" => self.tool.map_or(0.0, f64::from),
            "_selected_pocket" => self.selected.map_or(-1.0, f64::from),
            "_x" => self.prog_units()[0],
            "_y" => self.prog_units()[1],
            "_z" => self.prog_units()[2],
            "_a" => self.prog_abc()[0],
            "_b" => self.prog_abc()[1],
            "_c" => self.prog_abc()[2],
            "_u" | "_v" | "_w" => 0.0,
            "_abs_x" => self.pos[0] / k,
            "_abs_y" => self.pos[1] / k,
            "_abs_z" => self.pos[2] / k,
            "_abs_a" => self.abc[0],
            "_abs_b" => self.abc[1],
            "_abs_c" => self.abc[2],
            "_abs_u" | "_abs_v" | "_abs_w" => 0.0,
            "_value" => self.return_value,
            "_value_returned" => b(self.value_returned),
            "_call_level" => self.call_level as f64,
            "_remap_level" => self.remap_level as f64,
            "_task" => 1.0,
            "_vmajor" => 2.9,
            "_vminor" => 0.0,
            "_metric_machine" => 1.0,
            _ => return None,
        };
        Some(v)
    }

    /// Whether `#n` may be set by a program; if not, why.
    pub fn writable(&self, n: usize) -> Result<(), String> {
        match n {
            5400..=5413 => Err(format!(
                "#{n} describes the tool in the spindle: it is set by M06 and G43 only"
            )),
            5420..=5428 => Err(format!("#{n} is the current position: it cannot be set")),
            5600..=5602 => Err(format!(
                "#{n} is the tool changer's status: it cannot be set"
            )),
            _ => Ok(()),
        }
    }

    /// The M2/M30 reset (LinuxCNC's `convert_stop`): G54 in force (its offset and rotation
    /// read again), G17, G90, G94, F0, feed and speed overrides on, G40, the spindle
    /// stopped, G1, coolant off. The tool length offset, G92, the units, the tool and every
    /// parameter stay.
    pub fn program_end_reset(&mut self) {
        self.select_system(0);
        // Fanuc's G69 is in force after M02/M30 and RESET.
        self.g68 = None;
        let m = &mut self.modal;
        m.plane = Plane::XY;
        m.incremental = false;
        m.feed_mode = FeedMode::PerMinute;
        m.feed = 0.0;
        m.feed_override = true;
        m.speed_override = true;
        m.comp = CompSide::Off;
        m.spindle = 0;
        m.motion = Motion::Feed;
        m.mist = false;
        m.flood = false;
        self.comp_radius = 0.0;
        self.comp_tool = None;
        self.cycle = CycleMemory::default();
        self.saved.clear();
        self.call_level = 0;
    }

    /// A named parameter's value: a predefined one, or one set at the given call level
    /// (`locals`: the frame's own locals when in a subroutine).
    pub fn named_value(&self, name: &str, locals: Option<&HashMap<String, f64>>) -> Option<f64> {
        if name.starts_with('_') {
            return self
                .predefined(name)
                .or_else(|| self.named.get(name).copied());
        }
        match locals {
            Some(l) => l.get(name).copied(),
            None => self.named.get(name).copied(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_and_machine_frames_are_inverse_with_rotation_g92_and_tool_length() {
        let mut s = InterpState::default();
        s.params[system_base(1) + 1] = 100.0;
        s.params[system_base(1) + 2] = 50.0;
        s.params[system_base(1) + 3] = -20.0;
        s.params[system_base(1) + 10] = 30.0;
        s.select_system(1);
        s.g92 = [1.0, 2.0, 3.0];
        s.tlo = [0.0, 0.0, 150.0];
        let p = [10.0, -5.0, 7.0];
        let m = s.to_machine(p);
        let back = s.to_program(m);
        for a in 0..3 {
            assert!((back[a] - p[a]).abs() < 1e-12, "{back:?}");
        }
        // X10 in a system turned 90°: along machine Y.
        s.params[system_base(1) + 10] = 90.0;
        s.select_system(1);
        s.g92 = [0.0; 3];
        let m = s.to_machine([10.0, 0.0, 0.0]);
        assert!((m[0] - 100.0).abs() < 1e-9 && (m[1] - 60.0).abs() < 1e-9);
    }

    #[test]
    fn persistent_parameters_round_trip_and_select_the_system() {
        let mut s = InterpState::default();
        s.params[5220] = 3.0;
        s.params[system_base(2) + 1] = 12.5;
        s.params[5161] = -1.0;
        let p = s.persistent();
        let t = InterpState::with_persistent(&p, [0.0; 3], Some(4));
        assert_eq!(t.modal.cs, 2);
        assert_eq!(t.origin[0], 12.5);
        assert_eq!(t.params[5161], -1.0);
        assert_eq!(t.params[5400], 4.0);
        assert_eq!(t.predefined("_coord_system"), Some(560.0));
    }

    #[test]
    fn m2_resets_what_linuxcnc_resets() {
        let mut s = InterpState::default();
        s.modal.incremental = true;
        s.modal.plane = Plane::XZ;
        s.modal.inch = true;
        s.tlo = [0.0, 0.0, 150.0];
        s.modal.cs = 3;
        s.program_end_reset();
        assert!(!s.modal.incremental);
        assert_eq!(s.modal.plane, Plane::XY);
        assert_eq!(s.modal.cs, 0);
        assert!(s.modal.inch, "units stay");
        assert_eq!(s.tlo[2], 150.0, "tool length stays");
        assert_eq!(s.modal.motion, Motion::Feed);
    }
}
