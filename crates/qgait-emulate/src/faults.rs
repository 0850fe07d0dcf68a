//! Damaging a node stream the ways a radio link and a busy hub do, reproducibly (seeded):
//! bit flips, dropped packets, packets swapped inside a sample or reordered inside the hub's
//! reorder window, and bursts of line noise ([`FaultPlan`]; [`FaultPlan::radio_link`] is the
//! reference damage model). [`damage`] keeps a ledger of what happened to every packet
//! ([`Damaged`]), from which [`Damaged::accounting`] says what a hub must count, without
//! a protocol decoder; [`Arrivals`] says the same with the protocol's decoder, as the hub
//! decodes it.
//!
//! # What a hub accounts for
//!
//! A hub sees bytes, not packets: the 0x00 delimiters cut the stream into runs, and each
//! non-empty run is either one packet, accepted, or one damaged frame, counted once in exactly
//! one of `crc_errors`, `framing_errors`, `oversize_frames`, `malformed`, `unknown_version`
//! and `unknown_joint`. So for a damaged stream (nothing but joint-angle packets and noise):
//!
//! - every packet the link sent is delivered (its frame arrived whole, preceded by a 0x00),
//!   dropped (never arrived) or damaged (a bit of its frame flipped, or the bytes before it did
//!   not end with a 0x00, so that it ran into them); `packets_accepted` = delivered;
//! - the decode-error counters add up to the runs that are not a delivered packet:
//!   `packets_accepted` + their sum = the non-empty runs of the stream (followed by a 0x00,
//!   as the host's next request always is). Every damaged packet is in such a run: a flipped
//!   delimiter makes one run of two frames, a burst of non-zero noise one run of the noise and
//!   the next frame, a bit flipped to 0x00 two runs of one frame;
//! - a dropped or damaged packet shows in its sample: with the drop policy,
//!   `samples_completed` counts the samples whose packets were all delivered,
//!   `samples_incomplete` those with some but not all (a sample that lost every packet never
//!   reached the hub, [`Accounting::vanished`]); nothing is late or duplicated when packets
//!   only move inside the reorder window.

use crate::EmulateError;
use std::collections::{BTreeMap, BTreeSet};

use qgait_proto::{
    segment_bit, FrameDecoder, ImuConfig, JointAngle, JointId, Message, ModelId, RawImuSample,
    SegmentOrientation, Status,
};

use crate::push_frame;

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

/// The bytes of a burst of line noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Noise {
    /// Any byte, 0x00 included (a burst may end the frame before it, or itself).
    Any,
    /// Never 0x00, as a line idling or ringing gives: the burst always runs into the next
    /// frame, which it destroys.
    NonZero,
}

/// How much damage, per packet, per sample or per block of samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultPlan {
    /// Seed of the generator.
    pub seed: u64,
    /// Probability that a packet's frame gets one random bit flipped (delimiter included).
    pub flip: f64,
    /// Probability that a packet is not sent.
    pub drop: f64,
    /// Probability that a sample has two of its packets (chosen at random) trade places.
    pub swap: f64,
    /// Probability that the packets of a block of `window` samples are shuffled together.
    pub reorder: f64,
    /// The hub's reorder window (samples): blocks never span more than this.
    pub window: u32,
    /// Probability of a burst of 1 to 40 bytes of noise after a packet.
    pub garbage: f64,
    /// The bytes of a burst.
    pub noise: Noise,
    /// A joint whose node sends nothing (a node down): its packets are all dropped.
    pub silent: Option<JointId>,
}

impl FaultPlan {
    /// No damage at all.
    pub fn none(window: u32) -> FaultPlan {
        FaultPlan {
            seed: 0,
            flip: 0.0,
            drop: 0.0,
            swap: 0.0,
            reorder: 0.0,
            window,
            garbage: 0.0,
            noise: Noise::Any,
            silent: None,
        }
    }

    /// The reference damage of a radio link: 4 % of packets with one bit flipped, 4 % dropped,
    /// 2 % of samples with two packets swapped, and after 1 % of packets a burst of 1 to 40
    /// non-zero bytes.
    pub fn radio_link(seed: u64, window: u32) -> FaultPlan {
        FaultPlan {
            seed,
            flip: 0.04,
            drop: 0.04,
            swap: 0.02,
            reorder: 0.0,
            window,
            garbage: 0.01,
            noise: Noise::NonZero,
            silent: None,
        }
    }
}

