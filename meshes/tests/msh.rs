//! `.msh` reading: hand-written 2.2 / 4.1 ASCII / 4.1 binary files, gmsh-generated rotors and
//! blocks (hex8 and hex20), and malformed input (errors, never panics).

use proptest::prelude::*;
use squeal_meshes::geo::{self, BlockGeometry, RotorGeometry};
use squeal_meshes::gmsh::{mesh_geo, GmshOptions};
use squeal_meshes::{parse_msh, read_msh, CellKind, Mesh, MeshError};
use std::path::PathBuf;

/// squeal (= VTK) hex20 edge nodes 8..20 and their corners (mesh.rs documentation).
const SQUEAL_HEX20_EDGES: [(usize, usize); 12] = [
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
/// gmsh hex20 edge nodes 8..20 (gmsh manual, "Node ordering").
const GMSH_HEX20_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (0, 3),
    (0, 4),
    (1, 2),
    (1, 5),
    (2, 3),
    (2, 6),
    (3, 7),
    (4, 5),
    (4, 7),
    (5, 6),
    (6, 7),
];

/// Corners of the box [0, a] × [0, b] × [0, c] in gmsh = VTK order.
fn box_corners(a: f64, b: f64, c: f64) -> [[f64; 3]; 8] {
    [
        [0.0, 0.0, 0.0],
        [a, 0.0, 0.0],
        [a, b, 0.0],
        [0.0, b, 0.0],
        [0.0, 0.0, c],
        [a, 0.0, c],
        [a, b, c],
        [0.0, b, c],
    ]
}

fn mid(p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    [
        (p[0] + q[0]) / 2.0,
        (p[1] + q[1]) / 2.0,
        (p[2] + q[2]) / 2.0,
    ]
}

fn close(p: [f64; 3], q: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (p[k] - q[k]).abs() <= tol)
}

/// A single hex8 in a named physical volume, a named bottom face, a named corner point, an
/// unnamed physical line, and a node no cell uses (tag 99, dropped).
const HEX8_V22: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
0 10 "corner"
2 2 "bottom"
3 1 "body"
$EndPhysicalNames
$Nodes
9
10 0 0 0
11 1 0 0
12 1 1 0
13 0 1 0
99 5 5 5
14 0 0 2
15 1 0 2
16 1 1 2
17 0 1 2
$EndNodes
$Elements
4
1 15 2 10 1 10
7 1 2 7 3 10 11
2 3 2 2 1 10 13 12 11
3 5 2 1 1 10 11 12 13 14 15 16 17
$EndElements
"#;

fn check_single_hex8(m: &Mesh) {
    assert_eq!(
        m.nodes.len(),
        8,
        "node 99 is used by no cell and must be dropped"
    );
    assert_eq!(m.node_tags, vec![10, 11, 12, 13, 14, 15, 16, 17]);
    assert_eq!(m.nodes[5], [1.0, 0.0, 2.0]);
    assert_eq!(m.volumes.len(), 1);
    let b = &m.volumes[0];
    assert_eq!(b.name.as_deref(), Some("body"));
    assert_eq!(b.kind, CellKind::Hex8);
    assert_eq!(b.conn, (0..8).collect::<Vec<_>>());
    assert_eq!(b.tags, vec![3]);
    let f = &m.face_set("bottom").unwrap().blocks[0];
    assert_eq!(f.kind, CellKind::Quad4);
    assert_eq!(f.conn, vec![0, 3, 2, 1]);
    assert_eq!(m.node_set("corner").unwrap(), &[0]);
    assert_eq!(m.node_set("physical_7").unwrap(), &[0, 1]);
    assert_eq!(m.node_set("bottom").unwrap(), &[0, 1, 2, 3]);
    assert_eq!(m.node_set("body").unwrap(), &[0, 1, 2, 3, 4, 5, 6, 7]);
    // A unit square prism of height 2: J = diag(1/2, 1/2, 1), det = 1/4.
    assert!((m.centroid_jacobian(0, 0) - 0.25).abs() < 1e-15);
    assert_eq!(m.bounding_box(), Some(([0.0; 3], [1.0, 1.0, 2.0])));
}

