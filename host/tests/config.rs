//! `qgait config`: the frames written for built-in and subject models decode to the documented
//! messages, and bad combinations are one-line errors.

mod common;

use std::path::Path;

use common::{qgait, stderr};
use qgait_device::config::geometry_of_parts;
use qgait_kernel::Gait2392Geometry;
use qgait_proto::{FrameDecoder, Message, MissingPolicy, ModelId};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `qgait config ARGS -o out.bin` and decodes the file.
fn config(dir: &Path, args: &[&str]) -> Vec<Message> {
    let out = dir.join("out.bin");
    let mut all: Vec<&str> = vec!["config"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", s(&out)]);
    let run = qgait(&all);
    assert!(run.status.success(), "{args:?}: {}", stderr(&run));
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(bytes.first(), Some(&0), "frames start after a delimiter");
    let mut d = FrameDecoder::new();
    bytes
        .iter()
        .filter_map(|&b| d.push(b))
        .map(|r| r.expect("every frame decodes"))
        .collect()
}

#[test]
fn phak_with_lengths_hold_and_window() {
    let dir = tempfile::tempdir().unwrap();
    let lengths = dir.path().join("a.toml");
    std::fs::write(
        &lengths,
        "pelvis_half_width = 0.09\nfemur = 0.41\ntibia = 0.44\nfoot = 0.21\n",
    )
    .unwrap();
    let sent = config(
        dir.path(),
        &[
            "--model",
            "phak",
            "--anthropometry",
            s(&lengths),
            "--policy",
            "hold",
            "--window",
            "3",
        ],
    );
    let [Message::Config(c)] = sent.as_slice() else {
        panic!("{sent:?}")
    };
    assert_eq!(c.model, ModelId::Phak);
    assert_eq!(c.missing_policy, MissingPolicy::HoldLast);
    assert_eq!(c.reorder_window, 3);
    assert!(c.request_status);
    assert_eq!(c.anthropometry, Some([[0.09, 0.41, 0.44, 0.21]; 2]));
}

#[test]
fn subject_toml_is_six_parts_and_a_subject_config() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gait2392Geometry::generic();
    g.left.toetip_in_toes[0] = 0.09;
    let file = dir.path().join("subject.toml");
    std::fs::write(&file, qgait_model::subject::to_toml(&g, &[])).unwrap();
    let sent = config(
        dir.path(),
        &["--model", s(&file), "--upload", "17", "--no-status-request"],
    );
    assert_eq!(sent.len(), 7);
    let Message::SubjectConfig(c) = sent[6] else {
        panic!("{:?}", sent[6])
    };
    assert_eq!(
        (c.upload, c.request_status, c.reorder_window),
        (17, false, 4)
    );
    let back = geometry_of_parts(&sent[..6]).unwrap();
    assert_eq!(back.left.toetip_in_toes[0], 0.09f32 as f64);
    assert_eq!(back.right.knee_tx.n, g.right.knee_tx.n);
}

#[test]
fn generic_gait2392_is_one_config() {
    let dir = tempfile::tempdir().unwrap();
    let sent = config(dir.path(), &["--model", "gait2392"]);
    assert!(
        matches!(sent.as_slice(), [Message::Config(c)] if c.model == ModelId::Gait2392 && c.anthropometry.is_none())
    );
}

#[test]
fn bad_combinations_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.bin");
    let lengths = dir.path().join("a.toml");
    std::fs::write(&lengths, "femur = 0.41\n").unwrap();
    for (args, needle) in [
        (
            vec!["--model", "gait2392", "--anthropometry", s(&lengths)],
            "--anthropometry applies to hak and phak only",
        ),
        (vec!["--model", "phak", "--upload", "3"], "--upload applies"),
        (vec!["--model", "nonsense"], "unknown model `nonsense`"),
    ] {
        let mut all = vec!["config"];
        all.extend(args);
        all.extend(["-o", s(&out)]);
        let run = qgait(&all);
        assert!(!run.status.success(), "{all:?}");
        let e = stderr(&run);
        assert!(
            e.contains(needle) && e.trim_end().lines().count() == 1,
            "{e}"
        );
    }
    assert!(!out.exists());
}

