#!/usr/bin/env python3
"""Writes the project's default scene to data/default/ (see data/default/README.md).

    python3 scripts/make_default_scene.py [--out DIR]

Outputs scene.glb, camera.json, lights.json and light_volumes.json. Plain
Python 3 standard library only, and deterministic: running it again yields
byte-identical files.

The level is five rooms joined in a loop by four corridors. Rooms and
corridors are built in their own local frames and placed by node transforms
(rotations, a uniform scale, a mirror, a non-uniform scale with rotated
children, a matrix node), so the loader's whole transform path is exercised by
the scene every run uses.

lights.json is produced with the same algorithm as ml::generateLights (C++):
mt19937_64, 53-bit uniforms, per light box/x/y/z/hue/jitter, double arithmetic
rounded to float32, so the C++ generator reproduces it from light_volumes.json.
"""
import argparse
import json
import math
import os
import struct
import zlib

# --------------------------------------------------------------------------
# Small numeric helpers


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def fmt_f32(x):
    """Shortest decimal that reads back (via double, as the C++ loader does) as the float32 x."""
    x = f32(x)
    for digits in range(1, 18):
        s = "%.*g" % (digits, x)
        if f32(float(s)) == x:
            return s
    return repr(x)


def vec_json(v):
    return "[" + ", ".join(fmt_f32(c) for c in v) + "]"


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(v):
    n = math.sqrt(dot(v, v))
    return [c / n for c in v]


def quat_y(degrees):
    """glTF quaternion (x, y, z, w) for a rotation about +y."""
    h = math.radians(degrees) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def mat_trs(t=(0, 0, 0), q=(0, 0, 0, 1), s=(1, 1, 1)):
    """Column-major 4x4 (list of 16) = T * R * S, the glTF node convention."""
    x, y, z, w = q
    r = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    m = [0.0] * 16
    for c in range(3):
        for row in range(3):
            m[c * 4 + row] = r[row][c] * s[c]
    m[12], m[13], m[14], m[15] = t[0], t[1], t[2], 1.0
    return m


def mat_mul(a, b):
    return [sum(a[k * 4 + row] * b[c * 4 + k] for k in range(4)) for c in range(4) for row in range(4)]


def mat_point(m, p):
    return [m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row] for row in range(3)]


def mat_det3(m):
    a = [[m[c * 4 + row] for c in range(3)] for row in range(3)]
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))


# --------------------------------------------------------------------------
# PNG writer (RGB, 8 bit, no filtering)


