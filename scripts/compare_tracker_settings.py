#!/usr/bin/env python3
"""Tracks generated sequences (pcl_icf_make_dataset --kind sequence) with several tracker
settings and scores each with pcl_icf_track_score, to calibrate a TrackerParams field on many
sequences (doc/BENCHMARKS.md, "Tracking"). Each setting writes SEQDIR/poses_<name>.jsonl in
pcl_icf_tool --track's line format (frame, ms, objects: name, state, pose, refine_ms), so the
scorer reads it as it reads the tool's output.

  PYTHONPATH=build/release/python python3 scripts/compare_tracker_settings.py \
      --setting 'default=dict()' --setting 'fe30=dict(reacquire_full_evidence=0.3)' SEQDIR...

Prints, per setting, the scorer's totals line and bars, the poses given beyond 1 cm / 5 deg,
and the median and 90th percentile of the frames' time (all objects) and of the
re-acquisitions' time.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

import pcl_icf


def frames_of(seq):
    with open(os.path.join(seq, "frames.txt")) as f:
        return [l.strip() for l in f if l.strip() and not l.startswith("#")]


def models_of(seq):
    with open(os.path.join(seq, "tracked_models.txt")) as f:
        return [l.strip() for l in f if l.strip()]


def track(seq, name, kwargs, reacquire_ms):
    tracker = pcl_icf.Tracker(**kwargs)
    for path in models_of(seq):
        tracker.add_object(pcl_icf.Model.from_file(os.path.join(seq, path)),
                           os.path.splitext(os.path.basename(path))[0])
    frame_ms = []
    with open(os.path.join(seq, "poses_%s.jsonl" % name), "w") as out:
        for f, frame in enumerate(frames_of(seq)):
            scene = pcl_icf.load_scene(os.path.join(seq, frame))
            start = time.perf_counter()
            result = tracker.track(scene.xyz, scene.rgb)
            ms = 1e3 * (time.perf_counter() - start)
            frame_ms.append(ms)
            objects = []
            for o in result.objects:
                objects.append({"name": o.name, "state": o.state,
                                "pose": None if o.pose is None else np.asarray(o.pose).tolist(),
                                "confidence": o.confidence, "refine_ms": o.refine_ms})
                if o.reacquire_tried:
                    reacquire_ms.append(o.reacquire_ms)
            out.write(json.dumps({"frame": f, "ms": ms, "objects": objects}) + "\n")
    return frame_ms


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--setting", action="append", required=True,
                        help="NAME=dict(keyword=value, ...): Tracker keywords")
    parser.add_argument("--scorer", default="build/release/tools/pcl_icf_track_score")
    parser.add_argument("sequences", nargs="+")
    args = parser.parse_args()
    for setting in args.setting:
        name, _, expr = setting.partition("=")
        kwargs = eval(expr, {"__builtins__": {}}, {"dict": dict})  # keywords only
        frame_ms, reacquire_ms = [], []
        for seq in args.sequences:
            frame_ms += track(seq, name, kwargs, reacquire_ms)
        score = subprocess.run([args.scorer, "--poses", "poses_%s.jsonl" % name] + args.sequences,
                               capture_output=True, text=True)
        if score.returncode > 1:
            sys.exit("%s: %s" % (args.scorer, score.stderr.strip()))
        lines = score.stdout.splitlines()
        print("## %s %s" % (name, kwargs))
        print("\n".join(l for l in lines if l.startswith("| **all**") or l.startswith("bars")
                        or l.startswith("posed beyond") or l.startswith("missed")))
        q = lambda v, p: float(np.percentile(v, p)) if v else float("nan")
        print("frame ms: median %.1f, p90 %.1f; re-acquisitions: %d, median %.1f ms, p90 %.1f ms"
              % (q(frame_ms, 50), q(frame_ms, 90), len(reacquire_ms), q(reacquire_ms, 50),
                 q(reacquire_ms, 90)))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
