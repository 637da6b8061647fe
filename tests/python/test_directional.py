"""Directional micro-occlusion (occlusion/directional.h): directional_transport / directional_term against the
formula written independently in numpy, broadcasting and dtypes, and bake_directional_channels against the
flat surface's exact channels, the CLI's `bake directional` and the transport's meaning."""
import struct
import zlib

import numpy as np
import pytest

import microshadow as msh


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def basis(l):
    """b(l) = (1, x, y, z, xz, yz, x^2 - y^2, xy, z^2), the channel order of directional.h."""
    x, y, z = l[..., 0], l[..., 1], l[..., 2]
    return np.stack([np.ones_like(x), x, y, z, x * z, y * z, x * x - y * y, x * y, z * z], axis=-1)


def ref_transport(c, l):
    s = np.sum(c * basis(l), axis=-1)
    return np.where(l[..., 2] > 0, np.maximum(s, 0.0), 0.0)


def ref_term(c, l, n):
    nl = np.sum(n * l, axis=-1)
    safe = np.where(nl > 1e-4, nl, 1.0)
    return np.where(nl > 1e-4, ref_transport(c, l) / safe, 0.0)


def scale(c, l):
    """S = sum |c_i| |b_i(l)| (x^2 - y^2 read as x^2 + y^2): what rounding is relative to."""
    b = np.abs(basis(l))
    b[..., 6] = l[..., 0] ** 2 + l[..., 1] ** 2
    return np.sum(np.abs(c) * b, axis=-1)


def random_inputs(n, seed):
    g = np.random.default_rng(seed)
    c = g.uniform(-1, 1, (n, 9)) * 10.0 ** g.uniform(-2, 1, (n, 1))
    c[: n // 4] = [0, 0, 0, 1, 0, 0, 0, 0, 0] + 0.05 * g.uniform(-1, 1, (n // 4, 9))  # near the flat surface
    l = unit(g.normal(size=(n, 3)))  # half of them below the horizon
    l[:8, 2] = [0.0, -0.0, 1e-7, -1e-7, 1.0, 1e-3, 0.5, -1.0]
    l[:8] = np.concatenate([l[:8, :2] * np.sqrt(np.maximum(1 - l[:8, 2:] ** 2, 0)) /
                            np.linalg.norm(l[:8, :2], axis=-1, keepdims=True), l[:8, 2:]], axis=-1)
    nrm = unit(g.normal(size=(n, 3)) * [0.4, 0.4, 1] + [0, 0, 0.5])
    return c, l, nrm


def test_transport_and_term_match_numpy():
    c, l, n = random_inputs(20000, 1)
    t = msh.directional_transport(c, l)
    assert t.shape == (20000,) and t.dtype == np.float64
    s = scale(c, l)
    assert np.all(np.abs(t - ref_transport(c, l)) <= 1e-14 * s)
    assert np.all(t[l[:, 2] <= 0] == 0)  # below the horizon (and on it): exactly 0
    assert np.count_nonzero(t) > 5000
    term = msh.directional_term(c, l, n)
    nl = np.sum(n * l, axis=-1)
    ok = np.abs(nl - 1e-4) > 1e-12  # the early-out boundary itself may go either way at one rounding
    assert np.all(np.abs(term - ref_term(c, l, n))[ok] <= 1e-14 * (s / np.maximum(nl, 1e-4) + np.abs(term))[ok])
    assert np.all(term[nl < 1e-4] == 0)
    # the flat surface: transport = z, term = z / (n . l)
    flat = np.array([0, 0, 0, 1, 0, 0, 0, 0, 0.0])
    up = l[:, 2] > 1e-4
    assert np.allclose(msh.directional_transport(flat, l[up]), l[up, 2], rtol=0, atol=1e-15)
    assert np.allclose(msh.directional_term(flat, l[up], [0, 0, 1]), 1.0, rtol=0, atol=1e-15)


def test_broadcasting_dtypes_and_errors():
    c, l, n = random_inputs(35, 2)
    got = msh.directional_transport(c[:5, None, :], l[None, :7])  # (5, 1, 9) with (1, 7, 3)
    assert got.shape == (5, 7)
    want = ref_transport(c[:5, None, :], l[None, :7])
    assert np.max(np.abs(got - want)) < 1e-12
    c32, l32, n32 = c.astype(np.float32), l.astype(np.float32), n.astype(np.float32)
    t32 = msh.directional_term(c32, l32, n32)
    assert t32.dtype == np.float32
    # computed in double from the float32 inputs, rounded once
    ref = ref_term(c32.astype(float), l32.astype(float), n32.astype(float))
    assert np.max(np.abs(t32 - ref) / (np.abs(ref) + 1e-30)) < 1e-7
    assert msh.directional_transport(c32, np.float32([0.0, 0.6, 0.8])).dtype == np.float32
    assert msh.directional_transport(c32, [0.0, 0.6, 0.8]).dtype == np.float64  # a list is a float64 array
    assert np.shape(msh.directional_transport(list(c[0]), [0.0, 0.6, 0.8])) == ()  # one element: 0-d
    assert msh.directional_transport(np.zeros((0, 9)), [0, 0, 1]).shape == (0,)
    with pytest.raises(ValueError, match="last axis of length 9"):
        msh.directional_transport(np.zeros((4, 8)), [0, 0, 1])
    with pytest.raises(ValueError, match="last axis of length 3"):
        msh.directional_term(np.zeros(9), [0, 0, 1], [0, 1])
    with pytest.raises(ValueError, match="shape mismatch"):
        msh.directional_transport(np.zeros((4, 9)), np.zeros((5, 3)))


def bumpy(n=32):
    u = 2 * np.pi * np.arange(n) / n
    x, y = np.meshgrid(u, u)  # rows = y (v), columns = x (u)
    return np.clip(0.5 + 0.25 * np.sin(2 * x) * np.cos(3 * y) + 0.2 * np.sin(5 * x + y), 0, 1)


def test_bake_flat_and_meaning():
    flat = msh.bake_directional_channels(np.full((16, 24), 0.5), 4.0)
    assert flat.shape == (16, 24, 9) and flat.dtype == np.float32
    # a flat surface is lit everywhere with n = +z: transport = z, which the basis holds exactly
    assert np.max(np.abs(flat - [0, 0, 0, 1, 0, 0, 0, 0, 0])) < 1e-5

    h = bumpy()
    ch = msh.bake_directional_channels(h, 3.0, azimuths=16)
    assert ch.shape == (32, 32, 9)
    # Light at the zenith: nothing shadows, the transport is n_z of the central-difference normal; the fit
    # is a least-squares one, so compare the texture means (the fit is close there, not exact).
    dzdx = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) * 3.0 / 2
    dzdy = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) * 3.0 / 2
    nz = 1 / np.sqrt(1 + dzdx**2 + dzdy**2)
    t = msh.directional_transport(ch, [0, 0, 1])
    assert abs(t.mean() - nz.mean()) < 0.02
    # The channels are linear: the transport of a 4x4 box mean (a mip texel) is the mean of the fits.
    coarse = ch.reshape(8, 4, 8, 4, 9).mean(axis=(1, 3))
    l = unit([0.6, -0.3, 0.4])
    fine = np.sum(ch * basis(l), -1).reshape(8, 4, 8, 4).mean(axis=(1, 3))
    assert np.max(np.abs(np.sum(coarse * basis(l), -1) - fine)) < 1e-6
    # Grazing light is shadowed on relief: less transport than the lit flat surface's z.
    lg = unit([1.0, 0.0, 0.1])
    assert msh.directional_transport(ch, lg).mean() < 0.9 * lg[2]


