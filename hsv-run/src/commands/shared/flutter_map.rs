//! A flutter map's outputs: the CSVs and PNGs of paper Figs. 14-16, `summary.json` and the
//! table on standard output, as `hsv-run flutter` and `hsv-run merge` of flutter shards write
//! them.

use std::path::Path;

use anyhow::Result;
use serde_json::json;

use crate::analysis::flutter::Instability;
use crate::analysis::flutter::sweep::{
    FlutterBoundary, FlutterMap, FlutterPoint, FlutterSetup, PointStatus, status_text,
};
use crate::outln;
use crate::output::{self, LinePlot, RunFolder, RunStatus, Series};

/// The analysed lifting surface: the right one (the left is its mirror image).
pub const SURFACE_REGION: &str = "right_surface";

/// The map's CSVs, PNGs and summary; the summary as written.
pub fn write_map(
    folder: &mut RunFolder,
    setup: &FlutterSetup,
    map: &FlutterMap,
) -> Result<serde_json::Value> {
    write_outputs(folder, map)?;
    folder.write_summary(summary(setup, map), &RunStatus::Completed)
}

/// The map's outputs and the table (or the summary with `json`): what `hsv-run merge` of
/// flutter shards ends with.
pub fn write_run(
    folder: &mut RunFolder,
    setup: &FlutterSetup,
    map: &FlutterMap,
    json: bool,
) -> Result<()> {
    let summary = write_map(folder, setup, map)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&summary)?)?;
    } else {
        print_table(setup, map, &folder.path)?;
    }
    Ok(())
}

/// The largest of the points' method differences, if any were computed.
fn worst_difference(map: &FlutterMap) -> Option<(f64, f64)> {
    map.points
        .iter()
        .flatten()
        .filter_map(|p| p.method_difference)
        .map(|d| (d.relative_matrix_difference, d.critical_root_difference))
        .reduce(|a, b| (a.0.max(b.0), a.1.max(b.1)))
}

/// The JSON summary: keys name quantity and unit.
fn summary(setup: &FlutterSetup, map: &FlutterMap) -> serde_json::Value {
    let boundaries: Vec<_> = map
        .times_s
        .iter()
        .zip(map.boundaries.iter().zip(&map.divergence))
        .map(|(t, (f, d))| {
            json!({"time_s": t, "flutter_mach": f.mach(), "flutter": f,
                   "divergence_mach": d.mach(), "divergence": d})
        })
        .collect();
    let limits: Vec<_> = map
        .points
        .iter()
        .flatten()
        .filter(|p| !p.status.is_analysed())
        .map(|p| json!({"mach": p.mach, "time_s": p.time_s, "status": p.status}))
        .collect();
    let first = map.boundaries.first().and_then(FlutterBoundary::mach);
    let last = map.boundaries.last().and_then(FlutterBoundary::mach);
    let difference = worst_difference(map);
    json!({
        "command": "flutter",
        "altitude_m": setup.altitude_m,
        "alpha_deg": setup.alpha_rad.to_degrees(),
        "models": setup.models,
        "derivative_method": setup.method,
        "mach_grid": map.machs,
        "times_s": map.times_s,
        "initial_temperature_k": setup.heating.initial_k,
        "conduction_dt_s": setup.heating.dt_s,
        "flutter_mach_first_time": first,
        "flutter_mach_last_time": last,
        "divergence_mach_first_time": map.divergence.first().and_then(FlutterBoundary::mach),
        "divergence_mach_last_time": map.divergence.last().and_then(FlutterBoundary::mach),
        "flutter_margin_loss": match (first, last) {
            (Some(a), Some(b)) if a > 0.0 => Some(1.0 - b / a),
            _ => None,
        },
        "boundaries": boundaries,
        "buckled_melting_or_failed_points": limits,
        "max_relative_matrix_difference_forward_vs_direct": difference.map(|d| d.0),
        "max_critical_root_difference_forward_vs_direct": difference.map(|d| d.1),
        "wall_time_s": map.wall_time_s,
        "paper": {"cold_flutter_mach": 16.1, "flutter_mach_after_100_s": 3.5,
                  "note": "Klock & Cesnik §IV.D, Fig. 16: first-mode flutter of their surface; ours is the sample planform"},
    })
}

