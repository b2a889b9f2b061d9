//! The node graph of a sparse symmetric matrix: DOFs grouped into nodes by their coordinates.

use crate::{DofMap, Mesh, Real};
use faer::sparse::SymbolicSparseColMatRef;
use rayon::prelude::*;

/// Coordinates of every free DOF of `dofs` (the point of its node), in free-DOF order: the
/// input that [`solve_modes_with`](crate::modal::solve_modes_with) and
/// [`nested_dissection`](super::nested_dissection) take.
pub fn dof_coordinates(mesh: &Mesh, dofs: &DofMap) -> Vec<[Real; 3]> {
    (0..dofs.n_free())
        .map(|i| mesh.nodes[dofs.dof_of(i).0])
        .collect()
}

/// Node graph: nodes are runs of consecutive DOFs at the same point; two nodes are adjacent
/// when the matrix couples any of their DOFs (either triangle). No self loops.
pub(crate) struct NodeGraph {
    /// Adjacency lists, compressed: neighbours of node g are `adj[ptr[g]..ptr[g + 1]]`.
    pub ptr: Vec<usize>,
    pub adj: Vec<usize>,
    /// DOFs of node g are `dof_ptr[g]..dof_ptr[g + 1]`.
    pub dof_ptr: Vec<usize>,
    /// Point of each node.
    pub xyz: Vec<[Real; 3]>,
}

impl NodeGraph {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.xyz.len()
    }

    /// Neighbours of node `g`.
    #[inline]
    pub fn neighbours(&self, g: usize) -> &[usize] {
        &self.adj[self.ptr[g]..self.ptr[g + 1]]
    }

    /// Groups the DOFs of `pattern` (n × n) by `coords` (one point per DOF) and builds the
    /// symmetrised node adjacency.
    pub fn new(pattern: SymbolicSparseColMatRef<'_, usize>, coords: &[[Real; 3]]) -> Self {
        let n = pattern.ncols();
        let mut dof_ptr = vec![0];
        let mut node_of = vec![0usize; n];
        let mut xyz = Vec::new();
        for i in 0..n {
            if i == 0 || coords[i] != coords[i - 1] {
                if i > 0 {
                    dof_ptr.push(i);
                }
                xyz.push(coords[i]);
            }
            node_of[i] = xyz.len() - 1;
        }
        if n > 0 {
            dof_ptr.push(n);
        }
        let nn = xyz.len();
        // Column lists at node level, then symmetrised.
        let lists: Vec<Vec<usize>> = (0..nn)
            .into_par_iter()
            .map(|g| {
                let mut l: Vec<usize> = (dof_ptr[g]..dof_ptr[g + 1])
                    .flat_map(|j| pattern.row_idx_of_col(j).map(|i| node_of[i]))
                    .filter(|&h| h != g)
                    .collect();
                l.sort_unstable();
                l.dedup();
                l
            })
            .collect();
        let mut count = vec![0usize; nn + 1];
        for (g, l) in lists.iter().enumerate() {
            count[g + 1] += l.len();
            for &h in l {
                count[h + 1] += 1;
            }
        }
        for g in 0..nn {
            count[g + 1] += count[g];
        }
        let mut fill = count.clone();
        let mut both = vec![0usize; count[nn]];
        for (g, l) in lists.iter().enumerate() {
            for &h in l {
                both[fill[g]] = h;
                fill[g] += 1;
                both[fill[h]] = g;
                fill[h] += 1;
            }
        }
        let merged: Vec<Vec<usize>> = (0..nn)
            .into_par_iter()
            .map(|g| {
                let mut l = both[count[g]..count[g + 1]].to_vec();
                l.sort_unstable();
                l.dedup();
                l
            })
            .collect();
        let mut ptr = Vec::with_capacity(nn + 1);
        ptr.push(0);
        let mut adj = Vec::with_capacity(merged.iter().map(Vec::len).sum());
        for l in merged {
            adj.extend(l);
            ptr.push(adj.len());
        }
        NodeGraph {
            ptr,
            adj,
            dof_ptr,
            xyz,
        }
    }
}