def test_bake_errors():
    # Four azimuths make the harmonic fit (orders 0-2, five unknowns in phi) singular.
    for n in (3, 4, 4097):
        with pytest.raises(ValueError, match=r"azimuths must be in \[5, 4096\]"):
            msh.bake_directional_channels(np.full((8, 8), 0.5), 2.0, azimuths=n)
    assert np.all(np.isfinite(msh.bake_directional_channels(np.full((8, 8), 0.5), 2.0, azimuths=5)))
    with pytest.raises(ValueError, match="2-D array"):
        msh.bake_directional_channels(np.full(64, 0.5), 2.0)
    with pytest.raises(ValueError, match="outside"):
        msh.bake_directional_channels(np.full((8, 8), 1.5), 2.0)
    with pytest.raises(ValueError, match="each side"):
        msh.bake_directional_channels(np.full((4, 8), 0.5), 2.0)
    with pytest.raises(ValueError, match="depth"):
        msh.bake_directional_channels(np.full((8, 8), 0.5), 0.0)


def write_png16(path, h):
    """A 16-bit grey PNG of h in [0, 1] (what `bake directional` reads)."""
    q = np.round(h * 65535).astype(">u2")
    raw = b"".join(b"\x00" + row.tobytes() for row in q)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    hdr = struct.pack(">IIBBBBB", q.shape[1], q.shape[0], 16, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", hdr) + chunk(b"IDAT", zlib.compress(raw)) +
                     chunk(b"IEND", b""))
    return q.astype(np.float64) / 65535


