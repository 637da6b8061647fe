// Loading microshadow's baked micro-shadowing tables (cone layout, docs/lut.md) as three.js 3D textures:
// `microshadow bake micro-shadowing --out lut.npy` (float32 NPY, shape (depth, height, width, channels), with
// its sidecar lut.npy.json), `--out lut.ktx2` (through three's KTX2Loader; the installed default tables
// share/microshadow/tables/micro_shadowing*.ktx2 are such files) or the viewer's raw half floats
// (`microshadow view --export`: data/lut3d.f16 with data/lut3d.json). Linear filtering, clamp to edge, no
// mips: the layout the GLSL cone sampler expects (shaders/glsl/micro_shadowing.glsl, msh_ms_lut_sample_cone);
// NPY and raw tables are uploaded as half floats (linear filtering everywhere WebGL2 runs).
import { ClampToEdgeWrapping, Data3DTexture, DataUtils, HalfFloatType, LinearFilter, RedFormat, RGFormat, RGBAFormat } from 'three';

async function fetchOk(url, kind) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`microshadow: could not load ${url}: HTTP ${r.status}`);
  return kind === 'json' ? r.json() : r.arrayBuffer();
}

// {shape, data (Float32Array)} of a little-endian float32 or float16 C-order NPY file.
export function parseNpy(buf, name = 'NPY') {
  const u8 = new Uint8Array(buf);
  const magic = String.fromCharCode(...u8.subarray(0, 6));
  if (magic !== '\x93NUMPY') throw new Error(`microshadow: ${name} is not an NPY file`);
  const major = u8[6];
  const hlen = major >= 2 ? new DataView(buf).getUint32(8, true) : new DataView(buf).getUint16(8, true);
  const off = major >= 2 ? 12 : 10;
  const header = new TextDecoder().decode(u8.subarray(off, off + hlen));
  const descr = /'descr':\s*'([^']+)'/.exec(header), shape = /'shape':\s*\(([^)]*)\)/.exec(header);
  if (!descr || !shape || /'fortran_order':\s*True/.test(header))
    throw new Error(`microshadow: ${name}: unsupported NPY header ${header.trim()}`);
  const dims = shape[1].split(',').map((s) => s.trim()).filter((s) => s.length).map(Number);
  const count = dims.reduce((a, b) => a * b, 1), start = off + hlen;
  let data;
  if (descr[1] === '<f4') data = new Float32Array(buf.slice(start, start + 4 * count));
  else if (descr[1] === '<f2') data = Float32Array.from(new Uint16Array(buf.slice(start, start + 2 * count)), DataUtils.fromHalfFloat);
  else throw new Error(`microshadow: ${name}: dtype ${descr[1]} (float32 or float16 expected)`);
  if (data.length !== count) throw new Error(`microshadow: ${name}: ${data.length} values, the header says ${count}`);
  return { shape: dims, data };
}

function lutTexture(half, w, h, d, c) {
  const format = [RedFormat, RGFormat, null, RGBAFormat][c - 1];
  if (!format) throw new Error(`microshadow: a table with ${c} channels (1, 2 or 4 expected)`);
  const tex = new Data3DTexture(half, w, h, d);
  tex.format = format;
  tex.type = HalfFloatType;
  tex.minFilter = tex.magFilter = LinearFilter;
  tex.wrapS = tex.wrapT = tex.wrapR = ClampToEdgeWrapping;
  tex.generateMipmaps = false;
  tex.unpackAlignment = 1;
  tex.needsUpdate = true;
  return tex;
}

