//! Lookups and simple geometry on a [`Mesh`]: named sets, bounding box, cell orientation.

use crate::{CellBlock, FaceSet, Mesh, MeshError, Real};

impl Mesh {
    /// Sorted, unique node indices of the physical group `name` (any dimension).
    pub fn node_set(&self, name: &str) -> Result<&[usize], MeshError> {
        self.node_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| MeshError::UnknownSet {
                what: "node set",
                name: name.to_string(),
                available: list(self.node_sets.keys()),
            })
    }

    /// Face cells of the physical surface `name`.
    pub fn face_set(&self, name: &str) -> Result<&FaceSet, MeshError> {
        self.faces.get(name).ok_or_else(|| MeshError::UnknownSet {
            what: "face set",
            name: name.to_string(),
            available: list(self.faces.keys()),
        })
    }

    /// Smallest and largest coordinates over all nodes, or None for a mesh without nodes.
    pub fn bounding_box(&self) -> Option<([Real; 3], [Real; 3])> {
        let first = *self.nodes.first()?;
        let (mut lo, mut hi) = (first, first);
        for p in &self.nodes {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// Number of volume cells over all blocks.
    pub fn n_volume_cells(&self) -> usize {
        self.volumes.iter().map(CellBlock::len).sum()
    }

    /// Jacobian determinant at the centroid of volume cell `cell` of block `block`
    /// (from its corners; positive for a well-oriented cell in squeal's node order).
    pub fn centroid_jacobian(&self, block: usize, cell: usize) -> Real {
        let b = &self.volumes[block];
        let x: Vec<[Real; 3]> = b.cell(cell).iter().map(|&v| self.nodes[v]).collect();
        crate::jacobian::centroid_jacobian(b.kind, &x)
    }
}

fn list<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = names.map(String::as_str).collect();
    if v.is_empty() {
        "none".to_string()
    } else {
        v.join(", ")
    }
}

/// Determinant of the trilinear map's Jacobian ∂x/∂ξ at ξ = η = ζ = 0, for corners in squeal
/// (VTK) order: 0-1-2-3 counter-clockwise at ζ = −1, 4-5-6-7 above them at ζ = +1.
/// It is 1/8 of the volume for a parallelepiped, positive when the order is right-handed.
pub fn hex_centroid_jacobian(corners: &[[Real; 3]; 8]) -> Real {
    // Natural coordinates of the corners.
    const XI: [[Real; 3]; 8] = [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    // J[i][a] = ∂x_i/∂ξ_a = Σ_k x_k,i ξ_k,a / 8 at the centroid.
    let mut j = [[0.0; 3]; 3];
    for (x, xi) in corners.iter().zip(&XI) {
        for i in 0..3 {
            for a in 0..3 {
                j[i][a] += x[i] * xi[a] / 8.0;
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box a×b×c has J = diag(a/2, b/2, c/2), det = abc/8.
    #[test]
    fn box_jacobian_is_volume_over_eight() {
        let (a, b, c) = (2.0, 3.0, 0.5);
        let corners = [
            [0.0, 0.0, 0.0],
            [a, 0.0, 0.0],
            [a, b, 0.0],
            [0.0, b, 0.0],
            [0.0, 0.0, c],
            [a, 0.0, c],
            [a, b, c],
            [0.0, b, c],
        ];
        assert!((hex_centroid_jacobian(&corners) - a * b * c / 8.0).abs() < 1e-14);
        let mut flipped = corners;
        flipped.swap(1, 3);
        flipped.swap(5, 7);
        assert!((hex_centroid_jacobian(&flipped) + a * b * c / 8.0).abs() < 1e-14);
    }

    #[test]
    fn unknown_set_lists_the_names() {
        let mut m = Mesh::default();
        m.node_sets.insert("hub".into(), vec![0, 1]);
        assert_eq!(m.node_set("hub").unwrap(), &[0, 1]);
        let e = m.node_set("rim").unwrap_err().to_string();
        assert!(e.contains("rim") && e.contains("hub"), "{e}");
        assert!(m.face_set("hub").is_err());
        assert!(m.bounding_box().is_none());
    }
}
