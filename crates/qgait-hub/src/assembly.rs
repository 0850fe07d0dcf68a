//! Sample assembly: per-joint packets gathered by sequence number in a small reorder window.
//!
//! Every IMU node sends one [`JointAngle`](qgait_proto::JointAngle) per joint per sample, all
//! tagged with the sample's sequence number. Packets arrive interleaved and slightly out of
//! order. The [`Assembler`] keeps the last `window` sequence numbers open: a sample completes
//! as soon as every joint the model needs has arrived, and a sample that leaves the window
//! incomplete is either dropped or completed with the last known values
//! ([`MissingPolicy`](qgait_proto::MissingPolicy)). Packets older than the window, duplicates
//! and joints the model does not use are reported to the caller, which counts them.
//!
//! Sequence numbers wrap around (`u32`). A jump of more than [`RESYNC_DISTANCE`] samples either
//! way (a node restarted, or a long outage) abandons the open samples and restarts the window
//! at the new number, so a restarted sender is never taken for an endless stream of late
//! packets.
//!
//! The same window assembles the samples of the IMU orientation input ([`SegmentSample`]):
//! the assembler is generic over the value a packet carries and the number of keys (17 joint
//! angles, or 8 segments' Q14 quaternions), with the same window, late, duplicate, resync and
//! missing policies.
//!
//! The caller judges each packet's angle in or out of range as it arrives
//! ([`Assembler::push`]); a sample carries the joints whose angle was out of range
//! ([`Sample::out_of_range`]), a held angle with the judgement of the packet it came from, so
//! nothing re-checks the angles when a sample leaves.

use qgait_proto::JointId;

/// The deepest reorder window the assembler supports (samples): the protocol's
/// [`MAX_REORDER_WINDOW`](qgait_proto::MAX_REORDER_WINDOW), the deepest a configuration asks for.
pub const MAX_WINDOW: usize = qgait_proto::MAX_REORDER_WINDOW as usize;

/// Sequence-number distance beyond which the window restarts (see the module docs).
pub const RESYNC_DISTANCE: u32 = 1024;

const JOINTS: usize = JointId::COUNT;

/// A sample of the orientation input: each segment's Q14 quaternion (`w, x, y, z`), indexed
/// by the segment's wire byte ([`WireByte`](qgait_proto::WireByte)).
pub type SegmentSample = Sample<[i16; 4], { qgait_kernel::imu::SENSORS }>;

/// The orientation input's assembler: one Q14 quaternion per segment.
pub type SegmentAssembler = Assembler<[i16; 4], { qgait_kernel::imu::SENSORS }>;

/// A set of joints, one bit per [`JointId::index`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointSet(u32);

impl JointSet {
    /// The empty set.
    pub const EMPTY: JointSet = JointSet(0);

    /// The set of the keys whose bits are set in `bits` (bit `i` for key `i`: a joint's or a
    /// segment's index).
    pub const fn from_bits(bits: u32) -> JointSet {
        JointSet(bits)
    }

    /// Whether key `index` is in the set.
    pub fn contains_index(self, index: u8) -> bool {
        self.0 & (1 << index) != 0
    }

    /// The set of `joints`.
    pub fn of(joints: &[JointId]) -> JointSet {
        joints.iter().fold(JointSet::EMPTY, |s, &j| s.with(j))
    }

    /// This set plus `joint`.
    pub fn with(self, joint: JointId) -> JointSet {
        JointSet(self.0 | 1 << joint.index())
    }

    /// Whether `joint` is in the set.
    pub fn contains(self, joint: JointId) -> bool {
        self.0 & (1 << joint.index()) != 0
    }

    /// Whether every joint of `other` is in this set.
    pub fn contains_all(self, other: JointSet) -> bool {
        self.0 & other.0 == other.0
    }

    /// The joints of `other` that are not in this set.
    pub fn missing_from(self, other: JointSet) -> JointSet {
        JointSet(other.0 & !self.0)
    }

    /// The joints in this set or in `other`.
    pub fn union(self, other: JointSet) -> JointSet {
        JointSet(self.0 | other.0)
    }

    /// The joints in both this set and `other`.
    pub fn intersection(self, other: JointSet) -> JointSet {
        JointSet(self.0 & other.0)
    }

