//! Fanuc Custom Macro B's system variables in the Fanuc dialect (docs/gcode.md "Fanuc
//! dialect", "System variables"): the modal information #4001–#4130 and #4201–#4330, the
//! positions #5001–#5048, the tool length offsets #5081–#5088, the tool offsets #2001–#2800
//! and #10001–#13999 (memory C), the part counter #3901/#3902, and the clocks #3001/#3002.
//! Each but the clocks is worked out when read from the interpreter's state as read (the
//! state the machine will have when it reaches the line), as LinuxCNC's #5420 is; the clocks
//! are the machine's when it reached the line (reading waits for it, `GcodeSource`). The
//! LinuxCNC dialect never comes here.

use super::exec::{Clocks, Event};
use super::read::MAX_PARAM;
use super::state::{CompSide, FeedMode, InterpState, Motion, PathMode};
use crate::block::Plane;
use crate::tooldata::Magazine;

/// The highest variable number the Fanuc dialect reads (#13999: radius geometry of offset 999).
pub const MAX_FANUC_VAR: usize = 13999;

/// What the system variables are worked out from.
pub struct SysEnv<'a> {
    /// The interpreter's state as read.
    pub st: &'a InterpState,
    /// The tool data.
    pub magazine: &'a Magazine,
    /// The console's part counter: parts made and required (None: no counter here).
    pub parts: Option<(u64, u64)>,
    /// The number of the program running now (#4115), if it has one.
    pub program: Option<f64>,
    /// The machine's clocks when it reached this line, once it has answered; until then a
    /// read of #3001/#3002 sets `wants_clocks` and fails (the line is read again with them,
    /// or refused with the reason).
    pub clocks: Option<Clocks>,
    /// The clock read without `clocks`, if one was.
    pub wants_clocks: &'a std::cell::Cell<Option<usize>>,
}

/// Where Fanuc's clocks come back to 0, ms: #3001 at 2^31 ms, #3002 at 2^35 ms (9544.37 h).
const CLOCK_WRAP_MS: [f64; 2] = [2_147_483_648.0, 34_359_738_368.0];

/// The clock #3001 (millisecond) or #3002 (hour)'s name.
pub fn clock_name(n: usize) -> String {
    format!(
        "#{n} (the {} clock)",
        if n == 3001 { "millisecond" } else { "hour" }
    )
}

/// Clock `n`'s machine time at `c`, whole ms (as Fanuc counts): 3001 since power-on, 3002
/// with the cycle-start lamp lit.
fn machine_ms(n: usize, c: Clocks) -> f64 {
    let ns = if n == 3001 { c.machine_ns } else { c.cycle_ns };
    (ns / 1_000_000) as f64
}

/// The value of clock `n` at `c` (#3001 ms, #3002 hours), moved by what the program wrote to
/// it, back to 0 where Fanuc's comes back.
fn clock_value(n: usize, c: Clocks, st: &InterpState) -> f64 {
    let i = n - 3001;
    let ms = (machine_ms(n, c) + st.clock_offset_ms[i]).rem_euclid(CLOCK_WRAP_MS[i]);
    if i == 0 {
        ms
    } else {
        ms / 3.6e6
    }
}

/// What the hour clock #3002 reads, hours, once the cycle-start lamp has been lit for
/// `lamp_ns` since power-on: what the stores keep of it (docs/gcode.md "Fanuc dialect").
pub fn hour_clock(lamp_ns: u64, st: &InterpState) -> f64 {
    clock_value(
        3002,
        Clocks {
            machine_ns: 0,
            cycle_ns: lamp_ns,
        },
        st,
    )
}

