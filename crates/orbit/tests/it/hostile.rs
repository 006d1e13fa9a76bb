//! Hostile inputs end in typed errors, never in a panic or a hang.

use crate::common::{Bilinear, ImpactOscillator, Rattle, bilinear};
use nalgebra::DMatrix;
use orbit::{
    ContinuationOptions, FlowOptions, OrbitError, OrbitProblem, Parameter, Restitution,
    ShootingCorrection, ShootingOptions,
};
use system::SecondOrderSystem;

#[test]
fn bad_periods_and_states_are_rejected() {
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            OrbitProblem::new(bilinear(), t),
            Err(OrbitError::InvalidInput {
                field: "period",
                ..
            })
        ));
    }
    let p = OrbitProblem::new(bilinear(), 4.0).unwrap();
    assert!(matches!(
        p.shoot(&[f64::NAN, 0.0], &ShootingOptions::default()),
        Err(OrbitError::NonFinite { .. })
    ));
    assert!(matches!(
        p.shoot(&[0.0], &ShootingOptions::default()),
        Err(OrbitError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        p.flow(0.0, &[0.0, 0.0], 0.0, false),
        Err(OrbitError::InvalidInput {
            field: "duration",
            ..
        })
    ));
    assert!(matches!(
        p.flow(f64::NAN, &[0.0, 0.0], 1.0, false),
        Err(OrbitError::InvalidInput { field: "t0", .. })
    ));
    assert!(p.clone_free_with_phase(f64::INFINITY).is_err());
}

trait PhaseCheck {
    fn clone_free_with_phase(&self, t0: f64) -> orbit::Result<()>;
}
impl PhaseCheck for OrbitProblem<Bilinear> {
    fn clone_free_with_phase(&self, t0: f64) -> orbit::Result<()> {
        OrbitProblem::new(*self.system(), self.period())?
            .with_phase(t0)
            .map(|_| ())
    }
}

