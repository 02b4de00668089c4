#!/usr/bin/env bash
# same-outputs.sh: prove that the current tree's `orbifold` CLI writes byte-for-byte the same
# outputs as the CLI of an earlier revision (for refactors that must not change behaviour).
#
# Usage:
#   scripts/same-outputs.sh BASE_REV [OUT_DIR]
#
#   BASE_REV  any git revision (commit, tag, branch, HEAD~3) of this repository.
#   OUT_DIR   where the outputs go (default: target/same-outputs/out): OUT_DIR/base and
#             OUT_DIR/head, one file per output, plus OUT_DIR/inputs (the scene files used by
#             both sides, copied from BASE_REV's examples/ so that both binaries read the very
#             same inputs). Each side's stderr and the job list are kept under SIDE/.log (not
#             compared).
#
# What it does:
#   1. Checks BASE_REV out as a git worktree in target/same-outputs/base-src (reused, and moved
#      to BASE_REV, when already there) and builds its CLI with
#      `cargo build --release -p orbifold-cli` and CARGO_TARGET_DIR=target/same-outputs/base-target
#      (the main target dir is left alone). Builds the current tree's CLI with
#      `cargo build --release -p orbifold-cli` (normal target dir).
#   2. Runs the same list of commands with each binary (cwd OUT_DIR/SIDE, relative paths only,
#      so that paths echoed into outputs agree):
#        - `render SCENE --size 96x72 --spp 4 --seed 1 --denoise -o X.exr --json` for every
#          scene in examples/scenes/*.toml and examples/peer/*.toml (EXR defaults to no
#          denoising: --denoise keeps the denoised pipeline under test; no --time-limit,
#          no --noise-target, adaptive sampling left on: it is deterministic);
#        - renders with other options: --no-denoise, --straight-rays, --no-adaptive, --no-nee,
#          --no-footprint, --no-radiance-cache, --filter box, --light-candidates 1, --glow,
#          --max-depth, --threads 1, PNG/JPEG (tone mapping, auto and fixed exposure), a bare
#          signature, the built-in default scene, a panorama camera (a scene copied with
#          `kind = "panorama"` added to its [camera]);
#        - `animate` (walls, orbit, turn with a panorama, keyframes, a walking object), 2-3
#          frames at 48x36;
#        - `trace`: AOV EXRs, one-ray hits as text and --json;
#        - `tiling` PNGs and SVGs for spherical, Euclidean, hyperbolic and ideal signatures,
#          every --color mode, every --model, a --motif;
#        - `layout` text, --json, SVG and PNG; `info` and `enumerate` text and --json;
#          `cover --json` (with and without --tiles); `room` OBJ(+MTL, textures)/PLY/glb/SVG/PNG
#          with --json; `scene show --json` of every scene, `scene check`, `scene new`;
#        - `preview` PNGs (needs a wgpu adapter; llvmpipe is enough and is deterministic).
#      Each command's stdout is kept (NAME.json / NAME.jsonl / NAME.txt) and a non-zero exit
#      status is kept as NAME.rc; a few commands that must fail also keep stderr (NAME.stderr).
#      Run-to-run noise that is DROPPED before comparing: the value of every JSON field named
#      in DROP_FIELDS below ("seconds": render, animate, room, cover and preview timings) is
#      replaced by null with sed (the rest of the bytes are kept as printed). Text outputs
#      that print timings are not kept (those commands are run with --json instead).
#   3. Compares OUT_DIR/base and OUT_DIR/head file by file, byte for byte (EXR included: the
#      EXR writer puts no timestamp in the header, and renders with a fixed --spp and --seed
#      are bit-identical run to run and for any --threads), prints one line per file that
#      differs or exists on one side only, then `N files compared, M differ`, and exits 1
#      when any differ (2 on usage or build errors).
#
# Jobs run in parallel (SAME_OUTPUTS_JOBS, default: the number of cores): every job is its own
# process writing its own files, and each output is the same whatever the thread count, so the
# order does not matter. The output phase is about 35 s of CPU a side (250 commands, 377 files);
# 1.5 min a side of wall time on 2 busy cores (load 11), so about 3 min for both.
#
# Environment:
#   SAME_OUTPUTS_SKIP_BASE_BUILD=1  Do not run cargo for the base: reuse
#                                   target/same-outputs/base-target/release/orbifold if it was
#                                   built from BASE_REV (stamp file beside it); else build.
#   SAME_OUTPUTS_REUSE_BASE=1       Keep OUT_DIR/base when it is complete and was made from
#                                   BASE_REV by this same version of the script (stamp file
#                                   OUT_DIR/base/.log/stamp); only the head side is redone.
#   SAME_OUTPUTS_HEAD_BIN=PATH      Use this binary for the head side instead of building the
#                                   current tree (e.g. the base binary, to check determinism).
#   SAME_OUTPUTS_SKIP_HEAD_BUILD=1  Use target/release/orbifold as it is (no cargo run).
#   SAME_OUTPUTS_JOBS=N             Parallel jobs per side (default: nproc).
#
# Typical use during a refactor (base outputs and base binary made once, cheap reruns):
#   scripts/same-outputs.sh 7d7ed4c target/same-outputs/out                # first time
#   SAME_OUTPUTS_SKIP_BASE_BUILD=1 SAME_OUTPUTS_REUSE_BASE=1 \
#     scripts/same-outputs.sh 7d7ed4c target/same-outputs/out              # after each change
set -euo pipefail

