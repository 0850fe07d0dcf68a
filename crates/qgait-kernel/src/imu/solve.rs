//! Segment orientations to gait2392 coordinates: the closed form and the per-leg least squares.

use super::math::{rotation_vector, three_axes, twist, two_axes, unwrap_turns};
use super::{Orientations, Segment};
use crate::chain::Frame;
use crate::{Gait2392, Quat, Real, Vec3};

/// Gauss-Newton iterations per frame of [`Mode::LeastSquares`] (the default of [`Solver`]).
pub const ITERATIONS: usize = 3;

/// gait2392's lumbar coordinates, the torso relative to the pelvis about z, x, y (body-fixed):
/// OpenSim's names, in [`ImuAngles::lumbar`] order.
pub const LUMBAR: [&str; 3] = ["lumbar_extension", "lumbar_bending", "lumbar_rotation"];

/// The chain's 17 coordinates and the lumbar joint (radians).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuAngles<T> {
    /// In [`gait2392::COORDINATES`](crate::models::gait2392::COORDINATES) order.
    pub coordinates: [T; 17],
    /// In [`LUMBAR`] order.
    pub lumbar: [T; 3],
    /// Which of them kept their previous value this frame for want of a sensor: bit `i` for
    /// coordinate `i`, bits 17 to 19 for the lumbar joint (the MTP joints, which no sensor
    /// determines, are not flagged).
    pub held: u32,
}

/// How coordinates are computed from segment orientations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Each joint's relative rotation decomposed into its axes (the cheap mode).
    ClosedForm,
    /// Per leg, the coordinates that minimise the squared orientation errors of the leg's
    /// sensors (OpenSense's problem), by Gauss-Newton from the previous frame.
    LeastSquares,
}

/// One leg of the chain: its joints and coordinates.
struct Leg {
    /// Chain joints: hip (femur), knee (tibia), ankle (talus), subtalar (calcaneus).
    hip: usize,
    /// The segments with sensors: femur, tibia, calcaneus.
    segments: [Segment; 3],
    /// Index of the hip flexion coordinate; the leg's coordinates follow it (hip 3, knee,
    /// ankle, subtalar, MTP).
    first: usize,
}

const LEGS: [Leg; 2] = [
    Leg {
        hip: 1,
        segments: [Segment::FemurR, Segment::TibiaR, Segment::CalcnR],
        first: 3,
    },
    Leg {
        hip: 6,
        segments: [Segment::FemurL, Segment::TibiaL, Segment::CalcnL],
        first: 10,
    },
];

/// The unit axes of chain joint `j` (the first `N`).
fn axes<T: Real, const N: usize>(model: &Gait2392<T>, j: usize) -> [Vec3<T>; N] {
    let joint = &model.chain().joints()[j];
    core::array::from_fn(|k| joint.axes[k].direction)
}

/// The closed form (see the [module](super) docs): each joint's relative rotation decomposed
/// into its axes, for the segment orientations `segments` ([`Calibration::segments`](super::Calibration::segments)).
/// Coordinates whose segments are missing keep their value in `previous`; `pelvis_rotation`
/// is unwrapped relative to it. No coordinate is clamped: gait2392 clamps none
/// (`<clamped>false</clamped>` throughout), so OpenSense's inverse kinematics bounds none.
pub fn closed_form<T: Real>(
    model: &Gait2392<T>,
    segments: &Orientations<T>,
    previous: &ImuAngles<T>,
) -> ImuAngles<T> {
    decompose(model, segments, previous, true)
}

