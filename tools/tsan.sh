#!/usr/bin/env bash
# Runs d2vdb's parallel tests under ThreadSanitizer with a ThreadSanitizer-instrumented TBB:
#   tools/tsan.sh            build (if needed) and run the tests of test_threads
# Debian's libtbb.so.12 is not instrumented, so TSan would not see the synchronisation by which TBB
# hands a task to a worker thread and joins it, and would report every parallel loop. This script
# builds the same TBB from Debian's source package of the installed libtbb-dev (apt-get source
# through a private package list, so the system's apt sources stay as they are), with oneTBB's own
# TBB_SANITIZE=thread, and runs the tests against it through LD_LIBRARY_PATH (same soname, same
# headers; OpenVDB's library picks it up too). d2vdb is built with -DD2VDB_SANITIZE=thread
# (-O1 -g1) in build-tsan/ (D2VDB_TSAN_BUILD_DIR). Suppressions: tests/tsan-suppressions.txt,
# each explained there. See RELIABILITY.md.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
build_dir=${D2VDB_TSAN_BUILD_DIR:-build-tsan}
jobs=${D2VDB_JOBS:-$(nproc 2>/dev/null || echo 2)}

# dpkg-dev unpacks the source package (dpkg-source applies Debian's patches).
EXTRA_PACKAGES="dpkg-dev xz-utils" tools/setup.sh deps

# ---- TBB from Debian's source, instrumented ------------------------------------------------------
tbb_dir=$(realpath -m "$build_dir/tbb")
tbb_version=$(dpkg-query -W -f='${source:Version}' libtbb-dev)
tbb_lib="$tbb_dir/lib"
if [ ! -f "$tbb_lib/libtbb.so.12" ] || [ "$(cat "$tbb_dir/version" 2>/dev/null)" != "$tbb_version" ]; then
  echo "== building TBB $tbb_version with ThreadSanitizer in $tbb_dir"
  rm -rf "$tbb_dir"
  mkdir -p "$tbb_dir/apt/lists/partial" "$tbb_dir/apt/cache" "$tbb_dir/apt/sources"
  # The suite and mirror of the system's own Debian sources, as a deb-src entry of a private list.
  mirror=$(apt-get indextargets --format '$(REPO_URI)' 'Created-By: Packages' 2>/dev/null |
    grep -m1 -E 'debian/?$' || echo http://deb.debian.org/debian/)
  cat > "$tbb_dir/apt/sources/debian-src.sources" <<EOF
Types: deb-src
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
  touch "$tbb_dir/apt/none.list"
  apt_private=(-o "Dir::Etc::SourceList=$tbb_dir/apt/none.list"
               -o "Dir::Etc::SourceParts=$tbb_dir/apt/sources"
               -o "Dir::State::Lists=$tbb_dir/apt/lists"
               -o "Dir::Cache=$tbb_dir/apt/cache"
               -o "APT::Sandbox::User=$(id -un)")
  apt-get -q "${apt_private[@]}" update >/dev/null
  (cd "$tbb_dir" && apt-get -q "${apt_private[@]}" source --download-only "onetbb=$tbb_version" >/dev/null &&
     dpkg-source -x --no-check onetbb_*.dsc source >/dev/null)
  cmake -S "$tbb_dir/source" -B "$tbb_dir/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBBMALLOC_BUILD=OFF -DTBB_STRICT=OFF \
    -DTBB_ENABLE_IPO=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON >/dev/null
  cmake --build "$tbb_dir/build" -j "$jobs" >/dev/null
  mkdir -p "$tbb_lib"
  cp -P "$tbb_dir"/build/*/libtbb.so* "$tbb_lib/"
  echo "$tbb_version" > "$tbb_dir/version"
fi

# ---- d2vdb's parallel tests ----------------------------------------------------------------------
echo "== building test_threads with ThreadSanitizer in $build_dir"
# shellcheck disable=SC2086  # D2VDB_CMAKE_ARGS is a list of flags
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DD2VDB_SANITIZE=thread \
  ${D2VDB_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$jobs" --target test_threads

echo "== running the parallel tests under ThreadSanitizer"
export LD_LIBRARY_PATH="$tbb_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tests/tsan-suppressions.txt ${TSAN_OPTIONS:-}"
# The tests that run each parallel algorithm with 1 and with 2 threads (field build and batch
# queries, mesh to level set and its signs, smooth-surface fields, marching cubes, curve, cloud,
# surface and support fitting, Hausdorff distance, projection); the rest of test_threads runs the
# same code on one shape after another and takes ten times longer under TSan.
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" \
  -R '^tsan[.].*(OneAndTwoThreads|AnyThreadCount|BothPasses|FieldFit[.])'
