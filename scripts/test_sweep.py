#!/usr/bin/python3
"""Tests of `gpusim sweep` (docs/sweeps.md), run by ctest (sweep_local, sweep_slurm).

    scripts/test_sweep.py --gpusim build/gpusim local
    scripts/test_sweep.py --gpusim build/gpusim slurm

local: a sweep of 2 scenes x units {1, 2, 4} x tile_size {8, 16} on the local
pool: 12 rows in order, each row's cycles equal to a direct `gpusim run` of
that point with a configuration this test writes itself, the stage shares and
memory figures recomputed from that run's stats.json; twice -> byte-identical
tables; resumption (points already done are not rerun; a sweep killed halfway
and rerun gives the same tables); a failing point reported while the others
complete; bad sweep files -> one line, exit 2, nothing written or submitted;
sweep plot.

slurm: the same sweep on a real single-node Slurm cluster started by
scripts/slurm_cluster (as root, with Debian's slurmctld, slurmd and munge),
waited for and with --detach + sweep collect: results.csv byte-identical to
the local run's. Without slurm, the script or root it prints why and exits 77,
which ctest reports as skipped.
"""

import argparse
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = [os.path.join(SRC, "testbench/scenes/default.json"),
          os.path.join(SRC, "testbench/scenes/quad_clipspace.json")]
UNITS = [1, 2, 4]
TILES = [8, 16]
SKIP = 77
failures = []


