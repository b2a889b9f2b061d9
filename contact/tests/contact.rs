//! Tests of squeal-contact: friction laws, gap matching, gap forces and tangents.

use faer::Mat;
use proptest::prelude::*;
use squeal_contact::forces::regularisation;
use squeal_contact::friction::FrictionTable;
use squeal_contact::{
    match_gaps, ContactError, ContactNode, FrictionLaw, Gap, GapSet, MatchOptions, RotorRow,
};

// ---------------------------------------------------------------- friction laws

fn table3() -> FrictionLaw {
    // 3 pressures × 3 speeds × 2 temperatures, temperature fastest.
    let values = (0..18)
        .map(|i| 0.3 + 0.02 * ((i * 7) % 11) as f64)
        .collect();
    FrictionLaw::Table(FrictionTable {
        pressures: vec![0.0, 1.0, 2.5],
        speeds: vec![0.0, 0.5, 2.0],
        temperatures: vec![20.0, 100.0],
        values,
    })
}

fn equation() -> FrictionLaw {
    FrictionLaw::Equation {
        mu0: 0.4,
        a: 0.05,
        b: -0.1,
        c: 0.002,
        t0: 20.0,
    }
}

fn near_knot(x: f64, knots: &[f64]) -> bool {
    knots.iter().any(|k| (x - k).abs() < 1e-4)
}

proptest! {
    /// Central differences of μ match ∂μ/∂p, ∂μ/∂|V_t|, ∂μ/∂T away from table knots
    /// (multilinear and separable laws: the FD error is round-off only).
    #[test]
    fn friction_derivatives_match_finite_differences(p in -0.5f64..3.0, v in 0.0f64..2.5, t in 0.0f64..120.0) {
        for law in [table3(), equation(), FrictionLaw::LinearSpeed { mu0: 0.7, slope: -0.0005 }] {
            if let FrictionLaw::Table(tb) = &law {
                prop_assume!(!near_knot(p, &tb.pressures) && !near_knot(v, &tb.speeds) && !near_knot(t, &tb.temperatures));
            }
            let e = law.evaluate(p, v, t);
            let h = 1e-6;
            let fd = |dp: f64, dv: f64, dt: f64| (law.evaluate(p + dp, v + dv, t + dt).mu - law.evaluate(p - dp, v - dv, t - dt).mu) / (2.0 * h);
            prop_assert!((fd(h, 0.0, 0.0) - e.dmu_dp).abs() < 1e-7, "{law:?} dp");
            prop_assert!((fd(0.0, h, 0.0) - e.dmu_dv).abs() < 1e-7, "{law:?} dv");
            prop_assert!((fd(0.0, 0.0, h) - e.dmu_dt).abs() < 1e-7, "{law:?} dt");
        }
    }

    /// Outside the table, μ is clamped to the boundary value and its derivative along the
    /// clamped axis is 0.
    #[test]
    fn table_clamps_outside_its_range(v in 0.0f64..2.0, t in 20.0f64..100.0, over in 0.01f64..100.0) {
        let law = table3();
        let inside_hi = law.evaluate(2.5, v, t);
        let out_hi = law.evaluate(2.5 + over, v, t);
        prop_assert!((inside_hi.mu - out_hi.mu).abs() < 1e-15);
        prop_assert_eq!(out_hi.dmu_dp, 0.0);
        let out_lo = law.evaluate(-over, v, t);
        prop_assert!((law.evaluate(0.0, v, t).mu - out_lo.mu).abs() < 1e-15);
        prop_assert_eq!(out_lo.dmu_dp, 0.0);
        let out_t = law.evaluate(1.0, v, 100.0 + over);
        prop_assert!((law.evaluate(1.0, v, 100.0).mu - out_t.mu).abs() < 1e-15);
        prop_assert_eq!(out_t.dmu_dt, 0.0);
    }
}

