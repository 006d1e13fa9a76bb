//! The short `sin_cos` of the models' inner loops: [`math::short::sin_cos`] (its docs give the
//! reduction, the polynomials and the accuracy).

pub(crate) use math::short::sin_cos;
