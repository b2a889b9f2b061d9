//! The guard on synthetic evidence.

use super::super::validity::GapEvent;
use super::*;

/// BDF2's numerical damping ratio at N steps per period against the values computed from
/// the characteristic root independently (numpy.roots on the same polynomial): 40 → 9.128e-4,
/// 20 → 6.227e-3, 10 → 3.124e-2; BDF1 against ln(1 + θ²)/(2θ).
#[test]
fn numerical_decay_of_bdf1_and_bdf2() {
    let f = 1000.0;
    for (n, zeta) in [(40.0, 9.128e-4), (20.0, 6.227e-3), (10.0, 3.124e-2)] {
        let h = 1.0 / (n * f);
        let s = numerical_decay(Integrator::Bdf, 2, 0.9, h, f);
        let z = s / (2.0 * std::f64::consts::PI * f);
        assert!((z / zeta - 1.0).abs() < 1e-3, "N = {n}: {z} vs {zeta}");
    }
    let h = 1e-4;
    let th = 2.0 * std::f64::consts::PI * f * h;
    let s1 = numerical_decay(Integrator::Bdf, 1, 0.9, h, f);
    assert!((s1 - (1.0 + th * th).ln() / (2.0 * h)).abs() < 1e-9 * s1);
    // Generalized-α with ρ∞ = 1 is energy conserving: no decay.
    let s = numerical_decay(Integrator::GeneralizedAlpha, 2, 1.0, h, f);
    assert!(s.abs() < 1e-6, "{s}");
    assert!(numerical_decay(Integrator::GeneralizedAlpha, 2, 0.5, h, f) > 0.0);
}

fn base<'a>(c: &'a ContactValidity, st: &'a Status) -> Evidence<'a> {
    Evidence {
        clear_growth: false,
        window: [0.0, 0.02],
        h_max_window: Some(2.5e-6),
        steps_by_order: None,
        frequencies: vec![(FrequencySource::Dominant, 2000.0)],
        contact: c,
        separation: false,
        status: st,
        h_end: Some(2.5e-6),
        integrator: Integrator::Bdf,
        max_order: 2,
        rho_inf: 0.9,
        min_growth_rate_per_s: 100.0,
        min_growth_factor: 2.0,
        limit_cycle: None,
    }
}

/// BDF1 steps after the ramp count in the window's numerical decay (it once said
/// `no_squeal` with the CEA's 5.4 kHz root at +298 /s: the cad brake with pad damping
/// GE = 0.1 took 5 596 of its 14 001 steps at order 1, and the guard weighed BDF2's decay
/// alone, 5 /s at h = 2.5 µs). Reference: BDF1 damps y' = iωy by ½ ln(1 + θ²) a step,
/// θ = ωh (its amplification 1/(1 − iθ)).
#[test]
fn bdf1_steps_after_the_ramp_count_in_the_numerical_decay() {
    let (h, f) = (2.5e-6, 5437.0);
    let th = 2.0 * std::f64::consts::PI * f * h;
    let bdf1 = 0.5 * (1.0 + th * th).ln() / h;
    assert!((bdf1 - 1453.6).abs() < 0.5, "{bdf1}");
    let bdf2 = numerical_decay(Integrator::Bdf, 2, 0.9, h, f);
    assert!(bdf2 > 4.0 && bdf2 < 6.0, "{bdf2}");
    // Only order 2: the mean is BDF2's.
    let only2 = StepsByOrder {
        counts: vec![0, 0, 6000],
        t0: 0.02,
        t1: 0.02 + 6000.0 * h,
    };
    assert!((only2.decay(h, f).unwrap() - bdf2).abs() < 1e-9 * bdf2);
    // 5 596 BDF1 steps among 6 001: the mean is theirs, weighted.
    let mixed = StepsByOrder {
        counts: vec![0, 5596, 405],
        t0: 0.02,
        t1: 0.02 + 6001.0 * h,
    };
    let want = (5596.0 * bdf1 + 405.0 * bdf2) / 6001.0;
    let got = mixed.decay(h, f).unwrap();
    assert!((got - want).abs() < 1e-9 * want, "{got} {want}");
    let c = ContactValidity::default();
    let ok = Status::Reached { t: 0.035 };
    let mut e = base(&c, &ok);
    e.window = [0.02, 0.035];
    e.frequencies = vec![(FrequencySource::CeaUnstable, f)];
    assert_eq!(judge(&e).0, VerdictState::NoSqueal);
    e.steps_by_order = Some(&only2);
    assert_eq!(judge(&e).0, VerdictState::NoSqueal);
    e.steps_by_order = Some(&mixed);
    let (s, r, _) = judge(&e);
    assert!(
        matches!(&s, VerdictState::Unresolved { reasons } if matches!(reasons[0], Unresolved::StepsTooCoarse(_))),
        "{s:?}"
    );
    assert!(
        !r[0].resolved && r[0].numerical_decay_per_s > 1000.0,
        "{r:?}"
    );
    // Generalized-α runs have no order count: the scheme's own decay.
    e.integrator = Integrator::GeneralizedAlpha;
    assert!(judge(&e).1[0].numerical_decay_per_s < 1.0);
}

