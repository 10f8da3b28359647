#!/usr/bin/python3
"""The seed paper's sphere compression (Hu & Wu 2013, section 4.2) as a reproducible study.

Runs the two committed decks of input/sphere/ (quarter sphere between rigid plates, mortar
contact, frictionless and mu = 0.2) one after the other on 2 MPI ranks each, results in
tests/out/sphere/<case>/, and writes to doc/verification_data/:
  sphere_force_displacement.png  normal contact force (full sphere = 4 x quarter model) against
                                 the top plate's displacement, both cases; the high-frequency
                                 part of the force; kinetic / internal energy
  sphere_curves.csv              those curves
  sphere_summary.csv             per case: forces at a few displacements, high-frequency
                                 content, top/bottom force balance, energies, run time
  sphere_plastic_strain.png      effective plastic strain on the deformed symmetry plane x = 0
                                 (mirrored to a full meridian section) at four stages, both cases
  sphere_pressure.png            the same for the pressure -tr(sigma)/3
  sphere_progressive.png         progressive deformation of the frictional case: cut-away 3D
                                 views (three quadrants) coloured by effective plastic strain
and prints a summary table. Setup and discussion: doc/verification.md, "Sphere compression
(paper section 4.2)".

Forces: from rcforc (contact resultants, read by label: post/lsdyna_ascii.py read_rcforc) when
the run wrote one with both interfaces, else from rbdout (the reactions of the plates'
constraints, corrected for the driven plate's inertia). Energies from glstat (the top plate's
kinetic energy removed).

Usage: /usr/bin/python3 post/sphere_study.py [--no-run] [--stand-in] [--ranks N] [--exe PATH]
                                             [--results DIR] [--figures DIR]
  --no-run    reuse the results in tests/out/sphere/ (only measure and plot)
  --results DIR  results directory of the runs (default tests/out/sphere)
  --figures DIR  where figures and tables go (default doc/verification_data)
  --stand-in  exercise this script without contact: the same mesh squeezed between two rigid
              caps made of its own surface triangles near the poles (merged nodes, no
              contact), a short run (2223 cycles, ~40 s); deck, results and figures in
              tests/out/sphere_stand_in/ (nothing is written to doc/)
  --ranks N   MPI ranks per run (default 2)
  --exe PATH  the mefem executable (default bin/mefem)
`make sphere` builds bin/mefem and runs this script (two runs, 6-6.5 minutes each on two
otherwise idle cores, measured 2026-11-27).
"""
import csv
import argparse
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt                                  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection           # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..'))
DECKS = os.path.join(ROOT, 'input', 'sphere')
OUT = os.path.join(ROOT, 'tests', 'out', 'sphere')
OUT_STAND_IN = os.path.join(ROOT, 'tests', 'out', 'sphere_stand_in')
DATA = os.path.join(ROOT, 'doc', 'verification_data')
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, DECKS)
from lsdyna_ascii import read_glstat, read_rbdout, read_rcforc      # noqa: E402
import msh_to_k as deck                                             # noqa: E402

QUARTER_TO_FULL = 4.0          # the quarter model carries a quarter of the plate force
HF_WINDOW_FRACTION = 0.02      # smoothing window of the high-frequency measure: 2 % of the run
HF_RANGE = (0.05, 0.95)        # part of the stroke over which it is evaluated
ENERGY_FROM = 0.1              # kinetic/internal ratio reported from 10 % of the stroke on
SHORT_STEP = 0.9              # a record after a step below 0.9 x the median step is left out
END_TOLERANCE = 0.002          # forces 'at the end' may come from 0.2 % before it
STAGE_FRACTIONS = (0.25, 0.5, 0.75, 1.0)            # stages of the section figures
PROGRESSIVE_FRACTIONS = (0.0, 0.25, 0.5, 0.75, 1.0)  # stages of the 3D figure
LABELS = {'frictionless': 'frictionless', 'friction': 'Coulomb mu = 0.2',
          'stand_in': 'stand-in (no contact)'}
COLOURS = {'frictionless': 'tab:blue', 'friction': 'tab:red', 'stand_in': 'tab:green'}
SPHERE_TET = 10                # VTK cell type of the sphere's cells in the HDF5 file
PLATE_DRAWN, PLATE_TILES = 0.14, 8    # drawn plates: [-0.14, 0.14]^2 m in 8 x 8 tiles


# ---- cases --------------------------------------------------------------------------------

def deck_case(name, results=OUT):
    """One committed deck: where it is, what drives it, where its forces are."""
    t, v, end_time = deck.velocity_curve()
    return {'name': name, 'deck': os.path.join(DECKS, 'sphere_%s.k' % name),
            'out': os.path.join(results, name), 'top_part': deck.TOP_PART,
            'bottom_part': deck.BOTTOM_PART,
            'contacts': (deck.TOP_CONTACT, deck.BOTTOM_CONTACT),
            'curve': (t, v), 'end_time': end_time, 'stroke': deck.STROKE,
            'driven_mass': deck.PLATE_MASS}


