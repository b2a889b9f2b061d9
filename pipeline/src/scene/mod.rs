//! The scene file: one TOML document that says what to simulate.
//!
//! Each table maps to one Options struct of the stage that owns it, with `deny_unknown_fields`,
//! so a typo is an error naming the key. Only what the scene names is computed.

pub mod accuracy;
pub mod arrays;
mod brake;
pub mod cea;
pub mod contact;
pub mod interface;
pub mod material;
mod materials;
mod overrides;
pub mod reduction;
pub mod ties;
pub mod transient;
pub mod values;

pub use accuracy::AccuracySpec;
pub use arrays::{ArraysRef, StoredArrays};
pub use cea::{CeaSpec, CeaState, CeaSweepSpec, SweepVary};
pub use contact::{ContactPair, FrictionSpec, Pairing, RotorSpec, Sliding};
pub use interface::InterfaceSpec;
pub use material::MaterialSpec;
pub use materials::{scaled_stiffness, BlockLoss};
pub use overrides::apply_override;
pub use reduction::{ModelSource, ModelSpec, ReductionSpec};
pub use ties::{TieKind, TiePairing, TieSide, TieSpec};
pub use transient::{DampingSpec, Integrator, LoadsSpec, OutputSpec, TransientSpec, VerdictCea};

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_fe::modal::ModalOptions;
use squeal_fe::Hex8Formulation;
use squeal_meshes::geo::{BlockGeometry, CaliperDims, PadPlacement, RotorGeometry};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A whole scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text shown in reports (default: empty).
    #[serde(default)]
    pub title: String,
    /// Unit system, for reports only: squeal uses consistent units (default: "SI").
    #[serde(default = "default_units")]
    pub units: String,
    /// The structural components (rotor, pads, caliper, or a verification specimen).
    #[serde(default)]
    pub components: Vec<ComponentSpec>,
    /// Modal analysis options; its presence asks for `squeal modes` (default: absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<ModalOptions>,
    /// Where the reduced model comes from and how components are joined (default: meshed
    /// components, merge tolerance 1e-6).
    #[serde(default)]
    pub model: ModelSpec,
    /// Craig–Bampton options (default: absent = the defaults of [`ReductionSpec`] when a verb
    /// needs a reduced model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reduction: Option<ReductionSpec>,
    /// Pad/rotor contact surfaces (default: none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contact: Vec<ContactPair>,
    /// Bonded ties between face sets, inside a component or between two (default: none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ties: Vec<TieSpec>,
    /// Friction law and VTOL (default: absent = no friction).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionSpec>,
    /// Rotor speed and axis (default: absent = not turning).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotor: Option<RotorSpec>,
    /// Brake loads, PMAX and TLOAD (default: absent = no load).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loads: Option<LoadsSpec>,
    /// Structural and modal damping (default: absent = undamped).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<DampingSpec>,
    /// Transient controls; its presence asks for `squeal transient` (default: absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transient: Option<TransientSpec>,
    /// Complex eigenvalue analysis; its presence asks for `squeal cea` (default: absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cea: Option<CeaSpec>,
    /// Recorded grids and gaps, squeal verdict (default: see [`OutputSpec`]).
    #[serde(default)]
    pub output: OutputSpec,
    /// Work–precision study ladders, read by `squeal accuracy` (default: absent = the defaults
    /// of [`AccuracySpec`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<AccuracySpec>,
    /// Harmonic-balance options of `squeal limit-cycle` (default: absent = the defaults of
    /// [`squeal_solver::hb::HbOptions`], the velocity scale the largest sliding speed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_cycle: Option<squeal_solver::hb::HbOptions>,
    /// Folder that relative paths in the scene are resolved against (not read from the file).
    #[serde(skip)]
    pub base_dir: PathBuf,
}

fn default_units() -> String {
    "SI".into()
}

