//! Plane geometry of the definitions (patent lines 307–309, subroutine AP02): lines, circles
//! and their intersections, with the XL/XS/YL/YS selector, on `nalgebra` vectors.
//!
//! Everything is in millimetres in the XY plane. Errors are plain messages; the translator adds
//! the line and column.

use super::parse::Sel;
use nalgebra::Vector2;

/// A 2-D vector or point, mm.
pub type V2 = Vector2<f64>;

/// Lengths closer than this are equal (mm): far below one pulse.
pub const EPS: f64 = 1e-9;

/// An infinite line through `p` with unit direction `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// A point on the line.
    pub p: V2,
    /// Unit direction.
    pub d: V2,
}

/// A circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Centre.
    pub c: V2,
    /// Radius, > 0.
    pub r: f64,
}

impl Line {
    /// The line through two distinct points.
    pub fn through(a: V2, b: V2) -> Result<Line, String> {
        let d = b - a;
        let n = d.norm();
        if n < EPS {
            return Err("the two points are the same; they do not define a line".to_string());
        }
        Ok(Line { p: a, d: d / n })
    }

    /// The line through `a` at `deg` degrees counter-clockwise from +X.
    pub fn at_angle(a: V2, deg: f64) -> Line {
        let t = deg.to_radians();
        Line {
            p: a,
            d: V2::new(t.cos(), t.sin()),
        }
    }
}

impl Circle {
    /// The circle about `c` with radius `r` (> 0).
    pub fn new(c: V2, r: f64) -> Result<Circle, String> {
        if r.is_nan() || r <= 0.0 {
            return Err(format!("the radius {r} must be greater than 0"));
        }
        Ok(Circle { c, r })
    }

    /// The circle through three points that are not on one line.
    pub fn through(a: V2, b: V2, c: V2) -> Result<Circle, String> {
        let (ab, ac) = (b - a, c - a);
        let det = 2.0 * (ab.x * ac.y - ab.y * ac.x);
        let scale = ab.norm().max(ac.norm()).max(1.0);
        if det.abs() < EPS * scale * scale {
            return Err(
                "the three points are on one line; no circle passes through them".to_string(),
            );
        }
        let (b2, c2) = (ab.norm_squared(), ac.norm_squared());
        let u = V2::new(ac.y * b2 - ab.y * c2, ab.x * c2 - ac.x * b2) / det;
        Ok(Circle {
            c: a + u,
            r: u.norm(),
        })
    }
}

/// 2-D cross product (z of the 3-D one).
pub fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Where two lines meet.
pub fn line_line(a: &Line, b: &Line) -> Result<V2, String> {
    let den = cross(a.d, b.d);
    if den.abs() < 1e-12 {
        return Err("the lines are parallel; they do not meet".to_string());
    }
    let t = cross(b.p - a.p, b.d) / den;
    Ok(a.p + a.d * t)
}

/// Picks one of two intersections by the selector. A tangent (one point) needs no choice.
pub fn select(pts: &[V2], sel: Sel) -> Result<V2, String> {
    match pts {
        [] => Err("they do not meet".to_string()),
        [p] => Ok(*p),
        [a, b, ..] => {
            let (ka, kb, axis) = match sel {
                Sel::Xl | Sel::Xs => (a.x, b.x, "X"),
                Sel::Yl | Sel::Ys => (a.y, b.y, "Y"),
            };
            if (ka - kb).abs() < EPS {
                let other = if axis == "X" { "YL or YS" } else { "XL or XS" };
                return Err(format!(
                    "both intersections have the same {axis}; choose with {other}"
                ));
            }
            let larger = matches!(sel, Sel::Xl | Sel::Yl);
            Ok(if (ka > kb) == larger { *a } else { *b })
        }
    }
}

/// Where a line meets a circle: none, one (tangent) or two points.
pub fn line_circle(l: &Line, c: &Circle) -> Vec<V2> {
    let foot_t = (c.c - l.p).dot(&l.d);
    let foot = l.p + l.d * foot_t;
    let dist = (c.c - foot).norm();
    let tol = EPS * c.r.max(1.0);
    if dist > c.r + tol {
        return Vec::new();
    }
    if (dist - c.r).abs() <= tol {
        return vec![foot];
    }
    let h = (c.r * c.r - dist * dist).sqrt();
    vec![foot - l.d * h, foot + l.d * h]
}

