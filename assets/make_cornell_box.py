#!/usr/bin/env python3
"""Writes assets/cornell_box/cornell_box.gltf: the project's own Cornell box.

A 2 x 2 x 2 m room (floor at y = 0, open towards +Z where the camera stands),
red left wall, green right wall, white floor/ceiling/back, a short and a tall
block, and a 0.5 x 0.5 m ceiling light of radiance 17 x (1, 0.72, 0.24) W/(sr m^2)
(KHR_materials_emissive_strength), whose normal faces down. Metres, Y up.

It moves (glTF animations, an 8 s loop, what the demo walks through): the
ceiling light circles 0.3 m wide in its plane, the short block turns about its
vertical axis by up to 45 degrees either way (the engine's built-in motion,
engine/animation.h, written into the file), and an orange bar (0.1 x 0.1 x 0.9 m
at x = -0.5, z = 0.5) skinned to two joints bends 60 degrees towards the red
wall and back every 4 s (a deforming mesh: gltf_writer.add_skinned_bar).
Only the Python standard library is used; the output is committed, so users
need nothing but the repository to run the demo.
"""
import os

import math

from gltf_writer import Gltf, add_skinned_bar, block, quad

here = os.path.dirname(os.path.abspath(__file__))

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
    "bar": {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.45, 0.12, 1], "metallicFactor": 0, "roughnessFactor": 0.9}},
}

gltf = Gltf("assets/make_cornell_box.py", ["KHR_materials_emissive_strength"])
gltf.materials(materials)
for name, (geometry, material) in meshes.items():
    gltf.mesh(name, geometry, material)

roots = list(range(len(gltf.doc["nodes"])))

# The light circles and the short block turns: 33 keys over 8 s (LINEAR), as engine/animation.h moves them.
PERIOD, RADIUS, KEYS = 8.0, 0.3, 33
BLOCK_CENTRE = (0.33, 0.3, 0.3)
times, light, block_t, block_r = [], [], [], []
for k in range(KEYS):
    t = PERIOD * k / (KEYS - 1)
    phase = 2 * math.pi * k / (KEYS - 1)
    times.append(t)
    light.append((RADIUS * math.cos(phase) - RADIUS, 0.0, RADIUS * math.sin(phase)))
    angle = 0.785 * math.sin(phase)
    c, s_ = math.cos(angle), math.sin(angle)
    cx, cy, cz = BLOCK_CENTRE  # turning about the centre: translation c - R c
    block_t.append((cx - (c * cx + s_ * cz), 0.0, cz - (-s_ * cx + c * cz)))
    block_r.append((0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)))
node = {n["name"]: i for i, n in enumerate(gltf.doc["nodes"])}
key = gltf.accessor(times, "f", 5126, "SCALAR")
gltf.doc["accessors"][key].update(min=[0.0], max=[PERIOD])
samplers = [{"input": key, "output": gltf.accessor(v, "f", 5126, kind), "interpolation": "LINEAR"}
            for v, kind in ((light, "VEC3"), (block_t, "VEC3"), (block_r, "VEC4"))]
gltf.doc["animations"] = [{"name": "light_and_block", "samplers": samplers, "channels": [
    {"sampler": 0, "target": {"node": node["light"], "path": "translation"}},
    {"sampler": 1, "target": {"node": node["short_block"], "path": "translation"}},
    {"sampler": 2, "target": {"node": node["short_block"], "path": "rotation"}}]}]

roots += add_skinned_bar(gltf, "bar", "bar", (-0.5, 0.0, 0.5), 0.05, 0.9, 12, 0.45, (0.3, 0.6), 4.0, 60.0)

# Camera 3.9 m in front of the opening, looking down -Z at the room's centre.
gltf.doc["cameras"] = [{"type": "perspective", "name": "front",
                        "perspective": {"yfov": 0.6860, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}]
roots.append(len(gltf.doc["nodes"]))
gltf.node({"name": "front", "camera": 0, "translation": [0.0, 1.0, 3.9]})
gltf.write(os.path.join(here, "cornell_box"), "cornell_box", roots)
