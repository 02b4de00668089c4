#!/usr/bin/env bash
# The gallery: renders every example scene examples/scenes/NAME.toml to docs/gallery/NAME.jpg
# (small JPEGs, to keep the repository light), for docs/gallery.md. Runs from any directory.
#
# Usage: scripts/gallery.sh [--size WxH] [--spp N] [--time-limit S] [--only GLOB] [--force]
#                           [--no-build]
#   --size WxH        image size (default 640x480)
#   --spp N           samples per pixel (default 64)
#   --time-limit S    stop a picture after S seconds, at the end of the pass under way (default 15)
#   --only GLOB       only the scenes whose name (the file's stem) matches GLOB, e.g. 'fig-8.1*'
#   --force           render again even where the picture exists and is newer than its scene
#   --no-build        use target/release/orbifold as it is (by default `cargo build --release`
#                     runs first; it does nothing when the binary is up to date)
#
# By default a picture that exists and is newer than its scene file is skipped. Each picture is
# written to a temporary file and renamed (by `orbifold render`), so an interrupted run leaves no
# half picture. Prints one line per scene: seconds, samples per pixel reached, and the relative
# noise (the mean over pixels of the standard error of a pixel's luminance over that luminance +
# 0.01, before denoising), then the total time and the gallery's size. Exits 1 if a scene failed.
# The whole gallery (49 scenes) takes about 6 minutes on a 2-vCPU machine (see docs/gallery.md).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
size=640x480
spp=64
limit=15
only='*'
force=0
build=1
while [[ $# -gt 0 ]]; do
    case "$1" in
        --size) size=${2:?--size needs WxH}; shift 2 ;;
        --spp) spp=${2:?--spp needs N}; shift 2 ;;
        --time-limit) limit=${2:?--time-limit needs S}; shift 2 ;;
        --only) only=${2:?--only needs GLOB}; shift 2 ;;
        --force) force=1; shift ;;
        --no-build) build=0; shift ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        *) echo "gallery.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    esac
done

orbifold=$root/target/release/orbifold
if [[ $build == 1 ]]; then
    cargo build --release -q -p orbifold-cli --manifest-path "$root/Cargo.toml"
elif [[ ! -x $orbifold ]]; then
    echo "gallery.sh: $orbifold is missing; run without --no-build" >&2
    exit 1
fi

out_dir=$root/docs/gallery
mkdir -p "$out_dir"
log=$(mktemp)
err=$(mktemp)
trap 'rm -f "$log" "$err"' EXIT

start=$SECONDS
rendered=0
skipped=0
failed=()
shopt -s nullglob
for scene in "$root"/examples/scenes/*.toml; do
    name=$(basename "$scene" .toml)
    # shellcheck disable=SC2053 # GLOB is a pattern on purpose
    [[ $name == $only ]] || continue
    out=$out_dir/$name.jpg
    if [[ $force == 0 && -f $out && $out -nt $scene ]]; then
        printf '%-32s skipped (up to date)\n' "$name"
        skipped=$((skipped + 1))
        continue
    fi
    if "$orbifold" render "$scene" -o "$out" --size "$size" --spp "$spp" \
        --time-limit "$limit" --json >"$log" 2>"$err"; then
        python3 - "$name" "$log" <<'EOF'
import json, sys
name, path = sys.argv[1], sys.argv[2]
d = json.load(open(path))
early = "  (time limit)" if d.get("stopped_early") else ""
print(f"{name:<32} {d['seconds']:6.1f} s  {d['samples']:4d} spp  noise {d['relative_noise']:.3f}{early}")
EOF
        rendered=$((rendered + 1))
    else
        printf '%-32s FAILED:\n' "$name"
        sed 's/^/    /' "$err" "$log"
        failed+=("$name")
    fi
done

total=$((SECONDS - start))
printf '%d rendered, %d skipped, %d failed in %dm%02ds; docs/gallery/ is %s\n' \
    "$rendered" "$skipped" "${#failed[@]}" $((total / 60)) $((total % 60)) \
    "$(du -sh "$out_dir" | cut -f1)"
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "failed: ${failed[*]}" >&2
    exit 1
fi