/// `#3001=v` or `#3002=v` at `c`: the clock reads `v` there (to the ms) and counts on from it.
pub fn set_clock(n: usize, v: f64, c: Clocks, st: &mut InterpState) -> Result<(), String> {
    let i = n - 3001;
    let ms = if i == 0 { v } else { v * 3.6e6 };
    let max = CLOCK_WRAP_MS[i];
    if read_null(v) {
        return Err(format!("{}: a clock cannot be null", clock_name(n)));
    }
    if !(ms.is_finite() && (0.0..max).contains(&ms)) {
        let (top, unit) = if i == 0 {
            (max - 1.0, "ms")
        } else {
            (max / 3.6e6, "hours")
        };
        return Err(format!(
            "{}: {v} is not a time it counts (0 to {top} {unit})",
            clock_name(n)
        ));
    }
    st.clock_offset_ms[i] = ms.round() - machine_ms(n, c);
    Ok(())
}

/// A tool offset variable: which of memory C's four kinds, of which offset number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ToolVar {
    /// The offset number (novanc's T code, as H and D name them).
    pub offset: u32,
    /// Radius (else length).
    pub radius: bool,
    /// Wear (else geometry).
    pub wear: bool,
}

/// The tool offset variable `#n`, if it is one: #2001–#2200 length wear, #2201–#2400 length
/// geometry, #2401–#2600 radius wear, #2601–#2800 radius geometry (offsets 1–200), and
/// #10001–#10999, #11001–, #12001–, #13001– the same for offsets 1–999 (Fanuc 0i memory C).
pub fn tool_var(n: usize) -> Option<ToolVar> {
    let (kind, offset) = match n {
        2001..=2800 => ((n - 2001) / 200, (n - 2001) % 200 + 1),
        10001..=13999 if !n.is_multiple_of(1000) => ((n - 10000) / 1000, n % 1000),
        _ => return None,
    };
    Some(ToolVar {
        offset: offset as u32,
        radius: kind >= 2,
        wear: kind % 2 == 0,
    })
}

fn var_name(v: ToolVar) -> String {
    format!(
        "{} {}",
        if v.radius { "radius" } else { "length" },
        if v.wear { "wear" } else { "geometry" }
    )
}

/// The value of a tool offset variable, mm: (length, radius) geometry or wear.
fn tool_value(v: ToolVar, n: usize, m: &Magazine) -> Result<f64, String> {
    let rec = m.tools.get(v.offset).ok_or_else(|| {
        format!(
            "#{n} ({} of offset {o}): T code {o} has no tool data in the tool file",
            var_name(v),
            o = v.offset
        )
    })?;
    Ok(match (v.radius, v.wear) {
        (false, false) => rec.set_length,
        (false, true) => rec.wear_length,
        (true, false) => rec.diameter / 2.0,
        (true, true) => rec.wear_diameter / 2.0,
    })
}

/// A Fanuc system variable's value, or why it cannot be read; `None` when `#n` is not one of
/// these (a variable kept as LinuxCNC's parameters are).
pub fn read(n: usize, e: &SysEnv) -> Option<Result<f64, String>> {
    let st = e.st;
    let k = st.factor();
    if let Some(v) = tool_var(n) {
        return Some(tool_value(v, n, e.magazine).map(|mm| mm / k));
    }
    Some(match n {
        3001 | 3002 => match e.clocks {
            Some(c) => Ok(clock_value(n, c, st)),
            None => {
                e.wants_clocks.set(Some(n));
                Err(format!("{} waits for the machine", clock_name(n)))
            }
        },
        3901 | 3902 => parts(n, e.parts),
        4001..=4130 | 4201..=4330 => return modal_info(n, st, e.program, st),
        5001..=5008 | 5021..=5028 | 5041..=5048 => position(n, st),
        5081..=5088 => tool_length(n, st),
        _ if n > MAX_PARAM => Err(unknown(n)),
        _ => return None,
    })
}

fn unknown(n: usize) -> String {
    format!("#{n}: novanc has no such variable (the Fanuc dialect reads #1 to #{MAX_PARAM}, and the tool offsets #10001 to #{MAX_FANUC_VAR})")
}

