#!/usr/bin/env bash
# Fuzzes the scene loaders: builds the libFuzzer targets with clang (the fuzz
# preset, build-fuzz/) and runs each for N seconds (default 60) on its seed
# corpus in tests/fuzz/. Exits non-zero when a target crashes, trips a
# sanitizer or breaks an invariant; the input that did it is kept in
# build-fuzz/artifacts/<target>/ (replay: build-fuzz/bin/<target> FILE).
# New interesting inputs go to build-fuzz/corpus/<target>/, never into the source tree.
#   usage: scripts/fuzz.sh [SECONDS] [TARGET...]     (targets: fuzz_obj fuzz_json fuzz_model)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(fuzz_obj fuzz_json fuzz_model)
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2; }
# Inputs up to 1 MiB reach the loaders' size paths: faces beyond 255 and 512
# corners with v/vt/vn indices, objects past 16 keys (hashed duplicate check)
# with real bodies, pointers longer than the 240-byte cut, arrays of thousands
# (the seeds in tests/fuzz/corpus_* include such files; 16 KiB reached few).
max_len=${PENUMBRA_FUZZ_MAX_LEN:-1048576}

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (scripts/setup.sh installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)" --target "${targets[@]}"

failed=()
for t in "${targets[@]}"; do
  bin=build-fuzz/bin/$t
  [[ -x "$bin" ]] || { echo "fuzz.sh: $bin was not built (is tests/fuzz added to the build?)" >&2; exit 1; }
  kind=${t#fuzz_}
  work=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  mkdir -p "$work" "$artifacts"
  echo "fuzz.sh: $t for ${seconds}s"
  # abort_on_error: a finding ends the run with a signal, which libFuzzer reports as a crash.
  # lsan.supp: third-party leaks Penumbra cannot avoid, each with its evidence. Its
  # entries name our callers of such code, which allocation stacks reach only with
  # the slow unwinder (libassimp has no frame pointers): fuzz_model uses it.
  unwind=1
  [[ $t == fuzz_model ]] && unwind=0
  if ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:fast_unwind_on_malloc=$unwind:${ASAN_OPTIONS:-}" \
     LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}" \
     UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1:${UBSAN_OPTIONS:-}" \
     "$bin" "$work" "tests/fuzz/corpus_$kind" \
       -dict="tests/fuzz/$kind.dict" \
       -max_total_time="$seconds" \
       -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
       -artifact_prefix="$artifacts/" -print_final_stats=1 \
       > "build-fuzz/$t.log" 2>&1; then
    grep -E "^(#[0-9]+.*DONE|stat::number_of_executed_units|stat::peak_rss_mb)" "build-fuzz/$t.log" || true
  else
    echo "fuzz.sh: $t FAILED; log: build-fuzz/$t.log; inputs: $artifacts/" >&2
    tail -n 40 "build-fuzz/$t.log" >&2
    failed+=("$t")
  fi
done

if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz.sh: failures in: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz.sh: no findings in ${targets[*]} (${seconds}s each)"
