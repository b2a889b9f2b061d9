//! The Abaqus keywords squeal reads, typed, in their scopes (the model level, each *PART, the
//! *ASSEMBLY with its *INSTANCEs); every other keyword counted by name.

use super::elements::ElemType;
use super::keywords::{label, name_key, name_text, read_blocks, real, Block};
use super::materials::{read_material_option, MaterialDef, OrientDef};
use super::sets;
use super::sets::Instances;
use crate::deck::{shorten, Deck, Loc};
use crate::MeshError;
use std::collections::{BTreeMap, HashMap};

/// Whose entity a set member is: the scope's own, or (at the assembly level) an instance's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Scope {
    Own,
    Instance(usize),
}

#[derive(Debug, Clone)]
pub(crate) struct NodeDef {
    pub label: u64,
    pub x: [f64; 3],
    pub at: Loc,
}

#[derive(Debug, Clone)]
pub(crate) struct ElemDef {
    pub label: u64,
    /// The type, or the name of a type squeal does not read.
    pub ty: Result<ElemType, String>,
    pub nodes: Vec<u64>,
    /// The *ELEMENT line's ELSET (display name), if any.
    pub elset: Option<String>,
    pub at: Loc,
}

/// A node or element set: display name, members in definition order (may repeat).
#[derive(Debug, Clone)]
pub(crate) struct SetDef {
    pub name: String,
    pub members: Vec<(Scope, u64)>,
}

/// An element-based surface: (scope, element label, face 1..6 or None = every free face);
/// a node-based surface keeps its nodes.
#[derive(Debug, Clone)]
pub(crate) struct SurfDef {
    pub name: String,
    pub faces: Vec<(Scope, u64, Option<u8>, Loc)>,
    pub nodes: Vec<(Scope, u64)>,
    pub at: Loc,
}

/// *SOLID SECTION.
#[derive(Debug, Clone)]
pub(crate) struct SectionDef {
    pub elset: String,
    pub material: String,
    pub orientation: Option<String>,
    pub at: Loc,
}

/// A zero-displacement boundary condition on a node or a node set.
#[derive(Debug, Clone)]
pub(crate) struct BcDef {
    pub scope: Scope,
    pub target: BcTarget,
    /// Degrees of freedom 1..6.
    pub dofs: Vec<u8>,
    pub at: Loc,
}

#[derive(Debug, Clone)]
pub(crate) enum BcTarget {
    Node(u64),
    Set(String),
}

/// A part, the model level of a file without parts, or the assembly level.
#[derive(Debug, Clone, Default)]
pub(crate) struct Scoped {
    pub name: String,
    pub nodes: Vec<NodeDef>,
    pub node_index: HashMap<u64, usize>,
    pub elements: Vec<ElemDef>,
    pub elem_index: HashMap<u64, usize>,
    pub nsets: BTreeMap<String, SetDef>,
    pub elsets: BTreeMap<String, SetDef>,
    pub surfaces: BTreeMap<String, SurfDef>,
    pub sections: Vec<SectionDef>,
    pub orientations: BTreeMap<String, OrientDef>,
    pub bcs: Vec<BcDef>,
}

/// *INSTANCE: a part placed by x' = rot · x + shift.
#[derive(Debug, Clone)]
pub(crate) struct InstanceDef {
    pub name: String,
    pub part: usize,
    pub rot: [[f64; 3]; 3],
    pub shift: [f64; 3],
}

/// The whole input.
#[derive(Debug, Default)]
pub(crate) struct Model {
    /// The model level (nodes and elements of a file without parts).
    pub root: Scoped,
    pub parts: Vec<Scoped>,
    pub part_index: HashMap<String, usize>,
    pub assembly: Option<Scoped>,
    pub instances: Vec<InstanceDef>,
    pub instance_index: HashMap<String, usize>,
    pub materials: BTreeMap<String, MaterialDef>,
    pub unsupported: BTreeMap<String, (usize, Loc)>,
    /// Keywords whose presence makes a *BOUNDARY's frame differ from the global one.
    pub transform: Option<Loc>,
    pub notes: Vec<String>,
}

/// Where the reader is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Level {
    Root,
    Part(usize),
    Assembly,
    Instance,
    Step,
}

/// Keywords that would change the mesh: skipping them would silently change the model.
const GEOMETRY_KEYWORDS: [&str; 9] = [
    "NCOPY",
    "NFILL",
    "NGEN",
    "NMAP",
    "ELGEN",
    "ELCOPY",
    "SYSTEM",
    "NODAL THICKNESS",
    "IMPORT",
];

