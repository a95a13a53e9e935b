#!/usr/bin/env bash
# d2vdb set-up on Debian 12: installs whatever Debian packages are missing, builds, and then
#   tools/setup.sh demo   runs the main job on the bundled default volume, results in out/
#   tools/setup.sh test   runs the whole test suite with ctest
#   tools/setup.sh build  only installs and builds
#   tools/setup.sh deps   only installs (EXTRA_PACKAGES: more Debian packages, e.g. clang)
# demo builds only the d2vdb command; test and build build everything.
# Both are idempotent: a second run installs nothing and rebuilds only what changed.
# Environment: D2VDB_BUILD_DIR (default build), D2VDB_CMAKE_ARGS (extra configure flags),
#              D2VDB_JOBS (parallel build jobs, default: number of cores).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
mode=${1:-demo}
case "$mode" in demo|test|build|deps) ;; *)
  echo "usage: tools/setup.sh [demo|test|build|deps]" >&2; exit 1 ;;
esac

build_dir=${D2VDB_BUILD_DIR:-build}
jobs=${D2VDB_JOBS:-$(nproc 2>/dev/null || echo 2)}
packages=(g++ cmake ninja-build pkg-config
          libopenvdb-dev libboost-iostreams-dev libtbb-dev libeigen3-dev libblosc-dev zlib1g-dev
          libcli11-dev nlohmann-json3-dev libnanoflann-dev libsuitesparse-dev libopenblas0-serial
          libgtest-dev libbenchmark-dev libopenvdb-tools)
# The Python module (python/) is built for tests and builds: pybind11 against Debian's
# /usr/bin/python3 with numpy, and Boost.Python to hand grids to and from pyopenvdb. The tests
# run it with pytest and read our files with Debian's pyopenvdb, as client pipeline scripts do.
python_packages=(python3-dev python3-numpy pybind11-dev libboost-python-dev)
case "$mode" in
  test) packages+=("${python_packages[@]}" python3-pytest python3-openvdb) ;;
  build) packages+=("${python_packages[@]}") ;;
esac
# shellcheck disable=SC2206  # a list of package names
packages+=(${EXTRA_PACKAGES:-})

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$package")
done
if ((${#missing[@]})); then
  echo "== installing missing Debian packages: ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "error: not root and sudo is not available;" \
      "install as root: apt-get install ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

[ "$mode" = deps ] && exit 0

echo "== configuring and building (Release) in $build_dir"
# shellcheck disable=SC2086  # D2VDB_CMAKE_ARGS is a list of flags
python_flag=()
case "$mode" in test|build) python_flag=(-DD2VDB_BUILD_PYTHON=ON) ;; esac
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${python_flag[@]}" \
  ${D2VDB_CMAKE_ARGS:-} >/dev/null
# The main job needs only the d2vdb command: a newcomer does not wait for the test suite.
targets=()
[ "$mode" = demo ] && targets=(--target d2vdb)
cmake --build "$build_dir" -j "$jobs" "${targets[@]}"

d2vdb="$build_dir/tools/d2vdb"
case "$mode" in
  build) ;;
  test)
    echo "== running the test suite"
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
    ;;
  demo)
    input=${D2VDB_DEMO_INPUT:-volumes/bunny.vdb}
    mkdir -p out
    echo "== main job on $input (results in out/)"
    "$d2vdb" info "$input"
    "$d2vdb" info --json "$input" > out/info.json
    "$d2vdb" convert "$input" out/surface.vdb
    "$d2vdb" info out/surface.vdb
    "$d2vdb" mesh out/surface.vdb out/surface.obj --check
    # The squared-distance approximant field of the level set, and what it answers inside the
    # bunny and outside it (coarse levels beyond the band answer both).
    "$d2vdb" field "$input" out/field.vdb
    if [ "$input" = volumes/bunny.vdb ]; then
      "$d2vdb" query out/field.vdb 0 4.8 0
      "$d2vdb" query out/field.vdb -4.5 4.0 -1.0
    fi
    echo "== wrote out/info.json, out/surface.vdb, out/surface.obj and out/field.vdb"
    ;;
esac
