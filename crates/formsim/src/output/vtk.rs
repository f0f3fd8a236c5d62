//! ParaView time series of the deforming blank: one VTU file (XML unstructured
//! grid of quadrilateral shells) per output frame and a PVD collection that
//! lists the frames with their times.
//!
//! Every frame carries the current node coordinates (mm), the node
//! displacement (mm, point vector `displacement`) and any number of named
//! point (per node) or cell (per element) fields. Each VTU also stores its own
//! time and stroke as field data (`TimeValue` in s, `stroke` in mm), so a lone
//! file still says where in the press stroke it was taken.
//!
//! Data are checked before anything is written: lengths must match the mesh,
//! node numbers must exist and every value must be finite. A NaN or an
//! infinity is reported with the field name and the node or element index; it
//! is never written.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

use super::error::{OutputError, create_parent_dir};

/// Name of the built-in point vector holding the node displacement (mm).
pub const DISPLACEMENT_FIELD: &str = "displacement";

/// One frame of the blank: mesh, state and result fields at one instant.
#[derive(Clone, Copy, Debug)]
pub struct BlankFrame<'a> {
    /// Simulation time (s).
    pub time: f64,
    /// Punch stroke (mm).
    pub stroke: f64,
    /// Quadrilateral shells, four zero-based node numbers each,
    /// counter-clockwise seen from the shell normal.
    pub quads: &'a [[u32; 4]],
    /// Current node coordinates (mm).
    pub x: &'a [[f64; 3]],
    /// Node displacement from the initial blank (mm); same length as `x`.
    pub displacement: &'a [[f64; 3]],
    /// Named fields with one value per node.
    pub point_fields: &'a [(&'a str, FieldData<'a>)],
    /// Named fields with one value per element.
    pub cell_fields: &'a [(&'a str, FieldData<'a>)],
}

/// Values of one named field: a scalar or a 3-vector per node or element.
#[derive(Clone, Copy, Debug)]
pub enum FieldData<'a> {
    /// One number per entity.
    Scalar(&'a [f64]),
    /// Three components per entity (x, y, z).
    Vector(&'a [[f64; 3]]),
}

impl FieldData<'_> {
    /// Number of entities (nodes or elements) covered.
    pub fn len(&self) -> usize {
        match self {
            FieldData::Scalar(v) => v.len(),
            FieldData::Vector(v) => v.len(),
        }
    }

    /// True when the field holds no entity.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Components per entity: 1 for scalars, 3 for vectors.
    pub fn num_components(&self) -> usize {
        match self {
            FieldData::Scalar(_) => 1,
            FieldData::Vector(_) => 3,
        }
    }

    /// The values, component-interleaved (`x0 y0 z0 x1 …` for vectors).
    fn flat(&self) -> &[f64] {
        match self {
            FieldData::Scalar(v) => v,
            FieldData::Vector(v) => v.as_flattened(),
        }
    }
}

/// Where a field lives, for messages.
#[derive(Clone, Copy)]
enum Location {
    Point,
    Cell,
}

impl Location {
    fn field_kind(self) -> &'static str {
        match self {
            Location::Point => "point field",
            Location::Cell => "cell field",
        }
    }
    fn entity(self) -> &'static str {
        match self {
            Location::Point => "node",
            Location::Cell => "element",
        }
    }
    fn entities(self) -> &'static str {
        match self {
            Location::Point => "nodes",
            Location::Cell => "elements",
        }
    }
}

/// First non-finite entry of component-interleaved `values` as
/// `(entity index, component, value)`.
fn first_non_finite(values: &[f64], num_comp: usize) -> Option<(usize, usize, f64)> {
    values
        .iter()
        .position(|v| !v.is_finite())
        .map(|i| (i / num_comp, i % num_comp, values[i]))
}

/// Check that a field is finite; the error names the field, the entity and the value.
fn check_finite(
    path: &Path,
    loc: Location,
    name: &str,
    unit: &str,
    data: &FieldData,
) -> Result<(), OutputError> {
    match first_non_finite(data.flat(), data.num_components()) {
        None => Ok(()),
        Some((i, c, v)) => {
            let comp = match data {
                FieldData::Scalar(_) => String::new(),
                FieldData::Vector(_) => format!(" component {}", ["x", "y", "z"][c]),
            };
            Err(OutputError::invalid(
                path,
                format!(
                    "{} '{name}' is {v}{unit} at {} {i}{comp}; VTK output needs finite values",
                    loc.field_kind(),
                    loc.entity()
                ),
            ))
        }
    }
}

