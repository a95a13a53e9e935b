# Finds every third-party dependency. Each is a Debian package; a missing one stops the configure
# step with the name of the package to install.

function(d2vdb_missing what apt_package)
  message(FATAL_ERROR
    "d2vdb: ${what} was not found. Install it with:\n"
    "    sudo apt-get install ${apt_package}\n"
    "(or run tools/setup.sh, which installs every dependency).")
endfunction()

find_package(Eigen3 3.3 QUIET NO_MODULE)
if(NOT TARGET Eigen3::Eigen)
  d2vdb_missing("Eigen 3" libeigen3-dev)
endif()

find_package(TBB QUIET)
if(NOT TARGET TBB::tbb)
  d2vdb_missing("oneTBB" libtbb-dev)
endif()

# Debian ships OpenVDB's find module (no config file) in its own directory.
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB /usr/lib/cmake/OpenVDB)
find_package(Boost QUIET COMPONENTS iostreams)
if(NOT Boost_IOSTREAMS_FOUND)
  d2vdb_missing("Boost.Iostreams (needed by OpenVDB's headers)" libboost-iostreams-dev)
endif()
find_path(D2VDB_BLOSC_INCLUDE blosc.h)
if(NOT D2VDB_BLOSC_INCLUDE)
  d2vdb_missing("Blosc" libblosc-dev)
endif()
find_package(ZLIB QUIET)
if(NOT ZLIB_FOUND)
  d2vdb_missing("zlib (needed by OpenVDB's find module)" zlib1g-dev)
endif()
find_package(OpenVDB QUIET)
if(NOT TARGET OpenVDB::openvdb)
  d2vdb_missing("OpenVDB" libopenvdb-dev)
endif()
# The .vdb reader checks compressed chunks itself before OpenVDB decompresses them.
if(NOT TARGET Blosc::blosc OR NOT TARGET ZLIB::ZLIB)
  d2vdb_missing("Blosc and zlib as found by OpenVDB's find module" "libblosc-dev zlib1g-dev")
endif()

# CHOLMOD factorises the fitting systems (supernodal, BLAS level 3); Debian's OpenBLAS (serial
# build: deterministic, one thread) makes its dense kernels fast. Only CHOLMOD is a build
# requirement: any BLAS that Debian's alternatives provide works, OpenBLAS only faster.
find_package(CHOLMOD QUIET)
if(NOT TARGET SuiteSparse::CHOLMOD)
  d2vdb_missing("CHOLMOD (SuiteSparse)" libsuitesparse-dev)
endif()

find_package(nlohmann_json 3.9 QUIET)
if(NOT TARGET nlohmann_json::nlohmann_json)
  d2vdb_missing("nlohmann-json" nlohmann-json3-dev)
endif()

find_package(nanoflann QUIET)
if(NOT TARGET nanoflann::nanoflann)
  d2vdb_missing("nanoflann (k-d trees of the approximant field)" libnanoflann-dev)
endif()

find_package(CLI11 QUIET)
if(NOT TARGET CLI11::CLI11)
  d2vdb_missing("CLI11" libcli11-dev)
endif()

if(D2VDB_BUILD_TESTS)
  find_package(GTest QUIET)
  if(NOT TARGET GTest::gtest_main)
    d2vdb_missing("GoogleTest" libgtest-dev)
  endif()
  find_program(D2VDB_VDB_PRINT vdb_print)
  if(NOT D2VDB_VDB_PRINT)
    d2vdb_missing("vdb_print (used by the .vdb interoperability tests)" libopenvdb-tools)
  endif()
endif()

if(D2VDB_BUILD_BENCHMARKS)
  find_package(benchmark QUIET)
  if(NOT TARGET benchmark::benchmark)
    d2vdb_missing("Google Benchmark" libbenchmark-dev)
  endif()
endif()