#[test]
fn table_reproduces_knot_values_and_single_axis_tables() {
    let law = table3();
    let FrictionLaw::Table(tb) = &law else {
        unreachable!()
    };
    for (ip, &p) in tb.pressures.iter().enumerate() {
        for (iv, &v) in tb.speeds.iter().enumerate() {
            for (it, &t) in tb.temperatures.iter().enumerate() {
                let expect = tb.values[(ip * 3 + iv) * 2 + it];
                assert!((law.evaluate(p, v, t).mu - expect).abs() < 1e-14);
            }
        }
    }
    // μ(|V_t|) only: linear between knots, no pressure/temperature dependence.
    let v_only = FrictionLaw::Table(FrictionTable {
        pressures: vec![],
        speeds: vec![0.0, 10.0],
        temperatures: vec![],
        values: vec![0.5, 0.4],
    });
    v_only.validate().unwrap();
    let e = v_only.evaluate(123.0, 2.5, -40.0);
    assert!((e.mu - 0.475).abs() < 1e-15 && (e.dmu_dv + 0.01).abs() < 1e-15);
    assert_eq!((e.dmu_dp, e.dmu_dt), (0.0, 0.0));
    assert!(
        v_only.depends_on_speed()
            && !v_only.depends_on_pressure()
            && !v_only.depends_on_temperature()
    );
}

#[test]
fn dependency_flags_and_constant_law_has_no_derivatives() {
    let c = FrictionLaw::Constant { mu: 0.3 };
    assert!(!c.depends_on_pressure() && !c.depends_on_speed() && !c.depends_on_temperature());
    assert_eq!(
        c.evaluate(5.0, 3.0, 200.0),
        squeal_contact::FrictionEval {
            mu: 0.3,
            dmu_dp: 0.0,
            dmu_dv: 0.0,
            dmu_dt: 0.0
        }
    );
    let l = FrictionLaw::LinearSpeed {
        mu0: 0.7,
        slope: -0.0005,
    };
    assert!(l.depends_on_speed() && !l.depends_on_pressure());
    // The paper's cases 1–3 law at V = 15 rad/s × 5 in = 75 in/s: 0.7 − 0.0005·75.
    assert!((l.evaluate(40.0, 75.0, 0.0).mu - 0.6625).abs() < 1e-15);
    let e = FrictionLaw::Equation {
        mu0: 0.4,
        a: 0.0,
        b: 0.1,
        c: 0.0,
        t0: 0.0,
    };
    assert!(e.depends_on_speed() && !e.depends_on_pressure() && !e.depends_on_temperature());
    assert!(table3().depends_on_temperature());
}

