"""Render a mefem result with ParaView, by one command and without a display: the deformed
model (Warp By Vector with `displacement`) coloured by a field, saved as a PNG.

    pvpython --force-offscreen-rendering post/render_paraview.py results/deck/deck.pvd \\
        --field von_mises --out deck.png
    xvfb-run pvpython post/render_paraview.py ...        (a ParaView built without offscreen)
    pvbatch post/render_paraview.py ...                  (the same script, MPI-built ParaView)

Reads the `.pvd` collection mefem writes (serial `.vtu` or per-rank `.pvtu` states):
  --field      point or cell field (default von_mises); --field list prints the state's fields
               (this needs no ParaView: /usr/bin/python3 post/render_paraview.py X.pvd --field list)
  --on         points or cells, where a name is both (default: cells, the element values)
  --component  component of a vector or tensor field: -1 its magnitude (default), 0, 1, ...
               (mefem's tensors: xx yy zz xy yz zx)
  --state      state number as written (0, 1, ...), negative counts from the last (default -1)
  --scale      displacement magnification (default 1: the true deformed shape)
  --view       iso (default), +x, -x, +y, -y, +z, -z: the direction the camera looks from
  --size       picture width and height in pixels (default 1200 900)
  --out        picture file (default <result>_<field>_<state>.png beside the .pvd)
Units are those of the deck. Without ParaView's Python (pvpython, pvbatch) the picture cannot be
drawn: post/render_result.py draws one with matplotlib alone.

Test: tests/output/test_render_paraview.py (the fields and states read here for any Python; the
picture where pvpython is installed, skipped with a message otherwise).
"""
import argparse
import os
import re
import sys

VIEWS = {'iso': (1.0, -1.0, 0.8), '+x': (1.0, 0.0, 0.0), '-x': (-1.0, 0.0, 0.0),
         '+y': (0.0, 1.0, 0.0), '-y': (0.0, -1.0, 0.0), '+z': (0.0, 0.0, 1.0),
         '-z': (0.0, 0.0, -1.0)}
_DATASET = re.compile(r'<DataSet\b[^>]*\btimestep="([^"]+)"[^>]*\bfile="([^"]+)"')
_ARRAY = re.compile(r'<P?DataArray\b([^>]*)>')
_ATTRIBUTE = re.compile(r'(\w+)="([^"]*)"')


def states(pvd):
    """[(time, absolute state file)] of a .pvd collection, in its order."""
    with open(pvd) as f:
        text = f.read()
    folder = os.path.dirname(os.path.abspath(pvd))
    found = [(float(t), os.path.join(folder, name)) for t, name in _DATASET.findall(text)]
    if not found:
        raise ValueError('%s: no DataSet in the collection (not a .pvd of mefem?)' % pvd)
    return found


def fields(state_file):
    """{'points': {name: components}, 'cells': {name: components}} of a .vtu or .pvtu state,
    read from its XML header (the appended binary data is not read)."""
    with open(state_file, 'rb') as f:
        head = f.read(1 << 20).split(b'<AppendedData')[0].decode('utf-8', 'replace')
    out = {}
    for kind, tag in (('points', 'PointData'), ('cells', 'CellData')):
        block = re.search(r'<P?%s\b.*?</P?%s>' % (tag, tag), head, re.S)
        out[kind] = {}
        if block is None:
            continue
        for attributes in _ARRAY.findall(block.group(0)):
            values = dict(_ATTRIBUTE.findall(attributes))
            if 'Name' in values:
                out[kind][values['Name']] = int(values.get('NumberOfComponents', '1'))
    return out


def choose(available, name, on):
    """('POINTS' or 'CELLS', components) of field name; on: 'points', 'cells' or None (a name
    that is both: cells). Raises ValueError naming the fields there are."""
    kinds = [on] if on else ['cells', 'points']
    for kind in kinds:
        if name in available[kind]:
            return kind.upper(), available[kind][name]
    names = ', '.join('%s (%s)' % (n, k) for k in ('points', 'cells') for n in available[k])
    raise ValueError('field %s is not in the state%s; the fields are: %s'
                     % (name, ' as ' + on if on else '', names))


