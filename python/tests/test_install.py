"""`cmake --install`: the package lands where Debian's Python finds it, and finds the installed program."""
import os
import subprocess
import sys

import pytest

import slipfront


def test_installed_package_finds_the_installed_program(tmp_path):
    build, cmake = os.environ.get("SLIPFRONT_BUILD_DIR"), os.environ.get("SLIPFRONT_CMAKE_COMMAND")
    if not build or not cmake:
        pytest.skip("needs the build tree (run from ctest)")
    prefix = tmp_path / "prefix"
    subprocess.run([cmake, "--install", build, "--prefix", str(prefix)], check=True, capture_output=True)
    site = prefix / "lib" / ("python3.%d" % sys.version_info.minor) / "dist-packages"
    assert (site / "slipfront" / "__init__.py").is_file()
    env = {k: v for k, v in os.environ.items() if k not in ("SLIPFRONT_PROGRAM", "PYTHONPATH")}
    env["PYTHONPATH"] = str(site)
    script = ("import slipfront, slipfront._program as p; print(slipfront.__file__); print(p.find_program()); "
              "print(hasattr(slipfront, 'Simulation'))")
    out = subprocess.run(["/usr/bin/python3", "-c", script], env=env, cwd=tmp_path, check=True,
                         capture_output=True, text=True).stdout.splitlines()
    assert out[0] == str(site / "slipfront" / "__init__.py")
    assert out[1] == str(prefix / "bin" / "slipfront")
    assert out[2] == str(hasattr(slipfront, "Simulation"))  # the in-process module installed when it was built
