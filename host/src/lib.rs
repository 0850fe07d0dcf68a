#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod anthropometry;
pub mod builtin;
pub mod cli;
pub mod cli_config;
pub mod cli_device;
pub mod cli_gait2392;
pub mod cli_imu;
pub mod coords;
pub mod device;
pub mod export;
pub mod fidelity;
pub mod fk_csv;
pub mod hub_config;
pub mod imu_sto;
pub mod kinematics;
pub mod model_spec;
pub mod mot;
pub mod osim_import;
pub mod progress;
pub mod report;
pub mod source;
pub mod subject;
