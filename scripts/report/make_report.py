"""The benchmark report's driver (called by scripts/run-benchmarks.sh; docs/benchmarks.md).

  make_report.py --out DIR --build DIR [--quick] [--only PART] [--render-only]

Runs every part in scripts/report/parts/ (ordered by ORDER; --only: the one whose NAME is given),
then renders report.md from whatever data DIR holds: a part that was not run in this call keeps
the section of its last run in DIR, a part that never ran says so. Exits 1 when a part failed
(its section says why) so that a broken benchmark cannot pass unnoticed.
"""

import argparse
import datetime
import importlib.util
import json
import os
import platform
import re
import subprocess
import sys
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import report_lib  # noqa: E402


def load_parts():
    parts = []
    for path in sorted((HERE / "parts").glob("*.py")):
        if path.name.startswith("_"):
            continue
        spec = importlib.util.spec_from_file_location("report_part_" + path.stem, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        for attr in ("NAME", "TITLE", "ORDER", "run", "render"):
            if not hasattr(module, attr):
                raise SystemExit(f"make_report: {path} lacks {attr} (scripts/report/report_lib.py says what a part has)")
        parts.append(module)
    names = [p.NAME for p in parts]
    if len(set(names)) != len(names):
        raise SystemExit(f"make_report: two parts share a NAME: {names}")
    return sorted(parts, key=lambda p: p.ORDER)


def _cmd(args, default="unknown"):
    try:
        return subprocess.run(args, capture_output=True, text=True, timeout=20).stdout.strip() or default
    except (OSError, subprocess.SubprocessError):
        return default


def _package_version(pkg):
    return _cmd(["dpkg-query", "-W", "-f=${Version}", pkg])


def cpu_model():
    """The CPU as /proc/cpuinfo names it, with family, model and stepping: a VM's "AMD EPYC"
    alone does not tell one generation from the next."""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return "unknown"
    field = {k: (re.search(rf"^{k}\s*:\s*(.+)$", info, re.M) or [None, None])[1] for k in
             ("model name", "cpu family", "model", "stepping", "cache size")}
    name = (field["model name"] or "unknown").strip()
    ids = ", ".join(f"{k} {field[k].strip()}" for k in ("cpu family", "model", "stepping") if field[k])
    extra = "; ".join(x for x in (ids, f"cache {field['cache size'].strip()}" if field["cache size"] else "") if x)
    return f"{name} ({extra})" if extra else name


def compiler_text(build):
    """The C++ compiler of the Release tree, its version and the flags a Release build compiles with."""
    cache = Path(build) / "CMakeCache.txt"
    if not cache.exists():
        return "unknown (no CMakeCache.txt in the build tree)"
    text = cache.read_text()
    m = re.search(r"^CMAKE_CXX_COMPILER:\w+=(.+)$", text, re.M)
    version = _cmd([m.group(1).strip(), "--version"]).splitlines()[0] if m else "unknown"
    flags = " ".join(x for x in (re.search(rf"^{k}:\w+=(.*)$", text, re.M) for k in ("CMAKE_CXX_FLAGS", "CMAKE_CXX_FLAGS_RELEASE"))
                     if x for x in [x.group(1).strip()] if x)
    extra = " ".join(f"-D{k}={v}" for k, v in re.findall(r"^(BEMSURG_\w+):BOOL=(\w+)$", text, re.M) if k in
                     ("BEMSURG_NATIVE", "BEMSURG_USE_BLAS"))
    return f"{version}; flags {flags or '(none)'}" + (f"; {extra}" if extra else "")


def tree_state(repo):
    """(the commit's 12-digit hash, whether tracked files differ from it)."""
    commit = _cmd(["git", "-C", str(repo), "rev-parse", "--short=12", "HEAD"])
    dirty = _cmd(["git", "-C", str(repo), "status", "--porcelain", "--untracked-files=no"], default="")
    return commit, bool(dirty)


def load_average():
    try:
        return " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


# What every part's data depend on: the library, the build, the benchmark programs and the report's
# shared code. A part whose data ran at a commit before a change to any of these is stale; a change
# to the part's own file is not enough (it may only change the drawing), so the part file is left out.
# A part names the further files its data come from in its SOURCES (the organ peers: the CalculiX
# driver and the code they share), which make that part stale and no other.
DATA_SOURCES = ("include", "src", "benchmarks", "tests/support", "examples", "CMakeLists.txt", "cmake",
                "scripts/report/report_lib.py")


def stale_sources(repo, commit, head, extra=()):
    """The files under DATA_SOURCES and `extra` (a part's SOURCES) that changed between `commit` and
    `head` (empty: not stale)."""
    if not commit or commit == "unknown" or commit == head:
        return []
    try:  # a commit this repository does not hold (a shallow clone, rewritten history): not known current
        known = subprocess.run(["git", "-C", str(repo), "cat-file", "-e", commit + "^{commit}"], capture_output=True,
                               timeout=20).returncode == 0
    except (OSError, subprocess.SubprocessError):
        known = False
    if not known:
        return [f"(commit {commit} is not in this repository)"]
    out = _cmd(["git", "-C", str(repo), "diff", "--name-only", commit, head, "--", *DATA_SOURCES, *extra], default="")
    return [line for line in out.splitlines() if line.strip()]


def machine_header(ctx):
    """The facts a reader needs to compare this report with another one."""
    cpu = cpu_model()
    mem = "unknown"
    try:
        kb = int(re.search(r"^MemTotal:\s*(\d+)", Path("/proc/meminfo").read_text(), re.M).group(1))
        mem = f"{kb / 2**20:.1f} GiB"
    except (OSError, AttributeError):
        pass
    eigen = "unknown"
    macros = Path("/usr/include/eigen3/Eigen/src/Core/util/Macros.h")
    if macros.exists():
        t = macros.read_text()
        v = [re.search(rf"#define EIGEN_{k}_VERSION (\d+)", t) for k in ("WORLD", "MAJOR", "MINOR")]
        if all(v):
            eigen = ".".join(x.group(1) for x in v)
    compiler = compiler_text(ctx.build)
    blas = _cmd(["readlink", "-f", "/usr/lib/x86_64-linux-gnu/libblas.so.3"])
    commit, dirty = tree_state(ctx.repo)
    threads = os.environ.get("OMP_NUM_THREADS", f"{os.cpu_count()} (OpenMP default: one per core)")
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "mode": ctx.mode,
        "commit": commit + (" (with uncommitted changes)" if dirty else ""),
        "commit_hash": commit,
        "cpu": cpu,
        "cores": str(os.cpu_count()),
        "memory": mem,
        "os": _cmd(["sh", "-c", ". /etc/os-release && echo $PRETTY_NAME"], platform.platform()),
        "compiler": compiler,
        "eigen": eigen,
        "openblas": _package_version("libopenblas0") if _package_version("libopenblas0") != "unknown" else _package_version("libopenblas0-pthread"),
        "suitesparse": _package_version("libsuitesparse-dev"),
        "blas_backend": blas,
        "threads": threads,
        "calculix": _package_version("calculix-ccx"),
        "gmsh": _package_version("libgmsh-dev"),
        "matplotlib": _cmd([sys.executable, "-c", "import matplotlib; print(matplotlib.__version__)"]),
    }


