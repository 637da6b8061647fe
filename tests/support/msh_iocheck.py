#!/usr/bin/python3
"""Independent readers/writers used by the io tests (tests/test_io_*.cpp).

Everything here is written from the format specifications (numpy NPY, Microsoft DDS_HEADER / DDS_HEADER_DXT10,
Khronos KTX 2.0 + Data Format 1.3, PNG ISO/IEC 15948) with struct/zlib/numpy, sharing no code with the C++
library. Each check prints what differs and exits 1 on the first failure, 0 when everything matches.

Usage:
  msh_iocheck.py npy  FILE RAW D H W C
  msh_iocheck.py dds  FILE RAW D H W C PF
  msh_iocheck.py ktx2 FILE RAW D H W C PF
  msh_iocheck.py png  FILE RAW D H W C BITS
  msh_iocheck.py make-png OUT RAW H W C BITS [palette]   (writes OUT and OUT.expected.raw)
  msh_iocheck.py make-dds OUT RAW D H W C PF    (writes OUT and OUT.expected.raw: the stored values as float32)
  msh_iocheck.py make-ktx2 OUT RAW D H W C PF
  msh_iocheck.py batch MANIFEST      (one command per line, as above; every line checked, failures listed)
RAW is the float32 little-endian source data, C order (D, H, W, C). PF is a pixel-format name (rgba16f, ...).
"""
import struct
import sys
import zlib

import numpy as np

# name: (channels, bytes per channel, kind) with kind 'f' = IEEE float, 'u' = UNORM.
PIXEL_FORMATS = {
    "rgba8": (4, 1, "u"), "rgba16f": (4, 2, "f"), "rgba32f": (4, 4, "f"),
    "rg16f": (2, 2, "f"), "rg32f": (2, 4, "f"), "r16f": (1, 2, "f"),
    "r32f": (1, 4, "f"), "r8": (1, 1, "u"), "rg8": (2, 1, "u"),
}
# DXGI_FORMAT values (Microsoft docs, DXGI_FORMAT enumeration).
DXGI = {"rgba8": 28, "rgba16f": 10, "rgba32f": 2, "rg16f": 34, "rg32f": 16, "r16f": 54, "r32f": 41,
        "r8": 61, "rg8": 49}
# VkFormat values (Vulkan spec, VkFormat enumeration).
VKFORMAT = {"rgba8": 37, "rgba16f": 97, "rgba32f": 109, "rg16f": 83, "rg32f": 103, "r16f": 76, "r32f": 100,
            "r8": 9, "rg8": 16}


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def expect(cond, msg):
    if not cond:
        fail(msg)


def load_raw(path, shape):
    a = np.fromfile(path, dtype="<f4")
    expect(a.size == int(np.prod(shape)), f"raw file {path} has {a.size} values, expected shape {shape}")
    return a.reshape(shape)


def quantize(src, pf):
    """The stored representation the writers must produce, computed with numpy."""
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    if kind == "u":
        return np.floor(np.clip(src.astype(np.float64), 0.0, 1.0) * 255.0 + 0.5).astype("<u1")
    if nbytes == 2:
        return src.astype("<f2")  # numpy: round to nearest, ties to even
    return src.astype("<f4")


def compare_texels(data_bytes, src, pf, what):
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    exp = quantize(src, pf)
    got = np.frombuffer(data_bytes, dtype=exp.dtype).reshape(exp.shape)
    # Compare bit patterns, so -0.0 and +0.0 differ and every texel and channel is checked.
    eb = exp.view(f"<u{nbytes}") if kind == "f" else exp
    gb = got.view(f"<u{nbytes}") if kind == "f" else got
    bad = np.argwhere(eb != gb)
    if bad.size:
        i = tuple(bad[0])
        fail(f"{what}: {len(bad)} texel values differ; first at (z,y,x,c)={i}: got {got[i]!r} "
             f"expected {exp[i]!r} (source {src[i]!r})")


