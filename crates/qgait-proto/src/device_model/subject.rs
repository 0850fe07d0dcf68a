//! Subject-specific gait2392 models as they travel: [`parts_of`] cuts a geometry into the six
//! [`SubjectLeg`] and [`SubjectKnee`] parts (numbers rounded to `f32`), [`SubjectParts`]
//! gathers the parts of one upload back into the kernel's [`Gait2392Geometry`] (in `f32`, as
//! the hub builds its model, with no double-precision arithmetic on the device). The leg's
//! fields are copied between a part and the kernel's [`LegGeometry`] here and nowhere else.

use qgait_kernel::models::gait2392::{Knots, LegGeometry};
use qgait_kernel::spline::MAX_KNOTS;
use qgait_kernel::Gait2392Geometry;

use crate::device_model::{ConfigError, MAX_SEGMENT_M};
use crate::{KneeDirection, Leg, SubjectKnee, SubjectLeg, MAX_KNEE_KNOTS};

// A knee part the protocol can carry always fits the kernel's spline.
const _: () = assert!(MAX_KNEE_KNOTS <= MAX_KNOTS);

impl SubjectLeg {
    /// The part of `leg` of a geometry, numbers rounded to `f32`.
    pub fn of_geometry(upload: u8, leg: Leg, g: &LegGeometry) -> SubjectLeg {
        let v = |a: [f64; 3]| a.map(|c| c as f32);
        SubjectLeg {
            upload,
            leg,
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
    }

    /// Writes this part's numbers into `g` (everything but the knee splines).
    pub fn write_into(&self, g: &mut LegGeometry<f32>) {
        g.hip_in_pelvis = self.hip_in_pelvis;
        g.hip_axes = self.hip_axes;
        g.ankle_in_tibia = self.ankle_in_tibia;
        g.ankle_axis = self.ankle_axis;
        g.subtalar_in_talus = self.subtalar_in_talus;
        g.subtalar_axis = self.subtalar_axis;
        g.mtp_in_calcn = self.mtp_in_calcn;
        g.mtp_axis = self.mtp_axis;
        g.toetip_in_toes = self.toetip_in_toes;
    }

    /// The positions (not the axes): what must be within [`MAX_SEGMENT_M`].
    fn positions(&self) -> [[f32; 3]; 5] {
        [
            self.hip_in_pelvis,
            self.ankle_in_tibia,
            self.subtalar_in_talus,
            self.mtp_in_calcn,
            self.toetip_in_toes,
        ]
    }
}

impl SubjectKnee {
    /// The `direction` spline of `leg` of a geometry, numbers rounded to `f32`; fails if it has
    /// more knots than a part carries.
    pub fn of_geometry(
        upload: u8,
        leg: Leg,
        direction: KneeDirection,
        g: &LegGeometry,
    ) -> Result<SubjectKnee, ConfigError> {
        let k = knots(g, direction);
        let too_many = ConfigError::SubjectKnots {
            leg: leg.index(),
            direction,
        };
        let mut knots = heapless::Vec::new();
        for i in 0..k.n {
            let (Some(x), Some(y)) = (k.x.get(i), k.y.get(i)) else {
                return Err(too_many);
            };
            knots.push([*x as f32, *y as f32]).map_err(|_| too_many)?;
        }
        Ok(SubjectKnee {
            upload,
            leg,
            direction,
            knots,
        })
    }

