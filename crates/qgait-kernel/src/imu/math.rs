//! The inverse trigonometry the IMU path needs, in [`Real`] arithmetic only (so one code serves
//! `f32` on the device and `f64` on the host), and the rotation decompositions built on it.

use crate::{Quat, Real, Vec3};

/// `true` for a single-precision `T` (1 + 1e-10 rounds to 1): the arctangent series then stops
/// earlier. Constant-folded for `f32` and `f64`.
#[inline(always)]
fn single_precision<T: Real>() -> bool {
    T::from_f64(1.0 + 1e-10) == T::ONE
}

/// `atan(t)` for `|t| <= 1`: two half-angle reductions (`atan t = 2 atan(t / (1 + sqrt(1 + t^2)))`)
/// bring `|t|` below `tan(pi/16)`, then the Taylor series (6 terms in `f32`, 12 in `f64`, each
/// below the precision's rounding).
fn atan_unit<T: Real>(t: T) -> T {
    let halve = |t: T| t / (T::ONE + (T::ONE + t * t).sqrt());
    let z = halve(halve(t));
    let s = z * z;
    // The series' coefficients (-1)^k / (2k + 1) as literals, so that converting them to `T`
    // folds at compile time (a loop over an `f64` table converts at run time: in software on
    // the device).
    let c = |x: f64| T::from_f64(x);
    let p = if single_precision::<T>() {
        let p = c(-1.0 / 11.0) * s + c(1.0 / 9.0);
        let p = p * s + c(-1.0 / 7.0);
        let p = p * s + c(1.0 / 5.0);
        p * s + c(-1.0 / 3.0)
    } else {
        let p = c(-1.0 / 23.0) * s + c(1.0 / 21.0);
        let p = p * s + c(-1.0 / 19.0);
        let p = p * s + c(1.0 / 17.0);
        let p = p * s + c(-1.0 / 15.0);
        let p = p * s + c(1.0 / 13.0);
        let p = p * s + c(-1.0 / 11.0);
        let p = p * s + c(1.0 / 9.0);
        let p = p * s + c(-1.0 / 7.0);
        let p = p * s + c(1.0 / 5.0);
        p * s + c(-1.0 / 3.0)
    };
    let p = p * s + T::ONE;
    T::from_f64(4.0) * z * p
}

/// The angle of the point `(x, y)` in `(-pi, pi]` (0 for the origin; NaN in, NaN out).
pub fn atan2<T: Real>(y: T, x: T) -> T {
    let r = (x * x + y * y).sqrt();
    if r == T::ZERO {
        return T::ZERO;
    }
    if x >= T::ZERO {
        // tan(angle/2) = y / (r + x), within [-1, 1].
        T::TWO * atan_unit(y / (r + x))
    } else {
        // cot(angle/2) = y / (r - x), within [-1, 1]: angle = ±pi - 2 atan(cot).
        let pi = T::from_f64(core::f64::consts::PI);
        let half_turn = if y >= T::ZERO { pi } else { -pi };
        half_turn - T::TWO * atan_unit(y / (r - x))
    }
}

/// `acos(c)` in `[0, pi]`, `c` clamped to `[-1, 1]`.
pub fn acos<T: Real>(c: T) -> T {
    let c = c.max(-T::ONE).min(T::ONE);
    atan2(((T::ONE - c) * (T::ONE + c)).sqrt(), c)
}

/// `q` or `-q`, whichever has `w >= 0` (the same rotation, by at most half a turn).
#[inline(always)]
pub fn positive<T: Real>(q: Quat<T>) -> Quat<T> {
    if q.w < T::ZERO {
        Quat::new(-q.w, -q.x, -q.y, -q.z)
    } else {
        q
    }
}

/// The rotation vector (axis times angle in `[0, pi]`, radians) of the unit quaternion `q`:
/// its logarithm, whose length is the angle OpenSim's orientation tracking squares.
pub fn rotation_vector<T: Real>(q: Quat<T>) -> Vec3<T> {
    let q = positive(q);
    let v = q.vector();
    let s = v.norm();
    let k = if s > T::ZERO {
        T::TWO * atan2(s, q.w) / s
    } else {
        T::TWO
    };
    v * k
}

/// The angle of the rotation about the unit `axis` nearest to `q` (its twist about `axis`, in
/// `[-pi, pi]`): exact when `q` is a rotation about `axis`, the least-squares 1-DoF fit
/// otherwise.
pub fn twist<T: Real>(q: Quat<T>, axis: Vec3<T>) -> T {
    let q = positive(q);
    T::TWO * atan2(q.vector().dot(axis), q.w)
}

