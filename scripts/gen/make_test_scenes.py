#!/usr/bin/env python3
"""Writes the procedural test scenes (deterministic: a fixed seed, so running
it again gives the same files).

Writes only where told: `--out DIR` writes them into DIR, `--write-testbench`
rewrites the committed copies in testbench/scenes/. With neither, it prints
its usage and writes nothing; `--help` prints the usage."""
import argparse
import json
import math
import os
import random
import sys

TESTBENCH = os.path.normpath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testbench", "scenes"))
OUT = TESTBENCH


def write(name, scene):
    with open(os.path.join(OUT, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def r(x):
    return round(x, 5)


def tiny_triangles():
    """Sub-pixel, 1-pixel, slivers and needles in clip space, 96x64."""
    rng = random.Random(1234)
    w, h = 96, 64
    pos, col = [], []
    for _ in range(400):
        cx, cy = rng.uniform(-1, 1), rng.uniform(-1, 1)
        size = 2.0 ** rng.uniform(-3, 3) / w * 2  # 1/8 .. 8 pixels
        kind = rng.random()
        for k in range(3):
            a = rng.uniform(0, 2 * math.pi)
            s = size * (0.02 if kind < 0.2 and k == 2 else 1.0)  # slivers
            pos.append([r(cx + s * math.cos(a)), r(cy + s * math.sin(a) * (8 if kind > 0.9 else 1)),
                        r(rng.uniform(-0.9, 0.9)), 1])
            col.append([r(rng.random()), r(rng.random()), r(rng.random()), 1])
    return {
        "framebuffer": {"width": w, "height": h, "depth_format": "unorm16"},
        "draws": [{"primitive": "triangles", "positions": pos, "colors": col,
                   "state": {"depth_test": "lequal"}}],
    }


def shared_edges():
    """A 12x9 grid of quads as indexed triangles sharing every edge, and a
    fan around the centre, additively blended so that any pixel drawn twice
    shows: the fill rule must cover each pixel exactly once."""
    n, m = 12, 9
    pos, col, idx = [], [], []
    rng = random.Random(7)
    for j in range(m + 1):
        for i in range(n + 1):
            jitter = 0.0 if i in (0, n) or j in (0, m) else rng.uniform(-0.03, 0.03)
            pos.append([r(-1 + 2 * i / n + jitter), r(-1 + 2 * j / m - jitter), 0.5, 1])
            col.append([0.25, 0.25, 0.25, 1])
    for j in range(m):
        for i in range(n):
            a = j * (n + 1) + i
            idx += [a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]
    fan = [[0, 0, 0.2, 1]]
    for k in range(17):
        a = 2 * math.pi * (k % 16) / 16
        fan.append([r(0.7 * math.cos(a)), r(0.7 * math.sin(a)), 0.2, 1])
    additive = {"blend": {"src": "one", "dst": "one"}, "depth_test": "off"}
    return {
        "framebuffer": {"width": 120, "height": 90, "clear_color": [0, 0, 0, 0]},
        "draws": [
            {"primitive": "triangles", "positions": pos, "colors": col, "indices": idx,
             "state": additive},
            {"primitive": "triangle_fan", "positions": fan,
             "colors": [[0.3, 0.1, 0.05, 0.5]] * len(fan), "state": additive},
        ],
    }


def clipping():
    """A perspective view where geometry crosses the near and far planes,
    passes behind the eye and reaches far beyond the guard band."""
    ground = {"primitive": "triangle_strip",
              "positions": [[-500, -1, 500], [500, -1, 500], [-500, -1, -500], [500, -1, -500]],
              "colors": [[0.2, 0.6, 0.2, 1], [0.6, 0.6, 0.2, 1], [0.2, 0.2, 0.6, 1], [0.6, 0.2, 0.6, 1]]}
    near_cut = {"primitive": "triangles",
                "positions": [[-0.5, -0.3, 0.5], [0.6, -0.2, -3], [0.1, 0.6, -2],
                              [-3, 0.2, -1], [2, 0.1, 1], [0.5, 1.5, -6]],
                "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [0, 1, 1, 1], [1, 0, 1, 1]]}
    behind = {"primitive": "triangles",
              "positions": [[-1, 0, 2], [1, 0, 2], [0, 1, 3]], "colors": [[1, 1, 1, 1]] * 3}
    huge = {"primitive": "triangles",
            "positions": [[-100000, -0.5, -10], [100000, -0.4, -10], [0, 80000, -12]],
            "colors": [[0.9, 0.4, 0.1, 1], [0.1, 0.4, 0.9, 1], [0.5, 0.9, 0.5, 1]],
            "state": {"depth_test": "lequal", "shading": "flat"}}
    return {
        "framebuffer": {"width": 128, "height": 96, "depth_format": "float32",
                        "clear_color": [0.05, 0.05, 0.1, 1]},
        "camera": {"type": "perspective", "fovy": 70, "near": 0.5, "far": 40,
                   "eye": [0, 0, 0], "target": [0, -0.1, -1]},
        "draws": [ground, near_cut, behind, huge],
    }


def zfight():
    """Coplanar planes: the second loses with less, wins with polygon offset."""
    quad = [[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]
    def plane(color, state):
        return {"primitive": "triangle_strip", "positions": quad, "colors": [color] * 4,
                "transform": {"rotate": [[60, 1, 0, 0], [25, 0, 1, 0]], "translate": [0, 0, -3]},
                "state": state}
    return {
        "framebuffer": {"width": 100, "height": 100, "depth_format": "unorm16"},
        "camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 50},
        "draws": [
            plane([0.8, 0.2, 0.2, 1], {"depth_test": "less"}),
            plane([0.2, 0.8, 0.2, 1], {"depth_test": "less"}),
            {**plane([0.2, 0.2, 0.8, 1], {"depth_test": "less", "polygon_offset": [-1, -2]}),
             "transform": {"rotate": [[60, 1, 0, 0], [25, 0, 1, 0]], "translate": [0, 0, -3],
                           "scale": 0.5}},
        ],
    }


def states():
    """Strips, fans, culling modes, front faces, blending, colour masks,
    depth functions, flat shading, into an rgba16f buffer."""
    draws = []
    rng = random.Random(99)
    funcs = ["less", "lequal", "greater", "gequal", "equal", "notequal", "always", "never", "off"]
    blends = [("src_alpha", "one_minus_src_alpha", "add"), ("one", "one", "add"),
              ("dst_color", "zero", "add"), ("one", "one", "subtract"),
              ("src_alpha_saturate", "one", "reverse_subtract"), ("one_minus_dst_alpha", "dst_alpha", "add")]
    for k in range(18):
        cx, cy = -0.8 + 0.32 * (k % 6), -0.7 + 0.7 * (k // 6)
        strip = k % 2 == 0
        n = 6
        pos = []
        for v in range(n):
            if strip:
                pos.append([r(cx + 0.05 * v), r(cy + (0.25 if v % 2 else 0) + rng.uniform(-0.02, 0.02)),
                            r(rng.uniform(-0.5, 0.5)), 1])
            else:
                a = 2 * math.pi * v / n
                pos.append([r(cx + (0 if v == 0 else 0.15 * math.cos(a))),
                            r(cy + (0 if v == 0 else 0.15 * math.sin(a))), r(rng.uniform(-0.5, 0.5)), 1])
        b = blends[k % len(blends)]
        draws.append({
            "primitive": "triangle_strip" if strip else "triangle_fan",
            "positions": pos,
            "colors": [[r(rng.random()), r(rng.random()), r(rng.random()), r(rng.uniform(0.2, 1))] for _ in pos],
            "state": {"cull": ["none", "back", "front"][k % 3], "front_face": ["ccw", "cw"][(k // 3) % 2],
                      "depth_test": funcs[k % len(funcs)], "depth_write": k % 4 != 3,
                      "blend": {"src": b[0], "dst": b[1], "equation": b[2]} if k % 3 else "off",
                      "color_mask": [True, k % 5 != 1, True, k % 7 != 2],
                      "shading": "flat" if k % 4 == 1 else "gouraud"}})
    # A full-screen backdrop first so every depth function has something to meet.
    draws.insert(0, {"primitive": "triangle_strip",
                     "positions": [[-1, -1, 0.1, 1], [1, -1, 0.1, 1], [-1, 1, 0.1, 1], [1, 1, 0.1, 1]],
                     "colors": [[0.5, 0.5, 0.5, 0.5]] * 4})
    return {
        "framebuffer": {"width": 160, "height": 90, "color_format": "rgba16f", "depth_format": "unorm24",
                        "clear_color": [0.1, 0.2, 0.3, 0.4], "clear_depth": 0.75},
        "draws": draws,
    }


def lines_random():
    """Lines, strips and loops in every direction, at random 1/256 end points
    and on pixel centres, widths 1-6, both line rules, flat and Gouraud,
    crossing the framebuffer's edges and (in a perspective draw) the near
    plane, with a depth test, 80x60."""
    rng = random.Random(4242)
    w, h = 80, 60
    draws = []

    def ndc(px, size):
        return r(px / size * 2 - 1)

    for k in range(24):
        prim = ["lines", "line_strip", "line_loop"][k % 3]
        n = rng.randint(2, 7)
        centred = k % 4 == 1  # end points exactly on pixel centres
        pos = []
        for _ in range(n):
            if centred:
                x, y = rng.randint(-3, w + 2) + 0.5, rng.randint(-3, h + 2) + 0.5
            else:
                x, y = rng.uniform(-6, w + 6), rng.uniform(-6, h + 6)
            pos.append([ndc(x, w), ndc(y, h), r(rng.uniform(-0.9, 0.9)), 1])
        draws.append({
            "primitive": prim, "positions": pos,
            "colors": [[r(rng.random()), r(rng.random()), r(rng.random()), 1] for _ in pos],
            "state": {"line_width": [1, 1, 2, 3, 1.5, 6, 2.5, 4][k % 8],
                      "line_rasterization": "bresenham" if k % 5 == 2 else "diamond_exit",
                      "shading": "flat" if k % 3 == 1 else "gouraud",
                      "depth_test": "lequal"}})
    # Clip-space end points (no camera: positions are clip coordinates) across
    # the near plane (z < -w), the far plane and w < 0.
    draws.append({"primitive": "lines",
                  "positions": [[-0.5, 0.2, -1.5, 1], [0.4, -0.1, 0.5, 1], [0.8, 0.5, 0.2, 1.2],
                                [-0.6, -0.4, 0.1, -0.8], [-0.3, -0.3, 0.9, 0.5], [0.2, 0.4, 2.5, 1.5]],
                  "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [0, 1, 1, 1],
                             [1, 0, 1, 1]],
                  "state": {"line_width": 2}})
    return {
        "framebuffer": {"width": w, "height": h, "depth_format": "unorm24",
                        "clear_color": [0.05, 0.05, 0.05, 1]},
        "draws": draws,
    }


def points_wireframe():
    """Points of sizes 1-24 (integer and fractional) on and off the
    framebuffer's edges, and triangles in polygon mode line and point with
    culling, flat shading and a near-plane cut, 96x72."""
    rng = random.Random(515)
    w, h = 96, 72
    pos, col = [], []
    for _ in range(60):
        pos.append([r(rng.uniform(-1.1, 1.1)), r(rng.uniform(-1.1, 1.1)), r(rng.uniform(-0.9, 0.9)), 1])
        col.append([r(rng.random()), r(rng.random()), r(rng.random()), 1])
    draws = []
    for k, size in enumerate([1, 2, 3, 1.5, 4.7, 8, 13, 24]):
        draws.append({"primitive": "points", "positions": pos[k::8], "colors": col[k::8],
                      "state": {"point_size": size, "depth_test": "lequal"}})
    tri = []
    tcol = []
    for _ in range(12):
        cx, cy = rng.uniform(-1, 1), rng.uniform(-1, 1)
        for _ in range(3):
            tri.append([r(cx + rng.uniform(-0.4, 0.4)), r(cy + rng.uniform(-0.4, 0.4)),
                        r(rng.uniform(-0.5, 0.5)), 1])
            tcol.append([r(rng.random()), r(rng.random()), r(rng.random()), 1])
    modes = [("line", "none", "gouraud", "diamond_exit", 1), ("line", "back", "flat", "bresenham", 2),
             ("point", "front", "gouraud", "diamond_exit", 3), ("line", "none", "flat", "diamond_exit", 3)]
    for k, (mode, cull, shading, rule, size) in enumerate(modes):
        draws.append({"primitive": "triangles", "positions": tri[9 * k:9 * k + 9],
                      "colors": tcol[9 * k:9 * k + 9],
                      "state": {"polygon_mode": mode, "cull": cull, "shading": shading,
                                "line_rasterization": rule, "line_width": size, "point_size": size}})
    return {
        "framebuffer": {"width": w, "height": h, "depth_format": "float32"},
        "draws": draws,
    }


def antialiased(samples, supersample, seed, color_format="rgba8", depth_format="unorm24"):
    """Multisampling and supersampling (pipeline-spec.md section 14) at 96x64:
    overlapping triangles with a depth test, alpha blending and additive
    blending, a coplanar pair resolved by polygon offset, lines of widths 1,
    1.5, 2, 3 and 5 in every direction (both line rules: multisampled lines
    ignore the rule), points of sizes 1 to 9 on and off the edges, depth
    tested."""
    rng = random.Random(seed)
    w, h = 96, 64
    draws = []
    tri, tcol = [], []
    for _ in range(10):
        cx, cy = rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9)
        for _ in range(3):
            tri.append([r(cx + rng.uniform(-0.5, 0.5)), r(cy + rng.uniform(-0.5, 0.5)),
                        r(rng.uniform(-0.8, 0.8)), 1])
            tcol.append([r(rng.random()), r(rng.random()), r(rng.random()), r(rng.uniform(0.3, 1))])
    draws.append({"primitive": "triangles", "positions": tri[:15], "colors": tcol[:15],
                  "state": {"depth_test": "less"}})
    draws.append({"primitive": "triangles", "positions": tri[15:24], "colors": tcol[15:24],
                  "state": {"depth_test": "lequal",
                            "blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}})
    draws.append({"primitive": "triangles", "positions": tri[24:], "colors": tcol[24:],
                  "state": {"depth_test": "always", "depth_write": False,
                            "blend": {"src": "one", "dst": "one"}}})
    # A tilted plane and a coplanar copy drawn over it with polygon offset.
    plane = [[-0.7, -0.6, -0.3, 1], [0.6, -0.7, 0.4, 1], [-0.6, 0.7, 0.1, 1], [0.7, 0.6, 0.6, 1]]
    draws.append({"primitive": "triangle_strip", "positions": plane, "colors": [[0.8, 0.2, 0.2, 1]] * 4,
                  "state": {"depth_test": "less"}})
    draws.append({"primitive": "triangle_strip", "positions": plane, "colors": [[0.2, 0.3, 0.9, 1]] * 4,
                  "state": {"depth_test": "less", "polygon_offset": [-1, -2]}})
    for k, width in enumerate([1, 1.5, 2, 3, 5]):
        pos, col = [], []
        for _ in range(6):
            x, y = rng.uniform(-4, w + 4), rng.uniform(-4, h + 4)
            pos.append([r(x / w * 2 - 1), r(y / h * 2 - 1), r(rng.uniform(-0.9, 0.9)), 1])
            col.append([r(rng.random()), r(rng.random()), r(rng.random()), 1])
        draws.append({"primitive": ["lines", "line_strip", "line_loop"][k % 3], "positions": pos,
                      "colors": col,
                      "state": {"line_width": width, "depth_test": "lequal",
                                "line_rasterization": "bresenham" if k == 2 else "diamond_exit",
                                "shading": "flat" if k == 1 else "gouraud"}})
    for k, size in enumerate([1, 2, 3, 4.5, 9]):
        pos, col = [], []
        for _ in range(5):
            pos.append([r(rng.uniform(-1.05, 1.05)), r(rng.uniform(-1.05, 1.05)), r(rng.uniform(-0.9, 0.9)), 1])
            col.append([r(rng.random()), r(rng.random()), r(rng.random()), 1])
        draws.append({"primitive": "points", "positions": pos, "colors": col,
                      "state": {"point_size": size, "depth_test": "lequal"}})
    fb = {"width": w, "height": h, "samples": samples, "supersample": supersample,
          "color_format": color_format, "depth_format": depth_format,
          "clear_color": [0.05, 0.05, 0.1, 1]}
    return {"framebuffer": fb, "draws": draws}


def provoking_interpolation():
    """Every primitive type flat-shaded with the first-vertex convention, and
    screen interpolation beside perspective, clipped and not; clip space, 160x128."""
    c = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [1, 0, 1, 1], [0, 1, 1, 1],
         [1, 1, 1, 1], [0.5, 0.25, 0, 1], [0.25, 0.5, 1, 1], [0.75, 0.1, 0.4, 1]]
    ff = {"shading": "flat", "provoking_vertex": "first"}
    scr = {"interpolation": "screen"}

    def pos(points):
        return [[r(v) for v in p] for p in points]

    def homogeneous(x, y, z, w):
        return [x * w, y * w, z * w, w]

    fan = [[0.55, 0.7, 0.0, 1]] + [[0.55 + 0.35 * math.cos(a), 0.7 + 0.28 * math.sin(a), 0.0, 1]
                                   for a in (0.1, 1.0, 2.0, 3.0, 4.2, 5.5)]
    draws = [
        {"name": "triangles, first-vertex flat", "primitive": "triangles",
         "positions": pos([[-0.95, 0.6, 0.1, 1], [-0.7, 0.6, 0.1, 1], [-0.85, 0.95, 0.1, 1],
                           [-0.65, 0.6, 0.1, 1], [-0.4, 0.95, 0.1, 1], [-0.6, 0.95, 0.1, 1]]),
         "colors": c[:6], "state": ff},
        {"name": "strip, first-vertex flat", "primitive": "triangle_strip",
         "positions": pos([[-0.35 + 0.12 * (i // 2), 0.55 + 0.4 * (i % 2), 0.2, 1]
                           for i in range(7)]),
         "colors": c[:7], "state": ff},
        {"name": "fan, first-vertex flat (vertex i+1, not the centre), indexed",
         "primitive": "triangle_fan", "positions": pos(fan), "colors": c[:7],
         "indices": list(range(7)), "state": ff},
        {"name": "lines, first-vertex flat", "primitive": "lines",
         "positions": pos([[-0.95, 0.45, 0, 1], [-0.5, 0.35, 0, 1], [-0.95, 0.3, 0, 1],
                           [-0.5, 0.2, 0, 1]]),
         "colors": c[:4], "state": dict(ff, line_width=2)},
        {"name": "line strip, first-vertex flat", "primitive": "line_strip",
         "positions": pos([[-0.4, 0.45, 0, 1], [-0.2, 0.25, 0, 1], [0.0, 0.45, 0, 1],
                           [0.2, 0.25, 0, 1]]),
         "colors": c[2:6], "state": ff},
        {"name": "line loop, first-vertex flat, Bresenham", "primitive": "line_loop",
         "positions": pos([[0.3, 0.2, 0, 1], [0.6, 0.22, 0, 1], [0.62, 0.45, 0, 1],
                           [0.32, 0.42, 0, 1]]),
         "colors": c[4:8], "state": dict(ff, line_rasterization="bresenham")},
        {"name": "polygon mode line, strip, first-vertex flat", "primitive": "triangle_strip",
         "positions": pos([[-0.95 + 0.15 * (i // 2), -0.1 + 0.25 * (i % 2), 0.3, 1]
                           for i in range(6)]),
         "colors": c[:6], "state": dict(ff, polygon_mode="line")},
        {"name": "polygon mode point, fan, first-vertex flat", "primitive": "triangle_fan",
         "positions": pos([[-0.3, 0.05, 0.3, 1], [-0.1, -0.1, 0.3, 1], [-0.05, 0.1, 0.3, 1],
                           [-0.2, 0.2, 0.3, 1]]),
         "colors": c[3:7], "state": dict(ff, polygon_mode="point", point_size=3)},
        {"name": "clipped: first vertex behind the eye (w < 0) and beyond near",
         "primitive": "triangles",
         "positions": pos([[0.2, 0.0, -0.5, -0.4], [0.9, -0.1, 0.5, 1], [0.5, 0.15, 0.2, 1],
                           [0.3, -0.2, -2.5, 1], [0.8, -0.3, 0.1, 1], [0.6, 0.0, 0.1, 1]]),
         "colors": c[:6], "state": ff},
        {"name": "strip cut by the guard band, first-vertex flat", "primitive": "triangle_strip",
         "positions": pos([[-900, -0.4, 0.2, 1], [-0.6, -0.5, 0.2, 1], [-900, -0.3, 0.2, 1],
                           [-0.6, -0.25, 0.2, 1]]),
         "colors": c[5:9], "state": ff},
        {"name": "screen interpolation, strip with varying w", "primitive": "triangle_strip",
         "positions": pos([homogeneous(-0.9, -0.95, 0.5, 1), homogeneous(-0.3, -0.95, 0.5, 4),
                           homogeneous(-0.9, -0.55, 0.5, 0.5), homogeneous(-0.3, -0.55, 0.5, 3)]),
         "colors": c[:4], "state": scr},
        {"name": "perspective, the same strip", "primitive": "triangle_strip",
         "positions": pos([homogeneous(-0.2, -0.95, 0.5, 1), homogeneous(0.4, -0.95, 0.5, 4),
                           homogeneous(-0.2, -0.55, 0.5, 0.5), homogeneous(0.4, -0.55, 0.5, 3)]),
         "colors": c[:4]},
        {"name": "screen interpolation, clipped by w = 0 and near", "primitive": "triangles",
         "positions": pos([[0.5, -0.9, 0.0, 1], [0.95, -0.5, 0.3, 2], [0.7, -0.6, -1.0, -0.2],
                           [0.45, -0.5, -3, 1], [0.9, -0.8, 0.2, 1], [0.9, -0.55, 0.1, 0.5]]),
         "colors": c[3:9], "state": scr},
        {"name": "screen interpolation, guard band, polygon mode line", "primitive": "triangles",
         "positions": pos([[0.1, -0.9, 0.1, 1], [5000, -0.6, 0.1, 2], [0.2, -0.4, 0.1, 1]]),
         "colors": c[6:9], "state": dict(scr, polygon_mode="line")},
        {"name": "screen interpolation, clipped lines", "primitive": "line_strip",
         "positions": pos([[0.0, -0.2, 0.1, 1], [0.3, -0.9, -2, 1], [-0.3, -0.8, 0.5, -0.5],
                           [0.1, -0.3, 0.2, 0.5]]),
         "colors": c[:4], "state": dict(scr, line_width=2)},
        {"name": "screen and flat, first vertex: flat wins", "primitive": "triangle_fan",
         "positions": pos([[0.0, -0.1, 0.05, 1], [0.15, -0.15, 0.05, 2], [0.2, 0.1, 0.05, 1],
                           [0.0, 0.15, 0.05, 0.5]]),
         "colors": c[:4], "state": dict(ff, interpolation="screen")},
    ]
    return {"framebuffer": {"width": 160, "height": 128, "clear_color": [0, 0, 0, 1]},
            "draws": draws}


def main(argv=None):
    global OUT
    parser = argparse.ArgumentParser(
        description="Write the procedural test scenes (tiny_triangles.json, shared_edges.json, "
                    "clipping.json, zfight_offset.json, states.json, lines_random.json, points_wireframe.json, "
                    "aa_samples2.json, aa_samples8.json, aa_samples16.json, aa_super3_samples4.json, "
                    "aa_super2.json, provoking_interpolation.json).")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--out", metavar="DIR", help="write the scenes into DIR (created if needed)")
    where.add_argument("--write-testbench", action="store_true",
                       help="rewrite the committed scenes in testbench/scenes/")
    args = parser.parse_args(argv)
    if args.out is None and not args.write_testbench:
        parser.print_usage(sys.stderr)
        print(f"{parser.prog}: error: give --out DIR, or --write-testbench to rewrite "
              "testbench/scenes/", file=sys.stderr)
        return 2
    OUT = TESTBENCH if args.write_testbench else args.out
    os.makedirs(OUT, exist_ok=True)
    write("tiny_triangles.json", tiny_triangles())
    write("shared_edges.json", shared_edges())
    write("clipping.json", clipping())
    write("zfight_offset.json", zfight())
    write("states.json", states())
    write("lines_random.json", lines_random())
    write("points_wireframe.json", points_wireframe())
    write("aa_samples2.json", antialiased(2, 1, 2002, "rgba16f", "float32"))
    write("aa_samples8.json", antialiased(8, 1, 8008))
    write("aa_samples16.json", antialiased(16, 1, 1616, "rgba8", "unorm16"))
    write("aa_super3_samples4.json", antialiased(4, 3, 3434))
    write("aa_super2.json", antialiased(1, 2, 2020, "rgba16f", "unorm24"))
    write("provoking_interpolation.json", provoking_interpolation())
    print(f"wrote 13 scenes to {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
