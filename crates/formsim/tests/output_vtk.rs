//! Round trips of the run outputs: VTU frames read back with vtkio, the PVD
//! collection, rejection of NaN, and the element colour map PNG.

use formsim::output::OutputError;
use formsim::output::field_plots::element_map_png;
use formsim::output::vtk::{BlankFrame, FieldData, write_pvd, write_vtu};
use vtkio::model::{Attribute, CellType, DataSet, VertexNumbers, Vtk};

/// Structured `nx × ny` mesh of `size × size` mm quads in the z = 0 plane.
fn grid(nx: u32, ny: u32, size: f64) -> (Vec<[u32; 4]>, Vec<[f64; 3]>) {
    let mut x = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            x.push([f64::from(i) * size, f64::from(j) * size, 0.0]);
        }
    }
    let node = |i: u32, j: u32| j * (nx + 1) + i;
    let mut quads = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            quads.push([
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            ]);
        }
    }
    (quads, x)
}

/// The f64 values of a named point or cell attribute.
fn values(attrs: &[Attribute], name: &str) -> (usize, Vec<f64>) {
    let a = attrs
        .iter()
        .find(|a| a.name() == name)
        .unwrap_or_else(|| panic!("attribute {name} missing"));
    match a {
        Attribute::DataArray(d) => (d.num_comp(), d.data.cast_into::<f64>().unwrap()),
        Attribute::Field { .. } => panic!("{name} read back as a legacy field"),
    }
}

#[test]
fn vtu_frame_round_trips_through_vtkio() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frames/blank_0001.vtu");
    let (quads, x0) = grid(2, 2, 10.0);
    // A punch-like dip: node displacement depends on position so a swapped
    // or shifted array would not read back equal.
    let disp: Vec<[f64; 3]> = x0
        .iter()
        .map(|p| [0.01 * p[0], -0.02 * p[1], -0.1 * (p[0] + 2.0 * p[1])])
        .collect();
    let x: Vec<[f64; 3]> = x0
        .iter()
        .zip(&disp)
        .map(|(p, u)| [p[0] + u[0], p[1] + u[1], p[2] + u[2]])
        .collect();
    let thickness: Vec<f64> = (0..x.len()).map(|n| 1.0 - 0.01 * n as f64).collect();
    let velocity: Vec<[f64; 3]> = (0..x.len())
        .map(|n| [n as f64, 0.5, -(n as f64) * 0.25])
        .collect();
    let thinning: Vec<f64> = (0..quads.len()).map(|e| 0.03 * e as f64 - 0.01).collect();
    let traction: Vec<[f64; 3]> = (0..quads.len())
        .map(|e| [1.5 * e as f64, -2.0, 1e-3 * e as f64])
        .collect();
    let point_fields = [
        ("thickness", FieldData::Scalar(&thickness)),
        ("velocity", FieldData::Vector(&velocity)),
    ];
    let cell_fields = [
        ("thinning", FieldData::Scalar(&thinning)),
        ("contact_traction", FieldData::Vector(&traction)),
    ];
    let frame = BlankFrame {
        time: 2.5e-3,
        stroke: 12.5,
        quads: &quads,
        x: &x,
        displacement: &disp,
        point_fields: &point_fields,
        cell_fields: &cell_fields,
    };
    write_vtu(&path, &frame).unwrap();

    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("Name=\"TimeValue\""), "{text}");
    assert!(text.contains("Name=\"stroke\""), "{text}");

    let vtk = Vtk::import(&path).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid: {:?}", vtk.data);
    };
    assert_eq!(pieces.len(), 1);
    let piece = pieces[0].load_piece_data(None).unwrap();
    // Counts: a 2×2 grid has 9 nodes and 4 quads (VTK type 9).
    assert_eq!(piece.num_points(), 9);
    assert_eq!(piece.cells.types, vec![CellType::Quad; 4]);
    // Base64 binary f64 must round-trip exactly.
    let pts = piece.points.cast_into::<f64>().unwrap();
    assert_eq!(pts, x.as_flattened());
    match &piece.cells.cell_verts {
        VertexNumbers::XML {
            connectivity,
            offsets,
        } => {
            let want: Vec<u64> = quads.as_flattened().iter().map(|&n| n.into()).collect();
            assert_eq!(connectivity, &want);
            assert_eq!(offsets, &vec![4, 8, 12, 16]);
        }
        other => panic!("legacy cells read back: {other:?}"),
    }

    let point = &piece.data.point;
    let cell = &piece.data.cell;
    let names = |a: &[Attribute]| a.iter().map(|a| a.name().to_string()).collect::<Vec<_>>();
    assert_eq!(names(point), ["displacement", "thickness", "velocity"]);
    assert_eq!(names(cell), ["thinning", "contact_traction"]);
    assert_eq!(
        values(point, "displacement"),
        (3, disp.as_flattened().to_vec())
    );
    assert_eq!(values(point, "thickness"), (1, thickness.clone()));
    assert_eq!(
        values(point, "velocity"),
        (3, velocity.as_flattened().to_vec())
    );
    assert_eq!(values(cell, "thinning"), (1, thinning.clone()));
    assert_eq!(
        values(cell, "contact_traction"),
        (3, traction.as_flattened().to_vec())
    );
}

