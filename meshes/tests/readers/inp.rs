//! Abaqus input.

use super::{check_cells, data, json, node, write};
use squeal_meshes::{read_inp, AxesKind, CellKind, Elastic, InpOptions};

fn link2() -> InpOptions {
    InpOptions {
        instances: vec!["link-2".into()],
        ..Default::default()
    }
}

fn pt(v: &serde_json::Value) -> [f64; 3] {
    [0, 1, 2].map(|k| v[k].as_f64().unwrap())
}

/// Both instances: Link-1 where the part is, Link-2 translated then rotated by 37.5° about
/// the axis a–b (numpy's Rodrigues in the generator); node tags offset per instance.
#[test]
fn instances_are_placed_by_translation_then_rotation() {
    let (mesh, report) = read_inp(&data("assembly.inp"), &InpOptions::default()).unwrap();
    let r = json("assembly.json");
    let n_part = r["link1"].as_object().unwrap().len();
    assert_eq!(mesh.nodes.len(), 2 * n_part);
    let base = 100; // the smallest power of ten above the largest label (65)
    for (inst, key) in [(1u64, "link1"), (2, "link2")] {
        for (lab, x) in r[key].as_object().unwrap() {
            let i = node(&mesh, inst * base + lab.parse::<u64>().unwrap());
            let w = pt(x);
            for k in 0..3 {
                assert!((mesh.nodes[i][k] - w[k]).abs() < 1e-15, "{key} node {lab}");
            }
        }
    }
    assert_eq!(check_cells(&mesh, 1e-15), 10);
    // Part-level names carry the instance when both are read.
    assert!(mesh.node_sets.contains_key("Link-1.FIX") && mesh.node_sets.contains_key("Link-2.FIX"));
    assert_eq!(report.files.len(), 2);
}

/// One instance: labels as node tags, its sections with the file's materials and the
/// orientations turned with the instance, its element sets as blocks.
#[test]
fn one_instance_sections_materials_and_axes() {
    let (mesh, report) = read_inp(&data("assembly.inp"), &link2()).unwrap();
    let r = json("assembly.json");
    assert_eq!(mesh.nodes.len(), r["link2"].as_object().unwrap().len());
    let i = node(&mesh, 7);
    let w = pt(&r["link2"]["7"]);
    assert!((0..3).all(|k| (mesh.nodes[i][k] - w[k]).abs() < 1e-15));
    let mut names: Vec<String> = mesh
        .volumes
        .iter()
        .map(|b| b.name.clone().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["E_C3D10", "E_C3D15", "E_C3D8I", "HEXES"]);
    let rot: Vec<[f64; 3]> = r["rotation"].as_array().unwrap().iter().map(pt).collect();
    let turn =
        |v: [f64; 3]| -> [f64; 3] { [0, 1, 2].map(|i| (0..3).map(|k| rot[i][k] * v[k]).sum()) };
    let hexes = &mesh.sections["HEXES"];
    assert_eq!(
        hexes.material.elastic,
        Elastic::EngineeringConstants {
            young: [4.0e9, 4.0e9, 1.2e9],
            poisson: [0.25, 0.1, 0.1],
            shear: [1.6e9, 0.6e9, 0.6e9]
        }
    );
    assert_eq!(hexes.material.density, Some(2500.0));
    let ax = hexes.axes.unwrap();
    assert_eq!(ax.kind, AxesKind::Rectangular);
    for (a, v) in [[0.6, 0.8, 0.0], [-0.8, 0.6, 0.0], [0.0, 0.0, 1.0]]
        .iter()
        .enumerate()
    {
        let want = turn(*v);
        assert!(
            (0..3).all(|k| (ax.frame[a][k] - want[k]).abs() < 1e-15),
            "axis {a}"
        );
    }
    let ring = mesh.sections["E_C3D15"].axes.unwrap();
    assert_eq!(ring.kind, AxesKind::Cylindrical);
    let z = turn([0.0, 0.0, 1.0]);
    assert!((0..3).all(|k| (ring.frame[2][k] - z[k]).abs() < 1e-15));
    let Elastic::Stiffness { c } = mesh.sections["E_C3D15"].material.elastic else {
        panic!("ORTHOTROPIC")
    };
    // D1111, D1122, D2222, D1133, D2233, D3333, D1212, D1313, D2323 in Voigt 11 22 33 23 13 12.
    assert_eq!(
        [c[0][0], c[0][1], c[1][1], c[0][2], c[1][2], c[2][2]],
        [12e9, 3e9, 10e9, 2e9, 2.5e9, 9e9]
    );
    assert_eq!([c[5][5], c[4][4], c[3][3]], [2e9, 3e9, 2.5e9]);
    assert_eq!(
        mesh.sections["E_C3D10"].material.elastic,
        Elastic::Isotropic {
            young: 2.1e11,
            poisson: 0.3
        }
    );
    let notes = report.notes.join("\n");
    for w in ["C3D20R", "C3D8I", "*EXPANSION"] {
        assert!(notes.contains(w), "{w} not in {notes}");
    }
    // LINING's `*Damping, structural=0.05` is its loss factor, read (no note).
    assert!(!notes.contains("*DAMPING"), "{notes}");
    assert_eq!(hexes.material.structural_damping, Some(0.05));
    assert_eq!(mesh.sections["E_C3D10"].material.structural_damping, None);
    let unsupported: Vec<&str> = report.unsupported.iter().map(|u| u.name.as_str()).collect();
    for w in ["*HEADING", "*STEP", "*FREQUENCY"] {
        assert!(unsupported.contains(&w), "{unsupported:?}");
    }
}

