//! A material's structural loss factor η (`loss_factor`, NASTRAN's MAT1/MAT9 GE, Abaqus's
//! `*DAMPING, STRUCTURAL`): the element damping of a component becomes
//! B_c = (1/W4)·Tᵀ (GE_c K_c + Σ_b η_b K_b) T.
//!
//! The two-body pad: a Nastran deck written here, 1 × 0.5 × 0.3 in 4 × 2 × 3 hex8, PSOLID 1
//! (`pid_1`, the backplate: the two lower layers) and PSOLID 2 (`pid_2`, the shim: the top
//! layer), sharing its x = 1 face with a support block (same grid) clamped at its far end, so
//! the pad's reduction has boundary DOFs (constraint modes Ψ) besides its modes.

mod common;

use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use squeal_pipeline::model::cache::component::ComponentCache;
use squeal_pipeline::model::cache::key::ModelKey;
use squeal_pipeline::model::{build, build_from_mesh_cached};
use squeal_pipeline::problem::system::damping_matrix;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::{RunDir, Scene};
use std::path::{Path, PathBuf};

type Model = squeal_pipeline::model::ReducedModel;

const BACK: (f64, f64) = (2.0e4, 0.3);
const SHIM: (f64, f64) = (2.0e3, 0.45);
const W4: f64 = 50.0;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("loss_factor")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The pad deck: MAT1 1 (backplate) and MAT1 2 (shim) with GE fields `ge` (None: blank).
fn pad_deck(ge: [Option<f64>; 2]) -> String {
    let (nx, ny, nz) = (4usize, 2usize, 3usize);
    let id = |i: usize, j: usize, k: usize| 1 + i + (nx + 1) * (j + (ny + 1) * k);
    let mut s = String::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let x = [i as f64 * 0.25, j as f64 * 0.25, k as f64 * 0.1];
                s += &format!("GRID,{},,{:?},{:?},{:?}\n", id(i, j, k), x[0], x[1], x[2]);
            }
        }
    }
    let mut e = 1;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let pid = if k < 2 { 1 } else { 2 };
                let g = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                s += &format!(
                    "CHEXA,{e},{pid},{},{},{},{},{},{}\n,{},{}\n",
                    g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7]
                );
                e += 1;
            }
        }
    }
    for (mid, (young, nu)) in [(1, BACK), (2, SHIM)] {
        let g = ge[mid - 1].map_or(String::new(), |g| format!("{g:?}"));
        s += &format!("PSOLID,{mid},{mid}\nMAT1,{mid},{young:?},,{nu:?},1.0,,,{g}\n");
    }
    s
}

