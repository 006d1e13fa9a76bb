//! The Liu model as a system of the `orbit` crate with named continuation parameters
//! ([`Parametric`]): the one home of the Liu system that branches and codim-2 curves change.

use system::{Direction, SecondOrderSystem, SystemError};

use super::{Model, Parameters};

/// Table 1 entries a [`Parametric`] system can change, with their units: the load torque `T₂`,
/// the relative stiffness amplitude `a_k = k_r/k₀` (Eq. 19), the damping ratio `ζ` and the
/// error amplitude `e_r`. None of them moves the frequency scale `ω̄_c` or the length scale of
/// the dimensionless model (Eqs. 8–12), so a branch in one of them stays in one state space
/// and one period; the base frequency (the pinion speed `ω₁`) is
/// [`SecondOrderSystem::set_base_frequency`].
pub const PARAMETERS: [(&str, &str); 4] = [
    ("load_torque", "N·m"),
    ("ak", "1"),
    ("damping_ratio", "1"),
    ("er", "m"),
];

/// The Liu model with its parameter set, so that a Table 1 entry of [`PARAMETERS`] can be a
/// continuation parameter: the model is rebuilt from the parameters at every change (no
/// accumulated scaling), and keeps its present `ω̄_c` (which the base frequency sets).
#[derive(Debug, Clone)]
pub struct Parametric {
    p: Parameters,
    m: Model,
}

impl Parametric {
    /// The model of `p` with `p` kept for rebuilding.
    ///
    /// # Errors
    /// The parameters' validation ([`Parameters::model`]).
    pub fn new(p: Parameters) -> Result<Self, crate::Error> {
        let m = p.model()?;
        Ok(Self { p, m })
    }

    /// The present model.
    pub fn model(&self) -> &Model {
        &self.m
    }

    /// The present parameter set (its `omega1` is the one it was built with: the base
    /// frequency is the model's `ω̄_c`).
    pub fn parameters(&self) -> &Parameters {
        &self.p
    }
}

fn unknown(name: &str, value: f64) -> SystemError {
    SystemError::invalid(name, "load_torque, ak, damping_ratio or er", value)
}

