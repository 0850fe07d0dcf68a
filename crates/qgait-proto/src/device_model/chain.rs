//! Imported lower-limb chains as they travel: [`ChainUpload::of_chain`] cuts a kernel chain
//! (the host's `LowerLimb<f64>`) into its parts (numbers rounded to `f32`), [`ChainParts`]
//! gathers the parts of one upload on the hub and builds the kernel's chain from them in `f32`
//! ([`DeviceChain`], splines' coefficients computed in `f32`), and [`chain_pose`] is a chain's
//! pose from a sample's angles, on both sides. The chain's fields are copied between the wire
//! and the kernel here and nowhere else.

use qgait_kernel::models::custom::{
    Argument, BodyPoint, Coupler, CustomChain, CustomJoint, Driven, Function, Functions, Offset,
    MAX_COUPLERS,
};
use qgait_kernel::{BilateralPose, Gait2392Pose, Quat, Real, Spline, Vec3};

use crate::device_model::ConfigError;
use crate::{
    ChainArgument, ChainAxes, ChainAxis, ChainConfig, ChainCoupler, ChainFunction, ChainJoint,
    ChainOffset, ChainPoint, ChainSpline, JointId, MissingPolicy, CHAIN_BODIES, CHAIN_GROUND,
    MAX_CHAIN_COUPLERS, MAX_CHAIN_KNOTS, MAX_CHAIN_SPLINES,
};

// The wire's couplers always fit the kernel's table.
const _: () = assert!(MAX_CHAIN_COUPLERS <= MAX_COUPLERS);

/// Output points of a chain: per side (right first) hip, knee, ankle, subtalar and MTP centres,
/// then the toe tip (the kernel's `gait2392::POINTS` order).
pub const CHAIN_POINTS: usize = 12;

/// The chain a hub computes with: the 17 coordinates in [`JointId`] order, [`CHAIN_BODIES`]
/// bodies, [`CHAIN_POINTS`] points, up to [`MAX_CHAIN_SPLINES`] splines of up to
/// [`MAX_CHAIN_KNOTS`] knots, no polynomials (the wire has none), in `f32`.
pub type DeviceChain = CustomChain<
    f32,
    { JointId::COUNT },
    CHAIN_BODIES,
    CHAIN_POINTS,
    MAX_CHAIN_SPLINES,
    MAX_CHAIN_KNOTS,
    0,
>;

/// A lower-limb chain of any size (the host's `LowerLimb` is `S = 12`, `K = 16`, `Q = 12`).
pub type LowerLimbChain<T, const S: usize, const K: usize, const Q: usize> =
    CustomChain<T, { JointId::COUNT }, CHAIN_BODIES, CHAIN_POINTS, S, K, Q>;

/// The pose of a chain from a sample's angles (indexed by [`JointId::index`], the chain's
/// coordinate order): hip, knee, ankle and toe tip of each leg.
#[inline(always)]
pub fn chain_pose<T: Real, const S: usize, const K: usize, const Q: usize>(
    chain: &LowerLimbChain<T, S, K, Q>,
    angles: &[T; JointId::COUNT],
) -> BilateralPose<T> {
    Gait2392Pose {
        points: chain.forward(angles),
    }
    .bilateral()
}

/// The body a point `k` (`0..CHAIN_POINTS`, not a toe tip) is the joint centre of.
const fn centre_body(k: usize) -> usize {
    1 + 5 * (k / 6) + k % 6
}

/// Whether point `k` is a toe tip (5 and 11).
const fn is_toe_tip(k: usize) -> bool {
    k % 6 == 5
}

/// Every part of a chain as a host sends it: the joints, then the axes, then the splines, then
/// the [`ChainConfig`] ([`config`](Self::config)).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainUpload {
    /// The upload id.
    pub upload: u8,
    /// One per body.
    pub joints: [ChainJoint; CHAIN_BODIES],
    /// One per body.
    pub axes: [ChainAxes; CHAIN_BODIES],
    /// The splines, in index order.
    pub splines: heapless::Vec<ChainSpline, MAX_CHAIN_SPLINES>,
    /// The couplers.
    pub couplers: heapless::Vec<ChainCoupler, MAX_CHAIN_COUPLERS>,
    /// The toe tips, right then left.
    pub toe_tips: [ChainPoint; 2],
}

