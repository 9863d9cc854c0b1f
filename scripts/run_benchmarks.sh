#!/usr/bin/env bash
# One benchmark run: penumbra-bench and the anchors, then docs/benchmarks.md
# generated from their output (scripts/make_benchmarks_doc.py). Run from
# anywhere after the README's build; ../shared must lie beside the repository.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
# penumbra-bench runs from a copy of the built libraries, as the anchors'
# processes do (scripts/bench_anchors.sh says why).
libs=$(mktemp -d)
trap 'rm -rf "$libs"' EXIT
cp -P build/lib/*.so* "$libs/"
LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" build/bin/penumbra-bench --obj ../shared/scenes/bunny_stanford/bun_zipper.obj \
  --obj ../shared/scenes/dragon_100k/dragon.obj \
  --scene ../shared/bench/textbook_fig18_04.json --scene ../shared/bench/textbook_fig24_06.json \
  --scene ../shared/bench/room.json \
  --json docs/bench_rays.json --plot docs/bench_rays.png "$@" | tee docs/bench_rays.txt
scripts/bench_anchors.sh --pairs 3 --reps 3 --out docs/bench_anchors.json 2>&1 | tee docs/bench_anchors.txt
python3 scripts/make_benchmarks_doc.py
echo "docs/benchmarks.md regenerated"
