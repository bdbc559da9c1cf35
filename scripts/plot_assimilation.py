#!/usr/bin/env python3
"""PNG plots of a `bcassim assimilate` or `bcassim validate` output directory.

Usage: plot_assimilation.py DIR

Draws from the CSV files present in DIR (docs/assimilation-format.md):
  parameters.png  each parameter's estimate with its ±σ band and the true value
                  (estimates.csv, parameters.csv); the free run is shaded (filter.csv)
  errors.png      mean validation error over time, estimated vs initial parameters (errors.csv)
Needs matplotlib only (no numpy import of its own). Exits 1 with one line on bad input.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def free_run_start(directory):
    """Time (s) after the last step that used observations, or None without a free run."""
    path = os.path.join(directory, "filter.csv")
    if not os.path.exists(path):
        return None
    rows = read_rows(path)
    observed = [float(r["time_s"]) for r in rows if int(r["observed_entries"]) > 0]
    if not rows or not observed or observed[-1] >= float(rows[-1]["time_s"]):
        return None
    return observed[-1]


def plot_parameters(directory):
    estimates = read_rows(os.path.join(directory, "estimates.csv"))
    truths = {}
    params_path = os.path.join(directory, "parameters.csv")
    if os.path.exists(params_path):
        for r in read_rows(params_path):
            t = float(r["truth"])
            if not math.isnan(t):
                truths[r["parameter"]] = t
    series = {}
    for r in estimates:
        s = series.setdefault(r["parameter"], ([], [], []))
        s[0].append(float(r["time_s"]))
        s[1].append(float(r["mean"]))
        s[2].append(float(r["stddev"]))
    if not series:
        return None
    free = free_run_start(directory)
    fig, axes = plt.subplots(len(series), 1, figsize=(8, 2.8 * len(series)), sharex=True,
                             squeeze=False)
    for ax, (name, (t, m, sd)) in zip(axes[:, 0], series.items()):
        lo = [a - b for a, b in zip(m, sd)]
        hi = [a + b for a, b in zip(m, sd)]
        ax.fill_between(t, lo, hi, alpha=0.3, label="±σ")
        ax.plot(t, m, label="estimate")
        if name in truths:
            ax.axhline(truths[name], color="k", linestyle="--", label="truth")
        if free is not None:
            ax.axvspan(free, t[-1], color="0.9", label="free run")
        ax.set_ylabel(name)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel("time (s)")
    fig.tight_layout()
    out = os.path.join(directory, "parameters.png")
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def plot_errors(directory):
    rows = read_rows(os.path.join(directory, "errors.csv"))
    if not rows:
        return None
    t = [float(r["time_s"]) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(t, [float(r["estimated_mean_mm"]) for r in rows], label="estimated parameters")
    ax.plot(t, [float(r["initial_mean_mm"]) for r in rows], label="initial parameters")
    free = free_run_start(directory)
    if free is not None:
        ax.axvspan(free, t[-1], color="0.9", label="free run")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mean validation error (mm)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    fig.tight_layout()
    out = os.path.join(directory, "errors.png")
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: plot_assimilation.py DIR (an assimilate or validate output directory)",
              file=sys.stderr)
        return 1
    directory = argv[1]
    written = []
    try:
        if os.path.exists(os.path.join(directory, "estimates.csv")):
            written.append(plot_parameters(directory))
        if os.path.exists(os.path.join(directory, "errors.csv")):
            written.append(plot_errors(directory))
    except (KeyError, ValueError, OSError) as e:
        print(f"plot_assimilation.py: {directory}: {e}", file=sys.stderr)
        return 1
    written = [w for w in written if w]
    print("plots: " + (", ".join(written) if written else "nothing to plot"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
