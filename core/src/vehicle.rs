//! The sample vehicle's geometry: the `[geometry]` and `[lifting_surface]` config tables and the
//! panel meshes built from them (main body and the two all-movable lifting surfaces).
//!
//! **Body frame.** Origin at the nose tip; x forward (so every point of the vehicle has x ≤ 0 and
//! the tail is at x = -length), y right, z down; z = 0 is the horizontal line through the nose
//! (the "nose line"). The moment reference point is on the centerline `forebody_length_m` aft of
//! the nose (paper Table 1: the fore and aft beams join there), at `reference_z_m`.
//!
//! **Body profile** (Bolender & Doman 2007, "Nonlinear longitudinal dynamical model of an
//! air-breathing hypersonic vehicle", J. Spacecraft Rockets 44(2)), extruded over the width:
//! the upper surface rises aft from the nose; the lower forebody is the inlet ramp down to the
//! inlet; the engine (full body width) hangs below the body from the inlet to the engine exit,
//! its underside the flat cowl; aft of the engine the aftbody lower surface is the external
//! nozzle, rising to the tail, where a (possibly zero-height) base closes the profile.
//!
//! **Body mesh surfaces** (name, region):
//! `upper-forebody`, `upper-aftbody` (main body); `inlet-ramp` (propulsion); `cowl` (main body,
//! the engine's outer underside); `nozzle` (propulsion); `left-side`, `right-side` (main body,
//! including the engine's outer side walls); `base` (main body); `inlet-face`, `nozzle-exit`
//! (other: caps over the engine's capture area and exit so the mesh is closed; the internal flow
//! path is not meshed, the engine model owns it). The body mesh is closed and its enclosed
//! volume includes the capped engine flow path.
//!
//! **Strips** run upstream to downstream (x decreasing): one per spanwise column on the upper
//! surface (nose to tail across both upper surfaces), on the inlet ramp (nose to inlet), on the
//! cowl (cowl lip to engine exit) and on the nozzle (engine exit to tail); one per row on each
//! side (nose to tail above the flow path, inlet to exit on the engine walls). Base and caps are
//! in no strip: models treat them panel by panel.
//!
//! **Lifting surfaces** (after Falkiewicz & Cesnik): trapezoidal, double-wedge section, mounted
//! on the body sides with the torque tube (pivot axis) parallel to y. Each mesh is closed:
//! `<side>-surface-upper`, `<side>-surface-lower`, `<side>-surface-tip` (lifting surface) and
//! `<side>-surface-root` (other: the root cap against the body). Strips run leading edge to
//! trailing edge along the chord at each spanwise station, on the upper and lower surfaces.

use nalgebra::{Point2, Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::{MeshError, PanelMesh, PanelSpec, RegionKind, Strip, Surface, weld_vertices};

/// The `[geometry]` table: the body profile after Bolender & Doman (2007) and its discretisation.
/// Distances in m, angles in degrees (radians internally), all measured in the body frame
/// described in the module docs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryConfig {
    /// Nose to tail, m.
    pub length_m: f64,
    /// Nose to the fore/aft beam junction and moment reference point, m; the upper surface may
    /// change slope here.
    pub forebody_length_m: f64,
    /// z of the moment reference point below the nose line, m.
    pub reference_z_m: f64,
    /// Body (and engine) width, m.
    pub width_m: f64,
    /// Upper forebody surface angle above the nose line, deg (rises aft).
    pub upper_forebody_angle_deg: f64,
    /// Upper aftbody surface angle above the nose line, deg (rises aft).
    pub upper_aftbody_angle_deg: f64,
    /// Lower forebody (inlet ramp) angle below the nose line, deg.
    pub lower_forebody_angle_deg: f64,
    /// Nose to the inlet (end of the ramp, cowl lip station), m.
    pub inlet_aft_of_nose_m: f64,
    /// Inlet to engine exit, m.
    pub engine_length_m: f64,
    /// Cowl lip below the ramp end (engine capture height), m.
    pub inlet_height_m: f64,
    /// Combustor duct height, m (used by the engine models; not meshed).
    pub combustor_height_m: f64,
    /// Aftbody lower surface (external nozzle) angle above the nose line, deg (rises aft).
    pub nozzle_angle_deg: f64,
    /// Panels along x, nose to tail (distributed over the profile's segments by length; each
    /// segment gets at least one).
    pub panels_along_x: usize,
    /// Panels across the width on the upper and lower surfaces, base and caps.
    pub panels_across_width: usize,
    /// Panel rows on each side between the upper surface and the ramp/engine top/nozzle.
    pub panels_per_side: usize,
    /// Panel rows over the engine height on its side walls and the inlet and exit caps.
    pub panels_engine_height: usize,
}

/// The `[lifting_surface]` table: one trapezoidal all-movable surface with a double-wedge
/// section (after Falkiewicz & Cesnik), mirrored to the left side. Distances in m, angles in
/// degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LiftingSurfaceConfig {
    /// Chord at the root, m.
    pub root_chord_m: f64,
    /// Chord at the tip, m.
    pub tip_chord_m: f64,
    /// Root to tip of one surface, m.
    pub span_m: f64,
    /// Leading-edge sweep, deg (positive: tip aft).
    pub leading_edge_sweep_deg: f64,
    /// Maximum thickness over chord, same at every station.
    pub thickness_to_chord: f64,
    /// Chordwise position of the maximum thickness (ridge of the double wedge) over chord.
    pub max_thickness_chord_fraction: f64,
    /// Nose to the pivot (torque tube) axis, m.
    pub pivot_aft_of_nose_m: f64,
    /// Pivot position along the root chord from the root leading edge, over root chord.
    pub pivot_root_chord_fraction: f64,
    /// z of the pivot axis (and the surface's mid-plane) below the nose line, m.
    pub pivot_z_m: f64,
    /// Distance of the root from the centerline, m (the body's half width when mounted on its
    /// sides).
    pub root_y_m: f64,
    /// Panels along the chord on each of the upper and lower surfaces (≥ 2, split over the two
    /// wedges by length).
    pub panels_chordwise: usize,
    /// Panels along the span.
    pub panels_spanwise: usize,
}

/// Which lifting surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// y < 0.
    Left,
    /// y > 0.
    Right,
}

impl Side {
    /// "left" or "right".
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// -1 for left, +1 for right.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => -1.0,
            Side::Right => 1.0,
        }
    }
}

