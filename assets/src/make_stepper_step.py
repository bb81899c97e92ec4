#!/usr/bin/env python3
"""Sinew's stepper: a pelvis on two legs, marching forward in a loop, as BVH.

    python3 assets/src/make_stepper_step.py > assets/stepper_step.bvh
    python3 assets/src/make_stepper_step.py --check assets/stepper_step.bvh

Centimetres, Y up, the stepper faces +Z (its left is +X).  BVH conventions
as in make_biped_walk.py; the rest pose (all rotations zero) is standing.
Standard library only; the output is deterministic.

No upper body: the pelvis is the whole trunk, the classic walking-machine
test character.  The gait is a slow, high-stepping walk.  In stance each foot
rolls heel -> flat -> ball about whichever point is on the ground, so it
cannot slide; the roll starts and ends at rest, so the swing (smooth in
position and pitch) joins it without a jolt.  Legs are solved by two-bone IK
with the knee forwards.
"""
import math
import sys

sys.dont_write_bytecode = True    # keep assets/src free of __pycache__
from rig import (main, open_and_check_ground, loop_and_speed_ok, joint_offsets, mmul, mT, mvec, periodic, rotx, roty, rotz, smooth,
                 stance_slides, two_bone, bone_rotation, hermite, vadd, vsub, write_bvh,
                 Motion, hinge_report)

# ------------------------------------------------------------------ timing
FPS = 30
STRIDE_FRAMES = 36                        # one gait cycle: left + right step
STRIDES = 4
NFRAMES = STRIDES * STRIDE_FRAMES + 1     # +1 so the loop closes
SPEED = 60.0                              # cm/s along +Z
STRIDE_LEN = SPEED * STRIDE_FRAMES / FPS  # 72 cm; a step is half of it

# ------------------------------------------------------------------ rig (cm)
THIGH, SHIN, ANKLE_H = 26.0, 26.0, 8.0
HIP = (10.0, -4.0, 0.0)     # Pelvis -> LeftUpLeg (X mirrored for the right)
BALL = (0.0, -6.0, 12.0)    # ankle -> ball of the foot (the Toe joint)
TIP = (0.0, -2.0, 6.0)      # ball -> toe tip
HEEL = (0.0, -8.0, -5.0)    # ankle -> heel contact point (a marker, no joint)


def _leg(s, side):
    return (side + "UpLeg", (HIP[0] * s, HIP[1], HIP[2]), [
        (side + "Leg", (0, -THIGH, 0), [(side + "Foot", (0, -SHIN, 0), [
            (side + "Toe", BALL, [(None, TIP, [])])])])])


SKELETON = ("Pelvis", (0, 0, 0), [_leg(1, "Left"), _leg(-1, "Right")])
OFF = joint_offsets(SKELETON)

# ------------------------------------------------------------------ keys
# Stride phase 0..1: 0 = left heel strike, 0.5 = right heel strike.
_HALF = [(0.00, 61.0), (0.10, 61.3), (0.25, 62.7), (0.40, 61.9)]
PELVIS_HEIGHT = _HALF + [(p + 0.5, h) for p, h in _HALF]
PELVIS_SWAY = [(0.00, 0.0), (0.25, 3.0), (0.50, 0.0), (0.75, -3.0)]   # cm, + = left
PELVIS_YAW = [(0.00, -6.0), (0.25, 0.0), (0.50, 6.0), (0.75, 0.0)]    # deg about +Y
PELVIS_ROLL = [(0.00, 0.0), (0.18, 3.5), (0.50, 0.0), (0.68, -3.5)]   # deg about +Z
PELVIS_TILT = [(0.00, 3.0), (0.25, 4.0), (0.50, 3.0), (0.75, 4.0)]    # deg about +X

FOOT_X = 9.0            # lateral placement of the ankles
CONTACT_LEAD = 16.0     # flat-foot ankle z ahead of the pelvis at heel strike
# Stance roll-over: (phase of the leg, foot pitch deg [+ = toes up]); the
# pitch rate is 0 at every row, so the roll eases in and out of each state.
STANCE = [(0.00, 14.0),     # heel strike
          (0.12, 0.0),      # foot flat
          (0.36, 0.0),      # heel off
          (0.62, -34.0)]    # toe off, the toes still flat on the ground
TOE_OFF = STANCE[-1][0]
SWING_LIFT = 14.0       # extra ankle height at mid-swing: a high, marching step
SWING_PITCH = 12.0      # toes raised at mid-swing (deg) so they clear


def stance(p, x, z0):
    """(ankle, pitch, toe bend) at stance phase p; z0 = ankle z when flat."""
    for (p0, a0), (p1, a1) in zip(STANCE, STANCE[1:]):
        if p <= p1:
            break
    pitch = hermite(a0, a1, 0.0, 0.0, (p - p0) / (p1 - p0))
    pivot = HEEL if pitch > 0 else BALL
    ankle = vsub(vadd((x, ANKLE_H, z0), pivot), mvec(rotx(-pitch), pivot))
    return ankle, pitch, min(pitch, 0.0)


