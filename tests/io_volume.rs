//! Voxel volumes: analytic volumes (a ball's and a torus's implicit function on a grid with
//! anisotropic voxels and a rotated + translated affine) written in every format and variant by the
//! test helpers, read back (header, values, world coordinates), and their iso-surface targets
//! compared with the analytic surfaces (distance, orientation, genus via `validate()`); header
//! edge cases; malformed and truncated files → errors, never panics. Runs natively and in headless
//! Chromium; the shared brain files (native only) where `LSW_SHARED_DATA` is set.

#[path = "common/field_data.rs"]
mod field_data;
#[path = "common/volume_files.rs"]
mod volume_files;

use lsw::io::{
    read_bytes, read_bytes_with, read_volume_bytes, Format, Inside, IoError, VolumeOptions,
    VoxelVolume,
};
use lsw::mesh::HalfedgeMesh;
use lsw::DVec3;
use volume_files::*;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// Every writer variant of `v`, with a file name and the format it must be read as.
fn all_variants(v: &Vol) -> Vec<(String, Format, Vec<u8>)> {
    let mut out = Vec::new();
    for version in [1u8, 2] {
        for big in [false, true] {
            for geom in [NiftiGeom::Sform, NiftiGeom::Qform] {
                let o = NiftiOpts {
                    version,
                    big,
                    geom,
                    ..Default::default()
                };
                out.push((
                    format!(
                        "nifti{version}_{}_{geom:?}.nii",
                        if big { "be" } else { "le" }
                    ),
                    Format::Nifti,
                    write_nifti(v, o),
                ));
            }
        }
    }
    out.push((
        "gz.nii.gz".into(),
        Format::Nifti,
        gzip(&write_nifti(v, NiftiOpts::default())),
    ));
    for (name, enc, big, lps) in [
        ("raw_le", NrrdEnc::Raw, false, false),
        ("raw_be", NrrdEnc::Raw, true, false),
        ("gzip", NrrdEnc::Gzip, false, false),
        ("ascii", NrrdEnc::Ascii, false, false),
        ("lps", NrrdEnc::Raw, false, true),
        ("lps_gzip_be", NrrdEnc::Gzip, true, true),
    ] {
        out.push((
            format!("{name}.nrrd"),
            Format::Nrrd,
            write_nrrd(v, enc, big, lps),
        ));
    }
    for (name, enc, wide) in [
        ("ascii", VtiEnc::Ascii, false),
        ("base64", VtiEnc::Base64, false),
        ("base64_u64", VtiEnc::Base64, true),
        ("zlib", VtiEnc::Zlib { block: 1000 }, false),
        ("zlib_u64", VtiEnc::Zlib { block: 4096 }, true),
        ("appended", VtiEnc::AppendedRaw, false),
        ("appended_u64", VtiEnc::AppendedRaw, true),
    ] {
        out.push((format!("{name}.vti"), Format::Vti, write_vti(v, enc, wide)));
    }
    for (name, compressed, big) in [
        ("raw", false, false),
        ("msb", false, true),
        ("zlib", true, false),
    ] {
        out.push((
            format!("{name}.mha"),
            Format::MetaImage,
            write_mha(v, compressed, big),
        ));
    }
    out
}

fn read_vol(name: &str, bytes: &[u8], opts: &VolumeOptions) -> (VoxelVolume, Format) {
    let (v, f, _) =
        read_volume_bytes(bytes, Some(name), opts).unwrap_or_else(|e| panic!("{name}: {e}"));
    (v, f)
}

/// Worst distance between the world positions of the grid's corners and centre in `a` and `v`.
fn world_error(a: &Affine, v: &VoxelVolume) -> f64 {
    let [nx, ny, nz] = v.dims.map(|d| (d - 1) as f64);
    let mut worst = 0.0f64;
    for i in [
        DVec3::ZERO,
        DVec3::new(nx, 0.0, 0.0),
        DVec3::new(0.0, ny, 0.0),
        DVec3::new(0.0, 0.0, nz),
        DVec3::new(nx, ny, nz),
        DVec3::new(nx / 2.0, ny / 3.0, nz / 4.0),
    ] {
        worst = worst.max((a.world(i) - v.world(i)).length());
    }
    worst
}

