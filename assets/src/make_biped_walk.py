#!/usr/bin/env python3
"""Sinew's default biped rig and keyframed walk cycle, written as BVH.

    python3 assets/src/make_biped_walk.py > assets/biped_walk.bvh
    python3 assets/src/make_biped_walk.py --check assets/biped_walk.bvh

Centimetres, Y up, the character faces +Z (its left is +X). Standard BVH
semantics: "Zrotation Xrotation Yrotation" means the local rotation is
R = Rz(z) * Rx(x) * Ry(y), and p_parent = OFFSET + R * p_child.  Rest pose
(all rotations zero) is a T-pose.  Standard library only; the output is
deterministic, so rerunning the script reproduces the file byte for byte.
"""
import math
import sys

sys.dont_write_bytecode = True    # keep assets/src free of __pycache__
from rig import (cross, dot, euler_zxy, hermite, main, mmul, mT, mvec, norm, periodic, rotx,
                 roty, rotz, unit, vadd, vmul, vsub, zxy)

# ------------------------------------------------------------------ timing
FPS = 30
STRIDE_FRAMES = 32                        # one gait cycle: left + right step
NFRAMES = 4 * STRIDE_FRAMES + 1           # 4 strides; +1 so the loop closes
SPEED = 130.0                             # cm/s along +Z
STRIDE_LEN = SPEED * STRIDE_FRAMES / FPS  # 138.67 cm; a step is half of it

# ------------------------------------------------------------------ rig (cm)
THIGH, SHIN, ANKLE_H = 42.0, 42.0, 8.0
HIP = (9.0, -5.0, 0.0)      # Hips -> LeftUpLeg (X mirrored for the right)
BALL = (0.0, -6.0, 14.0)    # ankle -> ball of the foot (the Toe joint)
TIP = (0.0, -2.0, 6.0)      # ball -> toe tip, which touches the ground
HEEL = (0.0, -8.0, -6.0)    # ankle -> heel contact point (a marker, no joint)


def _arm(s, side):
    return (side + "Shoulder", (3 * s, 16, 0), [(side + "Arm", (13 * s, 0, 0), [
        (side + "ForeArm", (29 * s, 0, 0), [
            (side + "Hand", (26 * s, 0, 0), [(None, (18 * s, 0, 0), [])])])])])


def _leg(s, side):
    return (side + "UpLeg", (HIP[0] * s, HIP[1], HIP[2]), [
        (side + "Leg", (0, -THIGH, 0), [(side + "Foot", (0, -SHIN, 0), [
            (side + "Toe", BALL, [(None, TIP, [])])])])])


# (name, offset from parent, children); name None is an End Site.  The root
# OFFSET is zero so the Hips position channels are the world position.
# Standing: Hips 97 cm, shoulders 147, neck 151, top of the head 175.
SKELETON = ("Hips", (0, 0, 0), [
    ("Spine", (0, 10, 0), [("Spine1", (0, 12, 0), [("Chest", (0, 12, 0), [
        ("Neck", (0, 20, 0), [("Head", (0, 9, 0), [(None, (0, 15, 0), [])])]),
        _arm(1, "Left"), _arm(-1, "Right")])])]),
    _leg(1, "Left"), _leg(-1, "Right")])

# ------------------------------------------------------------------ keys
# Phase runs 0..1 over a stride: 0 = left heel strike, 0.5 = right heel
# strike.  Tables of (phase, value...) are splined with periodic Catmull-Rom,
# so the cycle loops without a seam.

# Pelvis height (cm): lowest at contact, highest at passing.  It drops early
# (0.44-0.47) because the swing leg must reach its heel strike.
_HALF = [(0.00, 92.2), (0.06, 92.5), (0.125, 93.6), (0.25, 95.6),
         (0.375, 94.9), (0.44, 93.3), (0.47, 92.25)]
