"""A run that blows up stops cleanly (issue 5): one node of a block is thrown at a speed that
inverts its elements within a few cycles. mefem must stop with a non-zero exit code and a
message naming the element and the cycle, after writing the state reached (readable HDF5 and
VTK, a final glstat record). And a run whose step falls below DTMIN x the first step (a block
crushed on a rigid wall) stops naming the cycle, the time and the element that sets the step.
"""
import os
import re
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import box_tets, elastic, glstat, part_cards, run_case

checks = Checks('explicit_failure')
x, conn = box_tets(10.0, 10.0, 10.0, 2, 2, 2)
corner = int(np.argmin(np.linalg.norm(x - [10.0, 10.0, 10.0], axis=1)))
blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn), part_cards(43, elastic()),
          ['*INITIAL_VELOCITY_NODE', free(corner + 1, -1.0e9, -1.0e9, -1.0e9)],
          ['*CONTROL_TERMINATION', f10(1.0e-5), '*DATABASE_BINARY_D3PLOT', f10(1.0e-5),
           '*DATABASE_GLSTAT', f10(1.0e-7)]]
rc, text, out = run_case('blow_up', blocks)
print('    ' + '\n    '.join(line for line in text.splitlines() if 'error' in line))
checks.check(rc != 0, 'exits with a non-zero code', 'rc = %d' % rc)
m = re.search(r'error: element (\d+): (.*)', text)
checks.check(m is not None, 'names the failed element and why', text[-400:])
c = re.search(r'a cell failed at cycle (\d+), t = (\S+)', text)
checks.check(c is not None, 'names the cycle and the time', text[-400:])
h5 = os.path.join(out, 'blow_up.h5')
ok = os.path.exists(h5)
if ok:
    with h5py.File(h5) as f:
        states = sorted(f['states'].keys())
        ok = len(states) >= 2 and 'displacement' in f['states/%s/point' % states[-1]]
        t_last = f['states/%s' % states[-1]].attrs['time'] if ok else None
checks.check(ok, 'the state reached is written to the HDF5 file', h5)
if ok:
    # state 0 is the explicit run's t = 0 state: the initial velocity (and the fields the
    # later states have), not the model alone
    with h5py.File(h5) as f:
        first = f['states/000000']
        ids = f['mesh/node_ids'][()]
        fields = sorted(first['point'].keys())
        v0 = first['point/velocity'][()][int(np.nonzero(ids == corner + 1)[0][0])] \
            if 'velocity' in first['point'] else None
        t0 = first.attrs['time']
    checks.check(t0 == 0.0 and v0 is not None and np.array_equal(v0, [-1.0e9] * 3) and
                 'displacement' in fields, 'state 0 is t = 0 with the fields, the thrown '
                 'node\'s initial velocity among them', '%s %s %s' % (t0, fields, v0))
if ok and c is not None:
    checks.check(abs(t_last - float(c.group(2))) <= 1e-5 * float(c.group(2)),   # 6 digits
                 'the last state is at the failure time', '%s vs %s' % (t_last, c.group(2)))
checks.check(os.path.exists(os.path.join(out, 'blow_up.pvd')), 'the ParaView file is written')
g = glstat(out)
checks.check(len(g['time']) >= 2, 'glstat holds the records up to the failure',
             '%d records' % len(g['time']))

# ---- DTMIN: the step falls below DTMIN x the first step -----------------------------------
# The block hits a rigid wall at 1.5 km/s; the crushed elements lower the stable step, and
# DTMIN = 0.99 stops the run at the first 1 % drop, after writing the state reached.
blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn), part_cards(43, elastic()),
          ['*INITIAL_VELOCITY', f10(0), f10(-1.5e6, 0.0, 0.0)],
          ['*RIGIDWALL_PLANAR', f10(0, 0, 0, 0.0), f10(-0.01, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)],
          ['*CONTROL_TERMINATION', f10(1.0e-5, 0, 0.99), '*DATABASE_BINARY_D3PLOT', f10(1.0e-5),
           '*DATABASE_GLSTAT', f10(1.0e-8)]]
rc, text, out = run_case('dtmin_stop', blocks)
print('    ' + '\n    '.join(line for line in text.splitlines() if 'error' in line))
checks.check(rc != 0, 'DTMIN: exits with a non-zero code', 'rc = %d' % rc)
m = re.search(r'fell below DTMIN x the initial step = \S+ at cycle (\d+), t = \S+ \(the step '
              r'is set by solid (\d+) of part 1\)', text)
checks.check(m is not None, 'DTMIN: names the cycle, the time and the element setting the step',
             text[-400:])
g = glstat(out) if os.path.exists(os.path.join(out, 'glstat')) else None
if m is not None and g is not None:
    checks.check(len(g['time']) >= 2, 'DTMIN: glstat holds the records up to the stop',
                 '%d records' % len(g['time']))
checks.exit()
