#!/usr/bin/env bash
# Renders McGuire's CornellBox-Original, -Water and -Glossy, and the Stanford
# bunny (its PLY file, read through Assimp) under the sky of
# assets/scenes/sky.pfm, with both integrators (256x256 PNG) into docs/gallery/ and writes docs/gallery/README.md
# with the images side by side, the commands, the machine and each render's
# time from --stats-json. Run from anywhere after the README's build;
# ../shared must lie beside the repository (or set SHARED).
#
# CornellBox-Glossy's MTL has no material named `light` (its light faces would
# get the grey default and the box would be unlit), so the script renders a
# copy whose MTL gains Original's light (Ke 17 12 4); the OBJ is unchanged.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
shared=${SHARED:-$here/../shared}
src=$shared/scenes/cornell_mcguire
out=docs/gallery
size=${SIZE:-256}
whitted_args=${WHITTED_ARGS:-"--spp 64 --light-samples 4"}
path_args=${PATH_ARGS:-"--spp 256 --light-samples 1"}
threads=${THREADS:-0}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"

cp "$src/CornellBox-Glossy.obj" "$src/CornellBox-Glossy.mtl" "$tmp/"
printf '\nnewmtl light\n  Kd 0.78 0.78 0.78\n  Ks 0 0 0\n  Ke 17 12 4\n  illum 2\n' >>"$tmp/CornellBox-Glossy.mtl"

scene_file() {
  case $1 in
    Glossy) echo "$tmp/CornellBox-Glossy.obj" ;;
    Bunny) echo "$shared/scenes/bunny_stanford/bun_zipper.ply" ;;
    *) echo "$src/CornellBox-$1.obj" ;;
  esac
}

# What a scene needs beyond the integrator's settings: the bunny has no light
# of its own, so it gets the sky (rotated so the sun lights it from the left).
scene_args() {
  case $1 in
    Bunny) echo "--env assets/scenes/sky.pfm --env-rotate 60" ;;
    *) echo "" ;;
  esac
}

label() {
  case $1 in
    Bunny) echo "Stanford bunny (\`bun_zipper.ply\`) under \`sky.pfm\`" ;;
    *) echo "CornellBox-$1" ;;
  esac
}

{
  echo "# Gallery: \`whitted\` and \`path\` side by side"
  echo
  echo "McGuire's Cornell boxes (\`../shared/scenes/cornell_mcguire\`, CC BY 3.0, Cardenas & McGuire 2011),"
  echo "${size}x${size}, rendered by \`scripts/make_gallery.sh\` on $(nproc) cores of"
  echo "\`$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')\`, $(date -u +%Y-%m-%d)."
  echo "\`whitted\`: \`$whitted_args\`; \`path\`: \`$path_args\` (default \`--max-depth 10\`)."
  echo "CornellBox-Glossy gets Original's light (its MTL has none; see the script). The Stanford bunny"
  echo "(\`../shared/scenes/bunny_stanford/bun_zipper.ply\`, 69,451 triangles, read through Assimp, smoothed at"
  echo "the default 30 degrees) is lit by \`assets/scenes/sky.pfm\` (\`--env assets/scenes/sky.pfm --env-rotate 60\`)."
  echo "Water's water and Sphere's glass say \`Tf 0.1\` in their MTL: dark glass (docs/mtl-mapping.md)."
  echo "Times are render seconds from \`--stats-json\` (one run each, not a benchmark)."
  echo
  echo "| scene | whitted | path |"
  echo "| --- | --- | --- |"
} >"$tmp/README.md"

for name in Original Water Glossy Bunny; do
  scene=$(scene_file "$name")
  extra=$(scene_args "$name")
  row="| $(label "$name")"
  cells=""
  for integrator in whitted path; do
    args=$whitted_args
    [ "$integrator" = path ] && args=$path_args
    png=$out/$( [ "$name" = Bunny ] && echo bunny || echo "cornell-$(echo "$name" | tr 'A-Z' 'a-z')")-$integrator.png
    # shellcheck disable=SC2086
    build/bin/penumbra "$scene" -o "$png" --width "$size" --height "$size" --threads "$threads" \
      --integrator "$integrator" $args $extra --stats-json "$tmp/stats.json" -q
    seconds=$(python3 -c "import json; s = json.load(open('$tmp/stats.json')); print('%.1f' % s['render_seconds'])")
    rays=$(python3 -c "import json; s = json.load(open('$tmp/stats.json')); print('%.1f' % (s['rays']['total'] / 1e6))")
    echo "$name $integrator: ${seconds} s, ${rays} M rays" >&2
    cells="$cells | ![$name $integrator]($(basename "$png"))<br>${seconds} s, ${rays} M rays"
  done
  echo "$row$cells |" >>"$tmp/README.md"
done
cp "$tmp/README.md" "$out/README.md"
echo "wrote $out/README.md" >&2
