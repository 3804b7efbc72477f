//! `hsv-run modes`: natural frequencies and mode shapes of the main body and the lifting surfaces
//! (one file: the report types, their computation and their table change together; the files
//! written are `modes/files.rs`'s).
//!
//! The main body's structure model is `regions.main_body.structure`, the lifting surfaces'
//! `regions.lifting_surfaces.structure` (one instance per side). Lifting surfaces are analysed at
//! 293 K, at a uniform `--temperature-k`, or at the node temperatures of a `--temperature-field`
//! CSV, through `StructureModel::set_temperatures`; a surface whose thermal stress has buckled it
//! is reported as buckled. Outputs go to a run folder: one legacy-VTK file of the deformed mesh
//! per mode (with the mode shape as a vector field, for ParaView's "Warp by Vector"), a `.pvd`
//! collection per component to step through the modes, and PNG plots of the first shapes.
//!
//! With the main body and both surfaces configured (at the reference temperature) it also
//! reports the **coupled** in-vacuo modes of the assembled vehicle, from the partitioned
//! equations with the body-surface interface closed
//! ([`PartitionedVehicle::in_vacuo_modes`](crate::vehicle::partitioned::PartitionedVehicle::in_vacuo_modes)):
//! the frequencies and each region's share of the strain energy, where the body's and the
//! surfaces' modes near each other mix.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hsv_core::config::LoadedConfig;
use hsv_core::geometry::Side;
use hsv_core::mesh::{ModeShapes, PanelMesh};
use hsv_core::region::RegionInfo;
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::structure::StructureModel;
use nalgebra::{DVector, Vector3};

use super::{ConfigArg, JsonFlag, OutArgs, load_config};
use crate::outln;
use crate::output::{self, LinePlot, RunFolder, RunStatus, Series};
use crate::vehicle::flexible_vehicle;
use crate::vehicle::partitioned::{InVacuoModes, SurfaceModel};

mod files;

pub use files::*;

/// Reference (unheated) structure temperature, K.
pub const REFERENCE_TEMPERATURE_K: f64 = 293.0;

/// Largest vertex displacement of a deformed mesh written to VTK, m (our choice: visible on a
/// 30 m vehicle, small enough to read the shape).
pub const VTK_MAX_DISPLACEMENT_M: f64 = 1.0;

/// Modes drawn per PNG.
const PLOTTED_MODES: usize = 6;

/// Arguments of `hsv-run modes`.
#[derive(Args, Debug, Clone)]
#[command(
    after_help = "TEMPERATURE FIELD CSV: a header line `node,temperature_k`, then one \
    line per structural node of the lifting-surface model: its 0-based node index and its \
    temperature in K. Every node appears exactly once, in any order; blank lines and lines \
    starting with `#` are ignored. The same field is applied to the left and the right surface \
    (mirror images with the same node numbering). The main body's structure is temperature \
    independent (paper §II.A: thermally protected)."
)]
pub struct ModesArgs {
    #[command(flatten)]
    pub config: ConfigArg,
    /// Uniform lifting-surface structure temperature, K (default: 293 K, the reference state).
    #[arg(
        long = "temperature-k",
        value_name = "T",
        allow_negative_numbers = true,
        conflicts_with = "temperature_field"
    )]
    pub temperature_k: Option<f64>,
    /// Lifting-surface node temperatures from a CSV file `node,temperature_k` (see below).
    #[arg(long = "temperature-field", value_name = "FILE.csv")]
    pub temperature_field: Option<PathBuf>,
    /// Run folder for the VTK and PNG files and summary.json.
    #[command(flatten)]
    pub output: OutArgs,
    #[command(flatten)]
    pub json: JsonFlag,
}

/// The lifting-surface temperature state.
#[derive(Debug, Clone, PartialEq)]
pub enum Temperature {
    /// Every node at this temperature, K.
    Uniform(f64),
    /// Node temperatures from a CSV file, K, indexed by node.
    Field { file: String, node_k: Vec<f64> },
}

