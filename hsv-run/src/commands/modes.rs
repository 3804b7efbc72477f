//! `hsv-run modes`: natural frequencies and mode shapes of the main body and the lifting surfaces.
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

/// File-name stem of a mode: "body-mode-01-vertical-bending-1".
fn mode_stem(prefix: &str, index: usize, name: &str) -> String {
    let slug: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect::<String>()
        .split('-')
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("-");
    format!("{prefix}-mode-{:02}-{slug}", index + 1)
}

/// Per-vertex displacement vectors of mode `k`.
fn vertex_vectors(shapes: &ModeShapes, k: usize) -> Vec<Vector3<f64>> {
    let col = shapes.vertex_displacement.column(k);
    (0..col.len() / 3)
        .map(|v| Vector3::new(col[3 * v], col[3 * v + 1], col[3 * v + 2]))
        .collect()
}

/// Largest vertex displacement of mode `k`, m per unit modal coordinate.
fn largest_displacement(shapes: &ModeShapes, k: usize) -> f64 {
    vertex_vectors(shapes, k)
        .iter()
        .map(|v| v.norm())
        .fold(0.0, f64::max)
}

/// Writes the undeformed mesh, one deformed mesh per mode (largest displacement
/// [`VTK_MAX_DISPLACEMENT_M`]) with the unscaled shape as the vector `mode_shape`, and a `.pvd`
/// stepping through the modes (its "time" is the mode number). Returns the files written.
fn write_vtk(folder: &Path, prefix: &str, s: &StructureModes) -> Result<Vec<PathBuf>> {
    let Some(shapes) = &s.shapes else {
        return Ok(Vec::new());
    };
    let mut files = Vec::new();
    let base = folder.join(format!("{prefix}-undeformed.vtk"));
    output::write_vtk_mesh(&base, &s.mesh, &[], &[])?;
    files.push(base);
    let mut entries = Vec::new();
    let mut deformed = PanelMesh::default();
    for (k, row) in s.rows().iter().enumerate().take(shapes.n_modes()) {
        let vectors = vertex_vectors(shapes, k);
        let largest = largest_displacement(shapes, k);
        let scale = if largest > 0.0 {
            VTK_MAX_DISPLACEMENT_M / largest
        } else {
            0.0
        };
        let mut q = DVector::zeros(shapes.n_modes());
        q[k] = scale;
        shapes.deform(&s.mesh, &q, &mut deformed);
        let name = format!("{}.vtk", mode_stem(prefix, k, &row.name));
        let path = folder.join(&name);
        let title = format!(
            "hsv {prefix} mode {} ({}) at {} Hz ({}): mesh displaced by {scale:.6e} x \
             mode_shape (largest displacement {VTK_MAX_DISPLACEMENT_M} m)",
            k + 1,
            row.name,
            row.frequency_hz,
            s.model
        );
        output::write_vtk_mesh_described(
            &path,
            &title,
            &[
                ("mode_number", (k + 1) as f64),
                ("frequency_hz", row.frequency_hz),
                ("display_scale", scale),
                ("largest_display_displacement_m", VTK_MAX_DISPLACEMENT_M),
            ],
            &deformed,
            &[("mode_shape", &vectors)],
            &[],
        )?;
        entries.push(((k + 1) as f64, name));
        files.push(path);
    }
    let pvd = folder.join(format!("{prefix}-modes.pvd"));
    let refs: Vec<(f64, &str)> = entries.iter().map(|(t, n)| (*t, n.as_str())).collect();
    output::write_pvd(&pvd, &refs)?;
    files.push(pvd);
    Ok(files)
}

/// Stations of a mesh along `axis` (0 = x, 1 = y): vertex indices grouped by equal coordinate.
fn stations(mesh: &PanelMesh, axis: usize) -> Vec<(f64, Vec<usize>)> {
    let mut order: Vec<usize> = (0..mesh.vertices.len()).collect();
    order.sort_by(|&a, &b| mesh.vertices[a][axis].total_cmp(&mesh.vertices[b][axis]));
    let mut out: Vec<(f64, Vec<usize>)> = Vec::new();
    for v in order {
        let c = mesh.vertices[v][axis];
        match out.last_mut() {
            Some((c0, members)) if (c - *c0).abs() < 1e-6 => members.push(v),
            _ => out.push((c, vec![v])),
        }
    }
    out
}

/// Divides every series by the mode's largest vertex displacement `peak`, so components the
/// mode hardly moves stay near zero instead of being blown up to round-off shapes.
fn normalize(series: &mut [Series], peak: f64) {
    if peak > 0.0 {
        for s in series {
            for y in &mut s.y {
                // Round-off of a component the mode does not move would fill the auto-scaled
                // axis with noise.
                *y = if (*y / peak).abs() < 1e-9 {
                    0.0
                } else {
                    *y / peak
                };
            }
        }
    }
}

