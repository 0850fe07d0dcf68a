//! VQF, a port of the reference implementation's `vqf.cpp` (version 2.1.2 of the `vqf` package)
//! to Rust, generic over the kernel's scalar type.
//!
//! Copyright (c) 2021 Daniel Laidig <laidig@control.tu-berlin.de>
//!
//! Permission is hereby granted, free of charge, to any person obtaining a copy of this software
//! and associated documentation files (the "Software"), to deal in the Software without
//! restriction, including without limitation the rights to use, copy, modify, merge, publish,
//! distribute, sublicense, and/or sell copies of the Software, and to permit persons to whom the
//! Software is furnished to do so, subject to the following conditions:
//!
//! The above copyright notice and this permission notice shall be included in all copies or
//! substantial portions of the Software.
//!
//! THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR IMPLIED, INCLUDING
//! BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY, FITNESS FOR A PARTICULAR PURPOSE AND
//! NONINFRINGEMENT. IN NO EVENT SHALL THE AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM,
//! DAMAGES OR OTHER LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
//! OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE SOFTWARE.
//!
//! The port keeps the reference's order of operations, so that in `f64` it reproduces the
//! reference (compiled with `vqf_real_t = double`) to rounding; see the crate's tests. It leaves
//! out what the update does not depend on: the debugging outputs `lastAccCorrAngularRate` and
//! `lastMagCorrAngularRate` (an `acos` per sample) and the run-time setters of the parameters
//! (construct a new filter instead). Differences by precision, all in [`FusionReal`]:
//! the gyroscope step's and the heading's half-angle sine and cosine are
//! [`Real::half_angle_sin_cos`] (libm in `f64`, the kernel's polynomial in `f32`), and `f32`
//! keeps the low-pass filters' state in `f32` where the reference keeps it in `double` (see
//! [`FusionReal`]).

use core::f64::consts::PI;

use crate::Real;

use super::FusionReal;

/// The parameters of VQF, with the reference's defaults ([`Default`]). Times in seconds,
/// angular thresholds in degrees (per second), as in the reference's `VQFParams`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VqfParams {
    /// Time constant of the accelerometer low-pass filter (inclination correction), s.
    pub tau_acc: f64,
    /// Time constant of the magnetometer update (heading correction), s.
    pub tau_mag: f64,
    /// Gyroscope bias estimation during motion.
    pub motion_bias_est_enabled: bool,
    /// Gyroscope bias estimation at rest.
    pub rest_bias_est_enabled: bool,
    /// Magnetic disturbance detection and rejection.
    pub mag_dist_rejection_enabled: bool,
    /// Standard deviation of the initial bias estimation uncertainty, °/s.
    pub bias_sigma_init: f64,
    /// Time in which the bias uncertainty grows from 0 to 0.1 °/s, s.
    pub bias_forgetting_time: f64,
    /// Maximum expected gyroscope bias, °/s.
    pub bias_clip: f64,
    /// Standard deviation of the converged bias estimate during motion, °/s.
    pub bias_sigma_motion: f64,
    /// Forgetting factor of the vertical bias component during motion.
    pub bias_vertical_forgetting_factor: f64,
    /// Standard deviation of the converged bias estimate at rest, °/s.
    pub bias_sigma_rest: f64,
    /// Time without movement before rest is detected, s.
    pub rest_min_t: f64,
    /// Time constant of the rest detection's low-pass filters, s.
    pub rest_filter_tau: f64,
    /// Rest detection's gyroscope threshold, °/s.
    pub rest_th_gyr: f64,
    /// Rest detection's accelerometer threshold, m/s².
    pub rest_th_acc: f64,
    /// Time constant of the current magnetic norm and dip low-pass filter, s (<= 0: none).
    pub mag_current_tau: f64,
    /// Time constant of the adaptation of the magnetic reference norm and dip, s.
    pub mag_ref_tau: f64,
    /// Relative threshold on the magnetic norm for disturbance detection.
    pub mag_norm_th: f64,
    /// Threshold on the magnetic dip angle for disturbance detection, °.
    pub mag_dip_th: f64,
    /// Time after which a new, homogeneous field is accepted, s.
    pub mag_new_time: f64,
    /// The same at the start, before any field was accepted, s.
    pub mag_new_first_time: f64,
    /// Minimum angular rate for the new-field time to count, °/s.
    pub mag_new_min_gyr: f64,
    /// Minimum undisturbed time before the magnetometer is used again, s.
    pub mag_min_undisturbed_time: f64,
    /// Maximum time of full rejection of a disturbed field, s.
    pub mag_max_rejection_time: f64,
    /// Factor of the reduced gain after the maximum rejection time, and of the recovery of
    /// rejection time.
    pub mag_rejection_factor: f64,
}

