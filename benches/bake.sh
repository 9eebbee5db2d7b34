#!/usr/bin/env bash
# The bake benchmark (BENCHMARKS.md, "Baking"): `tutorial13 bake` at 2048² with 1 and 4 × 4 rays per
# texel from a 1,310,720-triangle bumpy icosphere onto a 32 × 16 UV sphere, and Blender's Cycles
# bake of the very same files in the same run where Blender is installed (Debian's `blender`;
# skipped, with a line, where it is not). Our figure is the whole command, both files read.
#
#   bash benches/bake.sh [DIR]      # DIR: where the pair and the maps go (default target/bench-bake)
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-target/bench-bake}"
mkdir -p "$dir"
cargo build --release --quiet
bin="$PWD/target/release/tutorial13"
settings=(--extrusion 0.05 --max-distance 0.1 --margin 16)

# /usr/bin/time's elapsed seconds of a command, its log kept in $dir/$name.log.
seconds() {
  local name="$1"; shift
  /usr/bin/env time -f %e -o "$dir/$name.time" "$@" > "$dir/$name.log" 2>&1
  cat "$dir/$name.time"
}

if command -v blender > /dev/null; then
  for k in 1 4; do
    # Blender's bake samples are rays per texel: K × K of ours.
    out="$dir/blender-$k"
    mkdir -p "$out"
    blender -b --factory-startup --python benches/blender/bake_pair.py -- --out "$out" \
      --size 2048 --samples $((k * k)) "${settings[@]}" > "$out/blender.log" 2>&1
    python3 - "$out/blender_timings.json" "$k" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["timings"]
k = sys.argv[2]
print(f"blender {k}x{k}: bake {t['bake_operator_s']:.2f} s, save 8-bit {t['save_png8_s']:.2f} s, "
      f"bake + save {t['bake_operator_s'] + t['save_png8_s']:.2f} s")
PY
  done
  pair="$dir/blender-1"
else
  echo "blender: not installed, its bake skipped (apt-get install blender python3-numpy)"
  pair="$dir/ours"
  mkdir -p "$pair"
  # Without Blender, a pair of our own of the same sizes: a bumpy UV sphere of 1024 × 640
  # segments (1,308,672 triangles) and the 32 × 16 one.
  "$bin" bake --help > /dev/null
  python3 - "$pair" <<'PY'
import math, sys
out = sys.argv[1]
def sphere(path, segments, rings, amp):
    with open(path, "w") as f:
        pts = [(0.0, 0.0)] + [(math.pi * r / rings, 2 * math.pi * s / segments)
                              for r in range(1, rings) for s in range(segments)] + [(math.pi, 0.0)]
        for th, ph in pts:
            u = (math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph))
            r = 1 + amp * math.cos(12 * u[0]) * math.cos(12 * u[1]) * math.cos(12 * u[2])
            f.write("v %.7f %.7f %.7f\n" % (u[0] * r, u[1] * r, u[2] * r))
        for r in range(1, rings):
            for s in range(segments + 1):
                f.write("vt %.7f %.7f\n" % (s / segments, 1 - r / rings))
        for v in (1.0, 0.0):
            for s in range(segments):
                f.write("vt %.7f %.1f\n" % ((s + 0.5) / segments, v))
        last = len(pts)
        V = lambda r, s: 1 if r == 0 else last if r == rings else 2 + (r - 1) * segments + s % segments
        ring_vts = (rings - 1) * (segments + 1)
        T = lambda r, s: ring_vts + s + 1 if r == 0 else ring_vts + segments + s + 1 if r == rings else (r - 1) * (segments + 1) + s + 1
        c = lambda r, s, p: "%d/%d" % (V(r, s), T(r, p if r in (0, rings) else s))
        for s in range(segments):
            f.write("f %s %s %s\n" % (c(0, s, s), c(1, s, s), c(1, s + 1, s)))
            for r in range(1, rings - 1):
                a, b, cc, d = c(r, s, s), c(r + 1, s, s), c(r + 1, s + 1, s), c(r, s + 1, s)
                f.write("f %s %s %s\nf %s %s %s\n" % (a, b, cc, a, cc, d))
            f.write("f %s %s %s\n" % (c(rings - 1, s, s), c(rings, s, s), c(rings - 1, s + 1, s)))
sphere(out + "/high.obj", 1024, 640, 0.02)
sphere(out + "/low.obj", 32, 16, 0.0)
PY
fi

for k in 1 4; do
  s=$(seconds "ours-$k" "$bin" bake "$pair/high.obj" "$pair/low.obj" -o "$dir/ours-$k.png" \
      --size 2048 --samples "$k" "${settings[@]}")
  split=$(grep -oE "(read .* in [0-9.]+ s|frames in [0-9.]+ s|BVH over .* in [0-9.]+ s|rays in [0-9.]+ s|margin of .* in [0-9.]+ s|written in [0-9.]+ s)" "$dir/ours-$k.log" | grep -oE "[0-9.]+ s$" | tr '\n' ' ')
  echo "ours ${k}x${k}: ${s} s in all (read, frames, BVH, rays, margin, write: ${split})"
done

# Agreement with Blender's bake of the same files: 16-bit maps, texels inside LOW's UV triangles.
if command -v blender > /dev/null; then
  "$bin" bake "$pair/high.obj" "$pair/low.obj" -o "$dir/ours-16bit.png" --size 2048 --depth 16 \
    "${settings[@]}" > /dev/null 2>&1
  echo "agreement with Blender's map (16 bits):"
  python3 benches/blender/compare.py "$dir/ours-16bit.png" "$pair/blender_normal16.png" \
    --uv-mask "$pair/low.obj" | sed -n 2p
fi
