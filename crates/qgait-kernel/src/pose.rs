//! What forward kinematics produces: joint centres of one leg or both.

use crate::{Real, Vec3};

/// A side of the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// Right (+z).
    Right,
    /// Left (-z).
    Left,
}

impl Side {
    /// Both sides, right first (the order of every output in qgait).
    pub const ALL: [Side; 2] = [Side::Right, Side::Left];
    /// OpenSim's suffix: `"r"` or `"l"`.
    pub fn suffix(self) -> &'static str {
        match self {
            Side::Right => "r",
            Side::Left => "l",
        }
    }
    /// +1 for right, -1 for left (the paper's `s`).
    pub fn sign<T: Real>(self) -> T {
        match self {
            Side::Right => T::ONE,
            Side::Left => -T::ONE,
        }
    }
}

/// A joint centre (or the toe tip) of the stick model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Joint {
    /// Hip centre.
    Hip,
    /// Knee centre.
    Knee,
    /// Ankle centre.
    Ankle,
    /// Tip of the big toe.
    Toe,
}

impl Joint {
    /// All four, proximal to distal.
    pub const ALL: [Joint; 4] = [Joint::Hip, Joint::Knee, Joint::Ankle, Joint::Toe];
    /// Lower-case name: `"hip"`, `"knee"`, `"ankle"`, `"toe"`.
    pub fn name(self) -> &'static str {
        match self {
            Joint::Hip => "hip",
            Joint::Knee => "knee",
            Joint::Ankle => "ankle",
            Joint::Toe => "toe",
        }
    }
}

/// Hip, knee, ankle and toe of one leg (metres).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LegPose<T> {
    /// Hip centre.
    pub hip: Vec3<T>,
    /// Knee centre.
    pub knee: Vec3<T>,
    /// Ankle centre.
    pub ankle: Vec3<T>,
    /// Toe tip.
    pub toe: Vec3<T>,
}

impl<T: Real> LegPose<T> {
    /// The point of `joint`.
    pub fn get(&self, joint: Joint) -> Vec3<T> {
        match joint {
            Joint::Hip => self.hip,
            Joint::Knee => self.knee,
            Joint::Ankle => self.ankle,
            Joint::Toe => self.toe,
        }
    }
    /// From four points in the order hip, knee, ankle, toe.
    pub fn from_points(p: [Vec3<T>; 4]) -> Self {
        Self {
            hip: p[0],
            knee: p[1],
            ankle: p[2],
            toe: p[3],
        }
    }
    /// The four points in the order hip, knee, ankle, toe.
    pub fn points(&self) -> [Vec3<T>; 4] {
        [self.hip, self.knee, self.ankle, self.toe]
    }
    /// Every point moved by `d`.
    pub fn translated(&self, d: Vec3<T>) -> Self {
        Self::from_points(self.points().map(|p| p + d))
    }
}

/// Both legs (metres): PHAK's output, and the shape of every pose qgait reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BilateralPose<T> {
    /// Right leg.
    pub right: LegPose<T>,
    /// Left leg.
    pub left: LegPose<T>,
}

impl<T: Real> BilateralPose<T> {
    /// One leg.
    pub fn leg(&self, side: Side) -> &LegPose<T> {
        match side {
            Side::Right => &self.right,
            Side::Left => &self.left,
        }
    }
    /// One point.
    pub fn point(&self, side: Side, joint: Joint) -> Vec3<T> {
        self.leg(side).get(joint)
    }
    /// The eight points in output order: hip, knee, ankle, toe of the right leg, then the left.
    pub fn points(&self) -> [Vec3<T>; 8] {
        let (r, l) = (self.right.points(), self.left.points());
        [r[0], r[1], r[2], r[3], l[0], l[1], l[2], l[3]]
    }
    /// From eight points in output order.
    pub fn from_points(p: [Vec3<T>; 8]) -> Self {
        Self {
            right: LegPose::from_points([p[0], p[1], p[2], p[3]]),
            left: LegPose::from_points([p[4], p[5], p[6], p[7]]),
        }
    }
}