fn offset_part<T: Real>(o: &Offset<T>) -> ChainOffset {
    let q = o.rotation;
    ChainOffset {
        translation: o.translation.to_array().map(f),
        rotation: [q.w, q.x, q.y, q.z].map(f),
    }
}

fn f<T: Real>(x: T) -> f32 {
    x.to_f64() as f32
}

fn function_part<T: Real>(fun: &Function<T>) -> Result<ChainFunction, ConfigError> {
    Ok(match *fun {
        Function::Constant(c) => ChainFunction::Constant(f(c)),
        Function::Linear { slope, intercept } => ChainFunction::Linear {
            slope: f(slope),
            intercept: f(intercept),
        },
        Function::Spline(k) => ChainFunction::Spline(small(k)?),
        Function::Polynomial(_) => return Err(ConfigError::ChainPolynomial),
    })
}

fn small(i: usize) -> Result<u8, ConfigError> {
    u8::try_from(i).map_err(|_| ConfigError::ChainTooLarge)
}

fn axis_part<T: Real>(d: &Driven<T>) -> Result<ChainAxis, ConfigError> {
    Ok(ChainAxis {
        axis: d.axis.to_array().map(f),
        function: function_part(&d.function)?,
        argument: match d.argument {
            Argument::None => ChainArgument::None,
            Argument::Coordinate(i) => ChainArgument::Coordinate(small(i)?),
            Argument::Coupled(k) => ChainArgument::Coupled(small(k)?),
        },
    })
}

/// The axes that move (the kernel's table has dropped zero constants and put the moving ones
/// first; what is left is [`Driven::NONE`]).
fn moving_parts<T: Real>(
    axes: &[Driven<T>; 3],
) -> Result<heapless::Vec<ChainAxis, 3>, ConfigError> {
    let mut out = heapless::Vec::new();
    for d in axes
        .iter()
        .filter(|d| d.function != Function::Constant(T::ZERO))
    {
        // At most 3 from 3.
        let _ = out.push(axis_part(d)?);
    }
    Ok(out)
}

impl ChainUpload {
    /// The parts of `chain` (numbers rounded to `f32`) under `upload`. Fails if it has more
    /// splines or knots than the hub holds ([`MAX_CHAIN_SPLINES`], [`MAX_CHAIN_KNOTS`]), or if
    /// its points are not the joint centres of the leg bodies and a toe tip per side, or if it
    /// has polynomials (the wire carries none: [`ConfigError::ChainPolynomial`]).
    pub fn of_chain<T: Real, const S: usize, const K: usize, const Q: usize>(
        chain: &LowerLimbChain<T, S, K, Q>,
        upload: u8,
    ) -> Result<ChainUpload, ConfigError> {
        let points = chain.points();
        let mut joints = [ChainJoint {
            upload,
            body: 0,
            parent: CHAIN_GROUND,
            in_parent: offset_part(&Offset::<f32>::IDENTITY),
            in_child: offset_part(&Offset::<f32>::IDENTITY),
            point: [0.0; 3],
        }; CHAIN_BODIES];
        let mut axes: [ChainAxes; CHAIN_BODIES] = core::array::from_fn(|_| ChainAxes {
            upload,
            body: 0,
            rotations: heapless::Vec::new(),
            translations: heapless::Vec::new(),
        });
        for (b, (joint, (part, a))) in chain
            .joints()
            .iter()
            .zip(joints.iter_mut().zip(axes.iter_mut()))
            .enumerate()
        {
            part.body = b as u8;
            part.parent = match joint.parent {
                None => CHAIN_GROUND,
                Some(p) => small(p)?,
            };
            part.in_parent = offset_part(&joint.in_parent);
            part.in_child = offset_part(&joint.in_child);
            a.body = b as u8;
            a.rotations = moving_parts(&joint.rotations)?;
            a.translations = moving_parts(&joint.translations)?;
        }
        let mut toe_tips = [ChainPoint {
            body: 0,
            offset: [0.0; 3],
        }; 2];
        for (k, p) in points.iter().enumerate() {
            if is_toe_tip(k) {
                toe_tips[k / 6] = ChainPoint {
                    body: small(p.body)?,
                    offset: p.offset.to_array().map(f),
                };
            } else if p.body == centre_body(k) {
                joints[p.body].point = p.offset.to_array().map(f);
            } else {
                return Err(ConfigError::ChainTooLarge);
            }
        }
        let mut splines = heapless::Vec::new();
        for (index, s) in chain.splines().iter().enumerate() {
            let (x, y) = s.knots();
            let mut knots = heapless::Vec::new();
            for (x, y) in x.iter().zip(y) {
                knots
                    .push([f(*x), f(*y)])
                    .map_err(|_| ConfigError::ChainTooLarge)?;
            }
            splines
                .push(ChainSpline {
                    upload,
                    index: small(index)?,
                    linear: s.is_piecewise_linear(),
                    knots,
                })
                .map_err(|_| ConfigError::ChainTooLarge)?;
        }
        let mut couplers = heapless::Vec::new();
        for c in chain.couplers() {
            couplers
                .push(ChainCoupler {
                    independent: small(c.independent)?,
                    function: function_part(&c.function)?,
                })
                .map_err(|_| ConfigError::ChainTooLarge)?;
        }
        Ok(ChainUpload {
            upload,
            joints,
            axes,
            splines,
            couplers,
            toe_tips,
        })
    }

