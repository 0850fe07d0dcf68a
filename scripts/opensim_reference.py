#!/usr/bin/env python3
"""OpenSim 4.6's joint centres and toe tips of the lower-limb models qgait imports, written as
reference CSVs for crates/qgait-model/tests/opensim_models.rs.

Usage: python3 scripts/opensim_reference.py [SHARED_OPENSIM_DIR] [OUT_DIR]
(defaults: ../shared/data/opensim and crates/qgait-model/tests/data/opensim_reference, from the
repo root).

For every model and motion, one CSV row per motion row:
- `time`, then the 17 gait2392 coordinates (radians, the values set in OpenSim; named as in
  gait2392, which Rajagopal and gait10dof18musc share), then
- `<point>_<side>_{x,y,z}`: points in ground axes with the origin at the pelvis origin (pelvis
  translation removed), metres, printed with repr (exact f64). Points, per side r then l:
  `hip`, `knee`, `ankle`, `subtalar`, `mtp`: the origin of the child frame of the joint that
  moves `femur`, `tibia`, `talus`, `calcn`, `toes` (the joint centre, whatever the joint is
  called; for a weld, the weld's frame); `toetip`: marker `R.Toe.Tip`/`L.Toe.Tip` if the model
  has one, else (0.0812, 0.007, -/+0.00108) in `toes_<s>` (gait2392's toe tip) multiplied axis by
  axis by the toes' first attached geometry's scale factors (a scaled model's body scale).
Every coordinate the motion lacks is at the model's default (translations too: they cancel).
Values are set with `Coordinate.setValue(state, v, False)` (no clamping to the range, no
constraint projection: the coupler-driven patella is not part of the output) and realized to
Position.

Motions:
- `normal`: ../opensim/normal.mot (gait2392 coordinates, degrees). For Rajagopal models, whose
  knee flexion is positive, knee_angle is negated.
- `opensense` (Rajagopal2015_opensense only): OpenSense's own Rajagopal solution of the IMU
  walking recording (../imu/: IMUPlacer on placement_orientations.sto, then
  IMUInverseKinematicsTool on walking_orientations.sto from 0 s to 12 s, the setup files'
  settings), every 10th row: a long realistic motion in the model's own coordinates.
- `sweep`: 61 rows, knee flexion from 0.3 rad beyond one end of the model's knee range to 0.3
  rad beyond the other, every other coordinate a different slow sine within +-0.6 rad.

`rajagopal2016_polynomial_knee` is Rajagopal2016.osim with the four spline functions of each
walker knee (rotation2, rotation3, translation1, translation2) replaced by the
`PolynomialFunction`s of KNEE_POLYNOMIALS (the left knee's translation1 inside a
`MultiplierFunction` of scale 1.1), as Rajagopal-Lai-Uhlrich 2023 drives its knee; the model
file is written to a temporary directory, never kept. crates/qgait-model/tests/opensim_models.rs makes the
same model from the same numbers by its own text edit.
"""
import math
import os
import sys

import opensim as osim

COORDINATES = [
    "pelvis_tilt", "pelvis_list", "pelvis_rotation",
    "hip_flexion_r", "hip_adduction_r", "hip_rotation_r", "knee_angle_r", "ankle_angle_r",
    "subtalar_angle_r", "mtp_angle_r",
    "hip_flexion_l", "hip_adduction_l", "hip_rotation_l", "knee_angle_l", "ankle_angle_l",
    "subtalar_angle_l", "mtp_angle_l",
]
BODIES = [("hip", "femur"), ("knee", "tibia"), ("ankle", "talus"), ("subtalar", "calcn"),
          ("mtp", "toes")]
MODELS = [
    ("gait2392", "gait2392_simbody.osim"),
    ("gait2354", "gait2354_simbody.osim"),
    ("gait10dof18musc", "gait10dof18musc.osim"),
    ("rajagopal2016", "Rajagopal2016.osim"),
    ("rajagopal2015_opensense", "Rajagopal2015_opensense.osim"),
]


