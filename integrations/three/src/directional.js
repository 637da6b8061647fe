// Directional micro-occlusion channels for three.js (docs/three.md, "directional-view"; the data:
// docs/directional-occlusion.md, "The stored channels"). The loader is generic over a linear code: K coefficient
// channels a_k = lo_k + (hi_k − lo_k) · unorm_k, stored four per RGBA8 texture (ceil(K/4) textures; channel
// 4t + c in channel c of texture t), and the 21 channels c_i = mean_i + Σ_k basis[i][k] · a_k that
// msh_dir_view_term reads. gen-material's 21-channel form ("directional" in mips/mips.json) is K = 21,
// basis = identity, mean = 0; a compact form ("directional_compact": K coefficients, a basis and a mean) plugs
// in unchanged. The same object comes from the glTF extension MSH_materials_directional_occlusion
// (docs/gltf.md, gltf.js).
import { LinearFilter, LinearMipmapLinearFilter, NoColorSpace, RedFormat, RepeatWrapping, RGBAFormat, RGFormat, Vector4 } from 'three';

export const DIRECTIONAL_CHANNELS = 21;   // 9 transport + 12 view-slope channels (occlusion/directional.h)
export const MAX_DIRECTIONAL_TEXTURES = 6; // K ≤ 24

const fail = (where, msg) => { throw new Error(`microshadow: ${where}: ${msg}`); };
const isNum = (x) => typeof x === 'number' && Number.isFinite(x);

function numbers(where, name, a, n) {
  if (!Array.isArray(a) || a.length !== n || !a.every(isNum))
    fail(where, `'${name}' must be an array of ${n} finite numbers${Array.isArray(a) ? ` (got ${a.length} entries)` : ''}`);
  return a;
}

// Checks a linear code and packs it for the shader. code: { K, lo[K], hi[K], mean[21] (default 0),
// basis[21][K] (default identity, K = 21 only), textures[ceil(K/4)] (THREE.Texture, UNORM data), form }.
// where: what to name in errors (a URL or the glTF material). Throws one line naming the problem.
export function directionalOcclusion(code, where = 'directional occlusion') {
  if (!code || typeof code !== 'object') fail(where, 'no directional occlusion data');
  const K = code.K;
  if (!Number.isInteger(K) || K < 1 || K > 4 * MAX_DIRECTIONAL_TEXTURES)
    fail(where, `K (the number of coefficient channels) must be an integer in [1, ${4 * MAX_DIRECTIONAL_TEXTURES}], got ${JSON.stringify(K)}`);
  const NT = Math.ceil(K / 4);
  const lo = numbers(where, 'lo', code.lo, K), hi = numbers(where, 'hi', code.hi, K);
  const mean = code.mean === undefined ? new Array(DIRECTIONAL_CHANNELS).fill(0) : numbers(where, 'mean', code.mean, DIRECTIONAL_CHANNELS);
  let basis = code.basis;
  if (basis === undefined) {
    if (K !== DIRECTIONAL_CHANNELS) fail(where, `no basis: only K = ${DIRECTIONAL_CHANNELS} (the channels themselves) may leave it out, K = ${K}`);
    basis = Array.from({ length: DIRECTIONAL_CHANNELS }, (_, i) => Array.from({ length: K }, (_, k) => (i === k ? 1 : 0)));
  }
  if (!Array.isArray(basis) || basis.length !== DIRECTIONAL_CHANNELS)
    fail(where, `'basis' must have ${DIRECTIONAL_CHANNELS} rows (one per channel), got ${Array.isArray(basis) ? basis.length : typeof basis}`);
  basis.forEach((row, i) => numbers(where, `basis[${i}]`, row, K));
  const textures = code.textures;
  if (!Array.isArray(textures) || textures.length !== NT)
    fail(where, `K = ${K} needs ${NT} coefficient textures (4 channels each), got ${Array.isArray(textures) ? textures.length : 'none'}`);
  textures.forEach((t, i) => {
    if (!t || !t.isTexture) fail(where, `coefficient texture ${i} is missing`);
    const have = { [RedFormat]: 1, [RGFormat]: 2, [RGBAFormat]: 4 }[t.format];
    const need = Math.min(4, K - 4 * i);
    if (have !== undefined && have < need) fail(where, `coefficient texture ${i} has ${have} channels, K = ${K} needs ${need} in it`);
  });
  const identity = K === DIRECTIONAL_CHANNELS && mean.every((m) => m === 0) &&
    basis.every((row, i) => row.every((b, k) => b === (i === k ? 1 : 0)));
  const v4 = (a, n) => Array.from({ length: n }, (_, j) => new Vector4(a[4 * j] ?? 0, a[4 * j + 1] ?? 0, a[4 * j + 2] ?? 0, a[4 * j + 3] ?? 0));
  // basis rows padded to 4·NT: basis4[i·NT + t] = (basis[i][4t .. 4t+3]).
  const basis4 = [];
  for (const row of basis) basis4.push(...v4(row, NT));
  return { form: code.form || (identity ? 'channels21' : 'linear'), K, textures: NT, maps: textures, lo, hi, mean, basis, identity,
    uniforms: { lo: v4(lo, NT), hi: v4(hi, NT), mean: v4(mean, 6), basis: basis4 } };
}

