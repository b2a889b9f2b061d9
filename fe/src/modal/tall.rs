//! Products with tall-skinny dense blocks (n × k, n ≫ k), parallel over row chunks.
//!
//! faer's parallel `matmul` on these shapes was erratic on a loaded 2-core machine (up to 20×
//! slower) and its sequential one packs the whole tall operand on every call; splitting the
//! rows into a few chunks, each multiplied sequentially, spreads the memory traffic over the
//! cores with one fork–join per product.

use crate::Real;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;

/// Smallest row chunk worth a task.
const MIN_ROWS: usize = 4096;

/// Row ranges splitting `n` rows into about one chunk per rayon thread.
fn chunks(n: usize) -> Vec<(usize, usize)> {
    let parts = rayon::current_num_threads()
        .max(1)
        .min(n.div_ceil(MIN_ROWS))
        .max(1);
    let size = n.div_ceil(parts);
    (0..parts)
        .map(|p| (p * size, ((p + 1) * size).min(n)))
        .filter(|(a, b)| a < b)
        .collect()
}

/// Returns Aᵀ B (k × m) for A n × k and B n × m.
pub(crate) fn tn(a: MatRef<'_, Real>, b: MatRef<'_, Real>) -> Mat<Real> {
    let (k, m) = (a.ncols(), b.ncols());
    let parts: Vec<Mat<Real>> = chunks(a.nrows())
        .into_par_iter()
        .map(|(r0, r1)| {
            let mut c = Mat::<Real>::zeros(k, m);
            matmul(
                c.as_mut(),
                Accum::Replace,
                a.subrows(r0, r1 - r0).transpose(),
                b.subrows(r0, r1 - r0),
                1.0,
                Par::Seq,
            );
            c
        })
        .collect();
    let mut c = Mat::<Real>::zeros(k, m);
    for p in &parts {
        c += p;
    }
    c
}

/// `dst ← beta·dst + alpha·A C` (A n × k, C k × m, dst n × m); `accum = false` overwrites.
pub(crate) fn nn(
    dst: MatMut<'_, Real>,
    accum: bool,
    a: MatRef<'_, Real>,
    c: MatRef<'_, Real>,
    alpha: Real,
) {
    let ranges = chunks(a.nrows());
    // Split dst into disjoint row blocks.
    let mut blocks = Vec::with_capacity(ranges.len());
    let mut rest = dst;
    let mut start = 0;
    for &(r0, r1) in &ranges {
        let (top, bot) = rest.split_at_row_mut(r1 - start);
        blocks.push((r0, r1, top));
        rest = bot;
        start = r1;
    }
    blocks.into_par_iter().for_each(|(r0, r1, blk)| {
        matmul(
            blk,
            if accum { Accum::Add } else { Accum::Replace },
            a.subrows(r0, r1 - r0),
            c,
            alpha,
            Par::Seq,
        );
    });
}
