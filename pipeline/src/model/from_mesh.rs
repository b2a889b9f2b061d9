//! The reduced model from the scene's meshes.
//!
//! Loads are projected with the Craig–Bampton transformation, f_r = Tᵀ f =
//! [f_b + Ψᵀ f_i; Φᵀ f_i], so loaded faces need not be boundary nodes.

use super::areas::pad_areas;
use super::cache::component::{
    ComponentCache, ComponentCacheUse, ComponentInputs, StoredReduction,
};
use super::degree::Ladders;
use super::grids::{merge, Grids};
use super::ties::Mpc;
use super::{symmetrise, ComponentRecovery, ComponentReport, ReducedModel};
use crate::error::PipelineError;
use crate::model::mesh::fixed_dofs;
use crate::model::mesh::mesh_component;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::ContactBoundary;
use crate::scene::{ModelSource, Pairing, Scene};
use crate::warning::Warning;
use faer::Mat;
use rayon::prelude::*;
use squeal_contact::{
    match_gaps, mortar_gaps, tie_gaps, ContactNode, FaceKind, FrictionLaw, GapSet, MatchOptions,
    MortarOptions, RotorFace,
};
use squeal_fe::{assemble, pressure_load, AssemblyOptions, DofMap};
use squeal_meshes::{CellKind, FaceSet, Mesh};
use squeal_reduction::cb::{self, CbCheck, CheckOptions};
use squeal_reduction::superelement::{self, Component, DofKey, DofKind};
use squeal_reduction::CbModel;
use std::collections::{BTreeSet, HashMap};

use squeal_solver::Real;

/// One reduced component before assembly.
struct Reduced {
    /// The reduction, with Ψ and Φ (None: read from the component cache).
    cb: Option<CbModel>,
    /// The cached reduction (None: reduced here).
    stored: Option<StoredReduction>,
    dofs: DofMap,
    keys: Vec<DofKey>,
    /// Keys of the interface-reduced DOFs (rows of `cb.interface`; empty without).
    interface_keys: Vec<DofKey>,
    load: Vec<Real>,
    check: Option<CbCheck>,
    n_nodes: usize,
    cache: Option<ComponentCacheUse>,
    /// The ties inside the component (its free DOFs = T × the reduction's).
    mpc: Option<Mpc>,
    /// The bodies' material damping Tᵀ B_η T, B_η = Σ_b (η_b/W4) K_b over the bodies with a
    /// loss factor (None: none, or W4 = 0); also the reduction's `b`.
    b_eta: Option<Mat<Real>>,
    /// The bodies whose loss factor W4 = 0 turns off.
    loss_off: Vec<crate::scene::BlockLoss>,
}

impl Reduced {
    fn k(&self) -> &Mat<Real> {
        self.cb
            .as_ref()
            .map_or_else(|| &self.stored_ref().k, |c| &c.k)
    }
    fn m(&self) -> &Mat<Real> {
        self.cb
            .as_ref()
            .map_or_else(|| &self.stored_ref().m, |c| &c.m)
    }
    fn stored_ref(&self) -> &StoredReduction {
        // Invariant: exactly one of `cb` and `stored` is set (reduce_component).
        self.stored.as_ref().expect("a reduction or a stored one")
    }
    fn n_modes(&self) -> usize {
        self.cb
            .as_ref()
            .map_or_else(|| self.stored_ref().n_modes, |c| c.n_modes)
    }
    fn n_boundary(&self) -> usize {
        self.keys.len()
    }
    fn n_dofs(&self) -> usize {
        self.cb
            .as_ref()
            .map_or_else(|| self.stored_ref().n_dofs, |c| c.n_dofs)
    }
    fn fixed_hz(&self) -> &[Real] {
        self.cb.as_ref().map_or_else(
            || self.stored_ref().fixed_frequencies_hz.as_slice(),
            |c| c.fixed_frequencies_hz.as_slice(),
        )
    }
}

fn fe_err(component: &str) -> impl Fn(squeal_fe::FeError) -> PipelineError + '_ {
    move |source| PipelineError::fe(component, source)
}

/// True for the quadratic face kinds (their consistent corner areas are ≤ 0).
fn quadratic_faces(kind: CellKind) -> bool {
    face_kind(kind).is_some_and(FaceKind::is_quadratic)
}

/// The contact crate's kind of a face cell kind (None: not a face).
fn face_kind(kind: CellKind) -> Option<FaceKind> {
    match kind {
        CellKind::Quad4 => Some(FaceKind::Quad4),
        CellKind::Quad8 => Some(FaceKind::Quad8),
        CellKind::Tri3 => Some(FaceKind::Tri3),
        CellKind::Tri6 => Some(FaceKind::Tri6),
        _ => None,
    }
}

/// The faces of a face set (any mix of quad4, quad8, tri3, tri6) as the contact crate takes
/// them (node ids = grids, face id = index in the set).
pub(super) fn rotor_faces(
    set: &FaceSet,
    mesh: &Mesh,
    grid_of: &[u64],
) -> Result<Vec<RotorFace>, String> {
    let mut out = Vec::with_capacity(set.len());
    for face in set.iter() {
        let kind = face_kind(face.kind).ok_or_else(|| {
            format!(
                "has {:?} faces; surface pairing takes quad4, quad8, tri3 or tri6 faces",
                face.kind
            )
        })?;
        out.push(RotorFace {
            id: out.len() as u64,
            kind,
            nodes: face.nodes.iter().map(|&n| grid_of[n]).collect(),
            coords: face.nodes.iter().map(|&n| mesh.nodes[n]).collect(),
        });
    }
    Ok(out)
}

