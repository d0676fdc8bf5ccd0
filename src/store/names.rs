//! Program names: the stored form (`program_name`) and the name PROGRAM READ gives a tape file
//! (`program_name_from_file`; docs/stores.md "Program names").

use std::path::Path;

/// A program name as stored: trimmed, upper case, 1 to 32 of `A-Z 0-9 _ - .`.
pub fn program_name(name: &str) -> Result<String, String> {
    let n = name.trim().to_ascii_uppercase();
    if n.is_empty() || n.len() > 32 {
        return Err(format!(
            "program name '{}' must be 1 to 32 characters",
            name.trim()
        ));
    }
    if let Some(c) = n
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Err(format!(
            "program name '{n}' may not contain '{c}' (letters, digits, _ - . only)"
        ));
    }
    Ok(n)
}

/// The program name PROGRAM READ gives a tape file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileProgramName {
    /// The program name, valid for program memory.
    pub name: String,
    /// The characters of the file name that were changed beyond upper case, e.g. `ü → U`,
    /// `' ' → _`. When not empty, other file names give the same program name.
    pub changes: Vec<String>,
}

/// Latin letters with accents and ligatures, and the plain letters they become.
const FOLD: [(&str, &str); 27] = [
    ("ÀÁÂÃÄÅàáâãäåĀāĂăĄą", "A"),
    ("Ææ", "AE"),
    ("ÇçĆćĈĉĊċČč", "C"),
    ("ĎďĐđÐð", "D"),
    ("ÈÉÊËèéêëĒēĔĕĖėĘęĚě", "E"),
    ("ĜĝĞğĠġĢģ", "G"),
    ("ĤĥĦħ", "H"),
    ("ÌÍÎÏìíîïĨĩĪīĬĭĮįİı", "I"),
    ("Ĳĳ", "IJ"),
    ("Ĵĵ", "J"),
    ("Ķķĸ", "K"),
    ("ĹĺĻļĽľĿŀŁł", "L"),
    ("ÑñŃńŅņŇňŉŊŋ", "N"),
    ("ÒÓÔÕÖØòóôõöøŌōŎŏŐő", "O"),
    ("Œœ", "OE"),
    ("ŔŕŖŗŘř", "R"),
    ("ŚśŜŝŞşŠšſ", "S"),
    ("ß", "SS"),
    ("ŢţŤťŦŧ", "T"),
    ("Þþ", "TH"),
    ("ÙÚÛÜùúûüŨũŪūŬŭŮůŰűŲų", "U"),
    ("Ŵŵ", "W"),
    ("ÝýÿŶŷŸ", "Y"),
    ("ŹźŻżŽž", "Z"),
    (" ", "_"),
    ("\u{a0}", "_"),
    ("\t", "_"),
];

