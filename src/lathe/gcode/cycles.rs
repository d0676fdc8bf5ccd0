//! Lathe cycles (docs/lathe-gcode.md "Cycles"): G76 threading in LinuxCNC's form, G71
//! roughing and G70 finishing in Fanuc 0i-T's two-block form.

use super::exec::{err, Flow, Reader};
use super::out::{Kind, Mv};
use super::MAX_PASSES;
use crate::block::TranslateError;
use crate::gcode::geom::lead_on_longest;
use crate::gcode::geom::sweep;
use crate::gcode::words::Words;
use crate::gcode::Lines;
use std::f64::consts::FRAC_PI_2;

/// A move of `kind` to `end` (its start is where the emitter stands), at line `n`, column `c`.
pub(super) fn mv(kind: Kind, end: [f64; 2], n: u32, c: u32) -> Mv {
    Mv {
        kind,
        start: end,
        end,
        line: n,
        col: c,
    }
}

/// How far a G71/G72 profile's arc may come back past its extreme before it turns back:
/// under a pulse (an end written to the least increment, 0.0001 inch, lies that far off the
/// circle's top; the arc then passes it by some nanometres).
const ARC_TURN_TOLERANCE_MM: f64 = 0.0005;

fn need(w: &Words, l: char, n: u32, c: u32, what: &str) -> Result<f64, TranslateError> {
    w.get(l)
        .ok_or_else(|| err(n, c, format!("{what} needs {l}")))
}

fn refuse(w: &Words, letters: &str, n: u32, what: &str) -> Result<(), TranslateError> {
    for l in letters.chars() {
        if let Some(c) = w.col(l) {
            return Err(err(n, c, format!("{what} takes no {l} word")));
        }
    }
    Ok(())
}

/// The depths of a G76's passes, mm below the thread's crest: `j`·n^(1/`r`) for n = 1, 2, …,
/// each at least `step` deeper than the one before, while below `k` − `allowance`; then
/// `k` − `allowance`; then `finish` passes at `k`. LinuxCNC 2.9's G76 is J, K, R and H spring
/// passes with no step and no allowance; Fanuc's two-block G76 is Δd, k, 2 (Δd·√n), m
/// finishing passes, Δdmin and d (docs/lathe-gcode.md "G76, Fanuc's two-block form").
pub fn g76_depths(
    j: f64,
    k: f64,
    r: f64,
    finish: u32,
    step: f64,
    allowance: f64,
) -> Option<Vec<f64>> {
    let rough = k - allowance;
    let mut v = Vec::new();
    let mut i = 1.0f64;
    let mut last = 0.0f64;
    loop {
        let d = (j * i.powf(1.0 / r)).max(last + step);
        if d >= rough - 1e-9 {
            break;
        }
        if v.len() >= MAX_PASSES {
            return None;
        }
        v.push(d);
        last = d;
        i += 1.0;
    }
    v.push(rough);
    for _ in 0..finish {
        v.push(k);
    }
    (v.len() <= MAX_PASSES).then_some(v)
}

/// One thread's passes, as both forms of G76 make them.
struct Passes {
    /// The drive line: where the tool stood when the cycle started, `[Z, X]`.
    start: [f64; 2],
    /// The thread's end Z.
    z_end: f64,
    /// The crest's offset from the drive line at the thread's end (radius; negative
    /// outside, positive in a bore).
    crest: f64,
    /// The depths, mm below the crest.
    depths: Vec<f64>,
    /// The thread's full depth.
    full: f64,
    /// tan of the compound angle (0: straight in).
    tan_q: f64,
    /// The lead, mm per revolution.
    lead: f64,
    /// Fanuc: each pass retracts to the drive line and the cycle ends where it started;
    /// LinuxCNC: the retract lies `full` − depth beyond the drive line and the cycle ends at
    /// the drive line at `z_end`.
    fanuc: bool,
    /// Fanuc's taper, the radius at the start of the cut less the radius at its end.
    taper: f64,
    /// Fanuc's chamfer (thread pull-out): the last `chamfer` mm of Z leave at 45°.
    chamfer: f64,
    /// LinuxCNC's E taper ends (L 1, 2, 3): the Z length of the taper into the groove at the
    /// start and out of it at the end (0: none), each a thread block run on from the one
    /// before it, the lead along the path `taper_pitch` (LinuxCNC's `taper_pitch`).
    taper_in: f64,
    /// See `taper_in`.
    taper_out: f64,
}

/// The passes (LinuxCNC 2.9's `threading_pass`, interp_convert.cc): back to the retract X
/// at the start Z, in to the depth, the synchronised cut to Z (a 45° pull-out over its last
/// `chamfer` mm), out to the retract X.
fn thread_passes(r: &mut Reader, p: &Passes, n: u32, c: u32) -> Result<(), TranslateError> {
    use crate::block::Tap;
    let sign = p.crest.signum();
    let first = p.depths.first().copied().unwrap_or(0.0);
    let dz = (p.z_end - p.start[0]).signum();
    let length = (p.z_end - p.start[0]).abs();
    // Q, the compound angle, so that the tool goes down one flank. Fanuc's: each pass starts
    // and ends (depth − first)·tan(Q) further along −Z than the first. LinuxCNC's
    // (convert_threading_cycle): the start depth·tan(Q) on from Z0 towards Z, and the end
    // (K − depth)·tan(Q) short of Z, the angle's sign turned when the thread runs towards +Z.
    let (tan_q, beyond) = if p.fanuc {
        (p.tan_q, 0.0)
    } else {
        let t = -dz * p.tan_q;
        (t, p.full * t)
    };
    // Each segment after the first of a pass goes on in the groove the one before it cut
    // (`Tap::Part` on the one before): a taper end, a chamfer.
    let thread = |r: &mut Reader, lead: f64, end: [f64; 2], last: bool| {
        r.out.set_tap(if last { Tap::No } else { Tap::Part });
        let done = r.out.motion(mv(Kind::Thread(lead), end, n, c));
        r.out.set_tap(Tap::No);
        done
    };
    for &d in &p.depths {
        let x = p.start[1] + p.crest + sign * d;
        let back = if p.fanuc {
            p.start[1]
        } else {
            p.start[1] - sign * (p.full - d)
        };
        let zoff = if p.fanuc {
            (d - first) * tan_q
        } else {
            d * tan_q
        };
        let (z0, z1) = (p.start[0] - zoff, p.z_end + beyond - zoff);
        r.out.motion(mv(Kind::Rapid, [z0, back], n, c))?;
        if p.taper_in > 0.0 {
            // In to the crest's height above the cut, then down the taper to the cut, both
            // geared to the spindle (LinuxCNC's threading_pass).
            let top = x - sign * p.full;
            let taper_pitch = p.lead * p.taper_in.hypot(p.full) / p.taper_in;
            thread(r, taper_pitch, [z0, top], false)?;
            let down = lead_on_longest(taper_pitch, &[p.taper_in, p.full]);
            thread(r, down, [z0 + dz * p.taper_in, x], false)?;
        } else {
            r.out.motion(mv(Kind::Rapid, [z0, x + p.taper], n, c))?;
        }
        if p.taper_out > 0.0 {
            thread(r, p.lead, [z1 - dz * p.taper_out, x], false)?;
            let taper_pitch = p.lead * p.taper_out.hypot(p.full) / p.taper_out;
            let up = lead_on_longest(taper_pitch, &[p.taper_out, p.full]);
            thread(r, up, [z1, x - sign * p.full], true)?;
        } else if p.chamfer > 0.0 {
            let at = x + p.taper * p.chamfer / length;
            thread(r, p.lead, [z1 - dz * p.chamfer, at], false)?;
            thread(r, p.lead, [z1, x - sign * p.chamfer], true)?;
        } else {
            thread(r, p.lead, [z1, x], true)?;
        }
        r.out.motion(mv(Kind::Rapid, [z1, back], n, c))?;
    }
    let end = if p.fanuc {
        p.start
    } else {
        [p.z_end, p.start[1]]
    };
    r.out.motion(mv(Kind::Rapid, end, n, c))
}

