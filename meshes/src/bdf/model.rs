//! The bulk data cards squeal reads, typed; every other card counted by name.

use super::card::Fields;
use super::cards::{read_cards, Card, CaseControl};
use crate::deck::{Deck, Loc};
use crate::MeshError;
use std::collections::BTreeMap;

/// GRID: a point in coordinate system `cp`, displacements in `cd`, permanent constraints `ps`.
#[derive(Debug, Clone)]
pub(crate) struct Grid {
    pub id: u64,
    pub cp: u64,
    pub x: [f64; 3],
    pub cd: u64,
    pub ps: Vec<u8>,
    pub at: Loc,
}

/// How a coordinate system is defined.
#[derive(Debug, Clone)]
pub(crate) enum CoordDef {
    /// CORD2x: origin A, a point B on the z axis, a point C in the x–z plane, in system `rid`.
    Points {
        rid: u64,
        a: [f64; 3],
        b: [f64; 3],
        c: [f64; 3],
    },
    /// CORD1x: the same three points as GRID ids.
    Grids { g: [u64; 3] },
}

/// The kind of a coordinate system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CoordKind {
    Rectangular,
    Cylindrical,
    Spherical,
}

/// CORD1R/C/S, CORD2R/C/S.
#[derive(Debug, Clone)]
pub(crate) struct CoordCard {
    pub id: u64,
    pub kind: CoordKind,
    pub def: CoordDef,
    pub card: String,
    pub at: Loc,
}

/// Solid element shapes as Nastran names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum SolidCard {
    Chexa,
    Cpenta,
    Ctetra,
    Cpyram,
}

impl SolidCard {
    /// (corner count, full count with mid-edge nodes).
    pub fn counts(self) -> (usize, usize) {
        match self {
            SolidCard::Chexa => (8, 20),
            SolidCard::Cpenta => (6, 15),
            SolidCard::Ctetra => (4, 10),
            SolidCard::Cpyram => (5, 13),
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            SolidCard::Chexa => "CHEXA",
            SolidCard::Cpenta => "CPENTA",
            SolidCard::Ctetra => "CTETRA",
            SolidCard::Cpyram => "CPYRAM",
        }
    }
}

/// A solid element: grids in Nastran's order (corners, then the mid-edge nodes when given).
#[derive(Debug, Clone)]
pub(crate) struct Solid {
    pub id: u64,
    pub pid: u64,
    pub card: SolidCard,
    pub grids: Vec<u64>,
    pub at: Loc,
}

/// A shell element read as a face: CQUAD4, CQUAD8, CTRIA3, CTRIA6.
#[derive(Debug, Clone)]
pub(crate) struct Shell {
    pub id: u64,
    pub pid: u64,
    pub card: &'static str,
    /// Grids: corners, then mid-edge nodes (quad8: (1,2) (2,3) (3,4) (4,1); tri6: (1,2)
    /// (2,3) (3,1)) when given.
    pub grids: Vec<u64>,
    pub at: Loc,
}

/// PSOLID.
#[derive(Debug, Clone)]
pub(crate) struct Psolid {
    pub pid: u64,
    pub mid: u64,
    /// Material coordinate system: 0 basic, −1 element system, else a CORD id.
    pub cordm: i64,
    /// Integration options given (IN, ISOP), for a note: squeal's rule is the element's own.
    pub integration: Option<String>,
    pub at: Loc,
}

/// PSHELL (only whether it carries a structural shell, for the note on shells read as faces).
#[derive(Debug, Clone)]
pub(crate) struct Pshell {
    pub structural: bool,
}

/// MAT1 and MAT9.
#[derive(Debug, Clone)]
pub(crate) enum Mat {
    Mat1 {
        e: Option<f64>,
        g: Option<f64>,
        nu: Option<f64>,
        rho: Option<f64>,
        ge: Option<f64>,
    },
    /// The 21 upper-triangle entries G11, G12, …, G66 row by row.
    Mat9 {
        g: [f64; 21],
        rho: Option<f64>,
        ge: Option<f64>,
    },
}

