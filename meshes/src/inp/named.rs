//! The mesh's named sets and fixed DOFs from the model's *NSET, *ELSET, *SURFACE and
//! *BOUNDARY, for the units (placed instances) read.

use super::build::Unit;
use super::model::{BcTarget, Model, Scope, Scoped};
use crate::deck::Deck;
use crate::import::Builder;
use crate::{CellKind, MeshError};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// Node sets: every *NSET and, under its own name unless an *NSET has it, the nodes of every
/// *ELSET; part sets prefixed with the instance name when several units are read.
pub(super) fn node_sets(
    m: &Model,
    units: &[Unit],
    node_of: &HashMap<(usize, u64), usize>,
) -> BTreeMap<String, Vec<usize>> {
    let mut out: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (ui, u) in units.iter().enumerate() {
        for set in u.scope.nsets.values() {
            out.entry(format!("{}{}", u.prefix, set.name))
                .or_default()
                .extend(
                    set.members
                        .iter()
                        .filter_map(|&(_, l)| node_of.get(&(ui, l)).copied()),
                );
        }
        for set in u.scope.elsets.values() {
            let name = format!("{}{}", u.prefix, set.name);
            if u.scope
                .nsets
                .values()
                .any(|n| n.name.eq_ignore_ascii_case(&set.name))
            {
                continue;
            }
            let v = out.entry(name).or_default();
            for &(_, l) in &set.members {
                if let Some(&j) = u.scope.elem_index.get(&l) {
                    v.extend(
                        u.scope.elements[j]
                            .nodes
                            .iter()
                            .filter_map(|&n| node_of.get(&(ui, n)).copied()),
                    );
                }
            }
        }
    }
    // Node-based surfaces are node sets.
    for (ui, u) in units.iter().enumerate() {
        for surf in u.scope.surfaces.values().filter(|s| !s.nodes.is_empty()) {
            out.entry(format!("{}{}", u.prefix, surf.name))
                .or_default()
                .extend(
                    surf.nodes
                        .iter()
                        .filter_map(|&(_, l)| node_of.get(&(ui, l)).copied()),
                );
        }
    }
    if let Some(a) = &m.assembly {
        let unit_of: HashMap<usize, usize> = units
            .iter()
            .enumerate()
            .filter_map(|(ui, u)| u.instance.map(|i| (i, ui)))
            .collect();
        let member = |&(s, l): &(Scope, u64)| match s {
            Scope::Instance(i) => unit_of
                .get(&i)
                .and_then(|&ui| node_of.get(&(ui, l)).copied()),
            Scope::Own => None,
        };
        for surf in a.surfaces.values().filter(|s| !s.nodes.is_empty()) {
            out.entry(surf.name.clone())
                .or_default()
                .extend(surf.nodes.iter().filter_map(member));
        }
        for set in a.nsets.values() {
            out.entry(set.name.clone())
                .or_default()
                .extend(set.members.iter().filter_map(|&(s, l)| {
                    match s {
                        Scope::Instance(i) => unit_of
                            .get(&i)
                            .and_then(|&ui| node_of.get(&(ui, l)).copied()),
                        Scope::Own => None,
                    }
                }));
        }
    }
    // Sets with no node read (an assembly set of another instance) are left out.
    out.retain(|_, v| !v.is_empty());
    out
}

type FaceSets = BTreeMap<String, Vec<(CellKind, Vec<usize>, u64)>>;

/// Element-based surfaces as face sets (faces of elements read; S-numbered faces mapped to
/// the cell's local face with the same corners; a surface without face ids takes the free
/// faces of its elements). Node-based surfaces are node sets (see [`node_sets`]).
pub(super) fn face_sets(
    m: &Model,
    deck: &Deck,
    units: &[Unit],
    b: &Builder,
    cell_of: &HashMap<(usize, u64), usize>,
    corners_of: &[Vec<usize>],
) -> Result<FaceSets, MeshError> {
    let mut out: FaceSets = BTreeMap::new();
    let unit_of: HashMap<usize, usize> = units
        .iter()
        .enumerate()
        .filter_map(|(ui, u)| u.instance.map(|i| (i, ui)))
        .collect();
    let mut add = |name: String,
                   faces: &[(Scope, u64, Option<u8>, crate::deck::Loc)],
                   own_unit: Option<usize>|
     -> Result<(), MeshError> {
        let mut all_free: Vec<usize> = Vec::new();
        let list = out.entry(name.clone()).or_default();
        for &(s, l, face, at) in faces {
            let ui = match (s, own_unit) {
                (Scope::Own, Some(ui)) => ui,
                (Scope::Instance(i), _) => match unit_of.get(&i) {
                    Some(&ui) => ui,
                    None => continue,
                },
                (Scope::Own, None) => continue,
            };
            let Some(&ci) = cell_of.get(&(ui, l)) else {
                continue;
            };
            let Some(k) = face else {
                all_free.push(ci);
                continue;
            };
            let Ok(e_ty) = units[ui].scope.elements[units[ui].scope.elem_index[&l]].ty else {
                continue;
            };
            let Some(local) = e_ty.face_corners(k) else {
                return Err(deck.err(
                    at,
                    format!(
                        "*SURFACE {name}: element {l} ({}) has no face S{k}",
                        e_ty.name()
                    ),
                ));
            };
            let corners: Vec<usize> = local.iter().map(|&c| corners_of[ci][c]).collect();
            let Some((kind, nodes)) = b.face_with_corners(ci, &corners) else {
                return Err(deck.err(
                    at,
                    format!("*SURFACE {name}: face S{k} of element {l} is not a face of its cell"),
                ));
            };
            list.push((kind, nodes, l));
        }
        if !all_free.is_empty() {
            list.extend(b.free_faces(&all_free));
        }
        Ok(())
    };
    for (ui, u) in units.iter().enumerate() {
        for s in u.scope.surfaces.values() {
            if !s.faces.is_empty() {
                add(format!("{}{}", u.prefix, s.name), &s.faces, Some(ui))?;
            }
        }
    }
    if let Some(a) = &m.assembly {
        for s in a.surfaces.values() {
            if !s.faces.is_empty() {
                add(s.name.clone(), &s.faces, None)?;
            }
        }
    }
    out.retain(|_, v| !v.is_empty());
    Ok(out)
}

