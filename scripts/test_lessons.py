#!/usr/bin/python3
"""Tests scripts/lessons: that it passes on the committed gallery and fails,
naming the cause, on each kind of mismatch it exists to catch.

    /usr/bin/python3 scripts/test_lessons.py [--build build]

Works on a copy of the gallery (scripts/lessons, testbench/scenes/lessons/,
docs/lessons.md, docs/images/lessons/) in a temporary directory, since
scripts/lessons finds its files next to itself; the committed files are
never touched. Checks: the copy passes (exit 0) and its renders reproduce
every committed PNG; a PNG with one pixel changed, a manifest expectation
changed, `beyond: 0` in place of 1 (the one-step differences count), a
measured number edited in the doc, a scene changed (one image and one
relation fail together), a block for a lesson the manifest does not list,
and a missing PNG each exit 1 with a line naming it; --update repairs the
doc and the PNGs; a bad manifest exits 2 with one line. Exits 1 on a
failure, naming it.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy
import OpenImageIO

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
PARTS = ["scripts/lessons", "testbench/scenes/lessons", "docs/lessons.md", "docs/images/lessons"]

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        failures.append(what)


class Copy:
    def __init__(self, root, build):
        self.root, self.build = root, build
        for part in PARTS:
            src, dst = os.path.join(REPO, part), os.path.join(root, part)
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            (shutil.copytree if os.path.isdir(src) else shutil.copy2)(src, dst)

    def path(self, rel):
        return os.path.join(self.root, rel)

    def run(self, *args):
        p = subprocess.run([sys.executable, self.path("scripts/lessons"), "--build", self.build,
                            "--out", self.path("out"), *args], capture_output=True, text=True)
        return p.returncode, p.stdout.strip().splitlines(), p.stderr

    def edit(self, rel, old, new):
        with open(self.path(rel)) as f:
            text = f.read()
        assert old in text, (rel, old)
        with open(self.path(rel), "w") as f:
            f.write(text.replace(old, new, 1))


def flip_pixel(path):
    buf = OpenImageIO.ImageBuf(path)
    px = numpy.asarray(buf.get_pixels(OpenImageIO.UINT8)).copy()
    px[3, 4, 1] ^= 1
    h, w, c = px.shape
    out = OpenImageIO.ImageBuf(OpenImageIO.ImageSpec(w, h, c, OpenImageIO.UINT8))
    out.set_pixels(OpenImageIO.ROI(0, w, 0, h, 0, 1, 0, c), px)
    out.write(path)


def same_pixels(a, b):
    pa = numpy.asarray(OpenImageIO.ImageBuf(a).get_pixels(OpenImageIO.UINT8))
    pb = numpy.asarray(OpenImageIO.ImageBuf(b).get_pixels(OpenImageIO.UINT8))
    return pa.shape == pb.shape and (pa == pb).all()


def main():
    ap = argparse.ArgumentParser(description="Tests scripts/lessons.")
    ap.add_argument("--build", default=os.path.join(REPO, "build"), help="build directory (gpusim)")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    with tempfile.TemporaryDirectory(prefix="gpusim-lessons-") as tmp:
        # The committed gallery passes, and every render equals its committed PNG.
        g = Copy(os.path.join(tmp, "pristine"), build)
        rc, out, err = g.run()
        check(rc == 0 and out[-1].endswith("0 mismatches"), f"committed gallery passes: {rc} {out} {err}")
        images = sorted(os.listdir(g.path("docs/images/lessons")))
        check(len(images) >= 7, f"{len(images)} committed PNGs")
        check(all(same_pixels(g.path(f"out/images/{n}"), g.path(f"docs/images/lessons/{n}"))
                  for n in images), "the renders reproduce every committed PNG")
        with open(g.path("testbench/scenes/lessons/lessons.json")) as f:
            n_lessons = len(json.load(f)["lessons"])

        # One pixel of one committed PNG changed.
        g = Copy(os.path.join(tmp, "pixel"), build)
        flip_pixel(g.path("docs/images/lessons/cull_cube_culled_color.png"))
        rc, out, _ = g.run()
        check(rc == 1 and "cull_cube: docs/images/lessons/cull_cube_culled_color.png: 1 pixel differs"
              in out[0] and len(out) == 2, f"a changed pixel fails: {out}")
        # --update writes the render back.
        rc, out, _ = g.run("--update")
        check(rc == 0, f"--update after a changed pixel: {out}")
        check(same_pixels(g.path("out/images/cull_cube_culled_color.png"),
                          g.path("docs/images/lessons/cull_cube_culled_color.png")),
              "--update rewrote the PNG")

        # An expectation the measurement misses (the doc's expected column changes too).
        g = Copy(os.path.join(tmp, "expect"), build)
        g.edit("testbench/scenes/lessons/lessons.json", '"expect": 16, "why"', '"expect": 15, "why"')
        rc, out, _ = g.run()
        check(rc == 1 and "needles: tiles visited, horizontal: measured 16, expected 15 (15)" in out,
              f"a missed expectation fails: {out}")
        rc, out, _ = g.run("--update")
        check(rc == 1 and "needles: tiles visited, horizontal: measured 16, expected 15 (15)" in out,
              f"--update still fails on a missed expectation: {out}")

        # differing_pixels with `beyond`: the painter's blades differ from the
        # z-buffer's only by one-step roundings, so `beyond: 1` counts none and
        # `beyond: 0` (any difference) counts them, as the plain count does.
        g = Copy(os.path.join(tmp, "beyond"), build)
        g.edit("testbench/scenes/lessons/lessons.json", '"cycle_zbuffer"], "beyond": 1',
               '"cycle_zbuffer"], "beyond": 0')
        rc, out, _ = g.run()
        prefix = "painter: blades: pixels that differ by more than one step: measured "
        hit = [line for line in out if line.startswith(prefix)]
        check(rc == 1 and len(hit) == 1 and int(hit[0][len(prefix):].split(",")[0]) > 0,
              f"beyond: 0 counts the one-step differences: {out}")

        # A quoted number edited in the doc.
        g = Copy(os.path.join(tmp, "doc"), build)
        g.edit("docs/lessons.md", "| fragments, depth-tested | 6518 |", "| fragments, depth-tested | 6517 |")
        rc, out, _ = g.run()
        check(rc == 1 and out[0].startswith("docs/lessons.md: line ") and len(out) == 2,
              f"an edited number in the doc fails: {out}")
        rc, _, _ = g.run("--update")
        with open(g.path("docs/lessons.md")) as f, open(os.path.join(REPO, "docs/lessons.md")) as c:
            check(rc == 0 and f.read() == c.read(), "--update restores the doc")

        # A scene changed: the cube's clear colour. Its image differs, and the
        # relation between the two renders fails; nothing else.
        g = Copy(os.path.join(tmp, "scene"), build)
        g.edit("testbench/scenes/lessons/cull_cube_culled.json", '"height": 96\n',
               '"height": 96,\n  "clear_color": [0, 0, 0.5, 1]\n')
        rc, out, _ = g.run()
        joined = "\n".join(out)
        check(rc == 1 and "cull_cube_culled_color.png" in joined
              and "cull_cube: pixels that differ between the two images: measured" in joined
              and all(line.startswith(("cull_cube:", "docs/lessons.md:", "lessons:")) for line in out),
              f"a changed scene fails its lesson only: {out}")

        # A block for a lesson the manifest does not list; a missing PNG.
        g = Copy(os.path.join(tmp, "stale"), build)
        with open(g.path("docs/lessons.md"), "a") as f:
            f.write("\n<!-- lesson gone begin: x -->\n<!-- lesson gone end -->\n")
        os.remove(g.path("docs/images/lessons/antialias_four_color.png"))
        rc, out, _ = g.run()
        check(rc == 1 and "docs/lessons.md: a block for lesson gone, which lessons.json does not list"
              in out and any("antialias_four_color.png is missing" in line for line in out),
              f"a stale block and a missing PNG fail: {out}")

        # Bad manifests: exit 2, one line.
        for name, text, want in (("syntax", "{", "lessons: "),
                                 ("key", '{"lessons": [{"title": "x"}]}', "missing key 'id'"),
                                 ("expr", None, "only numbers, ids and + - * / ** allowed")):
            g = Copy(os.path.join(tmp, "bad-" + name), build)
            if text is None:
                g.edit("testbench/scenes/lessons/lessons.json", '"expect": "2 * culled_frags"',
                       '"expect": "__import__(\'os\')"')
            else:
                with open(g.path("testbench/scenes/lessons/lessons.json"), "w") as f:
                    f.write(text)
            rc, out, _ = g.run()
            check(rc == 2 and len(out) == 1 and want in out[0], f"bad manifest ({name}) exits 2: {rc} {out}")
        print(f"{n_lessons} lessons")
    if failures:
        print(f"test_lessons: {len(failures)} failure(s)")
        return 1
    print("test_lessons: all passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
