#!/usr/bin/python3
"""Checks of the benchmark deck generator: positive tets, conforming faces, exact volume, and
decks that `mefem --check` accepts in both *ELEMENT_SOLID layouts, with 8-digit ids."""
import collections
import os
import subprocess
import sys

import numpy as np

ROOT = os.environ.get('MEFEM_ROOT', os.path.abspath(os.path.join(os.path.dirname(__file__),
                                                                 '..', '..')))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'bench'))
import generate_block_deck as gen  # noqa: E402

OUT = os.path.join(ROOT, 'tests', 'out', 'bench_test')


def report(ok, what, detail=''):
    print(('PASS: ' if ok else 'FAIL: ') + what + ('' if ok else ': ' + detail))


def mesh_checks(n_tets):
    nx, ny, nz, h = 3, 4, 5, 0.5
    ids, x, conn = gen.block_mesh(nx, ny, nz, n_tets, h, 0)
    c = conn - 1
    p = x[c]
    det = np.einsum('ij,ij->i', np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                    p[:, 3] - p[:, 0])
    report(det.min() > 0, f'{n_tets}-tet split: every tet positively oriented',
           f'min det {det.min()}')
    volume, exact = det.sum() / 6.0, nx * ny * nz * h ** 3
    report(abs(volume - exact) < 1e-12 * exact, f'{n_tets}-tet split: volume of the block',
           f'{volume} vs {exact}')
    faces = collections.Counter()
    for t in c:
        for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            faces[tuple(sorted(t[list(f)]))] += 1
    boundary = sum(1 for v in faces.values() if v == 1)
    expected = 4 * (nx * ny + ny * nz + nx * nz)      # two triangles per boundary cell face
    report(max(faces.values()) == 2 and boundary == expected,
           f'{n_tets}-tet split: conforming (each face in at most two tets, '
           f'{expected} boundary faces)', f'max {max(faces.values())}, boundary {boundary}')
    report(len(conn) == nx * ny * nz * n_tets and len(ids) == (nx + 1) * (ny + 1) * (nz + 1),
           f'{n_tets}-tet split: element and node counts')


def deck_checks():
    os.makedirs(OUT, exist_ok=True)
    exe = os.path.join(ROOT, 'bin', 'mefem')
    for layout in ('current', 'legacy'):
        deck = os.path.join(OUT, f'block_{layout}.k')
        nodes, elems, lines = gen.write_deck(deck, 4, 3, 2, 5, layout, 2.0, 99990000)
        with open(deck) as f:
            text = f.read().split('\n')
        first = text.index('*NODE') + 2
        report(len(text[first]) == 56 and text[first][:8] == '99990001',
               f'{layout}: *NODE card is I8 + 3 x E16 with 8-digit ids', repr(text[first]))
        if not os.access(exe, os.X_OK):
            report(False, f'{layout}: mefem --check accepts the deck', f'{exe} missing')
            continue
        run = subprocess.run([exe, '--check', deck], capture_output=True, text=True,
                             env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1',
                                      OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1'))
        log = run.stdout + run.stderr
        report(run.returncode == 0 and 'deck accepted' in log and
               f'model: {nodes} nodes, {elems} elements' in log,
               f'{layout}: mefem --check accepts the deck ({nodes} nodes, {elems} tets)',
               log[-400:])


if __name__ == '__main__':
    mesh_checks(5)
    mesh_checks(6)
    deck_checks()
