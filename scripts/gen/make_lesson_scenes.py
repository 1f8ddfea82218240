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


def provoking_vertex(out):
    # Window coordinates of a 160x80 frame without camera: clip x = X/80 - 1.
    # Vertex k of the strip and of the fan has green k/5 (8-bit 51 k), so the
    # green of a flat triangle names its provoking vertex.
    w, h = 160, 80

    def clip(x, y):
        return [r(x / (w / 2) - 1), r(y / (h / 2) - 1), 0.5]

    def green(k):
        return [1, r(k / 5), 0, 1]

    strip = [(10 + 28 * k, 76 if k % 2 else 44) for k in range(6)]
    fan = [(80, 4)] + [(10 + 35 * k, 36) for k in range(5)]
    for conv in ("first", "last"):
        state = {"shading": "flat", "provoking_vertex": conv}
        write(out, f"provoking_{conv}.json", f"""
Lesson "first or last provoking vertex" (docs/lessons.md): a flat-shaded
strip of 4 triangles (top) and fan of 4 triangles (bottom), vertex k green
k/5, provoking_vertex {conv}. GL's table: strip triangle i takes vertex i
(first) or i + 2 (last); fan triangle i takes vertex i + 1 (first) or i + 2
(last), never the centre. Window coordinates (X, Y) are given as clip
coordinates X/80 - 1, Y/40 - 1 (no camera).
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0.3, 1]},
            "draws": [
                {"name": "strip", "primitive": "triangle_strip",
                 "positions": [clip(x, y) for x, y in strip],
                 "colors": [green(k) for k in range(6)], "state": state},
                {"name": "fan", "primitive": "triangle_fan",
                 "positions": [clip(x, y) for x, y in fan],
                 "colors": [green(k) for k in range(6)], "state": state},
            ],
        })


def icosahedron():
    t = (1 + 5 ** 0.5) / 2
    vs = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
          (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    n = (1 + t * t) ** 0.5
    vs = [tuple(c / n for c in v) for v in vs]
    faces = []
    for a in range(12):
        for b in range(a + 1, 12):
            for c in range(b + 1, 12):
                d = [sum((vs[i][k] - vs[j][k]) ** 2 for k in range(3)) for i, j in ((a, b), (b, c),
                                                                                    (a, c))]
                if all(abs(x - 4 / n / n) < 1e-9 for x in d):  # the 20 equilateral faces
                    u = [vs[b][k] - vs[a][k] for k in range(3)]
                    v = [vs[c][k] - vs[a][k] for k in range(3)]
                    cr = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                          u[0] * v[1] - u[1] * v[0]]
                    faces.append((a, b, c) if sum(cr[k] * vs[a][k] for k in range(3)) > 0 else
                                 (a, c, b))  # counter-clockwise seen from outside
    return vs, faces


def phong_gouraud(out):
    # An icosahedron (unit vertices, normals = positions) seen from (0, 0, 4):
    # the view only translates, so eye-space directions are world ones. The
    # directional light is placed so that the half vector H = normalize(L +
    # (0, 0, 1)) (docs/pipeline-spec.md 2, the infinite viewer) is the normal
    # at the centre of a face turned to the viewer (of the two most turned,
    # the left one): the highlight (n.H = 1) falls there, 37.4 degrees from
    # each of its vertices.
    vs, faces = icosahedron()
    lines = ["# Lesson \"Phong against Gouraud\" (docs/lessons.md): an icosahedron,",
             "# unit vertices, smooth normals. Written by scripts/gen/make_lesson_scenes.py."]
    lines += [f"v {r(x)} {r(y)} {r(z)}" for x, y, z in vs]
    lines += [f"vn {r(x)} {r(y)} {r(z)}" for x, y, z in vs]
    lines += [f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}" for a, b, c in faces]
    with open(os.path.join(out, "icosahedron.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")
    face = max(faces, key=lambda f: sum(vs[i][2] for i in f) - 0.01 * sum(vs[i][0] for i in f))
    c = [sum(vs[i][k] for i in face) for k in range(3)]
    hn = math.sqrt(sum(x * x for x in c))
    hv = [x / hn for x in c]
    lv = [2 * hv[2] * hv[k] - (0, 0, 1)[k] for k in range(3)]  # normalize(L + V) = H
    for shading in ("phong", "gouraud"):
        write(out, f"phong_gouraud_{shading}.json", f"""
Lesson "Phong against Gouraud" (docs/lessons.md): an icosahedron lit by one
directional light whose highlight (n.H = 1) falls at the centre of face
{list(face)}, 37.4 degrees from each of its vertices; specular white,
shininess 20, diffuse blue only, so red is the specular term alone; shading
{shading}. Face centre H = {[r(x) for x in hv]}, light towards
{[r(-x) for x in lv]}.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 96, "height": 96, "clear_color": [0, 0.25, 0, 1]},
            "camera": {"type": "perspective", "fovy": 40, "near": 1, "far": 10, "eye": [0, 0, 4],
                       "target": [0, 0, 0]},
            "ambient": [0, 0, 0, 1],
            "lights": [{"type": "directional", "direction": [r(-x) for x in lv]}],
            "draws": [{"name": "icosahedron", "mesh": "icosahedron.obj",
                       "material": {"ambient": [0, 0, 0, 1], "diffuse": [0, 0, 0.7, 1],
                                    "specular": [1, 1, 1, 1], "shininess": 20},
                       "state": {"cull": "back", "shading": shading}}],
        })
    # The highlight's pixel: the face centre (the mean of its vertices)
    # projected, for the manifest (printed, not written).
    p = [x / 3 for x in c]
    tf = math.tan(math.radians(20))
    X = (p[0] / (4 - p[2]) / tf + 1) / 2 * 96
    Y = (p[1] / (4 - p[2]) / tf + 1) / 2 * 96
    cosv = sum(vs[face[0]][k] * hv[k] for k in range(3))
    print(f"phong_gouraud: face centre at window ({X:.2f}, {Y:.2f}); n_vertex.H = {cosv:.6f}",
          file=sys.stderr)


