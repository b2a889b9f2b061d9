//! The critical μ of a friction sweep against an independent reference: a bisection on the
//! largest Re p of the dense exact CEA (`method = "exact"`), on a small random constrained
//! model (`common::random`). The projected sweep's critical μ is moved to the crossing of the
//! exact root (`refine_critical`), the exact sweep's is located by regula falsi; both must
//! equal the dense bisection to the sweep's `bisection_tol`.

use squeal_solver::cea::{
    complex_eigen, sweep, CeaError, CeaMethod, CeaOptions, Critical, ProjectionOptions, Sweep,
    SweepOptions,
};

mod common;
use common::random::RandomConstrained;

/// The test model: 40 DOFs, 4 constraints.
fn model() -> RandomConstrained {
    RandomConstrained::new(40, 4, 7)
}

/// Every root computed, unstable when Re p > 0 (no threshold: the reference is Re p = 0).
fn exact_opts() -> CeaOptions {
    CeaOptions {
        unstable_tol: 0.0,
        method: CeaMethod::Exact,
        ..CeaOptions::default()
    }
}

/// Largest Re p of the dense exact roots with frequency ≤ `band` Hz at μ.
fn dense_max_re(m: &RandomConstrained, mu: f64, band: f64) -> f64 {
    let r = complex_eigen(&m.at(mu), &exact_opts()).unwrap();
    r.modes
        .iter()
        .filter(|x| x.frequency_hz <= band)
        .map(|x| x.real_part)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The lowest μ in `mus` at which an in-band dense root turns unstable: the first sign change
/// of [`dense_max_re`] over the grid, then plain bisection to 1e-12.
fn dense_bisection(m: &RandomConstrained, mus: &[f64], band: f64) -> f64 {
    let k = mus
        .windows(2)
        .position(|w| dense_max_re(m, w[0], band) <= 0.0 && dense_max_re(m, w[1], band) > 0.0)
        .expect("an in-band onset on the grid");
    let (mut lo, mut hi) = (mus[k], mus[k + 1]);
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if dense_max_re(m, mid, band) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The sweep's lowest onset with frequency ≤ `band`.
fn lowest_in_band(s: &Sweep, band: f64) -> &Critical {
    s.tracks
        .iter()
        .filter_map(|t| t.critical.as_ref())
        .filter(|c| c.frequency_hz <= band)
        .min_by(|a, b| a.mu.total_cmp(&b.mu))
        .expect("an in-band onset in the sweep")
}

#[test]
fn critical_mu_equals_dense_exact_bisection() {
    let m = model();
    let mus: Vec<f64> = (0..11).map(|i| 0.1 * i as f64).collect();
    // Band: the lowest quarter of the spectrum at μ = 0.
    let r0 = complex_eigen(&m.at(0.0), &exact_opts()).unwrap();
    let band = 0.25 * r0.modes.last().unwrap().frequency_hz;
    let reference = dense_bisection(&m, &mus, band);
    let build = |mu: f64| Ok::<_, CeaError>(m.at(mu));
    let tol = SweepOptions::default().bisection_tol;

    // The exact sweep: regula falsi on the dense roots.
    let exact = sweep(
        build,
        &mus,
        &SweepOptions {
            cea: exact_opts(),
            ..SweepOptions::default()
        },
    )
    .unwrap();
    let c = lowest_in_band(&exact, band);
    eprintln!(
        "dense bisection {reference:.12}; exact sweep {:.12} ({} solves)",
        c.mu, c.locate_solves
    );
    assert!(c.exact.is_none());
    assert!((c.mu - reference).abs() <= tol, "{} vs {reference}", c.mu);

    // The projected sweep on a truncated basis: its own crossing is off by the projection
    // error; the exact crossing is the reference's.
    let projection = ProjectionOptions {
        frequency_max_hz: Some(band),
        cutoff_factor: 1.5,
        basis_mu: Some(0.0),
        ..ProjectionOptions::default()
    };
    // The onset is a coalescence: the exact Re p is flat, then grows like √(μ − μc), where
    // regula falsi degrades to its bisection steps (measured: 17 evaluations from 0.019 away, 4e-9 from the reference).
    let opts = SweepOptions {
        cea: CeaOptions {
            method: CeaMethod::Projection,
            projection,
            ..exact_opts()
        },
        max_exact_critical: 30,
        // The friction-free basis alone, so that the exact search starts from a projected
        // crossing well off the exact one (the enriched basis: the last test).
        enrich: false,
        ..SweepOptions::default()
    };
    let s = sweep(build, &mus, &opts).unwrap();
    assert!(s.stats.n_basis < 36);
    let c = lowest_in_band(&s, band);
    let x = c.exact.as_ref().expect("refined exactly");
    eprintln!(
        "projected sweep: located {:.12} ({} solves), exact {:.12} ({} exact solves, {} shifts, \
         root error {:.2e}); stats: {} exact, {} failed, max |dmu| {:?}",
        c.mu_located,
        c.locate_solves,
        c.mu,
        x.n_solves,
        x.n_shifts,
        x.max_rel_root_error,
        s.stats.n_critical_exact,
        s.stats.n_critical_exact_failed,
        s.stats.max_critical_mu_change
    );
    // The exact crossing is bracketed to `exact_critical_tol` (1e-5) and interpolated there.
    let tol_exact = opts.exact_critical_tol;
    assert!(x.converged);
    let [lo, hi] = x.bracket.unwrap();
    assert!(
        lo < reference && reference <= hi && hi - lo <= tol_exact,
        "{lo} {hi}"
    );
    assert!(
        (c.mu - reference).abs() <= tol_exact,
        "{} vs {reference}",
        c.mu
    );
    // The projection error moved the projected crossing by much more than the tolerance.
    assert!((c.mu_located - reference).abs() > 100.0 * tol_exact);
    assert_eq!(s.stats.n_critical_exact_solves, {
        let t = s.tracks.iter().filter_map(|t| t.critical.as_ref());
        t.filter_map(|c| c.exact.as_ref())
            .map(|x| x.n_solves)
            .sum::<usize>()
    });
    assert!(s.stats.max_rel_critical_root_error.unwrap() > 0.0);
}

/// `max_exact_onsets` spends the exact evaluations on the lowest in-band onsets: with 1, the
/// lowest one is refined exactly as without the limit, the others keep their projected
/// crossing and are counted as skipped; with 0 none is refined.
#[test]
fn the_exact_onset_budget_goes_to_the_lowest_onsets() {
    let m = model();
    let mus: Vec<f64> = (0..11).map(|i| 0.1 * i as f64).collect();
    let r0 = complex_eigen(&m.at(0.0), &exact_opts()).unwrap();
    // The whole spectrum is the band: several onsets to refine.
    let band = r0.modes.last().unwrap().frequency_hz;
    let opts = |max_exact_onsets: usize| SweepOptions {
        cea: CeaOptions {
            method: CeaMethod::Projection,
            projection: ProjectionOptions {
                frequency_max_hz: Some(band),
                cutoff_factor: 1.0,
                basis_mu: Some(0.0),
                ..ProjectionOptions::default()
            },
            ..exact_opts()
        },
        max_exact_critical: 30,
        max_exact_onsets,
        ..SweepOptions::default()
    };
    let build = |mu: f64| Ok::<_, CeaError>(m.at(mu));
    let all = sweep(build, &mus, &opts(usize::MAX)).unwrap();
    let attempted = all.stats.n_critical_exact + all.stats.n_critical_exact_failed;
    eprintln!(
        "no limit: {} exact, {} failed, {} skipped",
        all.stats.n_critical_exact,
        all.stats.n_critical_exact_failed,
        all.stats.n_critical_exact_skipped
    );
    assert!(
        attempted >= 2,
        "the test needs two in-band onsets: {attempted}"
    );
    assert_eq!(all.stats.n_critical_exact_skipped, 0);
    // The onsets in the order the sweep meets them (step, then track).
    let first_onset = |s: &Sweep| {
        s.tracks
            .iter()
            .filter_map(|t| t.critical.as_ref().map(|c| (t.id, c)))
            .filter(|(_, c)| c.exact.is_some())
            .min_by(|a, b| a.1.step.cmp(&b.1.step).then(a.0.cmp(&b.0)))
            .map(|(id, c)| (id, c.clone()))
    };

    let one = sweep(build, &mus, &opts(1)).unwrap();
    assert_eq!(
        one.stats.n_critical_exact + one.stats.n_critical_exact_failed,
        1
    );
    assert_eq!(one.stats.n_critical_exact_skipped, attempted - 1);
    let (id1, c1) = first_onset(&one).expect("one onset refined");
    let (id_all, c_all) = first_onset(&all).unwrap();
    assert_eq!(id1, id_all);
    assert_eq!(
        c1.mu, c_all.mu,
        "the same exact crossing as without the limit"
    );
    // No in-band onset met before it, and the refined one is the only one with `exact`.
    for t in &one.tracks {
        if let Some(c) = &t.critical {
            if t.id != id1 {
                assert!(
                    c.exact.is_none(),
                    "track {} refined beyond the budget",
                    t.id
                );
                assert_eq!(c.mu, c.mu_located);
            }
        }
    }

    let none = sweep(build, &mus, &opts(0)).unwrap();
    assert_eq!(
        none.stats.n_critical_exact + none.stats.n_critical_exact_failed,
        0
    );
    assert_eq!(none.stats.n_critical_exact_skipped, attempted);
}

/// The basis enrichment ([`SweepOptions::enrich`]): on a model whose friction-free modes are a
/// poor basis at high μ, the enriched basis' roots match the dense exact roots at every step
/// (the least stable in-band ones, to the enrichment's tolerance), the measured
/// `basis_error` is honest (the dense comparison at its μ is no larger), and the projected
/// crossing moves onto the exact one.
#[test]
fn enriched_basis_keeps_the_projection_exact_across_the_sweep() {
    let m = RandomConstrained::new(120, 8, 11);
    let mus: Vec<f64> = (0..11).map(|i| 0.1 * i as f64).collect();
    let r0 = complex_eigen(&m.at(0.0), &exact_opts()).unwrap();
    let band = 0.25 * r0.modes.last().unwrap().frequency_hz;
    let opts = |enrich: bool| SweepOptions {
        cea: CeaOptions {
            method: CeaMethod::Projection,
            projection: ProjectionOptions {
                frequency_max_hz: Some(band),
                cutoff_factor: 1.5,
                basis_mu: Some(0.0),
                ..ProjectionOptions::default()
            },
            ..exact_opts()
        },
        enrich,
        max_exact_critical: 30,
        ..SweepOptions::default()
    };
    let build = |mu: f64| Ok::<_, CeaError>(m.at(mu));
    let plain = sweep(build, &mus, &opts(false)).unwrap();
    let rich = sweep(build, &mus, &opts(true)).unwrap();
    let st = &rich.stats;
    let tol = opts(true).enrich_tol;
    let k = opts(true).enrich_roots;
    eprintln!(
        "basis {} ({} enriched of {} reduced), tests: {:?}",
        st.n_basis,
        st.n_basis_enriched,
        st.n_reduced,
        st.enrichment
            .iter()
            .map(|p| (p.mu, p.max_rel_error, p.n_added))
            .collect::<Vec<_>>()
    );
    assert!(plain.stats.enrichment.is_empty() && plain.stats.basis_error.is_none());
    // The friction-free basis fails the first test; the enriched one passes at a μ it was not
    // enriched at, with a basis still truncated.
    assert!(st.enrichment[0].max_rel_error > tol);
    assert!(st.n_basis_enriched > 0 && st.n_basis < st.n_reduced);
    assert_eq!(st.basis_converged, Some(true));
    let last = st.enrichment.last().unwrap();
    assert_eq!(last.n_added, 0);
    assert!(st.basis_error.unwrap() <= tol);
    assert!(st.enrichment[..st.enrichment.len() - 1]
        .iter()
        .all(|p| p.mu != last.mu));
    // Every step: each of the k in-band projected roots with the largest Re p against the
    // nearest dense exact root.
    let worst = |s: &Sweep| {
        let mut worst: f64 = 0.0;
        for step in &s.steps {
            let exact = complex_eigen(&m.at(step.mu), &exact_opts()).unwrap();
            let mut inb: Vec<_> = step
                .modes
                .iter()
                .filter(|x| x.frequency_hz <= band)
                .collect();
            inb.sort_by(|a, b| b.real_part.total_cmp(&a.real_part));
            for x in inb.iter().take(k) {
                let d = exact
                    .modes
                    .iter()
                    .map(|e| (e.eigenvalue - x.eigenvalue).norm() / e.eigenvalue.norm())
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
        worst
    };
    let (w_plain, w_rich) = (worst(&plain), worst(&rich));
    eprintln!(
        "worst relative root error over the steps: plain {w_plain:.3e}, enriched {w_rich:.3e}"
    );
    assert!(
        w_plain > 10.0 * tol,
        "the test needs a poor friction-free basis"
    );
    assert!(w_rich <= 10.0 * tol, "{w_rich}");
    // The projected crossing (before the exact search) is now the exact one's neighbour.
    let reference = dense_bisection(&m, &mus, band);
    let (cp, cr) = (lowest_in_band(&plain, band), lowest_in_band(&rich, band));
    eprintln!(
        "reference {reference:.9}: located plain {:.9}, enriched {:.9}; exact {:.9} ({} solves) vs {:.9} ({} solves)",
        cp.mu_located,
        cr.mu_located,
        cp.mu,
        cp.exact.as_ref().map_or(0, |x| x.n_solves),
        cr.mu,
        cr.exact.as_ref().map_or(0, |x| x.n_solves)
    );
    assert!((cr.mu_located - reference).abs() < 0.1 * (cp.mu_located - reference).abs());
    let x = cr.exact.as_ref().expect("refined exactly");
    assert!(x.converged);
    assert!((cr.mu - reference).abs() <= opts(true).exact_critical_tol);
    // The trials after the first followed its exact roots with its LU (residual inverse
    // iteration): one factorisation for the whole search, and the crossing above is the
    // dense bisection's all the same.
    eprintln!(
        "enriched exact search: {} evaluations, {} followed ({} iterations, largest backward \
         error {:?}), {} shifts",
        x.n_solves, x.n_followed, x.n_follow_iterations, x.max_followed_residual, x.n_shifts
    );
    assert_eq!(x.n_followed, x.n_solves - 1);
    assert_eq!(x.n_shifts, 1);
    // The iteration stops at the refinement's tolerance (refine.tol = 1e-10; measured 2.9e-12).
    assert!(x.max_followed_residual.unwrap() <= opts(true).cea.projection.refine.tol);
    assert_eq!(
        rich.stats.n_critical_exact_followed,
        rich.tracks
            .iter()
            .filter_map(|t| t.critical.as_ref()?.exact.as_ref())
            .map(|x| x.n_followed)
            .sum::<usize>()
    );
}
