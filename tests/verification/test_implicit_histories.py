"""glstat and rbdout of the implicit (quasi-static) analysis (doc/theory.md 5,
doc/output_histories.md): a block of ME-FEM tets (1 x 1 x 1 mm, *MAT_ELASTIC E = 1000 MPa,
nu = 0.3, symmetry planes x = 0, y = 0, z = 0: uniaxial stress) pressed by a rigid shell tool
moved down by DELTA = 1e-3 mm (*BOUNDARY_PRESCRIBED_MOTION_RIGID VAD = 2) in 4 steps; and the
same block stretched by a nodal load (*LOAD_NODE_SET on its top, no tool). Units mm, N, MPa, mJ.

Exact (linear elasticity, small strain): the strain energy of the block is E eps^2 V / 2 with
eps the block's strain (read from its top); the tool's drive does the work int F d(delta_tool)
(F from rcforc); the penalty spring holds F (delta_tool - delta_top) / 2 (linear spring); the
load does the work F u_top / 2 under a linear ramp. rbdout: the tool's translation, its mean
velocity over the last step, and the force its drive applies, minus rcforc's force on it.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import box_tets, node_set, curve, run_case
from lsdyna_ascii import read_glstat, read_rbdout, read_rcforc

E, NU, DELTA, LOAD = 1000.0, 0.3, 1.0e-3, 0.5
checks = Checks('implicit_histories')


def deck(tool):
    xb, cb = box_tets(1.0, 1.0, 1.0, 3, 3, 3)
    nb = len(xb)
    spc = []
    for k in range(3):
        spc += node_set(k + 1, np.nonzero(xb[:, k] < 1e-9)[0])
        dofs = [0, 0, 0]
        dofs[k] = 1
        spc += ['*BOUNDARY_SPC_SET', f10(k + 1, 0, *dofs)]
    blocks = [['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
               '*MAT_ELASTIC', free(1, 1e-9, E, NU)], spc, curve(1, [(0, 0), (1, 1)])]
    if tool:
        xt = np.array([[-0.5 + i * 0.5, -0.5 + j * 0.5, 1.0] for j in range(5) for i in range(5)])
        ct = np.array([[j * 5 + i, j * 5 + i + 1, (j + 1) * 5 + i + 1, (j + 1) * 5 + i]
                       for j in range(4) for i in range(4)])
        blocks += [nodes_card(np.vstack([xb, xt])), elements_card('ELEMENT_SOLID', cb, pid=1),
                   elements_card('ELEMENT_SHELL', ct + nb, pid=2, first_id=len(cb) + 1),
                   ['*PART', 'tool', f10(2, 2, 2), '*SECTION_SHELL', f10(2, 2),
                    f10(0.1, 0.1, 0.1, 0.1), '*MAT_RIGID', free(2, 1e-9, 2e5, 0.3),
                    f10(1.0, 0, 7)],
                   ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, 3, 2, 1, -DELTA)],
                   ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), f10(0.0),
                    f10(1.0, 1.0)], ['*DATABASE_RCFORC', f10(0.25)]]
    else:
        top = np.nonzero(abs(xb[:, 2] - 1.0) < 1e-9)[0]
        blocks += [nodes_card(xb), elements_card('ELEMENT_SOLID', cb, pid=1),
                   node_set(9, top), ['*LOAD_NODE_SET', f10(9, 3, 1, LOAD / len(top))]]
    blocks += [['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.25),
                '*CONTROL_IMPLICIT_SOLUTION', f10(12), '*DATABASE_BINARY_D3PLOT', f10(0.25),
                '*DATABASE_GLSTAT', f10(0.25)]]
    return nb, blocks


def top_strain(out, name, nb):
    """Mean strain of the block's top (from its z displacement) in each state."""
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        xs = f['mesh/coordinates'][()]
        ids = f['mesh/node_ids'][()]
        top = (abs(xs[:, 2] - 1.0) < 1e-9) & (ids <= nb)
        return np.array([-f['states/%s/point/displacement' % k][()][top, 2].mean()
                         for k in sorted(f['states'].keys())])


