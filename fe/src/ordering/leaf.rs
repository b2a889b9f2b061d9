//! Ordering of a dissection leaf: AMD on the subgraph the leaf's nodes induce.

use super::graph::NodeGraph;
use super::separator::Marks;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

/// Appends the nodes of a leaf to `order`, in AMD order of their induced subgraph (natural order
/// if `use_amd` is false, or if AMD fails).
pub(crate) fn order_leaf(
    g: &NodeGraph,
    nodes: &[usize],
    use_amd: bool,
    marks: &mut Marks,
    order: &mut Vec<usize>,
) {
    let n = nodes.len();
    if !use_amd || n < 3 {
        order.extend_from_slice(nodes);
        return;
    }
    for (k, &v) in nodes.iter().enumerate() {
        marks.local[v] = k;
    }
    let mut ptr = Vec::with_capacity(n + 1);
    ptr.push(0);
    let mut rows = Vec::new();
    for (k, &v) in nodes.iter().enumerate() {
        rows.push(k);
        for &u in g.neighbours(v) {
            if marks.local[u] != usize::MAX {
                rows.push(marks.local[u]);
            }
        }
        ptr.push(rows.len());
    }
    for &v in nodes {
        marks.local[v] = usize::MAX;
    }
    let nnz = rows.len();
    let a = SymbolicSparseColMatRef::new_unsorted_checked(n, n, &ptr, None, &rows);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let ok = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, nnz))
        .ok()
        .and_then(|mut buf| {
            amd::order_maybe_unsorted(
                &mut perm,
                &mut perm_inv,
                a,
                amd::Control::default(),
                MemStack::new(&mut buf),
            )
            .ok()
        })
        .is_some();
    if ok {
        order.extend(perm.iter().map(|&k| nodes[k]));
    } else {
        order.extend_from_slice(nodes);
    }
}
