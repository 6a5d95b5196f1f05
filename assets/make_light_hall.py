#!/usr/bin/env python3
"""Writes assets/light_hall/light_hall.gltf: a hall lit by 256 small point lights (issue 31's many-light scene).

A closed 12 x 5 x 24 m hall (floor at y = 0, x in [-6, 6], z in [-24, 0]; every surface faces inwards),
a red-brown left wall and a blue right wall to bleed colour, two rows of six pillars, and 256 warm point
lights (KHR_lights_punctual) on a 16 x 16 grid 0.4 m under the ceiling, 0.75 cd each (192 cd in all).
The camera stands at the near end, 1.7 m up, looking down the hall (-Z). Metres, Y up.
Only the Python standard library is used; the output is committed.

With --panels N --out DIR (scripts/bench emissive; not shipped): the same hall lit instead by N square
emissive panels 0.2 m wide just under the ceiling, on as square a grid as N allows, facing down, their
total power the 256 lamps' (4 pi W per cd; a one-sided Lambertian panel of area A and radiance L emits
pi L A): the many-emissive-triangle scene of issue 31, two triangles a panel.

With --lit K beside --panels N: the same N panels, of which only the K nearest to where a K-panel hall has
its panels emit (their total power the same); the others are dark, black as every panel's base colour. The
geometry of N panels with the light count of K: what more lights cost apart from more triangles.

With --spots N --out DIR (scripts/bench spots; not shipped): N spot lights instead of the lamps, on as
square a grid as N allows 0.4 m under the ceiling, 40 degree outer and 30 degree inner cones; every
other row aimed straight down, the others 50 degrees towards the nearer side wall (wall washers); their
total power the 256 lamps' (a spot of intensity I emits 2 pi (1 - cos outer) I): spot lights whose
cones the light tree must bound.

With --open (scripts/bench sky_reservoirs; not shipped): no ceiling, so that a sky lights the hall through
its roof and the walls and pillars shadow part of it: a courtyard lit by the same lamps (or panels, spots).
"""
import argparse
import math
import os

from gltf_writer import Gltf, block, merge, quad

here = os.path.dirname(os.path.abspath(__file__))
WIDTH, HEIGHT, LENGTH = 12.0, 5.0, 24.0
X0, X1, Z0, Z1 = -WIDTH / 2, WIDTH / 2, -LENGTH, 0.0
LIGHTS_X, LIGHTS_Z = 16, 16
CANDELA = 0.75
COLOUR = [1.0, 0.85, 0.7]

meshes = {
    "floor": (quad((X0, 0, Z1), (X1, 0, Z1), (X1, 0, Z0), (X0, 0, Z0)), "floor"),
    "ceiling": (quad((X0, HEIGHT, Z0), (X1, HEIGHT, Z0), (X1, HEIGHT, Z1), (X0, HEIGHT, Z1)), "white"),
    "far_wall": (quad((X0, 0, Z0), (X1, 0, Z0), (X1, HEIGHT, Z0), (X0, HEIGHT, Z0)), "white"),
    "near_wall": (quad((X1, 0, Z1), (X0, 0, Z1), (X0, HEIGHT, Z1), (X1, HEIGHT, Z1)), "white"),
    "left_wall": (quad((X0, 0, Z1), (X0, 0, Z0), (X0, HEIGHT, Z0), (X0, HEIGHT, Z1)), "red"),
    "right_wall": (quad((X1, 0, Z0), (X1, 0, Z1), (X1, HEIGHT, Z1), (X1, HEIGHT, Z0)), "blue"),
}
for row, x in (("left", -3.0), ("right", 3.0)):
    for k in range(6):
        meshes[f"pillar_{row}_{k}"] = (block(x, -3.5 - 3.4 * k, 0.6, HEIGHT, 0.6, 0.0), "stone")

