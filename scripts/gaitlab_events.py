#!/usr/bin/env python3
"""Kinematics-only gait events, speed and mode on the gait-lab recordings, scored against
force plates (20 N vertical force, interpolated) and markers (belt speed from foot markers in
mid-stance). Methods and constants: docs/gait-events-methods.md.

Usage: python3 scripts/gaitlab_events.py [DATA_DIR]   (default /work/shared/data/gaitlab)

Needs opensim 4.x (pip), numpy, scipy. Prints the tables the write-up quotes.
"""

import os
import sys

import numpy as np

DATA = sys.argv[1] if len(sys.argv) > 1 else "/work/shared/data/gaitlab"
RECORDINGS = [
    ("walk (subject01)", "subject01_walk1", "subject01_walk1_ik.mot",
     "subject01_simbody.osim", "subject01_walk1_grf.mot", "subject01_walk1.trc"),
    ("run (subject02)", "subject02_running", "subject02_running_ik.mot",
     "subject02_scaled.osim", "subject02_running_grf.mot", "subject02_running.trc"),
]
SIDES = ("r", "l")
FORCE_THRESHOLD = 20.0  # N, the truth's contact threshold (issue 29)

# ---- constants of the methods (reasons in docs/gait-events-methods.md) ----
ZENI_PROMINENCE_FRACTION = 0.3  # qgait's events.rs
ZENI_MIN_PROMINENCE = 0.05  # m, qgait's events.rs
HS_SPEED_FRACTION = 0.78  # Bruening & Ridge 2014: heel sagittal speed < 0.78 v at contact
TO_SPEED_FRACTION = 0.66  # Bruening & Ridge 2014: toe sagittal speed > 0.66 v after toe off
GHOUSSAYNI_SPEED = 0.5  # m/s, Ghoussayni et al. 2004 (as tabulated by Bonci et al. 2022)
RUN_DUTY_FACTOR = 0.5  # Alexander 1989: running is duty factor < 0.5 (a flight phase)
OVERGROUND_RATIO = 0.5  # pelvis travel / foot-derived travel: ~1 overground, ~0 treadmill
FROUDE_TRANSITION = 0.5  # Alexander 1989, Kram et al. 1997: humans change gait near Fr = 0.5
FROUDE_RUN_FLOOR = 0.25  # half of it: no "running" at walking pace (a guard, see the doc)


# --------------------------------------------------------------------------------------------
# File reading
# --------------------------------------------------------------------------------------------
def read_table(path):
    """An OpenSim .mot/.sto (new or legacy header): (column names, N x M array)."""
    with open(path) as f:
        lines = f.read().splitlines()
    end = next(i for i, l in enumerate(lines) if l.strip().lower() == "endheader")
    names = lines[end + 1].split()
    rows = [list(map(float, l.split())) for l in lines[end + 2:] if l.strip()]
    return names, np.array(rows)


def read_trc(path):
    """Marker trajectories (m) by name, and the time column."""
    with open(path) as f:
        lines = f.read().splitlines()
    names = lines[3].split("\t")[2:]
    names = [n for n in names if n.strip()]
    units = lines[2].split("\t")[4].strip()
    scale = 0.001 if units == "mm" else 1.0
    rows = []
    for l in lines[5:]:
        parts = l.split("\t")
        if len(parts) < 2 or not parts[1].strip():
            continue
        rows.append([float(x) if x.strip() else np.nan for x in parts[1:2 + 3 * len(names)]])
    a = np.array(rows)
    t = a[:, 0]
    return t, {n: a[:, 1 + 3 * i:4 + 3 * i] * scale for i, n in enumerate(names)}


# --------------------------------------------------------------------------------------------
# Kinematics with OpenSim: points fixed in the foot segments, in ground
# --------------------------------------------------------------------------------------------
def foot_points(model_path, ik_path):
    """Per frame (ground axes, m): the pelvis origin and, per side, the ankle centre (talus
    origin), subtalar centre (calcn origin, qgait's `heel` today), the heel marker (model's
    `R.Heel`/`L.Heel`, on calcn), the MTP centre (toes origin) and the toe tip (gait2392's
    `Toe.Tip` point in the toes frame, as the kernel's `toetip_in_toes`, scaled with the foot)."""
    import opensim as osim

    model = osim.Model(model_path)
    state = model.initSystem()
    names, data = read_table(ik_path)
    time = data[:, 0]
    coords = model.getCoordinateSet()
    cols = []
    for j, n in enumerate(names[1:], start=1):
        if coords.contains(n):
            c = coords.get(n)
            rot = c.getMotionType() == 1  # Rotational
            cols.append((c, j, rot))
    bodies = {b: model.getBodySet().get(b) for b in
              ["pelvis", "femur_r", "talus_r", "calcn_r", "toes_r", "femur_l", "talus_l", "calcn_l",
               "toes_l"]}
    markers = model.getMarkerSet()
    heel_in_calcn = {}
    for s in SIDES:
        name = ("R" if s == "r" else "L") + ".Heel"
        # a model without the marker set: the calcn origin stands in (the heel marker changed
        # nothing measurable on the gait-lab recordings)
        heel_in_calcn[s] = markers.get(name).get_location() if markers.contains(name) else osim.Vec3(0, 0, 0)
    # the kernel's toe tip: gait2392's Toe.Tip in the toes frame, scaled like the MTP offset
    mtp_generic = 0.1788
    out = {"pelvis": np.zeros((len(time), 3)), "pelvis_forward": np.zeros((len(time), 3))}
    for s in SIDES:
        for p in ("hip", "ankle", "subtalar", "heel", "mtp", "toe"):
            out[f"{p}_{s}"] = np.zeros((len(time), 3))
        out[f"knee_angle_{s}"] = np.radians(data[:, names.index(f"knee_angle_{s}")])
    toe_local = {}
    for s in SIDES:
        mtp_loc = model.getJointSet().get(f"mtp_{s}").get_frames(0).get_translation()
        k = mtp_loc.get(0) / mtp_generic
        z = -0.00108 if s == "r" else 0.00108
        toe_local[s] = osim.Vec3(0.0812 * k, 0.007 * k, z * k)
    for i in range(len(time)):
        for c, j, rot in cols:
            v = data[i, j]
            c.setValue(state, np.radians(v) if rot else v, False)
        model.assemble(state) if False else model.realizePosition(state)

        def at(body, p=osim.Vec3(0, 0, 0)):
            g = bodies[body].findStationLocationInGround(state, p)
            return [g.get(0), g.get(1), g.get(2)]

        out["pelvis"][i] = at("pelvis")
        fwd = bodies["pelvis"].expressVectorInGround(state, osim.Vec3(1, 0, 0))
        out["pelvis_forward"][i] = [fwd.get(0), fwd.get(1), fwd.get(2)]
        for s in SIDES:
            out[f"hip_{s}"][i] = at(f"femur_{s}")
            out[f"ankle_{s}"][i] = at(f"talus_{s}")
            out[f"subtalar_{s}"][i] = at(f"calcn_{s}")
            out[f"heel_{s}"][i] = at(f"calcn_{s}", heel_in_calcn[s])
            out[f"mtp_{s}"][i] = at(f"toes_{s}")
            out[f"toe_{s}"][i] = at(f"toes_{s}", toe_local[s])
    return time, out


