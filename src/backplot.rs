//! Backplot: the programmed path of a program as drawable segments (rapid, feed, arc), the
//! executed path as a trail of sampled axis positions, and the plane/zoom/pan geometry of the
//! plot. Feature-independent, so that it is testable without egui; the window draws it.
//!
//! Everything is in millimetres, machine (axis) coordinates: the programmed path comes from
//! the blocks' pulse amounts (what the pulse core is told to output, B1 contents), the executed
//! path from the axis pulse counters, so the two lie on top of each other when the machine
//! follows the program.

use crate::block::{Block, Motion, Plane as ArcPlane};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use crate::translator::{TranslateError, Translator};
use std::f64::consts::TAU;

/// What kind of move a piece of the programmed path is (how it is drawn).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PathKind {
    /// Positioning at the rapid rate (G00, POUT): drawn dashed.
    Rapid,
    /// Linear cutting feed (G01, LINE/PCHK): drawn solid.
    Feed,
    /// Circular interpolation (G02/G03): drawn solid, as the true arc.
    Arc,
}

/// The circle an arc segment lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcGeom {
    /// Centre in mm (absolute) in the two axes of `plane`, X Y Z order (X, Y for G17).
    pub center: [f64; 2],
    /// Signed sweep angle in radians: positive counter-clockwise (G03), negative clockwise
    /// (G02), seen from the positive end of the plane's normal. A full circle sweeps ±2π.
    pub sweep: f64,
    /// The arc's plane.
    pub plane: ArcPlane,
}

/// One drawable piece of the programmed path: one motion block.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// How it is drawn.
    pub kind: PathKind,
    /// The source statement (1-based line) the block came from.
    pub stmt: u32,
    /// The block's sequence number (ISO `N`).
    pub seq: u32,
    /// Start point, mm.
    pub from: [f64; 3],
    /// End point, mm.
    pub to: [f64; 3],
    /// The circle, for arcs.
    pub arc: Option<ArcGeom>,
}

/// Largest angle between two consecutive points of a drawn arc (3°): the chord error is
/// r·(1 − cos 1.5°) ≈ 0.00034·r, far below a pixel at any sensible zoom.
pub const ARC_STEP_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

impl Segment {
    /// The segment of one block, or `None` for a block that does not move (dwell, M/S/T only,
    /// zero amounts).
    pub fn of_block(b: &Block, settings: &MachineSettings) -> Option<Segment> {
        let mm = |p: crate::block::Axes| {
            [
                settings.to_mm(p[0]),
                settings.to_mm(p[1]),
                settings.to_mm(p[2]),
            ]
        };
        let start = b.start();
        let (kind, arc) = match b.motion {
            Motion::Dwell | Motion::Aux => return None,
            Motion::Rapid | Motion::Linear if b.delta == [0; 3] => return None,
            Motion::Rapid => (PathKind::Rapid, None),
            Motion::Linear => (PathKind::Feed, None),
            Motion::ArcCw | Motion::ArcCcw => {
                let Some(ij) = b.center else {
                    // An arc without a centre cannot be drawn true; draw its chord as a feed.
                    return Some(Segment {
                        kind: PathKind::Feed,
                        stmt: b.stmt,
                        seq: b.seq,
                        from: mm(start),
                        to: mm(b.end),
                        arc: None,
                    });
                };
                let ccw = b.motion == Motion::ArcCcw;
                let [a0, a1, _] = b.plane.axes();
                let [u, v] = b.plane.turn_axes();
                // The sweep is measured in turning order (Z→X for G18).
                let c = if u == a0 { ij } else { [ij[1], ij[0]] };
                let sweep = arc_sweep([start[u], start[v]], [b.end[u], b.end[v]], c, ccw);
                let center = [
                    settings.to_mm(start[a0] + ij[0]),
                    settings.to_mm(start[a1] + ij[1]),
                ];
                let plane = b.plane;
                (
                    PathKind::Arc,
                    Some(ArcGeom {
                        center,
                        sweep,
                        plane,
                    }),
                )
            }
        };
        Some(Segment {
            kind,
            stmt: b.stmt,
            seq: b.seq,
            from: mm(start),
            to: mm(b.end),
            arc,
        })
    }

