"""*DEFINE_CURVE_SMOOTH (issue 23): the velocity curve that rises over TRISE from TSTART, holds
V0 and falls back to 0 at TEND, its area DIST (keywords.md 3.7; mm, s, mm/s). A block of
hexahedra every node of which follows the curve as a prescribed velocity (VAD 0) translates
rigidly; nodout gives its velocity and displacement:
- zero velocity before TSTART and after TEND; V0/2 half-way up the rise (the half cosine's
  middle), V0 on the plateau: V0 = DIST/(TEND - TSTART - TRISE) when TEND is given;
- the displacement after TEND equals DIST (the central difference integrates the prescribed
  velocity by the midpoint rule: exact on the curve's linear pieces, off by at most
  dt^2 |slope jump|/8 at each of its 34 kinks, below 1e-7 of DIST here);
- given V0 instead of TEND, the curve ends at TSTART + TRISE + DIST/V0 with the same area.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_hexes, node_set, run_case, nodout, history_nodes

checks = Checks('define curve smooth')
DIST, TSTART, TRISE = 2.0, 1.0e-4, 2.0e-4


def deck(curve_card, end_time):
    x, conn = box_hexes(1.0, 1.0, 1.0, 2, 2, 2)
    return [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
            ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
             '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
            node_set(1, range(len(x))),
            ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(1, 1, 0, 1, 1.0)],
            ['*DEFINE_CURVE_SMOOTH', curve_card],
            ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_NODOUT', f10(end_time / 400),
             '*DATABASE_BINARY_D3PLOT', f10(end_time)], history_nodes([0])]


def check_case(label, card, t_end, v_max):
    rc, text, out = run_case('curve_smooth_%s' % label, deck(card, t_end + 2.0e-4))
    checks.check(rc == 0, '%s: run succeeds' % label, text[-600:])
    if rc != 0:
        return
    h = nodout(out)
    t, vel, disp = h['time'], h['x-vel'][:, 0], h['x-disp'][:, 0]
    # nodout gives v(t - dt/2): margins of 1 % of TRISE (dt is about 1e-7 s)
    margin = 0.01 * TRISE
    before, after = t < TSTART, t > t_end + margin
    plateau = (t > TSTART + TRISE + margin) & (t < t_end - TRISE)
    checks.check(np.all(vel[before] == 0.0) and np.all(vel[after] == 0.0) and
                 np.all(abs(vel[plateau] / v_max - 1.0) < 1e-12),
                 '%s: velocity 0 before TSTART and after TEND, V0 = %.6g mm/s on the plateau'
                 % (label, v_max), '%s' % vel[plateau][:3])
    # half-way up the rise: the sampled cosine is within V0 pi^2/(16 16^2) = 2.4e-3 V0 of the
    # cosine and nodout's v(t - dt/2) lags by V0 pi dt/(4 TRISE) < 1e-3 V0: 5e-3 V0
    k = np.argmin(abs(t - (TSTART + 0.5 * TRISE)))
    s = (t[k] - TSTART) / TRISE
    want = 0.5 * v_max * (1.0 - np.cos(np.pi * s))
    checks.check(abs(vel[k] - want) < 5e-3 * v_max, '%s: half-way up the rise the velocity '
                 'is V0 (1 - cos(pi s))/2 = %.5g (got %.5g)' % (label, want, vel[k]))
    checks.check(abs(disp[after][-1] / DIST - 1.0) < 1e-7, '%s: displacement after TEND = '
                 'DIST = %g mm (got %.12g)' % (label, DIST, disp[after][-1]))


t_end = 1.0e-3
check_case('tend', f10(1, 0, DIST, TSTART, t_end, TRISE), t_end, DIST / (t_end - TSTART - TRISE))
v0 = 4000.0
check_case('v0', f10(1, 0, DIST, TSTART, 0.0, TRISE, v0), TSTART + TRISE + DIST / v0, v0)
checks.exit()
