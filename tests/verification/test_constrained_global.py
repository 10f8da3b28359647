"""*CONSTRAINED_GLOBAL (issue 23): the nodes on a plane normal to a global axis held by a TC code.

A steel bar of standard tets (4 x 1 x 1 mm, its nodes at x = 0 and y = 0 off the grid by less
than TOL) pulled at 1 m/s at x = 4 for 20 us (explicit), held in two ways:
- *CONSTRAINED_GLOBAL: TC 7 on the plane x = 0 (TOL 1e-4 mm), TC 2 on y = 0 (TOL 0: 1e-6 of
  the extent), and a plane z = 9 with no node (a warning);
- *BOUNDARY_SPC_SET on the same nodes (listed);
the displacements are the same bits; the nodes of x = 0 stay put, those of y = 0 keep y = 0.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_tets, node_set, curve, run_case

checks = Checks('constrained_global')
END = 2.0e-5


def deck(global_constraints):
    x, conn = box_tets(4.0, 1.0, 1.0, 4, 2, 2)
    x = np.array(x)
    rng = np.random.default_rng(3)
    end0 = abs(x[:, 0]) < 1e-9
    side0 = abs(x[:, 1]) < 1e-9
    x[end0, 0] += rng.uniform(-5e-5, 5e-5, end0.sum())        # within TOL 1e-4
    x[side0, 1] += rng.uniform(-1e-9, 1e-9, side0.sum())       # within 1e-6 x 4 mm
    pulled = np.nonzero(abs(x[:, 0] - 4.0) < 1e-9)[0]
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'bar', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
              node_set(3, pulled),
              ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(3, 1, 0, 1, 1000.0)],
              curve(1, [(0.0, 1.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(END), '*DATABASE_BINARY_D3PLOT', f10(END)]]
    if global_constraints:
        blocks += [['*CONSTRAINED_GLOBAL', f10(7, 0, 1, 0.0, 0.0, 0.0, 1.0e-4),
                    f10(2, 0, 2, 0.0, 0.0, 0.0, 0.0), f10(3, 0, 3, 0.0, 0.0, 9.0, 0.0)]]
    else:
        blocks += [node_set(1, np.nonzero(end0)[0]), node_set(2, np.nonzero(side0)[0]),
                   ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1), f10(2, 0, 0, 1, 0)]]
    return blocks, x, end0, side0


def final(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'])[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        return f['states/%s/point/displacement' % last][()][order]


def main():
    results = {}
    for name, flag in (('global_planes', True), ('global_spcs', False)):
        blocks, x, end0, side0 = deck(flag)
        rc, text, out = run_case(name, blocks)
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return
        results[name] = final(out, name)
        if flag:
            checks.check('*CONSTRAINED_GLOBAL: no node lies on the plane z = 9' in text,
                         'a plane without nodes gets a warning', text[-600:])
    u, v = results['global_planes'], results['global_spcs']
    checks.check(np.array_equal(u, v), 'the planes hold the same nodes as the SPC sets: the '
                 'same bits', 'max diff %g' % np.max(abs(u - v)))
    checks.check(np.all(u[end0] == 0.0) and np.all(u[side0, 1] == 0.0) and
                 np.max(abs(u[:, 0])) > 1e-3, 'x = 0 held, y = 0 kept in its plane, the bar '
                 'stretched', 'max u %g' % np.max(abs(u)))


main()
checks.exit()
