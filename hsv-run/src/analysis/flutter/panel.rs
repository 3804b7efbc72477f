//! Classical panel flutter through the same path (equations, identification, eigenvalues,
//! bracketing and Brent): a flat rectangular panel with the flow over its upper face and still
//! air at p∞ below, under piston theory without aerodynamic damping.
//!
//! **Aerodynamics.** First-order piston theory gives Δp = ρ∞ a∞ w with w the normal velocity of
//! the surface into the air (Ashley & Zartarian, "Piston theory — a new aerodynamic tool for
//! the aeroelastician", J. Aero. Sci. 23(12), 1956); without the elastic velocity (quasi-static
//! aero, no aerodynamic damping) w = U ∂w/∂x and Δp = ρ U² w_x / M = 2 q w_x / M, the
//! high-Mach form of the quasi-steady Ackeret pressure 2 q w_x / √(M² − 1) (Dowell,
//! *Aeroelasticity of Plates and Shells*, Noordhoff, 1975, ch. 2). The registered
//! `piston-theory` is the third-order expansion; around the flat panel its linear part is
//! exactly the first-order law, which is all the identified A keeps. Dowell's parameter is
//! λ = 2 q a³ / (β D) with a the chord (streamwise length) and D = E h³ / (12 (1 − ν²)); the
//! panel's aero is Dowell's with β = M, so [`PanelFlutter::lambda`] uses β = M (and
//! [`PanelFlutter::lambda_ackeret`] gives the same dynamic pressure with β = √(M² − 1)).
//!
//! **Search.** The Mach number at a fixed altitude sets q = γ p∞ M² / 2: the crossing of the
//! growth margin ([`super::stability`](mod@super::stability)) is bracketed on a grid and found by Brent's method.

use hsv_core::aero::{AeroModel, ReferenceValues};
use hsv_core::flow::{FlightCondition, Freestream};
use hsv_core::gas::PerfectGas;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Surface};
use hsv_core::region::{ModelSettings, RegionInfo};
use hsv_core::registry::{ModelContext, Registry};
use hsv_core::structure::StructureModel;
use nalgebra::{DVector, Point3};
use serde::Serialize;

use super::stability::{Instability, Stability, brent_root, stability};
use super::surface::{DerivativeMethod, SurfaceDynamics, SurfaceOptions};
use super::sweep::FlutterBoundary;
use super::{FlutterError, check_positive};

/// Which faces of a flat plate are wetted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Faces {
    /// The upper face (outward normal −z, up): a panel with still air below.
    Upper,
    /// Both faces: a thin wing or typical section in the flow.
    Both,
}

/// A flat rectangular plate at z = 0 from the leading edge x = 0 aft to x = −chord, y from 0
/// to span, in `nx` × `ny` quads per face, on the lifting-surface region.
pub fn flat_plate_mesh(
    chord_m: f64,
    span_m: f64,
    nx: usize,
    ny: usize,
    faces: Faces,
) -> Result<PanelMesh, FlutterError> {
    check_positive("plate chord (m)", chord_m)?;
    check_positive("plate span (m)", span_m)?;
    if nx == 0 || ny == 0 {
        return Err(FlutterError::InvalidInput {
            quantity: "plate mesh panels".to_owned(),
            value: (nx.min(ny)) as f64,
            allowed: ">= 1 each way",
        });
    }
    let vertices: Vec<Point3<f64>> = (0..=ny)
        .flat_map(|j| {
            (0..=nx).map(move |i| {
                Point3::new(
                    -chord_m * i as f64 / nx as f64,
                    span_m * j as f64 / ny as f64,
                    0.0,
                )
            })
        })
        .collect();
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    let mut panels = Vec::new();
    let mut surfaces = vec![Surface::new("upper", RegionKind::LiftingSurface)];
    for j in 0..ny {
        for i in 0..nx {
            // Counter-clockwise seen from above: the normal points up (−z).
            panels.push(PanelSpec::quad(
                at(i, j),
                at(i + 1, j),
                at(i + 1, j + 1),
                at(i, j + 1),
                0,
            ));
        }
    }
    if faces == Faces::Both {
        surfaces.push(Surface::new("lower", RegionKind::LiftingSurface));
        for j in 0..ny {
            for i in 0..nx {
                panels.push(PanelSpec::quad(
                    at(i, j),
                    at(i, j + 1),
                    at(i + 1, j + 1),
                    at(i + 1, j),
                    1,
                ));
            }
        }
    }
    PanelMesh::new(vertices, &panels, Vec::new(), surfaces)
        .map_err(|e| FlutterError::Inconsistent(format!("plate mesh: {e}")))
}

