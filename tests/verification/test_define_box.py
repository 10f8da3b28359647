"""*DEFINE_BOX (issue 23) and what uses it: *INITIAL_VELOCITY BOXID, *RIGIDWALL_PLANAR BOXID,
*SET_NODE_GENERAL BOX / DBOX (explicit; mm, t, s, N, MPa).

Two steel cubes of standard tets side by side (A: x in [0, 2], B: x in [3, 5]; z in [1, 3]), above
a planar rigid wall at z = 0. Box 1 holds cube A, box 3 cube B, box 2 the bottom layer of both.
1. *INITIAL_VELOCITY NSID 0 with BOXID 1: cube A's nodes start at -2000 mm/s in z, cube B's at
   rest (the t = 0 state, exactly);
2. node set 10 = BOX 1 + BOX 3 - DBOX 2 (the nodout history set): exactly the nodes above the
   bottom layer, in ascending order;
3. both cubes at -2000 mm/s for 2 ms: the wall with BOXID 2 (every node that can reach the
   wall) gives the same bits as the wall without a box; with BOXID 1 it stops cube A (no node
   below z = -1e-9 mm) and cube B passes through (its highest node below z = -0.5 mm).
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_tets, run_case, nodout

checks = Checks('define_box')
V = 2000.0          # mm/s
END = 2.0e-3        # s


def model():
    xa, ca = box_tets(2.0, 2.0, 2.0, 2, 2, 2)
    xb, cb = box_tets(2.0, 2.0, 2.0, 2, 2, 2)
    xa = xa + [0.0, 0.0, 1.0]
    xb = xb + [3.0, 0.0, 1.0]
    return np.vstack([xa, xb]), np.vstack([ca, cb + len(xa)]), len(xa)


def deck(initial_box, wall_box, nodout_set=False):
    x, conn, na = model()
    boxes = ['*DEFINE_BOX', f10(1, -0.1, 2.1, -0.1, 2.1, -0.1, 3.1),
             '*DEFINE_BOX_TITLE', 'bottom layer', f10(2, -1.0, 6.0, -1.0, 3.0, 0.9, 1.1),
             '*DEFINE_BOX', f10(3, 2.9, 5.1, -0.1, 2.1, -0.1, 3.1)]
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'cubes', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)], boxes,
              ['*INITIAL_VELOCITY', f10(0, 0, initial_box), f10(0.0, 0.0, -V)],
              ['*RIGIDWALL_PLANAR', f10(0, 0, wall_box), f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)],
              ['*CONTROL_TERMINATION', f10(END), '*DATABASE_BINARY_D3PLOT', f10(END)]]
    if nodout_set:
        blocks += [['*SET_NODE_GENERAL', f10(10), 'BOX       ' + f10(1, 3), 'DBOX      ' + f10(2),
                    '*DATABASE_HISTORY_NODE_SET', f10(10), '*DATABASE_NODOUT', f10(END / 4)]]
    return blocks, x, na


def states(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        keys = sorted(f['states'])
        return [(f['states/%s/point/velocity' % k][()][order],
                 f['states/%s/point/displacement' % k][()][order]) for k in keys]


def main():
    # 1 and 3: the initial velocity in box 1 only; the general node set
    blocks, x, na = deck(1, 0, nodout_set=True)
    rc, text, out = run_case('box_initial', blocks)
    checks.check(rc == 0, 'run with BOXID 1 on the initial velocity succeeds', text[-600:])
    if rc == 0:
        v0 = states(out, 'box_initial')[0][0]
        want = np.zeros_like(v0)
        want[:na, 2] = -V
        checks.check(np.array_equal(v0, want), '*INITIAL_VELOCITY BOXID 1: cube A at -2000 mm/s, '
                     'cube B at rest', 'max diff %g' % np.max(abs(v0 - want)))
        bottom = abs(x[:, 2] - 1.0) < 1e-9
        expected = [k + 1 for k in range(len(x)) if not bottom[k]]
        ids = list(nodout(out)['ids'])
        checks.check(ids == expected, 'node set BOX 1 + BOX 3 - DBOX 2: the %d nodes above the '
                     'bottom layer, in order' % len(expected), 'got %d ids' % len(ids))
    # 2: the wall with and without boxes
    finals = {}
    for name, wall_box in (('box_wall_none', 0), ('box_wall_bottom', 2), ('box_wall_a', 1)):
        blocks, x, na = deck(0, wall_box)
        rc, text, out = run_case(name, blocks)
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return
        finals[name] = states(out, name)[-1][1]
    z = x[:, 2] + finals['box_wall_a'][:, 2]
    checks.check(np.array_equal(finals['box_wall_none'], finals['box_wall_bottom']),
                 'wall BOXID 2 (every node that reaches the wall): the same bits as no box', '')
    za, zb = z[:na].min(), z[na:].max()
    print('    wall BOXID 1: lowest node of cube A at z = %.3g mm, highest of cube B at %.3g mm'
          % (za, zb))
    checks.check(za > -1e-9 and zb < -0.5, 'wall BOXID 1: cube A held on the wall, cube B '
                 'passes through', 'A min z %g, B max z %g' % (za, zb))


main()
checks.exit()