# ---- the tool --------------------------------------------------------------------------------
nb, blocks = deck(tool=True)
runs = {}
for ranks in (1, 2):
    name = 'implicit_histories_tool_np%d' % ranks
    rc, text, out = run_case(name, blocks, ranks=ranks)
    checks.check(rc == 0, 'tool on %d rank(s): run succeeds' % ranks, text[-600:])
    if rc == 0:
        runs[ranks] = (name, out)
if 1 in runs:
    name, out = runs[1]
    g = read_glstat(os.path.join(out, 'glstat'))
    checks.check(np.allclose(g['time'], [0, 0.25, 0.5, 0.75, 1.0]) and
                 list(g['cycle']) == [0, 1, 2, 3, 4], 'glstat: a record at t = 0 and at every '
                 'DT = 0.25 (steps 0-4)', str(list(g['time'])))
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']
    eps = top_strain(out, name, nb)
    ie_exact = 0.5 * E * eps[-1] ** 2
    # the tool's drive: it applies -F (F the block's push on the tool, rcforc's master force,
    # +z) while the tool moves by -DELTA t: its work is int F d(DELTA t)
    force = np.concatenate([[0.0], r['z']])
    delta_tool = DELTA * np.array([0, 0.25, 0.5, 0.75, 1.0])
    work_exact = np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(delta_tool))
    spring = 0.5 * force[-1] * (DELTA - eps[-1])
    ie, work, sliding = g['internal energy'][-1], g['external work'][-1], \
        g['sliding interface energy'][-1]
    ratio = g['total energy / initial energy']
    print('    tool: internal energy %.6e mJ (E eps^2 V/2 = %.6e), external work %.6e (drive, '
          'trapezoid of rcforc %.6e), sliding energy %.6e (F penetration/2 = %.6e); ratio '
          '%.9f .. %.9f' % (ie, ie_exact, work, work_exact, sliding, spring, ratio.min(),
                            ratio.max()))
    # measured 5.3e-4: the finite-strain response at 0.1 % strain (the tool force: 1e-3)
    checks.check(abs(ie / ie_exact - 1) < 2e-3, 'tool: internal energy = E eps^2 V / 2 within '
                 '0.2 %', '%.3e' % (ie / ie_exact - 1))
    checks.check(abs(work / work_exact - 1) < 1e-9, 'tool: external work = the work of the '
                 'tool\'s drive (trapezoid of rcforc) to 1e-9', '%.3e' % (work / work_exact - 1))
    # measured 1.9e-4 (the penetration read from the top's mean displacement)
    checks.check(abs(sliding / spring - 1) < 2e-3, 'tool: sliding interface energy = the '
                 'penalty spring\'s F d / 2 within 0.2 %', '%.3e' % (sliding / spring - 1))
    # measured 2e-8: the work of the Newton residual
    checks.check(np.all(abs(ratio - 1) < 1e-6), 'tool: energy ratio 1 to 1e-6 (equilibrium at '
                 'every step)', '%.3e' % np.max(abs(ratio - 1)))
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        keys = sorted(f['states'])
        first, last = f['states'][keys[0]]['point'], f['states'][keys[-1]]['point']
        sets = sorted(a for a in first if a.startswith('node_set'))
        checks.check(f['states'][keys[0]].attrs['time'] == 0.0 and
                     all(a in first for a in last) and sets == ['node_set_1', 'node_set_2',
                                                                'node_set_3'],
                     'state 0: every array of the later states and the deck\'s 3 node sets',
                     '%s / %s' % (sorted(first), sorted(last)))
    b = read_rbdout(os.path.join(out, 'rbdout'))
    checks.check(list(b.keys()) == [2], 'rbdout: the tool (part 2)', str(list(b.keys())))
    if 2 in b:
        t = b[2]
        ok = (np.allclose(t['z-disp'], -delta_tool, rtol=0, atol=1e-15) and
              np.allclose(t['z-vel'][1:], -DELTA, rtol=1e-12, atol=0) and
              np.allclose(t['x-disp'], 0) and np.allclose(t['x-vel'], 0))
        checks.check(ok, 'rbdout: translation -DELTA t and velocity -DELTA of the tool',
                     '%s %s' % (t['z-disp'], t['z-vel']))
        diff = np.max(abs(t['z-reaction'][1:] + r['z'])) / np.max(abs(r['z']))
        checks.check(diff < 1e-12, 'rbdout: reaction = minus rcforc\'s force on the tool',
                     '%.3e' % diff)
        # the push acts near the tool's centroid (x = y = 0.5, above the block's centre): its
        # moment about it is F times the offset of the centre of pressure, measured 1.5e-4 F L
        # (the contact pressure of the tet mesh is uniform to about that); about a wrong point
        # (e.g. the origin) it would be F L / 2
        moment = np.max(abs(t['xx-reaction'])) + np.max(abs(t['yy-reaction']))
        checks.check(moment < 1e-3 * np.max(abs(r['z'])), 'rbdout: the moment about the tool\'s '
                     'centroid is that of a centred push (below 1e-3 F L)',
                     '%.3e' % (moment / np.max(abs(r['z']))))