impl Temperature {
    /// The node temperatures for a model with `n_nodes` nodes.
    fn node_temperatures(&self, n_nodes: usize, model: &str) -> Result<Vec<f64>> {
        match self {
            Temperature::Uniform(t) => Ok(vec![*t; n_nodes]),
            Temperature::Field { file, node_k } => {
                if node_k.len() != n_nodes {
                    bail!(
                        "{file}: has {} node temperatures, but the `{model}` structure has {n_nodes} nodes (0..{})",
                        node_k.len(),
                        n_nodes.saturating_sub(1)
                    );
                }
                Ok(node_k.clone())
            }
        }
    }

    fn describe(&self) -> String {
        match self {
            Temperature::Uniform(t) if *t == REFERENCE_TEMPERATURE_K => {
                format!("{t} K (reference)")
            }
            Temperature::Uniform(t) => format!("{t} K uniform"),
            Temperature::Field { file, node_k } => {
                let (lo, hi) = node_k
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &t| {
                        (lo.min(t), hi.max(t))
                    });
                format!("temperature field {file} ({lo} to {hi} K)")
            }
        }
    }
}

/// Reads a `node,temperature_k` CSV (module docs of [`ModesArgs`]): every node 0..n once.
pub fn read_temperature_field(path: &Path) -> Result<Vec<f64>> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("{file}: cannot read"))?;
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.trim()))
        .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'));
    match rows.next() {
        Some((_, header))
            if header
                .split(',')
                .map(str::trim)
                .eq(["node", "temperature_k"]) => {}
        Some((line, header)) => {
            bail!("{file}:{line}: expected the header `node,temperature_k`, found `{header}`")
        }
        None => {
            bail!("{file}: empty; expected a header `node,temperature_k` and one line per node")
        }
    }
    let mut values: Vec<Option<f64>> = Vec::new();
    for (line, text) in rows {
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let [node, temperature] = fields[..] else {
            bail!("{file}:{line}: expected `node,temperature_k`, found `{text}`");
        };
        let node: usize = node.parse().with_context(|| {
            format!("{file}:{line}: node `{node}` is not a non-negative integer")
        })?;
        let t: f64 = temperature.parse().with_context(|| {
            format!("{file}:{line}: temperature_k `{temperature}` is not a number")
        })?;
        if !(t.is_finite() && t > 0.0) {
            bail!("{file}:{line}: temperature_k = {t} must be a positive number of kelvin");
        }
        if node >= 10_000_000 {
            bail!("{file}:{line}: node {node} is beyond any structural grid (< 10000000)");
        }
        if values.len() <= node {
            values.resize(node + 1, None);
        }
        if values[node].replace(t).is_some() {
            bail!("{file}:{line}: node {node} appears twice");
        }
    }
    if values.is_empty() {
        bail!("{file}: no node temperatures after the header");
    }
    values
        .iter()
        .enumerate()
        .map(|(node, t)| {
            t.ok_or_else(|| {
                anyhow::anyhow!(
                    "{file}: node {node} has no temperature (every node 0..{} must appear)",
                    values.len() - 1
                )
            })
        })
        .collect()
}

/// One mode: its name and natural frequency.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModeRow {
    pub name: String,
    pub frequency_hz: f64,
}

/// The modes of one structure, or why it has none.
#[derive(Debug, Clone, PartialEq)]
pub enum ModesOutcome {
    Modes(Vec<ModeRow>),
    /// Thermal stress made the stiffness indefinite; the model's message.
    Buckled(String),
}

/// One analysed structure and its mode shapes on its mesh.
#[derive(Debug, Clone)]
pub struct StructureModes {
    /// Registered model name.
    pub model: String,
    /// "main body", "left lifting surface", ...
    pub component: String,
    pub outcome: ModesOutcome,
    /// Shapes on `mesh` (None when they could not be mapped; `notes` says why).
    pub shapes: Option<ModeShapes>,
    pub mesh: PanelMesh,
    pub notes: Vec<String>,
}

impl StructureModes {
    fn rows(&self) -> &[ModeRow] {
        match &self.outcome {
            ModesOutcome::Modes(rows) => rows,
            ModesOutcome::Buckled(_) => &[],
        }
    }
}

