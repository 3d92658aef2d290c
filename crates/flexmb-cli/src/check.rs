//! `flexmb check`: validate a model, assemble it, and report degrees of freedom and redundancy.

use flexmb::analysis::{assemble, velocity_analysis, AssemblyReport, AssemblySettings, State, VelocityReport};
use flexmb::{Data, Model};

/// Result of checking a model.
pub struct CheckReport {
    pub assembly: AssemblyReport,
    pub velocity: VelocityReport,
}

/// Assembles the model and runs the velocity analysis.
pub fn check_model(model: &Model) -> Result<CheckReport, flexmb::analysis::AssemblyError> {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let assembly = assemble(model, &mut data, &mut state, AssemblySettings::default())?;
    let velocity = velocity_analysis(model, &mut data, &mut state)?;
    Ok(CheckReport { assembly, velocity })
}

/// Text for the assembly part of a check or run.
pub fn describe(model: &Model, report: &CheckReport) -> String {
    let a = &report.assembly;
    let l = model.layout();
    let mut s = format!(
        "model '{}': {} bodies, {} markers, {} joints ({} constraint equations), {} force elements\n\
         assembly: {} iterations, residual {:.2e} -> {:.2e}\n\
         degrees of freedom: {}\n",
        model.name(),
        model.bodies().len(),
        model.markers().len(),
        model.joints().len(),
        l.nc,
        model.forces().len(),
        a.iterations,
        a.initial_residual,
        a.residual,
        a.degrees_of_freedom,
    );
    if a.redundant.is_empty() {
        s.push_str("redundant constraints: none\n");
    } else {
        s.push_str(&format!(
            "redundant constraints: {} (removed; their reaction forces are reported as zero):\n",
            a.redundant.len()
        ));
        for r in &a.redundant {
            s.push_str(&format!("  - {}\n", r.description));
        }
    }
    for adj in &report.velocity.adjusted {
        s.push_str(&format!("warning: {adj}\n"));
    }
    s
}
