//! Single-point constraints: SPC, SPC1 and SPCADD sets, and GRID's permanent constraints PS,
//! as fixed (grid, global component) pairs.
//!
//! Which set applies: the geometry's `spc` option (0: none); else the case control's
//! `SPC = n` (all subcases must agree); else the deck's only set. Components are in the grid's
//! displacement system CD: squeal holds global x, y, z, so a constrained component must lie
//! along a basic axis at the grid (or all three translations are held, which is the same in
//! any frame). Rotations (4, 5, 6) do not exist on solid grids and are left out, as Nastran's
//! AUTOSPC does.

use super::coords::Resolved;
use super::model::Bulk;
use crate::deck::Deck;
use crate::MeshError;
use std::collections::{BTreeMap, BTreeSet};

/// The constraints found: fixed (grid id, component 0..3), the grids of each set id, and notes.
#[derive(Debug, Default)]
pub(crate) struct Constraints {
    pub fixed: BTreeSet<(u64, usize)>,
    /// Set id → its grids (every SPC/SPC1 set of the deck, applied or not).
    pub sets: BTreeMap<u64, BTreeSet<u64>>,
    /// The set applied, if any.
    pub applied: Option<u64>,
}

/// Chooses the set, expands SPCADD, checks every grid and maps the components.
pub(crate) fn constraints(
    bulk: &Bulk,
    deck: &Deck,
    resolved: &Resolved,
    chosen: Option<u64>,
    notes: &mut Vec<String>,
) -> Result<Constraints, MeshError> {
    let mut out = Constraints::default();
    let ids = sorted_ids(resolved);
    // The grids of each entry (a THRU range: those that exist in it).
    let mut grids_of: Vec<Vec<u64>> = Vec::with_capacity(bulk.spcs.len());
    let mut by_sid: BTreeMap<u64, Vec<usize>> = BTreeMap::new();
    for (k, e) in bulk.spcs.iter().enumerate() {
        let g = existing(&ids, e.first, e.last);
        if g.is_empty() || (!e.range && g.len() != 1) {
            let what = if e.range {
                format!("no GRID between {} and {}", e.first, e.last)
            } else {
                format!("GRID {}, which no GRID card defines", e.first)
            };
            return Err(deck.err(e.at, format!("{} {}: {what}", e.card, e.sid)));
        }
        by_sid.entry(e.sid).or_default().push(k);
        out.sets.entry(e.sid).or_default().extend(g.iter().copied());
        grids_of.push(g.to_vec());
    }
    for (sid, add) in &bulk.spcadds {
        if by_sid.contains_key(sid) {
            return Err(deck.err(
                add.at,
                format!("SPCADD {sid}: set id {sid} is also an SPC/SPC1 set"),
            ));
        }
    }
    let all: BTreeSet<u64> = by_sid.keys().chain(bulk.spcadds.keys()).copied().collect();
    let list = || {
        if all.is_empty() {
            "none".to_string()
        } else {
            all.iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    let sid = match chosen {
        Some(0) => None,
        Some(s) => {
            if !all.contains(&s) {
                return Err(MeshError::Input {
                    file: deck.files[0].clone(),
                    message: format!(
                        "`spc = {s}`: the deck has no SPC, SPC1 or SPCADD set {s} (it has: {})",
                        list()
                    ),
                });
            }
            Some(s)
        }
        None => {
            let asked: BTreeSet<u64> = bulk.case.spc.iter().map(|(s, _)| *s).collect();
            match asked.len() {
                0 => {
                    // Sets referenced by an SPCADD are parts of it, not choices.
                    let roots: Vec<u64> = all
                        .iter()
                        .copied()
                        .filter(|s| !bulk.spcadds.values().any(|a| a.sets.contains(s)))
                        .collect();
                    match roots.len() {
                        0 => None,
                        1 => {
                            notes.push(format!(
                                "SPC set {} applied: the deck's only constraint set (`spc = 0` \
                                 in the geometry leaves it out)",
                                roots[0]
                            ));
                            Some(roots[0])
                        }
                        _ => {
                            return Err(MeshError::Input {
                                file: deck.files[0].clone(),
                                message: format!(
                                    "the deck has several SPC sets ({}) and no case control \
                                     `SPC = n`: choose one with `spc` in the component's \
                                     geometry (0: none)",
                                    list()
                                ),
                            })
                        }
                    }
                }
                1 => {
                    let s = *asked.iter().next().unwrap_or(&0);
                    let at = bulk.case.spc[0].1;
                    if !all.contains(&s) {
                        return Err(deck.err(
                            at,
                            format!(
                                "case control `SPC = {s}`: the bulk data has no such set (it has: \
                                 {})",
                                list()
                            ),
                        ));
                    }
                    Some(s)
                }
                _ => {
                    return Err(deck.err(
                        bulk.case.spc[1].1,
                        format!(
                            "the subcases select different SPC sets ({}); set `spc` in the \
                             component's geometry",
                            asked
                                .iter()
                                .map(u64::to_string)
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ))
                }
            }
        }
    };
    out.applied = sid;
    let mut rotations = 0usize;
    if let Some(sid) = sid {
        let mut sids = Vec::new();
        expand(bulk, deck, sid, &mut sids, 0)?;
        for s in sids {
            for &k in by_sid.get(&s).into_iter().flatten() {
                let e = &bulk.spcs[k];
                for &g in &grids_of[k] {
                    add(
                        &mut out.fixed,
                        bulk,
                        deck,
                        resolved,
                        g,
                        &e.comps,
                        &mut rotations,
                        || format!("{} {}", e.card, e.sid),
                        e.at,
                    )?;
                }
            }
        }
    }
    for g in &bulk.grids {
        if !g.ps.is_empty() {
            add(
                &mut out.fixed,
                bulk,
                deck,
                resolved,
                g.id,
                &g.ps,
                &mut rotations,
                || format!("GRID {} PS", g.id),
                g.at,
            )?;
        }
    }
    if rotations > 0 {
        notes.push(format!(
            "{rotations} constrained rotational components (4, 5, 6) left out: solid grids have \
             no rotations"
        ));
    }
    Ok(out)
}

/// The SPC/SPC1 set ids that `sid` stands for (itself, or an SPCADD's members).
fn expand(
    bulk: &Bulk,
    deck: &Deck,
    sid: u64,
    out: &mut Vec<u64>,
    depth: usize,
) -> Result<(), MeshError> {
    match bulk.spcadds.get(&sid) {
        None => out.push(sid),
        Some(add) => {
            if depth > 8 {
                return Err(deck.err(
                    add.at,
                    format!("SPCADD {sid}: sets nest too deeply (a cycle?)"),
                ));
            }
            for &s in &add.sets {
                let known = bulk.spcs.iter().any(|e| e.sid == s) || bulk.spcadds.contains_key(&s);
                if !known {
                    return Err(deck.err(
                        add.at,
                        format!("SPCADD {sid}: set {s}, which no SPC, SPC1 or SPCADD defines"),
                    ));
                }
                expand(bulk, deck, s, out, depth + 1)?;
            }
        }
    }
    Ok(())
}

/// Adds the components `comps` (1..6, in the grid's CD system) of grid `id` as global ones.
fn add(
    fixed: &mut BTreeSet<(u64, usize)>,
    bulk: &Bulk,
    deck: &Deck,
    resolved: &Resolved,
    id: u64,
    comps: &[u8],
    rotations: &mut usize,
    what: impl Fn() -> String,
    at: crate::deck::Loc,
) -> Result<(), MeshError> {
    let (gi, x) = resolved.grids[&id];
    let cd = bulk.grids[gi].cd;
    let trans: Vec<usize> = comps
        .iter()
        .filter(|&&c| c <= 3)
        .map(|&c| c as usize - 1)
        .collect();
    *rotations += comps.len() - trans.len();
    if cd == 0 || trans.len() == 3 {
        fixed.extend(trans.iter().map(|&k| (id, k)));
        return Ok(());
    }
    let Some(sys) = resolved.systems.get(&cd) else {
        return Err(deck.err(
            bulk.grids[gi].at,
            format!("GRID {id}: CD = {cd}, which no coordinate card defines"),
        ));
    };
    let axes = sys.axes_at(x);
    for &j in &trans {
        let k = axes.and_then(|a| (0..3).find(|&k| a[j][k].abs() >= 1.0 - 1e-9));
        match k {
            Some(k) => {
                fixed.insert((id, k));
            }
            None => {
                return Err(deck.err(
                    at,
                    format!(
                        "{}: component {} of GRID {id} is along its CD = {cd} axis {}, not a \
                         basic axis; squeal holds global x, y, z only (hold all of 123, or \
                         constrain along basic axes)",
                        what(),
                        j + 1,
                        axes.map(|a| format!("{:?}", a[j])).unwrap_or(
                            "(undefined at the \
                             system's axis)"
                                .into()
                        )
                    ),
                ))
            }
        }
    }
    Ok(())
}

/// Every grid id, sorted.
pub(crate) fn sorted_ids(resolved: &Resolved) -> Vec<u64> {
    let mut ids: Vec<u64> = resolved.grids.keys().copied().collect();
    ids.sort_unstable();
    ids
}

/// The ids of `ids` (sorted) in `first..=last`.
pub(crate) fn existing(ids: &[u64], first: u64, last: u64) -> &[u64] {
    let a = ids.partition_point(|&x| x < first);
    let b = ids.partition_point(|&x| x <= last);
    &ids[a..b.max(a)]
}