#[test]
fn friction_laws_deserialize_with_snake_case_tags_and_reject_unknown_keys() {
    let l: FrictionLaw =
        toml::from_str("kind = \"linear_speed\"\nmu0 = 0.7\nslope = -0.0005").unwrap();
    assert_eq!(
        l,
        FrictionLaw::LinearSpeed {
            mu0: 0.7,
            slope: -0.0005
        }
    );
    let t: FrictionLaw =
        toml::from_str("kind = \"table\"\nspeeds = [0.0, 1.0]\nvalues = [0.5, 0.4]").unwrap();
    t.validate().unwrap();
    let e: FrictionLaw = toml::from_str("kind = \"equation\"\nmu0 = 0.4\nb = 0.1").unwrap();
    assert_eq!(
        e,
        FrictionLaw::Equation {
            mu0: 0.4,
            a: 0.0,
            b: 0.1,
            c: 0.0,
            t0: 0.0
        }
    );
    let err = toml::from_str::<FrictionLaw>("kind = \"constant\"\nmu = 0.3\nmuu = 1").unwrap_err();
    assert!(err.to_string().contains("muu"), "{err}");
    let json = serde_json::to_string(&FrictionLaw::Constant { mu: 0.3 }).unwrap();
    assert_eq!(json, r#"{"kind":"constant","mu":0.3}"#);
    // Validation names the field.
    let bad = FrictionLaw::Table(FrictionTable {
        pressures: vec![0.0, 0.0],
        speeds: vec![],
        temperatures: vec![],
        values: vec![0.1, 0.2],
    });
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("friction.pressures[1]"));
    let bad = FrictionLaw::Table(FrictionTable {
        pressures: vec![0.0, 1.0],
        speeds: vec![],
        temperatures: vec![],
        values: vec![0.1],
    });
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("friction.values"));
    // μ is bounded by MU_MAX = 10 (the largest measured between solids): μ = 1e300 passed
    // validation once and failed later as a singular Newton matrix.
    for (law, field) in [
        (FrictionLaw::Constant { mu: 1e300 }, "friction.mu"),
        (
            FrictionLaw::LinearSpeed {
                mu0: 10.5,
                slope: 0.0,
            },
            "friction.mu0",
        ),
        (
            FrictionLaw::Table(FrictionTable {
                pressures: vec![0.0, 1.0],
                speeds: vec![],
                temperatures: vec![],
                values: vec![0.4, 11.0],
            }),
            "friction.values[1]",
        ),
    ] {
        let e = law.validate().unwrap_err().to_string();
        assert!(e.contains(field) && e.contains("[0, 10]"), "{e}");
    }
    let e = FrictionLaw::Constant { mu: 1e300 }
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("1e300"), "{e}");
    FrictionLaw::Constant {
        mu: squeal_contact::friction::MU_MAX,
    }
    .validate()
    .unwrap();
}

// ---------------------------------------------------------------- gap matching

fn plate(nx: usize, jitter: f64, id0: u64) -> Vec<ContactNode> {
    (0..nx * nx)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            let j2 = if jitter > 0.0 {
                jitter * (((k * 37) % 11) as f64 / 11.0 - 0.5)
            } else {
                0.0
            };
            ContactNode {
                id: id0 + k as u64,
                coords: [1.0 + 0.1 * i as f64 + j2, 0.1 * j as f64, 0.5],
                area: [0.0, 0.0, 0.01],
            }
        })
        .collect()
}

#[test]
fn matching_pairs_coincident_nodes_with_normal_area_and_rotor_speed() {
    let pad = plate(20, 0.0, 1000);
    let mut rotor = plate(20, 1e-9, 5000);
    rotor.reverse();
    // 15 rad/s about +z (the paper's RPM 143.239), axis through the origin.
    let opts = MatchOptions {
        tolerance: 1e-6,
        rpm: 143.239,
        p0: 40.0,
        ..MatchOptions::default()
    };
    let set = match_gaps(&pad, &rotor, &opts).unwrap();
    assert_eq!(set.len(), 400);
    let w = 143.239 * 2.0 * std::f64::consts::PI / 60.0;
    assert!((w - 15.0).abs() < 1e-4);
    for g in &set.gaps {
        assert_eq!(g.rotor_node - 5000, g.pad_node - 1000);
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        assert!((g.area - 0.01).abs() < 1e-15 && g.p0 == 40.0);
        // ω × r with ω = w e_z, r = (x, y, 0.5): (−w y, w x, 0).
        let [x, y, _] = g.coords;
        assert!(
            (g.v_slide[0] + w * y).abs() < 1e-12
                && (g.v_slide[1] - w * x).abs() < 1e-12
                && g.v_slide[2] == 0.0
        );
    }
}

