//! NIfTI-1 and NIfTI-2 volumes (`.nii`, `.nii.gz`, and `.hdr`/`.img` pairs), the format of
//! neuro-imaging: a fixed binary header (348 or 540 bytes) in either byte order, then the voxels.
//!
//! World coordinates are NIfTI's RAS+ millimetres: the sform (`srow_x/y/z`) when `sform_code > 0`,
//! else the qform (quaternion + offset + `pixdim`, with `qfac = pixdim[0]`) when
//! `qform_code > 0`, else the voxel size alone ("method 1" of the standard). Values are
//! `raw·scl_slope + scl_inter` when the slope is non-zero (slope 0 means "no scaling"). A 4-D (or
//! higher) file holds several volumes; [`VolumeOptions::frame`] picks one and only the bytes up to
//! its end are read (and, for `.nii.gz`, inflated). Reference: the NIfTI-1 header `nifti1.h`
//! and the NIfTI-2 header `nifti2.h` of the NIfTI Data Format Working Group.

use super::error::{Format, IoError, Location};
use super::volume::{
    affine, checked_count, decode_samples, inflate_prefix, is_gzip, Packing, ScalarType,
    VolumeOptions, VoxelVolume, MAX_INFLATE_RATIO,
};
use super::Encoding;
use glam::{DMat3, DVec3};

const F: Format = Format::Nifti;

/// True when `bytes` begin like a NIfTI header (sizeof_hdr 348 or 540 in either byte order, with
/// the matching magic string).
pub fn sniff(bytes: &[u8]) -> bool {
    header_kind(bytes).is_some()
}

/// (NIfTI version 1 or 2, big-endian) from the first bytes, if they are a NIfTI header.
fn header_kind(b: &[u8]) -> Option<(u8, bool)> {
    let head: [u8; 4] = b.get(..4)?.try_into().ok()?;
    let (le, be) = (i32::from_le_bytes(head), i32::from_be_bytes(head));
    let v1 = |m: &[u8]| m == b"n+1\0" || m == b"ni1\0";
    let v2 = |m: &[u8]| m.starts_with(b"n+2\0") || m.starts_with(b"ni2\0");
    for (size, big) in [(le, false), (be, true)] {
        if size == 348 && b.get(344..348).is_some_and(v1) {
            return Some((1, big));
        }
        if size == 540 && b.get(4..12).is_some_and(v2) {
            return Some((2, big));
        }
    }
    None
}

/// The header fields LSW uses, in NIfTI-2 widths.
#[derive(Clone, Debug)]
struct Header {
    version: u8,
    big: bool,
    /// True for `ni1`/`ni2` (separate `.img` file).
    pair: bool,
    dim: [i64; 8],
    datatype: i16,
    pixdim: [f64; 8],
    vox_offset: f64,
    slope: f64,
    inter: f64,
    qform_code: i32,
    sform_code: i32,
    quatern: [f64; 3],
    qoffset: [f64; 3],
    srow: [[f64; 4]; 3],
}

/// Field reader over the header bytes (all offsets are within the checked header size).
struct Fields<'a> {
    b: &'a [u8],
    big: bool,
}

impl Fields<'_> {
    fn raw<const N: usize>(&self, off: usize) -> [u8; N] {
        self.b[off..off + N]
            .try_into()
            .expect("header size checked")
    }
    fn i16(&self, off: usize) -> i16 {
        let a = self.raw::<2>(off);
        if self.big {
            i16::from_be_bytes(a)
        } else {
            i16::from_le_bytes(a)
        }
    }
    fn i32(&self, off: usize) -> i32 {
        let a = self.raw::<4>(off);
        if self.big {
            i32::from_be_bytes(a)
        } else {
            i32::from_le_bytes(a)
        }
    }
    fn i64(&self, off: usize) -> i64 {
        let a = self.raw::<8>(off);
        if self.big {
            i64::from_be_bytes(a)
        } else {
            i64::from_le_bytes(a)
        }
    }
    fn f32(&self, off: usize) -> f64 {
        let a = self.raw::<4>(off);
        (if self.big {
            f32::from_be_bytes(a)
        } else {
            f32::from_le_bytes(a)
        }) as f64
    }
    fn f64(&self, off: usize) -> f64 {
        let a = self.raw::<8>(off);
        if self.big {
            f64::from_be_bytes(a)
        } else {
            f64::from_le_bytes(a)
        }
    }
}

