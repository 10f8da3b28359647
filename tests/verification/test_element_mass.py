"""Added masses (issue 23): *ELEMENT_MASS, *ELEMENT_MASS_NODE_SET, *ELEMENT_MASS_PART and
*ELEMENT_MASS_PART_SET (explicit; mm, t, s, N, MPa).

A deformable block of 2 one-point hexahedra (2 x 1 x 1 mm, steel: 1.57e-8 t) carries a point
mass of 1e-8 t on one node, 2e-8 t shared by the 4 nodes of its far end and ADDMASS 3e-8 t;
a rigid cube (1 mm^3, 7.85e-9 t) beside it gets FINMASS 5e-8 t through a part set. Everything
starts at 1000 mm/s in x; equal forces in x act on every node of each body (12 x 1 N on the
block, 8 x 0.5 N on the cube). Checked against the masses the deck gives:
- the run summary: each part's element mass, and the added mass 1.0215e-7 t on 16 nodes;
- glstat at t = 0: kinetic energy m v^2 / 2 with m = 1.257e-7 t (to 1e-12);
- glstat at the end: global x velocity (momentum / mass) = 1000 + (12 + 4) N t / m (1e-9; the
  rigid body's velocity is its half-step one, at t less half the last step);
- the cube's nodes: velocity 1000 + 4 N t / 5e-8 t (the body's mass is FINMASS; 1e-9);
- 2 ranks: nodout the same bits as 1 rank, glstat's energies to round-off.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_hexes, node_set, curve, run_case, glstat, \
    nodout, history_nodes

checks = Checks('element_mass')
V0 = 1000.0                                   # mm/s
END = 2.0e-5                                  # s
BLOCK_FORCE, CUBE_FORCE = 1.0, 0.5            # N per node
M_POINT, M_SET, M_ADD, M_FINAL = 1.0e-8, 2.0e-8, 3.0e-8, 5.0e-8     # t


def deck():
    xb, cb = box_hexes(2.0, 1.0, 1.0, 2, 1, 1)
    xc, cc = box_hexes(1.0, 1.0, 1.0, 1, 1, 1)
    xc = xc + [5.0, 0.0, 0.0]
    x = np.vstack([xb, xc])
    far_end = np.nonzero(abs(xb[:, 0] - 2.0) < 1e-9)[0]
    block_nodes, cube_nodes = np.arange(len(xb)), len(xb) + np.arange(len(xc))
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', cb, pid=1),
              elements_card('ELEMENT_SOLID', cc + len(xb), pid=2, first_id=3),
              ['*PART', 'block', f10(1, 1, 1), '*PART', 'cube', f10(2, 1, 2),
               '*SECTION_SOLID', f10(1, 1),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3),
               '*MAT_RIGID', free(2, DENSITY, YOUNG, 0.3), f10(0.0)],
              node_set(1, far_end), node_set(2, block_nodes), node_set(3, cube_nodes),
              ['*SET_PART_LIST', f10(9), f10(2)],
              ['*ELEMENT_MASS', '%8d%8d%16.8e' % (101, 1, M_POINT),
               '*ELEMENT_MASS_NODE_SET', '%8d%8d%16.8e' % (102, 1, M_SET),
               '*ELEMENT_MASS_PART', '%8d%16.8e%16.8e' % (1, M_ADD, 0.0),
               '*ELEMENT_MASS_PART_SET', '%8d%16.8e%16.8e' % (9, 0.0, M_FINAL)],
              ['*INITIAL_VELOCITY', f10(0), f10(V0, 0.0, 0.0)],
              ['*LOAD_NODE_SET', f10(2, 1, 1, BLOCK_FORCE), f10(3, 1, 1, CUBE_FORCE)],
              curve(1, [(0.0, 1.0), (1.0, 1.0)]),
              history_nodes([cube_nodes[0], cube_nodes[-1]]),
              ['*CONTROL_TERMINATION', f10(END), '*DATABASE_GLSTAT', f10(END / 10),
               '*DATABASE_NODOUT', f10(END / 10)]]
    return blocks, len(xb), len(xc), cube_nodes


def main():
    blocks, n_block, n_cube, cube_nodes = deck()
    block_mass = DENSITY * 2.0
    added = M_POINT + M_SET + M_ADD + (M_FINAL - DENSITY)
    total = block_mass + DENSITY + added
    results = {}
    for ranks in (1, 2):
        rc, text, out = run_case('element_mass_%d' % ranks, blocks, ranks=ranks)
        checks.check(rc == 0, '%d rank(s): the run succeeds' % ranks, text[-600:])
        if rc != 0:
            return
        results[ranks] = (open(os.path.join(out, 'glstat')).read(),      # (the first line:
                          open(os.path.join(out, 'nodout')).read().split('\n', 1)[1])  # title)
        if ranks > 1:
            continue
        m = re.search(r'added mass \(\*ELEMENT_MASS, \*ELEMENT_MASS_PART\) (\S+) at (\d+) nodes',
                      text)
        parts = {int(a): float(b) for a, b in re.findall(r'part (\d+): .*, mass (\S+)', text)}
        checks.check(m is not None and abs(float(m.group(1)) - added) <= 1e-5 * added and
                     int(m.group(2)) == n_block + n_cube and
                     abs(parts.get(1, 0) - block_mass) <= 1e-5 * block_mass and
                     abs(parts.get(2, 0) - DENSITY) <= 1e-5 * DENSITY,
                     'summary: parts 1.57e-8 and 7.85e-9 t, added mass %.5g t at 16 nodes'
                     % added, m.group(0) if m else text[-800:])
        g = glstat(out)
        ke0 = 0.5 * total * V0 ** 2
        err_ke = abs(g['kinetic energy'][0] - ke0) / ke0
        # a rigid body's velocity is the half-step one, v^{n-1/2} at t^n: its time is t less
        # half the step that reached t (the deformable nodes' are full-step in glstat)
        t_end, dt_end = g['time'][-1], g['time step'][-1]
        momentum = total * V0 + n_block * BLOCK_FORCE * t_end + \
            n_cube * CUBE_FORCE * (t_end - dt_end / 2)
        v_mean = momentum / total
        err_v = abs(g['global x velocity'][-1] - v_mean) / (v_mean - V0)
        print('    kinetic energy at t = 0: %.6e mJ (m v^2/2: %.6e); global x velocity at %.3g s: '
              '%.6f mm/s (%.6f)' % (g['kinetic energy'][0], ke0, t_end,
                                     g['global x velocity'][-1], v_mean))
        checks.check(err_ke < 1e-12, 'kinetic energy at t = 0 is m v^2/2 with every added mass '
                     '(1e-12)', '%.2e' % err_ke)
        checks.check(err_v < 1e-9, 'momentum: the global velocity grows by F t / m, m with '
                     'every added mass (1e-9 of the change)', '%.2e' % err_v)
        n = nodout(out)
        v_cube = V0 + n_cube * CUBE_FORCE * (t_end - dt_end / 2) / M_FINAL
        got = n['x-vel'][-1]
        err_c = np.max(abs(got - v_cube)) / (v_cube - V0)
        checks.check(err_c < 1e-9, 'the rigid cube moves as a body of FINMASS = 5e-8 t '
                     '(1e-9 of the change)', 'got %s, want %.6f' % (got, v_cube))
    checks.check(results[1][1] == results[2][1], '2 ranks: nodout the same bits as 1', '')
    g1, g2 = (np.array([float(v) for v in re.findall(r'kinetic energy\.*\s*(\S+)', results[r][0])])
              for r in (1, 2))
    checks.check(len(g1) > 0 and np.allclose(g1, g2, rtol=1e-12, atol=0.0), '2 ranks: glstat\'s '
                 'kinetic energies those of 1 rank to round-off (1e-12)', '')


main()
checks.exit()
