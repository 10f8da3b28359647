"""post/plot_histories.py on a run with every history file: a block pressed onto a rigid plate
(contact, rigid part, history node, glstat) for a short time; the script must write one PNG
per history file, answer --help, and refuse a directory without histories.
"""
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks, f10                                       # noqa: E402
from explicit_cases import (curve, run_case, face_segments, smooth_ramp,  # noqa: E402
                            block_on_plate, block_on_plate_cards, OUT)

checks = Checks('plot_histories')
SCRIPT = os.path.join(ROOT, 'post', 'plot_histories.py')
x, cb, quads, nb = block_on_plate(0.0)
probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))
blocks = block_on_plate_cards(x, cb, quads, 1.0e-9, 1000.0, 0.3) + [
    face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
    curve(1, smooth_ramp(2.0e-4, 10.0) + [(1.0, 10.0)]),
    ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), '', ''],
    ['*RIGIDWALL_PLANAR', f10(0), f10(0.0, 0.0, -1.0, 0.0, 0.0, 0.0)],
    ['*CONTROL_TERMINATION', f10(2.0e-4), '*DATABASE_BINARY_D3PLOT', f10(2.0e-4),
     '*DATABASE_GLSTAT', f10(1.0e-5), '*DATABASE_RCFORC', f10(1.0e-5),
     '*DATABASE_NODOUT', f10(1.0e-5), '*DATABASE_HISTORY_NODE', f10(probe + 1)]]
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
