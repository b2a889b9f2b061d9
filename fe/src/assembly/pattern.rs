//! Node graph (node–node adjacency through shared cells) in compressed-column form.

use rayon::prelude::*;
use squeal_meshes::Mesh;

/// Sorted neighbour lists of every node (including itself), compressed.
pub(crate) struct NodeGraph {
    pub ptr: Vec<usize>,
    pub idx: Vec<usize>,
}

impl NodeGraph {
    /// Builds the graph of the volume blocks; connectivity must be in range (checked by caller).
    pub fn new(mesh: &Mesh) -> Self {
        let n = mesh.nodes.len();
        // node → cells incidence (cells numbered globally over blocks).
        let mut cell_nodes: Vec<&[usize]> = Vec::new();
        for b in &mesh.volumes {
            for c in 0..b.len() {
                cell_nodes.push(b.cell(c));
            }
        }
        let mut count = vec![0usize; n + 1];
        for c in &cell_nodes {
            for &v in c.iter() {
                count[v + 1] += 1;
            }
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut inc = vec![0usize; count[n]];
        for (ci, c) in cell_nodes.iter().enumerate() {
            for &v in c.iter() {
                inc[fill[v]] = ci;
                fill[v] += 1;
            }
        }
        let lists: Vec<Vec<usize>> = (0..n)
            .into_par_iter()
            .map(|v| {
                let mut l: Vec<usize> = inc[count[v]..count[v + 1]]
                    .iter()
                    .flat_map(|&c| cell_nodes[c].iter().copied())
                    .collect();
                l.push(v);
                l.sort_unstable();
                l.dedup();
                l
            })
            .collect();
        let mut ptr = Vec::with_capacity(n + 1);
        ptr.push(0);
        for l in &lists {
            ptr.push(ptr.last().copied().unwrap_or(0) + l.len());
        }
        let mut idx = Vec::with_capacity(*ptr.last().unwrap_or(&0));
        for l in lists {
            idx.extend(l);
        }
        NodeGraph { ptr, idx }
    }

    /// Position of (row node `a`, column node `b`) in the compressed storage.
    #[inline]
    pub fn pos(&self, a: usize, b: usize) -> usize {
        let s = &self.idx[self.ptr[b]..self.ptr[b + 1]];
        self.ptr[b] + s.binary_search(&a).unwrap_or(0)
    }
}