#[test]
fn matching_errors_list_every_offending_node() {
    let pad = plate(4, 0.0, 1);
    let mut rotor = plate(4, 0.0, 100);
    rotor.remove(5); // pad node 6 unmatched
    rotor.push(ContactNode {
        id: 999,
        coords: [1.0 + 0.1 * 2.0 + 1e-8, 0.0, 0.5],
        area: [0.0; 3],
    }); // pad 3 ambiguous
    let mut pad2 = pad.clone();
    pad2.push(ContactNode {
        id: 77,
        coords: pad[0].coords,
        area: [0.0, 0.0, 0.01],
    }); // rotor 100 used twice
    pad2.push(ContactNode {
        id: 78,
        coords: [5.0, 5.0, 5.0],
        area: [0.0; 3],
    }); // zero area
    let err = match_gaps(&pad2, &rotor, &MatchOptions::default()).unwrap_err();
    let ContactError::Matching { nodes, .. } = &err else {
        panic!("{err}")
    };
    let ids: Vec<u64> = nodes.iter().map(|n| n.id).collect();
    for id in [6, 3, 100, 78] {
        assert!(ids.contains(&id), "{id} missing in {err}");
    }
    let msg = err.to_string();
    assert!(
        msg.contains("node 6 at (1.100000e0, 1.000000e-1, 5.000000e-1)"),
        "{msg}"
    );
    assert!(msg.contains("999") && msg.contains("1, 77"), "{msg}");
}

#[test]
fn matching_is_linear_time_on_many_nodes() {
    // 40 000 pairs: an O(n²) search would take minutes, the grid takes milliseconds.
    let pad = plate(200, 0.0, 0);
    let rotor = plate(200, 1e-9, 1_000_000);
    let set = match_gaps(&pad, &rotor, &MatchOptions::default()).unwrap();
    assert_eq!(set.len(), 40_000);
}

// ---------------------------------------------------------------- forces and tangents

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// Three gaps on 12 DOFs with oblique normals, some fixed DOFs, a pressure- and
/// speed-dependent law.
fn three_gaps(law: FrictionLaw, vslide: f64) -> GapSet {
    let mk = |k: usize, normal: [f64; 3], pad: [Option<usize>; 3], rotor: [Option<usize>; 3]| Gap {
        pad_node: k as u64,
        rotor_node: 100 + k as u64,
        coords: [0.0; 3],
        pad_dofs: pad,
        rotor_dofs: rotor,
        normal: unit(normal),
        area: 0.5 + 0.25 * k as f64,
        v_slide: [vslide, 0.3 * vslide, -0.1 * vslide],
        p0: 2.0,
        temperature: 60.0,
        tie: None,
        rotor_rows: Vec::new(),
        pad_side: None,
        friction: None,
    };
    GapSet::new(
        vec![
            mk(
                0,
                [0.1, 0.2, 1.0],
                [Some(0), Some(1), Some(2)],
                [Some(3), Some(4), Some(5)],
            ),
            mk(
                1,
                [-0.3, 0.1, 1.0],
                [Some(6), None, Some(7)],
                [Some(8), Some(9), None],
            ),
            mk(
                2,
                [0.0, 0.0, 1.0],
                [Some(10), Some(11), Some(1)],
                [None, None, None],
            ),
        ],
        law,
        1e-3,
    )
    .unwrap()
}

fn forces(set: &GapSet, v: &[f64], lam: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; v.len()];
    set.add_forces(v, lam, &mut f).unwrap();
    f
}

