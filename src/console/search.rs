//! SEARCH: a program name makes that program current; a line number or text positions the
//! program so that the next AUTO run starts at a chosen statement.
//!
//! The console builds no block itself: the program source (the translator, or the G-code
//! source for a G-code program) resumes at the statement from the machine's actual state
//! (`Translator::resume_at`, `GcodeSource::resume_at`). The statements before it are translated
//! for the state they leave, not run; a restore statement then brings the machine there: a tool
//! change if the spindle holds another tool, the spindle, Z up to machine zero before any X Y
//! rapid, X Y, then Z. The display lists those moves for the machine as it stands now; START
//! translates again from the state at START, so the restore always fits the real machine.

use super::run::run_source;
use super::Console;
use crate::block::{Block, MachineState};
use crate::gcode::{GcodeSource, InterpState};
use crate::pulse_core::RunKind;
use crate::store::Target;
use crate::translator::Translator;

/// Where SEARCH positioned the program.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchPoint {
    /// Source line AUTO starts at.
    pub line: u32,
    /// The statement's text.
    pub text: String,
}

/// What a run from the SEARCH point does first, for the machine as it stands.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The restore blocks (empty when the machine is already in the state the statement
    /// needs).
    pub restore: Vec<Block>,
    /// G-code: the interpreter's state rebuilt by reading from the top to the SEARCH line
    /// (the modal groups, the work offset system, G92, the tool, the spindle, coolant), as
    /// display lines.
    pub rebuilt: Vec<String>,
}