fn parse_header(b: &[u8]) -> Result<Header, IoError> {
    let Some((version, big)) = header_kind(b) else {
        if b.len() < 4 {
            return Err(IoError::truncated(
                F,
                Location::Byte(b.len()),
                "the 4-byte sizeof_hdr field",
            ));
        }
        let head: [u8; 4] = b[..4].try_into().expect("4 bytes");
        let size = i32::from_le_bytes(head);
        let found = if size == 348 || size == 540 || i32::from_be_bytes(head) == 348 {
            "a matching sizeof_hdr but no NIfTI magic (\"n+1\", \"ni1\", \"n+2\"); an Analyze 7.5 file?".to_string()
        } else {
            format!("{size}")
        };
        return Err(if b.len() < 348 && (size == 348 || size == 540) {
            IoError::truncated(F, Location::Byte(b.len()), "the whole header")
        } else {
            IoError::syntax(
                F,
                Location::Byte(0),
                "sizeof_hdr 348 (NIfTI-1) or 540 (NIfTI-2) and the magic string",
                found,
            )
        });
    };
    let size = if version == 1 { 348 } else { 540 };
    if b.len() < size {
        return Err(IoError::truncated(
            F,
            Location::Byte(b.len()),
            format!("the {size}-byte NIfTI-{version} header"),
        ));
    }
    let f = Fields { b, big };
    Ok(if version == 1 {
        Header {
            version,
            big,
            pair: &b[344..347] == b"ni1",
            dim: std::array::from_fn(|i| f.i16(40 + 2 * i) as i64),
            datatype: f.i16(70),
            pixdim: std::array::from_fn(|i| f.f32(76 + 4 * i)),
            vox_offset: f.f32(108),
            slope: f.f32(112),
            inter: f.f32(116),
            qform_code: f.i16(252) as i32,
            sform_code: f.i16(254) as i32,
            quatern: std::array::from_fn(|i| f.f32(256 + 4 * i)),
            qoffset: std::array::from_fn(|i| f.f32(268 + 4 * i)),
            srow: std::array::from_fn(|r| std::array::from_fn(|c| f.f32(280 + 16 * r + 4 * c))),
        }
    } else {
        Header {
            version,
            big,
            pair: &b[4..7] == b"ni2",
            dim: std::array::from_fn(|i| f.i64(16 + 8 * i)),
            datatype: f.i16(12),
            pixdim: std::array::from_fn(|i| f.f64(104 + 8 * i)),
            vox_offset: f.i64(168) as f64,
            slope: f.f64(176),
            inter: f.f64(184),
            qform_code: f.i32(344),
            sform_code: f.i32(348),
            quatern: std::array::from_fn(|i| f.f64(352 + 8 * i)),
            qoffset: std::array::from_fn(|i| f.f64(376 + 8 * i)),
            srow: std::array::from_fn(|r| std::array::from_fn(|c| f.f64(400 + 32 * r + 8 * c))),
        }
    })
}

/// The sample type of a NIfTI `datatype` code.
fn scalar_type(code: i16, at: usize) -> Result<ScalarType, IoError> {
    Ok(match code {
        2 => ScalarType::U8,
        4 => ScalarType::I16,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        768 => ScalarType::U32,
        1024 => ScalarType::I64,
        1280 => ScalarType::U64,
        32 | 1792 | 2048 => {
            return Err(IoError::Unsupported {
                format: F,
                what: format!("complex voxels (datatype {code} at byte {at})"),
            })
        }
        128 | 2304 => {
            return Err(IoError::Unsupported {
                format: F,
                what: format!("RGB(A) voxels (datatype {code} at byte {at})"),
            })
        }
        _ => {
            return Err(IoError::syntax(
                F,
                Location::Byte(at),
                "a known datatype code (2, 4, 8, 16, 64, 256, 512, 768, 1024, 1280)",
                code.to_string(),
            ))
        }
    })
}

