//! Device benchmark: instructions per call of the kernel's forward kinematics and of one whole
//! hub sample, counted under QEMU `-icount shift=0,align=off` (one virtual nanosecond per
//! instruction, so SysTick on the 25 MHz core clock ticks once per 40 instructions).
//!
//! Each figure is the average over many calls with inputs that change on every call
//! (`black_box`), minus the same loop with an empty body. Results are `println!`ed as
//! `bench NAME VALUE` lines; `cargo xtask bench` (xtask/src/bench.rs) builds this binary, runs
//! it under QEMU with `-icount` and turns the lines into its machine-readable output.
//!
//! The binary first runs a calibration loop of a known instruction count: without `-icount`
//! (e.g. plain `cargo run --bin bench`) SysTick follows host time and the run fails instead of
//! printing meaningless numbers.

#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::entry;
use qgait_firmware::board;
use qgait_hub::{Hub, JointSet, Kinematics, ManualClock, Sample, READ_CHUNK};
use qgait_kernel::fusion::Vqf;
use qgait_kernel::imu::{Calibration, Mode, Orientations, Segment, Settings, Solver};
use qgait_kernel::metrics::distances;
use qgait_kernel::reference::chain_by_matrices;
use qgait_kernel::trig::half_angle_sin_cos_f32;
use qgait_kernel::{
    Anthropometry, BilateralPose, Gait2392, Gait2392Geometry, Hak, HakAngles, Limb, Phak,
    PhakAngles, Real,
};
use qgait_proto::device_model::{table_crc, DeviceChain};
use qgait_proto::{
    crc32c, decode_message, decode_packet, encode_frame, encode_message, encode_pose_frame, Config,
    FrameDecoder, JointAngle, JointId, Message, MissingPolicy, ModelId, PoseFrame, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};

/// Virtual instructions per SysTick tick: 1 GHz instruction clock (`shift=0`) / 25 MHz.
const INSTRUCTIONS_PER_TICK: u64 = 40;
/// SysTick is a 24-bit down-counter.
const RELOAD: u32 = 0x00FF_FFFF;
/// Distinct input sets, cycled through (a power of two).
const INPUTS: usize = 64;
/// Calls per kernel measurement.
const CALLS: u32 = 2048;
/// Calls per measurement of the slow matrix method (libm `sincosf`).
const MATRIX_CALLS: u32 = 256;
/// Samples through the whole hub pipeline.
const SAMPLES: u32 = 200;
/// Bytes of the encoded packets of all samples (17 gait2392 packets of at most 21 bytes each).
const RX_CAPACITY: usize = 72 * 1024;
/// Exit status when the instruction counter does not count instructions.
const NOT_COUNTING_EXIT_CODE: i32 = 3;
/// Exit status when the hub pipeline did not produce the expected frames.
const PIPELINE_EXIT_CODE: i32 = 4;

#[entry]
fn main() -> ! {
    let Some(mut core) = cortex_m::Peripherals::take() else {
        board::exit(1)
    };
    core.SYST.set_clock_source(SystClkSource::Core);
    core.SYST.set_reload(RELOAD);
    core.SYST.clear_current();
    core.SYST.enable_counter();

    calibrate();

    let mut rng = Lcg(0x2545_F491);
    let hak_in: [HakAngles<f32>; INPUTS] =
        core::array::from_fn(|_| HakAngles::from_array(rng.angles()));
    let phak_in: [PhakAngles<f32>; INPUTS] =
        core::array::from_fn(|_| PhakAngles::from_array(rng.angles()));
    let g_in: [[f32; 17]; INPUTS] = core::array::from_fn(|_| rng.angles());
    let scalars: [f32; INPUTS] = core::array::from_fn(|_| rng.angles::<1>()[0]);
    // Speeds (rad/s) and accelerations (rad/s^2) for the differential kinematics: gait-like
    // magnitudes (the angles' range times 4 and 40).
    let phak_rates: [[[f32; 8]; 2]; INPUTS] = core::array::from_fn(|_| {
        [
            rng.angles().map(|v| 4.0 * v),
            rng.angles().map(|v| 40.0 * v),
        ]
    });
    let g_rates: [[[f32; 17]; 2]; INPUTS] = core::array::from_fn(|_| {
        [
            rng.angles().map(|v| 4.0 * v),
            rng.angles().map(|v| 40.0 * v),
        ]
    });

    let hak = Hak::<f32>::new(&Limb::gait2392()).unwrap_or_else(|_| board::exit(1));
    let phak = Phak::<f32>::new(&Anthropometry::gait2392()).unwrap_or_else(|_| board::exit(1));
    let g = Gait2392::<f32>::new(&Gait2392Geometry::generic()).unwrap_or_else(|_| board::exit(1));

    report("empty_loop.ticks", bench_empty(&phak_in, CALLS) as f32, 1.0);
    let scalar = Base::of(&scalars, CALLS);
    scalar.net("trig.half_angle_sin_cos", |n| bench_half_angle(&scalars, n));
    Base::of(&scalars, MATRIX_CALLS).net("trig.libm_sincosf", |n| bench_libm_sincos(&scalars, n));
    scalar.net("trig.sqrt_f32", |n| bench_sqrt(&scalars, n));

    let base = Base::of(&hak_in, CALLS);
    base.net("hak.quat", |n| bench_hak_quat(&hak, &hak_in, n));
    Base::of(&hak_in, MATRIX_CALLS).net("hak.matrix", |n| bench_hak_matrix(&hak, &hak_in, n));

    let base = Base::of(&phak_in, CALLS);
    base.net("phak.quat", |n| bench_phak_quat(&phak, &phak_in, n));
    base.net("phak.velocities", |n| {
        bench_phak_velocities(&phak, &phak_in, &phak_rates, n)
    });
    base.net("phak.motion", |n| {
        bench_phak_motion(&phak, &phak_in, &phak_rates, n)
    });
    base.net("phak.quat_frames", |n| {
        bench_phak_frames(&phak, &phak_in, n)
    });
    Base::of(&phak_in, MATRIX_CALLS).net("phak.matrix", |n| bench_phak_matrix(&phak, &phak_in, n));

    let base = Base::of(&g_in, CALLS);
    base.net("gait2392.quat", |n| bench_gait2392_quat(&g, &g_in, n));
    base.net("gait2392.quat_frames", |n| {
        bench_gait2392_frames(&g, &g_in, n)
    });
    base.net("gait2392.velocities", |n| {
        bench_gait2392_velocities(&g, &g_in, &g_rates, n)
    });
    base.net("gait2392.motion", |n| {
        bench_gait2392_motion(&g, &g_in, &g_rates, n)
    });
    Base::of(&g_in, MATRIX_CALLS).net("gait2392.matrix", |n| bench_gait2392_matrix(&g, &g_in, n));

    let raj = rajagopal();
    base.net("rajagopal.quat", |n| bench_rajagopal_quat(&raj, &g_in, n));
    base.net("rajagopal.velocities", |n| {
        bench_rajagopal_velocities(&raj, &g_in, &g_rates, n)
    });
    base.net("rajagopal.motion", |n| {
        bench_rajagopal_motion(&raj, &g_in, &g_rates, n)
    });

    imu_benches(&g, &mut rng);
    fusion_benches(&mut rng);

    sample_sections(&phak_in);
    whole_sample(ModelId::Phak, "sample");
    whole_sample(ModelId::Gait2392, "sample_gait2392");
    #[cfg(feature = "raw")]
    raw_whole_sample();

    board::exit(0)
}

