//! Core types to and from the plain data of ABI 2: the host flattens meshes, flight conditions
//! and regions into buffers; the plugin side rebuilds the same core types from them, checking
//! every count and index so a bad buffer is an error, never undefined behaviour (one file: each
//! type's flattening sits beside its rebuild, so the two directions stay in step).

use std::collections::BTreeMap;

use nalgebra::{DMatrix, Point3, Vector3};

use super::abi::*;
use crate::aero::{EdgeState, ReferenceValues};
use crate::control::{LinearDesignModel, StateFeedback, matrix_rows};
use crate::flow::{FlightCondition, Freestream};
use crate::gas::PerfectGas;
use crate::geometry::Side;
use crate::mesh::{Panel, PanelMesh, RegionKind, Strip, Surface};
use crate::region::{ModelSettings, RegionGeometry, RegionInfo};

pub(crate) fn region_code(kind: RegionKind) -> u32 {
    match kind {
        RegionKind::MainBody => REGION_MAIN_BODY,
        RegionKind::LiftingSurface => REGION_LIFTING_SURFACE,
        RegionKind::Propulsion => REGION_PROPULSION,
        RegionKind::Other => REGION_OTHER,
    }
}

pub(crate) fn region_kind(code: u32) -> Result<RegionKind, String> {
    Ok(match code {
        REGION_MAIN_BODY => RegionKind::MainBody,
        REGION_LIFTING_SURFACE => RegionKind::LiftingSurface,
        REGION_PROPULSION => RegionKind::Propulsion,
        REGION_OTHER => RegionKind::Other,
        other => return Err(format!("region kind code {other} is not 0-3")),
    })
}

/// A mesh flattened for the ABI; the buffers keep their capacity between calls.
#[derive(Debug, Default)]
pub(crate) struct MeshBuffers {
    n_vertices: usize,
    vertices: Vec<f64>,
    panel_vertices: Vec<usize>,
    vertex_count: Vec<u8>,
    panel_surface: Vec<u32>,
    centroid: Vec<f64>,
    normal: Vec<f64>,
    area: Vec<f64>,
    strip_offsets: Vec<usize>,
    strip_panels: Vec<usize>,
    surface_kind: Vec<u32>,
    name_offsets: Vec<usize>,
    names: Vec<u8>,
}

impl MeshBuffers {
    /// Copies `mesh` into the buffers.
    pub(crate) fn fill(&mut self, mesh: &PanelMesh) {
        self.n_vertices = mesh.vertices.len();
        self.vertices.clear();
        for v in &mesh.vertices {
            self.vertices.extend_from_slice(v.coords.as_slice());
        }
        self.panel_vertices.clear();
        self.vertex_count.clear();
        self.panel_surface.clear();
        self.centroid.clear();
        self.normal.clear();
        self.area.clear();
        for panel in &mesh.panels {
            self.panel_vertices.extend_from_slice(&panel.vertices);
            self.vertex_count.push(panel.vertex_count);
            self.panel_surface.push(u32::from(panel.surface));
            self.centroid
                .extend_from_slice(panel.centroid.coords.as_slice());
            self.normal.extend_from_slice(panel.normal.as_slice());
            self.area.push(panel.area_m2);
        }
        self.strip_offsets.clear();
        self.strip_panels.clear();
        self.strip_offsets.push(0);
        for strip in &mesh.strips {
            self.strip_panels.extend_from_slice(&strip.panels);
            self.strip_offsets.push(self.strip_panels.len());
        }
        self.surface_kind.clear();
        self.name_offsets.clear();
        self.names.clear();
        self.name_offsets.push(0);
        for surface in &mesh.surfaces {
            self.surface_kind.push(region_code(surface.region));
            self.names.extend_from_slice(surface.name.as_bytes());
            self.name_offsets.push(self.names.len());
        }
    }

