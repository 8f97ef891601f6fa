//! Spatial indices over points and triangles, used by the field, the flow, the remesher and the
//! metrics alike.

pub mod box_grid;
pub mod bvh;
pub mod isolated;
pub mod local_spacing;
pub mod parts;
pub mod point_grid;
pub mod radix;
pub mod spacing;
pub mod surface_spacing;
