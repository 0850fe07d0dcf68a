//! The least squares for any chain model whose bodies carry the sensors: PHAK (the paper's
//! 8-DoF model, solved on its own axes) and imported OpenSim chains ([`LowerLimb`](crate::models::LowerLimb): Rajagopal,
//! gait10dof18musc, ...; oriented frames, spline-coupled rotations, couplers).
//!
//! The problem is OpenSense's, as for gait2392 ([`Solver`](super::Solver)): per frame, the
//! coordinates that minimise the sum of the squared angles between each sensor's segment
//! orientation ([`Calibration::segments`](super::Calibration::segments)) and the model's
//! prediction of it. It splits into independent groups (a group's coordinates move only its
//! sensors' bodies): the pelvis (its coordinates, fitted to the pelvis sensor, and to the torso
//! sensor too when the lumbar joint is locked: [`FitSolver::torso_on_pelvis`]) and each leg
//! (its coordinates, fitted to femur, tibia and calcaneus). Each group is solved by
//! Gauss-Newton with the same normal equations as gait2392's analytic solver; the Jacobian's
//! columns (each coordinate's angular velocity of each sensor's body, in ground) are central
//! differences of the model's own body orientations ([`FitModel::orientations`]), so one code
//! serves every joint type, spline and coupler the chain can say. The fixed point is the exact
//! minimiser up to the Jacobian's small errors times the residual (below 1e-8 degrees in `f64`;
//! in `f32` the whole solve follows `f64` within 0.005 degrees on the tutorial recording).
//!
//! Start: the pelvis from its sensor by a closed form on the model's pelvis axes
//! ([`FitModel::pelvis_start`]), its heading unwrapped to within half a turn of the previous
//! frame's, then refined; the legs from the previous frame's solution, and on the first frame
//! (and after [`FitSolver::reset`]) from the default pose with [`FIRST_ITERATIONS`] iterations.
//! `no_std`, no allocation, `f32` and `f64`.

use super::math::{rotation_vector, three_axes, twist, unwrap_turns};
use super::solve::NormalEquations;
use super::{Orientations, Segment, SENSORS};
use crate::models::custom::{Argument, CustomChain};
use crate::models::Phak;
use crate::{Quat, Real, Vec3};

/// Gauss-Newton iterations of the legs on the first frame (from the default pose).
pub const FIRST_ITERATIONS: usize = 20;

