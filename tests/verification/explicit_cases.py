"""Meshes and decks of the explicit-dynamics verification tests (shared by the tests and by
post-processing scripts). Units: mm, tonne, s, N, MPa (steel: E = 210 GPa = 210000 MPa,
rho = 7.85e-9 t/mm^3, so energies are in mJ and velocities in mm/s)."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import ROOT, f10, free, nodes_card, elements_card, write_deck, run
from benchmarks import extrude_to_tets, boundary_facets
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


def box_hexes(lx, ly, lz, nx, ny, nz, distortion=0.0, seed=1):
    """Nodes and hexahedra (0-based, LS-DYNA's order: N1-N4 the bottom face counter-clockwise
    seen from the top, N5-N8 above them) of the box [0,lx]x[0,ly]x[0,lz]; interior nodes moved
    at random by up to `distortion` times the element size."""
    cube = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
    g = np.array([[i * lx / nx, j * ly / ny, k * lz / nz] for k in range(nz + 1)
                  for j in range(ny + 1) for i in range(nx + 1)])

    def index(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)
    conn = np.array([[index(i + a, j + b, k + c) for a, b, c in cube]
                     for k in range(nz) for j in range(ny) for i in range(nx)])
    if distortion > 0.0:
        rng = np.random.default_rng(seed)
        h = np.array([lx / nx, ly / ny, lz / nz])
        inner = np.all((g > 1e-9) & (g < np.array([lx, ly, lz]) - 1e-9), axis=1)
        g[inner] += distortion * h * rng.uniform(-1.0, 1.0, (inner.sum(), 3))
    return g, conn


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


def face_segments(x, conn, axis, value, sign, sid):
    """*SET_SEGMENT sid of the boundary faces of the tets conn on the plane x[axis] = value,
    oriented along sign (+1 or -1) of that axis."""
    lines = ['*SET_SEGMENT', f10(sid)]
    for f in boundary_facets(conn):
        f = [int(v) for v in f]
        if not all(abs(x[v, axis] - value) < 1e-9 for v in f):
            continue
        if np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[axis] * sign < 0:
            f = [f[0], f[2], f[1]]
        lines.append(f10(f[0] + 1, f[1] + 1, f[2] + 1, f[2] + 1))
    return lines


def smooth_ramp(t_end, value, n=41):
    """Curve points of a ramp from 0 to value over [0, t_end] with zero slope at both ends."""
    s = np.linspace(0.0, 1.0, n)
    return [(t_end * v, value * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]


def block_on_plate(z_bottom):
    """The contact tests' block on a plate: the block [1,2] x [1,2] x [z_bottom, z_bottom + 0.5]
    (3 x 3 x 2 hexahedra x 6 tets) and a rigid plate [0,3] x [0,3] at z = 0 of 6 x 6 quads.
    Returns (x, block tets, plate quads, nb): all nodes (block first), the block's tets and the
    plate's quads (0-based rows of x), and the number of block nodes."""
    xb, cb = box_tets(1.0, 1.0, 0.5, 3, 3, 2)
    xb = xb + [1.0, 1.0, z_bottom]
    plate = np.array([[i * 0.5, j * 0.5, 0.0] for j in range(7) for i in range(7)])
    quads = np.array([[j * 7 + i, j * 7 + i + 1, (j + 1) * 7 + i + 1, (j + 1) * 7 + i]
                      for j in range(6) for i in range(6)])
    nb = len(xb)
    return np.vstack([xb, plate]), cb, quads + nb, nb


def block_on_plate_cards(x, cb, quads, rho, young, poisson):
    """Nodes, elements and parts of block_on_plate: part 1 the elastic ME-FEM block, part 2 the
    rigid shell plate (all its nodes fixed: CON1 = CON2 = 7)."""
    return [nodes_card(x), elements_card('ELEMENT_SOLID', cb, pid=1),
            elements_card('ELEMENT_SHELL', quads, pid=2, first_id=len(cb) + 1),
            ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
             '*MAT_ELASTIC', free(1, rho, young, poisson),
             '*PART', 'plate', f10(2, 2, 2), '*SECTION_SHELL', f10(2, 2),
             f10(0.1, 0.1, 0.1, 0.1),
             '*MAT_RIGID', free(2, 7.85e-9, 210000.0, 0.3), f10(1.0, 7, 7)]]


