"""Rigid bodies in the explicit solver (issue 5): a *MAT_RIGID part moved by
*BOUNDARY_PRESCRIBED_MOTION_RIGID compresses an elastic block it shares nodes with, slowly
(quasi-static): its reaction equals the block's force E A delta / H; and a free rigid body
keeps its momentum, and one given a spin by *INITIAL_VELOCITY_GENERATION spins; a free rigid
plate struck by a block moves the same bits on 1-4 ranks.
ME-FEM tets, units mm, t, s, MPa.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import (DENSITY, YOUNG, POISSON, box_tets, curve, elastic, glstat,
                            history_nodes, node_set, nodout, run_case)
from lsdyna_ascii import NODOUT_COLUMNS, read_rbdout

checks = Checks('explicit_rigid_body')

# ---- a rigid plate drives a block -------------------------------------------------------
# Block 10 x 10 x 20 mm (4 x 4 x 8 hexahedra of 6 tets), every node held laterally and the
# bottom held vertically: uniaxial strain (the rigid plate holds its nodes laterally anyway).
# The top face carries a rigid plate of 4 x 4 shell quads sharing the block's top nodes,
# moved down by delta = 0.02 mm (strain 1e-3) along d(t) = delta (s - sin(2 pi s)/(2 pi)),
# s = t/T, T = 200 us (60 wave transits): quasi-static. Expected force
# (lambda + 2 mu) A delta / H, stress -(lambda + 2 mu) delta / H in every element.
A, H, DELTA, T = 10.0, 20.0, 0.02, 2.0e-4
x, conn = box_tets(A, A, H, 4, 4, 8)
top = np.nonzero(abs(x[:, 2] - H) < 1e-9)[0]
grid = {(round(x[n, 0] / 2.5), round(x[n, 1] / 2.5)): n for n in top}
quads = [[grid[(i, j)], grid[(i + 1, j)], grid[(i + 1, j + 1)], grid[(i, j + 1)]]
         for j in range(4) for i in range(4)]
s = np.linspace(0.0, 1.0, 41)
motion = [(T * v, -DELTA * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]
blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
          elements_card('ELEMENT_SHELL', np.array(quads), pid=2, first_id=len(conn) + 1),
          ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43)] + elastic(),
          ['*PART', 'plate', f10(2, 2, 2), '*SECTION_SHELL', f10(2, 2), f10(1.0, 1.0, 1.0, 1.0),
           '*MAT_RIGID', free(2, DENSITY, YOUNG, POISSON), f10(1.0, 0, 7)],
          node_set(1, range(len(x))), node_set(3, np.nonzero(x[:, 2] < 1e-9)[0]),
          ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 0), '*BOUNDARY_SPC_SET', f10(3, 0, 0, 0, 1)],
          ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(2, 3, 2, 1, 1.0)],
          curve(1, motion + [(1.0, -DELTA)]),
          ['*CONTROL_TERMINATION', f10(T), '*DATABASE_BINARY_D3PLOT', f10(T),
           '*DATABASE_GLSTAT', f10(T / 100)]]
rc, text, out = run_case('rigid_drives_block', blocks)
checks.check(rc == 0, 'rigid plate drives a block: run succeeds', text[-600:])
if rc == 0:
    r = read_rbdout(os.path.join(out, 'rbdout'))[2]
    modulus = YOUNG * (1 - POISSON) / ((1 + POISSON) * (1 - 2 * POISSON))    # lambda + 2 mu
    expected = modulus * A * A * DELTA / H
    reaction = -r['z-reaction'][-1]          # the constraint pushes the plate down
    disp = r['z-disp'][-1]
    print('    plate displacement %.5e mm (prescribed %.5e); reaction %.5e N, (l+2m) A d/H = '
          '%.5e N (%+.2f %%)' % (disp, -DELTA, reaction, expected,
                                 100 * (reaction / expected - 1)))
    checks.check(abs(disp / -DELTA - 1) < 1e-9, 'rigid plate follows the prescribed '
                 'displacement', '%.6e' % disp)
    # measured +0.09 %: the plate's reaction is the block's elastic force (quasi-static)
    checks.check(abs(reaction / expected - 1) < 0.02, 'reaction of the rigid plate = '
                 '(lambda + 2 mu) A delta / H within 2 %', '%.5e vs %.5e' % (reaction, expected))
    half = len(r['time']) // 2
    d_half = -r['z-disp'][half]
    f_half = -r['z-reaction'][half]
    # at mid-stroke too (the force follows the displacement): measured within 1 %
    checks.check(abs(f_half / (modulus * A * A * d_half / H) - 1) < 0.03, 'reaction follows '
                 'the displacement at mid-stroke within 3 %',
                 '%.5e vs %.5e' % (f_half, modulus * A * A * d_half / H))
    with h5py.File(os.path.join(out, 'rigid_drives_block.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        szz = f['states/%s/cell/stress' % last][()][:, 2]
        parts = f['mesh/part_ids'][()] if 'mesh/part_ids' in f else None
    solid = szz[:len(conn)] if parts is None else szz[parts == 1]
    sigma = -modulus * DELTA / H
    print('    block sigma_zz %.2f .. %.2f MPa, -(lambda + 2 mu) delta/H = %.2f MPa' % (
        solid.min(), solid.max(), sigma))
    # measured -283.5 .. -282.5 MPa against -282.7
    checks.check(np.all(abs(solid / sigma - 1) < 0.03), 'block stress uniform = '
                 '-(lambda + 2 mu) delta/H within 3 %', '%.3f .. %.3f' % (solid.min(),
                                                                         solid.max()))
    g = glstat(out)
    ratio = g['total energy / initial energy'][5:]
    print('    energy ratio %.5f .. %.5f, kinetic / internal at the end %.2e' % (
        ratio.min(), ratio.max(), g['kinetic energy'][-1] / g['internal energy'][-1]))
    # measured 1.0000 .. 1.0002 (from the 5th record; the first hold micro-joules)
    checks.check(np.all(abs(ratio - 1) < 0.01), 'energy balance with the rigid plate within '
                 '1 %', '%.5f .. %.5f' % (ratio.min(), ratio.max()))

# ---- a free rigid body -----------------------------------------------------------------------
# A rigid tet block with an initial velocity and nothing else: it must keep its velocity
# and kinetic energy exactly, and its elements must not deform.
xr, connr = box_tets(10.0, 10.0, 10.0, 2, 2, 2)
v0 = np.array([1000.0, -500.0, 250.0])
blocks = [nodes_card(xr), elements_card('ELEMENT_SOLID', connr),
          ['*PART', 'rigid block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
           '*MAT_RIGID', free(1, DENSITY, YOUNG, POISSON), f10(0.0, 0, 0)],
          ['*INITIAL_VELOCITY', f10(0), f10(*v0)],
          ['*CONTROL_TERMINATION', f10(1.0e-4), '*CONTROL_TIMESTEP', free(1.0e-6, 0.9),
           '*DATABASE_BINARY_D3PLOT', f10(1.0e-4), '*DATABASE_GLSTAT', f10(1.0e-5)]]
rc, text, out = run_case('free_rigid_body', blocks)
checks.check(rc == 0, 'free rigid body: run succeeds', text[-600:])
if rc == 0:
    r = read_rbdout(os.path.join(out, 'rbdout'))[1]
    disp = np.array([r['x-disp'][-1], r['y-disp'][-1], r['z-disp'][-1]])
    err = np.linalg.norm(disp - v0 * r['time'][-1]) / np.linalg.norm(v0 * r['time'][-1])
    checks.check(err < 1e-12, 'free rigid body: moves at its initial velocity (1e-12)',
                 '%.3e' % err)
    g = glstat(out)
    ke = g['kinetic energy']
    mass = DENSITY * 1000.0
    checks.check(np.all(abs(ke / (0.5 * mass * v0 @ v0) - 1) < 1e-12), 'free rigid body: '
                 'kinetic energy 1/2 m v0^2 throughout', '%s' % ke[:3])

# ---- a spinning rigid body ---------------------------------------------------------------------
# The same block given *INITIAL_VELOCITY_GENERATION: OMEGA = 1000 rad/s about z through its centre
# c = (5, 5, 5) plus (VX, VY, VZ): the body takes the rigid field's translation and spin (the
# nodes' velocities fitted as a rigid field); a cube spins about a principal axis, so at T every
# node is at c + v T + Rz(OMEGA T)(x0 - c) (1e-10 of the displacement) and the kinetic energy is
# M |v|^2/2 + I_zz OMEGA^2/2, I_zz = M (10^2 + 10^2)/12, throughout (1e-10).
OMEGA0, T_SPIN = 1000.0, 1.0e-4
blocks = [nodes_card(xr), elements_card('ELEMENT_SOLID', connr),
          ['*PART', 'rigid block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
           '*MAT_RIGID', free(1, DENSITY, YOUNG, POISSON), f10(0.0, 0, 0)],
          ['*INITIAL_VELOCITY_GENERATION', f10(1, 2, OMEGA0, *v0),
           f10(5.0, 5.0, 5.0, 0.0, 0.0, 1.0)],
          ['*CONTROL_TERMINATION', f10(T_SPIN), '*CONTROL_TIMESTEP', free(1.0e-6, 0.9),
           '*DATABASE_BINARY_D3PLOT', f10(T_SPIN), '*DATABASE_GLSTAT', f10(T_SPIN / 10)]]
rc, text, out = run_case('spinning_rigid_body', blocks)
checks.check(rc == 0, 'spinning rigid body: run succeeds', text[-600:])
if rc == 0:
    with h5py.File(os.path.join(out, 'spinning_rigid_body.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        last = sorted(f['states'])[-1]
        t_end = float(f['time_history/time'][-1])
        u = f['states/%s/point/displacement' % last][()][order]
    angle = OMEGA0 * t_end
    rz = np.array([[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0],
                   [0.0, 0.0, 1.0]])
    centre = np.array([5.0, 5.0, 5.0])
    want = centre + v0 * t_end + (xr - centre) @ rz.T - xr
    err = np.max(np.linalg.norm(u - want, axis=1)) / np.max(np.linalg.norm(want, axis=1))
    checks.check(err < 1e-10, 'spinning rigid body: every node at c + v T + Rz(OMEGA T)(x0 - c) '
                 '(error %.1e)' % err)
    mass = DENSITY * 1000.0
    ke_want = 0.5 * mass * v0 @ v0 + 0.5 * mass * 200.0 / 12.0 * OMEGA0 ** 2
    ke = glstat(out)['kinetic energy']
    checks.check(np.all(abs(ke / ke_want - 1) < 1e-10), 'spinning rigid body: kinetic energy '
                 'M v^2/2 + I_zz OMEGA^2/2 throughout (1e-10)', '%s vs %.9e' % (ke[:3], ke_want))

# ---- rigid parts only: the step is DTINIT -----------------------------------------------------
# The rigid block driven in x by a velocity curve (VAD 0) that ramps from 0 at 20 us to 1 m/s at
# 30 us, 100 us in all: no deformable element bounds the step, so it is DTINIT (1e-7 s) every
# cycle and the block moves by the curve's integral, 75 um (the build before took one step of
# 100 us and moved it 100 um); without DTINIT (or LCTM) the run stops with a message.
def driven_block(timestep_cards):
    return [nodes_card(xr), elements_card('ELEMENT_SOLID', connr),
            ['*PART', 'rigid block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
             '*MAT_RIGID', free(1, DENSITY, YOUNG, POISSON), f10(1.0, 5, 7)],
            ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(1, 1, 0, 1, 1.0)],
            curve(1, [(0.0, 0.0), (2.0e-5, 0.0), (3.0e-5, 1000.0), (1.0, 1000.0)]),
            ['*CONTROL_TERMINATION', f10(1.0e-4), '*DATABASE_GLSTAT', f10(1.0e-5)] +
            timestep_cards]


rc, text, out = run_case('rigid_only_dtinit', driven_block(['*CONTROL_TIMESTEP', f10(1.0e-7)]))
checks.check(rc == 0, 'rigid parts only, DTINIT: run succeeds', text[-600:])
if rc == 0:
    r = read_rbdout(os.path.join(out, 'rbdout'))[1]
    cycles = int(glstat(out)['cycle'][-1])
    print('    rigid parts only: %d cycles, x-disp %.9e mm (curve integral 0.075)' % (
        cycles, r['x-disp'][-1]))
    checks.check(cycles == 1000 and abs(r['x-disp'][-1] / 0.075 - 1) < 1e-9, 'rigid parts '
                 'only: the step is DTINIT (1000 cycles) and the block moves by the velocity '
                 'curve\'s integral', '%d cycles, %.9e' % (cycles, r['x-disp'][-1]))
rc, text, out = run_case('rigid_only_no_step', driven_block([]))
checks.check(rc != 0 and 'no deformable element bounds the time step' in text, 'rigid parts '
             'only without DTINIT: the run stops and says to give DTINIT', text[-400:])

# ---- a free rigid plate struck by a block, on 1-4 ranks -----------------------------------
# An elastic block 1 x 2 x 2 mm (4 x 8 x 8 hexahedra of 6 standard tets) flies at 10 m/s
# (with 2 m/s sideways) into a free rigid plate 0.2 x 2 x 2 mm, 0.01
# mm away (frictionless contact); the plate is 12 x 12 x 12 hexahedra. The plate is split among the ranks and the contact pushes
# on nodes of several of them; its resultant force and moment are added in ascending node
# order on every rank count, so the plate's motion, and with it the block's, are the same
# bits on 1-4 ranks (with sums per rank added over the ranks they differed on 4 ranks).
xb, connb = box_tets(1.0, 2.0, 2.0, 4, 8, 8)
xb = xb + np.array([3.0, -0.5, -0.5])
nb = 12
grid = np.array([[4.01 + 0.2 * i / nb, -0.5 + 2.0 * j / nb, -0.5 + 2.0 * k / nb]
                 for k in range(nb + 1) for j in range(nb + 1) for i in range(nb + 1)])


def plate_node(i, j, k):
    return len(xb) + (k * (nb + 1) + j) * (nb + 1) + i


hexes = np.array([[plate_node(i, j, k), plate_node(i + 1, j, k), plate_node(i + 1, j + 1, k),
                   plate_node(i, j + 1, k), plate_node(i, j, k + 1), plate_node(i + 1, j, k + 1),
                   plate_node(i + 1, j + 1, k + 1), plate_node(i, j + 1, k + 1)]
                  for k in range(nb) for j in range(nb) for i in range(nb)])
probes = [0, len(xb) - 1, plate_node(nb, nb, nb), plate_node(0, 0, 0)]
blocks = [nodes_card(np.vstack([xb, grid])), elements_card('ELEMENT_SOLID', connb),
          elements_card('ELEMENT_SOLID', hexes, pid=2, first_id=len(connb) + 1),
          ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10)] + elastic(),
          ['*PART', 'plate', f10(2, 2, 2), '*SECTION_SOLID', f10(2, 1),
           '*MAT_RIGID', free(2, DENSITY, YOUNG, POISSON), f10(0.0, 0, 0)],
          ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', f10(1, 2, 3, 3), '', ''],
          ['*INITIAL_VELOCITY_GENERATION', f10(1, 2, 0.0, 1.0e4, 0.0, 2.0e3),
           f10(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)],
          ['*CONTROL_TERMINATION', f10(5.0e-6), '*DATABASE_NODOUT', f10(1.0e-7)] +
          history_nodes(probes)]
found = {}
for ranks in (1, 2, 3, 4):
    rc, text, out = run_case('free_plate_ranks%d' % ranks, blocks, ranks=ranks)
    checks.check(rc == 0, 'free rigid plate struck on %d ranks: run succeeds' % ranks,
                 text[-600:])
    if rc == 0:
        n = nodout(out)
        found[ranks] = np.stack([n[c] for c in NODOUT_COLUMNS[:9]])
if 1 in found:
    moved = found[1][0][:, 2:]                         # the plate's probes, x-disp
    checks.check(np.all(moved[-1] > 1e-4), 'free rigid plate: the block pushes it (x-disp '
                 'of its corners at the end > 1e-4 mm)', '%s' % moved[-1])
    for ranks in (2, 3, 4):
        if ranks in found:
            checks.check(np.array_equal(found[1], found[ranks]), 'free rigid plate struck, '
                         '%d ranks: histories identical to 1 rank (bit for bit)' % ranks,
                         'max difference %.3e' % np.max(abs(found[1] - found[ranks])))
checks.exit()
