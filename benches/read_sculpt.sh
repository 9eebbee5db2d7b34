#!/usr/bin/env bash
# The sculpt read benchmark (BENCHMARKS.md, "Reading a sculpt without UVs"): a bake's HIGH, a bumpy
# UV sphere of 1024 × 641 segments (1,310,720 triangles, with `vn`), written with UVs
# (`f v/vt/vn`) and without (`f v//vn`, as sculpting tools export), each read by `tutorial13 bake`
# round after round, alternating, in one run. LOW is a triangle without UVs, which the bake refuses
# once both files are read: what is timed is HIGH's read alone (no BVH, no rays). Each figure is
# /usr/bin/time's wall time and maximum resident size of the whole command; medians of the rounds.
#
#   bash benches/read_sculpt.sh [DIR] [BINARY…]   # DIR default target/bench-read; BINARY default
#                                                 # target/release/tutorial13 (several: compared)
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-target/bench-read}"
shift || true
bins=("$@")
if [ ${#bins[@]} -eq 0 ]; then
  cargo build --release --quiet
  bins=("$PWD/target/release/tutorial13")
fi
rounds="${ROUNDS:-5}"
mkdir -p "$dir"
if [ ! -s "$dir/without.obj" ]; then
  python3 - "$dir" <<'PY'
import sys
sys.path.insert(0, "benches")
from pairs import sphere
out = sys.argv[1]
sphere(out + "/with.obj", 1024, 641, 0.02, uvs=True, normals=True)
sphere(out + "/without.obj", 1024, 641, 0.02, uvs=False, normals=True)
PY
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$dir/refused-low.obj"
fi
rm -f "$dir/figures"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores"
ls -l "$dir/with.obj" "$dir/without.obj" | awk '{print $5, $9}'
# Round after round, each binary and each file in turn: the machine's load falls on all alike.
for round in $(seq "$rounds"); do
  for bin in "${bins[@]}"; do
    for high in with without; do
      # The bake fails on LOW (no UVs) after HIGH is read: exit 1 is expected.
      /usr/bin/time -f '%e %M' -o "$dir/time" "$bin" bake "$dir/$high.obj" "$dir/refused-low.obj" \
        -o "$dir/never.png" > "$dir/log" 2>&1 || true
      grep -q 'refused-low.obj' "$dir/log" || { cat "$dir/log"; exit 1; }
      echo "$bin $high $(tail -1 "$dir/time")" >> "$dir/figures"
    done
  done
done
python3 - "$dir/figures" "${bins[@]}" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
for bin in sys.argv[2:]:
    med = {}
    for high in ("with", "without"):
        mine = [r for r in rows if r[0] == bin and r[1] == high]
        med[high] = (statistics.median(float(r[2]) for r in mine),
                     statistics.median(int(r[3]) for r in mine) / 1024)
        print(f"{bin} {high} UVs: {med[high][0]:.2f} s, {med[high][1]:.0f} MiB "
              f"(rounds: {', '.join(r[2] for r in mine)} s)")
    print(f"{bin} without / with: time {med['without'][0] / med['with'][0]:.2f}x, "
          f"memory {med['without'][1] / med['with'][1]:.2f}x")
PY