# --------------------------------------------------------------------------------------------
# Truth
# --------------------------------------------------------------------------------------------
def crossings(t, y, level, rising):
    """Times where y crosses level (linear interpolation)."""
    out = []
    for i in range(len(y) - 1):
        a, b = y[i] - level, y[i + 1] - level
        if (rising and a < 0 <= b) or (not rising and a >= 0 > b):
            out.append(t[i] + (t[i + 1] - t[i]) * a / (a - b))
    return np.array(out)


def plate_events(grf_path):
    names, d = read_table(grf_path)
    t = d[:, 0]
    ev = {}
    for s, col in (("r", "ground_force_vy"), ("l", "1_ground_force_vy")):
        fy = d[:, names.index(col)]
        ev[s] = (crossings(t, fy, FORCE_THRESHOLD, True), crossings(t, fy, FORCE_THRESHOLD, False))
    return t, ev


def belt_speed(trc_path, plate):
    """Per stance (middle third of the plate's stance), the median backward velocity of the
    heel and toe-tip markers: (times of mid-stance, speeds)."""
    t, m = read_trc(trc_path)
    out = []
    for s in SIDES:
        hs, to = plate[s]
        for h in hs:
            later = to[to > h]
            if not len(later):
                continue
            o = later[0]
            a, b = h + (o - h) / 3, h + 2 * (o - h) / 3
            sel = (t >= a) & (t <= b)
            if sel.sum() < 2 or b > t[-1]:
                continue
            v = []
            for mk in (("R" if s == "r" else "L") + ".Heel", ("R" if s == "r" else "L") + ".Toe.Tip"):
                vx = np.gradient(m[mk][:, 0], t)
                v.append(-np.median(vx[sel]))
            out.append(((a + b) / 2, float(np.mean(v)), v))
    return out


# --------------------------------------------------------------------------------------------
# Signal helpers
# --------------------------------------------------------------------------------------------
def deriv(t, y):
    return np.gradient(y, t, axis=0)


def lowpass(t, y, fc):
    if fc is None:
        return y
    from scipy.signal import butter, filtfilt
    fs = 1.0 / np.median(np.diff(t))
    b, a = butter(2, fc / (fs / 2))  # 2nd order twice (filtfilt) = 4th order zero lag
    return filtfilt(b, a, y, axis=0)


def peaks(t, y, min_prom=None):
    """Local maxima with qgait's prominence rule, refined by the parabola: times."""
    from scipy.signal import find_peaks
    lo, hi = np.percentile(y, [5, 95])
    prom = max(ZENI_PROMINENCE_FRACTION * (hi - lo), ZENI_MIN_PROMINENCE if min_prom is None else min_prom)
    idx, _ = find_peaks(y, prominence=prom)
    return np.array([refine(t, y, i) for i in idx])


def refine(t, y, i):
    if 0 < i < len(y) - 1:
        a, b, c = y[i - 1], y[i], y[i + 1]
        den = a - 2 * b + c
        if den < 0:
            off = np.clip(0.5 * (a - c) / den, -0.5, 0.5)
            return t[i] + off * (t[i + 1] - t[i])
    return t[i]


def local_extremum(t, y, a, b, maximum=True):
    """The largest (or smallest) sample of y within [a, b], parabola-refined; None if at an
    edge of the window (no interior extremum)."""
    sel = np.where((t >= a) & (t <= b))[0]
    if len(sel) < 3:
        return None
    yy = y[sel] if maximum else -y[sel]
    k = int(np.argmax(yy))
    if k == 0 or k == len(sel) - 1:
        return None
    i = sel[k]
    return refine(t, y if maximum else -y, i)


def nearest_extremum(t, y, a, b, anchor, maximum=True):
    """The interior local maximum (or minimum) of y within [a, b] nearest to `anchor`,
    parabola-refined; None if there is none."""
    sel = np.where((t >= a) & (t <= b))[0]
    yy = y if maximum else -y
    cands = [i for i in sel if 0 < i < len(y) - 1 and yy[i] > yy[i - 1] and yy[i] >= yy[i + 1]]
    if not cands:
        return None
    i = min(cands, key=lambda i: abs(t[i] - anchor))
    return refine(t, yy, i)


