//! Abaqus solid element types and their face numbering.
//!
//! # Reference
//! Abaqus Analysis User's Guide, "Three-dimensional solid element library": node ordering and
//! face numbering. The node orders of C3D4, C3D10, C3D6, C3D15, C3D8 and C3D20 are squeal's
//! (= VTK's, [`crate::mesh`]) as they are, so no permutation is needed. Faces (1-based nodes):
//! hexahedra S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1;
//! tetrahedra S1 1-2-3, S2 1-4-2, S3 2-4-3, S4 3-4-1; wedges S1 1-2-3, S2 4-6-5,
//! S3 1-4-5-2, S4 2-5-6-3, S5 3-6-4-1.

use crate::CellKind;

/// An Abaqus solid element type squeal reads: a family (`C3D20`) and a variant suffix
/// (`R`, `H`, `RH`, `I`, `M`, `MH`, …) that changes the integration or the formulation but
/// not the nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct ElemType {
    /// Index into [`FAMILIES`].
    family: u8,
    /// Index into [`SUFFIXES`].
    suffix: u8,
}

/// Families: (name, squeal kind).
const FAMILIES: [(&str, CellKind); 6] = [
    ("C3D4", CellKind::Tet4),
    ("C3D10", CellKind::Tet10),
    ("C3D6", CellKind::Wedge6),
    ("C3D15", CellKind::Wedge15),
    ("C3D8", CellKind::Hex8),
    ("C3D20", CellKind::Hex20),
];

/// Variant suffixes read (the empty one first); `T` (coupled temperature), `P` (pore
/// pressure), `E` (piezoelectric) add degrees of freedom and are not.
const SUFFIXES: [&str; 8] = ["", "I", "R", "H", "RH", "IH", "M", "MH"];

impl ElemType {
    /// The readable type names, for messages.
    pub const NAMES: [&'static str; 6] = ["C3D4", "C3D10", "C3D6", "C3D15", "C3D8", "C3D20"];

    /// The type of an upper-case Abaqus name (family + variant suffix), if read.
    pub fn from_name(name: &str) -> Option<ElemType> {
        // Longest family first (C3D20 before C3D4… is not a prefix issue except C3D1x).
        let mut best: Option<ElemType> = None;
        for (f, (fam, kind)) in FAMILIES.iter().enumerate() {
            let Some(rest) = name.strip_prefix(fam) else {
                continue;
            };
            let Some(s) = SUFFIXES.iter().position(|x| *x == rest) else {
                continue;
            };
            // I and IH are hexahedron-8 variants only; M and MH tetrahedron-10 only.
            let ok = match SUFFIXES[s] {
                "I" | "IH" => *kind == CellKind::Hex8,
                "M" | "MH" => *kind == CellKind::Tet10,
                _ => true,
            };
            if ok {
                best = Some(ElemType {
                    family: f as u8,
                    suffix: s as u8,
                });
            }
        }
        best
    }

    /// The Abaqus name, e.g. `C3D20R`.
    pub fn name(self) -> String {
        format!(
            "{}{}",
            FAMILIES[self.family as usize].0, SUFFIXES[self.suffix as usize]
        )
    }

    pub fn n_nodes(self) -> usize {
        self.kind().n_nodes()
    }

    /// The squeal cell kind.
    pub fn kind(self) -> CellKind {
        FAMILIES[self.family as usize].1
    }

    /// What squeal computes differently from Abaqus for this type (None: the same element).
    pub fn note(self) -> Option<String> {
        let name = self.name();
        let suffix = SUFFIXES[self.suffix as usize];
        let kind = self.kind();
        let what = match (kind, suffix) {
            (CellKind::Hex8, "I") => {
                "read as hex8 with the component's `hex8` formulation (default: incompatible \
                 modes, as C3D8I)"
            }
            (CellKind::Hex8, "") => {
                "(full integration, which locks in bending) read as hex8 with the component's \
                 `hex8` formulation (default: incompatible modes, as C3D8I)"
            }
            (CellKind::Hex8, _) => {
                "(reduced integration with hourglass control, or hybrid) read as hex8 with the \
                 component's `hex8` formulation (default: incompatible modes, as C3D8I): \
                 frequencies differ from Abaqus's"
            }
            (CellKind::Hex20, "R" | "RH") => {
                "(8-point reduced integration) read as hex20 with squeal's 27-point rule: \
                 slightly stiffer than Abaqus's"
            }
            (CellKind::Tet10, "M" | "MH") => {
                "(Abaqus's modified tetrahedron) read as the standard tet10"
            }
            (_, "H") => {
                "(hybrid, mixed displacement–pressure) read as the displacement element of the \
                 same nodes"
            }
            _ => return None,
        };
        Some(format!("{name} {what}"))
    }

    /// Face `k` (1-based, S1 …) as 0-based corner indices, or None when the type has no such
    /// face.
    pub fn face_corners(self, k: u8) -> Option<&'static [usize]> {
        const HEX: [&[usize]; 6] = [
            &[0, 1, 2, 3],
            &[4, 7, 6, 5],
            &[0, 4, 5, 1],
            &[1, 5, 6, 2],
            &[2, 6, 7, 3],
            &[3, 7, 4, 0],
        ];
        const TET: [&[usize]; 4] = [&[0, 1, 2], &[0, 3, 1], &[1, 3, 2], &[2, 3, 0]];
        const WEDGE: [&[usize]; 5] = [
            &[0, 1, 2],
            &[3, 5, 4],
            &[0, 3, 4, 1],
            &[1, 4, 5, 2],
            &[2, 5, 3, 0],
        ];
        let table: &[&[usize]] = match self.kind().linear() {
            CellKind::Hex8 => &HEX,
            CellKind::Tet4 => &TET,
            _ => &WEDGE,
        };
        table.get((k as usize).checked_sub(1)?).copied()
    }
}