#[test]
fn bad_options_name_their_field() {
    let p = OrbitProblem::new(bilinear(), 4.0).unwrap();
    let bad = [
        ShootingOptions {
            periods: 0,
            ..Default::default()
        },
        ShootingOptions {
            segments: 0,
            ..Default::default()
        },
        ShootingOptions {
            tol: f64::NAN,
            ..Default::default()
        },
        ShootingOptions {
            tol: -1.0,
            ..Default::default()
        },
        ShootingOptions {
            max_iter: 0,
            ..Default::default()
        },
    ];
    for o in bad {
        assert!(
            matches!(
                p.shoot(&[0.0, 0.0], &o),
                Err(OrbitError::InvalidInput { .. })
            ),
            "{o:?}"
        );
    }
    for f in [
        FlowOptions {
            rtol: 0.0,
            ..Default::default()
        },
        FlowOptions {
            atol: f64::NAN,
            ..Default::default()
        },
        FlowOptions {
            max_step_fraction: 2.0,
            ..Default::default()
        },
        FlowOptions {
            max_steps: 0,
            ..Default::default()
        },
        FlowOptions {
            event_tol: -1.0,
            ..Default::default()
        },
    ] {
        assert!(
            OrbitProblem::new(bilinear(), 4.0)
                .unwrap()
                .with_flow_options(f)
                .is_err()
        );
    }
    let mut p = OrbitProblem::new(bilinear(), 4.0).unwrap();
    for c in [
        ContinuationOptions {
            corrector: ShootingCorrection {
                range: [1.0, 0.0],
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
        ContinuationOptions {
            corrector: ShootingCorrection {
                direction: 0.5,
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
        ContinuationOptions {
            min_step: 0.0,
            ..Default::default()
        },
        ContinuationOptions {
            initial_step: 10.0,
            ..Default::default()
        },
        ContinuationOptions {
            corrector: ShootingCorrection {
                parameter_scale: f64::NAN,
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
        ContinuationOptions {
            corrector: ShootingCorrection {
                locate_tol: 0.0,
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
        ContinuationOptions {
            corrector: ShootingCorrection {
                locate_samples: 0,
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
        ContinuationOptions {
            corrector: ShootingCorrection {
                shooting: ShootingOptions {
                    segments: 2,
                    ..Default::default()
                },
                ..ShootingCorrection::default()
            },
            ..Default::default()
        },
    ] {
        assert!(
            matches!(
                p.continuation(&[0.0, 0.0], 1.5, &c),
                Err(OrbitError::InvalidInput { .. })
            ),
            "{c:?}"
        );
    }
    assert!(
        p.continuation(&[0.0, 0.0], f64::NAN, &ContinuationOptions::default())
            .is_err()
    );
    assert!(matches!(
        p.set_parameter(&Parameter::Named("nope".into()), 1.0),
        Err(OrbitError::System(_))
    ));
    assert!(p.set_parameter(&Parameter::BaseFrequency, 0.0).is_err());
    assert!(Restitution::new(0, 1.5, vec![0]).is_err());
    assert!(Restitution::new(0, f64::NAN, vec![0]).is_err());
}

/// A system whose force is NaN, one whose mass matrix is singular, one that blows up.
#[derive(Debug, Clone, Copy)]
struct Bad {
    kind: u8,
}
impl SecondOrderSystem for Bad {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, if self.kind == 1 { 0.0 } else { 1.0 })
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::zeros(1, 1)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _v: &[f64], g: &mut [f64]) {
        g[0] = match self.kind {
            0 => f64::NAN,
            2 => -q[0].powi(3), // q'' = q³: finite-time blow-up
            _ => q[0],
        };
    }
    fn forcing(&self, _t: f64, f: &mut [f64]) {
        f[0] = 0.0;
    }
}

#[test]
fn broken_models_give_errors() {
    let p = OrbitProblem::new(Bad { kind: 0 }, 1.0).unwrap();
    assert!(matches!(
        p.flow(0.0, &[0.0, 0.0], 1.0, false),
        Err(OrbitError::NonFinite { .. })
    ));
    assert!(matches!(
        OrbitProblem::new(Bad { kind: 1 }, 1.0),
        Err(OrbitError::Singular { .. })
    ));
    let p = OrbitProblem::new(Bad { kind: 2 }, 10.0).unwrap();
    let r = p.flow(0.0, &[2.0, 0.0], 10.0, false);
    assert!(r.is_err(), "{r:?}");
    assert!(p.shoot(&[2.0, 0.0], &ShootingOptions::default()).is_err());
}

#[test]
fn newton_reports_non_convergence() {
    let s = Rattle {
        zeta: 0.05,
        b: 0.5,
        f0: 0.1,
        f: 1.2,
        omega: 1.2,
    };
    let p = OrbitProblem::new(s, 2.0 * std::f64::consts::PI / 1.2).unwrap();
    let r = p.shoot(
        &[3.0, -2.0],
        &ShootingOptions {
            max_iter: 1,
            ..Default::default()
        },
    );
    assert!(matches!(r, Err(OrbitError::NotConverged { .. })), "{r:?}");
}

/// A ball on a vibrating table with `r = 1` never settles, but one with an absurd event cap
/// stops with `TooManyEvents`; a step cap stops a long flow with `TooManySteps`.
#[test]
fn caps_end_the_flow() {
    let s = ImpactOscillator {
        zeta: 0.0,
        sigma: 0.0,
        omega: 2.0,
    };
    let p = OrbitProblem::new(s, std::f64::consts::PI)
        .unwrap()
        .with_impacts(Restitution::new(0, 1.0, vec![0]).unwrap())
        .with_flow_options(FlowOptions {
            max_events: 2,
            ..Default::default()
        })
        .unwrap();
    let r = p.flow(0.0, &[-0.1, 1.0], 100.0, false);
    assert!(matches!(r, Err(OrbitError::TooManyEvents { .. })), "{r:?}");
    let p = OrbitProblem::new(bilinear(), 4.0)
        .unwrap()
        .with_flow_options(FlowOptions {
            max_steps: 10,
            ..Default::default()
        })
        .unwrap();
    assert!(matches!(
        p.flow(0.0, &[0.0, 0.0], 100.0, false),
        Err(OrbitError::TooManySteps { .. })
    ));
}

#[test]
fn shooting_stops_at_the_threads_deadline() {
    let p = OrbitProblem::new(bilinear(), 4.0).unwrap();
    let r = system::deadline::scope(Some(std::time::Instant::now()), || {
        p.shoot(&[0.0, 0.0], &ShootingOptions::default())
    });
    match r {
        Err(e @ OrbitError::TimeLimit { .. }) => {
            assert!(e.to_string().starts_with(system::deadline::REASON), "{e}")
        }
        other => panic!("{other:?}"),
    }
    // without a deadline the same orbit is found
    assert!(p.shoot(&[0.0, 0.0], &ShootingOptions::default()).is_ok());
}
