"""post/render_paraview.py: a ParaView picture of a result by one command. A short explicit run
(a block of ME-FEM tetrahedra held at its bottom, pulled at its top) on 1 and 2 ranks (.vtu and
.pvtu states); checked with any Python: the states and times read from the .pvd are those of
the HDF5 result, the fields read from a state's header are those of the HDF5 state (point and
cell, with their components), --field list prints them, an unknown field or component stops
with a message, and without ParaView's Python the script says what to run. The picture itself
(its size, not blank, several colours) where pvpython is installed; otherwise that part is
skipped with a message (this machine's Debian packages have no pvpython).
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

ROOT = os.environ.get('MEFEM_ROOT',
                      os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
OUT = os.path.join(ROOT, 'tests', 'out', 'render_paraview')
SCRIPT = os.path.join(ROOT, 'post', 'render_paraview.py')
sys.path.insert(0, os.path.join(ROOT, 'post'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
import render_paraview  # noqa: E402
from deck_writer import Checks, f10, free, nodes_card, elements_card, write_deck, MPIRUN  # noqa: E402
from explicit_cases import node_set, curve, box_tets  # noqa: E402

checks = Checks('render_paraview')
check = checks.check


def pulled_block(path):
    x, tets = box_tets(1.0, 1.0, 1.0, 2, 2, 2)
    bottom = np.nonzero(x[:, 2] < 1e-9)[0]
    top = np.nonzero(x[:, 2] > 1 - 1e-9)[0]
    write_deck(path, [nodes_card(x), elements_card('ELEMENT_SOLID', tets, pid=1),
                      ['*PART', 'body', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
                       '*MAT_ELASTIC', free(1, 1e-9, 1000.0, 0.3)],
                      node_set(1, bottom), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)],
                      node_set(2, top), curve(1, [(0.0, 0.0), (1.0, 1.0)]),
                      ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, 3, 2, 1, 0.01)],
                      ['*CONTROL_TERMINATION', f10(1e-5), '*DATABASE_BINARY_D3PLOT',
                       f10(5e-6)]], title='block')


env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1')
os.makedirs(OUT, exist_ok=True)
deck = os.path.join(OUT, 'block.k')
pulled_block(deck)
pvpython = shutil.which('pvpython')
for ranks in (1, 2):
    stem = 'block_np%d' % ranks
    folder = os.path.join(OUT, stem)
    command = [os.path.join(ROOT, 'bin', 'mefem'), deck, '-o', folder]
    if ranks > 1:
        command = MPIRUN + ['-np', str(ranks)] + command
    run = subprocess.run(command, capture_output=True, text=True, env=env)
    check(run.returncode == 0, '%s: mefem runs the deck' % stem, (run.stdout + run.stderr)[-400:])
    if run.returncode != 0:
        continue
    pvd = os.path.join(folder, 'block.pvd')
    found = render_paraview.states(pvd)
    with h5py.File(os.path.join(folder, 'block.h5'), 'r') as f:
        keys = sorted(f['states'])
        times = [float(f['states/' + k].attrs['time']) for k in keys]
        last = f['states/' + keys[-1]]
        want = {'points': {n: (last['point/' + n].shape + (1,))[1] for n in last['point']},
                'cells': {n: (last['cell/' + n].shape + (1,))[1] for n in last['cell']}}
    check(np.allclose([t for t, _ in found], times, rtol=1e-12, atol=0) and
          all(os.path.isfile(p) for _, p in found) and
          found[-1][1].endswith('.pvtu' if ranks > 1 else '.vtu'),
          '%s: the .pvd\'s states and times are the HDF5 result\'s (%d states)' % (stem, len(found)),
          '%s vs %s' % ([t for t, _ in found], times))
    got = render_paraview.fields(found[-1][1])
    same = all(all(got[k].get(n) == c for n, c in want[k].items()) for k in want)
    check(same, '%s: the fields of the last state (points and cells, with their components) '
          'are the HDF5 state\'s' % stem, '%s vs %s' % (got, want))
    check(render_paraview.choose(got, 'von_mises', None) == ('CELLS', 1) and
          render_paraview.choose(got, 'von_mises', 'points') == ('POINTS', 1) and
          render_paraview.choose(got, 'displacement', None) == ('POINTS', 3),
          '%s: a name that is both is taken on the cells unless --on points' % stem)
    listing = subprocess.run([sys.executable, SCRIPT, pvd, '--field', 'list'],
                             capture_output=True, text=True)
    check(listing.returncode == 0 and 'displacement' in listing.stdout and
          'cells' in listing.stdout, '%s: --field list prints the fields (no ParaView needed)'
          % stem, listing.stdout + listing.stderr)
    bad = subprocess.run([sys.executable, SCRIPT, pvd, '--field', 'no_such_field'],
                         capture_output=True, text=True)
    check(bad.returncode == 2 and 'no_such_field' in bad.stderr and 'von_mises' in bad.stderr,
          '%s: an unknown field stops with a message naming the fields' % stem, bad.stderr)
    bad = subprocess.run([sys.executable, SCRIPT, pvd, '--field', 'displacement',
                          '--component', '3'], capture_output=True, text=True)
    check(bad.returncode == 2 and '3 component(s)' in bad.stderr, '%s: a component the field '
          'does not have stops with a message' % stem, bad.stderr)
    picture = os.path.join(OUT, stem + '.png')
    if pvpython is None:
        plain = subprocess.run([sys.executable, SCRIPT, pvd, '--out', picture],
                               capture_output=True, text=True)
        check(plain.returncode == 2 and 'pvpython' in plain.stderr and not
              os.path.exists(picture), '%s: without ParaView\'s Python it says to run pvpython'
              % stem, plain.stderr)
        print('SKIP: render_paraview: %s: the picture (pvpython is not installed here)' % stem)
        continue
    drawn = subprocess.run([pvpython, '--force-offscreen-rendering', SCRIPT, pvd, '--field',
                            'von_mises', '--size', '640', '480', '--out', picture],
                           capture_output=True, text=True)
    check(drawn.returncode == 0 and os.path.isfile(picture), '%s: pvpython draws the picture'
          % stem, drawn.stdout + drawn.stderr)
    if os.path.isfile(picture):
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.image
        pixels = matplotlib.image.imread(picture)
        colours = len(np.unique((255 * pixels[:, :, :3]).astype(int).reshape(-1, 3), axis=0))
        check(pixels.shape[:2] == (480, 640) and colours > 20, '%s: 640 x 480 pixels, not '
              'blank (%d colours)' % (stem, colours), str(pixels.shape))
checks.exit()