def first_crossing(t, y, level, start, stop, rising):
    """The first crossing of level by y between times start and stop, going forward (or
    backward when stop < start), linearly interpolated; None if none."""
    idx = np.where((t >= min(start, stop)) & (t <= max(start, stop)))[0]
    if len(idx) < 2:
        return None
    if stop < start:
        idx = idx[::-1]
    for i, j in zip(idx[:-1], idx[1:]):
        a, b = y[i] - level, y[j] - level
        hit = (a < 0 <= b) if rising else (a >= 0 > b)
        if hit:
            return t[i] + (t[j] - t[i]) * a / (a - b)
    return None


# --------------------------------------------------------------------------------------------
# Methods. Each takes the recording's kinematics dict K (built by `signals`) and returns per
# side (heel strikes, toe offs) as arrays of times.
# --------------------------------------------------------------------------------------------
def progression(t, P, window=1.2):
    """The direction of progression per frame, as qgait's events::progression in spirit: the
    horizontal direction the pelvis faces, averaged over `window` s centred on the frame."""
    f = P["pelvis_forward"].copy()
    f[:, 1] = 0
    f /= np.linalg.norm(f, axis=1)[:, None]
    out = np.zeros_like(f)
    for i in range(len(t)):
        sel = np.abs(t - t[i]) <= window / 2
        m = f[sel].mean(axis=0)
        out[i] = m / np.linalg.norm(m)
    return out


def to_heading(v, d):
    """Vectors v (N x 3, ground axes) in the heading frame of directions d: x along d, y up."""
    z = np.cross(d, [0.0, 1.0, 0.0])  # right of the direction of progression
    return np.stack([np.sum(v * d, axis=1), v[:, 1], -np.sum(v * z, axis=1)], axis=1)


def signals(t, P, translation=True, fc=None, heading=False):
    """What a kinematics-only method can use: positions relative to the pelvis origin (the
    kernel's FK frame), their velocities, and, with `translation`, the ground-frame ones.
    With `heading`, the relative ones are expressed along the direction of progression
    (derivatives taken in ground axes, then projected), for recordings that turn."""
    K = {"t": t}
    pel = lowpass(t, P["pelvis"], fc)
    d = progression(t, P) if heading else None
    rot = (lambda v: to_heading(v, d)) if heading else (lambda v: v)
    for s in SIDES:
        for p in ("ankle", "subtalar", "heel", "mtp", "toe"):
            g = lowpass(t, P[f"{p}_{s}"], fc)
            r = g - pel
            vr = deriv(t, r)
            K[f"{p}_{s}_rel"] = rot(r)
            K[f"{p}_{s}_vrel"] = rot(vr)
            K[f"{p}_{s}_arel"] = rot(deriv(t, vr))
            if translation:
                K[f"{p}_{s}"] = g
                K[f"{p}_{s}_v"] = deriv(t, g)
                K[f"{p}_{s}_a"] = deriv(t, K[f"{p}_{s}_v"])
        K[f"knee_angle_{s}"] = P[f"knee_angle_{s}"]
        K[f"hip_{s}_rel"] = rot(P[f"hip_{s}"] - P["pelvis"])
    return K


def zeni(K, heel="subtalar", toe="toe"):
    t = K["t"]
    out = {}
    for s in SIDES:
        hs = peaks(t, K[f"{heel}_{s}_rel"][:, 0])
        to = peaks(t, -K[f"{toe}_{s}_rel"][:, 0])
        out[s] = (hs, to)
    return out


def stride_time(ev):
    d = np.concatenate([np.diff(ev[s][0]) for s in SIDES])
    return float(np.median(d))


def windows(K, base):
    """Search windows per side from the base (Zeni) events: around each heel strike,
    +-0.15 T; for each toe off, from the middle of the preceding stance (midway between the
    Zeni heel strike and Zeni toe off) to 0.1 T after the Zeni toe off. T = median stride."""
    T = stride_time(base)
    out = {}
    for s in SIDES:
        hs, to = base[s]
        hw = [(h - 0.15 * T, h + 0.15 * T, h) for h in hs]
        tw = []
        for o in to:
            prev = hs[hs < o]
            start = (prev[-1] + o) / 2 if len(prev) and o - prev[-1] < T else o - 0.4 * T
            tw.append((start, o + 0.1 * T, o))
        out[s] = (hw, tw)
    return out, T


def foot_centre(K, s, suffix, heel="heel", toe="mtp"):
    return 0.5 * (K[f"{heel}_{s}{suffix}"] + K[f"{toe}_{s}{suffix}"])


def oconnor(K, base, frame="", heel="heel", toe="mtp"):
    """Foot velocity algorithm (O'Connor et al. 2007): foot centre (heel-toe midpoint)
    vertical velocity; heel strike at its minimum (the trough of the descent) and toe off at
    its maximum (the peak of the rise), each in its window. frame "" = ground, "rel" = pelvis."""
    t = K["t"]
    W, T = windows(K, base)
    out = {}
    v = "_v" if frame == "" else "_vrel"
    for s in SIDES:
        vy = foot_centre(K, s, v, heel, toe)[:, 1]
        hs = [nearest_extremum(t, vy, a, b, c, maximum=False) for a, b, c in W[s][0]]
        to = [nearest_extremum(t, vy, a, b, c, maximum=True) for a, b, c in W[s][1]]
        out[s] = (np.array([x for x in hs if x is not None]), np.array([x for x in to if x is not None]))
    return out


