//! hsv-benches: criterion benchmarks comparing models on the sample vehicle; see `benches/`.
