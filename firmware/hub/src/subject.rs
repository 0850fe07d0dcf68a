//! Subject-specific gait2392 models arriving in parts: [`SubjectParts`] keeps the
//! [`SubjectLeg`] and [`SubjectKnee`] messages of one upload and assembles them into the
//! kernel's [`Gait2392Geometry`] once all six are there, in `f32` as they travel (the hub
//! builds the model in `f32`, with no double-precision arithmetic on the device).

use qgait_kernel::models::gait2392::{Knots, LegGeometry};
use qgait_kernel::spline::MAX_KNOTS;
use qgait_kernel::Gait2392Geometry;
use qgait_proto::{KneeDirection, Leg, SubjectKnee, SubjectLeg, MAX_KNEE_KNOTS};

use crate::kinematics::{ConfigError, MAX_SEGMENT_M};

// A knee part the protocol can carry always fits the kernel's spline.
const _: () = assert!(MAX_KNEE_KNOTS <= MAX_KNOTS);

/// The parts of one upload received so far.
#[derive(Debug, Clone, Default)]
pub struct SubjectParts {
    upload: Option<u8>,
    /// Counts every part taken (wrapping): tells whether the parts changed since a model was
    /// built from them.
    generation: u32,
    legs: [Option<SubjectLeg>; 2],
    /// Indexed by leg, then direction.
    knees: [[Option<SubjectKnee>; 2]; 2],
}

impl SubjectParts {
    /// No parts.
    pub const fn new() -> Self {
        SubjectParts { upload: None, generation: 0, legs: [None, None], knees: [[None, None], [None, None]] }
    }

    /// Keeps a leg part. A part of another upload than the parts held discards them first; a
    /// part for a leg already held replaces it.
    pub fn add_leg(&mut self, part: &SubjectLeg) {
        self.start(part.upload);
        self.generation = self.generation.wrapping_add(1);
        self.legs[part.leg as usize] = Some(*part);
    }

    /// Keeps a knee part (same rules as [`add_leg`](Self::add_leg)).
    pub fn add_knee(&mut self, part: &SubjectKnee) {
        self.start(part.upload);
        self.generation = self.generation.wrapping_add(1);
        self.knees[part.leg as usize][part.direction as usize] = Some(part.clone());
    }

    /// The upload whose parts are held, if any.
    pub fn upload(&self) -> Option<u8> {
        self.upload
    }

    /// Changes whenever a part is taken.
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// Number of the 6 parts held.
    pub fn count(&self) -> usize {
        self.legs.iter().flatten().count() + self.knees.iter().flatten().flatten().count()
    }

    /// The model of `upload`: all 6 parts must be held, every position and knot value must be
    /// within [`MAX_SEGMENT_M`] (finite). The kernel checks the rest (axes, knot order) when the
    /// model is built.
    pub fn geometry(&self, upload: u8) -> Result<Gait2392Geometry<f32>, ConfigError> {
        if self.upload != Some(upload) {
            return Err(ConfigError::SubjectIncomplete { upload, parts: 0 });
        }
        let incomplete = ConfigError::SubjectIncomplete { upload, parts: self.count() as u8 };
        let leg = |side: Leg| -> Result<LegGeometry<f32>, ConfigError> {
            let i = side as usize;
            let (Some(l), [Some(tx), Some(ty)]) = (&self.legs[i], &self.knees[i]) else {
                return Err(incomplete);
            };
            leg_geometry(l, tx, ty)
        };
        Ok(Gait2392Geometry { right: leg(Leg::Right)?, left: leg(Leg::Left)? })
    }

    fn start(&mut self, upload: u8) {
        if self.upload != Some(upload) {
            *self = SubjectParts { upload: Some(upload), generation: self.generation, ..SubjectParts::new() };
        }
    }
}

fn position(v: [f32; 3], leg: Leg) -> Result<[f32; 3], ConfigError> {
    if v.iter().all(|c| c.abs() <= MAX_SEGMENT_M) {
        Ok(v)
    } else {
        Err(ConfigError::SubjectOutOfRange { leg: leg as u8 })
    }
}

fn knots(part: &SubjectKnee) -> Result<Knots<f32>, ConfigError> {
    // MAX_KNEE_KNOTS <= MAX_KNOTS (asserted above): every knot of the part has a slot.
    let mut k = Knots { n: part.knots.len(), x: [0.0; MAX_KNOTS], y: [0.0; MAX_KNOTS] };
    for ((x, y), [kx, ky]) in k.x.iter_mut().zip(k.y.iter_mut()).zip(&part.knots) {
        if ky.abs() > MAX_SEGMENT_M {
            return Err(ConfigError::SubjectOutOfRange { leg: part.leg as u8 });
        }
        (*x, *y) = (*kx, *ky);
    }
    Ok(k)
}

fn leg_geometry(l: &SubjectLeg, tx: &SubjectKnee, ty: &SubjectKnee) -> Result<LegGeometry<f32>, ConfigError> {
    Ok(LegGeometry {
        hip_in_pelvis: position(l.hip_in_pelvis, l.leg)?,
        hip_axes: l.hip_axes,
        knee_tx: knots(tx)?,
        knee_ty: knots(ty)?,
        ankle_in_tibia: position(l.ankle_in_tibia, l.leg)?,
        ankle_axis: l.ankle_axis,
        subtalar_in_talus: position(l.subtalar_in_talus, l.leg)?,
        subtalar_axis: l.subtalar_axis,
        mtp_in_calcn: position(l.mtp_in_calcn, l.leg)?,
        mtp_axis: l.mtp_axis,
        toetip_in_toes: position(l.toetip_in_toes, l.leg)?,
    })
}