def perspective_screen(out):
    # A floor (y = -1) of 3 x 4 tiles, each 1 wide and 3 deep, from distance
    # 2 to 14, seen from the origin looking down -z (fovy 60: tan 30 deg).
    # Red runs 0 to 1 across each tile from its near edge to its far one;
    # green and blue make the checkerboard and are constant per tile, so only
    # red depends on the interpolation.
    draws = []
    for row in range(4):
        z0, z1 = 2 + 3 * row, 5 + 3 * row
        for col in range(3):
            x0, x1 = -1.5 + col, -0.5 + col
            gb = [0.9, 0.2] if (row + col) % 2 else [0.2, 0.9]
            draws.append({"name": f"tile row {row} column {col}", "primitive": "triangle_strip",
                          "positions": [[x0, -1, -z0], [x1, -1, -z0], [x0, -1, -z1], [x1, -1, -z1]],
                          "colors": [[0] + gb + [1]] * 2 + [[1] + gb + [1]] * 2})
    for interp in ("perspective", "screen"):
        for d in draws:
            d["state"] = {"interpolation": interp}
        write(out, f"interp_{interp}.json", f"""
Lesson "perspective against screen interpolation" (docs/lessons.md): a
receding floor (y = -1) of 3 x 4 tiles, 1 wide and 3 deep from distance 2 to
14; red runs from 0 at each tile's near edge to 1 at its far edge, green and
blue make the checkerboard; interpolation {interp}.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": 128, "height": 96, "clear_color": [0, 0, 0, 1]},
            "camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 20,
                       "eye": [0, 0, 0], "target": [0, 0, -1]},
            "draws": draws,
        })


def painter(out):
    # Clip coordinates (no camera, w = 1) of a 128x64 frame: X/64 - 1.
    # Three rectangles on pixel boundaries at depths 0.2 (near), 0.5, 0.8
    # (far), listed nearest first: the z-buffer's best order, which the
    # painter's sort reverses.
    w, h = 128, 64

    def rect(x0, x1, y0, y1, z, color, name):
        return {"name": name, "primitive": "triangle_strip",
                "positions": [[r(x / (w / 2) - 1), r(y / (h / 2) - 1), z]
                              for x, y in ((x0, y0), (x1, y0), (x0, y1), (x1, y1))],
                "colors": [color] * 4}

    stack = [rect(10, 60, 10, 40, 0.2, [1, 0.25, 0.25, 1], "near, 50x30 at z 0.2"),
             rect(40, 90, 20, 50, 0.5, [0.25, 1, 0.25, 1], "middle, 50x30 at z 0.5"),
             rect(70, 120, 5, 35, 0.8, [0.25, 0.25, 1, 1], "far, 50x30 at z 0.8")]
    # The cyclic blades of testbench/scenes/painter_cycle.json: each lies
    # over the next one's tip, so no order of the three is right.
    blades = [
        {"name": "blade 0", "positions": [[0.0374, 0.7748, -0.5], [-0.6263, -0.6348, 0.5],
                                          [0.2626, 0.6448, -0.5]],
         "colors": [[1, 0.3, 0.2, 1], [0.5, 0.1, 0.05, 1], [1, 0.3, 0.2, 1]]},
        {"name": "blade 1", "positions": [[-0.7763, -0.505, -0.5], [0.7763, -0.375, 0.5],
                                          [-0.7763, -0.245, -0.5]],
         "colors": [[0.3, 1, 0.3, 1], [0.1, 0.45, 0.1, 1], [0.3, 1, 0.3, 1]]},
        {"name": "blade 2", "positions": [[0.7389, -0.5698, -0.5], [-0.15, 0.7098, 0.5],
                                          [0.5137, -0.6998, -0.5]],
         "colors": [[0.3, 0.5, 1, 1], [0.1, 0.15, 0.5, 1], [0.3, 0.5, 1, 1]]},
    ]
    for vis in ("painter", "zbuffer"):
        write(out, f"painter_stack_{vis}.json", f"""
Lesson "the painter's algorithm against the z-buffer" (docs/lessons.md):
three 50x30-pixel rectangles at depths 0.2, 0.5 and 0.8, the near one over
20x20 pixels of the middle one, the middle one over 20x15 of the far one,
listed nearest first; visibility {vis}. No camera: positions
are clip coordinates X/64 - 1, Y/32 - 1.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "visibility": vis,
            "framebuffer": {"width": w, "height": h, "clear_color": [0, 0, 0, 1]},
            "draws": stack,
        })
        write(out, f"painter_cycle_{vis}.json", f"""
Lesson "the painter's algorithm against the z-buffer" (docs/lessons.md):
the three blades of testbench/scenes/painter_cycle.json, each near the
viewer at its wide end and far at its tip and lying over the next blade's
tip: no order of the three is right; visibility {vis}.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "visibility": vis,
            "framebuffer": {"width": 128, "height": 128, "depth_format": "unorm24",
                            "clear_color": [0.08, 0.08, 0.1, 1]},
            "draws": blades,
        })


def depth_partitions(out):
    # unorm16, the whole scene from 0.1 to 100000: a blue quad at 5100 drawn
    # first, a red one at 5000 over part of it, and a green one at 2. The
    # generator projects each vertex itself (no camera: clip coordinates), so
    # the two passes can use two projections: far (1000, 100000) and near
    # (0.1, 1000). Rectangles are on pixel boundaries of the 120x60 frame.
    w, h = 120, 60

    def quad(x0, x1, y0, y1, d, near, far, color, name):
        # GL's perspective: z_clip = (f + n) / (f - n) d - 2 f n / (f - n), w = d.
        zc = (far + near) / (far - near) * d - 2 * far * near / (far - near)
        return {"name": name, "primitive": "triangle_strip",
                "positions": [[r((x / (w / 2) - 1) * d), r((y / (h / 2) - 1) * d), r(zc), d]
                              for x, y in ((x0, y0), (x1, y0), (x0, y1), (x1, y1))],
                "colors": [color] * 4}

    blue, red, green = [0.2, 0.3, 1, 1], [1, 0.2, 0.2, 1], [0.2, 1, 0.2, 1]

    def far_pass(n, f):
        return [quad(30, 90, 10, 50, 5100, n, f, blue, "blue at 5100"),
                quad(10, 60, 20, 40, 5000, n, f, red, "red at 5000")]

    def near_pass(n, f):
        return [quad(70, 110, 5, 55, 2, n, f, green, "green at 2")]

    variants = {
        "single": ("one projection, near 0.1, far 100000, for everything",
                   far_pass(0.1, 1e5) + near_pass(0.1, 1e5)),
        "partitioned": ("two partitions: the far pass (near 1000, far 100000), a depth clear, "
                        "the near pass (near 0.1, far 1000)",
                        far_pass(1000, 1e5) + [{"clear": {"depth": 1}}] + near_pass(0.1, 1000)),
        "farpass": ("the far pass alone (near 1000, far 100000), to read its depths",
                    far_pass(1000, 1e5)),
        "expected": ("the expected image: far to near with the depth test off",
                     [dict(d, state={"depth_test": "off"})
                      for d in far_pass(0.1, 1e5) + near_pass(0.1, 1e5)]),
    }
    for name, (what, draws) in variants.items():
        write(out, f"partition_{name}.json", f"""
Lesson "depth partitions" (docs/lessons.md): unorm16 depth; a blue quad at
distance 5100 drawn first, a red one at 5000 over its left half, a green one
at 2; {what}. No camera: each vertex is projected by the generator.
Written by scripts/gen/make_lesson_scenes.py.
""", {
            "framebuffer": {"width": w, "height": h, "depth_format": "unorm16",
                            "clear_color": [0, 0, 0, 1]},
            "draws": draws,
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
                 polygon_offset, provoking_vertex, phong_gouraud, perspective_screen, painter,
                 depth_partitions):
        make(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
