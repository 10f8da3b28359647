"""Coulomb friction of the mortar contact (issue 6). Explicit, ME-FEM tets, units mm, t, s, MPa.

1. Sliding block: a block (SURFA) on a fixed rigid plate of shells (SURFB), FS = FD = 0.3,
   pressed by p = 10 MPa (ramped over T1, then held) and pulled sideways by a force growing
   linearly from 0 to 2 mu N over T2. While the pull is below mu N the block sticks: the
   friction force equals the pull and the slip stays at the elastic (penalty) level; above it,
   the block slides with friction force = mu N. Stick-slip at the time the pull reaches mu N.
2. Objectivity: two blocks pressed together, standing on a turntable (a rigid plate with a
   prescribed spin) and spinning with it a quarter turn, FS = 0.3: the friction force must stay
   as small as for the pair at rest (the slip comes from the change of the mortar weights,
   which a rigid rotation of the pair leaves unchanged).
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import (box_tets, node_set, curve, run_case, face_segments, smooth_ramp,
                            block_on_plate, block_on_plate_cards)
from lsdyna_ascii import read_glstat, read_nodout, read_rcforc

E, NU, P, MU = 1000.0, 0.3, 10.0, 0.3
RHO_BLOCK = 1.0e-9           # light: the contact spring's period (6 us) << the load ramps
RHO_PAIR = 1.0e-9            # light: the centrifugal stress of the spin is 1 % of p
# divide the contact work among the ranks however small the interfaces (by default only from
# 2000 candidate pairs per rank; doc/theory.md 10.8), so that the rank checks exercise it
os.environ['MEFEM_CONTACT_DIVIDE_MIN'] = '0'
checks = Checks('contact_friction')


# ---- 1. sliding block -----------------------------------------------------------------------
T1, T2 = 5.0e-5, 2.0e-4
x, cb, quads, nb = block_on_plate(0.0)              # block on [1,2] x [1,2] x [0,0.5]
top = np.nonzero(abs(x[:nb, 2] - 0.5) < 1e-9)[0]
bottom_probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))
normal_force = P * 1.0
pull_end = 2.0 * MU * normal_force                 # the pull grows to 2 mu N over T2
blocks = block_on_plate_cards(x, cb, quads, RHO_BLOCK, E, NU) + [
          face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
          curve(1, smooth_ramp(T1, P) + [(1.0, P)]),
          node_set(5, top), ['*LOAD_NODE_SET', f10(5, 1, 2, 1.0 / len(top))],
          curve(2, [(0.0, 0.0), (T1, 0.0), (T1 + T2, pull_end), (1.0, pull_end)]),
          ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3),
           f10(MU, MU), f10(1.0, 1.0)],
          ['*CONTROL_TERMINATION', f10(T1 + 0.65 * T2), '*DATABASE_BINARY_D3PLOT',
           f10(T1 + 0.65 * T2),
           '*DATABASE_GLSTAT', f10(T2 / 100), '*DATABASE_RCFORC', f10(T2 / 200),
           '*DATABASE_NODOUT', f10(T2 / 200), '*DATABASE_HISTORY_NODE',
           f10(bottom_probe + 1)]]
rc, text, out = run_case('sliding_block', blocks)
checks.check(rc == 0, 'sliding block: run succeeds', text[-600:])
if rc == 0:
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    n = read_nodout(os.path.join(out, 'nodout'))
    t = r['time']
    pull = np.interp(t, [0.0, T1, T1 + T2], [0.0, 0.0, pull_end])
    t_slip = T1 + T2 * MU * normal_force / pull_end
    stick = (t > T1) & (pull < 0.8 * MU * normal_force)
    slide = t > t_slip + 0.05 * T2                # after the transition (the run ends at
                                                  # t_slip + 0.15 T2: the block slides < 0.3 mm)
    fx, fn = abs(r['x']), r['normal']              # friction along the pull, normal force
    ft = r['tangential']                           # magnitude of the whole friction force
    # stick: friction balances the pull (the block is at rest): |F_t - pull| small
    stick_err = np.max(abs(abs(fx[stick]) - pull[stick])) / (MU * normal_force)
    ratio = ft[slide] / fn[slide]
    slip_x = np.interp(t, n['time'], n['x-disp'][:, 0])
    stick_slip = np.max(abs(slip_x[stick]))
    moved = np.nonzero(slip_x > 10 * max(stick_slip, 1e-12))[0]
    t_moved = t[moved[0]] if len(moved) else np.inf
    print('    stick: |friction - pull| <= %.2e mu N, bottom slip <= %.2e mm; sliding: '
          'friction / normal %.4f .. %.4f (mu %.2f); slip starts at %.4e s (pull = mu N at '
          '%.4e s)' % (stick_err, stick_slip, ratio.min(), ratio.max(), MU, t_moved, t_slip))
    # measured 1.5e-2 mu N (the block's inertia under the growing pull)
    checks.check(stick_err < 0.03, 'stick: friction force = pull within 3 % of mu N',
                 '%.3e' % stick_err)
    # measured 5.2e-3 mm: the elastic (penalty) compliance of the tangential traction,
    # mu p / eps_T, with eps_T capped at (1 - TSSFAC^2) m/dt^2 per area (doc/theory.md 10.5),
    # so it grows with the stable step (8.6e-3 mm with a fixed cap of 0.1); sliding moves the
    # block 10x that within T2/10
    checks.check(stick_slip < 0.01, 'stick: no slip (bottom node moves < 1 % of the block)',
                 '%.3e' % stick_slip)
    # measured 0.3000 throughout the slide
    checks.check(np.all(abs(ratio / MU - 1) < 0.02), 'sliding: friction / normal force = mu '
                 'within 2 %', '%.4f .. %.4f' % (ratio.min(), ratio.max()))
    checks.check(abs(t_moved - t_slip) < 0.1 * T2, 'stick-slip transition when the pull '
                 'reaches mu N (within 10 % of the pull ramp)', '%.4e vs %.4e' % (t_moved,
                                                                                t_slip))

# ---- 1b. the penalty cap at smaller TSSFAC ------------------------------------------------------
# The cap is max(0.1, 1 - TSSFAC^2) m/dt^2 per area: 0.75 at TSSFAC 0.5, 0.55 at 0.67 (a common
# choice with contact), 0.19 at the default 0.9 (above). The stiffer penalty must stay stable
# (energy ratio, measured 1.0011 and 1.0018 at most) and slide at mu N. (At TSSFAC 0.95, where
# the cap is the floor 0.1, this block's contact breaks down near the end of the run, in this
# build and the one before the rebalanced split: doc/theory.md 10.5.)
for tssfac in (0.5, 0.67):
    name = 'sliding_block_tssfac_%g' % tssfac
    rc_t, text_t, out_t = run_case(name, blocks + [['*CONTROL_TIMESTEP', f10(0.0, tssfac)]])
    checks.check(rc_t == 0, '%s: run succeeds' % name, text_t[-600:])
    if rc_t != 0:
        continue
    g = read_glstat(os.path.join(out_t, 'glstat'))
    energy = g['total energy / initial energy'][1:]
    r = read_rcforc(os.path.join(out_t, 'rcforc'))[1]['slave']
    slide = r['time'] > T1 + T2 * MU * normal_force / pull_end + 0.05 * T2
    ratio = r['tangential'][slide] / r['normal'][slide]
    print('    TSSFAC %g: energy ratio %.5f .. %.5f, sliding friction / normal %.4f .. %.4f' % (
        tssfac, energy.min(), energy.max(), ratio.min(), ratio.max()))
    checks.check(np.all(abs(energy - 1) < 0.01) and np.all(abs(ratio / MU - 1) < 0.02),
                 '%s: stable (energy ratio within 1 %%) and sliding at mu N (2 %%)' % name,
                 '%.5f .. %.5f; %.4f .. %.4f' % (energy.min(), energy.max(), ratio.min(),
                                                 ratio.max()))

# ---- 1a. the friction from *PART_CONTACT (the contact's FS = -1): the same bits --------------
if rc == 0:
    from_parts = []
    for block in blocks:
        block = list(block)
        if block[:3] == ['*PART', 'block', f10(1, 1, 1)]:
            block = ['*PART_CONTACT', 'block', f10(1, 1, 1), f10(MU, MU)] + block[3:]
        if block and block[0] == '*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR':
            block = [block[0], block[1], f10(-1.0), block[3]]
        from_parts.append(block)
    rc_p, text_p, out_p = run_case('sliding_block_part_contact', from_parts)
    checks.check(rc_p == 0, 'sliding block, FS = -1 with *PART_CONTACT: run succeeds',
                 text_p[-600:])
    if rc_p == 0:
        # (the first line names the deck)
        same = open(os.path.join(out, 'rcforc')).read().split('\n')[1:] == \
            open(os.path.join(out_p, 'rcforc')).read().split('\n')[1:]
        checks.check(same, 'sliding block: FS = -1 takes *PART_CONTACT\'s FS, FD (rcforc '
                     'identical to FS = FD = 0.3 on the contact card)')

# ---- 1b. the same sliding block on 2 ranks: the same bits --------------------------------
# The mortar kernels are divided among the ranks (doc/theory.md 10.8) and the friction state
# is kept per slave node on every rank: the rcforc history and the last state (displacement,
# velocity, contact pressure) must be bit-identical to the 1-rank run.


def last_state(outdir, name):
    """The last state's nodal fields in node-id order."""
    with h5py.File(os.path.join(outdir, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        return [f['states/%s/point/%s' % (last, k)][()][order]
                for k in ('displacement', 'velocity', 'contact_pressure')]


if rc == 0:
    rc2, text2, out2 = run_case('sliding_block_np2', blocks, ranks=2)
    checks.check(rc2 == 0, 'sliding block on 2 ranks: run succeeds', text2[-600:])
    if rc2 == 0:
        r1 = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
        r2 = read_rcforc(os.path.join(out2, 'rcforc'))[1]['slave']
        keys = ('x', 'y', 'z', 'normal', 'tangential')
        same = all(np.array_equal(r1[k], r2[k]) for k in keys)
        checks.check(same, 'sliding block: rcforc history on 2 ranks identical to 1 rank')
        s1, s2 = last_state(out, 'sliding_block'), last_state(out2, 'sliding_block_np2')
        same = all(np.array_equal(a, b) for a, b in zip(s1, s2))
        checks.check(same, 'sliding block: last state on 2 ranks bit-identical to 1 rank',
                     '%.3e' % max(np.max(abs(a - b)) for a, b in zip(s1, s2)))

# ---- 2. objectivity: a pressed pair spinning as one body ------------------------------------
# The lower block stands on a rigid plate (shell quads sharing its bottom nodes) that turns
# about z at a prescribed rate (*BOUNDARY_PRESCRIBED_MOTION_RIGID DOF 7, its other rotations
# held): the support that keeps the dead-loaded pair from tipping over (a free pair pressed by
# two opposite dead loads is a strut that buckles). The upper block is pressed down by p; both
# blocks start with the same rigid spin. The friction force must stay as small as for the pair
# at rest (the slight difference of the two meshes' Poisson expansion: 2.4e-3 of the normal
# force measured at rest); a slip measure that mistook the rotation for sliding would drive the
# friction to its limit mu N.
T = 1.0e-4
x1, c1 = box_tets(1.0, 1.0, 1.0, 3, 3, 3)
x2, c2 = box_tets(1.0, 1.0, 1.0, 4, 4, 3)
x2 = x2 + [0.0, 0.0, 1.0]
x = np.vstack([x1, x2])
c2 = c2 + len(x1)
base = {(round(x[n, 0] * 3), round(x[n, 1] * 3)): n for n in np.nonzero(x[:, 2] < 1e-9)[0]}
base_quads = np.array([[base[(i, j)], base[(i + 1, j)], base[(i + 1, j + 1)], base[(i, j + 1)]]
                       for j in range(3) for i in range(3)])


def spinning_pair(turn_rate, name):
    omega = turn_rate * 0.5 * np.pi / T
    return omega, [nodes_card(x), elements_card('ELEMENT_SOLID', c1, pid=1),
                   elements_card('ELEMENT_SOLID', c2, pid=2, first_id=len(c1) + 1),
                   elements_card('ELEMENT_SHELL', base_quads, pid=3,
                                 first_id=len(c1) + len(c2) + 1),
                   ['*PART', 'lower', f10(1, 1, 1), '*PART', 'upper', f10(2, 1, 1),
                    '*SECTION_SOLID', f10(1, 43), '*MAT_ELASTIC', free(1, RHO_PAIR, E, NU),
                    '*PART', 'turntable', f10(3, 2, 2), '*SECTION_SHELL', f10(2, 2),
                    f10(0.1, 0.1, 0.1, 0.1), '*MAT_RIGID', free(2, 7.85e-9, 210000.0, 0.3),
                    f10(1.0, 7, 4)],
                   ['*BOUNDARY_PRESCRIBED_MOTION_RIGID', f10(3, 7, 0, 2, omega)],
                   curve(2, [(0.0, 1.0), (1.0, 1.0)]),
                   face_segments(x, c2, 2, 2.0, 1, 8), ['*LOAD_SEGMENT_SET', f10(8, 1, 1.0)],
                   curve(1, smooth_ramp(0.3 * T, P) + [(1.0, P)]),
                   node_set(1, range(len(x))),
                   ['*INITIAL_VELOCITY_GENERATION', free(1, 3, omega, 0.0, 0.0, 0.0),
                    free(0.5, 0.5, 1.0, 0.0, 0.0, 1.0)],
                   ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(2, 1, 3, 3),
                    f10(MU, MU), f10(1.0, 1.0)],
                   ['*CONTROL_TERMINATION', f10(T), '*DATABASE_BINARY_D3PLOT', f10(T),
                    '*DATABASE_GLSTAT', f10(T / 50), '*DATABASE_RCFORC', f10(T / 50)]]


ratios = {}
for turn_rate, name in ((0.0, 'pair_at_rest'), (1.0, 'spinning_pair')):
    omega, blocks = spinning_pair(turn_rate, name)
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, name + ': run succeeds', text[-600:])
    if rc != 0:
        continue
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    pressed = r['time'] > 0.3 * T
    ratios[name] = np.max(r['tangential'][pressed] / r['normal'][pressed])
    print('    %s (omega %.3e rad/s, %.0f deg at the end): friction / normal force <= %.2e, '
          'normal force %.4f .. %.4f N' % (name, omega, np.degrees(omega * T), ratios[name],
                                          r['normal'][pressed].min(), r['normal'][pressed].max()))
if len(ratios) == 2:
    # measured 2.4e-3 at rest and 8.8e-3 spinning a quarter turn (the centrifugal stress,
    # rho omega^2 r^2 ~ 1 % of p, stretches the two meshes slightly differently): 3 % of mu;
    # a slip measure that saw the rotation as sliding would reach mu
    checks.check(ratios['spinning_pair'] < 0.1 * MU, 'spinning pair: friction force below '
                 '10 % of mu N under a quarter turn (objective slip)',
                 '%.3e (at rest %.3e)' % (ratios['spinning_pair'], ratios['pair_at_rest']))
checks.exit()