def hreljac(K, base, frame="", heel="heel", toe="toe"):
    """Hreljac & Marshall 2000: heel strike at the heel's vertical acceleration maximum, toe off
    at the toe's horizontal (forward) acceleration maximum (jerk zero crossings)."""
    t = K["t"]
    W, T = windows(K, base)
    a = "_a" if frame == "" else "_arel"
    out = {}
    for s in SIDES:
        ay = K[f"{heel}_{s}{a}"][:, 1]
        ax = K[f"{toe}_{s}{a}"][:, 0]
        hs = [nearest_extremum(t, ay, lo, hi, c) for lo, hi, c in W[s][0]]
        to = [nearest_extremum(t, ax, lo, hi, c) for lo, hi, c in W[s][1]]
        out[s] = (np.array([x for x in hs if x is not None]), np.array([x for x in to if x is not None]))
    return out


def mid_stance_speed(K, ev, point="mtp", frame="rel"):
    """Per stance (heel strike to the next toe off of the same side) the median backward
    velocity of `point` relative to the pelvis over the middle third: [(time, speed)]."""
    t = K["t"]
    out = []
    for s in SIDES:
        hs, to = ev[s]
        vx = K[f"{point}_{s}_v{frame}"][:, 0]
        for h in hs:
            later = to[to > h]
            if not len(later):
                continue
            o = later[0]
            a, b = h + (o - h) / 3, h + 2 * (o - h) / 3
            sel = (t >= a) & (t <= b)
            if sel.sum() < 1:
                continue
            out.append(((a + b) / 2, float(-np.median(vx[sel]))))
    return out


def in_stance(ev, s, x):
    """Whether time x is in a stance of side s (between a heel strike and the next toe off),
    and that heel strike's time."""
    hs, to = ev[s]
    prev = hs[hs <= x]
    if not len(prev):
        return False, None
    h = prev[-1]
    nxt = to[to > h]
    return (len(nxt) > 0 and x < nxt[0]), h


def stride_speed(K, ev, point="mtp"):
    """Per stride (heel strike to heel strike of each side): the mean over the stride of the
    backward velocity, relative to the pelvis, of the foot in stance (the trailing one in
    double support: it is the one still rolling on the ground; a stance foot stands still on
    the ground, so this is the pelvis's velocity over the ground, or the belt's on a
    treadmill); in a flight phase (no foot down: running) the pelvis flies at a constant
    horizontal velocity, so the value is interpolated linearly between the toe off and the
    next heel strike. Returns [(mid time, speed)]."""
    t = K["t"]
    out = []
    for s in SIDES:
        hs = ev[s][0]
        for a, b in zip(hs[:-1], hs[1:]):
            sel = np.where((t >= a) & (t <= b))[0]
            v = np.full(len(sel), np.nan)
            for j, i in enumerate(sel):
                best = None
                for q in SIDES:
                    on, h = in_stance(ev, q, t[i])
                    if on and (best is None or h < best[1]):
                        best = (q, h)
                if best is not None:
                    v[j] = -K[f"{point}_{best[0]}_vrel"][i, 0]
            ok = ~np.isnan(v)
            if ok.sum() < 2:
                continue
            v = np.interp(t[sel], t[sel][ok], v[ok])
            out.append(((a + b) / 2, float(np.trapezoid(v, t[sel]) / (t[sel][-1] - t[sel][0]))))
    return out


def handsaker(K, base, frame=""):
    """Handsaker et al. 2016 (running): touchdown at the vertical acceleration peak of the heel
    or the MTP, whichever comes first; toe off at the vertical jerk peak of the toe."""
    t = K["t"]
    W, T = windows(K, base)
    a = "_a" if frame == "" else "_arel"
    out = {}
    for s in SIDES:
        ah = K[f"heel_{s}{a}"][:, 1]
        am = K[f"mtp_{s}{a}"][:, 1]
        jt = deriv(t, K[f"toe_{s}{a}"][:, 1])
        hs = []
        for lo, hi, c in W[s][0]:
            x = [v for v in (nearest_extremum(t, ah, lo, hi, c), nearest_extremum(t, am, lo, hi, c))
                 if v is not None]
            if x:
                hs.append(min(x))
        to = [nearest_extremum(t, jt, lo, hi, c) for lo, hi, c in W[s][1]]
        out[s] = (np.array(hs), np.array([x for x in to if x is not None]))
    return out


def fellin_toe_off(K, base, speed=None):
    """Fellin et al. 2010 (running): toe off at the peak knee extension (the largest
    gait2392 `knee_angle`, 0 = straight, flexion negative) late in stance: between the stance
    core (the frame of least forefoot speed relative to the surface in the half stride before
    the base toe off) and 0.1 T after the base (Zeni) toe off, which in running lags toe off."""
    t = K["t"]
    if speed is None:
        speed = float(np.median([v for _, v in mid_stance_speed(K, base)]))
    T = stride_time(base)
    out = {}
    for s in SIDES:
        um = np.hypot(K[f"mtp_{s}_vrel"][:, 0] + speed, K[f"mtp_{s}_vrel"][:, 1])
        k = K[f"knee_angle_{s}"]
        to = []
        for o in base[s][1]:
            sel = np.where((t >= o - 0.5 * T) & (t <= o))[0]
            if not len(sel):
                continue
            c = t[sel[np.argmin(um[sel])]]
            x = local_extremum(t, k, c, o + 0.1 * T, maximum=True)
            if x is not None:
                to.append(x)
        out[s] = np.array(to)
    return out


