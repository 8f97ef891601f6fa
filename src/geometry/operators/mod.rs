//! Discrete differential operators on triangle meshes, shared by the flow, the remesher and the
//! metrics: the cotangent Laplacian with its co-volumes, vertex normals and principal curvatures.
//! One home, so that every stage measures the surface the same way.

pub mod curvature;
pub mod laplacian;
pub mod normals;

pub use laplacian::{CotanLaplacian, COT_CLAMP};
