//! Host-only property test: pseudo-random mixes of good samples, samples with one truncated
//! packet, and line noise. Whatever the mix, every good sample gives exactly one pose, every
//! damaged one is counted as incomplete, and the hub never panics.

use qgait_hub::{Hub, ManualClock};
use qgait_hub_checks::{packet, send, CheckSerial, XorShift};
use qgait_proto::{encode_frame, FrameDecoder, Message, ModelId, MAX_FRAME_LEN};

/// Sends sample `seq`; if `damage` is `Some(i)`, its i-th packet is cut in half.
fn send_sample(serial: &mut CheckSerial, seq: u32, damage: Option<usize>) {
    for (i, &joint) in ModelId::Phak.required_joints().iter().enumerate() {
        let message = Message::JointAngle(packet(seq, joint));
        if damage == Some(i) {
            let mut buf = [0u8; MAX_FRAME_LEN];
            let frame = encode_frame(&message, &mut buf).unwrap();
            let half = frame.len() / 2;
            serial.receive(&frame[..half]);
            serial.receive(&[0]);
        } else {
            assert!(send(serial, &message));
        }
    }
}

fn run(seed: u32) {
    let clock = ManualClock::new(0);
    let mut hub = Hub::new(CheckSerial::new(), &clock, 0).unwrap();
    let mut rng = XorShift(seed.max(1));
    let samples = 8 + rng.next_u32() % 16;
    let mut expected = Vec::new();
    let mut damaged = 0;
    for seq in 0..samples {
        // The last window's worth of samples is always clean so every damaged one is evicted.
        let damage = (seq + 4 < samples && rng.next_u32().is_multiple_of(3))
            .then(|| (rng.next_u32() % 8) as usize);
        send_sample(hub.serial_mut(), seq, damage);
        match damage {
            Some(_) => damaged += 1,
            None => expected.push(seq),
        }
        if rng.next_u32().is_multiple_of(2) {
            let noise: Vec<u8> = (0..rng.next_u32() % 300)
                .map(|_| (rng.next_u32() % 255 + 1) as u8)
                .collect();
            hub.serial_mut().receive(&noise);
            hub.serial_mut().receive(&[0]);
        }
        while hub.serial_mut().pending() > 0 {
            hub.poll();
        }
    }
    let mut got = Vec::new();
    let mut decoder = FrameDecoder::new();
    for &b in hub.serial_mut().transmitted() {
        if let Some(Ok(Message::PoseFrame(p))) = decoder.push(b) {
            got.push(p.seq);
        }
    }
    // Complete samples come out in order here because they are sent in order.
    let clean_tail = expected.iter().filter(|&&s| s + 4 >= samples).count();
    assert!(clean_tail >= 4, "seed {seed}");
    assert_eq!(got, expected, "seed {seed}");
    let status = hub.status();
    assert_eq!(status.samples_incomplete, damaged, "seed {seed}");
    assert_eq!(
        status.samples_completed as usize,
        expected.len(),
        "seed {seed}"
    );
    assert!(!hub.serial_mut().tx_overflowed(), "seed {seed}");
}

#[test]
fn every_good_sample_gives_one_pose_whatever_the_noise() {
    for seed in 1..=300 {
        run(seed);
    }
}
