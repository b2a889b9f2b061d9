//! Rectangular block: plates (NAFEMS FV52), beams, brake pads.

use super::{define_constants, divisions, positive, Param};
use crate::{MeshError, Real};
use serde::{Deserialize, Serialize};

/// A box `origin + [0, lx] × [0, ly] × [0, lz]` meshed with nx × ny × nz hexahedra.
/// Physical groups: volume "block"; surfaces "x0", "x1", "y0", "y1", "z0", "z1" (the faces at
/// the low/high end of each axis); curves "z0_edges" (the four edges of face z0, where FV52's
/// plate is simply supported).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BlockGeometry {
    /// Length along x (default: 10.0, the NAFEMS FV52 plate).
    pub lx: Real,
    /// Length along y (default: 10.0).
    pub ly: Real,
    /// Length along z (default: 1.0).
    pub lz: Real,
    /// Elements along x (default: 8).
    pub nx: usize,
    /// Elements along y (default: 8).
    pub ny: usize,
    /// Elements along z (default: 2).
    pub nz: usize,
    /// Corner with the smallest coordinates (default: [0, 0, 0]).
    pub origin: [Real; 3],
}

impl Default for BlockGeometry {
    /// NAFEMS FV52: a 10 m × 10 m × 1 m plate, here 8 × 8 × 2 elements.
    fn default() -> Self {
        BlockGeometry {
            lx: 10.0,
            ly: 10.0,
            lz: 1.0,
            nx: 8,
            ny: 8,
            nz: 2,
            origin: [0.0; 3],
        }
    }
}

impl BlockGeometry {
    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), MeshError> {
        positive("lx", self.lx)?;
        positive("ly", self.ly)?;
        positive("lz", self.lz)?;
        divisions("nx", self.nx, 10_000)?;
        divisions("ny", self.ny, 10_000)?;
        divisions("nz", self.nz, 10_000)?;
        if let Some(v) = self.origin.iter().find(|v| !v.is_finite()) {
            return Err(MeshError::InvalidGeometry {
                field: "origin",
                value: v.to_string(),
                reason: "must be finite".into(),
            });
        }
        Ok(())
    }

    /// Hex cells of the mesh gmsh makes from [`block`].
    pub fn n_cells(&self) -> usize {
        self.nx * self.ny * self.nz
    }

    /// Nodes of that mesh: order 1 (hex8) or 2 (hex20).
    pub fn n_nodes(&self, order: u8) -> usize {
        let (x, y, z) = (self.nx, self.ny, self.nz);
        let corners = (x + 1) * (y + 1) * (z + 1);
        if order < 2 {
            return corners;
        }
        corners + x * (y + 1) * (z + 1) + (x + 1) * y * (z + 1) + (x + 1) * (y + 1) * z
    }
}

/// The `.geo` text of an all-hex block.
pub fn block(g: &BlockGeometry) -> String {
    let mut s = define_constants(
        "Rectangular block",
        &[
            Param {
                name: "lx",
                value: g.lx,
                doc: "length along x",
            },
            Param {
                name: "ly",
                value: g.ly,
                doc: "length along y",
            },
            Param {
                name: "lz",
                value: g.lz,
                doc: "length along z",
            },
            Param {
                name: "nx",
                value: g.nx as Real,
                doc: "elements along x",
            },
            Param {
                name: "ny",
                value: g.ny as Real,
                doc: "elements along y",
            },
            Param {
                name: "nz",
                value: g.nz as Real,
                doc: "elements along z",
            },
            Param {
                name: "ox",
                value: g.origin[0],
                doc: "x of the corner with the smallest coordinates",
            },
            Param {
                name: "oy",
                value: g.origin[1],
                doc: "y of that corner",
            },
            Param {
                name: "oz",
                value: g.origin[2],
                doc: "z of that corner",
            },
        ],
    );
    s.push_str(BLOCK_BODY);
    s
}

/// A transfinite rectangle at z = oz, extruded along +z in nz layers. With the loop
/// {y0 edge, x1 edge, y1 edge, x0 edge}, Extrude returns [top, volume, y0, x1, y1, x0].
const BLOCK_BODY: &str = r#"SetFactory("Built-in");
c1 = newp; Point(c1) = {ox, oy, oz};
c2 = newp; Point(c2) = {ox + lx, oy, oz};
c3 = newp; Point(c3) = {ox + lx, oy + ly, oz};
c4 = newp; Point(c4) = {ox, oy + ly, oz};
e1 = newc; Line(e1) = {c1, c2};
e2 = newc; Line(e2) = {c2, c3};
e3 = newc; Line(e3) = {c3, c4};
e4 = newc; Line(e4) = {c4, c1};
Transfinite Curve{e1, e3} = nx + 1;
Transfinite Curve{e2, e4} = ny + 1;
cloop = newcl; Curve Loop(cloop) = {e1, e2, e3, e4};
bottom = news; Plane Surface(bottom) = {cloop};
Transfinite Surface{bottom};
Recombine Surface{bottom};
ex[] = Extrude {0, 0, lz} { Surface{bottom}; Layers{nz}; Recombine; };
Physical Volume("block", 1) = {ex[1]};
Physical Surface("x0", 2) = {ex[5]};
Physical Surface("x1", 3) = {ex[3]};
Physical Surface("y0", 4) = {ex[2]};
Physical Surface("y1", 5) = {ex[4]};
Physical Surface("z0", 6) = {bottom};
Physical Surface("z1", 7) = {ex[0]};
Physical Curve("z0_edges", 8) = {e1, e2, e3, e4};
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_bad_values_name_the_field() {
        BlockGeometry::default().validate().unwrap();
        let g = BlockGeometry {
            nz: 0,
            ..Default::default()
        };
        assert!(g.validate().unwrap_err().to_string().contains("nz"));
        let g = BlockGeometry {
            lx: -1.0,
            ..Default::default()
        };
        assert!(g.validate().unwrap_err().to_string().contains("lx"));
    }

    /// 2 × 3 × 1: corners 3·4·2 = 24; hex20 edges 2·4·2 + 3·3·2 + 3·4·1 = 16 + 18 + 12.
    #[test]
    fn node_counts() {
        let g = BlockGeometry {
            nx: 2,
            ny: 3,
            nz: 1,
            ..Default::default()
        };
        assert_eq!(g.n_nodes(1), 24);
        assert_eq!(g.n_nodes(2), 24 + 46);
        assert_eq!(g.n_cells(), 6);
    }
}
