//! Work–precision of the ways to integrate through contact separation (issue 22, item 1), on
//! Hoffmann's model with one unilateral gap (`tests/common/hoffmann_gap.rs`).
//!
//! From the steady sliding state at μ = 0.6 (above the critical μ) with a 1e-3 kick, the
//! flutter grows (σ ≈ 0.107 /s) until the gap opens (t ≈ 57) and then settles into a limit
//! cycle with an opening and a closing per cycle. The growth phase amplifies every error by
//! e^{σt} whatever the events, so the runs compared here all start at `T_START` = 50 from the
//! reference's state there (just before the first opening, the gap closed) and integrate to
//! `T_END` through ~20 events, sampled on a common grid (each run interpolates its own
//! solution). Errors: the trajectory's, max over the grid and the 3 displacements u of
//! |u − u_ref| / max |u_ref| (u is continuous at the impacts, where v jumps: a max-norm error
//! in v would measure the jump times a shift of the event, not the accuracy); and the limit
//! cycle's, the relative errors of its period (mean
//! of the rotor point's upward zero crossings of v_z) and of its peak |v_z| over the last
//! `T_END − T_LC` time units.
//!
//! Methods:
//! - `events_order1`: events (root location, switch, plastic impact on a rigid row), the BDF
//!   restarted at order 1 with 0.1 × the last step (what squeal did);
//! - `events_taylor2`: the same events, the BDF restarted at order 2 from the Taylor past of
//!   (y, y', y'') (`Bdf::reinit_taylor`), with `f` × the last step;
//! - `smooth`: no event: the compliant gap's smooth unilateral law (`bsql::smooth`) with
//!   p_ε = `w` × P0, integrated by the BDF alone.
//!
//! Two models: the rigid gap (the paper's contact: events only), and a compliant gap with
//! k_n = 50 (events or the smooth law). References: the same model at RTOL 1e-10 (events: both
//! restarts, their difference reported; smooth: per width, and its distance to the events'
//! reference, which is the smoothing's own model error).
//!
//! ```text
//! cargo build --release -p squeal-solver --example separation_work_precision
//! target/release/examples/separation_work_precision [out.json]
//! ```

#[path = "../tests/common/hoffmann_gap.rs"]
mod hoffmann_gap;

use hoffmann_gap::{hoffmann_start, hoffmann_system, HoffmannFriction, P0};
use serde::Serialize;
use squeal_solver::bdf::{Bdf, BdfOptions, Status};
use squeal_solver::bsql::{BsqlSystem, EventRestart, Unilateral, UnilateralOptions};
use squeal_solver::Real;
use std::time::Instant;

const T_START: Real = 50.0;
const T_END: Real = 120.0;
const T_LC: Real = 90.0;
const SAMPLES: usize = 7000;
const KN: Real = 50.0;

#[derive(Debug, Clone, Copy, Serialize)]
#[serde(tag = "method", rename_all = "snake_case")]
enum Method {
    EventsOrder1 { step_fraction: Real },
    EventsTaylor2 { step_fraction: Real },
    Smooth { p_eps_over_p0: Real },
}

#[derive(Debug, Clone, Serialize)]
struct Run {
    model: &'static str,
    #[serde(flatten)]
    method: Method,
    rtol: Real,
    error_max: Real,
    /// Relative errors of the limit cycle's period and peak |v_z| of the rotor point.
    period_error: Real,
    peak_error: Real,
    steps: u64,
    order1_steps: u64,
    order2_steps: u64,
    residual_evals: u64,
    factorisations: u64,
    error_test_failures: u64,
    convergence_failures: u64,
    events: u64,
    openings: u64,
    closings: u64,
    cpu_s: Real,
    repeats: usize,
    status: String,
    #[serde(skip)]
    samples: Vec<Vec<Real>>,
    /// The state at T_START (y, y').
    #[serde(skip)]
    start: (Vec<Real>, Vec<Real>),
}

/// The state at `T_START` of the reference (or the start at t = 0 when `from` is None).
type Start = Option<(Vec<Real>, Vec<Real>)>;

