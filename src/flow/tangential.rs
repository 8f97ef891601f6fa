//! Tangential redistribution (docs/method.md §6.3, the intended cyclic formula): moves vertices
//! within the surface towards the bisectors of narrow wedges, which evens out angles and
//! co-volumes without changing the shape.

use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// `v_T = u − (u·N)N`, `u = (weight/m)·Σ_k (1 + ê_k·ê_{k+1})(e_k + e_{k+1})` over the one-ring
/// spokes `e_k = F_{w_k} − F_i` in rotational order (indices cyclic). `weight` is ω·ε_i.
/// Zero on a perfectly symmetric star.
pub fn tangential_velocity(mesh: &HalfedgeMesh, v: u32, normal: DVec3, weight: f64) -> DVec3 {
    if weight <= 0.0 {
        return DVec3::ZERO;
    }
    let p = mesh.position(v);
    let mut first: Option<(DVec3, DVec3)> = None;
    let mut prev: Option<(DVec3, DVec3)> = None;
    let mut u = DVec3::ZERO;
    let mut m = 0usize;
    let term = |(e0, h0): (DVec3, DVec3), (e1, h1): (DVec3, DVec3)| (1.0 + h0.dot(h1)) * (e0 + e1);
    for w in mesh.neighbors(v) {
        let e = mesh.position(w) - p;
        let cur = (e, e.normalize_or_zero());
        if let Some(pr) = prev {
            u += term(pr, cur);
        } else {
            first = Some(cur);
        }
        prev = Some(cur);
        m += 1;
    }
    if let (Some(last), Some(f)) = (prev, first) {
        u += term(last, f);
    }
    if m == 0 {
        return DVec3::ZERO;
    }
    u *= weight / m as f64;
    u - u.dot(normal) * normal
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_on_regular_star_and_pulls_into_narrow_wedges() {
        let star = |angles: &[f64]| {
            let mut p = vec![DVec3::ZERO];
            p.extend(
                angles
                    .iter()
                    .map(|a| DVec3::new(crate::fmath::cos(*a), crate::fmath::sin(*a), 0.0)),
            );
            let n = angles.len() as u32;
            let faces: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
            HalfedgeMesh::from_triangles(p, &faces).unwrap()
        };
        let regular: Vec<f64> = (0..6)
            .map(|k| k as f64 * std::f64::consts::TAU / 6.0)
            .collect();
        let m = star(&regular);
        assert!(tangential_velocity(&m, 0, DVec3::Z, 1.0).length() < 1e-14);
        // Squeeze two spokes together near +x: the vertex is pulled towards them (into the
        // narrow wedge's bisector), i.e. towards +x.
        let mut squeezed = regular.clone();
        squeezed[1] = 0.3;
        squeezed[5] = -0.3;
        let m = star(&squeezed);
        let v = tangential_velocity(&m, 0, DVec3::Z, 1.0);
        assert!(v.x > 0.05 && v.z.abs() < 1e-14, "{v:?}");
    }
}