/// Reads SysTick's current value (counts down).
#[inline(always)]
fn now() -> u32 {
    SYST::get_current()
}

/// Ticks from `start` to `end` of the down-counter (one wrap at most: 671 M instructions).
#[inline(always)]
fn ticks(start: u32, end: u32) -> u32 {
    start.wrapping_sub(end) & RELOAD
}

/// Runs `body(i)` for `i` in `0..n` between two SysTick readings; returns the ticks.
#[inline(always)]
fn timed(n: u32, mut body: impl FnMut(usize)) -> u32 {
    let start = now();
    for i in 0..n as usize {
        body(i);
    }
    ticks(start, now())
}

/// Prints `bench NAME VALUE` with `VALUE = x / divisor` to one decimal.
fn report(name: &str, x: f32, divisor: f32) {
    let tenths = (10.0 * x / divisor + 0.5) as u32;
    defmt::println!("bench {=str} {=u32}.{=u32}", name, tenths / 10, tenths % 10);
}

/// Reports `name.instructions_per_call` from the ticks of `n` calls minus the empty loop's.
fn net(name: &str, ticks: u32, base: u32, n: u32) {
    let instructions = (ticks as i64 - base as i64) * INSTRUCTIONS_PER_TICK as i64;
    defmt::println!(
        "bench {=str}.ticks {=u32} base {=u32} calls {=u32}",
        name,
        ticks,
        base,
        n
    );
    let tenths = (instructions * 10 + n as i64 / 2) / n as i64;
    defmt::println!(
        "bench {=str}.instructions_per_call {=i64}.{=i64}",
        name,
        tenths / 10,
        (tenths % 10).abs()
    );
}

/// The empty loop's ticks over some inputs for `calls` calls: what the figures measured on
/// those inputs with as many calls subtract.
#[derive(Clone, Copy)]
struct Base {
    ticks: u32,
    calls: u32,
}

// Inlined, so that each measured loop sees its call count as the constant it is (as when it
// is called with the constant).
impl Base {
    /// The ticks of `measure(calls)`, a loop standing for the empty one.
    #[inline(always)]
    fn with(calls: u32, measure: impl FnOnce(u32) -> u32) -> Self {
        Base {
            ticks: measure(calls),
            calls,
        }
    }

    /// The empty loop over `inputs`.
    #[inline(always)]
    fn of<I>(inputs: &Inputs<I>, calls: u32) -> Self {
        Base::with(calls, |n| bench_empty(inputs, n))
    }

    /// [`net`] of `measure(calls)`, the ticks of a measured loop of `calls` calls.
    #[inline(always)]
    fn net(self, name: &str, measure: impl FnOnce(u32) -> u32) {
        net(name, measure(self.calls), self.ticks, self.calls)
    }

    /// [`Base::net`] as `{name}_{what}`.
    #[inline(always)]
    fn net_named(self, name: &str, what: &str, measure: impl FnOnce(u32) -> u32) {
        let mut full: heapless::String<48> = heapless::String::new();
        if full.push_str(name).is_err() || full.push('_').is_err() || full.push_str(what).is_err() {
            board::exit(1)
        }
        self.net(&full, measure)
    }
}

/// A loop of `n` `subs`/`bne` pairs (2n instructions) must take 2n / 40 ticks: otherwise QEMU
/// is not counting instructions (`-icount shift=0,align=off` missing) and the run fails.
fn calibrate() {
    const LOOPS: u32 = 1_000_000;
    let start = now();
    // SAFETY: a register-only countdown loop; touches no memory, no stack.
    unsafe {
        core::arch::asm!("1:", "subs {0}, {0}, #1", "bne 1b", inout(reg) LOOPS => _, options(nomem, nostack));
    }
    let measured = ticks(start, now()) as u64 * INSTRUCTIONS_PER_TICK;
    let expected = 2 * LOOPS as u64;
    defmt::println!(
        "bench calibration.instructions {=u64} expected {=u64}",
        measured,
        expected
    );
    if measured.abs_diff(expected) > expected / 1000 {
        defmt::error!(
            "SysTick does not count instructions: run QEMU with -icount shift=0,align=off"
        );
        board::exit(NOT_COUNTING_EXIT_CODE)
    }
}

/// Deterministic pseudo-random gait-like angles in [-0.75, 0.75] rad.
struct Lcg(u32);

