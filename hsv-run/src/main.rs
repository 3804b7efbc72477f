//! `hsv-run`: the command-line front end of the hsv simulator.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};
use hsv_run::commands::{
    self, ConfigArg, JsonFlag, aero::AeroArgs, engine::EngineArgs, heat::HeatArgs,
    modes::ModesArgs, trim::TrimArgs,
};

#[derive(Parser)]
#[command(
    name = "hsv-run",
    version,
    about = "Partitioned aerothermoelastic simulation of flexible air-breathing hypersonic vehicles",
    long_about = "Partitioned aerothermoelastic simulation of flexible air-breathing hypersonic \
                  vehicles (after Klock & Cesnik). Every command runs on the embedded sample \
                  vehicle unless --config names a vehicle TOML; `hsv-run config` prints the \
                  embedded one to start from."
)]
struct Cli {
    /// Load a dylib model plugin before anything else (repeatable); its models join the registry.
    #[arg(long = "plugin", value_name = "PATH", global = true)]
    plugins: Vec<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List every registered model with its family, role and fidelity.
    Models(JsonFlag),
    /// Show one model's summary and settings.
    Describe {
        /// Registered model name, e.g. `shock-expansion`.
        name: String,
        #[command(flatten)]
        json: JsonFlag,
    },
    /// Print the embedded sample-vehicle config (TOML, commented) to start your own from.
    Config {
        #[command(flatten)]
        config: ConfigArg,
        #[command(flatten)]
        json: JsonFlag,
    },
    /// Forces, moments and coefficients of the vehicle (or an STL mesh), one row per aero model.
    Aero(AeroArgs),
    /// Natural frequencies and mode shapes of the main body and the lifting surfaces.
    Modes(ModesArgs),
    /// Heat a lifting surface in the flow over time with each conduction model (temperature history).
    Heat(HeatArgs),
    /// Scramjet thrust, lift, moment, mass flow and station states, one row per propulsion model.
    Engine(EngineArgs),
    /// Trim steady level flight (rigid vehicle): alpha, elevon and fuel equivalence ratio.
    Trim(TrimArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {}", chain(&error));
            ExitCode::FAILURE
        }
    }
}

/// One line: the error and its causes, outermost first.
fn chain(error: &anyhow::Error) -> String {
    error
        .chain()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(": ")
}

fn run(cli: Cli) -> Result<()> {
    let mut registry = hsv_run::registry()?;
    for path in &cli.plugins {
        registry.load_plugin(path)?;
    }
    match cli.command {
        Command::Models(json) => commands::catalog::models(&registry, json.json),
        Command::Describe { name, json } => {
            commands::catalog::describe(&registry, &name, json.json)
        }
        Command::Config { config, json } => {
            commands::config::print_config(config.config.as_deref(), json.json)
        }
        Command::Aero(args) => commands::aero::run(args, &registry),
        Command::Modes(args) => commands::modes::run(args, &registry),
        Command::Heat(args) => commands::heat::run(args, &registry),
        Command::Engine(args) => commands::engine::run(args, &registry),
        Command::Trim(args) => commands::trim::run(args, &registry),
    }
}
