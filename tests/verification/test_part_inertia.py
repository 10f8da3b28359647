"""*PART_INERTIA (issue 23): a rigid body's mass, centre, inertia tensor and initial velocity
given in the deck (explicit; mm, t, s, N, MPa).

A rigid cube of 1 mm^3 (its elements' mass 7.85e-9 t) is given TM = 2e-6 t, its centre, the
inertia diag(1, 2, 3) e-6 t mm^2 (a body the mesh does not describe, as a tool's carriage), an
initial velocity VTX = 500 mm/s and spin VRZ = 100 rad/s. Forces: 0.25 N in +y on each of its 8
nodes (no moment about the centre), and a couple of +-0.3 N in y on two nodes 1 mm apart in x
(a moment F cos(theta) about z as the body turns). A standard tetrahedron far away sets the
time step. Checked:
- glstat at t = 0: kinetic energy TM v^2/2 + Izz w^2/2 (1e-12);
- rbdout: the centre moved 500 t in x and a t^2/2 in y with a = 2 N / TM (1e-9);
- the nodes at the end: the centre's motion plus the rotation theta(t) of theta'' = F cos(theta)
  / Izz, theta'(0) = 100 rad/s (integrated here; 1e-8 of the largest displacement);
- errors: a deformable part with *PART_INERTIA, TM <= 0, IRCS = 1, NODEID undefined.
"""
import os
import subprocess
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, ROOT, f10, free, nodes_card, elements_card, write_deck
from explicit_cases import DENSITY, YOUNG, OUT, box_hexes, node_set, curve, run_case, glstat
from lsdyna_ascii import read_rbdout

checks = Checks('part_inertia')
TM, INERTIA = 2.0e-6, (1.0e-6, 2.0e-6, 3.0e-6)      # t, t mm^2
VTX, VRZ = 500.0, 100.0                            # mm/s, rad/s
PUSH, COUPLE = 0.25, 0.3                           # N
END = 1.0e-4                                       # s


def cube_deck(part_cards):
    xc, cc = box_hexes(1.0, 1.0, 1.0, 1, 1, 1)
    xc = xc + [5.0, 0.0, 0.0]
    tet = np.array([[20.0, 0, 0], [21.0, 0, 0], [20.0, 1.0, 0], [20.0, 0, 1.0]])
    x = np.vstack([xc, tet])
    a = int(np.nonzero(np.all(abs(xc - [6.0, 0.0, 0.0]) < 1e-9, axis=1))[0][0])
    b = int(np.nonzero(np.all(abs(xc - [5.0, 0.0, 0.0]) < 1e-9, axis=1))[0][0])
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', cc, pid=1),
              elements_card('ELEMENT_SOLID', [[8, 9, 10, 11, 11, 11, 11, 11]], pid=2,
                            first_id=2),
              part_cards,
              ['*PART', 'clock', f10(2, 2, 2), '*SECTION_SOLID', f10(1, 1), f10(2, 10),
               '*MAT_RIGID', free(1, DENSITY, YOUNG, 0.3), f10(0.0),
               '*MAT_ELASTIC', free(2, DENSITY, YOUNG, 0.3)],
              node_set(1, range(8)),
              ['*LOAD_NODE_SET', f10(1, 2, 1, PUSH)],
              ['*LOAD_NODE_POINT', f10(a + 1, 2, 1, COUPLE), f10(b + 1, 2, 1, -COUPLE)],
              curve(1, [(0.0, 1.0), (1.0, 1.0)]),
              ['*CONTROL_TERMINATION', f10(END), '*DATABASE_BINARY_D3PLOT', f10(END),
               '*DATABASE_GLSTAT', f10(END / 10)]]
    return blocks, xc


def inertia_part(pid=1, mid=1, tm=TM, ircs=0, nodeid=0):
    return ['*PART_INERTIA', 'cube', f10(pid, 1, mid), f10(5.5, 0.5, 0.5, tm, ircs, nodeid),
            f10(INERTIA[0], 0.0, 0.0, INERTIA[1], 0.0, INERTIA[2]),
            f10(VTX, 0.0, 0.0, 0.0, 0.0, VRZ)]


