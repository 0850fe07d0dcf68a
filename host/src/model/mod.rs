//! The models qgait evaluates and their inputs: which model (`--model`, [`spec`]), a motion's
//! columns picked for it ([`coords`]), the kernel evaluation ([`kinematics`]), subject models
//! ([`subject`], [`anthropometry`]), the named points and their CSV ([`points_csv`]), and how far
//! the paper's model is from gait2392 ([`fidelity`]).

pub mod anthropometry;
pub mod choice;
pub mod coords;
pub mod error;
pub mod fidelity;
pub mod kinematics;
pub mod points;
pub mod subject;