impl Default for VqfParams {
    /// The reference's defaults (`VQFParams::VQFParams()`).
    fn default() -> Self {
        Self {
            tau_acc: 3.0,
            tau_mag: 9.0,
            motion_bias_est_enabled: true,
            rest_bias_est_enabled: true,
            mag_dist_rejection_enabled: true,
            bias_sigma_init: 0.5,
            bias_forgetting_time: 100.0,
            bias_clip: 2.0,
            bias_sigma_motion: 0.1,
            bias_vertical_forgetting_factor: 0.0001,
            bias_sigma_rest: 0.03,
            rest_min_t: 1.5,
            rest_filter_tau: 0.5,
            rest_th_gyr: 2.0,
            rest_th_acc: 0.5,
            mag_current_tau: 0.05,
            mag_ref_tau: 20.0,
            mag_norm_th: 0.1,
            mag_dip_th: 10.0,
            mag_new_time: 20.0,
            mag_new_first_time: 5.0,
            mag_new_min_gyr: 20.0,
            mag_min_undisturbed_time: 0.5,
            mag_max_rejection_time: 60.0,
            mag_rejection_factor: 2.0,
        }
    }
}

/// Coefficients of a second-order Butterworth low-pass filter (`a0` = 1).
#[derive(Clone, Copy, Debug)]
struct Lp<T> {
    b: [T; 3],
    a: [T; 2],
}

/// The run-time constants: the parameters the update reads, in `T`, and the derived
/// coefficients (the reference's `VQFCoefficients`).
#[derive(Clone, Copy, Debug)]
struct Coeffs<T: FusionReal> {
    motion_bias_est_enabled: bool,
    rest_bias_est_enabled: bool,
    mag_dist_rejection_enabled: bool,
    gyr_ts: T,
    acc_ts: T,
    mag_ts: T,
    tau_acc: T,
    tau_mag: T,
    rest_filter_tau: T,
    mag_current_tau: T,
    acc_lp: Lp<T::Acc>,
    rest_gyr_lp: Lp<T::Acc>,
    rest_acc_lp: Lp<T::Acc>,
    mag_norm_dip_lp: Lp<T::Acc>,
    k_mag: T,
    k_mag_ref: T,
    bias_p0: T,
    bias_v: T,
    bias_motion_w: T,
    bias_vertical_w: T,
    bias_rest_w: T,
    /// `bias_clip` in rad/s.
    bias_clip: T,
    /// `(rest_th_gyr` in rad/s`)²`.
    rest_th_gyr_sq: T,
    /// `rest_th_acc²`.
    rest_th_acc_sq: T,
    rest_min_t: T,
    mag_norm_th: T,
    /// `mag_dip_th` in rad.
    mag_dip_th: T,
    mag_new_time: T,
    mag_new_first_time: T,
    /// `mag_new_min_gyr` in rad/s.
    mag_new_min_gyr: T,
    mag_min_undisturbed_time: T,
    mag_max_rejection_time: T,
    mag_rejection_factor: T,
}

/// The filter's state (the reference's `VQFState`, less the debugging outputs).
#[derive(Clone, Copy, Debug)]
struct State<T: FusionReal> {
    gyr_quat: [T; 4],
    acc_quat: [T; 4],
    delta: T,
    rest_detected: bool,
    mag_dist_detected: bool,
    last_acc_lp: [T; 3],
    acc_lp_state: [T::Acc; 6],
    k_mag_init: T,
    last_mag_dis_angle: T,
    bias: [T; 3],
    bias_p: [T; 9],
    motion_bias_est_r_lp_state: [T::Acc; 18],
    motion_bias_est_bias_lp_state: [T::Acc; 4],
    rest_last_squared_deviations: [T; 2],
    rest_t: T,
    rest_last_gyr_lp: [T; 3],
    rest_gyr_lp_state: [T::Acc; 6],
    rest_last_acc_lp: [T; 3],
    rest_acc_lp_state: [T::Acc; 6],
    mag_ref_norm: T,
    mag_ref_dip: T,
    mag_undisturbed_t: T,
    mag_reject_t: T,
    mag_candidate_norm: T,
    mag_candidate_dip: T,
    mag_candidate_t: T,
    mag_norm_dip: [T; 2],
    mag_norm_dip_lp_state: [T::Acc; 4],
}

/// VQF orientation estimation from gyroscope, accelerometer and (optionally) magnetometer
/// samples; see the [module docs](super).
///
/// Inputs in the sensor frame: angular rate in rad/s, specific force in any unit (m/s²), the
/// magnetic field in any unit (µT). Outputs map sensor coordinates into the earth frame (ENU
/// for 9D; for 6D, an earth frame with z up and an arbitrary heading).
#[derive(Clone, Copy, Debug)]
pub struct Vqf<T: FusionReal> {
    coeffs: Coeffs<T>,
    state: State<T>,
}

#[inline(always)]
fn square<T: Real>(x: T) -> T {
    x * x
}

/// `1 - exp(-ts/tau)` (0 for negative `tau`, 1 for `tau` = 0): the gain of a first-order
/// low-pass filter.
fn gain_from_tau(tau: f64, ts: f64) -> f64 {
    if tau < 0.0 {
        0.0
    } else if tau == 0.0 {
        1.0
    } else {
        1.0 - libm::exp(-ts / tau)
    }
}

