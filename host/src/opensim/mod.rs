//! OpenSim's files: motions and storages (`.mot`/`.sto`, [`mot`]), orientation storages of IMUs
//! ([`imu_sto`]), models (`.osim`: gait2392's family [`osim`], any lower-limb chain [`leg_chain`]) and the marker and storage files `qgait export`
//! writes ([`export`]).

pub mod export;
pub mod imu_sto;
pub mod leg_chain;
pub mod mot;
pub mod osim;
