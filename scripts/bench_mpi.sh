#!/usr/bin/env bash
# Scaling of penumbra-mpi over 1, 2 and 3 ranks on this machine: time and
# efficiency. One rank renders the frame itself; with more, rank 0 hands out
# tiles and the other ranks render them, so N ranks have N-1 rendering ranks.
# Each rank renders with one thread (--threads 1) so that ranks, not threads,
# do the scaling. The configurations run interleaved, ROUNDS times, and the
# best time of each is kept (the machine drifts; other work shares it).
#
# Usage: scripts/bench_mpi.sh [BUILD_DIR] [ROUNDS]
#   env: SCENE (default assets/scenes/showcase.json), WIDTH, HEIGHT, SPP, RANKS ("1 2 3")
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
rounds=${2:-3}
scene=${SCENE:-$root/assets/scenes/showcase.json}
width=${WIDTH:-480}
height=${HEIGHT:-320}
spp=${SPP:-48}
ranks_list=${RANKS:-"1 2 3"}
bin=$build/bin/penumbra-mpi
[[ -x $bin ]] || { echo "bench_mpi: $bin not built (MPI not found?)" >&2; exit 1; }

export OMPI_MCA_btl_vader_single_copy_mechanism=none
mpirun=(mpirun --oversubscribe --mca btl self,vader)
[[ $(id -u) -eq 0 ]] && mpirun+=(--allow-run-as-root)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
json_number() { sed -n "s/^  \"$2\": \([0-9.eE+-]*\),\{0,1\}$/\1/p" "$1"; }

echo "# penumbra-mpi scaling: $(basename "$scene") ${width}x${height}, $spp spp, --threads 1 per rank"
echo "# machine: $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')), $(date -u +%Y-%m-%dT%H:%MZ)"
echo "# load average before: $(cut -d' ' -f1-3 /proc/loadavg) (other work on the machine makes the figures noisy)"
echo "# raw runs: round ranks render_s job_s (render: rank 0's first tile out to last tile back; job: the whole mpirun)"
declare -A best_render best_job
for round in $(seq 1 "$rounds"); do
    for n in $ranks_list; do
        start=$(date +%s.%N)
        "${mpirun[@]}" -np "$n" "$bin" "$scene" -q --width "$width" --height "$height" --spp "$spp" --threads 1 \
            -o "$tmp/out$n.pfm" --stats-json "$tmp/stats$n.json"
        end=$(date +%s.%N)
        render=$(json_number "$tmp/stats$n.json" render_seconds)
        job=$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')
        printf "run %d %d %.3f %.3f\n" "$round" "$n" "$render" "$job"
        best_render[$n]=$(awk -v a="${best_render[$n]:-inf}" -v b="$render" 'BEGIN { print (b < a ? b : a) }')
        best_job[$n]=$(awk -v a="${best_job[$n]:-inf}" -v b="$job" 'BEGIN { print (b < a ? b : a) }')
    done
done
# The images of all rank counts are the same, bit for bit (PFM: raw floats).
for n in $ranks_list; do
    cmp -s "$tmp/out1.pfm" "$tmp/out$n.pfm" || { echo "bench_mpi: the $n-rank image differs from the 1-rank one" >&2; exit 1; }
done
echo "# images of all rank counts identical (cmp of the PFM files)"
echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| ranks | rendering ranks | render s (best) | speed-up | efficiency per rank | efficiency per rendering rank | job s (best) |"
echo "|---|---|---|---|---|---|---|"
t1=${best_render[1]}
for n in $ranks_list; do
    workers=$(( n == 1 ? 1 : n - 1 ))
    awk -v n="$n" -v w="$workers" -v t1="$t1" -v t="${best_render[$n]}" -v job="${best_job[$n]}" 'BEGIN {
        s = t1 / t
        printf "| %d | %d | %.3f | %.2f | %.0f%% | %.0f%% | %.2f |\n", n, w, t, s, 100 * s / n, 100 * s / w, job }'
done
