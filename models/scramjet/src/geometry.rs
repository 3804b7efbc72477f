//! The engine's flow-path geometry read from the (deformed) body mesh: one two-dimensional
//! section per spanwise column of the `inlet-ramp`, `cowl` and `nozzle` strips, and sections
//! interpolated between columns at the engine's spanwise stations.
//!
//! Sections live in the body x-z plane (x forward, z down), m. A polyline runs upstream to
//! downstream; its points are the leading- and trailing-edge midpoints of the strip's panels, so
//! point `i` and `i + 1` bound panel `i` of the strip.

use hsv_core::error::ModelError;
use hsv_core::geometry::BodyProfile;
use hsv_core::mesh::{Panel, PanelMesh};
use nalgebra::{Point2, Vector2};

/// Surface names of the vehicle body mesh the engine reads (see `hsv_core::geometry`).
pub const RAMP_SURFACE: &str = "inlet-ramp";
/// The engine's outer underside (main body); its first point is the cowl lip.
pub const COWL_SURFACE: &str = "cowl";
/// The external nozzle (aftbody underside).
pub const NOZZLE_SURFACE: &str = "nozzle";

/// A two-dimensional engine section at spanwise position `y_m`, body x-z plane, m.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SectionGeometry {
    /// Spanwise position of the section, m.
    pub y_m: f64,
    /// Inlet ramp, nose to ramp end (top of the flow path at the inlet).
    pub ramp_m: Vec<Point2<f64>>,
    /// Cowl, lip to engine exit (bottom of the flow path).
    pub cowl_m: Vec<Point2<f64>>,
    /// External nozzle (aftbody underside), engine exit to tail.
    pub nozzle_m: Vec<Point2<f64>>,
}

/// Angle of the segment a → b below the aft direction (-x), rad: positive when the surface
/// descends (z grows) going aft. The freestream direction on this scale is -α.
pub fn slope_rad(a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    (b.y - a.y).atan2(a.x - b.x)
}

/// Unit vector from a to b (body x, z).
pub fn direction(a: &Point2<f64>, b: &Point2<f64>) -> Vector2<f64> {
    (b - a).normalize()
}

impl SectionGeometry {
    /// A straight-segment section from a body side profile (undeformed vehicle), with
    /// `ramp_panels`, `cowl_panels` and `nozzle_panels` equal segments.
    pub fn from_profile(
        profile: &BodyProfile,
        y_m: f64,
        ramp_panels: usize,
        cowl_panels: usize,
        nozzle_panels: usize,
    ) -> Self {
        let line = |a: Point2<f64>, b: Point2<f64>, n: usize| -> Vec<Point2<f64>> {
            let n = n.max(1);
            (0..=n)
                .map(|i| {
                    let t = i as f64 / n as f64;
                    Point2::from(a.coords * (1.0 - t) + b.coords * t)
                })
                .collect()
        };
        Self {
            y_m,
            ramp_m: line(profile.nose_m, profile.ramp_end_m, ramp_panels),
            cowl_m: line(profile.cowl_lip_m, profile.engine_exit_lower_m, cowl_panels),
            nozzle_m: line(profile.nozzle_start_m, profile.tail_lower_m, nozzle_panels),
        }
    }

    /// Nose tip (first ramp point).
    pub fn nose(&self) -> Point2<f64> {
        self.ramp_m[0]
    }

    /// End of the ramp: top of the flow path at the inlet face.
    pub fn ramp_end(&self) -> Point2<f64> {
        self.ramp_m[self.ramp_m.len() - 1]
    }

    /// Cowl lip: bottom of the inlet face.
    pub fn cowl_lip(&self) -> Point2<f64> {
        self.cowl_m[0]
    }

    /// Bottom of the engine exit face.
    pub fn exit_lower(&self) -> Point2<f64> {
        self.cowl_m[self.cowl_m.len() - 1]
    }

    /// Top of the engine exit face (start of the external nozzle).
    pub fn nozzle_start(&self) -> Point2<f64> {
        self.nozzle_m[0]
    }

    /// Direction of the flow leaving the ramp (its last segment).
    pub fn inlet_direction(&self) -> Vector2<f64> {
        let n = self.ramp_m.len();
        direction(&self.ramp_m[n - 2], &self.ramp_m[n - 1])
    }

    /// Direction of the flow leaving the engine (the cowl's last segment).
    pub fn exit_direction(&self) -> Vector2<f64> {
        let n = self.cowl_m.len();
        direction(&self.cowl_m[n - 2], &self.cowl_m[n - 1])
    }

    /// Engine length from the lip to the exit along the cowl, m.
    pub fn engine_length_m(&self) -> f64 {
        self.cowl_m.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }

    /// Checks the section is usable: at least one segment per polyline, finite points, no
    /// zero-length segment, and a flow path of positive height at the inlet.
    pub fn check(&self, model: &str) -> Result<(), ModelError> {
        for (name, line) in [
            ("inlet ramp", &self.ramp_m),
            ("cowl", &self.cowl_m),
            ("nozzle", &self.nozzle_m),
        ] {
            if line.len() < 2 {
                return Err(ModelError::inconsistent(
                    model,
                    format!(
                        "the {name} of the section at y = {} m has no segment",
                        self.y_m
                    ),
                ));
            }
            for w in line.windows(2) {
                let length = (w[1] - w[0]).norm();
                if !(length.is_finite() && length > 0.0) {
                    return Err(ModelError::inconsistent(
                        model,
                        format!(
                            "the {name} of the section at y = {} m has a degenerate or non-finite segment",
                            self.y_m
                        ),
                    ));
                }
            }
        }
        let height = self.cowl_lip().y - self.ramp_end().y;
        if height.is_nan() || height <= 0.0 {
            return Err(ModelError::inconsistent(
                model,
                format!(
                    "the cowl lip is not below the ramp end at y = {} m (inlet height {height} m)",
                    self.y_m
                ),
            ));
        }
        Ok(())
    }

    /// Sets `self` to (1 - t) a + t b point by point (same point counts).
    fn blend(&mut self, a: &SectionGeometry, b: &SectionGeometry, t: f64, y_m: f64) {
        let mix = |out: &mut Vec<Point2<f64>>, pa: &[Point2<f64>], pb: &[Point2<f64>]| {
            out.clear();
            out.extend(
                pa.iter()
                    .zip(pb)
                    .map(|(p, q)| Point2::from(p.coords * (1.0 - t) + q.coords * t)),
            );
        };
        self.y_m = y_m;
        mix(&mut self.ramp_m, &a.ramp_m, &b.ramp_m);
        mix(&mut self.cowl_m, &a.cowl_m, &b.cowl_m);
        mix(&mut self.nozzle_m, &a.nozzle_m, &b.nozzle_m);
    }
}

/// One spanwise column of the engine surfaces of the body mesh.
#[derive(Debug, Clone, Default)]
pub struct Column {
    /// Mean spanwise position of the column's ramp panels, m.
    pub y_m: f64,
    /// Ramp panel indices, nose to inlet.
    pub ramp_panels: Vec<usize>,
    /// Nozzle panel indices, exit to tail.
    pub nozzle_panels: Vec<usize>,
    /// The column's section (ramp, cowl and nozzle polylines).
    pub section: SectionGeometry,
}

/// The engine surfaces of a body mesh, column by column (reused between evaluations).
#[derive(Debug, Clone, Default)]
pub struct EngineSurfaces {
    /// Columns sorted by y.
    pub columns: Vec<Column>,
    /// Spanwise extent of the engine (ramp panel vertices), m.
    pub y_min_m: f64,
    pub y_max_m: f64,
    /// Scratch: (mean y, strip index) of the cowl and nozzle strips.
    cowl_strips: Vec<(f64, usize)>,
    nozzle_strips: Vec<(f64, usize)>,
    spare: Vec<Column>,
}

/// Leading- and trailing-edge midpoints (x, z) of a panel whose edges run across the span:
/// the mean of the vertices forward of the panel's mean x, and of those aft of it.
fn panel_edges(mesh: &PanelMesh, panel: &Panel) -> (Point2<f64>, Point2<f64>) {
    let idx = panel.vertex_indices();
    let mean_x = idx.iter().map(|&i| mesh.vertices[i].x).sum::<f64>() / idx.len() as f64;
    let (mut fore, mut aft) = ((Vector2::zeros(), 0.0), (Vector2::zeros(), 0.0));
    for &i in idx {
        let v = mesh.vertices[i];
        let side = if v.x > mean_x { &mut fore } else { &mut aft };
        side.0 += Vector2::new(v.x, v.z);
        side.1 += 1.0;
    }
    let mean = |(sum, n): (Vector2<f64>, f64)| Point2::from(sum / n.max(1.0));
    (mean(fore), mean(aft))
}

/// Polyline of a strip: leading edge of its first panel, then every panel's trailing edge.
fn strip_polyline(mesh: &PanelMesh, panels: &[usize], out: &mut Vec<Point2<f64>>) {
    out.clear();
    for (k, &p) in panels.iter().enumerate() {
        let (le, te) = panel_edges(mesh, &mesh.panels[p]);
        if k == 0 {
            out.push(le);
        }
        out.push(te);
    }
}

fn mean_y(mesh: &PanelMesh, panels: &[usize]) -> f64 {
    panels
        .iter()
        .map(|&p| mesh.panels[p].centroid.y)
        .sum::<f64>()
        / panels.len().max(1) as f64
}