/// Why the vehicle geometry could not be read or built.
#[derive(Debug, thiserror::Error)]
pub enum VehicleError {
    /// A config value is out of range or inconsistent with another.
    #[error("[{table}] {key} = {value}: {message}")]
    Invalid {
        table: &'static str,
        key: &'static str,
        value: String,
        message: String,
    },
    /// The config text could not be parsed.
    #[error("{origin}: {message}")]
    Parse { origin: String, message: String },
    /// The generated mesh failed validation (a bug or an extreme config).
    #[error("{what} mesh: {source}")]
    Mesh {
        what: &'static str,
        source: MeshError,
    },
}

/// The side profile of the body in the body x-z plane (x ≤ 0 aft of the nose, z down), m.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyProfile {
    /// Nose tip, (0, 0).
    pub nose_m: Point2<f64>,
    /// Upper surface at the forebody/aftbody junction.
    pub upper_junction_m: Point2<f64>,
    /// Upper surface at the tail.
    pub tail_upper_m: Point2<f64>,
    /// Nozzle surface at the tail (equal to `tail_upper_m` for a sharp tail).
    pub tail_lower_m: Point2<f64>,
    /// Start of the external nozzle: top of the engine flow path at the engine exit.
    pub nozzle_start_m: Point2<f64>,
    /// Bottom of the engine (cowl) at the engine exit.
    pub engine_exit_lower_m: Point2<f64>,
    /// Cowl lip.
    pub cowl_lip_m: Point2<f64>,
    /// End of the inlet ramp (top of the flow path at the inlet).
    pub ramp_end_m: Point2<f64>,
}

impl BodyProfile {
    /// The closed outline: nose, upper surface, base, nozzle, engine exit, cowl, inlet, ramp.
    pub fn outline_m(&self) -> [Point2<f64>; 8] {
        [
            self.nose_m,
            self.upper_junction_m,
            self.tail_upper_m,
            self.tail_lower_m,
            self.nozzle_start_m,
            self.engine_exit_lower_m,
            self.cowl_lip_m,
            self.ramp_end_m,
        ]
    }

    /// Enclosed area of the outline (shoelace formula), m².
    pub fn area_m2(&self) -> f64 {
        let o = self.outline_m();
        let twice: f64 = (0..o.len())
            .map(|i| {
                let (a, b) = (o[i], o[(i + 1) % o.len()]);
                a.x * b.y - b.x * a.y
            })
            .sum();
        0.5 * twice.abs()
    }

    /// Perimeter of the outline, m.
    pub fn perimeter_m(&self) -> f64 {
        let o = self.outline_m();
        (0..o.len())
            .map(|i| (o[(i + 1) % o.len()] - o[i]).norm())
            .sum()
    }
}

/// The vehicle's meshes and reference quantities, body frame (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleGeometry {
    /// Closed main-body mesh (surfaces and strips in the module docs).
    pub body: PanelMesh,
    /// Closed left lifting-surface mesh (y < 0).
    pub left_surface: PanelMesh,
    /// Closed right lifting-surface mesh (y > 0), mirror image of the left.
    pub right_surface: PanelMesh,
    /// Moment reference point: centerline, `forebody_length_m` aft of the nose, m.
    pub reference_point_m: Point3<f64>,
    /// Nose to tail, m.
    pub length_m: f64,
    /// Body width, m.
    pub width_m: f64,
    /// Root end of the left torque tube (pivot axis parallel to y), m.
    pub left_pivot_m: Point3<f64>,
    /// Root end of the right torque tube (pivot axis parallel to y), m.
    pub right_pivot_m: Point3<f64>,
    /// Side profile of the body.
    pub profile: BodyProfile,
}

fn invalid(
    table: &'static str,
    key: &'static str,
    value: impl ToString,
    message: impl Into<String>,
) -> VehicleError {
    VehicleError::Invalid {
        table,
        key,
        value: value.to_string(),
        message: message.into(),
    }
}

/// Checks that `v` is finite and inside (lo, hi) (open) or [lo, hi] (closed).
fn check_range(
    table: &'static str,
    key: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    closed: bool,
) -> Result<(), VehicleError> {
    let inside = if closed {
        v >= lo && v <= hi
    } else {
        v > lo && v < hi
    };
    if v.is_finite() && inside {
        Ok(())
    } else {
        let (l, r) = if closed { ("[", "]") } else { ("(", ")") };
        Err(invalid(
            table,
            key,
            v,
            format!("must be finite and in {l}{lo}, {hi}{r}"),
        ))
    }
}

/// Checks a panel count is in [min, 10000].
fn check_count(
    table: &'static str,
    key: &'static str,
    n: usize,
    min: usize,
) -> Result<(), VehicleError> {
    if (min..=10_000).contains(&n) {
        Ok(())
    } else {
        Err(invalid(
            table,
            key,
            n,
            format!("must be between {min} and 10000"),
        ))
    }
}

/// Profile functions of a validated [`GeometryConfig`]; s is the distance aft of the nose, m.
struct Profile {
    length: f64,
    junction: f64,
    inlet: f64,
    exit: f64,
    tan_upper_fore: f64,
    tan_upper_aft: f64,
    tan_ramp: f64,
    tan_nozzle: f64,
    /// z of the flow path top (ramp end), m.
    z_ramp_end: f64,
    /// z of the cowl, m.
    z_cowl: f64,
}

