# Compiler flags shared by every d2vdb target: warnings, -Werror in CI, sanitizers on request.
add_library(d2vdb_build_flags INTERFACE)
target_compile_options(d2vdb_build_flags INTERFACE -Wall -Wextra -Wpedantic)
if(D2VDB_WERROR)
  target_compile_options(d2vdb_build_flags INTERFACE -Werror)
endif()
if(D2VDB_SANITIZE)
  target_compile_options(d2vdb_build_flags INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(d2vdb_build_flags INTERFACE -fsanitize=address,undefined)
endif()
