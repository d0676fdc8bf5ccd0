//! SEARCH: a program name makes that program current; a line number or text positions the
//! program so that AUTO starts at a chosen statement. The program is
//! translated from the top without moving; the statements before the chosen one are not
//! executed, but the tool, spindle and origin in force there are rebuilt: the run starts with
//! restoring blocks (T/M06, S/M03 or M04, then a safe rapid to where the chosen statement
//! begins), shown on the display as one extra statement.

use super::Console;
use crate::block::{Block, Motion};
use crate::settings::MachineSettings;
use crate::store::Target;
use crate::translator::{translate_all, Statement};

/// Where SEARCH positioned the program.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchPoint {
    /// Source line AUTO starts at.
    pub line: u32,
    /// The statement's text.
    pub text: String,
    /// What will be restored, in the operator's words, one item per line.
    pub restored: Vec<String>,
}

/// A run from a searched statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The restoring statement (if anything is restored) then every statement from the chosen one.
    pub statements: Vec<Statement>,
    /// What is restored, one item per line.
    pub restored: Vec<String>,
}

/// The state in force before a statement.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct InForce {
    tool: Option<u32>,
    speed: Option<u32>,
    /// 3 forward, 4 reverse, 5 or None stopped.
    spindle_m: Option<u8>,
}

/// The origin (`DAn`) last designated in the statements before the chosen one.
fn origin_in_force(stmts: &[Statement]) -> Option<String> {
    let mut last = None;
    for s in stmts {
        let t = s.text.to_ascii_uppercase();
        // The designations of a cutting statement follow its last '/'; PAT definitions name one too.
        let region = if t.contains('/') {
            t.rsplit('/').next().unwrap_or("").to_string()
        } else if t.trim_start().starts_with("PAT") {
            t.split('=').nth(1).unwrap_or("").to_string()
        } else {
            String::new()
        };
        for (i, _) in region.match_indices("DA") {
            let d: String = region[i + 2..]
                .chars()
                .take_while(|c| c.is_ascii_digit())
                .collect();
            if !d.is_empty() {
                last = Some(format!("DA{d}"));
            }
        }
    }
    last
}

/// Plans a run of `stmts` (translated from the top, starting at `pos`) from source line `line`.
pub fn plan(
    stmts: &[Statement],
    line: u32,
    pos: [i64; 3],
    s: &MachineSettings,
) -> Result<Plan, String> {
    // The translator's end of program is not a statement of the source: it cannot be searched.
    let in_source = |st: &Statement| st.text != crate::translator::END_OF_PROGRAM;
    let Some(first) = stmts.iter().position(|st| st.line >= line && in_source(st)) else {
        let last = stmts
            .iter()
            .rev()
            .find(|s| in_source(s))
            .map(|s| s.line)
            .unwrap_or(0);
        return Err(format!(
            "no statement at or after line {line} (the last is line {last})"
        ));
    };
    let before = &stmts[..first];
    let mut st = InForce::default();
    let mut resume = pos;
    for b in before.iter().flat_map(|s| s.blocks.iter()) {
        if b.t.is_some() {
            st.tool = b.t;
        }
        if b.s.is_some() {
            st.speed = b.s;
        }
        if let Some(m) = b.m {
            if matches!(m, 3..=5) {
                st.spindle_m = Some(m);
            }
        }
        resume = b.end;
    }
    let rest = &stmts[first..];
    // What the chosen part does itself before it first cuts (feeds) needs no restoring.
    let mut own_tool = false;
    let mut own_spindle = false;
    for b in rest.iter().flat_map(|s| s.blocks.iter()) {
        if b.m == Some(6) {
            own_tool = true;
        }
        if matches!(b.m, Some(3..=5)) {
            own_spindle = true;
        }
        if !matches!(b.motion, Motion::Aux | Motion::Rapid) {
            break;
        }
    }
    let at = rest[0].line;
    let mut blocks = Vec::new();
    let mut restored = Vec::new();
    if let (Some(t), false) = (st.tool, own_tool) {
        let mut b = Block::aux(0, at, pos);
        b.t = Some(t);
        b.m = Some(6);
        blocks.push(b);
        restored.push(format!("tool T{t:02} M06"));
    }
    if let (Some(m @ (3 | 4)), false) = (st.spindle_m, own_spindle) {
        let mut b = Block::aux(0, at, pos);
        b.s = st.speed;
        b.m = Some(m);
        blocks.push(b);
        restored.push(format!("spindle S{} M0{m}", st.speed.unwrap_or(0)));
    }
    for b in approach(pos, resume, at) {
        blocks.push(b);
    }
    if resume != pos {
        restored.push(format!(
            "rapid to X{:.3} Y{:.3} Z{:.3}",
            s.to_mm(resume[0]),
            s.to_mm(resume[1]),
            s.to_mm(resume[2])
        ));
    }
    if let Some(o) = origin_in_force(before) {
        restored.push(format!("origin {o} (by translation)"));
    }
    let mut statements = Vec::new();
    if !blocks.is_empty() {
        statements.push(Statement {
            line: at,
            text: format!("(SEARCH: restore state for line {at})"),
            blocks,
        });
    }
    statements.extend(rest.iter().cloned());
    Ok(Plan {
        statements,
        restored,
    })
}