/// G76 P Z I J K [R] [H] [Q] [E0] [L]: threading passes from the drive line (where the
/// tool stands) to Z, as LinuxCNC 2.9 makes them (Q read, not applied).
pub fn g76(r: &mut Reader, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
    const WHAT: &str = "G76";
    refuse(
        w,
        "XUWFDS",
        n,
        "G76 (the drive line is where the tool stands)",
    )?;
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            "G76 with nose-radius compensation in force: give G40 first",
        ));
    }
    if r.st.stopped() {
        return Err(err(n, c, "G76 with the spindle stopped: give M03 or M04"));
    }
    let f = r.st.factor();
    let pitch = need(w, 'P', n, c, WHAT)? * f;
    let z = need(w, 'Z', n, c, WHAT)? * f;
    // I, J and K are distances across the axis: diameters in G07, as in LinuxCNC.
    let dia = if r.st.diameter { 2.0 } else { 1.0 };
    let i = need(w, 'I', n, c, WHAT)? * f / dia;
    let j = need(w, 'J', n, c, WHAT)? * f / dia;
    let k = need(w, 'K', n, c, WHAT)? * f / dia;
    let col = |l: char| w.col(l).unwrap_or(c);
    if !(pitch > 0.0 && pitch <= 100.0) {
        return Err(err(
            n,
            col('P'),
            "G76 P, the pitch, must be above 0 and at most 100 mm",
        ));
    }
    if !(j > 0.0 && j.is_finite()) {
        return Err(err(
            n,
            col('J'),
            "G76 J, the first cut's depth, must be above 0",
        ));
    }
    if !(k > j && k < 1000.0) {
        return Err(err(
            n,
            col('K'),
            "G76 K, the thread's depth, must be greater than J",
        ));
    }
    if !(i != 0.0 && i.is_finite()) {
        return Err(err(n, col('I'), "G76 I, the peak's offset from the drive line, must not be 0 (negative outside, positive inside)"));
    }
    let deg = w.get('R').unwrap_or(1.0);
    if !(1.0..=10.0).contains(&deg) {
        return Err(err(
            n,
            col('R'),
            "G76 R, the depth degression, must be 1 to 10",
        ));
    }
    let h = w.get('H').unwrap_or(0.0);
    if !(h.fract() == 0.0 && (0.0..=100.0).contains(&h)) {
        return Err(err(
            n,
            col('H'),
            "G76 H, the spring passes, must be a whole number 0 to 100",
        ));
    }
    // Q, the compound angle: each pass starts and ends depth·tan(Q) further along -Z than
    // the first, so the tool goes down one flank (LinuxCNC: zoff = (depth - J)·tan(Q)).
    let q = w.get('Q').unwrap_or(0.0);
    if !(0.0..90.0).contains(&q) {
        return Err(err(
            n,
            col('Q'),
            "G76 Q, the compound angle, must be 0 to below 90 degrees",
        ));
    }
    let tan_q = q.to_radians().tan();
    // E, the taper ends' length along Z, and L, which ends: 1 the start, 2 the end, 3 both
    // (LinuxCNC: an E without L tapers neither end).
    let e = w.get('E').unwrap_or(0.0) * f;
    if !(e.is_finite() && (0.0..1000.0).contains(&e)) {
        return Err(err(
            n,
            col('E'),
            "G76 E, the taper ends' length along Z, must be 0 or more",
        ));
    }
    let l = w.get('L').unwrap_or(0.0);
    if !(l.fract() == 0.0 && (0.0..=3.0).contains(&l)) {
        return Err(err(n, col('L'), "G76 L must be 0 to 3"));
    }
    let l = l as u32;
    // An absolute Z from the program's zero (moved by G92 X Z, or system A's G50), as every
    // move reads it.
    let z_end = if r.st.absolute {
        r.zero()[0] + z
    } else {
        r.out.pos[0] + z
    };
    let start = r.out.pos;
    if (z_end - start[0]).abs() < 1e-9 {
        return Err(err(
            n,
            col('Z'),
            "G76 Z is where the tool stands: a thread needs a length",
        ));
    }
    let Some(depths) = g76_depths(j, k, deg, h as u32, 0.0, 0.0) else {
        return Err(err(
            n,
            c,
            format!("G76 makes more than {MAX_PASSES} passes: deepen J or raise R"),
        ));
    };
    let (taper_in, taper_out) = (
        if l & 1 != 0 { e } else { 0.0 },
        if l & 2 != 0 { e } else { 0.0 },
    );
    if taper_in + taper_out >= (z_end - start[0]).abs() {
        return Err(err(
            n,
            col('E'),
            "G76 E: the taper ends are as long as the thread",
        ));
    }
    let passes = Passes {
        start,
        z_end,
        crest: i,
        depths,
        full: k,
        tan_q,
        lead: pitch,
        fanuc: false,
        taper: 0.0,
        chamfer: 0.0,
        taper_in,
        taper_out,
    };
    thread_passes(r, &passes, n, c)
}

fn profile_lines(
    r: &Reader,
    w: &Words,
    n: u32,
    c: u32,
    what: &str,
) -> Result<(usize, usize), TranslateError> {
    let mut idx = [0usize; 2];
    for (k, l) in ['P', 'Q'].into_iter().enumerate() {
        // Fanuc's `Q20` here is N20, not 20 least increments.
        let v = r.as_written(l, need(w, l, n, c, what)?);
        let col = w.col(l).unwrap_or(c);
        if !(v.fract() == 0.0 && (0.0..1e9).contains(&v)) {
            return Err(err(
                n,
                col,
                format!(
                    "{what} {l}{}: a sequence number N",
                    crate::input_text::short_number(v)
                ),
            ));
        }
        idx[k] = *r
            .n_lines
            .get(&(v as u32))
            .ok_or_else(|| err(n, col, format!("{what} {l}{v}: no line N{v}")))?;
    }
    if idx[1] < idx[0] {
        return Err(err(n, c, format!("{what}: line Q comes before line P")));
    }
    Ok((idx[0], idx[1]))
}

