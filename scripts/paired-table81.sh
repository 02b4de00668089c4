#!/usr/bin/env bash
# paired-table81.sh: paths a second of two builds of the `table81` example, run at once, one on
# each core, then swapped, so that the virtual machine's drift between hours falls on both alike.
#
# Usage: scripts/paired-table81.sh BEFORE_BIN AFTER_BIN ROOM [ROOM ...]
#   BEFORE_BIN, AFTER_BIN  two builds of target/release/examples/table81 (for example one built
#                          in a git worktree of an earlier revision with its own CARGO_TARGET_DIR)
#   ROOM                   a room of the seed's Table 8.1: '*', '*22', '*222', '*333', '*444',
#                          '*2222' or '*3333'
# Environment: SIZE (default 448), SPP (default 4), MESH (default ../shared/models/dragon.ply
# beside the checkout; both builds get the same mesh whatever their own default).
#
# Prints a line a run: build, core, room, million paths a second, mean samples a pixel, and the
# denoised display noise (RMS, median, 99th percentile), which must agree between two builds
# that render the same images.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 3 ]; then
  sed -n '2,16p' "$0" >&2
  exit 2
fi
before=$1 after=$2
shift 2
size=${SIZE:-448} spp=${SPP:-4} mesh=${MESH:-../shared/models/dragon.ply}
[ -f "$mesh" ] || { echo "error: no mesh at $mesh (set MESH)" >&2; exit 2; }
run() { # core binary room name
  taskset -c "$1" env RAYON_NUM_THREADS=1 "$2" --only "$3" --size "$size" --spp "$spp" \
    --mesh "$mesh" 2>/dev/null | grep '^| `' |
    awk -F'|' -v name="$4" -v core="$1" \
      '{gsub(/ /, "", $9); print name, "core " core, $2, "M paths/s", $9, "spp", $4, "denoised", $7}'
}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for room in "$@"; do
  run 0 "$before" "$room" before >"$out/a" & run 1 "$after" "$room" after >"$out/b" & wait
  cat "$out/a" "$out/b"
  run 0 "$after" "$room" after >"$out/a" & run 1 "$before" "$room" before >"$out/b" & wait
  cat "$out/a" "$out/b"
done
