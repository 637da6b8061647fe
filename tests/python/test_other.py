"""The rest of the module: bump-terminator terms, NDFs and VNDF sampling, BRDF models, LUT bake/load,
render and compare. Each is checked against the CLI and/or an independent numpy reference."""
import math

import numpy as np
import pytest

import microshadow as msh


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def rand_dirs(n, seed, upper=True):
    g = np.random.default_rng(seed)
    d = unit(g.normal(size=(n, 3)))
    if upper:
        d[:, 2] = np.abs(d[:, 2])
    return d


# ---- bump terminator ----------------------------------------------------------------------------------

def test_bump_equals_cli(cli):
    cases = [("conty-2019", "0,0,1", "0.3,0,1", "1,0,0.2"), ("chiang-2019", "0,0,1", "0.3,0.1,1", "1,0.5,0.3"),
             ("conty-2019", "0,0.1,1", "-0.4,0,1", "0.2,0.9,0.1"), ("none", "0,0,1", "0.3,0,1", "1,0,0.2")]
    for m, ng, ns, l in cases:
        rc, out, err = cli("eval", "bump-terminator", "--method", m, "--geometric-normal", ng, "--shading-normal",
                           ns, "--light", l, "--json")
        assert rc == 0, err
        vec = [np.array([float(x) for x in s.split(",")]) for s in (ng, ns, l)]
        assert msh.bump_terminator(m, *vec) == out["value"]
        if m == "conty-2019":
            assert msh.bump_alpha2(vec[0], vec[1]) == out["alpha2"]
    with pytest.raises(ValueError, match="unknown --method 'x'"):
        msh.bump_terminator("x", [0, 0, 1], [0, 0, 1], [0, 0, 1])


def test_bump_against_numpy_formulas():
    ng = np.array([0.0, 0.0, 1.0])
    ns = unit(rand_dirs(5000, 1) * [0.5, 0.5, 1])
    l = rand_dirs(5000, 2)
    # Chiang et al. 2019: g = (ng.l)/((ns.l)(ng.ns)), -g^3 + g^2 + g on [0, 1]
    g = (l @ ng) / (np.sum(ns * l, -1) * (ns @ ng))
    ref = np.where(g >= 1, 1.0, np.where(g <= 0, 0.0, -g**3 + g**2 + g))
    assert np.max(np.abs(msh.bump_terminator("chiang-2019", ng, ns, l) - ref)) < 1e-12
    # Conty Estevez et al. 2019: alpha^2 = clamp(tan^2(theta_d)/8, 0, 1), G1 = 2/(1 + sqrt(1 + a2 tan^2 theta_i))
    cd = ns @ ng
    a2 = np.clip((1 - cd**2) / cd**2 / 8, 0, 1)
    ci = l @ ng
    ref = 2 / (1 + np.sqrt(1 + a2 * (1 - ci**2) / np.maximum(ci**2, 1e-12)))
    got = msh.bump_terminator("conty-2019", ng, ns, l)
    assert got.shape == (5000,)
    assert np.max(np.abs(got - ref)) < 1e-9
    assert msh.bump_terminator("conty-2019", ng, ns.astype(np.float32), l.astype(np.float32)).dtype == np.float64
    assert msh.bump_terminator("conty-2019", ng.astype(np.float32), ns.astype(np.float32),
                               l.astype(np.float32)).dtype == np.float32
    with pytest.raises(ValueError, match="last axis of length 3"):
        msh.bump_terminator("conty-2019", [0, 1], ns, l)


# ---- NDFs ---------------------------------------------------------------------------------------------

def view_dir(ndotv, phi):
    s = math.sqrt(max(0.0, 1 - ndotv * ndotv))
    return np.array([s * math.cos(phi), s * math.sin(phi), ndotv])


@pytest.mark.parametrize("ndf", ["ggx", "beckmann", "blinn-phong", "gtr"])
def test_ndf_equals_cli(cli, ndf):
    rc, out, err = cli("eval", "microfacet", "--ndf", ndf, "--alpha", "0.3", "--ndotv", "0.6", "--phi", "0.5",
                       "--json")
    assert rc == 0, err
    v = view_dir(0.6, 0.5)
    assert msh.ndf_D(ndf, [0, 0, 1], alpha=0.3) == out["D_normal"]
    assert msh.ndf_D(ndf, v, alpha=0.3) == out["D_v"]
    assert msh.ndf_lambda(ndf, v, alpha=0.3) == out["Lambda"]
    assert msh.ndf_G1(ndf, v, alpha=0.3) == out["G1"]


