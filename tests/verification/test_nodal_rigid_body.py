"""Rigid bodies of nodes (issue 23): *CONSTRAINED_NODAL_RIGID_BODY and *CONSTRAINED_SPOTWELD
(explicit; doc/theory.md 8).
1. Spot welds: a bar in two halves whose interface nodes coincide, every pair welded, pulled at
   one end at 2 m/s (the other end fixed): the displacements of the bar meshed in one piece
   (a weld of coincident nodes moves them as one node: a merge), to 1e-9.
2. Nodal rigid body: the end face of a cantilever (its nodes a node set) made one rigid body,
   pushed sideways by a force on one of its nodes: the face's nodes keep their distances (to
   1e-9 of the tip deflection) while the face moves and turns; rbdout has the body under its
   PID; kinetic plus internal energy equal the force's work (within 1 % of it); without the
   constraint the face distorts.
3. Errors: a node in two nodal rigid bodies (when the analysis starts).
Standard tets (ELFORM 10); mm, t, s, MPa.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_tets, node_set, curve, run_case
from lsdyna_ascii import read_glstat, read_rbdout

checks = Checks('nodal_rigid_body')


def displacements(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        return [f['states/%s/point/displacement' % s][()][order]
                for s in sorted(f['states'].keys())]


def spotwelds():
    length, width = 20.0, 4.0
    x1, c1 = box_tets(length, width, width, 5, 2, 2)
    x2, c2 = box_tets(length, width, width, 5, 2, 2)
    x2 = x2 + [length, 0.0, 0.0]
    n1 = len(x1)
    x = np.vstack([x1, x2])
    pairs = [(a, n1 + int(np.nonzero(np.all(abs(x2 - x1[a]) < 1e-9, axis=1))[0][0]))
             for a in np.nonzero(abs(x1[:, 0] - length) < 1e-9)[0]]
    # the merged bar: the second half's interface nodes replaced by the first half's
    merge_to = np.arange(len(x))
    for a, b in pairs:
        merge_to[b] = a
    keep = np.unique(merge_to)
    renumber = np.zeros(len(x), dtype=int)
    renumber[keep] = np.arange(len(keep))
    end_time = 2.0e-5
    results = {}
    for name in ('spotweld_halves', 'spotweld_merged'):
        if name == 'spotweld_halves':
            xx, conn, welds = x, np.vstack([c1, c2 + n1]), \
                ['*CONSTRAINED_SPOTWELD'] + [f10(a + 1, b + 1) for a, b in pairs]
            fixed = np.nonzero(x[:, 0] < 1e-9)[0]
            pulled = np.nonzero(x[:, 0] > 2 * length - 1e-9)[0]
        else:
            xx, conn, welds = x[keep], renumber[merge_to[np.vstack([c1, c2 + n1])]], []
            fixed = renumber[np.nonzero(x[:, 0] < 1e-9)[0]]
            pulled = renumber[np.nonzero(x[:, 0] > 2 * length - 1e-9)[0]]
        blocks = [nodes_card(xx), elements_card('ELEMENT_SOLID', conn),
                  ['*PART', 'bar', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
                   '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
                  node_set(1, fixed), node_set(2, pulled),
                  ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)],
                  ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, 1, 0, 1, 2000.0)],
                  curve(1, [(0.0, 1.0), (1.0, 1.0)]), welds,
                  # the same steps in both runs (the merged nodes' larger masses would
                  # lengthen them): LCTM caps them below both bounds
                  curve(3, [(0.0, 1.0e-8), (1.0, 1.0e-8)]),
                  ['*CONTROL_TIMESTEP', f10(0.0, 0.9, 0, 0.0, 0.0, 3)],
                  ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT',
                   f10(end_time / 4)]]
        rc, text, out = run_case(name, blocks)
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return
        results[name] = displacements(out, name)[-1]
    u_halves = results['spotweld_halves'][keep]
    u_merged = results['spotweld_merged']
    diff = np.max(abs(u_halves - u_merged)) / np.max(abs(u_merged))
    print('    spot welds: welded halves against the bar in one piece: largest displacement '
          'difference %.1e of %.3e mm' % (diff, np.max(abs(u_merged))))
    checks.check(diff < 1e-9, 'spot welds of coincident nodes: the bar in one piece (1e-9)',
                 '%.3e' % diff)


def cantilever(constrained):
    length, width = 30.0, 5.0
    x, conn = box_tets(length, width, width, 12, 2, 2)
    clamped = np.nonzero(x[:, 0] < 1e-9)[0]
    face = np.nonzero(x[:, 0] > length - 1e-9)[0]
    loaded = int(face[np.argmax(x[face, 1] + x[face, 2])])     # a corner of the end face
    end_time = 1.0e-4
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'beam', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
              node_set(1, clamped), node_set(2, face),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)],
              ['*LOAD_NODE_POINT', f10(loaded + 1, 2, 1, 200.0)],
              curve(1, [(0.0, 0.0), (end_time / 2, 1.0), (1.0, 1.0)]),
              ['*CONSTRAINED_NODAL_RIGID_BODY', f10(77, 0, 2)] if constrained else [],
              ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT',
               f10(end_time / 20), '*DATABASE_GLSTAT', f10(end_time / 100)]]
    name = 'nrb_cantilever' + ('' if constrained else '_free')
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    states = displacements(out, name)
    xf = x[face]
    d0 = np.linalg.norm(xf[:, None, :] - xf[None, :, :], axis=2)
    change = max(np.max(abs(np.linalg.norm((xf + u[face])[:, None, :] -
                                            (xf + u[face])[None, :, :], axis=2) - d0))
                 for u in states)
    tip = np.max(abs(states[-1][face, 1]))
    g = read_glstat(os.path.join(out, 'glstat'))
    rbd = read_rbdout(os.path.join(out, 'rbdout')) if constrained else None
    # energy balance: kinetic + internal against the force's work, over the run, relative to
    # the work at the end (the ratio itself is noise while the energies are near zero)
    balance = np.max(abs(g['kinetic energy'] + g['internal energy'] - g['external work'])) / \
        g['external work'][-1]
    return change, tip, balance, rbd


spotwelds()
nrb = cantilever(True)
free_end = cantilever(False)
if nrb and free_end:
    change, tip, balance, rbd = nrb
    print('    nodal rigid body end face: distances between its nodes change by %.1e mm (without '
          'it %.1e mm) for a tip deflection of %.3e mm; energy balance within %.1e of the '
          'work (without it %.1e); rbdout bodies %s' % (change, free_end[0], tip, balance,
                                                          free_end[2],
                                                          sorted(rbd) if rbd else None))
    checks.check(change < 1e-9 * tip and free_end[0] > 1e-4 * tip, 'nodal rigid body: the end '
                 'face moves rigidly (1e-9 of the deflection; without it the face distorts)',
                 '%.3e %.3e' % (change, free_end[0]))
    checks.check(tip > 0.01, 'nodal rigid body: the face moves', '%.3e' % tip)
    checks.check(rbd is not None and 77 in rbd, 'nodal rigid body: in rbdout under its PID 77',
                 str(sorted(rbd) if rbd else None))
    checks.check(balance < 0.01, 'nodal rigid body: kinetic + internal energy = the force\'s '
                 'work within 1 % of it', '%.3e' % balance)

# a node in two nodal rigid bodies: stopped when the analysis starts
x, conn = box_tets(2.0, 2.0, 2.0, 1, 1, 1)
blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
          ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
           '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
          node_set(1, [0, 1]), node_set(2, [1, 2]),
          ['*CONSTRAINED_NODAL_RIGID_BODY', f10(5, 0, 1), f10(6, 0, 2)],
          ['*CONTROL_TERMINATION', f10(1.0e-6)]]
rc, text, out = run_case('nrb_twice', blocks)
checks.check(rc == 1 and 'node 2 belongs to two rigid bodies, the nodal rigid body 5 and the '
             'nodal rigid body 6' in text, 'a node in two nodal rigid bodies: an error naming '
             'both', text[-400:])
checks.exit()
