#!/usr/bin/env python3
"""Fuzz tier (issue 16): a seeded, deterministic generator of malformed and
extreme glTF / GLB files, each run through rtgi-bench headless.

Every file must end in a clean exit within 5 s, never a signal:
  0      valid-but-odd files (the scene loads; rendered at 16x16 for a few),
  2 / 3  bad files, with one error sentence on stderr that names the file.
Classes: wrong JSON types, indices out of range (-1, n, 2.5, strings), numbers
beyond float (1e300, 1e-300, 1e38, 1e-45) in lights, cameras, materials,
transforms and vertices, broken structure (missing members, duplicate
children, two parents, cycles), accessor/bufferView ranges, GLB containers,
truncated and bit-flipped files. Usage:
  gltf_fuzz.py --bench build/rtgi-bench [--count 300] [--seed 16] [--jobs 2] [--keep DIR]
"""
import argparse
import base64
import concurrent.futures
import copy
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time

F32, U16, U8, U32 = 5126, 5123, 5121, 5125


def base_asset():
    """Quad facing +z lit by a sun, seen by a camera: a valid file."""
    pos = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
    nrm = [0, 0, 1] * 4
    uv = [0, 0, 1, 0, 1, 1, 0, 1]
    idx = [0, 1, 2, 0, 2, 3]
    binary = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<8f", *uv) + struct.pack("<6H", *idx)
    binary += b"\0" * ((4 - len(binary) % 4) % 4)
    doc = {
        "asset": {"version": "2.0", "generator": "rtgi gltf_fuzz.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0, "name": "quad"},
            {"camera": 0, "translation": [0.5, 0.5, 3.0]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [-0.3826834, 0, 0, 0.9238795]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 100.0}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1, 1, 1], "intensity": 3.0}]}},
        "materials": [{"name": "grey", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                                                 "metallicFactor": 0.0, "roughnessFactor": 0.6},
                       "emissiveFactor": [0, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                    "material": 0, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": F32, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": F32, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": F32, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": U16, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12},
        ],
        "buffers": [{"byteLength": len(binary)}],
    }
    return doc, binary


def embed(doc, binary):
    d = copy.deepcopy(doc)
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(binary).decode()
    d["buffers"][0]["byteLength"] = len(binary)
    return json.dumps(d).encode()


