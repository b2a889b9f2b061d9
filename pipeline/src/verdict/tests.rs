//! [`decide`] on synthetic records: the whole verdict (roots, envelope, limit cycle, guard,
//! decision) without a run. Each signal's reference is its closed form: v(t) = A(t) sin(2πft)
//! with A(t) = e^{σt} (a growing or damped exponential), a linear chirp, or a logistic growth
//! that saturates at a stated amplitude.

use super::limit_cycle::FaceSeries;
use super::roots::PencilOptions;
use super::*;
use crate::verdict::guard::{StepsByOrder, Unresolved, VerdictState};
use crate::verdict::validity::{ContactValidity, GapEvent};
use squeal_solver::bdf::Status;
use squeal_solver::Real;
use std::f64::consts::PI;

/// Sampling step (also the "accepted step" of the record): 80 steps per period at 5 kHz.
const H: Real = 2.5e-6;
/// End of the record, s.
const T_END: Real = 0.04;
/// End of the load ramp: the window starts here.
const T_RAMP: Real = 0.002;

/// A one-channel record of v(t) = amp(t) sin(phase(t)), velocity and acceleration.
fn record(amp: impl Fn(Real) -> Real, phase: impl Fn(Real) -> Real) -> Series {
    let mut s = Series::new(vec!["rotor_normal".into()]);
    let n = (T_END / H).round() as usize;
    for i in 0..=n {
        let t = i as Real * H;
        s.t.push(t);
        s.v[0].push(amp(t) * phase(t).sin());
        s.a[0].push(0.0);
    }
    s
}

/// The rotor face's record of the same signal (one gap): peak |v| and v² per step.
fn face(s: &Series) -> FaceSeries {
    FaceSeries {
        t: s.t.clone(),
        peak: s.v[0].iter().map(|v| v.abs()).collect(),
        mean_square: s.v[0].iter().map(|v| v * v).collect(),
        open: Vec::new(),
    }
}

fn contact(tensile_at: Option<Real>) -> ContactValidity {
    let event = tensile_at.map(|t| GapEvent {
        t,
        gap: 3,
        pressure: -1.0e3,
    });
    ContactValidity {
        n_gaps: 8,
        judged_from: T_RAMP,
        first_separation: event,
        first_tensile_after_ramp: event,
        min_pressure: event,
        tensile_gap_steps: u64::from(event.is_some()),
        steps: (T_END / H) as u64,
        ..Default::default()
    }
}

/// Every step after the ramp at BDF order 2.
fn orders() -> StepsByOrder {
    StepsByOrder {
        counts: vec![0, 0, ((T_END - T_RAMP) / H) as u64],
        t0: T_RAMP,
        t1: T_END,
    }
}

fn settings(separation: bool) -> Settings {
    Settings {
        t_after: T_RAMP,
        stall_h: None,
        band_hz: Some(10_000.0),
        pencil: PencilOptions::default(),
        separation,
        integrator: Integrator::Bdf,
        max_order: 2,
        rho_inf: 1.0,
        // The scene's `[output]` defaults.
        growth_threshold_per_s: 0.0,
        min_growth_factor: 2.0,
        min_growth_rate_per_s: 100.0,
    }
}

fn run(series: &Series, face: Option<&FaceSeries>, c: &ContactValidity, st: &Status) -> Decision {
    let steps = orders();
    let r = Record {
        response: series,
        face,
        contact: c,
        steps_by_order: Some(&steps),
        status: st,
        h_end: Some(H),
        first_opening: None,
    };
    decide(&r, &settings(face.is_some()), None)
}

fn reached() -> Status {
    Status::Reached { t: T_END }
}

fn exponential(sigma: Real, f: Real) -> Series {
    record(move |t| 1e-4 * (sigma * t).exp(), move |t| 2.0 * PI * f * t)
}

