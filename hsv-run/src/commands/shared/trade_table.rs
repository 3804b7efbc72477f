//! The trade table's outputs: `trade.csv`, `trade.json`, `trade.png` (error against cost, the
//! Pareto front), `summary.json` and the table on standard output, as `hsv-run trade` and
//! `hsv-run merge` of trade shards write them.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;

use crate::analysis::trade::{CaseResult, StudySpec, TradeJob, TradeTable, flutter_mach_key};
use crate::outln;
use crate::output::{
    LinePlot, LineStyle, RunFolder, RunStatus, Series, StyledPlot, write_file,
    write_styled_plots_png,
};

/// Writes `trade.csv`, `trade.json`, `trade.png` and `summary.json`, and prints the table (or
/// the summary with `json`).
pub fn write_table(folder: &mut RunFolder, table: &TradeTable, json: bool) -> Result<()> {
    let csv = folder.join("trade.csv");
    write_file(&csv, table_csv(table))?;
    folder.record(csv);
    let path = folder.join("trade.json");
    write_file(&path, serde_json::to_string_pretty(&table_json(table))?)?;
    folder.record(path);
    let png = folder.join("trade.png");
    write_pareto_png(&png, table)?;
    folder.record(png);
    let failed = table
        .rows
        .iter()
        .filter(|r| r.case.failure.is_some())
        .count();
    let summary = serde_json::json!({
        "job": table.spec.job.as_str(),
        "cases": table.rows.len(),
        "failed_cases": failed,
        "reference_case": table.reference_case,
        "pareto_cases": table.rows.iter().filter(|r| r.pareto).map(|r| r.case.index).collect::<Vec<_>>(),
    });
    let status = if failed == table.rows.len() {
        RunStatus::Failed("every case failed".to_owned())
    } else {
        RunStatus::Completed
    };
    let written = folder.write_summary(summary, &status)?;
    if json {
        outln!("{}", serde_json::to_string_pretty(&written)?)?;
    } else {
        print_table(table)?;
        outln!("outputs in {}", folder.path.display())?;
    }
    Ok(())
}

/// Names of the value columns: every value any case reports, sorted.
fn value_names(table: &TradeTable) -> Vec<String> {
    let mut names: Vec<String> = table
        .rows
        .iter()
        .flat_map(|r| r.case.values.keys().cloned())
        .collect();
    names.sort();
    names.dedup();
    names
}

/// Names of the deviation columns.
fn deviation_names(table: &TradeTable) -> Vec<String> {
    let mut names: Vec<String> = table
        .rows
        .iter()
        .flat_map(|r| r.deviations.keys().cloned())
        .collect();
    names.sort();
    names.dedup();
    names
}

fn number(value: Option<f64>) -> String {
    value.map_or_else(String::new, |v| format!("{v:.9e}"))
}

/// The table as CSV: one row per case; units in the headers; failures leave cells empty.
pub fn table_csv(table: &TradeTable) -> String {
    let values = value_names(table);
    let deviations = deviation_names(table);
    let deviation_label = match table.spec.job {
        TradeJob::Trim | TradeJob::Flutter => "abs_deviation",
        TradeJob::Simulate => "rms_deviation",
    };
    let flutter = table.spec.job == TradeJob::Flutter;
    let mut text = String::from(
        "case,combination,reference,pareto,fidelity_sum,wall_time_s,model_cost_s,error",
    );
    for v in &values {
        let _ = write!(text, ",{v}");
    }
    for d in &deviations {
        let _ = write!(text, ",{deviation_label}_{d}");
    }
    if flutter {
        text.push_str(",flutter_boundaries");
    }
    text.push_str(",failure\n");
    for row in &table.rows {
        let fidelity: u32 = row.fidelity.iter().map(|&f| u32::from(f)).sum();
        let _ = write!(
            text,
            "{},\"{}\",{},{},{fidelity},{:.6e},{},{}",
            row.case.index,
            row.label,
            row.reference,
            row.pareto,
            row.case.wall_time_s,
            number(row.model_cost_s),
            number(row.error)
        );
        for v in &values {
            let _ = write!(text, ",{}", number(row.case.values.get(v).copied()));
        }
        for d in &deviations {
            let _ = write!(text, ",{}", number(row.deviations.get(d).copied()));
        }
        if flutter {
            let _ = write!(
                text,
                ",\"{}\"",
                boundaries_text(&row.case).replace('"', "'")
            );
        }
        let failure = row.case.failure.as_deref().unwrap_or("").replace('"', "'");
        let _ = writeln!(text, ",\"{failure}\"");
    }
    text
}

