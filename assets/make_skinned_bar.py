#!/usr/bin/env python3
"""Writes assets/skinned_bar/skinned_bar.gltf: a skinned bar that bends (issue 32's deforming mesh).

A room open towards the camera (floor 4 x 4 m at y = 0, x and z in [-2, 2]; a white back wall at z = -2,
a red left wall at x = -2, a blue right wall at x = 2, all 2.8 m high, facing inwards), lit by one point
light of 6 cd at (0, 2.6, 0.5). In its middle stands a 0.2 x 0.2 x 1.6 m bar (x and z in [-0.1, 0.1],
y in [0, 1.6]) of 16 segments, skinned to two joints: `root` at the origin and its child `bend` at
(0, 0.8, 0), whose inverse bind matrix is a translation by (0, -0.8, 0). A vertex at height y weighs
`bend` by smoothstep(0.6, 1.0, y) and `root` by the rest. One animation, `bend`, turns the joint `bend`
about +Z from 0 to 90 degrees over the first second and back over the next (LINEAR, rotation keys at
0, 1 and 2 s), so the bar's top half bends over towards -X and straightens again, every 2 s.
The camera stands at (0, 1.1, 4.2) looking down -Z. Metres, Y up. tests/skinning_test.cpp poses the bar
on the CPU from these numbers (an oracle independent of the engine's animation code).
Only the Python standard library is used; the output is committed.
"""
import math
import os
import struct

from gltf_writer import Gltf, quad

here = os.path.dirname(os.path.abspath(__file__))
HALF, HEIGHT, SEGMENTS, BEND_Y = 0.1, 1.6, 16, 0.8


def smoothstep(a, b, x):
    t = min(max((x - a) / (b - a), 0.0), 1.0)
    return t * t * (3 - 2 * t)


def bar():
    """Four sides of SEGMENTS rows each (their own vertices: flat normals) and a top cap."""
    pos, nrm, idx = [], [], []
    sides = [((1, 0, 0), (HALF, -HALF), (HALF, HALF)), ((-1, 0, 0), (-HALF, HALF), (-HALF, -HALF)),
             ((0, 0, 1), (-HALF, HALF), (HALF, HALF)), ((0, 0, -1), (HALF, -HALF), (-HALF, -HALF))]
    for normal, (ax, az), (bx, bz) in sides:
        base = len(pos)
        for row in range(SEGMENTS + 1):
            y = HEIGHT * row / SEGMENTS
            pos += [(ax, y, az), (bx, y, bz)]
            nrm += [normal, normal]
        for row in range(SEGMENTS):
            a, b, c, d = base + 2 * row, base + 2 * row + 1, base + 2 * row + 3, base + 2 * row + 2
            idx += [a, b, c, a, c, d]  # counter-clockwise seen from outside
    top = quad((-HALF, HEIGHT, HALF), (HALF, HEIGHT, HALF), (HALF, HEIGHT, -HALF), (-HALF, HEIGHT, -HALF))
    base = len(pos)
    pos += top[0]
    nrm += top[1]
    idx += [base + i for i in top[2]]
    return pos, nrm, idx


gltf = Gltf("make_skinned_bar.py", extensions=["KHR_lights_punctual"])
gltf.materials({
    "white": {"pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.75, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "red": {"pbrMetallicRoughness": {"baseColorFactor": [0.65, 0.08, 0.06, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "blue": {"pbrMetallicRoughness": {"baseColorFactor": [0.08, 0.12, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "bar": {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.55, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.8}},
})
H = 2.8
for name, geometry, material in [
        ("floor", quad((-2, 0, 2), (2, 0, 2), (2, 0, -2), (-2, 0, -2)), "white"),
        ("back_wall", quad((-2, 0, -2), (2, 0, -2), (2, H, -2), (-2, H, -2)), "white"),
        ("left_wall", quad((-2, 0, 2), (-2, 0, -2), (-2, H, -2), (-2, H, 2)), "red"),
        ("right_wall", quad((2, 0, -2), (2, 0, 2), (2, H, 2), (2, H, -2)), "blue")]:
    gltf.mesh(name, geometry, material)
roots = list(range(len(gltf.doc["nodes"])))

# The bar: its mesh with JOINTS_0 and WEIGHTS_0, placed by its skin alone.
pos, nrm, idx = bar()
weights = [smoothstep(0.6, 1.0, p[1]) for p in pos]
p = gltf.accessor(pos, "f", 5126, "VEC3", 34962)
gltf.doc["accessors"][p].update(min=[min(v[i] for v in pos) for i in range(3)], max=[max(v[i] for v in pos) for i in range(3)])
n = gltf.accessor(nrm, "f", 5126, "VEC3", 34962)
j = gltf.accessor([(0, 1, 0, 0)] * len(pos), "B", 5121, "VEC4", 34962)
w = gltf.accessor([(1 - b, b, 0.0, 0.0) for b in weights], "f", 5126, "VEC4", 34962)
i = gltf.accessor(idx, "H", 5123, "SCALAR", 34963)
gltf.doc["meshes"].append({"name": "bar", "primitives": [{
    "attributes": {"POSITION": p, "NORMAL": n, "JOINTS_0": j, "WEIGHTS_0": w}, "indices": i,
    "material": gltf.material_index["bar"]}]})
root = len(gltf.doc["nodes"])
gltf.node({"name": "root", "children": [root + 1]})
gltf.node({"name": "bend", "translation": [0, BEND_Y, 0]})
inverse_bind = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] + [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -BEND_Y, 0, 1]
ibm = gltf.accessor([tuple(inverse_bind[:16]), tuple(inverse_bind[16:])], "f", 5126, "MAT4")
gltf.doc["skins"] = [{"name": "bar", "joints": [root, root + 1], "skeleton": root, "inverseBindMatrices": ibm}]
gltf.node({"name": "bar", "mesh": len(gltf.doc["meshes"]) - 1, "skin": 0})
roots += [root, root + 2]

# Turn `bend` about +Z: 0, 90 and 0 degrees at 0, 1 and 2 s.
times = gltf.accessor([0.0, 1.0, 2.0], "f", 5126, "SCALAR")
gltf.doc["accessors"][times].update(min=[0.0], max=[2.0])
s45 = math.sin(math.radians(45))
turns = gltf.accessor([(0.0, 0.0, 0.0, 1.0), (0.0, 0.0, s45, s45), (0.0, 0.0, 0.0, 1.0)], "f", 5126, "VEC4")
gltf.doc["animations"] = [{"name": "bend", "samplers": [{"input": times, "output": turns, "interpolation": "LINEAR"}],
                           "channels": [{"sampler": 0, "target": {"node": root + 1, "path": "rotation"}}]}]

gltf.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
    {"name": "lamp", "type": "point", "color": [1.0, 0.9, 0.8], "intensity": 6.0}]}}
roots.append(len(gltf.doc["nodes"]))
gltf.node({"name": "lamp", "translation": [0, 2.6, 0.5], "extensions": {"KHR_lights_punctual": {"light": 0}}})
gltf.doc["cameras"] = [{"type": "perspective", "name": "front",
                        "perspective": {"yfov": 0.75, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}]
roots.append(len(gltf.doc["nodes"]))
gltf.node({"name": "front", "camera": 0, "translation": [0.0, 1.1, 4.2]})
gltf.write(os.path.join(here, "skinned_bar"), "skinned_bar", roots)
