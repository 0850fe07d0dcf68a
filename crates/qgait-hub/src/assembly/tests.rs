extern crate std;
use super::*;
use std::vec::Vec;

const TWO: [JointId; 2] = [JointId::HipFlexionR, JointId::KneeAngleR];

/// A [`SampleEvent`] as the tests keep it: the sample copied out of the assembler.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Event {
    Complete(Sample),
    Held(Sample, JointSet),
    Dropped { seq: u32, missing: JointSet },
}

fn own(e: SampleEvent<'_>) -> Event {
    match e {
        SampleEvent::Complete(s) => Event::Complete(*s),
        SampleEvent::Held { sample, held } => Event::Held(*sample, held),
        SampleEvent::Dropped { seq, missing } => Event::Dropped { seq, missing },
    }
}

/// The event of sample `seq` dropped for lack of `missing`.
fn dropped(seq: u32, missing: &[JointId]) -> Event {
    Event::Dropped {
        seq,
        missing: JointSet::of(missing),
    }
}

fn push(a: &mut Assembler, seq: u32, joint: JointId, angle: f32) -> (PacketOutcome, Vec<Event>) {
    push_judged(a, seq, joint, angle, false)
}

fn push_judged(
    a: &mut Assembler,
    seq: u32,
    joint: JointId,
    angle: f32,
    out_of_range: bool,
) -> (PacketOutcome, Vec<Event>) {
    let mut events = Vec::new();
    let outcome = a.push(
        seq,
        seq.wrapping_mul(10_000),
        joint,
        angle,
        out_of_range,
        &mut |e| events.push(own(e)),
    );
    (outcome, events)
}

#[test]
fn sample_completes_when_every_required_joint_arrived() {
    let mut a = Assembler::new(&TWO, 4, false);
    assert_eq!(
        push(&mut a, 7, JointId::KneeAngleR, -0.5),
        (PacketOutcome::Stored, Vec::new())
    );
    let (outcome, events) = push(&mut a, 7, JointId::HipFlexionR, 0.25);
    assert_eq!(outcome, PacketOutcome::Stored);
    match events.as_slice() {
        [Event::Complete(s)] => {
            assert_eq!(s.seq, 7);
            assert_eq!(s.angle(JointId::HipFlexionR), 0.25);
            assert_eq!(s.angle(JointId::KneeAngleR), -0.5);
        }
        other => panic!("unexpected events {other:?}"),
    }
    assert_eq!(a.open_samples(), 0);
}

#[test]
fn packets_of_a_completed_sample_are_duplicates() {
    let mut a = Assembler::new(&TWO, 4, false);
    push(&mut a, 1, JointId::HipFlexionR, 0.0);
    push(&mut a, 1, JointId::KneeAngleR, 0.0);
    assert_eq!(
        push(&mut a, 1, JointId::KneeAngleR, 0.0).0,
        PacketOutcome::Duplicate
    );
    push(&mut a, 2, JointId::KneeAngleR, 0.0);
    assert_eq!(
        push(&mut a, 2, JointId::KneeAngleR, 0.0).0,
        PacketOutcome::Duplicate
    );
}

#[test]
fn sample_leaving_the_window_incomplete_is_dropped_in_order() {
    let mut a = Assembler::new(&TWO, 3, false);
    push(&mut a, 10, JointId::HipFlexionR, 0.0);
    push(&mut a, 11, JointId::KneeAngleR, 0.0);
    push(&mut a, 12, JointId::KneeAngleR, 0.0);
    // 14 pushes 10 and 11 out (window 3 keeps 12, 13, 14).
    let (_, events) = push(&mut a, 14, JointId::KneeAngleR, 0.0);
    assert_eq!(
        events,
        [
            dropped(10, &[JointId::KneeAngleR]),
            dropped(11, &[JointId::HipFlexionR]),
        ]
    );
    assert_eq!(
        push(&mut a, 11, JointId::HipFlexionR, 0.0).0,
        PacketOutcome::Late
    );
    // 12 is still open and completes.
    let (_, events) = push(&mut a, 12, JointId::HipFlexionR, 0.0);
    assert!(matches!(events.as_slice(), [Event::Complete(s)] if s.seq == 12));
}

