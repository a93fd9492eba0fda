#!/usr/bin/env bash
# Bounded libFuzzer run over every s3m input format (targets in tests/fuzz/targets_*.cpp).
# Builds build-fuzz/ with Debian's clang (-DS3M_FUZZ=ON: ASan + UBSan + libFuzzer coverage), then runs
# each target for SECONDS (default 60) starting from its seed corpus tests/fuzz/corpus/<target>/.
# New inputs go to build-fuzz/corpus/<target>/ (the repo's seeds stay small); crashes, leaks, timeouts
# and OOMs go to build-fuzz/artifacts/<target>/. Exit status 1 when any target found something.
# A finding becomes a fix plus a regression input: copy it to tests/fuzz/regress/<target>/ (replayed by
# the test_fuzz_corpus unit test in every build).
# Usage: tools/fuzz.sh [--no-build] [SECONDS] [TARGET...]   e.g. tools/fuzz.sh 60, tools/fuzz.sh 300 camera_yaml
set -euo pipefail
cd "$(dirname "$0")/.."
build=1
if [ "${1:-}" = --no-build ]; then build=0; shift; fi
seconds="${1:-60}"
[ $# -gt 0 ] && shift
case "$seconds" in ''|*[!0-9]*) echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2 ;; esac

command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (scripts/setup.sh installs clang)" >&2; exit 2; }
jobs="$(nproc)"; [ "$jobs" -gt 2 ] && jobs=2
[ "$build" = 1 ] && cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DS3M_FUZZ=ON -DS3M_BUILD_BENCH=OFF >/dev/null
[ "$build" = 1 ] && cmake --build build-fuzz -j "$jobs" --target fuzzers

targets=("$@")
if [ "${#targets[@]}" -eq 0 ]; then
  for exe in build-fuzz/tests/fuzz/fuzz_*; do targets+=("${exe##*/fuzz_}"); done
fi

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=1:symbolize=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
failed=()
for t in "${targets[@]}"; do
  exe="build-fuzz/tests/fuzz/fuzz_$t"
  [ -x "$exe" ] || { echo "fuzz.sh: no fuzz target '$t' (built: $(ls build-fuzz/tests/fuzz | grep '^fuzz_' | tr '\n' ' '))" >&2; exit 2; }
  work="build-fuzz/corpus/$t"; art="build-fuzz/artifacts/$t"
  mkdir -p "$work" "$art"
  seeds="tests/fuzz/corpus/$t"
  echo "=== fuzz_$t: ${seconds} s (seeds: $(ls "$seeds" 2>/dev/null | wc -l), log: build-fuzz/fuzz_$t.log)"
  # -timeout: one input taking > 10 s is a hang; -rss_limit_mb: a decompression bomb is a finding too.
  if "$exe" "$work" "$seeds" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
       -print_final_stats=1 -artifact_prefix="$art/" >"build-fuzz/fuzz_$t.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^stat::new_units_added" "build-fuzz/fuzz_$t.log" | tr '\n' ' '; echo
  else
    echo "!!! fuzz_$t found a problem; artifacts in $art:"; ls "$art"
    grep -m 3 -E "ERROR|runtime error|terminate called|what\(\)" "build-fuzz/fuzz_$t.log" || true
    failed+=("$t")
  fi
done
if [ "${#failed[@]}" -gt 0 ]; then
  echo "fuzz.sh: findings in: ${failed[*]}"
  exit 1
fi
echo "fuzz.sh: no findings in ${#targets[@]} targets x ${seconds} s"
