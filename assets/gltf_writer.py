"""A minimal glTF 2.0 writer for the scenes we generate (assets/make_*.py): quads and blocks of
outward-facing triangles, meshes with one primitive each, materials, nodes, a camera, punctual
lights. Only the Python standard library; the outputs are committed, so users need nothing but
the repository."""
import json
import math
import os
import struct


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def quad(a, b, c, d):
    """Two CCW triangles a-b-c, a-c-d; the normal follows the right-hand rule."""
    n = cross(sub(b, a), sub(c, a))
    length = math.sqrt(dot(n, n))
    n = tuple(x / length for x in n)
    return [a, b, c, d], [n] * 4, [0, 1, 2, 0, 2, 3]


def merge(parts):
    pos, nrm, idx = [], [], []
    for p, n, i in parts:
        base = len(pos)
        pos += p
        nrm += n
        idx += [base + k for k in i]
    return pos, nrm, idx


def block(cx, cz, w, h, d, angle, y0=0):
    """A block standing on y = y0, rotated about Y, as 5 outward-facing quads (no bottom)."""
    c, s = math.cos(angle), math.sin(angle)

    def p(x, y, z):
        return (cx + c * x + s * z, y0 + y, cz - s * x + c * z)

    hw, hd = w / 2, d / 2
    faces = [
        quad(p(-hw, h, -hd), p(-hw, h, hd), p(hw, h, hd), p(hw, h, -hd)),    # top (+Y)
        quad(p(-hw, 0, hd), p(hw, 0, hd), p(hw, h, hd), p(-hw, h, hd)),      # +Z
        quad(p(hw, 0, -hd), p(-hw, 0, -hd), p(-hw, h, -hd), p(hw, h, -hd)),  # -Z
        quad(p(hw, 0, hd), p(hw, 0, -hd), p(hw, h, -hd), p(hw, h, hd)),      # +X
        quad(p(-hw, 0, -hd), p(-hw, 0, hd), p(-hw, h, hd), p(-hw, h, -hd)),  # -X
    ]
    return merge(faces)


