//! Annular disc: a brake rotor, or the thin annular plate of the verification suite.

use super::{define_constants, divisions, positive, Param};
use crate::{MeshError, Real};
use serde::{Deserialize, Serialize};

/// An annular disc between radii `r_in` and `r_out`, from z = 0 to z = `thickness`, centred
/// on the z axis. Physical groups: volume "rotor"; surfaces "hub" (r = r_in), "outer"
/// (r = r_out), "friction_bottom" (z = 0), "friction_top" (z = thickness).
/// Units are the user's (the default is a sample rotor in inches).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RotorGeometry {
    /// Inner (hub) radius (default: 2.0).
    pub r_in: Real,
    /// Outer radius (default: 5.5).
    pub r_out: Real,
    /// Axial thickness (default: 0.5).
    pub thickness: Real,
    /// Elements around the circumference, a multiple of 4 (default: 64).
    pub n_circ: usize,
    /// Elements across the radius (default: 6).
    pub n_rad: usize,
    /// Elements through the thickness (default: 2).
    pub n_thick: usize,
}

impl Default for RotorGeometry {
    /// A sample solid rotor in inches: 11 in outside, 4 in hub bore, 0.5 in thick.
    fn default() -> Self {
        RotorGeometry {
            r_in: 2.0,
            r_out: 5.5,
            thickness: 0.5,
            n_circ: 64,
            n_rad: 6,
            n_thick: 2,
        }
    }
}

impl RotorGeometry {
    /// The thin annular plate of the verification suite (SI units): outer radius a = 0.16 m,
    /// inner radius b = 0.08 m, thickness h = 4 mm, 64 × 8 × 2 elements; clamp the set "hub".
    pub fn annular_plate() -> Self {
        RotorGeometry {
            r_in: 0.08,
            r_out: 0.16,
            thickness: 0.004,
            n_circ: 64,
            n_rad: 8,
            n_thick: 2,
        }
    }

    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), MeshError> {
        positive("r_in", self.r_in)?;
        positive("r_out", self.r_out)?;
        positive("thickness", self.thickness)?;
        if self.r_out <= self.r_in {
            return Err(MeshError::InvalidGeometry {
                field: "r_out",
                value: self.r_out.to_string(),
                reason: format!("must be larger than r_in = {}", self.r_in),
            });
        }
        divisions("n_circ", self.n_circ, 100_000)?;
        if self.n_circ % 4 != 0 {
            return Err(MeshError::InvalidGeometry {
                field: "n_circ",
                value: self.n_circ.to_string(),
                reason: "must be a multiple of 4 (the disc is meshed in quarters)".into(),
            });
        }
        divisions("n_rad", self.n_rad, 10_000)?;
        divisions("n_thick", self.n_thick, 10_000)?;
        Ok(())
    }

    /// Hex cells of the mesh gmsh makes from [`rotor`].
    pub fn n_cells(&self) -> usize {
        self.n_circ * self.n_rad * self.n_thick
    }

    /// Nodes of that mesh: order 1 (hex8) or 2 (hex20, incomplete second order).
    pub fn n_nodes(&self, order: u8) -> usize {
        let (c, r, t) = (self.n_circ, self.n_rad, self.n_thick);
        let corners = c * (r + 1) * (t + 1);
        if order < 2 {
            return corners;
        }
        // Mid-edge nodes: circumferential, radial and axial edges.
        corners + c * (r + 1) * (t + 1) + c * r * (t + 1) + c * (r + 1) * t
    }
}

/// The annular plate is a rotor; this is [`rotor`] under the verification suite's name.
pub fn annulus(g: &RotorGeometry) -> String {
    rotor(g)
}

/// The `.geo` text of an all-hex annular disc. Geometry values are written as
/// `DefineConstant` defaults, so `gmsh -setnumber r_out 6` changes them.
pub fn rotor(g: &RotorGeometry) -> String {
    let mut s = define_constants(
        "Annular disc (rotor)",
        &[
            Param {
                name: "r_in",
                value: g.r_in,
                doc: "inner (hub) radius",
            },
            Param {
                name: "r_out",
                value: g.r_out,
                doc: "outer radius",
            },
            Param {
                name: "thickness",
                value: g.thickness,
                doc: "axial thickness, z = 0 .. thickness",
            },
            Param {
                name: "n_circ",
                value: g.n_circ as Real,
                doc: "elements around the circumference (multiple of 4)",
            },
            Param {
                name: "n_rad",
                value: g.n_rad as Real,
                doc: "elements across the radius",
            },
            Param {
                name: "n_thick",
                value: g.n_thick as Real,
                doc: "elements through the thickness",
            },
        ],
    );
    s.push_str(ROTOR_BODY);
    s
}