    /// The ABI view of the buffers; valid while `self` is neither changed nor dropped.
    pub(crate) fn abi(&self) -> MeshAbi {
        MeshAbi {
            n_vertices: self.n_vertices,
            vertices_m: self.vertices.as_ptr(),
            n_panels: self.area.len(),
            panel_vertices: self.panel_vertices.as_ptr(),
            panel_vertex_count: self.vertex_count.as_ptr(),
            panel_surface: self.panel_surface.as_ptr(),
            centroid_m: self.centroid.as_ptr(),
            normal: self.normal.as_ptr(),
            area_m2: self.area.as_ptr(),
            n_strips: self.strip_offsets.len() - 1,
            strip_offsets: self.strip_offsets.as_ptr(),
            strip_panels: self.strip_panels.as_ptr(),
            n_surfaces: self.surface_kind.len(),
            surface_kind: self.surface_kind.as_ptr(),
            surface_name_offsets: self.name_offsets.as_ptr(),
            surface_names: self.names.as_ptr(),
        }
    }
}

pub(crate) fn flight_abi(flight: &FlightCondition) -> FlightAbi {
    let f = &flight.freestream;
    FlightAbi {
        mach: f.mach,
        altitude_m: f.altitude_m,
        pressure_pa: f.pressure_pa,
        temperature_k: f.temperature_k,
        density_kg_m3: f.density_kg_m3,
        speed_of_sound_m_s: f.speed_of_sound_m_s,
        velocity_m_s: f.velocity_m_s,
        dynamic_viscosity_pa_s: f.dynamic_viscosity_pa_s,
        dynamic_pressure_pa: f.dynamic_pressure_pa,
        gamma: f.gas.gamma,
        gas_constant_j_kg_k: f.gas.gas_constant_j_kg_k,
        alpha_rad: flight.alpha_rad,
        beta_rad: flight.beta_rad,
        angular_velocity_rad_s: flight.angular_velocity_rad_s.into(),
        rotation_center_m: flight.rotation_center_m.coords.into(),
    }
}

pub(crate) fn flight_from_abi(abi: &FlightAbi) -> FlightCondition {
    FlightCondition {
        freestream: Freestream {
            mach: abi.mach,
            altitude_m: abi.altitude_m,
            pressure_pa: abi.pressure_pa,
            temperature_k: abi.temperature_k,
            density_kg_m3: abi.density_kg_m3,
            speed_of_sound_m_s: abi.speed_of_sound_m_s,
            velocity_m_s: abi.velocity_m_s,
            dynamic_viscosity_pa_s: abi.dynamic_viscosity_pa_s,
            dynamic_pressure_pa: abi.dynamic_pressure_pa,
            gas: PerfectGas {
                gamma: abi.gamma,
                gas_constant_j_kg_k: abi.gas_constant_j_kg_k,
            },
        },
        alpha_rad: abi.alpha_rad,
        beta_rad: abi.beta_rad,
        angular_velocity_rad_s: Vector3::from(abi.angular_velocity_rad_s),
        rotation_center_m: Point3::from(abi.rotation_center_m),
    }
}

/// Edge states as 5 numbers per panel.
pub(crate) fn flatten_edges(edges: &[EdgeState], out: &mut Vec<f64>) {
    out.clear();
    for e in edges {
        out.extend_from_slice(&[
            e.mach,
            e.pressure_pa,
            e.temperature_k,
            e.density_kg_m3,
            e.velocity_m_s,
        ]);
    }
}

pub(crate) fn edge_from(values: &[f64]) -> EdgeState {
    EdgeState {
        mach: values[0],
        pressure_pa: values[1],
        temperature_k: values[2],
        density_kg_m3: values[3],
        velocity_m_s: values[4],
    }
}

/// `{"body": ..}`, `{"lifting_surface": .., "side": ..}`, `{"vertical_fin": ..}` or `"mesh"`.
pub(crate) fn geometry_json(geometry: &RegionGeometry) -> String {
    let value = match geometry {
        RegionGeometry::Body(body) => serde_json::json!({ "body": body }),
        RegionGeometry::LiftingSurface { planform, side } => {
            serde_json::json!({ "lifting_surface": planform, "side": side })
        }
        RegionGeometry::VerticalFin(fin) => serde_json::json!({ "vertical_fin": fin }),
        RegionGeometry::Mesh => serde_json::json!("mesh"),
    };
    value.to_string()
}

