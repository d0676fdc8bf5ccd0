//! Arcs by the chord and perpendicular method of seed 001 (lines 604–706), with what the
//! missing page after line 706 must have held reconstructed (docs/pulse-core.md, "Arcs by the
//! chord and the perpendicular").
//!
//! From the patent: the errors E = (E_u, E_v) are the chord from the interpolated position T
//! to the commanded end C; h the perpendicular from the centre M to the chord; the tangent
//! velocity is V = E + A with A ⊥ E and |A| = |E|²/2h (Equations VI–IX). Circuit 130 (the
//! Z residue register 131 with sign memory 141) makes the ratio E/2h: each iteration (gate
//! opening) with its number ≥ 0 subtracts E_m, and the errors go straight to their own gates
//! (94x ← E_x, 94y ← E_y); with it negative, 2h_n is added and network 142 crosses the errors
//! (94x ← ±E_y, 94y ← ∓E_x, signed by the direction of rotation). So one crossed iteration
//! comes per 2h_n / E_m straight ones, and on average the gates add E + rot(E)·E_m/2h_n, the
//! tangent (E_m/2h_n = |E|/2h exactly, since h ⊥ E). 2h_n = |2(M_n − T_n) − E_n| is 2h's
//! coordinate across the larger error coordinate (Equations X, XI).
//!
//! Reconstructed: the sign of the crossing (outward from the centre: the chord turned
//! clockwise for a counter-clockwise arc); arcs are cut into pieces of at most 90° at points
//! on the circle (the chord method needs the centre on the inner side of the chord, and a
//! full circle has no chord), and the commanded point moves on to the next piece's end when
//! the chord has shrunk below a quarter of the radius, so the arc does not slow down at the joints;
//! only the last piece ends with the exponential tail, exactly on the end point. The feed
//! regulator's lines G and M go to the axis moving faster, the one across the larger radius
//! coordinate (comparator 124).

/// The largest ratio E_m / 2h_n applied (tan 63.4°).
const RHO_MAX: f64 = 2.0;

/// The arc registers count in 1/2^SHIFT pulse.
pub const SHIFT: u32 = 16;

/// The plan of one arc in its plane, turning-order axes (u → v counter-clockwise).
#[derive(Clone, Debug)]
pub struct ArcPlan {
    /// Machine axes of u and v.
    pub axes: [usize; 2],
    /// The centre M, machine coordinates of u and v.
    centre: [i64; 2],
    /// Counter-clockwise in (u, v).
    ccw: bool,
    /// The pieces' end points (u, v), the last one the block's end.
    targets: Vec<[i64; 2]>,
    /// How far each end point lies from the whole pulse it is rounded to (0 for the block's
    /// end): the tangent is aimed at the point on the circle, the pulses counted to the whole
    /// pulse.
    rounding: Vec<[f64; 2]>,
    /// The piece in force.
    piece: usize,
    /// (R / 4)², pulses²: a chord shorter than this moves the commanded point on.
    switch2: i64,
    /// A helix: the normal axis and its commanded coordinate at each piece's end.
    normal: Option<(usize, Vec<i64>)>,
    /// The normal axis's speed against the plane's, in the units of `speeds`.
    normal_speed: i64,
}

impl ArcPlan {
    /// The plan from `start` to `end` (u, v machine coordinates) about `centre`.
    /// A helix (reconstruction) adds `normal` = (axis, start, end): the normal axis's commanded
    /// point moves with the pieces, in proportion to their angle.
    pub fn new(
        axes: [usize; 2],
        start: [i64; 2],
        end: [i64; 2],
        centre: [i64; 2],
        ccw: bool,
        normal: Option<(usize, i64, i64)>,
    ) -> ArcPlan {
        use std::f64::consts::{FRAC_PI_2, TAU};
        let rel = |p: [i64; 2]| [(p[0] - centre[0]) as f64, (p[1] - centre[1]) as f64];
        let (s, e) = (rel(start), rel(end));
        let (r0, r1) = (s[0].hypot(s[1]), e[0].hypot(e[1]));
        let a0 = s[1].atan2(s[0]);
        let a1 = e[1].atan2(e[0]);
        let dir = if ccw { 1.0 } else { -1.0 };
        let mut sweep = ((a1 - a0) * dir).rem_euclid(TAU);
        if start == end || sweep < 1e-12 {
            sweep = TAU;
        }
        let n = (sweep / FRAC_PI_2).ceil().max(1.0) as usize;
        let mut targets = Vec::with_capacity(n);
        let mut rounding = Vec::with_capacity(n);
        for k in 1..n {
            let f = k as f64 / n as f64;
            let a = a0 + dir * sweep * f;
            let r = r0 + (r1 - r0) * f;
            let exact = [r * a.cos(), r * a.sin()];
            let whole = [exact[0].round(), exact[1].round()];
            targets.push([centre[0] + whole[0] as i64, centre[1] + whole[1] as i64]);
            rounding.push([exact[0] - whole[0], exact[1] - whole[1]]);
        }
        targets.push(end);
        rounding.push([0.0, 0.0]);
        let normal_speed = normal.map_or(0, |(_, z0, z1)| ((z1 - z0).abs() as f64 / sweep) as i64);
        let normal = normal.map(|(axis, z0, z1)| {
            let zs = (1..=n)
                .map(|k| z0 + ((z1 - z0) as f64 * k as f64 / n as f64).round() as i64)
                .collect();
            (axis, zs)
        });
        // A quarter of the radius: switching earlier (half the radius, 0.9 of it) left the
        // helices further from the circle (2.8, 3.6 pulses against 2.1).
        let quarter = (r0.min(r1) / 4.0) as i64;
        ArcPlan {
            axes,
            centre,
            ccw,
            targets,
            rounding,
            piece: 0,
            switch2: quarter * quarter,
            normal,
            normal_speed,
        }
    }

