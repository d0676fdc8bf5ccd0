//! Arc geometry as LinuxCNC 2.9 computes it (docs/gcode.md "Arcs"): the centre of an I J K or
//! R arc in the plane's turning order (X→Y for G17, Z→X for G18, Y→Z for G19), with the same
//! tolerances, so that novanc refuses what LinuxCNC refuses.

/// R arcs: how far the chord's half may exceed |R| (LinuxCNC's centre-arc radius tolerance),
/// mm and inches.
pub const R_TOLERANCE_MM: f64 = 0.00127;
/// The same in inches.
pub const R_TOLERANCE_INCH: f64 = 0.00005;

/// I J K arcs: LinuxCNC refuses an arc whose end radius differs from its start radius by more
/// than 100 × this, or by more than this and 0.1 % (measured on rs274 2.9), mm.
pub const IJK_ABS_TOLERANCE_MM: f64 = 0.028_284_3;
/// The same in inches.
pub const IJK_ABS_TOLERANCE_INCH: f64 = 0.002_828_43;
/// The relative part of the I J K tolerance.
pub const IJK_REL_TOLERANCE: f64 = 0.001;

/// novanc's own limit on an arc's radius difference, mm: its pulse core turns a spiral of up
/// to 30 pulses into the end radius (`pulse_core::arc::MAX_RADIUS_DIFF`); this leaves room for
/// rounding to pulses.
pub const NOVANC_RADIUS_DIFF_MM: f64 = 0.028;

/// Why an arc has no centre.
#[derive(Clone, Debug, PartialEq)]
pub enum ArcFault {
    /// R arc: the end point is farther than 2·|R| from the start.
    RTooSmall { half: f64, r: f64 },
    /// R arc: start and end are the same point.
    RFullCircle,
    /// I J K arc: the radius to the end differs from the radius to the start.
    NotOnCircle { r0: f64, r1: f64 },
    /// A radius of (almost) zero.
    ZeroRadius,
}