/// The angles `[a1, a2, a3]` of `q = R(u1, a1) R(u2, a2) R(u3, a3)` (a body-fixed sequence about
/// the orthonormal axes `u`, OpenSim's CustomJoint rotation order), middle angle in
/// `[-pi/2, pi/2]`, the others in `(-pi, pi]`. Exact for orthonormal axes; for others, the
/// decomposition in the basis they nearly form.
pub fn three_axes<T: Real>(q: Quat<T>, u: [Vec3<T>; 3]) -> [T; 3] {
    // A left-handed triple is a right-handed one with the third axis reversed: its angle
    // changes sign.
    let flip = u[0].cross(u[1]).dot(u[2]) < T::ZERO;
    let u3 = if flip { -u[2] } else { u[2] };
    // In the basis A = [u1 u2 u3] the rotation A^T R A has the quaternion (w, A^T v), and the
    // sequence becomes x, y, z.
    let v = q.vector();
    let p = Quat::new(q.w, u[0].dot(v), u[1].dot(v), u3.dot(v));
    let (w, x, y, z) = (p.w, p.x, p.y, p.z);
    let two = T::TWO;
    // R = Rx(a) Ry(b) Rz(c): R02 = sin b, R12 = -sin a cos b, R22 = cos a cos b,
    // R01 = -cos b sin c, R00 = cos b cos c.
    let r00 = T::ONE - two * (y * y + z * z);
    let r01 = two * (x * y - w * z);
    let r02 = two * (x * z + w * y);
    let r12 = two * (y * z - w * x);
    let r22 = T::ONE - two * (x * x + y * y);
    let a = atan2(-r12, r22);
    let b = atan2(r02, (r00 * r00 + r01 * r01).sqrt());
    let c = atan2(-r01, r00);
    [a, b, if flip { -c } else { c }]
}

/// The angles `[a1, a2]` of `q ≈ R(u1, a1) R(u2, a2)` for two non-parallel unit axes (the second
/// in the frame after the first rotation): `a1` turns `u2` onto `R(q) u2` about `u1` (projected
/// on the plane normal to `u1`: Paden-Kahan's first subproblem), `a2` is the twist about `u2` of
/// what remains. Exact when `q` is such a product.
pub fn two_axes<T: Real>(q: Quat<T>, u1: Vec3<T>, u2: Vec3<T>) -> [T; 2] {
    let target = q.rotate(u2);
    let p = u2 - u1 * u1.dot(u2);
    let t = target - u1 * u1.dot(target);
    let a1 = atan2(u1.dot(p.cross(t)), p.dot(t));
    let rest = Quat::from_axis_angle(u1, -a1) * q;
    [a1, twist(rest, u2)]
}

/// The rotation of OpenSim's space-fixed X-Y-Z sequence `(rx, ry, rz)` (radians):
/// `Rz(rz) Ry(ry) Rx(rx)` (SimTK's `SpaceRotationSequence`).
pub fn space_fixed_xyz<T: Real>(r: [T; 3]) -> Quat<T> {
    Quat::from_axis_angle(Vec3::unit_z(), r[2])
        * Quat::from_axis_angle(Vec3::unit_y(), r[1])
        * Quat::from_axis_angle(Vec3::unit_x(), r[0])
}

/// The unit quaternion (`w >= 0`) of the rotation matrix `m` (row-major, `m[row][column]`), by
/// Shepperd's method (from the largest of `w`, `x`, `y`, `z`, so that no division is by a small
/// number); a matrix a little off orthonormal (printed digits) gives the nearest such rotation's
/// quaternion to first order, normalised. Vendors that export orientation matrices (Xsens
/// `Mat[r][c]`) are read through it.
pub fn from_rotation_matrix<T: Real>(m: [[T; 3]; 3]) -> Quat<T> {
    let (one, quarter) = (T::ONE, T::from_f64(0.25));
    let trace = m[0][0] + m[1][1] + m[2][2];
    let q = if trace >= m[0][0] && trace >= m[1][1] && trace >= m[2][2] {
        let s = (one + trace).sqrt() * T::TWO; // 4w
        Quat::new(
            quarter * s,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        )
    } else if m[0][0] >= m[1][1] && m[0][0] >= m[2][2] {
        let s = (one + m[0][0] - m[1][1] - m[2][2]).sqrt() * T::TWO; // 4x
        Quat::new(
            (m[2][1] - m[1][2]) / s,
            quarter * s,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        )
    } else if m[1][1] >= m[2][2] {
        let s = (one + m[1][1] - m[0][0] - m[2][2]).sqrt() * T::TWO; // 4y
        Quat::new(
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            quarter * s,
            (m[1][2] + m[2][1]) / s,
        )
    } else {
        let s = (one + m[2][2] - m[0][0] - m[1][1]).sqrt() * T::TWO; // 4z
        Quat::new(
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            quarter * s,
        )
    };
    let n = q.norm();
    positive(Quat::new(q.w / n, q.x / n, q.y / n, q.z / n))
}

/// `value` moved by whole turns to within half a turn of `previous` (unchanged if either is not
/// finite).
pub(crate) fn unwrap_turns<T: Real>(value: T, previous: T) -> T {
    let d = previous - value;
    if !d.is_finite() || d.abs() <= T::from_f64(core::f64::consts::PI) {
        return value;
    }
    // In `T` (no `f64` arithmetic on the device).
    let turn = T::from_f64(core::f64::consts::TAU);
    value + (d / turn).round() * turn
}