/// Fixed DOFs being gathered.
#[derive(Default)]
struct Fixed {
    out: BTreeSet<(usize, usize)>,
    rotations: usize,
    any: bool,
}

impl Fixed {
    fn add(&mut self, node: usize, dofs: &[u8]) {
        for &d in dofs {
            if d <= 3 {
                self.out.insert((node, d as usize - 1));
            } else {
                self.rotations += 1;
            }
        }
    }

    /// A condition on a node or node set of unit `ui`'s own scope.
    fn apply(
        &mut self,
        deck: &Deck,
        ui: usize,
        scope: &Scoped,
        node_of: &HashMap<(usize, u64), usize>,
        target: &BcTarget,
        dofs: &[u8],
        at: crate::deck::Loc,
    ) -> Result<(), MeshError> {
        let labels: Vec<u64> = match target {
            BcTarget::Node(l) => {
                if !scope.node_index.contains_key(l) {
                    return Err(
                        deck.err(at, format!("*BOUNDARY: node {l}, which no *NODE defines"))
                    );
                }
                vec![*l]
            }
            BcTarget::Set(key) => match scope.nsets.get(key) {
                Some(s) => s.members.iter().map(|&(_, l)| l).collect(),
                None => {
                    return Err(deck.err(
                        at,
                        format!("*BOUNDARY: `{key}` is neither a node label nor a node set"),
                    ))
                }
            },
        };
        self.any = true;
        for l in labels {
            if let Some(&i) = node_of.get(&(ui, l)) {
                self.add(i, dofs);
            }
        }
        Ok(())
    }
}

/// Zero *BOUNDARY conditions as (node, component 0..3); rotations are left out (noted).
pub(super) fn fixed_dofs(
    m: &Model,
    deck: &Deck,
    units: &[Unit],
    node_of: &HashMap<(usize, u64), usize>,
    notes: &mut Vec<String>,
) -> Result<Vec<(usize, usize)>, MeshError> {
    let mut f = Fixed::default();
    for (ui, u) in units.iter().enumerate() {
        for bc in &u.scope.bcs {
            f.apply(deck, ui, u.scope, node_of, &bc.target, &bc.dofs, bc.at)?;
        }
    }
    let unit_of = |i: usize| units.iter().position(|u| u.instance == Some(i));
    if let Some(a) = &m.assembly {
        for bc in &a.bcs {
            match bc.scope {
                Scope::Instance(i) => {
                    if let Some(ui) = unit_of(i) {
                        f.apply(
                            deck,
                            ui,
                            units[ui].scope,
                            node_of,
                            &bc.target,
                            &bc.dofs,
                            bc.at,
                        )?;
                    }
                }
                Scope::Own => {
                    // An assembly set names instance nodes; an assembly node is a reference
                    // point no element uses.
                    let BcTarget::Set(key) = &bc.target else {
                        continue;
                    };
                    let Some(set) = a.nsets.get(key) else {
                        return Err(deck.err(
                            bc.at,
                            format!("*BOUNDARY: `{key}` is neither a node label nor a node set"),
                        ));
                    };
                    f.any = true;
                    for &(s, l) in &set.members {
                        let Scope::Instance(i) = s else { continue };
                        if let Some(&n) = unit_of(i).and_then(|ui| node_of.get(&(ui, l))) {
                            f.add(n, &bc.dofs);
                        }
                    }
                }
            }
        }
    }
    if f.any {
        if let Some(at) = m.transform {
            return Err(deck.err(
                at,
                "*TRANSFORM with *BOUNDARY: squeal holds global x, y, z only; boundary \
                 conditions in a transformed frame are not read",
            ));
        }
    }
    if f.rotations > 0 {
        notes.push(format!(
            "{} constrained rotational DOFs (4, 5, 6) left out: solid nodes have no rotations",
            f.rotations
        ));
    }
    Ok(f.out.into_iter().collect())
}
