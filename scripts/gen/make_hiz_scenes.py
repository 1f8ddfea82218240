#!/usr/bin/python3
"""Scenes for hierarchical Z (issue #11): writes testbench/scenes/hiz_funcs.json,
hiz_funcs_samples4.json for the bit-exact matrix: every compare function
with tiles HZ can and cannot cull, depth clears mid-frame, polygon offset,
depth range and viewport changes; single-sampled unorm24 and 4x
multisampled float32.

Usage: scripts/gen/make_hiz_scenes.py  (from the repository root; deterministic)
"""
import json
import random


def quad(z, color, state=None, x0=-1.0, y0=-1.0, x1=1.0, y1=1.0, dz=0.0):
    """A triangle strip rectangle at depth z (clip space, w = 1); dz tilts it in x."""
    d = {
        "primitive": "triangle_strip",
        "positions": [[x0, y0, z - dz, 1], [x1, y0, z + dz, 1], [x0, y1, z - dz, 1],
                      [x1, y1, z + dz, 1]],
        "colors": [color] * 4,
    }
    if state:
        d["state"] = state
    return d


def funcs_scene(samples, depth_format):
    rnd = random.Random(11)
    col = lambda: [round(rnd.random(), 3) for _ in range(3)] + [1.0]
    draws = []
    # Front to back with less: the later layers are culled where the first is.
    for z in (-0.5, -0.2, 0.1, 0.4):
        draws.append(quad(z, col(), {"depth_test": "less"}, x0=-0.9, x1=0.9 - 0.3 * (z + 0.5)))
    # lequal at the stored depth (not culled) and behind it (culled).
    draws.append(quad(-0.5, col(), {"depth_test": "lequal"}, x0=-0.7, y0=-0.7, x1=0.2, y1=0.6))
    draws.append(quad(-0.4, col(), {"depth_test": "lequal"}, x0=-0.8, y0=-0.9, x1=0.3, y1=0.9))
    # equal: at the stored depth, and at depths outside the blocks' ranges.
    draws.append(quad(-0.5, col(), {"depth_test": "equal", "depth_write": False}, x0=-0.5, x1=0.5))
    draws.append(quad(0.9, col(), {"depth_test": "equal"}, x0=-0.6, x1=0.6))
    # Tilted surfaces: ranges that straddle the blocks.
    draws.append(quad(-0.45, col(), {"depth_test": "less"}, dz=0.2))
    draws.append(quad(0.0, col(), {"depth_test": "notequal"}, x0=0.2, x1=1.0, dz=0.5))
    draws.append(quad(0.3, col(), {"depth_test": "always", "depth_write": False}, y0=0.5))
    draws.append(quad(-0.9, col(), {"depth_test": "never"}))
    # Polygon offset: pulled in front of and pushed behind the stored layer.
    draws.append(quad(-0.5, col(), {"depth_test": "less", "polygon_offset": [0, -4]}, x0=0.0))
    draws.append(quad(-0.5, col(), {"depth_test": "less", "polygon_offset": [1, 4]}, x1=0.0, dz=0.1))
    # Depth clear mid-frame to 0.25, then greater / gequal, back to front.
    draws.append({"clear": {"depth": 0.25}})
    draws.append(quad(-0.2, col(), {"depth_test": "greater"}, x0=-0.8, x1=0.5))
    draws.append(quad(-0.6, col(), {"depth_test": "greater"}))
    draws.append(quad(-0.2, col(), {"depth_test": "gequal"}, y0=-0.5, y1=0.5))
    draws.append(quad(-0.3, col(), {"depth_test": "gequal", "depth_write": False}))
    draws.append(quad(0.2, col(), {"depth_test": "greater", "depth_write": False}, x0=0.3))
    # Depth range and viewport changes.
    draws.append({"clear": {"color": [0.0, 0.0, 0.0, 1.0], "depth": 1.0}})
    draws.append(quad(0.0, col(), {"depth_test": "less", "depth_range": [0.2, 0.4]}))
    draws.append(quad(-0.8, col(), {"depth_test": "less", "depth_range": [0.5, 0.9]}))
    draws.append(quad(0.5, col(), {"depth_test": "lequal", "depth_range": [0.9, 0.1]}, dz=0.3))
    draws.append(quad(-1.0, col(), {"depth_test": "less", "viewport": [8, 8, 48, 40]}))
    draws.append(quad(-0.9, col(), {"depth_test": "less", "viewport": [8, 8, 96, 80]}))
    # Random triangles, random functions and writes.
    funcs = ["less", "lequal", "equal", "greater", "gequal", "notequal", "always", "never", "off"]
    for _ in range(40):
        tri = []
        for _ in range(3):
            tri.append([round(rnd.uniform(-1.2, 1.2), 4), round(rnd.uniform(-1.2, 1.2), 4),
                        round(rnd.uniform(-0.9, 0.9), 4), 1])
        draws.append({"primitive": "triangles", "positions": tri, "colors": [col(), col(), col()],
                      "state": {"depth_test": rnd.choice(funcs),
                                "depth_write": rnd.random() < 0.7}})
    fb = {"width": 128, "height": 96, "color_format": "rgba8", "depth_format": depth_format,
          "clear_color": [0.1, 0.1, 0.15, 1.0], "clear_depth": 1.0}
    if samples > 1:
        fb["samples"] = samples
    return {"framebuffer": fb, "draws": draws}


def write(path, scene):
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    write("testbench/scenes/hiz_funcs.json", funcs_scene(1, "unorm24"))
    write("testbench/scenes/hiz_funcs_samples4.json", funcs_scene(4, "float32"))
