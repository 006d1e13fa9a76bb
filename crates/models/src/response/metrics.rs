//! One-record gear metrics: the rattle state of a backlash coordinate (Liu et al. 2021,
//! Sect. 3.2, "rsv"), the dynamic factor (Yu et al. 2021, Eq. 20) and the RMS over harmonic
//! amplitudes (Yu et al. 2021, Eq. 21). They live here, with the long-window statistics, and not
//! in the gear-agnostic `timestep` engine: the signal tools they build on (peak-to-peak, Fourier
//! projection) stay there.

use crate::error::Error;
use math::DetMath;

fn invalid(field: &str, bound: &str, value: f64) -> Error {
    Error::InvalidParameter {
        field: field.to_owned(),
        bound: bound.to_owned(),
        value,
    }
}

/// A non-empty, finite signal.
fn signal(name: &str, x: &[f64]) -> Result<(), Error> {
    if x.is_empty() {
        return Err(invalid(&format!("{name} (length)"), ">= 1 sample", 0.0));
    }
    match x.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(invalid(&format!("{name}[{i}]"), "finite", x[i])),
        None => Ok(()),
    }
}

/// Rattle state of a backlash coordinate (Liu et al. 2021, Sect. 3.2, "rsv"): the one rattle
/// state of the workspace (the Liu 2021 model and the long-window statistics classify into it).
///
/// With relative displacement `x` and gap edges `±b` (dead zone `|x| ≤ b`), contact on the
/// upper flank means `x > b`, on the lower flank `x < −b`. Ordered by rsv (so that the worst
/// state of a record is the `max` of its samples' states); serde names in snake_case
/// (`no_rattle`, `unilateral`, `no_contact`, `bilateral`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum RattleState {
    /// Permanent contact on one flank, never separating (rsv = 0).
    NoRattle,
    /// Contact on one flank only, with separations into the gap (rsv = 1).
    Unilateral,
    /// Never in contact (pure free flight); only [`rattle_state`] (flank-agnostic) gives it.
    NoContact,
    /// Contact on both flanks (rsv = 2).
    Bilateral,
}

impl RattleState {
    /// Liu's rattle-state value: 0, 1, 2. [`RattleState::NoContact`] counts as 1: in Liu's
    /// definition rsv 1 means "the flanks are apart somewhere and the back flank is never
    /// reached", which free flight satisfies (Sect. 3.2; `docs/readings/timestep.md`).
    pub fn rsv(self) -> u8 {
        match self {
            RattleState::NoRattle => 0,
            RattleState::Unilateral | RattleState::NoContact => 1,
            RattleState::Bilateral => 2,
        }
    }

    /// `no rattle`, `unilateral`, `no contact`, `bilateral`.
    pub fn label(self) -> &'static str {
        match self {
            RattleState::NoRattle => "no rattle",
            RattleState::Unilateral => "unilateral",
            RattleState::NoContact => "no contact",
            RattleState::Bilateral => "bilateral",
        }
    }
}

/// Rattle state of the steady-state samples `x` for a constant gap half-width `b`;
/// `tol` (≥ 0) is a margin: separation means going more than `tol` into the gap.
///
/// # Errors
/// An empty or non-finite signal, a non-finite or negative `b`, a negative or non-finite `tol`.
pub fn rattle_state(x: &[f64], b: f64, tol: f64) -> Result<RattleState, Error> {
    if !b.is_finite() {
        return Err(invalid("gap", "finite", b));
    }
    rattle_state_with_gap(x, &vec![b; x.len()], tol)
}

/// As [`rattle_state`] with a time-varying gap `b[i]` at each sample (dynamic backlash).
///
/// # Errors
/// As [`rattle_state`]; a gap of another length than `x`.
pub fn rattle_state_with_gap(x: &[f64], b: &[f64], tol: f64) -> Result<RattleState, Error> {
    signal("signal", x)?;
    if b.len() != x.len() {
        return Err(invalid(
            "gap (length)",
            &format!("= {} (the signal's)", x.len()),
            b.len() as f64,
        ));
    }
    if let Some(i) = b.iter().position(|&v| !(v.is_finite() && v >= 0.0)) {
        return Err(invalid(&format!("gap[{i}]"), "finite and >= 0", b[i]));
    }
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(invalid("tol", "finite and >= 0", tol));
    }
    let upper = x.iter().zip(b).any(|(&v, &g)| v > g);
    let lower = x.iter().zip(b).any(|(&v, &g)| v < -g);
    Ok(match (upper, lower) {
        (true, true) => RattleState::Bilateral,
        (false, false) => RattleState::NoContact,
        (true, false) => {
            if x.iter().zip(b).all(|(&v, &g)| v >= g - tol) {
                RattleState::NoRattle
            } else {
                RattleState::Unilateral
            }
        }
        (false, true) => {
            if x.iter().zip(b).all(|(&v, &g)| v <= -g + tol) {
                RattleState::NoRattle
            } else {
                RattleState::Unilateral
            }
        }
    })
}

/// Dynamic factor `DF = max F_m / F_s` (Yu et al. 2021, Eq. 20): maximum dynamic mesh force
/// over the static force.
///
/// # Errors
/// An empty or non-finite force record; a static force that is zero or not finite.
pub fn dynamic_factor(mesh_force: &[f64], static_force: f64) -> Result<f64, Error> {
    signal("mesh force", mesh_force)?;
    if !(static_force.is_finite() && static_force != 0.0) {
        return Err(invalid("static force", "finite and nonzero", static_force));
    }
    let max = mesh_force.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(max / static_force)
}

