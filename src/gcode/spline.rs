//! G5 (cubic), G5.1 (quadratic) and G5.2/G5.3 (NURBS) splines (docs/gcode.md "Splines").

use super::comp::Comp;
use super::exec::Exec;
use super::state::InterpState;
use super::words::Words;
use crate::block::TranslateError;

/// One spline line, motion `g` (×10: 50, 51, 52).
pub fn spline(
    _st: &mut InterpState,
    _comp: &mut Comp,
    x: &mut Exec,
    _w: &Words,
    g: u16,
    col: u32,
    _inverse: Option<f64>,
) -> Result<(), TranslateError> {
    Err(x.err(
        col,
        format!("G{}.{} splines are not read yet", g / 10, g % 10),
    ))
}
