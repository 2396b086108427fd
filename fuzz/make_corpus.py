#!/usr/bin/env python3
"""Writes the fuzzers' seed corpora under fuzz/corpus/<target>/: small valid files of every
variant the loaders accept (PCD ascii/binary/binary_compressed, organized, colour; PLY ascii
and binary, with and without faces; XYZ with 3 and 6 columns; OBJ; STL ascii and binary; legacy
VTK ascii and binary, classic and 5.1 cell layouts, with a triangle strip) and
pipeline inputs in fuzz_pipeline's byte layout, plus the test/data fixtures. Seeds stay small
(a few KiB) so that libFuzzer's default -max_len stays small. Re-run after changing it; the
files are committed."""
import math
import os
import shutil
import struct

ROOT = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(ROOT, "corpus")
TEST_DATA = os.path.join(ROOT, "..", "test", "data")

CUBE_V = [(x, y, z) for z in (0.0, 0.05) for y in (0.0, 0.05) for x in (0.0, 0.05)]
CUBE_T = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
          (1, 3, 7), (1, 7, 5), (3, 2, 6), (3, 6, 7), (2, 0, 4), (2, 4, 6)]


def put(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def copy(target, name):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    shutil.copy(os.path.join(TEST_DATA, name), os.path.join(d, name))


def points(n, nan_every=0):
    out = []
    for i in range(n):
        a = 0.7 * i
        p = (0.1 * math.cos(a), 0.1 * math.sin(a), 0.8 + 0.01 * i)
        out.append((float("nan"),) * 3 if nan_every and i % nan_every == 0 else p)
    return out


def pcd_header(fields, sizes, types, width, height, data):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            f"FIELDS {' '.join(fields)}\nSIZE {' '.join(map(str, sizes))}\n"
            f"TYPE {' '.join(types)}\nCOUNT {' '.join('1' for _ in fields)}\n"
            f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\n"
            f"POINTS {width * height}\nDATA {data}\n").encode()


def lzf_literals(raw):
    """LZF stream of literal runs only (control byte 0..31 = run of 1..32 bytes): valid for
    PCL's decompressor, and simple."""
    out = bytearray()
    for i in range(0, len(raw), 32):
        chunk = raw[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def pcd_seeds():
    pts = points(6)
    body = "".join(f"{x:.4f} {y:.4f} {z:.4f}\n" for x, y, z in pts)
    put("fuzz_scene_pcd", "ascii_xyz.pcd", pcd_header("xyz", [4] * 3, "FFF", 6, 1, "ascii") +
        body.encode())
    rgb = "".join(f"{x:.4f} {y:.4f} {z:.4f} {0xff8020}\n" for x, y, z in pts)
    put("fuzz_scene_pcd", "ascii_rgb.pcd",
        pcd_header(["x", "y", "z", "rgb"], [4] * 4, "FFFU", 6, 1, "ascii") + rgb.encode())
    org = points(6, nan_every=3)
    put("fuzz_scene_pcd", "binary_organized_nan.pcd",
        pcd_header("xyz", [4] * 3, "FFF", 3, 2, "binary") +
        b"".join(struct.pack("<3f", *p) for p in org))
    put("fuzz_scene_pcd", "binary_double_int16.pcd",
        pcd_header(["x", "y", "z", "intensity"], [8, 8, 8, 2], "FFFU", 4, 1, "binary") +
        b"".join(struct.pack("<3dH", *p, 7) for p in points(4)))
    soa = b"".join(struct.pack("<f", p[a]) for a in range(3) for p in pts)
    comp = lzf_literals(soa)
    put("fuzz_scene_pcd", "binary_compressed.pcd",
        pcd_header("xyz", [4] * 3, "FFF", 6, 1, "binary_compressed") +
        struct.pack("<II", len(comp), len(soa)) + comp)


def ply_seeds():
    pts = points(5)
    head = ("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
            "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
            "end_header\n")
    put("fuzz_scene_ply", "ascii_colour.ply",
        head + "".join(f"{x:.4f} {y:.4f} {z:.4f} 200 30 10\n" for x, y, z in pts))
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n").encode()
    put("fuzz_scene_ply", "binary_with_face.ply",
        head + b"".join(struct.pack("<3f", *p) for p in pts) + struct.pack("<B3i", 3, 0, 1, 2))
    head = ("ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\n"
            "property double y\nproperty double z\nend_header\n").encode()
    put("fuzz_scene_ply", "binary_big_endian_double.ply",
        head + b"".join(struct.pack(">3d", *p) for p in points(4)))
    # Meshes: ascii quads (fixture), binary triangles, colour + normals.
    copy("fuzz_mesh_ply", "box_quads.ply")
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n"
            "property float y\nproperty float z\nelement face 12\n"
            "property list uchar int vertex_indices\nend_header\n").encode()
    put("fuzz_mesh_ply", "cube_binary_triangles.ply",
        head + b"".join(struct.pack("<3f", *v) for v in CUBE_V) +
        b"".join(struct.pack("<B3i", 3, *t) for t in CUBE_T))
    head = ("ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 12\n"
            "property list uchar uint vertex_indices\nend_header\n")
    put("fuzz_mesh_ply", "cube_normals_colour.ply",
        head + "".join(f"{x} {y} {z} 0 0 1 10 20 30\n" for x, y, z in CUBE_V) +
        "".join(f"3 {a} {b} {c}\n" for a, b, c in CUBE_T))