def velocity_events(K, base, vertical="rel", horizontal_only=False, hs_frac=HS_SPEED_FRACTION,
                    to_frac=TO_SPEED_FRACTION, heel="heel", toe="toe", speed=None,
                    hs_abs=None, to_abs=None):
    """Foot speed relative to the surface from the kinematics relative to the pelvis:
    u = v_rel + v x (the walker's speed v added back along the direction of progression:
    the pelvis moves forward at v overground; on a treadmill the belt moves back at v), and
    the vertical velocity relative to the pelvis ("rel") or in ground ("ground").
    Heel strike: going back from the stance core (the frame of least forefoot speed between a
    base heel strike and the next base toe off), the last time the heel's sagittal speed was
    above hs_frac * v (Bruening & Ridge 2014: 0.78); toe off: going forward from the core, the
    first time the toe tip's sagittal speed rises above to_frac * v (0.66).
    v: the median over strides of the mid-stance backward foot velocity (base events)."""
    t = K["t"]
    if speed is None:
        speed = float(np.median([v for _, v in mid_stance_speed(K, base)]))
    T = stride_time(base)
    out = {}
    for s in SIDES:

        def sag(p):
            vr = K[f"{p}_{s}_vrel"]
            ux = vr[:, 0] + speed
            if horizontal_only:
                return np.abs(ux)
            vy = vr[:, 1] if vertical == "rel" else K[f"{p}_{s}_v"][:, 1]
            return np.hypot(ux, vy)

        uh, ut, um = sag(heel), sag(toe), sag("mtp")
        hs_b, to_b = base[s]
        lh = hs_abs if hs_abs is not None else hs_frac * speed
        lt = to_abs if to_abs is not None else to_frac * speed

        def core(a, b):
            sel = np.where((t >= a) & (t <= b))[0]
            return t[sel[np.argmin(um[sel])]] if len(sel) else None

        hs, to = [], []
        for h in hs_b:  # the stance core follows the base heel strike by less than T/2
            c = core(h, h + 0.5 * T)
            x = None if c is None else first_crossing(t, uh, lh, c, c - 0.5 * T, rising=True)
            if x is not None and (not hs or x > hs[-1] + 0.5 * T):
                hs.append(x)
        for o in to_b:  # and precedes the base toe off by less than T/2
            c = core(o - 0.5 * T, o)
            y = None if c is None else first_crossing(t, ut, lt, c, c + 0.5 * T, rising=True)
            if y is not None and (not to or y > to[-1] + 0.5 * T):
                to.append(y)
        out[s] = (np.array(hs), np.array(to))
    return out, speed


# --------------------------------------------------------------------------------------------
# Scoring
# --------------------------------------------------------------------------------------------
def score(detected, truth, t0, t1, tol=0.15):
    """Match each true event inside [t0, t1] (kinematics cover it, with a margin) to the
    nearest detected one within tol s: errors (ms, detected - true), missed, false."""
    errs, missed = [], 0
    used = set()
    for e in truth:
        if e < t0 or e > t1:
            continue
        if len(detected) == 0:
            missed += 1
            continue
        k = int(np.argmin(np.abs(detected - e)))
        if abs(detected[k] - e) <= tol and k not in used:
            errs.append(1000 * (detected[k] - e))
            used.add(k)
        else:
            missed += 1
    false = sum(1 for k, d in enumerate(detected) if t0 <= d <= t1 and k not in used)
    return np.array(errs), missed, false


def leg_length(K):
    """Leg length (m): the 95th percentile over the recording of the hip centre's height above
    the lowest foot point of the same leg (the leg is near straight in stance)."""
    ls = []
    for s in SIDES:
        low = np.minimum.reduce([K[f"{p}_{s}_rel"][:, 1] for p in ("subtalar", "mtp", "toe")])
        ls.append(np.percentile(K[f"hip_{s}_rel"][:, 1] - low, 95))
    return float(np.mean(ls))


def stance_points(ev, T_side=None):
    """Per side, stance % of each complete stride: (toe off - heel strike) / stride."""
    out = {}
    for s in SIDES:
        hs, to = ev[s]
        vals = []
        for a, b in zip(hs[:-1], hs[1:]):
            o = to[(to > a) & (to < b)]
            if len(o) == 1:
                vals.append(100 * (o[0] - a) / (b - a))
        out[s] = vals
    return out


def summarise(name, ev, truth, t0, t1, rows):
    line = [name]
    worst_all = 0.0
    for s in SIDES:
        for k, kind in ((0, "HS"), (1, "TO")):
            e, m, f = score(ev[s][k], truth[s][k], t0, t1)
            mean = e.mean() if len(e) else np.nan
            worst = np.abs(e).max() if len(e) else np.nan
            worst_all = max(worst_all, worst if len(e) else 0)
            line.append(f"{kind}_{s} {mean:+6.1f}/{worst:5.1f} n{len(e)} m{m} f{f}")
    st = stance_points(ev)
    stt = stance_points(truth)
    ds = []
    for s in SIDES:
        # compare per-side mean stance over strides within [t0, t1]
        if st[s] and stt[s]:
            ds.append(np.mean(st[s]) - np.mean(stt[s]))
    line.append("stance " + " ".join(f"{d:+.1f}" for d in ds))
    rows.append(line)
    print(" | ".join(line))