impl Profile {
    fn new(g: &GeometryConfig) -> Result<Self, VehicleError> {
        const T: &str = "geometry";
        check_range(T, "length_m", g.length_m, 0.0, 1e4, false)?;
        check_range(
            T,
            "forebody_length_m",
            g.forebody_length_m,
            0.0,
            g.length_m,
            false,
        )?;
        check_range(T, "reference_z_m", g.reference_z_m, -1e4, 1e4, true)?;
        check_range(T, "width_m", g.width_m, 0.0, 1e4, false)?;
        for (key, v) in [
            ("upper_forebody_angle_deg", g.upper_forebody_angle_deg),
            ("upper_aftbody_angle_deg", g.upper_aftbody_angle_deg),
            ("lower_forebody_angle_deg", g.lower_forebody_angle_deg),
            ("nozzle_angle_deg", g.nozzle_angle_deg),
        ] {
            check_range(T, key, v, -80.0, 80.0, true)?;
        }
        check_range(
            T,
            "inlet_aft_of_nose_m",
            g.inlet_aft_of_nose_m,
            0.0,
            g.length_m,
            false,
        )?;
        check_range(
            T,
            "engine_length_m",
            g.engine_length_m,
            0.0,
            g.length_m - g.inlet_aft_of_nose_m,
            false,
        )
        .map_err(|_| {
            invalid(
                T,
                "engine_length_m",
                g.engine_length_m,
                format!(
                    "must be > 0 and end before the tail (inlet_aft_of_nose_m + engine_length_m < length_m = {})",
                    g.length_m
                ),
            )
        })?;
        check_range(
            T,
            "inlet_height_m",
            g.inlet_height_m,
            0.0,
            g.length_m,
            false,
        )?;
        check_range(
            T,
            "combustor_height_m",
            g.combustor_height_m,
            0.0,
            g.length_m,
            false,
        )?;
        check_count(T, "panels_along_x", g.panels_along_x, 1)?;
        check_count(T, "panels_across_width", g.panels_across_width, 1)?;
        check_count(T, "panels_per_side", g.panels_per_side, 1)?;
        check_count(T, "panels_engine_height", g.panels_engine_height, 1)?;
        let p = Self {
            length: g.length_m,
            junction: g.forebody_length_m,
            inlet: g.inlet_aft_of_nose_m,
            exit: g.inlet_aft_of_nose_m + g.engine_length_m,
            tan_upper_fore: g.upper_forebody_angle_deg.to_radians().tan(),
            tan_upper_aft: g.upper_aftbody_angle_deg.to_radians().tan(),
            tan_ramp: g.lower_forebody_angle_deg.to_radians().tan(),
            tan_nozzle: g.nozzle_angle_deg.to_radians().tan(),
            z_ramp_end: g.inlet_aft_of_nose_m * g.lower_forebody_angle_deg.to_radians().tan(),
            z_cowl: g.inlet_aft_of_nose_m * g.lower_forebody_angle_deg.to_radians().tan()
                + g.inlet_height_m,
        };
        // The body must have positive thickness everywhere aft of the nose (zero allowed at the
        // tail); both boundaries are piecewise linear, so checking the breakpoints suffices.
        for (s, what) in [
            (p.junction, "at the forebody/aftbody junction"),
            (p.inlet, "at the inlet"),
            (p.exit, "at the engine exit"),
        ] {
            if p.z_lower(s) - p.z_upper(s) <= 0.0 {
                return Err(invalid(
                    T,
                    "upper_forebody_angle_deg",
                    g.upper_forebody_angle_deg,
                    format!(
                        "the upper surface is not above the lower surface {what} (s = {s} m aft of the nose); check the surface angles"
                    ),
                ));
            }
        }
        let nozzle_end = p.z_ramp_end - (p.length - p.exit) * p.tan_nozzle;
        let tail = nozzle_end - p.z_upper(p.length);
        if tail < -1e-9 * p.length {
            return Err(invalid(
                T,
                "nozzle_angle_deg",
                g.nozzle_angle_deg,
                format!(
                    "the nozzle surface crosses the upper surface before the tail (base height {tail:.4} m < 0); reduce the nozzle angle"
                ),
            ));
        }
        Ok(p)
    }

    /// Upper surface z at s, m.
    fn z_upper(&self, s: f64) -> f64 {
        if s <= self.junction {
            -s * self.tan_upper_fore
        } else {
            -self.junction * self.tan_upper_fore - (s - self.junction) * self.tan_upper_aft
        }
    }

    /// Lower boundary of the body above the flow path (ramp, engine top, nozzle) at s, m.
    fn z_lower(&self, s: f64) -> f64 {
        if s <= self.inlet {
            s * self.tan_ramp
        } else if s <= self.exit {
            self.z_ramp_end
        } else {
            // Validation keeps the nozzle below the upper surface; `max` only absorbs round-off.
            (self.z_ramp_end - (s - self.exit) * self.tan_nozzle).max(self.z_upper(s))
        }
    }

    fn body_profile(&self) -> BodyProfile {
        let pt = |s: f64, z: f64| Point2::new(-s, z);
        BodyProfile {
            nose_m: pt(0.0, 0.0),
            upper_junction_m: pt(self.junction, self.z_upper(self.junction)),
            tail_upper_m: pt(self.length, self.z_upper(self.length)),
            tail_lower_m: pt(self.length, self.z_lower(self.length)),
            nozzle_start_m: pt(self.exit, self.z_ramp_end),
            engine_exit_lower_m: pt(self.exit, self.z_cowl),
            cowl_lip_m: pt(self.inlet, self.z_cowl),
            ramp_end_m: pt(self.inlet, self.z_ramp_end),
        }
    }

    /// Stations along the body, s = 0..length, with every breakpoint included; about `n`
    /// panels distributed by segment length (largest remainder, at least one per segment).
    fn stations(&self, n: usize) -> Vec<f64> {
        let mut breaks = vec![0.0, self.junction, self.inlet, self.exit, self.length];
        breaks.sort_by(f64::total_cmp);
        breaks.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * self.length);
        let lengths: Vec<f64> = breaks.windows(2).map(|w| w[1] - w[0]).collect();
        let counts = distribute(n, &lengths);
        let mut out = Vec::with_capacity(counts.iter().sum::<usize>() + 1);
        out.push(0.0);
        for (w, &c) in breaks.windows(2).zip(&counts) {
            for k in 1..=c {
                out.push(if k == c {
                    w[1]
                } else {
                    lerp(w[0], w[1], k as f64 / c as f64)
                });
            }
        }
        out
    }
}

/// Splits `n` items over segments proportionally to `lengths` (largest remainder), ≥ 1 each.
fn distribute(n: usize, lengths: &[f64]) -> Vec<usize> {
    let total: f64 = lengths.iter().sum();
    let n = n.max(lengths.len());
    let spare = n - lengths.len();
    let ideal: Vec<f64> = lengths.iter().map(|l| spare as f64 * l / total).collect();
    let mut counts: Vec<usize> = ideal.iter().map(|x| 1 + x.floor() as usize).collect();
    let mut left = n.saturating_sub(counts.iter().sum());
    let mut order: Vec<usize> = (0..lengths.len()).collect();
    order.sort_by(|&a, &b| (ideal[b] - ideal[b].floor()).total_cmp(&(ideal[a] - ideal[a].floor())));
    for &i in order.iter().cycle() {
        if left == 0 {
            break;
        }
        counts[i] += 1;
        left -= 1;
    }
    counts
}

/// a (1 - t) + b t, exact at t = 0 and t = 1.
fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a * (1.0 - t) + b * t
}

