"""Element erosion (issue 23): a point whose equivalent plastic strain reaches the material's
failure strain (FAIL of *MAT_024, FS of *MAT_003, EPSF of *MAT_018, PSFAIL of *MAT_098) fails
and carries no stress from then on (explicit; mm, t, s, N, MPa; doc/theory.md 6.6).

1. One hexahedron (ELFORM 1) in uniaxial tension at 1000 mm/s, perfectly plastic (SIGY 200,
   ETAN 0), FAIL 0.1: it fails when ln(1 + v t/L) = FAIL + SIGY/E (the log strain's elastic part
   at the yield stress): not eroded at 0.99 t_f, eroded at 1.01 t_f; glstat's eroded internal
   energy is the plastic work SIGY FAIL V0 (to 0.5 %), the internal energy falls to the elastic
   rest, 'energy ratio w/o eroded energy' stays 1 (1e-3) while the ratio itself drops by the
   eroded share; the stress is zero after.
2. A tensile bar with a notch, pulled at 5 m/s until it separates, for ELFORM 43 (ME-FEM: its
   smoothing cells fail one by one), 13 (the nodal-pressure means leave the failed cells out)
   and 10 (standard tets): elements erode, the run ends normally; on 2 ranks the same nodal bits
   and the same count of eroded cells as on 1 (every rank takes the same decisions).
3. *MAT_003 FS and *MAT_018 EPSF on the one-hexahedron case: eroded as well; *MAT_ADD_EROSION
   on it (an elastic cube: MXEPS, EFFEPS, FAILTM, NCS 2 with MXEPS and FAILTM; the hardening
   cube: SIGVM): not eroded at 0.99, eroded at 1.01 of the failure time of each criterion.
   *MAT_015 with the Johnson-Cook failure D1 D2 D3 (perfectly plastic, no rate or heat): in
   tension (triaxiality 1/3) the point fails at alpha = D1 + D2 exp(D3/3), in compression
   (-1/3) at D1 + D2 exp(-D3/3), 2.5 times later: each erodes between 0.99 and 1.01 of its time.
4. Contact: a strip of 4 hexahedra lying on a rigid support under a body load of 1e8 mm/s^2,
   pulled apart at its ends (FAIL 0.01): the support holds it until its elements erode; then
   their faces leave the contact and the free nodes fall through the support (with the faces
   kept it would go on holding them), which carries no force at the end.
"""
import os
import re
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from lsdyna_ascii import read_rcforc
from explicit_cases import DENSITY, YOUNG, box_tets, box_hexes, node_set, curve, run_case, glstat

checks = Checks('erosion')
SIGY, FAIL, V = 200.0, 0.1, 1000.0


def cube_deck(end_time, material, velocity=V):
    x, conn = box_hexes(1.0, 1.0, 1.0, 1, 1, 1)
    bottom = np.nonzero(x[:, 2] < 1e-9)[0]
    top = np.nonzero(x[:, 2] > 1.0 - 1e-9)[0]
    # uniaxial stress: the bottom on rollers (one corner pinned, one on a line), the top pulled
    spc = ['*BOUNDARY_SPC_NODE']
    for n in bottom:
        px, py = x[n, 0], x[n, 1]
        spc.append(f10(n + 1, 0, int(px == 0.0), int(py == 0.0), 1))
    return [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
            ['*PART', 'cube', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1)], material,
            spc, node_set(2, top), ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, 3, 0, 1, velocity)],
            curve(1, [(0.0, 1.0), (1.0, 1.0)]),
            ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_GLSTAT', f10(end_time / 50),
             '*DATABASE_BINARY_D3PLOT', f10(end_time)]]


