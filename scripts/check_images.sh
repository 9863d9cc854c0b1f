#!/usr/bin/env bash
# Renders a fixed list of small images with two builds of penumbra and compares
# their PFMs byte for byte (cmp): the check that a change keeps every image.
#
#   scripts/check_images.sh OLD_BUILD NEW_BUILD [OUT_DIR]
#
# OLD_BUILD and NEW_BUILD each hold a build's bin/ and lib/ (a build folder, or
# /work/baseline). The cases cover the default scene, every scene of
# assets/scenes/, the benchmark anchors of ../shared/bench/, both integrators,
# both light selections, light-sample counts that take each of the direct-light
# estimator's strategies (1, 2 to 15, 16 and more per shading point), light
# samples only, mirrors and glass, and path renders under an HDR environment.
# Cases whose scene is missing (../shared absent) are skipped. For images that
# differ it prints both images' mean radiance, so that a change that is meant
# to alter the noise (and only the noise) can show it. Exit status: 0 when
# every image is identical, 1 when some differ, 2 on a usage error or a failed
# render.
set -u

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
    sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
OLD=$1
NEW=$2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SHARED=$ROOT/../shared
OUT=${3:-$(mktemp -d -t check_images.XXXXXX)}
mkdir -p "$OUT"
for b in "$OLD" "$NEW"; do
    [ -x "$b/bin/penumbra" ] || { echo "check_images.sh: $b/bin/penumbra: no executable" >&2; exit 2; }
done

CORNELL=$ROOT/assets/cornell/cornell.obj
HDRI=$SHARED/scenes/hdri_polyhaven/studio_small_03_1k.hdr
SMALL="--width 64 --height 48 --spp 4 --threads 2"

# name | scene | options
CASES=(
    "cornell|$CORNELL|--width 96 --height 96 --spp 4 --threads 2"
    "cornell_ls1|$CORNELL|$SMALL --light-samples 1"
    "cornell_ls3|$CORNELL|$SMALL --light-samples 3"
    "cornell_ls16|$CORNELL|$SMALL --light-samples 16"
    "cornell_ls20|$CORNELL|$SMALL --light-samples 20"
    "cornell_light_only|$CORNELL|$SMALL --direct-light light"
    "cornell_power|$CORNELL|$SMALL --light-selection power --light-samples 3"
    "cornell_ambient_mirror_depth|$CORNELL|$SMALL --ambient 0.1,0.1,0.1 --max-depth 3"
    "cornell_path|$CORNELL|--width 64 --height 64 --spp 8 --threads 2 --integrator path"
    "cornell_path_ls4|$CORNELL|$SMALL --integrator path --light-samples 4"
    "cornell_path_power|$CORNELL|$SMALL --integrator path --light-selection power --light-samples 2"
    "cornell_path_env|$CORNELL|$SMALL --integrator path --env $HDRI"
    "cornell_whitted_env|$CORNELL|$SMALL --env $HDRI"
)
for scene in "$ROOT"/assets/scenes/*.json; do
    name=$(basename "$scene" .json)
    CASES+=("$name|$scene|--width 80 --height 54 --spp 4 --threads 2")
done
CASES+=(
    "environment_path|$ROOT/assets/scenes/environment.json|$SMALL --integrator path"
    "many_lights_power|$ROOT/assets/scenes/many_lights.json|$SMALL --light-selection power --light-samples 8"
    "many_lights_path_power|$ROOT/assets/scenes/many_lights.json|$SMALL --integrator path --light-selection power"
    "showcase_path|$ROOT/assets/scenes/showcase.json|$SMALL --integrator path"
    "fig18_04|$SHARED/bench/textbook_fig18_04.json|--width 100 --height 100 --spp 4 --threads 2"
    "fig24_06|$SHARED/bench/textbook_fig24_06.json|--width 96 --height 64 --spp 4 --threads 2"
    "room|$SHARED/bench/room.json|--width 64 --height 64 --spp 2 --threads 2"
    "room_ls1|$SHARED/bench/room.json|--width 64 --height 64 --spp 4 --light-samples 1 --threads 2"
    "room_ls2|$SHARED/bench/room.json|--width 64 --height 64 --spp 4 --light-samples 2 --threads 2"
    "room_path|$SHARED/bench/room.json|--width 48 --height 48 --spp 4 --threads 2 --integrator path"
    "cornell_sphere_glass|$SHARED/scenes/cornell_mcguire/CornellBox-Sphere.obj|$SMALL"
    "cornell_sphere_glass_path|$SHARED/scenes/cornell_mcguire/CornellBox-Sphere.obj|$SMALL --integrator path"
    "cornell_mirror|$SHARED/scenes/cornell_mcguire/CornellBox-Mirror.obj|$SMALL"
    "cornell_glossy_env_path|$SHARED/scenes/cornell_mcguire/CornellBox-Glossy.obj|$SMALL --integrator path --env $HDRI --light-selection power"
)

mean() {
    python3 - "$1" <<'EOF'
import struct, sys
with open(sys.argv[1], "rb") as f:
    kind = f.readline().strip()
    w, h = map(int, f.readline().split())
    scale = float(f.readline())
    n = w * h * (3 if kind == b"PF" else 1)
    data = struct.unpack(("<" if scale < 0 else ">") + "f" * n, f.read(4 * n))
print(f"{sum(data) / n:.6g}")
EOF
}

total=0
same=0
status=0
for case in "${CASES[@]}"; do
    IFS='|' read -r name scene opts <<<"$case"
    if [ ! -e "$scene" ]; then
        echo "skip      $name ($scene not found)"
        continue
    fi
    case "$opts" in *"$HDRI"*) [ -e "$HDRI" ] || { echo "skip      $name ($HDRI not found)"; continue; } ;; esac
    for side in old new; do
        build=$OLD
        [ $side = new ] && build=$NEW
        # shellcheck disable=SC2086
        if ! LD_LIBRARY_PATH=$build/lib "$build/bin/penumbra" "$scene" -q -o "$OUT/$name.$side.pfm" $opts \
            2>"$OUT/$name.$side.err"; then
            echo "FAILED    $name ($side build): $(tail -1 "$OUT/$name.$side.err")"
            exit 2
        fi
    done
    total=$((total + 1))
    if cmp -s "$OUT/$name.old.pfm" "$OUT/$name.new.pfm"; then
        same=$((same + 1))
        echo "same      $name"
    else
        status=1
        echo "DIFFERENT $name: mean old $(mean "$OUT/$name.old.pfm"), new $(mean "$OUT/$name.new.pfm")"
    fi
done
echo "$same of $total images identical (images in $OUT)"
exit $status
