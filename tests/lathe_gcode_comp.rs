//! Tool-nose radius compensation on the lathe (docs/lathe-gcode.md "Nose-radius
//! compensation"): a profile with a taper, a fillet, a convex arc and a shoulder, turned with a
//! 0.8 mm nose in every tip position. From the operations the path of P is sampled, the nose
//! centre C = P − R·v(tip) recovered with the chart written out here (not the reader's), and
//! the nose circle's envelope compared with the programmed profile.

use novanc::block::Motion;
use novanc::lathe::desc::{LatheDesc, ToolDesc};
use novanc::lathe::gcode::{read_program, ReadOptions};

const R: f64 = 0.8;
const TOL: f64 = 0.002;

/// Fanuc's chart, `[X, Z]` from C to P (docs/lathe-gcode.md).
fn chart(tip: u8) -> [f64; 2] {
    match tip {
        1 => [1.0, 1.0],
        2 => [1.0, -1.0],
        3 => [-1.0, -1.0],
        4 => [-1.0, 1.0],
        5 => [0.0, 1.0],
        6 => [1.0, 0.0],
        7 => [0.0, -1.0],
        8 => [-1.0, 0.0],
        _ => [0.0, 0.0],
    }
}

fn desc(tip: u8) -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
        c.tools = vec![ToolDesc {
            number: 1,
            radius: R,
            tip,
            offset: [0.0, 0.0],
        }];
    }
    d
}

/// A geometric piece, `[X, Z]` mm: a segment or an arc (centre, ccw from +Z towards +X).
#[derive(Clone, Copy, Debug)]
enum Piece {
    Seg([f64; 2], [f64; 2]),
    Arc([f64; 2], [f64; 2], [f64; 2], bool),
}

fn angle(p: [f64; 2], c: [f64; 2]) -> f64 {
    // Z is the first turning axis, X the second.
    (p[0] - c[0]).atan2(p[1] - c[1])
}

