#!/usr/bin/python3
"""Writes the textured regression scenes (tex_*.json) of testbench/scenes/regress
(docs/pipeline-spec.md section 9c; docs/validation.md, "Texturing").
Deterministic: every texture has its own fixed seed, so running it again
gives the same files. The references come from scripts/make_references
(--only tex_).

Most scenes are exact by construction: 2D quads in raw clip coordinates
whose corners are whole pixels of a power-of-two framebuffer (clip -> window
is exact) and whose texture coordinates put every pixel centre at a known
texel position (a texel centre, or a quarter or an eighth texel from one),
never on a NEAREST boundary or a LINEAR rounding tie; the minified ones make
rho exactly 2 or 4 per 2x2 quad. The floors are perspective and are not.

usage: scripts/gen/make_texture_scenes.py [--out DIR] [--all] [--table]
"""
import argparse
import json
import math
import os
import random
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "testbench", "scenes", "regress")

# (format, channels, bits of each channel)
FORMATS = [("alpha8", 1, 8), ("luminance8", 1, 8), ("luminance_alpha8", 2, 8), ("intensity8", 1, 8),
           ("rgb8", 3, 8), ("rgba8", 4, 8), ("rgb565", 3, (5, 6, 5)), ("rgba4444", 4, 4)]
CHANNELS = {f: (n, b) for f, n, b in FORMATS}


def random_texels(fmt, w, h, seed):
    """w x h random texels of `fmt` in the scene file's notation."""
    n, bits = CHANNELS[fmt]
    bits = bits if isinstance(bits, tuple) else (bits,) * n
    rng = random.Random(seed)
    return [[rng.randrange(1 << b) for b in bits] for _ in range(w * h)]


def pattern_texels(w, h, seed):
    """rgba8: a checkerboard of 4x4-texel squares, each square's colour
    varying smoothly, with a little noise: edges for NEAREST, gradients for
    LINEAR, and mipmap levels that differ from one another."""
    rng = random.Random(seed)
    out = []
    for y in range(h):
        for x in range(w):
            on = ((x // 4) + (y // 4)) % 2
            r = int(40 + 180 * x / max(1, w - 1)) if on else 230 - int(150 * y / max(1, h - 1))
            g = int(60 + 150 * y / max(1, h - 1)) if on else 30 + int(60 * on)
            b = 200 if on else int(20 + 200 * x / max(1, w - 1))
            out.append([min(255, max(0, c + rng.randrange(-12, 13))) for c in (r, g, b)] + [255])
    return out


def clip(px, size):
    """Clip coordinate (w = 1) of window coordinate px: exact for a power-of-two size."""
    return px / (size / 2.0) - 1.0


def quad(fb_w, fb_h, x0, y0, x1, y1, s0, t0, s1, t1, **extra):
    """A triangle strip over window rectangle [x0, x1] x [y0, y1] with texture
    coordinates (s0, t0) at its lower left and (s1, t1) at its upper right."""
    d = {"primitive": "triangle_strip",
         "positions": [[clip(x0, fb_w), clip(y0, fb_h), 0], [clip(x1, fb_w), clip(y0, fb_h), 0],
                       [clip(x0, fb_w), clip(y1, fb_h), 0], [clip(x1, fb_w), clip(y1, fb_h), 0]],
         "texcoords": [[s0, t0], [s1, t0], [s0, t1], [s1, t1]]}
    d.update(extra)
    d.setdefault("state", {"depth_test": "off"})
    return d


def solid(color, n=4):
    return [list(color) for _ in range(n)]


SCENES = {}  # name -> (description, scene)


def scene(name, description):
    def register(fn):
        SCENES[name] = (description, fn)
        return fn
    return register


def tex(fmt, w, h, texels, **sampler):
    t = {"format": fmt, "width": w, "height": h}
    t.update(sampler)
    t["texels"] = texels
    return t


@scene("tex_formats", "every texture format (alpha8 .. rgba4444), 4x4 random texels at exact 4x "
       "magnification, one column each: replace with NEAREST, modulate with a constant colour, "
       "LINEAR (replace), and CLAMP_TO_EDGE with s in [-0.5, 0.5], t in [0.5, 1.5]")
def tex_formats():
    W, H = 128, 64
    textures, draws = {}, []
    for i, (fmt, _, _) in enumerate(FORMATS):
        texels = random_texels(fmt, 4, 4, 100 + i)
        textures[f"{fmt}_nearest"] = tex(fmt, 4, 4, texels, min_filter="nearest", mag_filter="nearest")
        textures[f"{fmt}_linear"] = tex(fmt, 4, 4, texels, min_filter="linear", mag_filter="linear")
        textures[f"{fmt}_clamp"] = tex(fmt, 4, 4, texels, wrap="clamp_to_edge", min_filter="nearest",
                                       mag_filter="nearest")
        x = 16 * i
        white = solid([1, 1, 1, 1])
        draws.append(quad(W, H, x, 48, x + 16, 64, 0, 0, 1, 1, texture=f"{fmt}_nearest", colors=white,
                          texture_env="replace", name=f"{fmt} nearest replace"))
        draws.append(quad(W, H, x, 32, x + 16, 48, 0, 0, 1, 1, texture=f"{fmt}_nearest",
                          colors=solid([0.8, 0.6, 1.0, 0.75]), name=f"{fmt} nearest modulate"))
        draws.append(quad(W, H, x, 16, x + 16, 32, 0, 0, 1, 1, texture=f"{fmt}_linear", colors=white,
                          texture_env="replace", name=f"{fmt} linear replace"))
        draws.append(quad(W, H, x, 0, x + 16, 16, -0.5, 0.5, 0.5, 1.5, texture=f"{fmt}_clamp",
                          colors=white, texture_env="replace", name=f"{fmt} clamp_to_edge"))
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0.1, 0.2, 0.3, 0.5]},
            "textures": textures, "draws": draws}