    /// Writes this part's spline into `g`.
    pub fn write_into(&self, g: &mut LegGeometry<f32>) {
        let k = match self.direction {
            KneeDirection::Tx => &mut g.knee_tx,
            KneeDirection::Ty => &mut g.knee_ty,
        };
        // MAX_KNEE_KNOTS <= MAX_KNOTS (asserted above): every knot of the part has a slot.
        k.n = self.knots.len();
        for ((x, y), [kx, ky]) in k.x.iter_mut().zip(k.y.iter_mut()).zip(&self.knots) {
            (*x, *y) = (*kx, *ky);
        }
    }
}

fn knots(g: &LegGeometry, direction: KneeDirection) -> &Knots {
    match direction {
        KneeDirection::Tx => &g.knee_tx,
        KneeDirection::Ty => &g.knee_ty,
    }
}

/// The parts of `geometry` (the inverse of [`SubjectParts::geometry`], rounding to `f32`): what
/// a host sends, in the order legs, then knees (right tx, right ty, left tx, left ty). Fails if
/// a spline has more knots than a part carries.
pub fn parts_of(
    geometry: &Gait2392Geometry,
    upload: u8,
) -> Result<([SubjectLeg; 2], [SubjectKnee; 4]), ConfigError> {
    let leg = |leg: Leg| SubjectLeg::of_geometry(upload, leg, leg_of(geometry, leg));
    let knee = |leg: Leg, direction| {
        SubjectKnee::of_geometry(upload, leg, direction, leg_of(geometry, leg))
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

fn leg_of<T>(g: &Gait2392Geometry<T>, leg: Leg) -> &LegGeometry<T> {
    match leg {
        Leg::Right => &g.right,
        Leg::Left => &g.left,
    }
}

/// The parts of one upload received so far, kept as the geometry they make: each part is
/// written into it as it arrives, so the model is built straight from here (no copy of the
/// geometry on the stack when the hub switches to it).
#[derive(Debug, Clone)]
pub struct SubjectParts {
    upload: Option<u8>,
    /// Counts every part taken (wrapping): tells whether the parts changed since a model was
    /// built from them.
    generation: u32,
    /// Which of the six parts are held ([`part_bit`]).
    held: u8,
    /// Which of the parts held have a position or knot value beyond [`MAX_SEGMENT_M`].
    out_of_range: u8,
    /// The parts held, in place; what is not held is stale or zero, never read.
    geometry: Gait2392Geometry<f32>,
}

/// A spline without knots.
const NO_KNOTS: Knots<f32> = Knots {
    n: 0,
    x: [0.0; MAX_KNOTS],
    y: [0.0; MAX_KNOTS],
};

/// A leg without numbers (zeros, no knots).
const NO_LEG: LegGeometry<f32> = LegGeometry {
    hip_in_pelvis: [0.0; 3],
    hip_axes: [[0.0; 3]; 3],
    knee_tx: NO_KNOTS,
    knee_ty: NO_KNOTS,
    ankle_in_tibia: [0.0; 3],
    ankle_axis: [0.0; 3],
    subtalar_in_talus: [0.0; 3],
    subtalar_axis: [0.0; 3],
    mtp_in_calcn: [0.0; 3],
    mtp_axis: [0.0; 3],
    toetip_in_toes: [0.0; 3],
};

/// The bit of a part in [`SubjectParts`]' masks: per leg (right first) the leg part, then the
/// knee's x and y parts.
fn part_bit(leg: Leg, knee: Option<KneeDirection>) -> u8 {
    let k = match knee {
        None => 0,
        Some(KneeDirection::Tx) => 1,
        Some(KneeDirection::Ty) => 2,
    };
    1 << (3 * leg as u8 + k)
}

/// The three parts of a leg.
fn leg_bits(leg: Leg) -> u8 {
    0b111 << (3 * leg as u8)
}

impl Default for SubjectParts {
    fn default() -> Self {
        SubjectParts::new()
    }
}

impl SubjectParts {
    /// No parts.
    pub const fn new() -> Self {
        SubjectParts {
            upload: None,
            generation: 0,
            held: 0,
            out_of_range: 0,
            geometry: Gait2392Geometry {
                right: NO_LEG,
                left: NO_LEG,
            },
        }
    }

    /// Keeps a leg part. A part of another upload than the parts held discards them first; a
    /// part for a leg already held replaces it.
    pub fn add_leg(&mut self, part: &SubjectLeg) {
        self.start(part.upload);
        part.write_into(self.leg_mut(part.leg));
        let in_range = part
            .positions()
            .iter()
            .flatten()
            .all(|c| c.abs() <= MAX_SEGMENT_M);
        self.took(part_bit(part.leg, None), in_range);
    }

    /// Keeps a knee part (same rules as [`add_leg`](Self::add_leg)).
    pub fn add_knee(&mut self, part: &SubjectKnee) {
        self.start(part.upload);
        part.write_into(self.leg_mut(part.leg));
        // (A NaN knot passes here; the kernel refuses it when the model is built.)
        let in_range = !part.knots.iter().any(|[_, y]| y.abs() > MAX_SEGMENT_M);
        self.took(part_bit(part.leg, Some(part.direction)), in_range);
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
        self.held.count_ones() as usize
    }

    /// The model of `upload`: all 6 parts must be held, every position and knot value must be
    /// within [`MAX_SEGMENT_M`] (finite). The kernel checks the rest (axes, knot order) when the
    /// model is built.
    pub fn geometry(&self, upload: u8) -> Result<&Gait2392Geometry<f32>, ConfigError> {
        if self.upload != Some(upload) {
            return Err(ConfigError::SubjectIncomplete { upload, parts: 0 });
        }
        for leg in Leg::ALL {
            if self.held & leg_bits(leg) != leg_bits(leg) {
                return Err(ConfigError::SubjectIncomplete {
                    upload,
                    parts: self.count() as u8,
                });
            }
            if self.out_of_range & leg_bits(leg) != 0 {
                return Err(ConfigError::SubjectOutOfRange { leg: leg as u8 });
            }
        }
        Ok(&self.geometry)
    }

    fn leg_mut(&mut self, leg: Leg) -> &mut LegGeometry<f32> {
        match leg {
            Leg::Right => &mut self.geometry.right,
            Leg::Left => &mut self.geometry.left,
        }
    }

    /// Records the part `bit` as held, in range or not.
    fn took(&mut self, bit: u8, in_range: bool) {
        self.generation = self.generation.wrapping_add(1);
        self.held |= bit;
        if in_range {
            self.out_of_range &= !bit;
        } else {
            self.out_of_range |= bit;
        }
    }

    /// Discards the parts held if they are of another upload than `upload`.
    fn start(&mut self, upload: u8) {
        if self.upload != Some(upload) {
            self.upload = Some(upload);
            self.held = 0;
            self.out_of_range = 0;
        }
    }
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
        *parts.geometry(4).unwrap()
    }

    #[test]
    fn parts_give_back_the_geometry_rounded_to_f32() {
        let g = Gait2392Geometry::generic();
        let r = rounded(&g);
        assert_eq!(r.left.knee_tx.n, 12);
        assert_eq!(r.right.knee_ty.n, 7);
        assert_eq!(
            r.right.hip_in_pelvis,
            g.right.hip_in_pelvis.map(|c| c as f32)
        );
        assert_eq!(
            r.left.knee_ty.y[..7],
            g.left.knee_ty.y[..7]
                .iter()
                .map(|&c| c as f32)
                .collect::<std::vec::Vec<_>>()[..]
        );
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
        assert_eq!(
            parts.geometry(4).unwrap_err(),
            ConfigError::SubjectIncomplete {
                upload: 4,
                parts: 5
            }
        );
        assert_eq!(
            parts.geometry(5).unwrap_err(),
            ConfigError::SubjectIncomplete {
                upload: 5,
                parts: 0
            }
        );
        parts.add_leg(&legs[1]);
        assert!(parts.geometry(4).is_ok());
        // A repeated part replaces the one held.
        let mut far = legs[1];
        far.toetip_in_toes[0] = f32::NAN;
        parts.add_leg(&far);
        assert_eq!(parts.count(), 6);
        assert_eq!(
            parts.geometry(4).unwrap_err(),
            ConfigError::SubjectOutOfRange { leg: 1 }
        );
    }

    #[test]
    fn too_many_knots_cannot_be_sent() {
        let mut g = Gait2392Geometry::generic();
        g.left.knee_ty.n = 13;
        assert_eq!(
            parts_of(&g, 1).unwrap_err(),
            ConfigError::SubjectKnots {
                leg: 1,
                direction: KneeDirection::Ty
            }
        );
    }
}
