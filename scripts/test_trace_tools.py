#!/usr/bin/python3
"""Tests scripts/trace_plots and scripts/report on real traces.

    /usr/bin/python3 scripts/test_trace_tools.py [--gpusim build/gpusim] [--keep DIR]

Records a small scene with `gpusim run --trace`, runs both scripts on it and
checks: every PNG opens (OpenImageIO) with a sensible size and is not blank;
the heat-maps' numbers (tiles.json) equal sums computed here, independently,
from the raw transactions.bin and fragments.bin (struct, not the scripts'
reader); the HTML embeds every image and holds the summary's bottleneck
line; filtered traces plot; bad input exits 2 with one line. Exits 1 on a
failure, naming it.
"""

import argparse
import base64
import html
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SCENE = os.path.join(REPO, "testbench", "scenes", "shared_edges.json")
PLOTS = ["utilization.png", "fifo_occupancy.png", "tiles_owner.png", "tiles_cycles.png", "tiles_overdraw.png"]

failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        failures.append(what)
    return cond


def run(cmd, **kw):
    env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, **kw)


def must(cmd):
    r = run(cmd)
    if r.returncode != 0:
        print(f"FAIL  {' '.join(cmd)} exited {r.returncode}:\n{r.stderr}", file=sys.stderr)
        sys.exit(1)
    return r


# -- independent readers of the raw files (docs/traces.md) -------------------


def read_raw(path, magic, fmt):
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == magic, f"{path}: magic {data[:8]!r}"
    version, size = struct.unpack_from("<II", data, 8)
    assert version == 1 and size == struct.calcsize(fmt) == 48, f"{path}: version {version} size {size}"
    return list(struct.iter_unpack(fmt, data[16:]))


TX_FMT = "<QQqqIHBBhhI"      # cycle_in cycle_out prim_first prim_last draw stage kind prim_kind tile_x tile_y count
FR_FMT = "<QqHHBBBBff4f"     # cycle prim x y stage unit outcome reserved depth old_depth value[4]


def stage_roles(manifest, stats):
    """The stages' roles as the trace records them, read here without the
    scripts' code (and in the manifest's netlist order, where trace_plots
    follows the FIFOs): the stages that make fragment records form two sites
    (manifest `fragments`), the first in pipeline order tests fragments
    (fragments.bin stage 0), the second writes them (stage 1), each
    {"kind", "code", "names"}; "memory": the names of the stages that work on
    stamp batches and are clients of the memory (stats.json)."""
    sites = {}
    for s in manifest["stages"]:
        if s["fragments"]:
            sites.setdefault(s["fragments"], []).append(s)
    assert len(sites) == 2, f"manifest: fragment sites {list(sites)}"
    tester, writer = ({"kind": stages[0]["kind"], "code": code, "names": {x["name"] for x in stages}}
                      for code, stages in enumerate(sites.values()))
    clients = stats["timing"]["memory"]["clients"]
    memory = {s["name"] for s in manifest["stages"] if s["item"] == "stamp batch" and s["name"] in clients}
    return {"tester": tester, "writer": writer, "memory": memory}


def png_ok(path, name, min_w=200, min_h=150):
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if not check(inp is not None, f"{name}: opens as an image"):
        return
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT)
    inp.close()
    check(spec.width >= min_w and spec.height >= min_h, f"{name}: {spec.width}x{spec.height} is a sensible size")
    px = np.asarray(px).reshape(spec.height, spec.width, spec.nchannels)
    check(float(px[..., :3].std()) > 0.01, f"{name}: not blank (pixel std {float(px[..., :3].std()):.3f})")


def check_plots(trace, plots, manifest, label):
    for p in PLOTS:
        path = os.path.join(plots, p)
        if check(os.path.isfile(path) and os.path.getsize(path) > 1000, f"{label}: {p} written"):
            png_ok(path, f"{label}: {p}")
    leftovers = [n for n in os.listdir(plots) if ".tmp" in n]
    check(not leftovers, f"{label}: no temporary files left ({leftovers})")