fn geometry_from_json(text: &str) -> Result<RegionGeometry, String> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Surface {
        lifting_surface: crate::geometry::LiftingSurfaceConfig,
        side: Side,
    }
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Body {
        body: crate::geometry::GeometryConfig,
    }
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Fin {
        vertical_fin: crate::geometry::VerticalFinConfig,
    }
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format!("region geometry is not JSON: {e}"))?;
    if value.as_str() == Some("mesh") {
        return Ok(RegionGeometry::Mesh);
    }
    if value.get("body").is_some() {
        let body: Body =
            serde_json::from_value(value).map_err(|e| format!("region body geometry: {e}"))?;
        return Ok(RegionGeometry::Body(body.body));
    }
    if value.get("vertical_fin").is_some() {
        let fin: Fin =
            serde_json::from_value(value).map_err(|e| format!("region fin geometry: {e}"))?;
        return Ok(RegionGeometry::VerticalFin(fin.vertical_fin));
    }
    let surface: Surface =
        serde_json::from_value(value).map_err(|e| format!("region geometry: {e}"))?;
    Ok(RegionGeometry::LiftingSurface {
        planform: surface.lifting_surface,
        side: surface.side,
    })
}

/// The owned data behind a [`RegionAbi`].
pub(crate) struct RegionBuffers {
    mesh: MeshBuffers,
    geometry: String,
}

impl RegionBuffers {
    pub(crate) fn new(region: &RegionInfo) -> Self {
        let mut mesh = MeshBuffers::default();
        mesh.fill(&region.mesh);
        Self {
            mesh,
            geometry: geometry_json(&region.geometry),
        }
    }

    /// The ABI view; valid while `self` and `region` live.
    pub(crate) fn abi(&self, region: &RegionInfo) -> RegionAbi {
        let r = &region.reference;
        RegionAbi {
            name: StrAbi::new(&region.name),
            kind: region_code(region.kind),
            side: match region.side {
                None => SIDE_NONE,
                Some(Side::Left) => SIDE_LEFT,
                Some(Side::Right) => SIDE_RIGHT,
            },
            mesh: self.mesh.abi(),
            reference: [
                r.area_m2,
                r.chord_m,
                r.span_m,
                r.moment_point_m[0],
                r.moment_point_m[1],
                r.moment_point_m[2],
            ],
            gamma: region.gas.gamma,
            gas_constant_j_kg_k: region.gas.gas_constant_j_kg_k,
            geometry_json: StrAbi::new(&self.geometry),
        }
    }
}

/// The region a controller is created with: named `control`, kind other, no mesh, zero
/// reference and gas values (a controller belongs to the vehicle, not to a region).
pub(crate) fn control_region(empty_mesh: &MeshBuffers) -> RegionAbi {
    RegionAbi {
        name: StrAbi::new("control"),
        kind: REGION_OTHER,
        side: SIDE_NONE,
        mesh: empty_mesh.abi(),
        reference: [0.0; 6],
        gamma: 0.0,
        gas_constant_j_kg_k: 0.0,
        geometry_json: StrAbi::new("\"mesh\""),
    }
}

/// A matrix from JSON rows of equal length.
fn matrix_from_rows(value: &serde_json::Value, what: &str) -> Result<DMatrix<f64>, String> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(value.clone())
        .map_err(|e| format!("`{what}` is not a list of rows of numbers: {e}"))?;
    let ncols = rows.first().map_or(0, Vec::len);
    if let Some(bad) = rows.iter().position(|r| r.len() != ncols) {
        return Err(format!(
            "`{what}` row {bad} has {} values, row 0 has {ncols}",
            rows[bad].len()
        ));
    }
    Ok(DMatrix::from_fn(rows.len(), ncols, |i, j| rows[i][j]))
}

fn names_from(value: &serde_json::Value, what: &str) -> Result<Vec<String>, String> {
    serde_json::from_value(value.clone())
        .map_err(|e| format!("`{what}` is not a list of names: {e}"))
}

