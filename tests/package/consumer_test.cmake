# ctest (cmake/install.cmake): `cmake --install` into a fresh prefix outside the build tree, then
#  1. examples/consumer configured with find_package(microshadow CONFIG) against that prefix only, built,
#     run; its output is checked;
#  2. the installed CLI runs (--version) and reads the installed default table's sidecar;
#  3. one-file programs compiled with pkg-config (microshadow-core.pc, microshadow.pc) and run;
#  and the three.js module's files in share/microshadow/three/ when the build packed it (node and npm).
# -DBUILD_DIR=... -DSOURCE_DIR=... -DCXX=... -DGENERATOR=... [-DTHREE_TGZ=the packed module] [-DSANITIZE=ON: the installed library is
# ASan/UBSan-instrumented (MSH_SANITIZE), so every consumer is compiled and linked with the same runtime]
cmake_policy(VERSION 3.25)
string(RANDOM LENGTH 8 tag)
if(DEFINED ENV{TMPDIR})
  set(tmp $ENV{TMPDIR})
else()
  set(tmp /tmp)
endif()
set(root ${tmp}/msh_package_test_${tag})
set(prefix ${root}/prefix)
file(REMOVE_RECURSE ${root})
file(MAKE_DIRECTORY ${root})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    file(REMOVE_RECURSE ${root})
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()
function(expect text regex)
  if(NOT text MATCHES "${regex}")
    file(REMOVE_RECURSE ${root})
    message(FATAL_ERROR "expected /${regex}/ in:\n${text}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f include/microshadow/microshadow.h share/microshadow/shaders/glsl/micro_shadowing.glsl
          share/microshadow/shaders/hlsl/micro_shadowing.hlsl share/microshadow/shaders/glsl/msh_prelude.glsl
          share/microshadow/shaders/hlsl/msh_prelude.hlsl share/microshadow/shaders/portable/micro_shadowing.h
          share/microshadow/tables/micro_shadowing.ktx2
          share/microshadow/tables/micro_shadowing.ktx2.json bin/microshadow)
  if(NOT EXISTS ${prefix}/${f})
    file(REMOVE_RECURSE ${root})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# The three.js module (cmake/three_package.cmake), when the build packed it (node and npm present): the npm
# tarball as built, the unpacked module with its generated files, the import-map example page.
if(THREE_TGZ)
  set(tgzs ${THREE_TGZ})
  get_filename_component(tgz ${tgzs} NAME)
  set(three ${prefix}/share/microshadow/three)
  foreach(f ${tgz} importmap-example.html microshadow-three/package.json microshadow-three/src/index.js
            microshadow-three/src/luts.js microshadow-three/src/generated/methods.js
            microshadow-three/src/generated/glsl.js)
    if(NOT EXISTS ${three}/${f})
      file(REMOVE_RECURSE ${root})
      message(FATAL_ERROR "not installed: share/microshadow/three/${f}")
    endif()
  endforeach()
  file(SHA256 ${tgzs} built)
  file(SHA256 ${three}/${tgz} installed)
  if(NOT built STREQUAL installed)
    file(REMOVE_RECURSE ${root})
    message(FATAL_ERROR "share/microshadow/three/${tgz} differs from the built ${tgzs}")
  endif()
  message(STATUS "the three.js module is installed: share/microshadow/three/${tgz}, microshadow-three/, importmap-example.html")
else()
  message(STATUS "the three.js module was not packed (no node/npm at configure time): not checked")
endif()
# The installed shaders compile through the compiler's own #include (the prelude and the portable/ body found
# relative to the entry point), in both languages.
# glslang is a build dependency of the shader tests (scripts/install-deps.sh): its absence is an error here too.
find_program(GLSLANG glslangValidator REQUIRED)
set(sh ${prefix}/share/microshadow/shaders)
file(WRITE ${root}/use.comp "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
     "#include \"micro_shadowing.glsl\"\nlayout(local_size_x = 1) in;\n"
     "layout(std430, binding = 0) buffer B { float o[]; };\nvoid main() { o[0] = msh_ms_cone_cos(o[1]); }\n")
