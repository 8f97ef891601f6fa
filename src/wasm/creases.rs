//! A cloud's crease detection in a helper worker: the session hands out the job
//! ([`WrapSession::crease_job`]), [`cloud_creases`] runs it in another wasm instance while the
//! steps go on, and [`WrapSession::set_creases`] brings the result back before the final fit,
//! which otherwise finds them itself (the same creases either way, but then on the wrap's own
//! thread).

use super::errors::UiError;
use super::session::WrapSession;
use crate::flow::CreaseJob;
use crate::geometry::creases::Creases;
use glam::DVec3;
use js_sys::Float64Array;
use wasm_bindgen::prelude::*;

/// Numbers before the lists in a job: the fit radius, the crease angle and the point count.
const JOB_HEAD: usize = 3;

/// Points per slice copied between a job's array and wasm memory.
const SLICE: usize = 4096;

/// The most points handed to a helper. It holds the points about three times (as sent, in
/// input order, in its grid) on a core that the page and the steps may share: beyond this the
/// helper costs more time and memory than it saves. A larger cloud's creases are left to the
/// fit.
pub const HELPER_MAX_POINTS: usize = 1_500_000;

/// `x` as an index or count below `limit`, if it is a whole number in range.
fn whole_below(x: f64, limit: f64) -> Option<usize> {
    (x >= 0.0 && x.fract() == 0.0 && x < limit).then_some(x as usize)
}

fn bad_job(what: &str) -> JsValue {
    UiError::bad_parameter(
        format!("crease job: {what}"),
        "Pass what WrapSession.creaseJob returned.",
    )
    .into()
}

/// The creases of a job from [`WrapSession::crease_job`], as [`WrapSession::set_creases`]
/// takes them.
#[wasm_bindgen(js_name = cloudCreases)]
pub fn cloud_creases(job: &Float64Array) -> Result<Float64Array, JsValue> {
    let len = job.length() as usize;
    let head: Vec<f64> = (0..JOB_HEAD.min(len))
        .map(|k| job.get_index(k as u32))
        .collect();
    let [radius, angle, n] = head[..] else {
        return Err(bad_job("too short"));
    };
    let n = whole_below(n, len as f64)
        .filter(|&n| len == JOB_HEAD + 4 * n)
        .ok_or_else(|| bad_job("not a radius, an angle, a count and its lists"))?;
    // Straight into vectors, a slice at a time: the whole array copied into wasm memory first
    // would be one more copy of the points in the helper.
    let mut points = Vec::with_capacity(n);
    let mut order = Vec::with_capacity(n);
    let mut buf = vec![0.0; 3 * SLICE];
    for first in (0..n).step_by(SLICE) {
        let m = SLICE.min(n - first);
        let at = (JOB_HEAD + 3 * first) as u32;
        job.subarray(at, at + 3 * m as u32)
            .copy_to(&mut buf[..3 * m]);
        points.extend(buf[..3 * m].chunks_exact(3).map(DVec3::from_slice));
        let at = (JOB_HEAD + 3 * n + first) as u32;
        job.subarray(at, at + m as u32).copy_to(&mut buf[..m]);
        let index = |x: f64| whole_below(x, n as f64).map_or(u32::MAX, |i| i as u32);
        order.extend(buf[..m].iter().map(|&x| index(x)));
    }
    let finite = radius > 0.0 && radius.is_finite() && angle.is_finite();
    if !(finite && points.iter().all(|p| p.is_finite())) {
        return Err(bad_job("a number that is not finite"));
    }
    let job = CreaseJob::from_cell_order(points, &order, radius, angle)
        .ok_or_else(|| bad_job("the order does not number the points"))?;
    let creases = job
        .run(&mut |_| {})
        .unwrap_or_else(|| Creases::new(vec![], vec![]));
    Ok(Float64Array::from(creases.to_flat().as_slice()))
}

#[wasm_bindgen]
impl WrapSession {
    /// The session's crease detection as plain numbers for [`cloud_creases`] in a helper worker:
    /// the fit radius, the crease angle, the point count n, the points (stabilised frame) in
    /// the fit grid's cell order (3n), and each one's index in the target (n). Undefined when
    /// there is none to do (a mesh, a volume, no final fit, more than [`HELPER_MAX_POINTS`]
    /// points, or the fit has found them already).
    #[wasm_bindgen(js_name = creaseJob)]
    pub fn crease_job(&self) -> Option<Float64Array> {
        let job = self.run.evolver().crease_job()?;
        let (points, order) = job.cell_order();
        let n = points.len();
        if n > HELPER_MAX_POINTS {
            return None;
        }
        // Filled a slice at a time (not from one vector of all the numbers, which would grow
        // this instance's memory for good).
        let out = Float64Array::new_with_length((JOB_HEAD + 4 * n) as u32);
        for (k, x) in [job.radius, job.angle, n as f64].into_iter().enumerate() {
            out.set_index(k as u32, x);
        }
        for (k, chunk) in points.chunks(SLICE).enumerate() {
            let flat: Vec<f64> = chunk.iter().flat_map(|p| p.to_array()).collect();
            let at = JOB_HEAD + 3 * SLICE * k;
            out.set(&Float64Array::from(flat.as_slice()), at as u32);
        }
        for (k, chunk) in order.chunks(SLICE).enumerate() {
            let flat: Vec<f64> = chunk.iter().map(|&i| i as f64).collect();
            let at = JOB_HEAD + 3 * n + SLICE * k;
            out.set(&Float64Array::from(flat.as_slice()), at as u32);
        }
        Some(out)
    }

    /// Takes [`cloud_creases`]'s result for the final fit; false when it came too late (the fit
    /// found them itself) or none was asked for.
    #[wasm_bindgen(js_name = setCreases)]
    pub fn set_creases(&mut self, flat: &[f64]) -> Result<bool, JsValue> {
        let creases =
            Creases::from_flat(flat).ok_or_else(|| bad_job("not creases from cloudCreases"))?;
        Ok(self
            .run
            .evolver_mut()
            .supply_creases((!creases.is_empty()).then_some(creases)))
    }
}