/// Sets: GENERATE, sets of sets, ELSET= node sets, assembly sets of one instance; surfaces
/// by S-number (hexahedron S1 = its bottom, tetrahedron S2) and the free faces of a set;
/// *BOUNDARY in the part and in the step.
#[test]
fn sets_surfaces_and_boundaries() {
    let (mesh, _) = read_inp(&data("assembly.inp"), &link2()).unwrap();
    let r = json("assembly.json");
    let tags = |n: &str| -> Vec<u64> {
        mesh.node_sets[n]
            .iter()
            .map(|&i| mesh.node_tags[i])
            .collect()
    };
    assert_eq!(tags("FIX"), [1, 4, 5, 8, 12]);
    assert_eq!(tags("TIPS"), [7]);
    assert_eq!(tags("HEX1NODES").len(), 32);
    let bottom = &mesh.faces["BOTTOM"];
    assert_eq!(bottom.len(), 2);
    assert_eq!(bottom.kind(), Some(CellKind::Quad8));
    // S1 of a hexahedron is its face 1-2-3-4; outward means along −(local ζ).
    for f in bottom.iter() {
        let mut got: Vec<u64> = f.nodes[..4].iter().map(|&i| mesh.node_tags[i]).collect();
        got.sort();
        let e = &r["elements"][f.tag as usize - 1][2];
        let mut want: Vec<u64> = (0..4).map(|k| e[k].as_u64().unwrap()).collect();
        want.sort();
        assert_eq!(got, want);
    }
    let tet = &mesh.faces["TETFACE"];
    assert_eq!(tet.kind(), Some(CellKind::Tri6));
    let mut got: Vec<u64> = tet.iter().next().unwrap().nodes[..3]
        .iter()
        .map(|&i| mesh.node_tags[i])
        .collect();
    got.sort();
    // S2 of C3D10 element 3 (nodes 33…): corners 1, 4, 2 → labels 33, 36, 34.
    assert_eq!(got, [33, 34, 36]);
    let skin = &mesh.faces["SKIN"];
    assert_eq!(skin.len(), 5);
    // The assembly's surface on Link-2's HEXES (read here), absent with Link-1 alone.
    assert_eq!(mesh.faces["ASM_BOTTOM"].len(), 2);
    let one = InpOptions {
        instances: vec!["Link-1".into()],
        ..Default::default()
    };
    let (m1, _) = read_inp(&data("assembly.inp"), &one).unwrap();
    assert!(!m1.faces.contains_key("ASM_BOTTOM") && !m1.node_sets.contains_key("TIPS"));
    let mut fixed: Vec<(u64, usize)> = mesh
        .fixed
        .iter()
        .map(|&(i, k)| (mesh.node_tags[i], k))
        .collect();
    fixed.sort();
    let mut want: Vec<(u64, usize)> = [1, 4, 5, 7, 8, 12]
        .iter()
        .flat_map(|&n| (0..3).map(move |k| (n, k)))
        .collect();
    want.sort();
    assert_eq!(fixed, want);
}

