//! Bonded ties (`[[ties]]`): each tie's sides paired (node-to-surface or mortar) and solved
//! for the slave nodes, u_s = Σ_m w u_m ([`squeal_contact::bond_rows`]), then eliminated.
//!
//! *Inside a component* (a component of several meshed bodies): before its Craig–Bampton
//! reduction, as a multi-point constraint on its free DOFs ([`Mpc`]): K' = Tᵀ K T, M' = Tᵀ M T,
//! f' = Tᵀ f, the slave DOFs recovered as u = T u'. The reduction then sees the glued body:
//! no boundary DOF is added, and its fixed-interface modes are the glued body's.
//!
//! *Between components*: the tied nodes of both sides become boundary DOFs of their
//! components, and after the superelement assembly the slave grid DOFs are eliminated from the
//! assembled K, M, B and loads with the same T ([`eliminate`]), kept as recovered DOFs (rows
//! over the reduced vector) for the gaps and the outputs. A Craig–Bampton reduction keeps its
//! boundary DOFs exactly, so this is the tie of the full model, and each component is still
//! reduced (and cached) on its own.

use super::from_mesh::rotor_faces;
use super::grids::Grids;
use crate::error::PipelineError;
use crate::scene::{Scene, TiePairing};
use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use faer::Par;
use squeal_contact::{
    bond_rows_joined, mortar_gaps, tie_gaps, ContactNode, MatchOptions, MortarOptions,
};
use squeal_fe::DofMap;
use squeal_meshes::Mesh;
use squeal_reduction::superelement::{DofKey, DofKind, RecoveredDof, ReducedDofMap};
use std::collections::{BTreeMap, HashMap};

use squeal_solver::Real;

/// Mesh-node rows of the ties inside a component: (slave node, [(master node, weight)]).
pub type NodeRows = Vec<(usize, Vec<(usize, Real)>)>;

/// One tie's rows: slave grid → [(master grid, weight)].
#[derive(Debug, Clone)]
pub struct TieRows {
    /// Slave and master component indices (equal for a tie inside a component).
    pub slave: usize,
    pub master: usize,
    pub rows: Vec<(u64, Vec<(u64, Real)>)>,
}

impl TieRows {
    /// Every grid of the tie with a non-zero weight (slaves and masters).
    pub fn grids(&self) -> impl Iterator<Item = u64> + '_ {
        self.rows
            .iter()
            .flat_map(|(s, m)| std::iter::once(*s).chain(m.iter().map(|x| x.0)))
    }
}