/// G70 P Q: the finishing pass, the profile's lines run as written, then back to the start.
pub fn g70(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    lines: &mut dyn Lines,
) -> Result<Flow, TranslateError> {
    refuse(w, "XZUWIKRJHEL", n, "G70")?;
    let (p, q) = profile_lines(r, w, n, c, "G70")?;
    let start = r.out.pos;
    r.in_cycle = true;
    let res = r.run_range(p, q + 1, lines);
    r.in_cycle = false;
    res?;
    r.out.motion(mv(Kind::Rapid, start, n, c))?;
    Ok(Flow::Next)
}

/// G71 U R (depth of cut, retract) or G71 P Q U W F: roughing in passes parallel to Z down to
/// the profile of lines P..Q, left with the allowances U (on the diameter in G07) and W, then
/// one pass along the profile; the lines P..Q are then skipped.
pub fn g71(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    idx: usize,
    lines: &mut dyn Lines,
) -> Result<Flow, TranslateError> {
    rough(r, w, n, c, idx, lines, false)
}

/// G72 W R (depth of cut along Z, retract) or G72 P Q U W F: Fanuc 0i-T's stock removal in
/// facing, G71 with the axes' parts swapped: passes parallel to X, one depth of cut deeper in
/// Z each, down to the profile of lines P..Q (its first move Z only, type I), then one pass
/// along the profile. The depth and retract are the ones G71's first block sets (a Fanuc keeps
/// both cycles' in one pair of parameters, 5132 and 5133).
pub fn g72(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    idx: usize,
    lines: &mut dyn Lines,
) -> Result<Flow, TranslateError> {
    rough(r, w, n, c, idx, lines, true)
}

/// The retract of G71/G72's one-block form (`G71 P Q U W D F`) before any first block has set
/// one, mm (a Fanuc's parameter 5133, a Haas's setting 73).
pub const ONE_BLOCK_RETRACT_MM: f64 = 0.5;

/// Letter `l`'s value `v` as a length in program units where the one reader keeps it as
/// written (D): in Fanuc's dialect a number written without a decimal point is in least
/// increments (`D1500` is 1.5 mm), unless the input is calculator-type.
pub(super) fn fanuc_length(r: &Reader, l: char, v: f64) -> f64 {
    if r.fanuc && !r.calculator && r.written_without_point(l) {
        v * r.increment()
    } else {
        v
    }
}

/// G71 (`face` false) or G72 (`face` true).
fn rough(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    idx: usize,
    lines: &mut dyn Lines,
    face: bool,
) -> Result<Flow, TranslateError> {
    let f = r.st.factor();
    let (name, dl) = if face { ("G72", 'W') } else { ("G71", 'U') };
    if w.get('P').is_none() && w.get('Q').is_none() {
        let other = if face { "XZUIKJHEL" } else { "XZWIKJHEL" };
        refuse(w, other, n, &format!("{name} {dl} R"))?;
        if let Some(c) = w.col('D') {
            return Err(err(
                n,
                c,
                format!("{name} {dl} R takes no D word (D is the depth of cut of the one-block form {name} P Q U W D F)"),
            ));
        }
        let d = need(w, dl, n, c, &format!("{name} (first block)"))? * f;
        let e = w.get('R').unwrap_or(0.0) * f;
        if !(d > 0.0 && d < 1000.0) {
            return Err(err(
                n,
                w.col(dl).unwrap_or(c),
                format!("{name} {dl}, the depth of cut, must be above 0"),
            ));
        }
        if !(0.0..1000.0).contains(&e) {
            return Err(err(
                n,
                w.col('R').unwrap_or(c),
                format!("{name} R, the retract, must not be negative"),
            ));
        }
        r.st.g71 = Some((d, e));
        return Ok(Flow::Next);
    }
    if w.get('P').is_none() && !r.fanuc {
        // `G71 Q100 X Z D I R`: Q an O-word subroutine, the profile's start X Z.
        return Err(err(
            n,
            c,
            format!("{name} Q without P is LinuxCNC's own {name} form (Q an O-word profile), which the lathe does not read: write Fanuc's {name} P Q, the profile's first and last N (docs/lathe-gcode.md)"),
        ));
    }
    refuse(w, "XZIKRJHEL", n, &format!("{name} P Q"))?;
    if r.out.comp_on() {
        return Err(err(n, c, format!("{name} with nose-radius compensation in force: give G40 first (the allowances U and W take the nose's place)")));
    }
    let (depth, retract) = match (w.get('D'), r.st.g71) {
        // The one-block form (Fanuc's FS15 format, Haas): D the depth of cut, the retract the
        // one the last first block set (Fanuc's parameter 5133), else ONE_BLOCK_RETRACT_MM.
        (Some(d), kept) => {
            let d = fanuc_length(r, 'D', d) * f;
            if !(d > 0.0 && d < 1000.0) {
                return Err(err(
                    n,
                    w.col('D').unwrap_or(c),
                    format!("{name} D, the depth of cut, must be above 0 and under 1000 mm"),
                ));
            }
            (d, kept.map_or(ONE_BLOCK_RETRACT_MM, |k| k.1))
        }
        (None, Some(kept)) => kept,
        (None, None) => {
            return Err(err(
                n,
                c,
                format!("{name} P Q needs its depth of cut: the first {name} block ({name} {dl} R: depth of cut and retract) before it, or D on this line ({name} P Q U W D F)"),
            ))
        }
    };
    let Profile {
        moves: prof,
        start: a,
        allow: [dw, du],
        feed,
        q,
        type2,
    } = profile(r, w, n, c, idx, lines, name)?;
    let rough = if face {
        // G72 is G71 on the plane mirrored across Z = X: swap each point's parts, cut, swap back.
        let prof: Vec<Mv> = prof.iter().map(swapped).collect();
        g71_moves(
            &prof,
            [a[1], a[0]],
            depth,
            retract,
            [du, dw],
            feed,
            n,
            c,
            true,
            false,
        )?
        .iter()
        .map(swapped)
        .collect()
    } else {
        g71_moves(&prof, a, depth, retract, [dw, du], feed, n, c, false, type2)?
    };
    for m in rough {
        r.out.motion(m)?;
    }
    Ok(Flow::Jump(q + 1))
}

/// A roughing cycle's profile (G71, G72, G73): its moves as read, not emitted.
struct Profile {
    /// The profile's moves, `[Z, X]` mm (X a radius).
    moves: Vec<Mv>,
    /// Where the tool stands at the cycle's line: the start point A.
    start: [f64; 2],
    /// The finishing allowances `[W, U as a radius]`, mm.
    allow: [f64; 2],
    /// The roughing feed (the feed in force, F on the line).
    feed: super::out::Feed,
    /// The profile's last line (0-based): reading goes on after it.
    q: usize,
    /// Its first line names Z or W: Fanuc's type II (G71 with pockets).
    type2: bool,
}

