//! Craig–Bampton reduction of one component.

use super::eigen::{self, LanczosParams, Want};
use super::factor::KiiFactor;
use super::interface::{project_blocks, project_ib_bb, sparse_of, BbRef, InterfaceBasis};
use super::model::{peak_rss_kib, CbModel, CbStats, EigenMethod, PhaseMemory};
use super::options::CbOptions;
use super::partition::{at_b, check_square, split, sym_spmm, to_dense, Blocks, Partition, Sparse};
use crate::error::ReductionError;
use faer::{Mat, MatRef};
use rayon::prelude::*;
use squeal_meshes::Real;
use std::f64::consts::PI;
use std::time::Instant;

/// Craig–Bampton reduction of a component with stiffness `k` and mass `m` (sparse, full
/// symmetric storage, over the component's free DOFs) onto the `boundary` free DOFs and the
/// fixed-interface modes chosen by `opts`. See [`reduce_damped`].
pub fn reduce(
    k: &Sparse,
    m: &Sparse,
    boundary: &[usize],
    opts: &CbOptions,
) -> Result<CbModel, ReductionError> {
    reduce_damped(k, m, None, boundary, opts)
}

/// Craig–Bampton reduction, also reducing a viscous damping matrix `b` when given.
///
/// K, M and B must be symmetric with full storage (checked: an asymmetric entry is an error);
/// the products below use that symmetry.
///
/// # Derivation
/// Partition u = [u_b, u_i]. The constraint modes Ψ = −K_ii⁻¹ K_ib (one sparse Cholesky of
/// K_ii, many right-hand sides) give the interior's static response to boundary motion; the
/// fixed-interface modes Φ solve K_ii Φ = M_ii Φ diag(ω²), ΦᵀM_iiΦ = I. With
/// T = [[I, 0], [Ψ, Φ]] and x = [u_b, q]:
///
/// K_r = TᵀKT = [[K_bb + K_bi Ψ, 0], [0, diag ω²]]  (K_ii Ψ + K_ib = 0 kills the coupling),
/// M_r = TᵀMT = [[M_bb + ΨᵀM_ib + M_biΨ + ΨᵀM_iiΨ, (M_bi + ΨᵀM_ii)Φ], [·ᵀ, I]].
///
/// Computed as W = M_ii Ψ + M_ib (sparse × dense), M̂_bb = M_bb + M_ibᵀΨ + ΨᵀW, M_bq = WᵀΦ.
pub fn reduce_damped(
    k: &Sparse,
    m: &Sparse,
    b: Option<&Sparse>,
    boundary: &[usize],
    opts: &CbOptions,
) -> Result<CbModel, ReductionError> {
    reduce_ordered(k, m, b, boundary, opts, None)
}

/// [`reduce_damped`] with the coordinates of every free DOF (`dof_coords[i]`: the point of
/// DOF i, e.g. `squeal_fe::dof_coordinates`): K_ii is then factorised in a geometric
/// nested-dissection ordering when it has at least 20 000 DOFs (AMD otherwise, and without
/// coordinates). Same matrices to round-off; on solid meshes the factor is smaller and every
/// solve (constraint modes, Lanczos) faster.
pub fn reduce_ordered(
    k: &Sparse,
    m: &Sparse,
    b: Option<&Sparse>,
    boundary: &[usize],
    opts: &CbOptions,
    dof_coords: Option<&[[Real; 3]]>,
) -> Result<CbModel, ReductionError> {
    reduce_interface(k, m, b, boundary, None, opts, dof_coords)
}

