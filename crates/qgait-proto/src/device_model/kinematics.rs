//! Poses from a sample's angles: a wire model as a kernel chain ([`Kinematics`] in `f32` for
//! the hub, [`PoseModels`] in any precision), the kernel's forward kinematics, and the pose as
//! a [`PoseFrame`].

use qgait_kernel::metrics::distances;
use qgait_kernel::models::ranges::KneeFlexion;
use qgait_kernel::models::LowerLimb;
use qgait_kernel::{
    Anthropometry, BilateralPose, Gait2392, Gait2392Geometry, Gait2392Pose, Limb, ModelError, Phak,
    PhakAngles, Real, Vec3,
};

use crate::device_model::chain::chain_pose;
#[cfg(feature = "chain")]
use crate::device_model::chain::{table_crc, DeviceChain, CHAIN_IMAGE_LEN};
use crate::device_model::error::{ConfigError, MAX_SEGMENT_M};
use crate::{
    encode_pose_frame_parts, encode_pose_velocities_frame, point, segment, EncodeError, FrameFlags,
    JointId, ModelId, PoseFrame, PoseFrameParts, PoseVelocities,
};
#[cfg(feature = "chain")]
use crate::{ChainTable, ChainTableConfig};

/// The generic gait2392 in `f32`, rounded from the kernel's `f64` numbers at compile time.
static GENERIC_GAIT2392: Gait2392Geometry<f32> = Gait2392Geometry::generic().to_f32();

/// The PHAK angles among a sample's angles (indexed by [`JointId::index`]); HAK takes the same
/// ones and ignores the pelvis ones.
#[inline(always)]
pub fn phak_angles<T: Copy>(angles: &[T; JointId::COUNT]) -> PhakAngles<T> {
    let a = |joint: JointId| angles[joint.index() as usize];
    PhakAngles {
        pelvis_rotation: a(JointId::PelvisRotation),
        pelvis_list: a(JointId::PelvisList),
        hip_flexion_r: a(JointId::HipFlexionR),
        knee_angle_r: a(JointId::KneeAngleR),
        ankle_angle_r: a(JointId::AnkleAngleR),
        hip_flexion_l: a(JointId::HipFlexionL),
        knee_angle_l: a(JointId::KneeAngleL),
        ankle_angle_l: a(JointId::AnkleAngleL),
    }
}

/// The pose of HAK or PHAK (`model`) on the PHAK chain `phak`, from a sample's angles (indexed
/// by [`JointId::index`]).
///
/// HAK has no pelvis joints: its legs hang from a level, forward-facing pelvis, i.e. PHAK with
/// zero pelvis rotation and list (the kernel's [`Phak::fk_hak`]), so both models give points in
/// the same frame.
#[inline(always)]
pub fn stick_pose<T: Real>(
    phak: &Phak<T>,
    model: ModelId,
    angles: &[T; JointId::COUNT],
) -> BilateralPose<T> {
    let q = phak_angles(angles);
    // Written as one `fk` call (not `fk_hak` in a branch): one copy of the evaluator in flash.
    phak.fk(&if model == ModelId::Hak {
        q.level_pelvis()
    } else {
        q
    })
}

/// The velocities of HAK's or PHAK's (`model`) points on the PHAK chain `phak`, from a
/// sample's angles and their speeds (both indexed by [`JointId::index`]): the kernel's
/// `forward_velocities`, in [`point`] order. HAK's pelvis is level and still, as in
/// [`stick_pose`].
#[inline(always)]
pub fn stick_velocities<T: Real>(
    phak: &Phak<T>,
    model: ModelId,
    angles: &[T; JointId::COUNT],
    rates: &[T; JointId::COUNT],
) -> [Vec3<T>; point::COUNT] {
    let (q, qd) = (phak_angles(angles), phak_angles(rates));
    let (q, qd) = if model == ModelId::Hak {
        (q.level_pelvis(), qd.level_pelvis())
    } else {
        (q, qd)
    };
    phak.chain()
        .forward_velocities(&q.to_array(), &qd.to_array())
        .1
}

