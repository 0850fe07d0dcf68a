//! `qgait decode` and `qgait verify` on a serial port, end to end: the hub firmware under QEMU
//! with UART0 on a pseudo-terminal (`-serial pty`), so qgait reads a real tty. Before each run
//! the terminal is put back as a freshly plugged port is (cooked, echoing, 9600 baud, as
//! `stty sane 9600` leaves it); qgait must set it raw at 115200 itself. Only qgait reads the
//! terminal; this test writes the nodes' packets through a second open of it (writes to the
//! slave go to QEMU, the master) and reads what qgait prints.
//!
//! Needs `qemu-system-arm`, the release firmware and `stty` (Linux); skipped, with the reason
//! printed, when QEMU or the firmware is missing.
#![cfg(target_os = "linux")]

use qgait_system_tests as common;

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

use qgait_device::frames_csv;
use qgait_device::packets::{push_frame, stream, Samples, Timing};
use qgait_emulate::qemu::{Echo, Qemu};
use qgait_model::coords::KneeFlexion;
use qgait_model::motion::source::load_motion;
use qgait_proto::{Config, JointAngle, Message, MissingPolicy, ModelId, PoseFrame, PoseModels};

/// Samples per run.
const N: usize = 150;
/// Safety limit of every wait (the runs take a second or two).
const PATIENCE: Duration = Duration::from_secs(60);

/// The terminal as a freshly plugged port: cooked mode with echo, 9600 baud.
fn unplug_and_replug(pty: &Path) {
    let o = Command::new("stty")
        .arg("-F")
        .arg(pty)
        .args(["sane", "9600"])
        .output()
        .expect("stty runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (baud, raw) = settings(pty);
    assert!((baud, raw) == (9600, false), "{baud} raw {raw}");
}

/// The terminal's baud rate and whether it is raw (no line editing, echo, signals, output
/// processing or input translation).
fn settings(pty: &Path) -> (u32, bool) {
    let port = serial2::SerialPort::open(pty, serial2::KeepSettings).expect("the pty opens");
    let s = port.get_configuration().expect("termios");
    let t = s.as_termios();
    let raw = t.c_lflag & (libc::ICANON | libc::ECHO | libc::ISIG | libc::IEXTEN) == 0
        && t.c_oflag & libc::OPOST == 0
        && t.c_iflag & (libc::ICRNL | libc::IXON | libc::ISTRIP) == 0
        && t.c_cflag & libc::CSIZE == libc::CS8
        && t.c_cflag & (libc::PARENB | libc::CSTOPB | libc::CRTSCTS) == 0;
    (s.get_baud_rate().unwrap_or(0), raw)
}

/// Starts `qgait args` and waits until it has set the port raw at 115200 baud.
fn start_qgait(pty: &Path, args: &[&str]) -> Child {
    let mut child = Command::new(common::qgait_bin())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("qgait runs");
    let deadline = Instant::now() + PATIENCE;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            panic!("qgait {args:?} ended ({status}) before configuring the port:\n{err}");
        }
        let (baud, raw) = settings(pty);
        if baud == 115_200 && raw {
            return child;
        }
        assert!(
            Instant::now() < deadline,
            "qgait did not set {} raw at 115200 baud (it is at {baud}, raw {raw})",
            pty.display()
        );
        thread::sleep(Duration::from_millis(20));
    }
}

/// Writes `bytes` to the terminal (they go to the hub) from a thread; the returned handle
/// gives back the open file, to be closed once qgait is done.
fn send(pty: &Path, bytes: Vec<u8>) -> thread::JoinHandle<File> {
    let mut w = std::fs::OpenOptions::new()
        .write(true)
        .custom_flags(libc::O_NOCTTY)
        .open(pty)
        .expect("the pty opens for writing");
    thread::spawn(move || {
        w.write_all(&bytes).expect("the hub takes the packets");
        w
    })
}

fn wait(child: &mut Child) -> ExitStatus {
    let deadline = Instant::now() + PATIENCE;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("qgait still running after {PATIENCE:?}");
        }
        thread::sleep(Duration::from_millis(10));
    }
}

fn read_all(r: Option<impl Read + Send + 'static>) -> thread::JoinHandle<String> {
    let mut r = r.unwrap();
    thread::spawn(move || {
        let mut s = String::new();
        r.read_to_string(&mut s).unwrap();
        s
    })
}

/// The packets of samples `rows`, framed as the nodes send them.
fn packets(samples: &Samples, rows: std::ops::Range<usize>) -> Vec<u8> {
    let p: Vec<JointAngle> = rows.flat_map(|r| samples.packets(r)).collect();
    stream(&p)
}

