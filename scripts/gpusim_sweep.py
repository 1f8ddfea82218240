#!/usr/bin/python3
"""The sweep runner behind `gpusim sweep` (docs/sweeps.md).

    gpusim sweep SWEEP.json --out DIR [-j N] [--timeout S]
                 [--slurm [--partition P] [--time T] [--throttle K]
                          [--sbatch-arg ARG ...] [--detach]]
    gpusim sweep collect DIR
    gpusim sweep plot DIR

`gpusim sweep` runs this script with `--gpusim` set to its own binary
(/proc/self/exe), which every point then runs as `gpusim run`. Each point gets
DIR/points/NNNN/ with point.json (its scene and parameters), config.json (the
base configuration with the point's parameters set by dotted path), the run's
outputs, stdout.txt, stderr.txt and, once finished, status.json. Results go to
DIR/results.csv and DIR/results.json. Exit status: 0 every point ran, 1 some
point failed (the tables list it with its error), 2 bad command line or sweep
file (one line on stderr; nothing is run, written or submitted).
"""

import argparse
import csv
import io
import json
import os
import subprocess
import sys
import time

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_CONFIG = os.path.join(SOURCE_DIR, "testbench", "configs", "default.json")

SWEEP_KEYS = {"description", "scenes", "base", "parameters", "combine"}


class SweepError(Exception):
    """Bad input: one line, exit 2."""


def strip_comments(text):
    """Removes // and /* */ comments outside strings (the config file rule)."""
    out, i, n, in_str = [], 0, len(text), False
    while i < n:
        c = text[i]
        if in_str:
            out.append(c)
            if c == "\\" and i + 1 < n:
                out.append(text[i + 1])
                i += 1
            elif c == '"':
                in_str = False
        elif c == '"':
            in_str = True
            out.append(c)
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            if end < 0:
                raise ValueError("unterminated /* comment")
            out.append(" ")
            i = end + 2
            continue
        else:
            out.append(c)
        i += 1
    return "".join(out)


def load_json(path, what, comments=False):
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise SweepError(f"{path}: cannot read {what}: {e.strerror}")
    try:
        return json.loads(strip_comments(text) if comments else text)
    except ValueError as e:
        raise SweepError(f"{path}: {what} is not valid JSON: {e}")


def key_exists(tree, dotted):
    node = tree
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            return False
        node = node[part]
    return True


def set_dotted(tree, dotted, value):
    parts = dotted.split(".")
    node = tree
    for part in parts[:-1]:
        node = node.setdefault(part, {})
    node[parts[-1]] = value


