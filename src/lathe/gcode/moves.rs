//! Moves (docs/lathe-gcode.md "Moves"): end points from X/U and Z/W in diameter or radius
//! mode, feeds, arcs by centre (I always a radius) or R, and G33 thread passes.

use super::exec::{err, Reader};
use super::out::{Feed, Kind, Mv};
use crate::block::TranslateError;
use crate::gcode::geom::{self, ArcFault};
use crate::gcode::words::Words;
use crate::input_text::fixed;

impl Reader<'_> {
    /// The end point of a move from X/U and Z/W, `[Z, X]` mm (X a radius), absolute X and Z
    /// from the program's zero (`State::origin`, moved by system A's G50 X Z).
    pub fn target(&self, w: &Words, n: u32) -> Result<[f64; 2], TranslateError> {
        let f = self.st.factor();
        let dia = if self.st.diameter { 2.0 } else { 1.0 };
        let mut p = self.out.pos;
        if let (Some(_), Some(c)) = (w.get('X'), w.col('U')) {
            return Err(err(
                n,
                c,
                "X and U on one line: give one (U is incremental X)",
            ));
        }
        if let (Some(_), Some(c)) = (w.get('Z'), w.col('W')) {
            return Err(err(
                n,
                c,
                "Z and W on one line: give one (W is incremental Z)",
            ));
        }
        if let Some(x) = w.get('X') {
            let v = x * f / dia;
            p[1] = if self.st.absolute {
                self.zero()[1] + v
            } else {
                p[1] + v
            };
        }
        if let Some(u) = w.get('U') {
            p[1] += u * f / dia;
        }
        if let Some(z) = w.get('Z') {
            let v = z * f;
            p[0] = if self.st.absolute {
                self.zero()[0] + v
            } else {
                p[0] + v
            };
        }
        if let Some(wv) = w.get('W') {
            p[0] += wv * f;
        }
        reasonable(p, n)?;
        Ok(p)
    }

    /// The feed in force for a feed move (refused without F, or per revolution with the
    /// spindle stopped).
    pub fn feed_in_force(&self, n: u32, c: u32) -> Result<Feed, TranslateError> {
        let Some(feed) = self.st.feed_of() else {
            return Err(err(n, c, "a feed move without a feed: give F"));
        };
        if self.st.per_rev && self.st.stopped() {
            return Err(err(
                n,
                c,
                format!(
                    "a feed per revolution ({}) with the spindle stopped: give M03 or M04",
                    self.out.feed_codes.1
                ),
            ));
        }
        Ok(feed)
    }

    /// Executes one move of mode `g` (×10) to the line's end point.
    pub fn motion(&mut self, g: u32, w: &Words, n: u32, c: u32) -> Result<(), TranslateError> {
        let end = self.target(w, n)?;
        let kind = match g {
            0 => Kind::Rapid,
            10 => Kind::Line(self.feed_in_force(n, c)?),
            20 | 30 => {
                let feed = self.feed_in_force(n, c)?;
                let ccw = g == 30;
                let f = self.st.factor();
                let s = self.out.pos;
                let centre = match (w.get('R'), w.get('I').is_some() || w.get('K').is_some()) {
                    (Some(_), true) => {
                        return Err(err(n, c, "an arc with both R and I/K: give one"));
                    }
                    (Some(r), false) => {
                        let tol = if self.st.inch {
                            geom::R_TOLERANCE_INCH * 25.4
                        } else {
                            geom::R_TOLERANCE_MM
                        };
                        geom::centre_r(s, end, r * f, !ccw, tol).map_err(|e| arc_err(e, n, c))?
                    }
                    (None, true) => {
                        let ctr = [
                            s[0] + w.get('K').unwrap_or(0.0) * f,
                            s[1] + w.get('I').unwrap_or(0.0) * f,
                        ];
                        let tol = if self.st.inch {
                            geom::IJK_ABS_TOLERANCE_INCH * 25.4
                        } else {
                            geom::IJK_ABS_TOLERANCE_MM
                        };
                        let [r0, r1] = geom::check_ijk_linuxcnc(s, end, ctr, tol)
                            .map_err(|e| arc_err(e, n, c))?;
                        // A spiral LinuxCNC reads (its end off its start's circle within
                        // LinuxCNC's tolerances) is cut in arcs about the same centre, each
                        // ending on it, as the mill's reader cuts one (docs/gcode.md "Arcs").
                        let total = geom::sweep(s, end, ctr, ccw);
                        let pieces = geom::spiral_pieces(r0, r1, total);
                        if pieces > 1 && self.out.comp_on() {
                            return Err(err(
                                n,
                                c,
                                format!(
                                    "a spiral (radius {} at the start, {} at the end) cannot be cut under nose-radius compensation",
                                    fixed(r0, 4),
                                    fixed(r1, 4)
                                ),
                            ));
                        }
                        let kind = Kind::Arc { c: ctr, ccw, feed };
                        for i in 1..pieces {
                            let f = f64::from(i) / f64::from(pieces);
                            let at = geom::spiral_point(s, ctr, r1, total, ccw, f);
                            let start = self.out.pos;
                            self.out.motion(Mv {
                                kind,
                                start,
                                end: at,
                                line: n,
                                col: c,
                            })?;
                        }
                        ctr
                    }
                    (None, false) => {
                        return Err(err(
                            n,
                            c,
                            "an arc needs its centre (I and K, I always a radius) or R",
                        ))
                    }
                };
                Kind::Arc {
                    c: centre,
                    ccw,
                    feed,
                }
            }
            _ => {
                // G33 (its K the lead) or Fanuc's G32 (the F in force the lead, modal, as
                // G76's and G92's: `G32 Z-20. F1.5` then `G32 Z-20.` cuts the same lead). In
                // Fanuc's dialect a G33 without K is Fanuc's: G code systems B and C name G32
                // G33, its F the lead.
                let by_f = g == 320 || (self.fanuc && w.get('K').is_none());
                let name = if g == 320 { "G32" } else { "G33" };
                let l = if by_f { 'F' } else { 'K' };
                let (given, lead) = if by_f {
                    let Some(lead) = self.st.feed else {
                        return Err(err(
                            n,
                            c,
                            format!("{name} needs F, the lead in mm per revolution"),
                        ));
                    };
                    (w.get('F').unwrap_or(lead), lead)
                } else {
                    let Some(k) = w.get('K') else {
                        return Err(err(n, c, "G33 needs K, the lead in mm per revolution (in Fanuc's dialect, F: `dialect fanuc`)"));
                    };
                    (k, k * self.st.factor())
                };
                if !(lead > 0.0 && lead <= 100.0) {
                    return Err(err(
                        n,
                        w.col(l).unwrap_or(c),
                        format!(
                            "{name} {l}{}: the lead must be above 0 and at most 100 mm",
                            crate::input_text::short_number(given)
                        ),
                    ));
                }
                if self.st.stopped() {
                    return Err(err(
                        n,
                        c,
                        format!("{name} with the spindle stopped: give M03 or M04"),
                    ));
                }
                let (dz, dx) = (end[0] - self.out.pos[0], end[1] - self.out.pos[1]);
                if dz.abs() < 1e-9 {
                    return Err(err(
                        n,
                        c,
                        format!("{name} needs a Z move ({l} is the lead along Z)"),
                    ));
                }
                // The kernel gears a taper's longest axis at the lead it is given, as a Fanuc
                // measures G32's F. LinuxCNC measures G33's K along the path (its planner's
                // spindle sync), so its K is given as the longest axis's share of it.
                if self.fanuc {
                    Kind::Thread(lead)
                } else {
                    Kind::Thread(geom::lead_on_longest(lead, &[dz, dx]))
                }
            }
        };
        self.out.motion(Mv {
            kind,
            start: self.out.pos,
            end,
            line: n,
            col: c,
        })
    }
}

/// An end point `[Z, X]` mm within a million mm, or the refusal of line `n`.
pub(super) fn reasonable(p: [f64; 2], n: u32) -> Result<(), TranslateError> {
    if p[0].is_finite() && p[1].is_finite() && p[0].abs() < 1e6 && p[1].abs() < 1e6 {
        Ok(())
    } else {
        Err(err(n, 1, "the end point is not a reasonable number"))
    }
}

fn arc_err(e: ArcFault, n: u32, c: u32) -> TranslateError {
    let m = match e {
        ArcFault::RTooSmall { half, r } => format!(
            "R {} is too small: the end point is {} mm away, more than 2·R",
            fixed(r, 4),
            fixed(2.0 * half, 4)
        ),
        ArcFault::RFullCircle => "an R arc cannot end where it starts".to_string(),
        ArcFault::NotOnCircle { r0, r1 } => format!(
            "the end point is not on the arc: radius {} at the start, {} at the end",
            fixed(r0, 4),
            fixed(r1, 4)
        ),
        ArcFault::ZeroRadius => "the arc's radius is zero".to_string(),
    };
    err(n, c, m)
}
