# Type stub of the microshadow package (the functions live in the C++ extension microshadow._core).
# Array arguments accept anything numpy.asarray accepts (numbers, sequences, arrays) and broadcast like ufuncs;
# the result is float32 when the array inputs are float32, else float64 (a numpy scalar for scalar input).
import os
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
FloatArray = Union[npt.NDArray[np.float32], npt.NDArray[np.float64], np.floating[Any]]
PathLike = Union[str, "os.PathLike[str]"]
NdfName = Literal["ggx", "beckmann", "blinn-phong", "gtr"]

def micro_shadowing_methods(details: bool = False) -> list[Any]: ...
def eval_micro_shadowing(
    method: str,
    visibility: ArrayLike,
    ndotl: ArrayLike,
    ndotv: ArrayLike = 1.0,
    roughness: ArrayLike = 0.5,
    phi: Optional[ArrayLike] = None,
    samples: Optional[int] = None,
    seed: int = 1,
    g2: Literal["height-correlated", "uncorrelated"] = "height-correlated",
    lut: Optional[PathLike] = None,
    roughness_y: Optional[ArrayLike] = None,
    path: Literal["auto", "registry"] = "auto",
    lobe: Optional[Literal["diffuse", "specular"]] = None,
) -> FloatArray: ...
def bump_terminator(
    method: Literal["conty-2019", "chiang-2019", "none"],
    geometric_normal: ArrayLike,
    shading_normal: ArrayLike,
    light: ArrayLike,
    hemisphere_test: bool = False,
) -> FloatArray: ...
def bump_alpha2(geometric_normal: ArrayLike, shading_normal: ArrayLike) -> FloatArray: ...
def directional_transport(channels: ArrayLike, light: ArrayLike) -> FloatArray: ...
def directional_term(channels: ArrayLike, light: ArrayLike, normal: ArrayLike) -> FloatArray: ...
def directional_view_transport(channels: ArrayLike, light: ArrayLike, view: ArrayLike) -> FloatArray: ...
def directional_view_term(
    channels: ArrayLike, light: ArrayLike, view: ArrayLike, normal: ArrayLike
) -> FloatArray: ...
def bake_directional_channels(
    height: ArrayLike, depth_texels: float, azimuths: int = 32, max_distance: float = 0.0, view: bool = False
) -> npt.NDArray[np.float32]: ...
def ndf_D(
    ndf: NdfName, m: ArrayLike, alpha: ArrayLike = 0.5, alpha_y: Optional[ArrayLike] = None, gamma: float = 2.0
) -> FloatArray: ...
def ndf_lambda(
    ndf: NdfName, w: ArrayLike, alpha: ArrayLike = 0.5, alpha_y: Optional[ArrayLike] = None, gamma: float = 2.0
) -> FloatArray: ...
def ndf_G1(
    ndf: NdfName,
    w: ArrayLike,
    m: Optional[ArrayLike] = None,
    alpha: ArrayLike = 0.5,
    alpha_y: Optional[ArrayLike] = None,
    gamma: float = 2.0,
) -> FloatArray: ...
def ndf_G2(
    ndf: NdfName,
    wo: ArrayLike,
    wi: ArrayLike,
    m: Optional[ArrayLike] = None,
    form: Literal[
        "height-correlated", "separable", "uncorrelated", "direction-correlated", "height-direction-correlated"
    ] = "height-correlated",
    lambda_phi: Literal["ashikhmin", "van-ginneken"] = "ashikhmin",
    alpha: ArrayLike = 0.5,
    alpha_y: Optional[ArrayLike] = None,
    gamma: float = 2.0,
) -> FloatArray: ...
def vndf_pdf(
    ndf: NdfName,
    w: ArrayLike,
    m: ArrayLike,
    alpha: ArrayLike = 0.5,
    alpha_y: Optional[ArrayLike] = None,
    gamma: float = 2.0,
) -> FloatArray: ...
def sample_vndf(
    ndf: Literal["ggx", "beckmann"],
    w: ArrayLike,
    u: ArrayLike,
    alpha: ArrayLike = 0.5,
    alpha_y: Optional[ArrayLike] = None,
    sampler: Literal["spherical-caps", "heitz-2018"] = "spherical-caps",
) -> FloatArray: ...
def brdf_models() -> list[dict[str, Any]]: ...
def eval_brdf(model: str, wo: ArrayLike, wi: ArrayLike, **params: Any) -> FloatArray: ...
def brdf_pdf(model: str, wo: ArrayLike, wi: ArrayLike, **params: Any) -> FloatArray: ...
def sample_brdf(
    model: str, wo: ArrayLike, u: ArrayLike, **params: Any
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], FloatArray]: ...
def bake_micro_shadowing_lut(
    layout: Literal["cone", "seed"] = "cone",
    harmonics: int = 0,
    two_d: bool = False,
    n_vis: Optional[int] = None,
    n_nl: Optional[int] = None,
    n_nv: Optional[int] = None,
    n_rough: Optional[int] = None,
    roughness: Optional[Sequence[float]] = None,
    roughness_range: Optional[Tuple[float, float]] = None,
    samples: Optional[int] = None,
    phi_nodes: int = 16,
    seed: int = 1,
    out: Optional[PathLike] = None,
) -> Tuple[npt.NDArray[np.float32], dict[str, Any]]: ...
def load_micro_shadowing_lut(
    path: PathLike, roughness: Optional[Sequence[float]] = None, harmonics: Optional[int] = None
) -> Tuple[npt.NDArray[np.float32], dict[str, Any]]: ...
@overload
def render(
    scene: Union[PathLike, Mapping[str, Any]],
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    method: Optional[str] = None,
    seed: Optional[int] = None,
    lut: Optional[str] = None,
    asset_dir: Optional[PathLike] = None,
    std_error: Literal[False] = False,
) -> npt.NDArray[np.float32]: ...
@overload
def render(
    scene: Union[PathLike, Mapping[str, Any]],
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    method: Optional[str] = None,
    seed: Optional[int] = None,
    lut: Optional[str] = None,
    asset_dir: Optional[PathLike] = None,
    *,
    std_error: Literal[True],
) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]: ...
def compare(
    a: Union[PathLike, ArrayLike], b: Union[PathLike, ArrayLike], exposure: float = 0.0, downsample: int = 1,
    diff: Optional[PathLike] = None,
) -> dict[str, float]: ...