def xyz_seeds():
    pts = points(5)
    put("fuzz_scene_xyz", "three.xyz", "".join(f"{x:.4f} {y:.4f} {z:.4f}\n" for x, y, z in pts))
    put("fuzz_scene_xyz", "six_commas.xyz", "# x,y,z,r,g,b\n" + "".join(
        f"{x:.4f},{y:.4f},{z:.4f},255,128,0\r\n" for x, y, z in pts))
    put("fuzz_scene_xyz", "nan_blank.xyz", "\n0 0 1\nnan nan nan\n\t1e-3\t2E+1 -0.5 # c\n")


def obj_seeds():
    copy("fuzz_mesh_obj", "box_quads.obj")
    put("fuzz_mesh_obj", "cube_vt_vn.obj",
        "o cube\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_V) +
        "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n" +
        "".join(f"f {a + 1}/1/1 {b + 1}/2/1 {c + 1}/3/1\n" for a, b, c in CUBE_T[:6]) +
        "".join(f"f {a - 8}//1 {b - 8}//1 {c - 8}//1\n" for a, b, c in CUBE_T[6:]))


def stl_seeds():
    copy("fuzz_mesh_stl", "box_triangles.stl")
    body = b"".join(struct.pack("<12fH", 0, 0, 1, *CUBE_V[a], *CUBE_V[b], *CUBE_V[c], 0)
                    for a, b, c in CUBE_T)
    put("fuzz_mesh_stl", "cube_binary.stl",
        b"binary cube".ljust(80, b" ") + struct.pack("<I", len(CUBE_T)) + body)