/// What the link did to a packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fate {
    /// Its frame arrived whole, after a 0x00.
    Delivered,
    /// Not sent.
    Dropped,
    /// A bit of its frame flipped, or it ran into bytes not ended by a 0x00 (noise, or the
    /// previous frame whose delimiter flipped).
    Damaged,
}

/// A packet a node sends, as the link carries it: a [`JointAngle`], from an IMU node of the
/// orientation input a [`SegmentOrientation`], or from a raw node a [`RawImuSample`].
pub trait NodePacket: Copy {
    /// The sample it belongs to.
    fn seq(&self) -> u32;
    /// The joint it carries, if it is a joint angle ([`FaultPlan::silent`] names a joint).
    fn joint(&self) -> Option<JointId>;
    /// The message it travels as.
    fn message(&self) -> Message;
}

impl NodePacket for JointAngle {
    fn seq(&self) -> u32 {
        self.seq
    }
    fn joint(&self) -> Option<JointId> {
        Some(self.joint)
    }
    fn message(&self) -> Message {
        Message::JointAngle(*self)
    }
}

impl NodePacket for SegmentOrientation {
    fn seq(&self) -> u32 {
        self.header.seq
    }
    fn joint(&self) -> Option<JointId> {
        None
    }
    fn message(&self) -> Message {
        Message::SegmentOrientation(*self)
    }
}

impl NodePacket for RawImuSample {
    fn seq(&self) -> u32 {
        self.header.seq
    }
    fn joint(&self) -> Option<JointId> {
        None
    }
    fn message(&self) -> Message {
        Message::RawImuSample(*self)
    }
}

/// A damaged stream and the ledger of what happened to each packet.
#[derive(Debug, Clone, PartialEq)]
pub struct Damaged<P = JointAngle> {
    /// The bytes: a 0x00 first, then the frames with the damage.
    pub stream: Vec<u8>,
    /// Every packet, in the order the link sent them (after swaps and reordering), with its
    /// fate.
    pub packets: Vec<(P, Fate)>,
    /// Samples with two packets swapped.
    pub swapped: u32,
    /// Bursts of noise.
    pub bursts: u32,
}

/// What a hub must count for a [`Damaged`] stream (see the module docs), from the ledger and
/// the delimiters alone, once the stream is followed by a 0x00 (as the host's next request
/// is): noise after the last frame is then one more damaged run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Accounting {
    /// Packets delivered: `packets_accepted`.
    pub delivered: u32,
    /// Packets dropped by the link.
    pub dropped: u32,
    /// Packets damaged on the link.
    pub damaged: u32,
    /// Non-empty runs between 0x00 bytes that are not a delivered packet: the sum of the
    /// decode-error counters.
    pub bad_runs: u32,
    /// Samples whose packets were all delivered: `samples_completed`.
    pub complete: u32,
    /// Samples with some but not all packets delivered: `samples_incomplete` (drop policy).
    pub incomplete: u32,
    /// Samples none of whose packets was delivered (the hub never hears of them).
    pub vanished: u32,
}

impl Accounting {
    /// The sum of `s`'s decode-error counters.
    pub fn decode_errors(s: &Status) -> u32 {
        s.crc_errors
            + s.framing_errors
            + s.oversize_frames
            + s.malformed
            + s.unknown_version
            + s.unknown_joint
    }

    /// Each counter of `s` (a hub's status after the stream, drop policy, nothing else sent
    /// but configuration) that disagrees with this accounting, as `name got != expected`.
    pub fn mismatches(&self, s: &Status) -> Vec<String> {
        [
            ("packets_accepted", s.packets_accepted, self.delivered),
            ("decode errors", Self::decode_errors(s), self.bad_runs),
            ("samples_completed", s.samples_completed, self.complete),
            ("samples_incomplete", s.samples_incomplete, self.incomplete),
            ("late_packets", s.late_packets, 0),
            ("duplicate_packets", s.duplicate_packets, 0),
            ("out_of_range", s.out_of_range, 0),
            ("uart_overruns", s.uart_overruns, 0),
        ]
        .into_iter()
        .filter(|(_, got, want)| got != want)
        .map(|(name, got, want)| format!("{name} {got} != {want}"))
        .collect()
    }
}