def recommended(K):
    """The recommended pipeline (docs/gait-events-methods.md): returns (events, mode, speed,
    first-pass duty factor, Froude number)."""
    base = zeni(K)  # cycle anchors: one heel strike and one toe off per stride
    v0 = float(np.median([v for _, v in mid_stance_speed(K, base)]))
    first, _ = velocity_events(K, base, vertical="rel", heel="subtalar", speed=v0)
    duty = np.mean([x for s in SIDES for x in stance_points(first)[s]]) / 100
    L = leg_length(K)
    mode = "running" if duty < RUN_DUTY_FACTOR and v0 * v0 / (9.81 * L) >= FROUDE_RUN_FLOOR else "walking"
    if mode == "walking":
        v = float(np.median([v for _, v in lowest_point_speed(K, first, ("subtalar", "mtp"))]))
        # Ghoussayni's fixed heel level, Bruening & Ridge's speed-scaled toe level.
        ev, _ = velocity_events(K, base, vertical="rel", heel="subtalar", speed=v,
                                hs_abs=GHOUSSAYNI_SPEED)
    else:
        v = v0
        to = fellin_toe_off(K, base, speed=v)
        ev = {s: (first[s][0], to[s]) for s in SIDES}
    froude = v * v / (9.81 * L)
    return ev, mode, v, duty, froude, L


def imu_check():
    """OpenSense's IMU solution of a real walk (no translation, no markers, no plates): what
    the rules say, for plausibility only."""
    sto = os.path.join(os.path.dirname(DATA.rstrip("/")), "imu", "walking_gait2392_opensense_0-12s.sto")
    osim_file = os.path.join(os.path.dirname(DATA.rstrip("/")), "opensim", "gait2392_simbody.osim")
    if not (os.path.exists(sto) and os.path.exists(osim_file)):
        print("\n(no IMU solution found beside the gait-lab data: skipped)")
        return
    cfile = "/tmp/gaitlab_kin3_imu.npz"
    if os.path.exists(cfile):
        z = np.load(cfile)
        t, P = z["t"], {k: z[k] for k in z.files if k != "t"}
    else:
        t, P = foot_points(osim_file, sto)
        np.savez(cfile, t=t, **P)
    K = signals(t, P, translation=False, heading=True)
    base = zeni(K)
    v0 = float(np.median([v for _, v in mid_stance_speed(K, base)]))
    first, _ = velocity_events(K, base, vertical="rel", heel="subtalar", speed=v0)
    duty1 = np.mean([x for s in SIDES for x in stance_points(first)[s]]) / 100
    ev, mode, v, _, froude, L = recommended(K)
    st = stance_points(ev)
    print(f"\n=== OpenSense IMU solution, walking_gait2392_opensense_0-12s (no truth): first-pass duty "
          f"{duty1:.3f}, mid-stance speed {v0:.3f} m/s, Froude {v0 * v0 / (9.81 * L):.3f} -> {mode}; "
          f"speed {v:.3f} m/s; stride time {stride_time(ev):.2f} s; heel strikes "
          f"{[len(ev[s][0]) for s in SIDES]}, toe offs {[len(ev[s][1]) for s in SIDES]}; stance % "
          f"{[round(x, 1) for x in st['r']]} {[round(x, 1) for x in st['l']]}")


def load():
    """Per recording: (label, IK time, points, GRF time, plate events, belt speeds)."""
    results = {}
    for label, folder, ik, osim_file, grf, trc in RECORDINGS:
        d = os.path.join(DATA, folder)
        cfile = f"/tmp/gaitlab_kin3_{folder}.npz"  # a cache of the OpenSim evaluation
        if os.path.exists(cfile):
            z = np.load(cfile)
            t = z["t"]
            P = {k: z[k] for k in z.files if k != "t"}
        else:
            t, P = foot_points(os.path.join(d, osim_file), os.path.join(d, ik))
            np.savez(cfile, t=t, **P)
        gt, plate = plate_events(os.path.join(d, grf))
        belt = belt_speed(os.path.join(d, trc), plate)
        results[folder] = (label, t, P, gt, plate, belt)
    return results


def duty_and_flight(ev, t0=None, t1=None):
    """Mean stance fraction of the strides (duty factor) and the mean, over steps, of the
    flight time (a toe off to the other foot's next heel strike, when that is positive) as a
    fraction of the stride; the double support is the negative part."""
    st = stance_points(ev)
    duty = np.mean(st["r"] + st["l"]) / 100 if st["r"] + st["l"] else np.nan
    flights = []
    T = stride_time(ev)
    for s, o in ((SIDES[0], SIDES[1]), (SIDES[1], SIDES[0])):
        for x in ev[s][1]:
            near = ev[o][0][np.abs(ev[o][0] - x) < 0.5 * T]  # the other foot's contact of this step
            if len(near) == 1:
                flights.append((near[0] - x) / T)
    return duty, float(np.mean(flights)) if flights else np.nan


def ground_ratio(K, P, ev, speed):
    """Per stride (heel strike to heel strike of a side): the pelvis's horizontal displacement
    (from the motion's translation) over the distance the feet say was covered (speed x
    stride time): ~1 overground, ~0 on a treadmill. Stride by stride, so turns and out-and-back
    walks count their travel."""
    t = K["t"]
    out = []
    for s in SIDES:
        hs = ev[s][0]
        for a, b in zip(hs[:-1], hs[1:]):
            pa = np.array([np.interp(a, t, P["pelvis"][:, j]) for j in (0, 2)])
            pb = np.array([np.interp(b, t, P["pelvis"][:, j]) for j in (0, 2)])
            out.append(float(np.hypot(*(pb - pa)) / (speed * (b - a))))
    return out


def step_times(ev):
    """Times from each heel strike to the next heel strike of the other foot."""
    allhs = sorted([(x, s) for s in SIDES for x in ev[s][0]])
    return np.array([b[0] - a[0] for a, b in zip(allhs[:-1], allhs[1:]) if a[1] != b[1]])


