//! Parallel element computation, scatter into the node graph, free-DOF matrices.

use super::pattern::NodeGraph;
use super::{Assembled, AssemblyOptions, AssemblyStats, Hex8Formulation};
use crate::element::{hex20, hex8, hex8_incompatible};
use crate::{DofMap, FeError, Material, Real};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;
use squeal_meshes::{CellBlock, CellKind, Mesh};
use std::time::Instant;

/// Cells computed in parallel before one serial scatter.
const CHUNK: usize = 512;

/// Element stiffness (column-major, 3N×3N) and scalar mass (N×N) of one cell.
type ElementPair = (Vec<Real>, Vec<Real>);

/// Assembles the stiffness K and consistent mass M over the free DOFs of `dofs`.
///
/// `materials[i]` belongs to `mesh.volumes[i]`. Hex8 cells use `opts.hex8`, hex20 cells
/// 3×3×3 Gauss. Elements are computed in parallel (rayon). The matrices have full symmetric
/// storage (both triangles) with sorted row indices; fixed DOFs are removed.
///
/// Errors: material count mismatch, invalid material, face kinds among the volumes,
/// connectivity out of range, non-positive Jacobian (naming block, element tag and value).
pub fn assemble(
    mesh: &Mesh,
    materials: &[Material],
    dofs: &DofMap,
    opts: &AssemblyOptions,
) -> Result<Assembled, FeError> {
    let t0 = Instant::now();
    opts.validate()?;
    check_inputs(mesh, materials, dofs)?;
    let graph = NodeGraph::new(mesh);
    let pattern_s = t0.elapsed().as_secs_f64();

    let t1 = Instant::now();
    let npairs = graph.idx.len();
    let mut kblk = vec![[0.0 as Real; 9]; npairs];
    let mut mblk = vec![0.0 as Real; npairs];
    let mut n_elements = 0;
    for (block, mat) in mesh.volumes.iter().zip(materials) {
        n_elements += block.len();
        let nn = block.kind.n_nodes();
        let d = 3 * nn;
        for start in (0..block.len()).step_by(CHUNK) {
            let end = (start + CHUNK).min(block.len());
            let mats: Vec<ElementPair> = (start..end)
                .into_par_iter()
                .map(|c| element(mesh, block, c, mat, opts))
                .collect::<Result<_, _>>()?;
            for (c, (ke, me)) in (start..end).zip(mats) {
                let nd = block.cell(c);
                for b in 0..nn {
                    for a in 0..nn {
                        let p = graph.pos(nd[a], nd[b]);
                        let kb = &mut kblk[p];
                        for j in 0..3 {
                            let col = &ke[(3 * b + j) * d + 3 * a..(3 * b + j) * d + 3 * a + 3];
                            for i in 0..3 {
                                kb[3 * i + j] += col[i];
                            }
                        }
                        mblk[p] += me[b * nn + a];
                    }
                }
            }
        }
    }
    let elements_s = t1.elapsed().as_secs_f64();

    let t2 = Instant::now();
    let (k, m) = build_free(&graph, &kblk, &mblk, dofs);
    let build_s = t2.elapsed().as_secs_f64();
    let stats = AssemblyStats {
        n_elements,
        n_free: dofs.n_free(),
        nnz_k: k.compute_nnz(),
        nnz_m: m.compute_nnz(),
        pattern_s,
        elements_s,
        build_s,
        total_s: t0.elapsed().as_secs_f64(),
    };
    Ok(Assembled { k, m, stats })
}

fn check_inputs(mesh: &Mesh, materials: &[Material], dofs: &DofMap) -> Result<(), FeError> {
    if materials.len() != mesh.volumes.len() {
        return Err(FeError::MaterialCount {
            expected: mesh.volumes.len(),
            got: materials.len(),
        });
    }
    if dofs.n_nodes() != mesh.nodes.len() {
        return Err(FeError::DofMapMismatch {
            dof_nodes: dofs.n_nodes(),
            mesh_nodes: mesh.nodes.len(),
        });
    }
    for (block, mat) in mesh.volumes.iter().zip(materials) {
        mat.validate()?;
        let name = block_name(block);
        if !matches!(block.kind, CellKind::Hex8 | CellKind::Hex20) {
            return Err(FeError::WrongCellKind {
                block: name,
                kind: format!("{:?}", block.kind),
                expected: "hex8 or hex20",
            });
        }
        let nn = block.kind.n_nodes();
        if block.conn.len() != nn * block.tags.len() {
            return Err(FeError::Dimension {
                what: "connectivity length of a volume block",
                got: block.conn.len(),
                expected: nn * block.tags.len(),
            });
        }
        if let Some(&bad) = block.conn.iter().find(|&&v| v >= mesh.nodes.len()) {
            return Err(FeError::NodeOutOfRange {
                node: bad,
                n_nodes: mesh.nodes.len(),
                context: format!("connectivity of block '{name}'"),
            });
        }
    }
    Ok(())
}

