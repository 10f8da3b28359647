"""*SET_NODE_LIST_GENERATE (issue 21): a set is every defined node whose id lies in one of its
ranges, once, in ascending id order; its memory follows the nodes, not the ranges' width.

1. Overlapping ranges over a gap in the numbering (1-1002, 1000-1003, 3-3 over nodes 1-4 and
   1001-1004) as the history nodes of an explicit run: nodout lists 1, 2, 3, 4, 1001, 1002,
   1003, each once.
2. 2 000 cards of four ranges up to 2e9 ids each: `--check` accepts it within 10 s and 100 MiB
   (when the ranges were expanded id by id, 28 such cards took 3.5 GB).
3. *SET_NODE_GENERAL (issue 23): PART 2, NODE 1 3, DNODE 1002 gives 1 3 1001 1003 1004; ALL,
   DSET (that set) gives 2 4 1002 (nodout of an explicit run lists a history set's nodes).
4. *SET_PART_GENERAL: ALL, DPART 2 as the parts of *LOAD_BODY_PARTS: gravity moves part 1's
   nodes at -g t and leaves part 2's at rest.
"""
import os
import re
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
sys.path.insert(0, os.path.join(ROOT, 'post'))
from deck_writer import Checks, write_deck, run  # noqa: E402
from lsdyna_ascii import read_nodout  # noqa: E402

checks = Checks('generated_sets')
OUT = os.path.join(ROOT, 'tests', 'out', 'generated_sets')
NODES = ['*NODE', '1,0.0,0.0,0.0', '2,1.0,0.0,0.0', '3,0.0,1.0,0.0', '4,0.0,0.0,1.0',
         '1001,1.0,1.0,1.0', '1002,2.0,1.0,1.0', '1003,1.0,2.0,1.0', '1004,1.0,1.0,2.0',
         '*ELEMENT_SOLID', '1,1,1,2,3,4', '2,1,1001,1002,1003,1004', '*PART', 'tets', '1,1,1',
         '*SECTION_SOLID', '1,10', '*MAT_ELASTIC', '1,7.85e-9,210000.0,0.3']

deck = os.path.join(OUT, 'overlapping.k')
write_deck(deck, [NODES, ['*SET_NODE_LIST_GENERATE', '5', '1,1002,1000,1003,3,3',
                          '*DATABASE_HISTORY_NODE_SET', '5', '*INITIAL_VELOCITY', '0',
                          '0.0,0.0,-1000.0', '*CONTROL_TERMINATION', '1.0e-7',
                          '*DATABASE_NODOUT', '1.0e-7']], title='generated set')
rc, text = run(deck, os.path.join(OUT, 'overlapping'))
checks.check(rc == 0, 'overlapping ranges: the run succeeds', text[-500:])
if rc == 0:
    ids = list(read_nodout(os.path.join(OUT, 'overlapping', 'nodout'))['ids'])
    checks.check(ids == [1, 2, 3, 4, 1001, 1002, 1003], 'overlapping ranges over a gap: the '
                 'defined nodes in them, once each, ascending', 'nodout ids %s' % ids)

deck = os.path.join(OUT, 'wide_ranges.k')
cards = ['%d,%d,%d,%d,%d,%d,%d,%d' % (1, 1000000000 + k, 5, 2000000000, 3, 1500000000,
                                       1001, 1900000000) for k in range(2000)]
write_deck(deck, [NODES, ['*SET_NODE_LIST_GENERATE', '7'] + cards,
                  ['*BOUNDARY_SPC_SET', '7,0,1,1,1']], title='wide ranges')
try:
    p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '--check', deck],
                       capture_output=True, text=True, timeout=10,
                       env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1',
                                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1'))
    peak = re.search(r'peak memory ([0-9.eE+-]+) MiB per rank', p.stdout + p.stderr)
    peak_mib = float(peak.group(1)) if peak else float('nan')
    print('    2 000 cards of ranges up to 2e9 ids: exit %d, peak memory %.1f MiB'
          % (p.returncode, peak_mib))
    checks.check(p.returncode == 0 and peak_mib < 100, 'wide ranges: accepted within 10 s '
                 'and 100 MiB', 'exit %d, %.1f MiB: %s' % (p.returncode, peak_mib,
                                                         (p.stdout + p.stderr)[-300:]))
