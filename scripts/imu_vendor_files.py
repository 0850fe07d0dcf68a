#!/usr/bin/env python3
"""Vendor IMU exports for host/tests/imu_vendor.rs, written from the tutorial recording, and the
same files read by OpenSim's own readers (an independent client of the formats).

From ../shared/data/imu (the OpenSense tutorial's Xsens recording): the static pose
(`placement_orientations.sto`, 1 row) and 1 s of walking (`walking_orientations.sto` rows from
6.0 s, 100 rows) are written as
- Xsens MT Manager exports (`xsens/`): one tab-separated `.txt` per sensor and trial, named
  `<trial prefix><sensor id>.txt` (`walk-000_00B421AF.txt`, ...), `//` comment lines with
  `Update Rate: 100.0Hz`, a label line (`PacketCounter`, `Acc_X`..., `Mat[1][1]`, `Mat[2][1]`,
  `Mat[3][1]`, `Mat[1][2]`, ...: the sensor-to-world rotation matrix column by column) and one
  line per sample; `xsens/mappings.xml` is OpenSim's `XsensDataReaderSettings` (trial prefix,
  sensor id to model IMU name);
- APDM exports (`apdm/`): one comma-separated `.csv` per trial in APDM's older layout (`Test
  Name:`, `Sample Rate:` lines, a label line `Time,<Sensor>/Acceleration/X,...,
  <Sensor>/Orientation/Scalar,<Sensor>/Orientation/X,...`, a units line, then samples);
  `apdm/mappings.xml` is OpenSim's `APDMDataReaderSettings` (APDM sensor label to model IMU
  name).
Then OpenSim 4.6's `XsensDataReader` and `APDMDataReader` read them with those settings and
`STOFileAdapter` writes their orientation tables (`*_opensim.sto`): what OpenSense would take.

    pip install opensim      # OpenSim 4.6's Python package
    python3 scripts/imu_vendor_files.py [--shared ../shared] [--out host/tests/data/imu/vendor]
"""

import argparse
import math
import os

import opensim as osim

# Model IMU name, Xsens id, APDM label.
SENSORS = [
    ("pelvis_imu", "00B421AF", "Lumbar"),
    ("femur_r_imu", "00B4227B", "Right Thigh"),
    ("tibia_r_imu", "00B42268", "Right Shank"),
    ("calcn_r_imu", "00B421ED", "Right Foot"),
    ("femur_l_imu", "00B421EE", "Left Thigh"),
    ("tibia_l_imu", "00B42263", "Left Shank"),
    ("calcn_l_imu", "00B421E5", "Left Foot"),
    ("torso_imu", "00B421D3", "Sternum"),
]


def read_sto(path):
    with open(path) as f:
        lines = f.read().splitlines()
    end = next(i for i, l in enumerate(lines) if l.strip() == "endheader")
    names = lines[end + 1].split("\t")
    rows = []
    for l in lines[end + 2:]:
        if not l.strip():
            continue
        cells = l.split("\t")
        rows.append({n: [float(v) for v in c.split(",")] for n, c in zip(names[1:], cells[1:])})
    return rows


def matrix(q):
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def write_xsens(folder, prefix, rows):
    labels = ["PacketCounter", "SampleTimeFine", "Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y",
              "Gyr_Z", "Mag_X", "Mag_Y", "Mag_Z"]
    labels += [f"Mat[{r}][{c}]" for c in (1, 2, 3) for r in (1, 2, 3)]
    for name, sensor_id, _ in SENSORS:
        with open(os.path.join(folder, f"{prefix}_{sensor_id}.txt"), "w", newline="\n") as f:
            f.write("// Start Time: Unknown\n// Update Rate: 100.0Hz\n")
            f.write("// Filter Profile: human (46.1)\n// Option Flags: AHS Disabled ICC Disabled\n")
            f.write("// Firmware Version: 4.0.2\n")
            f.write("\t".join(labels) + "\n")
            for k, row in enumerate(rows):
                m = matrix(row[name])
                cells = [str(k), str(10000 * k), "0.1", "0.2", "9.81", "0.0", "0.0", "0.0",
                         "0.5", "0.1", "-0.8"]
                cells += [repr(m[r][c]) for c in range(3) for r in range(3)]
                f.write("\t".join(cells) + "\n")


