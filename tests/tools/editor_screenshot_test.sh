#!/usr/bin/env bash
# The editor under Xvfb: `screenshot` renders the bundled walk for 20 frames and checks the PNG
# (size 1600x900, many colours, the viewport not blank); `broken` opens a truncated BVH file and
# checks that the editor still runs, exits 0 and names the file and line in its log; `evolve`
# starts the search from the editor, waits for two generations and checks the log reports them
# and the population is drawn (a green best run in the viewport) with the ghost's figures (finite,
# above zero) in the log; `fox` opens the shared Fox.glb
# and checks its skinned mesh is drawn (its orange coat fills the viewport, and does not with
# --no-mesh) and casts a shadow on the floor (dark floor pixels, none with --no-shadows).
# `bench` prints the editor's frame time with 16 characters while the search runs and saves the
# panels; `render` checks the frames of `sinew render`.
# Usage: editor_screenshot_test.sh SINEW_BINARY WORK_DIR (screenshot|broken|evolve|bench|render|fox)
#        [SHARED_DATA]
# Exit 77 (skipped) when xvfb-run is missing, or (fox) when the shared data is.
set -euo pipefail
sinew="$1"
work="$2"
mode="$3"
data="${SINEW_SHARED_DATA:-${4:-}}"
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIP: xvfb-run is not installed (apt-get install xvfb)"
  exit 77
fi
mkdir -p "$work"
xvfb=(xvfb-run -a -s "-screen 0 1600x900x24")

case "$mode" in
  screenshot)
    png="$work/editor_walk.png"
    rm -f "$png"
    "${xvfb[@]}" "$sinew" edit --screenshot "$png" --frames 20
    test -s "$png" || { echo "FAIL: no screenshot at $png"; exit 1; }
    # A PNG reader with the standard library only: size, then distinct colours overall and in
    # the viewport (the middle of the window, where the characters are).
    python3 - "$png" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
pos, idat, width, height = 8, b"", 0, 0
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    if kind == b"IHDR":
        width, height, depth, color = struct.unpack(">IIBB", body[:10])
        assert depth == 8 and color == 2, f"expected 8-bit RGB, got depth {depth} colour {color}"
    elif kind == b"IDAT":
        idat += body
    pos += 12 + length
if (width, height) != (1600, 900):
    sys.exit(f"FAIL: screenshot is {width}x{height}, expected 1600x900")
raw = zlib.decompress(idat)
stride = width * 3
rows, prev = [], bytearray(stride)
for y in range(height):
    f = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    if f == 1:
        for i in range(3, stride): line[i] = (line[i] + line[i - 3]) & 255
    elif f == 2:
        line = bytearray((a + b) & 255 for a, b in zip(line, prev))
    elif f == 3:
        for i in range(stride):
            left = line[i - 3] if i >= 3 else 0
            line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
    elif f == 4:
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], (prev[i - 3] if i >= 3 else 0)
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
def colours(x0, x1, y0, y1):
    return {bytes(rows[y][3 * x:3 * x + 3]) for y in range(y0, y1, 2) for x in range(x0, x1, 2)}