/// The profile of the cycle `name` on line `n`: the lines P to Q (after the cycle's line) read
/// without emitting anything and without changing the program's modes, its allowances U
/// (on the diameter in G07) and W, and the feed in force.
fn profile(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    idx: usize,
    lines: &mut dyn Lines,
    name: &str,
) -> Result<Profile, TranslateError> {
    let f = r.st.factor();
    let (p, q) = profile_lines(r, w, n, c, name)?;
    if p <= idx {
        return Err(err(
            n,
            c,
            format!("the {name} profile (lines P to Q) must follow the {name} line"),
        ));
    }
    let dia = if r.st.diameter { 2.0 } else { 1.0 };
    let du = w.get('U').unwrap_or(0.0) * f / dia;
    let dw = w.get('W').unwrap_or(0.0) * f;
    let Some(feed) = r.st.feed_of() else {
        return Err(err(
            n,
            c,
            format!("{name} roughs at the feed in force: give F"),
        ));
    };
    let (saved, a) = (r.st.clone(), r.out.pos);
    r.out.capture = Some(Vec::new());
    r.in_cycle = true;
    (r.profile_first, r.profile_names_z) = (Some(p), None);
    let res = r.run_range(p, q + 1, lines);
    r.profile_first = None;
    r.in_cycle = false;
    let moves = r.out.capture.take().unwrap_or_default();
    r.st = saved;
    r.out.pos = a;
    res?;
    Ok(Profile {
        moves,
        start: a,
        allow: [dw, du],
        feed,
        q,
        type2: r.profile_names_z.take().unwrap_or(false),
    })
}

/// The most passes of a G73 (its first block's R).
pub const MAX_G73_PASSES: u32 = 100;

/// G73 U(Δi) W(Δk) R(d), then G73 P Q U W F: Fanuc 0i-T's pattern repeating, in Fanuc's
/// dialect. The profile of lines P..Q is cut d times, each time shifted by its share of the
/// relief (Δi, Δk) plus the allowances: the first pass (Δi, Δk) out, the last at the
/// allowances alone, the ones between evenly. Each pass goes from the start point A along the
/// shifted profile (its first move in that move's own mode, the rest at the roughing feed, as
/// written rapids at rapid) and leaves as G71 does: out to A's X, along Z to A's Z, to A.
/// The lines P..Q are then skipped. The relief and count are kept (the first block's, as a
/// Fanuc keeps them in parameters 5135 to 5137) for a later G73 P Q.
pub fn g73(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
    idx: usize,
    lines: &mut dyn Lines,
) -> Result<Flow, TranslateError> {
    if !r.fanuc {
        return Err(err(
            n,
            c,
            "G73 is Fanuc's pattern repeating, read in Fanuc's dialect only (LinuxCNC's G73 is a mill's drilling cycle)",
        ));
    }
    let f = r.st.factor();
    if w.get('P').is_none() && w.get('Q').is_none() {
        refuse(w, "XZIKJHELDF", n, "G73 U W R")?;
        let relief = [w.get('W').unwrap_or(0.0) * f, w.get('U').unwrap_or(0.0) * f];
        let d = r.as_written('R', need(w, 'R', n, c, "G73 (first block)")?);
        if !(d.fract() == 0.0 && (1.0..=f64::from(MAX_G73_PASSES)).contains(&d)) {
            return Err(err(
                n,
                w.col('R').unwrap_or(c),
                format!(
                    "G73 R, the number of passes, must be a whole number 1 to {MAX_G73_PASSES}"
                ),
            ));
        }
        if relief.iter().any(|v| v.abs() >= 1000.0) {
            return Err(err(n, c, "G73 U and W, the relief, must be under 1000 mm"));
        }
        r.st.g73 = Some((relief, d as u32));
        return Ok(Flow::Next);
    }
    refuse(w, "XZIKRJHELD", n, "G73 P Q")?;
    if r.out.comp_on() {
        return Err(err(n, c, "G73 with nose-radius compensation in force: give G40 first (the allowances U and W take the nose's place)"));
    }
    let Some((relief, d)) = r.st.g73 else {
        return Err(err(
            n,
            c,
            "G73 P Q needs the first G73 block (G73 U W R: the relief and the number of passes) before it",
        ));
    };
    let pr = profile(r, w, n, c, idx, lines, "G73")?;
    let a = pr.start;
    let Some(first) = pr.moves.first() else {
        return Err(err(n, c, "the G73 profile (lines P to Q) has no move"));
    };
    if !matches!(first.kind, Kind::Rapid | Kind::Line(_)) {
        // It is made from the start point to the shifted profile: a G02/G03 there would not be
        // the arc written.
        return Err(err(
            first.line,
            first.col,
            "the G73 profile's first move must be G00 or G01",
        ));
    }
    // The side the profile lies on from A, across X: where the way out goes.
    let sx = if first.end[1] < a[1] { 1.0 } else { -1.0 };
    let mut out = Vec::new();
    for k in 1..=d {
        let t = if d > 1 {
            f64::from(d - k) / f64::from(d - 1)
        } else {
            0.0
        };
        let off = [relief[0] * t + pr.allow[0], relief[1] * t + pr.allow[1]];
        let shift = |p: [f64; 2]| [p[0] + off[0], p[1] + off[1]];
        for (i, m) in pr.moves.iter().enumerate() {
            let mut s = *m;
            s.start = if i == 0 { a } else { shift(m.start) };
            s.end = shift(m.end);
            s.kind = match m.kind {
                Kind::Thread(_) => {
                    return Err(err(m.line, m.col, "G33 in a G73 profile"));
                }
                Kind::Arc { c: ctr, ccw, .. } => Kind::Arc {
                    c: shift(ctr),
                    ccw,
                    feed: pr.feed,
                },
                Kind::Rapid => Kind::Rapid,
                _ => Kind::Line(pr.feed),
            };
            out.push(s);
        }
        let e = out.last().map_or(a, |m: &Mv| m.end);
        way_out(&mut out, e, a, sx, n, c);
    }
    for m in moving(out, a) {
        r.out.motion(m)?;
    }
    Ok(Flow::Jump(pr.q + 1))
}

/// `m` mirrored across the line Z = X: each point's `[Z, X]` swapped, so an arc turns the other
/// way. Twice is `m` again.
fn swapped(m: &Mv) -> Mv {
    let sw = |p: [f64; 2]| [p[1], p[0]];
    let mut s = *m;
    s.start = sw(m.start);
    s.end = sw(m.end);
    if let Kind::Arc { c, ccw, feed } = m.kind {
        s.kind = Kind::Arc {
            c: sw(c),
            ccw: !ccw,
            feed,
        };
    }
    s
}

