"""OpenSense's IMU inverse kinematics per frame on the tutorial's walking recording, timed.

The host-cost comparison of BENCHMARKS.md ("Host: the IMU path beside OpenSense"): OpenSim 4.6's
IMUPlacer then IMUInverseKinematicsTool on `../shared/data/imu/` with the gait2392 model and the
tutorial's settings (base IMU `torso_imu`, heading axis `z`, sensor-to-OpenSim (-pi/2, 0, 0)),
over the first 12 s (1,201 frames); the IK run is timed with a wall clock, `--runs` times, and
the median per frame printed as `opensense_ik_ms_per_frame VALUE`.

    pip install opensim            # OpenSim 4.6's Python package
    python3 scripts/opensense_ik_timing.py [--shared ../shared] [--runs 3]
"""

import argparse
import os
import shutil
import statistics
import tempfile
import time

import opensim as osim


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--shared", default=os.path.join(here, "..", "..", "shared"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--end", type=float, default=12.0)
    args = parser.parse_args()
    imu = os.path.join(args.shared, "data", "imu")
    model_file = os.path.join(args.shared, "data", "opensim", "gait2392_simbody.osim")
    work = tempfile.mkdtemp(prefix="opensense-timing-")
    osim.Logger.setLevelString("error")
    rotations = osim.Vec3(-1.5707963267948966, 0, 0)

    placer = osim.IMUPlacer()
    placer.set_model_file(model_file)
    placer.set_orientation_file_for_calibration(os.path.join(imu, "placement_orientations.sto"))
    placer.set_sensor_to_opensim_rotations(rotations)
    placer.set_base_imu_label("torso_imu")
    placer.set_base_heading_axis("z")
    calibrated = os.path.join(work, "calibrated.osim")
    placer.set_output_model_file(calibrated)
    placer.run(False)

    per_frame = []
    frames = None
    for run in range(args.runs):
        ik = osim.IMUInverseKinematicsTool()
        ik.set_model_file(calibrated)
        ik.set_orientations_file(os.path.join(imu, "walking_orientations.sto"))
        ik.set_sensor_to_opensim_rotations(rotations)
        ik.set_time_range(0, 0.0)
        ik.set_time_range(1, args.end)
        ik.set_results_directory(work)
        ik.set_output_motion_file(os.path.join(work, f"ik{run}.mot"))
        start = time.perf_counter()
        ik.run(False)
        seconds = time.perf_counter() - start
        if frames is None:
            frames = osim.TimeSeriesTable(os.path.join(work, f"ik{run}.mot")).getNumRows()
        per_frame.append(seconds / frames * 1e3)
        print(f"run {run + 1}: {frames} frames in {seconds:.2f} s, {per_frame[-1]:.2f} ms per frame")
    shutil.rmtree(work, ignore_errors=True)
    print(f"opensense_ik_ms_per_frame {statistics.median(per_frame):.3f}")


if __name__ == "__main__":
    main()
