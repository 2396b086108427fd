#!/usr/bin/env python3
"""Find the box in the bundled table-top scene (the Python twin of scripts/demo.sh):

    python3 python/examples/localize_demo.py [SCENE.pcd MODEL.ply]

Needs the module on the path: after `cmake --install build/release`, or with
PYTHONPATH=build/release/python.
"""
import pathlib
import sys

import numpy as np

import pcl_icf

demo = pathlib.Path(__file__).resolve().parents[2] / "data" / "demo"
scene_path = sys.argv[1] if len(sys.argv) > 1 else str(demo / "tabletop_box5.pcd")
model_path = sys.argv[2] if len(sys.argv) > 2 else str(demo / "box5.ply")

scene = pcl_icf.load_scene(scene_path)          # xyz (H, W, 3) float32, rgb uint8: views
model = pcl_icf.Model.from_file(model_path)     # units="auto": metres here
result = pcl_icf.localize(scene.xyz, scene.rgb, model, camera=scene.camera_pose)

print(f"{scene_path}: {result.status} ({len(result.clusters)} clusters tried, "
      f"{result.timing['total_ms']:.0f} ms)")
np.set_printoptions(precision=4, suppress=True)
for n, found in enumerate(result.instances):
    print(f"instance {n}: cluster {found.cluster}, confidence {found.confidence:.3f}, "
          f"{found.method}, visible support {found.verification['visible_support']:.3f}"
          + (f", {len(found.alternatives)} look-alike turn(s)" if found.alternatives else ""))
    print(found.pose)
if not result.found:
    print(result.message)
sys.exit(0 if result.found else 1)
