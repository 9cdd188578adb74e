#!/usr/bin/env python3
"""Seed corpora for the fuzz targets (fuzz/CMakeLists.txt), one folder per reader.

Usage: python3 fuzz/make_seeds.py OUT [--mpfb2 DIR]

Writes OUT/<reader>/ for ply, obj, glb, body_json, keypoints, npz, garment_obj and, when the
MPFB2 folder is found (default ../shared/bodymodels/mpfb2 beside the repository), mpfb2_obj and
mpfb2_target. Every seed is small (a few hundred bytes to 3 KB) and valid, so the fuzzer starts
from inputs the readers accept. The MPFB2 seeds are cut from the model's own files at run time:
nothing derived from the model is kept in the repository.
"""
import argparse
import gzip
import io
import json
import os
import struct
import sys
import zipfile

# An octahedron: 6 vertices, 8 outward faces, one colour per vertex.
V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
F = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
C = [(200, 30, 30), (30, 200, 30), (30, 30, 200), (200, 200, 30), (30, 200, 200), (200, 30, 200)]


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def ply_seeds(out):
    head = ("ply\nformat {}\nelement vertex 6\nproperty float x\nproperty float y\n"
            "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
            "element face 8\nproperty list uchar int vertex_indices\nend_header\n")
    body = "".join(f"{x} {y} {z} {r} {g} {b}\n" for (x, y, z), (r, g, b) in zip(V, C))
    body += "".join(f"3 {a} {b} {c}\n" for a, b, c in F)
    write(f"{out}/ply/octahedron_ascii.ply", head.format("ascii 1.0") + body)
    binary = head.format("binary_little_endian 1.0").encode()
    for (x, y, z), (r, g, b) in zip(V, C):
        binary += struct.pack("<fffBBB", x, y, z, r, g, b)
    for a, b, c in F:
        binary += struct.pack("<Biii", 3, a, b, c)
    write(f"{out}/ply/octahedron_binary.ply", binary)


def obj_text(with_uv_normals):
    s = "".join(f"v {x} {y} {z} {r / 255:.3f} {g / 255:.3f} {b / 255:.3f}\n"
                for (x, y, z), (r, g, b) in zip(V, C))
    if with_uv_normals:
        s += "".join(f"vt {0.5 + 0.5 * x} {0.5 + 0.5 * y}\n" for x, y, _ in V)
        s += "".join(f"vn {x} {y} {z}\n" for x, y, z in V)
        s += "g panel\n"
        s += "".join(f"f {a + 1}/{a + 1}/{a + 1} {b + 1}/{b + 1}/{b + 1} {c + 1}/{c + 1}/{c + 1}\n"
                     for a, b, c in F)
    else:
        s += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
    return s


def obj_seeds(out, reader):
    write(f"{out}/{reader}/octahedron.obj", obj_text(False))
    write(f"{out}/{reader}/octahedron_vt_vn.obj", obj_text(True))


def glb_seed(out):
    idx = [i for face in F for i in face]
    blobs = [b"".join(struct.pack("<3f", *p) for p in V),
             b"".join(struct.pack("<3f", *(c / 255 for c in col)) for col in C),
             struct.pack(f"<{len(idx)}H", *idx)]
    views, offset = [], 0
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
        offset += (len(b) + 3) // 4 * 4
    binary = b"".join(b + b"\0" * ((-len(b)) % 4) for b in blobs)
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"},
        ],
    }
    js = json.dumps(gltf).encode()
    js += b" " * ((-len(js)) % 4)
    chunks = struct.pack("<II", len(js), 0x4E4F534A) + js
    chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    write(f"{out}/glb/octahedron.glb", struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)


def json_seeds(out):
    body = {"source": "mannequin", "shape": {}, "pose": {"left_elbow": [0, 0.3, 0]},
            "translation": [0, 0, 0]}
    write(f"{out}/body_json/body.json", json.dumps(body, indent=1))
    people = [0.0] * 100
    for i in range(25):
        people[4 * i: 4 * i + 4] = [0.01 * i, 1.0 - 0.04 * i, 0.0, 0.9 if i % 7 else 0.0]
    write(f"{out}/keypoints/openpose_body25.json",
          json.dumps({"version": 1.3, "people": [{"pose_keypoints_3d": people}]}))
    named = {"pelvis": [0, 0.95, 0], "left_wrist": [0.6, 1.0, 0, 1.0], "right_wrist": None,
             "neck": [0, 1.45, 0], "left_ankle": [0.1, 0.08, 0], "right_ankle": [-0.1, 0.08, 0]}
    write(f"{out}/keypoints/named.json", json.dumps({"joints": named}))


def npy(shape, dtype, values):
    """One array in NumPy's .npy format (version 1.0, C order)."""
    header = f"{{'descr': '{dtype}', 'fortran_order': False, 'shape': {tuple(shape)}, }}"
    header += " " * ((-(10 + len(header) + 1)) % 64) + "\n"
    code = {"<f8": "d", "<i8": "q", "<u4": "I"}[dtype]
    return (b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() +
            struct.pack(f"<{len(values)}{code}", *values))


def npz_seed(out):
    # A 3-joint, 6-vertex SMPL-like model (the octahedron, two shape directions).
    nv, nj = len(V), 3
    arrays = {
        "v_template": npy((nv, 3), "<f8", [c for p in V for c in p]),
        "shapedirs": npy((nv, 3, 2), "<f8", [0.01] * (nv * 6)),
        "posedirs": npy((nv, 3, 9 * (nj - 1)), "<f8", [0.0] * (nv * 3 * 9 * (nj - 1))),
        "J_regressor": npy((nj, nv), "<f8", [1.0 / nv] * (nj * nv)),
        "weights": npy((nv, nj), "<f8", [0.6, 0.3, 0.1] * nv),
        "kintree_table": npy((2, nj), "<i8", [-1, 0, 1, 0, 1, 2]),
        "f": npy((len(F), 3), "<u4", [i for face in F for i in face]),
    }
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, data in arrays.items():
            z.writestr(name + ".npy", data)
    write(f"{out}/npz/tiny_smpl.npz", buf.getvalue())


def mpfb2_seeds(out, folder):
    base = os.path.join(folder, "3dobjs", "base.obj")
    target = os.path.join(folder, "targets", "buttocks", "buttocks-volume-incr.target.gz")
    if not (os.path.isfile(base) and os.path.isfile(target)):
        print(f"make_seeds: no MPFB2 model at {folder}: mpfb2_obj and mpfb2_target skipped",
              file=sys.stderr)
        return
    with open(base, "rb") as f:
        head = f.read(3072)
    write(f"{out}/mpfb2_obj/base_head.obj", head[: head.rfind(b"\n") + 1])
    with gzip.open(target, "rb") as f:
        lines = f.read().splitlines(keepends=True)[:40]
    write(f"{out}/mpfb2_target/head.target", b"".join(lines))
    write(f"{out}/mpfb2_target/head.target.gz", gzip.compress(b"".join(lines)))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--mpfb2", default=os.path.join(here, "..", "..", "shared", "bodymodels",
                                                    "mpfb2"))
    a = ap.parse_args()
    ply_seeds(a.out)
    obj_seeds(a.out, "obj")
    obj_seeds(a.out, "garment_obj")
    glb_seed(a.out)
    json_seeds(a.out)
    npz_seed(a.out)
    mpfb2_seeds(a.out, a.mpfb2)
    print(f"make_seeds: seeds in {a.out}/<reader>/")


if __name__ == "__main__":
    main()
