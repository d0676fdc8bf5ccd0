//! The definition tables (patent Fig. 4 work areas: the point table n7–n8 and the DA table;
//! subroutines AP01–AP03, Fig. 11) and the resolution of designations against them.
//!
//! Every name is defined once: a second definition of the same name is an error, so a name
//! means the same thing wherever it is used, and a macro can keep what its names meant.

use super::geom::{self, Circle, Line, V2};
use super::mill::V3;
use super::parse::{CircleBy, Desig, LineBy, Name, PointExpr, Stmt};
use super::TranslateError;
use std::collections::HashMap;
use std::rc::Rc;

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

/// A resolved designation.
#[derive(Clone, Debug)]
pub enum Item {
    /// Selects this origin (machine coordinates) for the points that follow.
    Origin(V3),
    /// A point in part coordinates (relative to the origin in force).
    Point(V3, u32),
    /// Pattern holes, in machine coordinates (their own origin).
    Holes(Rc<[V3]>, u32),
    /// A circle in part coordinates, with the part z of its centre.
    Circle(Circle, f64, u32),
}

impl Item {
    fn with_col(&self, col: u32) -> Item {
        match self {
            Item::Origin(o) => Item::Origin(*o),
            Item::Point(p, _) => Item::Point(*p, col),
            Item::Holes(h, _) => Item::Holes(h.clone(), col),
            Item::Circle(c, z, _) => Item::Circle(*c, *z, col),
        }
    }
}

/// The point table, the DA table and the line, circle, pattern and macro definitions.
#[derive(Default)]
pub struct Tables {
    da: HashMap<u32, Def<V3>>,
    p: HashMap<u32, Def<V3>>,
    l: HashMap<u32, Def<Line>>,
    c: HashMap<u32, Def<(Circle, f64)>>,
    pat: HashMap<u32, Def<Rc<[V3]>>>,
    mac: HashMap<u32, Def<Rc<[Item]>>>,
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

    /// Computes a point expression (part coordinates).
    pub fn point(&self, e: &PointExpr, line: u32) -> Result<V3, TranslateError> {
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
                define(
                    &mut self.da,
                    "DA",
                    *name,
                    b + V3::new(v[0], v[1], v[2]),
                    line,
                    self.base,
                )
            }
            Stmt::Point { name, expr } => {
                let p = self.point(expr, line)?;
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
                if k.fract() != 0.0 || !(1.0..=10_000.0).contains(&k) {
                    return Err(err(
                        line,
                        kcol,
                        format!("NH{k}: a pattern has a whole number of holes from 1 to 10000"),
                    ));
                }
                if r.0.is_nan() || r.0 <= 0.0 {
                    return Err(err(
                        line,
                        r.1,
                        format!("the pattern radius R{} must be greater than 0", r.0),
                    ));
                }
                let step = ia.unwrap_or(360.0 / k);
                let holes: Vec<V3> = (0..k as usize)
                    .map(|i| {
                        let a = (sa + step * i as f64).to_radians();
                        origin + c + V3::new(r.0 * a.cos(), r.0 * a.sin(), 0.0)
                    })
                    .collect();
                define(&mut self.pat, "PAT", *name, holes.into(), line, self.base)
            }
            Stmt::Mac { name, items } => {
                let mut v = Vec::new();
                self.resolve(items, line, &mut v)?;
                define(&mut self.mac, "MAC", *name, v.into(), line, self.base)
            }
            _ => Ok(()),
        }
    }

    /// Resolves designations to items, defining inline points as it goes.
    pub fn resolve(
        &mut self,
        desigs: &[Desig],
        line: u32,
        out: &mut Vec<Item>,
    ) -> Result<(), TranslateError> {
        for d in desigs {
            match d {
                Desig::Da(n) => out.push(Item::Origin(self.origin(*n, line)?)),
                Desig::Point(n) => out.push(Item::Point(*get(&self.p, "P", *n, line)?, n.col)),
                Desig::Pat(n) => {
                    out.push(Item::Holes(get(&self.pat, "PAT", *n, line)?.clone(), n.col))
                }
                Desig::Circle(n) => {
                    let (c, z) = *get(&self.c, "C", *n, line)?;
                    out.push(Item::Circle(c, z, n.col));
                }
                Desig::Mac(n) => {
                    let items = get(&self.mac, "MAC", *n, line)?;
                    out.extend(items.iter().map(|i| i.with_col(n.col)));
                }
                Desig::Inline { expr, name, col } => {
                    let p = self.point(expr, line)?;
                    if let Some(n) = name {
                        define(&mut self.p, "P", *n, p, line, self.base)?;
                    }
                    out.push(Item::Point(p, *col));
                }
            }
        }
        Ok(())
    }
}