/// [`reduce_ordered`] with part of the boundary reduced to an interface basis: the boundary
/// is `boundary` (kept as physical coordinates) followed by `interface.dofs`, which move as
/// u_f = L p (`interface.basis`). `None` is the exact Craig–Bampton reduction.
///
/// # Derivation
/// The boundary coordinates are x_b = [u_kept, p] with u_b = blockdiag(I, L) x_b =: L̂ x_b.
/// Craig–Bampton on x_b is the exact one restricted to boundary motions in the range of L̂:
/// T = [[L̂, 0], [Ψ, Φ]] with Ψ = −K_ii⁻¹ K_ib L̂ (one solve per column of L̂). Every formula
/// of [`reduce_damped`] holds with A_ib → A_ib L̂ and A_bb → L̂ᵀA_bb L̂, which is how the
/// blocks are transformed before the reduction. The fixed-interface modes Φ do not change.
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn reduce_interface(
    k: &Sparse,
    m: &Sparse,
    b: Option<&Sparse>,
    boundary: &[usize],
    interface: Option<&InterfaceBasis>,
    opts: &CbOptions,
    dof_coords: Option<&[[Real; 3]]>,
) -> Result<CbModel, ReductionError> {
    opts.validate()?;
    if let Some(f) = interface {
        f.validate()?;
    }
    if let Some(c) = dof_coords {
        if c.len() != k.nrows() {
            return Err(ReductionError::InvalidOption {
                field: "dof_coords",
                value: c.len().to_string(),
                reason: format!("one point per DOF: K has {} rows", k.nrows()),
            });
        }
    }
    let t_start = Instant::now();
    let n = k.nrows();
    check_square(k, n, "stiffness K")?;
    check_square(m, n, "mass M")?;
    if let Some(b) = b {
        check_square(b, n, "damping B")?;
    }
    let n_interior = n - boundary.len() - interface.map_or(0, |f| f.dofs.len());
    if let (Some(above), Some(c)) = (opts.substructures.above_dofs, dof_coords) {
        if n_interior > above {
            if b.is_some() {
                return Err(ReductionError::InvalidOption {
                    field: "substructures.above_dofs",
                    value: above.to_string(),
                    reason: "a damping matrix is not reduced by substructures".into(),
                });
            }
            return super::multilevel::reduce(k, m, boundary, interface, opts, c);
        }
    }
    let iface_dofs = interface.map_or(&[][..], |f| f.dofs.as_slice());
    // Projected at once: the unprojected A_bb (dense, over every interface DOF) is not kept.
    let basis = interface.map(|f| f.basis.as_ref());
    let interior = Interior::new(
        k, m, b, boundary, iface_dofs, basis, opts, dof_coords, t_start,
    )?;
    let (kib, kbb) = interior.project_k(None);
    let t = Instant::now();
    let psi = interior.constraint_modes(&kib, opts)?;
    let constraint_modes_s = t.elapsed().as_secs_f64();
    let nb = kib.ncols();
    interior.finish(
        boundary,
        interface,
        (kib, kbb),
        psi,
        (constraint_modes_s, nb),
        opts,
        t_start,
    )
}

/// The part of a Craig–Bampton reduction that does not depend on how the boundary moves: the
/// partition into interior and boundary DOFs (kept boundary DOFs, then the interface DOFs),
/// the K_ii factor and the fixed-interface modes. [`reduce_interface`] uses it once; the
/// interface ladder ([`super::InterfaceLadder`]) reduces with several interface bases on it.
pub(crate) struct Interior {
    n: usize,
    part: Partition,
    n_kept: usize,
    /// The blocks below are already in the interface basis's coordinates.
    projected: bool,
    /// K, M (and B) split on the boundary [kept, interface DOFs] (unless `projected`).
    k: Blocks,
    m: Blocks,
    b: Option<Blocks>,
    /// Unless `projected`: their A_bb blocks, sparse (over every interface DOF a dense A_bb
    /// would be (kept + interface DOFs)² numbers); the Blocks' own `bb` are then empty.
    bb_sparse: Option<(Sparse, Sparse, Option<Sparse>)>,
    llt: Option<KiiFactor>,
    factor_info: Option<super::factor::FactorInfo>,
    nnz_kii: usize,
    lambda: Vec<Real>,
    phi: Mat<Real>,
    method: EigenMethod,
    krylov_dim: usize,
    eig_solves: usize,
    eigen_split_s: (Real, Real, Real),
    cutoff_hz: Option<Real>,
    partition_s: Real,
    factor_s: Real,
    eigen_s: Real,
    mem: PhaseMemory,
}

