//! `hsv-run fmu`: packages the vehicle as an FMI 3.0 co-simulation FMU: the `hsv_fmu` library
//! (the `fmu/` crate, built by `cargo build --release -p hsv-fmu`), the model description it
//! writes of itself, and the vehicle config as `resources/config.toml`.

use std::ffi::{CStr, c_char};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::registry::Registry;

use super::{ConfigArg, load_config};
use crate::output::{write_file, zip_archive};

/// The library's model identifier (its file name, the FMI binaries folder's member).
const MODEL_IDENTIFIER: &str = "hsv_fmu";

/// The symbol through which the library writes its modelDescription.xml.
const DESCRIPTION_SYMBOL: &[u8] = b"hsv_fmu_model_description";

/// Arguments of `hsv-run fmu`.
#[derive(Args, Debug, Clone)]
pub struct FmuArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// The FMU archive to write.
    #[arg(long, value_name = "FILE", default_value = "hsv.fmu")]
    pub out: PathBuf,
    /// The FMU library to package (default: the `hsv_fmu` library beside this executable,
    /// where `cargo build --release -p hsv-fmu` puts it).
    #[arg(long, value_name = "PATH")]
    pub library: Option<PathBuf>,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
}

/// `hsv-run fmu`.
pub fn run(args: FmuArgs, registry: &Registry) -> Result<()> {
    // A config is checked as every command checks it, so the importer never meets a bad one.
    let (loaded, _) = load_config(args.config.config.as_deref(), registry)?;
    if !loaded.config.plugins.is_empty() {
        bail!(
            "{}: key `plugins`: an FMU carries its config but not the plugins it names; \
             remove the plugins or package a config without them",
            loaded.file
        );
    }
    if args.out.exists() && !args.force {
        bail!("{} exists; give --force to replace it", args.out.display());
    }
    let library = match args.library {
        Some(path) => path,
        None => default_library()?,
    };
    let library_bytes = std::fs::read(&library)
        .with_context(|| format!("cannot read the FMU library {}", library.display()))?;
    let description = model_description(&library)?;
    let mut members = vec![
        (
            "modelDescription.xml".to_owned(),
            description.clone().into_bytes(),
        ),
        (
            format!(
                "binaries/{}/{MODEL_IDENTIFIER}{}",
                platform_folder()?,
                std::env::consts::DLL_SUFFIX
            ),
            library_bytes,
        ),
    ];
    if let Some(path) = &args.config.config {
        let text =
            std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
        members.push(("resources/config.toml".to_owned(), text));
    }
    write_file(&args.out, zip_archive(&members)?)?;
    crate::outln!(
        "wrote {} (FMI 3.0 co-simulation, model identifier {MODEL_IDENTIFIER}): the vehicle of {}",
        args.out.display(),
        loaded.file
    )?;
    let flight = (loaded.config.flight.mach, loaded.config.flight.altitude_m);
    if let (Some(mach), Some(altitude_m)) = (
        start_value(&description, "trim_mach"),
        start_value(&description, "trim_altitude_m"),
    ) && (mach, altitude_m) != flight
    {
        eprintln!(
            "note: the FMU trims at its parameters trim_mach and trim_altitude_m, which start \
             at Mach {mach}, {altitude_m} m; {} flies Mach {}, {} m: set them in the importer",
            loaded.file, flight.0, flight.1
        );
    }
    Ok(())
}

/// The `hsv_fmu` library beside this executable.
fn default_library() -> Result<PathBuf> {
    let exe = std::env::current_exe().context("cannot locate the hsv-run executable")?;
    let name = format!(
        "{}{MODEL_IDENTIFIER}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    let path = exe.with_file_name(name);
    if !path.exists() {
        bail!(
            "no FMU library at {}: build it with `cargo build --release -p hsv-fmu` (it lands \
             beside the release hsv-run) or give --library PATH",
            path.display()
        );
    }
    Ok(path)
}

/// The modelDescription.xml the library at `path` writes of itself.
fn model_description(path: &Path) -> Result<String> {
    let fail = |why: String| anyhow::anyhow!("{} is not an hsv FMU library: {why}", path.display());
    // SAFETY: loading runs the library's initializers; an hsv_fmu library registers its models
    // there and does nothing else. The symbol's type is the one `fmu/src/lib.rs` exports.
    unsafe {
        let library = libloading::Library::new(path).map_err(|e| fail(e.to_string()))?;
        let describe: libloading::Symbol<'_, unsafe extern "C" fn() -> *const c_char> = library
            .get(DESCRIPTION_SYMBOL)
            .map_err(|e| fail(e.to_string()))?;
        let text = describe();
        if text.is_null() {
            return Err(fail("it could not write its model description".to_owned()));
        }
        let xml = CStr::from_ptr(text)
            .to_str()
            .map_err(|e| fail(e.to_string()))?
            .to_owned();
        if !xml.contains(&format!("modelIdentifier=\"{MODEL_IDENTIFIER}\"")) {
            return Err(fail(format!(
                "its model description names no model identifier {MODEL_IDENTIFIER}"
            )));
        }
        Ok(xml)
    }
}

/// The start value of the scalar variable `name` in a model description.
fn start_value(xml: &str, name: &str) -> Option<f64> {
    let variable = &xml[xml.find(&format!("name=\"{name}\""))?..];
    let variable = &variable[..variable.find('>')?];
    let start = &variable[variable.find("start=\"")? + "start=\"".len()..];
    start[..start.find('"')?].parse().ok()
}

/// The FMI 3.0 platform folder of this machine (`x86_64-linux`, `aarch64-darwin`, ...).
fn platform_folder() -> Result<String> {
    let system = match std::env::consts::OS {
        "linux" => "linux",
        "macos" => "darwin",
        "windows" => "windows",
        other => bail!("FMI 3.0 names no platform folder for the operating system {other}"),
    };
    Ok(format!("{}-{system}", std::env::consts::ARCH))
}