# Coefficients, highest power first, by walker-knee transform axis.
KNEE_POLYNOMIALS = {
    "rotation2": [0.004, -0.02, -0.01, 0.07, 0.0],
    "rotation3": [0.0, 0.02, -0.12, 0.33, 0.0],
    "translation1": [0.0, 0.0004, -0.0019, 0.0029, 0.0],
    "translation2": [0.0001, -0.0006, 0.0001, 0.0055, 0.0],
}
KNEE_MULTIPLIED = ("walker_knee_l", "translation1", 1.1)


def polynomial_knee(path, out_path):
    """Writes the model at path with its walker knees driven by KNEE_POLYNOMIALS."""
    import xml.etree.ElementTree as ET
    tree = ET.parse(path)
    for joint in tree.iter("CustomJoint"):
        if joint.get("name") not in ("walker_knee_r", "walker_knee_l"):
            continue
        for axis in joint.iter("TransformAxis"):
            c = KNEE_POLYNOMIALS.get(axis.get("name"))
            if c is None:
                continue
            spline = axis.find("SimmSpline")
            index = list(axis).index(spline)
            axis.remove(spline)
            poly = ET.Element("PolynomialFunction", {"name": "function"})
            ET.SubElement(poly, "coefficients").text = " ".join(repr(v) for v in c)
            joint_name, axis_name, scale = KNEE_MULTIPLIED
            if (joint.get("name"), axis.get("name")) == (joint_name, axis_name):
                wrapped = ET.Element("MultiplierFunction", {"name": "function"})
                ET.SubElement(wrapped, "function").append(poly)
                ET.SubElement(wrapped, "scale").text = repr(scale)
                poly = wrapped
            axis.insert(index, poly)
    tree.write(out_path)


def read_mot(path):
    with open(path) as f:
        lines = f.read().splitlines()
    end = next(i for i, l in enumerate(lines) if l.strip() == "endheader")
    degrees = any(l.replace(" ", "") == "inDegrees=yes" for l in lines[:end])
    names = lines[end + 1].split()
    rows = [[float(v) for v in l.split()] for l in lines[end + 2:] if l.strip()]
    out = []
    for r in rows:
        values = {}
        for n, v in zip(names[1:], r[1:]):
            if n in COORDINATES:
                values[n] = math.radians(v) if degrees else v
        out.append((r[0], values))
    return out


def opensense_rajagopal(model_path, imu_dir):
    """OpenSense's IK of the IMU walking recording with the model at model_path."""
    import shutil
    import tempfile
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        for f in ["placement_orientations.sto", "walking_orientations.sto"]:
            shutil.copy(os.path.join(imu_dir, f), tmp)
        os.chdir(tmp)
        try:
            rotation = osim.Vec3(-math.pi / 2, 0, 0)
            placer = osim.IMUPlacer()
            placer.set_model_file(os.path.abspath(os.path.join(cwd, model_path)))
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
            # From the start (the calibration pose's neighbourhood): IK started later assembles
            # from the default pose into a wrong branch (pelvis angles of thousands of radians).
            ik.set_time_range(0, 0)
            ik.set_time_range(1, 12)
            ik.set_results_directory(".")
            ik.run(False)
            rows = read_mot("ik_walking_orientations.mot")
        finally:
            os.chdir(cwd)
    return rows[::10]


def knee_positive(model):
    return model.getCoordinateSet().get("knee_angle_r").getRangeMax() > 1.0


def sweep(model):
    lo = model.getCoordinateSet().get("knee_angle_r").getRangeMin()
    hi = model.getCoordinateSet().get("knee_angle_r").getRangeMax()
    rows = []
    n = 61
    for k in range(n):
        t = k / (n - 1)
        values = {}
        for i, c in enumerate(COORDINATES):
            values[c] = 0.6 * math.sin(0.7 * (i + 1) * 2 * math.pi * t + i)
        knee = (lo - 0.3) + t * (hi - lo + 0.6)
        values["knee_angle_r"] = knee
        values["knee_angle_l"] = (hi + 0.3) - t * (hi - lo + 0.6)
        rows.append((t, values))
    return rows