/// A material card with its id and place.
#[derive(Debug, Clone)]
pub(crate) struct MatCard {
    pub id: u64,
    pub mat: Mat,
    pub at: Loc,
}

/// Constrained grids of an SPC or SPC1 set: one grid, or the grids that exist in an SPC1
/// `THRU` range (Nastran: the range's missing ids are ignored).
#[derive(Debug, Clone)]
pub(crate) struct SpcEntry {
    pub sid: u64,
    pub first: u64,
    pub last: u64,
    /// True for a `THRU` range.
    pub range: bool,
    pub comps: Vec<u8>,
    pub card: &'static str,
    pub at: Loc,
}

/// SPCADD: a set made of other sets.
#[derive(Debug, Clone)]
pub(crate) struct SpcAdd {
    pub sets: Vec<u64>,
    pub at: Loc,
}

/// SET1 (grid ids, single or `THRU` ranges of the ids that exist).
#[derive(Debug, Clone)]
pub(crate) struct Set1 {
    pub ids: Vec<(u64, u64, Loc)>,
}

/// Every card read, by kind; `unsupported`: card name → (count, first place).
#[derive(Debug, Default)]
pub(crate) struct Bulk {
    pub grids: Vec<Grid>,
    pub grdset: Option<(u64, u64, Vec<u8>)>,
    pub coords: Vec<CoordCard>,
    pub solids: Vec<Solid>,
    pub shells: Vec<Shell>,
    pub psolids: BTreeMap<u64, Psolid>,
    pub pshells: BTreeMap<u64, Pshell>,
    pub mats: BTreeMap<u64, MatCard>,
    pub spcs: Vec<SpcEntry>,
    pub spcadds: BTreeMap<u64, SpcAdd>,
    pub set1: BTreeMap<u64, Set1>,
    pub unsupported: BTreeMap<String, (usize, Loc)>,
    /// Material cards not read (MAT2, MAT8, MAT11, …): material id → (card name, place), so
    /// that a PSOLID naming one says which card it is.
    pub other_mats: BTreeMap<u64, (String, Loc)>,
    pub case: CaseControl,
}

/// Reads every card of `deck` into a [`Bulk`].
pub(crate) fn read_bulk(deck: &mut Deck) -> Result<Bulk, MeshError> {
    let mut bulk = Bulk::default();
    let case = read_cards(deck, |deck, card| add_card(&mut bulk, deck, &card))?;
    bulk.case = case;
    // GRDSET defaults apply to every GRID whatever the card order.
    if let Some((cp, cd, ps)) = bulk.grdset.clone() {
        for g in &mut bulk.grids {
            if g.cp == u64::MAX {
                g.cp = cp;
            }
            if g.cd == u64::MAX {
                g.cd = cd;
            }
            if g.ps.is_empty() {
                g.ps = ps.clone();
            }
        }
    }
    for g in &mut bulk.grids {
        if g.cp == u64::MAX {
            g.cp = 0;
        }
        if g.cd == u64::MAX {
            g.cd = 0;
        }
    }
    Ok(bulk)
}

