//! Caliper: a C-shaped bridge over the rotor rim, with fingers behind the outboard pad and a
//! piston behind the inboard pad, sharing nodes with both pads' backs.

use super::pad::RotorSide;
use super::sector::{extrude, patch, ring, EdgeShape};
use super::{define_constants, divisions, positive, PadGeometry, Param, RotorGeometry};
use crate::{MeshError, Real};
use serde::{Deserialize, Serialize};

/// The caliper's own dimensions; its footprint and axial positions come from the pads
/// ([`CaliperGeometry::over_pads`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CaliperDims {
    /// Radial clearance between the rotor's outer radius and the bridge (default: 0.25).
    pub clearance: Real,
    /// Radial thickness of the bridge (default: 0.6).
    pub bridge_thickness: Real,
    /// Axial thickness of the fingers behind the outboard pad (default: 0.4).
    pub finger_thickness: Real,
    /// Axial length of the piston behind the inboard pad (default: 0.5).
    pub piston_length: Real,
    /// Axial thickness of the housing behind the piston (default: 0.4).
    pub housing_thickness: Real,
    /// Elements across the radial gap between the pads' outer radius and the bridge (default: 1).
    pub n_gap: usize,
    /// Elements across the bridge's radial thickness (default: 1).
    pub n_bridge: usize,
    /// Elements through the fingers (default: 1).
    pub n_finger: usize,
    /// Elements along the bridge between the two pad backs (default: 3).
    pub n_middle: usize,
    /// Elements along the piston (default: 1).
    pub n_piston: usize,
    /// Elements through the housing (default: 1).
    pub n_housing: usize,
}

impl Default for CaliperDims {
    fn default() -> Self {
        CaliperDims {
            clearance: 0.25,
            bridge_thickness: 0.6,
            finger_thickness: 0.4,
            piston_length: 0.5,
            housing_thickness: 0.4,
            n_gap: 1,
            n_bridge: 1,
            n_finger: 1,
            n_middle: 3,
            n_piston: 1,
            n_housing: 1,
        }
    }
}

/// A caliper spanning the pads' angles. In the (r, z) section it is a C: fingers (z_finger
/// outwards by `finger_thickness`) from the pads' inner radius up to the bridge's outer radius;
/// the bridge (r_bridge_in .. r_bridge_out) from the fingers to the housing; behind the inboard
/// pad the piston (pads' radii, `piston_length`) in a housing wall (pads' outer radius ..
/// r_bridge_out), then the housing (`housing_thickness`) over all radii.
///
/// Physical groups: volumes "caliper" (1: fingers, bridge, housing) and "piston" (2), so
/// `Mesh::volumes` is `[caliper, piston]`; surfaces "finger_face" (3, at z_finger, on the
/// outboard pad's "back"), "piston_face" (4, at z_piston, on the inboard pad's "back"),
/// "housing_back" (5, the housing's outer axial face), "mount" (6, the housing's two
/// circumferential end faces, where a fixed caliper is bolted to the knuckle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CaliperGeometry {
    /// Pads' inner radius (default: 3.75).
    pub r_pad_in: Real,
    /// Pads' outer radius (default: 5.5).
    pub r_pad_out: Real,
    /// Bridge inner radius, > r_pad_out (default: 5.75).
    pub r_bridge_in: Real,
    /// Bridge outer radius (default: 6.35).
    pub r_bridge_out: Real,
    /// First sector end, degrees from +x about +z (default: −28.125).
    pub theta_start_deg: Real,
    /// Angular span, degrees, in (0, 180) (default: 56.25).
    pub theta_span_deg: Real,
    /// Elements around the sector (default: 10).
    pub n_circ: usize,
    /// Elements across the pads' radii (default: 3).
    pub n_rad: usize,
    /// Elements across the gap r_pad_out .. r_bridge_in (default: 1).
    pub n_gap: usize,
    /// Elements across the bridge (default: 1).
    pub n_bridge: usize,
    /// Shape of the edge at r_pad_in, as the pads' (default: chords).
    pub pad_inner_edge: EdgeShape,
    /// Shape of the edge at r_pad_out, as the pads' (default: arc).
    pub pad_outer_edge: EdgeShape,
    /// z of the outboard pad's back = the fingers' face (default: −0.6).
    pub z_finger: Real,
    /// z of the inboard pad's back = the piston's face (default: 1.1).
    pub z_piston: Real,
    /// Finger thickness (default: 0.4).
    pub finger_thickness: Real,
    /// Elements through the fingers (default: 1).
    pub n_finger: usize,
    /// Elements along the bridge from z_finger to z_piston (default: 3).
    pub n_middle: usize,
    /// Piston length (default: 0.5).
    pub piston_length: Real,
    /// Elements along the piston (default: 1).
    pub n_piston: usize,
    /// Housing thickness behind the piston (default: 0.4).
    pub housing_thickness: Real,
    /// Elements through the housing (default: 1).
    pub n_housing: usize,
}