/// Reads the deck into a [`Model`].
pub(crate) fn read_model(deck: &mut Deck) -> Result<Model, MeshError> {
    let mut m = Model::default();
    let mut level = Level::Root;
    let mut material: Option<String> = None;
    let mut root_bc: Option<Loc> = None;
    read_blocks(deck, |deck, b| {
        let kw = b.keyword.as_str();
        // Material options follow their *MATERIAL.
        if let Some(key) = &material {
            if read_material_option(deck, &b, m.materials.get_mut(key).expect("added"))? {
                return Ok(());
            }
            material = None;
        }
        if GEOMETRY_KEYWORDS.contains(&kw) {
            return Err(deck.err(
                b.at,
                format!(
                    "*{kw} generates or moves nodes or elements, which squeal does not do: \
                     write the mesh out in full (e.g. from the pre-processor)"
                ),
            ));
        }
        match (kw, level) {
            ("PART", Level::Root) => {
                let name = required(deck, &b, "NAME")?;
                let key = name_key(&name);
                if m.part_index.contains_key(&key) {
                    return Err(deck.err(b.at, format!("*PART {name}: defined twice")));
                }
                m.parts.push(Scoped {
                    name: name_text(&name),
                    ..Default::default()
                });
                m.part_index.insert(key, m.parts.len() - 1);
                level = Level::Part(m.parts.len() - 1);
            }
            ("END PART", Level::Part(_)) => level = Level::Root,
            ("ASSEMBLY", Level::Root) => {
                if m.assembly.is_some() {
                    return Err(deck.err(b.at, "a second *ASSEMBLY"));
                }
                m.assembly = Some(Scoped {
                    name: b.param("NAME").map(name_text).unwrap_or_default(),
                    ..Default::default()
                });
                level = Level::Assembly;
            }
            ("END ASSEMBLY", Level::Assembly) => level = Level::Root,
            ("INSTANCE", Level::Assembly) => {
                add_instance(&mut m, deck, &b)?;
                level = Level::Instance;
            }
            ("END INSTANCE", Level::Instance) => level = Level::Assembly,
            ("STEP", Level::Root) => {
                level = Level::Step;
                count(&mut m, &b);
            }
            ("END STEP", Level::Step) => level = Level::Root,
            ("MATERIAL", Level::Root) => {
                let name = required(deck, &b, "NAME")?;
                let key = name_key(&name);
                if let Some(old) = m.materials.get(&key) {
                    return Err(deck.err(
                        b.at,
                        format!("*MATERIAL {name}: also defined at {}", deck.at(old.at)),
                    ));
                }
                m.materials
                    .insert(key.clone(), MaterialDef::new(name_text(&name), b.at));
                material = Some(key);
            }
            ("NODE" | "ELEMENT", Level::Instance) => {
                return Err(deck.err(
                    b.at,
                    format!(
                        "*{kw} inside an *INSTANCE: instances with their own mesh are not read"
                    ),
                ))
            }
            (
                "PART" | "ASSEMBLY" | "INSTANCE" | "STEP" | "MATERIAL" | "END PART"
                | "END ASSEMBLY" | "END INSTANCE" | "END STEP",
                _,
            ) => {
                return Err(deck.err(
                    b.at,
                    format!("*{kw} is out of place here ({})", level_name(level)),
                ))
            }
            ("BOUNDARY", Level::Step) => {
                let bcs = sets::boundary(deck, &b, m.assembly.is_some(), &m)?;
                m.notes.push(format!(
                    "{}: *BOUNDARY inside a *STEP applied as fixed DOFs",
                    deck.at(b.at)
                ));
                scope_mut(&mut m, Level::Assembly).bcs.extend(bcs);
            }
            (_, Level::Step | Level::Instance) => count(&mut m, &b),
            ("TRANSFORM", _) => {
                m.transform.get_or_insert(b.at);
                count(&mut m, &b);
            }
            ("NODE", _) => add_nodes(scope_mut(&mut m, level), deck, &b)?,
            ("ELEMENT", _) => add_elements(scope_mut(&mut m, level), deck, &b)?,
            ("NSET" | "ELSET" | "SURFACE", _) => {
                let read = with_scope(&mut m, level, |s, parts, instances| match kw {
                    "NSET" => sets::nset(s, deck, &b, instances, parts).map(|_| true),
                    "ELSET" => sets::elset(s, deck, &b, instances, parts).map(|_| true),
                    _ => sets::surface(s, deck, &b, instances, parts),
                })?;
                if !read {
                    count(&mut m, &b);
                }
            }
            ("SOLID SECTION", Level::Root | Level::Part(_)) => {
                let s = scope_mut(&mut m, level);
                s.sections.push(SectionDef {
                    elset: name_key(&required(deck, &b, "ELSET")?),
                    material: name_key(&required(deck, &b, "MATERIAL")?),
                    orientation: b.param("ORIENTATION").map(name_key),
                    at: b.at,
                });
            }
            ("ORIENTATION", Level::Root | Level::Part(_)) => {
                let o = super::materials::orientation(deck, &b)?;
                let s = scope_mut(&mut m, level);
                s.orientations.insert(name_key(&o.name), o);
            }
            // Model data after the *ASSEMBLY (as Abaqus/CAE writes it) names the assembly's
            // sets and `instance.set`s: it belongs to the assembly, as in a *STEP.
            ("BOUNDARY", Level::Root) if m.assembly.is_some() => {
                let bcs = sets::boundary(deck, &b, true, &m)?;
                scope_mut(&mut m, Level::Assembly).bcs.extend(bcs);
            }
            ("BOUNDARY", _) => {
                let at_assembly = level == Level::Assembly;
                let bcs = sets::boundary(deck, &b, at_assembly, &m)?;
                if level == Level::Root {
                    root_bc.get_or_insert(b.at);
                }
                scope_mut(&mut m, level).bcs.extend(bcs);
            }
            _ => count(&mut m, &b),
        }
        Ok(())
    })?;
    // A model-level *BOUNDARY before an *ASSEMBLY read later names nothing the instances
    // hold: refused, not dropped.
    if let (Some(at), Some(_)) = (root_bc, &m.assembly) {
        return Err(deck.err(
            at,
            "*BOUNDARY at the model level before the *ASSEMBLY: with an assembly, give the \
             conditions after *END ASSEMBLY (or in the assembly or a step) on `instance.set` \
             names",
        ));
    }
    if level != Level::Root && level != Level::Step {
        let file = deck.files[0].clone();
        return Err(MeshError::Input {
            file,
            message: format!(
                "the input ends inside {} (a missing *END …)",
                level_name(level)
            ),
        });
    }
    Ok(m)
}