impl Lcg {
    fn angles<const N: usize>(&mut self) -> [f32; N] {
        core::array::from_fn(|_| {
            self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            ((self.0 >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 1.5
        })
    }
}

// Each measured loop is its own non-inlined function, so its code size can be read from the
// ELF's symbol table (the kernel's share per model; see xtask/src/bench.rs).

#[inline(never)]
fn bench_empty<I>(inputs: &[I; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        black_box(&inputs[i % INPUTS]);
    })
}

/// A measured loop: `fn $name($args.., n: u32) -> u32`, never inlined, the ticks of `n`
/// calls of `$body` (its value kept with `black_box`) for `i` in `0..n`.
macro_rules! measured {
    ($(#[$doc:meta])* fn $name:ident($($arg:ident: $ty:ty),*) |$i:ident| $body:expr) => {
        $(#[$doc])*
        #[inline(never)]
        fn $name($($arg: $ty,)* n: u32) -> u32 {
            timed(n, |$i| {
                black_box($body);
            })
        }
    };
}

/// Angles of each of the [`INPUTS`] input sets.
type Inputs<A> = [A; INPUTS];
/// Speeds and accelerations of `N` coordinates for each input set.
type Rates<const N: usize> = [[[f32; N]; 2]; INPUTS];

measured!(fn bench_half_angle(x: &Inputs<f32>) |i| {
    half_angle_sin_cos_f32(*black_box(&x[i % INPUTS]))
});
measured!(fn bench_libm_sincos(x: &Inputs<f32>) |i| Real::sin_cos(*black_box(&x[i % INPUTS])));
measured!(fn bench_sqrt(x: &Inputs<f32>) |i| Real::sqrt(black_box(&x[i % INPUTS]).abs()));

measured!(fn bench_hak_quat(model: &Hak<f32>, q: &Inputs<HakAngles<f32>>) |i| {
    black_box(model).fk(black_box(&q[i % INPUTS]))
});
measured!(fn bench_hak_matrix(model: &Hak<f32>, q: &Inputs<HakAngles<f32>>) |i| {
    chain_by_matrices(black_box(model).chain(), &black_box(&q[i % INPUTS]).to_array())
});

measured!(fn bench_phak_quat(model: &Phak<f32>, q: &Inputs<PhakAngles<f32>>) |i| {
    black_box(model).fk(black_box(&q[i % INPUTS]))
});
measured!(
    /// PHAK's points' positions and velocities from angles and speeds.
    fn bench_phak_velocities(model: &Phak<f32>, q: &Inputs<PhakAngles<f32>>, rates: &Rates<8>)
    |i| {
        let [qd, _] = black_box(&rates[i % INPUTS]);
        black_box(model).chain().forward_velocities(&black_box(&q[i % INPUTS]).to_array(), qd)
    }
);
measured!(
    /// PHAK's points' positions, velocities and accelerations.
    fn bench_phak_motion(model: &Phak<f32>, q: &Inputs<PhakAngles<f32>>, rates: &Rates<8>)
    |i| {
        let [qd, qdd] = black_box(&rates[i % INPUTS]);
        black_box(model).chain().forward_motion(&black_box(&q[i % INPUTS]).to_array(), qd, qdd)
    }
);
measured!(fn bench_phak_frames(model: &Phak<f32>, q: &Inputs<PhakAngles<f32>>) |i| {
    black_box(model).chain().frames(&black_box(&q[i % INPUTS]).to_array())
});
measured!(fn bench_phak_matrix(model: &Phak<f32>, q: &Inputs<PhakAngles<f32>>) |i| {
    chain_by_matrices(black_box(model).chain(), &black_box(&q[i % INPUTS]).to_array())
});

measured!(fn bench_gait2392_quat(model: &Gait2392<f32>, q: &Inputs<[f32; 17]>) |i| {
    black_box(model).fk(black_box(&q[i % INPUTS]))
});
measured!(
    fn bench_gait2392_velocities(model: &Gait2392<f32>, q: &Inputs<[f32; 17]>, rates: &Rates<17>)
    |i| {
        let [qd, _] = black_box(&rates[i % INPUTS]);
        black_box(model).chain().forward_velocities(black_box(&q[i % INPUTS]), qd)
    }
);
measured!(
    fn bench_gait2392_motion(model: &Gait2392<f32>, q: &Inputs<[f32; 17]>, rates: &Rates<17>)
    |i| {
        let [qd, qdd] = black_box(&rates[i % INPUTS]);
        black_box(model).chain().forward_motion(black_box(&q[i % INPUTS]), qd, qdd)
    }
);
measured!(fn bench_gait2392_frames(model: &Gait2392<f32>, q: &Inputs<[f32; 17]>) |i| {
    black_box(model).chain().frames(black_box(&q[i % INPUTS]))
});

/// The imported Rajagopal 2015 (OpenSense) chain, as `qgait config --model` sends it: its
/// table's parts written into the hub's table, checked against its config's CRC.
/// `rajagopal2015_opensense.chain.bin` is made by `qgait model import
/// ../shared/data/opensim/Rajagopal2015_opensense.osim -o raj.toml` then
/// `qgait config --model raj.toml --upload 1 -o firmware/src/bin/rajagopal2015_opensense.chain.bin`.
fn rajagopal() -> DeviceChain {
    static FRAMES: &[u8] = include_bytes!("rajagopal2015_opensense.chain.bin");
    let mut decoder = FrameDecoder::new();
    let mut table = DeviceChain::EMPTY;
    let mut config = None;
    for message in decoder.feed(FRAMES) {
        match message {
            Ok(Message::ChainTable(p)) => table.write_image(usize::from(p.at), &p.bytes),
            Ok(Message::ChainTableConfig(c)) => config = Some(c),
            _ => board::exit(5),
        }
    }
    match config {
        Some(c) if table_crc(&table, usize::from(c.len)) == c.crc => table,
        _ => board::exit(5),
    }
}

measured!(fn bench_rajagopal_quat(model: &DeviceChain, q: &Inputs<[f32; 17]>) |i| {
    black_box(model).forward(black_box(&q[i % INPUTS]))
});
measured!(
    fn bench_rajagopal_velocities(model: &DeviceChain, q: &Inputs<[f32; 17]>, rates: &Rates<17>)
    |i| {
        let [qd, _] = black_box(&rates[i % INPUTS]);
        black_box(model).forward_velocities(black_box(&q[i % INPUTS]), qd)
    }
);
measured!(
    fn bench_rajagopal_motion(model: &DeviceChain, q: &Inputs<[f32; 17]>, rates: &Rates<17>)
    |i| {
        let [qd, qdd] = black_box(&rates[i % INPUTS]);
        black_box(model).forward_motion(black_box(&q[i % INPUTS]), qd, qdd)
    }
);

measured!(fn bench_gait2392_matrix(model: &Gait2392<f32>, q: &Inputs<[f32; 17]>) |i| {
    chain_by_matrices(black_box(model).chain(), black_box(&q[i % INPUTS]))
});

/// The PHAK packet of `joint` in sample `seq`, with an angle that changes every sample.
fn packet(seq: u32, joint: JointId, rng: &mut Lcg) -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: joint.index(),
        joint,
        seq,
        timestamp_us: seq.wrapping_mul(10_000),
        angle: 0.5 * rng.angles::<1>()[0],
        quality: 0,
    }
}

/// The parts of one sample, each measured on its own: frame decoding of the 8 packets, the
/// pose frame (FK, distances, packing), the inter-limb distances alone, and frame encoding.
fn sample_sections(phak_in: &[PhakAngles<f32>; INPUTS]) {
    let mut rng = Lcg(7);
    // The encoded packets of INPUTS samples, one byte stream per sample.
    let mut streams: [heapless::Vec<u8, 192>; INPUTS] =
        core::array::from_fn(|_| heapless::Vec::new());
    let mut buf = [0u8; MAX_FRAME_LEN];
    for (seq, stream) in streams.iter_mut().enumerate() {
        for &joint in ModelId::Phak.required_joints() {
            let Ok(frame) = encode_frame(
                &Message::JointAngle(packet(seq as u32, joint, &mut rng)),
                &mut buf,
            ) else {
                board::exit(PIPELINE_EXIT_CODE)
            };
            if stream.extend_from_slice(frame).is_err() {
                board::exit(PIPELINE_EXIT_CODE)
            }
        }
    }
    defmt::println!("bench sample.rx_bytes {=usize}", streams[0].len());
    Base::of(&streams, CALLS / 4).net("sample.decode_8_packets", |n| bench_decode(&streams, n));

    let payloads: [heapless::Vec<u8, 32>; INPUTS] = core::array::from_fn(|i| {
        let mut out = [0u8; 32];
        let p = packet(i as u32, JointId::KneeAngleR, &mut rng);
        let len = encode_message(&Message::JointAngle(p), &mut out)
            .map(|m| m.len())
            .unwrap_or(0);
        heapless::Vec::from_slice(&out[..len]).unwrap_or_default()
    });
    defmt::println!(
        "bench sample.packet_payload_bytes {=usize}",
        payloads[0].len()
    );
    let base = Base::of(&payloads, CALLS);
    base.net("sample.crc32c_packet", |n| bench_crc(&payloads, n));
    base.net("sample.decode_message_packet", |n| {
        bench_decode_message(&payloads, n)
    });
    base.net("sample.decode_packet", |n| {
        bench_decode_packet(&payloads, n)
    });
    // One packet frame's bytes into the decoder, then its delimiter (the frame checks): the
    // same bytes followed by a reset instead of the delimiter are the base, so the figure is
    // the checks alone; the base against the empty loop is the per-byte cost of 16 bytes.
    let frames: [heapless::Vec<u8, 32>; INPUTS] = core::array::from_fn(|i| {
        let mut out = [0u8; 32];
        let p = packet(i as u32, JointId::KneeAngleR, &mut rng);
        let len = encode_frame(&Message::JointAngle(p), &mut out)
            .map(|f| f.len())
            .unwrap_or(1);
        heapless::Vec::from_slice(&out[..len - 1]).unwrap_or_default()
    });
    let bytes_only = Base::with(CALLS, |n| bench_frame_bytes(&frames, n, false));
    Base::of(&frames, CALLS).net("sample.packet_frame_bytes", |_| bytes_only.ticks);
    bytes_only.net("sample.packet_frame_checks", |n| {
        bench_frame_bytes(&frames, n, true)
    });

    let kinematics = Kinematics::new(ModelId::Phak, None).unwrap_or_else(|_| board::exit(1));
    let samples: [Sample; INPUTS] = core::array::from_fn(|i| {
        let mut s = Sample {
            seq: i as u32,
            timestamp_us: i as u32 * 10_000,
            angles: [0.0; JointId::COUNT],
            out_of_range: JointSet::EMPTY,
        };
        for (&j, &a) in ModelId::Phak
            .required_joints()
            .iter()
            .zip(phak_in[i].to_array().iter())
        {
            s.angles[j.index() as usize] = a;
        }
        s
    });
    Base::of(&samples, CALLS).net("sample.pose_frame", |n| {
        bench_pose_frame(&kinematics, &samples, n)
    });

    let phak = Phak::<f32>::new(&Anthropometry::gait2392()).unwrap_or_else(|_| board::exit(1));
    let poses: [BilateralPose<f32>; INPUTS] = core::array::from_fn(|i| phak.fk(&phak_in[i]));
    Base::of(&poses, CALLS).net("sample.distances", |n| bench_distances(&poses, n));

    let pose_frames: [PoseFrame; INPUTS] = core::array::from_fn(|i| {
        kinematics.pose_frame(
            samples[i].seq,
            samples[i].timestamp_us,
            &samples[i].angles,
            0,
        )
    });
    let frames: [Message; INPUTS] =
        core::array::from_fn(|i| Message::PoseFrame(pose_frames[i].clone()));
    let Ok(len) = encode_frame(&frames[0], &mut buf).map(|f| f.len()) else {
        board::exit(PIPELINE_EXIT_CODE)
    };
    defmt::println!("bench sample.tx_bytes {=usize}", len);
    Base::of(&pose_frames, CALLS).net("sample.encode_pose_frame", |n| {
        bench_encode(&pose_frames, n)
    });
    Base::of(&frames, CALLS).net("sample.encode_message_pose_frame", |n| {
        bench_encode_message(&frames, n)
    });
    crc_cobs_beside_crates(&payloads, &frames);
    defmt::println!(
        "bench size.message_bytes {=usize} pose_frame {=usize} kinematics {=usize} frame_decoder {=usize} phak {=usize} gait2392 {=usize}",
        core::mem::size_of::<Message>(),
        core::mem::size_of::<qgait_proto::PoseFrame>(),
        core::mem::size_of::<Kinematics>(),
        core::mem::size_of::<FrameDecoder>(),
        core::mem::size_of::<Phak<f32>>(),
        core::mem::size_of::<Gait2392<f32>>()
    );
}

#[inline(never)]
fn bench_crc(payloads: &[heapless::Vec<u8, 32>; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        black_box(crc32c(black_box(&payloads[i % INPUTS])));
    })
}