/// A flutter case's boundary at each time, `; `-separated.
fn boundaries_text(case: &CaseResult) -> String {
    case.flutter
        .iter()
        .map(|b| b.describe())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The table as JSON (histories left out: they are in `trade-cases.json`).
pub fn table_json(table: &TradeTable) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = table
        .rows
        .iter()
        .map(|r| {
            let mut row = serde_json::json!({
                "case": r.case.index,
                "combination": r.label,
                "models": r.case.models,
                "fidelity": r.fidelity,
                "reference": r.reference,
                "pareto": r.pareto,
                "wall_time_s": r.case.wall_time_s,
                "model_cost_s": r.model_cost_s,
                "error": r.error,
                "values": r.case.values,
                "deviations": r.deviations,
                "failure": r.case.failure,
            });
            if !r.case.flutter.is_empty() {
                row["flutter_boundaries"] = serde_json::json!(r.case.flutter);
            }
            row
        })
        .collect();
    serde_json::json!({
        "job": table.spec.job.as_str(),
        "study": table.spec,
        "reference_case": table.reference_case,
        "error_definition": match table.spec.job {
            TradeJob::Trim => "max over alpha, elevon, phi of |value - reference| / |reference|",
            TradeJob::Simulate => "max over altitude, airspeed, alpha, pitch, q of RMS(history - reference) / max(RMS(reference), peak-to-peak(reference), floor); floors 0.01 m, 0.01 m/s, 0.001 deg, 0.001 deg, 0.001 deg/s",
            TradeJob::Flutter => FLUTTER_ERROR,
        },
        "rows": rows,
    })
}

/// Error against cost: every case as a marker, the Pareto front as a line; cost on a log10 axis.
fn write_pareto_png(path: &Path, table: &TradeTable) -> Result<()> {
    let point =
        |r: &crate::analysis::trade::TradeRow| (r.cost_s().log10(), r.error.unwrap_or(f64::NAN));
    let (x, y): (Vec<f64>, Vec<f64>) = table.rows.iter().map(point).unzip();
    let mut front: Vec<(f64, f64)> = table.rows.iter().filter(|r| r.pareto).map(point).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    // A staircase: each front point's error holds until the next, cheaper-to-better step.
    let mut stairs: Vec<(f64, f64)> = Vec::with_capacity(2 * front.len());
    for (i, p) in front.iter().enumerate() {
        if i > 0 {
            stairs.push((p.0, front[i - 1].1));
        }
        stairs.push(*p);
    }
    let (fx, fy): (Vec<f64>, Vec<f64>) = stairs.into_iter().unzip();
    let cost = if table.rows.iter().any(|r| r.model_cost_s.is_some()) {
        "log10 model cost (s)"
    } else {
        "log10 wall time (s)"
    };
    let plot = StyledPlot {
        plot: LinePlot {
            title: format!(
                "Fidelity trade ({}): error against cost",
                table.spec.job.as_str()
            ),
            x_label: cost.to_owned(),
            y_label: "error vs highest fidelity (-)".to_owned(),
            series: vec![
                Series {
                    label: "cases".to_owned(),
                    x,
                    y,
                },
                Series {
                    label: "Pareto front".to_owned(),
                    x: fx,
                    y: fy,
                },
            ],
        },
        styles: vec![
            LineStyle {
                colour: 0,
                markers_only: true,
                ..LineStyle::default()
            },
            LineStyle {
                colour: 1,
                ..LineStyle::default()
            },
        ],
    };
    write_styled_plots_png(path, &[plot], 1, (900, 600))
}

