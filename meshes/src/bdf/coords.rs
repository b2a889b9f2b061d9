//! Coordinate systems (CORD1R/C/S, CORD2R/C/S, chained through their reference systems and
//! grids) and the grid positions in the basic system.
//!
//! # Reference
//! MSC Nastran Quick Reference Guide, CORD2R/CORD2C/CORD2S and CORD1x: the origin A, a point B
//! on the z axis and a point C in the x–z plane (given in the reference system RID, or as
//! GRIDs for CORD1x) define
//! $$ e_z = \frac{B-A}{|B-A|},\quad e_x = \frac{(C-A) - ((C-A)\cdot e_z)e_z}{|\dots|},\quad
//!    e_y = e_z \times e_x. $$
//! A point with coordinates u in a system is at $A + \sum_i p_i e_i$ in basic, with
//! p = u (rectangular), $p = (r\cos θ, r\sin θ, z)$ for u = (r, θ°, z) (cylindrical),
//! $p = (r\sin θ\cos φ, r\sin θ\sin φ, r\cos θ)$ for u = (r, θ°, φ°) (spherical).

use super::model::{Bulk, CoordDef, CoordKind};
use crate::deck::Deck;
use crate::section::{AxesKind, MaterialAxes};
use crate::MeshError;
use std::collections::HashMap;

/// A resolved coordinate system: kind, origin and unit axes (rows) in basic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct System {
    pub kind: CoordKind,
    pub origin: [f64; 3],
    pub axes: [[f64; 3]; 3],
}