fn sweep_of(s: [f64; 2], e: [f64; 2], c: [f64; 2], ccw: bool) -> f64 {
    let d = if ccw {
        angle(e, c) - angle(s, c)
    } else {
        angle(s, c) - angle(e, c)
    };
    let d = d.rem_euclid(std::f64::consts::TAU);
    if d < 1e-12 {
        std::f64::consts::TAU
    } else {
        d
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

impl Piece {
    fn distance(&self, p: [f64; 2]) -> f64 {
        match *self {
            Piece::Seg(a, b) => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l2 = d[0] * d[0] + d[1] * d[1];
                let t = if l2 == 0.0 {
                    0.0
                } else {
                    (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
                };
                dist(p, [a[0] + t * d[0], a[1] + t * d[1]])
            }
            Piece::Arc(s, e, c, ccw) => {
                let r = dist(s, c);
                let sw = sweep_of(s, e, c, ccw);
                let d = if ccw {
                    angle(p, c) - angle(s, c)
                } else {
                    angle(s, c) - angle(p, c)
                };
                if d.rem_euclid(std::f64::consts::TAU) <= sw {
                    (dist(p, c) - r).abs()
                } else {
                    dist(p, s).min(dist(p, e))
                }
            }
        }
    }

    fn samples(&self, step: f64) -> Vec<[f64; 2]> {
        match *self {
            Piece::Seg(a, b) => {
                let n = ((dist(a, b) / step).ceil() as usize).max(1);
                (0..=n)
                    .map(|i| {
                        let t = i as f64 / n as f64;
                        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
                    })
                    .collect()
            }
            Piece::Arc(s, e, c, ccw) => {
                let r = dist(s, c);
                let sw = sweep_of(s, e, c, ccw);
                let n = ((r * sw / step).ceil() as usize).max(1);
                let a0 = angle(s, c);
                (0..=n)
                    .map(|i| {
                        let a = a0 + if ccw { 1.0 } else { -1.0 } * sw * i as f64 / n as f64;
                        [c[0] + r * a.sin(), c[1] + r * a.cos()]
                    })
                    .collect()
            }
        }
    }

    fn shifted(&self, v: [f64; 2]) -> Piece {
        let m = |p: [f64; 2]| [p[0] - v[0], p[1] - v[1]];
        match *self {
            Piece::Seg(a, b) => Piece::Seg(m(a), m(b)),
            Piece::Arc(s, e, c, ccw) => Piece::Arc(m(s), m(e), m(c), ccw),
        }
    }
}

/// The programmed profile, `[X radius, Z]`.
fn profile() -> Vec<Piece> {
    vec![
        Piece::Seg([5.0, 2.0], [5.0, 0.0]),
        Piece::Seg([5.0, 0.0], [10.0, -10.0]),
        Piece::Arc([10.0, -10.0], [15.0, -15.0], [15.0, -10.0], false),
        Piece::Arc([15.0, -15.0], [20.0, -20.0], [15.0, -20.0], true),
        Piece::Seg([20.0, -20.0], [20.0, -30.0]),
        Piece::Seg([20.0, -30.0], [25.0, -30.0]),
    ]
}

const PROGRAM: &str = "T0101\nM3 S1000\nG0 X30 Z5\n{SIDE} G0 X10 Z2\nG1 Z0 F100\nG1 X20 Z-10\nG2 X30 Z-15 R5\nG3 X40 Z-20 R5\nG1 Z-30\nG1 X50\nG40 G0 X60 Z-25\nM30\n";
/// The inside corners `[X, Z]` (the entry move's end against the first cut, the taper's
/// start, the shoulder): a round nose cannot reach into them, it leaves a fillet of its own
/// radius, so the profile within R of them is not checked against R (the centres are still
/// checked for coming too close).
const INSIDE: [[f64; 2]; 3] = [[5.0, 2.0], [5.0, 0.0], [20.0, -30.0]];
/// Lines of the profile moves (the cut): 5 to 10.
const CUT: std::ops::RangeInclusive<u32> = 5..=10;

/// The pieces of P's path from the operations, with each one's source line.
fn path(tip: u8, side: &str) -> Vec<(u32, Piece)> {
    let d = desc(tip);
    let text = PROGRAM.replace("{SIDE}", side);
    let p = match read_program(&text, &d, 0, &ReadOptions::default()) {
        Ok(p) => p,
        Err(e) => panic!("tip {tip} {side}: {e}"),
    };
    let mm = |q: [i64; 2]| [q[0] as f64 * d.pulse_mm, q[1] as f64 * d.pulse_mm];
    let mut at: Option<[f64; 2]> = None;
    let mut out = Vec::new();
    for b in p.iter().flat_map(|s| &s.blocks) {
        let end = [b.end[0], b.end[2]];
        let (end, piece) = match (b.motion, b.centre3()) {
            (Motion::Rapid | Motion::Linear, _) => (mm(end), at.map(|a| Piece::Seg(a, mm(end)))),
            (Motion::ArcCw | Motion::ArcCcw, Some(c)) => {
                let s = b.start();
                let centre = [s[0] + c[0], s[2] + c[2]];
                let ccw = b.motion == Motion::ArcCcw;
                (mm(end), at.map(|a| Piece::Arc(a, mm(end), mm(centre), ccw)))
            }
            _ => continue,
        };
        if let Some(pc) = piece {
            out.push((b.stmt, pc));
        }
        at = Some(end);
    }
    out
}

/// The envelope's worst errors: how far a profile point's nearest centre is from R, and how
/// much closer than R a centre on the cut comes to the profile.
fn envelope(tip: u8, side: &str, v: [f64; 2]) -> (f64, f64) {
    let shift = [R * v[0], R * v[1]];
    let centres: Vec<(u32, Piece)> = path(tip, side)
        .into_iter()
        .map(|(l, p)| (l, p.shifted(shift)))
        .collect();
    let prof = profile();
    let mut worst_far: f64 = 0.0;
    for pc in &prof {
        for q in pc.samples(0.01) {
            if INSIDE.iter().any(|&k| dist(k, q) < R) {
                continue;
            }
            let near = centres
                .iter()
                .map(|(_, c)| c.distance(q))
                .fold(f64::INFINITY, f64::min);
            worst_far = worst_far.max((near - R).abs());
        }
    }
    let mut worst_close: f64 = 0.0;
    for (l, c) in &centres {
        if !CUT.contains(l) {
            continue;
        }
        for q in c.samples(0.01) {
            let d = prof
                .iter()
                .map(|p| p.distance(q))
                .fold(f64::INFINITY, f64::min);
            worst_close = worst_close.max(R - d);
        }
    }
    (worst_far, worst_close)
}

#[test]
fn the_nose_envelope_is_the_profile_in_every_tip_position() {
    for tip in 0..=9u8 {
        let (far, close) = envelope(tip, "G42", chart(tip));
        assert!(
            far <= TOL && close <= TOL,
            "tip {tip}: profile to nose centre off R by {far:.4} mm, centre inside by {close:.4} mm"
        );
    }
}

#[test]
fn the_envelope_check_fails_on_the_wrong_side_or_a_wrong_chart() {
    for tip in [0u8, 3, 8] {
        let (far, close) = envelope(tip, "G41", chart(tip));
        assert!(
            far > 0.1 || close > 0.1,
            "tip {tip} G41 passed: {far} {close}"
        );
    }
    for tip in [1u8, 2, 3, 4, 5, 6, 7, 8] {
        let v = chart(tip);
        let (far, close) = envelope(tip, "G42", [-v[0], -v[1]]);
        assert!(far > 0.1 || close > 0.1, "tip {tip} negated chart passed");
    }
}

#[test]
fn a_tip_3_tool_turning_parallel_to_z_moves_p_on_the_profile() {
    // Imaginary tip: on a cut parallel to Z, P runs on the programmed diameter.
    let p = path(3, "G42");
    let on_z30 = p
        .iter()
        .filter(|(l, _)| *l == 9)
        .find_map(|(_, pc)| match pc {
            Piece::Seg(a, b) if (a[1] - b[1]).abs() > 5.0 => Some((a[0], b[0])),
            _ => None,
        });
    let Some((xa, xb)) = on_z30 else {
        panic!("no Z cut on line 9: {p:?}");
    };
    assert!(
        (xa - 20.0).abs() < 0.001 && (xb - 20.0).abs() < 0.001,
        "{xa} {xb}"
    );
}

/// An entry move straight into an inside corner (the Citizen's system 1: G42, then along Z on
/// the diameter, then out to a larger one): its end is where the line through its own end,
/// parallel to it, meets the next offset move, as LinuxCNC's convert_straight_comp2 takes it
/// (rs274 prints the same). Before stop 50 the reader crossed the next move with the line
/// from where the tool stood to the entry's end, one radius off: P ran 0.013 mm under the
/// diameter on the way in.
#[test]
fn an_entry_move_into_an_inside_corner_keeps_p_on_its_diameter() {
    let d = desc(3);
    let text = "T0101\nM3 S1000\nG8 G0 X7 Z1\nG42\nG1 Z-12 F100\nX9 Z-16\nZ-22\nG40 G0 X20\nM30\n";
    let p = match read_program(text, &d, 0, &ReadOptions::default()) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let entry: Vec<[i64; 2]> = p
        .iter()
        .filter(|s| s.line == 5)
        .flat_map(|s| &s.blocks)
        .map(|b| [b.start()[0], b.end[0]])
        .collect();
    assert_eq!(entry, [[7000, 7000]], "X along the entry, pulses");
}

/// The tool path as the kernel moves it: the same program run on one channel (the bar feeder
/// supplies the work at M10), P at every step of its pulses. Returns each step's source line
/// and position, mm. (Until issue 22 this was the lathe simulator's path, sampled at each
/// 100 µs tick: 48,321 samples on the cut, the envelope within 0.000663 mm of R and no centre
/// closer than R by more than 0.000698 mm in every tip position; G41 instead of G42 put the
/// nose in the work. The kernel's steps: 38,997 on the cut, within 0.000487 mm and 0.000498 mm.)
fn recorded(tip: u8, side: &str) -> Vec<(u32, [f64; 2])> {
    use novanc::pulse_core::Outcome;
    let mut d = desc(tip);
    d.channels.truncate(1);
    d.transfers.clear();
    d.supplier = 0;
    d.unloader = 0;
    let text = format!("M10\n{}", PROGRAM.replace("{SIDE}", side));
    let p = read_program(&text, &d, 0, &ReadOptions::default()).unwrap();
    let home = novanc::lathe::gcode::home(&d, 0);
    let start = [home[0], 0, home[1]];
    let mm = d.pulse_mm;
    let mut k = novanc::lathe::testkit::kernel(&d, vec![p], 1, None).unwrap();
    let m = k.machine_mut(0).unwrap();
    m.set_recording(None, true);
    m.set_audit(true);
    k.start(None).unwrap();
    let o = k.run_until_idle(3_600_000_000_000);
    assert!(matches!(o, Outcome::Finished { .. }), "tip {tip}: {o:?}");
    let m = k.machine_mut(0).unwrap();
    // The blocks that moved, in order: a step belongs to the block whose end it has not yet
    // reached (a line or an arc of less than a turn passes its end point once, at its end).
    let ends: Vec<(u32, [i64; 3])> = m
        .take_audit()
        .iter()
        .filter(|e| e.pos != e.start)
        .map(|e| (e.stmt, e.pos.xyz()))
        .collect();
    let mut i = 0;
    let mut out = Vec::new();
    for (_, pos) in novanc::pulse_core::testkit::steps(start, &m.take_pulses()) {
        let Some(&(stmt, end)) = ends.get(i) else {
            panic!("tip {tip}: a step after the last block's end");
        };
        // The program's lines are one further down for the M10 put in front.
        out.push((stmt - 1, [pos[0] as f64 * mm, pos[2] as f64 * mm]));
        if pos == end {
            i += 1;
        }
    }
    assert_eq!(i, ends.len(), "tip {tip}: every block's end reached");
    out
}

/// The recorded path's envelope: as `envelope`, with the nose centres taken from the samples.
fn recorded_envelope(tip: u8, side: &str) -> (f64, f64, usize) {
    let v = chart(tip);
    let centres: Vec<(u32, [f64; 2])> = recorded(tip, side)
        .into_iter()
        .map(|(l, p)| (l, [p[0] - R * v[0], p[1] - R * v[1]]))
        .collect();
    let cut: Vec<[f64; 2]> = centres
        .iter()
        .filter(|(l, _)| CUT.contains(l))
        .map(|c| c.1)
        .collect();
    let prof = profile();
    let mut far: f64 = 0.0;
    for pc in &prof {
        for q in pc.samples(0.01) {
            if INSIDE.iter().any(|&k| dist(k, q) < R) {
                continue;
            }
            // Every 8th sample (about a micrometre apart) is dense enough for the nearest.
            let near = cut
                .iter()
                .step_by(8)
                .map(|c| dist(*c, q))
                .fold(f64::INFINITY, f64::min);
            far = far.max((near - R).abs());
        }
    }
    let mut close: f64 = 0.0;
    for c in &cut {
        let d = prof
            .iter()
            .map(|p| p.distance(*c))
            .fold(f64::INFINITY, f64::min);
        close = close.max(R - d);
    }
    // The side: the work is below the profile (an outside turn), so between the face and the
    // shoulder a nose centre below the profile's X at its Z is in the material.
    let line: Vec<[f64; 2]> = prof.iter().flat_map(|p| p.samples(0.01)).collect();
    let profile_x = |z: f64| {
        line.iter()
            .filter(|q| (q[1] - z).abs() < 0.01)
            .map(|q| q[0])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let in_material = cut
        .iter()
        .filter(|c| c[1] < -0.1 && c[1] > -29.9 && c[0] < profile_x(c[1]) - TOL)
        .count();
    (
        far.max(if in_material > 0 { 1.0 } else { 0.0 }),
        close,
        cut.len(),
    )
}

#[test]
fn the_recorded_tool_path_envelope_is_the_profile_in_every_tip_position() {
    for tip in 0..=9u8 {
        let (far, close, n) = recorded_envelope(tip, "G42");
        eprintln!("tip {tip}: {n} steps on the cut, profile to nose centre off R by {far:.6} mm, centre inside by {close:.6} mm");
        assert!(n > 10_000, "tip {tip}: only {n} samples on the cut");
        assert!(
            far <= TOL && close <= TOL,
            "tip {tip}: recorded path: profile to nose centre off R by {far:.4} mm, centre inside by {close:.4} mm"
        );
    }
    // The same check on the wrong side fails: the nose would be in the work.
    let (far, close, _) = recorded_envelope(3, "G41");
    assert!(far > 0.1 || close > 0.1, "G41 passed: {far} {close}");
}

/// An arc as the entry move (LinuxCNC's convert_arc_comp1, read since stop 51; refused
/// before), with every tip: where the nose centre is not P, P first moves onto the entry arc's
/// start by a feed move R·v(tip) long; the arc is then an arc, ending one radius off the
/// programmed end, less than half a turn (LinuxCNC 2.9 cuts a full circle there), and the
/// nose centre then runs on the Z cut one radius off the programmed radius.
#[test]
fn an_arc_entry_moves_p_onto_the_arc_and_cuts_no_full_circle() {
    let text = "T0101\nM3 S1000\nG8 G0 X20 Z5\nG42 G2 X10 Z-2 R9 F100\nG1 Z-10\nG40 G0 X20\nM30\n";
    for tip in 0..=9u8 {
        let d = desc(tip);
        let p = match read_program(text, &d, 0, &ReadOptions::default()) {
            Ok(p) => p,
            Err(e) => panic!("tip {tip}: {e}"),
        };
        let mm = |q: i64| q as f64 * d.pulse_mm;
        let v = chart(tip);
        let entry: Vec<_> = p
            .iter()
            .filter(|s| s.line == 4)
            .flat_map(|s| &s.blocks)
            .collect();
        let arc = entry.last().expect("the entry arc");
        if v == [0.0, 0.0] {
            assert_eq!(entry.len(), 1, "tip {tip}: the arc alone");
        } else {
            assert_eq!(
                entry.len(),
                2,
                "tip {tip}: a feed move onto the arc, then the arc"
            );
            let first = entry[0];
            assert_eq!(first.motion, Motion::Linear, "tip {tip}");
            let (s, e) = (first.start(), first.end);
            let dx = mm(e[0] - s[0]);
            let dz = mm(e[2] - s[2]);
            assert!(
                (dx - R * v[0]).abs() < 0.0015 && (dz - R * v[1]).abs() < 0.0015,
                "tip {tip}: moved {dx} {dz}"
            );
        }
        assert!(
            matches!(arc.motion, Motion::ArcCw),
            "tip {tip}: {:?}",
            arc.motion
        );
        let c = arc.centre3().expect("centre");
        let s = arc.start();
        let r0 = mm(c[0]).hypot(mm(c[2]));
        let r1 = mm(s[0] + c[0] - arc.end[0]).hypot(mm(s[2] + c[2] - arc.end[2]));
        assert!((r0 - r1).abs() < 0.002, "tip {tip}: radius {r0} then {r1}");
        let chord = mm(arc.end[0] - s[0]).hypot(mm(arc.end[2] - s[2]));
        assert!(
            chord > 1.0 && r0 < 30.0,
            "tip {tip}: chord {chord}, radius {r0}"
        );
        // The nose centre on the Z cut (line 5): one radius outside X 10 (G8: a radius), G42.
        for b in p.iter().filter(|s| s.line == 5).flat_map(|s| &s.blocks) {
            let cx = mm(b.end[0]) - R * v[0];
            assert!(
                (cx - (10.0 + R)).abs() < 0.0015,
                "tip {tip}: centre at X {cx}"
            );
        }
    }
}
