//! Nastran bulk data.

use super::{check_cells, data, json, node, write};
use squeal_meshes::{read_bdf, BdfOptions, CellKind, Elastic};

fn mixed() -> (squeal_meshes::Mesh, squeal_meshes::ReadReport) {
    read_bdf(&data("mixed.bdf"), &BdfOptions::default()).unwrap()
}

/// Grid positions (CP in chained CORD2R → CORD2C → CORD2S systems, large field in an
/// include, free field with Nastran's exponent forms) equal pyNastran's, to round-off.
#[test]
fn mixed_deck_grid_positions_match_pynastran() {
    let (mesh, report) = mixed();
    let r = json("mixed.json");
    let pos = r["positions"].as_object().unwrap();
    assert_eq!(report.files.len(), 3, "{:?}", report.files);
    let mut worst: f64 = 0.0;
    for (i, t) in mesh.node_tags.iter().enumerate() {
        let want = &pos[&t.to_string()];
        for k in 0..3 {
            let w = want[k].as_f64().unwrap();
            worst = worst.max((mesh.nodes[i][k] - w).abs());
        }
    }
    // Coordinates are about 0.3 in size: 1e-15 relative.
    assert!(worst < 3e-16 * 1e3, "largest difference {worst:e}");
    // Grid 9001 belongs to no element: not a mesh node.
    assert!(!mesh.node_tags.contains(&9001));
    assert_eq!(mesh.nodes.len(), pos.len() - 1);
}

