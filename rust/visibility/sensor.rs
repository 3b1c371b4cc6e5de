//! What one UAV's sensor can see before occlusion: a range (at least `d_min`, at most `d_max`)
//! and, for a camera, a pinhole frustum.
//!
//! The paper's sensor is omnidirectional up to `d_max` (every UAV the same); a team may mix
//! sensors, and a camera sees a target only inside its field of view. The frustum is given by
//! the camera's axes in the world frame (unit vectors: `forward` along the optical axis, `right`
//! along the image's width, `up` along its height) and the tangents of its half-angles; a target
//! at offset `d` from the camera is inside when `d . forward > 0`, `|d . right| <=
//! tan_h (d . forward)` and `|d . up| <= tan_v (d . forward)`, each dot product summed x, then
//! y, then z (so an independent reference written the same way finds the same boundary targets).
//! The axes come from the caller (the Python side turns heading and gimbal pitch into them), so
//! this module holds no trigonometry whose last bit could differ from the reference's.
//!
//! ```
//! use uavcov::visibility::sensor::{Frustum, Sensor};
//! // A nadir camera (looking down, image top to the north), 90 deg x 60 deg, 2 m to 30 m range.
//! let nadir = Frustum::new([0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1.0, 0.5773502691896257)?;
//! let sensor = Sensor::new(2.0, 30.0, Some(nadir))?;
//! let uav = [0.0, 0.0, 10.0];
//! assert!(sensor.accepts(uav, [5.0, 0.0, 0.0])); // 45 deg off the axis, across the width
//! assert!(!sensor.accepts(uav, [0.0, 7.0, 0.0])); // 35 deg off the axis along the height: outside
//! assert!(!sensor.accepts(uav, [0.0, 0.0, 9.0])); // 1 m away: under d_min
//! # Ok::<(), uavcov::Error>(())
//! ```

use crate::error::{ensure, Result};
use crate::geometry::{Point, UNLIMITED_RANGE};

/// A pinhole camera's field of view in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    forward: Point,
    right: Point,
    up: Point,
    tan_h: f64,
    tan_v: f64,
}

/// One UAV's sensor: its range and, for a camera, its field of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensor {
    /// Least distance at which a target is seen, m (0: none).
    pub d_min: f64,
    /// Greatest distance at which a target is seen, m.
    pub d_max: f64,
    /// `d_max`, at most [`UNLIMITED_RANGE`]: the range the tests use, and its square.
    range: f64,
    d_min2: f64,
    d_max2: f64,
    camera: Option<Frustum>,
    /// Cosine of the largest incidence angle accepted (between the target's normal and the
    /// direction to the UAV), and its square.
    incidence: Option<(f64, f64)>,
    /// `(gsd per metre of distance, the GSD of full quality)`, m per pixel.
    resolution: Option<(f64, f64)>,
}

fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn is_unit(a: Point) -> bool {
    a.iter().all(|c| c.is_finite()) && (dot(a, a) - 1.0).abs() <= 1e-9
}

impl Frustum {
    /// A frustum from the camera's unit axes and the tangents of its half fields of view.
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] when an axis is not a finite unit vector, the axes are not
    /// orthogonal (to 1e-9), or a tangent is not finite and positive (a field of view in
    /// `(0, 180)` degrees).
    pub fn new(forward: Point, right: Point, up: Point, tan_h: f64, tan_v: f64) -> Result<Self> {
        ensure!(is_unit(forward) && is_unit(right) && is_unit(up), "the camera's axes must be finite unit vectors");
        ensure!(
            dot(forward, right).abs() <= 1e-9 && dot(forward, up).abs() <= 1e-9 && dot(right, up).abs() <= 1e-9,
            "the camera's axes must be orthogonal"
        );
        ensure!(
            tan_h.is_finite() && tan_h > 0.0 && tan_v.is_finite() && tan_v > 0.0,
            "a field of view must be in (0, 180) degrees: its half-angle tangents must be finite and > 0, got {tan_h} and {tan_v}"
        );
        Ok(Self { forward, right, up, tan_h, tan_v })
    }

    /// Whether the offset `d` (target minus camera) lies inside the field of view, its boundary
    /// included.
    #[must_use]
    pub fn contains(&self, d: Point) -> bool {
        let depth = dot(d, self.forward);
        depth > 0.0 && dot(d, self.right).abs() <= self.tan_h * depth && dot(d, self.up).abs() <= self.tan_v * depth
    }
}

