//! The per-vertex scalars of the evolving surface that the app colours by and the writers
//! record: one list, [`ColourMap::ALL`], with each map's name, label, legend text and unit, and
//! [`ColourMap::values`] computing it from an [`Evolver`].

use super::{mcf::mean_curvature, Evolver};
use crate::geometry::operators::CotanLaplacian;
use crate::mesh::HalfedgeMesh;
use serde::{Deserialize, Serialize};

/// A per-vertex scalar of the surface being wrapped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub enum ColourMap {
    /// Distance to the target at each vertex, in target units: the exact one once the wrap is
    /// certified, the field's |d| while it runs.
    Distance,
    /// Mean curvature H (1/r on a sphere of radius r), in 1/target units.
    Curvature,
    /// Mean κ(J_Δ) of the incident faces (1 = equilateral).
    Kappa,
    /// Co-volume (mixed Voronoi area) in the stabilised frame.
    Covolume,
    /// 1 for feature vertices (creases, corners), 0 elsewhere.
    Features,
    /// 1 where a finished wrap is not faithful to the data (far from it, or folded where it
    /// does not turn: the certificate's flagged vertices), 0 elsewhere and while it runs.
    Flagged,
}

/// A colour map as the app lists it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ColourMapInfo {
    /// The map (not serialised: `name` identifies it).
    #[serde(skip)]
    pub map: ColourMap,
    /// Stable name (the wasm facade's `scalar(name)`, the share link's `cmap`).
    pub name: &'static str,
    /// Menu label.
    pub label: &'static str,
    /// Legend title shown next to the colour bar.
    pub legend: &'static str,
    /// Unit of the values ("" when dimensionless).
    pub unit: &'static str,
    /// Name of the per-vertex property when a result is exported (PLY, GLB, VTK), or `None`
    /// when the map is not exported.
    pub export_name: Option<&'static str>,
}

/// Every colour map, in menu order and in the order of [`ColourMap`]'s variants (so
/// `COLOUR_MAPS[map as usize]` is its entry; a unit test checks it).
pub const COLOUR_MAPS: &[ColourMapInfo] = &[
    ColourMapInfo {
        map: ColourMap::Distance,
        name: "distance",
        label: "distance to target",
        legend: "distance to target |d|",
        unit: "target units",
        export_name: Some("distance"),
    },
    ColourMapInfo {
        map: ColourMap::Curvature,
        name: "curvature",
        label: "mean curvature",
        legend: "mean curvature H",
        unit: "1 / target units",
        export_name: Some("mean_curvature"),
    },
    ColourMapInfo {
        map: ColourMap::Kappa,
        name: "kappa",
        label: "κ(J_Δ) quality",
        legend: "κ(J_Δ) (1 = equilateral)",
        unit: "",
        export_name: Some("kappa"),
    },
    ColourMapInfo {
        map: ColourMap::Covolume,
        name: "covolume",
        label: "co-volume",
        legend: "co-volume (stabilised)",
        unit: "stabilised frame",
        export_name: None,
    },
    ColourMapInfo {
        map: ColourMap::Features,
        name: "features",
        label: "feature vertices",
        legend: "feature vertices (1)",
        unit: "",
        export_name: None,
    },
    ColourMapInfo {
        map: ColourMap::Flagged,
        name: "flagged",
        label: "off the data or folded",
        legend: "off the data or folded (1), once done",
        unit: "",
        export_name: None,
    },
];

/// The maps the MCF lesson offers: those that need the mesh alone (no target, no field, no
/// remesher), in menu order.
pub const LESSON_COLOUR_MAPS: [ColourMap; 2] = [ColourMap::Curvature, ColourMap::Kappa];