/// The roughing moves of G71 from the start `a` `[Z, X]` over the profile `prof` (its first
/// move X only), shifted by `allow` `[W, U radius]`. With `face` the points come swapped,
/// `[X, Z]`, from G72, and the messages name G72's axes and words. With `pockets` (Fanuc's
/// type II: the profile's first block names Z or W) the profile may turn back in X, and each
/// level also cuts the pockets below it (docs/lathe-gcode.md "Type II: pockets").
#[allow(clippy::too_many_arguments)]
pub fn g71_moves(
    prof: &[Mv],
    a: [f64; 2],
    depth: f64,
    retract: f64,
    allow: [f64; 2],
    feed: super::out::Feed,
    n: u32,
    c: u32,
    face: bool,
    pockets: bool,
) -> Result<Vec<Mv>, TranslateError> {
    // The cycle, the axis of its depth (across the passes) and of its passes, its depth word.
    let (g, ax, along, dl) = if face {
        ("G72", 'Z', 'X', 'W')
    } else {
        ("G71", 'X', 'Z', 'U')
    };
    let Some(first) = prof.first() else {
        return Err(err(
            n,
            c,
            format!("the {g} profile (lines P to Q) has no move"),
        ));
    };
    // Type I's first move is X only; type II's (its line names Z) may move Z too, towards the
    // part, from the start point in front of it.
    let z_first = first.end[0] - a[0];
    if (z_first.abs() > 1e-9 && !pockets) || (first.end[1] - a[1]).abs() < 1e-9 {
        let why = if face {
            format!("the {g} profile's first move must move {ax} only (Fanuc type I)")
        } else {
            format!("the {g} profile's first move must move {ax} only (Fanuc type I; a first line that names Z or W is type II, which may move Z too)")
        };
        return Err(err(first.line, first.col, why));
    }
    let sx = if first.end[1] < a[1] { 1.0 } else { -1.0 };
    // Moves that end the profile out of the stock, at or beyond the start's X (shop programs
    // end a profile with a rapid out and back to the start's Z before G40): no level reaches
    // them, so the roughing ends before them and leaves by its own way out; G70 runs them as
    // written. They are not a turn back (docs/lathe-gcode.md "G71 roughing").
    let outside = |p: [f64; 2]| sx * (p[1] - a[1]) >= -1e-9;
    let mut prof = prof;
    while prof.len() > 2 {
        let m = prof[prof.len() - 1];
        if matches!(m.kind, Kind::Arc { .. } | Kind::Thread(_))
            || !(outside(m.start) && outside(m.end))
        {
            break;
        }
        prof = &prof[..prof.len() - 1];
    }
    // The way the profile goes along its passes is the way its first move along them goes; a
    // profile that comes back (to where it began, even) turns back at a line of its own, found
    // below, not here.
    let Some(dz) = prof[1..]
        .iter()
        .map(|m| m.end[0] - m.start[0])
        .find(|d| d.abs() > 1e-9)
    else {
        return Err(err(
            first.line,
            first.col,
            format!("the {g} profile must move along {along} after its first move"),
        ));
    };
    let sz = if dz > 0.0 { 1.0 } else { -1.0 };
    if sz * z_first < -1e-9 {
        return Err(err(
            first.line,
            first.col,
            format!("the {g} profile must be monotonic: its first move turns back in {along}"),
        ));
    }
    // Shift and check monotony: X away from the axis (OD) or towards it (ID), Z one way.
    let shift = |p: [f64; 2]| [p[0] + allow[0], p[1] + allow[1]];
    let mut segs: Vec<Mv> = Vec::with_capacity(prof.len());
    for m in &prof[1..] {
        let bad = |what: &str| {
            err(
                m.line,
                m.col,
                format!("the {g} profile must be monotonic: this move {what}"),
            )
        };
        if sx * (m.end[1] - m.start[1]) < -1e-9 && !pockets {
            let hint = if face {
                String::new()
            } else {
                " (a pocket is Fanuc's type II: name Z or W0 in the profile's first block)".into()
            };
            return Err(bad(&format!("turns back in {ax}{hint}")));
        }
        if sz * (m.end[0] - m.start[0]) < -1e-9 {
            return Err(bad(&format!("turns back in {along}")));
        }
        let mut s = *m;
        s.start = shift(m.start);
        s.end = shift(m.end);
        match m.kind {
            Kind::Thread(_) => return Err(err(m.line, m.col, format!("G33 in a {g} profile"))),
            Kind::Arc { c: ctr, ccw, feed } => {
                let sw = sweep(m.start, m.end, ctr, ccw);
                let a0 = (m.start[1] - ctr[1]).atan2(m.start[0] - ctr[0]);
                let radius = (m.start[0] - ctr[0]).hypot(m.start[1] - ctr[1]);
                for k in 0..4 {
                    let q = k as f64 * FRAC_PI_2;
                    let d = if ccw { q - a0 } else { a0 - q }.rem_euclid(std::f64::consts::TAU);
                    if d > 1e-9 && d < sw - 1e-9 {
                        // How far the arc comes back past its extreme, along the axis of that
                        // extreme: an end written a least increment off the circle's top (a
                        // CAM's or a hand's rounding) passes it by far less than a pulse.
                        let axis = k % 2;
                        let extreme = ctr[axis] + radius * if k < 2 { 1.0 } else { -1.0 };
                        let back = (extreme - m.start[axis])
                            .abs()
                            .min((extreme - m.end[axis]).abs());
                        // Type II: an arc may turn in X (the bottom of a pocket), not in Z.
                        if back > ARC_TURN_TOLERANCE_MM && !(pockets && axis == 1) {
                            return Err(bad("is an arc that turns back"));
                        }
                    }
                }
                s.kind = Kind::Arc {
                    c: shift(ctr),
                    ccw,
                    feed,
                };
            }
            _ => s.kind = Kind::Line(feed),
        }
        segs.push(s);
    }
    let x1 = first.end[1] + allow[1];
    let span = sx * (a[1] - x1);
    if span <= 0.0 {
        return Err(err(n, c, format!("the {g} start point must be outside the stock: {ax} beyond the profile's first {ax} and its allowance")));
    }
    // Type II: the levels go down to the deepest point of the profile (a pocket may be deeper
    // than its first point).
    let bottom = if pockets {
        segs.iter()
            .flat_map(extremes_x)
            .fold(x1, |b, x| if sx * (x - b) < 0.0 { x } else { b })
    } else {
        x1
    };
    let levels = (sx * (a[1] - bottom) / depth).ceil() as usize;
    if levels > MAX_PASSES {
        return Err(err(
            n,
            c,
            format!("{g} would make more than {MAX_PASSES} passes: deepen {dl}"),
        ));
    }
    let mut out = Vec::new();
    let mut k = 1usize;
    loop {
        let x = a[1] - sx * depth * k as f64;
        if sx * (x - bottom) <= 1e-9 {
            break;
        }
        if !pockets {
            let z = z_at(&segs, x, sx).unwrap_or(segs[segs.len() - 1].end[0]);
            out.push(mv(Kind::Rapid, [a[0], x], n, c));
            out.push(mv(Kind::Line(feed), [z, x], n, c));
            out.push(mv(Kind::Rapid, [z - sz * retract, x + sx * retract], n, c));
            out.push(mv(Kind::Rapid, [a[0], x + sx * retract], n, c));
            k += 1;
            continue;
        }
        // Type II: every stretch of the level where the profile lies below it. The first
        // (from the start's Z) is cut as type I cuts it; a pocket is reached over the profile
        // at the start's X, down its near side to the last level, then in at the feed.
        let ivs = below(&segs, x, sx);
        let x_prev = x + sx * depth;
        let mut at_a_x = false;
        for (i, iv) in ivs.iter().enumerate() {
            let first = (iv[0] - segs[0].start[0]).abs() < 1e-9;
            if first {
                out.push(mv(Kind::Rapid, [a[0], x], n, c));
            } else {
                if !at_a_x {
                    let here = out.last().map_or(a, |m| m.end);
                    out.push(mv(Kind::Rapid, [here[0], a[1]], n, c));
                }
                out.push(mv(Kind::Rapid, [iv[0], a[1]], n, c));
                out.push(mv(Kind::Rapid, [iv[0], x_prev + sx * retract], n, c));
                out.push(mv(Kind::Line(feed), [iv[0], x], n, c));
            }
            out.push(mv(Kind::Line(feed), [iv[1], x], n, c));
            // Back along Z by the retract, but not past the pocket's start (its near wall).
            let along = if first {
                retract
            } else {
                retract.min((iv[1] - iv[0]).abs())
            };
            let back = [iv[1] - sz * along, x + sx * retract];
            out.push(mv(Kind::Rapid, back, n, c));
            if first && i + 1 == ivs.len() {
                out.push(mv(Kind::Rapid, [a[0], x + sx * retract], n, c));
                at_a_x = false;
            } else {
                out.push(mv(Kind::Rapid, [back[0], a[1]], n, c));
                at_a_x = true;
            }
        }
        if at_a_x {
            out.push(mv(Kind::Rapid, [a[0], a[1]], n, c));
        }
        k += 1;
    }
    // The last pass along the profile with its allowances, then out and back to the start.
    out.push(mv(Kind::Rapid, [a[0], x1], n, c));
    out.push(mv(Kind::Rapid, segs[0].start, n, c));
    for s in &segs {
        out.push(*s);
    }
    way_out(&mut out, segs[segs.len() - 1].end, a, sx, n, c);
    Ok(moving(out, a))
}

