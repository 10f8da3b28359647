"""Decks of the implicit contact tests (test_implicit_contact.py, test_restart.py): a block
compressed, and slid along, by a rigid tool wider than it. Units mm, N, MPa."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import f10, free, nodes_card, elements_card
from benchmarks import quad_grid_triangles
from explicit_cases import box_tets, node_set, curve

E, NU, DELTA = 1000.0, 0.3, 1.0e-3


def tool_block_deck(dim, mu=0.0, slide=0.0):
    """The block and the tool; with slide > 0 the tool presses until t = 0.5, then moves by
    slide along x (contact with FS = mu)."""
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
              ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), f10(mu),
               f10(1.0, 1.0)]]
    if slide > 0:
        step = 0.1
        blocks += [curve(1, [(0, 0), (0.5, 1), (1, 1)]),
                   ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, 1, 2, 2, slide)],
                   curve(2, [(0, 0), (0.5, 0), (1, 1)])]
    else:
        step = 0.25
        blocks += [curve(1, [(0, 0), (1, 1)])]
    blocks += [['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, step),
                '*CONTROL_IMPLICIT_SOLUTION', f10(12), '*DATABASE_BINARY_D3PLOT', f10(step),
                '*DATABASE_RCFORC', f10(1.0)]]
    return nb, blocks