/// Second-order Butterworth coefficients `(b, a)` for time constant `tau` and sampling period
/// `ts` (pass-through when `tau < ts/2`).
fn filter_coeffs(tau: f64, ts: f64) -> ([f64; 3], [f64; 2]) {
    if tau < ts / 2.0 {
        return ([1.0, 0.0, 0.0], [0.0, 0.0]);
    }
    let fc = (core::f64::consts::SQRT_2 / (2.0 * PI)) / tau;
    let c = libm::tan(PI * fc * ts);
    let d = c * c + libm::sqrt(2.0) * c + 1.0;
    let b0 = c * c / d;
    (
        [b0, 2.0 * b0, b0],
        [
            2.0 * (c * c - 1.0) / d,
            (1.0 - libm::sqrt(2.0) * c + c * c) / d,
        ],
    )
}

fn lp<T: FusionReal>((b, a): ([f64; 3], [f64; 2])) -> Lp<T::Acc> {
    Lp {
        b: b.map(T::acc_coeff),
        a: a.map(T::acc_coeff),
    }
}

/// One step of the filter (transposed direct form II, as `scipy.signal.lfilter`).
#[inline(always)]
fn filter_step<T: FusionReal>(x: T, c: &Lp<T::Acc>, state: &mut [T::Acc]) -> T {
    T::filter_step(x, &c.b, &c.a, state)
}

/// Filters the vector `x` into `out` (`state` holds 2 values per element). For the first
/// `tau` seconds the output is the running mean, which then initialises the filter in steady
/// state (the reference's `filterVec`).
fn filter_vec<T: FusionReal>(
    x: &[T],
    tau: T,
    ts: T,
    c: &Lp<T::Acc>,
    state: &mut [T::Acc],
    out: &mut [T],
) {
    let n = x.len();
    if T::acc_is_nan(state[0]) {
        // Initialisation: state[1] counts the samples, state[2..2+n] hold the sums.
        if T::acc_is_nan(state[1]) {
            state[1] = T::acc_zero();
            for s in &mut state[2..2 + n] {
                *s = T::acc_zero();
            }
        }
        state[1] = T::acc_add(state[1], T::ONE);
        let count = T::acc_value(state[1]);
        for i in 0..n {
            state[2 + i] = T::acc_add(state[2 + i], x[i]);
            out[i] = T::acc_div(state[2 + i], state[1]);
        }
        if count * ts >= tau {
            for i in 0..n {
                // Steady state for input out[i] (scipy's lfilter_zi).
                T::filter_initial_state(out[i], &c.b, &c.a, &mut state[2 * i..2 * i + 2]);
            }
        }
        return;
    }
    for i in 0..n {
        out[i] = filter_step(x[i], c, &mut state[2 * i..2 * i + 2]);
    }
}

fn quat_multiply<T: Real>(q1: &[T; 4], q2: &[T; 4]) -> [T; 4] {
    [
        q1[0] * q2[0] - q1[1] * q2[1] - q1[2] * q2[2] - q1[3] * q2[3],
        q1[0] * q2[1] + q1[1] * q2[0] + q1[2] * q2[3] - q1[3] * q2[2],
        q1[0] * q2[2] - q1[1] * q2[3] + q1[2] * q2[0] + q1[3] * q2[1],
        q1[0] * q2[3] + q1[1] * q2[2] - q1[2] * q2[1] + q1[3] * q2[0],
    ]
}

/// `q ⊗ (0, v) ⊗ q*` for unit `q`.
fn quat_rotate<T: Real>(q: &[T; 4], v: &[T; 3]) -> [T; 3] {
    let one = T::ONE;
    let two = T::TWO;
    [
        (one - two * q[2] * q[2] - two * q[3] * q[3]) * v[0]
            + two * v[1] * (q[2] * q[1] - q[0] * q[3])
            + two * v[2] * (q[0] * q[2] + q[3] * q[1]),
        two * v[0] * (q[0] * q[3] + q[2] * q[1])
            + v[1] * (one - two * q[1] * q[1] - two * q[3] * q[3])
            + two * v[2] * (q[2] * q[3] - q[1] * q[0]),
        two * v[0] * (q[3] * q[1] - q[0] * q[2])
            + two * v[1] * (q[0] * q[1] + q[3] * q[2])
            + v[2] * (one - two * q[1] * q[1] - two * q[2] * q[2]),
    ]
}

fn norm<T: Real>(v: &[T]) -> T {
    let mut s = T::ZERO;
    for x in v {
        s += *x * *x;
    }
    s.sqrt()
}

