//! What `hsv-run modes` writes and prints: VTK mode shapes with their `.pvd` collections, PNG
//! plots of the body's modes along its length and maps of the surfaces' modes, the summary and
//! the tables on standard output.

use super::*;

/// File-name stem of a mode: "body-mode-01-vertical-bending-1".
pub(super) fn mode_stem(prefix: &str, index: usize, name: &str) -> String {
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
pub(super) fn vertex_vectors(shapes: &ModeShapes, k: usize) -> Vec<Vector3<f64>> {
    let col = shapes.vertex_displacement.column(k);
    (0..col.len() / 3)
        .map(|v| Vector3::new(col[3 * v], col[3 * v + 1], col[3 * v + 2]))
        .collect()
}

/// Largest vertex displacement of mode `k`, m per unit modal coordinate.
pub(super) fn largest_displacement(shapes: &ModeShapes, k: usize) -> f64 {
    vertex_vectors(shapes, k)
        .iter()
        .map(|v| v.norm())
        .fold(0.0, f64::max)
}

/// Writes the undeformed mesh, one deformed mesh per mode (largest displacement
/// [`VTK_MAX_DISPLACEMENT_M`]) with the unscaled shape as the vector `mode_shape`, and a `.pvd`
/// stepping through the modes (its "time" is the mode number). Returns the files written.
pub(super) fn write_vtk(folder: &Path, prefix: &str, s: &StructureModes) -> Result<Vec<PathBuf>> {
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
pub(super) fn stations(mesh: &PanelMesh, axis: usize) -> Vec<(f64, Vec<usize>)> {
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
pub(super) fn normalize(series: &mut [Series], peak: f64) {
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
pub(super) fn body_plots(s: &StructureModes) -> Vec<LinePlot> {
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
pub(super) fn surface_maps(s: &StructureModes) -> Vec<output::FieldMap> {
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

pub(super) fn rows_json(s: &StructureModes) -> serde_json::Value {
    serde_json::to_value(s.rows()).unwrap_or(serde_json::Value::Null)
}

pub(super) fn status_json(s: &StructureModes) -> serde_json::Value {
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

pub(super) fn print_structure(s: &StructureModes) -> Result<()> {
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
pub(super) fn print_coupled(coupled: &InVacuoModes) -> Result<()> {
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
