"""Bad arrays and parameters raise ValueError (TypeError for a wrong keyword or type) naming the
parameter; the C++ validate() messages come through unchanged."""
import threading

import numpy as np
import pytest

import pcl_icf
from conftest import DEMO

GOOD = np.random.default_rng(1).uniform(-0.1, 0.1, (500, 3)).astype(np.float32)


@pytest.mark.parametrize("xyz, match", [
    (np.zeros((10, 2), np.float32), "scene_xyz: shape"),
    (np.zeros((10,), np.float32), "scene_xyz: shape"),
    (np.zeros((10, 3), np.int32), "scene_xyz: dtype"),
    (np.zeros((10, 3), np.float16), "scene_xyz: dtype"),
    (np.zeros((0, 3), np.float32), "scene_xyz: no points"),
    (np.full((10, 3), np.nan, np.float32), "scene_xyz: no finite point"),
    (np.full((4, 5, 3), np.inf), "scene_xyz: no finite point"),
    ([[0.0, 0.0, 1.0]], "scene_xyz: expected a numpy array"),
])
def test_bad_scene(box_model, xyz, match):
    with pytest.raises(ValueError, match=match):
        pcl_icf.localize(xyz, box_model)


@pytest.mark.parametrize("rgb, match", [
    (np.zeros((500, 3), np.float32), "rgb: dtype"),
    (np.zeros((499, 3), np.uint8), "rgb: shape"),
    (np.zeros((500, 4), np.uint8), "rgb: shape"),
])
def test_bad_rgb(box_model, rgb, match):
    with pytest.raises(ValueError, match=match):
        pcl_icf.localize(GOOD, rgb, box_model)


@pytest.mark.parametrize("params, match", [
    (dict(max_instances=0), "max_instances"),
    (dict(min_confidence=1.5), "min_confidence"),
    (dict(full_evidence=0.0), "full_evidence"),
    (dict(max_conflict=1.5), "max_conflict"),
    (dict(max_continuation=-0.1), "max_continuation"),
    (dict(cluster_tolerance=-1.0), "cluster.tolerance"),
    (dict(strategy="fastest"), "strategy"),
    (dict(fallback="sometimes"), "fallback"),
    (dict(intrinsics=dict(fx=-1.0)), "fx"),
    (dict(intrinsics=dict(focal=1.0)), "intrinsics"),
    (dict(camera=np.eye(3)), "camera"),
    (dict(camera=np.full((4, 4), np.nan)), "camera"),
    (dict(camera=np.diag([1.0, 1.0, -1.0, 1.0])), "camera"),
])
def test_bad_parameters(box_model, params, match):
    with pytest.raises(ValueError, match=match):
        pcl_icf.localize(GOOD, box_model, **params)


@pytest.mark.parametrize("value", [0.0, 0.005])
def test_min_confidence_below_refine_min_confidence_is_valid(box_model, demo_scene, value):
    """A calibration asks for every hypothesis (min_confidence 0, below refine_min_confidence
    0.01): valid, and the bundled box is still the best, at the default's pose (the same
    cluster and seeded search; 0.1 mm for float round-off)."""
    default = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model)
    r = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model, min_confidence=value)
    assert default.found and r.found
    assert np.abs(r.best.pose[:3, 3] - default.best.pose[:3, 3]).max() < 1e-4
    assert r.best.confidence == pytest.approx(default.best.confidence, abs=1e-6)


def test_unknown_or_mistyped_keyword(box_model):
    with pytest.raises(TypeError, match="max_instance"):
        pcl_icf.localize(GOOD, box_model, max_instance=2)
    with pytest.raises(TypeError, match="seed"):
        pcl_icf.localize(GOOD, box_model, seed="x")
    with pytest.raises(TypeError, match="model"):
        pcl_icf.localize(GOOD, GOOD)
    with pytest.raises(TypeError, match="exact_mesh is gone.*mesh_accuracy"):
        pcl_icf.localize(GOOD, box_model, exact_mesh=True)
    with pytest.raises(TypeError, match="exact_mesh is gone.*depth_systematic"):
        pcl_icf.Tracker(exact_mesh=True)


def test_bad_estimate_pose(box_model):
    with pytest.raises(ValueError, match="cluster_xyz: no finite point"):
        pcl_icf.estimate_pose(np.full((5, 3), np.nan), box_model)
    with pytest.raises(ValueError, match="cluster_xyz: dtype"):
        pcl_icf.estimate_pose(np.zeros((5, 3), np.int64), box_model)
    with pytest.raises(ValueError, match="guess"):
        pcl_icf.estimate_pose(GOOD, box_model, guess=np.eye(4) * 2)
    with pytest.raises(ValueError, match="max_rmse"):
        pcl_icf.estimate_pose(GOOD, box_model, max_rmse=-1.0)


@pytest.mark.parametrize("vertices, faces, match", [
    (np.zeros((4, 2)), np.array([[0, 1, 2]]), "vertices: shape"),
    (np.zeros((4, 3), np.int32), np.array([[0, 1, 2]]), "vertices: dtype"),
    (np.zeros((0, 3)), np.array([[0, 1, 2]]), "vertices: no points"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]]), np.array([[0, 1, 2]]), "vertices: row 2"),
    (np.eye(3), np.array([[0, 1, 3]]), "faces: row 0"),
    (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "faces: dtype"),
    (np.eye(3), np.array([[0, 1]]), "faces: shape"),
    (np.eye(3), np.zeros((0, 3), np.int64), "faces: no faces"),
])
def test_bad_mesh(vertices, faces, match):
    with pytest.raises(ValueError, match=match):
        pcl_icf.Model(vertices, faces)


def test_bad_files():
    with pytest.raises(ValueError, match="units"):
        pcl_icf.Model.from_file(str(DEMO / "box5.ply"), units="inch")
    with pytest.raises(OSError):
        pcl_icf.Model.from_file(str(DEMO / "missing.ply"))
    with pytest.raises(OSError):
        pcl_icf.load_scene(str(DEMO / "missing.pcd"))


def test_defaults_are_the_cpp_defaults():
    d = pcl_icf.localize_defaults()
    assert d["min_confidence"] == 0.875
    assert d["max_instances"] == 1
    assert d["seed"] == 42
    assert d["strategy"] == "fast"
    assert d["intrinsics"] is None
    assert set(pcl_icf.estimate_pose_defaults()) <= set(d)


def test_threads_run_together(box_model, demo_scene):
    """The GIL is released while the C++ works: two threads, the same answers."""
    results = [None, None]

    def work(i):
        results[i] = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model, threads=1)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    np.testing.assert_array_equal(results[0].best.pose, results[1].best.pose)


def test_scene_views_are_read_only(demo_scene):
    assert not demo_scene.xyz.flags.writeable
    assert demo_scene.xyz.base is not None
    assert demo_scene.rgb.shape == demo_scene.xyz.shape