/// A machine's modal information as Fanuc numbers it (Custom Macro B's #4000 + item, and
/// #4200 + item the same): the items it keeps and their values. The one reader keeps
/// #4113–#4115 itself for every machine ([`modal_info`]); the mill's is its
/// [`InterpState`], the lathe's its reader (docs/lathe-gcode.md "System variables").
pub trait Modal {
    /// The items it keeps, ascending (#4113–#4115 aside).
    fn items(&self) -> &'static [usize];
    /// Item `i`'s value, for each of [`Modal::items`] (null: none yet).
    fn item(&self, i: usize) -> f64;
}

/// The modal items the one reader keeps for every machine: the last M code read, the last
/// N, the number of the program running.
const READER_ITEMS: [usize; 3] = [113, 114, 115];

/// Modal information `#n` (#4001–#4130, #4201–#4330): the one reader's items (#4113 the
/// last M code, #4114 the last N, #4115 the program running, `program`), else machine `m`'s,
/// else refused with the list of those there are; `None` for another number.
pub fn modal_info(
    n: usize,
    st: &InterpState,
    program: Option<f64>,
    m: &dyn Modal,
) -> Option<Result<f64, String>> {
    let i = match n {
        4001..=4130 => n - 4000,
        4201..=4330 => n - 4200,
        _ => return None,
    };
    Some(match i {
        113 => Ok(st.fanuc_m),
        114 => Ok(st.line_number),
        115 => Ok(program.unwrap_or(f64::NAN)),
        _ if m.items().contains(&i) => Ok(m.item(i)),
        _ => {
            let mut have: Vec<usize> = m.items().iter().chain(&READER_ITEMS).copied().collect();
            have.sort_unstable();
            let have: Vec<String> = have.iter().map(|j| format!("#{}", n - i + j)).collect();
            Err(format!(
                "#{n}: novanc keeps no such modal information (it has {})",
                have.join(" ")
            ))
        }
    })
}

/// The mill's modal information (docs/gcode.md "System variables").
impl Modal for InterpState {
    fn items(&self) -> &'static [usize] {
        &[1, 2, 3, 5, 6, 7, 8, 9, 10, 14, 15, 107, 109, 111, 119, 120]
    }

    fn item(&self, i: usize) -> f64 {
        let st = self;
        let m = &st.modal;
        match i {
            1 => match m.motion {
                Motion::Rapid => 0.0,
                Motion::Feed => 1.0,
                Motion::Cw => 2.0,
                Motion::Ccw => 3.0,
                _ => 80.0,
            },
            2 => match m.plane {
                Plane::XY => 17.0,
                Plane::XZ => 18.0,
                Plane::YZ => 19.0,
            },
            3 => {
                if m.incremental {
                    91.0
                } else {
                    90.0
                }
            }
            5 => match m.feed_mode {
                FeedMode::InverseTime => 93.0,
                FeedMode::PerMinute => 94.0,
                FeedMode::PerRevolution => 95.0,
            },
            6 => {
                if m.inch {
                    20.0
                } else {
                    21.0
                }
            }
            7 => match m.comp {
                CompSide::Off => 40.0,
                CompSide::Left => 41.0,
                CompSide::Right => 42.0,
            },
            8 => {
                if st.tlo_tool.is_some() || st.tlo.iter().any(|&v| v != 0.0) {
                    43.0
                } else {
                    49.0
                }
            }
            9 => match m.motion {
                Motion::Cycle(g) => f64::from(g) / 10.0,
                _ => 80.0,
            },
            10 => {
                if m.retract_r {
                    99.0
                } else {
                    98.0
                }
            }
            14 => match m.cs {
                cs @ 0..=5 => 54.0 + cs as f64,
                cs => 59.0 + (cs - 5) as f64 / 10.0,
            },
            15 => match m.path {
                PathMode::Blend { .. } => 64.0,
                _ => 61.0,
            },
            107 => st.comp_tool.map_or(0.0, f64::from),
            109 => m.feed / st.factor(),
            111 => st.tlo_tool.map_or(0.0, f64::from),
            119 => m.speed,
            120 => st.selected.map_or(f64::NAN, f64::from),
            _ => f64::NAN,
        }
    }
}

