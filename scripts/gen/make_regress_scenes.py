#!/usr/bin/python3
"""Writes the regression scenes of testbench/scenes/regress/ (deterministic:
every scene has its own fixed seed, so running it again gives the same
files). A scene's category, the sections of docs/pipeline-spec.md it
exercises and its description live here (SCENES), not in the scene file;
scripts/regress imports them for its report, and --table prints them as the
Markdown table of docs/validation.md. The reference images
(testbench/references/) come from scripts/make_references.

Writes only where told: `--out DIR` writes the scenes (and lines_mesh.obj,
which they name relatively) into DIR, `--write-testbench` rewrites the
committed copies in testbench/scenes/regress/. With neither, it prints its
usage and writes nothing.

usage: scripts/gen/make_regress_scenes.py (--out DIR | --write-testbench | --table)
"""
import argparse
import json
import math
import os
import random
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "testbench", "scenes", "regress")
MODELS = "/usr/share/assimp/models"

SCENES = []  # (name, category, spec sections, description, scene)


def scene(name, category, sections, description):
    def register(fn):
        SCENES.append((name, category, sections, description, fn))
        return fn
    return register


def r(x):
    """Rounds to 6 decimals, so files stay readable; the loader reads floats."""
    v = round(x, 6)
    return 0.0 if v == 0 else v


def rcol(rng, alpha=1.0):
    return [r(rng.random()), r(rng.random()), r(rng.random()), alpha]


def clip_x(px, width):
    """Clip-space x (w = 1) of window x px: exact for multiples of 1/256."""
    return px / (width / 2.0) - 1.0


def quad_strip(x0, y0, x1, y1, z=0.0):
    return [[x0, y0, z], [x1, y0, z], [x0, y1, z], [x1, y1, z]]


# ---------------------------------------------------------------- real meshes

@scene("mesh_wuson_lit", "mesh", "2, 7, 9, 11",
       "WusonOBJ.obj lit by a directional and an attenuated point light with specular highlights, "
       "back faces culled, perspective camera, unorm24 depth")
def mesh_wuson_lit():
    return {
        "framebuffer": {"width": 256, "height": 256, "clear_color": [0.1, 0.1, 0.15, 1]},
        "camera": {"type": "perspective", "fovy": 40, "near": 1, "far": 20,
                   "eye": [3.2, 2.2, 3.6], "target": [0, 0.7, 0]},
        "ambient": [0.15, 0.15, 0.15, 1],
        "lights": [
            {"type": "directional", "direction": [-0.5, -1, -0.3], "diffuse": [0.8, 0.75, 0.7, 1],
             "specular": [1, 1, 1, 1]},
            {"type": "point", "position": [-1.5, 2.0, 2.0], "diffuse": [0.3, 0.4, 0.9, 1],
             "ambient": [0.05, 0.05, 0.1, 1], "attenuation": [0.5, 0.2, 0.05]},
        ],
        "draws": [{"mesh": MODELS + "/OBJ/WusonOBJ.obj",
                   "material": {"color": [0.8, 0.6, 0.4, 1], "specular": [0.6, 0.6, 0.6, 1],
                                "shininess": 24},
                   "state": {"cull": "back"}}],
    }


@scene("mesh_spider_materials", "mesh", "2, 8, 11",
       "spider.obj with the materials of its .mtl (4 meshes), orthographic camera, no culling, "
       "non-square 256x192")
def mesh_spider_materials():
    return {
        "framebuffer": {"width": 256, "height": 192, "clear_color": [0.9, 0.9, 0.85, 1]},
        "camera": {"type": "orthographic", "left": -125, "right": 125, "bottom": -94, "top": 94,
                   "near": -300, "far": 300, "eye": [1, 1.2, 1.5], "target": [0, 0, 0]},
        "lights": [{"type": "directional", "direction": [0.3, -1, -0.6]}],
        "draws": [{"mesh": MODELS + "/OBJ/spider.obj"}],
    }


@scene("mesh_truck_float_depth", "mesh", "2, 9, 11, 12",
       "CesiumMilkTruck (glTF 1) lit, float32 depth, rgba16f colour, perspective, 256x160")
def mesh_truck_float_depth():
    return {
        "framebuffer": {"width": 256, "height": 160, "color_format": "rgba16f",
                        "depth_format": "float32", "clear_color": [0.2, 0.3, 0.4, 1]},
        "camera": {"type": "perspective", "fovy": 35, "near": 2, "far": 30,
                   "eye": [5.5, 3.5, 6.5], "target": [0, 1, 0]},
        "lights": [{"type": "directional", "direction": [-1, -1.5, -0.5], "specular": [0.5, 0.5, 0.5, 1]},
                   {"type": "point", "position": [0, 5, 3], "diffuse": [0.6, 0.6, 0.5, 1],
                    "attenuation": [1, 0.05, 0.01]}],
        "draws": [{"mesh": MODELS + "/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf",
                   "state": {"cull": "back"}}],
    }


@scene("mesh_engine_dense", "mesh", "6, 7, 8, 11",
       "2CylinderEngine.glb: 121k triangles in 34 meshes at 256x256, most of them pixel-sized or "
       "smaller (snapping, degenerate triangles, sub-pixel coverage), unorm16 depth")
def mesh_engine_dense():
    return {
        "framebuffer": {"width": 256, "height": 256, "depth_format": "unorm16",
                        "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 45, "near": 200, "far": 2000,
                   "eye": [500, 350, 700], "target": [0, -40, 0]},
        "lights": [{"type": "directional", "direction": [-0.4, -1, -0.7]},
                   {"type": "directional", "direction": [1, 0.2, 0.3], "diffuse": [0.3, 0.3, 0.5, 1]}],
        "draws": [{"mesh": MODELS + "/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"}],
    }


@scene("mesh_duck_cull_front", "mesh", "7, 11",
       "duck.dae (Collada) with cull front and front_face cw: the mesh's clockwise faces are "
       "the front ones, so its back faces go; point light; 200x200")
def mesh_duck_cull_front():
    return {
        "framebuffer": {"width": 200, "height": 200, "clear_color": [0.05, 0.1, 0.05, 1]},
        "camera": {"type": "perspective", "fovy": 50, "near": 0.5, "far": 10,
                   "eye": [1.6, 1.6, 2.2], "target": [0.1, 0.8, 0]},
        "lights": [{"type": "point", "position": [1, 3, 2], "attenuation": [1, 0.1, 0.0]}],
        "draws": [{"mesh": MODELS + "/Collada/duck.dae",
                   "material": {"color": [0.9, 0.8, 0.2, 1], "specular": [0.4, 0.4, 0.4, 1],
                                "shininess": 10},
                   "state": {"cull": "front", "front_face": "cw"}}],
    }


@scene("mesh_terrain_flat", "mesh", "2, 3, 9",
       "fels.3ds terrain, flat shading (provoking = last vertex) with lighting, odd size 255x201")
def mesh_terrain_flat():
    return {
        "framebuffer": {"width": 255, "height": 201, "clear_color": [0.5, 0.6, 0.9, 1]},
        "camera": {"type": "perspective", "fovy": 55, "near": 0.5, "far": 20,
                   "eye": [-0.5, -5.5, 4.5], "target": [-0.4, 0, 0.8], "up": [0, 0, 1]},
        "lights": [{"type": "directional", "direction": [0.5, 0.8, -1]}],
        "draws": [{"mesh": MODELS + "/3DS/fels.3ds",
                   "material": {"color": [0.6, 0.55, 0.45, 1]},
                   "state": {"shading": "flat"}}],
    }


@scene("mesh_sphere_translucent", "mesh", "2, 11, 12",
       "sphereWithHole.stl twice: opaque, then translucent (src_alpha, one_minus_src_alpha, depth "
       "writes off) and scaled so it intersects; rgba8")
