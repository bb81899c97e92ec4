#!/usr/bin/env python3
"""Sinew's hopper: a one-legged creature hopping forward in a loop, as BVH.

    python3 assets/src/make_hopper_hop.py > assets/hopper_hop.bvh
    python3 assets/src/make_hopper_hop.py --check assets/hopper_hop.bvh

Centimetres, Y up, the hopper faces +Z.  BVH conventions as in
make_biped_walk.py; the rest pose (all rotations zero) is standing upright.
Standard library only; the output is deterministic.

A body (pelvis, a short trunk and a head) on one leg, after Raibert's
hopping machines.  Each hop is a stance on the ball of the foot, where the
body sinks and rebounds like a mass on a spring (a half sine, so the height
and its velocity are continuous at touchdown and lift-off), and a ballistic
flight under gravity.  The ball does not move while it is down; the leg is
solved by two-bone IK (knee forwards only), the foot pitch is keyed.
"""
import math
import sys

sys.dont_write_bytecode = True    # keep assets/src free of __pycache__
from rig import (main, open_and_check_ground, loop_and_speed_ok, joint_offsets, mmul, mT, mvec, periodic, rotx, smooth, stance_slides,
                 two_bone, bone_rotation, vadd, vsub, write_bvh, Motion, hinge_report)

# ------------------------------------------------------------------ timing
FPS = 30
STANCE_FRAMES, FLIGHT_FRAMES = 8, 8
HOP_FRAMES = STANCE_FRAMES + FLIGHT_FRAMES   # one hop is the stride
HOPS = 5
NFRAMES = HOPS * HOP_FRAMES + 1              # +1 so the loop closes
SPEED = 60.0                                 # cm/s along +Z
HOP_LEN = SPEED * HOP_FRAMES / FPS           # 32 cm
DUTY = STANCE_FRAMES / HOP_FRAMES
GRAVITY = 981.0                              # cm/s^2
T_STANCE, T_FLIGHT = STANCE_FRAMES / FPS, FLIGHT_FRAMES / FPS
V_LIFT = GRAVITY * T_FLIGHT / 2              # vertical speed at lift-off, cm/s
SINK = V_LIFT * T_STANCE / math.pi           # stance compression: the half sine's depth

# ------------------------------------------------------------------ rig (cm)
THIGH, SHIN = 30.0, 30.0
HIP = (0.0, -8.0, 0.0)       # Pelvis -> UpLeg
BALL = (0.0, -6.0, 11.0)     # ankle -> ball of the foot (the Toe joint)
TIP = (0.0, -2.0, 5.0)       # ball -> toe tip
SKELETON = ("Pelvis", (0, 0, 0), [
    ("Spine", (0, 12, 0), [("Head", (0, 22, 2), [(None, (0, 16, 0), [])])]),
    ("UpLeg", HIP, [("Leg", (0, -THIGH, 0), [("Foot", (0, -SHIN, 0), [
        ("Toe", BALL, [(None, TIP, [])])])])])])
OFF = joint_offsets(SKELETON)

# ------------------------------------------------------------------ keys
# Hop phase runs 0..1: 0 = the middle of the stance (deepest), DUTY / 2 =
# lift-off, 1 - DUTY / 2 = touchdown.  Foot pitch (deg, + = heel up) over the
# hop: lands on the ball with the heel raised, sinks onto it, pushes off,
# recovers in the air.
LO, TD = DUTY / 2, 1 - DUTY / 2
FOOT_PITCH = [(0.00, 8.0), (LO, 34.0), (0.5, 22.0), (TD, 18.0)]
BODY_PITCH = [(0.00, 8.0), (LO, 2.0), (0.5, 0.0), (TD, 3.0)]    # deg, + = lean forward
SPINE_PITCH = 0.4            # the trunk gives back this share of the pelvis lean
LIFT = 9.0                   # ball clearance at mid-flight, cm
LEG_AT_TOUCHDOWN = 0.95      # hip-ankle distance at touchdown over THIGH + SHIN


def ankle_from_ball(ball, pitch):
    foot = rotx(pitch)
    return vsub(ball, mvec(foot, BALL)), foot


def root_height(p):
    """Pelvis height (cm) at hop phase p: half-sine stance, parabolic flight."""
    p %= 1.0
    if p <= LO or p >= TD:                 # stance
        t = (p + 1 - TD if p >= TD else p + LO) * HOP_FRAMES / FPS
        return TOUCHDOWN_HEIGHT - SINK * math.sin(math.pi * t / T_STANCE)
    t = (p - LO) * HOP_FRAMES / FPS
    return TOUCHDOWN_HEIGHT + V_LIFT * t - GRAVITY * t * t / 2


