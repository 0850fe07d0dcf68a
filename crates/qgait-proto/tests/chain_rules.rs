//! Section 9.4's rules for a chain table's every content, on the table of 9.5 with one byte or
//! number changed: what a parent index at or past its body, an angle index past 16, a coupled
//! index not before its drive, a polynomial function, bit 5 with no spline before it, a spline
//! of fewer than 2 knots, a read past the pool, a point's body past the table and axes past the
//! drives in use evaluate to (what the hub's table, the kernel's `PackedChain`, does).
mod common;

use qgait_proto::device_model::{DeviceChain, CHAIN_IMAGE_LEN};

const JOINTS: usize = 0;
const DRIVES: usize = 66;
const POINTS: usize = 114;
const SPLINES: usize = 138;
const COUNTS: usize = 186;
const NUMBERS: usize = 192;

/// The angles the checks use: `hip_flexion_r` (3) 0.5, `knee_angle_r` (6) -0.6.
fn angles() -> [f32; 17] {
    let mut q = [0.0; 17];
    q[3] = 0.5;
    q[6] = -0.6;
    q
}

fn image() -> Vec<u8> {
    let mut image = common::chain_coupled_image();
    image.resize(CHAIN_IMAGE_LEN, 0);
    image
}

fn points(image: &[u8]) -> [[f64; 3]; 12] {
    let mut table = DeviceChain::EMPTY;
    table.write_image(0, image);
    table
        .forward(&angles())
        .map(|p| [f64::from(p.x), f64::from(p.y), f64::from(p.z)])
}

fn set_number(image: &mut [u8], index: usize, value: f32) {
    image[NUMBERS + 4 * index..NUMBERS + 4 * index + 4].copy_from_slice(&value.to_le_bytes());
}