impl ColourMap {
    /// The map's value at every vertex of a bare `mesh` (mesh units): the
    /// [`LESSON_COLOUR_MAPS`]; `None` for a map that needs a wrap's target or settings.
    pub fn mesh_values(self, mesh: &HalfedgeMesh) -> Option<Vec<f64>> {
        match self {
            ColourMap::Curvature => Some(mean_curvature(mesh)),
            ColourMap::Kappa => Some(crate::metrics::quality::vertex_kappa(mesh)),
            ColourMap::Distance
            | ColourMap::Covolume
            | ColourMap::Features
            | ColourMap::Flagged => None,
        }
    }

    /// The range the legend and the colours span for `values` of this map: an indicator map's
    /// is [0, 1]; another's is robust — its 2nd and 98th percentiles, so a few outliers do not
    /// flatten the rest into one colour, widened where they nearly agree, so a uniform field's
    /// rounding noise is not coloured as a pattern.
    /// Non-finite values are left out; [0, 1] when none is finite.
    pub fn display_range(self, values: &[f64]) -> [f64; 2] {
        if matches!(self, ColourMap::Features | ColourMap::Flagged) {
            return [0.0, 1.0];
        }
        let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        if finite.is_empty() {
            return [0.0, 1.0];
        }
        finite.sort_unstable_by(f64::total_cmp);
        let last = (finite.len() - 1) as f64;
        let mut lo = finite[(0.02 * last).floor() as usize];
        let mut hi = finite[(0.98 * last).ceil() as usize];
        if hi - lo <= 1e-4 * lo.abs().max(hi.abs()) {
            let pad = (0.05 * hi.abs()).max(1e-6);
            lo -= pad;
            hi += pad;
        }
        [lo, hi]
    }

    /// Every colour map, in menu order.
    pub fn all() -> impl Iterator<Item = ColourMap> {
        COLOUR_MAPS.iter().map(|i| i.map)
    }

    /// This map's catalog entry.
    pub fn info(self) -> &'static ColourMapInfo {
        &COLOUR_MAPS[self as usize]
    }

    /// The stable name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The map called `name`, if any.
    pub fn from_name(name: &str) -> Option<ColourMap> {
        COLOUR_MAPS.iter().find(|i| i.name == name).map(|i| i.map)
    }

    /// The map's value at every vertex of the evolver's surface (see the variants for units).
    pub fn values(self, ev: &Evolver) -> Vec<f64> {
        let mesh = ev.mesh();
        match self {
            ColourMap::Distance => ev.vertex_distances(),
            ColourMap::Curvature => mean_curvature(mesh)
                .into_iter()
                .map(|h| h * ev.scale())
                .collect(),
            ColourMap::Kappa => crate::metrics::quality::vertex_kappa(mesh),
            ColourMap::Covolume => CotanLaplacian::new(mesh).covolumes,
            ColourMap::Features => {
                let f =
                    crate::remesh::features::detect(mesh, &ev.settings().tuning.remesh.features);
                f.vertices.into_iter().map(|b| b as u8 as f64).collect()
            }
            // Known from the certificate alone (see `WrapRun::colour`).
            ColourMap::Flagged => vec![0.0; mesh.n_vertices()],
        }
    }
}

/// The per-vertex scalars a written result records: `(export name, values)` of every map with
/// an export name, in menu order.
pub fn export_scalars(ev: &Evolver) -> Vec<(&'static str, Vec<f64>)> {
    export_scalars_with(|map| map.values(ev))
}