/// Four quarter-annulus transfinite quadrangles at z = 0, extruded along +z in layers.
/// Extrude returns [top, volume, side of each boundary curve in loop order], so with the loop
/// {radial q, outer arc q, -radial q+1, -inner arc q} the sides are ex[3] = outer, ex[5] = hub.
const ROTOR_BODY: &str = r#"SetFactory("Built-in");
If (n_circ % 4 != 0 || n_circ < 4)
  Error("n_circ = %g must be a positive multiple of 4", n_circ);
EndIf
centre = newp; Point(centre) = {0, 0, 0};
For q In {0:3}
  angle = q * Pi / 2;
  p_in[q] = newp; Point(p_in[q]) = {r_in * Cos(angle), r_in * Sin(angle), 0};
  p_out[q] = newp; Point(p_out[q]) = {r_out * Cos(angle), r_out * Sin(angle), 0};
EndFor
For q In {0:3}
  q_next = (q + 1) % 4;
  arc_in[q] = newc; Circle(arc_in[q]) = {p_in[q], centre, p_in[q_next]};
  arc_out[q] = newc; Circle(arc_out[q]) = {p_out[q], centre, p_out[q_next]};
  radial[q] = newc; Line(radial[q]) = {p_in[q], p_out[q]};
EndFor
For q In {0:3}
  q_next = (q + 1) % 4;
  cloop = newcl; Curve Loop(cloop) = {radial[q], arc_out[q], -radial[q_next], -arc_in[q]};
  bottom[q] = news; Plane Surface(bottom[q]) = {cloop};
  Transfinite Curve{arc_in[q], arc_out[q]} = n_circ / 4 + 1;
  Transfinite Curve{radial[q]} = n_rad + 1;
  Transfinite Surface{bottom[q]};
  Recombine Surface{bottom[q]};
EndFor
For q In {0:3}
  ex[] = Extrude {0, 0, thickness} { Surface{bottom[q]}; Layers{n_thick}; Recombine; };
  top[q] = ex[0];
  body[q] = ex[1];
  outer[q] = ex[3];
  hub[q] = ex[5];
EndFor
Physical Volume("rotor", 1) = {body[]};
Physical Surface("hub", 2) = {hub[]};
Physical Surface("outer", 3) = {outer[]};
Physical Surface("friction_bottom", 4) = {bottom[]};
Physical Surface("friction_top", 5) = {top[]};
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_bad_values_name_the_field() {
        RotorGeometry::default().validate().unwrap();
        RotorGeometry::annular_plate().validate().unwrap();
        let g = RotorGeometry {
            n_circ: 10,
            ..Default::default()
        };
        assert!(g.validate().unwrap_err().to_string().contains("n_circ"));
        let g = RotorGeometry {
            r_out: 1.0,
            ..Default::default()
        };
        assert!(g.validate().unwrap_err().to_string().contains("r_out"));
        let g = RotorGeometry {
            thickness: Real::NAN,
            ..Default::default()
        };
        assert!(g.validate().unwrap_err().to_string().contains("thickness"));
    }

    #[test]
    fn geo_text_defines_the_parameters() {
        let text = rotor(&RotorGeometry::annular_plate());
        assert!(text.contains("r_in = {0.08, Name \"Parameters/r_in\"}"));
        assert!(text.contains("thickness = {0.004,"));
        assert!(text.contains("n_circ = {64.0,"));
        for name in [
            "\"rotor\"",
            "\"hub\"",
            "\"outer\"",
            "\"friction_bottom\"",
            "\"friction_top\"",
        ] {
            assert!(text.contains(name), "{name}");
        }
    }

    /// Counting by hand for 8 × 2 × 1: corners 8·3·2 = 48; hex20 adds 8·3·2 circumferential,
    /// 8·2·2 radial and 8·3·1 axial mid-edge nodes = 48 + 32 + 24.
    #[test]
    fn node_counts() {
        let g = RotorGeometry {
            n_circ: 8,
            n_rad: 2,
            n_thick: 1,
            ..Default::default()
        };
        assert_eq!(g.n_nodes(1), 48);
        assert_eq!(g.n_nodes(2), 48 + 48 + 32 + 24);
        assert_eq!(g.n_cells(), 16);
    }
}
