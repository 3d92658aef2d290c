"""Render one frame of a flexmb ParaView series (.pvd) to a PNG, with ParaView's pvpython.

    xvfb-run -a pvpython docs/render/render_frame.py PVD TIME OUT.png [options]

PVD is a series written by `flexmb run MODEL --vtk DIR` (or a mode animation of `flexmb modes
--vtk`); TIME is snapped to the nearest frame. The blocks are told apart by their point data:

- flexible bodies (blocks with the `--array` vector, `elastic_displacement` by default) are coloured
  by its magnitude, with a colour bar in m, and drawn with their deformation magnified by `--warp`;
- joints (blocks with `marker`) are small red spheres;
- all other blocks (rigid bodies: their shapes or frame glyphs) are grey.

Options:
  --warp K          draw the deformation K times its true size (default 1): the mesh is moved by
                    (K - 1) x the array (Warp By Vector); the annotation states K. The colours
                    are always the true magnitude.
  --array NAME      the vector to colour and warp by (default elastic_displacement; use
                    `displacement` for a mode animation of `flexmb modes`)
  --color NAME      colour the flexible bodies by this point scalar instead (e.g. von_mises, the
                    von Mises stress of a body whose table asks for stresses; colour bar in Pa)
  --undeformed      also draw the undeformed mesh (positions minus the array) in thin grey
  --view V          the direction the camera looks along: iso (default), +x, -x, +y, -y, +z, -z,
                    or three numbers "dx,dy,dz" (write --view=-z, with "=", for a leading minus)
  --up U            the screen's up direction, same forms (default +z, or +y when looking along z)
  --zoom Z          > 1 to come closer (default 1: the visible blocks fill the frame)
  --size W H        image size in pixels (default 1200 800)
  --range MAX       upper end of the colour bar in m (default: the largest magnitude in the frame)
  --hide NAME...    blocks (bodies, joints) to leave out
  --line A B        a grey bar between joints A and B (repeatable): a hinge line, or a rigid body
                    that has no shape (flexmb draws a frame glyph for it; --hide that)
  --radius R        joint sphere radius in m (default 1% of the model's size)
  --title TEXT      first line of the annotation (default: the series' name)
  --note TEXT       an extra line for the legend (upper right)

The camera is orthographic (parallel projection), so lengths across the screen compare directly.
"""
import argparse
import math
import os

from paraview import servermanager as sm
from paraview.simple import (ColorBy, CreateView, ExtractBlock, GetColorTransferFunction, GetScalarBar,
                             Line, PVDReader, SaveScreenshot, Show, Text, WarpByVector)

GREY, DARK, RED = [0.62, 0.62, 0.64], [0.15, 0.15, 0.15], [0.75, 0.1, 0.1]
AXES = {'+x': (1, 0, 0), '-x': (-1, 0, 0), '+y': (0, 1, 0), '-y': (0, -1, 0), '+z': (0, 0, 1),
        '-z': (0, 0, -1), 'iso': (-1, -1, -0.8)}


def direction(text):
    v = AXES.get(text) or tuple(float(c) for c in text.split(','))
    return unit(v)


