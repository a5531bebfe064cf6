"""What every part of the benchmark report shares (scripts/run-benchmarks.sh, docs/benchmarks.md).

A part is a module in scripts/report/parts/ with NAME, TITLE, ORDER and two functions:
``run(ctx)`` measures (runs benchmark programs, writes CSV under ``ctx.part_dir(NAME)``) and
``render(ctx)`` draws its charts from those CSV files alone and returns its Markdown section.
Adding a study, an element type or a solver is adding a part or a series inside one: nothing
else changes.

The CSV schema (docs/benchmarks.md, "The report's data"): one header row, one column per
parameter (strings or numbers), then one column per metric (numbers; SI units, seconds and bytes,
errors as fractions, not per cent); an empty cell is "not measured".
"""

import csv
import gzip
import hashlib
import json
import math
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display: CI and headless machines
import matplotlib.pyplot as plt  # noqa: E402

THRESHOLDS = (0.10, 0.05, 0.01)  # the errors a user picks a model by (item 2 of issue 24)


class PartFailed(RuntimeError):
    """A benchmark program failed: the message names the command and ends with its stderr."""


class Context:
    """Where a report run reads and writes: the output folder, the built programs, the mode."""

    def __init__(self, out, build, repo, quick):
        self.out = Path(out).resolve()
        self.build = Path(build).resolve()
        self.bin = self.build / "bin"
        self.repo = Path(repo).resolve()
        self.quick = quick
        self.mode = "quick" if quick else "full"
        (self.out / "images").mkdir(parents=True, exist_ok=True)
        (self.out / "logs").mkdir(parents=True, exist_ok=True)
        (self.out / "cache").mkdir(parents=True, exist_ok=True)

    # ---- where things go ------------------------------------------------------------------
    def part_dir(self, name):
        """DIR/<part>/: the part's CSV files (and any raw JSON the programs wrote)."""
        d = self.out / name
        d.mkdir(parents=True, exist_ok=True)
        return d

    def image(self, name):
        """DIR/images/<name>.png; report.md refers to it as images/<name>.png."""
        return self.out / "images" / (name + ".png")

    def program(self, name):
        p = self.bin / name
        if not p.exists():
            raise PartFailed(f"{p} does not exist: build the Release tree first (scripts/run-benchmarks.sh builds it)")
        return str(p)

    # ---- running programs -------------------------------------------------------------------
    def _start_log(self, args, part, env):
        """The child's environment (ours plus env) and the part's log, with the command appended."""
        full_env = dict(os.environ)
        if env:
            full_env.update({k: str(v) for k, v in env.items()})
        log = self.out / "logs" / (part + ".log")
        with open(log, "a") as lf:
            lf.write("$ " + " ".join(shlex.quote(str(a)) for a in args) + "\n")
        return full_env, log

    def run(self, args, part, env=None, timeout=None, cwd=None):
        """Run one command to completion, logging it and its stderr to DIR/logs/<part>.log;
        returns (stdout, seconds). A failure raises PartFailed with the end of its stderr."""
        full_env, log = self._start_log(args, part, env)
        start = time.monotonic()
        proc = subprocess.Popen([str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=full_env,
                                cwd=cwd, text=True)
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            stdout, stderr = proc.communicate()
            raise PartFailed(f"{' '.join(map(str, args))}: timed out after {timeout} s")
        seconds = time.monotonic() - start
        with open(log, "a") as lf:
            lf.write(stderr[-4000:] + f"[exit {proc.returncode}, {seconds:.2f} s]\n")
        if proc.returncode != 0:
            tail = "\n".join(stderr.strip().splitlines()[-15:])
            raise PartFailed(f"{' '.join(map(str, args))} exited with {proc.returncode}:\n{tail}")
        return stdout, seconds

    def run_isolated(self, args, part, env=None, timeout=None):
        """Run one configuration in a process of its own and return (stdout, seconds,
        peak_rss_bytes): the peak resident memory of that process alone (below)."""
        full_env, log = self._start_log(args, part, env)
        out_path = self.out / "logs" / (part + ".stdout.tmp")
        err_path = self.out / "logs" / (part + ".stderr.tmp")
        start = time.monotonic()
        hwm = 0
        with open(out_path, "w") as so, open(err_path, "w") as se:
            proc = subprocess.Popen([str(a) for a in args], stdout=so, stderr=se, env=full_env)
            deadline = None if timeout is None else start + timeout
            while True:
                hwm = max(hwm, _vm_hwm_bytes(proc.pid))
                pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
                if pid != 0:
                    break
                if deadline is not None and time.monotonic() > deadline:
                    proc.kill()
                    os.wait4(proc.pid, 0)
                    raise PartFailed(f"{' '.join(map(str, args))}: timed out after {timeout} s")
                time.sleep(0.01)
        proc.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.monotonic() - start
        stdout = out_path.read_text()
        stderr = err_path.read_text()
        with open(log, "a") as lf:
            lf.write(stderr[-4000:] + f"[exit {proc.returncode}, {seconds:.2f} s, peak {usage.ru_maxrss} KiB]\n")
        if proc.returncode != 0:
            tail = "\n".join(stderr.strip().splitlines()[-15:])
            raise PartFailed(f"{' '.join(map(str, args))} exited with {proc.returncode}:\n{tail}")
        # The peak is the child's own VmHWM, polled every 10 ms (the kernel keeps it per address
        # space: it starts afresh at exec). wait4's ru_maxrss is not used when a poll succeeded:
        # Linux carries the high-water mark across fork and exec, so a small program would report
        # the driver's own size. A program that ends before the first poll falls back to it.
        return stdout, seconds, (hwm if hwm > 0 else usage.ru_maxrss * 1024)  # ru_maxrss: KiB

    # ---- cached references ------------------------------------------------------------------
    def cache(self, name, key):
        """DIR/cache/<name>-<hash of key>/ and whether it holds a finished result. ``key`` is a
        JSON-able dict of every input the result depends on (sizes, versions, script hashes);
        a change of any of them gives a new folder, so a stale reference is never reused."""
        digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]
        d = self.out / "cache" / f"{name}-{digest}"
        d.mkdir(parents=True, exist_ok=True)
        (d / "key.json").write_text(json.dumps(key, indent=1, sort_keys=True))
        return d, (d / "done").exists()

    @staticmethod
    def mark_cached(d):
        (Path(d) / "done").write_text(time.strftime("%Y-%m-%dT%H:%M:%S") + "\n")