/// A model the generic least squares fits.
pub trait FitModel<T: Real, const N: usize> {
    /// The pelvis's coordinates (up to 3), in [`pelvis_start`](Self::pelvis_start) order.
    const PELVIS: &'static [usize];
    /// The pelvis coordinate that is the heading (about the vertical): unbounded, unwrapped.
    const HEADING: usize;
    /// Each leg's coordinates (up to 6), right then left: they move only that leg's femur,
    /// tibia and calcaneus.
    const LEGS: [&'static [usize]; 2];
    /// The orientation (body to ground) of the body that carries each segment's sensor, at
    /// coordinates `q`; `None` for a segment the model does not have.
    fn orientations(&self, q: &[T; N]) -> [Option<Quat<T>>; SENSORS];
    /// The pelvis coordinates ([`PELVIS`](Self::PELVIS) order) of the pelvis orientation
    /// `pelvis`, by a closed form on the model's pelvis axes (exact for orthogonal axes).
    fn pelvis_start(&self, pelvis: Quat<T>) -> [T; 3];
}

/// The segments whose sensors each leg's coordinates fit, right then left.
const LEG_SENSORS: [[Segment; 3]; 2] = [
    [Segment::FemurR, Segment::TibiaR, Segment::CalcnR],
    [Segment::FemurL, Segment::TibiaL, Segment::CalcnL],
];

/// PHAK's coordinates ([`PhakAngles::NAMES`](crate::PhakAngles::NAMES)) from the sensors:
/// the pelvis's rotation (about the vertical) and list (about the forward axis) from the pelvis
/// sensor; per leg, hip flexion, knee and ankle (all about the pelvis's lateral axis) from the
/// femur, tibia and calcaneus sensors. PHAK's ankle carries the foot: the calcaneus sensor is
/// on it. No torso.
impl<T: Real> FitModel<T, 8> for Phak<T> {
    const PELVIS: &'static [usize] = &[0, 1];
    const HEADING: usize = 0;
    const LEGS: [&'static [usize]; 2] = [&[2, 3, 4], &[5, 6, 7]];

    fn orientations(&self, q: &[T; 8]) -> [Option<Quat<T>>; SENSORS] {
        let f = self.chain().frames(q);
        // Joints: pelvis, right hip, knee, ankle, left hip, knee, ankle.
        let mut out = [None; SENSORS];
        for (segment, joint) in [
            (Segment::Pelvis, 0),
            (Segment::FemurR, 1),
            (Segment::TibiaR, 2),
            (Segment::CalcnR, 3),
            (Segment::FemurL, 4),
            (Segment::TibiaL, 5),
            (Segment::CalcnL, 6),
        ] {
            out[segment as usize] = Some(f[joint].rotation);
        }
        out
    }

    fn pelvis_start(&self, pelvis: Quat<T>) -> [T; 3] {
        // Rotation about y, then list about x (body-fixed); a third, z, takes up what PHAK's
        // pelvis cannot do (tilt) and is dropped.
        let [rotation, list, _] =
            three_axes(pelvis, [Vec3::unit_y(), Vec3::unit_x(), Vec3::unit_z()]);
        [rotation, list, T::ZERO]
    }
}

/// An imported OpenSim lower-limb chain ([`LowerLimb`](crate::models::LowerLimb)): gait2392's
/// 17 coordinates and bodies (pelvis, then femur, tibia, talus, calcaneus, toes per side). The
/// sensors sit on pelvis, femurs, tibias and calcanei; per leg the hip's three coordinates,
/// the knee, the ankle and the subtalar are fitted (a locked one, a constant in the chain, has
/// no effect and stays). No torso.
impl<T: Real, const P: usize> FitModel<T, 17> for CustomChain<T, 17, 11, P> {
    const PELVIS: &'static [usize] = &[0, 1, 2];
    const HEADING: usize = 2;
    const LEGS: [&'static [usize]; 2] = [&[3, 4, 5, 6, 7, 8], &[10, 11, 12, 13, 14, 15]];

    fn orientations(&self, q: &[T; 17]) -> [Option<Quat<T>>; SENSORS] {
        let f = self.frames(q);
        let mut out = [None; SENSORS];
        for segment in Segment::ALL {
            if let Some(b) = segment.chain_joint() {
                out[segment as usize] = Some(f[b].rotation);
            }
        }
        out
    }

    fn pelvis_start(&self, pelvis: Quat<T>) -> [T; 3] {
        // The pelvis joint's rotation between its offset frames: R = F R(q) M^-1.
        let joint = &self.joints()[0];
        let inner = joint.in_parent.rotation.conj() * pelvis * joint.in_child.rotation;
        let mut out = [T::ZERO; 3];
        let driven: [Option<usize>; 3] = joint.rotations.map(|d| match d.argument {
            Argument::Coordinate(i) if i < 3 => Some(i),
            _ => None,
        });
        if driven.iter().all(Option::is_some) {
            let angles = three_axes(inner, joint.rotations.map(|d| d.axis));
            for (i, a) in driven.into_iter().zip(angles) {
                out[i.unwrap_or(0)] = a;
            }
        } else {
            // Fewer pelvis rotations (a planar model): each the twist about its axis.
            for (i, d) in driven.into_iter().zip(&joint.rotations) {
                if let Some(i) = i {
                    out[i] = twist(inner, d.axis);
                }
            }
        }
        out
    }
}

/// One frame's solution of [`FitSolver`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitAngles<T, const N: usize> {
    /// The model's coordinates (radians).
    pub coordinates: [T; N],
    /// Which of them kept their previous value this frame for want of a sensor (bit `i` for
    /// coordinate `i`).
    pub held: u32,
}

/// The generic least squares, frame by frame (see the [module](self) docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSolver<T, const N: usize> {
    previous: [T; N],
    started: bool,
    /// Lower bounds of the coordinates (radians; the heading is never clamped).
    pub min: [T; N],
    /// Upper bounds.
    pub max: [T; N],
    /// Gauss-Newton iterations per frame after the first.
    pub iterations: usize,
    /// Fit the pelvis to the torso sensor as well (the torso then moves with the pelvis): what
    /// OpenSense does when the model's lumbar joint is locked (Rajagopal2015_opensense).
    pub torso_on_pelvis: bool,
}

impl<T: Real, const N: usize> Default for FitSolver<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real, const N: usize> FitSolver<T, N> {
    /// Unbounded coordinates, [`ITERATIONS`](super::ITERATIONS) iterations, torso free.
    pub fn new() -> Self {
        Self {
            previous: [T::ZERO; N],
            started: false,
            min: [T::from_f64(f64::NEG_INFINITY); N],
            max: [T::from_f64(f64::INFINITY); N],
            iterations: super::ITERATIONS,
            torso_on_pelvis: false,
        }
    }

