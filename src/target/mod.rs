//! The thing to wrap: a point cloud, a triangle soup/mesh, or a volume's iso-surface, as read
//! from a file; its construction and cleaning here, and what each kind answers to the pipeline
//! in its oracle ([`Target::oracle`]): nothing outside this module branches on the kind.

mod cloud;
mod iso_surface;
pub mod oracle;
mod soup;

use crate::geometry::aabb::Aabb;
use glam::DVec3;
pub use oracle::{CreaseSource, Surface, TargetKind, TargetOracle};

/// A target for wrapping: points plus optional triangles indexing them.
///
/// Invariants (checked by [`Target::new`]): every coordinate is finite and every triangle index is
/// in range.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// Vertex positions (for a point cloud: the points).
    pub points: Vec<DVec3>,
    /// Triangles as vertex-index triples; empty for a point cloud.
    pub triangles: Vec<[u32; 3]>,
    /// Axis-aligned bounding box of `points`.
    pub bbox: Aabb,
    /// The triangles are a voxel volume's iso-surface (see [`Target::iso_surface`]): their
    /// angles and genus are the sampling's, not the object's. Ask [`Target::oracle`] what that
    /// means rather than reading it.
    pub sampled: bool,
}

/// Why a [`Target`] could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TargetError {
    /// The input has no points at all. Fix: give a file with at least one vertex.
    #[error("the target is empty: it has no points")]
    Empty,
    /// A coordinate is NaN or infinite. Fix: clean the input; the index names the first bad point.
    #[error("point {index} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        index: usize,
        x: f64,
        y: f64,
        z: f64,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {vertex}, but there are only {count} vertices")]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    /// Fewer than four distinct points: nothing with a volume can be wrapped around them. Fix:
    /// give a scan of a solid object.
    #[error("the target has only {distinct} distinct point(s) ({total} in all); a wrap needs at least 4 that are not coplanar")]
    TooFewPoints { distinct: usize, total: usize },
    /// A point cloud of fewer than [`MIN_CLOUD_POINTS`] distinct points: too few to outline a
    /// surface. Fix: give a denser scan (a mesh of few vertices is fine).
    #[error("the point cloud has only {distinct} distinct points ({total} in all); a cloud needs at least {least} to outline a surface")]
    SparseCloud {
        distinct: usize,
        total: usize,
        least: usize,
    },
    /// Every point lies on one line (to 1e-9 of the target's size).
    #[error("all {count} points lie on one line; a wrap needs a 3-D shape")]
    Collinear { count: usize },
    /// Every point lies in one plane (to 1e-9 of the target's size). Fix: a thin but real object
    /// (a plate with some thickness) is fine; an exactly flat one has no inside to wrap.
    #[error("all {count} points lie in one plane (thickness {thickness:.1e} of a size {size:.3e}); a wrap needs a 3-D shape")]
    Coplanar {
        count: usize,
        thickness: f64,
        size: f64,
    },
    /// The target lies so far from the origin, for its size, that 32-bit coordinates (what every
    /// output format stores, and what the wrap is checked with) cannot resolve it: the wrap's
    /// vertices would collapse onto a few representable positions, and every face would meet
    /// every other. Fix: move it near the origin.
    #[error("the target lies {distance:.3e} from the origin but is only {size:.3e} across: 32-bit output coordinates cannot resolve it (steps of {step:.1e}); move it near the origin")]
    FarFromOrigin { distance: f64, size: f64, step: f64 },
    /// A mesh whose triangles all have zero area.
    #[error("all {faces} triangles of the mesh have zero area")]
    ZeroArea { faces: usize },
    /// A volume's level set {v = iso} is empty: the iso-value lies outside the values (or the
    /// volume has fewer than two distinct values, so no default iso-value exists). Fix: choose
    /// an iso-value strictly between the minimum and the maximum.
    #[error("the iso-surface at {iso} is empty: the volume's values span [{min}, {max}]")]
    NoIsosurface { iso: f64, min: f64, max: f64 },
}