def _vm_hwm_bytes(pid):
    """The process's peak resident memory so far (/proc/PID/status VmHWM), 0 when unreadable."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def file_digest(*paths):
    """A short hash of files' contents: part of a cache key when a script or input changes."""
    h = hashlib.sha256()
    for p in paths:
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


# ---- CSV -------------------------------------------------------------------------------------
def write_csv(path, rows, columns):
    """Rows (dicts) under the given columns; None and NaN are written as an empty cell."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in rows:
            cells = []
            for c in columns:
                v = r.get(c)
                if v is None or (isinstance(v, float) and math.isnan(v)):
                    cells.append("")
                elif isinstance(v, float):
                    cells.append(repr(v))
                else:
                    cells.append(str(v))
            w.writerow(cells)


def data_path(path):
    """A data file's path, or its gzipped copy's (docs/report-data/ keeps files over 1 MB gzipped)."""
    path = Path(path)
    gz = path.with_name(path.name + ".gz")
    return gz if not path.exists() and gz.exists() else path


def read_csv(path):
    """The rows of a report CSV as dicts: numbers as float (int when integral), empty as None.
    Reads PATH.gz when only that exists (the published data, docs/benchmarks.md)."""
    rows = []
    path = data_path(path)
    opener = gzip.open if path.suffix == ".gz" else open
    with opener(path, "rt", newline="") as f:
        for r in csv.DictReader(f):
            rows.append({k: _number(v) for k, v in r.items()})
    return rows


def _number(v):
    if v is None or v == "":
        return None
    try:
        x = float(v)
    except ValueError:
        return v
    if x.is_integer() and "." not in v and "e" not in v.lower() and "inf" not in v.lower():
        return int(x)
    return x


# ---- charts ---------------------------------------------------------------------------------
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "<", ">"]


def new_figure(width=6.4, height=4.4):
    fig, ax = plt.subplots(figsize=(width, height), dpi=110)
    ax.grid(True, which="both", alpha=0.3)
    return fig, ax


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def pareto_front(points):
    """Indices of the points (cost, error) that no other point beats in both (cost first)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        c, e = points[i]
        if c is None or e is None or not (c > 0 and e > 0):
            continue
        if e < best:
            front.append(i)
            best = e
    return front