/// The centre of an R arc from `s` to `e` (turning order), `cw` for G02; `r` negative for an
/// arc over 180°. `tol` is the R tolerance in the program's units (as mm here: callers pass
/// the converted value).
pub fn centre_r(
    s: [f64; 2],
    e: [f64; 2],
    r: f64,
    cw: bool,
    tol: f64,
) -> Result<[f64; 2], ArcFault> {
    if s == e {
        return Err(ArcFault::RFullCircle);
    }
    let abs_r = r.abs();
    let mid = [(s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0];
    let mut half = (mid[0] - e[0]).hypot(mid[1] - e[1]);
    if half - abs_r > tol {
        return Err(ArcFault::RTooSmall { half, r: abs_r });
    }
    if abs_r == 0.0 {
        return Err(ArcFault::ZeroRadius);
    }
    if half / abs_r > 1.0 - 1e-12 {
        half = abs_r;
    }
    let base = (e[1] - s[1]).atan2(e[0] - s[0]);
    let theta = if (cw && r > 0.0) || (!cw && r < 0.0) {
        base - std::f64::consts::FRAC_PI_2
    } else {
        base + std::f64::consts::FRAC_PI_2
    };
    let turn2 = (half / abs_r).asin();
    let offset = abs_r * turn2.cos();
    Ok([mid[0] + offset * theta.cos(), mid[1] + offset * theta.sin()])
}

/// LinuxCNC's tolerances only: the start and end radii of an arc LinuxCNC cuts, as a spiral
/// where they differ (the milling interpreter cuts a wider one in pieces, `spiral_pieces`).
pub fn check_ijk_linuxcnc(
    s: [f64; 2],
    e: [f64; 2],
    c: [f64; 2],
    abs_tol: f64,
) -> Result<[f64; 2], ArcFault> {
    let r0 = (c[0] - s[0]).hypot(c[1] - s[1]);
    let r1 = (c[0] - e[0]).hypot(c[1] - e[1]);
    if r0 < 1e-4 || r1 < 1e-4 {
        return Err(ArcFault::ZeroRadius);
    }
    let abs_err = (r0 - r1).abs();
    let rel_err = abs_err / r0.max(r1);
    if abs_err > abs_tol * 100.0 || (rel_err > IJK_REL_TOLERANCE && abs_err > abs_tol) {
        return Err(ArcFault::NotOnCircle { r0, r1 });
    }
    Ok([r0, r1])
}

/// A spiral whose radius changes by more than this (mm) is cut in pieces: below
/// `NOVANC_RADIUS_DIFF_MM`, and off the round values that programs and LinuxCNC's tolerance
/// use, so that rs274's listing (4 decimals) tells on which side of it an arc is.
pub const SPIRAL_WHOLE_MM: f64 = 0.0265;

/// The most a piece of a spiral changes its radius, mm: below `NOVANC_RADIUS_DIFF_MM`, with
/// room for rounding the piece's ends and centre to pulses.
pub const SPIRAL_STEP_MM: f64 = 0.02;

/// How many arcs about the same centre cut a spiral from radius `r0` to `r1` sweeping `sweep`
/// radians: each changes the radius by at most `SPIRAL_STEP_MM` and turns by at most half a
/// turn (so that none is taken for a full circle). 1 when the pulse core turns it whole.
pub fn spiral_pieces(r0: f64, r1: f64, sweep: f64) -> u32 {
    let diff = (r1 - r0).abs();
    if diff <= SPIRAL_WHOLE_MM {
        return 1;
    }
    let by_radius = (diff / SPIRAL_STEP_MM).ceil();
    let by_angle = (sweep / std::f64::consts::PI).ceil();
    // The difference is bounded by LinuxCNC's tolerance (100 × 0.0718 mm at most), the
    // sweep by the turn count's limit.
    by_radius.max(by_angle).min(1e6) as u32
}

/// The angle an arc from `s` to `e` about `c` turns, counter-clockwise if `ccw` (radians, 0
/// to 2π; a full circle when they meet): both readers' (before stop 51 the lathe's had one of
/// its own).
pub fn sweep(s: [f64; 2], e: [f64; 2], c: [f64; 2], ccw: bool) -> f64 {
    let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
    let a1 = (e[1] - c[1]).atan2(e[0] - c[0]);
    let tau = 2.0 * std::f64::consts::PI;
    let mut d = if ccw { a1 - a0 } else { a0 - a1 };
    while d <= 1e-12 {
        d += tau;
    }
    while d > tau + 1e-12 {
        d -= tau;
    }
    d
}

/// The point a fraction `f` along LinuxCNC's spiral from `s` about `c` (its radius changing
/// from `s`'s to `r1` in proportion to the angle turned), turning `total` radians,
/// counter-clockwise if `ccw`: where a piece of it ends (`spiral_pieces`).
pub fn spiral_point(s: [f64; 2], c: [f64; 2], r1: f64, total: f64, ccw: bool, f: f64) -> [f64; 2] {
    let r0 = (s[0] - c[0]).hypot(s[1] - c[1]);
    let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
    let dir = if ccw { 1.0 } else { -1.0 };
    let a = a0 + dir * f * total;
    let r = r0 + f * (r1 - r0);
    [c[0] + r * a.cos(), c[1] + r * a.sin()]
}

/// The lead a thread block gives the kernel for a move of `d` (its amount on each axis) whose
/// lead LinuxCNC measures along its path: the kernel gears a thread block's longest axis to
/// the spindle (as a Fanuc measures G32's F), so it gets `lead` × longest / path. The mill's
/// G33, the lathe's G33 and the lathe's G76 taper ends in LinuxCNC's dialect.
pub fn lead_on_longest(lead: f64, d: &[f64]) -> f64 {
    let longest = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let path = d.iter().map(|v| v * v).sum::<f64>().sqrt();
    if path > 0.0 {
        lead * longest / path
    } else {
        lead
    }
}

/// The distance between two points of a plane.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The point `r` from `p` at angle `a` (radians, counter-clockwise from the first axis).
pub fn polar(p: [f64; 2], r: f64, a: f64) -> [f64; 2] {
    [p[0] + r * a.cos(), p[1] + r * a.sin()]
}

/// The angle (radians) of the direction from `from` to `to`.
pub fn angle(from: [f64; 2], to: [f64; 2]) -> f64 {
    (to[1] - from[1]).atan2(to[0] - from[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn r_arcs_choose_the_side_by_sign_and_direction() {
        let c = centre_r([0.0, 0.0], [10.0, 0.0], 5.0, true, 0.001).unwrap();
        assert!((c[0] - 5.0).abs() < 1e-9 && c[1].abs() < 1e-9);
        let c = centre_r([0.0, 0.0], [10.0, 10.0], 10.0, false, 0.001).unwrap();
        assert!((c[0]).abs() < 1e-9 && (c[1] - 10.0).abs() < 1e-9, "{c:?}");
        let c = centre_r([0.0, 0.0], [10.0, 10.0], -10.0, false, 0.001).unwrap();
        assert!((c[0] - 10.0).abs() < 1e-9 && c[1].abs() < 1e-9, "{c:?}");
        assert!(matches!(
            centre_r([0.0, 0.0], [10.0, 0.0], 4.99, true, 0.00127),
            Err(ArcFault::RTooSmall { .. })
        ));
    }

    #[test]
    fn ijk_tolerance_is_linuxcnc() {
        let ok = |e: f64, c: f64| {
            check_ijk_linuxcnc([0.0, 0.0], [e, 0.0], [c, 0.0], IJK_ABS_TOLERANCE_MM)
        };
        assert!(ok(20.001, 10.0).is_ok());
        assert!(ok(20.02, 10.0).is_ok());
        // Above the absolute tolerance and 0.1 %: refused.
        assert!(ok(20.03, 10.0).is_err());
        // Large radii: 0.1 % lets more through, for both readers to cut as a spiral in pieces
        // (`spiral_pieces`; the lathe's refused it before stop 51).
        assert_eq!(ok(2000.05, 1000.0), Ok([1000.0, 1000.05]));
    }

    #[test]
    fn a_spiral_point_turns_and_grows_in_proportion() {
        let c = [0.0, 0.0];
        let half = std::f64::consts::PI;
        let p = spiral_point([10.0, 0.0], c, 12.0, half, true, 0.5);
        assert!((p[0]).abs() < 1e-9 && (p[1] - 11.0).abs() < 1e-9, "{p:?}");
        let p = spiral_point([10.0, 0.0], c, 12.0, half, false, 0.5);
        assert!((p[0]).abs() < 1e-9 && (p[1] + 11.0).abs() < 1e-9, "{p:?}");
        assert!((sweep([10.0, 0.0], [0.0, 10.0], c, true) - half / 2.0).abs() < 1e-12);
        assert!((sweep([10.0, 0.0], [0.0, 10.0], c, false) - 1.5 * half).abs() < 1e-12);
        assert!((sweep([10.0, 0.0], [10.0, 0.0], c, true) - 2.0 * half).abs() < 1e-12);
    }

    #[test]
    fn a_spiral_is_cut_in_pieces_the_pulse_core_turns() {
        let half = std::f64::consts::PI;
        // Within what the core turns: whole.
        assert_eq!(spiral_pieces(100.0, 100.026, half), 1);
        // Each piece changes the radius by 0.02 mm at most...
        assert_eq!(spiral_pieces(100.0, 100.15, half), 8);
        assert_eq!(spiral_pieces(100.15, 100.0, half), 8);
        // ...and turns half a turn at most.
        assert_eq!(spiral_pieces(100.0, 100.03, 4.0 * half), 4);
    }
}