def test_bake_equals_cli(cli, tmp_path):
    h = write_png16(tmp_path / "h.png", bumpy())
    rc, _, err = cli("bake", "directional", tmp_path / "h.png", "--depth", 3, "--azimuths", 16, "--out",
                     tmp_path / "out")
    assert rc == 0, err
    want = np.load(tmp_path / "out" / "directional_mip0.npy")[0]  # shape (1, h, w, 9), as io writes NPY
    got = msh.bake_directional_channels(h.astype(np.float32), 3.0, azimuths=16)
    assert np.array_equal(got, want)  # the same heights, the same bake: the same bits


def ref_view_transport(c, l, v):
    """T + (G_x v_x + G_y v_y) / max(v_z, 0.5), clamped at 0, 0 for l.z <= 0 (occlusion/directional.h): T on
    the 9 functions, G_x and G_y on the first 6 (1, x, y, z, xz, yz)."""
    b = basis(l)
    t = np.sum(c[..., :9] * b, axis=-1)
    gx = np.sum(c[..., 9:15] * b[..., :6], axis=-1)
    gy = np.sum(c[..., 15:21] * b[..., :6], axis=-1)
    vz = np.maximum(v[..., 2], 0.5)
    s = t + (gx * v[..., 0] + gy * v[..., 1]) / vz
    return np.where(l[..., 2] > 0, np.maximum(s, 0.0), 0.0)


def test_view_transport_and_term_match_numpy():
    g = np.random.default_rng(3)
    n = 5000
    c = g.uniform(-1, 1, (n, 21))
    c[:, 3] += 1.5
    l = unit(g.normal(size=(n, 3)))
    v = unit(g.normal(size=(n, 3)) * [1, 1, 0.5] + [0, 0, 0.3])  # some below v_z = 0.5 (the clamp)
    nrm = unit(g.normal(size=(n, 3)) * [0.3, 0.3, 1] + [0, 0, 0.5])
    t = msh.directional_view_transport(c, l, v)
    ref = ref_view_transport(c, l, v)
    assert np.max(np.abs(t - ref)) < 1e-12 * (1 + np.max(np.abs(ref)))
    assert np.count_nonzero(t) > 1000 and np.all(t[l[:, 2] <= 0] == 0)
    assert np.count_nonzero(v[:, 2] < 0.5) > 100 and np.count_nonzero(v[:, 2] > 0.5) > 100
    nl = np.sum(nrm * l, axis=-1)
    term = msh.directional_view_term(c, l, v, nrm)
    ok = nl > 1e-3
    assert np.max(np.abs(term[ok] - ref[ok] / nl[ok]) / (1 + np.abs(term[ok]))) < 1e-12
    assert np.all(term[nl < 1e-4] == 0)
    # the first 9 channels alone are directional_transport; zero slope channels: the view does not matter
    c0 = c.copy()
    c0[:, 9:] = 0
    assert np.array_equal(msh.directional_view_transport(c0, l, v), msh.directional_transport(c[:, :9], l))
    with pytest.raises(ValueError, match="last axis of length 21"):
        msh.directional_view_transport(np.zeros((4, 9)), [0, 0, 1], [0, 0, 1])


def test_bake_view_channels_and_cli(cli, tmp_path):
    h = write_png16(tmp_path / "h.png", bumpy())
    ch21 = msh.bake_directional_channels(h.astype(np.float32), 3.0, azimuths=16, view=True)
    assert ch21.shape == (32, 32, 21) and ch21.dtype == np.float32
    ch9 = msh.bake_directional_channels(h.astype(np.float32), 3.0, azimuths=16)
    assert np.array_equal(ch21[..., :9], ch9)
    # G = E[f n_x / n_z], E[f n_y / n_z] per texel; at the zenith nothing is shadowed, so f = n_z and G is
    # the texel's own slope -dz/dx, -dz/dy (central differences, as the bake's normal): the fit is least
    # squares, so compare texture-wide (the mean slope of a wrapping field is 0) and the correlation.
    dzdx = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) * 3.0 / 2
    dzdy = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) * 3.0 / 2
    nz = 1 / np.sqrt(1 + dzdx**2 + dzdy**2)
    up = np.array([0.0, 0.0, 1.0])
    gx = np.sum(ch21[..., 9:15] * basis(up)[:6], -1)
    gy = np.sum(ch21[..., 15:21] * basis(up)[:6], -1)
    assert abs(gx.mean()) < 0.02 and abs(gy.mean()) < 0.02
    assert np.corrcoef(gx.ravel(), (-dzdx * nz).ravel())[0, 1] > 0.95
    assert np.corrcoef(gy.ravel(), (-dzdy * nz).ravel())[0, 1] > 0.95
    rc, _, err = cli("bake", "directional", tmp_path / "h.png", "--depth", 3, "--azimuths", 16, "--view",
                     "--out", tmp_path / "out")
    assert rc == 0, err
    assert np.array_equal(np.load(tmp_path / "out" / "directional_mip0.npy")[0], ch21)