materials = {
    "floor": {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "white": {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "red": {"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.2, 0.12, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "blue": {"pbrMetallicRoughness": {"baseColorFactor": [0.12, 0.25, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    "stone": {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.65, 0.55, 1], "metallicFactor": 0, "roughnessFactor": 1}},
}

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--panels", type=int, default=0, help="emissive panels instead of the point lights")
parser.add_argument("--lit", type=int, default=0, help="with --panels: only this many of them emit")
parser.add_argument("--spots", type=int, default=0, help="spot lights instead of the point lights")
parser.add_argument("--open", action="store_true", help="no ceiling: the sky reaches in")
parser.add_argument("--out", default=os.path.join(here, "light_hall"), help="output directory")
args = parser.parse_args()

if args.open:
    del meshes["ceiling"]
PANEL = 0.2
def panel_centres(n):  # n panels on as square a grid as n allows, (x, z) each
    columns = max(1, round(math.sqrt(n * WIDTH / LENGTH)))
    rows = math.ceil(n / columns)
    return [(X0 + (k % columns + 0.5) * WIDTH / columns, Z0 + (k // columns + 0.5) * LENGTH / rows) for k in range(n)]


if args.lit and not 0 < args.lit <= args.panels:
    parser.error(f"--lit {args.lit}: needs --panels and at most that many (--panels {args.panels})")
if args.panels > 0:
    centres = panel_centres(args.panels)
    lit = set(range(args.panels))
    if args.lit:  # each of a K-panel hall's centres takes the nearest panel not yet taken
        lit = set()
        for cx, cz in panel_centres(args.lit):
            lit.add(min((k for k in range(args.panels) if k not in lit),
                        key=lambda k: (centres[k][0] - cx) ** 2 + (centres[k][1] - cz) ** 2))
    power = 4 * math.pi * CANDELA * LIGHTS_X * LIGHTS_Z
    radiance = power / (len(lit) * math.pi * PANEL * PANEL)
    materials["panel"] = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                          "emissiveFactor": COLOUR,
                          "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": round(radiance, 4)}}}
    parts, dark = [], []
    for k, (x, z) in enumerate(centres):
        y, h = HEIGHT - 0.01, PANEL / 2
        (parts if k in lit else dark).append(quad((x - h, y, z - h), (x + h, y, z - h), (x + h, y, z + h),
                                                  (x - h, y, z + h)))
    meshes["panels"] = (merge(parts), "panel")
    if dark:
        materials["dark_panel"] = {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}}
        meshes["dark_panels"] = (merge(dark), "dark_panel")

extensions = ["KHR_materials_emissive_strength"] if args.panels > 0 else ["KHR_lights_punctual"]
gltf = Gltf("assets/make_light_hall.py", extensions)
gltf.materials(materials)
for name, (geometry, material) in meshes.items():
    gltf.mesh(name, geometry, material)

if args.spots > 0:
    OUTER, INNER, TILT = math.radians(40), math.radians(30), math.radians(50)
    columns = max(1, round(math.sqrt(args.spots * WIDTH / LENGTH)))
    rows = math.ceil(args.spots / columns)
    candela = 4 * math.pi * CANDELA * LIGHTS_X * LIGHTS_Z / (args.spots * 2 * math.pi * (1 - math.cos(OUTER)))
    lights = []
    for k in range(args.spots):
        x = X0 + (k % columns + 0.5) * WIDTH / columns
        z = Z0 + (k // columns + 0.5) * LENGTH / rows
        # A spot shines down its node's -Z: turn -Z to straight down (about +X by -90 degrees), then, on
        # the tilted rows, about Z towards the nearer side wall.
        down = [-math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4)]
        tilt = TILT * (1 if x > 0 else -1) if (k // columns) % 2 else 0.0
        about_z = [0.0, 0.0, math.sin(tilt / 2), math.cos(tilt / 2)]
        ax, ay, az, aw = about_z
        bx, by, bz, bw = down
        rotation = [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]
        gltf.node({"name": f"spot_{k}", "translation": [round(x, 4), HEIGHT - 0.4, round(z, 4)],
                   "rotation": [round(c, 6) for c in rotation],
                   "extensions": {"KHR_lights_punctual": {"light": len(lights)}}})
        lights.append({"name": f"spot_{k}", "type": "spot", "color": COLOUR, "intensity": round(candela, 5),
                       "spot": {"innerConeAngle": round(INNER, 5), "outerConeAngle": round(OUTER, 5)}})
    gltf.doc["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
elif args.panels == 0:
    lights = []
    for j in range(LIGHTS_Z):
        for i in range(LIGHTS_X):
            x = X0 + (i + 0.5) * WIDTH / LIGHTS_X
            z = Z0 + (j + 0.5) * LENGTH / LIGHTS_Z
            gltf.node({"name": f"lamp_{j}_{i}", "translation": [round(x, 4), HEIGHT - 0.4, round(z, 4)],
                       "extensions": {"KHR_lights_punctual": {"light": len(lights)}}})
            lights.append({"name": f"lamp_{j}_{i}", "type": "point", "color": COLOUR, "intensity": CANDELA})
    gltf.doc["extensions"] = {"KHR_lights_punctual": {"lights": lights}}

gltf.doc["cameras"] = [{"type": "perspective", "name": "entrance",
                        "perspective": {"yfov": 1.0, "aspectRatio": 16 / 9, "znear": 0.05, "zfar": 100.0}}]
gltf.node({"name": "entrance", "camera": 0, "translation": [0.0, 1.7, -0.5]})
gltf.write(args.out, "light_hall")