#[test]
fn hold_last_fills_missing_joints_with_the_newest_known_value() {
    let mut a = Assembler::new(&TWO, 2, true);
    push(&mut a, 1, JointId::HipFlexionR, 0.1);
    push(&mut a, 1, JointId::KneeAngleR, -0.1);
    push(&mut a, 2, JointId::HipFlexionR, 0.2);
    let (_, events) = push(&mut a, 4, JointId::HipFlexionR, 0.4);
    match events.as_slice() {
        [Event::Held(s, held)] => {
            assert_eq!(s.seq, 2);
            assert_eq!(s.angle(JointId::HipFlexionR), 0.2);
            assert_eq!(s.angle(JointId::KneeAngleR), -0.1);
            assert_eq!(*held, JointSet::of(&[JointId::KneeAngleR]));
        }
        other => panic!("unexpected events {other:?}"),
    }
}

#[test]
fn a_sample_carries_its_out_of_range_joints() {
    let mut a = Assembler::new(&TWO, 4, false);
    push_judged(&mut a, 1, JointId::KneeAngleR, 1.5, true);
    let (_, events) = push_judged(&mut a, 1, JointId::HipFlexionR, 0.2, false);
    match events.as_slice() {
        [Event::Complete(s)] => {
            assert_eq!(s.out_of_range, JointSet::of(&[JointId::KneeAngleR]))
        }
        other => panic!("unexpected events {other:?}"),
    }
    push(&mut a, 2, JointId::KneeAngleR, -0.5);
    let (_, events) = push(&mut a, 2, JointId::HipFlexionR, 0.2);
    assert!(matches!(events.as_slice(), [Event::Complete(s)] if s.out_of_range.is_empty()));
}

#[test]
fn a_held_angle_keeps_the_judgement_of_its_packet() {
    let mut a = Assembler::new(&TWO, 1, true);
    // Sample 1: the knee out of range, the hip in range.
    push_judged(&mut a, 1, JointId::KneeAngleR, 1.5, true);
    push(&mut a, 1, JointId::HipFlexionR, 0.1);
    // Sample 2 lacks the knee: it holds sample 1's out-of-range knee, and is flagged so
    // though every packet of its own was in range.
    push(&mut a, 2, JointId::HipFlexionR, 0.2);
    let (_, events) = push(&mut a, 3, JointId::HipFlexionR, 0.3);
    match events.as_slice() {
        [Event::Held(s, held)] => {
            assert_eq!(s.seq, 2);
            assert_eq!(s.angle(JointId::KneeAngleR), 1.5);
            assert_eq!(*held, JointSet::of(&[JointId::KneeAngleR]));
            assert_eq!(s.out_of_range, JointSet::of(&[JointId::KneeAngleR]));
        }
        other => panic!("unexpected events {other:?}"),
    }
    // Sample 3 lacks the knee too: still sample 1's knee, still flagged.
    let (_, events) = push_judged(&mut a, 4, JointId::KneeAngleR, -0.4, false);
    assert!(matches!(events.as_slice(),
        [Event::Held(s, _)] if s.seq == 3 && s.out_of_range == JointSet::of(&[JointId::KneeAngleR])));
    // Sample 4's knee arrived in range: sample 5, lacking the knee, holds that one, unflagged;
    // its own out-of-range hip is flagged.
    push(&mut a, 4, JointId::HipFlexionR, 0.4);
    push_judged(&mut a, 5, JointId::HipFlexionR, 2.5, true);
    let (_, events) = push(&mut a, 6, JointId::HipFlexionR, 0.6);
    match events.as_slice() {
        [Event::Held(s, held)] => {
            assert_eq!(s.seq, 5);
            assert_eq!(*held, JointSet::of(&[JointId::KneeAngleR]));
            assert_eq!(s.angle(JointId::KneeAngleR), -0.4);
            assert_eq!(s.out_of_range, JointSet::of(&[JointId::HipFlexionR]));
        }
        other => panic!("unexpected events {other:?}"),
    }
}

#[test]
fn hold_last_drops_when_a_joint_was_never_seen() {
    let mut a = Assembler::new(&TWO, 1, true);
    push(&mut a, 1, JointId::HipFlexionR, 0.1);
    let (_, events) = push(&mut a, 2, JointId::HipFlexionR, 0.1);
    assert_eq!(events, [dropped(1, &[JointId::KneeAngleR])]);
}

