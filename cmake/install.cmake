# `cmake --install build --prefix P`: headers, libmicroshadow, the CLI, the shaders, the default tables, a
# CMake package (find_package(microshadow CONFIG): microshadow::core, microshadow::microshadow) and pkg-config
# files (microshadow-core.pc, microshadow.pc), the three.js module (npm tarball). Layout and usage: docs/packaging.md.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(MSH_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/microshadow)
set(MSH_INSTALL_SHADERDIR ${CMAKE_INSTALL_DATADIR}/microshadow/shaders)
set(MSH_INSTALL_TABLEDIR ${CMAKE_INSTALL_DATADIR}/microshadow/tables)

# --- The header-only core --------------------------------------------------------------------------------
# The rule is by path (docs/architecture.md): the top level of math/, microfacet/, occlusion/, bsdf/, lut/,
# reference/, filter/ and shader/ (with the shaders' shaders/portable/*.h it compiles as C++); runtime/
# subfolders are compiled into the library. tests/package/check_core_headers.cmake proves that each of these
# headers, preprocessed, pulls in only the standard library, other core headers and shaders/portable, and that
# the umbrella header includes exactly this set.
set(MSH_CORE_HEADERS)
foreach(area math microfacet occlusion bsdf lut reference filter shader)
  file(GLOB hs RELATIVE ${CMAKE_SOURCE_DIR}/include CONFIGURE_DEPENDS
       ${CMAKE_SOURCE_DIR}/include/microshadow/${area}/*.h)
  list(APPEND MSH_CORE_HEADERS ${hs})
endforeach()
list(SORT MSH_CORE_HEADERS)

# <prefix>/share/microshadow holds shaders/portable, which <microshadow/shader/portable.h> includes.
target_include_directories(microshadow_core INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
                                                      $<INSTALL_INTERFACE:${CMAKE_INSTALL_DATADIR}/microshadow>)
target_compile_features(microshadow_core INTERFACE cxx_std_20)
set_target_properties(microshadow_core PROPERTIES EXPORT_NAME core)
set_target_properties(microshadow_engine PROPERTIES EXPORT_NAME engine)

# --- The default micro-shadowing tables, baked at build time ---------------------------------------------
# The library bakes its default table on first use (lut::default_micro_shadowing_lut, in float); engines
# want a file. These are what `bake micro-shadowing` writes by default (KTX2, half): the 3D cone table, the
# 2D (N·V = 1) slice and the azimuth-aware table, each with its JSON sidecar. Re-baked only when the baker's
# sources change (a few CPU-seconds).
set(MSH_TABLE_BUILD_DIR ${CMAKE_BINARY_DIR}/share/microshadow/tables)
set(MSH_TABLES)
set(MSH_TABLE_COMMANDS)
foreach(spec "micro_shadowing" "micro_shadowing_2d|--2d" "micro_shadowing_azimuth|--azimuth")
  string(REPLACE "|" ";" spec "${spec}")
  list(POP_FRONT spec name)
  set(flags ${spec})
  set(out ${MSH_TABLE_BUILD_DIR}/${name}.ktx2)
  list(APPEND MSH_TABLES ${out} ${out}.json)
  # The CLI by path, not by target name: a target name would re-bake on every relink of the CLI.
  list(APPEND MSH_TABLE_COMMANDS COMMAND ${CMAKE_BINARY_DIR}/bin/microshadow bake micro-shadowing ${flags}
       --out ${out} --threads 2 --quiet)
endforeach()
file(GLOB MSH_TABLE_DEPENDS CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/lut/*.cpp
     ${CMAKE_SOURCE_DIR}/include/microshadow/lut/*.h ${CMAKE_SOURCE_DIR}/include/microshadow/lut/runtime/*.h
     ${CMAKE_SOURCE_DIR}/include/microshadow/reference/*.h
     ${CMAKE_SOURCE_DIR}/include/microshadow/occlusion/*.h ${CMAKE_SOURCE_DIR}/src/io/ktx2.cpp)
add_custom_command(OUTPUT ${MSH_TABLES}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${MSH_TABLE_BUILD_DIR} ${MSH_TABLE_COMMANDS}
  DEPENDS ${MSH_TABLE_DEPENDS} COMMENT "Baking the default micro-shadowing tables (share/microshadow/tables)"
  VERBATIM)
add_custom_target(microshadow_tables ALL DEPENDS ${MSH_TABLES})
add_dependencies(microshadow_tables microshadow_cli)

# --- Install rules ---------------------------------------------------------------------------------------
install(TARGETS microshadow_core microshadow_engine EXPORT microshadowCoreTargets)
install(TARGETS microshadow EXPORT microshadowTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS microshadow_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/include/microshadow DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/shaders/glsl ${CMAKE_SOURCE_DIR}/shaders/hlsl ${CMAKE_SOURCE_DIR}/shaders/portable
        DESTINATION ${MSH_INSTALL_SHADERDIR})
install(FILES ${MSH_TABLES} DESTINATION ${MSH_INSTALL_TABLEDIR})

install(EXPORT microshadowCoreTargets NAMESPACE microshadow:: DESTINATION ${MSH_INSTALL_CMAKEDIR})
install(EXPORT microshadowTargets NAMESPACE microshadow:: DESTINATION ${MSH_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/microshadowConfig.cmake.in
  ${CMAKE_BINARY_DIR}/cmake/microshadowConfig.cmake INSTALL_DESTINATION ${MSH_INSTALL_CMAKEDIR}
  PATH_VARS MSH_INSTALL_SHADERDIR MSH_INSTALL_TABLEDIR)
# 0.x: minor versions may break the API.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/microshadowConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/cmake/microshadowConfig.cmake
        ${CMAKE_BINARY_DIR}/cmake/microshadowConfigVersion.cmake DESTINATION ${MSH_INSTALL_CMAKEDIR})

# The three.js module: the npm tarball, the unpacked module and the import-map example (share/microshadow/three).
include(${CMAKE_SOURCE_DIR}/cmake/three_package.cmake)

# pkg-config: relocatable (prefix from ${pcfiledir}), since `cmake --install --prefix` picks the prefix late.
# libmicroshadow is static, so microshadow.pc lists its dependencies in Requires/Libs (not *.private).
file(RELATIVE_PATH MSH_PC_TO_PREFIX ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig
     ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" MSH_PC_TO_PREFIX "${MSH_PC_TO_PREFIX}")
foreach(pc microshadow-core microshadow)
  configure_file(${CMAKE_SOURCE_DIR}/cmake/${pc}.pc.in ${CMAKE_BINARY_DIR}/cmake/${pc}.pc.gen @ONLY)
  file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/cmake/${pc}.pc INPUT ${CMAKE_BINARY_DIR}/cmake/${pc}.pc.gen)
  install(FILES ${CMAKE_BINARY_DIR}/cmake/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()

# --- Tests of the package --------------------------------------------------------------------------------
if(MSH_BUILD_TESTS)
  # The umbrella header alone, warnings as errors, in a program that links nothing but microshadow::core.
  add_executable(test_core_umbrella ${CMAKE_SOURCE_DIR}/tests/package/core_umbrella.cpp)
  target_link_libraries(test_core_umbrella PRIVATE microshadow_core)
  target_compile_options(test_core_umbrella PRIVATE -Wall -Wextra -Werror)
  add_test(NAME test_core_umbrella COMMAND test_core_umbrella)
  # The engine surface likewise, linking nothing but microshadow::engine.
  add_executable(test_engine_umbrella ${CMAKE_SOURCE_DIR}/tests/package/engine_umbrella.cpp)
  target_link_libraries(test_engine_umbrella PRIVATE microshadow_engine)
  target_compile_options(test_engine_umbrella PRIVATE -Wall -Wextra -Werror)
  add_test(NAME test_engine_umbrella COMMAND test_engine_umbrella)
  # Every core header: standard library and core headers only; the umbrella includes exactly the core set;
  # and the umbrella compiles warning-free with the other compiler (clang when building with GCC), as an
  # engine's toolchain may differ from ours.
  find_program(MSH_OTHER_CXX NAMES clang++ clang++-14 g++)
  add_test(NAME test_core_headers COMMAND ${CMAKE_COMMAND} -DCXX=${CMAKE_CXX_COMPILER} -DOTHER_CXX=${MSH_OTHER_CXX}
           -DINCLUDE_DIR=${CMAKE_SOURCE_DIR}/include -DSHADER_ROOT=${CMAKE_SOURCE_DIR} "-DCORE_HEADERS=${MSH_CORE_HEADERS}"
           -P ${CMAKE_SOURCE_DIR}/tests/package/check_core_headers.cmake)
  # Install into a fresh prefix, build examples/consumer against it with find_package, run it; pkg-config
  # builds of one-file programs.
  add_test(NAME test_package_consumer COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR}
           -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DCXX=${CMAKE_CXX_COMPILER} -DGENERATOR=${CMAKE_GENERATOR}
           -DSANITIZE=${MSH_SANITIZE} -DTHREE_TGZ=${MSH_THREE_PACKAGED_TGZ}
           -P ${CMAKE_SOURCE_DIR}/tests/package/consumer_test.cmake)
  set_tests_properties(test_core_headers test_package_consumer PROPERTIES TIMEOUT 600)
endif()
