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
use crate::pulse_core::RunKind;
use crate::store::Target;

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
    let mut t = src.statements(state);
    let first = match t.next() {
        Some(Ok(s)) => s,
        Some(Err(e)) if e.line == line && e.col == 1 && e.message.starts_with("no statement") => {
            return Err(e.message)
        }
        Some(Err(e)) => return Err(format!("line {}:{}: {}", e.line, e.col, e.message)),
        None => return Err(format!("no statement at or after line {line}")),
    };
    let restore = first.text == crate::translator::restore_text(first.line)
        || first.text == crate::gcode::restore_text(first.line);
    if restore {
        let at = match t.next() {
            Some(Ok(s)) => s,
            Some(Err(e)) => return Err(format!("line {}:{}: {}", e.line, e.col, e.message)),
            None => return Err(format!("no statement at or after line {line}")),
        };
        return Ok((
            at.line,
            at.text,
            Plan {
                restore: first.blocks,
            },
        ));
    }
    if first.text == crate::translator::END_OF_PROGRAM {
        return Err(format!(
            "no statement at or after line {line} (the end of the program cannot be searched)"
        ));
    }
    Ok((first.line, first.text, Plan { restore: vec![] }))
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
/// regard to case, as the language has none).
fn find_line(source: &str, what: &str) -> Result<Option<u32>, String> {
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
        .position(|l| l.to_ascii_uppercase().contains(&up))
        .map(|i| Some(i as u32 + 1))
        .ok_or_else(|| format!("'{w}' is not in the program"))
}

/// SEARCH: a command line (a program name, a line number, or text to find) entered with EOB.
pub(super) fn enter(c: &mut Console, line: &str) {
    let wanted = line.trim();
    if let Some(name) = c
        .mem
        .program_names()
        .into_iter()
        .find(|n| n.eq_ignore_ascii_case(wanted))
    {
        c.message = match c.mem.select_program(&name) {
            Ok(()) => format!("program {name} is current; AUTO starts at the top"),
            Err(e) => format!("SEARCH: {e}"),
        };
        c.search = None;
        return;
    }
    let source = c.mem.text(Target::Program);
    let n = match find_line(&source, line) {
        Ok(Some(n)) => n,
        Ok(None) => {
            c.search = None;
            c.message = "SEARCH cleared: AUTO starts at the top".into();
            return;
        }
        Err(e) => {
            c.message = format!("SEARCH: {e}");
            return;
        }
    };
    match make_plan(c, n, c.status.machine_state()) {
        Ok((at, text, _)) => {
            c.message = format!("AUTO starts at line {at}");
            c.search = Some(SearchPoint { line: at, text });
        }
        Err(e) => c.message = format!("SEARCH refused: {e}"),
    }
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
}