/// Pairs every `[[ties]]` entry and solves it for its slave nodes. A slave grid merged with a
/// grid of the master component (coincident nodes within `model.merge_tolerance`) is already
/// joined by the assembly and gets no row.
pub fn pair_ties(
    scene: &Scene,
    meshes: &[Mesh],
    grids: &Grids,
) -> Result<Vec<TieRows>, PipelineError> {
    let pos = |name: &str| scene.components.iter().position(|c| c.name == name);
    let mut out = Vec::with_capacity(scene.ties.len());
    for (i, tie) in scene.ties.iter().enumerate() {
        let unknown = |side: &str, name: &str| PipelineError::Scene {
            field: format!("ties[{i}].{side}.component"),
            message: format!("no component named `{name}`"),
        };
        let ca = pos(&tie.a.component).ok_or_else(|| unknown("a", &tie.a.component))?;
        let cb = pos(&tie.b.component).ok_or_else(|| unknown("b", &tie.b.component))?;
        let faces_of = |side: &str, c: usize, set: &str| {
            let mesh = &meshes[c];
            let block = mesh.faces.get(set).ok_or_else(|| PipelineError::Scene {
                field: format!("ties[{i}].{side}.faces"),
                message: format!(
                    "component `{}` has no face set `{set}` (it has: {})",
                    scene.components[c].name,
                    mesh.faces.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            })?;
            rotor_faces(block, mesh, &grids.grid_of[c]).map_err(|m| PipelineError::Scene {
                field: format!("ties[{i}].{side}.faces"),
                message: format!("face set `{set}` of `{}`: {m}", scene.components[c].name),
            })
        };
        let slave_faces = faces_of("a", ca, &tie.a.faces)?;
        let master_faces = faces_of("b", cb, &tie.b.faces)?;
        let slave_nodes: Vec<ContactNode> = super::areas::pad_areas(&meshes[ca], &tie.a.faces)
            .map_err(|source| PipelineError::Fe {
                component: tie.a.component.clone(),
                source,
            })?
            .into_iter()
            .map(|(n, s)| ContactNode {
                id: grids.grid_of[ca][n],
                coords: meshes[ca].nodes[n],
                area: s,
            })
            .collect();
        // Grids merged into the master component: already joined.
        let in_master: std::collections::HashSet<u64> = grids.grid_of[cb].iter().copied().collect();
        let (slave_nodes, skipped): (Vec<ContactNode>, Vec<ContactNode>) = if ca == cb {
            (slave_nodes, Vec::new())
        } else {
            slave_nodes
                .into_iter()
                .partition(|n| !in_master.contains(&n.id))
        };
        let what = || {
            format!(
                "ties[{i}]: `{}` faces `{}` on `{}` faces `{}`",
                tie.a.component, tie.a.faces, tie.b.component, tie.b.faces
            )
        };
        let contact_err = |source| PipelineError::Contact {
            what: what(),
            source,
        };
        let opts = MatchOptions::default();
        let gaps = match tie.pairing {
            TiePairing::Mortar => {
                // Merged slave nodes stay as pad nodes of the integration (their faces need
                // them), and their rows are dropped below.
                let all: Vec<ContactNode> = slave_nodes.iter().chain(&skipped).copied().collect();
                mortar_gaps(
                    &all,
                    &slave_faces,
                    &master_faces,
                    &opts,
                    &tie.tie_options(),
                    &MortarOptions::default(),
                )
                .map_err(contact_err)?
                .0
                .gaps
            }
            TiePairing::Surface => {
                tie_gaps(&slave_nodes, &master_faces, &opts, &tie.tie_options())
                    .map_err(contact_err)?
                    .gaps
            }
        };
        let joined: Vec<u64> = skipped.iter().map(|n| n.id).collect();
        let rows = bond_rows_joined(&gaps, &joined).map_err(contact_err)?;
        out.push(TieRows {
            slave: ca,
            master: cb,
            rows: rows.into_iter().map(|r| (r.node, r.masters)).collect(),
        });
    }
    Ok(out)
}

/// A multi-point constraint on a component's free DOFs: the slave DOFs u_s = Σ w u_m are
/// eliminated, u_free = T u_indep.
#[derive(Debug, Clone)]
pub struct Mpc {
    /// Independent index of each free DOF (None: a slave).
    indep_of: Vec<Option<usize>>,
    /// Slave free DOF → [(independent index, weight)].
    slaves: HashMap<usize, Vec<(usize, Real)>>,
    n_indep: usize,
}

impl Mpc {
    /// The MPC of `rows` (slave mesh node → [(master mesh node, weight)], every direction)
    /// on the free DOFs `dofs`. A fixed master DOF drops out (u = 0); a master that is itself
    /// a slave (ties in a chain) is substituted. Err: a slave DOF that is fixed, or a cycle.
    pub fn new(dofs: &DofMap, rows: &[(usize, Vec<(usize, Real)>)]) -> Result<Mpc, String> {
        // Slave free DOF → [(free DOF, weight)], then masters that are slaves substituted.
        let mut raw: BTreeMap<usize, Vec<(usize, Real)>> = BTreeMap::new();
        for (s, masters) in rows {
            for k in 0..3 {
                let Some(i) = dofs.free(*s, k) else {
                    return Err(format!(
                        "tied node {s} (mesh index) has a fixed DOF {}: fix the master side, \
                         or swap the tie's sides",
                        ["x", "y", "z"][k]
                    ));
                };
                let terms = masters
                    .iter()
                    .filter_map(|&(m, w)| dofs.free(m, k).map(|j| (j, w)))
                    .collect();
                if raw.insert(i, terms).is_some() {
                    return Err(format!("node {s} (mesh index) is the slave of two ties"));
                }
            }
        }
        for _ in 0..=raw.len() {
            let chained: Vec<usize> = raw
                .iter()
                .filter(|(_, t)| t.iter().any(|(j, _)| raw.contains_key(j)))
                .map(|(&i, _)| i)
                .collect();
            if chained.is_empty() {
                break;
            }
            for i in chained {
                let mut row: BTreeMap<usize, Real> = BTreeMap::new();
                for &(j, w) in &raw[&i] {
                    match raw.get(&j) {
                        Some(sub) if j != i => {
                            for &(m, v) in sub {
                                *row.entry(m).or_default() += w * v;
                            }
                        }
                        Some(_) => return Err(format!("free DOF {i} is tied to itself")),
                        None => *row.entry(j).or_default() += w,
                    }
                }
                raw.insert(i, row.into_iter().collect());
            }
        }
        if raw
            .values()
            .any(|t| t.iter().any(|(j, _)| raw.contains_key(j)))
        {
            return Err("the ties form a cycle (a node is its own master through them)".into());
        }
        let mut indep_of = vec![None; dofs.n_free()];
        let mut n_indep = 0;
        for (i, slot) in indep_of.iter_mut().enumerate() {
            if !raw.contains_key(&i) {
                *slot = Some(n_indep);
                n_indep += 1;
            }
        }
        let slaves = raw
            .into_iter()
            .map(|(i, t)| {
                let t = t
                    .into_iter()
                    .map(|(j, w)| (indep_of[j].expect("masters are not slaves"), w))
                    .collect();
                (i, t)
            })
            .collect();
        Ok(Mpc {
            indep_of,
            slaves,
            n_indep,
        })
    }

    /// Number of independent DOFs.
    pub fn n_indep(&self) -> usize {
        self.n_indep
    }

    /// Number of free DOFs (rows of T).
    pub fn n_free(&self) -> usize {
        self.indep_of.len()
    }

    /// Independent index of free DOF `i` (None: a slave).
    pub fn indep(&self, i: usize) -> Option<usize> {
        self.indep_of[i]
    }

    /// Row i of T: (independent index, weight).
    fn row(&self, i: usize) -> Vec<(usize, Real)> {
        match self.indep_of[i] {
            Some(j) => vec![(j, 1.0)],
            None => self.slaves[&i].clone(),
        }
    }

    /// Tᵀ A T of a sparse matrix over the free DOFs.
    pub fn transform(
        &self,
        a: &SparseColMat<usize, Real>,
    ) -> Result<SparseColMat<usize, Real>, String> {
        // T and Tᵀ as sparse matrices, then two sparse products: the triplets of Tᵀ A T
        // written out entry by entry would number Σ_ij |row_i| |row_j| over A's non-zeros,
        // hundreds of millions for mortar rows on tet10 faces (a slave row has tens of terms).
        let err = |e: faer::sparse::CreationError| format!("the tie matrix T: {e:?}");
        let mut t = Vec::with_capacity(self.n_free() + 8 * self.slaves.len());
        let mut tt = Vec::with_capacity(t.capacity());
        for i in 0..self.n_free() {
            for (j, w) in self.row(i) {
                t.push(Triplet::new(i, j, w));
                tt.push(Triplet::new(j, i, w));
            }
        }
        let t =
            SparseColMat::try_new_from_triplets(self.n_free(), self.n_indep, &t).map_err(err)?;
        let tt =
            SparseColMat::try_new_from_triplets(self.n_indep, self.n_free(), &tt).map_err(err)?;
        let mul = |x: faer::sparse::SparseColMatRef<'_, usize, Real>,
                   y: faer::sparse::SparseColMatRef<'_, usize, Real>| {
            sparse_sparse_matmul(x, y, 1.0, Par::Seq).map_err(|e| format!("the tied matrix: {e:?}"))
        };
        let at = mul(a.as_ref(), t.as_ref())?;
        mul(tt.as_ref(), at.as_ref())
    }

    /// Tᵀ f.
    pub fn project(&self, f: &[Real]) -> Vec<Real> {
        let mut out = vec![0.0; self.n_indep];
        for (i, &v) in f.iter().enumerate() {
            if v != 0.0 {
                for (j, w) in self.row(i) {
                    out[j] += w * v;
                }
            }
        }
        out
    }

    /// T u: the free DOFs of an independent vector.
    pub fn expand(&self, u: &[Real]) -> Vec<Real> {
        (0..self.n_free())
            .map(|i| self.row(i).iter().map(|&(j, w)| w * u[j]).sum())
            .collect()
    }

    /// The independent entries of a free-DOF list (slaves dropped).
    pub fn select<T: Clone>(&self, free: &[T]) -> Vec<T> {
        free.iter()
            .enumerate()
            .filter(|(i, _)| self.indep_of[*i].is_some())
            .map(|(_, x)| x.clone())
            .collect()
    }
}