def last_stress(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'])[-1]
        return f['states/%s/cell/stress' % last][()]


def one_cube():
    t_fail = (np.exp(FAIL + SIGY / YOUNG) - 1.0) / V
    mat024 = ['*MAT_PIECEWISE_LINEAR_PLASTICITY', free(1, DENSITY, YOUNG, 0.3, SIGY, 0.0, FAIL),
              free(0.0, 0.0)]
    for name, factor in (('erosion_cube_before', 0.99), ('erosion_cube_after', 1.01)):
        rc, text, out = run_case(name, cube_deck(factor * t_fail, mat024))
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return
        eroded = 'eroded 1 cells, 1 elements' in text
        g = glstat(out)
        stress = last_stress(out, name)
        if factor < 1.0:
            checks.check('eroded 0 cells' in text and g['eroded internal energy'][-1] == 0.0 and
                         np.max(abs(stress)) > 0.5 * SIGY, 'at 0.99 t_f = %.4g s: not eroded, '
                         'stressed' % (factor * t_fail), text[-300:])
            continue
        work = SIGY * FAIL * 1.0
        e_ie = g['eroded internal energy'][-1]
        checks.check(eroded and abs(e_ie - work) < 5e-3 * work and np.all(stress == 0.0),
                     'at 1.01 t_f: eroded, no stress, eroded internal energy %.4f = SIGY FAIL V0 '
                     '= %.1f mJ (0.5 %%)' % (e_ie, work), text[-300:])
        ratio, ratio_all = g['total energy / initial energy'][-1], \
            g['energy ratio w/o eroded energy'][-1]
        print('    energy ratio %.4f, without eroded energy %.6f; internal energy left %.4f mJ'
              % (ratio, ratio_all, g['internal energy'][-1]))
        checks.check(abs(ratio_all - 1.0) < 1e-3 and ratio < 0.1 and
                     g['internal energy'][-1] < 0.01 * work, 'energy ratio w/o eroded energy 1 '
                     '(1e-3), the ratio down by the eroded share, the internal energy the elastic '
                     'rest', '%g %g' % (ratio, ratio_all))
    for label, material in (
            ('*MAT_003 FS', ['*MAT_PLASTIC_KINEMATIC', free(1, DENSITY, YOUNG, 0.3, SIGY, 0.0, 1.0),
                             free(0.0, 0.0, FAIL)]),
            ('*MAT_018 EPSF', ['*MAT_POWER_LAW_PLASTICITY', free(1, DENSITY, YOUNG, 0.3, SIGY, 0.0),
                               free(0.0, 0.0, FAIL)])):
        rc, text, out = run_case('erosion_cube_%s' % label[5:8], cube_deck(1.01 * t_fail, material))
        checks.check(rc == 0 and 'eroded 1 cells, 1 elements' in text, '%s: the cube erodes at '
                     '1.01 t_f' % label, text[-400:])


def notched_bar(elform, ranks):
    x, conn = box_tets(12.0, 2.0, 2.0, 12, 2, 2)
    conn = np.array(conn)
    # a notch: the elements whose centroid is near x = 6, y > 1.4 removed
    centre = x[conn].mean(axis=1)
    conn = conn[~((abs(centre[:, 0] - 6.0) < 0.5) & (centre[:, 1] > 1.4))]
    used = np.unique(conn)
    renumber = np.zeros(len(x), dtype=int)
    renumber[used] = np.arange(len(used))
    x, conn = x[used], renumber[conn]
    left = np.nonzero(x[:, 0] < 1e-9)[0]
    right = np.nonzero(x[:, 0] > 12.0 - 1e-9)[0]
    end = 6.0e-4
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'bar', f10(1, 1, 1), '*SECTION_SOLID', f10(1, elform),
               '*MAT_PIECEWISE_LINEAR_PLASTICITY',
               free(1, DENSITY, YOUNG, 0.3, SIGY, 2000.0, 0.3), free(0.0, 0.0)],
              node_set(1, left), node_set(2, right),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)],
              ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, 1, 0, 1, 5000.0)],
              curve(1, [(0.0, 0.0), (5.0e-5, 1.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(end), '*DATABASE_GLSTAT', f10(end / 20),
               '*DATABASE_BINARY_D3PLOT', f10(end / 2)]]
    name = 'erosion_bar_%d_%d' % (elform, ranks)
    rc, text, out = run_case(name, blocks, ranks=ranks)
    cells = re.search(r'eroded (\d+) cells, (\d+) elements', text)
    u = None
    if rc == 0:
        with h5py.File(os.path.join(out, name + '.h5')) as f:
            last = sorted(f['states'])[-1]
            order = np.argsort(f['mesh/node_ids'][()])
            u = f['states/%s/point/displacement' % last][()][order]
    return rc, text, cells, u


def bars():
    for elform in (43, 13, 10):
        results = {}
        for ranks in (1, 2):
            rc, text, cells, u = notched_bar(elform, ranks)
            checks.check(rc == 0 and cells is not None and int(cells.group(2)) > 0,
                         'notched bar ELFORM %d, %d rank(s): elements erode, the run ends' %
                         (elform, ranks), text[-500:])
            if rc != 0 or cells is None:
                return
            results[ranks] = (cells.groups(), u)
        print('    ELFORM %d: eroded %s cells, %s elements' % (elform, *results[1][0]))
        checks.check(results[1][0] == results[2][0] and np.array_equal(results[1][1],
                                                                        results[2][1]),
                     'ELFORM %d: 2 ranks erode the same cells, the same displacement bits' % elform,
                     '%s %s' % (results[1][0], results[2][0]))


def strip_on_support():
    xp, cp = box_hexes(4.0, 1.0, 0.5, 4, 1, 1)
    n = len(xp)
    ends = np.nonzero((xp[:, 0] < 1e-9) | (xp[:, 0] > 4.0 - 1e-9))[0]
    left = np.nonzero(xp[:, 0] < 1e-9)[0]
    right = np.nonzero(xp[:, 0] > 4.0 - 1e-9)[0]
    inner = np.setdiff1d(np.arange(n), ends)
    support_x = np.array([[-1.0, -1.0, 0.0], [5.0, -1.0, 0.0], [5.0, 2.0, 0.0], [-1.0, 2.0, 0.0]])
    clock_x = np.array([[20.0, 0, 0], [21.0, 0, 0], [20.0, 1.0, 0], [20.0, 0, 1.0]])
    x = np.vstack([xp, support_x, clock_x])
    end = 1.0e-4
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', cp, pid=1),
              ['*ELEMENT_SHELL', '%8d%8d%8d%8d%8d%8d' % (100, 2, n + 1, n + 2, n + 3, n + 4)],
              # an elastic tet far away keeps bounding the step once the strip has eroded
              elements_card('ELEMENT_SOLID', [[n + 4, n + 5, n + 6, n + 7]], pid=3,
                            first_id=200),
              ['*PART', 'clock', f10(3, 3, 3), '*SECTION_SOLID', f10(3, 10),
               '*MAT_ELASTIC', free(3, DENSITY, YOUNG, 0.3)],
              ['*PART', 'strip', f10(1, 1, 1), '*PART', 'support', f10(2, 2, 2),
               '*SECTION_SOLID', f10(1, 1), '*SECTION_SHELL', f10(2, 2), f10(0.1, 0.1, 0.1, 0.1),
               '*MAT_PIECEWISE_LINEAR_PLASTICITY', free(1, DENSITY, YOUNG, 0.3, SIGY, 1000.0,
                                                        0.01), free(0.0, 0.0),
               '*MAT_RIGID', free(2, DENSITY, YOUNG, 0.3), f10(1.0, 7, 7)],
              node_set(1, left), node_set(2, right),
              ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, 1, 0, 1, -1000.0),
               f10(2, 1, 0, 1, 1000.0)],
              curve(1, [(0.0, 1.0), (1.0, 1.0)]),
              ['*LOAD_BODY_Z', f10(1, 1.0e8)],
              ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), f10(0.0), ''],
              ['*CONTROL_TERMINATION', f10(end), '*DATABASE_BINARY_D3PLOT', f10(end / 4),
               '*DATABASE_RCFORC', f10(end / 50)]]
    rc, text, out = run_case('erosion_strip', blocks)
    checks.check(rc == 0, 'strip: run succeeds', text[-600:])
    if rc != 0:
        return
    with h5py.File(os.path.join(out, 'erosion_strip.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        z = [(f['mesh/coordinates'][()][order] + f['states/%s/point/displacement' % k][()][
            order])[inner, 2].min() for k in sorted(f['states'])]
    cells = re.search(r'eroded (\d+) cells', text)
    print('    lowest inner node of the strip at the states: %s mm; %s' %
          (np.round(z, 4), cells.group(0) if cells else 'no erosion line'))
    # (states every end/4: held at the first, eroded by about 2.2e-5 s, then falling: 1/2 g t^2)
    checks.check(cells is not None and int(cells.group(1)) == 4 and len(z) == 5 and
                 z[1] > -0.01 and z[3] < -0.1 and z[4] < z[3], 'strip: held by the support '
                 'until it eroded, then its free nodes fall through (its faces left the '
                 'contact)', text[-400:])
    forces = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']['z']
    peak, final = np.max(abs(forces)), abs(forces[-1])
    print('    support force: peak %.4g N, at the end %.3g N' % (peak, final))
    checks.check(peak > 0.0 and final == 0.0, 'strip: the support carries no force at the end',
                 '%g %g' % (peak, final))


