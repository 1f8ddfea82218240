#!/usr/bin/python3
"""scripts/replay-check on its quick set, end to end (docs/replay.md): every
program recorded with frames, one llvmpipe reference per frame (a 320x240
image of the program's window, drawn after frame 0), a census whose counts add up to the
trace's calls with one swap per frame and no texture or shader function, and,
when build/gpusim has a `replay` command, a match share per reference. Bad command lines: one line and
exit 2.

usage: scripts/test_replay_check.py --build DIR
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, 'scripts', 'replay-check')
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print('FAIL: ' + message)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--build', required=True)
    args = parser.parse_args()

    for bad, text in ((['--frames', '0'], 'must be positive'),
                      (['--programs', 'no-such-hack'], 'unknown program no-such-hack')):
        r = subprocess.run([sys.executable, SCRIPT, '--build', args.build] + bad,
                           capture_output=True, text=True)
        check(r.returncode == 2, '%s: exit %d, expected 2' % (bad, r.returncode))
        lines = r.stderr.strip().splitlines()
        check(len(lines) == 1 and text in lines[0], '%s: stderr %r' % (bad, r.stderr))

    with tempfile.TemporaryDirectory(prefix='test_replay_check_') as out:
        r = subprocess.run([sys.executable, SCRIPT, '--build', args.build, '--out', out,
                            '--frames', '3', '--seconds', '2', '--jobs', '3'],
                           capture_output=True, text=True)
        print(r.stdout, end='')
        check(r.returncode == 0, 'replay-check exited %d: %s' % (r.returncode, r.stderr.strip()))
        with open(os.path.join(out, 'results.json')) as f:
            results = json.load(f)
        programs = results['programs']
        check([p['program'] for p in programs] == ['glxgears', 'gears', 'sierpinski3d'],
              'quick set: %s' % [p['program'] for p in programs])
        for p in programs:
            name = p['program']
            check(p['traced'] and p['frames'] >= 1, '%s: not traced: %s' % (name, p.get('note')))
            if not p['traced']:
                continue
            check(sum(p['functions'].values()) == p['calls'], '%s: census total' % name)
            check(p['textures'] == [] and p['shaders'] == [],
                  '%s: the quick set needs no textures or shaders, found %s' % (
                      name, p['textures'] + p['shaders']))
            swaps = p['functions'].get('glXSwapBuffers', 0) + p['functions'].get(
                'eglSwapBuffers', 0)
            check(swaps == p['frames'], '%s: %d swaps for %d frames' % (name, swaps, p['frames']))
            check(p.get('references') == p['frames'],
                  '%s: %s references for %d frames' % (name, p.get('references'), p['frames']))
            for i in range(p.get('references', 0)):
                path = os.path.join(out, name, 'ref_%d.png' % i)
                image = oiio.ImageInput.open(path)
                check(image is not None, '%s: cannot read' % path)
                if image is None:
                    continue
                spec = image.spec()
                pixels = numpy.asarray(image.read_image(format=oiio.UINT8))
                image.close()
                check((spec.width, spec.height) == (320, 240),
                      '%s: %dx%d, expected the 320x240 window' % (path, spec.width, spec.height))
                colours = len(numpy.unique(pixels[:, :, :3].reshape(-1, 3), axis=0))
                # Frame 0's reference is not the program's image and may be
                # blank (docs/replay.md, "References"); every later one is drawn.
                check(colours > 8 or i == 0, '%s: %d colours: a blank frame' % (path, colours))
            if 'match' in p:
                check(len(p['match']) == p['references'] - 1,
                      '%s: a share per reference from frame 1 on' % name)

    if failures:
        print('%d failures' % len(failures))
        return 1
    print('test_replay_check: all checks passed')
    return 0


if __name__ == '__main__':
    sys.exit(main())