def check_tiles(trace, plots, manifest, stats):
    fb = manifest["framebuffer"]
    nx, ny, ts, units = fb["tiles_x"], fb["tiles_y"], fb["tile_size"], manifest["units"]
    tiles = json.load(open(os.path.join(plots, "tiles.json")))
    tx = read_raw(os.path.join(trace, "transactions.bin"), b"GPUSIMTX", TX_FMT)
    fr = read_raw(os.path.join(trace, "fragments.bin"), b"GPUSIMFR", FR_FMT)
    stage_unit = [s["unit"] for s in manifest["stages"]]
    # shared_edges.json draws filled triangles only: prim_kind 3 on every work
    # item, 0 on control tokens.
    check(all(r[7] == (3 if r[6] == 0 else 0) for r in tx),
          "transactions: prim_kind is 3 (triangle) for work items, 0 for control tokens")
    check(all(d.get("primitive", "").startswith("triangle") and d.get("polygon_mode") == "fill"
              for d in manifest["draws"]), "manifest: every draw names its triangle type and fill")

    # Owner: the units seen per tile, and the rule tile_owner = (tx + ty) % units.
    seen = {}
    cycles = np.zeros((ny, nx), dtype=np.int64)
    for r in tx:
        stage, x, y = r[5], r[8], r[9]
        if stage_unit[stage] is None or x < 0 or y < 0:
            continue
        seen.setdefault((y, x), set()).add(stage_unit[stage])
        cycles[y, x] += r[1] - r[0]
    owner = np.array(tiles["owner"])
    check(owner.shape == (ny, nx), f"tiles.json: owner is {ny} rows of {nx} tiles")
    check(all(len(u) == 1 for u in seen.values()), "transactions: every tile is handled by one unit only")
    ok = all((owner[y, x] == next(iter(seen[(y, x)]))) if (y, x) in seen else owner[y, x] == -1
             for y in range(ny) for x in range(nx))
    check(ok, "tiles_owner: equals the units seen per tile in transactions.bin (-1 where none)")
    rule = np.add.outer(np.arange(ny), np.arange(nx)) % units
    check(bool(np.all(owner[owner >= 0] == rule[owner >= 0])), "tiles_owner: equals (tx + ty) % units")
    check(len(seen) > 0, f"tiles_owner: {len(seen)} tiles with work")

    check(np.array_equal(np.array(tiles["cycles"]), cycles),
          f"tiles_cycles: equals sum(cycle_out - cycle_in) of unit-stage records per tile (total {int(cycles.sum())})")

    # Overdraw: fragments per tile at the site that tests them.
    tester = stage_roles(manifest, stats)["tester"]
    frag = np.zeros((ny, nx), dtype=np.int64)
    n_dt = 0
    for r in fr:
        if r[4] == tester["code"]:
            n_dt += 1
            frag[r[3] // ts, r[2] // ts] += 1
    check(tiles["overdraw_source"] == "fragments", "tiles_overdraw: from fragments.bin")
    check(np.array_equal(np.array(tiles[f"{tester['kind']}_fragments"]), frag),
          "tiles_overdraw: per-tile depth-test fragment counts equal fragments.bin's")
    pixels = np.array(tiles["pixels"])
    check(int(pixels.sum()) == fb["width"] * fb["height"], "tiles.json: tile pixels sum to the frame's")
    od_total = float((np.array(tiles["overdraw"]) * pixels).sum())
    check(abs(od_total - n_dt) < 1e-3 * max(1, n_dt),
          f"tiles_overdraw: overdraw x pixels sums to the {n_dt} depth-test fragments ({od_total:.1f})")
    gen = sum(v.get("fragments_in", 0) for k, v in stats["timing"]["stages"].items() if k in tester["names"])
    check(n_dt == gen and n_dt > 0, f"fragments.bin: {n_dt} depth-test fragments = stats.json depth tests' "
                                     f"fragments_in ({gen})")


def raw_vcd_wires(path, cycle_ps):
    """signals.vcd read here, independently of the scripts' reader: {(scope,
    name): [(cycle, value), ...]}, times divided by the period in $timescale
    units (docs/traces.md)."""
    units = {"fs": 1, "ps": 10**3, "ns": 10**6, "us": 10**9, "ms": 10**12, "s": 10**15}
    with open(path) as f:
        text = f.read()
    head, body = text.split("$enddefinitions $end", 1)
    ts = re.search(r"\$timescale\s+(\d+)\s*(\w+)\s+\$end", head)
    per_cycle = cycle_ps * 1000 // (int(ts.group(1)) * units[ts.group(2)])
    ids, scope = {}, []
    for tok in re.findall(r"\$(scope|upscope|var)([^$]*)\$end", head):
        words = tok[1].split()
        if tok[0] == "scope":
            scope.append(words[1])
        elif tok[0] == "upscope":
            scope.pop()
        else:
            ids[words[2]] = (".".join(scope), words[3])
    wires, t = {key: [] for key in ids.values()}, 0
    for tok in body.split():
        if tok[0] == "#":
            t = int(tok[1:]) // per_cycle
        elif tok[0] in "01" and tok[1:] in ids:
            wires[ids[tok[1:]]].append((t, int(tok[0])))
    return wires


def time_at_one(changes, a, b):
    """Cycles in [a, b) a 1-bit wire given as [(cycle, value)] holds 1."""
    total = 0
    for k, (t, v) in enumerate(changes):
        end = changes[k + 1][0] if k + 1 < len(changes) else b
        if v == 1:
            total += max(0, min(end, b) - max(t, a))
    return total


def check_tile_split(trace, plots, manifest, stats):
    """Issue #16 item 9: tiles_cycles splits each tile's cycles into work,
    waiting on memory and stalled. Recomputed here from the raw files: an
    item's stalled cycles are its stage's `stalled` wire over [cycle_in,
    cycle_out); a depth test's or ROP's wait on memory is its busy cycles
    beyond ii x stamps (ii from the configuration), which over every item
    (clear and end_of_frame tokens included, ii each) must be the stages'
    memory_stall_cycles in stats.json."""
    tiles = json.load(open(os.path.join(plots, "tiles.json")))
    fb = manifest["framebuffer"]
    nx, ny = fb["tiles_x"], fb["tiles_y"]
    wires = raw_vcd_wires(os.path.join(trace, "signals.vcd"), manifest["cycle_ps"])
    stages = manifest["stages"]
    ii = {k: v["ii"] for k, v in manifest["config"]["stages"].items()}
    waits = stage_roles(manifest, stats)["memory"]
    stalled = np.zeros((ny, nx), dtype=np.int64)
    memory = np.zeros((ny, nx), dtype=np.int64)
    waited = {}
    for r in read_raw(os.path.join(trace, "transactions.bin"), b"GPUSIMTX", TX_FMT):
        s = stages[r[5]]
        if s["unit"] is None:
            continue
        scope = f"gpu.unit_{s['unit']}.{s['name']}"
        busy = time_at_one(wires[(scope, s["name"] + "_busy")], r[0], r[1])
        stall = time_at_one(wires[(scope, s["name"] + "_stalled")], r[0], r[1])
        wait = 0
        if s["name"] in waits:
            wait = max(0, busy - ii[s["kind"]] * (max(r[10], 1) if r[6] == 0 else 1))
            waited[s["name"]] = waited.get(s["name"], 0) + wait
        if r[8] >= 0 and r[9] >= 0:
            stalled[r[9], r[8]] += stall
            memory[r[9], r[8]] += wait if r[6] == 0 else 0
    check(np.array_equal(np.array(tiles["stalled_cycles"]), stalled),
          f"tiles_cycles: stalled cycles per tile equal signals.vcd's over each item (total {int(stalled.sum())})")
    check(np.array_equal(np.array(tiles["memory_wait_cycles"]), memory),
          f"tiles_cycles: memory wait per tile equals busy beyond ii x stamps (total {int(memory.sum())})")
    st = stats["timing"]["stages"]
    want = {k: int(v["memory_stall_cycles"]) for k, v in st.items() if "memory_stall_cycles" in v}
    check(waited == want and sum(want.values()) > 0,
          f"tiles_cycles: busy beyond ii x stamps over every item is stats.json's memory_stall_cycles per stage "
          f"({sum(waited.values())} vs {sum(want.values())})")
    check(bool((np.array(tiles["cycles"]) >= stalled + memory).all()), "tiles_cycles: work = cycles - memory - stalled >= 0")


def check_vcd_reader(trace, stats):
    """The plots' VCD reader: each stage's busy / stalled / starved time equals stats.json's."""
    sys.dont_write_bytecode = True
    sys.path.insert(0, HERE)
    import gpusim_trace as gt
    t = gt.open_trace(trace)
    st = stats["timing"]["stages"]
    bad = []
    for s in t.stages:
        got = [float(t.vcd().stage_state(s["name"], x).integrate(np.array([0, t.cycles]))[0])
               for x in ("busy", "stalled", "starved")]
        want = [float(st[s["name"]][k]) for k in ("busy_cycles", "stalled_cycles", "starved_cycles")]
        if got != want:
            bad.append(f"{s['name']} {got} != {want}")
    check(not bad, f"signals.vcd read by gpusim_trace: busy/stalled/starved cycles of {len(t.stages)} stages "
                   f"equal stats.json's" + (f" {bad[:2]}" if bad else ""))
    fifos = stats["timing"]["fifos"]
    bad = [f["name"] for f in t.fifos
           if abs(t.vcd().fifo(f["name"]).integrate(np.array([0, t.cycles]))[0] / t.cycles
                  - fifos[f["name"]]["mean_occupancy"]) > 1e-9 * max(1, fifos[f["name"]]["mean_occupancy"])]
    check(not bad, "signals.vcd read by gpusim_trace: FIFO mean occupancies equal stats.json's"
          + (f" {bad[:3]}" if bad else ""))


def check_gtkwave(tmp, trace):
    """GTKWave's own VCD parser (vcd2fst, Debian's gtkwave) reads signals.vcd,
    and converting its FST back (fst2vcd) gives the same signals, timestamps
    and value changes: the file opens in GTKWave as written."""
    vcd2fst, fst2vcd = shutil.which("vcd2fst"), shutil.which("fst2vcd")
    if not check(bool(vcd2fst and fst2vcd), "gtkwave: vcd2fst and fst2vcd installed (scripts/setup installs gtkwave)"):
        return
    src = os.path.join(trace, "signals.vcd")
    fst = os.path.join(tmp, "signals.fst")
    r = run([vcd2fst, src, fst])
    if not check(r.returncode == 0 and os.path.isfile(fst), f"gtkwave: vcd2fst reads signals.vcd ({r.stderr.strip()[:200]!r})"):
        return
    back = run([fst2vcd, fst]).stdout

    def body(text):
        """Declared signal names (with scope) and the value-change section,
        without the header lines GTKWave rewrites ($date, $version, ...)."""
        names, changes, scope, in_body = [], [], [], False
        for line in text.splitlines():
            tok = line.split()
            if not tok:
                continue
            if tok[0] == "$scope":
                scope.append(tok[2])
            elif tok[0] == "$upscope":
                scope.pop()
            elif tok[0] == "$var":
                names.append(".".join(scope + [tok[4]]) + f"[{tok[2]}]")
            elif tok[0] == "$enddefinitions":
                in_body = True
            elif in_body and tok[0] not in ("$dumpvars", "$end"):
                changes.append(tok[0])
        return names, changes

    n_ours, c_ours = body(open(src).read())
    n_back, c_back = body(back)
    check(n_ours == n_back and len(n_ours) > 0, f"gtkwave: the same {len(n_ours)} signals after the FST round trip")
    ts = lambda c: [x for x in c if x.startswith("#")]
    check(ts(c_ours) == ts(c_back), f"gtkwave: the same {len(ts(c_ours))} timestamps after the FST round trip")
    check(len(c_ours) == len(c_back), f"gtkwave: the same number of value changes ({len(c_ours)} against {len(c_back)})")


def expected_vcd_order(manifest):
    """signals.vcd's signals as docs/traces.md lays them out, derived from the
    manifest's tables: per group (front end, unit 0, ...), in stage order,
    each FIFO a stage reads, then the stage's three wires; last the memory's
    busy wire per channel (the configuration's memory.channels)."""
    order = []
    for s in manifest["stages"]:
        group = "front_end" if s["unit"] is None else f"unit_{s['unit']}"
        for f in manifest["fifos"]:
            if f["reader"] == s["name"]:
                width = max(1, int(f["depth"]).bit_length())
                order.append(f"gpu.{group}.{f['name']}[{width - 1}:0]")
        order += [f"gpu.{group}.{s['name']}.{s['name']}_{w}" for w in ("busy", "stalled", "starved")]
    order += [f"gpu.memory.channel_{c}_busy" for c in range(manifest["config"]["memory"]["channels"])]
    return order


def xwd_to_png(xwd, png):
    """Xvfb's -fbdir framebuffer (an XWD image, 32-bit TrueColor) to a PNG;
    returns the pixels (height, width, 3)."""
    import OpenImageIO as oiio
    with open(xwd, "rb") as f:
        data = f.read()
    h = struct.unpack(">25I", data[:100])
    header, width, height, lsb_first, bpp, per_line, ncolors = h[0], h[4], h[5], h[7] == 0, h[11], h[12], h[19]
    assert bpp == 32, f"{xwd}: {bpp} bits per pixel"
    px = np.frombuffer(data, np.uint8, height * per_line, header + 12 * ncolors)
    px = px.reshape(height, per_line)[:, :width * 4].reshape(height, width, 4)
    rgb = np.ascontiguousarray(px[..., [2, 1, 0]] if lsb_first else px[..., [1, 2, 3]])
    out = oiio.ImageOutput.create(png)
    out.open(png, oiio.ImageSpec(width, height, 3, "uint8"))
    out.write_image(rgb)
    out.close()
    return rgb


GTKWAVE_TCL = r"""
puts "FACS [gtkwave::getNumFacs]"
puts "MAXTIME [gtkwave::getMaxTime] [gtkwave::getTimeDimension]"
foreach s [gtkwave::getDisplayedSignals] { puts "SIGNAL $s [gtkwave::getTraceFlagsFromName $s]" }
for {set i 0} {$i < [gtkwave::getTotalNumTraces]} {incr i} { puts "TRACE [gtkwave::getTraceNameFromIndex $i]" }
gtkwave::setMarker @MARKER@
puts "VALUE [gtkwave::getTraceValueAtMarkerFromName {@FIFO@}]"
gtkwave::/Time/Zoom/Zoom_Full
puts "DONE"
"""


def check_gtkwave_view(tmp, gpusim, scene, artifacts):
    """Issue #16 item 9: GTKWave itself, under Xvfb, opens a 300 MHz trace's
    signals.vcd with signals.gtkw. Its Tcl interface reports the time axis in
    picoseconds ending at cycles x 3333, the displayed signals in the
    manifest's pipeline order, grouped per unit, with names unique on their
    own, FIFOs in decimal (TR_DEC) and a full-ish FIFO's value as decimal
    text; the screenshot (kept in ARTIFACTS/gtkwave.png) shows waves."""
    gtkwave, xvfb = shutil.which("gtkwave"), shutil.which("Xvfb")
    if not (gtkwave and xvfb):
        print(f"\n*** SKIPPED: GTKWave view check: {'gtkwave' if not gtkwave else 'Xvfb'} is not installed "
              f"(scripts/setup installs gtkwave and xvfb) ***\n", file=sys.stderr)
        return
    sys.dont_write_bytecode = True
    sys.path.insert(0, HERE)
    import gpusim_trace as gt
    config = os.path.join(tmp, "clock300.json")
    with open(config, "w") as f:
        json.dump({"clock_mhz": 300}, f)
    trace = os.path.join(tmp, "trace300")
    must([gpusim, "run", scene, "--config", config, "--out", os.path.join(tmp, "out300"), "--trace", trace])
    manifest = json.load(open(os.path.join(trace, "manifest.json")))
    cycles, period = manifest["cycles"], manifest["cycle_ps"]
    check(period == 3333, f"300 MHz: cycle_ps {period}")
    # The time at which some FIFO holds the most (10..16 reads differently in
    # hex), from the raw VCD times (picoseconds).
    raw = gt.read_vcd(os.path.join(trace, "signals.vcd"))
    fifo, marker, level = None, 0, -1
    for sig in raw.signals:
        if sig.width > 1 and len(sig.values) and int(sig.values.max()) > level:
            k = int(np.argmax(sig.values))
            fifo, marker, level = sig, int(sig.times[k]), int(sig.values[k])
    check(level >= 10, f"300 MHz: FIFO {fifo.name} holds {level} at #{marker}")
    fifo_path = f"{fifo.path}[{fifo.width - 1}:0]"
    script = os.path.join(tmp, "gtkwave_check.tcl")
    with open(script, "w") as f:
        f.write(GTKWAVE_TCL.replace("@MARKER@", str(marker)).replace("@FIFO@", fifo_path))

    fbdir = os.path.join(tmp, "xvfb")
    os.makedirs(fbdir, exist_ok=True)
    rfd, wfd = os.pipe()
    xv = subprocess.Popen([xvfb, "-displayfd", str(wfd), "-screen", "0", "1400x900x24", "-fbdir", fbdir,
                           "-nolisten", "tcp"], pass_fds=(wfd,), stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)
    os.close(wfd)
    gw = None
    try:
        display = b""
        while not display.endswith(b"\n"):  # Xvfb writes "N\n" once it is ready
            chunk = os.read(rfd, 16)
            if not chunk:
                break
            display += chunk
        display = display.decode().strip()
        if not check(display.isdigit(), f"gtkwave: Xvfb started (display {display!r})"):
            return
        env = dict(os.environ, DISPLAY=":" + display)
        gw = subprocess.Popen([gtkwave, "-S", script, "signals.vcd", "signals.gtkw"], cwd=trace, env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines = []
        deadline = time.monotonic() + 60
        for line in gw.stdout:
            lines.append(line.rstrip("\n"))
            if line.startswith("DONE") or time.monotonic() > deadline:
                break
        if not check(any(x.startswith("DONE") for x in lines), "gtkwave: ran the Tcl script"
                     + ("" if lines else "") + f" ({' | '.join(lines[-5:])!r})"):
            return
        time.sleep(2)  # let it draw the zoomed-out waves
        os.makedirs(artifacts, exist_ok=True)
        shot = os.path.join(artifacts, "gtkwave.png")
        px = xwd_to_png(os.path.join(fbdir, "Xvfb_screen0"), shot)
    finally:
        if gw:
            gw.kill()
            gw.wait()
        xv.kill()
        xv.wait()
        os.close(rfd)

    got = {k: [x.split(" ", 1)[1] for x in lines if x.startswith(k + " ")] for k in
           ("FACS", "MAXTIME", "SIGNAL", "TRACE", "VALUE")}
    want = expected_vcd_order(manifest)
    check(got["FACS"] == [str(len(want))], f"gtkwave: {got['FACS']} facilities, {len(want)} expected")
    check(got["MAXTIME"] == [f"{cycles * period} p"],
          f"gtkwave: the time axis ends at {got['MAXTIME']} = {cycles} cycles x {period} ps")
    shown = [x.rsplit(" ", 1) for x in got["SIGNAL"]]
    check([n for n, _ in shown] == want,
          f"gtkwave: displays the {len(want)} signals in pipeline order, grouped per unit "
          f"(first differences: {[(a, b) for a, b in zip([n for n, _ in shown], want) if a != b][:2]})")
    flags = {n: int(f) for n, f in shown}
    TR_HEX, TR_DEC, TR_BIN = 0x2, 0x4, 0x8
    check(all((flags[n] & TR_DEC and not flags[n] & TR_HEX) if n.endswith(":0]") else flags[n] & TR_BIN
              for n in flags) and len(flags) == len(want),
          "gtkwave: FIFO occupancies shown in decimal, stage wires in binary")
    check(got["VALUE"] == [str(level)], f"gtkwave: {fifo_path} reads {got['VALUE']} at #{marker} "
                                        f"(decimal {level}, not hex {level:x})")
    groups = ["front end"] + [f"unit {u}" for u in range(manifest["units"])] + ["memory"]
    names = got["TRACE"]
    check([n for n in names if n in groups] == [g for g in groups for _ in (0, 1)],
          f"gtkwave: one group per unit, in order ({[n for n in names if n in groups][:4]}...)")
    leaves = [n for n in names if n not in groups]
    check(len(leaves) == len(want) and len(set(leaves)) == len(leaves),
          f"gtkwave: the {len(leaves)} displayed names are unique on their own")
    # The screenshot: GTKWave's window, not a blank screen, with its green
    # waveforms (pure green pixels) across the wave pane.
    green = (px[..., 1] > 200) & (px[..., 0] < 60) & (px[..., 2] < 60)
    check(px.shape[:2] == (900, 1400) and float(px.std()) > 20 and int(green.sum()) > 5000,
          f"gtkwave: screenshot {shot} shows waveforms ({int(green.sum())} green pixels)")


def check_report(trace, out_html, summary):
    text = open(out_html, encoding="utf-8").read()
    imgs = dict(re.findall(r'<img id="([^"]+)"[^>]*? src="data:image/png;base64,([^"]+)"', text))
    for name in ["frame.png", "depth.png"] + PLOTS:
        if check(name in imgs, f"report: embeds {name}"):
            data = base64.b64decode(imgs[name])
            check(data[:8] == b"\x89PNG\r\n\x1a\n", f"report: {name} is a PNG")
            tmp = os.path.join(os.path.dirname(out_html), "check_" + name)
            with open(tmp, "wb") as f:
                f.write(data)
            if name in ("frame.png", "depth.png"):
                import OpenImageIO as oiio
                inp = oiio.ImageInput.open(tmp)
                spec = inp.spec()
                inp.close()
                m = json.load(open(os.path.join(trace, "manifest.json")))["framebuffer"]
                check((spec.width, spec.height) == (m["width"], m["height"]),
                      f"report: {name} is {spec.width}x{spec.height}, the frame's size")
            else:
                png_ok(tmp, f"report: {name}")
    lines = [ln.strip() for ln in summary.splitlines() if "bottleneck" in ln.lower()]
    if check(bool(lines), "summary: has a bottleneck line"):
        check(html.escape(lines[0]) in text, f"report: holds the summary's bottleneck line: {lines[0]!r}")
    # The page names the scene relative to the repository (item 10 below).
    first = summary.strip().splitlines()[0].replace(SCENE, os.path.relpath(SCENE, REPO))
    check(text.count('<pre class="summary">') == 1 and html.escape(first) in text,
          f"report: holds the summary text ({first!r})")
    check("shared_edges.json" in text, "report: names the scene")
    # Issue #16 item 10: the scene was given to gpusim run as an absolute
    # path inside the checkout; the page shows it relative to the repository.
    check(REPO not in text and "testbench/scenes/shared_edges.json" in text,
          f"report: no absolute path of the checkout ({REPO}); the scene shown relative to it")


# Appended to a copy of the report: measures, after layout, every element
# whose text must be readable in full, into an attribute --dump-dom shows.
CLIP_PROBE = """<script>
const rows = [];
for (const el of document.querySelectorAll("pre.summary, div.bottleneck, table.kv td, figcaption")) {
  rows.push(`${el.tagName.toLowerCase()}.${el.className}|${el.scrollWidth}|${el.clientWidth}`);
}
document.body.setAttribute("data-widths", rows.join(";"));
</script>"""


def chromium_widths(chromium, tmp, text, name, extra_css=""):
    """[(element, scrollWidth, clientWidth)] of the page `text` laid out by
    headless Chromium in an 1100-pixel-wide window."""
    probe = os.path.join(tmp, name)
    with open(probe, "w", encoding="utf-8") as f:
        f.write(text.replace("</body>", f"<style>{extra_css}</style>{CLIP_PROBE}</body>"))
    r = run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--window-size=1100,1150",
             "--virtual-time-budget=3000", "--dump-dom", "file://" + probe])
    m = re.search(r'data-widths="([^"]*)"', r.stdout)
    if not m:
        return None
    return [(e, int(a), int(b)) for e, a, b in (x.split("|") for x in html.unescape(m.group(1)).split(";") if x)]


