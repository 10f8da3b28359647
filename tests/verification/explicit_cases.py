"""Meshes and decks of the explicit-dynamics verification tests (shared by the tests and by
post-processing scripts). Units: mm, tonne, s, N, MPa (steel: E = 210 GPa = 210000 MPa,
rho = 7.85e-9 t/mm^3, so energies are in mJ and velocities in mm/s)."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import ROOT, f10, free, nodes_card, elements_card, write_deck, run
from benchmarks import extrude_to_tets
from lsdyna_ascii import read_glstat, read_nodout

OUT = os.path.join(ROOT, 'tests', 'out', 'explicit')
YOUNG, POISSON, DENSITY = 210000.0, 0.3, 7.85e-9        # MPa, -, t/mm^3


def wave_speeds(young=YOUNG, poisson=POISSON, density=DENSITY):
    """(c_0, c_d, c_s): bar, dilatational and shear wave speeds in mm/s."""
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    return np.sqrt(young / density), np.sqrt((lam + 2 * mu) / density), np.sqrt(mu / density)


def box_tets(lx, ly, lz, nx, ny, nz):
    """Tets of the box [0,lx]x[0,ly]x[0,lz], nx x ny x nz hexahedra cut into 6 tets each."""
    x2 = np.array([[i * lx / nx, j * ly / ny] for j in range(ny + 1) for i in range(nx + 1)])
    return extrude_to_tets(x2, nx, ny, nz, lz)


def part_cards(elform, material):
    """*PART 1 with *SECTION_SOLID ELFORM and the given material card lines."""
    return ['*PART', 'body', f10(1, 1, 1), '*SECTION_SOLID', f10(1, elform)] + material


def elastic(young=YOUNG, poisson=POISSON, density=DENSITY):
    return ['*MAT_ELASTIC', free(1, density, young, poisson)]


def node_set(sid, nodes):
    """*SET_NODE_LIST of 0-based node indices."""
    lines = ['*SET_NODE_LIST', f10(sid)]
    ids = [int(n) + 1 for n in nodes]
    for k in range(0, len(ids), 8):
        lines.append(''.join('%10d' % v for v in ids[k:k + 8]))
    return lines


def history_nodes(nodes):
    """*DATABASE_HISTORY_NODE of 0-based node indices."""
    lines = ['*DATABASE_HISTORY_NODE']
    ids = [int(n) + 1 for n in nodes]
    for k in range(0, len(ids), 8):
        lines.append(''.join('%10d' % v for v in ids[k:k + 8]))
    return lines


def curve(lcid, points):
    lines = ['*DEFINE_CURVE', f10(lcid)]
    return lines + ['%20.10e%20.10e' % (a, b) for a, b in points]


def run_case(name, blocks, ranks=1):
    """Write and run a deck; returns (rc, text, output directory)."""
    deck = os.path.join(OUT, name + '.k')
    write_deck(deck, blocks, title=name)
    outdir = os.path.join(OUT, name)
    rc, text = run(deck, outdir, ranks=ranks)
    return rc, text, outdir


def glstat(outdir):
    return read_glstat(os.path.join(outdir, 'glstat'))


def nodout(outdir):
    return read_nodout(os.path.join(outdir, 'nodout'))
