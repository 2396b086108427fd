#!/usr/bin/env python3
"""Localize every case of bench manifests under several LocalizerParams settings in one run and
compare each setting's decisions with the first one's: found or not, the pose within 1 mm and
1 degree, and the median registration time per suite (ratios of medians from the same run;
doc/BENCHMARKS.md). A case whose truth is "none" counts a false pose when found.

  PYTHONPATH=build/release/python python3 scripts/compare_localizer_settings.py \\
      --setting 'before=dict(check_turns=False)' --setting 'default=dict()' \\
      data/manifests/ycbv_video0000.txt data/manifests/ycbv_absent.txt ...

Settings are Python dicts of pcl_icf.localize keyword arguments; the first is the reference.
"""
import argparse
import ast
import pathlib
import statistics

import numpy as np
import pcl_icf


def read_manifest(path):
    cases = []
    for line in pathlib.Path(path).read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        fields = dict(token.split("=", 1) for token in line.split())
        base = pathlib.Path(path).parent
        truth = None
        if fields.get("truth", "none") != "none":
            truth = np.array([float(v) for v in fields["truth"].split(",")]).reshape(4, 4)
        cases.append((fields["name"], (base / fields["scene"]).resolve(),
                      (base / fields["model"]).resolve(), truth))
    return cases


def parse_setting(text):
    name, _, expr = text.partition("=")
    tree = ast.parse(expr, mode="eval").body
    if not (isinstance(tree, ast.Call) and getattr(tree.func, "id", "") == "dict"):
        raise SystemExit(f"--setting {text!r}: expected NAME=dict(key=value, ...)")
    return name, {k.arg: ast.literal_eval(k.value) for k in tree.keywords}


def same_pose(a, b):
    if a is None or b is None:
        return a is None and b is None
    turn = a[:3, :3].T @ b[:3, :3]
    angle = np.degrees(np.arccos(np.clip((np.trace(turn) - 1) / 2, -1, 1)))
    return np.linalg.norm(a[:3, 3] - b[:3, 3]) < 1e-3 and angle < 1.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--setting", action="append", required=True, type=parse_setting)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("manifests", nargs="+")
    args = parser.parse_args()
    names = [name for name, _ in args.setting]
    models = {}
    for manifest in args.manifests:
        times = {name: [] for name in names}
        segmentation = {name: [] for name in names}
        found = {name: 0 for name in names}
        right = {name: 0 for name in names}
        false = {name: 0 for name in names}
        differ = {name: [] for name in names}
        cases = read_manifest(manifest)
        for case, scene_path, model_path, truth in cases:
            if model_path not in models:
                models[model_path] = pcl_icf.Model.from_file(str(model_path))
            scene = pcl_icf.load_scene(str(scene_path))
            poses = {}
            for name, kw in args.setting:
                r = pcl_icf.localize(scene.xyz, scene.rgb, models[model_path],
                                     threads=args.threads, **kw)
                times[name].append(r.timing["registration_ms"])
                segmentation[name].append(r.timing["segmentation_ms"])
                pose = np.array(r.best.pose) if r.found else None
                poses[name] = pose
                if r.found:
                    found[name] += 1
                    if truth is None:
                        false[name] += 1
                    elif np.linalg.norm(pose[:3, 3] - truth[:3, 3]) < 0.01:
                        right[name] += 1
                if not same_pose(pose, poses[names[0]]):
                    differ[name].append(case)
        print(f"{pathlib.Path(manifest).name}: {len(cases)} cases")
        for name in names:
            ratio = statistics.median(times[names[0]]) / statistics.median(times[name])
            print(f"  {name:>12}: found {found[name]}, origin within 1 cm {right[name]}, "
                  f"false {false[name]}, median {statistics.median(times[name]):.0f} ms "
                  f"({ratio:.2f}x the first; segmentation "
                  f"{statistics.median(segmentation[name]):.0f} ms apart), decisions unlike the first: {len(differ[name])}"
                  + (f" {differ[name]}" if differ[name] else ""), flush=True)


if __name__ == "__main__":
    main()