    /// Number of joints in the set.
    pub fn len(self) -> u32 {
        self.0.count_ones()
    }

    /// Whether the set is empty.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// One assembled sample: an angle for every joint the model needs (or, for the orientation
/// input, a quaternion for every segment the nodes send: [`SegmentSample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample<V = f32, const N: usize = JOINTS> {
    /// Sequence number shared by the sample's packets.
    pub seq: u32,
    /// Sensor time of the sample (µs): the `timestamp_us` of the packet that opened it (a
    /// sample's packets share theirs).
    pub timestamp_us: u32,
    /// Angles in radians indexed by [`JointId::index`]; only the model's joints are meaningful
    /// (the orientation input: quaternions by segment index).
    pub angles: [V; N],
    /// Joints whose angle is out of range, as judged when its packet arrived (see
    /// [`Assembler::push`]); a held angle is out of range if the packet it came from was.
    pub out_of_range: JointSet,
}

impl Sample<f32, JOINTS> {
    /// The angle of `joint` (radians).
    pub fn angle(&self, joint: JointId) -> f32 {
        self.angles[joint.index() as usize]
    }
}

/// What happened to one packet given to [`Assembler::push`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PacketOutcome {
    /// Stored in an open sample (which may have completed: see the events).
    Stored,
    /// Older than the reorder window: dropped.
    Late,
    /// This joint of this sample had already arrived, or the sample was already complete.
    Duplicate,
    /// The configured model does not use this joint: dropped.
    NotRequired,
    /// The sequence number jumped by more than [`RESYNC_DISTANCE`]: the window restarted there
    /// and the packet was stored.
    Resynced,
}

/// A sample leaving the assembler, reported through the callback of [`Assembler::push`]. The
/// sample is lent from the assembler's window for the call, not copied out of it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SampleEvent<'a, V = f32, const N: usize = JOINTS> {
    /// Every required joint arrived.
    Complete(&'a Sample<V, N>),
    /// The sample left the window incomplete and its missing joints were filled with the last
    /// known values (policy `HoldLast`).
    Held {
        /// The sample, missing joints filled.
        sample: &'a Sample<V, N>,
        /// The joints whose angle was held from an earlier sample.
        held: JointSet,
    },
    /// The sample left the window incomplete and was dropped; `missing` says which joints
    /// never arrived.
    Dropped {
        /// Sequence number of the dropped sample.
        seq: u32,
        /// Required joints that never arrived.
        missing: JointSet,
    },
}

/// One sample of the window. Its state is in `present`: free if empty (a slot is opened by a
/// packet it then stores), complete if it holds every required joint, open otherwise.
#[derive(Debug, Clone, Copy)]
struct Slot<V, const N: usize> {
    present: JointSet,
    /// The sample as it is assembled: its sequence number, the angles of the `present` joints,
    /// those of them whose packet was out of range; the events lend it.
    sample: Sample<V, N>,
}

impl<V: Copy + Default, const N: usize> Slot<V, N> {
    fn free() -> Self {
        Slot {
            present: JointSet::EMPTY,
            sample: Sample {
                seq: 0,
                timestamp_us: 0,
                angles: [V::default(); N],
                out_of_range: JointSet::EMPTY,
            },
        }
    }

    /// Whether the slot holds a sample (open or complete).
    fn is_used(&self) -> bool {
        !self.present.is_empty()
    }
}

/// The reorder window (see the module docs).
#[derive(Debug, Clone)]
pub struct Assembler<V = f32, const N: usize = JOINTS> {
    slots: [Slot<V, N>; MAX_WINDOW],
    /// `1..=MAX_WINDOW`.
    window: u8,
    required: JointSet,
    hold_last: bool,
    newest: Option<u32>,
    /// Newest angle of each joint among the samples that already left the window (the values
    /// hold-last uses: always older than the sample being completed).
    last_angle: [V; N],
    /// Joints with a value in `last_angle`.
    known: JointSet,
    /// The joints of `known` whose value in `last_angle` came from an out-of-range packet.
    last_out_of_range: JointSet,
}