PELVIS_HEIGHT = _HALF + [(p + 0.5, h) for p, h in _HALF]   # same for both steps
# Lateral sway (cm, + = left): over the stance foot at mid-stance.
PELVIS_SWAY = [(0.00, 0.0), (0.25, 2.4), (0.50, 0.0), (0.75, -2.4)]
# Yaw (deg about +Y; negative brings the left hip forward): the pelvis turns
# with the leg that reaches forward.
PELVIS_YAW = [(0.00, -4.5), (0.25, 0.0), (0.50, 4.5), (0.75, 0.0)]
# Obliquity (deg about +Z): the swing-side hip drops, most in early stance.
PELVIS_ROLL = [(0.00, 0.0), (0.18, 3.0), (0.50, 0.0), (0.68, -3.0)]
# Anterior tilt (deg about +X), a small twice-per-stride oscillation.
PELVIS_TILT = [(0.00, 4.0), (0.25, 5.0), (0.50, 4.0), (0.75, 5.0)]
# Thorax orientation in the world (deg): yaw counter-rotates the pelvis,
# lean is the forward lean of walking, roll partly cancels the hip drop.
THORAX = [(0.00, 3.5, 6.0, 0.0), (0.25, 0.0, 5.0, -1.0),      # phase, yaw,
          (0.50, -3.5, 6.0, 0.0), (0.75, 0.0, 5.0, 1.0)]      # lean, roll
SPINE_SHARE = (0.3, 0.3, 0.4)     # how Spine, Spine1, Chest split that
# Head stabilisation: the head's world orientation (yaw, pitch deg) barely
# moves whatever the trunk does; the small nod offsets the bob.
HEAD = [(0.00, 0.0, 1.0), (0.25, 0.0, -0.5), (0.50, 0.0, 1.0), (0.75, 0.0, -0.5)]
# Left arm (the right one runs half a stride later): swing (deg, + = forward,
# opposite to the left leg) and elbow flexion, larger as the arm comes forward.
ARM = [(0.00, -16.0, 14.0), (0.25, 0.0, 19.0), (0.50, 18.0, 32.0), (0.75, 2.0, 24.0)]
ARM_ABDUCT = 8.0        # arms hang slightly away from the thighs
CLAVICLE_SHARE = 0.15   # the clavicle protracts a little with the swing
WRIST_FLEX = 6.0

# Feet, in their own leg's phase (left = stride phase, right = phase + 0.5).
FOOT_X = 7.0            # lateral placement: a 14 cm step width
TOE_OUT = 5.0           # feet point slightly outwards (deg)
CONTACT_LEAD = 35.0     # flat-foot ankle z ahead of the Hips at heel strike
# Stance roll-over: (phase, foot pitch deg [+ = toes up], pitch rate deg per
# unit phase), cubic Hermite between rows.  Toes up = rolling on the heel,
# toes down = rolling on the ball, zero = foot flat (ankle rocker).
STANCE = [(0.00, 20.0, -450.0),     # heel strike
          (0.10, 0.0, 0.0),         # foot flat
          (0.38, 0.0, 0.0),         # heel off
          (0.60, -58.0, -500.0)]    # toe off, toes still flat on the ground
TOE_OFF = STANCE[-1][0]
# Swing, u = 0 at toe off .. 1 at heel strike: ankle height (cm), fraction of
# the forward travel, foot pitch (deg), toe bend (deg).  None = taken from the
# stance, and end tangents match the stance velocities: no jolt either end.
SWING = [(0.00, None, 0.00, None, None),
         (0.25, 20.0, 0.20, -40.0, -25.0),
         (0.55, 13.5, 0.60, -8.0, 0.0),
         (0.85, 11.0, 0.94, 11.0, 0.0),
         (1.00, None, 1.00, None, None)]


# ------------------------------------------------------------------ maths
# Vectors, rotations, Euler angles, Hermite splines and the BVH writer are shared with the other
# creature scripts (rig.py).


def spline(us, vs, m0, m1, u):
    """Catmull-Rom through (us, vs) over [0, 1] with given end tangents."""
    n = len(us)
    i = min(max(j for j in range(n) if us[j] <= u), n - 2)
    m = lambda j: m0 if j == 0 else m1 if j == n - 1 else \
        (vs[j + 1] - vs[j - 1]) / (us[j + 1] - us[j - 1])
    h = us[i + 1] - us[i]
    return hermite(vs[i], vs[i + 1], m(i), m(i + 1), (u - us[i]) / h, h)


# ------------------------------------------------------------------ feet
def stance(p, x, z0, yaw):
    """(ankle position, foot pitch, toe bend) at stance phase p.

    The foot rolls over whichever point is on the ground - heel, whole sole,
    then ball - and that point never moves, so the foot cannot slide.  z0 is
    the ankle z while the foot is flat."""
    for (p0, a0, r0), (p1, a1, r1) in zip(STANCE, STANCE[1:]):
        if p <= p1:
            break
    pitch = hermite(a0, a1, r0, r1, (p - p0) / (p1 - p0), p1 - p0)
    ry = roty(yaw)
    pivot = HEEL if pitch > 0 else BALL       # at pitch 0 both give the same
    ankle = vsub(vadd((x, ANKLE_H, z0), mvec(ry, pivot)),
                 mvec(mmul(ry, rotx(-pitch)), pivot))
    return ankle, pitch, min(pitch, 0.0)      # bent toes stay flat on the ground


