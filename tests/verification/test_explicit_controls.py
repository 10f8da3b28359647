"""Mass scaling with contact, and explicit controls that LS-DYNA forming decks set (issue 5). A
block (SURFA) pressed by p = 10 MPa onto a fixed rigid plate of shells (SURFB), quasi-static
through heavy selective mass scaling (DT2MS = -1e-5 s: 100 times the natural step, about 10^4
times the mass where the step needs it). ME-FEM tets, units mm, t, s, MPa.
1. The penalty's stability cap eps <= 0.1 m_A / (a_A dt^2) must take the integrator's (scaled)
   masses with the scaled step: with the physical masses the cap falls by the added mass'
   ratio and the block sinks through the plate (a tester's upsetting: the die passed through
   the billet, nothing warned). Expected: contact force p A, the bottom sinking by about
   p / eps_material (the unscaled penalty), not by the block's height.
2. *CONTROL_TIMESTEP LCTM = a curve of 5e-6 s: every step is 5e-6 s instead of 1e-5 s.
3. Contact DT = 6 ms (the load is ramped to p by 5 ms): the plate carries p A until 6 ms, and
   nothing afterwards (rcforc zero), as in LS-DYNA.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10
from explicit_cases import (curve, run_case, face_segments, smooth_ramp, block_on_plate,
                            block_on_plate_cards, glstat)
from lsdyna_ascii import read_nodout, read_rcforc

E, NU, P, RHO = 1000.0, 0.3, 10.0, 1.0e-9
T1, T_END, DT2MS, CAP, DEATH = 5.0e-3, 7.0e-3, -1.0e-5, 5.0e-6, 6.0e-3
checks = Checks('explicit_controls')
x, cb, quads, nb = block_on_plate(0.0)      # block [1,2] x [1,2] x [0,0.5] on the plate z = 0
bottom_probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))


def deck(lctm=0, death=None):
    contact_card2 = '' if death is None else f10(0.0, 0.0, 0.0, 0.0, 0.0, 0, 0.0, death)
    return block_on_plate_cards(x, cb, quads, RHO, E, NU) + [
        face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
        curve(1, smooth_ramp(T1, P) + [(1.0, P)]), curve(2, [(0.0, CAP), (1.0, CAP)]),
        ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), contact_card2, ''],
        ['*CONTROL_TIMESTEP', f10(0.0, 0.9, 0, 0.0, DT2MS, lctm)],
        ['*CONTROL_TERMINATION', f10(T_END), '*DATABASE_BINARY_D3PLOT', f10(T_END),
         '*DATABASE_GLSTAT', f10(T_END / 100), '*DATABASE_RCFORC', f10(T_END / 100),
         '*DATABASE_NODOUT', f10(T_END / 100), '*DATABASE_HISTORY_NODE',
         f10(bottom_probe + 1)]]


rc, text, out = run_case('mass_scaled_contact', deck())
checks.check(rc == 0, 'block pressed on a plate with mass scaling: run succeeds', text[-600:])
if rc == 0:
    added = glstat(out)['percentage increase'][-1]
    force = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']['normal'][-1]
    sink = -read_nodout(os.path.join(out, 'nodout'))['z-disp'][-1, 0]
    # the unscaled penalty: eps_material = SLSFAC K / h, K = E / (3 (1 - 2 nu)), h = 0.25 mm
    # (block height over its 2 layers of hexahedra); the mortar pressure averages it over
    # the facets, so the sink is about p / eps_material
    sink_expected = P / (0.1 * E / (3.0 * (1.0 - 2.0 * NU)) / 0.25)
    print('    added mass %.0f %%; contact force %.4f N (p A = %.4f); the bottom sinks %.4e mm '
          '(p / eps_material = %.4e)' % (added, force, P * 1.0, sink, sink_expected))
    checks.check(added > 1.0e5, 'mass scaling adds over 1000 times the mass', '%.0f %%' % added)
    checks.check(abs(force / P - 1) < 0.03, 'mass scaling: contact force = p A within 3 %',
                 '%.5f vs %.5f' % (force, P))
    checks.check(0.0 < sink < 2.0 * sink_expected, 'mass scaling: the block sinks into the '
                 'plate by less than 2 p / eps_material (the unscaled penalty holds)',
                 '%.4e vs %.4e' % (sink, sink_expected))


rc, text, out = run_case('lctm_cap', deck(lctm=2))
checks.check(rc == 0, 'LCTM: run succeeds', text[-600:])
if rc == 0:
    steps = glstat(out)['time step'][1:]
    print('    LCTM %.1e s: steps %.4e .. %.4e s (DT2MS %.1e s)' % (CAP, steps.min(), steps.max(),
                                                                  DT2MS))
    checks.check(np.all(abs(steps / CAP - 1) < 1e-12), 'LCTM: every step is the curve\'s value '
                 '(below the mass-scaled step)', '%.6e .. %.6e' % (steps.min(), steps.max()))

rc, text, out = run_case('contact_death', deck(death=DEATH))
checks.check(rc == 0, 'contact DT: run succeeds', text[-600:])
if rc == 0:
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    before = (r['time'] > T1) & (r['time'] < DEATH)
    after = r['time'] > DEATH
    print('    contact DT %.1e s: force %.4f .. %.4f N before (p A = %.1f), %.3e after' % (
        DEATH, r['normal'][before].min(), r['normal'][before].max(), P,
        np.max(abs(r['normal'][after]))))
    checks.check(np.all(abs(r['normal'][before] / P - 1) < 0.03), 'contact DT: the plate '
                 'carries p A (3 %) until DT', '%.4f .. %.4f' % (r['normal'][before].min(),
                                                                r['normal'][before].max()))
    checks.check(np.any(after) and np.all(r['normal'][after] == 0.0), 'contact DT: no contact '
                 'force after DT', '%.3e' % np.max(abs(r['normal'][after])))
checks.exit()