def unit(v):
    n = math.sqrt(dot(v, v))
    return tuple(c / n for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def parse():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('pvd'), p.add_argument('time', type=float), p.add_argument('out')
    p.add_argument('--warp', type=float, default=1.0)
    p.add_argument('--array', default='elastic_displacement')
    p.add_argument('--color')
    p.add_argument('--undeformed', action='store_true')
    p.add_argument('--view', default='iso', type=direction)
    p.add_argument('--up', type=direction)
    p.add_argument('--zoom', type=float, default=1.0)
    p.add_argument('--size', type=int, nargs=2, default=[1200, 800])
    p.add_argument('--range', type=float)
    p.add_argument('--hide', nargs='+', default=[])
    p.add_argument('--line', nargs=2, action='append', default=[])
    p.add_argument('--radius', type=float)
    p.add_argument('--title')
    p.add_argument('--note')
    return p, p.parse_args()


def blocks(reader):
    """(name, selector, dataset) of each block; a series of one part is read as a single dataset."""
    data = sm.Fetch(reader)
    if not data.IsA('vtkMultiBlockDataSet'):
        name = data.GetFieldData().GetAbstractArray('Name')   # the .pvd's name, as characters
        name = ''.join(str(name.GetValue(i)) for i in range(name.GetNumberOfValues())) if name else ''
        return [(name.rstrip('\0'), None, data)]
    tree = reader.GetDataInformation().DataInformation.GetHierarchy()
    out = []
    for i, node in enumerate(tree.GetChildNodes(0, False)):
        block = data.GetBlock(i)
        while block is not None and block.IsA('vtkMultiBlockDataSet'):   # a named block holds one piece
            block = block.GetBlock(0)
        out.append((tree.GetAttributeOrDefault(node, 'label', ''), '/Root/' + tree.GetNodeName(node), block))
    return out


def points(src, t):
    """The points of a pipeline's output at time t (every block)."""
    src.UpdatePipeline(t)
    data = sm.Fetch(src)
    leaves = [data]
    if data.IsA('vtkCompositeDataSet'):
        it, leaves = data.NewIterator(), []
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaves.append(it.GetCurrentDataObject())
            it.GoToNextItem()
    return [leaf.GetPoint(i) for leaf in leaves for i in range(leaf.GetNumberOfPoints())]


def colour_bar(view, array, vmax, scalar=False):
    lut = GetColorTransferFunction(array)
    lut.ApplyPreset('Viridis (matplotlib)', True)
    lut.AutomaticRescaleRangeMode = 'Never'
    lut.RescaleTransferFunction(0.0, vmax)
    bar = GetScalarBar(lut, view)
    what = '%s [Pa]' if scalar else '%s, magnitude [m]'
    bar.Title, bar.ComponentTitle = what % array.replace('_', ' '), ''
    bar.TitleColor = bar.LabelColor = DARK
    bar.TitleFontSize, bar.LabelFontSize = 18, 16
    bar.AutomaticLabelFormat = 0                       # fixed point, two significant digits at the top
    bar.RangeLabelFormat = bar.LabelFormat = '%.2e' if vmax >= 1e4 else \
        '%%.%df' % max(0, 1 - math.floor(math.log10(vmax)))
    bar.WindowLocation, bar.ScalarBarLength = 'Lower Right Corner', 0.45
    return bar


def look(view, a, pts, radius, free):
    """Orthographic camera along --view, the points filling the free box (fractions of the image)."""
    d = a.view
    up = a.up or ((0, 1, 0) if abs(d[2]) > 0.99 else (0, 0, 1))
    right = unit(cross(d, up))
    up = cross(right, d)
    xs, ys = [dot(p, right) for p in pts], [dot(p, up) for p in pts]
    x0, x1, y0, y1 = free
    aspect = a.size[0] / a.size[1]
    half = max((max(xs) - min(xs) + 4 * radius) / (x1 - x0) / aspect,
               (max(ys) - min(ys) + 4 * radius) / (y1 - y0)) / 2 / a.zoom    # half the image height
    cx = (min(xs) + max(xs)) / 2 + (1 - x0 - x1) * half * aspect           # the box's centre ...
    cy = (min(ys) + max(ys)) / 2 + (1 - y0 - y1) * half                    # ... on the points' centre
    depth = sum(dot(p, d) for p in pts) / len(pts)
    focus = tuple(cx * r + cy * u + depth * c for r, u, c in zip(right, up, d))
    view.CameraFocalPoint = focus
    view.CameraPosition = tuple(f - 10 * half * c for f, c in zip(focus, d))
    view.CameraViewUp = up
    view.CameraParallelScale = half


def main():
    parser, a = parse()
    reader = PVDReader(FileName=a.pvd)
    times = reader.TimestepValues                      # a number if the series has one frame
    times = [times] if isinstance(times, (int, float)) else list(times) or [0.0]
    t = min(times, key=lambda x: abs(x - a.time))
    reader.UpdatePipeline(t)

    groups, names = {'flex': [], 'joint': [], 'rigid': []}, {}
    for label, selector, block in blocks(reader):
        if block is None or label in a.hide:
            continue
        pd = block.GetPointData()
        kind = 'flex' if pd.GetArray(a.array) else 'joint' if pd.GetArray('marker') else 'rigid'
        groups[kind].append(selector)
        names[label] = block
    for ends in a.line:
        for j in ends:
            if j not in names:
                parser.error('--line: no block %r (the blocks: %s)' % (j, ', '.join(sorted(names))))

    def part(selectors):
        return reader if selectors == [None] else ExtractBlock(Input=reader, Selectors=selectors)

    view = CreateView('RenderView')
    view.ViewSize, view.ViewTime = a.size, t
    view.UseColorPaletteForBackground, view.Background = 0, [1, 1, 1]
    view.OrientationAxesVisibility, view.OrientationAxesLabelColor = 1, DARK
    view.CameraParallelProjection = 1
    shown = []                                         # what the camera frames

    if groups['rigid']:
        rigid = part(groups['rigid'])
        r = Show(rigid, view)
        r.ColorArrayName = ['POINTS', '']   # one plain colour
        r.AmbientColor = r.DiffuseColor = GREY
        r.LineWidth, r.RenderLinesAsTubes = 3, 1
        shown.append(rigid)

    vmax = 0.0
    if groups['flex']:
        flex = part(groups['flex'])
        if a.undeformed:
            ref = WarpByVector(Input=flex, Vectors=['POINTS', a.array], ScaleFactor=-1.0)
            r = Show(ref, view)
            r.ColorArrayName = ['POINTS', '']   # one plain colour
            r.Representation, r.AmbientColor, r.DiffuseColor, r.Opacity = 'Wireframe', DARK, DARK, 0.5
            shown.append(ref)
        if a.warp != 1.0:
            flex = WarpByVector(Input=flex, Vectors=['POINTS', a.array], ScaleFactor=a.warp - 1.0)
        r = Show(flex, view)
        r.Representation = 'Surface'
        r.LineWidth, r.RenderLinesAsTubes = 5, 1       # beams
        r.Ambient, r.Diffuse = 0.3, 0.8
        colour = a.color or a.array
        ColorBy(r, ('POINTS', colour) if a.color else ('POINTS', a.array, 'Magnitude'))
        vmax = a.range or max(b.GetPointData().GetArray(colour).GetRange(-1)[1]
                              for b in names.values() if b.GetPointData().GetArray(colour)) or 1e-12
        colour_bar(view, colour, vmax, scalar=bool(a.color))
        r.SetScalarBarVisibility(view, True)
        shown.append(flex)

    pts = [p for src in shown for p in points(src, t)]
    pts += [b.GetPoint(0) for b in names.values() if b.GetPointData().GetArray('marker')]
    radius = a.radius or 0.01 * math.dist([min(p[k] for p in pts) for k in range(3)],
                                          [max(p[k] for p in pts) for k in range(3)])
    if groups['joint']:
        r = Show(part(groups['joint']), view)
        r.ColorArrayName = ['POINTS', '']   # one plain colour
        r.Representation, r.ShaderPreset, r.GaussianRadius = 'Point Gaussian', 'Sphere', radius
        r.AmbientColor = r.DiffuseColor = RED
    for ends in a.line:
        r = Show(Line(Point1=names[ends[0]].GetPoint(0), Point2=names[ends[1]].GetPoint(0)), view)
        r.AmbientColor = r.DiffuseColor = GREY
        r.LineWidth, r.RenderLinesAsTubes = 4, 1

    # annotation: what and when upper left, the legend upper right
    title = os.path.splitext(os.path.basename(a.pvd))[0]
    lines = [a.title or (title + ': ' + next(iter(names)) if len(names) == 1 else title)]
    mode = any(b.GetPointData().GetArray('rotation') for b in names.values())   # flexmb modes --vtk
    if mode:
        lines += ['frame at %.3g of the period' % t,
                  'mode shape, amplitude arbitrary (largest displacement 10% of the body size)']
    else:
        lines.append('t = %.3f s' % t)
    if groups['flex']:
        if a.warp != 1.0:
            lines.append('deformation drawn %g x its size (warp)' % a.warp)
        elif not mode:
            lines.append('deformation drawn to scale')
        lines.append('colour: %s%s, max %.3g %s' % ('' if mode else 'true ', (a.color or a.array).replace('_', ' '),
                                                  vmax, 'Pa' if a.color else 'm'))
    legend = (['thin grey: undeformed mesh'] if a.undeformed and groups['flex'] else []) \
        + (['red spheres: joints'] if groups['joint'] else []) + ([a.note] if a.note else [])
    for words, corner, justify in ((lines, 'Upper Left Corner', 'Left'),
                                   (legend, 'Upper Right Corner', 'Right')):
        text = Show(Text(Text='\n'.join(words)), view)
        text.WindowLocation, text.Justification, text.FontSize, text.Color = corner, justify, 20, DARK

    top = 1 - (25 * max(len(lines), len(legend)) + 20) / a.size[1]     # below the text
    look(view, a, pts, radius, (0.02, 0.86 if groups['flex'] else 0.98, 0.03, top))   # left of the bar
    SaveScreenshot(a.out, view, ImageResolution=a.size, CompressionLevel='9')
    print('wrote %s (t = %g s)' % (a.out, t))


main()
