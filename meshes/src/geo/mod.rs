//! Parametric gmsh `.geo` templates written from Rust.
//!
//! Each template starts with its parameters as `DefineConstant[...]`, so a gmsh run can
//! override them (`-setnumber r_out 6`, see [`crate::gmsh::GmshOptions::set_numbers`]), and
//! meshes all-hex: transfinite quadrangles recombined in the z = 0 plane, extruded in layers
//! along +z. Physical groups name the volume, the faces and (for the block) the supported edges.

mod block;
mod brake;
mod caliper;
mod pad;
mod rotor;
mod sector;

pub use block::{block, BlockGeometry};
pub use brake::BrakeGeometry;
pub use caliper::{caliper, CaliperDims, CaliperGeometry};
pub use pad::{pad, PadGeometry, PadPlacement, RotorSide};
pub use rotor::{annulus, rotor, RotorGeometry};
pub use sector::EdgeShape;

use crate::{MeshError, Real};
use std::fmt::Write;

/// A gmsh parameter: its name, value and what it is.
pub(crate) struct Param {
    pub name: &'static str,
    pub value: Real,
    pub doc: &'static str,
}

/// `DefineConstant[...]` for the parameters, one per line with its description.
pub(crate) fn define_constants(title: &str, params: &[Param]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "// {title}, written by squeal-meshes.");
    let _ = writeln!(
        s,
        "// Parameters may be overridden on the command line: gmsh -setnumber NAME VALUE."
    );
    s.push_str("DefineConstant[\n");
    for (i, p) in params.iter().enumerate() {
        let sep = if i + 1 < params.len() { "," } else { "" };
        let _ = writeln!(
            s,
            "  {} = {{{}, Name \"Parameters/{}\"}}{sep} // {}",
            p.name,
            number(p.value),
            p.name,
            p.doc
        );
    }
    s.push_str("];\n");
    s
}

/// A real as gmsh reads it back exactly (Rust's shortest round-trip form).
pub(crate) fn number(v: Real) -> String {
    format!("{v:?}")
}

/// Checks that a length is finite and positive.
pub(crate) fn positive(field: &'static str, v: Real) -> Result<(), MeshError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(MeshError::InvalidGeometry {
            field,
            value: v.to_string(),
            reason: "must be a finite number > 0".into(),
        })
    }
}

/// Checks that a division count is in 1..=max.
pub(crate) fn divisions(field: &'static str, n: usize, max: usize) -> Result<(), MeshError> {
    if (1..=max).contains(&n) {
        Ok(())
    } else {
        Err(MeshError::InvalidGeometry {
            field,
            value: n.to_string(),
            reason: format!("must be between 1 and {max}"),
        })
    }
}