/// meshio's Abaqus writer (C3D20RH, *NSET, *ELSET, no sections): read with the scene's
/// material, sets by name, every cell positive with its mid-edge nodes on its edges.
#[test]
fn meshio_written_input() {
    let (mesh, report) = read_inp(&data("bracket_hex20.inp"), &InpOptions::default()).unwrap();
    assert!(mesh.sections.is_empty());
    assert!(mesh.volumes.iter().all(|b| b.kind == CellKind::Hex20));
    // gmsh put the mid-edge nodes at the midpoints to 1.7e-13 (meshio's reading of the .msh).
    assert_eq!(check_cells(&mesh, 1e-12), mesh.n_volume_cells());
    assert!(!mesh.node_sets["clamp"].is_empty() && !mesh.node_sets["top"].is_empty());
    assert!(report.notes.iter().any(|n| n.contains("C3D20RH")));
}

/// Bad input: each error names the file, the line and the entity.
#[test]
fn bad_inputs_name_file_line_and_entity() {
    let nodes = "*NODE\n1, 0., 0., 0.\n2, 1., 0., 0.\n3, 0., 1., 0.\n4, 0., 0., 1.\n";
    let tet = "*ELEMENT, TYPE=C3D4, ELSET=B\n1, 1, 2, 3, 4\n";
    let mat = "*MATERIAL, NAME=M\n*ELASTIC\n1., 0.3\n*DENSITY\n1.\n";
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "unknown-element",
            format!("{nodes}*ELEMENT, TYPE=S4R\n1, 1, 2, 3, 4\n"),
            vec![":7:", "element 1", "S4R", "elsets"],
        ),
        (
            "undefined-node",
            format!("{nodes}*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 9\n"),
            vec![":7:", "element 1", "node 9"],
        ),
        (
            "nset-nothing",
            format!("{nodes}{tet}*NSET, NSET=X\n1, 77\n"),
            vec![":9:", "*NSET X", "node 77"],
        ),
        (
            "nset-unknown-set",
            format!("{nodes}{tet}*NSET, NSET=X\nNOSUCH\n"),
            vec![":9:", "*NSET X", "NOSUCH"],
        ),
        (
            "generate-nothing",
            format!("{nodes}{tet}*ELSET, ELSET=X, GENERATE\n10, 20, 1\n"),
            vec![":9:", "*ELSET X", "no element between 10 and 20"],
        ),
        (
            "section-elset",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=NOPE, MATERIAL=M\n{mat}"),
            vec![":8:", "ELSET=NOPE"],
        ),
        (
            "section-material",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=B, MATERIAL=STEEL\n{mat}"),
            vec![":8:", "MATERIAL=STEEL"],
        ),
        (
            "no-elastic",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=B, MATERIAL=M\n*MATERIAL, NAME=M\n*DENSITY\n1.\n"),
            vec![":9:", "*MATERIAL M", "*ELASTIC"],
        ),
        (
            "tet-face",
            format!("{nodes}{tet}*SURFACE, NAME=S\n1, S5\n"),
            vec![":9:", "*SURFACE S", "element 1", "S5"],
        ),
        (
            "ncopy",
            format!("{nodes}*NCOPY, OLD SET=A, NEW SET=B, CHANGE NUMBER=10\n"),
            vec![":6:", "*NCOPY"],
        ),
        (
            "instance-part",
            "*ASSEMBLY, NAME=A\n*INSTANCE, NAME=I, PART=NOPART\n*END INSTANCE\n*END ASSEMBLY\n".into(),
            vec![":2:", "*INSTANCE I", "NOPART"],
        ),
        (
            "node-count",
            format!("{nodes}*ELEMENT, TYPE=C3D10\n1, 1, 2, 3, 4\n"),
            vec![":7:", "*ELEMENT 1", "4 node labels, expected 10"],
        ),
        (
            "temperature-table",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=B, MATERIAL=M\n*MATERIAL, NAME=M\n*ELASTIC\n1., 0.3, 20.\n2., 0.3, 100.\n"),
            vec![":12:", "*MATERIAL M", "temperature"],
        ),
        (
            "damping-negative",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=B, MATERIAL=M\n{mat}*DAMPING, STRUCTURAL=-0.1\n"),
            vec![":14:", "*MATERIAL M", "STRUCTURAL=-0.1", "loss factor"],
        ),
        (
            "damping-nan",
            format!("{nodes}{tet}*SOLID SECTION, ELSET=B, MATERIAL=M\n{mat}*DAMPING, STRUCTURAL=nan\n"),
            vec![":14:", "*MATERIAL M", "STRUCTURAL=nan", "not a number"],
        ),
        (
            "boundary-set",
            format!("{nodes}{tet}*BOUNDARY\nNOSET, 1, 3\n"),
            vec![":9:", "NOSET"],
        ),
        (
            "boundary-magnitude",
            format!("{nodes}{tet}*NSET, NSET=F\n1\n*BOUNDARY\nF, 1, 1, 0.5\n"),
            vec![":11:", "0.5"],
        ),
    ];
    for (name, text, want) in cases {
        let p = write("bad-inp", &format!("{name}.inp"), &text);
        let e = match read_inp(&p, &InpOptions::default()) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(&format!("{name}.inp")), "{name}: {e}");
        for w in want {
            assert!(e.contains(w), "{name}: `{w}` not in: {e}");
        }
    }
}