@scene("tex_wrap", "REPEAT and CLAMP_TO_EDGE on power-of-two and odd-sized textures: 8x8 REPEAT "
       "NEAREST at 2x over s, t in [-1, 3]; 8x8 CLAMP_TO_EDGE LINEAR at 4x over [-0.5, 1.5]; 5x3 "
       "REPEAT NEAREST at 4x from -1; 6x5 LINEAR at 4x, REPEAT in s and CLAMP_TO_EDGE in t")
def tex_wrap():
    W = H = 128
    white = solid([1, 1, 1, 1])
    textures = {
        "pot_repeat": tex("rgba8", 8, 8, random_texels("rgba8", 8, 8, 200), wrap="repeat",
                          min_filter="nearest", mag_filter="nearest"),
        "pot_clamp": tex("rgb8", 8, 8, random_texels("rgb8", 8, 8, 201), wrap="clamp_to_edge",
                         min_filter="linear", mag_filter="linear"),
        "npot_repeat": tex("rgba8", 5, 3, random_texels("rgba8", 5, 3, 202), wrap="repeat",
                           min_filter="nearest", mag_filter="nearest"),
        "npot_mixed": tex("rgb8", 6, 5, random_texels("rgb8", 6, 5, 203), wrap_s="repeat",
                          wrap_t="clamp_to_edge", min_filter="linear", mag_filter="linear"),
    }
    draws = [
        # 64 pixels over 32 texels: 2x.
        quad(W, H, 0, 64, 64, 128, -1, -1, 3, 3, texture="pot_repeat", colors=white,
             texture_env="replace", name="8x8 repeat nearest 2x"),
        # 64 pixels over 16 texels: 4x.
        quad(W, H, 64, 64, 128, 128, -0.5, -0.5, 1.5, 1.5, texture="pot_clamp", colors=white,
             texture_env="replace", name="8x8 clamp_to_edge linear 4x"),
        # 64 pixels over 16 texels of 5 and of 3: 4x; NEAREST boundaries are
        # never nearer than 1/8 texel to a pixel centre.
        quad(W, H, 0, 0, 64, 64, -1, -1, -1 + 16 / 5, -1 + 16 / 3, texture="npot_repeat", colors=white,
             texture_env="replace", name="5x3 repeat nearest 4x"),
        quad(W, H, 64, 0, 128, 64, -0.5, -0.5, -0.5 + 16 / 6, -0.5 + 16 / 5, texture="npot_mixed",
             colors=white, texture_env="replace", name="6x5 repeat/clamp_to_edge linear 4x"),
    ]
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


