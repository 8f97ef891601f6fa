//! Feature detection, re-derived (docs/method.md §8.2, §13.8; project decision 4).
//!
//! The reference's mean-curvature test marks a vertex when `γ = 4·l̄·H < γ_crit`, which selects
//! flat and concave vertices (every vertex of a sphere) and then locks them against remeshing;
//! its features also accumulate forever. Here a feature is what the word means — a sharp convex
//! crease or corner — and the detection is redone from scratch on every call:
//!
//! * **Mean-curvature angle** (scale-invariant): `γ = 2·l̄·H = l̄·(κ_min + κ_max)` (the paper's
//!   formula; l̄ the mean incident edge length, so γ is the turning angle across one edge).
//!   A vertex is a feature when `γ > γ_crit`, i.e. strongly *convex* relative to the local edge
//!   length. Flat (γ ≈ 0) and concave (γ < 0) vertices are never marked. Excluded as in the
//!   reference: convex-dominant saddles (`κ_min·κ_max < 0` and `|κ_max| < K·|κ_min|`), and
//!   vertices of valence above `max_valence`.
//! * **Dihedral angle**: an interior edge is a feature edge when the angle between its two face
//!   normals exceeds `dihedral_angle` and the edge is convex (concave creases only with
//!   `include_concave_edges`); its ends become feature vertices. Only this detector marks edges,
//!   so only it lets the remesher slide vertices along feature lines.

use crate::geometry::operators::curvature::Curvatures;
use crate::mesh::{HalfedgeMesh, INVALID};
use serde::{Deserialize, Serialize};

/// Which detector runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureDetector {
    /// No features (as in the reference's experiments).
    #[default]
    Off,
    /// Mean-curvature-angle test on vertices only (every feature vertex is locked).
    MeanCurvature,
    /// Dihedral-angle test on edges (feature lines; their vertices slide along them).
    DihedralAngle,
    /// Union of both.
    Both,
}

/// Settings of the feature detection.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FeatureSettings {
    /// Which detector runs. Default [`FeatureDetector::Off`].
    pub detector: FeatureDetector,
    /// γ_crit in radians: a vertex is a feature when its mean-curvature angle
    /// `γ = l̄·(κ_min + κ_max)` exceeds it. Range (0, π]; default π/2 (a crease turning by
    /// roughly 80° or more across one edge).
    pub critical_mean_curvature_angle: f64,
    /// K ≥ 1: saddles with `|κ_max| < K·|κ_min|` are never features. Default 3.2 (the reference's
    /// point-cloud value).
    pub principal_curvature_factor: f64,
    /// Vertices of higher valence are never mean-curvature features (the reference's "m > 6"
    /// rule). Default 6.
    pub max_valence: u32,
    /// Dihedral threshold in radians: an edge is a feature when its face normals differ by more
    /// than this. Range (0, π); default 60° = π/3.
    pub dihedral_angle: f64,
    /// Also mark concave creases as feature edges. Default false (decision 4: no concave
    /// features).
    pub include_concave_edges: bool,
}

impl Default for FeatureSettings {
    fn default() -> Self {
        Self {
            detector: FeatureDetector::Off,
            critical_mean_curvature_angle: std::f64::consts::FRAC_PI_2,
            principal_curvature_factor: 3.2,
            max_valence: 6,
            dihedral_angle: std::f64::consts::FRAC_PI_3,
            include_concave_edges: false,
        }
    }
}

/// Detected features: per-vertex and per-edge flags (indexed like the mesh).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Features {
    /// Feature vertices.
    pub vertices: Vec<bool>,
    /// Feature edges (only the dihedral detector sets them).
    pub edges: Vec<bool>,
    /// Vertices the remesher must not move whatever their feature edges (the target's corners,
    /// placed by the final fit). Empty: none.
    pub pinned: Vec<bool>,
    /// Vertices the remesher leaves as they are, with their edges: not moved, and no edge at one
    /// of them split, collapsed or flipped (a region where a remesh made faces intersect, tried
    /// again without it). Empty: none.
    pub frozen: Vec<bool>,
}

impl Features {
    /// No features on a mesh of this size.
    pub fn none(mesh: &HalfedgeMesh) -> Self {
        Self {
            vertices: vec![false; mesh.n_vertices()],
            edges: vec![false; mesh.n_edges()],
            pinned: Vec::new(),
            frozen: Vec::new(),
        }
    }
    /// Number of feature vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.iter().filter(|&&b| b).count()
    }
    /// Number of feature edges.
    pub fn n_edges(&self) -> usize {
        self.edges.iter().filter(|&&b| b).count()
    }
}

/// The mean-curvature angle `γ = l̄·(κ_min + κ_max)` of vertex `v` (radians, convex > 0).
pub fn mean_curvature_angle(mesh: &HalfedgeMesh, curv: &Curvatures, v: u32) -> f64 {
    mesh.mean_edge_length(v) * (curv.kmin[v as usize] + curv.kmax[v as usize])
}

/// Runs the configured detector on `mesh` (garbage-free), given its curvatures.
pub fn detect_features(
    mesh: &HalfedgeMesh,
    curv: &Curvatures,
    settings: &FeatureSettings,
) -> Features {
    let mut out = Features::none(mesh);
    let (mc, dh) = match settings.detector {
        FeatureDetector::Off => (false, false),
        FeatureDetector::MeanCurvature => (true, false),
        FeatureDetector::DihedralAngle => (false, true),
        FeatureDetector::Both => (true, true),
    };
    if mc {
        for v in 0..mesh.n_vertices() as u32 {
            let (k1, k2) = (curv.kmin[v as usize], curv.kmax[v as usize]);
            let saddle = k1 * k2 < 0.0;
            let balanced = k2.abs() < settings.principal_curvature_factor * k1.abs();
            if saddle && balanced {
                continue;
            }
            if mesh.valence(v) > settings.max_valence as usize {
                continue;
            }
            if mean_curvature_angle(mesh, curv, v) > settings.critical_mean_curvature_angle {
                out.vertices[v as usize] = true;
            }
        }
    }
    if dh {
        for e in 0..mesh.n_edges() as u32 {
            if mesh.face(2 * e) == INVALID || mesh.face(2 * e + 1) == INVALID {
                continue;
            }
            let beta = curv.dihedral[e as usize];
            let sharp = if settings.include_concave_edges {
                beta.abs()
            } else {
                beta
            };
            if sharp > settings.dihedral_angle {
                out.edges[e as usize] = true;
                out.vertices[mesh.to(2 * e) as usize] = true;
                out.vertices[mesh.to(2 * e + 1) as usize] = true;
            }
        }
    }
    out
}

/// Convenience: curvatures (one smoothing pass) and features in one call.
pub fn detect(mesh: &HalfedgeMesh, settings: &FeatureSettings) -> Features {
    let curv = crate::geometry::operators::curvature::principal_curvatures(mesh, None, 1);
    detect_features(mesh, &curv, settings)
}
