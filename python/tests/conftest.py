"""Shared fixtures: the module (from PYTHONPATH: ctest sets it to the build folder), the data
folders and the C++ tool to compare with (PCL_ICF_TOOL, set by ctest)."""
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("PCL_ICF_SOURCE_DIR",
                                     pathlib.Path(__file__).resolve().parents[2]))
SHARED = pathlib.Path(os.environ.get("PCL_ICF_SHARED_DATA", SOURCE.parent / "shared" / "data"))
DEMO = SOURCE / "data" / "demo"


def require(condition, reason):
    """Skip when \a condition fails, but fail under CI (CI=true has the data and the tool), as
    the C++ tests do (test/test_paths.h)."""
    if not condition:
        if os.environ.get("CI") == "true":
            pytest.fail(reason + " (CI=true: required)")
        pytest.skip(reason)


@pytest.fixture(scope="session")
def box_model():
    import pcl_icf
    return pcl_icf.Model.from_file(str(DEMO / "box5.ply"))


@pytest.fixture(scope="session")
def demo_scene():
    import pcl_icf
    return pcl_icf.load_scene(str(DEMO / "tabletop_box5.pcd"))


@pytest.fixture(scope="session")
def tool():
    path = os.environ.get("PCL_ICF_TOOL") or str(SOURCE / "build/release/tools/pcl_icf_tool")
    require(os.access(path, os.X_OK), "pcl_icf_tool not built")
    return path