#[test]
fn pvd_lists_every_frame_with_time_and_relative_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("blank.pvd");
    let entries: Vec<(f64, String)> = (0..3)
        .map(|i| (1e-3 * f64::from(i), format!("frames/blank_{i:04}.vtu")))
        .collect();
    write_pvd(&path, &entries).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("<?xml"), "{text}");
    assert!(text.contains("<VTKFile type=\"Collection\""), "{text}");
    assert_eq!(text.matches("<Collection>").count(), 1);
    assert_eq!(text.matches("</Collection>").count(), 1);
    assert!(text.trim_end().ends_with("</VTKFile>"), "{text}");
    let datasets: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("<DataSet"))
        .collect();
    assert_eq!(datasets.len(), 3, "{text}");
    for (line, (t, file)) in datasets.iter().zip(&entries) {
        assert!(line.ends_with("/>"), "{line}");
        let attr = |key: &str| {
            let start = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
            let len = line[start..].find('"').unwrap();
            line[start..start + len].to_string()
        };
        assert_eq!(attr("timestep").parse::<f64>().unwrap(), *t);
        assert_eq!(&attr("file"), file);
    }
}

#[test]
fn pvd_escapes_markup_in_file_names() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("blank.pvd");
    write_pvd(&path, &[(0.0, "R&D <1>/\"a\".vtu".into())]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("file=\"R&amp;D &lt;1&gt;/&quot;a&quot;.vtu\""),
        "{text}"
    );
}

#[test]
fn pvd_rejects_nan_time_and_absolute_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("blank.pvd");
    let err = write_pvd(&path, &[(f64::NAN, "a.vtu".into())]).unwrap_err();
    assert!(err.to_string().contains("NaN"), "{err}");
    let abs = dir.path().join("a.vtu").display().to_string();
    let err = write_pvd(&path, &[(0.0, abs)]).unwrap_err();
    assert!(err.to_string().contains("relative"), "{err}");
    assert!(!path.exists());
}

fn frame_with<'a>(
    quads: &'a [[u32; 4]],
    x: &'a [[f64; 3]],
    point_fields: &'a [(&'a str, FieldData<'a>)],
    cell_fields: &'a [(&'a str, FieldData<'a>)],
) -> BlankFrame<'a> {
    BlankFrame {
        time: 0.0,
        stroke: 0.0,
        quads,
        x,
        displacement: x,
        point_fields,
        cell_fields,
    }
}

#[test]
fn vtu_nan_in_cell_field_is_an_error_naming_field_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtu");
    let (quads, x) = grid(2, 2, 1.0);
    let thinning = [0.0, 0.1, f64::NAN, 0.2];
    let cells = [("thinning", FieldData::Scalar(&thinning))];
    let err = write_vtu(&path, &frame_with(&quads, &x, &[], &cells)).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, OutputError::Invalid { .. }), "{msg}");
    assert!(
        msg.contains("'thinning'") && msg.contains("element 2"),
        "{msg}"
    );
    assert!(msg.contains("NaN") && msg.contains("bad.vtu"), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
    assert!(!path.exists(), "nothing may be written on error");
}