def test_ggx_against_closed_forms():
    # RTR4 eq. 9.41 (GGX D) and 9.37 (GGX Lambda), with per-element alpha broadcast against directions.
    m = rand_dirs(4000, 3)
    alpha = np.linspace(0.05, 1, 4000)
    c = m[:, 2]
    d_ref = alpha**2 / (np.pi * (1 + c**2 * (alpha**2 - 1)) ** 2)
    assert np.max(np.abs(msh.ndf_D("ggx", m, alpha=alpha) / d_ref - 1)) < 1e-12
    lam_ref = (np.sqrt(1 + alpha**2 * (1 - c**2) / c**2) - 1) / 2
    assert np.max(np.abs(msh.ndf_lambda("ggx", m, alpha=alpha) - lam_ref)) < 1e-9
    g2 = msh.ndf_G2("ggx", m, m[::-1], alpha=0.4)
    l1, l2 = (msh.ndf_lambda("ggx", x, alpha=0.4) for x in (m, m[::-1]))
    assert np.max(np.abs(g2 - 1 / (1 + l1 + l2))) < 1e-12


@pytest.mark.parametrize("ndf", ["ggx", "beckmann"])
def test_vndf_sampling_matches_pdf(ndf):
    # E[f(m)] over sample_vndf equals the quadrature of f(m) D_w(m) (vndf_pdf) over the hemisphere.
    w = view_dir(0.4, 0.3)
    alpha = 0.5
    u = np.random.default_rng(5).random((200000, 2))
    m = msh.sample_vndf(ndf, w, u, alpha=alpha, alpha_y=0.3)
    assert np.allclose(np.linalg.norm(m, axis=-1), 1, atol=1e-12)
    nt, nphi = 400, 400
    t = (np.arange(nt) + 0.5) / nt * (np.pi / 2)
    p = (np.arange(nphi) + 0.5) / nphi * (2 * np.pi)
    T, P = np.meshgrid(t, p, indexing="ij")
    dirs = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    dA = np.sin(T) * (np.pi / 2 / nt) * (2 * np.pi / nphi)
    pdf = msh.vndf_pdf(ndf, w, dirs, alpha=alpha, alpha_y=0.3)
    assert abs(np.sum(pdf * dA) - 1) < 2e-3
    for f in (lambda x: x[..., 2], lambda x: x[..., 0] ** 2):
        q = np.sum(f(dirs) * pdf * dA)
        s = f(m)
        assert abs(s.mean() - q) < 5 * s.std() / math.sqrt(len(s)) + 2e-3


def test_ndf_errors():
    with pytest.raises(ValueError, match="--ndf must be one of"):
        msh.ndf_D("phong", [0, 0, 1])
    with pytest.raises(ValueError, match=r"--alpha must be in \[0, 4\], got 5"):
        msh.ndf_D("ggx", [0, 0, 1], alpha=[0.5, 5.0])
    with pytest.raises(ValueError, match="GTR is isotropic"):
        msh.ndf_D("gtr", [0, 0, 1], alpha=0.3, alpha_y=0.2)


# ---- BRDF models --------------------------------------------------------------------------------------

def test_every_brdf_model_equals_cli(cli):
    models = msh.brdf_models()
    assert len(models) > 10
    rc, out, err = cli("eval", "brdf", "--list", "--json")
    assert [m["name"] for m in out["models"]] == [m["name"] for m in models]
    wo = np.array([0.8, 0.0, 0.6])
    light = "0.3,0.2,0.9"
    for m in models:
        rc, out, err = cli("eval", "brdf", "--model", m["name"], "--ndotv", "0.6", "--light", light, "--json")
        assert rc == 0, err
        wi = np.array(out["light"])
        got = msh.eval_brdf(m["name"], wo, wi)
        assert got.shape == (3,)
        assert list(got) == out["value"], m["name"]
        assert msh.brdf_pdf(m["name"], wo, wi) == out["pdf"], m["name"]


def test_brdf_params_and_vectorization(cli):
    wo, wi = rand_dirs(1000, 7), rand_dirs(1000, 8)
    # Lambert: rho / pi, independent of the directions (both above the horizon)
    f = msh.eval_brdf("lambert", wo, wi, rho=(0.2, 0.4, 0.6))
    assert f.shape == (1000, 3)
    assert np.allclose(f, np.array([0.2, 0.4, 0.6]) / np.pi, rtol=1e-15, atol=0)
    rc, out, _ = cli("eval", "brdf", "--model", "ggx", "--ndotv", "0.6", "--light", "0.3,0.2,0.9",
                     "--roughness", "0.3", "--fresnel", "schlick", "--json")
    assert list(msh.eval_brdf("ggx", [0.8, 0, 0.6], out["light"], roughness=0.3, fresnel="schlick")) == out["value"]
    wi_s, f_s, pdf_s = msh.sample_brdf("ggx", wo, np.random.default_rng(1).random((1000, 2)), roughness=0.5)
    ok = pdf_s > 0
    assert np.allclose(msh.eval_brdf("ggx", wo[ok], wi_s[ok], roughness=0.5), f_s[ok], rtol=1e-12, atol=0)
    assert np.allclose(msh.brdf_pdf("ggx", wo[ok], wi_s[ok], roughness=0.5), pdf_s[ok], rtol=1e-10, atol=0)
    with pytest.raises(ValueError, match="has no parameter --nope"):
        msh.eval_brdf("ggx", wo, wi, nope=1)
    with pytest.raises(ValueError):
        msh.eval_brdf("no-such-model", wo, wi)


