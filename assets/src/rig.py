"""Shared pieces of the creature asset scripts (quadruped, hopper, stepper).

Standard library only.  Maths and BVH conventions are those of make_biped_walk.py
(which stays self-contained): centimetres, Y up, facing +Z, left = +X;
"Zrotation Xrotation Yrotation" means R = Rz(z) * Rx(x) * Ry(y) and
p_parent = OFFSET + R * p_child.  A skeleton is (name, offset, children); name
None is an End Site.

The checking half (read_bvh, Motion) parses the written text and rebuilds
rotations from the axis-angle formula, not from the generator's matrices, so a
sign slip in the generator shows up in --check.
"""
import math
import sys


# ------------------------------------------------------------------ maths
def vadd(a, b): return tuple(x + y for x, y in zip(a, b))
def vsub(a, b): return tuple(x - y for x, y in zip(a, b))
def vmul(a, k): return tuple(x * k for x in a)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def norm(a): return math.sqrt(dot(a, a))
def unit(a): return vmul(a, 1.0 / norm(a))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0])
def mmul(a, b): return tuple(tuple(dot(r, c) for c in zip(*b)) for r in a)
def mvec(m, v): return tuple(dot(r, v) for r in m)
def mT(m): return tuple(zip(*m))
def cols(a, b, c): return mT((a, b, c))     # matrix with columns a, b, c


def rot(axis, d):
    """Right-handed rotation by d degrees about the X, Y or Z axis."""
    c, s = math.cos(math.radians(d)), math.sin(math.radians(d))
    return {"x": ((1, 0, 0), (0, c, -s), (0, s, c)),
            "y": ((c, 0, s), (0, 1, 0), (-s, 0, c)),
            "z": ((c, -s, 0), (s, c, 0), (0, 0, 1))}[axis]


def rotx(d): return rot("x", d)
def roty(d): return rot("y", d)
def rotz(d): return rot("z", d)
def zxy(z, x, y): return mmul(rotz(z), mmul(rotx(x), roty(y)))


IDENTITY = ((1, 0, 0), (0, 1, 0), (0, 0, 1))


def euler_zxy(m):
    """Inverse of zxy(): (z, x, y) in degrees with R = Rz Rx Ry."""
    x = math.asin(max(-1.0, min(1.0, m[2][1])))
    return tuple(math.degrees(a) for a in
                 (math.atan2(-m[0][1], m[1][1]), x, math.atan2(-m[2][0], m[2][2])))


def hermite(v0, v1, m0, m1, u, h=1.0):
    """Cubic Hermite on a segment of length h; tangents per unit parameter."""
    u2, u3 = u * u, u * u * u
    return ((2 * u3 - 3 * u2 + 1) * v0 + (u3 - 2 * u2 + u) * h * m0
            + (3 * u2 - 2 * u3) * v1 + (u3 - u2) * h * m1)


def periodic(table, p, col=1):
    """Periodic Catmull-Rom through (phase, ...) rows; first phase is 0."""
    n = len(table)
    t = lambda i: table[i % n][0] + i // n       # key phase, wrapped
    v = lambda i: table[i % n][col]
    m = lambda i: (v(i + 1) - v(i - 1)) / (t(i + 1) - t(i - 1))
    p %= 1.0
    i = max(j for j in range(n) if table[j][0] <= p)
    h = t(i + 1) - t(i)
    return hermite(v(i), v(i + 1), m(i), m(i + 1), (p - t(i)) / h, h)


def smooth(u):
    """0 -> 1 with zero slope at both ends (smoothstep)."""
    u = min(1.0, max(0.0, u))
    return u * u * (3 - 2 * u)


# ------------------------------------------------------------------ skeleton
def joint_offsets(skeleton):
    """{name: OFFSET} of every joint (End Sites under '<parent>_end')."""
    out = {}

    def walk(node, parent):
        name, off, kids = node
        key = name if name is not None else parent + "_end"
        out[key] = off
        for k in kids:
            walk(k, key)
    walk(skeleton, None)
    return out


def bone_rotation(rest_dir, new_dir, lateral):
    """World rotation taking a bone along rest_dir (in the YZ plane at rest, so
    perpendicular to +X) onto new_dir, with +X going onto `lateral` (made
    perpendicular to new_dir).  Two bones solved with the same lateral differ
    by a pure rotation about that axis: a hinge."""
    r0 = unit(rest_dir)
    n = unit(lateral)
    r1 = unit(new_dir)
    n1 = unit(vsub(n, vmul(r1, dot(n, r1))))
    x0 = (1.0, 0.0, 0.0)
    return mmul(cols(n1, r1, cross(n1, r1)), mT(cols(x0, r0, cross(x0, r0))))