#[test]
fn joints_the_model_does_not_use_are_reported() {
    let mut a = Assembler::new(&TWO, 4, false);
    assert_eq!(
        push(&mut a, 1, JointId::PelvisTilt, 0.0).0,
        PacketOutcome::NotRequired
    );
    assert_eq!(a.open_samples(), 0);
}

#[test]
fn sequence_numbers_wrap_around() {
    let mut a = Assembler::new(&TWO, 2, false);
    push(&mut a, u32::MAX, JointId::HipFlexionR, 0.0);
    push(&mut a, 0, JointId::HipFlexionR, 0.0);
    let (_, events) = push(&mut a, u32::MAX, JointId::KneeAngleR, 0.0);
    assert!(matches!(events.as_slice(), [Event::Complete(s)] if s.seq == u32::MAX));
    let (_, events) = push(&mut a, 1, JointId::KneeAngleR, 0.0);
    assert_eq!(events, []);
    let (_, events) = push(&mut a, 2, JointId::KneeAngleR, 0.0);
    assert_eq!(events, [dropped(0, &[JointId::KneeAngleR])]);
}

#[test]
fn a_restarted_sender_resyncs_instead_of_being_late_forever() {
    let mut a = Assembler::new(&TWO, 4, false);
    push(&mut a, 1_000_000, JointId::HipFlexionR, 0.0);
    let (outcome, events) = push(&mut a, 0, JointId::HipFlexionR, 0.0);
    assert_eq!(outcome, PacketOutcome::Resynced);
    assert_eq!(events, [dropped(1_000_000, &[JointId::KneeAngleR])]);
    let (outcome, events) = push(&mut a, 0, JointId::KneeAngleR, 0.0);
    assert_eq!(outcome, PacketOutcome::Stored);
    assert!(matches!(events.as_slice(), [Event::Complete(s)] if s.seq == 0));
}

#[test]
fn window_is_clamped() {
    assert_eq!(Assembler::new(&TWO, 0, false).window(), 1);
    assert_eq!(Assembler::new(&TWO, 200, false).window(), MAX_WINDOW as u8);
}
/// The assembler as it was before slots were indexed by sequence number (a linear search
/// for the sample's slot, every slot copied on retirement, the last values always kept),
/// with the out-of-range judgements kept per joint as booleans beside the angles (the
/// assembler keeps them as sets): the reference the current one must match event for
/// event.
#[allow(dead_code)]
mod reference {
    use super::super::{JointSet, PacketOutcome, Sample, SampleEvent, MAX_WINDOW, RESYNC_DISTANCE};
    use qgait_proto::JointId;

    const JOINTS: usize = JointId::COUNT;

    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum SlotState {
        Free,
        Open,
        Done,
    }

    #[derive(Debug, Clone, Copy)]
    struct Slot {
        state: SlotState,
        seq: u32,
        /// The timestamp of the packet that opened it.
        time: u32,
        present: JointSet,
        angles: [f32; JOINTS],
        /// Whether each joint's packet was out of range.
        bad: [bool; JOINTS],
    }

    impl Slot {
        const FREE: Slot = Slot {
            state: SlotState::Free,
            seq: 0,
            time: 0,
            present: JointSet::EMPTY,
            angles: [0.0; JOINTS],
            bad: [false; JOINTS],
        };
    }

    /// The joints `bad` marks.
    fn bad_set(bad: &[bool; JOINTS]) -> JointSet {
        JointId::ALL
            .iter()
            .filter(|j| bad[j.index() as usize])
            .fold(JointSet::EMPTY, |s, &j| s.with(j))
    }

    /// The reorder window (see the module docs).
    #[derive(Debug, Clone)]
    pub struct Reference {
        slots: [Slot; MAX_WINDOW],
        window: u32,
        required: JointSet,
        hold_last: bool,
        newest: Option<u32>,
        /// Newest angle of each joint among the samples that already left the window (the values
        /// hold-last uses: always older than the sample being completed).
        last_angle: [f32; JOINTS],
        /// Joints with a value in `last_angle`.
        known: JointSet,
        /// Whether each value in `last_angle` came from an out-of-range packet.
        last_bad: [bool; JOINTS],
    }

    impl Reference {
        /// An empty assembler needing `required` joints, with a window of `window` samples
        /// (clamped to `1..=MAX_WINDOW`), holding last values for incomplete samples if `hold_last`.
        pub fn new(required: &[JointId], window: u8, hold_last: bool) -> Reference {
            Reference {
                slots: [Slot::FREE; MAX_WINDOW],
                window: (window as u32).clamp(1, MAX_WINDOW as u32),
                required: JointSet::of(required),
                hold_last,
                newest: None,
                last_angle: [0.0; JOINTS],
                known: JointSet::EMPTY,
                last_bad: [false; JOINTS],
            }
        }