/// [`closed_form`], the legs only if `legs` (otherwise they keep `previous`'s values: the
/// least squares' warm start).
// Not inlined: one copy on the device whichever caller (flash; BENCHMARKS.md).
#[inline(never)]
fn decompose<T: Real>(
    model: &Gait2392<T>,
    segments: &Orientations<T>,
    previous: &ImuAngles<T>,
    legs: bool,
) -> ImuAngles<T> {
    let mut out = *previous;
    out.held = 0;
    let pelvis = segments.get(Segment::Pelvis);
    match pelvis {
        Some(p) => {
            let [tilt, list, rotation] = three_axes(p, axes(model, 0));
            out.coordinates[0] = tilt;
            out.coordinates[1] = list;
            out.coordinates[2] = unwrap_turns(rotation, previous.coordinates[2]);
        }
        None => out.held |= 0b111,
    }
    match (pelvis, segments.get(Segment::Torso)) {
        (Some(p), Some(t)) => out.lumbar = lumbar(p, t),
        _ => out.held |= 0b111 << 17,
    }
    for leg in LEGS.iter().filter(|_| legs) {
        let [femur, tibia, calcn] = leg.segments.map(|s| segments.get(s));
        let c = leg.first;
        let q = &mut out.coordinates;
        match (pelvis, femur) {
            (Some(p), Some(f)) => {
                let hip = three_axes(p.conj() * f, axes(model, leg.hip));
                for (k, angle) in hip.into_iter().enumerate() {
                    q[c + k] = angle;
                }
            }
            _ => out.held |= 0b111 << c,
        }
        match (femur, tibia) {
            (Some(f), Some(t)) => {
                let [knee] = axes(model, leg.hip + 1);
                q[c + 3] = twist(f.conj() * t, knee);
            }
            _ => out.held |= 1 << (c + 3),
        }
        match (tibia, calcn) {
            (Some(t), Some(f)) => {
                let [ankle] = axes(model, leg.hip + 2);
                let [subtalar] = axes(model, leg.hip + 3);
                let [a, s] = two_axes(t.conj() * f, ankle, subtalar);
                q[c + 4] = a;
                q[c + 5] = s;
            }
            _ => out.held |= 0b11 << (c + 4),
        }
    }
    out
}