#[wasm_bindgen_test(unsupported = test)]
fn every_format_round_trips_header_values_and_world_coordinates() {
    let vol = sphere_volume([14, 17, 11], 6.0);
    for (name, format, bytes) in all_variants(&vol) {
        let (v, f) = read_vol(&name, &bytes, &VolumeOptions::default());
        assert_eq!(f, format, "{name}");
        // Detected from the content alone as well.
        assert_eq!(lsw::io::detect(&bytes, None), Ok(format), "{name}");
        assert_eq!(v.dims, vol.dims, "{name}");
        assert_eq!(v.values, vol.values, "{name}: values");
        assert_eq!(v.frames, 1, "{name}");
        // NIfTI-1 stores the affine in f32.
        let err = world_error(&vol.affine, &v);
        assert!(err < 1e-4, "{name}: world coordinates off by {err} mm");
        let (sp, expect) = (v.voxel_size(), vol.affine.spacing());
        for (got, want) in sp.iter().zip(expect.iter()) {
            assert!((got - want).abs() < 1e-5, "{name}: voxel size");
        }
    }
}

/// Checks the target of a volume against an analytic surface: every vertex within `tol` of it,
/// closed, manifold, oriented outwards (positive enclosed volume), of the given genus.
fn check_surface(
    name: &str,
    t: &lsw::target::Target,
    dist: impl Fn(DVec3) -> f64,
    tol: f64,
    genus: i64,
) {
    let (mut worst, mut sum) = (0.0f64, 0.0);
    for &p in &t.points {
        let d = dist(p);
        worst = worst.max(d);
        sum += d;
    }
    let mean = sum / t.points.len() as f64;
    assert!(worst < tol, "{name}: max distance {worst} ≥ {tol}");
    assert!(mean < tol / 3.0, "{name}: mean distance {mean}");
    let m = HalfedgeMesh::from_triangles(t.points.clone(), &t.triangles).unwrap();
    let r = m.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(r.components, 1, "{name}");
    assert_eq!(r.genus, genus, "{name}");
    let volume: f64 = t
        .triangles
        .iter()
        .map(|&[a, b, c]| {
            let (a, b, c) = (
                t.points[a as usize],
                t.points[b as usize],
                t.points[c as usize],
            );
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!(
        volume > 0.0,
        "{name}: triangles face inwards (volume {volume})"
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn isosurface_targets_match_the_analytic_sphere_and_torus_in_every_format() {
    let dims = [22, 30, 17];
    let r = 10.0;
    let vol = sphere_volume(dims, r);
    let c = centre(dims, &vol.affine);
    // Linear interpolation of 100·(r − |x − c|) along edges up to ~2.9 mm: error ≤ h²/(2r).
    let tol = 0.45;
    let opts = VolumeOptions {
        iso: Some(0.0),
        ..Default::default()
    };
    let mut reference: Option<Vec<DVec3>> = None;
    for (name, _, bytes) in all_variants(&vol) {
        let t = read_bytes_with(&bytes, Some(&name), &opts)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .target;
        check_surface(&name, &t, |p| ((p - c).length() - r).abs(), tol, 0);
        // Every format gives the same surface (NIfTI-1's f32 affine to 1e-4 mm).
        match &reference {
            None => reference = Some(t.points.clone()),
            Some(p0) => {
                assert_eq!(p0.len(), t.points.len(), "{name}");
                let e = p0
                    .iter()
                    .zip(&t.points)
                    .map(|(a, b)| (*a - *b).length())
                    .fold(0.0, f64::max);
                assert!(e < 1e-4, "{name}: surface differs by {e} mm");
            }
        }
    }
    // A torus (genus 1) with its axis oblique to the grid.
    let axis = DVec3::new(0.3, -0.5, 1.0);
    let (big, small) = (9.0, 3.5);
    let tv = torus_volume([30, 40, 24], big, small, axis);
    let tc = centre(tv.dims, &tv.affine);
    for (name, bytes) in [
        ("torus.nii", write_nifti(&tv, NiftiOpts::default())),
        (
            "torus.vti",
            write_vti(&tv, VtiEnc::Zlib { block: 2048 }, false),
        ),
    ] {
        let t = read_bytes_with(&bytes, Some(name), &opts).unwrap().target;
        check_surface(
            name,
            &t,
            |p| torus_distance(p, tc, big, small, axis),
            0.45,
            1,
        );
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn mirrored_affine_dark_inside_and_otsu() {
    let dims = [16, 18, 14];
    // Radiological order: the x axis reversed (negative determinant) — still outward normals.
    let mut a = test_affine();
    a.cols[0] = -a.cols[0];
    let ca = centre(dims, &a);
    let vol = sample(dims, a, |p| 100.0 * (7.0 - (p - ca).length()));
    let bytes = write_nifti(&vol, NiftiOpts::default());
    let opts = VolumeOptions {
        iso: Some(0.0),
        ..Default::default()
    };
    let t = read_bytes_with(&bytes, Some("mirror.nii"), &opts)
        .unwrap()
        .target;
    check_surface("mirrored", &t, |p| ((p - ca).length() - 7.0).abs(), 0.4, 0);
    // The negated volume with "dark inside" gives the same surface.
    let neg = Vol {
        values: vol.values.iter().map(|v| -v).collect(),
        ..vol.clone()
    };
    let dark = VolumeOptions {
        iso: Some(0.0),
        inside: Inside::Dark,
        ..Default::default()
    };
    let t2 = read_bytes_with(
        &write_nifti(&neg, NiftiOpts::default()),
        Some("neg.nii"),
        &dark,
    )
    .unwrap()
    .target;
    assert_eq!(t2.points.len(), t.points.len());
    check_surface(
        "dark inside",
        &t2,
        |p| ((p - ca).length() - 7.0).abs(),
        0.4,
        0,
    );
    // Otsu on a two-level (0/200) ball picks the middle, and that is the default iso.
    let mask = Vol {
        values: vol
            .values
            .iter()
            .map(|&v| if v > 0.0 { 200.0 } else { 0.0 })
            .collect(),
        ..vol.clone()
    };
    let r = read_bytes(
        &write_nifti(
            &mask,
            NiftiOpts {
                ty: Ty::U8,
                ..Default::default()
            },
        ),
        Some("m.nii"),
    )
    .unwrap();
    let vr = r.volume.as_ref().unwrap();
    assert_eq!((vr.iso, vr.iso_source), (99.5, "otsu"));
    assert_eq!(vr.volume.otsu(), Some(99.5));
    // An iso-value outside the range is a clear error.
    let e = read_bytes_with(
        &bytes,
        Some("x.nii"),
        &VolumeOptions {
            iso: Some(1e6),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("iso-surface"), "{e}");
}

#[wasm_bindgen_test(unsupported = test)]
fn nifti_scaling_datatypes_4d_and_gzip() {
    let vol = sphere_volume([9, 8, 7], 3.0);
    // Integer storage with scl_slope/scl_inter: values come back to within half a step.
    for (ty, slope, inter) in [
        (Ty::I16, 0.05, -5.0),
        (Ty::U16, 0.05, -1000.0),
        (Ty::I32, 0.001, 0.0),
        (Ty::U32, 0.001, -2000.0),
        (Ty::I8, 10.0, 0.0),
        (Ty::U8, 10.0, -900.0),
        (Ty::F64, 0.0, 0.0),
    ] {
        for big in [false, true] {
            let o = NiftiOpts {
                ty,
                slope,
                inter,
                big,
                ..Default::default()
            };
            let (v, _) = read_vol("s.nii", &write_nifti(&vol, o), &VolumeOptions::default());
            let step = if slope == 0.0 { 1e-6 } else { slope };
            for (a, b) in v.values.iter().zip(&vol.values) {
                // I8/U8 clamp the range; compare only representable values.
                let clamp_lo = match ty {
                    Ty::I8 => -128.0 * slope + inter,
                    Ty::U8 => inter,
                    _ => f64::NEG_INFINITY,
                };
                let clamp_hi = match ty {
                    Ty::I8 => 127.0 * slope + inter,
                    Ty::U8 => 255.0 * slope + inter,
                    _ => f64::INFINITY,
                };
                let want = (*b as f64).clamp(clamp_lo, clamp_hi);
                assert!(
                    (*a as f64 - want).abs() <= 0.5 * step + 1e-3 * want.abs().max(1.0),
                    "{ty:?} big={big}: {a} vs {want}"
                );
            }
        }
    }
    // 4-D: frame k holds values + 1000·k; the first by default, any by option, too far = error.
    for version in [1, 2] {
        let o = NiftiOpts {
            version,
            frames: 3,
            ..Default::default()
        };
        let bytes = write_nifti(&vol, o);
        for (file, bytes) in [("4d.nii", bytes.clone()), ("4d.nii.gz", gzip(&bytes))] {
            let (v0, _) = read_vol(file, &bytes, &VolumeOptions::default());
            assert_eq!((v0.frames, v0.frame_index), (3, 0));
            assert_eq!(v0.values, vol.values);
            let (v2, _) = read_vol(
                file,
                &bytes,
                &VolumeOptions {
                    frame: 2,
                    ..Default::default()
                },
            );
            assert_eq!(v2.frame_index, 2);
            for (a, b) in v2.values.iter().zip(&vol.values) {
                assert_eq!(*a, b + 2000.0);
            }
            let e = read_volume_bytes(
                &bytes,
                Some(file),
                &VolumeOptions {
                    frame: 3,
                    ..Default::default()
                },
            )
            .unwrap_err();
            assert!(e.to_string().contains("frame 3"), "{e}");
        }
    }
}

/// A small volume of every variant, cut at many lengths: always an error, never a panic, except
/// where only bytes the reader does not need were cut (the gzip trailer, VTI closing tags).
#[wasm_bindgen_test(unsupported = test)]
fn truncated_files_are_errors() {
    let vol = sphere_volume([5, 6, 4], 2.0);
    for (name, _, bytes) in all_variants(&vol) {
        let needed = if name.ends_with(".vti") {
            let rfind = |pat: &[u8]| bytes.windows(pat.len()).rposition(|w| w == pat);
            // Appended data ends at the end of its bytes.
            if name.starts_with("appended") {
                rfind(b"\n  </AppendedData").unwrap()
            } else {
                rfind(b"</DataArray").unwrap()
            }
        } else if name.ends_with(".gz") || name.starts_with("gzip") || name.starts_with("lps_gzip")
        {
            // The gzip trailer (CRC, size) and the last bits of the deflate stream are not needed
            // once every sample is inflated.
            bytes.len() - 16
        } else if name == "zlib.mha" {
            bytes.len() - 12
        } else if name.ends_with(".nrrd") && name.starts_with("ascii") {
            // A cut inside the last number still leaves a (different) number.
            let body = &bytes[..bytes.len() - 1];
            body.iter().rposition(|b| b.is_ascii_whitespace()).unwrap()
        } else {
            bytes.len()
        };
        let step = (bytes.len() / 300).max(1);
        let mut cut = 0;
        while cut < bytes.len() {
            let r = read_volume_bytes(&bytes[..cut], Some(&name), &VolumeOptions::default());
            if cut < needed {
                assert!(r.is_err(), "{name}: cut at {cut} of {} reads", bytes.len());
            }
            cut += if cut < 600 { 1 } else { step };
        }
    }
}

/// Corrupted headers (every header byte replaced in turn by a few values): errors or volumes,
/// never panics or absurd allocations.
#[wasm_bindgen_test(unsupported = test)]
fn corrupted_headers_never_panic() {
    let vol = sphere_volume([4, 3, 5], 1.5);
    for (name, _, bytes) in all_variants(&vol) {
        let header = match name.rsplit('.').next().unwrap() {
            "nii" => bytes.len().min(560),
            _ => bytes.len().min(900),
        };
        for i in 0..header {
            for v in [0u8, 0xff, b'9', b' '] {
                let mut b = bytes.clone();
                if b[i] == v {
                    continue;
                }
                b[i] = v;
                let _ = read_volume_bytes(&b, Some(&name), &VolumeOptions::default());
            }
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn malformed_files_give_clear_typed_errors() {
    let vol = sphere_volume([4, 3, 5], 1.5);
    let opts = VolumeOptions::default();
    let err = |bytes: &[u8], name: &str| read_volume_bytes(bytes, Some(name), &opts).unwrap_err();
    // NIfTI: unknown datatype (byte 70), RGB unsupported, bad dim[0] (byte 40), vox_offset.
    let mut b = write_nifti(&vol, NiftiOpts::default());
    b[70..72].copy_from_slice(&77i16.to_le_bytes());
    let e = err(&b, "a.nii");
    assert!(
        matches!(
            e,
            IoError::Syntax {
                format: Format::Nifti,
                at: lsw::io::Location::Byte(70),
                ..
            }
        ),
        "{e}"
    );
    b[70..72].copy_from_slice(&128i16.to_le_bytes());
    assert!(matches!(err(&b, "a.nii"), IoError::Unsupported { .. }));
    let mut b = write_nifti(&vol, NiftiOpts::default());
    b[40..42].copy_from_slice(&9i16.to_le_bytes());
    assert!(matches!(
        err(&b, "a.nii"),
        IoError::Syntax {
            at: lsw::io::Location::Byte(40),
            ..
        }
    ));
    let mut b = write_nifti(&vol, NiftiOpts::default());
    b[42..44].copy_from_slice(&30000i16.to_le_bytes());
    assert!(matches!(err(&b, "a.nii"), IoError::CountTooLarge { .. }));
    let mut b = write_nifti(&vol, NiftiOpts::default());
    b[108..112].copy_from_slice(&10f32.to_le_bytes());
    assert!(matches!(
        err(&b, "a.nii"),
        IoError::Syntax {
            at: lsw::io::Location::Byte(108),
            ..
        }
    ));
    // A .hdr/.img pair header alone, in memory.
    let mut b = write_nifti(&vol, NiftiOpts::default());
    b[344..348].copy_from_slice(b"ni1\0");
    assert!(err(&b, "a.hdr").to_string().contains(".img"));
    // Corrupt gzip stream.
    let mut g = gzip(&write_nifti(&vol, NiftiOpts::default()));
    let n = g.len();
    for x in &mut g[12..n - 8] {
        *x ^= 0x5a;
    }
    let e = err(&g, "a.nii.gz");
    assert!(
        matches!(
            e,
            IoError::Decompress { .. } | IoError::Truncated { .. } | IoError::Syntax { .. }
        ),
        "{e}"
    );
    // NRRD: missing field, bad type, unsupported encoding, a huge size.
    let text = String::from_utf8_lossy(&write_nrrd(&vol, NrrdEnc::Ascii, false, false)).to_string();
    let e = err(text.replace("sizes:", "sizez:").as_bytes(), "a.nrrd");
    assert!(e.to_string().contains("sizes"), "{e}");
    let e = err(
        text.replace("type: float", "type: quaternion").as_bytes(),
        "a.nrrd",
    );
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    let e = err(
        text.replace("encoding: ascii", "encoding: bzip2")
            .as_bytes(),
        "a.nrrd",
    );
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    let e = err(
        text.replace("sizes: 4 3 5", "sizes: 4000 3000 5000")
            .as_bytes(),
        "a.nrrd",
    );
    assert!(matches!(e, IoError::CountTooLarge { .. }), "{e}");
    let e = err(text.replace("(", "[").as_bytes(), "a.nrrd");
    assert!(
        matches!(
            e,
            IoError::Syntax {
                at: lsw::io::Location::Line(_),
                ..
            }
        ),
        "{e}"
    );
    // VTI: invalid base64, an unknown array name, a point array that is too short.
    let t = String::from_utf8_lossy(&write_vti(&vol, VtiEnc::Base64, false)).to_string();
    let e = err(
        t.replacen(
            "format=\"binary\">\n        ",
            "format=\"binary\">\n        !!",
            1,
        )
        .as_bytes(),
        "a.vti",
    );
    assert!(
        matches!(
            e,
            IoError::Syntax {
                format: Format::Vti,
                ..
            }
        ),
        "{e}"
    );
    let e = read_volume_bytes(
        t.as_bytes(),
        Some("a.vti"),
        &VolumeOptions {
            array: Some("nope".into()),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("nope"), "{e}");
    // The decoy Int16 array can be chosen by name.
    let (v, _, _) = read_volume_bytes(
        t.as_bytes(),
        Some("a.vti"),
        &VolumeOptions {
            array: Some("other".into()),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(v.values.iter().all(|&x| x == 7.0));
    let e = err(
        t.replace("WholeExtent=\"0 3", "WholeExtent=\"0 9")
            .as_bytes(),
        "a.vti",
    );
    assert!(
        matches!(e, IoError::Syntax { .. } | IoError::Truncated { .. }),
        "{e}"
    );
    // MetaImage: unknown element type, missing DimSize, channels.
    let m = write_mha(&vol, false, false);
    let mt = String::from_utf8_lossy(&m[..m.len() - 4 * 60]).to_string();
    let head = mt.split("ElementDataFile").next().unwrap().to_string();
    let body = &m[head.len() + "ElementDataFile = LOCAL\n".len()..];
    let with = |h: String| {
        let mut x = h.into_bytes();
        x.extend(b"ElementDataFile = LOCAL\n");
        x.extend(body);
        x
    };
    let e = err(
        &with(head.replace("MET_FLOAT", "MET_FLOAT_MATRIX")),
        "a.mha",
    );
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    let e = err(&with(head.replace("DimSize", "DimSise")), "a.mha");
    assert!(e.to_string().contains("DimSize"), "{e}");
    let e = err(
        &with(head.clone() + "ElementNumberOfChannels = 3\n"),
        "a.mha",
    );
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    // Empty input names the format from the extension.
    assert!(matches!(
        err(b"", "x.nrrd"),
        IoError::Empty {
            format: Some(Format::Nrrd)
        }
    ));
}

/// The shared brain files and nibabel's test volumes (native only).
#[cfg(not(target_arch = "wasm32"))]
#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn shared_volumes_read_and_the_half_resolution_copies_agree() {
    let dir = field_data::data_dir("io_volume");
    let read = |name: &str, frame: usize| {
        lsw::io::read_volume_path(
            dir.join(name),
            &VolumeOptions {
                frame,
                ..Default::default()
            },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let (v, f, e) = read("anatomical.nii", 0);
    assert_eq!(
        (v.dims, f, e),
        ([33, 41, 25], Format::Nifti, lsw::io::Encoding::BinaryBe)
    );
    assert_eq!(v.value_range(), Some((-610.0, 30393.0)));
    assert_eq!(v.voxel_size(), [2.0, 2.0, 2.0]);
    let (v0, _, _) = read("example4d.nii.gz", 0);
    let (v1, _, _) = read("example4d.nii.gz", 1);
    assert_eq!((v0.dims, v0.frames), ([128, 96, 24], 2));
    assert!((v0.voxel_size()[2] - 2.2).abs() < 1e-5);
    assert_ne!(v0.values, v1.values);
    let (v, _, _) = read("example_nifti2.nii.gz", 0);
    assert_eq!((v.dims, v.frames), ([32, 20, 12], 2));
    // The three half-resolution copies: identical volumes in the same (RAS) world frame, and so
    // identical iso-surfaces at 128.
    let halves: Vec<_> = ["gm_half.nrrd", "gm_half.vti", "gm_half.mha"]
        .iter()
        .map(|n| read(n, 0).0)
        .collect();
    for h in &halves {
        assert_eq!(h.dims, [99, 117, 95]);
        assert_eq!(h.values, halves[0].values);
        assert_eq!(h.index_to_world, halves[0].index_to_world);
        assert_eq!(h.world(DVec3::ZERO), DVec3::new(-98.0, -134.0, -72.0));
        assert_eq!(h.voxel_size(), [2.0, 2.0, 2.0]);
    }
    let surf = |v: &VoxelVolume| v.isosurface(128.0, Inside::Bright);
    let (p0, t0) = surf(&halves[0]);
    for h in &halves[1..] {
        let (p, t) = surf(h);
        assert_eq!((p.len(), &t), (p0.len(), &t0));
        let e = p
            .iter()
            .zip(&p0)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        assert!(e <= 1e-9, "{e}");
    }
    // The `lsw info` bar: dimensions of the big-endian, 4-D and NIfTI-2 files.
    for (name, dims) in [
        ("anatomical.nii", [33, 41, 25]),
        ("example4d.nii.gz", [128, 96, 24]),
        ("example_nifti2.nii.gz", [32, 20, 12]),
    ] {
        let a = lsw::cli::info::InfoArgs {
            file: dir.join(name),
            volume: Default::default(),
        };
        let j: serde_json::Value = serde_json::from_str(&lsw::cli::info::run(&a).unwrap()).unwrap();
        assert_eq!(j["volume"]["dims"], serde_json::json!(dims), "{name}");
        assert_eq!(j["format"], "nifti");
        assert!(j["volume"]["iso"].as_f64().is_some());
    }
}

/// Detached data natively: NIfTI `.hdr`/`.img` (plain and gzip), NRRD `.nhdr` + gzip data file,
/// MetaImage `.mhd` + raw file; all read as the attached files do.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn detached_headers_read_their_data_files() {
    let vol = sphere_volume([7, 9, 6], 3.0);
    let dir = std::env::temp_dir().join(format!("lsw_io_volume_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let check = |name: &str| {
        let (v, _, _) = lsw::io::read_volume_path(dir.join(name), &VolumeOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(v.values, vol.values, "{name}");
        assert!(world_error(&vol.affine, &v) < 1e-4, "{name}");
    };
    // NIfTI pair: magic "ni1", vox_offset 0 into the .img.
    let single = write_nifti(&vol, NiftiOpts::default());
    let mut hdr = single[..348].to_vec();
    hdr[344..348].copy_from_slice(b"ni1\0");
    hdr[108..112].copy_from_slice(&0f32.to_le_bytes());
    std::fs::write(dir.join("pair.hdr"), &hdr).unwrap();
    std::fs::write(dir.join("pair.img"), &single[352..]).unwrap();
    check("pair.hdr");
    std::fs::write(dir.join("zpair.hdr"), &hdr).unwrap();
    std::fs::write(dir.join("zpair.img.gz"), gzip(&single[352..])).unwrap();
    check("zpair.hdr");
    // NRRD detached.
    let attached = write_nrrd(&vol, NrrdEnc::Gzip, false, true);
    let split = attached.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let mut nhdr = attached[..split - 1].to_vec();
    nhdr.extend(b"data file: sphere.raw.gz\n");
    std::fs::write(dir.join("sphere.nhdr"), &nhdr).unwrap();
    std::fs::write(dir.join("sphere.raw.gz"), &attached[split..]).unwrap();
    check("sphere.nhdr");
    // MetaImage detached.
    let mha = write_mha(&vol, false, false);
    let end = mha.windows(6).position(|w| w == b"LOCAL\n").unwrap();
    let mut mhd = mha[..end].to_vec();
    mhd.extend(b"sphere.raw\n");
    std::fs::write(dir.join("sphere.mhd"), &mhd).unwrap();
    std::fs::write(dir.join("sphere.raw"), &mha[end + 6..]).unwrap();
    check("sphere.mhd");
    // Without its data file: a clear error naming it.
    std::fs::remove_file(dir.join("sphere.raw")).unwrap();
    let e =
        lsw::io::read_volume_path(dir.join("sphere.mhd"), &VolumeOptions::default()).unwrap_err();
    assert!(e.to_string().contains("sphere.raw"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The wasm facade in the browser: `VolumeView` (info, histogram, slices, preview), typed errors,
/// and the gallery phantom read back through the same reader as a dropped file.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen_test]
fn volume_view_facade_in_the_browser() {
    use lsw::wasm::{phantom_volume, VolumeView};
    use wasm_bindgen::JsValue;
    let get = |o: &js_sys::Object, k: &str| js_sys::Reflect::get(o, &JsValue::from_str(k)).unwrap();
    let vol = sphere_volume([10, 12, 9], 4.0);
    let bytes = write_nifti(&vol, NiftiOpts::default());
    let v = VolumeView::new(&bytes, Some("s.nii".into()), 0).unwrap();
    assert_eq!(v.slice(2, 4).length(), 10 * 12);
    assert_eq!(v.slice(0, 3).length(), 12 * 9);
    assert_eq!(v.slice(1, 99).length(), 0);
    let h = v.histogram(16).unwrap();
    let counts = js_sys::Float64Array::from(get(&h, "counts"));
    assert_eq!(counts.length(), 16);
    assert_eq!(counts.to_vec().iter().sum::<f64>(), (10 * 12 * 9) as f64);
    let iso = v.isosurface(0.0, false).unwrap();
    let pos = js_sys::Float32Array::from(get(&iso, "positions"));
    let idx = js_sys::Uint32Array::from(get(&iso, "indices"));
    assert!(pos.length() > 0 && idx.length() % 3 == 0);
    assert!(VolumeView::new(b"NRRD0004\ntype: float\n", Some("x.nrrd".into()), 0).is_err());
    let ph = phantom_volume(24).to_vec();
    let r = read_bytes(&ph, Some("phantom.nii")).unwrap();
    assert_eq!(r.volume.unwrap().volume.dims, [24, 24, 18]);
}

/// A volume read back from a file wraps with the defaults (the auto start takes the exterior of
/// the iso-surface): valid, the torus's genus, and within half a voxel of the analytic surface —
/// in the file's world frame, through the rotated, anisotropic affine. NIfTI and MetaImage.
#[wasm_bindgen_test(unsupported = test)]
fn volumes_wrap_valid_onto_the_analytic_surface() {
    let axis = DVec3::new(0.3, -0.5, 1.0);
    let (big, small) = (9.0, 3.5);
    let tv = torus_volume([30, 40, 24], big, small, axis);
    let tc = centre(tv.dims, &tv.affine);
    let opts = VolumeOptions {
        iso: Some(0.0),
        ..Default::default()
    };
    for (name, bytes) in [
        ("torus.nii", write_nifti(&tv, NiftiOpts::default())),
        ("torus.mha", write_mha(&tv, true, false)),
    ] {
        let target = read_bytes_with(&bytes, Some(name), &opts).unwrap().target;
        let mut ev = lsw::flow::Evolver::new(&target, lsw::flow::WrapSettings::default()).unwrap();
        ev.run(|_| {}).unwrap();
        let (p, t) = (ev.positions(), ev.triangles());
        let c = lsw::metrics::certificate::certify(&p, &t, Some(&target));
        assert!(c.valid && c.genus == Some(1), "{name}: {c:?}");
        let mean = p
            .iter()
            .map(|q| torus_distance(*q, tc, big, small, axis))
            .sum::<f64>()
            / p.len() as f64;
        // The smallest voxel side is 1 mm.
        assert!(mean < 0.5, "{name}: mean distance {mean} mm");
        println!(
            "{name}: {} vertices, mean distance to the analytic torus {mean:.3} mm",
            p.len()
        );
    }
}