#[test]
fn vtu_infinite_point_vector_is_an_error_naming_node_and_component() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtu");
    let (quads, x) = grid(2, 2, 1.0);
    let mut v = vec![[0.0; 3]; x.len()];
    v[5][2] = f64::INFINITY;
    let points = [("velocity", FieldData::Vector(&v))];
    let msg = write_vtu(&path, &frame_with(&quads, &x, &points, &[]))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("'velocity'") && msg.contains("node 5"),
        "{msg}"
    );
    assert!(msg.contains("component z") && msg.contains("inf"), "{msg}");
}

#[test]
fn vtu_wrong_length_and_bad_node_number_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtu");
    let (quads, x) = grid(2, 2, 1.0);
    let short = [1.0; 8];
    let points = [("thickness", FieldData::Scalar(&short))];
    let msg = write_vtu(&path, &frame_with(&quads, &x, &points, &[]))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("'thickness' has 8 values") && msg.contains("9 nodes"),
        "{msg}"
    );

    let cells4 = [1.0; 4];
    let dup = [
        ("thinning", FieldData::Scalar(&cells4)),
        ("thinning", FieldData::Scalar(&cells4)),
    ];
    let msg = write_vtu(&path, &frame_with(&quads, &x, &[], &dup))
        .unwrap_err()
        .to_string();
    assert!(msg.contains("'thinning' is given twice"), "{msg}");

    let mut bad = quads.clone();
    bad[3][1] = 99;
    let msg = write_vtu(&path, &frame_with(&bad, &x, &[], &[]))
        .unwrap_err()
        .to_string();
    assert!(msg.contains("element 3 refers to node 99"), "{msg}");
    assert!(!path.exists());
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |s: &[u8]| u32::from_be_bytes([s[0], s[1], s[2], s[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

fn map_mesh(n: u32) -> (Vec<[u32; 4]>, Vec<[f64; 2]>, Vec<f64>) {
    let (quads, x) = grid(n, n, 5.0);
    let xy: Vec<[f64; 2]> = x.iter().map(|p| [p[0], p[1]]).collect();
    // Thinning-like field: largest at the mesh centre.
    let c = 2.5 * f64::from(n);
    let values = quads
        .iter()
        .map(|q| {
            let [x, y] = xy[q[0] as usize];
            0.2 * (-((x - c).powi(2) + (y - c).powi(2)) / 200.0).exp()
        })
        .collect();
    (quads, xy, values)
}

#[test]
fn element_map_png_of_10x10_mesh_is_a_valid_image() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plots/thinning.png");
    let (quads, xy, values) = map_mesh(10);
    let t0 = std::time::Instant::now();
    element_map_png(&path, "Thinning", "thinning (-)", &quads, &xy, &values).unwrap();
    let elapsed = t0.elapsed();
    let bytes = std::fs::read(&path).unwrap();
    // 800×700 px with text and 100 coloured quads compresses to far more than 1 kB.
    assert!(bytes.len() > 1024, "PNG only {} bytes", bytes.len());
    assert_eq!(png_size(&bytes), (800, 700));
    // Budget: < 1 s (release build).
    eprintln!("element_map_png 10x10: {elapsed:?}, {} bytes", bytes.len());
}

#[test]
fn element_map_png_rejects_nan_and_length_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.png");
    let (quads, xy, mut values) = map_mesh(3);
    values[4] = f64::NAN;
    let msg = element_map_png(&path, "t", "c", &quads, &xy, &values)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("element 4") && msg.contains("NaN"), "{msg}");
    let msg = element_map_png(&path, "t", "c", &quads, &xy, &values[..5])
        .unwrap_err()
        .to_string();
    assert!(msg.contains("5 element values for 9 elements"), "{msg}");
    assert!(!path.exists());
}
