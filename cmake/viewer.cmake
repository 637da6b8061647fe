# The browser viewer (`microshadow view`, docs/viewer.md): cpp-httplib (header-only, Debian libcpp-httplib-dev)
# for src/view/, the source tree's path for the view command only (the library builds identically from any
# checkout), and install rules: the page and the GLSL files go to <prefix>/share/microshadow, where the
# installed binary looks for them.
find_path(MSH_HTTPLIB_INCLUDE_DIR httplib.h REQUIRED)
target_include_directories(microshadow PRIVATE ${MSH_HTTPLIB_INCLUDE_DIR})
set_source_files_properties(${CMAKE_SOURCE_DIR}/src/cli/cmd_view.cpp PROPERTIES
  COMPILE_DEFINITIONS MSH_VIEW_SOURCE_DIR="${CMAKE_SOURCE_DIR}")

include(GNUInstallDirs)
install(TARGETS microshadow_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/web/ DESTINATION ${CMAKE_INSTALL_DATADIR}/microshadow/web)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/shaders/glsl DESTINATION ${CMAKE_INSTALL_DATADIR}/microshadow/shaders)