def render(state_time, pvd, field, association, components, component, scale, view_name,
           size, out):
    """Draw the picture with ParaView (paraview.simple, imported here)."""
    from paraview import simple as pv
    reader = pv.PVDReader(FileName=os.path.abspath(pvd))
    reader.UpdatePipeline(state_time)
    shape = reader
    if 'displacement' in reader.PointData.keys():
        shape = pv.WarpByVector(Input=reader)
        shape.Vectors = ['POINTS', 'displacement']
        shape.ScaleFactor = scale
    view = pv.CreateView('RenderView')
    view.ViewSize = list(size)
    view.ViewTime = state_time
    view.OrientationAxesVisibility = 1
    view.Background = [1.0, 1.0, 1.0]
    display = pv.Show(shape, view)
    pv.ColorBy(display, (association, field))
    lut = pv.GetColorTransferFunction(field)
    if components > 1:
        if component < 0:
            lut.VectorMode = 'Magnitude'
        else:
            lut.VectorMode = 'Component'
            lut.VectorComponent = component
    display.RescaleTransferFunctionToDataRange(False, True)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = field if components == 1 or component < 0 else '%s [%d]' % (field, component)
    bar.ComponentTitle = ''
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    shape.UpdatePipeline(state_time)
    bounds = shape.GetDataInformation().GetBounds()
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    direction = VIEWS[view_name]
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[i] + direction[i] for i in range(3)]
    view.CameraViewUp = [0.0, 1.0, 0.0] if abs(direction[2]) > 0.9 else [0.0, 0.0, 1.0]
    view.ResetCamera()
    pv.Render(view)
    pv.SaveScreenshot(out, view, ImageResolution=list(size))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('pvd')
    parser.add_argument('--field', default='von_mises')
    parser.add_argument('--on', choices=['points', 'cells'])
    parser.add_argument('--component', type=int, default=-1)
    parser.add_argument('--state', type=int, default=-1)
    parser.add_argument('--scale', type=float, default=1.0)
    parser.add_argument('--view', choices=sorted(VIEWS), default='iso')
    parser.add_argument('--size', type=int, nargs=2, default=[1200, 900])
    parser.add_argument('--out')
    args = parser.parse_args(argv)
    try:
        found = states(args.pvd)
        state_time, state_file = found[args.state]
        available = fields(state_file)
        if args.field == 'list':
            for kind in ('points', 'cells'):
                for name, n in available[kind].items():
                    print('%-6s %-24s %d component(s)' % (kind, name, n))
            return 0
        association, components = choose(available, args.field, args.on)
    except (OSError, ValueError, IndexError) as error:
        print('render_paraview: %s' % error, file=sys.stderr)
        return 2
    if args.component >= components:
        print('render_paraview: field %s has %d component(s): --component %d is not one'
              % (args.field, components, args.component), file=sys.stderr)
        return 2
    out = args.out or os.path.splitext(args.pvd)[0] + '_%s_%d.png' % (
        args.field, args.state if args.state >= 0 else len(found) + args.state)
    try:
        import paraview.simple  # noqa: F401
    except ImportError:
        print('render_paraview: this needs ParaView\'s Python: run it with pvpython '
              '(--force-offscreen-rendering without a display) or pvbatch; '
              'post/render_result.py draws a picture with matplotlib alone', file=sys.stderr)
        return 2
    render(state_time, args.pvd, args.field, association, components, args.component,
           args.scale, args.view, args.size, out)
    print('render_paraview: %s at t = %g on the deformed shape (x %g): %s'
          % (args.field, state_time, args.scale, out))
    return 0


if __name__ == '__main__':
    sys.exit(main())
