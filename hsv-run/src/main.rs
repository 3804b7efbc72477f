//! `hsv-run`: the command-line front end of the hsv simulator.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};
use hsv_run::commands::{
    self, ConfigArg, JsonFlag, aero::AeroArgs, compare::CompareArgs, engine::EngineArgs,
    flutter::FlutterArgs, fmu::FmuArgs, heat::HeatArgs, linearize::LinearizeArgs, merge::MergeArgs,
    modes::ModesArgs, rom::RomArgs, simulate::SimulateArgs, trade::TradeArgs, trim::TrimArgs,
    vehicle::VehicleArgs,
};
use hsv_run::output;

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
    /// Print the embedded sample-vehicle config (TOML, commented) to start your own from, or
    /// check a config (--check FILE).
    Config {
        #[command(flatten)]
        config: ConfigArg,
        /// Validate this config as every command would before running (keys, values, plugins,
        /// geometry, region model names and roles) and check every model a job could build with
        /// its settings (without training any); prints `FILE: OK` or every problem found.
        #[arg(long, value_name = "FILE", conflicts_with = "config")]
        check: Option<PathBuf>,
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
    /// The assembled vehicle: regions, models, mass, centre of mass, inertia, modal frequencies.
    Vehicle(VehicleArgs),
    /// The partitioned and monolithic vehicles side by side: trims and doublet histories.
    Compare(CompareArgs),
    /// Linear model (A, B, C, D) of the trimmed flexible vehicle and its named modes.
    Linearize(LinearizeArgs),
    /// Fly the partitioned flexible vehicle from trim under the control inputs (default: the
    /// paper's elevon doublet).
    Simulate(SimulateArgs),
    /// Trim steady level flight (rigid vehicle): alpha, elevon and fuel equivalence ratio; a vehicle
    /// without a propulsion region trims for a steady glide (flight-path angle in place of phi).
    Trim(TrimArgs),
    /// Flutter of the heated lifting surface versus time in the flow (identified state matrix,
    /// eigenvalues, flutter Mach number); `--panel` for the classical simply supported panel.
    Flutter(FlutterArgs),
    /// Fidelity trade study: every combination of the varied region models (--vary) through
    /// trim or a simulation, compared with the highest-fidelity one, with its cost; --shard K/N
    /// runs a share, --emit-slurm N writes a Slurm job array.
    Trade(TradeArgs),
    /// Join `hsv-run trade --shard` output folders into the study's table.
    Merge(MergeArgs),
    /// A region's reduced-order aero model (convolution ROM): identify it from a source model
    /// and cache it, or check it against its source (error, speed-up, histories).
    Rom(RomArgs),
    /// Package the vehicle as an FMI 3.0 co-simulation FMU (inputs: elevon and fuel commands
    /// around the trim; outputs: the flight state; parameters: the trim's Mach and altitude).
    Fmu(FmuArgs),
}

/// Exit status when standard output was closed early: 128 + SIGPIPE, as a Unix tool killed by
/// the signal reports it.
const CLOSED_STDOUT_EXIT: u8 = 141;

fn main() -> ExitCode {
    quiet_on_closed_stdout();
    let cli = Cli::parse();
    match run(cli).and_then(|()| output::flush_stdout()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.chain().any(|e| e.is::<output::StdoutClosed>()) => {
            ExitCode::from(CLOSED_STDOUT_EXIT)
        }
        Err(error) => {
            // Nothing more to do if stderr is gone too.
            let _ = writeln!(
                std::io::stderr(),
                "error: {}",
                hsv_run::error_line::error_line(&error)
            );
            ExitCode::FAILURE
        }
    }
}

/// A `println!` left anywhere that fails no longer panics: a closed pipe exits quietly, another
/// failure (a full disk) is one error line. Commands print through `outln!`, which returns the
/// failure as an error; this catches what still prints with `println!`.
fn quiet_on_closed_stdout() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or_default();
        if let Some(cause) = message.strip_prefix("failed printing to stdout: ") {
            if cause.contains("os error 32") {
                std::process::exit(i32::from(CLOSED_STDOUT_EXIT));
            }
            let _ = writeln!(
                std::io::stderr(),
                "error: cannot write to standard output: {cause}"
            );
            std::process::exit(1);
        }
        default(info);
    }));
}

/// One line: the error and its causes, outermost first.
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
        Command::Config {
            check: Some(file),
            json,
            ..
        } => commands::config::check_config(&file, &registry, json.json),
        Command::Config { config, json, .. } => {
            commands::config::print_config(config.config.as_deref(), json.json)
        }
        Command::Aero(args) => commands::aero::run(args, &registry),
        Command::Modes(args) => commands::modes::run(args, &registry),
        Command::Heat(args) => commands::heat::run(args, &registry),
        Command::Engine(args) => commands::engine::run(args, &registry),
        Command::Trim(args) => commands::trim::run(args, &registry),
        Command::Flutter(args) => commands::flutter::run(args, &registry),
        Command::Simulate(args) => commands::simulate::run(args, &registry),
        Command::Linearize(args) => commands::linearize::run(args, &registry),
        Command::Compare(args) => commands::compare::run(args, &registry),
        Command::Vehicle(args) => commands::vehicle::run(args, &registry),
        Command::Trade(args) => commands::trade::run(args, &registry),
        Command::Merge(args) => commands::merge::run(args, &registry),
        Command::Rom(args) => commands::rom::run(args, &registry),
        Command::Fmu(args) => commands::fmu::run(args, &registry),
    }
}
