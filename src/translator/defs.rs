//! The definition tables (patent Fig. 4 work areas: the point table n7–n8 and the DA table;
//! subroutines AP01–AP03, Fig. 11) and the resolution of designations against them.
//!
//! Every name is defined once: a second definition of the same name is an error, so a name
//! means the same thing wherever it is used, and a macro can keep what its names meant.
//!
//! The work is bounded (docs/language.md, *Limits*): a pattern keeps its parameters, not its
//! holes, and a macro keeps its own list, naming the macros in it rather than copying them, so
//! a definition costs memory in proportion to its text. What a designation list stands for is
//! counted (without expanding it) against `MAX_DESIGNATIONS` when a macro or a statement is
//! read, and computed points must lie within `MAX_COORD_MM`.

use super::geom::{self, Circle, Line, V2};
use super::mill::V3;
use super::parse::{CircleBy, Desig, LineBy, Name, PointExpr, Stmt};
use super::TranslateError;
use std::collections::HashMap;

/// The most points and origins one statement or macro may stand for, counted as if written
/// out: a `PAT` counts its holes and a `MAC` everything it stands for.
pub const MAX_DESIGNATIONS: u64 = 100_000;

/// The most holes of a pattern (`NH`).
pub const MAX_HOLES: u32 = 10_000;

/// The largest coordinate a definition may compute, mm (relative points and origins add up,
/// intersections of nearly parallel lines lie far away); beyond it is an error, so positions
/// stay far inside the range of whole pulses.
pub const MAX_COORD_MM: f64 = 1e12;

/// Two holes of a pattern closer than this, mm, fall on the same spot.
pub const SAME_SPOT_MM: f64 = 0.001;

/// A definition and the line that made it.
#[derive(Clone, Debug)]
pub struct Def<T> {
    /// The value.
    pub v: T,
    /// The source line of the definition.
    pub line: u32,
    /// Defined by program memory for an MDI translation: the MDI text may define the name
    /// again (its own definition then stands).
    pub base: bool,
}

/// A bolt-hole pattern: `k` holes on a circle, worked out where it is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pattern {
    /// The centre in machine coordinates (the pattern's origin plus its centre point).
    pub centre: V3,
    /// Radius, mm.
    pub r: f64,
    /// Angle of the first hole, degrees counter-clockwise from +X.
    pub sa: f64,
    /// Angle from one hole to the next, degrees.
    pub step: f64,
    /// Number of holes.
    pub k: u32,
}

impl Pattern {
    /// Hole `i` (from 0), machine coordinates.
    pub fn hole(&self, i: u32) -> V3 {
        let a = (self.sa + self.step * f64::from(i)).to_radians();
        self.centre + V3::new(self.r * a.cos(), self.r * a.sin(), 0.0)
    }
}

/// A resolved designation.
#[derive(Clone, Debug)]
pub enum Item {
    /// Selects this origin (machine coordinates) for the points that follow.
    Origin(V3),
    /// A point in part coordinates (relative to the origin in force).
    Point(V3, u32),
    /// Pattern holes, in machine coordinates (their own origin).
    Holes(Pattern, u32),
    /// A circle in part coordinates, with the part z of its centre.
    Circle(Circle, f64, u32),
    /// A macro (its index in the macro list), standing for its items where it is used.
    Macro(usize, u32),
}

/// A macro's resolved list and how many points and origins it stands for.
#[derive(Clone, Debug)]
struct Macro {
    items: Vec<Item>,
    count: u64,
}

/// The point table, the DA table and the line, circle, pattern and macro definitions.
#[derive(Default)]
pub struct Tables {
    da: HashMap<u32, Def<V3>>,
    p: HashMap<u32, Def<V3>>,
    l: HashMap<u32, Def<Line>>,
    c: HashMap<u32, Def<(Circle, f64)>>,
    pat: HashMap<u32, Def<Pattern>>,
    mac: HashMap<u32, Def<usize>>,
    macros: Vec<Macro>,
    /// Definitions made now are program memory's, for MDI (see [`Def::base`]).
    base: bool,
}

fn err(line: u32, col: u32, message: String) -> TranslateError {
    TranslateError { line, col, message }
}

fn get<'a, T>(
    map: &'a HashMap<u32, Def<T>>,
    kw: &str,
    name: Name,
    line: u32,
) -> Result<&'a T, TranslateError> {
    map.get(&name.n).map(|d| &d.v).ok_or_else(|| {
        err(
            line,
            name.col,
            format!(
                "{kw}{} is not defined (define it on an earlier line)",
                name.n
            ),
        )
    })
}

