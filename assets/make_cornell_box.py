#!/usr/bin/env python3
"""Writes assets/cornell_box/cornell_box.gltf: the project's own Cornell box.

A 2 x 2 x 2 m room (floor at y = 0, open towards +Z where the camera stands),
red left wall, green right wall, white floor/ceiling/back, a short and a tall
block, and a 0.5 x 0.5 m ceiling light of radiance 17 x (1, 0.72, 0.24) W/(sr m^2)
(KHR_materials_emissive_strength), whose normal faces down. Metres, Y up.
Only the Python standard library is used; the output is committed, so users
need nothing but the repository to run the demo.
"""
import os

from gltf_writer import Gltf, block, quad

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
}

gltf = Gltf("assets/make_cornell_box.py", ["KHR_materials_emissive_strength"])
gltf.materials(materials)
for name, (geometry, material) in meshes.items():
    gltf.mesh(name, geometry, material)

# Camera 3.9 m in front of the opening, looking down -Z at the room's centre.
gltf.doc["cameras"] = [{"type": "perspective", "name": "front",
                        "perspective": {"yfov": 0.6860, "aspectRatio": 1.0, "znear": 0.01, "zfar": 100.0}}]
gltf.node({"name": "front", "camera": 0, "translation": [0.0, 1.0, 3.9]})
gltf.write(os.path.join(here, "cornell_box"), "cornell_box")
