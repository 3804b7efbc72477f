//! The vehicle's geometry, one file per part: the body profile and mesh (`body`), the lifting
//! surfaces (`lifting_surface`), the vertical fin (`vertical_fin`), and the polygon-mesh builder
//! they use (`polygon_mesh`).
//!
//! **Body frame.** Origin at the nose tip; x forward (so every point of the vehicle has x ≤ 0 and
//! the tail is at x = -length), y right, z down; z = 0 is the horizontal line through the nose
//! (the "nose line"). The moment reference point is on the centerline `forebody_length_m` aft of
//! the nose (paper Table 1: the fore and aft beams join there), at `reference_z_m`.

mod body;
mod checks;
mod lifting_surface;
mod polygon_mesh;
#[cfg(test)]
mod tests;
mod vertical_fin;

pub use body::{BodyProfile, GeometryConfig, body_mesh, body_profile};
pub use checks::VehicleError;
use checks::invalid;
pub use lifting_surface::{LiftingSurfaceConfig, Side, lifting_surface_mesh, pivot_point};
pub use vertical_fin::{VerticalFinConfig, vertical_fin_mesh};

use nalgebra::Point3;

use crate::mesh::PanelMesh;

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
