"""Scaffolding shared by the study scripts: running nfrc, reading its output, figures, tables."""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DPI = 130
MAX_FIGURE_BYTES = 300_000  # a figure larger than this is reported: keep the repository small


def parse_arguments(study, description):
    """Command line of a study named `study` (e.g. "contact"): --nfrc, --out, --force, --jobs,
    --figures, --markdown. Exits with a message if --nfrc is not executable."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--nfrc", default=os.path.join(REPO, "build", "nfrc"))
    parser.add_argument("--out", default=os.path.join(REPO, "out", study))
    parser.add_argument("--force", action="store_true", help="rerun finished runs too")
    parser.add_argument("--jobs", type=int, default=1,
                        help="runs in parallel (default 1; >1 distorts the timing table)")
    parser.add_argument("--figures", default=os.path.join(REPO, "docs", "figures", study))
    parser.add_argument("--markdown", default=os.path.join(REPO, "docs", f"{study}_results.md"))
    args = parser.parse_args()
    if not os.access(args.nfrc, os.X_OK):
        sys.exit(f"{study}_study: {args.nfrc} is not an executable (build nfrc, or --nfrc)")
    return args


def load(out, name, what="branch.json"):
    """A run's JSON output, or None if missing or unreadable (a status, not an error)."""
    try:
        with open(os.path.join(out, name, what)) as handle:
            return json.load(handle)
    except (OSError, json.JSONDecodeError):
        return None


def termination(document):
    return document.get("summary", {}).get("termination", "missing") if document else "missing"


def execute(command, directory):
    """Runs command with its output in directory/nfrc.log; returns (exit code, seconds)."""
    os.makedirs(directory, exist_ok=True)
    started = time.monotonic()
    with open(os.path.join(directory, "nfrc.log"), "w") as log:
        code = subprocess.call(command, stdout=log, stderr=log)
    return code, time.monotonic() - started


def save(figure, path, study):
    figure.savefig(path, dpi=DPI)
    plt.close(figure)
    size = os.path.getsize(path)
    if size > MAX_FIGURE_BYTES:
        print(f"{study}_study: warning: {path} is {size // 1000} kB (> 300 kB)")
    return path


def value_at(omega, values, target):
    """Linear interpolation of values (along the branch) at the first crossing of target."""
    for i in range(len(omega) - 1):
        lo, hi = omega[i], omega[i + 1]
        if (lo - target) * (hi - target) <= 0.0 and lo != hi:
            t = (target - lo) / (hi - lo)
            return values[i] + t * (values[i + 1] - values[i])
    return float("nan")


def fmt(value, digits=4):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    return f"{value:.{digits}g}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)
