#!/usr/bin/env python3
"""OpenSense's own joint angles of the tutorial's IMU walking recording with OpenSense's own model
(Rajagopal2015_opensense.osim), for host/tests/imu_chain.rs.

OpenSim 4.6's IMUPlacer on `placement_orientations.sto`, then IMUInverseKinematicsTool on
`walking_orientations.sto` from 0 s to `--end` seconds (default 10), with the tutorial's settings
(base IMU `torso_imu`, heading axis `z`, sensor-to-OpenSim (-pi/2, 0, 0): `imuPlacer_Setup.xml`
in ../shared/data/imu). The model's own coordinate states are kept (its subtalar, MTP and lumbar
coordinates are locked, so OpenSense holds them at 0; its knee flexion is positive). Written: an
OpenSim `.mot` in degrees with `time`, gait2392's 17 coordinate names (which Rajagopal shares)
and the lumbar joint's three, one row per recording row.

    pip install opensim      # OpenSim 4.6's Python package
    python3 scripts/opensense_rajagopal_ik.py [--shared ../shared] [--end 10] [-o OUT.mot]
"""

import argparse
import math
import os
import shutil
import tempfile

import opensim as osim

COLUMNS = [
    "pelvis_tilt", "pelvis_list", "pelvis_rotation",
    "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "ankle_angle_r",
    "subtalar_angle_r", "mtp_angle_r",
    "hip_flexion_l", "hip_adduction_l", "hip_rotation_l", "knee_angle_l", "ankle_angle_l",
    "subtalar_angle_l", "mtp_angle_l",
    "lumbar_extension", "lumbar_bending", "lumbar_rotation",
]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--shared", default=os.path.join(here, "..", "..", "shared"))
    parser.add_argument("--end", type=float, default=10.0)
    parser.add_argument(
        "-o", "--output",
        default=os.path.join(here, "..", "host", "tests", "data", "imu",
                             "walking_rajagopal2015_opensense_0-10s.mot"))
    args = parser.parse_args()
    imu = os.path.abspath(os.path.join(args.shared, "data", "imu"))
    model_file = os.path.abspath(
        os.path.join(args.shared, "data", "opensim", "Rajagopal2015_opensense.osim"))
    output = os.path.abspath(args.output)
    osim.Logger.setLevelString("error")
    rotation = osim.Vec3(-math.pi / 2, 0, 0)
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        for f in ["placement_orientations.sto", "walking_orientations.sto"]:
            shutil.copy(os.path.join(imu, f), tmp)
        os.chdir(tmp)
        try:
            placer = osim.IMUPlacer()
            placer.set_model_file(model_file)
            placer.set_orientation_file_for_calibration("placement_orientations.sto")
            placer.set_sensor_to_opensim_rotations(rotation)
            placer.set_base_imu_label("torso_imu")
            placer.set_base_heading_axis("z")
            placer.run(False)
            placer.getCalibratedModel().printToXML("calibrated.osim")
            ik = osim.IMUInverseKinematicsTool()
            ik.set_model_file("calibrated.osim")
            ik.set_orientations_file("walking_orientations.sto")
            ik.set_sensor_to_opensim_rotations(rotation)
            # From the start: IK started later assembles from the default pose into a wrong
            # branch.
            ik.set_time_range(0, 0)
            ik.set_time_range(1, args.end)
            ik.set_results_directory(".")
            ik.run(False)
            with open("ik_walking_orientations.mot") as f:
                lines = f.read().splitlines()
        finally:
            os.chdir(cwd)
    end = next(i for i, l in enumerate(lines) if l.strip() == "endheader")
    header = lines[:end]
    if not any(l.replace(" ", "") == "inDegrees=yes" for l in header):
        raise SystemExit("OpenSense's output is not in degrees")
    names = lines[end + 1].split("\t")
    names = [n.strip() for n in names]
    index = [names.index(c) for c in ["time"] + COLUMNS]
    rows = [l.split("\t") for l in lines[end + 2:] if l.strip()]
    with open(output, "w") as f:
        f.write("walking_rajagopal2015_opensense\nversion=1\n")
        f.write(f"nRows={len(rows)}\nnColumns={len(index)}\ninDegrees=yes\n")
        f.write("# OpenSim 4.6 OpenSense (IMUPlacer, IMUInverseKinematicsTool) with\n")
        f.write("# Rajagopal2015_opensense.osim on the tutorial's walking recording;\n")
        f.write("# made by scripts/opensense_rajagopal_ik.py\n")
        f.write("endheader\n")
        f.write("\t".join(["time"] + COLUMNS) + "\n")
        for r in rows:
            f.write("\t".join(format(float(r[i]), ".10g") for i in index) + "\n")
    print(f"{output}: {len(rows)} rows")


if __name__ == "__main__":
    main()
