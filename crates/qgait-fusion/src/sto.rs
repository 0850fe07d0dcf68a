//! OpenSense's orientation storage: the `.sto` that `IMUInverseKinematicsTool` and `qgait imu`
//! read (`DataType=Quaternion`, a `time` column, one tab-separated column per sensor whose
//! cells are `w,x,y,z`).

use std::io::Write;

/// Writes the header (`DataRate`, `DataType=Quaternion`, `version=3`, `OpenSimVersion=4.1`,
/// `endheader`, as OpenSense's own files), the labels `time` and `names`, then one row per
/// time with each sensor's quaternion. Every column holds one quaternion per time.
pub fn write_orientations<W: Write>(
    mut out: W,
    rate: f64,
    times: &[f64],
    names: &[&str],
    columns: &[&[[f64; 4]]],
) -> std::io::Result<()> {
    assert_eq!(names.len(), columns.len(), "one name per column");
    assert!(
        columns.iter().all(|c| c.len() == times.len()),
        "one quaternion per time in every column"
    );
    writeln!(out, "DataRate={rate:.6}")?;
    writeln!(out, "DataType=Quaternion")?;
    writeln!(out, "version=3")?;
    writeln!(out, "OpenSimVersion=4.1")?;
    writeln!(out, "endheader")?;
    write!(out, "time")?;
    for n in names {
        write!(out, "\t{n}")?;
    }
    writeln!(out)?;
    for (i, t) in times.iter().enumerate() {
        write!(out, "{t}")?;
        for c in columns {
            let [w, x, y, z] = c[i];
            write!(out, "\t{w},{x},{y},{z}")?;
        }
        writeln!(out)?;
    }
    out.flush()
}
