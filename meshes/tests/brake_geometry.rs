//! The sample brake's parametric geometry meshed with gmsh: rotor, pads and caliper are
//! all-hex with positive Jacobians, the volumes they enclose are the analytic ones, and every
//! interface has coincident nodes (pad friction faces on the rotor's friction faces, the
//! caliper's finger and piston faces on the pads' backs) in hex8 and hex20.

use squeal_meshes::geo::{
    self, BrakeGeometry, CaliperGeometry, PadGeometry, PadPlacement, RotorGeometry, RotorSide,
};
use squeal_meshes::gmsh::{mesh_geo, GmshOptions};
use squeal_meshes::{read_msh, CellKind, Mesh};
use std::f64::consts::PI;
use std::path::PathBuf;

fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("squeal-brake-geometry");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn mesh(geo_text: &str, name: &str, order: u8) -> Mesh {
    let path = out_dir(&format!("{name}-o{order}.msh"));
    let opts = GmshOptions {
        order,
        ..Default::default()
    };
    let run = mesh_geo(geo_text, &path, &opts).unwrap_or_else(|e| {
        panic!("{e}\n(the gmsh tests need the project .venv: run `bash scripts/test.sh`)")
    });
    eprintln!("{name} order {order}: gmsh in {:.3} s", run.elapsed_s);
    read_msh(&path).unwrap()
}