/// One structural component.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentSpec {
    /// Name used in outputs and DOF maps (required, unique).
    pub name: String,
    /// Where the mesh comes from.
    pub geometry: GeometrySpec,
    /// Element kind when squeal meshes the geometry: `hex8` or `hex20` (default: hex20).
    #[serde(default)]
    pub element: ElementChoice,
    /// Formulation of hex8 elements (default: incompatible).
    #[serde(default)]
    pub hex8: Hex8Formulation,
    /// Material of the volumes that have no other: isotropic (`young`, `poisson`,
    /// `density`) or anisotropic with material axes (see [`material::MaterialSpec`]); required
    /// unless the geometry file gives every volume its material, as a Nastran or Abaqus file
    /// may (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<MaterialSpec>,
    /// Materials of named volumes (gmsh physical volumes, Nastran `pid_<PID>`, Abaqus section
    /// element sets), overriding the file's and `material` for them, e.g. a pad's
    /// `{ lining = {...}, backplate = {...} }` (default: none).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Fixed (SPC) node sets (default: none, a free-free component).
    #[serde(default)]
    pub fixed: Vec<FixedSpec>,
    /// Rigid rotation of the component's mesh, degrees, about the `[rotor]` axis through its
    /// origin (right hand; default axis z through 0), applied to the nodes as they are read,
    /// before anything pairs or loads them: its node and face sets (fixed, load, friction
    /// faces) turn with it, and no other component is remeshed. Any finite angle (default: 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotate_deg: Real,
    /// Interface reduction of the component's contact boundary (opt-in; default: none, the
    /// exact Craig–Bampton reduction with every gap node as a boundary DOF). Only for the
    /// rotor side of `[[contact]]` pairs: README "Interface reduction of a big rotor".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface: Option<InterfaceSpec>,
    /// Contact boundary of this component in its Craig–Bampton reduction: `gaps` (default)
    /// the nodes its gaps act on; `contact_faces` every node of its contact sets (the
    /// `rotor_faces` or `pad_faces` of the `[[contact]]` pairs naming it), so its reduction
    /// does not depend on where the other side's nodes fall: a rotor with `contact_faces`
    /// keeps one reduction, reused from the model cache, over a sweep of the pads'
    /// `rotate_deg`. More boundary DOFs (those no gap touches stay in the reduced model).
    #[serde(default, skip_serializing_if = "is_default_boundary")]
    pub boundary: ContactBoundary,
}

/// Which nodes of a component's contact sets are Craig–Bampton boundary nodes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactBoundary {
    /// The nodes the gaps act on (matched nodes; a tied face's nodes of non-zero weight).
    #[default]
    Gaps,
    /// Every node of the component's contact face or node sets.
    ContactFaces,
}

fn is_default_boundary(b: &ContactBoundary) -> bool {
    *b == ContactBoundary::Gaps
}

fn is_zero(x: &Real) -> bool {
    *x == 0.0
}

use squeal_solver::Real;

/// Element kind of a meshed geometry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElementChoice {
    Hex8,
    #[default]
    Hex20,
}

impl ElementChoice {
    /// gmsh element order (1 → hex8, 2 → incomplete second order = hex20).
    pub fn gmsh_order(self) -> u8 {
        match self {
            ElementChoice::Hex8 => 1,
            ElementChoice::Hex20 => 2,
        }
    }
}

/// Geometry of a component: a parametric template meshed by gmsh, or the user's own mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum GeometrySpec {
    /// Annular disc (brake rotor or annular plate).
    Rotor(RotorGeometry),
    /// Rectangular block (plates, beams, pads).
    Block(BlockGeometry),
    /// A gmsh `.msh` file (2.2 or 4.1), path relative to the scene file. The element order
    /// is the file's (`element` is not read).
    Msh { path: PathBuf },
    /// Nastran bulk data, path relative to the scene file (README "Nastran and Abaqus
    /// meshes"): its solids, materials (MAT1; MAT9 not yet), SPC sets as fixed DOFs, volumes
    /// and node sets `pid_<PID>`, shell faces as face sets `pid_<PID>`, SET1 as `set1_<SID>`.
    Bdf {
        path: PathBuf,
        /// Solid property ids to read (default: every solid; one file may hold several
        /// components).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        pids: Vec<u64>,
        /// SPC set applied (0: none; default: the case control's `SPC = n`, else the deck's
        /// only set).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spc: Option<u64>,
    },
    /// Abaqus input, path relative to the scene file (README "Nastran and Abaqus meshes"):
    /// its solids placed by their instances, materials (isotropic; anisotropic not yet),
    /// zero *BOUNDARY conditions as fixed DOFs, *NSET/*ELSET node sets, *SURFACE face sets.
    Inp {
        path: PathBuf,
        /// Instances to read (default: every instance).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        instances: Vec<String>,
        /// Read the instances of this part only (default: any).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        part: Option<String>,
        /// Element sets to read within the instances (default: every element).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        elsets: Vec<String>,
    },
    /// A gmsh `.geo` file the user writes, path relative to the scene file, meshed by the
    /// gmsh program in 3D at the component's `element` order (hex20: incomplete second
    /// order). Its physical groups name the volumes (materials), the fixed sets, the load
    /// faces and the friction faces the scene refers to.
    Geo {
        path: PathBuf,
        /// `.geo` parameters (`DefineNumber`) to override, passed as `-setnumber NAME VALUE`
        /// (default: none).
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        set_numbers: BTreeMap<String, Real>,
    },
    /// Brake pad on a friction face of the rotor component `rotor` (default: "rotor"), placed
    /// in rotor elements so its friction-face nodes are the rotor's ([`PadPlacement`]).
    Pad {
        #[serde(default = "brake::default_rotor_name")]
        rotor: String,
        #[serde(flatten)]
        placement: PadPlacement,
    },
    /// Caliper over the pad components `inboard` (piston side, default: "inboard_pad") and
    /// `outboard` (fingers, default: "outboard_pad"), sharing their back nodes ([`CaliperDims`]).
    Caliper {
        #[serde(default = "brake::default_inboard_name")]
        inboard: String,
        #[serde(default = "brake::default_outboard_name")]
        outboard: String,
        #[serde(flatten)]
        dims: CaliperDims,
    },
}