class Gltf:
    def __init__(self, generator, extensions=()):
        self.blob = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": generator}}
        if extensions:
            self.doc["extensionsUsed"] = list(extensions)
        self.doc.update({"scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "accessors": [],
                         "bufferViews": [], "materials": []})
        self.material_index = {}

    def materials(self, materials):
        for name, m in materials.items():
            self.material_index[name] = len(self.doc["materials"])
            self.doc["materials"].append(dict(name=name, **m))

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data),
                                        "target": target})
        self.blob.extend(data)
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, values, fmt, comp, kind, target, minmax=False):
        flat = [x for v in values for x in (v if isinstance(v, tuple) else (v,))]
        view = self._view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target)
        acc = {"bufferView": view, "componentType": comp, "count": len(values), "type": kind}
        if minmax:
            acc["min"] = [min(v[i] for v in values) for i in range(3)]
            acc["max"] = [max(v[i] for v in values) for i in range(3)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def mesh(self, name, geometry, material):
        """A mesh of one primitive and the node that places it (at the origin)."""
        pos, nrm, idx = geometry
        p = self._accessor(pos, "f", 5126, "VEC3", 34962, minmax=True)
        n = self._accessor(nrm, "f", 5126, "VEC3", 34962)
        wide = len(pos) > 65535
        i = self._accessor(idx, "I" if wide else "H", 5125 if wide else 5123, "SCALAR", 34963)
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": self.material_index[material]}]})
        self.doc["nodes"].append({"name": name, "mesh": len(self.doc["meshes"]) - 1})

    def node(self, node):
        self.doc["nodes"].append(node)

    def accessor(self, values, fmt, comp, kind, target=None):
        """An accessor of VALUES (tuples or scalars) packed as struct format FMT; no bufferView target for
        animation and skin data (TARGET None)."""
        index = self._accessor(values, fmt, comp, kind, target or 0)
        if target is None:
            self.doc["bufferViews"][self.doc["accessors"][index]["bufferView"]].pop("target")
        return index

    def write(self, directory, stem, roots=None):
        """Writes DIRECTORY/STEM.gltf and STEM.bin; the scene holds ROOTS (default: every node)."""
        self.doc["scenes"][0]["nodes"] = list(range(len(self.doc["nodes"]))) if roots is None else roots
        self.doc["buffers"] = [{"byteLength": len(self.blob), "uri": stem + ".bin"}]
        os.makedirs(directory, exist_ok=True)
        with open(os.path.join(directory, stem + ".bin"), "wb") as f:
            f.write(self.blob)
        with open(os.path.join(directory, stem + ".gltf"), "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")
        print("wrote", os.path.join(directory, stem + ".gltf"), len(self.blob), "bytes of geometry")


def smoothstep(a, b, x):
    t = min(max((x - a) / (b - a), 0.0), 1.0)
    return t * t * (3 - 2 * t)


def bar(half, height, segments):
    """A square bar standing on y = 0 (x and z in [-half, half]): four sides of SEGMENTS rows each (their own
    vertices: flat normals) and a top cap."""
    pos, nrm, idx = [], [], []
    sides = [((1, 0, 0), (half, -half), (half, half)), ((-1, 0, 0), (-half, half), (-half, -half)),
             ((0, 0, 1), (-half, half), (half, half)), ((0, 0, -1), (half, -half), (-half, -half))]
    for normal, (ax, az), (bx, bz) in sides:
        base = len(pos)
        for row in range(segments + 1):
            y = height * row / segments
            pos += [(ax, y, az), (bx, y, bz)]
            nrm += [normal, normal]
        for row in range(segments):
            a, b, c, d = base + 2 * row, base + 2 * row + 1, base + 2 * row + 3, base + 2 * row + 2
            idx += [a, b, c, a, c, d]  # counter-clockwise seen from outside
    top = quad((-half, height, half), (half, height, half), (half, height, -half), (-half, height, -half))
    base = len(pos)
    pos += top[0]
    nrm += top[1]
    idx += [base + i for i in top[2]]
    return pos, nrm, idx


def add_skinned_bar(gltf, name, material, base, half, height, segments, bend_y, blend, seconds, degrees):
    """A bar standing at BASE skinned to two joints: `NAME_root` at BASE and its child `NAME_bend` BEND_Y above
    it; a vertex at height y weighs the bend joint by smoothstep(BLEND[0], BLEND[1], y). An animation turns the
    bend joint about +Z from 0 to DEGREES over SECONDS / 2 and back (LINEAR). Returns the root nodes to put in
    the scene (the joints' root and the skinned mesh's node)."""
    pos, nrm, idx = bar(half, height, segments)
    weights = [smoothstep(blend[0], blend[1], p[1]) for p in pos]
    pos = [(x + base[0], y + base[1], z + base[2]) for x, y, z in pos]
    p = gltf.accessor(pos, "f", 5126, "VEC3", 34962)
    gltf.doc["accessors"][p].update(min=[min(v[i] for v in pos) for i in range(3)], max=[max(v[i] for v in pos) for i in range(3)])
    n = gltf.accessor(nrm, "f", 5126, "VEC3", 34962)
    j = gltf.accessor([(0, 1, 0, 0)] * len(pos), "B", 5121, "VEC4", 34962)
    w = gltf.accessor([(1 - b, b, 0.0, 0.0) for b in weights], "f", 5126, "VEC4", 34962)
    i = gltf.accessor(idx, "H", 5123, "SCALAR", 34963)
    gltf.doc["meshes"].append({"name": name, "primitives": [{
        "attributes": {"POSITION": p, "NORMAL": n, "JOINTS_0": j, "WEIGHTS_0": w}, "indices": i,
        "material": gltf.material_index[material]}]})
    root = len(gltf.doc["nodes"])
    gltf.node({"name": name + "_root", "translation": list(base), "children": [root + 1]})
    gltf.node({"name": name + "_bend", "translation": [0, bend_y, 0]})
    identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]
    ibm = gltf.accessor([tuple(identity + [-base[0], -base[1], -base[2], 1]),
                         tuple(identity + [-base[0], -base[1] - bend_y, -base[2], 1])], "f", 5126, "MAT4")
    gltf.doc.setdefault("skins", []).append({"name": name, "joints": [root, root + 1], "skeleton": root,
                                             "inverseBindMatrices": ibm})
    gltf.node({"name": name, "mesh": len(gltf.doc["meshes"]) - 1, "skin": len(gltf.doc["skins"]) - 1})
    times = gltf.accessor([0.0, seconds / 2, seconds], "f", 5126, "SCALAR")
    gltf.doc["accessors"][times].update(min=[0.0], max=[seconds])
    half_angle = math.radians(degrees) / 2
    turns = gltf.accessor([(0.0, 0.0, 0.0, 1.0), (0.0, 0.0, math.sin(half_angle), math.cos(half_angle)),
                           (0.0, 0.0, 0.0, 1.0)], "f", 5126, "VEC4")
    gltf.doc.setdefault("animations", []).append({"name": name + "_bend", "samplers": [
        {"input": times, "output": turns, "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": root + 1, "path": "rotation"}}]})
    return [root, root + 2]