#[inline(never)]
fn bench_decode_message(payloads: &[heapless::Vec<u8, 32>; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        if let Ok(m) = decode_message(black_box(&payloads[i % INPUTS])) {
            black_box(&m);
        }
    })
}

#[inline(never)]
fn bench_decode_packet(payloads: &[heapless::Vec<u8, 32>; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        black_box(decode_packet(black_box(&payloads[i % INPUTS])));
    })
}

/// Each frame's bytes through `push_frame`, then the delimiter if `delimit`, else a reset.
#[inline(never)]
fn bench_frame_bytes(frames: &[heapless::Vec<u8, 32>; INPUTS], n: u32, delimit: bool) -> u32 {
    let mut decoder = FrameDecoder::new();
    timed(n, |i| {
        for &b in black_box(&frames[i % INPUTS]).iter() {
            black_box(decoder.push_frame(b).is_some());
        }
        if black_box(delimit) {
            black_box(decoder.push_frame(0).map(|f| f.map(|m| m.len())));
        } else {
            decoder.reset();
        }
    })
}

#[inline(never)]
fn bench_encode_message(frames: &[Message; INPUTS], n: u32) -> u32 {
    let mut buf = [0u8; MAX_FRAME_LEN];
    timed(n, |i| {
        black_box(
            encode_message(black_box(&frames[i % INPUTS]), &mut buf)
                .map(|m| m.len())
                .ok(),
        );
    })
}

#[inline(never)]
fn bench_decode(streams: &[heapless::Vec<u8, 192>; INPUTS], n: u32) -> u32 {
    let mut decoder = FrameDecoder::new();
    // The hub's path: frame checks in the decoder, the packet decoded from its buffer.
    timed(n, |i| {
        for &b in black_box(&streams[i % INPUTS]).iter() {
            if let Some(Ok(message)) = decoder.push_frame(b) {
                black_box(&decode_packet(message));
            }
        }
    })
}

#[inline(never)]
fn bench_pose_frame(k: &Kinematics, samples: &[Sample; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        let s = black_box(&samples[i % INPUTS]);
        black_box(black_box(k).pose_frame(s.seq, s.timestamp_us, &s.angles, 0));
    })
}

#[inline(never)]
fn bench_distances(poses: &[BilateralPose<f32>; INPUTS], n: u32) -> u32 {
    timed(n, |i| {
        black_box(distances(black_box(&poses[i % INPUTS])));
    })
}

#[inline(never)]
fn bench_encode(frames: &[PoseFrame; INPUTS], n: u32) -> u32 {
    let mut buf = [0u8; MAX_FRAME_LEN];
    // The hub's path: the pose frame encoded in place, without a `Message`.
    timed(n, |i| {
        black_box(
            encode_pose_frame(black_box(&frames[i % INPUTS]), &mut buf)
                .map(|f| f.len())
                .ok(),
        );
    })
}

/// A serial port double with the least overhead: reads a byte stream from memory (as much as
/// asked each time, as a UART driver copies what its ring holds), counts and checksums what is
/// written (a UART's data register write a byte costs about as much). Its `read_ready`, `read`
/// and `write` are never inlined, as the firmware's UART driver's are not, so that the hub's
/// code here is the firmware's and the double's own instructions can be told apart; it counts
/// its calls, which [`serial_double_share`] makes again to time them.
struct StreamSerial<'a> {
    rx: &'a [u8],
    pos: usize,
    tx_bytes: u32,
    tx_sum: u32,
    ready_calls: u32,
    reads: u32,
    writes: u32,
}

