//! The sample disc brake: rotor, inboard and outboard pads and caliper, placed consistently.

use super::{CaliperDims, CaliperGeometry, PadGeometry, PadPlacement, RotorGeometry, RotorSide};
use crate::MeshError;
use serde::{Deserialize, Serialize};

/// The parameters of the whole sample brake; the pads and the caliper are derived from the
/// rotor's mesh so that every interface has coincident nodes (pad friction faces on the rotor's
/// friction faces, caliper finger and piston faces on the pads' backs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BrakeGeometry {
    /// The rotor (default: [`RotorGeometry::default`], 64 × 6 × 2 elements).
    pub rotor: RotorGeometry,
    /// The inboard (piston-side) pad (default: [`PadPlacement::default`], on the top face).
    pub inboard: PadPlacement,
    /// The outboard (finger-side) pad (default: as the inboard one, on the bottom face).
    pub outboard: PadPlacement,
    /// The caliper (default: [`CaliperDims::default`]).
    pub caliper: CaliperDims,
}

impl Default for BrakeGeometry {
    fn default() -> Self {
        BrakeGeometry {
            rotor: RotorGeometry::default(),
            inboard: PadPlacement::default(),
            outboard: PadPlacement {
                side: RotorSide::Bottom,
                ..Default::default()
            },
            caliper: CaliperDims::default(),
        }
    }
}

impl BrakeGeometry {
    /// The inboard pad on the rotor.
    pub fn inboard_pad(&self) -> Result<PadGeometry, MeshError> {
        PadGeometry::on_rotor(&self.rotor, &self.inboard)
    }

    /// The outboard pad on the rotor.
    pub fn outboard_pad(&self) -> Result<PadGeometry, MeshError> {
        PadGeometry::on_rotor(&self.rotor, &self.outboard)
    }

    /// The caliper over both pads.
    pub fn caliper(&self) -> Result<CaliperGeometry, MeshError> {
        CaliperGeometry::over_pads(
            &self.rotor,
            &self.inboard_pad()?,
            &self.outboard_pad()?,
            &self.caliper,
        )
    }
}
