//! The IMU node's on-target tests under QEMU (`cargo test --release --features node --test
//! node_on_target`), run by knurling's `defmt-test` and counted by the runner into
//! `N passed, M failed` as the hub's: the node's `f32` fusion on the Cortex-M4F against its
//! rules in `f64` on the host (build.rs), and the node on an in-memory serial port (frames in,
//! orientations and counters out, damaged input counted).

#![no_std]
#![no_main]

// The panic and HardFault handlers, and the board's defmt logger and semihosting exit.
use qgait_firmware as _;

mod cases {
    include!(concat!(env!("OUT_DIR"), "/node_cases.rs"));
}

use qgait_proto::{segment_bit, FusionMode, RawImuConfig, RawImuSample, SampleHeader, SegmentId};

/// The configuration build.rs used.
fn config() -> RawImuConfig {
    RawImuConfig {
        segments: segment_bit(SegmentId::TibiaL),
        fusion: FusionMode::NineD,
        rate_hz: 100,
        output_every: 2,
        gyro_per_count: RawImuConfig::gyro_per_count_of(16.4),
        accel_per_count: RawImuConfig::accel_per_count_of(2048.0),
        mag_per_count: 0.15,
        request_status: false,
    }
}

fn sample(case: &cases::Case) -> RawImuSample {
    RawImuSample {
        header: SampleHeader::new(5, SegmentId::TibiaL, case.0, case.1),
        gyro: case.2,
        accel: case.3,
        mag: Some(case.4),
    }
}

/// The angle between two quaternions, radians (either sign).
fn angle(a: [f64; 4], b: [f64; 4]) -> f64 {
    let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
    let n = |q: &[f64; 4]| libm::sqrt(q.iter().map(|x| x * x).sum());
    2.0 * libm::acos((dot / (n(&a) * n(&b))).abs().min(1.0))
}

#[defmt_test::tests]
mod tests {
    use qgait_hub::{ManualClock, MemorySerial};
    use qgait_node::{Node, RawInput, RawOutcome};
    use qgait_proto::{encode_frame, FrameDecoder, Message, RawImuConfig, MAX_FRAME_LEN};

    use super::{angle, cases, config, sample};

    /// Every orientation of the node's f32 fusion within 0.01° of the host's f64 one, and
    /// exactly the samples due one give one.
    #[test]
    fn node_f32_fusion_matches_host_f64() {
        let mut input = RawInput::<f32, 1>::new();
        defmt::assert!(input.configure(&config()));
        let mut worst = 0.0f64;
        let mut compared = 0;
        for case in cases::CASES {
            let RawOutcome::Fused(q) = input.push(&sample(case)) else {
                defmt::panic!("sample {=u32} not fused", case.0);
            };
            defmt::assert_eq!(q.is_some(), case.5.is_some());
            if let (Some(q), Some(host)) = (q, case.5) {
                worst = worst.max(angle(q.map(f64::from), host));
                compared += 1;
            }
        }
        defmt::info!(
            "{=usize} orientations, largest f32 - f64 difference {=f64} deg",
            compared,
            worst.to_degrees()
        );
        defmt::assert!(compared > 150);
        defmt::assert!(worst.to_degrees() < 0.01);
        let s = input.status();
        defmt::assert_eq!(s.rate_gaps, 1);
        defmt::assert_eq!(s.samples_lost, 3);
        defmt::assert_eq!(s.timing_errors, 2);
    }

    /// Frames in through a serial port: an orientation frame per due sample, the counters
    /// answering the closing request, damaged frames and foreign messages counted.
    #[test]
    fn node_on_a_serial_port() {
        let clock = ManualClock::new(0);
        let mut node: Node<MemorySerial<256, 8192>, &ManualClock> =
            Node::new(MemorySerial::new(), &clock, 0);
        let mut buf = [0u8; MAX_FRAME_LEN];
        let mut send =
            |node: &mut Node<MemorySerial<256, 8192>, &ManualClock>, m: &Message, flip: bool| {
                let frame = encode_frame(m, &mut buf).unwrap_or_default();
                let mut bytes = [0u8; MAX_FRAME_LEN];
                let bytes = &mut bytes[..frame.len()];
                bytes.copy_from_slice(frame);
                if flip {
                    // A damaged byte that is not a delimiter: one bad frame.
                    bytes[2] ^= 0x10;
                    if bytes[2] == 0 {
                        bytes[2] = 0x55;
                    }
                }
                let mut rest: &[u8] = bytes;
                while !rest.is_empty() {
                    let n = node.serial_mut().receive(rest);
                    rest = &rest[n..];
                    node.poll();
                }
                while node.serial_mut().pending() > 0 {
                    node.poll();
                }
            };
        send(&mut node, &Message::RawImuConfig(config()), false);
        for case in &cases::CASES[..100] {
            send(
                &mut node,
                &Message::RawImuSample(sample(case)),
                case.0 == 40,
            );
        }
        send(&mut node, &Message::Status(Default::default()), false);
        send(
            &mut node,
            &Message::RawImuConfig(RawImuConfig {
                request_status: true,
                ..config()
            }),
            false,
        );
        let mut orientations = 0u32;
        let mut last = None;
        let mut raw = None;
        for m in FrameDecoder::new().feed(node.serial_mut().transmitted()) {
            match m {
                Ok(Message::SegmentOrientation(o)) => {
                    defmt::assert_eq!(o.header.seq % 2, 0);
                    orientations += 1;
                }
                Ok(Message::Status(s)) => last = Some(s),
                Ok(Message::RawImuStatus(s)) => raw = Some(s),
                _ => defmt::panic!("the node sent a frame that does not decode"),
            }
        }
        // 100 samples, one damaged (seq 40): 49 orientations of even seqs.
        defmt::assert_eq!(orientations, 49);
        let Some(s) = last else {
            defmt::panic!("no status");
        };
        defmt::assert_eq!(s.packets_accepted, 99);
        defmt::assert_eq!(s.samples_completed, 49);
        defmt::assert_eq!(s.crc_errors + s.framing_errors, 1);
        defmt::assert_eq!(s.malformed, 1);
        let Some(r) = raw else {
            defmt::panic!("no raw status");
        };
        defmt::assert_eq!(r.samples_accepted, 99);
        // The sample lost to the damage is a gap of one.
        defmt::assert_eq!((r.rate_gaps, r.samples_lost), (1, 1));
    }
}