impl<P: NodePacket> Damaged<P> {
    /// Packets with fate `fate`.
    pub fn count(&self, fate: Fate) -> u32 {
        self.packets.iter().filter(|(_, f)| *f == fate).count() as u32
    }

    /// Per sample (`seq`): its packets sent, and how many of them were delivered.
    pub fn per_sample(&self) -> BTreeMap<u32, (u32, u32)> {
        let mut samples: BTreeMap<u32, (u32, u32)> = BTreeMap::new();
        for (p, fate) in &self.packets {
            let e = samples.entry(p.seq()).or_default();
            e.0 += 1;
            e.1 += u32::from(*fate == Fate::Delivered);
        }
        samples
    }

    /// The samples whose packets were all delivered.
    pub fn intact_samples(&self) -> BTreeSet<u32> {
        self.per_sample()
            .into_iter()
            .filter(|(_, (sent, got))| sent == got)
            .map(|(seq, _)| seq)
            .collect()
    }

    /// What a hub must count (see the module docs).
    pub fn accounting(&self) -> Accounting {
        let runs = self.stream.split(|&b| b == 0).filter(|r| !r.is_empty());
        let delivered = self.count(Fate::Delivered);
        let samples = self.per_sample();
        let mut a = Accounting {
            delivered,
            dropped: self.count(Fate::Dropped),
            damaged: self.count(Fate::Damaged),
            bad_runs: runs.count() as u32 - delivered,
            ..Accounting::default()
        };
        for (sent, got) in samples.values() {
            match *got {
                0 => a.vanished += 1,
                g if g == *sent => a.complete += 1,
                _ => a.incomplete += 1,
            }
        }
        a
    }
}

/// Damages `samples` (each the packets of one sample, in sending order) as `plan` says.
pub fn damage<P: NodePacket>(samples: &[Vec<P>], plan: &FaultPlan) -> Damaged<P> {
    let mut rng = Rng::new(plan.seed);
    let window = plan.window.max(1) as usize;
    let mut d = Damaged {
        stream: vec![0u8],
        packets: Vec::new(),
        swapped: 0,
        bursts: 0,
    };
    let out = &mut d.stream;
    for block in samples.chunks(window) {
        let mut packets: Vec<P> = Vec::new();
        for sample in block {
            let start = packets.len();
            packets.extend_from_slice(sample);
            let n = sample.len();
            if rng.chance(plan.swap) && n >= 2 {
                let i = rng.below(n);
                let j = (i + 1 + rng.below(n - 1)) % n;
                packets.swap(start + i, start + j);
                d.swapped += 1;
            }
        }
        if rng.chance(plan.reorder) {
            // Fisher-Yates.
            for i in (1..packets.len()).rev() {
                packets.swap(i, rng.below(i + 1));
            }
        }
        for p in packets {
            if rng.chance(plan.drop) || (plan.silent.is_some() && plan.silent == p.joint()) {
                d.packets.push((p, Fate::Dropped));
                continue;
            }
            // Bytes not ended by a 0x00 before the frame make one run with it.
            let runs_in = out.last() != Some(&0);
            let start = out.len();
            push_frame(out, &p.message());
            let flipped = rng.chance(plan.flip);
            if flipped {
                let i = start + rng.below(out.len() - start);
                out[i] ^= 1 << rng.below(8);
            }
            let fate = if runs_in || flipped {
                Fate::Damaged
            } else {
                Fate::Delivered
            };
            d.packets.push((p, fate));
            if rng.chance(plan.garbage) {
                let n = 1 + rng.below(40);
                d.bursts += 1;
                out.extend((0..n).map(|_| match plan.noise {
                    Noise::Any => rng.next_u64() as u8,
                    Noise::NonZero => 1 + rng.below(255) as u8,
                }));
            }
        }
    }
    d
}