/// `*DAMPING, STRUCTURAL=η` inside a *MATERIAL is the section's loss factor; ALPHA and BETA
/// (Rayleigh) are not read and listed in a note.
#[test]
fn damping_structural_is_the_loss_factor() {
    let head = "*NODE\n1, 0., 0., 0.\n2, 1., 0., 0.\n3, 0., 1., 0.\n4, 0., 0., 1.\n\
                *ELEMENT, TYPE=C3D4, ELSET=B\n1, 1, 2, 3, 4\n\
                *SOLID SECTION, ELSET=B, MATERIAL=M\n\
                *MATERIAL, NAME=M\n*ELASTIC\n1., 0.3\n*DENSITY\n1.\n";
    let p = write(
        "damping",
        "s.inp",
        &format!("{head}*DAMPING, STRUCTURAL=0.25\n"),
    );
    let (mesh, report) = read_inp(&p, &InpOptions::default()).unwrap();
    assert_eq!(mesh.sections["B"].material.structural_damping, Some(0.25));
    assert!(
        report.notes.iter().all(|n| !n.contains("DAMPING")),
        "{:?}",
        report.notes
    );
    let p = write(
        "damping",
        "ab.inp",
        &format!("{head}*DAMPING, ALPHA=2., STRUCTURAL=0.1\n"),
    );
    let (mesh, report) = read_inp(&p, &InpOptions::default()).unwrap();
    assert_eq!(mesh.sections["B"].material.structural_damping, Some(0.1));
    let notes = report.notes.join("\n");
    assert!(
        notes.contains("*DAMPING ALPHA=2.") && !notes.contains("STRUCTURAL="),
        "{notes}"
    );
}