/// Everything `hsv-run modes` computes.
#[derive(Debug, Clone)]
pub struct ModesReport {
    pub config_file: String,
    pub temperature: Temperature,
    pub body: Option<StructureModes>,
    /// Left then right; empty when no surface structure model is configured.
    pub surfaces: Vec<(Side, StructureModes)>,
    /// The assembled vehicle's in-vacuo modes (module docs); None with a note when not
    /// computed.
    pub coupled: Option<InVacuoModes>,
    pub notes: Vec<String>,
}

/// Builds structure model `name` for `region`.
fn build_structure(
    region: &RegionInfo,
    registry: &Registry,
    name: &str,
) -> Result<Box<dyn StructureModel>> {
    let settings = region.model_settings(name);
    registry
        .create::<dyn StructureModel>(name, &ModelContext::new(region, registry, &settings))
        .with_context(|| {
            format!(
                "building structure model `{name}` for region `{}`",
                region.name
            )
        })
}

/// Frequencies paired with the model's mode names; an error from the model is a buckled state.
fn modes_of(model: &dyn StructureModel) -> Result<ModesOutcome> {
    let names = &model.modal_model().names;
    match model.natural_frequencies_hz() {
        Ok(f) => {
            if f.len() != names.len() {
                bail!(
                    "structure model `{}` gave {} frequencies for {} modes",
                    model.name(),
                    f.len(),
                    names.len()
                );
            }
            if let Some(k) = f.iter().position(|v| !v.is_finite()) {
                bail!(
                    "structure model `{}`: frequency of mode `{}` is not finite",
                    model.name(),
                    names[k]
                );
            }
            Ok(ModesOutcome::Modes(
                names
                    .iter()
                    .zip(f)
                    .map(|(name, frequency_hz)| ModeRow {
                        name: name.clone(),
                        frequency_hz,
                    })
                    .collect(),
            ))
        }
        Err(e) => Ok(ModesOutcome::Buckled(e.to_string())),
    }
}

/// Shapes of `model` on `mesh`, or a note saying why there are none.
fn shapes_on(
    model: &dyn StructureModel,
    mesh: &PanelMesh,
    notes: &mut Vec<String>,
) -> Option<ModeShapes> {
    let shapes = model
        .mode_shapes_on(mesh)
        .map_err(|e| e.to_string())
        .and_then(|shapes| {
            shapes
                .check(mesh)
                .map(|()| shapes)
                .map_err(|e| e.to_string())
        });
    match shapes {
        Ok(shapes) => Some(shapes),
        Err(e) => {
            notes.push(format!("mode shapes not written: {e}"));
            None
        }
    }
}

