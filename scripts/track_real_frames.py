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


def ascii_ply_vertices(path):
    """The x y z of an ASCII PLY's vertices (the shared real meshes are ASCII)."""
    with open(path) as f:
        if f.readline().strip() != "ply" or "ascii" not in f.readline():
            raise ValueError(f"{path}: not an ASCII PLY")
        count = 0
        for line in f:
            if line.startswith("element vertex"):
                count = int(line.split()[2])
            if line.strip() == "end_header":
                break
        return np.array([[float(v) for v in f.readline().split()[:3]] for _ in range(count)])


def adds(points, estimated, truth):
    """Mean distance of the model's points under the estimate to the nearest of the truly
    posed points (brute force over a strided subset)."""
    est = points @ estimated[:3, :3].T + estimated[:3, 3]
    tru = points @ truth[:3, :3].T + truth[:3, 3]
    best = np.full(len(est), np.inf)
    for chunk in range(0, len(tru), 512):
        d = np.linalg.norm(est[:, None, :] - tru[None, chunk:chunk + 512, :], axis=2)
        best = np.minimum(best, d.min(axis=1))
    return float(best.mean())


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
    models, vertices, samples = {}, {}, {}
    for o in first_gt["objects"]:
        path = (first_dir / o["model"]).resolve()
        models[o["name"]] = pcl_icf.Model.from_file(str(path))
        vertices[o["name"]] = ascii_ply_vertices(path)
        samples[o["name"]] = vertices[o["name"]][:: max(1, len(vertices[o["name"]]) // 2000)]
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
            lo, hi = vertices[name].min(axis=0), vertices[name].max(axis=0)
            centre = 0.5 * (lo + hi)
            diameter = float(np.linalg.norm(hi - lo))
            ok, text = False, "no pose"
            if got.pose is not None:
                pose = np.array(got.pose)
                t_err = np.linalg.norm(pose[:3, :3] @ centre + pose[:3, 3] -
                                       truth[name][:3, :3] @ centre - truth[name][:3, 3])
                a = adds(samples[name], pose, truth[name])
                ok = t_err < 0.01 and a < 0.1 * diameter
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
