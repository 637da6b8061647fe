// The viewer's bump-terminator terms (shaders/glsl/bump_terminator.glsl): { id, label, glsl, requires? } with
// glsl a float expression over vec3 ng (geometric normal), ns (normal-mapped), wl (towards the light), world
// space, and bool u_bump_hemi (hemisphere test). The micro-shadowing terms are not listed here: the server
// generates methods.js from the runtime registry (docs/viewer.md).
export const BUMP_TERMINATOR_METHODS = [
  { id: 'none', label: 'none', glsl: '1.0' },
  { id: 'conty-2019', label: 'Conty Estevez et al. 2019', glsl: 'msh_bump_conty2019(ng, ns, wl, u_bump_hemi)', requires: 'msh_bump_conty2019' },
  { id: 'chiang-2019', label: 'Chiang et al. 2019', glsl: 'msh_bump_chiang2019(ng, ns, wl, u_bump_hemi)', requires: 'msh_bump_chiang2019' },
];
