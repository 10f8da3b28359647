"""Output intervals far below the step must not stall the explicit cycle loop (issue 21: a
*DATABASE_GLSTAT, _NODOUT or _BINARY_D3PLOT DT of 1e-20 ... 1e-300 made the run write its first
record and then spin without progress until killed). A block of 2 x 2 x 2 hexahedra of 6 ME-FEM
tets, 30 cycles (ENDCYC), every output interval tiny: the run ends within the time limit, writes
a state and a glstat and nodout record at every cycle (an interval below the step means
every cycle), and the same deck with the intervals at 0.1 us writes a state every few cycles
with the same final displacements (the schedule changes no result).
The implicit analysis (the punch of input/punch/punch_u1_mefem.k, 80 steps of 0.0125) with a
D3PLOT DT of 1e-12 used to cut every step down to the interval (1 561 states in 30 s); now an
interval below the smallest step the analysis may take (DTMIN, here 1e-6 ENDTIM) writes every
step: 81 states, and the final state is that of
the deck's DT of 0.025 (41 states) up to round-off.
"""
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'verification'))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import ROOT, Checks, f10, nodes_card, elements_card, write_deck
from explicit_cases import box_tets, part_cards, elastic, node_set, history_nodes, OUT
from lsdyna_ascii import read_glstat, read_nodout

TIMEOUT = 120                      # s; the run takes well below a second
CYCLES = 30
checks = Checks('output_schedule')
x, conn = box_tets(2.0, 2.0, 2.0, 2, 2, 2)


def deck(interval):
    return [nodes_card(x), elements_card('ELEMENT_SOLID', conn), part_cards(43, elastic()),
            node_set(1, range(len(x))),
            ['*INITIAL_VELOCITY', f10(1), f10(1000.0, -500.0, 250.0)],
            ['*CONTROL_TERMINATION', f10(0.0, CYCLES),
             '*DATABASE_BINARY_D3PLOT', f10(interval), '*DATABASE_GLSTAT', f10(interval),
             '*DATABASE_NODOUT', f10(interval)],
            history_nodes([0, len(x) - 1])]


def run(name, interval):
    path = os.path.join(OUT, name + '.k')
    write_deck(path, deck(interval), title=name)
    out = os.path.join(OUT, name)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
    try:
        p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '-o', out, path], cwd=ROOT,
                           capture_output=True, text=True, env=env, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, 'no end within %d s' % TIMEOUT, out
    return p.returncode, p.stdout + p.stderr, out


def final_displacement(out, name):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        steps = f['time_history/step'][()]
        return len(steps), f['states/%06d/point/displacement' % steps[-1]][()]


results = {}
for name, interval in (('schedule_1e-20', 1.0e-20), ('schedule_1e-300', 1.0e-300),
                       ('schedule_0.1us', 1.0e-7)):
    rc, text, out = run(name, interval)
    checks.check(rc == 0, '%s: the run ends (exit 0 within %d s)' % (name, TIMEOUT),
                 text[-600:])
    if rc != 0:
        continue
    # one warning per keyword, naming its line: the interval is below the step
    warned = [kw for kw in ('*DATABASE_BINARY_D3PLOT', '*DATABASE_GLSTAT', '*DATABASE_NODOUT')
              if re.search(r'%s\.k:\d+: \%s: DT = \S+ s is below the first time step '
                           r'\(\S+ s\): a .* is written every cycle' % (re.escape(name), kw), text)]
    if interval < 1.0e-9:
        checks.check(len(warned) == 3, '%s: a warning with the line of each of the 3 '
                     'intervals' % name, text[-800:])
    else:
        checks.check(len(warned) == 0 and 'is below the first time step' not in text,
                     '%s: no warning for an interval above the step' % name, text[-800:])
    states, u = final_displacement(out, name)
    records = len(read_glstat(os.path.join(out, 'glstat'))['time'])
    blocks = len(read_nodout(os.path.join(out, 'nodout'))['time'])
    results[name] = (states, records, blocks, u)
    print('    %s: %d states, %d glstat records, %d nodout blocks' % (name, states, records,
                                                                      blocks))