/// Rest detection's test of one sensor: its sample `x` low-pass filtered into `lp` (as
/// [`filter_vec`]), and the squared distance of `x` from that.
#[inline(always)]
fn rest_deviation<T: FusionReal>(
    x: &[T; 3],
    tau: T,
    ts: T,
    c: &Lp<T::Acc>,
    state: &mut [T::Acc],
    lp: &mut [T; 3],
) -> T {
    filter_vec(x, tau, ts, c, state, lp);
    square(x[0] - lp[0]) + square(x[1] - lp[1]) + square(x[2] - lp[2])
}

/// Divides by the norm unless it is below the epsilon.
fn normalize<T: FusionReal>(v: &mut [T]) {
    let n = norm(v);
    if n < T::EPSILON {
        return;
    }
    for x in v {
        *x = *x / n;
    }
}

/// Clips to `[min, max]` (NaN stays NaN).
fn clip<T: Real>(v: &mut [T], min: T, max: T) {
    for x in v {
        if *x < min {
            *x = min;
        } else if *x > max {
            *x = max;
        }
    }
}

fn matrix3_multiply<T: Real>(a: &[T; 9], b: &[T; 9]) -> [T; 9] {
    core::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j]
    })
}

/// `aᵀ b`.
fn matrix3_multiply_tps_first<T: Real>(a: &[T; 9], b: &[T; 9]) -> [T; 9] {
    core::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j]
    })
}

/// `a bᵀ`.
fn matrix3_multiply_tps_second<T: Real>(a: &[T; 9], b: &[T; 9]) -> [T; 9] {
    core::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2]
    })
}

/// The inverse by cofactors; zeros when the determinant is within the epsilon of 0.
fn matrix3_inv<T: FusionReal>(m: &[T; 9]) -> [T; 9] {
    let a = m[4] * m[8] - m[5] * m[7];
    let d = m[2] * m[7] - m[1] * m[8];
    let g = m[1] * m[5] - m[2] * m[4];
    let b = m[5] * m[6] - m[3] * m[8];
    let e = m[0] * m[8] - m[2] * m[6];
    let h = m[2] * m[3] - m[0] * m[5];
    let c = m[3] * m[7] - m[4] * m[6];
    let f = m[1] * m[6] - m[0] * m[7];
    let i = m[0] * m[4] - m[1] * m[3];
    let det = m[0] * a + m[1] * b + m[2] * c;
    if det >= -T::EPSILON && det <= T::EPSILON {
        return [T::ZERO; 9];
    }
    [
        a / det,
        d / det,
        g / det,
        b / det,
        e / det,
        h / det,
        c / det,
        f / det,
        i / det,
    ]
}

fn scaled_identity<T: Real>(s: T) -> [T; 9] {
    let z = T::ZERO;
    [s, z, z, z, s, z, z, z, s]
}

impl<T: FusionReal> Vqf<T> {
    /// A filter with the reference's default parameters for samples every `ts` seconds.
    pub fn new_default(ts: f64) -> Self {
        Self::new(&VqfParams::default(), ts)
    }

    /// A filter for gyroscope, accelerometer and magnetometer samples every `ts` seconds.
    ///
    /// # Panics
    /// If `ts` is not positive.
    pub fn new(params: &VqfParams, ts: f64) -> Self {
        Self::with_rates(params, ts, ts, ts)
    }