impl<'a> StreamSerial<'a> {
    fn new(rx: &'a [u8]) -> Self {
        StreamSerial {
            rx,
            pos: 0,
            tx_bytes: 0,
            tx_sum: 0,
            ready_calls: 0,
            reads: 0,
            writes: 0,
        }
    }
}

impl embedded_io::ErrorType for StreamSerial<'_> {
    type Error = core::convert::Infallible;
}

impl embedded_io::ReadReady for StreamSerial<'_> {
    #[inline(never)]
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        self.ready_calls += 1;
        Ok(self.pos < self.rx.len())
    }
}

impl embedded_io::Read for StreamSerial<'_> {
    /// What is left of the stream, up to `buf.len()` (0 at its end: never blocks).
    #[inline(never)]
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        self.reads += 1;
        let rest = self.rx.get(self.pos..).unwrap_or_default();
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        self.pos += n;
        Ok(n)
    }
}

impl embedded_io::Write for StreamSerial<'_> {
    #[inline(never)]
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        self.writes += 1;
        let mut sum = self.tx_sum;
        for &byte in buf {
            sum = sum.wrapping_mul(31).wrapping_add(byte as u32);
        }
        self.tx_sum = sum;
        self.tx_bytes += buf.len() as u32;
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// SAMPLES samples of `model` through the hub (drop policy, window 4): bytes in, frame
/// decoding, sample assembly, FK, pose frame encoding, bytes out. The serial double's own cost
/// (the same reads and writes without the hub) is measured and reported separately, and
/// subtracted. A `Config` selecting `model` goes first (not counted).
fn whole_sample(model: ModelId, name: &str) {
    let mut rng = Lcg(11);
    let mut rx: heapless::Vec<u8, RX_CAPACITY> = heapless::Vec::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    let config = Config {
        model,
        anthropometry: None,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: false,
    };
    let Ok(config_len) = encode_frame(&Message::Config(config), &mut buf).map(|f| f.len()) else {
        board::exit(PIPELINE_EXIT_CODE)
    };
    if rx.extend_from_slice(&buf[..config_len]).is_err() {
        board::exit(PIPELINE_EXIT_CODE)
    }
    for seq in 0..SAMPLES {
        for &joint in model.required_joints() {
            let ok = encode_frame(&Message::JointAngle(packet(seq, joint, &mut rng)), &mut buf)
                .is_ok_and(|frame| rx.extend_from_slice(frame).is_ok());
            if !ok {
                board::exit(PIPELINE_EXIT_CODE)
            }
        }
    }
    let clock = ManualClock::new(0);
    // Status period 0: no periodic status frame, only pose frames.
    let Ok(mut hub) = Hub::new(StreamSerial::new(&rx[..config_len]), &clock, 0) else {
        board::exit(1)
    };
    defmt::println!(
        "bench size.hub_bytes {=usize}",
        core::mem::size_of_val(&hub)
    );
    run_hub(&mut hub);
    *hub.serial_mut() = StreamSerial::new(&rx[config_len..]);
    let hub_ticks = run_hub(&mut hub);
    let status = hub.status();
    let io = hub.serial_mut();
    let (tx_bytes, calls) = (
        io.tx_bytes,
        Calls {
            ready: io.ready_calls,
            reads: io.reads,
            writes: io.writes,
        },
    );
    defmt::println!(
        "bench {=str}.check model {=str} samples_completed {=u32} frames_sent {=u32} rx_bytes {=usize} tx_bytes {=u32}",
        name,
        hub.config().model.name(),
        status.samples_completed,
        status.frames_sent,
        rx.len() - config_len,
        tx_bytes
    );
    defmt::println!(
        "bench {=str}.serial_calls read_ready {=u32} read {=u32} write {=u32}",
        name,
        calls.ready,
        calls.reads,
        calls.writes
    );
    if hub.config().model != model
        || status.samples_completed != SAMPLES
        || status.frames_sent != SAMPLES
    {
        defmt::error!("the hub did not turn every sample into a pose frame");
        board::exit(PIPELINE_EXIT_CODE)
    }
    let rx_bytes = (rx.len() - config_len) as u32;
    let io_ticks = serial_double_share(&rx[config_len..], rx_bytes, tx_bytes, calls);
    let mut label: heapless::String<48> = heapless::String::new();
    let mut named = |suffix: &str| {
        label.clear();
        let _ = label.push_str(name);
        let _ = label.push_str(suffix);
        label.clone()
    };
    net(&named(".serial_double"), io_ticks, 0, SAMPLES);
    net(&named(".gross"), hub_ticks, 0, SAMPLES);
    net(&named(".net"), hub_ticks, io_ticks, SAMPLES);
}

/// The hub with raw input (`--features imu,raw`): eight raw sensors (9D, 100 Hz, as an
/// ICM-20948 sends them) fused on the hub, then gait2392's least squares and the pose frame.
/// After the configurations and the calibration (samples 0 and 1, not timed), [`SAMPLES`]
/// samples of 8 `RawImuSample`s each, read from the serial double; the figure per sample is
/// everything the hub does (the double's reads included: `raw_sample.gross`).
#[cfg(feature = "raw")]
fn raw_whole_sample() {
    use qgait_proto::{FusionMode, ImuConfig, InputMode, RawImuSample, SampleHeader, SegmentId};
    let imu = |calibrate| {
        Message::ImuConfig(ImuConfig::opensense_tutorial(
            InputMode::OrientationsLeastSquares,
            calibrate,
        ))
    };
    let mut rng = Lcg(13);
    // Each sensor at its own tilt (the torso's z horizontal), turning slowly and noisily.
    let sample = |segment: SegmentId, seq: u32, rng: &mut Lcg| {
        let i = segment as i16;
        let mut noise = || (rng.angles::<1>()[0] * 4.0) as i16;
        RawImuSample {
            header: SampleHeader::new(segment as u8, segment, seq, seq.wrapping_mul(10_000)),
            gyro: [40 - 9 * i + noise(), 25 + noise(), -30 + noise()],
            accel: match segment {
                SegmentId::Torso => [2048 + noise(), noise(), noise()],
                _ => [
                    300 * (i - 3) + noise(),
                    200 - 60 * i + noise(),
                    1900 + noise(),
                ],
            },
            mag: Some([150 + 10 * i + noise(), -40 + noise(), 200 + noise()]),
        }
    };
    let mut rx: heapless::Vec<u8, RX_CAPACITY> = heapless::Vec::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    let mut push = |rx: &mut heapless::Vec<u8, RX_CAPACITY>, m: &Message| {
        let ok = encode_frame(m, &mut buf).is_ok_and(|frame| rx.extend_from_slice(frame).is_ok());
        if !ok {
            board::exit(PIPELINE_EXIT_CODE)
        }
    };
    let config = Config {
        model: ModelId::Gait2392,
        anthropometry: None,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: false,
    };
    push(&mut rx, &Message::Config(config));
    push(&mut rx, &imu(false));
    let raw = qgait_hub::raw::icm20948_config(ImuConfig::ALL_SEGMENTS, FusionMode::NineD);
    push(&mut rx, &Message::RawImuConfig(raw));
    for seq in 0..SAMPLES + 2 {
        if seq == 1 {
            push(&mut rx, &imu(true));
        }
        for segment in SegmentId::ALL {
            push(
                &mut rx,
                &Message::RawImuSample(sample(segment, seq, &mut rng)),
            );
        }
    }
    // The set-up: the configurations and samples 0 and 1 (the calibration).
    let setup_len = {
        let mut decoder = FrameDecoder::new();
        let (mut frames, mut end) = (0, 0);
        for (i, &b) in rx.iter().enumerate() {
            if decoder.push(b).is_some() {
                frames += 1;
                if frames == 3 + 1 + 16 {
                    end = i + 1;
                    break;
                }
            }
        }
        end
    };
    let clock = ManualClock::new(0);
    let Ok(mut hub) = Hub::new(StreamSerial::new(&rx[..setup_len]), &clock, 0) else {
        board::exit(1)
    };
    defmt::println!(
        "bench size.raw_hub_bytes {=usize}",
        core::mem::size_of_val(&hub)
    );
    run_hub(&mut hub);
    *hub.serial_mut() = StreamSerial::new(&rx[setup_len..]);
    let hub_ticks = run_hub(&mut hub);
    let status = hub.status();
    let raw_status = hub.raw().status();
    defmt::println!(
        "bench raw_sample.check samples_completed {=u32} frames_sent {=u32} raw_samples {=u32} rx_bytes {=usize} calibrations {=u32} not_unit {=u32}",
        status.samples_completed,
        status.frames_sent,
        raw_status.samples_accepted,
        rx.len() - setup_len,
        status.calibrations,
        status.orientation_not_unit
    );
    if status.samples_completed != SAMPLES || status.frames_sent != SAMPLES {
        defmt::error!("the raw hub did not turn every sample into a pose frame");
        board::exit(PIPELINE_EXIT_CODE)
    }
    net("raw_sample.gross", hub_ticks, 0, SAMPLES);
}