    /// The segment as a polyline, mm: two points for a straight move, the true arc in steps of
    /// at most `ARC_STEP_RAD` for an arc (the plane's normal axis interpolated linearly, for a helix).
    pub fn points(&self) -> Vec<[f64; 3]> {
        let Some(a) = self.arc else {
            return vec![self.from, self.to];
        };
        let [p0, _, normal] = a.plane.axes();
        let [u, v] = a.plane.turn_axes();
        // The centre in turning order.
        let c = if u == p0 {
            a.center
        } else {
            [a.center[1], a.center[0]]
        };
        let r0 = [self.from[u] - c[0], self.from[v] - c[1]];
        let radius = (r0[0] * r0[0] + r0[1] * r0[1]).sqrt();
        let a0 = r0[1].atan2(r0[0]);
        let n = ((a.sweep.abs() / ARC_STEP_RAD).ceil() as usize).clamp(1, 10_000);
        let mut out = Vec::with_capacity(n + 1);
        out.push(self.from);
        for k in 1..n {
            let t = k as f64 / n as f64;
            let ang = a0 + a.sweep * t;
            let mut p = [0.0; 3];
            p[u] = c[0] + radius * ang.cos();
            p[v] = c[1] + radius * ang.sin();
            p[normal] = self.from[normal] + (self.to[normal] - self.from[normal]) * t;
            out.push(p);
        }
        // End exactly on the block's end point (as the pulse core does).
        out.push(self.to);
        out
    }
}

/// The signed sweep of an arc from `start` to `end` (pulses) about `start + ij`: in (0, 2π]
/// counter-clockwise, in [−2π, 0) clockwise; a zero X/Y move is a full circle.
fn arc_sweep(start: [i64; 2], end: [i64; 2], ij: [i64; 2], ccw: bool) -> f64 {
    let c = [(start[0] + ij[0]) as f64, (start[1] + ij[1]) as f64];
    let a0 = (start[1] as f64 - c[1]).atan2(start[0] as f64 - c[0]);
    let a1 = (end[1] as f64 - c[1]).atan2(end[0] as f64 - c[0]);
    if start == end {
        return if ccw { TAU } else { -TAU };
    }
    let mut ccw_sweep = (a1 - a0).rem_euclid(TAU);
    if ccw_sweep == 0.0 {
        ccw_sweep = TAU;
    }
    if ccw {
        ccw_sweep
    } else {
        -(TAU - ccw_sweep)
    }
}

/// An axis-aligned box, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest X, Y, Z.
    pub min: [f64; 3],
    /// Largest X, Y, Z.
    pub max: [f64; 3],
}

impl Bounds {
    /// The box of a single point.
    pub fn point(p: [f64; 3]) -> Bounds {
        Bounds { min: p, max: p }
    }

    /// Grows the box to hold `p`.
    pub fn include(&mut self, p: [f64; 3]) {
        for (a, v) in p.into_iter().enumerate() {
            self.min[a] = self.min[a].min(v);
            self.max[a] = self.max[a].max(v);
        }
    }
}

/// The programmed path of a program: its motion segments in execution order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Backplot {
    /// The segments, in the order the blocks execute.
    pub segments: Vec<Segment>,
    /// The translation error that ended the path early, if any (the path up to it is kept).
    pub error: Option<TranslateError>,
    /// Whether the path was cut at the segment limit.
    pub truncated: bool,
}

/// Most segments a backplot keeps (beyond this the plot says it is cut short).
pub const MAX_SEGMENTS: usize = 200_000;