def write_apdm(path, trial, rows):
    labels = ["Time"]
    units = ["s"]
    for _, _, label in SENSORS:
        for kind, unit in [("Acceleration", "m/s^2"), ("Angular Velocity", "rad/s"),
                           ("Magnetic Field", "uT")]:
            labels += [f"{label}/{kind}/{a}" for a in "XYZ"]
            units += [unit] * 3
        labels += [f"{label}/Orientation/{a}" for a in ["Scalar", "X", "Y", "Z"]]
        units += ["", "", "", ""]
    width = len(labels)
    with open(path, "w", newline="\n") as f:
        f.write(",".join([f"Test Name:", trial] + [""] * (width - 2)) + "\n")
        f.write(",".join(["Sample Rate:", "100.000000", "Hz"] + [""] * (width - 3)) + "\n")
        f.write(",".join(labels) + "\n")
        f.write(",".join(units) + "\n")
        for k, row in enumerate(rows):
            cells = [repr(k / 100.0)]
            for name, _, _ in SENSORS:
                cells += ["0.1", "0.2", "9.81", "0.0", "0.0", "0.0", "20.0", "5.0", "-40.0"]
                cells += [repr(v) for v in row[name]]
            f.write(",".join(cells) + "\n")


def mappings(settings, xml, prefix=None):
    if prefix is not None:
        settings.set_trial_prefix(prefix)
    for name, sensor_id, label in SENSORS:
        key = f"_{sensor_id}" if prefix is not None else label
        settings.append_ExperimentalSensors(osim.ExperimentalSensor(key, name))
    settings.printToXML(xml)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--shared", default=os.path.join(here, "..", "..", "shared"))
    parser.add_argument("--out", default=os.path.join(here, "..", "host", "tests", "data",
                                                      "imu", "vendor"))
    args = parser.parse_args()
    imu = os.path.join(args.shared, "data", "imu")
    static = read_sto(os.path.join(imu, "placement_orientations.sto"))
    walk = read_sto(os.path.join(imu, "walking_orientations.sto"))[600:700]
    osim.Logger.setLevelString("error")
    xsens = os.path.join(args.out, "xsens")
    apdm = os.path.join(args.out, "apdm")
    os.makedirs(xsens, exist_ok=True)
    os.makedirs(apdm, exist_ok=True)
    trials = [("static", static), ("walk", walk)]
    for trial, rows in trials:
        write_xsens(xsens, f"{trial}-000", rows)
        write_apdm(os.path.join(apdm, f"{trial}.csv"), trial, rows)
    mappings(osim.XsensDataReaderSettings(), os.path.join(xsens, "mappings.xml"), "walk-000")
    mappings(osim.APDMDataReaderSettings(), os.path.join(apdm, "mappings.xml"))
    for trial, _ in trials:
        settings = osim.XsensDataReaderSettings(os.path.join(xsens, "mappings.xml"))
        settings.set_trial_prefix(f"{trial}-000")
        reader = osim.XsensDataReader(settings)
        tables = reader.read(xsens + os.sep)
        table = reader.getOrientationsTable(tables)
        osim.STOFileAdapterQuaternion.write(table, os.path.join(args.out,
                                                                f"xsens_{trial}_opensim.sto"))
        settings = osim.APDMDataReaderSettings(os.path.join(apdm, "mappings.xml"))
        reader = osim.APDMDataReader(settings)
        tables = reader.read(os.path.join(apdm, f"{trial}.csv"))
        table = reader.getOrientationsTable(tables)
        osim.STOFileAdapterQuaternion.write(table, os.path.join(args.out,
                                                                f"apdm_{trial}_opensim.sto"))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
