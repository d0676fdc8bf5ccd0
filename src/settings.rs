//! Machine settings: the numbers a machine builder sets once (units, rates, limits, timings).
//!
//! Every length is in millimetres, every feed in mm/min, every time in nanoseconds of machine
//! time. One pulse is `pulse_mm` (0.001 mm by default). Positions inside the controller are whole
//! pulses in machine coordinates; machine zero (the `CL` position) is (0, 0, 0).

use crate::block::Axes;

/// The machine settings in force for the translator, the pulse core and the console.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineSettings {
    /// Length of one feed pulse, mm (the least input increment).
    pub pulse_mm: f64,
    /// Rapid traverse rate, mm/min (G00): the path's fastest, the highest of the linear
    /// axes' own rates (`axis_rate`), each of which still holds its axis.
    pub rapid_mm_min: f64,
    /// Path acceleration and deceleration, mm/s²: the highest of the linear axes', each of
    /// which still holds its axis (`axis_accel`) on a straight move; an arc is held to the
    /// lowest.
    pub accel_mm_s2: f64,
    /// Each axis's own rate, X Y Z mm/min and A B C degrees/min (infinite: none of its own):
    /// a straight move is slowed so that no axis moves faster than its own (docs/pulse-core.md
    /// "Axes", LinuxCNC's rule and a Fanuc's linear-interpolation positioning). The rotary
    /// axes' since stop 54, the linear axes' since stop 58; before, X Y Z kept one rate, the
    /// lowest of theirs, so an axis with a higher rate never reached it.
    pub axis_rate: [f64; crate::block::MAX_AXES],
    /// Each axis's own acceleration, X Y Z mm/s² and A B C degrees/s² (infinite: none of its
    /// own).
    pub axis_accel: [f64; crate::block::MAX_AXES],
    /// Default clearance SCL above the surface where rapid advance ends, mm.
    pub clearance_mm: f64,
    /// What each axis is: linear (mm) or rotary (degrees, perhaps wrapped). X, Y and Z are
    /// linear; A, B and C are the machine's when rotary (`has_axis`), absent when `Linear`
    /// (docs/pulse-core.md, "Axes").
    pub axis_kinds: Axes<AxisKind>,
    /// Lower travel limit of each axis in machine coordinates, mm (degrees for a rotary axis).
    pub travel_min_mm: Axes<f64>,
    /// Upper travel limit of each axis in machine coordinates, mm (degrees for a rotary axis).
    pub travel_max_mm: Axes<f64>,
    /// Jog feed in CONTINUOUS mode, mm/min.
    pub jog_mm_min: f64,
    /// The F0 rate of the rapid override (Fanuc parameter 1421): rapids, jogs and returns
    /// move at no more than this with the rapid override at F0, mm/min (docs/pulse-core.md,
    /// "Overrides and switches").
    pub rapid_f0_mm_min: f64,
    /// Increment of one STEP jog, mm.
    pub step_mm: f64,
    /// Time a tool change (M06) takes, ns.
    pub tool_change_ns: u64,
    /// Where Z goes for a tool change (M06), machine mm: the top of the Z travel, machine Z 0,
    /// on the centre (docs/gcode.md "M06").
    pub tool_change_z_mm: f64,
    /// Time the spindle takes to start, stop or reverse (M03/M04/M05), ns.
    pub spindle_ns: u64,
    /// The spindle's highest speed, rpm: caps its target (G96 included) (docs/pulse-core.md,
    /// "The spindle").
    pub spindle_max_rpm: f64,
    /// The spindle's acceleration, rpm/s; 0: it reaches a new speed at once (the centre).
    pub spindle_accel_rpm_s: f64,
    /// The spindle encoder's counts per revolution (one index per revolution).
    pub spindle_encoder_lines: u32,
    /// The tools are on a turret: a T word indexes it at once and is the tool in use (a
    /// lathe's channel); otherwise T selects and M6 changes (a magazine).
    pub tool_turret: bool,
    /// Where the reference return (HOME) takes the axes, machine mm: machine zero on the
    /// centre, the top of each axis's travel on a lathe's channel (docs/pulse-core.md
    /// "Position memory and the reference return").
    pub reference_mm: Axes<f64>,
    /// The axis that takes the tool away from the work (Z on the centre, X on a lathe): a
    /// return (HOME, the way back after a manual move in a hold) moves it first when it goes
    /// up (+), away from the work, and last when it goes down.
    pub retract_axis: usize,
    /// Number of pockets in the magazine (T codes 1..=capacity).
    pub magazine_capacity: u32,
    /// Capacity of the block buffer B1, in blocks.
    pub b1_capacity: usize,
    /// NCBR real-time clock period, ns (5 ms in the patent).
    pub ncbr_period_ns: u64,
    /// Tape reader 13's speed, frames (characters) per second: 300 by default, a common
    /// photoelectric reader (docs/tape.md, "At the console").
    pub tape_chars_per_s: u32,
    /// How the pulse core distributes the pulses of lines, rapids and arcs (docs/pulse-core.md).
    pub interpolator: Interpolator,
    /// The error-proportional interpolator's constant L (adder 100 of seed 001), pulses: the
    /// tail's time constant is L / f_r (docs/pulse-core.md, "Choosing L").
    pub ep_l_pulses: i64,
    /// The stock on the table, in machine coordinates of the tool tip: what a probe touches
    /// (docs/gcode.md "Probing").
    pub workpiece: crate::workpiece::Workpiece,
    /// M6 remapped to this O-word subroutine (lower case), as LinuxCNC's
    /// `REMAP=M6 modalgroup=6 ngc=NAME`: the machine description's `remap` line
    /// (docs/gcode.md "Remapping M6 and other M codes"). None: M6 is the built-in change.
    pub remap_m6: Option<String>,
    /// Other M codes remapped to O-word subroutines, as LinuxCNC's `REMAP=M31 modalgroup=10
    /// ngc=NAME`: codes novanc does not define (a machine builder's, such as Haas's M31 chip
    /// conveyor), in modal group 10 (docs/gcode.md "Remapping M6 and other M codes"). Empty:
    /// none.
    pub remap_m: Vec<Remap>,
    /// The G-code dialect programs are read in: LinuxCNC's (the default) or Fanuc's Custom
    /// Macro B (docs/gcode.md "Fanuc dialect"): the machine description's `dialect` line, or
    /// `--dialect`.
    pub dialect: Dialect,
    /// The Fanuc dialect's settings of a machine: Fanuc's parameters 6001#6 and 3401#0
    /// (the description's `common` and `decimal` lines; docs/gcode.md "Fanuc dialect").
    pub fanuc: FanucSettings,
}