def angle(t_end):
    """theta(t_end) of theta'' = COUPLE cos(theta) / Izz, theta(0) = 0, theta'(0) = VRZ (RK4)."""
    n = 20000
    h = t_end / n
    y = np.array([0.0, VRZ])

    def f(y):
        return np.array([y[1], COUPLE * np.cos(y[0]) / INERTIA[2]])
    for _ in range(n):
        k1 = f(y)
        k2 = f(y + h / 2 * k1)
        k3 = f(y + h / 2 * k2)
        k4 = f(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return y[0]


def motion():
    blocks, xc = cube_deck(inertia_part())
    rc, text, out = run_case('part_inertia', blocks)
    checks.check(rc == 0, 'the run succeeds', text[-600:])
    if rc != 0:
        return
    g = glstat(out)
    ke0 = 0.5 * TM * VTX ** 2 + 0.5 * INERTIA[2] * VRZ ** 2
    err = abs(g['kinetic energy'][0] - ke0) / ke0
    checks.check(err < 1e-12, 'kinetic energy at t = 0: TM v^2/2 + Izz w^2/2 = %.4g mJ (1e-12)'
                 % ke0, '%.3e (got %.6e)' % (err, g['kinetic energy'][0]))
    rbd = read_rbdout(os.path.join(out, 'rbdout'))
    body = rbd.get(1)
    if body is None:
        checks.check(False, 'rbdout has the body', str(rbd.keys()))
        return
    t = body['time'][-1]
    acc = 8 * PUSH / TM
    want = np.array([VTX * t, 0.5 * acc * t ** 2, 0.0])
    got = np.array([body['x-disp'][-1], body['y-disp'][-1], body['z-disp'][-1]])
    err = np.max(abs(got - want)) / np.max(abs(want))
    checks.check(err < 1e-9, 'rbdout: the centre moved (500 t, a t^2/2, 0) with a = 2 N / TM '
                 '(1e-9)', 'got %s, want %s' % (got, want))
    with h5py.File(os.path.join(out, 'part_inertia.h5')) as f:
        last = sorted(f['states'])[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        u = f['states/%s/point/displacement' % last][()][order][:8]
        t_state = f['states/%s' % last].attrs['time']
    theta = angle(t_state)
    c0 = np.array([5.5, 0.5, 0.5])
    rot = np.array([[np.cos(theta), -np.sin(theta), 0], [np.sin(theta), np.cos(theta), 0],
                    [0, 0, 1]])
    centre = c0 + [VTX * t_state, 0.5 * acc * t_state ** 2, 0.0]
    want = centre + (xc - c0) @ rot.T - xc
    err = np.max(abs(u - want)) / np.max(abs(want))
    print('    theta(%.3g s) = %.6f rad; node displacement error %.2e of %.4f mm'
          % (t_state, theta, err, np.max(abs(want))))
    checks.check(err < 1e-8, 'the nodes follow the centre and the turn of theta\'\' = F cos '
                 '(theta) / Izz with the given inertia (1e-8)', '%.3e' % err)


def errors():
    cases = [
        ('deformable', inertia_part(mid=2), 'the part\'s material is not *MAT_RIGID'),
        ('tm', inertia_part(tm=0.0), 'field TM (the body\'s mass) must be positive'),
        ('ircs', inertia_part(ircs=1), 'IRCS = 1: an inertia tensor in a local coordinate '
                                       'system is not supported'),
        ('nodeid', inertia_part(nodeid=999), 'NODEID: node 999 is not defined')]
    for name, part, message in cases:
        blocks, _ = cube_deck(part)
        deck = os.path.join(OUT, 'part_inertia_%s.k' % name)
        write_deck(deck, blocks)
        p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '--check', deck],
                           capture_output=True, text=True)
        text = p.stdout + p.stderr
        checks.check(p.returncode == 1 and message in text and '*PART_INERTIA' in text,
                     'error: %s' % message, text[-400:])


motion()
errors()
checks.exit()
