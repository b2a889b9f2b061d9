//! Global grid ids: coincident nodes of different components merged (superelement joints),
//! except the contact-face nodes of a pad/rotor pair, which stay distinct (they become gaps).

use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use squeal_meshes::Mesh;
use std::collections::HashMap;

use squeal_solver::Real;

/// One global grid point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridInfo {
    /// Grid id: `(component index + 1) · base + node tag` of its first component.
    pub grid: u64,
    pub coords: [Real; 3],
    /// (component name, node tag) of every mesh node merged into this grid.
    pub members: Vec<(String, u64)>,
}

/// The merged grids of all components.
#[derive(Debug, Clone)]
pub struct Grids {
    pub grids: Vec<GridInfo>,
    /// `grid_of[c][node]` = grid id of node `node` of component `c`.
    pub grid_of: Vec<Vec<u64>>,
    /// `shared[c][node]`: the node's grid is also a node of another component.
    pub shared: Vec<Vec<bool>>,
    /// Id base: grid = (c + 1)·base + tag.
    pub base: u64,
}

impl Grids {
    /// Index of grid id → position in `grids`.
    pub fn index(&self) -> HashMap<u64, usize> {
        self.grids
            .iter()
            .enumerate()
            .map(|(i, g)| (g.grid, i))
            .collect()
    }
}

fn cell(x: &[Real; 3], h: Real) -> (i64, i64, i64) {
    (
        (x[0] / h).floor() as i64,
        (x[1] / h).floor() as i64,
        (x[2] / h).floor() as i64,
    )
}

/// Merges coincident nodes across components within `tol` with a spatial hash (cells of size
/// `tol`, 27 neighbours searched). Nodes of one component never merge with each other; a
/// node on a pair's pad face never merges with a node on the same pair's rotor face.
pub fn merge(scene: &Scene, meshes: &[Mesh], tol: Real) -> Grids {
    let names: Vec<&str> = scene.components.iter().map(|c| c.name.as_str()).collect();
    let max_tag = meshes
        .iter()
        .flat_map(|m| m.node_tags.iter().copied())
        .max()
        .unwrap_or(0);
    let mut base: u64 = 100_000;
    while base <= max_tag {
        base *= 10;
    }
    // Contact-face membership: on_face[c][pair] = flags of nodes of component c on the pair's
    // face. The pairs are the `[[contact]]` pairs, then the `[[ties]]` between components:
    // nodes on both faces of one are never merged (a tie's slave node coinciding with a
    // master node is tied, not shared, so that the mortar tie stays exact at it).
    let pairs: Vec<[(&str, &str); 2]> = scene
        .contact
        .iter()
        .map(|p| {
            [
                (p.pad.as_str(), p.pad_faces.as_str()),
                (p.rotor.as_str(), p.rotor_faces.as_str()),
            ]
        })
        .chain(scene.ties.iter().filter(|t| !t.inside()).map(|t| {
            [
                (t.a.component.as_str(), t.a.faces.as_str()),
                (t.b.component.as_str(), t.b.faces.as_str()),
            ]
        }))
        .collect();
    let mut on_face: Vec<Vec<Option<Vec<bool>>>> = vec![vec![None; pairs.len()]; meshes.len()];
    for (p, pair) in pairs.iter().enumerate() {
        for (comp, set) in pair {
            if let Some(c) = names.iter().position(|n| n == comp) {
                let mut flags = vec![false; meshes[c].nodes.len()];
                if let Some(nodes) = meshes[c].node_sets.get(*set) {
                    nodes.iter().for_each(|&n| flags[n] = true);
                }
                on_face[c][p] = Some(flags);
            }
        }
    }
    let pair_between = |a: usize, b: usize| -> Vec<usize> {
        pairs
            .iter()
            .enumerate()
            .filter(|(_, p)| {
                (p[0].0 == names[a] && p[1].0 == names[b])
                    || (p[0].0 == names[b] && p[1].0 == names[a])
            })
            .map(|(i, _)| i)
            .collect()
    };
    let mut grids: Vec<GridInfo> = Vec::new();
    let mut members: Vec<Vec<(usize, usize)>> = Vec::new();
    let mut hash: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    let mut grid_of = Vec::with_capacity(meshes.len());
    for (c, mesh) in meshes.iter().enumerate() {
        let mut ids = Vec::with_capacity(mesh.nodes.len());
        for (node, x) in mesh.nodes.iter().enumerate() {
            let (i, j, k) = cell(x, tol);
            let mut found = None;
            'search: for di in -1..=1 {
                for dj in -1..=1 {
                    for dk in -1..=1 {
                        let Some(cands) = hash.get(&(i + di, j + dj, k + dk)) else {
                            continue;
                        };
                        for &g in cands {
                            let y = grids[g].coords;
                            let d2 = (0..3).map(|a| (x[a] - y[a]).powi(2)).sum::<Real>();
                            if d2 > tol * tol || members[g].iter().any(|&(cc, _)| cc == c) {
                                continue;
                            }
                            let excluded = members[g].iter().any(|&(cb, nb)| {
                                pair_between(c, cb).into_iter().any(|p| {
                                    let a = on_face[c][p].as_ref().is_some_and(|f| f[node]);
                                    let b = on_face[cb][p].as_ref().is_some_and(|f| f[nb]);
                                    a && b
                                })
                            });
                            if !excluded {
                                found = Some(g);
                                break 'search;
                            }
                        }
                    }
                }
            }
            let tag = mesh.node_tags.get(node).copied().unwrap_or(node as u64 + 1);
            let g = match found {
                Some(g) => {
                    grids[g].members.push((names[c].to_string(), tag));
                    members[g].push((c, node));
                    g
                }
                None => {
                    grids.push(GridInfo {
                        grid: (c as u64 + 1) * base + tag,
                        coords: *x,
                        members: vec![(names[c].to_string(), tag)],
                    });
                    members.push(vec![(c, node)]);
                    hash.entry((i, j, k)).or_default().push(grids.len() - 1);
                    grids.len() - 1
                }
            };
            ids.push(g);
        }
        grid_of.push(ids);
    }
    let shared = grid_of
        .iter()
        .map(|ids| ids.iter().map(|&g| members[g].len() > 1).collect())
        .collect();
    let grid_of = grid_of
        .into_iter()
        .map(|ids| ids.into_iter().map(|g| grids[g].grid).collect())
        .collect();
    Grids {
        grids,
        grid_of,
        shared,
        base,
    }
}