# ---------------------------------------------------------------------------------------------------- NPY
def check_npy(path, raw, d, h, w, c):
    src = load_raw(raw, (d, h, w, c))
    a = np.load(path, allow_pickle=False)
    expect(a.dtype == np.dtype("<f4"), f"dtype {a.dtype}, expected <f4")
    expect(a.shape == (d, h, w, c), f"shape {a.shape}, expected {(d, h, w, c)}")
    expect(a.flags["C_CONTIGUOUS"], "not C order")
    with open(path, "rb") as f:
        head = f.read(10)
    expect(head[:8] == b"\x93NUMPY\x01\x00", f"magic/version {head[:8]!r}, expected version 1.0")
    hlen = struct.unpack("<H", head[8:10])[0]
    expect((10 + hlen) % 16 == 0, "data not 16-byte aligned (NPY 1.0 requirement)")
    bad = np.argwhere(a.view("<u4") != src.view("<u4"))
    expect(bad.size == 0, f"{len(bad)} values differ; first at {tuple(bad[0]) if bad.size else None}")


# ---------------------------------------------------------------------------------------------------- DDS
def check_dds(path, raw, d, h, w, c, pf):
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    expect(ch == c, "channel count does not match the pixel format")
    src = load_raw(raw, (d, h, w, c))
    buf = open(path, "rb").read()
    expect(len(buf) >= 148, "file shorter than the DDS + DX10 headers")
    expect(buf[:4] == b"DDS ", f"magic {buf[:4]!r}")
    hdr = struct.unpack("<7I11I", buf[4:76])
    size, flags, height, width, pitch, depth, mips = hdr[:7]
    reserved1 = hdr[7:]
    volume = d > 1
    DDSD_CAPS, DDSD_HEIGHT, DDSD_WIDTH, DDSD_PITCH = 0x1, 0x2, 0x4, 0x8
    DDSD_PIXELFORMAT, DDSD_MIPMAPCOUNT, DDSD_DEPTH = 0x1000, 0x20000, 0x800000
    want_flags = DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PITCH | DDSD_PIXELFORMAT | DDSD_MIPMAPCOUNT
    if volume:
        want_flags |= DDSD_DEPTH
    expect(size == 124, f"dwSize {size}")
    expect(flags == want_flags, f"dwFlags {flags:#x}, expected {want_flags:#x}")
    expect((height, width) == (h, w), f"dwHeight/dwWidth {height}x{width}, expected {h}x{w}")
    expect(pitch == w * ch * nbytes, f"dwPitchOrLinearSize {pitch}, expected row pitch {w * ch * nbytes}")
    expect(depth == (d if volume else 0), f"dwDepth {depth}")
    expect(mips == 1, f"dwMipMapCount {mips}")
    expect(all(r == 0 for r in reserved1), "dwReserved1 not zero")
    pfsize, pfflags, fourcc, bitcount, rm, gm, bm, am = struct.unpack("<II4s5I", buf[76:108])
    expect(pfsize == 32, f"ddspf.dwSize {pfsize}")
    expect(pfflags == 0x4, f"ddspf.dwFlags {pfflags:#x}, expected DDPF_FOURCC")
    expect(fourcc == b"DX10", f"ddspf.dwFourCC {fourcc!r}")
    expect((bitcount, rm, gm, bm, am) == (0, 0, 0, 0, 0), "ddspf bit count/masks not zero")
    caps, caps2, caps3, caps4, reserved2 = struct.unpack("<5I", buf[108:128])
    expect(caps == 0x1000, f"dwCaps {caps:#x}, expected DDSCAPS_TEXTURE")
    expect(caps2 == (0x200000 if volume else 0), f"dwCaps2 {caps2:#x}")
    expect((caps3, caps4, reserved2) == (0, 0, 0), "dwCaps3/dwCaps4/dwReserved2 not zero")
    dxgi, dim, misc, array_size, misc2 = struct.unpack("<5I", buf[128:148])
    expect(dxgi == DXGI[pf], f"dxgiFormat {dxgi}, expected {DXGI[pf]}")
    expect(dim == (4 if volume else 3), f"resourceDimension {dim}")
    expect(misc == 0 and array_size == 1 and misc2 == 0, f"miscFlag/arraySize/miscFlags2 {misc}/{array_size}/{misc2}")
    n = w * h * d * ch * nbytes
    expect(len(buf) == 148 + n, f"file size {len(buf)}, expected {148 + n}")
    compare_texels(buf[148:], src, pf, "DDS")


