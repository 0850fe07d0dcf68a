#!/usr/bin/env python3
"""OpenSim 4.6's velocities, accelerations and IMU signals of an analytic motion, written as
fixtures for the kernel's differential kinematics (crates/qgait-kernel/tests/derivatives.rs,
gait2392) and the host's (host/tests/derivatives_opensim.rs, Rajagopal 2015 imported).

Usage: python3 scripts/opensim_derivatives.py [SHARED_OPENSIM_DIR] [OUT_DIR]
(defaults: ../shared/data/opensim and crates/qgait-kernel/tests/data/derivatives, from the
repo root).

The motion (per model): every one of the 17 gait2392 coordinates and the three pelvis
translations is `c + A1 sin(2 pi f1 t + p1) + A2 sin(2 pi f2 t + p2)` (radians or metres,
PARAMETERS below; Rajagopal's knee flexion is positive, so its knee offsets are negated), so q,
q' and q'' are known exactly; a coordinate the model locks (Rajagopal2015_opensense's subtalar
and MTP joints) stays at its default with zero speed. Every other coordinate of the model stays at its default with
zero speed (the patella's coupled coordinate too: the patella is not part of the output). In
OpenSim's state: `Coordinate.setValue(state, q, False)` (no clamping, no constraint
projection), `Coordinate.setSpeedValue(state, q')` (every coordinate here is a `CustomJoint` or
`PinJoint` coordinate, whose generalised speed is its coordinate's time derivative), then
`realizeVelocity`.

Outputs, per model (`gait2392`, `rajagopal2015`):
- `<model>_parameters.csv`: `coordinate,c,a1,f1,p1,a2,f2,p2`: the motion itself, so a test
  can sample it at any rate (100 Hz, 1 kHz) and know the exact derivatives.
- `<model>.mot`: the motion at 1 kHz over [0, SPAN] s, degrees for rotations (metres for the
  translations), as OpenSim's coordinate files; `<model>_states.sto`: the same rows as an
  OpenSim 4 states file in radians with the exact speeds (`/jointset/<joint>/<coord>/value` and
  `/speed` columns), each printed with 12 significant digits.
- `<model>_reference.csv`: at the REFERENCE_TIMES, with every number printed with repr (exact
  f64): `time`; per coordinate (the 17 in gait2392 order, then `pelvis_tx,ty,tz`) `q_<c>`,
  `qd_<c>`, `qdd_<c>`; per output point (POINTS, qgait's: per side `hip`, `knee`, `ankle`,
  `subtalar`, `mtp`, the origin of the child frame of the joint that moves femur, tibia,
  talus, calcaneus, toes, and `toetip`: marker `R.Toe.Tip`/`L.Toe.Tip` if the model has one,
  else gait2392's toe tip in `toes_<s>` scaled by the toes' geometry scale factors, as
  scripts/opensim_reference.py defines them) its
  velocity `<p>_v{x,y,z}` and acceleration `<p>_a{x,y,z}` in ground (m/s, m/s^2: with the
  pelvis translation's); per body (pelvis, then femur, tibia, talus, calcn, toes per side r
  then l) its angular velocity `<b>_w{x,y,z}` and angular acceleration `<b>_dw{x,y,z}` in
  ground, expressed in ground (rad/s, rad/s^2); per IMU of IMUS (an OpenSim `IMU` component on
  a `PhysicalOffsetFrame` of its body, translation and body-fixed X-Y-Z orientation as given)
  `<imu>_gyro_{x,y,z}`: `IMU.calcGyroscopeSignal` (the IMU frame's angular velocity in ground,
  expressed in the IMU frame, rad/s), `<imu>_acc_{x,y,z}`: the accelerometer (the IMU origin's
  acceleration in ground minus gravity (0, -9.80665, 0), expressed in the IMU frame, m/s^2) and
  `<imu>_q{w,x,y,z}`: the IMU frame's orientation in ground (its rotation matrix in ground as a
  unit quaternion, w >= 0: what `IMU.calcOrientationAsQuaternion` reports).

Accelerations (points, angular, accelerometer) are differences of OpenSim's exact velocities,
not OpenSim's acceleration stage (which would take the accelerations from forward dynamics, and
whose walker-knee accelerations in 4.6 drop a term): the five-point central difference
`(v(t-2h) - 8 v(t-h) + 8 v(t+h) - v(t+2h)) / 12h` with h = STEP (1e-5 s), velocities from the
analytic q(t +- k h), q'(t +- k h). Its error is estimated by the same stencil at 2h: the
largest difference of the two is printed: about 1e-9 (m/s^2, rad/s^2) where the motion is
smooth (truncation ~ h^4, rounding ~ 1e-16 / h), more where a stencil straddles a knot of a
knee spline (the spline's third derivative jumps there, so the error is ~ h times the jump). The script also checks OpenSim's own IMU outputs against the frames'
quantities at a state realised to accelerations (gyroscope = R_GI^T omega_GI, accelerometer =
R_GI^T (a_GI - g)) and prints the largest difference: the frames stated above are OpenSim's.
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
    "pelvis_tx", "pelvis_ty", "pelvis_tz",
]
# c, (a1, f1 Hz, p1), (a2, f2 Hz, p2): gait-like ranges and speeds (up to ~5 rad/s).
PARAMETERS = {
    "pelvis_tilt": (-0.05, (0.10, 1.9, 0.3), (0.03, 3.7, 1.1)),
    "pelvis_list": (0.02, (0.08, 0.95, 1.4), (0.02, 2.9, 0.2)),
    "pelvis_rotation": (0.1, (0.15, 0.95, 2.0), (0.04, 2.1, 0.7)),
    "hip_flexion_r": (0.2, (0.50, 0.95, 0.0), (0.08, 2.8, 0.9)),
    "hip_adduction_r": (0.0, (0.12, 1.9, 0.5), (0.03, 3.1, 2.2)),
    "hip_rotation_r": (0.05, (0.15, 0.95, 1.2), (0.05, 2.3, 0.4)),
    "knee_angle_r": (-0.7, (0.55, 0.95, 2.4), (0.10, 1.9, 0.8)),
    "ankle_angle_r": (0.05, (0.25, 0.95, 0.6), (0.08, 2.6, 1.7)),
    "subtalar_angle_r": (0.05, (0.15, 1.4, 0.9), (0.04, 3.3, 0.1)),
    "mtp_angle_r": (0.1, (0.30, 0.95, 1.9), (0.06, 2.7, 2.6)),
    "hip_flexion_l": (0.15, (0.45, 0.95, 3.2), (0.07, 2.6, 1.5)),
    "hip_adduction_l": (-0.02, (0.10, 1.9, 2.9), (0.03, 3.4, 0.6)),
    "hip_rotation_l": (-0.05, (0.12, 0.95, 0.2), (0.05, 2.2, 1.3)),
    "knee_angle_l": (-0.75, (0.50, 0.95, 5.5), (0.12, 2.1, 0.3)),
    "ankle_angle_l": (0.0, (0.22, 0.95, 3.9), (0.07, 2.4, 2.1)),
    "subtalar_angle_l": (-0.03, (0.12, 1.3, 1.8), (0.05, 3.0, 0.4)),
    "mtp_angle_l": (0.12, (0.28, 0.95, 4.6), (0.05, 2.9, 1.0)),
    "pelvis_tx": (0.0, (0.60, 0.5, 0.0), (0.02, 1.9, 0.5)),
    "pelvis_ty": (0.93, (0.02, 1.9, 1.0), (0.005, 3.8, 0.2)),
    "pelvis_tz": (0.01, (0.03, 0.95, 0.4), (0.01, 1.9, 1.2)),
}
POINTS = ["hip", "knee", "ankle", "subtalar", "mtp", "toetip"]
JOINT_BODIES = ["femur", "tibia", "talus", "calcn", "toes"]
BODIES = ["pelvis"] + [f"{b}_{s}" for s in "rl" for b in JOINT_BODIES]
# name, body, translation in the body (m), body-fixed X-Y-Z orientation (rad).
IMUS = [
    ("pelvis_imu", "pelvis", (-0.14, 0.03, 0.0), (0.51, -0.70, 0.40)),
    ("femur_r_imu", "femur_r", (0.02, -0.20, 0.06), (0.10, 0.30, -0.20)),
    ("tibia_l_imu", "tibia_l", (0.03, -0.15, -0.05), (-0.30, 0.20, 0.60)),
    ("calcn_r_imu", "calcn_r", (0.10, 0.05, 0.0), (1.20, -0.40, 0.30)),
]
MODELS = [
    ("gait2392", "gait2392_simbody.osim"),
    ("rajagopal2015", "Rajagopal2015_opensense.osim"),
]
GRAVITY = (0.0, -9.80665, 0.0)
RATE = 1000.0
SPAN = 0.1
STEP = 1e-5
REFERENCE_TIMES = [0.02 * k for k in range(6)] + [0.2 * k for k in range(1, 11)]


def parameters(knee_positive):
    out = {}
    for c, (c0, t1, t2) in PARAMETERS.items():
        if knee_positive and c.startswith("knee_angle"):
            c0 = -c0
        out[c] = (c0, t1, t2)
    return out


def motion(params, c, t):
    """q, q', q'' of coordinate c at t."""
    c0, *terms = params[c]
    q, qd, qdd = c0, 0.0, 0.0
    for a, f, p in terms:
        w = 2.0 * math.pi * f
        s, co = math.sin(w * t + p), math.cos(w * t + p)
        q += a * s
        qd += a * w * co
        qdd -= a * w * w * s
    return q, qd, qdd


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
    # A scaled model: its scale tool multiplied the toes' geometry scale factors by the body's
    # scale factors; the generic toe tip is scaled the same way (1 when absent).
    k = [1.0, 1.0, 1.0]
    if toes.getPropertyByName("attached_geometry").size() > 0:
        f = toes.get_attached_geometry(0).get_scale_factors()
        k = [f.get(i) for i in range(3)]
    return toes, osim.Vec3(0.0812 * k[0], 0.007 * k[1], z * k[2])