def renamed_stages(gpusim):
    """{former kind: current kind} of the stages gpusim renamed (`gpusim config
    --renamed`), whose former names a sweep file may still use; {} when gpusim
    cannot tell."""
    try:
        out = subprocess.run([gpusim, "config", "--renamed"], capture_output=True, text=True,
                             env=dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE"), check=True).stdout
        renamed = json.loads(out)
        return renamed if isinstance(renamed, dict) else {}
    except (OSError, subprocess.CalledProcessError, ValueError):
        return {}


def current_key(key, renamed):
    """`key` with a renamed stage's former kind under its current one
    (stages.<former>.ii), or `key` itself."""
    parts = key.split(".")
    if len(parts) >= 2 and parts[0] == "stages" and parts[1] in renamed:
        return ".".join([parts[0], renamed[parts[1]]] + parts[2:])
    return key


def load_sweep(path, gpusim=None):
    """Validates a sweep file; returns (spec, points). Raises SweepError. A
    parameter naming a renamed stage by its former kind is read under the
    current one, with a warning (`gpusim`, the binary, tells the renames)."""
    spec = load_json(path, "the sweep file", comments=True)
    if not isinstance(spec, dict):
        raise SweepError(f"{path}: the sweep file must be a JSON object")
    unknown = sorted(set(spec) - SWEEP_KEYS)
    if unknown:
        raise SweepError(f"{path}: unknown key '{unknown[0]}' (keys: {', '.join(sorted(SWEEP_KEYS))})")
    base_dir = os.path.dirname(os.path.abspath(path))
    scenes = spec.get("scenes")
    if not isinstance(scenes, list) or not scenes or not all(isinstance(s, str) and s for s in scenes):
        raise SweepError(f"{path}: scenes must be a non-empty list of scene file paths")
    if len(set(scenes)) != len(scenes):
        raise SweepError(f"{path}: scenes lists a scene twice")
    for s in scenes:
        if not os.path.isfile(os.path.join(base_dir, s)):
            raise SweepError(f"{path}: scene '{s}' not found (paths are relative to the sweep file)")
    base = spec.get("base", {})
    if isinstance(base, str):
        base = load_json(os.path.join(base_dir, base), "the base configuration", comments=True)
    if not isinstance(base, dict):
        raise SweepError(f"{path}: base must be a configuration file path or a JSON object")
    params = spec.get("parameters")
    if not isinstance(params, dict) or not params:
        raise SweepError(f"{path}: parameters must be a non-empty object: dotted config key -> list of values")
    defaults = load_json(DEFAULT_CONFIG, "the default configuration", comments=True)
    renamed = None
    for key in list(params):
        if key_exists(defaults, key) or gpusim is None:
            continue
        renamed = renamed_stages(gpusim) if renamed is None else renamed
        current = current_key(key, renamed)
        if current != key:
            if current in params:
                raise SweepError(f"{path}: parameter '{key}' is given together with '{current}', its new name")
            sys.stderr.write(f"sweep: warning: {path}: parameter '{key}' is deprecated, read as "
                             f"'{current}' (the stage was renamed; the old name goes in the next release)\n")
            params = {current if k == key else k: v for k, v in params.items()}
            spec["parameters"] = params
    for key, values in params.items():
        if not key_exists(defaults, key):
            raise SweepError(f"{path}: parameter '{key}' is not a GPU configuration key (docs/gpu-config.md)")
        if not isinstance(values, list) or not values:
            raise SweepError(f"{path}: parameter '{key}' needs a non-empty list of values")
        seen = set()
        for v in values:
            if isinstance(v, dict):
                raise SweepError(f"{path}: parameter '{key}': a value may not be an object")
            enc = json.dumps(v)
            if enc in seen:
                raise SweepError(f"{path}: parameter '{key}' lists the value {enc} twice")
            seen.add(enc)
    combine = spec.get("combine", "grid")
    if combine not in ("grid", "zip"):
        raise SweepError(f"{path}: combine must be \"grid\" or \"zip\", not {json.dumps(combine)}")
    names = list(params)
    if combine == "zip":
        lengths = {len(v) for v in params.values()}
        if len(lengths) != 1:
            raise SweepError(f"{path}: combine \"zip\" needs lists of one length; they have {sorted(lengths)}")
        combos = [dict(zip(names, vals)) for vals in zip(*params.values())]
    else:
        combos = [{}]
        for name in names:
            combos = [dict(c, **{name: v}) for c in combos for v in params[name]]
    points = []
    for scene in scenes:
        for combo in combos:
            config = json.loads(json.dumps(base))
            for k, v in combo.items():
                set_dotted(config, k, v)
            points.append({
                "index": len(points),
                "scene": scene,
                "scene_path": os.path.normpath(os.path.join(base_dir, scene)),
                "parameters": combo,
                "config": config,
            })
    normalized = {"scenes": scenes, "base": base, "parameters": params, "combine": combine}
    return normalized, points


def point_dir(out, index):
    return os.path.join(out, "points", f"{index:04d}")


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def dump(obj):
    return json.dumps(obj, indent=2, sort_keys=False) + "\n"


def read_status(pdir):
    try:
        with open(os.path.join(pdir, "status.json"), encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def is_done(pdir):
    st = read_status(pdir)
    return st is not None and st.get("exit_status") == 0


def prepare(out, spec, points):
    """Writes DIR/sweep.json and each point's point.json and config.json."""
    try:
        os.makedirs(os.path.join(out, "points"), exist_ok=True)
    except OSError as e:
        raise SweepError(f"{out}: cannot create the directory: {e.strerror}; give another --out")
    write_atomic(os.path.join(out, "sweep.json"), dump(spec))
    for p in points:
        pdir = point_dir(out, p["index"])
        os.makedirs(pdir, exist_ok=True)
        write_atomic(os.path.join(pdir, "point.json"), dump(
            {"index": p["index"], "scene": p["scene"], "scene_path": p["scene_path"],
             "parameters": p["parameters"]}))
        write_atomic(os.path.join(pdir, "config.json"), dump(p["config"]))


def check_out_dir(out, spec):
    """A rerun must be the same sweep: refuses a DIR holding another one, or
    a file."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise SweepError(f"{out} is a file, not a directory; give a new --out")
    old = os.path.join(out, "sweep.json")
    if os.path.exists(old):
        try:
            with open(old, encoding="utf-8") as f:
                previous = json.load(f)
        except (OSError, ValueError):
            previous = None
        if previous != json.loads(json.dumps(spec)):
            raise SweepError(f"{out} holds another sweep (its sweep.json differs); give a new --out")
    elif os.path.isdir(out) and os.listdir(out):
        raise SweepError(f"{out} exists, is not empty and holds no sweep.json; give a new --out")


def error_line(stderr_text, exit_status):
    lines = [l for l in stderr_text.splitlines() if l.strip()]
    for l in lines:
        if l.startswith("gpusim:") and not l.startswith("gpusim: scene has no camera"):
            return l
    return lines[-1] if lines else f"exit status {exit_status}"


def run_point(gpusim, pdir, timeout=None):
    """Runs one point in its directory; writes stdout.txt, stderr.txt, status.json."""
    with open(os.path.join(pdir, "point.json"), encoding="utf-8") as f:
        point = json.load(f)
    try:
        os.remove(os.path.join(pdir, "status.json"))
    except FileNotFoundError:
        pass
    cmd = [gpusim, "run", point["scene_path"], "--config", "config.json", "--out", ".", "--quiet"]
    env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
    with open(os.path.join(pdir, "stdout.txt"), "wb") as out, \
            open(os.path.join(pdir, "stderr.txt"), "wb") as err:
        try:
            proc = subprocess.run(cmd, cwd=pdir, stdout=out, stderr=err, env=env, timeout=timeout)
            code = proc.returncode
            timed_out = False
        except subprocess.TimeoutExpired:
            code, timed_out = -1, True
    with open(os.path.join(pdir, "stderr.txt"), encoding="utf-8", errors="replace") as f:
        stderr_text = f.read()
    if code == 0:
        # The bottleneck and the stages in pipeline order, by the rule of
        # `gpusim stats summary` (docs/stats.md), which collect reads.
        summary = subprocess.run([gpusim, "stats", "summary", "stats.json", "--json"], cwd=pdir,
                                 capture_output=True, text=True, env=env)
        if summary.returncode == 0:
            write_atomic(os.path.join(pdir, "summary.json"), summary.stdout)
        else:
            code = summary.returncode
            stderr_text = summary.stderr
    status = {"exit_status": code}
    if timed_out:
        status["error"] = f"timed out after {timeout:g} s (--timeout)"
    elif code != 0:
        status["error"] = (error_line(stderr_text, code) if code > 0
                           else f"killed by signal {-code}")
    write_atomic(os.path.join(pdir, "status.json"), dump(status))
    return status


class Progress:
    def __init__(self, total):
        self.total = total
        self.tty = sys.stderr.isatty()
        self.last = None
        self.last_time = 0.0

    def show(self, done, running, failed, final=False):
        line = f"sweep: {done}/{self.total} done, {running} running, {failed} failed"
        now = time.monotonic()
        if line == self.last and not final:
            return
        if not final and not self.tty and now - self.last_time < 1.0 and self.last is not None:
            return
        self.last, self.last_time = line, now
        if self.tty:
            sys.stderr.write("\r" + line + ("\n" if final else ""))
        else:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()


def run_local(gpusim, out, points, jobs, timeout):
    todo = [p for p in points if not is_done(point_dir(out, p["index"]))]
    skipped = len(points) - len(todo)
    if skipped:
        sys.stderr.write(f"sweep: {skipped} of {len(points)} points already done, running {len(todo)}\n")
    progress = Progress(len(points))
    done, failed = skipped, 0
    running = {}  # Popen of a `point` worker -> index
    queue = list(todo)
    me = os.path.abspath(__file__)
    progress.show(done, 0, failed)
    while queue or running:
        while queue and len(running) < jobs:
            p = queue.pop(0)
            cmd = [sys.executable, me, "point", point_dir(out, p["index"]), "--gpusim", gpusim]
            if timeout:
                cmd += ["--timeout", str(timeout)]
            running[subprocess.Popen(cmd)] = p["index"]
        progress.show(done, len(running), failed)
        time.sleep(0.02)
        for proc in [q for q in running if q.poll() is not None]:
            index = running.pop(proc)
            st = read_status(point_dir(out, index))
            if st is not None and st.get("exit_status") == 0:
                done += 1
            else:
                failed += 1
                err = st.get("error") if st else f"point runner exited {proc.returncode}"
                sys.stderr.write(("\n" if progress.tty else "") +
                                 f"sweep: point {index:04d} failed: {err}\n")
    progress.show(done, 0, failed, final=True)


def slurm_env():
    return dict(os.environ)


def submit_slurm(gpusim, out, points, args):
    todo = [p["index"] for p in points if not is_done(point_dir(out, p["index"]))]
    sdir = os.path.join(out, "slurm")
    os.makedirs(sdir, exist_ok=True)
    if not todo:
        sys.stderr.write(f"sweep: all {len(points)} points already done, nothing submitted\n")
        return None
    out_abs = os.path.abspath(out)
    write_atomic(os.path.join(sdir, "points.txt"), "".join(f"{i:04d}\n" for i in todo))
    script = "\n".join([
        "#!/bin/sh",
        "# gpusim sweep: one array task per line of points.txt (docs/sweeps.md).",
        "#SBATCH --job-name=gpusim-sweep",
        f"#SBATCH --output={out_abs}/slurm/task_%A_%a.out",
        "#SBATCH --ntasks=1",
        "#SBATCH --cpus-per-task=1",
        "set -eu",
        f"point=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" '{out_abs}/slurm/points.txt')",
        f"exec {sys.executable} '{os.path.abspath(__file__)}' point '{out_abs}/points/'\"$point\" "
        f"--gpusim '{gpusim}'",
        "",
    ])
    write_atomic(os.path.join(sdir, "job.sh"), script)
    os.chmod(os.path.join(sdir, "job.sh"), 0o755)
    array = f"0-{len(todo) - 1}" + (f"%{args.throttle}" if args.throttle else "")
    cmd = ["sbatch", "--parsable", f"--array={array}"]
    if args.partition:
        cmd.append(f"--partition={args.partition}")
    if args.time:
        cmd.append(f"--time={args.time}")
    cmd += args.sbatch_arg or []
    cmd.append(os.path.join(sdir, "job.sh"))
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, env=slurm_env())
    except OSError as e:
        raise SweepError(f"cannot run sbatch: {e.strerror} (is Slurm installed?)")
    if proc.returncode != 0:
        msg = (proc.stderr.strip().splitlines() or ["no message"])[-1]
        raise SweepError(f"sbatch failed (exit {proc.returncode}): {msg}")
    job = proc.stdout.strip().split(";")[0]
    write_atomic(os.path.join(sdir, "job.json"), dump({"job_id": job, "command": cmd, "points": todo}))
    sys.stderr.write(f"sweep: submitted job array {job} ({len(todo)} points, {array}) with {' '.join(cmd)}\n")
    return job


def slurm_wait(out, points, job, poll):
    progress = Progress(len(points))
    warned = False
    while True:
        q = subprocess.run(["squeue", "-h", "-j", job, "-o", "%T"], capture_output=True, text=True,
                           env=slurm_env())
        states = q.stdout.split() if q.returncode == 0 else []
        done = failed = 0
        for p in points:
            st = read_status(point_dir(out, p["index"]))
            if st is None:
                continue
            if st.get("exit_status") == 0:
                done += 1
            else:
                failed += 1
        running = sum(1 for s in states if s == "RUNNING")
        # squeue lists a job while it is pending, running or completing; once
        # Slurm has purged it, `-j JOB` is an invalid job id.
        gone = (q.returncode == 0 and not states) or "Invalid job id" in q.stderr
        if gone or done + failed == len(points):
            if not gone:
                time.sleep(poll)  # let the tasks' exits reach Slurm
            progress.show(done, 0, failed, final=True)
            return
        if q.returncode != 0 and not warned:
            warned = True
            sys.stderr.write(f"sweep: squeue failed ({q.stderr.strip()}); still waiting for the points' "
                             "status.json\n")
        progress.show(done, running, failed)
        time.sleep(poll)


# ---------------------------------------------------------------------------
# Results


def figures(stats, summary):
    """The row's figures from one stats.json and its `gpusim stats summary --json`
    (docs/sweeps.md, "Result columns"), and the per-kind shares with the kinds
    in pipeline order."""
    t = stats["timing"]
    f = {"cycles": t["cycles"], "simulated_seconds": t["simulated_seconds"]}
    kinds = {}  # kind -> its stages' entries, in pipeline order
    for s in summary["stages"]:
        kinds.setdefault(s["kind"], []).append(s)
    shares = {}
    for kind, group in kinds.items():
        for state in ("busy", "stalled", "starved"):
            shares[f"{kind}.{state}"] = sum(float(s[state]) for s in group) / len(group)
    rates = t.get("rates", {})
    for k in ("raster_pixels_per_clock", "raster_pixels_per_clock_peak",
              "setup_triangles_per_clock", "setup_triangles_per_clock_peak"):
        f[k] = rates.get(k)
    f["memory_utilization"] = t.get("memory", {}).get("utilization")
    b = summary["bottleneck"]
    f["busiest_stage"] = b["kind"]
    f["busiest_unit"] = b["busiest"]
    f["busiest_busy"] = b["busy"]
    f["memory_stall_share"] = b["memory_stall_share"]
    f["memory_bound"] = bool(b["memory_bound"])
    return f, shares


def fmt(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return format(v, ".6g")
    if isinstance(v, (list, dict)):
        return json.dumps(v, separators=(",", ":"))
    return str(v)


def rounded(v):
    return float(format(v, ".6g")) if isinstance(v, float) else v


def collect(out):
    """Writes DIR/results.csv and DIR/results.json; returns (rows, failed)."""
    try:
        with open(os.path.join(out, "sweep.json"), encoding="utf-8") as f:
            spec = json.load(f)
    except (OSError, ValueError):
        raise SweepError(f"{out}: no sweep here (sweep.json missing or unreadable)")
    pdirs = sorted(d for d in os.listdir(os.path.join(out, "points")) if d.isdigit())
    params = list(spec["parameters"])
    rows, kinds, failed = [], [], 0  # kinds: pipeline order, as the points list them
    for d in pdirs:
        pdir = os.path.join(out, "points", d)
        with open(os.path.join(pdir, "point.json"), encoding="utf-8") as f:
            point = json.load(f)
        row = {"point": point["index"], "scene": point["scene"]}
        for k in params:
            row[k] = point["parameters"][k]
        st = read_status(pdir)
        shares = {}
        if st is None:
            row["status"] = "missing"
            row["error"] = "not run or not finished (no status.json)"
        elif st.get("exit_status") != 0:
            row["status"] = "failed"
            row["error"] = st.get("error", "")
        else:
            try:
                with open(os.path.join(pdir, "stats.json"), encoding="utf-8") as f:
                    stats = json.load(f)
                with open(os.path.join(pdir, "summary.json"), encoding="utf-8") as f:
                    figs, shares = figures(stats, json.load(f))
                row["status"] = "ok"
                row["error"] = ""
                row.update(figs)
            except (OSError, ValueError, KeyError) as e:
                row["status"] = "failed"
                row["error"] = f"stats.json or summary.json unreadable: {e}"
        if row["status"] != "ok":
            failed += 1
        row["_shares"] = shares
        for k in shares:
            if k.split(".")[0] not in kinds:
                kinds.append(k.split(".")[0])
        rows.append(row)
    share_cols = [f"{k}.{s}" for k in kinds for s in ("busy", "stalled", "starved")]
    columns = (["point", "scene"] + params + ["status", "error", "cycles", "simulated_seconds"] +
               share_cols +
               ["raster_pixels_per_clock", "raster_pixels_per_clock_peak",
                "setup_triangles_per_clock", "setup_triangles_per_clock_peak",
                "memory_utilization", "busiest_stage", "busiest_unit", "busiest_busy",
                "memory_stall_share", "memory_bound"])
    table = []
    for row in rows:
        shares = row.pop("_shares")
        table.append({c: rounded(row.get(c, shares.get(c))) for c in columns})
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for r in table:
        w.writerow([fmt(r[c]) for c in columns])
    write_atomic(os.path.join(out, "results.csv"), buf.getvalue())
    write_atomic(os.path.join(out, "results.json"),
                 json.dumps({"sweep": spec, "columns": columns, "rows": table}, indent=1) + "\n")
    return table, failed


def report_collect(out, table, failed):
    ok = sum(1 for r in table if r["status"] == "ok")
    sys.stderr.write(f"sweep: {ok} of {len(table)} points ok, {failed} failed or missing; "
                     f"{os.path.join(out, 'results.csv')}, {os.path.join(out, 'results.json')}\n")
    for r in table:
        if r["status"] != "ok":
            sys.stderr.write(f"  point {r['point']:04d} ({r['scene']}): {r['status']}: {r['error']}\n")


# ---------------------------------------------------------------------------
# Plots


def plot(out):
    try:
        with open(os.path.join(out, "results.json"), encoding="utf-8") as f:
            res = json.load(f)
    except (OSError, ValueError):
        raise SweepError(f"{out}: no results.json (run gpusim sweep collect {out} first)")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in res["rows"] if r["status"] == "ok"]
    params = list(res["sweep"]["parameters"])
    scenes = list(dict.fromkeys(r["scene"] for r in res["rows"]))
    pdir = os.path.join(out, "plots")
    os.makedirs(pdir, exist_ok=True)
    images = []

    def key(v):
        return json.dumps(v)

    for p in params:
        others = [o for o in params if o != p]
        fig, axes = plt.subplots(1, len(scenes), figsize=(5.5 * len(scenes), 4), squeeze=False)
        for ax, scene in zip(axes[0], scenes):
            lines = {}
            for r in rows:
                if r["scene"] != scene:
                    continue
                label = ", ".join(f"{o}={fmt(r[o])}" for o in others) or "cycles"
                lines.setdefault(label, []).append((r[p], r["cycles"]))
            numeric = all(isinstance(r[p], (int, float)) for r in rows)
            xs_all = sorted({key(r[p]) for r in rows})
            for label, pts in lines.items():
                if numeric:
                    pts.sort()
                    ax.plot([x for x, _ in pts], [y for _, y in pts], marker="o", label=label)
                else:
                    pts.sort(key=lambda t: xs_all.index(key(t[0])))
                    ax.plot([xs_all.index(key(x)) for x, _ in pts], [y for _, y in pts],
                            marker="o", label=label)
            if not numeric:
                ax.set_xticks(range(len(xs_all)), xs_all)
            elif all(isinstance(r[p], int) for r in rows) and len(xs_all) > 1:
                vals = sorted({r[p] for r in rows})
                if vals[0] > 0 and vals[-1] / vals[0] >= 8:
                    ax.set_xscale("log", base=2)
                ax.set_xticks(vals, [str(v) for v in vals])
            ax.set_title(scene, fontsize=9)
            ax.set_xlabel(p)
            ax.set_ylabel("cycles")
            ax.grid(True, alpha=0.3)
            if lines:
                ax.legend(fontsize=7)
        fig.suptitle(f"cycles against {p}")
        fig.tight_layout()
        name = f"cycles_vs_{p.replace('.', '_')}.png"
        fig.savefig(os.path.join(pdir, name), dpi=100)
        plt.close(fig)
        images.append(name)

    kinds = [c[:-len(".busy")] for c in res["columns"] if c.endswith(".busy")]
    if rows and kinds:
        fig, axes = plt.subplots(len(kinds), 1, figsize=(min(30, max(6, 0.45 * len(rows) + 2)), 1.6 * len(kinds)),
                                 sharex=True, squeeze=False)
        xs = range(len(rows))
        colours = {"busy": "#2a7fd4", "stalled": "#e0543a", "starved": "#c8c8c8"}
        for ax, kind in zip(axes[:, 0], kinds):
            bottom = [0.0] * len(rows)
            for state in ("busy", "stalled", "starved"):
                vals = [(r.get(f"{kind}.{state}") or 0.0) * 100 for r in rows]
                ax.bar(xs, vals, bottom=bottom, color=colours[state], label=state, width=0.8)
                bottom = [b + v for b, v in zip(bottom, vals)]
            ax.set_ylim(0, 100)
            ax.set_ylabel(kind, rotation=0, ha="right", va="center", fontsize=8)
            ax.tick_params(axis="y", labelsize=7)
        axes[0, 0].legend(loc="upper right", fontsize=7, ncol=3)
        axes[0, 0].set_title("stage utilization per point (% of cycles, mean over units)")
        step = max(1, len(rows) // 60)  # at most about 60 labels
        axes[-1, 0].set_xticks(list(xs)[::step], [f"{r['point']}" for r in rows][::step], fontsize=7)
        axes[-1, 0].set_xlabel("point (results.csv)")
        fig.tight_layout()
        fig.savefig(os.path.join(pdir, "utilization.png"), dpi=100)
        plt.close(fig)
        images.append("utilization.png")

    import html
    cols = res["columns"]
    head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
    body = "\n".join("<tr>" + "".join(f"<td>{html.escape(fmt(r[c]))}</td>" for c in cols) + "</tr>"
                     for r in res["rows"])
    imgs = "\n".join(f'<p><img src="plots/{n}" alt="{n}"></p>' for n in images)
    page = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>gpusim sweep {html.escape(out)}</title>
<style>body{{font-family:sans-serif}} table{{border-collapse:collapse;font-size:12px}}
td,th{{border:1px solid #ccc;padding:2px 5px;text-align:right}} img{{max-width:100%}}</style></head>
<body><h1>gpusim sweep</h1>
<p>{len(res['rows'])} points; scenes {html.escape(', '.join(scenes))}; parameters
{html.escape(', '.join(params))} ({html.escape(res['sweep']['combine'])}).
Columns: docs/sweeps.md. Tables: <a href="results.csv">results.csv</a>,
<a href="results.json">results.json</a>.</p>
{imgs}
<table><tr>{head}</tr>
{body}
</table></body></html>
"""
    write_atomic(os.path.join(out, "index.html"), page)
    sys.stderr.write(f"sweep plot: {os.path.join(out, 'index.html')} and {len(images)} plots in {pdir}\n")


# ---------------------------------------------------------------------------


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise SweepError(message + "; see gpusim sweep --help")


def positive_int(s):
    try:
        v = int(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: '{s}'")
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1: {v}")
    return v


def positive_float(s):
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{s}'")
    if not v > 0:
        raise argparse.ArgumentTypeError(f"must be positive: {s}")
    return v


def main(argv):
    gpusim = os.environ.get("GPUSIM_BINARY", os.path.join(SOURCE_DIR, "build", "gpusim"))
    if len(argv) >= 2 and argv[0] == "--gpusim":
        gpusim, argv = argv[1], argv[2:]
    cmd = argv[0] if argv else ""
    if cmd == "point":  # internal: one point, run by the local pool and by Slurm tasks
        ap = Parser(prog="gpusim sweep point")
        ap.add_argument("dir")
        ap.add_argument("--gpusim", default=gpusim)
        ap.add_argument("--timeout", type=positive_float)
        a = ap.parse_args(argv[1:])
        st = run_point(a.gpusim, a.dir, a.timeout)
        return 0 if st["exit_status"] == 0 else 1
    if cmd in ("collect", "plot"):
        ap = Parser(prog=f"gpusim sweep {cmd}")
        ap.add_argument("dir", help="the sweep's --out directory")
        a = ap.parse_args(argv[1:])
        if cmd == "plot":
            plot(a.dir)
            return 0
        table, failed = collect(a.dir)
        report_collect(a.dir, table, failed)
        return 1 if failed else 0

    ap = Parser(prog="gpusim sweep",
                description="Run a design-space sweep (docs/sweeps.md); also: gpusim sweep collect DIR, "
                            "gpusim sweep plot DIR")
    ap.add_argument("sweep", help="sweep file (JSON)")
    ap.add_argument("--out", required=True, help="output directory (shared by the Slurm nodes)")
    ap.add_argument("-j", "--jobs", type=positive_int, help="local processes (default: the cores)")
    ap.add_argument("--timeout", type=positive_float, help="local runs: seconds before a point is killed")
    ap.add_argument("--slurm", action="store_true", help="submit one job array to Slurm")
    ap.add_argument("--partition", help="sbatch --partition")
    ap.add_argument("--time", help="sbatch --time: each array task's time limit")
    ap.add_argument("--throttle", type=positive_int, help="at most K tasks at once (--array=...%%K)")
    ap.add_argument("--sbatch-arg", action="append", help="extra sbatch argument (repeatable)")
    ap.add_argument("--detach", action="store_true", help="submit and return; gpusim sweep collect DIR later")
    ap.add_argument("--poll", type=positive_float, default=2.0, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if not a.slurm:
        for opt in ("partition", "time", "throttle", "sbatch_arg"):
            if getattr(a, opt):
                raise SweepError(f"--{opt.replace('_', '-')} needs --slurm; see gpusim sweep --help")
        if a.detach:
            raise SweepError("--detach needs --slurm; see gpusim sweep --help")
    elif a.jobs or a.timeout:
        raise SweepError("-j and --timeout are for local runs; with --slurm use --throttle and --time")
    spec, points = load_sweep(a.sweep, gpusim)
    check_out_dir(a.out, spec)
    if a.slurm and not os.access(gpusim, os.X_OK):
        raise SweepError(f"{gpusim}: not an executable gpusim")
    prepare(a.out, spec, points)
    if a.slurm:
        job = submit_slurm(gpusim, a.out, points, a)
        if job is not None and a.detach:
            sys.stderr.write(f"sweep: detached; when job {job} is done: gpusim sweep collect {a.out}\n")
            return 0
        if job is not None:
            slurm_wait(a.out, points, job, a.poll)
    else:
        jobs = a.jobs or len(os.sched_getaffinity(0))
        run_local(gpusim, a.out, points, jobs, a.timeout)
    table, failed = collect(a.out)
    report_collect(a.out, table, failed)
    return 1 if failed else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except SweepError as e:
        sys.stderr.write(f"gpusim: sweep: {e}\n")
        sys.exit(2)
    except KeyboardInterrupt:
        sys.stderr.write("\ngpusim: sweep: interrupted; rerun the same command to resume\n")
        sys.exit(130)