def foot(frame, side, shift):
    """(ankle, pitch, toe bend) of one foot; shift = its phase offset."""
    c = frame / STRIDE_FRAMES + shift
    n = math.floor(c)
    p = c - n
    x, yaw = side * FOOT_X, side * TOE_OUT
    z0 = CONTACT_LEAD + (n - shift) * STRIDE_LEN   # this step's footprint
    if p <= TOE_OFF:
        return stance(p, x, z0, yaw)
    # Swing from this stance's toe off to the next heel strike, with end
    # tangents from finite differences of the stance motion.
    e, k = 1e-5, 1.0 - TOE_OFF                     # k = d(phase)/du
    a0, f0, t0 = stance(TOE_OFF, x, z0, yaw)
    b0, g0, _ = stance(TOE_OFF - e, x, z0, yaw)
    a1, f1, t1 = stance(0.0, x, z0 + STRIDE_LEN, yaw)
    b1, g1, _ = stance(e, x, z0 + STRIDE_LEN, yaw)
    d0 = [(q - r) / e * k for q, r in zip(a0 + (f0,), b0 + (g0,))]
    d1 = [(r - q) / e * k for q, r in zip(a1 + (f1,), b1 + (g1,))]
    u, us = (p - TOE_OFF) / k, [r[0] for r in SWING]
    col = lambda j, first, last: [first] + [r[j] for r in SWING[1:-1]] + [last]
    run = a1[2] - a0[2]
    x = hermite(a0[0], a1[0], d0[0], d1[0], u, 1.0)
    y = spline(us, col(1, a0[1], a1[1]), d0[1], d1[1], u)
    z = a0[2] + run * spline(us, col(2, 0.0, 1.0), d0[2] / run, d1[2] / run, u)
    pitch = spline(us, col(3, f0, f1), d0[3], d1[3], u)
    toe = spline(us, col(4, t0, t1), d0[3], 0.0, u)   # toes unbend in the air
    return (x, y, z), pitch, toe


def leg_ik(hip, ankle, pole):
    """Analytic two-bone IK: thigh world rotation and knee flexion (deg).

    The knee lies in the plane of hip, ankle and pole, on the pole side, so
    it only ever bends forwards: no hyper-extension by construction."""
    d = norm(vsub(ankle, hip))
    if d > (THIGH + SHIN) * 0.9995:     # a clamped leg would drag its foot
        raise SystemExit("leg cannot reach its foot target: retune the keys")
    dh = unit(vsub(ankle, hip))
    perp = unit(vsub(pole, vmul(dh, dot(pole, dh))))
    a = (THIGH ** 2 - SHIN ** 2 + d * d) / (2 * d)
    knee = vadd(hip, vadd(vmul(dh, a), vmul(perp, math.sqrt(THIGH ** 2 - a * a))))
    ty = unit(vsub(hip, knee))                      # the bone is -Y at rest
    tz = unit(vsub(perp, vmul(ty, dot(perp, ty))))  # the knee's front
    cosk = (THIGH ** 2 + SHIN ** 2 - d * d) / (2 * THIGH * SHIN)
    return mT((cross(ty, tz), ty, tz)), 180.0 - math.degrees(math.acos(cosk))


