//! *NSET, *ELSET (with GENERATE, ELSET=, INSTANCE=), *SURFACE and *BOUNDARY, resolved in
//! file order against what is defined before them (as Abaqus does).
//!
//! A set item is a label, a set name of the same scope, or at the assembly level
//! `instance.set` / `instance.label`. A label that no *NODE / *ELEMENT defines, or a name
//! that no set has, is an error naming the file, line and item: a set never names nothing.

use super::keywords::{label, name_key, name_text, Block};
use super::model::{required, BcDef, BcTarget, Model, Scope, Scoped, SetDef, SurfDef};
use crate::deck::{shorten, Deck};
use crate::MeshError;
use std::collections::HashMap;

/// Instance key → (instance index, part index).
pub(crate) type Instances = HashMap<String, (usize, usize)>;

/// Largest GENERATE range read.
const MAX_RANGE: u64 = 10_000_000;

/// Which entities a set holds.
#[derive(Clone, Copy, PartialEq)]
enum What {
    Nodes,
    Elements,
}

/// The scope an item refers to: `s` itself, or an instance's part.
struct View<'a> {
    own: &'a Scoped,
    parts: &'a [Scoped],
    instances: &'a Instances,
}

impl View<'_> {
    fn scoped(&self, scope: Scope) -> &Scoped {
        match scope {
            Scope::Own => self.own,
            Scope::Instance(i) => {
                let part = self
                    .instances
                    .values()
                    .find(|(k, _)| *k == i)
                    .map(|&(_, p)| p)
                    .unwrap_or(0);
                &self.parts[part]
            }
        }
    }

    /// `instance.rest` at the assembly level: (scope, rest).
    fn split<'t>(&self, item: &'t str) -> (Scope, &'t str) {
        if let Some((inst, rest)) = item.split_once('.') {
            if let Some(&(i, _)) = self.instances.get(&name_key(inst)) {
                return (Scope::Instance(i), rest);
            }
        }
        (Scope::Own, item)
    }

    fn has(&self, scope: Scope, what: What, lab: u64) -> bool {
        let s = self.scoped(scope);
        match what {
            What::Nodes => s.node_index.contains_key(&lab),
            What::Elements => s.elem_index.contains_key(&lab),
        }
    }

    fn set(&self, scope: Scope, what: What, name: &str) -> Option<&SetDef> {
        let s = self.scoped(scope);
        match what {
            What::Nodes => s.nsets.get(&name_key(name)),
            What::Elements => s.elsets.get(&name_key(name)),
        }
    }
}

/// The scope of an INSTANCE= parameter (assembly level only).
fn instance_param(deck: &Deck, b: &Block, v: &View) -> Result<Option<Scope>, MeshError> {
    let Some(name) = b.param("INSTANCE") else {
        return Ok(None);
    };
    match v.instances.get(&name_key(name)) {
        Some(&(i, _)) => Ok(Some(Scope::Instance(i))),
        None => Err(deck.err(
            b.at,
            format!(
                "*{}: INSTANCE={}, which no *INSTANCE before it defines",
                b.keyword,
                name_text(name)
            ),
        )),
    }
}