/// The program name PROGRAM READ gives the tape file `file`: its name without the directory
/// and the last extension, in upper case; a G-code file (`gcode::GCODE_EXTENSIONS`: `.ngc`,
/// `.nc`, `.iso`, `.tap`, `.gcode`, `.cnc`) keeps its
/// extension, so that the program stays G-code in memory (`gcode::is_gcode`). A Latin letter with an accent becomes the plain
/// letter (`ü` → `U`, `ß` → `SS`, `æ` → `AE`) and a space `_`, and `changes` says so. Refused
/// (with the reason, asking to rename the file) when a character has no such equivalent, or
/// when the name would be empty or longer than 32 characters.
pub fn program_name_from_file(file: &str) -> Result<FileProgramName, String> {
    let path = Path::new(file);
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .filter(|e| crate::gcode::GCODE_EXTENSIONS.contains(&e.as_str()));
    let mut stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(e) = &ext {
        if !stem.is_empty() {
            stem = format!("{stem}.{e}");
        }
    }
    // The file name as shown in messages, control characters escaped.
    let file: String = file
        .chars()
        .flat_map(|c| match c.is_control() {
            true => c.escape_debug().collect::<Vec<_>>(),
            false => vec![c],
        })
        .collect();
    let mut name = String::new();
    let mut changes = Vec::new();
    for c in stem.chars() {
        if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
            name.push(c.to_ascii_uppercase());
        } else if let Some((_, to)) = FOLD.iter().find(|(from, _)| from.contains(c)) {
            name.push_str(to);
            let shown = if c.is_whitespace() {
                "' '".to_string()
            } else {
                c.to_string()
            };
            let change = format!("{shown} → {to}");
            if !changes.contains(&change) {
                changes.push(change);
            }
        } else {
            let shown = match c {
                '\u{fffd}' => "a byte that is not UTF-8".to_string(),
                c if c.is_control() => format!("'{}'", c.escape_debug()),
                c => format!("'{c}'"),
            };
            return Err(format!(
                "tape {file}: {shown} has no equivalent in a program name (letters, digits, _ - . only); rename the file"
            ));
        }
    }
    if name.is_empty() {
        return Err(format!(
            "tape {file}: its name gives no program name; rename the file"
        ));
    }
    if name.chars().count() > 32 {
        return Err(format!(
            "tape {file}: the program name {name} would be {} characters, at most 32; rename the file",
            name.chars().count()
        ));
    }
    Ok(FileProgramName { name, changes })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(file: &str) -> (String, Vec<String>) {
        let n = program_name_from_file(file).unwrap();
        (n.name, n.changes)
    }

    #[test]
    fn stored_names() {
        assert_eq!(program_name(" part-7.a "), Ok("PART-7.A".to_string()));
        assert!(program_name("").unwrap_err().contains("1 to 32"));
        assert!(program_name(&"A".repeat(33))
            .unwrap_err()
            .contains("1 to 32"));
        assert!(program_name("a/b").unwrap_err().contains("'/'"));
    }

    #[test]
    fn file_names_become_program_names_and_say_what_changed() {
        assert_eq!(named("/tapes/part7.ap"), ("PART7".into(), vec![]));
        assert_eq!(named("/tapes/part7.ngc"), ("PART7.NGC".into(), vec![]));
        assert_eq!(named("p.NC"), ("P.NC".into(), vec![]));
        assert_eq!(named("p.Iso"), ("P.ISO".into(), vec![]));
        assert_eq!(named("p.tap"), ("P.TAP".into(), vec![]));
        assert_eq!(named("p.tape"), ("P".into(), vec![]));
        assert_eq!(named("a.b-c_d.ap"), ("A.B-C_D".into(), vec![]));
        assert_eq!(named("prüf.ap"), ("PRUF".into(), vec!["ü → U".into()]));
        assert_eq!(
            named("Straße 2.tape"),
            ("STRASSE_2".into(), vec!["ß → SS".into(), "' ' → _".into()])
        );
        assert_eq!(
            named("ÆØÅ"),
            (
                "AEOA".into(),
                vec!["Æ → AE".into(), "Ø → O".into(), "Å → A".into()]
            )
        );
        // Every name it gives is a valid stored name.
        for f in ["prüf.ap", "Straße 2.tape", "x", "ŁÓDŹ.ap"] {
            let n = named(f).0;
            assert_eq!(program_name(&n), Ok(n));
        }
    }

    #[test]
    fn file_names_with_no_program_name_are_refused() {
        assert_eq!(
            program_name_from_file("prüf€.ap").unwrap_err(),
            "tape prüf€.ap: '€' has no equivalent in a program name (letters, digits, _ - . only); rename the file"
        );
        assert!(program_name_from_file("部品.ap")
            .unwrap_err()
            .contains("'部' has no equivalent"));
        assert!(program_name_from_file("caf\u{fffd}.ap")
            .unwrap_err()
            .contains(": a byte that is not UTF-8 has no equivalent"));
        assert_eq!(
            program_name_from_file("a\u{1b}b.ap").unwrap_err(),
            "tape a\\u{1b}b.ap: '\\u{1b}' has no equivalent in a program name (letters, digits, _ - . only); rename the file"
        );
        assert_eq!(
            program_name_from_file("").unwrap_err(),
            "tape : its name gives no program name; rename the file"
        );
        let long = format!("{}.ap", "ß".repeat(17));
        assert!(program_name_from_file(&long)
            .unwrap_err()
            .contains("would be 34 characters, at most 32"));
    }
}