/// Check names, lengths and finiteness of one group of fields.
fn check_fields(
    path: &Path,
    loc: Location,
    fields: &[(&str, FieldData)],
    expected_len: usize,
    reserved: &[&str],
) -> Result<(), OutputError> {
    let mut seen: HashSet<&str> = reserved.iter().copied().collect();
    for (name, data) in fields {
        if name.trim().is_empty() {
            return Err(OutputError::invalid(
                path,
                format!("{} with an empty name", loc.field_kind()),
            ));
        }
        if !seen.insert(name) {
            return Err(OutputError::invalid(
                path,
                format!(
                    "{} '{name}' is given twice (or clashes with a built-in field)",
                    loc.field_kind()
                ),
            ));
        }
        if data.len() != expected_len {
            return Err(OutputError::invalid(
                path,
                format!(
                    "{} '{name}' has {} values but the blank has {expected_len} {}",
                    loc.field_kind(),
                    data.len(),
                    loc.entities()
                ),
            ));
        }
        check_finite(path, loc, name, "", data)?;
    }
    Ok(())
}

/// Check the whole frame before anything is written.
fn validate(path: &Path, frame: &BlankFrame) -> Result<(), OutputError> {
    for (what, v, unit) in [("time", frame.time, " s"), ("stroke", frame.stroke, " mm")] {
        if !v.is_finite() {
            return Err(OutputError::invalid(
                path,
                format!("frame {what} is {v}{unit}; VTK output needs finite values"),
            ));
        }
    }
    let nodes = frame.x.len();
    if frame.displacement.len() != nodes {
        return Err(OutputError::invalid(
            path,
            format!(
                "point field '{DISPLACEMENT_FIELD}' has {} values but the blank has {nodes} nodes",
                frame.displacement.len()
            ),
        ));
    }
    check_finite(
        path,
        Location::Point,
        "coordinates",
        " mm",
        &FieldData::Vector(frame.x),
    )?;
    check_finite(
        path,
        Location::Point,
        DISPLACEMENT_FIELD,
        " mm",
        &FieldData::Vector(frame.displacement),
    )?;
    for (e, quad) in frame.quads.iter().enumerate() {
        if let Some(&n) = quad.iter().find(|&&n| n as usize >= nodes) {
            return Err(OutputError::invalid(
                path,
                format!("element {e} refers to node {n} but the blank has {nodes} nodes"),
            ));
        }
    }
    check_fields(
        path,
        Location::Point,
        frame.point_fields,
        nodes,
        &[DISPLACEMENT_FIELD],
    )?;
    check_fields(
        path,
        Location::Cell,
        frame.cell_fields,
        frame.quads.len(),
        &[],
    )?;
    Ok(())
}

/// A vtkio attribute for one named field.
fn attribute(name: &str, data: &FieldData) -> Attribute {
    let elem = match data {
        FieldData::Scalar(_) => ElementType::Scalars {
            num_comp: 1,
            lookup_table: None,
        },
        FieldData::Vector(_) => ElementType::Vectors,
    };
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem,
        data: data.flat().to_vec().into(),
    })
}

/// XML `<FieldData>` block with the frame time and stroke (ParaView reads
/// `TimeValue` as the time of a single file).
fn field_data_xml(frame: &BlankFrame) -> String {
    let mut s = String::from("<FieldData>");
    for (name, v) in [("TimeValue", frame.time), ("stroke", frame.stroke)] {
        // `{:e}` of a finite f64 is the shortest exact round-trip representation.
        let _ = write!(
            s,
            "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfTuples=\"1\" format=\"ascii\">{v:e}</DataArray>"
        );
    }
    s.push_str("</FieldData>");
    s
}