/// Collects polygons over free points, then welds, drops collapsed polygons, orients each by
/// an outward hint and builds the mesh.
#[derive(Default)]
struct Builder {
    points: Vec<Point3<f64>>,
    polys: Vec<([usize; 4], u16, Vector3<f64>)>,
    strips: Vec<Vec<usize>>,
    surfaces: Vec<Surface>,
}

impl Builder {
    fn surface(&mut self, name: impl Into<String>, region: RegionKind) -> u16 {
        self.surfaces.push(Surface::new(name, region));
        // A handful of surfaces per mesh; cannot overflow.
        u16::try_from(self.surfaces.len() - 1).unwrap_or(u16::MAX)
    }

    /// Quads over `nodes[i][j]` (i streamwise, j across); with `strips`, one strip per j with
    /// panels in increasing i.
    fn grid(
        &mut self,
        nodes: &[Vec<Point3<f64>>],
        surface_of: impl Fn(usize) -> u16,
        outward: Vector3<f64>,
        strips: bool,
    ) {
        let ni = nodes.len().saturating_sub(1);
        let nj = nodes.first().map_or(0, |r| r.len().saturating_sub(1));
        let base = self.points.len();
        for row in nodes {
            self.points.extend_from_slice(row);
        }
        let id = |i: usize, j: usize| base + i * (nj + 1) + j;
        let first_poly = self.polys.len();
        for j in 0..nj {
            for i in 0..ni {
                self.polys.push((
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                    surface_of(i),
                    outward,
                ));
            }
        }
        if strips {
            for j in 0..nj {
                self.strips
                    .push((0..ni).map(|i| first_poly + j * ni + i).collect());
            }
        }
    }

    fn finish(self, what: &'static str) -> Result<PanelMesh, VehicleError> {
        let (lo, hi) = crate::mesh::bounding_box_of(&self.points);
        let size = (hi - lo).norm();
        let (welded, map) = weld_vertices(&self.points, 1e-9 * size);
        let min_twice_area = 2.0 * (1e-10 * size).powi(2);
        let mut new_index = vec![None; self.polys.len()];
        let mut specs = Vec::with_capacity(self.polys.len());
        for (k, (raw, surface, outward)) in self.polys.iter().enumerate() {
            // Map to welded vertices and drop repeats (cyclically).
            let mut v: Vec<usize> = Vec::with_capacity(4);
            for &r in raw {
                let w = map[r];
                if v.last() != Some(&w) {
                    v.push(w);
                }
            }
            while v.len() > 1 && v.first() == v.last() {
                v.pop();
            }
            if v.len() < 3 {
                continue;
            }
            let p = |i: usize| welded[v[i]];
            let cross = if v.len() == 4 {
                (p(2) - p(0)).cross(&(p(3) - p(1)))
            } else {
                (p(1) - p(0)).cross(&(p(2) - p(0)))
            };
            if cross.norm() <= min_twice_area {
                continue;
            }
            if cross.dot(outward) < 0.0 {
                v.reverse();
            }
            new_index[k] = Some(specs.len());
            specs.push(if v.len() == 4 {
                PanelSpec::quad(v[0], v[1], v[2], v[3], *surface)
            } else {
                PanelSpec::triangle(v[0], v[1], v[2], *surface)
            });
        }
        let strips = self
            .strips
            .iter()
            .map(|s| Strip {
                panels: s.iter().filter_map(|&k| new_index[k]).collect(),
            })
            .filter(|s| !s.panels.is_empty())
            .collect();
        PanelMesh::new(welded, &specs, strips, self.surfaces)
            .map_err(|source| VehicleError::Mesh { what, source })
    }
}

/// The body's side profile (checks the config).
pub fn body_profile(geometry: &GeometryConfig) -> Result<BodyProfile, VehicleError> {
    Profile::new(geometry).map(|p| p.body_profile())
}

/// The closed main-body mesh (surfaces, regions and strips in the module docs).
pub fn body_mesh(geometry: &GeometryConfig) -> Result<PanelMesh, VehicleError> {
    let prof = Profile::new(geometry)?;
    let xs = prof.stations(geometry.panels_along_x);
    let n = xs.len() - 1;
    let index_of = |s: f64| {
        xs.iter()
            .position(|&x| (x - s).abs() <= 1e-9 * prof.length)
            .unwrap_or(0)
    };
    let (i_inlet, i_exit) = (index_of(prof.inlet), index_of(prof.exit));
    let half_w = 0.5 * geometry.width_m;
    let ny = geometry.panels_across_width;
    let nz = geometry.panels_per_side;
    let ne = geometry.panels_engine_height;
    let ys: Vec<f64> = (0..=ny)
        .map(|j| lerp(-half_w, half_w, j as f64 / ny as f64))
        .collect();
    let p3 = |s: f64, y: f64, z: f64| Point3::new(-s, y, z);

    let mut b = Builder::default();
    let upper_fore = b.surface("upper-forebody", RegionKind::MainBody);
    let upper_aft = b.surface("upper-aftbody", RegionKind::MainBody);
    let ramp = b.surface("inlet-ramp", RegionKind::Propulsion);
    let cowl = b.surface("cowl", RegionKind::MainBody);
    let nozzle = b.surface("nozzle", RegionKind::Propulsion);
    let left = b.surface("left-side", RegionKind::MainBody);
    let right = b.surface("right-side", RegionKind::MainBody);
    let base = b.surface("base", RegionKind::MainBody);
    let inlet_face = b.surface("inlet-face", RegionKind::Other);
    let nozzle_exit = b.surface("nozzle-exit", RegionKind::Other);

    let up = -Vector3::z();
    let down = Vector3::z();
    let fwd = Vector3::x();

    // Upper surface, nose to tail.
    let nodes: Vec<Vec<Point3<f64>>> = xs
        .iter()
        .map(|&s| ys.iter().map(|&y| p3(s, y, prof.z_upper(s))).collect())
        .collect();
    let junction = prof.junction;
    b.grid(
        &nodes,
        |i| {
            if 0.5 * (xs[i] + xs[i + 1]) < junction {
                upper_fore
            } else {
                upper_aft
            }
        },
        up,
        true,
    );

    // Lower surfaces: ramp (nose to inlet), cowl (inlet to exit), nozzle (exit to tail).
    let lower = |range: std::ops::RangeInclusive<usize>, z: &dyn Fn(f64) -> f64| {
        xs[range]
            .iter()
            .map(|&s| ys.iter().map(|&y| p3(s, y, z(s))).collect())
            .collect::<Vec<Vec<_>>>()
    };
    b.grid(
        &lower(0..=i_inlet, &|s| prof.z_lower(s)),
        |_| ramp,
        down,
        true,
    );
    b.grid(
        &lower(i_inlet..=i_exit, &|_| prof.z_cowl),
        |_| cowl,
        down,
        true,
    );
    b.grid(
        &lower(i_exit..=n, &|s| prof.z_lower(s)),
        |_| nozzle,
        down,
        true,
    );

    // Sides: above the flow path (nose to tail) and the engine walls (inlet to exit).
    for (y, surface, outward) in [
        (-half_w, left, -Vector3::y()),
        (half_w, right, Vector3::y()),
    ] {
        let nodes: Vec<Vec<Point3<f64>>> = xs
            .iter()
            .map(|&s| {
                (0..=nz)
                    .map(|k| {
                        let t = k as f64 / nz as f64;
                        p3(s, y, lerp(prof.z_upper(s), prof.z_lower(s), t))
                    })
                    .collect()
            })
            .collect();
        b.grid(&nodes, |_| surface, outward, true);
        let nodes: Vec<Vec<Point3<f64>>> = xs[i_inlet..=i_exit]
            .iter()
            .map(|&s| {
                (0..=ne)
                    .map(|k| {
                        p3(
                            s,
                            y,
                            lerp(prof.z_ramp_end, prof.z_cowl, k as f64 / ne as f64),
                        )
                    })
                    .collect()
            })
            .collect();
        b.grid(&nodes, |_| surface, outward, true);
    }

    // Base (collapses away for a sharp tail) and the engine caps.
    let cap = |s: f64, z0: f64, z1: f64, rows: usize| -> Vec<Vec<Point3<f64>>> {
        ys.iter()
            .map(|&y| {
                (0..=rows)
                    .map(|k| p3(s, y, lerp(z0, z1, k as f64 / rows as f64)))
                    .collect()
            })
            .collect()
    };
    let l = prof.length;
    b.grid(
        &cap(l, prof.z_upper(l), prof.z_lower(l), nz),
        |_| base,
        -fwd,
        false,
    );
    b.grid(
        &cap(prof.inlet, prof.z_ramp_end, prof.z_cowl, ne),
        |_| inlet_face,
        fwd,
        false,
    );
    b.grid(
        &cap(prof.exit, prof.z_ramp_end, prof.z_cowl, ne),
        |_| nozzle_exit,
        -fwd,
        false,
    );
    b.finish("body")
}

