#!/usr/bin/env python3
"""A long recording built from the IMU walk: `qgait imu`'s joint angles of OpenSense's tutorial
walk (24.31 s, 100 Hz) repeated end to end to HOURS hours, times continuing at 100 Hz, values
rounded to 1e-4 (degrees).

    qgait imu $D/walking_orientations.sto --calibration $D/placement_orientations.sto \\
        --base-imu torso_imu --base-heading-axis z -o walk.mot
    python3 scripts/long_recording.py walk.mot 24 /tmp/day.mot

Used for BENCHMARKS.md's memory and time of `qgait gait` against `qgait fk` (tests/memory.rs
builds its shorter recordings the same way)."""

import sys


def main():
    src, hours, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    lines = open(src).read().splitlines()
    end = next(i for i, l in enumerate(lines) if l.strip().lower() == "endheader")
    labels = lines[end + 1]
    rows = [l.split("\t") for l in lines[end + 2:] if l.strip()]
    rest = ["\t".join(f"{float(v):.4f}" for v in r[1:]) for r in rows]
    n = round(hours * 3600 * 100)
    with open(out, "w") as f:
        f.write(f"long_walk\nversion=1\nnRows={n}\nnColumns={len(rows[0])}\ninDegrees=yes\nendheader\n")
        f.write(labels + "\n")
        k = len(rest)
        for i in range(n):
            f.write(f"{i / 100:.2f}\t{rest[i % k]}\n")


main()