#[allow(non_snake_case)]
impl Interior {
    /// Partitions, factorises K_ii and solves the fixed-interface eigenproblem. With
    /// `project`, the boundary blocks are projected on that interface basis at once (and
    /// [`Self::project_k`] and [`Self::finish`] take no other); without, they are kept over
    /// the interface DOFs for any basis later.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        k: &Sparse,
        m: &Sparse,
        b: Option<&Sparse>,
        boundary: &[usize],
        iface_dofs: &[usize],
        project: Option<MatRef<'_, Real>>,
        opts: &CbOptions,
        dof_coords: Option<&[[Real; 3]]>,
        t_start: Instant,
    ) -> Result<Self, ReductionError> {
        let n = k.nrows();
        let all_boundary: Vec<usize> = boundary.iter().chain(iface_dofs).copied().collect();
        let part = Partition::new(n, &all_boundary)?;
        drop(all_boundary);
        let ni = part.interior.len();
        let nk = boundary.len();
        let proj = |blocks: Blocks| match project {
            Some(l) => project_blocks(blocks, nk, l),
            None => blocks,
        };
        let mut Kp = proj(split(k, &part));
        let mut Mp = proj(split(m, &part));
        let mut Bp = b.map(|b| proj(split(b, &part)));
        let bb_sparse = match project {
            Some(_) => None,
            None => {
                let take = |blocks: &mut Blocks| {
                    let s = sparse_of(&blocks.bb);
                    blocks.bb = Mat::zeros(0, 0);
                    s
                };
                Some((take(&mut Kp), take(&mut Mp), Bp.as_mut().map(take)))
            }
        };
        let mut mem = PhaseMemory {
            partition: peak_rss_kib(),
            ..Default::default()
        };
        let partition_s = t_start.elapsed().as_secs_f64();

        // One sparse Cholesky of K_ii.
        opts.check_interrupt("the Craig–Bampton partition")?;
        let t = Instant::now();
        let interior_coords: Option<Vec<[Real; 3]>> =
            dof_coords.map(|c| part.interior.iter().map(|&i| c[i]).collect());
        let (llt, factor_info) = if ni > 0 {
            let (f, info) = KiiFactor::new(&Kp.ii, interior_coords.as_deref())?;
            (Some(f), Some(info))
        } else {
            (None, None)
        };
        drop(interior_coords);
        mem.factor = peak_rss_kib();
        let factor_s = t.elapsed().as_secs_f64();

        // Fixed-interface modes of (K_ii, M_ii).
        opts.check_interrupt("the factorisation of K_ii")?;
        let t = Instant::now();
        let cutoff_hz = opts.resolved_cutoff_hz();
        let want = Want {
            lambda_max: cutoff_hz.map(|f| (2.0 * PI * f).powi(2)),
            n_max: opts.n_modes,
        };
        let (pairs, method) = match &llt {
            _ if ni == 0 || opts.n_modes == Some(0) => (None, EigenMethod::None),
            Some(_) if ni <= opts.dense_max => {
                let p = eigen::dense(
                    to_dense(&Kp.ii).as_ref(),
                    to_dense(&Mp.ii).as_ref(),
                    want,
                    "fixed-interface K_ii, M_ii",
                )?;
                (Some(p), EigenMethod::Dense)
            }
            Some(llt) => {
                // One traversal of the factor per thread: split the block's columns evenly.
                let threads = if llt.is_parallel() {
                    1
                } else {
                    rayon::current_num_threads()
                };
                let solve = |x: faer::MatMut<'_, Real>| {
                    let chunk = x.ncols().div_ceil(threads).max(1);
                    x.par_col_chunks_mut(chunk)
                        .for_each(|b| llt.solve_in_place(b));
                };
                let params = LanczosParams {
                    block: opts.lanczos_block,
                    max_dim: opts.lanczos_max_dim,
                    tol: opts.lanczos_tol,
                };
                let p = eigen::lanczos(
                    &solve,
                    &Mp.ii,
                    0.0,
                    want,
                    params,
                    "fixed-interface K_ii, M_ii",
                    &opts.interrupt,
                )?;
                (Some(p), EigenMethod::BlockLanczos)
            }
            None => (None, EigenMethod::None),
        };
        let eigen_split_s = pairs
            .as_ref()
            .map_or((0.0, 0.0, 0.0), |p| (p.solve_s, p.orth_s, p.qr_s));
        let (lambda, phi, krylov_dim, eig_solves) = match pairs {
            Some(p) => (p.values, p.vectors, p.krylov_dim, p.n_solves),
            None => (Vec::new(), Mat::<Real>::zeros(ni, 0), 0, 0),
        };
        mem.eigen = peak_rss_kib();
        let eigen_s = t.elapsed().as_secs_f64();
        // K_ii is in the factor now, its modes found; the products read K_ib and K_bb only.
        let nnz_kii = Kp.ii.val().len();
        Kp.ii = Sparse::try_new_from_triplets(0, 0, &[]).map_err(|e| {
            ReductionError::Factorization {
                what: "freeing K_ii".into(),
                n: 0,
                detail: format!("{e:?}"),
            }
        })?;
        Ok(Self {
            n,
            part,
            n_kept: nk,
            projected: project.is_some(),
            k: Kp,
            m: Mp,
            b: Bp,
            bb_sparse,
            llt,
            factor_info,
            nnz_kii,
            lambda,
            phi,
            method,
            krylov_dim,
            eig_solves,
            eigen_split_s,
            cutoff_hz,
            partition_s,
            factor_s,
            eigen_s,
            mem,
        })
    }

    /// Interior DOFs.
    pub(crate) fn n_interior(&self) -> usize {
        self.part.interior.len()
    }

    /// A_ib and A_bb of `blocks` (`bb`: its sparse A_bb when kept so) in the boundary
    /// coordinates [u_kept, p] of `basis`; None: the blocks as they are.
    fn project(
        &self,
        blocks: &Blocks,
        bb: Option<&Sparse>,
        basis: Option<MatRef<'_, Real>>,
    ) -> (Sparse, Mat<Real>) {
        let bb_ref = match bb {
            Some(s) => BbRef::Sparse(s),
            None => BbRef::Dense(&blocks.bb),
        };
        match (basis, bb) {
            (Some(l), _) if !self.projected => project_ib_bb(&blocks.ib, bb_ref, self.n_kept, l),
            (_, Some(s)) => (blocks.ib.clone(), to_dense(s)),
            _ => (blocks.ib.clone(), blocks.bb.clone()),
        }
    }

    /// K_ib and K_bb in the boundary coordinates of `basis` (None: the boundary as split).
    pub(crate) fn project_k(&self, basis: Option<MatRef<'_, Real>>) -> (Sparse, Mat<Real>) {
        self.project(&self.k, self.bb_sparse.as_ref().map(|b| &b.0), basis)
    }

    /// K_ib as split (kept boundary DOFs, then the interface DOFs).
    pub(crate) fn kib(&self) -> &Sparse {
        &self.k.ib
    }

    /// Constraint modes −K_ii⁻¹ `kib` for the columns of `kib` (n_i × c), solved in parallel
    /// column blocks.
    pub(crate) fn constraint_modes(
        &self,
        kib: &Sparse,
        opts: &CbOptions,
    ) -> Result<Mat<Real>, ReductionError> {
        let (ni, nb) = (self.n_interior(), kib.ncols());
        let mut psi = Mat::<Real>::zeros(ni, nb);
        add_sparse(psi.as_mut(), kib, -1.0);
        if let Some(llt) = &self.llt {
            // Each solve works on a permuted copy of its columns (faer's workspace: n_i ×
            // block), so the blocks are capped: whole halves of Ψ would double its memory.
            let threads = if llt.is_parallel() {
                1
            } else {
                rayon::current_num_threads()
            };
            let chunk = match opts.constraint_block {
                0 => nb.div_ceil(threads).clamp(1, CONSTRAINT_BLOCK_MAX),
                c => c,
            };
            // A block not yet started when the caller asks to stop is skipped (Ψ is dropped).
            psi.par_col_chunks_mut(chunk).for_each(|block| {
                if !opts.interrupt.is_set() {
                    llt.solve_in_place(block)
                }
            });
        }
        opts.check_interrupt("the constraint modes")?;
        check_finite(psi.as_ref(), "constraint modes Ψ")?;
        Ok(psi)
    }

    /// The reduced model from the projected K blocks `kp` = (K_ib L̂, L̂ᵀK_bb L̂) and their
    /// constraint modes `psi`; `solves` = (seconds, right-hand sides) spent on `psi`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn finish(
        &self,
        boundary: &[usize],
        interface: Option<&InterfaceBasis>,
        kp: (Sparse, Mat<Real>),
        psi: Mat<Real>,
        solves: (Real, usize),
        opts: &CbOptions,
        t_start: Instant,
    ) -> Result<CbModel, ReductionError> {
        let (kib, kbb) = kp;
        let basis = interface.map(|f| f.basis.as_ref());
        let mut mem = self.mem.clone();
        mem.constraint_modes = peak_rss_kib();
        let ni = self.n_interior();
        let nb = kbb.nrows();
        let nq = self.lambda.len();
        let phi = self.phi.clone();

        // Reduced matrices.
        let t = Instant::now();
        let nr = nb + nq;
        let mut kr = Mat::<Real>::zeros(nr, nr);
        let kbb = sym(kbb + sparse_t_dense(&kib, psi.as_ref()));
        drop(kib);
        kr.submatrix_mut(0, 0, nb, nb).copy_from(&kbb);
        for (j, &l) in self.lambda.iter().enumerate() {
            kr[(nb + j, nb + j)] = l;
        }
        opts.check_interrupt("the fixed-interface modes")?;
        let (mib, mbb) = self.project(&self.m, self.bb_sparse.as_ref().map(|b| &b.1), basis);
        let mr = reduced_mass_like(
            (&self.m.ii, &mib, &mbb),
            psi.as_ref(),
            phi.as_ref(),
            true,
            &opts.interrupt,
        )?;
        drop((mib, mbb));
        let br = self
            .b
            .as_ref()
            .map(|bp| {
                let bb = self.bb_sparse.as_ref().and_then(|b| b.2.as_ref());
                let (bib, bbb) = self.project(bp, bb, basis);
                reduced_mass_like(
                    (&bp.ii, &bib, &bbb),
                    psi.as_ref(),
                    phi.as_ref(),
                    false,
                    &opts.interrupt,
                )
            })
            .transpose()?;
        check_finite(kr.as_ref(), "reduced stiffness")?;
        check_finite(mr.as_ref(), "reduced mass")?;
        mem.products = peak_rss_kib();
        let products_s = t.elapsed().as_secs_f64();

        let (eigen_solve_s, eigen_orth_s, eigen_qr_s) = self.eigen_split_s;
        let fi = self.factor_info.as_ref();
        let stats = CbStats {
            n_dofs: self.n,
            n_boundary: nb,
            n_interface_dofs: interface.map_or(0, |f| f.dofs.len()),
            n_interface_coords: interface.map_or(0, |f| f.n_coords()),
            n_interior: ni,
            n_modes: nq,
            nnz_kii: self.nnz_kii,
            frequency_of_interest_hz: opts.frequency_of_interest_hz,
            cutoff_hz: self.cutoff_hz,
            eigen_method: self.method,
            krylov_dim: self.krylov_dim,
            n_solves: if ni > 0 {
                solves.1 + self.eig_solves
            } else {
                0
            },
            partition_s: self.partition_s,
            ordering: fi.map(|f| f.ordering).unwrap_or_default(),
            ordering_s: fi.map_or(0.0, |f| f.ordering_s),
            factor_nnz: fi.map_or(0, |f| f.factor_nnz),
            factor_s: self.factor_s,
            constraint_modes_s: solves.0,
            eigen_s: self.eigen_s,
            eigen_solve_s,
            eigen_orth_s,
            eigen_qr_s,
            products_s,
            total_s: t_start.elapsed().as_secs_f64(),
            peak_rss_kib: mem,
            multilevel: None,
        };
        Ok(CbModel {
            k: kr,
            m: mr,
            b: br,
            boundary: boundary.to_vec(),
            interface: interface.cloned(),
            interior: self.part.interior.clone(),
            n_modes: nq,
            fixed_frequencies_hz: self
                .lambda
                .iter()
                .map(|&l| l.max(0.0).sqrt() / (2.0 * PI))
                .collect(),
            psi,
            phi,
            n_dofs: self.n,
            stats,
        })
    }
}