file(WRITE ${root}/use.hlsl "#include \"micro_shadowing.hlsl\"\nRWStructuredBuffer<float> o;\n"
     "[numthreads(1, 1, 1)] void main() { o[0] = msh_ms_cone_cos(o[1]); }\n")
run(${GLSLANG} -V -I${sh}/glsl ${root}/use.comp -o ${root}/use_glsl.spv)
run(${GLSLANG} -V -I${sh}/hlsl -D -S comp -e main ${root}/use.hlsl -o ${root}/use_hlsl.spv)
message(STATUS "the installed shaders compile through #include in GLSL and HLSL")
file(GLOB_RECURSE pcs ${prefix}/*/microshadow.pc)
file(GLOB_RECURSE libs ${prefix}/*/libmicroshadow.a)
if(NOT pcs OR NOT libs)
  file(REMOVE_RECURSE ${root})
  message(FATAL_ERROR "libmicroshadow.a or microshadow.pc not installed")
endif()
get_filename_component(pcdir ${pcs} DIRECTORY)

# 1. find_package against the prefix only (CMAKE_FIND_USE_PACKAGE_REGISTRY off: never the build tree).
set(launcher)
set(san_flags)
set(san_cmake)
if(SANITIZE)
  set(san_flags -fsanitize=address,undefined)
  set(san_cmake -DCMAKE_CXX_FLAGS=-fsanitize=address,undefined -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined)
endif()
find_program(ccache ccache)
if(ccache)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${ccache})
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${root}/consumer -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DCMAKE_BUILD_TYPE=Release ${launcher} ${san_cmake})
run(${CMAKE_COMMAND} --build ${root}/consumer)
run(${root}/consumer/consumer)
# Independent values: Chan 2018 at V = 0.6, N·L = 0.4 is (0.4 / sqrt(0.4))² = 0.4; Brinck–Maximov 2016 is
# 0.4 + 2·0.36 − 1 = 0.12; the table agrees with the exact term (checked by the program, "consumer: ok").
expect("${out}" "chan_2018 0\\.400000\n")
expect("${out}" "brinck_maximov_2016 0\\.120000\n")
expect("${out}" "consumer: ok")
message(STATUS "consumer:\n${out}")

# 2. The installed CLI, and the installed table's sidecar through it.
run(${prefix}/bin/microshadow --version)
expect("${out}" "microshadow [0-9]")
run(${prefix}/bin/microshadow eval micro-shadowing --method lut3d --visibility 0.6 --ndotl 0.4 --ndotv 0.8
    --roughness 0.5 --lut ${prefix}/share/microshadow/tables/micro_shadowing.ktx2)
message(STATUS "installed CLI with the installed table: ${out}")

# 3. pkg-config (relocatable .pc files: the prefix comes from their own location).
find_program(pkgconfig pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${pcdir})
run(${pkgconfig} --cflags microshadow-core)
separate_arguments(core_flags UNIX_COMMAND "${out}")
run(${CXX} -std=c++20 -Wall -Wextra -Werror ${san_flags} ${core_flags} ${SOURCE_DIR}/tests/package/pkgconfig_core.cpp
    -o ${root}/pkgconfig_core)
run(${root}/pkgconfig_core)
expect("${out}" "chan_2018 1\\.000000")
run(${pkgconfig} --cflags --libs microshadow)
separate_arguments(lib_flags UNIX_COMMAND "${out}")
run(${CXX} -std=c++20 ${san_flags} ${SOURCE_DIR}/tests/package/pkgconfig_lib.cpp ${lib_flags} -o ${root}/pkgconfig_lib)
run(${root}/pkgconfig_lib ${root}/roundtrip.npy)
expect("${out}" "round trip ok")

file(REMOVE_RECURSE ${root})
message(STATUS "package test: ok")
