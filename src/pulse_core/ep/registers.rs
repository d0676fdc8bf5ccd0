//! The Pratt & Whitney interpolator's registers as pure logic (seed 001, lines 300–460):
//! the recirculation circuit 98 of one axis (residue register 96, adders 95 and 97, sign memory
//! 99 and interpolation pulse detector 101), the error magnitude comparator 93, the error gate
//! 94 as the iteration memory 87 opens it, and the feed-rate counter 81 with the weights of
//! Equation II. `docs/pulse-core.md` ("The error-proportional interpolator") gives the
//! reading of the patent and Table I rebuilt from this code.

/// Recirculation circuit 98 of one axis: the residue register 96 with its sign memory 99 and
/// interpolation pulse detector 101 (seed 001 lines 308–345).
///
/// Each recirculation cycle the gated error (0 when the error gate 94 is shut) is added in
/// adder 95, and L + E_m is applied in the bidirectional adder 97 with the sign opposite to
/// the one memory 99 holds (the sign of the number at the end of the previous cycle). The
/// number then swings round zero; two consecutive cycles ending with the same sign make a
/// command pulse in that sign's direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResidueRegister {
    /// The number RR in the circuit at the end of the last cycle.
    pub rr: i64,
    /// Sign memory 99: the number at the end of the last cycle was ≥ 0.
    pub positive: bool,
}

impl ResidueRegister {
    /// A register holding `rr` (memory 99 set by its sign).
    pub fn new(rr: i64) -> ResidueRegister {
        ResidueRegister {
            rr,
            positive: rr >= 0,
        }
    }

    /// One recirculation cycle with `gated` added in adder 95 (the axis error when gate 94
    /// is open, else 0) and `c` = L + E_m applied in adder 97: the command pulse detector
    /// 101 gives (−1, 0 or +1).
    #[inline(always)]
    pub fn cycle(&mut self, gated: i64, c: i64) -> i8 {
        let n = self.rr + gated + if self.positive { -c } else { c };
        let pos = n >= 0;
        let same = pos == self.positive;
        self.rr = n;
        self.positive = pos;
        // Two ends of the same sign: a pulse in that direction.
        (same as i8) * (2 * pos as i8 - 1)
    }

    /// Whether the number lies in the band where cycles without an error added only swing it
    /// round zero (no pulse possible): [0, c) after a positive end, [−c, 0) after a negative.
    #[inline(always)]
    pub fn in_band(&self, c: i64) -> bool {
        // [0, c) after a positive end; [−c, 0), i.e. −rr − 1 in [0, c), after a negative.
        let v = if self.positive { self.rr } else { -self.rr - 1 };
        v < c
    }

    /// Keeps a number that was inside the band of the old constant `c0` inside the band of the
    /// smaller `c` (after E_m fell): without this a number at the top of the old band would
    /// make a pulse with no error to send it (the one place the implementation departs from
    /// the hardware; docs/pulse-core.md). A number outside the old band (a pulse the last gate
    /// decided, still to come out) is left alone.
    #[inline(always)]
    pub fn clamp(&mut self, c0: i64, c: i64) {
        if self.positive {
            if self.rr >= c && self.rr < c0 {
                self.rr = c - 1;
            }
        } else if self.rr < -c && self.rr >= -c0 {
            self.rr = -c;
        }
    }

    /// Refers the number to a larger constant `c` (from `c0`, when the commanded point of an
    /// arc moves on and E_m grows): a number in the band keeps its place in it, the fraction
    /// u / C of a pulse (u = RR after a positive end, RR + C after a negative one); a number
    /// outside it (a pulse decided, still to come out) keeps what lies beyond the band, so the
    /// pulse still comes. Without it the next swing would add the larger C to a number the
    /// smaller one had put below zero, moving the axis's residue by up to a pulse at once
    /// (a reconstruction; docs/pulse-core.md, "Arcs by the chord and the perpendicular").
    pub fn rescale(&mut self, c0: i64, c: i64) {
        if c <= c0 || c0 <= 0 {
            return;
        }
        // u · c / c0 in 128 bits: arc registers count in 1/2¹⁶ pulse.
        let grow = c - c0;
        let scale = |u: i64| ((u as i128 * c as i128 + c0 as i128 / 2) / c0 as i128) as i64;
        if self.positive {
            if self.rr >= c0 {
                self.rr += grow;
            } else {
                self.rr = scale(self.rr).min(c - 1);
            }
        } else if self.rr < -c0 {
            self.rr -= grow;
        } else {
            self.rr = (scale(self.rr + c0) - c).clamp(-c, -1);
        }
    }