/// A reorder window a hub would reject (section 4.4 of the protocol) is refused here first.
#[test]
fn a_window_outside_one_to_eight_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.bin");
    for window in ["0", "9"] {
        let run = qgait(&[
            "config",
            "--model",
            "hak",
            "--window",
            window,
            "-o",
            s(&out),
        ]);
        assert!(!run.status.success(), "--window {window}");
        assert!(stderr(&run).contains("is not in 1..=8"), "{}", stderr(&run));
    }
    assert!(!out.exists());
    assert_eq!(
        config(dir.path(), &["--model", "hak", "--window", "8"]).len(),
        1
    );
}

/// OpenSense's Rajagopal 2015 imported by `qgait model import` into `dir` (`None`, and a printed
/// reason, without the shared data).
fn imported_rajagopal(dir: &Path) -> Option<std::path::PathBuf> {
    let shared = common::shared_dir()?;
    let osim = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    let toml = dir.join("raj.toml");
    let run = qgait(&["model", "import", "-q", s(&osim), "-o", s(&toml)]);
    assert!(run.status.success(), "{}", stderr(&run));
    Some(toml)
}

/// The device benchmark's Rajagopal upload (`firmware/src/bin/rajagopal2015_opensense.chain.bin`,
/// which its `rajagopal()` decodes and checks by its CRC) is what `qgait config` sends today:
/// a change to the table or its messages fails here, not as a benchmark that exits.
#[test]
fn the_benchmarks_rajagopal_upload_is_current() {
    let dir = tempfile::tempdir().unwrap();
    let Some(toml) = imported_rajagopal(dir.path()) else {
        return;
    };
    let out = dir.path().join("raj.bin");
    let run = qgait(&[
        "config",
        "--model",
        s(&toml),
        "--upload",
        "1",
        "-o",
        s(&out),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let bench = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../firmware/src/bin/rajagopal2015_opensense.chain.bin");
    assert!(
        std::fs::read(&out).unwrap() == std::fs::read(&bench).unwrap(),
        "{} is stale: make it again as its doc comment in firmware/src/bin/bench.rs says",
        bench.display()
    );
}

/// An imported Rajagopal model is its table's image in 12 `ChainTable` parts and a
/// `ChainTableConfig`; the table the parts write, which the config's CRC accepts, gives the
/// imported model's joint centres to 2 µm in `f32`.
#[test]
fn imported_chain_is_its_table_and_a_chain_table_config() {
    use qgait_proto::device_model::{table_crc, DeviceChain};
    let dir = tempfile::tempdir().unwrap();
    let Some(toml) = imported_rajagopal(dir.path()) else {
        return;
    };
    let messages = config(dir.path(), &["--model", s(&toml), "--upload", "3"]);
    // 192 bytes of codes and 325 numbers: 1,492 bytes, 128 a part.
    assert_eq!(messages.len(), 13);
    let mut hub = DeviceChain::EMPTY;
    for m in &messages[..12] {
        let Message::ChainTable(p) = m else {
            panic!("{m:?}")
        };
        assert_eq!(p.upload, 3);
        hub.write_image(usize::from(p.at), &p.bytes);
    }
    let Message::ChainTableConfig(c) = &messages[12] else {
        panic!("{:?}", messages[12])
    };
    assert_eq!((c.upload, c.len, c.reorder_window), (3, 1492, 4));
    assert!(c.request_status);
    assert_eq!(table_crc(&hub, usize::from(c.len)), c.crc);
    let text = std::fs::read_to_string(&toml).unwrap();
    let host = qgait_model::chain::ChainModel::parse(&text, "raj.toml")
        .unwrap()
        .chain("test")
        .unwrap();
    for k in 0..20 {
        let q: [f64; 17] = std::array::from_fn(|i| 0.6 * ((k * 17 + i) as f64 * 0.7).sin());
        let q = q.map(|a| a.abs().min(2.0) * if a < 0.0 { -0.3 } else { 1.0 });
        let a = host.forward(&q);
        let b = hub.forward(&q.map(|x| x as f32));
        for (a, b) in a.iter().zip(&b) {
            assert!(a.max_abs_diff(b.cast()) < 2e-6, "{a:?} {b:?}");
        }
    }
}