/// RMS over harmonic amplitudes `A_1..A_n` (Yu et al. 2021, Eq. 21): `RMS = sqrt(Σ A_i² / n)`
/// (amplitudes from `timestep::fourier_projection` and
/// `timestep::harmonic_amplitudes_of_projection`).
///
/// # Errors
/// No amplitudes, or a non-finite one.
pub fn rms_of_harmonics(amplitudes: &[f64]) -> Result<f64, Error> {
    signal("harmonic amplitudes", amplitudes)?;
    let s: f64 = amplitudes.iter().map(|a| a * a).sum();
    Ok((s / amplitudes.len() as f64).sqrt())
}

/// The order of magnitude of `x` as text: `1e<k>` with `k = floor(log10 x)` (so `x` lies in
/// `[1e<k>, 1e<k+1>)`), or `infinity` (flags give the size of a change that moves
/// with every integrator retune only to its order of magnitude).
pub fn order_of_magnitude(x: f64) -> String {
    if x.is_finite() && x > 0.0 {
        format!("1e{}", x.dlog10().floor() as i32)
    } else if x == 0.0 {
        "0".to_owned()
    } else {
        "infinity".to_owned()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn order_of_magnitude_rounds_the_exponent() {
        assert_eq!(super::order_of_magnitude(2.671e-2), "1e-2");
        assert_eq!(super::order_of_magnitude(3.97e-2), "1e-2");
        assert_eq!(super::order_of_magnitude(1.0), "1e0");
        assert_eq!(super::order_of_magnitude(0.0), "0");
        assert_eq!(super::order_of_magnitude(f64::NAN), "infinity");
    }

    use super::*;

    #[test]
    fn rattle_states_by_construction() {
        let b = 1.0;
        // held on the upper flank, never into the gap: no rattle
        assert_eq!(
            rattle_state(&[1.2, 1.5, 1.1], b, 0.0).unwrap(),
            RattleState::NoRattle
        );
        // into the gap from the upper flank: unilateral; within the margin: no rattle
        assert_eq!(
            rattle_state(&[1.2, 0.5, 1.1], b, 0.0).unwrap(),
            RattleState::Unilateral
        );
        assert_eq!(
            rattle_state(&[1.2, 0.95, 1.1], b, 0.1).unwrap(),
            RattleState::NoRattle
        );
        // both flanks
        assert_eq!(
            rattle_state(&[1.2, -1.5], b, 0.0).unwrap(),
            RattleState::Bilateral
        );
        // free flight
        assert_eq!(
            rattle_state(&[0.2, -0.5], b, 0.0).unwrap(),
            RattleState::NoContact
        );
        assert_eq!(RattleState::NoContact.rsv(), 1);
        assert!(RattleState::Bilateral > RattleState::Unilateral);
        // a moving gap
        let g = [1.0, 2.0, 1.0];
        assert_eq!(
            rattle_state_with_gap(&[1.5, 1.5, 1.5], &g, 0.0).unwrap(),
            RattleState::Unilateral
        );
    }

    #[test]
    fn rattle_states_rsv_and_order() {
        let b = 1.0;
        let contact = [1.5, 2.0, 1.2];
        assert_eq!(rattle_state(&contact, b, 0.0).unwrap().rsv(), 0);
        let neg = [-1.5, -2.0, -1.2];
        assert_eq!(rattle_state(&neg, b, 0.0).unwrap(), RattleState::NoRattle);
        let uni = [1.5, 0.0, 1.2];
        assert_eq!(rattle_state(&uni, b, 0.0).unwrap().rsv(), 1);
        let bi = [1.5, 0.0, -1.2];
        assert_eq!(rattle_state(&bi, b, 0.0).unwrap().rsv(), 2);
        assert_eq!(
            rattle_state(&[0.0, 0.5], b, 0.0).unwrap(),
            RattleState::NoContact
        );
        assert_eq!(RattleState::NoContact.rsv(), 1);
        // ordered by rsv: the worst state of a record is the max
        assert!(RattleState::NoRattle < RattleState::Unilateral);
        assert!(RattleState::NoContact < RattleState::Bilateral);
        assert!(rattle_state(&[], b, 0.0).is_err());
        assert!(rattle_state(&[1.0], f64::NAN, 0.0).is_err());
    }

    #[test]
    fn bad_inputs_name_their_field() {
        let e = |r: Result<RattleState, Error>| r.unwrap_err().to_string();
        assert!(e(rattle_state(&[], 1.0, 0.0)).contains("signal (length)"));
        assert!(e(rattle_state(&[0.0, f64::NAN], 1.0, 0.0)).contains("signal[1]"));
        assert!(e(rattle_state(&[0.0], f64::INFINITY, 0.0)).contains("gap"));
        assert!(e(rattle_state(&[0.0], -1.0, 0.0)).contains("gap[0]"));
        assert!(e(rattle_state(&[0.0], 1.0, -1.0)).contains("tol"));
        assert!(e(rattle_state_with_gap(&[0.0, 1.0], &[1.0], 0.0)).contains("gap (length)"));
        assert!(dynamic_factor(&[1.0], 0.0).is_err());
        assert!(dynamic_factor(&[], 1.0).is_err());
        assert!(rms_of_harmonics(&[f64::NAN]).is_err());
    }

    #[test]
    fn dynamic_factor_and_rms_exact() {
        assert_eq!(
            dynamic_factor(&[1.0, 3.0, 2.0], 1.5).unwrap().to_bits(),
            2.0f64.to_bits()
        );
        // RMS of (3, 4) over n = 2: sqrt(25 / 2)
        let r = rms_of_harmonics(&[3.0, 4.0]).unwrap();
        assert!((r - (12.5f64).sqrt()).abs() < 1e-15);
    }
}
