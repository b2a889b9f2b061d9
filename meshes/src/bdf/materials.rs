//! PSOLID → MAT1 / MAT9 → [`Section`], with the material coordinate system CORDM.
//!
//! # Reference
//! MSC Nastran Quick Reference Guide, MAT1: of E, G and ν any two define the third through
//! $G = E / (2(1+ν))$ (when all three are given, E and ν are used and a G that differs from
//! theirs by more than 1e-6 relative is reported); MAT9: the 21 entries $G_{ij}$, i ≤ j, of
//! the symmetric 6×6 stiffness in the strain order ε_x, ε_y, ε_z, γ_xy, γ_yz, γ_zx (permuted
//! into this crate's Voigt order 11, 22, 33, 23, 13, 12, [`crate::section`]), in the material
//! coordinate system of the
//! PSOLID's CORDM (0: basic; a CORD id, rectangular, cylindrical or spherical; −1, the
//! element coordinate system, is read for isotropic materials only, where it has no effect).
//! MAT1's GE (field 8) and MAT9's GE (field 31) are the material's structural loss factor η
//! ([`MaterialData::structural_damping`]), applied by the pipeline as (η/W4)·K of its elements.

use super::coords::Resolved;
use super::model::{Bulk, Mat, MatCard, Psolid};
use crate::deck::Deck;
use crate::section::{Elastic, MaterialData, Section};
use crate::MeshError;

/// The section of property `p`; `notes` gets what the reader changed or left out.
pub(crate) fn section(
    bulk: &Bulk,
    deck: &Deck,
    resolved: &Resolved,
    p: &Psolid,
    notes: &mut Vec<String>,
) -> Result<Section, MeshError> {
    let Some(m) = bulk.mats.get(&p.mid) else {
        if let Some((card, at)) = bulk.other_mats.get(&p.mid) {
            let why = match card.as_str() {
                "MAT2" | "MAT8" => "a shell material, which a solid cannot use",
                _ => "a card squeal does not read",
            };
            return Err(deck.err(
                p.at,
                format!(
                    "PSOLID {}: MID = {} is {card} {} ({}), {why}: give the material as MAT1 \
                     or MAT9 (its 6×6 stiffness), or set the scene's `materials.pid_{}`",
                    p.pid,
                    p.mid,
                    p.mid,
                    deck.at(*at),
                    p.pid
                ),
            ));
        }
        return Err(deck.err(
            p.at,
            format!(
                "PSOLID {}: MID = {}, which no MAT1 or MAT9 card defines",
                p.pid, p.mid
            ),
        ));
    };
    let material = material(deck, m, notes)?;
    let isotropic = matches!(material.elastic, Elastic::Isotropic { .. });
    let axes = match p.cordm {
        0 => None,
        -1 if isotropic => None,
        -1 => {
            return Err(deck.err(
                p.at,
                format!(
                    "PSOLID {}: CORDM = -1 (the element coordinate system) with the \
                     anisotropic MAT9 {}: per-element material axes from Nastran's element \
                     systems are not yet supported; give CORDM a coordinate system",
                    p.pid, p.mid
                ),
            ))
        }
        id => {
            let Some(s) = resolved.systems.get(&(id as u64)) else {
                return Err(deck.err(
                    p.at,
                    format!(
                        "PSOLID {}: CORDM = {id}, which no coordinate card defines",
                        p.pid
                    ),
                ));
            };
            Some(s.material_axes())
        }
    };
    if let Some(i) = &p.integration {
        notes.push(format!(
            "{}: PSOLID {} gives {i}; squeal integrates each element with its own rule \
             (docs/elements.md)",
            deck.at(p.at),
            p.pid
        ));
    }
    Ok(Section {
        material,
        axes,
        source: format!("{}: PSOLID {}", deck.at(p.at), p.pid),
    })
}

/// A MAT1 or MAT9 card as plain material data.
fn material(deck: &Deck, m: &MatCard, notes: &mut Vec<String>) -> Result<MaterialData, MeshError> {
    let err = |msg: String| deck.err(m.at, msg);
    let (name, elastic, rho, ge) = match &m.mat {
        Mat::Mat1 { e, g, nu, rho, ge } => {
            let name = format!("MAT1 {}", m.id);
            let (young, poisson) = match (*e, *g, *nu) {
                (Some(e), Some(g), Some(nu)) => {
                    let g_en = e / (2.0 * (1.0 + nu));
                    if ((g - g_en) / g_en).abs() > 1e-6 {
                        notes.push(format!(
                            "{}: {name} gives E = {e}, G = {g}, NU = {nu}, and G differs from \
                             E/(2(1+NU)) = {g_en}: squeal's isotropic solid uses E and NU",
                            deck.at(m.at)
                        ));
                    }
                    (e, nu)
                }
                (Some(e), None, Some(nu)) => (e, nu),
                (Some(e), Some(g), None) => (e, e / (2.0 * g) - 1.0),
                (None, Some(g), Some(nu)) => (2.0 * (1.0 + nu) * g, nu),
                _ => {
                    return Err(err(format!(
                        "{name}: give two of E, G, NU (a solid needs both its moduli)"
                    )))
                }
            };
            if !(young > 0.0 && young.is_finite() && poisson > -1.0 && poisson < 0.5) {
                return Err(err(format!(
                    "{name}: E = {young}, NU = {poisson} is not a stable isotropic solid \
                     (E > 0, -1 < NU < 0.5)"
                )));
            }
            (name, Elastic::Isotropic { young, poisson }, *rho, *ge)
        }
        Mat::Mat9 { g, rho, ge } => {
            let name = format!("MAT9 {}", m.id);
            // Nastran's xx, yy, zz, xy, yz, zx → Voigt 0, 1, 2, 5, 3, 4.
            const VOIGT: [usize; 6] = [0, 1, 2, 5, 3, 4];
            let mut c = [[0.0; 6]; 6];
            let mut k = 0;
            for i in 0..6 {
                for j in i..6 {
                    let (a, b) = (VOIGT[i], VOIGT[j]);
                    c[a][b] = g[k];
                    c[b][a] = g[k];
                    k += 1;
                }
            }
            (name, Elastic::Stiffness { c }, *rho, *ge)
        }
    };
    if let Some(r) = rho {
        if r.is_nan() || r <= 0.0 {
            return Err(err(format!("{name}: RHO = {r} must be > 0")));
        }
    }
    elastic.check().map_err(|m| err(format!("{name}: {m}")))?;
    if let Some(g) = ge {
        if !(g.is_finite() && g >= 0.0) {
            return Err(err(format!(
                "{name}: GE = {g} must be finite and >= 0 (the structural loss factor)"
            )));
        }
    }
    Ok(MaterialData {
        name,
        source: deck.at(m.at),
        elastic,
        density: rho,
        structural_damping: ge.filter(|&g| g != 0.0),
    })
}