/// The pad (from `deck`, with `pad` keys added to its table) on the clamped support, and
/// `damping` as the `[damping]` table's body.
fn scene(dir: &Path, deck: &str, pad: &str, damping: &str) -> Scene {
    std::fs::write(dir.join("pad.bdf"), deck).unwrap();
    scene_with(dir, r#"{ kind = "bdf", path = "pad.bdf" }"#, pad, damping)
}

/// [`scene`] with the pad's `geometry`.
fn scene_with(dir: &Path, geometry: &str, pad: &str, damping: &str) -> Scene {
    let text = format!(
        r#"
[[components]]
name = "pad"
geometry = {geometry}
{pad}

[[components]]
name = "support"
element = "hex8"
geometry = {{ kind = "block", origin = [1.0, 0.0, 0.0], lx = 1.0, ly = 0.5, lz = 0.3, nx = 4, ny = 2, nz = 3 }}
material = {{ young = 2.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x1" }}]

[reduction]
n_modes = 8
checks = false

[damping]
{damping}
"#
    );
    Scene::from_toml_str(&text, dir.to_path_buf(), &[]).unwrap()
}

fn model_of(s: &Scene, dir: &Path, name: &str) -> Model {
    let run = RunDir::create(&dir.join(name)).unwrap();
    build(s, &run, &Progress::quiet()).unwrap()
}

/// max |a − b| / max |b|.
fn rel(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()));
    let mut d: f64 = 0.0;
    let mut n: f64 = 0.0;
    for j in 0..b.ncols() {
        for i in 0..b.nrows() {
            d = d.max((a[(i, j)] - b[(i, j)]).abs());
            n = n.max(b[(i, j)].abs());
        }
    }
    d / n
}

fn mat_keys(eta: [f64; 2]) -> String {
    let m = |(e, nu): (f64, f64), eta: f64| {
        format!("{{ young = {e:?}, poisson = {nu:?}, density = 1.0, loss_factor = {eta:?} }}")
    };
    format!(
        "materials = {{ pid_1 = {}, pid_2 = {} }}",
        m(BACK, eta[0]),
        m(SHIM, eta[1])
    )
}

/// η on every body of a component is the component's GE: the same model B (and the same
/// damping matrix the CEA and the transient take) as `damping.ge.pad = η`.
#[test]
fn loss_factor_on_every_body_equals_component_ge() {
    let d = tmp("every_body");
    let eta = 0.2;
    let deck = pad_deck([None, None]);
    let by_ge = scene(
        &d,
        &deck,
        &mat_keys([0.0, 0.0]),
        &format!("w4 = {W4:?}\nge = {{ pad = {eta:?} }}"),
    );
    let by_eta = scene(&d, &deck, &mat_keys([eta, eta]), &format!("w4 = {W4:?}"));
    let (m_ge, m_eta) = (model_of(&by_ge, &d, "ge"), model_of(&by_eta, &d, "eta"));
    let (b_ge, b_eta) = (m_ge.b.clone().unwrap(), m_eta.b.clone().unwrap());
    let r = rel(&b_eta, &b_ge);
    let r_cea = rel(
        &damping_matrix(&by_eta, &m_eta).unwrap(),
        &damping_matrix(&by_ge, &m_ge).unwrap(),
    );
    eprintln!(
        "η on every body vs GE_c: B relative difference {r:.2e} (damping_matrix {r_cea:.2e}), \
         n = {}",
        b_ge.nrows()
    );
    assert!(r < 1e-12 && r_cea < 1e-12, "{r:e} {r_cea:e}");
    assert!(rel(&m_eta.k, &m_ge.k) == 0.0 && rel(&m_eta.m, &m_ge.m) == 0.0);
    // Both at once add: GE_c and η give (GE_c + η)/W4 K.
    let both = scene(
        &d,
        &deck,
        &mat_keys([eta, eta]),
        &format!("w4 = {W4:?}\nge = {{ pad = {eta:?} }}"),
    );
    let m_both = model_of(&both, &d, "both");
    let twice = Mat::from_fn(b_ge.nrows(), b_ge.ncols(), |i, j| 2.0 * b_ge[(i, j)]);
    let r2 = rel(m_both.b.as_ref().unwrap(), &twice);
    eprintln!("GE_c + η vs 2 GE_c: {r2:.2e}");
    assert!(r2 < 1e-12, "{r2:e}");
}

/// η on the shim only: the model's B equals (η/W4)·Tᵀ K_shim T with K_shim assembled here by
/// squeal_fe from the shim's cells alone and T the pad's Craig–Bampton transformation (its
/// recovery data), placed at the pad's assembled coordinates.
#[test]
fn loss_factor_on_one_body_is_its_projected_stiffness() {
    let d = tmp("one_body");
    let eta = 0.35;
    let s = scene(
        &d,
        &pad_deck([None, None]),
        &mat_keys([0.0, eta]),
        &format!("w4 = {W4:?}"),
    );
    let model = model_of(&s, &d, "shim");
    let b = model.b.clone().expect("element damping");
    let rec = model.recovery.iter().find(|r| r.name == "pad").unwrap();
    assert!(rec.mpc.is_none());
    let shim = rec
        .mesh
        .volumes
        .iter()
        .position(|v| v.name.as_deref() == Some("pid_2"))
        .unwrap();
    let sub = squeal_meshes::Mesh {
        nodes: rec.mesh.nodes.clone(),
        node_tags: rec.mesh.node_tags.clone(),
        volumes: vec![rec.mesh.volumes[shim].clone()],
        ..Default::default()
    };
    let mat = squeal_fe::Material {
        young: SHIM.0,
        poisson: SHIM.1,
        density: 1.0,
    };
    let k_shim = squeal_fe::assemble(&sub, &[mat], &rec.dofs, &Default::default())
        .unwrap()
        .k
        .to_dense();
    let t = rec.cb.transformation();
    let kr = t.transpose() * &k_shim * &t;
    let n = model.n();
    let mut want = Mat::<f64>::zeros(n, n);
    for (j, tj) in rec.assembled.iter().enumerate() {
        for (k, tk) in rec.assembled.iter().enumerate() {
            for &(a, wa) in tj {
                for &(c, wc) in tk {
                    want[(a, c)] += eta / W4 * wa * wc * kr[(j, k)];
                }
            }
        }
    }
    let r = rel(&b, &want);
    eprintln!(
        "η on the shim: B vs (η/W4) Tᵀ K_shim T, relative {r:.2e} ({} pad coordinates, \
         {} boundary)",
        rec.cb.n_reduced(),
        rec.cb.n_boundary_coords()
    );
    assert!(rec.cb.n_boundary_coords() > 0);
    assert!(r < 1e-12, "{r:e}");
    // The shim's damping is not the pad's stiffness scaled: a check that could fail.
    let all = squeal_fe::assemble(
        &rec.mesh,
        &[
            squeal_fe::Material {
                young: BACK.0,
                poisson: BACK.1,
                density: 1.0,
            },
            mat,
        ],
        &rec.dofs,
        &Default::default(),
    )
    .unwrap()
    .k
    .to_dense();
    let kall = t.transpose() * &all * &t;
    let ratio = kr[(0, 0)] / kall[(0, 0)];
    let off = (0..kr.nrows())
        .map(|i| (kr[(i, i)] / kall[(i, i)] - ratio).abs())
        .fold(0.0, f64::max);
    assert!(
        off > 1e-3,
        "the shim's K is proportional to the pad's: {off:e}"
    );
}

/// The first root's damping ratio of a uniform loss factor at W4 = ω_1.
///
/// # Derivation
/// A single-body cantilever (2 × 0.3 × 0.2, 10 × 1 × 1 hex8, clamped at x = 0) with η on
/// its one material: B = (η/W4)·Tᵀ K T = (η/W4)·K_r. The reduced modes x_i (K_r x = ω_i² M_r
/// x, M_r-orthonormal) diagonalise B too, so each mode obeys q̈ + (η ω_i²/W4) q̇ + ω_i² q = 0:
/// 2 ζ_i ω_i = η ω_i²/W4, ζ_i = η ω_i/(2 W4) (the viscous equivalent c = η k/W4, exact at
/// ω = W4). With W4 = ω_1, ζ_1 = η/2 to the reduced model's round-off; the second mode's is
/// η ω_2/(2 ω_1), not η/2. The roots are the eigenvalues λ of the state matrix
/// [[0, I], [−M⁻¹K, −M⁻¹B]] with B from `damping_matrix` (the CEA's and transient's), ζ =
/// −Re λ/|λ|.
#[test]
fn uniform_loss_factor_damps_the_first_mode_by_half_eta_at_w4() {
    let d = tmp("cantilever");
    let eta = 0.2;
    let text = |damping: &str| {
        format!(
            r#"
[[components]]
name = "beam"
element = "hex8"
geometry = {{ kind = "block", origin = [0.0, 0.0, 0.0], lx = 2.0, ly = 0.3, lz = 0.2, nx = 10, ny = 1, nz = 1 }}
material = {{ young = 1.0e4, poisson = 0.3, density = 1.0, loss_factor = {eta:?} }}
fixed = [{{ set = "x0" }}]

[reduction]
n_modes = 6
{damping}
"#
        )
    };
    let s0 = Scene::from_toml_str(&text(""), d.clone(), &[]).unwrap();
    let m0 = model_of(&s0, &d, "undamped");
    assert!(m0.b.is_none());
    // W4 = 0: η is off, and a warning names the material.
    let w = &m0.warnings;
    assert!(
        w.iter().any(|w| w
            .input
            .contains("components[name = beam].material.loss_factor")
            && w.message.contains("w4")
            && w.value == eta),
        "{w:?}"
    );
    let (vals, _) =
        squeal_reduction::cb::dense_generalized_eigen(m0.k.as_ref(), m0.m.as_ref()).unwrap();
    let omega: Vec<f64> = vals.iter().map(|v| v.sqrt()).collect();
    let w4 = omega[0];
    let s =
        Scene::from_toml_str(&text(&format!("[damping]\nw4 = {w4:?}")), d.clone(), &[]).unwrap();
    let m = model_of(&s, &d, "damped");
    assert!(m
        .warnings
        .iter()
        .all(|w| !w.message.contains("loss factor")));
    let b = damping_matrix(&s, &m).unwrap();
    let n = m.n();
    // Dense M⁻¹ by solving M X = I (small model).
    let minv = m.m.as_ref().partial_piv_lu().inverse();
    let (mk, mb) = (&minv * &m.k, &minv * &b);
    let a = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - n == i)),
        (false, true) => -mk[(i - n, j)],
        (false, false) => -mb[(i - n, j - n)],
    });
    let mut roots: Vec<num_complex::Complex<f64>> = a
        .eigenvalues()
        .unwrap()
        .into_iter()
        .filter(|l| l.im > 0.0)
        .collect();
    roots.sort_by(|x, y| x.norm().total_cmp(&y.norm()));
    let zeta = |l: num_complex::Complex<f64>| -l.re / l.norm();
    let (z1, z2) = (zeta(roots[0]), zeta(roots[1]));
    let want2 = eta * omega[1] / (2.0 * w4);
    eprintln!(
        "cantilever ω1 = {:.6} rad/s, ω2 = {:.6}: ζ1 = {z1:.15} (η/2 = {}, relative {:.2e}), \
         ζ2 = {z2:.12} (η ω2/(2 W4) = {want2:.12}, relative {:.2e}); |λ1| = {:.6}",
        omega[0],
        omega[1],
        eta / 2.0,
        (z1 - eta / 2.0).abs() / (eta / 2.0),
        (z2 - want2).abs() / want2,
        roots[0].norm()
    );
    assert!((z1 - eta / 2.0).abs() < 1e-10 * eta, "ζ1 = {z1}");
    assert!((z2 - want2).abs() < 1e-9 * want2, "ζ2 = {z2}, want {want2}");
    assert!((roots[0].norm() - omega[0]).abs() < 1e-9 * omega[0]);
}

