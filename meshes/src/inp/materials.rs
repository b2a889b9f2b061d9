//! *MATERIAL with *ELASTIC and *DENSITY, and *ORIENTATION, into [`Section`]s.
//!
//! # Reference
//! Abaqus Analysis User's Guide, "Linear elastic behavior": TYPE=ISOTROPIC (E, ν),
//! ENGINEERING CONSTANTS (E1, E2, E3, ν12, ν13, ν23, G12, G13, G23), ORTHOTROPIC (D1111,
//! D1122, D2222, D1133, D2233, D3333, D1212, D1313, D2323), ANISOTROPIC (the 21 D_ijkl in the
//! order 1111, 1122, 2222, 1133, 2233, 3333, 1112, 2212, 3312, 1212, 1113, 2213, 3313, 1213,
//! 1313, 1123, 2223, 3323, 1223, 1323, 2323), all with engineering shear strains, permuted
//! here into this crate's Voigt order 11, 22, 33, 23, 13, 12 ([`crate::section`]).
//! "Orientations": SYSTEM=RECTANGULAR, a on the local 1 axis, b in the 1–2 plane, c the origin
//! (default the global origin); CYLINDRICAL, a and b on the axis (local 3 from a to b; 1
//! radial, 2 tangential); SPHERICAL, a the centre, b on the polar axis. An additional rotation
//! about a local axis (the second data line) is read for rectangular systems.

use super::keywords::{name_text, real, Block};
use crate::deck::{shorten, Deck, Loc};
use crate::section::{AxesKind, Elastic, MaterialAxes};
use crate::MeshError;

/// A *MATERIAL and the options read for it.
#[derive(Debug, Clone)]
pub(crate) struct MaterialDef {
    pub name: String,
    pub at: Loc,
    pub elastic: Option<(Elastic, Loc)>,
    pub density: Option<f64>,
    /// Options of the material not read (keyword, place).
    pub ignored: Vec<(String, Loc)>,
    /// *DAMPING values given and not read (ALPHA, BETA, COMPOSITE), for the note.
    pub damping: Option<String>,
    /// *DAMPING, STRUCTURAL=η: the structural loss factor (finite, >= 0).
    pub structural: Option<f64>,
}

impl MaterialDef {
    pub fn new(name: String, at: Loc) -> Self {
        MaterialDef {
            name,
            at,
            elastic: None,
            density: None,
            ignored: Vec::new(),
            damping: None,
            structural: None,
        }
    }
}

/// Keywords that belong to a *MATERIAL definition (those after ELASTIC and DENSITY are
/// listed as not read).
const MATERIAL_OPTIONS: [&str; 22] = [
    "ELASTIC",
    "DENSITY",
    "DAMPING",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "PLASTIC",
    "HYPERELASTIC",
    "HYPERFOAM",
    "VISCOELASTIC",
    "CREEP",
    "DEPVAR",
    "USER MATERIAL",
    "LATENT HEAT",
    "DIFFUSIVITY",
    "SOLUBILITY",
    "FAIL STRESS",
    "FAIL STRAIN",
    "HARDENING",
    "RATE DEPENDENT",
    "POROUS ELASTIC",
    "MATERIAL DAMPING",
];

