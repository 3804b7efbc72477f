//! `hsv-run merge`: joins shard folders into the outputs one unsharded run gives, with the
//! shared machinery of [`crate::analysis::shards`] (same study, every shard once, every case
//! once) and the writers the sharded commands use ([`super::shared`]): the table of a trade
//! study (`hsv-run trade --shard K/N`), the flutter map of `hsv-run flutter --shard K/N`, whose
//! flutter boundary it finds on the merged grid, or the linear models of `hsv-run linearize
//! --grid --shard K/N`.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::registry::Registry;
use serde::Serialize;
use serde::de::DeserializeOwned;

use super::shared::flutter_map::write_run;
use super::shared::linear_grid::write_grid_folder;
use super::shared::trade_table::write_table;
use super::{JsonFlag, OutArgs, load_config};
use crate::analysis::linear_grid::{GRID_CASES_FILE, LinearGridShard};
use crate::analysis::shards::{
    FLUTTER_CASES_FILE, FlutterShard, Shard, ShardOutput, map_from_columns, merge_shards,
};
use crate::analysis::trade::{CASES_FILE, TradeCases, compare, merge_cases, read_costs};
use crate::output::{RunFolder, write_file};

/// Arguments of `hsv-run merge`.
#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// Shard output folders (each holds trade-cases.json, flutter-cases.json or
    /// linear-grid-cases.json), one per shard.
    #[arg(value_name = "DIR", required = true)]
    pub folders: Vec<PathBuf>,
    /// Per-model cost CSV `model,seconds`, as for `hsv-run trade --costs` (trade studies).
    #[arg(long, value_name = "FILE")]
    pub costs: Option<PathBuf>,
    #[command(flatten)]
    pub output: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Reads `file` from every shard folder, named by its folder.
fn read_parts<T: DeserializeOwned>(folders: &[PathBuf], file: &str) -> Result<Vec<(String, T)>> {
    folders
        .iter()
        .map(|folder| {
            let path = folder.join(file);
            let text = std::fs::read_to_string(&path).with_context(|| {
                format!(
                    "cannot read {} (is {} a `hsv-run trade --shard` or `hsv-run flutter \
                     --shard` output folder?)",
                    path.display(),
                    folder.display()
                )
            })?;
            let part = serde_json::from_str(&text)
                .with_context(|| format!("{} is not a {file} file", path.display()))?;
            Ok((folder.display().to_string(), part))
        })
        .collect()
}

/// Writes the merged cases into `file` of the run folder, as an unsharded run writes them.
fn write_merged<S: Serialize, C: Serialize>(
    folder: &mut RunFolder,
    file: &str,
    merged: &ShardOutput<S, C>,
) -> Result<()> {
    let path = folder.join(file);
    write_file(&path, serde_json::to_string_pretty(merged)?)?;
    folder.record(path);
    Ok(())
}

/// Reads the shard folders, merges and writes the trade table or the flutter map.
pub fn run(args: MergeArgs, registry: &Registry) -> Result<()> {
    let flutter = args
        .folders
        .first()
        .is_some_and(|f| f.join(FLUTTER_CASES_FILE).exists());
    if flutter {
        return merge_flutter(&args, registry);
    }
    if (args.folders.first()).is_some_and(|f| f.join(GRID_CASES_FILE).exists()) {
        return merge_linear_grid(&args);
    }
    let parts: Vec<(String, TradeCases)> = read_parts(&args.folders, CASES_FILE)?;
    let (spec, cases) = merge_cases(parts)?;
    let costs = args
        .costs
        .as_deref()
        .map(|path| {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read --costs {}", path.display()))?;
            read_costs(&text, &path.display().to_string())
        })
        .transpose()?;
    let mut folder = RunFolder::create("merge", args.output.out.as_deref(), args.output.force)?;
    let merged = TradeCases {
        spec: spec.clone(),
        shard: Shard::ALL,
        cases,
    };
    write_merged(&mut folder, CASES_FILE, &merged)?;
    let table = compare(&spec, merged.cases, costs.as_ref())?;
    write_table(&mut folder, &table, args.json.json)
}

/// Flutter shards: the merged Mach columns, the boundary at each time by bracketing on the
/// merged grid and Brent's method (new marches, on the config the shards ran on), and the
/// flutter command's outputs.
fn merge_flutter(args: &MergeArgs, registry: &Registry) -> Result<()> {
    if args.costs.is_some() {
        bail!("--costs is for trade studies; these are flutter shards");
    }
    let parts: Vec<(String, FlutterShard)> = read_parts(&args.folders, FLUTTER_CASES_FILE)?;
    let (spec, columns) = merge_shards(parts)?;
    let (loaded, registry) = load_config(spec.config.as_deref(), registry)?;
    let setup = spec.setup(&loaded)?;
    let mut folder = RunFolder::create("merge", args.output.out.as_deref(), args.output.force)?;
    let merged = FlutterShard {
        spec: spec.clone(),
        shard: Shard::ALL,
        cases: columns,
    };
    write_merged(&mut folder, FLUTTER_CASES_FILE, &merged)?;
    let map = folder.run(
        |_| map_from_columns(&spec, &setup, &registry, merged.cases),
        || serde_json::json!({"command": "merge"}),
    )?;
    write_run(&mut folder, &setup, &map, args.json.json)
}

/// Linear-model grid shards: the merged points and the `.npz` an unsharded grid writes.
fn merge_linear_grid(args: &MergeArgs) -> Result<()> {
    if args.costs.is_some() {
        bail!("--costs is for trade studies; these are linear-model grid shards");
    }
    let parts: Vec<(String, LinearGridShard)> = read_parts(&args.folders, GRID_CASES_FILE)?;
    let (spec, cases) = merge_shards(parts)?;
    let mut folder = RunFolder::create("merge", args.output.out.as_deref(), args.output.force)?;
    let merged = LinearGridShard {
        spec,
        shard: Shard::ALL,
        cases,
    };
    write_grid_folder(&mut folder, &merged, args.json.json)
}
