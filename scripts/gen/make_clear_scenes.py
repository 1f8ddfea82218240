#!/usr/bin/env python3
"""Writes the scenes with clears in the middle of the draw list
(docs/scene-format.md, "Clears"; docs/pipeline-spec.md, section 15).
Deterministic: no randomness, so running it again gives the same files.

  regress/clear_depth_partition.json   the depth-partition trick: far pass,
                                       depth clear, near pass (llvmpipe reference)
  regress/clear_color_between_draws.json  a colour-only clear between draws
  clears.json, clears_samples4.json, clears_super2.json
                                       every kind of clear and placement, single
                                       sample, 4x multisampled, supersampled
                                       (the bit-exact matrix, sim_bitexact_test)

Writes only where told: `--out DIR` writes them into DIR (with a regress/
subdirectory), `--write-testbench` rewrites the committed copies in
testbench/scenes/. With neither, it prints its usage and writes nothing."""
import argparse
import json
import math
import os
import sys

TESTBENCH = os.path.normpath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testbench", "scenes"))


def r(x):
    return round(x, 5)


def perspective(fovy_deg, aspect, near, far):
    """GL's perspective matrix, as a function of an eye-space point."""
    f = 1.0 / math.tan(math.radians(fovy_deg) / 2)

    def clip(p):
        x, y, z = p
        return [r(f / aspect * x), r(f * y), r((far + near) / (near - far) * z +
                                               2 * far * near / (near - far)), r(-z)]
    return clip


def quad(clip, corners, color, name, state=None):
    """Two triangles (a strip) through four eye-space corners."""
    d = {"name": name, "primitive": "triangle_strip",
         "positions": [clip(c) for c in corners], "colors": [color] * 4}
    if state:
        d["state"] = state
    return d


def rect(x0, y0, x1, y1, z):
    return [(x0, y0, z), (x1, y0, z), (x0, y1, z), (x1, y1, z)]


def depth_partition():
    """A scene spanning eye distances 0.5 to 9000 in a unorm16 depth buffer.
    One projection (near 0.5, far 10000) cannot tell surfaces 100 apart at
    distance 6000 (they fall within one depth step), so the scene is drawn in
    two ranges, each with a projection of its own: far (100..10000) first,
    then the depth buffer is cleared and near (0.5..100) is drawn. The near
    pass's depths are larger than many of the far pass's (a surface at 50 in
    the near projection is further along its range than one at 6000 in the
    far one), so without the clear the near surfaces would fail the test."""
    w, h = 160, 120
    far = perspective(60, w / h, 100, 10000)
    near = perspective(60, w / h, 0.5, 100)
    draws = [
        quad(far, rect(-9000, -4000, 9000, 1500, -9000), [0.35, 0.3, 0.25, 1], "far: ground plate"),
        # Drawn in front-to-back order, so the back one fails where they overlap.
        quad(far, rect(-2500, -1500, 800, 2000, -5900), [0.85, 0.2, 0.15, 1], "far: red at 5900"),
        quad(far, rect(-800, -2500, 2500, 1000, -6000), [0.15, 0.3, 0.85, 1], "far: blue at 6000"),
        {"clear": {"depth": 1}},
        quad(near, rect(-30, -25, 10, 5, -50), [0.9, 0.8, 0.2, 1], "near: yellow at 50"),
        {"name": "near: green triangle from 1.5 to 3", "primitive": "triangles",
         "positions": [near((-0.9, -0.6, -1.5)), near((1.6, -0.2, -3)), near((0.2, 1.1, -2.2))],
         "colors": [[0.2, 0.8, 0.3, 1], [0.1, 0.6, 0.2, 1], [0.3, 0.9, 0.4, 1]]},
    ]
    return {"framebuffer": {"width": w, "height": h, "depth_format": "unorm16",
                            "clear_color": [0.5, 0.7, 0.9, 1]},
            "draws": draws}


def ndc(x, y, z):
    return [x, y, z, 1]


def tri(p, color, name, state=None):
    d = {"name": name, "primitive": "triangles", "positions": p, "colors": [color] * len(p)}
    if state:
        d["state"] = state
    return d


