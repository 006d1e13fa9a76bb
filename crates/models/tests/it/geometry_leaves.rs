//! The spur-pair geometry is one type, `system::PairGeometry`: the backlash leaf re-exports it
//! (`backlash::PairGeometry`, the dynamic backlash the Yu model uses) and
//! `gear_geometry::SpurPair` (geometry studies, the generic pair) is built on it. The
//! pressure-angle law and the centre-distance form are one definition
//! (`system::PressureAngleLaw`, `system::CentreDistanceForm`) that both re-export; this checks
//! that the two leaves give the same pair (nominal distance, base radii) and apply the law alike
//! (the geometry leaf rejects `a` below the law's domain, the backlash leaf clamps), over a grid
//! of centre displacements.

use backlash::{CentreDisplacement, PairGeometry, PressureAngleLaw};
use gear_geometry::{SpurPair, SpurPairParams};

/// Both leaves name the one law of `system` (a second enum would not compile here).
#[test]
fn one_law_for_both_leaves() {
    let same = |l: gear_geometry::PressureAngleLaw| -> backlash::PressureAngleLaw { l };
    assert_eq!(
        same(system::PressureAngleLaw::default()),
        PressureAngleLaw::Involute
    );
    let form = |f: gear_geometry::CentreDistanceForm| -> backlash::CentreDistanceForm { f };
    assert_eq!(
        form(system::CentreDistanceForm::default()),
        backlash::CentreDistanceForm::PrintedEq8
    );
}

/// One geometry type: the backlash leaf's is `system`'s, and the geometry leaf's pair hands out
/// the same value it was built from (a second type would not compile here).
#[test]
fn one_geometry_type_for_both_leaves() {
    let same = |g: system::PairGeometry| -> backlash::PairGeometry { g };
    let s = SpurPair::from_module(3e-3, 50, 50, 20f64.to_radians()).unwrap();
    let g = same(s.geometry());
    assert_eq!(
        g,
        PairGeometry::new(0.075, 0.075, 20f64.to_radians()).unwrap()
    );
    assert_eq!(
        s.params(),
        SpurPairParams {
            rp: 0.075,
            rg: 0.075,
            pressure_angle: g.alpha0
        }
    );
    // each leaf names an out-of-range field in its own words
    let e = SpurPair::new(SpurPairParams {
        rp: -1.0,
        rg: 0.1,
        pressure_angle: 0.3,
    })
    .unwrap_err();
    assert!(e.to_string().starts_with("rp"), "{e}");
    let e = backlash::Error::from(PairGeometry::new(0.1, 0.1, 2.0).unwrap_err());
    assert!(e.to_string().starts_with("alpha0"), "{e}");
}

#[test]
fn spur_pair_geometry_agrees_between_the_leaves() {
    for (rp, rg, alpha0) in [
        (0.094, 0.094, 20f64.to_radians()),
        (0.075, 0.15, 20f64.to_radians()),
        (0.03, 0.09, 25f64.to_radians()),
    ] {
        let s = SpurPair::new(SpurPairParams {
            rp,
            rg,
            pressure_angle: alpha0,
        })
        .unwrap();
        let b = PairGeometry::new(rp, rg, alpha0).unwrap();
        assert_eq!(s.nominal_centre_distance().to_bits(), b.a0().to_bits());
        let (rpb, rgb) = s.base_radii();
        assert!((rpb - b.r_pb()).abs() <= 1e-15 * rpb);
        assert!((rpb + rgb - b.base_sum()).abs() <= 1e-15 * (rpb + rgb));
        for &(xp, yp, xg, yg) in &[
            (0.0, 0.0, 0.0, 0.0),
            (1e-6, -2e-6, -3e-6, 4e-7),
            (2e-5, 1e-5, -1e-5, -3e-5),
            (1e-4, 0.0, 0.0, 2e-4),
        ] {
            let a_geo = s.centre_distance(xp, yp, xg, yg);
            let (a_bl, _, _) = b.centre_distance(&CentreDisplacement::new(xp, yp, xg, yg));
            assert!((a_geo - a_bl).abs() <= 1e-15 * a_geo, "{a_geo} vs {a_bl}");
            let consistent = s
                .operating_pressure_angle(a_geo, PressureAngleLaw::Involute)
                .unwrap();
            let (involute, _) = b.pressure_angle(a_bl, PressureAngleLaw::Involute);
            assert!(
                (consistent - involute).abs() <= 1e-12,
                "{consistent} vs {involute}"
            );
            if a_geo > s.nominal_centre_distance() {
                let printed = s
                    .operating_pressure_angle(a_geo, PressureAngleLaw::PrintedEq16)
                    .unwrap();
                let (printed_bl, _) = b.pressure_angle(a_bl, PressureAngleLaw::PrintedEq16);
                assert!(
                    (printed - printed_bl).abs() <= 1e-12,
                    "{printed} vs {printed_bl}"
                );
            }
        }
    }
}