#[test]
fn v22_single_hex8_with_physical_groups() {
    check_single_hex8(&parse_msh(HEX8_V22.as_bytes(), "hex8.msh").unwrap());
}

/// The same mesh in 4.1 ASCII: physical tags come from $Entities.
const HEX8_V41: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
0 10 "corner"
2 2 "bottom"
3 1 "body"
$EndPhysicalNames
$Entities
1 1 1 1
1 0 0 0 1 10
4 0 0 0 1 0 0 1 7 0
2 0 0 0 1 1 0 1 2 0
1 0 0 0 1 1 2 1 1 0
$EndEntities
$Nodes
2 9 10 99
0 1 0 1
99
5 5 5
3 1 0 8
10
11
12
13
14
15
16
17
0 0 0
1 0 0
1 1 0
0 1 0
0 0 2
1 0 2
1 1 2
0 1 2
$EndNodes
$Elements
4 4 1 7
0 1 15 1
1 10
1 4 1 1
7 10 11
2 2 3 1
2 10 13 12 11
3 1 5 1
3 10 11 12 13 14 15 16 17
$EndElements
"#;

#[test]
fn v41_ascii_single_hex8_with_physical_groups() {
    let m = parse_msh(HEX8_V41.as_bytes(), "hex8_41.msh").unwrap();
    // Node 99 comes first in this file; it is dropped, the rest keep file order.
    check_single_hex8(&m);
}

/// Writes the 4.1 binary form of [`HEX8_V41`] (gmsh manual, "MSH file format version 4.1").
fn hex8_v41_binary() -> Vec<u8> {
    let mut b: Vec<u8> = Vec::new();
    let int = |b: &mut Vec<u8>, v: i32| b.extend_from_slice(&v.to_le_bytes());
    let size = |b: &mut Vec<u8>, v: u64| b.extend_from_slice(&v.to_le_bytes());
    let real = |b: &mut Vec<u8>, v: f64| b.extend_from_slice(&v.to_le_bytes());
    b.extend_from_slice(b"$MeshFormat\n4.1 1 8\n");
    int(&mut b, 1);
    b.extend_from_slice(b"\n$EndMeshFormat\n$PhysicalNames\n3\n0 10 \"corner\"\n2 2 \"bottom\"\n3 1 \"body\"\n$EndPhysicalNames\n$Entities\n");
    for n in [1, 1, 1, 1] {
        size(&mut b, n);
    }
    // point 1 at the origin in physical 10
    int(&mut b, 1);
    for _ in 0..3 {
        real(&mut b, 0.0);
    }
    size(&mut b, 1);
    int(&mut b, 10);
    // curve 4 (physical 7), surface 2 (physical 2), volume 1 (physical 1), no boundaries
    for (tag, phys) in [(4, 7), (2, 2), (1, 1)] {
        int(&mut b, tag);
        for _ in 0..6 {
            real(&mut b, 0.0);
        }
        size(&mut b, 1);
        int(&mut b, phys);
        size(&mut b, 0);
    }
    b.extend_from_slice(b"\n$EndEntities\n$Nodes\n");
    for v in [2, 9, 10, 99] {
        size(&mut b, v);
    }
    int(&mut b, 0);
    int(&mut b, 1);
    int(&mut b, 0);
    size(&mut b, 1);
    size(&mut b, 99);
    for _ in 0..3 {
        real(&mut b, 5.0);
    }
    int(&mut b, 3);
    int(&mut b, 1);
    int(&mut b, 0);
    size(&mut b, 8);
    for t in 10..18 {
        size(&mut b, t);
    }
    for p in box_corners(1.0, 1.0, 2.0) {
        for x in p {
            real(&mut b, x);
        }
    }
    b.extend_from_slice(b"\n$EndNodes\n$Elements\n");
    for v in [4, 4, 1, 7] {
        size(&mut b, v);
    }
    let blocks: [(i32, i32, i32, Vec<u64>); 4] = [
        (0, 1, 15, vec![1, 10]),
        (1, 4, 1, vec![7, 10, 11]),
        (2, 2, 3, vec![2, 10, 13, 12, 11]),
        (3, 1, 5, vec![3, 10, 11, 12, 13, 14, 15, 16, 17]),
    ];
    for (dim, tag, ty, data) in blocks {
        int(&mut b, dim);
        int(&mut b, tag);
        int(&mut b, ty);
        size(&mut b, 1);
        for v in data {
            size(&mut b, v);
        }
    }
    b.extend_from_slice(b"\n$EndElements\n");
    b
}