def two_bone(hip, target, upper, lower, lateral, bend):
    """Knee position for a two-bone chain from `hip` reaching `target`.

    The knee lies in the plane through hip and target normal to `lateral`, on
    the forward side (bend = +1, a knee or stifle) or the backward side
    (bend = -1, an elbow), so it never flips.  Fails when out of reach."""
    d = norm(vsub(target, hip))
    if d > (upper + lower) * 0.999 or d < abs(upper - lower) * 1.001:
        raise SystemExit("limb cannot reach its target (%.2f of %.2f cm): retune the keys"
                         % (d, upper + lower))
    dh = unit(vsub(target, hip))
    n = unit(vsub(lateral, vmul(dh, dot(lateral, dh))))
    perp = vmul(unit(cross(dh, n)), bend)     # +1: forward of the hip-target line
    a = (upper ** 2 - lower ** 2 + d * d) / (2 * d)
    return vadd(hip, vadd(vmul(dh, a), vmul(perp, math.sqrt(upper ** 2 - a * a))))


# ------------------------------------------------------------------ BVH out
def fmt(v):
    s = "%.6f" % v
    return "0.000000" if s == "-0.000000" else s    # no "-0" noise in diffs


def write_bvh(out, skeleton, nframes, fps, pose):
    """pose(frame) -> (root position, {joint: local rotation matrix})."""
    order, rots = [], "Zrotation Xrotation Yrotation"

    def node(n, depth):
        name, off, kids = n
        tab = "\t" * depth
        if name is None:
            out.write("%sEnd Site\n%s{\n" % (tab, tab))
        else:
            order.append(name)
            out.write("%s%s %s\n%s{\n" % (tab, "JOINT" if depth else "ROOT", name, tab))
        out.write("%s\tOFFSET %s\n" % (tab, " ".join(fmt(c) for c in off)))
        if name is not None:
            out.write("%s\tCHANNELS %s\n" % (
                tab, "3 " + rots if depth else "6 Xposition Yposition Zposition " + rots))
        for k in kids:
            node(k, depth + 1)
        out.write("%s}\n" % tab)

    out.write("HIERARCHY\n")
    node(skeleton, 0)
    out.write("MOTION\nFrames: %d\nFrame Time: %.7f\n" % (nframes, 1.0 / fps))
    for f in range(nframes):
        root, loc = pose(f)
        vals = list(root) + [a for name in order for a in euler_zxy(loc.get(name, IDENTITY))]
        out.write(" ".join(fmt(v) for v in vals) + "\n")