/// The velocities of the pose's points of a 12-point model (gait2392, a chain): the 8 of
/// [`Gait2392Pose::bilateral`] among the 12.
#[inline(always)]
fn bilateral_velocities<T: Real>(velocities: [Vec3<T>; 12]) -> [Vec3<T>; point::COUNT] {
    Gait2392Pose { points: velocities }.bilateral().points()
}

/// The pose of gait2392 from a sample's angles: all 17 (its coordinates are in [`JointId`]
/// order), the hip, knee, ankle and toe tip of each leg.
#[inline(always)]
pub fn gait2392_pose<T: Real>(
    gait2392: &Gait2392<T>,
    angles: &[T; JointId::COUNT],
) -> BilateralPose<T> {
    gait2392.fk(angles).bilateral()
}

/// The pose's joint centres in [`point`] order (which is the kernel's), in `f32`.
pub fn pose_points<T: Real>(pose: &BilateralPose<T>) -> [[f32; 3]; point::COUNT] {
    pose.points().map(|p| p.to_array().map(to_f32))
}

/// The pose's inter-limb distances as a [`PoseFrame`] has them: knee, ankle, toe.
pub fn pose_distances<T: Real>(pose: &BilateralPose<T>) -> [f32; 3] {
    let d = distances(pose);
    [to_f32(d.knee), to_f32(d.ankle), to_f32(d.toe)]
}

/// `x` in `f32` (the identity for an `f32`).
#[inline(always)]
fn to_f32<T: Real>(x: T) -> f32 {
    x.to_f64() as f32
}

/// A sample's angles (indexed by [`JointId::index`]) from the angles of `model`'s joints (in
/// [`ModelId::required_joints`] order, as a [`PoseFrame`] and a node network have them), the
/// joints `model` does not take at 0.
pub fn sample_angles<T: Real, A: Copy + Into<f64>>(
    model: ModelId,
    angles: &[A],
) -> [T; JointId::COUNT] {
    let mut all = [T::ZERO; JointId::COUNT];
    for (&joint, &angle) in model.required_joints().iter().zip(angles) {
        all[joint.index() as usize] = T::from_f64(angle.into());
    }
    all
}

impl PoseFrame {
    /// The frame's angles as a sample's ([`sample_angles`]).
    pub fn joint_angles<T: Real>(&self) -> [T; JointId::COUNT] {
        sample_angles(self.model, &self.angles)
    }
}

/// Every model a hub computes with, at once: HAK and PHAK on one set of segment lengths,
/// gait2392 on one geometry (a hub keeps its lengths while it computes gait2392). The host
/// recomputes a hub's frames with it, in `f64`.
#[derive(Debug, Clone)]
pub struct PoseModels<T> {
    phak: Phak<T>,
    gait2392: Gait2392<T>,
    chain: Option<LowerLimb<T>>,
}

impl<T: Real> PoseModels<T> {
    /// HAK and PHAK with `anthropometry`, gait2392 with `geometry`.
    pub fn new(
        anthropometry: &Anthropometry<T>,
        geometry: &Gait2392Geometry,
    ) -> Result<Self, ModelError> {
        Ok(PoseModels {
            phak: Phak::new(anthropometry)?,
            gait2392: Gait2392::new(geometry)?,
            chain: None,
        })
    }

    /// These models with `chain` as [`ModelId::Chain`].
    pub fn with_chain(self, chain: LowerLimb<T>) -> Self {
        PoseModels {
            chain: Some(chain),
            ..self
        }
    }

    /// A hub's defaults: gait2392's segment lengths for HAK and PHAK, the generic gait2392.
    pub fn defaults() -> Self {
        match Self::new(&Anthropometry::gait2392(), &Gait2392Geometry::generic()) {
            Ok(models) => models,
            // The kernel's own defaults: never refused (its tests build them).
            Err(_) => unreachable!("the kernel refused its own defaults"),
        }
    }

