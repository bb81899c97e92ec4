#!/usr/bin/env python3
"""Sinew's quadruped: a medium dog and a looping trot, written as BVH.

    python3 assets/src/make_quadruped_trot.py > assets/quadruped_trot.bvh
    python3 assets/src/make_quadruped_trot.py --check assets/quadruped_trot.bvh

Centimetres, Y up, the dog faces +Z (its left is +X).  BVH conventions as in
make_biped_walk.py; the rest pose (all rotations zero) is the dog standing.
Standard library only; the output is deterministic.

A trot moves the legs in diagonal pairs: left fore with right hind, then right
fore with left hind, half a stride later.  Each paw is planted flat and does
not move while it is down; the leg above it is solved by two-bone IK (hip or
shoulder -> stifle or elbow -> hock or wrist) with the metatarsus (the "Foot"
bone) at a keyed angle, so stifles only ever bend forwards and elbows
backwards.
"""
import math
import sys

sys.dont_write_bytecode = True    # keep assets/src free of __pycache__
from rig import (main, open_and_check_ground, loop_and_speed_ok, bone_rotation, half_rotation, hinge_report, joint_offsets, mmul, mT, mvec,
                 norm, periodic, rotx, roty, rotz, smooth, stance_slides, two_bone, vadd, vsub,
                 write_bvh, Motion)

# ------------------------------------------------------------------ timing
FPS = 30
STRIDE_FRAMES = 16                        # one full trot cycle, both diagonals
STRIDES = 4
NFRAMES = STRIDES * STRIDE_FRAMES + 1     # +1 so the loop closes
SPEED = 90.0                              # cm/s along +Z
STRIDE_LEN = SPEED * STRIDE_FRAMES / FPS  # 48 cm
DUTY = 0.55                               # share of the stride a paw is down

# ------------------------------------------------------------------ rig (cm)
PAW_TIP = (0.0, -2.0, 4.0)  # paw joint -> toe tip, which touches the ground


def _leg(side, s, where, attach, upper, lower, meta):
    p = side + where
    return (p + "UpLeg", (attach[0] * s, attach[1], attach[2]), [
        (p + "Leg", upper, [(p + "Foot", lower, [
            (p + "Toe", meta, [(None, PAW_TIP, [])])])])])


# Hind: hip -> stifle (forward) -> hock -> paw; fore: shoulder -> elbow
# (backward) -> wrist -> paw.  Standing, the Hips are 43 cm up and the chains
# add up so every toe tip is at y = 0.  The Spine joint sits close to the Hips
# (the body plan merges it into the pelvis) and the tail is one segment: short
# light links between the heavy trunk boxes made the simulated dog blow up.
HIND = dict(where="Hind", attach=(6.0, -4.0, -2.0), upper=(0.0, -15.0, 7.0),
            lower=(0.0, -14.0, -8.0), meta=(0.0, -8.0, 3.0))
FORE = dict(where="Front", attach=(6.0, -8.0, 3.0), upper=(0.0, -13.0, -8.0),
            lower=(0.0, -15.0, 4.0), meta=(0.0, -6.0, 1.0))

SKELETON = ("Hips", (0, 0, 0), [
    ("Spine", (0, 1, 10), [("Chest", (0, 0, 28), [
        ("Neck", (0, 5, 6), [("Head", (0, 9, 5), [(None, (0, 0, 14), [])])]),
        _leg("Left", 1, **FORE), _leg("Right", -1, **FORE)])]),
    ("Tail", (0, 4, -5), [(None, (0, 2, -20), [])]),
    _leg("Left", 1, **HIND), _leg("Right", -1, **HIND)])
OFF = joint_offsets(SKELETON)

# ------------------------------------------------------------------ keys
# Phase runs 0..1 over a stride: 0 = left fore and right hind touch down,
# 0.5 = right fore and left hind.  Tables are periodic Catmull-Rom splines.
# Body: height (cm, lowest just after each diagonal lands), pitch (deg, +X =
# nose down), roll (deg about +Z), yaw (deg about +Y).
BODY_HEIGHT = [(0.00, 41.6), (0.12, 41.1), (0.30, 42.1), (0.50, 41.6), (0.62, 41.1),
               (0.80, 42.1)]