# JSON fields whose values vary run to run and are replaced by null before comparing.
DROP_FIELDS=(seconds)

die() {
    echo "same-outputs: $*" >&2
    exit 2
}

if [[ $# -lt 1 || $# -gt 2 || $1 == -h || $1 == --help ]]; then
    sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
    exit 2
fi

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SO="$ROOT/target/same-outputs"
BASE_SRC="$SO/base-src"
BASE_TARGET="$SO/base-target"
BASE_REV=$1
OUT_DIR=${2:-$SO/out}
mkdir -p "$OUT_DIR"
OUT_DIR=$(cd "$OUT_DIR" && pwd) # relative to the caller's directory
cd "$ROOT"
JOBS=${SAME_OUTPUTS_JOBS:-$(nproc)}
BASE_COMMIT=$(git rev-parse --verify --quiet "$BASE_REV^{commit}") ||
    die "not a revision: $BASE_REV"
SCRIPT_SUM=$(sha256sum "${BASH_SOURCE[0]}" | cut -d' ' -f1)
START=$SECONDS

# ---------------------------------------------------------------------------------------------
# 1. The two binaries.

mkdir -p "$SO"
if [[ -e $BASE_SRC ]]; then
    [[ $(git -C "$BASE_SRC" rev-parse --show-toplevel 2>/dev/null) == "$BASE_SRC" ]] ||
        die "$BASE_SRC exists but is not a git worktree: remove it"
    if [[ $(git -C "$BASE_SRC" rev-parse HEAD) != "$BASE_COMMIT" ]]; then
        echo "same-outputs: moving $BASE_SRC to $BASE_COMMIT" >&2
        git -C "$BASE_SRC" checkout -q --detach --force "$BASE_COMMIT"
    fi
else
    echo "same-outputs: worktree of $BASE_COMMIT in $BASE_SRC" >&2
    git worktree prune # forget a base-src that was deleted (e.g. by cargo clean)
    git worktree add -q --detach "$BASE_SRC" "$BASE_COMMIT"
fi

BASE_BIN="$BASE_TARGET/release/orbifold"
BASE_STAMP="$BASE_TARGET/same-outputs-rev"
if [[ ${SAME_OUTPUTS_SKIP_BASE_BUILD:-0} == 1 && -x $BASE_BIN && -f $BASE_STAMP &&
    $(cat "$BASE_STAMP") == "$BASE_COMMIT" ]]; then
    echo "same-outputs: base: reusing $BASE_BIN (built from $BASE_COMMIT)" >&2
else
    echo "same-outputs: base: building $BASE_COMMIT" >&2
    rm -f "$BASE_STAMP"
    (cd "$BASE_SRC" && CARGO_TARGET_DIR="$BASE_TARGET" cargo build --release -p orbifold-cli) ||
        die "base build failed"
    echo "$BASE_COMMIT" >"$BASE_STAMP"
fi

if [[ -n ${SAME_OUTPUTS_HEAD_BIN:-} ]]; then
    HEAD_BIN=$(realpath "$SAME_OUTPUTS_HEAD_BIN")
    echo "same-outputs: head: using $HEAD_BIN (SAME_OUTPUTS_HEAD_BIN)" >&2
else
    HEAD_BIN="$ROOT/target/release/orbifold"
    if [[ ${SAME_OUTPUTS_SKIP_HEAD_BUILD:-0} != 1 ]]; then
        echo "same-outputs: head: building the current tree" >&2
        cargo build --release -p orbifold-cli || die "head build failed"
    fi
fi
[[ -x $HEAD_BIN ]] || die "no head binary at $HEAD_BIN"
BUILT=$SECONDS

# ---------------------------------------------------------------------------------------------
# 2. The outputs.

# Inputs shared by both sides: BASE_REV's examples, and a few scenes and files made from them.
INPUTS="$OUT_DIR/inputs"
rm -rf "$INPUTS"
mkdir -p "$INPUTS/extra"
git -C "$BASE_SRC" archive --format=tar "$BASE_COMMIT" examples | tar -x -C "$INPUTS"
add_panorama() { # SCENE OUT: the scene with `kind = "panorama"` as the first key of [camera]
    grep -q '^\[camera\]' "$1" || die "no [camera] in $1"
    sed 's/^\[camera\]$/[camera]\nkind = "panorama"/' "$1" >"$2"
}
add_panorama "$INPUTS/examples/scenes/default.toml" "$INPUTS/extra/panorama-default.toml"
add_panorama "$INPUTS/examples/scenes/fig-8.10-444.toml" "$INPUTS/extra/panorama-444.toml"
cat >"$INPUTS/extra/keys.txt" <<'EOF'
# x y height yaw [pitch]
-0.2 0.0 0.5 0
0.0 0.15 0.5 90 -10
0.15 0.0 0.6 180
EOF

S=../inputs/examples     # as seen from OUT_DIR/SIDE
X=../inputs/extra
R=(--size 96x72 --spp 4 --seed 1) # every render
A=(--size 48x36 --spp 2 --seed 1) # every animation

JOBLIST=$(mktemp)
trap 'rm -f "$JOBLIST"' EXIT
# job MODE NAME ARGS...: run `orbifold ARGS...` and keep its stdout as NAME.json (MODE json),
# NAME.jsonl (jsonl: one JSON object a line), NAME.txt (text), or not at all (none); MODE err
# keeps stdout as NAME.txt and stderr as NAME.stderr (for commands that must fail).
job() { printf '%q ' run_job "$@" >>"$JOBLIST"; echo >>"$JOBLIST"; }

# -- render: every scene, then the options.
for f in "$INPUTS"/examples/scenes/*.toml "$INPUTS"/examples/peer/*.toml; do
    d=$(basename "$(dirname "$f")")
    n=$(basename "$f" .toml)
    job json "render/$d/$n" render "$S/$d/$n.toml" "${R[@]}" --denoise -o "render/$d/$n.exr" --json
done
for n in default fig-8.10-444 fig-8.12-ideal-4 fig-1.2-222; do
    sc="$S/scenes/$n.toml"
    job json "render-opt/$n-no-denoise" render "$sc" "${R[@]}" --no-denoise -o "render-opt/$n-no-denoise.exr" --json
    job json "render-opt/$n-straight" render "$sc" "${R[@]}" --denoise --straight-rays -o "render-opt/$n-straight.exr" --json
done
sc="$S/scenes/fig-8.10-444.toml"
o=render-opt/444
job json "$o-no-adaptive" render "$sc" "${R[@]}" --denoise --no-adaptive -o "$o-no-adaptive.exr" --json
job json "$o-no-nee" render "$sc" "${R[@]}" --denoise --no-nee -o "$o-no-nee.exr" --json
job json "$o-no-footprint" render "$sc" "${R[@]}" --denoise --no-footprint -o "$o-no-footprint.exr" --json
job json "$o-no-radiance-cache" render "$sc" "${R[@]}" --denoise --no-radiance-cache -o "$o-no-radiance-cache.exr" --json
job json "$o-filter-box" render "$sc" "${R[@]}" --denoise --filter box -o "$o-filter-box.exr" --json
job json "$o-candidates-1" render "$sc" "${R[@]}" --denoise --light-candidates 1 -o "$o-candidates-1.exr" --json
job json "$o-glow" render "$sc" "${R[@]}" --denoise --glow 0.3 --max-depth 2 -o "$o-glow.exr" --json
job json "$o-threads-1" render "$sc" "${R[@]}" --denoise --threads 1 -o "$o-threads-1.exr" --json
job json "$o-seed-7-spp-9" render "$sc" --size 96x72 --spp 9 --seed 7 --denoise -o "$o-seed-7-spp-9.exr" --json
job json "$o-png" render "$sc" "${R[@]}" -o "$o.png" --json
job json "$o-png-exposure" render "$sc" "${R[@]}" --exposure 1.5 -o "$o-exposure.png" --json
job json "$o-jpg-no-denoise" render "$sc" "${R[@]}" --no-denoise -o "$o-no-denoise.jpg" --json
job json render-opt/materials-png render "$S/scenes/materials.toml" "${R[@]}" -o render-opt/materials.png --json
job json render-opt/textures-png render "$S/peer/textures-2222.toml" "${R[@]}" -o render-opt/textures.png --json
job json render-opt/sig-2223 render '*2223' "${R[@]}" --denoise -o render-opt/sig-2223.exr --json
job json render-opt/sig-235 render '*235' "${R[@]}" -o render-opt/sig-235.png --json
job json render-opt/builtin-default render "${R[@]}" --denoise -o render-opt/builtin-default.exr --json
job json render-opt/panorama-default render "$X/panorama-default.toml" "${R[@]}" --denoise -o render-opt/panorama-default.exr --json
job json render-opt/panorama-444 render "$X/panorama-444.toml" "${R[@]}" -o render-opt/panorama-444.png --json

# -- animate: 2-3 frames each.
sc="$S/scenes/default.toml"
job jsonl animate/walls animate "$sc" --path walls --count 3 "${A[@]}" -o animate/walls --json
job jsonl animate/orbit-exr animate "$S/scenes/fig-8.10-444.toml" --path orbit --count 60 --frames 0..1 --format exr "${A[@]}" --denoise -o animate/orbit-exr --json
job jsonl animate/turn-panorama animate "$X/panorama-default.toml" --path turn --count 3 --format jpg "${A[@]}" -o animate/turn-panorama --json
job jsonl animate/keys animate "$sc" --path "$X/keys.txt" --count 3 "${A[@]}" -o animate/keys --json
job jsonl animate/walker animate "$sc" --path walls --walker 0 --count 40 --frames 5..6 "${A[@]}" --exposure 0 -o animate/walker --json

# -- trace: AOVs and single rays.
for n in default fig-1.2-222 fig-8.10-444 fig-8.12-ideal-4 fig-8.4-235-straight; do
    job none "trace/aov-$n" trace "$S/scenes/$n.toml" --aov "trace/aov-$n.exr" --size 96x72
done
job none trace/aov-moved trace "$S/peer/mixed-333.toml" --aov trace/aov-moved.exr --size 64x48 --from 0.05,0.02,0.4 --yaw 30 --pitch 5
for n in default fig-8.10-444 fig-8.12-ideal-4 fig-6.10-22222; do
    job json "trace/ray-$n" trace "$S/scenes/$n.toml" --json
    job text "trace/ray-$n" trace "$S/scenes/$n.toml"
done
job json trace/ray-333 trace '*333' --from 0,0,0.5 --yaw 20 --pitch 10 --json
job json trace/ray-2223 trace '*2223' --from 0.1,0,0.5 --yaw 45 --pitch -5 --bounces 20 --json
job json trace/ray-inf trace '*∞∞∞' --from 0,0,0.5 --yaw 10 --pitch 1 --bounces 200 --json
job text trace/ray-2223 trace '*2223' --from 0.1,0,0.5 --yaw 45 --pitch -5 --bounces 20 --height 2

# -- tiling.
t=(--size 128)
for sig in '*235' '*333' '*2222' '*237' '*2333' '*∞∞∞' '*22∞∞'; do
    n=${sig//\*/}
    n=${n//∞/inf}
    job none "tiling/$n" tiling "$sig" "${t[@]}" -o "tiling/$n.png"
    job none "tiling/$n-depth4" tiling "$sig" --depth 4 -o "tiling/$n-depth4.svg"
done
job none tiling/237-color-depth tiling '*237' "${t[@]}" --color depth -o tiling/237-color-depth.png
job none tiling/237-color-wall tiling '*237' "${t[@]}" --color wall -o tiling/237-color-wall.png
job none tiling/inf-halfplane-depth tiling '*∞∞∞' "${t[@]}" --model halfplane --color depth --depth 30 -o tiling/inf-halfplane-depth.png
job none tiling/237-klein-wall tiling '*237' "${t[@]}" --model klein --color wall -o tiling/237-klein-wall.png
job none tiling/235-sphere tiling '*235' "${t[@]}" --model sphere --color wall -o tiling/235-sphere.png
job none tiling/235-stereographic-svg tiling '*235' --model stereographic --color depth --depth 5 -o tiling/235-stereographic.svg
job none tiling/333-zoom tiling '*333' "${t[@]}" --zoom 0.3 --center 0.1,0 --color depth -o tiling/333-zoom.png
job none tiling/2222-euclidean-svg tiling '*2222' --model euclidean --color wall --depth 6 -o tiling/2222-euclidean.svg
job none tiling/244-motif tiling '*244' "${t[@]}" --motif "$S/peer/quadrants.png" -o tiling/244-motif.png
job none tiling/237-motif tiling '*237' "${t[@]}" --motif "$S/peer/quadrants.png" --color depth -o tiling/237-motif.png

# -- layout, info, enumerate, cover.
for sig in '*2333' '*235' '*2222' '*∞∞∞∞∞' '*(3/2)33' '*22222'; do
    n=${sig//\*/}
    n=${n//∞/inf}
    n=${n//\//-}
    job text "layout/$n" layout "$sig"
    job json "layout/$n" layout "$sig" --json
    job none "layout/$n-svg" layout "$sig" -o "layout/$n.svg"
done
job json layout/22222-params layout '*22222' --params 1,3 --json
job json layout/2222-params layout '*2222' --params 2.5 --json
job none layout/inf5-incircle layout '*∞∞∞∞∞' --shape incircle -o layout/inf5-incircle.svg
job none layout/235-png layout '*235' --at 0.3,-0.1 --angle 30 -o layout/235.png --size 200
job none layout/2333-png layout '*2333' --shape incircle -o layout/2333.png --size 160
job text info/text info '*22222' '*632' '*362' '*236' 4*2 '*∞∞∞' 632 2*22 '22×' '**' '*×' '××' o 22222 '*(3/2)33' '*(1.5)33' '*23456789(10)(11)' '*222infinf'
job json info/json info '*22222' '*632' 4*2 '*∞∞∞' 632 2*22 '22×' '**' '*×' '××' o 22222 '*(3/2)33' '*23' '*2' '*' '*22' '*(12)(12)(12)'
job err info/bad-signature info 'zz' '*2333'
job text enumerate/c3-k6 enumerate --corners 3 --max-order 6
job json enumerate/c3-k7 enumerate --corners 3 --max-order 7 --json
job json enumerate/c3-k7-hyperbolic enumerate --corners 3 --max-order 7 --geometry hyperbolic --json
job json enumerate/c4-k4-ideal enumerate --corners 4 --max-order 4 --ideal --json
job json enumerate/c0 enumerate --corners 0 --max-order 3 --json
job text enumerate/c5-k9-count enumerate --corners 5 --max-order 9 --count
job json enumerate/c5-k6-count enumerate --corners 5 --max-order 6 --count --json
job text enumerate/table enumerate --table
job json enumerate/table enumerate --table --json
job json cover/235 cover '*235' --json
job json cover/235-tiles cover '*235' --tiles --json
job json cover/2222222-d9 cover '*2222222' --depth 9 --json
job json cover/237-d6-tiles cover '*237' --depth 6 --tiles --json
job json cover/inf3-max-tiles cover '*∞∞∞' --max-tiles 300 --tiles --json
job json cover/333-radius cover '*333' --radius 2.5 --json
job json cover/2222-depth cover '*2222' --depth 5 --tiles --json

# -- room exports, each in its own folder (OBJ writes .mtl and textures beside it).
sc="$S/scenes/default.toml"
job json room/default-obj/room room "$sc" -o room/default-obj/room.obj --json
job json room/default-ply/room room "$sc" -o room/default-ply/room.ply --json
job json room/default-glb/room room "$sc" -o room/default-glb/room.glb --json
job json room/default-svg/room room "$sc" -o room/default-svg/room.svg --json
job json room/default-png/room room "$sc" -o room/default-png/room.png --json
job json room/materials-obj/room room "$S/scenes/materials.toml" -o room/materials-obj/room.obj --json
job json room/textures-ply/room room "$S/peer/textures-2222.toml" -o room/textures-ply/room.ply --json
job json room/textures-glb/room room "$S/peer/textures-2222.toml" -o room/textures-glb/room.glb --json
job json room/444-geodesic-glb/room room "$S/scenes/fig-8.10-444.toml" --tessellation geodesic --resolution 0.2 -o room/444-geodesic-glb/room.glb --json
job json room/333-cover-ply/room room '*333' --cover 2 -o room/333-cover-ply/room.ply --json
job json room/2223-obj/room room '*2223' --height 2 -o room/2223-obj/room.obj --json
job json room/ideal-obj/room room "$S/scenes/fig-8.12-ideal-4.toml" --cusp 1.5 -o room/ideal-obj/room.obj --json

# -- scenes.
for f in "$INPUTS"/examples/scenes/*.toml "$INPUTS"/examples/peer/*.toml; do
    d=$(basename "$(dirname "$f")")
    n=$(basename "$f" .toml)
    job json "scene/show/$d/$n" scene show "$S/$d/$n.toml" --json
done
job text scene/show-default scene show "$S/scenes/default.toml"
all_scenes=()
for f in "$INPUTS"/examples/scenes/*.toml "$INPUTS"/examples/peer/*.toml; do
    all_scenes+=("$S/${f#"$INPUTS"/examples/}")
done
job text scene/check scene check "${all_scenes[@]}"
job none scene/new-default scene new -o scene/new-default.toml
job none scene/new-2333 scene new '*2333' -o scene/new-2333.toml

# -- the real-time preview (wgpu; a software adapter such as llvmpipe will do).
for n in default fig-8.10-444 fig-8.12-ideal-4; do
    job json "preview/$n" preview "$S/scenes/$n.toml" --size 160x120 -o "preview/$n.png" --json
done
job json preview/444-straight preview "$S/scenes/fig-8.10-444.toml" --size 160x120 --straight --attenuation universal --depth 3 -o preview/444-straight.png --json

# run_job MODE NAME ARGS... (run by xargs in OUT_DIR/SIDE with $BIN set).
run_job() {
    local mode=$1 name=$2 rc=0
    shift 2
    mkdir -p "$(dirname "$name")" ".log/$(dirname "$name")"
    "$BIN" "$@" >".log/$name.$mode.stdout" 2>".log/$name.$mode.stderr" || rc=$?
    case $mode in
    json | jsonl) sed -E "s/(\"($DROP_RE)\"[[:space:]]*:[[:space:]]*)-?[0-9][-+.0-9eE]*/\\1null/g" \
        ".log/$name.$mode.stdout" >"$name.$mode" ;;
    text) cp ".log/$name.$mode.stdout" "$name.txt" ;;
    err) cp ".log/$name.$mode.stdout" "$name.txt" && cp ".log/$name.$mode.stderr" "$name.stderr" ;;
    none) ;;
    esac
    if [[ $rc != 0 ]]; then
        echo "$rc" >"$name.$mode.rc"
        echo "  exit status $rc: orbifold $*" >>.log/failures
    fi
    return 0
}
export -f run_job
DROP_RE=$(
    IFS='|'
    echo "${DROP_FIELDS[*]}"
)
export DROP_RE

produce() { # SIDE BIN
    local side=$1 dir="$OUT_DIR/$1" t0=$SECONDS
    rm -rf "$dir"
    mkdir -p "$dir/.log"
    cp "$JOBLIST" "$dir/.log/jobs"
    echo "same-outputs: $side: $(wc -l <"$JOBLIST") commands with $2 ($JOBS at a time)" >&2
    (cd "$dir" && BIN=$2 xargs -d '\n' -P "$JOBS" -n 1 bash -c 'eval "$1"' _ <"$JOBLIST")
    if [[ -s $dir/.log/failures ]]; then
        echo "same-outputs: $side: commands with a non-zero exit status (kept as .rc files):" >&2
        sort "$dir/.log/failures" >&2
    fi
    echo "same-outputs: $side: $(find "$dir" -type f -not -path '*/.log/*' | wc -l) files in $((SECONDS - t0)) s" >&2
}

STAMP="$BASE_COMMIT $SCRIPT_SUM"
if [[ ${SAME_OUTPUTS_REUSE_BASE:-0} == 1 && -f $OUT_DIR/base/.log/stamp &&
    $(cat "$OUT_DIR/base/.log/stamp") == "$STAMP" ]]; then
    echo "same-outputs: base: reusing $OUT_DIR/base" >&2
else
    produce base "$BASE_BIN"
    echo "$STAMP" >"$OUT_DIR/base/.log/stamp"
fi
produce head "$HEAD_BIN"

# ---------------------------------------------------------------------------------------------
# 3. The comparison.

compared=0
differ=0
while IFS= read -r f; do
    compared=$((compared + 1))
    if [[ ! -f $OUT_DIR/base/$f ]]; then
        echo "only in head: $f"
        differ=$((differ + 1))
    elif [[ ! -f $OUT_DIR/head/$f ]]; then
        echo "only in base: $f"
        differ=$((differ + 1))
    elif ! cmp -s "$OUT_DIR/base/$f" "$OUT_DIR/head/$f"; then
        echo "differs: $f"
        differ=$((differ + 1))
    fi
done < <(
    for side in base head; do
        (cd "$OUT_DIR/$side" && find . -type f -not -path './.log/*' | sed 's|^\./||')
    done | LC_ALL=C sort -u
)
echo "$compared files compared, $differ differ (base $BASE_COMMIT: $OUT_DIR/base; head $HEAD_BIN: $OUT_DIR/head; builds $((BUILT - START)) s, outputs and comparison $((SECONDS - BUILT)) s)"
[[ $differ == 0 ]]