# the stand-in: caps of the sphere's own surface within STAND_IN_CAP of the poles become rigid
# parts (they share the sphere's nodes); the top cap follows a faster version of the decks'
# velocity ramp. Only meant to exercise the reading and plotting code (not a result).
STAND_IN_CAP = 0.01            # m: cap height (cap radius about 45 mm)
STAND_IN_SPEED = 20.0          # m/s
STAND_IN_RAMP = 2.0e-4         # s
STAND_IN_END = 6.0e-4          # s: 10 mm of stroke
STAND_IN_TOP, STAND_IN_BOTTOM = 4, 5      # part ids of the caps
STAND_IN_SETS = (11, 12)                  # symmetry node sets without the cap nodes


def read_mesh_deck(path):
    """Node ids and coordinates, tetrahedra (node rows) and node sets of mesh_sphere.k."""
    ids, x, tets, sets = [], [], [], {}
    section, current = None, None
    with open(path) as f:
        for line in f:
            if line.startswith('$'):
                continue
            if line.startswith('*'):
                section = line.strip()
                current = None
                continue
            if section == '*NODE':
                ids.append(int(line[:8]))
                x.append([float(line[8 + 16 * k:24 + 16 * k]) for k in range(3)])
            elif section == '*ELEMENT_SOLID':
                tets.append([int(line[16 + 8 * k:24 + 8 * k]) for k in range(4)])
            elif section == '*SET_NODE_LIST_TITLE':
                if current is None and not line[:10].strip().isdigit():
                    continue                                   # the title line
                if current is None:
                    current = int(line[:10])
                    sets[current] = []
                else:
                    sets[current] += [int(v) for v in line.split()]
    row = {n: k for k, n in enumerate(ids)}
    return (np.array(ids), np.array(x), np.array([[row[n] for n in t] for t in tets]),
            {s: np.array([row[n] for n in m]) for s, m in sets.items()})


