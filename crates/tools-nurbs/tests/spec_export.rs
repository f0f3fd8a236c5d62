//! Shipped tool specs build, S-rail seams are G1, faceted tools read from OBJ/STL agree with the exact ones, VTU reads back.

use plugins_api::{ToolSurface, Vec3};
use std::path::{Path, PathBuf};
use tools_nurbs::FacetedTool;
use tools_nurbs::export::{tessellate, write_obj, write_vtu};
use tools_nurbs::mesh_io::{parse_stl, read_mesh};
use tools_nurbs::spec::{Tool, load, parse};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/tools")
}

/// Both shipped specs build; the square-cup set has the docs/benchmarks.md §1 placement.
#[test]
fn shipped_square_cup_and_s_rail_specs_build() {
    let cup = load(&scenes().join("square-cup-tools.toml")).unwrap();
    let names: Vec<&str> = cup.iter().map(|t| t.name()).collect();
    assert_eq!(names, ["blankholder", "die", "punch"]);
    // Punch faces down with its nose on the blank top (z = 0.78).
    let p = cup[2].project(&Vec3::new(3.0, 4.0, 0.0), None).unwrap();
    assert!((p.distance - 0.78).abs() < 1e-12 && (p.normal.z + 1.0).abs() < 1e-14);
    let rail = load(&scenes().join("s-rail-tools.toml")).unwrap();
    assert_eq!(rail.len(), 3);
    // Above the punch top at the start: 2 mm above, flat.
    let p = rail[2].project(&Vec3::new(10.0, 0.0, 2.0), None).unwrap();
    assert!((p.distance - 2.0).abs() < 1e-12 && p.k1.abs() < 1e-12);
    // Beside the punch wall on straight 1: the wall at y = 15.
    let p = rail[2]
        .project(&Vec3::new(10.0, 18.0, -20.0), None)
        .unwrap();
    assert!((p.distance - 3.0).abs() < 1e-10 && (p.normal.y - 1.0).abs() < 1e-12);
    // Die: normal down on its face.
    let p = rail[1].project(&Vec3::new(0.0, 50.0, 0.0), None).unwrap();
    assert!((p.distance - 1.0).abs() < 1e-12 && (p.normal.z + 1.0).abs() < 1e-14);
}

/// The S-rail reconstruction is G1 across all its seams (1e-9), like the square cup.
#[test]
fn s_rail_reconstruction_seams_are_g1() {
    for tool in load(&scenes().join("s-rail-tools.toml")).unwrap() {
        let Tool::Nurbs(tool) = tool else {
            unreachable!()
        };
        let mut seams = 0;
        for (a, pa) in tool.patches().iter().enumerate() {
            let (du, dv) = pa.surface.domain();
            for k in 0..5 {
                let t = (k as f64 + 0.5) / 5.0;
                for (u, v) in [
                    (du[0], dv[0] + t * (dv[1] - dv[0])),
                    (du[1], dv[0] + t * (dv[1] - dv[0])),
                    (du[0] + t * (du[1] - du[0]), dv[0]),
                    (du[0] + t * (du[1] - du[0]), dv[1]),
                ] {
                    let x = pa.surface.point(u, v);
                    let na = tool.project_on_patch(a, &x).unwrap().normal;
                    for b in 0..tool.patches().len() {
                        if b == a {
                            continue;
                        }
                        let pb = tool.project_on_patch(b, &x).unwrap();
                        if (pb.point - x).norm() < 1e-9 {
                            seams += 1;
                            let dn = (na - pb.normal).norm();
                            assert!(
                                dn < 1e-9,
                                "{}: patches {a}/{b} normal jump {dn:e}",
                                tool.name()
                            );
                        }
                    }
                }
            }
        }
        assert!(seams > 0, "{}: no seams found", tool.name());
    }
}

