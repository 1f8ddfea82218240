#!/usr/bin/python3
"""A real single-node Slurm cluster, started and stopped by this test
(scripts/slurm_cluster, docs/slurm-cluster.md).

Starts the cluster in a temporary directory, checks that a second start
says it is already running, submits a 6-task job array of 1 s tasks with at
most 2 at a time, waits until squeue no longer lists it, checks that every
array task is COMPLETED with exit code 0:0 (scontrol keeps finished jobs for
MinJobAge; there is no accounting, so no sacct), wrote its output file, and
that two tasks (no more) ran at once; then stops the cluster and checks that
no process of it remains and that a second stop exits 0. Any failure: exit 1.
Needs root and Slurm + munge installed (scripts/setup); without them the test
fails, it does not skip. About 9 s.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
CLUSTER = os.path.join(HERE, "slurm_cluster")
TASKS = 6


def run(args, env=None, check=True):
    p = subprocess.run(args, env=env, text=True, capture_output=True, timeout=120)
    if check and p.returncode != 0:
        raise AssertionError(f"{' '.join(args)} exited {p.returncode}\n"
                             f"stdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    return p


def alive(pid):
    """The process exists and is not a zombie (dead, not yet reaped)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def processes_mentioning(text):
    """Live processes whose command line, or a file they hold open, contains text
    (the cluster's directory: the daemons, slurmscriptd and slurmstepd hold its logs)."""
    pids = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace").strip()
            files = []
            for fd in os.listdir(f"/proc/{pid}/fd"):
                try:
                    files.append(os.readlink(f"/proc/{pid}/fd/{fd}"))
                except OSError:
                    pass
        except OSError:
            continue
        if (text in cmd or any(text in f for f in files)) and alive(pid):
            pids.append((int(pid), cmd))
    return pids


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--keep", action="store_true", help="keep the temporary directory")
    args = ap.parse_args()

    t0 = time.monotonic()
    d = tempfile.mkdtemp(prefix="gpusim-slurm-")
    os.chmod(d, 0o755)  # munged runs as the munge user and needs to reach cluster/munge
    cdir = os.path.join(d, "cluster")
    jobs = os.path.join(d, "jobs")
    os.makedirs(jobs)
    ok = False
    try:
        out = run([CLUSTER, "start", cdir]).stdout
        lines = dict(l.split("=", 1) for l in out.splitlines() if "=" in l)
        assert lines.get("SLURM_CONF") == os.path.join(cdir, "slurm.conf"), out
        assert lines.get("PARTITION") == "debug", out
        env = dict(os.environ, SLURM_CONF=lines["SLURM_CONF"])
        daemons = {}
        for name, pidfile in (("munged", "munge/munged.pid"), ("slurmctld", "run/slurmctld.pid"),
                              ("slurmd", "run/slurmd.pid")):
            with open(os.path.join(cdir, pidfile)) as f:
                daemons[name] = int(f.read().strip())
        print(f"test_slurm_cluster: started {daemons} in {time.monotonic() - t0:.1f} s")

        again = run([CLUSTER, "start", cdir])
        assert "already running" in again.stderr and again.stdout == out, again

        sinfo = run(["sinfo", "-h", "-o", "%P %T %D"], env).stdout.split()
        assert sinfo == ["debug*", "idle", "1"], sinfo

        job = run(["sbatch", "--parsable", f"--array=0-{TASKS - 1}%2", "-p", "debug",
                   f"--chdir={jobs}", "-o", os.path.join(jobs, "slurm-%A_%a.out"),
                   "--wrap", "echo $SLURM_ARRAY_TASK_ID > out_$SLURM_ARRAY_TASK_ID.txt; "
                   "t=$(date +%s.%N); sleep 1; echo $t $(date +%s.%N) > span_$SLURM_ARRAY_TASK_ID.txt"],
                  env).stdout.strip().split(";")[0]
        assert job.isdigit(), job
        deadline = time.monotonic() + 60
        max_running = 0
        while True:
            q = run(["squeue", "-h", "-j", job, "-o", "%i %T"], env).stdout.split("\n")
            q = [l for l in q if l.strip()]
            max_running = max(max_running, sum(l.endswith(" RUNNING") for l in q))
            if not q:
                break
            assert time.monotonic() < deadline, f"job array {job} not done after 60 s:\n" + "\n".join(q)
            time.sleep(0.2)
        assert max_running <= 2, f"squeue showed {max_running} tasks running at once despite %2"

        show = run(["scontrol", "-o", "show", "job", job], env).stdout.splitlines()
        states = {}
        for l in show:
            task = re.search(r"\bArrayTaskId=(\d+)\b", l)
            state = re.search(r"\bJobState=(\S+)", l)
            code = re.search(r"\bExitCode=(\S+)", l)
            assert task and state and code, l
            states[int(task.group(1))] = (state.group(1), code.group(1))
        assert states == {i: ("COMPLETED", "0:0") for i in range(TASKS)}, states

        for i in range(TASKS):
            with open(os.path.join(jobs, f"out_{i}.txt")) as f:
                assert f.read() == f"{i}\n", f"out_{i}.txt"
            assert os.path.exists(os.path.join(jobs, f"slurm-{job}_{i}.out")), i
        # %2: two of the 1 s tasks (no more) overlap, from the times they wrote.
        spans = []
        for i in range(TASKS):
            with open(os.path.join(jobs, f"span_{i}.txt")) as f:
                spans.append(tuple(map(float, f.read().split())))
        overlap = max(sum(a <= t < b for a, b in spans) for t, _ in spans)
        want = min(2, len(os.sched_getaffinity(0)))  # the node has nproc CPUs
        assert overlap == want, f"{overlap} tasks overlapped (want {want} with %2): {spans}"
        print(f"test_slurm_cluster: job array {job}: {TASKS} tasks COMPLETED 0:0, "
              f"2 at a time, outputs right")
        ok = True
    finally:
        stop = run([CLUSTER, "stop", cdir], check=False)
        if stop.returncode != 0:
            print(f"test_slurm_cluster: stop exited {stop.returncode}:\n{stop.stderr}", file=sys.stderr)
            ok = False
        if not ok:
            for log in ("munged.log", "slurmctld.log", "slurmd.log"):
                p = os.path.join(cdir, "log", log)
                if os.path.exists(p):
                    with open(p, errors="replace") as f:
                        print(f"---- {p} (end)\n" + "".join(f.readlines()[-20:]), file=sys.stderr)

    left = processes_mentioning(cdir)
    left += [(pid, name) for name, pid in daemons.items() if alive(pid)
             and pid not in [p for p, _ in left]]
    assert not left, f"still running after stop: {left}"
    again = run([CLUSTER, "stop", cdir])  # stopping a stopped cluster: exit 0
    assert not os.path.exists(os.path.join(cdir, "munge", "munge.socket")), "munge socket left"
    if args.keep:
        print(f"test_slurm_cluster: kept {d}")
    else:
        shutil.rmtree(d)
    print(f"test_slurm_cluster: passed in {time.monotonic() - t0:.1f} s")


if __name__ == "__main__":
    try:
        main()
    except (AssertionError, OSError, subprocess.SubprocessError) as e:
        print(f"test_slurm_cluster: FAILED: {e}", file=sys.stderr)
        sys.exit(1)
