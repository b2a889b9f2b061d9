//! Abaqus model → [`Mesh`]: the selected instances (or parts, or the model level) placed by
//! their translation and rotation, their solid elements grouped by section, node sets from
//! *NSET and *ELSET, face sets from element-based *SURFACEs, sections with their material
//! axes (turned with the instance), zero *BOUNDARY conditions as fixed DOFs.

use super::materials::{axes, OrientPoints};
use super::model::{Model, Scope, Scoped};
use super::named;
use super::InpOptions;
use crate::deck::Deck;
use crate::import::{Builder, RawCell, ReadReport, Unsupported};
use crate::section::{MaterialData, Section};
use crate::{Mesh, MeshError};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// One placed copy of a part (or the model level): what it reads and where it goes.
pub(super) struct Unit<'a> {
    pub scope: &'a Scoped,
    /// Instance index (None: a part without assembly, or the model level).
    pub instance: Option<usize>,
    pub rot: [[f64; 3]; 3],
    pub shift: [f64; 3],
    /// Name prefix of its sets and blocks (`instance.`; empty when only one unit is read).
    pub prefix: String,
    /// Its name in messages.
    pub label: String,
}

impl Unit<'_> {
    fn place(&self, x: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| self.shift[i] + (0..3).map(|k| self.rot[i][k] * x[k]).sum::<f64>())
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn input_err(deck: &Deck, message: String) -> MeshError {
    MeshError::Input {
        file: deck.files[0].clone(),
        message,
    }
}

/// The units the options select.
fn units<'a>(m: &'a Model, deck: &Deck, opts: &InpOptions) -> Result<Vec<Unit<'a>>, MeshError> {
    let unit = |scope: &'a Scoped, instance, rot, shift, label: String| Unit {
        scope,
        instance,
        rot,
        shift,
        prefix: String::new(),
        label,
    };
    let mut out: Vec<Unit> = Vec::new();
    if m.parts.is_empty() {
        if !opts.instances.is_empty() || opts.part.is_some() {
            return Err(input_err(
                deck,
                "`instances`/`part`: the file has no *PART (select element sets with `elsets`)"
                    .into(),
            ));
        }
        out.push(unit(&m.root, None, IDENTITY, [0.0; 3], "the model".into()));
        return Ok(out);
    }
    if !m.root.elements.is_empty() {
        return Err(deck.err(
            m.root.elements[0].at,
            "elements outside any *PART in a file with parts",
        ));
    }
    let part_key = opts.part.as_deref().map(super::keywords::name_key);
    if let Some(k) = &part_key {
        if !m.part_index.contains_key(k) {
            return Err(input_err(
                deck,
                format!(
                    "`part = {}`: no *PART of that name (parts: {})",
                    opts.part.as_deref().unwrap_or(""),
                    super::model::list(m.parts.iter().map(|p| p.name.as_str()))
                ),
            ));
        }
    }
    if m.assembly.is_none() {
        if !opts.instances.is_empty() {
            return Err(input_err(
                deck,
                "`instances`: the file has no *ASSEMBLY".into(),
            ));
        }
        for (i, p) in m.parts.iter().enumerate() {
            if part_key.as_ref().is_none_or(|k| m.part_index[k] == i) {
                out.push(unit(
                    p,
                    None,
                    IDENTITY,
                    [0.0; 3],
                    format!("part {}", p.name),
                ));
            }
        }
        return Ok(out);
    }
    for want in &opts.instances {
        if !m
            .instance_index
            .contains_key(&super::keywords::name_key(want))
        {
            return Err(input_err(
                deck,
                format!(
                    "`instances`: no *INSTANCE named `{want}` (instances: {})",
                    super::model::list(m.instances.iter().map(|i| i.name.as_str()))
                ),
            ));
        }
    }
    let wanted: BTreeSet<String> = opts
        .instances
        .iter()
        .map(|s| super::keywords::name_key(s))
        .collect();
    for (i, inst) in m.instances.iter().enumerate() {
        let key = super::keywords::name_key(&inst.name);
        let by_name = wanted.is_empty() || wanted.contains(&key);
        let by_part = part_key
            .as_ref()
            .is_none_or(|k| m.part_index[k] == inst.part);
        if by_name && by_part {
            out.push(unit(
                &m.parts[inst.part],
                Some(i),
                inst.rot,
                inst.shift,
                format!("instance {}", inst.name),
            ));
        }
    }
    if out.is_empty() {
        return Err(input_err(
            deck,
            "the selection (`instances`, `part`) names no instance".into(),
        ));
    }
    if out.len() > 1 {
        for u in &mut out {
            if let Some(i) = u.instance {
                u.prefix = format!("{}.", m.instances[i].name);
            }
        }
    }
    Ok(out)
}