def color_between_draws():
    """A colour-only clear between draws: the first triangle's colour is
    cleared, its depth is not, so the full-screen quad drawn after it fails
    the depth test there and the clear colour shows the triangle's shape; a
    blended triangle then mixes with the cleared colour."""
    return {
        "framebuffer": {"width": 128, "height": 128, "clear_color": [0, 0, 0, 1]},
        "draws": [
            tri([ndc(-0.9, -0.8, -0.5), ndc(0.4, -0.7, -0.4), ndc(-0.5, 0.8, -0.6)],
                [1, 1, 1, 1], "hidden: its depth stays, its colour is cleared"),
            {"clear": {"color": [0.2, 0.4, 0.6, 1]}},
            {"name": "full-screen quad behind the hidden triangle", "primitive": "triangle_strip",
             "positions": [ndc(-1, -1, 0), ndc(1, -1, 0), ndc(-1, 1, 0), ndc(1, 1, 0)],
             "colors": [[0.9, 0.5, 0.1, 1]] * 4},
            tri([ndc(-0.2, -0.95, -0.9), ndc(0.95, 0.1, -0.9), ndc(-0.6, 0.6, -0.9)],
                [0.1, 0.9, 0.3, 0.5], "translucent, over both",
                {"blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}),
        ],
    }


def every_clear(framebuffer):
    """Every kind and place of clear: before the first draw, between draws
    (colour and depth, depth only, colour only, two in a row), after a draw
    with every colour channel masked off, and after the last draw (depth
    only: the output's depth is its value). Lines and points too, since every
    raster path writes through the cleared tiles."""
    strip = [ndc(-1, -1, 0.2), ndc(1, -1, 0.6), ndc(-1, 1, -0.2), ndc(1, 1, 0.4)]
    return {
        "framebuffer": framebuffer,
        "draws": [
            {"clear": {"color": [0.3, 0.1, 0.2, 1], "depth": 0.9}},
            {"name": "background strip", "primitive": "triangle_strip", "positions": strip,
             "colors": [[0.2, 0.2, 0.6, 1], [0.6, 0.2, 0.2, 1], [0.2, 0.6, 0.2, 1],
                        [0.6, 0.6, 0.2, 1]]},
            tri([ndc(-0.8, -0.8, -0.3), ndc(0.7, -0.5, 0.1), ndc(-0.3, 0.9, -0.1)],
                [0.9, 0.9, 0.9, 1], "front triangle"),
            {"clear": {"depth": 0.75}},
            tri([ndc(-0.95, 0.1, 0.45), ndc(0.9, -0.9, 0.45), ndc(0.6, 0.95, 0.45)],
                [0.95, 0.6, 0.1, 1], "after the depth clear: passes at 0.45 < 0.75, not 0.5"),
            {"clear": {"color": [0.05, 0.25, 0.3, 1]}},
            {"clear": {"depth": 0.6}},
            tri([ndc(-0.9, -0.9, -0.2), ndc(0.3, -0.9, -0.2), ndc(-0.4, 0.7, -0.2)],
                [0.5, 0.5, 0.5, 1], "depth only (colour masked off)",
                {"color_mask": [False, False, False, False]}),
            {"clear": {"color": [0.1, 0.1, 0.1, 1]}},
            {"name": "lines", "primitive": "line_loop",
             "positions": [ndc(-0.7, -0.6, -0.5), ndc(0.8, -0.4, -0.3), ndc(0.1, 0.85, -0.1)],
             "colors": [[1, 0.3, 0.3, 1], [0.3, 1, 0.3, 1], [0.3, 0.3, 1, 1]],
             "state": {"line_width": 2}},
            {"name": "points", "primitive": "points",
             "positions": [ndc(-0.5, 0.5, 0.1), ndc(0.5, 0.5, 0.7), ndc(0.0, -0.2, 0.0)],
             "colors": [[1, 1, 0, 1], [0, 1, 1, 1], [1, 0, 1, 1]],
             "state": {"point_size": 5}},
            tri([ndc(-0.95, -0.95, 0.0), ndc(0.95, -0.5, 0.0), ndc(0.0, 0.95, 0.0)],
                [0.2, 0.5, 1.0, 0.6], "blended over the cleared colour, not over the masked one",
                {"blend": {"src": "src_alpha", "dst": "one_minus_src_alpha"}}),
            {"clear": {"depth": 0.125}},
        ],
    }


def scenes():
    return {
        "regress/clear_depth_partition.json": depth_partition(),
        "regress/clear_color_between_draws.json": color_between_draws(),
        "clears.json": every_clear({"width": 96, "height": 64, "depth_format": "unorm16"}),
        "clears_samples4.json": every_clear({"width": 80, "height": 56, "samples": 4}),
        "clears_super2.json": every_clear({"width": 48, "height": 40, "supersample": 2,
                                           "samples": 2, "color_format": "rgba16f",
                                           "depth_format": "float32"}),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", help="write the scenes into this directory")
    ap.add_argument("--write-testbench", action="store_true",
                    help="rewrite the committed scenes in testbench/scenes/")
    args = ap.parse_args(argv)
    if not args.out and not args.write_testbench:
        ap.print_usage()
        return 2
    out = TESTBENCH if args.write_testbench else args.out
    for name, scene in scenes().items():
        path = os.path.join(out, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