    /// The register of an arc's axis turning round to direction `dir` (±1), with constant `c`:
    /// the number keeps its place in the band, u / C (a number beyond the band is taken at its
    /// edge), but no nearer than a quarter of the band to the edge the new direction pulses
    /// across. After a pulse one way the number stands at the very edge for the other way;
    /// kept there, the axis would pulse back at once and forth again (chatter). Started again
    /// from the middle, as until 24 November, the tool lost up to half a pulse at every
    /// quadrant point (a reconstruction; docs/pulse-core.md).
    pub fn turned(self, c: i64, dir: i64) -> ResidueRegister {
        let u = if self.positive { self.rr } else { self.rr + c }.clamp(0, c - 1);
        let u = if dir > 0 {
            u.min(c - c / 4)
        } else {
            u.max(c / 4)
        };
        ResidueRegister::new(u)
    }

    /// `m` cycles with the gate shut from inside the band: the number swings, no pulse.
    #[inline(always)]
    pub fn swing(&mut self, m: u64, c: i64) {
        if m & 1 == 1 {
            self.rr += if self.positive { -c } else { c };
            self.positive = !self.positive;
        }
    }
}

/// Error magnitude comparator 93: the axes ranked by the magnitude of their error, largest
/// (G), middle (M), smallest (S); ties in X, Y, Z order.
#[inline]
pub fn rank(e: [i64; 3]) -> [usize; 3] {
    let m = [e[0].abs(), e[1].abs(), e[2].abs()];
    let mut r = [0usize, 1, 2];
    // Three elements: a stable insertion sort by decreasing magnitude.
    for i in 1..3 {
        let mut j = i;
        while j > 0 && m[r[j - 1]] < m[r[j]] {
            r.swap(j - 1, j);
            j -= 1;
        }
    }
    r
}

/// Weight of one feed-rate pulse f_p in the counter 81 (Equation II's 2.5 V_r, × 8).
pub const W_FEED: i32 = 20;
/// Weights of a command pulse of the largest, middle and smallest error on lines G, M and S
/// (Equation II: 2.5 : 1 : 0.75, × 8, which lands on stages 2–5 of the counter as the patent
/// says: G = 16 + 4, M = 8, S = 4 + 2).
pub const W_GMS: [i32; 3] = [20, 8, 6];

/// The feed-rate regulator 80: the bidirectional counter 81 and the iteration memory 87 that
/// opens the error gates (seed 001 lines 264–300).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct FeedCounter {
    /// The count (stage 1 = 1, stage 8 = 128).
    pub k: i32,
}

impl FeedCounter {
    /// A feed-rate pulse: counted up unless the four highest stages are full (gate 89).
    #[inline(always)]
    pub fn feed(&mut self, n: u64) {
        // In closed form: W_FEED at a time while the count is below 240.
        if n > 0 && self.k < 240 {
            let room = (240 - self.k) as u64;
            let steps = n.min(room.div_ceil(W_FEED as u64));
            self.k += W_FEED * steps as i32;
        }
    }

    /// A command pulse of the axis ranked `r` (0 = G, 1 = M, 2 = S) counts down.
    #[inline(always)]
    pub fn command(&mut self, r: usize) {
        self.k -= W_GMS[r];
    }

