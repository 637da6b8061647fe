// A GLTFLoader plugin for the glTF material extension MSH_materials_directional_occlusion (docs/gltf.md): the
// directional micro-occlusion channels as a linear code (K coefficient textures, lo/hi, mean, basis). Every mesh
// material whose glTF material has the extension gets addMicroShadowing with the directional-view method and
// the extension's code; materials without it are left alone (their occlusionTexture, the scalar V, is three's
// aoMap as usual, and addMicroShadowing's scalar methods can use it).
//
//   const loader = new GLTFLoader().register((parser) => new MicroShadowGLTFPlugin(parser));
//   const gltf = await loader.loadAsync('material.gltf');
//
// options: method (default 'directional-view+generic-vndf-alu': the term on the diffuse lobe, the generic ALU
// fit with V from the occlusion texture on the specular lobe), and any other addMicroShadowing option (debug,
// aoOnIndirect, samples). The handle is material.userData.microshadow.
import { addMicroShadowing } from './index.js';
import { directionalOcclusion, prepareCoefficientTexture } from './directional.js';

export const GLTF_DIRECTIONAL_EXTENSION = 'MSH_materials_directional_occlusion';
export const GLTF_DEFAULT_METHOD = 'directional-view+generic-vndf-alu';

export class MicroShadowGLTFPlugin {
  constructor(parser, options = {}) {
    this.parser = parser;
    this.name = GLTF_DIRECTIONAL_EXTENSION;
    this.options = options;
    this.codes = new Map();  // glTF material index -> Promise of the code
  }

  // The code of glTF material `index` (directionalOcclusion's object), its textures through the parser (PNG,
  // unflipped, no colour conversion, no premultiplication: GLTFLoader's ImageBitmapLoader settings).
  loadCode(index) {
    if (!this.codes.has(index)) this.codes.set(index, this._loadCode(index));
    return this.codes.get(index);
  }

  async _loadCode(index) {
    const def = this.parser.json.materials[index];
    const ext = def.extensions[GLTF_DIRECTIONAL_EXTENSION];
    const where = `glTF material ${index}${def.name ? ` '${def.name}'` : ''}: ${GLTF_DIRECTIONAL_EXTENSION}`;
    if (!ext || typeof ext !== 'object') throw new Error(`microshadow: ${where}: not an object`);
    if (ext.channels !== 21) throw new Error(`microshadow: ${where}: 'channels' must be 21, got ${JSON.stringify(ext.channels)}`);
    if (!Array.isArray(ext.textures) || ext.textures.some((t) => !t || !Number.isInteger(t.index)))
      throw new Error(`microshadow: ${where}: 'textures' must be a list of textureInfo objects ({ "index": N })`);
    if (Number.isInteger(ext.coefficients) && ext.textures.length !== Math.ceil(ext.coefficients / 4))
      throw new Error(`microshadow: ${where}: K = ${ext.coefficients} needs ${Math.ceil(ext.coefficients / 4)} textures, the extension lists ${ext.textures.length}`);
    for (const t of ext.textures)
      if ((t.texCoord || 0) !== 0) throw new Error(`microshadow: ${where}: texCoord ${t.texCoord}: the module reads UV channel 0 only`);
    const textures = await Promise.all(ext.textures.map(async (t) => {
      if (!this.parser.json.textures || !this.parser.json.textures[t.index]) throw new Error(`microshadow: ${where}: no texture ${t.index}`);
      const img = (this.parser.json.images || [])[this.parser.json.textures[t.index].source];
      const what = `texture ${t.index}${img && img.uri ? ` (${img.uri})` : ''}`;
      let tex;
      try { tex = await this.parser.getDependency('texture', t.index); } catch (e) { throw new Error(`microshadow: ${where}: ${what} did not load: ${e.message || e}`); }
      if (!tex) throw new Error(`microshadow: ${where}: ${what} did not load`);
      return prepareCoefficientTexture(tex.clone());
    }));
    return directionalOcclusion({ form: ext.form, K: ext.coefficients, lo: ext.lo, hi: ext.hi, mean: ext.mean, basis: ext.basis, textures }, where);
  }

  async afterRoot(result) {
    const materials = this.parser.json.materials || [];
    const jobs = [];
    const seen = new Set();
    for (const scene of result.scenes || [result.scene]) {
      scene.traverse((o) => {
        if (!o.isMesh) return;
        for (const m of [].concat(o.material)) {
          if (!m || seen.has(m)) continue;
          seen.add(m);
          const a = this.parser.associations.get(m);
          if (!a || a.materials === undefined) continue;
          const def = materials[a.materials];
          if (!def || !def.extensions || !def.extensions[GLTF_DIRECTIONAL_EXTENSION]) continue;
          jobs.push(this.loadCode(a.materials).then((directional) => {
            const { method = GLTF_DEFAULT_METHOD, ...rest } = this.options;
            m.userData.microshadow = addMicroShadowing(m, { ...rest, method, directional });
          }));
        }
      });
    }
    await Promise.all(jobs);
  }
}