def mesh_sphere_translucent():
    return {
        "framebuffer": {"width": 192, "height": 192, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 45, "near": 1, "far": 20,
                   "eye": [5, 4, 6], "target": [1.5, 1.5, 1.5]},
        "lights": [{"type": "directional", "direction": [-1, -1, -1], "specular": [1, 1, 1, 1]}],
        "draws": [
            {"mesh": MODELS + "/STL/sphereWithHole.stl",
             "material": {"color": [0.2, 0.5, 0.9, 1], "specular": [0.8, 0.8, 0.8, 1], "shininess": 40}},
            {"mesh": MODELS + "/STL/sphereWithHole.stl",
             "transform": {"translate": [0.8, 0.6, 0.3], "scale": 0.8},
             "material": {"color": [0.9, 0.3, 0.2, 0.45]},
             "state": {"depth_write": False, "cull": "back",
                       "blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}},
        ],
    }


# ------------------------------------------------------ rasterization stress

@scene("fan_pinwheel", "fill rule", "3, 8",
       "fans of 8 to 96 thin triangles around centres on and off pixel centres, additively blended "
       "(one, one) onto black: a pixel covered twice or a gap shows; 251x199")
def fan_pinwheel():
    rng = random.Random(11)
    w, h = 251, 199
    draws = []
    centres = [(125.5, 99.5), (40.0, 40.0), (200.25, 150.75), (60.5, 160.0), (190.0, 45.5)]
    for k, (cx, cy) in enumerate(centres):
        n = [96, 8, 33, 17, 64][k]
        radius = [90, 35, 45, 30, 40][k]
        pos = [[r(clip_x(cx, w)), r(clip_x(cy, h)), 0, 1]]
        for i in range(n + 1):
            a = 2 * math.pi * (i % n) / n + 0.1 * k
            rad = radius * (1 if i % 2 else rng.uniform(0.7, 1))
            pos.append([r(clip_x(cx + rad * math.cos(a), w)), r(clip_x(cy + rad * math.sin(a), h)), 0, 1])
        draws.append({"primitive": "triangle_fan", "positions": pos,
                      "colors": [[0.25, 0.125, 0.0625, 0.25]] * len(pos),
                      "state": {"depth_test": "off", "blend": {"src": "one", "dst": "one"}}})
    return {"framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 0]}, "draws": draws}


def slivers(rng, size, count, max_length, wide, thin, framebuffer):
    """count random slivers (one vertex almost on the opposite edge) and
    needles (long, under a pixel wide) in every direction over a size x size
    frame: lengths 4..max_length, widths from `wide` (odd i) or `thin` (even
    i), Gouraud colours, depth lequal."""
    w = h = size
    pos, col = [], []
    for i in range(count):
        cx, cy = rng.uniform(0, w), rng.uniform(0, h)
        length = rng.uniform(4, max_length)
        a = rng.uniform(0, 2 * math.pi)
        dx, dy = math.cos(a) * length / 2, math.sin(a) * length / 2
        width = rng.uniform(*wide) if i % 2 else rng.uniform(*thin)
        t = rng.uniform(0.1, 0.9)
        ox, oy = -math.sin(a) * width, math.cos(a) * width
        for (x, y) in ((cx - dx, cy - dy), (cx + dx, cy + dy),
                       (cx - dx + 2 * t * dx + ox, cy - dy + 2 * t * dy + oy)):
            pos.append([r(clip_x(x, w)), r(clip_x(y, h)), r(rng.uniform(-0.9, 0.9)), 1])
            col.append(rcol(rng))
    return {"framebuffer": dict({"width": w, "height": h}, **framebuffer),
            "draws": [{"primitive": "triangles", "positions": pos, "colors": col,
                       "state": {"depth_test": "lequal"}}]}


@scene("slivers_needles", "fill rule", "6, 7, 8",
       "600 random slivers (one vertex almost on the opposite edge) and needles (long, under a "
       "pixel wide) in every direction, Gouraud colours, depth lequal, unorm24")
def slivers_needles():
    return slivers(random.Random(21), 160, 600, 120, (0.01, 1.2), (0.0005, 0.05),
                   {"clear_color": [0, 0, 0, 1]})


@scene("tiny_subpixel", "fill rule", "6, 7, 8",
       "1-pixel and sub-pixel triangles: random ones of 1/16 to 2 pixels, and small triangles "
       "placed exactly on pixel centres and 1/256 either side, both windings; degenerate ones "
       "(zero area after snapping)")
def tiny_subpixel():
    rng = random.Random(31)
    w, h = 128, 128
    pos, col = [], []

    def add(pts, z=0.0, exact=False):
        # exact: on the subpixel grid, written unrounded (the values are
        # multiples of 2^-14, exact in float, and clip -> window is exact at 128x128).
        for (x, y) in pts:
            if exact:
                pos.append([clip_x(x, w), clip_x(y, h), z, 1])
            else:
                pos.append([r(clip_x(x, w)), r(clip_x(y, h)), z, 1])
            col.append(rcol(rng))

    for _ in range(800):
        cx, cy = rng.uniform(0, w), rng.uniform(0, h)
        s = 2.0 ** rng.uniform(-4, 1)
        add([(cx + s * rng.uniform(-1, 1), cy + s * rng.uniform(-1, 1)) for _ in range(3)],
            r(rng.uniform(-0.5, 0.5)))
    # On the subpixel grid around pixel centres: offsets of -1, 0, +1 subpixel.
    step = 1 / 256
    for j in range(16):
        for i in range(16):
            px, py = 4 + i * 7 + 0.5, 4 + j * 7 + 0.5
            ox = ((i % 3) - 1) * step
            oy = ((j % 3) - 1) * step
            size = [0.5, 1.0, 0.25, 2.0][(i + j) % 4]
            tri = [(px + ox, py + oy), (px + ox + size, py + oy), (px + ox, py + oy + size)]
            if (i + j) % 2:
                tri = [tri[0], tri[2], tri[1]]  # clockwise
            if (i * j) % 5 == 4:
                tri = [(px + ox - size, py + oy), (px + ox, py + oy), (px + ox, py + oy - size)]
            add(tri, exact=True)
    # Degenerate after snapping: three points within one subpixel cell.
    for k in range(20):
        x, y = 10 + k * 5.3, 50.2
        add([(x, y), (x + 0.001, y), (x, y + 0.001)], exact=True)
    return {"framebuffer": {"width": w, "height": h, "depth_format": "unorm16",
                            "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "triangles", "positions": pos, "colors": col,
                       "state": {"depth_test": "always"}}]}


@scene("fullscreen_huge", "clipping", "4, 5, 8",
       "a full-screen triangle, quads as big as the viewport, a triangle reaching 20000 pixels out "
       "(inside the guard band: not clipped by the spec) and one far beyond the guard band "
       "(clipped by the spec), flat and Gouraud")
def fullscreen_huge():
    w, h = 200, 150
    return {
        "framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 1]},
        "draws": [
            {"positions": [[-1, -1, 0.9], [3, -1, 0.9], [-1, 3, 0.9]],
             "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]]},
            {"positions": [[-150, -0.8, 0.5], [199, -0.7, 0.2], [0.2, 230, -0.3]],
             "colors": [[0.9, 0.9, 0.2, 1], [0.2, 0.9, 0.9, 1], [0.9, 0.2, 0.9, 1]],
             "state": {"depth_test": "lequal"}},
            {"positions": [[-2000, -900, 0.1, 1], [3000, -700, 0.1, 1], [-0.3, 0.6, 0.1, 1]],
             "colors": [[0.3, 0.3, 0.3, 1], [0.8, 0.5, 0.1, 1], [0.1, 0.6, 0.3, 1]],
             "state": {"depth_test": "lequal", "shading": "flat"}},
            {"primitive": "triangle_strip", "positions": quad_strip(-0.5, -1.0, 1.0, 0.25, -0.5),
             "colors": [[0, 0, 0, 1], [1, 1, 1, 1], [1, 0, 0, 1], [0, 0, 1, 1]],
             "state": {"depth_test": "lequal", "blend": {"src": "one", "dst": "one"}}},
        ],
    }


def jittered_grid(rng, w, h, n, m, jitter):
    """An n x m grid of quads over a w x h frame, as indexed triangles sharing
    every edge; inner vertices moved by up to `jitter` pixels, the diagonals
    alternating. Returns (positions, indices)."""
    pos, idx = [], []
    for j in range(m + 1):
        for i in range(n + 1):
            x, y = i * w / n, j * h / m
            if 0 < i < n and 0 < j < m:
                x += rng.uniform(-jitter, jitter)
                y += rng.uniform(-jitter, jitter)
            pos.append([r(clip_x(x, w)), r(clip_x(y, h)), 0.5, 1])
    for j in range(m):
        for i in range(n):
            a = j * (n + 1) + i
            if (i + j) % 2:
                idx += [a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]
            else:
                idx += [a, a + 1, a + n + 1, a + 1, a + n + 2, a + n + 1]
    return pos, idx


@scene("grid_shared_edges", "fill rule", "7, 8",
       "a 16x8 grid of jittered quads (indexed triangles sharing every edge) plus exact "
       "horizontal and vertical edges through pixel centres, additively blended: every pixel "
       "exactly once")
def grid_shared_edges():
    w, h = 256, 128
    pos, idx = jittered_grid(random.Random(41), w, h, 16, 8, 4)
    # Axis-aligned quads whose edges run exactly through pixel centres.
    axis = []
    for k in range(8):
        x0, y0 = 10.5 + 30 * k, 20.5 + 3 * k
        x1, y1 = x0 + 12 + k, y0 + 80
        p = lambda x, y: [clip_x(x, w), clip_x(y, h), 0.2, 1]  # exact: 2^-7 multiples
        axis += [p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y0), p(x1, y1), p(x0, y1)]
    additive = {"depth_test": "off", "blend": {"src": "one", "dst": "one"}}
    return {
        "framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 0]},
        "draws": [
            {"positions": pos, "indices": idx, "colors": [[0.25, 0.25, 0.25, 0.25]] * len(pos),
             "state": additive},
            {"positions": axis, "colors": [[0.0, 0.3, 0.5, 0.25]] * len(axis), "state": additive},
        ],
    }


@scene("snapping_ties", "fill rule", "6, 8",
       "300 triangles whose vertices lie exactly halfway between subpixels (k/256 + 1/512 or "
       "3/512: ties to even, both directions), at 128x64 so that clip -> window is exact")
def snapping_ties():
    rng = random.Random(51)
    w, h = 128, 64
    pos, col = [], []
    for _ in range(300):
        cx, cy = rng.randrange(2, w - 8), rng.randrange(2, h - 8)
        pts = []
        for _ in range(3):
            sx = cx + rng.randrange(0, 6 * 256) / 256 + (rng.choice([1, 3]) / 512)
            sy = cy + rng.randrange(0, 6 * 256) / 256 + (rng.choice([1, 3]) / 512)
            pts.append((sx, sy))
        for (x, y) in pts:
            pos.append([clip_x(x, w), clip_x(y, h), 0, 1])
            col.append(rcol(rng))
    return {"framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 1]},
            "draws": [{"positions": pos, "colors": col, "state": {"depth_test": "off"}}]}


# ------------------------------------------------------------------- depth

def zfight_planes(depth_format, offset_a, offset_b):
    quad = quad_strip(-1, -1, 1, 1)

    def plane(color, state, scale=1.0):
        return {"primitive": "triangle_strip", "positions": quad, "colors": [color] * 4,
                "transform": {"rotate": [[55, 1, 0, 0], [30, 0, 1, 0]], "translate": [0, 0, -3.2],
                              "scale": scale},
                "state": state}
    return {
        "framebuffer": {"width": 160, "height": 160, "depth_format": depth_format,
                        "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 20},
        "draws": [
            plane([0.8, 0.2, 0.2, 1], {"depth_test": "less"}),
            plane([0.2, 0.8, 0.2, 1], {"depth_test": "less"}),  # coplanar, loses everywhere
            # The same triangles again: equal passes everywhere, in any arithmetic.
            plane([0.9, 0.5, 0.9, 1], {"depth_test": "equal", "depth_write": False,
                                       "color_mask": [True, False, True, False]}),
            plane([0.9, 0.9, 0.2, 1], {"depth_test": "less", "polygon_offset": offset_a}, 0.7),
            plane([0.2, 0.3, 0.9, 1], {"depth_test": "lequal", "polygon_offset": offset_b}, 0.4),
        ],
    }


@scene("zfight_coplanar", "depth", "9, 11",
       "coplanar planes without polygon offset: the same triangles again lose with less, win "
       "with lequal and equal (also submitted as another primitive type); unorm24")
def zfight_coplanar():
    quad = quad_strip(-1, -1, 1, 1)
    tf = {"rotate": [[-50, 1, 0, 0], [20, 0, 0, 1]], "translate": [0, 0, -3]}
    return {
        "framebuffer": {"width": 160, "height": 120, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 10},
        "draws": [
            {"primitive": "triangle_strip", "positions": quad, "colors": [[0.8, 0.1, 0.1, 1]] * 4,
             "transform": tf},
            {"primitive": "triangle_strip", "positions": quad, "colors": [[0.1, 0.8, 0.1, 1]] * 4,
             "transform": tf, "state": {"depth_test": "less"}},
            # The strip's second triangle again, as a list: lequal passes all over it.
            {"primitive": "triangles", "positions": [[-1, 1, 0], [1, -1, 0], [1, 1, 0]],
             "colors": [[0.1, 0.1, 0.8, 1]] * 3, "transform": tf, "state": {"depth_test": "lequal"}},
            # The strip's first triangle again with equal and no depth writes.
            {"primitive": "triangles", "positions": [[-1, -1, 0], [1, -1, 0], [-1, 1, 0]],
             "colors": [[0.9, 0.9, 0.9, 1], [0.9, 0.2, 0.9, 1], [0.2, 0.9, 0.9, 1]], "transform": tf,
             "state": {"depth_test": "equal", "depth_write": False}},
        ],
    }


@scene("zfight_offset_unorm16", "depth", "10, 11",
       "coplanar planes separated by polygon offset (factor and units, positive and negative), "
       "unorm16 depth")
def zfight_offset_unorm16():
    return zfight_planes("unorm16", [-1, -2], [-1, -8])


@scene("zfight_offset_unorm24", "depth", "10, 11",
       "coplanar planes separated by polygon offset, unorm24 depth")
def zfight_offset_unorm24():
    return zfight_planes("unorm24", [-2, -1], [-3, 0])


@scene("zfight_offset_float32", "depth", "10, 11",
       "coplanar planes separated by polygon offset, float32 depth (r from the exponent of the "
       "largest z)")
def zfight_offset_float32():
    return zfight_planes("float32", [-1, -4], [-1, -2000])


@scene("depth_funcs", "depth", "11",
       "every depth function (never .. always, off) and depth_write false on interpenetrating "
       "tilted quads over a sloped background; clear depth 0.75; unorm24")
def depth_funcs():
    rng = random.Random(61)
    funcs = ["never", "less", "equal", "lequal", "greater", "notequal", "gequal", "always", "off"]
    draws = [{"primitive": "triangle_strip",
              "positions": [[-1, -1, -0.6], [1, -1, 0.2], [-1, 1, 0.4], [1, 1, 0.9]],
              "colors": [[0.3, 0.3, 0.3, 1]] * 4}]
    for k, f in enumerate(funcs):
        cx, cy = -0.66 + 0.66 * (k % 3), -0.66 + 0.66 * (k // 3)
        for layer in range(2):
            z0, z1 = r(rng.uniform(-0.8, 0.8)), r(rng.uniform(-0.8, 0.8))
            s = 0.28 - 0.06 * layer
            draws.append({"primitive": "triangle_strip",
                          "positions": [[r(cx - s), r(cy - s), z0], [r(cx + s), r(cy - s), z1],
                                        [r(cx - s), r(cy + s), z1], [r(cx + s), r(cy + s), z0]],
                          "colors": [rcol(rng) for _ in range(4)],
                          "state": {"depth_test": f, "depth_write": layer == 0 or k % 2 == 0}})
    return {"framebuffer": {"width": 150, "height": 150, "clear_color": [0, 0, 0, 1],
                            "clear_depth": 0.75},
            "draws": draws}


@scene("interpenetrating_unorm16", "depth", "9, 11",
       "five planes through one another at different angles in unorm16: the intersection "
       "lines depend on depth interpolation and rounding")
def interpenetrating_unorm16():
    rng = random.Random(71)
    draws = []
    for k in range(5):
        a = k * 36
        draws.append({"primitive": "triangle_strip", "positions": quad_strip(-1.2, -0.6, 1.2, 0.6),
                      "colors": [rcol(rng) for _ in range(4)],
                      "transform": {"rotate": [[a, 0, 1, 0], [15 * k - 30, 1, 0, 0]],
                                    "translate": [0, 0, -3]}})
    return {"framebuffer": {"width": 192, "height": 128, "depth_format": "unorm16",
                            "clear_color": [0.1, 0.1, 0.1, 1]},
            "camera": {"type": "perspective", "fovy": 50, "near": 1, "far": 8},
            "draws": draws}


@scene("clear_only", "depth", "11, 12",
       "no draws: the clear colour and clear depth (0.3) in unorm16, with colour values that are "
       "not multiples of 1/255")
def clear_only():
    return {"framebuffer": {"width": 64, "height": 48, "depth_format": "unorm16",
                            "clear_color": [0.3, 0.6, 0.123, 0.77], "clear_depth": 0.3},
            "draws": []}


# ---------------------------------------------------------------- clears

def perspective_clip(fovy_deg, aspect, near, far):
    """GL's perspective projection as a function of an eye-space point: the
    clip coordinates, so that a scene can use several projections."""
    f = 1.0 / math.tan(math.radians(fovy_deg) / 2)

    def clip(p):
        x, y, z = p
        return [r(f / aspect * x), r(f * y),
                r((far + near) / (near - far) * z + 2 * far * near / (near - far)), r(-z)]
    return clip


def eye_rect(x0, y0, x1, y1, z):
    return [(x0, y0, z), (x1, y0, z), (x0, y1, z), (x1, y1, z)]


@scene("clear_depth_partition", "clears", "11, 15",
       "the depth-partition trick in unorm16: eye distances 0.5 to 9000, where one projection "
       "cannot tell surfaces 100 apart at 6000; far pass (projection 100..10000), depth clear, "
       "near pass (0.5..100), whose depths exceed the far pass's")
def clear_depth_partition():
    w, h = 160, 120
    far = perspective_clip(60, w / h, 100, 10000)
    near = perspective_clip(60, w / h, 0.5, 100)

    def quad(clip, corners, color, name):
        return {"name": name, "primitive": "triangle_strip",
                "positions": [clip(c) for c in corners], "colors": [color] * 4}
    draws = [
        quad(far, eye_rect(-9000, -4000, 9000, 1500, -9000), [0.35, 0.3, 0.25, 1],
             "far: ground plate"),
        # Front to back, so the back one fails where they overlap.
        quad(far, eye_rect(-2500, -1500, 800, 2000, -5900), [0.85, 0.2, 0.15, 1],
             "far: red at 5900"),
        quad(far, eye_rect(-800, -2500, 2500, 1000, -6000), [0.15, 0.3, 0.85, 1],
             "far: blue at 6000"),
        {"clear": {"depth": 1}},
        # Window z 0.995 here against the red quad's 0.993: it fails without the clear.
        quad(near, eye_rect(-30, -25, 10, 5, -50), [0.9, 0.8, 0.2, 1], "near: yellow at 50"),
        {"name": "near: green triangle from 1.5 to 3", "primitive": "triangles",
         "positions": [near((-0.9, -0.6, -1.5)), near((1.6, -0.2, -3)), near((0.2, 1.1, -2.2))],
         "colors": [[0.2, 0.8, 0.3, 1], [0.1, 0.6, 0.2, 1], [0.3, 0.9, 0.4, 1]]},
    ]
    return {"framebuffer": {"width": w, "height": h, "depth_format": "unorm16",
                            "clear_color": [0.5, 0.7, 0.9, 1]},
            "draws": draws}


@scene("clear_color_between_draws", "clears", "11, 12, 15",
       "a colour-only clear between draws: the first triangle's depth stays and hides the "
       "full-screen quad drawn after the clear, so the clear colour shows its shape; a "
       "translucent triangle blends over both")
def clear_color_between_draws():
    def tri(p, color, name, state=None):
        d = {"name": name, "primitive": "triangles", "positions": p, "colors": [color] * 3}
        if state:
            d["state"] = state
        return d
    return {
        "framebuffer": {"width": 128, "height": 128, "clear_color": [0, 0, 0, 1]},
        "draws": [
            tri([[-0.9, -0.8, -0.5], [0.4, -0.7, -0.4], [-0.5, 0.8, -0.6]], [1, 1, 1, 1],
                "hidden: its depth stays, its colour is cleared"),
            {"clear": {"color": [0.2, 0.4, 0.6, 1]}},
            {"name": "full-screen quad behind the hidden triangle", "primitive": "triangle_strip",
             "positions": quad_strip(-1, -1, 1, 1), "colors": [[0.9, 0.5, 0.1, 1]] * 4},
            tri([[-0.2, -0.95, -0.9], [0.95, 0.1, -0.9], [-0.6, 0.6, -0.9]],
                [0.1, 0.9, 0.3, 0.5], "translucent, over both",
                {"blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}),
        ],
    }


# ---------------------------------------------------------------- clipping

@scene("near_plane", "clipping", "4, 5, 9",
       "triangles crossing the near plane at grazing and steep angles, a ground plane through it, "
       "perspective-correct colours on the cut; float32 depth")
def near_plane():
    rng = random.Random(81)
    tris, col = [], []
    for _ in range(12):
        cx, cy = rng.uniform(-1.5, 1.5), rng.uniform(-1, 1)
        for k in range(3):
            tris.append([r(cx + rng.uniform(-1.5, 1.5)), r(cy + rng.uniform(-1, 1)),
                         r(rng.uniform(-6, 0.3))])
            col.append(rcol(rng))
    return {
        "framebuffer": {"width": 160, "height": 120, "depth_format": "float32",
                        "clear_color": [0.05, 0.05, 0.1, 1]},
        "camera": {"type": "perspective", "fovy": 70, "near": 0.5, "far": 40},
        "draws": [
            {"primitive": "triangle_strip",
             "positions": [[-30, -1, 5], [30, -1, 5], [-30, -1, -30], [30, -1, -30]],
             "colors": [[0.9, 0.1, 0.1, 1], [0.1, 0.9, 0.1, 1], [0.1, 0.1, 0.9, 1], [0.9, 0.9, 0.1, 1]]},
            {"positions": tris, "colors": col, "state": {"depth_test": "lequal"}},
        ],
    }


@scene("frustum_planes", "clipping", "4, 5",
       "triangles crossing each frustum plane: left, right, bottom and top are inside the guard "
       "band (not clipped: coverage exact), far is clipped; orthographic camera")
def frustum_planes():
    col = [[1, 0.2, 0.2, 1], [0.2, 1, 0.2, 1], [0.2, 0.2, 1, 1]]
    draws = []
    for (pts) in ([[-1.6, -0.2, -1], [-0.5, 0.1, -1], [-1.4, 0.6, -1]],    # left
                  [[1.7, -0.5, -2], [0.6, -0.3, -2], [1.3, 0.4, -2]],      # right
                  [[-0.4, -1.5, -3], [0.2, -1.4, -3], [0.0, -0.6, -3]],    # bottom
                  [[-0.3, 1.6, -4], [0.1, 0.7, -4], [0.5, 1.8, -4]],       # top
                  [[-0.5, -0.5, -1], [0.5, -0.4, -12], [0.0, 0.5, -6]],    # far
                  [[-3, -3, -5], [3, -3, -5], [0, 3, -5]]):                # all four
        draws.append({"positions": pts, "colors": col, "state": {"depth_test": "lequal"}})
    return {"framebuffer": {"width": 160, "height": 160, "clear_color": [0, 0, 0, 1]},
            "camera": {"type": "orthographic", "left": -1, "right": 1, "bottom": -1, "top": 1,
                       "near": 0.5, "far": 8},
            "draws": draws}


@scene("behind_eye", "clipping", "4",
       "triangles with vertices behind the eye (w < 0), one vertex at w = 0, and one entirely "
       "behind (clipped away); raw clip coordinates")
def behind_eye():
    return {
        "framebuffer": {"width": 128, "height": 128, "clear_color": [0, 0, 0, 1]},
        "draws": [
            {"positions": [[-0.5, -0.5, 0, 1], [0.5, -0.5, 0, -1], [0, 0.5, 0, 1]],
             "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]]},
            {"positions": [[-0.9, 0.2, 0.5, 1], [0.2, 0.9, 0.5, 0], [-0.9, 0.9, 0.5, 1]],
             "colors": [[1, 1, 0, 1], [0, 1, 1, 1], [1, 0, 1, 1]], "state": {"depth_test": "lequal"}},
            {"positions": [[0.3, -0.9, 0.2, 0.5], [0.9, -0.9, 0.2, -2], [0.9, -0.2, -0.4, 2]],
             "colors": [[1, 1, 1, 1], [0.2, 0.2, 0.2, 1], [1, 0.5, 0, 1]],
             "state": {"shading": "flat", "depth_test": "lequal"}},
            {"positions": [[-0.5, -0.5, 0, -1], [0.5, -0.5, 0, -1], [0, 0.5, 0, -1]],
             "colors": [[1, 1, 1, 1]] * 3},
        ],
    }


# ----------------------------------------------- assembly, culling, shading

@scene("strips_fans_cull", "assembly", "3, 7, 9",
       "strips and fans (indexed and not) under every cull mode and front face, flat shading "
       "with distinct provoking colours, a partial last triangle, out-of-range indices")
def strips_fans_cull():
    rng = random.Random(91)
    draws = []
    for k in range(12):
        cx, cy = -0.78 + 0.31 * (k % 6), -0.5 + 1.0 * (k // 6)
        strip = k % 2 == 0
        n = 9
        pos = []
        for v in range(n):
            if strip:
                pos.append([r(cx - 0.12 + 0.03 * v), r(cy + (0.3 if v % 2 else -0.3) * (1 if v < 5 else -1)),
                            r(rng.uniform(-0.5, 0.5))])
            else:
                a = 2 * math.pi * v / (n - 1) * (1 if k % 4 < 2 else -1)
                pos.append([r(cx + (0 if v == 0 else 0.14 * math.cos(a))),
                            r(cy + (0 if v == 0 else 0.3 * math.sin(a))), r(rng.uniform(-0.5, 0.5))])
        d = {"primitive": "triangle_strip" if strip else "triangle_fan", "positions": pos,
             "colors": [rcol(rng) for _ in pos],
             "state": {"cull": ["none", "back", "front"][k % 3], "front_face": ["ccw", "cw"][(k // 3) % 2],
                       "shading": "flat" if k % 4 in (1, 2) else "gouraud"}}
        if k % 5 == 3:
            d["indices"] = list(range(n)) + [2, 7, 40]  # the last triangle has an out-of-range index
        draws.append(d)
    draws.append({"primitive": "triangles",
                  "positions": [[-0.9, -0.95, 0], [-0.6, -0.95, 0], [-0.75, -0.8, 0], [0.5, 0.5, 0]],
                  "colors": [[1, 1, 1, 1]] * 4})  # 4 vertices: the partial triangle is ignored
    return {"framebuffer": {"width": 224, "height": 128, "clear_color": [0.1, 0.1, 0.1, 1]},
            "draws": draws}


@scene("cull_modes", "assembly", "7",
       "a grid of triangles of both windings drawn with each of cull none/back/front and front "
       "face ccw/cw; a mirrored (negative scale) transform flips windings")
def cull_modes():
    rng = random.Random(101)
    draws = []
    combos = [(c, f) for c in ("none", "back", "front") for f in ("ccw", "cw")]
    for k, (cull, front) in enumerate(combos):
        ox, oy = -0.66 + 0.66 * (k % 3), -0.5 + 1.0 * (k // 3)
        pos, col = [], []
        for j in range(3):
            for i in range(3):
                x, y = ox - 0.25 + 0.17 * i, oy - 0.4 + 0.27 * j
                tri = [[r(x), r(y), 0], [r(x + 0.15), r(y), 0], [r(x + 0.07), r(y + 0.22), 0]]
                if (i + j) % 2:
                    tri = [tri[0], tri[2], tri[1]]
                pos += tri
                col += [rcol(rng) for _ in range(3)]
        draws.append({"positions": pos, "colors": col, "state": {"cull": cull, "front_face": front}})
    draws.append({"positions": [[0.1, 0.1, 0], [0.3, 0.1, 0], [0.2, 0.3, 0]],
                  "colors": [[1, 1, 1, 1]] * 3,
                  "transform": {"scale": [-1, 1, 1], "translate": [0, -0.2, 0]},
                  "state": {"cull": "back", "depth_test": "always"}})
    return {"framebuffer": {"width": 192, "height": 160, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("perspective_gouraud", "shading", "9",
       "a long receding floor and wall with strongly different vertex colours (perspective-"
       "correct interpolation), the same in flat shading, and colours outside [0, 1] (clamped)")
def perspective_gouraud():
    return {
        "framebuffer": {"width": 200, "height": 150, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 0.5, "far": 100,
                   "eye": [0, 1, 0], "target": [0.3, 0.6, -5]},
        "draws": [
            {"primitive": "triangle_strip",
             "positions": [[-3, 0, -1], [3, 0, -1], [-3, 0, -60], [3, 0, -60]],
             "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]]},
            {"primitive": "triangle_strip",
             "positions": [[3, 0, -1], [3, 4, -1], [3, 0, -60], [3, 4, -60]],
             "colors": [[2, -1, 0.5, 1], [0, 0, 0, 1], [-0.5, 1.5, 0, 1], [1, 0, 1, 1]]},
            {"primitive": "triangle_strip",
             "positions": [[-3, 0, -1], [-3, 4, -1], [-3, 0, -60], [-3, 4, -60]],
             "colors": [[0.9, 0.5, 0.1, 1], [0.1, 0.5, 0.9, 1], [0.5, 0.9, 0.1, 1], [0.9, 0.1, 0.5, 1]],
             "state": {"shading": "flat"}},
        ],
    }


VERTEX_COLOURS = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [1, 0, 1, 1],
                  [0, 1, 1, 1], [1, 1, 1, 1], [0.5, 0.25, 0, 1], [0.25, 0.5, 1, 1]]
FLAT_FIRST = {"shading": "flat", "provoking_vertex": "first"}


@scene("provoking_first_strip_fan", "shading", "3, 9",
       "flat shading with provoking_vertex first (glProvokingVertex(GL_FIRST_VERTEX_CONVENTION)), "
       "every vertex a different colour: a strip (triangle i takes vertex i), a fan (triangle i "
       "takes vertex i+1, not the centre) and a line loop (its closing line takes the last "
       "vertex)")
def provoking_first_strip_fan():
    fan = [[0.45, -0.05, 0.0, 1.0]]
    for i in range(6):
        a = math.radians(10 + i * 60)
        fan.append([r(0.45 + 0.4 * math.cos(a)), r(-0.05 + 0.4 * math.sin(a) * 4 / 3), 0.0, 1.0])
    return {
        "framebuffer": {"width": 160, "height": 120, "clear_color": [0, 0, 0, 1]},
        "draws": [
            {"primitive": "triangle_strip",
             "positions": [[r(-0.9 + 0.25 * (i // 2)), r(0.1 + 0.7 * (i % 2)), 0.0, 1.0]
                           for i in range(7)],
             "colors": VERTEX_COLOURS[:7], "state": FLAT_FIRST},
            {"primitive": "triangle_fan", "positions": fan, "colors": VERTEX_COLOURS[2:9],
             "state": FLAT_FIRST},
            {"primitive": "line_loop",
             "positions": [[-0.8513, -0.8471, 0, 1], [-0.1529, -0.7983, 0, 1],
                           [-0.2017, -0.1537, 0, 1], [-0.7991, -0.2479, 0, 1]],
             "colors": VERTEX_COLOURS[3:7], "state": FLAT_FIRST},
        ],
    }


@scene("provoking_first_clipped", "clipping", "3, 4, 9",
       "flat shading with provoking_vertex first on triangles and a strip crossing the near "
       "plane, the provoking vertex of several beyond it: the colour of the vertex the clipper "
       "cut away survives on every piece; perspective camera")
def provoking_first_clipped():
    return {
        "framebuffer": {"width": 200, "height": 150, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 0.5, "far": 100,
                   "eye": [0, 1, 0], "target": [0, 0.6, -5]},
        "draws": [
            {"primitive": "triangles",
             "positions": [[-2, 0, 1], [-0.5, 0, -8], [-2.5, 0, -8], [0.3, 0, 2], [2.5, 0, -6],
                           [0.5, 0, -6], [0, 2.5, -3], [-1, 0.2, 3], [1, 0.2, 3]],
             "colors": VERTEX_COLOURS, "state": FLAT_FIRST},
            {"primitive": "triangle_strip",
             "positions": [[-1, -0.3, 2], [1, -0.3, 2], [-1, -0.3, -4], [1, -0.3, -4],
                           [-1, -0.3, -10], [1, -0.3, -10]],
             "colors": VERTEX_COLOURS[3:9], "state": FLAT_FIRST},
        ],
    }


@scene("interpolation_screen_quad", "shading", "5, 9",
       "a receding floor quad twice, perspective-correct (left) and with interpolation screen "
       "(right: affine in window space, GLSL noperspective, the scan-line Gouraud that "
       "perspective correction fixes), the same vertex colours; perspective camera")
def interpolation_screen_quad():
    def quad(x0, x1):
        return [[x0, 0, -1], [x1, 0, -1], [x0, 0, -40], [x1, 0, -40]]
    colours = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]]
    return {
        "framebuffer": {"width": 240, "height": 160, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 0.5, "far": 100,
                   "eye": [0, 1.2, 0], "target": [0, 0.4, -5]},
        "draws": [
            {"primitive": "triangle_strip", "positions": quad(-3.2, -0.2), "colors": colours},
            {"primitive": "triangle_strip", "positions": quad(0.2, 3.2), "colors": colours,
             "state": {"interpolation": "screen"}},
        ],
    }


@scene("interpolation_screen_clipped", "clipping", "4, 9",
       "interpolation screen through the clipper: a floor quad reaching behind the eye, crossing "
       "the near plane, beside the same quad perspective-correct: a cut vertex takes the colour "
       "affine in window space (llvmpipe's t_nopersp), extrapolated from the vertices behind "
       "the eye")
def interpolation_screen_clipped():
    colours = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]]
    return {
        "framebuffer": {"width": 200, "height": 150, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 60, "near": 0.5, "far": 100,
                   "eye": [0, 1, 0], "target": [0, 0.6, -5]},
        "draws": [
            {"primitive": "triangle_strip",
             "positions": [[-3, 0, 3], [-0.1, 0, 3], [-3, 0, -20], [-0.1, 0, -20]],
             "colors": colours, "state": {"interpolation": "screen"}},
            {"primitive": "triangle_strip",
             "positions": [[0.1, 0, 3], [3, 0, 3], [0.1, 0, -20], [3, 0, -20]],
             "colors": colours},
        ],
    }


@scene("camera_matrices", "shading", "1, 2, 7",
       "a camera given as matrices: a mirrored, oblique projection (windings flip, culling "
       "follows window space) over a lit WusonOBJ and raw triangles")
def camera_matrices():
    return {
        "framebuffer": {"width": 160, "height": 160, "clear_color": [0.2, 0.2, 0.2, 1]},
        "camera": {"view": [[1, 0, 0, 0], [0, 1, 0, -1.0], [0, 0, 1, -3.4], [0, 0, 0, 1]],
                   "projection": [[-1.4, 0.2, 0, 0], [0, 1.4, 0.1, 0], [0, 0, -1.2, -2.2],
                                  [0, 0, -1, 0]]},
        "lights": [{"type": "directional", "direction": [0.2, -0.5, -1]}],
        "draws": [
            {"mesh": MODELS + "/PLY/Wuson.ply", "transform": {"rotate": [60, 0, 1, 0], "scale": 1.3},
             "material": {"color": [0.7, 0.5, 0.3, 1]},
             "state": {"cull": "back", "front_face": "cw"}},  # the mirror makes its front faces cw
            {"positions": [[-1.5, -1.2, -1], [-0.5, -1.2, -1], [-1, 0, -1]],
             "colors": [[1, 0, 0, 1], [1, 1, 0, 1], [1, 0, 1, 1]], "state": {"cull": "back"}},
            {"positions": [[1.5, -1.2, -1], [0.5, -1.2, -1], [1, 0, -1]],
             "colors": [[0, 1, 0, 1], [0, 1, 1, 1], [0, 0, 1, 1]], "state": {"cull": "back"}},
        ],
    }


# ---------------------------------------------------------------- blending

BLEND_FACTORS = ["zero", "one", "src_color", "one_minus_src_color", "dst_color", "one_minus_dst_color",
                 "src_alpha", "one_minus_src_alpha", "dst_alpha", "one_minus_dst_alpha",
                 "src_alpha_saturate"]


def blend_grid(rng, equations):
    """Every source factor against a destination factor, in a grid over a
    gradient background, two overlapping quads per cell (order matters)."""
    draws = [{"primitive": "triangle_strip", "positions": quad_strip(-1, -1, 1, 1, 0.9),
              "colors": [[0.1, 0.2, 0.9, 0.2], [0.9, 0.2, 0.1, 0.9], [0.1, 0.9, 0.2, 0.6],
                         [0.8, 0.8, 0.8, 1.0]], "state": {"depth_test": "off"}}]
    n = len(BLEND_FACTORS)
    for i, src in enumerate(BLEND_FACTORS):
        dst = BLEND_FACTORS[(i * 4 + 3) % n]
        for j, eq in enumerate(equations):
            x0 = -1 + 2 * i / n
            y0 = -1 + 2 * j / len(equations)
            cw, ch = 2 / n, 2 / len(equations)
            for layer in range(2):
                a = rng.uniform(0.1, 0.95)
                pos = quad_strip(r(x0 + cw * (0.1 + 0.25 * layer)), r(y0 + ch * (0.1 + 0.25 * layer)),
                                 r(x0 + cw * (0.65 + 0.25 * layer)), r(y0 + ch * (0.65 + 0.25 * layer)),
                                 0)
                draws.append({"primitive": "triangle_strip", "positions": pos,
                              "colors": [rcol(rng, r(a)) for _ in range(4)],
                              "state": {"depth_test": "off",
                                        "blend": {"src": src if layer == 0 else dst,
                                                  "dst": dst if layer == 0 else src, "equation": eq}}})
    return draws


@scene("blend_factors_rgba8", "blending", "12",
       "every blend factor as source and destination with add, subtract and reverse_subtract, "
       "two overlapping quads per cell over a Gouraud background, rgba8 (clamped)")
def blend_factors_rgba8():
    rng = random.Random(111)
    return {"framebuffer": {"width": 220, "height": 96, "clear_color": [0, 0, 0, 0]},
            "draws": blend_grid(rng, ["add", "subtract", "reverse_subtract"])}


@scene("blend_rgba16f", "blending", "12",
       "the blend grid in rgba16f: unclamped results, negative values from subtract, HDR sums "
       "from repeated additive layers")
def blend_rgba16f():
    rng = random.Random(121)
    draws = blend_grid(rng, ["add", "subtract", "reverse_subtract"])
    for k in range(6):
        draws.append({"primitive": "triangle_strip",
                      "positions": quad_strip(r(-0.9 + 0.1 * k), -0.3, r(0.2 + 0.1 * k), 0.4, 0),
                      "colors": [[0.7, 0.5, 0.3, 0.5]] * 4,
                      "state": {"depth_test": "off", "blend": {"src": "one", "dst": "one"}}})
    return {"framebuffer": {"width": 220, "height": 96, "color_format": "rgba16f",
                            "clear_color": [0.25, -0.5, 2.0, 0.5]},
            "draws": draws}


@scene("blend_order", "blending", "11, 12",
       "translucent layers in back-to-front and front-to-back order with depth test on and depth "
       "writes off: the result depends on submission order only")
def blend_order():
    rng = random.Random(131)
    draws = []
    for side, order in ((-1, range(6)), (1, reversed(range(6)))):
        for k in order:
            z = -0.8 + 0.3 * k
            x0 = 0.5 * side - 0.4 + 0.05 * k
            y0 = -0.7 + 0.08 * k
            draws.append({"primitive": "triangle_strip",
                          "positions": quad_strip(r(x0), r(y0), r(x0 + 0.45), r(y0 + 0.9), r(z)),
                          "colors": [rcol(rng, 0.5)] * 4,
                          "state": {"depth_write": False, "depth_test": "lequal",
                                    "blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}})
    # The opaque bar's depth matches no layer's (a tie would hang on rounding).
    draws.insert(0, {"primitive": "triangle_strip", "positions": quad_strip(-1, -0.1, 1, 0.05, 0.15),
                     "colors": [[1, 1, 1, 1]] * 4})
    return {"framebuffer": {"width": 200, "height": 120, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("color_mask", "blending", "12",
       "colour masks (each channel, none, all) with and without blending, over overlapping quads")
def color_mask():
    rng = random.Random(141)
    masks = [[True, False, False, False], [False, True, False, True], [False, False, True, False],
             [False, False, False, True], [False, False, False, False], [True, True, True, True],
             [True, False, True, False], [False, True, True, True]]
    draws = [{"primitive": "triangle_strip", "positions": quad_strip(-1, -1, 1, 1, 0.5),
              "colors": [[0.5, 0.5, 0.5, 0.5]] * 4}]
    for k, m in enumerate(masks):
        x0 = -0.95 + 0.24 * k
        for layer in range(2):
            state = {"color_mask": m, "depth_test": "always"}
            if layer:
                state["blend"] = {"src": "one", "dst": "one"}
            draws.append({"primitive": "triangle_strip",
                          "positions": quad_strip(r(x0), r(-0.8 + 0.7 * layer), r(x0 + 0.2), r(0.0 + 0.7 * layer), 0),
                          "colors": [rcol(rng, 0.6) for _ in range(4)], "state": state})
    return {"framebuffer": {"width": 192, "height": 96, "clear_color": [0, 0, 0, 0]},
            "draws": draws}


@scene("constant_depth_lequal", "depth", "9, 11",
       "a quad of constant depth (z = 0.1 everywhere, z_w = 0.55) drawn with lequal and no depth "
       "writes over an opaque bar of the same depth: every fragment must encode to exactly the "
       "bar's value and pass. The spec's z0 + (f1*(z1 - z0) + f2*(z2 - z0)) / A is exact for "
       "equal z; the former (f0*z0 + f1*z1 + f2*z2) / A was not once float(E_i) rounds (here E "
       "reaches 1.6e8 > 2^24) and failed in 6 pixels, where llvmpipe's plane equation passes")
def constant_depth_lequal():
    return {
        "framebuffer": {"width": 200, "height": 120, "clear_color": [0, 0, 0, 1]},
        "draws": [
            {"primitive": "triangle_strip", "positions": quad_strip(-1, -0.1, 1, 0.05, 0.1),
             "colors": [[1, 1, 1, 1]] * 4},
            {"primitive": "triangle_strip", "positions": quad_strip(-0.75, -0.46, -0.3, 0.44, 0.1),
             "colors": [[1, 0, 0, 1]] * 4, "state": {"depth_test": "lequal", "depth_write": False}},
        ],
    }


# ------------------------------------------------------ lines and points
# Window coordinates are given in pixels and written as exact clip
# coordinates (power-of-two framebuffers, multiples of 1/256 pixel), never
# rounded by r(), so the spec and llvmpipe start from the same end points.

def win(px, py, size, z=0.0):
    """Clip coordinates (w = 1) of window point (px, py) in a size x size target."""
    return [clip_x(px, size), clip_x(py, size), z]


def sub(v):
    """v rounded to the 1/256-pixel grid."""
    return round(v * 256) / 256


@scene("lines_octants", "lines", "3, 8b",
       "a star of 48 width-1 lines from random subpixel end points near the centre out to a "
       "circle, every octant and both directions of travel, plus the four axis directions and "
       "the four exact diagonals; flat colours")
def lines_octants():
    rng = random.Random(1201)
    size = 128
    pos, col = [], []
    for k in range(48):
        a = 2 * math.pi * (k + rng.uniform(0.1, 0.9)) / 48
        x0, y0 = sub(64 + rng.uniform(-3, 3)), sub(64 + rng.uniform(-3, 3))
        x1, y1 = sub(64 + 58 * math.cos(a)), sub(64 + 58 * math.sin(a))
        if k % 2:  # travel inwards as often as outwards
            x0, y0, x1, y1 = x1, y1, x0, y0
        pos += [win(x0, y0, size), win(x1, y1, size)]
        col += [rcol(rng), rcol(rng)]
    for (dx, dy) in ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (-1, -1), (1, -1)):
        x0, y0 = sub(20.3 + 4 * (dx + 2)), sub(20.7 + 4 * (dy + 2))
        pos += [win(x0, y0, size), win(x0 + 12 * dx, y0 + 12 * dy, size)]
        col += [rcol(rng), rcol(rng)]
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "lines", "positions": pos, "colors": col,
                       "state": {"depth_test": "off", "shading": "flat"}}]}


@scene("lines_pixel_centres", "lines", "8b",
       "width-1 lines whose end points lie on pixel centres, in every octant (slopes 0, 1/3, 1/2, "
       "1, 2, 3, infinite, both directions): llvmpipe 22.3 drops the first pixel of y-major lines "
       "going downward from a centre (docs/validation.md)")
def lines_pixel_centres():
    size = 128
    pos, col = [], []
    dirs = [(12, 0), (12, 4), (12, 6), (12, 12), (6, 12), (4, 12), (0, 12)]
    k = 0
    for sx in (1, -1):
        for sy in (1, -1):
            for (dx, dy) in dirs:
                cx = 16 + 30 * (k % 4) + 0.5
                cy = 10 + 15 * (k // 4) + 0.5
                x0, y0 = cx - sx * dx / 2, cy - sy * dy / 2
                x0, y0 = math.floor(x0) + 0.5, math.floor(y0) + 0.5
                pos += [win(x0, y0, size), win(x0 + sx * dx, y0 + sy * dy, size)]
                col += [id_col(k), id_col(k)]
                k += 1
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "lines", "positions": pos, "colors": col,
                       "state": {"depth_test": "off", "shading": "flat"}}]}


def id_col(k):
    return [((k * 53) % 200 + 55) / 255, ((k * 97) % 200 + 55) / 255, ((k * 31) % 200 + 55) / 255, 1]


@scene("lines_diamond_edges", "lines", "8b",
       "width-1 lines exactly on diamond boundaries: horizontal and vertical lines halfway "
       "between pixel centres, 45-degree lines through diamond corners, end points on diamond "
       "corners and edges (the tie rules of section 8b)")
def lines_diamond_edges():
    size = 128
    pos, col = [], []
    segs = []
    for i in range(4):
        y = 8 + 6 * i  # integer y: halfway between two rows of centres
        segs.append(((4.5 + i * 0.25, y), (40.5 + i * 0.5, y)))
        segs.append(((40.5 + i * 0.5, y + 3), (4.5 + i * 0.25, y + 3)))
        x = 50 + 6 * i  # integer x: halfway between two columns
        segs.append(((x, 4.5 + i * 0.25), (x, 40.5 + i * 0.5)))
        segs.append(((x + 3, 40.5 + i * 0.5), (x + 3, 4.5 + i * 0.25)))
    for i in range(6):
        # 45-degree lines through the corners (x + 0.5, y) of diamonds.
        x0, y0 = 6 + 8 * i + 0.0, 50.5
        d = 1 if i % 2 else -1
        segs.append(((x0, y0), (x0 + 14, y0 + 14 * d + (14 if d < 0 else 0))))
        segs.append(((x0 + 0.5, 80), (x0 + 0.5 + 12, 92)))
        segs.append(((x0 + 12.5, 100), (x0 + 0.5, 112)))
    # End points on diamond corners and edge midpoints.
    for i, (ox, oy) in enumerate(((0.5, 0), (0, 0.5), (0.25, 0.25), (-0.25, 0.25), (0.5, 0.5))):
        x0, y0 = 70 + 0.5 + ox, 60 + 8 * i + 0.5 + oy
        segs.append(((x0, y0), (x0 + 20, y0 + 3)))
        segs.append(((x0 + 30, y0 + 5), (x0 + 25, y0 - 2)))
    for k, ((x0, y0), (x1, y1)) in enumerate(segs):
        pos += [win(x0, y0, size), win(x1, y1, size)]
        col += [id_col(k), id_col(k)]
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "lines", "positions": pos, "colors": col,
                       "state": {"depth_test": "off", "shading": "flat"}}]}


@scene("line_strips_loops", "lines", "3, 8b, 9",
       "line strips and loops, indexed and not, Gouraud and flat, with a degenerate "
       "(zero-length) segment and a two-vertex loop; shared vertices drawn once")
def line_strips_loops():
    rng = random.Random(1203)
    size = 128
    draws = []
    for k, prim in enumerate(("line_strip", "line_loop", "line_strip", "line_loop")):
        n = 7 + 2 * k
        cx, cy = 32 + 64 * (k % 2), 32 + 64 * (k // 2)
        pts = []
        for i in range(n):
            a = 2 * math.pi * i / n + rng.uniform(-0.2, 0.2)
            rad = rng.uniform(10, 28)
            pts.append(win(sub(cx + rad * math.cos(a)), sub(cy + rad * math.sin(a)), size))
        if k == 2:
            pts.insert(3, list(pts[3]))  # a zero-length segment
        d = {"primitive": prim, "positions": pts, "colors": [rcol(rng) for _ in pts],
             "state": {"depth_test": "off", "shading": "flat" if k % 2 else "gouraud"}}
        if k >= 2:
            order = list(range(len(pts)))
            rng.shuffle(order)
            d["positions"] = [pts[i] for i in order]
            d["colors"] = [d["colors"][i] for i in order]
            inv = {o: j for j, o in enumerate(order)}
            d["indices"] = [inv[i] for i in range(len(pts))]
        draws.append(d)
    draws.append({"primitive": "line_loop", "positions": [win(60.3, 60.6, size), win(68.2, 66.9, size)],
                  "colors": [[1, 1, 1, 1], [1, 0.5, 0, 1]], "state": {"depth_test": "off", "shading": "flat"}})
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("lines_wide", "lines", "8b",
       "wide lines, widths 1 to 10 and fractional widths (1.4, 1.5, 2.5, 3.7, 6.5), x-major, "
       "y-major and 45 degrees, subpixel end points; widths round half away from zero")
def lines_wide():
    rng = random.Random(1205)
    size = 256
    draws = []
    widths = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 1.4, 1.5, 2.5, 3.7, 6.5]
    for k, w in enumerate(widths):
        pos = []
        x0, y0 = sub(8 + 16 * k + rng.uniform(0, 1)), sub(12 + rng.uniform(0, 1))
        pos += [win(x0, y0, size), win(sub(x0 + rng.uniform(-5, 5)), sub(y0 + 70), size)]  # y-major
        x0, y0 = sub(12 + rng.uniform(0, 1)), sub(100 + 10 * k + rng.uniform(0, 1))
        if k < 8:
            pos += [win(x0, y0, size), win(sub(x0 + 100), sub(y0 + rng.uniform(-4, 4)), size)]  # x-major
        else:
            pos += [win(sub(x0 + 130), y0, size), win(sub(x0 + 230), sub(y0 + rng.uniform(-4, 4)), size)]
        x0, y0 = 130.5 + 14 * (k % 8), 200.25 + 25 * (k // 8)
        pos += [win(x0, y0, size), win(x0 + 10, y0 + 10 * (1 if k % 2 else -1), size)]   # 45 degrees
        draws.append({"primitive": "lines", "positions": pos, "colors": [id_col(k)] * len(pos),
                      "state": {"depth_test": "off", "shading": "flat", "line_width": w}})
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("points_sizes", "points", "8c",
       "points of sizes 1 to 64 and fractional sizes (0.25, 0.5, 1.5, 2.25, 3.7, 4.5, 10.3, "
       "33.3) at random subpixel positions, on pixel centres and on pixel corners")
def points_sizes():
    rng = random.Random(1207)
    size = 256
    sizes = [1, 2, 3, 4, 5, 8, 13, 16, 24, 32, 64, 0.25, 0.5, 1.5, 2.25, 3.7, 4.5, 10.3, 33.3]
    draws = []
    for k, s in enumerate(sizes):
        pos = []
        for j, (fx, fy) in enumerate(((None, None), (0.5, 0.5), (0.0, 0.0))):
            cx = 12 + (k % 6) * 40 + j * 11 if s < 30 else 40 + 90 * (k % 3)
            cy = 16 + (k // 6) * 44 if s < 30 else 200
            if s >= 30:
                cx, cy = cx + j * 0.3, cy
                if j:
                    continue
            if fx is None:
                x, y = sub(cx + rng.random()), sub(cy + rng.random())
            else:
                x, y = math.floor(cx) + fx, math.floor(cy) + fy
            pos.append(win(x, y, size))
        draws.append({"primitive": "points", "positions": pos, "colors": [id_col(k)] * len(pos),
                      "state": {"depth_test": "off", "point_size": s}})
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("points_ties", "points", "4c, 8c",
       "points whose (x_w - 0.5) * 256 falls exactly halfway between subpixels (the snap rounds "
       "half away from zero, unlike vertex snapping), sizes 1, 2, 3, 1.5, 2.5 with odd and even "
       "subpixel widths, and many 1-pixel points at random float positions; Gouraud state, "
       "depth test on")
def points_ties():
    rng = random.Random(1208)
    size = 128
    draws = []
    for k, s in enumerate((1, 2, 3, 1.5, 2.5, 1 + 1 / 256, 2 - 1 / 512)):
        pos = []
        for j in range(12):
            # x_w a multiple of 1/512 pixel: an odd multiple is a tie of the
            # point snap; every third point is moved off the tie.
            fx = rng.randrange(512) / 512 + (1 / 1024 if j % 3 == 0 else 0)
            fy = rng.randrange(512) / 512
            pos.append(win(6 + 10 * j + fx, 6 + 9 * k + fy, size, r(rng.uniform(-0.5, 0.5))))
        draws.append({"primitive": "points", "positions": pos, "colors": [rcol(rng) for _ in pos],
                      "state": {"depth_test": "less", "point_size": s}})
    pos = [[r(rng.uniform(-0.95, 0.95)), r(rng.uniform(0.1, 0.95)), r(rng.uniform(-1, 1))] for _ in range(300)]
    draws.append({"primitive": "points", "positions": pos, "colors": [rcol(rng) for _ in pos],
                  "state": {"depth_test": "less"}})
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("lines_clipped", "clipping", "4b, 8b",
       "lines cut by the near plane, many with an end behind the eye (w < 0), crossing the "
       "framebuffer's edges (inside the guard band: not clipped), entirely off-screen, and "
       "entirely behind (clipped away); perspective camera, depth test on")
def lines_clipped():
    rng = random.Random(1209)
    pos, col = [], []
    for _ in range(14):  # across the near plane (z = -0.5 in eye space)
        pos += [[r(rng.uniform(-1.5, 1.5)), r(rng.uniform(-1, 1)), r(rng.uniform(-0.45, 0.4))],
                [r(rng.uniform(-3, 3)), r(rng.uniform(-2, 2)), r(rng.uniform(-8, -2))]]
        col += [rcol(rng), rcol(rng)]
    for _ in range(10):  # crossing the left/right/top/bottom edges
        pos += [[r(rng.uniform(-2, 2)), r(rng.uniform(-2, 2)), -3],
                [r(rng.uniform(-6, 6)), r(rng.uniform(-5, 5)), r(rng.uniform(-6, -3))]]
        col += [rcol(rng), rcol(rng)]
    pos += [[8, 0, -3], [9, 2, -4], [0.2, 0.3, 2], [0.5, -0.3, 3]]  # off-screen; behind the eye
    col += [[1, 1, 1, 1]] * 4
    return {"framebuffer": {"width": 160, "height": 128, "depth_format": "float32",
                            "clear_color": [0.05, 0.05, 0.1, 1]},
            "camera": {"type": "perspective", "fovy": 70, "near": 0.5, "far": 40},
            "draws": [{"primitive": "lines", "positions": pos, "colors": col,
                       "state": {"depth_test": "less", "shading": "flat"}}]}


@scene("points_clipped", "clipping", "4c, 8c",
       "points near and beyond the framebuffer's edges (large points partly outside with the "
       "centre inside: drawn; centre outside: discarded whole; centre exactly on the edge: "
       "drawn), behind the near plane, beyond far, and with w < 0; raw clip coordinates")
def points_clipped():
    size = 64
    pos = []
    for k, c in enumerate((0.05, 0.5, 0.95, 1.0, 1.02, 1.3)):
        pos += [[clip_x(c, size), clip_x(10 + 8 * k, size), 0.1],
                [clip_x(size - c, size), clip_x(12 + 8 * k, size), 0.1],
                [clip_x(10 + 8 * k, size), clip_x(c, size), 0.1],
                [clip_x(12 + 8 * k, size), clip_x(size - c, size), 0.1]]
    pos += [[clip_x(0, size), clip_x(30, size), 0.2], [clip_x(size, size), clip_x(34, size), 0.2],
            [clip_x(30, size), clip_x(0, size), 0.2], [clip_x(34, size), clip_x(size, size), 0.2],
            [clip_x(-0.01, size), clip_x(40, size), 0.2], [clip_x(size + 0.01, size), clip_x(44, size), 0.2]]
    near = [[0, 0, -1.01, 1], [0.2, 0.1, -0.999, 1], [-0.2, 0.1, 1.001, 1], [0.2, -0.2, 0.999, 1],
            [0.3, 0.3, 0, -1], [-0.3, -0.3, 0, 0], [0.4, -0.4, 0, 1e-12], [-0.1, 0.4, 0.5, 2]]
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "points", "positions": pos,
                       "colors": [id_col(k) for k in range(len(pos))],
                       "state": {"depth_test": "off", "point_size": 6}},
                      {"primitive": "points", "positions": near,
                       "colors": [id_col(40 + k) for k in range(len(near))],
                       "state": {"depth_test": "off", "point_size": 5}}]}


@scene("wireframe_mesh", "polygon mode", "4d, 8b",
       "duck.dae in polygon_mode line with its back faces culled (cull front, front_face cw, as "
       "mesh_duck_cull_front): the edges of front faces only, an edge shared by two of them "
       "drawn twice; perspective camera, depth test on")
def wireframe_mesh():
    return {
        "framebuffer": {"width": 256, "height": 256, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 50, "near": 0.5, "far": 10,
                   "eye": [1.6, 1.6, 2.2], "target": [0.1, 0.8, 0]},
        # One colour, as a wireframe is drawn: without the duck's texture,
        # which along a line would show the documented line-attribute
        # difference (docs/validation.md) a texel at a time.
        "draws": [{"mesh": MODELS + "/Collada/duck.dae", "lighting": False, "textures": False,
                   "material": {"color": [0.9, 0.8, 0.2, 1]},
                   "state": {"cull": "front", "front_face": "cw", "polygon_mode": "line",
                             "depth_test": "less"}}],
    }


@scene("wireframe_wide_clipped", "polygon mode", "4, 4d, 8b",
       "raw triangles in polygon_mode line, widths 1 and 3: culled ones (cull back), ones cut "
       "by the near plane (the cut edge is not drawn: edge flags), strips with flat provoking "
       "colours")
def wireframe_wide_clipped():
    rng = random.Random(1211)
    size = 128
    tris, col = [], []
    for _ in range(10):
        cx, cy = rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8)
        for k in range(3):
            tris.append([r(cx + rng.uniform(-0.4, 0.4)), r(cy + rng.uniform(-0.4, 0.4)),
                         r(rng.uniform(-0.6, 0.6))])
            col.append(rcol(rng))
    cut = [[-0.9, -0.9, -1.6], [0.9, -0.7, 0.2], [0.0, 0.9, 0.3],
           [0.2, -0.2, 0.5], [0.95, 0.1, -1.4], [0.5, 0.95, 0.1]]
    return {"framebuffer": {"width": size, "height": size, "clear_color": [0, 0, 0, 1]},
            "draws": [{"positions": tris, "colors": col,
                       "state": {"polygon_mode": "line", "cull": "back", "shading": "flat",
                                 "depth_test": "off"}},
                      {"positions": cut, "colors": [rcol(rng) for _ in cut],
                       "state": {"polygon_mode": "line", "shading": "flat", "depth_test": "off"}},
                      {"primitive": "triangle_strip",
                       "positions": quad_strip(-0.6, -0.95, 0.6, -0.75) + quad_strip(-0.6, 0.75, 0.6, 0.95),
                       "colors": [rcol(rng) for _ in range(8)],
                       "state": {"polygon_mode": "line", "line_width": 3, "shading": "flat",
                                 "depth_test": "off"}}]}


@scene("polygon_mode_point", "polygon mode", "4d, 8c",
       "WusonOBJ.obj in polygon_mode point, point size 2, back faces culled, orthographic camera, "
       "depth test on")
def polygon_mode_point():
    return {
        "framebuffer": {"width": 256, "height": 256, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "orthographic", "left": -1.6, "right": 1.6, "bottom": -0.6, "top": 2.6,
                   "near": -10, "far": 10, "eye": [1, 0.6, 1.5], "target": [0, 0, 0]},
        "draws": [{"mesh": MODELS + "/OBJ/WusonOBJ.obj", "lighting": False,
                   "material": {"color": [0.3, 0.9, 0.6, 1]},
                   "state": {"cull": "back", "polygon_mode": "point", "point_size": 2,
                             "depth_test": "less"}}],
    }


@scene("polygon_mode_point_clipped", "polygon mode", "4, 4d, 8c",
       "raw triangles in polygon_mode point, size 3, cut by the near and far planes and by w = 0 "
       "(a polygon's points: the original vertices inside and the vertices where an edge enters "
       "the volume, per the edge flags), flat colours, perspective camera")
def polygon_mode_point_clipped():
    rng = random.Random(1213)
    tris, col = [], []
    for _ in range(16):
        cx, cy = rng.uniform(-1.2, 1.2), rng.uniform(-0.9, 0.9)
        for k in range(3):
            tris.append([r(cx + rng.uniform(-1, 1)), r(cy + rng.uniform(-0.8, 0.8)),
                         r(rng.uniform(-9, 0.6))])
            col.append(rcol(rng))
    return {"framebuffer": {"width": 128, "height": 128, "clear_color": [0, 0, 0, 1]},
            "camera": {"type": "perspective", "fovy": 70, "near": 0.5, "far": 8},
            "draws": [{"positions": tris, "colors": col,
                       "state": {"polygon_mode": "point", "point_size": 3, "shading": "flat",
                                 "depth_test": "off"}}]}


LINE_MESH = "lines_mesh.obj"


def line_mesh_obj():
    """A wire helix and a box's 12 edges as OBJ `l` elements (polylines)."""
    lines = ["# written by scripts/gen/make_regress_scenes.py: OBJ line elements (`l`)"]
    n = 60
    for i in range(n):
        a = 2 * math.pi * i / 20
        lines.append(f"v {0.8 * math.cos(a):.6f} {-1 + 2 * i / (n - 1):.6f} {0.8 * math.sin(a):.6f}")
    lines.append("l " + " ".join(str(i + 1) for i in range(n)))
    for (x, y, z) in [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]:
        lines.append(f"v {x} {y} {z}")
    b = n + 1
    for (i, j) in ((0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)):
        lines.append(f"l {b + i} {b + j}")
    return "\n".join(lines) + "\n"


@scene("mesh_lines_obj", "lines", "3, 4b, 8b",
       "a mesh file with line primitives: " + LINE_MESH + " (written by the generator), a helix "
       "polyline and a box's 12 edges as OBJ `l` elements, perspective camera")
def mesh_lines_obj():
    return {
        "framebuffer": {"width": 128, "height": 128, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 50, "near": 0.5, "far": 20,
                   "eye": [2.2, 1.6, 3.4], "target": [0, 0, 0]},
        "draws": [{"mesh": LINE_MESH, "lighting": False, "material": {"color": [0.6, 0.8, 1, 1]},
                   "state": {"depth_test": "less"}}],
    }


# ------------------------------------------- known disagreements (reported)
# Minimal reproductions of the differences found between the golden model and
# llvmpipe; scripts/regress expects them (KNOWN_DISAGREEMENTS) and reports
# them as such instead of failing, and warns when they change.

@scene("known_offset_units", "known disagreement", "10",
       "one quad at constant window depth 0.75 with polygon_offset [0, 4] in unorm16: the spec "
       "adds 4 * r with r = 1 / 65535, llvmpipe 4 * 2 / 65535 (its r for unorm buffers is twice "
       "one step), so its stored depth is 4 steps farther")
def known_offset_units():
    return {
        "framebuffer": {"width": 32, "height": 32, "depth_format": "unorm16"},
        "draws": [{"primitive": "triangle_strip", "positions": quad_strip(-0.5, -0.5, 0.5, 0.5, 0.5),
                   "colors": [[0.5, 0.5, 0.5, 1]] * 4,
                   "state": {"depth_test": "always", "polygon_offset": [0, 4]}}],
    }


@scene("known_half_rounding", "known disagreement", "12",
       "rgba16f: flat colours 0.1, 0.3, 0.7, 0.9 written and blended (one, one): the spec "
       "rounds float to half to nearest even (0.3 -> 0.30005), llvmpipe toward zero (0.2998)")
def known_half_rounding():
    draws = []
    for i, v in enumerate((0.1, 0.3, 0.7, 0.9)):
        x0 = -1 + 0.5 * i
        draws.append({"primitive": "triangle_strip", "positions": quad_strip(x0, -1, x0 + 0.5, 0, 0),
                      "colors": [[v, v, v, v]] * 4, "state": {"depth_test": "off"}})
        draws.append({"primitive": "triangle_strip", "positions": quad_strip(x0, 0, x0 + 0.5, 1, 0),
                      "colors": [[v, v, v, v]] * 4,
                      "state": {"depth_test": "off", "blend": {"src": "one", "dst": "one"}}})
    return {"framebuffer": {"width": 32, "height": 16, "color_format": "rgba16f",
                            "clear_color": [0.1, 0.3, 0.7, 0.9]},
            "draws": draws}


# ------------------------------------------------------------- multisampling
#
# 4 samples per pixel (section 14), the count llvmpipe supports besides 1.
# scripts/regress compares, per pixel, the number of covered samples
# (round(4 * alpha) of the coverage variant, the union over every primitive)
# exactly, and the resolved colour within 1/255.

MSAA = 4


@scene("msaa_sunburst", "multisampling", "8, 14",
       "4 samples: a fan of 90 thin triangles around a centre off the pixel grid (edges at every "
       "angle) and piglit's accuracy pattern (8x8 triangles, each rotated by 2pi/64 more), "
       "flat white and grey on black")
def msaa_sunburst():
    w = h = 128
    pos, col = [], []
    cx, cy, n = 40.3, 44.7, 90
    for i in range(n):
        a0, a1 = 2 * math.pi * i / n, 2 * math.pi * (i + 0.55) / n
        for (x, y) in ((cx, cy), (cx + 38 * math.cos(a0), cy + 38 * math.sin(a0)),
                       (cx + 38 * math.cos(a1), cy + 38 * math.sin(a1))):
            pos.append([r(clip_x(x, w)), r(clip_x(y, h)), 0, 1])
            col.append([1, 1, 1, 1] if i % 2 else [0.5, 0.5, 0.5, 1])
    # piglit ext_framebuffer_multisample/accuracy's Triangles pattern in the
    # right half and the top: NDC (pattern) -> this framebuffer's region.
    tri = [(-0.5, -1.0), (0.0, 1.0), (0.5, -1.0)]
    across = 8
    for t in range(across * across):
        rot = 2 * math.pi / (across * across) * t
        i, j = t % across, across - 1 - t // across
        for (px, py) in tri:
            x, y = 0.1 * px, 0.1 * py
            x, y = math.cos(rot) * x - math.sin(rot) * y, math.sin(rot) * x + math.cos(rot) * y
            x, y = 0.95 * (x + (2 * i + 1) / across - 1), 0.95 * (y + (2 * j + 1) / across - 1)
            wx, wy = 84 + (x + 1) * 22, 20 + (y + 1) * 54   # 44 x 108 pixels at the right
            pos.append([r(clip_x(wx, w)), r(clip_x(wy, h)), 0, 1])
            col.append([1, 1, 1, 1])
    return {"framebuffer": {"width": w, "height": h, "samples": MSAA, "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "triangles", "positions": pos, "colors": col,
                       "state": {"depth_test": "off", "shading": "flat"}}]}


@scene("msaa_slivers", "multisampling", "8, 9, 14",
       "4 samples: 300 slivers and needles (under a pixel wide, some under 1/100) in every "
       "direction, Gouraud colours, depth lequal per sample, unorm24")
def msaa_slivers():
    return slivers(random.Random(1401), 112, 300, 80, (0.05, 1.2), (0.002, 0.05),
                   {"samples": MSAA, "clear_color": [0, 0, 0, 1]})


@scene("msaa_grid_shared_edges", "multisampling", "7, 8, 14",
       "4 samples: a 12x8 grid of jittered quads (indexed triangles sharing every edge) and "
       "axis-aligned quads with edges exactly on sample rows and columns, additively blended "
       "(one, one) at 0.25: every sample covered exactly once, 4 per pixel inside the grid")
def msaa_grid_shared_edges():
    w, h = 128, 96
    pos, idx = jittered_grid(random.Random(1402), w, h, 12, 8, 3)
    # Side by side quads whose shared edges run exactly through sample
    # positions (x = k + 6/16 etc.: the edge owns its samples by the fill rule).
    axis = []
    p = lambda x, y: [clip_x(x, w), clip_x(y, h), 0.2, 1]  # exact: multiples of 1/256 pixel
    for k in range(6):
        x0, x1 = 8 + 18 * k + [0.375, 0.875, 0.125, 0.625, 0.5, 0.0][k], 8 + 18 * (k + 1) + 0.375
        y0, y1 = 30 + [0.125, 0.375, 0.625, 0.875, 0.5, 0.0][k], 66.625
        axis += [p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y0), p(x1, y1), p(x0, y1)]
    additive = {"depth_test": "off", "blend": {"src": "one", "dst": "one"}}
    return {
        "framebuffer": {"width": w, "height": h, "samples": MSAA, "clear_color": [0, 0, 0, 0]},
        "draws": [
            {"positions": pos, "indices": idx, "colors": [[0.25, 0.25, 0.25, 0.25]] * len(pos),
             "state": additive},
            {"positions": axis, "colors": [[0.0, 0.25, 0.5, 0.25]] * len(axis), "state": additive},
        ],
    }


@scene("msaa_interpenetrating", "multisampling", "9, 11, 14",
       "4 samples: five planes through one another at different angles, perspective, unorm24: "
       "along the intersection lines each sample keeps its own nearest surface")
def msaa_interpenetrating():
    rng = random.Random(1403)
    draws = []
    for k in range(5):
        a = k * 36 + 7
        draws.append({"primitive": "triangle_strip", "positions": quad_strip(-1.2, -0.6, 1.2, 0.6),
                      "colors": [rcol(rng) for _ in range(4)],
                      "transform": {"rotate": [[a, 0, 1, 0], [15 * k - 30, 1, 0, 0]],
                                    "translate": [0, 0, -3]},
                      "state": {"depth_test": "less"}})
    return {"framebuffer": {"width": 128, "height": 96, "samples": MSAA,
                            "clear_color": [0.1, 0.1, 0.1, 1]},
            "camera": {"type": "perspective", "fovy": 50, "near": 1, "far": 8},
            "draws": draws}


@scene("msaa_blend", "multisampling", "12, 14",
       "4 samples: rotated translucent quads (src_alpha, one_minus_src_alpha) and additive ones "
       "over a tilted Gouraud background quad and the clear colour: each sample blends with its "
       "own stored colour")
def msaa_blend():
    rng = random.Random(1404)
    w, h = 128, 96
    draws = [{"primitive": "triangle_strip",
              "positions": [[-0.85, -0.95, 0.9], [0.95, -0.7, 0.9], [-0.95, 0.8, 0.9], [0.7, 0.9, 0.9]],
              "colors": [[0.1, 0.2, 0.9, 1], [0.9, 0.2, 0.1, 1], [0.1, 0.9, 0.2, 1],
                         [0.8, 0.8, 0.8, 1]], "state": {"depth_test": "off"}}]
    for k in range(10):
        cx, cy = rng.uniform(-0.7, 0.7), rng.uniform(-0.7, 0.7)
        s, a = rng.uniform(0.15, 0.45), rng.uniform(0, math.pi)
        corners = [(cx + s * math.cos(a + q * math.pi / 2), cy + s * math.sin(a + q * math.pi / 2))
                   for q in (0, 1, 3, 2)]
        blend = ({"src": "src_alpha", "dst": "one_minus_src_alpha"} if k % 3
                 else {"src": "one", "dst": "one"})
        draws.append({"primitive": "triangle_strip",
                      "positions": [[r(x), r(y), 0] for (x, y) in corners],
                      "colors": [rcol(rng, r(rng.uniform(0.2, 0.8))) for _ in range(4)],
                      "state": {"depth_test": "off", "blend": blend,
                                "shading": "flat" if k % 2 else "gouraud"}})
    return {"framebuffer": {"width": w, "height": h, "samples": MSAA, "clear_color": [0, 0, 0, 0]},
            "draws": draws}


@scene("msaa_lines", "multisampling", "8b, 14",
       "4 samples: lines as rectangles (no diamond exit, width not rounded), widths 0.5 to 7.3 "
       "at every angle from subpixel end points, and a strip of width-1 lines; flat colours")
def msaa_lines():
    rng = random.Random(1405)
    size = 128
    draws = []
    widths = [1, 0.5, 1.5, 2, 2.5, 3.7, 5, 7.3]
    for k, wd in enumerate(widths):
        pos = []
        for q in range(4):
            a = 2 * math.pi * (k * 4 + q + rng.uniform(0.1, 0.9)) / 32
            cx, cy = 34 + 60 * (k % 2), 14 + 15 * (k // 2) * 2
            length = rng.uniform(10, 26)
            x0, y0 = sub(cx + rng.uniform(-3, 3)), sub(cy + rng.uniform(-3, 3))
            pos += [win(x0, y0, size),
                    win(sub(x0 + length * math.cos(a)), sub(y0 + length * math.sin(a) * 0.5), size)]
        draws.append({"primitive": "lines", "positions": pos, "colors": [id_col(k)] * len(pos),
                      "state": {"depth_test": "off", "shading": "flat", "line_width": wd}})
    strip = [win(sub(4 + 120 * i / 11), sub(118 + 6 * math.sin(i * 1.3)), size) for i in range(12)]
    draws.append({"primitive": "line_strip", "positions": strip, "colors": [id_col(9)] * len(strip),
                  "state": {"depth_test": "off", "shading": "flat"}})
    return {"framebuffer": {"width": size, "height": size, "samples": MSAA,
                            "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("msaa_lines_tile_edges", "multisampling", "8b, 14",
       "4 samples: rectangle lines along and across llvmpipe's 64-pixel tile boundaries (x, y = "
       "64 + 0.1, reaching into pixel 63's samples; controls at 70 + 0.1), widths 1 and 2.3: "
       "llvmpipe 22.3 loses the samples in the last row or column of a tile (docs/validation.md)")
def msaa_lines_tile_edges():
    size = 128
    pos = []
    for x in (64.1, 70.1, 64.6):
        pos += [win(sub(x), 6, size), win(sub(x), 40, size)]                  # vertical
    for y in (64.1, 70.1, 64.6):
        pos += [win(76, sub(y), size), win(120, sub(y), size)]                # horizontal
    pos += [win(44.25, 80.5, size), win(84.75, 100.25, size)]                 # across x = 64
    pos += [win(10.5, 44.75, size), win(30.25, 84.5, size)]                   # across y = 64
    wide = [win(sub(64.3), 90, size), win(sub(64.3), 124, size),
            win(90, sub(64.4), size), win(124, sub(64.4), size)]
    return {"framebuffer": {"width": size, "height": size, "samples": MSAA,
                            "clear_color": [0, 0, 0, 1]},
            "draws": [{"primitive": "lines", "positions": pos, "colors": [id_col(3)] * len(pos),
                       "state": {"depth_test": "off", "shading": "flat"}},
                      {"primitive": "lines", "positions": wide, "colors": [id_col(5)] * len(wide),
                       "state": {"depth_test": "off", "shading": "flat", "line_width": 2.3}}]}


@scene("msaa_points", "multisampling", "8c, 14",
       "4 samples: point squares of sizes 0.25 to 12.5 at random subpixel positions, on pixel "
       "centres and on pixel corners, tested at the sample positions")
def msaa_points():
    rng = random.Random(1406)
    size = 128
    sizes = [1, 2, 3, 4, 5, 8, 12.5, 0.25, 0.5, 1.5, 2.25, 3.7]
    draws = []
    for k, s in enumerate(sizes):
        pos = []
        for j, (fx, fy) in enumerate(((None, None), (0.5, 0.5), (0.0, 0.0), (None, None))):
            cx, cy = 10 + (k % 4) * 30 + j * 6.5, 14 + (k // 4) * 40 + (j % 2) * 14
            if fx is None:
                x, y = sub(cx + rng.random()), sub(cy + rng.random())
            else:
                x, y = math.floor(cx) + fx, math.floor(cy) + fy
            pos.append(win(x, y, size))
        draws.append({"primitive": "points", "positions": pos, "colors": [id_col(k)] * len(pos),
                      "state": {"depth_test": "off", "point_size": s}})
    return {"framebuffer": {"width": size, "height": size, "samples": MSAA,
                            "clear_color": [0, 0, 0, 1]},
            "draws": draws}


@scene("msaa_mesh_duck", "multisampling", "2, 7, 9, 11, 14",
       "4 samples: duck.dae (Collada) lit by a point light, back faces culled, perspective, "
       "unorm24: silhouettes and self-occlusion per sample")
def msaa_mesh_duck():
    return {
        "framebuffer": {"width": 128, "height": 128, "samples": MSAA,
                        "clear_color": [0.05, 0.1, 0.05, 1]},
        "camera": {"type": "perspective", "fovy": 50, "near": 0.5, "far": 10,
                   "eye": [1.6, 1.6, 2.2], "target": [0.1, 0.8, 0]},
        "lights": [{"type": "point", "position": [1, 3, 2], "attenuation": [1, 0.1, 0.0]}],
        "draws": [{"mesh": MODELS + "/Collada/duck.dae",
                   "material": {"color": [0.9, 0.8, 0.2, 1], "specular": [0.4, 0.4, 0.4, 1],
                                "shininess": 10},
                   "state": {"cull": "front", "front_face": "cw"}}],
    }


@scene("viewport_subrect", "viewport", "4, 5, 8d",
       "a viewport sub-rectangle with odd sides (51x45 at 13, 9) and depth range [0.25, 0.75]: triangles crossing every viewport edge (inside the viewport's guard band: not clipped, the draw rectangle bounds them), one far beyond the guard band (clipped), one through the near plane (clipped: llvmpipe's own depth range transform), a depth-tested strip")
def viewport_subrect():
    return {"framebuffer": {"width": 96,
                 "height": 80,
                 "clear_color": [0.05, 0.05, 0.1, 1],
                 "viewport": [13, 9, 51, 45],
                 "depth_range": [0.25, 0.75]},
 "draws": [{"name": "crossing every viewport edge",
            "positions": [[-1.7, -1.3, 0.2], [1.45, -0.4, -0.3], [-0.2, 1.6, 0.6]],
            "colors": [[1, 0.2, 0.2, 1], [0.2, 1, 0.2, 1], [0.2, 0.3, 1, 1]]},
           {"name": "strip over the right and top edges, depth lequal",
            "primitive": "triangle_strip",
            "positions": [[0.1, 0.2, -0.5], [1.9, 0.1, 0.1], [0.3, 1.4, 0.4], [1.6, 1.2, -0.2]],
            "colors": [[1, 1, 0.2, 1], [0.2, 1, 1, 1], [1, 0.2, 1, 1], [0.9, 0.9, 0.9, 1]],
            "state": {"depth_test": "lequal"}},
           {"name": "far beyond the guard band: clipped",
            "positions": [[-0.9, -0.95, 0.0, 1], [3000, -0.5, 0.0, 1], [-0.8, 0.3, 0.0, 1]],
            "colors": [[0.8, 0.5, 0.1, 1], [0.8, 0.5, 0.1, 1], [0.1, 0.5, 0.8, 1]]},
           {"name": "through the near plane",
            "positions": [[-0.6, -0.8, -2.0, 1.5], [0.9, -0.7, 0.5, 1], [0.2, 0.9, 0.9, 1]],
            "colors": [[0.3, 0.9, 0.5, 1], [0.9, 0.3, 0.5, 1], [0.5, 0.3, 0.9, 1]]}]}


@scene("viewport_two_draws", "viewport", "5, 8d, 11",
       "two draws with their own viewports and depth ranges in one frame ([0, 0.5] left, the reversed [1, 0.5] on the right, where the order of the pair flips), then a full-frame plane at window depth 0.5 tested against both, blended")
def viewport_two_draws():
    return {"framebuffer": {"width": 90,
                 "height": 70,
                 "clear_color": [0, 0, 0, 1],
                 "depth_format": "unorm24"},
 "draws": [{"name": "left: two triangles, depth [0, 0.5]",
            "positions": [[-0.9, -0.8, -0.6],
                          [0.8, -0.6, 0.6],
                          [-0.1, 0.9, 0.0],
                          [-0.8, 0.7, 0.6],
                          [0.9, 0.6, -0.6],
                          [0.0, -0.9, 0.1]],
            "colors": [[1, 0.3, 0.3, 1],
                       [1, 0.3, 0.3, 1],
                       [1, 0.6, 0.3, 1],
                       [0.3, 0.3, 1, 1],
                       [0.3, 0.6, 1, 1],
                       [0.3, 0.3, 1, 1]],
            "state": {"viewport": [2, 3, 43, 61], "depth_range": [0, 0.5]}},
           {"name": "right: the same, depth [1, 0.5]",
            "positions": [[-0.9, -0.8, -0.6],
                          [0.8, -0.6, 0.6],
                          [-0.1, 0.9, 0.0],
                          [-0.8, 0.7, 0.6],
                          [0.9, 0.6, -0.6],
                          [0.0, -0.9, 0.1]],
            "colors": [[1, 0.3, 0.3, 1],
                       [1, 0.3, 0.3, 1],
                       [1, 0.6, 0.3, 1],
                       [0.3, 0.3, 1, 1],
                       [0.3, 0.6, 1, 1],
                       [0.3, 0.3, 1, 1]],
            "state": {"viewport": [47, 5, 41, 57],
                      "depth_range": [1, 0.5],
                      "depth_test": "less"}},
           {"name": "plane at window depth 0.5 where it is nearer",
            "primitive": "triangle_strip",
            "positions": [[-1, -1, 0.0], [1, -1, 0.0], [-1, 1, 0.0], [1, 1, 0.0]],
            "colors": [[0.2, 0.8, 0.2, 1],
                       [0.2, 0.8, 0.2, 1],
                       [0.2, 0.8, 0.2, 1],
                       [0.2, 0.8, 0.2, 1]],
            "state": {"depth_test": "less",
                      "blend": {"src": "src_alpha", "dst": "one"},
                      "color_mask": [True, True, False, True]}}]}


@scene("scissor_prims", "scissor", "8d, 8b, 8c, 4d",
       "a scissor per draw with odd edges that cut tiles and stamps: a fan, wide lines, a line loop, points of size 6.5 across the scissor edges and a wireframe triangle")
def scissor_prims():
    return {"framebuffer": {"width": 80, "height": 64, "clear_color": [0.1, 0.1, 0.1, 1]},
 "draws": [{"name": "fan cut by the scissor",
            "primitive": "triangle_fan",
            "positions": [[0, 0, 0.5],
                          [-0.95, -0.9, 0.5],
                          [0.9, -0.95, 0.5],
                          [0.95, 0.9, 0.5],
                          [-0.9, 0.95, 0.5],
                          [-0.95, -0.9, 0.5]],
            "colors": [[1, 1, 1, 1],
                       [1, 0.2, 0.2, 1],
                       [0.2, 1, 0.2, 1],
                       [0.2, 0.2, 1, 1],
                       [1, 1, 0.2, 1],
                       [1, 0.2, 0.2, 1]],
            "state": {"scissor": [9, 7, 37, 29]}},
           {"name": "lines, width 3",
            "primitive": "lines",
            "positions": [[-0.9, -0.7, 0.2],
                          [0.85, 0.8, 0.2],
                          [-0.8, 0.6, 0.2],
                          [0.9, -0.5, 0.2],
                          [-0.95, 0.05, 0.2],
                          [0.95, 0.12, 0.2]],
            "colors": [[1, 0.5, 0, 1],
                       [1, 0.5, 0, 1],
                       [0, 0.8, 1, 1],
                       [0, 0.8, 1, 1],
                       [0.8, 0.8, 0.8, 1],
                       [0.8, 0.8, 0.8, 1]],
            "state": {"line_width": 3, "scissor": [30, 21, 41, 30], "depth_test": "off"}},
           {"name": "loop, width 1",
            "primitive": "line_loop",
            "positions": [[-0.7, -0.8, 0.1],
                          [0.75, -0.6, 0.1],
                          [0.6, 0.85, 0.1],
                          [-0.5, 0.7, 0.1]],
            "colors": [[1, 0, 1, 1], [1, 1, 0, 1], [0, 1, 1, 1], [1, 1, 1, 1]],
            "state": {"scissor": [5, 33, 70, 27]}},
           {"name": "points across the scissor edges",
            "primitive": "points",
            "positions": [[-0.55, -0.55, 0.1],
                          [-0.3, -0.5, 0.1],
                          [-0.05, -0.45, 0.1],
                          [0.2, -0.4, 0.1],
                          [0.45, -0.35, 0.1],
                          [0.7, -0.3, 0.1],
                          [-0.5, 0.3, 0.1],
                          [-0.2, 0.35, 0.1],
                          [0.1, 0.4, 0.1],
                          [0.4, 0.45, 0.1]],
            "colors": [[1, 0, 0, 1],
                       [0, 1, 0, 1],
                       [0, 0, 1, 1],
                       [1, 1, 0, 1],
                       [0, 1, 1, 1],
                       [1, 0, 1, 1],
                       [1, 0.5, 0, 1],
                       [0.5, 1, 0, 1],
                       [0, 0.5, 1, 1],
                       [1, 1, 1, 1]],
            "state": {"point_size": 6.5, "scissor": [17, 12, 40, 33], "depth_test": "off"}},
           {"name": "wireframe triangle",
            "positions": [[-0.9, 0.9, 0.0], [-0.2, -0.1, 0.0], [0.8, 0.95, 0.0]],
            "colors": [[0.6, 1, 0.6, 1], [0.6, 1, 0.6, 1], [0.6, 1, 0.6, 1]],
            "state": {"polygon_mode": "line",
                      "line_width": 2,
                      "scissor": [0, 40, 52, 24],
                      "depth_test": "off"}}]}


# ---------------------------------------------------------- Phong shading

PHONG_SPHERE = "phong_sphere.obj"
PHONG_LOWPOLY = "phong_lowpoly.obj"


def sphere_obj(n_lon, n_lat, comment):
    """A unit UV sphere as OBJ with smooth normals (the position itself):
    n_lat bands of n_lon quads, each two counter-clockwise triangles seen
    from outside; the poles are fans."""
    lines = ["# written by scripts/gen/make_regress_scenes.py: " + comment]
    verts = [(0.0, 1.0, 0.0)]
    for i in range(1, n_lat):
        theta = math.pi * i / n_lat
        for j in range(n_lon):
            phi = 2 * math.pi * j / n_lon
            verts.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                          -math.sin(theta) * math.sin(phi)))
    verts.append((0.0, -1.0, 0.0))
    for v in verts:
        lines.append("v %.6f %.6f %.6f" % v)
    for v in verts:
        lines.append("vn %.6f %.6f %.6f" % v)

    def ring(i, j):  # 1-based OBJ index of ring i (1..n_lat-1), longitude j
        return 2 + (i - 1) * n_lon + (j % n_lon)

    faces = []
    for j in range(n_lon):
        faces.append((1, ring(1, j), ring(1, j + 1)))
    for i in range(1, n_lat - 1):
        for j in range(n_lon):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    last = len(verts)
    for j in range(n_lon):
        faces.append((ring(n_lat - 1, j), last, ring(n_lat - 1, j + 1)))
    for f in faces:
        lines.append("f " + " ".join("%d//%d" % (k, k) for k in f))
    return "\n".join(lines) + "\n"


def phong_sphere_obj():
    return sphere_obj(48, 24, "a smooth UV sphere (48 x 24) for the Phong scenes")


def phong_lowpoly_obj():
    return sphere_obj(8, 4, "a low-polygon UV sphere (8 x 4) with smooth normals")


@scene("phong_sphere_point_light", "shading", "2, 9, 9b",
       "Phong: " + PHONG_SPHERE + " (written by the generator, smooth normals) lit by a white point "
       "light just 0.6 above its surface (strong attenuation) and a dim directional fill light; the "
       "direction to the light and the attenuation change fast across each triangle")
def phong_sphere_point_light():
    return {
        "framebuffer": {"width": 192, "height": 192, "clear_color": [0.05, 0.05, 0.08, 1]},
        "camera": {"type": "perspective", "fovy": 40, "near": 0.5, "far": 20,
                   "eye": [0, 0.6, 3.6], "target": [0, 0, 0]},
        "ambient": [0.1, 0.1, 0.1, 1],
        "lights": [
            {"type": "point", "position": [0.7, 0.9, 1.2], "diffuse": [1, 0.95, 0.9, 1],
             "specular": [1, 1, 1, 1], "attenuation": [0.2, 0.5, 1.0]},
            {"type": "directional", "direction": [1, -0.3, -0.5], "diffuse": [0.15, 0.2, 0.3, 1],
             "specular": [0, 0, 0, 1]},
        ],
        "draws": [{"mesh": PHONG_SPHERE,
                   "material": {"color": [0.7, 0.3, 0.25, 1], "specular": [0.9, 0.9, 0.9, 1],
                                "shininess": 60},
                   "state": {"cull": "back", "shading": "phong"}}],
    }


@scene("phong_lowpoly_highlight", "shading", "2, 9, 9b",
       "Phong against Gouraud: " + PHONG_LOWPOLY + " (an 8 x 4 sphere, smooth normals) twice, "
       "Gouraud on the left and Phong on the right, under a directional light whose sharp "
       "highlight (shininess 80) falls inside a triangle: Gouraud's vertices miss it, Phong "
       "draws it")
def phong_lowpoly_highlight():
    # Turned 22.5 degrees about y, the sphere has no vertex at the normal
    # (0, sin 22.5, cos 22.5), the middle of a quad of its upper band; the
    # light's half vector with the viewer's +z is that normal, so Phong puts
    # the highlight's peak there, while the nearest vertices see n.H <= 0.874
    # and pow(0.874, 80) < 3e-5: no highlight at all with Gouraud.
    light = {"type": "directional", "direction": [0, -1, -1], "diffuse": [0.8, 0.8, 0.8, 1],
             "specular": [1, 1, 1, 1]}
    material = {"color": [0.2, 0.4, 0.8, 1], "specular": [1, 1, 1, 1], "shininess": 80}
    return {
        "framebuffer": {"width": 256, "height": 128, "clear_color": [0, 0, 0, 1]},
        "camera": {"type": "perspective", "fovy": 32, "near": 1, "far": 20,
                   "eye": [0, 0, 6], "target": [0, 0, 0]},
        "lights": [light],
        "draws": [
            {"mesh": PHONG_LOWPOLY,
             "transform": {"translate": [-1.15, 0, 0], "rotate": [22.5, 0, 1, 0]},
             "material": material, "state": {"cull": "back", "shading": "gouraud"}},
            {"mesh": PHONG_LOWPOLY,
             "transform": {"translate": [1.15, 0, 0], "rotate": [22.5, 0, 1, 0]},
             "material": material, "state": {"cull": "back", "shading": "phong"}},
        ],
    }


@scene("phong_three_lights", "shading", "2, 9, 9b",
       "Phong under three lights: a red and a blue point light on either side (attenuated) and a "
       "white directional light from above, on " + PHONG_SPHERE + " and a flattened copy of it; "
       "overlapping coloured highlights, depth test between the two")
def phong_three_lights():
    return {
        "framebuffer": {"width": 192, "height": 160, "clear_color": [0.02, 0.02, 0.02, 1]},
        "camera": {"type": "perspective", "fovy": 45, "near": 1, "far": 20,
                   "eye": [0.5, 1.5, 4.5], "target": [0, 0, 0]},
        "ambient": [0.05, 0.05, 0.05, 1],
        "lights": [
            {"type": "point", "position": [-1.8, 0.5, 1.2], "diffuse": [0.9, 0.2, 0.1, 1],
             "specular": [1, 0.4, 0.3, 1], "attenuation": [0.5, 0.3, 0.1]},
            {"type": "point", "position": [1.8, 0.3, 1.0], "diffuse": [0.1, 0.3, 0.9, 1],
             "specular": [0.3, 0.5, 1, 1], "attenuation": [0.5, 0.3, 0.1]},
            {"type": "directional", "direction": [0, -1, -0.4], "diffuse": [0.4, 0.4, 0.4, 1],
             "specular": [0.8, 0.8, 0.8, 1], "ambient": [0.05, 0.05, 0.05, 1]},
        ],
        "draws": [
            {"mesh": PHONG_SPHERE, "material": {"color": [0.8, 0.8, 0.8, 1],
                                                "specular": [0.7, 0.7, 0.7, 1], "shininess": 30},
             "state": {"cull": "back", "shading": "phong"}},
            {"mesh": PHONG_SPHERE, "transform": {"translate": [0, -1.0, 0], "scale": [2.2, 0.3, 1.6]},
             "material": {"color": [0.5, 0.6, 0.5, 1], "specular": [0.5, 0.5, 0.5, 1],
                          "shininess": 12},
             "state": {"cull": "back", "shading": "phong"}},
        ],
    }


@scene("phong_mesh_wuson", "mesh", "2, 7, 9, 9b, 11",
       "Phong on a real mesh: WusonOBJ.obj as mesh_wuson_lit (a directional and an attenuated "
       "point light, specular highlights, back faces culled), shaded per pixel")
def phong_mesh_wuson():
    s = mesh_wuson_lit()
    s["draws"][0]["state"]["shading"] = "phong"
    return s


@scene("msaa_phong_duck", "multisampling", "2, 9b, 14",
       "4 samples: duck.dae as msaa_mesh_duck, shaded per pixel (Phong): lit once per pixel at "
       "its centre, stored in every covered sample")
def msaa_phong_duck():
    s = msaa_mesh_duck()
    s["draws"][0]["state"]["shading"] = "phong"
    return s


# ---------------------------------------------------------------- painter


def without_comments(name):
    """A scene of testbench/scenes/ (the one source), its // comment lines dropped."""
    with open(os.path.join(ROOT, "testbench", "scenes", name + ".json")) as f:
        return json.loads("".join(line for line in f if not line.lstrip().startswith("//")))


@scene("painter_cycle", "painter", "docs/painter.md",
       "\"visibility\": \"painter\": three blades overlapping cyclically, which the host's sort "
       "must split; llvmpipe draws the same sorted, split clip-space draws with depth func always")
def painter_cycle():
    return without_comments("painter_cycle")


@scene("painter_interpenetrate", "painter", "docs/painter.md",
       "\"visibility\": \"painter\": two triangles passing through each other, split along their "
       "intersection in clip space under a perspective camera")
def painter_interpenetrate():
    return without_comments("painter_interpenetrate")


@scene("painter_features", "painter", "docs/painter.md",
       "\"visibility\": \"painter\": a depth clear between two stretches sorted on their own, "
       "per-draw viewports, flat shading under the first-vertex convention, and a "
       "screen-interpolated and a Phong draw passed unsorted")
def painter_features():
    s = without_comments("painter_features")
    # The meshes of testbench/scenes/regress/ sit beside the regression scenes.
    for d in s["draws"]:
        if "mesh" in d:
            d["mesh"] = d["mesh"].removeprefix("regress/")
    return s


def dump(value):
    """JSON with one line per vertex: arrays of numbers (and of booleans) stay on
    one line, and so do the index lists."""
    text = json.dumps(value, indent=1)
    text = re.sub(r"\[\s+([^\[\]{}]*?)\s+\]",
                  lambda m: "[" + re.sub(r",\s+", ", ", m.group(1)) + "]", text)
    return text + "\n"


def main(argv=None):
    global OUT
    parser = argparse.ArgumentParser(
        description="Write the regression scenes (docs/validation.md), or print their table.")
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--out", metavar="DIR",
                      help="write the scenes and lines_mesh.obj into DIR (created if needed)")
    what.add_argument("--write-testbench", action="store_true",
                      help="rewrite the committed scenes in testbench/scenes/regress/")
    what.add_argument("--table", action="store_true",
                      help="print the scenes as a Markdown table; write nothing")
    args = parser.parse_args(argv)
    if not (args.table or args.write_testbench or args.out is not None):
        parser.print_usage(sys.stderr)
        print(f"{parser.prog}: error: give --out DIR, --write-testbench to rewrite "
              "testbench/scenes/regress/, or --table", file=sys.stderr)
        return 2
    if args.table:
        print("| scene | category | spec sections | what it exercises |")
        print("|---|---|---|---|")
        for name, category, sections, description, _ in SCENES:
            print(f"| `{name}` | {category} | {sections} | {description} |")
        return 0
    if args.out is not None:
        OUT = args.out
    os.makedirs(OUT, exist_ok=True)
    for mesh, text in ((LINE_MESH, line_mesh_obj), (PHONG_SPHERE, phong_sphere_obj),
                       (PHONG_LOWPOLY, phong_lowpoly_obj)):
        with open(os.path.join(OUT, mesh), "w") as f:
            f.write(text())
    for name, _, _, _, fn in SCENES:
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            f.write(dump(fn()))
    print(f"wrote {len(SCENES)} scenes to {os.path.relpath(OUT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
