//! The models qgait evaluates and their inputs: the one model choice ([`choice::Model`], what
//! `--model` and `--anthropometry` load) and its errors ([`error::ModelError`]), a motion's
//! columns picked for it ([`coords`]), the kernel evaluation of HAK and PHAK ([`kinematics`]),
//! subject models and lengths, imported chains of other OpenSim models ([`chain`]), ([`subject`], [`anthropometry`]), the named points every model
//! gives and their CSV ([`points`]), and how far the paper's model is from gait2392
//! ([`fidelity`]).

pub mod anthropometry;
pub mod chain;
pub mod choice;
pub mod coords;
pub mod error;
pub mod fidelity;
pub mod kinematics;
pub mod points;
pub mod subject;
