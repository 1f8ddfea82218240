#!/usr/bin/env python3
"""Writes the lesson scenes of testbench/scenes/lessons/ (docs/lessons.md).

Each scene is computed from the few numbers its lesson is about (near, far,
the distances of the planes, the needles' corners), so the geometry can be
checked against the analytic values scripts/lessons quotes. Deterministic:
running it again gives the same files.

Writes only where told: `--out DIR` writes into DIR, `--write-testbench`
rewrites the committed copies in testbench/scenes/lessons/."""
import argparse
import json
import math
import os
import random
import sys

LESSONS = os.path.normpath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testbench", "scenes",
                 "lessons"))


def r(x):
    return round(x, 6)


def dump(value, indent=0):
    """JSON with one line per vertex, colour or short list: the scenes stay
    readable (json.dump's indent puts every number on its own line)."""
    pad = " " * indent
    if isinstance(value, dict):
        items = [f'{pad} {json.dumps(k)}: {dump(v, indent + 1).lstrip()}' for k, v in value.items()]
        return pad + "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list) and value and all(isinstance(v, (list, dict)) for v in value):
        return pad + "[\n" + ",\n".join(dump(v, indent + 1) for v in value) + "\n" + pad + "]"
    return pad + json.dumps(value, separators=(", ", ": "))


def write(out, name, comment, scene):
    with open(os.path.join(out, name), "w") as f:
        for line in comment.strip().splitlines():
            f.write(f"// {line}".rstrip() + "\n")
        f.write(dump(scene) + "\n")


def eye_quad(x0, x1, y0, y1, distance, color):
    """A quad facing the camera at `distance` along -z (eye space, camera at
    the origin), two triangles, counter-clockwise seen from the camera."""
    z = -distance
    return {
        "primitive": "triangle_strip",
        "positions": [[r(x0), r(y0), r(z)], [r(x1), r(y0), r(z)], [r(x0), r(y1), r(z)],
                      [r(x1), r(y1), r(z)]],
        "colors": [color] * 4,
    }


def depth_nonlinear(out):
    # fovy 90: tan(45°) = 1, so at distance d the view is ±d·aspect wide and
    # ±d high. Strip i covers the i-th ninth of the width, at the fraction
    # f = (i + 1) / 10 of the way from near to far, grey level f.
    w, h, near, far = 180, 60, 1.0, 10.0
    aspect = w / h
    draws = []
    for i in range(9):
        f = (i + 1) / 10
        d = near + f * (far - near)
        x0 = (-1 + 2 * i / 9) * d * aspect
        x1 = (-1 + 2 * (i + 1) / 9) * d * aspect
        quad = eye_quad(x0, x1, -1.2 * d, 1.2 * d, d, [r(f), r(f), r(f), 1])
        quad["name"] = f"{round(f * 100)}% of the range: distance {r(d)}"
        draws.append(quad)
    write(out, "depth_nonlinear.json", """
Lesson "depth is not linear" (docs/lessons.md): nine strips facing the
camera at 10%, 20%, ... 90% of the way from near (1) to far (10), each
coloured by that fraction; the depth buffer stores
(1/near - 1/d) / (1/near - 1/far), 0.81 at 30% (distance 3.7).
Written by scripts/gen/make_lesson_scenes.py.
""", {
        "framebuffer": {"width": w, "height": h, "depth_format": "unorm24"},
        "camera": {"type": "perspective", "fovy": 90, "near": near, "far": far},
        "draws": draws,
    })


