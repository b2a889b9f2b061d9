//! `examples/corner/corner.toml`: a whole brake corner — a vented hat rotor, two pads of lining,
//! backplate and damping shim (a loss factor), a floating caliper with its piston in the bore,
//! and the anchor bracket with the pads' abutments — six components of eleven tet10 bodies,
//! eight `[[ties]]` and four `[[contact]]` pairs (the linings on the rotor; the inboard pad's
//! trailing ear on its abutment and the piston's seal band on the bore, neither sliding).
//!
//! The check is the load path's equilibrium along the axis, exact whatever the meshes. The
//! brake-line pressure on the piston's back reaches the inboard lining (piston rim → shim →
//! backplate → lining); the same pressure on the bore's bottom reaches the outboard lining
//! (housing → fingers → shim → backplate → lining). The ear's normal is y and the housing is
//! held in plane only, so along z only the seal couples the two chains: with S the z force of
//! the seal's gaps on the piston (the bore feels −S = Σ −λ̇ n_z over the seal's gaps, n the
//! rotor side's normal), the piston's chain balances f_piston + S = N_in and the housing's
//! −f_bore − S + N_out = 0, f the z resultants of the consistent pressure loads, computed here
//! from the meshes, and N the linings' normal forces. A tie that lost or created force, an untied node or a leak through
//! the reductions would break it.
//!
//! Needs the gmsh program (the project's `.venv`); without it the test prints why and returns.
//! `#[ignore]`d: minutes of CPU (six gmsh runs, six reductions of up to 43 k DOFs, eight mortar
//! ties); run it in release:
//! `cargo test --release -p squeal-pipeline --test corner -- --ignored --nocapture`.
//! Measured 2026-11-28 (72 s): 4 240 reduced DOFs, 713 gaps; each lining 1 887.280011 N,
//! f_piston = f_bore = 1 887.354948 N, the seal's axial force on the piston −0.0749 N; the
//! balances 1.1e-13 (inboard) and 1.6e-13 (outboard).

mod common;

use squeal_pipeline::problem::{system, tangents};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::model;
use squeal_solver::bsql::SteadyOptions;

#[test]
#[ignore = "minutes of CPU (gmsh, six reductions, eight mortar ties): run with --release --ignored"]
fn whole_corner_carries_the_line_pressure_to_the_linings() {
    if let Err(e) = squeal_meshes::gmsh::find_gmsh() {
        eprintln!("skipped: this test needs gmsh: {e}");
        return;
    }
    let (scene, dir, meshes) = common::corner_meshes("corner", &[], 8);
    let index = |name: &str| common::component_index(&scene, name);

    // p × the z resultant of the consistent load on each hydraulic face.
    let p = scene.loads.as_ref().unwrap().pmax;
    let f_piston = common::pressure_resultant_z(&meshes[index("piston")], "back", p);
    let f_bore = common::pressure_resultant_z(&meshes[index("caliper")], "bore_bottom", p);
    let circle = p * std::f64::consts::PI * 0.024f64.powi(2);
    assert!((f_piston / circle - 1.0).abs() < 2e-2, "{f_piston}");
    assert!((f_bore / circle - 1.0).abs() < 2e-2, "{f_bore}");

    let m = model::build(&scene, &dir, &Progress::quiet()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.gap_pairs.len(), 4);
    let problem = system::problem(&scene, &m).unwrap();
    let opts = SteadyOptions {
        tol: 1e-12,
        ..Default::default()
    };
    let lin = tangents::at_steady_state(&problem, &problem.gaps, &opts).unwrap();
    // Per pair: Σ −λ̇ (the normal force) and Σ −λ̇ n_z (its z part).
    let mut start = 0;
    let mut normal = Vec::new();
    let mut axial = Vec::new();
    for &n in &m.gap_pairs {
        let gaps = start..start + n;
        normal.push(gaps.clone().map(|k| -lin.lambda_dot[k]).sum::<f64>());
        axial.push(
            gaps.map(|k| -lin.lambda_dot[k] * m.gap_geometry.gaps[k].normal[2])
                .sum::<f64>(),
        );
        start += n;
    }
    let (n_in, n_out, seal_z) = (normal[0], normal[1], axial[3]);
    eprintln!(
        "{} reduced DOFs, {} gaps {:?}; normal force per pair {normal:?} N, z part {axial:?} N; \
         f_piston {f_piston:.6} N, f_bore {f_bore:.6} N",
        m.n(),
        m.gap_geometry.len(),
        m.gap_pairs
    );
    // The ear's normal is y: no z force.
    assert!(axial[2].abs() < 1e-9 * f_piston, "{axial:?}");
    // Σ −λ̇ n (n the rotor side's normal) is the pair's force on its rotor side, the bore:
    // the seal pushes the piston with the opposite.
    let on_piston = -seal_z;
    let e_in = (n_in - (f_piston + on_piston)).abs() / f_piston;
    let e_out = (n_out - (f_bore + on_piston)).abs() / f_bore;
    eprintln!(
        "inboard balance {e_in:.2e}, outboard {e_out:.2e} (seal on the piston {on_piston:.3e} N)"
    );
    assert!(e_in < 1e-8 && e_out < 1e-8, "{e_in:.2e} {e_out:.2e}");
}