    /// The [`ChainConfig`] that switches a hub to this chain, with these settings.
    pub fn config(
        &self,
        missing_policy: MissingPolicy,
        reorder_window: u8,
        request_status: bool,
    ) -> ChainConfig {
        ChainConfig {
            upload: self.upload,
            splines: self.splines.len() as u8,
            couplers: self.couplers.clone(),
            toe_tips: self.toe_tips,
            missing_policy,
            reorder_window,
            request_status,
        }
    }
}

/// The parts of one chain upload received so far, as they arrived (a hub's; fixed size).
#[derive(Debug, Clone)]
pub struct ChainParts {
    upload: Option<u8>,
    /// Which joints, axes and splines are held (bit per body or index).
    joints_held: u16,
    axes_held: u16,
    splines_held: u8,
    joints: [ChainJoint; CHAIN_BODIES],
    axes: [ChainAxes; CHAIN_BODIES],
    splines: [ChainSpline; MAX_CHAIN_SPLINES],
}

const NO_OFFSET: ChainOffset = ChainOffset {
    translation: [0.0; 3],
    rotation: [1.0, 0.0, 0.0, 0.0],
};
const NO_JOINT: ChainJoint = ChainJoint {
    upload: 0,
    body: 0,
    parent: CHAIN_GROUND,
    in_parent: NO_OFFSET,
    in_child: NO_OFFSET,
    point: [0.0; 3],
};
const NO_AXES: ChainAxes = ChainAxes {
    upload: 0,
    body: 0,
    rotations: heapless::Vec::new(),
    translations: heapless::Vec::new(),
};
const NO_SPLINE: ChainSpline = ChainSpline {
    upload: 0,
    index: 0,
    linear: false,
    knots: heapless::Vec::new(),
};

/// Every body's bit.
const ALL_BODIES: u16 = (1 << CHAIN_BODIES) - 1;

impl Default for ChainParts {
    fn default() -> Self {
        ChainParts::new()
    }
}

impl ChainParts {
    /// No parts.
    pub const fn new() -> Self {
        ChainParts {
            upload: None,
            joints_held: 0,
            axes_held: 0,
            splines_held: 0,
            joints: [NO_JOINT; CHAIN_BODIES],
            axes: [NO_AXES; CHAIN_BODIES],
            splines: [NO_SPLINE; MAX_CHAIN_SPLINES],
        }
    }