/// A roughing cycle's way out from `e` back to its start `a` `[Z, X]`, the stock on side `sx`
/// of `a` across X: out to A's X (or stays at `e`'s X, if that is farther out), along Z to A's
/// Z, then to A. G71, G72 and G73 leave so; no such move crosses the stock.
fn way_out(out: &mut Vec<Mv>, e: [f64; 2], a: [f64; 2], sx: f64, n: u32, c: u32) {
    let x_out = if sx * (a[1] - e[1]) > 0.0 { a[1] } else { e[1] };
    out.push(mv(Kind::Rapid, [e[0], x_out], n, c));
    out.push(mv(Kind::Rapid, [a[0], x_out], n, c));
    out.push(mv(Kind::Rapid, a, n, c));
}

/// `out` from `a` without its moves to where the tool already stands: no standing still.
fn moving(mut out: Vec<Mv>, a: [f64; 2]) -> Vec<Mv> {
    let mut at = a;
    out.retain(|m| {
        let keep = (m.end[0] - at[0]).abs() > 1e-9 || (m.end[1] - at[1]).abs() > 1e-9;
        at = m.end;
        keep
    });
    out
}

/// The X of a segment's ends and of the extremes in X inside an arc's sweep.
fn extremes_x(s: &Mv) -> Vec<f64> {
    let mut v = vec![s.start[1], s.end[1]];
    if let Kind::Arc { c, ccw, .. } = s.kind {
        let rr = (s.start[0] - c[0]).hypot(s.start[1] - c[1]);
        let sw = sweep(s.start, s.end, c, ccw);
        let a0 = (s.start[1] - c[1]).atan2(s.start[0] - c[0]);
        for (q, x) in [(FRAC_PI_2, c[1] + rr), (3.0 * FRAC_PI_2, c[1] - rr)] {
            let d = if ccw { q - a0 } else { a0 - q }.rem_euclid(std::f64::consts::TAU);
            if d < sw {
                v.push(x);
            }
        }
    }
    v
}

/// The stretches `[from Z, to Z]` of the level X = `x`, in the profile's order, where the
/// profile lies below it (on the stock's side `sx`: there is stock to cut at the level). A
/// stretch shorter than a nanometre (the level touching a pocket's bottom) is left out.
fn below(segs: &[Mv], x: f64, sx: f64) -> Vec<[f64; 2]> {
    let under = |px: f64| sx * (x - px) > 1e-9;
    let mut out = Vec::new();
    let mut open = under(segs[0].start[1]).then_some(segs[0].start[0]);
    let mut toggle = |z: f64, open: &mut Option<f64>| match open.take() {
        Some(z0) => {
            if (z - z0).abs() > 1e-9 {
                out.push([z0, z]);
            }
        }
        None => *open = Some(z),
    };
    for s in segs {
        match s.kind {
            Kind::Arc { c, ccw, .. } => {
                let rr = (s.start[0] - c[0]).hypot(s.start[1] - c[1]);
                let v = (x - c[1]) / rr;
                if v.abs() < 1.0 {
                    let sw = sweep(s.start, s.end, c, ccw);
                    let a0 = (s.start[1] - c[1]).atan2(s.start[0] - c[0]);
                    let phi = v.asin();
                    let mut roots: Vec<(f64, f64)> = [phi, std::f64::consts::PI - phi]
                        .iter()
                        .map(|&q| {
                            let d =
                                if ccw { q - a0 } else { a0 - q }.rem_euclid(std::f64::consts::TAU);
                            (d, c[0] + rr * q.cos())
                        })
                        .filter(|&(d, _)| d > 1e-12 && d < sw - 1e-12)
                        .collect();
                    roots.sort_by(|p, q| p.0.total_cmp(&q.0));
                    for (_, z) in roots {
                        toggle(z, &mut open);
                    }
                }
                // The end's side decides (a root at the end, or a tangent counted twice).
                if open.is_some() != under(s.end[1]) {
                    toggle(s.end[0], &mut open);
                }
            }
            _ => {
                let (u0, u1) = (under(s.start[1]), under(s.end[1]));
                if u0 != u1 || open.is_some() != u1 {
                    let (f0, f1) = (sx * (x - s.start[1]), sx * (x - s.end[1]));
                    let t = if (f0 - f1).abs() < 1e-15 {
                        0.0
                    } else {
                        (f0 / (f0 - f1)).clamp(0.0, 1.0)
                    };
                    toggle(s.start[0] + t * (s.end[0] - s.start[0]), &mut open);
                }
            }
        }
    }
    if let Some(z0) = open {
        let z = segs[segs.len() - 1].end[0];
        if (z - z0).abs() > 1e-9 {
            out.push([z0, z]);
        }
    }
    out
}