# ---- LUT ----------------------------------------------------------------------------------------------

def test_lut_bake_and_load(small_lut, tmp_path):
    path, table, side = small_lut
    assert table.dtype == np.float32 and table.shape == (6 * 4, 10, 12, 4)
    assert side["layout"] == "cone" and side["harmonics"] == 3
    t2, s2 = msh.load_micro_shadowing_lut(path)
    assert np.array_equal(t2, table) and s2 == side
    # Bit-identical re-bake (deterministic whatever the threads); the seed layout without a sidecar
    seed_t, seed_s = msh.bake_micro_shadowing_lut(layout="seed", n_vis=6, n_nl=6, n_nv=3, samples=128,
                                                  out=tmp_path / "s.npy")
    assert seed_t.shape == (3, 6, 6, 4) and seed_s["roughness"] == [0.1, 0.4, 0.7, 1.0]
    # V = 0 column is exactly 0 and V = 1 column exactly 1 (written exactly by the baker, docs/lut.md)
    assert np.all(seed_t[:, :, 0, :] == 0) and np.all(seed_t[:, 1:, -1, :] == 1)
    # the sampler at a texel node of a channel's roughness returns that texel
    v, nl, nv = 3 / 5, 4 / 5, 1 / 2
    got = msh.eval_micro_shadowing("lut3d", v, nl, nv, 0.4, lut=tmp_path / "s.npy")
    assert abs(got - seed_t[1, 4, 3, 1]) < 1e-6
    (tmp_path / "s.npy.json").unlink()
    t3, s3 = msh.load_micro_shadowing_lut(tmp_path / "s.npy")
    assert s3["sidecar"] is None and s3["layout"] == "seed" and np.array_equal(t3, seed_t)
    _, s4 = msh.load_micro_shadowing_lut(tmp_path / "s.npy", roughness=[0.2, 0.4, 0.6, 0.8])
    assert s4["roughness"] == [0.2, 0.4, 0.6, 0.8]
    with pytest.raises(ValueError, match="Visibility size"):
        msh.bake_micro_shadowing_lut(layout="seed", n_vis=1)
    with pytest.raises(ValueError):
        msh.load_micro_shadowing_lut(tmp_path / "missing.npy")


# ---- render and compare -------------------------------------------------------------------------------

SCENE = {
    "camera": {"eye": [0, -5, 2.2], "target": [0, 0, 0.6], "up": [0, 0, 1], "fov_deg": 35},
    "materials": {"grey": {"base_color": [0.6, 0.6, 0.6], "roughness": 0.45, "metallic": 0}},
    "objects": [{"type": "sphere", "material": "grey", "center": [0, 0, 1], "radius": 1}],
    "lights": [{"type": "directional", "elevation_deg": 40, "azimuth_deg": -30, "intensity": 3}],
    "settings": {"width": 24, "height": 16, "spp": 2},
}


def test_render_and_compare_equal_cli(cli, tmp_path):
    import json

    scene_path = tmp_path / "scene.json"
    scene_path.write_text(json.dumps(SCENE))
    img = msh.render(SCENE)
    assert img.dtype == np.float32 and img.shape == (16, 24, 3) and np.isfinite(img).all() and img.max() > 0
    assert np.array_equal(msh.render(scene_path), img)
    assert np.array_equal(msh.render(json.dumps(SCENE)), img)
    rc, out, err = cli("render", scene_path, "--out", tmp_path / "cli", "--quiet")
    assert rc == 0, err
    # The CLI writes half-float EXR: equal to the module's image up to half rounding
    c = msh.compare(img, tmp_path / "cli.exr")
    assert c["rmse"] < 2e-3 * max(1.0, float(img.max())) and c["ssim"] > 0.999
    other = msh.render(SCENE, spp=4, seed=3)
    rc, _, _ = cli("render", scene_path, "--out", tmp_path / "b", "--spp", "4", "--quiet")
    rc, out, err = cli("compare", tmp_path / "cli.exr", tmp_path / "b.exr", "--downsample", "2")
    assert rc == 0, err
    assert msh.compare(tmp_path / "cli.exr", tmp_path / "b.exr", downsample=2) == {k: out[k] for k in out}
    assert msh.compare(img, img, diff=tmp_path / "d.png") == {"rmse": 0.0, "ssim": 1.0}
    assert (tmp_path / "d.png").stat().st_size > 0
    assert other.shape == img.shape
    with pytest.raises(ValueError):
        msh.compare(img, img[:8])
    with pytest.raises(ValueError):
        msh.render({"camera": {}})