fn define<T>(
    map: &mut HashMap<u32, Def<T>>,
    kw: &str,
    name: Name,
    v: T,
    line: u32,
    base: bool,
) -> Result<(), TranslateError> {
    if let Some(d) = map.get(&name.n).filter(|d| !d.base || base) {
        return Err(err(
            line,
            name.col,
            format!(
                "{kw}{} is already defined on line {}; a name can be defined only once",
                name.n, d.line
            ),
        ));
    }
    map.insert(name.n, Def { v, line, base });
    Ok(())
}

fn v2(p: &V3) -> V2 {
    V2::new(p.x, p.y)
}

/// A computed point or origin, if every coordinate is a number within `MAX_COORD_MM`.
fn bounded(v: V3, line: u32, col: u32) -> Result<V3, TranslateError> {
    if v.iter().all(|x| x.abs() <= MAX_COORD_MM) {
        return Ok(v);
    }
    Err(err(
        line,
        col,
        format!(
            "this point lies too far away ({:.0}, {:.0}, {:.0}); computed coordinates go up to {MAX_COORD_MM:e} mm",
            v.x, v.y, v.z
        ),
    ))
}

/// The column of a designation.
fn desig_col(d: &Desig) -> u32 {
    match d {
        Desig::Da(n) | Desig::Point(n) | Desig::Pat(n) | Desig::Mac(n) | Desig::Circle(n) => n.col,
        Desig::Inline { col, .. } => *col,
    }
}

/// Checks that no two holes of a pattern fall on the same spot (`IA0`, or an `IA` that comes
/// round a whole turn, or a radius too small to set the holes apart): the error is the message.
///
/// Holes i and i + d are `2 R |sin(π ‖d·x‖)|` apart, x = IA/360 and ‖·‖ the distance to the
/// nearest whole number. Over d < NH the smallest ‖d·x‖ is reached at a denominator of a
/// continued-fraction convergent of x (best approximation), and the first convergent whose
/// holes meet is the smallest such d; so a few dozen steps check any NH.
fn distinct_holes(k: u32, r: f64, step: f64) -> Result<(), String> {
    let x = (step / 360.0).rem_euclid(1.0);
    let apart = |d: u64| {
        let t = d as f64 * x;
        2.0 * r * (std::f64::consts::PI * (t - t.round()).abs()).sin()
    };
    // Denominators of the convergents: q(n) = a(n) q(n-1) + q(n-2), from q(-1) = 0, q(0) = 1.
    let (mut q_prev, mut q) = (0u64, 1u64);
    let mut rest = x;
    for _ in 0..64 {
        if q >= u64::from(k) {
            break;
        }
        if apart(q) < SAME_SPOT_MM {
            let why = if x == 0.0 {
                format!("IA{step} does not move on round the circle")
            } else if (q as f64 * x - (q as f64 * x).round()).abs() < 1e-9 {
                format!("{q} steps of IA{step} make a whole number of turns")
            } else {
                format!("the radius R{r} is too small to set them {SAME_SPOT_MM} mm apart")
            };
            return Err(format!(
                "holes 1 and {} of the pattern fall on the same spot: {why}; a pattern drills each hole once",
                q + 1
            ));
        }
        if rest < 1e-12 {
            break;
        }
        let t = 1.0 / rest;
        let a = t.floor();
        rest = t - a;
        if a >= 1e12 {
            break;
        }
        (q_prev, q) = (q, (a as u64).saturating_mul(q).saturating_add(q_prev));
    }
    Ok(())
}

impl Tables {
    /// From now on, definitions are program memory's, defined for an MDI translation (`on`),
    /// or the text's own.
    pub fn set_base(&mut self, on: bool) {
        self.base = on;
    }

    /// The origin DAn.
    pub fn origin(&self, name: Name, line: u32) -> Result<V3, TranslateError> {
        get(&self.da, "DA", name, line).copied()
    }

    /// Computes a point expression (part coordinates); `col` is where an error is charged.
    pub fn point(&self, e: &PointExpr, line: u32, col: u32) -> Result<V3, TranslateError> {
        bounded(self.point_unchecked(e, line)?, line, col)
    }

