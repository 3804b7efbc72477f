//! The flutter job of a trade study: one lifting surface heated in the flow and analysed over a
//! Mach grid as `hsv-run flutter` does ([`crate::analysis::flutter::sweep`]), the flutter Mach
//! number at each time in the flow, and its error against the reference combination's.

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};
use hsv_core::config::LoadedConfig;
use hsv_core::registry::Registry;
use serde::{Deserialize, Serialize};

use super::{CaseResult, StudySpec, Variation};
use crate::analysis::flutter::sweep::{FlutterBoundary, FlutterModels, FlutterSetup, flutter_map};
use crate::analysis::flutter::{DerivativeMethod, SurfaceOptions};
use crate::analysis::heating::HeatingSteps;

/// The grid and heating of a `flutter` study: the options of `hsv-run flutter` (direct state
/// derivative, no method comparison; conduction `full-order` unless a variation names it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlutterGrid {
    /// The analysed lifting surface ([`flutter_region`]).
    pub region: String,
    /// The grid's range and step as given (shards rebuild the same grid from them).
    pub mach_range: (f64, f64),
    pub mach_step: f64,
    pub machs: Vec<f64>,
    /// Times in the flow, ascending, s.
    pub times_s: Vec<f64>,
    /// Conduction step of the heating, s.
    pub dt_s: f64,
    pub alpha_deg: f64,
}

/// The lifting surface a flutter study analyses: the side its variations name, else the right
/// one (as `hsv-run flutter`; the left is its mirror image).
pub fn flutter_region(variations: &[Variation]) -> Result<String> {
    let named = |side: &str| variations.iter().any(|v| v.parts().0 == side);
    match (named("left_surface"), named("right_surface")) {
        (true, true) => bail!(
            "a flutter study analyses one lifting surface, but the variations name both              left_surface and right_surface; vary lifting_surfaces or one side"
        ),
        (true, false) => Ok("left_surface".to_owned()),
        _ => Ok("right_surface".to_owned()),
    }
}

/// Key of the flutter Mach number at `time_s` in a case's values.
pub fn flutter_mach_key(time_s: f64) -> String {
    format!("flutter_mach_at_{time_s}_s")
}

/// The flutter boundary of a case at one time in the flow.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlutterAtTime {
    pub time_s: f64,
    pub boundary: FlutterBoundary,
}

impl FlutterAtTime {
    /// `t = 20 s: Mach 12.345` or what the boundary is instead.
    pub fn describe(&self) -> String {
        let what = match &self.boundary {
            FlutterBoundary::Crossing {
                mach, frequency_hz, ..
            } => format!("flutter at Mach {mach:.4} ({frequency_hz:.2} Hz)"),
            FlutterBoundary::StableInRange {
                max_real_per_s,
                at_mach,
                least_damping_ratio,
                limited_by,
            } => format!(
                "no flutter in the Mach range (largest real part {max_real_per_s:.4} /s at \
                 Mach {at_mach}, least damping ratio {least_damping_ratio:.4}){}",
                limited_by
                    .as_ref()
                    .map_or_else(String::new, |l| format!(", not analysable {l}"))
            ),
            FlutterBoundary::UnstableAtLowest {
                lowest_mach,
                max_real_per_s,
                ..
            } => format!(
                "already unstable at the lowest Mach {lowest_mach} (largest real part \
                 {max_real_per_s:.4} /s)"
            ),
            FlutterBoundary::Unresolved { reason } => format!("unresolved: {reason}"),
        };
        format!("t = {} s: {what}", self.time_s)
    }
}

/// The flutter analysis of case `loaded`: the flutter command's, with its models from the
/// case's region (conduction `full-order` unless a variation names it: `pod` would train).
pub fn flutter_setup(spec: &StudySpec, loaded: &LoadedConfig) -> Result<FlutterSetup> {
    let Some(grid) = &spec.flutter else {
        bail!("a flutter study needs its Mach grid and times");
    };
    let region = grid.region.as_str();
    let configured = loaded.config.regions.region(region).with_context(|| {
        format!(
            "{}: key `regions.{region}`: not a lifting surface",
            loaded.file
        )
    })?;
    let conduction_varied = spec.variations.iter().any(|v| {
        let (table, role) = v.parts();
        role == "conduction" && (table == region || table == "lifting_surfaces")
    });
    let structure = configured.structure.with_context(|| {
        format!(
            "{}: region `{region}` has no structure model (set `regions.lifting_surfaces.structure`)",
            loaded.file
        )
    })?;
    let or = |name: Option<String>, default: &str| name.unwrap_or_else(|| default.to_owned());
    Ok(FlutterSetup {
        region: loaded.region(region)?,
        models: FlutterModels {
            aero: or(configured.aero, "shock-expansion-piston"),
            heat_flux: or(configured.heat_flux, "eckert"),
            conduction: if conduction_varied {
                or(configured.conduction, "full-order")
            } else {
                "full-order".to_owned()
            },
            structure,
        },
        altitude_m: spec.altitude_m,
        alpha_rad: grid.alpha_deg.to_radians(),
        heating: HeatingSteps {
            dt_s: grid.dt_s,
            flux_every: 1,
            initial_k: 293.0,
        },
        method: DerivativeMethod::Direct,
        compare_methods: false,
        options: SurfaceOptions::default(),
    })
}