/// The points the hub must send for sample `row`, from the f64 kernel.
fn expected_points(model: &PoseModels<f64>, samples: &Samples, row: usize) -> [[f64; 3]; 8] {
    let angles: Vec<f32> = samples.packets(row).map(|p| p.angle).collect();
    let frame = PoseFrame {
        seq: row as u32,
        timestamp_us: row as u32 * 10_000,
        model: ModelId::Phak,
        angles: heapless::Vec::from_slice(&angles).unwrap(),
        points: [[0.0; 3]; 8],
        distances: [0.0; 3],
        flags: 0,
    };
    model
        .frame_pose(&frame)
        .expect("a hub's own model")
        .points()
        .map(|p| p.to_array())
}

#[test]
fn decode_and_verify_read_the_hub_on_a_pseudo_terminal() {
    let Some(elf) = common::firmware_elf() else {
        return;
    };
    let (qemu, pty) = Qemu::start_pty(&elf, Echo::Quiet).expect("QEMU starts");
    let port = pty.to_str().unwrap();
    let (table, _) = load_motion(&format!("builtin:normal,rows={}", 2 * N)).unwrap();
    let (samples, _) = Samples::from_motion(
        &table,
        ModelId::Phak,
        KneeFlexion::Negative,
        Timing::Rate(100.0),
    )
    .unwrap();
    let mut first = vec![0u8];
    push_frame(
        &mut first,
        &Message::Config(Config {
            model: ModelId::Phak,
            anthropometry: None,
            missing_policy: MissingPolicy::Drop,
            reorder_window: 4,
            request_status: false,
        }),
    );
    first.extend(packets(&samples, 0..N));

    // decode: rows come out as frames arrive; Ctrl-C ends it with the output whole.
    unplug_and_replug(&pty);
    let mut child = start_qgait(&pty, &["decode", port, "--baud", "115200"]);
    let writer = send(&pty, first);
    let err = read_all(child.stderr.take());
    let (tx, rows) = mpsc::channel();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let reader = thread::spawn(move || {
        let mut line = String::new();
        while out.read_line(&mut line).unwrap() > 0 {
            let _ = tx.send(std::mem::take(&mut line));
        }
    });
    let mut text = String::new();
    for _ in 0..=N {
        match rows.recv_timeout(PATIENCE) {
            Ok(line) => text.push_str(&line),
            Err(_) => panic!(
                "qgait decode printed {} lines, not {N} rows and the header, while the hub sent",
                text.lines().count()
            ),
        }
    }
    let interrupted = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
    let status = wait(&mut child);
    reader.join().unwrap();
    text.extend(rows.try_iter());
    let err = err.join().unwrap();
    drop(writer.join().unwrap());
    assert!(status.success(), "{status}\n{err}");
    assert!(
        text.ends_with('\n') && err.contains("stopped: interrupted"),
        "{err}"
    );
    // What the hub sends while no one has the terminal open is dropped by QEMU, so a status
    // frame being sent at the moment a program opened it may arrive cut: at most that one, at
    // the start.
    let summary = err
        .lines()
        .find(|l| l.starts_with("decoded "))
        .unwrap_or("");
    // ("LOG: damaged frame ending at byte N: …" or "LOG: a frame longer than …, at byte N: …")
    let offsets: Vec<u64> = err
        .lines()
        .filter_map(|l| l.split_once(" at byte "))
        .map(|(_, l)| l.split(':').next().unwrap().parse::<u64>().unwrap())
        .collect();
    let cut_at_start = !offsets.is_empty() && offsets.iter().all(|&offset| offset < 128);
    assert!(
        summary.contains(&format!(": {N} pose frames"))
            && (summary.contains(" 0 damaged frames")
                || summary.contains(" 1 damaged frames") && cut_at_start),
        "{err}"
    );
    let table = frames_csv::parse(&text, "decode output").unwrap();
    assert_eq!(table.seq, (0..N as u32).collect::<Vec<_>>());
    let model = PoseModels::defaults();
    for (row, points) in table.points.iter().enumerate() {
        let want = expected_points(&model, &samples, row);
        for (p, q) in points.iter().zip(want) {
            let d = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
            assert!(d < 10e-6, "seq {row}: {p:?} vs {q:?}");
        }
    }

    // verify: every frame of the next samples checked as it arrives, stopping after N.
    unplug_and_replug(&pty);
    let n = N.to_string();
    let mut child = start_qgait(
        &pty,
        &[
            "verify", port, "--baud", "115200", "--frames", &n, "--live", "on",
        ],
    );
    let writer = send(&pty, packets(&samples, N..2 * N));
    let (out, err) = (read_all(child.stdout.take()), read_all(child.stderr.take()));
    let status = wait(&mut child);
    let (out, err) = (out.join().unwrap(), err.join().unwrap());
    drop(writer.join().unwrap());
    assert!(status.success(), "{status}\n{out}{err}");
    assert!(
        out.contains(&format!("{N} frames ({N} phak)"))
            && out.contains("missing samples: 0")
            && out.ends_with("verify: ok\n"),
        "{out}"
    );
    assert!(
        err.contains(&format!("stopped after {N} pose frames")),
        "{err}"
    );
    qemu.stop();
}
