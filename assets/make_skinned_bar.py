#!/usr/bin/env python3
"""Writes assets/skinned_bar/skinned_bar.gltf: a skinned bar that bends (issue 32's deforming mesh).

A room open towards the camera (floor 4 x 4 m at y = 0, x and z in [-2, 2]; a white back wall at z = -2,
a red left wall at x = -2, a blue right wall at x = 2, all 2.8 m high, facing inwards), lit by one point
light of 6 cd at (0, 2.6, 0.5). In its middle stands a 0.2 x 0.2 x 1.6 m bar (x and z in [-0.1, 0.1],
y in [0, 1.6]) of 16 segments, skinned to two joints: `bar_root` at the origin and its child `bar_bend` at
(0, 0.8, 0), whose inverse bind matrix is a translation by (0, -0.8, 0). A vertex at height y weighs
`bar_bend` by smoothstep(0.6, 1.0, y) and `bar_root` by the rest. One animation, `bar_bend`, turns that joint
about +Z from 0 to 90 degrees over the first second and back over the next (LINEAR, rotation keys at
0, 1 and 2 s), so the bar's top half bends over towards -X and straightens again, every 2 s.
The camera stands at (0, 1.1, 4.2) looking down -Z. Metres, Y up. tests/skinning_test.cpp poses the bar
on the CPU from these numbers (an oracle independent of the engine's animation code).
Only the Python standard library is used; the output is committed.
"""
import os

from gltf_writer import Gltf, add_skinned_bar, quad

here = os.path.dirname(os.path.abspath(__file__))
HALF, HEIGHT, SEGMENTS, BEND_Y = 0.1, 1.6, 16, 0.8


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

# The bar, bending 90 degrees over the first second and back over the next.
roots += add_skinned_bar(gltf, "bar", "bar", (0.0, 0.0, 0.0), HALF, HEIGHT, SEGMENTS, BEND_Y, (0.6, 1.0), 2.0, 90.0)

gltf.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
    {"name": "lamp", "type": "point", "color": [1.0, 0.9, 0.8], "intensity": 6.0}]}}
roots.append(len(gltf.doc["nodes"]))
gltf.node({"name": "lamp", "translation": [0, 2.6, 0.5], "extensions": {"KHR_lights_punctual": {"light": 0}}})
gltf.doc["cameras"] = [{"type": "perspective", "name": "front",
                        "perspective": {"yfov": 0.75, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}]
roots.append(len(gltf.doc["nodes"]))
gltf.node({"name": "front", "camera": 0, "translation": [0.0, 1.1, 4.2]})
gltf.write(os.path.join(here, "skinned_bar"), "skinned_bar", roots)
