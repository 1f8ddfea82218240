"""Reads a trace directory written by `gpusim run SCENE --trace DIR`.

The formats are docs/traces.md's: manifest.json, stats.json, signals.vcd,
transactions.bin and fragments.bin. Binary files are memory-mapped as numpy
structured arrays, so a large trace costs what the caller touches.

Errors in the input raise TraceError with a one-line message naming the file;
the scripts print it and exit 2 (`fail`).

Needs Debian's python3 (/usr/bin/python3) with numpy.
"""

import json
import os
import re
import sys

import numpy as np

HEADER_SIZE = 16
RECORD_SIZE = 48
FORMAT = "gpusim-trace"
VERSION = 1  # of the binary record files
MANIFEST_VERSION = 2  # of manifest.json: stages list their "inputs", FIFOs their "kind"

# The formats `gpusim run --trace-formats` can write (docs/traces.md).
ALL_FORMATS = ("vcd", "timeline", "transactions", "fragments")

# transactions.bin record, little endian, 48 bytes.
TX_DTYPE = np.dtype([
    ("cycle_in", "<u8"),
    ("cycle_out", "<u8"),
    ("prim_first", "<i8"),
    ("prim_last", "<i8"),
    ("draw", "<u4"),
    ("stage", "<u2"),
    ("kind", "u1"),
    ("prim_kind", "u1"),  # what the item's primitives are at its stage (PRIM_KIND_NAMES)
    ("tile_x", "<i2"),
    ("tile_y", "<i2"),
    ("count", "<u4"),
])
TX_MAGIC = b"GPUSIMTX"
TX_WORK, TX_CLEAR, TX_END_OF_FRAME = 0, 1, 2
# prim_kind: 0 for control tokens and in traces written before the field (the
# byte was reserved, 0).
PRIM_KIND_NAMES = {0: "primitive", 1: "point", 2: "line", 3: "triangle"}
NO_DRAW = 0xFFFFFFFF

# fragments.bin record, little endian, 48 bytes.
FR_DTYPE = np.dtype([
    ("cycle", "<u8"),
    ("prim", "<i8"),
    ("x", "<u2"),
    ("y", "<u2"),
    ("stage", "u1"),
    ("unit", "u1"),
    ("outcome", "u1"),
    ("reserved", "u1"),
    ("depth", "<f4"),
    ("old_depth", "<f4"),
    ("value", "<f4", (4,)),
])
FR_MAGIC = b"GPUSIMFR"
FR_TEST, FR_WRITE = 0, 1  # fragments.bin `stage`: the site, as manifest `fragments` names it
assert TX_DTYPE.itemsize == RECORD_SIZE and FR_DTYPE.itemsize == RECORD_SIZE



class TraceError(Exception):
    """Bad input: the message is one line, naming the file."""


def fail(prog, message, code=2):
    """Prints `prog: message` on one line to stderr and exits `code`."""
    text = " ".join(str(message).split())
    print(f"{prog}: {text}", file=sys.stderr)
    sys.exit(code)


def _read_records(path, magic, dtype, expected):
    """Memory-maps a record file after checking its header and length."""
    name = os.path.basename(path)
    try:
        size = os.path.getsize(path)
        with open(path, "rb") as f:
            header = f.read(HEADER_SIZE)
    except OSError as e:
        raise TraceError(f"{path}: cannot read: {e.strerror}")
    if len(header) < HEADER_SIZE:
        raise TraceError(f"{path}: truncated header ({len(header)} of {HEADER_SIZE} bytes)")
    if header[:8] != magic:
        raise TraceError(f"{path}: not a {name} file (magic {header[:8]!r}, expected {magic.decode()})")
    version = int.from_bytes(header[8:12], "little")
    record_size = int.from_bytes(header[12:16], "little")
    if version != VERSION:
        raise TraceError(f"{path}: version {version}, this reader knows version {VERSION}")
    if record_size != dtype.itemsize:
        raise TraceError(f"{path}: record size {record_size}, expected {dtype.itemsize}")
    body = size - HEADER_SIZE
    if body % record_size:
        raise TraceError(f"{path}: truncated: {body} bytes after the header is not a whole number of "
                         f"{record_size}-byte records")
    count = body // record_size
    if expected is not None and count != expected:
        raise TraceError(f"{path}: {count} records, manifest.json says {expected}")
    if count == 0:
        return np.zeros(0, dtype=dtype)
    return np.memmap(path, dtype=dtype, mode="r", offset=HEADER_SIZE, shape=(count,))


