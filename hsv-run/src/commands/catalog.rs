//! `hsv-run models` and `hsv-run describe NAME`: what models exist and what settings they take.

use anyhow::Result;
use hsv_core::registry::Registry;

/// Lists every registered model with family, role, fidelity and summary.
pub fn models(registry: &Registry, json: bool) -> Result<()> {
    if json {
        let list: Vec<_> = registry
            .iter()
            .map(|e| {
                serde_json::json!({
                    "name": e.name,
                    "family": e.role().family(),
                    "role": e.role(),
                    "fidelity": e.fidelity,
                    "summary": e.summary,
                    "origin": e.origin.to_string(),
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&list)?);
        return Ok(());
    }
    println!(
        "{:<24} {:<11} {:<11} {:>8}  summary",
        "name", "family", "role", "fidelity"
    );
    for e in registry.iter() {
        println!(
            "{:<24} {:<11} {:<11} {:>8}  {}",
            e.name,
            e.role().family().to_string(),
            e.role().to_string(),
            e.fidelity,
            e.summary
        );
    }
    Ok(())
}

/// Prints one model's summary, origin and settings.
pub fn describe(registry: &Registry, name: &str, json: bool) -> Result<()> {
    let e = registry.get(name)?;
    if json {
        let value = serde_json::json!({
            "name": e.name,
            "family": e.role().family(),
            "role": e.role(),
            "fidelity": e.fidelity,
            "summary": e.summary,
            "origin": e.origin.to_string(),
            "settings": e.settings_doc,
        });
        println!("{}", serde_json::to_string_pretty(&value)?);
        return Ok(());
    }
    println!(
        "{}  ({} / {}, fidelity {})",
        e.name,
        e.role().family(),
        e.role(),
        e.fidelity
    );
    println!("{}", e.summary);
    println!("origin: {}", e.origin);
    if e.settings_doc.trim().is_empty() {
        println!("settings: none");
    } else {
        println!("settings ([models.{}] in the config):", e.name);
        for line in e.settings_doc.lines() {
            println!("  {line}");
        }
    }
    Ok(())
}