fn level_name(l: Level) -> &'static str {
    match l {
        Level::Root => "the model level",
        Level::Part(_) => "a *PART",
        Level::Assembly => "the *ASSEMBLY",
        Level::Instance => "an *INSTANCE",
        Level::Step => "a *STEP",
    }
}

fn scope_mut(m: &mut Model, level: Level) -> &mut Scoped {
    match level {
        Level::Part(i) => &mut m.parts[i],
        Level::Assembly | Level::Instance | Level::Step if m.assembly.is_some() => {
            m.assembly.as_mut().expect("checked")
        }
        _ => &mut m.root,
    }
}

/// Runs `f` on the scope of `level` with the parts (for `instance.name` references at the
/// assembly level).
fn with_scope<R>(
    m: &mut Model,
    level: Level,
    f: impl FnOnce(&mut Scoped, &[Scoped], &Instances) -> R,
) -> R {
    let none = Instances::new();
    match level {
        Level::Part(i) => {
            let mut p = std::mem::take(&mut m.parts[i]);
            let r = f(&mut p, &[], &none);
            m.parts[i] = p;
            r
        }
        _ => match m.assembly.take() {
            Some(mut a) => {
                let instances = instance_view(m);
                let r = f(&mut a, &m.parts, &instances);
                m.assembly = Some(a);
                r
            }
            None => f(&mut m.root, &[], &none),
        },
    }
}

/// (instance key → (index, part index)) for resolving `instance.name` references.
pub(crate) fn instance_view(m: &Model) -> Instances {
    m.instance_index
        .iter()
        .map(|(k, &i)| (k.clone(), (i, m.instances[i].part)))
        .collect()
}

fn count(m: &mut Model, b: &Block) {
    let e = m
        .unsupported
        .entry(format!("*{}", b.keyword))
        .or_insert((0, b.at));
    e.0 += 1;
}

/// A required parameter's value (as written).
pub(crate) fn required(deck: &Deck, b: &Block, name: &str) -> Result<String, MeshError> {
    match b.param(name) {
        Some(v) if !v.trim().is_empty() => Ok(v.to_string()),
        _ => Err(deck.err(b.at, format!("*{} needs {name}=", b.keyword))),
    }
}