proptest! {
    /// Both tangents match central differences of the forces, in and out of the regularised
    /// zone (speeds from 1e-5 to 1), for a law depending on p and |V_t|.
    #[test]
    fn tangents_match_finite_differences(seed in prop::collection::vec(-1.0f64..1.0, 15), scale in prop::sample::select(vec![1e-5, 3e-4, 2e-3, 0.05, 1.0])) {
        let mut set = three_gaps(equation(), scale);
        // Gap 1 with its own (speed-dependent) law: the tangents follow each gap's law.
        set.gaps[1].friction = Some(FrictionLaw::LinearSpeed { mu0: 0.35, slope: -0.02 });
        let v: Vec<f64> = seed[..12].iter().map(|x| x * scale).collect();
        let lam: Vec<f64> = seed[12..].to_vec();
        // Skip states within 1 % of the kink of the regularisation at 10 VTOL.
        for g in 0..3 {
            let s = set.gap_output(g, &v, &lam).unwrap().slip_speed;
            prop_assume!((s / 1e-2 - 1.0).abs() > 0.01);
        }
        let mut dl = Mat::zeros(12, 3);
        let mut dv = Mat::zeros(12, 12);
        set.add_tangents(&v, &lam, &mut dl, Some(&mut dv)).unwrap();
        let mut dvmax = 0.0f64;
        for j in 0..12 {
            for i in 0..12 {
                dvmax = dvmax.max(dv[(i, j)].abs());
            }
        }
        for j in 0..12 {
            let h = 1e-6 * scale;
            let (mut vp, mut vm) = (v.clone(), v.clone());
            vp[j] += h;
            vm[j] -= h;
            let (fp, fm) = (forces(&set, &vp, &lam), forces(&set, &vm, &lam));
            for i in 0..12 {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                prop_assert!((fd - dv[(i, j)]).abs() <= 1e-6 * (dv[(i, j)].abs() + dvmax), "d f{i}/d v{j}: fd {fd} vs {}", dv[(i, j)]);
            }
        }
        for g in 0..3 {
            let h = 1e-6;
            let (mut lp, mut lm) = (lam.clone(), lam.clone());
            lp[g] += h;
            lm[g] -= h;
            let (fp, fm) = (forces(&set, &v, &lp), forces(&set, &v, &lm));
            for i in 0..12 {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                prop_assert!((fd - dl[(i, g)]).abs() <= 1e-6 * (1.0 + dl[(i, g)].abs()), "d f{i}/d lam{g}: fd {fd} vs {}", dl[(i, g)]);
            }
        }
    }

    /// |F_t| ≤ μ p_n A for p_n ≥ 0 (the regularisation only reduces it), and friction
    /// dissipates: f_p·v_p + f_r·(v_r + v_slide) = −F_t r |V_t| ≤ 0.
    #[test]
    fn friction_is_bounded_and_dissipative(seed in prop::collection::vec(-1.0f64..1.0, 12), lam in prop::collection::vec(-5.0f64..0.5, 3), scale in prop::sample::select(vec![1e-4, 5e-3, 1.0])) {
        let set = three_gaps(equation(), scale);
        let v: Vec<f64> = seed.iter().map(|x| x * scale).collect();
        let f = forces(&set, &v, &lam);
        let mut power = 0.0;
        for (g, gap) in set.gaps.iter().enumerate() {
            let o = set.gap_output(g, &v, &lam).unwrap();
            prop_assume!(o.pressure >= 0.0 && o.friction.mu >= 0.0);
            let fp = o.force_on_pad;
            let mag = (fp[0] * fp[0] + fp[1] * fp[1] + fp[2] * fp[2]).sqrt();
            prop_assert!(mag <= o.friction.mu * o.pressure * gap.area * (1.0 + 1e-12));
            prop_assert!((mag - o.friction_force).abs() <= 1e-12 * (1.0 + mag));
            for k in 0..3 {
                let vp = gap.pad_dofs[k].map_or(0.0, |d| v[d]);
                let vr = gap.rotor_dofs[k].map_or(0.0, |d| v[d]) + gap.v_slide[k];
                power += fp[k] * vp - fp[k] * vr;
            }
        }
        prop_assert!(power <= 1e-14, "friction power {power} > 0");
        prop_assert!(f.iter().all(|x| x.is_finite()));
    }
}

/// One gap, pad below the rotor (n = +z), rotor surface sliding at +x.
fn one_gap(mu: f64, vslide: f64) -> GapSet {
    let gap = Gap {
        pad_node: 1,
        rotor_node: 2,
        coords: [0.0; 3],
        pad_dofs: [Some(0), Some(1), Some(2)],
        rotor_dofs: [Some(3), Some(4), Some(5)],
        normal: [0.0, 0.0, 1.0],
        area: 2.0,
        v_slide: [vslide, 0.0, 0.0],
        p0: 10.0,
        temperature: 0.0,
        tie: None,
        rotor_rows: Vec::new(),
        pad_side: None,
        friction: None,
    };
    GapSet::new(vec![gap], FrictionLaw::Constant { mu }, 1e-3).unwrap()
}