    /// The pose of `model` from a sample's angles (indexed by [`JointId::index`]); `None` for
    /// a chain without one ([`with_chain`](Self::with_chain)).
    pub fn pose(&self, model: ModelId, angles: &[T; JointId::COUNT]) -> Option<BilateralPose<T>> {
        Some(match model {
            ModelId::Hak | ModelId::Phak => stick_pose(&self.phak, model, angles),
            ModelId::Gait2392 => gait2392_pose(&self.gait2392, angles),
            ModelId::Chain => chain_pose(self.chain.as_ref()?, angles),
        })
    }

    /// The velocities of `model`'s points ([`point`] order, m/s) from a sample's angles and
    /// speeds (indexed by [`JointId::index`]); `None` for a chain without one.
    pub fn velocities(
        &self,
        model: ModelId,
        angles: &[T; JointId::COUNT],
        rates: &[T; JointId::COUNT],
    ) -> Option<[Vec3<T>; point::COUNT]> {
        Some(match model {
            ModelId::Hak | ModelId::Phak => stick_velocities(&self.phak, model, angles, rates),
            ModelId::Gait2392 => {
                bilateral_velocities(self.gait2392.chain().forward_velocities(angles, rates).1)
            }
            ModelId::Chain => bilateral_velocities(
                self.chain
                    .as_ref()?
                    .table()
                    .forward_velocities(angles, rates)
                    .1,
            ),
        })
    }

    /// The pose a hub should have sent for `frame`, from the angles it echoes (`None`: a
    /// chain's frame, and no chain).
    pub fn frame_pose(&self, frame: &PoseFrame) -> Option<BilateralPose<T>> {
        self.pose(frame.model, &frame.joint_angles())
    }
}

/// A configured model, ready to compute poses: the hub's, in `f32`, one chain at a time.
#[derive(Debug, Clone)]
pub struct Kinematics {
    model: ModelId,
    chain: ModelChain,
    /// The knee flexion of an uploaded chain (negative for the built-in models).
    #[cfg(feature = "chain")]
    knee: KneeFlexion,
    /// The upload whose table the slot holds (`None` for the built-in models).
    #[cfg(feature = "chain")]
    upload: Option<u8>,
    /// A table is being written: no model to compute with until a
    /// [`set_chain`](Kinematics::set_chain) takes it.
    #[cfg(feature = "chain")]
    loading: bool,
}

/// What [`Kinematics::check_chain`] gives for the table it accepted, and
/// [`Kinematics::take_chain`] takes (only the kinematics make one).
#[cfg(feature = "chain")]
#[derive(Debug)]
#[must_use]
pub struct CheckedChain(KneeFlexion);

/// The kernel model that computes the poses.
#[derive(Debug, Clone)]
// One Kinematics lives in the hub, for its whole life: boxing is not an option without a heap.
#[allow(clippy::large_enum_variant)]
// An explicit tag (no niche in the chains' bytes), so that `Kinematics::EMPTY` is all zero bits
// and writing it is a memset, not a copy of a constant as large as the chain.
#[repr(u32)]
enum ModelChain {
    /// HAK and PHAK.
    Phak(Phak<f32>),
    /// gait2392, generic or subject-specific.
    Gait2392(Gait2392<f32>),
    /// An uploaded chain.
    #[cfg(feature = "chain")]
    Chain(DeviceChain),
}

impl Kinematics {
    /// Nothing set yet (HAK on the kernel's empty PHAK chain: every point at the origin); a
    /// slot that [`set_phak`](Self::set_phak) or [`set_gait2392`](Self::set_gait2392) fill in
    /// place. All zero bits (HAK is model 0, the PHAK variant tag 0, the empty chain zeros), so
    /// writing it compiles to a memset: no constant in flash, no copy on the stack.
    pub const EMPTY: Kinematics = Kinematics {
        model: ModelId::Hak,
        chain: ModelChain::Phak(Phak::EMPTY),
        #[cfg(feature = "chain")]
        knee: KneeFlexion::Negative,
        #[cfg(feature = "chain")]
        upload: None,
        #[cfg(feature = "chain")]
        loading: false,
    };

