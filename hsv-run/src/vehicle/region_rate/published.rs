//! What a region publishes: the values of the loads, skin-friction and structure-temperature
//! topics of
//! [`super::RegionExchange`], and how the data manager interpolates and extrapolates them
//! ([`Interpolate`]: component by component).

use hsv_core::data::{Interpolate, ShapeMismatch};
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};

/// One publication of a region (the body's, or a lifting surface's with its applied loads about
/// the pivot in the surface's frame as the total and no separate aero part): the value of the
/// region's loads topic; the data manager stamps it with its time.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedLoads {
    /// The body: aero, skin friction, engine (and the monolithic model's surfaces) about the
    /// centre of mass, body axes; a surface: its pressure and friction about its pivot in its
    /// own frame. N and N m.
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
    /// The body's aero (pressure and friction) part alone, N and N m (zero for a surface).
    pub aero_force_n: Vector3<f64>,
    pub aero_moment_nm: Vector3<f64>,
    /// Generalized forces of the region's modes (a surface's: the aero part), N (per unit
    /// modal coordinate).
    pub generalized: DVector<f64>,
}

impl Interpolate for PublishedLoads {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .lerp_into(&other.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .lerp_into(&other.moment_nm, w, &mut out.moment_nm)?;
        self.aero_force_n
            .lerp_into(&other.aero_force_n, w, &mut out.aero_force_n)?;
        self.aero_moment_nm
            .lerp_into(&other.aero_moment_nm, w, &mut out.aero_moment_nm)?;
        self.generalized
            .lerp_into(&other.generalized, w, &mut out.generalized)
    }

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .extrapolate_into(&newer.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .extrapolate_into(&newer.moment_nm, w, &mut out.moment_nm)?;
        self.aero_force_n
            .extrapolate_into(&newer.aero_force_n, w, &mut out.aero_force_n)?;
        self.aero_moment_nm
            .extrapolate_into(&newer.aero_moment_nm, w, &mut out.aero_moment_nm)?;
        self.generalized
            .extrapolate_into(&newer.generalized, w, &mut out.generalized)
    }

    fn copy_into(&self, out: &mut Self) {
        out.force_n = self.force_n;
        out.moment_nm = self.moment_nm;
        out.aero_force_n = self.aero_force_n;
        out.aero_moment_nm = self.aero_moment_nm;
        self.generalized.copy_into(&mut out.generalized);
    }
}

/// The body's skin friction at one evaluation, about the centre of mass, body axes, N and N m:
/// the value of its topic.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedFriction {
    pub force_n: Vector3<f64>,
    pub moment_nm: Vector3<f64>,
}

impl Interpolate for PublishedFriction {
    fn lerp_into(&self, other: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .lerp_into(&other.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .lerp_into(&other.moment_nm, w, &mut out.moment_nm)
    }

    fn extrapolate_into(&self, newer: &Self, w: f64, out: &mut Self) -> Result<(), ShapeMismatch> {
        self.force_n
            .extrapolate_into(&newer.force_n, w, &mut out.force_n)?;
        self.moment_nm
            .extrapolate_into(&newer.moment_nm, w, &mut out.moment_nm)
    }
}

/// One publication of a surface's thermal region for its structure: the temperature field moved
/// onto the structure's nodes ([`hsv_core::coupling::StructureTemperatures`]), K, which the
/// structure's temperature-dependent stiffness reads.
#[derive(Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct PublishedTemperatures {
    /// Mean (mid-plane) temperature of each structure node, K.
    pub mean_k: Vec<f64>,
    /// Upper-less-lower face temperature difference of each structure node, K.
    pub difference_k: Vec<f64>,
}

/// By hand so `clone_from` reuses both fields' buffers: the data manager copies a publication
/// into its history that way, and the time loop allocates nothing.
impl Clone for PublishedTemperatures {
    fn clone(&self) -> Self {
        Self {
            mean_k: self.mean_k.clone(),
            difference_k: self.difference_k.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.mean_k.clone_from(&source.mean_k);
        self.difference_k.clone_from(&source.difference_k);
    }
}
