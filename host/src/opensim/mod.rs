//! OpenSim's files: motions and storages (`.mot`/`.sto`, [`mot`]), orientation storages of IMUs
//! ([`imu_sto`]) and the vendor exports OpenSense also reads (Xsens `.txt`, APDM `.csv`:
//! [`imu_vendor`]), models (`.osim`: gait2392's family [`osim`], any lower-limb chain [`leg_chain`]) and the marker and storage files `qgait export`
//! writes ([`export`]).

pub mod export;
pub mod imu_sto;
pub mod imu_vendor;
pub mod leg_chain;
pub mod mot;
pub mod osim;
