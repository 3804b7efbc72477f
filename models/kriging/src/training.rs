//! The surrogate's training: a Latin hypercube of the base heat-flux model on flat plates (or a
//! user's CSV), the Gaussian-process fit per regime, and the cache of fitted surrogates keyed by
//! the fingerprint of what they depend on.

use super::*;

/// Inputs and log10 St of the training samples of one regime.
pub(super) struct TrainingSet {
    inputs: Array2<f64>,
    log_stanton: Array1<f64>,
}

pub(super) fn shape_error(e: ndarray::ShapeError) -> ModelError {
    ModelError::inconsistent(NAME, format!("input matrix: {e}"))
}

/// What a saved training must match: our settings (minus the file names and the online-only
/// keys) and the base and aero models' settings.
pub(super) fn fingerprint(
    settings: &Settings,
    context: &ModelContext<'_>,
) -> Result<String, ModelError> {
    let mut relevant = settings.clone();
    relevant.training_file.clear();
    relevant.extrapolate = false;
    relevant.emissivity = 0.0;
    relevant.melting_point_k = 0.0;
    relevant.default_running_length_m = 0.0;
    let csv = if settings.training_csv.is_empty() {
        String::new()
    } else {
        std::fs::read_to_string(&settings.training_csv).unwrap_or_default()
    };
    serde_json::to_string(&(
        relevant,
        config_model_settings(context, &settings.base_model),
        config_model_settings(context, &settings.training_aero_model),
        csv,
    ))
    .map_err(|e| ModelError::inconsistent(NAME, format!("fingerprint: {e}")))
}

/// The saved training at `path` if its seal matches and it was built from `fingerprint`; a
/// damaged file is reported and retrained.
pub(super) fn load(path: &Path, fingerprint: &str) -> Option<Surrogate> {
    match hsv_core::cache::load::<Surrogate>(path) {
        Ok(surrogate) => (surrogate.format == FORMAT && surrogate.fingerprint == fingerprint)
            .then_some(surrogate),
        Err(e) => {
            if e.is_damaged() {
                hsv_core::cache::warn_rebuilding(&e);
            }
            None
        }
    }
}

/// Writes the training as a sealed cache, atomically, and returns it as the file holds it, so
/// this run predicts exactly what a reloading run will.
pub(super) fn save(path: &Path, surrogate: &Surrogate) -> Result<Surrogate, ModelError> {
    let fail = |e: hsv_core::cache::CacheError| {
        ModelError::inconsistent(NAME, format!("saving the training: {e}"))
    };
    hsv_core::cache::save(path, surrogate).map_err(fail)?;
    hsv_core::cache::load(path).map_err(fail)
}

/// One flat-plate panel of length 2x (so its running length is x) inclined by θ to a freestream
/// along +x: normal n = (sin θ, 0, cos θ), so asin(n · V̂) = θ.
pub(super) fn training_plate(
    inclination_rad: f64,
    running_length_m: f64,
) -> Result<PanelMesh, ModelError> {
    let (s, c) = inclination_rad.sin_cos();
    let tangent = Vector3::new(-c, 0.0, s) * (2.0 * running_length_m);
    let a = Point3::new(0.0, -0.5, 0.0);
    let b = Point3::new(0.0, 0.5, 0.0);
    PanelMesh::new(
        vec![a, b, b + tangent, a + tangent],
        &[PanelSpec::quad(0, 1, 2, 3, 0)],
        vec![Strip { panels: vec![0] }],
        vec![Surface::new("training-plate", RegionKind::Other)],
    )
    .map_err(|e| ModelError::inconsistent(NAME, format!("training plate: {e}")))
}

