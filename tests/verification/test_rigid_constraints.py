"""*CONSTRAINED_EXTRA_NODES_SET and *CONSTRAINED_RIGID_BODIES in the explicit analysis (issue 23).

A block 10 x 10 x 20 mm (2 x 2 x 4 hexahedra of 6 standard tets) held laterally (uniaxial
strain) and at its base; its top nodes are *not* nodes of the rigid plate above it (part 2, a
shell quad 1 mm above the top) but extra nodes of its body (*CONSTRAINED_EXTRA_NODES_SET); a
second rigid quad elsewhere (part 3) is merged into that body (*CONSTRAINED_RIGID_BODIES). The
body is moved down by delta = 0.02 mm (smooth, quasi-static over 60 wave transits) by a
*BOUNDARY_PRESCRIBED_MOTION_RIGID on part 2. Expected: the block's top nodes and part 3's nodes
follow the prescribed displacement, and the body's reaction is the block's elastic force
(lambda + 2 mu) A delta / H. Without the constraints part 3 stays where it is and the block is
not loaded (the same deck without them). The nonlinear implicit analysis (the plate a driven
tool, VAD 2): the extra nodes follow it, the same bits as the top nodes driven themselves
(*BOUNDARY_PRESCRIBED_MOTION_SET DOF 3); a merge of rigid parts is refused there. mm, t, s, MPa.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import (DENSITY, YOUNG, POISSON, box_tets, curve, elastic, node_set,
                            run_case)
from lsdyna_ascii import read_rbdout

checks = Checks('rigid_constraints')
A, H, DELTA, T = 10.0, 20.0, 0.02, 2.0e-4
xb, cb = box_tets(A, A, H, 2, 2, 4)
top = np.nonzero(abs(xb[:, 2] - H) < 1e-9)[0]
nb = len(xb)
plate = np.array([[0.0, 0.0, H + 1], [A, 0.0, H + 1], [A, A, H + 1], [0.0, A, H + 1]])
tab = np.array([[30.0, 0.0, 0.0], [31.0, 0.0, 0.0], [31.0, 1.0, 0.0], [30.0, 1.0, 0.0]])
x = np.vstack([xb, plate, tab])
s = np.linspace(0.0, 1.0, 41)
motion = [(T * v, -DELTA * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]


def deck(constrained):
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', cb),
              elements_card('ELEMENT_SHELL', np.array([[nb, nb + 1, nb + 2, nb + 3]]), pid=2,
                            first_id=len(cb) + 1),
              elements_card('ELEMENT_SHELL', np.array([[nb + 4, nb + 5, nb + 6, nb + 7]]),
                            pid=3, first_id=len(cb) + 2),
              ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10)] + elastic(),
              ['*PART', 'plate', f10(2, 2, 2), '*PART', 'tab', f10(3, 2, 2),
               '*SECTION_SHELL', f10(2, 2), f10(1.0, 1.0, 1.0, 1.0),
               '*MAT_RIGID', free(2, DENSITY, YOUNG, POISSON), f10(1.0, 0, 7)],
              node_set(1, range(nb)), node_set(3, np.nonzero(xb[:, 2] < 1e-9)[0]),
              node_set(4, top),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 0), '*BOUNDARY_SPC_SET', f10(3, 0, 0, 0, 1)],
              ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, 3, 2, 1, 1.0)],
              curve(1, motion + [(1.0, -DELTA)]),
              ['*CONTROL_TERMINATION', f10(T), '*DATABASE_BINARY_D3PLOT', f10(T),
               '*DATABASE_GLSTAT', f10(T / 100)]]
    if constrained:
        blocks.append(['*CONSTRAINED_EXTRA_NODES_SET', f10(2, 4)])
        blocks.append(['*CONSTRAINED_RIGID_BODIES', f10(2, 3)])
    name = 'rigid_constraints' if constrained else 'rigid_constraints_none'
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        u = f['states/%s/point/displacement' % last][()][order]
    return u, read_rbdout(os.path.join(out, 'rbdout'))


with_constraints = deck(True)
without = deck(False)
if with_constraints and without:
    u, rb = with_constraints
    modulus = YOUNG * (1 - POISSON) / ((1 + POISSON) * (1 - 2 * POISSON))
    expected = modulus * A * A * DELTA / H
    reaction = -rb[2]['z-reaction'][-1]
    top_error = np.abs(u[top, 2] + DELTA).max()
    tab_error = np.abs(u[nb + 4:nb + 8, 2] + DELTA).max()
    print('    extra nodes: top of the block moved %.6e .. %.6e mm (prescribed %.6e); merged '
          'part 3 %.6e mm; reaction %.5e N, (l+2m) A d/H = %.5e N (%+.2f %%)'
          % (u[top, 2].min(), u[top, 2].max(), -DELTA, u[nb + 4, 2], reaction, expected,
             100 * (reaction / expected - 1)))
    checks.check(top_error < 1e-9 * DELTA, 'the extra nodes (the block\'s top) follow the '
                 'rigid body', '%.3e' % top_error)
    checks.check(tab_error < 1e-9 * DELTA, 'the merged part follows the lead part\'s motion',
                 '%.3e' % tab_error)
    checks.check(abs(reaction / expected - 1) < 0.02, 'the body\'s reaction is the block\'s '
                 'force (lambda + 2 mu) A delta / H within 2 %', '%.5e' % reaction)
    checks.check(3 not in rb, 'part 3 is no body of its own (merged into part 2\'s)',
                 'bodies in rbdout: %s' % sorted(rb))
    u0, rb0 = without
    checks.check(np.abs(u0[top, 2]).max() < 1e-12 and np.abs(u0[nb + 4:nb + 8, 2]).max() < 1e-12,
                 'without the constraints the block and part 3 stay at rest',
                 '%.3e %.3e' % (np.abs(u0[top, 2]).max(), np.abs(u0[nb + 4:nb + 8, 2]).max()))


def implicit(how):
    """The block in the nonlinear implicit analysis (4 steps), its top driven down by DELTA by
    the plate's body (how = 'extra') or directly (how = 'nodes'); or with the merge ('merge')."""
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', cb),
              elements_card('ELEMENT_SHELL', np.array([[nb, nb + 1, nb + 2, nb + 3]]), pid=2,
                            first_id=len(cb) + 1),
              elements_card('ELEMENT_SHELL', np.array([[nb + 4, nb + 5, nb + 6, nb + 7]]),
                            pid=3, first_id=len(cb) + 2),
              ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10)] + elastic(),
              ['*PART', 'plate', f10(2, 2, 2), '*PART', 'tab', f10(3, 2, 2),
               '*SECTION_SHELL', f10(2, 2), f10(1.0, 1.0, 1.0, 1.0),
               '*MAT_RIGID', free(2, DENSITY, YOUNG, POISSON), f10(1.0, 7, 7)],
              node_set(1, range(nb)), node_set(3, np.nonzero(xb[:, 2] < 1e-9)[0]),
              node_set(4, top),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 0), '*BOUNDARY_SPC_SET', f10(3, 0, 0, 0, 1)],
              ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, 3, 2, 1, 1.0)],
              curve(1, [(0.0, 0.0), (1.0, -DELTA)]),
              ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.25),
               '*DATABASE_BINARY_D3PLOT', f10(1.0)]]
    if how == 'nodes':
        blocks.append(['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(4, 3, 2, 1, 1.0)])
    else:
        blocks.append(['*CONSTRAINED_EXTRA_NODES_SET', f10(2, 4)])
    if how == 'merge':
        blocks.append(['*CONSTRAINED_RIGID_BODIES', f10(2, 3)])
    name = 'rigid_constraints_implicit_' + how
    rc, text, out = run_case(name, blocks)
    if how == 'merge':
        checks.check(rc != 0 and 'implicit analysis does not take *CONSTRAINED_RIGID_BODIES' in
                     text, 'implicit: a merge of rigid parts is refused, naming the line',
                     text[-400:])
        return None
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        return f['states/%s/point/displacement' % last][()][order][:nb]


extra, direct = implicit('extra'), implicit('nodes')
implicit('merge')
if extra is not None and direct is not None:
    print('    implicit: the extra nodes moved %.6e .. %.6e mm (driven %.6e); against the top '
          'driven itself %.1e' % (extra[top, 2].min(), extra[top, 2].max(), -DELTA,
                                  np.abs(extra - direct).max()))
    checks.check(np.abs(extra[top, 2] + DELTA).max() < 1e-12 and np.array_equal(extra, direct),
                 'implicit: the extra nodes follow the driven tool: the bits of the top driven '
                 'itself', '%.3e' % np.abs(extra - direct).max())
checks.exit()
