#!/usr/bin/env python3
"""Calibrates AcceptanceParams::max_seen_through (doc/experiments/2026-11-27-seen-through.md, "Seen through").

For every case of the given bench manifests (doc/DATASETS.md) the cluster is cut as the bench
cuts it (cluster=all: the whole cloud; cluster=crop:M: the points inside the model's box at the
truth grown by M), and pcl_icf.estimate_pose runs with the check measuring but never rejecting
(max_seen_through 0.99999: measured, as good as never rejecting; fallback off) at the default search budget and at deliberately poor ones
(fewer rotations, fewer kept hypotheses): poor searches end in wrong basins, the poses the check
must catch. Each pose is labelled right (origin within 1 cm and rotation within 5 degrees,
symmetry-aware as the bench scores) or wrong, with its measured seen_through.

Prints per threshold the right poses the check would reject and the wrong poses it would catch;
with --plot FILE.png, the two rates against the threshold (gnuplot).

    PYTHONPATH=build/release/python python3 scripts/seen_through_curve.py \\
        data/manifests/synthetic_views.txt data/manifests/synthetic_freeform.txt \\
        data/manifests/ycbv.txt data/manifests/ycbv_video0000.txt --plot doc/img/seen_through.png

Needs numpy (python3-numpy) and the pcl_icf module; gnuplot for the picture.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import pcl_icf

BUDGETS = [
    ("default", {}),
    ("200 rotations, keep 3", {"rotations": 200, "keep": 3, "exact_candidates": 1}),
    ("60 rotations, keep 1", {"rotations": 60, "keep": 1, "exact_candidates": 1}),
    ("20 rotations, keep 1", {"rotations": 20, "keep": 1, "exact_candidates": 1}),
]


def rotation(axis, degrees):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k


def angle_deg(r):
    return math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2))))


def rotation_error(est, truth, symmetry):
    """Symmetry-aware rotation error in degrees (synthetic/pose_error.h)."""
    kind, _, args = symmetry.partition(":")
    if kind == "cylinder":
        z_est, z_true = est[:3, 2], truth[:3, 2]
        a = math.degrees(math.acos(max(-1.0, min(1.0, float(z_est @ z_true)))))
        return a if args == "noflip" else min(a, 180 - a)
    group = [np.eye(3)]
    if kind == "box":
        sides = [float(s) for s in args.split(",")]
        if len(set(sides)) < 3:
            sys.exit("seen_through_curve: boxes with equal sides are not handled")
        group += [rotation(e, 180) for e in np.eye(3)]
    elif kind == "prism":
        n = int(args)
        group = [rotation([0, 0, 1], 360 * k / n) @ f
                 for k in range(n) for f in (np.eye(3), rotation([1, 0, 0], 180))]
    relative = truth[:3, :3].T @ est[:3, :3]
    return min(angle_deg(relative @ s) for s in group)


def model_box(path):
    """Axis-aligned bounds of a mesh's vertices: ASCII PLY or OBJ (the cropped suites' meshes)."""
    if path.lower().endswith(".obj"):
        with open(path) as f:
            xyz = np.array([[float(v) for v in line.split()[1:4]] for line in f
                            if line.startswith("v ")])
        return xyz.min(0), xyz.max(0)
    with open(path, "rb") as f:
        head = []
        while not head or head[-1] != "end_header":
            line = f.readline()
            if not line:
                sys.exit(f"seen_through_curve: {path}: no PLY header")
            head.append(line.decode("ascii", "replace").strip())
        if not any(h.startswith("format ascii") for h in head):
            sys.exit(f"seen_through_curve: {path} is not an ASCII PLY")
        vertices = next(int(h.split()[2]) for h in head if h.startswith("element vertex"))
        xyz = np.array([[float(v) for v in f.readline().split()[:3]] for _ in range(vertices)])
        return xyz.min(0), xyz.max(0)


def read_cases(manifest):
    base = os.path.dirname(os.path.abspath(manifest))
    cases = []
    for line in open(manifest):
        if not line.startswith("name="):
            continue
        f = dict(kv.split("=", 1) for kv in line.split())
        if f["truth"] == "none":
            continue
        truth = np.array([float(x) for x in f["truth"].split(",")]).reshape(4, 4)
        cases.append((f, os.path.join(base, f["scene"]), os.path.join(base, f["model"]), truth))
    return cases


def cluster_points(scene, truth, cluster, box):
    sc = pcl_icf.load_scene(scene)
    xyz = np.asarray(sc.xyz, dtype=np.float64).reshape(-1, 3)
    xyz = xyz[np.isfinite(xyz).all(1)]
    if cluster == "all":
        return xyz
    if not cluster.startswith("crop:"):
        sys.exit(f"seen_through_curve: cluster={cluster} is not handled")
    margin = float(cluster[5:])
    local = (xyz - truth[:3, 3]) @ truth[:3, :3]
    keep = np.all((local >= box[0] - margin) & (local <= box[1] + margin), axis=1)
    return xyz[keep]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("manifests", nargs="+")
    ap.add_argument("--verbose", action="store_true", help="print every pose to stderr")
    ap.add_argument("--plot", help="write the rates as a PNG picture (gnuplot)")
    args = ap.parse_args()
    poses = []  # (suite, case, budget, right, seen_through)
    models = {}
    for manifest in args.manifests:
        suite = os.path.basename(manifest).replace(".txt", "")
        for f, scene, model_path, truth in read_cases(manifest):
            if model_path not in models:
                crop = f.get("cluster", "all") != "all"
                models[model_path] = (pcl_icf.Model.from_file(model_path, f.get("units", "m")),
                                      model_box(model_path) if crop else None)
            model, box = models[model_path]
            points = cluster_points(scene, truth, f.get("cluster", "all"), box)
            reference = np.eye(4)
            if "axes" in f:
                reference[:3, :3] = np.array([float(x) for x in f["axes"].split(",")]).reshape(3, 3)
            if "center" in f:
                reference[:3, 3] = [float(x) for x in f["center"].split(",")]
            for budget, extra in BUDGETS:
                r = pcl_icf.estimate_pose(points, model, fallback="off", max_seen_through=0.99999,
                                          threads=2, **extra)
                # Scored in the case's symmetry frame (center=, axes=), as the bench does.
                est, ref_truth = np.asarray(r.pose) @ reference, truth @ reference
                right = (np.linalg.norm(est[:3, 3] - ref_truth[:3, 3]) < 0.01 and
                         rotation_error(est, ref_truth, f.get("symmetry", "none")) < 5.0)
                poses.append((suite, f["name"], budget, right, r.quality["seen_through"]))
                if args.verbose:
                    print(f"{f['name']} {len(points)} points, {budget}: {'right' if right else 'wrong'}, "
                          f"seen through {r.quality['seen_through']:.4f}, {r.time_ms:.0f} ms",
                          file=sys.stderr, flush=True)
    right = [p[4] for p in poses if p[3]]
    wrong = [p[4] for p in poses if not p[3]]
    print(f"{len(poses)} poses: {len(right)} right, {len(wrong)} wrong "
          f"({', '.join(os.path.basename(m) for m in args.manifests)})")
    print("| max_seen_through | right poses rejected | wrong poses caught |")
    print("|---:|---:|---:|")
    for t in (0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2, 0.3, 0.5):
        print(f"| {t} | {sum(v > t for v in right)}/{len(right)} | "
              f"{sum(v > t for v in wrong)}/{len(wrong)} |")
    print("Largest right: " + ", ".join(f"{p[1]} ({p[2]}) {p[4]:.4f}" for p in
                                         sorted((p for p in poses if p[3]), key=lambda p: -p[4])[:3]))
    print("Wrong below 0.05: " + ", ".join(f"{p[1]} ({p[2]}) {p[4]:.4f}" for p in
                                           sorted((p for p in poses if not p[3] and p[4] <= 0.05),
                                                  key=lambda p: -p[4])[:10]) + ", ...")
    if args.plot:
        fine = sorted({0.0, 1.0} | set(right) | set(wrong))
        with tempfile.NamedTemporaryFile("w", suffix=".dat", delete=False) as dat:
            for t in fine:
                dat.write(f"{max(t, 1e-4)} {sum(v > t for v in right) / max(1, len(right))} "
                          f"{sum(v > t for v in wrong) / max(1, len(wrong))}\n")
        script = f"""set terminal pngcairo size 720,420
set output '{args.plot}'
set logscale x
set xrange [1e-4:1]
set yrange [0:1.05]
set xlabel 'max\\_seen\\_through: share of the posed model pixels seen through'
set ylabel 'share of poses'
set key top right
set arrow from 0.05,0 to 0.05,1.05 nohead dashtype 2
set title 'Seen-through check: {len(right)} right and {len(wrong)} wrong poses'
plot '{dat.name}' using 1:3 with steps lw 2 title 'wrong poses caught', \\
     '{dat.name}' using 1:2 with steps lw 2 title 'right poses rejected'
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        os.unlink(dat.name)


if __name__ == "__main__":
    main()
