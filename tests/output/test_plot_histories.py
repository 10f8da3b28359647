"""post/plot_histories.py on a run with every history file: a block pressed onto a rigid plate
(contact, rigid part, history node, glstat) for a short time; the script must write one PNG
per history file, answer --help, and refuse a directory without histories.
"""
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks                                            # noqa: E402
from explicit_cases import all_histories_blocks, run_case, OUT             # noqa: E402

checks = Checks('plot_histories')
SCRIPT = os.path.join(ROOT, 'post', 'plot_histories.py')
blocks = all_histories_blocks(2.0e-4)
rc, text, out = run_case('plot_histories', blocks)
checks.check(rc == 0, 'the run succeeds', text[-600:])
if rc == 0:
    figures = os.path.join(OUT, 'plot_histories_figures')
    run = subprocess.run([sys.executable, SCRIPT, out, '--out', figures], capture_output=True,
                         text=True)
    checks.check(run.returncode == 0, 'plot_histories.py runs on the results',
                 run.stdout + run.stderr)
    for name in ('energies', 'contact_forces', 'wall_forces', 'rigid_bodies', 'nodes'):
        path = os.path.join(figures, name + '.png')
        ok = os.path.exists(path) and os.path.getsize(path) > 5000
        if ok:
            with open(path, 'rb') as f:
                ok = f.read(8) == b'\x89PNG\r\n\x1a\n'
        checks.check(ok, 'writes %s.png (a PNG of more than 5 kB)' % name, path)
run = subprocess.run([sys.executable, SCRIPT, '--help'], capture_output=True, text=True)
checks.check(run.returncode == 0 and 'RESULTS_DIR' in run.stdout, '--help prints the usage',
             run.stdout[-300:])
run = subprocess.run([sys.executable, SCRIPT, ROOT], capture_output=True, text=True)
checks.check(run.returncode != 0 and 'no history file' in run.stderr, 'a directory without '
             'histories is refused with a message', run.stderr[-300:])
checks.exit()