    /// Whether the iteration memory 87 opens the error gates in recirculation cycle `cycle`:
    /// every cycle with stage 8 set (k ≥ 128), every second with stage 7 (k ≥ 64), every
    /// fourth with stage 6 (k ≥ 32) (bf4, bf5, bf6).
    #[inline(always)]
    pub fn gate(&self, cycle: u64) -> bool {
        // Without short circuits: the count hovers about a stage, so branches would mispredict.
        (self.k >= 128) | ((self.k >= 64) & (cycle & 1 == 0)) | ((self.k >= 32) & (cycle & 3 == 0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seed 001 lines 320–345: RR = 5, L + E_m applied as 10, E_x = −6, the gate open every
    /// third cycle. The text's L = 8 and E_m = −6 do not make 10; Table I's column L reads 4
    /// (4 + 6 = 10), so the trace is reproduced with C = 10 (docs/pulse-core.md).
    #[test]
    fn the_patents_worked_trace_cycle_by_cycle() {
        let mut r = ResidueRegister::new(5);
        let (mut ex, l) = (-6i64, 4i64);
        let mut trace = vec![r.rr];
        let mut pulses = Vec::new();
        for cycle in 1..=5u64 {
            let gate = cycle % 3 == 0;
            let c = l + ex.abs();
            let p = r.cycle(if gate { ex } else { 0 }, c);
            trace.push(r.rr);
            if p != 0 {
                pulses.push((cycle, p));
                ex -= p as i64;
            }
            if cycle == 1 {
                assert!(r.rr == -5 && !r.positive, "cycle 1: 5 - 10 = -5");
            }
        }
        // 5 → −5 → +5 → −11 → −1 (a pulse, X negative), then with E_x = −5, L + E_m = 9:
        // −1 + 9 = 8 (Table I's fifth row).
        assert_eq!(trace, vec![5, -5, 5, -11, -1, 8]);
        assert_eq!(pulses, vec![(4, -1)]);
    }

    /// Table I goes on to cycle 26 with pulses at cycles 4, 9, 16 and 25 (line 373). With the
    /// error and L + E_m updated from the cycle after each pulse, this register gives the
    /// pulses of cycles 4, 9 and 16 as the text says, and the fourth at 21; the table's own
    /// rows 10, 17 and 26 apply the old L + E_m for one more cycle, while its row 5 does not
    /// (docs/pulse-core.md, Table I).
    #[test]
    fn table_one_continued() {
        let mut r = ResidueRegister::new(5);
        let (mut ex, l) = (-6i64, 4i64);
        let mut at = Vec::new();
        for cycle in 1..=26u64 {
            let p = r.cycle(if cycle % 3 == 0 { ex } else { 0 }, l + ex.abs());
            if p != 0 {
                at.push(cycle);
                ex -= p as i64;
            }
        }
        assert_eq!(at, vec![4, 9, 16, 21]);
        assert_eq!(ex, -2);
    }

    /// Table I rebuilt from this register (docs/pulse-core.md):
    /// `cargo test --lib table_one_printed -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn table_one_printed() {
        let mut r = ResidueRegister::new(5);
        let (mut ex, l) = (-6i64, 4i64);
        println!("| cycle | RR at the start | gate 94 | R ± E | (R ± E) ∓ (L + E_m) = RR at the end | E_x | L | L + E_m | pulse |");
        println!("|---|---|---|---|---|---|---|---|---|");
        for cycle in 1..=26u64 {
            let gate = cycle % 3 == 0;
            let c = l + ex.abs();
            let start = r.rr;
            let sign = if r.positive { "−" } else { "+" };
            let with_e = start + if gate { ex } else { 0 };
            let p = r.cycle(if gate { ex } else { 0 }, c);
            println!(
                "| {cycle} | {start} | {} | {} | {with_e} {sign} {c} = {} | {ex} | {l} | {c} | {} |",
                if gate { "open" } else { "" },
                if gate { format!("{start} {} {} = {with_e}", if ex < 0 { "−" } else { "+" }, ex.abs()) } else { String::new() },
                r.rr,
                match p {
                    1 => "+X",
                    -1 => "−X",
                    _ => "",
                }
            );
            if p != 0 {
                ex -= p as i64;
            }
        }
    }

    #[test]
    fn the_comparator_ranks_by_magnitude_ties_in_axis_order() {
        assert_eq!(rank([5, -9, 7]), [1, 2, 0]);
        assert_eq!(rank([3, 3, -3]), [0, 1, 2]);
        assert_eq!(rank([0, 0, 1]), [2, 0, 1]);
    }

    #[test]
    fn the_gate_opens_every_cycle_second_or_fourth_by_the_count() {
        let opens = |k: i32| (0..16).filter(|&c| FeedCounter { k }.gate(c)).count();
        assert_eq!(opens(200), 16);
        assert_eq!(opens(100), 8);
        assert_eq!(opens(40), 4);
        assert_eq!(opens(31), 0);
        let mut f = FeedCounter::default();
        f.feed(100);
        assert_eq!(f.k, 240, "the counter stops at the full top stages");
        f.command(0);
        f.command(2);
        assert_eq!(f.k, 240 - 26);
        // `feed` in closed form counts as one feed-rate pulse at a time would.
        for k in -60..260 {
            for n in 0..20u64 {
                let mut one = FeedCounter { k };
                for _ in 0..n {
                    if one.k < 240 {
                        one.k += W_FEED;
                    }
                }
                let mut f = FeedCounter { k };
                f.feed(n);
                assert_eq!(f, one, "k {k} n {n}");
            }
        }
    }

    /// `rescale` keeps a number in the band at its place (u / C) and one outside it the same
    /// distance beyond, so the pulse it decided still comes; a smaller C changes nothing.
    #[test]
    fn rescale_keeps_the_place_in_the_band() {
        // Positive end, u = 300 of 1000 -> 600 of 2000; the swings keep it there.
        let mut r = ResidueRegister::new(300);
        r.rescale(1000, 2000);
        assert_eq!(r, ResidueRegister::new(600));
        // Negative end: RR = -700 is u = 300 of 1000 -> u = 600 of 2000, RR = -1400.
        let mut r = ResidueRegister::new(-700);
        r.rescale(1000, 2000);
        assert_eq!(r, ResidueRegister::new(-1400));
        assert_eq!(r.cycle(0, 2000), 0, "a negative end swings up to u");
        assert_eq!(r.rr, 600);
        // Outside the band: 1100 after a positive end still makes its pulse next cycle.
        let mut r = ResidueRegister::new(1100);
        r.rescale(1000, 2000);
        assert_eq!(r.rr, 2100);
        assert_eq!(r.cycle(0, 2000), 1);
        let mut r = ResidueRegister::new(-1200);
        r.rescale(1000, 2000);
        assert_eq!(r.cycle(0, 2000), -1);
        let mut r = ResidueRegister::new(300);
        r.rescale(1000, 900);
        assert_eq!(r, ResidueRegister::new(300));
    }

    /// `turned` keeps the place in the band, a quarter of the band away from the edge the new
    /// direction pulses across.
    #[test]
    fn a_turn_keeps_the_place_but_not_the_edge() {
        // Just after a pulse upward (u = 10 of 1000), turning downward: u stays at the edge
        // below, so held at 250.
        let r = ResidueRegister {
            rr: -990,
            positive: false,
        };
        assert_eq!(r.turned(1000, -1), ResidueRegister::new(250));
        // The same number turning upward is far from that edge: kept.
        assert_eq!(r.turned(1000, 1), ResidueRegister::new(10));
        // In the middle, kept either way; near the top, held a quarter below it going up.
        assert_eq!(
            ResidueRegister::new(600).turned(1000, -1),
            ResidueRegister::new(600)
        );
        assert_eq!(
            ResidueRegister::new(990).turned(1000, 1),
            ResidueRegister::new(750)
        );
        // Beyond the band: taken at its edge.
        assert_eq!(
            ResidueRegister::new(1500).turned(1000, 1),
            ResidueRegister::new(750)
        );
        assert_eq!(
            ResidueRegister::new(-1500).turned(1000, -1),
            ResidueRegister::new(250)
        );
    }

    /// A run of shut cycles in closed form (`swing`) agrees with cycle-by-cycle stepping,
    /// from random states in the band.
    #[test]
    fn shut_cycles_in_closed_form_agree_with_single_cycles() {
        let mut rng = crate::pulse_core::testkit::Rng::new(7);
        for _ in 0..20_000 {
            let c = rng.range(2, 5000);
            let positive = rng.range(0, 1) == 1;
            let rr = if positive {
                rng.range(0, c - 1)
            } else {
                rng.range(-c, -1)
            };
            let r0 = ResidueRegister { rr, positive };
            let mut s = r0;
            let mut t = r0;
            let m = rng.range(0, 9) as u64;
            s.swing(m, c);
            for _ in 0..m {
                assert_eq!(t.cycle(0, c), 0);
            }
            assert_eq!(s, t);
        }
    }
}