/// Model data after *END ASSEMBLY (where Abaqus/CAE writes the boundary conditions of the
/// initial step's model data) names `instance.set`s: its *BOUNDARY holds the instances' nodes.
/// Before an *ASSEMBLY, a model-level *BOUNDARY names nothing the instances hold: an error
/// naming the line, not conditions dropped in silence (they were, until 2026-11-28).
#[test]
fn model_level_boundaries_after_the_assembly_fix_instance_sets() {
    let part = "*PART, NAME=P\n*NODE\n1, 0., 0., 0.\n2, 1., 0., 0.\n3, 0., 1., 0.\n4, 0., 0., 1.\n\
                *ELEMENT, TYPE=C3D4, ELSET=B\n1, 1, 2, 3, 4\n*NSET, NSET=BASE\n1, 2\n\
                *SOLID SECTION, ELSET=B, MATERIAL=M\n,\n*END PART\n";
    let asm = "*ASSEMBLY, NAME=A\n*INSTANCE, NAME=I1, PART=P\n*END INSTANCE\n\
               *INSTANCE, NAME=I2, PART=P\n0., 0., 2.\n*END INSTANCE\n*END ASSEMBLY\n";
    let mat = "*MATERIAL, NAME=M\n*ELASTIC\n1., 0.3\n*DENSITY\n1.\n";
    let bc = "*BOUNDARY\nI1.BASE, 1, 3\n*BOUNDARY\nI2.BASE, 3, 3\n";
    let p = write("model-bc", "after.inp", &format!("{part}{asm}{mat}{bc}"));
    for (inst, want) in [
        ("I1", vec![(1, 0), (1, 1), (1, 2), (2, 0), (2, 1), (2, 2)]),
        ("I2", vec![(1, 2), (2, 2)]),
    ] {
        let opts = InpOptions {
            instances: vec![inst.into()],
            ..Default::default()
        };
        let (mesh, report) = read_inp(&p, &opts).unwrap();
        let mut fixed: Vec<(u64, usize)> = mesh
            .fixed
            .iter()
            .map(|&(i, k)| (mesh.node_tags[i], k))
            .collect();
        fixed.sort();
        assert_eq!(fixed, want, "{inst}");
        assert_eq!(report.counts["fixed DOFs"], want.len(), "{inst}");
    }
    let p = write(
        "model-bc",
        "before.inp",
        &format!("{part}*BOUNDARY\n1, 1, 3\n{asm}{mat}"),
    );
    let e = read_inp(&p, &InpOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("before.inp:14:") && e.contains("before the *ASSEMBLY"),
        "{e}"
    );
}

/// Leaving an unread element type out with `elsets`; selection errors list what exists.
#[test]
fn elsets_leave_other_elements_out() {
    let text = "*NODE\n1, 0., 0., 0.\n2, 1., 0., 0.\n3, 0., 1., 0.\n4, 0., 0., 1.\n\
                *ELEMENT, TYPE=C3D4, ELSET=SOLID\n1, 1, 2, 3, 4\n\
                *ELEMENT, TYPE=S3, ELSET=SKIN\n2, 1, 2, 3\n";
    let p = write("elsets", "m.inp", text);
    let opts = InpOptions {
        elsets: vec!["solid".into()],
        ..Default::default()
    };
    let (mesh, _) = read_inp(&p, &opts).unwrap();
    assert_eq!(mesh.n_volume_cells(), 1);
    let opts = InpOptions {
        elsets: vec!["NOPE".into()],
        ..Default::default()
    };
    let e = read_inp(&p, &opts).unwrap_err().to_string();
    assert!(
        e.contains("m.inp") && e.contains("NOPE") && e.contains("SOLID"),
        "{e}"
    );
}
