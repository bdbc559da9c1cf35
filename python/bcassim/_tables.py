"""The CSV files runs write, read into NumPy arrays (format: docs/assimilation-format.md)."""
import numpy as np


def _read(path, columns):
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    table = np.atleast_1d(table)
    missing = [c for c in columns if c not in table.dtype.names]
    if missing:
        raise ValueError(f"{path}: expected columns {', '.join(columns)}; missing {', '.join(missing)}")
    return table


def read_hidden_points(path):
    """hidden_points.csv -> dict of arrays indexed [step, point]: time_s (steps), position (m,
    steps x points x 3), sigma (m, steps x points x 3), radius95_m and radius95_total_m."""
    t = _read(path, ["step", "time_s", "point", "x_m", "y_m", "z_m", "radius95_m"])
    steps = np.unique(t["step"])
    points = np.unique(t["point"])
    si = np.searchsorted(steps, t["step"])
    pi = np.searchsorted(points, t["point"])
    shape = (len(steps), len(points))
    out = {"step": steps, "time_s": np.zeros(len(steps)), "position": np.full(shape + (3,), np.nan),
           "sigma": np.full(shape + (3,), np.nan), "radius95_m": np.full(shape, np.nan)}
    out["time_s"][si] = t["time_s"]
    out["position"][si, pi] = np.column_stack([t["x_m"], t["y_m"], t["z_m"]])
    if "sigma_x_m" in t.dtype.names:
        out["sigma"][si, pi] = np.column_stack([t["sigma_x_m"], t["sigma_y_m"], t["sigma_z_m"]])
    out["radius95_m"][si, pi] = t["radius95_m"]
    if "radius95_total_m" in t.dtype.names:
        out["radius95_total_m"] = np.full(shape, np.nan)
        out["radius95_total_m"][si, pi] = t["radius95_total_m"]
    return out


def read_estimates(path):
    """estimates.csv -> dict name -> (step, time_s, mean, stddev) arrays, SI units."""
    t = _read(path, ["step", "time_s", "parameter", "mean", "stddev"])
    out = {}
    for name in dict.fromkeys(t["parameter"]):
        rows = t[t["parameter"] == name]
        out[str(name)] = {k: np.asarray(rows[k]) for k in ("step", "time_s", "mean", "stddev")}
    return out


def read_tracks(path):
    """markers.csv / validation.csv / hidden.csv (time,marker,x,y,z) -> (times, positions
    frames x points x 3), m."""
    t = _read(path, ["time", "marker", "x", "y", "z"])
    times = np.unique(t["time"])
    markers = np.unique(t["marker"])
    pos = np.full((len(times), len(markers), 3), np.nan)
    pos[np.searchsorted(times, t["time"]), np.searchsorted(markers, t["marker"])] = np.column_stack(
        [t["x"], t["y"], t["z"]])
    return times, pos
