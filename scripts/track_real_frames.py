#!/usr/bin/python3
"""Tracks every meshed object of a real annotated sequence (../shared/data/ycbv-video0001 by
default: five frames, four objects) with pcl_icf.Tracker and scores each object in each frame
with the suites' rule (the model's bounding-box centre within 1 cm of the truth's and ADD-S
under 10% of the diameter; doc/DATASETS.md).

  scripts/track_real_frames.py [DATASET] [--threads N]

Needs the Python module (scripts/test.sh installs it, or PYTHONPATH=build/release/python).
Prints one line per frame and object and a summary; exit 0 when every object is posed right
in every frame after the first, 1 otherwise, 2 on bad input."""
import argparse
import json
import pathlib
import sys

import numpy as np

import pcl_icf
from real_scoring import Scorer


def main():
    here = pathlib.Path(__file__).resolve().parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", nargs="?",
                        default=str(here.parent.parent / "shared/data/ycbv-video0001"))
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()
    root = pathlib.Path(args.dataset)
    cases = sorted((root / "cases").glob("*/gt.json"))
    if not cases:
        print(f"no cases under {root / 'cases'}", file=sys.stderr)
        return 2
    frames = {}
    for gt_path in cases:
        gt = json.loads(gt_path.read_text())
        frames[gt["frame"]] = (gt_path.parent, gt)
    first_dir, first_gt = frames[sorted(frames)[0]]
    names = [o["name"] for o in first_gt["objects"]]
    tracker = pcl_icf.Tracker(threads=args.threads)
    models, scorers = {}, {}
    for o in first_gt["objects"]:
        path = (first_dir / o["model"]).resolve()
        models[o["name"]] = pcl_icf.Model.from_file(str(path))
        scorers[o["name"]] = Scorer(path)
        tracker.add_object(models[o["name"]], o["name"])
    posed_right = total = 0
    times = []
    for k, frame in enumerate(sorted(frames)):
        case_dir, gt = frames[frame]
        scene = pcl_icf.load_scene(str((case_dir / json.loads(
            (case_dir / "case.json").read_text())["scene"]).resolve()))
        result = tracker.track(scene.xyz, scene.rgb, camera=scene.camera_pose)
        truth = {o["name"]: np.array(o["pose"]) for o in gt["objects"]}
        for name, got in zip(names, result.objects):
            ok, text = False, "no pose"
            if got.pose is not None:
                ok, t_err, a = scorers[name].score(got.pose, truth[name])
                text = f"centre {1e3 * t_err:.1f} mm, ADD-S {1e3 * a:.1f} mm"
            ms = got.refine_ms + got.verify_ms + got.search_ms + got.reacquire_ms
            if k > 0:
                total += 1
                posed_right += ok
                times.append(ms)
            how = "searched" if got.searched else "refined" if got.refined else ""
            print(f"{frame} {name:28s} {got.state:10s} {'right' if ok else 'WRONG':5s} {text}"
                  f", {how} {ms:.0f} ms")
    median = float(np.median(times)) if times else float("nan")
    print(f"frames after the first: {posed_right}/{total} object-frames posed right, "
          f"median {median:.0f} ms per object and frame")
    return 0 if posed_right == total else 1


if __name__ == "__main__":
    sys.exit(main())