/// What a flutter study's error is.
const FLUTTER_ERROR: &str = "max over times of |flutter Mach - reference| / reference; a time at which neither flutters in the Mach range adds nothing, one at which only one of them flutters leaves the error undefined";

/// The value columns printed for `job`: (key, title).
fn shown_values(spec: &StudySpec) -> Vec<(String, String)> {
    let pairs = |list: &[(&str, &str)]| {
        list.iter()
            .map(|(k, t)| ((*k).to_owned(), (*t).to_owned()))
            .collect()
    };
    match spec.job {
        TradeJob::Trim => pairs(&[
            ("alpha_deg", "alpha (deg)"),
            ("elevon_deg", "elevon (deg)"),
            ("fuel_equivalence_ratio", "phi"),
            ("flight_path_angle_deg", "gamma (deg)"),
        ]),
        TradeJob::Simulate => pairs(&[
            ("trim_alpha_deg", "trim alpha"),
            ("final_altitude_m", "final alt (m)"),
            ("final_alpha_deg", "final alpha"),
        ]),
        TradeJob::Flutter => spec
            .flutter
            .iter()
            .flat_map(|g| &g.times_s)
            .map(|&t| (flutter_mach_key(t), format!("M_f @ {t} s")))
            .collect(),
    }
}

/// The table on standard output.
fn print_table(table: &TradeTable) -> Result<()> {
    let spec = &table.spec;
    let condition = match &spec.flutter {
        Some(g) => format!(
            "{} over Mach {:?}, {} m",
            g.region, g.machs, spec.altitude_m
        ),
        None => format!("Mach {}, {} m", spec.mach, spec.altitude_m),
    };
    outln!(
        "Fidelity trade study: {} at {condition}; {} cases, reference (highest fidelity) case {}",
        spec.job.as_str(),
        table.rows.len(),
        table.reference_case
    )?;
    let shown = shown_values(spec);
    let mut header = format!(
        "{:>4} {:>3} {:>8} {:>11} {:>11}",
        "case", "fid", "mark", "wall (s)", "cost (s)"
    );
    let _ = write!(header, " {:>11}", "error");
    for (_, title) in &shown {
        let _ = write!(header, " {title:>14}");
    }
    header.push_str("  combination");
    outln!("{header}")?;
    for row in &table.rows {
        let fidelity: u32 = row.fidelity.iter().map(|&f| u32::from(f)).sum();
        let mark = match (row.reference, row.pareto) {
            (true, true) => "ref,pf",
            (true, false) => "ref",
            (false, true) => "pf",
            _ => "",
        };
        let cell = |v: Option<f64>, w: usize| {
            v.map_or_else(|| format!("{:>w$}", "-"), |v| format!("{v:>w$.4e}"))
        };
        let mut line = format!(
            "{:>4} {fidelity:>3} {mark:>8} {:>11.4} {}",
            row.case.index,
            row.case.wall_time_s,
            cell(row.model_cost_s, 11)
        );
        let _ = write!(line, " {}", cell(row.error, 11));
        for (key, _) in &shown {
            let v = row.case.values.get(key).copied();
            let _ = write!(
                line,
                " {}",
                v.map_or_else(|| format!("{:>14}", "-"), |v| format!("{v:>14.6}"))
            );
        }
        let _ = write!(line, "  {}", row.label);
        if let Some(f) = &row.case.failure {
            let _ = write!(line, "  FAILED: {f}");
        }
        outln!("{line}")?;
        for b in row
            .case
            .flutter
            .iter()
            .filter(|b| b.boundary.mach().is_none())
        {
            outln!("{:>10}{}", "", b.describe())?;
        }
    }
    outln!(
        "error: {}; pf = on the Pareto front of (cost, error)",
        match spec.job {
            TradeJob::Trim => {
                "largest relative deviation of alpha, elevon, phi (gamma for a glide) from the \
                 reference"
            }
            TradeJob::Simulate =>
                "largest RMS deviation of altitude, airspeed, alpha, pitch, q relative to the reference's size (max of its RMS and peak-to-peak)",
            TradeJob::Flutter => FLUTTER_ERROR,
        }
    )?;
    Ok(())
}
