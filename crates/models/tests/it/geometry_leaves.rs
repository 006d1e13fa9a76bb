//! The spur-pair geometry is held by two leaves that do not depend on each other:
//! `gear_geometry::SpurPair` (geometry studies, the generic pair) and `backlash::PairGeometry`
//! (the dynamic backlash the Yu model uses). The pressure-angle law and the centre-distance form
//! are one definition (`system::PressureAngleLaw`, `system::CentreDistanceForm`) that both
//! re-export; this checks that the two leaves feed it the same pair (nominal distance, base
//! radii) and apply it alike (the geometry leaf rejects `a` below the law's domain, the
//! backlash leaf clamps), over a grid of centre displacements.

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
