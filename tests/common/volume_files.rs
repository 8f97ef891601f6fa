//! Test helpers for the volume readers: analytic volumes (implicit functions sampled on a grid
//! with anisotropic voxels and a rotated + translated affine) and minimal writers for NIfTI-1/2,
//! NRRD, VTI and MetaImage, written from the format specifications independently of the readers.
#![allow(dead_code)]
// Header writers address fields by byte offset: index loops mirror the format tables, and the
// explicit casts name each field's on-disk type even where it is already that type.
#![allow(clippy::needless_range_loop, clippy::unnecessary_cast)]

use flate2::write::{GzEncoder, ZlibEncoder};
use flate2::Compression;
use lsw::DVec3;
use std::io::Write;

/// An index → world map: `world = origin + Σ_k index_k · cols[k]`.
#[derive(Clone, Copy, Debug)]
pub struct Affine {
    /// Columns: world direction × voxel size of each index axis.
    pub cols: [DVec3; 3],
    /// World position of voxel (0, 0, 0).
    pub origin: DVec3,
}

impl Affine {
    /// World position of an index.
    pub fn world(&self, i: DVec3) -> DVec3 {
        self.origin + self.cols[0] * i.x + self.cols[1] * i.y + self.cols[2] * i.z
    }

    /// Voxel sizes.
    pub fn spacing(&self) -> [f64; 3] {
        self.cols.map(|c| c.length())
    }

    /// Unit directions (rotation columns).
    pub fn directions(&self) -> [DVec3; 3] {
        self.cols.map(|c| c.normalize())
    }
}

/// Rotation by `angle` about `axis` (Rodrigues), as columns.
pub fn rotation(axis: DVec3, angle: f64) -> [DVec3; 3] {
    let k = axis.normalize();
    let (s, c) = lsw::fmath::sin_cos(angle);
    [DVec3::X, DVec3::Y, DVec3::Z].map(|v| v * c + k.cross(v) * s + k * k.dot(v) * (1.0 - c))
}

/// The test affine: voxels 1.5 × 1.0 × 2.0 mm, rotated 25° about (1, 2, 3), origin (−20, 7, 31).
pub fn test_affine() -> Affine {
    let r = rotation(DVec3::new(1.0, 2.0, 3.0), 25f64.to_radians());
    let s = [1.5, 1.0, 2.0];
    Affine {
        cols: [r[0] * s[0], r[1] * s[1], r[2] * s[2]],
        origin: DVec3::new(-20.0, 7.0, 31.0),
    }
}

/// A volume: dims, values (x fastest), affine.
#[derive(Clone, Debug)]
pub struct Vol {
    pub dims: [usize; 3],
    pub values: Vec<f32>,
    pub affine: Affine,
}

/// Samples `f(world)` on the grid.
pub fn sample(dims: [usize; 3], affine: Affine, f: impl Fn(DVec3) -> f64) -> Vol {
    let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                values.push(f(affine.world(DVec3::new(x as f64, y as f64, z as f64))) as f32);
            }
        }
    }
    Vol {
        dims,
        values,
        affine,
    }
}

/// The centre of the test shapes: the world position of the middle of a `dims` grid.
pub fn centre(dims: [usize; 3], a: &Affine) -> DVec3 {
    a.world(DVec3::new(
        (dims[0] - 1) as f64 / 2.0,
        (dims[1] - 1) as f64 / 2.0,
        (dims[2] - 1) as f64 / 2.0,
    ))
}

/// A ball of radius `r` about the grid's centre: `100·(r − |x − c|)` (positive inside, so the
/// surface is the iso-value 0 with "bright inside").
pub fn sphere_volume(dims: [usize; 3], r: f64) -> Vol {
    let a = test_affine();
    let c = centre(dims, &a);
    sample(dims, a, |p| 100.0 * (r - (p - c).length()))
}