/// A reached limit cycle (separation on) with the fitted window showing no growth: its
/// amplitude grew ×8 from the first cycle, so `squeal`; ×1.2 is not evidence of
/// self-excitation but never `no_squeal` either.
#[test]
fn a_reached_limit_cycle_is_squeal_never_no_squeal() {
    let c = ContactValidity::default();
    let ok = Status::Reached { t: 0.02 };
    let mut e = base(&c, &ok);
    e.separation = true;
    assert_eq!(judge(&e).0, VerdictState::NoSqueal);
    e.limit_cycle = Some(LimitCycleEvidence {
        peak_normal_velocity: 3.0,
        amplitude_growth: Some(8.0),
    });
    assert_eq!(judge(&e).0, VerdictState::Squeal);
    for growth in [Some(1.2), None] {
        e.limit_cycle = Some(LimitCycleEvidence {
            peak_normal_velocity: 3.0,
            amplitude_growth: growth,
        });
        let s = judge(&e).0;
        assert!(
            matches!(&s, VerdictState::Unresolved { reasons }
                if matches!(reasons[0], Unresolved::LimitCycleWithoutGrowth { .. })),
            "{s:?}"
        );
    }
}

/// Each guard turns a negative into `unresolved` with its reason; a clear growth stays
/// `squeal` whatever else happened.
#[test]
fn guards_decide_the_state() {
    let c = ContactValidity::default();
    let ok = Status::Reached { t: 0.02 };
    assert_eq!(judge(&base(&c, &ok)).0, VerdictState::NoSqueal);
    // 0.02 s window: ln 2 / 0.02 = 34.7 /s ≤ 100.
    assert!((judge(&base(&c, &ok)).2.unwrap() - 2f64.ln() / 0.02).abs() < 1e-12);
    let mut e = base(&c, &ok);
    e.h_max_window = Some(2.1e-3); // the hex20 example's last step: 1 step per period
    let (s, r, _) = judge(&e);
    assert!(
        matches!(&s, VerdictState::Unresolved { reasons } if matches!(reasons[0], Unresolved::StepsTooCoarse(_))),
        "{s:?}"
    );
    assert!(!r[0].resolved && r[0].samples_per_period < 1.0);
    let mut e = base(&c, &ok);
    e.window = [0.0025, 0.006];
    assert!(matches!(judge(&e).0, VerdictState::Unresolved { .. }));
    let event = GapEvent {
        t: 0.0171,
        gap: 0,
        pressure: -3.0,
    };
    let tensile = ContactValidity {
        first_separation: Some(event),
        first_tensile_after_ramp: Some(event),
        ..Default::default()
    };
    let s = judge(&base(&tensile, &ok)).0;
    assert!(format!("{s:?}").contains("ContactTensile"), "{s:?}");
    // Tensile only while the load was applied (the start state under P0 alone): reported,
    // not judged.
    let during_ramp = ContactValidity {
        tensile_at_start: 7,
        first_separation: Some(GapEvent { t: 0.0, ..event }),
        judged_from: 5e-4,
        ..Default::default()
    };
    assert_eq!(judge(&base(&during_ramp, &ok)).0, VerdictState::NoSqueal);
    let mut e = base(&tensile, &ok);
    e.separation = true;
    assert_eq!(judge(&e).0, VerdictState::NoSqueal);
    let collapsed = Status::StepSizeTooSmall {
        t: 0.019,
        h: 1e-14,
        order: 1,
        residual_norm: 1.0,
    };
    let s = judge(&base(&c, &collapsed)).0;
    assert!(matches!(s, VerdictState::Unresolved { .. }), "{s:?}");
    let mut e = base(&tensile, &collapsed);
    e.clear_growth = true;
    assert_eq!(judge(&e).0, VerdictState::Squeal);
    // A run stopped at once because its steps stayed far below the band's (issue 22: the
    // step collapse to ~1e-9 s after a gap turned tensile): `unresolved`, `stopped` with the
    // status's time and step, never a negative.
    let crawl = Status::StepCollapse {
        t: 2.6e-3,
        h: 1e-9,
        order: 1,
        h_collapse: 5e-8,
        steps: 200,
    };
    match judge(&base(&c, &crawl)).0 {
        VerdictState::Unresolved { reasons } => assert!(
            reasons
                .iter()
                .any(|r| matches!(r, Unresolved::Stopped { t, h: Some(h), .. }
                if *t == 2.6e-3 && *h == 1e-9)),
            "{reasons:?}"
        ),
        other => panic!("{other:?}"),
    }
    let text = status_text(&crawl);
    assert!(
        text.contains("200 consecutive steps below 5.000e-8 s") && text.contains("collapse_factor"),
        "{text}"
    );
}