// The coefficient textures as the shader samples them: linear data (no colour conversion), trilinear over the
// file's own mip chain (box means: the channels are linear, docs/directional-occlusion.md), repeat.
export function prepareCoefficientTexture(t) {
  t.colorSpace = NoColorSpace;
  t.wrapS = t.wrapT = RepeatWrapping;
  t.magFilter = LinearFilter;
  t.unpackAlignment = 1;  // R8 levels and levels narrower than 4 texels
  const mips = Array.isArray(t.mipmaps) && t.mipmaps.length > 1;
  t.minFilter = mips || t.generateMipmaps ? LinearMipmapLinearFilter : LinearFilter;
  t.needsUpdate = true;
  return t;
}

async function fetchJson(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`microshadow: could not load ${url}: HTTP ${r.status}`);
  const text = await r.text();
  try { return JSON.parse(text); } catch (e) { throw new Error(`microshadow: ${url} is not valid JSON: ${e.message}`); }
}

// A gen-material texture set's directional channels from its mips/mips.json (URL): "directional_compact" when
// present, else the 21-channel "directional" entry; the KTX2 files (RGBA8/R8 UNORM with their mip chains)
// through three's KTX2Loader (uncompressed formats, no transcoder; it needs the renderer). Returns the object
// addMicroShadowing's `directional` option takes. options.prefer: 'directional' to skip the compact form.
export async function loadDirectionalOcclusion(url, options = {}) {
  const renderer = options.renderer;
  if (!renderer) throw new Error(`microshadow: ${url}: the channel textures load through three's KTX2Loader, which needs the renderer: loadDirectionalOcclusion(url, { renderer })`);
  const j = await fetchJson(url);
  const base = url.replace(/[^/]*$/, '');
  let code, files;
  if (j.directional_compact !== undefined && options.prefer !== 'directional') {
    const c = j.directional_compact;
    if (!c || typeof c !== 'object') fail(url, "'directional_compact' is not an object");
    if (c.channels !== undefined && c.channels !== DIRECTIONAL_CHANNELS)
      fail(url, `'directional_compact' decodes to ${c.channels} channels, the shader reads ${DIRECTIONAL_CHANNELS}`);
    if (!Array.isArray(c.textures) || !c.textures.every((s) => typeof s === 'string')) fail(url, "'directional_compact.textures' must be a list of file names");
    code = { form: c.form, K: c.coefficients, lo: c.lo, hi: c.hi, mean: c.mean, basis: c.basis };
    files = c.textures;
  } else if (j.directional !== undefined) {
    const d = j.directional;
    if (!d || d.channels !== DIRECTIONAL_CHANNELS)
      fail(url, `'directional' has ${d && d.channels} channels: directional-view reads ${DIRECTIONAL_CHANNELS} (gen-material --directional-view)`);
    code = { form: 'channels21', K: DIRECTIONAL_CHANNELS, lo: d.lo, hi: d.hi };
    files = [];
    for (let t = 0; 4 * t < DIRECTIONAL_CHANNELS; ++t) {
      const m = j.maps && j.maps[`directional_${t}`];
      if (!m || typeof m.ktx2 !== 'string') fail(url, `no maps.directional_${t}.ktx2 entry`);
      files.push(m.ktx2);
    }
  } else {
    fail(url, "neither 'directional_compact' nor 'directional': the texture set has no directional channels (gen-material --directional-view)");
  }
  if (Number.isInteger(code.K) && files.length !== Math.ceil(code.K / 4))
    fail(url, `K = ${code.K} needs ${Math.ceil(code.K / 4)} textures, the file lists ${files.length}`);
  const { KTX2Loader } = await import('three/addons/loaders/KTX2Loader.js');
  const loader = new KTX2Loader().detectSupport(renderer);
  try {
    code.textures = await Promise.all(files.map(async (f) => {
      const u = base + f;
      let t;
      try { t = await loader.loadAsync(u); } catch (e) { throw new Error(`microshadow: could not load ${u}: ${e.message || e}`); }
      if (t.isData3DTexture || t.isCompressedTexture) fail(u, 'not an uncompressed 2D texture');
      return prepareCoefficientTexture(t);
    }));
  } finally {
    loader.dispose();
  }
  const out = directionalOcclusion(code, url);
  out.url = url;
  return out;
}
