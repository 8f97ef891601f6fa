//! Export of a field as a legacy VTK `STRUCTURED_POINTS` file (binary, big-endian), readable by
//! ParaView and VisIt: point data `distance` (f64), `band` (1 = exact near band) and the vector
//! `gradient` (`−∇d/|∇d|`, f32).

use super::DistanceField;

/// The field as the bytes of a legacy binary VTK structured-points file.
pub fn structured_points(field: &DistanceField) -> Vec<u8> {
    let g = field.grid();
    let [nx, ny, nz] = g.dims;
    let n = g.node_count();
    let mut out = Vec::with_capacity(n * 21 + 512);
    let header = format!(
        "# vtk DataFile Version 3.0\nLSW distance field ({:?}, lsw {})\nBINARY\n\
         DATASET STRUCTURED_POINTS\nDIMENSIONS {nx} {ny} {nz}\nORIGIN {:e} {:e} {:e}\n\
         SPACING {:e} {:e} {:e}\nPOINT_DATA {n}\nSCALARS distance double 1\nLOOKUP_TABLE default\n",
        field.signedness(),
        crate::VERSION,
        g.origin.x,
        g.origin.y,
        g.origin.z,
        g.cell,
        g.cell,
        g.cell,
    );
    out.extend_from_slice(header.as_bytes());
    for v in field.values() {
        out.extend_from_slice(&v.to_be_bytes());
    }
    out.extend_from_slice(b"\nSCALARS band unsigned_char 1\nLOOKUP_TABLE default\n");
    out.extend(field.band_mask().iter().map(|&b| b as u8));
    out.extend_from_slice(b"\nVECTORS gradient float\n");
    for g in field.gradients() {
        for c in g {
            out.extend_from_slice(&c.to_be_bytes());
        }
    }
    out.push(b'\n');
    out
}