/// A solid torus (radii `big`, `small`) about the grid's centre, its axis along `axis`.
pub fn torus_volume(dims: [usize; 3], big: f64, small: f64, axis: DVec3) -> Vol {
    let a = test_affine();
    let c = centre(dims, &a);
    let n = axis.normalize();
    sample(dims, a, move |p| {
        let q = p - c;
        let h = q.dot(n);
        let rho = (q - n * h).length();
        small - ((rho - big).powi(2) + h * h).sqrt()
    })
}

/// Distance of `p` from the torus surface.
pub fn torus_distance(p: DVec3, c: DVec3, big: f64, small: f64, axis: DVec3) -> f64 {
    let n = axis.normalize();
    let q = p - c;
    let h = q.dot(n);
    let rho = (q - n * h).length();
    (((rho - big).powi(2) + h * h).sqrt() - small).abs()
}

pub fn gzip(data: &[u8]) -> Vec<u8> {
    let mut e = GzEncoder::new(Vec::new(), Compression::default());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

pub fn zlib(data: &[u8]) -> Vec<u8> {
    let mut e = ZlibEncoder::new(Vec::new(), Compression::default());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

/// Sample storage types used by the writers (NIfTI datatype code, bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ty {
    U8,
    I8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    pub fn nifti_code(self) -> i16 {
        match self {
            Ty::U8 => 2,
            Ty::I16 => 4,
            Ty::I32 => 8,
            Ty::F32 => 16,
            Ty::F64 => 64,
            Ty::I8 => 256,
            Ty::U16 => 512,
            Ty::U32 => 768,
        }
    }
    pub fn size(self) -> usize {
        match self {
            Ty::U8 | Ty::I8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

/// Encodes raw values (already in the type's range) in the given byte order.
pub fn encode(values: &[f64], ty: Ty, big: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(values.len() * ty.size());
    macro_rules! put {
        ($v:expr) => {
            if big {
                out.extend_from_slice(&$v.to_be_bytes())
            } else {
                out.extend_from_slice(&$v.to_le_bytes())
            }
        };
    }
    for &v in values {
        match ty {
            Ty::U8 => out.push(v as u8),
            Ty::I8 => out.push(v as i8 as u8),
            Ty::I16 => put!(v as i16),
            Ty::U16 => put!(v as u16),
            Ty::I32 => put!(v as i32),
            Ty::U32 => put!(v as u32),
            Ty::F32 => put!(v as f32),
            Ty::F64 => put!(v),
        }
    }
    out
}

/// How a NIfTI file stores its geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NiftiGeom {
    /// sform (code 1) and a dummy qform (code 0).
    Sform,
    /// qform only (code 1; sform code 0).
    Qform,
}

/// NIfTI writer options.
#[derive(Clone, Copy, Debug)]
pub struct NiftiOpts {
    pub version: u8,
    pub big: bool,
    pub ty: Ty,
    pub slope: f64,
    pub inter: f64,
    pub geom: NiftiGeom,
    /// Extra volumes (4-D): frame k holds the values + 1000·k (raw).
    pub frames: usize,
}

impl Default for NiftiOpts {
    fn default() -> Self {
        Self {
            version: 1,
            big: false,
            ty: Ty::F32,
            slope: 0.0,
            inter: 0.0,
            geom: NiftiGeom::Sform,
            frames: 1,
        }
    }
}

/// Quaternion (b, c, d) and qfac of a rotation given by columns (det ±1).
fn quaternion(cols: [DVec3; 3]) -> ([f64; 3], f64) {
    let mut r = cols;
    let det = r[0].dot(r[1].cross(r[2]));
    let qfac = if det < 0.0 { -1.0 } else { 1.0 };
    r[2] *= qfac;
    // Element (row i, col j) = r[j][i].
    let m = |i: usize, j: usize| r[j][i];
    let a = 0.5 * (1.0 + m(0, 0) + m(1, 1) + m(2, 2)).max(0.0).sqrt();
    let (b, c, d) = if a > 0.1 {
        (
            0.25 * (m(2, 1) - m(1, 2)) / a,
            0.25 * (m(0, 2) - m(2, 0)) / a,
            0.25 * (m(1, 0) - m(0, 1)) / a,
        )
    } else {
        panic!("test rotations stay away from 180°");
    };
    ([b, c, d], qfac)
}

/// Writes a single-file NIfTI (`.nii`): raw values are `(v − inter)/slope` when slope ≠ 0.
pub fn write_nifti(v: &Vol, o: NiftiOpts) -> Vec<u8> {
    let n = v.values.len();
    let mut raw = Vec::with_capacity(n * o.frames);
    for k in 0..o.frames {
        for &x in &v.values {
            let x = x as f64;
            let r = if o.slope != 0.0 {
                ((x - o.inter) / o.slope).round()
            } else {
                x
            };
            raw.push(r + 1000.0 * k as f64);
        }
    }
    let data = encode(&raw, o.ty, o.big);
    let (hsize, off) = if o.version == 1 {
        (348usize, 352usize)
    } else {
        (540, 544)
    };
    let mut h = vec![0u8; off];
    let big = o.big;
    let put = |h: &mut Vec<u8>, at: usize, b: &[u8]| h[at..at + b.len()].copy_from_slice(b);
    macro_rules! w {
        ($at:expr, $v:expr) => {
            if big {
                put(&mut h, $at, &$v.to_be_bytes())
            } else {
                put(&mut h, $at, &$v.to_le_bytes())
            }
        };
    }
    let nd: i64 = if o.frames > 1 { 4 } else { 3 };
    let dim = [
        nd,
        v.dims[0] as i64,
        v.dims[1] as i64,
        v.dims[2] as i64,
        o.frames as i64,
        1,
        1,
        1,
    ];
    let sp = v.affine.spacing();
    let (quat, qfac) = quaternion(v.affine.directions());
    let pixdim = [qfac, sp[0], sp[1], sp[2], 1.0, 0.0, 0.0, 0.0];
    let (qcode, scode) = match o.geom {
        NiftiGeom::Sform => (0, 1),
        NiftiGeom::Qform => (1, 0),
    };
    let srow: [[f64; 4]; 3] = std::array::from_fn(|r| {
        [
            v.affine.cols[0][r],
            v.affine.cols[1][r],
            v.affine.cols[2][r],
            v.affine.origin[r],
        ]
    });
    if o.version == 1 {
        w!(0, 348i32);
        for (i, d) in dim.iter().enumerate() {
            w!(40 + 2 * i, *d as i16);
        }
        w!(70, o.ty.nifti_code());
        w!(72, (o.ty.size() * 8) as i16);
        for (i, p) in pixdim.iter().enumerate() {
            w!(76 + 4 * i, *p as f32);
        }
        w!(108, off as f32);
        w!(112, o.slope as f32);
        w!(116, o.inter as f32);
        w!(252, qcode as i16);
        w!(254, scode as i16);
        for i in 0..3 {
            w!(256 + 4 * i, quat[i] as f32);
            w!(268 + 4 * i, v.affine.origin[i] as f32);
        }
        for r in 0..3 {
            for c in 0..4 {
                w!(280 + 16 * r + 4 * c, srow[r][c] as f32);
            }
        }
        put(&mut h, 344, b"n+1\0");
    } else {
        w!(0, 540i32);
        put(&mut h, 4, b"n+2\0\r\n\x1a\n");
        w!(12, o.ty.nifti_code());
        w!(14, (o.ty.size() * 8) as i16);
        for (i, d) in dim.iter().enumerate() {
            w!(16 + 8 * i, *d);
        }
        for (i, p) in pixdim.iter().enumerate() {
            w!(104 + 8 * i, *p);
        }
        w!(168, off as i64);
        w!(176, o.slope);
        w!(184, o.inter);
        w!(344, qcode as i32);
        w!(348, scode as i32);
        for i in 0..3 {
            w!(352 + 8 * i, quat[i]);
            w!(376 + 8 * i, v.affine.origin[i]);
        }
        for r in 0..3 {
            for c in 0..4 {
                w!(400 + 32 * r + 8 * c, srow[r][c]);
            }
        }
    }
    let _ = hsize;
    h.extend(data);
    h
}

/// NRRD encodings the writer produces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NrrdEnc {
    Raw,
    Gzip,
    Ascii,
}

/// Writes an attached NRRD (float samples) in `space` ("RAS" world given; "left-posterior-superior"
/// converts the directions and origin to LPS as a real LPS file would hold them).
pub fn write_nrrd(v: &Vol, enc: NrrdEnc, big: bool, lps: bool) -> Vec<u8> {
    let flip = if lps {
        DVec3::new(-1.0, -1.0, 1.0)
    } else {
        DVec3::ONE
    };
    let vec3 = |p: DVec3| format!("({},{},{})", p.x, p.y, p.z);
    let mut s = String::from("NRRD0004\n# written by the LSW tests\ntype: float\ndimension: 3\n");
    s += if lps {
        "space: left-posterior-superior\n"
    } else {
        "space: right-anterior-superior\n"
    };
    s += &format!("sizes: {} {} {}\n", v.dims[0], v.dims[1], v.dims[2]);
    s += &format!(
        "space directions: {} {} {}\n",
        vec3(v.affine.cols[0] * flip),
        vec3(v.affine.cols[1] * flip),
        vec3(v.affine.cols[2] * flip)
    );
    s += "kinds: domain domain domain\n";
    s += &format!("endian: {}\n", if big { "big" } else { "little" });
    s += &format!(
        "encoding: {}\n",
        match enc {
            NrrdEnc::Raw => "raw",
            NrrdEnc::Gzip => "gzip",
            NrrdEnc::Ascii => "ascii",
        }
    );
    s += &format!("space origin: {}\n\n", vec3(v.affine.origin * flip));
    let mut out = s.into_bytes();
    let vals: Vec<f64> = v.values.iter().map(|&x| x as f64).collect();
    match enc {
        NrrdEnc::Raw => out.extend(encode(&vals, Ty::F32, big)),
        NrrdEnc::Gzip => out.extend(gzip(&encode(&vals, Ty::F32, big))),
        NrrdEnc::Ascii => {
            for x in &v.values {
                out.extend(format!("{x}\n").bytes());
            }
        }
    }
    out
}

/// VTI data layouts the writer produces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VtiEnc {
    Ascii,
    /// Inline base64, header and data in one base64 stream.
    Base64,
    /// Inline base64, zlib-compressed blocks of `block` bytes; header base64-encoded separately.
    Zlib {
        block: usize,
    },
    /// Appended raw data.
    AppendedRaw,
}

/// Writes a `.vti` (Float32 point array "density", plus an Int16 array "other" before it so the
/// `Scalars` attribute matters).
pub fn write_vti(v: &Vol, enc: VtiEnc, wide: bool) -> Vec<u8> {
    use base64::Engine as _;
    let b64 = |d: &[u8]| base64::engine::general_purpose::STANDARD.encode(d);
    let sp = v.affine.spacing();
    let dir = v.affine.directions();
    // Direction is row-major: row i = (dir[0][i], dir[1][i], dir[2][i]).
    let direction: Vec<String> = (0..3)
        .flat_map(|i| (0..3).map(move |k| (i, k)))
        .map(|(i, k)| dir[k][i].to_string())
        .collect();
    let [nx, ny, nz] = v.dims;
    let ext = format!("0 {} 0 {} 0 {}", nx - 1, ny - 1, nz - 1);
    let compressor = if matches!(enc, VtiEnc::Zlib { .. }) {
        " compressor=\"vtkZLibDataCompressor\""
    } else {
        ""
    };
    let header_type = if wide { "UInt64" } else { "UInt32" };
    let hint = |x: usize| -> Vec<u8> {
        if wide {
            (x as u64).to_le_bytes().to_vec()
        } else {
            (x as u32).to_le_bytes().to_vec()
        }
    };
    let data = encode(
        &v.values.iter().map(|&x| x as f64).collect::<Vec<_>>(),
        Ty::F32,
        false,
    );
    let mut s = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"{header_type}\"{compressor}>\n  <ImageData WholeExtent=\"{ext}\" Origin=\"{} {} {}\" Spacing=\"{} {} {}\" Direction=\"{}\">\n  <Piece Extent=\"{ext}\">\n    <PointData Scalars=\"density\">\n",
        v.affine.origin.x, v.affine.origin.y, v.affine.origin.z, sp[0], sp[1], sp[2],
        direction.join(" ")
    );
    // A decoy array first (ascii, Int16).
    s += "      <DataArray type=\"Int16\" Name=\"other\" format=\"ascii\">\n";
    for _ in 0..v.values.len() {
        s += "7 ";
    }
    s += "\n      </DataArray>\n";
    let mut appended = Vec::new();
    match enc {
        VtiEnc::Ascii => {
            s += "      <DataArray type=\"Float32\" Name=\"density\" format=\"ascii\">\n";
            for x in &v.values {
                s += &format!("{x} ");
            }
            s += "\n      </DataArray>\n";
        }
        VtiEnc::Base64 => {
            let mut block = hint(data.len());
            block.extend(&data);
            s += &format!(
                "      <DataArray type=\"Float32\" Name=\"density\" format=\"binary\">\n        {}\n      </DataArray>\n",
                b64(&block)
            );
        }
        VtiEnc::Zlib { block } => {
            let chunks: Vec<&[u8]> = data.chunks(block).collect();
            let comp: Vec<Vec<u8>> = chunks.iter().map(|c| zlib(c)).collect();
            let mut header = hint(chunks.len());
            header.extend(hint(block));
            header.extend(hint(chunks.last().map_or(0, |c| c.len())));
            for c in &comp {
                header.extend(hint(c.len()));
            }
            let body: Vec<u8> = comp.concat();
            s += &format!(
                "      <DataArray type=\"Float32\" Name=\"density\" format=\"binary\">\n        {}{}\n      </DataArray>\n",
                b64(&header),
                b64(&body)
            );
        }
        VtiEnc::AppendedRaw => {
            s += "      <DataArray type=\"Float32\" Name=\"density\" format=\"appended\" offset=\"0\"/>\n";
            appended = hint(data.len());
            appended.extend(&data);
        }
    }
    s += "    </PointData>\n  </Piece>\n  </ImageData>\n";
    let mut out = s.into_bytes();
    if enc == VtiEnc::AppendedRaw {
        out.extend(b"  <AppendedData encoding=\"raw\">\n   _");
        out.extend(appended);
        out.extend(b"\n  </AppendedData>\n");
    }
    out.extend(b"</VTKFile>\n");
    out
}