    /// A filter for different sampling periods of the gyroscope, the accelerometer and the
    /// magnetometer (call [`update_gyr`](Self::update_gyr), [`update_acc`](Self::update_acc)
    /// and [`update_mag`](Self::update_mag) at their rates).
    ///
    /// # Panics
    /// If a period is not positive.
    pub fn with_rates(params: &VqfParams, gyr_ts: f64, acc_ts: f64, mag_ts: f64) -> Self {
        assert!(
            gyr_ts > 0.0 && acc_ts > 0.0 && mag_ts > 0.0,
            "sampling periods must be positive"
        );
        let p = params;
        let t = T::from_f64;
        let bias_p0 = square(p.bias_sigma_init * 100.0);
        let bias_v = square(0.1 * 100.0) * acc_ts / p.bias_forgetting_time;
        let p_motion = square(p.bias_sigma_motion * 100.0);
        let bias_motion_w = square(p_motion) / bias_v + p_motion;
        let bias_vertical_w = bias_motion_w / p.bias_vertical_forgetting_factor.max(1e-10);
        let p_rest = square(p.bias_sigma_rest * 100.0);
        let bias_rest_w = square(p_rest) / bias_v + p_rest;
        let nan = Lp {
            b: [T::acc_coeff(f64::NAN); 3],
            a: [T::acc_coeff(f64::NAN); 2],
        };
        let coeffs = Coeffs {
            motion_bias_est_enabled: p.motion_bias_est_enabled,
            rest_bias_est_enabled: p.rest_bias_est_enabled,
            mag_dist_rejection_enabled: p.mag_dist_rejection_enabled,
            gyr_ts: t(gyr_ts),
            acc_ts: t(acc_ts),
            mag_ts: t(mag_ts),
            tau_acc: t(p.tau_acc),
            tau_mag: t(p.tau_mag),
            rest_filter_tau: t(p.rest_filter_tau),
            mag_current_tau: t(p.mag_current_tau),
            acc_lp: lp::<T>(filter_coeffs(p.tau_acc, acc_ts)),
            rest_gyr_lp: lp::<T>(filter_coeffs(p.rest_filter_tau, gyr_ts)),
            rest_acc_lp: lp::<T>(filter_coeffs(p.rest_filter_tau, acc_ts)),
            mag_norm_dip_lp: if p.mag_current_tau > 0.0 {
                lp::<T>(filter_coeffs(p.mag_current_tau, mag_ts))
            } else {
                nan
            },
            k_mag: t(gain_from_tau(p.tau_mag, mag_ts)),
            k_mag_ref: t(gain_from_tau(p.mag_ref_tau, mag_ts)),
            bias_p0: t(bias_p0),
            bias_v: t(bias_v),
            bias_motion_w: t(bias_motion_w),
            bias_vertical_w: t(bias_vertical_w),
            bias_rest_w: t(bias_rest_w),
            bias_clip: t(p.bias_clip * (PI / 180.0)),
            rest_th_gyr_sq: t(square(p.rest_th_gyr * (PI / 180.0))),
            rest_th_acc_sq: t(square(p.rest_th_acc)),
            rest_min_t: t(p.rest_min_t),
            mag_norm_th: t(p.mag_norm_th),
            mag_dip_th: t(p.mag_dip_th * (PI / 180.0)),
            mag_new_time: t(p.mag_new_time),
            mag_new_first_time: t(p.mag_new_first_time),
            mag_new_min_gyr: t(p.mag_new_min_gyr * (PI / 180.0)),
            mag_min_undisturbed_time: t(p.mag_min_undisturbed_time),
            mag_max_rejection_time: t(p.mag_max_rejection_time),
            mag_rejection_factor: t(p.mag_rejection_factor),
        };
        let mut vqf = Self {
            coeffs,
            state: State::initial(&coeffs),
        };
        vqf.reset_state();
        vqf
    }

    /// Back to the initial state (identity orientation, zero bias), keeping the parameters.
    pub fn reset_state(&mut self) {
        self.state = State::initial(&self.coeffs);
    }

    /// One sample of all sensors: gyroscope (rad/s), accelerometer and, for 9D, magnetometer,
    /// all in the sensor frame. A magnetometer sample of exactly zero is ignored, as is an
    /// accelerometer sample of zero.
    #[inline]
    pub fn update(&mut self, gyr: [T; 3], acc: [T; 3], mag: Option<[T; 3]>) {
        self.update_gyr(gyr);
        self.update_acc(acc);
        if let Some(mag) = mag {
            self.update_mag(mag);
        }
    }

    /// The gyroscope step: rest detection's angular-rate part and the strapdown integration of
    /// the bias-corrected angular rate.
    pub fn update_gyr(&mut self, gyr: [T; 3]) {
        let c = &self.coeffs;
        let s = &mut self.state;
        if c.rest_bias_est_enabled || c.mag_dist_rejection_enabled {
            s.rest_last_squared_deviations[0] = rest_deviation(
                &gyr,
                c.rest_filter_tau,
                c.gyr_ts,
                &c.rest_gyr_lp,
                &mut s.rest_gyr_lp_state,
                &mut s.rest_last_gyr_lp,
            );
            if s.rest_last_squared_deviations[0] >= c.rest_th_gyr_sq
                || s.rest_last_gyr_lp[0].abs() > c.bias_clip
                || s.rest_last_gyr_lp[1].abs() > c.bias_clip
                || s.rest_last_gyr_lp[2].abs() > c.bias_clip
            {
                s.rest_t = T::ZERO;
                s.rest_detected = false;
            }
        }

        let gyr_no_bias = [gyr[0] - s.bias[0], gyr[1] - s.bias[1], gyr[2] - s.bias[2]];
        let gyr_norm = norm(&gyr_no_bias);
        let angle = gyr_norm * c.gyr_ts;
        if gyr_norm > T::EPSILON {
            let (sin_half, cos_half) = angle.half_angle_sin_cos();
            let k = sin_half / gyr_norm;
            let step = [
                cos_half,
                k * gyr_no_bias[0],
                k * gyr_no_bias[1],
                k * gyr_no_bias[2],
            ];
            s.gyr_quat = quat_multiply(&s.gyr_quat, &step);
            normalize(&mut s.gyr_quat);
        }
    }

