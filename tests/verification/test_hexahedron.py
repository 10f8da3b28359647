"""The one-point hexahedron (solid ELFORM 1) with hourglass control in the explicit analysis
(doc/theory.md 2.8, doc/verification.md "One-point hexahedron").

1. Patch test: a block of distorted hexahedra, every node driven by one affine motion v = L X
   (a general velocity gradient): every element has the exact F = I + t L, so its stress is
   the elastic law's at that F, the same in all elements, and the hourglass forces of both
   forms are zero (the hourglass vectors are orthogonal to the linear fields).
   Tetrahedra given as degenerate hexahedra in an ELFORM 1 part give ELFORM 10's results.
2. Rigid rotation: a free block spinning a quarter turn about z. An objective element keeps
   only the centripetal stress (rho omega^2 R^2); the hourglass energy stays at round-off.
3. Hourglass modes: a block of 12 x 12 x 6 hexahedra loaded on the middle 2 x 2 mm of its top
   face (4 x 4 elements). With the default control (IHQ 1, QM 0.1) under a fast load and with
   the physical stiffness (IHQ 6, QM 1) under a fast and a slow load the hourglass energy stays
   below 10 % of the internal energy; with (almost) no control (QM 1e-6) the hourglass mode
   takes over: the hourglass displacements are many times those with control.
4. Bending: a slender cantilever (10 x 1 x 1 mm, 20 x 2 x 2 hexahedra) under a tip shear
   force, loaded slowly: with IHQ 6, QM 1 its tip deflection is that of Timoshenko's beam
   theory; ELFORM 2 (computed as ELFORM 1 with IHQ 6, QM 1) gives the same. The linear static
   and the nonlinear implicit analyses give the explicit run's deflection (a viscous IHQ 1 is
   computed as IHQ 6 there).
5. Copper Taylor bar in hexahedra (tests/bench/taylor_copper.py's coarse mesh, 80 us):
   final length and footprint radius against the published ranges, energy balance, hourglass
   energy below 10 % of the internal energy.
6. The loaded block on 1 and 3 ranks: the same bits.
7. Step of free and thin structures: a free block under equal forces at every node (2 ms).
   One element thick (1 x 1 x 1, 1 x 1 x 4, 1 x 4 x 4 elements: no node inside the body) the
   step is the element bound's, 0.9 x 2/omega of the dilatation mode omega^2 = 12 K/(rho L^2),
   and the run stays stable (energy ratio 1 to 1e-6); at LS-DYNA's L/c rule these blocks
   invert within 40-400 cycles (measured). Two elements thick (2 x 4 x 4) every element has
   an interior node and the rule's 0.9 L/c holds, stable as well.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, ROOT, f10, free, nodes_card, elements_card
from explicit_cases import OUT, box_tets, box_hexes, elastic, node_set, history_nodes, curve, \
    run_case, glstat, nodout, smooth_ramp, wave_speeds, YOUNG, POISSON, DENSITY

sys.path.insert(0, os.path.join(ROOT, 'tests', 'bench'))
import taylor_copper as tc  # noqa: E402

checks = Checks('hexahedron')

HOURGLASS_BASE = np.array([[-1, 1, 1, -1, -1, 1, 1, -1], [-1, -1, 1, 1, -1, -1, 1, 1],
                           [-1, -1, -1, -1, 1, 1, 1, 1]]).T        # xi eta zeta per node


def hourglass_amplitude(x0, conn, u):
    """Largest hourglass displacement |sum_I h_aI u_I| / 8 over the elements and modes,
    h_a = xi eta, eta zeta, zeta xi, xi eta zeta (the box's elements are parallelepipeds,
    for which these are the hourglass shape vectors)."""
    xi = HOURGLASS_BASE
    h = np.stack([xi[:, 0] * xi[:, 1], xi[:, 1] * xi[:, 2], xi[:, 2] * xi[:, 0],
                  xi[:, 0] * xi[:, 1] * xi[:, 2]])
    q = np.einsum('ai,eic->eac', h, u[conn]) / 8.0
    return float(np.abs(q).max())


def hourglass_cards(ihq, qm):
    return ['*HOURGLASS', f10(1, ihq, qm)]


def hex_part(elform, material, hgid=0):
    return ['*PART', 'body', f10(1, 1, 1, 0, hgid), '*SECTION_SOLID', f10(1, elform)] + material


def last_state(out, with_time=False):
    """Point and cell fields of the last state (and its time)."""
    import h5py
    path = [os.path.join(out, f) for f in os.listdir(out) if f.endswith('.h5')][0]
    with h5py.File(path, 'r') as h:
        last = h['states'][sorted(h['states'].keys())[-1]]
        fields = {k: np.array(last['point'][k]) for k in last['point']}, \
            {k: np.array(last['cell'][k]) for k in last['cell']}
        time = float(h['time_history/time'][-1])
    return fields + (time,) if with_time else fields


# ---- 1. patch test: affine motion of distorted hexahedra --------------------------------------
xp, cp = box_hexes(2.0, 2.0, 2.0, 3, 3, 3, distortion=0.2)
xp = xp + 1.0                           # in [1, 3]^3: no velocity component is zero (SF 0 = 1)
xp = np.array([[float('%16.9e' % v) for v in p] for p in xp])    # as *NODE writes them
L_RATE = np.array([[-120.0, 30.0, 20.0], [10.0, -60.0, 40.0], [25.0, 15.0, 70.0]])   # 1/s
T_PATCH = 1.0e-5


def pentahedra(x, conn):
    """Each hexahedron cut into two prisms, written as LS-DYNA's degenerate hexahedra
    N1 N2 N3 N4 N5 N5 N6 N6 (triangles N1 N2 N5 and N4 N3 N6), oriented positively."""
    out = []
    for v in conn:
        for a, b in (((v[0], v[1], v[2]), (v[4], v[5], v[6])),
                     ((v[0], v[2], v[3]), (v[4], v[6], v[7]))):
            c = [a[0], a[1], b[1], b[0], a[2], a[2], b[2], b[2]]
            # positive: (x2 - x1) x (x4 - x1) . (x5 - x1) > 0, else mirrored
            if np.dot(np.cross(x[c[1]] - x[c[0]], x[c[3]] - x[c[0]]), x[c[4]] - x[c[0]]) < 0:
                c = [a[1], a[0], b[0], b[1], a[2], a[2], b[2], b[2]]
            out.append(c)
    return np.array(out)


def affine_patch(ihq, qm, conn=cp, label='hexahedra'):
    blocks = [nodes_card(xp), elements_card('ELEMENT_SOLID', conn),
              hex_part(1, elastic(poisson=0.3), hgid=1), hourglass_cards(ihq, qm)]
    v = xp @ L_RATE.T
    for k in range(len(xp)):
        blocks.append(node_set(10 + k, [k]))
        for d in range(3):
            blocks.append(['*BOUNDARY_PRESCRIBED_MOTION_SET', free(10 + k, d + 1, 0, 1, v[k, d])])
    blocks += [curve(1, [(0.0, 1.0), (1.0, 1.0)]),
               ['*CONTROL_TERMINATION', f10(T_PATCH), '*DATABASE_BINARY_D3PLOT', f10(T_PATCH),
                '*DATABASE_GLSTAT', f10(T_PATCH / 10)]]
    rc, text, out = run_case('hex_patch_%s_ihq%d' % (label, ihq), blocks)
    checks.check(rc == 0, 'patch test IHQ %d, %s: run succeeds' % (ihq, label), text[-600:])
    if rc != 0:
        return
    point, cell, t = last_state(out, with_time=True)
    u_exact = t * xp @ L_RATE.T
    err_u = np.abs(point['displacement'] - u_exact).max() / np.abs(u_exact).max()
    # mefem's *MAT_ELASTIC: compressible neo-Hookean, sigma = (mu (b - 1) + lambda ln J 1)/J
    lam = YOUNG * 0.3 / (1.3 * 0.4)
    mu = YOUNG / 2.6
    f = np.eye(3) + t * L_RATE
    j = np.linalg.det(f)
    sigma = (mu * (f @ f.T - np.eye(3)) + lam * np.log(j) * np.eye(3)) / j
    exact = np.array([sigma[0, 0], sigma[1, 1], sigma[2, 2], sigma[0, 1], sigma[1, 2],
                      sigma[2, 0]])
    stress = cell['stress']
    err_s = np.abs(stress - exact[None, :]).max() / np.abs(exact).max()
    g = glstat(out)
    hg = np.abs(g['hourglass energy']).max() / g['internal energy'][-1]
    print('    patch IHQ %d, %s: |u - u_exact| %.1e, |stress - exact| %.1e (|sigma| %.4g MPa), '
          'hourglass / internal energy %.1e' % (ihq, label, err_u, err_s, np.abs(exact).max(),
                                                hg))
    checks.check(err_u < 1e-12, 'patch test IHQ %d, %s: the nodes follow the motion'
                 % (ihq, label), '%.2e' % err_u)
    checks.check(err_s < 1e-9, 'patch test IHQ %d, %s: every distorted element has the exact '
                 'stress' % (ihq, label), '%.2e' % err_s)
    checks.check(hg < 1e-12, 'patch test IHQ %d, %s: no hourglass energy in a linear field'
                 % (ihq, label), '%.2e' % hg)


affine_patch(1, 0.1)
affine_patch(6, 1.0)
# pentahedra (degenerate hexahedra, their repeated corners merged: doc/theory.md 2.8) pass
# the same patch test: their merged hourglass vectors are orthogonal to the linear fields too
affine_patch(6, 1.0, pentahedra(xp, cp), 'pentahedra')

# ---- 1b. tetrahedra in an ELFORM 1 part --------------------------------------------------------
# tetrahedra given as degenerate hexahedra (N1 N2 N3 N4 N4 N4 N4 N4) in an ELFORM 1 part are
# the linear tetrahedra of ELFORM 10: the same run to round-off
xt, ct = box_tets(2.0, 2.0, 1.0, 3, 3, 2)
corner = int(np.argmax(xt.sum(axis=1)))


def tet_block(elform):
    blocks = [nodes_card(xt), elements_card('ELEMENT_SOLID', ct), hex_part(elform, elastic()),
              node_set(1, np.nonzero(xt[:, 2] < 1e-9)[0]),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1, 1, 1, 1)],
              ['*LOAD_NODE_POINT', f10(corner + 1, 3, 1, -50.0)],
              curve(1, [(0.0, 0.0), (1.0e-5, 1.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(4.0e-6), '*DATABASE_BINARY_D3PLOT', f10(4.0e-6)]]
    rc, text, out = run_case('hex_part_tets_e%d' % elform, blocks)
    checks.check(rc == 0, 'tetrahedra in an ELFORM %d part: run succeeds' % elform, text[-600:])
    return last_state(out)[0]['displacement'] if rc == 0 else None


u10, u1 = tet_block(10), tet_block(1)
if u10 is not None and u1 is not None:
    diff = np.abs(u1 - u10).max() / np.abs(u10).max()
    print('    tetrahedra in an ELFORM 1 part against ELFORM 10: |u1 - u10| / |u| = %.1e' % diff)
    checks.check(diff < 1e-9, 'tetrahedra in an ELFORM 1 part are ELFORM 10\'s linear '
                 'tetrahedra', '%.2e' % diff)

# ---- 2. rigid rotation --------------------------------------------------------------------------
xr, cr = box_hexes(2.0, 2.0, 1.0, 4, 4, 2, distortion=0.15)
xr = xr - [1.0, 1.0, 0.5]
OMEGA = 2.0e4                           # rad/s about z
T_ROT = 0.5 * np.pi / OMEGA             # a quarter turn
blocks = [nodes_card(xr), elements_card('ELEMENT_SOLID', cr),
          hex_part(1, elastic(), hgid=1), hourglass_cards(6, 1.0),
          ['*INITIAL_VELOCITY_GENERATION', f10(1, 2, OMEGA, 0.0, 0.0, 0.0, 0, 0),
           f10(0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0, 0)],
          ['*CONTROL_TERMINATION', f10(T_ROT), '*DATABASE_BINARY_D3PLOT', f10(T_ROT),
           '*DATABASE_GLSTAT', f10(T_ROT / 20)]]
rc, text, out = run_case('hex_rotation', blocks)
checks.check(rc == 0, 'rigid rotation: run succeeds', text[-600:])
if rc == 0:
    point, cell = last_state(out)
    g = glstat(out)
    centripetal = DENSITY * OMEGA ** 2 * 2.0          # rho omega^2 R^2, R^2 = 2 mm^2 (corner)
    vm = np.abs(cell['von_mises']).max()
    angle = np.degrees(np.arctan2(*(xr[0] + point['displacement'][0])[[1, 0]]) -
                       np.arctan2(*xr[0][[1, 0]]))
    hg = np.abs(g['hourglass energy']).max() / g['kinetic energy'][0]
    ie = g['internal energy'][-1] / g['kinetic energy'][0]
    print('    rotation %.1f deg: largest von Mises %.3g MPa (rho omega^2 R^2 = %.3g MPa), '
          'internal / kinetic %.1e, hourglass / kinetic %.1e' % (angle, vm, centripetal, ie, hg))
    # a non-objective element would show the rotation as strain: stress of order E (2e5 MPa)
    checks.check(vm < 10.0 * centripetal, 'rigid rotation: only the centripetal stress '
                 '(von Mises < 10 rho omega^2 R^2)', '%.3g MPa' % vm)
    # (the centripetal stretch is not linear in the radius: a little hourglass energy is
    # physical, of the order of the internal energy; a non-objective hourglass form would
    # turn the rotation into hourglass displacements of the order of the element size)
    checks.check(hg < 1e-4 and ie < 1e-4, 'rigid rotation: hourglass and internal energy at '
                 'the centripetal level (< 1e-4 of kinetic)', '%.2e %.2e' % (hg, ie))

# ---- 3. hourglass modes under a concentrated load --------------------------------------------
xc, cc = box_hexes(6.0, 6.0, 3.0, 12, 12, 6)
base = np.nonzero(xc[:, 2] < 1e-9)[0]
PATCH = 2.0                              # mm: the load on the middle 2 x 2 mm of the top face
patch = np.nonzero((abs(xc[:, 2] - 3) < 1e-9) & (abs(xc[:, 0] - 3) <= PATCH / 2 + 1e-9) &
                   (abs(xc[:, 1] - 3) <= PATCH / 2 + 1e-9))[0]
top_centre = int(patch[np.argmin(np.hypot(xc[patch, 0] - 3, xc[patch, 1] - 3))])
patch_weights = np.array([0.5 ** ((abs(abs(xc[n, 0] - 3) - PATCH / 2) < 1e-9) +
                                  (abs(abs(xc[n, 1] - 3) - PATCH / 2) < 1e-9)) for n in patch])
FORCE = 200.0                            # N, shared by the patch's nodes as a uniform pressure
patch_weights *= FORCE / patch_weights.sum()
TRANSIT = 6.0 / wave_speeds()[2]         # a shear wave across the block's width


def concentrated(ihq, qm, transits, ranks=1, tag=''):
    """The load ramped smoothly over half the run (transits shear-wave transits), then held."""
    t_end = transits * TRANSIT
    blocks = [nodes_card(xc), elements_card('ELEMENT_SOLID', cc),
              hex_part(1, elastic(), hgid=1), hourglass_cards(ihq, qm), node_set(1, base),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1, 1, 1, 1)],
              ['*LOAD_NODE_POINT'] + [free(n + 1, 3, 1, -w) for n, w in zip(patch, patch_weights)],
              curve(1, smooth_ramp(t_end / 2, 1.0) + [(2.0 * t_end, 1.0)]),
              ['*CONTROL_TERMINATION', f10(t_end), '*DATABASE_BINARY_D3PLOT', f10(t_end),
               '*DATABASE_GLSTAT', f10(t_end / 50), '*DATABASE_NODOUT', f10(t_end / 50)],
              history_nodes([top_centre])]
    name = 'hex_patch_load_ihq%d_qm%g_t%g%s' % (ihq, qm, transits, tag)
    rc, text, out = run_case(name, blocks, ranks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    return out if rc == 0 else None


# (IHQ, QM, transits of the load): the default viscous control under a fast load, the
# physical stiffness under a fast and a slow (quasi-static) one, no control (QM 1e-6)
amplitude = {}
for ihq, qm, transits in ((1, 0.1, 2.0), (6, 1.0, 2.0), (6, 1.0, 20.0), (4, 1e-6, 2.0)):
    out = concentrated(ihq, qm, transits)
    if out is None:
        continue
    point, cell = last_state(out)
    g = glstat(out)
    amplitude[ihq, qm, transits] = hourglass_amplitude(xc, cc, point['displacement'])
    ratio = g['hourglass energy'][-1] / g['internal energy'][-1]
    print('    load on 2 x 2 mm, IHQ %d QM %g, %g transits: hourglass / internal energy %.3f, '
          'top displacement %.4g mm, largest hourglass displacement %.3g mm'
          % (ihq, qm, transits, ratio, point['displacement'][top_centre, 2],
             amplitude[ihq, qm, transits]))
    if ihq == 1:
        # the step: LS-DYNA's rule for solids, TSSFAC L/c with L = V / largest face area (the
        # 0.5 mm edge of these cubes) and c the elastic wave speed
        expected = 0.9 * 0.5 / wave_speeds()[1]
        print('    first step %.8e s, TSSFAC L/c = %.8e s' % (g['time step'][0], expected))
        checks.check(abs(g['time step'][0] / expected - 1) < 1e-7, 'the hexahedra\'s step is '
                     'LS-DYNA\'s TSSFAC V/(A_max c)', '%.8e' % g['time step'][0])
    if qm >= 0.1:
        checks.check(ratio < 0.10, 'load on 2 x 2 mm, IHQ %d QM %g, %g transits: hourglass '
                     'energy < 10 %% of internal' % (ihq, qm, transits), '%.3f' % ratio)
if len(amplitude) == 4:
    mode = amplitude[4, 1e-6, 2.0] / max(amplitude[1, 0.1, 2.0], amplitude[6, 1.0, 2.0])
    print('    hourglass displacement without control / with: %.1f' % mode)
    checks.check(mode > 5.0, 'load on 2 x 2 mm: without control the hourglass mode grows '
                 '(> 5 x the controlled amplitude)', '%.2f' % mode)

# ---- 4. cantilever bending ---------------------------------------------------------------------
LB, HB, NXB = 10.0, 1.0, 20
xb, cb = box_hexes(LB, HB, HB, NXB, 2, 2)
clamped = np.nonzero(xb[:, 0] < 1e-9)[0]
tip = np.nonzero(abs(xb[:, 0] - LB) < 1e-9)[0]
P_TIP = 2.0                               # N in all, shared by the tip nodes
inertia = HB ** 4 / 12.0
shear_modulus = YOUNG / (2 * (1 + POISSON))
exact_tip = P_TIP * LB ** 3 / (3 * YOUNG * inertia) + P_TIP * LB / (5.0 / 6.0 * shear_modulus * HB ** 2)
f1 = 1.875 ** 2 / (2 * np.pi) * np.sqrt(YOUNG * inertia / (DENSITY * HB ** 2 * LB ** 4))
T_BEND = 6.0 / f1                        # six periods of the first bending mode
# tip nodes: corner nodes carry a quarter, edge nodes half the share of a middle node
weights = np.ones(len(tip))
for k, n in enumerate(tip):
    on_edge = (abs(xb[n, 1]) < 1e-9 or abs(xb[n, 1] - HB) < 1e-9) + \
              (abs(xb[n, 2]) < 1e-9 or abs(xb[n, 2] - HB) < 1e-9)
    weights[k] = 0.5 ** on_edge
weights *= P_TIP / weights.sum()


def cantilever(elform, ihq, qm):
    blocks = [nodes_card(xb), elements_card('ELEMENT_SOLID', cb),
              hex_part(elform, elastic(), hgid=1), hourglass_cards(ihq, qm),
              node_set(1, clamped), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1, 1, 1, 1)],
              curve(1, smooth_ramp(T_BEND / 2, 1.0) + [(2.0 * T_BEND, 1.0)]),
              ['*CONTROL_TERMINATION', f10(T_BEND), '*DATABASE_BINARY_D3PLOT', f10(T_BEND),
               '*DATABASE_NODOUT', f10(T_BEND / 200)], history_nodes(tip)]
    blocks.append(['*LOAD_NODE_POINT'] + [f10(n + 1, 3, 1, -w) for n, w in zip(tip, weights)])
    rc, text, out = run_case('hex_cantilever_e%d_ihq%d' % (elform, ihq), blocks)
    checks.check(rc == 0, 'cantilever ELFORM %d IHQ %d: run succeeds' % (elform, ihq),
                 text[-600:])
    if rc != 0:
        return None
    n = nodout(out)
    # the mean deflection of the tip over the hold (the last half: the load is constant and
    # the residual vibration averages out)
    t = n['time']
    hold = t >= T_BEND / 2
    return float(-np.mean(n['z-disp'][hold, :]))


explicit_tip = None
for elform, ihq, qm in ((1, 6, 1.0), (2, 1, 0.1)):
    d = cantilever(elform, ihq, qm)
    if d is None:
        continue
    if elform == 1:
        explicit_tip = d
    err = d / exact_tip - 1
    print('    cantilever ELFORM %d (IHQ %d QM %g): tip deflection %.5f mm, Timoshenko %.5f mm, '
          '%+.1f %%' % (elform, ihq, qm, d, exact_tip, 100 * err))
    checks.check(abs(err) < 0.05, 'cantilever ELFORM %d: tip deflection within 5 %% of beam '
                 'theory' % elform, '%+.3f' % err)



def cantilever_static(nsolvr, ihq, qm):
    """The cantilever's static tip deflection: linear static (NSOLVR 1) or nonlinear implicit
    (12, two load steps); the load on the curve's value 1 at t = 1."""
    blocks = [nodes_card(xb), elements_card('ELEMENT_SOLID', cb),
              hex_part(1, elastic(), hgid=1), hourglass_cards(ihq, qm),
              node_set(1, clamped), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1, 1, 1, 1)],
              curve(1, [(0.0, 0.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.5),
               '*CONTROL_IMPLICIT_SOLUTION', free(nsolvr, 11, 15, 1.0e-6),
               '*DATABASE_BINARY_D3PLOT', f10(0.5)]]
    blocks.append(['*LOAD_NODE_POINT'] + [free(n + 1, 3, 1, -w) for n, w in zip(tip, weights)])
    rc, text, out = run_case('hex_cantilever_static_s%d_ihq%d' % (nsolvr, ihq), blocks)
    checks.check(rc == 0, 'cantilever, %s, IHQ %d: run succeeds'
                 % ('linear static' if nsolvr == 1 else 'nonlinear implicit', ihq), text[-600:])
    if rc != 0:
        return None
    point, cell = last_state(out)
    return float(-point['displacement'][tip, 2].mean())


