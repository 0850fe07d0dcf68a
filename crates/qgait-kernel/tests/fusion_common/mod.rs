//! Test support for orientation estimation: a reader of raw inertial CSV files in BROAD's
//! layout (the shared layout of `qgait fuse`), the VQF fixtures written by
//! `scripts/vqf_fixtures.py`, and BROAD's scoring of a whole trial.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use qgait_kernel::fusion::{ErrorRms, FusionReal, OrientationError, Vqf, VqfParams};

/// One sensor's recording: `time,gyr_x..z,acc_x..z[,mag_x..z][,opt_w..z][,movement]` by header
/// name, in any order; other columns are ignored.
#[derive(Clone, Debug, Default)]
pub struct RawTrial {
    /// Sampling period from the times, s.
    pub ts: f64,
    /// rad/s, sensor frame.
    pub gyr: Vec<[f64; 3]>,
    /// m/s², sensor frame.
    pub acc: Vec<[f64; 3]>,
    /// µT, sensor frame (empty without magnetometer columns).
    pub mag: Vec<[f64; 3]>,
    /// Reference orientation, sensor to ENU (`None` where the cells are empty or absent).
    pub opt: Vec<Option<[f64; 4]>>,
    /// Rows that BROAD's metric uses (`movement` = 1; all rows without the column).
    pub movement: Vec<bool>,
}

/// A bad cell or a missing column, with the file's line (1-based) and column name.
#[derive(Debug)]
pub struct CsvError(pub String);

fn col(header: &[&str], name: &str) -> Option<usize> {
    header.iter().position(|h| h.trim() == name)
}

/// Reads a CSV in the shared layout.
pub fn read_raw_csv(path: &Path) -> Result<RawTrial, CsvError> {
    let text =
        std::fs::read_to_string(path).map_err(|e| CsvError(format!("{}: {e}", path.display())))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| CsvError(format!("{}: empty file", path.display())))?
        .split(',')
        .collect();
    let need = |name: &str| {
        col(&header, name).ok_or_else(|| CsvError(format!("{}: no column {name}", path.display())))
    };
    let time = need("time")?;
    let gyr = [need("gyr_x")?, need("gyr_y")?, need("gyr_z")?];
    let acc = [need("acc_x")?, need("acc_y")?, need("acc_z")?];
    let mag = ["mag_x", "mag_y", "mag_z"].map(|n| col(&header, n));
    let opt = ["opt_w", "opt_x", "opt_y", "opt_z"].map(|n| col(&header, n));
    let movement = col(&header, "movement");
    let has_mag = mag.iter().all(Option::is_some);
    let has_opt = opt.iter().all(Option::is_some);
    let mut t = RawTrial::default();
    let (mut t0, mut t1) = (f64::NAN, f64::NAN);
    for (i, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        let num = |c: usize| -> Result<f64, CsvError> {
            let cell = cells.get(c).copied().unwrap_or("").trim();
            cell.parse::<f64>().map_err(|_| {
                CsvError(format!(
                    "{}:{}: column {} ({}): not a number: {cell:?}",
                    path.display(),
                    i + 2,
                    c + 1,
                    header[c]
                ))
            })
        };
        let v3 = |c: [usize; 3]| -> Result<[f64; 3], CsvError> {
            Ok([num(c[0])?, num(c[1])?, num(c[2])?])
        };
        let ti = num(time)?;
        if t0.is_nan() {
            t0 = ti;
        }
        t1 = ti;
        t.gyr.push(v3(gyr)?);
        t.acc.push(v3(acc)?);
        if has_mag {
            t.mag.push(v3(mag.map(Option::unwrap))?);
        }
        let q = if has_opt {
            let o = opt.map(Option::unwrap);
            if o.iter()
                .all(|&c| cells.get(c).is_none_or(|s| s.trim().is_empty()))
            {
                None
            } else {
                Some([num(o[0])?, num(o[1])?, num(o[2])?, num(o[3])?])
            }
        } else {
            None
        };
        t.opt.push(q);
        t.movement.push(match movement {
            Some(c) => num(c)? == 1.0,
            None => true,
        });
    }
    if t.gyr.len() < 2 || t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
        return Err(CsvError(format!(
            "{}: fewer than two samples or times not increasing",
            path.display()
        )));
    }
    t.ts = (t1 - t0) / (t.gyr.len() - 1) as f64;
    Ok(t)
}

/// The shared BROAD trials (`$QGAIT_SHARED/data/broad` or `../shared/data/broad`), sorted;
/// `None` with a printed reason when absent.
pub fn broad_trials() -> Option<Vec<PathBuf>> {
    let dir = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"))
        .join("data/broad");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "csv"));
    files.sort();
    if files.is_empty() {
        eprintln!(
            "SKIPPED: BROAD trials not found in {} (set QGAIT_SHARED)",
            dir.display()
        );
        return None;
    }
    Some(files)
}