def vec(v):
    return [v.get(k) for k in range(3)]


def transpose_times(rotation, v):
    """R^T v for a SimTK Rotation."""
    return [sum(rotation.get(i, k) * v[i] for i in range(3)) for k in range(3)]


def quaternion(rotation):
    """The unit quaternion (w >= 0) of a SimTK Rotation (Shepperd's method)."""
    m = [[rotation.get(i, j) for j in range(3)] for i in range(3)]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > max(m[0][0], m[1][1], m[2][2]):
        w = 0.5 * math.sqrt(1.0 + trace)
        q = [w, (m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w),
             (m[1][0] - m[0][1]) / (4 * w)]
    else:
        i = max(range(3), key=lambda k: m[k][k])
        j, k = (i + 1) % 3, (i + 2) % 3
        r = 0.5 * math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
        v = [0.0, 0.0, 0.0]
        v[i] = r
        v[j] = (m[j][i] + m[i][j]) / (4 * r)
        v[k] = (m[k][i] + m[i][k]) / (4 * r)
        q = [(m[k][j] - m[j][k]) / (4 * r)] + v
    if q[0] < 0:
        q = [-x for x in q]
    return q


class Probe:
    def __init__(self, path):
        self.model = osim.Model(path)
        self.imus = []
        for name, body, t, o in IMUS:
            frame = osim.PhysicalOffsetFrame(f"{name}_frame", self.model.getBodySet().get(body),
                                             osim.Transform(osim.Rotation(
                                                 osim.BodyRotationSequence,
                                                 o[0], osim.CoordinateAxis(0),
                                                 o[1], osim.CoordinateAxis(1),
                                                 o[2], osim.CoordinateAxis(2)),
                                                 osim.Vec3(*t)))
            self.model.getBodySet().get(body).addComponent(frame)
            imu = osim.IMU()
            imu.setName(name)
            imu.connectSocket_frame(frame)
            self.model.addModelComponent(imu)
            self.imus.append((name, frame, imu))
        self.state = self.model.initSystem()
        coords = self.model.getCoordinateSet()
        self.coords = coords
        self.knee_positive = coords.get("knee_angle_r").getRangeMax() > 1.0
        self.params = parameters(self.knee_positive)
        # A locked coordinate (Rajagopal2015_opensense's subtalar and MTP) stays at its
        # default, not moving.
        self.locked = [c for c in COORDINATES if coords.get(c).getDefaultLocked()]
        for c in self.locked:
            self.params[c] = (coords.get(c).getDefaultValue(), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        self.frames = []
        for s in "rl":
            for point, body in zip(POINTS, JOINT_BODIES):
                self.frames.append((f"{point}_{s}", joint_of(self.model, f"{body}_{s}")
                                    .getChildFrame(), None))
            frame, loc = toe_tip(self.model, s)
            self.frames.append((f"toetip_{s}", frame, loc))
        self.bodies = [self.model.getBodySet().get(b) for b in BODIES]
        self.changed = 0

    def set(self, t):
        state = self.state
        for i in range(self.coords.getSize()):
            c = self.coords.get(i)
            c.setValue(state, c.getDefaultValue(), False)
            c.setSpeedValue(state, 0.0)
        for c in COORDINATES:
            q, qd, _ = motion(self.params, c, t)
            coord = self.coords.get(c)
            coord.setValue(state, q, False)
            coord.setSpeedValue(state, qd)
            if coord.getValue(state) != q or coord.getSpeedValue(state) != qd:
                self.changed += 1
        self.model.realizeVelocity(state)

    def velocities(self, t):
        """Every velocity the reference differentiates, flat: points, bodies' angular, IMUs'
        origins (ground)."""
        self.set(t)
        s = self.state
        out = []
        for _, frame, loc in self.frames:
            v = frame.getLinearVelocityInGround(s) if loc is None else \
                frame.findStationVelocityInGround(s, loc)
            out += vec(v)
        for b in self.bodies:
            out += vec(b.getAngularVelocityInGround(s))
        for _, frame, _ in self.imus:
            out += vec(frame.getLinearVelocityInGround(s))
        return out

    def derivative(self, t, h):
        vm2, vm1, vp1, vp2 = (self.velocities(t + k * h) for k in (-2, -1, 1, 2))
        return [(a - 8 * b + 8 * c - d) / (12 * h) for a, b, c, d in zip(vm2, vm1, vp1, vp2)]

    def row(self, t):
        acc = self.derivative(t, STEP)
        coarse = self.derivative(t, 2 * STEP)
        error = max(abs(a - b) for a, b in zip(acc, coarse))
        v = self.velocities(t)
        s = self.state
        out = [t]
        for c in COORDINATES:
            out += list(motion(self.params, c, t))
        n = len(self.frames)
        for k in range(n):
            out += v[3 * k:3 * k + 3] + acc[3 * k:3 * k + 3]
        for k in range(len(self.bodies)):
            i = 3 * (n + k)
            out += v[i:i + 3] + acc[i:i + 3]
        m = n + len(self.bodies)
        for k, (_, frame, imu) in enumerate(self.imus):
            gyro = vec(imu.calcGyroscopeSignal(s))
            rotation = frame.getTransformInGround(s).R()
            a = acc[3 * (m + k):3 * (m + k) + 3]
            specific = transpose_times(rotation, [a[i] - GRAVITY[i] for i in range(3)])
            out += gyro + specific + quaternion(rotation)
        return out, error

    def header(self):
        h = ["time"]
        for c in COORDINATES:
            h += [f"q_{c}", f"qd_{c}", f"qdd_{c}"]
        for p, _, _ in self.frames:
            h += [f"{p}_v{a}" for a in "xyz"] + [f"{p}_a{a}" for a in "xyz"]
        for b in BODIES:
            h += [f"{b}_w{a}" for a in "xyz"] + [f"{b}_dw{a}" for a in "xyz"]
        for name, _, _ in self.imus:
            h += [f"{name}_gyro_{a}" for a in "xyz"] + [f"{name}_acc_{a}" for a in "xyz"]
            h += [f"{name}_q{a}" for a in "wxyz"]
        return h

    def check_imu_frames(self):
        """OpenSim's IMU outputs against the frames' quantities, at a state realised to
        accelerations (forward dynamics' accelerations: any will do for the check)."""
        self.set(0.37)
        s = self.state
        self.model.realizeAcceleration(s)
        worst = 0.0
        for _, frame, imu in self.imus:
            rotation = frame.getTransformInGround(s).R()
            w = transpose_times(rotation, vec(frame.getAngularVelocityInGround(s)))
            a = vec(frame.getLinearAccelerationInGround(s))
            f = transpose_times(rotation, [a[i] - GRAVITY[i] for i in range(3)])
            worst = max(worst, *(abs(x - y) for x, y in zip(w, vec(imu.calcGyroscopeSignal(s)))))
            worst = max(worst,
                        *(abs(x - y) for x, y in zip(f, vec(imu.calcAccelerometerSignal(s)))))
        g = vec(self.model.getGravity())
        assert g == list(GRAVITY), g
        return worst


def joint_path(model, c):
    return model.getCoordinateSet().get(c).getJoint().getName()


def write_motion(probe, name, out_dir):
    n = int(round(SPAN * RATE)) + 1
    times = [k / RATE for k in range(n)]
    rotational = [c for c in COORDINATES if c not in ("pelvis_tx", "pelvis_ty", "pelvis_tz")]
    lines = [f"{name}_analytic", "version=1", f"nRows={n}", f"nColumns={1 + len(COORDINATES)}",
             "inDegrees=yes", "endheader", "\t".join(["time"] + COORDINATES)]
    for t in times:
        row = [f"{t:.3f}"]
        for c in COORDINATES:
            q = motion(probe.params, c, t)[0]
            row.append(f"{math.degrees(q) if c in rotational else q:.12g}")
        lines.append("\t".join(row))
    with open(os.path.join(out_dir, f"{name}.mot"), "w") as f:
        f.write("\n".join(lines) + "\n")
    columns = []
    for c in COORDINATES:
        j = joint_path(probe.model, c)
        columns += [f"/jointset/{j}/{c}/value", f"/jointset/{j}/{c}/speed"]
    lines = [f"{name}_analytic_states", "version=1", f"nRows={n}",
             f"nColumns={1 + len(columns)}", "inDegrees=no", "", "OpenSimVersion=4.6",
             "endheader", "\t".join(["time"] + columns)]
    for t in times:
        row = [f"{t:.3f}"]
        for c in COORDINATES:
            q, qd, _ = motion(probe.params, c, t)
            row += [f"{q:.12g}", f"{qd:.12g}"]
        lines.append("\t".join(row))
    with open(os.path.join(out_dir, f"{name}_states.sto"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out_dir, f"{name}_parameters.csv"), "w") as f:
        f.write("coordinate,c,a1,f1,p1,a2,f2,p2\n")
        for c in COORDINATES:
            c0, (a1, f1, p1), (a2, f2, p2) = probe.params[c]
            f.write(",".join([c] + [repr(v) for v in (c0, a1, f1, p1, a2, f2, p2)]) + "\n")


def main():
    shared = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/opensim"
    out_dir = sys.argv[2] if len(sys.argv) > 2 else "crates/qgait-kernel/tests/data/derivatives"
    os.makedirs(out_dir, exist_ok=True)
    for name, file in MODELS:
        probe = Probe(os.path.join(shared, file))
        lines = [",".join(probe.header())]
        worst_error = 0.0
        for t in REFERENCE_TIMES:
            row, error = probe.row(t)
            worst_error = max(worst_error, error)
            lines.append(",".join(repr(v) for v in row))
        with open(os.path.join(out_dir, f"{name}_reference.csv"), "w") as f:
            f.write("\n".join(lines) + "\n")
        write_motion(probe, name, out_dir)
        imu_check = probe.check_imu_frames()
        print(f"{name}: {len(REFERENCE_TIMES)} rows; values or speeds changed by setValue: "
              f"{probe.changed}; locked (held still): {probe.locked}; largest difference of the acceleration stencils at h and 2h: "
              f"{worst_error:.2e}; OpenSim IMU outputs against the frames' quantities: "
              f"{imu_check:.2e}")


if __name__ == "__main__":
    main()