fn rz(theta: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(k: f64, a: [f64; 3]) -> [f64; 3] {
    a.map(|x| k * x)
}

/// Body 1's origin and point 2 for a slide `slide` along the axis and a turn `theta` about z,
/// body 1 on an identity parent at the origin (9.5's closed form).
fn body1(slide: f64, theta: f64) -> ([f64; 3], [f64; 3]) {
    let start = [0.0, -0.1, 0.08];
    let axis = [0.6, 0.8, 0.0];
    let o = add(add(start, scale(slide, axis)), rz(theta, [0.0, -0.4, 0.0]));
    (o, add(o, rz(theta, [0.05, -0.2, 0.0])))
}

fn assert_near(got: [f64; 3], want: [f64; 3], what: &str) {
    for i in 0..3 {
        assert!(
            (got[i] - want[i]).abs() < 1e-6,
            "{what}: {got:?} vs {want:?}"
        );
    }
}

/// The documented evaluation: c = 0.5 q6 + 0.1 slides body 1, -q3 + 0.25 turns it.
fn check(image: &[u8], slide: f64, theta: f64, what: &str) {
    let p = points(image);
    let (o, p2) = body1(slide, theta);
    assert_near(p[1], o, what);
    assert_near(p[2], p2, what);
}

const C: f64 = 0.5 * -0.6 + 0.1;
const THETA: f64 = -0.5 + 0.25;

#[test]
fn the_example_evaluates_as_documented() {
    check(&image(), C, THETA, "the example");
    assert_eq!(points(&image())[0], [0.0; 3]);
}

#[test]
fn a_parent_at_or_past_its_body_is_the_ground() {
    let mut image = image();
    // Body 0 starts at (0.6, 0.8, 0) (its START reads numbers 7 to 9); body 2 does not move.
    image[JOINTS..JOINTS + 6].copy_from_slice(&[0, 0, 0x01, 0, 7, 0]);
    image[POINTS + 6..POINTS + 8].copy_from_slice(&[2, 1]);
    image[JOINTS + 12] = 0;
    assert_near(points(&image)[3], [0.6, 0.8, 0.0], "parent 0");
    for parent in [2, 7, 255] {
        image[JOINTS + 12] = parent;
        assert_eq!(points(&image)[3], [0.0; 3], "parent {parent}");
    }
}

#[test]
fn an_angle_index_past_16_is_zero() {
    let mut image = image();
    image[DRIVES + 5] = 0x40 | 17;
    check(&image, C, 0.25, "angle 17");
    image[DRIVES + 5] = 0x40 | 63;
    check(&image, C, 0.25, "angle 63");
    // Argument kinds 0 (nothing) and 3 (not used): 0 as well.
    image[DRIVES + 5] = 0xc3;
    check(&image, C, 0.25, "kind 3");
}

#[test]
fn a_coupled_index_not_before_its_drive_is_zero() {
    let mut image = image();
    // Drive 1 reading coupled 1 (itself) or 2 (a later drive): 0.
    image[DRIVES + 3] = 0x81;
    check(&image, 0.0, THETA, "coupled 1 at drive 1");
    image[DRIVES + 3] = 0x82;
    check(&image, 0.0, THETA, "coupled 2 at drive 1");
    // Any earlier drive is read, a coupled coordinate or not: drive 2 at drive 1's value.
    let mut image = self::image();
    image[DRIVES + 5] = 0x81;
    check(&image, C, -C + 0.25, "coupled 1 at drive 2");
}

#[test]
fn a_polynomial_is_zero_and_moves_no_cursor() {
    let mut image = image();
    // Drive 0 a polynomial: the coupled coordinate is 0, and drive 2's linear coefficients are
    // still read from the cursor's start (numbers 0 and 1).
    image[DRIVES] = 0x80;
    check(&image, 0.0, 0.5 * 0.5 + 0.1, "polynomial drive 0");
}

#[test]
fn bit_5_with_no_spline_before_is_the_first_value() {
    let mut image = image();
    // Drive 2: spline 0, sharing (bit 5) with no spline drive before it. Spline 0: abscissae
    // at 0, values at 7, 3 knots: its value is y0, number 7 (0.6), whatever the angle.
    image[DRIVES + 4] = 0x40 | 0x20;
    image[SPLINES..SPLINES + 6].copy_from_slice(&[0, 0, 7, 0, 3, 0]);
    check(&image, C, 0.6, "shared weights, none before");
}

#[test]
fn a_spline_of_fewer_than_two_knots_is_its_first_value() {
    let mut image = image();
    image[DRIVES + 4] = 0x40;
    for knots in [0, 1] {
        image[SPLINES..SPLINES + 6].copy_from_slice(&[0, 0, 8, 0, knots, 0]);
        check(&image, C, 0.8, "fewer than 2 knots");
    }
    // Abscissae reaching past the pool (index 383, 3 knots): the same.
    image[SPLINES..SPLINES + 6].copy_from_slice(&[0x7f, 0x01, 8, 0, 3, 0]);
    check(&image, C, 0.8, "abscissae past the pool");
    // A spline index past the table's 8: 0.
    image[DRIVES + 4] = 0x40 | 8;
    check(&image, C, 0.0, "spline 8");
}

#[test]
fn a_read_past_the_pool_reads_its_last_numbers() {
    let mut image = image();
    for (k, v) in [(381, 1.0), (382, 2.0), (383, 3.0)] {
        set_number(&mut image, k, v);
    }
    // Body 1's numbers from index 383: every read of 3 is numbers 381 to 383.
    image[JOINTS + 10..JOINTS + 12].copy_from_slice(&383u16.to_le_bytes());
    let v = [1.0, 2.0, 3.0];
    let o = add(add(v, scale(C, v)), rz(THETA, v));
    assert_near(points(&image)[1], o, "past the pool");
}

#[test]
fn a_points_body_past_the_table_is_the_last_body() {
    let mut image = image();
    // Body 10 is 1's shape (on body 0); point 2 in body 12.
    image[JOINTS + 60..JOINTS + 66].copy_from_slice(&[0, 0x05, 0x09, 0x03, 4, 0]);
    image[POINTS + 4] = 12;
    let p = points(&image);
    // Body 10 takes no drive (body 1 took the two): its slide and turn are 0.
    let (_, p2) = body1(0.0, 0.0);
    assert_near(p[2], p2, "body 12");
}

#[test]
fn axes_past_the_drives_in_use_are_zero_or_not_applied() {
    let mut image = image();
    // Two drives in use: body 1's rotation takes drive slot 2's 0.
    image[COUNTS] = 2;
    check(&image, C, 0.0, "rotation past the drives in use");
    // Every one of the 24 slots a coupled coordinate: body 1 takes no value, its axes are not
    // applied and their numbers not read, so ENDS_AWAY reads the translation's axis.
    let mut image = self::image();
    image[COUNTS + 1] = 24;
    let o = add([0.0, -0.1, 0.08], [0.6, 0.8, 0.0]);
    assert_near(points(&image)[1], o, "no values left");
}
