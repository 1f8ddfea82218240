#!/usr/bin/python3
"""Renders a scene with the cycle model at 1 and at 4 samples per pixel
(framebuffer.samples; docs/pipeline-spec.md section 14), each checked
bit-exact against the golden model (--check), scales both frames up with
nearest-neighbour and writes them side by side, labelled "1 sample" and
"4 samples", to --out (the README's docs/images/antialias.png). The frames
are rendered into a temporary directory, removed afterwards; nothing else is
written.

usage: scripts/gen/make_antialias_image.py --out docs/images/antialias.png
           [--scene testbench/scenes/antialias_edge.json] [--build build] [--scale 6]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def render(gpusim, scene, samples, tmp):
    """Renders `scene` with framebuffer.samples = `samples` (--check); returns
    the frame as an H x W x 3 float array, row 0 at the top."""
    with open(scene) as f:
        data = json.load(f)
    data.setdefault("framebuffer", {})["samples"] = samples
    path = os.path.join(tmp, f"scene_{samples}.json")
    with open(path, "w") as f:
        json.dump(data, f)
    out = os.path.join(tmp, f"out_{samples}")
    p = subprocess.run([gpusim, "run", path, "--out", out, "--check", "--quiet"],
                       capture_output=True, text=True)
    sys.stdout.write("".join(l + "\n" for l in p.stdout.splitlines() if l.startswith("check:")))
    if p.returncode != 0:
        sys.exit(f"make_antialias_image: gpusim failed on {samples} samples:\n{p.stderr}")
    img = oiio.ImageBuf(os.path.join(out, "frame.png"))
    pixels = img.get_pixels(oiio.FLOAT)
    if pixels is None or img.has_error:
        sys.exit(f"make_antialias_image: cannot read {out}/frame.png: {img.geterror()}")
    return np.asarray(pixels)[:, :, :3]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="the PNG to write")
    ap.add_argument("--scene", default=os.path.join(ROOT, "testbench/scenes/antialias_edge.json"))
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory")
    ap.add_argument("--scale", type=int, default=6, help="nearest-neighbour magnification")
    a = ap.parse_args()
    gpusim = os.path.join(a.build, "gpusim")
    if not os.path.exists(gpusim):
        sys.exit(f"make_antialias_image: {gpusim} is missing; build first")
    with tempfile.TemporaryDirectory(prefix="antialias_") as tmp:
        frames = [(label, render(gpusim, a.scene, n, tmp))
                  for label, n in (("1 sample", 1), ("4 samples", 4))]
    h, w = frames[0][1].shape[:2]
    s = a.scale
    gap, top = 16, 44  # pixels between the panes, above them for the label
    dpi = 100
    width, height = 2 * w * s + gap, h * s + top
    fig = plt.figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor="white")
    for i, (label, img) in enumerate(frames):
        big = np.repeat(np.repeat(img, s, axis=0), s, axis=1)
        left = i * (w * s + gap)
        ax = fig.add_axes([left / width, 0, w * s / width, h * s / height])
        ax.imshow(np.clip(big, 0, 1), interpolation="nearest")
        ax.set_axis_off()
        fig.text((left + w * s / 2) / width, 1 - (top / 2) / height, label,
                 ha="center", va="center", fontsize=16)
    fig.savefig(a.out, dpi=dpi, facecolor="white")
    print(f"make_antialias_image: wrote {a.out} ({width}x{height})")


if __name__ == "__main__":
    main()
