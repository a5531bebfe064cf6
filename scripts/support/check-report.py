"""Checks a benchmark report (scripts/run-benchmarks.sh) so that it cannot rot unnoticed (CI runs it
after the --quick report):

  check-report.py DIR

- every image report.md embeds exists and is a PNG that is not blank (more than one colour over a
  real share of its pixels, not one flat background);
- each of the chart families issue 24 asks for, and each stability study of issue 25, has at least
  one chart in its section;
- no section says that it failed or was not run.
Exit status 1 with one line per problem.
"""

import re
import sys
from pathlib import Path

from PIL import Image, ImageStat

# Section titles (parts' TITLE) that must hold at least one chart.
REQUIRED = {
    "Accuracy against cost": "the work-precision diagrams",
    "A finite-element peer: CalculiX on an organ": "the CalculiX comparison",
    "A second peer: the liver, hung and pressed": "the CalculiX comparison on the liver (issue 38)",
    "The paper's Table 1: re-solves after a cut": "Table 1",
    "Cut-step latency against n": "cut latency against n",
    "Precompute against n": "precompute against n",
    "Haptic force time and jitter": "the haptic distributions",
    "Preparing a segmentation: time and memory against input size": "prepare time and memory (issue 28)",
    "Beyond one machine: tables and the dense solve on MPI ranks": "time and memory per rank (issue 41)",
    # The stability studies of issue 25 (docs/stability.md): one section each, named as in the issue.
    "(a) Poisson's ratio towards 0.5": "stability study (a)",
    "(b) Interior points approaching the surface": "stability study (b)",
    "(c) Sliver triangles": "stability study (c)",
    "(d) Cut gap width against element size": "stability study (d)",
    "(e) GMRES restart length, BiCG and BiCGStab breakdowns": "stability study (e)",
    "(f) Accumulated low-rank updates after many cut steps": "stability study (f)",
    "(g) Thin parts and tool size against element size": "stability study (g)",
    "(h) Press depth against tool radius": "stability study (h)",
    "(i) Non-uniform meshes": "stability study (i)",
}
MIN_CHARTS = 15


def blank(path):
    """True when the picture is one flat colour or nearly so (an empty axes box still has ink)."""
    img = Image.open(path).convert("L")
    hist = img.histogram()
    total = sum(hist)
    background = max(hist)
    ink_share = 1.0 - background / total
    return ink_share < 0.01 or ImageStat.Stat(img).stddev[0] < 2.0


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    report = out / "report.md"
    if not report.exists():
        print(f"check-report: {report} does not exist", file=sys.stderr)
        return 1
    text = report.read_text()
    problems = []
    sections = re.split(r"^## ", text, flags=re.M)[1:]
    charts = 0
    seen = set()
    for s in sections:
        title = s.splitlines()[0].strip()
        seen.add(title)
        images = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", s)
        for rel in images:
            p = out / rel
            if not p.exists():
                problems.append(f"section '{title}': {rel} is missing")
            elif blank(p):
                problems.append(f"section '{title}': {rel} is blank")
            else:
                charts += 1
        if title in REQUIRED and not images:
            problems.append(f"section '{title}' has no chart ({REQUIRED[title]})")
        for marker in ("This part failed", "Not run yet", "Rendering failed"):
            if marker in s:
                problems.append(f"section '{title}': {marker}")
    for title, what in REQUIRED.items():
        if title not in seen:
            problems.append(f"no section '{title}' ({what})")
    if charts < MIN_CHARTS:
        problems.append(f"{charts} non-blank charts, at least {MIN_CHARTS} expected")
    for p in problems:
        print("check-report: " + p, file=sys.stderr)
    if not problems:
        print(f"check-report: {report}: {charts} charts, all sections present")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