#[test]
fn v41_binary_single_hex8_with_physical_groups() {
    check_single_hex8(&parse_msh(&hex8_v41_binary(), "hex8_bin.msh").unwrap());
}

/// One hex20 on [0,2]×[0,3]×[0,1] in gmsh node order with tags 101.., its top face as a quad8
/// (gmsh quad8: corners, then mid-edges (4,5) (5,6) (6,7) (7,4) of the hex = gmsh nodes 16, 18,
/// 19, 17). Reading must permute to squeal order: node k ≥ 8 at the midpoint of its edge.
fn hex20_v41() -> String {
    let c = box_corners(2.0, 3.0, 1.0);
    let mut pts: Vec<[f64; 3]> = c.to_vec();
    pts.extend(GMSH_HEX20_EDGES.iter().map(|&(a, b)| mid(c[a], c[b])));
    let mut s = String::from(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 5 \"top\"\n3 7 \"solid\"\n$EndPhysicalNames\n\
         $Entities\n0 0 1 1\n3 0 0 1 2 3 1 1 5 0\n1 0 0 0 2 3 1 1 7 0\n$EndEntities\n$Nodes\n1 20 101 120\n3 1 0 20\n",
    );
    for i in 0..20 {
        s += &format!("{}\n", 101 + i);
    }
    for p in &pts {
        s += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    s += "$EndNodes\n$Elements\n2 2 1 2\n2 3 16 1\n1";
    for g in [4, 5, 6, 7, 16, 18, 19, 17] {
        s += &format!(" {}", 101 + g);
    }
    s += "\n3 1 17 1\n2";
    for g in 0..20 {
        s += &format!(" {}", 101 + g);
    }
    s += "\n$EndElements\n";
    s
}

#[test]
fn v41_hex20_is_permuted_to_squeal_order() {
    let m = parse_msh(hex20_v41().as_bytes(), "hex20.msh").unwrap();
    assert_eq!(m.nodes.len(), 20);
    let b = &m.volumes[0];
    assert_eq!(
        (b.name.as_deref(), b.kind),
        (Some("solid"), CellKind::Hex20)
    );
    let cell = b.cell(0);
    for (k, &(p, q)) in SQUEAL_HEX20_EDGES.iter().enumerate() {
        let want = mid(m.nodes[cell[p]], m.nodes[cell[q]]);
        assert!(
            close(m.nodes[cell[8 + k]], want, 1e-15),
            "squeal node {}",
            8 + k
        );
    }
    let top = &m.face_set("top").unwrap().blocks[0];
    assert_eq!(top.kind, CellKind::Quad8);
    // quad8: corners then 4:(0,1) 5:(1,2) 6:(2,3) 7:(3,0), all at z = 1.
    let f = top.cell(0);
    for k in 0..4 {
        let want = mid(m.nodes[f[k]], m.nodes[f[(k + 1) % 4]]);
        assert!(close(m.nodes[f[4 + k]], want, 1e-15));
        assert_eq!(m.nodes[f[k]][2], 1.0);
    }
    assert_eq!(m.node_set("top").unwrap().len(), 8);
    // Box 2×3×1: det J = (2/2)(3/2)(1/2).
    assert!((m.centroid_jacobian(0, 0) - 0.75).abs() < 1e-14);
}

/// The same hex as `hex20_v41` written as gmsh's complete second-order elements (hex27 with
/// its 6 face nodes and centre, the top face as a quad9 with its centre; tags 121..127): the
/// reader keeps the serendipity nodes and gives exactly the hex20 mesh (gmsh node ordering:
/// hex27 = hex20 nodes, then faces, then the centre; quad9 = quad8 nodes, then the centre).
#[test]
fn v41_hex27_reads_as_its_hex20() {
    let c = box_corners(2.0, 3.0, 1.0);
    let centre = |k: &[usize]| {
        let mut p = [0.0; 3];
        for &i in k {
            for d in 0..3 {
                p[d] += c[i][d] / k.len() as f64;
            }
        }
        p
    };
    // Face centres (gmsh hex27 nodes 20..25) and the body centre (26).
    let extra = [
        centre(&[0, 1, 2, 3]),
        centre(&[0, 1, 5, 4]),
        centre(&[0, 3, 7, 4]),
        centre(&[1, 2, 6, 5]),
        centre(&[2, 3, 7, 6]),
        centre(&[4, 5, 6, 7]),
        centre(&[0, 1, 2, 3, 4, 5, 6, 7]),
    ];
    let mut text = hex20_v41()
        .replace(
            "$Nodes\n1 20 101 120\n3 1 0 20\n",
            "$Nodes\n1 27 101 127\n3 1 0 27\n",
        )
        .replace("2 3 16 1\n", "2 3 10 1\n")
        .replace("3 1 17 1\n", "3 1 12 1\n");
    let coords_end = text.find("$EndNodes").unwrap();
    // Node tags come before the coordinates in a 4.1 node block: insert 121..127 after 120.
    let mut extra_coords = String::new();
    for p in &extra {
        extra_coords += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    text.insert_str(coords_end, &extra_coords);
    text = text.replacen("120\n", "120\n121\n122\n123\n124\n125\n126\n127\n", 1);
    // quad9: the top face's centre is node 25 (tag 126); hex27: nodes 20..26 (tags 121..127).
    let quad_line_end = text.find("2 3 10 1\n").unwrap() + "2 3 10 1\n".len();
    let eol = quad_line_end + text[quad_line_end..].find('\n').unwrap();
    text.insert_str(eol, " 126");
    let hex_line_end = text.find("3 1 12 1\n").unwrap() + "3 1 12 1\n".len();
    let eol = hex_line_end + text[hex_line_end..].find('\n').unwrap();
    text.insert_str(eol, " 121 122 123 124 125 126 127");

    let m27 = parse_msh(text.as_bytes(), "hex27.msh").unwrap();
    let m20 = parse_msh(hex20_v41().as_bytes(), "hex20.msh").unwrap();
    assert_eq!(m27.nodes, m20.nodes);
    assert_eq!(m27.node_tags, m20.node_tags);
    assert_eq!(m27.volumes[0].kind, CellKind::Hex20);
    assert_eq!(m27.volumes[0].conn, m20.volumes[0].conn);
    let (t27, t20) = (m27.face_set("top").unwrap(), m20.face_set("top").unwrap());
    assert_eq!(t27, t20);
    assert_eq!(t27.kind(), Some(CellKind::Quad8));
    assert_eq!(m27.node_sets, m20.node_sets);
}

/// A hex8 whose corners are listed top face first has a negative Jacobian; the reader flips it.
#[test]
fn inverted_hex8_is_flipped() {
    let text = HEX8_V22.replace(
        "3 5 2 1 1 10 11 12 13 14 15 16 17",
        "3 5 2 1 1 14 15 16 17 10 11 12 13",
    );
    let m = parse_msh(text.as_bytes(), "inv.msh").unwrap();
    assert!(m.centroid_jacobian(0, 0) > 0.0);
    assert_eq!(m.volumes[0].cell(0), &[0, 1, 2, 3, 4, 5, 6, 7]);
}

fn err_text(text: &str) -> String {
    match parse_msh(text.as_bytes(), "bad.msh") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn errors_name_file_line_and_value() {
    // A cubic tetrahedron (gmsh type 29): unsupported, with type, element tag and line.
    let e = err_text(&HEX8_V22.replace(
        "3 5 2 1 1 10 11 12 13 14 15 16 17",
        "3 29 2 1 1 10 11 12 13",
    ));
    assert!(
        e.contains("bad.msh:27") && e.contains("type 29") && e.contains("element 3"),
        "{e}"
    );
    // A cubic prism in 4.1 (type 90; hex27 is read as hex20: `v41_hex27_reads_as_its_hex20`).
    let e = err_text(&HEX8_V41.replace("3 1 5 1\n", "3 1 90 1\n"));
    assert!(e.contains("type 90") && e.contains("element 3"), "{e}");
    // Unknown node tag.
    let e = err_text(&HEX8_V22.replace("10 11 12 13 14 15 16 17", "10 11 12 13 14 15 16 18"));
    assert!(
        e.contains("bad.msh:27") && e.contains("node 18") && e.contains("element 3"),
        "{e}"
    );
    // A bad number.
    let e = err_text(&HEX8_V22.replace("15 1 0 2", "15 1 0x 2"));
    assert!(e.contains("bad.msh:18") && e.contains("`0x`"), "{e}");
    let e = err_text(&HEX8_V22.replace("15 1 0 2", "15 1 nan 2"));
    assert!(e.contains("bad.msh:18") && e.contains("nan"), "{e}");
    // Unsupported version.
    let e = err_text(&HEX8_V22.replace("2.2 0 8", "3.0 0 8"));
    assert!(e.contains("bad.msh:2") && e.contains("3.0"), "{e}");
    // Truncated inside $Elements.
    let cut = &HEX8_V22[..HEX8_V22.find("3 5 2 1").unwrap()];
    let e = err_text(cut);
    assert!(e.contains("$Elements") && e.contains("truncated"), "{e}");
    // A face on a node that no volume uses.
    let e = err_text(&HEX8_V22.replace("2 3 2 2 1 10 13 12 11", "2 3 2 2 1 10 13 12 99"));
    assert!(e.contains("node 99") && e.contains("bottom"), "{e}");
    // Duplicate node tag.
    let e = err_text(&HEX8_V22.replace("99 5 5 5", "10 5 5 5"));
    assert!(e.contains("node tag 10 defined twice"), "{e}");
    // Count larger than the entries.
    let e = err_text(&HEX8_V22.replace("$Elements\n4", "$Elements\n5"));
    assert!(e.contains("$Elements"), "{e}");
    // Binary truncated.
    let bin = hex8_v41_binary();
    let e = parse_msh(&bin[..bin.len() - 40], "b.msh")
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.msh") && e.contains("Elements"), "{e}");
}

proptest! {
    /// Cutting a file anywhere before its last section ends gives an error, never a panic.
    #[test]
    fn truncated_files_are_errors(which in 0usize..4, frac in 0.0f64..1.0) {
        let files: [Vec<u8>; 4] = [
            HEX8_V22.as_bytes().to_vec(),
            HEX8_V41.as_bytes().to_vec(),
            hex8_v41_binary(),
            hex20_v41().into_bytes(),
        ];
        let f = &files[which];
        let end = f.windows(12).rposition(|w| w == b"$EndElements").unwrap();
        let cut = (frac * end as f64) as usize;
        prop_assert!(parse_msh(&f[..cut], "cut.msh").is_err());
    }

    /// Overwriting bytes with arbitrary ones may give a mesh or an error, never a panic.
    #[test]
    fn garbled_files_do_not_panic(which in 0usize..4,
                                  edits in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 1..6)) {
        let files: [Vec<u8>; 4] = [
            HEX8_V22.as_bytes().to_vec(),
            HEX8_V41.as_bytes().to_vec(),
            hex8_v41_binary(),
            hex20_v41().into_bytes(),
        ];
        let mut f = files[which].clone();
        for (pos, byte) in edits {
            let i = ((pos * f.len() as f64) as usize).min(f.len() - 1);
            f[i] = byte;
        }
        let _ = parse_msh(&f, "garbled.msh");
    }
}

// ---------------------------------------------------------------- gmsh-generated meshes

fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("squeal-meshes-tests");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn mesh_with_gmsh(geo_text: &str, name: &str, opts: &GmshOptions) -> Mesh {
    let path = out_dir(name);
    let run = mesh_geo(geo_text, &path, opts).unwrap_or_else(|e| {
        panic!("{e}\n(the gmsh tests need the project .venv: run `bash scripts/test.sh`, the README's test command)")
    });
    eprintln!(
        "{name}: gmsh {} in {:.3} s",
        run.version.as_deref().unwrap_or("?"),
        run.elapsed_s
    );
    assert!(run.geo_path.is_file());
    read_msh(&path).unwrap()
}

fn coarse_rotor() -> RotorGeometry {
    RotorGeometry {
        n_circ: 8,
        n_rad: 2,
        n_thick: 1,
        ..Default::default()
    }
}

fn radius(p: [f64; 3]) -> f64 {
    p[0].hypot(p[1])
}

/// Checks counts, orientation and face sets of a gmsh rotor of geometry `g` and `order`.
fn check_rotor(m: &Mesh, g: &RotorGeometry, order: u8) {
    let kind = if order == 1 {
        CellKind::Hex8
    } else {
        CellKind::Hex20
    };
    assert_eq!(m.nodes.len(), g.n_nodes(order));
    assert_eq!(m.volumes.len(), 1);
    assert_eq!(m.volumes[0].name.as_deref(), Some("rotor"));
    assert_eq!(m.volumes[0].kind, kind);
    assert_eq!(m.volumes[0].len(), g.n_cells());
    for c in 0..m.volumes[0].len() {
        assert!(m.centroid_jacobian(0, c) > 0.0, "cell {c}");
    }
    let tol = 1e-9 * g.r_out;
    let faces = [
        ("friction_bottom", g.n_circ * g.n_rad),
        ("friction_top", g.n_circ * g.n_rad),
        ("hub", g.n_circ * g.n_thick),
        ("outer", g.n_circ * g.n_thick),
    ];
    for (name, count) in faces {
        let f = m.face_set(name).unwrap();
        assert_eq!(f.len(), count, "{name}");
        assert_eq!(
            f.kind().map(CellKind::n_nodes),
            Some(if order == 1 { 4 } else { 8 })
        );
        let set = m.node_set(name).unwrap();
        assert!(!set.is_empty());
        for &i in set {
            let p = m.nodes[i];
            let on = match name {
                "friction_bottom" => p[2].abs() < tol,
                "friction_top" => (p[2] - g.thickness).abs() < tol,
                "hub" => (radius(p) - g.r_in).abs() < tol,
                _ => (radius(p) - g.r_out).abs() < tol,
            };
            assert!(on, "{name}: node {i} at {p:?}");
        }
    }
    // Every node lies in the annulus.
    for p in &m.nodes {
        let r = radius(*p);
        assert!(r > g.r_in - tol && r < g.r_out + tol && p[2] > -tol && p[2] < g.thickness + tol);
    }
}

#[test]
fn gmsh_rotor_hex8() {
    let g = coarse_rotor();
    let opts = GmshOptions {
        order: 1,
        ..Default::default()
    };
    let m = mesh_with_gmsh(&geo::rotor(&g), "rotor8.msh", &opts);
    check_rotor(&m, &g, 1);
}

/// The thin annular plate of the verification suite (a = 0.16 m, b = 0.08 m, h = 4 mm,
/// 64 × 8 × 2 hex20) is a RotorGeometry; its clamped set "hub" lies at r = b.
#[test]
fn gmsh_annular_plate_hex20() {
    let g = RotorGeometry::annular_plate();
    let m = mesh_with_gmsh(&geo::annulus(&g), "annulus20.msh", &GmshOptions::default());
    check_rotor(&m, &g, 2);
    // hub (quad8 cylinder): at each of the n_thick + 1 levels a ring of n_circ corners and
    // n_circ circumferential mid-edge nodes, plus n_circ axial mid-edge nodes per layer.
    let hub = m.node_set("hub").unwrap();
    assert_eq!(
        hub.len(),
        2 * g.n_circ * (g.n_thick + 1) + g.n_circ * g.n_thick
    );
}

/// hex20 mid-edge nodes: an edge along the inner or outer circle has its mid node on the arc
/// (same radius and z as its corners, mean angle: gmsh places second-order nodes on the
/// geometry); every other edge (radial, axial, and circumferential edges inside the plane
/// quarter surfaces, which gmsh meshes with straight edges) has it at the chord midpoint.
/// Tolerance: gmsh's transfinite nodes carry ~1e-12 relative parametrisation error.
#[test]
fn gmsh_rotor_hex20_midnodes() {
    let g = coarse_rotor();
    let m = mesh_with_gmsh(&geo::rotor(&g), "rotor20.msh", &GmshOptions::default());
    check_rotor(&m, &g, 2);
    let tol = 1e-9 * g.r_out;
    let b = &m.volumes[0];
    let mut on_arc = 0;
    for c in 0..b.len() {
        let cell = b.cell(c);
        for (k, &(p, q)) in SQUEAL_HEX20_EDGES.iter().enumerate() {
            let (a, e, x) = (m.nodes[cell[p]], m.nodes[cell[q]], m.nodes[cell[8 + k]]);
            let (ra, re) = (radius(a), radius(e));
            let boundary_circle = (a[2] - e[2]).abs() < tol
                && [g.r_in, g.r_out]
                    .iter()
                    .any(|&r| (ra - r).abs() < tol && (re - r).abs() < tol);
            let want = if boundary_circle {
                on_arc += 1;
                // Mean direction of the two corners (the arc spans less than π).
                let (ux, uy) = (a[0] / ra + e[0] / re, a[1] / ra + e[1] / re);
                let n = ux.hypot(uy);
                [ra * ux / n, ra * uy / n, a[2]]
            } else {
                mid(a, e)
            };
            assert!(
                close(x, want, tol),
                "cell {c} node {}: {x:?} vs {want:?}",
                8 + k
            );
        }
    }
    // Each cell touching the hub or the outer circle has 2 arc edges there (z = 0 and z = t).
    assert_eq!(on_arc, 2 * 2 * g.n_circ * g.n_thick);
}

/// Straight edges only: every hex20 mid node is exactly the midpoint of its corners; the
/// supported-edge set holds the nodes on the border of face z0.
#[test]
fn gmsh_block_hex20_midnodes_and_sets() {
    let g = BlockGeometry {
        lx: 2.0,
        ly: 1.0,
        lz: 0.5,
        nx: 2,
        ny: 1,
        nz: 1,
        origin: [1.0, -1.0, 0.25],
    };
    let m = mesh_with_gmsh(&geo::block(&g), "block20.msh", &GmshOptions::default());
    // gmsh's transfinite nodes carry ~1e-12 relative parametrisation error.
    let tol = 1e-9 * g.lx;
    assert_eq!(m.nodes.len(), g.n_nodes(2));
    assert_eq!(m.n_volume_cells(), g.n_cells());
    let b = &m.volumes[0];
    assert_eq!(b.name.as_deref(), Some("block"));
    for c in 0..b.len() {
        assert!(m.centroid_jacobian(0, c) > 0.0);
        let cell = b.cell(c);
        for (k, &(p, q)) in SQUEAL_HEX20_EDGES.iter().enumerate() {
            let want = mid(m.nodes[cell[p]], m.nodes[cell[q]]);
            assert!(
                close(m.nodes[cell[8 + k]], want, tol),
                "cell {c} node {}",
                8 + k
            );
        }
    }
    let (lo, hi) = m.bounding_box().unwrap();
    assert!(close(lo, [1.0, -1.0, 0.25], tol) && close(hi, [3.0, 0.0, 0.75], tol));
    // Border of z0: 2(nx + ny) element edges with 2 nodes each on the loop (hex20).
    let edges = m.node_set("z0_edges").unwrap();
    assert_eq!(edges.len(), 2 * 2 * (g.nx + g.ny));
    for &i in edges {
        let p = m.nodes[i];
        let on_border = [p[0] - lo[0], hi[0] - p[0], p[1] - lo[1], hi[1] - p[1]]
            .iter()
            .any(|d| d.abs() < tol);
        assert!((p[2] - lo[2]).abs() < tol && on_border, "{p:?}");
    }
    for (name, axis, at) in [
        ("x0", 0, lo[0]),
        ("x1", 0, hi[0]),
        ("y0", 1, lo[1]),
        ("y1", 1, hi[1]),
        ("z0", 2, lo[2]),
        ("z1", 2, hi[2]),
    ] {
        let set = m.node_set(name).unwrap();
        assert!(!set.is_empty());
        assert!(
            set.iter().all(|&i| (m.nodes[i][axis] - at).abs() < tol),
            "{name}"
        );
        assert!(!m.face_set(name).unwrap().is_empty());
    }
}

/// `-setnumber` overrides the DefineConstant defaults, and msh 4.1 binary reads the same as
/// ASCII.
#[test]
fn gmsh_setnumber_and_binary() {
    let g = coarse_rotor();
    let mut opts = GmshOptions {
        order: 1,
        binary: true,
        ..Default::default()
    };
    opts.set_numbers.insert("n_circ".into(), 12.0);
    opts.set_numbers.insert("r_out".into(), 3.0);
    let bin = mesh_with_gmsh(&geo::rotor(&g), "rotor_bin.msh", &opts);
    let want = RotorGeometry {
        n_circ: 12,
        r_out: 3.0,
        ..g.clone()
    };
    check_rotor(&bin, &want, 1);
    opts.binary = false;
    let ascii = mesh_with_gmsh(&geo::rotor(&g), "rotor_ascii.msh", &opts);
    // Same topology; coordinates equal to the 16 digits gmsh prints in ASCII.
    assert_eq!(bin.node_tags, ascii.node_tags);
    assert_eq!(bin.volumes, ascii.volumes);
    assert_eq!(bin.faces, ascii.faces);
    assert_eq!(bin.node_sets, ascii.node_sets);
    for (p, q) in bin.nodes.iter().zip(&ascii.nodes) {
        assert!(close(*p, *q, 1e-14 * 3.0), "{p:?} vs {q:?}");
    }
}

/// A `.geo` error is reported with gmsh's message (gmsh itself exits with status 0).
#[test]
fn gmsh_error_is_reported() {
    let g = RotorGeometry {
        n_circ: 10,
        ..coarse_rotor()
    };
    let path = out_dir("bad_rotor.msh");
    match mesh_geo(&geo::rotor(&g), &path, &GmshOptions::default()) {
        Err(MeshError::GmshFailed {
            command, message, ..
        }) => {
            assert!(command.contains("bad_rotor.geo"), "{command}");
            assert!(message.contains("n_circ = 10"), "{message}");
        }
        other => panic!("expected GmshFailed, got {other:?}"),
    }
    assert!(!path.exists());
}

/// A hexahedron written with repeated nodes (corners 2 = 3 and 6 = 7, an Ansys-style prism) is
/// read as the wedge it is; a repetition that is no wedge, pyramid or tet is an error naming the
/// element. The bottom face (a quad on a collapsed edge) would be degenerate, so the collapsed
/// files carry no face element.
#[test]
fn collapsed_hex_is_read_as_its_wedge_or_refused() {
    let text = HEX8_V22
        .replace(
            "3 5 2 1 1 10 11 12 13 14 15 16 17",
            "3 5 2 1 1 10 11 12 12 14 15 16 16",
        )
        .replace("2 3 2 2 1 10 13 12 11\n", "")
        .replace("$Elements\n4\n", "$Elements\n3\n");
    let m = parse_msh(text.as_bytes(), "prism.msh").unwrap();
    assert_eq!(m.volumes[0].kind, CellKind::Wedge6);
    let tags: Vec<u64> = m.volumes[0]
        .cell(0)
        .iter()
        .map(|&i| m.node_tags[i])
        .collect();
    assert_eq!(tags, [10, 11, 12, 14, 15, 16]);
    assert!(m.centroid_jacobian(0, 0) > 0.0);
    let bad = HEX8_V22
        .replace(
            "3 5 2 1 1 10 11 12 13 14 15 16 17",
            "3 5 2 1 1 10 10 12 13 14 15 16 17",
        )
        .replace("2 3 2 2 1 10 13 12 11\n", "")
        .replace("$Elements\n4\n", "$Elements\n3\n");
    let e = err_text(&bad);
    assert!(
        e.contains("hexahedron 3") && e.contains("repeats nodes") && e.contains("0=1"),
        "{e}"
    );
}
