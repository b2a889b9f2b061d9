//! Parallel element computation, scatter into the node graph, free-DOF matrices.

use super::pattern::NodeGraph;
use super::{Assembled, AssemblyOptions, AssemblyStats};
use crate::element::kinds::element_into;
use crate::element::solid::BlockLaw;
use crate::{DofMap, FeError, Real, SolidMaterial};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;
use squeal_meshes::{CellBlock, Mesh};
use std::time::Instant;

/// Cells computed in parallel before one serial scatter.
const CHUNK: usize = 512;

/// Assembles the stiffness K and consistent mass M over the free DOFs of `dofs`.
///
/// `materials[i]` belongs to `mesh.volumes[i]`: an isotropic [`crate::Material`] or any
/// [`SolidMaterial`] (anisotropic elasticity with material axes). Hex8 cells use `opts.hex8`;
/// every kind's quadrature rule is in [`crate::element::kinds`]. Elements are computed in
/// parallel (rayon) into buffers allocated once per block, with no allocation per element.
/// The matrices have full symmetric storage (both triangles) with sorted row indices; fixed
/// DOFs are removed.
///
/// Errors: material count mismatch, invalid material (named by its block), face kinds among
/// the volumes, connectivity out of range, non-positive Jacobian (naming block, element tag
/// and value).
pub fn assemble<M: Clone + Into<SolidMaterial>>(
    mesh: &Mesh,
    materials: &[M],
    dofs: &DofMap,
    opts: &AssemblyOptions,
) -> Result<Assembled, FeError> {
    let t0 = Instant::now();
    opts.validate()?;
    let materials: Vec<SolidMaterial> = materials.iter().cloned().map(Into::into).collect();
    check_inputs(mesh, &materials, dofs)?;
    let graph = NodeGraph::new(mesh);
    let pattern_s = t0.elapsed().as_secs_f64();

    let t1 = Instant::now();
    let npairs = graph.idx.len();
    let mut kblk = vec![[0.0 as Real; 9]; npairs];
    let mut mblk = vec![0.0 as Real; npairs];
    let mut n_elements = 0;
    for (block, mat) in mesh.volumes.iter().zip(&materials) {
        n_elements += block.len();
        let law = BlockLaw::new(mat);
        let nn = block.kind.n_nodes();
        let d = 3 * nn;
        let per = d * d + nn * nn;
        let mut buf = vec![0.0 as Real; per * CHUNK.min(block.len())];
        for start in (0..block.len()).step_by(CHUNK) {
            if opts.interrupt.is_set() {
                return Err(FeError::Interrupted { during: "assembly" });
            }
            let end = (start + CHUNK).min(block.len());
            buf[..per * (end - start)]
                .par_chunks_mut(per)
                .enumerate()
                .try_for_each(|(i, out)| {
                    let (ke, me) = out.split_at_mut(d * d);
                    element(mesh, block, start + i, &law, opts, ke, me)
                })?;
            for (c, out) in (start..end).zip(buf.chunks(per)) {
                let (ke, me) = out.split_at(d * d);
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

fn check_inputs(mesh: &Mesh, materials: &[SolidMaterial], dofs: &DofMap) -> Result<(), FeError> {
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
        let name = block_name(block);
        mat.validate(&format!("material of block '{name}'"))?;
        if !block.kind.is_volume() {
            return Err(FeError::WrongCellKind {
                block: name,
                kind: format!("{:?}", block.kind),
                expected: "a volume kind (hex, tet, wedge, pyramid)",
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
        if let crate::MaterialAxes::PerCell(frames) = &mat.axes {
            if frames.len() != block.len() {
                return Err(FeError::Dimension {
                    what: "material frames per cell of a block",
                    got: frames.len(),
                    expected: block.len(),
                });
            }
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

/// Element matrices of cell `c` into `ke` / `me`; Jacobian failures are named by block and tag.
fn element(
    mesh: &Mesh,
    block: &CellBlock,
    c: usize,
    law: &BlockLaw,
    opts: &AssemblyOptions,
    ke: &mut [Real],
    me: &mut [Real],
) -> Result<(), FeError> {
    let named = |e: FeError| match e {
        FeError::ElementJacobian { det, .. } => FeError::NonPositiveJacobian {
            block: block_name(block),
            tag: block.tags[c],
            det,
        },
        FeError::InvalidValue {
            field,
            value,
            reason,
        } => FeError::InvalidValue {
            field: format!(
                "block '{}', element tag {}: {field}",
                block_name(block),
                block.tags[c]
            ),
            value,
            reason,
        },
        other => other,
    };
    let cell_law = law.cell(c).map_err(named)?;
    element_into(
        block.kind,
        opts.hex8,
        block.cell(c),
        &mesh.nodes,
        &cell_law,
        law.density(),
        ke,
        me,
    )
    .map_err(|e| match e {
        // The incompatible-mode condensation reports its failure with a positive det.
        FeError::ElementJacobian { det, .. }
            if det > 0.0 && block.kind == squeal_meshes::CellKind::Hex8 =>
        {
            FeError::SingularIncompatible {
                block: block_name(block),
                tag: block.tags[c],
            }
        }
        other => named(other),
    })
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