/// What a Fanuc's parameters decide that the Fanuc dialect follows (docs/gcode.md "Fanuc
/// dialect"). The defaults are Fanuc's parameters at 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct FanucSettings {
    /// RESET keeps the common variables #100–#199 (parameter 6001#6 CCV = 1: the
    /// description's `common keep`); false: RESET makes them vacant (`common clear`).
    pub keep_common: bool,
    /// Calculator-type decimal point input (parameter 3401#0 DPI = 1: `decimal
    /// calculator`): `X10` is 10 mm; false: in least increments, 0.010 mm (`decimal
    /// increments`).
    pub calculator: bool,
    /// G04's P written with a decimal point is seconds, without one milliseconds (a Haas's
    /// reading: the description's `g04 p point seconds`); false: a P with a point is refused,
    /// as Fanuc refuses it (`g04 p point refuse`, the default).
    pub p_point_seconds: bool,
}

/// An M code a machine description remaps to an O-word subroutine (`remap M59 modalgroup=10
/// argspec=Pq ngc=relay`; docs/gcode.md "Remapping M6 and other M codes").
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Remap {
    /// The M code.
    pub code: u32,
    /// The subroutine's name, lower case.
    pub ngc: String,
    /// LinuxCNC's `argspec`: the letters of the code's line the subroutine gets as its local
    /// parameters `#<p>`, `#<q>` ...; a capital letter must be on the line. Empty: none.
    pub argspec: String,
}

