//! Brake pad: an annular-sector friction lining on a steel backplate, placed on a friction
//! face of the rotor with its friction-face nodes on the rotor's nodes.

use super::sector::{extrude, patch, ring, EdgeShape};
use super::{define_constants, divisions, positive, Param, RotorGeometry};
use crate::{MeshError, Real};
use serde::{Deserialize, Serialize};

/// Which friction face of the rotor (z = 0 .. thickness) a pad sits on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RotorSide {
    /// z = thickness; the pad extends towards +z.
    #[default]
    Top,
    /// z = 0; the pad extends towards −z.
    Bottom,
}

impl RotorSide {
    /// +1 for the top face, −1 for the bottom face: the direction from the rotor into the pad.
    pub fn sign(self) -> Real {
        match self {
            RotorSide::Top => 1.0,
            RotorSide::Bottom => -1.0,
        }
    }
}

/// A pad placed on the rotor's mesh, in rotor elements: the pad covers whole rotor elements,
/// so its friction-face nodes are rotor friction-face nodes (the paper's coincident grids).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PadPlacement {
    /// Friction face the pad sits on (default: top).
    pub side: RotorSide,
    /// First rotor element (circumferential index) under the pad; may be negative, element k
    /// starts at the angle k·360°/n_circ from +x (default: −5, so the 10-element default pad is
    /// centred on the +x axis, where the rotor's circumferential velocity is along y).
    pub start_element: i64,
    /// Rotor elements the pad spans around the circumference (default: 10).
    pub n_elements: usize,
    /// Rotor node ring (0 = r_in .. n_rad = r_out) at the pad's inner radius (default: 3).
    pub first_ring: usize,
    /// Rotor node ring at the pad's outer radius, > first_ring (default: 6).
    pub last_ring: usize,
    /// Friction lining thickness (default: 0.4).
    pub lining: Real,
    /// Elements through the lining (default: 2).
    pub n_lining: usize,
    /// Steel backplate thickness (default: 0.2).
    pub backplate: Real,
    /// Elements through the backplate (default: 1).
    pub n_backplate: usize,
}

impl Default for PadPlacement {
    /// The sample brake's inboard pad on the default rotor: rings 3..6 (r = 3.75 .. 5.5 in),
    /// 10 of 64 elements (56.25°), a 0.4 in lining on a 0.2 in backplate.
    fn default() -> Self {
        PadPlacement {
            side: RotorSide::Top,
            start_element: -5,
            n_elements: 10,
            first_ring: 3,
            last_ring: 6,
            lining: 0.4,
            n_lining: 2,
            backplate: 0.2,
            n_backplate: 1,
        }
    }
}

/// An annular-sector pad: friction face at z = `z_face` between radii `r_in` and `r_out` and
/// angles `theta_start_deg` .. `theta_start_deg + theta_span_deg`, the lining extending
/// `lining` away from the rotor (towards `side.sign()`·z), the backplate `backplate` beyond it.
/// Physical groups: volumes "lining" (1) and "backplate" (2); surfaces "friction" (3, the
/// contact face), "back" (4, the backplate's outer face, where the piston or fingers push),
/// "abutment_start" (5, the sector end at `theta_start_deg`), "abutment_end" (6).
///
/// squeal-meshes keeps gmsh's element order, which is by volume entity: `Mesh::volumes` is
/// `[lining, backplate]` (one block per physical volume and element kind).
/// Build it with [`PadGeometry::on_rotor`] to get nodes coincident with the rotor's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PadGeometry {
    /// Inner radius of the friction face (default: 3.75).
    pub r_in: Real,
    /// Outer radius of the friction face (default: 5.5).
    pub r_out: Real,
    /// Angle of the sector's first end, degrees from +x about +z (default: −28.125).
    pub theta_start_deg: Real,
    /// Angular span, degrees, in (0, 180) (default: 56.25).
    pub theta_span_deg: Real,
    /// Elements around the sector (default: 10).
    pub n_circ: usize,
    /// Elements across the radius (default: 3).
    pub n_rad: usize,
    /// z of the friction face (default: 0.5, the default rotor's top face).
    pub z_face: Real,
    /// Rotor face the pad sits on; the pad extends away from the rotor (default: top).
    pub side: RotorSide,
    /// Lining thickness (default: 0.4).
    pub lining: Real,
    /// Elements through the lining (default: 2).
    pub n_lining: usize,
    /// Backplate thickness (default: 0.2).
    pub backplate: Real,
    /// Elements through the backplate (default: 1).
    pub n_backplate: usize,
    /// Shape of the inner circumferential edge (default: chords).
    pub inner_edge: EdgeShape,
    /// Shape of the outer circumferential edge (default: arc).
    pub outer_edge: EdgeShape,
}

impl Default for PadGeometry {
    /// [`PadPlacement::default`] on [`RotorGeometry::default`].
    fn default() -> Self {
        PadGeometry {
            r_in: 3.75,
            r_out: 5.5,
            theta_start_deg: -28.125,
            theta_span_deg: 56.25,
            n_circ: 10,
            n_rad: 3,
            z_face: 0.5,
            side: RotorSide::Top,
            lining: 0.4,
            n_lining: 2,
            backplate: 0.2,
            n_backplate: 1,
            inner_edge: EdgeShape::Chords,
            outer_edge: EdgeShape::Arc,
        }
    }
}

