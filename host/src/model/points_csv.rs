//! The CSV written by `qgait fk`: one row per motion row,
//! `time,hip_r_x,hip_r_y,hip_r_z,knee_r_x,...,toe_r_z,hip_l_x,...,toe_l_z` (see [`header`]).
//! Positions in metres in ground axes (x forward, y up, z right); time in seconds. Numbers are
//! printed with Rust's `{}` for `f64`, the shortest text that reads back to the same value.

use std::io::{self, Write};

use qgait_kernel::{BilateralPose, Joint, Side};

/// The header line (without the newline).
pub fn header() -> String {
    let mut cols = vec!["time".to_string()];
    for side in Side::ALL {
        for joint in Joint::ALL {
            for axis in ["x", "y", "z"] {
                cols.push(format!("{}_{}_{}", joint.name(), side.suffix(), axis));
            }
        }
    }
    cols.join(",")
}

/// Writes the header line.
pub fn write_header<W: Write + ?Sized>(w: &mut W) -> io::Result<()> {
    writeln!(w, "{}", header())
}

/// Writes one row.
pub fn write_row<W: Write + ?Sized>(
    w: &mut W,
    time: f64,
    pose: &BilateralPose<f64>,
) -> io::Result<()> {
    write!(w, "{time}")?;
    for side in Side::ALL {
        for joint in Joint::ALL {
            let p = pose.point(side, joint);
            write!(w, ",{},{},{}", p.x, p.y, p.z)?;
        }
    }
    w.write_all(b"\n")
}
