"""The cap on printed input errors (src/util/errors.f90): a deck with 1 240 errors (600 solid
elements naming an undefined node and an undefined part, 40 SPCs on undefined nodes) prints the
first 500, says that the rest are counted, and then lists the unprinted ones by keyword: their
counts add up to the total less 500, under the keywords that have them; the total is right.
"""
import os
import re
import subprocess
import sys

ROOT = os.environ.get('MEFEM_ROOT', os.path.join(os.path.dirname(__file__), '..', '..'))
OUT = os.path.join(ROOT, 'tests', 'out', 'decks')
os.makedirs(OUT, exist_ok=True)
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('error cap')
check = checks.check


lines = ['*KEYWORD', '*NODE'] + ['%8d%16.1f%16.1f%16.1f' % (i, i, 0.0, 0.0) for i in range(1, 11)]
lines += ['*ELEMENT_SOLID'] + ['%8d%8d%8d%8d%8d%8d' % (i, 1, 1, 2, 3, 99) for i in range(1, 601)]
lines += ['*BOUNDARY_SPC_NODE'] + ['%10d%10d%10d' % (1000 + i, 0, 1) for i in range(40)]
lines += ['*END']
deck = os.path.join(OUT, 'error_cap.k')
with open(deck, 'w') as f:
    f.write('\n'.join(lines) + '\n')
run = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '--check', deck],
                     capture_output=True, text=True)
text = run.stdout + run.stderr
printed = [l for l in text.splitlines() if l.startswith(deck + ':') and 'input error(s)' not in l]
total = re.search(r'(\d+) input error\(s\)', text)
counts = re.findall(r'^  (\d+) at (\*\S+)$', text, re.M)
check(run.returncode == 1 and total is not None and int(total.group(1)) == 1240,
      'the total is 1 240 (600 x 2 element errors, 40 SPCs)', text[-300:])
check(len(printed) == 500 and 'further input errors are counted but not printed' in text,
      '500 errors printed, then the notice', '%d printed' % len(printed))
check(sum(int(n) for n, _ in counts) == 740 and
      {k for _, k in counts} <= {'*ELEMENT_SOLID', '*BOUNDARY_SPC_NODE'} and len(counts) > 0,
      'the unprinted errors by keyword add up to 740: %s' % ', '.join('%s at %s' % c for c in counts),
      text[-400:])
checks.exit()