for nsolvr, ihq, qm in ((1, 6, 1.0), (12, 6, 1.0), (12, 1, 1.0)):
    d = cantilever_static(nsolvr, ihq, qm)
    if d is None or explicit_tip is None:
        continue
    err = d / exact_tip - 1
    print('    cantilever %s IHQ %d QM %g: tip deflection %.5f mm (%+.1f %% from Timoshenko, '
          '%+.2f %% from the explicit run)' % ('linear static' if nsolvr == 1 else
                                               'nonlinear implicit', ihq, qm, d, 100 * err,
                                               100 * (d / explicit_tip - 1)))
    # the static analyses compute the same element: the explicit run's mean deflection within
    # 1 % (its residual vibration), beam theory within 5 %
    checks.check(abs(d / explicit_tip - 1) < 0.01 and abs(err) < 0.05, 'cantilever, NSOLVR %d '
                 'IHQ %d: static deflection = explicit (1 %%) and beam theory (5 %%)'
                 % (nsolvr, ihq), '%+.4f %+.4f' % (d / explicit_tip - 1, err))

# ---- 5. copper Taylor bar in hexahedra ---------------------------------------------------------
deck = os.path.join(OUT, 'taylor_hex_coarse.k')
os.makedirs(OUT, exist_ok=True)
tc.write_deck(deck, 1, 'coarse', plots=2)
out = os.path.join(OUT, 'taylor_hex_coarse')
import subprocess  # noqa: E402
proc = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '-o', out, deck], capture_output=True,
                      text=True)