impl Assembler {
    /// An empty assembler needing `required` joints, with a window of `window` samples
    /// (clamped to `1..=MAX_WINDOW`), holding last values for incomplete samples if `hold_last`.
    pub fn new(required: &[JointId], window: u8, hold_last: bool) -> Assembler {
        Assembler::with_keys(JointSet::of(required), window, hold_last)
    }

    /// Takes one packet: the angle of `joint` in sample `seq` taken at `timestamp_us` (kept as
    /// the sample's if the packet opens it), and whether the caller found it
    /// out of range (carried to the sample's [`Sample::out_of_range`], and to later samples
    /// that hold this angle). Samples that complete or leave the window are reported to
    /// `on_event` in sequence order (evictions first, then the packet's own sample if it
    /// completed).
    #[inline(always)]
    pub fn push(
        &mut self,
        seq: u32,
        timestamp_us: u32,
        joint: JointId,
        angle: f32,
        out_of_range: bool,
        on_event: &mut impl FnMut(SampleEvent),
    ) -> PacketOutcome {
        self.push_key(
            seq,
            timestamp_us,
            joint.index(),
            angle,
            out_of_range,
            on_event,
        )
    }
}

impl<V: Copy + Default, const N: usize> Assembler<V, N> {
    /// An empty assembler needing the keys of `required` (each below `N`), with a window of
    /// `window` samples (clamped to `1..=MAX_WINDOW`), holding last values for incomplete
    /// samples if `hold_last`.
    pub fn with_keys(required: JointSet, window: u8, hold_last: bool) -> Self {
        Assembler {
            slots: core::array::from_fn(|_| Slot::free()),
            window: window.clamp(1, MAX_WINDOW as u8),
            required,
            hold_last,
            newest: None,
            last_angle: [V::default(); N],
            known: JointSet::EMPTY,
            last_out_of_range: JointSet::EMPTY,
        }
    }

    /// The keys a sample needs.
    pub fn required(&self) -> JointSet {
        self.required
    }

    /// The window depth in samples.
    pub fn window(&self) -> u8 {
        self.window
    }

    /// Number of samples currently open (some but not all joints arrived).
    #[cfg(test)]
    pub(crate) fn open_samples(&self) -> usize {
        self.slots
            .iter()
            .filter(|s| s.is_used() && !s.present.contains_all(self.required))
            .count()
    }

    /// [`Assembler::push`] for any key: the value of key `key` (a joint's or a segment's
    /// index) in sample `seq` taken at `timestamp_us`.
    pub fn push_key(
        &mut self,
        seq: u32,
        timestamp_us: u32,
        key: u8,
        angle: V,
        out_of_range: bool,
        on_event: &mut impl FnMut(SampleEvent<V, N>),
    ) -> PacketOutcome {
        if !self.required.contains_index(key) || usize::from(key) >= N {
            return PacketOutcome::NotRequired;
        }
        let mut outcome = PacketOutcome::Stored;
        match self.newest {
            None => self.newest = Some(seq),
            Some(newest) => {
                let ahead = seq.wrapping_sub(newest);
                let behind = newest.wrapping_sub(seq);
                if ahead != 0 && ahead <= RESYNC_DISTANCE {
                    self.advance_to(seq, on_event);
                } else if ahead == 0 || behind < self.window as u32 {
                    // Inside the window.
                } else if behind <= RESYNC_DISTANCE {
                    return PacketOutcome::Late;
                } else {
                    self.flush(on_event);
                    self.newest = Some(seq);
                    outcome = PacketOutcome::Resynced;
                }
            }
        }
        // Every used slot holds a sequence number inside the window (less than MAX_WINDOW
        // apart from `seq`), so sample `seq` lives in slot `seq % MAX_WINDOW`: free, or holding
        // `seq` itself.
        let slot = &mut self.slots[seq as usize % MAX_WINDOW];
        if !slot.is_used() {
            // The angles are left as the slot's last sample had them (not zeroed: a 68-byte
            // copy per sample): only the angles of present joints are ever read (a sample
            // completes with every required joint present, a held one overwrites the missing
            // ones), and joints the model does not use are never stored, so stay 0.0.
            slot.sample.seq = seq;
            slot.sample.timestamp_us = timestamp_us;
            slot.sample.out_of_range = JointSet::EMPTY;
        } else if slot.sample.seq != seq {
            // Unreachable by the invariant above; refused rather than mixed into another sample.
            return PacketOutcome::Late;
        }
        // `joint` is required: present already in a complete sample too.
        if slot.present.contains_index(key) {
            return PacketOutcome::Duplicate;
        }
        let Some(value) = slot.sample.angles.get_mut(usize::from(key)) else {
            return PacketOutcome::NotRequired;
        };
        *value = angle;
        let bit = JointSet(1 << key);
        slot.present = slot.present.union(bit);
        if out_of_range {
            slot.sample.out_of_range = slot.sample.out_of_range.union(bit);
        }
        if slot.present.contains_all(self.required) {
            on_event(SampleEvent::Complete(&slot.sample));
        }
        outcome
    }