for name in ('schedule_1e-20', 'schedule_1e-300'):
    if name in results:
        states, records, blocks, _ = results[name]
        checks.check(states == CYCLES + 1 and records == CYCLES + 1 and blocks == CYCLES + 1,
                     '%s: a state, a glstat record and a nodout block at t = 0 and every cycle'
                     % name, '%d, %d, %d (expected %d)' % (states, records, blocks, CYCLES + 1))
if len(results) == 3:
    u_tiny, u_regular = results['schedule_1e-20'][3], results['schedule_0.1us'][3]
    checks.check(results['schedule_0.1us'][0] < CYCLES and np.array_equal(u_tiny, u_regular),
                 'the output schedule changes no result (final displacements the same bits)',
                 'states %d' % results['schedule_0.1us'][0])

# ---- implicit: the punch with DT = 1e-12 and with the deck's 0.025 -----------------------
punch_dir = os.path.join(OUT, 'schedule_punch')
os.makedirs(punch_dir, exist_ok=True)
for f in ('mesh_u1.k', 'punch_tool.k'):
    shutil.copy(os.path.join(ROOT, 'input', 'punch', f), punch_dir)
with open(os.path.join(ROOT, 'input', 'punch', 'punch_u1_mefem.k')) as f:
    original = f.read()
assert '*DATABASE_BINARY_D3PLOT\n     0.025\n' in original
finals = {}
for name, dt in (('punch_tiny', '     1e-12'), ('punch_regular', '     0.025')):
    path = os.path.join(punch_dir, name + '.k')
    with open(path, 'w') as f:
        f.write(original.replace('*DATABASE_BINARY_D3PLOT\n     0.025\n',
                                 '*DATABASE_BINARY_D3PLOT\n%s\n' % dt))
    out = os.path.join(punch_dir, name)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
    try:
        p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '-o', out, path],
                           cwd=punch_dir, capture_output=True, text=True, env=env,
                           timeout=300)
        rc, text = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        rc, text = None, 'no end within 300 s'
    checks.check(rc == 0, 'implicit %s: the run ends (exit 0 within 300 s)' % name, text[-600:])
    if rc == 0:
        steps = len(re.findall(r'^step \d+: t = ', text, re.M))    # the converged steps
        finals[name] = (steps,) + final_displacement(out, name)
        warned = re.search(r'%s\.k:\d+: \*DATABASE_BINARY_D3PLOT: DT = \S+ s is below the '
                           r'smallest step, DTMIN, \(\S+ s\): a result state is written '
                           r'every step' % name, text)
        checks.check(bool(warned) == (name == 'punch_tiny'), 'implicit %s: a warning with the '
                     'line of D3PLOT exactly when its DT is below DTMIN' % name, text[-600:])
if len(finals) == 2:
    (steps_tiny, states_tiny, u_tiny), (steps_regular, states_regular, u_regular) = (
        finals['punch_tiny'], finals['punch_regular'])
    print('    implicit punch: DT 1e-12: %d steps, %d states; DT 0.025: %d steps, %d states' % (
        steps_tiny, states_tiny, steps_regular, states_regular))
    checks.check(steps_tiny == steps_regular and states_tiny == steps_tiny + 1,
                 'implicit: an output interval below DTMIN writes every step and cuts no '
                 'step', '%d steps (%d with DT 0.025), %d states' % (steps_tiny, steps_regular,
                                                                     states_tiny))
    # landing on the output times of 0.025 makes the steps next_output - t instead of 0.0125,
    # equal up to round-off: measured 3.6e-15 of the largest displacement
    diff = np.max(abs(u_tiny - u_regular)) / np.max(abs(u_regular))
    checks.check(diff < 1e-12, 'implicit: the output interval changes no result (final '
                 'displacements within 1e-12)', '%.2e' % diff)
checks.exit()
