# Sourced by the bake benchmarks (bake.sh, bake_shapes.sh): the folder for their files ($dir: the
# script's first argument, else DEFAULT_DIR), the release binary built ($bin) and the bake settings
# both compare with Blender's ($settings).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
dir="${1:-$DEFAULT_DIR}"
mkdir -p "$dir"
cargo build --release --quiet
bin="$PWD/target/release/tutorial13"
settings=(--extrusion 0.05 --max-distance 0.1 --margin 16)
