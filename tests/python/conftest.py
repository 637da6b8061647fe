"""Shared fixtures of the Python tests: the module (from PYTHONPATH, set by ctest to build/python) and the
CLI (MSH_CLI, set by ctest; else build/bin/microshadow) to compare against."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def cli_path():
    p = os.environ.get("MSH_CLI") or str(ROOT / "build" / "bin" / "microshadow")
    return p if os.path.exists(p) else None


@pytest.fixture(scope="session")
def cli():
    """run(*args) -> (returncode, parsed JSON or None, stderr) of one CLI invocation."""
    path = cli_path()
    if path is None:
        pytest.skip("the microshadow CLI is not built")

    def run(*args):
        r = subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=120)
        out = json.loads(r.stdout) if r.returncode == 0 and r.stdout.strip().startswith("{") else None
        return r.returncode, out, r.stderr.strip()

    return run


@pytest.fixture(scope="session")
def small_lut(tmp_path_factory):
    """A small azimuth-aware cone-layout table baked through the module (a few seconds at most), as .npy."""
    import microshadow as msh

    path = tmp_path_factory.mktemp("lut") / "small.npy"
    table, side = msh.bake_micro_shadowing_lut(layout="cone", harmonics=3, n_vis=12, n_nl=10, n_nv=6,
                                               n_rough=4, samples=256, phi_nodes=8, out=path)
    return path, table, side