/// The parts of `geometry` (the inverse of [`SubjectParts::geometry`], rounding to `f32`): what
/// a host sends, in the order legs, then knees (right tx, right ty, left tx, left ty). Fails if
/// a spline has more knots than a part carries.
pub fn parts_of(geometry: &Gait2392Geometry, upload: u8) -> Result<([SubjectLeg; 2], [SubjectKnee; 4]), ConfigError> {
    let v = |a: [f64; 3]| a.map(|c| c as f32);
    let leg = |side: Leg| {
        let g = match side {
            Leg::Right => &geometry.right,
            Leg::Left => &geometry.left,
        };
        SubjectLeg {
            upload,
            leg: side,
            hip_in_pelvis: v(g.hip_in_pelvis),
            hip_axes: g.hip_axes.map(v),
            ankle_in_tibia: v(g.ankle_in_tibia),
            ankle_axis: v(g.ankle_axis),
            subtalar_in_talus: v(g.subtalar_in_talus),
            subtalar_axis: v(g.subtalar_axis),
            mtp_in_calcn: v(g.mtp_in_calcn),
            mtp_axis: v(g.mtp_axis),
            toetip_in_toes: v(g.toetip_in_toes),
        }
    };
    let knee = |side: Leg, direction: KneeDirection| {
        let g = match side {
            Leg::Right => &geometry.right,
            Leg::Left => &geometry.left,
        };
        let k = match direction {
            KneeDirection::Tx => &g.knee_tx,
            KneeDirection::Ty => &g.knee_ty,
        };
        let mut knots = heapless::Vec::new();
        for i in 0..k.n {
            let (Some(x), Some(y)) = (k.x.get(i), k.y.get(i)) else {
                return Err(ConfigError::SubjectKnots { leg: side as u8 });
            };
            knots.push([*x as f32, *y as f32]).map_err(|_| ConfigError::SubjectKnots { leg: side as u8 })?;
        }
        Ok(SubjectKnee { upload, leg: side, direction, knots })
    };
    Ok((
        [leg(Leg::Right), leg(Leg::Left)],
        [
            knee(Leg::Right, KneeDirection::Tx)?,
            knee(Leg::Right, KneeDirection::Ty)?,
            knee(Leg::Left, KneeDirection::Tx)?,
            knee(Leg::Left, KneeDirection::Ty)?,
        ],
    ))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    fn rounded(g: &Gait2392Geometry) -> Gait2392Geometry<f32> {
        let (legs, knees) = parts_of(g, 4).unwrap();
        let mut parts = SubjectParts::new();
        for l in &legs {
            parts.add_leg(l);
        }
        for k in &knees {
            parts.add_knee(k);
        }
        parts.geometry(4).unwrap()
    }

    #[test]
    fn parts_give_back_the_geometry_rounded_to_f32() {
        let g = Gait2392Geometry::generic();
        let r = rounded(&g);
        assert_eq!(r.left.knee_tx.n, 12);
        assert_eq!(r.right.knee_ty.n, 7);
        assert_eq!(r.right.hip_in_pelvis, g.right.hip_in_pelvis.map(|c| c as f32));
        assert_eq!(r.left.knee_ty.y[..7], g.left.knee_ty.y[..7].iter().map(|&c| c as f32).collect::<std::vec::Vec<_>>()[..]);
        assert_eq!(r.left.mtp_axis, g.left.mtp_axis.map(|c| c as f32));
        // Everything is the geometry rounded to f32, and rounding twice changes nothing more.
        assert_eq!(r, g.to_f32());
        assert_eq!(rounded(&r.cast()), r);
    }

    #[test]
    fn incomplete_or_other_uploads_make_no_model() {
        let (legs, knees) = parts_of(&Gait2392Geometry::generic(), 4).unwrap();
        let mut parts = SubjectParts::new();
        parts.add_leg(&legs[0]);
        for k in &knees {
            parts.add_knee(k);
        }
        assert_eq!(parts.geometry(4).unwrap_err(), ConfigError::SubjectIncomplete { upload: 4, parts: 5 });
        assert_eq!(parts.geometry(5).unwrap_err(), ConfigError::SubjectIncomplete { upload: 5, parts: 0 });
        parts.add_leg(&legs[1]);
        assert!(parts.geometry(4).is_ok());
        // A repeated part replaces the one held.
        let mut far = legs[1];
        far.toetip_in_toes[0] = f32::NAN;
        parts.add_leg(&far);
        assert_eq!(parts.count(), 6);
        assert_eq!(parts.geometry(4).unwrap_err(), ConfigError::SubjectOutOfRange { leg: 1 });
    }

    #[test]
    fn too_many_knots_cannot_be_sent() {
        let mut g = Gait2392Geometry::generic();
        g.left.knee_tx.n = 13;
        assert_eq!(parts_of(&g, 1).unwrap_err(), ConfigError::SubjectKnots { leg: 1 });
    }
}
