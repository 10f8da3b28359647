"""Implicit (Newton-Raphson) mortar contact with rigid tools (issue 6): frictionless penalty
contact with the frozen-geometry tangent of formulation 5.5. A block is compressed by a rigid
tool (a *MAT_RIGID part moved by *BOUNDARY_PRESCRIBED_MOTION_RIGID VAD=2) that is wider than
the block: uniaxial stress, so the tool's force must be E' delta A (E' = E/(1 - nu^2) in plane
strain, E in 3D, delta the strain of the block read from its top), and for a flat tool the
frozen tangent is the exact one, so each load step converges in very few iterations. 2D plane
strain (ME-FEM triangles, a tool of in-plane quads) and 3D (ME-FEM tets, a tool of shell quads);
non-matching meshes. Units mm, N, MPa.
"""
import os
import re
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from benchmarks import quad_grid_triangles
from explicit_cases import box_tets, node_set, curve, run_case
from lsdyna_ascii import read_rcforc

E, NU, DELTA = 1000.0, 0.3, 1.0e-3
checks = Checks('implicit_contact')


def deck(dim):
    if dim == 2:
        xb = np.array([[i / 4, j / 4] for j in range(5) for i in range(5)])
        cb = quad_grid_triangles(4, 4, 'alternate')
        xt = np.array([[-0.5 + i * 0.4, 1.0 + j * 0.2] for j in range(2) for i in range(6)])
        ct = np.array([[i, i + 1, i + 7, i + 6] for i in range(5)])
        solid = ['*SECTION_SHELL', f10(1, 43), f10(1.0)]
        keyword = 'ELEMENT_SHELL'
    else:
        xb, cb = box_tets(1.0, 1.0, 1.0, 3, 3, 3)
        xt = np.array([[-0.5 + i * 0.5, -0.5 + j * 0.5, 1.0] for j in range(5) for i in range(5)])
        ct = np.array([[j * 5 + i, j * 5 + i + 1, (j + 1) * 5 + i + 1, (j + 1) * 5 + i]
                       for j in range(4) for i in range(4)])
        solid = ['*SECTION_SOLID', f10(1, 43)]
        keyword = 'ELEMENT_SOLID'
    nb = len(xb)
    x = np.vstack([xb, xt])
    spc = []
    for k in range(dim):
        spc += node_set(k + 1, np.nonzero(xb[:, k] < 1e-9)[0])
        dofs = [0, 0, 0]
        dofs[k] = 1
        spc += ['*BOUNDARY_SPC_SET', f10(k + 1, 0, *dofs)]
    blocks = [nodes_card(x), elements_card(keyword, cb, pid=1),
              elements_card('ELEMENT_SHELL', ct + nb, pid=2, first_id=len(cb) + 1),
              ['*PART', 'block', f10(1, 1, 1)] + solid + ['*MAT_ELASTIC', free(1, 1e-9, E, NU),
               '*PART', 'tool', f10(2, 2, 2), '*SECTION_SHELL', f10(2, 2), f10(0.1, 0.1, 0.1,
                                                                                0.1),
               '*MAT_RIGID', free(2, 1e-9, 2e5, 0.3), f10(1.0, 0, 7)], spc,
              ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, dim, 2, 1, -DELTA)],
              curve(1, [(0, 0), (1, 1)]),
              ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), f10(0.0),
               f10(1.0, 1.0)],
              ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.25),
               '*CONTROL_IMPLICIT_SOLUTION', f10(12), '*DATABASE_BINARY_D3PLOT', f10(0.25),
               '*DATABASE_RCFORC', f10(1.0)]]
    return nb, blocks


for dim in (2, 3):
    nb, blocks = deck(dim)
    for ranks in (1, 2):
        name = 'implicit_tool_%dd_np%d' % (dim, ranks)
        rc, text, out = run_case(name, blocks, ranks=ranks)
        checks.check(rc == 0, '%dD on %d rank(s): run succeeds' % (dim, ranks), text[-600:])
        if rc != 0:
            continue
        r = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']
        force = r['y' if dim == 2 else 'z']
        if ranks == 2:
            diff = np.max(abs(force - ref)) / np.max(abs(ref))
            # measured 3.6e-11: the contact is the same on every rank, the solution to MUMPS's
            # round-off
            checks.check(diff < 1e-8, '%dD: 1 and 2 ranks give the same tool force' % dim,
                         '%.3e' % diff)
            continue
        ref = force
        iterations = [int(m) for m in re.findall(r'step \d+: t = \S+, dt = \S+, (\d+) iterations',
                                                 text)]
        with h5py.File(os.path.join(out, name + '.h5')) as f:
            states = sorted(f['states'].keys())[1:]
            xs = f['mesh/coordinates'][()]
            ids = f['mesh/node_ids'][()]
            top = (abs(xs[:, dim - 1] - 1.0) < 1e-9) & (ids <= nb)
            strains = [-f['states/%s/point/displacement' % k][()][top, dim - 1].mean()
                       for k in states]
        modulus = E / (1 - NU ** 2) if dim == 2 else E
        expected = modulus * np.array(strains)
        err = np.max(abs(force / expected - 1))
        print('    %dD: tool force %s N, E\' delta A %s N (max error %.1e); tool penetration '
              '%.1e of its motion; Newton iterations per step %s' % (
                  dim, ' '.join('%.5f' % v for v in force), ' '.join('%.5f' % v for v in expected),
                  err, 1 - strains[-1] / DELTA, iterations))
        # measured 8e-4 (2D) / 1e-3 (3D): the finite-strain response at 0.1 % strain
        checks.check(err < 5e-3, '%dD: tool force = E\' delta A within 0.5 %%' % dim,
                     '%.3e' % err)
        # the penalty (100 K/h) lets the tool penetrate 1e-3..1e-2 of its motion
        checks.check(0.0 < 1 - strains[-1] / DELTA < 0.02, '%dD: the block follows the tool '
                     '(penetration below 2 %% of the motion)' % dim,
                     '%.3e' % (1 - strains[-1] / DELTA))
        # flat tool: the frozen-geometry tangent is exact: 2 iterations per step (measured)
        checks.check(max(iterations) <= 3, '%dD: Newton converges in at most 3 iterations per '
                     'step' % dim, str(iterations))
checks.exit()