    /// The `model` with the given segment lengths (right, left; [`segment`] order), or
    /// gait2392's if `None`. HAK is computed as PHAK with a level, forward-facing pelvis
    /// ([`stick_pose`]). gait2392 is the generic model (its lengths are its own: `lengths` must
    /// be `None`).
    pub fn new(
        model: ModelId,
        lengths: Option<[[f32; segment::COUNT]; 2]>,
    ) -> Result<Kinematics, ConfigError> {
        let mut kinematics = Kinematics::EMPTY;
        if model == ModelId::Chain {
            // A chain comes in parts, with a `ChainTableConfig`.
            return Err(ConfigError::ChainIncomplete { upload: 0 });
        }
        if model == ModelId::Gait2392 {
            if lengths.is_some() {
                return Err(ConfigError::AnthropometryWithGait2392);
            }
            kinematics.set_gait2392(&GENERIC_GAIT2392)?;
        } else {
            kinematics.set_phak(model, &Kinematics::anthropometry(lengths)?)?;
        }
        Ok(kinematics)
    }

    /// The segment lengths of HAK or PHAK, checked (each within [`MAX_SEGMENT_M`], and by the
    /// kernel) without building anything: gait2392's if `None`.
    pub fn anthropometry(
        lengths: Option<[[f32; segment::COUNT]; 2]>,
    ) -> Result<Anthropometry<f32>, ConfigError> {
        let anthropometry = match lengths {
            None => Anthropometry::gait2392(),
            Some(legs) => Anthropometry {
                right: limb(&legs[0], 0)?,
                left: limb(&legs[1], 1)?,
            },
        };
        Phak::check(&anthropometry).map_err(|_| ConfigError::Kernel)?;
        Ok(anthropometry)
    }

    /// Makes this HAK or PHAK (`model`, not gait2392) with these lengths, rebuilt in place (no
    /// copy of a chain on the stack). Unchanged if the kernel refuses the lengths, which
    /// [`anthropometry`](Self::anthropometry) rules out.
    // Never inlined: the kernel's rebuild is the deepest part of a model switch.
    #[inline(never)]
    pub fn set_phak(
        &mut self,
        model: ModelId,
        anthropometry: &Anthropometry<f32>,
    ) -> Result<(), ConfigError> {
        if !matches!(self.chain, ModelChain::Phak(_)) {
            // The other model is given up only for lengths the kernel takes (a rebuild in the
            // same variant checks them itself, before writing anything).
            Phak::check(anthropometry).map_err(|_| ConfigError::Kernel)?;
            self.chain = ModelChain::Phak(Phak::EMPTY);
        }
        if let ModelChain::Phak(phak) = &mut self.chain {
            phak.rebuild(anthropometry)
                .map_err(|_| ConfigError::Kernel)?;
        }
        self.model = model;
        #[cfg(feature = "chain")]
        self.built_in();
        Ok(())
    }

