//! Frame benchmark (prints its figures): time to the first frame, full frame render time,
//! bytes for an idle frame, bytes for a frame where only the position readout changed, and
//! frames per second while a program runs. `cargo bench --bench frame`.

use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::{OpMode, PanelEvent};
use novanc::pulse_core::ClockMode;
use novanc::terminal::layout::{draw_panel, panel_size};
use novanc_panel::{Renderer, Screen};
use std::time::{Duration, Instant};

fn temp_state(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("novanc-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn open(name: &str, clock: ClockMode) -> Console {
    let mut cfg = ConsoleConfig::new(temp_state(name));
    cfg.clock = clock;
    match Console::open(cfg) {
        Ok((c, _)) => c,
        Err(e) => panic!("cannot open the console: {e}"),
    }
}

fn main() {
    let (w, h) = panel_size(12, 40);

    // Time to the first frame: open the console (fresh state: the embedded defaults), draw
    // the panel, render it.
    let t0 = Instant::now();
    let console = open("first", ClockMode::Virtual);
    let mut screen = Screen::new(w, h);
    draw_panel(&mut screen, &console.view());
    let mut out = Vec::new();
    let mut r = Renderer::new();
    r.render(&screen, &mut out);
    let first = t0.elapsed();
    let full_bytes = out.len();
    println!(
        "time to first frame:            {:>9.3} ms ({full_bytes} bytes, {w}x{h} panel)",
        first.as_secs_f64() * 1e3
    );
    drop(console);

    // Full frame: draw the panel and render it from scratch.
    let console = open("full", ClockMode::Virtual);
    let view = console.view();
    let n = 2000;
    let t0 = Instant::now();
    for _ in 0..n {
        screen.clear();
        draw_panel(&mut screen, &view);
        r.invalidate();
        out.clear();
        r.render(&screen, &mut out);
    }
    let per = t0.elapsed() / n;
    println!(
        "full frame render:              {:>9.1} us ({} bytes)",
        per.as_secs_f64() * 1e6,
        out.len()
    );

    // Idle frame: nothing changed.
    screen.clear();
    draw_panel(&mut screen, &view);
    out.clear();
    r.render(&screen, &mut out);
    let t0 = Instant::now();
    screen.clear();
    draw_panel(&mut screen, &console.view());
    out.clear();
    r.render(&screen, &mut out);
    let idle_t = t0.elapsed();
    println!(
        "idle frame:                     {:>9} bytes (target 0), {:.1} us",
        out.len(),
        idle_t.as_secs_f64() * 1e6
    );

    // Only the position readout changed: X moves by one pulse, then X and Y by 12.345 mm.
    let mut v = view.clone();
    v.axis_mm[0] += 0.001;
    v.tip_mm[0] += 0.001;
    screen.clear();
    draw_panel(&mut screen, &v);
    out.clear();
    r.render(&screen, &mut out);
    println!(
        "position-only frame (X +1 pulse):  {:>6} bytes (target < 100)",
        out.len()
    );
    let mut v2 = v.clone();
    for a in 0..2 {
        v2.axis_mm[a] += 12.345;
        v2.tip_mm[a] += 12.345;
    }
    screen.clear();
    draw_panel(&mut screen, &v2);
    out.clear();
    r.render(&screen, &mut out);
    println!(
        "position-only frame (X, Y +12.345 mm): {:>3} bytes (target < 100)",
        out.len()
    );
    drop(console);

    // Frames per second while Table B runs in real time: tick, draw, render, as fast as the
    // console can (the terminal loop itself ticks at about 50 Hz).
    // Tool changes and spindle starts shortened (0.2 s, 0.1 s) so that the 3 s are mostly motion.
    let mut cfg = ConsoleConfig::new(temp_state("run"));
    cfg.clock = ClockMode::RealTime;
    cfg.settings.tool_change_ns = 200_000_000;
    cfg.settings.spindle_ns = 100_000_000;
    let mut console = match Console::open(cfg) {
        Ok((c, _)) => c,
        Err(e) => panic!("cannot open the console: {e}"),
    };
    console.handle(PanelEvent::Op(OpMode::Auto));
    console.handle(PanelEvent::Start);
    let mut r = Renderer::new();
    let mut frames = 0u64;
    let mut changed = 0u64;
    let mut bytes = 0usize;
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(3) {
        console.tick();
        screen.clear();
        draw_panel(&mut screen, &console.view());
        out.clear();
        r.render(&screen, &mut out);
        bytes += out.len();
        changed += u64::from(!out.is_empty());
        frames += 1;
    }
    let secs = t0.elapsed().as_secs_f64();
    let st = console.status().clone();
    println!(
        "frames while Table B runs:      {:>9.0} frames/s ({} frames changed, avg {} bytes per changed frame; {} blocks done in {:.1} s)",
        frames as f64 / secs,
        changed,
        bytes / changed.max(1) as usize,
        st.blocks_done,
        secs
    );
    console.handle(PanelEvent::Reset);
    for name in ["first", "full", "run"] {
        let _ = std::fs::remove_dir_all(temp_state(name));
    }
}
