//! Tool-nose radius compensation G41/G42 in the Z–X plane (docs/lathe-gcode.md "Nose-radius
//! compensation"; seed 003 lines 2682–2698: the control needs the nose radius and the
//! position of the imaginary tip P relative to the nose centre C).
//!
//! The nose centre C runs one radius to the left (G41) or right (G42) of the programmed
//! profile, looking along the direction of travel with Z to the right and X up. The
//! controlled point is P = C + R·v(tip) ([`tip_vector`], Fanuc's chart). The nose centre's
//! path is the mill's cutter compensation (`crate::gcode::comp::Comp`, LinuxCNC 2.9's rules)
//! in the Z–X plane: the emitter (`super::out`) hands it the programmed moves and adds
//! R·v(tip) to what it hands back. Before stop 51 this file held a second, batch
//! implementation of the same rules, which refused an arc as the entry move and joined
//! corners its own way.

/// The direction from the nose centre C to the imaginary tip P for a tip position, `[Z, X]`
/// (Fanuc's chart with Z to the right and X up; 0 and 9 are the centre itself):
///
/// ```text
///        +X
///    2   6   1
///    7  0/9  5   +Z
///    3   8   4
/// ```
pub fn tip_vector(tip: u8) -> [f64; 2] {
    match tip {
        1 => [1.0, 1.0],
        2 => [-1.0, 1.0],
        3 => [-1.0, -1.0],
        4 => [1.0, -1.0],
        5 => [1.0, 0.0],
        6 => [0.0, 1.0],
        7 => [-1.0, 0.0],
        8 => [0.0, -1.0],
        _ => [0.0, 0.0],
    }
}

/// LinuxCNC's orientation (its tool table's Q, #5411) of the tool whose tip position is `tip`
/// in Fanuc's chart: LinuxCNC draws its chart with +X down (`latheorigin_x`/`_z` in its
/// `interp_queue.cc`), so its 2 is the usual outside turning tool, Fanuc's 3
/// (docs/lathe-gcode.md "Nose-radius compensation").
pub fn linuxcnc_orientation(tip: u8) -> u8 {
    [0, 4, 3, 2, 1, 5, 8, 7, 6, 9]
        .get(usize::from(tip))
        .copied()
        .unwrap_or(0)
}