    /// Closes every open sample (as if the window had moved past them), reporting each one.
    pub fn flush(&mut self, on_event: &mut impl FnMut(SampleEvent<V, N>)) {
        while let Some(i) = self.oldest_slot(|_| true) {
            self.retire(i, on_event);
        }
    }

    /// Moves the newest sequence number to `seq`, retiring the samples that leave the window.
    fn advance_to(&mut self, seq: u32, on_event: &mut impl FnMut(SampleEvent<V, N>)) {
        let window = self.window as u32;
        if let Some(newest) = self.newest {
            // Used slots hold samples `newest - window < s <= newest`, sample `s` in slot
            // `s % MAX_WINDOW`; those with `seq - s >= window` leave the window, oldest first.
            // `seq` is ahead of `newest` (by at most RESYNC_DISTANCE), so `seq - s` falls as `s`
            // rises: the leaving ones are a run from the oldest.
            let mut s = newest.wrapping_sub(window - 1);
            for _ in 0..window {
                if seq.wrapping_sub(s) < window {
                    break;
                }
                let i = s as usize % MAX_WINDOW;
                if self.slots[i].is_used() && self.slots[i].sample.seq == s {
                    self.retire(i, on_event);
                }
                s = s.wrapping_add(1);
            }
        }
        self.newest = Some(seq);
    }

    /// The used slot with the oldest sequence number among those `leaving` selects.
    fn oldest_slot(&self, leaving: impl Fn(u32) -> bool) -> Option<usize> {
        let newest = self.newest.unwrap_or(0);
        self.slots
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_used() && leaving(s.sample.seq))
            .max_by_key(|(_, s)| newest.wrapping_sub(s.sample.seq))
            .map(|(i, _)| i)
    }

    /// Frees slot `i`: its angles become the last known values, and an open sample is
    /// completed with held values (in the slot) or dropped.
    fn retire(&mut self, i: usize, on_event: &mut impl FnMut(SampleEvent<V, N>)) {
        let Assembler {
            slots,
            required,
            hold_last,
            last_angle,
            known,
            last_out_of_range,
            ..
        } = self;
        let Some(slot) = slots.get_mut(i) else { return };
        // Frees the slot.
        let present = core::mem::take(&mut slot.present);
        if present.is_empty() {
            return;
        }
        let sample = &mut slot.sample;
        // The last known values first: they are only ever read for the joints a sample lacks,
        // never for this one's present joints, so the sample held below gets older ones.
        if *hold_last {
            for (k, (last, value)) in last_angle.iter_mut().zip(&sample.angles).enumerate() {
                if present.contains_index(k as u8) {
                    *last = *value;
                }
            }
            *known = known.union(present);
            // The present joints' judgements replace the ones of their older values.
            *last_out_of_range = present
                .missing_from(*last_out_of_range)
                .union(sample.out_of_range);
        }
        let missing = present.missing_from(*required);
        // Open, not complete.
        if !missing.is_empty() {
            if *hold_last && known.contains_all(missing) {
                for (k, (value, last)) in sample.angles.iter_mut().zip(&*last_angle).enumerate() {
                    if missing.contains_index(k as u8) {
                        *value = *last;
                    }
                }
                // A held angle is out of range if the packet it came from was.
                sample.out_of_range = sample
                    .out_of_range
                    .union(last_out_of_range.intersection(missing));
                on_event(SampleEvent::Held {
                    sample,
                    held: missing,
                });
            } else {
                on_event(SampleEvent::Dropped {
                    seq: sample.seq,
                    missing,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests;