/// A G number as written (`G1`, `G59.1`) from its value ×10.
fn g(code: u16) -> String {
    if code.is_multiple_of(10) {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

/// The interpreter's state as the operator reads it: the active G codes of the modal groups,
/// the work offset system's zero and G92, the tool, the spindle and coolant.
pub fn state_lines(st: &InterpState) -> Vec<String> {
    use crate::block::Plane;
    use crate::gcode::state::{CompSide, FeedMode, PathMode, SYSTEM_NAMES};
    let m = &st.modal;
    let codes = [
        g(m.motion.code()),
        match m.plane {
            Plane::XY => "G17",
            Plane::XZ => "G18",
            Plane::YZ => "G19",
        }
        .into(),
        if m.incremental { "G91" } else { "G90" }.into(),
        match m.feed_mode {
            FeedMode::InverseTime => "G93",
            FeedMode::PerMinute => "G94",
            FeedMode::PerRevolution => "G95",
        }
        .into(),
        if m.inch { "G20" } else { "G21" }.into(),
        match m.comp {
            CompSide::Off => "G40",
            CompSide::Left => "G41",
            CompSide::Right => "G42",
        }
        .into(),
        if st.tlo.iter().any(|&v| v != 0.0) {
            "G43"
        } else {
            "G49"
        }
        .into(),
        if m.retract_r { "G99" } else { "G98" }.into(),
        SYSTEM_NAMES.get(m.cs).copied().unwrap_or("G54").to_string(),
        match m.path {
            PathMode::ExactPath => "G61",
            PathMode::ExactStop => "G61.1",
            PathMode::Blend { .. } => "G64",
        }
        .into(),
    ];
    let mut out = vec![codes.join(" ")];
    let o = st.origin;
    let mut ofs = format!(
        "{} X{:.3} Y{:.3} Z{:.3}",
        SYSTEM_NAMES.get(m.cs).copied().unwrap_or("G54"),
        o[0],
        o[1],
        o[2]
    );
    // The rotary axes' offsets, where not 0 (docs/gcode.md "Rotary axes").
    let rotary = |o: [f64; 3]| -> String {
        (0..3)
            .filter(|&r| o[r] != 0.0)
            .map(|r| format!(" {}{:.3}", ['A', 'B', 'C'][r], o[r]))
            .collect()
    };
    ofs.push_str(&rotary(st.origin_abc));
    if st.rotation != 0.0 {
        ofs.push_str(&format!(" R{:.3}", st.rotation));
    }
    if st.g92 != [0.0; 3] || st.g92_abc != [0.0; 3] {
        ofs.push_str(&format!(
            "  G92 X{:.3} Y{:.3} Z{:.3}{}",
            st.g92[0],
            st.g92[1],
            st.g92[2],
            rotary(st.g92_abc)
        ));
    }
    out.push(ofs);
    let tool = match st.tool {
        Some(t) if t > 0 => format!("T{t:02}"),
        _ => "T--".into(),
    };
    let tlo = if st.tlo[2] != 0.0 {
        format!(" H{:.3}", st.tlo[2])
    } else {
        String::new()
    };
    let spindle = match m.spindle {
        1 => "M3",
        -1 => "M4",
        _ => "M5",
    };
    let coolant = match (m.mist, m.flood) {
        (false, false) => "M9",
        (true, false) => "M7",
        (false, true) => "M8",
        (true, true) => "M7 M8",
    };
    out.push(format!(
        "{tool}{tlo} S{} {spindle} {coolant} F{}",
        m.speed,
        m.feed / m.factor()
    ));
    out
}

/// The plan shown, and the state it was made for.
#[derive(Clone, Debug, Default)]
pub struct PlanCache {
    key: Option<(u64, u32, MachineState)>,
    plan: Option<Result<Plan, String>>,
}

/// Translates up to the statement at or after `line` from `state`: the statement's line and
/// text, and the restore blocks before it.
fn make_plan(
    c: &mut Console,
    line: u32,
    state: MachineState,
) -> Result<(u32, String, Plan), String> {
    let mut src = run_source(c, RunKind::Auto);
    src.resume_at = Some(line);
    // The source language's translator is kept as itself, to ask it why it stopped.
    let (mut t, mut g): (Option<Translator>, Option<GcodeSource>) = if src.gcode {
        (None, src.gcode_source(state))
    } else {
        (Some(src.translator(state)), None)
    };
    let next = |t: &mut Option<Translator>, g: &mut Option<GcodeSource>| match (t, g) {
        (_, Some(g)) => g.next(),
        (Some(t), None) => t.next(),
        (None, None) => None,
    };
    let first = match next(&mut t, &mut g) {
        Some(Ok(s)) => s,
        Some(Err(e)) => {
            return Err(match t.as_ref().and_then(Translator::past_end) {
                Some(past) => past.to_string(),
                None => format!("line {}:{}: {}", e.line, e.col, e.message),
            })
        }
        None => return Err(format!("no statement at or after line {line}")),
    };
    let restore = first.text == crate::translator::restore_text(first.line)
        || first.text == crate::gcode::restore_text(first.line);
    let rebuilt = g
        .as_ref()
        .map(|g| state_lines(g.state()))
        .unwrap_or_default();
    if restore {
        let at = match next(&mut t, &mut g) {
            Some(Ok(s)) => s,
            Some(Err(e)) => return Err(format!("line {}:{}: {}", e.line, e.col, e.message)),
            None => return Err(format!("no statement at or after line {line}")),
        };
        return Ok((
            at.line,
            at.text,
            Plan {
                restore: first.blocks,
                rebuilt,
            },
        ));
    }
    if first.text == crate::translator::END_OF_PROGRAM {
        return Err(format!(
            "no statement at or after line {line} (the end of the program cannot be searched)"
        ));
    }
    Ok((
        first.line,
        first.text,
        Plan {
            restore: vec![],
            rebuilt,
        },
    ))
}

/// The restore plan for the SEARCH point and the machine as it stands; made again when the
/// program, the tool data or the machine's state has changed (not while an axis moves).
pub(super) fn current_plan(c: &mut Console) -> Option<Result<Plan, String>> {
    let sp = c.search.clone()?;
    let key = (c.mem.rev(), sp.line, c.status.machine_state());
    if c.plan.key != Some(key) && !c.status.moving {
        let plan = make_plan(c, sp.line, key.2).map(|(_, _, p)| p);
        c.plan = PlanCache {
            key: Some(key),
            plan: Some(plan),
        };
    }
    c.plan.plan.clone()
}

/// Finds the statement the operator asked for: a line number, or text to look for (without
/// regard to case, as the language has none), as whole words: `T1` finds `T1` and `T1 M6`
/// but not `T16` or `T1.5`, `X1` not `MAX1` (Fanuc's address search).
pub(crate) fn find_line(source: &str, what: &str) -> Result<Option<u32>, String> {
    let w = what.trim();
    if w.is_empty() || w == "0" {
        return Ok(None);
    }
    if let Ok(n) = w.parse::<u32>() {
        return Ok(Some(n));
    }
    let up = w.to_ascii_uppercase();
    source
        .lines()
        .position(|l| has_word(&l.to_ascii_uppercase(), &up))
        .map(|i| Some(i as u32 + 1))
        .ok_or_else(|| format!("'{w}' is not in the program"))
}

/// Whether `what` stands in `line` as a whole word: where `what` begins with a letter or a
/// digit, the character before it is not one; where it ends with one, the character after it
/// is neither one nor a decimal point.
fn has_word(line: &str, what: &str) -> bool {
    let word = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let (lb, wb) = (line.as_bytes(), what.as_bytes());
    let (Some(&first), Some(&last)) = (wb.first(), wb.last()) else {
        return false;
    };
    let mut from = 0;
    while let Some(i) = line[from..].find(what) {
        let at = from + i;
        let end = at + wb.len();
        let before_ok = !word(first) || at == 0 || !word(lb[at - 1]);
        let after_ok = !word(last)
            || end == lb.len()
            || !(word(lb[end]) || (last.is_ascii_digit() && lb[end] == b'.'));
        if before_ok && after_ok {
            return true;
        }
        from = at + 1;
        while !line.is_char_boundary(from) {
            from += 1;
        }
    }
    false
}

/// SEARCH: a command line (a program name, a line number, or text to find) entered with EOB.
pub(super) fn enter(c: &mut Console, line: &str) -> Result<(), String> {
    let wanted = line.trim();
    if let Some(name) = c
        .mem
        .program_names()
        .into_iter()
        .find(|n| n.eq_ignore_ascii_case(wanted))
    {
        c.mem
            .select_program(&name)
            .map_err(|e| format!("SEARCH: {e}"))?;
        c.shell.front.message = format!("program {name} is current; AUTO starts at the top");
        c.search = None;
        return Ok(());
    }
    let source = c.mem.text(Target::Program);
    let n = match find_line(&source, line) {
        Ok(Some(n)) => n,
        Ok(None) => {
            c.search = None;
            c.shell.front.message = "SEARCH cleared: AUTO starts at the top".into();
            return Ok(());
        }
        Err(e) => return Err(format!("SEARCH: {e}")),
    };
    let (at, text, _) =
        make_plan(c, n, c.status.machine_state()).map_err(|e| format!("SEARCH refused: {e}"))?;
    c.shell.front.message = format!("AUTO starts at line {at}");
    c.search = Some(SearchPoint { line: at, text });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_finds_its_line_without_regard_to_case() {
        assert_eq!(find_line("A\nDRL, 106\n", "drl").unwrap(), Some(2));
        assert_eq!(find_line("A\nBOR, 610\n", "bor,").unwrap(), Some(2));
        assert!(find_line("A\n", "XYZ").is_err());
        assert_eq!(find_line("A\n", "").unwrap(), None);
        assert_eq!(find_line("A\n", "7").unwrap(), Some(7));
    }

    #[test]
    fn an_address_word_finds_itself_and_not_a_longer_one() {
        let src = "N1 T16 M6\nN2 T1.5\nN3 MAX1\nN4 T1 M6\nN5 T1\n";
        assert_eq!(find_line(src, "T1").unwrap(), Some(4));
        assert_eq!(find_line(src, "t16").unwrap(), Some(1));
        assert!(find_line("N3 MAX1\n", "X1").is_err());
        assert_eq!(find_line(src, "T1.5").unwrap(), Some(2));
        assert_eq!(find_line("N1 G0 X1\n", "X1").unwrap(), Some(1));
        assert_eq!(find_line("DRL, 106\n", "DRL,").unwrap(), Some(1));
        assert!(find_line("N1 T16\n", "T1").is_err());
    }
}
