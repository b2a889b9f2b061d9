//! Assembly of reduced components on shared boundary DOFs.

use super::dofmap::{DofKey, DofKind, RecoveredDof, ReducedDof, ReducedDofMap};
use crate::cb::CbModel;
use crate::error::ReductionError;
use faer::{Mat, MatRef};
use serde::Serialize;
use squeal_meshes::Real;
use std::collections::{BTreeMap, BTreeSet};

/// One reduced component: matrices ordered [boundary DOFs, interface coordinates, modal
/// coordinates].
#[derive(Debug, Clone)]
pub struct Component<'a> {
    pub name: String,
    pub k: MatRef<'a, Real>,
    pub m: MatRef<'a, Real>,
    pub b: Option<MatRef<'a, Real>>,
    /// Global key of each boundary DOF, in the order of the matrices' first rows.
    pub boundary_keys: Vec<DofKey>,
    /// Interface-reduced grid DOFs: their keys and basis L (keys.len() × interface
    /// coordinates), u = L p; none for an exact Craig–Bampton component.
    pub interface: Option<(Vec<DofKey>, MatRef<'a, Real>)>,
    /// Number of modal coordinates after the boundary DOFs.
    pub n_modes: usize,
}

impl<'a> Component<'a> {
    /// A component from a Craig–Bampton model; `boundary_keys[j]` is the key of `model.boundary[j]`.
    pub fn from_cb(
        name: impl Into<String>,
        model: &'a CbModel,
        boundary_keys: Vec<DofKey>,
    ) -> Self {
        Self {
            name: name.into(),
            k: model.k.as_ref(),
            m: model.m.as_ref(),
            b: model.b.as_ref().map(|b| b.as_ref()),
            boundary_keys,
            interface: None,
            n_modes: model.n_modes,
        }
    }

    /// A component from an interface-reduced Craig–Bampton model; `interface_keys[r]` is the
    /// key of `model.interface.dofs[r]` (ignored without an interface basis).
    pub fn from_cb_interface(
        name: impl Into<String>,
        model: &'a CbModel,
        boundary_keys: Vec<DofKey>,
        interface_keys: Vec<DofKey>,
    ) -> Self {
        let mut c = Self::from_cb(name, model, boundary_keys);
        c.interface = model
            .interface
            .as_ref()
            .map(|f| (interface_keys, f.basis.as_ref()));
        c
    }

    /// Interface coordinates (0 without an interface basis).
    pub fn n_interface(&self) -> usize {
        self.interface.as_ref().map_or(0, |(_, l)| l.ncols())
    }
}

/// Statistics of an assembly.
#[derive(Debug, Clone, Serialize)]
pub struct AssemblyStats {
    pub n_components: usize,
    /// Distinct grid DOFs kept (after removing fixed ones).
    pub n_grid_dofs: usize,
    /// Grid DOFs appearing in more than one component.
    pub n_shared_dofs: usize,
    pub n_fixed_dofs: usize,
    pub n_modal_dofs: usize,
    /// Interface coordinates of interface-reduced components.
    pub n_interface_coords: usize,
    /// Grid DOFs recovered from them.
    pub n_recovered_dofs: usize,
}

/// The assembled reduced system: dense K, M (and B when any component has one) and its DOF map.
#[derive(Debug, Clone)]
pub struct Assembly {
    pub k: Mat<Real>,
    pub m: Mat<Real>,
    pub b: Option<Mat<Real>>,
    pub dofs: ReducedDofMap,
    pub stats: AssemblyStats,
}

fn se_err(component: &str, detail: String) -> ReductionError {
    ReductionError::Superelement {
        component: component.to_string(),
        detail,
    }
}

