"""Mortar contact with mass scaling (explicit, issue 5/6): a block (SURFA) pressed by p = 10 MPa
onto a fixed rigid plate of shells (SURFB), quasi-static through heavy selective mass scaling
(DT2MS < 0: about 10^4 times the mass where the step needs it). The penalty's stability cap
eps <= 0.1 m_A / (a_A dt^2) must take the integrator's (scaled) masses with the scaled step:
with the physical masses the cap falls by the added mass' ratio and the block sinks through
the plate (a tester's upsetting run: the die passed through the billet, nothing warned).
Expected: the contact force equals p A and the block's bottom sinks into the plate by about
p / eps_material (the penalty of the unscaled contact), not by the block's height.
ME-FEM tets, units mm, t, s, MPa.
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
T1, T_END = 5.0e-3, 7.0e-3                  # load ramp, end (the scaled block's period ~2e-4 s)
DT2MS = -1.0e-5                             # 100 times the natural step (~1e-7 s)
checks = Checks('contact_mass_scaling')

x, cb, quads, nb = block_on_plate(0.0)      # block [1,2] x [1,2] x [0,0.5] on the plate z = 0
bottom_probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))
blocks = block_on_plate_cards(x, cb, quads, RHO, E, NU) + [
          face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
          curve(1, smooth_ramp(T1, P) + [(1.0, P)]),
          ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), '', ''],
          ['*CONTROL_TIMESTEP', f10(0.0, 0.9, 0, 0.0, DT2MS)],
          ['*CONTROL_TERMINATION', f10(T_END), '*DATABASE_BINARY_D3PLOT', f10(T_END),
           '*DATABASE_GLSTAT', f10(T_END / 100), '*DATABASE_RCFORC', f10(T_END / 100),
           '*DATABASE_NODOUT', f10(T_END / 100), '*DATABASE_HISTORY_NODE',
           f10(bottom_probe + 1)]]
rc, text, out = run_case('mass_scaled_contact', blocks)
checks.check(rc == 0, 'block pressed on a plate with mass scaling: run succeeds', text[-600:])
if rc == 0:
    g = glstat(out)
    added = g['percentage increase'][-1]
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    force = r['normal'][-1]
    sink = -read_nodout(os.path.join(out, 'nodout'))['z-disp'][-1, 0]
    # the unscaled penalty: eps_material = SLSFAC K / h, K = E / (3 (1 - 2 nu)), h = 0.25 mm
    # (block height over its 2 layers of hexahedra); the mortar pressure averages it over
    # the facets, so the sink is about p / eps_material
    bulk = E / (3.0 * (1.0 - 2.0 * NU))
    sink_expected = P / (0.1 * bulk / 0.25)
    print('    added mass %.0f %%; contact force %.4f N (p A = %.4f); the bottom sinks %.4e mm '
          '(p / eps_material = %.4e)' % (added, force, P * 1.0, sink, sink_expected))
    checks.check(added > 1.0e5, 'mass scaling adds over 1000 times the mass', '%.0f %%' % added)
    checks.check(abs(force / P - 1) < 0.03, 'contact force = p A within 3 %',
                 '%.5f vs %.5f' % (force, P))
    checks.check(0.0 < sink < 2.0 * sink_expected, 'the block sinks into the plate by less '
                 'than 2 p / eps_material (the unscaled penalty holds)',
                 '%.4e vs %.4e' % (sink, sink_expected))
checks.exit()