/// Validated lifting-surface planform quantities.
struct Planform {
    root_chord: f64,
    tip_chord: f64,
    span: f64,
    tan_sweep: f64,
    tc: f64,
    ridge: f64,
    root_le_s: f64,
    root_y: f64,
    pivot_z: f64,
}

impl Planform {
    fn new(c: &LiftingSurfaceConfig) -> Result<Self, VehicleError> {
        const T: &str = "lifting_surface";
        check_range(T, "root_chord_m", c.root_chord_m, 0.0, 1e4, false)?;
        check_range(T, "tip_chord_m", c.tip_chord_m, 0.0, 1e4, false)?;
        check_range(T, "span_m", c.span_m, 0.0, 1e4, false)?;
        check_range(
            T,
            "leading_edge_sweep_deg",
            c.leading_edge_sweep_deg,
            -80.0,
            80.0,
            true,
        )?;
        check_range(
            T,
            "thickness_to_chord",
            c.thickness_to_chord,
            0.0,
            0.5,
            false,
        )?;
        check_range(
            T,
            "max_thickness_chord_fraction",
            c.max_thickness_chord_fraction,
            0.0,
            1.0,
            false,
        )?;
        check_range(
            T,
            "pivot_aft_of_nose_m",
            c.pivot_aft_of_nose_m,
            -1e4,
            1e4,
            true,
        )?;
        check_range(
            T,
            "pivot_root_chord_fraction",
            c.pivot_root_chord_fraction,
            0.0,
            1.0,
            true,
        )?;
        check_range(T, "pivot_z_m", c.pivot_z_m, -1e4, 1e4, true)?;
        check_range(T, "root_y_m", c.root_y_m, 0.0, 1e4, true)?;
        check_count(T, "panels_chordwise", c.panels_chordwise, 2)?;
        check_count(T, "panels_spanwise", c.panels_spanwise, 1)?;
        Ok(Self {
            root_chord: c.root_chord_m,
            tip_chord: c.tip_chord_m,
            span: c.span_m,
            tan_sweep: c.leading_edge_sweep_deg.to_radians().tan(),
            tc: c.thickness_to_chord,
            ridge: c.max_thickness_chord_fraction,
            root_le_s: c.pivot_aft_of_nose_m - c.pivot_root_chord_fraction * c.root_chord_m,
            root_y: c.root_y_m,
            pivot_z: c.pivot_z_m,
        })
    }

    /// Point at chord fraction u, span fraction eta, on the upper (true) or lower surface, for
    /// the right side (y > 0), m.
    fn point(&self, u: f64, eta: f64, upper: bool) -> Point3<f64> {
        let chord = lerp(self.root_chord, self.tip_chord, eta);
        let le_s = self.root_le_s + eta * self.span * self.tan_sweep;
        let shape = if u <= self.ridge {
            u / self.ridge
        } else {
            (1.0 - u) / (1.0 - self.ridge)
        };
        let half_t = 0.5 * self.tc * chord * shape;
        let z = if upper {
            self.pivot_z - half_t
        } else {
            self.pivot_z + half_t
        };
        Point3::new(-(le_s + u * chord), self.root_y + eta * self.span, z)
    }
}

/// Chord fractions 0..1 with the ridge included; `n` panels split over the two wedges by length.
fn chord_stations(n: usize, ridge: f64) -> Vec<f64> {
    let counts = distribute(n, &[ridge, 1.0 - ridge]);
    let mut out = vec![0.0];
    for (k, &(a, b)) in [(0.0, ridge), (ridge, 1.0)].iter().enumerate() {
        let c = counts[k];
        for i in 1..=c {
            out.push(if i == c {
                b
            } else {
                lerp(a, b, i as f64 / c as f64)
            });
        }
    }
    out
}

