#!/usr/bin/env python3
"""Tutorial 2: a model written in Python, estimated with bcassim's ROUKF.

A damped oscillator m x'' + c x' + k x = F sin(w t) whose stiffness k (N/m) is unknown: only its
position x (m) is observed, with noise. The model is a bcassim.assimilation.ForecastModel
subclass, like a user's own simulator: forecast() advances one time step from any state and
parameter value; the filter (reduced-order UKF, thesis Alg. 2) estimates k in log space together
with the state.

    PYTHONPATH=build/python python3 examples/python/02_python_model_roukf.py --out out/py-oscillator
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from bcassim.assimilation import (Observation, ParameterTransform, Parameter,  # noqa: E402
                                  RoukfFilter, StochasticState, ForecastModel)

MASS, DAMPING, FORCE, OMEGA, DT = 1.0, 0.4, 2.0, 1.3, 0.02  # kg, N s/m, N, rad/s, s


class Oscillator(ForecastModel):
    """State [x (m), v (m/s)]; parameter k (N/m); observable x. Semi-implicit Euler steps."""

    def __init__(self):
        super().__init__()
        self.t = 0.0  # the model's reference time, advanced by end_step

    def state_size(self):
        return 2

    def observable_size(self):
        return 1

    def forecast(self, state, params):
        x, v = state
        k = params[0]
        a = (FORCE * np.sin(OMEGA * self.t) - DAMPING * v - k * x) / MASS
        v = v + DT * a
        x = x + DT * v
        return np.array([x, v]), np.array([x])

    def end_step(self, state, params):
        self.t += DT


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/py-oscillator", help="output folder")
    parser.add_argument("--small", action="store_true", help="a few seconds' version (tests)")
    args = parser.parse_args()
    steps = 400 if args.small else 2000
    os.makedirs(args.out, exist_ok=True)

    truth_k, noise = 5.0, 0.01  # N/m, m
    rng = np.random.default_rng(0)
    truth, observations = Oscillator(), []
    state = np.array([0.5, 0.0])
    for _ in range(steps):
        state, x = truth.forecast(state, [truth_k])
        truth.end_step(state, [truth_k])
        observations.append((state[0], x + noise * rng.standard_normal(1)))

    layout = StochasticState([0.5, 0.0], [0.01, 0.01],
                             [Parameter("k", 1.5, 1.0, ParameterTransform("exp"))])
    roukf = RoukfFilter(layout, Oscillator())
    history = []
    for _, y in observations:
        report = roukf.step(Observation(y, sigma=noise))
        history.append((report.mean[0], report.mean[2], report.stddev[2]))
    x_est, k, k_sd = np.array(history).T
    print(f"k = {k[-1]:.3f} ± {k_sd[-1]:.3f} N/m (truth {truth_k}, prior 1.5 ± 1.0); "
          f"position error {np.sqrt(np.mean((x_est - [x for x, _ in observations]) ** 2)):.4f} m "
          f"RMS (noise {noise} m)")

    t = DT * np.arange(1, steps + 1)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
    top.plot(t, [y[0] for _, y in observations], ".", ms=2, color="grey", label="observed x")
    top.plot(t, x_est, label="ROUKF x")
    top.set(ylabel="x (m)")
    top.legend(loc="upper right")
    bottom.fill_between(t, k - 1.96 * k_sd, k + 1.96 * k_sd, alpha=0.3, label="95 % band")
    bottom.plot(t, k, label="ROUKF k")
    bottom.axhline(truth_k, color="k", ls="--", label="truth")
    bottom.set(xlabel="time (s)", ylabel="k (N/m)", ylim=(0, 10))
    bottom.legend(loc="lower right")
    fig.tight_layout()
    plot = os.path.join(args.out, "oscillator.png")
    fig.savefig(plot, dpi=120)
    print(f"plot: {plot}")
    if abs(k[-1] - truth_k) > 0.01 * truth_k:
        raise SystemExit("k is not within 1 % of the truth")


if __name__ == "__main__":
    main()