/// Computes the modes of the main body and the lifting surfaces (no output written).
pub fn compute(
    loaded: &LoadedConfig,
    registry: &Registry,
    temperature: Temperature,
) -> Result<ModesReport> {
    let regions = &loaded.config.regions;
    let mut notes = Vec::new();
    let body = match regions.main_body.structure.as_deref() {
        None => {
            notes.push(
                "no main-body structure model configured (regions.main_body.structure)".to_owned(),
            );
            None
        }
        Some(name) => {
            let region = loaded.region("main_body")?;
            let model = build_structure(&region, registry, name)?;
            let mut body_notes = Vec::new();
            let outcome = modes_of(model.as_ref())?;
            let shapes = shapes_on(model.as_ref(), &region.mesh, &mut body_notes);
            Some(StructureModes {
                model: name.to_owned(),
                component: "main body".to_owned(),
                outcome,
                shapes,
                mesh: region.mesh,
                notes: body_notes,
            })
        }
    };
    if body.is_some() && temperature != Temperature::Uniform(REFERENCE_TEMPERATURE_K) {
        notes.push(
            "the main body's structure is temperature independent (paper §II.A: thermally \
             protected); the temperature applies to the lifting surfaces"
                .to_owned(),
        );
    }
    let mut surfaces = Vec::new();
    for (side, region_name) in [(Side::Left, "left_surface"), (Side::Right, "right_surface")] {
        let Some(name) = regions.region(region_name).and_then(|r| r.structure) else {
            notes.push(format!(
                "no {region_name} structure model configured (regions.{region_name}.structure or \
                 regions.lifting_surfaces.structure)"
            ));
            continue;
        };
        let region = loaded.region(region_name)?;
        let mut model = build_structure(&region, registry, &name)?;
        let mut surface_notes = Vec::new();
        match model.thermal_stiffness_mut() {
            None => surface_notes.push(format!(
                "`{name}` has no temperature dependence; frequencies at its reference state"
            )),
            Some(thermal) => {
                let node_k = temperature.node_temperatures(thermal.temperature_nodes(), &name)?;
                thermal.set_temperatures(&node_k).with_context(|| {
                    format!(
                        "{} lifting surface at {}",
                        side.name(),
                        temperature.describe()
                    )
                })?;
            }
        }
        let outcome = modes_of(model.as_ref())?;
        let shapes = match outcome {
            ModesOutcome::Modes(_) => shapes_on(model.as_ref(), &region.mesh, &mut surface_notes),
            ModesOutcome::Buckled(_) => None,
        };
        surfaces.push((
            side,
            StructureModes {
                model: name.clone(),
                component: format!("{} lifting surface", side.name()),
                outcome,
                shapes,
                mesh: region.mesh,
                notes: surface_notes,
            },
        ));
    }
    if body.is_none() && surfaces.is_empty() {
        bail!(
            "{}: the config names no structure model (regions.main_body.structure, \
             regions.lifting_surfaces.structure)",
            loaded.file
        );
    }
    let all_free = body
        .iter()
        .chain(surfaces.iter().map(|(_, s)| s))
        .all(|s| matches!(s.outcome, ModesOutcome::Modes(_)));
    let coupled = if body.is_none() || surfaces.len() < 2 || !all_free {
        None
    } else if temperature != Temperature::Uniform(REFERENCE_TEMPERATURE_K) {
        notes.push(
            "coupled modes of the assembled vehicle: at the reference temperature only (run \
             without a temperature)"
                .to_owned(),
        );
        None
    } else {
        match flexible_vehicle(loaded, registry, SurfaceModel::Partitioned, "modes")
            .map_err(|e| e.to_string())
            .and_then(|mut v| v.in_vacuo_modes().map_err(|e| e.to_string()))
        {
            Ok(modes) => Some(modes),
            Err(e) => {
                notes.push(format!(
                    "coupled modes of the assembled vehicle not computed: {e}"
                ));
                None
            }
        }
    };
    Ok(ModesReport {
        config_file: loaded.file.clone(),
        temperature,
        body,
        surfaces,
        coupled,
        notes,
    })
}

