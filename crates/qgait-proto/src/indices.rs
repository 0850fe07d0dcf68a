//! The fixed indices of the messages' arrays: a pose frame's points ([`point`]) and a
//! configuration's segment lengths ([`segment`]).

/// Indices into [`PoseFrame::points`](crate::PoseFrame::points).
pub mod point {
    /// Right hip joint centre.
    pub const HIP_R: usize = 0;
    /// Right knee joint centre.
    pub const KNEE_R: usize = 1;
    /// Right ankle joint centre.
    pub const ANKLE_R: usize = 2;
    /// Right toe.
    pub const TOE_R: usize = 3;
    /// Left hip joint centre.
    pub const HIP_L: usize = 4;
    /// Left knee joint centre.
    pub const KNEE_L: usize = 5;
    /// Left ankle joint centre.
    pub const ANKLE_L: usize = 6;
    /// Left toe.
    pub const TOE_L: usize = 7;
    /// Number of points.
    pub const COUNT: usize = 8;
}

/// Anthropometry of one leg, metres, in the order of [`Config::anthropometry`](crate::Config::anthropometry)'s inner array.
pub mod segment {
    /// Half the distance between the hip joint centres.
    pub const PELVIS_HALF_WIDTH: usize = 0;
    /// Hip to knee.
    pub const FEMUR: usize = 1;
    /// Knee to ankle.
    pub const TIBIA: usize = 2;
    /// Ankle to toe.
    pub const FOOT: usize = 3;
    /// Number of segment lengths per leg.
    pub const COUNT: usize = 4;
}
