//! Damaging a node stream the ways a radio link and a busy hub do, reproducibly (seeded):
//! bit flips, dropped packets, packets reordered inside the hub's reorder window, and bursts of
//! line noise. What the hub must make of the result is found by decoding it with the same
//! protocol decoder (see [`Arrivals`]).

use std::collections::BTreeMap;

use qgait_proto::{FrameDecoder, JointAngle, Message, ModelId, Status};

use crate::device::packets::push_frame;

/// A small seeded generator (SplitMix64): the same seed gives the same damage everywhere.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
}

/// How much damage, per packet or per block of samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultPlan {
    /// Seed of the generator.
    pub seed: u64,
    /// Probability that a packet's frame gets one random bit flipped (delimiter included).
    pub flip: f64,
    /// Probability that a packet is not sent.
    pub drop: f64,
    /// Probability that the packets of a block of `window` samples are shuffled together.
    pub reorder: f64,
    /// The hub's reorder window (samples): blocks never span more than this.
    pub window: u32,
    /// Probability of a burst of random bytes (1 to 40, zeros included) after a packet.
    pub garbage: f64,
}

impl FaultPlan {
    /// No damage at all.
    pub fn none(window: u32) -> FaultPlan {
        FaultPlan {
            seed: 0,
            flip: 0.0,
            drop: 0.0,
            reorder: 0.0,
            window,
            garbage: 0.0,
        }
    }
}

/// The damaged stream of `samples` (each the packets of one sample, in sending order): a
/// 0x00 first, then the frames with the damage of `plan`.
pub fn damage(samples: &[Vec<JointAngle>], plan: &FaultPlan) -> Vec<u8> {
    let mut rng = Rng::new(plan.seed);
    let window = plan.window.max(1) as usize;
    let mut out = vec![0u8];
    for block in samples.chunks(window) {
        let mut packets: Vec<JointAngle> = block.iter().flatten().copied().collect();
        if rng.chance(plan.reorder) {
            // Fisher-Yates.
            for i in (1..packets.len()).rev() {
                packets.swap(i, rng.below(i + 1));
            }
        }
        for p in packets {
            if rng.chance(plan.drop) {
                continue;
            }
            let start = out.len();
            push_frame(&mut out, &Message::JointAngle(p));
            if rng.chance(plan.flip) {
                let i = start + rng.below(out.len() - start);
                out[i] ^= 1 << rng.below(8);
            }
            if rng.chance(plan.garbage) {
                let n = 1 + rng.below(40);
                out.extend((0..n).map(|_| rng.next_u64() as u8));
            }
        }
    }
    out
}

/// What a stream delivers to a hub, found with the protocol's decoder (as the hub decodes it).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Arrivals {
    /// The decodable joint-angle packets, by sequence number.
    pub packets: BTreeMap<u32, Vec<JointAngle>>,
    /// The counters the hub's decoder must end with (`packets_accepted` and the decode-error
    /// counters).
    pub status: Status,
}

impl Arrivals {
    /// Decodes `stream`.
    pub fn of(stream: &[u8]) -> Arrivals {
        let mut a = Arrivals::default();
        for r in FrameDecoder::new().feed(stream) {
            match r {
                Ok(Message::JointAngle(p)) => {
                    a.status.packets_accepted += 1;
                    a.packets.entry(p.seq).or_default().push(p);
                }
                Ok(_) => {}
                Err(e) => a.status.count_decode_error(&e),
            }
        }
        a
    }

    /// Whether every joint `model` needs arrived for sample `seq`.
    pub fn intact(&self, seq: u32, model: ModelId) -> bool {
        self.packets.get(&seq).is_some_and(|ps| {
            model
                .required_joints()
                .iter()
                .all(|j| ps.iter().any(|p| p.joint == *j))
        })
    }

    /// Samples of which some but not all joints of `model` arrived.
    pub fn partial(&self, model: ModelId) -> Vec<u32> {
        self.packets
            .iter()
            .filter(|(seq, ps)| {
                !self.intact(**seq, model)
                    && ps
                        .iter()
                        .any(|p| model.required_joints().contains(&p.joint))
            })
            .map(|(seq, _)| *seq)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::packets::packet;

    fn samples(n: u32) -> Vec<Vec<JointAngle>> {
        (0..n)
            .map(|s| {
                ModelId::Phak
                    .required_joints()
                    .iter()
                    .map(|&j| packet(s, s * 10, j, 0.01 * s as f32))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn no_damage_delivers_everything() {
        let stream = damage(&samples(20), &FaultPlan::none(4));
        let a = Arrivals::of(&stream);
        assert_eq!(a.status.packets_accepted, 160);
        assert!((0..20).all(|s| a.intact(s, ModelId::Phak)));
        assert!(a.partial(ModelId::Phak).is_empty());
    }

    #[test]
    fn damage_is_seeded_and_reordering_stays_inside_the_window() {
        let plan = FaultPlan {
            seed: 7,
            flip: 0.05,
            drop: 0.05,
            reorder: 0.5,
            window: 4,
            garbage: 0.05,
        };
        let s = samples(400);
        let stream = damage(&s, &plan);
        assert_eq!(stream, damage(&s, &plan));
        assert_ne!(stream, damage(&s, &FaultPlan { seed: 8, ..plan }));
        let a = Arrivals::of(&stream);
        let errors = a.status.crc_errors
            + a.status.framing_errors
            + a.status.oversize_frames
            + a.status.malformed;
        assert!(
            errors > 0 && a.partial(ModelId::Phak).len() > 10,
            "{:?}",
            a.status
        );
        // In arrival order, no packet comes after one of a sample `window` or more ahead.
        let mut newest = 0u32;
        for r in FrameDecoder::new().feed(&damage(
            &s,
            &FaultPlan {
                flip: 0.0,
                drop: 0.0,
                garbage: 0.0,
                ..plan
            },
        )) {
            let Ok(Message::JointAngle(p)) = r else {
                panic!("{r:?}")
            };
            assert!(newest < p.seq + 4, "seq {} after {newest}", p.seq);
            newest = newest.max(p.seq);
        }
    }
}