/// The largest f32 step at a target's coordinates, as a fraction of its diagonal, that a wrap
/// accepts (a target up to about 840 diagonals from the origin).
pub const MOST_F32_STEP: f64 = 1e-4;

/// The fewest distinct points a point cloud may have (see [`TargetError::SparseCloud`]).
pub const MIN_CLOUD_POINTS: usize = 20;

/// The largest share of a cloud [`Target::without_isolated_points`] leaves out.
pub const MOST_ISOLATED: f64 = 0.1;

impl Target {
    /// What this target's kind answers to the pipeline's questions.
    pub fn oracle(&self) -> Box<dyn TargetOracle<'_> + '_> {
        let (points, triangles) = (&self.points[..], &self.triangles[..]);
        let mesh = soup::Soup { points, triangles };
        match (triangles.is_empty(), self.sampled) {
            (true, _) => Box::new(cloud::Cloud { points }),
            (false, false) => Box::new(mesh),
            (false, true) => Box::new(iso_surface::IsoSurface { mesh }),
        }
    }

    /// Genus and components of a target of one closed manifold part, whose genus a wrap must
    /// keep (the certificate's `target_genus`, the start's and the surgery's checks); None for
    /// clouds, open or non-manifold meshes, and meshes of several parts.
    pub fn one_closed_part(&self) -> Option<crate::mesh::MeshReport> {
        self.oracle().topology().filter(|t| t.components == 1)
    }