#[test]
fn a_growing_exponential_is_squeal_at_its_rate_and_frequency() {
    let (sigma, f) = (200.0, 5000.0);
    let d = run(&exponential(sigma, f), None, &contact(None), &reached());
    let v = &d.verdict;
    assert_eq!(v.state, VerdictState::Squeal, "{v:?}");
    assert_eq!(v.evidence, Some(SquealEvidence::Growth));
    let g = v.growth_rate_per_s.unwrap();
    let fd = v.dominant_frequency_hz.unwrap();
    assert!(
        (g - sigma).abs() < 1e-2 * sigma,
        "σ = {g} (closed form {sigma})"
    );
    assert!((fd - f).abs() < 1e-4 * f, "f = {fd} (closed form {f})");
}

#[test]
fn a_damped_exponential_is_no_squeal_when_the_run_could_have_seen_growth() {
    let (sigma, f) = (-300.0, 5000.0);
    let d = run(&exponential(sigma, f), None, &contact(None), &reached());
    let v = &d.verdict;
    assert_eq!(v.state, VerdictState::NoSqueal, "{v:?}");
    let g = v.growth_rate_per_s.unwrap();
    assert!(
        (g - sigma).abs() < 1e-2 * sigma.abs(),
        "σ = {g} (closed form {sigma})"
    );
    // The window (38 ms) shows a growth factor 2 down to ln 2 / 0.038 = 18 /s.
    let detectable = v.detectable_growth_per_s.unwrap();
    assert!(
        (detectable - 2f64.ln() / (T_END - T_RAMP)).abs() < 1.0,
        "{detectable}"
    );
}

#[test]
fn the_same_decay_on_a_stopped_run_is_unresolved_not_no_squeal() {
    let st = Status::StepCollapse {
        t: 0.01,
        h: 1e-9,
        order: 1,
        h_collapse: 5e-8,
        steps: 200,
    };
    let d = run(&exponential(-300.0, 5000.0), None, &contact(None), &st);
    match &d.verdict.state {
        VerdictState::Unresolved { reasons } => assert!(
            reasons
                .iter()
                .any(|r| matches!(r, Unresolved::Stopped { .. })),
            "{reasons:?}"
        ),
        s => panic!("a stopped run judged {s:?}"),
    }
}

#[test]
fn a_constant_amplitude_chirp_is_not_squeal_and_its_frequency_is_in_the_sweep() {
    // f(t) = f0 + k t: 4.5 kHz to 5.5 kHz over the record, constant amplitude.
    let (f0, f1) = (4500.0, 5500.0);
    let k = (f1 - f0) / T_END;
    let s = record(|_| 1e-3, move |t| 2.0 * PI * (f0 * t + 0.5 * k * t * t));
    let d = run(&s, None, &contact(None), &reached());
    let v = &d.verdict;
    // Before the fit residual decided, this chirp was judged squeal at σ = 606 /s (the
    // pencil modelled the sweep by roots growing in turn, relative residual 0.54).
    match &v.state {
        VerdictState::Unresolved { reasons } => assert!(
            reasons.iter().any(|r| matches!(r, Unresolved::PoorFit { relative_residual, .. } if *relative_residual > 0.2)),
            "{reasons:?}"
        ),
        s => panic!("a chirp judged {s:?}"),
    }
    let fd = v.dominant_frequency_hz.unwrap();
    assert!(
        (f0..=f1).contains(&fd),
        "dominant {fd} Hz outside the sweep"
    );
}

#[test]
fn a_growth_after_the_contact_went_tensile_does_not_count() {
    // Damped until 20 ms, then growing fast: the contact went tensile at 20 ms, so the
    // growth is judged before it and the run is not squeal.
    let t_x: Real = 0.02;
    let amp = move |t: Real| match t < t_x {
        true => 1e-3 * (-150.0 * t).exp(),
        false => 1e-3 * (-150.0 * t_x).exp() * (800.0 * (t - t_x)).exp(),
    };
    let s = record(amp, |t| 2.0 * PI * 5000.0 * t);
    let d = run(&s, None, &contact(Some(t_x)), &reached());
    let v = &d.verdict;
    assert!(!v.state.is_squeal(), "{v:?}");
    assert_eq!(v.valid_until, Some(t_x));
    assert!(
        v.window[1] <= t_x + H,
        "window {:?} past the tensile event",
        v.window
    );
    assert!(
        v.growth_rate_per_s.unwrap() < 0.0,
        "{:?}",
        v.growth_rate_per_s
    );
    // Without the event the same record is squeal.
    assert!(run(&s, None, &contact(None), &reached())
        .verdict
        .state
        .is_squeal());
}