/// The surface's flutter map: the flutter Mach number at each time, or the largest real part
/// and least damping where it does not flutter in the range.
pub(super) fn flutter_case(
    spec: &StudySpec,
    loaded: &LoadedConfig,
    registry: &Registry,
    out: &mut CaseResult,
) -> Result<()> {
    let setup = flutter_setup(spec, loaded)?;
    let Some(grid) = &spec.flutter else {
        bail!("a flutter study needs its Mach grid and times");
    };
    let map = flutter_map(&setup, registry, &grid.machs, &grid.times_s)?;
    for (&time_s, boundary) in grid.times_s.iter().zip(map.boundaries) {
        match &boundary {
            FlutterBoundary::Crossing { mach, .. } => {
                out.values.insert(flutter_mach_key(time_s), *mach);
            }
            FlutterBoundary::StableInRange {
                max_real_per_s,
                least_damping_ratio,
                ..
            } => {
                out.values
                    .insert(format!("max_real_per_s_at_{time_s}_s"), *max_real_per_s);
                out.values.insert(
                    format!("least_damping_ratio_at_{time_s}_s"),
                    *least_damping_ratio,
                );
            }
            _ => {}
        }
        out.flutter.push(FlutterAtTime { time_s, boundary });
    }
    Ok(())
}

/// Flutter error: max over times of |M_f − M_f,ref| / M_f,ref. A time at which neither
/// flutters in the range (or both already flutter at its lowest Mach) agrees and adds
/// nothing; one at which only one of them flutters, or either is unresolved, leaves the error
/// undefined (`None`): the range holds no number to compare.
pub(super) fn flutter_deviation(
    case: &CaseResult,
    reference: &CaseResult,
) -> (BTreeMap<String, f64>, Option<f64>) {
    use FlutterBoundary::{Crossing, StableInRange, UnstableAtLowest};
    let mut deviations = BTreeMap::new();
    if case.flutter.len() != reference.flutter.len() {
        return (deviations, None);
    }
    let mut error: f64 = 0.0;
    for (c, r) in case.flutter.iter().zip(&reference.flutter) {
        match (&c.boundary, &r.boundary) {
            (Crossing { mach, .. }, Crossing { mach: m_ref, .. }) => {
                let d = (mach - m_ref).abs();
                deviations.insert(flutter_mach_key(c.time_s), d);
                error = error.max(d / m_ref);
            }
            (StableInRange { .. }, StableInRange { .. })
            | (UnstableAtLowest { .. }, UnstableAtLowest { .. }) => {}
            _ => return (deviations, None),
        }
    }
    (deviations, error.is_finite().then_some(error))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(index: usize, flutter: Vec<FlutterAtTime>) -> CaseResult {
        CaseResult {
            index,
            models: Vec::new(),
            wall_time_s: 1.0,
            values: BTreeMap::new(),
            history: BTreeMap::new(),
            flutter,
            failure: None,
        }
    }

    fn at(time_s: f64, boundary: FlutterBoundary) -> FlutterAtTime {
        FlutterAtTime { time_s, boundary }
    }

    fn crossing(mach: f64) -> FlutterBoundary {
        FlutterBoundary::Crossing {
            mach,
            bracket: (mach - 0.5, mach + 0.5),
            evaluations: 5,
            frequency_hz: 20.0,
            grows_from: None,
        }
    }

    fn stable() -> FlutterBoundary {
        FlutterBoundary::StableInRange {
            max_real_per_s: -0.5,
            at_mach: 20.0,
            least_damping_ratio: 0.01,
            limited_by: None,
        }
    }

    /// Hand-computed: flutter Mach 15 and 4 against the reference's 12.5 and 5 give relative
    /// deviations 0.2 and 0.2, 2.5/12.5 and 1/5; a time at which neither flutters in the range
    /// adds nothing; one at which only one flutters leaves the error undefined.
    #[test]
    fn flutter_error_follows_its_definition() {
        let with = case;
        let reference = with(
            1,
            vec![
                at(0.0, crossing(12.5)),
                at(10.0, crossing(5.0)),
                at(20.0, stable()),
            ],
        );
        let other = with(
            0,
            vec![
                at(0.0, crossing(15.0)),
                at(10.0, crossing(4.0)),
                at(20.0, stable()),
            ],
        );
        let (d, e) = flutter_deviation(&other, &reference);
        assert!((e.unwrap() - 0.2).abs() < 1e-12);
        assert!((d[&flutter_mach_key(0.0)] - 2.5).abs() < 1e-12);
        assert!((d[&flutter_mach_key(10.0)] - 1.0).abs() < 1e-12);
        assert_eq!(d.len(), 2, "no deviation where neither flutters");
        let (_, e) = flutter_deviation(&reference, &reference);
        assert_eq!(e, Some(0.0));
        let only_one = with(
            0,
            vec![
                at(0.0, crossing(15.0)),
                at(10.0, stable()),
                at(20.0, stable()),
            ],
        );
        assert_eq!(flutter_deviation(&only_one, &reference).1, None);
        assert!(
            at(20.0, stable())
                .describe()
                .contains("no flutter in the Mach range")
        );
        assert!(
            at(20.0, stable())
                .describe()
                .contains("least damping ratio 0.0100")
        );
    }

    #[test]
    fn a_flutter_study_analyses_the_side_its_variations_name() {
        let region = |keys: &[&str]| {
            let v: Vec<Variation> = keys.iter().map(|k| k.parse().unwrap()).collect();
            flutter_region(&v)
        };
        assert_eq!(region(&["left_surface.aero=a"]).unwrap(), "left_surface");
        assert_eq!(
            region(&["lifting_surfaces.aero=a"]).unwrap(),
            "right_surface"
        );
        assert_eq!(region(&["main_body.aero=a"]).unwrap(), "right_surface");
        assert!(region(&["left_surface.aero=a", "right_surface.heat_flux=b"]).is_err());
    }
}
