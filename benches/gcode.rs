//! G-code reading speed (docs/gcode.md "Speed"): a generated CAM-like program of 200,000
//! lines (contours of G01 and G02/G03 with I J and R, helices, G41 contours, canned-cycle
//! hole rows, subprogram calls, expressions) read and expanded into machine blocks in process.
//! Prints lines/s and blocks/s (target ≥ 2 M blocks/s).
//!
//! Then the same program with a decimal point on every length (so that it means the same in
//! both) read in the LinuxCNC and the Fanuc dialect, alternately, best CPU time of each
//! (issue 24: the Fanuc dialect reads within 10 % of LinuxCNC's).
//!
//! Run: `cargo bench --bench gcode`; `cargo bench --bench gcode -- --write FILE` writes the
//! program for `benches/gcode_vs_rs274.sh`.

use novanc::block::{iso_program, MachineState, Statement};
use novanc::gcode::{GcodeSource, Switches, WorkOffsets};
use novanc::settings::{Dialect, MachineSettings};
use novanc::tooldata::sample_magazine;
use std::fmt::Write;
use std::time::Instant;

/// About `units` × 40 lines.
fn program(units: usize) -> String {
    let mut s = String::with_capacity(units * 1200);
    s.push_str("%\nO0100 (generated for the benchmark)\nG21 G90 G17 G94 G40 G49 G80\n");
    s.push_str("G10 L2 P1 X300 Y300 Z-400\nG54\nT14 M6\nG43 H14\nS2000 M3\nF600\n");
    for k in 0..units {
        let x0 = (k % 10) as f64 * 5.0 - 25.0;
        let y0 = (k % 7) as f64 * 5.0 - 20.0;
        let _ = writeln!(s, "G0 X{x0:.3} Y{y0:.3} Z5");
        s.push_str("G1 Z-2\n");
        // A contour of lines and arcs.
        for i in 0..8 {
            let a = i as f64 * 0.7;
            let _ = writeln!(
                s,
                "G1 X{:.3} Y{:.3}",
                x0 + 30.0 * a.cos(),
                y0 + 30.0 * a.sin()
            );
        }
        let _ = writeln!(s, "G1 X{:.3} Y{:.3}", x0 + 40.0, y0);
        let _ = writeln!(s, "G3 X{:.3} Y{:.3} I-10 J0", x0 + 20.0, y0);
        let _ = writeln!(s, "G2 X{:.3} Y{:.3} R10", x0 + 40.0, y0);
        let _ = writeln!(s, "G3 X{:.3} Y{:.3} Z-3 I-10 J0", x0 + 40.0, y0);
        let _ = writeln!(s, "G1 X[{x0:.3}+#1] Y{y0:.3} Z-2");
        // A compensated square.
        let _ = writeln!(s, "G0 X{:.3} Y{:.3}", x0 - 15.0, y0 - 15.0);
        let _ = writeln!(s, "G41 D14 G1 X{x0:.3} Y{y0:.3}");
        let _ = writeln!(s, "X{:.3}", x0 + 20.0);
        let _ = writeln!(s, "G3 X{:.3} Y{:.3} R8", x0 + 28.0, y0 + 8.0);
        let _ = writeln!(s, "G1 Y{:.3}", y0 + 20.0);
        let _ = writeln!(s, "X{x0:.3}");
        let _ = writeln!(s, "Y{y0:.3}");
        let _ = writeln!(s, "G40 G1 X{:.3} Y{:.3}", x0 - 15.0, y0 - 15.0);
        // A row of holes.
        s.push_str("G0 Z5\n");
        let _ = writeln!(s, "G99 G81 X{x0:.3} Y{y0:.3} Z-8 R2");
        for h in 1..8 {
            let _ = writeln!(s, "X{:.3}", x0 + h as f64 * 4.0);
        }
        s.push_str("G80\n");
        let _ = writeln!(s, "G73 X{x0:.3} Y{:.3} Z-10 R2 Q2", y0 + 10.0);
        s.push_str("G80\nG0 Z5\n");
        let _ = writeln!(s, "#1=[{}*0.001]", k % 13);
        if k % 4 == 0 {
            s.push_str("M98 P200 L2\n");
        }
    }
    s.push_str("G0 Z5\nM5\nM30\nO200\nG91 G1 X1 Y1\nG90\nM99\n%\n");
    s
}

