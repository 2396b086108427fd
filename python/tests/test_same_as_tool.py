"""localize() gives the C++ tool's answers (pcl_icf_tool --json) to 1e-6."""
import json
import subprocess

import numpy as np
import pytest

import pcl_icf
from conftest import DEMO, SHARED, require


def tool_json(tool, tmp_path, scene, model, *options):
    out = tmp_path / "result.json"
    out.unlink(missing_ok=True)
    run = subprocess.run([tool, str(scene), str(model), "--json", str(out), "--force", "--quiet",
                          *options], check=False)
    assert run.returncode in (0, 1), run  # found, not found
    return json.loads(out.read_text())


def assert_same(result, expected):
    assert result.status == expected["status"]
    assert len(result.clusters) == len(expected["clusters"])
    assert len(result.instances) == len(expected["instances"])
    for got, want in zip(result.instances, expected["instances"]):
        assert got.cluster == want["cluster"]
        np.testing.assert_allclose(got.pose, np.array(want["pose"]), rtol=0, atol=1e-6)
        assert got.confidence == pytest.approx(want["confidence"], abs=1e-9)
        assert got.accepted == want["accepted"]
        assert got.method == want["method"]
        assert got.verification["supported"] == pytest.approx(
            want["verification"]["supported"], abs=1e-9)
        assert len(got.alternatives) == len(want["alternatives"])


def test_bundled_scene(tool, tmp_path, box_model, demo_scene):
    expected = tool_json(tool, tmp_path, DEMO / "tabletop_box5.pcd", DEMO / "box5.ply")
    result = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model,
                              camera=demo_scene.camera_pose)
    assert result.found
    assert_same(result, expected)
    assert result.best is result.instances[0]
    assert result.best.pose.shape == (4, 4)
    assert result.timing["total_ms"] > 0


def test_bundled_scene_copies_and_float64_give_the_same(box_model, demo_scene):
    view = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model)
    copy = pcl_icf.localize(np.array(demo_scene.xyz, dtype=np.float64),
                            rgb=np.ascontiguousarray(demo_scene.rgb), model=box_model)
    np.testing.assert_array_equal(view.best.pose, copy.best.pose)


def test_model_from_arrays_is_the_file(box_model, demo_scene):
    lines = (DEMO / "box5.ply").read_text().splitlines()
    start = lines.index("end_header") + 1
    vertices = np.array([[float(v) for v in line.split()] for line in lines[start:start + 24]])
    faces = np.array([[int(v) for v in line.split()[1:]] for line in lines[start + 24:start + 30]])
    model = pcl_icf.Model(vertices, faces)
    assert model.faces == box_model.faces
    a = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, model)
    b = pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model)
    np.testing.assert_allclose(a.best.pose, b.best.pose, atol=1e-6)


def test_estimate_pose_on_the_bundled_cluster(box_model):
    cluster = pcl_icf.load_scene(str(DEMO / "box5_cluster.pcd"))
    truth = np.loadtxt(DEMO / "box5_truth.txt")
    r = pcl_icf.estimate_pose(cluster.xyz, box_model)
    assert r.accepted, r.status
    assert np.linalg.norm(r.pose[:3, 3] - truth[:3, 3]) < 0.005
    refined = pcl_icf.estimate_pose(cluster.xyz, box_model, guess=r.pose)
    assert refined.method == "guess+icf"
    assert np.linalg.norm(refined.pose[:3, 3] - truth[:3, 3]) < 0.005


YCBV = SHARED / "ycbv-video0000"


def test_ycbv_frame(tool, tmp_path):
    require(YCBV.is_dir(), f"{YCBV} not present")
    scene = YCBV / "scenes" / "ycbv0000_000002.pcd"
    mesh = YCBV / "models" / "ycb_009_gelatin_box.ply"
    expected = tool_json(tool, tmp_path, scene, mesh)
    loaded = pcl_icf.load_scene(str(scene))
    result = pcl_icf.localize(loaded.xyz, loaded.rgb, pcl_icf.Model.from_file(str(mesh)),
                              camera=loaded.camera_pose)
    assert_same(result, expected)


def test_the_cameras_noise_is_the_tools_in_any_order(tool, tmp_path, box_model, demo_scene):
    # The Box5 pose fits within the limits with a real camera's low-frequency error and with a
    # simulated camera's noise alone, so it is found either way; the tool and Python give the
    # same hypotheses, residuals and decisions in any order of the options.
    scene, mesh = DEMO / "tabletop_box5.pcd", DEMO / "box5.ply"

    def localize(**kw):
        return pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model,
                                camera=demo_scene.camera_pose, **kw)

    def residuals(result):
        return [c.verification["residual"] for c in result.clusters]

    def tool_residuals(*options):
        want = tool_json(tool, tmp_path, scene, mesh, *options)
        return [c["verification"]["residual"] for c in want["clusters"]], want

    simulated = localize(depth_systematic=0.0, mesh_accuracy=0.001)
    assert simulated.found
    want_residuals, want = tool_residuals("--set", "depth_systematic=0", "--mesh-accuracy", "0.001")
    assert_same(simulated, want)
    assert residuals(simulated) == pytest.approx(want_residuals, abs=1e-9)
    want_residuals, want = tool_residuals("--mesh-accuracy", "0.001", "--set", "depth_systematic=0")
    assert residuals(simulated) == pytest.approx(want_residuals, abs=1e-9)
    default = localize()
    assert default.found
    # The unit of the residual: the simulated camera's is smaller, so its residuals are larger.
    assert residuals(simulated)[0] > residuals(default)[0]