/// Assembles reduced components: boundary DOFs with equal keys are one global DOF, modal
/// coordinates stay per component, DOFs whose key is in `fixed` (SPC) are removed.
///
/// Global order: grid DOFs sorted by (grid, comp), then per component (in component order)
/// its interface coordinates and its modal coordinates. The interface grid DOFs of a
/// component go to [`ReducedDofMap::recovered`] as rows over its interface coordinates.
pub fn assemble(
    components: &[Component<'_>],
    fixed: &[DofKey],
) -> Result<Assembly, ReductionError> {
    let fixed_set: BTreeSet<DofKey> = fixed.iter().copied().collect();
    let mut owners: BTreeMap<DofKey, Vec<usize>> = BTreeMap::new();
    for (c, comp) in components.iter().enumerate() {
        let nr = comp.boundary_keys.len() + comp.n_interface() + comp.n_modes;
        if let Some((keys, l)) = &comp.interface {
            if keys.len() != l.nrows() {
                return Err(se_err(
                    &comp.name,
                    format!(
                        "{} interface keys for an interface basis of {} rows",
                        keys.len(),
                        l.nrows()
                    ),
                ));
            }
        }
        for (what, a) in [("K", Some(comp.k)), ("M", Some(comp.m)), ("B", comp.b)] {
            if let Some(a) = a {
                if a.nrows() != nr || a.ncols() != nr {
                    return Err(se_err(
                        &comp.name,
                        format!(
                            "{what} is {}x{}, expected {nr}x{nr} ({} boundary DOFs + {} \
                             interface coordinates + {} modes)",
                            a.nrows(),
                            a.ncols(),
                            comp.boundary_keys.len(),
                            comp.n_interface(),
                            comp.n_modes
                        ),
                    ));
                }
            }
        }
        let mut seen = BTreeSet::new();
        for key in &comp.boundary_keys {
            if !(1..=6).contains(&key.comp) {
                return Err(se_err(
                    &comp.name,
                    format!(
                        "grid {} has DOF component {} (not 1..6)",
                        key.grid, key.comp
                    ),
                ));
            }
            if !seen.insert(*key) {
                return Err(se_err(
                    &comp.name,
                    format!("boundary DOF grid {} comp {} repeated", key.grid, key.comp),
                ));
            }
            owners.entry(*key).or_default().push(c);
        }
        if components[..c].iter().any(|o| o.name == comp.name) {
            return Err(se_err(&comp.name, "two components have this name".into()));
        }
    }
    // An interface-reduced grid DOF is recovered from its component's interface
    // coordinates: no other component may hold it as a physical DOF, and it cannot be fixed.
    let mut recovered_keys: BTreeMap<DofKey, usize> = BTreeMap::new();
    for (c, comp) in components.iter().enumerate() {
        for key in comp.interface.iter().flat_map(|(k, _)| k) {
            let clash = owners
                .get(key)
                .map(|o| components[o[0]].name.as_str())
                .or_else(|| {
                    recovered_keys
                        .get(key)
                        .map(|&o| components[o].name.as_str())
                })
                .or_else(|| fixed_set.contains(key).then_some("(fixed)"));
            if let Some(other) = clash {
                return Err(se_err(
                    &comp.name,
                    format!(
                        "interface DOF grid {} comp {} is also a DOF of `{other}`; shared or \
                         fixed grid DOFs must stay physical boundary DOFs",
                        key.grid, key.comp
                    ),
                ));
            }
            recovered_keys.insert(*key, c);
        }
    }
    for key in &fixed_set {
        if !owners.contains_key(key) {
            return Err(se_err(
                "(fixed)",
                format!(
                    "fixed DOF grid {} comp {} is in no component",
                    key.grid, key.comp
                ),
            ));
        }
    }
    let mut dofs = Vec::new();
    let mut grid_index: BTreeMap<DofKey, usize> = BTreeMap::new();
    for (key, own) in &owners {
        if fixed_set.contains(key) {
            continue;
        }
        grid_index.insert(*key, dofs.len());
        dofs.push(ReducedDof {
            component: components[own[0]].name.clone(),
            shared_with: own[1..]
                .iter()
                .map(|&c| components[c].name.clone())
                .collect(),
            kind: DofKind::Grid {
                grid: key.grid,
                comp: key.comp,
            },
        });
    }
    let n_grid = dofs.len();
    let n_shared = owners
        .iter()
        .filter(|(k, o)| o.len() > 1 && !fixed_set.contains(k))
        .count();
    // Local-to-global maps (None = fixed).
    let mut maps: Vec<Vec<Option<usize>>> = Vec::with_capacity(components.len());
    let mut recovered = Vec::new();
    for comp in components {
        let mut map: Vec<Option<usize>> = comp
            .boundary_keys
            .iter()
            .map(|k| grid_index.get(k).copied())
            .collect();
        let first_interface = dofs.len();
        for p in 0..comp.n_interface() {
            map.push(Some(dofs.len()));
            dofs.push(ReducedDof {
                component: comp.name.clone(),
                shared_with: Vec::new(),
                kind: DofKind::Interface { index: p },
            });
        }
        if let Some((keys, l)) = &comp.interface {
            for (r, key) in keys.iter().enumerate() {
                let (idx, coefs): (Vec<usize>, Vec<Real>) = (0..l.ncols())
                    .filter(|&c| l[(r, c)] != 0.0)
                    .map(|c| (first_interface + c, l[(r, c)]))
                    .unzip();
                recovered.push(RecoveredDof {
                    component: comp.name.clone(),
                    grid: key.grid,
                    comp: key.comp,
                    dofs: idx,
                    coefs,
                });
            }
        }
        for q in 0..comp.n_modes {
            map.push(Some(dofs.len()));
            dofs.push(ReducedDof {
                component: comp.name.clone(),
                shared_with: Vec::new(),
                kind: DofKind::Modal { index: q },
            });
        }
        maps.push(map);
    }
    let n = dofs.len();
    // which: 0 = K, 1 = M, 2 = B.
    let scatter = |which: u8| -> Mat<Real> {
        let mut g = Mat::<Real>::zeros(n, n);
        for (comp, map) in components.iter().zip(&maps) {
            let a = match which {
                0 => Some(comp.k),
                1 => Some(comp.m),
                _ => comp.b,
            };
            if let Some(a) = a {
                for (j, gj) in map.iter().enumerate() {
                    let Some(gj) = gj else { continue };
                    for (i, gi) in map.iter().enumerate() {
                        if let Some(gi) = gi {
                            g[(*gi, *gj)] += a[(i, j)];
                        }
                    }
                }
            }
        }
        g
    };
    let n_interface: usize = components.iter().map(|c| c.n_interface()).sum();
    let n_recovered = recovered.len();
    let k = scatter(0);
    let m = scatter(1);
    let b = components.iter().any(|c| c.b.is_some()).then(|| scatter(2));
    Ok(Assembly {
        k,
        m,
        b,
        dofs: ReducedDofMap { dofs, recovered },
        stats: AssemblyStats {
            n_components: components.len(),
            n_grid_dofs: n_grid,
            n_shared_dofs: n_shared,
            n_fixed_dofs: fixed_set.len(),
            n_modal_dofs: n - n_grid - n_interface,
            n_interface_coords: n_interface,
            n_recovered_dofs: n_recovered,
        },
    })
}
