#!/usr/bin/env python3
"""Push robustness of an evolved controller, over a whole stride.

  bench/push_robustness.py SINEW CLIP BEST_JSON [ANALYSIS_JSON]

A push is an impulse on the pelvis (`sinew simulate --push`), forward along the clip's travel,
back, to the left and to the right; it is held when the replay keeps walking 3 s after it. One
push at one moment says as much about the moment as about the gait (a push just before a
touchdown and one just after differ), so every push is tried at five moments spread over one
stride of the clip from 2 s on. Prints one line:

  f/b/l/r ALL_MOMENTS  f/b/l/r AT_2S  HELD_AT_AIM/20

ALL_MOMENTS: per direction, the largest impulse of 10/20/40/60/80 N s held at all five moments;
AT_2S: the same at 2 s alone (the bench's measure before 2026-12-07); HELD_AT_AIM: of the 20
pushes of 40 N s (the issue's aim: four directions x five moments), how many were held.
ANALYSIS_JSON (`sinew analyze --json`) gives the travel and the stride; without it, forward is +Z
and the stride 1 s. A replay that fails (sinew exits non-zero: a crash, a refused file) is
counted as not held and named on stderr with its exit code and last message.
"""
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

LEVELS = [10, 20, 40, 60, 80]  # N s
AIM = 40
MOMENTS = 5
START_S = 2.0
AFTER_S = 3.0


def travel_and_stride(analysis):
    forward, stride = (0.0, 1.0), 1.0
    try:
        a = json.load(open(analysis))
        v = a["travel_velocity_m_s"]
        n = (v[0] ** 2 + v[2] ** 2) ** 0.5
        if n > 0.05:
            forward = (v[0] / n, v[2] / n)
        if a.get("period_s", 0) > 0:
            stride = float(a["period_s"])
    except (OSError, KeyError, ValueError, TypeError):
        pass
    return forward, stride


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    sinew, clip, best = sys.argv[1:4]
    forward, stride = travel_and_stride(sys.argv[4] if len(sys.argv) > 4 else "")
    fx, fz = forward
    directions = [(fx, fz), (-fx, -fz), (fz, -fx), (-fz, fx)]  # forward, back, left, right
    direction_names = ["forward", "back", "left", "right"]
    moments = [START_S + stride * k / MOMENTS for k in range(MOMENTS)]
    held_cache = {}

    def run(key):  # one pushed replay: held?
        direction, impulse, moment = key
        dx, dz = directions[direction]
        fd, out = tempfile.mkstemp(suffix=".json")
        os.close(fd)
        try:
            done = subprocess.run(
                [sinew, "simulate", "--rig", clip, "--controller", best, "--seconds",
                 f"{moment + AFTER_S:.4f}", "--push",
                 f"{moment:.4f},{dx * impulse:.3f},0,{dz * impulse:.3f}", "--json", out],
                capture_output=True, text=True)
            if done.returncode != 0:  # not a fall: say so, and count it as not held
                last = (done.stderr.strip().splitlines() or ["no message"])[-1]
                print(f"push_robustness: the replay pushed {impulse} N s ({direction_names[direction]}) "
                      f"at {moment:.2f} s failed (exit {done.returncode}): {last}; counted as not held",
                      file=sys.stderr)
                return False
            return not json.load(open(out))["fell"]
        finally:
            os.remove(out)

    pool = concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1)

    def held_all(direction, impulse, at):  # the moments of `at` in parallel, cached
        keys = [(direction, impulse, m) for m in at if (direction, impulse, m) not in held_cache]
        for key, result in zip(keys, pool.map(run, keys)):
            held_cache[key] = result
        return [held_cache[(direction, impulse, m)] for m in at]

    def largest(direction, at):
        best_held = 0
        for impulse in LEVELS:
            if not all(held_all(direction, impulse, at)):
                break
            best_held = impulse
        return str(best_held)

    every = "/".join(largest(d, moments) for d in range(4))
    first = "/".join(largest(d, moments[:1]) for d in range(4))
    at_aim = sum(sum(held_all(d, AIM, moments)) for d in range(4))
    pool.shutdown()
    print(f"{every} {first} {at_aim}/{4 * MOMENTS}")


if __name__ == "__main__":
    main()