impl Backplot {
    /// The path of hand-made or already translated blocks.
    pub fn from_blocks<'a>(
        blocks: impl IntoIterator<Item = &'a Block>,
        settings: &MachineSettings,
    ) -> Backplot {
        let mut bp = Backplot::default();
        for b in blocks {
            if !bp.push_block(b, settings) {
                break;
            }
        }
        bp
    }

    /// The path of a part program, translated with the same translator the machine uses,
    /// from machine position `start` (pulses). A translation error keeps the path up to the
    /// failing statement and is recorded in `error`.
    pub fn from_program(
        source: &str,
        magazine: &Magazine,
        settings: &MachineSettings,
        start: [i64; 3],
    ) -> Backplot {
        let tr = Translator::new(source, magazine.clone(), settings.clone(), start);
        Backplot::from_statements(tr, settings)
    }

    /// The path of the blocks of a program source (the translator, or the G-code source).
    pub fn from_statements(
        statements: impl Iterator<Item = Result<crate::block::Statement, TranslateError>>,
        settings: &MachineSettings,
    ) -> Backplot {
        let mut bp = Backplot::default();
        'statements: for st in statements {
            match st {
                Ok(st) => {
                    for b in &st.blocks {
                        if !bp.push_block(b, settings) {
                            break 'statements;
                        }
                    }
                }
                Err(e) => {
                    bp.error = Some(e);
                    break;
                }
            }
        }
        bp
    }

    /// Adds one block's segment; false when the segment limit is reached.
    fn push_block(&mut self, b: &Block, settings: &MachineSettings) -> bool {
        if self.segments.len() >= MAX_SEGMENTS {
            self.truncated = true;
            return false;
        }
        if let Some(s) = Segment::of_block(b, settings) {
            self.segments.push(s);
        }
        true
    }

    /// The box holding every drawn point of the path, if there is any.
    pub fn bounds(&self) -> Option<Bounds> {
        let mut it = self.segments.iter().flat_map(|s| s.points());
        let mut b = Bounds::point(it.next()?);
        for p in it {
            b.include(p);
        }
        Some(b)
    }
}

/// The executed path: axis positions sampled from the pulse counters while the machine moves,
/// each with a tag of what it was (`()` on the centre; on a lathe the work in the spindle, so
/// that each work's cuts are drawn in its colour). Every window's backplot keeps this one.
#[derive(Clone, Debug, PartialEq)]
pub struct Trail<T = ()> {
    points: Vec<[f64; 3]>,
    tags: Vec<T>,
    epoch: u64,
}

impl<T> Default for Trail<T> {
    fn default() -> Self {
        Trail {
            points: Vec::new(),
            tags: Vec::new(),
            epoch: 0,
        }
    }
}

/// Most points a trail keeps; beyond this every other inner point is dropped.
pub const MAX_TRAIL_POINTS: usize = 100_000;

impl Trail {
    /// An empty trail.
    pub fn new() -> Trail {
        Trail::default()
    }

    /// Records a sampled position (see [`Trail::push_tagged`]).
    pub fn push(&mut self, p: [f64; 3]) {
        self.push_tagged(p, ());
    }
}

impl<T: Copy + PartialEq> Trail<T> {
    /// Records a sampled position with its tag; a sample within 0.5 µm of the last one adds
    /// nothing, and a sample in line with the last two replaces the last (so a long straight
    /// move stays two points however often it is sampled), as long as the tag stays the
    /// same: a new tag always starts a point.
    pub fn push_tagged(&mut self, p: [f64; 3], tag: T) {
        let n = self.points.len();
        let same = |k: usize| n >= k && self.tags[n - k..].iter().all(|t| *t == tag);
        if same(1) && dist(self.points[n - 1], p) < 0.0005 {
            return;
        }
        if same(2) && collinear(self.points[n - 2], self.points[n - 1], p) {
            self.points[n - 1] = p;
            return;
        }
        self.points.push(p);
        self.tags.push(tag);
        if self.points.len() > MAX_TRAIL_POINTS {
            self.epoch += 1;
            let last = self.points.len() - 1;
            let keep = |i: usize| i == 0 || i == last || i.is_multiple_of(2);
            let mut i = 0;
            self.points.retain(|_| {
                i += 1;
                keep(i - 1)
            });
            let mut i = 0;
            self.tags.retain(|_| {
                i += 1;
                keep(i - 1)
            });
        }
    }

