//! The typed form of a statement, as the parser produces it (patent Table 1: definitions 1–9,
//! cutting statements 11–15, modifiers 111–120). Names are not yet resolved.

/// A reference to a numbered definition (`P3`, `DA1`) and where it was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Name {
    /// The number after the keyword.
    pub n: u32,
    /// 1-based column of the keyword.
    pub col: u32,
}

/// Which of two intersections to take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sel {
    /// Larger X.
    Xl,
    /// Smaller X.
    Xs,
    /// Larger Y.
    Yl,
    /// Smaller Y.
    Ys,
}

/// The right-hand side of a point definition.
#[derive(Clone, Debug, PartialEq)]
pub enum PointExpr {
    /// `(x, y[, z])`, part coordinates.
    Coords([f64; 3]),
    /// `Pm(dx, dy[, dz])`, relative to point m.
    Rel {
        /// Point m.
        base: Name,
        /// The offset (dx, dy, dz).
        d: [f64; 3],
    },
    /// `La, Lb`.
    LineLine {
        /// The first line.
        a: Name,
        /// The second line.
        b: Name,
    },
    /// `La, Cb, SEL` (or `Cb, La, SEL`).
    LineCircle {
        /// The line.
        l: Name,
        /// The circle.
        c: Name,
        /// Which intersection.
        sel: Sel,
    },
    /// `Ca, Cb, SEL`.
    CircleCircle {
        /// The first circle.
        a: Name,
        /// The second circle.
        b: Name,
        /// Which intersection.
        sel: Sel,
    },
}

/// A designation in a cutting statement or a macro.
#[derive(Clone, Debug, PartialEq)]
pub enum Desig {
    /// `DAn`: the origin for the points that follow.
    Da(Name),
    /// `Pn`.
    Point(Name),
    /// `PATn`.
    Pat(Name),
    /// `MACn`.
    Mac(Name),
    /// `Cn` (a full circle, MIL only).
    Circle(Name),
    /// `(expr[=Pn])`: an inline point, named if `=Pn` is given.
    Inline {
        /// Where the point is.
        expr: PointExpr,
        /// The name it is defined under, if any.
        name: Option<Name>,
        /// Column of the opening parenthesis.
        col: u32,
    },
}

/// The second part of a line definition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LineBy {
    /// `Ln = Pa, Pb`.
    Point(Name),
    /// `Ln = Pa, A<deg>`.
    Angle(f64),
}

/// The second part of a circle definition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CircleBy {
    /// `Cn = Pa, R<r>` (with the column of R).
    Radius(f64, u32),
    /// `Cn = Pa, Pb, Pc`: through three points.
    Through(Name, Name),
}

/// The five cycles (Table 1, numbers 11–15).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleKind {
    /// DRL, drilling.
    Drl,
    /// TAP, tapping.
    Tap,
    /// REM, reaming.
    Rem,
    /// MIL, milling.
    Mil,
    /// BOR, boring.
    Bor,
}

impl CycleKind {
    /// The keyword.
    pub fn word(self) -> &'static str {
        match self {
            CycleKind::Drl => "DRL",
            CycleKind::Tap => "TAP",
            CycleKind::Rem => "REM",
            CycleKind::Mil => "MIL",
            CycleKind::Bor => "BOR",
        }
    }
}

/// A modifier value and the column of its keyword.
pub type Valued = Option<(f64, u32)>;

/// The modifiers of a cutting statement (Table 1, numbers 111–120).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mods {
    /// RGT (column).
    pub rgt: Option<u32>,
    /// LFT (column).
    pub lft: Option<u32>,
    /// DP effective depth.
    pub dp: Valued,
    /// DI chamfer diameter.
    pub di: Valued,
    /// FR feed rate.
    pub fr: Valued,
    /// SS spindle speed.
    pub ss: Valued,
    /// SCL clearance.
    pub scl: Valued,
    /// SDP rapid-feed depth; the inner None is `SDP` with no value (the tool's normal depth).
    pub sdp: Option<(Option<f64>, u32)>,
    /// DW dwell, seconds.
    pub dw: Valued,
    /// DH peck step.
    pub dh: Valued,
}

/// A cutting statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// Which cycle.
    pub kind: CycleKind,
    /// Tool number and its column.
    pub tool: (u32, u32),
    /// The modifiers.
    pub mods: Mods,
    /// The designations, in order.
    pub desigs: Vec<Desig>,
}

/// One parsed statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `DAn = (x,y,z)` or `DAn = DAm, (dx,dy,dz)`.
    Da {
        /// The origin defined.
        name: Name,
        /// The origin it is relative to, if any.
        base: Option<Name>,
        /// The coordinates (or offsets).
        v: [f64; 3],
    },
    /// `Pn = ...`.
    Point {
        /// The point defined.
        name: Name,
        /// Where it is.
        expr: PointExpr,
    },
    /// `Ln = Pa, ...`.
    Line {
        /// The line defined.
        name: Name,
        /// The point it passes through.
        a: Name,
        /// A second point or an angle.
        by: LineBy,
    },
    /// `Cn = Pa, ...`.
    Circle {
        /// The circle defined.
        name: Name,
        /// The centre, or the first of three points.
        c: Name,
        /// A radius or two more points.
        by: CircleBy,
    },
    /// `PATn = DAm, NHk, Pc, Rr, SAa, IAi`.
    Pat {
        /// The pattern defined.
        name: Name,
        /// Its origin, if given.
        da: Option<Name>,
        /// NH, the number of holes (with its column).
        nh: (f64, u32),
        /// P, the centre point.
        centre: Name,
        /// R, the radius (with its column).
        r: (f64, u32),
        /// SA, the first hole's angle, degrees.
        sa: f64,
        /// IA, the angle between holes, degrees, with its column, if given.
        ia: Option<(f64, u32)>,
    },
    /// `MACn = designations`.
    Mac {
        /// The macro defined.
        name: Name,
        /// Its designations.
        items: Vec<Desig>,
    },
    /// `GO, [DAm,] x, y, z`.
    Go {
        /// The origin of the coordinates, if given.
        da: Option<Name>,
        /// Tool-tip x, y, z.
        v: [f64; 3],
    },
    /// `GD, dx, dy, dz`.
    Gd {
        /// dx, dy, dz.
        v: [f64; 3],
    },
    /// `CL`.
    Cl,
    /// A cutting statement.
    Cut(Cut),
}