/// A design model as the JSON of [`DesignSourceAbi::model`].
pub(crate) fn design_model_json(model: &LinearDesignModel) -> String {
    serde_json::json!({
        "state_names": model.state_names,
        "input_names": model.input_names,
        "a": matrix_rows(&model.a),
        "b": matrix_rows(&model.b),
        "reduction": model.reduction,
    })
    .to_string()
}

/// A design model from the JSON of [`DesignSourceAbi::model`], its shapes checked.
pub(crate) fn design_model_from_json(json: &str) -> Result<LinearDesignModel, String> {
    let v: serde_json::Value =
        serde_json::from_str(json).map_err(|e| format!("design model is not JSON: {e}"))?;
    let model = LinearDesignModel {
        state_names: names_from(&v["state_names"], "state_names")?,
        input_names: names_from(&v["input_names"], "input_names")?,
        a: matrix_from_rows(&v["a"], "a")?,
        b: matrix_from_rows(&v["b"], "b")?,
        reduction: v["reduction"].as_str().unwrap_or_default().to_owned(),
    };
    let (n, m) = (model.state_names.len(), model.input_names.len());
    if model.a.shape() != (n, n) || model.b.nrows() != n || (m > 0 && model.b.ncols() != m) {
        return Err(format!(
            "design model of {n} states and {m} inputs has A {:?} and B {:?}",
            model.a.shape(),
            model.b.shape()
        ));
    }
    Ok(model)
}

/// State-feedback laws as the JSON of [`ControlFunctions::state_feedback`].
pub(crate) fn state_feedback_json(laws: &[StateFeedback]) -> String {
    let laws = laws.iter().map(|law| {
        serde_json::json!({
            "state_names": law.state_names,
            "input_names": law.input_names,
            "k": matrix_rows(&law.k),
        })
    });
    serde_json::Value::Array(laws.collect()).to_string()
}

/// State-feedback laws from the JSON of [`ControlFunctions::state_feedback`], shapes checked.
pub(crate) fn state_feedback_from_json(json: &str) -> Result<Vec<StateFeedback>, String> {
    let v: serde_json::Value =
        serde_json::from_str(json).map_err(|e| format!("state feedback is not JSON: {e}"))?;
    let laws = v.as_array().ok_or("state feedback is not a JSON list")?;
    laws.iter()
        .map(|law| {
            let law = StateFeedback {
                state_names: names_from(&law["state_names"], "state_names")?,
                input_names: names_from(&law["input_names"], "input_names")?,
                k: matrix_from_rows(&law["k"], "k")?,
            };
            let shape = (law.input_names.len(), law.state_names.len());
            if law.k.shape() != shape {
                return Err(format!("gain K is {:?}, not {shape:?}", law.k.shape()));
            }
            Ok(law)
        })
        .collect()
}

/// A slice from an ABI pointer and count; a null pointer is an error unless `len` is 0.
///
/// # Safety
/// A non-null `ptr` must be valid for `len` values for `'a`.
pub(crate) unsafe fn slice<'a, T>(
    ptr: *const T,
    len: usize,
    what: &str,
) -> Result<&'a [T], String> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what}: null pointer for {len} values"));
    }
    // SAFETY: per the contract above.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// A mutable slice from an ABI pointer and count.
///
/// # Safety
/// A non-null `ptr` must be valid for writing `len` values for `'a`, and not aliased.
pub(crate) unsafe fn slice_mut<'a, T>(
    ptr: *mut T,
    len: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
    if len == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(format!("{what}: null pointer for {len} values"));
    }
    // SAFETY: per the contract above.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

/// A string from the ABI.
///
/// # Safety
/// `text.ptr` must be valid for `text.len` bytes for `'a`.
pub(crate) unsafe fn str_from<'a>(text: StrAbi, what: &str) -> Result<&'a str, String> {
    // SAFETY: per the contract above.
    let bytes = unsafe { slice(text.ptr, text.len, what)? };
    std::str::from_utf8(bytes).map_err(|_| format!("{what} is not UTF-8"))
}