    fn point_unchecked(&self, e: &PointExpr, line: u32) -> Result<V3, TranslateError> {
        match e {
            PointExpr::Coords(v) => Ok(V3::new(v[0], v[1], v[2])),
            PointExpr::Rel { base, d } => {
                Ok(get(&self.p, "P", *base, line)? + V3::new(d[0], d[1], d[2]))
            }
            PointExpr::LineLine { a, b } => {
                let la = get(&self.l, "L", *a, line)?;
                let lb = get(&self.l, "L", *b, line)?;
                let q = geom::line_line(la, lb)
                    .map_err(|m| err(line, a.col, format!("L{} and L{}: {m}", a.n, b.n)))?;
                Ok(V3::new(q.x, q.y, 0.0))
            }
            PointExpr::LineCircle { l, c, sel } => {
                let ln = get(&self.l, "L", *l, line)?;
                let (ci, _) = get(&self.c, "C", *c, line)?;
                let pts = geom::line_circle(ln, ci);
                let col = l.col.min(c.col);
                let q = geom::select(&pts, *sel)
                    .map_err(|m| err(line, col, format!("L{} and C{}: {m}", l.n, c.n)))?;
                Ok(V3::new(q.x, q.y, 0.0))
            }
            PointExpr::CircleCircle { a, b, sel } => {
                let (ca, _) = get(&self.c, "C", *a, line)?;
                let (cb, _) = get(&self.c, "C", *b, line)?;
                let what = |m: String| err(line, a.col, format!("C{} and C{}: {m}", a.n, b.n));
                let pts = geom::circle_circle(ca, cb).map_err(what)?;
                let q = geom::select(&pts, *sel).map_err(what)?;
                Ok(V3::new(q.x, q.y, 0.0))
            }
        }
    }

    /// Carries out a definition statement (DA, P, L, C, PAT, MAC).
    pub fn define(&mut self, stmt: &Stmt, line: u32) -> Result<(), TranslateError> {
        match stmt {
            Stmt::Da { name, base, v } => {
                let b = match base {
                    Some(m) => self.origin(*m, line)?,
                    None => V3::zeros(),
                };
                let o = bounded(b + V3::new(v[0], v[1], v[2]), line, name.col)?;
                define(&mut self.da, "DA", *name, o, line, self.base)
            }
            Stmt::Point { name, expr } => {
                let p = self.point(expr, line, name.col)?;
                define(&mut self.p, "P", *name, p, line, self.base)
            }
            Stmt::Line { name, a, by } => {
                let pa = v2(get(&self.p, "P", *a, line)?);
                let l = match by {
                    LineBy::Angle(deg) => Line::at_angle(pa, *deg),
                    LineBy::Point(b) => {
                        let pb = v2(get(&self.p, "P", *b, line)?);
                        Line::through(pa, pb).map_err(|m| err(line, b.col, m))?
                    }
                };
                define(&mut self.l, "L", *name, l, line, self.base)
            }
            Stmt::Circle { name, c, by } => {
                let pc = *get(&self.p, "P", *c, line)?;
                let ci = match by {
                    CircleBy::Radius(r, col) => {
                        Circle::new(v2(&pc), *r).map_err(|m| err(line, *col, m))?
                    }
                    CircleBy::Through(b, d) => {
                        let pb = v2(get(&self.p, "P", *b, line)?);
                        let pd = v2(get(&self.p, "P", *d, line)?);
                        Circle::through(v2(&pc), pb, pd).map_err(|m| err(line, c.col, m))?
                    }
                };
                if ci.r > MAX_COORD_MM {
                    return Err(err(
                        line,
                        c.col,
                        format!(
                            "the circle's radius {:.0} is too large (up to {MAX_COORD_MM:e} mm)",
                            ci.r
                        ),
                    ));
                }
                define(&mut self.c, "C", *name, (ci, pc.z), line, self.base)
            }
            Stmt::Pat {
                name,
                da,
                nh,
                centre,
                r,
                sa,
                ia,
            } => {
                let origin = match da {
                    Some(d) => self.origin(*d, line)?,
                    None => V3::zeros(),
                };
                let c = *get(&self.p, "P", *centre, line)?;
                let (k, kcol) = *nh;
                if k.fract() != 0.0 || !(1.0..=f64::from(MAX_HOLES)).contains(&k) {
                    return Err(err(
                        line,
                        kcol,
                        format!(
                            "NH{k}: a pattern has a whole number of holes from 1 to {MAX_HOLES}"
                        ),
                    ));
                }
                if r.0.is_nan() || r.0 <= 0.0 {
                    return Err(err(
                        line,
                        r.1,
                        format!("the pattern radius R{} must be greater than 0", r.0),
                    ));
                }
                let k = k as u32;
                let step = ia.map_or(360.0 / f64::from(k), |(a, _)| a);
                let col = ia.map_or(r.1, |(_, c)| c);
                distinct_holes(k, r.0, step).map_err(|m| err(line, col, m))?;
                let pat = Pattern {
                    centre: bounded(origin + c, line, centre.col)?,
                    r: r.0,
                    sa: *sa,
                    step,
                    k,
                };
                define(&mut self.pat, "PAT", *name, pat, line, self.base)
            }
            Stmt::Mac { name, items } => {
                let mut v = Vec::new();
                let count = self.resolve(items, line, &mut v)?;
                self.macros.push(Macro { items: v, count });
                define(
                    &mut self.mac,
                    "MAC",
                    *name,
                    self.macros.len() - 1,
                    line,
                    self.base,
                )
            }
            _ => Ok(()),
        }
    }