fn invalid(field: &'static str, value: impl ToString, reason: String) -> MeshError {
    MeshError::InvalidGeometry {
        field,
        value: value.to_string(),
        reason,
    }
}

impl PadGeometry {
    /// The pad `p` on the rotor `rotor`: radii on the rotor's node rings, the rotor's angular
    /// step, a circle arc where the pad edge lies on the rotor's r_in or r_out circle and chords
    /// elsewhere, so that gmsh puts every friction-face node (hex8 and hex20) on a rotor node.
    pub fn on_rotor(rotor: &RotorGeometry, p: &PadPlacement) -> Result<PadGeometry, MeshError> {
        rotor.validate()?;
        if p.last_ring > rotor.n_rad {
            return Err(invalid(
                "last_ring",
                p.last_ring,
                format!("the rotor has node rings 0..={}", rotor.n_rad),
            ));
        }
        if p.first_ring >= p.last_ring {
            return Err(invalid(
                "first_ring",
                p.first_ring,
                format!("must be smaller than last_ring = {}", p.last_ring),
            ));
        }
        divisions("n_elements", p.n_elements, rotor.n_circ)?;
        if 2 * p.n_elements >= rotor.n_circ {
            return Err(invalid(
                "n_elements",
                p.n_elements,
                format!(
                    "the pad must span less than half the rotor's {} elements",
                    rotor.n_circ
                ),
            ));
        }
        let dr = (rotor.r_out - rotor.r_in) / rotor.n_rad as Real;
        let ring_r = |i: usize| {
            if i == rotor.n_rad {
                rotor.r_out
            } else {
                rotor.r_in + i as Real * dr
            }
        };
        let edge = |i: usize| {
            if i == 0 || i == rotor.n_rad {
                EdgeShape::Arc
            } else {
                EdgeShape::Chords
            }
        };
        let step_deg = 360.0 / rotor.n_circ as Real;
        let g = PadGeometry {
            r_in: ring_r(p.first_ring),
            r_out: ring_r(p.last_ring),
            theta_start_deg: p.start_element as Real * step_deg,
            theta_span_deg: p.n_elements as Real * step_deg,
            n_circ: p.n_elements,
            n_rad: p.last_ring - p.first_ring,
            z_face: match p.side {
                RotorSide::Top => rotor.thickness,
                RotorSide::Bottom => 0.0,
            },
            side: p.side,
            lining: p.lining,
            n_lining: p.n_lining,
            backplate: p.backplate,
            n_backplate: p.n_backplate,
            inner_edge: edge(p.first_ring),
            outer_edge: edge(p.last_ring),
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), MeshError> {
        positive("r_in", self.r_in)?;
        positive("r_out", self.r_out)?;
        if self.r_out <= self.r_in {
            return Err(invalid(
                "r_out",
                self.r_out,
                format!("must be larger than r_in = {}", self.r_in),
            ));
        }
        if !self.theta_start_deg.is_finite() {
            return Err(invalid(
                "theta_start_deg",
                self.theta_start_deg,
                "must be finite".into(),
            ));
        }
        if !(self.theta_span_deg > 0.0 && self.theta_span_deg < 180.0) {
            return Err(invalid(
                "theta_span_deg",
                self.theta_span_deg,
                "must be in (0, 180) degrees (the edges are single circle arcs)".into(),
            ));
        }
        if !self.z_face.is_finite() {
            return Err(invalid("z_face", self.z_face, "must be finite".into()));
        }
        positive("lining", self.lining)?;
        positive("backplate", self.backplate)?;
        divisions("n_circ", self.n_circ, 10_000)?;
        divisions("n_rad", self.n_rad, 10_000)?;
        divisions("n_lining", self.n_lining, 10_000)?;
        divisions("n_backplate", self.n_backplate, 10_000)?;
        Ok(())
    }

    /// z of the backplate's outer face ("back").
    pub fn z_back(&self) -> Real {
        self.z_face + self.side.sign() * (self.lining + self.backplate)
    }

    /// Hex cells of the mesh gmsh makes from [`pad`].
    pub fn n_cells(&self) -> usize {
        self.n_circ * self.n_rad * (self.n_lining + self.n_backplate)
    }

    /// Nodes of that mesh: order 1 (hex8) or 2 (hex20).
    pub fn n_nodes(&self, order: u8) -> usize {
        structured_nodes(
            self.n_circ,
            self.n_rad,
            self.n_lining + self.n_backplate,
            order,
        )
    }
}

/// Nodes of an a × b × c structured hex mesh (open in all directions): corners, and for order 2
/// the mid-edge nodes of the three edge directions.
pub(crate) fn structured_nodes(a: usize, b: usize, c: usize, order: u8) -> usize {
    let corners = (a + 1) * (b + 1) * (c + 1);
    if order < 2 {
        return corners;
    }
    corners + a * (b + 1) * (c + 1) + (a + 1) * b * (c + 1) + (a + 1) * (b + 1) * c
}

/// The `.geo` text of an all-hex pad. Geometry values are `DefineConstant` defaults.
pub fn pad(g: &PadGeometry) -> String {
    let p = |name, value, doc| Param { name, value, doc };
    let mut s = define_constants(
        "Brake pad (lining + backplate)",
        &[
            p("r_in", g.r_in, "inner radius of the friction face"),
            p("r_out", g.r_out, "outer radius of the friction face"),
            p(
                "theta_start",
                g.theta_start_deg,
                "first sector end, degrees",
            ),
            p("theta_span", g.theta_span_deg, "angular span, degrees"),
            p("n_circ", g.n_circ as Real, "elements around the sector"),
            p("n_rad", g.n_rad as Real, "elements across the radius"),
            p("z_face", g.z_face, "z of the friction face"),
            p("dir", g.side.sign(), "+1: pad towards +z, -1: towards -z"),
            p("lining", g.lining, "lining thickness"),
            p(
                "n_lining",
                g.n_lining as Real,
                "elements through the lining",
            ),
            p("backplate", g.backplate, "backplate thickness"),
            p(
                "n_backplate",
                g.n_backplate as Real,
                "elements through the backplate",
            ),
            p(
                "inner_arc",
                g.inner_edge.flag(),
                "1: inner edge a circle arc, 0: chords",
            ),
            p(
                "outer_arc",
                g.outer_edge.flag(),
                "1: outer edge a circle arc, 0: chords",
            ),
        ],
    );
    s.push_str(
        r#"SetFactory("Built-in");
If (theta_span <= 0 || theta_span >= 180)
  Error("theta_span = %g must be in (0, 180) degrees", theta_span);
EndIf
a0 = theta_start * Pi / 180;
da = theta_span * Pi / 180 / n_circ;
centre = newp; Point(centre) = {0, 0, z_face};
"#,
    );
    ring(&mut s, "inner", "r_in", "z_face", "inner_arc");
    ring(&mut s, "outer", "r_out", "z_face", "outer_arc");
    patch(&mut s, "face", "inner", "outer", "n_rad");
    extrude(&mut s, "lin", "face", "dir * lining", "n_lining");
    extrude(&mut s, "bp", "lin[0]", "dir * backplate", "n_backplate");
    s.push_str(
        r#"n_outer = #outer_c[];
Physical Volume("lining", 1) = {lin[1]};
Physical Volume("backplate", 2) = {bp[1]};
Physical Surface("friction", 3) = {face};
Physical Surface("back", 4) = {bp[0]};
Physical Surface("abutment_start", 5) = {lin[2], bp[2]};
Physical Surface("abutment_end", 6) = {lin[3 + n_outer], bp[3 + n_outer]};
"#,
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_default_placement_on_the_default_rotor() {
        let g = PadGeometry::on_rotor(&RotorGeometry::default(), &PadPlacement::default()).unwrap();
        assert_eq!(g, PadGeometry::default());
        assert!((g.z_back() - 1.1).abs() < 1e-15);
    }

    #[test]
    fn placement_errors_name_the_field() {
        let r = RotorGeometry::default();
        let bad = |p: PadPlacement| PadGeometry::on_rotor(&r, &p).unwrap_err().to_string();
        let e = bad(PadPlacement {
            last_ring: 7,
            ..Default::default()
        });
        assert!(e.contains("last_ring"), "{e}");
        let e = bad(PadPlacement {
            first_ring: 6,
            ..Default::default()
        });
        assert!(e.contains("first_ring"), "{e}");
        let e = bad(PadPlacement {
            n_elements: 32,
            ..Default::default()
        });
        assert!(e.contains("n_elements"), "{e}");
        let e = bad(PadPlacement {
            lining: 0.0,
            ..Default::default()
        });
        assert!(e.contains("lining"), "{e}");
    }

    /// Ring 0 of the rotor is its hub circle: the pad's inner edge must then be an arc.
    #[test]
    fn edges_follow_the_rotor_rings() {
        let r = RotorGeometry::default();
        let g = PadGeometry::on_rotor(
            &r,
            &PadPlacement {
                first_ring: 0,
                last_ring: 2,
                side: RotorSide::Bottom,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(g.inner_edge, EdgeShape::Arc);
        assert_eq!(g.outer_edge, EdgeShape::Chords);
        assert_eq!(g.z_face, 0.0);
        assert!((g.z_back() + 0.6).abs() < 1e-15);
    }

    /// 2 × 1 × 1: corners 3·2·2 = 12; hex20 edges 2·2·2 + 3·1·2 + 3·2·1 = 8 + 6 + 6.
    #[test]
    fn node_counts() {
        assert_eq!(structured_nodes(2, 1, 1, 1), 12);
        assert_eq!(structured_nodes(2, 1, 1, 2), 12 + 20);
        let g = PadGeometry::default();
        assert_eq!(g.n_cells(), 10 * 3 * 3);
    }
}
