#!/usr/bin/env python3
"""The same search fed from Open3D objects (Debian: python3-open3d): a PointCloud scene and a
TriangleMesh model; the found pose moves the mesh. Exits 0 with a note when Open3D is missing.

    python3 python/examples/open3d_demo.py [SCENE.pcd MODEL.ply]
"""
import pathlib
import sys

import numpy as np

import pcl_icf

try:
    import open3d as o3d
except ImportError:
    print("open3d is not installed (apt-get install python3-open3d): nothing to do")
    sys.exit(0)

demo = pathlib.Path(__file__).resolve().parents[2] / "data" / "demo"
scene_path = sys.argv[1] if len(sys.argv) > 1 else str(demo / "tabletop_box5.pcd")
model_path = sys.argv[2] if len(sys.argv) > 2 else str(demo / "box5.ply")

cloud = o3d.io.read_point_cloud(scene_path, remove_nan_points=False)
mesh = o3d.io.read_triangle_mesh(model_path)
xyz = np.asarray(cloud.points)                   # (N, 3) float64: read in place, not copied
rgb = (np.asarray(cloud.colors) * 255).round().astype(np.uint8) if cloud.has_colors() else None
model = pcl_icf.Model(np.asarray(mesh.vertices), np.asarray(mesh.triangles))

# Open3D flattens the organized cloud: the camera's intrinsics are no longer implied, so give
# them (the bundled scene: 320 x 240, fx = fy = 262.5) or let localize assume a virtual camera.
result = pcl_icf.localize(xyz, rgb, model,
                          intrinsics=dict(fx=262.5, fy=262.5, cx=159.5, cy=119.5,
                                          width=320, height=240))
print(f"{scene_path}: {result.status}")
if result.found:
    print(np.array2string(result.best.pose, precision=4, suppress_small=True))
    mesh.transform(result.best.pose)             # the model, posed in the scene
sys.exit(0 if result.found else 1)