/// Rapid blocks from `from` to `to` in a safe order: up first if the target is higher, else
/// across first and down last.
fn approach(from: [i64; 3], to: [i64; 3], stmt: u32) -> Vec<Block> {
    let mut out = Vec::new();
    let mut at = from;
    let mut step = |at: &mut [i64; 3], next: [i64; 3]| {
        if next != *at {
            let mut b = Block::aux(0, stmt, next);
            b.motion = Motion::Rapid;
            b.delta = [next[0] - at[0], next[1] - at[1], next[2] - at[2]];
            out.push(b);
            *at = next;
        }
    };
    if to[2] > from[2] {
        step(&mut at, [from[0], from[1], to[2]]);
        step(&mut at, to);
    } else {
        step(&mut at, [to[0], to[1], from[2]]);
        step(&mut at, to);
    }
    out
}

/// Finds the statement the operator asked for: a line number, or text to look for.
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

/// SEARCH: a command line (a line number, or text to find) entered with EOB.
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
    let magazine = c.mem.magazine();
    let stmts = match translate_all(&source, &magazine, &c.cfg.settings, c.status.pos) {
        Ok(s) => s,
        Err(e) => {
            c.message = format!("SEARCH refused: line {}:{}: {}", e.line, e.col, e.message);
            return;
        }
    };
    match plan(&stmts, n, c.status.pos, &c.cfg.settings) {
        Ok(p) => {
            let at = stmts
                .iter()
                .find(|s| s.line >= n)
                .map(|s| (s.line, s.text.clone()))
                .unwrap_or((n, String::new()));
            c.message = format!("AUTO starts at line {}", at.0);
            c.search = Some(SearchPoint {
                line: at.0,
                text: at.1,
                restored: p.restored,
            });
        }
        Err(e) => c.message = format!("SEARCH: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stmt(line: u32, text: &str, blocks: Vec<Block>) -> Statement {
        Statement {
            line,
            text: text.into(),
            blocks,
        }
    }

    fn rapid(end: [i64; 3], from: [i64; 3]) -> Block {
        let mut b = Block::aux(1, 1, end);
        b.motion = Motion::Rapid;
        b.delta = [end[0] - from[0], end[1] - from[1], end[2] - from[2]];
        b
    }

    #[test]
    fn restores_tool_spindle_and_position_before_the_chosen_statement() {
        let mut tc = Block::aux(1, 2, [0, 0, 0]);
        tc.t = Some(2);
        tc.m = Some(6);
        let mut sp = Block::aux(2, 2, [0, 0, 0]);
        sp.s = Some(1200);
        sp.m = Some(3);
        let mv = rapid([100, 200, -50], [0, 0, 0]);
        let later = rapid([300, 200, -50], [100, 200, -50]);
        let stmts = vec![
            stmt(1, "DA1 = (0,0,0)", vec![]),
            stmt(2, "DRL, 106/DP20/DA1, P1", vec![tc, sp, mv]),
            stmt(3, "DRL, 106/DP20/DA1, P2", vec![later]),
        ];
        let p = plan(&stmts, 3, [0, 0, 0], &MachineSettings::default()).unwrap();
        assert_eq!(p.statements.len(), 2);
        let r = &p.statements[0].blocks;
        assert_eq!((r[0].t, r[0].m), (Some(2), Some(6)));
        assert_eq!((r[1].s, r[1].m), (Some(1200), Some(3)));
        // Z first is not needed (target lower): across, then down.
        assert_eq!(r[2].end, [100, 200, 0]);
        assert_eq!(r[3].end, [100, 200, -50]);
        let total: i64 = r.iter().map(|b| b.delta[0]).sum();
        assert_eq!(total, 100);
        assert_eq!(p.statements[1].line, 3);
        assert!(p.restored.iter().any(|l| l.contains("T02")));
        assert!(p.restored.iter().any(|l| l.contains("origin DA1")));
    }

    #[test]
    fn a_line_past_the_end_is_an_error_and_text_finds_its_line() {
        let stmts = vec![stmt(1, "P1 = (1,2)", vec![])];
        let e = plan(&stmts, 9, [0; 3], &MachineSettings::default()).unwrap_err();
        assert!(e.contains("line 9"), "{e}");
        assert_eq!(find_line("A\nDRL, 106\n", "drl").unwrap(), Some(2));
        assert!(find_line("A\n", "XYZ").is_err());
        assert_eq!(find_line("A\n", "").unwrap(), None);
    }

    #[test]
    fn going_up_moves_z_first() {
        let b = approach([10, 10, -100], [50, 60, -20], 4);
        assert_eq!(b[0].end, [10, 10, -20]);
        assert_eq!(b[1].end, [50, 60, -20]);
    }
}