        /// The window depth in samples.
        pub fn window(&self) -> u8 {
            self.window as u8
        }

        /// Number of samples currently open (some but not all joints arrived).
        #[cfg(test)]
        pub(crate) fn open_samples(&self) -> usize {
            self.slots
                .iter()
                .filter(|s| s.state == SlotState::Open)
                .count()
        }

        /// Takes one packet. Samples that complete or leave the window are reported to `on_event`
        /// in sequence order (evictions first, then the packet's own sample if it completed).
        pub fn push(
            &mut self,
            seq: u32,
            time: u32,
            joint: JointId,
            angle: f32,
            out_of_range: bool,
            on_event: &mut impl FnMut(SampleEvent),
        ) -> PacketOutcome {
            if !self.required.contains(joint) {
                return PacketOutcome::NotRequired;
            }
            let mut outcome = PacketOutcome::Stored;
            match self.newest {
                None => self.newest = Some(seq),
                Some(newest) => {
                    // The module docs' rule read as a signed distance from the newest sample
                    // (the assembler works with two unsigned ones): up to RESYNC_DISTANCE ahead
                    // moves the window, less than the window behind is inside it, up to
                    // RESYNC_DISTANCE behind is late, farther either way restarts.
                    let distance = seq.wrapping_sub(newest) as i32;
                    let resync = RESYNC_DISTANCE as i32;
                    match distance {
                        d if d <= 0 && d.unsigned_abs() < self.window => {}
                        d if (1..=resync).contains(&d) => self.advance_to(seq, on_event),
                        d if (-resync..0).contains(&d) => return PacketOutcome::Late,
                        _ => {
                            self.flush(on_event);
                            self.newest = Some(seq);
                            outcome = PacketOutcome::Resynced;
                        }
                    }
                }
            }
            // Every used slot holds a distinct sequence number inside the window, so when `seq` has
            // no slot yet a free one exists.
            let index = match self
                .slots
                .iter()
                .position(|s| s.state != SlotState::Free && s.seq == seq)
            {
                Some(i) => i,
                None => match self.slots.iter().position(|s| s.state == SlotState::Free) {
                    Some(i) => {
                        self.slots[i] = Slot {
                            state: SlotState::Open,
                            seq,
                            time,
                            ..Slot::FREE
                        };
                        i
                    }
                    None => return PacketOutcome::Late,
                },
            };
            let slot = &mut self.slots[index];
            if slot.state == SlotState::Done || slot.present.contains(joint) {
                return PacketOutcome::Duplicate;
            }
            slot.angles[joint.index() as usize] = angle;
            slot.bad[joint.index() as usize] = out_of_range;
            slot.present = slot.present.with(joint);
            if slot.present.contains_all(self.required) {
                slot.state = SlotState::Done;
                on_event(SampleEvent::Complete(&Sample {
                    seq,
                    timestamp_us: slot.time,
                    angles: slot.angles,
                    out_of_range: bad_set(&slot.bad),
                }));
            }
            outcome
        }

        /// Closes every open sample (as if the window had moved past them), reporting each one.
        pub fn flush(&mut self, on_event: &mut impl FnMut(SampleEvent)) {
            while let Some(i) = self.oldest_slot(|_| true) {
                self.retire(i, on_event);
            }
        }

        /// Moves the newest sequence number to `seq`, retiring the samples that leave the window.
        fn advance_to(&mut self, seq: u32, on_event: &mut impl FnMut(SampleEvent)) {
            let window = self.window;
            // Samples with `seq - s >= window` leave the window, oldest first.
            while let Some(i) = self.oldest_slot(|s| seq.wrapping_sub(s) >= window) {
                self.retire(i, on_event);
            }
            self.newest = Some(seq);
        }

