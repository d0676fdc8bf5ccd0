//! Key-to-screen benchmark (prints its figures; issue 23's target: under 2 ms): the time from
//! reading a single key's bytes to writing the last byte of the frame it changes, through
//! what the terminal loop does (`src/terminal/mod.rs`): `read` from a file descriptor (a pipe
//! here, the terminal there), the key decoder, `Console::press`, `Console::tick`, the panel
//! drawn from `Console::view`, the diff renderer, and `write` of the frame (to `/dev/null`).
//! The console runs in real time, as the interactive panel does. `cargo bench --bench keys`.

use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::{OpMode, PanelEvent};
use novanc::pulse_core::ClockMode;
use novanc::terminal::layout::{draw_panel, panel_size};
use novanc_panel::{Decoder, Renderer, Screen};
use std::io::{Read, Write};
use std::time::{Duration, Instant};

fn temp_state(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("novanc-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The terminal loop's state between frames.
struct Loop {
    console: Console,
    dec: Decoder,
    screen: Screen,
    renderer: Renderer,
    out: Vec<u8>,
    keys_in: std::io::PipeReader,
    keys_typed: std::io::PipeWriter,
    tty: std::fs::File,
}

impl Loop {
    fn open(name: &str) -> Loop {
        let mut cfg = ConsoleConfig::new(temp_state(name));
        cfg.clock = ClockMode::RealTime;
        cfg.settings.tool_change_ns = 200_000_000;
        cfg.settings.spindle_ns = 100_000_000;
        let mut console = match Console::open(cfg) {
            Ok((c, _)) => c,
            Err(e) => panic!("cannot open the console: {e}"),
        };
        console.set_saves_after_frame(true);
        let (w, h) = panel_size(12, 40);
        let (keys_in, keys_typed) = std::io::pipe().expect("a pipe");
        let tty = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/null")
            .expect("/dev/null");
        let mut l = Loop {
            console,
            dec: Decoder::new(),
            screen: Screen::new(w, h),
            renderer: Renderer::new(),
            out: Vec::with_capacity(16 * 1024),
            keys_in,
            keys_typed,
            tty,
        };
        l.frame();
        l
    }

    /// Draws and writes one frame, then lets the console save what it held back, as the
    /// terminal loop does.
    fn frame(&mut self) -> usize {
        let n = self.draw_and_write();
        self.console.frame_written();
        n
    }

    /// Ticks, draws and writes one frame (what changed since the last).
    fn draw_and_write(&mut self) -> usize {
        self.console.tick();
        self.screen.clear();
        draw_panel(&mut self.screen, &self.console.view());
        self.out.clear();
        self.renderer.render(&self.screen, &mut self.out);
        if !self.out.is_empty() {
            self.tty.write_all(&self.out).expect("write");
        }
        self.out.len()
    }

    /// Types `bytes` (one key), then times the loop from the read to the frame's last byte
    /// written. Returns the time and the frame's bytes.
    fn key(&mut self, bytes: &[u8]) -> (Duration, usize) {
        self.keys_typed.write_all(bytes).expect("type");
        let mut buf = [0u8; 64];
        let t0 = Instant::now();
        let n = self.keys_in.read(&mut buf).expect("read");
        let mut keys = self.dec.feed(&buf[..n]);
        if keys.is_empty() {
            keys = self.dec.flush();
        }
        for k in keys {
            self.console.press(k);
        }
        let written = self.draw_and_write();
        let t = t0.elapsed();
        // After the frame's last byte: the saves the console held back.
        self.console.frame_written();
        (t, written)
    }
}

/// Median, 99th percentile and worst of `t`, in ms.
fn figures(t: &mut [Duration]) -> (f64, f64, f64) {
    t.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let p = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
    (ms(p(0.5)), ms(p(0.99)), ms(t[t.len() - 1]))
}

/// Prints the figures of `t`; `bytes` is the frames' total.
fn report(what: &str, t: &mut [Duration], bytes: usize) {
    let bytes = bytes / t.len().max(1);
    let (med, p99, max) = figures(t);
    println!(
        "{what:<44} median {med:>7.3} ms  p99 {p99:>7.3} ms  max {max:>7.3} ms  ({} keys, {bytes} bytes/frame avg)",
        t.len()
    );
}

fn main() {
    let n = 300;

    // A letter typed on the PROGRAM REVISION page, then rubbed out (two keys, both timed).
    let mut l = Loop::open("keys-type");
    l.console.handle(PanelEvent::Op(OpMode::Data));
    l.frame();
    let mut t = Vec::new();
    let mut bytes = 0;
    for _ in 0..n {
        for k in [&b"L"[..], &b"\x7f"[..]] {
            let (d, b) = l.key(k);
            t.push(d);
            bytes += b;
        }
    }
    report("data key / rubout (DATA INPUT, idle)", &mut t, bytes);

    // A key that does nothing in this mode and says so (Delete, then a data key that clears
    // the message): the message goes to the MSG history too.
    let mut t = Vec::new();
    let mut bytes = 0;
    for _ in 0..n / 2 {
        for k in [&b"\x1b[3~"[..], &b"L"[..]] {
            let (d, b) = l.key(k);
            t.push(d);
            bytes += b;
        }
        l.key(b"\x7f");
    }
    report("Delete (a message) / data key (DATA INPUT)", &mut t, bytes);

    // The page keys POS and back while Table B runs.
    let mut l = Loop::open("keys-run");
    l.console.handle(PanelEvent::Op(OpMode::Auto));
    l.console.handle(PanelEvent::Start);
    l.frame();
    let mut t = Vec::new();
    let mut bytes = 0;
    for i in 0..n {
        // Ctrl-P (0x10) twice: POS and back; Alt+= / Alt+- (feed override).
        let k: &[u8] = match i % 4 {
            0 | 1 => b"\x10",
            2 => b"\x1b=",
            _ => b"\x1b-",
        };
        let (d, b) = l.key(k);
        t.push(d);
        bytes += b;
        std::thread::sleep(Duration::from_millis(2));
    }
    report("page key / feed override (AUTO, running)", &mut t, bytes);

    // START (F9) of Table B from idle (the run begins: the program source is made), then
    // RESET (F11), each timed.
    let mut t_start = Vec::new();
    let mut t_reset = Vec::new();
    let (mut b_start, mut b_reset) = (0, 0);
    l.console.handle(PanelEvent::Reset);
    l.frame();
    for _ in 0..n / 3 {
        let (d, b) = l.key(b"\x1b[20~");
        t_start.push(d);
        b_start += b;
        std::thread::sleep(Duration::from_millis(5));
        l.frame();
        let (d, b) = l.key(b"\x1b[23~");
        t_reset.push(d);
        b_reset += b;
    }
    report(
        "START (F9, AUTO, a new run of Table B)",
        &mut t_start,
        b_start,
    );
    report("RESET (F11, AUTO, running)", &mut t_reset, b_reset);
    for name in ["keys-type", "keys-run"] {
        let _ = std::fs::remove_dir_all(temp_state(name));
    }
}