def _load_json(path):
    try:
        with open(path, "r", encoding="utf-8") as f:
            return json.load(f)
    except FileNotFoundError:
        raise TraceError(f"{path}: no such file")
    except OSError as e:
        raise TraceError(f"{path}: cannot read: {e.strerror}")
    except ValueError as e:
        raise TraceError(f"{path}: not valid JSON: {e}")


class Trace:
    """One trace directory. Files are read on first use."""

    def __init__(self, directory):
        self.dir = directory
        if not os.path.exists(directory):
            raise TraceError(f"{directory}: no such directory")
        if not os.path.isdir(directory):
            raise TraceError(f"{directory}: not a directory")
        mpath = self.path("manifest.json")
        if not os.path.isfile(mpath):
            # The likeliest mix-up, a run's --out directory, is named as such
            # (the same words as gpusim's TraceReader).
            looks_like_out = any(os.path.exists(os.path.join(directory, f))
                                 for f in ("stats.json", "frame.exr"))
            raise TraceError(f"{directory}: not a trace directory (no manifest.json; write one with "
                             f"gpusim run SCENE --trace DIR)"
                             + (" (this looks like a run's --out directory)" if looks_like_out else ""))
        m = _load_json(mpath)
        if not isinstance(m, dict) or m.get("format") != FORMAT:
            raise TraceError(f"{mpath}: not a gpusim trace manifest (format is not \"{FORMAT}\")")
        if m.get("version") != MANIFEST_VERSION:
            raise TraceError(f"{mpath}: version {m.get('version')}, this reader knows version "
                             f"{MANIFEST_VERSION}")
        try:
            fb = m["framebuffer"]
            self.width, self.height = int(fb["width"]), int(fb["height"])
            self.tile_size = int(fb["tile_size"])
            self.tiles_x, self.tiles_y = int(fb["tiles_x"]), int(fb["tiles_y"])
            self.units = int(m["units"])
            self.cycles = int(m["cycles"])
            self.stages = list(m["stages"])
            self.fifos = list(m["fifos"])
            for i, s in enumerate(self.stages):
                if int(s["index"]) != i:
                    raise TraceError(f"{mpath}: stages[{i}] has index {s['index']}")
                s["name"], s["kind"]  # noqa: B018 (presence)
            for i, f in enumerate(self.fifos):
                if int(f["index"]) != i:
                    raise TraceError(f"{mpath}: fifos[{i}] has index {f['index']}")
                f["name"], int(f["depth"])  # noqa: B018
        except (KeyError, TypeError, ValueError) as e:
            raise TraceError(f"{mpath}: missing or malformed field {e}")
        # The stages that are the memory's clients, by name; None in traces
        # written before the netlist listed them.
        self.memory_clients = ([c["stage"] for c in m["memory_clients"]]
                               if "memory_clients" in m else None)
        self.manifest = m
        self.filters = m.get("filters") or {}
        self.records = m.get("records") or {}
        # What `run --trace-formats` wrote; traces written before it have all.
        self.formats = list(m.get("formats") or ALL_FORMATS)
        self._stats = None
        self._tx = None
        self._fr = None
        self._vcd = None

    def path(self, name):
        return os.path.join(self.dir, name)

    def _recorded(self, fmt, name):
        """The path of `name`, or a TraceError in gpusim's words when the run
        left format `fmt` out."""
        if fmt not in self.formats:
            raise TraceError(f"{self.dir}: {name} was not recorded (--trace-formats "
                             f"{','.join(self.formats)}); rerun gpusim run --trace with {fmt} in "
                             f"--trace-formats")
        return self.path(name)

    # -- manifest helpers ---------------------------------------------------

    @property
    def scene(self):
        return self.manifest.get("scene", "?")

    @property
    def config(self):
        return self.manifest.get("config") or {}

    def window(self):
        """The traced cycles [start, end): the window filter clamped to the frame."""
        w = self.filters.get("window")
        start, end = 0, self.cycles
        if w:
            if w[0] is not None:
                start = max(0, min(int(w[0]), self.cycles))
            if w[1] is not None:
                end = max(start, min(int(w[1]), self.cycles))
        return start, end

    def stage_units(self):
        """numpy array: stage index -> unit (-1 for front-end stages)."""
        return np.array([-1 if s.get("unit") is None else int(s["unit"]) for s in self.stages],
                        dtype=np.int64)

    def filtered(self):
        return any(self.filters.get(k) is not None for k in ("stages", "window", "prims"))

    def describe_filters(self):
        """'--trace-window 1000:5000, --trace-prims 3:9' or '' when unfiltered."""
        parts = []
        st = self.filters.get("stages")
        if st is not None:
            kept = set(st)
            # A kind whose every unit is kept is named by its kind (rop, not rop_0,rop_1,...).
            names = []
            for s in self.stages:
                name, kind = s["name"], s["kind"]
                if name not in kept:
                    continue
                whole = s.get("unit") is not None and all(
                    o["name"] in kept for o in self.stages if o["kind"] == kind)
                shown = kind if whole else name
                if shown not in names:
                    names.append(shown)
            names += [n for n in st if n not in {x["name"] for x in self.stages}]
            shown = ",".join(names) if len(names) <= 8 else ",".join(names[:8]) + f",... ({len(st)} stages)"
            parts.append(f"--trace-stages {shown}")
        w = self.filters.get("window")
        if w is not None:
            a = "" if w[0] is None else str(w[0])
            b = "" if w[1] is None else str(w[1])
            parts.append(f"--trace-window {a}:{b}")
        p = self.filters.get("prims")
        if p is not None:
            parts.append(f"--trace-prims {p[0]}:{p[1]}")
        return ", ".join(parts)

    def stage_kept(self, name):
        st = self.filters.get("stages")
        return st is None or name in st

    # -- files --------------------------------------------------------------

    def stats(self):
        if self._stats is None:
            self._stats = _load_json(self.path("stats.json"))
        return self._stats

    def transactions(self):
        """Structured array (TX_DTYPE), memory-mapped."""
        if self._tx is None:
            tx = _read_records(self._recorded("transactions", "transactions.bin"), TX_MAGIC, TX_DTYPE,
                               self.records.get("transactions"))
            if len(tx) and int(tx["stage"].max()) >= len(self.stages):
                raise TraceError(f"{self.path('transactions.bin')}: a record names stage "
                                 f"{int(tx['stage'].max())}, the manifest has {len(self.stages)}")
            self._tx = tx
        return self._tx

    def fragments(self):
        """Structured array (FR_DTYPE), memory-mapped."""
        if self._fr is None:
            self._fr = _read_records(self._recorded("fragments", "fragments.bin"), FR_MAGIC, FR_DTYPE,
                                     self.records.get("fragments"))
        return self._fr

    def vcd(self):
        if self._vcd is None:
            self._vcd = read_vcd(self._recorded("vcd", "signals.vcd"),
                                 int(self.manifest.get("cycle_ps") or 0))
        return self._vcd