@scene("tex_magnify", "NEAREST and LINEAR magnification at exactly 4x (8x8 texture) and 2x (16x16) "
       "on 32x32-pixel quads, replace; bottom row the same with s, t shifted by 1/16 and 3/16 texel")
def tex_magnify():
    W, H = 128, 64
    white = solid([1, 1, 1, 1])
    textures, draws = {}, []
    col = 0
    for filt in ("nearest", "linear"):
        for n in (8, 16):
            name = f"{filt}_{n}"
            textures[name] = tex("rgba8", n, n, random_texels("rgba8", n, n, 300 + n), min_filter=filt,
                                 mag_filter=filt)
            x = 32 * col
            draws.append(quad(W, H, x, 32, x + 32, 64, 0, 0, 1, 1, texture=name, colors=white,
                              texture_env="replace", name=f"{filt} {32 // n}x"))
            ds, dt = 1 / (16 * n), 3 / (16 * n)
            draws.append(quad(W, H, x, 0, x + 32, 32, ds, dt, 1 + ds, 1 + dt, texture=name, colors=white,
                              texture_env="replace", name=f"{filt} {32 // n}x shifted"))
            col += 1
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


@scene("tex_env", "the five texture environments (rows: modulate, replace, decal, blend, add, then "
       "modulate, blend and add again with another colour) on every format (columns), 4x4 random "
       "texels at 4x NEAREST, constant fragment colours, blend's environment colour")
def tex_env():
    W = H = 128
    textures, draws = {}, []
    # Colours that are multiples of 0.2 or of 1/17 (whole unorm8 steps): a
    # constant like 0.3 or 0.7 lies within a float ulp of a rounding tie
    # (76.5, 178.5 steps), which llvmpipe's conversion to unorm8 rounds the
    # other way (untextured too; docs/validation.md, "Texturing").
    rows = [("modulate", [0.8, 0.4, 0.2, 0.6], None), ("replace", [0.8, 0.4, 0.2, 0.6], None),
            ("decal", [0.8, 0.4, 0.2, 0.6], None), ("blend", [0.8, 0.4, 0.2, 0.6], [0.2, 0.8, 0.4, 0.6]),
            ("add", [0.8, 0.4, 0.2, 0.6], None), ("modulate", [0.2, 0.6, 1.0, 0.4], None),
            ("blend", [0.2, 0.6, 1.0, 0.4], [1.0, 4 / 17, 0.0, 13 / 17]),
            ("add", [2 / 17, 0.2, 7 / 17, 0.4], None)]
    for i, (fmt, _, _) in enumerate(FORMATS):
        textures[fmt] = tex(fmt, 4, 4, random_texels(fmt, 4, 4, 400 + i), min_filter="nearest",
                            mag_filter="nearest")
    for r, (mode, color, env_color) in enumerate(rows):
        env = mode if env_color is None else {"mode": mode, "color": env_color}
        for i, (fmt, _, _) in enumerate(FORMATS):
            draws.append(quad(W, H, 16 * i, 112 - 16 * r, 16 * i + 16, 128 - 16 * r, 0, 0, 1, 1,
                              texture=fmt, colors=solid(color), texture_env=env, name=f"{fmt} {mode}"))
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


MINIFY_FILTERS = ["nearest_mipmap_nearest", "linear_mipmap_nearest", "nearest_mipmap_linear",
                  "linear_mipmap_linear", "linear"]


@scene("tex_minify", "minification at exactly 0.5x, 0.25x and 0.125x (rho 2, 4, 8 in every 2x2 "
       "quad) of a 32x32 texture with generated mipmaps, one column per minification filter "
       "(the four mipmap filters and LINEAR); s, t shifted by 1/4 texel of level 0")
