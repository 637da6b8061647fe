// microshadow's header-only core in one include: microfacet distributions, micro-shadowing terms, bump
// terminator, BRDF lobes, normal-map filtering, the LUT sampler and the exact references. C++20 standard
// library only: no I/O, no threads, nothing to link (CMake: microshadow::core; pkg-config: microshadow-core).
// The file readers, bakers and renderer are in the library (microshadow::microshadow), see docs/packaging.md.
#pragma once

#include <microshadow/bsdf/cloth.h>
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/layered.h>
#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/qmc.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/bsdf/tables_data.h>
#include <microshadow/bsdf/thin_film.h>
#include <microshadow/filter/blend.h>
#include <microshadow/filter/lean.h>
#include <microshadow/filter/toksvig.h>
#include <microshadow/filter/variance_mapping.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/math/color.h>
#include <microshadow/math/grid.h>
#include <microshadow/math/quadrature.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/albedo.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/bounded_vndf.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>
#include <microshadow/microfacet/masking.h>
#include <microshadow/microfacet/roughness.h>
#include <microshadow/microfacet/smith.h>
#include <microshadow/microfacet/vcavity.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_anisotropic.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_early_out.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/micro_shadowing_ring.h>
#include <microshadow/reference/micro_shadowing_vcavity.h>
#include <microshadow/shader/cpp_prelude.h>
#include <microshadow/shader/portable.h>
