# Compiler flags shared by every d2vdb target: warnings, -Werror in CI, sanitizers on request.
add_library(d2vdb_build_flags INTERFACE)
target_compile_options(d2vdb_build_flags INTERFACE -Wall -Wextra -Wpedantic)
if(D2VDB_WERROR)
  target_compile_options(d2vdb_build_flags INTERFACE -Werror)
endif()
if(D2VDB_SANITIZE)
  # -O1 -g1 come after the build type's flags and override them: with -O2 -g, ASan + UBSan made the
  # heaviest OpenVDB translation unit 8.6x slower to compile than the Release build (419 s against
  # 48.5 s of CPU); -O1 -g1 takes 189 s and still gives stack traces with line numbers.
  target_compile_options(d2vdb_build_flags INTERFACE -O1 -g1
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(d2vdb_build_flags INTERFACE -fsanitize=address,undefined)
endif()
