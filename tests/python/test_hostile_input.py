"""Hostile input (issue 35, item 6): every exported function refuses NaN, +-Inf and out-of-domain values with
a ValueError naming the argument, never returns a number for them. A table of (function, good arguments);
each argument in turn is replaced by bad values. A function exported without an entry here fails
test_every_function_is_covered."""
import inspect

import numpy as np
import pytest

import microshadow as msh

NAN, INF = float("nan"), float("inf")
CH9 = [0, 0, 0, 1, 0, 0, 0, 0, 0.0]
CH21 = CH9 + [0.0] * 12
IMG = np.full((8, 8, 3), 0.5)

# name -> (function, positional arguments, keyword arguments, {argument: [bad values]})
DIR_BAD = [[NAN, 0, 1], [0, INF, 1], [0, 0, -INF], [0, 0, 0]]  # non-finite or zero directions
U_BAD = [[NAN, 0.5], [0.5, INF], [2, 0.5], [0.5, -1], [1.0, 0.5]]  # uniforms outside [0, 1)
NUM_BAD = [NAN, INF, -INF]
CASES = {
    "bump_terminator": (msh.bump_terminator, ["conty-2019", [0, 0, 1], [0.3, 0, 1], [1, 0, 0.2]], {},
                        {1: DIR_BAD, 2: DIR_BAD, 3: DIR_BAD}),
    "bump_alpha2": (msh.bump_alpha2, [[0, 0, 1], [0.3, 0, 1]], {}, {0: DIR_BAD, 1: DIR_BAD}),
    "directional_transport": (msh.directional_transport, [CH9, [0, 0.6, 0.8]], {},
                              {0: [CH9[:3] + [NAN] + CH9[4:], CH9[:8] + [INF]], 1: DIR_BAD}),
    "directional_term": (msh.directional_term, [CH9, [0, 0.6, 0.8], [0, 0, 1]], {},
                         {0: [CH9[:3] + [NAN] + CH9[4:]], 1: DIR_BAD, 2: DIR_BAD}),
    "directional_view_transport": (msh.directional_view_transport, [CH21, [0, 0.6, 0.8], [0, 0, 1]], {},
                                   {0: [CH21[:20] + [NAN], CH21[:10] + [-INF] + CH21[11:]], 1: DIR_BAD,
                                    2: DIR_BAD}),
    "directional_view_term": (msh.directional_view_term, [CH21, [0, 0.6, 0.8], [0, 0, 1], [0, 0, 1]], {},
                              {0: [CH21[:20] + [NAN]], 1: DIR_BAD, 2: DIR_BAD, 3: DIR_BAD}),
    "bake_directional_channels": (msh.bake_directional_channels, [np.full((8, 8), 0.5), 4.0], {"azimuths": 8},
                                  {0: [np.where(np.eye(8) > 0, NAN, 0.5), np.full((8, 8), INF)],
                                   1: NUM_BAD + [0.0, -1.0], "max_distance": NUM_BAD}),
    "ndf_D": (msh.ndf_D, ["ggx", [0, 0.6, 0.8]], {"alpha": 0.5},
              {1: DIR_BAD, "alpha": NUM_BAD + [5.0], "gamma": NUM_BAD}),
    "ndf_lambda": (msh.ndf_lambda, ["beckmann", [0, 0.6, 0.8]], {"alpha": 0.5, "alpha_y": 0.3},
                   {1: DIR_BAD, "alpha": NUM_BAD, "alpha_y": NUM_BAD + [-1.0]}),
    "ndf_G1": (msh.ndf_G1, ["ggx", [0, 0.6, 0.8]], {"m": [0, 0, 1]},
               {1: DIR_BAD, "m": DIR_BAD, "alpha": NUM_BAD}),
    "ndf_G2": (msh.ndf_G2, ["ggx", [0, 0.6, 0.8], [0.6, 0, 0.8]], {"m": [0, 0, 1], "form": "separable"},
               {1: DIR_BAD, 2: DIR_BAD, "m": DIR_BAD, "alpha": NUM_BAD}),
    "vndf_pdf": (msh.vndf_pdf, ["ggx", [0, 0.6, 0.8], [0, 0, 1]], {}, {1: DIR_BAD, 2: DIR_BAD, "alpha": NUM_BAD}),
    "sample_vndf": (msh.sample_vndf, ["ggx", [0, 0.6, 0.8], [0.25, 0.5]], {},
                    {1: DIR_BAD, 2: U_BAD, "alpha": NUM_BAD}),
    "eval_brdf": (msh.eval_brdf, ["ggx", [0, 0.6, 0.8], [0.6, 0, 0.8]], {"roughness": 0.5},
                  {1: DIR_BAD, 2: DIR_BAD, "roughness": NUM_BAD + [2.0]}),
    "brdf_pdf": (msh.brdf_pdf, ["ggx", [0, 0.6, 0.8], [0.6, 0, 0.8]], {}, {1: DIR_BAD, 2: DIR_BAD}),
    "sample_brdf": (msh.sample_brdf, ["ggx", [0, 0.6, 0.8], [0.25, 0.5]], {}, {1: DIR_BAD, 2: U_BAD}),
    "eval_micro_shadowing": (msh.eval_micro_shadowing, ["chan-2018", 0.5, 0.5], {"ndotv": 0.5, "roughness": 0.5},
                             {1: NUM_BAD + [2.0], 2: NUM_BAD + [-0.5], "ndotv": NUM_BAD, "roughness": NUM_BAD}),
    "eval_micro_shadowing[generic-vndf]": (msh.eval_micro_shadowing, ["generic-vndf", 0.5, 0.5],
                                           {"phi": 1.0, "samples": 16, "roughness_y": 0.4},
                                           {"phi": NUM_BAD + [4.0], "roughness_y": NUM_BAD + [2.0]}),
    "compare": (msh.compare, [IMG, IMG], {},
                {0: [np.where(np.eye(8)[..., None] > 0, NAN, IMG), np.full((8, 8, 3), INF)],
                 1: [np.full((8, 8, 3), -INF)], "exposure": NUM_BAD}),
    "bake_micro_shadowing_lut": (msh.bake_micro_shadowing_lut, [],
                                 {"layout": "seed", "n_vis": 4, "n_nl": 4, "n_nv": 2, "roughness": [0.5],
                                  "samples": 16},
                                 {"roughness": [[NAN], [INF], [2.0]]}),
}
# Functions without numeric array input (names, files, scenes) and what covers them instead.
NOT_NUMERIC = {
    "micro_shadowing_methods": "no numeric input",
    "brdf_models": "no numeric input",
    "load_micro_shadowing_lut": "a file: the readers' checks (tests/test_io_errors.cpp); roughness below",
    "render": "a scene: the scene parser's checks (tests/test_render*.cpp)",
}


