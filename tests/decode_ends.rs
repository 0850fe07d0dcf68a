//! How `qgait decode` and `verify` end on a live input that never closes (a pipe kept open, as
//! from a serial bridge): `--idle`, `--seconds` and `--frames`, with the output whole. The
//! serial-port case, with Ctrl-C, is in `serial_pty.rs`.

use qgait_system_tests as common;

use std::io::{Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

use qgait_device::packets::push_frame;
use qgait_proto::{Message, ModelId, PoseFrame};

/// Safety limit of every wait (the runs end in well under a second).
const PATIENCE: Duration = Duration::from_secs(60);

fn pose(seq: u32) -> Message {
    Message::PoseFrame(PoseFrame {
        seq,
        timestamp_us: seq * 10_000,
        model: ModelId::Hak,
        angles: heapless::Vec::from_slice(&[0.0; 6]).unwrap(),
        points: [[0.25; 3]; 8],
        distances: [0.0; 3],
        flags: 0,
    })
}

/// `qgait args` with `bytes` written to its standard input, which is then kept open.
fn start(args: &[&str], bytes: &[u8]) -> (Child, ChildStdin) {
    let mut child = Command::new(common::qgait_bin())
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("qgait runs");
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(bytes).unwrap();
    stdin.flush().unwrap();
    (child, stdin)
}

/// Waits for the end (the input still open) and returns exit success, stdout, stderr.
fn finish(mut child: Child, stdin: ChildStdin) -> (bool, String, String) {
    let deadline = Instant::now() + PATIENCE;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("qgait still running after {PATIENCE:?} with its input open");
        }
        thread::sleep(Duration::from_millis(10));
    };
    drop(stdin);
    let (mut out, mut err) = (String::new(), String::new());
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (status.success(), out, err)
}

#[test]
fn a_live_pipe_ends_on_idle_seconds_or_frames_with_whole_rows() {
    let mut log = vec![0u8];
    for seq in 0..5 {
        push_frame(&mut log, &pose(seq));
    }
    // Half a frame more: it must not come out.
    let mut tail = Vec::new();
    push_frame(&mut tail, &pose(5));
    log.extend_from_slice(&tail[..tail.len() / 2]);

    let (child, stdin) = start(&["decode", "-", "--idle", "0.3"], &log);
    let (ok, out, err) = finish(child, stdin);
    assert!(ok, "{err}");
    assert_eq!(out.lines().count(), 6, "header and 5 rows:\n{out}");
    assert!(out.ends_with('\n'));
    assert!(
        err.contains("stopped: no pose frame for 0.3 s")
            && err.contains("5 pose frames")
            && err.contains("bytes at the end without a delimiter"),
        "{err}"
    );

    let (child, stdin) = start(
        &["decode", "-", "--seconds", "0.2", "--format", "jsonl"],
        &[],
    );
    let (ok, out, err) = finish(child, stdin);
    assert!(ok && out.is_empty(), "{out}{err}");
    assert!(err.contains("stopped after 0.2 s"), "{err}");

    let (child, stdin) = start(&["decode", "-", "--frames", "3"], &log);
    let (ok, out, err) = finish(child, stdin);
    assert!(ok, "{err}");
    let seqs: Vec<&str> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(seqs, ["0", "1", "2"], "{out}");
    assert!(err.contains("stopped after 3 pose frames"), "{err}");

    // verify stops the same way, and reports on what it read.
    let (child, stdin) = start(&["verify", "-", "--model", "hak", "--idle", "0.3"], &log);
    let (ok, out, err) = finish(child, stdin);
    assert!(!ok, "the points are not the kernel's: {out}");
    assert!(
        out.contains("5 frames (5 hak)") && out.contains("missing samples: 0"),
        "{out}"
    );
    assert!(err.contains("stopped: no pose frame for 0.3 s"), "{err}");

    let o = common::qgait(&["decode", "-", "--frames", "0"]);
    assert!(!o.status.success());
    assert!(
        common::stderr(&o).contains("--frames"),
        "{}",
        common::stderr(&o)
    );
    let o = common::qgait(&["decode", "-", "--idle", "0"]);
    assert!(
        common::stderr(&o).contains("not a positive number of seconds"),
        "{}",
        common::stderr(&o)
    );
}
