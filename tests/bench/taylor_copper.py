#!/usr/bin/python3
"""Copper Taylor bar: time to solution and accuracy per solid element (make bench;
doc/performance.md "Time to solution", doc/verification.md "Copper Taylor bar").

The classic benchmark of Wilkins & Guinan (1973) as used by Kamoulakos (1990) and most code
verification suites: an OFHC copper cylinder, L0 = 32.4 mm, D0 = 6.4 mm, strikes a rigid,
frictionless wall at 227 m/s; bilinear J2 plasticity, E = 117 GPa, nu = 0.35,
rho = 8930 kg/m^3, sigma_y = 400 MPa, E_t = 100 MPa; 80 us. Published final length
21.42-21.66 mm, footprint radius 7.0-7.2 mm. Quarter model (symmetry planes x = 0, y = 0),
the O-grid billet of input/generate_main_example.py scaled to the bar, 5 tets per hex (ELFORM 1:
the hexahedra themselves, the same nodes).
Units: mm, s, tonne, N, MPa.

For each element form and mesh the script writes the deck, runs mefem, and prints the wall
time, the number of cycles, the first and last stable steps, the final length and footprint
radius (from the last state of the HDF5 file), the energy ratio and the largest jump of the
cell plastic strain between face neighbours near the impact face.

usage: /usr/bin/python3 tests/bench/taylor_copper.py [--elforms 43 13 10 1] [--meshes coarse]
       [--ranks 1] [--workdir /tmp/taylor_copper] [--mefem bin/mefem]
"""
import argparse
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, 'input'))
import generate_main_example as gme  # noqa: E402
import generate_taylor_bar as gtb  # noqa: E402

LENGTH = 32.4            # mm
RADIUS = 3.2             # mm
SPEED = 2.27e5           # mm/s (227 m/s)
END_TIME = 80.0e-6       # s
RHO = 8.93e-9            # tonne/mm^3
YOUNG = 117.0e3          # MPa
POISSON = 0.35
SIGY = 400.0             # MPa
ETAN = 100.0             # MPa
GAP = 0.001              # wall below the end face (mm)
PUBLISHED_LENGTH = (21.42, 21.66)
PUBLISHED_RADIUS = (7.0, 7.2)
# meshes: (core, radial, layers) of the O-grid; 5 tets per hex
MESHES = {'coarse': (3, 3, 36), 'medium': (4, 4, 48), 'fine': (6, 6, 72)}


def bar_mesh(core, radial, layers, hexahedra=False):
    """Nodes and tets (or the hexahedra they are cut from: the same nodes) of the quarter
    bar: the main example's billet mesh, scaled."""
    if hexahedra:
        x, tets = gme.billet_hex_mesh(core, radial, layers)
    else:
        x, tets = gme.billet_mesh(core, radial, layers)
    x = x * np.array([RADIUS / gme.RADIUS, RADIUS / gme.RADIUS, LENGTH / gme.HEIGHT])
    return x, tets


def write_deck(path, elform, mesh, plots=8):
    x, tets = bar_mesh(*MESHES[mesh], hexahedra=elform == 1)
    card, heading = gme.card, gme.heading
    L = ['*KEYWORD',
         '$ Copper Taylor bar (Wilkins & Guinan), quarter model, %d %s, ELFORM %d.'
         % (len(tets), 'hexahedra' if elform == 1 else 'tets', elform),
         '$ Written by tests/bench/taylor_copper.py. Units: mm, s, tonne, N, MPa.',
         '*PART', 'bar', heading('pid', 'secid', 'mid'), card(1, 1, 1),
         '*SECTION_SOLID', heading('secid', 'elform'), card(1, elform),
         '*MAT_PIECEWISE_LINEAR_PLASTICITY',
         heading('mid', 'ro', 'e', 'pr', 'sigy', 'etan', 'fail', 'tdel'),
         card(1, RHO, YOUNG, POISSON, SIGY, ETAN, 1.0e21, 0.0),
         heading('c', 'p', 'lcss', 'lcsr', 'vp'), card(0.0, 0.0, 0, 0, 0.0)]
    L += gtb.quarter_bar_cards(x, tets, SPEED, GAP, END_TIME)
    L += ['*DATABASE_BINARY_D3PLOT', heading('dt'), card(END_TIME / plots),
          '*DATABASE_GLSTAT', heading('dt'), card(END_TIME / 80),
          '*END']
    with open(path, 'w') as f:
        f.write('\n'.join(L) + '\n')
    return len(x), len(tets)


def final_shape(h5_path):
    """Final length (mm) and footprint radius (mm) from the last state of the HDF5 file: the
    length is the highest deformed z (the wall is at z = -GAP), the footprint the largest
    radius of the nodes on the impact face (z0 = 0)."""
    import h5py
    with h5py.File(h5_path, 'r') as f:
        x = f['mesh/coordinates'][()]
        step = f['time_history/step'][-1]
        u = f['states/%06d/point/displacement' % step][()]
    y = x + u
    face = np.abs(x[:, 2]) < 1e-9
    return y[:, 2].max() + GAP, np.hypot(y[face, 0], y[face, 1]).max()


