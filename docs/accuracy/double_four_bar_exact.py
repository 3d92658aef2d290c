#!/usr/bin/env python3
"""The exact motion of the IFToMM A02 double four-bar (models/benchmarks/double_four_bar.toml) and the
error of flexmb's B0 path against it.

All links are 1 m, 1 kg; the cranks stay parallel and the couplers horizontal (the parallelogram branch,
on which the motion continues through every singular position), so the mechanism moves as one rigid
crank angle theta (from +x): kinetic energy 3/2 theta'^2 (three cranks of 1/3 kg m^2 about their pivots,
two couplers translating at theta'), potential energy 3.5 g sin(theta). With theta(0) = pi/2 and
theta'(0) = -1 rad/s the energy E0 = 1.5 + 3.5 g, theta' = -sqrt(2/3 (E0 - 3.5 g sin theta)) never
vanishes, and t(theta) is the integral of 1/|theta'| from theta to pi/2, evaluated here with mpmath at
30 digits and inverted by Newton's method: B0 = (cos theta, sin theta) to about 1e-25 m.

    python3 docs/accuracy/double_four_bar_exact.py OUT/double_four_bar.csv [...]

prints, per CSV (a flexmb run of the model with its b0.position output), the largest distance of B0
from the exact path over the output rows and over each second, and B0's x at the last row.
"""
import csv
import sys

import mpmath as mp

mp.mp.dps = 30
G = mp.mpf("9.81")
E0 = mp.mpf("1.5") + mp.mpf("3.5") * G


def rate(theta):
    return mp.sqrt(mp.mpf(2) / 3 * (E0 - mp.mpf("3.5") * G * mp.sin(theta)))


_cache = {}


def time_at(theta):
    """t(theta) for theta <= pi/2, integrated piecewise over quarter turns from pi/2."""
    start = mp.pi / 2
    t = mp.mpf(0)
    k = 0
    while True:
        end = start - mp.pi / 2
        if theta >= end:
            return t + mp.quad(lambda x: 1 / rate(x), [theta, start])
        if k not in _cache:
            _cache[k] = mp.quad(lambda x: 1 / rate(x), [end, start])
        t += _cache[k]
        start, k = end, k + 1


def theta_at(t, guess):
    theta = mp.mpf(guess)
    for _ in range(60):
        step = (time_at(theta) - t) * rate(theta)
        theta += step
        if abs(step) < mp.mpf(10) ** -26:
            break
    return theta


def main(paths):
    for path in paths:
        with open(path) as f:
            rows = list(csv.DictReader(f))
        worst, per_second, theta = 0.0, {}, mp.pi / 2
        for row in rows:
            t = mp.mpf(row["t"])
            theta = theta_at(t, theta - mp.mpf("0.01") * rate(theta) if t > 0 else theta)
            dx = float(mp.mpf(row["b0.position.x"]) - mp.cos(theta))
            dy = float(mp.mpf(row["b0.position.y"]) - mp.sin(theta))
            d = (dx * dx + dy * dy) ** 0.5
            worst = max(worst, d)
            second = min(int(float(t) - 1e-9), 9) if float(t) > 0 else 0
            per_second[second] = max(per_second.get(second, 0.0), d)
        print(f"{path}: rows {len(rows)}, t_end {rows[-1]['t']}, largest |B0 - exact| {worst:.2e} m, "
              f"B0 x at the end {rows[-1]['b0.position.x']} (exact {float(mp.cos(theta)):.10f})")
        print("  per second: " + ", ".join(f"{per_second[s]:.1e}" for s in sorted(per_second)))


if __name__ == "__main__":
    main(sys.argv[1:])