impl Frustum {
    /// Whether no point of the box `[lo, hi]` can lie inside the field of view seen from `apex`
    /// (a conservative test: `false` says nothing). Each of the five planes bounding the view
    /// (the four sides and the plane through the apex across the optical axis) is tried against
    /// the box's eight corners; a box entirely on the outer side of one, by more than a margin
    /// far wider than the rounding of [`Frustum::contains`], holds no point it accepts.
    #[must_use]
    pub fn misses_box(&self, apex: Point, lo: Point, hi: Point) -> bool {
        let (f, r, u) = (self.forward, self.right, self.up);
        let planes = [
            f,
            [self.tan_h * f[0] - r[0], self.tan_h * f[1] - r[1], self.tan_h * f[2] - r[2]],
            [self.tan_h * f[0] + r[0], self.tan_h * f[1] + r[1], self.tan_h * f[2] + r[2]],
            [self.tan_v * f[0] - u[0], self.tan_v * f[1] - u[1], self.tan_v * f[2] - u[2]],
            [self.tan_v * f[0] + u[0], self.tan_v * f[1] + u[1], self.tan_v * f[2] + u[2]],
        ];
        let offsets: Vec<Point> = (0..8)
            .map(|k| {
                let corner = [
                    if k & 1 == 0 { lo[0] } else { hi[0] },
                    if k & 2 == 0 { lo[1] } else { hi[1] },
                    if k & 4 == 0 { lo[2] } else { hi[2] },
                ];
                [corner[0] - apex[0], corner[1] - apex[1], corner[2] - apex[2]]
            })
            .collect();
        let size = offsets.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let margin = 1e-9 * size * (1.0 + self.tan_h + self.tan_v);
        planes.iter().any(|n| offsets.iter().all(|&d| dot(d, *n) < -margin))
    }
}

impl Sensor {
    /// Whether this sensor reaches no point of the box `[lo, hi]` from `uav` (conservative, like
    /// [`Frustum::misses_box`]): the box is out of range, or outside the camera's view.
    #[must_use]
    pub fn misses_box(&self, uav: Point, lo: Point, hi: Point) -> bool {
        let d2: f64 = (0..3).map(|k| (lo[k] - uav[k]).max(0.0).max(uav[k] - hi[k]).powi(2)).sum();
        d2 > self.d_max2 || self.camera.is_some_and(|c| c.misses_box(uav, lo, hi))
    }

    /// The paper's omnidirectional sensor of range `d_max`.
    ///
    /// # Errors
    /// As [`Sensor::new`].
    pub fn omnidirectional(d_max: f64) -> Result<Self> {
        Self::new(0.0, d_max, None)
    }