#[inline(never)]
fn run_hub(hub: &mut Hub<StreamSerial<'_>, &ManualClock>) -> u32 {
    let start = now();
    while black_box(&mut *hub).poll().bytes > 0 {}
    ticks(start, now())
}

/// The calls the hub made to the serial double in a run.
#[derive(Clone, Copy)]
struct Calls {
    ready: u32,
    reads: u32,
    writes: u32,
}

/// The serial double's own share of the hub run: the instructions inside its `read_ready`,
/// `read` and `write`, as many calls of each as the hub made (`calls`), reading the same
/// stream in blocks of the hub's [`READ_CHUNK`] and writing `tx_bytes` bytes over the `write`
/// calls. Each kind is timed in a loop of those calls and again with a function of the same
/// signature that does nothing; the difference is what the double's bodies cost beyond an
/// empty function. The call itself (argument set-up, `bl`, the result test) is the hub's work,
/// as it is in the firmware, and so is not subtracted; nor is the empty function's own return
/// (a `bx lr` or so a call), so the figure errs by about one instruction a call towards
/// counting too much, not too little.
fn serial_double_share(rx: &[u8], rx_bytes: u32, tx_bytes: u32, calls: Calls) -> u32 {
    use embedded_io::{Read as _, ReadReady as _, Write as _};
    let mut io = StreamSerial::new(rx);
    let mut buf = [0u8; READ_CHUNK];
    let ready = timed_calls(calls.ready, &mut io, |io, _| {
        black_box(io.read_ready()).is_ok()
    });
    let empty_ready = timed_calls(calls.ready, &mut io, |io, _| {
        black_box(ready_nothing(io)).is_ok()
    });
    let reads = timed_calls(calls.reads, &mut io, |io, _| {
        black_box(io.read(black_box(&mut buf))).is_ok()
    });
    if io.pos != rx_bytes as usize {
        defmt::error!("the double's reads did not read the stream as the hub did");
        board::exit(PIPELINE_EXIT_CODE)
    }
    let empty_reads = timed_calls(calls.reads, &mut io, |io, _| {
        black_box(read_nothing(io, black_box(&mut buf))).is_ok()
    });
    // The frames written: `tx_bytes` over `calls.writes` writes, the remainder spread one byte
    // a call over the first ones (the pose frames differ by a byte or two).
    let frame = [0x55u8; MAX_FRAME_LEN];
    let (per_call, longer) = (
        tx_bytes / calls.writes.max(1),
        tx_bytes % calls.writes.max(1),
    );
    let len = |i: u32| ((per_call + (i < longer) as u32) as usize).min(MAX_FRAME_LEN);
    let writes = timed_calls(calls.writes, &mut io, |io, i| {
        black_box(io.write(black_box(&frame[..len(i)]))).is_ok()
    });
    if io.tx_bytes != tx_bytes {
        defmt::error!("the double's writes did not write what the hub did");
        board::exit(PIPELINE_EXIT_CODE)
    }
    let empty_writes = timed_calls(calls.writes, &mut io, |io, i| {
        black_box(write_nothing(io, black_box(&frame[..len(i)]))).is_ok()
    });
    (ready + reads + writes).saturating_sub(empty_ready + empty_reads + empty_writes)
}

