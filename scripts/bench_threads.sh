#!/usr/bin/env bash
# Thread scaling of whole renders: the anchor scenes (../shared/bench) and the
# default scene at 1, 2, 4, ... threads, --reps times each, render seconds
# from --stats-json, and each image compared bit for bit with the 1-thread
# image of the same repetition (determinism). Prints the machine and one line
# per render; scripts/make_benchmarks_doc.py turns a saved copy
# (docs/bench_threads.txt) into a table.
#
#   scripts/bench_threads.sh [--threads "1 2 4 8 16"] [--reps N] [--bench-dir DIR]
#
# PENUMBRA overrides the command that runs the renderer (default
# build/bin/penumbra), e.g. a build carried to another machine and started by
# its own dynamic loader: PENUMBRA="DIR/ld-linux-x86-64.so.2 --library-path DIR DIR/penumbra"
# (PENUMBRA_COMMIT then names the commit it was built from).
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
bench_dir="$here/../shared/bench"
threads="1 2"
reps=2
while [[ $# -gt 0 ]]; do
  case "$1" in
    --threads) threads=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --bench-dir) bench_dir=$2; shift 2 ;;
    *) echo "bench_threads.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
read -r -a penumbra <<< "${PENUMBRA:-$here/build/bin/penumbra}"
[[ -d "$bench_dir" ]] || { echo "bench_threads.sh: $bench_dir not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "# bench_threads.sh --threads \"$threads\" --reps $reps"
commit=${PENUMBRA_COMMIT:-$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)}
echo "# date $(date -u +%Y-%m-%dT%H:%M:%SZ), commit $commit"
echo "# machine $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) hardware threads"
echo "scene threads rep render_seconds identical_to_1_thread"
names=(textbook_fig18_04 textbook_fig24_06 room_noaa_64 room_aa_16x16 cornell)
args=("$bench_dir/textbook_fig18_04.json" "$bench_dir/textbook_fig24_06.json"
      "$bench_dir/room.json --spp 1 --light-samples 64" "$bench_dir/room.json --spp 16 --light-samples 16"
      "$here/assets/cornell/cornell.obj")
for i in "${!names[@]}"; do
  for rep in $(seq 1 "$reps"); do
    for t in $threads; do
      rm -f "$tmp/stats.json"
      # shellcheck disable=SC2086
      "${penumbra[@]}" ${args[$i]} --threads "$t" -q -o "$tmp/t$t.pfm" --stats-json "$tmp/stats.json"
      same=no
      cmp -s "$tmp/t1.pfm" "$tmp/t$t.pfm" && same=yes
      seconds=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['render_seconds'])" "$tmp/stats.json")
      echo "${names[$i]} $t $rep $seconds $same"
    done
  done
done
