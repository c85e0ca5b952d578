//! VTK XML UnstructuredGrid (`.vtu`, ASCII) and ParaView collection
//! (`.pvd`) text: what ParaView, VTK and meshio read.

use std::fmt::Write as _;

/// VTK cell type of a two-point line.
pub const VTK_LINE: u8 = 3;
/// VTK cell type of a four-point quadrilateral.
pub const VTK_QUAD: u8 = 9;
/// VTK cell type of an eight-point hexahedron.
pub const VTK_HEXAHEDRON: u8 = 12;

/// One array of field data (the whole dataset) or point data.
pub struct Array<'a> {
    /// The array's name.
    pub name: &'a str,
    /// Components per tuple.
    pub components: usize,
    /// The values, tuple after tuple.
    pub values: Values,
}

/// The values of an [`Array`].
pub enum Values {
    /// `Float64`.
    Float(Vec<f64>),
    /// `Int64`.
    Int(Vec<i64>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Float(v) => v.len(),
            Values::Int(v) => v.len(),
        }
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace("--", "- -")
}

fn data_array(out: &mut String, a: &Array, tuples: bool) {
    let (ty, values): (&str, Vec<String>) = match &a.values {
        Values::Float(v) => ("Float64", v.iter().map(|x| format!("{x:e}")).collect()),
        Values::Int(v) => ("Int64", v.iter().map(i64::to_string).collect()),
    };
    let n = a.values.len() / a.components.max(1);
    let count = if tuples {
        format!(" NumberOfTuples=\"{n}\"")
    } else {
        String::new()
    };
    let _ = writeln!(
        out,
        "<DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{}\"{count} format=\"ascii\">",
        escape(a.name),
        a.components
    );
    for t in values.chunks(a.components.max(1)) {
        let _ = writeln!(out, "{}", t.join(" "));
    }
    out.push_str("</DataArray>\n");
}

/// An UnstructuredGrid file of one cell type: `comment` (an XML comment
/// before the dataset), field data, points, the cells (point indices of
/// each) and point data (one tuple per point).
pub fn unstructured_grid(
    comment: &str,
    field_data: &[Array],
    points: &[[f64; 3]],
    cells: &[Vec<usize>],
    cell_type: u8,
    point_data: &[Array],
) -> String {
    let mut t = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(t, "<!-- {} -->", escape(comment));
    t.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<FieldData>\n",
    );
    for a in field_data {
        data_array(&mut t, a, true);
    }
    let _ = writeln!(
        t,
        "</FieldData>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        cells.len()
    );
    t.push_str("<PointData>\n");
    for a in point_data {
        debug_assert_eq!(a.values.len(), a.components * points.len(), "{}", a.name);
        data_array(&mut t, a, false);
    }
    t.push_str("</PointData>\n<Points>\n");
    data_array(
        &mut t,
        &Array {
            name: "Points",
            components: 3,
            values: Values::Float(points.iter().flatten().copied().collect()),
        },
        false,
    );
    t.push_str("</Points>\n<Cells>\n");
    let mut offset = 0;
    let offsets: Vec<i64> = cells
        .iter()
        .map(|c| {
            offset += c.len() as i64;
            offset
        })
        .collect();
    for (name, values) in [
        (
            "connectivity",
            cells.iter().flatten().map(|&i| i as i64).collect(),
        ),
        ("offsets", offsets),
        ("types", vec![i64::from(cell_type); cells.len()]),
    ] {
        data_array(
            &mut t,
            &Array {
                name,
                components: 1,
                values: Values::Int(values),
            },
            false,
        );
    }
    t.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    t
}

/// One dataset of a collection: its time step, part and file (relative to the `.pvd`).
#[derive(Clone, Debug, PartialEq)]
pub struct DataSet {
    /// The `timestep` attribute.
    pub timestep: f64,
    /// The `part` attribute (the body or the interface).
    pub part: usize,
    /// The file name.
    pub file: String,
}

/// A ParaView data collection listing `datasets`.
pub fn collection(datasets: &[DataSet]) -> String {
    let mut t = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for d in datasets {
        let _ = writeln!(
            t,
            "<DataSet timestep=\"{:e}\" group=\"\" part=\"{}\" file=\"{}\"/>",
            d.timestep,
            d.part,
            escape(&d.file)
        );
    }
    t.push_str("</Collection>\n</VTKFile>\n");
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unstructured_grid_counts_points_cells_and_offsets() {
        let t = unstructured_grid(
            "a -- b",
            &[Array {
                name: "applied_pressure",
                components: 1,
                values: Values::Float(vec![1.0e3]),
            }],
            &[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            &[vec![0, 1], vec![1, 2]],
            VTK_LINE,
            &[Array {
                name: "p",
                components: 1,
                values: Values::Float(vec![1.0, 2.0, 3.0]),
            }],
        );
        assert!(t.contains("<!-- a - - b -->"), "{t}");
        assert!(t.contains("NumberOfPoints=\"3\" NumberOfCells=\"2\""));
        assert!(t.contains("NumberOfTuples=\"1\" format=\"ascii\">\n1e3\n"));
        assert!(t.contains("Name=\"offsets\" NumberOfComponents=\"1\" format=\"ascii\">\n2\n4\n"));
        assert!(t.contains("Name=\"types\" NumberOfComponents=\"1\" format=\"ascii\">\n3\n3\n"));
    }

    #[test]
    fn collection_lists_every_dataset() {
        let t = collection(&[
            DataSet {
                timestep: 1.0e3,
                part: 0,
                file: "p000_lower.vtu".into(),
            },
            DataSet {
                timestep: 1.0e4,
                part: 2,
                file: "p001_interface.vtu".into(),
            },
        ]);
        assert!(
            t.contains("<DataSet timestep=\"1e3\" group=\"\" part=\"0\" file=\"p000_lower.vtu\"/>")
        );
        assert!(t.contains("timestep=\"1e4\" group=\"\" part=\"2\" file=\"p001_interface.vtu\""));
    }
}