    /// The accelerometer step: rest detection's specific-force part, the inclination
    /// correction and the gyroscope bias estimation.
    pub fn update_acc(&mut self, acc: [T; 3]) {
        if acc[0] == T::ZERO && acc[1] == T::ZERO && acc[2] == T::ZERO {
            return;
        }
        let zero = T::ZERO;
        let c = &self.coeffs;

        if c.rest_bias_est_enabled {
            let s = &mut self.state;
            s.rest_last_squared_deviations[1] = rest_deviation(
                &acc,
                c.rest_filter_tau,
                c.acc_ts,
                &c.rest_acc_lp,
                &mut s.rest_acc_lp_state,
                &mut s.rest_last_acc_lp,
            );
            if s.rest_last_squared_deviations[1] >= c.rest_th_acc_sq {
                s.rest_t = zero;
                s.rest_detected = false;
            } else {
                s.rest_t += c.acc_ts;
                if s.rest_t >= c.rest_min_t {
                    s.rest_detected = true;
                }
            }
        }

        // Low-pass filter the specific force in the almost inertial frame of the gyroscope
        // strapdown integration.
        {
            let s = &mut self.state;
            let acc_earth = quat_rotate(&s.gyr_quat, &acc);
            filter_vec(
                &acc_earth,
                c.tau_acc,
                c.acc_ts,
                &c.acc_lp,
                &mut s.acc_lp_state,
                &mut s.last_acc_lp,
            );
        }
        // Into the 6D earth frame, normalised.
        let mut acc_earth = quat_rotate(&self.state.acc_quat, &self.state.last_acc_lp);
        normalize(&mut acc_earth);

        // Inclination correction.
        let q_w = ((acc_earth[2] + T::ONE) / T::TWO).sqrt();
        let acc_corr_quat = if q_w > T::from_f64(1e-6) {
            [
                q_w,
                T::HALF * acc_earth[1] / q_w,
                -T::HALF * acc_earth[0] / q_w,
                zero,
            ]
        } else {
            // acc close to [0 0 -1]: the correction is within 0.00011° of 180°.
            [zero, T::ONE, zero, zero]
        };
        {
            let s = &mut self.state;
            s.acc_quat = quat_multiply(&acc_corr_quat, &s.acc_quat);
            normalize(&mut s.acc_quat);
        }

        if c.motion_bias_est_enabled || c.rest_bias_est_enabled {
            self.estimate_bias(&acc_earth);
        }
    }

    /// The Kalman filter of the gyroscope bias (during motion and at rest).
    fn estimate_bias(&mut self, acc_earth: &[T; 3]) {
        let c = &self.coeffs;
        let one = T::ONE;
        let two = T::TWO;
        let q = self.quat_6d_array();
        let s = &mut self.state;
        let mut r = [
            one - two * square(q[2]) - two * square(q[3]),
            two * (q[2] * q[1] - q[0] * q[3]),
            two * (q[0] * q[2] + q[3] * q[1]),
            two * (q[0] * q[3] + q[2] * q[1]),
            one - two * square(q[1]) - two * square(q[3]),
            two * (q[2] * q[3] - q[1] * q[0]),
            two * (q[3] * q[1] - q[0] * q[2]),
            two * (q[0] * q[1] + q[3] * q[2]),
            one - two * square(q[1]) - two * square(q[2]),
        ];
        // R b (x and y only).
        let mut bias_lp = [
            r[0] * s.bias[0] + r[1] * s.bias[1] + r[2] * s.bias[2],
            r[3] * s.bias[0] + r[4] * s.bias[1] + r[5] * s.bias[2],
        ];
        let r_in = r;
        filter_vec(
            &r_in,
            c.tau_acc,
            c.acc_ts,
            &c.acc_lp,
            &mut s.motion_bias_est_r_lp_state,
            &mut r,
        );
        let bias_lp_in = bias_lp;
        filter_vec(
            &bias_lp_in,
            c.tau_acc,
            c.acc_ts,
            &c.acc_lp,
            &mut s.motion_bias_est_bias_lp_state,
            &mut bias_lp,
        );

        let w;
        let mut e = [T::ZERO; 3];
        if s.rest_detected && c.rest_bias_est_enabled {
            e = [
                s.rest_last_gyr_lp[0] - s.bias[0],
                s.rest_last_gyr_lp[1] - s.bias[1],
                s.rest_last_gyr_lp[2] - s.bias[2],
            ];
            r = scaled_identity(one);
            w = [c.bias_rest_w; 3];
        } else if c.motion_bias_est_enabled {
            let b = s.bias;
            e = [
                -acc_earth[1] / c.acc_ts + bias_lp[0] - r[0] * b[0] - r[1] * b[1] - r[2] * b[2],
                acc_earth[0] / c.acc_ts + bias_lp[1] - r[3] * b[0] - r[4] * b[1] - r[5] * b[2],
                -r[6] * b[0] - r[7] * b[1] - r[8] * b[2],
            ];
            w = [c.bias_motion_w, c.bias_motion_w, c.bias_vertical_w];
        } else {
            w = [-one; 3]; // no measurement update
        }

        // P = P + V, also without a measurement update.
        for i in [0, 4, 8] {
            if s.bias_p[i] < c.bias_p0 {
                s.bias_p[i] += c.bias_v;
            }
        }
        if w[0] >= T::ZERO {
            clip(&mut e, -c.bias_clip, c.bias_clip);
            // K = P Rᵀ inv(W + R P Rᵀ)
            let mut k = matrix3_multiply_tps_second(&s.bias_p, &r);
            k = matrix3_multiply(&r, &k);
            k[0] += w[0];
            k[4] += w[1];
            k[8] += w[2];
            k = matrix3_inv(&k);
            k = matrix3_multiply_tps_first(&r, &k);
            k = matrix3_multiply(&s.bias_p, &k);
            // b = b + K e
            s.bias[0] += k[0] * e[0] + k[1] * e[1] + k[2] * e[2];
            s.bias[1] += k[3] * e[0] + k[4] * e[1] + k[5] * e[2];
            s.bias[2] += k[6] * e[0] + k[7] * e[1] + k[8] * e[2];
            // P = P - K R P
            k = matrix3_multiply(&k, &r);
            k = matrix3_multiply(&k, &s.bias_p);
            for (p, k) in s.bias_p.iter_mut().zip(k) {
                *p -= k;
            }
            clip(&mut s.bias, -c.bias_clip, c.bias_clip);
        }
    }