/// Where the profile reaches the level X = `x`, its Z.
fn z_at(segs: &[Mv], x: f64, sx: f64) -> Option<f64> {
    for s in segs {
        let (x0, x1) = (s.start[1], s.end[1]);
        if sx * (x - x0) < -1e-12 || sx * (x1 - x) < -1e-12 {
            continue;
        }
        match s.kind {
            Kind::Arc { c, ccw, .. } => {
                let rr = (s.start[0] - c[0]).hypot(s.start[1] - c[1]);
                let h = (rr * rr - (x - c[1]).powi(2)).max(0.0).sqrt();
                let sw = sweep(s.start, s.end, c, ccw);
                let a0 = (s.start[1] - c[1]).atan2(s.start[0] - c[0]);
                let mut best: Option<(f64, f64)> = None;
                for z in [c[0] + h, c[0] - h] {
                    let a = (x - c[1]).atan2(z - c[0]);
                    let d = if ccw { a - a0 } else { a0 - a }.rem_euclid(std::f64::consts::TAU);
                    let miss = if d <= sw + 1e-9 {
                        0.0
                    } else {
                        (d - sw).min(std::f64::consts::TAU - d)
                    };
                    if best.is_none_or(|b| miss < b.1) {
                        best = Some((z, miss));
                    }
                }
                return best.map(|b| b.0);
            }
            _ => {
                if (x1 - x0).abs() < 1e-12 {
                    return Some(s.start[0]);
                }
                let t = (x - x0) / (x1 - x0);
                return Some(s.start[0] + t * (s.end[0] - s.start[0]));
            }
        }
    }
    None
}

/// Fanuc's two-block G76 (0i-T, "Multiple repetitive cycle: threading"), in Fanuc's dialect:
/// `G76 P(m)(r)(a) Q(Δdmin) R(d)` keeps the finishing passes m, the chamfer r (0.1 leads),
/// the tool angle a, the least cut Δdmin and the finishing allowance d; `G76 X(U) Z(W) R(i)
/// P(k) Q(Δd) F(L)` cuts the thread from where the tool stands to the root X at Z, with the
/// taper i, the height k (least increments), the first cut Δd and the lead L, in LinuxCNC's
/// passes (docs/lathe-gcode.md "G76, Fanuc's two-block form").
pub fn g76_fanuc(r: &mut Reader, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
    for l in ['J', 'H', 'E', 'L'] {
        if let Some(col) = w.col(l) {
            return Err(err(
                n,
                col,
                format!("G76 {l}: a word of LinuxCNC's one-block G76; in Fanuc's dialect G76 is Fanuc's two-block form (G76 P(m)(r)(a) Q R, then G76 X Z R P Q F) or its one-block form (G76 X Z I K D F A)"),
            ));
        }
    }
    let col = |l: char| w.col(l).unwrap_or(c);
    let whole = |v: f64| v.fract() == 0.0 && v.is_finite();
    let f = r.st.factor();
    // Fanuc's Series 15 form, a Haas's: one block, X Z I K D F A (P1).
    let one_block = ['I', 'K', 'D', 'A']
        .iter()
        .find_map(|&l| w.col(l).map(|c| (l, c)));
    let second = ['X', 'Z', 'U', 'W'].iter().any(|&l| w.get(l).is_some()) || one_block.is_some();
    if !second {
        refuse(w, "FDSHEL", n, "G76 P Q R (Fanuc's first block)")?;
        let mut g = r.st.g76.unwrap_or_default();
        if let Some(p) = w.get('P') {
            let (m, ch, a) = (
                (p / 10_000.0).floor(),
                ((p / 100.0).floor()) % 100.0,
                p % 100.0,
            );
            let ok = whole(p)
                && (0.0..=999_999.0).contains(&p)
                && (1.0..=99.0).contains(&m)
                && a <= 80.0;
            if !ok {
                return Err(err(
                    n,
                    col('P'),
                    format!(
                        "G76 P{}: six digits mmrraa: m the finishing passes 01 to 99, r the chamfer in tenths of the lead 00 to 99, a the tool's angle 00 to 80 (P021060)",
                        crate::input_text::short_number(p)
                    ),
                ));
            }
            g.m = m as u32;
            g.chamfer = ch / 10.0;
            g.angle = a;
        }
        if let Some(q) = w.get('Q').map(|q| r.in_increments('Q', q)) {
            if !(0.0..1000.0).contains(&q) {
                return Err(err(
                    n,
                    col('Q'),
                    "G76 Q, the least cut Δdmin, must not be negative",
                ));
            }
            g.step = q * f;
        }
        if let Some(d) = w.get('R') {
            if !(0.0..1000.0).contains(&d) {
                return Err(err(
                    n,
                    col('R'),
                    "G76 R, the finishing allowance d, must not be negative",
                ));
            }
            g.allowance = d * f;
        }
        r.st.g76 = Some(g);
        return Ok(());
    }
    let (g, taper, k, q, kl) = match one_block {
        Some(_) => g76_one_block(r, w, n, c)?,
        None => {
            refuse(w, "DSHEL", n, "G76 X Z R P Q F (Fanuc's second block)")?;
            let Some(g) = r.st.g76 else {
                return Err(err(
                    n,
                    c,
                    "G76 X Z needs Fanuc's first G76 block (G76 P(m)(r)(a) Q R) before it",
                ));
            };
            let taper = w.get('R').unwrap_or(0.0) * f;
            // P, the thread's height, in least increments whatever is written (Fanuc).
            let inc = if r.st.inch { 0.0001 } else { 0.001 };
            let p = need(w, 'P', n, c, "G76 (second block)")?;
            if !(whole(p) && p > 0.0 && p < 1e9) {
                return Err(err(
                    n,
                    col('P'),
                    format!(
                        "G76 P{}: the thread's height k, a whole number of least increments above 0 (P975 is 0.975 mm)",
                        crate::input_text::short_number(p)
                    ),
                ));
            }
            let k = p * inc * f;
            let q = r.in_increments('Q', need(w, 'Q', n, c, "G76 (second block)")?) * f;
            if !(q > 0.0 && q < 1000.0) {
                return Err(err(n, col('Q'), "G76 Q, the first cut Δd, must be above 0"));
            }
            (g, taper, k, q, 'P')
        }
    };
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            "G76 with nose-radius compensation in force: give G40 first",
        ));
    }
    if r.st.stopped() {
        return Err(err(n, c, "G76 with the spindle stopped: give M03 or M04"));
    }
    let start = r.out.pos;
    let end = r.target(w, n)?;
    if g.allowance >= k {
        return Err(err(
            n,
            col(kl),
            format!("G76 {kl}, the thread's height, must be greater than the finishing allowance (the first block's R)"),
        ));
    }
    let Some(lead) = r.st.feed.filter(|l| *l > 0.0 && *l <= 100.0) else {
        return Err(err(
            n,
            col('F'),
            "G76 needs F, the lead, above 0 and at most 100 mm",
        ));
    };
    if (end[0] - start[0]).abs() < 1e-9 {
        return Err(err(
            n,
            c,
            "G76 Z is where the tool stands: a thread needs a length",
        ));
    }
    // X is the root; the crest lies k beyond it, towards the start point.
    let outside = end[1] < start[1];
    let crest = if outside { end[1] + k } else { end[1] - k };
    let clear = if outside {
        start[1] - (crest + taper.max(0.0))
    } else {
        (crest + taper.min(0.0)) - start[1]
    };
    if clear <= 1e-9 || (end[1] - start[1]).abs() < 1e-9 {
        return Err(err(
            n,
            c,
            "G76: the start point must stand clear of the thread, beyond its crest (the root X less or more the height P)",
        ));
    }
    // M24 (a Haas's, and many a Fanuc lathe's): no chamfer out of the thread until M23.
    let chamfer = if r.st.no_chamfer {
        0.0
    } else {
        g.chamfer * lead
    };
    if chamfer >= (end[0] - start[0]).abs() {
        return Err(err(
            n,
            c,
            "G76: the chamfer (the first block's r, in tenths of the lead) is as long as the thread",
        ));
    }
    let Some(depths) = g76_depths(q, k, 2.0, g.m, g.step, g.allowance) else {
        return Err(err(
            n,
            c,
            format!("G76 makes more than {MAX_PASSES} passes: deepen Q or raise the least cut"),
        ));
    };
    let passes = Passes {
        start,
        z_end: end[0],
        crest: crest - start[1],
        depths,
        full: k,
        tan_q: (g.angle / 2.0).to_radians().tan(),
        lead,
        fanuc: true,
        taper,
        chamfer,
        taper_in: 0.0,
        taper_out: 0.0,
    };
    thread_passes(r, &passes, n, c)
}