fn add_nodes(s: &mut Scoped, deck: &Deck, b: &Block) -> Result<(), MeshError> {
    let system = b.param("SYSTEM").map(|v| v.trim().to_ascii_uppercase());
    let cylindrical = match system.as_deref() {
        None | Some("R") => false,
        Some("C") => true,
        Some(other) => {
            return Err(deck.err(
                b.at,
                format!("*NODE, SYSTEM={other}: only R (rectangular) and C (cylindrical) are read"),
            ))
        }
    };
    let mut added = Vec::new();
    for d in &b.data {
        let Some(lab) = d.items.first().and_then(|t| label(t)) else {
            return Err(deck.err(
                d.at,
                format!(
                    "*NODE: `{}` is not a node label (a positive integer)",
                    shorten(d.items.first().map(String::as_str).unwrap_or(""))
                ),
            ));
        };
        let mut x = [0.0; 3];
        for k in 0..3 {
            let t = d.items.get(k + 1).map(String::as_str).unwrap_or("");
            if t.is_empty() {
                continue;
            }
            x[k] = real(t).ok_or_else(|| {
                deck.err(
                    d.at,
                    format!(
                        "*NODE {lab}: coordinate {} = `{}` is not a finite number",
                        k + 1,
                        shorten(t)
                    ),
                )
            })?;
        }
        if cylindrical {
            let (sn, c) = x[1].to_radians().sin_cos();
            x = [x[0] * c, x[0] * sn, x[2]];
        }
        if let Some(&i) = s.node_index.get(&lab) {
            return Err(deck.err(
                d.at,
                format!(
                    "*NODE {lab}: defined twice (first at {})",
                    deck.at(s.nodes[i].at)
                ),
            ));
        }
        s.node_index.insert(lab, s.nodes.len());
        s.nodes.push(NodeDef {
            label: lab,
            x,
            at: d.at,
        });
        added.push(lab);
    }
    if let Some(n) = b.param("NSET") {
        let set = s.nsets.entry(name_key(n)).or_insert_with(|| SetDef {
            name: name_text(n),
            members: Vec::new(),
        });
        set.members
            .extend(added.into_iter().map(|l| (Scope::Own, l)));
    }
    Ok(())
}

fn add_elements(s: &mut Scoped, deck: &Deck, b: &Block) -> Result<(), MeshError> {
    let ty_text = required(deck, b, "TYPE")?;
    // A type squeal does not read is kept by name: an error only if such an element is read.
    let ty = ElemType::from_name(&name_key(&ty_text)).ok_or_else(|| name_text(&ty_text));
    let n = ty.as_ref().ok().map(|t| t.n_nodes());
    let elset = b.param("ELSET").map(name_text);
    let mut added = Vec::new();
    let mut i = 0;
    while i < b.data.len() {
        let first = &b.data[i];
        let mut items: Vec<&str> = Vec::new();
        // An element goes on over lines ending with a comma (and, for a known type, until
        // its node count is reached).
        loop {
            let d = &b.data[i];
            items.extend(d.items.iter().map(String::as_str).filter(|t| !t.is_empty()));
            i += 1;
            let complete = match n {
                Some(n) => items.len() > n,
                None => !d.open,
            };
            if complete || i >= b.data.len() {
                break;
            }
        }
        let Some(lab) = items.first().and_then(|t| label(t)) else {
            return Err(deck.err(
                first.at,
                format!(
                    "*ELEMENT: `{}` is not an element label",
                    shorten(items.first().copied().unwrap_or(""))
                ),
            ));
        };
        if let Some(n) = n {
            if items.len() != n + 1 {
                return Err(deck.err(
                    first.at,
                    format!(
                        "*ELEMENT {lab} ({}): {} node labels, expected {n}",
                        name_text(&ty_text),
                        items.len() - 1
                    ),
                ));
            }
        }
        let mut nodes = Vec::with_capacity(items.len() - 1);
        for t in &items[1..] {
            nodes.push(label(t).ok_or_else(|| {
                deck.err(
                    first.at,
                    format!("*ELEMENT {lab}: `{}` is not a node label", shorten(t)),
                )
            })?);
        }
        if let Some(&j) = s.elem_index.get(&lab) {
            return Err(deck.err(
                first.at,
                format!(
                    "*ELEMENT {lab}: defined twice (first at {})",
                    deck.at(s.elements[j].at)
                ),
            ));
        }
        s.elem_index.insert(lab, s.elements.len());
        s.elements.push(ElemDef {
            label: lab,
            ty: ty.clone(),
            nodes,
            elset: elset.clone(),
            at: first.at,
        });
        added.push(lab);
    }
    if let Some(e) = b.param("ELSET") {
        let set = s.elsets.entry(name_key(e)).or_insert_with(|| SetDef {
            name: name_text(e),
            members: Vec::new(),
        });
        set.members
            .extend(added.into_iter().map(|l| (Scope::Own, l)));
    }
    Ok(())
}