everything = colours(0, width, 0, height)
viewport = colours(width * 3 // 10, width * 6 // 10, height // 6, height * 2 // 3)
print(f"screenshot {width}x{height}: {len(everything)} colours, {len(viewport)} in the viewport")
if len(everything) <= 50 or len(viewport) <= 50:
    sys.exit("FAIL: the screenshot looks blank")
PY
    ;;
  broken)
    bvh="$work/broken.bvh"
    printf 'HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n  CHANNELS 6 Xposition\n' > "$bvh"
    out="$work/broken.log"
    "${xvfb[@]}" "$sinew" edit "$bvh" --screenshot "$work/broken.png" --frames 3 > "$out" 2>&1 \
      || { cat "$out"; echo "FAIL: the editor exited non-zero on a broken file"; exit 1; }
    cat "$out"
    grep -Eq 'error: .*broken\.bvh:[0-9]+' "$out" \
      || { echo "FAIL: the log does not name broken.bvh and a line"; exit 1; }
    test -s "$work/broken.png" || { echo "FAIL: no screenshot"; exit 1; }
    ;;
  evolve)
    png="$work/editor_evolve.png"
    out="$work/evolve.log"
    rm -f "$png"
    # 16 characters shown while the second generation is published (issue 16): the UI thread
    # must never wait for the search (every poll of its snapshot under 50 ms); the longest frame
    # after the first second is printed, and bounded only by SINEW_FRAME_BOUND_MS when set (a
    # generous bound, not the 250 ms goal: speed is measured by editor_bench, and this test also
    # runs beside others and under the sanitizers).
    "${xvfb[@]}" "$sinew" edit --evolve --screenshot "$png" --frames 5 --evolve-generations 2 \
      --shown 16 > "$out" 2>&1 || { cat "$out"; echo "FAIL: the editor exited non-zero"; exit 1; }
    grep -E 'evolve: |generation [12] |longest frame' "$out"
    grep -q 'generation 2 (' "$out" || { echo "FAIL: no second generation in the log"; exit 1; }
    grep -q ', 0 polls over 50 ms' "$out" \
      || { echo "FAIL: the UI thread waited for the search's snapshot"; exit 1; }
    longest=$(sed -n 's/.*longest frame after the first second \([0-9.]*\) ms.*/\1/p' "$out")
    [ -n "$longest" ] || { echo "FAIL: no longest frame reported"; exit 1; }
    if [ -n "${SINEW_FRAME_BOUND_MS:-}" ] &&
       awk -v l="$longest" -v b="$SINEW_FRAME_BOUND_MS" 'BEGIN { exit !(l > b) }'; then
      echo "FAIL: a frame took $longest ms (bound $SINEW_FRAME_BOUND_MS ms)"; exit 1
    fi
    awk -v l="$longest" 'BEGIN { print (l <= 250 ? "within" : "over") " the 250 ms goal: " l " ms" }'
    # The physics ghost (on by default): the chosen run's joints against the search's target at
    # the replayed frame's time, in degrees; a simulated run is never exactly on its target, and
    # every figure must be a finite number.
    ghost=$(grep -E 'ghost of individual [0-9]+ at ' "$out" || true)
    [ -n "$ghost" ] || { echo "FAIL: no ghost figures in the log"; exit 1; }
    echo "$ghost"
    echo "$ghost" | awk '{
      for (i = 1; i <= NF; ++i) { if ($i == "by") mean = $(i + 1); if ($i == "deg" && $(i + 1) == "at") worst = $(i - 1) }
      if (!(mean ~ /^[0-9]+\.[0-9]+$/ && worst ~ /^[0-9]+\.[0-9]+$/)) { print "FAIL: ghost figures not finite: " mean ", " worst; exit 1 }
      if (!(mean > 0 && worst >= mean)) { print "FAIL: ghost deviation " mean " mean, " worst " at most"; exit 1 }
    }' || exit 1
    python3 - "$png" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
pos, idat, width = 8, b"", 0
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    if kind == b"IHDR": width = struct.unpack(">I", data[pos + 8:pos + 12])[0]
    elif kind == b"IDAT": idat += data[pos + 8:pos + 8 + length]
    pos += 12 + length
raw, stride = zlib.decompress(idat), width * 3
# Unfiltered scan for the best run's green (filters make exact pixels uncertain: count pixels
# of any row filter type whose bytes read as a clearly green colour).
rows, prev = [], bytearray(stride)
for y in range(len(raw) // (stride + 1)):
    f = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - 3] if i >= 3 else 0
        b = prev[i]
        c = prev[i - 3] if i >= 3 else 0
        if f == 1: line[i] = (line[i] + a) & 255
        elif f == 2: line[i] = (line[i] + b) & 255
        elif f == 3: line[i] = (line[i] + ((a + b) >> 1)) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
green = sum(1 for row in rows[::2] for x in range(0, width, 2)
            if row[3 * x + 1] > 120 and row[3 * x + 1] > row[3 * x] + 50 and row[3 * x + 1] > row[3 * x + 2] + 50)
print(f"evolve screenshot: {green} green samples (the best run)")
if green < 200:
    sys.exit("FAIL: the population's best run is not drawn")
