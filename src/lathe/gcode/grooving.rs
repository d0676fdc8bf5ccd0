//! Fanuc 0i-T's peck cycles (docs/lathe-gcode.md "G74 and G75"): G74 pecks along Z (end-face
//! grooving, or peck drilling on the centre line), G75 along X (grooving, or parting), each in
//! Fanuc's two-block form or in its one-block form with I, K and D (Fanuc's Series 15 format,
//! which a Haas writes). Fanuc's dialect only: LinuxCNC has neither.

use super::cycles::mv;
use super::exec::{err, Flow, Reader};
use super::out::Kind;
use super::MAX_STEPS;
use crate::block::TranslateError;
use crate::gcode::words::Words;

/// G74 (`g` 740) or G75 (750): the first block `G74 R(e)` sets the return after each peck; the
/// second, `G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F`, cuts from where the tool stands to the end
/// point. G74 cuts along Z in pecks of Δk, shifting X by Δi between grooves; G75 cuts along X
/// in pecks of Δi, shifting Z by Δk; after each peck but the last the tool rapids back e; at
/// the bottom of each groove it moves Δd away from the next one, then rapids back to the start
/// of the cut. The tool ends where it started. P and Q are in least increments, written
/// without a decimal point (0i-T: `P1000` is 1.000 mm), P as a radius.
///
/// The one-block form `G75 X(U) Z(W) I(Δi) K(Δk) D(Δd) F` (Fanuc's Series 15 format, a
/// Haas's) gives the same amounts as lengths in program units (`I0.005`): I for P, K for Q, D
/// for R; the return after each peck is the one a first block `G75 R(e)` set (none before
/// one).
pub fn g74_75(r: &mut Reader, w: &Words, n: u32, c: u32, g: u32) -> Result<Flow, TranslateError> {
    let name = format!("G{}", g / 10);
    if !r.fanuc {
        return Err(err(
            n,
            c,
            format!("{name} is Fanuc's peck cycle; LinuxCNC has none: read the program in the Fanuc dialect (`dialect fanuc`)"),
        ));
    }
    if r.out.comp_on() {
        return Err(err(
            n,
            c,
            format!("{name} with nose-radius compensation in force: give G40 first"),
        ));
    }
    for l in ['J', 'H', 'E', 'L'] {
        if let Some(col) = w.col(l) {
            return Err(err(n, col, format!("{name} takes no {l} word")));
        }
    }
    // The one-block form: I, K and D where the two-block form's second block has P, Q and R.
    let one_block = ['I', 'K', 'D']
        .iter()
        .find_map(|&l| w.col(l).map(|c| (l, c)));
    if let Some((l, _)) = one_block {
        if let Some((p, col)) = ['P', 'Q', 'R']
            .iter()
            .find_map(|&p| w.col(p).map(|c| (p, c)))
        {
            return Err(err(
                n,
                col,
                format!("{name} {p} beside {l}: give the one-block form's I, K and D or the two-block form's P, Q and R"),
            ));
        }
    }
    let f = r.st.factor();
    let axes = ['X', 'Z', 'U', 'W', 'P', 'Q']
        .iter()
        .any(|&l| w.get(l).is_some())
        || one_block.is_some();
    if !axes {
        // The first block: the return after each peck.
        let e = w.get('R').unwrap_or(0.0) * f;
        if !(0.0..=1000.0).contains(&e) {
            return Err(err(
                n,
                w.col('R').unwrap_or(c),
                format!("{name} R, the return after each peck, is 0 to 1000 mm"),
            ));
        }
        r.st.peck_return = e;
        return Ok(Flow::Next);
    }
    // P (Δi) is not read in increments by the reader (it is not a length elsewhere); Q (Δk) is.
    if r.written_with_point('P') || r.written_with_point('Q') {
        let l = if r.written_with_point('P') { 'P' } else { 'Q' };
        return Err(err(
            n,
            w.col(l).unwrap_or(c),
            format!("{name} {l}: in least increments, without a decimal point (P1000 is 1.000 mm)"),
        ));
    }
    let inc = r.increment();
    let (di, dk, relief) = if one_block.is_some() {
        // Lengths as any other: without a point, least increments (but with `decimal
        // calculator`); the one reader has scaled I and K so, as an arc's.
        let d = super::cycles::fanuc_length(r, 'D', w.get('D').unwrap_or(0.0));
        let v = |l: char| w.get(l).unwrap_or(0.0) * f;
        (v('I'), v('K'), d * f)
    } else {
        (
            w.get('P').unwrap_or(0.0) * inc * f,
            r.in_increments('Q', w.get('Q').unwrap_or(0.0)) * f,
            w.get('R').unwrap_or(0.0) * f,
        )
    };
    // The words that give each amount in the form used.
    let word = |two: char| match (one_block.is_some(), two) {
        (false, l) => l,
        (true, 'P') => 'I',
        (true, 'Q') => 'K',
        (true, _) => 'D',
    };
    if !(di.is_finite() && dk.is_finite() && di >= 0.0 && dk >= 0.0) {
        let l = word(if di.is_finite() && di >= 0.0 {
            'Q'
        } else {
            'P'
        });
        return Err(err(
            n,
            w.col(l).unwrap_or(c),
            format!("{name} {l}: an amount without a sign"),
        ));
    }
    if !(relief.is_finite() && relief.abs() <= 1000.0) {
        let l = word('R');
        return Err(err(
            n,
            w.col(l).unwrap_or(c),
            format!("{name} {l}: the relief at the bottom is at most 1000 mm"),
        ));
    }
    let start = r.out.pos;
    let end = r.target(w, n)?;
    let feed = r.feed_in_force(n, c)?;
    // [Z, X]: the axis cut along in pecks and the axis shifted between grooves.
    let (cut, shift, peck, step) = if g == 740 {
        (0, 1, dk, di)
    } else {
        (1, 0, di, dk)
    };
    let (peck_l, step_l) = if g == 740 { ('Q', 'P') } else { ('P', 'Q') };
    let (peck_l, step_l) = (word(peck_l), word(step_l));
    let depth = (end[cut] - start[cut]).abs();
    let width = (end[shift] - start[shift]).abs();
    if depth > 1e-9 && peck <= 0.0 {
        return Err(err(
            n,
            w.col(peck_l).unwrap_or(c),
            format!("{name} needs {peck_l}, the depth of each peck, above 0"),
        ));
    }
    if width > 1e-9 && step <= 0.0 {
        return Err(err(
            n,
            w.col(step_l).unwrap_or(c),
            format!("{name} needs {step_l}, the shift between grooves, above 0"),
        ));
    }
    let pecks = if depth > 1e-9 {
        (depth / peck).ceil()
    } else {
        1.0
    };
    let grooves = if width > 1e-9 {
        (width / step).ceil() + 1.0
    } else {
        1.0
    };
    if pecks * grooves * 3.0 > MAX_STEPS as f64 {
        return Err(err(
            n,
            c,
            format!(
                "{name} makes {} pecks, more than a program may have",
                pecks * grooves
            ),
        ));
    }
    let dir_cut = (end[cut] - start[cut]).signum();
    let dir_shift = (end[shift] - start[shift]).signum();
    let e = r.st.peck_return;
    let at = |a: f64, b: f64| -> [f64; 2] {
        let mut p = [0.0; 2];
        p[cut] = a;
        p[shift] = b;
        p
    };
    let grooves = grooves as usize;
    for i in 0..grooves {
        let s = if i + 1 == grooves {
            end[shift]
        } else {
            start[shift] + dir_shift * step * i as f64
        };
        if i > 0 {
            r.out.motion(mv(Kind::Rapid, at(start[cut], s), n, c))?;
        }
        let mut pos = start[cut];
        loop {
            let next = if (end[cut] - pos).abs() <= peck + 1e-9 {
                end[cut]
            } else {
                pos + dir_cut * peck
            };
            r.out.motion(mv(Kind::Line(feed), at(next, s), n, c))?;
            pos = next;
            if (end[cut] - pos).abs() < 1e-9 {
                break;
            }
            if e > 0.0 {
                r.out
                    .motion(mv(Kind::Rapid, at(pos - dir_cut * e, s), n, c))?;
            }
        }
        // The relief at the bottom, away from the next groove (back along the shift).
        let mut back = s;
        if relief != 0.0 && width > 1e-9 {
            back = s - dir_shift * relief.abs();
            r.out
                .motion(mv(Kind::Line(feed), at(end[cut], back), n, c))?;
        }
        r.out.motion(mv(Kind::Rapid, at(start[cut], back), n, c))?;
    }
    r.out.motion(mv(Kind::Rapid, start, n, c))?;
    Ok(Flow::Next)
}