def open_trace(directory):
    return Trace(directory)


# -- VCD ----------------------------------------------------------------------


class Signal:
    """One VCD variable: a step function of time (cycles).

    `times` (int64, increasing) and `values` (int64; x/z read as -1): the
    value is values[i] from times[i] until times[i + 1].
    """

    def __init__(self, scope, name, width, code):
        self.scope = scope      # ("gpu", "primitive_setup")
        self.name = name        # "busy"
        self.width = width
        self.code = code
        self.times = None
        self.values = None

    @property
    def path(self):
        return ".".join(self.scope + (self.name,))

    def value_at(self, t):
        i = np.searchsorted(self.times, t, side="right") - 1
        return None if i < 0 else int(self.values[i])

    def cumulative(self, x):
        """The integral of the signal from its first change to each time in `x`
        (any order). Before the first change the value is unknown and counts
        as 0; x and z count as 0. Returns a float64 array shaped as `x`."""
        x = np.asarray(x, dtype=np.int64)
        t = self.times
        v = np.where(self.values < 0, 0, self.values).astype(np.float64)
        if len(t) == 0:
            return np.zeros(x.shape)
        # Cumulative integral at each change time.
        cum = np.concatenate(([0.0], np.cumsum(np.diff(t).astype(np.float64) * v[:-1])))
        k = np.searchsorted(t, x, side="right") - 1
        kk = np.clip(k, 0, None)
        return np.where(k < 0, 0.0, cum[kk] + v[kk] * (x - t[kk]))

    def integrate(self, edges):
        """The integral of the signal over each [edges[k], edges[k+1]) (see
        cumulative). Returns float64 array of len(edges) - 1."""
        return np.diff(self.cumulative(edges))

    def minmax(self, edges):
        """Per bin [edges[k], edges[k+1]): (min, max) of the values held."""
        edges = np.asarray(edges, dtype=np.int64)
        t, v = self.times, np.where(self.values < 0, 0, self.values)
        n = len(edges) - 1
        lo = np.zeros(n)
        hi = np.zeros(n)
        if len(t) == 0:
            return lo, hi
        # Value held at each bin start, then every change inside the bin.
        k0 = np.searchsorted(t, edges[:-1], side="right") - 1
        start_val = np.where(k0 < 0, 0, v[np.clip(k0, 0, None)]).astype(np.float64)
        lo[:] = start_val
        hi[:] = start_val
        inside = (t >= edges[0]) & (t < edges[-1])
        if inside.any():
            b = np.searchsorted(edges, t[inside], side="right") - 1
            vals = v[inside].astype(np.float64)
            np.minimum.at(lo, b, vals)
            np.maximum.at(hi, b, vals)
        return lo, hi


