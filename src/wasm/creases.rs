//! A cloud's crease detection in a helper worker: the session hands out the job
//! ([`WrapSession::crease_job`]), [`cloud_creases`] runs it in another wasm instance while the
//! steps go on, and [`WrapSession::set_creases`] brings the result back before the final fit,
//! which otherwise finds them itself (the same creases either way; 1 M points: 0.7 s of the
//! browser's one thread).

use super::errors::UiError;
use super::session::WrapSession;
use crate::flow::CreaseJob;
use crate::geometry::creases::Creases;
use glam::DVec3;
use js_sys::Float64Array;
use wasm_bindgen::prelude::*;

/// Numbers before the points in a job: the fit radius and the crease angle.
const JOB_HEAD: usize = 2;

/// The most points handed to a helper. Its wasm instance holds the points twice (as given and
/// in its grid): 1 M points took the tab from 533 to 645 MB for 0.3 s less; a larger cloud's
/// creases are left to the fit, where they cost no memory beyond the fit's own.
pub const HELPER_MAX_POINTS: usize = 2_000_000;

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
    let n = job.length() as usize;
    if n < JOB_HEAD || (n - JOB_HEAD) % 3 != 0 {
        return Err(bad_job("not a radius, an angle and a list of points"));
    }
    // The points straight into their vector, a slice at a time: a million points' numbers
    // copied whole into wasm memory first would be 24 MB more in the helper.
    let mut points = Vec::with_capacity((n - JOB_HEAD) / 3);
    let mut buf = vec![0.0; 3 * 4096];
    let mut at = JOB_HEAD;
    while at < n {
        let len = buf.len().min(n - at);
        job.subarray(at as u32, (at + len) as u32)
            .copy_to(&mut buf[..len]);
        points.extend(buf[..len].chunks_exact(3).map(DVec3::from_slice));
        at += len;
    }
    let (radius, angle) = (job.get_index(0), job.get_index(1));
    if !(radius.is_finite() && angle.is_finite() && points.iter().all(|p| p.is_finite())) {
        return Err(bad_job("a number that is not finite"));
    }
    let job = CreaseJob {
        points,
        radius,
        angle,
    };
    let creases = job
        .run(&mut |_| {})
        .unwrap_or_else(|| Creases::new(vec![], vec![]));
    Ok(Float64Array::from(creases.to_flat().as_slice()))
}

#[wasm_bindgen]
impl WrapSession {
    /// The session's crease detection as plain numbers (fit radius, crease angle, then the
    /// points) for [`cloud_creases`] in a helper worker; undefined when there is none to do (a
    /// mesh, a volume, no final fit, more than [`HELPER_MAX_POINTS`] points, or the fit has found
    /// them already).
    #[wasm_bindgen(js_name = creaseJob)]
    pub fn crease_job(&self) -> Option<Float64Array> {
        let job = self.evolver.crease_job()?;
        if job.points.len() > HELPER_MAX_POINTS {
            return None;
        }
        // Filled a slice at a time (not from one vector of all the numbers, which would grow
        // this instance's memory for good).
        let out = Float64Array::new_with_length((JOB_HEAD + 3 * job.points.len()) as u32);
        out.set_index(0, job.radius);
        out.set_index(1, job.angle);
        for (k, chunk) in job.points.chunks(4096).enumerate() {
            let flat: Vec<f64> = chunk.iter().flat_map(|p| p.to_array()).collect();
            out.set(
                &Float64Array::from(flat.as_slice()),
                (JOB_HEAD + 3 * 4096 * k) as u32,
            );
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
            .evolver
            .supply_creases((!creases.is_empty()).then_some(creases)))
    }
}