#[test]
fn pad_is_dragged_along_the_rotor_and_compression_raises_friction() {
    let set = one_gap(0.3, 1.0);
    // Pad at rest: dragged along +x with μ p0 A = 0.3·10·2 = 6; the rotor gets −6.
    let f = forces(&set, &[0.0; 6], &[0.0]);
    assert!((f[0] - 6.0).abs() < 1e-12 && (f[3] + 6.0).abs() < 1e-12);
    assert!(f[1] == 0.0 && f[2] == 0.0);
    // Pad sliding faster than the rotor surface: the force opposes the pad's relative sliding.
    let f = forces(&set, &[2.0, 0.0, 0.0, 0.0, 0.0, 0.0], &[0.0]);
    assert!((f[0] + 6.0).abs() < 1e-12);
    // Normal velocities do not change V_t.
    let f = forces(&set, &[0.0, 0.0, 0.7, 0.0, 0.0, -0.2], &[0.0]);
    assert!((f[0] - 6.0).abs() < 1e-12);
    // λ̇ = −4 is a compressive increment F_z = 4: p_n = 4/2 + 10 = 12, F = 0.3·12·2 = 7.2.
    let o = set.gap_output(0, &[0.0; 6], &[-4.0]).unwrap();
    assert!((o.pressure - 12.0).abs() < 1e-14 && (o.force_on_pad[0] - 7.2).abs() < 1e-12);
}

#[test]
fn regularised_force_is_continuous_at_ten_vtol() {
    let vtol = 1e-3;
    let below = one_gap(0.3, 10.0 * vtol * (1.0 - 1e-10));
    let above = one_gap(0.3, 10.0 * vtol);
    let fb = forces(&below, &[0.0; 6], &[0.0])[0];
    let fa = forces(&above, &[0.0; 6], &[0.0])[0];
    assert!((fa - 6.0).abs() < 1e-12);
    assert!((fb - fa).abs() < 1e-8, "{fb} vs {fa}");
    // Inside the zone: F·atan(|V_t|/VTOL)/atan(10), ≈ linear in V_t near 0.
    let f = forces(&one_gap(0.3, 1e-7), &[0.0; 6], &[0.0])[0];
    let expect = 6.0 * (1e-7 / vtol).atan() / 10f64.atan();
    assert!((f - expect).abs() < 1e-14 * expect, "{f} vs {expect}");
    let f = forces(&one_gap(0.3, 4e-3), &[0.0; 6], &[0.0])[0];
    let expect = 6.0 * 4f64.atan() / 10f64.atan();
    assert!((f - expect).abs() < 1e-13 * expect, "{f} vs {expect}");
    assert_eq!(forces(&one_gap(0.3, 0.0), &[0.0; 6], &[0.0])[0], 0.0);
    let (phi, _) = regularisation(0.0, vtol);
    assert!(phi.is_finite());
}

#[test]
fn constraint_matrix_is_rotor_minus_pad_along_the_normal() {
    let set = three_gaps(FrictionLaw::Constant { mu: 0.3 }, 1.0);
    let g = set.constraint_matrix(12).unwrap();
    let u: Vec<f64> = (0..12).map(|i| ((i * 7 % 5) as f64 - 2.0) * 0.3).collect();
    for (ig, gap) in set.gaps.iter().enumerate() {
        let gu: f64 = (0..12).map(|j| g[(ig, j)] * u[j]).sum();
        let mut expect = 0.0;
        for k in 0..3 {
            expect += gap.normal[k]
                * (gap.rotor_dofs[k].map_or(0.0, |d| u[d]) - gap.pad_dofs[k].map_or(0.0, |d| u[d]));
        }
        assert!((gu - expect).abs() < 1e-14);
    }
    // Out-of-range DOFs and wrong lengths are errors naming the gap / argument.
    assert!(matches!(
        set.constraint_matrix(11),
        Err(ContactError::DofOutOfRange {
            gap: 2,
            dof: 11,
            n: 11,
            ..
        })
    ));
    let mut f = vec![0.0; 12];
    assert!(matches!(
        set.add_forces(&[0.0; 12], &[0.0; 2], &mut f),
        Err(ContactError::Length {
            what: "lambda_dot",
            ..
        })
    ));
    let mut bad = Mat::zeros(12, 2);
    assert!(matches!(
        set.add_tangents(&[0.0; 12], &[0.0; 3], &mut bad, None),
        Err(ContactError::Shape { what: "d_dlam", .. })
    ));
}