#[test]
fn a_saturating_growth_is_a_limit_cycle_with_the_growth_before_it() {
    // Logistic amplitude: grows at σ = 400 /s from 1e-5 and saturates at 1e-2 m/s
    // (A(t) = A_max / (1 + (A_max/A_0 − 1) e^{−σt})), at 5 kHz, with separation on.
    let (sigma, a0, a_max, f): (Real, Real, Real, Real) = (400.0, 1e-5, 1e-2, 5000.0);
    let amp = move |t: Real| a_max / (1.0 + (a_max / a0 - 1.0) * (-sigma * t).exp());
    let s = record(amp, move |t| 2.0 * PI * f * t);
    let fs = face(&s);
    let d = run(&s, Some(&fs), &contact(None), &reached());
    let v = &d.verdict;
    assert!(v.state.is_squeal(), "{v:?}");
    let lc = d.limit_cycle.as_ref().expect("a limit cycle");
    assert!(lc.reached, "{lc:?}");
    assert!(
        (lc.peak_normal_velocity - a_max).abs() < 1e-2 * a_max,
        "limit-cycle peak {} (closed form {a_max})",
        lc.peak_normal_velocity
    );
    let sat = v.saturation.expect("where it saturated");
    // The growth phase fitted before saturation: its largest root is the logistic's early
    // growth (σ = 406.7 /s and 4999.5 Hz when written). The deciding root (the fastest-growing
    // significant one) is a side band of the bend into saturation (774 /s at 5086 Hz, 2 % of
    // the amplitude): it errs towards squeal, never away from it.
    let main = &v.roots[0];
    assert!(
        (main.growth_rate_per_s - sigma).abs() < 0.05 * sigma,
        "{main:?} (σ {sigma})"
    );
    assert!((main.frequency_hz - f).abs() < 1e-3 * f, "{main:?}");
    assert!(v.growth_rate_per_s.unwrap() >= main.growth_rate_per_s);
    assert!(sat.t > T_RAMP);
    assert!(v.window[1] <= sat.growth_end + H);
}

/// A response that grows at σ from a0 while the load is applied, is held at `a_sat` by the
/// contact's opening (a gap open wherever |v| > 0.8 a_sat) from t_s = ln(a_sat/a0)/σ, and
/// after t_s follows `after(t − t_s)` × a_sat, at f; four gaps carry no load at the very start
/// (t < 50 µs), as at the start of a ramp from zero. The load ramp ends at 15 ms, after t_s.
fn held_in_ramp(sigma: Real, after: impl Fn(Real) -> Real) -> (Series, FaceSeries, Settings) {
    let (a0, a_sat, f): (Real, Real, Real) = (1e-5, 1e-2, 5000.0);
    let t_s = (a_sat / a0).ln() / sigma;
    let amp = move |t: Real| match t < t_s {
        true => a0 * (sigma * t).exp(),
        false => a_sat * after(t - t_s),
    };
    let s = record(amp, move |t| 2.0 * PI * f * t);
    let mut fs = face(&s);
    fs.open =
        s.t.iter()
            .zip(&s.v[0])
            .map(|(&t, &v)| match (t < 5e-5, v.abs() > 0.8 * a_sat) {
                (true, _) => 4,
                (false, true) => 3,
                (false, false) => 0,
            })
            .collect();
    let settings = Settings {
        t_after: 0.015,
        ..settings(true)
    };
    (s, fs, settings)
}

