#!/usr/bin/env python3
"""Work-precision diagram of flexmb models: error against cost, per model and integrator.

Runs `flexmb run MODEL --integrator I --rtol TOL --atol TOL` for each integrator and tolerance, and a
reference (Adams at rtol = atol = 1e-12 unless --reference says otherwise), and measures the global
error the way docs/accuracy.md defines it:

    E = max over the position outputs' markers G of  max_{t,i in G} |y_i(t) - r_i(t)| / max_{t,i in G} |r_i(t)|

(t over the output times, i over the x, y, z columns of one `marker_position` or `node_position`
output). Prints one row per run (tolerance, E, E/tol, steps, rejected steps, Newton failures, residual
evaluations, factorizations, status) and writes an SVG diagram (E against steps, log-log) per model.

Usage: work_precision.py [--flexmb PATH] [--integrators bdf,adams,gen-alpha] [--tolerances 1e-3,...]
                         [--reference adams:1e-12] [--tolerance-span S] [--tag T] [--out DIR]
                         [--benchmarks] [--finest gen-alpha:1e-6] [--reuse] MODEL.toml...

--benchmarks adds the published benchmarks, every model of models/benchmarks/; --finest I:TOL runs
integrator I at no tolerance finer than TOL; --reuse reads the runs already in --out instead of
running them again.
"""
import argparse, csv, glob, json, math, os, subprocess, sys

COLOURS = {'bdf': '#1f77b4', 'adams': '#2ca02c', 'gen-alpha': '#d62728',
           'bdf per step': '#9ecae1', 'adams per step': '#a1d99b', 'gen-alpha per step': '#fc9272'}


def run(flexmb, model, integrator, tol, out, extra=(), reuse=False):
    name = os.path.splitext(os.path.basename(model))[0]
    cmd = [flexmb, 'run', model, '--integrator', integrator, '--rtol', repr(tol), '--atol', repr(tol), '--out', out, '-q', *extra]
    stderr = ''
    if not (reuse and os.path.exists(os.path.join(out, name + '.json'))):
        stderr = subprocess.run(cmd, capture_output=True, text=True).stderr
    summary = json.load(open(os.path.join(out, name + '.json')))
    rows = list(csv.DictReader(open(os.path.join(out, name + '.csv'))))
    return summary, rows, stderr.strip()


def position_groups(columns):
    groups = {}
    for c in columns:
        for axis in 'xyz':
            if c.endswith('.position.' + axis):
                groups.setdefault(c[:-2], []).append(c)
    return {g: cols for g, cols in groups.items() if len(cols) == 3}


def global_error(rows, reference):
    groups = position_groups(reference[0].keys())
    n = min(len(rows), len(reference))
    worst = 0.0
    for cols in groups.values():
        scale = max(abs(float(r[c])) for r in reference for c in cols)
        diff = max(abs(float(a[c]) - float(b[c])) for a, b in zip(rows[:n], reference[:n]) for c in cols)
        worst = max(worst, diff / scale if scale > 0 else diff)
    return worst, n