# ---------------------------------------------------------------------------------------------------- KTX2
def check_ktx2(path, raw, d, h, w, c, pf):
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    expect(ch == c, "channel count does not match the pixel format")
    src = load_raw(raw, (d, h, w, c))
    buf = open(path, "rb").read()
    ident = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
    expect(len(buf) >= 80 + 24, "file shorter than the KTX2 header")
    expect(buf[:12] == ident, "identifier")
    (vk, type_size, pw, ph, pd, layers, faces, levels, scheme) = struct.unpack("<9I", buf[12:48])
    expect(vk == VKFORMAT[pf], f"vkFormat {vk}, expected {VKFORMAT[pf]}")
    expect(type_size == nbytes, f"typeSize {type_size}, expected {nbytes}")
    expect((pw, ph) == (w, h), f"pixelWidth/Height {pw}x{ph}")
    expect(pd == (d if d > 1 else 0), f"pixelDepth {pd}")
    expect(layers == 0 and faces == 1 and levels == 1 and scheme == 0,
           f"layerCount/faceCount/levelCount/supercompressionScheme {layers}/{faces}/{levels}/{scheme}")
    dfd_off, dfd_len, kvd_off, kvd_len, sgd_off, sgd_len = struct.unpack("<4I2Q", buf[48:80])
    lvl_off, lvl_len, lvl_ulen = struct.unpack("<3Q", buf[80:104])
    expect(dfd_off == 104, f"dfdByteOffset {dfd_off}, expected 104 (right after the level index)")
    expect(sgd_off == 0 and sgd_len == 0, "sgd present")

    # Data Format Descriptor (KDFS 1.3): total size, then one basic descriptor block.
    dfd = buf[dfd_off:dfd_off + dfd_len]
    expect(len(dfd) == dfd_len and dfd_len >= 4 + 24, "DFD truncated")
    total = struct.unpack("<I", dfd[:4])[0]
    expect(total == dfd_len, f"dfdTotalSize {total} != dfdByteLength {dfd_len}")
    w0, w1, w2, w3, w4, w5 = struct.unpack("<6I", dfd[4:28])
    expect(w0 & 0x1FFFF == 0 and w0 >> 17 == 0, "vendorId/descriptorType not Khronos/basic")
    expect(w1 & 0xFFFF == 2, f"versionNumber {w1 & 0xFFFF}, expected 2 (KDFS 1.3)")
    block = w1 >> 16
    expect(block == 24 + 16 * ch, f"descriptorBlockSize {block}, expected {24 + 16 * ch}")
    expect(total == 4 + block, "dfdTotalSize != 4 + descriptorBlockSize")
    model, prim, transfer, dflags = w2 & 0xFF, (w2 >> 8) & 0xFF, (w2 >> 16) & 0xFF, w2 >> 24
    expect(model == 1, f"colorModel {model}, expected KHR_DF_MODEL_RGBSDA (1)")
    expect(prim == 1, f"colorPrimaries {prim}, expected BT709 (1)")
    expect(transfer == 1, f"transferFunction {transfer}, expected LINEAR (1)")
    expect(dflags == 0, f"flags {dflags}, expected ALPHA_STRAIGHT (0)")
    expect(w3 == 0, "texelBlockDimension not 1x1x1x1")
    expect(w4 == ch * nbytes and w5 == 0, f"bytesPlane0 {w4 & 0xFF}, expected {ch * nbytes}")
    channel_ids = [0, 1, 2, 15]
    for i in range(ch):
        s0, s1, lower, upper = struct.unpack("<4I", dfd[28 + 16 * i:44 + 16 * i])
        bit_off, bit_len, ctype = s0 & 0xFFFF, (s0 >> 16) & 0xFF, s0 >> 24
        expect(bit_off == i * 8 * nbytes, f"sample {i} bitOffset {bit_off}")
        expect(bit_len == 8 * nbytes - 1, f"sample {i} bitLength {bit_len}")
        quals = 0xC0 if kind == "f" else 0x00  # KHR_DF_SAMPLE_DATATYPE_FLOAT | SIGNED for *_SFLOAT
        expect(ctype == (channel_ids[i] | quals), f"sample {i} channelType {ctype:#x}")
        expect(s1 == 0, f"sample {i} samplePosition not 0")
        if kind == "f":
            want = (struct.unpack("<I", struct.pack("<f", -1.0))[0], struct.unpack("<I", struct.pack("<f", 1.0))[0])
        else:
            want = (0, 255)
        expect((lower, upper) == want, f"sample {i} sampleLower/Upper {lower:#x}/{upper:#x}, expected {want}")

    # Key/value data: entries sorted by key, NUL-terminated key, 4-byte value padding included in kvdByteLength.
    expect(kvd_off == dfd_off + dfd_len, f"kvdByteOffset {kvd_off} does not follow the DFD")
    kvd = buf[kvd_off:kvd_off + kvd_len]
    expect(len(kvd) == kvd_len, "kvd truncated")
    pos, keys = 0, {}
    while pos < kvd_len:
        n = struct.unpack("<I", kvd[pos:pos + 4])[0]
        kv = kvd[pos + 4:pos + 4 + n]
        key, sep, value = kv.partition(b"\0")
        expect(sep == b"\0", "key not NUL-terminated")
        keys[key.decode()] = value
        pos += 4 + n
        pad = (-pos) % 4
        expect(kvd[pos:pos + pad] == b"\0" * pad, "valuePadding not zero")
        pos += pad
    expect(pos == kvd_len, "kvdByteLength does not match the entries")
    expect(list(keys) == sorted(keys), "keys not sorted")
    expect("KTXwriter" in keys, "no KTXwriter")
    expect(keys["KTXwriter"].endswith(b"\0") and keys["KTXwriter"].startswith(b"microshadow"),
           f"KTXwriter value {keys['KTXwriter']!r} (must be NUL-terminated UTF-8)")

    # Level 0: aligned to lcm(texel block size, 4), right after the kvd plus zero mipPadding.
    texel = ch * nbytes
    align = np.lcm(texel, 4)
    end = kvd_off + kvd_len
    want_off = (end + align - 1) // align * align
    expect(lvl_off == want_off, f"level byteOffset {lvl_off}, expected {want_off}")
    expect(buf[end:lvl_off] == b"\0" * (lvl_off - end), "mipPadding not zero")
    n = w * h * d * texel
    expect(lvl_len == n and lvl_ulen == n, f"level byteLength/uncompressed {lvl_len}/{lvl_ulen}, expected {n}")
    expect(len(buf) == lvl_off + n, f"file size {len(buf)}, expected {lvl_off + n}")
    compare_texels(buf[lvl_off:], src, pf, "KTX2")