impl Remap {
    /// The remap of M`code` to `ngc`, with no arguments.
    pub fn new(code: u32, ngc: &str) -> Remap {
        Remap {
            code,
            ngc: ngc.to_string(),
            argspec: String::new(),
        }
    }

    /// Whether its subroutine takes the word `letter` of the line (upper case).
    pub fn takes(&self, letter: char) -> bool {
        self.argspec
            .chars()
            .any(|c| c.eq_ignore_ascii_case(&letter))
    }
}

/// The G-code dialect (docs/gcode.md "Fanuc dialect").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dialect {
    /// LinuxCNC 2.9's RS274NGC.
    #[default]
    LinuxCnc,
    /// Fanuc 0i/30i with Custom Macro B.
    Fanuc,
}

impl Dialect {
    /// The dialect named `s` (`fanuc` or `linuxcnc`, any case).
    pub fn parse(s: &str) -> Result<Dialect, String> {
        match s.to_ascii_lowercase().as_str() {
            "fanuc" => Ok(Dialect::Fanuc),
            "linuxcnc" => Ok(Dialect::LinuxCnc),
            _ => Err(format!("dialect '{s}': fanuc or linuxcnc")),
        }
    }

    /// Its name as `parse` reads it and the stores write it: `fanuc` or `linuxcnc`.
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Fanuc => "fanuc",
            Dialect::LinuxCnc => "linuxcnc",
        }
    }
}

/// The letters of the axes, by index.
pub const AXIS_NAMES: [char; crate::block::MAX_AXES] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// What an axis is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AxisKind {
    /// A linear axis, mm; one pulse is `pulse_mm`.
    #[default]
    Linear,
    /// A rotary axis, degrees; one pulse is `pulse_mm` degrees. `wrap`: LinuxCNC's
    /// WRAPPED_ROTARY, no travel limits, an absolute position is taken modulo 360
    /// (docs/pulse-core.md, "Axes").
    Rotary {
        /// Wrapped at 360°.
        wrap: bool,
    },
}

/// The pulse distribution method of the pulse core.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Interpolator {
    /// Toyoda's LINE/PCHK major-axis distribution with the KT ramps (seed 000).
    #[default]
    Dda,
    /// Pratt & Whitney's pulse trains at rates proportional to the remaining errors (seed 001).
    ErrorProportional,
}

impl Interpolator {
    /// The setting's word: `dda` or `error-proportional`.
    pub fn name(self) -> &'static str {
        match self {
            Interpolator::Dda => "dda",
            Interpolator::ErrorProportional => "error-proportional",
        }
    }

    /// Reads the setting's word (`dda`, `error-proportional`, or `ep` for short).
    pub fn parse(s: &str) -> Result<Interpolator, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "dda" => Ok(Interpolator::Dda),
            "error-proportional" | "ep" => Ok(Interpolator::ErrorProportional),
            other => Err(format!(
                "interpolator '{other}' is not dda or error-proportional"
            )),
        }
    }
}

/// Reads L for the error-proportional interpolator: a whole number of pulses, 1 to 10⁸.
pub fn parse_ep_l(s: &str) -> Result<i64, String> {
    match s.trim().parse::<i64>() {
        Ok(l) if (1..=100_000_000).contains(&l) => Ok(l),
        _ => Err(format!(
            "L '{}' is not a whole number of pulses from 1 to 100000000",
            s.trim()
        )),
    }
}

/// The error-proportional interpolator's recirculation cycle, ns (f_r = 500 kHz): the error
/// gates open at most once a cycle, so no axis gets more than f_r pulses a second.
pub const EP_CYCLE_NS: u64 = 2_000;

/// Default L: f_r / Kv with the position loop gain Kv = 1 (m/min)/mm = 16.7 s⁻¹, a common
/// machine-tool servo (docs/pulse-core.md, "Choosing L"): 500,000 / 16.67 = 30,000 pulses.
pub const EP_L_DEFAULT: i64 = 30_000;