/// `n` calls of `call` on the double (given the call's index), timed.
#[inline(always)]
fn timed_calls(
    n: u32,
    io: &mut StreamSerial<'_>,
    mut call: impl FnMut(&mut StreamSerial<'_>, u32) -> bool,
) -> u32 {
    let start = now();
    for i in 0..n {
        black_box(call(black_box(&mut *io), i));
    }
    ticks(start, now())
}

/// A `read_ready` that does nothing, shaped as [`StreamSerial`]'s.
#[inline(never)]
fn ready_nothing(_io: &mut StreamSerial<'_>) -> Result<bool, core::convert::Infallible> {
    Ok(true)
}

/// A read that does nothing, shaped as [`StreamSerial`]'s.
#[inline(never)]
fn read_nothing(
    _io: &mut StreamSerial<'_>,
    _buf: &mut [u8],
) -> Result<usize, core::convert::Infallible> {
    Ok(0)
}

/// A write that does nothing, shaped as [`StreamSerial`]'s.
#[inline(never)]
fn write_nothing(
    _io: &mut StreamSerial<'_>,
    buf: &[u8],
) -> Result<usize, core::convert::Infallible> {
    Ok(buf.len())
}

/// The IMU path of `qgait_kernel::imu` per sample, in `f32`: readings to calibrated segment
/// orientations, each solve mode, and the whole path with gait2392 FK, on random poses of the
/// model (identity calibration pose, no heading). The solver warm-starts from the previous
/// input, an unrelated pose, so the least-squares figures are a worst case for a recording.
fn imu_benches(g: &Gait2392<f32>, rng: &mut Lcg) {
    let joints = [0usize, 1, 2, 4, 6, 7, 9, 0];
    let readings: [Orientations<f32>; INPUTS] = core::array::from_fn(|_| {
        let q: [f32; 17] = rng.angles::<17>().map(|a| a * 0.3);
        let f = g.chain().frames(&q);
        let mut o = Orientations::EMPTY;
        for s in Segment::ALL {
            o.set(s, Some(f[joints[s as usize]].rotation));
        }
        o
    });
    let mut pose = Orientations::EMPTY;
    for s in Segment::ALL {
        pose.set(s, Some(qgait_kernel::Quat::identity()));
    }
    let settings = Settings {
        sensor_to_opensim: [0.0; 3],
        heading: None,
    };
    let cal = Calibration::new(g, &pose, &settings).unwrap_or_else(|_| board::exit(1));
    let segs: [Orientations<f32>; INPUTS] = core::array::from_fn(|i| {
        cal.segments(&readings[i])
            .unwrap_or_else(|_| board::exit(1))
    });
    let base = Base::of(&readings, 256);
    base.net("imu.segments", |n| {
        timed(n, |i| {
            black_box(
                black_box(&cal)
                    .segments(black_box(&readings[i % INPUTS]))
                    .ok(),
            );
        })
    });
    let mut solver = Solver::<f32>::new();
    base.net("imu.closed_form", |n| {
        timed(n, |i| {
            black_box(solver.solve(black_box(g), black_box(&segs[i % INPUTS]), Mode::ClosedForm));
        })
    });
    let mut solver = Solver::<f32>::new();
    base.net("imu.least_squares", |n| {
        timed(n, |i| {
            let segments = black_box(&segs[i % INPUTS]);
            black_box(solver.solve(black_box(g), segments, Mode::LeastSquares));
        })
    });
    base.net("imu.whole_ls", |n| {
        imu_whole(g, &cal, &readings, Mode::LeastSquares, n)
    });
    base.net("imu.whole_cf", |n| {
        imu_whole(g, &cal, &readings, Mode::ClosedForm, n)
    });
}

/// `n` times the whole IMU path: readings to segments, angles by `mode` (a new solver), FK.
#[inline(always)]
fn imu_whole(
    g: &Gait2392<f32>,
    cal: &Calibration<f32>,
    readings: &Inputs<Orientations<f32>>,
    mode: Mode,
    n: u32,
) -> u32 {
    let mut solver = Solver::<f32>::new();
    timed(n, |i| {
        if let Ok(s) = black_box(cal).segments(black_box(&readings[i % INPUTS])) {
            let a = solver.solve(black_box(g), &s, mode);
            black_box(g.fk(&a.coordinates));
        }
    })
}

// ---- Orientation estimation (the kernel's VQF, `qgait_kernel::fusion`) ----------------------
//
// A sensor turning about the vertical at 400 °/s (one turn in `VQF_INPUTS` samples at BROAD's
// 285.7 Hz, so the cycled inputs stay consistent) while it tilts back and forth by ±0.5 rad about
// a tilted axis (four times per turn): angular rate up to 15 rad/s with a little noise, gravity
// and a 44 µT field with 64° dip in the sensor frame. The filter first runs 7 s of it, past the
// running-mean start of its low-pass filters (3 s) and the first acceptance of the magnetic
// field (5 s of rotation above 20 °/s), so the figures are of the steady update in motion (bias
// estimation by the Kalman filter, magnetometer in use). Each figure is one `update` plus
// reading the orientation.

/// BROAD's sampling period, s.
const VQF_TS: f32 = 0.0035;
/// Samples of one turn.
const VQF_INPUTS: usize = 256;

struct ImuSample {
    gyr: [f32; 3],
    acc: [f32; 3],
    mag: [f32; 3],
}

fn imu_samples(rng: &mut Lcg) -> [ImuSample; VQF_INPUTS] {
    use qgait_kernel::{Quat, Vec3};
    let axis = Vec3::new(0.3f32, 0.5, 0.8).normalized();
    let up = Vec3::new(0.0f32, 0.0, 1.0);
    let amplitude = 0.5f32;
    // Heading rate and tilt frequency, rad/s.
    let turn = 2.0 * core::f32::consts::PI / (VQF_INPUTS as f32 * VQF_TS);
    let tilt = 4.0 * turn;
    core::array::from_fn(|k| {
        let t = k as f32 * VQF_TS;
        let (s, c) = Real::sin_cos(tilt * t);
        let tilt_q = Quat::from_axis_angle(axis, amplitude * s);
        // Sensor to earth: about the vertical, then the tilt.
        let q = Quat::from_axis_angle(up, turn * t) * tilt_q;
        let to_sensor = q.conj();
        let w = tilt_q.conj().rotate(up * turn) + axis * (amplitude * tilt * c);
        let noise = rng.angles::<3>().map(|a| a * 0.01);
        ImuSample {
            gyr: [w.x + noise[0], w.y + noise[1], w.z + noise[2]],
            acc: to_sensor.rotate(Vec3::new(0.0, 0.0, 9.81)).to_array(),
            mag: to_sensor.rotate(Vec3::new(0.0, 19.3, -39.5)).to_array(),
        }
    })
}

fn fusion_benches(rng: &mut Lcg) {
    let samples = imu_samples(rng);
    defmt::println!(
        "bench vqf.state_bytes {=usize}",
        core::mem::size_of::<Vqf<f32>>()
    );
    let base = Base::with(CALLS, |n| bench_vqf_empty(&samples, n));
    for nine_d in [true, false] {
        let mut vqf = Vqf::<f32>::new_default(VQF_TS as f64);
        for i in 0..2000 {
            let s = &samples[i % VQF_INPUTS];
            vqf.update(s.gyr, s.acc, nine_d.then_some(s.mag));
        }
        if nine_d {
            base.net("vqf.update_9d", |n| bench_vqf_9d(&mut vqf, &samples, n));
            if vqf.mag_dist_detected() {
                defmt::error!("the benchmark's magnetic field was not accepted");
                board::exit(PIPELINE_EXIT_CODE)
            }
        } else {
            base.net("vqf.update_6d", |n| bench_vqf_6d(&mut vqf, &samples, n));
        }
    } // vqf-rs on the same samples (fewer calls: it is slower).
    let base = Base::with(VQF_RS_CALLS, |n| bench_vqf_empty(&samples, n));
    for nine_d in [true, false] {
        let mut vqf = vqf_rs::VQF::new(VQF_TS, None, None, None);
        for i in 0..2000 {
            let s = &samples[i % VQF_INPUTS];
            vqf.update(s.gyr, s.acc, nine_d.then_some(s.mag));
        }
        let name = if nine_d {
            "vqf_rs.update_9d"
        } else {
            "vqf_rs.update_6d"
        };
        base.net(name, |n| bench_vqf_rs(&mut vqf, &samples, nine_d, n));
    }
}

/// Calls per measurement of vqf-rs.
const VQF_RS_CALLS: u32 = 512;

/// The inputs of the fusion benchmarks, one turn.
type Turn = [ImuSample; VQF_INPUTS];

measured!(fn bench_vqf_rs(vqf: &mut vqf_rs::VQF, x: &Turn, nine_d: bool) |i| {
    let s = black_box(&x[i % VQF_INPUTS]);
    vqf.update(s.gyr, s.acc, nine_d.then_some(s.mag));
    if nine_d {
        vqf.quat_9d()
    } else {
        vqf.quat_6d()
    }
});
measured!(fn bench_vqf_empty(x: &Turn) |i| &x[i % VQF_INPUTS]);
measured!(fn bench_vqf_9d(vqf: &mut Vqf<f32>, x: &Turn) |i| {
    let s = black_box(&x[i % VQF_INPUTS]);
    vqf.update(s.gyr, s.acc, Some(s.mag));
    vqf.quat_9d()
});
measured!(fn bench_vqf_6d(vqf: &mut Vqf<f32>, x: &Turn) |i| {
    let s = black_box(&x[i % VQF_INPUTS]);
    vqf.update(s.gyr, s.acc, None);
    vqf.quat_6d()
});

// ---- The protocol crate's CRC-32C and COBS beside the crates ----------------------------------
//
// qgait-proto computes CRC-32C and COBS with its own code (src/crc.rs, src/cobs.rs) where a
// crate exists: these figures are why. Each pair runs on the same bytes: the 11-byte message of
// a joint-angle packet (the receive side) and the 146-byte message of a PHAK pose frame (the
// transmit side), each followed by its CRC for COBS. The crates: `crc` (`FRAME_CRC`, its default
// 1 KiB table; postcard's CRC flavour is this crate), `cobs` (postcard decodes with
// `cobs::decode_in_place`) and postcard's own `Cobs` serialiser flavour.

/// The protocol crate's COBS functions, the very source it builds (they are not public API).
#[allow(dead_code)]
#[path = "../../../crates/qgait-proto/src/cobs.rs"]
mod proto_cobs;

/// Bytes of the largest input here (a pose frame's message and CRC, then COBS-encoded).
const CODEC_MAX: usize = 160;

/// Runs the comparison on the packet messages `packets` and the pose frame messages `poses`.
fn crc_cobs_beside_crates(packets: &[heapless::Vec<u8, 32>; INPUTS], poses: &[Message; INPUTS]) {
    let pose_messages: [heapless::Vec<u8, CODEC_MAX>; INPUTS] = core::array::from_fn(|i| {
        let mut out = [0u8; CODEC_MAX];
        let len = encode_message(&poses[i], &mut out)
            .map(|m| m.len())
            .unwrap_or(0);
        heapless::Vec::from_slice(&out[..len]).unwrap_or_default()
    });
    let packets: [heapless::Vec<u8, CODEC_MAX>; INPUTS] =
        core::array::from_fn(|i| heapless::Vec::from_slice(&packets[i]).unwrap_or_default());
    for (what, messages) in [("packet", &packets), ("pose", &pose_messages)] {
        if messages.iter().any(|m| m.is_empty()) {
            board::exit(PIPELINE_EXIT_CODE)
        }
        let base = Base::of(messages, CALLS);
        base.net_named("crc.ours", what, |n| bench_crc_of(messages, n, crc32c));
        base.net_named("crc.crc_crate", what, |n| {
            bench_crc_of(messages, n, |m| qgait_proto::FRAME_CRC.checksum(m))
        });

        // COBS input: the message and its CRC, as in a frame.
        let data: [heapless::Vec<u8, CODEC_MAX>; INPUTS] = core::array::from_fn(|i| {
            let mut d = messages[i].clone();
            let _ = d.extend_from_slice(&crc32c(&messages[i]).to_le_bytes());
            d
        });
        // Every encoder starts from a copy of the data in a scratch buffer (ours encodes in
        // place, at `buf[1..]`), so the copy alone is the base.
        let copy = Base::with(CALLS, |n| bench_cobs_encode(&data, n, |_, _| 0));
        copy.net_named("cobs.encode_ours", what, |n| {
            bench_cobs_encode(&data, n, |buf, len| {
                proto_cobs::encode_in_place(buf, len).unwrap_or(0)
            })
        });
        copy.net_named("cobs.encode_cobs_crate", what, |n| {
            bench_cobs_encode(&data, n, |buf, len| {
                let (src, dst) = buf.split_at_mut(CODEC_MAX);
                cobs::try_encode(&src[1..=len], dst).unwrap_or(0)
            })
        });
        copy.net_named("cobs.encode_postcard_flavour", what, |n| {
            bench_cobs_encode(&data, n, |buf, len| {
                use postcard::ser_flavors::{Cobs, Flavor, Slice};
                let (src, dst) = buf.split_at_mut(CODEC_MAX);
                Cobs::try_new(Slice::new(dst))
                    .and_then(|mut f| f.try_extend(&src[1..=len]).and_then(|()| f.finalize()))
                    .map(|out| out.len())
                    .unwrap_or(0)
            })
        });

        // Decoders: the COBS bytes of each frame (no delimiter), copied into a scratch buffer
        // before each call (both decode in place); the copy alone is the base.
        let encoded: [heapless::Vec<u8, CODEC_MAX>; INPUTS] = core::array::from_fn(|i| {
            let mut out = [0u8; CODEC_MAX];
            let n = proto_cobs::encode(data[i].iter().copied(), &mut out).unwrap_or(0);
            heapless::Vec::from_slice(&out[..n]).unwrap_or_default()
        });
        let copy = Base::with(CALLS, |n| bench_cobs_decode(&encoded, n, |_| 0));
        copy.net_named("cobs.decode_ours", what, |n| {
            bench_cobs_decode(&encoded, n, |buf| {
                proto_cobs::decode_in_place_unshifted(buf).map_or(0, |r| r.len())
            })
        });
        copy.net_named("cobs.decode_cobs_crate", what, |n| {
            bench_cobs_decode(&encoded, n, |buf| cobs::decode_in_place(buf).unwrap_or(0))
        });
    }
}

/// `crc` of each message in turn.
#[inline(never)]
fn bench_crc_of<const M: usize>(
    messages: &[heapless::Vec<u8, M>; INPUTS],
    n: u32,
    crc: impl Fn(&[u8]) -> u32,
) -> u32 {
    timed(n, |i| {
        black_box(crc(black_box(&messages[i % INPUTS])));
    })
}

/// Copies each input to `buf[1..]` and calls `encode(buf, len)`, which may use `buf[1..=len]`
/// as its input and write from `buf[0]` on, or read `buf[1..=len]` and write `buf[CODEC_MAX..]`.
#[inline(never)]
fn bench_cobs_encode(
    data: &[heapless::Vec<u8, CODEC_MAX>; INPUTS],
    n: u32,
    encode: impl Fn(&mut [u8], usize) -> usize,
) -> u32 {
    let mut buf = [0u8; 2 * CODEC_MAX + 2];
    timed(n, |i| {
        let d = black_box(&data[i % INPUTS]);
        if let Some(dst) = buf.get_mut(1..=d.len()) {
            dst.copy_from_slice(d);
        }
        black_box(encode(black_box(&mut buf), d.len()));
    })
}

/// Copies each encoded frame to a scratch buffer and calls `decode` on it.
#[inline(never)]
fn bench_cobs_decode(
    encoded: &[heapless::Vec<u8, CODEC_MAX>; INPUTS],
    n: u32,
    decode: impl Fn(&mut [u8]) -> usize,
) -> u32 {
    let mut buf = [0u8; CODEC_MAX];
    timed(n, |i| {
        let e = black_box(&encoded[i % INPUTS]);
        if let Some(dst) = buf.get_mut(..e.len()) {
            dst.copy_from_slice(e);
            black_box(decode(black_box(dst)));
        }
    })
}
