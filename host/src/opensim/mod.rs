//! OpenSim's files: motions and storages (`.mot`/`.sto`, [`mot`]), orientation storages of IMUs
//! ([`imu_sto`]), models (`.osim`, [`osim`]) and the marker and storage files `qgait export`
//! writes ([`export`]).

pub mod export;
pub mod imu_sto;
pub mod mot;
pub mod osim;