/// Every shape linear and quadratic (some written mirrored): the cells come out positive,
/// with each mid-edge node on its own edge (a wrong CHEXA20/CPENTA15 permutation would put
/// it on another), and with the element's grids.
#[test]
fn mixed_deck_cells_in_squeal_order() {
    let (mesh, _) = mixed();
    let r = json("mixed.json");
    // Grids in cylindrical and spherical systems, 11 digits in large field: the mid-edge
    // nodes are at their midpoints to ~1e-11 (cells are 0.01 in size; a wrong permutation
    // would be off by ~0.005).
    assert_eq!(check_cells(&mesh, 1e-9), 9);
    let mut kinds: Vec<CellKind> = mesh.volumes.iter().map(|b| b.kind).collect();
    kinds.sort();
    kinds.dedup();
    assert_eq!(kinds.len(), 8, "{kinds:?}");
    for b in &mesh.volumes {
        for i in 0..b.len() {
            let mut got: Vec<u64> = b.cell(i).iter().map(|&k| mesh.node_tags[k]).collect();
            let mut want: Vec<u64> = r["elements"][b.tags[i].to_string()]["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap())
                .collect();
            got.sort();
            want.sort();
            assert_eq!(got, want, "element {}", b.tags[i]);
        }
    }
    let names: Vec<_> = mesh
        .volumes
        .iter()
        .map(|b| b.name.clone().unwrap())
        .collect();
    assert!(
        names.iter().all(|n| n == "pid_1" || n == "pid_2"),
        "{names:?}"
    );
}

/// MAT1 as given; MAT9's 21 entries as pyNastran reads them; PSOLID 2's CORDM = CORD1R 4
/// on three grids, with pyNastran's origin and axes.
#[test]
fn mixed_deck_materials_and_axes() {
    let (mesh, report) = mixed();
    let r = json("mixed.json");
    let s1 = &mesh.sections["pid_1"];
    assert_eq!(
        s1.material.elastic,
        Elastic::Isotropic {
            young: 2.0e11,
            poisson: 0.29
        }
    );
    assert_eq!(s1.material.density, Some(7800.0));
    assert!(s1.axes.is_none());
    let s2 = &mesh.sections["pid_2"];
    let Elastic::Stiffness { c } = s2.material.elastic else {
        panic!("{:?}", s2.material.elastic)
    };
    // pyNastran's D is in Nastran's order xx, yy, zz, xy, yz, zx; squeal's Voigt order is
    // 11, 22, 33, 23, 13, 12.
    let voigt = [0, 1, 2, 5, 3, 4];
    for i in 0..6 {
        for j in 0..6 {
            let w = r["mat9"][i][j].as_f64().unwrap();
            let got = c[voigt[i]][voigt[j]];
            assert!((got - w).abs() <= 1e-12 * w.abs(), "G{}{}", i + 1, j + 1);
        }
    }
    assert_eq!(s2.material.density, Some(1800.0));
    let ax = s2.axes.expect("CORDM 4");
    for k in 0..3 {
        let o = r["cordm4"]["origin"][k].as_f64().unwrap();
        assert!((ax.origin[k] - o).abs() < 1e-15, "origin");
        for a in 0..3 {
            let w = r["cordm4"]["axes"][a][k].as_f64().unwrap();
            assert!(
                (ax.frame[a][k] - w).abs() < 1e-12,
                "axis {a}: {:?}",
                ax.frame[a]
            );
        }
    }
    assert!(
        report.notes.iter().any(|n| n.contains("PSHELL 7")),
        "{:?}",
        report.notes
    );
}

/// The case control's SPC = 10 is SPCADD 10 = SPC1 11 (grids 1-3, 123) + SPC 12 (grid 5,
/// 3); SET1 (in the main deck, and with THRU in free field) and shell faces as sets; the
/// cards squeal does not read listed with their counts.
#[test]
fn mixed_deck_constraints_sets_and_unsupported_cards() {
    let (mesh, report) = mixed();
    let mut want: Vec<(usize, usize)> = Vec::new();
    for g in [1, 2, 3] {
        for k in 0..3 {
            want.push((node(&mesh, g), k));
        }
    }
    want.push((node(&mesh, 5), 2));
    want.sort();
    assert_eq!(mesh.fixed, want);
    let set = |n: &str| -> Vec<u64> {
        mesh.node_sets[n]
            .iter()
            .map(|&i| mesh.node_tags[i])
            .collect()
    };
    assert_eq!(set("set1_5"), [1, 2, 3, 4]);
    assert_eq!(set("set1_6"), [1, 2, 3, 4]);
    assert_eq!(set("spc_11"), [1, 2, 3]);
    let faces = &mesh.faces["pid_7"];
    assert_eq!(faces.len(), 2);
    assert_eq!(faces.kind(), Some(CellKind::Quad4));
    let listed: Vec<(String, usize)> = report
        .unsupported
        .iter()
        .map(|u| (u.name.clone(), u.count))
        .collect();
    for card in ["CONM2", "EIGRL", "PARAM"] {
        assert!(listed.contains(&(card.to_string(), 1)), "{listed:?}");
    }
    assert!(report
        .unsupported
        .iter()
        .all(|u| u.first.contains("mixed.bdf:")));
    assert!(report.unsupported_summary().unwrap().contains("CONM2 ×1"));
}

/// `pids` reads one part of the deck; the other's PIDs are noted.
#[test]
fn pids_select_a_part() {
    let opts = BdfOptions {
        pids: vec![2],
        spc: Some(0),
    };
    let (mesh, report) = read_bdf(&data("mixed.bdf"), &opts).unwrap();
    assert_eq!(mesh.n_volume_cells(), 4);
    assert!(mesh.sections.contains_key("pid_2") && !mesh.sections.contains_key("pid_1"));
    assert!(mesh.fixed.is_empty());
    assert!(report.notes.iter().any(|n| n.contains("not selected")));
    let e = read_bdf(
        &data("mixed.bdf"),
        &BdfOptions {
            pids: vec![3],
            spc: None,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("mixed.bdf") && e.contains("PID 3") && e.contains("1, 2"),
        "{e}"
    );
}

/// The same grids in small, large and free field, with `+` and `*` continuations and tabs,
/// give the same mesh.
#[test]
fn field_formats_and_continuations_agree() {
    let hex = "CHEXA   1       1       1       2       3       4       5       6       +C1\n\
               +C1     7       8\n\
               PSOLID  1       1\nMAT1    1       2.1+5           .3      7.8-9\n";
    let grids = [
        // Small field.
        "GRID    1               0.      0.      0.\nGRID    2               1.      0.      0.\n\
         GRID    3               1.      1.      0.\nGRID    4               0.      1.      0.\n\
         GRID    5               0.      0.      1.\nGRID    6               1.      0.      1.\n\
         GRID    7               1.      1.      1.\nGRID    8               0.      1.      1.\n",
        // Large field with `*` continuations.
        "GRID*   1                               0.              0.\n*       0.\n\
         GRID*   2                               1.0+0           0.\n*       0.\n\
         GRID*   3                               1.              1.\n*       0.\n\
         GRID*   4                               0.              10.-1\n*       0.\n\
         GRID*   5                               0.              0.\n*       1.\n\
         GRID*   6                               1.              0.\n*       1.\n\
         GRID*   7                               1.              1.\n*       1.\n\
         GRID*   8                               0.              1.\n*       1.D0\n",
        // Free field, a blank-start continuation, tabs.
        "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n\
         GRID,5,,0.,0.,1. $ a comment\nGRID,6,,1.,0.,1.\nGRID\t7\t\t1.\t1.\t1.\nGRID,8,,0.,1.,1.\n",
    ];
    let mut meshes = Vec::new();
    for (k, g) in grids.iter().enumerate() {
        let p = write("formats", &format!("f{k}.bdf"), &format!("{g}{hex}"));
        meshes.push(read_bdf(&p, &BdfOptions::default()).unwrap().0);
    }
    for m in &meshes[1..] {
        assert_eq!(m.nodes, meshes[0].nodes);
        assert_eq!(m.volumes, meshes[0].volumes);
    }
    assert_eq!(
        meshes[0].sections["pid_1"].material.elastic,
        Elastic::Isotropic {
            young: 2.1e5,
            poisson: 0.3
        }
    );
}

/// The structural loss factor GE: MAT1's field 8 (small and free field) and MAT9's field 31
/// are read as the section's `structural_damping`, with no "not applied" note; a blank or zero
/// GE is none.
#[test]
fn mat1_and_mat9_ge_are_the_loss_factor() {
    let grids = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n\
                 GRID,5,,0.,0.,1.\nGRID,6,,1.,0.,1.\nGRID,7,,1.,1.,1.\nGRID,8,,0.,1.,1.\n\
                 CHEXA,1,1,1,2,3,4,5,6\n,7,8\nPSOLID,1,1\n";
    let cases = [
        (
            "small",
            "MAT1    1       2.1+5           .3      7.8-9                   .25\n",
            Some(0.25),
        ),
        ("free", "MAT1,1,2.1+5,,.3,7.8-9,,,0.25\n", Some(0.25)),
        ("blank", "MAT1,1,2.1+5,,.3,7.8-9\n", None),
        ("zero", "MAT1,1,2.1+5,,.3,7.8-9,,,0.\n", None),
        (
            "mat9",
            "MAT9,1,1.,,,,,,1.\n,,,,,1.,,,\n,1.,,,1.,,1.,1.\n,,,,,,,0.15\n",
            Some(0.15),
        ),
    ];
    for (name, mat, want) in cases {
        let p = write("ge", &format!("{name}.bdf"), &format!("{grids}{mat}"));
        let (mesh, report) = read_bdf(&p, &BdfOptions::default()).unwrap();
        let m = &mesh.sections["pid_1"].material;
        assert_eq!(m.structural_damping, want, "{name}");
        assert!(
            report.notes.iter().all(|n| !n.contains("GE")),
            "{name}: {:?}",
            report.notes
        );
    }
}

/// Bad input: each error names the file, the line and the entity.
#[test]
fn bad_decks_name_file_line_and_entity() {
    let base = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n\
                GRID,5,,0.,0.,1.\nGRID,6,,1.,0.,1.\nGRID,7,,1.,1.,1.\nGRID,8,,0.,1.,1.\n";
    let hex = "CHEXA,12,1,1,2,3,4,5,6\n,7,8\n";
    let prop = "PSOLID,1,1\nMAT1,1,2.1+5,,.3,7.8-9\n";
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "no-psolid",
            format!("{base}{hex}MAT1,1,2.1+5,,.3\n"),
            vec![":9:", "CHEXA 12", "PSOLID"],
        ),
        (
            "no-mat",
            format!("{base}{hex}PSOLID,1,7\n"),
            vec![":11:", "PSOLID 1", "MID = 7"],
        ),
        (
            "shell-mat",
            format!("{base}{hex}PSOLID,1,7\nMAT2,7,2.1+5,,,2.1+5\n"),
            vec![
                ":11:",
                "PSOLID 1",
                "MID = 7 is MAT2 7",
                ":12",
                "shell material",
            ],
        ),
        (
            "mat11",
            format!(
                "{base}{hex}PSOLID,1,7\nMAT11,7,8.+9,6.5+9,2.+9,.25,.12,.15,3.+9\n,1.1+9,.9+9\n"
            ),
            vec![":11:", "PSOLID 1", "MID = 7 is MAT11 7", ":12", "MAT9"],
        ),
        (
            "undefined-grid",
            format!("{base}CHEXA,12,1,1,2,3,4,5,6\n,7,99\n{prop}"),
            vec![":9:", "CHEXA 12", "G8 = 99"],
        ),
        (
            "bad-number",
            format!("{base}GRID,9,,1.2.3,0.,0.\n{hex}{prop}"),
            vec![":9:", "GRID 9", "X1", "1.2.3"],
        ),
        (
            "partial-midside",
            format!("{base}CHEXA,12,1,1,2,3,4,5,6\n,7,8,9\n{prop}"),
            vec![":9:", "CHEXA 12", "mid-edge"],
        ),
        (
            "orphan-continuation",
            format!("+C1,1,2\n{base}"),
            vec![":1:", "continuation"],
        ),
        (
            "cord-cycle",
            format!(
                "CORD2R,5,6,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\nCORD2R,6,5,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\n\
                 GRID,20,5,0.,0.,0.\n{base}{hex}{prop}"
            ),
            vec![":1:", "CORD2R 5", "CORD2R 6", "cycle"],
        ),
        (
            "cord-rid",
            format!("CORD2C,5,9,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\n{base}{hex}{prop}"),
            vec![":1:", "CORD2C 5", "RID = 9"],
        ),
        (
            "grid-cp",
            format!("GRID,20,4,0.,0.,0.\n{base}{hex}{prop}"),
            vec![":1:", "GRID 20", "CP = 4"],
        ),
        (
            "spc-grid",
            format!("{base}{hex}{prop}SPC1,1,123,1,77\n"),
            vec![":13:", "SPC1 1", "GRID 77"],
        ),
        (
            "spc1-range-empty",
            format!("{base}{hex}{prop}SPC1,1,123,100,THRU,200\n"),
            vec![":13:", "SPC1 1", "no GRID between 100 and 200"],
        ),
        (
            "set1-names-nothing",
            format!("{base}{hex}{prop}SET1,3,1,2,500\n"),
            vec![":13:", "SET1 3", "500"],
        ),
        (
            "include-missing",
            format!("{base}INCLUDE 'nowhere.bdf'\n{hex}{prop}"),
            vec![":9:", "nowhere.bdf"],
        ),
        (
            "cordm-missing",
            format!("{base}{hex}PSOLID,1,1,8\nMAT1,1,2.1+5,,.3,7.8-9\n"),
            vec![":11:", "PSOLID 1", "CORDM = 8"],
        ),
        (
            "cd-spc",
            format!(
                "CORD2C,5,,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\n{base}GRID,9,,1.,1.,2.,5\n{hex}{prop}\
                 SPC1,1,1,9\n"
            ),
            vec![":16:", "SPC1 1", "GRID 9", "CD = 5"],
        ),
        (
            "mat1-ge-negative",
            format!("{base}{hex}PSOLID,1,1\nMAT1,1,2.1+5,,.3,7.8-9,,,-.1\n"),
            vec![":12:", "MAT1 1", "GE = -0.1", "loss factor"],
        ),
        (
            "mat9-cordm-element",
            format!("{base}{hex}PSOLID,1,1,-1\nMAT9,1,1.,,,,,,1.\n,,,,,1.,,,\n,1.,,,1.,,1.,1.\n"),
            vec![":11:", "PSOLID 1", "CORDM = -1", "not yet supported"],
        ),
    ];
    for (name, text, want) in cases {
        let p = write("bad", &format!("{name}.bdf"), &text);
        let e = match read_bdf(&p, &BdfOptions::default()) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(&format!("{name}.bdf")), "{name}: {e}");
        for w in want {
            assert!(e.contains(w), "{name}: `{w}` not in: {e}");
        }
    }
}