impl GeometrySpec {
    /// True for the file kinds that may give their volumes a material (Nastran, Abaqus).
    pub fn file_has_materials(&self) -> bool {
        matches!(self, GeometrySpec::Bdf { .. } | GeometrySpec::Inp { .. })
    }

    /// True for the user's mesh or geometry files (their sets are checked against the scene).
    pub fn is_user_file(&self) -> bool {
        matches!(
            self,
            GeometrySpec::Msh { .. }
                | GeometrySpec::Geo { .. }
                | GeometrySpec::Bdf { .. }
                | GeometrySpec::Inp { .. }
        )
    }
}

/// A fixed node set: the named set's nodes have the given components held at zero.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedSpec {
    /// Node-set (physical group) name.
    pub set: String,
    /// Fixed components as letters from "xyz" (default: "xyz").
    #[serde(default = "default_dofs")]
    pub dofs: String,
}

fn default_dofs() -> String {
    "xyz".into()
}

impl FixedSpec {
    /// Component indices 0..3 of `dofs`.
    pub fn components(&self) -> Result<Vec<usize>, PipelineError> {
        let mut out = Vec::new();
        for ch in self.dofs.chars() {
            let c = match ch {
                'x' | 'X' | '1' => 0,
                'y' | 'Y' | '2' => 1,
                'z' | 'Z' | '3' => 2,
                _ => {
                    return Err(PipelineError::Scene {
                        field: format!("fixed[set = {}].dofs", self.set),
                        message: format!("`{}` has `{ch}`; use letters from \"xyz\"", self.dofs),
                    })
                }
            };
            if !out.contains(&c) {
                out.push(c);
            }
        }
        Ok(out)
    }
}