    /// Discards the parts held if they are of another upload than `upload`.
    fn start(&mut self, upload: u8) {
        if self.upload != Some(upload) {
            *self = ChainParts {
                upload: Some(upload),
                ..ChainParts::new()
            };
        }
    }

    /// Keeps a joint part (a part of another upload discards the parts held first, one for a
    /// body already held replaces it). `false` (nothing kept) for a body out of range.
    pub fn add_joint(&mut self, part: &ChainJoint) -> bool {
        let b = usize::from(part.body);
        if b >= CHAIN_BODIES {
            return false;
        }
        self.start(part.upload);
        self.joints[b] = *part;
        self.joints_held |= 1 << b;
        true
    }

    /// Keeps an axes part (as [`add_joint`](Self::add_joint)).
    pub fn add_axes(&mut self, part: &ChainAxes) -> bool {
        let b = usize::from(part.body);
        if b >= CHAIN_BODIES {
            return false;
        }
        self.start(part.upload);
        self.axes[b] = part.clone();
        self.axes_held |= 1 << b;
        true
    }

    /// Keeps a spline part (as [`add_joint`](Self::add_joint)); `false` for an index out of
    /// range.
    pub fn add_spline(&mut self, part: &ChainSpline) -> bool {
        let k = usize::from(part.index);
        if k >= MAX_CHAIN_SPLINES {
            return false;
        }
        self.start(part.upload);
        self.splines[k] = part.clone();
        self.splines_held |= 1 << k;
        true
    }

    /// The upload whose parts are held, if any.
    pub fn upload(&self) -> Option<u8> {
        self.upload
    }

    /// Builds the chain `config` names from the parts held, in `f32`: every joint, every axes
    /// part and the first `config.splines` splines must be held, and the kernel must accept
    /// the chain (finite numbers, unit quaternions, non-zero axes, parents before children,
    /// indices in range, 2 to [`MAX_CHAIN_KNOTS`] increasing knots per spline).
    pub fn chain(&self, config: &ChainConfig) -> Result<DeviceChain, ConfigError> {
        let mut chain = DeviceChain::EMPTY;
        self.build_into(config, &mut chain)?;
        Ok(chain)
    }

    /// Whether [`chain`](Self::chain) would succeed, without building the chain.
    pub fn check(&self, config: &ChainConfig) -> Result<(), ConfigError> {
        self.with_table(config, |j, p, s, c| {
            DeviceChain::check(j, p, Functions::splines(s), c)
        })
    }

    /// Makes `chain` the chain of [`chain`](Self::chain), rebuilt in place (no chain on the
    /// stack); unchanged if it is refused.
    pub fn build_into(
        &self,
        config: &ChainConfig,
        chain: &mut DeviceChain,
    ) -> Result<(), ConfigError> {
        self.with_table(config, |j, p, s, c| {
            chain.rebuild(j, p, Functions::splines(s), c)
        })
    }