/// The readers' loss factors are the scene key's: the deck's MAT1 GE on the shim gives the
/// model B of `materials.pid_2.loss_factor` (the same MAT1 moduli), and an Abaqus input's
/// `*DAMPING, STRUCTURAL` on its shim the B of `materials.SHIM.loss_factor`.
#[test]
fn file_loss_factors_equal_the_scene_key() {
    let d = tmp("files");
    let eta = 0.3;
    let damping = format!("w4 = {W4:?}");
    let from_file = scene(&d, &pad_deck([None, Some(eta)]), "", &damping);
    let mf = model_of(&from_file, &d, "bdf_ge");
    let by_key = scene(&d, &pad_deck([None, None]), &mat_keys([0.0, eta]), &damping);
    let mk = model_of(&by_key, &d, "bdf_key");
    let r = rel(mf.b.as_ref().unwrap(), mk.b.as_ref().unwrap());
    eprintln!("MAT1 GE vs loss_factor key: B relative {r:.2e}");
    assert!(r < 1e-12, "{r:e}");
    assert!(
        mf.warnings.iter().all(|w| !w.message.contains("GE")),
        "{:?}",
        mf.warnings
    );

    // The same pad as an Abaqus input (element sets BACK and SHIM, C3D8).
    let deck = pad_deck([None, None]);
    let mut inp = String::from("*NODE\n");
    let mut back = String::new();
    let mut shim = String::new();
    let mut lines = deck.lines();
    while let Some(l) = lines.next() {
        let f: Vec<&str> = l.split(',').collect();
        match f[0] {
            "GRID" => inp += &format!("{}, {}, {}, {}\n", f[1], f[3], f[4], f[5]),
            "CHEXA" => {
                let cont: Vec<&str> = lines.next().unwrap().split(',').collect();
                let row = format!(
                    "{}, {}, {}\n",
                    f[1],
                    f[3..].join(", "),
                    cont[1..].join(", ")
                );
                if f[2] == "1" {
                    back += &row;
                } else {
                    shim += &row;
                }
            }
            _ => {}
        }
    }
    let material = |name: &str, (e, nu): (f64, f64), extra: &str| {
        format!("*MATERIAL, NAME={name}\n*ELASTIC\n{e:?}, {nu:?}\n*DENSITY\n1.0\n{extra}")
    };
    inp += &format!(
        "*ELEMENT, TYPE=C3D8, ELSET=BACK\n{back}*ELEMENT, TYPE=C3D8, ELSET=SHIM\n{shim}\
         *SOLID SECTION, ELSET=BACK, MATERIAL=STEEL\n*SOLID SECTION, ELSET=SHIM, MATERIAL=VISCO\n{}{}",
        material("STEEL", BACK, ""),
        material("VISCO", SHIM, &format!("*DAMPING, STRUCTURAL={eta:?}\n"))
    );
    std::fs::write(d.join("pad.inp"), &inp).unwrap();
    let inp_scene =
        |pad: &str| scene_with(&d, r#"{ kind = "inp", path = "pad.inp" }"#, pad, &damping);
    let s_file = inp_scene("");
    let mi = model_of(&s_file, &d, "inp_damping");
    let m = |(e, nu): (f64, f64), eta: f64| {
        format!("{{ young = {e:?}, poisson = {nu:?}, density = 1.0, loss_factor = {eta:?} }}")
    };
    let s_key = inp_scene(&format!(
        "materials = {{ BACK = {}, SHIM = {} }}",
        m(BACK, 0.0),
        m(SHIM, eta)
    ));
    let mik = model_of(&s_key, &d, "inp_key");
    let r_inp = rel(mi.b.as_ref().unwrap(), mik.b.as_ref().unwrap());
    // And the Abaqus route against the Nastran one (the same mesh and materials).
    let r_routes = rel(mi.b.as_ref().unwrap(), mf.b.as_ref().unwrap());
    eprintln!(
        "*DAMPING, STRUCTURAL vs loss_factor key: B relative {r_inp:.2e}; Abaqus vs Nastran \
         route {r_routes:.2e}"
    );
    assert!(r_inp < 1e-12, "{r_inp:e}");
    assert!(r_routes < 1e-10, "{r_routes:e}");
}

/// Bad values are errors naming the key and the value; a file's bad GE names the card.
#[test]
fn bad_loss_factors_are_named() {
    let d = tmp("bad");
    let deck = pad_deck([None, None]);
    std::fs::write(d.join("pad.bdf"), &deck).unwrap();
    for (v, shown) in [("-0.1", "-0.1"), ("nan", "NaN"), ("inf", "inf")] {
        let text = format!(
            "[[components]]\nname = \"pad\"\ngeometry = {{ kind = \"bdf\", path = \"pad.bdf\" }}\n\
             materials = {{ pid_2 = {{ young = 2.0e3, poisson = 0.45, density = 1.0, \
             loss_factor = {v} }} }}\n"
        );
        let e = Scene::from_toml_str(&text, d.clone(), &[])
            .unwrap_err()
            .to_string();
        eprintln!("loss_factor = {v}: {e}");
        assert!(
            e.contains("materials.pid_2.loss_factor") && e.contains(shown),
            "{v}: {e}"
        );
    }
    let s = scene(&d, &pad_deck([None, Some(-0.2)]), "", "w4 = 1.0");
    let run = RunDir::create(&d.join("run")).unwrap();
    let e = build(&s, &run, &Progress::quiet()).unwrap_err().to_string();
    eprintln!("MAT1 GE = -0.2: {e}");
    assert!(e.contains("MAT1 2") && e.contains("GE = -0.2"), "{e}");
    // Substructured reduction does not project a damping matrix: refused, naming the option.
    let s = scene(&d, &deck, &mat_keys([0.0, 0.3]), "w4 = 1.0");
    let mut s = s;
    s.reduction
        .get_or_insert_with(Default::default)
        .substructures
        .above_dofs = Some(10);
    let run = RunDir::create(&d.join("sub")).unwrap();
    let e = build(&s, &run, &Progress::quiet()).unwrap_err().to_string();
    eprintln!("substructured: {e}");
    assert!(
        e.contains("components[name = pad]") && e.contains("above_dofs = 10"),
        "{e}"
    );
}

/// The model cache key follows η and W4; the component cache keeps no entry for a
/// component whose loss factor is on (η > 0, W4 > 0), and the other components' entries are
/// read back to the same B.
#[test]
fn caches_account_for_the_loss_factor() {
    let d = tmp("cache");
    let deck = pad_deck([None, None]);
    let damping = format!("w4 = {W4:?}");
    let key = |pad: &str, damping: &str| ModelKey::of(&scene(&d, &deck, pad, damping)).unwrap();
    let k0 = key(&mat_keys([0.0, 0.0]), &damping);
    let k1 = key(&mat_keys([0.0, 0.3]), &damping);
    let k2 = key(&mat_keys([0.0, 0.3]), "w4 = 60.0");
    assert!(k0.hex != k1.hex && k1.hex != k2.hex);
    // Without a loss factor (no scene key, no Nastran or Abaqus file) W4 is not in the key.
    let plain = |w4: &str| {
        let text = common::plate_brake("", [1.0, 1.0], "");
        let s = Scene::from_toml_str(&text, d.clone(), &[w4.to_string()]).unwrap();
        ModelKey::of(&s).unwrap().hex
    };
    assert_eq!(plain("damping.w4=10.0"), plain("damping.w4=20.0"));
    // The file's GE is in the key through the deck's bytes.
    let kf = ModelKey::of(&scene(&d, &pad_deck([None, Some(0.3)]), "", &damping)).unwrap();
    let kg = ModelKey::of(&scene(&d, &pad_deck([None, Some(0.4)]), "", &damping)).unwrap();
    assert_ne!(kf.hex, kg.hex);

    let s = scene(&d, &deck, &mat_keys([0.0, 0.3]), &damping);
    let cache = ComponentCache {
        root: d.join("components"),
    };
    let q = Progress::quiet();
    let first = build_from_mesh_cached(
        &s,
        &RunDir::create(&d.join("c1")).unwrap(),
        &q,
        Some(&cache),
    )
    .unwrap();
    let second = build_from_mesh_cached(
        &s,
        &RunDir::create(&d.join("c2")).unwrap(),
        &q,
        Some(&cache),
    )
    .unwrap();
    let uses = |m: &Model| -> Vec<Option<bool>> {
        m.components
            .iter()
            .map(|c| c.reduction_cache.as_ref().map(|u| u.hit))
            .collect()
    };
    eprintln!(
        "component cache use: first {:?}, second {:?}",
        uses(&first),
        uses(&second)
    );
    assert_eq!(uses(&first), [None, Some(false)]);
    assert_eq!(uses(&second), [None, Some(true)]);
    let r = rel(second.b.as_ref().unwrap(), first.b.as_ref().unwrap());
    assert!(r < 1e-14, "{r:e}");
    // With W4 = 0 the pad is cached (η is off) and warned about.
    let s0 = scene(&d, &deck, &mat_keys([0.0, 0.3]), "");
    let m0 = build_from_mesh_cached(
        &s0,
        &RunDir::create(&d.join("c3")).unwrap(),
        &q,
        Some(&cache),
    )
    .unwrap();
    assert_eq!(uses(&m0), [Some(false), Some(true)]);
    assert!(m0.b.is_none());
    assert!(
        m0.warnings
            .iter()
            .any(|w| w.input == "components[name = pad].materials.pid_2.loss_factor"),
        "{:?}",
        m0.warnings
    );
}

/// An interface-reduced rotor (the plate brake, its contact face in a polynomial basis of
/// fixed degree) with η on its one body has the B of `damping.ge.rotor = η` (the interface
/// basis' columns reduce K_η as they reduce K); with the degree chosen by a tolerance (the
/// interface ladder, which reduces no damping matrix) the loss factor is refused, naming the
/// key.
#[test]
fn interface_reduction_with_a_loss_factor() {
    let d = tmp("interface");
    let eta = 0.1;
    let lossy = format!(
        "materials = {{ block = {{ young = 1.0e4, poisson = 0.3, density = 1.0, \
         loss_factor = {eta:?} }} }}"
    );
    let fixed = "interface = { degree = 4 }";
    let text_eta = common::plate_brake(&format!("{fixed}\n{lossy}"), [1.0, 1.0], "");
    let text_ge = common::plate_brake(fixed, [1.0, 1.0], "");
    let build_with = |text: &str, set: &[&str], name: &str| {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        let s = Scene::from_toml_str(text, d.clone(), &set).unwrap();
        let run = RunDir::create(&d.join(name)).unwrap();
        build(&s, &run, &Progress::quiet()).map_err(|e| e.to_string())
    };
    let w4 = "damping.w4=30.0";
    let m_eta = build_with(&text_eta, &[w4], "eta").unwrap();
    let m_ge = build_with(&text_ge, &[w4, &format!("damping.ge.rotor={eta:?}")], "ge").unwrap();
    assert!(m_eta.components[0].interface.is_some());
    let r = rel(m_eta.b.as_ref().unwrap(), m_ge.b.as_ref().unwrap());
    eprintln!(
        "interface-reduced rotor, η vs GE_c: B relative {r:.2e} (n = {})",
        m_eta.n()
    );
    assert!(r < 1e-12, "{r:e}");

    let ladder = "interface = { tolerance = 0.2, degree = 2 }";
    let text = common::plate_brake(&format!("{ladder}\n{lossy}"), [1.0, 1.0], "");
    let e = build_with(&text, &[w4], "ladder").unwrap_err();
    eprintln!("ladder: {e}");
    assert!(
        e.contains("components[name = rotor].interface.tolerance")
            && e.contains("volume `block` (0.1)"),
        "{e}"
    );
    // Without W4 the loss factor is off: the ladder builds, with the warning.
    let m = build_with(&text, &[], "ladder_off").unwrap();
    assert!(m
        .warnings
        .iter()
        .any(|w| w.input.contains("materials.block.loss_factor")));
}

/// The pad's moduli scaled by s (both bodies, the shim's η kept) scale its element damping,
/// the bodies' loss factors included: the model's B at s = 1.2 is B(1) + 0.2·∂B/∂s of
/// `component_matrix_derivative` (exact: a whole component's scale keeps its Craig–Bampton
/// basis at a fixed `n_modes`), and the volume derivative of the shim's modulus carries
/// (GE_c + η_shim)/W4 × its ∂K.
#[test]
fn moduli_derivatives_carry_the_loss_factor() {
    use squeal_pipeline::stages::cea::params::{component_matrix_derivative, ComponentProperty};
    use squeal_pipeline::stages::cea::volume::volume_matrix_derivative;
    let d = tmp("young_scale");
    let deck = pad_deck([None, None]);
    let (eta, ge) = (0.3, 0.05);
    let damping = format!("w4 = {W4:?}\nge = {{ pad = {ge:?} }}");
    let keys = |s: f64| {
        let m = |(e, nu): (f64, f64), eta: f64| {
            format!(
                "{{ young = {:?}, poisson = {nu:?}, density = 1.0, loss_factor = {eta:?} }}",
                s * e
            )
        };
        format!(
            "materials = {{ pid_1 = {}, pid_2 = {} }}",
            m(BACK, 0.0),
            m(SHIM, eta)
        )
    };
    let s1 = scene(&d, &deck, &keys(1.0), &damping);
    let m1 = model_of(&s1, &d, "s1");
    let m2 = model_of(&scene(&d, &deck, &keys(1.2), &damping), &d, "s12");
    let der = component_matrix_derivative(&s1, &m1, "pad", ComponentProperty::YoungScale).unwrap();
    let b1 = m1.b.as_ref().unwrap();
    let db = der.b.as_ref().unwrap();
    let pred = Mat::from_fn(b1.nrows(), b1.ncols(), |i, j| b1[(i, j)] + 0.2 * db[(i, j)]);
    let r = rel(&pred, m2.b.as_ref().unwrap());
    // Without the loss factors' part the prediction misses by the shim's share.
    let dk = der.k.as_ref().unwrap();
    let ge_only = Mat::from_fn(b1.nrows(), b1.ncols(), |i, j| {
        b1[(i, j)] + 0.2 * ge / W4 * dk[(i, j)]
    });
    let miss = rel(&ge_only, m2.b.as_ref().unwrap());
    eprintln!("young_scale 1.2: B predicted to {r:.2e} (GE_c's part alone: {miss:.2e})");
    assert!(r < 1e-9, "{r:e}");
    assert!(miss > 1e-3, "{miss:e}");

    let v =
        volume_matrix_derivative(&s1, &m1, "pad", "pid_2", ComponentProperty::YoungScale).unwrap();
    let (vk, vb) = (v.k.unwrap(), v.b.unwrap());
    let f = (ge + eta) / W4;
    let want = Mat::from_fn(vk.nrows(), vk.ncols(), |i, j| f * vk[(i, j)]);
    let rv = rel(&vb, &want);
    assert!(rv < 1e-14, "{rv:e}");
}

/// A pad whose shim is meshed apart and tied to the backplate (`[[ties]]` inside the
/// component: its slave DOFs eliminated by the component's MPC before the reduction): η on
/// both bodies is still `damping.ge.pad = η` (B_η goes through the MPC as K does).
#[test]
fn tied_bodies_take_the_mpc_transform() {
    let d = tmp("tied");
    let (nx, ny) = (4usize, 2usize);
    let id =
        |base: usize, i: usize, j: usize, k: usize| base + 1 + i + (nx + 1) * (j + (ny + 1) * k);
    let mut s = String::new();
    // Backplate: grids 1.., z = 0, 0.1, 0.2; shim: grids 1001.., z = 0.2, 0.3.
    for (base, zs) in [(0, vec![0.0, 0.1, 0.2]), (1000, vec![0.2, 0.3])] {
        for (k, z) in zs.iter().enumerate() {
            for j in 0..=ny {
                for i in 0..=nx {
                    s += &format!(
                        "GRID,{},,{:?},{:?},{z:?}\n",
                        id(base, i, j, k),
                        i as f64 * 0.25,
                        j as f64 * 0.25
                    );
                }
            }
        }
    }
    let mut e = 1;
    for (base, layers, pid) in [(0, 2, 1), (1000, 1, 2)] {
        for k in 0..layers {
            for j in 0..ny {
                for i in 0..nx {
                    let g = |di: usize, dj: usize, dk: usize| id(base, i + di, j + dj, k + dk);
                    s += &format!(
                        "CHEXA,{e},{pid},{},{},{},{},{},{}\n,{},{}\n",
                        g(0, 0, 0),
                        g(1, 0, 0),
                        g(1, 1, 0),
                        g(0, 1, 0),
                        g(0, 0, 1),
                        g(1, 0, 1),
                        g(1, 1, 1),
                        g(0, 1, 1)
                    );
                    e += 1;
                }
            }
        }
    }
    // Faces: the backplate's top (PSHELL 9), the shim's bottom (PSHELL 8).
    for j in 0..ny {
        for i in 0..nx {
            for (base, k, pid) in [(0, 2, 9), (1000, 0, 8)] {
                s += &format!(
                    "CQUAD4,{e},{pid},{},{},{},{}\n",
                    id(base, i, j, k),
                    id(base, i + 1, j, k),
                    id(base, i + 1, j + 1, k),
                    id(base, i, j + 1, k)
                );
                e += 1;
            }
        }
    }
    s += "PSHELL,8\nPSHELL,9\n";
    for (mid, (young, nu)) in [(1, BACK), (2, SHIM)] {
        s += &format!("PSOLID,{mid},{mid}\nMAT1,{mid},{young:?},,{nu:?},1.0\n");
    }
    std::fs::write(d.join("tied.bdf"), s).unwrap();
    let text = |pad: &str, damping: &str| {
        format!(
            r#"
[[components]]
name = "pad"
geometry = {{ kind = "bdf", path = "tied.bdf" }}
{pad}

[[components]]
name = "support"
element = "hex8"
geometry = {{ kind = "block", origin = [1.0, 0.0, 0.0], lx = 1.0, ly = 0.5, lz = 0.1, nx = 4, ny = 2, nz = 1 }}
material = {{ young = 2.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x1" }}]

[[ties]]
a = {{ component = "pad", faces = "pid_8" }}
b = {{ component = "pad", faces = "pid_9" }}

[reduction]
n_modes = 8
checks = false

[damping]
{damping}
"#
        )
    };
    let eta = 0.25;
    let s_ge = Scene::from_toml_str(
        &text(
            &mat_keys([0.0, 0.0]),
            &format!("w4 = {W4:?}\nge = {{ pad = {eta:?} }}"),
        ),
        d.clone(),
        &[],
    )
    .unwrap();
    let s_eta = Scene::from_toml_str(
        &text(&mat_keys([eta, eta]), &format!("w4 = {W4:?}")),
        d.clone(),
        &[],
    )
    .unwrap();
    let (m_ge, m_eta) = (model_of(&s_ge, &d, "ge"), model_of(&s_eta, &d, "eta"));
    let rec = m_eta.recovery.iter().find(|r| r.name == "pad").unwrap();
    assert!(rec.mpc.is_some(), "the tie is the pad's MPC");
    let r = rel(m_eta.b.as_ref().unwrap(), m_ge.b.as_ref().unwrap());
    eprintln!("tied shim: η on both bodies vs GE_c, B relative {r:.2e}");
    assert!(r < 1e-12, "{r:e}");
}
