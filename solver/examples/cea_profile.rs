//! Profiles one CEA on matrices written by `squeal-pipeline`'s `cea_dump` example.
//!
//! ```text
//! cargo run --release -p squeal-solver --example cea_profile -- DIR [exact] [dense_basis] [basis] [micro]
//! ```
//! `exact`: the dense CEA; `dense_basis`: `projection.basis_solver = "dense"`; `basis`: only
//! build the basis (twice, timed); `micro`: time the dense kernels of a refinement step.

use faer::Mat;
use squeal_solver::cea::{complex_eigen, CeaMatrices, CeaMethod, CeaOptions};
use std::path::Path;
use std::time::Instant;

fn read(dir: &Path, name: &str, meta: &serde_json::Value) -> Option<Mat<f64>> {
    let shape = meta.get(name)?;
    let (r, c) = (shape[0].as_u64()? as usize, shape[1].as_u64()? as usize);
    let b = std::fs::read(dir.join(format!("{name}.f64"))).ok()?;
    Some(Mat::from_fn(r, c, |i, j| {
        let k = 8 * (i * c + j);
        f64::from_le_bytes(b[k..k + 8].try_into().unwrap())
    }))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let dir = Path::new(&argv[0]);
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("dump.json"))?)?;
    let mut opts: CeaOptions = serde_json::from_value(meta["options"].clone())?;
    if argv.iter().any(|a| a == "exact") {
        opts.method = CeaMethod::Exact;
    }
    let sys = CeaMatrices {
        m: read(dir, "m", &meta).ok_or("m")?,
        k: read(dir, "k", &meta).ok_or("k")?,
        b: read(dir, "b", &meta),
        g: read(dir, "g", &meta),
        d: read(dir, "d", &meta),
        c_f: read(dir, "c_f", &meta),
    };
    if argv.iter().any(|a| a == "dense_basis") {
        opts.projection.basis_solver = squeal_solver::cea::BasisSolver::Dense;
    }
    if argv.iter().any(|a| a == "basis") {
        for _ in 0..2 {
            let t = Instant::now();
            let b = squeal_solver::cea::ModalBasis::new(&sys, &opts)?;
            eprintln!(
                "basis {} modes, {:.2} s",
                b.len(),
                t.elapsed().as_secs_f64()
            );
        }
        return Ok(());
    }
    if argv.iter().any(|a| a == "micro") {
        micro(&sys.m, sys.g.as_ref().map_or(0, |g| g.nrows()));
        return Ok(());
    }
    let t = Instant::now();
    let r = complex_eigen(&sys, &opts)?;
    let wall = t.elapsed().as_secs_f64();
    let band = opts.projection.frequency_max_hz.unwrap_or(f64::INFINITY);
    let unstable: Vec<[f64; 2]> = r
        .modes
        .iter()
        .filter(|m| m.unstable && m.frequency_hz <= band)
        .map(|m| [m.eigenvalue.re, m.eigenvalue.im])
        .collect();
    let mut st = serde_json::to_value(&r.stats)?;
    if let Some(rf) = st.get_mut("refine") {
        rf.as_object_mut().unwrap().remove("roots");
    }
    println!(
        "{}",
        serde_json::to_string_pretty(&serde_json::json!({
            "wall_s": wall, "unstable_in_band": unstable, "stats": st,
        }))?
    );
    Ok(())
}

/// Times the kernels of one refinement step on M's size: products with n × 2 and n × 1
/// right-hand sides, real and complex LU of size n + ng and their solves.
fn micro(m: &Mat<f64>, ng: usize) {
    use faer::c64;
    use faer::linalg::solvers::Solve;
    let n = m.nrows();
    let x = Mat::from_fn(n, 2, |i, j| (i + j) as f64 * 1e-3);
    let t = Instant::now();
    for _ in 0..20 {
        let _y = m * &x;
    }
    eprintln!(
        "M*X(n x 2): {:.2} ms",
        t.elapsed().as_secs_f64() / 20.0 * 1e3
    );
    let xr = Mat::from_fn(n, 1, |i, _| i as f64 * 1e-3);
    let t = Instant::now();
    for _ in 0..20 {
        let _y = m * &xr;
    }
    eprintln!(
        "M*x(n x 1): {:.2} ms",
        t.elapsed().as_secs_f64() / 20.0 * 1e3
    );
    let nn = n + ng;
    let q = Mat::<c64>::from_fn(nn, nn, |i, j| {
        c64::new(
            if i == j {
                10.0
            } else {
                ((i * 7 + j * 13) % 17) as f64 * 1e-2
            },
            0.1,
        )
    });
    let t = Instant::now();
    let lu = q.partial_piv_lu();
    eprintln!("complex LU {nn}: {:.2} s", t.elapsed().as_secs_f64());
    let qr = Mat::<f64>::from_fn(nn, nn, |i, j| {
        if i == j {
            10.0
        } else {
            ((i * 7 + j * 13) % 17) as f64 * 1e-2
        }
    });
    let t = Instant::now();
    let lur = qr.partial_piv_lu();
    eprintln!("real LU {nn}: {:.2} s", t.elapsed().as_secs_f64());
    let mut b = Mat::<c64>::from_fn(nn, 1, |i, _| c64::new(i as f64, 1.0));
    let t = Instant::now();
    for _ in 0..20 {
        lu.solve_in_place(&mut b);
    }
    eprintln!(
        "complex solve 1 rhs: {:.2} ms",
        t.elapsed().as_secs_f64() / 20.0 * 1e3
    );
    let mut b = Mat::<c64>::from_fn(nn, 8, |i, _| c64::new(i as f64, 1.0));
    let t = Instant::now();
    for _ in 0..5 {
        lu.solve_in_place(&mut b);
    }
    eprintln!(
        "complex solve 8 rhs: {:.2} ms",
        t.elapsed().as_secs_f64() / 5.0 * 1e3
    );
    let mut b = Mat::<f64>::from_fn(nn, 2, |i, _| i as f64);
    let t = Instant::now();
    for _ in 0..20 {
        lur.solve_in_place(&mut b);
    }
    eprintln!(
        "real solve 2 rhs: {:.2} ms",
        t.elapsed().as_secs_f64() / 20.0 * 1e3
    );
}
