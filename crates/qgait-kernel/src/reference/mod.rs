//! Reference methods, for cross-checking the quaternion path (not the main path).
//!
//! - [`hak_geometric`]: HAK in closed form (Eqs 1-3), extended to the knee and ankle.
//! - [`hak_denavit_hartenberg`]: HAK by the Denavit-Hartenberg table (Table 2, Eqs 4-7).
//! - [`phak_homogeneous`]: PHAK by hand-written 4x4 homogeneous transforms (Eqs 16-17).
//! - [`chain_by_matrices`]: any [`Chain`](crate::Chain) table evaluated with homogeneous
//!   matrices instead of quaternions (the "matrix method" of the benchmarks).
//!
//! All use nalgebra's fixed-size types (no_std) and accurate libm sine/cosine.

mod dh;
mod geometric;
mod matrix;

pub use dh::{dh_transform, hak_denavit_hartenberg};
pub use geometric::hak_geometric;
pub use matrix::{chain_by_matrices, phak_homogeneous};
