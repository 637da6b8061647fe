// A shader library file with its `#include "..."` lines replaced by the files they name, recursively
// (paths relative to the including file, as glslang, DXC and the C preprocessor resolve them). The shaders
// are written once in a portable dialect (shaders/portable/*.h) over a per-language prelude, and the entry
// points shaders/glsl/*.glsl and shaders/hlsl/*.hlsl include them (docs/shaders.md). WebGL2 has no #include:
// the viewer's server sends the expanded text (docs/viewer.md); the shader tests compile the same text.
#pragma once

#include <filesystem>
#include <string>

namespace msh::view {

// The text of `file` with its includes expanded; every file's include guards stay in the text, so a file
// reached twice costs only its guarded text. InputError (one line) for an unreadable file, an include
// nested deeper than 16 (a cycle) or a malformed #include line.
std::string expand_shader_includes(const std::filesystem::path& file);

}  // namespace msh::view