/// The gap geometry of every `[[contact]]` pair (coincident nodes or surface pairing; no
/// operating value, [`crate::problem::OperatingPoint`]), DOFs unassigned,
/// the number of gaps of each pair, and the warnings (pad nodes excluded).
fn match_pairs(
    scene: &Scene,
    meshes: &[Mesh],
    grids: &Grids,
) -> Result<(GapSet, Vec<usize>, Vec<Warning>), PipelineError> {
    let mut warnings = Vec::new();
    let pos = |name: &str| scene.components.iter().position(|c| c.name == name);
    let rotor = scene.rotor.clone().unwrap_or_default();
    let mut all: Option<GapSet> = None;
    let mut counts = Vec::with_capacity(scene.contact.len());
    for (i, pair) in scene.contact.iter().enumerate() {
        let (cp, cr) = match (pos(&pair.pad), pos(&pair.rotor)) {
            (Some(a), Some(b)) => (a, b),
            _ => {
                return Err(PipelineError::Scene {
                    field: format!("contact[{i}]"),
                    message: format!("unknown component `{}` or `{}`", pair.pad, pair.rotor),
                })
            }
        };
        let pad_nodes: Vec<ContactNode> = pad_areas(&meshes[cp], &pair.pad_faces)
            .map_err(fe_err(&pair.pad))?
            .into_iter()
            .map(|(n, s)| ContactNode {
                id: grids.grid_of[cp][n],
                coords: meshes[cp].nodes[n],
                area: s,
            })
            .collect();
        let rmesh = &meshes[cr];
        let what = || {
            format!(
                "contact[{i}]: pad `{}` faces `{}` against rotor `{}` faces `{}`",
                pair.pad, pair.pad_faces, pair.rotor, pair.rotor_faces
            )
        };
        let no_set = || PipelineError::Scene {
            field: format!("contact[{i}].rotor_faces"),
            message: format!(
                "component `{}` has no face set `{}` (it has: {})",
                pair.rotor,
                pair.rotor_faces,
                rmesh.faces.keys().cloned().collect::<Vec<_>>().join(", ")
            ),
        };
        let opts = MatchOptions {
            tolerance: pair.tolerance,
            rotor_axis_origin: rotor.origin,
            rotor_axis: rotor.axis,
            // The gap geometry only: the operating point gives speeds, P0 and temperatures.
            rpm: 0.0,
            p0: 0.0,
            temperature: 0.0,
        };
        // No pairing named: mortar on quadratic pad faces, nodes otherwise (docs/pairing.md).
        let pad_block = meshes[cp].faces.get(&pair.pad_faces);
        let quadratic = pad_block.is_some_and(|set| set.kinds().any(quadratic_faces));
        let pairing = pair.pairing.unwrap_or(Pairing::default_for(quadratic));
        if pair.pairing.is_none() && pairing == Pairing::Nodes {
            let tie = pair.tie_options();
            let def = squeal_contact::TieOptions::default();
            let set = [
                ("unmatched", tie.unmatched != def.unmatched),
                ("extension", tie.extension != def.extension),
                ("max_distance", tie.max_distance.is_some()),
            ];
            if let Some((key, _)) = set.iter().find(|(_, on)| *on) {
                return Err(PipelineError::Scene {
                    field: format!("contact[{i}].{key}"),
                    message: format!(
                        "is read only with pairing = \"surface\" or \"mortar\"; the pad faces \
                         `{}` of `{}` are linear, so this pair matches coincident nodes unless \
                         `pairing` says otherwise",
                        pair.pad_faces, pair.pad
                    ),
                });
            }
        }
        if quadratic && pairing != Pairing::Mortar {
            warnings.push(Warning {
                input: format!("contact[{i}].pairing"),
                message: format!(
                    "the pad faces `{}` of `{}` are quadratic: with pairing = \"{}\" each pad \
                     node's gap carries its consistent nodal force, zero or tensile at the \
                     faces' corners under a uniform pressure; the default pairing (\"mortar\", \
                     docs/pairing.md) gives every gap a positive area",
                    pair.pad_faces,
                    pair.pad,
                    if pairing == Pairing::Nodes {
                        "nodes"
                    } else {
                        "surface"
                    }
                ),
                value: 0.0,
                tolerance: 0.0,
            });
        }
        let set = match pairing {
            Pairing::Nodes => {
                let rset = rmesh.node_sets.get(&pair.rotor_faces).ok_or_else(no_set)?;
                let rotor_nodes: Vec<ContactNode> = rset
                    .iter()
                    .map(|&n| ContactNode {
                        id: grids.grid_of[cr][n],
                        coords: rmesh.nodes[n],
                        area: [0.0; 3],
                    })
                    .collect();
                match_gaps(&pad_nodes, &rotor_nodes, &opts).map_err(|source| {
                    PipelineError::Contact {
                        what: what(),
                        source,
                    }
                })?
            }
            Pairing::Surface | Pairing::Mortar => {
                let block = rmesh.faces.get(&pair.rotor_faces).ok_or_else(no_set)?;
                let faces = rotor_faces(block, rmesh, &grids.grid_of[cr]).map_err(|m| {
                    PipelineError::Scene {
                        field: format!("contact[{i}].rotor_faces"),
                        message: format!(
                            "face set `{}` of `{}`: {m}",
                            pair.rotor_faces, pair.rotor
                        ),
                    }
                })?;
                let contact_err = |source| PipelineError::Contact {
                    what: what(),
                    source,
                };
                let out = if pairing == Pairing::Mortar {
                    let pmesh = &meshes[cp];
                    let block =
                        pmesh
                            .faces
                            .get(&pair.pad_faces)
                            .ok_or_else(|| PipelineError::Scene {
                                field: format!("contact[{i}].pad_faces"),
                                message: format!(
                                "mortar pairing integrates over the pad's faces: component `{}` \
                                 has no face set `{}`",
                                pair.pad, pair.pad_faces
                            ),
                            })?;
                    let pad_faces = rotor_faces(block, pmesh, &grids.grid_of[cp]).map_err(|m| {
                        PipelineError::Scene {
                            field: format!("contact[{i}].pad_faces"),
                            message: format!(
                                "face set `{}` of `{}`: {m}",
                                pair.pad_faces, pair.pad
                            ),
                        }
                    })?;
                    mortar_gaps(
                        &pad_nodes,
                        &pad_faces,
                        &faces,
                        &opts,
                        &pair.tie_options(),
                        &MortarOptions::default(),
                    )
                    .map_err(contact_err)?
                    .0
                } else {
                    tie_gaps(&pad_nodes, &faces, &opts, &pair.tie_options()).map_err(contact_err)?
                };
                if out.gaps.is_empty() {
                    // Every pad node excluded: the pad would float free of the rotor, and the
                    // first factorisation would fail with a bare "singular" pivot.
                    let first: Vec<String> = out
                        .unmatched
                        .iter()
                        .take(3)
                        .map(|r| r.to_string())
                        .collect();
                    return Err(PipelineError::Scene {
                        field: format!("contact[{i}].unmatched"),
                        message: format!(
                            "\"exclude\" left this pair without a gap: all {} pad node(s) of \
                             `{}` faces `{}` project on no face of `{}` faces `{}` within the \
                             extension {} and max_distance {} ({}{}); check the faces, or \
                             raise `contact[{i}].max_distance`",
                            out.unmatched.len(),
                            pair.pad,
                            pair.pad_faces,
                            pair.rotor,
                            pair.rotor_faces,
                            pair.extension,
                            pair.max_distance
                                .map_or("default".to_string(), |d| d.to_string()),
                            first.join("; "),
                            if out.unmatched.len() > 3 { "; …" } else { "" }
                        ),
                    });
                }
                if !out.unmatched.is_empty() {
                    let list: Vec<String> = out.unmatched.iter().map(|r| r.to_string()).collect();
                    warnings.push(Warning {
                        input: format!("contact[{i}].unmatched"),
                        message: format!(
                            "{} pad node(s) of `{}` project on no face of `{}` and were \
                             excluded (no gap): {}",
                            out.unmatched.len(),
                            pair.pad,
                            pair.rotor,
                            list.join("; ")
                        ),
                        value: out.unmatched.len() as Real,
                        tolerance: 0.0,
                    });
                }
                out.gaps
            }
        };
        counts.push(set.len());
        match &mut all {
            None => all = Some(set),
            Some(a) => a.append(set),
        }
    }
    let set = all.unwrap_or(GapSet {
        gaps: Vec::new(),
        law: FrictionLaw::default(),
        vtol: GapSet::DEFAULT_VTOL,
    });
    Ok((set, counts, warnings))
}