def work_precision(ax, series, cost_label, error_label, annotate=None, cost_range=None, style=None):
    """A work-precision diagram on ax: log-log, error (y) against cost (x), one series per method
    (``series``: {label: [(cost, error, row), ...]}, in refinement order), the Pareto front over
    all series drawn as a step line. Returns the front's points as (cost, error, label, row).
    ``cost_range(row)`` -> (low, high) or None draws the cost's spread (min-max over the runs) as a
    horizontal bar; ``style(label)`` -> matplotlib keywords (colour, marker) fixes a family's look.
    The legend goes outside the axes, right of the data."""
    everything = []
    for k, (label, pts) in enumerate(series.items()):
        pts = [p for p in pts if p[0] and p[1] and p[0] > 0 and p[1] > 0]
        if not pts:
            continue
        kw = {"marker": MARKERS[k % len(MARKERS)], "alpha": 0.85}
        kw.update(style(label) if style else {})
        line = ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, **kw)[0]
        if cost_range:
            for p in pts:
                rng = cost_range(p[2])
                if rng and rng[0] and rng[1] and rng[1] > rng[0]:
                    ax.plot([rng[0], rng[1]], [p[1], p[1]], color=line.get_color(), lw=1.0, alpha=0.7)
        if annotate:
            for p in pts:
                ax.annotate(annotate(p[2]), (p[0], p[1]), fontsize=6, alpha=0.7, xytext=(3, 3), textcoords="offset points")
        everything += [(p[0], p[1], label, p[2]) for p in pts]
    front = [everything[i] for i in pareto_front([(c, e) for c, e, _, _ in everything])]
    if front:
        xs, ys = [f[0] for f in front], [f[1] for f in front]
        ax.step(xs, ys, where="post", color="black", lw=2.2, alpha=0.35, label="Pareto front", zorder=0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(cost_label)
    ax.set_ylabel(error_label)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return front


def median(values):
    """The median of a non-empty list of numbers."""
    v = sorted(values)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def spread_text(med, low, high, runs, fmt=None):
    """'12.3 ms (11.9–13.0 ms, 5 runs)', or '12.3 s (one run)': a timing with its spread (issue 37)."""
    fmt = fmt or seconds_text
    if not runs or runs <= 1 or low is None or high is None:
        return f"{fmt(med)} (one run)"
    return f"{fmt(med)} ({fmt(low)}–{fmt(high)}, {int(runs)} runs)"


def cheapest_table(rows, error_key, cost_keys, describe, thresholds=THRESHOLDS):
    """Markdown: for each threshold, the configuration with the least cost_keys[0] whose
    error_key is at or below it, with every cost in cost_keys ({key: (heading, formatter)}, or
    (heading, formatter, True) for a formatter of the whole row)."""
    heads = " | ".join(v[0] for v in cost_keys.values())
    lines = [f"| error ≤ | configuration | {heads} |", "|---|---|" + "---|" * len(cost_keys)]
    first = next(iter(cost_keys))
    for t in thresholds:
        ok = [r for r in rows if r.get(error_key) is not None and r[error_key] <= t and r.get(first)]
        if not ok:
            lines.append(f"| {t:.0%} | none of the configurations measured reaches it |" + " |" * len(cost_keys))
            continue
        best = min(ok, key=lambda r: r[first])
        # (heading, formatter) formats the cost itself; (heading, formatter, row=True) formats the row
        # (a timing shown with its spread).
        cells = " | ".join(v[1](best) if len(v) > 2 and v[2] else v[1](best.get(k)) for k, v in cost_keys.items())
        lines.append(f"| {t:.0%} | {describe(best)} | {cells} |")
    return "\n".join(lines)


def seconds_text(s):
    if s is None:
        return "–"
    if s < 1e-3:
        return f"{s * 1e6:.3g} µs"
    if s < 1:
        return f"{s * 1e3:.3g} ms"
    return f"{s:.3g} s"


def bytes_text(b):
    if b is None:
        return "–"
    if b >= 2**30:
        return f"{b / 2**30:.3g} GiB"
    return f"{b / 2**20:.3g} MiB"


def fit_exponent(ns, ts):
    """Least-squares slope of log t against log n (the exponent p of t ≈ c n^p), or None."""
    pts = [(math.log(n), math.log(t)) for n, t in zip(ns, ts) if n and t and n > 0 and t > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return None
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def warn(msg):
    print("run-benchmarks: " + msg, file=sys.stderr)


def run_stability_study(ctx, part, study, timeout=1800):
    """Runs one study of bench_stability (issue 25, docs/stability.md) into DIR/<part>/ (--quick in
    the quick report) and returns its JSON summary (the threshold found and the behaviour there)."""
    d = ctx.part_dir(part)
    summary = d / "summary.json"
    args = [ctx.program("bench_stability"), "--study", study, "--csv-dir", d, "--json", summary]
    if ctx.quick:
        args.append("--quick")
    ctx.run(args, part, timeout=timeout)
    return json.loads(summary.read_text())["studies"][study]


def read_stability_summary(ctx, part, study):
    """The JSON summary run_stability_study left in DIR/<part>/ (for render)."""
    return json.loads((ctx.part_dir(part) / "summary.json").read_text())["studies"][study]