# Pelvis height at touchdown: the leg reaches LEG_AT_TOUCHDOWN of its length
# to a ball half a stance ahead of the hip.
_lead = SPEED * T_STANCE / 2
_ankle, _ = ankle_from_ball((0.0, -TIP[1], 0.0), periodic(FOOT_PITCH, TD))
_reach = LEG_AT_TOUCHDOWN * (THIGH + SHIN)
_dz = _lead + _ankle[2]
TOUCHDOWN_HEIGHT = _ankle[1] - HIP[1] + math.sqrt(_reach ** 2 - _dz ** 2)


def ball(frame):
    """World position of the ball of the foot."""
    c = frame / HOP_FRAMES - LO            # 0 at a lift-off
    n = math.floor(c)
    u = c - n                              # 0..1-DUTY flight, then stance
    # The stance ending at lift-off n + 1 is centred on hop n + 1's middle.
    z_next = SPEED * (n + 1) * HOP_FRAMES / FPS
    y = -TIP[1]
    if u >= 1 - DUTY:
        return (0.0, y, z_next)
    v = u / (1 - DUTY)
    return (0.0, y + LIFT * math.sin(math.pi * v) ** 2, z_next - HOP_LEN * (1 - smooth(v)))


def pose(frame):
    p = frame / HOP_FRAMES
    root = (0.0, root_height(p), SPEED * frame / FPS)
    lean = periodic(BODY_PITCH, p)
    pelvis = rotx(lean)
    loc = {"Pelvis": pelvis, "Spine": rotx(-SPINE_PITCH * lean)}
    trunk = mmul(pelvis, loc["Spine"])
    loc["Head"] = mT(trunk)                          # the head stays level
    hip = vadd(root, mvec(pelvis, HIP))
    ankle, foot = ankle_from_ball(ball(frame), periodic(FOOT_PITCH, p))
    lateral = (1.0, 0.0, 0.0)
    knee = two_bone(hip, ankle, THIGH, SHIN, lateral, 1)
    thigh = bone_rotation((0, -1, 0), vsub(knee, hip), lateral)
    shank = bone_rotation((0, -1, 0), vsub(ankle, knee), lateral)
    loc["UpLeg"] = mmul(mT(pelvis), thigh)
    loc["Leg"] = mmul(mT(thigh), shank)
    loc["Foot"] = mmul(mT(shank), foot)
    loc["Toe"] = mT(foot)                            # the toes stay flat
    return root, loc


# ------------------------------------------------------------------ check
def check(path):
    m, ok = open_and_check_ground(path)
    st = stance_slides([m.track("Toe"), m.track("Toe_end")], ground=0.01)
    print("contacts (first frame, frames, slide mm): " + ", ".join("%d %d %.3f" % c for c in st))
    slide = max(c[2] for c in st)
    print("max stance slide: %.3f mm" % slide)
    ok = ok and slide <= 1.0
    # In flight the foot is off the ground, in stance on it.
    flight = [f for f in range(m.nframes)
              if LO + 1e-9 < (f / HOP_FRAMES) % 1.0 < TD - 1e-9]
    clear = min(min(m.world[f][n][0][1] for n in ("Toe", "Toe_end", "Foot")) for f in flight)
    print("flight frames: %d of %d; lowest foot point in flight: %.2f cm" % (
        len(flight), m.nframes, clear))
    ok = ok and clear > 0.5 and all(
        m.world[f]["Toe_end"][0][1] < 0.01 for f in range(m.nframes) if f not in flight)
    ry = [w["Pelvis"][0][1] for w in m.world]
    print("pelvis height %.2f .. %.2f cm (stance sink %.2f cm, flight rise %.2f cm)" % (
        min(ry), max(ry), SINK, V_LIFT ** 2 / (2 * GRAVITY)))
    lo, hi = hinge_report(m, "UpLeg", "Leg", "Foot", lambda w: (1, 0, 0), 1)
    print("knee flexion: %.1f .. %.1f deg" % (lo, hi))
    ok = ok and lo > 5.0
    speed = (m.world[-1]["Pelvis"][0][2] - m.world[0]["Pelvis"][0][2]) / (
        (m.nframes - 1) * m.frame_time)
    print("average speed: %.2f cm/s; hop %d frames = %.4f s, %.2f cm" % (
        speed, HOP_FRAMES, HOP_FRAMES / FPS, HOP_LEN))
    ok = loop_and_speed_ok(m, speed, SPEED) and ok
    print("RESULT:", "PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    main(__doc__, check, SKELETON, NFRAMES, FPS, pose)
