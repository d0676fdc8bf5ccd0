//! The G-code interpreter's persistent parameters in the stores (docs/stores.md "The
//! interpreter's parameters"): LinuxCNC's parameter file, #5161–#5390 (the G28 and G30 homes,
//! G92, the system in force, the nine systems' zeros and rotations). Set by the OFS page and by
//! what a G-code run reads (G10, G92, G28.1, ...), journaled like the tool file, and in the
//! snapshot. The work offsets G54 to G59.3 are some of them.

use super::record::Record;
use super::{serr, to_store, StoreError, Stores};
use crate::gcode::state::{is_kept, system_base, SYSTEMS};
use crate::gcode::WorkOffsets;
use std::collections::BTreeMap;

/// A parameter's value as the stores keep it: whole millionths of its unit (nanometres for a
/// length); refused when not a finite number within the stores' limit.
pub fn to_millionths(n: usize, v: f64) -> Result<i64, String> {
    let m = (v * 1e6).round();
    if !m.is_finite() || m.abs() > super::state::PARAM_LIMIT as f64 {
        return Err(format!(
            "#{n} = {v} is not a number within {}",
            super::state::PARAM_LIMIT / 1_000_000
        ));
    }
    Ok(m as i64)
}

/// The work offsets G54 to G59 the parameters hold, mm.
pub fn offsets_of(params: &BTreeMap<u16, i64>) -> WorkOffsets {
    let mut w = WorkOffsets::default();
    for (cs, o) in w.0.iter_mut().enumerate() {
        let b = system_base(cs);
        for (a, v) in o.iter_mut().enumerate() {
            *v = params
                .get(&((b + 1 + a) as u16))
                .map_or(0.0, |&n| n as f64 / 1e6);
        }
    }
    w
}

/// The persistent parameters kept in `params`, as (number, value in its unit).
pub fn params_of(params: &BTreeMap<u16, i64>) -> Vec<(usize, f64)> {
    params
        .iter()
        .map(|(&n, &v)| (usize::from(n), v as f64 / 1e6))
        .collect()
}

impl Stores {
    /// The persistent parameters that are not zero, as (number, value in its unit).
    pub fn params(&self) -> Vec<(usize, f64)> {
        params_of(&self.state.params)
    }

    /// One persistent parameter's value (0 when not kept; #5220 then 1).
    pub fn param(&self, n: usize) -> f64 {
        match u16::try_from(n)
            .ok()
            .and_then(|k| self.state.params.get(&k))
        {
            Some(&v) => v as f64 / 1e6,
            None if n == 5220 => 1.0,
            None => 0.0,
        }
    }

    /// Sets persistent parameters together, as one journaled record, before it returns Ok.
    /// A parameter that is not persistent, or a value that is not a finite number within the
    /// limit, refuses the whole change; parameters that already hold their value are left out.
    pub fn set_params(&mut self, ps: &[(usize, f64)]) -> Result<(), StoreError> {
        let mut rec = Vec::with_capacity(ps.len());
        for &(n, v) in ps {
            if !is_kept(n) {
                return Err(serr(format!(
                    "#{n} is not a parameter the controller keeps (#500-#999 and the hour clock #3002 in the Fanuc dialect, #5161-#5169, #5181-#5189, #5210-#5390)"
                )));
            }
            let m = to_millionths(n, v).map_err(serr)?;
            let now = self.state.params.get(&(n as u16)).copied().unwrap_or(0);
            let now = if n == 5220 && now == 0 {
                1_000_000
            } else {
                now
            };
            if m != now {
                rec.retain(|&(k, _)| k != n as u16);
                rec.push((n as u16, m));
            }
        }
        if rec.is_empty() {
            return Ok(());
        }
        self.commit(Record::Params(rec), None)
            .map(|_| ())
            .map_err(to_store)
    }

    /// The work offsets G54 to G59, machine mm.
    pub fn work_offsets(&self) -> WorkOffsets {
        offsets_of(&self.state.params)
    }

    /// The zero of coordinate system `cs` (0 = G54 … 8 = G59.3), machine mm.
    pub fn system_offset(&self, cs: usize) -> [f64; 3] {
        let b = system_base(cs);
        [self.param(b + 1), self.param(b + 2), self.param(b + 3)]
    }

    /// The rotary axes' part of coordinate system `cs`'s zero (A, B, C), degrees.
    pub fn rotary_offset(&self, cs: usize) -> [f64; 3] {
        let b = system_base(cs);
        [self.param(b + 4), self.param(b + 5), self.param(b + 6)]
    }

    /// Sets the zero of coordinate system `system` (0 = G54 … 8 = G59.3) to `offs`: X Y Z in
    /// mm, then A B C in degrees as many as given, in one record journaled before it returns
    /// Ok; a value that is not a finite number within 100 m (a rotary axis's, within 10⁹
    /// degrees) changes nothing.
    pub fn set_work_offset(&mut self, system: usize, offs: &[f64]) -> Result<(), StoreError> {
        if system >= SYSTEMS {
            return Err(serr(format!(
                "work offset system {system} is not G54 to G59.3"
            )));
        }
        let limit = super::state::OFFSET_LIMIT_NM as f64 / 1e6;
        if let Some(v) = offs
            .iter()
            .take(3)
            .find(|v| !v.is_finite() || v.abs() > limit)
        {
            return Err(serr(format!(
                "work offset {v} mm is not a number within {limit} mm"
            )));
        }
        if let Some(v) = offs
            .iter()
            .skip(3)
            .find(|v| !v.is_finite() || v.abs() > 1e9)
        {
            return Err(serr(format!(
                "work offset {v} degrees is not a number within 10^9 degrees"
            )));
        }
        let b = system_base(system);
        let ps: Vec<(usize, f64)> = offs
            .iter()
            .take(6)
            .enumerate()
            .map(|(a, &v)| (b + 1 + a, v))
            .collect();
        self.set_params(&ps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_kept_in_millionths_and_refused_out_of_range() {
        assert_eq!(to_millionths(5221, 1.5), Ok(1_500_000));
        assert_eq!(to_millionths(5221, -0.0000004), Ok(0));
        assert!(to_millionths(5221, f64::NAN).is_err());
        assert!(to_millionths(5230, 2e6).is_err());
    }
}