impl EngineSurfaces {
    /// Reads the ramp, cowl and nozzle strips of `mesh` column by column.
    pub fn read(&mut self, model: &str, mesh: &PanelMesh) -> Result<(), ModelError> {
        let find = |name: &str| {
            mesh.surface_index(name).ok_or_else(|| {
                ModelError::inconsistent(
                    model,
                    format!(
                        "the body mesh has no `{name}` surface; the engine needs the vehicle body mesh \
                         (surfaces `{RAMP_SURFACE}`, `{COWL_SURFACE}` and `{NOZZLE_SURFACE}`)"
                    ),
                )
            })
        };
        let (ramp, cowl, nozzle) = (
            find(RAMP_SURFACE)?,
            find(COWL_SURFACE)?,
            find(NOZZLE_SURFACE)?,
        );
        self.spare.append(&mut self.columns);
        let mut cowls = std::mem::take(&mut self.cowl_strips);
        let mut nozzles = std::mem::take(&mut self.nozzle_strips);
        cowls.clear();
        nozzles.clear();
        for (s, strip) in mesh.strips.iter().enumerate() {
            let Some(&first) = strip.panels.first() else {
                continue;
            };
            let surface = mesh.panels[first].surface;
            if surface == ramp {
                let mut column = self.spare.pop().unwrap_or_default();
                column.y_m = mean_y(mesh, &strip.panels);
                column.ramp_panels.clear();
                column.ramp_panels.extend_from_slice(&strip.panels);
                column.nozzle_panels.clear();
                strip_polyline(mesh, &strip.panels, &mut column.section.ramp_m);
                self.columns.push(column);
            } else if surface == cowl {
                cowls.push((mean_y(mesh, &strip.panels), s));
            } else if surface == nozzle {
                nozzles.push((mean_y(mesh, &strip.panels), s));
            }
        }
        if self.columns.is_empty()
            || self.columns.len() != cowls.len()
            || self.columns.len() != nozzles.len()
        {
            return Err(ModelError::inconsistent(
                model,
                format!(
                    "the body mesh has {} inlet-ramp, {} cowl and {} nozzle strips; the engine needs \
                     one of each per spanwise column",
                    self.columns.len(),
                    cowls.len(),
                    nozzles.len()
                ),
            ));
        }
        self.columns.sort_by(|a, b| a.y_m.total_cmp(&b.y_m));
        cowls.sort_by(|a, b| a.0.total_cmp(&b.0));
        nozzles.sort_by(|a, b| a.0.total_cmp(&b.0));
        for ((column, (_, c)), (_, n)) in self.columns.iter_mut().zip(&cowls).zip(&nozzles) {
            let nozzle_strip = &mesh.strips[*n];
            column.nozzle_panels.extend_from_slice(&nozzle_strip.panels);
            strip_polyline(mesh, &mesh.strips[*c].panels, &mut column.section.cowl_m);
            strip_polyline(mesh, &nozzle_strip.panels, &mut column.section.nozzle_m);
            column.section.y_m = column.y_m;
        }
        self.cowl_strips = cowls;
        self.nozzle_strips = nozzles;
        for column in &self.columns {
            column.section.check(model)?;
        }
        let first = &self.columns[0].section;
        for c in &self.columns {
            let s = &c.section;
            if s.ramp_m.len() != first.ramp_m.len()
                || s.cowl_m.len() != first.cowl_m.len()
                || s.nozzle_m.len() != first.nozzle_m.len()
            {
                return Err(ModelError::inconsistent(
                    model,
                    "the engine strips of the body mesh differ in panel count across the span",
                ));
            }
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in &self.columns {
            for &p in &c.ramp_panels {
                for &v in mesh.panels[p].vertex_indices() {
                    lo = lo.min(mesh.vertices[v].y);
                    hi = hi.max(mesh.vertices[v].y);
                }
            }
        }
        if hi.is_nan() || lo.is_nan() || hi <= lo {
            return Err(ModelError::inconsistent(
                model,
                "the engine surfaces of the body mesh have no spanwise extent",
            ));
        }
        self.y_min_m = lo;
        self.y_max_m = hi;
        Ok(())
    }

    /// Engine width, m.
    pub fn width_m(&self) -> f64 {
        self.y_max_m - self.y_min_m
    }

    /// The section at `y_m`, linearly interpolated between the two nearest columns (the end
    /// columns beyond them).
    pub fn section_at(&self, y_m: f64, out: &mut SectionGeometry) {
        let cols = &self.columns;
        let last = cols.len() - 1;
        let (a, b, t) = if y_m <= cols[0].y_m {
            (0, 0, 0.0)
        } else if y_m >= cols[last].y_m {
            (last, last, 0.0)
        } else {
            let k = cols
                .windows(2)
                .position(|w| y_m >= w[0].y_m && y_m <= w[1].y_m)
                .unwrap_or(0);
            let span = cols[k + 1].y_m - cols[k].y_m;
            let t = if span > 0.0 {
                (y_m - cols[k].y_m) / span
            } else {
                0.0
            };
            (k, k + 1, t)
        };
        out.blend(&cols[a].section, &cols[b].section, t, y_m);
    }
}
