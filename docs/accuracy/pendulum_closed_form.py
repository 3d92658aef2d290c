#!/usr/bin/env python3
"""Global error of runs of the IFToMM A01 pendulum (models/benchmarks/simple_pendulum.toml) against
its closed-form solution, instead of a tight run.

Released from rest at the angle θ0 from the hanging position, a compound pendulum swings as

    sin(θ/2) = k sn(K(m) − ω0 t | m),   k = sin(θ0/2), m = k², ω0 = √(M g L / I_pivot)

(sn, dn the Jacobi elliptic functions, K the complete elliptic integral of the first kind), so its
point P1 at distance L from the pivot is at x = 2 L k sn dn, y = −L (1 − 2 m sn²). For A01, θ0 = 90°,
L = 1 m, M = 1 kg, I_pivot = M L² + 1e-9 kg m² (the lumped mass's own inertia), g = 9.81 m/s².

Prints, for each run directory holding simple_pendulum.csv and .json (as work_precision.py writes
them), E = max over the output times of |P1 − P1_exact| / L (the global error of docs/accuracy.md:
L is the largest coordinate of the reference), the steps and the status.

Usage: pendulum_closed_form.py DIR...   (e.g. out/work_precision/simple_pendulum)
"""
import csv, glob, json, os, sys

import mpmath as mp

mp.mp.dps = 30
G, L, M = mp.mpf('9.81'), mp.mpf(1), mp.mpf(1)
I_PIVOT = M * L**2 + mp.mpf('1e-9')
PARAMETER = mp.sin(mp.pi / 4) ** 2      # m = k², θ0 = 90°
QUARTER = mp.ellipk(PARAMETER)          # K(m): a quarter period in ω0 t
OMEGA0 = mp.sqrt(M * G * L / I_PIVOT)


def p1(t):
    u = QUARTER - OMEGA0 * mp.mpf(t)
    sn = mp.ellipfun('sn', u, m=PARAMETER)
    dn = mp.ellipfun('dn', u, m=PARAMETER)
    k = mp.sqrt(PARAMETER)
    return float(2 * L * k * sn * dn), float(-L * (1 - 2 * PARAMETER * sn**2))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    exact = {}
    for directory in sys.argv[1:]:
        for path in sorted(glob.glob(os.path.join(directory, '*', 'simple_pendulum.csv'))):
            worst = 0.0
            for row in csv.DictReader(open(path)):
                if row['t'] not in exact:
                    exact[row['t']] = p1(row['t'])
                x, y = exact[row['t']]
                worst = max(worst, abs(float(row['p1.position.x']) - x), abs(float(row['p1.position.y']) - y))
            summary = json.load(open(path[:-len('.csv')] + '.json'))
            print('%-40s E %9.2e  steps %8d  %s' % (os.path.relpath(os.path.dirname(path), directory), worst / float(L),
                                                   summary['statistics']['steps'], summary['status']), flush=True)


if __name__ == '__main__':
    main()