def foot(frame, side, shift):
    c = frame / STRIDE_FRAMES + shift
    n = math.floor(c)
    p = c - n
    x = side * FOOT_X
    z0 = CONTACT_LEAD + (n - shift) * STRIDE_LEN
    if p <= TOE_OFF:
        return stance(p, x, z0)
    a0, f0, t0 = stance(TOE_OFF, x, z0)
    a1, f1, t1 = stance(0.0, x, z0 + STRIDE_LEN)
    u = (p - TOE_OFF) / (1.0 - TOE_OFF)
    s, bump = smooth(u), math.sin(math.pi * u) ** 2
    ankle = (x, a0[1] + (a1[1] - a0[1]) * s + SWING_LIFT * bump, a0[2] + (a1[2] - a0[2]) * s)
    return ankle, f0 + (f1 - f0) * s + SWING_PITCH * bump, t0 + (t1 - t0) * s


def pose(frame):
    p = frame / STRIDE_FRAMES
    root = (periodic(PELVIS_SWAY, p), periodic(PELVIS_HEIGHT, p), SPEED * frame / FPS)
    yaw = periodic(PELVIS_YAW, p)
    pel = mmul(roty(yaw), mmul(rotx(periodic(PELVIS_TILT, p)), rotz(periodic(PELVIS_ROLL, p))))
    loc = {"Pelvis": pel}
    for side, s, shift in (("Left", 1, 0.0), ("Right", -1, 0.5)):
        ankle, pitch, toe = foot(frame, s, shift)
        hip = vadd(root, mvec(pel, OFF[side + "UpLeg"]))
        lateral = mvec(roty(0.5 * yaw), (1.0, 0.0, 0.0))
        knee = two_bone(hip, ankle, THIGH, SHIN, lateral, 1)
        thigh = bone_rotation((0, -1, 0), vsub(knee, hip), lateral)
        shank = bone_rotation((0, -1, 0), vsub(ankle, knee), lateral)
        loc[side + "UpLeg"] = mmul(mT(pel), thigh)
        loc[side + "Leg"] = mmul(mT(thigh), shank)
        loc[side + "Foot"] = mmul(mT(shank), rotx(-pitch))
        loc[side + "Toe"] = rotx(toe)
    return root, loc


# ------------------------------------------------------------------ check
def check(path):
    m, ok = open_and_check_ground(path)
    heel = lambda w, sd: vadd(w[sd + "Foot"][0], mvec(w[sd + "Foot"][1], HEEL))
    worst = 0.0
    for sd, shift in (("Left", 0.0), ("Right", 0.5)):
        heels = [heel(w, sd) for w in m.world]
        print("heel marker lowest: %.3f cm" % min(h[1] for h in heels))
        ok = ok and min(h[1] for h in heels) >= -0.05
        st = stance_slides([heels, m.track(sd + "Toe_end")], ground=0.01)
        print("%-5s contacts (first frame, frames, slide mm): %s" % (
            sd, ", ".join("%d %d %.3f" % c for c in st)))
        worst = max([worst] + [c[2] for c in st])
        # Down for the whole stance of every stride, up in mid-swing.
        for f in range(m.nframes):
            q = (f / STRIDE_FRAMES + shift) % 1.0
            tip, h = m.world[f][sd + "Toe_end"][0][1], heels[f][1]
            if q <= TOE_OFF - 1e-9 and min(tip, h) > 0.01:
                print("%s: off the ground in stance at frame %d" % (sd, f))
                ok = False
            if abs(q - (1 + TOE_OFF) / 2) < 0.05 and min(tip, h) < 5.0:
                print("%s: foot too low in mid-swing at frame %d" % (sd, f))
                ok = False
    print("max stance slide: %.3f mm" % worst)
    ok = ok and worst <= 1.0
    pel = lambda w: mvec(w["Pelvis"][1], (1, 0, 0))
    for sd in ("Left", "Right"):
        lo, hi = hinge_report(m, sd + "UpLeg", sd + "Leg", sd + "Foot", pel, 1)
        print("%-5s knee flexion: %.1f .. %.1f deg" % (sd, lo, hi))
        ok = ok and lo > 2.0
    rz = m.track("Pelvis")
    speed = (rz[-1][2] - rz[0][2]) / ((m.nframes - 1) * m.frame_time)
    print("average speed: %.2f cm/s; stride %d frames = %.4f s, %.2f cm; pelvis %.2f .. %.2f cm"
          % (speed, STRIDE_FRAMES, STRIDE_FRAMES / FPS, STRIDE_LEN,
             min(q[1] for q in rz), max(q[1] for q in rz)))
    ok = loop_and_speed_ok(m, speed, SPEED) and ok
    print("RESULT:", "PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    main(__doc__, check, SKELETON, NFRAMES, FPS, pose)