/// Reads `b` into `mat` when it is a material option (true), else false (the material ends).
pub(crate) fn read_material_option(
    deck: &Deck,
    b: &Block,
    mat: &mut MaterialDef,
) -> Result<bool, MeshError> {
    let kw = b.keyword.as_str();
    if !MATERIAL_OPTIONS.contains(&kw) {
        return Ok(false);
    }
    let who = format!("*MATERIAL {}: *{kw}", mat.name);
    match kw {
        "ELASTIC" => {
            if mat.elastic.is_some() {
                return Err(deck.err(b.at, format!("{who} given twice")));
            }
            if b.flag("DEPENDENCIES") || b.flag("MODULI") {
                return Err(deck.err(
                    b.at,
                    format!("{who}: DEPENDENCIES and MODULI are not read (one linear elastic behaviour)"),
                ));
            }
            let ty = b
                .param("TYPE")
                .map(|t| t.trim().to_ascii_uppercase())
                .unwrap_or_else(|| "ISOTROPIC".into());
            let (want, per_line): (usize, usize) = match ty.as_str() {
                "ISOTROPIC" => (2, 3),
                "ENGINEERING CONSTANTS" => (9, 8),
                "ORTHOTROPIC" => (9, 8),
                "ANISOTROPIC" => (21, 8),
                other => {
                    return Err(deck.err(
                        b.at,
                        format!(
                            "{who}, TYPE={other}: squeal reads ISOTROPIC, ENGINEERING \
                             CONSTANTS, ORTHOTROPIC and ANISOTROPIC"
                        ),
                    ))
                }
            };
            let v = values(deck, b, &who, want, per_line)?;
            let e = match ty.as_str() {
                "ISOTROPIC" => Elastic::Isotropic {
                    young: v[0],
                    poisson: v[1],
                },
                "ENGINEERING CONSTANTS" => Elastic::EngineeringConstants {
                    young: [v[0], v[1], v[2]],
                    poisson: [v[3], v[4], v[5]],
                    shear: [v[6], v[7], v[8]],
                },
                "ORTHOTROPIC" => {
                    let mut c = [[0.0; 6]; 6];
                    let set = |c: &mut [[f64; 6]; 6], i: usize, j: usize, x: f64| {
                        c[i][j] = x;
                        c[j][i] = x;
                    };
                    set(&mut c, 0, 0, v[0]);
                    set(&mut c, 0, 1, v[1]);
                    set(&mut c, 1, 1, v[2]);
                    set(&mut c, 0, 2, v[3]);
                    set(&mut c, 1, 2, v[4]);
                    set(&mut c, 2, 2, v[5]);
                    set(&mut c, 5, 5, v[6]);
                    set(&mut c, 4, 4, v[7]);
                    set(&mut c, 3, 3, v[8]);
                    Elastic::Stiffness { c }
                }
                _ => Elastic::Stiffness { c: anisotropic(&v) },
            };
            e.check()
                .map_err(|m| deck.err(b.at, format!("{who}: {m}")))?;
            mat.elastic = Some((e, b.at));
        }
        "DENSITY" => {
            if b.flag("DEPENDENCIES") {
                return Err(deck.err(b.at, format!("{who}: DEPENDENCIES is not read")));
            }
            let v = values(deck, b, &who, 1, 2)?;
            if v[0].is_nan() || v[0] <= 0.0 {
                return Err(deck.err(b.at, format!("{who}: density {} must be > 0", v[0])));
            }
            mat.density = Some(v[0]);
        }
        "DAMPING" => {
            if mat.structural.is_some() || mat.damping.is_some() {
                return Err(deck.err(b.at, format!("{who} given twice")));
            }
            if let Some(v) = b.param("STRUCTURAL") {
                let eta = real(v).ok_or_else(|| {
                    deck.err(
                        b.at,
                        format!("{who}: STRUCTURAL={v} is not a number (the loss factor)"),
                    )
                })?;
                if eta < 0.0 {
                    return Err(deck.err(
                        b.at,
                        format!(
                            "{who}: STRUCTURAL={eta} must be >= 0 (the structural loss factor)"
                        ),
                    ));
                }
                mat.structural = Some(eta);
            }
            let others: Vec<String> = b
                .params
                .iter()
                .filter(|(n, _)| n != "STRUCTURAL")
                .filter_map(|(n, v)| v.as_ref().map(|v| format!("{n}={v}")))
                .collect();
            if !others.is_empty() {
                mat.damping = Some(others.join(", "));
            }
        }
        _ => mat.ignored.push((format!("*{kw}"), b.at)),
    }
    Ok(true)
}