/// SPC1 `THRU` takes the grids that exist in the range (Nastran ignores the missing ones).
#[test]
fn spc1_thru_takes_the_existing_grids() {
    let text = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n\
                GRID,5,,0.,0.,1.\nGRID,6,,1.,0.,1.\nGRID,7,,1.,1.,1.\nGRID,8,,0.,1.,1.\n\
                CHEXA,1,1,1,2,3,4,5,6\n,7,8\nPSOLID,1,1\nMAT1,1,1.,,.3,1.\n\
                SPC1,3,12,2,THRU,7000000000\n";
    let p = write("thru", "t.bdf", text);
    let (mesh, _) = read_bdf(&p, &BdfOptions::default()).unwrap();
    assert_eq!(mesh.fixed.len(), 7 * 2);
    assert!(mesh
        .fixed
        .iter()
        .all(|&(i, k)| mesh.node_tags[i] >= 2 && k < 2));
}

/// An include that includes itself is a cycle, not a hang; a quoted name may go on over
/// lines; relative paths are relative to the including file.
#[test]
fn includes_nest_relative_to_their_file_and_refuse_cycles() {
    let sub = write(
        "inc/sub",
        "grids.bdf",
        "GRID,1,,0.,0.,0.\nINCLUDE 'more/\n  rest.bdf'\n",
    );
    write(
        "inc/sub/more",
        "rest.bdf",
        "GRID,2,,1.,0.,0.\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\nGRID,5,,0.,0.,1.\n\
         GRID,6,,1.,0.,1.\nGRID,7,,1.,1.,1.\nGRID,8,,0.,1.,1.\n",
    );
    assert!(sub.exists());
    let main = write(
        "inc",
        "main.bdf",
        "INCLUDE 'sub/grids.bdf'\nCHEXA,1,1,1,2,3,4,5,6\n,7,8\nPSOLID,1,1\nMAT1,1,1.,,.3,1.\n",
    );
    let (mesh, report) = read_bdf(&main, &BdfOptions::default()).unwrap();
    assert_eq!(mesh.nodes.len(), 8);
    assert_eq!(report.files.len(), 3);
    let cyc = write("cycle", "a.bdf", "INCLUDE 'b.bdf'\n");
    write("cycle", "b.bdf", "GRID,1,,0.,0.,0.\nINCLUDE 'a.bdf'\n");
    let e = read_bdf(&cyc, &BdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.bdf:2") && e.contains("cycle"), "{e}");
}