def main():
    R = load()
    for key, (label, t, P, gt, plate, belt) in R.items():
        t0 = max(t[0], gt[0]) + 0.2  # events this close to an end of either record are not scored
        t1 = min(t[-1], gt[-1]) - 0.2
        vb = float(np.median([b for _, b, _ in belt]))
        print(f"\n=== {label}: scored {t0:.2f}-{t1:.2f} s; belt {vb:.3f} m/s (markers, median of "
              f"{len(belt)} stances, range {min(b for _, b, _ in belt):.3f}-{max(b for _, b, _ in belt):.3f})")
        print("method | per side and event: mean/worst error ms, n matched, m missed, f false | stance error (points) r l")
        K = signals(t, P)
        base = zeni(K)
        rows = []
        summarise("A  Zeni (qgait today: subtalar / toe tip)", base, plate, t0, t1, rows)
        summarise("A' Zeni, toe off from the MTP centre", zeni(K, toe="mtp"), plate, t0, t1, rows)
        summarise("B  O'Connor FVA, ground (heel marker+MTP)", oconnor(K, base, ""), plate, t0, t1, rows)
        summarise("B' O'Connor FVA, ground (subtalar+MTP)", oconnor(K, base, "", heel="subtalar"), plate, t0, t1, rows)
        summarise("B\" O'Connor FVA, rel. pelvis (subtalar+MTP)", oconnor(K, base, "rel", heel="subtalar"), plate, t0, t1, rows)
        summarise("C  Hreljac-Marshall, ground", hreljac(K, base, ""), plate, t0, t1, rows)
        summarise("C' Hreljac-Marshall, rel. pelvis", hreljac(K, base, "rel"), plate, t0, t1, rows)
        summarise("C\" Handsaker 2016, ground", handsaker(K, base, ""), plate, t0, t1, rows)
        ev_d, vd = velocity_events(K, base, vertical="rel", heel="subtalar")
        summarise(f"D  velocity rel. pelvis + v (0.78v/0.66v), kernel points, v={vd:.3f}", ev_d, plate, t0, t1, rows)
        summarise("D' same, heel marker", velocity_events(K, base, vertical="rel")[0], plate, t0, t1, rows)
        summarise("D\" same, ground vertical", velocity_events(K, base, vertical="ground", heel="subtalar")[0], plate, t0, t1, rows)
        summarise("D* same, belt speed given", velocity_events(K, base, vertical="rel", heel="subtalar", speed=vb)[0], plate, t0, t1, rows)
        summarise("E  velocity rel. pelvis + v, fixed 0.5 m/s", velocity_events(K, base, vertical="rel", heel="subtalar", hs_abs=0.5, to_abs=0.5)[0], plate, t0, t1, rows)
        summarise("E' same, ground vertical", velocity_events(K, base, vertical="ground", heel="subtalar", hs_abs=0.5, to_abs=0.5)[0], plate, t0, t1, rows)
        f6 = signals(t, P, fc=6.0)
        fe = fellin_toe_off(K, base)
        summarise("F  Fellin 2010 toe off (peak knee extension), D heel strike", {q: (ev_d[q][0], fe[q]) for q in SIDES}, plate, t0, t1, rows)
        v_int = float(np.median([v for _, v in lowest_point_speed(K, ev_d, ("subtalar", "mtp"))]))
        summarise(f"E* E with the stride-integrated speed v={v_int:.3f}", velocity_events(K, base, vertical="rel", heel="subtalar", speed=v_int, hs_abs=0.5, to_abs=0.5)[0], plate, t0, t1, rows)
        summarise("E** E with the belt speed", velocity_events(K, base, vertical="rel", heel="subtalar", speed=vb, hs_abs=0.5, to_abs=0.5)[0], plate, t0, t1, rows)
        summarise(f"G  E* heel strike, D toe off (0.66 v), v={v_int:.3f}", velocity_events(K, base, vertical="rel", heel="subtalar", speed=v_int, hs_abs=0.5)[0], plate, t0, t1, rows)
        rec, mode, vrec, duty1, froude, L = recommended(K)
        summarise(f"R  recommended ({mode})", rec, plate, t0, t1, rows)
        duty_r, flight_r = duty_and_flight(rec, t0, t1)
        print(f"R: first-pass duty factor {duty1:.3f} -> {mode}; final duty {duty_r:.3f}, flight per step {100 * flight_r:+.1f} % of the stride; "
              f"speed {vrec:.3f} m/s ({100 * (vrec / vb - 1):+.1f} %); leg length {L:.3f} m; Froude {froude:.2f}")
        st_true = np.median(np.concatenate([np.diff(plate[q][0]) for q in SIDES]))
        sp_true = np.median(step_times(plate))
        st_r, sp_r = stride_time(rec), np.median(step_times(rec))
        print(f"R: stride time {st_r:.3f} s (plate {st_true:.3f}); cadence {120 / st_r:.1f}/min ({100 * (st_true / st_r - 1):+.2f} %); "
              f"stride length {vrec * st_r:.3f} m (truth {vb * st_true:.3f}, {100 * (vrec * st_r / (vb * st_true) - 1):+.1f} %); "
              f"step length {vrec * sp_r:.3f} m (truth {vb * sp_true:.3f}, {100 * (vrec * sp_r / (vb * sp_true) - 1):+.1f} %)")
        dt, ft = duty_and_flight(plate)
        print(f"plate: duty {dt:.3f}, flight per step {100 * ft:+.1f} % of the stride")
        for fc in (6.0, 12.0):
            Kf = signals(t, P, fc=fc)
            summarise(f"R on {fc:.0f} Hz low-passed points ({recommended(Kf)[1]})", recommended(Kf)[0], plate, t0, t1, rows)
        Ki = signals(t, P, translation=False)  # what an IMU solution gives: nothing in ground
        ri = recommended(Ki)
        summarise(f"R without any ground-frame quantity ({ri[1]}, v={ri[2]:.3f})", ri[0], plate, t0, t1, rows)
        Kh = signals(t, P, heading=True)
        rh = recommended(Kh)
        summarise(f"R along the pelvis heading (as qgait's progression) ({rh[1]}, v={rh[2]:.3f})", rh[0], plate, t0, t1, rows)
        summarise("D6 D on 6 Hz low-passed points", velocity_events(f6, zeni(f6), vertical="rel", heel="subtalar")[0], plate, t0, t1, rows)
        summarise("A6 A on 6 Hz low-passed points", zeni(f6), plate, t0, t1, rows)

        print("-- speed (m/s) and error vs belt")
        for name, ev in (("plate events", plate), ("Zeni events", base), ("D events", ev_d)):
            ms = [v for _, v in mid_stance_speed(K, ev)]
            lp = [v for _, v in lowest_point_speed(K, ev, ("subtalar", "mtp"))]
            print(f"{name:13s} mid-stance median {np.median(ms):.3f} ({100 * (np.median(ms) / vb - 1):+.1f} %), "
                  f"per stance {min(ms):.3f}-{max(ms):.3f} | lowest of subtalar/MTP over the stride "
                  f"{np.median(lp):.3f} ({100 * (np.median(lp) / vb - 1):+.1f} %)")
        st_true = np.median(np.concatenate([np.diff(plate[s][0]) for s in SIDES]))
        st_d = stride_time(ev_d)
        sp_true, sp_d = np.median(step_times(plate)), np.median(step_times(ev_d))
        v_ms = float(np.median([v for _, v in mid_stance_speed(K, ev_d)]))
        print(f"stride time plate {st_true:.3f} s, D {st_d:.3f} s; step time plate {sp_true:.3f}, D {sp_d:.3f}")
        print(f"stride length: truth belt x plate stride {vb * st_true:.3f} m; D mid-stance speed x D stride {v_ms * st_d:.3f} m "
              f"({100 * (v_ms * st_d / (vb * st_true) - 1):+.1f} %)")
        print(f"step length (distance travelled between opposite contacts): truth {vb * sp_true:.3f} m; D {v_ms * sp_d:.3f} m "
              f"({100 * (v_ms * sp_d / (vb * sp_true) - 1):+.1f} %)")
        print(f"cadence: plate {120 / st_true:.1f}/min, D {120 / st_d:.1f}/min ({100 * (st_true / st_d - 1):+.2f} %)")

        print("-- mode and ground")
        for name, ev in (("plate", plate), ("A Zeni", base), ("D velocity", ev_d)):
            duty, flight = duty_and_flight(ev, t0, t1)
            print(f"{name:11s} duty factor {duty:.3f}, mean flight per step {100 * flight:+.1f} % of the stride (negative: double support) -> "
                  f"{'running' if duty < RUN_DUTY_FACTOR else 'walking'}")
        ratios = ground_ratio(K, P, rec, vrec)
        r_med = float(np.median(ratios))
        print(f"pelvis displacement per stride / (speed x stride time): median {r_med:.3f} "
              f"(range {min(ratios):.3f}-{max(ratios):.3f}, {len(ratios)} strides) -> "
              f"{'overground' if r_med >= OVERGROUND_RATIO else 'treadmill'}")
        # The same recording made overground: the belt's displacement (markers' speed) added to
        # every point, as a walker on the floor would have it. Relative kinematics unchanged.
        Po = {k: (v + np.outer(vb * (t - t[0]), [1, 0, 0]) if v.ndim == 2 else v) for k, v in P.items()}
        Ko = signals(t, Po)
        ro = recommended(Ko)
        ratios = ground_ratio(Ko, Po, ro[0], ro[2])
        print(f"synthetic overground copy: ratio median {np.median(ratios):.3f} -> "
              f"{'overground' if np.median(ratios) >= OVERGROUND_RATIO else 'treadmill'}; mode {ro[1]}, speed {ro[2]:.3f}")




