//! The machine state a lathe program reads (docs/lathe-gcode.md "System variables"): in
//! Fanuc's dialect the 0i-TF's system variables — the block end position #5001/#5002, the
//! modal information #4001– of the lathe's groups, the tool offsets #2001–/#10001– — and in
//! LinuxCNC's the parameters #5400–#5422 and the predefined named parameters a lathe has.
//! Each is worked out from the lathe reader's state as read: the lathe reads its program
//! whole at START, so a line sees the state the blocks before it leave, which is what the
//! machine has when it reaches the line. None of them is written by a program.

use super::exec::Reader;
use crate::gcode::sysvars::{read_only, Modal};

/// What a tool offset variable of the 0i-TF is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    XWear,
    ZWear,
    RWear,
    Tip,
    XGeometry,
    ZGeometry,
    RGeometry,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::XWear => "X wear",
            Kind::ZWear => "Z wear",
            Kind::RWear => "nose radius wear",
            Kind::Tip => "imaginary tip",
            Kind::XGeometry => "X geometry",
            Kind::ZGeometry => "Z geometry",
            Kind::RGeometry => "nose radius geometry",
        }
    }
}

/// The tool offset variable `#n` of the 0i-TF, if it is one, and its offset number:
/// #2001–#2064 X wear, #2101– Z wear, #2201– nose radius wear, #2301– imaginary tip,
/// #2701– X geometry, #2801– Z geometry, #2901– nose radius geometry (offsets 1–64), and
/// #10001–#10999, #11001–, #12001–, #13001– the first four for offsets 1–999.
fn tool_var(n: usize) -> Option<(Kind, u32)> {
    let kind = match n {
        10001..=13999 if !n.is_multiple_of(1000) => {
            let k = [Kind::XWear, Kind::ZWear, Kind::RWear, Kind::Tip][(n - 10000) / 1000];
            return Some((k, (n % 1000) as u32));
        }
        2001..=2999 => match (n - 2001) / 100 {
            0 => Kind::XWear,
            1 => Kind::ZWear,
            2 => Kind::RWear,
            3 => Kind::Tip,
            7 => Kind::XGeometry,
            8 => Kind::ZGeometry,
            9 => Kind::RGeometry,
            _ => return None,
        },
        _ => return None,
    };
    let offset = (n - 2001) % 100 + 1;
    (offset <= 64).then_some((kind, offset as u32))
}

/// X in program units as it is programmed: on the diameter under G7, the radius under G8.
fn x_programmed(r: &Reader, radius_mm: f64) -> f64 {
    let d = if r.st.diameter { 2.0 } else { 1.0 };
    radius_mm * d / r.st.factor()
}

/// Tool offset variable `#n` (`kind` of offset `offset`): the channel's tool of that number
/// (novanc's offset number is the tool's, T0101), its offsets read as wear, its nose radius
/// as geometry; refused for a tool not on the channel's tool post.
fn tool_value(r: &Reader, n: usize, kind: Kind, offset: u32) -> Result<f64, String> {
    let Some(t) = r.chan.tool(offset) else {
        let have: Vec<String> = r.chan.tools.iter().map(|t| t.number.to_string()).collect();
        return Err(format!(
            "#{n} ({} of offset {offset}): tool {offset} is not on channel {}'s tool post (it has {}; a tool's offsets are its own number's)",
            kind.name(),
            r.ch + 1,
            if have.is_empty() { "none".to_string() } else { have.join(", ") }
        ));
    };
    let k = r.st.factor();
    Ok(match kind {
        Kind::XWear => x_programmed(r, t.offset[0]),
        Kind::ZWear => t.offset[1] / k,
        Kind::RGeometry => t.radius / k,
        Kind::Tip => f64::from(t.tip),
        Kind::RWear | Kind::XGeometry | Kind::ZGeometry => 0.0,
    })
}

