"""The XDMF file beside a mefem HDF5 result, read back through meshio's XDMF time-series
reader (the reader of the XDMF 3 format, independent of mefem): the points are the mesh
coordinates, the cells (a tetrahedron and a rigid quadrilateral shell: a mixed topology) have
the nodes of the connectivity, and every state has its time and the very values of each point
and cell field of the HDF5 file (exact: the XDMF file points into it). Two files: the one mefem
writes itself during the run (src/io/xdmf_output.f90, with the mixed topology
/mesh/xdmf_topology that src/io/hdf5_output.f90 writes; checked against the topology
post/h5_to_xdmf.py builds from the connectivity), and the one post/h5_to_xdmf.py writes.
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
sys.path.insert(0, os.path.join(ROOT, 'post'))
import h5_to_xdmf  # noqa: E402
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('h5_to_xdmf')
check = checks.check


env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
run = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), DECK, '-o', OUT], capture_output=True,
                     text=True, env=env)
check(run.returncode == 0, 'mefem runs the deck', (run.stdout + run.stderr)[-400:])
h5path = os.path.join(OUT, 'core_shared_element_ids.h5')
own = os.path.splitext(h5path)[0] + '.xdmf'
check(os.path.isfile(own), 'mefem writes %s beside the HDF5 file' % os.path.basename(own))
converted = os.path.join(OUT, 'converted.xdmf')
conv = subprocess.run([sys.executable, os.path.join(ROOT, 'post', 'h5_to_xdmf.py'), h5path,
                       '-o', converted], capture_output=True, text=True)
check(conv.returncode == 0 and os.path.isfile(converted), 'the converter writes %s'
      % os.path.basename(converted), conv.stdout + conv.stderr)
if checks.failed:
    checks.exit()

with h5py.File(h5path, 'r') as f:
    coordinates = f['mesh/coordinates'][()]
    offsets, connectivity = f['mesh/cell_offsets'][()], f['mesh/connectivity'][()]
    types = f['mesh/cell_types'][()]
    states = [(float(f['states'][k].attrs['time']),
               {n: f['states'][k]['point'][n][()] for n in f['states'][k]['point']},
               {n: f['states'][k]['cell'][n][()] for n in f['states'][k]['cell']})
              for k in sorted(f['states'])]
    topology = f['mesh/xdmf_topology'][()]
check(np.array_equal(topology, h5_to_xdmf.mixed_topology(types, offsets, connectivity)),
      'mefem\'s /mesh/xdmf_topology = the mixed topology built from the connectivity',
      str(topology[:20]))


def check_as(label, cond, what, detail=''):
    check(cond, label + ': ' + what, detail)


def compare(xdmf, label):
    """The XDMF file read by meshio against the HDF5 data: points, cells and every state's
    time and fields."""
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        compare_reader(reader, label)


def compare_reader(reader, label):
    """compare's checks on an open reader."""
    points, cells = reader.read_points_cells()
    check_as(label, np.array_equal(points, coordinates), 'the points are the mesh coordinates')
    vtk_names = {10: 'tetra', 9: 'quad'}
    want = [(vtk_names[int(t)], connectivity[offsets[c]:offsets[c + 1]])
            for c, t in enumerate(types)]
    got = [(block.type, row) for block in cells for row in block.data]
    check_as(label, len(got) == len(want) and all(g[0] == w[0] and np.array_equal(g[1], w[1])
                                        for g, w in zip(got, want)),
          'the cells (%s) and their nodes: the connectivity' % ', '.join(w[0] for w in want),
          str(got))
    check_as(label, reader.num_steps == len(states), '%d states' % len(states), str(reader.num_steps))
    for k in range(min(reader.num_steps, len(states))):
        time, point_data, cell_data = reader.read_data(k)
        want_time, want_point, want_cell = states[k]
        ok = time == want_time and set(point_data) == set(want_point) and all(
            np.array_equal(np.asarray(point_data[n]).reshape(want_point[n].shape), want_point[n])
            for n in want_point)
        cell_ok = set(cell_data) == set(want_cell) and all(
            np.array_equal(np.concatenate(cell_data[n]).reshape(want_cell[n].shape),
                           want_cell[n]) for n in want_cell)
        check_as(label, ok and cell_ok, 'state %d (t = %g): its time and its %d point and %d cell fields'
              % (k, want_time, len(want_point), len(want_cell)),
              '%s %s' % (sorted(point_data), sorted(cell_data)))


compare(own, 'mefem\'s own file')
compare(converted, 'the converter\'s file')

# the topology written in parallel: the Taylor bar (input/taylor_bar.k) on 3 ranks
taylor = os.path.join(OUT, 'taylor_np3')
run = subprocess.run(['mpirun', '--oversubscribe', '-np', '3', os.path.join(ROOT, 'bin', 'mefem'),
                      os.path.join(ROOT, 'input', 'taylor_bar.k'), '-o', taylor],
                     capture_output=True, text=True, env=env)
check(run.returncode == 0, 'the Taylor bar runs on 3 ranks', (run.stdout + run.stderr)[-400:])
if run.returncode == 0:
    with h5py.File(os.path.join(taylor, 'taylor_bar.h5'), 'r') as f:
        built = h5_to_xdmf.mixed_topology(f['mesh/cell_types'][()], f['mesh/cell_offsets'][()],
                                          f['mesh/connectivity'][()])
        written = f['mesh/xdmf_topology'][()]
        nstates = len(f['states'])
        last = f['states'][sorted(f['states'])[-1]]['point']['displacement'][()]
    check(np.array_equal(written, built), '3 ranks: /mesh/xdmf_topology = the mixed topology '
          'built from the connectivity (%d entries)' % len(built))
    with meshio.xdmf.TimeSeriesReader(os.path.join(taylor, 'taylor_bar.xdmf')) as reader:
        reader.read_points_cells()
        steps = reader.num_steps
        _, point_data, _ = reader.read_data(steps - 1)
    check(steps == nstates and np.array_equal(np.asarray(point_data['displacement']), last),
          '3 ranks: the XDMF file lists the %d states, the last one\'s displacement read '
          'through it' % nstates, '%d states' % steps)
checks.exit()