/// The lumbar joint's coordinates ([`LUMBAR`] order: extension, bending, rotation about z, x,
/// y, body-fixed) of the torso orientation `torso` relative to the pelvis orientation `pelvis`
/// (gait2392's and Rajagopal's back joint).
pub fn lumbar<T: Real>(pelvis: Quat<T>, torso: Quat<T>) -> [T; 3] {
    let (x, y, z) = (Vec3::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    three_axes(pelvis.conj() * torso, [z, x, y])
}

/// The pelvis coordinates `[tilt, list, rotation]` re-expressed relative to a direction of
/// progression `heading` (radians about the vertical y, e.g. a smoothed `pelvis_rotation`):
/// the pelvis turned by `-heading` about the vertical and decomposed again. The solver reports
/// the pelvis in the sensors' world frame as OpenSense does; gait2392's sequence puts the
/// heading last, so there tilt and list change with the walking direction, and here they do
/// not (facing the progression direction, the pelvis is as if walking along x).
pub fn heading_free_pelvis<T: Real>(model: &Gait2392<T>, pelvis: [T; 3], heading: T) -> [T; 3] {
    let axes: [Vec3<T>; 3] = axes(model, 0);
    let p = Quat::from_axis_angle(Vec3::unit_y(), -heading)
        * Quat::from_axis_angle(axes[0], pelvis[0])
        * Quat::from_axis_angle(axes[1], pelvis[1])
        * Quat::from_axis_angle(axes[2], pelvis[2]);
    three_axes(p, axes)
}

/// Solves `(H + damping I) x = b` for the leading `n x n` block (`n <= 6`) of a symmetric
/// positive semi-definite `H` by Cholesky, in place (`h`'s lower triangle becomes the factor:
/// no second matrix on the device's stack); `None` if it is not positive definite or the result
/// is not finite. The damping (1e-6) leaves a coordinate that no sensor depends on (a zero
/// row and column, e.g. a locked joint) where it is.
#[allow(clippy::needless_range_loop)] // (index arithmetic is the algorithm)
pub(crate) fn solve_normal<T: Real>(h: &mut [[T; 6]; 6], b: &[T; 6], n: usize) -> Option<[T; 6]> {
    let n = n.min(6);
    let damping = T::from_f64(1e-6);
    // Row by row: l[i][j] (j <= i) replaces h[i][j], which is read only before.
    let l = h;
    for i in 0..n {
        for j in 0..=i {
            let mut s = l[i][j];
            if i == j {
                s += damping;
            }
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                if s <= T::ZERO {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    // Forward then back substitution, in one vector.
    let mut x = *b;
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i][k] * x[k];
        }
        x[i] = s / l[i][i];
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= l[k][i] * x[k];
        }
        x[i] = s / l[i][i];
    }
    for v in &mut x[n..] {
        *v = T::ZERO;
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The normal equations of one Gauss-Newton step, accumulated sensor by sensor: for a sensor
/// whose error rotation (model times measured inverse, in ground) has the rotation vector `r`
/// and whose predicted orientation turns by `w[a] dq[a]` (in ground) for small changes of the
/// step's coordinates, `H += W^T W` and `g -= W^T r`. Because the rotation vector's log Jacobian
/// leaves the residual unchanged (`J(r) r = r`), `W^T r = 0` is the exact stationary point of
/// the summed squared angles, so the fixed point is the exact minimiser.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NormalEquations<T> {
    h: [[T; 6]; 6],
    g: [T; 6],
    /// Whether any sensor was added.
    pub any: bool,
}

impl<T: Real> NormalEquations<T> {
    pub const fn new() -> Self {
        Self {
            h: [[T::ZERO; 6]; 6],
            g: [T::ZERO; 6],
            any: false,
        }
    }

    /// Adds one sensor: its residual `r` and its first `n` columns `w`.
    pub fn add(&mut self, r: Vec3<T>, w: &[Vec3<T>; 6], n: usize) {
        self.any = true;
        for a in 0..n {
            self.g[a] -= w[a].dot(r);
            for b in 0..=a {
                self.h[a][b] += w[a].dot(w[b]);
            }
        }
    }

    /// The step for the first `n` coordinates (`None` if singular or not finite).
    pub fn step(mut self, n: usize) -> Option<[T; 6]> {
        // The factorisation reads the lower triangle only.
        solve_normal(&mut self.h, &self.g, n)
    }

    /// The step for the first `n` coordinates `q` within the bounds `min`, `max` (an active
    /// set): a coordinate at a bound that the step would push beyond it is held there (its
    /// row and column removed) and the others solved again without it, until no step leaves
    /// the box; the result is then clamped. Without this, a coordinate resting on its bound
    /// (a straight knee at 0) would pull the others towards its unconstrained step every
    /// iteration and the solve would settle away from the bounded minimiser.
    pub fn bounded_step(self, n: usize, q: &[T; 6], min: &[T; 6], max: &[T; 6]) -> Option<[T; 6]> {
        let mut system = self;
        let mut held = [false; 6];
        for a in 0..6 {
            for b in a + 1..6 {
                system.h[a][b] = system.h[b][a];
            }
        }
        loop {
            let mut factor = system.h;
            let step = solve_normal(&mut factor, &system.g, n)?;
            let mut changed = false;
            for k in 0..n {
                let beyond =
                    (q[k] <= min[k] && step[k] < T::ZERO) || (q[k] >= max[k] && step[k] > T::ZERO);
                if beyond && !held[k] {
                    held[k] = true;
                    changed = true;
                    for j in 0..6 {
                        system.h[k][j] = T::ZERO;
                        system.h[j][k] = T::ZERO;
                    }
                    system.g[k] = T::ZERO;
                }
            }
            if !changed {
                let mut out = [T::ZERO; 6];
                for k in 0..n {
                    out[k] = (q[k] + step[k]).max(min[k]).min(max[k]) - q[k];
                }
                return Some(out);
            }
        }
    }
}

/// The chain's joint frames at `q`: one copy of [`Chain::frames`](crate::Chain::frames) for the
/// solver and the calibration on the device (not inlined into each: flash).
#[inline(never)]
pub(crate) fn frames<T: Real>(model: &Gait2392<T>, q: &[T; 17]) -> [Frame<T>; 11] {
    model.chain().frames(q)
}

/// One Gauss-Newton step of one leg at the chain frames `frames` of coordinates `q`: updates
/// the leg's six coordinates in `q`, unless no sensor of the leg is present.
// Not inlined: one copy on the device whichever caller (flash; BENCHMARKS.md).
#[inline(never)]
fn gauss_newton_step<T: Real>(
    model: &Gait2392<T>,
    leg: &Leg,
    frames: &[Frame<T>; 11],
    segments: &Orientations<T>,
    q: &mut [T; 17],
) {
    let c = leg.first;
    // The six coordinates' axes in ground: the hip's three (body-fixed: the first in the
    // pelvis frame, the second after the first rotation, the third in the femur frame), then
    // the knee, ankle and subtalar axes in their child frames.
    let [h1, h2, h3] = axes(model, leg.hip);
    let pelvis = frames[0].rotation;
    let after_flexion = pelvis * Quat::from_axis_angle(h1, q[c]);
    let one = |j: usize| {
        let [a] = axes(model, j);
        frames[j].rotation.rotate(a)
    };
    let w = [
        pelvis.rotate(h1),
        after_flexion.rotate(h2),
        frames[leg.hip].rotation.rotate(h3),
        one(leg.hip + 1),
        one(leg.hip + 2),
        one(leg.hip + 3),
    ];
    // Femur: hip only; tibia: hip and knee; calcaneus: all six.
    let bodies = [(leg.hip, 3), (leg.hip + 1, 4), (leg.hip + 3, 6)];
    let mut normal = NormalEquations::new();
    for (segment, (body, n)) in leg.segments.into_iter().zip(bodies) {
        let Some(measured) = segments.get(segment) else {
            continue;
        };
        // The error rotation in ground, model times measured inverse: the model's prediction
        // turned by w_i dq_i moves it by w_i dq_i to first order.
        let r = rotation_vector(frames[body].rotation * measured.conj());
        normal.add(r, &w, n);
    }
    if !normal.any {
        return;
    }
    if let Some(step) = normal.step(6) {
        for (k, d) in step.into_iter().enumerate() {
            q[c + k] += d;
        }
    }
}

/// The state kept from frame to frame: the previous solution (warm start, held coordinates,
/// unwrapping) and the iteration count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solver<T> {
    previous: ImuAngles<T>,
    /// Whether `previous` holds a solution (false before the first frame and after a reset).
    started: bool,
    /// Gauss-Newton iterations per frame in [`Mode::LeastSquares`].
    pub iterations: usize,
}