    /// The commanded point of the piece in force.
    pub fn target(&self) -> [i64; 2] {
        self.targets[self.piece]
    }

    /// Whether the piece in force is the last.
    pub fn last(&self) -> bool {
        self.piece + 1 == self.targets.len()
    }

    /// (R / 4)², pulses²: a chord shorter than this moves the commanded point on.
    pub fn switch2(&self) -> i64 {
        self.switch2
    }

    /// The normal axis of a helix.
    pub fn normal_axis(&self) -> Option<usize> {
        self.normal.as_ref().map(|n| n.0)
    }

    /// The normal axis's commanded point for the first piece (the start's for an arc).
    pub fn normal_target(&self) -> Option<i64> {
        self.normal.as_ref().map(|n| n.1[self.piece])
    }

    /// Moves the commanded point on to the next piece's end (the caller has seen the chord
    /// fall below `switch2` or to 0): how much the errors of u, v and the normal axis grow.
    pub fn advance(&mut self) -> Option<[i64; 3]> {
        if self.last() {
            return None;
        }
        let (a, b) = (self.targets[self.piece], self.targets[self.piece + 1]);
        let dz = self
            .normal
            .as_ref()
            .map_or(0, |n| n.1[self.piece + 1] - n.1[self.piece]);
        self.piece += 1;
        Some([b[0] - a[0], b[1] - a[1], dz])
    }

    /// One gate opening: the amounts to add in adders 95 of u and v for the chord `e`, in
    /// 1/2¹⁶ pulse, with `c` = L + E_m: (E + A) / (1 + ρ), A the chord turned outward (away
    /// from the centre) times ρ = E_m / 2h_n, 2h_n = |2(M_n − T_n) − E_n| across the larger
    /// error coordinate n (Equations VIII–XI). The patent's circuit 130 makes the ratio by
    /// crossing the errors in one gate opening out of 1 + 1/ρ, so a gate adds on average
    /// (E + ρ·rot E) / (1 + ρ), never more than E_m to an axis; here each gate carries that
    /// average (crossing whole gates made the registers chatter: pulses back and forth, a
    /// third more pulses than the arc needs, docs/pulse-core.md).
    ///
    /// The tangent is turned in by half the angle the gate's step turns on the circle, so the
    /// step runs along the secant to the circle rather than the tangent off it (a
    /// reconstruction: a step of s pulses along the tangent leaves the circle by s² / 2R, which
    /// the chord's pull back corrects only as the chord shortens; the tool stood up to 0.4
    /// pulses outside the circle on average in the middle of a piece).
    ///
    /// On a helix the normal axis's error E_z is gated times ρ / atan ρ (ρ = E_m / 2h_n, the
    /// tangent of half the angle left), so that it shrinks as the angle left does, not as the
    /// chord: the helix's pitch is kept along the piece (a reconstruction: the patent has no
    /// helices).
    #[inline]
    pub fn gated(&mut self, e: [i64; 3], c: i64) -> [i64; 3] {
        let t = self.target();
        let pos = [t[0] - e[0], t[1] - e[1]];
        let r = [
            (self.centre[0] - pos[0]) as f64,
            (self.centre[1] - pos[1]) as f64,
        ];
        // The chord to the point on the circle, not to the whole pulse the count ends on.
        let k = self.rounding[self.piece];
        let e = [e[0] as f64 + k[0], e[1] as f64 + k[1], e[2] as f64];
        let (au, av) = (e[0].abs(), e[1].abs());
        let em = au.max(av);
        let h2 = if au >= av {
            (2.0 * r[1] - e[1]).abs()
        } else {
            (2.0 * r[0] - e[0]).abs()
        };
        // ρ = tan(half the angle left) ≤ tan 60° on pieces of at most 90° moved on at a
        // quarter of the radius; the cap is a guard for radii of a few pulses, where rounding
        // can make h tiny.
        let rho = (em / h2.max(1.0)).min(RHO_MAX);
        let turned = if self.ccw {
            [e[1], -e[0]]
        } else {
            [-e[1], e[0]]
        };
        let one = (1i64 << SHIFT) as f64;
        // atan only for a helix's normal axis.
        let pitch = if e[2] != 0.0 && rho > 1e-9 {
            rho / rho.atan()
        } else {
            1.0
        };
        let share = 1.0 / (1.0 + rho);
        // The step of this gate, pulses, and the angle it turns on a circle of the tool's
        // radius: the secant's turn is half of it. tan(atan ρ − δ) = (ρ − tan δ)/(1 + ρ tan δ).
        let chord = e[0].hypot(e[1]);
        let step = chord * (1.0 + rho * rho).sqrt() * share / c.max(1) as f64;
        let radius = r[0].hypot(r[1]).max(1.0);
        let t = (step / radius / 2.0).tan();
        let rho = ((rho - t) / (1.0 + rho * t)).max(0.0);
        [
            ((e[0] + turned[0] * rho) * share * one).round() as i64,
            ((e[1] + turned[1] * rho) * share * one).round() as i64,
            (e[2] * pitch * share * one).round() as i64,
        ]
    }

    /// The speeds' magnitudes (u, v) as the radius gives them, for comparator 124: the axis
    /// across the larger radius coordinate moves faster.
    pub fn speeds(&self, e: [i64; 2]) -> [i64; 3] {
        let t = self.target();
        let r = [
            self.centre[0] - (t[0] - e[0]),
            self.centre[1] - (t[1] - e[1]),
        ];
        [r[1].abs(), r[0].abs(), self.normal_speed]
    }
}