def check_report_in_chromium(tmp, out_html, artifacts):
    """Issue #16 item 9: the report in a real browser. Headless Chromium lays
    the page out 1100 pixels wide; no summary line, bottleneck line, key
    figure or caption is wider than its box (scrollWidth <= clientWidth),
    while the same probe on the page with the summary's old `white-space:
    pre` does find the clipped summary (the check can fail). The screenshot
    goes to ARTIFACTS/report.png."""
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if not chromium:
        print("\n*** SKIPPED: report in Chromium: chromium is not installed (scripts/setup installs it) ***\n",
              file=sys.stderr)
        return
    text = open(out_html, encoding="utf-8").read()
    widths = chromium_widths(chromium, tmp, text, "probe.html")
    if not check(bool(widths), "chromium: laid the report out and ran the probe"):
        return
    check(any(e.startswith("pre.summary") for e, _, _ in widths), "chromium: the report has the summary box")
    clipped = [(e, a, b) for e, a, b in widths if a > b]
    check(not clipped, f"chromium: none of {len(widths)} text boxes is clipped at 1100 px {clipped[:3]}")
    old = chromium_widths(chromium, tmp, text, "probe_nowrap.html", "pre.summary { white-space: pre; }") or []
    check(any(e.startswith("pre.summary") and a > b for e, a, b in old),
          "chromium: the probe finds the summary clipped when its lines do not wrap (as before)")
    os.makedirs(artifacts, exist_ok=True)
    shot = os.path.join(artifacts, "report.png")
    run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--window-size=1100,1150",
         f"--screenshot={shot}", "file://" + os.path.abspath(out_html)])
    if check(os.path.isfile(shot), f"chromium: screenshot {shot}"):
        png_ok(shot, "chromium: report screenshot", min_w=1100, min_h=1150)


