#!/usr/bin/env bash
# The anchor rows of issue 14, taken side by side on this machine:
#   * textbook scenes (../shared/bench/textbook_*.json): Penumbra's render time
#     per camera sample per thread, 1 and 2 threads (from --stats-json);
#   * POV-Ray 3.7 against Penumbra on the room and Figure 24.6, whole processes,
#     interleaved (POV, Penumbra, POV, Penumbra, ...), median of the pair-wise
#     ratios of wall time and of CPU time (user + sys);
#   * `penumbra --help` wall time and the peak memory of a 32-triangle render
#     written to PFM (a process that loads no image library).
# Writes JSON (every run's raw figures) to $OUT (default bench_anchors.json)
# and a human-readable log to stdout. Installs Debian's povray when missing
# (as root); without it the POV-Ray rows are skipped and say so.
#
#   scripts/bench_anchors.sh [--pairs N] [--reps N] [--out FILE] [--build DIR]
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
build="$here/build"
bench_dir="$here/../shared/bench"
out=bench_anchors.json
pairs=5
reps=3
while [[ $# -gt 0 ]]; do
  case "$1" in
    --pairs) pairs=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --bench-dir) bench_dir=$2; shift 2 ;;
    *) echo "bench_anchors.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
penumbra="$build/bin/penumbra"
[[ -x "$penumbra" ]] || { echo "bench_anchors.sh: $penumbra not built" >&2; exit 1; }
[[ -d "$bench_dir" ]] || { echo "bench_anchors.sh: $bench_dir not found" >&2; exit 1; }

if ! command -v povray > /dev/null; then
  if [[ $(id -u) -eq 0 ]] && command -v apt-get > /dev/null; then
    echo "installing povray (Debian package)" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y povray > /dev/null 2>&1 || true
  fi
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
runs="$tmp/runs.jsonl"
: > "$runs"