/// Runs VQF (default parameters) over a trial; `nine_d` uses the magnetometer. Returns the
/// estimate per row (9D or 6D quaternion) as `f64`.
pub fn run_vqf<T: FusionReal>(trial: &RawTrial, nine_d: bool) -> Vec<[f64; 4]> {
    let mut vqf = Vqf::<T>::new(&VqfParams::default(), trial.ts);
    let c = |v: [f64; 3]| v.map(T::from_f64);
    (0..trial.gyr.len())
        .map(|i| {
            let mag = if nine_d { Some(c(trial.mag[i])) } else { None };
            vqf.update(c(trial.gyr[i]), c(trial.acc[i]), mag);
            let q = if nine_d { vqf.quat_9d() } else { vqf.quat_6d() };
            q.map(T::to_f64)
        })
        .collect()
}

/// BROAD's errors of `estimate` over the scored rows: (total, heading, inclination) RMSE, °.
pub fn score(trial: &RawTrial, estimate: &[[f64; 4]]) -> [f64; 3] {
    let mut rms = ErrorRms::new();
    for ((q, opt), &moving) in estimate.iter().zip(&trial.opt).zip(&trial.movement) {
        if let (true, Some(opt)) = (moving, opt) {
            if let Some(e) = OrientationError::between(*q, *opt) {
                rms.add(e);
            }
        }
    }
    rms.rms_deg()
}

/// The rotation angle between two unit quaternions, rad, accurate also for tiny angles
/// (`2 atan2(|vector part|, |w|)` of `a ⊗ b⁻¹`).
pub fn angle_between(a: [f64; 4], b: [f64; 4]) -> f64 {
    let w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    let x = -a[0] * b[1] + a[1] * b[0] - a[2] * b[3] + a[3] * b[2];
    let y = -a[0] * b[2] + a[1] * b[3] + a[2] * b[0] - a[3] * b[1];
    let z = -a[0] * b[3] - a[1] * b[2] + a[2] * b[1] + a[3] * b[0];
    2.0 * (x * x + y * y + z * z).sqrt().atan2(w.abs())
}

/// The reference's outputs after one sample: (index, quat6D, quat9D if 9D, bias).
pub type Reference = (usize, [f64; 4], Option<[f64; 4]>, [f64; 3]);

/// One fixture written by `scripts/vqf_fixtures.py`.
pub struct Fixture {
    pub ts: f64,
    pub gyr: Vec<[f32; 3]>,
    pub acc: Vec<[f32; 3]>,
    pub mag: Option<Vec<[f32; 3]>>,
    /// Bit 0 rest detected, bit 1 magnetic disturbance detected, per sample.
    pub flags: Vec<u8>,
    /// Sample index and reference outputs (quat6D, quat9D if 9D, bias) every `stride` samples.
    pub outputs: Vec<Reference>,
}

struct Bytes<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Bytes<'a> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let s = self.b[self.at..self.at + N].try_into().unwrap();
        self.at += N;
        s
    }
    fn u32(&mut self) -> usize {
        u32::from_le_bytes(self.take()) as usize
    }
    fn f32s<const N: usize>(&mut self) -> [f32; N] {
        core::array::from_fn(|_| f32::from_le_bytes(self.take()))
    }
    fn f64s<const N: usize>(&mut self) -> [f64; N] {
        core::array::from_fn(|_| f64::from_le_bytes(self.take()))
    }
}

/// Reads `tests/data/vqf/NAME`.
pub fn read_fixture(name: &str) -> Fixture {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/vqf")
        .join(name);
    let b = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut r = Bytes { b: &b, at: 0 };
    assert_eq!(&r.take::<4>(), b"VQFX", "{name}: not a VQF fixture");
    assert_eq!(r.u32(), 1, "{name}: fixture version");
    let ts = f64::from_le_bytes(r.take());
    let n = r.u32();
    let stride = r.u32();
    let has_mag = r.take::<1>()[0] == 1;
    let mut f = Fixture {
        ts,
        gyr: vec![],
        acc: vec![],
        mag: has_mag.then(Vec::new),
        flags: vec![],
        outputs: vec![],
    };
    for i in 0..n {
        f.gyr.push(r.f32s());
        f.acc.push(r.f32s());
        if let Some(m) = &mut f.mag {
            m.push(r.f32s());
        }
        f.flags.push(r.take::<1>()[0]);
        if i % stride == 0 {
            let q6 = r.f64s();
            let q9 = has_mag.then(|| r.f64s());
            let bias = r.f64s();
            f.outputs.push((i, q6, q9, bias));
        }
    }
    assert_eq!(r.at, b.len(), "{name}: trailing bytes");
    f
}
