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


def path(times):
    """theta at each of the increasing `times` (from 0): from the last solved (t, theta), Newton's method
    on t(theta) = t_last + the integral of 1/|theta'| from theta to theta_last."""
    thetas, t_last, theta_last = [], mp.mpf(0), mp.pi / 2
    for t in times:
        theta = theta_last - (t - t_last) * rate(theta_last)
        for _ in range(60):
            step = (t_last + mp.quad(lambda x: 1 / rate(x), [theta, theta_last]) - t) * rate(theta)
            theta += step
            if abs(step) < mp.mpf(10) ** -26:
                break
        thetas.append(theta)
        t_last, theta_last = t, theta
    return thetas


def main(paths):
    exact = {}
    for name in paths:
        with open(name) as f:
            rows = list(csv.DictReader(f))
        missing = sorted({r["t"] for r in rows} - exact.keys(), key=float)
        exact.update(zip(missing, path([mp.mpf(t) for t in missing])) if not exact else
                     ((t, path([mp.mpf(t)])[0]) for t in missing))
        worst, per_second = 0.0, {}
        for row in rows:
            theta = exact[row["t"]]
            dx = float(mp.mpf(row["b0.position.x"]) - mp.cos(theta))
            dy = float(mp.mpf(row["b0.position.y"]) - mp.sin(theta))
            d = (dx * dx + dy * dy) ** 0.5
            worst = max(worst, d)
            second = min(max(int(float(row["t"]) - 1e-9), 0), 9)
            per_second[second] = max(per_second.get(second, 0.0), d)
        theta = exact[rows[-1]["t"]]
        print(f"{name}: rows {len(rows)}, t_end {rows[-1]['t']}, largest |B0 - exact| {worst:.2e} m, "
              f"B0 x at the end {float(rows[-1]['b0.position.x']):.10f} (exact {float(mp.cos(theta)):.10f})")
        print("  largest per second: " + ", ".join(f"{per_second[s]:.1e}" for s in sorted(per_second)))


if __name__ == "__main__":
    main(sys.argv[1:])