def test_every_function_is_covered():
    exported = {n for n, f in vars(msh).items() if callable(f) and not n.startswith("_") and
                not inspect.isclass(f) and not inspect.ismodule(f)}
    missing = exported - {n.split("[")[0] for n in CASES} - set(NOT_NUMERIC)
    assert not missing, f"exported functions without a hostile-input case: {sorted(missing)}"


def _bad_calls():
    for name, (f, args, kw, bad) in CASES.items():
        for where, values in bad.items():
            for v in values:
                yield pytest.param(name, where, v, id=f"{name}-{where}-{v!r}"[:80])


@pytest.mark.parametrize("name, where, value", list(_bad_calls()))
def test_bad_value_raises(name, where, value):
    f, args, kw, _ = CASES[name]
    f(*args, **kw)  # the good arguments are accepted
    args, kw = list(args), dict(kw)
    if isinstance(where, int):
        args[where] = value
    else:
        kw[where] = value
    with pytest.raises(ValueError):
        out = f(*args, **kw)
        print(out)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_first_bad_element_is_reported(dtype):
    # an array with a NaN at element 7 and an Inf at element 100000: the message names element 7
    w = np.tile(np.array([0, 0.6, 0.8], dtype=dtype), (200000, 1))
    w[7, 1], w[100000, 2] = np.nan, np.inf
    with pytest.raises(ValueError, match=r"w must be .*element 7\b"):
        msh.ndf_lambda("ggx", w, alpha=0.5)
    u = np.full((200000, 2), 0.5, dtype=dtype)
    u[5, 0] = 1.0
    with pytest.raises(ValueError, match=r"u must be in \[0, 1\).*element 5\b"):
        msh.sample_vndf("ggx", [0, 0, 1], u)


def test_load_lut_roughness_override(tmp_path):
    path = tmp_path / "seed.npy"
    msh.bake_micro_shadowing_lut(layout="seed", n_vis=4, n_nl=4, n_nv=2, roughness=[0.5], samples=16, out=path)
    msh.load_micro_shadowing_lut(path, roughness=[0.25])
    for r in ([NAN], [INF], [-1.0]):
        with pytest.raises(ValueError):
            msh.load_micro_shadowing_lut(path, roughness=r)