fn add_card(bulk: &mut Bulk, deck: &Deck, card: &Card) -> Result<(), MeshError> {
    let f = Fields::new(deck, card);
    match card.name.as_str() {
        "GRID" => {
            // Blank CP/CD: the GRDSET default (u64::MAX until applied).
            let cp = match f.int(1, "CP")? {
                None => u64::MAX,
                Some(v) if v >= 0 => v as u64,
                Some(_) => return Err(f.err(1, "CP", "must be ≥ 0")),
            };
            let cd = match f.int(5, "CD")? {
                None => u64::MAX,
                Some(v) if v >= 0 => v as u64,
                Some(-1) => {
                    return Err(f.err(5, "CD", "−1 is a fluid grid, which squeal does not read"))
                }
                Some(_) => return Err(f.err(5, "CD", "must be ≥ 0")),
            };
            bulk.grids.push(Grid {
                id: f.id(0, "ID")?,
                cp,
                x: [
                    f.real_or(2, "X1", 0.0)?,
                    f.real_or(3, "X2", 0.0)?,
                    f.real_or(4, "X3", 0.0)?,
                ],
                cd,
                ps: f.components(6, "PS")?,
                at: card.at,
            });
            if !f.text(7).is_empty() {
                f.int(7, "SEQ")?;
            }
        }
        "GRDSET" => {
            if bulk.grdset.is_some() {
                return Err(f.card_err("a second GRDSET"));
            }
            bulk.grdset = Some((
                f.nonneg(1, "CP", 0)?,
                f.nonneg(5, "CD", 0)?,
                f.components(6, "PS")?,
            ));
        }
        "CORD2R" | "CORD2C" | "CORD2S" => {
            let r = |i: usize, w: &str| f.real_or(i, w, 0.0);
            bulk.coords.push(CoordCard {
                id: f.id(0, "CID")?,
                kind: coord_kind(&card.name),
                def: CoordDef::Points {
                    rid: f.nonneg(1, "RID", 0)?,
                    a: [r(2, "A1")?, r(3, "A2")?, r(4, "A3")?],
                    b: [r(5, "B1")?, r(6, "B2")?, r(7, "B3")?],
                    c: [r(8, "C1")?, r(9, "C2")?, r(10, "C3")?],
                },
                card: card.name.clone(),
                at: card.at,
            });
        }
        "CORD1R" | "CORD1C" | "CORD1S" => {
            // One or two systems per card.
            for k in 0..2 {
                let o = 4 * k;
                if k == 1 && (o..o + 4).all(|i| f.text(i).is_empty()) {
                    break;
                }
                bulk.coords.push(CoordCard {
                    id: f.id(o, "CID")?,
                    kind: coord_kind(&card.name),
                    def: CoordDef::Grids {
                        g: [f.id(o + 1, "G1")?, f.id(o + 2, "G2")?, f.id(o + 3, "G3")?],
                    },
                    card: card.name.clone(),
                    at: card.at,
                });
            }
        }
        "CHEXA" | "CPENTA" | "CTETRA" | "CPYRAM" => {
            let kind = match card.name.as_str() {
                "CHEXA" => SolidCard::Chexa,
                "CPENTA" => SolidCard::Cpenta,
                "CTETRA" => SolidCard::Ctetra,
                _ => SolidCard::Cpyram,
            };
            let id = f.id(0, "EID")?;
            let pid = f.opt_id(1, "PID")?.unwrap_or(id);
            let grids = element_grids(&f, 2, kind.counts(), kind.name())?;
            bulk.solids.push(Solid {
                id,
                pid,
                card: kind,
                grids,
                at: card.at,
            });
        }
        "CQUAD4" | "CTRIA3" | "CQUAD8" | "CTRIA6" => {
            let (name, counts, last): (&'static str, (usize, usize), usize) =
                match card.name.as_str() {
                    "CQUAD4" => ("CQUAD4", (4, 4), 4),
                    "CTRIA3" => ("CTRIA3", (3, 3), 3),
                    "CQUAD8" => ("CQUAD8", (4, 8), 8),
                    _ => ("CTRIA6", (3, 6), 6),
                };
            let id = f.id(0, "EID")?;
            let pid = f.opt_id(1, "PID")?.unwrap_or(id);
            // Shell fields after the grids (thickness, offsets) are not read.
            let grids = shell_grids(&f, counts, last, name)?;
            bulk.shells.push(Shell {
                id,
                pid,
                card: name,
                grids,
                at: card.at,
            });
        }
        "PSOLID" => {
            let pid = f.id(0, "PID")?;
            let cordm = f.int(2, "CORDM")?.unwrap_or(0);
            if cordm < -1 {
                return Err(f.err(2, "CORDM", "must be −1, 0 or a coordinate system id"));
            }
            let fctn = f.text(6).to_ascii_uppercase();
            if !fctn.is_empty() && fctn != "SMECH" {
                return Err(f.err(6, "FCTN", "only structural solids (SMECH) are read"));
            }
            let integration = [(3, "IN"), (5, "ISOP")]
                .iter()
                .filter(|(i, _)| !f.text(*i).is_empty())
                .map(|(i, w)| format!("{w} = {}", f.text(*i)))
                .collect::<Vec<_>>();
            let p = Psolid {
                pid,
                mid: f.id(1, "MID")?,
                cordm,
                integration: (!integration.is_empty()).then(|| integration.join(", ")),
                at: card.at,
            };
            if bulk.psolids.insert(pid, p).is_some() {
                return Err(f.card_err("PSOLID id defined twice"));
            }
        }
        "PSHELL" => {
            let pid = f.id(0, "PID")?;
            let mid1 = f.opt_id(1, "MID1")?;
            let t = f.real(2, "T")?;
            let mid2 = f.int(3, "MID2")?;
            let structural =
                (mid1.is_some() || mid2.is_some_and(|m| m > 0)) && t.is_some_and(|t| t > 0.0);
            bulk.pshells.insert(pid, Pshell { structural });
        }
        "MAT1" => {
            let id = f.id(0, "MID")?;
            let mat = Mat::Mat1 {
                e: f.real(1, "E")?,
                g: f.real(2, "G")?,
                nu: f.real(3, "NU")?,
                rho: f.real(4, "RHO")?,
                ge: f.real(7, "GE")?,
            };
            add_mat(bulk, &f, id, mat)?;
        }
        "MAT9" => {
            let id = f.id(0, "MID")?;
            let mut g = [0.0; 21];
            for (k, v) in g.iter_mut().enumerate() {
                *v = f.real_or(1 + k, &format!("G{}", gij_name(k)), 0.0)?;
            }
            let mat = Mat::Mat9 {
                g,
                rho: f.real(22, "RHO")?,
                ge: f.real(30, "GE")?,
            };
            add_mat(bulk, &f, id, mat)?;
        }
        "SPC1" => {
            let sid = f.id(0, "SID")?;
            let comps = f.components(1, "C")?;
            for (first, last, i) in f.id_ranges(2, "G")? {
                bulk.spcs.push(SpcEntry {
                    sid,
                    first,
                    last,
                    range: f.text(i + 1).eq_ignore_ascii_case("THRU"),
                    comps: comps.clone(),
                    card: "SPC1",
                    at: f.at(i),
                });
            }
        }
        "SPC" => {
            let sid = f.id(0, "SID")?;
            for k in 0..2 {
                let o = 1 + 3 * k;
                if k == 1 && (o..o + 3).all(|i| f.text(i).is_empty()) {
                    break;
                }
                let d = f.real_or(o + 2, "D", 0.0)?;
                if d != 0.0 {
                    return Err(f.err(
                        o + 2,
                        "D",
                        "an enforced displacement; squeal holds constrained DOFs at zero",
                    ));
                }
                let g = f.id(o, "G")?;
                bulk.spcs.push(SpcEntry {
                    sid,
                    first: g,
                    last: g,
                    range: false,
                    comps: f.components(o + 1, "C")?,
                    card: "SPC",
                    at: f.at(o),
                });
            }
        }
        "SPCADD" => {
            let sid = f.id(0, "SID")?;
            let mut sets = Vec::new();
            for (a, b, i) in f.id_ranges(1, "S")? {
                if b - a > 1000 {
                    return Err(f.err(i, "S", "a range of more than 1000 set ids"));
                }
                sets.extend(a..=b);
            }
            if bulk
                .spcadds
                .insert(sid, SpcAdd { sets, at: card.at })
                .is_some()
            {
                return Err(f.card_err("SPCADD id defined twice"));
            }
        }
        "SET1" => {
            let sid = f.id(0, "SID")?;
            if f.text(1).eq_ignore_ascii_case("SKIN") {
                return Err(f.err(1, "SKIN", "SET1 with SKIN is not read"));
            }
            let ids = f
                .id_ranges(1, "ID")?
                .into_iter()
                .map(|(a, b, i)| (a, b, f.at(i)))
                .collect();
            if bulk.set1.insert(sid, Set1 { ids }).is_some() {
                return Err(f.card_err("SET1 id defined twice"));
            }
        }
        other => {
            if other.starts_with("MAT") {
                if let Ok(Some(mid)) = f.opt_id(0, "MID") {
                    bulk.other_mats
                        .entry(mid)
                        .or_insert((other.to_string(), card.at));
                }
            }
            let e = bulk
                .unsupported
                .entry(other.to_string())
                .or_insert((0, card.at));
            e.0 += 1;
        }
    }
    Ok(())
}

fn add_mat(bulk: &mut Bulk, f: &Fields, id: u64, mat: Mat) -> Result<(), MeshError> {
    if let Some(old) = bulk.mats.get(&id) {
        return Err(f.card_err(format!(
            "material id {id} is also defined at {}",
            f.deck.at(old.at)
        )));
    }
    bulk.mats.insert(
        id,
        MatCard {
            id,
            mat,
            at: f.card.at,
        },
    );
    Ok(())
}

/// `ij` of the k-th upper-triangle entry of a 6×6 matrix (row by row): 11, 12, …, 66.
pub(crate) fn gij_name(k: usize) -> String {
    let (mut i, mut left) = (0, k);
    while left >= 6 - i {
        left -= 6 - i;
        i += 1;
    }
    format!("{}{}", i + 1, i + left + 1)
}

fn coord_kind(name: &str) -> CoordKind {
    match name.as_bytes().last() {
        Some(b'C') => CoordKind::Cylindrical,
        Some(b'S') => CoordKind::Spherical,
        _ => CoordKind::Rectangular,
    }
}

/// Grid fields `from..from + full` of a solid: the corners must all be given; the mid-edge
/// nodes all or none (Nastran's partial mid-edge sets are not read).
fn element_grids(
    f: &Fields,
    from: usize,
    (corners, full): (usize, usize),
    name: &str,
) -> Result<Vec<u64>, MeshError> {
    let mut g: Vec<Option<u64>> = Vec::with_capacity(full);
    for k in 0..full {
        g.push(f.opt_id(from + k, &format!("G{}", k + 1))?);
    }
    if f.len() > from + full {
        return Err(f.err(
            from + full,
            "a field after the last grid",
            format!("{name} has at most {full} grids"),
        ));
    }
    if let Some(k) = (0..corners).find(|&k| g[k].is_none()) {
        return Err(f.err(
            from + k,
            &format!("G{}", k + 1),
            "a corner grid is required",
        ));
    }
    let mids = g[corners..].iter().filter(|x| x.is_some()).count();
    if mids != 0 && mids != full - corners {
        let missing = (corners..full)
            .filter(|&k| g[k].is_none())
            .map(|k| format!("G{}", k + 1))
            .collect::<Vec<_>>()
            .join(", ");
        return Err(f.card_err(format!(
            "has {mids} of its {} mid-edge grids (missing {missing}); squeal reads {name} with \
             all mid-edge grids or none",
            full - corners
        )));
    }
    Ok(g.into_iter().flatten().collect())
}

/// Grids of a shell read as a face.
fn shell_grids(
    f: &Fields,
    (corners, full): (usize, usize),
    last: usize,
    name: &str,
) -> Result<Vec<u64>, MeshError> {
    let mut g: Vec<Option<u64>> = Vec::with_capacity(full);
    for k in 0..full.max(last) {
        g.push(f.opt_id(2 + k, &format!("G{}", k + 1))?);
    }
    if let Some(k) = (0..corners).find(|&k| g[k].is_none()) {
        return Err(f.err(2 + k, &format!("G{}", k + 1), "a corner grid is required"));
    }
    let mids = g[corners..full].iter().filter(|x| x.is_some()).count();
    if mids != 0 && mids != full - corners {
        return Err(f.card_err(format!(
            "has {mids} of its {} mid-edge grids; squeal reads {name} with all or none",
            full - corners
        )));
    }
    Ok(g[..full].iter().flatten().copied().collect())
}

#[cfg(test)]
mod tests {
    #[test]
    fn gij_names() {
        let names: Vec<String> = (0..21).map(super::gij_name).collect();
        assert_eq!(names[0], "11");
        assert_eq!(names[5], "16");
        assert_eq!(names[6], "22");
        assert_eq!(names[11], "33");
        assert_eq!(names[20], "66");
    }
}