/// Builds the mesh and the report.
pub(crate) fn build(
    m: Model,
    deck: &Deck,
    opts: &InpOptions,
) -> Result<(Mesh, ReadReport), MeshError> {
    let units = units(&m, deck, opts)?;
    let mut notes = m.notes.clone();
    if !m.parts.is_empty() && m.assembly.is_none() {
        notes.push("parts without an *ASSEMBLY read in place (each once, not moved)".into());
    }
    let mut b = Builder::default();
    // Node tags: labels, made unique across units when several are read.
    let max_label = units
        .iter()
        .flat_map(|u| u.scope.nodes.iter().map(|n| n.label))
        .max()
        .unwrap_or(0);
    let mut base = 1u64;
    while base <= max_label {
        base = base.saturating_mul(10);
    }
    let mut node_of: HashMap<(usize, u64), usize> = HashMap::new();
    for (ui, u) in units.iter().enumerate() {
        for n in &u.scope.nodes {
            node_of.insert((ui, n.label), b.nodes.len());
            b.nodes.push(u.place(n.x));
            b.tags.push(if units.len() == 1 {
                n.label
            } else {
                (ui as u64 + 1).saturating_mul(base).saturating_add(n.label)
            });
        }
    }
    // Elements selected per unit, with their section.
    let selected = select_elements(&m, deck, &units, opts)?;
    let mut cell_of: HashMap<(usize, u64), usize> = HashMap::new();
    let mut sections = BTreeMap::new();
    let mut types: BTreeMap<String, usize> = BTreeMap::new();
    for (ui, u) in units.iter().enumerate() {
        let section_of = element_sections(deck, u.scope)?;
        for &ei in &selected[ui] {
            let e = &u.scope.elements[ei];
            let ty = match &e.ty {
                Ok(t) => *t,
                Err(name) => {
                    return Err(deck.err(
                        e.at,
                        format!(
                            "element {} of {} has type {name}, which squeal does not read (the \
                             solids {} and their R, H, I, M variants); leave such elements out \
                             by selecting solid element sets with `elsets` (or `instances`, \
                             `part`)",
                            e.label,
                            u.label,
                            super::elements::ElemType::NAMES.join(", ")
                        ),
                    ))
                }
            };
            let block = match section_of.get(&e.label) {
                Some(&si) => {
                    let s = &u.scope.sections[si];
                    let set_name = u
                        .scope
                        .elsets
                        .get(&s.elset)
                        .map_or(s.elset.clone(), |x| x.name.clone());
                    let name = format!("{}{set_name}", u.prefix);
                    if !sections.contains_key(&name) {
                        let sec = section(&m, deck, u, si, &mut notes)?;
                        sections.insert(name.clone(), sec);
                    }
                    Some(name)
                }
                None if u.scope.sections.is_empty() => {
                    e.elset.as_ref().map(|s| format!("{}{s}", u.prefix))
                }
                None => {
                    return Err(deck.err(
                        e.at,
                        format!(
                            "element {} ({}) of {} is in no *SOLID SECTION",
                            e.label,
                            ty.name(),
                            u.label
                        ),
                    ))
                }
            };
            let mut nodes = Vec::with_capacity(e.nodes.len());
            for n in &e.nodes {
                let Some(&i) = node_of.get(&(ui, *n)) else {
                    return Err(deck.err(
                        e.at,
                        format!(
                            "element {} ({}) of {} uses node {n}, which no *NODE defines",
                            e.label,
                            ty.name(),
                            u.label
                        ),
                    ));
                };
                nodes.push(i);
            }
            cell_of.insert((ui, e.label), b.cells.len());
            *types.entry(ty.name()).or_insert(0) += 1;
            b.cells.push(RawCell {
                kind: ty.kind(),
                nodes,
                tag: e.label,
                block,
                file: deck.file(e.at).to_string(),
                line: e.at.line as usize,
                what: format!("element {} of {}", e.label, u.label),
            });
        }
    }
    // The element's own corner nodes (Abaqus order = squeal order), before orientation.
    let corners_of: Vec<Vec<usize>> = b.cells.iter().map(|c| c.nodes.clone()).collect();
    b.orient()?;
    for ty in types.keys() {
        if let Some(n) = super::elements::ElemType::from_name(ty).and_then(|t| t.note()) {
            notes.push(n);
        }
    }

    let node_sets = named::node_sets(&m, &units, &node_of);
    let face_sets = named::face_sets(&m, deck, &units, &b, &cell_of, &corners_of)?;
    let fixed = named::fixed_dofs(&m, deck, &units, &node_of, &mut notes)?;

    let mut report = ReadReport {
        format: "abaqus".into(),
        files: deck.files.clone(),
        ..Default::default()
    };
    report.counts.insert("*NODE".into(), b.nodes.len());
    for (ty, n) in types {
        report.counts.insert(format!("*ELEMENT {ty}"), n);
    }
    report.counts.insert("fixed DOFs".into(), fixed.len());
    report.unsupported = m
        .unsupported
        .iter()
        .map(|(name, (count, at))| Unsupported {
            name: name.clone(),
            count: *count,
            first: deck.at(*at),
        })
        .collect();
    report.notes = notes;
    Ok((b.finish(node_sets, face_sets, sections, fixed), report))
}