if 1 in runs and 2 in runs:
    g1 = read_glstat(os.path.join(runs[1][1], 'glstat'))
    g2 = read_glstat(os.path.join(runs[2][1], 'glstat'))
    diff = max(np.max(abs(g1[k] - g2[k])) / max(np.max(abs(g1[k])), 1e-300)
               for k in ('internal energy', 'external work', 'sliding interface energy'))
    # MUMPS's round-off on 2 ranks (the tool force: 3.6e-11)
    checks.check(diff < 1e-8, 'tool: glstat on 2 ranks = 1 rank (1e-8)', '%.3e' % diff)

# ---- the load ---------------------------------------------------------------------------------
nb, blocks = deck(tool=False)
name = 'implicit_histories_load'
rc, text, out = run_case(name, blocks)
checks.check(rc == 0, 'load: run succeeds', text[-600:])
if rc == 0:
    g = read_glstat(os.path.join(out, 'glstat'))
    eps = -top_strain(out, name, nb)                   # stretched: u_z > 0
    ie, work = g['internal energy'][-1], g['external work'][-1]
    ie_exact = 0.5 * LOAD * eps[-1]                    # F u / 2, A = L = 1
    print('    load: internal energy %.6e mJ, external work %.6e, F u / 2 = %.6e (u = %.6e '
          'mm, F/(E A) = %.6e)' % (ie, work, ie_exact, eps[-1], LOAD / E))
    checks.check(abs(work / ie_exact - 1) < 1e-3 and abs(ie / work - 1) < 1e-6,
                 'load: external work = F u / 2 (1e-3), internal energy = external work (1e-6)',
                 '%.3e %.3e' % (work / ie_exact - 1, ie / work - 1))
    checks.check(np.all(g['sliding interface energy'] == 0), 'load: no sliding interface energy')
    checks.check(not os.path.exists(os.path.join(out, 'rbdout')), 'load: no rbdout without a '
                 'tool')

# ---- state 0 of the linear static analysis (the same load, NSOLVR = 1) ----------------------
nb, blocks = deck(tool=False)
blocks[-1] = [line.replace(f10(12), f10(1)) for line in blocks[-1]]
name = 'implicit_histories_linear'
rc, text, out = run_case(name, blocks)
checks.check(rc == 0 and 'linear static' in text, 'linear: run succeeds', text[-600:])
if rc == 0:
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        keys = sorted(f['states'])
        first, last = f['states'][keys[0]], f['states'][keys[-1]]
        same = all(a in first[kind] and np.all(first[kind][a][()] == 0)
                   for kind in ('point', 'cell') for a in last[kind])
        sets = [a for a in first['point'] if a.startswith('node_set')]
        checks.check(len(keys) == 2 and first.attrs['time'] == 0.0 and same and
                     len(sets) == 4, 'linear: state 0 at t = 0 carries every array of the '
                     'solution\'s state (zero) and the deck\'s 4 node sets',
                     '%s / %s' % (sorted(first['point']), sorted(last['point'])))
checks.exit()