pub(crate) fn block_name(block: &CellBlock) -> String {
    block
        .name
        .clone()
        .unwrap_or_else(|| "<unnamed>".to_string())
}

/// Element matrices of cell `c`; Jacobian failures are named by block and tag.
fn element(
    mesh: &Mesh,
    block: &CellBlock,
    c: usize,
    mat: &Material,
    opts: &AssemblyOptions,
) -> Result<ElementPair, FeError> {
    let nd = block.cell(c);
    let named = |e: FeError| match e {
        FeError::ElementJacobian { det, .. } => FeError::NonPositiveJacobian {
            block: block_name(block),
            tag: block.tags[c],
            det,
        },
        other => other,
    };
    match block.kind {
        CellKind::Hex20 => {
            let x: [[Real; 3]; 20] = std::array::from_fn(|a| mesh.nodes[nd[a]]);
            let k = hex20::stiffness(&x, mat).map_err(named)?;
            let m = hex20::mass_scalar(&x, mat.density).map_err(named)?;
            Ok((k.as_slice().to_vec(), m.as_slice().to_vec()))
        }
        _ => {
            let x: [[Real; 3]; 8] = std::array::from_fn(|a| mesh.nodes[nd[a]]);
            let k = match opts.hex8 {
                Hex8Formulation::Incompatible => hex8_incompatible::stiffness(&x, mat),
                Hex8Formulation::Standard => hex8::stiffness(&x, mat),
            }
            .map_err(|e| match e {
                FeError::ElementJacobian { det, .. } if det > 0.0 => {
                    FeError::SingularIncompatible {
                        block: block_name(block),
                        tag: block.tags[c],
                    }
                }
                other => named(other),
            })?;
            let m = hex8::mass_scalar(&x, mat.density).map_err(named)?;
            Ok((k.as_slice().to_vec(), m.as_slice().to_vec()))
        }
    }
}

/// Free-DOF CSC matrices from node-block values; rows sorted because free numbering is
/// node-major and the node lists are sorted.
fn build_free(
    graph: &NodeGraph,
    kblk: &[[Real; 9]],
    mblk: &[Real],
    dofs: &DofMap,
) -> (SparseColMat<usize, Real>, SparseColMat<usize, Real>) {
    let t = dofs.table();
    let n = dofs.n_free();
    let n_nodes = graph.ptr.len() - 1;
    let (mut kp, mut kr, mut kv) = (vec![0usize], Vec::new(), Vec::new());
    let (mut mp, mut mr, mut mv) = (vec![0usize], Vec::new(), Vec::new());
    let nnz_guess: usize = graph.idx.len() * 9;
    kr.reserve(nnz_guess);
    kv.reserve(nnz_guess);
    mr.reserve(nnz_guess / 3);
    mv.reserve(nnz_guess / 3);
    for b in 0..n_nodes {
        let range = graph.ptr[b]..graph.ptr[b + 1];
        for j in 0..3 {
            if t[3 * b + j] == usize::MAX {
                continue;
            }
            for p in range.clone() {
                let a = graph.idx[p];
                for i in 0..3 {
                    let r = t[3 * a + i];
                    if r != usize::MAX {
                        kr.push(r);
                        kv.push(kblk[p][3 * i + j]);
                        if i == j {
                            mr.push(r);
                            mv.push(mblk[p]);
                        }
                    }
                }
            }
            kp.push(kr.len());
            mp.push(mr.len());
        }
    }
    let k = SparseColMat::new(SymbolicSparseColMat::new_checked(n, n, kp, None, kr), kv);
    let m = SparseColMat::new(SymbolicSparseColMat::new_checked(n, n, mp, None, mr), mv);
    (k, m)
}