/// #3901/#3902: parts machined and required, from the console's counter `parts` (None: no
/// counter here).
pub fn parts(n: usize, parts: Option<(u64, u64)>) -> Result<f64, String> {
    match parts {
        Some((made, required)) => Ok(if n == 3901 { made } else { required } as f64),
        None => Err(format!(
            "#{n} (parts {}): there is no part counter here (the console's POS page keeps one)",
            if n == 3901 { "machined" } else { "required" }
        )),
    }
}

/// #5001–#5008 (block end, work, tool offset not included), #5021–#5028 (machine),
/// #5041–#5048 (work, tool offset included): axis 1–3 X Y Z, 4 A.
fn position(n: usize, st: &InterpState) -> Result<f64, String> {
    let kind = (n - 5001) / 20;
    let axis = (n - 5001) % 20;
    let what = [
        "the block end position",
        "the machine position",
        "the work position",
    ][kind];
    if st.modal.comp != CompSide::Off {
        return Err(format!(
            "#{n} ({what}) cannot be read with cutter radius compensation on"
        ));
    }
    if let Some(r) = axis
        .checked_sub(3)
        .filter(|&r| st.rotaries.get(r).is_some_and(|w| w.is_some()))
    {
        // Degrees: the work positions less the axis's offsets, the machine's as it stands.
        return Ok(if kind == 1 {
            st.abc[r]
        } else {
            st.prog_abc()[r]
        });
    }
    if axis >= 3 {
        return Err(format!(
            "#{n} ({what} of axis {}): this machine has the axes {}",
            axis + 1,
            st.axes_named()
        ));
    }
    let k = st.factor();
    let mm = match kind {
        0 => st.prog()[axis],
        1 => st.pos[axis],
        _ => st.work_with_tool(st.pos)[axis],
    };
    Ok(mm / k)
}

/// #5081–#5088: the tool length offset in force along axis 1–3 X Y Z (G43, G43.1: the
/// state's, in program units); axis 4 A has none (0 on a machine with A).
fn tool_length(n: usize, st: &InterpState) -> Result<f64, String> {
    let axis = n - 5081;
    match axis {
        0..=2 => Ok(st.tlo[axis] / st.factor()),
        3..=5 if st.rotaries[axis - 3].is_some() => Ok(0.0),
        _ => Err(format!(
            "#{n} (the tool length offset of axis {}): this machine has the axes {}",
            axis + 1,
            st.axes_named()
        )),
    }
}

/// Sets a Fanuc system variable: `None` when `#n` is not one (a parameter as LinuxCNC's);
/// else done, or why not. A tool offset is changed in the tool data and said as an event
/// (the console journals it as OFS does).
pub fn write(
    n: usize,
    v: f64,
    st: &InterpState,
    magazine: &mut Magazine,
    events: &mut Vec<Event>,
) -> Option<Result<(), String>> {
    if let Some(tv) = tool_var(n) {
        return Some(write_tool(n, tv, v * st.factor(), magazine, events));
    }
    if let Some(why) = read_only(n) {
        return Some(Err(why));
    }
    match n {
        5201..=5206 => Some(Err(format!("#{n}: {EXOFS}"))),
        _ if n > MAX_PARAM => Some(Err(unknown(n))),
        _ => None,
    }
}

/// Why Fanuc's external work offset (EXOFS: #5201–#5206, G10 L2 P0), which shifts every work
/// system at once, is refused: novanc has none, and LinuxCNC's P0 (the system in force) would
/// set one system where a Fanuc program meant to shift them all.
pub const EXOFS: &str = "Fanuc's external work offset (shifting every work system) is not on this machine: set G54–G59 with G10 L2 P1–P6";

