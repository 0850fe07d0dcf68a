#!/usr/bin/env python3
"""Reference outputs of VQF (the `vqf` package from PyPI, MIT) for qgait's port.

Runs outside the build. Two jobs:

* `fixtures` (default): runs the reference `vqf.VQF` (the C++ filter in double, default
  parameters, `updateBatch`) on

  - `broad34_9d.bin`: BROAD trial 34 (a magnet attached next to the IMU, rest at start and end)
    taken every 16th sample (17.9 Hz over the whole 169 s, so that rest detection, magnetic
    disturbance detection and rejection and the acceptance of a field all occur), 9D;
  - `synthetic_6d.bin`: 30 s of synthetic motion at 100 Hz with a constant gyroscope bias, rest
    phases and accelerations, 6D (no magnetometer),

  and writes inputs and outputs to `crates/qgait-kernel/tests/data/vqf/` (format below), read by
  `crates/qgait-kernel/tests/fusion_vqf.rs`.

* `broad`: prints the reference's own BROAD errors (9D total / heading / inclination RMSE and
  6D inclination RMSE, degrees) on the shared trials: the bar of the kernel's scoring test.

Fixture format (little-endian): `b"VQFX"`, u32 version = 1, f64 sampling period, u32 sample
count n, u32 output stride k, u8 has_mag; then per sample i: gyr (3 x f32, rad/s), acc (3 x f32,
m/s^2), mag (3 x f32, uT, if has_mag), u8 flags (bit 0 rest detected, bit 1 magnetic disturbance
detected), and when i % k == 0 the reference outputs after that sample as f64: quat6D (4),
quat9D (4, if has_mag), bias (3). Inputs are stored as f32 and the reference is fed exactly
those values (as double), so the fixture's inputs are exact.

Usage: scripts/vqf_fixtures.py [fixtures|broad] [--broad DIR]
"""

import argparse
import pathlib
import struct
import sys

import numpy as np
import vqf

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "crates" / "qgait-kernel" / "tests" / "data" / "vqf"
STRIDE = 4


def load_broad(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    t = d["time"]
    ts = (t[-1] - t[0]) / (len(t) - 1)
    gyr = np.column_stack([d["gyr_x"], d["gyr_y"], d["gyr_z"]])
    acc = np.column_stack([d["acc_x"], d["acc_y"], d["acc_z"]])
    mag = np.column_stack([d["mag_x"], d["mag_y"], d["mag_z"]])
    opt = np.column_stack([d["opt_w"], d["opt_x"], d["opt_y"], d["opt_z"]])
    return ts, gyr, acc, mag, opt, d["movement"]


def write_fixture(name, ts, gyr, acc, mag):
    gyr = np.ascontiguousarray(gyr, dtype=np.float32)
    acc = np.ascontiguousarray(acc, dtype=np.float32)
    f = vqf.VQF(ts)
    if mag is not None:
        mag = np.ascontiguousarray(mag, dtype=np.float32)
        out = f.updateBatch(gyr.astype(np.float64), acc.astype(np.float64), mag.astype(np.float64))
    else:
        out = f.updateBatch(gyr.astype(np.float64), acc.astype(np.float64))
    n = len(gyr)
    buf = bytearray(b"VQFX")
    buf += struct.pack("<IdIIB", 1, ts, n, STRIDE, 1 if mag is not None else 0)
    for i in range(n):
        buf += gyr[i].tobytes() + acc[i].tobytes()
        if mag is not None:
            buf += mag[i].tobytes()
        flags = int(out["restDetected"][i]) | (int(out["magDistDetected"][i]) << 1 if mag is not None else 0)
        buf += struct.pack("<B", flags)
        if i % STRIDE == 0:
            buf += out["quat6D"][i].astype("<f8").tobytes()
            if mag is not None:
                buf += out["quat9D"][i].astype("<f8").tobytes()
            buf += out["bias"][i].astype("<f8").tobytes()
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / name).write_bytes(bytes(buf))
    rest = out["restDetected"].mean()
    dist = out["magDistDetected"].mean() if mag is not None else float("nan")
    print(f"{name}: {n} samples, {len(buf)} bytes, rest {rest:.2f}, mag disturbed {dist:.2f}")


