#!/usr/bin/env bash
# The bake benchmark (BENCHMARKS.md, "Baking"): `tutorial13 bake` at 2048² with 1 and 4 × 4 rays per
# texel from a 1,310,720-triangle bumpy icosphere onto a 32 × 16 UV sphere, and Blender's Cycles
# bake of the very same files in the same run where Blender is installed (Debian's `blender`;
# skipped, with a line, where it is not). Our figure is the whole command, both files read.
#
#   bash benches/bake.sh [DIR]      # DIR: where the pair and the maps go (default target/bench-bake)
#   BAKE_ROUNDS=N bash benches/bake.sh   # N - 1 more rounds of the 4 × 4 bake, Blender's and ours in turn
DEFAULT_DIR=target/bench-bake
source "$(dirname "$0")/bake_setup.sh"

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
import sys
sys.path.insert(0, "benches")
from pairs import sphere
out = sys.argv[1]
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

# More rounds of the 4 × 4 bake, Blender's and ours in turn: from one run to the next this machine's
# times move by 5 % and more, as much as the changes worth measuring.
rounds="${BAKE_ROUNDS:-1}"
if command -v blender > /dev/null && [ "$rounds" -gt 1 ]; then
  for round in $(seq 2 "$rounds"); do
    out="$dir/blender-4"
    blender -b --factory-startup --python benches/blender/bake_pair.py -- --out "$out" \
      --size 2048 --samples 16 "${settings[@]}" > "$out/blender.log" 2>&1
    theirs=$(python3 - "$out/blender_timings.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["timings"]
print(f"{t['bake_operator_s'] + t['save_png8_s']:.2f}")
PY
)
    ours=$(seconds "ours-4" "$bin" bake "$pair/high.obj" "$pair/low.obj" -o "$dir/ours-4.png" \
      --size 2048 --samples 4 "${settings[@]}")
    echo "round $round, 4x4: Blender bake + save $theirs s, ours $ours s: $(python3 -c "print(f'{$ours / $theirs:.2f}x')")"
  done
fi
