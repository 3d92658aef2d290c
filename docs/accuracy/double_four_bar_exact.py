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
    python3 docs/accuracy/double_four_bar_exact.py --over-time OUT/double_four_bar.csv [...]

prints, per CSV (a flexmb run of the model with its b0.position output), the largest distance of B0
from the exact path over the output rows and over each second, and B0's x at the last row.

With --over-time it also prints, per output row, t, B0's distance from the exact path and its time lag
(theta - theta_exact) / |theta'| (positive: behind the exact motion), and per singular position (the
cranks horizontal, theta = -j pi; ten in the 10 s) the change of the lag across it (+-0.03 s, the output
rows nearest) and its drift since the last one. The lag separates the two sources of the error: a passage
that adds error makes the lag jump across it, the method's error on the smooth motion makes it drift
between them. An energy error dE changes the lag's rate by -dE / (3 theta'^2), so an error made anywhere
shows up as a drift that is fastest where the cranks are slow (the upper half-turn, between the 2nd and
3rd, 4th and 5th, ... positions): a passage's error often shows up after it, not across it.
Use an output step of 0.001 s (--output-step 0.001) to resolve the passages (a minute for 10,001 rows).
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


def singular_times():
    """The times of the singular positions in 10 s: theta(t) = -j pi (cranks horizontal), j = 0 .. 9, by
    Newton's method on t(theta) from theta = pi/2 at t = 0."""
    return [mp.quad(lambda x: 1 / rate(x), [-j * mp.pi, mp.pi / 2]) for j in range(10)]


def over_time(rows, exact, window=0.03):
    """Prints t, |B0 - exact| and the lag per row, then the lag's jump across each singular position and
    its drift between them."""
    import math
    lags = []
    print("  t, |B0 - exact| (m), lag (s)")
    for row in rows:
        theta_e = exact[row["t"]]
        x, y = float(row["b0.position.x"]), float(row["b0.position.y"])
        d = math.hypot(x - float(mp.cos(theta_e)), y - float(mp.sin(theta_e)))
        theta = math.atan2(y, x)
        theta += 2 * math.pi * round((float(theta_e) - theta) / (2 * math.pi))
        lag = (theta - float(theta_e)) / float(rate(theta_e))
        lags.append((float(row["t"]), lag))
        print(f"  {row['t']} {d:.3e} {lag:+.3e}")

    def lag_at(t):
        return min(lags, key=lambda p: abs(p[0] - t))[1]

    last = 0.0
    for j, ts in enumerate(float(t) for t in singular_times()):
        if ts + window > lags[-1][0]:
            break
        before, after = lag_at(ts - window), lag_at(ts + window)
        print(f"  position {j + 1} at t* = {ts:.6f} s: lag drift since the last {before - last:+.2e} s, "
              f"jump across it (+-{window} s) {after - before:+.2e} s")
        last = after
    print(f"  drift after the last: {lags[-1][1] - last:+.2e} s, lag at the end {lags[-1][1]:+.3e} s")


def main(paths):
    if not paths or any(p in ("-h", "--help") for p in paths):
        print(__doc__)
        return 0 if paths else 2
    per_row = "--over-time" in paths
    paths = [p for p in paths if p != "--over-time"]
    exact = {}
    for name in paths:
        try:
            with open(name) as f:
                rows = list(csv.DictReader(f))
        except OSError as e:
            print(f"{name}: cannot read it: {e.strerror}", file=sys.stderr)
            return 1
        if not rows or "b0.position.x" not in rows[0]:
            print(f"{name}: no rows with b0.position.x (a CSV of models/benchmarks/double_four_bar.toml is expected)",
                  file=sys.stderr)
            return 1
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
        if per_row:
            over_time(rows, exact)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
