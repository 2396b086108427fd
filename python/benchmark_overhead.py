#!/usr/bin/env python3
"""Python overhead of pcl_icf.localize on the bundled scene (doc/BENCHMARKS.md, "Python
bindings"): wall time of the Python call (argument checks, the copy into a PCL cloud, the result
objects) against the C++ localizeObject's own time (Localization::total_ms) measured inside it.

    PYTHONPATH=build/release/python python3 python/benchmark_overhead.py [RUNS]
"""
import pathlib
import statistics
import sys
import time

import pcl_icf

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 10
demo = pathlib.Path(__file__).resolve().parents[1] / "data" / "demo"
scene = pcl_icf.load_scene(str(demo / "tabletop_box5.pcd"))
model = pcl_icf.Model.from_file(str(demo / "box5.ply"))
pcl_icf.localize(scene.xyz, scene.rgb, model)  # warm-up

wall, cpp = [], []
for _ in range(runs):
    start = time.perf_counter()
    result = pcl_icf.localize(scene.xyz, scene.rgb, model, camera=scene.camera_pose)
    wall.append(1e3 * (time.perf_counter() - start))
    cpp.append(result.timing["total_ms"])
over = [w - c for w, c in zip(wall, cpp)]
print(f"runs {runs}: Python call median {statistics.median(wall):.1f} ms, C++ localizeObject "
      f"median {statistics.median(cpp):.1f} ms, overhead median {statistics.median(over):.2f} ms "
      f"(max {max(over):.2f} ms) = {100 * statistics.median(over) / statistics.median(cpp):.2f}% "
      f"of the C++ time")