/// A region around `mesh` for models built by name: `ritz-plate` gets `structure_settings`.
pub fn plate_region(
    mesh: PanelMesh,
    gas: PerfectGas,
    structure_settings: toml::Table,
) -> RegionInfo {
    let (lo, hi) = mesh.bounding_box();
    let reference = ReferenceValues {
        area_m2: (hi.x - lo.x) * (hi.y - lo.y),
        chord_m: hi.x - lo.x,
        span_m: hi.y - lo.y,
        moment_point_m: [0.0; 3],
    };
    let mut region = RegionInfo::standalone("panel", mesh, reference, gas, "<panel flutter>");
    region.kind = RegionKind::LiftingSurface;
    region.settings.insert(
        "ritz-plate".to_owned(),
        ModelSettings {
            table: structure_settings,
            key_path: "models.ritz-plate".to_owned(),
        },
    );
    region
}

/// The classical panel: the registered `ritz-plate` on a rectangular planform with all four
/// edges simply supported, no structural damping, `modes` free-vibration modes and no static
/// shapes, Ti-6Al-4V at 293 K.
pub struct SimplySupportedPanel {
    pub chord_m: f64,
    pub span_m: f64,
    pub thickness_m: f64,
    /// Structural elements along the chord and the span (the aero mesh uses the same).
    pub elements: (usize, usize),
    pub modes: usize,
}

impl SimplySupportedPanel {
    /// `[models.ritz-plate]` settings of the panel.
    pub fn structure_settings(&self) -> toml::Table {
        let mut rect = toml::Table::new();
        rect.insert("chord_m".into(), self.chord_m.into());
        rect.insert("span_m".into(), self.span_m.into());
        rect.insert("thickness_m".into(), self.thickness_m.into());
        let mut t = toml::Table::new();
        t.insert("planform".into(), "rectangular".into());
        t.insert("root".into(), "simply-supported".into());
        t.insert("free_vibration_modes".into(), (self.modes as i64).into());
        t.insert("static_shapes".into(), 0_i64.into());
        t.insert("damping_ratio".into(), 0.0.into());
        t.insert("elements_chordwise".into(), (self.elements.0 as i64).into());
        t.insert("elements_spanwise".into(), (self.elements.1 as i64).into());
        t.insert("rectangular".into(), toml::Value::Table(rect));
        t
    }

    /// The panel's region (upper-face mesh) and structure, built by name from `registry`.
    pub fn build(
        &self,
        registry: &Registry,
        gas: PerfectGas,
    ) -> Result<(RegionInfo, Box<dyn StructureModel>), FlutterError> {
        let mesh = flat_plate_mesh(
            self.chord_m,
            self.span_m,
            self.elements.0,
            self.elements.1,
            Faces::Upper,
        )?;
        let region = plate_region(mesh, gas, self.structure_settings());
        let settings = region.model_settings("ritz-plate");
        let structure = registry
            .create::<dyn StructureModel>(
                "ritz-plate",
                &ModelContext::new(&region, registry, &settings),
            )
            .map_err(|e| FlutterError::Inconsistent(format!("model `ritz-plate`: {e}")))?;
        Ok((region, structure))
    }

    /// D = E h³ / (12 (1 − ν²)) of Ti-6Al-4V at 293 K, N m.
    pub fn rigidity_n_m(&self) -> Result<f64, FlutterError> {
        let ti = hsv_core::material::Material::ti_6al_4v();
        let e = ti
            .youngs_modulus_pa(293.0)
            .map_err(|e| FlutterError::model("ti-6al-4v", e.into_model_error("panel")))?;
        let nu = ti.poisson_ratio;
        Ok(e * self.thickness_m.powi(3) / (12.0 * (1.0 - nu * nu)))
    }
}

/// The critical point of a panel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PanelFlutter {
    pub boundary: FlutterBoundary,
    /// At the flutter Mach number (when there is one).
    pub critical_mach: Option<f64>,
    pub critical_dynamic_pressure_pa: Option<f64>,
    /// λ = 2 q a³ / (M D) (piston theory's β = M).
    pub lambda: Option<f64>,
    /// λ with Ackeret's β = √(M² − 1) at the same q.
    pub lambda_ackeret: Option<f64>,
    /// Frequency of the fluttering root just above the crossing, Hz.
    pub flutter_frequency_hz: Option<f64>,
    pub altitude_m: f64,
    pub rigidity_n_m: f64,
    pub chord_m: f64,
}

/// Stability of `structure` on `mesh` at `mach` (no aerodynamic damping, flat equilibrium).
pub fn panel_stability(
    mesh: &PanelMesh,
    structure: &dyn StructureModel,
    aero: Box<dyn AeroModel>,
    flight: FlightCondition,
    method: DerivativeMethod,
) -> Result<Stability, FlutterError> {
    let options = SurfaceOptions {
        aero_damping: false,
        ..SurfaceOptions::default()
    };
    let mut surface = SurfaceDynamics::new(mesh.clone(), aero, structure, flight, options)?;
    let equilibrium = surface.equilibrium()?;
    let a = surface.identify(&equilibrium.state, method)?.a;
    stability(&a)
}