    /// The generic gait2392 geometry in `f32`: data computed at compile time (no `f64` on the
    /// device).
    pub fn generic_gait2392() -> &'static Gait2392Geometry<f32> {
        &GENERIC_GAIT2392
    }

    /// gait2392 with these numbers (generic or a subject's), built in `f32` (the knee splines'
    /// coefficients included, [`Gait2392::from_geometry`]).
    pub fn gait2392(geometry: &Gait2392Geometry<f32>) -> Result<Kinematics, ConfigError> {
        let mut kinematics = Kinematics::EMPTY;
        kinematics.set_gait2392(geometry)?;
        Ok(kinematics)
    }

    /// Whether the kernel accepts gait2392 with these numbers, without building anything.
    pub fn check_gait2392(geometry: &Gait2392Geometry<f32>) -> Result<(), ConfigError> {
        Gait2392::check(geometry).map_err(|_| ConfigError::Kernel)
    }

    /// Makes this gait2392 with these numbers, rebuilt in place (no copy of a chain on the
    /// stack). Unchanged if the kernel refuses them
    /// ([`check_gait2392`](Self::check_gait2392) tells beforehand).
    #[inline(never)]
    pub fn set_gait2392(&mut self, geometry: &Gait2392Geometry<f32>) -> Result<(), ConfigError> {
        if !matches!(self.chain, ModelChain::Gait2392(_)) {
            // As in `set_phak`: checked before the other model is given up.
            Kinematics::check_gait2392(geometry)?;
            self.chain = ModelChain::Gait2392(Gait2392::EMPTY);
        }
        if let ModelChain::Gait2392(g) = &mut self.chain {
            g.rebuild(geometry).map_err(|_| ConfigError::Kernel)?;
        }
        self.model = ModelId::Gait2392;
        #[cfg(feature = "chain")]
        self.built_in();
        Ok(())
    }

    /// The gait2392 model in force (generic or a subject's), `None` with HAK or PHAK: the
    /// model the IMU calibration and solver take.
    pub fn gait2392_model(&self) -> Option<&Gait2392<f32>> {
        match &self.chain {
            ModelChain::Gait2392(g) => Some(g),
            ModelChain::Phak(_) => None,
            #[cfg(feature = "chain")]
            ModelChain::Chain(_) => None,
        }
    }

    /// A built-in model in the slot: its knee flexes negatively, no table held.
    #[cfg(feature = "chain")]
    fn built_in(&mut self) {
        self.knee = KneeFlexion::Negative;
        self.upload = None;
        self.loading = false;
    }

    /// Writes a part of a chain's table into the slot: the model in force stops (until
    /// [`set_chain`](Self::set_chain)), and a part of another upload than the one held starts
    /// from an empty table. `false` (nothing written) for a part reaching past the image
    /// ([`CHAIN_IMAGE_LEN`]).
    #[cfg(feature = "chain")]
    #[inline]
    pub fn write_chain(&mut self, part: &ChainTable) -> bool {
        if !Kinematics::takes_chain_part(part) {
            return false;
        }
        if self.upload != Some(part.upload) || !matches!(self.chain, ModelChain::Chain(_)) {
            self.chain = ModelChain::Chain(DeviceChain::EMPTY);
            self.upload = Some(part.upload);
        }
        self.loading = true;
        if let ModelChain::Chain(c) = &mut self.chain {
            c.write_image(usize::from(part.at), &part.bytes);
        }
        true
    }

    /// Whether [`write_chain`](Self::write_chain) writes `part`: whether it lies within the
    /// image ([`CHAIN_IMAGE_LEN`]).
    #[cfg(feature = "chain")]
    pub fn takes_chain_part(part: &ChainTable) -> bool {
        usize::from(part.at) + part.bytes.len() <= CHAIN_IMAGE_LEN
    }

    /// Whether the table held is the one `config` describes: the same upload, the CRC of its
    /// image's first `config.len` bytes `config.crc`, and a table the hub can compute
    /// ([`DeviceChain::is_usable`]).
    #[cfg(feature = "chain")]
    #[inline]
    pub fn check_chain(&self, config: &ChainTableConfig) -> Result<CheckedChain, ConfigError> {
        let len = usize::from(config.len);
        match &self.chain {
            ModelChain::Chain(c)
                if self.upload == Some(config.upload)
                    && len <= CHAIN_IMAGE_LEN
                    && table_crc(c, len) == config.crc
                    && c.is_usable() =>
            {
                Ok(CheckedChain(if config.knee_flexes_positive {
                    KneeFlexion::Positive
                } else {
                    KneeFlexion::Negative
                }))
            }
            _ => Err(ConfigError::ChainIncomplete {
                upload: config.upload,
            }),
        }
    }

    /// Makes the table held the model if [`check_chain`](Self::check_chain) accepts it;
    /// unchanged otherwise.
    #[cfg(feature = "chain")]
    pub fn set_chain(&mut self, config: &ChainTableConfig) -> Result<(), ConfigError> {
        let checked = self.check_chain(config)?;
        self.take_chain(checked);
        Ok(())
    }

    /// Makes the table held the model: what [`check_chain`](Self::check_chain) accepted (its
    /// [`CheckedChain`] says so; nothing may be written between the two).
    #[cfg(feature = "chain")]
    #[inline]
    pub fn take_chain(&mut self, checked: CheckedChain) {
        self.knee = checked.0;
        self.loading = false;
        self.model = ModelId::Chain;
    }

    /// Whether there is a model to compute poses with: not while a chain's table is being
    /// written (`write_chain`, with the `chain` feature); always without it.
    #[inline(always)]
    pub fn computes(&self) -> bool {
        #[cfg(feature = "chain")]
        {
            !self.loading
        }
        #[cfg(not(feature = "chain"))]
        {
            true
        }
    }

    /// Which sign of `knee_angle` flexes the knee of the model in force: an uploaded chain's
    /// as its `ChainTableConfig` says (the host's [`KneeFlexion::of`] of the model), negative for
    /// HAK, PHAK and gait2392 (and always, without the `chain` feature). The hub checks the
    /// knee's range with it ([`in_model_range`](qgait_kernel::models::ranges::in_model_range)).
    #[inline]
    pub fn knee_flexion(&self) -> KneeFlexion {
        #[cfg(feature = "chain")]
        {
            self.knee
        }
        #[cfg(not(feature = "chain"))]
        {
            KneeFlexion::Negative
        }
    }

    /// The model poses are computed with.
    pub fn model(&self) -> ModelId {
        self.model
    }

    /// The pose frame of the sample `seq` taken at `timestamp_us` with these angles (indexed
    /// by [`JointId::index`]), with `flags` ([`FrameFlags`] bits) set by the caller: the angles
    /// the model takes, the points and distances of its pose ([`stick_pose`], [`gait2392_pose`]).
    pub fn pose_frame(
        &self,
        seq: u32,
        timestamp_us: u32,
        angles: &[f32; JointId::COUNT],
        flags: u8,
    ) -> PoseFrame {
        let pose = self.pose(angles);
        let mut used = heapless::Vec::new();
        for &joint in self.model.required_joints() {
            // Capacity is JointId::COUNT, the most any model requires.
            let _ = used.push(angles[joint.index() as usize]);
        }
        PoseFrame {
            seq,
            timestamp_us,
            model: self.model,
            angles: used,
            points: pose_points(&pose),
            distances: pose_distances(&pose),
            flags: flags & FrameFlags::ALL,
        }
    }

    /// The frame of [`pose_frame`](Self::pose_frame)`(seq, timestamp_us, angles, flags)`, encoded into `out`
    /// ([`encode_pose_frame_parts`]: the same bytes as `encode_pose_frame` of it) without
    /// building the [`PoseFrame`]: the angles are read from `angles` and the points from the
    /// kernel's pose as they are written.
    pub fn encode_pose_frame<'a>(
        &self,
        seq: u32,
        timestamp_us: u32,
        angles: &[f32; JointId::COUNT],
        flags: u8,
        out: &'a mut [u8],
    ) -> Result<&'a [u8], EncodeError> {
        let pose = self.pose(angles);
        let joints = self.model.required_joints();
        let points = pose.points();
        let parts = PoseFrameParts {
            seq,
            timestamp_us,
            model: self.model,
            angle: |i: usize| {
                joints
                    .get(i)
                    .map_or(0.0, |&joint| angles[joint.index() as usize])
            },
            point: |i: usize| points.get(i).map_or([0.0; 3], |p| p.to_array()),
            distances: pose_distances(&pose),
            flags: flags & FrameFlags::ALL,
        };
        encode_pose_frame_parts(&parts, out)
    }

    /// The [`PoseVelocities`] of the sample `seq` with these angles and speeds (indexed by
    /// [`JointId::index`]; the speeds over `dt_us`, which the message carries), framed into
    /// `out`: the kernel's `forward_velocities` with the model in force.
    pub fn encode_pose_velocities<'a>(
        &self,
        seq: u32,
        dt_us: u32,
        angles: &[f32; JointId::COUNT],
        rates: &[f32; JointId::COUNT],
        out: &'a mut [u8],
    ) -> Result<&'a [u8], EncodeError> {
        let velocities = match &self.chain {
            ModelChain::Phak(phak) => stick_velocities(phak, self.model, angles, rates),
            ModelChain::Gait2392(g) => {
                bilateral_velocities(g.chain().forward_velocities(angles, rates).1)
            }
            #[cfg(feature = "chain")]
            ModelChain::Chain(c) => bilateral_velocities(c.forward_velocities(angles, rates).1),
        };
        let message = PoseVelocities {
            seq,
            dt_us,
            velocities: velocities.map(|v| v.to_array()),
        };
        encode_pose_velocities_frame(&message, out)
    }

    /// The kernel's pose of these angles with the model in force.
    #[inline(always)]
    fn pose(&self, angles: &[f32; JointId::COUNT]) -> BilateralPose<f32> {
        // gait2392 and a chain have the same 12 points: one conversion to the pose.
        let points = match &self.chain {
            ModelChain::Phak(phak) => return stick_pose(phak, self.model, angles),
            ModelChain::Gait2392(g) => g.fk(angles).points,
            #[cfg(feature = "chain")]
            ModelChain::Chain(c) => c.forward(angles),
        };
        Gait2392Pose { points }.bilateral()
    }
}