/// Latin hypercube of the base model, forced into `regime`, on training plates.
pub(super) fn sample_base_model(
    settings: &Settings,
    context: &ModelContext<'_>,
    regime: Regime,
) -> Result<TrainingSet, ModelError> {
    let mut base_settings = context.settings_for(&settings.base_model);
    // Convection only, over the whole box: re-radiation and the wall-temperature limit are
    // applied online, so a box corner hotter than the melting point still trains.
    let table = &mut base_settings.table;
    table.insert("emissivity".to_owned(), toml::Value::Float(0.0));
    table.insert("melting_point_k".to_owned(), toml::Value::Float(f64::MAX));
    force_regime(table, settings, regime);
    let mut base = context
        .build::<dyn HeatFluxModel>(&settings.base_model, &base_settings)
        .map_err(|e| {
            settings_error(
                context,
                "base_model",
                format!(
                    "cannot build the training model (it needs `emissivity` and \
                     `melting_point_k` settings): {e}"
                ),
            )
        })?;
    let aero_settings = context.settings_for(&settings.training_aero_model);
    let mut aero = context
        .build::<dyn AeroModel>(&settings.training_aero_model, &aero_settings)
        .map_err(|e| settings_error(context, "training_aero_model", e.to_string()))?;
    let gas = context.region.gas;

    let limits = ndarray::arr2(&[
        settings.mach,
        settings.inclination_deg,
        settings.wall_temperature_ratio,
        settings.running_length_m.map(f64::log10),
        settings.altitude_m,
    ]);
    let points = Lhs::new(&limits)
        .with_rng(Xoshiro256Plus::seed_from_u64(settings.seed))
        .sample(settings.samples);
    let mut log_stanton = Array1::zeros(points.nrows());
    let mut solution = AeroSolution::default();
    for (i, x) in points.rows().into_iter().enumerate() {
        let running_length_m = 10f64.powf(x[3]);
        let plate = training_plate(x[1].to_radians(), running_length_m)?;
        let freestream = Freestream::standard(x[0], x[4], gas)?;
        let flight = FlightCondition::steady(freestream, 0.0, 0.0);
        aero.evaluate(&plate, &flight, &PanelMotion::default(), &mut solution)?;
        let edge = solution.edge[0];
        let turbulent = regime == Regime::Turbulent;
        let recovery_k = recovery_temperature_k(
            &edge,
            gas.gamma,
            recovery_factor(settings.prandtl_number, turbulent),
        );
        let wall_k = x[2] * recovery_k;
        let mut q = [0.0];
        base.heat_flux(&plate, &flight, &solution, &[wall_k], &mut q)?;
        let stanton = stanton_number(q[0], &edge, &gas, recovery_k, wall_k);
        if !(stanton.is_finite() && stanton > 0.0) {
            return Err(ModelError::inconsistent(
                NAME,
                format!(
                    "training sample {i} ({} = {:?}) gave St = {stanton}; narrow the training box",
                    INPUTS.join(", "),
                    x.to_vec()
                ),
            ));
        }
        log_stanton[i] = stanton.log10();
    }
    Ok(TrainingSet {
        inputs: points,
        log_stanton,
    })
}

/// The base model's settings for training in one regime: `regime` and `prandtl_number` are
/// the surrogate's, so its recovery temperature is the one St is referenced to.
pub(super) fn force_regime(base_settings: &mut toml::Table, settings: &Settings, regime: Regime) {
    let name = match regime {
        Regime::Laminar => "laminar",
        Regime::Turbulent => "turbulent",
        Regime::Transitional => "transitional",
    };
    base_settings.insert("regime".to_owned(), toml::Value::String(name.to_owned()));
    base_settings.insert(
        "prandtl_number".to_owned(),
        toml::Value::Float(settings.prandtl_number),
    );
}

/// St = q / (ρ_e u_e c_p (T_aw − T_w)).
pub(super) fn stanton_number(
    heat_flux_w_m2: f64,
    edge: &EdgeState,
    gas: &PerfectGas,
    recovery_temperature_k: f64,
    wall_temperature_k: f64,
) -> f64 {
    heat_flux_w_m2
        / (edge.density_kg_m3
            * edge.velocity_m_s
            * gas.cp()
            * (recovery_temperature_k - wall_temperature_k))
}