impl Default for CaliperGeometry {
    /// [`CaliperDims::default`] over the sample brake's default pads.
    fn default() -> Self {
        CaliperGeometry {
            r_pad_in: 3.75,
            r_pad_out: 5.5,
            r_bridge_in: 5.75,
            r_bridge_out: 6.35,
            theta_start_deg: -28.125,
            theta_span_deg: 56.25,
            n_circ: 10,
            n_rad: 3,
            n_gap: 1,
            n_bridge: 1,
            pad_inner_edge: EdgeShape::Chords,
            pad_outer_edge: EdgeShape::Arc,
            z_finger: -0.6,
            z_piston: 1.1,
            finger_thickness: 0.4,
            n_finger: 1,
            n_middle: 3,
            piston_length: 0.5,
            n_piston: 1,
            housing_thickness: 0.4,
            n_housing: 1,
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

impl CaliperGeometry {
    /// The caliper over `inboard` (piston side) and `outboard` (finger side) pads on `rotor`:
    /// the pads must have the same footprint (radii, angles, divisions, edge shapes) on opposite
    /// faces; the caliper takes it, so its finger and piston faces have the pads' back nodes.
    pub fn over_pads(
        rotor: &RotorGeometry,
        inboard: &PadGeometry,
        outboard: &PadGeometry,
        dims: &CaliperDims,
    ) -> Result<CaliperGeometry, MeshError> {
        rotor.validate()?;
        inboard.validate()?;
        outboard.validate()?;
        if inboard.side == outboard.side {
            return Err(invalid(
                "outboard.side",
                format!("{:?}", outboard.side),
                "the two pads must sit on opposite rotor faces".into(),
            ));
        }
        let same = |a: Real, b: Real| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
        let footprint = [
            ("outboard.r_in", inboard.r_in, outboard.r_in),
            ("outboard.r_out", inboard.r_out, outboard.r_out),
            (
                "outboard.theta_start_deg",
                inboard.theta_start_deg,
                outboard.theta_start_deg,
            ),
            (
                "outboard.theta_span_deg",
                inboard.theta_span_deg,
                outboard.theta_span_deg,
            ),
            (
                "outboard.n_circ",
                inboard.n_circ as Real,
                outboard.n_circ as Real,
            ),
            (
                "outboard.n_rad",
                inboard.n_rad as Real,
                outboard.n_rad as Real,
            ),
        ];
        for (field, a, b) in footprint {
            if !same(a, b) {
                return Err(invalid(
                    field,
                    b,
                    format!("must equal the inboard pad's {a} (one caliper footprint)"),
                ));
            }
        }
        if inboard.inner_edge != outboard.inner_edge || inboard.outer_edge != outboard.outer_edge {
            return Err(invalid(
                "outboard.inner_edge",
                format!("{:?}/{:?}", outboard.inner_edge, outboard.outer_edge),
                "edge shapes must equal the inboard pad's".into(),
            ));
        }
        positive("clearance", dims.clearance)?;
        positive("bridge_thickness", dims.bridge_thickness)?;
        let r_bridge_in = rotor.r_out.max(inboard.r_out) + dims.clearance;
        let g = CaliperGeometry {
            r_pad_in: inboard.r_in,
            r_pad_out: inboard.r_out,
            r_bridge_in,
            r_bridge_out: r_bridge_in + dims.bridge_thickness,
            theta_start_deg: inboard.theta_start_deg,
            theta_span_deg: inboard.theta_span_deg,
            n_circ: inboard.n_circ,
            n_rad: inboard.n_rad,
            n_gap: dims.n_gap,
            n_bridge: dims.n_bridge,
            pad_inner_edge: inboard.inner_edge,
            pad_outer_edge: inboard.outer_edge,
            z_finger: outboard.z_back(),
            z_piston: inboard.z_back(),
            finger_thickness: dims.finger_thickness,
            n_finger: dims.n_finger,
            n_middle: dims.n_middle,
            piston_length: dims.piston_length,
            n_piston: dims.n_piston,
            housing_thickness: dims.housing_thickness,
            n_housing: dims.n_housing,
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), MeshError> {
        positive("r_pad_in", self.r_pad_in)?;
        let radii = [
            ("r_pad_out", self.r_pad_in, self.r_pad_out),
            ("r_bridge_in", self.r_pad_out, self.r_bridge_in),
            ("r_bridge_out", self.r_bridge_in, self.r_bridge_out),
        ];
        for (field, below, v) in radii {
            if !(v.is_finite() && v > below) {
                return Err(invalid(
                    field,
                    v,
                    format!("must be larger than the radius inside it, {below}"),
                ));
            }
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
                "must be in (0, 180) degrees".into(),
            ));
        }
        if !(self.z_finger.is_finite() && self.z_piston.is_finite())
            || self.z_finger == self.z_piston
        {
            return Err(invalid(
                "z_piston",
                self.z_piston,
                format!(
                    "must be finite and differ from z_finger = {}",
                    self.z_finger
                ),
            ));
        }
        positive("finger_thickness", self.finger_thickness)?;
        positive("piston_length", self.piston_length)?;
        positive("housing_thickness", self.housing_thickness)?;
        for (field, n) in [
            ("n_circ", self.n_circ),
            ("n_rad", self.n_rad),
            ("n_gap", self.n_gap),
            ("n_bridge", self.n_bridge),
            ("n_finger", self.n_finger),
            ("n_middle", self.n_middle),
            ("n_piston", self.n_piston),
            ("n_housing", self.n_housing),
        ] {
            divisions(field, n, 10_000)?;
        }
        Ok(())
    }

    /// The side of the rotor the piston is on.
    pub fn piston_side(&self) -> RotorSide {
        if self.z_piston > self.z_finger {
            RotorSide::Top
        } else {
            RotorSide::Bottom
        }
    }

    /// Hex cells of the mesh gmsh makes from [`caliper`] (caliper and piston).
    pub fn n_cells(&self) -> usize {
        let across = self.n_rad + self.n_gap + self.n_bridge;
        self.n_circ
            * (across * (self.n_finger + self.n_piston + self.n_housing)
                + self.n_bridge * self.n_middle)
    }
}

/// The `.geo` text of an all-hex caliper. Geometry values are `DefineConstant` defaults.
pub fn caliper(g: &CaliperGeometry) -> String {
    let p = |name, value, doc| Param { name, value, doc };
    let mut s = define_constants(
        "Brake caliper (fingers, bridge, housing, piston)",
        &[
            p("r_pad_in", g.r_pad_in, "pads' inner radius"),
            p("r_pad_out", g.r_pad_out, "pads' outer radius"),
            p("r_bridge_in", g.r_bridge_in, "bridge inner radius"),
            p("r_bridge_out", g.r_bridge_out, "bridge outer radius"),
            p(
                "theta_start",
                g.theta_start_deg,
                "first sector end, degrees",
            ),
            p("theta_span", g.theta_span_deg, "angular span, degrees"),
            p("n_circ", g.n_circ as Real, "elements around the sector"),
            p("n_rad", g.n_rad as Real, "elements across the pads"),
            p("n_gap", g.n_gap as Real, "elements across the gap"),
            p("n_bridge", g.n_bridge as Real, "elements across the bridge"),
            p(
                "pad_inner_arc",
                g.pad_inner_edge.flag(),
                "1: arc, 0: chords",
            ),
            p(
                "pad_outer_arc",
                g.pad_outer_edge.flag(),
                "1: arc, 0: chords",
            ),
            p("z_finger", g.z_finger, "z of the fingers' face"),
            p("z_piston", g.z_piston, "z of the piston's face"),
            p("finger_thickness", g.finger_thickness, "finger thickness"),
            p(
                "n_finger",
                g.n_finger as Real,
                "elements through the fingers",
            ),
            p("n_middle", g.n_middle as Real, "elements along the bridge"),
            p("piston_length", g.piston_length, "piston length"),
            p("n_piston", g.n_piston as Real, "elements along the piston"),
            p(
                "housing_thickness",
                g.housing_thickness,
                "housing thickness",
            ),
            p(
                "n_housing",
                g.n_housing as Real,
                "elements through the housing",
            ),
        ],
    );
    s.push_str(
        r#"SetFactory("Built-in");
If (theta_span <= 0 || theta_span >= 180)
  Error("theta_span = %g must be in (0, 180) degrees", theta_span);
EndIf
dir = (z_piston > z_finger) ? 1 : -1;
z0 = z_finger - dir * finger_thickness;
a0 = theta_start * Pi / 180;
da = theta_span * Pi / 180 / n_circ;
centre = newp; Point(centre) = {0, 0, z0};
"#,
    );
    ring(&mut s, "ra", "r_pad_in", "z0", "pad_inner_arc");
    ring(&mut s, "rb", "r_pad_out", "z0", "pad_outer_arc");
    ring(&mut s, "rc", "r_bridge_in", "z0", "1");
    ring(&mut s, "rd", "r_bridge_out", "z0", "1");
    patch(&mut s, "zp", "ra", "rb", "n_rad");
    patch(&mut s, "zg", "rb", "rc", "n_gap");
    patch(&mut s, "zb", "rc", "rd", "n_bridge");
    // Layers 1 fingers, 2 middle (only the bridge is kept), 3 piston, 4 housing; one Extrude
    // per zone and layer, sides shared through the built-in kernel's coherence.
    let layers = [
        ("dir * finger_thickness", "n_finger"),
        ("z_piston - z_finger", "n_middle"),
        ("dir * piston_length", "n_piston"),
        ("dir * housing_thickness", "n_housing"),
    ];
    for zone in ["zp", "zg", "zb"] {
        let mut below = zone.to_string();
        for (k, (dz, n)) in layers.iter().enumerate() {
            let out = format!("{zone}{}", k + 1);
            extrude(&mut s, &out, &below, dz, n);
            below = format!("{out}[0]");
        }
    }
    s.push_str(
        r#"nb = #rb_c[];
Physical Volume("caliper", 1) = {zp1[1], zg1[1], zb1[1], zb2[1], zg3[1], zb3[1], zp4[1], zg4[1], zb4[1]};
Physical Volume("piston", 2) = {zp3[1]};
Physical Surface("finger_face", 3) = {zp1[0]};
Physical Surface("piston_face", 4) = {zp2[0]};
Physical Surface("housing_back", 5) = {zp4[0], zg4[0], zb4[0]};
Physical Surface("mount", 6) = {zp4[2], zp4[3 + nb], zg4[2], zg4[4], zb4[2], zb4[4]};
"#,
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geo::PadPlacement;

    fn pads() -> (RotorGeometry, PadGeometry, PadGeometry) {
        let r = RotorGeometry::default();
        let inb = PadGeometry::on_rotor(&r, &PadPlacement::default()).unwrap();
        let outb = PadGeometry::on_rotor(
            &r,
            &PadPlacement {
                side: RotorSide::Bottom,
                ..Default::default()
            },
        )
        .unwrap();
        (r, inb, outb)
    }

    #[test]
    fn default_is_the_default_dims_over_the_default_pads() {
        let (r, inb, outb) = pads();
        let g = CaliperGeometry::over_pads(&r, &inb, &outb, &CaliperDims::default()).unwrap();
        let d = CaliperGeometry::default();
        assert!((g.z_finger - d.z_finger).abs() < 1e-15 && (g.z_piston - d.z_piston).abs() < 1e-15);
        assert_eq!(
            CaliperGeometry {
                z_finger: d.z_finger,
                z_piston: d.z_piston,
                ..g.clone()
            },
            d
        );
        assert_eq!(g.piston_side(), RotorSide::Top);
        // Section cells: (3 + 1 + 1)·(1 + 1 + 1) + 1·3 = 18 per angular element.
        assert_eq!(g.n_cells(), 10 * 18);
    }

    #[test]
    fn mismatched_pads_are_refused_with_the_field() {
        let (r, inb, mut outb) = pads();
        let e = CaliperGeometry::over_pads(&r, &inb, &inb, &CaliperDims::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("side"), "{e}");
        outb.theta_start_deg += 5.625;
        let e = CaliperGeometry::over_pads(&r, &inb, &outb, &CaliperDims::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("theta_start_deg"), "{e}");
    }
}