    /// Forgets the previous frame: the next starts from the default pose.
    pub fn reset(&mut self) {
        self.previous = [T::ZERO; N];
        self.started = false;
    }

    /// The previous frame's coordinates (zero before the first).
    pub fn previous(&self) -> &[T; N] {
        &self.previous
    }

    /// The model's predicted sensor orientations at `q` (the torso on the pelvis if
    /// [`torso_on_pelvis`](Self::torso_on_pelvis)).
    fn predicted<M: FitModel<T, N>>(&self, model: &M, q: &[T; N]) -> [Option<Quat<T>>; SENSORS] {
        let mut o = model.orientations(q);
        if self.torso_on_pelvis {
            o[Segment::Torso as usize] = o[Segment::Pelvis as usize];
        }
        o
    }

    /// One Gauss-Newton step of the group `coordinates` on the sensors `sensors`; `false` if
    /// none of them has a reading (nothing changes).
    fn step<M: FitModel<T, N>>(
        &self,
        model: &M,
        q: &mut [T; N],
        coordinates: &[usize],
        sensors: &[Segment],
        measured: &Orientations<T>,
    ) -> bool {
        let n = coordinates.len().min(6);
        let base = self.predicted(model, q);
        // Central differences, the step about the cube root of the precision (2e-3 in f32,
        // 1e-5 in f64): truncation (h^2) and rounding (eps / h) then balance. In f32 the
        // columns are then good to about 1e-5 (forward differences: 1e-3, which slows the
        // warm-started iterations enough to lag a swinging knee by hundredths of a degree).
        let h = T::from_f64(if T::from_f64(1.0 + 1e-10) == T::ONE {
            2e-3
        } else {
            1e-5
        });
        let mut columns = [[Vec3::zero(); 6]; SENSORS];
        for (k, &c) in coordinates.iter().take(n).enumerate() {
            let (mut ahead, mut behind) = (*q, *q);
            ahead[c] += h;
            behind[c] -= h;
            let (after, before) = (
                self.predicted(model, &ahead),
                self.predicted(model, &behind),
            );
            for &s in sensors {
                // Bitwise the same: the coordinate does not move this body (a locked joint,
                // a distal coordinate), and its column is exactly zero (the product's rounding
                // would leave a tiny one, which the damping turns into a spurious step).
                match (after[s as usize], before[s as usize]) {
                    (Some(a), Some(b)) if a != b => {
                        columns[s as usize][k] = rotation_vector(a * b.conj()) * (T::ONE / (h + h));
                    }
                    _ => {}
                }
            }
        }
        let mut normal = NormalEquations::new();
        for &s in sensors {
            if let (Some(m), Some(p)) = (measured.get(s), base[s as usize]) {
                normal.add(rotation_vector(p * m.conj()), &columns[s as usize], n);
            }
        }
        if !normal.any {
            return false;
        }
        let inf = T::from_f64(f64::INFINITY);
        let mut at = [T::ZERO; 6];
        let (mut min, mut max) = ([-inf; 6], [inf; 6]);
        for (k, &c) in coordinates.iter().take(n).enumerate() {
            at[k] = q[c];
            if c != M::HEADING {
                (min[k], max[k]) = (self.min[c], self.max[c]);
            }
        }
        if let Some(step) = normal.bounded_step(n, &at, &min, &max) {
            for (k, &c) in coordinates.iter().take(n).enumerate() {
                q[c] += step[k];
            }
        }
        true
    }