/// The table on standard output.
pub fn print_table(setup: &FlutterSetup, map: &FlutterMap, folder: &Path) -> Result<()> {
    outln!(
        "flutter of `{}` at {} m, alpha {:.2} deg: aero `{}`, heat flux `{}`, conduction `{}`, structure `{}`",
        SURFACE_REGION,
        setup.altitude_m,
        setup.alpha_rad.to_degrees(),
        setup.models.aero,
        setup.models.heat_flux,
        setup.models.conduction,
        setup.models.structure
    )?;
    outln!(
        "Mach grid {:?}, {} times, wall time {:.1} s",
        map.machs,
        map.times_s.len(),
        map.wall_time_s
    )?;
    outln!(
        "{:>8}  {:>12}  {}",
        "t (s)",
        "flutter M",
        "flutter (oscillatory pair) | divergence (real root)"
    )?;
    for ((t, f), d) in map.times_s.iter().zip(&map.boundaries).zip(&map.divergence) {
        outln!(
            "{t:>8.1}  {:>12}  {}",
            f.mach()
                .map_or_else(|| "-".to_owned(), |m| format!("{m:.3}")),
            describe(f, Instability::Flutter)
        )?;
        outln!(
            "{:>8}  {:>12}  {}",
            "",
            d.mach()
                .map_or_else(|| "-".to_owned(), |m| format!("div {m:.3}")),
            describe(d, Instability::Divergence)
        )?;
    }
    for p in map.points.iter().flatten() {
        if !p.status.is_analysed() {
            outln!(
                "  Mach {:.2}, t = {:.1} s: {}",
                p.mach,
                p.time_s,
                status_text(&p.status)
            )?;
        }
    }
    if let Some((m, r)) = worst_difference(map) {
        outln!(
            "forward difference (7 steps) vs direct derivative: A differs by {m:.2e} (Frobenius, relative), the critical root by {r:.2e}"
        )?;
    }
    outln!("outputs in {}", folder.display())?;
    Ok(())
}

/// One line on a flutter or divergence boundary.
fn describe(b: &FlutterBoundary, kind: Instability) -> String {
    let what = kind.name();
    match b {
        FlutterBoundary::Crossing {
            mach,
            frequency_hz,
            evaluations,
            grows_from,
            ..
        } => {
            let origin = grows_from.map_or_else(
                || "mode not tracked".to_owned(),
                |g| {
                    format!(
                        "grows from mode {} ({:.2} Hz at Mach {})",
                        g.mode, g.frequency_hz, g.mach
                    )
                },
            );
            match kind {
                Instability::Flutter => format!(
                    "flutter at Mach {mach:.3}: {frequency_hz:.2} Hz, {origin}; {evaluations} Brent evaluations"
                ),
                Instability::Divergence => format!(
                    "divergence at Mach {mach:.3}: a real root crosses, {origin}; {evaluations} Brent evaluations"
                ),
            }
        }
        FlutterBoundary::StableInRange {
            max_real_per_s,
            at_mach,
            least_damping_ratio,
            limited_by,
        } => {
            let limit = limited_by
                .as_ref()
                .map_or_else(String::new, |l| format!("; analysable only below {l}"));
            // A time with no root of this kind (no real root for divergence) leaves the search's
            // maximum at −∞: say so instead of printing the sentinel.
            if max_real_per_s.is_finite() {
                format!(
                    "no {what} in the range (largest real part of its roots {max_real_per_s:.4} /s at Mach {at_mach}, least damping ratio {least_damping_ratio:.4}){limit}"
                )
            } else {
                format!("no {what} in the range (no root of its kind at any Mach analysed){limit}")
            }
        }
        FlutterBoundary::UnstableAtLowest {
            lowest_mach,
            max_real_per_s,
            least_damping_ratio,
        } => format!(
            "{what} already at Mach {lowest_mach} (largest real part {max_real_per_s:.4} /s, damping ratio {least_damping_ratio:.4})"
        ),
        FlutterBoundary::Unresolved { reason } => format!("{what} unresolved: {reason}"),
    }
}

/// The lowest grid Mach number of `row` that could not be analysed (melting, past the
/// material data, failed): above it the row says nothing about flutter.
fn limit_mach(row: &[FlutterPoint]) -> Option<f64> {
    row.iter()
        .filter(|p| !p.status.is_analysed())
        .map(|p| p.mach)
        .reduce(f64::min)
}

