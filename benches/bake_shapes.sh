#!/usr/bin/env bash
# The bake on the shapes artists hand over (BENCHMARKS.md, "Baking the shapes people model"): a
# hard-surface cube pair (benches/blender/cube_pair.py: 12 triangles as LOW, 388,800 as HIGH) with
# its faces along the axes, turned about two axes and about three, and the same cube's HIGH written
# as a sculpt without UVs; each baked at 1024² with one ray a texel and with 4 × 4 by
# `tutorial13 bake`, and by Blender's Cycles bake of the very same files (1 and 16 samples) in the
# same run, the two taking turns. Ours is the whole command, both files read; Blender's is its bake
# operator and the PNG save, the scene already built (as benches/bake.sh measures the sphere).
#
#   bash benches/bake_shapes.sh [DIR]   # DIR: where the pairs and the maps go (target/bench-shapes)
DEFAULT_DIR=target/bench-shapes
source "$(dirname "$0")/bake_setup.sh"
if ! command -v blender > /dev/null; then
  echo "blender: not installed (apt-get install blender python3-numpy); the ratios need it" >&2
  exit 1
fi

for shape in none two three sculpt; do
  pair="$dir/$shape"
  mkdir -p "$pair"
  case "$shape" in
    sculpt) python3 benches/blender/cube_pair.py "$pair" --turn three --no-uvs > /dev/null ;;
    *) python3 benches/blender/cube_pair.py "$pair" --turn "$shape" > /dev/null ;;
  esac
  for k in 1 4; do
    /usr/bin/env time -f %e -o "$pair/ours-$k.time" "$bin" bake "$pair/high.obj" "$pair/low.obj" \
      -o "$pair/ours-$k.png" --size 1024 --samples "$k" "${settings[@]}" > "$pair/ours-$k.log" 2>&1
    out="$pair/blender-$k"
    mkdir -p "$out"
    blender -b --factory-startup --python benches/blender/bake_pair.py -- --out "$out" \
      --high-obj "$pair/high.obj" --low-obj "$pair/low.obj" --size 1024 --samples $((k * k)) \
      "${settings[@]}" > "$out/blender.log" 2>&1
    python3 - "$shape" "$k" "$(cat "$pair/ours-$k.time")" "$out/blender_timings.json" <<'PY'
import json, sys
shape, k, ours, timings = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
t = json.load(open(timings))["timings"]
theirs = t["bake_operator_s"] + t["save_png8_s"]
print(f"{shape:>6} {k}x{k}: ours {ours:.2f} s, Blender bake + save {theirs:.2f} s: "
      f"{ours / theirs:.2f}x")
PY
  done
done