fn decide_held(s: &Series, fs: &FaceSeries, settings: &Settings) -> Decision {
    let steps = orders();
    let r = Record {
        response: s,
        face: Some(fs),
        contact: &contact(None),
        steps_by_order: Some(&steps),
        status: &reached(),
        h_end: Some(H),
        first_opening: None,
    };
    decide(&r, settings, None)
}

#[test]
fn a_growth_held_by_the_contact_opening_during_the_ramp_is_squeal_from_its_growth() {
    // Grows at 1000 /s to 1e-2 m/s by 6.9 ms, then held there (a 30 % beat at 200 Hz, no
    // decay) for the 25 ms after the ramp.
    let sigma = 1000.0;
    let (s, fs, st) = held_in_ramp(sigma, |t| 1.0 + 0.3 * (2.0 * PI * 200.0 * t).sin());
    let d = decide_held(&s, &fs, &st);
    let v = &d.verdict;
    assert_eq!(v.state, VerdictState::Squeal, "{v:?}");
    assert_eq!(v.evidence, Some(SquealEvidence::GrowthDuringRamp), "{v:?}");
    let rs = v.ramp_saturation.expect("held during the ramp");
    // The first opening: the first crest above 0.8 a_sat, within a period of
    // t_s − ln(1/0.8)/σ = 6.685 ms; the opening at the start (no load yet) is not counted.
    let t_s = (1e-2f64 / 1e-5).ln() / sigma;
    let expect = t_s - (1.0f64 / 0.8).ln() / sigma;
    assert!(
        (rs.first_opening - expect).abs() <= 1.0 / 5000.0,
        "{rs:?} (expected {expect})"
    );
    // Sustained: 25 ms / 0.2 ms = 125 cycles after the ramp (124 whole ones in the record),
    // a beat without trend, a gap open in the cycles whose amplitude 1 + 0.3 sin is above
    // 0.8: all but a fraction (π − 2 asin(2/3))/(2π) = 0.268 of the beat.
    let c = rs.after_ramp;
    assert!((124..=125).contains(&c.cycles), "{c:?}");
    assert!(c.envelope_trend_per_s.abs() < 5.0, "{c:?}");
    let open = c.cycles_with_open_gaps as Real / c.cycles as Real;
    assert!((open - 0.732).abs() < 0.05, "{c:?}");
    // The roots and the window are those of the growth (closed form σ, f).
    let g = v.growth_rate_per_s.unwrap();
    assert!(
        (g - sigma).abs() < 0.02 * sigma,
        "σ = {g} (closed form {sigma})"
    );
    let f = v.dominant_frequency_hz.unwrap();
    assert!((f - 5000.0).abs() < 1e-3 * 5000.0, "f = {f}");
    assert_eq!(v.window[0], 0.0);
    assert!(v.window[1] <= rs.first_opening, "{:?}", v.window);
}

#[test]
fn a_growth_during_the_ramp_that_decays_after_it_is_not_squeal() {
    // The same growth, then a decay at 400 /s after t_s: the gaps stop opening after the
    // ramp and the per-cycle peaks fall at 400 /s, faster than the 100 /s that matters.
    let (s, fs, st) = held_in_ramp(1000.0, |t| (-400.0 * t).exp());
    let d = decide_held(&s, &fs, &st);
    let v = &d.verdict;
    assert!(v.ramp_saturation.is_none(), "{v:?}");
    assert!(!v.state.is_squeal(), "{v:?}");
}

#[test]
fn a_sustained_oscillation_without_open_gaps_after_the_ramp_is_not_held_by_separation() {
    // Grows during the ramp, then stays at 0.7 a_sat: no gap opens after the ramp (the
    // amplitude is not the contact's), so the growth during the ramp does not decide.
    let (s, fs, st) = held_in_ramp(1000.0, |t| if t < 1e-3 { 1.0 } else { 0.7 });
    let d = decide_held(&s, &fs, &st);
    let v = &d.verdict;
    assert!(v.ramp_saturation.is_none(), "{v:?}");
    assert_ne!(v.evidence, Some(SquealEvidence::GrowthDuringRamp));
}
