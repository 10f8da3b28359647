"""Coordinate systems and vectors (issue 23): *DEFINE_COORDINATE_NODES, _SYSTEM, _VECTOR and
*DEFINE_VECTOR where the explicit analysis uses them (keywords.md 3.8; mm, t, s, N, MPa). A free
steel block (2 x 2 x 2 hexahedra, 1 mm) moves rigidly for T = 1e-4 s; its node displacements
against the closed forms:
1. *BOUNDARY_SPC_SET CID (a _NODES system turned by atan(4/3) about z, e1 = (0.6, 0.8, 0);
   local y and z fixed), the block started at (V, 0, 0): it slides along e1 at 0.6 V (the
   velocity's other components removed at t = 0): u = 0.6 V T e1 at every node (1e-12 of |u|);
   on 2 ranks the same bits; the same system given with DIR Y (N1 to N2 the local y axis) and
   DIR Z: the same motion (1e-12);
2. *INITIAL_VELOCITY and *INITIAL_VELOCITY_GENERATION with ICID (a _VECTOR system): the velocity
   components given in the local system: u = V T e1 (1e-12);
3. *BOUNDARY_PRESCRIBED_MOTION_SET DOF 4 along *DEFINE_VECTOR e = (1, 2, 2)/3 (VAD 0, W): with
   the block started at a velocity P normal to e, DOF 4 keeps P: u = (W e + P) T; DOF -4 removes
   it: u = W e T (1e-12); the velocity along e ramped from 0 over T/2 instead: u = 0.75 W T e
   + P T (1e-6: the midpoint rule misses dt^2 |slope jump|/8 = 3e-8 mm at the kink) and glstat's
   energy ratio 1 (1e-6; the axis motion DOF 3 gives 5.3e-7 on the same ramp); along (0, 0, 2)
   DOF 4 gives the bits of DOF 3 (displacements and energy ratios);
4. *LOAD_NODE_SET CID (a _SYSTEM system given by points in another system, CIDL): one
   hexahedron (8 equal nodal masses m), a constant force F on every node along the local x
   axis: u = F T^2/(2 m) e1 (1e-6: the last step's landing on ENDTIM);
5. the nonlinear implicit analysis with an SPC in a turned system (node frames): a bar of 4
   hexahedra along e1 = (0.6, 0.8, 0), its root fixed, its other nodes held to e1 (local y and
   z fixed; local z is global z), pulled by P along global x at the tip: u = 0.6 P x/(M A) e1
   (M the uniaxial-strain modulus) within 1e-5 (the strain, 1.7e-6: geometric nonlinearity),
   the normal components 0 to 1e-18, the same bar along x with global SPCs (turned back) to
   1e-9, 2 ranks to 1e-12; the linear static analysis gives the closed form and the bar along
   x turned to 1e-12; a moving system's SPC is refused, naming it;
6. a moving system (*DEFINE_COORDINATE_NODES FLAG 1 on three nodes of the block): the block
   spins freely about z a quarter turn; an SPC of its local x axis (radial, at start) at a node
   on that axis stays radial as the block turns, so it does no work: the run departs from the
   free spin by 5.7e-5 of the displacements (below 1e-4), and by half that at half the step
   (the condition is consistent: first order in dt), on 1 and 2 ranks alike (the same bits);
   the same SPC in the fixed system (FLAG 0) stops the node's global x velocity, which is its
   whole velocity after the quarter turn: the block's motion departs by 0.54.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, OUT, box_hexes, node_set, curve, run_case, glstat

checks = Checks('coordinate systems')
V, T = 1000.0, 1.0e-4
E1 = np.array([0.6, 0.8, 0.0])          # turned by atan(4/3) about z: exact in the deck
COS = E1[0]


def block(n=2):
    x, conn = box_hexes(1.0, 1.0, 1.0, n, n, n)
    return x, conn


def deck(x, conn, extra, end=T, implicit=False):
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
              node_set(1, range(len(x))), extra]
    blocks.append(['*CONTROL_TERMINATION', f10(end), '*DATABASE_BINARY_D3PLOT', f10(end)])
    if implicit:
        blocks.append(['*CONTROL_IMPLICIT_GENERAL', f10(1, end)])
    return blocks


def final_displacement(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        last = sorted(f['states'])[-1]
        return f['states/%s/point/displacement' % last][()][order]


def run_and_compare(name, blocks, want, tolerance, ranks=1, n_nodes=None):
    """Run; every node of the block (the first n_nodes) against the displacement want."""
    rc, text, out = run_case(name, blocks, ranks=ranks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    u = final_displacement(out, name)[:n_nodes]
    error = np.max(np.abs(u - want)) / np.linalg.norm(want)
    checks.check(error < tolerance, '%s: u = %s mm at every node (relative error %.1e)'
                 % (name, np.array2string(want, precision=6), error), '%s' % u[:2])
    return u


x, conn = block()
# 1. SPC in a local system by nodes: N1 the origin corner, N2 along e1, N3 in the x-y plane; the
# three extra nodes (not in any element) carry the system only
corner = len(x)
xs = np.vstack([x, [[5.0, 5.0, 0.0], [5.0 + E1[0], 5.0 + E1[1], 0.0],
                    [5.0 - E1[1], 5.0 + E1[0], 0.0]]])
spc = ['*DEFINE_COORDINATE_NODES', f10(7, corner + 1, corner + 2, corner + 3),
       '*BOUNDARY_SPC_SET', f10(1, 7, 0, 1, 1),
       '*INITIAL_VELOCITY', f10(1), f10(V, 0.0, 0.0)]
want = V * COS * T * E1
u1 = run_and_compare('cs_spc', deck(xs, conn, spc), want, 1e-12, n_nodes=len(x))
u2 = run_and_compare('cs_spc_2ranks', deck(xs, conn, spc), want, 1e-12, ranks=2, n_nodes=len(x))
if u1 is not None and u2 is not None:
    checks.check(np.array_equal(u1, u2), 'cs_spc: 1 and 2 ranks give the same bits')

# the same system by nodes with DIR Y (N1 to N2 the local y axis, e2; N3 in the y-z plane,
# along z) and DIR Z (N1 to N2 the local z axis; N3 in the z-x plane, along e1)
E2 = np.array([-E1[1], E1[0], 0.0])
for label, second, third in (('Y', E2, [0.0, 0.0, 1.0]), ('Z', [0.0, 0.0, 1.0], E1)):
    xd = np.vstack([x, [[5.0, 5.0, 0.0], [5.0, 5.0, 0.0] + np.asarray(second),
                        [5.0, 5.0, 0.0] + np.asarray(third)]])
    cards = ['*DEFINE_COORDINATE_NODES', '%10d%10d%10d%10d%10d%10s' % (
        7, corner + 1, corner + 2, corner + 3, 0, label)] + spc[2:]
    run_and_compare('cs_spc_dir' + label, deck(xd, conn, cards), want, 1e-12, n_nodes=len(x))

# 2. initial velocities in a local system (_VECTOR: x axis e1, (0, 0, 1) in its x-z... the
# second vector lies in the x-y plane)
vector_system = ['*DEFINE_COORDINATE_VECTOR', f10(3, E1[0], E1[1], 0.0, -E1[1], E1[0], 0.0)]
run_and_compare('cs_iv_icid', deck(x, conn, vector_system + [
    '*INITIAL_VELOCITY', f10(1, 0, 0, 0, 3), f10(V, 0.0, 0.0)]), V * T * E1, 1e-12)
run_and_compare('cs_ivg_icid', deck(x, conn, vector_system + [
    '*INITIAL_VELOCITY_GENERATION', f10(1, 2, 0.0, V, 0.0, 0.0, 0, 3),
    f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)]), V * T * E1, 1e-12)

# 3. motion along a vector, DOF 4 and -4, the block started at P normal to e
e = np.array([1.0, 2.0, 2.0]) / 3.0
p = 100.0 * np.array([2.0, -1.0, 0.0])
W = 800.0
for dof, keeps in ((4, True), (-4, False)):
    motion = ['*DEFINE_VECTOR', f10(5, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0),
              '*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, dof, 0, 9, W, 5),
              '*INITIAL_VELOCITY', f10(1), f10(*p)] + curve(9, [(0.0, 1.0), (1.0, 1.0)])
    want = (W * e + (p if keeps else 0.0)) * T
    run_and_compare('cs_motion_dof%d' % dof, deck(x, conn, motion), want, 1e-12)
# the velocity along e ramped from 0 to W over T/2 (no jump): u = 0.75 W T e + P T, and the
# reaction's work balances the kinetic energy
motion = ['*DEFINE_VECTOR', f10(5, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0),
          '*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, 4, 0, 9, W, 5),
          '*INITIAL_VELOCITY', f10(1), f10(*p), '*DATABASE_GLSTAT', f10(T / 10)] + \
    curve(9, [(0.0, 0.0), (T / 2, 1.0), (1.0, 1.0)])
if run_and_compare('cs_motion_ramp', deck(x, conn, motion), (0.75 * W * e + p) * T,
                   1e-6) is not None:
    ratio = glstat(os.path.join(OUT, 'cs_motion_ramp'))['total energy / initial energy'][-1]
    checks.check(abs(ratio - 1.0) < 1e-6, 'cs_motion_ramp: the work of the reaction along e '
                 'balances the kinetic energy: energy ratio %.9f (1e-6)' % ratio)
# along a vector that is the z axis: the same bits as DOF 3 (displacements, glstat)
found = {}
for label, cards in (('dof3', ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, 3, 0, 9, W)]),
                     ('vid_z', ['*DEFINE_VECTOR', f10(5, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0),
                                '*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, 4, 0, 9, W, 5)])):
    name = 'cs_motion_%s' % label
    rc, text, out = run_case(name, deck(x, conn, cards + motion[4:]))
    if rc == 0:
        found[label] = (final_displacement(out, name),
                        glstat(out)['total energy / initial energy'])
checks.check(len(found) == 2 and np.array_equal(found['dof3'][0], found['vid_z'][0]) and
             np.array_equal(found['dof3'][1], found['vid_z'][1]), 'DOF 4 along (0, 0, 2) gives '
             'the bits of DOF 3: displacements and glstat energy ratios')

# 4. nodal forces along the local x axis of a system given by points in another (CIDL)
x1, conn1 = block(1)
mass = DENSITY * 1.0 / 8.0
F = 2.0e-3
base = ['*DEFINE_COORDINATE_SYSTEM', f10(11, 1.0, 2.0, 3.0, 1.0, 3.0, 3.0), f10(0.0, 2.0, 4.0)]
# system 11: origin (1, 2, 3), x along global y, x-y plane through (0, 2, 4) - O = (-1, 0, 1):
# axes x = (0, 1, 0), z = x cross (-1, 0, 1) = (1, 0, 1)/sqrt2, y = z cross x = (-1, 0, 1)/sqrt2
# system 12 in 11: x along 11's (0.6, 0.8, 0)
local = ['*DEFINE_COORDINATE_SYSTEM', f10(12, 0.0, 0.0, 0.0, E1[0], E1[1], 0.0, 11),
         f10(-E1[1], E1[0], 0.0)]
axes11 = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 1.0] / np.sqrt(2.0), [1.0, 0.0, 1.0] / np.sqrt(2.0)]).T
e12 = axes11 @ E1
load = ['*LOAD_NODE_SET', f10(1, 1, 9, F, 12)] + curve(9, [(0.0, 1.0), (1.0, 1.0)])
run_and_compare('cs_load_cid', deck(x1, conn1, base + local + load), F * T ** 2 / (2 * mass) * e12,
                1e-6)

# 5. the implicit analysis with an SPC in a turned system: a bar along e1 held to it
xb, cb = box_hexes(4.0, 1.0, 1.0, 4, 1, 1)
turn = np.array([[E1[0], -E1[1], 0.0], [E1[1], E1[0], 0.0], [0.0, 0.0, 1.0]])
nb = len(xb)
system = np.array([[10.0, 10.0, 0.0], [10.0 + E1[0], 10.0 + E1[1], 0.0],
                   [10.0 - E1[1], 10.0 + E1[0], 0.0]])
P_BAR, NU = 1.0, 0.3
root, rest = np.nonzero(xb[:, 0] < 1e-9)[0], np.nonzero(xb[:, 0] > 1e-9)[0]
tip = np.nonzero(xb[:, 0] > 4.0 - 1e-9)[0]
unit = curve(9, [(0.0, 1.0), (1.0, 1.0)])


def bar(turned, moving=False, linear=False):
    # root fixed; the other nodes held to the bar's axis; the tip pulled along global x
    held = f10(3, 7, 0, 1, 1) if turned else f10(3, 0, 0, 1, 1)
    force = P_BAR if turned else E1[0] * P_BAR              # (along the axis when not turned)
    cards = node_set(2, root) + ['*BOUNDARY_SPC_SET', f10(2, 0, 1, 1, 1)] + node_set(3, rest) \
        + ['*BOUNDARY_SPC_SET', held] + node_set(4, tip) \
        + ['*LOAD_NODE_SET', f10(4, 1, 9, force / len(tip))] + unit
    if linear:                              # NSOLVR 1: the linear static analysis
        cards = cards + ['*CONTROL_IMPLICIT_SOLUTION', f10(1)]
    if turned:
        cards = ['*DEFINE_COORDINATE_NODES', f10(7, nb + 1, nb + 2, nb + 3, int(moving))] + cards
        return deck(np.vstack([xb @ turn.T, system]), cb, cards, end=1.0, implicit=True)
    return deck(xb, cb, cards, end=1.0, implicit=True)


found = {}
for name, blocks, ranks in (('cs_skew_implicit', bar(True), 1),
                            ('cs_skew_implicit_2ranks', bar(True), 2),
                            ('cs_skew_implicit_along_x', bar(False), 1),
                            ('cs_skew_linear', bar(True, linear=True), 1),
                            ('cs_skew_linear_along_x', bar(False, linear=True), 1)):
    rc, text, out = run_case(name, blocks, ranks=ranks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc == 0:
        found[name] = final_displacement(out, name)[:nb]
if len(found) == 5:
    u = found['cs_skew_implicit']
    modulus = YOUNG * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    want = np.outer(E1[0] * P_BAR * xb[:, 0] / modulus, E1)
    error = np.max(np.abs(u - want)) / np.max(np.abs(want))
    normal = max(np.max(np.abs(u @ np.array([-E1[1], E1[0], 0.0]))), np.max(np.abs(u[:, 2])))
    turned_back = np.max(np.abs(u - found['cs_skew_implicit_along_x'] @ turn.T)) / np.max(np.abs(u))
    ranks = np.max(np.abs(u - found['cs_skew_implicit_2ranks'])) / np.max(np.abs(u))
    print('    implicit, SPC in a turned system: u against 0.6 P x/(M A) e1 %.1e, normal components '
          '%.1e mm, against the bar along x %.1e, 2 ranks %.1e' % (error, normal, turned_back,
                                                                  ranks))
    checks.check(error < 1e-5 and normal < 1e-18, 'implicit: the bar held to e1 stretches by '
                 '0.6 P x/(M A) along it (1e-5) and not across (1e-18)', '%.2e %.2e'
                 % (error, normal))
    checks.check(turned_back < 1e-9, 'implicit: the turned bar is the bar along x turned (1e-9)',
                 '%.2e' % turned_back)
    checks.check(ranks < 1e-12, 'implicit: 2 ranks give 1 rank\'s displacements (1e-12)',
                 '%.2e' % ranks)
    lin = found['cs_skew_linear']
    lin_error = np.max(np.abs(lin - want)) / np.max(np.abs(want))
    lin_back = np.max(np.abs(lin - found['cs_skew_linear_along_x'] @ turn.T)) / np.max(np.abs(lin))
    print('    linear static, the same bar: against 0.6 P x/(M A) e1 %.1e, against the bar along x '
          '%.1e' % (lin_error, lin_back))
    checks.check(lin_error < 1e-12 and lin_back < 1e-12, 'linear static: the bar held to e1 '
                 'stretches by 0.6 P x/(M A) along it, and is the bar along x turned (1e-12)',
                 '%.2e %.2e' % (lin_error, lin_back))
# the same bar driven at its tip along e1 (DOF 4 / -4 along a vector, VAD 2) by DELTA: u =
# DELTA x/L e1, the bar along x driven by DOF 1 turned, and the reaction's work balances the
# strain energy (glstat)
DELTA, LENGTH = 1.0e-4, 4.0
inner = np.nonzero((xb[:, 0] > 1e-9) & (xb[:, 0] < LENGTH - 1e-9))[0]
drive = curve(8, [(0.0, 0.0), (1.0, 1.0)])


def driven(dof):
    sets = node_set(2, root) + ['*BOUNDARY_SPC_SET', f10(2, 0, 1, 1, 1)] + node_set(4, tip)
    if dof == 1:                                            # along x: the reference
        return deck(xb, cb, sets + node_set(3, inner) + ['*BOUNDARY_SPC_SET', f10(3, 0, 0, 1, 1),
                    '*BOUNDARY_SPC_SET', f10(4, 0, 0, 1, 1), '*BOUNDARY_PRESCRIBED_MOTION_SET',
                    f10(4, 1, 2, 8, DELTA)] + drive + ['*DATABASE_GLSTAT', f10(0.25)],
                    end=1.0, implicit=True)
    held = node_set(3, inner if dof == -4 else np.concatenate([inner, tip]))
    cards = ['*DEFINE_COORDINATE_NODES', f10(7, nb + 1, nb + 2, nb + 3),
             '*DEFINE_VECTOR', f10(5, 0.0, 0.0, 0.0, E1[0], E1[1], 0.0)] + sets + held + \
        ['*BOUNDARY_SPC_SET', f10(3, 7, 0, 1, 1), '*BOUNDARY_PRESCRIBED_MOTION_SET',
         f10(4, dof, 2, 8, DELTA, 5)] + drive + ['*DATABASE_GLSTAT', f10(0.25)]
    return deck(np.vstack([xb @ turn.T, system]), cb, cards, end=1.0, implicit=True)


runs = {}
for dof in (1, 4, -4):
    name = 'cs_vector_implicit_%s' % ('x' if dof == 1 else 'dof%d' % dof)
    blocks = driven(dof)
    blocks[-1] = ['*CONTROL_IMPLICIT_GENERAL', f10(1, 0.25)]          # 4 steps
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc == 0:
        runs[dof] = (final_displacement(out, name)[:nb], glstat(out))
if len(runs) == 3:
    want = np.outer(DELTA * xb[:, 0] / LENGTH, E1)
    for dof in (4, -4):
        u, g = runs[dof]
        closed = np.max(np.abs(u - want)) / DELTA
        turned_back = np.max(np.abs(u - runs[1][0] @ turn.T)) / DELTA
        ratio = g['total energy / initial energy'][-1] if 'total energy / initial energy' in g \
            else float('nan')
        print('    implicit, DOF %d along e1: u against DELTA x/L e1 %.1e, against the bar along x '
              'driven by DOF 1 %.1e, energy ratio %.6f' % (dof, closed, turned_back, ratio))
        checks.check(closed < 1e-6 and turned_back < 1e-9, 'implicit, DOF %d along a vector: '
                     'the bar stretched along e1 as the closed form (1e-6) and as the bar along x '
                     'turned (1e-9)' % dof, '%.2e %.2e' % (closed, turned_back))
        checks.check(abs(ratio - 1) < 1e-3, 'implicit, DOF %d: the reaction\'s work balances '
                     'the strain energy (glstat ratio within 1e-3)' % dof, '%.6f' % ratio)
rc, text, out = run_case('cs_skew_implicit_moving', bar(True, moving=True))
checks.check(rc != 0 and 'implicit analysis takes SPCs in fixed systems only' in text and
             'CID 7' in text, 'implicit: an SPC in a moving system is refused, naming CID and '
             'line', text[-400:])

# 6. a moving system: N1 N2 N3 on the block (its centre of the base, along x, along y)
xm = x - [0.5, 0.5, 0.0]
find = lambda p: int(np.nonzero(np.all(abs(xm - p) < 1e-9, axis=1))[0][0]) + 1  # noqa: E731
omega = 0.5 * np.pi / T                       # a quarter turn
n1, n2, n3, held = find([0, 0, 0]), find([0.5, 0, 0]), find([0, 0.5, 0]), find([0.5, 0, 1])
spin = ['*INITIAL_VELOCITY_GENERATION', f10(1, 2, omega, 0.0, 0.0, 0.0),
        f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)]
runs = {}
for label, flag, ranks in (('free', None, 1), ('moving', 1, 1), ('moving_2ranks', 1, 2),
                           ('fixed', 0, 1), ('free_half', None, 1), ('moving_half', 1, 1)):
    cards = list(spin)
    if label.endswith('_half'):
        cards += ['*CONTROL_TIMESTEP', f10(0.0, 0.45)]
    if flag is not None:
        cards += ['*DEFINE_COORDINATE_NODES', f10(8, n1, n2, n3, flag),
                  '*BOUNDARY_SPC_NODE', f10(held, 8, 1, 0, 0)]
    name = 'cs_moving_' + label
    rc, text, out = run_case(name, deck(xm, conn, cards), ranks=ranks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc == 0:
        runs[label] = final_displacement(out, name)
if len(runs) == 6:
    scale = np.max(np.abs(runs['free']))
    moving = np.max(np.abs(runs['moving'] - runs['free'])) / scale
    half = np.max(np.abs(runs['moving_half'] - runs['free_half'])) / scale
    fixed = np.max(np.abs(runs['fixed'] - runs['free'])) / scale
    turned = np.degrees(np.arctan2(xm[n2 - 1, 1] + runs['free'][n2 - 1, 1],
                                   xm[n2 - 1, 0] + runs['free'][n2 - 1, 0]))
    print('    moving system: the free block turned %.2f deg; the SPC in the moving system departs '
          'from it by %.2e (%.2e at half the step), in the fixed one by %.2f (of the largest '
          'displacement, %.3f mm)' % (turned, moving, half, fixed, scale))
    checks.check(abs(turned - 90.0) < 0.5, 'moving system: the free block turns a quarter turn')
    checks.check(moving < 1e-4 and moving / half > 1.8, 'moving system (FLAG 1): the radial '
                 'SPC turns with the block: the free spin within 1e-4, the departure halved with '
                 'the step (consistent)', '%.2e %.2e' % (moving, half))
    checks.check(np.array_equal(runs['moving'], runs['moving_2ranks']), 'moving system: 1 and 2 '
                 'ranks give the same bits')
    checks.check(fixed > 0.1, 'fixed system (FLAG 0): the same SPC holds the node\'s global x '
                 'velocity, and the motion departs (by more than 0.1)', '%.3f' % fixed)
checks.exit()