fn add_instance(m: &mut Model, deck: &Deck, b: &Block) -> Result<(), MeshError> {
    let name = required(deck, b, "NAME")?;
    let key = name_key(&name);
    let part_name = required(deck, b, "PART")?;
    let Some(&part) = m.part_index.get(&name_key(&part_name)) else {
        return Err(deck.err(
            b.at,
            format!(
                "*INSTANCE {}: PART={}, which no *PART before it defines (parts: {})",
                name_text(&name),
                name_text(&part_name),
                list(m.parts.iter().map(|p| p.name.as_str()))
            ),
        ));
    };
    if m.instance_index.contains_key(&key) {
        return Err(deck.err(
            b.at,
            format!("*INSTANCE {}: defined twice", name_text(&name)),
        ));
    }
    let nums = |k: usize, want: usize| -> Result<Vec<f64>, MeshError> {
        let d = &b.data[k];
        let v: Vec<f64> = d
            .items
            .iter()
            .filter(|t| !t.is_empty())
            .map(|t| {
                real(t).ok_or_else(|| {
                    deck.err(
                        d.at,
                        format!(
                            "*INSTANCE {}: `{}` is not a number",
                            name_text(&name),
                            shorten(t)
                        ),
                    )
                })
            })
            .collect::<Result<_, _>>()?;
        if v.len() != want {
            return Err(deck.err(
                d.at,
                format!(
                    "*INSTANCE {}: {} values, expected {want}",
                    name_text(&name),
                    v.len()
                ),
            ));
        }
        Ok(v)
    };
    if b.data.len() > 2 {
        return Err(deck.err(
            b.data[2].at,
            format!(
                "*INSTANCE {}: at most two data lines (translation, rotation)",
                name_text(&name)
            ),
        ));
    }
    let t = if b.data.is_empty() {
        vec![0.0; 3]
    } else {
        nums(0, 3)?
    };
    let t = [t[0], t[1], t[2]];
    let (rot, shift) = if b.data.len() == 2 {
        let r = nums(1, 7)?;
        let (a, bb) = ([r[0], r[1], r[2]], [r[3], r[4], r[5]]);
        let Some(rot) = rotation(a, bb, r[6]) else {
            return Err(deck.err(
                b.data[1].at,
                format!(
                    "*INSTANCE {}: the rotation axis points a and b coincide",
                    name_text(&name)
                ),
            ));
        };
        // Translation first, then the rotation about the axis through a:
        // x' = a + R (x + t − a) = R x + a + R (t − a).
        let d = [t[0] - a[0], t[1] - a[1], t[2] - a[2]];
        let rd = [0, 1, 2].map(|i| (0..3).map(|k| rot[i][k] * d[k]).sum::<f64>());
        (rot, [a[0] + rd[0], a[1] + rd[1], a[2] + rd[2]])
    } else {
        ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], t)
    };
    m.instances.push(InstanceDef {
        name: name_text(&name),
        part,
        rot,
        shift,
    });
    m.instance_index.insert(key, m.instances.len() - 1);
    Ok(())
}

/// The rotation by `deg` degrees about the axis from `a` to `b` (right hand), as a matrix
/// (Rodrigues); None when a = b.
pub(crate) fn rotation(a: [f64; 3], b: [f64; 3], deg: f64) -> Option<[[f64; 3]; 3]> {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    let k = d.map(|v| v / n);
    let (s, c) = deg.to_radians().sin_cos();
    let mut r = [[0.0; 3]; 3];
    let kx = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            let id = if i == j { 1.0 } else { 0.0 };
            r[i][j] = c * id + s * kx[i][j] + (1.0 - c) * k[i] * k[j];
        }
    }
    Some(r)
}

pub(crate) fn list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let v: Vec<&str> = names.collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}