def check_rop_only_overdraw(tmp, gpusim, scene):
    """Issue #16 item 5: with --trace-stages primitive_setup,rop the overdraw
    plot was empty and captioned "fragments not recorded" although the ROP's
    fragments were; it now draws those, and the report says so."""
    trace = os.path.join(tmp, "trace_rop")
    must([gpusim, "run", scene, "--out", os.path.join(tmp, "out"), "--trace", trace,
          "--trace-stages", "primitive_setup,rop"])
    plots = os.path.join(tmp, "plots_rop")
    must([os.path.join(HERE, "trace_plots"), trace, "--out", plots])
    tiles = json.load(open(os.path.join(plots, "tiles.json")))
    writer = stage_roles(json.load(open(os.path.join(trace, "manifest.json"))),
                         json.load(open(os.path.join(trace, "stats.json"))))["writer"]
    rop = [r for r in read_raw(os.path.join(trace, "fragments.bin"), b"GPUSIMFR", FR_FMT) if r[4] == writer["code"]]
    check(tiles["overdraw_source"] == f"{writer['kind']} fragments",
          f"rop only: overdraw from {tiles['overdraw_source']}")
    total = sum(map(sum, tiles[f"{writer['kind']}_fragments"]))
    check(len(rop) > 0 and total == len(rop), f"rop only: {total} ROP fragments in tiles.json, "
                                              f"{len(rop)} in fragments.bin")
    check(max(map(max, tiles["overdraw"])) > 0, "rop only: the overdraw map is not empty")
    png_ok(os.path.join(plots, "tiles_overdraw.png"), "rop only: tiles_overdraw.png")
    out_html = os.path.join(tmp, "report_rop.html")
    must([os.path.join(HERE, "report"), trace, "--out", out_html, "--gpusim", gpusim])
    text = open(out_html, encoding="utf-8").read()
    check("ROP fragments divided by" in text and "fragments not recorded" not in text,
          "rop only: the report's overdraw caption names the ROP fragments")


