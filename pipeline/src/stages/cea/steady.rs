//! The steady sliding states of a friction sweep, with K factorised once for the whole sweep.

use crate::error::PipelineError;
use crate::problem::system::Problem;
use crate::problem::tangents::{
    at_steady_state, full_load_time, tangents, Linearisation, StateSource,
};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Col, Mat};
use squeal_contact::GapSet;
use squeal_solver::bsql::SteadyOptions;

use squeal_solver::Real;

/// Smallest |U_ii|/max|U_ii| of the LU of K for the block elimination to be used (below it K
/// is treated as singular and every state is solved by the dense Newton of
/// `squeal_solver::bsql::steady_state`).
const K_PIVOT_RATIO_MIN: Real = 1e-12;

/// Steady states of the same structure (K, G, compliance, load) under different friction laws.
///
/// # Derivation
/// The steady state solves `K u + Gᵀλ̇ = P(t) + F_f(λ̇, 0)`, `G u − c∘λ̇ = 0` (see
/// `squeal_solver::bsql::steady_state`) by Newton's method, whose matrix
/// ```text
/// [K   A]            A = Gᵀ − ∂F_f/∂λ̇ (n × ng)
/// [G  −c]
/// ```
/// changes with the friction law only through A. With K = LU factorised once and
/// `W = K⁻ᵀGᵀ` (so `G K⁻¹ = Wᵀ`), a Newton correction is
/// ```text
/// (Wᵀ A + diag c) δλ̇ = Wᵀ r_u − r_g,      δu = K⁻¹(r_u − A δλ̇)
/// ```
/// — an ng × ng LU and one solve with K per iteration instead of a dense LU of size n + ng
/// (O(ng² n) instead of O((n + ng)³)). The convergence test is the one of `steady_state` on
/// the true residual, so the state is the same to within the Newton tolerance; Newton starts
/// from the state of the previous call (a neighbouring μ).
///
/// K is singular when a part is held only by the contact (brake pads free normal to the
/// rotor: their rigid motion along the normal). Then the first block row is replaced by itself
/// plus ρGᵀ times the second (an equivalent system: the augmented Lagrangian form),
/// ```text
/// [K + ρGᵀG   A − ρGᵀ diag c] [δu ]   [r_u + ρGᵀ r_g]
/// [G          −diag c       ] [δλ̇] = [r_g          ]
/// ```
/// whose K_ρ = K + ρGᵀG is regular when no motion is free in K and unseen by G; the same
/// elimination runs with K_ρ, W = K_ρ⁻ᵀGᵀ, A_ρ = A − ρGᵀ diag c and r_u + ρGᵀr_g. ρ is the
/// largest |K_ii| over the largest squared row norm of G (the added stiffness is of K's
/// size). When K_ρ is singular too, or Newton does not converge, the dense `steady_state`
/// runs instead (counted in [`SweepSteady::n_dense`]).
pub struct SweepSteady {
    /// LU of K_ρ = K + ρGᵀG (None: singular, always dense).
    k_lu: Option<PartialPivLu<Real>>,
    /// W = K_ρ⁻ᵀGᵀ (n × ng).
    w: Mat<Real>,
    /// ρ of the augmented form (0 when K itself is regular).
    pub rho: Real,
    /// P(t) at the full-load time t.
    p: Vec<Real>,
    t: Real,
    /// The last state (u, λ̇): the next Newton's starting point.
    last: Option<(Vec<Real>, Vec<Real>)>,
    /// States solved by the block elimination.
    pub n_fast: usize,
    /// States solved by the dense Newton (fallback).
    pub n_dense: usize,
    /// Newton iterations of the block elimination, in total.
    pub newton_iterations: usize,
}

