# `cmake --install`: the public headers, the module libraries, the d2vdb command and a CMake package config so
# that a downstream project can `find_package(d2vdb)` and link `d2vdb::engine`.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

get_property(d2vdb_modules GLOBAL PROPERTY D2VDB_MODULES)
install(TARGETS ${d2vdb_modules} d2vdb_engine EXPORT d2vdbTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Public headers only: every module's detail/ folder is internal and stays out of the install.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine/d2vdb DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h" PATTERN "detail" EXCLUDE)
install(FILES ${PROJECT_BINARY_DIR}/engine/generated/d2vdb/core/Version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/d2vdb/core)

set(d2vdb_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/d2vdb)
install(EXPORT d2vdbTargets NAMESPACE d2vdb:: DESTINATION ${d2vdb_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/d2vdbConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/d2vdbConfig.cmake
                              INSTALL_DESTINATION ${d2vdb_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/d2vdbConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/d2vdbConfig.cmake ${PROJECT_BINARY_DIR}/d2vdbConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindCHOLMOD.cmake
        DESTINATION ${d2vdb_cmake_dir})