/// `#n` as the lathe keeps it, or why it cannot be read; `None` when it keeps no such one
/// (the reader refuses it). Fanuc's modal information is [`Modal`]'s.
pub fn read(r: &Reader, n: usize, fanuc: bool) -> Option<Result<f64, String>> {
    let k = r.st.factor();
    // The programmed point in the program's coordinates (the work offset and a G50/G92 shift
    // taken off).
    let zero = r.zero();
    let [z, x] = [r.out.pos[0] - zero[0], r.out.pos[1] - zero[1]];
    if let Some(w) = work_var(n, fanuc) {
        return Some(w.map(|(work, axis)| {
            let v = r.work[work][axis];
            match axis {
                // Fanuc's X as programmed (a diameter under G07), LinuxCNC's a radius.
                1 if fanuc => x_programmed(r, v),
                _ => v / k,
            }
        }));
    }
    if !fanuc && n == 5220 {
        return Some(Ok((r.st.work + 1) as f64));
    }
    if !fanuc && (5221..=5340).contains(&n) {
        // Y, A, B, C, U, V, W and the rotation R of G54–G59: the lathe has none.
        return Some(Ok(0.0));
    }
    if fanuc {
        if let Some((kind, offset)) = tool_var(n) {
            return Some(tool_value(r, n, kind, offset));
        }
        return Some(match n {
            2001..=2999 => Err(format!(
                "#{n}: the lathe has no such tool offset variable (it has #2001–#2064 X wear, #2101– Z wear, #2201– nose radius wear, #2301– imaginary tip, #2701– X geometry, #2801– Z geometry, #2901– nose radius geometry)"
            )),
            5001 => Ok(x_programmed(r, x)),
            5002 => Ok(z / k),
            _ => return None,
        });
    }
    let tool = r.out.tool();
    let applied = tool.filter(|_| r.out.offsets_on());
    Some(match n {
        5400 => Ok(tool.map_or(0.0, |t| f64::from(t.number))),
        5401 => Ok(applied.map_or(0.0, |t| t.offset[0]) / k),
        5403 => Ok(applied.map_or(0.0, |t| t.offset[1]) / k),
        5410 => Ok(tool.map_or(0.0, |t| 2.0 * t.radius) / k),
        // LinuxCNC's number for the same tool (its chart is drawn with +X down).
        5411 => Ok(tool.map_or(0.0, |t| f64::from(super::comp::linuxcnc_orientation(t.tip)))),
        5420 | 5422 if r.out.comp_on() => Err(format!(
            "#{n} (the current position) cannot be read with nose-radius compensation on"
        )),
        5420 => Ok(x / k),
        5422 => Ok(z / k),
        _ => return None,
    })
}

/// Which work offset and axis (0 Z, 1 X) `#n` is, or why the lathe has no such one; `None`
/// when `#n` is not a work offset's. Fanuc 0i-TF: #5221 X and #5222 Z of G54, 20 on for each
/// of G55–G59, #5201/#5202 the external offset; LinuxCNC: #5221 X and #5223 Z, #5341– G59.1–.3.
fn work_var(n: usize, fanuc: bool) -> Option<Result<(usize, usize), String>> {
    let (first, last, axes): (usize, usize, &[(usize, usize)]) = if fanuc {
        (5201, 5340, &[(0, 1), (1, 0)])
    } else {
        (5221, 5400, &[(0, 1), (2, 0)])
    };
    if !(first..=last).contains(&n) {
        return None;
    }
    if fanuc && n < 5221 {
        return matches!(n, 5201 | 5202).then(|| {
            Err(format!(
                "#{n}: Fanuc's external work offset (shifting every work system) is not on this lathe: it has G54–G59, #5221–"
            ))
        });
    }
    let work = (n - 5221) / 20;
    let item = (n - 5221) % 20;
    let axis = axes.iter().find(|a| a.0 == item).map(|a| a.1)?;
    if work > 5 {
        return Some(Err(format!(
            "#{n}: the lathe's work systems are G54 to G59 (#5221–#5340)"
        )));
    }
    Some(Ok((work, axis)))
}

/// A program's write of a work offset's `#n` (docs/lathe-gcode.md "Work offsets"): set for
/// the rest of the read, as G10 L2 sets it; `None` when `#n` is not one.
pub fn write_work(r: &mut Reader, n: usize, v: f64, fanuc: bool) -> Option<Result<(), String>> {
    let (work, axis) = match work_var(n, fanuc)? {
        Ok(w) => w,
        Err(e) => return Some(Err(e)),
    };
    if !fanuc {
        // LinuxCNC keeps the parameter, but its work system in force moves only at the next
        // G54–G59 (rs274's SET_G5X_OFFSET comes from G10 and the selection): one way here.
        return Some(Err(format!(
            "#{n}: set a work offset with G10 L2 P1–P6 (LinuxCNC takes a written #{n} only at the next G54–G59)"
        )));
    }
    if work == r.st.work && r.out.comp_on() {
        return Some(Err(format!(
            "#{n}: the work system in force cannot change under nose-radius compensation: give G40 first"
        )));
    }
    let dia = if fanuc && axis == 1 && r.st.diameter {
        2.0
    } else {
        1.0
    };
    let mm = v * r.st.factor() / dia;
    if !(mm.is_finite() && mm.abs() <= super::MAX_WORK_OFFSET_MM) {
        return Some(Err(format!(
            "#{n}: a work offset is at most {} mm",
            super::MAX_WORK_OFFSET_MM
        )));
    }
    r.work[work][axis] = mm;
    Some(Ok(()))
}