/// Writes a single-file MetaImage (`.mha`) with float samples.
pub fn write_mha(v: &Vol, compressed: bool, big: bool) -> Vec<u8> {
    let sp = v.affine.spacing();
    let dir = v.affine.directions();
    let tm: Vec<String> = dir
        .iter()
        .flat_map(|d| d.to_array())
        .map(|x| x.to_string())
        .collect();
    let data = encode(
        &v.values.iter().map(|&x| x as f64).collect::<Vec<_>>(),
        Ty::F32,
        big,
    );
    let body = if compressed { zlib(&data) } else { data };
    let mut s = String::from("ObjectType = Image\nNDims = 3\nBinaryData = True\n");
    s += &format!(
        "BinaryDataByteOrderMSB = {}\n",
        if big { "True" } else { "False" }
    );
    s += &format!(
        "CompressedData = {}\n",
        if compressed { "True" } else { "False" }
    );
    if compressed {
        s += &format!("CompressedDataSize = {}\n", body.len());
    }
    s += &format!("TransformMatrix = {}\n", tm.join(" "));
    s += &format!(
        "Offset = {} {} {}\n",
        v.affine.origin.x, v.affine.origin.y, v.affine.origin.z
    );
    s += &format!("ElementSpacing = {} {} {}\n", sp[0], sp[1], sp[2]);
    s += &format!("DimSize = {} {} {}\n", v.dims[0], v.dims[1], v.dims[2]);
    s += "ElementType = MET_FLOAT\nElementDataFile = LOCAL\n";
    let mut out = s.into_bytes();
    out.extend(body);
    out
}
