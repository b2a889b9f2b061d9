//! The crate's one error type. Messages carry the file, line and offending value.

use std::path::PathBuf;

/// Everything that can go wrong in squeal-meshes.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A malformed `.msh` file: bad number, missing field, truncated section, bad structure.
    #[error("{file}:{line}: {message}")]
    Parse {
        file: String,
        line: usize,
        message: String,
    },
    /// The `$MeshFormat` names a version or file type this reader does not handle.
    #[error("{file}:{line}: unsupported msh format `{version}` ({reason}); squeal reads 2.2 ASCII and 4.1 ASCII/binary (gmsh `-format msh41` or `msh22`)")]
    UnsupportedVersion {
        file: String,
        line: usize,
        version: String,
        reason: String,
    },
    /// An element type squeal has no element for (higher orders, polyhedra, ...).
    #[error("{file}:{line}: element {element_tag} has gmsh type {gmsh_type} ({type_name}), which squeal does not support (volumes: hex8 = 5, hex20 = 17, hex27 = 12 read as hex20, tet4 = 4, tet10 = 11, prism6 = 6, prism15 = 18, prism18 = 13 read as prism15, pyramid5 = 7, pyramid13 = 19, pyramid14 = 14 read as pyramid13; faces: quad4 = 3, quad8 = 16, quad9 = 10 read as quad8, tri3 = 2, tri6 = 9; for serendipity cells mesh with `-order 2` and Mesh.SecondOrderIncomplete=1)")]
    UnsupportedElement {
        file: String,
        line: usize,
        element_tag: u64,
        gmsh_type: i64,
        type_name: String,
    },
    /// An element refers to a node tag that `$Nodes` does not define.
    #[error("{file}:{line}: element {element_tag} uses node {node_tag}, which is not in $Nodes")]
    UnknownNode {
        file: String,
        line: usize,
        element_tag: u64,
        node_tag: u64,
    },
    /// A face cell of a physical surface uses a node that no volume cell uses.
    #[error("{file}:{line}: face element {element_tag} of physical surface `{surface}` uses node {node_tag}, which no volume cell uses")]
    FaceNodeNotInVolume {
        file: String,
        line: usize,
        element_tag: u64,
        surface: String,
        node_tag: u64,
    },
    /// A physical surface mixes linear and quadratic faces (quad4 and quad8, tri3 and tri6…).
    #[error("{file}:{line}: physical surface `{surface}` mixes {first:?} and {second:?} faces (element {element_tag}): linear and quadratic faces cannot share a surface")]
    MixedFaceKinds {
        file: String,
        line: usize,
        surface: String,
        first: crate::CellKind,
        second: crate::CellKind,
        element_tag: u64,
    },
    /// A cell with (near) zero or non-finite volume at its centroid.
    #[error("{file}:{line}: {cell} {element_tag} is degenerate (Jacobian determinant {det:e} at its centroid)")]
    DegenerateCell {
        file: String,
        line: usize,
        element_tag: u64,
        det: f64,
        /// The cell's family ("hexahedron", "tetrahedron", "wedge", "pyramid").
        cell: &'static str,
    },
    /// A hexahedron with repeated nodes that is no recognisable wedge, pyramid or tetrahedron.
    #[error("{file}:{line}: {cell} {element_tag} repeats nodes but is no collapsed wedge, pyramid or tetrahedron: {reason}")]
    CollapsedCell {
        file: String,
        line: usize,
        element_tag: u64,
        cell: &'static str,
        reason: String,
    },
    /// A cell positive at its centroid but inverted (det J ≤ 0) at one of its nodes.
    #[error("{file}:{line}: {cell} {element_tag} is inverted at its {kind} node {node_tag} (Jacobian determinant {det:.4e} there, {centroid_det:.4e} at its centroid): move the node back inside the cell")]
    InvertedAtNode {
        file: String,
        line: usize,
        element_tag: u64,
        /// "corner" or "mid-edge".
        kind: &'static str,
        node_tag: u64,
        det: f64,
        centroid_det: f64,
        /// The cell's family ("hexahedron", "tetrahedron", "wedge", "pyramid").
        cell: &'static str,
    },
    /// The file has no volume cells.
    #[error(
        "{file}: no volume cells (is a physical volume defined, and was the mesh made with -3?)"
    )]
    NoVolumeCells { file: String },
    /// A named node or face set that the mesh does not have.
    #[error("no {what} named `{name}` (the mesh has: {available})")]
    UnknownSet {
        what: &'static str,
        name: String,
        available: String,
    },
    /// A geometry parameter out of range.
    #[error("geometry parameter `{field}` = {value}: {reason}")]
    InvalidGeometry {
        field: &'static str,
        value: String,
        reason: String,
    },
    /// No gmsh program was found.
    #[error("gmsh not found ({searched}). Set SQUEAL_GMSH to the gmsh program, put gmsh on PATH, or create the project's .venv with `bash scripts/setup.sh` (the README's setup; `bash scripts/test.sh` also runs it)")]
    GmshNotFound { searched: String },
    /// gmsh could not be started, failed, or wrote no mesh.
    #[error("`{command}` failed ({status}): {message}")]
    GmshFailed {
        command: String,
        status: String,
        message: String,
    },
    /// The caller's interrupt (`GmshOptions::interrupt`) asked to stop: gmsh was killed.
    #[error("interrupted by the caller: `{command}` was stopped")]
    Interrupted { command: String },
    /// An invalid gmsh option.
    #[error("gmsh option `{field}` = {value}: {reason}")]
    InvalidGmshOption {
        field: &'static str,
        value: String,
        reason: String,
    },
    /// A mesh file whose content is wrong as a whole (no line to name), e.g. a choice the file
    /// leaves open.
    #[error("{file}: {message}")]
    Input { file: String, message: String },
    /// A data array given to the VTU writer does not fit the mesh.
    #[error("VTU array `{name}`: {message}")]
    VtuArray { name: String, message: String },
}

impl MeshError {
    pub(crate) fn parse(file: &str, line: usize, message: impl Into<String>) -> MeshError {
        MeshError::Parse {
            file: file.to_string(),
            line,
            message: message.into(),
        }
    }
}