def lowest_point_speed(K, ev=None, points=("subtalar", "mtp", "toe")):
    """Per stride of each side: the mean over the stride of the backward velocity, relative to
    the pelvis, of the lowest foot point (the kernel's subtalar centre, MTP centre or toe tip,
    of either foot, by height relative to the pelvis): the lowest point of the foot in stance
    is the one on the ground, still over the ground as the foot rolls over heel, forefoot and
    toe, so its velocity relative to the pelvis is minus the pelvis's over the ground (the
    belt's on a treadmill). Frames where no foot is in stance (`ev`, a running flight) are
    filled by linear interpolation (the pelvis flies at a constant horizontal velocity).
    Returns [(mid time, speed)]."""
    t = K["t"]
    n = len(t)
    v = np.zeros(n)
    for i in range(n):
        best = None
        for s in SIDES:
            for p in points:
                h = K[f"{p}_{s}_rel"][i, 1]
                if best is None or h < best[0]:
                    best = (h, s, p)
        v[i] = -K[f"{best[2]}_{best[1]}_vrel"][i, 0]
    if ev is not None:
        down = np.array([any(in_stance(ev, s, x)[0] for s in SIDES) for x in t])
        if down.sum() >= 2:
            v = np.interp(t, t[down], v[down])
    out = []
    base = ev if ev is not None else None
    for s in SIDES:
        hs = base[s][0]
        for a, b in zip(hs[:-1], hs[1:]):
            sel = (t >= a) & (t <= b)
            if sel.sum() < 3:
                continue
            out.append(((a + b) / 2, float(np.trapezoid(v[sel], t[sel]) / (t[sel][-1] - t[sel][0]))))
    return out


if __name__ == "__main__":
    main()
    imu_check()