/// Computes and reports the modes; writes VTK and PNG files to the run folder.
pub fn run(args: ModesArgs, registry: &Registry) -> Result<()> {
    let (loaded, registry) = load_config(args.config.config.as_deref(), registry)?;
    let temperature = match (&args.temperature_k, &args.temperature_field) {
        (Some(t), _) => {
            if !(t.is_finite() && *t > 0.0) {
                bail!("--temperature-k must be a positive temperature in kelvin, got {t}");
            }
            Temperature::Uniform(*t)
        }
        (None, Some(path)) => Temperature::Field {
            file: path.display().to_string(),
            node_k: read_temperature_field(path)?,
        },
        (None, None) => Temperature::Uniform(REFERENCE_TEMPERATURE_K),
    };
    let report = compute(&loaded, &registry, temperature)?;
    let mut run = RunFolder::create("modes", args.output.out.as_deref(), args.output.force)?;
    let folder = run.path.clone();
    let files = run.run(
        |run| {
            let files = write_outputs(&report, &run.path)?;
            for file in &files {
                run.record(file.clone());
            }
            Ok(files)
        },
        || summary_json(&report, &folder, &[]),
    )?;
    let summary = run.write_summary(
        summary_json(&report, &folder, &files),
        &RunStatus::Completed,
    )?;

    if args.json.json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
        return Ok(());
    }
    outln!("structure modes of {}", report.config_file)?;
    if let Some(body) = &report.body {
        print_structure(body)?;
    }
    if !report.surfaces.is_empty() {
        outln!("lifting surfaces at {}:", report.temperature.describe())?;
        for (_, s) in &report.surfaces {
            print_structure(s)?;
        }
    }
    if let Some(coupled) = &report.coupled {
        print_coupled(coupled)?;
    }
    for note in &report.notes {
        outln!("note: {note}")?;
    }
    outln!(
        "mode shapes: {} ({} files: VTK per mode with .pvd collections for ParaView, PNG plots, summary.json)",
        folder.display(),
        run.files().len()
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use hsv_core::error::ModelError;
    use hsv_core::structure::ModalModel;
    use nalgebra::DMatrix;

    /// A one-mode structure with generalized stiffness `k` (negative: buckled).
    struct OneMode(ModalModel);

    impl OneMode {
        fn new(k: f64) -> Self {
            Self(ModalModel {
                names: vec!["bending 1".into()],
                mass: DMatrix::identity(1, 1),
                damping: DMatrix::zeros(1, 1),
                stiffness: DMatrix::from_element(1, 1, k),
            })
        }
    }

    impl StructureModel for OneMode {
        fn name(&self) -> &str {
            "one-mode"
        }
        fn modal_model(&self) -> &ModalModel {
            &self.0
        }
        fn natural_frequencies_hz(&self) -> Result<Vec<f64>, ModelError> {
            let k = self.0.stiffness[(0, 0)];
            if k > 0.0 {
                Ok(vec![k.sqrt() / std::f64::consts::TAU])
            } else {
                Err(ModelError::out_of_range(
                    "one-mode",
                    "generalized stiffness of `bending 1` (buckled)",
                    k,
                    "> 0",
                ))
            }
        }
        fn mode_shapes_on(&self, mesh: &PanelMesh) -> Result<ModeShapes, ModelError> {
            Ok(ModeShapes {
                vertex_displacement: DMatrix::zeros(3 * mesh.vertices.len(), 1),
            })
        }
    }

    fn structure_modes(outcome: ModesOutcome) -> StructureModes {
        StructureModes {
            model: "one-mode".into(),
            component: "right lifting surface".into(),
            outcome,
            shapes: None,
            mesh: PanelMesh::default(),
            notes: Vec::new(),
        }
    }

    #[test]
    fn a_buckled_structure_is_reported_as_buckled_not_nan() {
        let outcome = modes_of(&OneMode::new(-4.0)).expect("outcome");
        let ModesOutcome::Buckled(message) = &outcome else {
            panic!("not buckled: {outcome:?}");
        };
        assert!(message.contains("buckled"), "{message}");
        let report = ModesReport {
            config_file: "test.toml".into(),
            temperature: Temperature::Uniform(900.0),
            body: None,
            surfaces: vec![(Side::Right, structure_modes(outcome))],
            coupled: None,
            notes: Vec::new(),
        };
        let json = summary_json(&report, Path::new("run"), &[]);
        assert_eq!(json["surfaces"]["right"], serde_json::json!([]));
        assert_eq!(json["surface_status"]["right"]["state"], "buckled");
        assert!(
            json["surface_status"]["right"]["message"]
                .as_str()
                .is_some_and(|m| m.contains("buckled"))
        );
        assert!(!json.to_string().contains("NaN"));

        let outcome = modes_of(&OneMode::new(4.0 * std::f64::consts::PI.powi(2))).expect("ok");
        assert_eq!(
            outcome,
            ModesOutcome::Modes(vec![ModeRow {
                name: "bending 1".into(),
                frequency_hz: 1.0
            }])
        );
    }

    #[test]
    fn temperature_fields_must_cover_the_model_nodes() {
        let field = Temperature::Field {
            file: "t.csv".into(),
            node_k: vec![300.0, 310.0],
        };
        assert_eq!(
            field.node_temperatures(2, "m").expect("fits"),
            [300.0, 310.0]
        );
        let err = field.node_temperatures(5, "m").unwrap_err().to_string();
        assert!(err.contains("t.csv") && err.contains("5 nodes"), "{err}");
        assert_eq!(
            Temperature::Uniform(400.0)
                .node_temperatures(3, "m")
                .expect("uniform"),
            [400.0; 3]
        );
    }

    #[test]
    fn mode_file_names_are_slugs() {
        assert_eq!(
            mode_stem("body", 0, "Vertical bending 1"),
            "body-mode-01-vertical-bending-1"
        );
        assert_eq!(
            mode_stem("left-surface", 11, "torsion (2)"),
            "left-surface-mode-12-torsion-2"
        );
    }
}
