#!/usr/bin/env bash
# Renders McGuire's CornellBox-Original, -Water and -Glossy with both
# integrators (256x256 PNG) into docs/gallery/ and writes docs/gallery/README.md
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
    *) echo "$src/CornellBox-$1.obj" ;;
  esac
}

{
  echo "# Gallery: \`whitted\` and \`path\` side by side"
  echo
  echo "McGuire's Cornell boxes (\`../shared/scenes/cornell_mcguire\`, CC BY 3.0, Cardenas & McGuire 2011),"
  echo "${size}x${size}, rendered by \`scripts/make_gallery.sh\` on $(nproc) cores of"
  echo "\`$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')\`, $(date -u +%Y-%m-%d)."
  echo "\`whitted\`: \`$whitted_args\`; \`path\`: \`$path_args\` (default \`--max-depth 10\`)."
  echo "CornellBox-Glossy gets Original's light (its MTL has none; see the script)."
  echo "Water's water and Sphere's glass say \`Tf 0.1\` in their MTL: dark glass (docs/mtl-mapping.md)."
  echo "Times are render seconds from \`--stats-json\` (one run each, not a benchmark)."
  echo
  echo "| scene | whitted | path |"
  echo "| --- | --- | --- |"
} >"$tmp/README.md"

for name in Original Water Glossy; do
  scene=$(scene_file "$name")
  row="| CornellBox-$name"
  cells=""
  for integrator in whitted path; do
    args=$whitted_args
    [ "$integrator" = path ] && args=$path_args
    png=$out/cornell-$(echo "$name" | tr 'A-Z' 'a-z')-$integrator.png
    # shellcheck disable=SC2086
    build/bin/penumbra "$scene" -o "$png" --width "$size" --height "$size" --threads "$threads" \
      --integrator "$integrator" $args --stats-json "$tmp/stats.json" -q
    seconds=$(python3 -c "import json; s = json.load(open('$tmp/stats.json')); print('%.1f' % s['render_seconds'])")
    rays=$(python3 -c "import json; s = json.load(open('$tmp/stats.json')); print('%.1f' % (s['rays']['total'] / 1e6))")
    echo "$name $integrator: ${seconds} s, ${rays} M rays" >&2
    cells="$cells | ![$name $integrator]($(basename "$png"))<br>${seconds} s, ${rays} M rays"
  done
  echo "$row$cells |" >>"$tmp/README.md"
done
cp "$tmp/README.md" "$out/README.md"
echo "wrote $out/README.md" >&2