BODY_PITCH = [(0.00, 0.0), (0.25, 1.0), (0.50, 0.0), (0.75, 1.0)]
BODY_ROLL = [(0.00, 0.0), (0.25, 1.5), (0.50, 0.0), (0.75, -1.5)]
BODY_YAW = [(0.00, -1.5), (0.25, 0.0), (0.50, 1.5), (0.75, 0.0)]
SPINE_BEND = [(0.00, 2.0), (0.25, 0.0), (0.50, -2.0), (0.75, 0.0)]   # yaw, deg
HEAD_NOD = [(0.00, 1.5), (0.25, -1.5), (0.50, 1.5), (0.75, -1.5)]    # pitch, deg
# Tail: (phase, wag deg about +Y, raised deg about +X).
TAIL = [(0.00, 12.0, 18.0), (0.25, 0.0, 22.0), (0.50, -12.0, 18.0), (0.75, 0.0, 14.0)]

# Legs, in their own phase u (0 = touchdown, DUTY = lift-off).
LEGS = {  # name prefix: (side sign, phase shift, HIND or FORE)
    "LeftFront": (1, 0.0, FORE), "RightHind": (-1, 0.0, HIND),
    "RightFront": (-1, 0.5, FORE), "LeftHind": (1, 0.5, HIND)}
# Metatarsus pitch (deg about the lateral axis, + = paw behind the hock):
# reaching forward at touchdown, heel rising as the limb trails, folded in
# swing.
META = {"Hind": [(0.00, -6.0), (0.25, 0.0), (0.55, 28.0), (0.75, 30.0), (0.90, -4.0)],
        "Front": [(0.00, -6.0), (0.25, 0.0), (0.55, 36.0), (0.75, 45.0), (0.90, -6.0)]}
PAW_FLEX = 45.0         # paw curls (deg) at mid-swing
SWING_HEIGHT = {"Hind": 8.0, "Front": 9.0}   # paw lift, cm
# Where a paw lands relative to its hip (shoulder) at the middle of the stance.
STANCE_LEAD = {"Hind": 1.0, "Front": 3.0}


# ------------------------------------------------------------------ pose
def body(p):
    """Root position and rotation at stride phase p."""
    frame_z = SPEED * p * STRIDE_FRAMES / FPS
    root = (0.0, periodic(BODY_HEIGHT, p), frame_z)
    r = mmul(roty(periodic(BODY_YAW, p)),
             mmul(rotx(periodic(BODY_PITCH, p)), rotz(periodic(BODY_ROLL, p))))
    return root, r


def paw(frame, prefix):
    """World position of the paw joint and its flex (deg) at this frame."""
    s, shift, leg = LEGS[prefix]
    where = leg["where"]
    c = frame / STRIDE_FRAMES - shift
    n = math.floor(c)
    u = c - n
    # Footprint of the stance that starts at stride n + shift: the paw lands
    # where the standing pose has it, relative to the hip at mid-stance.
    mid = n + shift + DUTY / 2
    hip_rest = leg["attach"][2] + (OFF["Spine"][2] + OFF["Chest"][2] if where == "Front" else 0)
    reach = leg["upper"][2] + leg["lower"][2] + leg["meta"][2]
    x, y = s * leg["attach"][0], -PAW_TIP[1]
    z0 = SPEED * mid * STRIDE_FRAMES / FPS + hip_rest + reach + STANCE_LEAD[where]
    if u <= DUTY:
        return (x, y, z0), 0.0
    v = (u - DUTY) / (1.0 - DUTY)
    z = z0 + STRIDE_LEN * smooth(v)
    lift = SWING_HEIGHT[where] * math.sin(math.pi * v) ** 2
    return (x, y + lift, z), PAW_FLEX * math.sin(math.pi * v) ** 2