/// Where two circles meet: none, one (tangent) or two points.
pub fn circle_circle(a: &Circle, b: &Circle) -> Result<Vec<V2>, String> {
    let dv = b.c - a.c;
    let d = dv.norm();
    let tol = EPS * a.r.max(b.r).max(1.0);
    if d < tol {
        return Err("the circles are concentric; they do not meet in a point".to_string());
    }
    if d > a.r + b.r + tol || d < (a.r - b.r).abs() - tol {
        return Ok(Vec::new());
    }
    let u = dv / d;
    let x = (d * d + a.r * a.r - b.r * b.r) / (2.0 * d);
    let base = a.c + u * x;
    let h2 = a.r * a.r - x * x;
    if h2.max(0.0).sqrt() < 1e-7 * a.r.max(1.0) {
        return Ok(vec![base]);
    }
    let n = V2::new(-u.y, u.x) * h2.sqrt();
    Ok(vec![base + n, base - n])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    fn close(a: V2, b: V2) {
        assert!((a - b).norm() < 1e-9, "{a:?} != {b:?}");
    }

    #[test]
    fn line_line_meets_and_parallel_lines_do_not() {
        let a = Line::through(v(0.0, 0.0), v(10.0, 10.0)).unwrap();
        let b = Line::at_angle(v(10.0, 0.0), 90.0);
        close(line_line(&a, &b).unwrap(), v(10.0, 10.0));
        let c = Line::at_angle(v(0.0, 5.0), 45.0);
        assert!(line_line(&a, &c).unwrap_err().contains("parallel"));
        assert!(line_line(&a, &a).is_err());
        assert!(Line::through(v(1.0, 1.0), v(1.0, 1.0)).is_err());
    }

    #[test]
    fn line_circle_with_each_selector() {
        // The line y = x through a circle of radius 5 about (0, 0) meets it at ±(3.5355, 3.5355).
        let l = Line::through(v(-10.0, -10.0), v(10.0, 10.0)).unwrap();
        let c = Circle::new(v(0.0, 0.0), 5.0).unwrap();
        let pts = line_circle(&l, &c);
        let k = 5.0 / 2f64.sqrt();
        close(select(&pts, Sel::Xl).unwrap(), v(k, k));
        close(select(&pts, Sel::Yl).unwrap(), v(k, k));
        close(select(&pts, Sel::Xs).unwrap(), v(-k, -k));
        close(select(&pts, Sel::Ys).unwrap(), v(-k, -k));
        // A line of slope -1 separates the selectors: XL is the lower one.
        let m = Line::through(v(-10.0, 10.0), v(10.0, -10.0)).unwrap();
        let pts = line_circle(&m, &c);
        close(select(&pts, Sel::Xl).unwrap(), v(k, -k));
        close(select(&pts, Sel::Yl).unwrap(), v(-k, k));
        // A vertical line: both points have the same X, so XL is ambiguous.
        let vert = Line::at_angle(v(3.0, 0.0), 90.0);
        let pts = line_circle(&vert, &c);
        assert!(select(&pts, Sel::Xl).unwrap_err().contains("same X"));
        close(select(&pts, Sel::Ys).unwrap(), v(3.0, -4.0));
    }

    #[test]
    fn line_circle_tangent_and_missing() {
        let c = Circle::new(v(0.0, 0.0), 5.0).unwrap();
        let tangent = Line::at_angle(v(0.0, 5.0), 0.0);
        let pts = line_circle(&tangent, &c);
        assert_eq!(pts.len(), 1);
        close(select(&pts, Sel::Xs).unwrap(), v(0.0, 5.0));
        let away = Line::at_angle(v(0.0, 5.001), 0.0);
        assert!(select(&line_circle(&away, &c), Sel::Xl).is_err());
    }

    #[test]
    fn circle_circle_with_each_selector() {
        // Radii 5 and 5, centres 6 apart on X: they meet at (3, ±4).
        let a = Circle::new(v(0.0, 0.0), 5.0).unwrap();
        let b = Circle::new(v(6.0, 0.0), 5.0).unwrap();
        let pts = circle_circle(&a, &b).unwrap();
        close(select(&pts, Sel::Yl).unwrap(), v(3.0, 4.0));
        close(select(&pts, Sel::Ys).unwrap(), v(3.0, -4.0));
        assert!(select(&pts, Sel::Xl).is_err());
        // Centres 6 apart on Y: they meet at (±4, 3).
        let c = Circle::new(v(0.0, 6.0), 5.0).unwrap();
        let pts = circle_circle(&a, &c).unwrap();
        close(select(&pts, Sel::Xl).unwrap(), v(4.0, 3.0));
        close(select(&pts, Sel::Xs).unwrap(), v(-4.0, 3.0));
    }

    #[test]
    fn circle_circle_tangent_disjoint_and_concentric() {
        let a = Circle::new(v(0.0, 0.0), 5.0).unwrap();
        let outside = Circle::new(v(8.0, 0.0), 3.0).unwrap();
        let pts = circle_circle(&a, &outside).unwrap();
        assert_eq!(pts.len(), 1);
        close(pts[0], v(5.0, 0.0));
        let inside = Circle::new(v(2.0, 0.0), 3.0).unwrap();
        let pts = circle_circle(&a, &inside).unwrap();
        assert_eq!(pts.len(), 1);
        close(pts[0], v(5.0, 0.0));
        let far = Circle::new(v(20.0, 0.0), 3.0).unwrap();
        assert!(circle_circle(&a, &far).unwrap().is_empty());
        let within = Circle::new(v(1.0, 0.0), 1.0).unwrap();
        assert!(circle_circle(&a, &within).unwrap().is_empty());
        let conc = Circle::new(v(0.0, 0.0), 2.0).unwrap();
        assert!(circle_circle(&a, &conc).is_err());
    }

    #[test]
    fn circle_through_three_points() {
        let c = Circle::through(v(5.0, 0.0), v(0.0, 5.0), v(-5.0, 0.0)).unwrap();
        close(c.c, v(0.0, 0.0));
        assert!((c.r - 5.0).abs() < 1e-9);
        assert!(Circle::through(v(0.0, 0.0), v(1.0, 1.0), v(2.0, 2.0)).is_err());
        assert!(Circle::new(v(0.0, 0.0), 0.0).is_err());
    }
}