/// The crossings of `boundaries` as columns: time (s), Mach number, frequency (Hz), the mode
/// it grows from (0: not tracked) and that mode's frequency (Hz).
fn crossing_columns(times_s: &[f64], boundaries: &[FlutterBoundary]) -> [Vec<f64>; 5] {
    let mut cols: [Vec<f64>; 5] = Default::default();
    for (t, b) in times_s.iter().zip(boundaries) {
        if let FlutterBoundary::Crossing {
            mach,
            frequency_hz,
            grows_from,
            ..
        } = b
        {
            let (mode, from_hz) =
                grows_from.map_or((0.0, 0.0), |g| (g.mode as f64, g.frequency_hz));
            for (c, v) in cols
                .iter_mut()
                .zip([*t, *mach, *frequency_hz, mode, from_hz])
            {
                c.push(v);
            }
        }
    }
    cols
}

/// Fig. 16: the flutter Mach number versus time (flutter_mach.csv), the divergence Mach number
/// apart from it (divergence_mach.csv), the limit of the analysable range versus time
/// (flutter_limits.csv), and all three in flutter_mach.png.
fn write_flutter_mach(folder: &mut RunFolder, map: &FlutterMap) -> Result<()> {
    let flutter = crossing_columns(&map.times_s, &map.boundaries);
    let divergence = crossing_columns(&map.times_s, &map.divergence);
    for (name, kind, cols) in [
        ("flutter_mach.csv", "flutter", &flutter),
        ("divergence_mach.csv", "divergence", &divergence),
    ] {
        let path = folder.join(name);
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        output::write_csv(
            &path,
            &[
                "time_s",
                &format!("{kind}_mach"),
                "frequency_hz",
                "grows_from_mode",
                "grows_from_frequency_hz",
            ],
            &refs,
        )?;
        folder.record(path);
    }
    let (t_l, m_l): (Vec<f64>, Vec<f64>) = map
        .times_s
        .iter()
        .zip(&map.points)
        .filter_map(|(t, row)| limit_mach(row).map(|m| (*t, m)))
        .unzip();
    let path = folder.join("flutter_limits.csv");
    output::write_csv(
        &path,
        &["time_s", "lowest_unanalysable_mach"],
        &[&t_l, &m_l],
    )?;
    folder.record(path);
    let mut series = Vec::new();
    for (label, cols) in [
        ("flutter Mach (oscillatory pair crosses)", &flutter),
        ("divergence Mach (real root crosses)", &divergence),
    ] {
        if !cols[0].is_empty() {
            series.push(Series {
                label: label.to_owned(),
                x: cols[0].clone(),
                y: cols[1].clone(),
            });
        }
    }
    if !t_l.is_empty() {
        series.push(Series {
            label: "lowest Mach melted or past material data".to_owned(),
            x: t_l,
            y: m_l,
        });
    }
    if series.is_empty() {
        return Ok(());
    }
    let path = folder.join("flutter_mach.png");
    output::write_line_plots_png(
        &path,
        &[LinePlot {
            title: "Flutter and divergence Mach numbers versus time in flow".to_owned(),
            x_label: "time in flow (s)".to_owned(),
            y_label: "Mach number".to_owned(),
            series,
        }],
        1,
        (900, 600),
    )?;
    folder.record(path);
    Ok(())
}