        /// The used slot with the oldest sequence number among those `leaving` selects.
        fn oldest_slot(&self, leaving: impl Fn(u32) -> bool) -> Option<usize> {
            let newest = self.newest.unwrap_or(0);
            // (slot, how far behind the newest sample), the farthest so far.
            let mut oldest: Option<(usize, u32)> = None;
            for (i, slot) in self.slots.iter().enumerate() {
                if slot.state == SlotState::Free || !leaving(slot.seq) {
                    continue;
                }
                let behind = newest.wrapping_sub(slot.seq);
                if oldest.is_none_or(|(_, farthest)| behind > farthest) {
                    oldest = Some((i, behind));
                }
            }
            oldest.map(|(i, _)| i)
        }

        /// Frees slot `i`: an open sample is completed with held values or dropped; then its
        /// angles become the last known values.
        fn retire(&mut self, i: usize, on_event: &mut impl FnMut(SampleEvent)) {
            let slot = self.slots[i];
            self.slots[i] = Slot::FREE;
            if slot.state == SlotState::Open {
                let missing = slot.present.missing_from(self.required);
                if self.hold_last && self.known.contains_all(missing) {
                    let mut angles = slot.angles;
                    let mut bad = slot.bad;
                    for j in JointId::ALL.iter().filter(|&&j| missing.contains(j)) {
                        angles[j.index() as usize] = self.last_angle[j.index() as usize];
                        bad[j.index() as usize] = self.last_bad[j.index() as usize];
                    }
                    let out_of_range = bad_set(&bad);
                    on_event(SampleEvent::Held {
                        sample: &Sample {
                            seq: slot.seq,
                            timestamp_us: slot.time,
                            angles,
                            out_of_range,
                        },
                        held: missing,
                    });
                } else {
                    on_event(SampleEvent::Dropped {
                        seq: slot.seq,
                        missing,
                    });
                }
            }
            for j in JointId::ALL.iter().filter(|&&j| slot.present.contains(j)) {
                self.last_angle[j.index() as usize] = slot.angles[j.index() as usize];
                self.last_bad[j.index() as usize] = slot.bad[j.index() as usize];
                self.known = self.known.with(*j);
            }
        }
    }
}

#[test]
fn matches_the_reference_assembler_on_random_streams() {
    let mut x = 0x9E37_79B9u32;
    let mut next = |n: u32| {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x % n
    };
    let joints = [
        JointId::PelvisList,
        JointId::HipFlexionR,
        JointId::KneeAngleR,
        JointId::AnkleAngleL,
    ];
    let required = &joints[..3];
    let mut compared = 0;
    // Held samples flagged by a held angle alone: the case the judgements of the last
    // values are kept for.
    let mut flagged_by_held = 0;
    for round in 0..400 {
        let window = (round % 10) as u8;
        let hold_last = round % 3 == 0;
        let mut a = Assembler::new(required, window, hold_last);
        let mut r = reference::Reference::new(required, window, hold_last);
        let mut seq = next(u32::MAX);
        for _ in 0..300 {
            // Mostly in order with jitter, sometimes far back or far ahead, sometimes wrapping.
            seq = match next(20) {
                0 => seq.wrapping_add(next(3000)),
                1 => seq.wrapping_sub(next(3000)),
                2..=8 => seq.wrapping_add(1),
                _ => seq,
            };
            let s = seq.wrapping_sub(next(12));
            let joint = joints[next(4) as usize];
            let angle = next(1000) as f32 / 1000.0;
            let out_of_range = next(4) == 0;
            let (mut ea, mut er) = (Vec::new(), Vec::new());
            // A sample's packets share a timestamp, but the first one's is what counts.
            let time = next(1 << 20);
            let oa = a.push(s, time, joint, angle, out_of_range, &mut |e| {
                ea.push(own(e))
            });
            let or = r.push(s, time, joint, angle, out_of_range, &mut |e| {
                er.push(own(e))
            });
            assert_eq!((oa, &ea), (or, &er), "round {round} seq {s} {joint:?}");
            assert_eq!(a.open_samples(), r.open_samples());
            compared += ea.len();
            flagged_by_held += ea
                .iter()
                .filter(|e| matches!(e, Event::Held(s, held) if !s.out_of_range.intersection(*held).is_empty()))
                .count();
        }
        let (mut ea, mut er) = (Vec::new(), Vec::new());
        a.flush(&mut |e| ea.push(own(e)));
        r.flush(&mut |e| er.push(own(e)));
        assert_eq!(ea, er);
    }
    assert!(compared > 10_000, "{compared} events");
    assert!(
        flagged_by_held > 100,
        "{flagged_by_held} held samples flagged by a held angle"
    );
}