def tex_minify():
    W, H = 128, 64
    white = solid([1, 1, 1, 1])
    texels = pattern_texels(32, 32, 500)
    textures, draws = {}, []
    off = 1 / 128
    for i, f in enumerate(MINIFY_FILTERS):
        textures[f] = tex("rgba8", 32, 32, texels, mipmaps="generate", min_filter=f,
                          mag_filter="linear")
    for i, f in enumerate(MINIFY_FILTERS):
        x = 24 * i
        # 0.5x: 32 texels over 16 pixels; 0.25x over 8; 0.125x over 4.
        draws.append(quad(W, H, x, 48, x + 16, 64, off, off, 1 + off, 1 + off, texture=f, colors=white,
                          texture_env="replace", name=f"{f} 0.5x"))
        draws.append(quad(W, H, x, 32, x + 8, 40, off, off, 1 + off, 1 + off, texture=f, colors=white,
                          texture_env="replace", name=f"{f} 0.25x"))
        draws.append(quad(W, H, x + 12, 32, x + 16, 36, off, off, 1 + off, 1 + off, texture=f,
                          colors=white, texture_env="replace", name=f"{f} 0.125x"))
        # REPEAT: two copies over 16x16 pixels (0.25x).
        draws.append(quad(W, H, x, 8, x + 16, 24, off, off, 2 + off, 2 + off, texture=f, colors=white,
                          texture_env="replace", name=f"{f} 0.25x repeated"))
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


def floor_draw(texture, x0, x1, repeats, name):
    return {"name": name, "primitive": "triangle_strip",
            "positions": [[x0, 0, -1], [x1, 0, -1], [x0, 0, -41], [x1, 0, -41]],
            "texcoords": [[0, 0], [repeats * (x1 - x0) / 40, 0], [0, repeats], [repeats * (x1 - x0) / 40, repeats]],
            "colors": solid([1, 1, 1, 1]), "texture": texture, "texture_env": "replace"}


FLOOR_CAMERA = {"type": "perspective", "fovy": 60, "near": 0.5, "far": 100, "eye": [0, 1.0, 0],
                "target": [0, 0.3, -5]}


@scene("tex_floor_trilinear", "perspective floors receding to 40 units, a 32x32 texture with "
       "generated mipmaps repeated 10 times: LINEAR_MIPMAP_LINEAR (left), and with lod_bias 1 "
       "and max_lod 3 (right)")
def tex_floor_trilinear():
    texels = pattern_texels(32, 32, 600)
    textures = {
        "trilinear": tex("rgba8", 32, 32, texels, mipmaps="generate", min_filter="linear_mipmap_linear",
                         mag_filter="linear"),
        "trilinear_bias": tex("rgba8", 32, 32, texels, mipmaps="generate",
                              min_filter="linear_mipmap_linear", mag_filter="linear", lod_bias=1.0,
                              max_lod=3.0),
    }
    return {"framebuffer": {"width": 128, "height": 96, "clear_color": [0, 0, 0, 1]},
            "camera": FLOOR_CAMERA, "textures": textures,
            "draws": [floor_draw("trilinear", -3.2, -0.1, 10, "linear_mipmap_linear"),
                      floor_draw("trilinear_bias", 0.1, 3.2, 10, "linear_mipmap_linear, lod_bias 1")]}