/// The ties of component `c` as mesh-node rows, for its [`Mpc`] (None: no tie inside it).
pub fn component_rows(ties: &[TieRows], c: usize, grid_of: &[u64]) -> Option<NodeRows> {
    let inside: Vec<&TieRows> = ties
        .iter()
        .filter(|t| t.slave == c && t.master == c)
        .collect();
    if inside.is_empty() {
        return None;
    }
    let node: HashMap<u64, usize> = grid_of.iter().enumerate().map(|(n, &g)| (g, n)).collect();
    Some(
        inside
            .iter()
            .flat_map(|t| t.rows.iter())
            .map(|(s, m)| (node[s], m.iter().map(|&(g, w)| (node[&g], w)).collect()))
            .collect(),
    )
}

/// What [`eliminate`] keeps of the assembled model.
pub struct Eliminated {
    pub k: Mat<Real>,
    pub m: Mat<Real>,
    pub b: Option<Mat<Real>>,
    pub p: Vec<Real>,
    pub dofs: ReducedDofMap,
    /// New index of each old assembled DOF as (index, weight) terms (a kept DOF: itself; a
    /// slave: its master terms).
    pub terms: Vec<Vec<(usize, Real)>>,
}

/// Eliminates the slave grid DOFs of the ties between components from the assembled reduced
/// model: x_old = T x_new, K' = Tᵀ K T (and M, B), p' = Tᵀ p; the slave grid DOFs become
/// recovered DOFs. Every tied grid DOF is a grid DOF of the assembly (a boundary DOF), or a
/// fixed one (a fixed master drops out; a fixed slave is an error).
pub fn eliminate(
    k: &Mat<Real>,
    m: &Mat<Real>,
    b: Option<&Mat<Real>>,
    p: &[Real],
    dofs: &ReducedDofMap,
    rows: &[(u64, Vec<(u64, Real)>)],
) -> Result<Eliminated, PipelineError> {
    let n = dofs.len();
    let index: HashMap<DofKey, usize> = dofs
        .dofs
        .iter()
        .enumerate()
        .filter_map(|(i, d)| match d.kind {
            DofKind::Grid { grid, comp } => Some((DofKey { grid, comp }, i)),
            _ => None,
        })
        .collect();
    // Old slave index → [(old master index, w)], substituted through chains.
    let mut raw: BTreeMap<usize, Vec<(usize, Real)>> = BTreeMap::new();
    for (s, masters) in rows {
        for comp in 1..=3u8 {
            let Some(&i) = index.get(&DofKey { grid: *s, comp }) else {
                // A fixed slave DOF: held by its own support; its masters would have to follow.
                return Err(PipelineError::Model(format!(
                    "ties: slave grid {s} has no DOF {comp} in the reduced model (fixed?): fix \
                     the master side, or swap the tie's sides"
                )));
            };
            let terms = masters
                .iter()
                .filter_map(|&(g, w)| index.get(&DofKey { grid: g, comp }).map(|&j| (j, w)))
                .collect();
            if raw.insert(i, terms).is_some() {
                return Err(PipelineError::Model(format!(
                    "ties: grid {s} is the slave of two ties"
                )));
            }
        }
    }
    for _ in 0..=raw.len() {
        let chained: Vec<usize> = raw
            .iter()
            .filter(|(_, t)| t.iter().any(|(j, _)| raw.contains_key(j)))
            .map(|(&i, _)| i)
            .collect();
        if chained.is_empty() {
            break;
        }
        for i in chained {
            let mut row: BTreeMap<usize, Real> = BTreeMap::new();
            for &(j, w) in &raw[&i] {
                match raw.get(&j) {
                    Some(sub) if j != i => sub
                        .iter()
                        .for_each(|&(mm, v)| *row.entry(mm).or_default() += w * v),
                    _ => *row.entry(j).or_default() += w,
                }
            }
            raw.insert(i, row.into_iter().collect());
        }
    }
    if raw
        .values()
        .any(|t| t.iter().any(|(j, _)| raw.contains_key(j)))
    {
        return Err(PipelineError::Model(
            "ties: the ties form a cycle (a grid is its own master through them)".into(),
        ));
    }
    let mut new_of = vec![None; n];
    let mut kept = Vec::new();
    for i in 0..n {
        if !raw.contains_key(&i) {
            new_of[i] = Some(kept.len());
            kept.push(i);
        }
    }
    let terms: Vec<Vec<(usize, Real)>> = (0..n)
        .map(|i| match new_of[i] {
            Some(j) => vec![(j, 1.0)],
            None => raw[&i]
                .iter()
                .map(|&(j, w)| (new_of[j].unwrap(), w))
                .collect(),
        })
        .collect();
    let nn = kept.len();
    // Tᵀ A T with T sparse: (A T) column by column, then Tᵀ (A T) row by row.
    let transform = |a: &Mat<Real>| -> Mat<Real> {
        let mut at = Mat::<Real>::zeros(n, nn);
        for (i, t) in terms.iter().enumerate() {
            for &(j, w) in t {
                for r in 0..n {
                    at[(r, j)] += w * a[(r, i)];
                }
            }
        }
        let mut out = Mat::<Real>::zeros(nn, nn);
        for (i, t) in terms.iter().enumerate() {
            for &(j, w) in t {
                for c in 0..nn {
                    out[(j, c)] += w * at[(i, c)];
                }
            }
        }
        out
    };
    let mut pn = vec![0.0; nn];
    for (i, t) in terms.iter().enumerate() {
        for &(j, w) in t {
            pn[j] += w * p[i];
        }
    }
    let mut new_dofs = ReducedDofMap {
        dofs: kept.iter().map(|&i| dofs.dofs[i].clone()).collect(),
        recovered: Vec::new(),
    };
    // Earlier recovered DOFs (interface reduction) renumbered through T.
    for r in &dofs.recovered {
        let mut row: BTreeMap<usize, Real> = BTreeMap::new();
        for (&i, &c) in r.dofs.iter().zip(&r.coefs) {
            for &(j, w) in &terms[i] {
                *row.entry(j).or_default() += c * w;
            }
        }
        new_dofs.recovered.push(RecoveredDof {
            component: r.component.clone(),
            grid: r.grid,
            comp: r.comp,
            dofs: row.keys().copied().collect(),
            coefs: row.values().copied().collect(),
        });
    }
    for (&i, _) in raw.iter() {
        let d = &dofs.dofs[i];
        let DofKind::Grid { grid, comp } = d.kind else {
            unreachable!("slaves are grid DOFs")
        };
        new_dofs.recovered.push(RecoveredDof {
            component: d.component.clone(),
            grid,
            comp,
            dofs: terms[i].iter().map(|x| x.0).collect(),
            coefs: terms[i].iter().map(|x| x.1).collect(),
        });
    }
    Ok(Eliminated {
        k: transform(k),
        m: transform(m),
        b: b.map(transform),
        p: pn,
        dofs: new_dofs,
        terms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// T of the tie u_2 = ½ u_0 + ½ u_1 (every direction) on three free nodes: Tᵀ A T of a
    /// diagonal A, the expansion and the projection, against the matrices written out by
    /// hand (per direction k the independent DOFs are k of node 0 and 3 + k of node 1).
    #[test]
    fn mpc_transforms_and_expands() {
        let dofs = DofMap::new(3, &[]).unwrap();
        let mpc = Mpc::new(&dofs, &[(2, vec![(0, 0.5), (1, 0.5)])]).unwrap();
        assert_eq!(mpc.n_indep(), 6);
        assert_eq!(mpc.n_free(), 9);
        // A = diag(1, 2, 4) per node, the same in x, y and z.
        let diag = [1.0, 2.0, 4.0];
        let a = SparseColMat::try_new_from_triplets(
            9,
            9,
            &(0..9)
                .map(|i| Triplet::new(i, i, diag[i / 3]))
                .collect::<Vec<_>>(),
        )
        .unwrap();
        let t = mpc.transform(&a).unwrap().to_dense();
        // Per direction: Tᵀ A T = diag(1, 2) + 4 [½ ½]ᵀ[½ ½] = [[2, 1], [1, 3]]; no coupling
        // between directions.
        for i in 0..6 {
            for j in 0..6 {
                let want = match (i % 3 == j % 3, i / 3, j / 3) {
                    (false, _, _) => 0.0,
                    (true, 0, 0) => 2.0,
                    (true, 1, 1) => 3.0,
                    (true, _, _) => 1.0,
                };
                assert_eq!(t[(i, j)], want, "({i}, {j})");
            }
        }
        let u = mpc.expand(&[2.0, 0.0, -2.0, 4.0, 6.0, 2.0]);
        assert_eq!(u, vec![2.0, 0.0, -2.0, 4.0, 6.0, 2.0, 3.0, 3.0, 0.0]);
        let f = mpc.project(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 4.0]);
        assert_eq!(f, vec![2.0, 0.0, 2.0, 1.0, 0.0, 2.0]);
    }
}
