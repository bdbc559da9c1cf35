#!/usr/bin/env python3
"""Compares the POINT messages OpenIGTLink's ReceiveClient printed (stderr) with an offline
run's hidden_points.csv: one message per step 1..STEPS, in order, every hidden point's position
and 95 % radius within 1e-6 m. Usage: compare_received.py CLIENT_TXT HIDDEN_POINTS_CSV STEPS"""
import csv
import re
import sys

TOL_M = 1e-6


def messages(path):
    out, stamp, current = [], None, None
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("Time stamp: "):
            stamp = float(line.split(": ")[1])
        elif line == "Receiving POINT data type.":
            current = {"stamp": stamp, "points": {}}
            out.append(current)
        elif current is not None and line.startswith(" Name "):
            name = line.split(": ", 1)[1]
            current["points"][name] = {}
            last = current["points"][name]
        elif current is not None and line.startswith(" Position "):
            x, y, z = (float(v) for v in re.findall(r"-?\d+\.\d+", line))
            last["position_m"] = (x / 1e3, y / 1e3, z / 1e3)
        elif current is not None and line.startswith(" Radius "):
            last["radius_m"] = float(line.split(": ")[1]) / 1e3
    return out


def main():
    received = messages(sys.argv[1])
    steps = int(sys.argv[3])
    offline = {}
    for row in csv.DictReader(open(sys.argv[2])):
        offline[(int(row["step"]), int(row["point"]))] = row
    if len(received) != steps:
        sys.exit(f"received {len(received)} hidden-point messages, expected {steps} (one per step)")
    stamps = [m["stamp"] for m in received]
    if stamps != sorted(stamps) or len(set(stamps)) != len(stamps):
        sys.exit(f"messages out of order: stamps {stamps}")
    worst = 0.0
    for k, m in enumerate(received, start=1):
        for name, p in m["points"].items():
            i = int(name.split("_")[1])
            row = offline[(k, i)]
            want = (float(row["x_m"]), float(row["y_m"]), float(row["z_m"]))
            err = max(abs(a - b) for a, b in zip(p["position_m"], want))
            err = max(err, abs(p["radius_m"] - float(row["radius95_total_m"])))
            worst = max(worst, err)
            if err > TOL_M:
                sys.exit(f"step {k} {name}: received {p}, offline {want} "
                         f"radius {row['radius95_total_m']} (off by {err:.3g} m)")
    points = len(received[0]["points"])
    print(f"end to end: {len(received)} messages in order, {points} hidden points each, "
          f"largest difference from the offline run {worst:.3g} m (tolerance {TOL_M:g} m)")


main()