checks.check(proc.returncode == 0, 'Taylor bar in hexahedra: run succeeds', proc.stdout[-600:])
if proc.returncode == 0:
    length, radius = tc.final_shape(os.path.join(out, 'taylor_hex_coarse.h5'))
    g = glstat(out)
    ratio = g['total energy / initial energy'][-1]
    hg = g['hourglass energy'][-1] / g['internal energy'][-1]
    print('    Taylor bar (972 hexahedra): length %.3f mm, footprint radius %.3f mm, energy '
          'ratio %.5f, hourglass / internal %.3f' % (length, radius, ratio, hg))
    lo, hi = tc.PUBLISHED_LENGTH
    checks.check(0.99 * lo <= length <= 1.01 * hi, 'Taylor bar: final length within 1 % of '
                 'the published range', '%.3f' % length)
    lo, hi = tc.PUBLISHED_RADIUS
    checks.check(0.97 * lo <= radius <= 1.03 * hi, 'Taylor bar: footprint radius within 3 % of '
                 'the published range', '%.3f' % radius)
    checks.check(abs(ratio - 1) < 0.01, 'Taylor bar: energy balance within 1 %', '%.5f' % ratio)
    checks.check(hg < 0.10, 'Taylor bar: hourglass energy < 10 % of internal', '%.3f' % hg)