def png_bytes(width, height, pixel):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker_pixel(x, y):
    return (232, 230, 224) if ((x // 8) + (y // 8)) % 2 == 0 else (120, 122, 130)


def plank_pixel(x, y):
    if y % 4 == 0:  # seams between boards
        return (70, 48, 30)
    grain = ((x * 7 + (y // 4) * 5) % 6) * 6
    return (190 - grain, 140 - grain, 90 - grain // 2)


# --------------------------------------------------------------------------
# Geometry


class Prim:
    def __init__(self, material):
        self.material = material
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def quad(self, corners, normal, uvs):
        base = len(self.positions)
        self.positions += corners
        self.normals += [normal] * 4
        self.uvs += uvs
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]


class Mesh:
    """Named mesh; one primitive per material. write_normals=False leaves normals to the loader."""

    def __init__(self, name, write_normals=True, indexed=True):
        self.name, self.write_normals, self.indexed = name, write_normals, indexed
        self.prims = {}

    def prim(self, material):
        if material not in self.prims:
            self.prims[material] = Prim(material)
        return self.prims[material]

    def box(self, mn, mx, material, uv_scale=0.5, uv_unit=False):
        """Axis-aligned box, 24 vertices, counter-clockwise seen from outside.

        UVs follow world size (uv_scale per unit) so textures tile evenly, or
        span 0..1 per face with uv_unit."""
        p = self.prim(material)
        for a in range(3):
            u, v = (a + 1) % 3, (a + 2) % 3
            for side in (1, -1):
                coord = mx[a] if side > 0 else mn[a]
                corners = []
                for cu, cv in ((mn[u], mn[v]), (mx[u], mn[v]), (mx[u], mx[v]), (mn[u], mx[v])):
                    c = [0.0, 0.0, 0.0]
                    c[a], c[u], c[v] = coord, cu, cv
                    corners.append(c)
                if uv_unit:
                    uvs = [[0, 0], [1, 0], [1, 1], [0, 1]]
                else:
                    uvs = [[c[u] * uv_scale, c[v] * uv_scale] for c in corners]
                if side < 0:
                    corners.reverse()
                    uvs.reverse()
                normal = [0.0, 0.0, 0.0]
                normal[a] = float(side)
                p.quad(corners, normal, uvs)

    def cylinder(self, cx, cz, y0, y1, radius, segments, material, caps=False):
        p = self.prim(material)
        base = len(p.positions)
        for i in range(segments + 1):
            t = 2 * math.pi * i / segments
            c, s = math.cos(t), math.sin(t)
            for y in (y0, y1):
                p.positions.append([cx + radius * c, y, cz + radius * s])
                p.normals.append([c, 0.0, s])
                p.uvs.append([i / segments * 2, (y - y0) * 0.5])
        for i in range(segments):
            b0, t0, b1, t1 = base + 2 * i, base + 2 * i + 1, base + 2 * i + 2, base + 2 * i + 3
            p.indices += [b0, t0, b1, b1, t0, t1]
        if caps:
            for y, ny in ((y1, 1.0), (y0, -1.0)):
                centre = len(p.positions)
                p.positions.append([cx, y, cz])
                p.normals.append([0.0, ny, 0.0])
                p.uvs.append([0.5, 0.5])
                for i in range(segments):
                    t = 2 * math.pi * i / segments
                    p.positions.append([cx + radius * math.cos(t), y, cz + radius * math.sin(t)])
                    p.normals.append([0.0, ny, 0.0])
                    p.uvs.append([0.5 + 0.5 * math.cos(t), 0.5 + 0.5 * math.sin(t)])
                for i in range(segments):
                    a, b = centre + 1 + i, centre + 1 + (i + 1) % segments
                    p.indices += [centre, b, a] if ny > 0 else [centre, a, b]

    def sphere(self, cx, cy, cz, radius, rings, segments, material):
        p = self.prim(material)
        base = len(p.positions)
        for r in range(rings + 1):
            phi = math.pi * r / rings
            for s in range(segments + 1):
                theta = 2 * math.pi * s / segments
                n = [math.sin(phi) * math.cos(theta), math.cos(phi), math.sin(phi) * math.sin(theta)]
                p.positions.append([cx + radius * n[0], cy + radius * n[1], cz + radius * n[2]])
                p.normals.append(n)
                p.uvs.append([s / segments, r / rings])
        row = segments + 1
        for r in range(rings):
            for s in range(segments):
                a, b = base + r * row + s, base + r * row + s + 1
                c, d = a + row, b + row
                if r > 0:
                    p.indices += [a, b, c]
                if r < rings - 1:
                    p.indices += [b, d, c]

    def triangle_count(self):
        return sum(len(p.indices) // 3 for p in self.prims.values())

    def check_winding(self):
        """Every triangle must face the way its normals point (catches winding slips)."""
        for p in self.prims.values():
            for t in range(0, len(p.indices), 3):
                i0, i1, i2 = p.indices[t:t + 3]
                a, b, c = p.positions[i0], p.positions[i1], p.positions[i2]
                face = cross(sub(b, a), sub(c, a))
                n = [p.normals[i0][k] + p.normals[i1][k] + p.normals[i2][k] for k in range(3)]
                if dot(face, face) > 1e-12 and dot(face, n) <= 0:
                    raise AssertionError("%s: triangle %d faces against its normals" % (self.name, t // 3))


# Materials: name, baseColorFactor, texture (image index) or None.
MATERIALS = [
    ("Floor", [0.85, 0.85, 0.85, 1.0], 0),
    ("Wall", [0.78, 0.72, 0.62, 1.0], None),
    ("Ceiling", [0.50, 0.52, 0.58, 1.0], None),
    ("Stone", [0.62, 0.64, 0.70, 1.0], None),
    ("Crate", [0.95, 0.85, 0.70, 1.0], 1),
    ("Trim", [0.30, 0.36, 0.45, 1.0], None),
    ("Accent", [0.75, 0.18, 0.12, 1.0], None),
]
FLOOR, WALL, CEILING, STONE, CRATE, TRIM, ACCENT = range(len(MATERIALS))

WALL_T = 0.3   # wall thickness (room-local units)
SLAB = 0.25    # floor and ceiling slab thickness
DOOR_W, DOOR_H = 3.0, 3.5
CORRIDOR_W, CORRIDOR_H = 3.0, 3.5


def wall_run(mesh, axis, lo, hi, fixed_lo, fixed_hi, height, doors, inner, trim_lo, trim_hi):
    """A wall along `axis` (0 = x, 2 = z) from lo to hi, thickness between
    fixed_lo..fixed_hi on the other axis, with doorway holes (centre, width, height).
    A skirting board runs along the room side (`inner`: -1 or +1 on the other
    axis) between trim_lo..trim_hi, broken at the doorways."""
    other = 2 - axis

    def box(a0, a1, y0, y1, f0, f1, material):
        mn, mx = [0.0, y0, 0.0], [0.0, y1, 0.0]
        mn[axis], mx[axis] = a0, a1
        mn[other], mx[other] = f0, f1
        mesh.box(mn, mx, material)

    def full(a0, a1):
        box(a0, a1, 0.0, height, fixed_lo, fixed_hi, WALL)
        t0, t1 = max(a0, trim_lo), min(a1, trim_hi)
        if t1 > t0:
            face = fixed_lo if inner < 0 else fixed_hi
            box(t0, t1, 0.0, 0.15, min(face, face + 0.08 * inner), max(face, face + 0.08 * inner), TRIM)

    cursor = lo
    for centre, width, door_h in sorted(doors):
        d0, d1 = centre - width / 2, centre + width / 2
        if d0 > cursor:
            full(cursor, d0)
        box(d0, d1, door_h, height, fixed_lo, fixed_hi, WALL)  # lintel
        cursor = d1
    if cursor < hi:
        full(cursor, hi)


def room_mesh(name, w, d, h, doors, wall_t=WALL_T, door_w=DOOR_W, door_h=DOOR_H):
    """Room whose interior is x in [-w/2, w/2], z in [-d/2, d/2], y in [0, h].
    doors: {side: [offset along the wall, ...]} with sides N (-z), S (+z), E (+x), W (-x)."""
    m = Mesh(name)
    hw, hd, t = w / 2, d / 2, wall_t
    m.box([-hw - t, -SLAB, -hd - t], [hw + t, 0.0, hd + t], FLOOR)
    m.box([-hw - t, h, -hd - t], [hw + t, h + SLAB, hd + t], CEILING)
    dl = lambda side: [(o, door_w, door_h) for o in doors.get(side, [])]
    wall_run(m, 0, -hw - t, hw + t, -hd - t, -hd, h, dl("N"), +1, -hw, hw)
    wall_run(m, 0, -hw - t, hw + t, hd, hd + t, h, dl("S"), -1, -hw, hw)
    wall_run(m, 2, -hd, hd, hw, hw + t, h, dl("E"), -1, -hd + 0.08, hd - 0.08)
    wall_run(m, 2, -hd, hd, -hw - t, -hw, h, dl("W"), +1, -hd + 0.08, hd - 0.08)
    return m


def corridor_mesh(name, length):
    """Corridor along local +x from 0 to length, interior z in [-W/2, W/2], with ribs."""
    m = Mesh(name)
    hw, t, h = CORRIDOR_W / 2, WALL_T, CORRIDOR_H
    m.box([0.0, -SLAB, -hw - t], [length, 0.0, hw + t], FLOOR)
    m.box([0.0, h, -hw - t], [length, h + SLAB, hw + t], CEILING)
    m.box([0.0, 0.0, -hw - t], [length, h, -hw], WALL)
    m.box([0.0, 0.0, hw], [length, h, hw + t], WALL)
    ribs = max(2, int(length // 3))
    for i in range(ribs):
        x = length * (i + 0.5) / ribs
        m.box([x - 0.15, h - 0.3, -hw], [x + 0.15, h, hw], TRIM)
        m.box([x - 0.15, 0.0, -hw], [x + 0.15, h - 0.3, -hw + 0.2], TRIM)
        m.box([x - 0.15, 0.0, hw - 0.2], [x + 0.15, h - 0.3, hw], TRIM)
    return m


def pillar_mesh():
    m = Mesh("Pillar")
    m.box([-0.6, 0.0, -0.6], [0.6, 0.5, 0.6], STONE)
    m.cylinder(0.0, 0.0, 0.5, 5.5, 0.4, 16, STONE)
    m.box([-0.55, 5.5, -0.55], [0.55, 6.0, 0.55], STONE)
    return m


def crate_mesh():
    m = Mesh("Crate")
    m.box([-0.5, 0.0, -0.5], [0.5, 1.0, 0.5], CRATE, uv_unit=True)
    return m


def stairs_mesh():
    """Six steps rising along +x from x = 0; normals left to the loader."""
    m = Mesh("Stairs", write_normals=False)
    steps, run, rise, half_w = 6, 0.3, 0.16, 0.8
    for i in range(steps):
        m.box([i * run, 0.0, -half_w], [(i + 1) * run, (i + 1) * rise, half_w], TRIM)
    return m


def platform_mesh():
    m = Mesh("Platform", indexed=False)
    m.box([-1.4, 0.0, -4.0], [1.4, 0.96, 4.0], TRIM)
    m.box([-1.3, 0.96, -4.0], [-1.15, 1.76, 4.0], STONE)  # back rail, clear of the wall
    return m


def statue_mesh():
    m = Mesh("Statue")
    m.box([-0.7, 0.0, -0.7], [0.7, 0.9, 0.7], STONE)
    m.cylinder(0.0, 0.0, 0.9, 1.6, 0.3, 12, STONE, caps=True)
    m.sphere(0.0, 2.3, 0.0, 0.7, 10, 16, ACCENT)
    return m


def partition_mesh():
    m = Mesh("Partition")
    m.box([-2.0, 0.0, -0.15], [2.0, 2.2, 0.15], WALL)
    m.box([-2.0, 2.2, -0.2], [2.0, 2.35, 0.2], TRIM)
    return m


# --------------------------------------------------------------------------
# Level layout (world units: metres; y up; -z is "north")
#
#   Room B (0,-25) ---- corridor BD ---- Room D (25,-25)
#        |                                    |
#   corridor N                           corridor S
#        |                                    |
#   Main hall (0,0) --- corridor E ----- Room C (25,0)

HALL = dict(centre=(0.0, 0.0), w=16.0, d=16.0, h=6.0)
ROOM_B = dict(centre=(0.0, -25.0), w=10.0, d=10.0, h=4.5)
ROOM_C = dict(centre=(25.0, 0.0), w=10.0, d=10.0, h=5.0)   # built 8x8x4, scaled 1.25
ROOM_D = dict(centre=(25.0, -25.0), w=10.0, d=10.0, h=4.5)
C_SCALE = 1.25


class Gltf:
    def __init__(self):
        self.bin = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "manylights scripts/make_default_scene.py"},
            "scene": 0, "scenes": [{"name": "Level", "nodes": [0]}],
            "nodes": [], "meshes": [], "accessors": [], "bufferViews": [], "buffers": [],
            "materials": [], "textures": [], "images": [], "samplers": [],
        }
        self.mesh_index = {}

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        bv = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            bv["target"] = target
        self.bin += data
        self.doc["bufferViews"].append(bv)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, kind, ctype, target, minmax=False):
        comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[kind]
        flat = [c for v in values for c in v] if comps > 1 else values
        fmt = {5126: "f", 5123: "H", 5125: "I"}[ctype]
        acc = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target),
               "componentType": ctype, "count": len(values), "type": kind}
        if minmax:
            acc["min"] = [min(f32(v[k]) for v in values) for k in range(comps)]
            acc["max"] = [max(f32(v[k]) for v in values) for k in range(comps)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def add_mesh(self, mesh):
        mesh.check_winding()
        prims = []
        for material in sorted(mesh.prims):
            p = mesh.prims[material]
            positions, normals, uvs, indices = p.positions, p.normals, p.uvs, p.indices
            if not mesh.indexed:  # expand to a plain triangle list
                positions = [positions[i] for i in indices]
                normals = [normals[i] for i in indices]
                uvs = [uvs[i] for i in indices]
            attrs = {"POSITION": self.accessor(positions, "VEC3", 5126, 34962, minmax=True)}
            if mesh.write_normals:
                attrs["NORMAL"] = self.accessor(normals, "VEC3", 5126, 34962)
            attrs["TEXCOORD_0"] = self.accessor(uvs, "VEC2", 5126, 34962)
            prim = {"attributes": attrs, "material": material, "mode": 4}
            if mesh.indexed:
                ctype = 5123 if len(positions) < 65536 else 5125
                prim["indices"] = self.accessor(indices, "SCALAR", ctype, 34963)
            prims.append(prim)
        self.doc["meshes"].append({"name": mesh.name, "primitives": prims})
        self.mesh_index[mesh.name] = len(self.doc["meshes"]) - 1
        return self.mesh_index[mesh.name]

    def node(self, name, mesh=None, children=(), t=None, r=None, s=None, matrix=None):
        n = {"name": name}
        if mesh is not None:
            n["mesh"] = mesh
        if matrix is not None:
            n["matrix"] = [float(f32(x)) if abs(x) > 1e-12 else 0.0 for x in matrix]
        if t is not None:
            n["translation"] = list(t)
        if r is not None:
            n["rotation"] = list(r)
        if s is not None:
            n["scale"] = list(s)
        if children:
            n["children"] = list(children)
        self.doc["nodes"].append(n)
        return len(self.doc["nodes"]) - 1

    def glb(self):
        self.doc["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(self.doc, separators=(",", ":")).encode()
        js += b" " * ((4 - len(js) % 4) % 4)
        binary = bytes(self.bin) + b"\x00" * ((4 - len(self.bin) % 4) % 4)
        total = 12 + 8 + len(js) + 8 + len(binary)
        return (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(js), b"JSON") + js
                + struct.pack("<I4s", len(binary), b"BIN\x00") + binary)


def local_door_offsets(room, t, q, scale, local_w, local_d, world_doors):
    """Maps doorway centres given in world space (points on the interior wall
    line) to the room mesh's local wall sides and offsets."""
    inv = [[0.0] * 3 for _ in range(3)]
    m = mat_trs(t, q, (scale, scale, scale))
    # Rigid rotation times uniform scale: inverse = transpose / scale^2.
    for row in range(3):
        for c in range(3):
            inv[row][c] = m[row * 4 + c] / (scale * scale)
    doors = {}
    for wx, wz in world_doors:
        d = [wx - t[0], 0.0, wz - t[2]]
        lx = inv[0][0] * d[0] + inv[0][2] * d[2]
        lz = inv[2][0] * d[0] + inv[2][2] * d[2]
        if abs(lx - local_w / 2) < 1e-6:
            doors.setdefault("E", []).append(lz)
        elif abs(lx + local_w / 2) < 1e-6:
            doors.setdefault("W", []).append(lz)
        elif abs(lz - local_d / 2) < 1e-6:
            doors.setdefault("S", []).append(lx)
        elif abs(lz + local_d / 2) < 1e-6:
            doors.setdefault("N", []).append(lx)
        else:
            raise AssertionError("door (%g, %g) is not on a wall of %s" % (wx, wz, room))
    return {k: [round(v, 9) for v in vs] for k, vs in doors.items()}


def build_level():
    g = Gltf()
    for name, colour, image in MATERIALS:
        mat = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": colour, "metallicFactor": 0.0,
                                                      "roughnessFactor": 0.8}}
        if image is not None:
            mat["pbrMetallicRoughness"]["baseColorTexture"] = {"index": image}
        g.doc["materials"].append(mat)
    g.doc["samplers"].append({"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497})
    for i, (name, pixel) in enumerate((("checker", checker_pixel), ("planks", plank_pixel))):
        bv = g.view(png_bytes(16, 16, pixel))
        g.doc["images"].append({"name": name, "bufferView": bv, "mimeType": "image/png"})
        g.doc["textures"].append({"sampler": 0, "source": i})

    pillar = g.add_mesh(pillar_mesh())
    crate = g.add_mesh(crate_mesh())
    stairs = g.add_mesh(stairs_mesh())
    platform = g.add_mesh(platform_mesh())
    statue = g.add_mesh(statue_mesh())
    partition = g.add_mesh(partition_mesh())

    nodes = []  # children of the root

    # Main hall: identity placement; pillars and crates under group nodes.
    hall = g.add_mesh(room_mesh("Hall", 16.0, 16.0, 6.0, {"N": [0.0], "E": [0.0]}))
    pillars = [g.node("Pillar.%d" % i, pillar, t=[x, 0.0, z])
               for i, (x, z) in enumerate((x, z) for x in (-4.5, 4.5) for z in (-5.5, -1.8, 1.8, 5.5))]
    colonnade = g.node("Colonnade", children=pillars)
    hall_crates = [
        g.node("Crate.h0", crate, t=[0.0, 0.0, 0.0]),
        g.node("Crate.h1", crate, t=[-1.0, 0.0, 0.3], r=quat_y(20), s=[0.9, 0.9, 0.9]),
        g.node("Crate.h2", crate, t=[0.2, 1.0, 0.1], r=quat_y(-10), s=[0.8, 0.8, 0.8]),
        g.node("Crate.h3", crate, t=[0.3, 0.0, -1.2], r=quat_y(45), s=[1.2, 1.2, 1.2]),
    ]
    cargo_west = g.node("Cargo.west", children=hall_crates, t=[-6.4, 0.0, -3.9], r=quat_y(30))
    cargo_east = g.node("Cargo.east", children=[
        g.node("Crate.h4", crate, t=[0.0, 0.0, 0.0], s=[1.4, 1.4, 1.4]),
        g.node("Crate.h5", crate, t=[0.0, 1.4, 0.0], r=quat_y(15)),
        g.node("Crate.h6", crate, t=[0.1, 0.0, -1.5], r=quat_y(-25)),
    ], t=[6.3, 0.0, -3.6])
    nodes.append(g.node("MainHall", hall, children=[colonnade, cargo_west, cargo_east]))

    # Room B, rotated 90 degrees: world south door to the hall corridor, east door to corridor BD.
    b_t, b_q = [0.0, 0.0, -25.0], quat_y(90)
    b_doors = local_door_offsets("RoomB", b_t, b_q, 1.0, 10.0, 10.0, [(0.0, -20.0), (5.0, -25.0)])
    room_b = g.add_mesh(room_mesh("RoomB", 10.0, 10.0, 4.5, b_doors))
    b_children = [g.node("Statue", statue, t=[0.0, 0.0, 0.0], r=quat_y(-90))]
    b_children += [g.node("Pillar.b%d" % i, pillar, t=[x, 0.0, z], s=[0.8, 0.75, 0.8])
                   for i, (x, z) in enumerate(((-3.2, -3.2), (-3.2, 3.2), (3.2, -3.2), (3.2, 3.2)))]
    nodes.append(g.node("RoomB", room_b, children=b_children, t=b_t, r=b_q))

    # Room C: an 8x8x4 room scaled 1.25 and turned 180 degrees; a raised platform with
    # two staircases (one mirrored by a negative scale) and crates under a
    # non-uniformly scaled group whose rotated children therefore shear.
    c_t, c_q = [25.0, 0.0, 0.0], quat_y(180)
    c_doors = local_door_offsets("RoomC", c_t, c_q, C_SCALE, 8.0, 8.0, [(20.0, 0.0), (25.0, -5.0)])
    room_c = g.add_mesh(room_mesh("RoomC", 8.0, 8.0, 4.0, c_doors, wall_t=WALL_T,
                                  door_w=DOOR_W / C_SCALE, door_h=DOOR_H / C_SCALE))
    c_children = [
        g.node("Platform", platform, t=[-2.6, 0.0, 0.0]),
        g.node("Stairs.mirrored", stairs, t=[0.6, 0.0, 2.0], s=[-1.0, 1.0, 1.0]),
        g.node("Stairs.turned", stairs, t=[0.6, 0.0, -2.0], r=quat_y(180)),
        g.node("Cargo.C", children=[
            g.node("Crate.c0", crate, r=quat_y(35)),
            g.node("Crate.c1", crate, t=[1.2, 0.0, 0.4], r=quat_y(-20)),
            g.node("Crate.c2", crate, t=[0.5, 1.0, 0.2], r=quat_y(60), s=[0.8, 0.8, 0.8]),
        ], t=[2.2, 0.0, -2.6], s=[1.4, 1.0, 0.8]),
    ]
    nodes.append(g.node("RoomC", room_c, children=c_children, t=c_t, r=c_q, s=[C_SCALE] * 3))

    # Room D via a matrix node (turned -90 degrees); partition walls and crates.
    d_t, d_q = [25.0, 0.0, -25.0], quat_y(-90)
    d_doors = local_door_offsets("RoomD", d_t, d_q, 1.0, 10.0, 10.0, [(20.0, -25.0), (25.0, -20.0)])
    room_d = g.add_mesh(room_mesh("RoomD", 10.0, 10.0, 4.5, d_doors))
    d_children = [
        g.node("Partition.0", partition, t=[-1.5, 0.0, -2.0]),
        g.node("Partition.1", partition, t=[1.5, 0.0, 2.2], r=quat_y(90)),
        g.node("Partition.2", partition, t=[1.8, 0.0, -3.2], r=quat_y(30), s=[0.6, 1.0, 1.0]),
    ]
    d_children += [g.node("Crate.d%d" % i, crate, t=[x, 0.0, z], r=quat_y(a), s=[k, k, k])
                   for i, (x, z, a, k) in enumerate(((-3.5, 3.5, 10, 1.3), (-2.3, 3.8, -15, 1.0),
                                                     (-3.6, 2.1, 40, 0.9), (3.8, -4.0, 5, 1.4)))]
    # A mirrored instance of a mesh that carries its own normals: the loader must
    # flip the winding to match them.
    d_children.append(g.node("Crate.d.mirrored", crate, t=[3.4, 0.0, -1.6], r=quat_y(20), s=[-1.1, 1.1, 1.1]))
    nodes.append(g.node("RoomD", room_d, children=d_children, matrix=mat_trs(d_t, d_q)))

    # Corridors, each spanning the gap between two walls' outer faces.
    hall_t = WALL_T
    c_wall = WALL_T * C_SCALE
    corridors = [
        ("Corridor.N", [0.0, 0.0, -8.0 - hall_t], quat_y(90), (-8.0 - hall_t) - (-20.0 + WALL_T)),
        ("Corridor.E", [8.0 + hall_t, 0.0, 0.0], None, (20.0 - c_wall) - (8.0 + hall_t)),
        ("Corridor.S", [25.0, 0.0, -5.0 - c_wall], quat_y(90), (-5.0 - c_wall) - (-20.0 + WALL_T)),
        ("Corridor.BD", [5.0 + WALL_T, 0.0, -25.0], None, (20.0 - WALL_T) - (5.0 + WALL_T)),
    ]
    for name, t, q, length in corridors:
        mesh = g.add_mesh(corridor_mesh(name, length))
        nodes.append(g.node(name, mesh, t=t, r=q))

    root = g.node("Level", children=nodes)
    g.doc["scenes"][0]["nodes"] = [root]
    return g


def world_triangles(g):
    """(positions, det sign) per placed mesh, for the statistics printed at the end."""
    doc = g.doc
    tris, bounds = 0, [[1e30] * 3, [-1e30] * 3]

    def accessor_vec3(index):
        acc = doc["accessors"][index]
        bv = doc["bufferViews"][acc["bufferView"]]
        data = struct.unpack_from("<%df" % (acc["count"] * 3), g.bin, bv["byteOffset"])
        return [data[i:i + 3] for i in range(0, len(data), 3)]

    def local(node):
        if "matrix" in node:
            return node["matrix"]
        return mat_trs(node.get("translation", (0, 0, 0)), node.get("rotation", (0, 0, 0, 1)),
                       node.get("scale", (1, 1, 1)))

    def visit(i, parent):
        nonlocal tris
        node = doc["nodes"][i]
        world = mat_mul(parent, local(node))
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                pos = accessor_vec3(prim["attributes"]["POSITION"])
                count = doc["accessors"][prim["indices"]]["count"] if "indices" in prim else len(pos)
                tris += count // 3
                for p in pos:
                    w = mat_point(world, p)
                    for k in range(3):
                        bounds[0][k] = min(bounds[0][k], w[k])
                        bounds[1][k] = max(bounds[1][k], w[k])
        for c in node.get("children", []):
            visit(c, world)

    visit(doc["scenes"][0]["nodes"][0], mat_trs())
    return tris, bounds


# --------------------------------------------------------------------------
# Lights: a transcription of ml::generateLights (host/scene/LightSet.cpp)


class Mt19937_64:
    def __init__(self, seed):
        self.mt = [0] * 312
        self.mt[0] = seed & 0xFFFFFFFFFFFFFFFF
        for i in range(1, 312):
            prev = self.mt[i - 1]
            self.mt[i] = (6364136223846793005 * (prev ^ (prev >> 62)) + i) & 0xFFFFFFFFFFFFFFFF
        self.index = 312

    def next(self):
        if self.index >= 312:
            for i in range(312):
                x = (self.mt[i] & 0xFFFFFFFF80000000) | (self.mt[(i + 1) % 312] & 0x7FFFFFFF)
                xa = x >> 1
                if x & 1:
                    xa ^= 0xB5026F5AA96619E9
                self.mt[i] = self.mt[(i + 156) % 312] ^ xa
            self.index = 0
        y = self.mt[self.index]
        self.index += 1
        y ^= (y >> 29) & 0x5555555555555555
        y ^= (y << 17) & 0x71D67FFFEDA60000
        y ^= (y << 37) & 0xFFF7EEF000000000
        y ^= y >> 43
        return y

    def uniform01(self):
        return (self.next() >> 11) * 2.0 ** -53


def hue_to_rgb(h):
    h6 = h * 6.0
    sector = math.floor(h6)
    f = h6 - sector
    q = 1.0 - f
    return [(1.0, f, 0.0), (q, 1.0, 0.0), (0.0, 1.0, f), (0.0, q, 1.0), (f, 0.0, 1.0), (1.0, 0.0, q)][int(sector) % 6]


def generate_lights(volumes, count, radius, jitter, seed):
    rng = Mt19937_64(seed)
    total = 0.0
    for v in volumes:
        total += v["weight"]
    last_positive = max(i for i, v in enumerate(volumes) if v["weight"] > 0)
    lights = []
    for _ in range(count):
        target = rng.uniform01() * total
        box, cumulative = last_positive, 0.0
        for i, v in enumerate(volumes):
            cumulative += v["weight"]
            if v["weight"] > 0 and target < cumulative:
                box = i
                break
        v = volumes[box]
        pos = [f32(v["min"][c] + rng.uniform01() * (v["max"][c] - v["min"][c])) for c in range(3)]
        colour = [f32(c) for c in hue_to_rgb(rng.uniform01())]
        r = f32(radius * (1.0 + jitter * (2.0 * rng.uniform01() - 1.0)))
        lights.append((pos, r, colour))
    return lights


LIGHT_INSET = 0.3  # light volumes stay this far from floors, walls and ceilings


def light_volumes():
    """Interiors (inset from walls, floor and ceiling) of every room and corridor;
    weight = volume so the light density is uniform over the level."""
    inset = LIGHT_INSET
    boxes = []

    def room(name, spec):
        cx, cz = spec["centre"]
        boxes.append((name, [cx - spec["w"] / 2 + inset, inset, cz - spec["d"] / 2 + inset],
                      [cx + spec["w"] / 2 - inset, spec["h"] - inset, cz + spec["d"] / 2 - inset]))

    room("main hall", HALL)
    room("room B", ROOM_B)
    room("room C", ROOM_C)
    room("room D", ROOM_D)
    hw = CORRIDOR_W / 2 - inset
    top = CORRIDOR_H - inset
    c_wall = WALL_T * C_SCALE
    boxes.append(("corridor N", [-hw, inset, -20.0 + WALL_T], [hw, top, -8.0 - WALL_T]))
    boxes.append(("corridor E", [8.0 + WALL_T, inset, -hw], [20.0 - c_wall, top, hw]))
    boxes.append(("corridor S", [25.0 - hw, inset, -20.0 + WALL_T], [25.0 + hw, top, -5.0 - c_wall]))
    boxes.append(("corridor BD", [5.0 + WALL_T, inset, -25.0 - hw], [20.0 - WALL_T, top, -25.0 + hw]))
    out = []
    for name, mn, mx in boxes:
        mn, mx = [f32(c) for c in mn], [f32(c) for c in mx]
        weight = f32((mx[0] - mn[0]) * (mx[1] - mn[1]) * (mx[2] - mn[2]))
        out.append({"name": name, "min": mn, "max": mx, "weight": weight})
    return out


# --------------------------------------------------------------------------
# Camera: frame 0 is the default view (main hall, looking north down corridor N
# into room B); the path walks up the corridor into room B and turns east
# towards corridor BD.


def camera_frames(count=60):
    def smooth(t):
        return t * t * (3 - 2 * t)

    frames = []
    walk = 40
    start, end = [1.2, 1.7, 6.5], [0.0, 1.7, -21.5]
    for i in range(count):
        if i < walk:
            t = smooth(i / (walk - 1)) if walk > 1 else 0.0
            eye = [start[k] + (end[k] - start[k]) * t for k in range(3)]
            target = [0.0, 1.7, -30.0]
            d = normalize(sub(target, eye))
        else:
            t = smooth((i - walk + 1) / (count - walk))
            eye = [end[0] + 1.5 * t, 1.7, end[2] - 3.0 * t]
            yaw = math.radians(90.0 * t)  # from -z (north) to +x (east)
            d = [math.sin(yaw), 0.0, -math.cos(yaw)]
        centre = [eye[k] + 3.0 * d[k] for k in range(3)]
        frames.append((eye, centre, [0.0, 1.0, 0.0]))
    return frames


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--out", default=os.path.join(repo, "data", "default"))
    parser.add_argument("--lights", type=int, default=1024)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    g = build_level()
    glb = g.glb()
    with open(os.path.join(args.out, "scene.glb"), "wb") as f:
        f.write(glb)
    tris, bounds = world_triangles(g)

    radius, jitter = 2.5, 0.4
    volumes = light_volumes()
    with open(os.path.join(args.out, "light_volumes.json"), "w") as f:
        f.write('{"radius": %s, "radius_jitter": %s, "seed": %d, "count": %d, "surface_inset": %s, "volumes": [\n'
                % (fmt_f32(radius), fmt_f32(jitter), args.seed, args.lights, fmt_f32(LIGHT_INSET)))
        f.write(",\n".join('  {"name": "%s", "min": %s, "max": %s, "weight": %s}'
                           % (v["name"], vec_json(v["min"]), vec_json(v["max"]), fmt_f32(v["weight"]))
                           for v in volumes))
        f.write("\n]}\n")

    lights = generate_lights(volumes, args.lights, f32(radius), f32(jitter), args.seed)
    with open(os.path.join(args.out, "lights.json"), "w") as f:
        f.write('{"lights": [\n')
        f.write(",\n".join('  {"position": %s, "radius": %s, "intensity": %s}'
                           % (vec_json(p), fmt_f32(r), vec_json(c)) for p, r, c in lights))
        f.write("\n]}\n")

    with open(os.path.join(args.out, "camera.json"), "w") as f:
        f.write('{"fovy": 60, "near": 0.1, "far": 200, "frames": [\n')
        f.write(",\n".join('  {"eye": %s, "center": %s, "up": %s}' % (vec_json(e), vec_json(c), vec_json(u))
                           for e, c, u in camera_frames()))
        f.write("\n]}\n")

    print("scene.glb: %d bytes, %d triangles, %d materials, %d textures, %d nodes, %d meshes"
          % (len(glb), tris, len(g.doc["materials"]), len(g.doc["textures"]), len(g.doc["nodes"]),
             len(g.doc["meshes"])))
    print("bounds: min (%.3f, %.3f, %.3f) max (%.3f, %.3f, %.3f)" % tuple(bounds[0] + bounds[1]))
    print("lights: %d, radius %.2f +- %.0f%%, seed %d; %d light volumes"
          % (len(lights), radius, jitter * 100, args.seed, len(volumes)))


if __name__ == "__main__":
    main()