def depth_precision(out):
    # Two planes facing the camera: the far one (903, green) over the right
    # two thirds, drawn first; the near one (900, red) over the left two
    # thirds, drawn second with `less`. Where they overlap (the middle third)
    # the near plane should win.
    w, h, near, far = 120, 60, 0.1, 1000.0
    aspect = w / h
    for fmt in ("unorm16", "unorm24"):
        draws = []
        for d, x0, x1, color, name in ((903.0, -1 / 3, 1.2, [0.25, 1, 0.25, 1], "far plane, 903"),
                                       (900.0, -1.2, 1 / 3, [1, 0.25, 0.25, 1], "near plane, 900")):
            quad = eye_quad(x0 * d * aspect, x1 * d * aspect, -1.2 * d, 1.2 * d, d, color)
            quad["name"] = name
            draws.append(quad)
        write(out, f"depth_precision_{fmt}.json", f"""
Lesson "depth precision collapses far away" (docs/lessons.md): near 0.1,
far 1000, {fmt} depth. A green plane at distance 903 over the right two
thirds is drawn first, then a red plane at 900 over the left two thirds with
depth test `less`. Both store the depth code
round((10 - 1/d) / (10 - 1/1000) * (2^n - 1)): equal in unorm16 (65534), so
the nearer plane fails the test in the middle third; 6 codes apart in unorm24.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": w, "height": h, "depth_format": fmt},
            "camera": {"type": "perspective", "fovy": 90, "near": near, "far": far},
            "draws": draws,
        })


CUBE_FACES = [  # (normal axis, sign, colour): each face's four corners follow
    ((0, 1), [0.9, 0.3, 0.3, 1]), ((0, -1), [0.3, 0.9, 0.3, 1]), ((1, 1), [0.3, 0.3, 0.9, 1]),
    ((1, -1), [0.9, 0.9, 0.3, 1]), ((2, 1), [0.3, 0.9, 0.9, 1]), ((2, -1), [0.9, 0.3, 0.9, 1]),
]


def cube_draw(state):
    pos, col, idx = [], [], []
    for (axis, sign), color in CUBE_FACES:
        u, v = [a for a in range(3) if a != axis]
        if (axis == 1) == (sign > 0):
            u, v = v, u  # (u, v, outward normal) right-handed: counter-clockwise from outside
        base = len(pos)
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = [0, 0, 0]
            p[axis], p[u], p[v] = sign, a, b
            pos.append(p)
            col.append(color)
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return {"name": "cube", "primitive": "triangles", "positions": pos, "colors": col,
            "indices": idx, "transform": {"rotate": [[30, 0, 1, 0], [25, 1, 0, 0]]},
            "state": state}


def cull_cube(out):
    for name, state, what in (
            ("cull_cube_depth", {"cull": "none", "depth_test": "less"},
             "no culling, depth test `less`: the z-buffer hides the back faces"),
            ("cull_cube_culled", {"cull": "back", "depth_test": "off"},
             "back faces culled, depth test off: culling alone hides them")):
        write(out, f"{name}.json", f"""
Lesson "culling alone solves visibility for one convex solid"
(docs/lessons.md): a cube with one colour per face, {what}.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 96, "height": 96},
            "camera": {"type": "perspective", "fovy": 40, "near": 3, "far": 10,
                       "eye": [0, 0, 6]},
            "draws": [cube_draw(state)],
        })


def needles(out):
    # Window coordinates of a 256x256 frame without camera: clip x = X/128 - 1.
    def clip(x, y):
        return [r(x / 128 - 1), r(y / 128 - 1), 0.5]

    for name, corners, what in (
            ("needle_horizontal", [(0, 8), (256, 8), (0, 10)],
             "from (0, 8) to (256, 8) and (0, 10): its box is 256x2 pixels, one row of 16 tiles"),
            ("needle_diagonal", [(0, 0), (256, 256), (2, 0)],
             "from (0, 0) to (256, 256) and (2, 0): its box is the whole 256x256 frame, 16x16 tiles")):
        write(out, f"{name}.json", f"""
Lesson "long thin triangles cost tiles" (docs/lessons.md): one triangle of
area 256 pixels {what} (tile_size 16). Window coordinates (X, Y) are given as
clip coordinates X/128 - 1, Y/128 - 1 (no camera).
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 256, "height": 256},
            "draws": [{"name": "needle", "primitive": "triangles",
                       "positions": [clip(x, y) for x, y in corners],
                       "colors": [[1, 1, 1, 1]] * 3}],
        })


def shared_edges(out):
    # A grid of 8x6 quads over the whole frame with moved inner corners, and a
    # fan of 12 triangles around a point, each adding 0.25 (blend one, one).
    rng = random.Random(14)
    nx, ny = 8, 6
    w, h = 96, 72
    grid = {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            x, y = -1 + 2 * i / nx, -1 + 2 * j / ny
            if 0 < i < nx and 0 < j < ny:
                x += rng.uniform(-0.4, 0.4) * 2 / nx
                y += rng.uniform(-0.4, 0.4) * 2 / ny
            grid[i, j] = [r(x), r(y), 0.5]
    pos = [grid[i, j] for j in range(ny + 1) for i in range(nx + 1)]
    idx = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            idx += [a, a + 1, a + nx + 2, a, a + nx + 2, a + nx + 1]
    fan = [[0.1, 0.05, 0.5]]
    for k in range(13):
        t = 2 * math.pi * (k % 12) / 12 + 0.3
        rad = 0.55 if k % 2 else 0.4
        fan.append([r(0.1 + rad * math.cos(t) * h / w), r(0.05 + rad * math.sin(t)), 0.5])
    quarter = [0.25, 0.25, 0.25, 1]
    state = {"blend": {"src": "one", "dst": "one"}, "depth_test": "off"}
    write(out, "shared_edges.json", """
Lesson "shared edges are drawn exactly once" (docs/lessons.md): a grid of
8x6 quads with moved inner corners covering the frame and a fan of 12
triangles, each triangle adding 0.25 (blend one, one; depth test off).
A pixel covered once reads 64/255, twice 128/255; any other value would be
an edge pixel drawn twice or not at all.
Written by scripts/gen/make_lesson_scenes.py.
""", {
        "framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 1]},
        "draws": [
            {"name": "grid", "primitive": "triangles", "positions": pos,
             "colors": [quarter] * len(pos), "indices": idx, "state": state},
            {"name": "fan", "primitive": "triangle_fan", "positions": fan,
             "colors": [quarter] * len(fan), "state": state},
        ],
    })


def antialias(out):
    # A white triangle with long shallow edges on black: with 4 samples each
    # edge pixel is covered by 0..4 samples, so its grey is one of 5 levels.
    for samples in (1, 4):
        write(out, f"antialias_{samples}x.json", f"""
Lesson "antialiasing" (docs/lessons.md): a white triangle with long shallow
edges on black, {samples} sample{'s' if samples > 1 else ''} per pixel.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 64, "height": 48, "samples": samples},
            "draws": [{"name": "white triangle", "primitive": "triangles",
                       "positions": [[-0.9, -0.7, 0.5], [0.85, -0.35, 0.5], [-0.2, 0.8, 0.5]],
                       "colors": [[1, 1, 1, 1]] * 3}],
        })