    /// The target of a sampled iso-surface (a voxel volume's, see `Target::from_volume`),
    /// checked as [`Target::new`] checks.
    pub fn iso_surface(points: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self, TargetError> {
        let target = Self::new(points, triangles)?;
        Ok(Self {
            sampled: true,
            ..target
        })
    }

    /// Builds a target, checking that coordinates are finite and indices in range.
    pub fn new(points: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self, TargetError> {
        if points.is_empty() {
            return Err(TargetError::Empty);
        }
        if let Some((index, p)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(TargetError::NonFinite {
                index,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        let count = points.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= count) {
                return Err(TargetError::IndexOutOfRange {
                    triangle: t,
                    vertex: v,
                    count,
                });
            }
        }
        let bbox = Aabb::from_points(&points);
        Ok(Self {
            points,
            triangles,
            bbox,
            sampled: false,
        })
    }

    /// This mesh with its indices mended (see [`crate::mesh::repair`]): coincident corners
    /// merged, repeated faces dropped, faces wound consistently and outwards; and what changed.
    /// Itself, with None, where nothing needs or allows mending (every cloud).
    pub fn repaired(self) -> (Target, Option<crate::mesh::Repairs>) {
        match crate::mesh::repair::repair(&self.points, &self.triangles) {
            Some((points, triangles, repairs)) => {
                let bbox = Aabb::from_points(&points);
                let target = Target {
                    points,
                    triangles,
                    bbox,
                    sampled: self.sampled,
                };
                (target, Some(repairs))
            }
            None => (self, None),
        }
    }

    /// This cloud without its isolated points (see [`crate::geometry::spatial::isolated`]) at a
    /// radius of `spacings` median spacings, and how many were left out; None when there are
    /// none, for meshes, for `spacings` = 0, and when more than [`MOST_ISOLATED`] of the points
    /// would go (then the cloud is sparse in places, not strewn with strays).
    pub fn without_isolated_points(&self, spacings: f64) -> Option<(Target, usize)> {
        let oracle = self.oracle();
        if !oracle.removes_strays() || spacings.is_nan() || spacings <= 0.0 {
            return None;
        }
        let spacing = oracle.spacing()?;
        let isolated =
            crate::geometry::spatial::isolated::stray_points(&self.points, spacings * spacing);
        let removed = isolated.iter().filter(|&&i| i).count();
        if removed == 0 || removed as f64 > MOST_ISOLATED * self.points.len() as f64 {
            return None;
        }
        let kept: Vec<DVec3> = self
            .points
            .iter()
            .zip(&isolated)
            .filter(|(_, &i)| !i)
            .map(|(&p, _)| p)
            .collect();
        Target::new(kept, vec![]).ok().map(|t| (t, removed))
    }

    /// This mesh without its specks at grid cell `cell` (small closed parts floating apart, see
    /// [`crate::geometry::specks`]), and how many there were; None when there are none, and for
    /// clouds.
    pub fn without_specks(&self, cell: f64) -> Option<(Target, usize)> {
        let (speck, count) =
            crate::geometry::specks::speck_triangles(&self.points, &self.triangles, cell)?;
        let mut index = vec![u32::MAX; self.points.len()];
        let mut points = Vec::new();
        let triangles: Vec<[u32; 3]> = (self.triangles.iter().zip(&speck))
            .filter(|(_, &s)| !s)
            .map(|(t, _)| {
                t.map(|v| {
                    if index[v as usize] == u32::MAX {
                        index[v as usize] = points.len() as u32;
                        points.push(self.points[v as usize]);
                    }
                    index[v as usize]
                })
            })
            .collect();
        let mut kept = Target::new(points, triangles).ok()?;
        kept.sampled = self.sampled;
        Some((kept, count))
    }

    /// Refuses targets no wrap can make sense of, before any work: fewer than 4 distinct points,
    /// all points on a line or in a plane (relative tolerance 1e-9 of the diagonal, taken
    /// along the principal axes so a tilted plane counts too), a target so far from the origin for
    /// its size that 32-bit coordinates cannot resolve it, a mesh of zero total area.
    pub fn check_wrappable(&self) -> Result<(), TargetError> {
        let total = self.points.len();
        // Four distinct points are enough to go on, a cloud's [`MIN_CLOUD_POINTS`] (and below
        // that, these are all of them): no sort of every point.
        let enough = match self.triangles.is_empty() {
            true => MIN_CLOUD_POINTS,
            false => 4,
        };
        let mut distinct_keys: Vec<[u64; 3]> = Vec::with_capacity(enough);
        for p in &self.points {
            let key = crate::mesh::repair::position_key(*p);
            if !distinct_keys.contains(&key) {
                distinct_keys.push(key);
                if distinct_keys.len() == enough {
                    break;
                }
            }
        }
        let distinct = distinct_keys.len();
        if distinct < 4 {
            return Err(TargetError::TooFewPoints { distinct, total });
        }
        let size = self.bbox.diagonal();
        let c = self.points.iter().fold(DVec3::ZERO, |a, &p| a + p) / total as f64;
        let mut cov = nalgebra::Matrix3::<f64>::zeros();
        for p in &self.points {
            let d = nalgebra::Vector3::new(p.x - c.x, p.y - c.y, p.z - c.z);
            cov += d * d.transpose();
        }
        let eig = nalgebra::SymmetricEigen::new(cov);
        let mut axes: Vec<(f64, DVec3)> = (0..3)
            .map(|k| {
                let v = eig.eigenvectors.column(k);
                (eig.eigenvalues[k], DVec3::new(v[0], v[1], v[2]).normalize())
            })
            .collect();
        axes.sort_by(|a, b| a.0.total_cmp(&b.0));
        let extent = |n: DVec3| {
            self.points
                .iter()
                .map(|&p| (p - c).dot(n).abs())
                .fold(0.0, f64::max)
        };
        let tol = 1e-9 * size;
        let thickness = extent(axes[0].1);
        if thickness <= tol {
            if extent(axes[1].1) <= tol {
                return Err(TargetError::Collinear { count: total });
            }
            return Err(TargetError::Coplanar {
                count: total,
                thickness,
                size,
            });
        }
        // One f32 step at the farthest coordinate must stay a small fraction of the target's size.
        let distance = self.bbox.min.abs().max(self.bbox.max.abs()).max_element();
        let step = distance * f64::from(f32::EPSILON);
        if step > MOST_F32_STEP * size {
            return Err(TargetError::FarFromOrigin {
                distance,
                size,
                step,
            });
        }
        // A handful of points outlines no surface: wraps of so few points run for minutes
        // (rolled back over and over), diverge, or end as a blob of far too many vertices.
        if distinct < enough {
            return Err(TargetError::SparseCloud {
                distinct,
                total,
                least: MIN_CLOUD_POINTS,
            });
        }
        if !self.triangles.is_empty() {
            let area: f64 = self
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| self.points[v as usize]);
                    (b - a).cross(c - a).length()
                })
                .sum();
            if area <= 1e-18 * size * size {
                return Err(TargetError::ZeroArea {
                    faces: self.triangles.len(),
                });
            }
        }
        Ok(())
    }

