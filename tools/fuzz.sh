#!/usr/bin/env bash
# Runs one libFuzzer target of d2vdb (tests/fuzz/FuzzEntryPoints.cc) for a given time:
#   tools/fuzz.sh TARGET SECONDS [more libFuzzer flags]
#   tools/fuzz.sh list                      the targets
# Installs clang and the libFuzzer runtime from Debian when missing, builds fuzz_TARGET with
# ASan + UBSan in build-fuzz/ (D2VDB_FUZZ_BUILD_DIR), and runs it at the lowest CPU priority on
# a working corpus build-fuzz/corpus/TARGET started from tests/fuzz/seeds/TARGET and
# tests/fuzz/regressions/TARGET. An input that takes more than 1 s is a hang; crashes, leaks, hangs
# and inputs that allocate more than 1 GB at once are written to build-fuzz/findings/TARGET/.
# Keep a finding as a regression test by copying it to tests/fuzz/regressions/TARGET/ (the test
# suite replays that folder) once it is fixed. See RELIABILITY.md.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
targets=(obj ply stl spline_json polyline_json xyz vdb field input)

if [ "${1:-}" = list ]; then printf '%s\n' "${targets[@]}"; exit 0; fi
if [ $# -lt 2 ] || ! [[ "$2" =~ ^[0-9]+$ ]] || [[ ! " ${targets[*]} " =~ " $1 " ]]; then
  echo "usage: tools/fuzz.sh TARGET SECONDS [libFuzzer flags...]; targets: ${targets[*]}" >&2
  exit 1
fi
target=$1
seconds=$2
shift 2

# clang, the libFuzzer runtime and llvm-symbolizer (readable stack traces), besides d2vdb's own
# dependencies.
EXTRA_PACKAGES="clang libclang-rt-14-dev llvm" tools/setup.sh deps

build_dir=${D2VDB_FUZZ_BUILD_DIR:-build-fuzz}
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DD2VDB_FUZZ=ON \
  ${D2VDB_FUZZ_CMAKE_ARGS:-} >/dev/null
nice -n 19 cmake --build "$build_dir" -j "${D2VDB_JOBS:-2}" --target "fuzz_$target"

corpus="$build_dir/corpus/$target"
findings="$build_dir/findings/$target"
mkdir -p "$corpus" "$findings"
dictionary=()
if [ -f "tests/fuzz/dictionaries/$target.dict" ]; then
  dictionary=(-dict="tests/fuzz/dictionaries/$target.dict")
fi
seeds=(tests/fuzz/seeds/"$target")
if [ -d "tests/fuzz/regressions/$target" ]; then seeds+=(tests/fuzz/regressions/"$target"); fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
echo "== fuzzing $target for $seconds s (corpus $corpus, findings $findings)"
exec nice -n 19 "$build_dir/tests/fuzz_$target" -max_total_time="$seconds" -timeout=1 \
  -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1 -use_value_profile=1 \
  -artifact_prefix="$findings/" "${dictionary[@]}" "$@" "$corpus" "${seeds[@]}"