impl<T: Real> Default for Solver<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> Solver<T> {
    /// A solver with [`ITERATIONS`] iterations, before its first frame
    /// (every coordinate zero).
    pub fn new() -> Self {
        Self {
            previous: ImuAngles::default(),
            started: false,
            iterations: ITERATIONS,
        }
    }

    /// Forgets the previous frame: the next frame starts from the closed form, and held
    /// coordinates from zero.
    pub fn reset(&mut self) {
        self.previous = ImuAngles::default();
        self.started = false;
    }

    /// The last frame's solution (all zero before the first).
    pub fn previous(&self) -> &ImuAngles<T> {
        &self.previous
    }

    /// The coordinates for one frame's segment orientations
    /// ([`Calibration::segments`](super::Calibration::segments)), in `mode`; remembered for
    /// the next frame.
    pub fn solve(
        &mut self,
        model: &Gait2392<T>,
        segments: &Orientations<T>,
        mode: Mode,
    ) -> ImuAngles<T> {
        // The least squares starts from the previous frame's legs once it has one (the
        // closed form only for the pelvis and lumbar joint), from the closed form before.
        let legs = mode == Mode::ClosedForm || !self.started;
        let mut out = decompose(model, segments, &self.previous, legs);
        if mode == Mode::LeastSquares {
            let mut q = out.coordinates;
            for _ in 0..self.iterations {
                let frames = frames(model, &q);
                for leg in &LEGS {
                    gauss_newton_step(model, leg, &frames, segments, &mut q);
                }
            }
            out.coordinates = q;
            // Held: the coordinates that no present sensor depends on.
            out.held &= !(0x3fff << 3);
            for leg in &LEGS {
                let present = leg.segments.map(|s| segments.get(s).is_some());
                let hip = present.iter().any(|&p| p);
                let knee = present[1] || present[2];
                let foot = present[2];
                let c = leg.first;
                if !hip {
                    out.held |= 0b111 << c;
                }
                if !knee {
                    out.held |= 1 << (c + 3);
                }
                if !foot {
                    out.held |= 0b11 << (c + 4);
                }
            }
            if segments.get(Segment::Pelvis).is_none() {
                out.held |= 0b111;
            }
        }
        self.previous = out;
        self.started = true;
        out
    }
}