class Vcd:
    def __init__(self):
        self.timescale = None
        self.comments = []
        self.signals = []           # every variable, in declaration order
        self.end_time = 0           # last time stamp seen

    def find(self, *scope_and_name):
        """The signal at scope path + name, e.g. find('gpu', 'rop_0', 'busy'), or None."""
        want = tuple(scope_and_name)
        for s in self.signals:
            if s.scope + (s.name,) == want:
                return s
        return None

    def stage_state(self, stage, state):
        """Stage `stage`'s 1-bit wire `state` (busy, stalled, starved), or None: `<stage>_<state>`
        in a scope named as the stage (gpu.unit_0.rop_0.rop_0_busy), or, in traces written before
        units were grouped, `<state>` in gpu.<stage>."""
        for s in self.signals:
            if s.scope and s.scope[-1] == stage and s.name == f"{stage}_{state}":
                return s
        return self.find("gpu", stage, state)

    def fifo(self, name):
        """FIFO `name`'s occupancy: the vector named as the FIFO in its group's scope
        (gpu.unit_0.rasterizer_to_depth_0), or in gpu.fifos (traces written before)."""
        for s in self.signals:
            if s.name == name and len(s.scope) == 2 and s.scope[0] == "gpu":
                return s
        return None

    def scopes(self):
        """Scope paths in declaration order (without duplicates)."""
        seen = []
        for s in self.signals:
            if s.scope not in seen:
                seen.append(s.scope)
        return seen


def _vcd_header_tokens(f, path):
    """Yields the header's tokens, up to and including $enddefinitions ... $end."""
    for line in f:
        for tok in line.split():
            yield tok
            if tok == "$enddefinitions":
                for line2 in f:
                    if "$end" in line2.split():
                        return
                return
    raise TraceError(f"{path}: not a VCD file (no $enddefinitions)")


_TIME_UNITS_FS = {"fs": 1, "ps": 10**3, "ns": 10**6, "us": 10**9, "ms": 10**12, "s": 10**15}


def vcd_units_per_cycle(vcd, cycle_ps, path="signals.vcd"):
    """VCD time units per clock cycle of `cycle_ps` picoseconds: the period
    over the $timescale, which must divide it; 1 for traces written before
    signals.vcd was in simulated time (their $comment says so)."""
    if any("one time unit is one clock cycle" in c for c in vcd.comments):
        return 1
    m = re.fullmatch(r"(1|10|100) ?(fs|ps|ns|us|ms|s)", vcd.timescale or "")
    if not m:
        raise TraceError(f"{path}: $timescale {vcd.timescale!r} is not a time unit")
    unit = int(m.group(1)) * _TIME_UNITS_FS[m.group(2)]
    if cycle_ps * 1000 % unit:
        raise TraceError(f"{path}: the clock period, {cycle_ps} ps, is not a whole number of "
                         f"$timescale units ({vcd.timescale})")
    return cycle_ps * 1000 // unit


