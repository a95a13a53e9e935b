# Compiler flags shared by every d2vdb target: warnings, -Werror in CI, sanitizers on request.
add_library(d2vdb_build_flags INTERFACE)
target_compile_options(d2vdb_build_flags INTERFACE -Wall -Wextra -Wpedantic)
if(D2VDB_WERROR)
  target_compile_options(d2vdb_build_flags INTERFACE -Werror)
endif()
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # In a unity build a class of one source file whose member uses a type from that file's
  # anonymous namespace looks to GCC like a header's class doing so (-Wsubobject-linkage), which
  # it is not: each source file's names stay its own.
  target_compile_options(d2vdb_build_flags INTERFACE -Wno-subobject-linkage)
endif()
if(D2VDB_FUZZ)
  # libFuzzer: coverage instrumentation on every d2vdb object, the fuzzer's main only in the
  # fuzz_* programs (tests/CMakeLists.txt); sanitizers as in the ASan build.
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "D2VDB_FUZZ needs clang: configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  if(D2VDB_SANITIZE)
    message(FATAL_ERROR "D2VDB_FUZZ brings its own sanitizers; leave D2VDB_SANITIZE off")
  endif()
  target_compile_options(d2vdb_build_flags INTERFACE -fsanitize=fuzzer-no-link,address,undefined
    -fno-sanitize-recover=undefined -fno-omit-frame-pointer
    -fsanitize-ignorelist=${PROJECT_SOURCE_DIR}/tests/sanitizer-ignorelist.txt)
  target_link_options(d2vdb_build_flags INTERFACE -fsanitize=address,undefined)
elseif(D2VDB_SANITIZE STREQUAL "thread")
  # ThreadSanitizer: data races in d2vdb's parallel code. Run the tests with tools/tsan.sh, which
  # puts an instrumented TBB in front of Debian's (RELIABILITY.md). -O1 -g1 as for ASan below.
  target_compile_options(d2vdb_build_flags INTERFACE -O1 -g1 -fsanitize=thread
    -fno-omit-frame-pointer)
  target_link_options(d2vdb_build_flags INTERFACE -fsanitize=thread)
elseif(D2VDB_SANITIZE)
  # -O1 -g1 come after the build type's flags and override them: with -O2 -g, ASan + UBSan made the
  # heaviest OpenVDB translation unit 8.6x slower to compile than the Release build (419 s against
  # 48.5 s of CPU); -O1 -g1 takes 189 s and still gives stack traces with line numbers.
  target_compile_options(d2vdb_build_flags INTERFACE -O1 -g1
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # Third-party header code whose reports are known and harmless (the file says which).
    target_compile_options(d2vdb_build_flags INTERFACE
      -fsanitize-ignorelist=${PROJECT_SOURCE_DIR}/tests/sanitizer-ignorelist.txt)
  endif()
  target_link_options(d2vdb_build_flags INTERFACE -fsanitize=address,undefined)
endif()