/// Members of a set definition block.
fn members(
    deck: &Deck,
    b: &Block,
    v: &View,
    what: What,
    set_name: &str,
) -> Result<Vec<(Scope, u64)>, MeshError> {
    let fixed = instance_param(deck, b, v)?;
    let mut out = Vec::new();
    let who = format!("*{} {}", b.keyword, name_text(set_name));
    if what == What::Nodes {
        if let Some(es) = b.param("ELSET") {
            // The nodes of the elements of an element set.
            let scope = fixed.unwrap_or(Scope::Own);
            let (scope, name) = match fixed {
                Some(_) => (scope, es),
                None => v.split(es),
            };
            let Some(set) = v.set(scope, What::Elements, name) else {
                return Err(deck.err(
                    b.at,
                    format!(
                        "{who}: ELSET={}, which no *ELSET before it defines",
                        name_text(es)
                    ),
                ));
            };
            for &(sc, e) in &set.members {
                let s = v.scoped(sc);
                if let Some(&j) = s.elem_index.get(&e) {
                    out.extend(s.elements[j].nodes.iter().map(|&n| (sc, n)));
                }
            }
            return Ok(out);
        }
    }
    let generate = b.flag("GENERATE");
    for d in &b.data {
        let items: Vec<&str> = d
            .items
            .iter()
            .map(String::as_str)
            .filter(|t| !t.is_empty())
            .collect();
        if generate {
            if items.len() < 2 || items.len() > 3 {
                return Err(deck.err(
                    d.at,
                    format!("{who}, GENERATE: expected `first, last[, increment]`"),
                ));
            }
            let nums: Vec<u64> = items
                .iter()
                .map(|t| {
                    label(t).ok_or_else(|| {
                        deck.err(
                            d.at,
                            format!("{who}, GENERATE: `{}` is not a positive label", shorten(t)),
                        )
                    })
                })
                .collect::<Result<_, _>>()?;
            let (a, z, inc) = (nums[0], nums[1], nums.get(2).copied().unwrap_or(1));
            if z < a || (z - a) / inc > MAX_RANGE {
                return Err(deck.err(
                    d.at,
                    format!("{who}, GENERATE: {a} to {z} by {inc} is not a range of at most {MAX_RANGE} labels"),
                ));
            }
            let scope = fixed.unwrap_or(Scope::Own);
            let before = out.len();
            let mut k = a;
            while k <= z {
                if v.has(scope, what, k) {
                    out.push((scope, k));
                }
                k += inc;
            }
            if out.len() == before {
                return Err(deck.err(
                    d.at,
                    format!("{who}, GENERATE: no {} between {a} and {z}", entity(what)),
                ));
            }
            continue;
        }
        for t in items {
            let (scope, rest) = match fixed {
                Some(s) => (s, t),
                None => v.split(t),
            };
            if let Some(lab) = label(rest) {
                if !v.has(scope, what, lab) {
                    return Err(deck.err(
                        d.at,
                        format!("{who}: {} {lab}, which is not defined", entity(what)),
                    ));
                }
                out.push((scope, lab));
            } else {
                let Some(set) = v.set(scope, what, rest) else {
                    return Err(deck.err(
                        d.at,
                        format!(
                            "{who}: `{}` is neither a {} label nor a set defined before it",
                            shorten(t),
                            entity(what)
                        ),
                    ));
                };
                out.extend(set.members.iter().map(|&(sc, l)| {
                    // A set of an instance's part: its members belong to that instance.
                    if scope == Scope::Own {
                        (sc, l)
                    } else {
                        (scope, l)
                    }
                }));
            }
        }
    }
    Ok(out)
}

fn entity(what: What) -> &'static str {
    match what {
        What::Nodes => "node",
        What::Elements => "element",
    }
}

fn add(map: &mut std::collections::BTreeMap<String, SetDef>, name: &str, m: Vec<(Scope, u64)>) {
    map.entry(name_key(name))
        .or_insert_with(|| SetDef {
            name: name_text(name),
            members: Vec::new(),
        })
        .members
        .extend(m);
}

/// *NSET.
pub(crate) fn nset(
    s: &mut Scoped,
    deck: &Deck,
    b: &Block,
    instances: &Instances,
    parts: &[Scoped],
) -> Result<(), MeshError> {
    let name = required(deck, b, "NSET")?;
    let v = View {
        own: s,
        parts,
        instances,
    };
    let m = members(deck, b, &v, What::Nodes, &name)?;
    add(&mut s.nsets, &name, m);
    Ok(())
}

/// *ELSET.
pub(crate) fn elset(
    s: &mut Scoped,
    deck: &Deck,
    b: &Block,
    instances: &Instances,
    parts: &[Scoped],
) -> Result<(), MeshError> {
    let name = required(deck, b, "ELSET")?;
    let v = View {
        own: s,
        parts,
        instances,
    };
    let m = members(deck, b, &v, What::Elements, &name)?;
    add(&mut s.elsets, &name, m);
    Ok(())
}

/// *SURFACE of TYPE=ELEMENT (faces) or NODE (nodes); false for other types (not read).
pub(crate) fn surface(
    s: &mut Scoped,
    deck: &Deck,
    b: &Block,
    instances: &Instances,
    parts: &[Scoped],
) -> Result<bool, MeshError> {
    let ty = b
        .param("TYPE")
        .map(|t| t.trim().to_ascii_uppercase())
        .unwrap_or_else(|| "ELEMENT".into());
    let node_based = match ty.as_str() {
        "ELEMENT" => false,
        "NODE" => true,
        _ => return Ok(false),
    };
    let name = required(deck, b, "NAME")?;
    let who = format!("*SURFACE {}", name_text(&name));
    let v = View {
        own: s,
        parts,
        instances,
    };
    let mut surf = SurfDef {
        name: name_text(&name),
        faces: Vec::new(),
        nodes: Vec::new(),
        at: b.at,
    };
    for d in &b.data {
        let Some(first) = d.items.first().filter(|t| !t.is_empty()) else {
            continue;
        };
        let (scope, rest) = v.split(first);
        let what = if node_based {
            What::Nodes
        } else {
            What::Elements
        };
        let refs: Vec<(Scope, u64)> = match label(rest) {
            Some(l) if v.has(scope, what, l) => vec![(scope, l)],
            Some(l) => {
                return Err(deck.err(
                    d.at,
                    format!("{who}: {} {l}, which is not defined", entity(what)),
                ))
            }
            None => match v.set(scope, what, rest) {
                Some(set) => set
                    .members
                    .iter()
                    .map(|&(sc, l)| {
                        if scope == Scope::Own {
                            (sc, l)
                        } else {
                            (scope, l)
                        }
                    })
                    .collect(),
                None => {
                    return Err(deck.err(
                        d.at,
                        format!(
                            "{who}: `{}` is neither a {} label nor a set defined before it",
                            shorten(first),
                            entity(what)
                        ),
                    ))
                }
            },
        };
        if node_based {
            surf.nodes.extend(refs);
            continue;
        }
        let face = match d.items.get(1).map(|t| t.trim().to_ascii_uppercase()) {
            None => None,
            Some(t) if t.is_empty() => None,
            Some(t) => {
                let k = t
                    .strip_prefix('S')
                    .and_then(|n| n.parse::<u8>().ok())
                    .filter(|k| (1..=6).contains(k));
                match k {
                    Some(k) => Some(k),
                    None => {
                        return Err(deck.err(
                            d.at,
                            format!(
                                "{who}: face `{}` is not S1 … S6 (solid element faces)",
                                shorten(&t)
                            ),
                        ))
                    }
                }
            }
        };
        surf.faces
            .extend(refs.into_iter().map(|(sc, e)| (sc, e, face, d.at)));
    }
    if surf.faces.is_empty() && surf.nodes.is_empty() {
        return Err(deck.err(b.at, format!("{who}: names no face or node")));
    }
    let key = name_key(&name);
    if let Some(old) = s.surfaces.get(&key) {
        return Err(deck.err(b.at, format!("{who}: also defined at {}", deck.at(old.at))));
    }
    s.surfaces.insert(key, surf);
    Ok(true)
}

