"""post/h5_to_xdmf.py: the XDMF file beside a mefem HDF5 result, read back through meshio's
XDMF time-series reader (the reader of the XDMF 3 format, independent of mefem): the points are
the mesh coordinates, the cells (a tetrahedron and a rigid quadrilateral shell: a mixed
topology) have the nodes of the connectivity, and every state has its time and the very
values of each point and cell field of the HDF5 file (exact: the XDMF file points into it).
"""
import os
import subprocess
import sys

import h5py
import meshio
import numpy as np

ROOT = os.environ.get('MEFEM_ROOT',
                      os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
OUT = os.path.join(ROOT, 'tests', 'out', 'xdmf')
DECK = os.path.join(ROOT, 'tests', 'decks', 'good', 'core_shared_element_ids.k')
failed = 0


def check(cond, what, detail=''):
    global failed
    print('%s: h5_to_xdmf: %s%s' % ('PASS' if cond else 'FAIL', what, '' if cond else ': ' + detail))
    failed += 0 if cond else 1


env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
run = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), DECK, '-o', OUT], capture_output=True,
                     text=True, env=env)
check(run.returncode == 0, 'mefem runs the deck', (run.stdout + run.stderr)[-400:])
h5path = os.path.join(OUT, 'core_shared_element_ids.h5')
conv = subprocess.run([sys.executable, os.path.join(ROOT, 'post', 'h5_to_xdmf.py'), h5path],
                      capture_output=True, text=True)
xdmf = os.path.splitext(h5path)[0] + '.xdmf'
check(conv.returncode == 0 and os.path.isfile(xdmf), 'the converter writes %s'
      % os.path.basename(xdmf), conv.stdout + conv.stderr)
if failed:
    sys.exit(1)

with h5py.File(h5path, 'r') as f:
    coordinates = f['mesh/coordinates'][()]
    offsets, connectivity = f['mesh/cell_offsets'][()], f['mesh/connectivity'][()]
    types = f['mesh/cell_types'][()]
    states = [(float(f['states'][k].attrs['time']),
               {n: f['states'][k]['point'][n][()] for n in f['states'][k]['point']},
               {n: f['states'][k]['cell'][n][()] for n in f['states'][k]['cell']})
              for k in sorted(f['states'])]
with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
    points, cells = reader.read_points_cells()
    check(np.array_equal(points, coordinates), 'the points are the mesh coordinates')
    vtk_names = {10: 'tetra', 9: 'quad'}
    want = [(vtk_names[int(t)], connectivity[offsets[c]:offsets[c + 1]])
            for c, t in enumerate(types)]
    got = [(block.type, row) for block in cells for row in block.data]
    check(len(got) == len(want) and all(g[0] == w[0] and np.array_equal(g[1], w[1])
                                        for g, w in zip(got, want)),
          'the cells (%s) and their nodes: the connectivity' % ', '.join(w[0] for w in want),
          str(got))
    check(reader.num_steps == len(states), '%d states' % len(states), str(reader.num_steps))
    for k in range(min(reader.num_steps, len(states))):
        time, point_data, cell_data = reader.read_data(k)
        want_time, want_point, want_cell = states[k]
        ok = time == want_time and set(point_data) == set(want_point) and all(
            np.array_equal(np.asarray(point_data[n]).reshape(want_point[n].shape), want_point[n])
            for n in want_point)
        cell_ok = set(cell_data) == set(want_cell) and all(
            np.array_equal(np.concatenate(cell_data[n]).reshape(want_cell[n].shape),
                           want_cell[n]) for n in want_cell)
        check(ok and cell_ok, 'state %d (t = %g): its time and its %d point and %d cell fields'
              % (k, want_time, len(want_point), len(want_cell)),
              '%s %s' % (sorted(point_data), sorted(cell_data)))
sys.exit(1 if failed else 0)
