//! A linear-model grid's run folder: its points ([`GRID_CASES_FILE`]), the `.npz` of a whole
//! grid ([`GRID_NPZ_FILE`]), the summary and the line on standard output, as `hsv-run
//! linearize --grid` and `hsv-run merge` of grid shards write them.

use anyhow::Result;

use crate::analysis::linear_grid::{
    GRID_CASES_FILE, GRID_NPZ_FILE, LinearGridShard, write_grid_npz,
};
use crate::outln;
use crate::output::{RunFolder, RunStatus, write_file};

/// Writes a grid's (or a shard's) points, the `.npz` when they are the whole grid, and the
/// summary; prints where they are.
pub fn write_grid_folder(
    folder: &mut RunFolder,
    output: &LinearGridShard,
    json: bool,
) -> Result<()> {
    let path = folder.join(GRID_CASES_FILE);
    write_file(&path, serde_json::to_string_pretty(output)?)?;
    folder.record(path);
    let whole = output.shard.count == 1;
    if whole {
        let path = folder.join(GRID_NPZ_FILE);
        write_grid_npz(&path, &output.spec, &output.cases)?;
        folder.record(path);
    }
    let failed: Vec<serde_json::Value> = (output.cases.iter())
        .filter_map(|p| {
            let error = p.error.as_ref()?;
            Some(serde_json::json!({"mach": p.mach, "altitude_m": p.altitude_m, "error": error}))
        })
        .collect();
    let summary = serde_json::json!({
        "command": "linearize",
        "grid": {"mach": output.spec.machs, "altitude_m": output.spec.altitudes_m},
        "shard": format!("{}/{}", output.shard.index, output.shard.count),
        "points": output.cases.len(),
        "failed": failed,
    });
    let written = folder.write_summary(summary, &RunStatus::Completed)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
        return Ok(());
    }
    outln!(
        "{} of {} grid points linearized{}; outputs in {}",
        output.cases.len() - failed.len(),
        output.cases.len(),
        if whole {
            format!(" ({GRID_NPZ_FILE})")
        } else {
            "; join the shard folders with `hsv-run merge DIR...`".to_owned()
        },
        folder.path.display()
    )?;
    Ok(())
}