/// *BOUNDARY data lines as zero-displacement conditions.
pub(crate) fn boundary(
    deck: &Deck,
    b: &Block,
    at_assembly: bool,
    m: &Model,
) -> Result<Vec<BcDef>, MeshError> {
    for p in ["TYPE", "USER", "SUBMODEL"] {
        let bad = match p {
            "TYPE" => b
                .param("TYPE")
                .is_some_and(|t| !t.trim().eq_ignore_ascii_case("DISPLACEMENT")),
            _ => b.flag(p),
        };
        if bad {
            return Err(deck.err(
                b.at,
                format!("*BOUNDARY, {p}: only zero displacements are read"),
            ));
        }
    }
    let mut out = Vec::new();
    for d in &b.data {
        let items: Vec<&str> = d.items.iter().map(String::as_str).collect();
        let Some(first) = items.first().filter(|t| !t.is_empty()) else {
            continue;
        };
        let (scope, rest) = match first.split_once('.') {
            Some((inst, rest)) if at_assembly => match m.instance_index.get(&name_key(inst)) {
                Some(&i) => (Scope::Instance(i), rest),
                None => (Scope::Own, *first),
            },
            _ => (Scope::Own, *first),
        };
        let target = match label(rest) {
            Some(l) => BcTarget::Node(l),
            None => BcTarget::Set(name_key(rest)),
        };
        let second = items
            .get(1)
            .map(|t| t.trim().to_ascii_uppercase())
            .unwrap_or_default();
        let dofs: Vec<u8> = match second.as_str() {
            "ENCASTRE" => vec![1, 2, 3, 4, 5, 6],
            "PINNED" => vec![1, 2, 3],
            "XSYMM" => vec![1, 5, 6],
            "YSYMM" => vec![2, 4, 6],
            "ZSYMM" => vec![3, 4, 5],
            "XASYMM" => vec![2, 3, 4],
            "YASYMM" => vec![1, 3, 5],
            "ZASYMM" => vec![1, 2, 6],
            t => {
                let dof = |s: &str| -> Option<u8> {
                    s.trim().parse::<u8>().ok().filter(|k| (1..=6).contains(k))
                };
                let Some(a) = dof(t) else {
                    return Err(deck.err(
                        d.at,
                        format!("*BOUNDARY: `{}` is not a degree of freedom 1..6 or a type (ENCASTRE, PINNED, XSYMM, …)", shorten(t)),
                    ));
                };
                let z = match items.get(2).map(|t| t.trim()).filter(|t| !t.is_empty()) {
                    None => a,
                    Some(t) => dof(t).filter(|&z| z >= a).ok_or_else(|| {
                        deck.err(
                            d.at,
                            format!("*BOUNDARY: last DOF `{}` is not in {a}..6", shorten(t)),
                        )
                    })?,
                };
                if let Some(t) = items.get(3).map(|t| t.trim()).filter(|t| !t.is_empty()) {
                    match super::keywords::real(t) {
                        Some(0.0) => {}
                        _ => {
                            return Err(deck.err(
                                d.at,
                                format!(
                                "*BOUNDARY: magnitude `{}`: squeal holds constrained DOFs at zero",
                                shorten(t)
                            ),
                            ))
                        }
                    }
                }
                (a..=z).collect()
            }
        };
        out.push(BcDef {
            scope,
            target,
            dofs,
            at: d.at,
        });
    }
    Ok(out)
}