def crate_model(tmp_path):
    """A 40 x 30 x 20 cm box, written as PLY: not on the demo table."""
    corners = [(x, y, z) for x in (-0.2, 0.2) for y in (-0.15, 0.15) for z in (-0.1, 0.1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    path = tmp_path / "crate.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 6\n"
                    "property list uchar int vertex_indices\nend_header\n" +
                    "".join(f"{x} {y} {z}\n" for x, y, z in corners) +
                    "".join(f"4 {a} {b} {c} {d}\n" for a, b, c, d in quads))
    return path


def test_localize_many_is_the_tools(tool, tmp_path, box_model, demo_scene):
    # The demo's box and a crate that is not there, in one call, as the tool's several-MODEL
    # run gives them.
    crate = crate_model(tmp_path)
    out = tmp_path / "frame.json"
    run = subprocess.run([tool, str(DEMO / "tabletop_box5.pcd"), str(DEMO / "box5.ply"),
                          str(crate), "--json", str(out), "--quiet"], check=False)
    assert run.returncode == 0, run
    expected = json.loads(out.read_text())
    result = pcl_icf.localize_many(demo_scene.xyz, [box_model, pcl_icf.Model.from_file(str(crate))],
                                   rgb=demo_scene.rgb, camera=demo_scene.camera_pose,
                                   names=["box5.ply", "crate.ply"])
    assert result.status == expected["status"] == "Found"
    assert [o.found for o in result.objects] == [True, False]
    for got, want in zip(result.objects, expected["objects"]):
        assert_same(got, want)
    assert [(k, c.cluster) for k, c in result.instances] == [
        (i["object"], i["cluster"]) for i in expected["instances"]]
    assert result.timing["scene_ms"] > 0


def test_localize_many_bad_lists(box_model, demo_scene):
    with pytest.raises(ValueError, match="empty"):
        pcl_icf.localize_many(demo_scene.xyz, [])
    with pytest.raises(TypeError, match="models\\[1\\]"):
        pcl_icf.localize_many(demo_scene.xyz, [box_model, "box5.ply"])
    with pytest.raises(ValueError, match="one entry per model"):
        pcl_icf.localize_many(demo_scene.xyz, [box_model], counts=[1, 2])
    with pytest.raises(ValueError, match="at least 1"):
        pcl_icf.localize_many(demo_scene.xyz, [box_model], counts=[0])


def test_prepared_model_files_are_the_tools(tool, tmp_path, box_model, demo_scene):
    """A model saved from Python loads in the tool, one the tool prepared loads in Python, and
    each gives the mesh's own pose; a file in other units or a corrupt one is refused."""
    saved = tmp_path / "py.icfmodel"
    box_model.save(str(saved))
    expected = tool_json(tool, tmp_path, DEMO / "tabletop_box5.pcd", DEMO / "box5.ply",
                         "--no-cache")
    assert_same(pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model), expected)
    from_tool = tool_json(tool, tmp_path, DEMO / "tabletop_box5.pcd", saved, "--no-cache")
    assert from_tool["model_info"]["from_prepared_file"]
    assert_same(pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, box_model), from_tool)

    prepared = tmp_path / "tool.icfmodel"
    subprocess.run([tool, "--prepare", str(DEMO / "box5.ply"), "-o", str(prepared), "-q"],
                   check=True)
    model = pcl_icf.Model.from_file(str(prepared))
    assert model.source == "prepared file"
    assert model.faces == box_model.faces
    assert_same(pcl_icf.localize(demo_scene.xyz, demo_scene.rgb, model), expected)

    with pytest.raises(pcl_icf.ModelFileError, match="another mesh or other parameters"):
        pcl_icf.Model.from_file(str(prepared), units="mm")
    corrupt = tmp_path / "corrupt.icfmodel"
    data = bytearray(prepared.read_bytes())
    data[len(data) // 2] ^= 0x40
    corrupt.write_bytes(bytes(data))
    with pytest.raises(pcl_icf.ModelFileError, match="checksum"):
        pcl_icf.Model.from_file(str(corrupt))


def test_from_file_uses_the_cache(tmp_path, monkeypatch):
    """The second from_file of a mesh reads the cache ($XDG_CACHE_HOME/pcl_icf); cache=False
    neither reads nor writes it."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "home"))
    mesh = str(DEMO / "box5.ply")
    assert pcl_icf.Model.from_file(mesh).source == "built"
    assert pcl_icf.Model.from_file(mesh).source == "cache"
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "other"))
    assert pcl_icf.Model.from_file(mesh, cache=False).source == "built"
    assert not (tmp_path / "other").exists()
