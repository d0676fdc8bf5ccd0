//! Fuzz families at the console: panel scripts (random lines, good and bad, run on a console in
//! virtual time) and damaged state directories (a state with acknowledged changes, then bytes
//! flipped, cut or added in its files, then opened again).

use super::harness::{note, Ctx};
use super::rng::Rng;
use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::ClockMode;
use novanc::store::{Stores, Target};
use std::path::Path;

/// Words and arguments a script line is made of.
const WORDS: &[&str] = &[
    "op AUTO",
    "op MDI",
    "op DATA",
    "op SINGLE",
    "op STEP",
    "op HANDLE",
    "op CONTINUOUS",
    "data SEARCH",
    "data REVISE",
    "data MDI",
    "data TOOLREVISE",
    "data TCODE",
    "data READ",
    "start",
    "stop",
    "reset",
    "estop",
    "wait",
    "wait ms 250",
    "wait ms 4000",
    "wait block 5",
    "wait block 30",
    "show",
    "override 0",
    "override 70",
    "override 150",
    "wheel X 10",
    "wheel Z -25",
    "key F9",
    "key F10",
    "key F8",
    "key F12",
    "key F11",
    "key Alt+2",
    "key Alt+6",
    "key Right",
    "key PgDn",
    "key Enter",
    "key x",
    "type 3L",
    "type SDP$-2DI9",
    "type -99LIGO, 500, 300, -200*",
    "type 8",
    "type T21=106",
    "tape programs/tableb.ap",
    "tape /nonexistent",
];

/// Bad lines the parser must refuse with a message.
const BAD: &[&str] = &[
    "op SIDEWAYS",
    "wait block",
    "wait ms -3",
    "wait fortnight",
    "override 33",
    "wheel W 1",
    "key Hyper",
    "key",
    "jump",
    "start now",
];

/// One panel script: parsed, and if it parses, run on a console.
pub fn script_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let mut lines = Vec::new();
    for _ in 0..rng.range(1, 30) {
        let w = if rng.chance(0.05) {
            rng.pick(BAD).to_string()
        } else {
            rng.pick(WORDS).to_string()
        };
        lines.push(w);
    }
    let text = lines.join("\n");
    note("panel script", &text);
    let events = match PanelEvent::parse_script(&text) {
        Ok(e) => e,
        Err(e) => {
            if e.message.is_empty() || e.message.len() > 300 {
                return Err(format!("a bad script line gets an unclear message: {e:?}"));
            }
            return Ok(());
        }
    };
    let dir = ctx.tmp.join(format!("console-{:x}", rng.next_u64()));
    let _ = std::fs::create_dir_all(&dir);
    let r = run_script(&dir, events);
    let _ = std::fs::remove_dir_all(&dir);
    r
}

fn run_script(dir: &Path, events: Vec<PanelEvent>) -> Result<(), String> {
    let mut cfg = ConsoleConfig::new(dir.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    let (mut c, _) = Console::open(cfg).map_err(|e| format!("open: {e}"))?;
    c.core().set_audit(true);
    for ev in events {
        let ev = match ev {
            PanelEvent::Tape(p) if p.is_relative() => {
                PanelEvent::Tape(Path::new(env!("CARGO_MANIFEST_DIR")).join(p))
            }
            ev => ev,
        };
        c.handle(ev);
        for e in c.core().take_audit() {
            if e.pos != e.end {
                return Err(format!("N{} ended off its programmed point", e.seq));
            }
        }
        let v = c.view();
        if v.display.len() != c.config().rows
            || v.display
                .iter()
                .any(|l| l.chars().count() > c.config().cols)
        {
            return Err(format!("the display is out of shape:\n{}", c.frame_text()));
        }
        if v.lamps.estop != c.status().estop {
            return Err("the E-STOP lamp disagrees with the machine".into());
        }
    }
    c.finish().map(|_| ()).map_err(|e| format!("finish: {e}"))
}

/// A state directory with acknowledged changes, damaged, then opened again: opening never
/// panics; it succeeds with warnings or fails with a message naming the directory; a state that
/// opens takes a change and opens again.
pub fn damage_case(rng: &mut Rng, ctx: &Ctx) -> Result<(), String> {
    let dir = ctx.tmp.join(format!("damage-{:x}", rng.next_u64()));
    let _ = std::fs::remove_dir_all(&dir);
    let r = damage_in(rng, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    r
}

fn damage_in(rng: &mut Rng, dir: &Path) -> Result<(), String> {
    {
        let (mut s, _) = Stores::open(dir, 24).map_err(|e| format!("open: {e}"))?;
        if rng.chance(0.5) {
            s.set_journal_limit(rng.range(1, 6) as usize);
        }
        for k in 0..rng.range(1, 12) {
            let t = *rng.pick(&[Target::Program, Target::Mdi]);
            let _ = s.edit(t, &format!("{}LIX{k}*", rng.range(-3, 3)), None);
        }
    }
    let files: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| e.to_string())?
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n == "state.snap" || n == "journal.log")
        })
        .collect();
    let mut what = Vec::new();
    for _ in 0..rng.range(1, 4) {
        let Some(f) = files.get(rng.below(files.len().max(1))) else {
            break;
        };
        let mut bytes = std::fs::read(f).unwrap_or_default();
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        match rng.below(6) {
            0 if !bytes.is_empty() => {
                let i = rng.below(bytes.len());
                bytes[i] ^= 1 << rng.below(8);
                what.push(format!("{name}: bit flipped at {i}"));
            }
            1 if !bytes.is_empty() => {
                let n = rng.below(bytes.len());
                bytes.truncate(n);
                what.push(format!("{name}: cut to {n} bytes"));
            }
            2 => {
                for _ in 0..rng.range(1, 64) {
                    bytes.push(rng.next_u64() as u8);
                }
                what.push(format!("{name}: garbage appended"));
            }
            3 if !bytes.is_empty() => {
                let i = rng.below(bytes.len());
                let n = rng.below(64).min(bytes.len() - i);
                for b in &mut bytes[i..i + n] {
                    *b = rng.next_u64() as u8;
                }
                what.push(format!("{name}: {n} bytes overwritten at {i}"));
            }
            4 => {
                bytes.clear();
                what.push(format!("{name}: emptied"));
            }
            _ => {
                let _ = std::fs::remove_file(f);
                what.push(format!("{name}: removed"));
                continue;
            }
        }
        let _ = std::fs::write(f, &bytes);
    }
    note("damaged state", &what.join("\n"));
    match Stores::open(dir, 24) {
        Err(e) => {
            let m = e.to_string();
            if m.is_empty() || m.len() > 2000 {
                return Err(format!("an unclear refusal to open: {m:?}"));
            }
            Ok(())
        }
        Ok((mut s, _)) => {
            let _ = s.buffer(Target::Program).text();
            let r = s.edit(Target::Mdi, "IAFTER*", None);
            drop(s);
            let (s2, _) = Stores::open(dir, 24).map_err(|e| format!("reopen: {e}"))?;
            if r.is_ok() && !s2.buffer(Target::Mdi).text().contains("AFTER") {
                return Err("an acknowledged change after the damage was lost".into());
            }
            Ok(())
        }
    }
}