fn point(values: &[f64], i: usize) -> [f64; 3] {
    [values[3 * i], values[3 * i + 1], values[3 * i + 2]]
}

/// Rebuilds a [`PanelMesh`] from `abi` into `out`, reusing its allocations; panel geometry is
/// copied as given (not recomputed), so the plugin sees exactly the host's numbers.
///
/// # Safety
/// The pointers of `abi` must be valid for the counts it states.
pub(crate) unsafe fn mesh_from_abi(abi: &MeshAbi, out: &mut PanelMesh) -> Result<(), String> {
    let (nv, np, ns, nsurf) = (abi.n_vertices, abi.n_panels, abi.n_strips, abi.n_surfaces);
    // SAFETY: per the contract above, for every array below.
    let (vertices, panel_vertices, counts, surfaces, centroid, normal, area) = unsafe {
        (
            slice(abi.vertices_m, 3 * nv, "mesh vertices")?,
            slice(abi.panel_vertices, 4 * np, "panel vertices")?,
            slice(abi.panel_vertex_count, np, "panel vertex counts")?,
            slice(abi.panel_surface, np, "panel surfaces")?,
            slice(abi.centroid_m, 3 * np, "panel centroids")?,
            slice(abi.normal, 3 * np, "panel normals")?,
            slice(abi.area_m2, np, "panel areas")?,
        )
    };
    let (offsets, kinds, name_offsets) = unsafe {
        (
            slice(abi.strip_offsets, ns + 1, "strip offsets")?,
            slice(abi.surface_kind, nsurf, "surface kinds")?,
            slice(abi.surface_name_offsets, nsurf + 1, "surface name offsets")?,
        )
    };
    if offsets[0] != 0 || offsets.windows(2).any(|w| w[1] < w[0]) {
        return Err("strip offsets do not start at 0 and increase".to_owned());
    }
    if name_offsets[0] != 0 || name_offsets.windows(2).any(|w| w[1] < w[0]) {
        return Err("surface name offsets do not start at 0 and increase".to_owned());
    }
    let strip_panels = unsafe { slice(abi.strip_panels, offsets[ns], "strip panels")? };
    let names = unsafe { slice(abi.surface_names, name_offsets[nsurf], "surface names")? };
    if let Some(bad) = panel_vertices.iter().find(|&&v| v >= nv) {
        return Err(format!("panel vertex index {bad} >= {nv} vertices"));
    }
    if let Some(bad) = surfaces.iter().find(|&&s| s as usize >= nsurf) {
        return Err(format!("panel surface index {bad} >= {nsurf} surfaces"));
    }
    if let Some(bad) = strip_panels.iter().find(|&&p| p >= np) {
        return Err(format!("strip panel index {bad} >= {np} panels"));
    }
    if let Some(bad) = counts.iter().find(|&&c| c != 3 && c != 4) {
        return Err(format!("panel vertex count {bad} is not 3 or 4"));
    }
    out.vertices.clear();
    out.vertices
        .extend((0..nv).map(|i| Point3::from(point(vertices, i))));
    out.panels.clear();
    for i in 0..np {
        let surface = u16::try_from(surfaces[i])
            .map_err(|_| format!("panel surface index {} exceeds 65535", surfaces[i]))?;
        out.panels.push(Panel {
            vertices: [
                panel_vertices[4 * i],
                panel_vertices[4 * i + 1],
                panel_vertices[4 * i + 2],
                panel_vertices[4 * i + 3],
            ],
            vertex_count: counts[i],
            centroid: Point3::from(point(centroid, i)),
            normal: Vector3::from(point(normal, i)),
            area_m2: area[i],
            surface,
        });
    }
    let same_strips = out.strips.len() == ns
        && out
            .strips
            .iter()
            .enumerate()
            .all(|(s, strip)| strip.panels == strip_panels[offsets[s]..offsets[s + 1]]);
    if !same_strips {
        out.strips.clear();
        out.strips.extend(offsets.windows(2).map(|w| Strip {
            panels: strip_panels[w[0]..w[1]].to_vec(),
        }));
    }
    let mut same_surfaces = out.surfaces.len() == nsurf;
    for s in 0..nsurf {
        let name = std::str::from_utf8(&names[name_offsets[s]..name_offsets[s + 1]])
            .map_err(|_| format!("surface {s} name is not UTF-8"))?;
        let kind = region_kind(kinds[s])?;
        same_surfaces =
            same_surfaces && out.surfaces[s].name == name && out.surfaces[s].region == kind;
    }
    if !same_surfaces {
        out.surfaces.clear();
        for s in 0..nsurf {
            let name = String::from_utf8_lossy(&names[name_offsets[s]..name_offsets[s + 1]]);
            out.surfaces
                .push(Surface::new(name.into_owned(), region_kind(kinds[s])?));
        }
    }
    Ok(())
}