def pose(frame):
    p = frame / STRIDE_FRAMES
    root, hips = body(p)
    loc = {"Hips": hips}
    bend = periodic(SPINE_BEND, p)
    loc["Spine"] = roty(0.5 * bend)
    loc["Chest"] = roty(0.5 * bend)
    chest = mmul(hips, mmul(loc["Spine"], loc["Chest"]))
    chest_pos = vadd(root, mvec(hips, vadd(OFF["Spine"], mvec(loc["Spine"], OFF["Chest"]))))
    # The head keeps its heading and only nods a little.
    heading = roty(periodic(BODY_YAW, p))
    head = mmul(heading, rotx(periodic(HEAD_NOD, p)))
    neck_world = mmul(chest, half_rotation(mmul(mT(chest), head)))
    loc["Neck"] = mmul(mT(chest), neck_world)
    loc["Head"] = mmul(mT(neck_world), head)
    loc["Tail"] = mmul(roty(periodic(TAIL, p, 1)), rotx(periodic(TAIL, p, 2)))

    lateral = mvec(heading, (1.0, 0.0, 0.0))
    for prefix, (s, shift, leg) in LEGS.items():
        where = leg["where"]
        parent, parent_pos = (chest, chest_pos) if where == "Front" else (hips, root)
        hip = vadd(parent_pos, mvec(parent, OFF[prefix + "UpLeg"]))
        toe, flex = paw(frame, prefix)
        u = (p - shift) % 1.0
        meta = mmul(heading, rotx(periodic(META[where], u)))
        hock = vsub(toe, mvec(meta, leg["meta"]))
        knee = two_bone(hip, hock, norm(leg["upper"]), norm(leg["lower"]), lateral,
                        1 if where == "Hind" else -1)
        thigh = bone_rotation(leg["upper"], vsub(knee, hip), lateral)
        shank = bone_rotation(leg["lower"], vsub(hock, knee), lateral)
        loc[prefix + "UpLeg"] = mmul(mT(parent), thigh)
        loc[prefix + "Leg"] = mmul(mT(thigh), shank)
        loc[prefix + "Foot"] = mmul(mT(shank), meta)
        loc[prefix + "Toe"] = mmul(mT(meta), rotx(flex))   # planted paws point along +Z
    return root, loc


# ------------------------------------------------------------------ check
def check(path):
    m, ok = open_and_check_ground(path)
    worst_slide, contacts = 0.0, {}
    for prefix in LEGS:
        pts = [m.track(prefix + "Toe"), m.track(prefix + "Toe_end")]
        st = stance_slides(pts, ground=0.01)
        contacts[prefix] = st
        worst_slide = max([worst_slide] + [c[2] for c in st])
        print("%-10s contacts (first frame, frames, slide mm): %s" % (
            prefix, ", ".join("%d %d %.3f" % c for c in st)))
    print("max stance slide: %.3f mm" % worst_slide)
    ok = ok and worst_slide <= 1.0
    # Every paw must be down for its share of each stride, in diagonal pairs.
    for prefix, (s, shift, leg) in LEGS.items():
        for stride in range(STRIDES):
            f = round((stride + shift + DUTY / 2) * STRIDE_FRAMES)
            if f >= m.nframes:
                continue
            y = m.world[f][prefix + "Toe_end"][0][1]
            if abs(y) > 0.1:
                print("%s: not on the ground at mid-stance frame %d (%.2f cm)" % (prefix, f, y))
                ok = False
    for prefix, (s, shift, leg) in LEGS.items():
        lift = max(m.world[f][prefix + "Toe_end"][0][1] for f in range(m.nframes))
        print("%-10s paw lift: %.2f cm; down %d of %d frames" % (
            prefix, lift, sum(c[1] for c in contacts[prefix]), m.nframes))
        ok = ok and lift > 3.0
    # Stifles bend forwards and elbows backwards, always.
    hips = lambda w: mvec(w["Hips"][1], (1, 0, 0))
    for prefix, (s, shift, leg) in LEGS.items():
        sign = 1 if leg["where"] == "Hind" else -1
        lo, hi = hinge_report(m, prefix + "UpLeg", prefix + "Leg", prefix + "Foot", hips, sign)
        print("%-10s %s flexion %.1f .. %.1f deg" % (
            prefix, "stifle" if sign > 0 else "elbow", lo, hi))
        ok = ok and lo > 5.0
    rz = m.track("Hips")
    speed = (rz[-1][2] - rz[0][2]) / ((m.nframes - 1) * m.frame_time)
    print("average speed: %.2f cm/s; stride %d frames = %.4f s, %.2f cm; hips height %.2f .. %.2f"
          % (speed, STRIDE_FRAMES, STRIDE_FRAMES / FPS, STRIDE_LEN,
             min(q[1] for q in rz), max(q[1] for q in rz)))
    ok = loop_and_speed_ok(m, speed, SPEED) and ok
    print("RESULT:", "PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    main(__doc__, check, SKELETON, NFRAMES, FPS, pose)