    /// The magnetometer step: magnetic disturbance detection and rejection and the heading
    /// correction.
    pub fn update_mag(&mut self, mag: [T; 3]) {
        let zero = T::ZERO;
        if mag[0] == zero && mag[1] == zero && mag[2] == zero {
            return;
        }
        let c = &self.coeffs;
        let q6 = self.quat_6d_array();
        let s = &mut self.state;
        let mag_earth = quat_rotate(&q6, &mag);

        if c.mag_dist_rejection_enabled {
            s.mag_norm_dip[0] = norm(&mag_earth);
            s.mag_norm_dip[1] = -(mag_earth[2] / s.mag_norm_dip[0]).asin();
            if c.mag_current_tau > zero {
                let x = s.mag_norm_dip;
                filter_vec(
                    &x,
                    c.mag_current_tau,
                    c.mag_ts,
                    &c.mag_norm_dip_lp,
                    &mut s.mag_norm_dip_lp_state,
                    &mut s.mag_norm_dip,
                );
            }

            // Disturbance detection.
            if (s.mag_norm_dip[0] - s.mag_ref_norm).abs() < c.mag_norm_th * s.mag_ref_norm
                && (s.mag_norm_dip[1] - s.mag_ref_dip).abs() < c.mag_dip_th
            {
                s.mag_undisturbed_t += c.mag_ts;
                if s.mag_undisturbed_t >= c.mag_min_undisturbed_time {
                    s.mag_dist_detected = false;
                    s.mag_ref_norm += c.k_mag_ref * (s.mag_norm_dip[0] - s.mag_ref_norm);
                    s.mag_ref_dip += c.k_mag_ref * (s.mag_norm_dip[1] - s.mag_ref_dip);
                }
            } else {
                s.mag_undisturbed_t = zero;
                s.mag_dist_detected = true;
            }

            // Acceptance of a new homogeneous field.
            if (s.mag_norm_dip[0] - s.mag_candidate_norm).abs()
                < c.mag_norm_th * s.mag_candidate_norm
                && (s.mag_norm_dip[1] - s.mag_candidate_dip).abs() < c.mag_dip_th
            {
                if norm(&s.rest_last_gyr_lp) >= c.mag_new_min_gyr {
                    s.mag_candidate_t += c.mag_ts;
                }
                s.mag_candidate_norm += c.k_mag_ref * (s.mag_norm_dip[0] - s.mag_candidate_norm);
                s.mag_candidate_dip += c.k_mag_ref * (s.mag_norm_dip[1] - s.mag_candidate_dip);
                if s.mag_dist_detected
                    && (s.mag_candidate_t >= c.mag_new_time
                        || (s.mag_ref_norm == zero && s.mag_candidate_t >= c.mag_new_first_time))
                {
                    s.mag_ref_norm = s.mag_candidate_norm;
                    s.mag_ref_dip = s.mag_candidate_dip;
                    s.mag_dist_detected = false;
                    s.mag_undisturbed_t = c.mag_min_undisturbed_time;
                }
            } else {
                s.mag_candidate_t = zero;
                s.mag_candidate_norm = s.mag_norm_dip[0];
                s.mag_candidate_dip = s.mag_norm_dip[1];
            }
        }

        // Disagreement between the measured heading and the estimate, in [-pi, pi].
        let pi = T::from_f64(PI);
        let two_pi = T::from_f64(2.0 * PI);
        s.last_mag_dis_angle = mag_earth[0].atan2(mag_earth[1]) - s.delta;
        if s.last_mag_dis_angle > pi {
            s.last_mag_dis_angle -= two_pi;
        } else if s.last_mag_dis_angle < -pi {
            s.last_mag_dis_angle += two_pi;
        }

        let mut k = c.k_mag;
        if c.mag_dist_rejection_enabled {
            if s.mag_dist_detected {
                if s.mag_reject_t <= c.mag_max_rejection_time {
                    s.mag_reject_t += c.mag_ts;
                    k = zero;
                } else {
                    k = k / c.mag_rejection_factor;
                }
            } else {
                s.mag_reject_t = (s.mag_reject_t - c.mag_rejection_factor * c.mag_ts).max(zero);
            }
        }

        // Fast initial convergence: a gain of at least 1/N in the first samples.
        if s.k_mag_init != zero {
            if k < s.k_mag_init {
                k = s.k_mag_init;
            }
            s.k_mag_init = s.k_mag_init / (s.k_mag_init + T::ONE);
            if s.k_mag_init * c.tau_mag < c.mag_ts {
                s.k_mag_init = zero;
            }
        }

        s.delta += k * s.last_mag_dis_angle;
        if s.delta > pi {
            s.delta -= two_pi;
        } else if s.delta < -pi {
            s.delta += two_pi;
        }
    }

