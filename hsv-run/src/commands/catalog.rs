//! `hsv-run models` and `hsv-run describe NAME`: what models exist and what settings they take.

use anyhow::Result;
use hsv_core::registry::Registry;

use crate::outln;

/// Every registered model as JSON (what `models --json` prints): name, family, role, fidelity,
/// summary and origin.
pub fn models_json(registry: &Registry) -> serde_json::Value {
    registry.iter().map(entry_json).collect()
}

/// One registered model as JSON: name, family, role, fidelity, summary and origin.
fn entry_json(e: &hsv_core::registry::RegistryEntry) -> serde_json::Value {
    serde_json::json!({
        "name": e.name,
        "family": e.role().family(),
        "role": e.role(),
        "fidelity": e.fidelity,
        "summary": e.summary,
        "origin": e.origin.to_string(),
    })
}

/// Lists every registered model with family, role, fidelity and summary.
pub fn models(registry: &Registry, json: bool) -> Result<()> {
    if json {
        outln!("{}", serde_json::to_string_pretty(&models_json(registry))?)?;
        return Ok(());
    }
    outln!(
        "{:<24} {:<11} {:<11} {:>8}  summary",
        "name",
        "family",
        "role",
        "fidelity"
    )?;
    for e in registry.iter() {
        outln!(
            "{:<24} {:<11} {:<11} {:>8}  {}",
            e.name,
            e.role().family().to_string(),
            e.role().to_string(),
            e.fidelity,
            e.summary
        )?;
    }
    Ok(())
}

/// Prints one model's summary, origin and settings.
pub fn describe(registry: &Registry, name: &str, json: bool) -> Result<()> {
    let e = registry.get(name)?;
    if json {
        let mut value = entry_json(e);
        value["settings"] = serde_json::json!(e.settings_doc);
        outln!("{}", serde_json::to_string_pretty(&value)?)?;
        return Ok(());
    }
    outln!(
        "{}  ({} / {}, fidelity {})",
        e.name,
        e.role().family(),
        e.role(),
        e.fidelity
    )?;
    outln!("{}", e.summary)?;
    outln!("origin: {}", e.origin)?;
    if e.settings_doc.trim().is_empty() {
        outln!("settings: none")?;
    } else {
        outln!("settings ([models.{}] in the config):", e.name)?;
        for line in e.settings_doc.lines() {
            outln!("  {line}")?;
        }
    }
    Ok(())
}
