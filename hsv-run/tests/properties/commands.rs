//! Property tests of whole commands (issue 26 item 7): `simulate`, `flutter`, `linearize` and
//! `trade` on tiny grids with random flags, extreme and non-finite values included, either
//! succeed with a readable JSON summary or fail with `error:` lines, never a panic, and within
//! the corpus's 60 s.
//!
//! The runs stay tiny (a few steps, one or two Mach points, full-order conduction so no POD
//! basis trains): the properties are about inputs, the physics is tested elsewhere.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crate::common::cli::{hsv_run, scratch_dir, stderr, stdout};
use crate::common::strategies::awkward;
use proptest::prelude::*;

/// The longest any run of the corpus may take.
const LIMIT: Duration = Duration::from_secs(60);

/// A fresh `--out` folder for each run.
fn out_dir() -> String {
    static RUN: AtomicUsize = AtomicUsize::new(0);
    static DIR: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    let dir = DIR.get_or_init(|| scratch_dir("runs"));
    let k = RUN.fetch_add(1, Ordering::Relaxed);
    dir.join(format!("run-{k}")).display().to_string()
}

/// Runs `hsv-run args... --json --out DIR` and checks the outcome: success with a JSON summary
/// on stdout, or failure with an `error:` line on stderr; no panic either way, within [`LIMIT`].
fn check_outcome(args: &[String]) -> Result<(), TestCaseError> {
    let out = out_dir();
    let mut all: Vec<&str> = args.iter().map(String::as_str).collect();
    all.extend(["--json", "--out", &out]);
    let start = Instant::now();
    let output = hsv_run(&all);
    let elapsed = start.elapsed();
    let err = stderr(&output);
    prop_assert!(elapsed < LIMIT, "{all:?} took {elapsed:?}");
    prop_assert!(!err.contains("panicked"), "{all:?} panicked: {err}");
    if output.status.success() {
        let json: Result<serde_json::Value, _> = serde_json::from_str(&stdout(&output));
        prop_assert!(
            json.is_ok(),
            "{all:?}: no JSON summary: {}",
            stdout(&output)
        );
    } else {
        // An `error:` line that says something (clap's usage errors add a tip and usage).
        let said = err
            .lines()
            .any(|l| l.starts_with("error: ") && l.len() > "error: ".len());
        prop_assert!(said, "{all:?}: unclear failure: {err}");
    }
    Ok(())
}

/// A float flag value as a user would type it (`NaN`, `inf` and `-inf` included).
fn flag(value: f64) -> String {
    format!("{value}")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4, failure_persistence: None, ..ProptestConfig::default() })]

    /// A heated flutter sweep on one to three Mach points, heated for up to two seconds.
    #[test]
    fn flutter_succeeds_or_fails_clearly(
        altitude_m in awkward(5_000.0..40_000.0),
        mach_low in awkward(2.0..8.0),
        mach_span in awkward(0.0..2.0),
        mach_step in awkward(0.7..2.0),
        time_s in awkward(0.0..2.0),
        dt_s in awkward(0.1..1.0),
        alpha_deg in awkward(-10.0..10.0),
    ) {
        check_outcome(&[
            "flutter".into(),
            "--conduction".into(), "full-order".into(),
            "--altitude-m".into(), flag(altitude_m),
            "--mach-range".into(), format!("{}:{}", mach_low, mach_low + mach_span),
            "--mach-step".into(), flag(mach_step),
            "--times-s".into(), format!("0,{time_s}"),
            "--dt-s".into(), flag(dt_s),
            "--alpha-deg".into(), flag(alpha_deg),
        ])?;
    }

    /// A rigid-model trade study of two body aero models at a random flight condition.
    #[test]
    fn trade_succeeds_or_fails_clearly(
        mach in awkward(3.0..10.0),
        altitude_m in awkward(15_000.0..40_000.0),
        threads in 0usize..4,
    ) {
        check_outcome(&[
            "trade".into(), "--quiet".into(),
            "--job".into(), "trim".into(),
            "--vary".into(), "main_body.aero=shock-expansion,newtonian-vector".into(),
            "--mach".into(), flag(mach),
            "--altitude-m".into(), flag(altitude_m),
            "--threads".into(), threads.to_string(),
        ])?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3, failure_persistence: None, ..ProptestConfig::default() })]

    /// A few steps of the unheated flexible vehicle from its trim, at a random step size.
    #[test]
    fn simulate_succeeds_or_fails_clearly(
        duration_s in awkward(0.0..0.02),
        dt_s in awkward(2e-4..2e-3),
        record_every in 0usize..5,
    ) {
        check_outcome(&[
            "simulate".into(), "--no-heating".into(),
            "--duration-s".into(), flag(duration_s),
            "--dt-s".into(), flag(dt_s),
            "--record-every".into(), record_every.to_string(),
        ])?;
    }

    /// The linear model of the trimmed flexible vehicle at random perturbation sizes.
    #[test]
    fn linearize_succeeds_or_fails_clearly(
        relative in awkward(1e-6..0.05),
        absolute in awkward(1e-8..1e-2),
    ) {
        check_outcome(&[
            "linearize".into(),
            "--relative".into(), flag(relative),
            "--absolute".into(), flag(absolute),
        ])?;
    }
}