/// What the header says about the voxel block: (dims, frames, sample type, bytes per frame,
/// data offset).
struct Layout {
    dims: [usize; 3],
    frames: usize,
    ty: ScalarType,
    frame_bytes: usize,
    offset: usize,
}

fn layout(h: &Header, available: usize, ratio: u128) -> Result<Layout, IoError> {
    let (dim_at, dt_at, off_at) = if h.version == 1 {
        (40, 70, 108)
    } else {
        (16, 12, 168)
    };
    let nd = h.dim[0];
    if !(1..=7).contains(&nd) {
        return Err(IoError::syntax(
            F,
            Location::Byte(dim_at),
            "dim[0] (the number of dimensions) in 1…7",
            nd.to_string(),
        ));
    }
    let mut d = [1usize; 7];
    for i in 1..=nd as usize {
        let v = h.dim[i];
        if v < 1 {
            return Err(IoError::syntax(
                F,
                Location::Byte(dim_at + i * if h.version == 1 { 2 } else { 8 }),
                format!("dim[{i}] ≥ 1"),
                v.to_string(),
            ));
        }
        d[i - 1] = usize::try_from(v).unwrap_or(usize::MAX);
    }
    let ty = scalar_type(h.datatype, dt_at)?;
    let count = checked_count(&d, ty.size(), available, ratio, F, Location::Byte(dim_at))?;
    let frames = d[3..].iter().product::<usize>();
    let frame_bytes = count / frames * ty.size();
    let min_offset = if h.pair {
        0.0
    } else if h.version == 1 {
        348.0
    } else {
        540.0
    };
    if h.vox_offset.is_nan() || h.vox_offset < min_offset || h.vox_offset > 1e15 {
        return Err(IoError::syntax(
            F,
            Location::Byte(off_at),
            format!("vox_offset ≥ {min_offset}"),
            h.vox_offset.to_string(),
        ));
    }
    Ok(Layout {
        dims: [d[0], d[1], d[2]],
        frames,
        ty,
        frame_bytes,
        offset: h.vox_offset as usize,
    })
}

/// The index → world map and its description (sform, qform or pixdim; see the module docs).
fn world_map(h: &Header) -> (glam::DMat4, String) {
    let finite = |a: &[f64]| a.iter().all(|v| v.is_finite());
    let pix = |i: usize| {
        let p = h.pixdim[i];
        if p.is_finite() && p > 0.0 {
            p
        } else {
            1.0
        }
    };
    if h.sform_code > 0 && h.srow.iter().all(|r| finite(r)) {
        let s = h.srow;
        let cols = [0, 1, 2].map(|c| DVec3::new(s[0][c], s[1][c], s[2][c]));
        let m = affine(cols, DVec3::new(s[0][3], s[1][3], s[2][3]));
        if m.determinant() != 0.0 {
            return (m, format!("RAS (NIfTI sform, code {})", h.sform_code));
        }
    }
    if h.qform_code > 0 && finite(&h.quatern) && finite(&h.qoffset) {
        let [b, c, d] = h.quatern;
        let a2 = 1.0 - (b * b + c * c + d * d);
        // A slightly negative a² is rounding in the header (nifti1_io.c treats it the same way).
        let (a, b, c, d) = if a2 > 1e-7 {
            (a2.sqrt(), b, c, d)
        } else {
            let n = (b * b + c * c + d * d).sqrt().max(f64::MIN_POSITIVE);
            (0.0, b / n, c / n, d / n)
        };
        let r = DMat3::from_cols(
            DVec3::new(
                a * a + b * b - c * c - d * d,
                2.0 * (b * c + a * d),
                2.0 * (b * d - a * c),
            ),
            DVec3::new(
                2.0 * (b * c - a * d),
                a * a + c * c - b * b - d * d,
                2.0 * (c * d + a * b),
            ),
            DVec3::new(
                2.0 * (b * d + a * c),
                2.0 * (c * d - a * b),
                a * a + d * d - c * c - b * b,
            ),
        );
        let qfac = if h.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
        let cols = [
            r.x_axis * pix(1),
            r.y_axis * pix(2),
            r.z_axis * (pix(3) * qfac),
        ];
        let o = DVec3::from_array(h.qoffset);
        return (
            affine(cols, o),
            format!("RAS (NIfTI qform, code {})", h.qform_code),
        );
    }
    (
        affine(
            [DVec3::X * pix(1), DVec3::Y * pix(2), DVec3::Z * pix(3)],
            DVec3::ZERO,
        ),
        "voxel grid scaled by pixdim (NIfTI sform and qform codes are 0)".to_string(),
    )
}