def plastic_strain_jump(h5_path):
    """Cell plastic strain near the impact face (reference z < L0/8): the median and the 95th
    percentile over face-neighbouring cells of |eps_a - eps_b| / mean of the region's eps
    (a checkerboard gives jumps of the order of the strain itself)."""
    import h5py
    with h5py.File(h5_path, 'r') as f:
        x = f['mesh/coordinates'][()]
        offsets = f['mesh/cell_offsets'][()]
        conn = f['mesh/connectivity'][()]
        step = f['time_history/step'][-1]
        eps = f['states/%06d/cell/plastic_strain' % step][()].ravel()
    cells = [conn[offsets[c]:offsets[c + 1]] for c in range(len(offsets) - 1)]
    near = [c for c in range(len(cells)) if x[cells[c], 2].mean() < LENGTH / 8]
    hex_faces = ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                 (3, 0, 4, 7))
    faces = {}
    for c in near:
        t = cells[c]
        local = hex_faces if len(t) == 8 else [np.delete(np.arange(4), k) for k in range(4)]
        for f in local:
            key = tuple(sorted(t[list(f)]))
            faces.setdefault(key, []).append(c)
    jumps = np.array([abs(eps[p[0]] - eps[p[1]]) for p in faces.values() if len(p) == 2])
    scale = eps[near].mean()
    return np.median(jumps) / scale, np.percentile(jumps, 95) / scale


def glstat_figures(out):
    """First and last regular step, and the last energy ratio, from glstat."""
    sys.path.insert(0, os.path.join(ROOT, 'post'))
    import lsdyna_ascii
    g = lsdyna_ascii.read_glstat(os.path.join(out, 'glstat'))
    dt = g['time step']
    return dt[1], dt[-2], g['total energy / initial energy'][-1]


def run(elform, mesh, ranks, workdir, mefem):
    name = 'taylor_%s_%d' % (mesh, elform)
    deck = os.path.join(workdir, name + '.k')
    out = os.path.join(workdir, name)
    nodes, tets = write_deck(deck, elform, mesh)
    cmd = [mefem, '-o', out, deck]
    if ranks > 1:
        cmd = ['mpirun', '-np', str(ranks)] + cmd
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - start
    if proc.returncode != 0:
        print(proc.stdout[-2000:], proc.stderr[-2000:])
        raise SystemExit('%s failed' % name)
    cycles = int(re.search(r'explicit: cycles (\d+)', proc.stdout).group(1))
    length, radius = final_shape(os.path.join(out, name + '.h5'))
    jump50, jump95 = plastic_strain_jump(os.path.join(out, name + '.h5'))
    dt_first, dt_last, ratio = glstat_figures(out)
    return dict(elform=elform, mesh=mesh, tets=tets, wall=wall, cycles=cycles, length=length,
                radius=radius, dt_first=dt_first, dt_last=dt_last, ratio=ratio,
                jump50=jump50, jump95=jump95)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--elforms', type=int, nargs='+', default=[43, 13, 10, 1])
    ap.add_argument('--meshes', nargs='+', default=['coarse'], choices=sorted(MESHES))
    ap.add_argument('--ranks', type=int, default=1)
    ap.add_argument('--workdir', default='/tmp/taylor_copper')
    ap.add_argument('--mefem', default=os.path.join(ROOT, 'bin', 'mefem'))
    a = ap.parse_args(argv)
    os.makedirs(a.workdir, exist_ok=True)
    os.environ.setdefault('OMPI_ALLOW_RUN_AS_ROOT', '1')
    os.environ.setdefault('OMPI_ALLOW_RUN_AS_ROOT_CONFIRM', '1')
    print('Copper Taylor bar, 227 m/s, 80 us, %d rank(s); published length %.2f-%.2f mm, '
          'footprint radius %.1f-%.1f mm' % ((a.ranks,) + PUBLISHED_LENGTH + PUBLISHED_RADIUS))
    print('%-7s %7s %6s %8s %7s %10s %10s %9s %9s %8s %11s' % (
        'mesh', 'tets', 'ELFORM', 'wall s', 'cycles', 'first dt', 'last dt', 'length', 'radius',
        'E ratio', 'eps jump'))
    rows = []
    for mesh in a.meshes:
        for elform in a.elforms:
            r = run(elform, mesh, a.ranks, a.workdir, a.mefem)
            rows.append(r)
            print('%-7s %7d %6d %8.2f %7d %10.3e %10.3e %9.3f %9.3f %8.4f %5.2f/%5.2f' % (
                mesh, r['tets'], elform, r['wall'], r['cycles'], r['dt_first'], r['dt_last'],
                r['length'], r['radius'], r['ratio'], r['jump50'], r['jump95']), flush=True)
    for mesh in a.meshes:
        base = [r for r in rows if r['mesh'] == mesh and r['elform'] == 10]
        for r in rows:
            if base and r['mesh'] == mesh and r['elform'] != 10:
                print('%s: ELFORM %d / ELFORM 10: wall %.2f, cycles %.2f, wall per cycle %.2f' % (
                    mesh, r['elform'], r['wall'] / base[0]['wall'],
                    r['cycles'] / base[0]['cycles'],
                    (r['wall'] / r['cycles']) / (base[0]['wall'] / base[0]['cycles'])))
        nodal = [r for r in rows if r['mesh'] == mesh and r['elform'] == 13]
        mefem = [r for r in rows if r['mesh'] == mesh and r['elform'] == 43]
        if nodal and mefem:
            print('%s: ELFORM 43 / ELFORM 13: wall %.2f, cycles %.2f' % (
                mesh, mefem[0]['wall'] / nodal[0]['wall'], mefem[0]['cycles'] / nodal[0]['cycles']))


if __name__ == '__main__':
    main(sys.argv[1:])
