#!/usr/bin/env bash
# The large-scene check: builds penumbra-scale (Release, build/) and runs it on
# a 10-million-triangle heightfield generated in memory; prints the time of
# each step, the peak memory and the bytes per triangle (Penumbra's arrays and
# Embree's BVH), and writes build/scale_10m.json and build/scale_10m.png.
# It must fit in 24 GiB. Extra arguments go to penumbra-scale (e.g. --triangles 20000000).
set -euo pipefail
cd "$(dirname "$0")/.."

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target penumbra-scale
build/bin/penumbra-scale --triangles 10000000 --json build/scale_10m.json -o build/scale_10m.png "$@"
