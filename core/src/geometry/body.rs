//! The body: its `[geometry]` table, side profile and closed panel mesh.
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

use nalgebra::{Point2, Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::{PanelMesh, RegionKind};

use super::checks::{VehicleError, check_count, check_range, invalid};
use super::polygon_mesh::{Builder, distribute, lerp};

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

/// Profile functions of a validated [`GeometryConfig`]; s is the distance aft of the nose, m.
pub(super) struct Profile {
    pub(super) length: f64,
    pub(super) junction: f64,
    pub(super) inlet: f64,
    pub(super) exit: f64,
    pub(super) tan_upper_fore: f64,
    pub(super) tan_upper_aft: f64,
    pub(super) tan_ramp: f64,
    pub(super) tan_nozzle: f64,
    /// z of the flow path top (ramp end), m.
    pub(super) z_ramp_end: f64,
    /// z of the cowl, m.
    pub(super) z_cowl: f64,
}

impl Profile {
    pub(super) fn new(g: &GeometryConfig) -> Result<Self, VehicleError> {
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
    pub(super) fn z_upper(&self, s: f64) -> f64 {
        if s <= self.junction {
            -s * self.tan_upper_fore
        } else {
            -self.junction * self.tan_upper_fore - (s - self.junction) * self.tan_upper_aft
        }
    }

    /// Lower boundary of the body above the flow path (ramp, engine top, nozzle) at s, m.
    pub(super) fn z_lower(&self, s: f64) -> f64 {
        if s <= self.inlet {
            s * self.tan_ramp
        } else if s <= self.exit {
            self.z_ramp_end
        } else {
            // Validation keeps the nozzle below the upper surface; `max` only absorbs round-off.
            (self.z_ramp_end - (s - self.exit) * self.tan_nozzle).max(self.z_upper(s))
        }
    }

    pub(super) fn body_profile(&self) -> BodyProfile {
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
    pub(super) fn stations(&self, n: usize) -> Vec<f64> {
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
