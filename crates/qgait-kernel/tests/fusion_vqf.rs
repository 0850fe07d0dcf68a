//! The port is VQF: run on the inputs of fixtures written by the reference implementation
//! (`scripts/vqf_fixtures.py`: the `vqf` package's C++ filter in double, default parameters),
//! the `f64` filter reproduces its orientations, bias estimates and rest and magnetic
//! disturbance flags at every sample.

mod fusion_common;

use fusion_common::{angle_between, read_fixture, Fixture};
use qgait_kernel::fusion::{FusionReal, Vqf};

/// The largest differences from the reference over a fixture: (quaternion component, bias
/// component in rad/s, number of samples whose flags differ).
fn compare<T: FusionReal>(f: &Fixture) -> (f64, f64, f64, usize) {
    let mut vqf = Vqf::<T>::new_default(f.ts);
    let (mut dq, mut db, mut dangle, mut flags) = (0.0_f64, 0.0_f64, 0.0_f64, 0);
    let mut out = f.outputs.iter().peekable();
    let c = |v: [f32; 3]| v.map(|x| T::from_f64(x as f64));
    for i in 0..f.gyr.len() {
        vqf.update(c(f.gyr[i]), c(f.acc[i]), f.mag.as_ref().map(|m| c(m[i])));
        let mine = u8::from(vqf.rest_detected())
            | if f.mag.is_some() {
                u8::from(vqf.mag_dist_detected()) << 1
            } else {
                0
            };
        if mine != f.flags[i] {
            flags += 1;
        }
        if let Some((_, q6, q9, bias)) = out.next_if(|o| o.0 == i) {
            let mut pairs = vec![(vqf.quat_6d(), *q6)];
            if let Some(q9) = q9 {
                pairs.push((vqf.quat_9d(), *q9));
            }
            for (a, b) in pairs {
                let a = a.map(T::to_f64);
                for (x, y) in a.iter().zip(b) {
                    dq = dq.max((x - y).abs());
                }
                dangle = dangle.max(angle_between(a, b));
            }
            for (x, y) in vqf.bias().iter().zip(bias) {
                db = db.max((x.to_f64() - y).abs());
            }
        }
    }
    assert!(out.next().is_none());
    (dq, db, dangle, flags)
}

fn check(name: &str) {
    let f = read_fixture(name);
    let (dq, db, dangle, flags) = compare::<f64>(&f);
    eprintln!(
        "{name}: f64 max |dq| {dq:.2e}, max |dbias| {db:.2e} rad/s, max angle {dangle:.2e} rad, \
         {flags} flag mismatches over {} samples",
        f.gyr.len()
    );
    assert!(
        dq < 1e-9 && db < 1e-9 && dangle < 1e-9,
        "{name}: f64 port departs from VQF"
    );
    assert_eq!(flags, 0, "{name}: rest or disturbance flags differ");
    let (dq32, db32, dangle32, flags32) = compare::<f32>(&f);
    eprintln!(
        "{name}: f32 max |dq| {dq32:.2e}, max |dbias| {db32:.2e} rad/s, max angle {:.3}°, \
         {flags32} flag mismatches",
        dangle32.to_degrees()
    );
    assert!(
        dangle32.to_degrees() < 0.5,
        "{name}: f32 filter departs from VQF"
    );
}

#[test]
fn f64_port_matches_reference_9d_broad_excerpt() {
    check("broad34_9d.bin");
}

#[test]
fn f64_port_matches_reference_6d_synthetic() {
    check("synthetic_6d.bin");
}

/// The fixtures exercise what they are meant to: rest, disturbance and its end.
#[test]
fn fixtures_cover_rest_and_disturbance() {
    let f = read_fixture("broad34_9d.bin");
    let rest = f.flags.iter().filter(|&&x| x & 1 != 0).count();
    let dist = f.flags.iter().filter(|&&x| x & 2 != 0).count();
    let changes = f
        .flags
        .windows(2)
        .filter(|w| (w[0] ^ w[1]) & 2 != 0)
        .count();
    assert!(rest > 100 && dist > 100 && dist < f.flags.len() && changes > 2);
    let s = read_fixture("synthetic_6d.bin");
    assert!(s.flags.iter().any(|&x| x & 1 != 0));
}

/// The filter's whole state (parameters, coefficients and state) stays a few hundred bytes.
#[test]
fn state_size() {
    let (s32, s64) = (size_of::<Vqf<f32>>(), size_of::<Vqf<f64>>());
    eprintln!("Vqf<f32>: {s32} bytes, Vqf<f64>: {s64} bytes");
    assert!(s32 <= 600 && s64 <= 1200);
}
