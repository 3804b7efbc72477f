//! hsv-tests: cross-crate integration and validation tests; the tests live in `tests/`.