impl Default for MachineSettings {
    /// The centre's settings: `machines/centre.machine` (the embedded description, read once)
    /// over [`MachineSettings::builtin`], so that `--machine FILE` and the defaults are one
    /// path (docs/lathe.md "Machine description").
    fn default() -> Self {
        static CENTRE: std::sync::OnceLock<MachineSettings> = std::sync::OnceLock::new();
        CENTRE
            .get_or_init(
                || match crate::lathe::desc::parse(crate::lathe::desc::CENTRE) {
                    Ok(crate::lathe::desc::MachineDesc::Mill(s)) => s,
                    // A unit test parses the embedded file; this arm is never taken.
                    _ => MachineSettings::builtin(),
                },
            )
            .clone()
    }
}

impl MachineSettings {
    /// What a machine description starts from: the numbers it does not give (timings, jog,
    /// buffers, the interpolator), the centre's axes, no workpiece and no M6 remap.
    pub fn builtin() -> Self {
        MachineSettings {
            pulse_mm: 0.001,
            rapid_mm_min: 12_000.0,
            accel_mm_s2: 1_000.0,
            axis_rate: [f64::INFINITY; crate::block::MAX_AXES],
            axis_accel: [f64::INFINITY; crate::block::MAX_AXES],
            clearance_mm: 2.0,
            axis_kinds: Axes([AxisKind::Linear; crate::block::MAX_AXES]),
            travel_min_mm: Axes::from([0.0, 0.0, -600.0]),
            travel_max_mm: Axes::from([1_000.0, 800.0, 0.0]),
            jog_mm_min: 1_000.0,
            rapid_f0_mm_min: 400.0,
            step_mm: 0.1,
            tool_change_ns: 4_000_000_000,
            tool_change_z_mm: 0.0,
            spindle_ns: 1_000_000_000,
            spindle_max_rpm: 100_000.0,
            spindle_accel_rpm_s: 0.0,
            spindle_encoder_lines: 1024,
            tool_turret: false,
            reference_mm: Axes::default(),
            retract_axis: 2,
            magazine_capacity: 24,
            b1_capacity: 4096,
            ncbr_period_ns: 5_000_000,
            tape_chars_per_s: 300,
            interpolator: Interpolator::Dda,
            ep_l_pulses: EP_L_DEFAULT,
            workpiece: crate::workpiece::Workpiece::default(),
            remap_m6: None,
            remap_m: Vec::new(),
            dialect: Dialect::LinuxCnc,
            fanuc: FanucSettings {
                keep_common: false,
                calculator: false,
                p_point_seconds: false,
            },
        }
    }
}

/// Each axis's own rate (or acceleration) from those given (`(axis, value)`), the others none
/// of their own (infinite).
pub fn own_rates(given: &[(usize, f64)]) -> [f64; crate::block::MAX_AXES] {
    let mut r = [f64::INFINITY; crate::block::MAX_AXES];
    for &(a, v) in given {
        r[a] = v;
    }
    r
}