/// Body shapes along x per station: the lateral and vertical motion of the station's vertex
/// centroid and the least-squares twist about x times the body half width, so all three read
/// as displacements (normalized by the mode's largest vertex displacement).
fn body_plots(s: &StructureModes) -> Vec<LinePlot> {
    let Some(shapes) = &s.shapes else {
        return Vec::new();
    };
    let (lo, hi) = s.mesh.bounding_box();
    let half_width = 0.5 * (hi.y - lo.y);
    let stations = stations(&s.mesh, 0);
    s.rows()
        .iter()
        .enumerate()
        .take(PLOTTED_MODES.min(shapes.n_modes()))
        .map(|(k, row)| {
            let col = shapes.vertex_displacement.column(k);
            let (mut xs, mut v, mut w, mut twist) = (vec![], vec![], vec![], vec![]);
            for (x, members) in &stations {
                let n = members.len() as f64;
                let centre = members
                    .iter()
                    .fold(Vector3::zeros(), |c, &i| c + s.mesh.vertices[i].coords)
                    / n;
                let (mut sv, mut sw, mut num, mut den) = (0.0, 0.0, 0.0, 0.0);
                for &i in members {
                    let (uy, uz) = (col[3 * i + 1], col[3 * i + 2]);
                    let d = s.mesh.vertices[i].coords - centre;
                    sv += uy;
                    sw += uz;
                    num += d.y * uz - d.z * uy;
                    den += d.y * d.y + d.z * d.z;
                }
                xs.push(*x);
                v.push(sv / n);
                w.push(sw / n);
                twist.push(if den > 0.0 {
                    num / den * half_width
                } else {
                    0.0
                });
            }
            let mut series = vec![
                Series {
                    label: "lateral v (station centroid)".into(),
                    x: xs.clone(),
                    y: v,
                },
                Series {
                    label: "vertical w (station centroid)".into(),
                    x: xs.clone(),
                    y: w,
                },
                Series {
                    label: "twist × half width".into(),
                    x: xs,
                    y: twist,
                },
            ];
            normalize(&mut series, largest_displacement(shapes, k));
            LinePlot {
                title: format!(
                    "body ({}) mode {}: {} ({:.3} Hz)",
                    s.model,
                    k + 1,
                    row.name,
                    row.frequency_hz
                ),
                x_label: "x [m] (nose at 0)".into(),
                y_label: "displacement / max |u|".into(),
                series,
            }
        })
        .collect()
}

/// Every mode of a surface as a planform contour map of its z displacement (paper Fig. 5):
/// the surface's upper-face panels (normal up, -z) seen from above, x forward, y spanwise,
/// normalized by the mode's largest vertex displacement.
fn surface_maps(s: &StructureModes) -> Vec<output::FieldMap> {
    let Some(shapes) = &s.shapes else {
        return Vec::new();
    };
    // Upper face only: both faces carry nearly the same displacement, drawn once.
    let upper: Vec<Vec<usize>> = s
        .mesh
        .panels
        .iter()
        .filter(|p| p.normal.z < -0.5)
        .map(|p| p.vertex_indices().to_vec())
        .collect();
    let cells = if upper.is_empty() {
        s.mesh
            .panels
            .iter()
            .map(|p| p.vertex_indices().to_vec())
            .collect()
    } else {
        upper
    };
    let vertices: Vec<(f64, f64)> = s.mesh.vertices.iter().map(|v| (v.y, v.x)).collect();
    s.rows()
        .iter()
        .enumerate()
        .take(shapes.n_modes())
        .map(|(k, row)| {
            let col = shapes.vertex_displacement.column(k);
            let peak = largest_displacement(shapes, k);
            let values = (0..s.mesh.vertices.len())
                .map(|v| {
                    if peak > 0.0 {
                        col[3 * v + 2] / peak
                    } else {
                        0.0
                    }
                })
                .collect();
            output::FieldMap {
                title: format!("mode {}: {} ({:.2} Hz)", k + 1, row.name, row.frequency_hz),
                x_label: "y [m] (spanwise)".into(),
                y_label: "x [m] (nose at 0)".into(),
                vertices: vertices.clone(),
                values,
                cells: cells.clone(),
                value_label: "w/max|u|".into(),
            }
        })
        .collect()
}