def level_colors(w, h, seed):
    """Explicit levels after level 0, each a solid colour with a little noise."""
    rng = random.Random(seed)
    palette = [[230, 40, 40], [40, 200, 40], [40, 60, 230], [230, 200, 30], [30, 210, 210],
               [210, 40, 210], [240, 240, 240], [120, 120, 120], [60, 30, 10], [10, 10, 10]]
    levels = []
    l = 1
    while w > 1 or h > 1:
        w, h = max(1, w // 2), max(1, h // 2)
        base = palette[(l - 1) % len(palette)]
        levels.append([[min(255, max(0, c + rng.randrange(-20, 21))) for c in base] + [255]
                       for _ in range(w * h)])
        l += 1
    return levels


@scene("tex_floor_mip_nearest", "perspective floors: NEAREST_MIPMAP_NEAREST on a 32x32 texture "
       "with generated mipmaps (left), and LINEAR_MIPMAP_NEAREST with explicit levels of distinct "
       "colours, lod_bias -0.5, min_lod 1 (right): where each level starts")
def tex_floor_mip_nearest():
    texels = pattern_texels(32, 32, 700)
    textures = {
        "nearest_mips": tex("rgba8", 32, 32, texels, mipmaps="generate",
                            min_filter="nearest_mipmap_nearest", mag_filter="nearest"),
        "coloured_levels": tex("rgba8", 32, 32, texels, mipmaps=level_colors(32, 32, 701),
                               min_filter="linear_mipmap_nearest", mag_filter="linear", lod_bias=-0.5,
                               min_lod=1.0),
    }
    return {"framebuffer": {"width": 128, "height": 96, "clear_color": [0, 0, 0, 1]},
            "camera": FLOOR_CAMERA, "textures": textures,
            "draws": [floor_draw("nearest_mips", -3.2, -0.1, 10, "nearest_mipmap_nearest"),
                      floor_draw("coloured_levels", 0.1, 3.2, 10, "explicit levels, lod_bias -0.5")]}


@scene("tex_rotated_flat", "a quad rotated by 30 degrees, LINEAR magnification (about 5x) of an "
       "8x8 texture; a rotated, minified quad with LINEAR_MIPMAP_LINEAR; flat-shaded textured "
       "triangles (modulate, every vertex another colour: the provoking one's colour, the "
       "coordinate still interpolated)")
def tex_rotated_flat():
    W = H = 128
    textures = {
        "mag": tex("rgba8", 8, 8, random_texels("rgba8", 8, 8, 800), min_filter="linear",
                   mag_filter="linear"),
        "min": tex("rgba8", 32, 32, pattern_texels(32, 32, 801), mipmaps="generate",
                   min_filter="linear_mipmap_linear", mag_filter="linear"),
        "flat": tex("luminance_alpha8", 4, 4, random_texels("luminance_alpha8", 4, 4, 802),
                    min_filter="nearest", mag_filter="nearest"),
    }

    def rotated(cx, cy, half, angle):
        a = math.radians(angle)
        pts = []
        for (u, v) in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
            x = cx + half * (u * math.cos(a) - v * math.sin(a))
            y = cy + half * (u * math.sin(a) + v * math.cos(a))
            pts.append([round(clip(x, W), 6), round(clip(y, H), 6), 0])
        return pts

    draws = [
        {"name": "rotated linear magnified", "primitive": "triangle_strip", "positions": rotated(36, 92, 26, 30),
         "texcoords": [[0, 0], [1, 0], [0, 1], [1, 1]], "colors": solid([1, 1, 1, 1]), "texture": "mag",
         "texture_env": "replace", "state": {"depth_test": "off"}},
        {"name": "rotated minified trilinear", "primitive": "triangle_strip",
         "positions": rotated(96, 96, 14, -20), "texcoords": [[0, 0], [1, 0], [0, 1], [1, 1]],
         "colors": solid([1, 1, 1, 1]), "texture": "min", "texture_env": "replace",
         "state": {"depth_test": "off"}},
        {"name": "flat shaded, textured", "primitive": "triangle_strip",
         # Coordinates that put no pixel centre on a NEAREST boundary.
         "positions": [[clip(x, W), clip(y, H), 0] for x, y in
                       ((8.3, 8.1), (40.2, 4.7), (12.9, 56.4), (56.6, 48.3), (60.1, 16.8), (100.4, 60.2),
                        (120.7, 8.6))],
         "texcoords": [[0.013, 0.021], [1.037, 0.009], [0.029, 1.041], [1.011, 1.017], [2.043, 0.031],
                       [2.019, 1.027], [3.007, 0.047]],
         "colors": [[1, 0.2, 0.2, 1], [0.2, 1, 0.2, 0.8], [0.2, 0.2, 1, 0.6], [1, 1, 0.2, 1],
                    [0.2, 1, 1, 0.9], [1, 0.2, 1, 0.7], [0.9, 0.9, 0.9, 1]],
         "texture": "flat", "state": {"depth_test": "off", "shading": "flat"}},
    ]
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0.05, 0.05, 0.1, 1]},
            "textures": textures, "draws": draws}


@scene("tex_points", "textured points of sizes 1 to 7 on pixel centres (a point samples at its "
       "vertex's coordinate: one texel over the whole point), NEAREST and LINEAR textures and "
       "one with mipmaps (magnified: level 0), modulate and replace")