/// The flutter boundary of a plate over the Mach grid `machs` at `altitude_m` (module docs):
/// `make_aero` builds the aero model for each evaluation.
#[allow(clippy::too_many_arguments)]
pub fn panel_flutter(
    mesh: &PanelMesh,
    structure: &dyn StructureModel,
    make_aero: &dyn Fn() -> Result<Box<dyn AeroModel>, FlutterError>,
    gas: PerfectGas,
    altitude_m: f64,
    machs: &[f64],
    rigidity_n_m: f64,
    chord_m: f64,
) -> Result<PanelFlutter, FlutterError> {
    check_positive("rigidity D (N m)", rigidity_n_m)?;
    check_positive("chord (m)", chord_m)?;
    if machs.len() < 2 || machs.windows(2).any(|w| w[1] <= w[0]) {
        return Err(FlutterError::Inconsistent(
            "the Mach grid needs at least two ascending values".to_owned(),
        ));
    }
    let flight = |mach: f64| -> Result<FlightCondition, FlutterError> {
        let f = Freestream::standard(mach, altitude_m, gas)
            .map_err(|e| FlutterError::model("freestream", e))?;
        Ok(FlightCondition::steady(f, 0.0, 0.0))
    };
    let evaluate = |mach: f64| -> Result<Stability, FlutterError> {
        panel_stability(
            mesh,
            structure,
            make_aero()?,
            flight(mach)?,
            DerivativeMethod::Direct,
        )
    };
    let grid: Vec<Stability> = machs
        .iter()
        .map(|&m| evaluate(m))
        .collect::<Result<_, _>>()?;
    // Flutter only: an oscillatory pair's margin (a real root of a buckled panel is divergence).
    let margin = |s: &Stability| {
        s.margin_per_s(Instability::Flutter)
            .unwrap_or(-s.growth_threshold_per_s)
    };
    let boundary = if margin(&grid[0]) > 0.0 {
        FlutterBoundary::UnstableAtLowest {
            lowest_mach: machs[0],
            max_real_per_s: grid[0].max_real_per_s,
            least_damping_ratio: grid[0].least_damping_ratio(),
        }
    } else if let Some(i) = (1..grid.len()).find(|&i| margin(&grid[i]) > 0.0) {
        let search = brent_root(
            |m| evaluate(m).map(|s| margin(&s)),
            (machs[i - 1], machs[i]),
            (margin(&grid[i - 1]), margin(&grid[i])),
            1e-6 * machs[i],
            80,
        )?;
        let above = evaluate(search.bracket.1)?;
        FlutterBoundary::Crossing {
            mach: search.root,
            bracket: search.bracket,
            evaluations: search.evaluations,
            frequency_hz: above
                .critical_of(Instability::Flutter)
                .map_or(0.0, |k| above.roots[k].frequency_hz),
            grows_from: None,
        }
    } else {
        let (k, worst) = grid
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.max_real_per_s.total_cmp(&b.1.max_real_per_s))
            .map_or((0, f64::NEG_INFINITY), |(k, s)| (k, s.max_real_per_s));
        FlutterBoundary::StableInRange {
            max_real_per_s: worst,
            at_mach: machs[k],
            least_damping_ratio: grid
                .iter()
                .map(Stability::least_damping_ratio)
                .fold(f64::INFINITY, f64::min),
            limited_by: None,
        }
    };
    let critical_mach = boundary.mach();
    let q = critical_mach
        .map(|m| flight(m).map(|f| f.freestream.dynamic_pressure_pa))
        .transpose()?;
    let frequency = match &boundary {
        FlutterBoundary::Crossing { frequency_hz, .. } => Some(*frequency_hz),
        _ => None,
    };
    let lambda_with = |beta: f64| q.map(|q| 2.0 * q * chord_m.powi(3) / (beta * rigidity_n_m));
    Ok(PanelFlutter {
        lambda: critical_mach.and_then(&lambda_with),
        lambda_ackeret: critical_mach
            .filter(|&m| m > 1.0)
            .and_then(|m| lambda_with((m * m - 1.0).sqrt())),
        boundary,
        critical_mach,
        critical_dynamic_pressure_pa: q,
        flutter_frequency_hz: frequency,
        altitude_m,
        rigidity_n_m,
        chord_m,
    })
}

/// The Mach number where λ = 2 q a³ / (M D) equals `lambda` at `altitude_m`:
/// 2 q / M = γ p∞ M, so M = λ D / (γ p∞ a³).
pub fn mach_for_lambda(
    lambda: f64,
    rigidity_n_m: f64,
    chord_m: f64,
    altitude_m: f64,
    gas: PerfectGas,
) -> Result<f64, FlutterError> {
    let f = Freestream::standard(2.0, altitude_m, gas)
        .map_err(|e| FlutterError::model("freestream", e))?;
    Ok(lambda * rigidity_n_m / (gas.gamma * f.pressure_pa * chord_m.powi(3)))
}

/// A Mach grid of `n` points from `lo` to `hi`.
pub fn mach_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// A zero state of `n` Ritz coordinates (flat panel), for callers that analyse it directly.
pub fn flat_state(n_modes: usize) -> DVector<f64> {
    DVector::zeros(2 * n_modes)
}
