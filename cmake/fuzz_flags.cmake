# MSH_FUZZ=ON: instrument everything built after this point for libFuzzer + ASan + UBSan (clang only); the
# fuzz targets themselves are in fuzz/CMakeLists.txt. See docs/fuzzing.md.
option(MSH_FUZZ "Build the libFuzzer targets in fuzz/ (clang; ASan + UBSan)" OFF)
if(MSH_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "MSH_FUZZ=ON needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=address,undefined)
endif()
