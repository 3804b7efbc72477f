//! An error and its causes as one line: the one rendering the CLI, run folders, trade cases,
//! the Python layer and the FMU print.

/// The error and its causes, `: `-joined, each said once. Several error types quote their
/// source in their own message (`region `propulsion`: {source}`, so `e.to_string()` stays
/// complete where it is stored) and also chain it; anyhow's `{:#}` and a plain join would then
/// say that cause twice, so a cause the line already ends with is not added again.
pub fn error_line(error: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in error.chain().map(ToString::to_string) {
        if text.ends_with(&cause) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&cause);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::error_line;

    /// A vehicle error quotes its model's message and also chains it as its source, and a
    /// simulation error quotes the vehicle's: the line says each once, while distinct causes
    /// (the context) are all kept.
    #[test]
    fn the_error_line_says_each_cause_once() {
        let model = hsv_core::ModelError::inconsistent("scramjet-1d", "the flow would expand");
        let vehicle = crate::vehicle::partitioned::VehicleError::Model {
            region: "propulsion".to_owned(),
            source: model,
        };
        let simulation = crate::analysis::simulate::SimulationError {
            time_s: 0.5,
            source: vehicle,
        };
        let error = anyhow::Error::from(simulation).context("simulate");
        assert_eq!(
            error_line(&error),
            "simulate: at t = 0.5000 s: region `propulsion`: scramjet-1d: the flow would expand"
        );
        assert!(
            format!("{error:#}")
                .matches("the flow would expand")
                .count()
                > 1
        );
    }
}