def check(cond, what):
    print(("ok    " if cond else "FAIL  ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(cmd, **kw):
    env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
    env.update(kw.pop("env", {}))
    return subprocess.run(cmd, capture_output=True, text=True, env=env, **kw)


def write_sweep(path, body):
    with open(path, "w") as f:
        f.write(body if isinstance(body, str) else json.dumps(body))
    return path


def small_sweep(tmp):
    # Paths relative to the sweep file, a base configuration given inline.
    rel = [os.path.relpath(s, tmp) for s in SCENES]
    return write_sweep(os.path.join(tmp, "small.json"), """{
  // 2 scenes x 3 unit counts x 2 tile sizes
  "scenes": %s,
  "base": {"memory": {"latency": 20}},
  "parameters": {"units": [1, 2, 4], "tile_size": [8, 16]},
  "combine": "grid"
}""" % json.dumps(rel))


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read(path):
    with open(path, "rb") as f:
        return f.read()


def direct_run(gpusim, tmp, scene, units, tile):
    """The point run by hand: its own config file, its own output directory."""
    d = os.path.join(tmp, f"direct_{os.path.basename(scene)}_{units}_{tile}")
    os.makedirs(d, exist_ok=True)
    cfg = os.path.join(d, "gpu.json")
    with open(cfg, "w") as f:
        json.dump({"units": units, "tile_size": tile}, f)
    r = run([gpusim, "run", scene, "--config", cfg, "--out", d, "--quiet"])
    if r.returncode != 0:
        raise RuntimeError(f"direct run failed: {r.stderr}")
    with open(os.path.join(d, "stats.json")) as f:
        return json.load(f)


def test_local(gpusim, tmp):
    sweep = small_sweep(tmp)
    a = os.path.join(tmp, "a")
    r = run([gpusim, "sweep", sweep, "--out", a, "-j", "2"])
    check(r.returncode == 0, f"local sweep exits 0 (got {r.returncode}: {r.stderr.strip()[-300:]})")
    check("sweep: 12/12 done, 0 running, 0 failed" in r.stderr, "progress line reaches 12/12 done")
    rows = rows_of(os.path.join(a, "results.csv"))
    check(len(rows) == 12, f"results.csv has 12 rows (got {len(rows)})")
    expect = [(s, u, t) for s in SCENES for u in UNITS for t in TILES]
    order = [(os.path.normpath(os.path.join(tmp, r["scene"])), int(r["units"]), int(r["tile_size"]))
             for r in rows]
    check(order == expect, "rows in order: scenes as listed, then units, then tile_size (last fastest)")
    check([r["point"] for r in rows] == [str(i) for i in range(12)], "point column 0..11")
    check(all(r["status"] == "ok" and r["error"] == "" for r in rows), "every point ok")
    with open(os.path.join(a, "results.json")) as f:
        res = json.load(f)
    check([r["cycles"] for r in res["rows"]] == [int(r["cycles"]) for r in rows],
          "results.json has the same rows as results.csv")
    distinct = set()
    for row, (scene, units, tile) in zip(rows, expect):
        st = direct_run(gpusim, tmp, scene, units, tile)
        t = st["timing"]
        cyc = t["cycles"]
        distinct.add(cyc)
        tag = f"{os.path.basename(scene)} units={units} tile={tile}"
        check(int(row["cycles"]) == cyc, f"{tag}: cycles {row['cycles']} == direct run's {cyc}")
        check(st["config"]["units"] == units and st["config"]["tile_size"] == tile,
              f"{tag}: the direct run used units {units}, tile_size {tile}")
        rops = [s for n, s in t["stages"].items() if n.startswith("rop_")]
        check(len(rops) == units, f"{tag}: {units} ROPs in the direct run")
        rop_busy = sum(s["busy_cycles"] for s in rops) / len(rops) / cyc
        check(abs(float(row["rop.busy"]) - rop_busy) <= 1e-5 * max(rop_busy, 1e-9) + 1e-12,
              f"{tag}: rop.busy {row['rop.busy']} == mean ROP busy_cycles / cycles {rop_busy:.6g}")
        setup = t["stages"]["primitive_setup"]
        check(abs(float(row["primitive_setup.stalled"]) - setup["stalled_cycles"] / cyc) < 1e-6,
              f"{tag}: primitive_setup.stalled == stalled_cycles / cycles")
        util = t["memory"]["utilization"]
        check(abs(float(row["memory_utilization"]) - util) < 1e-5, f"{tag}: memory_utilization")
        check(float(row["raster_pixels_per_clock_peak"]) == 16 * units,
              f"{tag}: raster peak 16 pixels (a 4x4 stamp) x {units} units")
        # The busiest stage: the highest busy_cycles of any stage, by hand.
        best = max(t["stages"].items(), key=lambda kv: kv[1]["busy_cycles"])
        check(row["busiest_unit"] == best[0], f"{tag}: busiest stage {row['busiest_unit']} == {best[0]}")
        # Memory-bound: the busiest channel's utilization and the busiest
        # kind's memory stalls over its busy cycles, by hand (docs/stats.md).
        kind = best[0].rstrip("0123456789").rstrip("_") if best[0][-1].isdigit() else best[0]
        group = [s for n, s in t["stages"].items()
                 if n == kind or (n.startswith(kind + "_") and n[len(kind) + 1:].isdigit())]
        busy = sum(s["busy_cycles"] for s in group)
        stall_share = sum(s.get("memory_stall_cycles", 0) for s in group) / busy if busy else 0.0
        channel_util = max(c["utilization"] for c in t["memory"]["channels"])
        bound = channel_util >= 0.70 and stall_share >= 0.50
        check(row["memory_bound"] == ("true" if bound else "false"),
              f"{tag}: memory_bound {row['memory_bound']} == busiest channel {channel_util:.3f} "
              f">= 0.70 and stall share {stall_share:.3f} >= 0.50")
    check(len(distinct) >= 8, f"the points differ in cycles ({len(distinct)} distinct of 12)")

    # Determinism: the same sweep again -> byte-identical tables.
    b = os.path.join(tmp, "b")
    r = run([gpusim, "sweep", sweep, "--out", b, "-j", "1"])
    check(r.returncode == 0, "second local sweep exits 0")
    check(read(os.path.join(a, "results.csv")) == read(os.path.join(b, "results.csv")),
          "rerun into another directory (-j 1): results.csv byte-identical")
    check(read(os.path.join(a, "results.json")) == read(os.path.join(b, "results.json")),
          "rerun into another directory (-j 1): results.json byte-identical")

    # Resumption: points 0..5 done; 6..11 without status -> only they run.
    c = os.path.join(tmp, "c")
    shutil.copytree(a, c)
    kept = {}
    for i in range(12):
        pdir = os.path.join(c, "points", f"{i:04d}")
        if i < 6:
            kept[i] = os.stat(os.path.join(pdir, "stats.json")).st_mtime_ns
        else:
            os.remove(os.path.join(pdir, "status.json"))
            os.remove(os.path.join(pdir, "stats.json"))
    os.remove(os.path.join(c, "results.csv"))
    time.sleep(0.05)
    r = run([gpusim, "sweep", sweep, "--out", c])
    check(r.returncode == 0, "resumed sweep exits 0")
    check("6 of 12 points already done, running 6" in r.stderr, "resumed sweep runs only the 6 left")
    check(all(os.stat(os.path.join(c, "points", f"{i:04d}", "stats.json")).st_mtime_ns == m
              for i, m in kept.items()), "the points already done were not rerun (stats.json untouched)")
    check(read(os.path.join(a, "results.csv")) == read(os.path.join(c, "results.csv")),
          "resumed sweep: results.csv byte-identical")
    r = run([gpusim, "sweep", sweep, "--out", c])
    check("12 of 12 points already done, running 0" in r.stderr and r.returncode == 0,
          "a finished sweep rerun runs nothing")

    # Killed halfway (SIGKILL to its whole process group), then rerun.
    d = os.path.join(tmp, "d")
    env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
    proc = subprocess.Popen([gpusim, "sweep", sweep, "--out", d, "-j", "1"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True, env=env)
    deadline = time.time() + 60
    def n_done():
        return sum(os.path.exists(os.path.join(d, "points", f"{i:04d}", "status.json")) for i in range(12))
    while n_done() < 3 and time.time() < deadline and proc.poll() is None:
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    time.sleep(0.2)
    before = n_done()
    check(0 < before < 12, f"sweep killed halfway ({before} of 12 points finished)")
    r = run([gpusim, "sweep", sweep, "--out", d])
    check(r.returncode == 0 and f"{before} of 12 points already done, running {12 - before}" in r.stderr,
          f"rerun after the kill runs the {12 - before} points left")
    check(read(os.path.join(a, "results.csv")) == read(os.path.join(d, "results.csv")),
          "killed and resumed sweep: results.csv byte-identical")

    # A failing point: units 100 is out of range; the others complete.
    fail_sweep = write_sweep(os.path.join(tmp, "fail.json"), {
        "scenes": [SCENES[1]], "parameters": {"units": [1, 100, 2]}})
    e = os.path.join(tmp, "e")
    r = run([gpusim, "sweep", fail_sweep, "--out", e])
    check(r.returncode == 1, f"sweep with a failing point exits 1 (got {r.returncode})")
    rows = rows_of(os.path.join(e, "results.csv"))
    check([x["status"] for x in rows] == ["ok", "failed", "ok"], "the failing point failed, the others ok")
    check("units: 100 is out of range 1..64" in rows[1]["error"],
          f"its error is gpusim's message ({rows[1]['error']})")
    check("point 0001 failed: gpusim: config.json: units: 100 is out of range 1..64" in r.stderr,
          "the failure is reported on stderr")
    check(rows[0]["cycles"] != "" and rows[1]["cycles"] == "", "figures only for the ok points")

    # A watchdog stop and a timeout are failures too.
    wd_sweep = write_sweep(os.path.join(tmp, "watchdog.json"), {
        "scenes": [SCENES[1]], "base": {"stages": {"vertex_shader": {"ii": 5000}}},
        "parameters": {"watchdog_cycles": [10, 1000000]}})
    w = os.path.join(tmp, "w")
    r = run([gpusim, "sweep", wd_sweep, "--out", w])
    rows = rows_of(os.path.join(w, "results.csv"))
    check(r.returncode == 1 and [x["status"] for x in rows] == ["failed", "ok"]
          and "watchdog: no item moved" in rows[0]["error"], "a watchdog stop: that point failed, with its error")
    t_sweep = write_sweep(os.path.join(tmp, "timeout.json"), {"scenes": [SCENES[0]], "parameters": {"units": [1]}})
    t = os.path.join(tmp, "t")
    r = run([gpusim, "sweep", t_sweep, "--out", t, "--timeout", "0.001"])
    rows = rows_of(os.path.join(t, "results.csv"))
    check(r.returncode == 1 and rows[0]["status"] == "failed" and rows[0]["error"] == "timed out after 0.001 s (--timeout)",
          f"--timeout: the point failed as timed out ({rows[0]['error']})")

    # zip: the i-th values together. The setup stage is named by its former
    # kind (triangle_setup), which is read as the current one with a warning.
    zip_sweep = write_sweep(os.path.join(tmp, "zip.json"), {
        "scenes": [SCENES[1]], "combine": "zip",
        "parameters": {"units": [1, 4], "stages.triangle_setup.ii": [4, 1]}})
    z = os.path.join(tmp, "z")
    r = run([gpusim, "sweep", zip_sweep, "--out", z])
    check("parameter 'stages.triangle_setup.ii' is deprecated, read as 'stages.primitive_setup.ii'"
          in r.stderr, f"a renamed stage's former key: one warning ({r.stderr.strip()[:200]})")
    rows = rows_of(os.path.join(z, "results.csv"))
    check(r.returncode == 0 and [(x["units"], x["stages.primitive_setup.ii"]) for x in rows] ==
          [("1", "4"), ("4", "1")], "zip: 2 points, the values paired")
    with open(os.path.join(z, "points", "0001", "stats.json")) as f:
        cfg = json.load(f)["config"]
    check(cfg["stages"]["primitive_setup"]["ii"] == 1 and cfg["units"] == 4,
          "zip: point 1's run used units 4 and primitive_setup.ii 1")

    # Bad sweep files: one line, exit 2, nothing written, nothing submitted.
    fake_bin = os.path.join(tmp, "fakebin")
    os.makedirs(fake_bin)
    marker = os.path.join(tmp, "sbatch_called")
    with open(os.path.join(fake_bin, "sbatch"), "w") as f:
        f.write(f"#!/bin/sh\ntouch '{marker}'\necho 1\n")
    os.chmod(os.path.join(fake_bin, "sbatch"), 0o755)
    bad = {
        "not JSON": "{\"scenes\": [",
        "unknown key": {"scenes": [SCENES[1]], "parameters": {"units": [1]}, "grid": True},
        "no scenes": {"scenes": [], "parameters": {"units": [1]}},
        "missing scene": {"scenes": ["/nonexistent/scene.json"], "parameters": {"units": [1]}},
        "unknown parameter": {"scenes": [SCENES[1]], "parameters": {"unit": [1, 2]}},
        "empty values": {"scenes": [SCENES[1]], "parameters": {"units": []}},
        "zip lengths": {"scenes": [SCENES[1]], "combine": "zip",
                        "parameters": {"units": [1, 2], "tile_size": [8]}},
        "bad combine": {"scenes": [SCENES[1]], "combine": "cross", "parameters": {"units": [1]}},
        "base not found": {"scenes": [SCENES[1]], "base": "nope.json", "parameters": {"units": [1]}},
    }
    for name, body in bad.items():
        path = write_sweep(os.path.join(tmp, "bad.json"), body)
        for slurm in (False, True):
            out = os.path.join(tmp, "bad_out")
            cmd = [gpusim, "sweep", path, "--out", out] + (["--slurm"] if slurm else [])
            r = run(cmd, env={"PATH": fake_bin + ":" + os.environ["PATH"]})
            lines = r.stderr.splitlines()
            check(r.returncode == 2 and len(lines) == 1 and lines[0].startswith("gpusim: sweep: ")
                  and not os.path.exists(out) and not os.path.exists(marker),
                  f"bad sweep file ({name}{', --slurm' if slurm else ''}): exit 2, one line, nothing "
                  f"written or submitted: {r.returncode} {lines}")
    r = run([gpusim, "sweep", small_sweep(tmp), "--out", a, "--throttle", "2"])
    check(r.returncode == 2 and "--throttle needs --slurm" in r.stderr, "--throttle without --slurm: exit 2")
    other = write_sweep(os.path.join(tmp, "other.json"), {"scenes": [SCENES[1]], "parameters": {"units": [3]}})
    r = run([gpusim, "sweep", other, "--out", a])
    check(r.returncode == 2 and "holds another sweep" in r.stderr, "another sweep into the same DIR: exit 2")
    # --out a file, or a path that cannot be created: one line, exit 2.
    a_file = os.path.join(tmp, "a_file")
    with open(a_file, "w", encoding="utf-8") as f:
        f.write("kept")
    for out, says in ((a_file, "is a file, not a directory"),
                      (os.path.join(a_file, "below"), "cannot create the directory")):
        r = run([gpusim, "sweep", small_sweep(tmp), "--out", out])
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and says in lines[0] and read(a_file) == b"kept",
              f"--out {os.path.basename(out)}: exit 2, one line ({says}), the file kept: "
              f"{r.returncode} {lines}")

    # collect and plot.
    before = read(os.path.join(a, "results.csv"))
    r = run([gpusim, "sweep", "collect", a])
    check(r.returncode == 0 and read(os.path.join(a, "results.csv")) == before,
          "sweep collect rewrites the same results.csv")
    r = run([gpusim, "sweep", "plot", a])
    check(r.returncode == 0, f"sweep plot exits 0 ({r.stderr.strip()})")
    for f in ("index.html", "plots/cycles_vs_units.png", "plots/cycles_vs_tile_size.png",
              "plots/utilization.png"):
        p = os.path.join(a, f)
        check(os.path.exists(p) and os.path.getsize(p) > 1000, f"sweep plot wrote {f}")
    with open(os.path.join(a, "index.html")) as f:
        page = f.read()
    check(page.count("<tr>") == 13 and "plots/utilization.png" in page, "index.html: table of 12 rows and plots")


def test_slurm(gpusim, tmp):
    reasons = []
    if shutil.which("sbatch") is None:
        reasons.append("sbatch not installed (scripts/setup installs slurm)")
    cluster = os.path.join(SRC, "scripts", "slurm_cluster")
    if not os.access(cluster, os.X_OK):
        reasons.append("scripts/slurm_cluster missing")
    if os.geteuid() != 0:
        reasons.append("not root (slurmd must run as root)")
    if reasons:
        print("SKIPPED: sweep on Slurm not tested: " + "; ".join(reasons), flush=True)
        return SKIP
    os.chmod(tmp, 0o755)  # munged and slurmd's users reach the cluster's and the sweep's directories
    sweep = small_sweep(tmp)
    local = os.path.join(tmp, "local")
    r = run([gpusim, "sweep", sweep, "--out", local])
    check(r.returncode == 0, "local sweep exits 0")
    cdir = os.path.join(tmp, "cluster")
    r = run([cluster, "start", cdir])
    if r.returncode != 0:
        check(False, f"scripts/slurm_cluster start: {r.stderr.strip()}")
        return 1
    env = {}
    for line in r.stdout.splitlines():
        k, _, v = line.partition("=")
        if k in ("SLURM_CONF", "PARTITION"):
            env[k] = v
    try:
        part = env.get("PARTITION", "debug")
        s = os.path.join(tmp, "slurm")
        r = run([gpusim, "sweep", sweep, "--out", s, "--slurm", "--partition", part, "--time", "5",
                 "--throttle", "4"], env={"SLURM_CONF": env["SLURM_CONF"]}, timeout=600)
        check(r.returncode == 0, f"Slurm sweep exits 0 ({r.stderr.strip()[-400:]})")
        check("submitted job array" in r.stderr and "--array=0-11%4" in r.stderr,
              "one job array of 12 tasks, throttled to 4")
        with open(os.path.join(s, "slurm", "job.sh")) as f:
            check("SLURM_ARRAY_TASK_ID" in f.read(), "job.sh picks its point by SLURM_ARRAY_TASK_ID")
        check(read(os.path.join(local, "results.csv")) == read(os.path.join(s, "results.csv")),
              "Slurm and local: results.csv byte-identical")
        # --detach, then collect once the job has left the queue.
        dd = os.path.join(tmp, "detached")
        r = run([gpusim, "sweep", sweep, "--out", dd, "--slurm", "--partition", part, "--detach"],
                env={"SLURM_CONF": env["SLURM_CONF"]})
        check(r.returncode == 0 and "gpusim sweep collect" in r.stderr, "--detach returns after submitting")
        with open(os.path.join(dd, "slurm", "job.json")) as f:
            job = json.load(f)["job_id"]
        deadline = time.time() + 300
        while time.time() < deadline:
            q = run(["squeue", "-h", "-j", job, "-o", "%T"], env={"SLURM_CONF": env["SLURM_CONF"]})
            if (q.returncode == 0 and not q.stdout.strip()) or "Invalid job id" in q.stderr:
                break
            time.sleep(1)
        r = run([gpusim, "sweep", "collect", dd])
        check(r.returncode == 0, f"sweep collect after --detach exits 0 ({r.stderr.strip()[-300:]})")
        check(read(os.path.join(local, "results.csv")) == read(os.path.join(dd, "results.csv")),
              "--detach + collect and local: results.csv byte-identical")
    finally:
        run([cluster, "stop", cdir])
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gpusim", default=os.path.join(SRC, "build", "gpusim"))
    ap.add_argument("mode", choices=["local", "slurm"])
    a = ap.parse_args()
    gpusim = os.path.abspath(a.gpusim)
    tmp = tempfile.mkdtemp(prefix=f"gpusim_sweep_{a.mode}_")
    try:
        rc = test_local(gpusim, tmp) if a.mode == "local" else test_slurm(gpusim, tmp)
        if rc == SKIP:
            return SKIP
    finally:
        if not failures:
            shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        print(f"{len(failures)} check(s) failed; outputs kept in {tmp}")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
