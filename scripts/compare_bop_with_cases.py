#!/usr/bin/python3
"""The poses of pcl_icf_bench --bop on ../shared/data/bop-ycbv against those of the same frames'
PCD cases: for every target image, pcl_icf_tool on the case set's PCD with the case meshes (in
metres) of the image's targets, in the targets' order, the same call the bench makes on the
depth PNG and the millimetre meshes. Prints the largest translation (mm) and rotation (deg)
differences and the estimates found by one but not the other.

  scripts/compare_bop_with_cases.py BOP_CSV [--tool PATH] [--data DIR] [--tolerance-mm 0.5]

Exit 0 when every estimate has its twin within the tolerance (and 0.5 deg), 1 otherwise, 2 on
bad input."""
import argparse
import collections
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

# bop-ycbv's object ids (its README) and the case sets' mesh names.
NAMES = {1: "ycb_002_master_chef_can", 2: "ycb_003_cracker_box", 3: "ycb_004_sugar_box",
         5: "ycb_006_mustard_bottle", 8: "ycb_009_gelatin_box", 21: "ycb_061_foam_brick"}
VIDEOS = {0: "ycbv-video0000", 1: "ycbv-video0001"}


def read_csv(path):
    rows = collections.defaultdict(list)
    lines = pathlib.Path(path).read_text().splitlines()
    if not lines or lines[0] != "scene_id,im_id,obj_id,score,R,t,time":
        sys.exit(f"{path}: not a BOP results CSV")
    for line in lines[1:]:
        s, i, o, _, r, t, _ = line.split(",")
        pose = np.eye(4)
        pose[:3, :3] = np.array(r.split(), float).reshape(3, 3)
        pose[:3, 3] = np.array(t.split(), float)
        rows[(int(s), int(i), int(o))].append(pose)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--tool", default="build/release/tools/pcl_icf_tool")
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--tolerance-mm", type=float, default=0.5)
    a = ap.parse_args()
    data = pathlib.Path(a.data)
    bop = read_csv(a.csv)
    targets = json.loads((data / "bop-ycbv" / "test_targets_bop19.json").read_text())
    by_image = collections.defaultdict(list)
    for t in targets:
        by_image[(t["scene_id"], t["im_id"])].append(t["obj_id"])
    worst_t = worst_r = 0.0
    unmatched = 0
    with tempfile.TemporaryDirectory() as tmp:
        for (scene, im), objs in sorted(by_image.items()):
            video = data / VIDEOS[scene]
            pcd = video / "scenes" / f"ycbv{scene:04d}_{im:06d}.pcd"
            out = pathlib.Path(tmp) / "r.json"
            models = [str(video / "models" / f"{NAMES[o]}.ply") for o in objs]
            subprocess.run([a.tool, str(pcd), *models, "-q", "--force", "--max-instances", "1", "--json",
                            str(out)], check=False, stdout=subprocess.DEVNULL)
            found = json.loads(out.read_text())
            for o, obj in zip(objs, found["objects"]):
                poses = [np.array(i["pose"], float) for i in obj["instances"]]
                for p in poses:
                    p[:3, 3] *= 1000.0
                theirs = bop.get((scene, im, o), [])
                if len(poses) != len(theirs):
                    print(f"scene {scene} image {im} obj {o}: {len(poses)} from the PCD, "
                          f"{len(theirs)} in the CSV")
                    unmatched += 1
                    continue
                for p, q in zip(poses, theirs):
                    dt = np.linalg.norm(p[:3, 3] - q[:3, 3])
                    c = np.clip((np.trace(p[:3, :3].T @ q[:3, :3]) - 1) / 2, -1, 1)
                    dr = np.degrees(np.arccos(c))
                    worst_t, worst_r = max(worst_t, dt), max(worst_r, dr)
                    print(f"scene {scene} image {im} obj {o}: {dt:.4f} mm {dr:.4f} deg")
    print(f"largest difference {worst_t:.4f} mm, {worst_r:.4f} deg; {unmatched} unmatched")
    return 0 if unmatched == 0 and worst_t <= a.tolerance_mm and worst_r <= 0.5 else 1


if __name__ == "__main__":
    sys.exit(main())