def check_not_a_trace(tmp, gpusim):
    """Issue #16 item 5: a run's --out directory given as a trace said only
    `manifest.json: cannot open`; every tool now says what it is."""
    out = os.path.join(tmp, "out")  # written by run --out above: stats.json, frame.exr
    want = (f"{out}: not a trace directory (no manifest.json; write one with gpusim run SCENE --trace DIR) "
            f"(this looks like a run's --out directory)")
    for name, cmd in (("trace summary", [gpusim, "trace", "summary", out]),
                      ("trace follow", [gpusim, "trace", "follow", out, "--prim", "0"]),
                      ("trace_plots", [os.path.join(HERE, "trace_plots"), out]),
                      ("report", [os.path.join(HERE, "report"), out, "--gpusim", gpusim])):
        r = run(cmd)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and lines[0].endswith(want),
              f"{name}: --out directory exits 2 with one line ({r.stderr.strip()!r})")
    empty = os.path.join(tmp, "empty_dir")
    os.makedirs(empty, exist_ok=True)
    r = run([gpusim, "trace", "summary", empty])
    check(r.returncode == 2 and "not a trace directory" in r.stderr and "--out directory" not in r.stderr,
          f"trace summary: an empty directory is not a trace, without the --out hint ({r.stderr.strip()!r})")


