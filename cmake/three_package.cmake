# The three.js module as an npm package (docs/three.md, "Install"): a copy of integrations/three (package.json
# and src/, not its node_modules) with src/generated/ written by the freshly built CLI (`view --three-module`),
# packed with `npm pack` into build/three/microshadow-three-<version>.tgz (target microshadow_three_package,
# part of `all`). `cmake --install` puts the tarball, the unpacked module and the import-map example page in
# <prefix>/share/microshadow/three/. Without node and npm (find_program) or with -DMSH_THREE_PACKAGE=OFF neither
# is built nor installed (a STATUS line says so); the package's browser test (tests/test_three_package.cpp) then
# fails, or skips with MSH_ALLOW_NO_BROWSER=1, as the other browser tests do without chromium.
set(MSH_THREE_SOURCE ${CMAKE_SOURCE_DIR}/integrations/three)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${MSH_THREE_SOURCE}/package.json)
file(READ ${MSH_THREE_SOURCE}/package.json MSH_THREE_PACKAGE_JSON)
string(JSON MSH_THREE_NAME GET "${MSH_THREE_PACKAGE_JSON}" name)
string(JSON MSH_THREE_VERSION GET "${MSH_THREE_PACKAGE_JSON}" version)
set(MSH_THREE_PACKAGE_DIR ${CMAKE_BINARY_DIR}/three)
set(MSH_THREE_TGZ ${MSH_THREE_PACKAGE_DIR}/${MSH_THREE_NAME}-${MSH_THREE_VERSION}.tgz)
set(MSH_INSTALL_THREEDIR ${CMAKE_INSTALL_DATADIR}/microshadow/three)

set(MSH_THREE_PACKAGED_TGZ "")  # the tarball when it is built (the install test checks it)
option(MSH_THREE_PACKAGE "Pack the three.js module with npm (needs node and npm)" ON)
find_program(MSH_NODE node)
find_program(MSH_NPM npm)
if(NOT MSH_THREE_PACKAGE)
  message(STATUS "three.js package: MSH_THREE_PACKAGE=OFF: "
                 "three/${MSH_THREE_NAME}-${MSH_THREE_VERSION}.tgz is not built and not installed")
elseif(MSH_NODE AND MSH_NPM)
  file(GLOB MSH_THREE_DEPENDS CONFIGURE_DEPENDS ${MSH_THREE_SOURCE}/src/*.js ${CMAKE_SOURCE_DIR}/shaders/glsl/*.glsl
       ${CMAKE_SOURCE_DIR}/shaders/portable/*.h)
  add_custom_command(OUTPUT ${MSH_THREE_TGZ}
    COMMAND ${CMAKE_COMMAND} -DSOURCE=${MSH_THREE_SOURCE} -DSTAGE=${MSH_THREE_PACKAGE_DIR}/${MSH_THREE_NAME}
            -DTGZ=${MSH_THREE_TGZ} -DCLI=$<TARGET_FILE:microshadow_cli> -DNPM=${MSH_NPM}
            -DNPM_CACHE=${MSH_THREE_PACKAGE_DIR}/npm-cache -P ${CMAKE_SOURCE_DIR}/cmake/three_pack.cmake
    DEPENDS microshadow_cli ${MSH_THREE_SOURCE}/package.json ${MSH_THREE_DEPENDS} ${CMAKE_SOURCE_DIR}/cmake/three_pack.cmake
    COMMENT "Packing the three.js module (npm pack): three/${MSH_THREE_NAME}-${MSH_THREE_VERSION}.tgz" VERBATIM)
  add_custom_target(microshadow_three_package ALL DEPENDS ${MSH_THREE_TGZ})
  set(MSH_THREE_PACKAGED_TGZ ${MSH_THREE_TGZ})
  install(FILES ${MSH_THREE_TGZ} DESTINATION ${MSH_INSTALL_THREEDIR})
  install(FILES ${CMAKE_SOURCE_DIR}/examples/three-importmap/index.html DESTINATION ${MSH_INSTALL_THREEDIR}
          RENAME importmap-example.html)
  install(DIRECTORY ${MSH_THREE_PACKAGE_DIR}/${MSH_THREE_NAME}/ DESTINATION ${MSH_INSTALL_THREEDIR}/${MSH_THREE_NAME})
else()
  message(STATUS "three.js package: no node/npm on PATH (Debian packages nodejs, npm): "
                 "three/${MSH_THREE_NAME}-${MSH_THREE_VERSION}.tgz is not built and not installed")
endif()