/// Builds the volume from a parsed header and the bytes holding its voxels (`data` starts at
/// file offset `data_at`; the frame's samples begin at `start` within `data`).
fn finish(
    h: &Header,
    lay: &Layout,
    data: &[u8],
    start: usize,
    data_at: usize,
    opts: &VolumeOptions,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let end = start.saturating_add(lay.frame_bytes);
    if data.len() < end {
        return Err(IoError::truncated(
            F,
            Location::Byte(data_at + data.len()),
            format!(
                "{} bytes of voxel data for frame {} (of {}), {} present",
                lay.frame_bytes,
                opts.frame,
                lay.frames,
                data.len().saturating_sub(start)
            ),
        ));
    }
    let (slope, inter) = if h.slope != 0.0 && h.slope.is_finite() {
        (h.slope, if h.inter.is_finite() { h.inter } else { 0.0 })
    } else {
        (1.0, 0.0)
    };
    let values = decode_samples(&data[start..end], lay.ty, h.big, slope, inter);
    let (index_to_world, frame) = world_map(h);
    Ok((
        VoxelVolume {
            dims: lay.dims,
            values,
            index_to_world,
            datatype: lay.ty,
            frame,
            frames: lay.frames,
            frame_index: opts.frame,
        },
        if h.big {
            Encoding::BinaryBe
        } else {
            Encoding::BinaryLe
        },
    ))
}

fn check_frame(lay: &Layout, opts: &VolumeOptions) -> Result<(), IoError> {
    if opts.frame >= lay.frames {
        return Err(IoError::Unsupported {
            format: F,
            what: format!(
                "frame {} (the file holds {} volume{}; frames are 0-based)",
                opts.frame,
                lay.frames,
                if lay.frames == 1 { "" } else { "s" }
            ),
        });
    }
    Ok(())
}

/// Reads a single-file NIfTI (`.nii` or gzip-compressed `.nii.gz`).
pub fn read(bytes: &[u8], opts: &VolumeOptions) -> Result<(VoxelVolume, Encoding), IoError> {
    if is_gzip(bytes) {
        // Inflate the header first, then exactly up to the end of the chosen frame.
        let head = inflate_prefix(bytes, Packing::Gzip, 540, false, F, 0)?;
        let h = parse_header(&head)?;
        let lay = layout(&h, bytes.len(), MAX_INFLATE_RATIO)?;
        check_frame(&lay, opts)?;
        if h.pair {
            return Err(pair_error());
        }
        let start = lay
            .offset
            .saturating_add(opts.frame.saturating_mul(lay.frame_bytes));
        let data = inflate_prefix(
            bytes,
            Packing::Gzip,
            start.saturating_add(lay.frame_bytes),
            true,
            F,
            0,
        )?;
        return finish(&h, &lay, &data, start, 0, opts);
    }
    let h = parse_header(bytes)?;
    if h.pair {
        return Err(pair_error());
    }
    let lay = layout(&h, bytes.len(), 1)?;
    check_frame(&lay, opts)?;
    finish(
        &h,
        &lay,
        bytes,
        lay.offset
            .saturating_add(opts.frame.saturating_mul(lay.frame_bytes)),
        0,
        opts,
    )
}

