#!/usr/bin/env python3
"""Writes materials.gltf: a small closed room holding every BSDF family and
light kind lvcl has, for the golden-image test (tests/test_golden.c), which
pins its renders bit for bit.

Rough and smooth metal, rough plastic, rough and smooth solid glass, thin
glass, a base-colour texture, smooth shading normals, a mirrored instance,
an area light, a point light and a spot light. Python standard library only;
the output is deterministic.

    python3 tests/data/golden/make_materials.py [OUT.gltf]
"""
import base64
import json
import math
import os
import struct
import sys
import zlib


def png_rgba(width, height, pixel):
    """A PNG of width x height RGBA8 pixels, pixel(x, y) -> (r, g, b, a)."""
    rows = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")


class Mesh:
    def __init__(self, material):
        self.material = material
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def vertex(self, p, n, uv):
        self.positions.append(p)
        self.normals.append(n)
        self.uvs.append(uv)
        return len(self.positions) - 1

    def quad(self, o, u, v, flip=False):
        """The parallelogram o, o+u, o+u+v, o+v; front face along u x v (or against it)."""
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        ln = math.sqrt(sum(c * c for c in n))
        n = tuple(c / ln * (-1 if flip else 1) for c in n)
        corners = [o, tuple(o[k] + u[k] for k in range(3)), tuple(o[k] + u[k] + v[k] for k in range(3)),
                   tuple(o[k] + v[k] for k in range(3))]
        uvs = [(0, 0), (1, 0), (1, 1), (0, 1)]
        i = [self.vertex(corners[k], n, uvs[k]) for k in range(4)]
        tri = [(0, 1, 2), (0, 2, 3)] if not flip else [(0, 2, 1), (0, 3, 2)]
        for t in tri:
            self.indices += [i[t[0]], i[t[1]], i[t[2]]]

    def box(self, lo, hi, inward=False):
        dx, dy, dz = hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]
        faces = [(lo, (0, dy, 0), (dx, 0, 0)), (hi, (-dx, 0, 0), (0, -dy, 0)),  # -z, +z
                 (lo, (0, 0, dz), (0, dy, 0)), (hi, (0, -dy, 0), (0, 0, -dz)),  # -x, +x
                 (lo, (dx, 0, 0), (0, 0, dz)), (hi, (0, 0, -dz), (-dx, 0, 0))]  # -y, +y
        for o, u, v in faces:
            self.quad(o, u, v, flip=inward)

    def sphere(self, c, r, rings=8, segments=12):
        """A UV sphere with smooth vertex normals (shading normals differ from the facets')."""
        first = len(self.positions)
        for i in range(rings + 1):
            th = math.pi * i / rings
            for j in range(segments + 1):
                ph = 2 * math.pi * j / segments
                n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
                self.vertex(tuple(c[k] + r * n[k] for k in range(3)), n, (j / segments, i / rings))
        w = segments + 1
        for i in range(rings):
            for j in range(segments):
                a, b = first + i * w + j, first + i * w + j + 1
                cc, d = a + w, b + w
                if i > 0:
                    self.indices += [a, b, cc]
                if i < rings - 1:
                    self.indices += [b, d, cc]