def all_histories_blocks(plot_interval):
    """A short run that writes every history file (glstat, nodout, rwforc, rbdout, rcforc): the
    block of block_on_plate pressed onto the rigid plate by a ramped pressure (contact), a
    rigid wall below, a history node; result states every plot_interval (0.2 ms in all)."""
    x, cb, quads, nb = block_on_plate(0.0)
    probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))
    return block_on_plate_cards(x, cb, quads, 1.0e-9, 1000.0, 0.3) + [
        face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
        curve(1, smooth_ramp(2.0e-4, 10.0) + [(1.0, 10.0)]),
        ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), '', ''],
        ['*RIGIDWALL_PLANAR', f10(0), f10(0.0, 0.0, -1.0, 0.0, 0.0, 0.0)],
        ['*CONTROL_TERMINATION', f10(2.0e-4), '*DATABASE_BINARY_D3PLOT', f10(plot_interval),
         '*DATABASE_GLSTAT', f10(1.0e-5), '*DATABASE_RCFORC', f10(1.0e-5),
         '*DATABASE_NODOUT', f10(1.0e-5), '*DATABASE_HISTORY_NODE', f10(probe + 1)]]


def _eroding_punch_mesh():
    """The mesh of eroding_punch_blocks (see there)."""
    speed, gap, press, t_erode = 1.0e4, 0.1, 0.02, 1.0e-6
    xb, cb = box_hexes(4.0, 4.0, 2.0, 4, 4, 2)
    xp, cp = box_hexes(2.0, 2.0, 1.0, 1, 1, 1)
    top = [k for k, c in enumerate(cb) if xb[c, 2].min() > 0.5]
    return {'speed': speed, 'gap': gap, 'press': press, 't_erode': t_erode,
            'end': (gap + 1.0 + press) / speed, 'block_nodes': xb,
            'x': np.vstack([xb, xp + [1.0, 1.0, 2.0 + gap]]),
            'punch': np.asarray(cp) + len(xb), 'top_layer': [cb[k] for k in top],
            'low_layer': [c for k, c in enumerate(cb) if k not in top],
            'base': np.nonzero(xb[:, 2] < 1e-9)[0]}


#: The eroding-contact punch: a steel block 4 x 4 x 2 mm of 1 mm hexahedra held at its base,
#: its top layer (part 2) eroding at t_erode (*MAT_ADD_EROSION FAILTM) before a rigid punch
#: (2 x 2 mm, part 3, 'gap' above it) moving down at 'speed' arrives and presses 'press' into
#: the lower layer (part 1) by 'end'. Units mm, s.
ERODING_PUNCH = _eroding_punch_mesh()


def eroding_punch_blocks(contact):
    """The deck blocks of ERODING_PUNCH with the given contact card lines (part sets 1 = {1, 2},
    2 = {1, 2, 3})."""
    m = ERODING_PUNCH
    return [nodes_card(m['x']),
            elements_card('ELEMENT_SOLID', m['low_layer'], pid=1),
            elements_card('ELEMENT_SOLID', m['top_layer'], pid=2, first_id=100),
            elements_card('ELEMENT_SOLID', m['punch'], pid=3, first_id=200),
            ['*PART', 'lower layer', f10(1, 1, 1), '*PART', 'top layer', f10(2, 1, 2),
             '*PART', 'punch', f10(3, 1, 3), '*SECTION_SOLID', f10(1, 1),
             '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3),
             '*MAT_ELASTIC', free(2, DENSITY, YOUNG, 0.3),
             '*MAT_ADD_EROSION', f10(2), f10(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, m['t_erode']),
             # the punch moves along z only (x, y and the rotations held)
             '*MAT_RIGID', free(3, DENSITY, YOUNG, 0.3), f10(1.0, 4, 7)],
            ['*SET_PART_LIST', f10(1), f10(1, 2), '*SET_PART_LIST', f10(2), f10(1, 2, 3)],
            node_set(1, m['base']), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1, 1, 1, 1)],
            ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(3, 3, 0, 1, -m['speed'])],
            curve(1, [(0.0, 1.0), (1.0, 1.0)]),
            contact,
            ['*CONTROL_TERMINATION', f10(m['end']), '*DATABASE_BINARY_D3PLOT',
             f10(m['end'] / 4), '*DATABASE_RCFORC', f10(m['end'] / 100)]]