/// Rebuilds the region a plugin model is created for, with `settings` as its only model settings.
///
/// # Safety
/// The pointers of `abi` must be valid for the counts they state.
pub(crate) unsafe fn region_from_abi(
    abi: &RegionAbi,
    model: &str,
    settings: ModelSettings,
    file: &str,
) -> Result<RegionInfo, String> {
    // SAFETY: per the contract above.
    let name = unsafe { str_from(abi.name, "region name")? };
    let geometry = unsafe { str_from(abi.geometry_json, "region geometry")? };
    let mut mesh = PanelMesh::default();
    unsafe { mesh_from_abi(&abi.mesh, &mut mesh)? };
    let side = match abi.side {
        SIDE_NONE => None,
        SIDE_LEFT => Some(Side::Left),
        SIDE_RIGHT => Some(Side::Right),
        other => return Err(format!("side code {other} is not 0-2")),
    };
    let r = abi.reference;
    Ok(RegionInfo {
        name: name.to_owned(),
        kind: region_kind(abi.kind)?,
        side,
        geometry: geometry_from_json(geometry)?,
        mesh,
        reference: ReferenceValues {
            area_m2: r[0],
            chord_m: r[1],
            span_m: r[2],
            moment_point_m: [r[3], r[4], r[5]],
        },
        gas: PerfectGas {
            gamma: abi.gamma,
            gas_constant_j_kg_k: abi.gas_constant_j_kg_k,
        },
        file: file.to_owned(),
        settings: BTreeMap::from([(model.to_owned(), settings)]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh survives the round trip exactly (geometry copied, not recomputed), and an index
    /// past the end of its array is an error on the plugin side instead of a wild read.
    #[test]
    fn meshes_round_trip_and_bad_indices_are_rejected() {
        let mesh = crate::testing::sample_region("right_surface").mesh.clone();
        let mut buffers = MeshBuffers::default();
        buffers.fill(&mesh);
        let mut rebuilt = PanelMesh::default();
        // SAFETY: the ABI view of live buffers.
        unsafe { mesh_from_abi(&buffers.abi(), &mut rebuilt) }.unwrap();
        assert_eq!(rebuilt, mesh);

        buffers.panel_vertices[5] = mesh.vertices.len();
        let err = unsafe { mesh_from_abi(&buffers.abi(), &mut rebuilt) }.unwrap_err();
        assert!(err.contains("panel vertex index"), "{err}");
        buffers.fill(&mesh);
        buffers.strip_panels[0] = mesh.panels.len() + 3;
        let err = unsafe { mesh_from_abi(&buffers.abi(), &mut rebuilt) }.unwrap_err();
        assert!(err.contains("strip panel index"), "{err}");
    }

    /// Every region geometry a plugin can be handed survives its JSON round trip.
    #[test]
    fn region_geometries_round_trip() {
        let fin = crate::testing::sample_vertical_fin();
        for geometry in [
            crate::testing::sample_region("right_surface")
                .geometry
                .clone(),
            crate::testing::sample_region("main_body").geometry.clone(),
            RegionGeometry::VerticalFin(fin),
            RegionGeometry::Mesh,
        ] {
            assert_eq!(
                geometry_from_json(&geometry_json(&geometry)).expect("parses"),
                geometry
            );
        }
    }
}
