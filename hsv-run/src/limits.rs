//! Limits on the counts a user sets (threads, shards, Mach points, times, modes, elements,
//! steps), checked before any work starts so an absurd request is refused with its limit
//! instead of running for hours or exhausting memory. Time steps have their own rule in
//! [`crate::steps`] ([`crate::steps::MAX_STEPS`]).

/// Most worker threads a job may start (far more than any node; 10⁵ threads exhaust memory
/// before the first case runs).
pub const MAX_THREADS: usize = 1024;
/// Most shards a study may be split into (one Slurm array of this size is already huge).
pub const MAX_SHARDS: usize = 10_000;
/// Most Mach points of a flutter grid.
pub const MAX_MACH_POINTS: usize = 400;
/// Most times of a flutter map.
pub const MAX_FLUTTER_TIMES: usize = 1000;
/// Most conduction steps of a flutter map's heating (10⁵: 10⁴ s at the default 0.1 s step,
/// a hundred times the paper's longest 100 s; each step is a full conduction solve).
pub const MAX_HEATING_STEPS: u64 = 100_000;
/// Most free-vibration modes of a panel basis or a trained reduced-order model.
pub const MAX_MODES: usize = 500;
/// Most finite elements each way of a panel.
pub const MAX_PANEL_ELEMENTS: usize = 200;
/// Most full-order snapshot runs that train a POD basis (each is a full heating run).
pub const MAX_SNAPSHOT_RUNS: usize = 20;
/// Most steps per period or periods of a ROM check response.
pub const MAX_CHECK_STEPS: usize = 1_000_000;

/// `value_deg` if it is a finite flow angle within ±[`hsv_core::config::MAX_FLOW_ANGLE_DEG`]
/// (the rule config files obey too), else an error naming `what`.
pub fn check_flow_angle_deg(what: &str, value_deg: f64) -> anyhow::Result<f64> {
    hsv_core::config::flow_angle_deg(value_deg)
        .map_err(|message| anyhow::anyhow!("{what} {message}"))
}

/// A count outside its limit.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} must be from {min} to {max}, got {value}")]
pub struct CountError {
    pub what: String,
    pub value: usize,
    pub min: usize,
    pub max: usize,
}

/// `value` if `min <= value <= max`, else an error naming `what` (a flag or key) and the range.
pub fn check_count(what: &str, value: usize, min: usize, max: usize) -> Result<usize, CountError> {
    if value < min || value > max {
        return Err(CountError {
            what: what.to_owned(),
            value,
            min,
            max,
        });
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_inside_its_range_passes_and_outside_names_the_range() {
        assert_eq!(check_count("--threads", 8, 0, MAX_THREADS), Ok(8));
        let err = check_count("--threads", 100_000, 0, MAX_THREADS).unwrap_err();
        assert_eq!(
            err.to_string(),
            "--threads must be from 0 to 1024, got 100000"
        );
        assert!(check_count("--panel-modes", 0, 1, MAX_MODES).is_err());
    }
}