/// [`export_scalars`] with each map's values from `values`.
pub fn export_scalars_with(
    mut values: impl FnMut(ColourMap) -> Vec<f64>,
) -> Vec<(&'static str, Vec<f64>)> {
    COLOUR_MAPS
        .iter()
        .filter_map(|i| i.export_name.map(|n| (n, values(i.map))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::WrapSettings;
    use crate::geometry::icosphere::icosphere;
    use crate::target::Target;
    use glam::DVec3;

    #[test]
    fn the_display_range_leaves_outliers_and_noise_out() {
        let mut v: Vec<f64> = (0..100).map(f64::from).collect();
        v.extend([1e9, f64::NAN, f64::INFINITY]);
        let [lo, hi] = ColourMap::Curvature.display_range(&v);
        assert!(
            (0.0..=3.0).contains(&lo) && (90.0..1000.0).contains(&hi),
            "{lo} {hi}"
        );
        // A uniform field is widened by ±5 %, not coloured by its rounding noise.
        let noisy: Vec<f64> = (0..50).map(|i| 1.0 + 1e-6 * f64::from(i % 7)).collect();
        let [lo, hi] = ColourMap::Kappa.display_range(&noisy);
        assert!(
            (lo - 0.95).abs() < 1e-4 && (hi - 1.05).abs() < 1e-4,
            "{lo} {hi}"
        );
        assert_eq!(
            ColourMap::Distance.display_range(&[0.0, 0.0]),
            [-1e-6, 1e-6]
        );
        assert_eq!(ColourMap::Distance.display_range(&[f64::NAN]), [0.0, 1.0]);
        // Indicator maps span 0–1 whatever they hold.
        assert_eq!(ColourMap::Flagged.display_range(&[0.0; 9]), [0.0, 1.0]);
        assert_eq!(ColourMap::Features.display_range(&[1.0; 3]), [0.0, 1.0]);
    }

    #[test]
    fn lesson_maps_are_the_mesh_only_ones() {
        let mesh = icosphere(2, 2.0, DVec3::ZERO).unwrap();
        for m in ColourMap::all() {
            let v = m.mesh_values(&mesh);
            assert_eq!(v.is_some(), LESSON_COLOUR_MAPS.contains(&m), "{}", m.name());
            if let Some(v) = v {
                assert_eq!(v.len(), mesh.n_vertices());
            }
        }
        // H = 1/r on a sphere of radius 2; κ near 1 on the near-equilateral icosphere.
        let h = ColourMap::Curvature.mesh_values(&mesh).unwrap();
        assert!(h.iter().all(|&x| (x - 0.5).abs() < 0.05), "{h:?}");
        let k = ColourMap::Kappa.mesh_values(&mesh).unwrap();
        assert!(k.iter().all(|&x| (1.0..1.3).contains(&x)), "{k:?}");
    }

    #[test]
    fn list_matches_variants_and_names_round_trip() {
        for (i, m) in ColourMap::all().enumerate() {
            assert_eq!(m as usize, i);
            assert_eq!(m.info().map, m);
            assert_eq!(ColourMap::from_name(m.name()), Some(m));
            assert_eq!(serde_json::to_value(m).unwrap(), m.name());
            assert!(!m.info().label.is_empty() && !m.info().legend.is_empty());
        }
        assert_eq!(ColourMap::from_name("none"), None);
    }

    /// On the start surface of a wrap of a sphere's vertices, every map has one finite value per
    /// vertex, and κ is near 1 (the start icosphere is nearly equilateral).
    #[test]
    fn values_have_one_entry_per_vertex() {
        let r = 2.0;
        let cloud = icosphere(3, r, DVec3::ZERO).unwrap().positions().to_vec();
        let target = Target::new(cloud, vec![]).unwrap();
        let settings = {
            let mut w = WrapSettings::default();
            w.stop.steps = 1;
            w
        };
        let ev = Evolver::new(&target, settings).unwrap();
        let n = ev.mesh().n_vertices();
        for m in ColourMap::all() {
            let v = m.values(&ev);
            assert_eq!(v.len(), n, "{}", m.name());
            assert!(v.iter().all(|x| x.is_finite()), "{}", m.name());
        }
        let kappa = ColourMap::Kappa.values(&ev);
        assert!(kappa.iter().all(|&k| (1.0..1.5).contains(&k)));
        let names: Vec<_> = export_scalars(&ev).into_iter().map(|(n, _)| n).collect();
        assert_eq!(names, ["distance", "mean_curvature", "kappa"]);
    }
}
