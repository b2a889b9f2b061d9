//! Numbering of the free degrees of freedom: 3 per node, fixed (SPC) DOFs removed.

use crate::{FeError, Mesh, Real};

const FIXED: usize = usize::MAX;

/// Maps (node, component) to free-DOF indices, node-major (node 0 x,y,z, node 1 x,y,z, …),
/// skipping fixed DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    n_nodes: usize,
    /// `3 * n_nodes` entries: free index or `FIXED`.
    free_of: Vec<usize>,
    /// Free index → (node, component).
    dof_of: Vec<(usize, usize)>,
}

impl DofMap {
    /// DOF map of `n_nodes` nodes with the listed `(node, component 0..3)` DOFs fixed
    /// (duplicates allowed). Errors name an out-of-range node or component.
    pub fn new(n_nodes: usize, fixed: &[(usize, usize)]) -> Result<Self, FeError> {
        let mut free_of = vec![0usize; 3 * n_nodes];
        for &(node, comp) in fixed {
            if node >= n_nodes {
                return Err(FeError::NodeOutOfRange {
                    node,
                    n_nodes,
                    context: "fixed DOF list".to_string(),
                });
            }
            if comp >= 3 {
                return Err(FeError::ComponentOutOfRange { node, comp });
            }
            free_of[3 * node + comp] = FIXED;
        }
        let mut dof_of = Vec::with_capacity(3 * n_nodes);
        for (d, f) in free_of.iter_mut().enumerate() {
            if *f != FIXED {
                *f = dof_of.len();
                dof_of.push((d / 3, d % 3));
            }
        }
        Ok(DofMap {
            n_nodes,
            free_of,
            dof_of,
        })
    }

    /// DOF map fixing the given components of every node of the named node sets,
    /// e.g. `&[("hub", [true, true, true])]`.
    pub fn from_node_sets(mesh: &Mesh, fixed: &[(&str, [bool; 3])]) -> Result<Self, FeError> {
        let mut list = Vec::new();
        for (name, comps) in fixed {
            let set = mesh
                .node_sets
                .get(*name)
                .ok_or_else(|| FeError::UnknownSet {
                    what: "node set",
                    name: name.to_string(),
                    available: mesh
                        .node_sets
                        .keys()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", "),
                })?;
            for &n in set {
                for c in 0..3 {
                    if comps[c] {
                        list.push((n, c));
                    }
                }
            }
        }
        DofMap::new(mesh.nodes.len(), &list)
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Number of free DOFs.
    pub fn n_free(&self) -> usize {
        self.dof_of.len()
    }

    /// Free index of (node, component), `None` if fixed or out of range.
    pub fn free(&self, node: usize, comp: usize) -> Option<usize> {
        if node >= self.n_nodes || comp >= 3 {
            return None;
        }
        let f = self.free_of[3 * node + comp];
        (f != FIXED).then_some(f)
    }

    /// (node, component) of a free index. Panics if `free_index >= n_free()` (a programming error).
    pub fn dof_of(&self, free_index: usize) -> (usize, usize) {
        self.dof_of[free_index]
    }

    /// Nodal vectors from a free-DOF vector, zeros at fixed DOFs. Entries of `free` beyond
    /// `n_free()` are ignored; missing ones are taken as zero.
    pub fn expand(&self, free: &[Real]) -> Vec<[Real; 3]> {
        let mut out = vec![[0.0; 3]; self.n_nodes];
        for (i, &(n, c)) in self.dof_of.iter().enumerate() {
            if let Some(&v) = free.get(i) {
                out[n][c] = v;
            }
        }
        out
    }

    /// Raw free-index table (`usize::MAX` = fixed), 3 entries per node.
    pub(crate) fn table(&self) -> &[usize] {
        &self.free_of
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbering_skips_fixed() {
        let d = DofMap::new(3, &[(0, 2), (1, 0), (1, 0)]).unwrap();
        assert_eq!(d.n_free(), 7);
        assert_eq!(d.free(0, 2), None);
        assert_eq!(d.free(1, 1), Some(2));
        assert_eq!(d.dof_of(2), (1, 1));
        let e = d.expand(&[1., 2., 3., 4., 5., 6., 7.]);
        assert_eq!(e, vec![[1., 2., 0.], [0., 3., 4.], [5., 6., 7.]]);
        assert!(DofMap::new(3, &[(3, 0)]).is_err());
        assert!(DofMap::new(3, &[(0, 3)]).is_err());
    }
}
