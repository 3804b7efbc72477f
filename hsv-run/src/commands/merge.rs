//! `hsv-run merge`: joins the shard folders of a trade study (`hsv-run trade --shard K/N`) into
//! the table one unsharded run gives: same study, every shard once, every case once.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use hsv_core::registry::Registry;

use super::trade::{CASES_FILE, write_table};
use super::{JsonFlag, OutArgs};
use crate::analysis::trade::{Shard, TradeCases, compare, merge_cases, read_costs};
use crate::output::{RunFolder, write_file};

/// Arguments of `hsv-run merge`.
#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// Shard output folders (each holds trade-cases.json), one per shard.
    #[arg(value_name = "DIR", required = true)]
    pub folders: Vec<PathBuf>,
    /// Per-model cost CSV `model,seconds`, as for `hsv-run trade --costs`.
    #[arg(long, value_name = "FILE")]
    pub costs: Option<PathBuf>,
    #[command(flatten)]
    pub output: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Reads the shard folders, merges and writes the trade table.
pub fn run(args: MergeArgs, _registry: &Registry) -> Result<()> {
    let mut parts = Vec::with_capacity(args.folders.len());
    for folder in &args.folders {
        let path = folder.join(CASES_FILE);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "cannot read {} (is {} a `hsv-run trade --shard` output folder?)",
                path.display(),
                folder.display()
            )
        })?;
        let part: TradeCases = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a trade-cases file", path.display()))?;
        parts.push((folder.display().to_string(), part));
    }
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
    // The merged cases, as an unsharded run writes them.
    let merged = TradeCases {
        spec: spec.clone(),
        shard: Shard::ALL,
        cases,
    };
    let path = folder.join(CASES_FILE);
    write_file(&path, serde_json::to_string_pretty(&merged)?)?;
    folder.record(path);
    let table = compare(&spec, merged.cases, costs.as_ref())?;
    write_table(&mut folder, &table, args.json.json)
}