/// Mesh, assemble and reduce every component, assemble the superelements, match the gaps.
pub fn build_from_mesh(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<ReducedModel, PipelineError> {
    build_from_mesh_cached(scene, dir, progress, None)
}

/// [`build_from_mesh`], reading and storing each component's reduction in `cache` when given
/// (then the model has no per-component recovery data when any component came from it).
pub fn build_from_mesh_cached(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    cache: Option<&ComponentCache>,
) -> Result<ReducedModel, PipelineError> {
    let ladders = Ladders::new(scene);
    if ladders.any_adaptive() {
        return super::degree::build_adaptive(scene, dir, progress, cache, ladders);
    }
    build_once(scene, dir, progress, cache, &ladders)
}

/// [`build_from_mesh_cached`] with each interface-reduced component at the degree `ladders`
/// says (reduced on its ladder when its degree is chosen by a tolerance).
pub(super) fn build_once(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    cache: Option<&ComponentCache>,
    ladders: &Ladders,
) -> Result<ReducedModel, PipelineError> {
    if scene.components.is_empty() {
        return Err(PipelineError::Scene {
            field: "components".into(),
            message: "a meshed model needs at least one component".into(),
        });
    }
    let meshed: Vec<_> = scene
        .components
        .par_iter()
        .map(|c| mesh_component(scene, c, dir, progress))
        .collect::<Result<_, _>>()?;
    // Cards a Nastran or Abaqus reader left out are warnings of the model.
    let reader_warnings: Vec<_> = meshed.iter().flat_map(|(_, r)| r.warnings()).collect();
    let (meshes, mesh_files): (Vec<Mesh>, Vec<String>) =
        meshed.into_iter().map(|(m, r)| (m, r.msh_path)).unzip();
    let grids = merge(scene, &meshes, scene.model.merge_tolerance);
    let (mut gaps, gap_pairs, mut warnings) = match_pairs(scene, &meshes, &grids)?;
    warnings.splice(0..0, reader_warnings);

    // Fixed grid DOFs of any component hold for every component sharing the grid.
    let mut global_fixed: BTreeSet<(u64, usize)> = BTreeSet::new();
    for (c, spec) in scene.components.iter().enumerate() {
        let fixed = fixed_dofs(spec, &meshes[c])?;
        crate::model::mesh::check_not_all_fixed(scene, spec, &meshes[c], &fixed, &mesh_files[c])?;
        for (node, k) in fixed {
            global_fixed.insert((grids.grid_of[c][node], k));
        }
    }
    // Contact boundary: the matched pad and rotor nodes only (not a whole rotor face); for a
    // tied gap the face nodes of non-zero weight.
    let mut gap_grids: std::collections::HashSet<u64> = gaps
        .gaps
        .iter()
        .flat_map(|g| g.pad_nodes().into_iter().chain(g.rotor_nodes()))
        .collect();
    // The contact pair of each rotor gap grid (the patch of an interface basis).
    let mut patch_of: HashMap<u64, usize> = HashMap::new();
    let mut first = 0;
    for (pair, &count) in gap_pairs.iter().enumerate() {
        for g in &gaps.gaps[first..first + count] {
            for node in g.rotor_nodes() {
                patch_of.entry(node).or_insert(pair);
            }
        }
        first += count;
    }
    // `boundary = "contact_faces"`: every node of the component's contact sets.
    for (c, spec) in scene.components.iter().enumerate() {
        if spec.boundary != ContactBoundary::ContactFaces {
            continue;
        }
        for (pi, pair) in scene.contact.iter().enumerate() {
            for (side, set) in [
                (&pair.pad, &pair.pad_faces),
                (&pair.rotor, &pair.rotor_faces),
            ] {
                if *side != spec.name {
                    continue;
                }
                let mesh = &meshes[c];
                let nodes: Vec<usize> = match (mesh.faces.get(set), mesh.node_sets.get(set)) {
                    (Some(block), _) => block.node_indices().collect(),
                    (None, Some(ns)) => ns.clone(),
                    (None, None) => {
                        return Err(PipelineError::Scene {
                            field: format!("components.{c}.boundary"),
                            message: format!(
                                "`contact_faces`: component `{}` has no face or node set `{set}`",
                                spec.name
                            ),
                        })
                    }
                };
                // An interface-reduced rotor's contact faces are its pair's patch, whether a
                // gap touches them or not (the pad may cover part of it).
                if set == &pair.rotor_faces && spec.interface.is_some() {
                    for &n in &nodes {
                        patch_of.entry(grids.grid_of[c][n]).or_insert(pi);
                    }
                }
                gap_grids.extend(nodes.into_iter().map(|n| grids.grid_of[c][n]));
            }
        }
    }
    // Bonded ties: rows inside a component whose slave is a boundary grid (a gap grid, a
    // grid shared with another component) and the ties between components are eliminated
    // after the assembly, their grids boundary DOFs; the other inside rows are each
    // component's MPC before its reduction (model/ties.rs).
    let tie_rows = super::ties::pair_ties(scene, &meshes, &grids)?;
    let shared: std::collections::HashSet<u64> = grids
        .shared
        .iter()
        .zip(&grids.grid_of)
        .flat_map(|(sh, gid)| sh.iter().zip(gid).filter(|(s, _)| **s).map(|(_, g)| *g))
        .collect();
    let mut assembled_rows: Vec<(u64, Vec<(u64, Real)>)> = Vec::new();
    let mut inside_rows: Vec<super::ties::TieRows> = Vec::new();
    for t in &tie_rows {
        if t.slave != t.master {
            gap_grids.extend(t.grids());
            assembled_rows.extend(t.rows.iter().cloned());
        }
    }
    for t in tie_rows.iter().filter(|t| t.slave == t.master) {
        let (moved, kept): (Vec<_>, Vec<_>) = t
            .rows
            .iter()
            .cloned()
            .partition(|(s, _)| gap_grids.contains(s) || shared.contains(s));
        for (s, m) in &moved {
            gap_grids.insert(*s);
            gap_grids.extend(m.iter().map(|x| x.0));
        }
        assembled_rows.extend(moved);
        inside_rows.push(super::ties::TieRows {
            slave: t.slave,
            master: t.master,
            rows: kept,
        });
    }
    let opts = scene.reduction.clone().unwrap_or_default();
    let mut cb_opts = opts.cb_options();
    cb_opts.interrupt = progress.interrupt();
    let damping = scene.damping.clone().unwrap_or_default();
    let step = progress.step(format!(
        "assembling and reducing {} component(s)",
        scene.components.len()
    ));
    let reduced: Vec<Reduced> = (0..scene.components.len())
        .into_par_iter()
        .map(|c| {
            reduce_component(
                scene,
                c,
                &meshes[c],
                &grids,
                &global_fixed,
                &gap_grids,
                &patch_of,
                &cb_opts,
                opts.checks,
                cache,
                super::ties::component_rows(&inside_rows, c, &grids.grid_of[c]),
                ladders,
                progress,
            )
        })
        .collect::<Result<_, _>>()?;
    let hits = reduced
        .iter()
        .filter(|r| r.cache.as_ref().is_some_and(|u| u.hit))
        .count();
    step.done(if cache.is_some() {
        format!("reduced every component ({hits} read from the component cache)")
    } else {
        "reduced every component".to_string()
    });

    // Superelement assembly; element damping B_c = (GE_c/W4)·K_r,c + Tᵀ B_η,c T, B_η,c =
    // Σ_b (η_b/W4)·K_b over the component's bodies with a loss factor.
    let factors: Vec<Real> = scene
        .components
        .iter()
        .map(|c| damping.element_factor(&c.name))
        .collect();
    let b_mats: Vec<Mat<Real>> = reduced
        .iter()
        .zip(&factors)
        .map(|(r, &a)| {
            let k = r.k();
            match &r.b_eta {
                Some(be) => Mat::from_fn(k.nrows(), k.ncols(), |i, j| a * k[(i, j)] + be[(i, j)]),
                None => Mat::from_fn(k.nrows(), k.ncols(), |i, j| a * k[(i, j)]),
            }
        })
        .collect();
    let any_b = factors.iter().any(|&a| a != 0.0) || reduced.iter().any(|r| r.b_eta.is_some());
    for (spec, r) in scene.components.iter().zip(&reduced) {
        for l in &r.loss_off {
            warnings.push(Warning {
                input: l.input.clone(),
                message: format!(
                    "volume `{}` of component `{}` has loss factor {}, but GE is off until \
                     `[damping] w4` is given (W4 = 0, NASTRAN's convention): it adds no damping",
                    l.volume, spec.name, l.eta
                ),
                value: l.eta,
                tolerance: 0.0,
            });
        }
    }
    let comps: Vec<Component<'_>> = scene
        .components
        .iter()
        .zip(&reduced)
        .zip(&b_mats)
        .map(|((spec, r), b)| {
            let mut comp = match &r.cb {
                Some(cb) => Component::from_cb_interface(
                    spec.name.clone(),
                    cb,
                    r.keys.clone(),
                    r.interface_keys.clone(),
                ),
                // From the component cache (never an interface-reduced component).
                None => Component {
                    name: spec.name.clone(),
                    k: r.k().as_ref(),
                    m: r.m().as_ref(),
                    b: None,
                    boundary_keys: r.keys.clone(),
                    interface: None,
                    n_modes: r.n_modes(),
                },
            };
            comp.b = any_b.then(|| b.as_ref());
            comp
        })
        .collect();
    let asm = superelement::assemble(&comps, &[]).map_err(|source| PipelineError::Reduction {
        what: "superelement assembly".into(),
        source,
    })?;

    // Loads scattered onto the assembled DOFs.
    let n = asm.dofs.len();
    let mut grid_index: HashMap<DofKey, usize> = HashMap::new();
    let mut modal_index: HashMap<(&str, usize), usize> = HashMap::new();
    let mut interface_index: HashMap<(&str, usize), usize> = HashMap::new();
    for (i, d) in asm.dofs.dofs.iter().enumerate() {
        match d.kind {
            DofKind::Grid { grid, comp } => {
                grid_index.insert(DofKey { grid, comp }, i);
            }
            DofKind::Modal { index } => {
                modal_index.insert((d.component.as_str(), index), i);
            }
            DofKind::Interface { index } => {
                interface_index.insert((d.component.as_str(), index), i);
            }
        }
    }
    // Assembled index of component-reduced coordinate j ([boundary, interface, modal]).
    let assembled_index = |name: &str, r: &Reduced, j: usize| -> Option<usize> {
        let (nb, np) = (r.keys.len(), r.cb.as_ref().map_or(0, |c| c.n_interface()));
        if j < nb {
            grid_index.get(&r.keys[j]).copied()
        } else if j < nb + np {
            interface_index.get(&(name, j - nb)).copied()
        } else {
            modal_index.get(&(name, j - nb - np)).copied()
        }
    };
    let mut p_brake = vec![0.0; n];
    for (spec, r) in scene.components.iter().zip(&reduced) {
        for (j, &v) in r.load.iter().enumerate() {
            if let Some(i) = assembled_index(&spec.name, r, j) {
                p_brake[i] += v;
            }
        }
    }
    // Ties between components (and inside ones on boundary grids): their slave grid DOFs
    // eliminated from the assembled model, kept as recovered DOFs.
    let elim = if assembled_rows.is_empty() {
        None
    } else {
        let e = super::ties::eliminate(
            &asm.k,
            &asm.m,
            asm.b.as_ref(),
            &p_brake,
            &asm.dofs,
            &assembled_rows,
        )?;
        p_brake = e.p.clone();
        Some(e)
    };
    let tie_terms = elim.as_ref().map(|e| &e.terms);
    let components = scene
        .components
        .iter()
        .zip(&reduced)
        .zip(&factors)
        .map(|((spec, r), &f)| ComponentReport {
            name: spec.name.clone(),
            n_nodes: r.n_nodes,
            n_free_dofs: r.n_dofs(),
            n_boundary_dofs: r.n_boundary() + r.interface_keys.len(),
            n_modes: r.n_modes(),
            fixed_interface_hz: r.fixed_hz().to_vec(),
            cb_stats: r.cb.as_ref().map(|c| c.stats.clone()),
            element_damping_factor: f,
            reduction_cache: r.cache.clone(),
            interface: match (&spec.interface, r.cb.as_ref()) {
                (Some(f), Some(cb)) => Some(super::InterfaceChoice::fixed(
                    f.start_degree(),
                    cb.stats.n_interface_coords,
                    cb.stats.n_interface_dofs,
                )),
                _ => None,
            },
        })
        .collect();
    let checks: Vec<(String, CbCheck)> = scene
        .components
        .iter()
        .zip(reduced.iter())
        .filter_map(|(spec, r)| r.check.clone().map(|c| (spec.name.clone(), c)))
        .collect();
    for (name, c) in checks.iter().filter(|(_, c)| !c.passed) {
        warnings.push(Warning {
            input: format!("reduction.checks (component `{name}`)"),
            message: format!("the Craig–Bampton check failed: {}", c.failures.join("; ")),
            value: c.max_abs_error_pct.unwrap_or(Real::NAN),
            tolerance: CheckOptions::default().max_error_pct,
        });
    }
    drop(comps);
    // Recovery needs every component's Ψ and Φ: none when one came from the component cache.
    let recoverable = reduced.iter().all(|r| r.cb.is_some());
    let recovery = scene
        .components
        .iter()
        .zip(reduced)
        .zip(meshes)
        .zip(&grids.grid_of)
        .filter(|_| recoverable)
        .filter_map(|(((spec, r), mesh), grid_of)| {
            let assembled = (0..r.cb.as_ref()?.n_reduced())
                .map(|j| match (assembled_index(&spec.name, &r, j), &tie_terms) {
                    (None, _) => Vec::new(),
                    (Some(i), None) => vec![(i, 1.0)],
                    (Some(i), Some(t)) => t[i].clone(),
                })
                .collect();
            let cb = r.cb?;
            Some(ComponentRecovery {
                name: spec.name.clone(),
                mesh,
                dofs: r.dofs,
                cb,
                grid_of: grid_of.clone(),
                assembled,
                mpc: r.mpc,
            })
        })
        .collect();
    gaps.gaps.iter_mut().for_each(|g| {
        g.pad_dofs = [None; 3];
        g.rotor_dofs = [None; 3];
    });
    let (k, m, b, dofs) = match elim {
        Some(e) => (e.k, e.m, e.b, e.dofs),
        None => (asm.k, asm.m, asm.b, asm.dofs),
    };
    let mut model = ReducedModel {
        k: symmetrise(&k),
        m: symmetrise(&m),
        b: b.as_ref().map(symmetrise),
        p_brake,
        dofs,
        gap_geometry: gaps,
        gap_pairs,
        grids: grids.grids.clone(),
        checks,
        components,
        recovery,
        source: ModelSource::Mesh,
        warnings,
    };
    model.assign_gap_dofs()?;
    Ok(model)
}

/// Assembles and reduces component `c`: boundary = its gap nodes + shared nodes.
#[allow(clippy::too_many_arguments)]
fn reduce_component(
    scene: &Scene,
    c: usize,
    mesh: &Mesh,
    grids: &Grids,
    global_fixed: &BTreeSet<(u64, usize)>,
    gap_grids: &std::collections::HashSet<u64>,
    patch_of: &HashMap<u64, usize>,
    cb_opts: &squeal_reduction::CbOptions,
    run_checks: bool,
    cache: Option<&ComponentCache>,
    tie_rows: Option<super::ties::NodeRows>,
    ladders: &Ladders,
    progress: &Progress,
) -> Result<Reduced, PipelineError> {
    let start = std::time::Instant::now();
    let spec = &scene.components[c];
    let name = spec.name.as_str();
    let gid = &grids.grid_of[c];
    let fixed: Vec<(usize, usize)> = (0..mesh.nodes.len())
        .flat_map(|n| (0..3).map(move |k| (n, k)))
        .filter(|&(n, k)| global_fixed.contains(&(gid[n], k)))
        .collect();
    let dofs = DofMap::new(mesh.nodes.len(), &fixed).map_err(fe_err(name))?;
    // Bonded ties inside the component: its slave DOFs eliminated (u_free = T u_indep); the
    // boundary, interface and load vectors below are over the independent DOFs.
    let mpc = tie_rows
        .map(|rows| Mpc::new(&dofs, &rows))
        .transpose()
        .map_err(|m| PipelineError::Model(format!("component `{name}`: ties: {m}")))?;
    let indep = |i: usize| -> Result<usize, PipelineError> {
        match &mpc {
            None => Ok(i),
            Some(t) => t.indep(i).ok_or_else(|| {
                PipelineError::Model(format!(
                    "component `{name}`: free DOF {i} is both a tie's slave and a boundary DOF"
                ))
            }),
        }
    };
    let materials = spec.block_materials(mesh)?;
    // Structural loss factors: with W4 > 0 the bodies with η > 0 give B_η = Σ_b (η_b/W4) K_b,
    // reduced with the component (its element damping); with W4 = 0 GE is off (a warning).
    let losses = spec.block_loss_factors(mesh)?;
    let w4 = scene.damping.as_ref().map_or(0.0, |d| d.w4);
    let lossy: Vec<usize> = (0..losses.len()).filter(|&b| losses[b].eta > 0.0).collect();
    let loss_off: Vec<crate::scene::BlockLoss> = if w4 > 0.0 {
        Vec::new()
    } else {
        lossy.iter().map(|&b| losses[b].clone()).collect()
    };
    let with_eta = w4 > 0.0 && !lossy.is_empty();
    if with_eta && spec.interface.as_ref().is_some_and(|f| f.adaptive()) {
        return Err(PipelineError::Scene {
            field: format!("components[name = {name}].interface.tolerance"),
            message: format!(
                "the interface degree chosen by a tolerance (the interface ladder) does not \
                 reduce a damping matrix, and the loss factor of {} needs one: give the \
                 interface a fixed `degree`, or set the loss factor to 0 and use \
                 `damping.ge.{name}`",
                lossy
                    .iter()
                    .map(|&b| format!("volume `{}` ({})", losses[b].volume, losses[b].eta))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    let is_boundary: Vec<bool> = grids.shared[c]
        .iter()
        .zip(gid)
        .map(|(&shared, g)| shared || gap_grids.contains(g))
        .collect();
    // With `interface`, the gap nodes not shared with another component (each in its
    // contact pair's patch) move in the interface basis instead of being boundary DOFs.
    let interface_patch = |node: usize| -> Option<usize> {
        spec.interface.as_ref()?;
        if grids.shared[c][node] {
            return None;
        }
        patch_of.get(&gid[node]).copied()
    };
    let mut boundary = Vec::new();
    let mut keys = Vec::new();
    let (mut iface_dofs, mut iface_keys, mut iface_points) = (Vec::new(), Vec::new(), Vec::new());
    for (node, &b) in is_boundary.iter().enumerate() {
        if !b {
            continue;
        }
        let patch = interface_patch(node);
        for k in 0..3 {
            if let Some(i) = dofs.free(node, k) {
                let key = DofKey {
                    grid: gid[node],
                    comp: k as u8 + 1,
                };
                let i = indep(i)?;
                match patch {
                    Some(p) => {
                        iface_dofs.push(i);
                        iface_keys.push(key);
                        iface_points.push(cb::InterfaceDof {
                            point: mesh.nodes[node],
                            direction: k,
                            patch: p,
                        });
                    }
                    None => {
                        boundary.push(i);
                        keys.push(key);
                    }
                }
            }
        }
    }
    // Brake loads on this component (projected below: f_r = Tᵀ f).
    let mut f = vec![0.0; dofs.n_free()];
    if let Some(loads) = &scene.loads {
        for p in loads.pressure.iter().filter(|p| p.component == name) {
            let v = pressure_load(mesh, &p.faces, p.pressure, &dofs).map_err(fe_err(name))?;
            f.iter_mut().zip(&v).for_each(|(a, b)| *a += b);
        }
        for fs in loads.force.iter().filter(|f| f.component == name) {
            let nodes = mesh
                .node_sets
                .get(&fs.nodes)
                .ok_or_else(|| PipelineError::Scene {
                    field: "loads.force.nodes".into(),
                    message: format!(
                        "component `{name}` has no node set `{}` (it has: {})",
                        fs.nodes,
                        mesh.node_sets
                            .keys()
                            .cloned()
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })?;
            let share = 1.0 / nodes.len().max(1) as Real;
            for &node in nodes {
                for k in 0..3 {
                    if let Some(i) = dofs.free(node, k) {
                        f[i] += share * fs.force[k];
                    }
                }
            }
        }
    }
    let f = match &mpc {
        Some(t) => t.project(&f),
        None => f,
    };
    // The component cache: the same inputs give the same reduction (not for an
    // interface-reduced component: its key would need the basis too; nor for one with ties
    // inside: its key would need the ties; nor for one with a loss factor on (η > 0 and
    // W4 > 0): the entry would need Tᵀ B_η T and its key the η's).
    let key = match cache {
        Some(_) if !run_checks && spec.interface.is_none() && mpc.is_none() && !with_eta => Some(
            ComponentInputs {
                name,
                mesh,
                materials: &materials,
                hex8: &spec.hex8,
                fixed: &fixed,
                boundary: &boundary,
                keys: &keys,
                cb: cb_opts,
                load: &f,
            }
            .key()?,
        ),
        _ => None,
    };
    let mut note = None;
    // Processes sharing the cache reduce each component once: the lock is held until the
    // reduction is read, or computed and stored.
    let _held = match (cache, &key) {
        (Some(cache), Some(key)) => {
            let l = super::cache::lock::lock_entry(
                &cache.root,
                key,
                &format!("component `{name}`"),
                progress,
            )?;
            if let super::cache::lock::EntryLock::Unsupported(why) = &l {
                note = Some(why.clone());
            }
            Some(l)
        }
        _ => None,
    };
    if let (Some(cache), Some(key)) = (cache, &key) {
        match cache.read(key) {
            Ok(Some(stored)) => {
                let load = stored.load.clone();
                return Ok(Reduced {
                    cb: None,
                    stored: Some(stored),
                    dofs,
                    keys,
                    interface_keys: Vec::new(),
                    load,
                    check: None,
                    n_nodes: mesh.nodes.len(),
                    mpc: None,
                    b_eta: None,
                    loss_off,
                    cache: Some(ComponentCacheUse {
                        key: key.clone(),
                        hit: true,
                        seconds: start.elapsed().as_secs_f64(),
                        note: None,
                    }),
                });
            }
            Ok(None) => {}
            Err(why) => {
                cache.discard(key);
                let msg = format!(
                    "component cache entry {key} of `{name}` was unusable ({why}); rebuilt"
                );
                note = Some(match note {
                    Some(n) => format!("{n}; {msg}"),
                    None => msg,
                });
            }
        }
    }
    let mut asm = assemble(
        mesh,
        &materials,
        &dofs,
        &AssemblyOptions {
            hex8: spec.hex8,
            interrupt: cb_opts.interrupt.clone(),
        },
    )
    .map_err(fe_err(name))?;
    // B_η = Σ_b (η_b/W4)·K_b: the bodies with η > 0 assembled with their elasticity scaled
    // by η/W4 (an element's stiffness is linear in its elasticity tensor).
    let mut b_eta = if with_eta {
        let sub = Mesh {
            nodes: mesh.nodes.clone(),
            node_tags: mesh.node_tags.clone(),
            volumes: lossy.iter().map(|&b| mesh.volumes[b].clone()).collect(),
            ..Mesh::default()
        };
        let scaled: Vec<_> = lossy
            .iter()
            .map(|&b| crate::scene::scaled_stiffness(&materials[b], losses[b].eta / w4))
            .collect();
        let a = assemble(
            &sub,
            &scaled,
            &dofs,
            &AssemblyOptions {
                hex8: spec.hex8,
                interrupt: cb_opts.interrupt.clone(),
            },
        )
        .map_err(fe_err(name))?;
        Some(a.k)
    } else {
        None
    };
    if let Some(t) = &mpc {
        let err = |m| PipelineError::Model(format!("component `{name}`: ties: {m}"));
        asm.k = t.transform(&asm.k).map_err(err)?;
        asm.m = t.transform(&asm.m).map_err(err)?;
        if let Some(b) = &mut b_eta {
            *b = t.transform(b).map_err(err)?;
        }
    }
    if let (Some(above), true) = (cb_opts.substructures.above_dofs, with_eta) {
        let n_interior = asm.k.nrows() - boundary.len() - iface_dofs.len();
        if n_interior > above {
            return Err(PipelineError::Scene {
                field: format!("components[name = {name}]"),
                message: format!(
                    "its loss factor needs the Craig–Bampton projection of B_η, which the \
                     substructured reduction does not do ({n_interior} interior DOFs > \
                     reduction.substructures.above_dofs = {above}): raise `above_dofs`, or \
                     set the loss factor to 0 and use `damping.ge.{name}`"
                ),
            });
        }
    }

    let red_err = |what: &str| {
        let what = format!("component `{name}`: {what}");
        move |source| PipelineError::reduction(what, source)
    };
    // DOF coordinates: K_ii of a large component is factorised in nested-dissection order.
    let coords = squeal_fe::dof_coordinates(mesh, &dofs);
    let coords = match &mpc {
        Some(t) => t.select(&coords),
        None => coords,
    };
    let model = match &spec.interface {
        // The degree an error estimate chooses: one factor for every degree tried.
        Some(f) if f.adaptive() => ladders
            .reduce(c, || {
                cb::InterfaceLadder::new(
                    &asm.k,
                    &asm.m,
                    boundary.clone(),
                    iface_dofs.into_iter().zip(iface_points).collect(),
                    cb_opts,
                    Some(&coords),
                )
            })
            .map_err(red_err("Craig–Bampton (interface ladder)"))?,
        _ => {
            let interface = match &spec.interface {
                Some(f) => Some(cb::InterfaceBasis {
                    basis: cb::polynomial_basis(&iface_points, f.start_degree())
                        .map_err(red_err("interface basis"))?,
                    dofs: iface_dofs,
                }),
                None => None,
            };
            cb::reduce_interface(
                &asm.k,
                &asm.m,
                b_eta.as_ref(),
                &boundary,
                interface.as_ref(),
                cb_opts,
                Some(&coords),
            )
            .map_err(red_err("Craig–Bampton"))?
        }
    };
    drop(coords);
    drop(b_eta);
    let b_eta = model.b.clone();
    let check = if run_checks {
        let free_dofs: Vec<usize> = (0..dofs.n_free()).collect();
        let free_dofs = match &mpc {
            Some(t) => t.select(&free_dofs),
            None => free_dofs,
        };
        let points = cb::dof_points(&mesh.nodes, free_dofs.len(), |i| dofs.dof_of(free_dofs[i]));
        Some(
            cb::check(
                &model,
                Some((&asm.k, &asm.m)),
                Some(&points),
                &CheckOptions {
                    // A held component has no rigid-body motion to compare.
                    rigid_body: fixed.is_empty(),
                    ..CheckOptions::default()
                },
            )
            .map_err(red_err("checks"))?,
        )
    } else {
        None
    };

    // f_r = Tᵀ f = [f_b; Lᵀ f_f; 0] + [Ψᵀ f_i; Φᵀ f_i].
    let nb = model.n_boundary_coords();
    let mut load = vec![0.0; model.n_reduced()];
    for (j, &d) in model.boundary.iter().enumerate() {
        load[j] = f[d];
    }
    if let Some(iface) = &model.interface {
        let nk = model.boundary.len();
        for (r, &d) in iface.dofs.iter().enumerate() {
            if f[d] != 0.0 {
                for c in 0..iface.n_coords() {
                    load[nk + c] += iface.basis[(r, c)] * f[d];
                }
            }
        }
    }
    for (r, &d) in model.interior.iter().enumerate() {
        let fi = f[d];
        if fi == 0.0 {
            continue;
        }
        for j in 0..nb {
            load[j] += model.psi[(r, j)] * fi;
        }
        for q in 0..model.n_modes {
            load[nb + q] += model.phi[(r, q)] * fi;
        }
    }
    let cache_use = match (cache, key) {
        (Some(cache), Some(key)) => {
            let stored = StoredReduction {
                k: model.k.clone(),
                m: model.m.clone(),
                load: load.clone(),
                n_boundary: nb,
                n_modes: model.n_modes,
                n_dofs: model.n_dofs,
                fixed_frequencies_hz: model.fixed_frequencies_hz.clone(),
            };
            let build_s = start.elapsed().as_secs_f64();
            if let Err(e) = cache.store(&key, name, &stored, build_s) {
                let msg = format!("could not store `{name}` in the component cache: {e}");
                note = Some(match note {
                    Some(n) => format!("{n}; {msg}"),
                    None => msg,
                });
            }
            Some(ComponentCacheUse {
                key,
                hit: false,
                seconds: start.elapsed().as_secs_f64(),
                note,
            })
        }
        _ => None,
    };
    Ok(Reduced {
        cb: Some(model),
        stored: None,
        dofs,
        keys,
        interface_keys: iface_keys,
        load,
        check,
        n_nodes: mesh.nodes.len(),
        cache: cache_use,
        mpc,
        b_eta,
        loss_off,
    })
}
