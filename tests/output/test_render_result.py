"""post/render_result.py: a picture of a result without a display. Two short explicit runs
written here, a block of ME-FEM tetrahedra and a plane-strain square of ME-FEM triangles, each
held at its bottom and pulled at its top, are rendered; checked: the PNG has the size asked
for; the value range drawn is that of the surface faces computed here from the HDF5 file
independently (cell field: the cells that own a face; point field: the means of the faces'
nodes); the colours of the smallest and the largest value
(viridis) are among the picture's pixels; an unknown field stops with a message naming the
fields there are.
"""
import os
import subprocess
import sys

import itertools
from collections import Counter

import matplotlib
matplotlib.use('Agg')
import matplotlib.image  # noqa: E402
import matplotlib.pyplot  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.environ.get('MEFEM_ROOT',
                      os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
OUT = os.path.join(ROOT, 'tests', 'out', 'render')
SCRIPT = os.path.join(ROOT, 'post', 'render_result.py')
sys.path.insert(0, os.path.join(ROOT, 'post'))
import render_result  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('render_result')
check = checks.check


def surface_here(mesh):
    """(face nodes, owning cell) of the surface, found here without the script's face
    tables: the corner triples of the tetrahedra that belong to one of them only, and every
    triangle and quadrilateral cell."""
    types, offsets, conn = mesh['cell_types'], mesh['cell_offsets'], mesh['connectivity']
    count, owner, faces = Counter(), {}, []
    for c, kind in enumerate(types):
        nodes = [int(n) for n in conn[offsets[c]:offsets[c + 1]]]
        if kind == 10:
            for triple in itertools.combinations(nodes, 3):
                key = tuple(sorted(triple))
                count[key] += 1
                owner[key] = c
        elif kind in (5, 9):
            faces.append((nodes, c))
    faces += [(list(key), owner[key]) for key, n in count.items() if n == 1]
    return faces


def has_colour(pixels, rgb, tolerance=2):
    """Some pixel has the colour rgb (0-255) within tolerance per channel."""
    return bool(np.any(np.all(abs(pixels[:, :, :3].astype(int) - rgb) <= tolerance, axis=2)))


def pulled_deck(path, dim):
    """A unit square of 4 x 4 x 2 ME-FEM triangles (dim 2) or a unit cube of 2 x 2 x 2 cubes of
    ME-FEM tetrahedra (dim 3), its bottom held, its top pulled up."""
    sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
    from deck_writer import f10, free, nodes_card, elements_card, write_deck
    from benchmarks import quad_grid_triangles
    from explicit_cases import node_set, curve, box_tets
    if dim == 2:
        x = np.array([[i / 4, j / 4] for j in range(5) for i in range(5)])
        elements = elements_card('ELEMENT_SHELL', quad_grid_triangles(4, 4, 'alternate'), pid=1)
        section = ['*SECTION_SHELL', f10(1, 43), f10(1.0)]
    else:
        x, tets = box_tets(1.0, 1.0, 1.0, 2, 2, 2)
        elements = elements_card('ELEMENT_SOLID', tets, pid=1)
        section = ['*SECTION_SOLID', f10(1, 43)]
    bottom = np.nonzero(x[:, dim - 1] < 1e-9)[0]
    top = np.nonzero(x[:, dim - 1] > 1 - 1e-9)[0]
    blocks = [nodes_card(x), elements,
              ['*PART', 'body', f10(1, 1, 1)] + section + ['*MAT_ELASTIC',
                                                           free(1, 1e-9, 1000.0, 0.3)],
              node_set(1, bottom), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)],
              node_set(2, top), curve(1, [(0.0, 0.0), (1.0, 1.0)]),
              ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, dim, 2, 1, 0.01)],
              ['*CONTROL_TERMINATION', f10(1e-5), '*DATABASE_BINARY_D3PLOT', f10(1e-5)]]
    write_deck(path, blocks, title=os.path.basename(path))


env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
os.makedirs(OUT, exist_ok=True)
decks = [os.path.join(OUT, 'block.k'), os.path.join(OUT, 'square.k')]
pulled_deck(decks[0], 3)
pulled_deck(decks[1], 2)
for deck in decks:
    stem = os.path.splitext(os.path.basename(deck))[0]
    run = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), deck, '-o', os.path.join(OUT, stem)],
                         capture_output=True, text=True, env=env)
    check(run.returncode == 0, '%s: mefem runs the deck' % stem, (run.stdout + run.stderr)[-400:])
    if run.returncode != 0:
        continue
    h5path = os.path.join(OUT, stem, stem + '.h5')
    for field in ('von_mises', 'displacement'):
        picture = os.path.join(OUT, '%s_%s.png' % (stem, field))
        proc = subprocess.run([sys.executable, SCRIPT, h5path, '--field', field, '--out',
                               picture, '--size', '6', '4'], capture_output=True, text=True)
        what = stem + ', ' + field
        check(proc.returncode == 0 and os.path.isfile(picture), '%s: the script writes the '
              'picture' % what, proc.stdout + proc.stderr)
        if proc.returncode != 0:
            continue
        pixels = matplotlib.image.imread(picture)
        check(pixels.shape[:2] == (400, 600), '%s: 600 x 400 pixels (--size 6 4 at 100 dpi)'
              % what, str(pixels.shape))
        # the value range, computed here: surface faces of the tetrahedra, the shell quads
        mesh, key, time, point, cell = render_result.read_result(h5path, -1)
        faces = surface_here(mesh)
        data = point[field] if field in point else cell[field]      # nodes first, as the script
        magnitude = np.linalg.norm(data.reshape(len(data), -1), axis=1)
        if field in point:
            values = np.array([magnitude[f].mean() for f, _ in faces])
        else:
            values = np.array([magnitude[c] for _, c in faces])
        out, limits = render_result.render(h5path, field, -1, 1.0, (25.0, -60.0),
                                           os.path.join(OUT, 'again.png'), (6.0, 4.0))
        check(np.isclose(limits[0], values.min(), rtol=0, atol=1e-12 * abs(values).max()) and
              np.isclose(limits[1], values.max(), rtol=0, atol=1e-12 * abs(values).max()),
              '%s: the range drawn is that of the surface faces (%g .. %g)' % (
                  what, values.min(), values.max()), str(limits))
        cmap = matplotlib.pyplot.get_cmap('viridis')
        low = np.round(255 * np.array(cmap(0.0)[:3])).astype(int)
        high = np.round(255 * np.array(cmap(1.0)[:3])).astype(int)
        check(has_colour(255 * pixels, low) and has_colour(255 * pixels, high),
              '%s: the colours of the smallest and the largest value are drawn' % what)
    bad = subprocess.run([sys.executable, SCRIPT, h5path, '--field', 'no_such_field'],
                         capture_output=True, text=True)
    check(bad.returncode != 0 and 'no_such_field' in bad.stderr and 'von_mises' in bad.stderr,
          'an unknown field stops with a message naming the fields there are', bad.stderr)
checks.exit()
