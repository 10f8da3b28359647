"""Geometric rigid walls, *RIGIDWALL_GEOMETRIC_FLAT/_PRISM/_CYLINDER/_SPHERE and _MOTION
(issue 23): the elastic rod of test_explicit_rigid_wall.py (L = 100 mm, 5 x 5 mm, nu = 0, steel,
ME-FEM tets) at v0 = 5 m/s hits each wall: contact for 2L/c0 with the force rho c0 A v0.
- a FLAT wall with edges under the rod gives the planar wall's force history bit for bit; one
  whose rectangle lies beside the rod lets it pass;
- a PRISM (the rod hits the face of a box), a CYLINDER (the rod hits its side; radius 1000 mm)
  and a SPHERE (radius 1000 mm) press with rho c0 A v0 for 2L/c0 (within 5 %), and no node
  ends inside them;
- a FLAT wall with _MOTION pushing the rod at rest at V (OPT 0: a velocity curve; OPT 1: the
  displacement V t, the same run) presses with rho c0 A V, and no node gets behind it.
Units: mm, t, s, MPa.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_tets, elastic, curve, part_cards, run_case
from lsdyna_ascii import read_rwforc

checks = Checks('rigid_wall_geometric')
L, W, NX, V0, GAP = 100.0, 5.0, 40, 5000.0, 0.01
R = 1000.0
c0 = np.sqrt(YOUNG / DENSITY)
duration = 2 * L / c0
x, conn = box_tets(L, W, W, NX, 2, 2)
x = x - [0.0, W / 2, W / 2]                   # the rod's axis on the x axis, end at x = 0


def rod_deck(wall, v=(-V0, 0.0, 0.0), end_time=1.5 * duration):
    return [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
            part_cards(43, elastic(poisson=0.0)),
            ['*INITIAL_VELOCITY', f10(0), f10(*v)],
            ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT',
             f10(end_time / 30), '*DATABASE_GLSTAT', f10(duration / 200)], wall]


def run(name, wall, **kw):
    rc, text, out = run_case(name, rod_deck(wall, **kw))
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    f = read_rwforc(os.path.join(out, 'rwforc'))
    positions, times = [], []
    with h5py.File(os.path.join(out, name + '.h5')) as h:
        order = np.argsort(h['mesh/node_ids'][()])
        for s in sorted(h['states'].keys()):
            positions.append(x + h['states/%s/point/displacement' % s][()][order])
            times.append(h['states/%s' % s].attrs['time'])
    return f[min(f)], positions, times


def plateau_checks(name, f, force, direction):
    """Contact time 2L/c0 and force plateau rho c0 A v (the force along `direction`)."""
    along = f['x'] * direction[0] + f['y'] * direction[1] + f['z'] * direction[2]
    pressing = abs(along) > 0.5 * force
    if not pressing.any():
        checks.check(False, '%s: the wall is hit' % name)
        return
    t_on = f['time'][pressing]
    contact = t_on[-1] - t_on[0] + (f['time'][1] - f['time'][0])
    plateau = np.mean(abs(along[pressing][len(t_on) // 4: 3 * len(t_on) // 4]))
    print('    %s: contact %.4e s (2L/c0 %+.2f %%), force plateau %.4e N (rho c0 A v %+.2f %%)'
          % (name, contact, 100 * (contact / duration - 1), plateau,
             100 * (plateau / force - 1)))
    checks.check(abs(contact / duration - 1) < 0.05, '%s: contact lasts 2L/c0 within 5 %%' %
                 name, '%.4e' % contact)
    checks.check(abs(plateau / force - 1) < 0.05, '%s: force rho c0 A v within 5 %%' % name,
                 '%.4e' % plateau)


force0 = DENSITY * c0 * W * W * V0
planar = run('geo_planar', ['*RIGIDWALL_PLANAR', f10(0), f10(-GAP, 0.0, 0.0, 1.0, 0.0, 0.0)])
# a finite flat wall: the 20 x 20 mm square from (-GAP, -10, -10), l along y, m = n x l = z
flat = run('geo_flat', ['*RIGIDWALL_GEOMETRIC_FLAT_ID', f10(3), f10(0),
                        f10(-GAP, -10.0, -10.0, 1.0, -10.0, -10.0), f10(0.0, 1.0, 0.0, 20.0,
                                                                          20.0)])
if planar and flat:
    same = all(np.array_equal(planar[0][k], flat[0][k]) for k in ('time', 'x', 'y', 'z'))
    checks.check(same, 'flat with edges under the rod: the planar wall\'s forces bit for bit')
# the square beside the rod (y in [10, 30]): no contact
beside = run('geo_flat_beside', ['*RIGIDWALL_GEOMETRIC_FLAT', f10(0),
                                 f10(-GAP, 10.0, -10.0, 1.0, 10.0, -10.0),
                                 f10(0.0, 1.0, 0.0, 20.0, 20.0)], end_time=0.5 * duration)
if beside:
    checks.check(np.all(beside[0]['x'] == 0.0) and beside[1][-1][:, 0].min() < -GAP,
                 'flat wall beside the rod: no force, the rod passes its plane',
                 '%.3e %.3e' % (np.max(abs(beside[0]['x'])), beside[1][-1][:, 0].min()))
# prism: the box x in [-GAP - 50, -GAP], y, z in [-25, 25] (tail a corner, n = +x, l = y)
prism = run('geo_prism', ['*RIGIDWALL_GEOMETRIC_PRISM', f10(0),
                          f10(-GAP - 50.0, -25.0, -25.0, 1.0, -25.0, -25.0),
                          f10(0.0, 1.0, 0.0, 50.0, 50.0, 50.0)])
if prism:
    plateau_checks('prism', prism[0], force0, (1, 0, 0))
    inside = max(np.sum((p[:, 0] < -GAP - 1e-9) & (p[:, 0] > -GAP - 50.0) &
                        (abs(p[:, 1]) < 25.0) & (abs(p[:, 2]) < 25.0)) for p in prism[1])
    checks.check(inside == 0, 'prism: no node inside the box at any state', '%d' % inside)
# cylinder: axis along y through x = -GAP - R (its side at x = -GAP), infinite
cylinder = run('geo_cylinder', ['*RIGIDWALL_GEOMETRIC_CYLINDER', f10(0),
                                f10(-GAP - R, 0.0, 0.0, -GAP - R, 1.0, 0.0), f10(R)])
if cylinder:
    plateau_checks('cylinder', cylinder[0], force0, (1, 0, 0))
    depth = max(np.max(R - np.hypot(p[:, 0] + GAP + R, p[:, 2])) for p in cylinder[1])
    checks.check(depth <= 1e-9, 'cylinder: no node inside at any state', '%.3e' % depth)
# sphere: centre at (-GAP - R, 0, 0)
sphere = run('geo_sphere', ['*RIGIDWALL_GEOMETRIC_SPHERE', f10(0),
                            f10(-GAP - R, 0.0, 0.0, 0.0, 0.0, 0.0), f10(R)])
if sphere:
    plateau_checks('sphere', sphere[0], force0, (1, 0, 0))
    depth = max(np.max(R - np.linalg.norm(p + [GAP + R, 0.0, 0.0], axis=1)) for p in sphere[1])
    checks.check(depth <= 1e-9, 'sphere: no node inside at any state', '%.3e' % depth)
# motion: the wall at the rod's end (x = 0) moving +x at V pushes the rod at rest
V = 2000.0
moving = {}
for opt, points in ((0, [(0.0, V), (1.0, V)]), (1, [(0.0, 0.0), (1.0, V)])):
    name = 'geo_motion_opt%d' % opt
    result = run(name, ['*RIGIDWALL_GEOMETRIC_FLAT_MOTION', f10(0),
                        f10(0.0, -10.0, -10.0, 1.0, -10.0, -10.0),
                        f10(0.0, 1.0, 0.0, 0.0, 0.0), f10(9, opt, 1.0, 0.0, 0.0)] +
                 curve(9, points), v=(0.0, 0.0, 0.0), end_time=0.5 * duration)
    if result:
        moving[opt] = result
        force = DENSITY * c0 * W * W * V
        along = abs(result[0]['x'])
        steady = along[len(along) // 4:]
        behind = max(np.max(V * t - p[:, 0]) for t, p in zip(result[2], result[1]))
        print('    moving wall, OPT %d: force %.4e .. %.4e N (rho c0 A V %.4e); largest '
              'penetration %.2e mm' % (opt, steady.min(), steady.max(), force, behind))
        checks.check(np.all(abs(steady / force - 1) < 0.05), 'moving wall, OPT %d: the '
                     'wall pushes with rho c0 A V within 5 %%' % opt, '%.4e' % steady.mean())
        checks.check(behind <= 1e-9, 'moving wall, OPT %d: no node behind the wall' % opt,
                     '%.3e' % behind)
if 0 in moving and 1 in moving:
    diff = np.max(abs(moving[0][0]['x'] - moving[1][0]['x'])) / force
    checks.check(diff < 1e-6, 'moving wall: a velocity curve and the displacement curve of '
                 'the same motion give the same forces (1e-6)', '%.3e' % diff)
checks.exit()
