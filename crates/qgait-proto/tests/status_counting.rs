//! Status::count_decode_error puts each error kind in its documented counter.
use qgait_proto::{DecodeError, Status};

#[test]
fn each_error_goes_to_its_counter() {
    use DecodeError::*;
    let mut s = Status::default();
    let errors = [
        Crc,
        Crc,
        Cobs,
        TooShort,
        Oversize,
        UnknownVersion(2),
        UnknownMessage(9),
        UnknownJoint(17),
        UnknownModel(3),
        AngleCount {
            expected: 6,
            got: 5,
        },
        Malformed,
    ];
    for e in &errors {
        s.count_decode_error(e);
    }
    let want = Status {
        crc_errors: 2,
        framing_errors: 2,
        oversize_frames: 1,
        unknown_version: 2,
        unknown_joint: 1,
        malformed: 3,
        ..Status::default()
    };
    assert_eq!(s, want);
}

#[test]
fn counters_wrap() {
    let mut s = Status {
        crc_errors: u32::MAX,
        ..Status::default()
    };
    s.count_decode_error(&DecodeError::Crc);
    assert_eq!(s.crc_errors, 0);
}