// A KTX2 table through three's KTX2Loader (uncompressed formats need no transcoder): the 3D texture,
// filtered linearly. A float32 table (bake --pixel-format rgba32f) needs OES_texture_float_linear.
async function loadKtx2(url, renderer) {
  if (!renderer) throw new Error(`microshadow: ${url}: a KTX2 table loads through three's KTX2Loader, which needs the renderer: loadMicroShadowingLut(url, { renderer })`);
  const { KTX2Loader } = await import('three/addons/loaders/KTX2Loader.js');
  const loader = new KTX2Loader().detectSupport(renderer);
  try {
    const tex = await loader.loadAsync(url);
    if (!tex.isData3DTexture) throw new Error(`microshadow: ${url} is not a 3D texture`);
    tex.minFilter = tex.magFilter = LinearFilter;
    tex.wrapS = tex.wrapT = tex.wrapR = ClampToEdgeWrapping;
    tex.generateMipmaps = false;
    tex.mipmaps = [];
    tex.unpackAlignment = 1;
    tex.needsUpdate = true;
    return tex;
  } finally {
    loader.dispose();
  }
}

// A cone-layout table from a URL: `.npy` or `.ktx2` (sidecar URL + '.json', as `bake micro-shadowing` writes
// it) or `.f16` (sidecar: the same name with `.json`); options.sidecar overrides the sidecar's URL;
// options.renderer is needed for KTX2. Returns {texture, slabs, harmonics, size, channels, sidecar} for
// addMicroShadowing's `luts` option. Throws (one line) for a seed-layout table, non-default cone warps (the
// GLSL sampler has the defaults as constants) or a size that does not match the sidecar.
export async function loadMicroShadowingLut(url, options = {}) {
  const npy = /\.npy$/i.test(url), ktx2 = /\.ktx2$/i.test(url);
  const sideUrl = options.sidecar || (npy || ktx2 ? `${url}.json` : url.replace(/\.[^./]+$/, '.json'));
  const [buf, side] = await Promise.all([ktx2 ? loadKtx2(url, options.renderer) : fetchOk(url, 'buf'), fetchOk(sideUrl, 'json')]);
  if (side.layout !== 'cone')
    throw new Error(`microshadow: ${url} is a ${side.layout}-layout table; the shaders sample cone-layout tables (bake micro-shadowing --layout cone, the default)`);
  const defaults = { warp_scale: 2, nv_scale: 3, top_scale: 3, roughness_range: [0.1, 1] };
  for (const [k, v] of Object.entries(defaults))
    if (side[k] !== undefined && JSON.stringify(side[k]) !== JSON.stringify(v))
      throw new Error(`microshadow: ${url} was baked with ${k} = ${JSON.stringify(side[k])}; the GLSL sampler has the default ${JSON.stringify(v)}`);
  const slabs = side.roughness_slabs, harmonics = side.harmonics || 0;
  let w, h, d, c, half;
  if (ktx2) {
    const t = buf;
    [w, h, d] = [t.image.width, t.image.height, t.image.depth];
    c = { [RedFormat]: 1, [RGFormat]: 2, [RGBAFormat]: 4 }[t.format];
    if (w !== side.size_t || h !== side.size_n_dot_l || d !== side.size_n_dot_v * slabs || !c)
      throw new Error(`microshadow: ${url}: ${w}x${h}x${d} texels do not match its sidecar ${sideUrl}`);
    return { texture: t, slabs, harmonics, size: [w, h, d], channels: c, sidecar: side, url };
  }
  if (npy) {
    const a = parseNpy(buf, url);
    if (a.shape.length !== 4) throw new Error(`microshadow: ${url}: shape (${a.shape}) is not (depth, height, width, channels)`);
    [d, h, w, c] = a.shape;
    half = new Uint16Array(a.data.length);
    for (let i = 0; i < a.data.length; ++i) half[i] = DataUtils.toHalfFloat(a.data[i]);
  } else {
    w = side.size_t; h = side.size_n_dot_l; d = side.size_n_dot_v * slabs; c = harmonics > 0 ? 4 : 1;
    half = new Uint16Array(buf);
  }
  if (w !== side.size_t || h !== side.size_n_dot_l || d !== side.size_n_dot_v * slabs || half.length !== w * h * d * c)
    throw new Error(`microshadow: ${url}: ${w}x${h}x${d}x${c} texels (${half.length} values) do not match its sidecar ${sideUrl}`);
  return { texture: lutTexture(half, w, h, d, c), slabs, harmonics, size: [w, h, d], channels: c, sidecar: side, url };
}
