"""The suites' scoring rule for real annotated frames (doc/DATASETS.md): the model's
bounding-box centre within 1 cm of the truth's and ADD-S under 10% of the model's diameter.
Shared by scripts/track_real_frames.py and scripts/find_all_objects.py."""
import numpy as np


def mesh_vertices(path):
    """The x y z of an ASCII PLY's vertices or an OBJ's "v" lines (the shared real meshes)."""
    path = str(path)
    if path.endswith(".obj"):
        with open(path) as f:
            return np.array([[float(v) for v in line.split()[1:4]]
                             for line in f if line.startswith("v ")])
    with open(path) as f:
        if f.readline().strip() != "ply" or "ascii" not in f.readline():
            raise ValueError(f"{path}: not an ASCII PLY")
        count = 0
        for line in f:
            if line.startswith("element vertex"):
                count = int(line.split()[2])
            if line.strip() == "end_header":
                break
        return np.array([[float(v) for v in f.readline().split()[:3]] for _ in range(count)])


def adds(points, estimated, truth):
    """Mean distance of the model's points under the estimate to the nearest of the truly
    posed points (brute force over a strided subset)."""
    est = points @ estimated[:3, :3].T + estimated[:3, 3]
    tru = points @ truth[:3, :3].T + truth[:3, 3]
    best = np.full(len(est), np.inf)
    for chunk in range(0, len(tru), 512):
        d = np.linalg.norm(est[:, None, :] - tru[None, chunk:chunk + 512, :], axis=2)
        best = np.minimum(best, d.min(axis=1))
    return float(best.mean())


class Scorer:
    """Scores poses of one mesh against the truth with the suites' rule."""

    def __init__(self, mesh_path):
        vertices = mesh_vertices(mesh_path)
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        self.centre = 0.5 * (lo + hi)
        self.diameter = float(np.linalg.norm(hi - lo))
        self.samples = vertices[:: max(1, len(vertices) // 2000)]

    def score(self, pose, truth):
        """(right, centre error m, ADD-S m) of the 4x4 \a pose against \a truth."""
        pose, truth = np.asarray(pose), np.asarray(truth)
        t_err = float(np.linalg.norm(pose[:3, :3] @ self.centre + pose[:3, 3] -
                                     truth[:3, :3] @ self.centre - truth[:3, 3]))
        a = adds(self.samples, pose, truth)
        return t_err < 0.01 and a < 0.1 * self.diameter, t_err, a
