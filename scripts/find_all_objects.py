#!/usr/bin/python3
"""Every real annotated frame searched for all its meshed objects and absent distractors in one
call (pcl_icf_tool SCENE MODEL MODEL...), beside one call per object, scored with the suites'
rule (scripts/real_scoring.py): objects found right, wrong poses, false poses of the absent
models, and the localization time of the one call against the sum of the single ones (models
prepared in both: their preparation is not counted).

  scripts/find_all_objects.py [--tool PATH] [--data DIR] [--no-singles] [--frames N]

The frames: ../shared/data/ycbv-video0000 (nine frames at 0.55 m, two meshed objects),
ycbv-video0001 (five at 1 m, four), the YCB-V frame (two). Four distractors a frame, meshes of
objects that are not in it: the other video's, the potted meat can and the Stanford bunny.
Exit 0 when the one call finds at least as many as the single calls and gives no false pose,
1 otherwise, 2 on bad input."""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

from real_scoring import Scorer


def video_frames(root):
    """(scene, [(mesh, truth or None)]) per frame of a ycbv-video folder."""
    frames = {}
    for gt_path in sorted((root / "cases").glob("*/gt.json")):
        gt = json.loads(gt_path.read_text())
        case = json.loads((gt_path.parent / "case.json").read_text())
        scene = (gt_path.parent / case["scene"]).resolve()
        frames[gt["frame"]] = (scene, [((gt_path.parent / o["model"]).resolve(), o["pose"])
                                       for o in gt["objects"]])
    return [frames[k] for k in sorted(frames)]


def ycbv_frame(root):
    gt = json.loads((root / "gt.json").read_text())
    return (root / gt["scene"]).resolve(), [((root / o["mesh"]).resolve(),
                                            o["pose_model_to_camera"]) for o in gt["objects"]]


def run_tool(tool, scene, meshes, out):
    """The tool's JSON for \a meshes in \a scene (one MODEL: the single call's document)."""
    cmd = [tool, str(scene), *map(str, meshes), "--json", str(out), "-f", "-q"]
    code = subprocess.run(cmd).returncode
    if code == 2:
        raise SystemExit(f"{' '.join(cmd)}: exit 2")
    return json.loads(out.read_text())


def poses_of(document):
    """The instance poses of each model of a one-call or single-call document."""
    if "objects" in document:
        return [[np.array(i["pose"]) for i in o["instances"]] for o in document["objects"]]
    return [[np.array(i["pose"]) for i in document["instances"]]]


def main():
    here = pathlib.Path(__file__).resolve().parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tool", default=str(here.parent / "build/release/tools/pcl_icf_tool"))
    parser.add_argument("--data", default=str(here.parent.parent / "shared/data"))
    parser.add_argument("--no-singles", action="store_true", help="only the one call")
    parser.add_argument("--frames", type=int, default=0, help="at most N frames per dataset")
    args = parser.parse_args()
    data = pathlib.Path(args.data)
    v0, v1 = data / "ycbv-video0000", data / "ycbv-video0001"
    if not (v0 / "cases").is_dir() or not (v1 / "cases").is_dir():
        print(f"no ycbv-video0000/0001 under {data}", file=sys.stderr)
        return 2
    meshes0 = sorted((v0 / "models").glob("*.ply"))
    meshes1 = sorted((v1 / "models").glob("*.ply"))
    potted = data / "ycbv/010_potted_meat_can_textured.obj"
    bunny = data / "meshes/bunny.ply"
    suites = [("ycbv-video0000", video_frames(v0), meshes1),
              ("ycbv-video0001", video_frames(v1), meshes0 + [potted, bunny]),
              ("ycbv frame", [ycbv_frame(data / "ycbv")], meshes0 + meshes1[1:2] + meshes1[3:])]
    scorers = {}
    totals = {"one": [0, 0, 0], "single": [0, 0, 0]}  # right, wrong, false
    present = absent = 0
    one_ms, single_ms = [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "result.json"
        for suite, frames, extra in suites:
            for scene, objects in frames[: args.frames or None]:
                # A distractor that is one of the frame's objects is not absent.
                names = {m.name for m, _ in objects}
                distractors = [m for m in extra if m.name not in names][:4]
                meshes = [m for m, _ in objects] + distractors
                truths = [t for _, t in objects] + [None] * len(distractors)
                present += len(objects)
                absent += len(distractors)
                calls = {"one": [run_tool(args.tool, scene, meshes, out)]}
                if not args.no_singles:
                    calls["single"] = [run_tool(args.tool, scene, [m], out) for m in meshes]
                line = []
                for how, documents in calls.items():
                    found = sum((poses_of(d) for d in documents), [])
                    ms = sum(d["timing_ms"]["localization"] for d in documents)
                    (one_ms if how == "one" else single_ms).append(ms)
                    right = wrong = false = 0
                    for mesh, truth, poses in zip(meshes, truths, found):
                        scorer = scorers.setdefault(mesh, Scorer(mesh))
                        if truth is None:
                            false += len(poses)
                        elif poses:
                            ok = scorer.score(poses[0], truth)[0]
                            right += ok
                            wrong += not ok
                    for k, v in enumerate((right, wrong, false)):
                        totals[how][k] += v
                    line.append(f"{how}: {right}/{len(objects)} right, {wrong} wrong, "
                                f"{false}/{len(distractors)} false, {ms:.0f} ms")
                print(f"{suite} {scene.stem}: " + "; ".join(line), flush=True)
    print(f"one call:     {totals['one'][0]}/{present} right, {totals['one'][1]} wrong, "
          f"{totals['one'][2]}/{absent} false poses, median {np.median(one_ms):.0f} ms per frame")
    ok = totals["one"][1] == 0 and totals["one"][2] == 0
    if single_ms:
        print(f"single calls: {totals['single'][0]}/{present} right, {totals['single'][1]} "
              f"wrong, {totals['single'][2]}/{absent} false poses, median "
              f"{np.median(single_ms):.0f} ms per frame; one call / singles "
              f"{np.median(np.array(one_ms) / np.array(single_ms)):.2f} (median of frames)")
        ok = ok and totals["one"][0] >= totals["single"][0]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
