//! Isosurface extraction (placeholder, filled in below).