impl System {
    pub const BASIC: System = System {
        kind: CoordKind::Rectangular,
        origin: [0.0; 3],
        axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// Basic position of the point with coordinates `u` in this system.
    pub fn to_basic(self, u: [f64; 3]) -> [f64; 3] {
        let p = match self.kind {
            CoordKind::Rectangular => u,
            CoordKind::Cylindrical => {
                let (s, c) = u[1].to_radians().sin_cos();
                [u[0] * c, u[0] * s, u[2]]
            }
            CoordKind::Spherical => {
                let (st, ct) = u[1].to_radians().sin_cos();
                let (sp, cp) = u[2].to_radians().sin_cos();
                [u[0] * st * cp, u[0] * st * sp, u[0] * ct]
            }
        };
        [0, 1, 2].map(|k| self.origin[k] + (0..3).map(|i| p[i] * self.axes[i][k]).sum::<f64>())
    }

    /// The system's unit axes at the basic point `x` (rows; for cylindrical and spherical
    /// systems the local r, θ, z or r, θ, φ directions), or None on the axis or centre where
    /// they are undefined.
    pub fn axes_at(&self, x: [f64; 3]) -> Option<[[f64; 3]; 3]> {
        let ax = self.material_axes();
        let d: [f64; 3] = [0, 1, 2].map(|k| x[k] - self.origin[k]);
        let l = self.axes.map(|e| e[0] * d[0] + e[1] * d[1] + e[2] * d[2]);
        let r_xy = l[0].hypot(l[1]);
        let scale = d.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        match self.kind {
            CoordKind::Rectangular => Some(self.axes),
            _ if r_xy <= 1e-12 * scale || r_xy == 0.0 => None,
            _ => Some(ax.at(x)),
        }
    }

    /// The system as material axes.
    pub fn material_axes(&self) -> MaterialAxes {
        MaterialAxes {
            kind: match self.kind {
                CoordKind::Rectangular => AxesKind::Rectangular,
                CoordKind::Cylindrical => AxesKind::Cylindrical,
                CoordKind::Spherical => AxesKind::Spherical,
            },
            origin: self.origin,
            frame: self.axes,
        }
    }
}

/// Every coordinate system and grid position, in basic.
pub(crate) struct Resolved {
    pub systems: HashMap<u64, System>,
    /// Grid id → (index into `bulk.grids`, basic position).
    pub grids: HashMap<u64, (usize, [f64; 3])>,
}

/// Resolves the systems and the grid positions; errors name the card whose reference is
/// missing, or the cards of a reference cycle.
pub(crate) fn resolve(bulk: &Bulk, deck: &Deck) -> Result<Resolved, MeshError> {
    let mut grid_index: HashMap<u64, usize> = HashMap::with_capacity(bulk.grids.len());
    for (i, g) in bulk.grids.iter().enumerate() {
        if let Some(&j) = grid_index.get(&g.id) {
            let o = &bulk.grids[j];
            if o.cp != g.cp || o.x != g.x || o.cd != g.cd || o.ps != g.ps {
                return Err(deck.err(
                    g.at,
                    format!(
                        "GRID {}: defined again with other data (first at {})",
                        g.id,
                        deck.at(o.at)
                    ),
                ));
            }
            continue;
        }
        grid_index.insert(g.id, i);
    }
    let mut card_of: HashMap<u64, usize> = HashMap::new();
    for (i, c) in bulk.coords.iter().enumerate() {
        if c.id == 0 {
            return Err(deck.err(c.at, format!("{} 0: system 0 is the basic system", c.card)));
        }
        if let Some(&j) = card_of.get(&c.id) {
            return Err(deck.err(
                c.at,
                format!(
                    "{} {}: coordinate system id also defined at {}",
                    c.card,
                    c.id,
                    deck.at(bulk.coords[j].at)
                ),
            ));
        }
        card_of.insert(c.id, i);
    }
    let mut systems: HashMap<u64, System> = HashMap::new();
    systems.insert(0, System::BASIC);
    let mut grids: HashMap<u64, (usize, [f64; 3])> = HashMap::with_capacity(grid_index.len());
    let mut pending_grids: Vec<usize> = grid_index.values().copied().collect();
    pending_grids.sort_unstable();
    let mut pending_coords: Vec<usize> = (0..bulk.coords.len()).collect();
    loop {
        let before = pending_grids.len() + pending_coords.len();
        pending_grids.retain(|&i| {
            let g = &bulk.grids[i];
            match systems.get(&g.cp) {
                Some(s) => {
                    grids.insert(g.id, (i, s.to_basic(g.x)));
                    false
                }
                None => true,
            }
        });
        let mut err = None;
        pending_coords.retain(|&i| {
            if err.is_some() {
                return true;
            }
            let c = &bulk.coords[i];
            let points = match &c.def {
                CoordDef::Points { rid, a, b, c } => systems
                    .get(rid)
                    .map(|s| [s.to_basic(*a), s.to_basic(*b), s.to_basic(*c)]),
                CoordDef::Grids { g } => {
                    let p: Vec<_> = g.iter().filter_map(|id| grids.get(id)).collect();
                    (p.len() == 3).then(|| [p[0].1, p[1].1, p[2].1])
                }
            };
            let Some([a, b, cc]) = points else {
                return true;
            };
            match frame(a, b, cc) {
                Some(axes) => {
                    systems.insert(
                        c.id,
                        System {
                            kind: c.kind,
                            origin: a,
                            axes,
                        },
                    );
                    false
                }
                None => {
                    err = Some(deck.err(
                        c.at,
                        format!(
                            "{} {}: its points A, B, C are (nearly) collinear in basic ({a:?}, \
                             {b:?}, {cc:?}): no axes",
                            c.card, c.id
                        ),
                    ));
                    true
                }
            }
        });
        if let Some(e) = err {
            return Err(e);
        }
        if pending_grids.len() + pending_coords.len() == before {
            break;
        }
    }
    // What is left refers to something undefined, or to itself through a cycle.
    for &i in &pending_coords {
        let c = &bulk.coords[i];
        match &c.def {
            CoordDef::Points { rid, .. } if !card_of.contains_key(rid) => {
                return Err(deck.err(
                    c.at,
                    format!(
                        "{} {}: RID = {rid}, which no coordinate card defines",
                        c.card, c.id
                    ),
                ));
            }
            CoordDef::Grids { g } => {
                if let Some(id) = g.iter().find(|id| !grid_index.contains_key(id)) {
                    return Err(deck.err(
                        c.at,
                        format!("{} {}: GRID {id}, which no GRID card defines", c.card, c.id),
                    ));
                }
            }
            _ => {}
        }
    }
    for &i in &pending_grids {
        let g = &bulk.grids[i];
        if !card_of.contains_key(&g.cp) {
            return Err(deck.err(
                g.at,
                format!(
                    "GRID {}: CP = {}, which no coordinate card defines",
                    g.id, g.cp
                ),
            ));
        }
    }
    if let Some(&i) = pending_coords.first() {
        let names: Vec<String> = pending_coords
            .iter()
            .map(|&j| {
                let c = &bulk.coords[j];
                format!("{} {} ({})", c.card, c.id, deck.at(c.at))
            })
            .collect();
        let c = &bulk.coords[i];
        return Err(deck.err(
            c.at,
            format!(
                "coordinate systems defined through each other (a cycle): {}",
                names.join(", ")
            ),
        ));
    }
    if let Some(&i) = pending_grids.first() {
        let g = &bulk.grids[i];
        return Err(deck.err(
            g.at,
            format!("GRID {}: CP = {} is never resolved", g.id, g.cp),
        ));
    }
    Ok(Resolved { systems, grids })
}

/// Unit axes from origin `a`, z point `b`, x–z plane point `c`; None when degenerate.
fn frame(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<[[f64; 3]; 3]> {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let norm = |p: [f64; 3]| dot(p, p).sqrt();
    let ab = sub(b, a);
    let ac = sub(c, a);
    let scale = norm(ab).max(norm(ac));
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let lz = norm(ab);
    if lz <= 1e-10 * scale {
        return None;
    }
    let z = ab.map(|v| v / lz);
    let d = dot(ac, z);
    let xp = [ac[0] - d * z[0], ac[1] - d * z[1], ac[2] - d * z[2]];
    let lx = norm(xp);
    if lx <= 1e-10 * scale {
        return None;
    }
    let x = xp.map(|v| v / lx);
    let y = [
        z[1] * x[2] - z[2] * x[1],
        z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0],
    ];
    Some([x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cylindrical_and_spherical_points() {
        // A cylindrical system at (1, 0, 0) whose z axis is basic y and x axis basic z.
        let s = System {
            kind: CoordKind::Cylindrical,
            origin: [1.0, 0.0, 0.0],
            axes: frame([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]).unwrap(),
        };
        // r = 2, θ = 90° → along local y = basic x; z = 3 → along basic y.
        let p = s.to_basic([2.0, 90.0, 3.0]);
        let want = [3.0, 3.0, 0.0];
        for k in 0..3 {
            assert!((p[k] - want[k]).abs() < 1e-14, "{p:?}");
        }
        let sph = System {
            kind: CoordKind::Spherical,
            ..System::BASIC
        };
        // r = 2, θ = 90°, φ = 90° → (0, 2, 0).
        let p = sph.to_basic([2.0, 90.0, 90.0]);
        assert!((p[1] - 2.0).abs() < 1e-14 && p[0].abs() < 1e-14 && p[2].abs() < 1e-14);
        assert!(frame([0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 2.0]).is_none());
    }
}
