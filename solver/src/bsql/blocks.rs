//! The saddle matrix factorised by components: the blocks of A = cj M + B + K/cj that only
//! the constraint rows couple (pads and rotor of a reduced brake), found from the pattern.
//!
//! # Structure
//! A reduced brake's M, B, K are block-diagonal per component except where components share
//! DOFs: the pads meet the rotor only through the contact rows (G, and the friction tangents
//! D = ∂F_f/∂λ' in the multiplier columns), and a caliper reduced to its fixed-interface modes
//! couples the two pads only through those modes. So the blocks are the connected components
//! of the union pattern of M, B, K once the DOFs that bridge two of them are moved to the
//! border (with the multipliers):
//! - a *hub* is a DOF with no constraint on it, M_ii > 0, and no off-diagonal stiffness
//!   (K_ij = K_ji = 0 for j ≠ i: a Craig–Bampton modal coordinate, whose K_qb = 0);
//! - the components of the pattern without the hubs are found; a hub whose non-hub neighbours
//!   lie in two or more of them *bridges* them (the caliper's modes) and goes to the border, the
//!   others join their component's block;
//! - bridging DOFs are never eliminated by the diagonal-block elimination (`linalg::diag_block`,
//!   which would couple the pads densely); the DOFs it does eliminate merge the kept DOFs they
//!   couple with (the fill of A_bd A_dd⁻¹ A_db).
//!
//! The factorisation ([`crate::linalg::bordered`]) is used when there are at least two blocks
//! and its flop count is at most half the dense LU's; it checks at every set-up that the
//! matrix still fits (a friction damping C_f between pad and rotor does not) and factorises the
//! whole matrix otherwise (`BsqlStats::block_fallbacks`). The two paths differ by round-off.

use faer::Mat;

use crate::linalg::bordered::{cost_ratio, BorderedBlocks};
use crate::linalg::diag_block::DiagBlock;
use crate::Real;

/// Largest flop ratio (blocks over the dense LU) at which the blocks are used.
const MAX_COST_RATIO: f64 = 0.5;

/// Most blocks used (more, smaller ones would cost more in bookkeeping than they save).
const MAX_BLOCKS: usize = 64;

/// Union–find with path halving.
struct Sets(Vec<usize>);

impl Sets {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }
    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// Symmetric union pattern of M, B, K.
fn coupled(mats: &[&Mat<Real>; 3], i: usize, j: usize) -> bool {
    mats.iter().any(|a| a[(i, j)] != 0.0 || a[(j, i)] != 0.0)
}

/// DOFs that bridge two components (see the module docs).
#[allow(non_snake_case)]
pub(crate) fn bridging_dofs(
    M: &Mat<Real>,
    B: &Mat<Real>,
    K: &Mat<Real>,
    G: &Mat<Real>,
) -> Vec<bool> {
    let n = M.nrows();
    let mats = [M, B, K];
    let hub: Vec<bool> = (0..n)
        .map(|i| {
            M[(i, i)] > 0.0
                && (0..G.nrows()).all(|k| G[(k, i)] == 0.0)
                && (0..n).all(|j| j == i || (K[(i, j)] == 0.0 && K[(j, i)] == 0.0))
        })
        .collect();
    let mut sets = Sets::new(n);
    for j in 0..n {
        if hub[j] {
            continue;
        }
        for i in 0..j {
            if !hub[i] && coupled(&mats, i, j) {
                sets.union(i, j);
            }
        }
    }
    (0..n)
        .map(|h| {
            if !hub[h] {
                return false;
            }
            let mut first = None;
            for j in 0..n {
                if j != h && !hub[j] && coupled(&mats, h, j) {
                    let r = sets.find(j);
                    match first {
                        None => first = Some(r),
                        Some(f) if f != r => return true,
                        _ => {}
                    }
                }
            }
            false
        })
        .collect()
}

/// The partition of the saddle matrix's positions (the kept DOFs of `modal`, or all n DOFs,
/// then the ng multipliers) into component blocks and the border, when it pays
/// ([`MAX_COST_RATIO`]); None otherwise.
#[allow(non_snake_case)]
pub(crate) fn partition(
    M: &Mat<Real>,
    B: &Mat<Real>,
    K: &Mat<Real>,
    G: &Mat<Real>,
    modal: Option<&DiagBlock>,
    bridging: &[bool],
) -> Option<BorderedBlocks> {
    let (n, ng) = (M.nrows(), G.nrows());
    let mats = [M, B, K];
    let all: Vec<usize>;
    let kept: &[usize] = match modal {
        Some(blk) => &blk.kept,
        None => {
            all = (0..n).collect();
            &all
        }
    };
    let nv = kept.len();
    let mut sets = Sets::new(nv);
    for q in 0..nv {
        if bridging[kept[q]] {
            continue;
        }
        for p in 0..q {
            if !bridging[kept[p]] && coupled(&mats, kept[p], kept[q]) {
                sets.union(p, q);
            }
        }
    }
    // Fill through the eliminated DOFs.
    if let Some(blk) = modal {
        for &e in &blk.d {
            let mut first = None;
            for (p, &i) in kept.iter().enumerate() {
                if !bridging[i] && coupled(&mats, e, i) {
                    match first {
                        None => first = Some(p),
                        Some(f) => sets.union(f, p),
                    }
                }
            }
        }
    }
    let mut block_of: Vec<Option<usize>> = (0..nv)
        .map(|p| (!bridging[kept[p]]).then(|| sets.find(p)))
        .collect();
    block_of.extend(std::iter::repeat_n(None, ng));
    let blocks = BorderedBlocks::new(&block_of);
    let (sizes, n_border) = blocks.sizes();
    if sizes.len() < 2 {
        return None;
    }
    if sizes.len() > MAX_BLOCKS {
        return None;
    }
    // Block of each kept position, numbered by first appearance as in `BorderedBlocks::new`.
    let mut index_of_root = vec![usize::MAX; nv];
    let mut n_blocks = 0;
    let block: Vec<Option<usize>> = block_of[..nv]
        .iter()
        .map(|r| {
            r.map(|r| {
                if index_of_root[r] == usize::MAX {
                    index_of_root[r] = n_blocks;
                    n_blocks += 1;
                }
                index_of_root[r]
            })
        })
        .collect();
    // Border columns each block touches in the pattern: the constraint rows on its DOFs and
    // the bridging DOFs it couples with (the rows alike).
    let mut touch = vec![0usize; sizes.len()];
    for (b, t) in touch.iter_mut().enumerate() {
        let members: Vec<usize> = (0..nv)
            .filter(|&p| block[p] == Some(b))
            .map(|p| kept[p])
            .collect();
        *t = (0..ng)
            .filter(|&k| members.iter().any(|&i| G[(k, i)] != 0.0))
            .count()
            + (0..n)
                .filter(|&h| bridging[h] && members.iter().any(|&i| coupled(&mats, h, i)))
                .count();
    }
    let est: Vec<(usize, usize, usize)> =
        sizes.iter().zip(&touch).map(|(&s, &t)| (s, t, t)).collect();
    (cost_ratio(&est, n_border) <= MAX_COST_RATIO).then_some(blocks)
}
