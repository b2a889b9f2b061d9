//! Minimal free-free hex8 model for the Craig–Bampton tests: structured box and annulus
//! meshes, plain trilinear hex8 (2×2×2 Gauss) stiffness and consistent mass, sparse assembly.
use super::*;

/// Nodes and hex8 cells (squeal/VTK node order).
pub struct Hexes {
    pub nodes: Vec<[f64; 3]>,
    pub cells: Vec<[usize; 8]>,
}

fn cell(id: impl Fn(usize, usize, usize) -> usize, i: usize, j: usize, k: usize) -> [usize; 8] {
    [
        id(i, j, k),
        id(i + 1, j, k),
        id(i + 1, j + 1, k),
        id(i, j + 1, k),
        id(i, j, k + 1),
        id(i + 1, j, k + 1),
        id(i + 1, j + 1, k + 1),
        id(i, j + 1, k + 1),
    ]
}

/// Box [0,l]³ shifted by `origin`, n elements per direction; node (i,j,k) has index
/// i + (nx+1)(j + (ny+1)k).
pub fn box_mesh(n: [usize; 3], l: [f64; 3], origin: [f64; 3]) -> Hexes {
    let [nx, ny, nz] = n;
    let id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
    let mut nodes = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push([
                    origin[0] + l[0] * i as f64 / nx as f64,
                    origin[1] + l[1] * j as f64 / ny as f64,
                    origin[2] + l[2] * k as f64 / nz as f64,
                ]);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                cells.push(cell(id, i, j, k));
            }
        }
    }
    Hexes { nodes, cells }
}