fn pair_error() -> IoError {
    IoError::Unsupported {
        format: F,
        what: "a .hdr header (magic \"ni1\") without its .img data here; read the pair from disk \
               (lsw reads NAME.img next to NAME.hdr) or convert it to a single .nii"
            .into(),
    }
}

/// True when a header (possibly gzip-compressed) says its voxels are in a separate `.img` file.
pub fn is_pair_header(bytes: &[u8]) -> bool {
    let head = if is_gzip(bytes) {
        inflate_prefix(bytes, Packing::Gzip, 540, false, F, 0).unwrap_or_default()
    } else {
        bytes[..bytes.len().min(540)].to_vec()
    };
    parse_header(&head).is_ok_and(|h| h.pair)
}

/// Reads a `.hdr`/`.img` pair (either may be gzip-compressed); `vox_offset` counts into `img`.
pub fn read_pair(
    hdr: &[u8],
    img: &[u8],
    opts: &VolumeOptions,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let head = if is_gzip(hdr) {
        inflate_prefix(hdr, Packing::Gzip, 540, false, F, 0)?
    } else {
        hdr.to_vec()
    };
    let h = parse_header(&head)?;
    let (ratio, avail) = if is_gzip(img) {
        (MAX_INFLATE_RATIO, img.len())
    } else {
        (1, img.len())
    };
    let lay = layout(&h, avail, ratio)?;
    check_frame(&lay, opts)?;
    let start = lay
        .offset
        .saturating_add(opts.frame.saturating_mul(lay.frame_bytes));
    if is_gzip(img) {
        let data = inflate_prefix(
            img,
            Packing::Gzip,
            start.saturating_add(lay.frame_bytes),
            true,
            F,
            0,
        )?;
        finish(&h, &lay, &data, start, 0, opts)
    } else {
        finish(&h, &lay, img, start, 0, opts)
    }
}

/// Writes a volume as a single-file NIfTI-1 (`.nii`, little-endian float32, the affine as an
/// sform with code 2 "aligned", no qform, no scaling). Used for the app's procedurally generated
/// phantom (it then travels the same path as a dropped file) and to save volumes for other tools.
pub fn write(volume: &VoxelVolume) -> Vec<u8> {
    let mut h = vec![0u8; 352];
    let put = |h: &mut [u8], at: usize, b: &[u8]| h[at..at + b.len()].copy_from_slice(b);
    put(&mut h, 0, &348i32.to_le_bytes());
    let dims = [
        3,
        volume.dims[0],
        volume.dims[1],
        volume.dims[2],
        1,
        1,
        1,
        1,
    ];
    for (i, d) in dims.iter().enumerate() {
        put(
            &mut h,
            40 + 2 * i,
            &(*d).min(i16::MAX as usize).to_le_bytes()[..2],
        );
    }
    put(&mut h, 70, &16i16.to_le_bytes());
    put(&mut h, 72, &32i16.to_le_bytes());
    let vs = volume.voxel_size();
    let pixdim = [1.0, vs[0], vs[1], vs[2], 1.0, 1.0, 1.0, 1.0];
    for (i, p) in pixdim.iter().enumerate() {
        put(&mut h, 76 + 4 * i, &(*p as f32).to_le_bytes());
    }
    put(&mut h, 108, &352f32.to_le_bytes());
    put(&mut h, 123, &[2]); // xyzt_units: millimetres
    put(&mut h, 254, &2i16.to_le_bytes());
    let rows = volume.affine_rows();
    for (r, row) in rows.iter().take(3).enumerate() {
        for (c, x) in row.iter().enumerate() {
            put(&mut h, 280 + 16 * r + 4 * c, &(*x as f32).to_le_bytes());
        }
    }
    put(&mut h, 344, b"n+1\0");
    h.reserve(volume.values.len() * 4);
    for v in &volume.values {
        h.extend_from_slice(&v.to_le_bytes());
    }
    h
}
