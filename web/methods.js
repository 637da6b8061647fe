// The viewer's shading terms, one line each: adding a GLSL term to the viewer = adding one entry here.
//
// Micro-shadowing methods: { id, label, glsl, requires?, lut? }
//   id       stable name (the `microshadow eval micro-shadowing --method` name where one exists; the browser
//            test maps it to the C++ code it compares against: tests/test_viewer_browser.cpp)
//   glsl     a GLSL ES 3.00 expression (float) over these names, all in the shading frame (n = +z):
//              float vis, nl, nv, rough, alpha (= rough^2), cos_phi (relative azimuth of v and l);
//              vec3 v, l (unit, towards the eye / the light); int u_samples (the "N samples" control);
//              sampler3D u_lut3d, u_lut2d, u_lut_az; int u_lut3d_slabs, u_lut2d_slabs, u_lut_az_slabs,
//              u_lut_az_harmonics (the tables of data/manifest.json, uploaded as 3D textures)
//   requires a GLSL function that must exist in the shaders/glsl/*.glsl files the server lists (a method whose
//            file is absent is left out of the menus instead of breaking the shader)
//   lut      the table the method samples (manifest "luts" key); left out when the server has none
//   cpp      the C++ evaluation the browser test compares with: a method of the runtime registry
//            (include/microshadow/occlusion/runtime/micro_shadowing_methods.h) by name; phi: at the pixel's
//            relative azimuth (else the azimuth mean); samples: with the page's N; frame: at the pixel's own
//            v and l (the Sobol estimator is not rotation-invariant); two_stage: the per-pixel + per-light fit
export const MICRO_SHADOWING_METHODS = [
  { id: 'none', label: 'none (term = 1)', glsl: '1.0', cpp: null },
  { id: 'ao', label: 'AO on direct light (term = V)', glsl: 'vis', cpp: { method: 'ao' } },
  { id: 'reference', label: 'reference step (Zurita 2026)', glsl: 'msh_ms_reference_step(vis, nl)', requires: 'msh_ms_reference_step', cpp: { method: 'reference' } },
  { id: 'brinck-maximov-2016', label: 'Brinck & Maximov 2016', glsl: 'msh_ms_brinck_maximov2016(vis, nl)', requires: 'msh_ms_brinck_maximov2016', cpp: { method: 'brinck-maximov-2016' } },
  { id: 'chan-2018', label: 'Chan 2018 (Filament)', glsl: 'msh_ms_chan2018(vis, nl)', requires: 'msh_ms_chan2018', cpp: { method: 'chan-2018' } },
  { id: 'part1-analytic', label: 'Part 1 analytic (Zurita 2026)', glsl: 'msh_ms_part1_analytic(vis, nl)', requires: 'msh_ms_part1_analytic', cpp: { method: 'part1-analytic' } },
  { id: 'generic-vndf', label: 'generic VNDF, N samples (Zurita 2026)', glsl: 'msh_ms_generic_vndf_estimate(vis, vec2(alpha), v, l, u_samples, true, 1u)', requires: 'msh_ms_generic_vndf_estimate', cpp: { method: 'generic-vndf', samples: true, frame: true } },
  { id: 'generic-vndf-alu', label: 'generic VNDF, ALU fit (one call)', glsl: 'msh_ms_generic_vndf_alu(vis, nl, nv, rough)', requires: 'msh_ms_generic_vndf_alu', cpp: { method: 'generic-vndf-alu' } },
  { id: 'generic-vndf-alu-two-stage', label: 'generic VNDF, ALU fit (pixel + light)', glsl: 'msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(vis, nv, rough), nl)', requires: 'msh_ms_generic_vndf_alu_light', cpp: { method: 'generic-vndf-alu', two_stage: true } },
  { id: 'lut3d', label: '3D LUT (cone layout)', glsl: 'msh_ms_lut_sample_cone(u_lut3d, u_lut3d_slabs, vis, nl, nv, rough)', requires: 'msh_ms_lut_sample_cone', lut: 'lut3d', cpp: { method: 'lut3d' } },
  { id: 'lut2d', label: '2D LUT (N·V = 1 slice)', glsl: 'msh_ms_lut_sample_cone(u_lut2d, u_lut2d_slabs, vis, nl, 1.0, rough)', requires: 'msh_ms_lut_sample_cone', lut: 'lut2d', cpp: { method: 'lut2d' } },
  { id: 'lut-azimuth', label: 'azimuth-aware LUT (3 harmonics)', glsl: 'msh_ms_lut_sample_cone_azimuth(u_lut_az, u_lut_az_slabs, u_lut_az_harmonics, vis, nl, nv, rough, cos_phi)', requires: 'msh_ms_lut_sample_cone_azimuth', lut: 'lut_azimuth', cpp: { method: 'lut3d', phi: true } },
];

// Bump-terminator terms (shaders/glsl/bump_terminator.glsl): { id, label, glsl } over vec3 ng (geometric
// normal), ns (normal-mapped), wl (towards the light), world space; bool u_bump_hemi (hemisphere test).
export const BUMP_TERMINATOR_METHODS = [
  { id: 'none', label: 'none', glsl: '1.0' },
  { id: 'conty-2019', label: 'Conty Estevez et al. 2019', glsl: 'msh_bump_conty2019(ng, ns, wl, u_bump_hemi)', requires: 'msh_bump_conty2019' },
  { id: 'chiang-2019', label: 'Chiang et al. 2019', glsl: 'msh_bump_chiang2019(ng, ns, wl, u_bump_hemi)', requires: 'msh_bump_chiang2019' },
];
