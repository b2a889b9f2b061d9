//! Bonded (glued) ties: the gaps of a pairing solved for the slave nodes, u_s = Σ_a w_a u_a in
//! every direction (a multi-point constraint that can be eliminated).

use super::GapSet;
use crate::{ContactError, NodeReport, Real};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

/// One slave node of a bonded tie as a combination of master nodes: u_s = Σ_a w_a u_a, the
/// same weights in x, y and z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BondRow {
    /// Slave node id.
    pub node: u64,
    /// Its coordinates.
    pub coords: [Real; 3],
    /// (master node id, weight), by node id; the weights sum to 1.
    pub masters: Vec<(u64, Real)>,
}

/// Weights within this distance of 0 are dropped.
const DROP: Real = 1e-14;

/// The explicit form u_s = P u_m of a bonded tie whose gaps were made by [`crate::tie_gaps`]
/// or [`crate::mortar_gaps`] (their normals, areas, friction data are not used): gap j says
/// Σ_k p_jk u_k = Σ_a W_ja u_a, p_jk its pad side ([`super::Gap::pad_terms`]: the node itself,
/// or on a quadratic mortar face the transformed value û_j) and W_ja its master weights; the
/// gaps are solved for the slave nodes in the order that leaves one unknown each (corners
/// before the mid-side nodes that refer to them). One row per slave node, in gap order (the
/// `joined` ones of [`bond_rows_joined`] left out).
///
/// # Errors
/// [`ContactError::Matching`] naming the slave nodes that cannot be solved for (a pad side
/// refers to a node with no gap of its own, e.g. an excluded corner) or that are also master
/// nodes of the tie (a chained tie, which elimination cannot order).
pub fn bond_rows(gaps: &GapSet) -> Result<Vec<BondRow>, ContactError> {
    bond_rows_joined(gaps, &[])
}

/// [`bond_rows`] when the slave nodes `joined` are already nodes of the master side (a node
/// shared by both meshes): each is its own master (row [(node, 1)]), its own gap is not
/// used, and the other gaps' pad sides may refer to it.
pub fn bond_rows_joined(gaps: &GapSet, joined: &[u64]) -> Result<Vec<BondRow>, ContactError> {
    let n = gaps.gaps.len();
    let joined: std::collections::HashSet<u64> = joined.iter().copied().collect();
    // Master terms of each gap.
    let masters: Vec<Vec<(u64, Real)>> = gaps
        .gaps
        .iter()
        .map(|g| match &g.tie {
            Some(t) => t
                .nodes
                .iter()
                .copied()
                .zip(t.weights.iter().copied())
                .collect(),
            None => vec![(g.rotor_node, 1.0)],
        })
        .collect();
    let sides: Vec<Vec<(u64, Real)>> = gaps
        .gaps
        .iter()
        .map(|g| match &g.pad_side {
            Some(p) => p
                .nodes
                .iter()
                .copied()
                .zip(p.weights.iter().copied())
                .collect(),
            None => vec![(g.pad_node, 1.0)],
        })
        .collect();
    let master_set: std::collections::HashSet<u64> =
        masters.iter().flatten().map(|&(m, _)| m).collect();
    let report = |ig: usize, reason: &str| NodeReport {
        id: gaps.gaps[ig].pad_node,
        coords: gaps.gaps[ig].coords,
        reason: reason.to_string(),
    };
    let chained: Vec<NodeReport> = (0..n)
        .filter(|&ig| {
            let node = gaps.gaps[ig].pad_node;
            master_set.contains(&node) && !joined.contains(&node)
        })
        .map(|ig| {
            report(
                ig,
                "slave node of a bonded tie is also one of its master nodes",
            )
        })
        .collect();
    if !chained.is_empty() {
        return Err(ContactError::Matching {
            tolerance: 0.0,
            nodes: chained,
        });
    }
    let mut known: HashMap<u64, BTreeMap<u64, Real>> = joined
        .iter()
        .map(|&j| (j, BTreeMap::from([(j, 1.0)])))
        .collect();
    let mut done: Vec<bool> = gaps
        .gaps
        .iter()
        .map(|g| joined.contains(&g.pad_node))
        .collect();
    loop {
        let mut progress = false;
        for ig in 0..n {
            if done[ig] {
                continue;
            }
            let unknown: Vec<&(u64, Real)> = sides[ig]
                .iter()
                .filter(|(k, w)| *w != 0.0 && !known.contains_key(k))
                .collect();
            if unknown.len() != 1 {
                continue;
            }
            let (node, p) = *unknown[0];
            // p u_node = Σ_a W_a u_a − Σ_{known k} p_k u_k.
            let mut row: BTreeMap<u64, Real> = BTreeMap::new();
            for &(a, w) in &masters[ig] {
                *row.entry(a).or_default() += w / p;
            }
            for &(k, w) in &sides[ig] {
                if k == node || w == 0.0 {
                    continue;
                }
                for (&a, &c) in &known[&k] {
                    *row.entry(a).or_default() -= w * c / p;
                }
            }
            row.retain(|_, w| w.abs() > DROP);
            known.insert(node, row);
            done[ig] = true;
            progress = true;
        }
        if !progress {
            break;
        }
    }
    let stuck: Vec<NodeReport> = (0..n)
        .filter(|&ig| !done[ig])
        .map(|ig| {
            report(
                ig,
                "its gap refers to slave nodes without a gap of their own (excluded?): the \
                 bonded tie cannot be solved for it",
            )
        })
        .collect();
    if !stuck.is_empty() {
        return Err(ContactError::Matching {
            tolerance: 0.0,
            nodes: stuck,
        });
    }
    Ok(gaps
        .gaps
        .iter()
        .filter(|g| !joined.contains(&g.pad_node))
        .map(|g| BondRow {
            node: g.pad_node,
            coords: g.coords,
            masters: known[&g.pad_node].iter().map(|(&a, &w)| (a, w)).collect(),
        })
        .collect())
}
