"""The speed-up of a 16-variant sweep on local processes and on a local Ray instance against the same
sweep run serially, in wall time (docs/python.md, "Sweeps"; docs/performance.md).

    python python/bench/sweep_speedup.py [--repeat 5] [--workers 2] [--t-end 20] [--ray]

The sweep: models/pendulum.toml, 4 lengths × 2 masses × 2 integrators (BDF, Adams) over --t-end
seconds at rtol 1e-8. Each repetition runs the serial sweep and the parallel one in turn (paired, so
that a drift of the machine's speed moves both), and prints the medians: the serial wall time, the
parallel wall time and their ratio. The wall time is the whole `flexmb.sweep` call: on processes it
includes starting the pool and each worker loading the model file; Ray's start (`ray.init`) is
outside it, done once as a user would.
"""

import argparse
import pathlib
import statistics

import flexmb

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]


def one_sweep(executor, t_end, workers):
    return flexmb.sweep(
        REPOSITORY / "models" / "pendulum.toml",
        {"L": [0.5, 1.0, 2.0, 4.0], "m_bob": [1.0, 2.0]},
        integrators=["bdf", "adams"],
        outputs={"quarter_period": ("pivot_angle", "first_zero")},
        t_end=t_end,
        rtol=1e-8,
        atol=1e-8,
        executor=executor,
        workers=workers,
    )


def paired(executor, label, arguments):
    one_sweep("serial", arguments.t_end, None)  # warm-up: page cache, imports
    serial, parallel, ratios = [], [], []
    for _ in range(arguments.repeat):
        s = one_sweep("serial", arguments.t_end, None)
        p = one_sweep(executor, arguments.t_end, arguments.workers)
        assert not p.failures and [r["steps"] for r in p.rows] == [r["steps"] for r in s.rows]
        serial.append(s.wall_time)
        parallel.append(p.wall_time)
        ratios.append(s.wall_time / p.wall_time)
    integration = sum(row["wall_time"] for row in s.rows)
    print(
        f"{label:<28} serial {statistics.median(serial):7.3f} s  parallel {statistics.median(parallel):7.3f} s  "
        f"speed-up {statistics.median(ratios):.2f}× (min {min(ratios):.2f}, max {max(ratios):.2f}; "
        f"{arguments.repeat} pairs; the serial runs' integration {integration:.3f} s)"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--t-end", type=float, default=20.0)
    parser.add_argument("--ray", action="store_true", help="also on a local Ray instance (ray.init(num_cpus=workers))")
    arguments = parser.parse_args()
    paired(None, f"processes ({arguments.workers} workers)", arguments)
    if arguments.ray:
        import ray

        ray.init(num_cpus=arguments.workers, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
        try:
            paired("ray", f"Ray ({arguments.workers} CPUs)", arguments)
        finally:
            ray.shutdown()


if __name__ == "__main__":
    main()