/// Closed mesh of one lifting surface at zero deflection (surfaces and strips in the module
/// docs), tagged [`RegionKind::LiftingSurface`] except the root cap ([`RegionKind::Other`]).
pub fn lifting_surface_mesh(
    cfg: &LiftingSurfaceConfig,
    side: Side,
) -> Result<PanelMesh, VehicleError> {
    let pf = Planform::new(cfg)?;
    let us = chord_stations(cfg.panels_chordwise, pf.ridge);
    let ns = cfg.panels_spanwise;
    let etas: Vec<f64> = (0..=ns).map(|j| j as f64 / ns as f64).collect();
    let sign = side.sign();
    let mirror = |p: Point3<f64>| Point3::new(p.x, sign * p.y, p.z);
    let name = side.name();

    let mut b = Builder::default();
    let upper = b.surface(format!("{name}-surface-upper"), RegionKind::LiftingSurface);
    let lower = b.surface(format!("{name}-surface-lower"), RegionKind::LiftingSurface);
    let tip = b.surface(format!("{name}-surface-tip"), RegionKind::LiftingSurface);
    let root = b.surface(format!("{name}-surface-root"), RegionKind::Other);

    for (is_upper, surface, outward) in [(true, upper, -Vector3::z()), (false, lower, Vector3::z())]
    {
        let nodes: Vec<Vec<Point3<f64>>> = us
            .iter()
            .map(|&u| {
                etas.iter()
                    .map(|&eta| mirror(pf.point(u, eta, is_upper)))
                    .collect()
            })
            .collect();
        b.grid(&nodes, |_| surface, outward, true);
    }
    let outboard = Vector3::y() * sign;
    for (eta, surface, outward) in [(1.0, tip, outboard), (0.0, root, -outboard)] {
        let nodes: Vec<Vec<Point3<f64>>> = us
            .iter()
            .map(|&u| {
                vec![
                    mirror(pf.point(u, eta, true)),
                    mirror(pf.point(u, eta, false)),
                ]
            })
            .collect();
        b.grid(&nodes, |_| surface, outward, false);
    }
    b.finish(match side {
        Side::Left => "left lifting-surface",
        Side::Right => "right lifting-surface",
    })
}

/// Root end of the torque tube of `side`, m.
pub fn pivot_point(cfg: &LiftingSurfaceConfig, side: Side) -> Point3<f64> {
    Point3::new(
        -cfg.pivot_aft_of_nose_m,
        side.sign() * cfg.root_y_m,
        cfg.pivot_z_m,
    )
}

/// Builds the body and both lifting surfaces from the two config tables.
pub fn build_vehicle(
    geometry: &GeometryConfig,
    lifting: &LiftingSurfaceConfig,
) -> Result<VehicleGeometry, VehicleError> {
    let body = body_mesh(geometry)?;
    let half_w = 0.5 * geometry.width_m;
    if lifting.root_y_m < half_w * (1.0 - 1e-9) {
        return Err(invalid(
            "lifting_surface",
            "root_y_m",
            lifting.root_y_m,
            format!("the root is inside the body (half width {half_w} m)"),
        ));
    }
    Ok(VehicleGeometry {
        body,
        left_surface: lifting_surface_mesh(lifting, Side::Left)?,
        right_surface: lifting_surface_mesh(lifting, Side::Right)?,
        reference_point_m: Point3::new(-geometry.forebody_length_m, 0.0, geometry.reference_z_m),
        length_m: geometry.length_m,
        width_m: geometry.width_m,
        left_pivot_m: pivot_point(lifting, Side::Left),
        right_pivot_m: pivot_point(lifting, Side::Right),
        profile: body_profile(geometry)?,
    })
}