except subprocess.TimeoutExpired:
    checks.check(False, 'wide ranges: accepted within 10 s', 'no end within 10 s')

# ---- 3. *SET_NODE_GENERAL ---------------------------------------------------------------------
TWO_PARTS = NODES[:NODES.index('*ELEMENT_SOLID')] + [
    '*ELEMENT_SOLID', '1,1,1,2,3,4', '2,2,1001,1002,1003,1004', '*PART', 'one', '1,1,1',
    '*PART', 'two', '2,1,1', '*SECTION_SOLID', '1,10', '*MAT_ELASTIC', '1,7.85e-9,210000.0,0.3']
GENERAL = ['*SET_NODE_GENERAL', '8', 'PART,2', 'NODE,1,3', 'DNODE,1002',
           '*SET_NODE_GENERAL_TITLE', 'the rest', '9', 'ALL', 'DSET,8']
for sid, expected in ((8, [1, 3, 1001, 1003, 1004]), (9, [2, 4, 1002])):
    deck = os.path.join(OUT, 'general_%d.k' % sid)
    write_deck(deck, [TWO_PARTS, GENERAL, ['*DATABASE_HISTORY_NODE_SET', str(sid),
                                           '*INITIAL_VELOCITY', '0', '0.0,0.0,-1000.0',
                                           '*CONTROL_TERMINATION', '1.0e-7',
                                           '*DATABASE_NODOUT', '1.0e-7']], title='general set')
    rc, text = run(deck, os.path.join(OUT, 'general_%d' % sid))
    checks.check(rc == 0, '*SET_NODE_GENERAL %d: the run succeeds' % sid, text[-500:])
    if rc == 0:
        ids = list(read_nodout(os.path.join(OUT, 'general_%d' % sid, 'nodout'))['ids'])
        checks.check(ids == expected, '*SET_NODE_GENERAL %d: its entries in order (PART, '
                     'NODE, DNODE; ALL, DSET)' % sid, 'nodout ids %s' % ids)

# ---- 4. *SET_PART_GENERAL ---------------------------------------------------------------------
G = 9810.0                                                        # mm/s^2
deck = os.path.join(OUT, 'general_parts.k')
write_deck(deck, [TWO_PARTS, ['*SET_PART_GENERAL', '7', 'ALL', 'DPART,2',
                              '*LOAD_BODY_Z', '1,1.0', '*LOAD_BODY_PARTS', '7',
                              '*DEFINE_CURVE', '1', '0.0,%g' % G, '1.0,%g' % G,
                              '*DATABASE_HISTORY_NODE', '1,2,1001,1002',
                              '*CONTROL_TERMINATION', '1.0e-6', '*DATABASE_NODOUT', '1.0e-6']],
           title='general part set')
rc, text = run(deck, os.path.join(OUT, 'general_parts'))
checks.check(rc == 0, '*SET_PART_GENERAL: the run succeeds', text[-500:])
if rc == 0:
    n = read_nodout(os.path.join(OUT, 'general_parts', 'nodout'))
    vz = n['z-vel'][-1]
    t = n['time'][-1]
    ids = list(n['ids'])
    print('    *SET_PART_GENERAL ALL, DPART 2 loaded by gravity: z velocities %s at t = %.1e s '
          '(-g t = %.4e)' % (dict(zip(ids, np.round(vz, 6))), t, -G * t))
    checks.check(np.allclose(vz[:2], -G * t, rtol=1e-9) and np.all(vz[2:] == 0.0),
                 '*SET_PART_GENERAL: ALL, DPART 2 holds part 1 only (gravity moves it alone)',
                 'z velocities %s' % vz)
checks.exit()
