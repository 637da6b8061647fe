// Ground-truth micro-geometry as triangle meshes (private to src/render/): a height map displacing a plane or
// a cylinder, one vertex per texel centre, two triangles per texel cell with the diagonal of
// render/heightfield.h ((i, j)–(i+1, j+1)), facing outwards. Traced by Embree with front faces only.
#pragma once

#include <microshadow/render/scene.h>

namespace msh::render {

// InputError unless texels of world size tu × tv are square (to 1 %) and the material's depth is known.
void check_ground_truth_texels(float tu, float tv, const Material& m, const std::string& where);

// The plane's height field in world space: vertex (i, j) at c + T((i + ½)·texel − half.x) + B((j + ½)·texel −
// half.y) + N·(h − 1)·depth·texel for i ∈ [0, W·s], j ∈ [0, H·s] (heights wrap), W × H the map, s = uv_scale.
// InputError when the texels are not square.
Mesh displaced_plane_mesh(const Object& plane, const Material& m, const std::string& where);

// The cylinder of Object::cylinder (axis +z before the rotation about z, uv of make_cylinder: u = φ/2π, v = 0
// at the top): radius R + (h − 1)·depth·texel at vertex (i, j), i around (wrapping), j along the axis, texel
// = 2πR/(W·s) which must equal height/(H·s) to 1 % (InputError otherwise).
Mesh displaced_cylinder_mesh(const Object& cyl, const Material& m, const std::string& where);

}  // namespace msh::render
