#!/usr/bin/env python3
"""Writes a pcl_icf_bench manifest (doc/DATASETS.md) for a folder of real cases laid out as
../shared/data/ycbv-video0000 and ycbv-video0001 are: cases/<id>/case.json (scene, model) and
gt.json (every annotated object's pose, the target marked, its symmetry and visible share).

    scripts/make_real_manifest.py ../shared/data/ycbv-video0001 > data/manifests/ycbv_video0001.txt

Paths in the manifest are relative to data/manifests/ (where the manifests live). The errors are
measured at the model's bounding-box centre (the bench's default), the symmetry is the one
gt.json lists (continuous about z: cylinder:noflip; a discrete half turn about z, or none), the
group is the object, and the scene method searches the whole frame (cluster=crop is an oracle
crop for the cluster methods only)."""
import json
import os
import sys


def symmetry_spec(sym, extent):
    if sym is None or sym.get("label") == "none":
        return "none"
    if sym.get("type") == "continuous":
        if [round(a) for a in sym["axis"]] != [0, 0, 1]:
            raise SystemExit("only a continuous symmetry about z is expressible: %r" % sym)
        return "cylinder" if sym.get("flip") else "cylinder:noflip"
    rotations = [[round(x) for x in r] for r in sym["rotations"]]
    if rotations == [[1, 0, 0, 0, 1, 0, 0, 0, 1], [-1, 0, 0, 0, -1, 0, 0, 0, 1]]:
        return "halfturn:z"
    raise SystemExit("unknown discrete symmetry %r" % sym)


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    root = os.path.abspath(sys.argv[1])
    manifests = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "data", "manifests"))
    name = os.path.basename(root)
    print("# pcl_icf bench manifest v1 (doc/DATASETS.md)")
    print("# written by: scripts/make_real_manifest.py ../shared/data/%s" % name)
    print("# The real cases of ../shared/data/%s (its README.md): one per (frame, object), truth"
          % name)
    print("# the target's pose in cases/<id>/gt.json (model -> camera, row-major, metres); errors at")
    print("# the model's bounding-box centre, symmetry as gt.json lists it; groups are the objects.")
    print("# cluster=crop:0.02 is an ORACLE crop for the cluster methods; icf-scene ignores it and")
    print("# searches the whole frame.")
    for case in sorted(os.listdir(os.path.join(root, "cases"))):
        folder = os.path.join(root, "cases", case)
        spec = json.load(open(os.path.join(folder, "case.json")))
        gt = json.load(open(os.path.join(folder, "gt.json")))
        target = [o for o in gt["objects"] if o.get("target")]
        if len(target) != 1:
            raise SystemExit("%s: %d targets" % (case, len(target)))
        t = target[0]
        truth = ",".join(repr(float(x)) for row in t["pose"] for x in row)
        scene = os.path.relpath(os.path.normpath(os.path.join(folder, spec["scene"])), manifests)
        model = os.path.relpath(os.path.normpath(os.path.join(folder, spec["model"])), manifests)
        print("name=%s group=%s-%s scene=%s model=%s units=m truth=%s symmetry=%s cluster=crop:0.02"
              % (spec["id"], name.replace("ycbv-video", "ycbv"), spec["model_name"].replace("ycb_", "")
                 .split("_", 1)[1] if spec["model_name"].startswith("ycb_") else spec["model_name"],
                 scene, model, truth, symmetry_spec(t.get("symmetry"), None)))


if __name__ == "__main__":
    main()
