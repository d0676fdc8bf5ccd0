//! The lathe console's OFS mode (docs/lathe.md "Tool offsets"): a channel's tools as a table,
//! and the revision line `T1 X0.02 Z-0.01 R0.8 P3`.

use crate::lathe::desc::ToolDesc;

/// The tool table of a channel, one line per tool: number, nose radius, tip, X offset as a
/// diameter, Z offset.
pub fn table(tools: &[ToolDesc]) -> Vec<String> {
    let mut out = vec!["T   R     P  X(DIA)   Z".to_string()];
    out.extend(tools.iter().map(|t| {
        format!(
            "T{:02} {:5.3} {}  {:7.3} {:7.3}",
            t.number,
            t.radius,
            t.tip,
            t.offset[0] * 2.0,
            t.offset[1]
        )
    }));
    out
}

fn value(w: &str, letter: char) -> Result<f64, String> {
    match w[1..].parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{letter}: '{}' is not a number", &w[1..])),
    }
}

/// Applies a revision line to `tools`: returns the new tools and the tool revised. Nothing is
/// changed on an error.
pub fn revise(tools: &[ToolDesc], line: &str) -> Result<(Vec<ToolDesc>, u32), String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let Some(first) = words.first() else {
        return Err("type T, then X Z R P".into());
    };
    let n = match first.strip_prefix('T').map(|s| s.parse::<u32>()) {
        Some(Ok(n)) => n,
        _ => {
            return Err(format!(
                "'{first}': a revision starts with the tool, T1 X0.02 Z-0.01 R0.8 P3"
            ))
        }
    };
    let Some(i) = tools.iter().position(|t| t.number == n) else {
        return Err(format!("T{n} is not on this tool post"));
    };
    let mut t = tools[i].clone();
    if words.len() == 1 {
        return Err(format!("T{n}: say what to revise (X Z R P)"));
    }
    for w in &words[1..] {
        let letter = w.chars().next().unwrap_or(' ');
        if w.len() < 2 {
            return Err(format!("'{w}': a letter and a number"));
        }
        match letter {
            'X' => t.offset[0] = value(w, 'X')? / 2.0,
            'Z' => t.offset[1] = value(w, 'Z')?,
            'R' => t.radius = value(w, 'R')?,
            'P' => {
                let v = value(w, 'P')?;
                if v.fract() != 0.0 || !(0.0..=9.0).contains(&v) {
                    return Err(format!("P{v}: tip positions are 0 to 9"));
                }
                t.tip = v as u8;
            }
            c => return Err(format!("'{c}': a tool takes X (diameter) Z R P")),
        }
    }
    if t.offset.iter().any(|v| v.abs() > 1000.0) {
        return Err("X, Z: offsets within ±1000 mm (X ±2000 as a diameter)".into());
    }
    if !(0.0..=10.0).contains(&t.radius) {
        return Err(format!("R{}: a nose radius is 0 to 10 mm", t.radius));
    }
    let mut out = tools.to_vec();
    out[i] = t;
    Ok((out, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tools() -> Vec<ToolDesc> {
        vec![ToolDesc {
            number: 1,
            radius: 0.8,
            tip: 3,
            offset: [0.0, 0.0],
        }]
    }

    #[test]
    fn a_revision_changes_only_what_it_names() {
        let (t, n) = revise(&tools(), "T1 X0.04 Z-0.01").unwrap();
        assert_eq!(n, 1);
        assert_eq!(
            t[0],
            ToolDesc {
                number: 1,
                radius: 0.8,
                tip: 3,
                offset: [0.02, -0.01]
            }
        );
        let (t, _) = revise(&t, "T1 R0.4 P2").unwrap();
        assert_eq!(
            (t[0].radius, t[0].tip, t[0].offset),
            (0.4, 2, [0.02, -0.01])
        );
        assert_eq!(table(&t)[1], "T01 0.400 2    0.040  -0.010");
    }

    #[test]
    fn bad_revisions_say_why_and_change_nothing() {
        for (line, want) in [
            ("T7 X1", "T7 is not on this tool post"),
            ("X1", "a revision starts with the tool"),
            ("T1", "say what to revise"),
            ("T1 P12", "P12: tip positions are 0 to 9"),
            ("T1 R-1", "R-1: a nose radius"),
            ("T1 Xa", "X: 'a' is not a number"),
            ("T1 Q1", "'Q': a tool takes"),
            ("T1 Z5000", "offsets within"),
        ] {
            match revise(&tools(), line) {
                Err(e) => assert!(e.contains(want), "{line}: {e}"),
                Ok(t) => panic!("{line}: {t:?}"),
            }
        }
    }
}