    fn quat_6d_array(&self) -> [T; 4] {
        quat_multiply(&self.state.acc_quat, &self.state.gyr_quat)
    }

    /// The 6D orientation `(w, x, y, z)` (gyroscope and accelerometer): sensor to an earth
    /// frame with z up and a heading that drifts with the gyroscope.
    pub fn quat_6d(&self) -> [T; 4] {
        self.quat_6d_array()
    }

    /// The 9D orientation `(w, x, y, z)`: the 6D one turned about the vertical by the heading
    /// offset [`delta`](Self::delta) from the magnetometer; sensor to ENU (y to magnetic north)
    /// once the magnetometer has converged.
    pub fn quat_9d(&self) -> [T; 4] {
        let q = self.quat_6d_array();
        let (s, c) = self.state.delta.half_angle_sin_cos();
        [
            c * q[0] - s * q[3],
            c * q[1] - s * q[2],
            c * q[2] + s * q[1],
            c * q[3] + s * q[0],
        ]
    }

    /// The 3D orientation: the strapdown integration of the bias-corrected gyroscope alone.
    pub fn quat_3d(&self) -> [T; 4] {
        self.state.gyr_quat
    }

    /// The heading offset between the 6D and the 9D earth frames, rad, in `[-pi, pi]`.
    pub fn delta(&self) -> T {
        self.state.delta
    }

    /// The gyroscope bias estimate, rad/s, sensor frame.
    pub fn bias(&self) -> [T; 3] {
        self.state.bias
    }

    /// An upper bound of the standard deviation of the bias estimate, rad/s (the reference's
    /// `getBiasEstimate` return value).
    pub fn bias_sigma(&self) -> T {
        let p = &self.state.bias_p;
        let sum1 = p[0].abs() + p[1].abs() + p[2].abs();
        let sum2 = p[3].abs() + p[4].abs() + p[5].abs();
        let sum3 = p[6].abs() + p[7].abs() + p[8].abs();
        let p = sum1.max(sum2).max(sum3).min(self.coeffs.bias_p0);
        p.sqrt() * T::from_f64(PI / 100.0 / 180.0)
    }

    /// `true` while the sensor is detected at rest.
    pub fn rest_detected(&self) -> bool {
        self.state.rest_detected
    }

    /// `true` while the magnetic field is detected as disturbed (also before the first field
    /// was accepted).
    pub fn mag_dist_detected(&self) -> bool {
        self.state.mag_dist_detected
    }

    /// The reference magnetic norm (input units) and dip angle (rad).
    pub fn mag_ref(&self) -> (T, T) {
        (self.state.mag_ref_norm, self.state.mag_ref_dip)
    }
}

impl<T: FusionReal> State<T> {
    fn initial(c: &Coeffs<T>) -> Self {
        let zero = T::ZERO;
        let nan = T::acc_coeff(f64::NAN);
        let identity = [T::ONE, zero, zero, zero];
        Self {
            gyr_quat: identity,
            acc_quat: identity,
            delta: zero,
            rest_detected: false,
            mag_dist_detected: true,
            last_acc_lp: [zero; 3],
            acc_lp_state: [nan; 6],
            k_mag_init: T::ONE,
            last_mag_dis_angle: zero,
            bias: [zero; 3],
            bias_p: scaled_identity(c.bias_p0),
            motion_bias_est_r_lp_state: [nan; 18],
            motion_bias_est_bias_lp_state: [nan; 4],
            rest_last_squared_deviations: [zero; 2],
            rest_t: zero,
            rest_last_gyr_lp: [zero; 3],
            rest_gyr_lp_state: [nan; 6],
            rest_last_acc_lp: [zero; 3],
            rest_acc_lp_state: [nan; 6],
            mag_ref_norm: zero,
            mag_ref_dip: zero,
            mag_undisturbed_t: zero,
            mag_reject_t: c.mag_max_rejection_time,
            mag_candidate_norm: -T::ONE,
            mag_candidate_dip: zero,
            mag_candidate_t: zero,
            mag_norm_dip: [zero; 2],
            mag_norm_dip_lp_state: [nan; 4],
        }
    }
}
