#!/usr/bin/env bash
# Start-up cost of the penumbra command: wall time of `penumbra --help`, and
# peak RSS (/usr/bin/time) of a 32-triangle render (assets/cornell, 64x64,
# 4 spp) written to .pfm (no image library loaded) and to .exr (OpenImageIO
# loaded in the process on its first image). Runs the candidates interleaved,
# N rounds, and prints medians.
# Usage: scripts/bench_startup.sh [N] NAME=PENUMBRA_BINARY[:LD_LIBRARY_PATH] ...
set -euo pipefail
rounds=${1:-15}; shift
root=$(cd "$(dirname "$0")/.." && pwd)
scene="$root/assets/cornell/cornell.obj"
out=$(mktemp -d); trap 'rm -rf "$out"' EXIT
declare -A help pfm exr
for ((i = 0; i < rounds; ++i)); do
  for spec in "$@"; do
    name=${spec%%=*}; rest=${spec#*=}; bin=${rest%%:*}; lib=""
    [[ $rest == *:* ]] && lib=${rest#*:}
    run() { LD_LIBRARY_PATH="$lib" /usr/bin/time -f '%e %M' -o "$out/t" "$@" > /dev/null 2>&1; cat "$out/t"; }
    help[$name]+="$(run "$bin" --help | cut -d' ' -f1) "
    pfm[$name]+="$(run "$bin" "$scene" -q --width 64 --height 64 --spp 4 -o "$out/a.pfm" | cut -d' ' -f2) "
    exr[$name]+="$(run "$bin" "$scene" -q --width 64 --height 64 --spp 4 -o "$out/a.exr" | cut -d' ' -f2) "
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
echo "rounds: $rounds, machine: $(nproc) cores, $(uname -r)"
printf '%-10s %18s %22s %22s\n' name "--help wall (s)" "peak RSS .pfm (MiB)" "peak RSS .exr (MiB)"
for spec in "$@"; do
  name=${spec%%=*}
  h=$(echo "${help[$name]}" | median); p=$(echo "${pfm[$name]}" | median); e=$(echo "${exr[$name]}" | median)
  printf '%-10s %18s %22.1f %22.1f\n' "$name" "$h" "$(echo "$p/1024" | bc -l)" "$(echo "$e/1024" | bc -l)"
done