/// Writes VTK files and PNG plots into `folder`; returns the files written.
pub fn write_outputs(report: &ModesReport, folder: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    if let Some(body) = &report.body {
        files.extend(write_vtk(folder, "body", body)?);
        let plots = body_plots(body);
        if !plots.is_empty() {
            let path = folder.join("body-modes.png");
            output::write_line_plots_png(
                &path,
                &plots,
                plots.len().min(3),
                (1500, 450 * plots.len().div_ceil(3) as u32),
            )?;
            files.push(path);
        }
    }
    for (side, s) in &report.surfaces {
        files.extend(write_vtk(folder, &format!("{}-surface", side.name()), s)?);
    }
    if let Some((_, s)) = report
        .surfaces
        .iter()
        .find(|(side, _)| *side == Side::Right)
    {
        let title = format!(
            "Right lifting surface modes ({}, structure at {}): z displacement / largest |u|, \
             seen from above",
            s.model,
            report.temperature.describe()
        );
        let maps = surface_maps(s);
        if !maps.is_empty() {
            let path = folder.join("surface-modes.png");
            let columns = maps.len().min(4);
            output::write_field_maps_png(
                &path,
                &title,
                &maps,
                columns,
                (
                    440 * columns as u32,
                    520 * maps.len().div_ceil(columns) as u32,
                ),
            )?;
            files.push(path);
        }
    }
    Ok(files)
}

fn rows_json(s: &StructureModes) -> serde_json::Value {
    serde_json::to_value(s.rows()).unwrap_or(serde_json::Value::Null)
}

fn status_json(s: &StructureModes) -> serde_json::Value {
    match &s.outcome {
        ModesOutcome::Modes(_) => {
            serde_json::json!({"state": "ok", "model": s.model, "notes": s.notes})
        }
        ModesOutcome::Buckled(message) => {
            serde_json::json!({"state": "buckled", "model": s.model, "message": message, "notes": s.notes})
        }
    }
}

/// The `--json` summary: `body`, `surfaces` (`left`, `right`: lists of `{name, frequency_hz}`),
/// plus models, states, temperature, notes and files.
pub fn summary_json(report: &ModesReport, folder: &Path, files: &[PathBuf]) -> serde_json::Value {
    let mut surfaces = serde_json::Map::new();
    let mut states = serde_json::Map::new();
    for side in [Side::Left, Side::Right] {
        let found = report.surfaces.iter().find(|(s, _)| *s == side);
        surfaces.insert(
            side.name().to_owned(),
            found.map_or(serde_json::json!([]), |(_, s)| rows_json(s)),
        );
        states.insert(
            side.name().to_owned(),
            found.map_or(serde_json::json!({"state": "not configured"}), |(_, s)| {
                status_json(s)
            }),
        );
    }
    let temperature = match &report.temperature {
        Temperature::Uniform(t) => serde_json::json!({"uniform_k": t}),
        Temperature::Field { file, node_k } => {
            serde_json::json!({"field_file": file, "nodes": node_k.len()})
        }
    };
    serde_json::json!({
        "config": report.config_file,
        "body_model": report.body.as_ref().map(|b| b.model.clone()),
        "body": report.body.as_ref().map_or(serde_json::json!([]), rows_json),
        "body_status": report.body.as_ref().map_or(serde_json::json!({"state": "not configured"}), status_json),
        "surface_model": report.surfaces.first().map(|(_, s)| s.model.clone()),
        "surfaces": surfaces,
        "surface_status": states,
        "surface_temperature": temperature,
        "coupled": report.coupled.as_ref().map_or(serde_json::Value::Null, |c| {
            serde_json::to_value(c).unwrap_or(serde_json::Value::Null)
        }),
        "notes": report.notes,
        "run_folder": folder.display().to_string(),
        "files": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
    })
}

fn print_structure(s: &StructureModes) -> Result<()> {
    match &s.outcome {
        ModesOutcome::Modes(rows) => {
            outln!("{} ({}): {} modes", s.component, s.model, rows.len())?;
            outln!("  {:>3}  {:<28} {:>14}", "#", "mode", "frequency [Hz]")?;
            for (i, r) in rows.iter().enumerate() {
                outln!("  {:>3}  {:<28} {:>14.4}", i + 1, r.name, r.frequency_hz)?;
            }
        }
        ModesOutcome::Buckled(message) => {
            outln!("{} ({}): BUCKLED: {message}", s.component, s.model)?;
        }
    }
    for note in &s.notes {
        outln!("  note: {note}")?;
    }
    Ok(())
}

/// Prints the coupled modes with each region's share of the strain energy, %.
fn print_coupled(coupled: &InVacuoModes) -> Result<()> {
    outln!(
        "assembled vehicle (partitioned equations, interface closed): {} coupled modes",
        coupled.modes.len()
    )?;
    let header: String = coupled
        .regions
        .iter()
        .map(|r| format!(" {:>15}", format!("{r} [%]")))
        .collect();
    outln!("  {:>3}  {:>14}{header}", "#", "frequency [Hz]")?;
    for (i, m) in coupled.modes.iter().enumerate() {
        let shares: String = m
            .strain_energy_shares
            .iter()
            .map(|s| format!(" {:>15.1}", 100.0 * s))
            .collect();
        outln!("  {:>3}  {:>14.4}{shares}", i + 1, m.frequency_hz)?;
    }
    outln!("  (strain-energy shares: where each mode deforms)")?;
    Ok(())
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