PY
    ;;
  bench)
    # The frame-time benchmark (bench/CMakeLists.txt's editor_bench, labelled bench): the clip
    # alone, 16 characters while the search runs, the same scene paused, and the search's rate
    # with the editor drawing and paused; prints its figures. The panels are saved too (the user
    # guide's pictures): each must exist.
    out="$work/bench.txt"
    "${xvfb[@]}" "$sinew" edit --bench --shown 16 --frames 60 --evolve-minutes 10 \
      --screenshot "$work/bench.png" --panel-shots "$work/panels" | tee "$out"
    grep -q "the clip alone: *median" "$out" || { echo "FAIL: no idle frame time"; exit 1; }
    grep -q "16 characters while the search runs: *median" "$out" || { echo "FAIL: no search frame time"; exit 1; }
    grep -q "paused, while the search runs: *median" "$out" || { echo "FAIL: no paused frame time"; exit 1; }
    grep -q "with the editor drawing" "$out" || { echo "FAIL: no evaluation rates"; exit 1; }
    for panel in files body log timeline spectrum style evolve export viewport; do
      test -s "$work/panels/$panel.png" || { echo "FAIL: no $panel.png"; exit 1; }
    done
    echo "PASS: frame times printed, 9 panels saved"
    ;;
  render)
    # sinew render: the bundled walk (4.27 s) at 5 fps as a turntable: 22 frames of 480x270.
    rm -rf "$work/frames"
    "${xvfb[@]}" "$sinew" render "$(dirname "$0")/../../assets/biped_walk.bvh" -o "$work/frames" \
      --fps 5 --size 480x270 --turntable
    count=$(ls "$work/frames" | grep -c '^frame_[0-9]*\.png$')
    [ "$count" -eq 22 ] || { echo "FAIL: $count frames, expected 22"; exit 1; }
    python3 - "$work/frames/frame_0001.png" "$work/frames/frame_0012.png" <<'PY'
import struct, sys, zlib
for path in sys.argv[1:]:
    data = open(path, "rb").read()
    width, height = struct.unpack(">II", data[16:24])
    if (width, height) != (480, 270):
        sys.exit(f"FAIL: {path} is {width}x{height}, expected 480x270")
    if len(set(zlib.decompress(b"".join(
            data[p + 8:p + 8 + struct.unpack(">I", data[p:p + 4])[0]]
            for p in [i - 4 for i in range(len(data)) if data[i:i + 4] == b"IDAT"])))) < 64:
        sys.exit(f"FAIL: {path} looks blank")
print("render: 22 frames of 480x270, not blank")
PY
    ;;
  fox)
    fox="$data/gltf/Fox.glb"
    if [ ! -f "$fox" ]; then
      echo "SKIP: real test data not found at $data (the ../shared folder beside the checkout)"
      exit 77
    fi
    pixels="$(dirname "$0")/png_pixels.py"
    viewport=(372 0 1116 770)  # the 3D view of the 1600x900 window, less its borders
    for run in mesh no-mesh no-shadows; do
      flags=()
      [ "$run" = mesh ] || flags=("--$run")
      out="$work/fox_$run.log"
      "${xvfb[@]}" "$sinew" edit "$fox" --animation Walk --screenshot "$work/fox_$run.png" \
        --frames 10 "${flags[@]}" > "$out" 2>&1 || { cat "$out"; echo "FAIL: the editor exited non-zero"; exit 1; }
      if grep -q 'error:' "$out"; then cat "$out"; echo "FAIL: errors in the log"; exit 1; fi
      declare "orange_${run//-/_}=$(python3 "$pixels" "$work/fox_$run.png" orange "${viewport[@]}")"
      declare "dark_${run//-/_}=$(python3 "$pixels" "$work/fox_$run.png" dark "${viewport[@]}")"
    done
    grep -E 'skinned mesh|1/100' "$work/fox_mesh.log"
    echo "Fox: orange samples $orange_mesh (capsules only: $orange_no_mesh); dark floor samples" \
         "$dark_mesh (shadows off: $dark_no_shadows)"
    grep -q 'Fox.glb: 1 skinned mesh, 1,728 vertices' "$work/fox_mesh.log" \
      || { echo "FAIL: the log does not report the Fox's mesh"; exit 1; }
    # 1,800 samples since the camera frames the character (and its model beside it) rather than the
    # origin; 48 with capsules only.
    [ "$orange_mesh" -ge 1200 ] || { echo "FAIL: the Fox's coat is not in the viewport"; exit 1; }
    [ "$orange_no_mesh" -lt 1000 ] || { echo "FAIL: orange without the mesh: the check is blind"; exit 1; }
    [ "$dark_mesh" -ge 1000 ] || { echo "FAIL: no shadow on the floor"; exit 1; }
    [ "$dark_no_shadows" -lt 300 ] || { echo "FAIL: dark pixels without shadows: the check is blind"; exit 1; }
    ;;
  *)
    echo "unknown mode $mode"; exit 2 ;;
esac
echo PASS