    /// The kernel's table of the parts and `config` (its splines built in `f32`), given to `f`.
    #[inline(never)]
    fn with_table(
        &self,
        config: &ChainConfig,
        f: impl FnOnce(
            &[CustomJoint<f32>; CHAIN_BODIES],
            &[BodyPoint<f32>; CHAIN_POINTS],
            &[Spline<f32, MAX_CHAIN_KNOTS>],
            &[Coupler<f32>],
        ) -> Result<(), qgait_kernel::ModelError>,
    ) -> Result<(), ConfigError> {
        let n = usize::from(config.splines);
        let want = (1u16 << n.min(MAX_CHAIN_SPLINES)) - 1;
        if self.upload != Some(config.upload)
            || n > MAX_CHAIN_SPLINES
            || self.joints_held != ALL_BODIES
            || self.axes_held != ALL_BODIES
            || u16::from(self.splines_held) & want != want
        {
            return Err(ConfigError::ChainIncomplete {
                upload: config.upload,
            });
        }
        let mut splines = [Spline::<f32, MAX_CHAIN_KNOTS>::EMPTY; MAX_CHAIN_SPLINES];
        for (slot, part) in splines.iter_mut().zip(&self.splines[..n]) {
            let mut x = [0.0f32; MAX_CHAIN_KNOTS];
            let mut y = [0.0f32; MAX_CHAIN_KNOTS];
            for (k, [kx, ky]) in part.knots.iter().enumerate() {
                (x[k], y[k]) = (*kx, *ky);
            }
            let m = part.knots.len();
            *slot = if part.linear {
                Spline::piecewise_linear(&x[..m], &y[..m])
            } else {
                Spline::from_knots(&x[..m], &y[..m])
            }
            .map_err(|_| ConfigError::Kernel)?;
        }
        let mut joints = [CustomJoint::<f32>::WELD; CHAIN_BODIES];
        for (joint, (part, axes)) in joints.iter_mut().zip(self.joints.iter().zip(&self.axes)) {
            joint.parent = (part.parent != CHAIN_GROUND).then_some(usize::from(part.parent));
            joint.in_parent = offset(&part.in_parent);
            joint.in_child = offset(&part.in_child);
            for (slot, a) in joint.rotations.iter_mut().zip(&axes.rotations) {
                *slot = driven(a);
            }
            for (slot, a) in joint.translations.iter_mut().zip(&axes.translations) {
                *slot = driven(a);
            }
        }
        let points: [BodyPoint<f32>; CHAIN_POINTS] = core::array::from_fn(|k| {
            if is_toe_tip(k) {
                let t = &config.toe_tips[k / 6];
                BodyPoint {
                    body: usize::from(t.body),
                    offset: v3(t.offset),
                }
            } else {
                let b = centre_body(k);
                BodyPoint {
                    body: b,
                    offset: v3(self.joints[b].point),
                }
            }
        });
        let mut couplers = [Coupler {
            independent: 0,
            function: Function::Constant(0.0f32),
        }; MAX_CHAIN_COUPLERS];
        for (slot, c) in couplers.iter_mut().zip(&config.couplers) {
            *slot = Coupler {
                independent: usize::from(c.independent),
                function: function(&c.function),
            };
        }
        f(
            &joints,
            &points,
            &splines[..n],
            &couplers[..config.couplers.len()],
        )
        .map_err(|_| ConfigError::Kernel)
    }
}

fn v3([x, y, z]: [f32; 3]) -> Vec3<f32> {
    Vec3::new(x, y, z)
}

fn offset(o: &ChainOffset) -> Offset<f32> {
    let [w, x, y, z] = o.rotation;
    Offset {
        translation: v3(o.translation),
        rotation: Quat::new(w, x, y, z),
    }
}

fn function(f: &ChainFunction) -> Function<f32> {
    match *f {
        ChainFunction::Constant(c) => Function::Constant(c),
        ChainFunction::Linear { slope, intercept } => Function::Linear { slope, intercept },
        ChainFunction::Spline(k) => Function::Spline(usize::from(k)),
    }
}