# ------------------------------------------------------------------ pose
def pose(frame):
    """Root position and {joint: local rotation matrix} for one frame."""
    p = frame / STRIDE_FRAMES
    root = (periodic(PELVIS_SWAY, p), periodic(PELVIS_HEIGHT, p), SPEED * frame / FPS)
    yaw = periodic(PELVIS_YAW, p)
    pel = mmul(roty(yaw), mmul(rotx(periodic(PELVIS_TILT, p)), rotz(periodic(PELVIS_ROLL, p))))
    loc = {"Hips": pel}

    # Spine: share the pelvis -> thorax rotation out over three joints.
    thorax = mmul(roty(periodic(THORAX, p, 1)),
                  mmul(rotx(periodic(THORAX, p, 2)), rotz(periodic(THORAX, p, 3))))
    rel, chest = euler_zxy(mmul(mT(pel), thorax)), pel
    for name, share in zip(("Spine", "Spine1", "Chest"), SPINE_SHARE):
        loc[name] = zxy(*(a * share for a in rel))
        chest = mmul(chest, loc[name])

    # Neck takes half of the correction, the head lands exactly on target.
    head = mmul(roty(periodic(HEAD, p, 1)), rotx(periodic(HEAD, p, 2)))
    loc["Neck"] = zxy(*(a * 0.5 for a in euler_zxy(mmul(mT(chest), head))))
    loc["Head"] = mmul(mT(mmul(chest, loc["Neck"])), head)

    # Arms hang under gravity and swing in the chest's heading.
    fwd = mvec(chest, (0, 0, 1))
    heading = roty(math.degrees(math.atan2(fwd[0], fwd[2])))
    for side, s, shift in (("Left", 1, 0.0), ("Right", -1, 0.5)):
        swing = periodic(ARM, p + shift, 1)
        loc[side + "Shoulder"] = roty(-s * CLAVICLE_SHARE * swing)
        want = mmul(heading, mmul(rotx(-swing), rotz(-s * (90.0 - ARM_ABDUCT))))
        loc[side + "Arm"] = mmul(mT(mmul(chest, loc[side + "Shoulder"])), want)
        loc[side + "ForeArm"] = roty(-s * periodic(ARM, p + shift, 2))  # hinge
        loc[side + "Hand"] = rotz(-s * WRIST_FLEX)

    # Legs: feet are placed in the world, hips ride on the pelvis, IK joins them.
    for side, s, shift in (("Left", 1, 0.0), ("Right", -1, 0.5)):
        ankle, pitch, toe = foot(frame, s, shift)
        hip = vadd(root, mvec(pel, (HIP[0] * s, HIP[1], HIP[2])))
        pole = mvec(roty(0.5 * (yaw + s * TOE_OUT)), (0, 0, 1))  # knee over toes
        thigh, flex = leg_ik(hip, ankle, pole)
        loc[side + "UpLeg"] = mmul(mT(pel), thigh)
        loc[side + "Leg"] = rotx(flex)                          # a pure hinge
        loc[side + "Foot"] = mmul(mT(mmul(thigh, rotx(flex))),
                                  mmul(roty(s * TOE_OUT), rotx(-pitch)))
        loc[side + "Toe"] = rotx(toe)
    return root, loc