# ---------------------------------------------------------------------------------------------------- PNG
def png_chunks(buf):
    expect(buf[:8] == b"\x89PNG\r\n\x1a\n", "PNG signature")
    pos, chunks = 8, []
    while pos < len(buf):
        n, typ = struct.unpack(">I4s", buf[pos:pos + 8])
        data = buf[pos + 8:pos + 8 + n]
        crc = struct.unpack(">I", buf[pos + 8 + n:pos + 12 + n])[0]
        expect(zlib.crc32(typ + data) & 0xFFFFFFFF == crc, f"bad CRC in {typ!r}")
        chunks.append((typ, data))
        pos += 12 + n
    expect(chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND", "IHDR/IEND placement")
    return chunks


def png_decode(buf):
    chunks = png_chunks(buf)
    w, h, bits, ctype, comp, filt, inter = struct.unpack(">IIBBBBB", chunks[0][1])
    expect(comp == 0 and filt == 0 and inter == 0, "unexpected compression/filter/interlace method")
    ch = {0: 1, 4: 2, 2: 3, 6: 4}.get(ctype)
    expect(ch is not None and bits in (8, 16), f"color type {ctype} bit depth {bits} not handled by the checker")
    raw = zlib.decompress(b"".join(d for t, d in chunks if t == b"IDAT"))
    bpp = ch * bits // 8
    stride = w * bpp
    expect(len(raw) == h * (stride + 1), "IDAT size")
    out = bytearray(h * stride)
    prev = bytearray(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ft == 0:
                pred = 0
            elif ft == 1:
                pred = a
            elif ft == 2:
                pred = b
            elif ft == 3:
                pred = (a + b) // 2
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if (pa <= pb and pa <= pc) else (b if pb <= pc else c)
            else:
                fail(f"bad filter type {ft}")
            line[i] = (line[i] + pred) & 0xFF
        out[y * stride:(y + 1) * stride] = line
        prev = line
    dt = ">u2" if bits == 16 else "u1"
    img = np.frombuffer(bytes(out), dtype=dt).reshape(h, w, ch)
    texts = {}
    for t, d in chunks:
        if t == b"tEXt":
            k, _, v = d.partition(b"\0")
            texts[k.decode("latin-1")] = v.decode("latin-1")
    return img, bits, [t for t, _ in chunks], texts


def check_png(path, raw, d, h, w, c, bits):
    src = load_raw(raw, (d, h, w, c))
    img, got_bits, types, texts = png_decode(open(path, "rb").read())
    expect(got_bits == bits, f"bit depth {got_bits}, expected {bits}")
    expect(img.shape == (h * d, w, c), f"image shape {img.shape}, expected {(h * d, w, c)}")
    for t in (b"gAMA", b"sRGB", b"iCCP", b"cHRM"):
        expect(t not in types, f"unexpected color chunk {t!r} (values must be stored as-is)")
    if d > 1:
        expect(texts.get("microshadow:depth") == str(d), f"tEXt microshadow:depth = {texts.get('microshadow:depth')}")
    maxv = (1 << bits) - 1
    exp = np.floor(np.clip(src.astype(np.float64), 0, 1) * maxv + 0.5).astype(np.int64).reshape(h * d, w, c)
    bad = np.argwhere(img.astype(np.int64) != exp)
    expect(bad.size == 0, f"{len(bad)} samples differ; first at {tuple(bad[0]) if bad.size else None}")


def make_png(out, raw, h, w, c, bits, palette):
    src = load_raw(raw, (h, w, c))
    maxv = (1 << bits) - 1
    q = np.floor(np.clip(src.astype(np.float64), 0, 1) * maxv + 0.5).astype(np.int64)
    ctype = {1: 0, 2: 4, 3: 2, 4: 6}[c]
    if palette:
        expect(bits == 8 and c in (3, 4), "palette needs 8-bit RGB or RGBA")
        colors = sorted({tuple(px) for px in q.reshape(-1, c)})
        expect(len(colors) <= 256, "too many colors for a palette")
        index = {col: i for i, col in enumerate(colors)}
        pixels = np.array([index[tuple(px)] for px in q.reshape(-1, c)], dtype="u1").reshape(h, w)
        rows = b"".join(b"\0" + pixels[y].tobytes() for y in range(h))
        extra = [(b"PLTE", b"".join(bytes(col[:3]) for col in colors))]
        if c == 4:
            extra.append((b"tRNS", bytes(col[3] for col in colors)))
        ctype = 3
    else:
        dt = ">u2" if bits == 16 else "u1"
        arr = q.astype(dt)
        rows = b"".join(b"\0" + arr[y].tobytes() for y in range(h))
        extra = []

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bits, ctype, 0, 0, 0))
    for t, d in extra:
        data += chunk(t, d)
    data += chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")
    open(out, "wb").write(data)
    (q.astype(np.float64) / maxv).astype("<f4").tofile(out + ".expected.raw")