/// Write one frame of the blank as a VTK XML unstructured grid (`.vtu`) of
/// quadrilateral cells (VTK type 9), with `displacement` and the given point
/// and cell fields, data inline in base64 binary. Missing parent directories
/// are created.
///
/// # Errors
/// [`OutputError::Invalid`] when a field length differs from the node or
/// element count, a field name is empty or repeated (`displacement` is
/// reserved), an element refers to a missing node, or any value (coordinates
/// included) is NaN or infinite — the message names the field and the index.
/// [`OutputError::Vtk`] if the library cannot encode the data and
/// [`OutputError::Io`] if the file cannot be written. Nothing is written on
/// error.
pub fn write_vtu(path: &Path, frame: &BlankFrame) -> Result<(), OutputError> {
    validate(path, frame)?;

    let mut point = Vec::with_capacity(1 + frame.point_fields.len());
    point.push(attribute(
        DISPLACEMENT_FIELD,
        &FieldData::Vector(frame.displacement),
    ));
    point.extend(frame.point_fields.iter().map(|(n, d)| attribute(n, d)));
    let cell = frame
        .cell_fields
        .iter()
        .map(|(n, d)| attribute(n, d))
        .collect();

    let connectivity = frame
        .quads
        .iter()
        .flat_map(|q| q.iter().map(|&n| u64::from(n)))
        .collect();
    let offsets = (1..=frame.quads.len() as u64).map(|e| 4 * e).collect();
    let piece = UnstructuredGridPiece {
        points: frame.x.as_flattened().to_vec().into(),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets,
            },
            types: vec![CellType::Quad; frame.quads.len()],
        },
        data: Attributes { point, cell },
    };
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::native(),
        data: DataSet::inline(piece),
        file_path: None,
    };

    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|e| OutputError::Vtk {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let bytes = insert_field_data(path, bytes, &field_data_xml(frame))?;

    create_parent_dir(path)?;
    std::fs::write(path, bytes).map_err(|e| OutputError::io(path, e))
}

/// Insert `block` right after the `<UnstructuredGrid>` opening tag.
fn insert_field_data(path: &Path, mut xml: Vec<u8>, block: &str) -> Result<Vec<u8>, OutputError> {
    const TAG: &[u8] = b"<UnstructuredGrid>";
    let at = xml
        .windows(TAG.len())
        .position(|w| w == TAG)
        .ok_or_else(|| OutputError::Vtk {
            path: path.to_path_buf(),
            message: "encoded file has no <UnstructuredGrid> element".to_string(),
        })?;
    let end = at + TAG.len();
    xml.splice(end..end, block.bytes());
    Ok(xml)
}

/// Escape a string for use inside a double-quoted XML attribute.
fn xml_attr(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(ch),
        }
    }
    out
}

/// Write a ParaView collection (`.pvd`) listing frames as
/// `(time in s, VTU file name)`, one `<DataSet timestep=".." file=".."/>` each.
/// File names are written as given and must be relative to the directory of
/// the `.pvd` (ParaView resolves them from there); use `/` as separator.
/// Missing parent directories are created.
///
/// # Errors
/// [`OutputError::Invalid`] for a non-finite time, an empty or absolute file
/// name, or times that decrease; [`OutputError::Io`] if the file cannot be
/// written.
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> Result<(), OutputError> {
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    let mut previous = f64::NEG_INFINITY;
    for (i, (time, file)) in entries.iter().enumerate() {
        if !time.is_finite() {
            return Err(OutputError::invalid(
                path,
                format!("entry {i} ('{file}') has time {time} s; times must be finite"),
            ));
        }
        if *time < previous {
            return Err(OutputError::invalid(
                path,
                format!(
                    "entry {i} ('{file}') has time {time:e} s, before the previous entry at {previous:e} s"
                ),
            ));
        }
        previous = *time;
        if file.trim().is_empty() || Path::new(file).is_absolute() {
            return Err(OutputError::invalid(
                path,
                format!(
                    "entry {i} has file name '{file}'; it must be a non-empty path relative to the .pvd"
                ),
            ));
        }
        let _ = writeln!(
            xml,
            "    <DataSet timestep=\"{time:e}\" group=\"\" part=\"0\" file=\"{}\"/>",
            xml_attr(file)
        );
    }
    xml.push_str("  </Collection>\n</VTKFile>\n");
    create_parent_dir(path)?;
    std::fs::write(path, xml).map_err(|e| OutputError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xml_attr_escapes_markup_characters() {
        assert_eq!(xml_attr(r#"a&b<c>"d'"#), "a&amp;b&lt;c&gt;&quot;d&apos;");
    }

    #[test]
    fn first_non_finite_reports_entity_and_component() {
        let v = [0.0, 1.0, 2.0, 3.0, f64::INFINITY, 5.0];
        assert_eq!(first_non_finite(&v, 3), Some((1, 1, f64::INFINITY)));
        assert_eq!(first_non_finite(&v[..4], 1), None);
    }
}
