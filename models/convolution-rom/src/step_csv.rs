//! The step-response CSV import: a user's (e.g. CFD) generalized-force step responses, in the
//! format of the crate docs, read into a force `ResponseBlock` normalized by p∞ (and a∞).

use hsv_core::error::ModelError;

use crate::NAME;
use crate::identify::{ReferenceCondition, ResponseBlock};

/// Header columns of a step-response CSV before the `force_1..force_n` columns.
pub const CSV_COLUMNS: [&str; 4] = ["input", "mode", "step", "time_s"];

/// Reads a step-response CSV (format in the crate docs) into a force block normalized by the
/// reference p∞ (and a∞ for velocity steps).
pub fn read_step_csv(
    path: &str,
    text: &str,
    n_modes: usize,
    reference: &ReferenceCondition,
) -> Result<ResponseBlock, ModelError> {
    let error = |line: usize, message: String| {
        ModelError::inconsistent(NAME, format!("step CSV `{path}`, line {line}: {message}"))
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| error(1, "no header line".to_owned()))?;
    let columns: Vec<&str> = header.split(',').map(str::trim).collect();
    let expected: Vec<String> = CSV_COLUMNS
        .iter()
        .map(|c| (*c).to_owned())
        .chain((1..=n_modes).map(|k| format!("force_{k}")))
        .collect();
    if columns != expected {
        return Err(error(
            header_line,
            format!(
                "header `{header}`; expected `{}` (one force column per mode of the region's \
                 structure)",
                expected.join(",")
            ),
        ));
    }
    // Rows per input (modal coordinates, then velocities): (time, step, forces).
    let n_inputs = 2 * n_modes;
    let mut blocks: Vec<Vec<(f64, f64, Vec<f64>)>> = vec![Vec::new(); n_inputs];
    for (line, row) in lines {
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        if cells.len() != expected.len() {
            return Err(error(
                line,
                format!("{} cells, expected {}", cells.len(), expected.len()),
            ));
        }
        let number = |i: usize| {
            cells[i]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| error(line, format!("`{}` is not a finite number", cells[i])))
        };
        let mode = cells[1]
            .parse::<usize>()
            .ok()
            .filter(|m| (1..=n_modes).contains(m))
            .ok_or_else(|| error(line, format!("mode `{}` is not in 1..={n_modes}", cells[1])))?;
        let input = match cells[0] {
            "displacement" => mode - 1,
            "velocity" => n_modes + mode - 1,
            other => {
                return Err(error(
                    line,
                    format!("input `{other}`; expected `displacement` or `velocity`"),
                ));
            }
        };
        let step = number(2)?;
        if step == 0.0 {
            return Err(error(
                line,
                "step 0: the response per unit step is undefined".into(),
            ));
        }
        let time = number(3)?;
        let values = (4..cells.len())
            .map(number)
            .collect::<Result<Vec<_>, _>>()?;
        blocks[input].push((time, step, values));
    }
    let samples = blocks[0].len();
    for (input, block) in blocks.iter().enumerate() {
        let name = if input < n_modes {
            format!("displacement of mode {}", input + 1)
        } else {
            format!("velocity of mode {}", input - n_modes + 1)
        };
        if block.is_empty() && input < n_modes {
            return Err(error(header_line, format!("no rows for the {name}")));
        }
        if !block.is_empty() && block.len() != samples {
            return Err(error(
                header_line,
                format!(
                    "{} rows for the {name}, {samples} for the displacement of mode 1; every \
                     block needs the same times",
                    block.len()
                ),
            ));
        }
    }
    let dt_s = if samples > 1 {
        blocks[0][1].0 - blocks[0][0].0
    } else {
        0.0
    };
    if samples > 1 && dt_s <= 0.0 {
        return Err(error(header_line, format!("time step {dt_s} s is not > 0")));
    }
    for block in blocks.iter().filter(|b| !b.is_empty()) {
        for (i, (time, step, _)) in block.iter().enumerate() {
            let want = dt_s * i as f64;
            if (time - want).abs() > 1e-6 * dt_s.max(1e-12) + 1e-12 {
                return Err(error(
                    header_line,
                    format!(
                        "sample {i} at {time} s; times must run 0, dt, 2 dt, ... with dt = \
                         {dt_s} s in every block"
                    ),
                ));
            }
            if *step != block[0].1 {
                return Err(error(
                    header_line,
                    "the step size changes within a block".to_owned(),
                ));
            }
        }
    }
    let mut out = ResponseBlock::zeros(n_modes, n_inputs, samples, dt_s);
    for (input, block) in blocks.iter().enumerate() {
        for (sample, (_, step, values)) in block.iter().enumerate() {
            // Normalized input step: q, or q̇ / a∞.
            let input_step = if input < n_modes {
                *step
            } else {
                step / reference.speed_of_sound_m_s
            };
            for (s, v) in out.step_mut(sample, input, n_inputs).iter_mut().zip(values) {
                *s = v / (reference.pressure_pa * input_step);
            }
        }
    }
    Ok(out)
}