    /// The coordinates for one frame's segment orientations, remembered for the next frame.
    pub fn solve<M: FitModel<T, N>>(
        &mut self,
        model: &M,
        segments: &Orientations<T>,
    ) -> FitAngles<T, N> {
        let mut q = self.previous;
        let mut held = 0u32;
        let pelvis_sensors: &[Segment] = if self.torso_on_pelvis {
            &[Segment::Pelvis, Segment::Torso]
        } else {
            &[Segment::Pelvis]
        };
        match segments.get(Segment::Pelvis) {
            Some(p) => {
                let start = model.pelvis_start(p);
                for (&c, v) in M::PELVIS.iter().zip(start) {
                    q[c] = if c == M::HEADING {
                        unwrap_turns(v, self.previous[c])
                    } else {
                        v
                    };
                }
                for _ in 0..self.iterations {
                    self.step(model, &mut q, M::PELVIS, pelvis_sensors, segments);
                }
            }
            None => {
                for &c in M::PELVIS {
                    held |= 1 << c;
                }
            }
        }
        let iterations = if self.started {
            self.iterations
        } else {
            FIRST_ITERATIONS
        };
        for (coordinates, sensors) in M::LEGS.iter().zip(&LEG_SENSORS) {
            for _ in 0..iterations {
                if !self.step(model, &mut q, coordinates, sensors, segments) {
                    for &c in *coordinates {
                        held |= 1 << c;
                    }
                    break;
                }
            }
        }
        self.previous = q;
        self.started = true;
        FitAngles {
            coordinates: q,
            held,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anthropometry::Anthropometry;

    /// PHAK's own poses come back exactly from their own segment orientations, through a
    /// calibration with arbitrary sensor mountings, in `f64` and `f32`.
    #[test]
    fn phak_recovers_its_own_angles() {
        let phak = Phak::<f64>::new(&Anthropometry::gait2392()).unwrap();
        let mut solver = FitSolver::<f64, 8>::new();
        for k in 0..200 {
            let t = k as f64 * 0.01;
            let q: [f64; 8] = core::array::from_fn(|i| {
                0.5 * libm::sin(2.0 * t + i as f64) + if i == 0 { 3.0 * t } else { 0.0 }
            });
            let mut o = Orientations::EMPTY;
            for (s, r) in Segment::ALL.into_iter().zip(phak.orientations(&q)) {
                o.set(s, r);
            }
            let got = solver.solve(&phak, &o);
            for i in 0..8 {
                assert!(
                    (got.coordinates[i] - q[i]).abs() < 1e-9,
                    "{k} {i}: {:?} {q:?}",
                    got.coordinates
                );
            }
            assert_eq!(got.held, 0);
        }
        let phak32 = Phak::<f32>::new(&Anthropometry::<f64>::gait2392().cast()).unwrap();
        let mut solver = FitSolver::<f32, 8>::new();
        let q = [2.0f32, 0.1, 0.4, -0.9, 0.2, -0.3, -0.1, -0.2];
        let mut o = Orientations::EMPTY;
        for (s, r) in Segment::ALL.into_iter().zip(phak32.orientations(&q)) {
            o.set(s, r);
        }
        let got = solver.solve(&phak32, &o);
        for (i, (a, b)) in got.coordinates.iter().zip(&q).enumerate() {
            assert!((a - b).abs() < 1e-4, "{i}: {:?}", got.coordinates);
        }
    }

    /// A coordinate held on its bound: the others settle at the bounded minimiser (the cost's
    /// gradient along them zero, the bounded one's pointing out of the box), not where the
    /// bounded one's unconstrained steps would pull them.
    #[test]
    fn a_coordinate_on_its_bound_leaves_the_others_at_the_bounded_minimiser() {
        let phak = Phak::<f64>::new(&Anthropometry::gait2392()).unwrap();
        // Truth: the right knee hyperextended by 0.3 rad and the tibia twisted off the
        // model's plane, so nothing fits exactly; the knee is bounded above by 0.
        let q = [0.2, 0.05, 0.3, 0.3, -0.2, 0.1, -0.4, 0.1];
        let mut o = Orientations::EMPTY;
        for (s, r) in Segment::ALL.into_iter().zip(phak.orientations(&q)) {
            o.set(s, r);
        }
        let twist = Quat::from_axis_angle(Vec3::unit_y(), 0.2);
        o.set(Segment::TibiaR, o.get(Segment::TibiaR).map(|t| t * twist));
        let mut solver = FitSolver::<f64, 8>::new();
        solver.max[3] = 0.0;
        let got = solver.solve(&phak, &o).coordinates;
        assert_eq!(got[3], 0.0);
        let cost = |q: &[f64; 8]| {
            let p = phak.orientations(q);
            [Segment::FemurR, Segment::TibiaR, Segment::CalcnR]
                .iter()
                .map(|s| {
                    let r = rotation_vector(p[*s as usize].unwrap() * o.get(*s).unwrap().conj());
                    r.dot(r)
                })
                .sum::<f64>()
        };
        let gradient = |i: usize| {
            let (mut a, mut b) = (got, got);
            a[i] += 1e-6;
            b[i] -= 1e-6;
            (cost(&a) - cost(&b)) / 2e-6
        };
        for i in [2, 4] {
            assert!(gradient(i).abs() < 1e-7, "{i}: {}", gradient(i));
        }
        // The knee would lower the cost by going beyond its bound.
        assert!(gradient(3) < -1e-3, "{}", gradient(3));
    }
}