def add_erosion():
    """*MAT_ADD_EROSION criteria on the uniaxial cube (v = 1000 mm/s, L = 1 mm): eroded
    between 0.99 and 1.01 of the analytic failure time, not before."""
    elastic = ['*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)]
    j2 = ['*MAT_PIECEWISE_LINEAR_PLASTICITY', free(1, DENSITY, YOUNG, 0.3, SIGY, 1000.0),
          free(0.0, 0.0)]
    plastic_modulus = YOUNG * 1000.0 / (YOUNG - 1000.0)
    cases = [
        # MXEPS 0.05: the largest principal log strain ln(1 + v t) reaches 0.05
        ('MXEPS', elastic, [f10(1), f10(0.0, 0.0, 0.0, 0.05)], (np.exp(0.05) - 1.0) / V),
        # EFFEPS 0.05 on the elastic cube: the effective log strain 2/3 (1 + PR) ln(1 + v t)
        ('EFFEPS', elastic, [f10(1, 0.0, 0.0, 0.0, 0.05)],
         (np.exp(0.05 / (2.0 / 3.0 * 1.3)) - 1.0) / V),
        # SIGVM 250: the flow stress SIGY + Ep alpha of the hardening cube reaches 250
        ('SIGVM', j2, [f10(1), f10(0.0, 0.0, 250.0)],
         (np.exp((250.0 - SIGY) / plastic_modulus + 250.0 / YOUNG) - 1.0) / V),
        # FAILTM: the time
        ('FAILTM', elastic, [f10(1), f10(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0e-5)], 5.0e-5),
        # NCS 2: MXEPS 0.01 (reached at 1e-5 s) and FAILTM 5e-5 together: the later
        ('NCS 2', elastic, [f10(1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2),
                            f10(0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 5.0e-5)], 5.0e-5)]
    for label, material, cards, t_fail in cases:
        outcome = []
        for factor in (0.99, 1.01):
            name = 'erosion_add_%s_%d' % (label.replace(' ', ''), int(100 * factor))
            rc, text, out = run_case(name, cube_deck(factor * t_fail, material +
                                                     ['*MAT_ADD_EROSION'] + cards))
            outcome.append(rc == 0 and ('eroded 1 cells' in text) == (factor > 1.0))
        checks.check(all(outcome), '*MAT_ADD_EROSION %s: not eroded at 0.99 t_f, eroded at 1.01 '
                     't_f = %.4g s' % (label, t_fail), text[-400:])


def johnson_cook_cube():
    """*MAT_015 with D1 0.05, D2 0.5, D3 -1.5 (A = SIGY, B = 0): the damage sum reaches 1 at
    alpha = D1 + D2 exp(D3 s*), s* = +1/3 pulled, -1/3 pushed; |ln stretch| = alpha + SIGY/E."""
    d1, d2, d3 = 0.05, 0.5, -1.5
    material = ['*MAT_JOHNSON_COOK', free(1, DENSITY, 0.0, YOUNG, 0.3),
                free(SIGY, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0),
                free(0.0, 0.0, 0.0, 0.0, d1, d2, d3, 0.0)]
    for label, sign in (('tension', 1.0), ('compression', -1.0)):
        eps_f = d1 + d2 * np.exp(d3 * sign / 3.0)
        t_fail = abs(np.exp(sign * (eps_f + SIGY / YOUNG)) - 1.0) / V
        outcome = []
        for factor in (0.99, 1.01):
            name = 'erosion_jc_%s_%d' % (label, int(100 * factor))
            rc, text, out = run_case(name, cube_deck(factor * t_fail, material, sign * V))
            outcome.append(rc == 0 and ('eroded 1 cells' in text) == (factor > 1.0))
        checks.check(all(outcome), '*MAT_015 D1-D3, %s: fails at alpha = %.4f: not eroded at '
                     '0.99 t_f, eroded at 1.01 t_f = %.4g s' % (label, eps_f, t_fail),
                     text[-400:])


one_cube()
johnson_cook_cube()
add_erosion()
bars()
strip_on_support()
checks.exit()
