#!/usr/bin/python3
"""Write input/taylor_bar.k: Taylor impact of an aluminium cylinder on a rigid wall.

The explicit example `make run` runs (on 2 MPI ranks). The billet of the main example
(input/generate_main_example.py: cylinder D = 20 mm, H = 30 mm, quarter model with symmetry
planes x = 0 and y = 0, ME-FEM tetrahedra, aluminium with Ludwik hardening) flies at 200 m/s
onto a fixed, frictionless *RIGIDWALL_PLANAR at z = 0 (0.01 mm below its end face) and
mushrooms; 60 us, until the rebound. Units: mm, s, tonne, N, MPa (energy mJ).

The same bar in one-point hexahedra (the cells the tets are cut from): input/taylor_bar_hex.k,
written with --hexahedra --output input/taylor_bar_hex.k.

usage: /usr/bin/python3 input/generate_taylor_bar.py [--output input/taylor_bar.k]
       [--core N] [--radial M] [--layers K] [--hexahedra]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from generate_main_example import (AL_EPS, AL_K, AL_N, AL_PR, AL_RO, AL_SIGY, AL_E, HEIGHT,
                                   billet_hex_mesh, billet_mesh, card, check_mesh, heading,
                                   node_lines)

SPEED = 2.0e5            # impact speed (mm/s = 200 m/s)
GAP = 0.01               # wall below the end face (mm)
END_TIME = 60.0e-6       # s
PLOTS = 12               # output states


def quarter_bar_cards(x, tets, speed, gap, end_time, tssfac=0.9):
    """Cards of a quarter-bar impact (shared with tests/bench/taylor_copper.py): *NODE,
    *ELEMENT_SOLID (part 1: hexahedra, or tets as degenerate hexes), the symmetry planes x = 0 and y = 0
    (node sets 1, 2), the initial velocity -speed along z, a fixed frictionless
    *RIGIDWALL_PLANAR at z = -gap (normal +z), *CONTROL_TERMINATION and *CONTROL_TIMESTEP."""
    sym_x = [k + 1 for k in range(len(x)) if abs(x[k, 0]) < 1e-9]
    sym_y = [k + 1 for k in range(len(x)) if abs(x[k, 1]) < 1e-9]
    L = ['*NODE'] + node_lines([(k + 1, p[0], p[1], p[2]) for k, p in enumerate(x)])
    L += ['*ELEMENT_SOLID']
    L += ['%8d%8d' % (e + 1, 1) + ''.join('%8d' % (v + 1) for v in list(t) + [t[3]] * (8 - len(t)))
          for e, t in enumerate(tets)]
    for sid, nodes in ((1, sym_x), (2, sym_y)):
        L += ['*SET_NODE_LIST', card(sid)]
        L += [''.join('%10d' % v for v in nodes[i:i + 8]) for i in range(0, len(nodes), 8)]
    L += ['$ symmetry planes x = 0 and y = 0',
          '*BOUNDARY_SPC_SET', heading('nsid', 'cid', 'dofx', 'dofy', 'dofz'), card(1, 0, 1, 0, 0),
          '*BOUNDARY_SPC_SET', heading('nsid', 'cid', 'dofx', 'dofy', 'dofz'), card(2, 0, 0, 1, 0),
          '*INITIAL_VELOCITY', heading('nsid'), card(0), heading('vx', 'vy', 'vz'),
          card(0.0, 0.0, -speed),
          '$ fixed, frictionless wall: the plane z = -GAP, normal +z (tail -> head)',
          '*RIGIDWALL_PLANAR', heading('nsid', 'nsidex', 'boxid', 'offset'), card(0, 0, 0, 0.0),
          heading('xt', 'yt', 'zt', 'xh', 'yh', 'zh', 'fric'),
          card(0.0, 0.0, -gap, 0.0, 0.0, 1.0, 0.0),
          '*CONTROL_TERMINATION', heading('endtim'), card(end_time),
          '*CONTROL_TIMESTEP', heading('dtinit', 'tssfac'), card(0.0, tssfac)]
    return L


def write_deck(path, n_core, n_radial, n_layers, hexahedra=False):
    """The deck: ME-FEM tets (5 per cell of the O-grid) or, with hexahedra, the cells
    themselves as one-point hexahedra (ELFORM 1, viscous hourglass control IHQ 1, QM 0.1);
    the same nodes."""
    x, tets = billet_mesh(n_core, n_radial, n_layers)
    volume, exact, min_altitude, _ = check_mesh(x, tets)
    elements, elform, kind = tets, 43, 'ME-FEM tets'
    if hexahedra:
        elements, elform, kind = billet_hex_mesh(n_core, n_radial, n_layers)[1], 1, \
            'one-point hexahedra'
    es = [AL_SIGY + AL_K * e ** AL_N for e in AL_EPS]
    axis = [k + 1 for k in range(len(x)) if abs(x[k, 0]) < 1e-9 and abs(x[k, 1]) < 1e-9]
    history = [min(axis, key=lambda k: x[k - 1, 2]), max(axis, key=lambda k: x[k - 1, 2])]
    L = ['*KEYWORD',
         '$ Taylor impact of an aluminium cylinder (quarter model) on a rigid wall.',
         '$ Written by input/generate_taylor_bar.py (edit that script, not this file).',
         '$ Units: mm, s, tonne, N, MPa. %d nodes, %d %s, volume %.2f mm^3 '
         '(cylinder %.2f).' % (len(x), len(elements), kind, volume, exact),
         '*TITLE', 'Taylor impact of an aluminium cylinder, 200 m/s, ' + kind,
         '*PART', 'cylinder']
    L += ([heading('pid', 'secid', 'mid', 'eosid', 'hgid'), card(1, 1, 1, 0, 1)] if hexahedra
          else [heading('pid', 'secid', 'mid'), card(1, 1, 1)])
    L += ['*SECTION_SOLID', heading('secid', 'elform'), card(1, elform),
          '*MAT_PIECEWISE_LINEAR_PLASTICITY',
          heading('mid', 'ro', 'e', 'pr', 'sigy', 'etan', 'fail', 'tdel'),
          card(1, AL_RO, AL_E, AL_PR, AL_SIGY, 0.0, 1.0e21, 0.0),
          heading('c', 'p', 'lcss', 'lcsr', 'vp'), card(0.0, 0.0, 0, 0, 0.0),
          heading(*('eps%d' % (i + 1) for i in range(8))), card(*AL_EPS),
          heading(*('es%d' % (i + 1) for i in range(8))), card(*[round(v, 2) for v in es])]
    if hexahedra:
        L += ['$ the viscous hourglass control (LS-DYNA\'s default, written out): in this large',
              '$ plastic flow the elastic stiffness of IHQ 6, QM 1 would stiffen the mushrooming',
              '$ (footprint radius 13.6 mm against 14.8 mm; ME-FEM tets 14.9 mm)',
              '*HOURGLASS', heading('hgid', 'ihq', 'qm'), card(1, 1, 0.1)]
    L += quarter_bar_cards(x, elements, SPEED, GAP, END_TIME)
    L += ['*DATABASE_BINARY_D3PLOT', heading('dt'), card(END_TIME / PLOTS),
          '*DATABASE_GLSTAT', heading('dt'), card(END_TIME / 200),
          '*DATABASE_NODOUT', heading('dt'), card(END_TIME / 200),
          '*DATABASE_HISTORY_NODE', ''.join('%10d' % v for v in history),
          '*END']
    with open(path, 'w') as f:
        f.write('\n'.join(L) + '\n')
    return len(x), len(elements), min_altitude


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--output', default='input/taylor_bar.k')
    ap.add_argument('--core', type=int, default=4)
    ap.add_argument('--radial', type=int, default=3)
    ap.add_argument('--layers', type=int, default=20)
    ap.add_argument('--hexahedra', action='store_true',
                    help='one-point hexahedra (ELFORM 1) instead of ME-FEM tets '
                         '(input/taylor_bar_hex.k)')
    a = ap.parse_args(argv)
    n, m, h = write_deck(a.output, a.core, a.radial, a.layers, a.hexahedra)
    print('%s: %d nodes, %d %s, smallest altitude %.3f mm'
          % (a.output, n, m, 'hexahedra' if a.hexahedra else 'tets', h))


if __name__ == '__main__':
    main(sys.argv[1:])