# ------------------------------------------------------------------ check
def _axis_rot(k, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    skew = (0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0)
    return tuple(tuple((c if i == j else 0.0) + (1 - c) * k[i] * k[j] + s * skew[3 * i + j]
                       for j in range(3)) for i in range(3))


def _bvh_rot(z, x, y):   # channels left to right = matrix product order
    return mmul(_axis_rot((0, 0, 1), z), mmul(_axis_rot((1, 0, 0), x), _axis_rot((0, 1, 0), y)))


class Motion:
    """A parsed BVH file and its forward kinematics.

    joints: (name, parent index, offset, channel count); End Sites are named
    '<parent>_end'.  frames: the numbers of each frame.  world: per frame,
    {name: (position, rotation)}."""

    def __init__(self, path):
        tok = open(path).read().split()
        self.joints, pos = [], 1    # skip HIERARCHY

        def parse(parent):
            nonlocal pos
            name = self.joints[parent][0] + "_end" if tok[pos] == "End" else tok[pos + 1]
            off, pos, nch = tuple(float(v) for v in tok[pos + 4:pos + 7]), pos + 7, 0
            if tok[pos] == "CHANNELS":
                nch = int(tok[pos + 1])
                pos += 2 + nch
            self.joints.append((name, parent, off, nch))
            me = len(self.joints) - 1
            while tok[pos] != "}":
                parse(me)
            pos += 1

        parse(None)
        self.nframes, self.frame_time = int(tok[pos + 2]), float(tok[pos + 5])
        data, width = [float(v) for v in tok[pos + 6:]], sum(j[3] for j in self.joints)
        assert len(data) == self.nframes * width, "bad motion block"
        self.frames = [data[i * width:(i + 1) * width] for i in range(self.nframes)]
        self.world = []
        for fr in self.frames:
            w, i = {}, 0
            for name, par, off, nch in self.joints:
                vals, i = fr[i:i + nch], i + nch
                r = _bvh_rot(*vals[-3:]) if nch else _bvh_rot(0, 0, 0)
                pp, pr = w[self.joints[par][0]] if par is not None else (vals[:3], None)
                w[name] = (tuple(pp), r) if pr is None else (vadd(pp, mvec(pr, off)), mmul(pr, r))
            self.world.append(w)

    def names(self):
        return [j[0] for j in self.joints]

    def summary(self):
        return "joints: %d (+%d End Sites); frames: %d at %.7f s" % (
            sum(1 for j in self.joints if j[3]), sum(1 for j in self.joints if not j[3]),
            self.nframes, self.frame_time)

    def lowest(self):
        """(height, name, frame) of the lowest joint or End Site over the clip."""
        return min((w[j[0]][0][1], j[0], f) for f, w in enumerate(self.world) for j in self.joints)

    def loop_error(self, travel_channel=2):
        """Largest channel difference between the first and last frame, except
        the root's travel channel."""
        return max(abs(a - b) for i, (a, b) in enumerate(zip(self.frames[0], self.frames[-1]))
                   if i != travel_channel)

    def track(self, name):
        return [w[name][0] for w in self.world]


def stance_slides(points, ground=0.1):
    """Contacts of one foot: [(first frame, frames, slide mm)], where a foot
    is down while any of its `points` (lists of per-frame positions) is within
    `ground` cm of y = 0 (0.1 cm: a swing's first
    and last frames graze the ground), and slide is how far each grounded point moves while
    grounded."""
    n = len(points[0])
    down = [any(p[f][1] < ground for p in points) for f in range(n)] + [False]
    out, start = [], None
    for f, d in enumerate(down):
        if d and start is None:
            start = f
        elif not d and start is not None:
            worst = 0.0
            for tr in points:
                on = [tr[g] for g in range(start, f) if tr[g][1] < ground]
                worst = max([worst] + [norm(vsub(q, on[0])) * 10 for q in on])
            out.append((start, f - start, worst))
            start = None
    return out


def hinge_report(motion, upper, lower, end, lateral_of, sign):
    """Signed flexion (deg) of the joint between bones upper->lower->end about
    the lateral axis `lateral_of(world)`: positive = bent the way `sign` says.
    Returns (min, max) over the clip."""
    flex = []
    for w in motion.world:
        h, k, a = w[upper][0], w[lower][0], w[end][0]
        th, sh = vsub(k, h), vsub(a, k)
        flex.append(sign * math.degrees(math.atan2(dot(cross(th, sh), lateral_of(w)),
                                                   dot(th, sh))))
    return min(flex), max(flex)


def half_rotation(m):
    """The rotation about the same axis by half the angle."""
    angle = math.acos(max(-1.0, min(1.0, (m[0][0] + m[1][1] + m[2][2] - 1) / 2)))
    if angle < 1e-9:
        return IDENTITY
    axis = unit((m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]))
    return _axis_rot(axis, math.degrees(angle / 2))


def open_and_check_ground(path):
    """Reads a written BVH, prints its summary and its lowest point; (motion, nothing below ground)."""
    m = Motion(path)
    print(m.summary())
    low = m.lowest()
    print("lowest joint or end site: %.3f cm (%s, frame %d) -> %s" % (
        low[0] + 0.0, low[1], low[2], "OK" if low[0] >= -0.05 else "BELOW GROUND"))
    return m, low[0] >= -0.05


def loop_and_speed_ok(m, speed, expected_speed):
    """Prints the loop closure and says whether the loop closes and the speed is the authored one."""
    loop = m.loop_error()
    print("loop: first vs last frame, all channels but root Z: max diff %.6f" % loop)
    return loop < 1e-6 and abs(speed - expected_speed) < 1e-3


def main(doc, check, skeleton, nframes, fps, pose):
    """The scripts' command line: no argument writes the BVH to stdout, --check FILE checks it."""
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        sys.exit(0 if check(sys.argv[2]) else 1)
    elif len(sys.argv) == 1:
        write_bvh(sys.stdout, skeleton, nframes, fps, pose)
    else:
        sys.exit(doc)
