"""The example scripts run and find the box (the Open3D one only where python3-open3d is)."""
import os
import subprocess
import sys

import pytest

import pcl_icf
from conftest import SOURCE


def run_example(name):
    env = dict(os.environ)
    module_dir = os.path.dirname(pcl_icf.__file__)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (module_dir, env.get("PYTHONPATH")) if p)
    return subprocess.run([sys.executable, str(SOURCE / "python" / "examples" / name)],
                          env=env, capture_output=True, text=True, timeout=300)


def test_localize_demo():
    run = run_example("localize_demo.py")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Found" in run.stdout


def test_open3d_demo():
    pytest.importorskip("open3d")
    run = run_example("open3d_demo.py")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Found" in run.stdout