fn run_once(model: &'static str, method: Method, rtol: Real, from: &Start) -> Run {
    let kn = match model {
        "rigid" => None,
        _ => Some(KN),
    };
    let mut sys: BsqlSystem<HoffmannFriction> = hoffmann_system(kn);
    if let Method::Smooth { p_eps_over_p0 } = method {
        sys.set_smooth_unilateral(vec![P0], vec![p_eps_over_p0 * P0 / KN])
            .unwrap();
    }
    let (t0, (y, yp)) = match from {
        Some(s) => (T_START, s.clone()),
        None => (0.0, hoffmann_start(&mut sys)),
    };
    let opts = BdfOptions {
        tolerances: sys.tolerances(rtol, 1e-3 * rtol, rtol, 1e20),
        max_steps: 5_000_000,
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, t0, &y, &yp).unwrap();
    let mut uni = match method {
        Method::Smooth { .. } => None,
        Method::EventsOrder1 { step_fraction } | Method::EventsTaylor2 { step_fraction } => {
            let restart = match method {
                Method::EventsOrder1 { .. } => EventRestart::Order1,
                _ => EventRestart::Taylor2,
            };
            let o = UnilateralOptions {
                restart,
                restart_step_fraction: step_fraction,
                ..Default::default()
            };
            Some(Unilateral::new(&mut sys, vec![P0], None, &y, &yp, o).unwrap())
        }
    };
    let mut samples = Vec::with_capacity(SAMPLES + 1);
    let mut status = Status::Reached { t: 0.0 };
    if from.is_none() {
        // The reference's first leg: to T_START, whose state the others start from.
        status = match &mut uni {
            Some(u) => u.step_to(&mut bdf, &mut sys, T_START, |_, _, _, _| Ok(true)),
            None => bdf.integrate_to(&mut sys, T_START),
        }
        .unwrap();
        assert!(status.is_success(), "{status:?}");
    }
    let start = (bdf.y().to_vec(), bdf.yp().to_vec());
    samples.push(pick(&start.0));
    for i in 1..=SAMPLES {
        let t = T_START + (T_END - T_START) * i as Real / SAMPLES as Real;
        status = match &mut uni {
            Some(u) => u.step_to(&mut bdf, &mut sys, t, |_, _, _, _| Ok(true)),
            None => bdf.integrate_to(&mut sys, t),
        }
        .unwrap();
        if !status.is_success() {
            break;
        }
        samples.push(pick(bdf.y()));
    }
    let st = bdf.stats();
    let ev = uni.as_ref().map(|u| u.stats().clone()).unwrap_or_default();
    if std::env::var("SEP_DEBUG").is_ok() {
        eprintln!(
            "  first separation {:?}, y(T_START) {:?}, last {:?}",
            ev.first_separation_t,
            samples[0],
            samples.last()
        );
    }
    Run {
        model,
        method,
        rtol,
        error_max: Real::NAN,
        period_error: Real::NAN,
        peak_error: Real::NAN,
        steps: st.steps,
        order1_steps: st.order_histogram[1],
        order2_steps: st.order_histogram.get(2).copied().unwrap_or(0),
        residual_evals: st.residual_evals,
        factorisations: st.jacobian_setups,
        error_test_failures: st.error_test_failures,
        convergence_failures: st.convergence_failures,
        events: ev.events,
        openings: ev.openings,
        closings: ev.closings,
        cpu_s: st.cpu_s,
        repeats: 1,
        status: format!("{status:?}"),
        samples,
        start,
    }
}

/// v and u (the multiplier impulse λ is left out).
fn pick(y: &[Real]) -> Vec<Real> {
    [&y[..3], &y[4..7]].concat()
}

/// The displacements of a sample of `pick`.
fn disp(x: &[Real]) -> &[Real] {
    &x[3..]
}

/// Mean CPU over repeats until ≥ 0.3 s in total (at most 20).
fn run(model: &'static str, method: Method, rtol: Real, from: &Start) -> Run {
    let clock = Instant::now();
    let mut r = run_once(model, method, rtol, from);
    let mut total = r.cpu_s;
    let mut n = 1;
    while clock.elapsed().as_secs_f64() < 0.3 && n < 20 {
        total += run_once(model, method, rtol, from).cpu_s;
        n += 1;
    }
    r.cpu_s = total / n as Real;
    r.repeats = n;
    r
}

/// (period, peak |v_z|) of the rotor point over t ≥ T_LC.
fn limit_cycle(samples: &[Vec<Real>]) -> (Real, Real) {
    let dt = (T_END - T_START) / SAMPLES as Real;
    let i0 = ((T_LC - T_START) / dt) as usize;
    let mut ups = Vec::new();
    let mut peak: Real = 0.0;
    for i in i0.max(1)..samples.len() {
        let (a, b) = (samples[i - 1][2], samples[i][2]);
        peak = peak.max(b.abs());
        if a < 0.0 && b >= 0.0 {
            ups.push(T_START + dt * ((i - 1) as Real + a / (a - b)));
        }
    }
    let period = match ups.len() {
        0 | 1 => Real::NAN,
        n => (ups[n - 1] - ups[0]) / (n - 1) as Real,
    };
    (period, peak)
}

