"""microshadow: micro-scale direct lighting (microfacet BRDFs, micro-shadowing, LUTs, a reference renderer).

Vectorized numpy bindings of the C++ library (docs/python.md). Every function broadcasts its array
arguments like a numpy ufunc; float32 input gives float32 output, anything else float64; the work runs in
C++ with the GIL released (oneTBB threads for large arrays, bit-identical for any thread count). Bad input
raises ValueError with the message the `microshadow` CLI prints.

    >>> import numpy as np, microshadow as msh
    >>> v = np.linspace(0, 1, 5, dtype=np.float32)
    >>> msh.eval_micro_shadowing("chan-2018", v, 0.5)
"""

from ._core import (  # noqa: F401
    __version__,
    bake_directional_channels,
    bake_micro_shadowing_lut,
    brdf_models,
    brdf_pdf,
    bump_alpha2,
    bump_terminator,
    compare,
    directional_term,
    directional_transport,
    directional_view_term,
    directional_view_transport,
    eval_brdf,
    eval_micro_shadowing,
    load_micro_shadowing_lut,
    micro_shadowing_methods,
    ndf_D,
    ndf_G1,
    ndf_G2,
    ndf_lambda,
    render,
    sample_brdf,
    sample_vndf,
    vndf_pdf,
)

__all__ = [
    "bake_directional_channels",
    "bake_micro_shadowing_lut",
    "brdf_models",
    "brdf_pdf",
    "bump_alpha2",
    "bump_terminator",
    "compare",
    "directional_term",
    "directional_transport",
    "directional_view_term",
    "directional_view_transport",
    "eval_brdf",
    "eval_micro_shadowing",
    "load_micro_shadowing_lut",
    "micro_shadowing_methods",
    "ndf_D",
    "ndf_G1",
    "ndf_G2",
    "ndf_lambda",
    "render",
    "sample_brdf",
    "sample_vndf",
    "vndf_pdf",
]
