#!/usr/bin/env python3
"""PNG plots of a `bcassim liver run` output directory.

Usage: plot_liver.py DIR

  liver_errors.png   inner validation error over time (mean and max over the 12 points) of the
                     coarse model with the estimated springs, with the prior springs, and with the
                     ligament as fixed nodes (errors_over_time.csv), as thesis Fig. 5.3/5.4
  tumours.png        each tumour's 95 % uncertainty radius from the filter over time, and the
                     distance between its prediction and the truth (estimate/hidden_points.csv,
                     truth/hidden.csv)
Needs matplotlib only. Exits 1 with one line on bad input.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_errors(directory):
    rows = read_rows(os.path.join(directory, "errors_over_time.csv"))
    t = [float(r["time_s"]) for r in rows]
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ax, kind in zip(axes, ("mean", "max")):
        for name, label, colour in (("estimated", "estimated springs", "tab:green"),
                                    ("prior", "prior springs", "tab:orange"),
                                    ("fixed", "fixed ligament (baseline)", "tab:blue")):
            ax.plot(t, [float(r[f"{name}_{kind}_mm"]) for r in rows], label=label, color=colour)
        ax.set_ylabel(f"{kind} error (mm)")
        ax.grid(alpha=0.3)
    axes[0].legend()
    axes[0].set_title("inner validation points vs ground truth")
    axes[1].set_xlabel("time (s)")
    fig.tight_layout()
    out = os.path.join(directory, "liver_errors.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def read_truth_tracks(path):
    frames = {}
    for r in read_rows(path):
        frames.setdefault(float(r["time"]), {})[int(r["marker"])] = (
            float(r["x"]), float(r["y"]), float(r["z"]))
    return frames


def plot_tumours(directory):
    path = os.path.join(directory, "estimate", "hidden_points.csv")
    if not os.path.exists(path):
        return None
    rows = read_rows(path)
    truth_path = os.path.join(directory, "truth", "hidden.csv")
    truth = read_truth_tracks(truth_path) if os.path.exists(truth_path) else {}
    times = sorted(truth)
    series = {}
    for r in rows:
        i = int(r["point"])
        t = float(r["time_s"])
        s = series.setdefault(i, ([], [], [], []))
        s[0].append(t)
        s[1].append(1e3 * float(r["radius95_m"]))
        s[3].append(1e3 * float(r.get("radius95_total_m", r["radius95_m"])))
        err = float("nan")
        if times:
            nearest = min(times, key=lambda x: abs(x - t))
            if abs(nearest - t) < 1e-6 and i in truth[nearest]:
                p = truth[nearest][i]
                err = 1e3 * math.dist(p, (float(r["x_m"]), float(r["y_m"]), float(r["z_m"])))
        s[2].append(err)
    fig, ax = plt.subplots(figsize=(8, 5))
    for i, (t, radius, err, total) in sorted(series.items()):
        line, = ax.plot(t, total, label=f"tumour {i}: 95 % radius (with model error)")
        ax.plot(t, radius, ":", color=line.get_color(),
                label=f"tumour {i}: 95 % radius (parameters only)")
        ax.plot(t, err, "--", color=line.get_color(), label=f"tumour {i}: distance to truth")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mm")
    ax.set_title("hidden tumours: filter uncertainty and actual error")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.18))
    fig.tight_layout()
    out = os.path.join(directory, "tumours.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main():
    if len(sys.argv) != 2:
        print("usage: plot_liver.py DIR", file=sys.stderr)
        return 1
    directory = sys.argv[1]
    try:
        written = [p for p in (plot_errors(directory), plot_tumours(directory)) if p]
    except (OSError, KeyError, ValueError) as e:
        print(f"plot_liver.py: {directory}: {e}", file=sys.stderr)
        return 1
    print("plots: " + ", ".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
