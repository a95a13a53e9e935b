# Precompiled third-party headers. OpenVDB's main header takes several seconds of every
# translation unit that includes it (most of the field, contour and io modules, the command line
# and their tests); the targets where most files include it parse it once instead of once per
# file. Only headers that those files already include (directly or through the modules' public
# headers) are precompiled, so a build without them (-DD2VDB_PRECOMPILED_HEADERS=OFF) sees the same
# code. ccache does not cache compilations that use a precompiled header unless its sloppiness
# allows it (pch_defines,time_macros); with ccache, turning them off is simpler.
option(D2VDB_PRECOMPILED_HEADERS "Precompile OpenVDB's header for the targets that mostly use it" ON)

# The headers precompiled with OpenVDB's: Eigen's, which every file of those targets includes.
set(D2VDB_PCH_OPENVDB <openvdb/openvdb.h> <Eigen/Core> <Eigen/Geometry>)

# d2vdb_precompile_headers(TARGET HEADERS...): precompiles HEADERS (<...> include names) for the
# translation units of TARGET, unless D2VDB_PRECOMPILED_HEADERS is OFF.
function(d2vdb_precompile_headers target)
  if(D2VDB_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