impl SweepSteady {
    /// Factorises K of `problem` and forms W = K⁻ᵀGᵀ.
    pub fn new(problem: &Problem) -> Self {
        let (n, ng) = (problem.k.nrows(), problem.g.nrows());
        let t = full_load_time(problem);
        let mut p = vec![0.0; n];
        problem.load.add_to(t, 1.0, &mut p);
        let regular = |lu: &PartialPivLu<Real>| {
            let u = lu.U();
            let (mut pmin, mut pmax) = (Real::INFINITY, 0.0 as Real);
            for i in 0..n {
                pmin = pmin.min(u[(i, i)].abs());
                pmax = pmax.max(u[(i, i)].abs());
            }
            n > 0 && pmax.is_finite() && pmin > K_PIVOT_RATIO_MIN * pmax
        };
        let mut rho = 0.0;
        let mut lu = problem.k.partial_piv_lu();
        let mut ok = regular(&lu);
        if !ok && ng > 0 {
            // The augmented form: K + ρGᵀG.
            let g = &problem.g;
            let kmax = (0..n).fold(0.0 as Real, |m, i| m.max(problem.k[(i, i)].abs()));
            let gmax = (0..ng).fold(0.0 as Real, |m, r| {
                m.max((0..n).map(|j| g[(r, j)] * g[(r, j)]).sum::<Real>())
            });
            if kmax > 0.0 && gmax > 0.0 && kmax.is_finite() && gmax.is_finite() {
                rho = kmax / gmax;
                let k_rho = &problem.k + (g.transpose() * g) * faer::Scale(rho);
                lu = k_rho.partial_piv_lu();
                ok = regular(&lu);
            }
        }
        let w = if ok {
            let mut w = problem.g.transpose().to_owned();
            lu.solve_transpose_in_place(&mut w);
            w
        } else {
            Mat::zeros(n, ng)
        };
        SweepSteady {
            k_lu: ok.then_some(lu),
            w,
            rho: if ok { rho } else { 0.0 },
            p,
            t,
            last: None,
            n_fast: 0,
            n_dense: 0,
            newton_iterations: 0,
        }
    }

    /// The steady state of `problem` with the friction of `gaps`, and its tangents.
    pub fn solve(
        &mut self,
        problem: &Problem,
        gaps: &GapSet,
        opts: &SteadyOptions,
    ) -> Result<Linearisation, PipelineError> {
        let fast = match self.block_newton(problem, gaps, opts)? {
            Some(x) => Some(x),
            None => {
                // The cold start of the dense solver, as a single CEA runs it.
                self.last = None;
                None
            }
        };
        let lin = match fast {
            Some((u, lambda_dot, iterations, residual_norm)) => {
                let n = problem.k.nrows();
                let v = vec![0.0; n];
                let (d, c_f) = tangents(gaps, n, &v, &lambda_dot)?;
                self.n_fast += 1;
                self.newton_iterations += iterations;
                Linearisation {
                    source: StateSource::SteadyState {
                        t: self.t,
                        load_factor: problem.load.ramp(self.t),
                        newton_iterations: iterations,
                        residual_norm,
                    },
                    u,
                    v,
                    lambda_dot,
                    d,
                    c_f,
                }
            }
            None => {
                self.n_dense += 1;
                at_steady_state(problem, gaps, opts)?
            }
        };
        self.last = Some((lin.u.clone(), lin.lambda_dot.clone()));
        Ok(lin)
    }