/// The samples of a clean stream of joint-angle packets (e.g. from `qgait packets`): each run
/// of consecutive packets with the same sequence number is a sample. Anything else in the
/// stream (a damaged frame, another message) is an error naming its byte offset.
pub fn samples_of_stream(stream: &[u8]) -> Result<Vec<Vec<JointAngle>>, EmulateError> {
    let mut samples: Vec<Vec<JointAngle>> = Vec::new();
    let mut decoder = FrameDecoder::new();
    for (i, &b) in stream.iter().enumerate() {
        match decoder.push(b) {
            None => {}
            Some(Ok(Message::JointAngle(p))) => match samples.last_mut() {
                Some(s) if s.first().is_some_and(|q| q.seq == p.seq) => s.push(p),
                _ => samples.push(vec![p]),
            },
            Some(Ok(m)) => {
                return Err(EmulateError::Stream {
                    offset: i,
                    problem: format!("a {} message, not a joint-angle packet", m.tag()),
                })
            }
            Some(Err(e)) => {
                return Err(EmulateError::Stream {
                    offset: i,
                    problem: format!("a damaged frame ({e})"),
                })
            }
        }
    }
    Ok(samples)
}

/// What a stream delivers to a hub, found with the protocol's decoder (as the hub decodes it).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Arrivals {
    /// The decodable joint-angle packets, by sequence number.
    pub packets: BTreeMap<u32, Vec<JointAngle>>,
    /// The decodable segment-orientation packets: the segments that arrived (one bit per
    /// [`SegmentId`](qgait_proto::SegmentId)), by sequence number.
    pub segments: BTreeMap<u32, u8>,
    /// The last [`ImuConfig`] of the stream, if any: with an orientation input mode, the
    /// stream's samples are segment orientations.
    pub imu: Option<ImuConfig>,
    /// The counters the hub's decoder must end with (`packets_accepted` and the decode-error
    /// counters).
    pub status: Status,
}

/// Whether a hub takes node packet `m` (`packets_accepted`): a joint angle it can use
/// ([`JointAngle::usable`](qgait_proto::JointAngle::usable)), a segment orientation whose
/// quaternion is of unit length (protocol.md 8.3, 8.9). Other messages are not packets:
/// `false`.
pub(crate) fn accepted(m: &Message) -> bool {
    match m {
        Message::JointAngle(p) => p.usable(),
        Message::SegmentOrientation(p) => qgait_proto::device_model::packet_quat::<f32>(p).is_ok(),
        _ => false,
    }
}

impl Arrivals {
    /// Decodes `stream`.
    pub fn of(stream: &[u8]) -> Arrivals {
        let mut a = Arrivals::default();
        for r in FrameDecoder::new().feed(stream) {
            match r {
                // (A packet the hub does not take, an unusable angle or a quaternion not of
                // unit length, leaves its sample incomplete.)
                Ok(ref m @ (Message::JointAngle(_) | Message::SegmentOrientation(_)))
                    if !accepted(m) => {}
                Ok(Message::JointAngle(p)) => {
                    a.status.packets_accepted += 1;
                    a.packets.entry(p.seq).or_default().push(p);
                }
                Ok(Message::SegmentOrientation(p)) => {
                    a.status.packets_accepted += 1;
                    *a.segments.entry(p.header.seq).or_default() |= segment_bit(p.header.segment);
                }
                Ok(Message::ImuConfig(c)) => a.imu = Some(c),
                Ok(_) => {}
                Err(e) => a.status.count_decode_error(&e),
            }
        }
        a
    }

    /// The segments an orientation sample needs, if the stream's input is orientations.
    fn orientation_segments(&self) -> Option<u8> {
        self.imu
            .filter(|c| c.mode.orientations())
            .map(|c| c.segments)
    }

    /// Whether every packet a sample `seq` needs arrived: every joint `model` needs, or, for a
    /// stream of segment orientations, every segment of its [`ImuConfig`].
    pub fn intact(&self, seq: u32, model: ModelId) -> bool {
        if let Some(required) = self.orientation_segments() {
            return self
                .segments
                .get(&seq)
                .is_some_and(|got| got & required == required);
        }
        self.packets.get(&seq).is_some_and(|ps| {
            model
                .required_joints()
                .iter()
                .all(|j| ps.iter().any(|p| p.joint == *j))
        })
    }

    /// The samples of which every packet arrived ([`intact`](Self::intact)).
    pub fn intact_samples(&self, model: ModelId) -> BTreeSet<u32> {
        let seqs: Vec<u32> = match self.orientation_segments() {
            Some(_) => self.segments.keys().copied().collect(),
            None => self.packets.keys().copied().collect(),
        };
        seqs.into_iter()
            .filter(|&s| self.intact(s, model))
            .collect()
    }

