"""The seed paper's punch benchmark (Hu & Wu 2013, section 4.1): runs and measures shared by
tests/verification/test_punch_seed.py and post/punch_study.py.

The decks are committed under input/punch/ (generated from gmsh meshes by
input/punch/msh_to_k.py; setup and choices in doc/verification.md, "Seed punch"). Two punch
models per mesh and element: 'tool' (the main model: a rigid punch, part 2, pressed down by
*BOUNDARY_PRESCRIBED_MOTION_RIGID in frictionless mortar contact; load = the tool's vertical
rcforc force) and 'nodal' (the comparison: the nodes under the punch moved down; load = minus
the sum of their vertical reactions). Each run writes tests/out/punch/<deck name>/ with
<deck name>.h5 (and rcforc for the tool model); the measures read those files only.
Units of the decks: cm, N, s; loads are N per cm of thickness on the half model.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import ROOT, run  # noqa: E402
sys.path.insert(0, os.path.join(ROOT, 'post'))
from lsdyna_ascii import read_rcforc  # noqa: E402

DECKS = os.path.join(ROOT, 'input', 'punch')
OUT = os.path.join(ROOT, 'tests', 'out', 'punch')
sys.path.insert(0, DECKS)
from msh_to_k import (HEIGHT, NODE_SETS, PUNCH_DEPTH, PUNCH_HALF_WIDTH,  # noqa: E402,F401
                      MESHES, ELFORMS, MODELS, TOOL_FIRST_ID, TOOL_HEIGHT, TOOL_LEFT,
                      SIGMA0, deck_file)

VARIANTS = {'mefem': 'ME-FEM (43)', 'standard': 'standard (13)'}
BLOCK_PART = 1
CONTACT_ID = 1                 # the punch contact's interface number in rcforc


def deck_name(mesh, variant, model='tool'):
    """Deck (and output) name: punch_<mesh>_<variant> (tool), punch_<mesh>_<variant>_nodal."""
    return deck_file(mesh, variant, model)[:-2]


def run_deck(mesh, variant, model='tool', ranks=1, exe='bin/mefem', out=OUT):
    """Run one committed deck with results under `out`; return (return code, log text, path
    of the HDF5 file)."""
    name = deck_name(mesh, variant, model)
    outdir = os.path.join(out, name)
    rc, text = run(os.path.join(DECKS, name + '.k'), outdir, ranks=ranks, exe=exe)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, name + '.log'), 'w') as f:
        f.write(text)
    return rc, text, os.path.join(outdir, name + '.h5')


def _mesh(f):
    """Reference coordinates (n, 2), the block's triangles (m, 3) as node rows, and the mask
    of the block's cells among all output cells (the tool's are left out)."""
    x = f['mesh/coordinates'][()][:, :2]
    offsets = f['mesh/cell_offsets'][()]
    rows = f['mesh/connectivity'][()]
    block = f['mesh/cell_part'][()] == BLOCK_PART
    tri = np.array([rows[offsets[c]:offsets[c] + 3] for c in np.nonzero(block)[0]])
    return x, tri, block


def block_nodes(f):
    """Rows of the block's nodes (the tool's have ids from TOOL_FIRST_ID on)."""
    return np.nonzero(f['mesh/node_ids'][()] < TOOL_FIRST_ID)[0]


def _states(f):
    """State groups that carry results (displacement and reactions), in time order."""
    groups = [f['states'][k] for k in f['states']]
    groups = [g for g in groups if 'reaction_force' in g['point']]
    return sorted(groups, key=lambda g: g.attrs['time'])


def punch_nodes(f, x):
    """Rows of the punch node set: the node_set_4 output field, else by geometry."""
    name = 'node_set_%d' % NODE_SETS['punch']
    for g in _states(f)[:1]:
        if name in g['point']:
            return np.nonzero(g['point'][name][()][:, 0] > 0.5)[0]
    return np.nonzero(np.isclose(x[:, 1], HEIGHT) &
                      (x[:, 0] <= PUNCH_HALF_WIDTH * (1 + 1e-9)))[0]


def load_curve(h5path, model='tool'):
    """Arrays time, punch displacement d (positive down) and punch load F (N per cm, half
    model), starting at (0, 0, 0). Tool model: every converged step of rcforc (next to the
    HDF5 file), F = the vertical force of the block on the tool, d = d_y t (the tool's
    prescribed motion, linear in t). Nodal model: every output state, F = -sum of the
    vertical reactions at the punch nodes, d = minus their mean vertical displacement."""
    if model == 'tool':
        r = read_rcforc(os.path.join(os.path.dirname(h5path), 'rcforc'))[CONTACT_ID]['master']
        t = np.concatenate([[0.0], r['time']])
        return np.array([t, PUNCH_DEPTH * t, np.concatenate([[0.0], r['y']])])
    with h5py.File(h5path, 'r') as f:
        x, _, _ = _mesh(f)
        punch = punch_nodes(f, x)
        rows = [(0.0, 0.0, 0.0)]
        for g in _states(f):
            u = g['point/displacement'][()]
            r = g['point/reaction_force'][()]
            rows.append((g.attrs['time'], -u[punch, 1].mean(), -r[punch, 1].sum()))
    return np.array(rows).T


def edge_pairs(tri):
    """Pairs of triangles sharing an edge."""
    owner, pairs = {}, []
    for e, t in enumerate(tri):
        for k in range(3):
            key = tuple(sorted((t[k], t[(k + 1) % 3])))
            if key in owner:
                pairs.append((owner[key], e))
            else:
                owner[key] = e
    return np.array(pairs)


def tool_force_x(h5path):
    """Horizontal force of the block on the tool (rcforc) at the end: the material piled up
    against the flank pushes the tool towards the symmetry plane (negative)."""
    r = read_rcforc(os.path.join(os.path.dirname(h5path), 'rcforc'))[CONTACT_ID]['master']
    return float(r['x'][-1])


def support_balance(h5path):
    """Per output state of a tool run: time, the tool's vertical force from rcforc at that
    time, and the sum of the vertical reactions of the block's supports (only the bottom
    carries vertical reactions). Equilibrium of the block: the two are equal."""
    r = read_rcforc(os.path.join(os.path.dirname(h5path), 'rcforc'))[CONTACT_ID]['master']
    rows = []
    with h5py.File(h5path, 'r') as f:
        nodes = block_nodes(f)
        for g in _states(f):
            t = g.attrs['time']
            k = int(np.argmin(abs(r['time'] - t)))
            if abs(r['time'][k] - t) > 1e-9 * max(t, 1.0):
                continue
            rows.append((t, r['y'][k], g['point/reaction_force'][()][nodes, 1].sum()))
    return np.array(rows).T


def tool_penetration(state):
    """Deepest penetration (cm) of a block node into the tool at the final state: the tool
    occupies [TOOL_LEFT, A] x [H - d, H - d + TOOL_HEIGHT]; a node inside it is at the
    smaller of its distances to the bottom face and to the flank."""
    d = PUNCH_DEPTH * state['time']
    xd = state['x'] + state['u']
    xd = xd[state['block_nodes']]
    bottom = HEIGHT - d
    inside = (xd[:, 0] < PUNCH_HALF_WIDTH) & (xd[:, 1] > bottom) & \
        (xd[:, 1] < bottom + TOOL_HEIGHT)
    if not inside.any():
        return 0.0
    return float(np.max(np.minimum(xd[inside, 1] - bottom, PUNCH_HALF_WIDTH - xd[inside, 0])))


def pile_up(state):
    """Highest rise (cm) of the free surface beside the punch at the final state."""
    free = np.isclose(state['x'][:, 1], HEIGHT) & (state['x'][:, 0] > PUNCH_HALF_WIDTH + 1e-9)
    free &= np.isin(np.arange(len(state['x'])), state['block_nodes'])
    return float(state['u'][free, 1].max())


def final_state(h5path):
    """Mesh, displacement, element pressure and plastic strain (block only) of the last
    state."""
    with h5py.File(h5path, 'r') as f:
        x, tri, block = _mesh(f)
        g = _states(f)[-1]
        return {'x': x, 'tri': tri, 'time': g.attrs['time'], 'block_nodes': block_nodes(f),
                'u': g['point/displacement'][()][:, :2],
                'pressure': g['cell/pressure'][()][block, 0],
                'plastic_strain': g['cell/plastic_strain'][()][block, 0]}


def checkerboard(state):
    """Pressure-jump measures of the final state.

    p_ref: area-weighted mean element pressure in the square under the punch (reference
    centroids in [0, A] x [H - A, H]). Over all pairs of elements sharing an edge:
    jump_rms = RMS(p_1 - p_2) / p_ref; jump_rms_plastic: the same over the pairs whose two
    elements are both plastic (e_p > 1e-3), where the checkerboard of locking elements lives.
    """
    x, tri, p = state['x'], state['tri'], state['pressure']
    centroid = x[tri].mean(axis=1)
    a = x[tri[:, 1]] - x[tri[:, 0]]
    b = x[tri[:, 2]] - x[tri[:, 0]]
    area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    under = (centroid[:, 0] <= PUNCH_HALF_WIDTH) & (centroid[:, 1] >= HEIGHT - PUNCH_HALF_WIDTH)
    p_ref = np.sum(area[under] * p[under]) / np.sum(area[under])
    pairs = edge_pairs(tri)
    jump = p[pairs[:, 0]] - p[pairs[:, 1]]
    plastic = (state['plastic_strain'][pairs[:, 0]] > 1e-3) & \
        (state['plastic_strain'][pairs[:, 1]] > 1e-3)
    return {'p_ref': p_ref,
            'jump_rms': np.sqrt(np.mean(jump ** 2)) / abs(p_ref),
            'jump_rms_plastic': np.sqrt(np.mean(jump[plastic] ** 2)) / abs(p_ref),
            'plastic_pairs': int(plastic.sum()), 'pairs': len(pairs)}


def step_iterations(text):
    """Newton iterations of every converged step, from the run log."""
    return [int(line.split(',')[2].split()[0]) for line in text.splitlines()
            if line.startswith('step ') and line.rstrip().endswith('iterations')]


def newton_counts(text):
    """(steps, cut-backs, Newton iterations, wall seconds) from the run log, NaN/0 if
    missing."""
    counts, seconds = (0, 0, 0), float('nan')
    for line in text.splitlines():
        if line.startswith('implicit:') and 'cut-backs' in line:
            v = line.split()
            counts = int(v[1]), int(v[3]), int(v[5])
        elif line.startswith('wall time'):
            seconds = float(line.split()[2])
    return counts + (seconds,)