impl Scene {
    /// Reads a scene, applies `--set` overrides, types and validates it; relative paths in it
    /// are resolved against the file's folder.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, PipelineError> {
        let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let base = path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        Self::parse(&text, path, base, overrides)
    }

    /// A scene from TOML text (with `--set` overrides); relative paths in it are resolved
    /// against `base_dir`. Errors name the source as `<string>`.
    pub fn from_toml_str(
        text: &str,
        base_dir: impl Into<PathBuf>,
        overrides: &[String],
    ) -> Result<Scene, PipelineError> {
        Self::parse(text, Path::new("<string>"), base_dir.into(), overrides)
    }

    fn parse(
        text: &str,
        source: &Path,
        base_dir: PathBuf,
        overrides: &[String],
    ) -> Result<Scene, PipelineError> {
        let mut doc: toml::Value = toml::from_str(text).map_err(|e| PipelineError::SceneParse {
            path: source.to_path_buf(),
            message: e.to_string(),
        })?;
        for assignment in overrides {
            apply_override(&mut doc, assignment)?;
        }
        Self::from_value(doc, source, base_dir, None)
    }

    /// Types and validates a scene document.
    fn from_value(
        doc: toml::Value,
        source: &Path,
        base_dir: PathBuf,
        arrays: Option<ArraysRef>,
    ) -> Result<Scene, PipelineError> {
        let mut scene: Scene =
            doc.try_into()
                .map_err(|e: toml::de::Error| PipelineError::SceneParse {
                    path: source.to_path_buf(),
                    message: e.to_string(),
                })?;
        scene.base_dir = base_dir;
        scene.model.arrays = arrays;
        scene.validate()?;
        Ok(scene)
    }

    /// Sets one value as `--set key=value` does (`key` dotted, `value` a TOML value text:
    /// `0.5`, `"hex8"`, `[1, 2]`), then types and validates the whole scene again. On error
    /// the scene is unchanged and the error names the key.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), PipelineError> {
        self.set_all(&[format!("{key}={value}")])
    }

    /// [`Scene::set`] for several `key=value` assignments at once (validated together).
    pub fn set_all(&mut self, assignments: &[String]) -> Result<(), PipelineError> {
        let mut doc = toml::Value::try_from(&*self).map_err(|e| PipelineError::Scene {
            field: "<scene>".into(),
            message: format!("cannot be written as TOML: {e}"),
        })?;
        for a in assignments {
            apply_override(&mut doc, a)?;
        }
        let mut source = PathBuf::from("<scene set ");
        source.as_mut_os_string().push(assignments.join(", "));
        source.as_mut_os_string().push(">");
        *self = Self::from_value(
            doc,
            &source,
            self.base_dir.clone(),
            self.model.arrays.clone(),
        )?;
        Ok(())
    }

    /// Checks every table; errors name the field and the value.
    pub fn validate(&self) -> Result<(), PipelineError> {
        let mut names = std::collections::BTreeSet::new();
        for (i, c) in self.components.iter().enumerate() {
            if c.name.trim().is_empty() {
                return Err(PipelineError::Scene {
                    field: format!("components[{i}].name"),
                    message: "empty name".into(),
                });
            }
            if !names.insert(c.name.clone()) {
                return Err(PipelineError::Scene {
                    field: format!("components[{i}].name"),
                    message: format!("`{}` is used twice", c.name),
                });
            }
            if let Some(m) = &c.material {
                m.validate(&format!("components[{i}].material"))?;
            } else if !c.geometry.file_has_materials() {
                return Err(PipelineError::Scene {
                    field: format!("components[{i}].material"),
                    message: format!(
                        "component `{}` needs a `material` (only Nastran and Abaqus files \
                         bring their own)",
                        c.name
                    ),
                });
            }
            match &c.geometry {
                GeometrySpec::Rotor(g) => g.validate(),
                GeometrySpec::Block(g) => g.validate(),
                GeometrySpec::Msh { .. } | GeometrySpec::Bdf { .. } | GeometrySpec::Inp { .. } => {
                    Ok(())
                }
                GeometrySpec::Geo { set_numbers, .. } => squeal_meshes::GmshOptions {
                    set_numbers: set_numbers.clone(),
                    ..Default::default()
                }
                .validate(),
                GeometrySpec::Pad { .. } | GeometrySpec::Caliper { .. } => Ok(()),
            }
            .map_err(|e| PipelineError::Scene {
                field: format!("components[{i}].geometry"),
                message: e.to_string(),
            })?;
            if !c.rotate_deg.is_finite() {
                return Err(PipelineError::Scene {
                    field: format!("components[{i}].rotate_deg"),
                    message: format!("{} must be finite", c.rotate_deg),
                });
            }
            if let Some(f) = &c.interface {
                f.validate(i)?;
                if let Some(j) = self.contact.iter().position(|p| p.pad == c.name) {
                    return Err(PipelineError::Scene {
                        field: format!("components[{i}].interface"),
                        message: format!(
                            "`{}` is the pad of contact[{j}]; interface reduction applies to \
                             the rotor side of contact pairs only",
                            c.name
                        ),
                    });
                }
                if !self.contact.iter().any(|p| p.rotor == c.name) {
                    return Err(PipelineError::Scene {
                        field: format!("components[{i}].interface"),
                        message: format!(
                            "`{}` is the rotor of no [[contact]] pair: it has no contact \
                             boundary to reduce",
                            c.name
                        ),
                    });
                }
            }
            self.validate_brake_component(i, c)?;
            for f in &c.fixed {
                f.components()?;
            }
        }
        if let Some(m) = &self.modes {
            m.validate().map_err(|e| PipelineError::Scene {
                field: "modes".into(),
                message: e.to_string(),
            })?;
        }
        self.model.validate()?;
        if let Some(r) = &self.reduction {
            r.validate()?;
        }
        for (i, c) in self.contact.iter().enumerate() {
            c.validate(i)?;
            if self.model.from == ModelSource::Mesh {
                for name in [&c.pad, &c.rotor] {
                    if !names.contains(name) {
                        return Err(PipelineError::Scene {
                            field: format!("contact[{i}]"),
                            message: format!(
                                "no component named `{name}` (the scene has: {})",
                                self.component_names()
                            ),
                        });
                    }
                }
            }
        }
        for (i, t) in self.ties.iter().enumerate() {
            t.validate(i)?;
            if self.model.from != ModelSource::Mesh {
                return Err(PipelineError::Scene {
                    field: format!("ties[{i}]"),
                    message: "ties join meshed components; a stored model has its ties in its \
                              matrices"
                        .into(),
                });
            }
            for (side, s) in [("a", &t.a), ("b", &t.b)] {
                if !names.contains(&s.component) {
                    return Err(PipelineError::Scene {
                        field: format!("ties[{i}].{side}.component"),
                        message: format!(
                            "no component named `{}` (the scene has: {})",
                            s.component,
                            self.component_names()
                        ),
                    });
                }
            }
        }
        if let Some(f) = &self.friction {
            f.validate()?;
        }
        if let Some(r) = &self.rotor {
            r.validate()?;
        }
        if let Some(l) = &self.loads {
            l.validate()?;
            if self.model.from != ModelSource::Mesh
                && !(l.pressure.is_empty() && l.force.is_empty())
            {
                return Err(PipelineError::Scene {
                    field: "loads".into(),
                    message: "pressure and force load sets need a meshed model; a stored model \
                              carries its brake load as the matrix PBRAKE"
                        .into(),
                });
            }
        }
        if let Some(d) = &self.damping {
            d.validate()?;
        }
        if let Some(t) = &self.transient {
            t.validate()?;
        }
        if let Some(c) = &self.cea {
            c.validate()?;
        }
        self.output.validate()?;
        if let Some(a) = &self.accuracy {
            a.validate()?;
        }
        if let Some(l) = &self.limit_cycle {
            l.validate().map_err(|e| PipelineError::Scene {
                field: "limit_cycle".into(),
                message: e.to_string(),
            })?;
        }
        Ok(())
    }

    /// The scene as TOML, with every default filled in.
    pub fn resolved_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# could not print: {e}\n"))
    }

    /// The component named `name`, or the only one when `name` is None.
    pub fn component(&self, name: Option<&str>) -> Result<&ComponentSpec, PipelineError> {
        match name {
            Some(n) => {
                self.components
                    .iter()
                    .find(|c| c.name == n)
                    .ok_or_else(|| PipelineError::Scene {
                        field: "components".into(),
                        message: format!(
                            "no component named `{n}` (the scene has: {})",
                            self.component_names()
                        ),
                    })
            }
            None => match self.components.as_slice() {
                [one] => Ok(one),
                [] => Err(PipelineError::Scene {
                    field: "components".into(),
                    message: "the scene has no component".into(),
                }),
                _ => Err(PipelineError::Scene {
                    field: "components".into(),
                    message: format!(
                        "the scene has several components ({}); name one with --component",
                        self.component_names()
                    ),
                }),
            },
        }
    }

    fn component_names(&self) -> String {
        self.components
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The band the reduced model was made for, Hz: `reduction.frequency_of_interest_hz`
    /// (default 10 kHz) for meshed models, `model.band_hz` for stored matrices (None: unknown).
    pub fn band_hz(&self) -> Option<f64> {
        match self.model.from {
            ModelSource::Mesh => self
                .reduction
                .clone()
                .unwrap_or_default()
                .frequency_of_interest_hz
                .or(ReductionSpec::default().frequency_of_interest_hz),
            _ => self.model.band_hz,
        }
    }

    /// A scene over a stored model given in memory: `text` is the scene TOML (`model.from` is
    /// set to `arrays`; `model.matrices`, `dofmap`, `gaps` must not be given), `arrays` the
    /// matrices, DOF map and gaps. Nothing is read from files for the model; the arrays are
    /// checked when the model is built.
    pub fn with_arrays(
        text: &str,
        base_dir: impl Into<PathBuf>,
        overrides: &[String],
        arrays: StoredArrays,
    ) -> Result<Scene, PipelineError> {
        let mut doc: toml::Value = toml::from_str(text).map_err(|e| PipelineError::SceneParse {
            path: PathBuf::from("<string>"),
            message: e.to_string(),
        })?;
        for assignment in overrides {
            apply_override(&mut doc, assignment)?;
        }
        apply_override(&mut doc, "model.from=\"arrays\"")?;
        Self::from_value(
            doc,
            Path::new("<string>"),
            base_dir.into(),
            Some(ArraysRef(std::sync::Arc::new(arrays))),
        )
    }

    /// Resolves a path written in the scene against the scene's folder.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base_dir.join(p)
        }
    }
}