/// Why system variable `#n` cannot be written, if it is one a program only reads: the part
/// counter, the modal information, the positions, the tool length offset.
pub fn read_only(n: usize) -> Option<String> {
    let what = match n {
        3901 | 3902 => {
            return Some(format!(
            "#{n}: the part counter is set on the POS page (PARTS n, TARGET n), not by a program"
        ))
        }
        4001..=4130 | 4201..=4330 => "modal information",
        5001..=5008 => "the block end position",
        5021..=5028 => "the machine position",
        5041..=5048 => "the work position",
        5081..=5088 => "the tool length offset",
        _ => return None,
    };
    Some(format!("#{n} ({what}) is read-only"))
}

/// Fanuc's G10 L10–L13 P R (memory C, docs/gcode.md "Fanuc dialect"): offset P's length
/// geometry (L10), length wear (L11), radius geometry (L12) or radius wear (L13) set to R mm,
/// or R added to it under G91; as a program's #11000+P, #10000+P, #13000+P or #12000+P
/// would set it. The offset number is the T code, as H and D are.
pub fn g10_offset(
    l: u32,
    p: u32,
    r_mm: f64,
    incremental: bool,
    magazine: &mut Magazine,
    events: &mut Vec<Event>,
) -> Result<(), String> {
    let tv = ToolVar {
        offset: p,
        radius: l >= 12,
        wear: l == 11 || l == 13,
    };
    let n = 10_000 + 1000 * (2 * usize::from(tv.radius) + usize::from(!tv.wear)) + p as usize;
    let now = match magazine.tools.get(p) {
        Some(rec) => match (tv.radius, tv.wear) {
            (false, false) => rec.set_length,
            (false, true) => rec.wear_length,
            (true, false) => rec.diameter / 2.0,
            (true, true) => rec.wear_diameter / 2.0,
        },
        None => 0.0,
    };
    let v = if incremental { now + r_mm } else { r_mm };
    write_tool(n, tv, v, magazine, events)
}

fn write_tool(
    n: usize,
    tv: ToolVar,
    mm: f64,
    magazine: &mut Magazine,
    events: &mut Vec<Event>,
) -> Result<(), String> {
    if read_null(mm) {
        return Err(format!(
            "#{n} ({}): a tool offset cannot be null",
            var_name(tv)
        ));
    }
    let t = tv.offset;
    let Some(rec) = magazine.tools.get(t).cloned() else {
        return Err(format!(
            "#{n} ({} of offset {t}): T code {t} has no tool data in the tool file",
            var_name(tv)
        ));
    };
    let mut new = rec.clone();
    match (tv.radius, tv.wear) {
        (false, false) => new.set_length = mm,
        (false, true) => new.wear_length = mm,
        (true, false) => new.diameter = 2.0 * mm,
        (true, true) => new.wear_diameter = 2.0 * mm,
    }
    let max = crate::tooldata::MAX_WEAR_MM;
    if tv.wear && mm.abs() * if tv.radius { 2.0 } else { 1.0 } > max {
        return Err(format!(
            "#{n} ({}): {mm} mm is beyond the largest wear ({max} mm either way)",
            var_name(tv)
        ));
    }
    if !(new.length().is_finite() && new.length().abs() <= 1e5) {
        return Err(format!(
            "#{n} ({}): the tool length is out of range",
            var_name(tv)
        ));
    }
    if !(new.cutting_diameter() > 0.0 && new.diameter > 0.0 && new.cutting_diameter() <= 1e5) {
        return Err(format!(
            "#{n} ({}): it leaves no diameter (diameter {} mm, wear {} mm)",
            var_name(tv),
            new.diameter,
            new.wear_diameter
        ));
    }
    magazine.tools.set(t, Some(new.clone()));
    events.push(Event::ToolOffsets {
        t,
        length: new.set_length,
        diameter: new.diameter,
        wear_length: new.wear_length,
        wear_diameter: new.wear_diameter,
    });
    Ok(())
}

fn read_null(v: f64) -> bool {
    super::read::is_null(v)
}
