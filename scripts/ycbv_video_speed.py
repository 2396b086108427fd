#!/usr/bin/env python3
"""Time localize() on the 18 ycbv-video0000 cases under four settings in one run (ratios of
medians from the same run; doc/experiments/2026-11-27-real-frame-time.md, "Where the time goes"): before (one
full-resolution final refinement, every hypothesis scored on the whole subsample, every start
refined), coarse to fine alone, coarse to fine + the global search's cascade, and the default
(both, and no final refinement for a start the depth verification gives no chance). Prints per case the registration time, the translation error and whether the
truth is among the reported alternatives, and the largest pose difference to "before".

  PYTHONPATH=build/release/python python3 scripts/ycbv_video_speed.py [../shared/data]"""
import json
import pathlib
import statistics
import sys

import numpy as np
import pcl_icf

SETTINGS = {
    "before": dict(coarse_points=0, prescreen_share=0.0, refine_min_confidence=0.0),
    "coarse to fine": dict(prescreen_share=0.0, refine_min_confidence=0.0),
    "cascade": dict(refine_min_confidence=0.0),
    "default": {},
}


def main():
    data = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/data")
    root = data / "ycbv-video0000"
    models = {p.stem: pcl_icf.Model.from_file(str(p)) for p in (root / "models").glob("*.ply")}
    times = {name: [] for name in SETTINGS}
    strict = {name: 0 for name in SETTINGS}
    for case in sorted((root / "cases").iterdir()):
        c = json.loads((case / "case.json").read_text())
        gt = json.loads((case / "gt.json").read_text())
        truth = next(np.array(o["pose"]) for o in gt["objects"] if o.get("target"))
        scene = pcl_icf.load_scene(str((case / c["scene"]).resolve()))
        poses = {}
        line = [case.name]
        for name, kw in SETTINGS.items():
            r = pcl_icf.localize(scene.xyz, scene.rgb, models[c["model_name"]], **kw)
            times[name].append(r.timing["registration_ms"])
            if not r.found:
                line.append(f"{name}: not found")
                continue
            poses[name] = r.best.pose
            t = np.linalg.norm(r.best.pose[:3, 3] - truth[:3, 3])
            strict[name] += t < 0.01
            among = any(np.linalg.norm(a.pose[:3, 3] - truth[:3, 3]) < 0.01
                        for a in r.best.alternatives)
            line.append(f"{name}: {r.timing['registration_ms']:.0f} ms, {1e3 * t:.1f} mm"
                        f"{' (truth among alternatives)' if among else ''}")
        if "before" in poses:
            diff = max(np.linalg.norm(p[:3, 3] - poses["before"][:3, 3]) for p in poses.values())
            line.append(f"largest difference to before {1e3 * diff:.3f} mm")
        print("; ".join(line), flush=True)
    base = statistics.median(times["before"])
    for name in SETTINGS:
        m = statistics.median(times[name])
        print(f"{name}: median registration {m:.0f} ms, {base / m:.2f}x faster than before, "
              f"strict {strict[name]}/{len(times[name])}")


if __name__ == "__main__":
    main()