/// CSVs and PNGs of Figs. 14-16.
fn write_outputs(folder: &mut RunFolder, map: &FlutterMap) -> Result<()> {
    write_flutter_mach(folder, map)?;
    // Fig. 15: every root of every grid point (with its tracked mode) and of every point the
    // boundary searches evaluated (search 1: flutter, 2: divergence; mode 0: not tracked), the
    // largest-σ root of each point flagged critical.
    let mut cols: [Vec<f64>; 9] = Default::default();
    let mut push_point = |p: &FlutterPoint, search: f64, modes: &[Option<usize>]| {
        let critical = p
            .roots
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.real_per_s.total_cmp(&b.1.real_per_s))
            .map(|(i, _)| i);
        for (j, r) in p.roots.iter().enumerate() {
            let mode = modes
                .iter()
                .position(|m| *m == Some(j))
                .map_or(0.0, |k| (k + 1) as f64);
            for (c, v) in cols.iter_mut().zip([
                p.time_s,
                p.mach,
                search,
                mode,
                if critical == Some(j) { 1.0 } else { 0.0 },
                r.real_per_s,
                r.imag_rad_s,
                r.frequency_hz,
                r.damping_ratio,
            ]) {
                c.push(v);
            }
        }
    };
    let mut loci = Vec::new();
    for (ti, row) in map.points.iter().enumerate() {
        let mut x = Vec::new();
        let mut y = Vec::new();
        for (mi, p) in row.iter().enumerate() {
            let tracked = map
                .tracked
                .get(ti)
                .and_then(|r| r.get(mi))
                .map_or(&[][..], Vec::as_slice);
            push_point(p, 0.0, tracked);
            if let Some(r) = tracked
                .first()
                .copied()
                .flatten()
                .and_then(|j| p.roots.get(j))
            {
                x.push(r.real_per_s);
                y.push(r.frequency_hz);
            }
        }
        for s in map.searched.get(ti).into_iter().flatten() {
            let search = match s.instability {
                Instability::Flutter => 1.0,
                Instability::Divergence => 2.0,
            };
            push_point(&s.point, search, &[]);
        }
        if !x.is_empty() {
            loci.push(Series {
                label: format!("t = {} s", map.times_s[ti]),
                x,
                y,
            });
        }
    }
    let path = folder.join("root_loci.csv");
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    output::write_csv(
        &path,
        &[
            "time_s",
            "mach",
            "search",
            "mode",
            "critical",
            "real_per_s",
            "imag_rad_s",
            "frequency_hz",
            "damping_ratio",
        ],
        &refs,
    )?;
    folder.record(path);
    if !loci.is_empty() {
        let path = folder.join("root_loci.png");
        output::write_line_plots_png(
            &path,
            &[LinePlot {
                title: "Root loci of the first free-vibration mode over Mach, by time in flow"
                    .to_owned(),
                x_label: "real part (1/s)".to_owned(),
                y_label: "frequency (Hz)".to_owned(),
                series: loci,
            }],
            1,
            (1000, 700),
        )?;
        folder.record(path);
    }
    // Fig. 14: temperature range of the structure versus time, by Mach number.
    let mut t_cols: [Vec<f64>; 5] = Default::default();
    for p in map.points.iter().flatten() {
        if matches!(p.status, PointStatus::Failed { .. }) && p.min_temperature_k.is_infinite() {
            continue;
        }
        for (c, v) in t_cols.iter_mut().zip([
            p.mach,
            p.time_s,
            p.min_temperature_k,
            p.max_temperature_k,
            p.mean_temperature_k,
        ]) {
            c.push(v);
        }
    }
    let path = folder.join("temperature_range.csv");
    let refs: Vec<&[f64]> = t_cols.iter().map(Vec::as_slice).collect();
    output::write_csv(
        &path,
        &[
            "mach",
            "time_s",
            "min_temperature_k",
            "max_temperature_k",
            "mean_temperature_k",
        ],
        &refs,
    )?;
    folder.record(path);
    let shown: Vec<usize> = {
        let n = map.machs.len();
        let k = n.min(5);
        (0..k).map(|i| i * (n - 1) / (k - 1).max(1)).collect()
    };
    let mut series = Vec::new();
    for &mi in &shown {
        let mut t = Vec::new();
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for row in &map.points {
            let p = &row[mi];
            if p.min_temperature_k.is_finite() && p.max_temperature_k.is_finite() {
                t.push(p.time_s);
                lo.push(p.min_temperature_k);
                hi.push(p.max_temperature_k);
            }
        }
        if !t.is_empty() {
            let m = map.machs[mi];
            series.push(Series {
                label: format!("Mach {m:.1} max"),
                x: t.clone(),
                y: hi,
            });
            series.push(Series {
                label: format!("Mach {m:.1} min"),
                x: t,
                y: lo,
            });
        }
    }
    if !series.is_empty() {
        let path = folder.join("temperature_range.png");
        output::write_line_plots_png(
            &path,
            &[LinePlot {
                title: "Temperature range of the lifting surface structure".to_owned(),
                x_label: "time in flow (s)".to_owned(),
                y_label: "temperature (K)".to_owned(),
                series,
            }],
            1,
            (1000, 650),
        )?;
        folder.record(path);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A time whose roots are all oscillatory has no real root: the divergence line says so
    /// instead of printing the search's −∞ sentinel.
    #[test]
    fn a_kind_with_no_roots_is_named_not_printed_as_minus_infinity() {
        let none = FlutterBoundary::StableInRange {
            max_real_per_s: f64::NEG_INFINITY,
            at_mach: f64::NAN,
            least_damping_ratio: f64::INFINITY,
            limited_by: None,
        };
        let line = describe(&none, Instability::Divergence);
        assert_eq!(
            line,
            "no divergence in the range (no root of its kind at any Mach analysed)"
        );
        let some = FlutterBoundary::StableInRange {
            max_real_per_s: -2.04,
            at_mach: 5.0,
            least_damping_ratio: 0.01,
            limited_by: None,
        };
        assert!(describe(&some, Instability::Flutter).contains("-2.0400 /s at Mach 5"));
    }
}