    /// Points or mesh.
    pub fn kind(&self) -> TargetKind {
        self.oracle().kind()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_empty_nan_and_bad_index() {
        assert_eq!(Target::new(vec![], vec![]), Err(TargetError::Empty));
        let nan = vec![DVec3::ZERO, DVec3::new(0.0, f64::NAN, 0.0)];
        assert!(matches!(
            Target::new(nan, vec![]),
            Err(TargetError::NonFinite { index: 1, .. })
        ));
        let pts = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(matches!(
            Target::new(pts.clone(), vec![[0, 1, 3]]),
            Err(TargetError::IndexOutOfRange {
                triangle: 0,
                vertex: 3,
                count: 3
            })
        ));
        let t = Target::new(pts, vec![[0, 1, 2]]).unwrap();
        assert_eq!(t.kind(), TargetKind::Mesh);
        assert_eq!(t.bbox.max, DVec3::new(1.0, 1.0, 0.0));
    }

    /// A unit cube's corners 100 from the origin wrap (f32 steps of 1.2e-5); 1e5 away (steps of
    /// 0.012, 0.7 % of the diagonal) they are refused, on either side of the origin.
    #[test]
    fn a_target_too_far_from_the_origin_for_its_size_is_refused() {
        let cube = |offset: DVec3| {
            let pts = (0..8)
                .map(|i| offset + DVec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64))
                .collect();
            // (As a mesh: 8 points are too few for a cloud.)
            Target::new(pts, vec![[0, 1, 2], [4, 5, 6]])
                .unwrap()
                .check_wrappable()
        };
        assert_eq!(cube(DVec3::splat(100.0)), Ok(()));
        for offset in [DVec3::new(1e5, 0.0, 0.0), DVec3::new(0.0, 0.0, -1e5)] {
            match cube(offset) {
                Err(TargetError::FarFromOrigin { distance, step, .. }) => {
                    assert!(
                        distance >= 1e5 && step > 1e-4 * 3f64.sqrt(),
                        "{distance} {step}"
                    )
                }
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn degenerate_targets_are_refused_by_name() {
        let check = |pts: Vec<DVec3>, tris: Vec<[u32; 3]>| {
            Target::new(pts, tris).unwrap().check_wrappable()
        };
        // Three points, one point repeated, four coplanar points on a tilted plane, a line.
        assert!(matches!(
            check(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![]),
            Err(TargetError::TooFewPoints { distinct: 3, .. })
        ));
        assert!(matches!(
            check(vec![DVec3::ONE; 100], vec![]),
            Err(TargetError::TooFewPoints {
                distinct: 1,
                total: 100
            })
        ));
        let tilt = |x: f64, y: f64| DVec3::new(x, y, 0.3 * x - 0.7 * y + 2.0);
        let plane: Vec<DVec3> = (0..50)
            .map(|i| tilt((i % 7) as f64, (i / 7) as f64))
            .collect();
        let e = check(plane, vec![]).unwrap_err();
        assert!(matches!(e, TargetError::Coplanar { .. }), "{e}");
        assert!(e.to_string().contains("one plane"));
        let line: Vec<DVec3> = (0..20).map(|i| DVec3::splat(i as f64)).collect();
        assert!(matches!(
            check(line, vec![]),
            Err(TargetError::Collinear { .. })
        ));
        // A thin but real plate (1 % thick) passes; so does a tetrahedron.
        let plate: Vec<DVec3> = (0..200)
            .map(|i| {
                DVec3::new(
                    (i % 10) as f64,
                    (i / 20) as f64,
                    0.1 * ((i / 10) % 2) as f64,
                )
            })
            .collect();
        assert_eq!(check(plate, vec![]), Ok(()));
        // Eight corners of a cube as a cloud: too few (the same as a mesh is fine).
        let corners: Vec<DVec3> = (0..8)
            .map(|k| DVec3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64))
            .collect();
        let e = check(corners.repeat(3), vec![]).unwrap_err();
        assert_eq!(
            e,
            TargetError::SparseCloud {
                distinct: 8,
                total: 24,
                least: MIN_CLOUD_POINTS
            }
        );
        assert!(e.to_string().contains("at least 20"), "{e}");
        assert_eq!(check(corners, vec![[0, 1, 2], [4, 5, 6]]), Ok(()));
        let tet = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        assert_eq!(check(tet.clone(), vec![[0, 1, 2]]), Ok(()));
        // Zero-area mesh: every triangle repeats a vertex position.
        assert!(matches!(
            check(tet, vec![[0, 0, 1], [2, 2, 3]]),
            Err(TargetError::ZeroArea { faces: 2 })
        ));
    }

    /// Each kind answers through its own oracle: a cloud by its points, a mesh by its faces, an
    /// iso-surface as a mesh but for what its sampling makes of angles, genus and extra passes.
    #[test]
    fn each_kind_answers_through_its_oracle() {
        let tet = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let faces = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let mesh = Target::new(tet.clone(), faces.clone()).unwrap();
        let iso = Target::iso_surface(tet, faces).unwrap();
        let grid = (0..27).map(|i| DVec3::new((i % 3) as f64, (i / 3 % 3) as f64, (i / 9) as f64));
        let cloud = Target::new(grid.collect(), vec![]).unwrap();
        let (c, m, v) = (cloud.oracle(), mesh.oracle(), iso.oracle());
        assert!(matches!(c.surface(), Surface::Points(p) if p.len() == 27));
        assert!(
            matches!(v.surface(), Surface::Triangles { triangles, .. } if triangles.len() == 4)
        );
        assert_eq!(
            (c.kind(), m.kind(), v.kind()),
            (TargetKind::Points, TargetKind::Mesh, TargetKind::Mesh)
        );
        assert_eq!(
            (c.has_inside(), m.has_inside(), v.has_inside()),
            (false, true, true)
        );
        assert_eq!((c.spacing(), m.spacing()), (Some(1.0), None));
        assert_eq!(m.topology().map(|t| (t.genus, t.components)), Some((0, 1)));
        assert_eq!(v.topology(), m.topology());
        assert!(c.topology().is_none() && m.start_keeps_genus() && !v.start_keeps_genus());
        assert!(c.removes_strays() && !m.removes_strays() && m.removes_specks());
        assert!(m.second_pass_pays() && !v.second_pass_pays() && !v.refine_passes_help());
    }

    /// A volume's iso-surface is sampled: no creases on it, while a mesh of the same triangles
    /// has them at its edges and a cloud of the same points where plane fits meet.
    #[test]
    fn a_volume_target_has_no_creases() {
        let volume = crate::demo::phantom::phantom_volume(24);
        let t = Target::from_volume(&volume, 130.0, crate::io::volume::Inside::Bright).unwrap();
        assert_eq!(t.oracle().creases(), None);
        let mesh = Target::new(t.points.clone(), t.triangles.clone()).unwrap();
        assert_eq!(mesh.oracle().creases(), Some(CreaseSource::Dihedral));
        let cloud = Target::new(t.points, vec![]).unwrap();
        assert_eq!(cloud.oracle().creases(), Some(CreaseSource::PlaneFits));
    }
}