# ---- 6. ranks --------------------------------------------------------------------------------
one = concentrated(1, 0.1, 2.0, 1, '_r1')
three = concentrated(1, 0.1, 2.0, 3, '_r3')
if one and three:
    a, b = last_state(one)[0]['displacement'], last_state(three)[0]['displacement']
    checks.check(np.array_equal(a, b), 'load on 2 x 2 mm on 1 and 3 ranks: the same '
                 'displacements, bit for bit', '%.2e' % np.abs(a - b).max())
# ---- 7. free and thin structures: the step ------------------------------------------------------
K_BULK = YOUNG / (3 * (1 - 2 * POISSON))
for shape in ((1, 1, 1), (1, 1, 4), (1, 4, 4), (2, 4, 4)):
    xf, cf = box_hexes(float(shape[0]), float(shape[1]), float(shape[2]), *shape)
    name = 'hex_free_%d%d%d' % shape
    blocks = [nodes_card(xf), elements_card('ELEMENT_SOLID', cf), hex_part(1, elastic()),
              node_set(1, range(len(xf))), ['*LOAD_NODE_SET', f10(1, 1, 9, 0.002)],
              curve(9, [(0.0, 1.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(2e-3), '*DATABASE_GLSTAT', f10(2e-4),
               '*DATABASE_BINARY_D3PLOT', f10(2e-3)]]
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: a free block of %s hexahedra under nodal forces runs 2 ms' %
                 (name, 'x'.join(map(str, shape))), text[-500:])
    if rc != 0:
        continue
    g = glstat(out)
    thin = min(shape) == 1
    expected = 0.9 * (1.0 / np.sqrt(3 * K_BULK / DENSITY) if thin else 1.0 / wave_speeds()[1])
    ratio = g['total energy / initial energy'][-1]
    print('    %s: first step %.6e s (expected %.6e: %s), energy ratio %.9f'
          % (name, g['time step'][0], expected, 'element bound' if thin else 'L/c rule', ratio))
    checks.check(abs(g['time step'][0] / expected - 1) < 1e-6 and abs(ratio - 1) < 1e-6,
                 '%s: step %s, energy ratio 1 (1e-6)' % (name, '0.9 x 2/omega of the free '
                 'dilatation mode' if thin else '0.9 L/c (LS-DYNA\'s rule)'),
                 '%.6e %.9f' % (g['time step'][0], ratio))

checks.exit()
