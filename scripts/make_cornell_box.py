#!/usr/bin/env python3
"""Writes the Cornell box scene to data/cornell/ (see data/cornell/README.md).

    python3 scripts/make_cornell_box.py [--out DIR]

Outputs cornell.gltf + cornell.bin, camera.json and lights.json; the glTF carries
the same lights as lights.json, in the same order, as KHR_lights_punctual point
lights (nodes under the root, "range" = radius; colour x intensity = the light
file's intensity, see host/scene/GltfLights.hpp). Plain Python 3
standard library only, deterministic (byte-identical on rerun). Geometry and
glTF writing reuse scripts/make_default_scene.py.

The box: interior x in [-1, 1], y in [0, 2], z in [-1, 1] (metres, +y up), open
towards +z where the camera stands; walls are 0.1 m slabs (both faces, like the
default scene's). Red wall at -x, green at +x, white floor, ceiling and back
wall; a short and a tall white box turned about +y. Albedos are the classic
Cornell values. The lights are point lights inside the box, under the ceiling
and in the middle, with radii that reach the far walls (the renderer's falloff
clamp(1 - d / r)^2 ends at the radius).
"""
import argparse
import json
import os

from make_default_scene import Gltf, Mesh, fmt_f32, quat_y, vec_json

MATERIALS = [
    ("White", [0.73, 0.73, 0.73, 1.0]),
    ("Red", [0.63, 0.065, 0.05, 1.0]),
    ("Green", [0.14, 0.45, 0.091, 1.0]),
]
WHITE, RED, GREEN = range(len(MATERIALS))
HALF, HEIGHT, WALL = 1.0, 2.0, 0.1

LIGHTS = [  # position, radius, intensity
    ([0.0, 1.8, 0.0], 3.5, [2.0, 1.9, 1.7]),
    ([-0.5, 1.7, -0.5], 2.5, [0.8, 0.8, 0.8]),
    ([0.5, 1.7, 0.4], 2.5, [0.8, 0.8, 0.8]),
    ([0.0, 1.2, 0.8], 2.5, [0.8, 0.8, 0.9]),
]
CAMERA = {"fovy": 40, "near": 0.1, "far": 20,
          "frames": [{"eye": [0.0, 1.0, 3.9], "center": [0.0, 1.0, 0.0], "up": [0, 1, 0]}]}


def room_mesh():
    m = Mesh("CornellRoom")
    h, t, y = HALF, WALL, HEIGHT
    m.box([-h - t, -t, -h - t], [h + t, 0.0, h], WHITE)      # floor
    m.box([-h - t, y, -h - t], [h + t, y + t, h], WHITE)     # ceiling
    m.box([-h, 0.0, -h - t], [h, y, -h], WHITE)              # back wall
    m.box([-h - t, 0.0, -h], [-h, y, h], RED)                # left wall
    m.box([h, 0.0, -h], [h + t, y, h], GREEN)                # right wall
    return m


def block_mesh(name, half_w, height):
    m = Mesh(name)
    m.box([-half_w, 0.0, -half_w], [half_w, height, half_w], WHITE)
    return m


def punctual_light(radius, intensity):
    """The KHR_lights_punctual entry whose colour x intensity (in double, as the
    loader multiplies) is `intensity`: the colour as it is when it lies within
    [0, 1], else divided by its largest component (the same rule as the C++
    writer, host/scene/GltfLightsWrite.cpp)."""
    m = max(intensity)
    if m <= 1.0:
        colour, scale = list(intensity), 1.0
    else:
        colour, scale = [c / m for c in intensity], m
    return {"type": "point", "color": colour, "intensity": scale, "range": radius}


def add_lights(g):
    """Light nodes (in LIGHTS order) and the extension's table; returns the nodes."""
    table, nodes = [], []
    for i, (position, radius, intensity) in enumerate(LIGHTS):
        table.append(punctual_light(radius, intensity))
        nodes.append(g.node("Light%d" % i, t=position))
        g.doc["nodes"][nodes[-1]]["extensions"] = {"KHR_lights_punctual": {"light": i}}
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": table}}
    g.doc["extensionsUsed"] = sorted(set(g.doc.get("extensionsUsed", [])) | {"KHR_lights_punctual"})
    return nodes


def build_box():
    g = Gltf()
    g.doc["asset"]["generator"] = "manylights scripts/make_cornell_box.py"
    g.doc["scenes"][0]["name"] = "Cornell box"
    for key in ("textures", "images", "samplers"):
        del g.doc[key]
    for name, colour in MATERIALS:
        g.doc["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    room = g.add_mesh(room_mesh())
    short = g.add_mesh(block_mesh("ShortBlock", 0.3, 0.6))
    tall = g.add_mesh(block_mesh("TallBlock", 0.3, 1.2))
    nodes = [
        g.node("Room", room),
        g.node("ShortBlock", short, t=[0.35, 0.0, 0.3], r=quat_y(-17)),
        g.node("TallBlock", tall, t=[-0.35, 0.0, -0.35], r=quat_y(20)),
    ]
    nodes += add_lights(g)  # after the meshes: their node order (and the mesh loader's output) stays
    g.doc["scenes"][0]["nodes"] = [g.node("Cornell", children=nodes)]
    return g


def write_gltf(g, out_dir, stem):
    binary = bytes(g.bin) + b"\x00" * ((4 - len(g.bin) % 4) % 4)
    g.doc["buffers"] = [{"byteLength": len(binary), "uri": stem + ".bin"}]
    with open(os.path.join(out_dir, stem + ".bin"), "wb") as f:
        f.write(binary)
    with open(os.path.join(out_dir, stem + ".gltf"), "w") as f:
        json.dump(g.doc, f, indent=1, sort_keys=True)
        f.write("\n")


def lights_json():
    rows = ['  {"position": %s, "radius": %s, "intensity": %s}' % (vec_json(p), fmt_f32(r), vec_json(c))
            for p, r, c in LIGHTS]
    return '{"lights": [\n' + ",\n".join(rows) + "\n]}\n"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(here, "..", "data", "cornell"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    g = build_box()
    write_gltf(g, args.out, "cornell")
    with open(os.path.join(args.out, "lights.json"), "w") as f:
        f.write(lights_json())
    with open(os.path.join(args.out, "camera.json"), "w") as f:
        json.dump(CAMERA, f)
        f.write("\n")
    print("wrote %s: %d meshes, %d lights" % (os.path.normpath(args.out), len(g.doc["meshes"]), len(LIGHTS)))


if __name__ == "__main__":
    main()