    /// A sensor seeing from `d_min` to `d_max` metres, through `camera` when given.
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] unless `0 <= d_min < d_max`, both finite (a `d_max` of
    /// [`UNLIMITED_RANGE`] or more is an unlimited range, as for [`crate::Visibility`]).
    pub fn new(d_min: f64, d_max: f64, camera: Option<Frustum>) -> Result<Self> {
        ensure!(d_max.is_finite() && d_max > 0.0, "d_max must be finite and > 0, got {d_max}");
        ensure!(d_min.is_finite() && d_min >= 0.0 && d_min < d_max, "d_min must be in [0, d_max), got {d_min}");
        let range = d_max.min(UNLIMITED_RANGE);
        Ok(Self { d_min, d_max, range, d_min2: d_min * d_min, d_max2: range * range, camera, incidence: None, resolution: None })
    }

    /// This sensor, reaching only targets seen at most `acos(cos_max)` off their surface normal
    /// (either side of the surface: a mesh's winding says nothing of its outside).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] unless `cos_max` is in `[0, 1]` (an angle of 0 to 90 deg).
    pub fn with_incidence_limit(mut self, cos_max: f64) -> Result<Self> {
        ensure!((0.0..=1.0).contains(&cos_max), "the incidence limit's cosine must be in [0, 1], got {cos_max}");
        self.incidence = Some((cos_max, cos_max * cos_max));
        Ok(self)
    }

    /// This sensor, rating each target it sees by resolution: full quality where the ground
    /// sample distance `gsd_per_metre * distance` is at most `good_gsd`, `good_gsd / gsd`
    /// beyond.
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] unless both are finite and positive.
    pub fn with_resolution(mut self, gsd_per_metre: f64, good_gsd: f64) -> Result<Self> {
        ensure!(gsd_per_metre.is_finite() && gsd_per_metre > 0.0, "the GSD per metre must be finite and > 0, got {gsd_per_metre}");
        ensure!(good_gsd.is_finite() && good_gsd > 0.0, "the GSD of full quality must be finite and > 0, got {good_gsd}");
        self.resolution = Some((gsd_per_metre, good_gsd));
        Ok(self)
    }

    /// The cosine of the largest accepted incidence angle, when the sensor limits it.
    #[must_use]
    pub fn max_incidence_cos(&self) -> Option<f64> {
        self.incidence.map(|(c, _)| c)
    }

    /// Whether `target` (surface normal `normal`) is seen steeply enough from `uav`: true
    /// without a limit; false with a limit and no normal. Squared, so no root is taken:
    /// `(v . n)^2 >= cos^2 |v|^2`.
    #[must_use]
    pub fn incidence_ok(&self, uav: Point, target: Point, normal: Option<Point>) -> bool {
        let Some((_, cos2)) = self.incidence else { return true };
        let Some(n) = normal else { return false };
        let v = [uav[0] - target[0], uav[1] - target[1], uav[2] - target[2]];
        let along = dot(v, n);
        along * along >= cos2 * dot(v, v)
    }

    /// The quality of a view of `target` from `uav`, in `[0, 1]`: resolution (see
    /// [`Sensor::with_resolution`]; 1 without) times the cosine of the incidence angle (1 without
    /// a normal). Only meaningful for a target the sensor reaches and sees.
    #[must_use]
    pub fn quality(&self, uav: Point, target: Point, normal: Option<Point>) -> f64 {
        let v = [uav[0] - target[0], uav[1] - target[1], uav[2] - target[2]];
        let distance = dot(v, v).sqrt();
        let resolution = self.resolution.map_or(1.0, |(per_metre, good)| (good / (per_metre * distance)).min(1.0));
        let incidence = match normal {
            Some(n) if distance > 0.0 => (dot(v, n).abs() / distance).min(1.0),
            _ => 1.0,
        };
        resolution * incidence
    }

    /// The range the tests use: `d_max`, at most [`UNLIMITED_RANGE`].
    #[must_use]
    pub fn range(&self) -> f64 {
        self.range
    }

    /// Whether a target at `target` is within this sensor's reach from `uav`, before occlusion:
    /// within range (squared distances, summed x, y, z) and inside the camera's field of view.
    #[must_use]
    pub fn accepts(&self, uav: Point, target: Point) -> bool {
        let d = [target[0] - uav[0], target[1] - uav[1], target[2] - uav[2]];
        let d2 = dot(d, d);
        d2 <= self.d_max2 && d2 >= self.d_min2 && self.camera.is_none_or(|c| c.contains(d))
    }

    /// The camera, when the sensor is one.
    #[must_use]
    pub fn camera(&self) -> Option<&Frustum> {
        self.camera.as_ref()
    }
}

#[cfg(test)]
mod tests;