/// LinuxCNC's predefined named parameter `#<name>` as the lathe keeps it; `None` when it
/// keeps no such one. `_x` is the radius in G7 as in G8, as LinuxCNC's (its issue #1348).
pub fn named(r: &Reader, name: &str) -> Option<Result<f64, String>> {
    let b = |x: bool| if x { 1.0 } else { 0.0 };
    let k = r.st.factor();
    let st = &r.st;
    Some(Ok(match name {
        "_x" | "_z" if r.out.comp_on() => {
            return Some(Err(format!(
                "#<{name}> (the current position) cannot be read with nose-radius compensation on"
            )))
        }
        "_x" => (r.out.pos[1] - r.zero()[1]) / k,
        "_z" => (r.out.pos[0] - r.zero()[0]) / k,
        "_coord_system" => 540.0 + 10.0 * st.work as f64,
        "_metric" => b(!st.inch),
        "_imperial" => b(st.inch),
        "_absolute" => b(st.absolute),
        "_incremental" => b(!st.absolute),
        "_units_per_minute" => b(!st.per_rev),
        "_units_per_rev" => b(st.per_rev),
        "_inverse_time" => 0.0,
        "_lathe_diameter_mode" => b(st.diameter),
        "_lathe_radius_mode" => b(!st.diameter),
        "_spindle_css_mode" => b(st.css),
        "_spindle_rpm_mode" => b(!st.css),
        "_spindle_on" => b(!st.stopped()),
        "_spindle_cw" => b(st.dir == 3),
        "_feed" => st.feed.unwrap_or(0.0) / k,
        "_rpm" => st.s,
        "_current_tool" => r.out.tool().map_or(0.0, |t| f64::from(t.number)),
        "_motion_mode" => st.motion.map_or(800.0, f64::from),
        "_plane" => 180.0,
        "_ccomp" => match r.out.comp_side() {
            None => 400.0,
            Some(true) => 410.0,
            Some(false) => 420.0,
        },
        _ => return None,
    }))
}

/// Why `#n`, one the lathe keeps, cannot be written by a program; `None` when it keeps no
/// such one (the reader refuses it, or says it is read-only).
pub fn write(r: &Reader, n: usize, fanuc: bool) -> Option<String> {
    if fanuc {
        if let Some((kind, offset)) = tool_var(n) {
            return Some(format!(
                "#{n} ({} of offset {offset}): a lathe program cannot set a tool offset: the lathe reads its program whole at START, before any of it runs, so the write would change the tool before the blocks ahead of it have run; set it at OFS (docs/lathe-gcode.md \"System variables\")",
                kind.name()
            ));
        }
    }
    // One the lathe keeps (its value or why it cannot be read: either way not written).
    let _kept = read(r, n, fanuc)?;
    Some(
        read_only(n)
            .filter(|_| fanuc)
            .unwrap_or_else(|| format!("#{n} reports the lathe's state: it is read-only")),
    )
}

/// The lathe's modal information in Fanuc 0i-TF's groups (G-code system B): #4001 group 1
/// (G00–G03 as 0–3, G33 as 33; null before one), #4002 G96/G97, #4003 G90/G91, #4005
/// G94/G95, #4006 G20/G21, #4007 G40/G41/G42, #4010 G80/G83, #4011 G98/G99 (G83's return
/// level), #4014 the work system (54–59), #4016 the plane (18), #4109 F, #4119 S, #4120 the T code (tool and offset, 101;
/// null before one).
impl Modal for Reader<'_> {
    fn items(&self) -> &'static [usize] {
        &[1, 2, 3, 5, 6, 7, 10, 11, 14, 16, 109, 119, 120]
    }

    fn item(&self, i: usize) -> f64 {
        let st = &self.st;
        let pick = |yes: bool, a: f64, b: f64| if yes { a } else { b };
        match i {
            1 => st.motion.map_or(f64::NAN, |g| f64::from(g) / 10.0),
            2 => pick(st.css, 96.0, 97.0),
            3 => pick(st.absolute, 90.0, 91.0),
            5 => pick(st.per_rev, 95.0, 94.0),
            6 => pick(st.inch, 20.0, 21.0),
            7 => match self.out.comp_side() {
                None => 40.0,
                Some(true) => 41.0,
                Some(false) => 42.0,
            },
            10 => st.drill.map_or(80.0, |d| f64::from(d.code)),
            11 if self.system_a => f64::NAN,
            11 => pick(st.drill_to_r, 99.0, 98.0),
            14 => 54.0 + st.work as f64,
            16 => 18.0,
            109 => st.feed.unwrap_or(0.0) / st.factor(),
            119 => st.s,
            120 => self.out.tool().map_or(f64::NAN, |t| {
                let offset = if self.out.offsets_on() { t.number } else { 0 };
                f64::from(t.number * 100 + offset)
            }),
            _ => f64::NAN,
        }
    }
}