/// A rotor point given by recovery rows (an interface-reduced rotor) is the same gap in other
/// coordinates: with the rotor DOFs 3..6 of the first gap written as u = C x (rows
/// (3 + j, C[:, j])), forces, tangents and G equal those of the physical gap at x' = P x,
/// transformed by P = blockdiag(I₃, C, I₆): f = Pᵀf', ∂f/∂λ̇ = Pᵀ(∂f/∂λ̇)', C_f = PᵀC_f'P,
/// G = G'P.
#[test]
fn rotor_rows_are_the_physical_gap_in_other_coordinates() {
    let law = FrictionLaw::LinearSpeed {
        mu0: 0.6,
        slope: -0.02,
    };
    let physical = three_gaps(law.clone(), 1.5);
    let c = [[0.9, -0.2, 0.3], [0.1, 1.1, -0.4], [0.25, 0.05, 0.8]];
    let mut rows = physical.clone();
    rows.gaps[0].rotor_rows = (0..3)
        .map(|j| RotorRow {
            dof: 3 + j,
            weights: [c[0][j], c[1][j], c[2][j]],
        })
        .collect();
    rows.gaps[0].rotor_dofs = [None; 3];
    let mut p = Mat::<f64>::identity(12, 12);
    for i in 0..3 {
        for j in 0..3 {
            p[(3 + i, 3 + j)] = c[i][j];
        }
    }
    let x: Vec<f64> = (0..12).map(|i| 0.3 * ((i * 5) % 7) as f64 - 0.8).collect();
    let xp: Vec<f64> = (0..12)
        .map(|i| (0..12).map(|j| p[(i, j)] * x[j]).sum())
        .collect();
    let lam = [-1.0, -0.4, -2.2];
    let col = |v: &[f64]| Mat::from_fn(v.len(), 1, |i, _| v[i]);
    let close = |a: &Mat<f64>, b: &Mat<f64>, what: &str| {
        let e = (a - b).norm_max() / b.norm_max().max(1e-300);
        assert!(e < 1e-13, "{what}: relative difference {e:e}");
    };
    let f = forces(&rows, &x, &lam);
    let fp = forces(&physical, &xp, &lam);
    close(&col(&f), &(p.transpose() * col(&fp)), "forces");
    let (mut dl, mut cf) = (Mat::zeros(12, 3), Mat::zeros(12, 12));
    rows.add_tangents(&x, &lam, &mut dl, Some(&mut cf)).unwrap();
    let (mut dlp, mut cfp) = (Mat::zeros(12, 3), Mat::zeros(12, 12));
    physical
        .add_tangents(&xp, &lam, &mut dlp, Some(&mut cfp))
        .unwrap();
    close(&dl, &(p.transpose() * &dlp), "d/dlambda");
    close(&cf, &(p.transpose() * &cfp * &p), "C_f");
    let g = rows.constraint_matrix(12).unwrap();
    let gp = physical.constraint_matrix(12).unwrap();
    close(&g, &(&gp * &p), "G");
}

