//! `hsv-run flutter --shard K/N` and `--emit-slurm N`: the flutter map's Mach columns split
//! over a cluster with the shared shard machinery ([`crate::commands::shared::shard`]).

use anyhow::Result;
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;

use super::FlutterArgs;
use crate::analysis::flutter::DerivativeMethod;
use crate::analysis::flutter::sweep::FlutterSetup;
use crate::analysis::shards::{FLUTTER_CASES_FILE, FlutterMapSpec, ShardedStudy, march_shard};
use crate::commands::shared::shard::{SlurmJob, absolute, emit_slurm};
use crate::outln;
use crate::output::{RunFolder, RunStatus, write_file};

/// The `hsv-run flutter` arguments every shard runs: the map as resolved here.
fn flutter_shard_arguments(args: &FlutterArgs, spec: &FlutterMapSpec) -> Result<Vec<String>> {
    let mut line = vec!["flutter".to_owned()];
    if let Some(config) = &spec.config {
        line.extend(["--config".to_owned(), config.display().to_string()]);
    }
    let times = spec
        .times_s
        .iter()
        .map(f64::to_string)
        .collect::<Vec<_>>()
        .join(",");
    line.extend([
        "--altitude-m".to_owned(),
        spec.altitude_m.to_string(),
        "--mach-range".to_owned(),
        args.mach_range.clone(),
        "--mach-step".to_owned(),
        args.mach_step.to_string(),
        format!("--times-s={times}"),
        "--aero".to_owned(),
        spec.models.aero.clone(),
        "--heat-flux".to_owned(),
        spec.models.heat_flux.clone(),
        "--conduction".to_owned(),
        spec.models.conduction.clone(),
        "--dt-s".to_owned(),
        spec.heating_dt_s.to_string(),
        "--derivative".to_owned(),
        match spec.method {
            DerivativeMethod::Direct => "direct",
            DerivativeMethod::ForwardDifference => "forward-difference",
        }
        .to_owned(),
    ]);
    if let Some(alpha) = args.alpha_deg {
        line.extend(["--alpha-deg".to_owned(), alpha.to_string()]);
    }
    if !spec.compare_methods {
        line.push("--no-compare".to_owned());
    }
    Ok(line)
}

/// `hsv-run flutter --shard K/N`: marches the shard's Mach columns and writes
/// `flutter-cases.json` (what `hsv-run merge` joins); `--emit-slurm N`: the Slurm scripts.
pub fn run_shard(
    args: &FlutterArgs,
    loaded: &LoadedConfig,
    registry: &Registry,
    setup: &FlutterSetup,
    machs: &[f64],
    times_s: &[f64],
) -> Result<()> {
    let config = args.config.config.as_deref().map(absolute).transpose()?;
    let spec = FlutterMapSpec::new(setup, machs, times_s, config, loaded)?;
    let mut folder = RunFolder::create("flutter", args.out.out.as_deref(), args.out.force)?;
    if let Some(shards) = args.shards.emit_slurm {
        let job = SlurmJob {
            command: "flutter",
            what: "flutter-map",
            arguments: flutter_shard_arguments(args, &spec)?,
            merge_arguments: Vec::new(),
            cases: spec.case_count(),
            merge_computes: true,
        };
        return emit_slurm(&args.shards, &job, shards, &mut folder, args.json.json);
    }
    let shard = args.shards.shard()?;
    let output = march_shard(&spec, setup, registry, shard)?;
    let path = folder.join(FLUTTER_CASES_FILE);
    write_file(&path, serde_json::to_string_pretty(&output)?)?;
    folder.record(path);
    let summary = serde_json::json!({
        "command": "flutter",
        "shard": format!("{}/{}", shard.index, shard.count),
        "mach_columns": output.cases.iter().map(|c| c.mach).collect::<Vec<_>>(),
        "times_s": spec.times_s,
    });
    let written = folder.write_summary(summary, &RunStatus::Completed)?;
    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        outln!(
            "flutter shard {}/{}: Mach {:?} at {} times in {}; join the shard folders with \
             `hsv-run merge DIR...`",
            shard.index,
            shard.count,
            output.cases.iter().map(|c| c.mach).collect::<Vec<_>>(),
            spec.times_s.len(),
            folder.path.display()
        )?;
    }
    Ok(())
}