impl SecondOrderSystem for Parametric {
    fn n_dof(&self) -> usize {
        SecondOrderSystem::n_dof(&self.m)
    }
    fn mass(&self) -> nalgebra::DMatrix<f64> {
        SecondOrderSystem::mass(&self.m)
    }
    fn damping(&self) -> nalgebra::DMatrix<f64> {
        SecondOrderSystem::damping(&self.m)
    }
    fn stiffness(&self) -> nalgebra::DMatrix<f64> {
        SecondOrderSystem::stiffness(&self.m)
    }
    fn nonlinear_force(&self, t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
        SecondOrderSystem::nonlinear_force(&self.m, t, q, qd, g);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        SecondOrderSystem::forcing(&self.m, t, f);
    }
    fn force_jacobian(&self, t: f64, q: &[f64], qd: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        SecondOrderSystem::force_jacobian(&self.m, t, q, qd, dq, dv);
    }
    fn n_events(&self) -> usize {
        SecondOrderSystem::n_events(&self.m)
    }
    fn events(&self, t: f64, q: &[f64], qd: &[f64], e: &mut [f64]) {
        SecondOrderSystem::events(&self.m, t, q, qd, e);
    }
    // the time table and the shared time functions of the model (the same values as the
    // direct evaluations above, bit for bit: the trait's contract, tested in `liu2021`), so
    // that the orbit flow takes each `sin`/`cos` of `τ` once per stage time; not the grid
    // tabulation (`tabulate_grid`), whose quarter-circle form differs at rounding level
    fn time_table_len(&self) -> usize {
        SecondOrderSystem::time_table_len(&self.m)
    }
    fn fill_time_table(&self, t: f64, row: &mut [f64]) {
        SecondOrderSystem::fill_time_table(&self.m, t, row);
    }
    fn fill_time_functions(&self, t: f64, f: &mut [f64], row: &mut [f64]) {
        SecondOrderSystem::fill_time_functions(&self.m, t, f, row);
    }
    fn nonlinear_force_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], g: &mut [f64]) {
        SecondOrderSystem::nonlinear_force_tabulated(&self.m, t, row, q, qd, g);
    }
    fn force_jacobian_tabulated(
        &self,
        t: f64,
        row: &[f64],
        q: &[f64],
        qd: &[f64],
        dq: &mut [f64],
        dv: &mut [f64],
    ) {
        SecondOrderSystem::force_jacobian_tabulated(&self.m, t, row, q, qd, dq, dv);
    }
    fn events_tabulated(&self, t: f64, row: &[f64], q: &[f64], qd: &[f64], e: &mut [f64]) {
        SecondOrderSystem::events_tabulated(&self.m, t, row, q, qd, e);
    }
    fn event_direction(&self, index: usize) -> Direction {
        SecondOrderSystem::event_direction(&self.m, index)
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SystemError> {
        let mut p = self.p;
        match name {
            "load_torque" => p.load_torque = value,
            "ak" => p.kr = value * p.k0,
            "damping_ratio" => p.damping_ratio = value,
            "er" => p.er = value,
            _ => return Err(unknown(name, value)),
        }
        let mut m = p
            .model()
            .map_err(|_| SystemError::invalid(name, "a valid Liu parameter set", value))?;
        // none of the parameters moves ω̄_c; after a change of the base frequency (a codim-2
        // curve in ω1 and this parameter) the model keeps the present ω̄_c
        if m.omega_c.to_bits() != self.m.omega_c.to_bits() {
            m = m
                .with_omega_c(self.m.omega_c)
                .map_err(|_| SystemError::invalid(name, "a valid ω̄_c", value))?;
        }
        self.p = p;
        self.m = m;
        Ok(())
    }
    fn set_base_frequency(&mut self, omega: f64) -> Result<(), SystemError> {
        self.m = self
            .m
            .with_omega_c(omega)
            .map_err(|_| SystemError::invalid("liu2021.omega_c", "> 0", omega))?;
        Ok(())
    }
    fn parameter(&self, name: &str) -> Result<f64, SystemError> {
        match name {
            "load_torque" => Ok(self.p.load_torque),
            "ak" => Ok(self.p.kr / self.p.k0),
            "damping_ratio" => Ok(self.p.damping_ratio),
            "er" => Ok(self.p.er),
            _ => Err(unknown(name, f64::NAN)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::liu2021::table1;

    #[test]
    fn every_parameter_round_trips_and_keeps_the_frequency_scale() {
        let mut s = Parametric::new(table1()).unwrap();
        let wc = s.model().omega_c;
        s.set_base_frequency(1.25 * wc).unwrap();
        for (name, _) in PARAMETERS {
            let v = 1.1 * s.parameter(name).unwrap() + 1e-7;
            s.set_parameter(name, v).unwrap();
            assert!((s.parameter(name).unwrap() - v).abs() <= 1e-15 * v.abs());
            assert_eq!(s.model().omega_c.to_bits(), (1.25 * wc).to_bits(), "{name}");
        }
        // the changed model is the one its parameters build (up to the kept ω̄_c)
        let direct = s
            .parameters()
            .model()
            .unwrap()
            .with_omega_c(1.25 * wc)
            .unwrap();
        assert_eq!(direct.b3.to_bits(), s.model().b3.to_bits());
        assert_eq!(direct.b1.to_bits(), s.model().b1.to_bits());
        assert!(s.set_parameter("backlash", 1.0).is_err());
        assert!(s.set_parameter("damping_ratio", -1.0).is_err());
        assert!(s.parameter("omega1").is_err());
        assert!(s.set_base_frequency(-1.0).is_err());
    }
}
