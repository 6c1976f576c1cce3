#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, build-fuzz/) and fuzzes each for a bounded
# time, one after the other (docs/reliability.md, "Fuzzing"):
#
#   fuzz/run-fuzzers.sh [SECONDS] [TARGET...]     # default: 1200 s each, all targets
#
# Targets: case_file, expression, gmsh_msh. Each starts from its kept corpus
# fuzz/corpus/<target>/ and fresh seeds (fuzz/make-seeds.py), runs in libFuzzer's
# fork mode (crashes, hangs and out-of-memory runs are written to
# build-fuzz/work/<target>/artifacts/ and fuzzing goes on), logs to
# build-fuzz/work/<target>.log, and finally merges what it found into the kept
# corpus, minimized (-merge=1: only inputs that add coverage).
# Needs clang and libclang-rt-14-dev (libFuzzer).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-1200}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(case_file expression gmsh_msh)

build=build-fuzz
if [ ! -f $build/CMakeCache.txt ]; then
  CXX=clang++ cmake -S . -B $build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DBUILD_TESTING=OFF -DVPCONTACT_BENCHMARKS=OFF -DVPCONTACT_FUZZ=ON > /dev/null
fi
cmake --build $build -j "${JOBS:-2}" --target "${targets[@]/#/fuzz_}"

work=$build/work
rm -rf $work/seeds
/usr/bin/python3 fuzz/make-seeds.py $work/seeds > /dev/null
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
# A crash in vpcontact's own code must abort with a report; UBSan stops at the first.
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
for t in "${targets[@]}"; do
  mkdir -p $work/$t/corpus $work/$t/artifacts fuzz/corpus/$t
  echo "fuzz_$t: ${seconds} s, log in $work/$t.log"
  # Gmsh leaks when it rejects a file (tests/lsan.supp); checking for leaks after
  # every input would be slow, so gmsh_msh checks only at exit.
  leaks=1
  [ "$t" = gmsh_msh ] && leaks=0
  ( cd $work/$t && "$OLDPWD/$build/fuzz/fuzz_$t" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
      -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -detect_leaks=$leaks \
      -dict="$OLDPWD/fuzz/$t.dict" -artifact_prefix=artifacts/ \
      corpus "$OLDPWD/fuzz/corpus/$t" "$OLDPWD/$work/seeds/$t" ) > $work/$t.log 2>&1 || true
  grep -E '^#[0-9]+: cov' $work/$t.log | tail -1 || true
  # Minimize: the kept corpus becomes the smallest set with the same coverage.
  rm -rf $work/$t/merged && mkdir -p $work/$t/merged
  "$build/fuzz/fuzz_$t" -merge=1 -timeout=5 -rss_limit_mb=2048 -detect_leaks=0 \
    $work/$t/merged fuzz/corpus/$t $work/$t/corpus $work/seeds/$t > $work/$t.merge.log 2>&1
  rm -rf fuzz/corpus/$t && mv $work/$t/merged fuzz/corpus/$t
  echo "  corpus: $(ls fuzz/corpus/$t | wc -l) files, $(cat fuzz/corpus/$t/* | wc -c) bytes;" \
       "artifacts: $(ls $work/$t/artifacts | wc -l)"
done