/// G76's one-block form (Fanuc's Series 15 format, a Haas's) `G76 X(U) Z(W) I K D F A P1`: I
/// the taper (the second block's R), K the thread's height (P), D the first cut (Q), as
/// lengths in program units; A the tool's angle (the first block's a, in degrees as written);
/// P the way of cutting, 1 only (one edge, the same amount each pass, as the two-block form
/// cuts). The finishing passes, the chamfer, the least cut and the allowance are the last first
/// block's (`G76 P Q R`), else none: one finishing pass. The first block's state and its
/// taper, height and first cut, with the letter of the height for messages.
fn g76_one_block(
    r: &mut Reader,
    w: &Words,
    n: u32,
    c: u32,
) -> Result<(super::exec::FanucG76, f64, f64, f64, char), TranslateError> {
    let col = |l: char| w.col(l).unwrap_or(c);
    if let Some(q) = w.col('Q') {
        return Err(err(
            n,
            q,
            "G76 Q in the one-block form is the thread's start angle: novanc starts every pass at the spindle's index (give none)",
        ));
    }
    if let Some(r) = w.col('R') {
        return Err(err(
            n,
            r,
            "G76 R beside K or D: give the one-block form's I K D or the two-block form's R P Q",
        ));
    }
    if let Some(p) = w.get('P').filter(|&p| p != 1.0) {
        return Err(err(
            n,
            col('P'),
            format!(
                "G76 P{}: the way of cutting; novanc cuts with one edge, the same amount each pass (P1): P2, P3 and P4 are not modelled",
                crate::input_text::short_number(p)
            ),
        ));
    }
    let f = r.st.factor();
    let mut g = r.st.g76.unwrap_or_default();
    if let Some(a) = w.get('A') {
        let a = r.as_written('A', a);
        if !(0.0..=80.0).contains(&a) || a.fract() != 0.0 {
            return Err(err(
                n,
                col('A'),
                format!(
                    "G76 A{}: the tool's angle, whole degrees 0 to 80 (A60)",
                    crate::input_text::short_number(a)
                ),
            ));
        }
        g.angle = a;
    }
    let taper = w.get('I').unwrap_or(0.0) * f;
    let k = need(w, 'K', n, c, "G76 (one-block form)")? * f;
    if !(k > 0.0 && k < 1000.0) {
        return Err(err(
            n,
            col('K'),
            "G76 K, the thread's height, must be above 0",
        ));
    }
    let d = fanuc_length(r, 'D', need(w, 'D', n, c, "G76 (one-block form)")?) * f;
    if !(d > 0.0 && d < 1000.0) {
        return Err(err(n, col('D'), "G76 D, the first cut, must be above 0"));
    }
    Ok((g, taper, k, d, 'K'))
}

/// Fanuc's G code system A single cycles (0i-T, "Single repetitive cycle"): G90 turning,
/// G92 threading and G94 facing, each a box from where the tool stands to X(U) Z(W), R the
/// taper, its end and R kept for the lines after it that give X, Z, U or W.
pub fn single(r: &mut Reader, g: u32, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
    let name = match g {
        900 => "G90",
        920 => "G92",
        _ => "G94",
    };
    if r.in_cycle {
        return Err(err(n, c, format!("{name} inside a G70/G71 profile")));
    }
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            format!("{name} with nose-radius compensation in force: give G40 first"),
        ));
    }
    let s = r.out.pos;
    let mut e = r.target(w, n)?;
    let last = r.st.single;
    if let Some(l) = last {
        // What the line does not give is the cycle's last (Fanuc: X, Z and R are modal).
        if w.get('X').is_none() && w.get('U').is_none() {
            e[1] = l[1];
        }
        if w.get('Z').is_none() && w.get('W').is_none() {
            e[0] = l[0];
        }
    }
    let taper = match w.get('R') {
        Some(v) => v * r.st.factor(),
        None => last.map_or(0.0, |l| l[2]),
    };
    r.st.single = Some([e[0], e[1], taper]);
    if (e[0] - s[0]).abs() < 1e-9 || (e[1] - s[1]).abs() < 1e-9 {
        return Err(err(
            n,
            c,
            format!(
                "{name} ends where the tool stands in {}: the cycle needs a length in X and in Z",
                if (e[0] - s[0]).abs() < 1e-9 { 'Z' } else { 'X' }
            ),
        ));
    }
    let kind = if g == 920 {
        if r.st.stopped() {
            return Err(err(n, c, "G92 with the spindle stopped: give M03 or M04"));
        }
        match r.st.feed.filter(|l| *l > 0.0 && *l <= 100.0) {
            Some(lead) => Kind::Thread(lead),
            None => {
                return Err(err(
                    n,
                    w.col('F').unwrap_or(c),
                    "G92 needs F, the lead, above 0 and at most 100 mm",
                ))
            }
        }
    } else {
        Kind::Line(r.feed_in_force(n, c)?)
    };
    let moves = if g == 940 {
        // In along Z (to Z + R), down X, back along Z, out along X.
        [
            (Kind::Rapid, [e[0] + taper, s[1]]),
            (kind, e),
            (kind, [s[0], e[1]]),
            (Kind::Rapid, s),
        ]
    } else {
        // In along X (to X + R), the cut along Z, out along X (G92 rapid), back along Z.
        let out = if g == 920 { Kind::Rapid } else { kind };
        [
            (Kind::Rapid, [s[0], e[1] + taper]),
            (kind, e),
            (out, [e[0], s[1]]),
            (Kind::Rapid, s),
        ]
    };
    for (k, p) in moves {
        r.out.motion(mv(k, p, n, c))?;
    }
    Ok(())
}