# ------------------------------------------------------------------ BVH out
def check(path):
    """Independent check: parse the BVH text, run FK, measure the walk.

    Rotations are rebuilt from the axis-angle (Rodrigues) formula instead of
    the generator's matrices, so a sign slip there would show up here."""
    def axis_rot(k, deg):
        c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        skew = (0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0)
        return tuple(tuple((c if i == j else 0.0) + (1 - c) * k[i] * k[j] + s * skew[3 * i + j]
                           for j in range(3)) for i in range(3))

    def bvh_rot(z, x, y):   # channels left to right = matrix product order
        return mmul(axis_rot((0, 0, 1), z), mmul(axis_rot((1, 0, 0), x), axis_rot((0, 1, 0), y)))

    tok = open(path).read().split()
    joints, pos = [], 1     # (name, parent, offset, nchannels); skip HIERARCHY

    def parse(parent):
        nonlocal pos
        name = joints[parent][0] + "_end" if tok[pos] == "End" else tok[pos + 1]
        off, pos, nch = tuple(float(v) for v in tok[pos + 4:pos + 7]), pos + 7, 0
        if tok[pos] == "CHANNELS":
            nch = int(tok[pos + 1])
            pos += 2 + nch
        joints.append((name, parent, off, nch))
        me = len(joints) - 1
        while tok[pos] != "}":
            parse(me)
        pos += 1

    parse(None)
    nf, ft = int(tok[pos + 2]), float(tok[pos + 5])
    data, width = [float(v) for v in tok[pos + 6:]], sum(j[3] for j in joints)
    assert len(data) == nf * width, "bad motion block"
    frames = [data[i * width:(i + 1) * width] for i in range(nf)]
    world = []              # per frame: {name: (position, rotation)}
    for fr in frames:
        w, i = {}, 0
        for name, par, off, nch in joints:
            vals, i = fr[i:i + nch], i + nch
            r = bvh_rot(*vals[-3:]) if nch else bvh_rot(0, 0, 0)
            pp, pr = w[joints[par][0]] if par is not None else (vals[:3], None)
            w[name] = (tuple(pp), r) if pr is None else (vadd(pp, mvec(pr, off)), mmul(pr, r))
        world.append(w)

    def heel(w, side):
        return vadd(w[side + "Foot"][0], mvec(w[side + "Foot"][1], HEEL))

    def cm(v): return "%.3f" % (round(v, 3) + 0.0)      # no "-0.000"
    sides = ("Left", "Right")
    print("joints: %d (+%d End Sites); frames: %d at %.7f s" % (
        sum(1 for j in joints if j[3]), sum(1 for j in joints if not j[3]), nf, ft))
    fmin = min(w[sd + n][0][1] for w in world for sd in sides for n in ("Foot", "Toe", "Toe_end"))
    low = min((w[j[0]][0][1], j[0]) for w in world for j in joints)
    print("min foot height (ankle/ball/toe tip): %s cm; heel marker: %s cm" % (
        cm(fmin), cm(min(heel(w, sd)[1] for w in world for sd in sides))))
    print("lowest joint or end site: %s cm (%s) -> %s" % (
        cm(low[0]), low[1], "OK" if low[0] >= -0.5 else "BELOW GROUND"))

    # A foot is in stance while its heel marker or toe tip is within 1 mm of
    # the ground.  Slide = how far each grounded point moves while grounded.
    strikes, slides = [], []
    for sd in sides:
        heels = [heel(w, sd) for w in world]
        tips = [w[sd + "Toe_end"][0] for w in world]
        down = [h[1] < 0.1 or t[1] < 0.1 for h, t in zip(heels, tips)] + [False]
        start = None
        for f, d in enumerate(down):
            if d and start is None:
                start = f
                if heels[f][1] < 0.1 and f > 0:
                    strikes.append((f, sd, heels[f][2]))
            elif not d and start is not None:
                worst = 0.0
                for tr in (heels, tips):
                    on = [tr[g] for g in range(start, f) if tr[g][1] < 0.1]
                    worst = max([worst] + [norm(vsub(q, on[0])) * 10 for q in on])
                slides.append((start, sd, f - start, worst))
                start = None
    strikes.sort()
    print("heel strikes (frame foot heel-z):", ", ".join("%d %s %.1f" % s for s in strikes))
    print("stance slide per step (first frame, foot, frames, mm):",
          ", ".join("%d %s %d %.3f" % s for s in sorted(slides)))
    print("max stance slide: %.3f mm" % max(s[3] for s in slides))
    steps = [b[2] - a[2] for a, b in zip(strikes, strikes[1:])]
    per = [(b[0] - a[0]) * ft for a, b in zip(strikes, strikes[2:])]
    rz = [w["Hips"][0] for w in world]
    print("step length: %.2f .. %.2f cm; stride period: %.4f .. %.4f s" % (
        min(steps), max(steps), min(per), max(per)))
    print("average speed: %.2f cm/s; root starts at x=%s z=%s; pelvis height %.2f .. %.2f cm"
          % ((rz[-1][2] - rz[0][2]) / ((nf - 1) * ft), cm(rz[0][0]), cm(rz[0][2]),
             min(q[1] for q in rz), max(q[1] for q in rz)))

    # Knees: signed flexion about the thigh's own lateral axis, and the knee
    # must sit in front of the hip-ankle line (along the pelvis's forward).
    flex, ahead = [], []
    for w in world:
        for sd in sides:
            (h, hr), k, a = w[sd + "UpLeg"], w[sd + "Leg"][0], w[sd + "Foot"][0]
            th, sh, line = vsub(k, h), vsub(a, k), unit(vsub(a, h))
            flex.append(math.degrees(math.atan2(dot(cross(th, sh), mvec(hr, (1, 0, 0))),
                                                dot(th, sh))))
            ahead.append(dot(vsub(th, vmul(line, dot(th, line))), mvec(w["Hips"][1], (0, 0, 1))))
    print("knee flexion: %.2f .. %.2f deg; hyper-extension: %s; knee ahead of the "
          "hip-ankle line by >= %.2f cm" % (min(flex), max(flex),
                                            "none" if min(flex) > 0 else "YES", min(ahead)))
    loop = max(abs(a - b) for i, (a, b) in enumerate(zip(frames[0], frames[-1])) if i != 2)
    print("loop: first vs last frame, all channels but root Z: max diff %.6f" % loop)
    ok = (low[0] >= -0.5 and max(s[3] for s in slides) <= 2.0 and min(flex) > 0
          and min(ahead) > 0 and loop < 1e-6)
    print("RESULT:", "PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    main(__doc__, check, SKELETON, NFRAMES, FPS, pose)
