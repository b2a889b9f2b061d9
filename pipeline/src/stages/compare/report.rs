//! `compare.json` and `compare.md`.

use super::CompareReport;
use crate::error::PipelineError;
use crate::output::RunDir;
use std::fmt::Write;

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |v| format!("{v:.digits$}"))
}

fn sci(x: Option<f64>) -> String {
    x.map_or("–".into(), |v| format!("{v:.3e}"))
}

/// The report as markdown: checks, matrices, modes, roots, summaries.
pub fn markdown(r: &CompareReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# squeal compare\n");
    let _ = writeln!(s, "- A: `{}`", r.a.path().display());
    let _ = writeln!(s, "- B: `{}`", r.b.path().display());
    if let Some((na, nb)) = r.n_dofs {
        let _ = writeln!(s, "- reduced DOFs: {na} and {nb}");
    }
    let _ = writeln!(
        s,
        "- result: **{}**\n",
        if r.passed {
            "within the tolerances"
        } else {
            "beyond a tolerance"
        }
    );
    if !r.checks.is_empty() {
        let _ = writeln!(
            s,
            "## Checks\n\n| tolerance | value | worst | at | passed |\n|---|---|---|---|---|"
        );
        for c in &r.checks {
            let _ = writeln!(
                s,
                "| {} | {:.3e} | {:.3e} | {} | {} |",
                c.tolerance_name,
                c.tolerance,
                c.worst,
                c.at,
                if c.passed { "yes" } else { "**no**" }
            );
        }
        s.push('\n');
    }
    if !r.matrices.is_empty() {
        let _ = writeln!(
            s,
            "## Matrices\n\n| matrix | ‖A‖_F | ‖B‖_F | ‖A−B‖_F | ‖A−B‖/‖A‖ | max abs diff | at (row, col) |\n|---|---|---|---|---|---|---|"
        );
        for m in &r.matrices {
            let _ = writeln!(
                s,
                "| {} | {:.6e} | {:.6e} | {:.6e} | {:.3e} | {:.3e} | {} |",
                m.name,
                m.norm_a,
                m.norm_b,
                m.norm_difference,
                m.relative,
                m.max_abs_difference,
                m.at.map_or("–".into(), |(i, j)| format!("({i}, {j})"))
            );
        }
        s.push('\n');
    }
    if !r.modes.is_empty() {
        let _ = writeln!(
            s,
            "## Undamped modes (paired by MAC)\n\n| mode A | f A Hz | mode B | f B Hz | Δf/f | MAC |\n|---|---|---|---|---|---|"
        );
        for p in &r.modes {
            let _ = writeln!(
                s,
                "| {} | {:.6} | {} | {} | {} | {:.6} |",
                p.mode_a,
                p.frequency_a_hz,
                p.mode_b.map_or("–".into(), |j| j.to_string()),
                opt(p.frequency_b_hz, 6),
                sci(p.relative_frequency_difference),
                p.mac
            );
        }
        if !r.unpaired_modes_b.is_empty() {
            let _ = writeln!(
                s,
                "\nModes of B paired with none of A: {:?}",
                r.unpaired_modes_b
            );
        }
        s.push('\n');
    }
    match (&r.roots, &r.cea_note) {
        (Some(roots), _) => {
            let _ = writeln!(
                s,
                "## CEA roots (paired by frequency)\n\n| f A Hz | Re p A | f B Hz | Re p B | Δf/f | Δ Re p | ΔRe p/|p| |\n|---|---|---|---|---|---|---|"
            );
            for p in roots {
                let _ = writeln!(
                    s,
                    "| {:.6} | {:.6e} | {} | {} | {} | {} | {} |",
                    p.frequency_a_hz,
                    p.real_part_a,
                    opt(p.frequency_b_hz, 6),
                    sci(p.real_part_b),
                    sci(p.relative_frequency_difference),
                    sci(p.real_part_difference),
                    sci(p.relative_real_part_difference)
                );
            }
            s.push('\n');
        }
        (None, Some(note)) => {
            let _ = writeln!(s, "## CEA roots\n\n{note}\n");
        }
        _ => {}
    }
    if !r.summaries.is_empty() {
        let _ = writeln!(
            s,
            "## summary.json side by side\n\n| key | A | B | relative |\n|---|---|---|---|"
        );
        for row in &r.summaries {
            let _ = writeln!(
                s,
                "| {}{} | {} | {} | {} |",
                row.key,
                if row.timing { " (timing)" } else { "" },
                row.a,
                row.b,
                sci(row.relative)
            );
        }
    }
    s
}

/// Writes `compare.json` and `compare.md` into `dir`.
pub fn write(r: &CompareReport, dir: &RunDir) -> Result<(), PipelineError> {
    dir.write_json("compare.json", r)?;
    dir.write_bytes("compare.md", markdown(r).as_bytes())?;
    Ok(())
}