    /// How many points and origins an item stands for.
    fn count(&self, it: &Item) -> u64 {
        match it {
            Item::Holes(p, _) => u64::from(p.k),
            Item::Macro(i, _) => self.macros.get(*i).map_or(0, |m| m.count),
            _ => 1,
        }
    }

    /// Resolves designations to items, defining inline points as it goes; returns how many
    /// points and origins they stand for, which may not pass `MAX_DESIGNATIONS` (the error is
    /// charged to the designation that passes it). Macros stay macros: see [`Tables::each`].
    pub fn resolve(
        &mut self,
        desigs: &[Desig],
        line: u32,
        out: &mut Vec<Item>,
    ) -> Result<u64, TranslateError> {
        let mut total = 0u64;
        for d in desigs {
            let it = match d {
                Desig::Da(n) => Item::Origin(self.origin(*n, line)?),
                Desig::Point(n) => Item::Point(*get(&self.p, "P", *n, line)?, n.col),
                Desig::Pat(n) => Item::Holes(*get(&self.pat, "PAT", *n, line)?, n.col),
                Desig::Circle(n) => {
                    let (c, z) = *get(&self.c, "C", *n, line)?;
                    Item::Circle(c, z, n.col)
                }
                Desig::Mac(n) => Item::Macro(*get(&self.mac, "MAC", *n, line)?, n.col),
                Desig::Inline { expr, name, col } => {
                    let p = self.point(expr, line, *col)?;
                    if let Some(n) = name {
                        define(&mut self.p, "P", *n, p, line, self.base)?;
                    }
                    Item::Point(p, *col)
                }
            };
            total += self.count(&it);
            if total > MAX_DESIGNATIONS {
                return Err(err(
                    line,
                    desig_col(d),
                    format!(
                        "the designations come to {total} points and origins here, more than the {MAX_DESIGNATIONS} a statement or macro may stand for (a PAT counts its holes, a MAC all it stands for); split the work over several statements"
                    ),
                ));
            }
            out.push(it);
        }
        Ok(total)
    }

    /// Calls `f` for every point, origin, pattern and circle `items` stand for, in order, with
    /// the macros written out (without recursion, so any depth of macros is safe). An item
    /// from a macro is charged to the column of the outermost `MAC` that brought it.
    pub fn each<E>(
        &self,
        items: &[Item],
        mut f: impl FnMut(&Item, u32) -> Result<(), E>,
    ) -> Result<(), E> {
        // (list, next index, the column of the outermost MAC if inside one)
        let mut stack: Vec<(&[Item], usize, Option<u32>)> = vec![(items, 0, None)];
        while let Some(top) = stack.last_mut() {
            let (list, i, outer) = (top.0, top.1, top.2);
            let Some(it) = list.get(i) else {
                stack.pop();
                continue;
            };
            top.1 += 1;
            match it {
                Item::Macro(m, col) => {
                    if let Some(mac) = self.macros.get(*m) {
                        stack.push((&mac.items, 0, Some(outer.unwrap_or(*col))));
                    }
                }
                Item::Origin(_) => f(it, outer.unwrap_or(1))?,
                Item::Point(_, c) | Item::Holes(_, c) | Item::Circle(_, _, c) => {
                    f(it, outer.unwrap_or(*c))?
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first d in 1..k whose holes meet, by trying every d.
    fn brute(k: u32, r: f64, step: f64) -> Option<u32> {
        (1..k).find(|&d| {
            let half = (step * f64::from(d) / 2.0).to_radians();
            2.0 * r * half.sin().abs() < SAME_SPOT_MM
        })
    }

    fn holes_of(e: &str) -> u32 {
        let rest = e.strip_prefix("holes 1 and ").unwrap_or("");
        rest.split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or(0)
    }

    #[test]
    fn the_continued_fraction_check_agrees_with_trying_every_pair() {
        let mut rng = crate::pulse_core::testkit::Rng::new(7);
        let mut next = || rng.next_u64();
        let mut refused = 0;
        for _ in 0..20_000 {
            let k = 2 + (next() % 400) as u32;
            let step = match next() % 4 {
                0 => (next() % 1441) as f64 - 720.0,
                1 => ((next() % 72_001) as f64 - 36_000.0) / 100.0,
                2 => 360.0 / (1 + next() % 50) as f64 * (1 + next() % 7) as f64,
                _ => (next() % 1_000_000) as f64 / 1000.0,
            };
            let r = [0.0002, 0.01, 1.0, 65.0, 500.0][(next() % 5) as usize];
            let want = brute(k, r, step);
            let got = distinct_holes(k, r, step).err().map(|e| holes_of(&e) - 1);
            assert_eq!(got, want, "NH{k} R{r} IA{step}");
            refused += usize::from(want.is_some());
        }
        assert!(refused > 1000, "{refused}");
    }
}