def glb(doc, binary):
    d = copy.deepcopy(doc)
    d["buffers"][0].pop("uri", None)
    d["buffers"][0]["byteLength"] = len(binary)
    text = json.dumps(d).encode()
    text += b" " * ((4 - len(text) % 4) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def set_path(doc, path, value):
    """path: list of keys / indices; creates nothing (the path must exist up to its parent)."""
    cur = doc
    for k in path[:-1]:
        cur = cur[k]
    cur[path[-1]] = value


# Members with the JSON type the schema gives them (path, a valid value).
TYPED = [
    (["scene"], 0), (["scenes", 0, "nodes"], [0, 1, 2]), (["nodes", 0, "mesh"], 0), (["nodes", 1, "camera"], 0),
    (["nodes", 0, "children"], None), (["nodes", 1, "translation"], [0.5, 0.5, 3.0]),
    (["nodes", 2, "rotation"], [-0.38, 0, 0, 0.92]), (["nodes", 0, "scale"], [1, 1, 1]),
    (["nodes", 0, "matrix"], None), (["nodes", 0, "name"], "quad"), (["nodes", 0, "extensions"], None),
    (["meshes", 0, "primitives"], None), (["meshes", 0, "primitives", 0, "attributes"], None),
    (["meshes", 0, "primitives", 0, "indices"], 3), (["meshes", 0, "primitives", 0, "material"], 0),
    (["meshes", 0, "primitives", 0, "mode"], 4), (["materials", 0, "pbrMetallicRoughness"], None),
    (["materials", 0, "pbrMetallicRoughness", "baseColorFactor"], None),
    (["materials", 0, "pbrMetallicRoughness", "metallicFactor"], 0.0),
    (["materials", 0, "pbrMetallicRoughness", "roughnessFactor"], 0.6), (["materials", 0, "emissiveFactor"], None),
    (["materials", 0, "doubleSided"], False), (["materials", 0, "alphaMode"], "OPAQUE"),
    (["accessors", 0, "componentType"], F32), (["accessors", 0, "count"], 4), (["accessors", 0, "type"], "VEC3"),
    (["accessors", 0, "bufferView"], 0), (["accessors", 0, "byteOffset"], 0), (["accessors", 0, "normalized"], False),
    (["accessors", 0, "min"], None), (["bufferViews", 0, "buffer"], 0), (["bufferViews", 0, "byteLength"], 48),
    (["bufferViews", 0, "byteOffset"], 0), (["bufferViews", 0, "byteStride"], 12), (["buffers", 0, "byteLength"], 140),
    (["cameras", 0, "type"], "perspective"), (["cameras", 0, "perspective"], None),
    (["cameras", 0, "perspective", "yfov"], 0.8), (["cameras", 0, "perspective", "znear"], 0.05),
    (["cameras", 0, "perspective", "zfar"], 100.0), (["extensions", "KHR_lights_punctual", "lights"], None),
    (["extensions", "KHR_lights_punctual", "lights", 0, "color"], None),
    (["extensions", "KHR_lights_punctual", "lights", 0, "intensity"], 3.0),
    (["extensions", "KHR_lights_punctual", "lights", 0, "type"], "directional"),
    (["nodes", 2, "extensions", "KHR_lights_punctual"], None), (["nodes", 2, "extensions", "KHR_lights_punctual", "light"], 0),
    (["asset", "version"], "2.0"), (["extensionsUsed"], None),
]
WRONG = ["TRIANGLES", "0", "red", 1, 2.5, -1, True, None, [], [1], {}, {"a": 1}, [0, "x"], 1e300]

INDEX_PATHS = [["scene"], ["scenes", 0, "nodes", 0], ["nodes", 0, "mesh"], ["nodes", 1, "camera"],
               ["meshes", 0, "primitives", 0, "indices"], ["meshes", 0, "primitives", 0, "material"],
               ["meshes", 0, "primitives", 0, "attributes", "POSITION"], ["accessors", 0, "bufferView"],
               ["bufferViews", 0, "buffer"], ["nodes", 2, "extensions", "KHR_lights_punctual", "light"]]
BAD_INDICES = [-1, -2, 4, 99, 2.5, 1e20, "0", 2 ** 31, 2 ** 32]

# Numbers finite in double but not usable as float (or out of the supported range).
EXTREME = [1e300, -1e300, 1e-300, 1e38, 3.5e38, 1e-45, 0.0, -0.0, -1.0, 1e30, 1e15, 1e16]
NUMBER_PATHS = [["extensions", "KHR_lights_punctual", "lights", 0, "intensity"],
                ["extensions", "KHR_lights_punctual", "lights", 0, "color", 0],
                ["extensions", "KHR_lights_punctual", "lights", 0, "range"],
                ["cameras", 0, "perspective", "yfov"], ["cameras", 0, "perspective", "znear"],
                ["cameras", 0, "perspective", "zfar"], ["materials", 0, "pbrMetallicRoughness", "baseColorFactor", 0],
                ["materials", 0, "pbrMetallicRoughness", "roughnessFactor"], ["materials", 0, "emissiveFactor", 1],
                ["nodes", 1, "translation", 2], ["nodes", 0, "scale", 0], ["nodes", 0, "translation", 0],
                ["nodes", 2, "rotation", 3], ["nodes", 0, "matrix", 0], ["nodes", 0, "matrix", 12]]


def mutate_typed(rng, doc, binary):
    path, _ = rng.choice(TYPED)
    ensure_parent(doc, path)
    set_path(doc, path, rng.choice(WRONG))
    return "type " + "/".join(map(str, path)), embed(doc, binary)


def ensure_parent(doc, path):
    cur = doc
    for i, k in enumerate(path[:-1]):
        nxt = path[i + 1]
        if isinstance(cur, dict) and k not in cur:
            cur[k] = [] if isinstance(nxt, int) else {}
        if isinstance(cur, list):
            while len(cur) <= k:
                cur.append({})
        cur = cur[k]
    if isinstance(cur, list):
        while len(cur) <= path[-1]:
            cur.append(0)


def mutate_index(rng, doc, binary):
    path = rng.choice(INDEX_PATHS)
    set_path(doc, path, rng.choice(BAD_INDICES))
    return "index " + "/".join(map(str, path)), embed(doc, binary)


def mutate_number(rng, doc, binary):
    path = rng.choice(NUMBER_PATHS)
    if path[-2] == "matrix" or path[1:2] == ["matrix"]:
        doc["nodes"][0]["matrix"] = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    if path[:3] == ["nodes", 0, "scale"]:
        doc["nodes"][0]["scale"] = [1, 1, 1]
    if path[:3] == ["nodes", 0, "translation"]:
        doc["nodes"][0]["translation"] = [0, 0, 0]
    if path[-1] == "range":
        doc["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = 1.0
    if path[:3] == ["nodes", 0, "matrix"] and ("translation" in doc["nodes"][0]):
        del doc["nodes"][0]["translation"]
    set_path(doc, path, rng.choice(EXTREME))
    return "number " + "/".join(map(str, path)), embed(doc, binary)


def mutate_vertices(rng, doc, binary):
    v = rng.choice([1e38, 3e38, 5e9, -4e9, 1e16, 1e-40, float("inf"), float("nan"), 0.0])
    b = bytearray(binary)
    k = rng.randrange(12)
    struct.pack_into("<f", b, 4 * k, v)
    if rng.random() < 0.5:  # huge but valid triangles: edges > 4e9 (float cross product overflows)
        for i, s in enumerate([0, 0, 0, 5e9, 0, 0, 5e9, 5e9, 0, 0, 5e9, 0]):
            struct.pack_into("<f", b, 4 * i, s)
    return "vertex %r" % v, embed(doc, bytes(b))


def mutate_structure(rng, doc, binary):
    kind = rng.randrange(10)
    if kind == 0:
        doc["nodes"][0]["children"] = [1, 1]
    elif kind == 1:
        doc["nodes"][0]["children"] = [1]
        doc["nodes"][2]["children"] = [1]
    elif kind == 2:
        doc["nodes"][0]["children"] = [0]
    elif kind == 3:  # the instance bomb of issue 16: every node lists the next twice
        doc["nodes"] = [{"children": [i + 1, i + 1]} for i in range(40)] + [{"mesh": 0}]
        doc["scenes"] = [{"nodes": [0]}]
    elif kind == 4:  # the same bomb as a DAG without duplicates
        doc["nodes"] = [{"children": [i + 1, i + 2]} for i in range(40)] + [{"mesh": 0}, {"mesh": 0}]
        doc["scenes"] = [{"nodes": [0]}]
    elif kind == 5:
        del doc[rng.choice(["asset", "meshes", "accessors", "bufferViews", "buffers"])]
    elif kind == 6:
        del doc["accessors"][rng.randrange(4)][rng.choice(["componentType", "count", "type"])]
    elif kind == 7:
        doc["accessors"][rng.randrange(4)]["count"] = rng.choice([0, 5, 1000, 2 ** 31, 2 ** 40])
    elif kind == 8:
        doc["bufferViews"][rng.randrange(4)]["byteOffset"] = rng.choice([4, 139, 140, 2 ** 32, 2 ** 62])
    else:
        doc["bufferViews"][rng.randrange(4)]["byteStride"] = rng.choice([1, 3, 4, 253, 256, 1000])
    return "structure %d" % kind, embed(doc, binary)


def mutate_glb(rng, doc, binary):
    data = bytearray(glb(doc, binary))
    kind = rng.randrange(6)
    if kind == 0:
        struct.pack_into("<I", data, 8, rng.choice([0, 12, len(data) + 1, 2 ** 32 - 1]))
    elif kind == 1:
        struct.pack_into("<I", data, 12, rng.choice([0, 3, len(data), 2 ** 32 - 1]))
    elif kind == 2:
        struct.pack_into("<I", data, 16, rng.choice([0, 0x004E4942, 0x12345678]))
    elif kind == 3:
        data = data[: rng.randrange(1, len(data))]
    elif kind == 4:
        struct.pack_into("<I", data, 4, rng.choice([1, 3, 0]))
    else:
        for _ in range(rng.randrange(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
    return "glb %d" % kind, bytes(data)


def mutate_text(rng, doc, binary):
    text = bytearray(embed(doc, binary))
    kind = rng.randrange(4)
    if kind == 0:
        text = text[: rng.randrange(1, len(text))]
    elif kind == 1:
        for _ in range(rng.randrange(1, 6)):
            text[rng.randrange(len(text))] = rng.choice(b'{}[]",:0-e.x\x00\xff')
    elif kind == 2:
        text = b"[" * 100000
    else:
        text = b""
    return "text %d" % kind, bytes(text)


def valid_odd(rng, doc, binary):
    """Valid files at the edges of what is supported: must load (exit 0)."""
    kind = rng.randrange(6)
    if kind == 0:
        doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = rng.choice([1e-30, 1e20, 0.0])
    elif kind == 1:
        doc["cameras"][0]["perspective"]["yfov"] = rng.choice([0.0088, 3.05])
    elif kind == 2:
        doc["cameras"][0]["perspective"].pop("zfar")
    elif kind == 3:
        doc["nodes"][0]["scale"] = [1e6, 1e6, 1e6]
    elif kind == 4:
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = [5.0, -1.0, 0.5, 1.0]
    else:
        doc["nodes"][0]["extras"] = {"anything": [1, "x", None]}
    return "valid-odd %d" % kind, embed(doc, binary)


CLASSES = [mutate_typed, mutate_index, mutate_number, mutate_vertices, mutate_structure, mutate_glb, mutate_text,
           valid_odd]


def generate(count, seed, outdir):
    rng = random.Random(seed)
    files = []
    for i in range(count):
        cls = CLASSES[i % len(CLASSES)]
        doc, binary = base_asset()
        label, data = cls(rng, doc, binary)
        ext = ".glb" if data[:4] == b"glTF" or cls is mutate_glb else ".gltf"
        path = os.path.join(outdir, "fuzz%03d%s" % (i, ext))
        with open(path, "wb") as f:
            f.write(data)
        files.append((path, cls.__name__, label))
    return files


def run_one(bench, path, render):
    args = [bench, "--scene", path, "--res", "16x16", "--frames", "1", "--warmup", "0", "--no-images",
            "--out", os.path.join(os.path.dirname(path), "out-" + os.path.basename(path))]
    if not render:
        args.append("--validate-only")
    # Bad input must end within 5 s (docs/STABILITY.md); a valid file that is
    # rendered compiles every shader of the frame on llvmpipe, which under a
    # loaded 2-core CI machine takes longer, so it gets 30 s.
    limit = 30 if render else 5
    t0 = time.monotonic()
    try:
        p = subprocess.run(args, capture_output=True, text=True, errors="replace", timeout=limit)
    except subprocess.TimeoutExpired:
        return "timeout (more than %d s)" % limit, None, float(limit)
    dt = time.monotonic() - t0
    return p.returncode, p.stderr, dt


def check(path, cls, label, rc, stderr, dt):
    if isinstance(rc, str):  # a timeout
        return rc
    if rc < 0:
        return "killed by signal %d" % -rc
    if rc not in (0, 2, 3):
        return "exit %d (expected 0, 2 or 3)" % rc
    if cls == "valid_odd" and rc != 0:
        return "a valid file was rejected: " + stderr.strip()
    if rc != 0:
        errors = [l for l in stderr.splitlines() if l.startswith("rtgi-bench:") and ": warning:" not in l]
        if len(errors) != 1:
            return "expected one error line, got %d: %r" % (len(errors), stderr)
        if path not in errors[0]:
            return "the error does not name the file: " + errors[0]
        if "json.exception" in errors[0]:
            return "raw parser text: " + errors[0]
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", required=True)
    ap.add_argument("--count", type=int, default=320)
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--render", type=int, default=6, help="valid files also rendered at 16x16 (the rest: --validate-only)")
    ap.add_argument("--keep", help="write the files here and keep them")
    a = ap.parse_args()
    outdir = a.keep or tempfile.mkdtemp(prefix="rtgi-fuzz-")
    os.makedirs(outdir, exist_ok=True)
    try:
        files = generate(a.count, a.seed, outdir)
        rendered = set(p for p, c, _ in files if c == "valid_odd")
        rendered = set(sorted(rendered)[: a.render])
        t0 = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
            results = list(ex.map(lambda f: run_one(a.bench, f[0], f[0] in rendered), files))
        failures, outcomes = [], {}
        for (path, cls, label), (rc, stderr, dt) in zip(files, results):
            why = check(path, cls, label, rc, stderr, dt)
            outcomes.setdefault(cls, {}).setdefault(str(rc), 0)
            outcomes[cls][str(rc)] += 1
            if why:
                failures.append("%s (%s, %s): %s" % (os.path.basename(path), cls, label, why))
        total = time.monotonic() - t0
        print("fuzz: %d files (seed %d) in %.1f s; exit codes per class: %s" % (len(files), a.seed, total,
                                                                               json.dumps(outcomes, sort_keys=True)))
        slowest = max(r[2] for r in results)
        print("fuzz: slowest file %.2f s" % slowest)
        for f in failures:
            print("FAIL " + f)
        return 1 if failures else 0
    finally:
        if not a.keep:
            shutil.rmtree(outdir, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
