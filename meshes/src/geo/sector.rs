//! gmsh-script pieces shared by the pad and caliper templates: node rings on a circle and
//! annular-sector patches between two rings, all at one z.
//!
//! The rotor template meshes quarter annuli whose boundary curves are circle arcs and whose
//! interior is transfinite; gmsh then puts the hex20 mid-edge nodes of the boundary arcs on the
//! circle and those of interior circumferential edges on the chord (their midpoint in the plane
//! surface's linear parametrisation). A part that must share nodes with that mesh therefore
//! draws a ring as one circle arc where the rotor has its boundary circle (r_in, r_out), and as a
//! polyline of straight chords, one per element, where the rotor has an interior node ring
//! ([`EdgeShape`]). With the same node angles, both give the same corner and mid-edge nodes.
//!
//! The snippets expect the gmsh variables `a0` (first angle, rad), `da` (angular step, rad),
//! `n_circ` (elements around the sector) and the point `centre` on the axis at the ring's z.

use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// How a circumferential edge of a sector is drawn: one circle arc, or straight chords
/// between the nodes (see the module documentation for why both are needed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EdgeShape {
    /// A circle arc: hex20 mid-edge nodes on the circle (the rotor's r_in and r_out rings).
    Arc,
    /// Straight chords, one per element: mid-edge nodes on the chords (interior rotor rings).
    Chords,
}

impl EdgeShape {
    /// 1 for an arc, 0 for chords (the value written to the `.geo` parameters).
    pub(crate) fn flag(self) -> f64 {
        match self {
            EdgeShape::Arc => 1.0,
            EdgeShape::Chords => 0.0,
        }
    }
}

/// gmsh code for a node ring `id` at radius `r` and height `z` (gmsh expressions): points
/// `{id}_p[0..=n_circ]` (only both ends for an arc) and curves `{id}_c[]` in increasing angle;
/// `arc` is a gmsh expression, non-zero for one circle arc, zero for chords.
pub(crate) fn ring(s: &mut String, id: &str, r: &str, z: &str, arc: &str) {
    let _ = write!(
        s,
        r#"// Node ring `{id}`: r = {r}, z = {z}.
For k In {{0:n_circ}}
  If (k == 0 || k == n_circ || ({arc}) == 0)
    {id}_p[k] = newp; Point({id}_p[k]) = {{({r}) * Cos(a0 + k * da), ({r}) * Sin(a0 + k * da), {z}}};
  EndIf
EndFor
If (({arc}) != 0)
  c = newc; Circle(c) = {{{id}_p[0], centre, {id}_p[n_circ]}};
  {id}_c[] = {{c}};
  Transfinite Curve{{c}} = n_circ + 1;
Else
  For k In {{0:n_circ - 1}}
    c = newc; Line(c) = {{{id}_p[k], {id}_p[k + 1]}};
    {id}_c[k] = c;
    Transfinite Curve{{c}} = 2;
  EndFor
EndIf
"#
    );
}

/// gmsh code for the transfinite, recombined plane patch `id` between rings `inner` and
/// `outer` with `n_rad` (a gmsh expression) elements across. Its curve loop is
/// {radial edge at a0, outer ring, −radial edge at the last angle, −inner ring}, so an
/// `Extrude` of it returns [top, volume, side at a0, `#outer_c[]` outer sides, side at the last
/// angle, inner sides].
pub(crate) fn patch(s: &mut String, id: &str, inner: &str, outer: &str, n_rad: &str) {
    let _ = write!(
        s,
        r#"// Patch `{id}` between rings `{inner}` and `{outer}`.
{id}_r0 = newc; Line({id}_r0) = {{{inner}_p[0], {outer}_p[0]}};
{id}_r1 = newc; Line({id}_r1) = {{{inner}_p[n_circ], {outer}_p[n_circ]}};
Transfinite Curve{{{id}_r0, {id}_r1}} = ({n_rad}) + 1;
{id}_loop[] = {{{id}_r0}};
{id}_loop[] += {outer}_c[];
{id}_loop[] += {{-{id}_r1}};
For k In {{#{inner}_c[] - 1:0:-1}}
  {id}_loop[] += {{-{inner}_c[k]}};
EndFor
cl = newcl; Curve Loop(cl) = {{{id}_loop[]}};
{id} = news; Plane Surface({id}) = {{cl}};
Transfinite Surface{{{id}}} = {{{inner}_p[0], {outer}_p[0], {outer}_p[n_circ], {inner}_p[n_circ]}};
Recombine Surface{{{id}}};
"#
    );
}

/// gmsh code extruding `surface` by `dz` (a gmsh expression) in `layers` layers, the result in
/// the list `{out}[]` ([top, volume, sides...]).
pub(crate) fn extrude(s: &mut String, out: &str, surface: &str, dz: &str, layers: &str) {
    let _ = writeln!(
        s,
        "{out}[] = Extrude {{0, 0, {dz}}} {{ Surface{{{surface}}}; Layers{{{layers}}}; Recombine; }};"
    );
}