HEADER_ROWS = [("Date", "date"), ("Mode", "mode"), ("Commit (drawn at)", "commit"), ("CPU", "cpu"), ("Cores", "cores"),
               ("Memory", "memory"), ("System", "os"), ("Compiler", "compiler"), ("Eigen", "eigen"),
               ("OpenBLAS", "openblas"), ("SuiteSparse", "suitesparse"), ("BLAS back end (libblas.so.3)", "blas_backend"),
               ("Threads", "threads"), ("CalculiX (ccx)", "calculix"), ("Gmsh", "gmsh"), ("matplotlib", "matplotlib")]


RENDER_FAILED = set()  # parts whose render() raised in this call (not kept in status.json)
STALE = {}  # part -> the data sources changed since its run (filled by write_report)


def write_report(ctx, parts, header, status):
    lines = ["# bemsurg benchmark report", "",
             "Generated by `scripts/run-benchmarks.sh" + (" --quick" if ctx.quick else "") + "` "
             "(docs/benchmarks.md says how to regenerate and read it). Every figure and chart below comes from "
             "this run's CSV files, written beside this page; ratios compare measurements of the same run.", "",
             "| | |", "|---|---|"]
    lines += [f"| {label} | {header.get(key, 'unknown')} |" for label, key in HEADER_ROWS]
    timed = [(p.NAME, status[p.NAME]["seconds"]) for p in parts
             if isinstance(status.get(p.NAME), dict) and status[p.NAME].get("seconds") is not None]
    lines += ["", "Where and when each part ran (a part is **stale** when the library, the build, its benchmark programs or "
              "the report's shared code changed after it ran: rerun it with `--only PART`). Load average: 1 / 5 / 15 min "
              "at the part's start (on 2 cores the report's own programs hold it near 1–2; more means another process shared the "
              "machine).", "",
              "| part | commit | ran | seconds | load average | state |", "|---|---|---|---|---|---|"]
    head = header.get("commit_hash", "")
    for p in parts:
        st = status.get(p.NAME)
        if not isinstance(st, dict):
            lines.append(f"| {p.NAME} | | never ran | | | not run |")
            continue
        changed = (stale_sources(ctx.repo, st.get("commit"), head, getattr(p, "SOURCES", ())) if "commit" in st
                   else ["(no commit recorded)"])
        if changed:
            STALE[p.NAME] = changed
        state = ("**stale**: " + ", ".join(changed[:3]) + (f" and {len(changed) - 3} more" if len(changed) > 3 else "")
                 if changed else "current")
        if st.get("dirty"):
            state += "; ran with uncommitted changes"
        if st.get("error"):
            state += "; **failed**"
        secs = f"{st['seconds']:.0f}" if st.get("seconds") is not None else ""
        lines.append(f"| {p.NAME} | {st.get('commit', 'unknown')} | {st.get('date', '')} | {secs} | "
                     f"{st.get('load_average_at_start', 'unknown')} | {state} |")
    compilers = {st.get("compiler") for st in status.values() if isinstance(st, dict) and st.get("compiler")}
    if len(compilers) > 1:
        lines += ["", "**The parts were built by different compilers or flags**: " + "; ".join(sorted(compilers)) + "."]
    cpus = {st.get("cpu") for st in status.values() if isinstance(st, dict) and st.get("cpu")}
    if len(cpus) > 1:
        lines += ["", "**The parts ran on different CPUs**: " + "; ".join(sorted(cpus)) + "."]
    if timed:
        lines += ["", f"Time of the parts' runs (the CalculiX reference counts only when it was not cached): "
                  f"{sum(t for _, t in timed) / 60:.1f} min in all — " + ", ".join(f"{n} {t:.0f} s" for n, t in timed) + "."]
    if ctx.quick:
        lines += ["", "**Quick mode**: small sizes and few repeats, to check that every chart renders. "
                  "The figures are not the published ones (docs/report.md holds the full run)."]
    lines += ["", "Contents: " + ", ".join(f"[{p.TITLE}](#{_anchor(p.TITLE)})" for p in parts), ""]
    for p in parts:
        lines += [f"## {p.TITLE}", ""]
        st = status.get(p.NAME)
        if st and st.get("error"):
            lines += [f"**This part failed in the last run**: `{st['error'].splitlines()[0]}` (DIR/logs/{p.NAME}.log).", ""]
        try:
            lines += [p.render(ctx).rstrip(), ""]
        except FileNotFoundError as e:
            lines += [f"*Not run yet* (`scripts/run-benchmarks.sh --only {p.NAME}`): {Path(e.filename).name} is missing.", ""]
        except Exception:  # a rendering bug must not hide the other parts
            lines += ["**Rendering failed:**", "", "```", traceback.format_exc(limit=3).strip(), "```", ""]
            RENDER_FAILED.add(p.NAME)
        if st and st.get("seconds") is not None:
            lines += [f"<sub>Part `{p.NAME}`: {st['seconds']:.0f} s (one run) in the run of {st['date']}.</sub>", ""]
    (ctx.out / "report.md").write_text("\n".join(lines))