    /// The samples a hub sends a pose frame for: the intact ones, except, for a stream of
    /// segment orientations that asks for a calibration, the first intact one (the
    /// calibration pose, which gives no frame).
    pub fn framed_samples(&self, model: ModelId) -> BTreeSet<u32> {
        let mut intact = self.intact_samples(model);
        if self
            .imu
            .is_some_and(|c| c.mode.orientations() && c.calibrate)
        {
            intact.pop_first();
        }
        intact
    }

    /// Samples of which some but not all packets arrived.
    pub fn partial(&self, model: ModelId) -> Vec<u32> {
        if self.orientation_segments().is_some() {
            return self
                .segments
                .keys()
                .copied()
                .filter(|&seq| !self.intact(seq, model))
                .collect();
        }
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
    use crate::packet;

    /// The clean stream of `samples`: a 0x00, then each packet's frame.
    fn stream(samples: &[Vec<JointAngle>]) -> Vec<u8> {
        let mut out = vec![0u8];
        for p in samples.iter().flatten() {
            push_frame(&mut out, &Message::JointAngle(*p));
        }
        out
    }

    /// The packets of `d` with fate `fate`, as (sequence number, joint) pairs in order.
    fn keys(d: &Damaged, fate: Fate) -> Vec<(u32, JointId)> {
        let mut k: Vec<_> = d
            .packets
            .iter()
            .filter(|(_, f)| *f == fate)
            .map(|(p, _)| (p.seq, p.joint))
            .collect();
        k.sort_unstable();
        k
    }

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

    /// The ledger against the protocol's decoder: exactly the delivered packets decode, and
    /// the accounting equals the decoder's counts.
    fn ledger_agrees_with_the_decoder(d: &Damaged) -> Accounting {
        // The stream as the hub reads it: followed by the 0x00 of the host's next request.
        let a = Arrivals::of(&[d.stream.as_slice(), &[0]].concat());
        let mut decoded: Vec<(u32, JointId)> = a
            .packets
            .values()
            .flatten()
            .map(|p| (p.seq, p.joint))
            .collect();
        decoded.sort_unstable();
        assert_eq!(decoded, keys(d, Fate::Delivered));
        // Every decoded packet is the one sent, bit for bit.
        for (p, _) in d.packets.iter().filter(|(_, f)| *f == Fate::Delivered) {
            assert!(a.packets[&p.seq].contains(p), "{p:?}");
        }
        let acc = d.accounting();
        assert_eq!(acc.delivered, a.status.packets_accepted);
        assert_eq!(acc.bad_runs, Accounting::decode_errors(&a.status));
        assert_eq!(acc.complete as usize, a.intact_samples(ModelId::Phak).len());
        assert_eq!(acc.incomplete as usize, a.partial(ModelId::Phak).len());
        assert_eq!(
            acc.delivered + acc.dropped + acc.damaged,
            d.packets.len() as u32
        );
        acc
    }

    #[test]
    fn a_packet_the_hub_does_not_take_leaves_its_sample_incomplete() {
        // Intact on the wire, but an angle the hub does not use (protocol.md 8.3).
        let mut s = samples(5);
        s[2][3].angle = f32::NAN;
        let a = Arrivals::of(&stream(&s));
        assert_eq!(a.status.packets_accepted, 39);
        assert!(!a.intact(2, ModelId::Phak));
        assert!(a.intact(3, ModelId::Phak));
        assert_eq!(a.partial(ModelId::Phak), vec![2]);
        assert_eq!(crate::session::InputCounts::of(&stream(&s)).accepted, 39);
    }

    #[test]
    fn no_damage_delivers_everything() {
        let d = damage(&samples(20), &FaultPlan::none(4));
        let a = Arrivals::of(&d.stream);
        assert_eq!(a.status.packets_accepted, 160);
        assert!((0..20).all(|s| a.intact(s, ModelId::Phak)));
        assert!(a.partial(ModelId::Phak).is_empty());
        let acc = ledger_agrees_with_the_decoder(&d);
        assert_eq!((acc.delivered, acc.bad_runs, acc.complete), (160, 0, 20));
        assert_eq!(d.stream, stream(&samples(20)));
    }

    #[test]
    fn radio_link_damage_at_its_rates_is_all_accounted_for() {
        let s = samples(2000);
        let plan = FaultPlan::radio_link(1, 4);
        let d = damage(&s, &plan);
        let acc = ledger_agrees_with_the_decoder(&d);
        let sent = d.packets.len() as f64;
        assert_eq!(sent, 16_000.0);
        // Each rate within 5 standard deviations of its probability.
        let near =
            |got: f64, n: f64, p: f64| (got - n * p).abs() < 5.0 * (n * p * (1.0 - p)).sqrt();
        assert!(near(f64::from(acc.dropped), sent, 0.04), "{acc:?}");
        assert!(near(f64::from(d.swapped), 2000.0, 0.02), "{}", d.swapped);
        assert!(near(f64::from(d.bursts), sent, 0.01), "{}", d.bursts);
        // Flipped (4 % of those sent) plus those a burst ran into (1 %); about half the samples
        // (0.91^8) lose none of their 8 packets.
        assert!((600..900).contains(&acc.damaged), "{acc:?}");
        assert!(acc.incomplete > 500 && acc.complete > 800, "{acc:?}");
        // Swaps stay inside a sample.
        let mut newest = 0;
        for (p, _) in &d.packets {
            assert!(p.seq + 1 >= newest, "seq {} after {newest}", p.seq);
            newest = newest.max(p.seq);
        }
    }

    #[test]
    fn a_burst_of_non_zero_noise_destroys_the_next_packet_only() {
        // Every packet followed by noise, nothing else.
        let plan = FaultPlan {
            garbage: 1.0,
            noise: Noise::NonZero,
            ..FaultPlan::none(4)
        };
        let d = damage(&samples(10), &plan);
        let acc = ledger_agrees_with_the_decoder(&d);
        // The first packet follows the leading 0x00; every later one runs into noise, and
        // the last burst is a run of its own once the next 0x00 ends it.
        assert_eq!((acc.delivered, acc.damaged, acc.bad_runs), (1, 79, 80));
    }

    #[test]
    fn a_node_down_leaves_every_sample_incomplete() {
        let plan = FaultPlan {
            silent: Some(JointId::KneeAngleR),
            ..FaultPlan::none(4)
        };
        let d = damage(&samples(10), &plan);
        let acc = ledger_agrees_with_the_decoder(&d);
        assert_eq!(
            (acc.delivered, acc.dropped, acc.complete, acc.incomplete),
            (70, 10, 0, 10)
        );
    }

    #[test]
    fn damage_is_seeded_and_reordering_stays_inside_the_window() {
        let plan = FaultPlan {
            seed: 7,
            flip: 0.05,
            drop: 0.05,
            swap: 0.1,
            reorder: 0.5,
            window: 4,
            garbage: 0.05,
            noise: Noise::Any,
            silent: None,
        };
        let s = samples(400);
        let d = damage(&s, &plan);
        assert_eq!(d, damage(&s, &plan));
        assert_ne!(d.stream, damage(&s, &FaultPlan { seed: 8, ..plan }).stream);
        ledger_agrees_with_the_decoder(&d);
        let a = Arrivals::of(&d.stream);
        let errors = Accounting::decode_errors(&a.status);
        assert!(
            errors > 0 && a.partial(ModelId::Phak).len() > 10,
            "{:?}",
            a.status
        );
        // In arrival order, no packet comes after one of a sample `window` or more ahead.
        let mut newest = 0u32;
        for r in FrameDecoder::new().feed(
            &damage(
                &s,
                &FaultPlan {
                    flip: 0.0,
                    drop: 0.0,
                    garbage: 0.0,
                    ..plan
                },
            )
            .stream,
        ) {
            let Ok(Message::JointAngle(p)) = r else {
                panic!("{r:?}")
            };
            assert!(newest < p.seq + 4, "seq {} after {newest}", p.seq);
            newest = newest.max(p.seq);
        }
    }

    #[test]
    fn samples_are_read_back_from_a_clean_stream_and_damage_is_refused() {
        let s = samples(30);
        let clean = stream(&s);
        assert_eq!(samples_of_stream(&clean).unwrap(), s);
        let d = damage(&s, &FaultPlan::radio_link(3, 4));
        let e = samples_of_stream(&d.stream).unwrap_err();
        assert!(
            matches!(&e, EmulateError::Stream { problem, .. } if problem.contains("damaged frame")),
            "{e:?}"
        );
    }
}
