# The browser viewer (`microshadow view`, docs/viewer.md): cpp-httplib (Debian libcpp-httplib-dev)
# for src/view/, the source tree's path for the view command only (the library builds identically from any
# checkout), and the install rule of the page: <prefix>/share/microshadow/web, where the installed binary looks
# for it (the CLI and the GLSL files it also reads, <prefix>/share/microshadow/shaders/glsl, are installed by
# cmake/install.cmake).
# Debian builds it in split mode (the header declares, libcpp-httplib.so defines), with TLS, zlib and brotli:
# its pkg-config flags are needed for the same class layouts as the library's.
find_package(PkgConfig REQUIRED)
pkg_check_modules(MSH_HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
target_link_libraries(microshadow PRIVATE PkgConfig::MSH_HTTPLIB)
set_source_files_properties(${CMAKE_SOURCE_DIR}/src/cli/cmd_view.cpp PROPERTIES
  COMPILE_DEFINITIONS MSH_VIEW_SOURCE_DIR="${CMAKE_SOURCE_DIR}")

include(GNUInstallDirs)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/web/ DESTINATION ${CMAKE_INSTALL_DATADIR}/microshadow/web)
