#!/usr/bin/env python3
"""Writes assets/cornell_box/cornell_box.gltf: the project's own Cornell box.

A 2 x 2 x 2 m room (floor at y = 0, open towards +Z where the camera stands),
red left wall, green right wall, white floor/ceiling/back, a short and a tall
block, and a 0.5 x 0.5 m ceiling light of radiance 17 x (1, 0.72, 0.24) W/(sr m^2)
(KHR_materials_emissive_strength), whose normal faces down. Metres, Y up.
Only the Python standard library is used; the output is committed, so users
need nothing but the repository to run the demo.
"""
import base64
import json
import math
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))


def quad(a, b, c, d):
    """Two CCW triangles a-b-c, a-c-d; the normal follows the right-hand rule."""
    n = cross(sub(b, a), sub(c, a))
    length = math.sqrt(dot(n, n))
    n = tuple(x / length for x in n)
    return [a, b, c, d], [n] * 4, [0, 1, 2, 0, 2, 3]


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def block(cx, cz, w, h, d, angle):
    """An axis-aligned block rotated about Y, as 5 outward-facing quads (no bottom)."""
    c, s = math.cos(angle), math.sin(angle)

    def p(x, y, z):
        return (cx + c * x + s * z, y, cz - s * x + c * z)

    hw, hd = w / 2, d / 2
    faces = [
        quad(p(-hw, h, -hd), p(-hw, h, hd), p(hw, h, hd), p(hw, h, -hd)),    # top (+Y)
        quad(p(-hw, 0, hd), p(hw, 0, hd), p(hw, h, hd), p(-hw, h, hd)),      # +Z
        quad(p(hw, 0, -hd), p(-hw, 0, -hd), p(-hw, h, -hd), p(hw, h, -hd)),  # -Z
        quad(p(hw, 0, hd), p(hw, 0, -hd), p(hw, h, -hd), p(hw, h, hd)),      # +X
        quad(p(-hw, 0, -hd), p(-hw, 0, hd), p(-hw, h, hd), p(-hw, h, -hd)),  # -X
    ]
    return merge(faces)


def merge(parts):
    pos, nrm, idx = [], [], []
    for p, n, i in parts:
        base = len(pos)
        pos += p
        nrm += n
        idx += [base + k for k in i]
    return pos, nrm, idx


# Room faces point inwards.
meshes = {
    "floor": (quad((-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)), "white"),
    "ceiling": (quad((-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1)), "white"),
    "back": (quad((-1, 0, -1), (1, 0, -1), (1, 2, -1), (-1, 2, -1)), "white"),
    "left": (quad((-1, 0, 1), (-1, 0, -1), (-1, 2, -1), (-1, 2, 1)), "red"),
    "right": (quad((1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1)), "green"),
    "light": (quad((-0.25, 1.999, -0.25), (0.25, 1.999, -0.25), (0.25, 1.999, 0.25), (-0.25, 1.999, 0.25)), "light"),
    "short_block": (block(0.33, 0.3, 0.6, 0.6, 0.6, -0.3), "white"),
    "tall_block": (block(-0.35, -0.3, 0.6, 1.2, 0.6, 0.3), "white"),
}
materials = {
    "white": {"pbrMetallicRoughness": {"baseColorFactor": [0.73, 0.73, 0.73, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "red": {"pbrMetallicRoughness": {"baseColorFactor": [0.63, 0.065, 0.05, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "green": {"pbrMetallicRoughness": {"baseColorFactor": [0.14, 0.45, 0.091, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "light": {"pbrMetallicRoughness": {"baseColorFactor": [0.78, 0.78, 0.78, 1], "metallicFactor": 0, "roughnessFactor": 1},
              "emissiveFactor": [1.0, 0.72, 0.24],
              "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 17.0}}},
}
material_index = {name: i for i, name in enumerate(materials)}

blob = bytearray()
gltf = {
    "asset": {"version": "2.0", "generator": "assets/make_cornell_box.py"},
    "extensionsUsed": ["KHR_materials_emissive_strength"],
    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "accessors": [], "bufferViews": [],
    "materials": [dict(name=name, **m) for name, m in materials.items()],
}


def add_view(data, target):
    while len(blob) % 4:
        blob.append(0)
    gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
    blob.extend(data)
    return len(gltf["bufferViews"]) - 1


def add_accessor(values, fmt, comp, kind, target, minmax=False):
    flat = [x for v in values for x in (v if isinstance(v, tuple) else (v,))]
    view = add_view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target)
    acc = {"bufferView": view, "componentType": comp, "count": len(values), "type": kind}
    if minmax:
        acc["min"] = [min(v[i] for v in values) for i in range(3)]
        acc["max"] = [max(v[i] for v in values) for i in range(3)]
    gltf["accessors"].append(acc)
    return len(gltf["accessors"]) - 1


for name, ((pos, nrm, idx), mat) in meshes.items():
    p = add_accessor(pos, "f", 5126, "VEC3", 34962, minmax=True)
    n = add_accessor(nrm, "f", 5126, "VEC3", 34962)
    i = add_accessor(idx, "H", 5123, "SCALAR", 34963)
    gltf["meshes"].append({"name": name, "primitives": [
        {"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": material_index[mat]}]})
    gltf["nodes"].append({"name": name, "mesh": len(gltf["meshes"]) - 1})

# Camera 3.9 m in front of the opening, looking down -Z at the room's centre.
gltf["cameras"] = [{"type": "perspective", "name": "front",
                    "perspective": {"yfov": 0.6860, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}]
gltf["nodes"].append({"name": "front", "camera": 0, "translation": [0.0, 1.0, 3.9]})
gltf["scenes"][0]["nodes"] = list(range(len(gltf["nodes"])))
gltf["buffers"] = [{"byteLength": len(blob), "uri": "cornell_box.bin"}]

out = os.path.join(here, "cornell_box")
os.makedirs(out, exist_ok=True)
with open(os.path.join(out, "cornell_box.bin"), "wb") as f:
    f.write(blob)
with open(os.path.join(out, "cornell_box.gltf"), "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
print("wrote", os.path.join(out, "cornell_box.gltf"), len(blob), "bytes of geometry")
