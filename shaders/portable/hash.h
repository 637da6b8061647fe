// microshadow: shaders/portable/hash.h, written once for GLSL, HLSL and C++ in the portable dialect
// (docs/shaders.md). The integer hashes that derive the seeds of the scrambled Sobol sequence: the shaders'
// estimator (shaders/portable/micro_shadowing.h, included after this by the micro_shadowing entry points) and
// the C++ library's (msh::hash_u32 and msh::hash_combine in include/microshadow/math/sampling.h compile this
// file), so that a seed gives the same stream on the CPU and the GPU. Exact (integer arithmetic).
#ifndef MSH_HASH_PORTABLE_H
#define MSH_HASH_PORTABLE_H

// 32-bit mixing hash (C. Wellons 2018, "Prospecting for Hash Functions": lowbias32, a variant of MurmurHash3's
// finalizer).
MSH_FN uint msh_hash_u32(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
MSH_FN uint msh_hash_combine(uint seed, uint v) { return seed ^ (msh_hash_u32(v) + 0x9e3779b9u + (seed << 6) + (seed >> 2)); }

#endif  // MSH_HASH_PORTABLE_H
