//! The backplot's programmed path computed with the real translator (`novanc::translator::Translator`):
//! Table B and a milled circle. Feature-independent (no egui).

use novanc::backplot::{Backplot, PathKind, Segment};
use novanc::settings::MachineSettings;
use std::f64::consts::TAU;

fn s() -> MachineSettings {
    MachineSettings::default()
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() < 0.002
}

#[test]
fn table_b_path_from_the_translator_has_rapids_and_plunges_at_the_pattern_holes() {
    let src = include_str!("../programs/tableb.ap");
    let mag = novanc::tooldata::sample_magazine();
    let bp = Backplot::from_program(src, &mag, &s(), [0; 3]);
    assert_eq!(bp.error, None);
    assert!(!bp.truncated);
    assert!(bp.segments.iter().any(|g| g.kind == PathKind::Rapid));
    assert!(bp.segments.iter().all(|g| g.kind != PathKind::Arc));
    // The path starts where the machine is and is continuous, block after block.
    assert_eq!(bp.segments[0].from, [0.0, 0.0, 0.0]);
    for w in bp.segments.windows(2) {
        assert_eq!(
            w[0].to, w[1].from,
            "a gap between blocks {} and {}",
            w[0].seq, w[1].seq
        );
    }
    // Every PAT1 hole (DA1 + docs/language.md's pattern points) gets a feed straight down in Z.
    let holes = [
        (206.292, 162.5),
        (150.0, 195.0),
        (93.708, 162.5),
        (93.708, 97.5),
        (150.0, 65.0),
        (206.292, 97.5),
    ];
    for (hx, hy) in holes {
        let (x, y) = (200.0 + hx, hy);
        let plunge = bp.segments.iter().find(|g| {
            g.kind == PathKind::Feed
                && near(g.from[0], x)
                && near(g.from[1], y)
                && near(g.to[0], x)
                && near(g.to[1], y)
                && g.to[2] < g.from[2]
        });
        assert!(plunge.is_some(), "no plunge at ({x}, {y})");
    }
}

#[test]
fn a_milled_circle_is_an_arc_and_an_error_keeps_the_path_before_it() {
    let src = "DA1 = (200, 100, -450)\nP1 = (50, 50)\nC1 = P1, R20\nMIL, 402/DP5/DA1, C1\nDRL, 99999/DP5/DA1, P1\n";
    let mag = novanc::tooldata::sample_magazine();
    let bp = Backplot::from_program(src, &mag, &s(), [0; 3]);
    let arcs: Vec<&Segment> = bp
        .segments
        .iter()
        .filter(|g| g.kind == PathKind::Arc)
        .collect();
    assert_eq!(arcs.len(), 1, "{:?}", bp.segments);
    let a = arcs[0].arc.unwrap();
    assert!(
        near(a.center[0], 250.0) && near(a.center[1], 150.0),
        "{a:?}"
    );
    assert!(near(a.sweep.abs(), TAU));
    for p in arcs[0].points() {
        let r = ((p[0] - 250.0).powi(2) + (p[1] - 150.0).powi(2)).sqrt();
        assert!(near(r, 20.0), "point off the programmed circle: r = {r}");
    }
    let e = bp.error.expect("the unknown tool 99999 is an error");
    assert_eq!(e.line, 5);
}
