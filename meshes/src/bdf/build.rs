//! Bulk data → [`Mesh`]: the solids of the selected property ids in squeal's node order, grid
//! positions in basic, one block and one node set `pid_<id>` per property, shells as face
//! sets, SET1 and SPC sets as node sets, the applied constraints as fixed DOFs.

use super::coords;
use super::materials;
use super::model::{Bulk, SolidCard};
use super::spc;
use super::BdfOptions;
use crate::deck::Deck;
use crate::import::{Builder, RawCell, ReadReport, Unsupported};
use crate::{CellKind, Mesh, MeshError};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// squeal node k = Nastran grid `perm[k]` (0-based), for each solid with mid-edge nodes.
/// CHEXA: G13–G16 are the vertical edges (squeal 16–19), G17–G20 the top ones (12–15);
/// CPENTA: G10–G12 vertical (squeal 12–14), G13–G15 top (9–11). CTETRA and CPYRAM list
/// their mid-edge nodes in squeal's order.
const CHEXA20: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15,
];
const CPENTA15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14, 9, 10, 11];

fn kind_of(card: SolidCard, n: usize) -> CellKind {
    let quadratic = n > card.counts().0;
    match (card, quadratic) {
        (SolidCard::Chexa, false) => CellKind::Hex8,
        (SolidCard::Chexa, true) => CellKind::Hex20,
        (SolidCard::Cpenta, false) => CellKind::Wedge6,
        (SolidCard::Cpenta, true) => CellKind::Wedge15,
        (SolidCard::Ctetra, false) => CellKind::Tet4,
        (SolidCard::Ctetra, true) => CellKind::Tet10,
        (SolidCard::Cpyram, false) => CellKind::Pyramid5,
        (SolidCard::Cpyram, true) => CellKind::Pyramid13,
    }
}