/// Natural coordinates of the hex8 corners in squeal (VTK) order.
const XI: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// det ∂x/∂ξ of the trilinear map through `c` at natural point `p`.
fn trilinear_det(c: &[[f64; 3]; 8], p: [f64; 3]) -> f64 {
    let mut j = [[0.0; 3]; 3];
    for (x, xi) in c.iter().zip(&XI) {
        let dn = [
            xi[0] * (1.0 + xi[1] * p[1]) * (1.0 + xi[2] * p[2]) / 8.0,
            xi[1] * (1.0 + xi[0] * p[0]) * (1.0 + xi[2] * p[2]) / 8.0,
            xi[2] * (1.0 + xi[0] * p[0]) * (1.0 + xi[1] * p[1]) / 8.0,
        ];
        for i in 0..3 {
            for a in 0..3 {
                j[i][a] += x[i] * dn[a];
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// Checks every volume cell of `m`: the corner (trilinear) Jacobian is positive at the 8
/// corners, and hex20 mid-edge nodes are within 10 % of an edge length of the edge midpoint.
/// Returns the volume of the trilinear cells (2×2×2 Gauss, exact for trilinear maps).
fn check_cells(m: &Mesh, name: &str) -> f64 {
    const EDGES: [(usize, usize); 12] = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let g = 1.0 / 3f64.sqrt();
    let mut volume = 0.0;
    for b in &m.volumes {
        for i in 0..b.len() {
            let cell = b.cell(i);
            let c: [[f64; 3]; 8] = std::array::from_fn(|k| m.nodes[cell[k]]);
            for xi in XI {
                let d = trilinear_det(&c, xi);
                assert!(
                    d > 0.0,
                    "{name}: cell {} has det J = {d} at corner {xi:?}",
                    b.tags[i]
                );
            }
            for xi in XI {
                volume += trilinear_det(&c, [g * xi[0], g * xi[1], g * xi[2]]);
            }
            if b.kind == CellKind::Hex20 {
                for (e, (p, q)) in EDGES.iter().enumerate() {
                    let (p, q, mid) = (c[*p], c[*q], m.nodes[cell[8 + e]]);
                    let len = dist(p, q);
                    let off = dist(
                        mid,
                        [
                            (p[0] + q[0]) / 2.0,
                            (p[1] + q[1]) / 2.0,
                            (p[2] + q[2]) / 2.0,
                        ],
                    );
                    assert!(
                        off < 0.1 * len,
                        "{name}: cell {} edge {e} mid node {off} off",
                        b.tags[i]
                    );
                }
            }
        }
    }
    volume
}

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Every node of `a`'s set has a node of `b`'s set within `tol`, and no two share one; returns
/// the number of matched nodes.
fn coincide(a: &Mesh, set_a: &str, b: &Mesh, set_b: &str, tol: f64) -> usize {
    let (na, nb) = (a.node_set(set_a).unwrap(), b.node_set(set_b).unwrap());
    let mut used = vec![false; nb.len()];
    let mut worst: f64 = 0.0;
    for &i in na {
        let p = a.nodes[i];
        let near = nb
            .iter()
            .map(|&k| dist(p, b.nodes[k]))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(near);
        let hits: Vec<usize> = (0..nb.len())
            .filter(|&k| dist(p, b.nodes[nb[k]]) <= tol)
            .collect();
        assert_eq!(
            hits.len(),
            1,
            "{set_a} node {p:?}: {} nodes of {set_b} within {tol}",
            hits.len()
        );
        assert!(
            !used[hits[0]],
            "{set_a} node {p:?} matches a {set_b} node twice"
        );
        used[hits[0]] = true;
    }
    eprintln!(
        "{set_a} -> {set_b}: {} nodes, largest distance {worst:.3e}",
        na.len()
    );
    na.len()
}

/// The volume of an n-element polygonal annular sector between r1 and r2 (planar quads with
/// corners on both circles, each ½(r2² − r1²) sin dθ), extruded over h: what straight-edged
/// cells enclose, whatever the edge shapes of the .geo.
fn polygon_sector_volume(r1: f64, r2: f64, n: usize, dtheta: f64, h: f64) -> f64 {
    n as f64 * 0.5 * (r2 * r2 - r1 * r1) * dtheta.sin() * h
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// Meshes the brake `b` at `order` and checks everything; returns (rotor, pads, caliper).
fn check_brake(b: &BrakeGeometry, order: u8, tag: &str) -> [Mesh; 4] {
    let (inb, outb, cal) = (
        b.inboard_pad().unwrap(),
        b.outboard_pad().unwrap(),
        b.caliper().unwrap(),
    );
    let rotor = mesh(&geo::rotor(&b.rotor), &format!("{tag}-rotor"), order);
    let pin = mesh(&geo::pad(&inb), &format!("{tag}-pad-in"), order);
    let pout = mesh(&geo::pad(&outb), &format!("{tag}-pad-out"), order);
    let calm = mesh(&geo::caliper(&cal), &format!("{tag}-caliper"), order);

    // Positive Jacobians everywhere; hex8 volumes are those of the polygonal sectors.
    let r = &b.rotor;
    let dth_rotor = 2.0 * PI / r.n_circ as f64;
    let v_rotor = check_cells(&rotor, "rotor");
    let v_pin = check_cells(&pin, "inboard pad");
    let v_pout = check_cells(&pout, "outboard pad");
    let v_cal = check_cells(&calm, "caliper");
    if order == 1 {
        let vr = polygon_sector_volume(r.r_in, r.r_out, r.n_circ, dth_rotor, r.thickness);
        assert!(close(v_rotor, vr, 1e-12), "rotor volume {v_rotor} vs {vr}");
        let h = inb.lining + inb.backplate;
        let vp = polygon_sector_volume(inb.r_in, inb.r_out, inb.n_circ, dth_rotor, h);
        assert!(
            close(v_pin, vp, 1e-12),
            "inboard pad volume {v_pin} vs {vp}"
        );
        assert!(
            close(v_pout, vp, 1e-12),
            "outboard pad volume {v_pout} vs {vp}"
        );
        // Caliper: full section over finger + piston + housing, the bridge over the middle.
        let dth = cal.theta_span_deg.to_radians() / cal.n_circ as f64;
        let full = cal.finger_thickness + cal.piston_length + cal.housing_thickness;
        let vc = polygon_sector_volume(cal.r_pad_in, cal.r_bridge_out, cal.n_circ, dth, full)
            + polygon_sector_volume(
                cal.r_bridge_in,
                cal.r_bridge_out,
                cal.n_circ,
                dth,
                (cal.z_piston - cal.z_finger).abs(),
            );
        assert!(close(v_cal, vc, 1e-12), "caliper volume {v_cal} vs {vc}");
    }

    // Cell and node counts; the pad's blocks are [lining, backplate], the caliper's
    // [caliper, piston].
    let kind = if order == 1 {
        CellKind::Hex8
    } else {
        CellKind::Hex20
    };
    for (m, g) in [(&pin, &inb), (&pout, &outb)] {
        assert_eq!(m.n_volume_cells(), g.n_cells());
        assert_eq!(m.nodes.len(), g.n_nodes(order));
        let names: Vec<_> = m
            .volumes
            .iter()
            .map(|v| v.name.as_deref().unwrap())
            .collect();
        assert_eq!(names, ["lining", "backplate"]);
        assert!(m.volumes.iter().all(|v| v.kind == kind));
        assert_eq!(m.volumes[0].len(), g.n_circ * g.n_rad * g.n_lining);
    }
    assert_eq!(calm.n_volume_cells(), cal.n_cells());
    let names: Vec<_> = calm
        .volumes
        .iter()
        .map(|v| v.name.as_deref().unwrap())
        .collect();
    assert_eq!(names, ["caliper", "piston"]);
    assert_eq!(calm.volumes[1].len(), cal.n_circ * cal.n_rad * cal.n_piston);

    // Faces at the right heights.
    let z_of = |m: &Mesh, set: &str| -> Vec<f64> {
        m.node_set(set)
            .unwrap()
            .iter()
            .map(|&i| m.nodes[i][2])
            .collect()
    };
    let all_at = |zs: Vec<f64>, z: f64, what: &str| {
        assert!(
            zs.iter().all(|v| (v - z).abs() < 1e-12),
            "{what} not at z = {z}: {zs:?}"
        );
    };
    all_at(z_of(&pin, "friction"), inb.z_face, "inboard friction");
    all_at(z_of(&pout, "friction"), outb.z_face, "outboard friction");
    all_at(z_of(&pin, "back"), inb.z_back(), "inboard back");
    all_at(z_of(&pout, "back"), outb.z_back(), "outboard back");
    all_at(z_of(&calm, "piston_face"), cal.z_piston, "piston face");
    all_at(z_of(&calm, "finger_face"), cal.z_finger, "finger face");
    // The mount faces are the housing's two sector ends.
    let (t0, t1) = (
        cal.theta_start_deg.to_radians(),
        (cal.theta_start_deg + cal.theta_span_deg).to_radians(),
    );
    for &i in calm.node_set("mount").unwrap() {
        let p = calm.nodes[i];
        let t = p[1].atan2(p[0]);
        let on_end = [t0, t1]
            .iter()
            .any(|e| ((t - e + PI).rem_euclid(2.0 * PI) - PI).abs() < 1e-9);
        assert!(on_end, "mount node {p:?} is not on a sector end");
        // Along the piston's direction, the housing starts behind the piston.
        let s = cal.piston_side().sign();
        let behind = s * (p[2] - (cal.z_piston + s * cal.piston_length));
        assert!(behind >= -1e-12, "mount node {p:?} is not in the housing");
    }
    for (m, name) in [(&pin, "inboard"), (&pout, "outboard")] {
        for set in ["abutment_start", "abutment_end"] {
            let t_end = if set == "abutment_start" { t0 } else { t1 };
            for &i in m.node_set(set).unwrap() {
                let p = m.nodes[i];
                let t = p[1].atan2(p[0]);
                assert!(
                    ((t - t_end + PI).rem_euclid(2.0 * PI) - PI).abs() < 1e-9,
                    "{name} {set} node {p:?}"
                );
            }
        }
    }

    // Coincident interfaces. The pad and caliper nodes are computed from the same
    // expressions: to round-off. The rotor's circle nodes come from gmsh's 1D meshing of its
    // quarter arcs, which places them up to ~1.3e-8 in off the exact angles on the default
    // rotor (measured; unchanged by Mesh.LcIntegrationPrecision), while the pad's are exact:
    // 1e-8·r_out there, still 7 orders below the element size and 100× below the contact
    // crate's default matching tolerance (1e-6).
    let tol_rotor = 1e-8 * r.r_out;
    let tol = 1e-12 * r.r_out;
    let face_nodes = |g: &PadGeometry| {
        let (a, c) = (g.n_circ, g.n_rad);
        if order == 1 {
            (a + 1) * (c + 1)
        } else {
            (a + 1) * (c + 1) + a * (c + 1) + (a + 1) * c
        }
    };
    let top = match inb.side {
        RotorSide::Top => "friction_top",
        RotorSide::Bottom => "friction_bottom",
    };
    let bottom = if top == "friction_top" {
        "friction_bottom"
    } else {
        "friction_top"
    };
    assert_eq!(
        coincide(&pin, "friction", &rotor, top, tol_rotor),
        face_nodes(&inb)
    );
    assert_eq!(
        coincide(&pout, "friction", &rotor, bottom, tol_rotor),
        face_nodes(&outb)
    );
    assert_eq!(
        coincide(&pin, "back", &calm, "piston_face", tol),
        face_nodes(&inb)
    );
    assert_eq!(
        coincide(&calm, "piston_face", &pin, "back", tol),
        face_nodes(&inb)
    );
    assert_eq!(
        coincide(&pout, "back", &calm, "finger_face", tol),
        face_nodes(&outb)
    );
    assert_eq!(
        coincide(&calm, "finger_face", &pout, "back", tol),
        face_nodes(&outb)
    );
    eprintln!(
        "{tag} order {order}: nodes rotor {}, pads {} + {}, caliper {}: {} DOFs",
        rotor.nodes.len(),
        pin.nodes.len(),
        pout.nodes.len(),
        calm.nodes.len(),
        3 * (rotor.nodes.len() + pin.nodes.len() + pout.nodes.len() + calm.nodes.len())
    );
    [rotor, pin, pout, calm]
}

#[test]
fn default_brake_hex8_is_valid_and_coincident() {
    check_brake(&BrakeGeometry::default(), 1, "default");
}

#[test]
fn default_brake_hex20_is_valid_and_coincident() {
    let [rotor, pin, _, calm] = check_brake(&BrakeGeometry::default(), 2, "default");
    // hex20 rotor node count from the rotor's own formula (structured mesh).
    assert_eq!(rotor.nodes.len(), BrakeGeometry::default().rotor.n_nodes(2));
    assert!(pin.faces["friction"].kind() == Some(CellKind::Quad8));
    assert!(calm.faces["piston_face"].kind() == Some(CellKind::Quad8));
}

/// Pads touching the hub circle (an arc edge at ring 0) and an interior ring (chords), crossing
/// the rotor's 0° quarter boundary, on a coarse rotor, with the piston below the rotor.
#[test]
fn pads_at_the_hub_across_zero_degrees_hex20() {
    let rotor = RotorGeometry {
        n_circ: 16,
        n_rad: 3,
        n_thick: 1,
        ..Default::default()
    };
    let place = |side| PadPlacement {
        side,
        start_element: -2,
        n_elements: 3,
        first_ring: 0,
        last_ring: 2,
        lining: 0.3,
        n_lining: 1,
        ..Default::default()
    };
    let b = BrakeGeometry {
        rotor,
        inboard: place(RotorSide::Bottom),
        outboard: place(RotorSide::Top),
        ..Default::default()
    };
    let cal: CaliperGeometry = b.caliper().unwrap();
    assert_eq!(cal.piston_side(), RotorSide::Bottom);
    check_brake(&b, 2, "hub");
}