def svg(path, title, series):
    """series: {integrator: [(steps, error)]}; log-log axes."""
    pts = [p for s in series.values() for p in s if p[0] > 0 and p[1] > 0]
    if not pts:
        return
    lx = [math.log10(p[0]) for p in pts]
    ly = [math.log10(p[1]) for p in pts]
    x0, x1 = math.floor(min(lx)), math.ceil(max(lx))
    y0, y1 = math.floor(min(ly)), math.ceil(max(ly))
    x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)
    W, H, M = 520, 380, 60
    X = lambda v: M + (math.log10(v) - x0) / (x1 - x0) * (W - 2 * M)
    Y = lambda v: H - M - (math.log10(v) - y0) / (y1 - y0) * (H - 2 * M)
    o = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="11">' % (W, H),
         '<rect width="100%" height="100%" fill="white"/>',
         '<text x="%d" y="20" font-size="13">%s</text>' % (M, title)]
    for e in range(x0, x1 + 1):
        o.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (X(10**e), M, X(10**e), H - M))
        o.append('<text x="%.1f" y="%d" text-anchor="middle">1e%d</text>' % (X(10**e), H - M + 15, e))
    for e in range(y0, y1 + 1):
        o.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (M, Y(10**e), W - M, Y(10**e)))
        o.append('<text x="%d" y="%.1f" text-anchor="end">1e%d</text>' % (M - 4, Y(10**e) + 4, e))
    o.append('<text x="%d" y="%d" text-anchor="middle">steps</text>' % (W // 2, H - 20))
    o.append('<text x="14" y="%d" transform="rotate(-90 14 %d)" text-anchor="middle">global error E</text>' % (H // 2, H // 2))
    for k, (name, s) in enumerate(series.items()):
        s = [p for p in s if p[0] > 0 and p[1] > 0]
        c = COLOURS.get(name, '#555')
        if len(s) > 1:
            o.append('<polyline fill="none" stroke="%s" stroke-width="1.5" points="%s"/>' % (c, ' '.join('%.1f,%.1f' % (X(a), Y(b)) for a, b in s)))
        for a, b in s:
            o.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (X(a), Y(b), c))
        o.append('<text x="%d" y="%d" fill="%s">%s</text>' % (W - M - 60, M + 15 * k, c, name))
    o.append('</svg>')
    open(path, 'w').write('\n'.join(o))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('models', nargs='*')
    ap.add_argument('--benchmarks', action='store_true', help='add every model of models/benchmarks/')
    ap.add_argument('--flexmb', default='target/release/flexmb')
    ap.add_argument('--integrators', default='bdf,adams,gen-alpha')
    ap.add_argument('--tolerances', default='1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10')
    ap.add_argument('--reference', default='adams:1e-12', help='INTEGRATOR:TOL of the reference run')
    ap.add_argument('--out', default='out/work_precision')
    ap.add_argument('--tolerance-span', help='pass --tolerance-span to the runs (error per unit step); the reference runs without it')
    ap.add_argument('--tag', default='', help='suffix of the run directories and the diagram')
    ap.add_argument('--finest', action='append', default=[], help='INTEGRATOR:TOL, the finest tolerance to run INTEGRATOR at')
    ap.add_argument('--reuse', action='store_true', help='read the runs already in --out instead of running them again')
    a = ap.parse_args()
    if a.benchmarks:
        a.models += sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'models', 'benchmarks', '*.toml')))
    if not a.models:
        ap.error('no models: give MODEL.toml files or --benchmarks')
    ref_integrator, ref_tol = a.reference.split(':')
    tols = [float(t) for t in a.tolerances.split(',')]
    finest = {i: float(t) for i, t in (f.split(':') for f in a.finest)}
    print('%-22s %-9s %7s %10s %8s %8s %6s %7s %8s %6s %s' % ('model', 'method', 'tol', 'E', 'E/tol', 'steps', 'rej', 'newtonF', 'f-evals', 'LU', 'status'))
    for model in a.models:
        name = os.path.splitext(os.path.basename(model))[0]
        base = os.path.join(a.out, name)
        _, reference, err = run(a.flexmb, model, ref_integrator, float(ref_tol), os.path.join(base, 'reference'), reuse=a.reuse)
        if err:
            print('%s: reference: %s' % (name, err), file=sys.stderr)
        series = {}
        for integrator in a.integrators.split(','):
            for tol in tols:
                if tol < finest.get(integrator, 0.0):
                    continue
                extra = ['--tolerance-span', a.tolerance_span] if a.tolerance_span else []
                summary, rows, err = run(a.flexmb, model, integrator, tol, os.path.join(base, '%s_%g%s' % (integrator, tol, a.tag)), extra, a.reuse)
                s = summary['statistics']
                e, n = global_error(rows, reference)
                status = summary['status'] + ('' if n == len(reference) else ' (%d of %d rows)' % (n, len(reference)))
                print('%-22s %-9s %7.0e %10.2e %8.2f %8d %6d %7d %8d %6d %s' % (
                    name, integrator, tol, e, e / tol, s['steps'], s['rejected_steps'], s['newton_failures'],
                    s['residual_evaluations'], s['matrix_factorizations'], status), flush=True)
                if summary['status'] == 'completed':
                    series.setdefault(integrator, []).append((s['steps'], e))
        svg(os.path.join(base, name + a.tag + '_work_precision.svg'), '%s%s: global error against steps' % (name, a.tag), series)


if __name__ == '__main__':
    main()
