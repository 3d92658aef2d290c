#!/usr/bin/env python3
"""An independent reader of flexmb's ParaView output: reads a .pvd series and every .vtu it names with
meshio (not vtkio, which wrote them), and checks them against the run's CSV.

    check_vtk.py SERIES.pvd RESULTS.csv [--block=NAME=POINTS:CELLS ...] [--node=BODY:LABEL:TIME]

--block  every frame's block NAME has POINTS points and CELLS cells;
--node   at time TIME, the point of block BODY whose `node` label is LABEL is at the CSV's
         BODY.nodeLABEL.position.x/y/z and moves with BODY.nodeLABEL.velocity.x/y/z.

Prints what it checked and exits 0, or prints the first mismatch and exits 1.
"""

import argparse
import csv
import os
import sys
import xml.etree.ElementTree as ElementTree

import meshio


def fail(message):
    print(f"check_vtk: {message}")
    sys.exit(1)


def read_series(pvd):
    """The DataSet entries: (time, name, path), in file order."""
    root = ElementTree.parse(pvd).getroot()
    if root.get("type") != "Collection":
        fail(f"{pvd}: not a Collection")
    base = os.path.dirname(pvd)
    return [(float(d.get("timestep")), d.get("name"), os.path.join(base, d.get("file")))
            for d in root.iter("DataSet")]


def cell_count(mesh):
    return sum(len(block.data) for block in mesh.cells)


def check_blocks(entries, expected):
    frames = {}
    for time, name, path in entries:
        mesh = meshio.read(path)
        frames.setdefault(time, []).append(name)
        if name in expected:
            points, cells = expected[name]
            got = (len(mesh.points), cell_count(mesh))
            if got != (points, cells):
                fail(f"{path}: block {name} has {got[0]} points and {got[1]} cells, expected {points} and {cells}")
    names = {tuple(n) for n in frames.values()}
    if len(names) != 1:
        fail(f"the frames hold different blocks: {names}")
    missing = set(expected) - set(next(iter(names)))
    if missing:
        fail(f"no block named {sorted(missing)}")
    return len(frames)


def csv_row(path, time):
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if abs(float(row["t"]) - time) < 1e-9:
                return row
    fail(f"{path}: no row at t = {time}")


def check_node(entries, csv_path, body, label, time):
    paths = [p for t, n, p in entries if n == body and abs(t - time) < 1e-9]
    if len(paths) != 1:
        fail(f"{len(paths)} frames of block {body} at t = {time}")
    mesh = meshio.read(paths[0])
    labels = list(mesh.point_data["node"].ravel())
    if label not in labels:
        fail(f"{paths[0]}: no node {label}")
    k = labels.index(label)
    row = csv_row(csv_path, time)
    for array, what in ((mesh.points, "position"), (mesh.point_data["velocity"], "velocity")):
        expected = [float(row[f"{body}.node{label}.{what}.{c}"]) for c in "xyz"]
        got = [float(x) for x in array[k]]
        if any(abs(g - e) > 1e-8 * max(1.0, abs(e)) for g, e in zip(got, expected)):
            fail(f"{paths[0]}: node {label} {what} {got}, the CSV says {expected}")
    return paths[0]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("pvd")
    parser.add_argument("csv")
    parser.add_argument("--block", action="append", default=[])
    parser.add_argument("--node")
    args = parser.parse_args()
    expected = {}
    for block in args.block:
        name, counts = block.split("=")
        points, cells = counts.split(":")
        expected[name] = (int(points), int(cells))
    entries = read_series(args.pvd)
    if not entries:
        fail(f"{args.pvd}: no DataSet")
    frames = check_blocks(entries, expected)
    print(f"check_vtk: {frames} frames of {len(entries) // frames} blocks read with meshio {meshio.__version__}; "
          f"block sizes as expected: {', '.join(args.block) or 'none given'}")
    if args.node:
        body, label, time = args.node.split(":")
        path = check_node(entries, args.csv, body, int(label), float(time))
        print(f"check_vtk: node {label} of {body} at t = {time} ({path}) is where the CSV puts it")


if __name__ == "__main__":
    main()
