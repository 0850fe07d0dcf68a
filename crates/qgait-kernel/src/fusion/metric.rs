//! BROAD's orientation error metric (Laidig et al., *Data* 6:72, 2021): the error quaternion
//! `e = q_est ⊗ q_ref⁻¹` (the error expressed in the earth frame) split into total, heading
//! and inclination angles, reduced to root mean squares.

/// The error of one estimate against its reference, rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientationError {
    /// The whole rotation angle of `e`: `2 acos |e_w|`.
    pub total: f64,
    /// The part about the vertical (earth z) axis: `2 atan |e_z / e_w|`.
    pub heading: f64,
    /// The part about horizontal axes: `2 acos √(e_w² + e_z²)`.
    pub inclination: f64,
}

impl OrientationError {
    /// The error of `estimate` against `reference`, both `(w, x, y, z)` mapping sensor to
    /// earth coordinates; normalised here, signs irrelevant. `None` if either has a zero or
    /// non-finite norm (a missing reference).
    pub fn between(estimate: [f64; 4], reference: [f64; 4]) -> Option<Self> {
        let n = |q: [f64; 4]| libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
        let (na, nb) = (n(estimate), n(reference));
        if !(na.is_finite() && nb.is_finite() && na > 0.0 && nb > 0.0) {
            return None;
        }
        let a = estimate.map(|x| x / na);
        // The inverse of a unit quaternion is its conjugate.
        let b = [
            reference[0] / nb,
            -reference[1] / nb,
            -reference[2] / nb,
            -reference[3] / nb,
        ];
        let ew = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
        let ez = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
        Some(Self {
            total: 2.0 * libm::acos(ew.abs().min(1.0)),
            heading: 2.0 * libm::atan2(ez.abs(), ew.abs()),
            inclination: 2.0 * libm::acos(libm::sqrt(ew * ew + ez * ez).min(1.0)),
        })
    }
}

/// Root mean squares of [`OrientationError`]s, accumulated one sample at a time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorRms {
    sum_sq: [f64; 3],
    count: usize,
}

impl ErrorRms {
    /// No samples.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds one error.
    pub fn add(&mut self, e: OrientationError) {
        self.sum_sq[0] += e.total * e.total;
        self.sum_sq[1] += e.heading * e.heading;
        self.sum_sq[2] += e.inclination * e.inclination;
        self.count += 1;
    }
    /// The number of errors added.
    pub fn count(&self) -> usize {
        self.count
    }
    /// `(total, heading, inclination)` RMS in degrees; NaN without samples.
    pub fn rms_deg(&self) -> [f64; 3] {
        let n = self.count as f64;
        self.sum_sq.map(|s| libm::sqrt(s / n).to_degrees())
    }
}