/// Indices into each unit's elements of the elements read: all, or those of `opts.elsets`.
fn select_elements(
    m: &Model,
    deck: &Deck,
    units: &[Unit],
    opts: &InpOptions,
) -> Result<Vec<Vec<usize>>, MeshError> {
    let mut out = Vec::with_capacity(units.len());
    let mut found: BTreeSet<String> = BTreeSet::new();
    for u in units {
        if opts.elsets.is_empty() {
            out.push((0..u.scope.elements.len()).collect());
            continue;
        }
        let mut labels: BTreeSet<u64> = BTreeSet::new();
        for name in &opts.elsets {
            let key = super::keywords::name_key(name);
            if let Some(set) = u.scope.elsets.get(&key) {
                labels.extend(set.members.iter().map(|&(_, l)| l));
                found.insert(key.clone());
            }
            if let (Some(a), Some(i)) = (&m.assembly, u.instance) {
                if let Some(set) = a.elsets.get(&key) {
                    labels.extend(
                        set.members
                            .iter()
                            .filter(|&&(s, _)| s == Scope::Instance(i))
                            .map(|&(_, l)| l),
                    );
                    found.insert(key);
                }
            }
        }
        out.push(
            labels
                .iter()
                .filter_map(|l| u.scope.elem_index.get(l).copied())
                .collect(),
        );
    }
    for name in &opts.elsets {
        if !found.contains(&super::keywords::name_key(name)) {
            let mut have: BTreeSet<&str> = BTreeSet::new();
            for u in units {
                have.extend(u.scope.elsets.values().map(|s| s.name.as_str()));
            }
            if let Some(a) = &m.assembly {
                have.extend(a.elsets.values().map(|s| s.name.as_str()));
            }
            return Err(input_err(
                deck,
                format!(
                    "`elsets`: no *ELSET named `{name}` in the selection (element sets: {})",
                    super::model::list(have.into_iter())
                ),
            ));
        }
    }
    if out.iter().all(Vec::is_empty) {
        return Err(input_err(
            deck,
            "the selection holds no solid element".into(),
        ));
    }
    Ok(out)
}

