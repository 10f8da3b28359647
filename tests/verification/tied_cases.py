"""Decks of the tied-contact tests (test_contact_tied.py, test_restart.py): two blocks of
tets, one on the other, tied across their interface. Units: mm, tonne, s, N, MPa."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import f10, free, nodes_card, elements_card
from benchmarks import boundary_facets
from explicit_cases import box_tets, node_set, curve

E, NU, RHO, P, T = 1000.0, 0.3, 1.0e-9, 10.0, 1.0e-4
def top_segments(x, conn, z, sid):
    """*SET_SEGMENT of the faces of conn on the plane z (outward +z)."""
    seg = ['*SET_SEGMENT', f10(sid)]
    for f in boundary_facets(conn):
        f = [int(v) for v in f]
        if not all(abs(x[v, 2] - z) < 1e-9 for v in f):
            continue
        if np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[2] < 0:
            f = [f[0], f[2], f[1]]
        seg.append(f10(f[0] + 1, f[1] + 1, f[2] + 1, f[2] + 1))
    return seg


def symmetry(x):
    cards = []
    for k in range(3):
        dofs = [0, 0, 0]
        dofs[k] = 1
        cards += node_set(k + 1, np.nonzero(x[:, k] < 1e-9)[0])
        cards += ['*BOUNDARY_SPC_SET', f10(k + 1, 0, *dofs)]
    return cards


def ramp(p):
    s = np.linspace(0.0, 1.0, 41)
    return curve(1, [(T * v, p * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s] +
                 [(1.0, p)])


def two_blocks(gap, lower=(3, 3, 3), upper=(4, 4, 3)):
    x1, c1 = box_tets(1.0, 1.0, 1.0, *lower)
    x2, c2 = box_tets(1.0, 1.0, 1.0, *upper)
    x2 = x2 + [0.0, 0.0, 1.0 + gap]
    return np.vstack([x1, x2]), c1, c2 + len(x1), len(x1)


def deck(x, c1, c2, tie, loads, elform=43):
    return [nodes_card(x), elements_card('ELEMENT_SOLID', c1, pid=1),
            elements_card('ELEMENT_SOLID', c2, pid=2, first_id=len(c1) + 1),
            ['*PART', 'lower', f10(1, 1, 1), '*PART', 'upper', f10(2, 1, 1),
             '*SECTION_SOLID', f10(1, elform), '*MAT_ELASTIC', free(1, RHO, E, NU)], loads, tie,
            ['*CONTROL_TERMINATION', f10(1.5 * T), '*DATABASE_BINARY_D3PLOT', f10(T / 2)]]


def tiebreak_shear_blocks():
    """A block pressed (P) onto another and pushed sideways (S = P/5, friction 0.6), its tie
    failing in shear (SFLS = P/10) so that the companion contact then holds it; 2.5 T."""
    x, c1, c2, n1 = two_blocks(0.0)
    upper = np.arange(n1, len(x))
    shear_load = P / 5.0                    # (test_contact_tied reads it as P / 5)
    s = np.linspace(0.0, 1.0, 41)
    loads = node_set(1, np.nonzero(x[:, 2] < 1e-9)[0]) + ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)] \
        + top_segments(x, c2, 2.0, 9) + ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)] + ramp(P) \
        + node_set(5, upper) + ['*LOAD_NODE_SET', f10(5, 1, 2, 1.0 / len(upper))] \
        + curve(2, [(T * v, shear_load * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]
                + [(1.0, shear_load)])
    tie = ['*CONTACT_TIEBREAK_SURFACE_TO_SURFACE_ID', f10(5), f10(2, 1, 3, 3), f10(0.6, 0.6),
           '', f10(100.0 * P, 0.1 * P)]
    blocks = deck(x, c1, c2, tie, loads, elform=10)
    blocks[-1] = ['*CONTROL_TERMINATION', f10(2.5 * T), '*DATABASE_BINARY_D3PLOT', f10(0.5 * T),
                  '*DATABASE_RCFORC', f10(T / 50)]
    return blocks