def read_vcd(path, cycle_ps=0):
    """Parses an IEEE 1364 VCD file (the subset gpusim writes, and a bit more).

    Scalars 0/1/x/z and vectors bNNN; reals are skipped. The header is read
    as tokens, the value changes line by line into compact arrays. Times are
    the file's, or with `cycle_ps` (the clock period, picoseconds) clock
    cycles (vcd_units_per_cycle; a time stamp off a cycle boundary is an
    error). Returns a Vcd.
    """
    from array import array
    try:
        f = open(path, "r", encoding="ascii", errors="replace")
    except FileNotFoundError:
        raise TraceError(f"{path}: no such file")
    except OSError as e:
        raise TraceError(f"{path}: cannot read: {e.strerror}")
    with f:
        vcd = Vcd()
        by_code = {}
        scope = []
        toks = _vcd_header_tokens(f, path)

        def until_end():
            body = []
            for t in toks:
                if t == "$end":
                    return body
                body.append(t)
            raise TraceError(f"{path}: truncated header")

        for tok in toks:
            if tok == "$enddefinitions":
                break
            if tok == "$scope":
                body = until_end()  # module NAME
                if len(body) < 2:
                    raise TraceError(f"{path}: malformed $scope")
                scope.append(body[1])
            elif tok == "$upscope":
                until_end()
                if not scope:
                    raise TraceError(f"{path}: $upscope without $scope")
                scope.pop()
            elif tok == "$var":
                body = until_end()  # TYPE WIDTH CODE NAME [RANGE]
                if len(body) < 4:
                    raise TraceError(f"{path}: malformed $var: {' '.join(body)}")
                try:
                    width = int(body[1])
                except ValueError:
                    raise TraceError(f"{path}: malformed $var width: {' '.join(body)}")
                name = body[3]
                if "[" in name and not name.startswith("["):
                    name = name[:name.index("[")]
                sig = Signal(tuple(scope), name, width, body[2])
                vcd.signals.append(sig)
                by_code.setdefault(body[2], []).append(sig)
            elif tok == "$timescale":
                vcd.timescale = "".join(until_end())
            elif tok == "$comment":
                vcd.comments.append(" ".join(until_end()))
            elif tok.startswith("$"):
                until_end()  # $date, $version, ...
        per_cycle = vcd_units_per_cycle(vcd, cycle_ps, path) if cycle_ps else 1
        # Value changes.
        times = {c: array("q") for c in by_code}
        values = {c: array("q") for c in by_code}
        t = 0
        scalar = {"0": 0, "1": 1, "x": -1, "X": -1, "z": -1, "Z": -1}
        in_comment = False
        lineno = 0
        for line in f:
            lineno += 1
            parts = line.split()
            k = 0
            while k < len(parts):
                tok = parts[k]
                if in_comment:
                    if tok == "$end":
                        in_comment = False
                    k += 1
                    continue
                c = tok[0]
                if c == "#":
                    try:
                        t, off = divmod(int(tok[1:]), per_cycle)
                    except ValueError:
                        raise TraceError(f"{path}: bad time stamp {tok!r}")
                    if off:
                        raise TraceError(f"{path}: time stamp {tok} is not on a clock cycle boundary "
                                         f"({per_cycle} time units per cycle)")
                    k += 1
                elif c in scalar:
                    code = tok[1:]
                    tt = times.get(code)
                    if tt is None:
                        raise TraceError(f"{path}: value change for undeclared code {code!r} at time {t}")
                    tt.append(t)
                    values[code].append(scalar[c])
                    k += 1
                elif c == "b" or c == "B":
                    if k + 1 >= len(parts):
                        raise TraceError(f"{path}: vector value without a code at time {t}")
                    code = parts[k + 1]
                    tt = times.get(code)
                    if tt is None:
                        raise TraceError(f"{path}: value change for undeclared code {code!r} at time {t}")
                    try:
                        val = int(tok[1:], 2)
                    except ValueError:
                        val = -1
                    tt.append(t)
                    values[code].append(val)
                    k += 2
                elif c == "r" or c == "R":
                    k += 2
                elif c == "$":
                    if tok == "$comment":
                        in_comment = True
                    k += 1  # $dumpvars, $end, $dumpall, ...
                else:
                    raise TraceError(f"{path}: unexpected token {tok!r} at time {t}")
    vcd.end_time = t
    for code, sigs in by_code.items():
        tt = np.frombuffer(times[code], dtype=np.int64) if len(times[code]) else np.zeros(0, np.int64)
        vv = np.frombuffer(values[code], dtype=np.int64) if len(values[code]) else np.zeros(0, np.int64)
        # Keep the last value of several changes at one time.
        if len(tt) > 1:
            last = np.ones(len(tt), dtype=bool)
            last[:-1] = tt[1:] != tt[:-1]
            tt, vv = tt[last], vv[last]
        for s in sigs:
            s.times, s.values = tt, vv
    return vcd


def bin_edges(start, end, max_bins=400):
    """Integer bin edges covering [start, end) with at most max_bins bins of equal width."""
    span = max(1, end - start)
    width = max(1, -(-span // max_bins))
    # Round the width up to 1, 2 or 5 times a power of ten.
    mag = 1
    while True:
        for m in (1, 2, 5):
            if m * mag >= width:
                width = m * mag
                break
        else:
            mag *= 10
            continue
        break
    edges = np.arange(start, end, width, dtype=np.int64)
    edges = np.append(edges, end)
    return edges, width


def write_atomically(path, write):
    """Calls write(tmp_path), then renames tmp_path to path."""
    directory = os.path.dirname(os.path.abspath(path))
    base = os.path.basename(path)
    stem, ext = os.path.splitext(base)
    tmp = os.path.join(directory, f".{stem}.tmp{os.getpid()}{ext}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