def vtk_seeds():
    copy("fuzz_mesh_vtk", "box_quads.vtk")
    head = "# vtk DataFile Version {}\ncube\n{}\nDATASET POLYDATA\n"
    # Version 5.1 (VTK 9's writer): OFFSETS and CONNECTIVITY arrays; the sides as one strip
    # (0 1 4 5 ... wraps around the cube), top and bottom as triangles; attributes after.
    strip = [0, 4, 1, 5, 3, 7, 2, 6, 0, 4]
    tris = CUBE_T[:4]
    offsets = [3 * i for i in range(len(tris) + 1)]
    put("fuzz_mesh_vtk", "cube_strip_51.vtk",
        head.format("5.1", "ASCII") + "POINTS 8 float\n" +
        "".join(f"{x} {y} {z}\n" for x, y, z in CUBE_V) +
        f"POLYGONS {len(offsets)} {3 * len(tris)}\nOFFSETS vtktypeint64\n" +
        " ".join(map(str, offsets)) + "\nCONNECTIVITY vtktypeint64\n" +
        " ".join(str(i) for t in tris for i in t) + "\n" +
        "TRIANGLE_STRIPS 2 10\nOFFSETS vtktypeint64\n0 10\nCONNECTIVITY vtktypeint64\n" +
        " ".join(map(str, strip)) + "\nPOINT_DATA 8\nSCALARS s float 1\nLOOKUP_TABLE default\n" +
        " ".join("1" for _ in CUBE_V) + "\n")
    # Classic layout, BINARY (big-endian): double points, int32 cell records.
    cells = b"".join(struct.pack(">4i", 3, *t) for t in CUBE_T)
    put("fuzz_mesh_vtk", "cube_binary_42.vtk",
        head.format("4.2", "BINARY").encode() + b"POINTS 8 double\n" +
        b"".join(struct.pack(">3d", *v) for v in CUBE_V) +
        f"\nPOLYGONS {len(CUBE_T)} {4 * len(CUBE_T)}\n".encode() + cells +
        b"\nLINES 1 3\n" + struct.pack(">3i", 2, 0, 7) + b"\n")
    # Version 5.1, BINARY: unsigned_char points, 64-bit offsets and connectivity (VTK 9.1's
    # reader takes vtktypeint64 only there).
    put("fuzz_mesh_vtk", "cube_binary_51.vtk",
        head.format("5.1", "BINARY").encode() + b"POINTS 8 unsigned_char\n" +
        bytes(int(c * 20) for v in CUBE_V for c in v) +
        f"\nPOLYGONS {len(CUBE_T) + 1} {3 * len(CUBE_T)}\nOFFSETS vtktypeint64\n".encode() +
        struct.pack(f">{len(CUBE_T) + 1}q", *range(0, 3 * len(CUBE_T) + 1, 3)) +
        b"\nCONNECTIVITY vtktypeint64\n" +
        struct.pack(f">{3 * len(CUBE_T)}q", *(i for t in CUBE_T for i in t)) + b"\n")


def pipeline_seeds():
    def mesh(vertices, faces):
        out = bytes([len(vertices) - 3, len(faces) - 1])
        for v in vertices:
            out += bytes((int(round(c / 0.005)) & 0xff) for c in v)
        for f in faces:
            out += bytes([len(f) - 3] + list(f))
        return out

    cube = [(x - 0.025, y - 0.025, z - 0.025) for x, y, z in CUBE_V]
    # Scene sampled from the mesh under a pose (flag 4), with 2-thread check (32).
    put("fuzz_pipeline", "cube_sampled", bytes([4 | 32]) + mesh(cube, CUBE_T) +
        bytes([120, 7, 3, 0, 0, 0, 5]))
    put("fuzz_pipeline", "cube_sampled_thesis", bytes([4 | 8]) + mesh(cube, CUBE_T) +
        bytes([60, 20, 9, 4, 252, 10, 1]))
    put("fuzz_pipeline", "cube_sampled_sac", bytes([4 | 16]) + mesh(cube, CUBE_T) +
        bytes([150, 1, 2, 0, 0, 0, 3]))
    # Quads and a pentagon, raw scene points from the bytes.
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    scene = b"".join(bytes((int(round(c / 0.005)) & 0xff) for c in p)
                     for p in [(0.02 * math.cos(i), 0.02 * math.sin(i), 0.1) for i in range(40)])
    put("fuzz_pipeline", "cube_quads_points", bytes([0]) + mesh(cube, quads) + scene)
    put("fuzz_pipeline", "one_triangle_mm", bytes([4 | 64]) +
        mesh([(0, 0, 0), (0.5, 0, 0), (0, 0.5, 0)], [(0, 1, 2)]) + bytes([30, 0, 0, 0, 0, 0]))


if __name__ == "__main__":
    pcd_seeds()
    ply_seeds()
    xyz_seeds()
    obj_seeds()
    stl_seeds()
    vtk_seeds()
    pipeline_seeds()
