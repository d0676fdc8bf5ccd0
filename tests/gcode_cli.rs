//! `novanc translate` on G-code (docs/gcode.md "The listing"): the language chosen by the file
//! name or the first line, the blocks printed with G18/G19 and I J K on arcs outside XY,
//! the switches, and errors on stderr as `PROG:LINE:COL: message` with nothing on stdout.

mod common;

use common::{novanc, temp_file};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

const PROG: &str = "G21 G90\nG10 L2 P1 X100 Y100 Z-300\nG0 X0 Y0 Z0\nG18 G2 X10 Z0 I5 K0 F100\n/G17 G0 X50\nM1\nM30\n";

#[test]
fn a_file_named_ngc_is_read_as_g_code() {
    let p = temp_file("a.ngc", PROG);
    let out = novanc(&["translate", p.to_str().unwrap_or("")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout),
        "G21 G90 G17 G94 G40 G49 G80\n\
         N1 G00 X100.000 Y100.000 Z-300.000\n\
         N2 G18 G02 X110.000 Z-300.000 I5.000 K0.000 F100\n\
         N3 G00 X150.000\n\
         N4 M30\n"
    );
}

#[test]
fn a_first_line_of_percent_makes_g_code_of_any_name_and_switches_apply() {
    let p = temp_file("prog.txt", &format!("%\n{PROG}%\n"));
    let out = novanc(&[
        "translate",
        p.to_str().unwrap_or(""),
        "--block-delete",
        "--optional-stop",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(
        !s.contains("X150.000"),
        "block delete skipped the / line:\n{s}"
    );
    assert!(s.contains("N3 M01\n"), "optional stop kept M01:\n{s}");
}

#[test]
fn an_error_names_program_line_and_column_and_prints_nothing() {
    let p = temp_file("bad.nc", "G0 X0\nG1 X10\nM30\n");
    let prog = p.to_str().unwrap_or("");
    let out = novanc(&["translate", prog]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert_eq!(
        text(&out.stderr).trim_end(),
        format!("{prog}:2:1: a feed move without F: give F (mm/min, or in/min under G20)")
    );
}

#[test]
fn table_b_in_g_code_translates() {
    let out = novanc(&["translate", "programs/tableb.ngc"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(
        s.starts_with("G21 G90 G17 G94 G40 G49 G80\nN1 T01 M06\n"),
        "{s}"
    );
    assert!(s.ends_with("M30\n"));
}

#[test]
fn novanc_run_runs_a_g_code_program_to_its_end() {
    let p = temp_file(
        "run.ngc",
        "G21 G90\nG10 L2 P1 X100 Y50 Z-200\nG0 X1 Y2 Z3\nG91 G1 X-1 F500\nM30\n",
    );
    let out = novanc(&["run", p.to_str().unwrap_or("")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(
        s.contains("final position: X 100.000 Y 52.000 Z -197.000 mm"),
        "{s}"
    );
    let bad = temp_file("bad.ngc", "G21\nG0 X1 G1 Y1\nM30\n");
    let out = novanc(&["run", bad.to_str().unwrap_or("")]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("bad.ngc:2:"),
        "{}",
        text(&out.stderr)
    );
    let del = temp_file("del.ngc", "G0 X1\n/G0 X7\nM30\n");
    let out = novanc(&["run", del.to_str().unwrap_or(""), "--block-delete"]);
    assert!(
        text(&out.stdout).contains("final position: X 1.000"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn novanc_run_goes_on_past_m00_and_scripts_set_the_switches() {
    let p = temp_file("stop.ngc", "G0 X1\nM0\nG0 X2\nM30\n");
    let out = novanc(&["run", p.to_str().unwrap_or("")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("final position: X 2.000"),
        "{}",
        text(&out.stdout)
    );
    let script = temp_file(
        "sw.txt",
        &format!(
            "op data\ndata read\ntape {}\nstart\nwait\nblockdelete on\noptionalstop on\nshow\nblockdelete maybe\n",
            p.display()
        ),
    );
    let dir = common::temp_dir("gcode-cli-st");
    let out = novanc(&[
        "script",
        script.to_str().unwrap_or(""),
        "--state",
        dir.to_str().unwrap_or(""),
    ]);
    let err = text(&out.stderr);
    assert!(
        err.contains("'blockdelete' takes on or off, not 'maybe'"),
        "{err}"
    );
}

/// `o<name> call` finds `name.ngc` in the program's own folder, then in each `--subroutines`
/// folder in order; without it, the call is refused at its place, naming the file it looked for.
#[test]
fn named_subroutines_are_found_in_the_programs_folder_then_the_subroutine_path() {
    let dir = common::temp_dir("gcode-subs");
    let lib = dir.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    std::fs::write(
        lib.join("square.ngc"),
        "o<square> sub\nG1 X#1 F300\nG1 Y#1\no<square> endsub\nM2\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("hole.ngc"),
        "o<hole> sub\nG0 X#1 Y#2\no<hole> endsub\nM2\n",
    )
    .unwrap();
    let main = dir.join("main.ngc");
    std::fs::write(
        &main,
        "G10 L2 P1 X300 Y300 Z-300\nG0 Z5\no<square> call [10]\no<hole> call [3] [4]\nM30\n",
    )
    .unwrap();
    let m = main.to_str().unwrap();
    let out = novanc(&["translate", m]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr),
        format!("{m}:3:1: subroutine o<square> not found (not in this program, and no file square.ngc in the subroutine path)\n")
    );
    assert_eq!(text(&out.stdout), "");
    let out = novanc(&["translate", m, "--subroutines", lib.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout),
        "G21 G90 G17 G94 G40 G49 G80\n\
         N1 G00 Z-295.000\n\
         N2 G01 X310.000 F300\n\
         N3 G01 Y310.000 F300\n\
         N4 G00 X303.000 Y304.000\n\
         N5 M30\n"
    );
}
