//! Tool tapes and T-code tables, by grammar and by mutation of the samples, and the checks: a
//! tape or table either is refused with `FILE:LINE: message` in one short line, or reads into
//! values the language could write, which print and read back the same; and the sample
//! programs translated with a fuzzed magazine keep every limit.

use super::harness::{note, Ctx};
use super::programs::{check, mutate};
use super::rng::Rng;
use novanc::input_text::MAX_NUMBER;
use novanc::tooldata::{format_record, parse_record, parse_tape, parse_tcodes, Magazine, ToolKind};

/// A tape field: mostly a sensible number, sometimes one the language refuses.
fn field(rng: &mut Rng) -> String {
    match rng.below(14) {
        0 if rng.chance(0.1) => "9".repeat(400),
        0 => rng
            .pick(&[
                "1e308",
                "inf",
                "NaN",
                "-1",
                "0",
                "0.0004",
                "1000000000",
                "1000000001",
                ".",
                "1,5",
                "0x10",
                "+3",
                "00000001.5",
                "-0",
                "1E5",
            ])
            .to_string(),
        1..=3 => format!("{}", rng.range(0, 5000)),
        _ => format!("{}.{}", rng.range(0, 400), rng.below(1000)),
    }
}

/// A tape from the record grammar, with comments, blank lines and every line end.
fn tape_by_grammar(rng: &mut Rng) -> String {
    let mut s = String::new();
    if rng.chance(0.05) {
        s.push('\u{feff}');
    }
    let end = *rng.pick(&["\n", "\r\n", "\r"]);
    for _ in 0..rng.range(0, 40) {
        match rng.below(10) {
            0 => s.push_str("; a comment"),
            1 => {}
            _ => {
                let no = match rng.below(10) {
                    0 => rng
                        .pick(&["0", "00000", "123456", "12a", "-5", ""])
                        .to_string(),
                    _ => format!(
                        "{:05}",
                        rng.pick(&[106, 105, 208, 206, 610, 101, 402, 404, 301, 99_999, 1])
                    ),
                };
                let kind = if rng.chance(0.05) {
                    rng.pick(&["XX", "dr", "D", ""]).to_string()
                } else {
                    rng.pick(&ToolKind::ALL).code().to_string()
                };
                let mut rec = format!("{no}  {kind}");
                let n = if rng.chance(0.05) { rng.range(4, 9) } else { 6 };
                for _ in 0..n {
                    rec.push_str("  ");
                    rec.push_str(&field(rng));
                }
                if rng.chance(0.2) {
                    rec.push_str("  ; note");
                }
                s.push_str(&rec);
            }
        }
        s.push_str(end);
    }
    s
}

/// Family `tape`: a tape by grammar or mutation; read; the values within the language's
/// bounds and printing back the same; then the sample programs translated with it.
pub fn tape_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let tape = if rng.chance(0.5) {
        tape_by_grammar(rng)
    } else {
        let other = tape_by_grammar(rng);
        mutate(rng, &ctx.tape, &other)
    };
    note("tape", &tape);
    let recs = match parse_tape(&tape, "t.tt") {
        Err(e) => {
            let m = e.to_string();
            if !m.starts_with("t.tt:") || m.contains('\n') || m.len() > 400 || e.line == 0 {
                return Err(format!("bad message: {m:?}"));
            }
            return Ok(());
        }
        Ok(r) => r,
    };
    for r in &recs {
        let v = [
            r.diameter,
            r.set_length,
            r.effective_length,
            r.speed,
            r.feed,
            r.depth,
        ];
        if v.iter()
            .any(|x| !x.is_finite() || *x < 0.0 || *x > MAX_NUMBER)
            || r.diameter <= 0.0
        {
            return Err(format!("a value out of bounds was read: {r:?}"));
        }
        if r.number == 0 || r.number > 99_999 {
            return Err(format!("tool number {}", r.number));
        }
        let line = format_record(r);
        let again = parse_record(&line).map_err(|e| format!("'{line}' does not read back: {e}"))?;
        if format_record(&again) != line {
            return Err(format!(
                "'{line}' reads back as '{}'",
                format_record(&again)
            ));
        }
    }
    let tcodes = parse_tcodes(&ctx.tcodes, "m.tc", 24).map_err(|e| e.to_string())?;
    let magazine = Magazine::load(tcodes, &recs);
    let prog = rng.pick(&ctx.programs).clone();
    note("tape, then the program", &format!("{tape}\n---\n{prog}"));
    check(&prog, &magazine)
}

/// A T-code table from its grammar.
fn table_by_grammar(rng: &mut Rng) -> String {
    let mut s = String::new();
    let end = *rng.pick(&["\n", "\r\n", "\r"]);
    for _ in 0..rng.range(0, 30) {
        let t = match rng.below(12) {
            0 => rng
                .pick(&["T0", "T", "X01", "t05", "T+5", "T99999999999", "T-1"])
                .to_string(),
            _ => format!("T{:02}", rng.range(1, 30)),
        };
        let n = match rng.below(12) {
            0 => rng
                .pick(&["0", "100000", "abc", "1.5", "", "00106 7"])
                .to_string(),
            _ => format!("{:05}", rng.range(1, 700)),
        };
        s.push_str(&format!("{t} {n}"));
        if rng.chance(0.1) {
            s.push_str(rng.pick::<&str>(&[" ; c", " # c"]));
        }
        s.push_str(end);
    }
    s
}

/// Family `tcode-table`: a table by grammar or mutation; read; every tool in one pocket,
/// within 1 to 99999, and the table printing back the same.
pub fn tcode_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let text = if rng.chance(0.5) {
        table_by_grammar(rng)
    } else {
        let other = table_by_grammar(rng);
        mutate(rng, &ctx.tcodes, &other)
    };
    let cap = *rng.pick(&[24, 1, 30, 99, 999]);
    note(&format!("T-code table, {cap} pockets"), &text);
    match parse_tcodes(&text, "m.tc", cap) {
        Err(e) => {
            let m = e.to_string();
            if !m.starts_with("m.tc:") || m.contains('\n') || m.len() > 400 {
                return Err(format!("bad message: {m:?}"));
            }
            Ok(())
        }
        Ok(t) => {
            let mut seen = std::collections::HashSet::new();
            for (tc, n) in t.iter() {
                if tc == 0 || tc > cap || n == 0 || n > 99_999 || !seen.insert(n) {
                    return Err(format!("T{tc} holds {n}"));
                }
            }
            let again = parse_tcodes(&t.to_text(), "m.tc", cap).map_err(|e| e.to_string())?;
            if again != t {
                return Err("the table does not read back the same".to_string());
            }
            Ok(())
        }
    }
}