impl MachineSettings {
    /// The settings of lathe channel `ch` of `desc` as one channel of the multi-channel kernel
    /// (docs/pulse-core.md, "Channels"): X (a radius) is axis 0, Z axis 2, Y travels 0..0; the
    /// pulse size and the NCBR period are the description's (`tick`, 100 µs on the Citizen:
    /// the lockstep tick the channels ran on, so a block starts, a sync point is released and
    /// E-STOP acts within 100 µs). X and Z each keep their own rate and acceleration (a move
    /// is held so that neither exceeds its own: the path's are the higher, `axis_rate` and
    /// `axis_accel` hold each). The spindle is the channel's
    /// (maximum, acceleration, encoder lines); it has no fixed start time, its ramp is its
    /// time (a cut waits for it at speed). None: no such channel.
    pub fn lathe_channel(desc: &crate::lathe::desc::LatheDesc, ch: usize) -> Option<Self> {
        let c = desc.channels.get(ch)?;
        let [x, z] = &c.axes;
        Some(MachineSettings {
            pulse_mm: desc.pulse_mm,
            rapid_mm_min: x.rapid.max(z.rapid),
            accel_mm_s2: x.accel.max(z.accel),
            axis_rate: own_rates(&[(0, x.rapid), (2, z.rapid)]),
            axis_accel: own_rates(&[(0, x.accel), (2, z.accel)]),
            travel_min_mm: [x.travel[0], 0.0, z.travel[0]].into(),
            travel_max_mm: [x.travel[1], 0.0, z.travel[1]].into(),
            tool_change_ns: 0,
            spindle_ns: 0,
            spindle_max_rpm: c.max_rpm.max(0.0),
            spindle_accel_rpm_s: c.spindle_accel.max(0.0),
            spindle_encoder_lines: c.encoder.max(1),
            tool_turret: true,
            // HOME: X out to the top of its travel first, then Z (a lathe program's `G28 U0`
            // before `G28 W0`).
            reference_mm: [x.travel[1], 0.0, z.travel[1]].into(),
            retract_axis: 0,
            ncbr_period_ns: desc.tick_ns.max(1),
            ..MachineSettings::builtin()
        })
    }

    /// Where Z goes for a tool change, machine mm.
    pub fn tool_change_z(&self) -> f64 {
        self.tool_change_z_mm
    }

    /// Millimetres to the nearest whole pulse.
    pub fn to_pulses(&self, mm: f64) -> i64 {
        (mm / self.pulse_mm).round() as i64
    }

    /// Whole pulses to millimetres.
    pub fn to_mm(&self, pulses: i64) -> f64 {
        pulses as f64 * self.pulse_mm
    }

    /// Travel limits of one axis (0 = X, 1 = Y, 2 = Z, 3 = A, 4 = B, 5 = C) in pulses, (min, max).
    pub fn travel_pulses(&self, axis: usize) -> (i64, i64) {
        (
            self.to_pulses(self.travel_min_mm[axis]),
            self.to_pulses(self.travel_max_mm[axis]),
        )
    }

    /// Whether a machine position in pulses lies inside every travel limit.
    pub fn within_travel(&self, pos: Axes) -> bool {
        self.axis_list().all(|a| {
            let (lo, hi) = self.travel_pulses(a);
            self.wrapped(a) || (pos[a] >= lo && pos[a] <= hi)
        })
    }

    /// Whether axis `a` is a wrapped rotary axis (no travel limits).
    pub fn wrapped(&self, a: usize) -> bool {
        matches!(self.axis_kinds[a], AxisKind::Rotary { wrap: true })
    }

    /// Whether axis `a` is rotary (degrees).
    pub fn rotary(&self, a: usize) -> bool {
        matches!(self.axis_kinds.get(a), Some(AxisKind::Rotary { .. }))
    }

    /// The unit axis `a`'s positions are said in: `deg` on a rotary axis, else `mm`.
    pub fn unit(&self, a: usize) -> &'static str {
        if self.rotary(a) {
            "deg"
        } else {
            "mm"
        }
    }

    /// Whether the machine has axis `a`: X, Y and Z always; A, B and C when its description
    /// gives them (each is rotary).
    pub fn has_axis(&self, a: usize) -> bool {
        a < crate::block::FIRST_ROTARY || self.rotary(a)
    }

    /// The machine's axes, as indices in the order X Y Z A B C.
    pub fn axis_list(&self) -> impl Iterator<Item = usize> + '_ {
        (0..crate::block::MAX_AXES).filter(|&a| self.has_axis(a))
    }

    /// The rotary axes the machine has, as a mask: bit 0 A, bit 1 B, bit 2 C.
    pub fn rotary_mask(&self) -> u8 {
        (0..3).fold(0, |m, r| {
            m | (u8::from(self.rotary(crate::block::FIRST_ROTARY + r)) << r)
        })
    }
}