fn error(a: &[Vec<Real>], reference: &[Vec<Real>]) -> Real {
    if a.len() != reference.len() {
        return Real::INFINITY;
    }
    let scale = reference
        .iter()
        .flat_map(|x| disp(x))
        .fold(0.0 as Real, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(reference)
        .flat_map(|(x, y)| disp(x).iter().zip(disp(y)).map(|(p, q)| (p - q).abs()))
        .fold(0.0 as Real, Real::max);
    diff / scale
}

#[derive(Serialize)]
struct Report {
    what: &'static str,
    machine: String,
    t_start: Real,
    t_end: Real,
    t_limit_cycle: Real,
    samples: usize,
    normal_stiffness_compliant: Real,
    reference_rtol: Real,
    /// Distance between the references of the two event restarts (rigid, compliant).
    reference_restart_difference: Vec<(String, Real)>,
    /// Distance of each smooth law's reference to the compliant events' reference.
    smooth_model_error: Vec<(Real, Real)>,
    runs: Vec<Run>,
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/bench/separation_hoffmann.json".into());
    // SEP_RTOLS="1e-3,1e-4" and SEP_MODELS="rigid" restrict the study (for a quick look).
    let rtols: Vec<Real> = std::env::var("SEP_RTOLS")
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or_else(|_| vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]);
    let models: Vec<&'static str> = match std::env::var("SEP_MODELS").as_deref() {
        Ok("rigid") => vec!["rigid"],
        Ok("compliant") => vec!["compliant"],
        _ => vec!["rigid", "compliant"],
    };
    let ref_rtol: Real = std::env::var("SEP_REF_RTOL").map_or(1e-10, |s| s.parse().unwrap());
    let mut runs = Vec::new();
    let mut ref_diff = Vec::new();
    let mut smooth_err = Vec::new();
    let widths = [0.1, 0.02];
    for model in models {
        let r1 = run_once(
            model,
            Method::EventsOrder1 { step_fraction: 0.1 },
            ref_rtol,
            &None,
        );
        let r2 = run_once(
            model,
            Method::EventsTaylor2 { step_fraction: 0.5 },
            ref_rtol,
            &None,
        );
        let d = error(&r2.samples, &r1.samples);
        eprintln!(
            "{model}: reference events {} / {} steps, restarts differ by {d:.3e}",
            r1.steps, r2.steps
        );
        ref_diff.push((model.to_string(), d));
        let from = Some(r1.start.clone());
        let mut methods = vec![
            Method::EventsOrder1 { step_fraction: 0.1 },
            Method::EventsTaylor2 { step_fraction: 0.1 },
            Method::EventsTaylor2 { step_fraction: 0.5 },
            Method::EventsTaylor2 { step_fraction: 1.0 },
        ];
        if model == "compliant" {
            methods.extend(widths.map(|w| Method::Smooth { p_eps_over_p0: w }));
        }
        for m in methods {
            let (reference, from) = match m {
                Method::Smooth { p_eps_over_p0 } => {
                    // Its own model's reference, from its own state at T_START.
                    let rs = run_once(model, m, ref_rtol, &None);
                    let e = error(&rs.samples, &r1.samples);
                    eprintln!("smooth p_eps {p_eps_over_p0} P0: model error {e:.3e}");
                    smooth_err.push((p_eps_over_p0, e));
                    (rs.samples, Some(rs.start))
                }
                _ => (r1.samples.clone(), from.clone()),
            };
            let (period_ref, peak_ref) = limit_cycle(&reference);
            for &rtol in &rtols {
                eprintln!("{model} {m:?} rtol {rtol:e} ...");
                let mut r = run(model, m, rtol, &from);
                r.error_max = error(&r.samples, &reference);
                let (period, peak) = limit_cycle(&r.samples);
                r.period_error = (period - period_ref).abs() / period_ref;
                r.peak_error = (peak - peak_ref).abs() / peak_ref;
                eprintln!(
                    "{model:9} {m:?} rtol {rtol:.0e}: error {:.3e}, period {:.2e}, peak {:.2e}, \
                     steps {} (order 1: {}), events {}, cpu {:.3e} s",
                    r.error_max,
                    r.period_error,
                    r.peak_error,
                    r.steps,
                    r.order1_steps,
                    r.events,
                    r.cpu_s
                );
                runs.push(r);
            }
        }
    }
    let report = Report {
        what: "Hoffmann's model with separation: error vs CPU per way through the events",
        machine: "2 cores shared with other agents' builds and tests".into(),
        t_start: T_START,
        t_end: T_END,
        t_limit_cycle: T_LC,
        samples: SAMPLES,
        normal_stiffness_compliant: KN,
        reference_rtol: ref_rtol,
        reference_restart_difference: ref_diff,
        smooth_model_error: smooth_err,
        runs,
    };
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir).unwrap();
    }
    std::fs::write(&out, serde_json::to_string_pretty(&report).unwrap()).unwrap();
    eprintln!("wrote {out}");
}