    /// Newton with the block elimination: `Some((u, λ̇, iterations, residual))`, or `None`
    /// when K is singular or Newton did not converge (the caller then runs the dense solver).
    #[allow(clippy::type_complexity)]
    fn block_newton(
        &self,
        problem: &Problem,
        gaps: &GapSet,
        opts: &SteadyOptions,
    ) -> Result<Option<(Vec<Real>, Vec<Real>, usize, Real)>, PipelineError> {
        let Some(k_lu) = &self.k_lu else {
            return Ok(None);
        };
        opts.validate().map_err(|source| PipelineError::Solver {
            what: "steady-state options".into(),
            source,
        })?;
        let (k, g, c) = (&problem.k, &problem.g, &problem.compliance);
        let (n, ng) = (k.nrows(), g.nrows());
        let (mut u, mut lam) = match &self.last {
            Some((u, l)) if u.len() == n && l.len() == ng => (u.clone(), l.clone()),
            _ => (vec![0.0; n], vec![0.0; ng]),
        };
        let scale = self.p.iter().fold(1.0 as Real, |m, x| m.max(x.abs()));
        let tol = opts.tol * scale;
        let zero_v = vec![0.0; n];
        let contact = |e: squeal_contact::ContactError| PipelineError::Contact {
            what: "steady state of the friction sweep".into(),
            source: e,
        };
        let mut iterations = 0;
        loop {
            // Residual r = [K u + Gᵀλ̇ − P − F_f(λ̇, 0); G u − c∘λ̇].
            let uc = Col::from_fn(n, |i| u[i]);
            let lc = Col::from_fn(ng, |i| lam[i]);
            let mut ru = k * &uc + g.transpose() * &lc;
            let mut f = vec![0.0; n];
            gaps.add_forces(&zero_v, &lam, &mut f).map_err(contact)?;
            for i in 0..n {
                ru[i] -= self.p[i] + f[i];
            }
            let mut rg = g * &uc;
            for (kk, &ck) in c.iter().enumerate() {
                rg[kk] -= ck * lam[kk];
            }
            let rn = ru.iter().chain(rg.iter()).fold(0.0 as Real, |m, x| {
                if x.is_finite() {
                    m.max(x.abs())
                } else {
                    Real::NAN
                }
            });
            if !rn.is_finite() {
                return Ok(None);
            }
            if rn <= tol {
                return Ok(Some((u, lam, iterations, rn)));
            }
            if iterations == opts.max_iters {
                return Ok(None);
            }
            iterations += 1;
            // A = Gᵀ − ∂F_f/∂λ̇, S = WᵀA + diag c.
            let mut a = Mat::<Real>::zeros(n, ng);
            gaps.add_tangents(&zero_v, &lam, &mut a, None)
                .map_err(contact)?;
            let mut a = g.transpose() - &a;
            if self.rho != 0.0 {
                // The augmented form: A_ρ = A − ρGᵀ diag c, r_u + ρGᵀr_g.
                for (kk, &ck) in c.iter().enumerate() {
                    if ck != 0.0 {
                        for i in 0..n {
                            a[(i, kk)] -= self.rho * ck * g[(kk, i)];
                        }
                    }
                }
                ru += (g.transpose() * &rg) * faer::Scale(self.rho);
            }
            let mut s = self.w.transpose() * &a;
            for (kk, &ck) in c.iter().enumerate() {
                s[(kk, kk)] += ck;
            }
            let s_lu = s.partial_piv_lu();
            let mut dl = self.w.transpose() * &ru - &rg;
            s_lu.solve_in_place(dl.as_mat_mut());
            let mut du = ru - &a * &dl;
            k_lu.solve_in_place(du.as_mat_mut());
            for i in 0..n {
                u[i] -= du[i];
            }
            for kk in 0..ng {
                lam[kk] -= dl[kk];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_contact::{FrictionLaw, Gap};
    use squeal_solver::bsql::{BsqlOptions, LoadHistory};

    /// Two pad nodes (DOFs 0–2, 6–8) pressed on one rotor node (DOFs 3–5) sliding along +x:
    /// an unsymmetric friction coupling, a preload P0 and a brake load on the pads.
    /// `pad_z_stiffness = 0` leaves the pads free normal to the rotor (K singular; the
    /// contact holds them).
    fn model(pad_z_stiffness: f64) -> (Problem, GapSet) {
        let n = 9;
        let mut k = Mat::from_fn(n, n, |i, j| {
            if i == j {
                10.0 + i as f64
            } else {
                0.3 / (1.0 + (i as f64 - j as f64).abs())
            }
        });
        for i in [2, 8] {
            for j in 0..n {
                k[(i, j)] *= pad_z_stiffness;
                k[(j, i)] *= pad_z_stiffness;
            }
        }
        let gap = |pad: usize, x: f64| Gap {
            pad_node: pad as u64,
            rotor_node: 100,
            coords: [x, 0.0, 0.0],
            pad_dofs: [Some(pad), Some(pad + 1), Some(pad + 2)],
            rotor_dofs: [Some(3), Some(4), Some(5)],
            normal: [0.0, 0.0, -1.0],
            area: 0.5,
            v_slide: [2.0, 0.0, 0.0],
            p0: 0.1,
            temperature: 0.0,
            tie: None,
            rotor_rows: Vec::new(),
            pad_side: None,
            friction: None,
        };
        let gaps = GapSet::new(
            vec![gap(0, 0.0), gap(6, 1.0)],
            FrictionLaw::Constant { mu: 0.3 },
            1e-6,
        )
        .unwrap();
        let g = gaps.constraint_matrix(n).unwrap();
        let mut p_brake = vec![0.0; n];
        p_brake[2] = 1.0;
        p_brake[8] = 0.7;
        let problem = Problem {
            m: Mat::identity(n, n),
            b: Mat::zeros(n, n),
            k,
            g,
            load: LoadHistory {
                p_brake,
                ..LoadHistory::default()
            },
            bsql: BsqlOptions::default(),
            compliance: Vec::new(),
            smooth_width: Vec::new(),
            gaps: gaps.clone(),
            op: Default::default(),
        };
        (problem, gaps)
    }

    fn max_diff(a: &[Real], b: &[Real]) -> Real {
        a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
    }

    /// The block elimination (K factorised once, warm starts from the previous μ) gives the
    /// state and tangents of the dense Newton of `steady_state` at every μ, to round-off.
    #[test]
    fn block_elimination_equals_dense_newton() {
        let (problem, gaps) = model(1.0);
        let opts = SteadyOptions::default();
        let mut fast = SweepSteady::new(&problem);
        for mu in [0.1, 0.4, 0.9, 0.2] {
            let g = gaps
                .clone()
                .with_friction(FrictionLaw::Constant { mu }, gaps.vtol)
                .unwrap();
            let a = fast.solve(&problem, &g, &opts).unwrap();
            let b = at_steady_state(&problem, &g, &opts).unwrap();
            let scale = b.lambda_dot.iter().fold(0.0 as Real, |m, x| m.max(x.abs()));
            assert!(scale > 0.1, "the pads are pressed: {:?}", b.lambda_dot);
            assert!(max_diff(&a.u, &b.u) <= 1e-12 * scale, "mu {mu}: u");
            assert!(max_diff(&a.lambda_dot, &b.lambda_dot) <= 1e-12 * scale);
            let d = &a.d - &b.d;
            assert!(
                d.norm_max() <= 1e-12 * b.d.norm_max().max(1.0),
                "mu {mu}: D"
            );
        }
        assert_eq!((fast.n_fast, fast.n_dense), (4, 0));
    }

    /// K singular (the pads free normal to the rotor, held by the contact alone): the
    /// augmented form K + ρGᵀG is regular, and the block elimination gives the dense Newton's
    /// state at every μ, rigid and with compliant contact rows.
    #[test]
    fn singular_k_held_by_the_contact_uses_the_augmented_form() {
        for compliance in [Vec::new(), vec![1e-3, 2e-3]] {
            let (mut problem, gaps) = model(0.0);
            problem.compliance = compliance.clone();
            let lu = problem.k.partial_piv_lu();
            let pmin = (0..9).fold(Real::INFINITY, |m, i| m.min(lu.U()[(i, i)].abs()));
            assert!(pmin < 1e-12, "K is singular: smallest pivot {pmin}");
            let opts = SteadyOptions::default();
            let mut fast = SweepSteady::new(&problem);
            assert!(fast.rho > 0.0, "the augmented form is used");
            for mu in [0.1, 0.4, 0.9, 0.2] {
                let g = gaps
                    .clone()
                    .with_friction(FrictionLaw::Constant { mu }, gaps.vtol)
                    .unwrap();
                let a = fast.solve(&problem, &g, &opts).unwrap();
                let b = at_steady_state(&problem, &g, &opts).unwrap();
                let scale = b.lambda_dot.iter().fold(0.0 as Real, |m, x| m.max(x.abs()));
                assert!(scale > 0.1, "the pads are pressed: {:?}", b.lambda_dot);
                let uscale = b.u.iter().fold(0.0 as Real, |m, x| m.max(x.abs()));
                assert!(
                    max_diff(&a.u, &b.u) <= 1e-10 * uscale,
                    "mu {mu}, c {compliance:?}: u {:?} vs {:?}",
                    a.u,
                    b.u
                );
                assert!(max_diff(&a.lambda_dot, &b.lambda_dot) <= 1e-10 * scale);
            }
            assert_eq!((fast.n_fast, fast.n_dense), (4, 0), "c {compliance:?}");
        }
    }

    /// K singular along a motion no gap sees (a pad free in y): K + ρGᵀG is singular too, and
    /// the dense Newton runs instead (with its own outcome).
    #[test]
    fn singular_k_unseen_by_the_gaps_falls_back_to_dense_newton() {
        let (mut problem, gaps) = model(1.0);
        for j in 0..problem.k.nrows() {
            problem.k[(1, j)] = 0.0;
            problem.k[(j, 1)] = 0.0;
        }
        let opts = SteadyOptions::default();
        let mut fast = SweepSteady::new(&problem);
        assert_eq!(fast.rho, 0.0);
        let a = fast.solve(&problem, &gaps, &opts);
        let b = at_steady_state(&problem, &gaps, &opts);
        assert_eq!((fast.n_fast, fast.n_dense), (0, 1));
        match (a, b) {
            (Ok(a), Ok(b)) => assert_eq!((a.u, a.lambda_dot), (b.u, b.lambda_dot)),
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            (a, b) => panic!("fast {:?} vs dense {:?}", a.is_ok(), b.is_ok()),
        }
    }
}