/// Reads user training data (header [`CSV_HEADER`]) into (laminar, turbulent) sets.
pub(super) fn read_csv(path: &Path) -> Result<[Option<TrainingSet>; 2], ModelError> {
    let shown = path.display().to_string();
    let fail = |message: String| ModelError::inconsistent(NAME, format!("{shown}: {message}"));
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let expected = CSV_HEADER;
    match lines.next() {
        Some((_, header)) if header.replace(' ', "") == expected => {}
        _ => return Err(fail(format!("the first line must be `{expected}`"))),
    }
    let mut inputs = [Vec::new(), Vec::new()];
    let mut log_stanton = [Vec::new(), Vec::new()];
    for (number, line) in lines {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| fail(format!("line {}: {e}", number + 1)))?;
        if values.len() != 7 {
            return Err(fail(format!(
                "line {}: {} values, expected 7",
                number + 1,
                values.len()
            )));
        }
        if !(values[3] > 0.0 && values[6] > 0.0 && values.iter().all(|v| v.is_finite())) {
            return Err(fail(format!(
                "line {}: running length and Stanton number must be finite and > 0",
                number + 1
            )));
        }
        let regime = match values[5] {
            0.0 => 0,
            1.0 => 1,
            other => {
                return Err(fail(format!(
                    "line {}: turbulent = {other}, expected 0 (laminar) or 1 (turbulent)",
                    number + 1
                )));
            }
        };
        inputs[regime].extend_from_slice(&[
            values[0],
            values[1],
            values[2],
            values[3].log10(),
            values[4],
        ]);
        log_stanton[regime].push(values[6].log10());
    }
    let total = log_stanton[0].len() + log_stanton[1].len();
    let mut sets = [None, None];
    for (k, (inputs, log_stanton)) in inputs.into_iter().zip(log_stanton).enumerate() {
        if log_stanton.is_empty() {
            continue;
        }
        if log_stanton.len() < 10 {
            return Err(fail(format!(
                "{} {} samples; a 5-input surrogate needs at least 10",
                log_stanton.len(),
                ["laminar", "turbulent"][k]
            )));
        }
        sets[k] = Some(TrainingSet {
            inputs: Array2::from_shape_vec((log_stanton.len(), 5), inputs).map_err(shape_error)?,
            log_stanton: Array1::from(log_stanton),
        });
    }
    if total == 0 {
        return Err(fail("no samples".to_owned()));
    }
    Ok(sets)
}

pub(super) fn fit(inputs: Array2<f64>, log_stanton: Array1<f64>) -> Result<StantonGp, ModelError> {
    Kriging::params()
        .fit(&Dataset::new(inputs, log_stanton))
        .map_err(|e| ModelError::inconsistent(NAME, format!("kriging fit: {e}")))
}

/// Fits each regime's set, with the box the sets span (or the sampled box).
pub(super) fn train(
    data: [Option<TrainingSet>; 2],
    settings: &Settings,
    fingerprint: String,
) -> Result<Surrogate, ModelError> {
    let mut lower = [f64::INFINITY; 5];
    let mut upper = [f64::NEG_INFINITY; 5];
    for set in data.iter().flatten() {
        for row in set.inputs.rows() {
            for k in 0..5 {
                lower[k] = lower[k].min(row[k]);
                upper[k] = upper[k].max(row[k]);
            }
        }
    }
    if settings.training_csv.is_empty() {
        // A Latin hypercube does not reach the corners; the box is the one sampled over.
        let boxes = [
            settings.mach,
            settings.inclination_deg,
            settings.wall_temperature_ratio,
            settings.running_length_m.map(f64::log10),
            settings.altitude_m,
        ];
        for (k, [lo, hi]) in boxes.into_iter().enumerate() {
            lower[k] = lo;
            upper[k] = hi;
        }
    }
    let [laminar, turbulent] = data;
    Ok(Surrogate {
        format: FORMAT,
        fingerprint,
        lower,
        upper,
        laminar: laminar
            .map(|set| train_regime(&set, settings))
            .transpose()?,
        turbulent: turbulent
            .map(|set| train_regime(&set, settings))
            .transpose()?,
    })
}

/// Fits without the held-out tail to measure the error, then on everything.
pub(super) fn train_regime(
    data: &TrainingSet,
    settings: &Settings,
) -> Result<RegimeSurrogate, ModelError> {
    let n = data.log_stanton.len();
    let held_out = ((n as f64) * settings.holdout_fraction).round() as usize;
    let (holdout_rms_relative_error, holdout_max_relative_error) = if held_out > 0 {
        let split = n - held_out;
        let partial = fit(
            data.inputs.slice(ndarray::s![..split, ..]).to_owned(),
            data.log_stanton.slice(ndarray::s![..split]).to_owned(),
        )?;
        let predicted = partial
            .predict(&data.inputs.slice(ndarray::s![split.., ..]))
            .map_err(|e| ModelError::inconsistent(NAME, format!("kriging prediction: {e}")))?;
        let errors: Vec<f64> = predicted
            .iter()
            .zip(data.log_stanton.slice(ndarray::s![split..]))
            .map(|(p, t)| (10f64.powf(*p - *t) - 1.0).abs())
            .collect();
        let sum_sq: f64 = errors.iter().map(|e| e * e).sum();
        (
            (sum_sq / held_out as f64).sqrt(),
            errors.iter().copied().fold(0.0, f64::max),
        )
    } else {
        (f64::NAN, f64::NAN)
    };
    Ok(RegimeSurrogate {
        holdout_rms_relative_error,
        holdout_max_relative_error,
        samples: n,
        gp: fit(data.inputs.clone(), data.log_stanton.clone())?,
    })
}