def tex_points():
    W = H = 64
    textures = {
        "nearest": tex("rgba8", 4, 4, random_texels("rgba8", 4, 4, 900), min_filter="nearest",
                       mag_filter="nearest"),
        "linear": tex("rgb8", 4, 4, random_texels("rgb8", 4, 4, 901), min_filter="linear",
                      mag_filter="linear"),
        "mips": tex("rgba8", 8, 8, random_texels("rgba8", 8, 8, 902), mipmaps="generate",
                    min_filter="linear_mipmap_linear", mag_filter="nearest"),
    }
    rng = random.Random(903)
    draws = []
    for k, name in enumerate(textures):
        for size in range(1, 8):
            pos, tc, col = [], [], []
            for j in range(3):
                x = 4 + 9 * (size - 1) + 0.5
                y = 4 + 20 * k + 6 * j + 0.5
                pos.append([clip(x, W), clip(y, H), 0])
                tc.append([round(rng.random() * 2 - 0.5, 4), round(rng.random() * 2 - 0.5, 4)])
                col.append([round(rng.random(), 3), round(rng.random(), 3), round(rng.random(), 3), 1])
            draws.append({"name": f"{name} size {size}", "primitive": "points", "positions": pos,
                          "texcoords": tc, "colors": col, "texture": name,
                          "texture_env": "modulate" if size % 2 else "replace",
                          "state": {"depth_test": "off", "point_size": size}})
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


@scene("tex_lines", "textured lines, widths 1 and 3, x-major, y-major and diagonal, the "
       "coordinate interpolated along each line, NEAREST and LINEAR")
def tex_lines():
    W = H = 64
    textures = {
        "nearest": tex("rgba8", 8, 1, random_texels("rgba8", 8, 1, 1000), min_filter="nearest",
                       mag_filter="nearest"),
        "linear": tex("rgb8", 8, 8, random_texels("rgb8", 8, 8, 1001), min_filter="linear",
                      mag_filter="linear"),
    }
    segs = [((4.3, 6.2), (59.7, 10.6)), ((6.1, 58.4), (12.7, 14.1)), ((20.2, 20.9), (50.6, 52.3)),
            ((58.3, 30.1), (30.4, 60.2)), ((10.5, 40.5), (40.5, 40.5))]
    draws = []
    for k, name in enumerate(textures):
        pos, tc = [], []
        for (a, b) in segs:
            pos += [[clip(a[0], W), clip(a[1] + 2 * k, H), 0], [clip(b[0], W), clip(b[1] + 2 * k, H), 0]]
            tc += [[0, 0.1], [1, 0.9]]
        draws.append({"name": f"{name} lines", "primitive": "lines", "positions": pos, "texcoords": tc,
                      "colors": solid([1, 1, 1, 1], len(pos)), "texture": name, "texture_env": "replace",
                      "state": {"depth_test": "off", "line_width": 1 + 2 * k}})
    return {"framebuffer": {"width": W, "height": H, "clear_color": [0, 0, 0, 1]},
            "textures": textures, "draws": draws}


# Scenes written only with --all (docs/validation.md, "Texturing"), and why.
NOT_REGRESSION = {
    "tex_lines": "along a line the spec interpolates by the projection of the pixel centre on the "
                 "line, llvmpipe by its projection on the major axis: texels differ where the "
                 "coordinate changes fast, far beyond one step",
}


def dump(value):
    """JSON with arrays of numbers on one line (a texel, a position per line)."""
    text = json.dumps(value, indent=1)
    text = re.sub(r"\[\s+([^\[\]{}]*?)\s+\]",
                  lambda m: "[" + re.sub(r",\s+", ", ", m.group(1)) + "]", text)
    return text + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=OUT, help="directory to write into (default: testbench/scenes/regress)")
    ap.add_argument("--table", action="store_true", help="print a Markdown table of the scenes")
    ap.add_argument("--all", action="store_true",
                    help="also write the scenes of NOT_REGRESSION (measured, not regression scenes)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for name, (description, fn) in SCENES.items():
        if name in NOT_REGRESSION and not args.all and not args.table:
            continue
        if args.table:
            print(f"| `{name}` | texturing | 9c | {description} |")
            continue
        with open(os.path.join(args.out, name + ".json"), "w") as f:
            f.write(dump(fn()))


if __name__ == "__main__":
    main()
