//! `--export-dae DIR`: exactly what the solver integrates, as numpy-readable files.

use crate::error::PipelineError;
use crate::history::npy::write_npy;
use crate::output::RunDir;
use crate::problem::system::Problem;
use faer::Mat;
use serde::Serialize;
use squeal_solver::bdf::{BdfOptions, InitialConditionOptions};
use squeal_solver::bsql::SteadyOptions;

fn mat_npy(dir: &RunDir, name: &str, a: &Mat<f64>) -> Result<(), PipelineError> {
    let data: Vec<f64> = (0..a.nrows())
        .flat_map(|i| (0..a.ncols()).map(move |j| a[(i, j)]))
        .collect();
    write_npy(&dir.path(name), &data, a.ncols())
}

/// `solver_options.json`.
#[derive(Debug, Serialize)]
struct SolverOptionsFile<'a> {
    layout: &'static str,
    tfinal: f64,
    bdf: &'a BdfOptions,
    initial_conditions: &'a InitialConditionOptions,
    steady_state: &'a SteadyOptions,
    t_load: f64,
    step_load: bool,
    include_friction_damping: bool,
}

const README: &str = r#"# The BSQL problem as data (written by `squeal transient --export-dae`)

The solver integrates F(t, y, y') = 0 with y = [v (n), lambda (ng), u (n)] (paper eqs. 13-16):

    F_v      = M v' + B v + K u + G^T lambda' - P(t) - F_f(lambda', v)
    F_lambda = G v'
    F_u      = u' - v

lambda is the contact impulse: lambda' is the contact multiplier of paper eq. (12); a positive
lambda'_g is *tensile*, the compressive normal force of gap g is A_g P0_g - lambda'_g.

Files (all `.npy` are float64, C order, readable with `numpy.load`):

| file | shape | what |
|---|---|---|
| `M.npy`, `B.npy`, `K.npy` | n x n | reduced mass, damping (everything: element GE/W4, G/W3, modal), stiffness |
| `G.npy` | ng x n | contact constraint: row g = +n on the rotor DOFs, -n on the pad DOFs (eq. 9) |
| `p_pre.npy` | n x 1 | constant load (zero unless stated) |
| `p_brake.npy` | n x 1 | brake load at the end of the ramp (already multiplied by PMAX) |
| `gaps.json` | | gap table: per gap pad/rotor node ids, pad_dofs/rotor_dofs (0-based indices into v, null = fixed), unit normal n (out of the pad), area A, sliding velocity v_slide (omega x r), P0, temperature; a gap tied to a rotor face (pairing = surface) has `tie`: face, kind, xi, face node ids, weights N_a, their dofs (the rotor point is sum_a N_a u_a); plus the friction law and VTOL |
| `solver_options.json` | | BDF options (tolerances per partition, MAXORD, h0, ...), TOLINT, TFINAL, TLOAD |

P(t) = p_pre + r(t) p_brake with r(t) = min(t / t_load, 1) (a step at t = 0 when `step_load`).

Friction forces per gap (paper eqs. 1-7): p_n = -lambda'_g / A + P0; dv = v_r - v_p + v_slide
(v_r = sum_a N_a v_a on a tied gap, whose rotor force goes to the face nodes times N_a);
V_t = dv - (dv . n) n; F_t = mu(p_n, |V_t|, T) A p_n, times atan(|V_t| / VTOL) / atan(10) below
10 VTOL (the regularisation of paper eq. 5, normalised by its value at 10 VTOL so that it is
continuous there; squeal-contact's `regularisation`); the pad gets +F_t V_t/|V_t|, the rotor the
opposite.

Initial state: the steady sliding equilibrium before the brake load (v = 0, K u + G^T lambda' =
F_f(lambda', 0), G u = 0), then consistent y'(0) to TOLINT.
"#;

/// Writes the problem into `dir`.
pub fn export(
    dir: &RunDir,
    p: &Problem,
    bdf: &BdfOptions,
    ic: &InitialConditionOptions,
    steady: &SteadyOptions,
    tfinal: f64,
) -> Result<(), PipelineError> {
    mat_npy(dir, "M.npy", &p.m)?;
    mat_npy(dir, "B.npy", &p.b)?;
    mat_npy(dir, "K.npy", &p.k)?;
    mat_npy(dir, "G.npy", &p.g)?;
    let n = p.m.nrows();
    let pre = if p.load.p_pre.is_empty() {
        vec![0.0; n]
    } else {
        p.load.p_pre.clone()
    };
    let brake = if p.load.p_brake.is_empty() {
        vec![0.0; n]
    } else {
        p.load.p_brake.clone()
    };
    write_npy(&dir.path("p_pre.npy"), &pre, 1)?;
    write_npy(&dir.path("p_brake.npy"), &brake, 1)?;
    dir.write_json("gaps.json", &p.gaps)?;
    dir.write_json(
        "solver_options.json",
        &SolverOptionsFile {
            layout: "y = [v (n), lambda (ng), u (n)]",
            tfinal,
            bdf,
            initial_conditions: ic,
            steady_state: steady,
            t_load: p.load.t_load,
            step_load: p.load.step,
            include_friction_damping: p.bsql.include_friction_damping,
        },
    )?;
    dir.write_bytes("README.md", README.as_bytes())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::README;
    use squeal_contact::forces::regularisation;

    /// The README states the friction regularisation the code uses (issue: it said
    /// (2/π)·atan(|V_t|/VTOL), which the code does not use). Both laws are evaluated: the
    /// stated one, r(s) = atan(s/VTOL)/atan(10) below 10·VTOL and 1 above, equals the contact
    /// crate's s·φ(s) to round-off over the zone and beyond; the former statement differs by
    /// 1 − (2/π)·atan(10) = 6.3 % at the zone's end.
    #[test]
    fn the_readme_states_the_regularisation_the_code_uses() {
        let text = README.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            text.contains("times atan(|V_t| / VTOL) / atan(10) below 10 VTOL"),
            "the README's law"
        );
        assert!(!text.contains("(2/pi)"));
        let vtol = 2e-3;
        let stated = |s: f64| {
            if s < 10.0 * vtol {
                (s / vtol).atan() / 10f64.atan()
            } else {
                1.0
            }
        };
        for i in 1..=300 {
            let s = vtol * 12.0 * i as f64 / 300.0;
            let code = s * regularisation(s, vtol).0;
            assert!(
                (code - stated(s)).abs() < 1e-14,
                "s = {s}: {code} vs {}",
                stated(s)
            );
        }
        let end = 10.0 * vtol * (1.0 - 1e-12);
        let former = 2.0 / std::f64::consts::PI * (end / vtol).atan();
        let code = end * regularisation(end, vtol).0;
        let gap = (code - former) / code;
        assert!((gap - 0.0634).abs() < 1e-3, "{gap}");
    }
}
