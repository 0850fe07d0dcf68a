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
//! Numbers are printed with Rust's `{}` for `f64` (shortest round-trip text).

use std::io::{self, Write};

use crate::model_spec::PointTrack;

/// Frames per second from the time column.
pub fn data_rate(time: &[f64]) -> f64 {
    match (time.first(), time.last()) {
        (Some(a), Some(b)) if time.len() > 1 && b > a => (time.len() - 1) as f64 / (b - a),
        _ => 1.0,
    }
}

/// Writes the `.trc` marker file; `file_name` goes in its first line.
pub fn write_trc<W: Write + ?Sized>(
    w: &mut W,
    track: &PointTrack,
    file_name: &str,
) -> io::Result<()> {
    let rate = data_rate(&track.time);
    let (frames, markers) = (track.rows.len(), track.names.len());
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
    for n in &track.names {
        write!(w, "\t{n}\t\t")?;
    }
    writeln!(w)?;
    write!(w, "\t")?;
    for i in 1..=markers {
        write!(w, "\tX{i}\tY{i}\tZ{i}")?;
    }
    writeln!(w)?;
    writeln!(w)?;
    for (frame, (t, row)) in track.time.iter().zip(&track.rows).enumerate() {
        write!(w, "{}\t{t}", frame + 1)?;
        for p in row {
            write!(w, "\t{}\t{}\t{}", p.x, p.y, p.z)?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// Writes the `.sto` table.
pub fn write_sto<W: Write + ?Sized>(w: &mut W, track: &PointTrack) -> io::Result<()> {
    writeln!(w, "inDegrees=no")?;
    writeln!(w, "DataType=double")?;
    writeln!(w, "version=3")?;
    writeln!(w, "endheader")?;
    write!(w, "time")?;
    for n in &track.names {
        write!(w, "\t{n}_x\t{n}_y\t{n}_z")?;
    }
    writeln!(w)?;
    for (t, row) in track.time.iter().zip(&track.rows) {
        write!(w, "{t}")?;
        for p in row {
            write!(w, "\t{}\t{}\t{}", p.x, p.y, p.z)?;
        }
        writeln!(w)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_from_time() {
        assert_eq!(data_rate(&[0.0, 0.5, 1.0]), 2.0);
        assert_eq!(data_rate(&[3.0]), 1.0);
        assert_eq!(data_rate(&[]), 1.0);
    }
}
