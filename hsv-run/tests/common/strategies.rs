//! Proptest strategies the property tests share.

use proptest::prelude::*;

/// A number from `range`, or one of the values that break naive code.
pub fn awkward(range: std::ops::Range<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => range,
        1 => prop::sample::select(vec![
            0.0,
            -0.0,
            -1.0,
            1e-300,
            1e300,
            -1e300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]),
    ]
}