fn limb(lengths: &[f32; segment::COUNT], leg: u8) -> Result<Limb<f32>, ConfigError> {
    for (i, &l) in lengths.iter().enumerate() {
        if !(l > 0.0 && l <= MAX_SEGMENT_M) {
            return Err(ConfigError::BadSegment {
                leg,
                segment: i as u8,
            });
        }
    }
    Ok(Limb::from_array(*lengths))
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_kernel::{Hak, HakAngles};

    fn sample(angles: &[(JointId, f32)]) -> [f32; JointId::COUNT] {
        let mut all = [0.0; JointId::COUNT];
        for &(j, a) in angles {
            all[j.index() as usize] = a;
        }
        all
    }

    #[test]
    fn hak_frames_are_the_kernels_hak_legs_hung_at_the_hips() {
        let lengths = [[0.08, 0.40, 0.42, 0.20], [0.09, 0.38, 0.44, 0.21]];
        let k = Kinematics::new(ModelId::Hak, Some(lengths)).unwrap();
        let s = sample(&[
            (JointId::HipFlexionR, 0.4),
            (JointId::KneeAngleR, -0.9),
            (JointId::AnkleAngleR, 0.1),
            (JointId::HipFlexionL, -0.2),
            (JointId::KneeAngleL, -0.3),
            (JointId::AnkleAngleL, -0.15),
            // Ignored by HAK.
            (JointId::PelvisList, 0.3),
        ]);
        let frame = k.pose_frame(1, 10_000, &s, 0);
        for (leg, (offset, sign)) in [(0usize, 1.0f32), (4, -1.0)].into_iter().enumerate() {
            let limb = Limb::from_array(lengths[leg]);
            let q = |j: JointId| s[j.index() as usize];
            let angles = if leg == 0 {
                HakAngles {
                    hip_flexion: q(JointId::HipFlexionR),
                    knee_angle: q(JointId::KneeAngleR),
                    ankle_angle: q(JointId::AnkleAngleR),
                }
            } else {
                HakAngles {
                    hip_flexion: q(JointId::HipFlexionL),
                    knee_angle: q(JointId::KneeAngleL),
                    ankle_angle: q(JointId::AnkleAngleL),
                }
            };
            let hak = Hak::new(&limb).unwrap().fk(&angles);
            let hip = [0.0, 0.0, sign * lengths[leg][0]];
            for (i, p) in hak.points().iter().enumerate() {
                let want = p.to_array();
                let got = frame.points[offset + i];
                for k in 0..3 {
                    assert!(
                        (got[k] - hip[k] - want[k]).abs() < 1e-6,
                        "leg {leg} point {i}: {got:?} vs {want:?}"
                    );
                }
            }
        }
        assert_eq!(
            frame.angles.as_slice(),
            &[0.4, -0.9, 0.1, -0.2, -0.3, -0.15]
        );
    }

    #[test]
    fn lengths_outside_zero_to_two_metres_are_refused() {
        let mut lengths = [[0.08, 0.40, 0.42, 0.20]; 2];
        lengths[1][2] = 0.0;
        assert_eq!(
            Kinematics::new(ModelId::Phak, Some(lengths)).unwrap_err(),
            ConfigError::BadSegment { leg: 1, segment: 2 }
        );
        lengths[1][2] = f32::NAN;
        assert!(Kinematics::new(ModelId::Phak, Some(lengths)).is_err());
        lengths[1][2] = 2.5;
        assert!(Kinematics::new(ModelId::Phak, Some(lengths)).is_err());
        assert_eq!(
            Kinematics::new(ModelId::Gait2392, Some([[0.08, 0.40, 0.42, 0.20]; 2])).unwrap_err(),
            ConfigError::AnthropometryWithGait2392
        );
    }

    #[test]
    fn gait2392_frames_are_the_kernels_bilateral_pose_of_all_17_angles() {
        let k = Kinematics::new(ModelId::Gait2392, None).unwrap();
        let mut angles = [0.0f32; JointId::COUNT];
        for (i, a) in angles.iter_mut().enumerate() {
            *a = 0.05 * (i as f32 - 8.0);
        }
        let frame = k.pose_frame(3, 30_000, &angles, 0);
        let want = Gait2392::<f32>::from_geometry(&Gait2392Geometry::generic().to_f32())
            .unwrap()
            .fk(&angles);
        let b = want.bilateral();
        assert_eq!(frame.points, pose_points(&b));
        assert_eq!(frame.angles.as_slice(), &angles[..]);
        assert_eq!(frame.model, ModelId::Gait2392);
        let d = distances(&b);
        assert_eq!(frame.distances, [d.knee, d.ankle, d.toe]);
        // The toe tip, not the MTP joint, is the frame's toe.
        assert_eq!(frame.points[point::TOE_R], want.points[5].to_array());
        // Within a micrometre of the model whose splines are built in f64.
        let rounded = Gait2392::<f32>::new(&Gait2392Geometry::generic())
            .unwrap()
            .fk(&angles)
            .bilateral();
        for (a, b) in frame
            .points
            .iter()
            .flatten()
            .zip(pose_points(&rounded).iter().flatten())
        {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    /// The host's recomputation and the hub's computation are one mapping: in the same
    /// precision they give the same frames, for every model (HAK with its pelvis angles
    /// ignored).
    #[test]
    fn pose_models_give_the_hubs_frames() {
        let models =
            PoseModels::<f32>::new(&Anthropometry::gait2392(), &Gait2392Geometry::generic())
                .unwrap();
        let mut angles = [0.0f32; JointId::COUNT];
        for (i, a) in angles.iter_mut().enumerate() {
            *a = 0.07 * (i as f32 - 6.0);
        }
        // (A chain is not one of a hub's own models: `chain::tests` checks it.)
        assert!(Kinematics::new(ModelId::Chain, None).is_err());
        assert!(models.pose(ModelId::Chain, &angles).is_none());
        for model in [ModelId::Hak, ModelId::Phak, ModelId::Gait2392] {
            let k = Kinematics::new(model, None).unwrap();
            let frame = k.pose_frame(9, 90_000, &angles, 0);
            let pose = models.frame_pose(&frame).unwrap();
            let hub_points = frame.points;
            let host_points = pose_points(&pose);
            for (a, b) in hub_points
                .iter()
                .flatten()
                .zip(host_points.iter().flatten())
            {
                assert!((a - b).abs() < 1e-6, "{model}: {a} vs {b}");
            }
            for (a, b) in frame.distances.iter().zip(pose_distances(&pose)) {
                assert!((a - b).abs() < 1e-6, "{model}: {a} vs {b}");
            }
        }
        // HAK is PHAK with a level pelvis: the pelvis angles change PHAK's pose, not HAK's.
        let phak = models.pose(ModelId::Phak, &angles).unwrap();
        let hak = models.pose(ModelId::Hak, &angles).unwrap();
        let level = models
            .pose(ModelId::Phak, &{
                let mut a = angles;
                a[JointId::PelvisList.index() as usize] = 0.0;
                a[JointId::PelvisRotation.index() as usize] = 0.0;
                a
            })
            .unwrap();
        assert_eq!(pose_points(&hak), pose_points(&level));
        assert_ne!(pose_points(&hak), pose_points(&phak));
    }
}
