#!/usr/bin/env python3
"""Write the hostile input of doc/HOSTILE_INPUTS.md: a million-point unorganized cloud, a 1 x 1 m
table of 900k points (1 mm noise) with 100k points in a 10 x 6 x 4 cm block on it, shuffled,
seen by a camera 1 m above (camera frame, metres; binary PCD, 12 MB). Seeded.

  python3 scripts/make_million_point_cloud.py /tmp/million.pcd
  /usr/bin/time -v build/release/tools/pcl_icf_tool /tmp/million.pcd data/demo/box5.ply
"""
import sys

import numpy as np


def main():
    rng = np.random.default_rng(7)
    n_table, n_block = 900_000, 100_000
    table = np.c_[rng.uniform(-0.5, 0.5, n_table), rng.uniform(-0.5, 0.5, n_table),
                  rng.normal(0.0, 0.001, n_table)]
    block = np.c_[rng.uniform(-0.05, 0.05, n_block), rng.uniform(-0.03, 0.03, n_block),
                  rng.uniform(0.0, 0.04, n_block)]
    points = np.r_[table, block]
    rng.shuffle(points)
    camera = np.c_[points[:, 0], points[:, 1], 1.0 - points[:, 2]].astype(np.float32)
    header = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              f"WIDTH {len(camera)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(camera)}\n"
              "DATA binary\n")
    with open(sys.argv[1], "wb") as out:
        out.write(header.encode())
        out.write(camera.tobytes())


if __name__ == "__main__":
    main()
