"""The cost of a Python callable as a force law against the same law as a built-in expression.

Runs models/pd_pendulum.toml (a pendulum held at an angle by a PD controller, T = -k_p (θ - θ_set) - k_d θ̇)
once with the file's expression and once with the same law as a Python callable (`Model.with_law`),
counts the callable's evaluations, and prints the wall time of each run (the best of `--repeat`), their
ratio, and the overhead per call: (callable run − expression run) / calls. It also times the law itself
called from Python (timeit), and the same law given its measures as a dict by name instead of the numpy
array, to split the overhead into the binding's part and the law's own.

    python3 python/bench/callable_overhead.py [--t-end 30] [--repeat 5]

from the repository's root, with the package installed (`pip install ./python`).
"""

import argparse
import pathlib
import time
import timeit

import numpy as np

import flexmb

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]


def best_of(repeat, run):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - start)
    return min(times), result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=30.0)
    parser.add_argument("--repeat", type=int, default=5)
    arguments = parser.parse_args()

    model = flexmb.load(REPOSITORY / "models" / "pd_pendulum.toml")
    k_p, k_d, theta_set = (model.parameters[name] for name in ("k_p", "k_d", "theta_set"))
    calls = [0]

    def law(t, measures):
        calls[0] += 1
        return -k_p * (measures[0] - theta_set) - k_d * measures[1]

    names = ["pivot_angle", "pivot_rate"]

    def law_by_name(t, measures):
        m = dict(zip(names, measures.tolist()))
        calls[0] += 1
        return -k_p * (m["pivot_angle"] - theta_set) - k_d * m["pivot_rate"]

    controlled = model.with_law("controller", law, measures=names)
    by_name = model.with_law("controller", law_by_name, measures=names)
    t_end = arguments.t_end
    expression_time, expression = best_of(arguments.repeat, lambda: model.simulate(t_end=t_end))
    calls[0] = 0
    callable_time, results = best_of(arguments.repeat, lambda: controlled.simulate(t_end=t_end))
    per_run = calls[0] // arguments.repeat
    calls[0] = 0
    by_name_time, _ = best_of(arguments.repeat, lambda: by_name.simulate(t_end=t_end))
    difference = np.max(np.abs(results.values - expression.values))
    values = np.array([0.4, 0.1])
    law_alone = min(timeit.repeat(lambda: law(0.1, values), number=100_000, repeat=5)) / 100_000
    array_alone = min(timeit.repeat(lambda: np.array([0.4, 0.1]), number=100_000, repeat=5)) / 100_000

    overhead = (callable_time - expression_time) / per_run
    print(f"model: pd_pendulum, t_end = {t_end} s, {expression.stats['steps']} steps, "
          f"{expression.stats['residual_evaluations']} residual evaluations; best of {arguments.repeat}")
    print(f"expression law:        {expression_time * 1e3:8.2f} ms")
    print(f"Python callable:       {callable_time * 1e3:8.2f} ms  ({per_run} calls, ratio {callable_time / expression_time:.2f}, "
          f"largest difference of the results {difference:.1e})")
    print(f"overhead per call:     {overhead * 1e6:8.2f} µs  (of which the law's own Python: {law_alone * 1e6:.2f} µs, "
          f"a numpy array of two made in Python: {array_alone * 1e6:.2f} µs)")
    print(f"measures as a dict:    {by_name_time * 1e3:8.2f} ms  ({(by_name_time - expression_time) / per_run * 1e6:.2f} µs per call)")


if __name__ == "__main__":
    main()