/// `dst += alpha · a` for a sparse `a` of the same shape.
fn add_sparse(mut dst: faer::MatMut<'_, Real>, a: &Sparse, alpha: Real) {
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    for j in 0..a.ncols() {
        for p in cp[j]..cp[j + 1] {
            dst[(ri[p], j)] += alpha * v[p];
        }
    }
}

/// `A_ibᵀ X` for sparse A_ib (n_i × n_b) and dense X (n_i × c).
fn sparse_t_dense(a: &Sparse, x: MatRef<'_, Real>) -> Mat<Real> {
    let mut out = Mat::<Real>::zeros(a.ncols(), x.ncols());
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    for c in 0..x.ncols() {
        let xc = x.col(c);
        for j in 0..a.ncols() {
            let mut acc = 0.0;
            for p in cp[j]..cp[j + 1] {
                acc += v[p] * xc[ri[p]];
            }
            out[(j, c)] = acc;
        }
    }
    out
}

/// Symmetric part of a square matrix.
fn sym(a: Mat<Real>) -> Mat<Real> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// Most right-hand sides per solve with the K_ii factor when computing Ψ by default.
const CONSTRAINT_BLOCK_MAX: usize = 128;

/// Boundary columns per block of W = A_iiΨ + A_ib in [`reduced_mass_like`].
const W_BLOCK: usize = 256;

