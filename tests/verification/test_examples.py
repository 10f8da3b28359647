"""The shipped main example states facts in its comments; they must hold (issue 25):
- input/main_example.k is what input/generate_main_example.py writes (with the options its
  header names);
- the rigid plates touch the billet from the start: their mid-surfaces, mefem's contact
  surfaces, lie on the billet's end faces (no gap);
- mass scaling adds no more than the comment says (glstat "percentage increase" after 20
  cycles, and the run log's line at the start).
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, ROOT, run
from lsdyna_ascii import read_glstat

sys.path.insert(0, os.path.join(ROOT, 'input'))
import generate_main_example as gme  # noqa: E402

checks = Checks('examples')
OUT = os.path.join(ROOT, 'tests', 'out', 'examples')
os.makedirs(OUT, exist_ok=True)
DECK = os.path.join(ROOT, 'input', 'main_example.k')
text = open(DECK).read()

# the deck is the generator's
options = re.search(r'python3 input/generate_main_example\.py (.*)', text).group(1).split()
fresh = os.path.join(OUT, 'main_example_regenerated.k')
p = subprocess.run([sys.executable, os.path.join(ROOT, 'input', 'generate_main_example.py'),
                    '--output', fresh] + options, capture_output=True, text=True)
checks.check(p.returncode == 0 and open(fresh).read() == text, 'main example: the deck is '
             'what its generator writes (%s)' % ' '.join(options), p.stderr[-300:])

# the plates on the billet's end faces
nodes = {}
block = text.split('*NODE', 1)[1].split('*', 1)[0]
for line in block.splitlines():
    if line.startswith('$') or not line.strip():
        continue
    nodes[int(line[0:8])] = float(line[40:56])
z_billet = np.array([z for n, z in nodes.items() if n < gme.BOTTOM_NODE0])
z_bottom = np.array([z for n, z in nodes.items() if gme.BOTTOM_NODE0 <= n < gme.TOP_NODE0])
z_top = np.array([z for n, z in nodes.items() if n >= gme.TOP_NODE0])
gaps = (z_billet.min() - z_bottom.max(), z_top.min() - z_billet.max())
print('    main example: gaps between the plates and the billet %.3g mm (bottom), %.3g mm (top)'
      % gaps)
checks.check(max(abs(g) for g in gaps) < 1e-9, 'main example: the plates touch the billet '
             '(no gap between their mid-surfaces and its end faces)', '%s' % (gaps,))

# the added mass: at most what the comment states
stated = float(re.search(r'mefem adds (\S+) % of the billet', text).group(1))
short = os.path.join(OUT, 'main_example_20.k')
lines = text.splitlines()
k = lines.index('*CONTROL_TERMINATION') + 1
while lines[k].startswith('$'):
    k += 1
lines[k] = lines[k][:10] + '%10d' % 20 + lines[k][20:]        # ENDCYC = 20
open(short, 'w').write('\n'.join(lines) + '\n')
rc, log = run(short, os.path.join(OUT, 'main_example_20'))
checks.check(rc == 0, 'main example, 20 cycles: the run succeeds', log[-500:])
if rc == 0:
    added = read_glstat(os.path.join(OUT, 'main_example_20', 'glstat'))['percentage increase']
    logged = float(re.search(r'mass scaling adds \S+ at the start \((\S+) %', log).group(1))
    print('    main example: added mass %.2f %% (glstat), %.2f %% (log), the comment says %g %%'
          % (added.max(), logged, stated))
    checks.check(added.max() <= stated and abs(logged - added[0]) < 1e-3 * stated,
                 'main example: mass scaling adds no more than its comment says, and the log '
                 'says how much', '%.3f %.3f %g' % (added.max(), logged, stated))
checks.exit()