def polygon_offset(out):
    # A grey floor and a red decal on the same plane y = -1, the decal drawn
    # second with `less`: its depths, interpolated over other triangles, come
    # out a rounding above or below the floor's, pixel by pixel.
    def floor_quad(x0, x1, z0, z1, color):
        return {"primitive": "triangle_strip",
                "positions": [[x0, -1, z0], [x1, -1, z0], [x0, -1, z1], [x1, -1, z1]],
                "colors": [color] * 4}

    for name, offset, what in (("offset_none", [0, 0], "without polygon offset"),
                               ("offset_pulled", [-1, -1], "with polygon offset [-1, -1]")):
        floor = floor_quad(-4, 4, -2, -14, [0.5, 0.5, 0.5, 1])
        floor["name"] = "floor"
        red = [1, 0.25, 0.25, 1]
        decal = {"name": "decal", "primitive": "triangle_fan",
                 "positions": [[0, 0, 3.5], [2.5, 0, 0], [0, 0, -3.5], [-2.5, 0, 0]],
                 "colors": [red] * 4,
                 "transform": {"rotate": [20, 0, 1, 0], "translate": [0, -1, -6.5]}}
        decal["state"] = {"depth_test": "less", "polygon_offset": offset}
        write(out, f"{name}.json", f"""
Lesson "polygon offset against z-fighting" (docs/lessons.md): a grey floor
and a red decal on the same plane (y = -1), the decal drawn second with
depth test `less`, {what}.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 128, "height": 96},
            "camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 20, "eye": [0, 3, 0],
                       "target": [0, -1, -7]},
            "draws": [floor, decal],
        })


def main():
    ap = argparse.ArgumentParser(description="Write the lesson scenes of testbench/scenes/lessons/ "
                                 "(docs/lessons.md).")
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--out", metavar="DIR", help="write the scenes into DIR (created if needed)")
    where.add_argument("--write-testbench", action="store_true",
                       help="rewrite the committed scenes in testbench/scenes/lessons/")
    args = ap.parse_args()
    if args.out is None and not args.write_testbench:
        ap.print_usage(sys.stderr)
        print(f"{ap.prog}: error: give --out DIR, or --write-testbench to rewrite "
              "testbench/scenes/lessons/", file=sys.stderr)
        return 2
    out = LESSONS if args.write_testbench else args.out
    os.makedirs(out, exist_ok=True)
    for make in (depth_nonlinear, depth_precision, cull_cube, needles, shared_edges, antialias,
                 polygon_offset):
        make(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
