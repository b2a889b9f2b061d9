//! Limit cycles by harmonic balance (`squeal_solver::hb`) against an independent time
//! integration: Hoffmann's model on a compliant unilateral contact, whose flutter saturates by
//! the gap opening once per cycle.

mod common;

use common::hoffmann::{compliant_band, hoffmann_rk4};
use faer::Mat;
use squeal_solver::bsql::LoadHistory;
use squeal_solver::hb::{limit_cycle, HbOptions, LimitCycleStatus};
use squeal_solver::Real;

/// HB + AFT from the Hopf point to μ = 0.6, harmonics doubled until converged: the cycle's
/// frequency and the peak of the rotor point's normal velocity (the "face") agree with an
/// explicit RK4 integration run into the same cycle (the reference of
/// `condense.rs`, itself checked against scipy's LSODA) within 1 %; the cycle is stable.
#[test]
fn hoffmann_with_separation_limit_cycle_matches_the_time_integration() {
    let load = LoadHistory {
        p_brake: vec![0.02, 0.0, 0.0],
        t_load: 2.0,
        ..Default::default()
    };
    let c = 0.1;
    // The gap's relative coordinates as the contact I/O (3 outputs: the relative tangential
    // velocity, the rotor point's normal velocity, the normal force).
    let (mut band, u0) = compliant_band(c, true, true, &load);
    assert_eq!(band.n_velocities() + band.n_rows(), 3);
    let root = *band
        .model()
        .roots
        .iter()
        .find(|p| p.re > 0.0)
        .expect("an unstable root");
    // The face: the rotor point's normal velocity, the second velocity output.
    let face = Mat::from_fn(1, 2, |_, j| if j == 1 { 1.0 } else { 0.0 });
    let opts = HbOptions::default();
    let lc = limit_cycle(&mut band, 10.0, root, &face, &opts).unwrap();
    println!(
        "status {:?}; Hopf s {:?} at {:?} Hz; f {:.6} Hz, peak {:.6}, rms {:.6}; H {} (change \
         {:.2e}); floquet {:?}; {} points, {} Newton iterations, {:.2} s",
        lc.status,
        lc.hopf_scale,
        lc.hopf_frequency_hz,
        lc.frequency_hz,
        lc.peak_face_velocity,
        lc.rms_face_velocity,
        lc.harmonics,
        lc.harmonics_change,
        lc.floquet,
        lc.branch.len(),
        lc.newton_iterations,
        lc.time_s
    );
    assert_eq!(lc.status, LimitCycleStatus::Reached);
    let (peak, rms, f) = hoffmann_rk4(c, &u0, &load, 300.0, 2e-3);
    println!("RK4: f {f:.6} Hz, peak {peak:.6}, rms {rms:.6}");
    assert!(
        (lc.frequency_hz - f).abs() < 0.01 * f,
        "f {} vs {f}",
        lc.frequency_hz
    );
    assert!(
        (lc.rms_face_velocity - rms).abs() < 0.01 * rms,
        "rms {} vs {rms}",
        lc.rms_face_velocity
    );
    assert!(
        (lc.peak_face_velocity - peak).abs() < 0.01 * peak,
        "peak {} vs {peak}",
        lc.peak_face_velocity
    );
    let fl = lc.floquet.unwrap();
    assert!(fl.stable, "{fl:?}");
    let _: Real = lc.scale;
}