def _anchor(title):
    a = re.sub(r"[^\w\- ]", "", title.lower()).strip().replace(" ", "-")
    return a


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--build", required=True)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", default=None)
    ap.add_argument("--render-only", action="store_true", help="draw the charts and report.md from DIR's data, run nothing")
    ap.add_argument("--require-complete", action="store_true",
                    help="fail unless DIR holds a full run of every part without a failure (what --publish needs)")
    a = ap.parse_args()
    ctx = report_lib.Context(a.out, a.build, HERE.parent.parent, a.quick)
    parts = load_parts()
    if a.only and a.only not in [p.NAME for p in parts]:
        raise SystemExit(f"run-benchmarks: --only {a.only}: no such part; the parts are: {', '.join(p.NAME for p in parts)}")
    status_path = ctx.out / "status.json"
    status = json.loads(status_path.read_text()) if status_path.exists() else {}
    if status.get("_mode") not in (None, ctx.mode):
        report_lib.warn(f"{ctx.out} holds a {status['_mode']} run; parts not run now keep their {status['_mode']} data")
    status["_mode"] = ctx.mode
    if a.require_complete and tree_state(ctx.repo)[1]:
        raise SystemExit("run-benchmarks: --publish needs a clean tree (commit or stash the changes to tracked files first): "
                         "every part records the commit it ran on, and a dirty tree's commit does not say what ran")
    failed = []
    for p in parts:
        if a.render_only or (a.only and p.NAME != a.only):
            continue
        print(f"run-benchmarks: part {p.NAME} ({p.TITLE})", flush=True)
        start = time.monotonic()
        commit, dirty = tree_state(ctx.repo)
        entry = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "mode": ctx.mode,
                 "commit": commit, "dirty": dirty, "load_average_at_start": load_average(),
                 "compiler": compiler_text(ctx.build), "cpu": cpu_model()}
        try:
            p.run(ctx)
        except Exception as e:  # noqa: BLE001: record, report, keep going with the other parts
            entry["error"] = str(e)
            failed.append(p.NAME)
            report_lib.warn(f"part {p.NAME} failed: {e}")
            traceback.print_exc()
        entry["seconds"] = time.monotonic() - start
        print(f"run-benchmarks: part {p.NAME} took {entry['seconds']:.0f} s", flush=True)
        status[p.NAME] = entry
        status_path.write_text(json.dumps(status, indent=1))
    header = machine_header(ctx)
    kept = ctx.out / "machine.json"
    if a.render_only and kept.exists():
        # Redrawing elsewhere (from docs/report-data, say) must not relabel the data with this
        # machine: keep the machine the parts ran on, refresh only when and at which commit it is drawn.
        header = dict(json.loads(kept.read_text()), date=header["date"], commit=header["commit"],
                      commit_hash=header["commit_hash"])
    kept.write_text(json.dumps(header, indent=1))
    write_report(ctx, parts, header, status)
    status_path.write_text(json.dumps(status, indent=1))
    broken = failed + sorted(RENDER_FAILED)
    print(f"run-benchmarks: wrote {ctx.out / 'report.md'}")
    if a.require_complete:
        incomplete = [p.NAME for p in parts if not isinstance(status.get(p.NAME), dict)
                      or status[p.NAME].get("mode") != "full" or status[p.NAME].get("error")
                      or status[p.NAME].get("dirty", True) or STALE.get(p.NAME)]
        if ctx.quick or incomplete:
            report_lib.warn("not publishing: no full, successful run of " + ", ".join(incomplete or ["(quick mode)"]))
            return 1
    if broken:
        report_lib.warn("failed: " + ", ".join(sorted(set(broken))))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