/// Element label → index of its *SOLID SECTION in `s` (an element in two sections is an
/// error; a section whose set is undefined or empty too).
fn element_sections(deck: &Deck, s: &Scoped) -> Result<HashMap<u64, usize>, MeshError> {
    let mut out: HashMap<u64, usize> = HashMap::new();
    for (si, sec) in s.sections.iter().enumerate() {
        let Some(set) = s.elsets.get(&sec.elset) else {
            return Err(deck.err(
                sec.at,
                format!(
                    "*SOLID SECTION: ELSET={}, which no *ELSET or *ELEMENT defines",
                    sec.elset
                ),
            ));
        };
        if set.members.is_empty() {
            return Err(deck.err(
                sec.at,
                format!("*SOLID SECTION: ELSET={} has no element", set.name),
            ));
        }
        for &(_, l) in &set.members {
            if let Some(&other) = out.get(&l) {
                if other != si {
                    return Err(deck.err(
                        sec.at,
                        format!(
                            "element {l} is in two solid sections (also the one at {})",
                            deck.at(s.sections[other].at)
                        ),
                    ));
                }
            }
            out.insert(l, si);
        }
    }
    Ok(out)
}

/// The section `si` of unit `u`: its material and its axes, turned with the unit.
fn section(
    m: &Model,
    deck: &Deck,
    u: &Unit,
    si: usize,
    notes: &mut Vec<String>,
) -> Result<Section, MeshError> {
    let sec = &u.scope.sections[si];
    let Some(mat) = m.materials.get(&sec.material) else {
        return Err(deck.err(
            sec.at,
            format!(
                "*SOLID SECTION: MATERIAL={}, which no *MATERIAL defines (materials: {})",
                sec.material,
                super::model::list(m.materials.values().map(|x| x.name.as_str()))
            ),
        ));
    };
    let Some((elastic, _)) = &mat.elastic else {
        return Err(deck.err(
            mat.at,
            format!(
                "*MATERIAL {}: no *ELASTIC (squeal reads linear elastic solids)",
                mat.name
            ),
        ));
    };
    for (kw, at) in &mat.ignored {
        notes.push(format!(
            "{}: *MATERIAL {}: {kw} not read (linear elastic vibration)",
            deck.at(*at),
            mat.name
        ));
    }
    if let Some(d) = &mat.damping {
        notes.push(format!(
            "*MATERIAL {}: *DAMPING {d} not read (squeal reads STRUCTURAL, the loss factor; \
             Rayleigh damping is the scene's [damping])",
            mat.name
        ));
    }
    let ax = match &sec.orientation {
        None => None,
        Some(key) => {
            let Some(o) = u.scope.orientations.get(key) else {
                return Err(deck.err(
                    sec.at,
                    format!("*SOLID SECTION: ORIENTATION={key}, which no *ORIENTATION of the part defines"),
                ));
            };
            let pos = |l: u64| -> Result<[f64; 3], MeshError> {
                u.scope
                    .node_index
                    .get(&l)
                    .map(|&i| u.scope.nodes[i].x)
                    .ok_or_else(|| {
                        deck.err(
                            o.at,
                            format!("*ORIENTATION {}: node {l}, which no *NODE defines", o.name),
                        )
                    })
            };
            let (a, bb, c) = match o.points {
                OrientPoints::Coordinates(a, b, c) => (a, b, c),
                OrientPoints::Nodes(a, b, c) => (pos(a)?, pos(b)?, c.map(pos).transpose()?),
            };
            let Some(ax) = axes(o, a, bb, c) else {
                return Err(deck.err(
                    o.at,
                    format!(
                        "*ORIENTATION {}: its points do not define axes (coincident or collinear)",
                        o.name
                    ),
                ));
            };
            Some(ax.moved(&u.rot, u.shift))
        }
    };
    Ok(Section {
        material: MaterialData {
            name: mat.name.clone(),
            source: deck.at(mat.at),
            elastic: elastic.clone(),
            density: mat.density,
            structural_damping: mat.structural.filter(|&g| g != 0.0),
        },
        axes: ax,
        source: format!("{}: *SOLID SECTION of {}", deck.at(sec.at), u.label),
    })
}