/// Faceted tool from an exported OBJ of the exact punch: distances agree with
/// the exact tool to the tessellation's chord error, normals to a few degrees,
/// and a binary and an ASCII STL of the same facets give identical answers.
#[test]
fn faceted_punch_from_obj_and_stl_tracks_the_exact_punch() {
    let dir = std::env::temp_dir().join(format!("tools-nurbs-facets-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = "[tools.punch]\nkind = \"punch\"\nmodel = \"full\"\n";
    let exact = parse(text, &dir).unwrap().remove(0);
    let obj = dir.join("punch.obj");
    write_obj(&obj, &tessellate(&exact), "punch").unwrap();
    let mesh = read_mesh(&obj).unwrap();
    let facets = FacetedTool::new("punch", &mesh, false).unwrap();
    // Binary and ASCII STL of the same triangles.
    let mut bin = vec![0u8; 80];
    bin.extend((mesh.triangles.len() as u32).to_le_bytes());
    let mut ascii = String::from("solid punch\n");
    for t in &mesh.triangles {
        bin.extend([0u8; 12]);
        ascii.push_str("facet normal 0 0 0\nouter loop\n");
        for &i in t {
            let v = mesh.vertices[i as usize];
            for c in [v.x, v.y, v.z] {
                bin.extend((c as f32).to_le_bytes());
            }
            ascii.push_str(&format!(
                "vertex {} {} {}\n",
                v.x as f32, v.y as f32, v.z as f32
            ));
        }
        ascii.push_str("endloop\nendfacet\n");
        bin.extend([0u8; 2]);
    }
    ascii.push_str("endsolid punch\n");
    let from_bin = FacetedTool::new("b", &parse_stl(&bin).unwrap(), false).unwrap();
    let from_ascii = FacetedTool::new("a", &parse_stl(ascii.as_bytes()).unwrap(), false).unwrap();
    assert_eq!(from_bin.facet_count(), from_ascii.facet_count());
    let mut worst = (0.0f64, 0.0f64);
    for i in 0..400 {
        let s = i as f64 * 0.61803;
        let x = Vec3::new(
            40.0 * (s.fract() - 0.5) * 2.0,
            40.0 * ((s * 1.7).fract() - 0.5) * 2.0,
            3.0 - 30.0 * (s * 2.3).fract(),
        );
        let e = exact.project(&x, None).unwrap();
        let f = facets.project(&x, None).unwrap();
        worst.0 = worst.0.max((e.distance - f.distance).abs());
        worst.1 = worst.1.max(e.normal.angle(&f.normal));
        let a = from_ascii.project(&x, None).unwrap();
        let b = from_bin.project(&x, None).unwrap();
        // ASCII decimals of f32 values re-read as f64 differ from the binary f32 by ~1e-7 relative.
        assert!((a.distance - b.distance).abs() < 1e-5);
        // Warm start from the facet answer reproduces it.
        let w = facets.project(&x, Some(f.hint())).unwrap();
        assert_eq!((w.patch, w.distance), (f.patch, f.distance));
    }
    // Chord sag of the tessellation: 8 uniform parameter steps of a rational
    // quarter arc subtend at most 11.82°, so r (1 - cos 5.91°) per curved
    // direction; the torus corners are curved both ways (r = 10 around, 8 in
    // profile): 0.0532 + 0.0425 = 0.0957 mm bounds the distance error.
    assert!(worst.0 < 0.0957, "faceted vs exact distance: {}", worst.0);
    assert!(
        worst.1 < 0.2,
        "faceted vs exact normal angle: {} rad",
        worst.1
    );
    eprintln!(
        "faceted vs exact: distance {:.3e} mm, normal {:.3e} rad",
        worst.0, worst.1
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Curvature estimate of a finely faceted cylinder (radius 20) ≈ 1/20 on the facets' interiors.
#[test]
fn faceted_cylinder_curvature_estimate_is_close_to_one_over_radius() {
    let dir = std::env::temp_dir();
    let text = "[tools.c]\nkind = \"cylinder\"\nradius = 20.0\nlength = 40.0\n";
    let exact = parse(text, &dir).unwrap().remove(0);
    let t = tessellate(&exact);
    let mut mesh = tools_nurbs::mesh_io::TriMesh {
        vertices: t.points.clone(),
        triangles: vec![],
    };
    for c in &t.cells {
        mesh.triangles.push([c[0], c[1], c[2]]);
        mesh.triangles.push([c[0], c[2], c[3]]);
    }
    let f = FacetedTool::new("c", &mesh, false).unwrap();
    for th in [0.3f64, 1.1, 2.5, 4.0] {
        let x = Vec3::new(25.0 * th.cos(), 3.0, 25.0 * th.sin());
        let p = f.project(&x, None).unwrap();
        assert!((p.k1 - 0.05).abs() < 0.05 * 0.05, "k1 = {}", p.k1);
        assert!(p.k2.abs() < 0.05 * 0.05, "k2 = {}", p.k2);
        // Chord sag: steps of at most 11.82° (rational quarter arcs, 8 uniform
        // parameter steps): 20 (1 - cos 5.91°) ≈ 0.1064 mm.
        assert!((p.distance - 5.0).abs() < 0.1064, "distance {}", p.distance);
    }
}

/// The VTU export is read back by vtkio's XML reader with the right sizes and fields.
#[test]
fn vtu_export_reads_back_with_vtkio() {
    let dir = std::env::temp_dir().join(format!("tools-nurbs-vtu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for tool in load(&scenes().join("square-cup-tools.toml")).unwrap() {
        let t = tessellate(&tool);
        let path = dir.join(format!("{}.vtu", tool.name()));
        write_vtu(&path, &t).unwrap();
        let vtk = vtkio::Vtk::import(&path).unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let piece = pieces[0].load_piece_data(None).unwrap();
        assert_eq!(piece.num_points(), t.points.len());
        assert_eq!(piece.cells.types.len(), t.cells.len());
        let names: Vec<String> = piece
            .data
            .point
            .iter()
            .map(|a| match a {
                vtkio::model::Attribute::DataArray(d) => d.name.clone(),
                vtkio::model::Attribute::Field { name, .. } => name.clone(),
            })
            .collect();
        assert!(
            names.contains(&"normal".to_string()) && names.contains(&"k1".to_string()),
            "{names:?}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The S-rail apron prolongs the die face and the holder flat beyond the
/// swept flange: a point over the blank's corner (93 mm from the centre line
/// of straight 1, past the 70 mm flange) projects straight onto the plane,
/// and the channel is unchanged; an apron with no room beside the channel
/// is refused naming `apron`.
#[test]
fn s_rail_apron_covers_the_overhang_and_leaves_the_channel() {
    let spec = |apron: f64, flange: f64| {
        format!(
            "[tools.die]\nkind = \"s-rail-die\"\norigin = [0.0, 0.0, 1.0]\napron = {apron}\nflange_width = {flange}\n\
             [tools.holder]\nkind = \"s-rail-blankholder\"\nfacing = \"up\"\napron = {apron}\nflange_width = {flange}\n"
        )
    };
    let tools = parse(&spec(10.0, 70.0), Path::new(".")).unwrap();
    let (die, holder) = (&tools[0], &tools[1]);
    for (x, y) in [(0.0, 93.0), (290.0, -46.0), (190.0, -40.0), (60.0, 79.0)] {
        let p = holder.project(&Vec3::new(x, y, 0.5), None).unwrap();
        assert!(
            (p.distance - 0.5).abs() < 1e-12 && (p.normal.z - 1.0).abs() < 1e-14,
            "holder at ({x}, {y}): {p:?}"
        );
        let p = die.project(&Vec3::new(x, y, 0.5), None).unwrap();
        assert!(
            (p.distance - 0.5).abs() < 1e-12 && (p.normal.z + 1.0).abs() < 1e-14,
            "die at ({x}, {y}): {p:?}"
        );
    }
    // Over the punch gap of straight 3 (centre line y = 46.44) the holder
    // still has its inner edge at 17 mm: a point 16 mm from the centre line,
    // level with the face, lies beyond it (closest point on the edge).
    let p = holder
        .project(&Vec3::new(250.0, 46.436 + 16.0, 0.0), None)
        .unwrap();
    assert!((p.distance.abs() - 1.0).abs() < 1e-2, "{p:?}");
    let e = parse(&spec(10.0, 60.0), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("apron"), "{e}");
}

/// An export into a directory that does not exist is a typed error naming
/// the file, for both formats.
#[test]
fn export_into_a_missing_directory_names_the_file() {
    let text = "[tools.punch]\nkind = \"punch\"\nmodel = \"full\"\n";
    let punch = parse(text, &std::env::temp_dir()).unwrap().remove(0);
    let t = tessellate(&punch);
    let missing = std::env::temp_dir().join("tools-nurbs-no-such-dir/sub");
    for (e, file) in [
        (write_vtu(&missing.join("p.vtu"), &t).unwrap_err(), "p.vtu"),
        (
            write_obj(&missing.join("p.obj"), &t, "punch").unwrap_err(),
            "p.obj",
        ),
    ] {
        assert!(matches!(e, tools_nurbs::NurbsError::Write { .. }), "{e:?}");
        let text = e.to_string();
        assert!(
            text.contains(file) && text.contains("cannot write"),
            "{text}"
        );
    }
}