/// Each gap's blocks (`GapSet::gap_blocks`) scattered and summed are exactly G, D and C_f
/// (`constraint_matrix`, `add_tangents`), for coincident gaps with fixed DOFs and a DOF
/// shared by two gaps, and for a gap whose rotor point is given by recovery rows.
#[test]
fn gap_blocks_sum_to_g_d_and_c_f() {
    let law = FrictionLaw::LinearSpeed {
        mu0: 0.6,
        slope: -0.02,
    };
    let mut with_rows = three_gaps(law.clone(), 1.5);
    with_rows.gaps[0].rotor_rows = (0..3)
        .map(|j| RotorRow {
            dof: 3 + j,
            weights: [0.9 - 0.1 * j as f64, 0.2 * j as f64, 0.3],
        })
        .collect();
    with_rows.gaps[0].rotor_dofs = [None; 3];
    for set in [three_gaps(law, 1.5), with_rows] {
        let v: Vec<f64> = (0..12).map(|i| 0.2 * ((i * 3) % 5) as f64 - 0.4).collect();
        let lam = [-1.0, -0.4, -2.2];
        let (mut dl, mut cf) = (Mat::zeros(12, 3), Mat::zeros(12, 12));
        set.add_tangents(&v, &lam, &mut dl, Some(&mut cf)).unwrap();
        let g = set.constraint_matrix(12).unwrap();
        let blocks = set.gap_blocks(&v, &lam).unwrap();
        let mut g2 = Mat::<f64>::zeros(3, 12);
        let mut dl2 = Mat::<f64>::zeros(12, 3);
        let mut cf2 = Mat::<f64>::zeros(12, 12);
        for (k, b) in blocks.iter().enumerate() {
            assert!(b.dofs.windows(2).all(|w| w[0] < w[1]), "sorted, unique");
            for (a, &i) in b.dofs.iter().enumerate() {
                g2[(k, i)] += b.g[a];
                dl2[(i, k)] += b.d[a];
                for (c, &j) in b.dofs.iter().enumerate() {
                    cf2[(i, j)] += b.c_f[(a, c)];
                }
            }
        }
        assert!((&g - &g2).norm_max() <= 1e-15 * g.norm_max());
        assert!((&dl - &dl2).norm_max() <= 1e-15 * dl.norm_max());
        assert!((&cf - &cf2).norm_max() <= 1e-14 * cf.norm_max());
    }
}

/// A gap's own friction law replaces the set's for that gap only: with gap 1's law set to
/// the set's law B, its forces equal those of a set whose law is B, and the other gaps keep
/// law A's forces. An invalid own law is an error naming the gap.
#[test]
fn a_gap_with_its_own_law_uses_it() {
    let a = FrictionLaw::Constant { mu: 0.5 };
    let b = FrictionLaw::LinearSpeed {
        mu0: 0.2,
        slope: -0.01,
    };
    let v: Vec<f64> = (0..12).map(|i| 0.1 * (i as f64 - 5.0)).collect();
    let lam = vec![-1.0, -2.0, -0.5];
    let mut mixed = three_gaps(a.clone(), 1.0);
    mixed.gaps[1].friction = Some(b.clone());
    let all_a = three_gaps(a, 1.0);
    let all_b = three_gaps(b, 1.0);
    for g in 0..3 {
        let got = mixed.gap_output(g, &v, &lam).unwrap().force_on_pad;
        let want = if g == 1 { &all_b } else { &all_a }
            .gap_output(g, &v, &lam)
            .unwrap()
            .force_on_pad;
        assert_eq!(got, want, "gap {g}");
    }
    assert_eq!(mixed.laws().len(), 2);
    let mut bad = three_gaps(FrictionLaw::Constant { mu: 0.5 }, 1.0);
    bad.gaps[2].friction = Some(FrictionLaw::Constant { mu: f64::NAN });
    let e = bad
        .with_friction(FrictionLaw::Constant { mu: 0.5 }, 1e-3)
        .unwrap_err()
        .to_string();
    assert!(e.contains("gap 2") && e.contains("own friction law"), "{e}");
}