fn driven(a: &ChainAxis) -> Driven<f32> {
    Driven {
        axis: v3(a.axis),
        function: function(&a.function),
        argument: match a.argument {
            ChainArgument::None => Argument::None,
            ChainArgument::Coordinate(i) => Argument::Coordinate(usize::from(i)),
            ChainArgument::Coupled(k) => Argument::Coupled(usize::from(k)),
        },
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::{decode_message, encode_message, Message, MAX_MESSAGE_LEN};
    use qgait_kernel::models::fixtures::walker_chain;

    /// Every part through its wire bytes, into the hub's parts.
    pub(crate) fn received(upload: &ChainUpload) -> ChainParts {
        let mut parts = ChainParts::new();
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let mut through =
            |m: Message| decode_message(encode_message(&m, &mut buf).unwrap()).unwrap();
        for j in &upload.joints {
            let Message::ChainJoint(j) = through((*j).into()) else {
                panic!()
            };
            assert!(parts.add_joint(&j));
        }
        for a in &upload.axes {
            let Message::ChainAxes(a) = through(a.clone().into()) else {
                panic!()
            };
            assert!(parts.add_axes(&a));
        }
        for s in &upload.splines {
            let Message::ChainSpline(s) = through(s.clone().into()) else {
                panic!()
            };
            assert!(parts.add_spline(&s));
        }
        parts
    }

    #[test]
    fn hub_chain_is_the_hosts_within_micrometres() {
        let host = walker_chain();
        let upload = ChainUpload::of_chain(&host, 3).unwrap();
        assert_eq!(upload.splines.len(), 2);
        assert!(upload.splines[1].linear && !upload.splines[0].linear);
        assert_eq!(upload.axes[2].rotations.len(), 2);
        assert_eq!(upload.axes[2].translations.len(), 1);
        let parts = received(&upload);
        let config = upload.config(MissingPolicy::Drop, 4, true);
        let hub = parts.chain(&config).unwrap();
        let mut worst = 0.0f64;
        for k in 0..200 {
            let q: [f64; 17] = core::array::from_fn(|i| {
                let t = 0.37 * (k * 17 + i) as f64;
                0.8 * Real::sin_cos(t).0 + if i == 6 || i == 13 { 1.0 } else { 0.0 }
            });
            let want = chain_pose(&host, &q);
            let got = chain_pose(&hub, &q.map(|a| a as f32));
            for (a, b) in want.points().iter().zip(got.points()) {
                worst = worst.max(a.max_abs_diff(b.cast()));
            }
        }
        assert!(worst < 2e-6, "{worst}");
        assert!(worst > 0.0);
    }

    /// The hub's frames of a chain are what the host's `PoseModels` recomputes from them.
    #[cfg(feature = "chain")]
    #[test]
    fn hub_frames_of_a_chain_are_the_hosts() {
        use crate::{Kinematics, PoseModels};
        let host = walker_chain();
        let upload = ChainUpload::of_chain(&host, 3).unwrap();
        let mut k = Kinematics::new(crate::ModelId::Phak, None).unwrap();
        k.set_chain(
            &received(&upload),
            &upload.config(MissingPolicy::Drop, 4, false),
        )
        .unwrap();
        assert_eq!(k.model(), crate::ModelId::Chain);
        let models = PoseModels::<f64>::defaults().with_chain(host);
        let angles: [f32; 17] = core::array::from_fn(|i| 0.05 * (i as f32 - 6.0));
        let frame = k.pose_frame(7, &angles, 0);
        assert_eq!(frame.angles.len(), 17);
        let want = crate::device_model::pose_points(&models.frame_pose(&frame).unwrap());
        for (a, b) in frame.points.iter().flatten().zip(want.iter().flatten()) {
            assert!((a - b).abs() < 2e-6, "{a} vs {b}");
        }
    }

    #[test]
    fn incomplete_or_refused_chains_make_no_model() {
        let upload = ChainUpload::of_chain(&walker_chain(), 3).unwrap();
        let config = upload.config(MissingPolicy::Drop, 4, false);
        let mut parts = received(&upload);
        assert!(parts
            .chain(&ChainConfig {
                upload: 4,
                ..config.clone()
            })
            .is_err());
        assert!(parts
            .chain(&ChainConfig {
                splines: 3,
                ..config.clone()
            })
            .is_err());
        // Not a unit quaternion: the kernel refuses it.
        let mut bad = upload.joints[4];
        bad.in_parent.rotation = [2.0, 0.0, 0.0, 0.0];
        assert!(parts.add_joint(&bad));
        assert_eq!(parts.chain(&config).unwrap_err(), ConfigError::Kernel);
        assert!(parts.add_joint(&upload.joints[4]));
        assert!(parts.chain(&config).is_ok());
        // A part of another upload starts again.
        assert!(parts.add_joint(&ChainJoint {
            upload: 9,
            ..upload.joints[0]
        }));
        assert_eq!(
            parts.chain(&config).unwrap_err(),
            ConfigError::ChainIncomplete { upload: 3 }
        );
        assert!(!parts.add_joint(&ChainJoint {
            body: 11,
            ..upload.joints[0]
        }));
    }
}