/// Annulus r_in..r_out, thickness t (z from 0), nr × nt × nz elements; node (i,j,k) =
/// (radial, circumferential, axial) has index i + (nr+1)(j + nt k).
pub fn annulus_mesh(r_in: f64, r_out: f64, t: f64, nr: usize, nt: usize, nz: usize) -> Hexes {
    let id = |i: usize, j: usize, k: usize| i + (nr + 1) * ((j % nt) + nt * k);
    let mut nodes = Vec::new();
    for k in 0..=nz {
        for j in 0..nt {
            for i in 0..=nr {
                let r = r_in + (r_out - r_in) * i as f64 / nr as f64;
                let th = 2.0 * std::f64::consts::PI * j as f64 / nt as f64;
                nodes.push([r * th.cos(), r * th.sin(), t * k as f64 / nz as f64]);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..nt {
            for i in 0..nr {
                cells.push(cell(id, i, j, k));
            }
        }
    }
    Hexes { nodes, cells }
}

const XI: [[f64; 3]; 8] = [
    [-1., -1., -1.],
    [1., -1., -1.],
    [1., 1., -1.],
    [-1., 1., -1.],
    [-1., -1., 1.],
    [1., -1., 1.],
    [1., 1., 1.],
    [-1., 1., 1.],
];

/// Stiffness and consistent mass (24×24) of one hex8, isotropic, 2×2×2 Gauss.
fn hex8(x: &[[f64; 3]; 8], e: f64, nu: f64, rho: f64) -> (Vec<f64>, Vec<f64>) {
    let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let mut d = [[0.0; 6]; 6];
    for a in 0..3 {
        for b in 0..3 {
            d[a][b] = lam;
        }
        d[a][a] = lam + 2.0 * mu;
        d[a + 3][a + 3] = mu;
    }
    let g = 1.0 / 3f64.sqrt();
    let mut ke = vec![0.0; 576];
    let mut me = vec![0.0; 576];
    for gp in XI.iter() {
        let q = [gp[0] * g, gp[1] * g, gp[2] * g];
        let mut n = [0.0; 8];
        let mut dn = [[0.0; 3]; 8];
        for a in 0..8 {
            let f = [
                1.0 + XI[a][0] * q[0],
                1.0 + XI[a][1] * q[1],
                1.0 + XI[a][2] * q[2],
            ];
            n[a] = f[0] * f[1] * f[2] / 8.0;
            dn[a] = [
                XI[a][0] * f[1] * f[2] / 8.0,
                XI[a][1] * f[0] * f[2] / 8.0,
                XI[a][2] * f[0] * f[1] / 8.0,
            ];
        }
        let mut j = [[0.0; 3]; 3];
        for a in 0..8 {
            for r in 0..3 {
                for c in 0..3 {
                    j[r][c] += dn[a][r] * x[a][c];
                }
            }
        }
        let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
            - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
            + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
        assert!(det > 0.0, "inverted element");
        let inv = [
            [
                (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
                (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
                (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
            ],
            [
                (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
                (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
                (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
            ],
            [
                (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
                (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
                (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
            ],
        ];
        // dN/dx = J⁻¹ dN/dξ
        let mut gx = [[0.0; 3]; 8];
        for a in 0..8 {
            for r in 0..3 {
                gx[a][r] = (0..3).map(|c| inv[r][c] * dn[a][c]).sum();
            }
        }
        let mut bm = vec![[0.0; 24]; 6];
        for a in 0..8 {
            let [gxa, gya, gza] = gx[a];
            bm[0][3 * a] = gxa;
            bm[1][3 * a + 1] = gya;
            bm[2][3 * a + 2] = gza;
            bm[3][3 * a] = gya;
            bm[3][3 * a + 1] = gxa;
            bm[4][3 * a + 1] = gza;
            bm[4][3 * a + 2] = gya;
            bm[5][3 * a] = gza;
            bm[5][3 * a + 2] = gxa;
        }
        let mut db = vec![[0.0; 24]; 6];
        for r in 0..6 {
            for c in 0..24 {
                db[r][c] = (0..6).map(|s| d[r][s] * bm[s][c]).sum();
            }
        }
        for r in 0..24 {
            for c in 0..24 {
                ke[r * 24 + c] += det * (0..6).map(|s| bm[s][r] * db[s][c]).sum::<f64>();
            }
        }
        for a in 0..8 {
            for b in 0..8 {
                for c in 0..3 {
                    me[(3 * a + c) * 24 + 3 * b + c] += det * rho * n[a] * n[b];
                }
            }
        }
    }
    (ke, me)
}

/// Assembled K and M over all 3 n_nodes DOFs (DOF = 3 node + comp), free-free.
pub fn assemble(h: &Hexes, e: f64, nu: f64, rho: f64) -> (Sparse, Sparse) {
    let (mut tk, mut tm) = (Vec::new(), Vec::new());
    for c in &h.cells {
        let x: [[f64; 3]; 8] = std::array::from_fn(|a| h.nodes[c[a]]);
        let (ke, me) = hex8(&x, e, nu, rho);
        for r in 0..24 {
            for s in 0..24 {
                let (gr, gs) = (3 * c[r / 3] + r % 3, 3 * c[s / 3] + s % 3);
                tk.push(Triplet::new(gr, gs, ke[r * 24 + s]));
                if me[r * 24 + s] != 0.0 {
                    tm.push(Triplet::new(gr, gs, me[r * 24 + s]));
                }
            }
        }
    }
    let n = 3 * h.nodes.len();
    (
        SparseColMat::try_new_from_triplets(n, n, &tk).unwrap(),
        SparseColMat::try_new_from_triplets(n, n, &tm).unwrap(),
    )
}

/// DOF points of all 3 n_nodes DOFs.
pub fn points(h: &Hexes) -> Vec<DofPoint> {
    cb::dof_points(&h.nodes, 3 * h.nodes.len(), |i| (i / 3, i % 3))
}

/// All three DOFs of the given nodes.
pub fn dofs_of(nodes: &[usize]) -> Vec<usize> {
    nodes
        .iter()
        .flat_map(|&n| [3 * n, 3 * n + 1, 3 * n + 2])
        .collect()
}

/// Dense copy.
pub fn dense(a: &Sparse) -> Mat<f64> {
    a.to_dense()
}

/// Keeps rows/columns `keep` of a sparse matrix (dense result).
pub fn restrict(a: &Sparse, keep: &[usize]) -> Mat<f64> {
    let d = a.to_dense();
    Mat::from_fn(keep.len(), keep.len(), |i, j| d[(keep[i], keep[j])])
}

/// Sparse `a` times dense `x`.
pub fn dense_times(a: &Sparse, x: &Mat<f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), x.ncols());
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    for c in 0..x.ncols() {
        for j in 0..a.ncols() {
            let xj = x[(j, c)];
            if xj == 0.0 {
                continue;
            }
            for p in cp[j]..cp[j + 1] {
                out[(ri[p], c)] += v[p] * xj;
            }
        }
    }
    out
}