def boundary_faces(tets):
    """Faces (k, 3 node rows) that belong to one tetrahedron only, and that tetrahedron."""
    faces = np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]], tets[:, [0, 1, 3]],
                            tets[:, [0, 1, 2]]])
    owner = np.tile(np.arange(len(tets)), 4)
    key = np.sort(faces, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    once = first[count == 1]
    return faces[once], owner[once]


def stand_in_case():
    """Write the stand-in deck into tests/out/sphere_stand_in/ and describe it."""
    ids, x, tets, sets = read_mesh_deck(os.path.join(DECKS, 'mesh_sphere.k'))
    faces, _ = boundary_faces(tets)
    tol = 1e-9
    on_surface = ~(np.all(x[faces, 0] < tol, axis=1) | np.all(x[faces, 1] < tol, axis=1))
    top = faces[on_surface & np.all(x[faces, 2] > deck.RADIUS - STAND_IN_CAP, axis=1)]
    bottom = faces[on_surface & np.all(x[faces, 2] < -deck.RADIUS + STAND_IN_CAP, axis=1)]
    cap_nodes = set(np.unique(np.concatenate([top.ravel(), bottom.ravel()])).tolist())
    n_elements = len(tets) + 2 * deck.PLATE_DIVISIONS ** 2
    s = np.linspace(0.0, 1.0, deck.RAMP_POINTS)
    t_curve = np.append(STAND_IN_RAMP * s, 10.0 * STAND_IN_END)
    v_curve = np.append(-STAND_IN_SPEED * 0.5 * (1.0 - np.cos(np.pi * s)), -STAND_IN_SPEED)
    f10 = deck.f10
    lines = ['*KEYWORD', '*TITLE', 'sphere compression stand-in: rigid caps, no contact',
             '*INCLUDE', os.path.join(DECKS, 'mesh_sphere.k'),
             '*PART', 'sphere', f10(deck.SPHERE_PART, 1, 1), '*SECTION_SOLID', f10(1, 43),
             '*MAT_POWER_LAW_PLASTICITY',
             f10(1, deck.DENSITY, deck.YOUNG, deck.POISSON, deck.SIGMA0 * deck.ALPHA, 1.0),
             f10(deck.SIGMA0),
             '*SECTION_SHELL', f10(2, 2), f10(*[deck.PLATE_THICKNESS] * 4),
             '*MAT_RIGID', f10(2, deck.PLATE_DENSITY, deck.PLATE_YOUNG, deck.PLATE_POISSON),
             f10(1.0, 7, 7),
             '*MAT_RIGID', f10(3, deck.PLATE_DENSITY, deck.PLATE_YOUNG, deck.PLATE_POISSON),
             f10(1.0, 4, 7)]
    for pid, title, mid in ((deck.TOP_PART, 'top plate (idle)', 2),
                            (deck.BOTTOM_PART, 'bottom plate (idle)', 2),
                            (STAND_IN_TOP, 'top cap', 3), (STAND_IN_BOTTOM, 'bottom cap', 2)):
        lines += ['*PART', title, f10(pid, 2, mid)]
    lines.append('*ELEMENT_SHELL')
    eid = n_elements
    for pid, tri in ((STAND_IN_TOP, top), (STAND_IN_BOTTOM, bottom)):
        for f in tri:
            eid += 1
            lines.append('%8d%8d' % (eid, pid) + ''.join('%8d' % ids[v] for v in
                                                         (f[0], f[1], f[2], f[2])))
    for new, (name, sid) in zip(STAND_IN_SETS, deck.NODE_SETS.items()):
        members = [ids[v] for v in sets[sid] if v not in cap_nodes]
        lines += ['*SET_NODE_LIST', f10(new)]
        lines += [''.join('%10d' % m for m in members[k:k + 8])
                  for k in range(0, len(members), 8)]
    lines += ['*BOUNDARY_SPC_SET', f10(STAND_IN_SETS[0], 0, 1, 0, 0),
              f10(STAND_IN_SETS[1], 0, 0, 1, 0),
              '*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(STAND_IN_TOP, 3, 0, 1, 1.0),
              '*DEFINE_CURVE', f10(1)]
    lines += ['%20.10e%20.10e' % (a, b + 0.0) for a, b in zip(t_curve, v_curve)]
    lines += ['*CONTROL_TERMINATION', f10(STAND_IN_END),
              '*CONTROL_TIMESTEP', f10(0.0, deck.TSSFAC, 0, 0.0, deck.DT2MS),
              '*DATABASE_BINARY_D3PLOT', f10(STAND_IN_END / 8),
              '*DATABASE_GLSTAT', f10(STAND_IN_END / 400), '*END']
    os.makedirs(OUT_STAND_IN, exist_ok=True)
    path = os.path.join(OUT_STAND_IN, 'sphere_stand_in.k')
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    stroke = curve_motion(t_curve, v_curve, np.array([STAND_IN_END]))[0][0]
    return {'name': 'stand_in', 'deck': path, 'out': os.path.join(OUT_STAND_IN, 'stand_in'),
            'top_part': STAND_IN_TOP, 'bottom_part': STAND_IN_BOTTOM, 'contacts': None,
            'curve': (t_curve, v_curve), 'end_time': STAND_IN_END, 'stroke': stroke,
            'driven_mass': 0.0}


# ---- running ------------------------------------------------------------------------------

def run_case(case, ranks, exe):
    """Run one deck on `ranks` ranks; log next to its results; return (rc, seconds)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OPENBLAS_NUM_THREADS='1')
    os.makedirs(os.path.dirname(case['out']), exist_ok=True)
    cmd = ['mpirun', '--oversubscribe', '-np', str(ranks), exe, '-o', case['out'],
           case['deck']]
    print('running %s: %s' % (case['name'], ' '.join(cmd)), flush=True)
    start = time.time()
    with open(case['out'] + '.log', 'w') as log:
        rc = subprocess.run(cmd, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT,
                            env=env).returncode
    seconds = time.time() - start
    print('  %s: exit %d after %.0f s' % (case['name'], rc, seconds), flush=True)
    return rc, seconds


def run_log(case):
    """Cycles, wall seconds and the log text of a finished run (NaN when not found)."""
    path = case['out'] + '.log'
    if not os.path.exists(path):
        return float('nan'), float('nan'), ''
    with open(path) as f:
        text = f.read()
    m = re.findall(r'explicit: (\d+) cycles, (\S+) s', text)
    if not m:
        return float('nan'), float('nan'), text
    return float(m[-1][0]), float(m[-1][1]), text


# ---- histories ----------------------------------------------------------------------------

def curve_motion(t_curve, v_curve, times):
    """Displacement (positive down), velocity and acceleration of a plate whose z velocity is
    the piecewise linear curve (t_curve, v_curve), at the given times."""
    times = np.asarray(times, dtype=float)
    seg = np.diff(t_curve)
    slope = np.diff(v_curve) / seg
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (v_curve[1:] + v_curve[:-1]) * seg)])
    k = np.clip(np.searchsorted(t_curve, times, side='right') - 1, 0, len(seg) - 1)
    dt = times - t_curve[k]
    velocity = v_curve[k] + slope[k] * dt
    return -(cumulative[k] + v_curve[k] * dt + 0.5 * slope[k] * dt ** 2), velocity, slope[k]


def force_history(case):
    """Times, top plate displacement d (positive down) and the normal contact forces on the
    top and bottom plates of the quarter model (positive when pressed), from rcforc if it
    holds both interfaces, else from rbdout; plus the source name."""
    out = case['out']
    rc_path = os.path.join(out, 'rcforc')
    if case['contacts'] and os.path.exists(rc_path):
        rc = read_rcforc(rc_path)
        top, bottom = case['contacts']
        if all(c in rc and 'master' in rc[c] and 'z' in rc[c]['master'] for c in (top, bottom)):
            t = rc[top]['master']['time']
            f_top = rc[top]['master']['z']              # the sphere pushes the top plate up
            f_bottom = -np.interp(t, rc[bottom]['master']['time'], rc[bottom]['master']['z'])
            tangential = np.hypot(rc[top]['master']['x'], rc[top]['master']['y'])
            if np.nanmean(f_top) < 0:
                print('  warning: %s: rcforc z force on the top plate is mostly negative; '
                      'check the sign convention' % case['name'])
            return t, plate_displacement(case, t), f_top, f_bottom, tangential, 'rcforc'
    t, f_top, f_bottom, tangential = rbdout_forces(case)
    return t, plate_displacement(case, t), f_top, f_bottom, tangential, 'rbdout'


def rbdout_forces(case):
    """Times and the forces of the sphere on the top and bottom plates from the reactions of
    their constraints (rbdout), and the tangential force on the top plate."""
    rb = read_rbdout(os.path.join(case['out'], 'rbdout'))
    top, bottom = rb[case['top_part']], rb[case['bottom_part']]
    t = top['time']
    # plate: m a = R + F_contact, so the force of the sphere on it is m a - R
    _, _, accel = curve_motion(*case['curve'], t)
    f_top = case['driven_mass'] * accel - top['z-reaction']
    f_bottom = np.interp(t, bottom['time'], bottom['z-reaction'])
    return t, f_top, f_bottom, np.hypot(top['x-reaction'], top['y-reaction'])


def plate_displacement(case, t):
    """Top plate displacement at times t: rbdout's when there, else the curve's."""
    path = os.path.join(case['out'], 'rbdout')
    if os.path.exists(path):
        top = read_rbdout(path).get(case['top_part'])
        if top is not None and len(top['time']) > 1:
            return -np.interp(t, top['time'], top['z-disp'])
    return curve_motion(*case['curve'], t)[0]


def savitzky_golay(y, window, order=2):
    """Local least-squares polynomial smoothing (odd window); NaN within window/2 of the ends."""
    half = window // 2
    k = np.arange(-half, half + 1)
    vandermonde = np.vander(k, order + 1, increasing=True)
    weights = np.linalg.pinv(vandermonde)[0]            # value of the fit at the centre
    smooth = np.full(len(y), np.nan)
    if len(y) >= window:
        smooth[half:len(y) - half] = np.convolve(y, weights[::-1], mode='valid')
    return smooth


def high_frequency(t, d, force, stroke):
    """High-frequency content of a force history: F minus its Savitzky-Golay smoothing over a
    window of HF_WINDOW_FRACTION of the run, over HF_RANGE of the stroke. Returns the smooth
    force, RMS(F - F_s)/mean(F_s), max |F - F_s|/F_s, the window (s) and the samples used."""
    window = max(5, int(round(HF_WINDOW_FRACTION * len(t))) | 1)
    smooth = savitzky_golay(force, window)
    use = (d >= HF_RANGE[0] * stroke) & (d <= HF_RANGE[1] * stroke) & np.isfinite(smooth)
    if not np.any(use):
        return smooth, float('nan'), float('nan'), float('nan'), use
    residual = force[use] - smooth[use]
    rms = np.sqrt(np.mean(residual ** 2)) / np.mean(smooth[use])
    peak = np.max(np.abs(residual) / np.abs(smooth[use]))
    return smooth, rms, peak, window * np.mean(np.diff(t)), use


def energies(case, t):
    """glstat energies at times t: sphere kinetic energy (the driven plate's removed),
    internal, sliding interface, and the energy ratio; all of the quarter model."""
    g = read_glstat(os.path.join(case['out'], 'glstat'))
    kinetic = g['kinetic energy']
    if case['driven_mass'] > 0.0:
        _, velocity, _ = curve_motion(*case['curve'], g['time'])
        kinetic = kinetic - 0.5 * case['driven_mass'] * velocity ** 2
    at = {k: np.interp(t, g['time'], v) for k, v in (
        ('kinetic', kinetic), ('internal', g['internal energy']),
        ('sliding', g.get('sliding interface energy', np.zeros_like(kinetic))),
        ('ratio', g['total energy / initial energy']))}
    at['glstat_time'] = g['time']
    at['glstat_ratio'] = g['total energy / initial energy']
    return at


# ---- result states ------------------------------------------------------------------------

def read_states(case):
    """Mesh of the sphere (reference coordinates, tetrahedra as node rows, HDF5 cell rows)
    and the states: list of (time, displacement, cell plastic strain, cell pressure)."""
    name = os.path.splitext(os.path.basename(case['deck']))[0]    # mefem names it after the deck
    with h5py.File(os.path.join(case['out'], name + '.h5'), 'r') as f:
        x = f['mesh/coordinates'][()]
        offsets = f['mesh/cell_offsets'][()]
        conn = f['mesh/connectivity'][()]
        cells = np.nonzero((f['mesh/cell_part'][()] == deck.SPHERE_PART) &
                           (f['mesh/cell_types'][()] == SPHERE_TET))[0]
        tets = np.array([conn[offsets[c]:offsets[c] + 4] for c in cells])
        states = [(0.0, np.zeros_like(x), np.zeros(len(cells)), np.zeros(len(cells)))]
        for step, t in zip(f['time_history/step'][()], f['time_history/time'][()]):
            g = f['states/%06d' % step]
            if t <= 0.0 or 'displacement' not in g['point']:
                continue
            states.append((float(t), g['point/displacement'][()],
                           g['cell/plastic_strain'][()][cells, 0],
                           g['cell/pressure'][()][cells, 0]))
    return x, tets, states


def neighbour_jumps(x, tets, value):
    """RMS over all pairs of tetrahedra sharing a face of the jump of a cell field between
    them, divided by the volume-weighted RMS of the field: about h |grad| / |field| for a
    smooth field, O(1) for a checkerboard."""
    faces = np.sort(np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]], tets[:, [0, 1, 3]],
                                    tets[:, [0, 1, 2]]]), axis=1)
    owner = np.tile(np.arange(len(tets)), 4)
    order = np.lexsort(faces.T[::-1])
    faces, owner = faces[order], owner[order]
    same = np.all(faces[1:] == faces[:-1], axis=1)
    a, b = owner[:-1][same], owner[1:][same]
    a_, b_, c_ = (x[tets[:, i]] - x[tets[:, 0]] for i in (1, 2, 3))
    volume = np.abs(np.einsum('ij,ij->i', np.cross(a_, b_), c_)) / 6.0
    reference = np.sqrt(np.sum(volume * value ** 2) / np.sum(volume))
    return float(np.sqrt(np.mean((value[a] - value[b]) ** 2)) / reference)


def pick_states(case, states, fractions):
    """The states closest to the given fractions of the stroke: list of (d, state)."""
    d = curve_motion(*case['curve'], np.array([s[0] for s in states]))[0]
    picked = []
    for fraction in fractions:
        k = int(np.argmin(np.abs(d - fraction * case['stroke'])))
        picked.append((d[k], states[k]))
    return picked


def plot_sections(cases, meshes, field, label, scale, path, stroke_unit):
    """Field on the deformed symmetry plane x = 0, mirrored about y = 0 into a meridian
    section; one row per case, one column per stage; one colour scale."""
    panels = []
    for case in cases:
        x, tets, states = meshes[case['name']]
        faces, owner = boundary_faces(tets)
        plane = np.all(np.abs(x[faces, 0]) < 1e-9, axis=1)
        row = []
        for d, state in pick_states(case, states, STAGE_FRACTIONS):
            t, u, eps, pressure = state
            value = (eps if field == 'plastic_strain' else pressure)[owner[plane]] * scale
            row.append((d, x + u, faces[plane], value))
        panels.append(row)
    values = np.concatenate([p[3] for row in panels for p in row])
    lo, hi = (0.0, np.percentile(values, 99.5)) if field == 'plastic_strain' else \
        np.percentile(values, [0.5, 99.5])
    fig, axes = plt.subplots(len(cases), len(STAGE_FRACTIONS), squeeze=False,
                             figsize=(3.2 * len(STAGE_FRACTIONS), 2.5 * len(cases) + 0.7),
                             layout='constrained')
    for row_axes, row, case in zip(axes, panels, cases):
        for ax, (d, xd, tri, value) in zip(row_axes, row):
            for sign in (1.0, -1.0):
                pc = ax.tripcolor(sign * xd[:, 1], xd[:, 2], tri, facecolors=value,
                                  cmap='jet', vmin=lo, vmax=hi, edgecolors='none')
            top = deck.RADIUS - d
            ax.plot([-deck.PLATE_SIZE, deck.PLATE_SIZE], [top, top], color='0.3', lw=2)
            ax.plot([-deck.PLATE_SIZE, deck.PLATE_SIZE], [-deck.RADIUS, -deck.RADIUS],
                    color='0.3', lw=2)
            ax.set_aspect('equal')
            ax.set_xlim(-0.17, 0.17)
            ax.set_ylim(-0.11, 0.11)
            ax.set_title('%s, d = %.0f %s' % (LABELS[case['name']], d / stroke_unit[0],
                                              stroke_unit[1]), fontsize=8)
            ax.tick_params(labelsize=7)
    cb = fig.colorbar(pc, ax=axes, shrink=0.8)
    cb.set_label(label)
    fig.suptitle('Sphere compression: %s on the symmetry plane x = 0 (y < 0 mirrored)'
                 % label.split(' [')[0], fontsize=10)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_progressive(case, mesh, path, stroke_unit):
    """Cut-away 3D views (quadrants x>0 y>0, x<0 y>0 and x>0 y<0) of the deformed sphere at
    PROGRESSIVE_FRACTIONS of the stroke, coloured by effective plastic strain, plates in grey."""
    x, tets, states = mesh
    faces, owner = boundary_faces(tets)
    on_x0 = np.all(np.abs(x[faces, 0]) < 1e-9, axis=1)
    on_y0 = np.all(np.abs(x[faces, 1]) < 1e-9, axis=1)
    outer = ~(on_x0 | on_y0)
    picked = pick_states(case, states, PROGRESSIVE_FRACTIONS)
    hi = max(np.percentile(s[2], 99.5) for _, s in picked) or 1.0
    cmap = plt.get_cmap('jet')
    fig = plt.figure(figsize=(3.3 * len(picked), 3.8), layout='constrained')
    for k, (d, (t, u, eps, _)) in enumerate(picked):
        ax = fig.add_subplot(1, len(picked), k + 1, projection='3d')
        xd = x + u
        polys, colours = [], []
        # quadrant copies: (sign x, sign y, which faces); cut faces left open: y = 0 of the
        # x < 0 copy and x = 0 of the y < 0 copy
        for sx, sy, keep in ((1, 1, outer), (-1, 1, outer | on_y0), (1, -1, outer | on_x0)):
            verts = xd[faces[keep]] * np.array([sx, sy, 1.0])
            polys.append(verts)
            colours.append(cmap(np.clip(eps[owner[keep]] / hi, 0.0, 1.0)))
        for z in (deck.RADIUS - d, -deck.RADIUS):
            # plates as small translucent tiles, so that the depth sorting of matplotlib
            # (per polygon, by mean depth) places them correctly against the sphere
            g = np.linspace(-PLATE_DRAWN, PLATE_DRAWN, PLATE_TILES + 1)
            tiles = [[[g[i], g[j], z], [g[i + 1], g[j], z], [g[i + 1], g[j + 1], z],
                      [g[i], g[j + 1], z]] for i in range(PLATE_TILES) for j in range(PLATE_TILES)]
            polys.append(np.array(tiles))
            colours.append(np.tile([0.55, 0.55, 0.55, 0.18], (len(tiles), 1)))
        collection = Poly3DCollection([p for group in polys for p in group],
                                      facecolors=np.concatenate(colours),
                                      edgecolors=(0, 0, 0, 0.25), linewidths=0.1)
        ax.add_collection3d(collection)
        ax.set_xlim(-PLATE_DRAWN, PLATE_DRAWN)
        ax.set_ylim(-PLATE_DRAWN, PLATE_DRAWN)
        ax.set_zlim(-0.105, 0.105)
        ax.set_box_aspect((2 * PLATE_DRAWN, 2 * PLATE_DRAWN, 0.21), zoom=1.35)
        ax.view_init(elev=20, azim=-135)
        ax.set_axis_off()
        ax.set_title('d = %.0f %s' % (abs(d) / stroke_unit[0], stroke_unit[1]), fontsize=9)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, hi))
    cb = fig.colorbar(sm, ax=fig.axes, shrink=0.7)
    cb.set_label('effective plastic strain')
    fig.suptitle('Sphere compression, %s: progressive deformation (three quadrants of the '
                 'quarter model mirrored)' % LABELS[case['name']], fontsize=10)
    fig.savefig(path, dpi=130)
    plt.close(fig)


# ---- curves -------------------------------------------------------------------------------

def plot_curves(cases, histories, path, stroke_unit):
    """Force (full sphere) against plate displacement, its high-frequency part, and the
    kinetic / internal energy ratio, all cases."""
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 9.0), sharex=True,
                             gridspec_kw={'height_ratios': [3, 1.2, 1.2]}, layout='constrained')
    for case in cases:
        h = histories[case['name']]
        d = h['d'] / stroke_unit[0]
        colour = COLOURS[case['name']]
        axes[0].plot(d, QUARTER_TO_FULL * h['f_top'] / 1e3, color=colour, lw=1.3,
                     label='%s, top plate' % LABELS[case['name']])
        axes[0].plot(d, QUARTER_TO_FULL * h['f_bottom'] / 1e3, '--', color=colour, lw=0.8,
                     label='%s, bottom plate' % LABELS[case['name']])
        use = h['hf_use']
        axes[1].plot(d[use], 100 * (h['f_top'][use] - h['f_smooth'][use]) / h['f_smooth'][use],
                     color=colour, lw=0.7, label='%s: RMS %.2f %%' % (LABELS[case['name']],
                                                                    100 * h['hf_rms']))
        ok = h['internal'] > 0
        axes[2].semilogy(d[ok], np.maximum(h['kinetic'][ok] / h['internal'][ok], 1e-8),
                         color=colour, lw=1.0, label=LABELS[case['name']])
    axes[0].set_ylabel('normal contact force, full sphere [kN]')
    axes[0].set_title('Sphere compression (Hu & Wu 2013, sec. 4.2): force against plate '
                      'displacement', fontsize=10)
    axes[0].legend(fontsize=8, loc='upper left')
    axes[0].set_ylim(bottom=0)
    axes[1].set_ylabel('(F - F_smooth)/F_smooth [%]', fontsize=8)
    axes[1].legend(fontsize=7, loc='upper right')
    axes[2].set_ylabel('kinetic / internal energy', fontsize=8)
    axes[2].axhline(0.05, color='0.5', lw=0.8, ls=':')
    axes[2].legend(fontsize=7, loc='upper right')
    axes[2].set_xlabel('top plate displacement d [%s]' % stroke_unit[1])
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def short_step_records(case, t):
    """Mask of the history records (times t) written after a cycle whose time step was less
    than SHORT_STEP of the median step: the last cycle, shortened to land on the end time. The
    penalty of the contact is limited by the nodal mass over the square of the step, so that
    cycle's contact force is not comparable with the others (measured: +24 % at t = 3 ms of a
    shortened run)."""
    g = read_glstat(os.path.join(case['out'], 'glstat'))
    step = g['time step']
    short = g['time'][step < SHORT_STEP * np.median(step)]
    return np.isin(np.round(t, 15), np.round(short, 15))


def analyse(case):
    """Every measure of one finished run."""
    t, d, f_top, f_bottom, tangential, source = force_history(case)
    keep = ~short_step_records(case, t)
    if not np.all(keep):
        print('  %s: %d record(s) after a shortened last step left out (t = %s)' % (
            case['name'], np.sum(~keep), ', '.join('%.6g' % v for v in t[~keep])))
    t, d, f_top, f_bottom, tangential = (a[keep] for a in (t, d, f_top, f_bottom, tangential))
    smooth, hf_rms, hf_peak, window, use = high_frequency(t, d, f_top, case['stroke'])
    e = energies(case, t)
    h = {'t': t, 'd': d, 'f_top': f_top, 'f_bottom': f_bottom, 'tangential': tangential,
         'source': source, 'f_smooth': smooth, 'hf_rms': hf_rms, 'hf_peak': hf_peak,
         'hf_window': window, 'hf_use': use}
    h.update(e)
    loaded = (d >= ENERGY_FROM * case['stroke']) & (h['internal'] > 0)
    ratio = h['kinetic'][loaded] / h['internal'][loaded]
    h['ke_ie_max'] = float(ratio.max()) if ratio.size else float('nan')
    h['ke_ie_end'] = float(h['kinetic'][-1] / h['internal'][-1]) if h['internal'][-1] > 0 \
        else float('nan')
    balance = f_top[use] - f_bottom[use]
    h['balance_rms'] = float(np.sqrt(np.mean(balance ** 2)) / np.mean(f_top[use])) \
        if np.any(use) else float('nan')
    late = e['glstat_time'] > 0.05 * case['end_time']
    ratio = e['glstat_ratio'][late]
    h['energy_ratio'] = (float(ratio.min()), float(ratio.max())) if ratio.size else \
        (float('nan'), float('nan'))
    h['sliding_over_internal'] = float(h['sliding'][-1] / h['internal'][-1]) \
        if h['internal'][-1] > 0 else float('nan')
    h['cycles'], h['seconds'], _ = run_log(case)
    # two independent outputs of the same force: contact resultant and plate reaction
    h['rcforc_vs_rbdout'] = float('nan')
    if source == 'rcforc' and np.any(use):
        t_rb, f_rb, _, _ = rbdout_forces(case)
        diff = np.interp(t, t_rb, f_rb)[use] - f_top[use]
        h['rcforc_vs_rbdout'] = float(np.sqrt(np.mean(diff ** 2)) / np.mean(f_top[use]))
    return h


def field_measures(mesh):
    """Neighbour-jump measure of the pressure and plastic strain at the last state, and the
    largest plastic strain and the bulge (largest distance of a node from the z axis)."""
    x, tets, states = mesh
    _, u, eps, pressure = states[-1]
    xd = (x + u)[np.unique(tets)]
    return {'pressure_jumps': neighbour_jumps(x, tets, pressure),
            'eps_jumps': neighbour_jumps(x, tets, eps), 'eps_max': float(eps.max()),
            'bulge_radius': float(np.hypot(xd[:, 0], xd[:, 1]).max())}


def force_at(h, target):
    """Full-sphere force at plate displacement `target` (the last record if the run ended
    within END_TOLERANCE of it; NaN if not reached)."""
    if h['d'][-1] < target * (1 - END_TOLERANCE):
        return float('nan')
    return QUARTER_TO_FULL * float(np.interp(min(target, h['d'][-1]), h['d'], h['f_top']))


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--no-run', action='store_true', help='reuse the results (only '
                        'measure and plot)')
    parser.add_argument('--stand-in', action='store_true', help='the mesh squeezed between '
                        'two rigid plates without contact (tries the script)')
    parser.add_argument('--ranks', type=int, default=2, help='MPI ranks per run (default 2)')
    parser.add_argument('--exe', default=os.path.join(ROOT, 'bin', 'mefem'),
                        help='the mefem executable (default bin/mefem)')
    parser.add_argument('--results', help='results directory of the runs (default '
                        'tests/out/sphere)')
    parser.add_argument('--figures', help='where figures and tables go (default '
                        'doc/verification_data)')
    args = parser.parse_args()
    ranks = args.ranks
    exe = os.path.abspath(args.exe)
    stand_in = args.stand_in
    if stand_in:
        cases = [stand_in_case()]
        data = os.path.join(OUT_STAND_IN, 'figures')
        stroke_unit = (1e-3, 'mm')
    else:
        results = os.path.abspath(args.results) if args.results else OUT
        cases = [deck_case(name, results) for name in deck.FRICTION]
        data = DATA
        stroke_unit = (1e-3, 'mm')
    if args.figures:
        data = os.path.abspath(args.figures)
    if not args.no_run:
        for case in cases:
            rc, _ = run_case(case, ranks, exe)
            if rc != 0:
                print('  %s failed; see %s.log' % (case['name'], case['out']))
    os.makedirs(data, exist_ok=True)
    histories, meshes = {}, {}
    for case in list(cases):
        if not os.path.exists(os.path.join(case['out'], 'glstat')):
            print('%s: no results in %s' % (case['name'], case['out']))
            cases.remove(case)
            continue
        histories[case['name']] = analyse(case)
        meshes[case['name']] = read_states(case)
        histories[case['name']].update(field_measures(meshes[case['name']]))
    if not cases:
        raise SystemExit('no results to post-process')
    prefix = os.path.join(data, 'sphere_')
    plot_curves(cases, histories, prefix + 'force_displacement.png', stroke_unit)
    plot_sections(cases, meshes, 'plastic_strain', 'effective plastic strain', 1.0,
                  prefix + 'plastic_strain.png', stroke_unit)
    plot_sections(cases, meshes, 'pressure', 'pressure -tr(sigma)/3 [MPa]', 1e-6,
                  prefix + 'pressure.png', stroke_unit)
    progressive = [c for c in cases if c['name'] in ('friction', 'stand_in')]
    if progressive:
        plot_progressive(progressive[0], meshes[progressive[0]['name']],
                         prefix + 'progressive.png', stroke_unit)
    with open(prefix + 'curves.csv', 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(['case', 'time_s', 'plate_displacement_m', 'force_top_full_N',
                    'force_bottom_full_N', 'kinetic_quarter_J', 'internal_quarter_J',
                    'sliding_quarter_J'])
        for case in cases:
            h = histories[case['name']]
            for k in range(len(h['t'])):
                w.writerow([case['name']] + ['%.8g' % v for v in (
                    h['t'][k], h['d'][k], QUARTER_TO_FULL * h['f_top'][k],
                    QUARTER_TO_FULL * h['f_bottom'][k], h['kinetic'][k], h['internal'][k],
                    h['sliding'][k])])
    marks = [f * cases[0]['stroke'] for f in STAGE_FRACTIONS]
    rows = []
    for case in cases:
        h = histories[case['name']]
        row = {'case': case['name'], 'source': h['source'], 'd_end_m': h['d'][-1]}
        for m in marks:
            row['F_full_N_at_%.4g_m' % m] = force_at(h, m)
        row.update({'hf_rms': h['hf_rms'], 'hf_peak': h['hf_peak'],
                    'hf_window_s': h['hf_window'], 'top_bottom_rms': h['balance_rms'],
                    'ke_ie_max': h['ke_ie_max'], 'ke_ie_end': h['ke_ie_end'],
                    'energy_ratio_min': h['energy_ratio'][0],
                    'energy_ratio_max': h['energy_ratio'][1],
                    'sliding_over_internal_end': h['sliding_over_internal'],
                    'pressure_jump_rms': h['pressure_jumps'], 'eps_jump_rms': h['eps_jumps'],
                    'eps_max': h['eps_max'], 'bulge_radius_m': h['bulge_radius'],
                    'rcforc_vs_rbdout_rms': h['rcforc_vs_rbdout'],
                    'cycles': h['cycles'], 'wall_s': h['seconds']})
        rows.append(row)
    with open(prefix + 'summary.csv', 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: ('%.6g' % v if isinstance(v, float) else v) for k, v in r.items()})
    # table
    print()
    print('full-sphere normal force on the top plate [kN] at plate displacement d:')
    print('%-13s %-7s %8s ' % ('case', 'source', 'd_end mm') +
          ' '.join('%9s' % ('d=%.0fmm' % (m / 1e-3)) for m in marks))
    for case, r in zip(cases, rows):
        print('%-13s %-7s %8.2f ' % (case['name'], r['source'], 1e3 * r['d_end_m']) +
              ' '.join('%9.1f' % (force_at(histories[case['name']], m) / 1e3) for m in marks))
    print()
    print('%-13s %8s %8s %9s %9s %9s %9s %15s %9s %8s %7s' % (
        'case', 'HF rms%', 'HF max%', 'window', 'top-bot%', 'KE/IE max', 'KE/IE end',
        'energy ratio', 'slide/IE', 'cycles', 'wall s'))
    for case, r in zip(cases, rows):
        print('%-13s %8.3f %8.2f %9.2e %9.3f %9.2e %9.2e %7.4f..%6.4f %9.3f %8.0f %7.0f' % (
            case['name'], 100 * r['hf_rms'], 100 * r['hf_peak'], r['hf_window_s'],
            100 * r['top_bottom_rms'], r['ke_ie_max'], r['ke_ie_end'], r['energy_ratio_min'],
            r['energy_ratio_max'], r['sliding_over_internal_end'], r['cycles'], r['wall_s']))
    for case, r in zip(cases, rows):
        if np.isfinite(r['rcforc_vs_rbdout_rms']):
            print('%s: top plate force from rcforc and from rbdout differ by %.2e (RMS / mean)'
                  % (case['name'], r['rcforc_vs_rbdout_rms']))
    print()
    print('last state: %-13s %12s %12s %9s %12s' % ('case', 'p jumps/rms', 'ep jumps/rms',
                                                      'ep max', 'bulge r mm'))
    for case, r in zip(cases, rows):
        print('            %-13s %12.3f %12.3f %9.3f %12.1f' % (
            case['name'], r['pressure_jump_rms'], r['eps_jump_rms'], r['eps_max'],
            1e3 * r['bulge_radius_m']))
    if len(cases) == 2:
        a, b = (histories[c['name']] for c in cases)
        common = [m for m in marks if np.isfinite(force_at(a, m)) and np.isfinite(force_at(b, m))]
        for m in common:
            print('d = %.0f mm: friction / frictionless force = %.4f' % (
                m / 1e-3, force_at(b, m) / force_at(a, m)))
    print('figures and tables in %s' % data)


if __name__ == '__main__':
    main()