def joint_of(model, body):
    for j in model.getJointSet():
        if j.getChildFrame().findBaseFrame().getName() == body:
            return j
    raise SystemExit(f"{model.getName()}: no joint moves {body}")


def toe_tip(model, s):
    name = "R.Toe.Tip" if s == "r" else "L.Toe.Tip"
    markers = model.getMarkerSet()
    if markers.contains(name):
        m = markers.get(name)
        return m.getParentFrame(), m.get_location()
    z = -0.00108 if s == "r" else 0.00108
    toes = model.getBodySet().get(f"toes_{s}")
    # A scaled model: its scale tool multiplied the toes' geometry scale factors by the
    # body's scale factors; the generic toe tip is scaled the same way (1 when absent).
    k = [1.0, 1.0, 1.0]
    if toes.getPropertyByName("attached_geometry").size() > 0:
        f = toes.get_attached_geometry(0).get_scale_factors()
        k = [f.get(i) for i in range(3)]
    return toes, osim.Vec3(0.0812 * k[0], 0.007 * k[1], z * k[2])


def run(name, path, motions, out_dir):
    model = osim.Model(path)
    state = model.initSystem()
    coords = model.getCoordinateSet()
    present = [c for c in COORDINATES if coords.contains(c)]
    frames = []
    for s in ["r", "l"]:
        for point, body in BODIES:
            frames.append((f"{point}_{s}", joint_of(model, f"{body}_{s}").getChildFrame(), None))
        frame, loc = toe_tip(model, s)
        frames.append((f"toetip_{s}", frame, loc))
    pelvis = model.getBodySet().get("pelvis")
    for motion, rows in motions(model):
        header = ["time"] + COORDINATES + [f"{p}_{a}" for p, _, _ in frames for a in "xyz"]
        lines = [",".join(header)]
        clamped = 0
        for t, values in rows:
            q = []
            for i in range(coords.getSize()):
                c = coords.get(i)
                c.setValue(state, c.getDefaultValue(), False)
            for c in COORDINATES:
                v = values.get(c, 0.0) if c in present else 0.0
                if c in present:
                    coords.get(c).setValue(state, v, False)
                    if coords.get(c).getValue(state) != v:
                        clamped += 1
                else:
                    v = 0.0
                q.append(v)
            model.realizePosition(state)
            origin = pelvis.getPositionInGround(state)
            row = [repr(t)] + [repr(v) for v in q]
            for _, frame, loc in frames:
                p = frame.getPositionInGround(state) if loc is None else \
                    frame.findStationLocationInGround(state, loc)
                row += [repr(p.get(k) - origin.get(k)) for k in range(3)]
            lines.append(",".join(row))
        out = os.path.join(out_dir, f"{name}_{motion}.csv")
        with open(out, "w") as f:
            f.write("\n".join(lines) + "\n")
        absent = [c for c in COORDINATES if c not in present]
        print(f"{out}: {len(rows)} rows; values changed by setValue: {clamped}; "
              f"coordinates the model lacks (written as 0): {absent}")


def main():
    shared = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/opensim"
    out_dir = sys.argv[2] if len(sys.argv) > 2 else "crates/qgait-model/tests/data/opensim_reference"
    os.makedirs(out_dir, exist_ok=True)
    normal = read_mot(os.path.join(shared, "normal.mot"))

    def motions(model):
        rows = normal
        if knee_positive(model):
            rows = [(t, {c: (-v if c.startswith("knee_angle") else v) for c, v in r.items()})
                    for t, r in normal]
        out = [("normal", rows), ("sweep", sweep(model))]
        if model.getName() == "OpenSense_Subject":
            path = os.path.join(shared, "Rajagopal2015_opensense.osim")
            out.append(("opensense", opensense_rajagopal(path, os.path.join(shared, "../imu"))))
        return out

    for name, file in MODELS:
        run(name, os.path.join(shared, file), motions, out_dir)
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "Rajagopal2016_polynomial_knee.osim")
        polynomial_knee(os.path.join(shared, "Rajagopal2016.osim"), path)
        run("rajagopal2016_polynomial_knee", path, motions, out_dir)


if __name__ == "__main__":
    main()