def check_partial_formats(tmp, gpusim, scene):
    """Issue #15 item 5: a trace recorded with --trace-formats vcd has no
    transactions.bin; the Python tools say so in gpusim's words, exit 2."""
    trace = os.path.join(tmp, "trace_vcd_only")
    must([gpusim, "run", scene, "--out", os.path.join(tmp, "out"), "--trace", trace,
          "--trace-formats", "vcd"])
    want = (f"{trace}: transactions.bin was not recorded (--trace-formats vcd); rerun gpusim run "
            f"--trace with transactions in --trace-formats")
    for name, cmd in (("trace_plots", [os.path.join(HERE, "trace_plots"), trace]),
                      ("report", [os.path.join(HERE, "report"), trace, "--gpusim", gpusim])):
        r = run(cmd)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and lines[0].endswith(want),
              f"{name}: a vcd-only trace exits 2 naming the missing format ({r.stderr.strip()!r})")


def check_bad_input(tmp, trace):
    for script in ("trace_plots", "report"):
        r = run([os.path.join(HERE, script), os.path.join(tmp, "no_such_dir")])
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1,
              f"{script}: missing DIR exits 2 with one line ({r.stderr.strip()!r})")
        r = run([os.path.join(HERE, script), tmp])
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1,
              f"{script}: not a trace exits 2 with one line ({r.stderr.strip()!r})")
    bad = os.path.join(tmp, "bad_trace")
    shutil.rmtree(bad, ignore_errors=True)
    shutil.copytree(trace, bad)
    with open(os.path.join(bad, "transactions.bin"), "r+b") as f:
        f.write(b"NOTATRAC")
    r = run([os.path.join(HERE, "trace_plots"), bad, "--out", os.path.join(tmp, "bad_plots")])
    check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "magic" in r.stderr,
          f"trace_plots: bad magic exits 2 with one line ({r.stderr.strip()!r})")
    with open(os.path.join(bad, "transactions.bin"), "r+b") as f:
        f.write(b"GPUSIMTX\x02\x00\x00\x00")
    r = run([os.path.join(HERE, "trace_plots"), bad, "--out", os.path.join(tmp, "bad_plots")])
    check(r.returncode == 2 and "version" in r.stderr, f"trace_plots: bad version exits 2 ({r.stderr.strip()!r})")
    shutil.copy(os.path.join(trace, "transactions.bin"), os.path.join(bad, "transactions.bin"))
    with open(os.path.join(bad, "fragments.bin"), "r+b") as f:
        f.seek(0, 2)
        f.truncate(f.tell() - 5)
    r = run([os.path.join(HERE, "trace_plots"), bad, "--out", os.path.join(tmp, "bad_plots")])
    check(r.returncode == 2 and "fragments.bin" in r.stderr, f"trace_plots: truncated fragments.bin exits 2 "
                                                              f"({r.stderr.strip()!r})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gpusim", default=os.path.join(REPO, "build", "gpusim"))
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--keep", metavar="DIR", help="work in DIR and keep it (default: a temporary directory)")
    ap.add_argument("--artifacts", metavar="DIR",
                    help="where the GTKWave and Chromium screenshots go (default: test_artifacts next to gpusim)")
    args = ap.parse_args()
    gpusim = os.path.abspath(args.gpusim)
    artifacts = os.path.abspath(args.artifacts or os.path.join(os.path.dirname(gpusim), "test_artifacts"))
    if not os.access(gpusim, os.X_OK):
        print(f"test_trace_tools: {gpusim}: no gpusim binary", file=sys.stderr)
        return 2
    tmp = os.path.abspath(args.keep) if args.keep else tempfile.mkdtemp(prefix="test_trace_tools-")
    os.makedirs(tmp, exist_ok=True)
    try:
        trace = os.path.join(tmp, "trace")
        must([gpusim, "run", args.scene, "--out", os.path.join(tmp, "out"), "--trace", trace])
        manifest = json.load(open(os.path.join(trace, "manifest.json")))
        stats = json.load(open(os.path.join(trace, "stats.json")))

        plots = os.path.join(tmp, "plots")
        r = must([os.path.join(HERE, "trace_plots"), trace, "--out", plots])
        check(len(r.stdout.split()) == len(PLOTS), "trace_plots: prints the PNGs it wrote")
        check_plots(trace, plots, manifest, "unfiltered")
        check_tiles(trace, plots, manifest, stats)
        check_tile_split(trace, plots, manifest, stats)
        check_vcd_reader(trace, stats)
        check_gtkwave(tmp, trace)
        check_gtkwave_view(tmp, gpusim, args.scene, artifacts)

        r = must([os.path.join(HERE, "trace_plots"), trace])
        check(all(os.path.isfile(os.path.join(trace, "plots", p)) for p in PLOTS), "trace_plots: default DIR/plots")

        summary = must([gpusim, "trace", "summary", trace]).stdout
        out_html = os.path.join(tmp, "report.html")
        must([os.path.join(HERE, "report"), trace, "--out", out_html, "--gpusim", gpusim])
        check_report(trace, out_html, summary)
        check_report_in_chromium(tmp, out_html, artifacts)
        must([os.path.join(HERE, "report"), trace, "--gpusim", gpusim])
        check(os.path.isfile(os.path.join(trace, "report.html")), "report: default DIR/report.html")

        # Filtered traces still plot; without depth-test fragments the
        # overdraw map falls back on the ROP's fragments, else on stamps.
        cycles = manifest["cycles"]
        ftrace = os.path.join(tmp, "trace_filtered")
        must([gpusim, "run", args.scene, "--out", os.path.join(tmp, "out"), "--trace", ftrace, "--trace-window", f"{cycles // 4}:{cycles // 2}",
              "--trace-stages", "primitive_setup,tile_rasterizer,rop"])
        fplots = os.path.join(tmp, "plots_filtered")
        must([os.path.join(HERE, "trace_plots"), ftrace, "--out", fplots])
        check_plots(ftrace, fplots, manifest, "filtered (window, stages)")
        tiles = json.load(open(os.path.join(fplots, "tiles.json")))
        check(tiles["overdraw_source"] != "fragments", f"filtered: overdraw from {tiles['overdraw_source']}")
        check_rop_only_overdraw(tmp, gpusim, args.scene)
        ptrace = os.path.join(tmp, "trace_prims")
        must([gpusim, "run", args.scene, "--out", os.path.join(tmp, "out"), "--trace", ptrace, "--trace-prims", "0:9"])
        pplots = os.path.join(tmp, "plots_prims")
        must([os.path.join(HERE, "trace_plots"), ptrace, "--out", pplots])
        check_plots(ptrace, pplots, manifest, "filtered (prims 0:9)")
        must([os.path.join(HERE, "report"), ptrace, "--gpusim", gpusim])

        check_bad_input(tmp, trace)
        check_not_a_trace(tmp, gpusim)
        check_partial_formats(tmp, gpusim, args.scene)
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        print(f"test_trace_tools: {len(failures)} check(s) failed", file=sys.stderr)
        return 1
    print("test_trace_tools: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