/// The `want` constants of the one data set (`per_line` per line; a temperature or field
/// variables after them are read over: with one set they do not matter; more data lines
/// than one set needs are temperature-dependent data, refused).
fn values(
    deck: &Deck,
    b: &Block,
    who: &str,
    want: usize,
    per_line: usize,
) -> Result<Vec<f64>, MeshError> {
    let lines_needed = want.div_ceil(per_line.max(1)).max(1);
    if b.data.len() != lines_needed {
        let at = b.data.get(lines_needed).map_or(b.at, |d| d.at);
        return Err(deck.err(
            at,
            format!(
                "{who}: {} data lines, expected {lines_needed} ({want} values; more lines are \
                 temperature-dependent data, which squeal does not read)",
                b.data.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(want);
    for d in &b.data {
        for t in d.items.iter() {
            if t.is_empty() {
                if out.len() < want {
                    out.push(0.0);
                }
                continue;
            }
            let x = real(t).ok_or_else(|| {
                deck.err(
                    d.at,
                    format!("{who}: `{}` is not a finite number", shorten(t)),
                )
            })?;
            // After the constants: the temperature and field variables of this one data
            // set, which do not matter when there is one set.
            if out.len() < want {
                out.push(x);
            }
        }
    }
    if out.len() < want {
        return Err(deck.err(
            b.at,
            format!("{who}: {} values, expected {want}", out.len()),
        ));
    }
    Ok(out)
}

/// The 21 Abaqus anisotropic constants into this crate's Voigt order.
fn anisotropic(v: &[f64]) -> [[f64; 6]; 6] {
    // Abaqus pairs 11, 22, 33, 12, 13, 23 → Voigt 0, 1, 2, 5, 4, 3.
    const ORDER: [(usize, usize); 21] = [
        (0, 0),
        (0, 1),
        (1, 1),
        (0, 2),
        (1, 2),
        (2, 2),
        (0, 3),
        (1, 3),
        (2, 3),
        (3, 3),
        (0, 4),
        (1, 4),
        (2, 4),
        (3, 4),
        (4, 4),
        (0, 5),
        (1, 5),
        (2, 5),
        (3, 5),
        (4, 5),
        (5, 5),
    ];
    const VOIGT: [usize; 6] = [0, 1, 2, 5, 4, 3];
    let mut c = [[0.0; 6]; 6];
    for (k, &(i, j)) in ORDER.iter().enumerate() {
        let (a, b) = (VOIGT[i], VOIGT[j]);
        c[a][b] = v[k];
        c[b][a] = v[k];
    }
    c
}

/// How an orientation's points are given.
#[derive(Debug, Clone)]
pub(crate) enum OrientPoints {
    Coordinates([f64; 3], [f64; 3], Option<[f64; 3]>),
    Nodes(u64, u64, Option<u64>),
}

/// *ORIENTATION as read (resolved to axes once node positions are known).
#[derive(Debug, Clone)]
pub(crate) struct OrientDef {
    pub name: String,
    pub kind: AxesKind,
    pub points: OrientPoints,
    /// Additional rotation: (local axis 0..3, degrees).
    pub extra: Option<(usize, f64)>,
    pub at: Loc,
}

/// Parses *ORIENTATION.
pub(crate) fn orientation(deck: &Deck, b: &Block) -> Result<OrientDef, MeshError> {
    let name = super::model::required(deck, b, "NAME")?;
    let who = format!("*ORIENTATION {}", name_text(&name));
    let kind = match b
        .param("SYSTEM")
        .map(|s| s.trim().to_ascii_uppercase())
        .as_deref()
    {
        None | Some("RECTANGULAR") => AxesKind::Rectangular,
        Some("CYLINDRICAL") => AxesKind::Cylindrical,
        Some("SPHERICAL") => AxesKind::Spherical,
        Some(other) => {
            return Err(deck.err(
                b.at,
                format!("{who}: SYSTEM={other} is not read (RECTANGULAR, CYLINDRICAL, SPHERICAL)"),
            ))
        }
    };
    let def = b
        .param("DEFINITION")
        .map(|s| s.trim().to_ascii_uppercase())
        .unwrap_or_else(|| "COORDINATES".into());
    let Some(first) = b.data.first() else {
        return Err(deck.err(
            b.at,
            format!("{who}: no data line (a distribution or user orientation is not read)"),
        ));
    };
    let items: Vec<&str> = first
        .items
        .iter()
        .map(String::as_str)
        .filter(|t| !t.is_empty())
        .collect();
    let points = match def.as_str() {
        "COORDINATES" => {
            if items.len() != 6 && items.len() != 9 {
                return Err(deck.err(
                    first.at,
                    format!(
                        "{who}: {} coordinates, expected 6 (a, b) or 9 (a, b, c) (a \
                         distribution name is not read)",
                        items.len()
                    ),
                ));
            }
            let v: Vec<f64> = items
                .iter()
                .map(|t| {
                    real(t).ok_or_else(|| {
                        deck.err(first.at, format!("{who}: `{}` is not a number", shorten(t)))
                    })
                })
                .collect::<Result<_, _>>()?;
            OrientPoints::Coordinates(
                [v[0], v[1], v[2]],
                [v[3], v[4], v[5]],
                (v.len() == 9).then(|| [v[6], v[7], v[8]]),
            )
        }
        "NODES" => {
            if items.len() != 2 && items.len() != 3 {
                return Err(deck.err(
                    first.at,
                    format!("{who}: {} node labels, expected 2 or 3", items.len()),
                ));
            }
            let v: Vec<u64> = items
                .iter()
                .map(|t| {
                    super::keywords::label(t).ok_or_else(|| {
                        deck.err(
                            first.at,
                            format!("{who}: `{}` is not a node label", shorten(t)),
                        )
                    })
                })
                .collect::<Result<_, _>>()?;
            OrientPoints::Nodes(v[0], v[1], v.get(2).copied())
        }
        other => {
            return Err(deck.err(
                b.at,
                format!("{who}: DEFINITION={other} is not read (COORDINATES, NODES)"),
            ))
        }
    };
    let extra = match b.data.get(1) {
        None => None,
        Some(d) => {
            let it: Vec<&str> = d
                .items
                .iter()
                .map(String::as_str)
                .filter(|t| !t.is_empty())
                .collect();
            let axis = match it.first() {
                None => 1,
                Some(t) => super::keywords::label(t)
                    .filter(|&a| a <= 3)
                    .ok_or_else(|| {
                        deck.err(
                            d.at,
                            format!("{who}: local axis `{}` is not 1, 2 or 3", shorten(t)),
                        )
                    })? as usize,
            };
            let angle = match it.get(1) {
                None => 0.0,
                Some(t) => real(t).ok_or_else(|| {
                    deck.err(
                        d.at,
                        format!("{who}: angle `{}` is not a number", shorten(t)),
                    )
                })?,
            };
            (angle != 0.0).then_some((axis - 1, angle))
        }
    };
    if b.data.len() > 2 {
        return Err(deck.err(b.data[2].at, format!("{who}: at most two data lines")));
    }
    if extra.is_some() && kind != AxesKind::Rectangular {
        return Err(deck.err(
            b.at,
            format!(
                "{who}: an additional rotation of a {kind:?} system is not yet supported (give \
                 the rotated axes directly)"
            ),
        ));
    }
    Ok(OrientDef {
        name: name_text(&name),
        kind,
        points,
        extra,
        at: b.at,
    })
}

/// The axes of `o` whose points are `a`, `b`, `c` (c: the origin, default 0); None when the
/// points do not define axes.
pub(crate) fn axes(
    o: &OrientDef,
    a: [f64; 3],
    b: [f64; 3],
    c: Option<[f64; 3]>,
) -> Option<MaterialAxes> {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let unit = |p: [f64; 3]| {
        let n = dot(p, p).sqrt();
        (n > 0.0 && n.is_finite()).then(|| p.map(|v| v / n))
    };
    let cross = |p: [f64; 3], q: [f64; 3]| {
        [
            p[1] * q[2] - p[2] * q[1],
            p[2] * q[0] - p[0] * q[2],
            p[0] * q[1] - p[1] * q[0],
        ]
    };
    let ortho = |u: [f64; 3], w: [f64; 3]| -> Option<[f64; 3]> {
        let d = dot(w, u);
        let p = [w[0] - d * u[0], w[1] - d * u[1], w[2] - d * u[2]];
        let scale = dot(w, w).sqrt();
        (dot(p, p).sqrt() > 1e-10 * scale).then_some(())?;
        unit(p)
    };
    match o.kind {
        AxesKind::Rectangular => {
            let origin = c.unwrap_or([0.0; 3]);
            let x = unit(sub(a, origin))?;
            let y = ortho(x, sub(b, origin))?;
            let z = cross(x, y);
            let mut frame = [x, y, z];
            if let Some((axis, deg)) = o.extra {
                // Turn the two other axes about `axis` by `deg` (right hand).
                let (s, cs) = deg.to_radians().sin_cos();
                let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                let (ei, ej) = (frame[i], frame[j]);
                frame[i] = [0, 1, 2].map(|k| cs * ei[k] + s * ej[k]);
                frame[j] = [0, 1, 2].map(|k| -s * ei[k] + cs * ej[k]);
            }
            Some(MaterialAxes {
                kind: AxesKind::Rectangular,
                origin,
                frame,
            })
        }
        AxesKind::Cylindrical | AxesKind::Spherical => {
            let z = unit(sub(b, a))?;
            // Any x perpendicular to z: the material axes depend on the position only.
            let trial = if z[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let x = ortho(z, trial)?;
            let y = cross(z, x);
            Some(MaterialAxes {
                kind: o.kind,
                origin: a,
                frame: [x, y, z],
            })
        }
    }
}
