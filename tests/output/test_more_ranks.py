"""More ranks than elements (issue 21): a one-tet model run on 1, 2 and 3 ranks by every analysis
(linear static, nonlinear implicit, explicit, none) must run, the ranks without an element idle,
and give the results of 1 rank. Before, every analysis but the explicit one stopped with
"partitioning failed: cannot split 1 elements into 2 parts".
"""
import os
import sys

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks, write_deck, run  # noqa: E402

checks = Checks('more_ranks')
OUT = os.path.join(ROOT, 'tests', 'out', 'more_ranks')

MODEL = ['*NODE', '1,0.0,0.0,0.0', '2,1.0,0.0,0.0', '3,0.0,1.0,0.0', '4,0.0,0.0,1.0',
         '*ELEMENT_SOLID', '1,1,1,2,3,4', '*PART', 'tet', '1,1,1', '*SECTION_SOLID', '1,43',
         '*MAT_ELASTIC', '1,7.85e-9,210000.0,0.3', '*SET_NODE_LIST', '1', '1,2,3',
         '*SET_NODE_LIST', '2', '4', '*BOUNDARY_SPC_SET', '1,0,1,1,1',
         '*DEFINE_CURVE', '1', '0.0,0.0', '1.0,1.0']
ANALYSES = {
    'linear': ['*LOAD_NODE_SET', '2,3,1,-100.0', '*CONTROL_IMPLICIT_SOLUTION', '1',
               '*CONTROL_IMPLICIT_GENERAL', '1,1.0', '*CONTROL_TERMINATION', '1.0'],
    'implicit': ['*BOUNDARY_PRESCRIBED_MOTION_SET', '2,3,2,1,-0.01',
                 '*CONTROL_IMPLICIT_GENERAL', '1,0.5', '*CONTROL_TERMINATION', '1.0',
                 '*DATABASE_BINARY_D3PLOT', '0.5'],
    'explicit': ['*BOUNDARY_PRESCRIBED_MOTION_SET', '2,3,0,1,-100.0',
                 '*CONTROL_TERMINATION', '1.0e-6', '*DATABASE_BINARY_D3PLOT', '1.0e-6'],
    'none': [],
}

for analysis, cards in ANALYSES.items():
    deck = os.path.join(OUT, 'one_tet_%s.k' % analysis)
    write_deck(deck, [MODEL, cards], title='one tet, %s' % analysis)
    results = {}
    for ranks in (1, 2, 3):
        out = os.path.join(OUT, '%s_np%d' % (analysis, ranks))
        rc, text = run(deck, out, ranks=ranks)
        checks.check(rc == 0, '%s on %d rank(s): runs' % (analysis, ranks), text[-500:])
        if rc != 0:
            continue
        with h5py.File(os.path.join(out, 'one_tet_%s.h5' % analysis), 'r') as h:
            last = sorted(h['states'].keys())[-1]
            state = h['states'][last]
            results[ranks] = (len(h['states']),
                              np.array(state['point']['displacement'])
                              if 'displacement' in state['point'] else None,
                              np.array(state['cell']['stress']) if 'stress' in state['cell']
                              else None)
    if analysis == 'none' or 1 not in results:
        continue
    one = results[1]
    checks.check(one[1] is not None and np.abs(one[1]).max() > 0, '%s: the tet moves'
                 % analysis, '')
    for ranks in (2, 3):
        if ranks not in results:
            continue
        other = results[ranks]
        # the implicit solves differ by round-off with the rank count (MUMPS; README)
        same = other[0] == one[0] and np.allclose(other[1], one[1], rtol=1e-12, atol=0) and \
            np.allclose(other[2], one[2], rtol=1e-12, atol=1e-12 * np.abs(one[2]).max())
        checks.check(same, '%s: %d ranks give the states and results of 1 rank (1e-12)'
                     % (analysis, ranks), '%d vs %d states' % (other[0], one[0]))
checks.exit()