/// The embedded sample vehicle (`configs/sample-hsv.toml`).
pub fn build_sample_vehicle() -> Result<VehicleGeometry, VehicleError> {
    let loaded = crate::config::LoadedConfig::sample().map_err(|e| VehicleError::Parse {
        origin: e.file.clone(),
        message: e.to_string(),
    })?;
    build_vehicle(&loaded.config.geometry, &loaded.config.lifting_surface)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The error message of `r`, failing the test (without dumping meshes) when it is `Ok`.
    fn err_of<T>(r: Result<T, VehicleError>, case: &str) -> String {
        match r {
            Ok(_) => panic!("{case}: expected an error"),
            Err(e) => e.to_string(),
        }
    }

    fn sample() -> (GeometryConfig, LiftingSurfaceConfig) {
        let loaded = crate::config::LoadedConfig::sample().expect("sample config parses");
        (loaded.config.geometry, loaded.config.lifting_surface)
    }

    /// Strips run upstream to downstream: centroid x strictly decreasing (x points forward).
    fn assert_strips_downstream(mesh: &PanelMesh) {
        for (s, strip) in mesh.strips.iter().enumerate() {
            for w in strip.panels.windows(2) {
                let (a, b) = (mesh.panels[w[0]].centroid.x, mesh.panels[w[1]].centroid.x);
                assert!(
                    b < a,
                    "strip {s}: panel {} (x {b}) not aft of {} (x {a})",
                    w[1],
                    w[0]
                );
            }
        }
    }

    #[test]
    fn sample_tables_parse_from_the_embedded_config() {
        // Other tables live in the same file; pick ours out of the whole document.
        let doc: toml::Table =
            toml::from_str(crate::config::SAMPLE_CONFIG_TOML).expect("valid TOML");
        let g: GeometryConfig = doc["geometry"].clone().try_into().expect("[geometry]");
        let l: LiftingSurfaceConfig = doc["lifting_surface"]
            .clone()
            .try_into()
            .expect("[lifting_surface]");
        assert_eq!((g.clone(), l.clone()), sample());
        // Paper Table 1: L_f = L_a = 15.2 m.
        assert_eq!(g.forebody_length_m, 15.2);
        assert_eq!(g.length_m - g.forebody_length_m, 15.2);
        // B&D: tau_1U = 3 deg, tau_1L = 6.2 deg.
        assert_eq!(g.upper_forebody_angle_deg, 3.0);
        assert_eq!(g.lower_forebody_angle_deg, 6.2);
    }

    #[test]
    fn unknown_and_missing_keys_are_errors_naming_the_key() {
        use crate::config::{SAMPLE_CONFIG_TOML, parse_config};
        let text = SAMPLE_CONFIG_TOML.replace("width_m = 3.0", "widht_m = 3.0");
        let err = parse_config(&text, "my.toml").unwrap_err().to_string();
        assert!(
            err.contains("my.toml") && err.contains("geometry.widht_m"),
            "{err}"
        );
        let text = SAMPLE_CONFIG_TOML.replace("[lifting_surface]", "[lifting_surfaces]");
        let err = parse_config(&text, "my.toml").unwrap_err().to_string();
        assert!(err.contains("lifting_surface"), "{err}");
    }

    #[test]
    fn body_is_closed_with_outward_normals_and_analytic_area_and_volume() {
        let (g, _) = sample();
        let body = body_mesh(&g).expect("body");
        let profile = body_profile(&g).expect("profile");
        assert!(body.is_closed(), "body mesh must be watertight");
        assert!(body.is_consistently_oriented());
        // Prismatic body: V = profile area x width, A = perimeter x width + 2 x profile area.
        let volume = profile.area_m2() * g.width_m;
        let area = profile.perimeter_m() * g.width_m + 2.0 * profile.area_m2();
        assert_relative_eq!(body.enclosed_volume_m3(), volume, max_relative = 1e-10);
        assert_relative_eq!(body.total_area_m2(), area, max_relative = 1e-10);
        assert!(
            body.enclosed_volume_m3() > 0.0,
            "outward normals give a positive volume"
        );
        // Profile by hand (B&D, metric): ramp end 14.3 tan 6.2 deg below the nose line, upper
        // surface at the tail 30.4 tan 3 deg above it.
        let z_r = 14.3 * 6.2f64.to_radians().tan();
        assert_relative_eq!(profile.ramp_end_m.y, z_r, epsilon = 1e-12);
        assert_relative_eq!(profile.cowl_lip_m.y, z_r + 1.07, epsilon = 1e-12);
        assert_relative_eq!(
            profile.tail_upper_m.y,
            -30.4 * 3f64.to_radians().tan(),
            epsilon = 1e-12
        );
        let base = profile.tail_lower_m.y - profile.tail_upper_m.y;
        assert!(
            base > 0.0 && base < 0.02,
            "B&D's aftbody nearly closes: base {base} m"
        );
    }

    #[test]
    fn body_panel_count_and_region_tags() {
        let (g, _) = sample();
        let body = body_mesh(&g).expect("body");
        let prof = Profile::new(&g).expect("profile");
        let xs = prof.stations(g.panels_along_x);
        let n = xs.len() - 1;
        assert_eq!(n, g.panels_along_x);
        let n_engine = xs
            .iter()
            .filter(|&&s| s > prof.inlet + 1e-9 && s <= prof.exit + 1e-9)
            .count();
        let (ny, nz, ne) = (
            g.panels_across_width,
            g.panels_per_side,
            g.panels_engine_height,
        );
        // Upper + lower (ramp, cowl, nozzle) + sides + base + two caps.
        let expected = 2 * n * ny + 2 * (n * nz + n_engine * ne) + ny * nz + 2 * ny * ne;
        assert_eq!(body.panels.len(), expected);
        // Every panel has exactly one region; the regions partition the mesh.
        let count = |r| body.panels_in_region(r).count();
        assert_eq!(
            count(RegionKind::MainBody)
                + count(RegionKind::Propulsion)
                + count(RegionKind::Other)
                + count(RegionKind::LiftingSurface),
            body.panels.len()
        );
        assert_eq!(count(RegionKind::LiftingSurface), 0);
        let surf = |name: &str| body.surface_index(name).expect(name);
        let region_of = |name: &str| body.surfaces[usize::from(surf(name))].region;
        assert_eq!(region_of("inlet-ramp"), RegionKind::Propulsion);
        assert_eq!(region_of("nozzle"), RegionKind::Propulsion);
        assert_eq!(region_of("cowl"), RegionKind::MainBody);
        assert_eq!(region_of("inlet-face"), RegionKind::Other);
        assert_eq!(region_of("nozzle-exit"), RegionKind::Other);
        // Propulsion panels are exactly the ramp (nose to inlet) and the nozzle (exit to tail).
        for p in body.panels_in_region(RegionKind::Propulsion) {
            let x = -body.panels[p].centroid.x;
            assert!(x < prof.inlet || x > prof.exit);
        }
        // Outward normals by surface.
        for (name, check) in [
            (
                "upper-forebody",
                (|n: Vector3<f64>| n.z < -0.99) as fn(Vector3<f64>) -> bool,
            ),
            ("upper-aftbody", |n| n.z < -0.99),
            ("inlet-ramp", |n| n.z > 0.99 && n.x > 0.0),
            ("cowl", |n| n.z > 0.999),
            ("nozzle", |n| n.z > 0.9 && n.x < 0.0),
            ("left-side", |n| n.y < -0.999),
            ("right-side", |n| n.y > 0.999),
            ("base", |n| n.x < -0.999),
            ("inlet-face", |n| n.x > 0.999),
            ("nozzle-exit", |n| n.x < -0.999),
        ] {
            let s = surf(name);
            assert!(body.panels_in_surface(s).count() > 0, "{name} has panels");
            for p in body.panels_in_surface(s) {
                assert!(
                    check(body.panels[p].normal),
                    "{name}: {}",
                    body.panels[p].normal
                );
            }
        }
    }

    #[test]
    fn body_strips_run_nose_to_tail_and_cover_the_wetted_surfaces() {
        let (g, _) = sample();
        let body = body_mesh(&g).expect("body");
        assert!(body.is_structured());
        assert_strips_downstream(&body);
        let mut in_strip = vec![0u32; body.panels.len()];
        for s in &body.strips {
            for &p in &s.panels {
                in_strip[p] += 1;
            }
        }
        let name_of = |p: usize| {
            body.surfaces[usize::from(body.panels[p].surface)]
                .name
                .as_str()
        };
        for (p, &c) in in_strip.iter().enumerate() {
            let expect = u32::from(!matches!(name_of(p), "base" | "inlet-face" | "nozzle-exit"));
            assert_eq!(c, expect, "panel {p} on {} is in {c} strips", name_of(p));
        }
        // Upper strips start at the nose and end at the tail.
        let upper = body.surface_index("upper-forebody").expect("upper");
        let first = body
            .strips
            .iter()
            .find(|s| body.panels[s.panels[0]].surface == upper)
            .expect("an upper strip");
        let last = *first.panels.last().expect("non-empty");
        let (lo, _) = body.bounding_box();
        assert!(body.panels[last].centroid.x < lo.x + 0.6);
        assert_eq!(
            body.surfaces[usize::from(body.panels[last].surface)].name,
            "upper-aftbody"
        );
    }

    #[test]
    fn lifting_surfaces_are_closed_mirror_images_with_analytic_volume() {
        let (_, l) = sample();
        let right = lifting_surface_mesh(&l, Side::Right).expect("right");
        let left = lifting_surface_mesh(&l, Side::Left).expect("left");
        for m in [&left, &right] {
            assert!(m.is_closed() && m.is_consistently_oriented());
            assert_strips_downstream(m);
            // Double wedge: section area t c / 2 = (t/c) c² / 2, c linear in span:
            // V = (t/c)/2 b (c_r² + c_r c_t + c_t²)/3.
            let (cr, ct) = (l.root_chord_m, l.tip_chord_m);
            let v = 0.5 * l.thickness_to_chord * l.span_m * (cr * cr + cr * ct + ct * ct) / 3.0;
            assert_relative_eq!(m.enclosed_volume_m3(), v, max_relative = 1e-10);
            // Planform: projected area of the upper surface = (c_r + c_t)/2 b.
            let upper = m.panels_in_region(RegionKind::LiftingSurface).filter(|&p| {
                m.surfaces[usize::from(m.panels[p].surface)]
                    .name
                    .ends_with("upper")
            });
            let projected: f64 = upper
                .map(|p| -m.panels[p].normal.z * m.panels[p].area_m2)
                .sum();
            assert_relative_eq!(projected, 0.5 * (cr + ct) * l.span_m, max_relative = 1e-10);
            assert_eq!(m.strips.len(), 2 * l.panels_spanwise);
        }
        // Mirror images: same vertices with y negated, same panels, mirrored normals.
        assert_eq!(left.vertices.len(), right.vertices.len());
        for (a, b) in left.vertices.iter().zip(&right.vertices) {
            assert_eq!((a.x, -a.y, a.z), (b.x, b.y, b.z));
        }
        assert_eq!(left.panels.len(), right.panels.len());
        for (a, b) in left.panels.iter().zip(&right.panels) {
            assert_relative_eq!(a.normal.x, b.normal.x, epsilon = 1e-12);
            assert_relative_eq!(a.normal.y, -b.normal.y, epsilon = 1e-12);
            assert_relative_eq!(a.normal.z, b.normal.z, epsilon = 1e-12);
            assert_relative_eq!(a.area_m2, b.area_m2, max_relative = 1e-12);
        }
        assert!(right.bounding_box().0.y >= l.root_y_m - 1e-12);
        assert!(left.bounding_box().1.y <= -l.root_y_m + 1e-12);
    }

    #[test]
    fn sample_vehicle_assembles_with_surfaces_on_the_aftbody_sides() {
        let v = build_sample_vehicle().expect("sample vehicle");
        assert_eq!(v.reference_point_m, Point3::new(-15.2, 0.0, 0.0));
        assert_eq!(v.length_m, 30.4);
        let (lo, hi) = v.body.bounding_box();
        assert_relative_eq!(lo.x, -30.4, epsilon = 1e-12);
        assert_relative_eq!(hi.x, 0.0, epsilon = 1e-12);
        assert_relative_eq!(hi.y - lo.y, 3.0, epsilon = 1e-12);
        // The root section lies inside the body's side profile (between the upper surface and
        // the nozzle), so the surface is attached to the side wall.
        let (g, l) = sample();
        let prof = Profile::new(&g).expect("profile");
        let root = v
            .right_surface
            .surface_index("right-surface-root")
            .expect("root");
        for p in v.right_surface.panels_in_surface(root) {
            for &i in v.right_surface.panels[p].vertex_indices() {
                let q = v.right_surface.vertices[i];
                let s = -q.x;
                assert!(s > 0.0 && s < g.length_m);
                assert!(
                    q.z > prof.z_upper(s) && q.z < prof.z_lower(s),
                    "root point {q}"
                );
                assert_relative_eq!(q.y, l.root_y_m, epsilon = 1e-12);
            }
        }
        assert_eq!(v.right_pivot_m, Point3::new(-25.0, 1.5, -0.9));
        assert_eq!(v.left_pivot_m, Point3::new(-25.0, -1.5, -0.9));
    }

    #[test]
    fn bad_geometry_is_an_error_naming_the_key() {
        let (g, l) = sample();
        let cases: Vec<(GeometryConfig, &str)> = vec![
            (
                GeometryConfig {
                    width_m: -1.0,
                    ..g.clone()
                },
                "width_m",
            ),
            (
                GeometryConfig {
                    inlet_aft_of_nose_m: 40.0,
                    ..g.clone()
                },
                "inlet_aft_of_nose_m",
            ),
            (
                GeometryConfig {
                    engine_length_m: 20.0,
                    ..g.clone()
                },
                "engine_length_m",
            ),
            (
                GeometryConfig {
                    nozzle_angle_deg: 30.0,
                    ..g.clone()
                },
                "nozzle_angle_deg",
            ),
            (
                GeometryConfig {
                    panels_along_x: 0,
                    ..g.clone()
                },
                "panels_along_x",
            ),
            (
                GeometryConfig {
                    length_m: f64::NAN,
                    ..g.clone()
                },
                "length_m",
            ),
            (
                GeometryConfig {
                    upper_forebody_angle_deg: -10.0,
                    ..g.clone()
                },
                "upper_forebody_angle_deg",
            ),
        ];
        for (bad, key) in cases {
            let err = err_of(build_vehicle(&bad, &l), key);
            assert!(
                err.contains(key) && err.contains("[geometry]"),
                "{key}: {err}"
            );
        }
        let bad = LiftingSurfaceConfig {
            root_y_m: 1.0,
            ..l.clone()
        };
        let err = err_of(build_vehicle(&g, &bad), "root_y_m");
        assert!(
            err.contains("root_y_m") && err.contains("inside the body"),
            "{err}"
        );
        let bad = LiftingSurfaceConfig {
            panels_chordwise: 1,
            ..l
        };
        let err = err_of(lifting_surface_mesh(&bad, Side::Left), "panels_chordwise");
        assert!(err.contains("panels_chordwise"), "{err}");
    }

    #[test]
    fn sharp_tail_collapses_the_base() {
        let (mut g, _) = sample();
        // Nozzle angle that closes the aftbody exactly at the tail.
        let prof = Profile::new(&g).expect("profile");
        let rise = prof.z_ramp_end - prof.z_upper(g.length_m);
        let tail_len = g.length_m - prof.exit;
        g.nozzle_angle_deg = (rise / tail_len).atan().to_degrees();
        let body = body_mesh(&g).expect("body");
        assert!(body.is_closed() && body.is_consistently_oriented());
        let base = body.surface_index("base").expect("base surface");
        assert!(body.panels_in_surface(base).count() <= g.panels_across_width * g.panels_per_side);
        let profile = body_profile(&g).expect("profile");
        assert_relative_eq!(
            body.enclosed_volume_m3(),
            profile.area_m2() * g.width_m,
            max_relative = 1e-9
        );
    }
}
