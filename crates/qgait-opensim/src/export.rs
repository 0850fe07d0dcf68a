//! `qgait export`: computed joint centres as files OpenSim opens.
//!
//! - `.trc` marker file (`PathFileType 4`, tab separated): a header line with the file name,
//!   the `DataRate CameraRate NumFrames NumMarkers Units OrigDataRate OrigDataStartFrame
//!   OrigNumFrames` names and values (`Units` = `m`; the rate is `(rows - 1) / (last time -
//!   first time)`, 1 for a single row), the marker names (one per three columns), the
//!   `X1 Y1 Z1 X2 ...` line, an empty line, then `Frame# Time x y z ...` rows (frames from 1).
//! - `.sto` table, OpenSim 4 style: `inDegrees=no`, `DataType=double`, `version=3`,
//!   `endheader`, then `time` and `<point>_x,_y,_z` columns as in `qgait fk`, tab separated.
//!
//! Numbers are printed with Rust's `{}` for `f64` (shortest round-trip text). Rows are written
//! as they are computed; the `.trc` header's frame count and rate come from a first pass over
//! the motion's times, so memory does not grow with the number of rows.

use std::io::{self, Write};

use qgait_kernel::Vec3;

/// Frames per second of `rows` rows from `first` to `last` (s): `(rows - 1) / (last - first)`,
/// 1 for a single row.
pub fn rate(rows: usize, first: f64, last: f64) -> f64 {
    if rows > 1 && last > first {
        (rows - 1) as f64 / (last - first)
    } else {
        1.0
    }
}

/// Writes the header of the `.trc` marker file: `file_name` in its first line, the points'
/// `names` as markers, `frames` rows at `rate` frames per second.
pub fn write_trc_header<W: Write + ?Sized>(
    w: &mut W,
    names: &[String],
    file_name: &str,
    frames: usize,
    rate: f64,
) -> io::Result<()> {
    let markers = names.len();
    writeln!(w, "PathFileType\t4\t(X/Y/Z)\t{file_name}")?;
    writeln!(
        w,
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames"
    )?;
    writeln!(
        w,
        "{rate}\t{rate}\t{frames}\t{markers}\tm\t{rate}\t1\t{frames}"
    )?;
    write!(w, "Frame#\tTime")?;
    for n in names {
        write!(w, "\t{n}\t\t")?;
    }
    writeln!(w)?;
    write!(w, "\t")?;
    for i in 1..=markers {
        write!(w, "\tX{i}\tY{i}\tZ{i}")?;
    }
    writeln!(w)?;
    writeln!(w)
}

/// Writes one `.trc` row (`frame` from 1).
pub fn write_trc_row<W: Write + ?Sized>(
    w: &mut W,
    frame: usize,
    time: f64,
    points: &[Vec3<f64>],
) -> io::Result<()> {
    write!(w, "{frame}\t{time}")?;
    for p in points {
        write!(w, "\t{}\t{}\t{}", p.x, p.y, p.z)?;
    }
    writeln!(w)
}

/// Writes the header of the `.sto` table.
pub fn write_sto_header<W: Write + ?Sized>(w: &mut W, names: &[String]) -> io::Result<()> {
    writeln!(w, "inDegrees=no")?;
    writeln!(w, "DataType=double")?;
    writeln!(w, "version=3")?;
    writeln!(w, "endheader")?;
    write!(w, "time")?;
    for n in names {
        write!(w, "\t{n}_x\t{n}_y\t{n}_z")?;
    }
    writeln!(w)
}

/// Writes one `.sto` row.
pub fn write_sto_row<W: Write + ?Sized>(
    w: &mut W,
    time: f64,
    points: &[Vec3<f64>],
) -> io::Result<()> {
    write!(w, "{time}")?;
    for p in points {
        write!(w, "\t{}\t{}\t{}", p.x, p.y, p.z)?;
    }
    writeln!(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_from_time() {
        assert_eq!(rate(3, 0.0, 1.0), 2.0);
        assert_eq!(rate(1, 3.0, 3.0), 1.0);
        assert_eq!(rate(0, 0.0, 0.0), 1.0);
        assert_eq!(rate(2, 1.0, 1.0), 1.0);
    }
}