def material(name, rgb=(0.8, 0.8, 0.8), metallic=0.0, roughness=1.0, specular=None, transmission=None,
             thickness=None, emissive=None, texture=None, double_sided=True):
    m = {"name": name, "doubleSided": double_sided,
         "pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0], "metallicFactor": metallic,
                                  "roughnessFactor": roughness}}
    ext = {}
    if specular is not None:
        ext["KHR_materials_specular"] = {"specularFactor": specular}
    if transmission is not None:
        ext["KHR_materials_transmission"] = {"transmissionFactor": transmission}
        ext["KHR_materials_ior"] = {"ior": 1.5}
    if thickness is not None:
        ext["KHR_materials_volume"] = {"thicknessFactor": thickness, "attenuationColor": [0.9, 0.95, 1.0],
                                       "attenuationDistance": 0.5}
    if emissive is not None:
        peak = max(emissive)
        m["emissiveFactor"] = [c / peak for c in emissive]
        ext["KHR_materials_emissive_strength"] = {"emissiveStrength": peak}
    if texture is not None:
        m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture}
    if ext:
        m["extensions"] = ext
    return m


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                             "materials.gltf")
    materials = [
        material("walls", (0.7, 0.7, 0.65), specular=0.0),
        material("checker", texture=0, specular=0.0),
        material("rough_metal", (0.9, 0.6, 0.3), metallic=1.0, roughness=0.4),
        material("mirror", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.0),
        material("rough_plastic", (0.2, 0.4, 0.8), roughness=0.35),
        material("rough_glass", roughness=0.3, transmission=1.0, thickness=0.2, double_sided=False),
        material("smooth_glass", roughness=0.0, transmission=1.0, thickness=0.2, double_sided=False),
        material("thin_glass", roughness=0.0, transmission=1.0),
        material("light", (0, 0, 0), specular=0.0, emissive=(8.0, 7.0, 5.0)),
    ]
    WALLS, CHECKER, RMETAL, MIRROR, PLASTIC, RGLASS, SGLASS, THIN, LIGHT = range(9)
    meshes = []

    room = Mesh(WALLS)
    room.box((0, 0, 0), (2, 1.6, 2), inward=True)
    floor = Mesh(CHECKER)
    floor.quad((0.05, 0.001, 0.05), (0, 0, 1.9), (1.9, 0, 0))
    light = Mesh(LIGHT)
    light.quad((0.8, 1.599, 0.8), (0.4, 0, 0), (0, 0, 0.4))
    metal_ball = Mesh(RMETAL)
    metal_ball.sphere((0.5, 0.25, 1.3), 0.25)
    mirror = Mesh(MIRROR)
    mirror.quad((1.98, 0.2, 0.4), (0, 0, 1.0), (0, 0.9, 0))
    plastic_ball = Mesh(PLASTIC)
    plastic_ball.sphere((1.4, 0.2, 1.5), 0.2)
    rough_slab = Mesh(RGLASS)
    rough_slab.box((0.3, 0.0, 0.4), (0.7, 0.5, 0.6))
    smooth_ball = Mesh(SGLASS)
    smooth_ball.sphere((1.0, 0.3, 0.9), 0.2)
    sheet = Mesh(THIN)
    sheet.quad((1.2, 0.0, 0.6), (0.5, 0, 0), (0, 0.6, 0))
    block = Mesh(WALLS)  # instanced twice, once mirrored
    block.box((0.0, 0.0, 0.0), (0.15, 0.3, 0.1))
    meshes = [room, floor, light, metal_ball, mirror, plastic_ball, rough_slab, smooth_ball, sheet, block]

    blob = bytearray()
    accessors, views, gltf_meshes = [], [], []

    def add(data, fmt, count, kind, target, minmax=None):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        acc = {"bufferView": len(views) - 1, "componentType": fmt, "count": count, "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    for m in meshes:
        pos = b"".join(struct.pack("<3f", *p) for p in m.positions)
        lo = [min(p[k] for p in m.positions) for k in range(3)]
        hi = [max(p[k] for p in m.positions) for k in range(3)]
        attrs = {"POSITION": add(pos, 5126, len(m.positions), "VEC3", 34962, (lo, hi)),
                 "NORMAL": add(b"".join(struct.pack("<3f", *n) for n in m.normals), 5126, len(m.normals), "VEC3",
                               34962),
                 "TEXCOORD_0": add(b"".join(struct.pack("<2f", *uv) for uv in m.uvs), 5126, len(m.uvs), "VEC2",
                                   34962)}
        idx = add(b"".join(struct.pack("<I", i) for i in m.indices), 5125, len(m.indices), "SCALAR", 34963)
        gltf_meshes.append({"primitives": [{"attributes": attrs, "indices": idx, "material": m.material}]})

    nodes = [{"mesh": i} for i in range(len(meshes) - 1)]
    nodes += [{"mesh": len(meshes) - 1, "translation": [1.6, 0.0, 0.3]},
              {"mesh": len(meshes) - 1, "translation": [1.7, 0.0, 1.1], "scale": [-1.0, 1.2, 1.0]}]
    nodes.append({"name": "point", "extensions": {"KHR_lights_punctual": {"light": 0}},
                  "translation": [0.4, 1.2, 0.4]})
    nodes.append({"name": "spot", "extensions": {"KHR_lights_punctual": {"light": 1}},
                  "translation": [1.6, 1.4, 1.6], "rotation": [-0.5, 0.0, 0.0, 0.8660254]})
    # Camera at the front, looking into the room (-Z of the camera toward +z of the world).
    nodes.append({"name": "camera", "camera": 0, "translation": [1.0, 1.0, 0.05],
                  "rotation": [0.0, 0.9763, 0.2164, 0.0]})
    image = png_rgba(8, 8, lambda x, y: (220, 60, 40, 255) if (x + y) % 2 else (240, 230, 200, 255))
    doc = {
        "asset": {"version": "2.0", "generator": "lvcl tests/data/golden/make_materials.py"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_volume", "KHR_materials_emissive_strength", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.9, 0.8], "intensity": 0.6},
            {"type": "spot", "color": [0.8, 0.9, 1.0], "intensity": 1.5,
             "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}}]}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "materials": materials,
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(image).decode()}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.2, "aspectRatio": 1.0, "znear": 0.01}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