# Each Penumbra process runs from a fresh copy of the built libraries (found
# through LD_LIBRARY_PATH, which comes before the build's RUNPATH). Identical
# library files were measured up to 10% apart in render time on this machine
# (the file the linker wrote against copies of it; the copies ran alike), so
# the medians sample that spread instead of inheriting one file's placement.
export LD_LIBRARY_PATH="$tmp/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
fresh_libs() {
  rm -rf "$tmp/lib"
  mkdir -p "$tmp/lib"
  cp -P "$build"/lib/*.so* "$tmp/lib/"
}

# timed NAME KIND -- CMD...: one whole-process run; appends a JSON line with
# wall, user and sys seconds and peak RSS (KiB), plus the stats JSON if any.
timed() {
  local name=$1 kind=$2
  shift 3
  local stats="$tmp/stats.json"
  rm -f "$stats"
  /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" "$@" > /dev/null 2> "$tmp/err.txt" ||
    { echo "bench_anchors.sh: failed: $*" >&2; cat "$tmp/err.txt" >&2; exit 1; }
  read -r wall user sys rss < "$tmp/time.txt"
  local st=null
  [[ -s "$stats" ]] && st=$(python3 -c 'import json, sys; print(json.dumps(json.load(open(sys.argv[1]))))' "$stats")
  printf '{"name":"%s","kind":"%s","wall":%s,"user":%s,"sys":%s,"max_rss_kib":%s,"stats":%s}\n' \
    "$name" "$kind" "$wall" "$user" "$sys" "$rss" "$st" >> "$runs"
  echo "  $name [$kind] wall ${wall}s user ${user}s sys ${sys}s rss ${rss}KiB" >&2
}

echo "penumbra --help and a 32-triangle render" >&2
for i in $(seq 1 10); do fresh_libs; timed help penumbra -- "$penumbra" --help; done
for i in $(seq 1 3); do
  fresh_libs
  timed cornell32 penumbra -- "$penumbra" "$here/assets/cornell/cornell.obj" --width 64 --height 64 --spp 1 \
    -o "$tmp/c.pfm" -q --stats-json "$tmp/stats.json"
done

echo "textbook scenes (render time per camera sample from --stats-json)" >&2
for scene in textbook_fig18_04 textbook_fig24_06; do
  for i in $(seq 1 "$reps"); do
    for t in 1 2; do
      fresh_libs
      timed "$scene" "penumbra_${t}t" -- "$penumbra" "$bench_dir/$scene.json" --threads $t -o "$tmp/t.exr" -q \
        --stats-json "$tmp/stats.json"
    done
  done
done

# POV-Ray against Penumbra: each config is (name, scene, POV-Ray switches, Penumbra options); a scene
# is its POV-Ray file, its Penumbra file and its size.
declare -A scene_pov scene_json scene_size
scene_pov[room]="$bench_dir/room.pov"; scene_json[room]="$bench_dir/room.json"; scene_size[room]="512 512"
scene_pov[fig24_06]="$here/assets/scenes/bench/textbook_fig24_06.pov"
scene_json[fig24_06]="$bench_dir/textbook_fig24_06.json"; scene_size[fig24_06]="600 400"
declare -a cfg_name cfg_scene cfg_pov cfg_pen
cfg_name+=(noaa_n8); cfg_scene+=(room); cfg_pov+=("-A Declare=N=8 Declare=ADAPT=-1"); cfg_pen+=("--spp 1 --light-samples 64")
cfg_name+=(noaa_n4); cfg_scene+=(room); cfg_pov+=("-A Declare=N=4 Declare=ADAPT=-1"); cfg_pen+=("--spp 1 --light-samples 16")
cfg_name+=(aa3_n4); cfg_scene+=(room); cfg_pov+=("+A0.0 +AM1 +R3 Declare=N=4 Declare=ADAPT=-1"); cfg_pen+=("--spp 16 --light-samples 16")
# (POV-Ray AA 3x3 with 8x8 against --spp 9 --light-samples 64 is left out: it alone would take minutes.)
# Figure 24.6: mirrors to depth 10 and one point light. +AM1 +R4 traces a jittered 4x4 grid in every
# pixel (16 rays, plus the pixel corners), as the scene's 16 samples per pixel.
cfg_name+=(fig24_aa4); cfg_scene+=(fig24_06); cfg_pov+=("+A0.0 +AM1 +R4 +J"); cfg_pen+=("")
cfg_name+=(fig24_noaa); cfg_scene+=(fig24_06); cfg_pov+=("-A"); cfg_pen+=("--spp 1")
pov_version=null
if command -v povray > /dev/null; then
  pov_version="\"$(povray --version 2>&1 | grep -m1 '^POV-Ray' | tr -d '"')\""
  echo "POV-Ray / Penumbra on room and Figure 24.6, 2 threads each, $pairs interleaved pairs" >&2
  for c in "${!cfg_name[@]}"; do
    s=${cfg_scene[$c]}
    read -r w h <<< "${scene_size[$s]}"
    for i in $(seq 1 "$pairs"); do
      # shellcheck disable=SC2086
      (cd "$(dirname "${scene_pov[$s]}")" && timed "${cfg_name[$c]}" povray -- povray -D -GR \
        +I"$(basename "${scene_pov[$s]}")" +O"$tmp/$s.png" +W$w +H$h +WT2 ${cfg_pov[$c]})
      fresh_libs
      # shellcheck disable=SC2086
      timed "${cfg_name[$c]}" penumbra -- "$penumbra" "${scene_json[$s]}" ${cfg_pen[$c]} --threads 2 \
        -o "$tmp/$s.png" -q --stats-json "$tmp/stats.json"
    done
  done
else
  echo "povray not installed: POV-Ray rows skipped" >&2
fi

cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
{
  printf '{"format_version":1,"date":"%s","commit":"%s","command":"%s",' "$(date -u '+%Y-%m-%d %H:%M UTC')" \
    "$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)" "scripts/bench_anchors.sh --pairs $pairs --reps $reps"
  printf '"machine":{"cpu":"%s","cores":%s,"load_average_at_start":"%s"},' "$cpu" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
  printf '"povray":%s,"config":[' "$pov_version"
  for c in "${!cfg_name[@]}"; do
    [[ $c -gt 0 ]] && printf ','
    printf '{"name":"%s","scene":"%s","povray":"+WT2 %s","penumbra":"%s--threads 2"}' "${cfg_name[$c]}" "${cfg_scene[$c]}" \
      "${cfg_pov[$c]}" "${cfg_pen[$c]:+${cfg_pen[$c]} }"
  done
  printf '],"runs":['
  paste -sd, "$runs"
  printf ']}\n'
} > "$out"
python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$out"
echo "wrote $out" >&2
