#!/usr/bin/env python3
"""Writes the bit-exact matrix's scenes with clears in the middle of the draw
list (docs/scene-format.md, "Clears"; docs/pipeline-spec.md, section 15):
clears.json, clears_samples4.json and clears_super2.json, every kind and
place of clear single-sampled, 4x multisampled and supersampled
(sim_bitexact_test). Deterministic: no randomness. The regression scenes with
clears, compared with llvmpipe, are scripts/gen/make_regress_scenes.py's.

Writes only where told: `--out DIR` writes them into DIR, `--write-testbench`
rewrites the committed copies in testbench/scenes/. With neither, it prints
its usage and writes nothing."""
import argparse
import json
import os
import sys

TESTBENCH = os.path.normpath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testbench", "scenes"))


def ndc(x, y, z):
    return [x, y, z, 1]


def tri(p, color, name, state=None):
    d = {"name": name, "primitive": "triangles", "positions": p, "colors": [color] * len(p)}
    if state:
        d["state"] = state
    return d


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