def synthetic(ts=0.01, seconds=30.0, seed=7):
    """Orientation driven by smooth angular rates with rest phases; gyroscope with a constant
    bias and noise, accelerometer = gravity in the sensor frame + linear acceleration + noise."""
    rng = np.random.default_rng(seed)
    n = int(round(seconds / ts))
    t = np.arange(n) * ts
    moving = ~(((t > 2) & (t < 6)) | ((t > 16) & (t < 20)))
    w = np.column_stack(
        [
            1.5 * np.sin(2 * np.pi * 0.31 * t),
            1.0 * np.sin(2 * np.pi * 0.17 * t + 1.0),
            2.0 * np.sin(2 * np.pi * 0.23 * t + 2.0),
        ]
    ) * moving[:, None]
    q = np.array([0.9, 0.1, -0.3, 0.2])
    q /= np.linalg.norm(q)
    g = np.array([0.0, 0.0, 9.81])
    gyr = np.empty((n, 3))
    acc = np.empty((n, 3))
    bias = np.array([0.01, -0.015, 0.008])
    for i in range(n):
        # acc_S = q* (g + a) q with a linear acceleration while moving.
        a = g + (0.8 * np.array([np.sin(1.3 * t[i]), np.cos(0.7 * t[i]), 0.5 * np.sin(2.1 * t[i])]) if moving[i] else 0)
        acc[i] = rotate(conj(q), a) + rng.normal(0, 0.05, 3)
        gyr[i] = w[i] + bias + rng.normal(0, 0.003, 3)
        ang = np.linalg.norm(w[i]) * ts
        if ang > 0:
            axis = w[i] / np.linalg.norm(w[i])
            q = qmul(q, np.concatenate([[np.cos(ang / 2)], np.sin(ang / 2) * axis]))
    return ts, gyr, acc


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def conj(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def rotate(q, v):
    return qmul(qmul(q, np.concatenate([[0.0], v])), conj(q))[1:]


def broad_errors(est, opt, movement):
    """BROAD's metric: RMS (deg) of total, heading, inclination of est * opt^-1."""
    ok = (movement == 1) & np.all(np.isfinite(opt), axis=1)
    a = est[ok] / np.linalg.norm(est[ok], axis=1)[:, None]
    b = opt[ok] / np.linalg.norm(opt[ok], axis=1)[:, None]
    b = b * np.array([1, -1, -1, -1])
    ew = a[:, 0] * b[:, 0] - a[:, 1] * b[:, 1] - a[:, 2] * b[:, 2] - a[:, 3] * b[:, 3]
    ez = a[:, 0] * b[:, 3] + a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1] + a[:, 3] * b[:, 0]
    total = 2 * np.arccos(np.clip(np.abs(ew), 0, 1))
    heading = 2 * np.arctan2(np.abs(ez), np.abs(ew))
    incl = 2 * np.arccos(np.clip(np.sqrt(ew**2 + ez**2), 0, 1))
    rms = lambda x: np.degrees(np.sqrt(np.mean(x**2)))
    return rms(total), rms(heading), rms(incl)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("job", nargs="?", default="fixtures", choices=["fixtures", "broad"])
    ap.add_argument("--broad", default=str(ROOT.parent / "shared" / "data" / "broad"))
    args = ap.parse_args()
    broad = pathlib.Path(args.broad)
    if args.job == "fixtures":
        ts, gyr, acc, mag, _, _ = load_broad(broad / "34_disturbed_attached_magnet_3cm.csv")
        write_fixture("broad34_9d.bin", ts * 16, gyr[::16], acc[::16], mag[::16])
        ts, gyr, acc = synthetic()
        write_fixture("synthetic_6d.bin", ts, gyr, acc, None)
        return
    rows = []
    for path in sorted(broad.glob("*.csv")):
        ts, gyr, acc, mag, opt, movement = load_broad(path)
        out9 = vqf.VQF(ts).updateBatch(gyr, acc, mag)
        out6 = vqf.VQF(ts).updateBatch(gyr, acc)
        t9 = broad_errors(out9["quat9D"], opt, movement)
        t6 = broad_errors(out6["quat6D"], opt, movement)
        rows.append((path.stem, *t9, t6[2]))
        print(f"{path.stem:50s} 9D total {t9[0]:.4f} heading {t9[1]:.4f} incl {t9[2]:.4f}  6D incl {t6[2]:.4f}")
    m = np.mean([r[1:] for r in rows], axis=0)
    print(f"{'mean':50s} 9D total {m[0]:.4f} heading {m[1]:.4f} incl {m[2]:.4f}  6D incl {m[3]:.4f}")


if __name__ == "__main__":
    sys.exit(main())