/// CPU time of this thread, s (the machine is shared: wall time includes waiting for a core).
fn thread_cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec we pass and nothing else.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let src = program(5_000);
    if let Some(i) = args.iter().position(|a| a == "--write") {
        let Some(path) = args.get(i + 1) else {
            eprintln!("--write needs a file");
            std::process::exit(2);
        };
        if let Err(e) = std::fs::write(path, &src) {
            eprintln!("cannot write {path}: {e}");
            std::process::exit(1);
        }
        return;
    }
    let settings = MachineSettings::default();
    let magazine = sample_magazine();
    let lines = src.lines().count();
    let source = || {
        GcodeSource::new(
            src.as_str().into(),
            magazine.clone(),
            settings.clone(),
            MachineState::at([0, 0, 0]),
            WorkOffsets::default(),
            Switches::default(),
        )
    };
    // As the console consumes it: statement by statement, each dropped once its blocks are
    // taken (B1 holds blocks, not the whole program).
    let (mut best, mut best_cpu, mut n_blocks, mut n_stmts) = (f64::MAX, f64::MAX, 0, 0);
    for _ in 0..5 {
        let t = Instant::now();
        let c0 = thread_cpu();
        let (mut blocks, mut stmts) = (0usize, 0usize);
        for r in source() {
            match r {
                Ok(s) => {
                    blocks += s.blocks.len();
                    stmts += 1;
                }
                Err(e) => {
                    eprintln!("the generated program does not read: {e}");
                    std::process::exit(1);
                }
            }
        }
        best = best.min(t.elapsed().as_secs_f64());
        best_cpu = best_cpu.min(thread_cpu() - c0);
        (n_blocks, n_stmts) = (blocks, stmts);
    }
    println!(
        "gcode: {lines} lines, {n_stmts} statements, {n_blocks} blocks, {} bytes",
        src.len()
    );
    println!(
        "gcode: streamed: {:.2} M lines/s, {:.2} M blocks/s wall clock ({:.1} ms); {:.2} M blocks/s CPU time ({:.1} ms) (target >= 2 M blocks/s)",
        lines as f64 / best / 1e6,
        n_blocks as f64 / best / 1e6,
        best * 1e3,
        n_blocks as f64 / best_cpu / 1e6,
        best_cpu * 1e3
    );
    // Collected whole into a Vec (as `translate_all` does): the blocks' memory counts too.
    let mut best = f64::MAX;
    let mut best_cpu = f64::MAX;
    let mut result: Vec<Statement> = Vec::new();
    for _ in 0..3 {
        drop(std::mem::take(&mut result));
        let t = Instant::now();
        let c0 = thread_cpu();
        let r: Result<Vec<Statement>, _> = source().collect();
        best = best.min(t.elapsed().as_secs_f64());
        best_cpu = best_cpu.min(thread_cpu() - c0);
        match r {
            Ok(s) => result = s,
            Err(e) => {
                eprintln!("the generated program does not read: {e}");
                std::process::exit(1);
            }
        }
    }
    println!(
        "gcode: collected: {:.2} M blocks/s wall clock ({:.1} ms); {:.2} M blocks/s CPU time ({:.1} ms)",
        n_blocks as f64 / best / 1e6,
        best * 1e3,
        n_blocks as f64 / best_cpu / 1e6,
        best_cpu * 1e3
    );
    dialects(&src, &magazine);
    let t = Instant::now();
    let iso = iso_program(&result, &settings);
    let dt = t.elapsed().as_secs_f64();
    println!(
        "gcode: printing ISO {:.2} M lines/s ({} bytes)",
        n_blocks as f64 / dt / 1e6,
        iso.len()
    );
}

/// `src` with a decimal point after every whole number on a length address (X Y Z I J K R Q
/// outside brackets and comments): a program that means the same in both dialects (the Fanuc
/// dialect reads `Z5` as 0.005 mm).
fn pointed(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len() + src.len() / 8);
    let (mut depth, mut comment) = (0, false);
    let mut i = 0;
    while i < b.len() {
        let c = b[i] as char;
        out.push(c);
        i += 1;
        match c {
            '(' => comment = true,
            ')' => comment = false,
            '[' => depth += 1,
            ']' => depth -= 1,
            'X' | 'Y' | 'Z' | 'I' | 'J' | 'K' | 'R' | 'Q' if depth == 0 && !comment => {
                let start = i;
                if b.get(i) == Some(&b'-') {
                    i += 1;
                }
                while b.get(i).is_some_and(u8::is_ascii_digit) {
                    i += 1;
                }
                out.push_str(&src[start..i]);
                if i > start && b.get(i) != Some(&b'.') && b[i - 1].is_ascii_digit() {
                    out.push('.');
                }
            }
            _ => {}
        }
    }
    out
}

/// The pointed program read in each dialect, alternately, 5 times each: the best CPU time
/// of each, and the blocks (which must be the same).
fn dialects(src: &str, magazine: &novanc::tooldata::Magazine) {
    let text: std::sync::Arc<str> = pointed(src).into();
    let read = |dialect: Dialect| {
        let settings = MachineSettings {
            dialect,
            ..MachineSettings::default()
        };
        let c0 = thread_cpu();
        let mut blocks = 0usize;
        for r in GcodeSource::new(
            text.clone(),
            magazine.clone(),
            settings,
            MachineState::at([0, 0, 0]),
            WorkOffsets::default(),
            Switches::default(),
        ) {
            match r {
                Ok(s) => blocks += s.blocks.len(),
                Err(e) => {
                    eprintln!("the pointed program does not read in {dialect:?}: {e}");
                    std::process::exit(1);
                }
            }
        }
        (thread_cpu() - c0, blocks)
    };
    let (mut linuxcnc, mut fanuc) = ((f64::MAX, 0), (f64::MAX, 0));
    for _ in 0..5 {
        let l = read(Dialect::LinuxCnc);
        let f = read(Dialect::Fanuc);
        linuxcnc = (linuxcnc.0.min(l.0), l.1);
        fanuc = (fanuc.0.min(f.0), f.1);
    }
    if linuxcnc.1 != fanuc.1 {
        eprintln!(
            "the pointed program makes {} blocks in LinuxCNC's dialect, {} in Fanuc's",
            linuxcnc.1, fanuc.1
        );
        std::process::exit(1);
    }
    println!(
        "gcode: dialects: the same program ({} blocks) read in LinuxCNC's {:.1} ms, in Fanuc's {:.1} ms CPU time: Fanuc/LinuxCNC {:.3} (target <= 1.10)",
        fanuc.1,
        linuxcnc.0 * 1e3,
        fanuc.0 * 1e3,
        fanuc.0 / linuxcnc.0
    );
}