/// Builds the mesh and the report.
pub(crate) fn build(
    bulk: Bulk,
    deck: &Deck,
    opts: &BdfOptions,
) -> Result<(Mesh, ReadReport), MeshError> {
    let resolved = coords::resolve(&bulk, deck)?;
    let mut notes = Vec::new();
    let mut b = Builder::default();
    // Builder node index of every grid id, in file order.
    let mut node_of: HashMap<u64, usize> = HashMap::with_capacity(resolved.grids.len());
    for g in &bulk.grids {
        if node_of.contains_key(&g.id) {
            continue;
        }
        node_of.insert(g.id, b.nodes.len());
        b.nodes.push(resolved.grids[&g.id].1);
        b.tags.push(g.id);
    }
    check_element_ids(&bulk, deck)?;
    let selected = select(&bulk, deck, opts)?;
    for s in bulk.solids.iter().filter(|s| selected.contains(&s.pid)) {
        if !bulk.psolids.contains_key(&s.pid) {
            let shell = if bulk.pshells.contains_key(&s.pid) {
                " (it is a PSHELL)"
            } else {
                ""
            };
            return Err(deck.err(
                s.at,
                format!(
                    "{} {}: PID = {}, which no PSOLID card defines{shell}",
                    s.card.name(),
                    s.id,
                    s.pid
                ),
            ));
        }
        let kind = kind_of(s.card, s.grids.len());
        let mut nodes = Vec::with_capacity(s.grids.len());
        for (k, g) in s.grids.iter().enumerate() {
            let Some(&i) = node_of.get(g) else {
                return Err(deck.err(
                    s.at,
                    format!(
                        "{} {}: G{} = {g}, which no GRID card defines",
                        s.card.name(),
                        s.id,
                        k + 1
                    ),
                ));
            };
            nodes.push(i);
        }
        let nodes = match kind {
            CellKind::Hex20 => CHEXA20.iter().map(|&k| nodes[k]).collect(),
            CellKind::Wedge15 => CPENTA15.iter().map(|&k| nodes[k]).collect(),
            _ => nodes,
        };
        b.cells.push(RawCell {
            kind,
            nodes,
            tag: s.id,
            block: Some(format!("pid_{}", s.pid)),
            file: deck.file(s.at).to_string(),
            line: s.at.line as usize,
            what: format!("{} {}", s.card.name(), s.id),
        });
    }
    b.orient()?;

    let mut sections = BTreeMap::new();
    for pid in &selected {
        let p = &bulk.psolids[pid];
        sections.insert(
            format!("pid_{pid}"),
            materials::section(&bulk, deck, &resolved, p, &mut notes)?,
        );
    }
    let mut node_sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for c in &b.cells {
        if let Some(name) = &c.block {
            node_sets
                .entry(name.clone())
                .or_default()
                .extend(c.nodes.iter().copied());
        }
    }
    let ids = spc::sorted_ids(&resolved);
    for (sid, set) in &bulk.set1 {
        let mut v = Vec::with_capacity(set.ids.len());
        for &(a, b, at) in &set.ids {
            let g = spc::existing(&ids, a, b);
            if g.is_empty() || (a == b && g.len() != 1) {
                let what = if a == b {
                    format!("{a} is not a GRID (squeal reads SET1 as grid sets)")
                } else {
                    format!("no GRID between {a} and {b}")
                };
                return Err(deck.err(at, format!("SET1 {sid}: {what}")));
            }
            v.extend(g.iter().map(|id| node_of[id]));
        }
        node_sets.insert(format!("set1_{sid}"), v);
    }
    let cons = spc::constraints(&bulk, deck, &resolved, opts.spc, &mut notes)?;
    for (sid, grids) in &cons.sets {
        node_sets.insert(
            format!("spc_{sid}"),
            grids.iter().map(|g| node_of[g]).collect(),
        );
    }
    let fixed: Vec<(usize, usize)> = cons.fixed.iter().map(|&(g, k)| (node_of[&g], k)).collect();
    let face_sets = shell_faces(&bulk, deck, &b, &node_of, &mut notes)?;

    let mut report = ReadReport {
        format: "nastran".into(),
        files: deck.files.clone(),
        ..Default::default()
    };
    report.counts.insert("GRID".into(), node_of.len());
    for s in bulk.solids.iter().filter(|s| selected.contains(&s.pid)) {
        *report.counts.entry(s.card.name().into()).or_insert(0) += 1;
    }
    for s in &bulk.shells {
        *report.counts.entry(s.card.into()).or_insert(0) += 1;
    }
    report.counts.insert("fixed DOFs".into(), fixed.len());
    report.unsupported = bulk
        .unsupported
        .iter()
        .map(|(name, (count, at))| Unsupported {
            name: name.clone(),
            count: *count,
            first: deck.at(*at),
        })
        .collect();
    let unselected: BTreeSet<u64> = bulk
        .solids
        .iter()
        .map(|s| s.pid)
        .filter(|p| !selected.contains(p))
        .collect();
    if !unselected.is_empty() {
        notes.push(format!(
            "solid PIDs not selected (other components): {}",
            unselected
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    report.notes = notes;
    let mesh = b.finish(node_sets, face_sets, sections, fixed);
    Ok((mesh, report))
}

/// Element ids are unique over every element card read.
fn check_element_ids(bulk: &Bulk, deck: &Deck) -> Result<(), MeshError> {
    let mut seen: HashMap<u64, crate::deck::Loc> = HashMap::new();
    let all = bulk
        .solids
        .iter()
        .map(|s| (s.id, s.at))
        .chain(bulk.shells.iter().map(|s| (s.id, s.at)));
    for (id, at) in all {
        if let Some(first) = seen.insert(id, at) {
            return Err(deck.err(
                at,
                format!("element id {id} is also used at {}", deck.at(first)),
            ));
        }
    }
    Ok(())
}

/// The solid PIDs read: `opts.pids`, or every solid PID.
fn select(bulk: &Bulk, deck: &Deck, opts: &BdfOptions) -> Result<BTreeSet<u64>, MeshError> {
    let present: BTreeSet<u64> = bulk.solids.iter().map(|s| s.pid).collect();
    if present.is_empty() {
        return Err(MeshError::Input {
            file: deck.files[0].clone(),
            message: "no solid elements (CHEXA, CPENTA, CTETRA, CPYRAM)".into(),
        });
    }
    if opts.pids.is_empty() {
        return Ok(present);
    }
    for p in &opts.pids {
        if !present.contains(p) {
            return Err(MeshError::Input {
                file: deck.files[0].clone(),
                message: format!(
                    "`pids`: no solid element has PID {p} (the deck's solid PIDs: {})",
                    present
                        .iter()
                        .map(u64::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    Ok(opts.pids.iter().copied().collect())
}

type FaceSets = BTreeMap<String, Vec<(CellKind, Vec<usize>, u64)>>;

/// Shells whose corners are a face of a selected solid become that face (outward from the
/// solid, with its mid-edge nodes) in the face set `pid_<shell PID>`; shells entirely
/// outside the selected solids are left to the other components.
fn shell_faces(
    bulk: &Bulk,
    deck: &Deck,
    b: &Builder,
    node_of: &HashMap<u64, usize>,
    notes: &mut Vec<String>,
) -> Result<FaceSets, MeshError> {
    let mut out: FaceSets = BTreeMap::new();
    if bulk.shells.is_empty() {
        return Ok(out);
    }
    // Sorted corner nodes of every cell face → the cell.
    let mut cell_of: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut used = vec![false; b.nodes.len()];
    for (ci, c) in b.cells.iter().enumerate() {
        c.nodes.iter().for_each(|&i| used[i] = true);
        for f in c.kind.faces() {
            let mut key: Vec<usize> = f.nodes[..f.kind.n_corners()]
                .iter()
                .map(|&k| c.nodes[k])
                .collect();
            key.sort_unstable();
            cell_of.entry(key).or_insert(ci);
        }
    }
    // Corner sets of the faces of every solid of the deck (selected or not), built when a
    // shell is not on a selected solid.
    let all_faces = std::cell::OnceCell::new();
    let other_faces = || {
        all_faces.get_or_init(|| {
            let mut set: std::collections::HashSet<Vec<usize>> = Default::default();
            for s in &bulk.solids {
                let Some(nodes) = s
                    .grids
                    .iter()
                    .map(|g| node_of.get(g).copied())
                    .collect::<Option<Vec<usize>>>()
                else {
                    continue;
                };
                let kind = kind_of(s.card, s.grids.len()).linear();
                for f in kind.faces() {
                    let mut key: Vec<usize> = f.nodes.iter().map(|&k| nodes[k]).collect();
                    key.sort_unstable();
                    set.insert(key);
                }
            }
            set
        })
    };
    let mut structural: BTreeMap<u64, usize> = BTreeMap::new();
    let mut promoted = 0usize;
    for s in &bulk.shells {
        let mut nodes = Vec::with_capacity(s.grids.len());
        for (k, g) in s.grids.iter().enumerate() {
            match node_of.get(g) {
                Some(&i) => nodes.push(i),
                None => {
                    return Err(deck.err(
                        s.at,
                        format!(
                            "{} {}: G{} = {g}, which no GRID card defines",
                            s.card,
                            s.id,
                            k + 1
                        ),
                    ))
                }
            }
        }
        let corners = if s.card.starts_with("CQUAD") { 4 } else { 3 };
        let mut key = nodes[..corners].to_vec();
        key.sort_unstable();
        let Some(&ci) = cell_of.get(&key) else {
            // A face of a solid of another component, or on no solid at all (an error).
            if nodes.iter().all(|&i| !used[i]) || other_faces().contains(&key) {
                continue;
            }
            return Err(deck.err(
                s.at,
                format!(
                    "{} {} (PID {}) is not a face of any selected solid element: squeal reads \
                     shells as faces of the solids (friction, load and fixed faces)",
                    s.card, s.id, s.pid
                ),
            ));
        };
        let Some((kind, face)) = b.face_with_corners(ci, &nodes[..corners]) else {
            continue;
        };
        if nodes.len() > corners && !kind.is_quadratic() {
            return Err(deck.err(
                s.at,
                format!(
                    "{} {}: a quadratic shell on the linear solid {}",
                    s.card, s.id, b.cells[ci].what
                ),
            ));
        }
        if nodes.len() > corners {
            // Its mid-edge grids must be the solid's.
            let mut a: Vec<usize> = nodes[corners..].to_vec();
            let mut c: Vec<usize> = face[kind.n_corners()..].to_vec();
            a.sort_unstable();
            c.sort_unstable();
            if a != c {
                return Err(deck.err(
                    s.at,
                    format!(
                        "{} {}: its mid-edge grids are not those of {}'s face",
                        s.card, s.id, b.cells[ci].what
                    ),
                ));
            }
        } else if kind.is_quadratic() {
            promoted += 1;
        }
        if bulk.pshells.get(&s.pid).is_some_and(|p| p.structural) {
            *structural.entry(s.pid).or_insert(0) += 1;
        }
        out.entry(format!("pid_{}", s.pid))
            .or_default()
            .push((kind, face, s.id));
    }
    for (pid, n) in structural {
        notes.push(format!(
            "{n} shell elements of PSHELL {pid} (with a material and a thickness) read as the \
             face set pid_{pid} only: squeal has no shell elements, their stiffness and mass \
             are not in the model"
        ));
    }
    if promoted > 0 {
        notes.push(format!(
            "{promoted} linear shells on quadratic solids read as the solids' quadratic faces"
        ));
    }
    Ok(out)
}