    /// Forgets the trail (a new program, or the operator cleared the plot).
    pub fn clear(&mut self) {
        self.points.clear();
        self.tags.clear();
        self.epoch += 1;
    }

    /// Changes whenever points other than the last may have changed (cleared or thinned), so
    /// that a drawing of all but the last point can be kept until then.
    pub fn epoch(&self) -> u64 {
        self.epoch
    }

    /// The recorded points, oldest first.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// The points with their tags, oldest first.
    pub fn tagged(&self) -> impl Iterator<Item = ([f64; 3], T)> + '_ {
        self.points.iter().copied().zip(self.tags.iter().copied())
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Whether `b` lies on the segment a→c's line, between them, within 0.5 µm.
fn collinear(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ac = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let len = (ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2]).sqrt();
    if len == 0.0 {
        return false;
    }
    let cross = [
        ab[1] * ac[2] - ab[2] * ac[1],
        ab[2] * ac[0] - ab[0] * ac[2],
        ab[0] * ac[1] - ab[1] * ac[0],
    ];
    let off = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt() / len;
    let along = (ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2]) / len;
    off < 0.0005 && along > 0.0 && along < len
}

/// The plane the backplot shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    /// Looking down the Z axis: X to the right, Y up.
    XY,
    /// Looking along −Y (from the front): X to the right, Z up.
    XZ,
}

impl Plane {
    /// The point's coordinates in the plane (horizontal, vertical), mm.
    pub fn project(self, p: [f64; 3]) -> [f64; 2] {
        match self {
            Plane::XY => [p[0], p[1]],
            Plane::XZ => [p[0], p[2]],
        }
    }

    /// The axis letters (horizontal, vertical).
    pub fn axes(self) -> (char, char) {
        match self {
            Plane::XY => ('X', 'Y'),
            Plane::XZ => ('X', 'Z'),
        }
    }
}

/// The mapping from plane millimetres to screen pixels: a centre and a scale, changed by
/// fit, zoom (about the pointer) and pan. Screen Y grows downward, plane vertical grows upward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewTransform {
    /// The plane point (mm) at the middle of the plot.
    pub center: [f64; 2],
    /// Pixels per millimetre.
    pub scale: f64,
}

impl Default for ViewTransform {
    fn default() -> Self {
        ViewTransform {
            center: [0.0, 0.0],
            scale: 1.0,
        }
    }
}

/// Smallest and largest zoom, pixels per mm.
pub const SCALE_RANGE: (f64, f64) = (0.001, 10_000.0);

impl ViewTransform {
    /// A view that shows the plane box `min..max` inside a plot of `size` pixels, leaving
    /// `margin` pixels on each side.
    pub fn fit(min: [f64; 2], max: [f64; 2], size: [f64; 2], margin: f64) -> ViewTransform {
        let w = (max[0] - min[0]).max(1.0);
        let h = (max[1] - min[1]).max(1.0);
        let aw = (size[0] - 2.0 * margin).max(1.0);
        let ah = (size[1] - 2.0 * margin).max(1.0);
        ViewTransform {
            center: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
            scale: (aw / w).min(ah / h).clamp(SCALE_RANGE.0, SCALE_RANGE.1),
        }
    }