def stored_values(src, pf):
    q = quantize(src, pf)
    return (q.astype(np.float64) / 255.0).astype("<f4") if PIXEL_FORMATS[pf][2] == "u" else q.astype("<f4")


def make_dds(out, raw, d, h, w, c, pf):
    """A DX10 DDS written from the Microsoft documentation (a second, independent encoder)."""
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    src = load_raw(raw, (d, h, w, c))
    volume = d > 1
    flags = 0x1 | 0x2 | 0x4 | 0x1000 | (0x800000 if volume else 0)  # no PITCH/MIPMAPCOUNT: both optional
    hdr = struct.pack("<7I11I", 124, flags, h, w, 0, d if volume else 0, 0, *([0] * 11))
    hdr += struct.pack("<II4s5I", 32, 0x4, b"DX10", 0, 0, 0, 0, 0)
    hdr += struct.pack("<5I", 0x1000, 0x200000 if volume else 0, 0, 0, 0)
    hdr += struct.pack("<5I", DXGI[pf], 4 if volume else 3, 0, 1, 0)
    open(out, "wb").write(b"DDS " + hdr + quantize(src, pf).tobytes())
    stored_values(src, pf).tofile(out + ".expected.raw")


def make_ktx2(out, raw, d, h, w, c, pf):
    """A KTX2 file written from the KTX 2.0 spec with two key/value entries (a second, independent encoder)."""
    ch, nbytes, kind = PIXEL_FORMATS[pf]
    src = load_raw(raw, (d, h, w, c))
    texel = ch * nbytes
    samples = b""
    for i in range(ch):
        quals = 0xC0 if kind == "f" else 0
        lower, upper = (0xBF800000, 0x3F800000) if kind == "f" else (0, 255)
        samples += struct.pack("<4I", (i * 8 * nbytes) | ((8 * nbytes - 1) << 16) | (([0, 1, 2, 15][i] | quals) << 24),
                               0, lower, upper)
    block = 24 + 16 * ch
    dfd = struct.pack("<7I", 4 + block, 0, 2 | (block << 16), 1 | (1 << 8) | (1 << 16), 0, texel, 0) + samples
    kvd = b""
    for key, value in ((b"KTXorientation", b"rd\0"), (b"KTXwriter", b"msh_iocheck.py\0")):
        entry = key + b"\0" + value
        kvd += struct.pack("<I", len(entry)) + entry + b"\0" * ((-len(entry)) % 4)
    dfd_off = 80 + 24
    kvd_off = dfd_off + len(dfd)
    align = int(np.lcm(texel, 4))
    lvl_off = (kvd_off + len(kvd) + align - 1) // align * align
    data = quantize(src, pf).tobytes()
    ident = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
    head = ident + struct.pack("<9I", VKFORMAT[pf], nbytes, w, h, d if d > 1 else 0, 0, 1, 1, 0)
    head += struct.pack("<4I2Q", dfd_off, len(dfd), kvd_off, len(kvd), 0, 0)
    head += struct.pack("<3Q", lvl_off, len(data), len(data))
    body = head + dfd + kvd
    body += b"\0" * (lvl_off - len(body))
    open(out, "wb").write(body + data)
    stored_values(src, pf).tofile(out + ".expected.raw")


def main(argv):
    cmd = argv[1]
    if cmd == "batch":
        import shlex
        failures = 0
        for line in open(argv[2]):
            if not line.strip():
                continue
            try:
                main(["msh_iocheck.py"] + shlex.split(line))
            except SystemExit as e:
                if e.code:
                    failures += 1
                    print("  in:", line.strip())
        if failures:
            fail(f"{failures} check(s) failed")
        return
    if cmd == "npy":
        check_npy(argv[2], argv[3], *map(int, argv[4:8]))
    elif cmd in ("dds", "ktx2"):
        (check_dds if cmd == "dds" else check_ktx2)(argv[2], argv[3], *map(int, argv[4:8]), argv[8])
    elif cmd == "png":
        check_png(argv[2], argv[3], *map(int, argv[4:9]))
    elif cmd in ("make-dds", "make-ktx2"):
        (make_dds if cmd == "make-dds" else make_ktx2)(argv[2], argv[3], *map(int, argv[4:8]), argv[8])
    elif cmd == "make-png":
        make_png(argv[2], argv[3], *map(int, argv[4:8]), len(argv) > 8 and argv[8] == "palette")
    else:
        fail(f"unknown command {cmd}")
    print("OK")


if __name__ == "__main__":
    main(sys.argv)