/// TᵀAT for a mass-like matrix A (M or B). The modal block is I when `unit_modal` (M, with
/// M_ii-orthonormal Φ), else ΦᵀA_iiΦ.
fn reduced_mass_like(
    a: (&Sparse, &Sparse, &Mat<Real>),
    psi: MatRef<'_, Real>,
    phi: MatRef<'_, Real>,
    unit_modal: bool,
    interrupt: &squeal_fe::Interrupt,
) -> Result<Mat<Real>, ReductionError> {
    let (a_ii, a_ib, a_bb) = a;
    let (nb, nq) = (psi.ncols(), phi.ncols());
    let mut out = Mat::<Real>::zeros(nb + nq, nb + nq);
    // W = A_ii Ψ + A_ib in column blocks, never whole: on a brake rotor Ψ is gigabytes, and
    // a second matrix of its size would double the peak memory.
    let mut psi_t_w = Mat::<Real>::zeros(nb, nb);
    let mut bq = Mat::<Real>::zeros(nb, nq);
    let (ib_cp, ib_ri, ib_v) = (
        a_ib.symbolic().col_ptr(),
        a_ib.symbolic().row_idx(),
        a_ib.val(),
    );
    for c0 in (0..nb).step_by(W_BLOCK) {
        if interrupt.is_set() {
            return Err(ReductionError::Interrupted {
                during: "the reduced mass and damping",
            });
        }
        let c = W_BLOCK.min(nb - c0);
        let mut w = sym_spmm(a_ii, psi.subcols(c0, c));
        for j in 0..c {
            for p in ib_cp[c0 + j]..ib_cp[c0 + j + 1] {
                w[(ib_ri[p], j)] += ib_v[p];
            }
        }
        psi_t_w
            .subcols_mut(c0, c)
            .copy_from(at_b(psi, w.as_ref()).as_ref());
        if nq > 0 {
            bq.subrows_mut(c0, c)
                .copy_from(at_b(w.as_ref(), phi).as_ref());
        }
    }
    let bb = sym(a_bb.clone() + sparse_t_dense(a_ib, psi) + psi_t_w);
    out.submatrix_mut(0, 0, nb, nb).copy_from(&bb);
    if nq > 0 {
        out.submatrix_mut(0, nb, nb, nq).copy_from(&bq);
        out.submatrix_mut(nb, 0, nq, nb).copy_from(bq.transpose());
        if unit_modal {
            for j in 0..nq {
                out[(nb + j, nb + j)] = 1.0;
            }
        } else {
            let qq = sym(at_b(phi, sym_spmm(a_ii, phi).as_ref()));
            out.submatrix_mut(nb, nb, nq, nq).copy_from(&qq);
        }
    }
    Ok(out)
}

fn check_finite(a: MatRef<'_, Real>, what: &str) -> Result<(), ReductionError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let v = a[(i, j)];
            if !v.is_finite() {
                return Err(ReductionError::NonFinite {
                    what: what.to_string(),
                    row: i,
                    col: j,
                    value: v,
                });
            }
        }
    }
    Ok(())
}