    /// Plane point (mm) to pixel offset from the plot's middle.
    pub fn to_screen(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.center[0]) * self.scale,
            -(p[1] - self.center[1]) * self.scale,
        ]
    }

    /// Pixel offset from the plot's middle to plane point (mm).
    pub fn to_plane(&self, s: [f64; 2]) -> [f64; 2] {
        [
            self.center[0] + s[0] / self.scale,
            self.center[1] - s[1] / self.scale,
        ]
    }

    /// Zooms by `factor` keeping the plane point under pixel offset `at` where it is.
    pub fn zoom(&mut self, factor: f64, at: [f64; 2]) {
        if !(factor.is_finite() && factor > 0.0) {
            return;
        }
        let fixed = self.to_plane(at);
        self.scale = (self.scale * factor).clamp(SCALE_RANGE.0, SCALE_RANGE.1);
        self.center = [fixed[0] - at[0] / self.scale, fixed[1] + at[1] / self.scale];
    }

    /// Moves the drawing by a pixel drag.
    pub fn pan(&mut self, drag: [f64; 2]) {
        self.center[0] -= drag[0] / self.scale;
        self.center[1] += drag[1] / self.scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s() -> MachineSettings {
        MachineSettings::default()
    }

    fn block(seq: u32, motion: Motion, start: [i64; 3], end: [i64; 3]) -> Block {
        let mut b = Block::aux(seq, 1, end);
        b.motion = motion;
        b.delta = [end[0] - start[0], end[1] - start[1], end[2] - start[2]].into();
        b
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn rapid_and_feed_become_segments_in_mm_and_still_blocks_do_not() {
        let b1 = block(1, Motion::Rapid, [0; 3], [100_000, 50_000, 0]);
        let b2 = block(2, Motion::Aux, [100_000, 50_000, 0], [100_000, 50_000, 0]);
        let b3 = block(
            3,
            Motion::Linear,
            [100_000, 50_000, 0],
            [100_000, 50_000, -20_000],
        );
        let mut b4 = block(
            4,
            Motion::Dwell,
            [100_000, 50_000, -20_000],
            [100_000, 50_000, -20_000],
        );
        b4.dwell_ns = 1_000_000;
        let b5 = block(
            5,
            Motion::Linear,
            [100_000, 50_000, -20_000],
            [100_000, 50_000, -20_000],
        );
        let bp = Backplot::from_blocks([&b1, &b2, &b3, &b4, &b5], &s());
        assert_eq!(bp.segments.len(), 2);
        assert_eq!(bp.segments[0].kind, PathKind::Rapid);
        assert_eq!(bp.segments[0].to, [100.0, 50.0, 0.0]);
        assert_eq!(bp.segments[1].kind, PathKind::Feed);
        assert_eq!(bp.segments[1].seq, 3);
        assert_eq!(
            bp.segments[1].points(),
            vec![[100.0, 50.0, 0.0], [100.0, 50.0, -20.0]]
        );
        let b = bp.bounds().unwrap();
        assert_eq!(b.min, [0.0, 0.0, -20.0]);
        assert_eq!(b.max, [100.0, 50.0, 0.0]);
    }

    #[test]
    fn ccw_quarter_arc_is_drawn_on_the_true_circle_counter_clockwise() {
        // From (10, 0) to (0, 10) about the origin: I = -10, J = 0.
        let mut b = block(1, Motion::ArcCcw, [10_000, 0, 0], [0, 10_000, 0]);
        b.center = Some([-10_000, 0]);
        let seg = Segment::of_block(&b, &s()).unwrap();
        assert_eq!(seg.kind, PathKind::Arc);
        let a = seg.arc.unwrap();
        assert!(close(a.sweep, std::f64::consts::FRAC_PI_2), "{}", a.sweep);
        let pts = seg.points();
        assert!(
            pts.len() >= 30,
            "a quarter circle in 3° steps: {}",
            pts.len()
        );
        assert_eq!(pts[0], [10.0, 0.0, 0.0]);
        assert_eq!(*pts.last().unwrap(), [0.0, 10.0, 0.0]);
        for w in pts.windows(2) {
            let r = (w[1][0].powi(2) + w[1][1].powi(2)).sqrt();
            assert!((r - 10.0).abs() < 1e-9, "off the circle: {r}");
            // Counter-clockwise: the cross product of successive radii is positive.
            assert!(w[0][0] * w[1][1] - w[0][1] * w[1][0] > 0.0);
            // Within the first quadrant.
            assert!(w[1][0] >= -1e-9 && w[1][1] >= -1e-9);
        }
    }

    #[test]
    fn cw_arc_goes_the_long_way_when_the_end_is_counter_clockwise_of_the_start() {
        // Same end points as above, but G02: three quarters of the circle, clockwise.
        let mut b = block(1, Motion::ArcCw, [10_000, 0, 0], [0, 10_000, 0]);
        b.center = Some([-10_000, 0]);
        let seg = Segment::of_block(&b, &s()).unwrap();
        let a = seg.arc.unwrap();
        assert!(close(a.sweep, -1.5 * std::f64::consts::PI), "{}", a.sweep);
        let pts = seg.points();
        // It passes through (0, -10) and (-10, 0).
        assert!(pts.iter().any(|p| p[1] < -9.99));
        assert!(pts.iter().any(|p| p[0] < -9.99));
        for w in pts.windows(2) {
            assert!(w[0][0] * w[1][1] - w[0][1] * w[1][0] < 0.0, "clockwise");
        }
        let bb = Backplot::from_blocks([&b], &s()).bounds().unwrap();
        assert!(bb.min[0] < -9.99 && bb.min[1] < -9.99 && bb.max[0] > 9.99 && bb.max[1] > 9.99);
    }

    #[test]
    fn full_circle_is_a_whole_turn_and_helix_interpolates_z() {
        let mut b = block(1, Motion::ArcCcw, [65_000, 0, 0], [65_000, 0, -5_000]);
        b.center = Some([-65_000, 0]);
        let seg = Segment::of_block(&b, &s()).unwrap();
        assert!(close(seg.arc.unwrap().sweep, TAU));
        let pts = seg.points();
        assert_eq!(pts.len(), 121);
        let mid = pts[60];
        assert!((mid[0] + 65.0).abs() < 1e-9 && mid[1].abs() < 1e-9);
        assert!((mid[2] + 2.5).abs() < 1e-9);
        let mut cw = b.clone();
        cw.motion = Motion::ArcCw;
        assert!(close(
            Segment::of_block(&cw, &s()).unwrap().arc.unwrap().sweep,
            -TAU
        ));
    }

    #[test]
    fn arc_without_centre_falls_back_to_its_chord() {
        let b = block(1, Motion::ArcCw, [0; 3], [1_000, 0, 0]);
        let seg = Segment::of_block(&b, &s()).unwrap();
        assert_eq!(seg.kind, PathKind::Feed);
        assert_eq!(seg.points().len(), 2);
    }

    #[test]
    fn segment_limit_truncates() {
        let blocks: Vec<Block> = (0..(MAX_SEGMENTS as i64 + 5))
            .map(|i| block(i as u32, Motion::Linear, [i, 0, 0], [i + 1, 0, 0]))
            .collect();
        let bp = Backplot::from_blocks(&blocks, &s());
        assert!(bp.truncated);
        assert_eq!(bp.segments.len(), MAX_SEGMENTS);
    }

    #[test]
    fn trail_merges_straight_runs_and_keeps_corners() {
        let mut t = Trail::new();
        for i in 0..=100 {
            t.push([i as f64, 0.0, 0.0]);
        }
        t.push([100.0, 0.0, 0.0]); // standing still adds nothing
        assert_eq!(t.points(), &[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]);
        for i in 1..=10 {
            t.push([100.0, i as f64, 0.0]);
        }
        assert_eq!(t.points().len(), 3);
        assert_eq!(t.points()[2], [100.0, 10.0, 0.0]);
        // Going back along the same line is a corner, not a merge.
        t.push([100.0, 5.0, 0.0]);
        assert_eq!(t.points().len(), 4);
        assert_eq!(t.epoch(), 0);
        t.clear();
        assert!(t.points().is_empty());
        assert_eq!(t.epoch(), 1);
    }

    #[test]
    fn a_new_tag_starts_a_point_and_tags_stay_with_their_points() {
        let mut t: Trail<Option<u32>> = Trail::default();
        t.push_tagged([0.0, 0.0, 0.0], None);
        t.push_tagged([0.0, 0.0, -1.0], Some(1));
        t.push_tagged([0.0, 0.0, -2.0], Some(1));
        t.push_tagged([0.0, 0.0, -3.0], Some(1));
        // In line, same work: the last point follows the tip.
        assert_eq!(t.points().len(), 3);
        // The next work starts a point even in line.
        t.push_tagged([0.0, 0.0, -4.0], Some(2));
        let tags: Vec<Option<u32>> = t.tagged().map(|(_, w)| w).collect();
        assert_eq!(tags, [None, Some(1), Some(1), Some(2)]);
        for i in 0..(MAX_TRAIL_POINTS as i32 + 10) {
            t.push_tagged([f64::from(i % 2), 0.0, f64::from(i)], Some(3));
        }
        assert_eq!(t.points().len(), t.tags.len());
        assert!(t.points().len() <= MAX_TRAIL_POINTS);
        assert_eq!(t.tagged().next().map(|(_, w)| w), Some(None));
    }

    #[test]
    fn trail_stays_bounded_and_keeps_its_ends() {
        let mut t = Trail::new();
        let n = MAX_TRAIL_POINTS + 10;
        for i in 0..n {
            // A zig-zag: no three points in line.
            t.push([i as f64, (i % 2) as f64, 0.0]);
        }
        assert!(t.points().len() <= MAX_TRAIL_POINTS);
        assert_eq!(t.epoch(), 1, "thinned once");
        assert_eq!(t.points()[0], [0.0, 0.0, 0.0]);
        assert_eq!(
            *t.points().last().unwrap(),
            [(n - 1) as f64, ((n - 1) % 2) as f64, 0.0]
        );
    }

    #[test]
    fn planes_project_the_right_axes() {
        assert_eq!(Plane::XY.project([1.0, 2.0, 3.0]), [1.0, 2.0]);
        assert_eq!(Plane::XZ.project([1.0, 2.0, 3.0]), [1.0, 3.0]);
        assert_eq!(Plane::XZ.axes(), ('X', 'Z'));
    }

    #[test]
    fn fit_shows_the_box_and_zoom_keeps_the_pointed_spot() {
        let v = ViewTransform::fit([0.0, 0.0], [200.0, 100.0], [420.0, 420.0], 10.0);
        assert!(close(v.scale, 2.0));
        assert_eq!(v.to_screen([0.0, 0.0]), [-200.0, 100.0]);
        assert_eq!(v.to_screen([200.0, 100.0]), [200.0, -100.0]);
        let mut z = v;
        let at = [50.0, -30.0];
        let before = z.to_plane(at);
        z.zoom(1.5, at);
        assert!(close(z.scale, 3.0));
        let after = z.to_plane(at);
        assert!(close(before[0], after[0]) && close(before[1], after[1]));
        z.zoom(f64::NAN, at);
        assert!(close(z.scale, 3.0));
        let mut p = v;
        p.pan([20.0, 10.0]);
        // Dragging right and down moves the drawing right and down.
        assert_eq!(p.to_screen([0.0, 0.0]), [-180.0, 110.0]);
        // A degenerate box (one point) still gives a finite view.
        let d = ViewTransform::fit([5.0, 5.0], [5.0, 5.0], [100.0, 100.0], 10.0);
        assert!(d.scale.is_finite() && d.scale > 0.0);
    }

    #[test]
    fn an_arc_in_the_xz_plane_is_drawn_in_x_and_z() {
        // G18 G02 from (10, 5, 0) to (0, 5, 10) about (0, 5, 0): seen from +Y, clockwise turns
        // X toward Z (Z→X is counter-clockwise), a quarter circle of radius 10.
        let mut b = block(1, Motion::ArcCw, [10_000, 5_000, 0], [0, 5_000, 10_000]);
        b.plane = ArcPlane::XZ;
        b.center = Some([-10_000, 0]);
        let seg = Segment::of_block(&b, &s()).unwrap();
        let a = seg.arc.unwrap();
        assert!(close(a.sweep, -std::f64::consts::FRAC_PI_2), "{}", a.sweep);
        for p in seg.points() {
            assert!(close(p[0].hypot(p[2]), 10.0), "{p:?}");
            assert!(close(p[1], 5.0));
            assert!(
                p[0] >= -1e-9 && p[2] >= -1e-9,
                "stays in the first quadrant: {p:?}"
            );
        }
    }
}
