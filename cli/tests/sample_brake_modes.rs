//! `squeal modes` on the sample brake's components (examples/sample-brake/components.toml):
//! the two-material pad free-free against a composite-beam estimate, the hub-clamped rotor's
//! modes in the squeal band.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("examples/sample-brake/components.toml")
}

/// Runs `squeal modes` on one component and returns its frequencies (Hz).
fn modes(component: &str, extra: &[&str]) -> Vec<f64> {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("sample-brake-{component}"));
    let _ = std::fs::remove_dir_all(&out);
    let res = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["modes", "-q"])
        .arg(scene())
        .args(["--component", component, "--out"])
        .arg(&out)
        .args(extra)
        .output()
        .expect("run squeal");
    assert!(
        res.status.success(),
        "{}",
        String::from_utf8_lossy(&res.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("modes.json")).unwrap()).unwrap();
    let f: Vec<f64> = json["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    eprintln!("{component}: {f:.1?}");
    f
}

/// First free-free bending frequency of an Euler–Bernoulli beam of length `l` whose section is
/// a steel backplate (thickness `tb`) under a lining (thickness `tl`), width `b`:
/// f₁ = (4.7300)²/(2π l²)·√(EI/ρA) with EI of the transformed section (Timoshenko & Young,
/// Vibration Problems in Engineering, free-free beam, β₁l = 4.7300).
#[allow(non_snake_case)]
fn composite_beam_f1(
    l: f64,
    b: f64,
    tb: f64,
    tl: f64,
    steel: (f64, f64),
    lining: (f64, f64),
) -> f64 {
    let (es, rs) = steel;
    let (el, rl) = lining;
    let n = el / es;
    let (a_s, a_l) = (b * tb, n * b * tl);
    let (z_s, z_l) = (tb / 2.0, tb + tl / 2.0);
    let zc = (a_s * z_s + a_l * z_l) / (a_s + a_l);
    let I = b * tb.powi(3) / 12.0
        + a_s * (z_s - zc).powi(2)
        + n * b * tl.powi(3) / 12.0
        + a_l * (z_l - zc).powi(2);
    let EI = es * I;
    let rhoA = rs * b * tb + rl * b * tl;
    4.7300f64.powi(2) / (2.0 * std::f64::consts::PI * l * l) * (EI / rhoA).sqrt()
}

/// The free-free pad: six rigid-body modes, then a first bending mode along the arc. The
/// reference is the composite Euler–Bernoulli beam over the arc length at the mean radius
/// (4.625 in × 56.25° = 4.540 in), width 1.75 in, 0.2 in steel under 0.4 in lining (the
/// scene's values). Shear deformation (length/depth 7.6), the soft lining's shear and the
/// curvature make the solid lower than the beam, by less than 15 %. Swapping the two materials
/// (a wrong volume-block order) would give a frequency 1.7 times higher.
#[test]
fn free_free_pad_first_bending_is_near_the_composite_beam() {
    let f = modes("inboard_pad", &[]);
    assert!(f[..6].iter().all(|v| v.abs() < 1.0), "rigid modes {f:?}");
    let l = 4.625 * 56.25f64.to_radians();
    let fb = composite_beam_f1(l, 1.75, 0.2, 0.4, (3.0e7, 7.33e-4), (1.0e6, 2.5e-4));
    let ratio = f[6] / fb;
    eprintln!("pad f7 = {:.1} Hz, beam {fb:.1} Hz, ratio {ratio:.3}", f[6]);
    assert!(
        ratio > 0.85 && ratio < 1.0,
        "f7 = {} Hz vs beam {fb} Hz",
        f[6]
    );
}

/// The hub-clamped rotor has several modes in the squeal band 2–10 kHz (the paper's
/// "2000 to 10000 Hz"), the design requirement of the default geometry.
#[test]
fn clamped_rotor_has_modes_in_the_squeal_band() {
    let f = modes("rotor", &[]);
    let band = f
        .iter()
        .filter(|&&v| (2000.0..=10000.0).contains(&v))
        .count();
    assert!(band >= 10, "{band} rotor modes in 2-10 kHz: {f:?}");
}
