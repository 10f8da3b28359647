"""Restart of the explicit analysis (*DATABASE_BINARY_D3DUMP, *DATABASE_BINARY_RUNRSF, d3kil
sw1/sw3, `mefem r=FILE`; doc/keywords.md 3.11, doc/theory.md 6.8): a run continued from a
restart file gives the bits of the run that was never stopped, on the same and on another
number of ranks, and its output reads as if it had never stopped. Units: mm, t, s, N, MPa.

Each case runs whole on 2 ranks with a restart file every N cycles; its output directory is
then copied and the run continued from its first restart file (d3dump01) on 1, 2 and 3 ranks.
Checked against the whole run: every field of every result state of the HDF5 file (the same
bits), the states the .pvd lists (their times), the ASCII histories (the same lines; the
numbers within 1e-10 of their quantity's largest in the file, as the energy sums over the ranks
add in another order after a restart).

1. Taylor bar (input/taylor_bar.k, ME-FEM tets, J2 plasticity, rigid wall, initial velocity,
   nodout and rwforc), 15 us; and continued from its last restart file (written at its end)
   with a deck whose ENDTIM is 20 us: it runs on to 20 us. With NPLTC = 3 instead of CYCL, the
   restart files come at 5, 10 and 15 us, and the run continued from the second ends as the
   whole one.
2. Sliding block with friction: the block pressed onto a rigid plate (a rigid body, rbdout)
   and pulled sideways, FS = 0.3 (the friction's tractions carry over), the contact work
   divided among the ranks (MEFEM_CONTACT_DIVIDE_MIN = 0), selective mass scaling (DT2MS < 0:
   the added masses carry over), a rigid wall, rcforc; and the same with the nodal-pressure
   tetrahedron (ELFORM 13).
   A tiebreak (test_contact_tied's shear case) whose nodes are released during the run, then
   held by the companion contact.
3. Eroding contact: hexahedra (ELFORM 1, hourglass energy) whose top layer erodes, a rigid
   punch with a prescribed velocity meeting the exposed faces; restarts before and after the
   erosion.
4. A run killed (SIGKILL) while it runs is continued from the last restart file it left, and
   one stopped by SIGTERM from the restart file it writes when stopping: the same bits at the
   end.
5. d3kil sw1 stops a run with a restart file, sw3 writes one and goes on; *DATABASE_BINARY_RUNRSF
   keeps one file (runrsf), overwritten.
6. Wrong use: a restart file of another deck, a missing one, a cut one, an explicit one for an
   implicit deck, a bad CYCL: a message, no analysis.
7. The nonlinear implicit analysis (restart files every CYCL steps): the seed punch continued
   after steps 20 and 60 on 1 rank (the same bits), from a 2-rank run on 2 and 3 ranks (within
   1e-9: MUMPS's parallel sums vary from run to run), and a tool sliding with friction.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, ROOT, MPIRUN, f10, free, nodes_card, elements_card, write_deck
from explicit_cases import (OUT, curve, face_segments, node_set, smooth_ramp, block_on_plate,
                            block_on_plate_cards, eroding_punch_blocks, ERODING_PUNCH)
from tied_cases import tiebreak_shear_blocks
from implicit_cases import tool_block_deck

checks = Checks('restart')
EXE = os.path.join(ROOT, 'bin', 'mefem')
WORK = os.path.join(OUT, 'restart')
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1', OPENBLAS_NUM_THREADS='1',
           MEFEM_CONTACT_DIVIDE_MIN='0')
HISTORIES = ['glstat', 'nodout', 'rcforc', 'rwforc', 'rbdout']


def mefem(args, ranks=1, cwd=WORK):
    """Run mefem with the arguments; (exit code, output)."""
    command = [EXE] + args
    if ranks > 1:
        command = MPIRUN + ['-np', str(ranks)] + command
    done = subprocess.run(command, cwd=cwd, env=ENV, capture_output=True, text=True,
                          timeout=600)
    return done.returncode, done.stdout + done.stderr


def states(h5path):
    """{state: {field: array}} of every result state of an HDF5 file (rows by node/cell id)."""
    out = {}
    with h5py.File(h5path, 'r') as f:
        for name in f['states']:
            g = f['states'][name]
            out[name] = {k: g['point'][k][()] for k in g['point']}
            out[name].update({'cell/' + k: g['cell'][k][()] for k in g['cell']})
            out[name]['time'] = g.attrs['time']
        out['steps'] = f['time_history/step'][()]
    return out


def pvd_times(path):
    with open(path) as f:
        return [float(t) for t in re.findall(r'timestep="([^"]+)"', f.read())]


NUMBER = re.compile(r'[-+]?\d+\.\d*[eE][-+]?\d+')


def quantity(line):
    """What a history line's numbers are: its words (the three components of glstat's global
    velocity count as one quantity)."""
    return re.sub(r'global [xyz] velocity', 'global velocity', NUMBER.sub('#', line))


def histories_agree(a, b, tolerance=1e-10):
    """'' when the history files of two output directories agree: the same lines and words,
    each number within `tolerance` of the largest magnitude its quantity (the words before it on
    its line) has in the file; else what differs."""
    for name in HISTORIES:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if os.path.exists(pa) != os.path.exists(pb):
            return name + ': in one directory only'
        if not os.path.exists(pa):
            continue
        la, lb = open(pa).read().splitlines(), open(pb).read().splitlines()
        if len(la) != len(lb):
            return '%s: %d lines against %d' % (name, len(la), len(lb))
        scale = {}
        for line in la:
            key = quantity(line)
            values = [abs(float(v)) for v in NUMBER.findall(line)]
            if values:
                scale[key] = max(scale.get(key, 0.0), max(values))
        for k, (x, y) in enumerate(zip(la, lb)):
            if k < 3 and name in ('glstat', 'nodout'):   # banner with the date
                continue
            key = quantity(x)
            if NUMBER.sub('#', x) != NUMBER.sub('#', y):
                return '%s line %d: "%s" against "%s"' % (name, k + 1, x, y)
            u = np.array([float(v) for v in NUMBER.findall(x)])
            v = np.array([float(v) for v in NUMBER.findall(y)])
            if len(u) and np.abs(u - v).max() > tolerance * scale[key]:
                return '%s line %d: "%s" against "%s"' % (name, k + 1, x, y)
    return ''


def results_agree(whole, other, tolerance=0.0):
    """'' when two output directories hold the same results (with a tolerance: each field
    within it of the field's largest magnitude), else what differs."""
    sa, sb = states(os.path.join(whole, STEM + '.h5')), states(os.path.join(other, STEM + '.h5'))
    if sorted(sa) != sorted(sb) or not np.array_equal(sa['steps'], sb['steps']):
        return 'states %s against %s' % (sorted(sa), sorted(sb))
    for state in sa:
        if state == 'steps':
            continue
        for field, value in sa[state].items():
            other_value = sb[state][field]
            if tolerance == 0.0 and not np.array_equal(value, other_value):
                return 'state %s, %s: %.3e apart' % (state, field,
                                                     np.abs(value - other_value).max())
            if tolerance > 0.0 and np.abs(value - other_value).max() > \
                    tolerance * max(np.abs(value).max(), 1e-300):
                return 'state %s, %s: %.3e apart' % (state, field,
                                                     np.abs(value - other_value).max())
    if pvd_times(os.path.join(whole, STEM + '.pvd')) != pvd_times(os.path.join(other,
                                                                            STEM + '.pvd')):
        return '.pvd states differ'
    return histories_agree(whole, other, max(tolerance, 1e-10))


STEM = 'case'


def restart_case(name, blocks, dump_cycles, restart_ranks=(1, 2, 3), dumps=('d3dump01',),
                 whole_ranks=2, tolerance=0.0):
    """Run a deck whole (on whole_ranks) with restart files, continue copies of its output
    from each restart file named on each number of ranks and compare (results_agree)."""
    deck = os.path.join(WORK, name, STEM + '.k')
    write_deck(deck, blocks + [['*DATABASE_BINARY_D3DUMP', f10(dump_cycles)]], title=name)
    whole = os.path.join(WORK, name, 'whole')
    shutil.rmtree(whole, ignore_errors=True)
    rc, text = mefem(['-o', whole, deck], ranks=whole_ranks)
    checks.check(rc == 0 and all(os.path.exists(os.path.join(whole, d)) for d in dumps),
                 '%s: the whole run writes %s' % (name, ', '.join(dumps)), text[-800:])
    if rc != 0:
        return None, text
    for dump in dumps:
        for ranks in restart_ranks:
            copy = os.path.join(WORK, name, 'from_%s_on_%d' % (dump, ranks))
            shutil.rmtree(copy, ignore_errors=True)
            shutil.copytree(whole, copy)
            rc, out = mefem(['r=' + os.path.join(copy, dump)], ranks=ranks)
            ok = rc == 0 and 'restarted from' in out
            checks.check(ok, '%s: continued from %s on %d rank(s)' % (name, dump, ranks),
                         out[-800:])
            if ok:
                why = results_agree(whole, copy, tolerance)
                checks.check(why == '', '%s: from %s on %d rank(s): every state, the .pvd and '
                             'the histories as the whole run%s' % (
                                 name, dump, ranks, ' (within %g)' % tolerance if tolerance
                                 else ''), why)
    return whole, text


# ---- 1. Taylor bar --------------------------------------------------------------------------
with open(os.path.join(ROOT, 'input', 'taylor_bar.k')) as f:
    bar = f.read().replace('\n     6e-05\n', '\n    1.5e-5\n').replace('*END\n', '')
checks.check('1.5e-5' in bar, 'Taylor bar: deck shortened to 15 us')
bar_blocks = [bar.splitlines()[3:]]          # (write_deck adds *KEYWORD and the title)
restart_case('taylor_bar', bar_blocks, 100)

# a run goes on past its ENDTIM from its last restart file, with a deck that asks for more
longer = os.path.join(WORK, 'taylor_bar', 'longer.k')
write_deck(longer, [[line.replace('    1.5e-5', '    2.0e-5') for line in bar_blocks[0]],
                    ['*DATABASE_BINARY_D3DUMP', f10(100)]], title='taylor_bar')
dumps = sorted(d for d in os.listdir(os.path.join(WORK, 'taylor_bar', 'whole'))
               if re.fullmatch(r'd3dump\d+', d))
extended = os.path.join(WORK, 'taylor_bar', 'extended')
shutil.rmtree(extended, ignore_errors=True)
shutil.copytree(os.path.join(WORK, 'taylor_bar', 'whole'), extended)
rc, text = mefem(['r=' + os.path.join(extended, dumps[-1]), longer], ranks=2)
times = pvd_times(os.path.join(extended, STEM + '.pvd'))
checks.check(rc == 0 and 'time reached 2.00000E-05' in text and len(times) == 5 and
             abs(times[-1] - 2.0e-5) < 1e-12 and abs(times[3] - 1.5e-5) < 1e-12,
             'Taylor bar: continued from its last restart file (%s, t = 15 us) with ENDTIM 20 us: '
             'runs to 20 us, states at 0, 5, 10, 15, 20 us' % dumps[-1], str(times) + text[-400:])

# NPLTC: restart files at ENDTIM / NPLTC (5, 10, 15 us), the run continued from the second
npltc_blocks = [bar_blocks[0], ['*DATABASE_BINARY_D3DUMP', f10(0, 0, 0, 3)]]
deck = os.path.join(WORK, 'npltc', STEM + '.k')
write_deck(deck, npltc_blocks, title='npltc')
whole = os.path.join(WORK, 'npltc', 'whole')
shutil.rmtree(whole, ignore_errors=True)
rc, text = mefem(['-o', whole, deck], ranks=2)
at = [float(v) for v in re.findall(r'restart file d3dump\d+ written at cycle \d+, t = (\S+)',
                                   text)]
checks.check(rc == 0 and len(at) == 3 and abs(at[0] - 5e-6) < 1e-7 and
             abs(at[1] - 1e-5) < 1e-7 and at[2] == 1.5e-5,
             'NPLTC 3: restart files at the first cycles past 5, 10 and 15 us', str(at))
if rc == 0:
    copy = os.path.join(WORK, 'npltc', 'from_d3dump02')
    shutil.rmtree(copy, ignore_errors=True)
    shutil.copytree(whole, copy)
    rc, text = mefem(['r=' + os.path.join(copy, 'd3dump02')], ranks=3)
    why = results_agree(whole, copy) if rc == 0 else text[-600:]
    checks.check(why == '' and 'restart file d3dump03 written' in text,
                 'NPLTC 3: continued from d3dump02 on 3 ranks: the same results, d3dump03 at '
                 'the end', why)

# ---- 2. sliding block with friction, mass scaling, rigid plate and wall -----------------------
T1, T2, P, MU = 5.0e-5, 2.0e-4, 10.0, 0.3
x, cb, quads, nb = block_on_plate(0.0)
top = np.nonzero(abs(x[:nb, 2] - 0.5) < 1e-9)[0]
probe = int(np.argmin(np.linalg.norm(x[:nb] - [1.5, 1.5, 0.0], axis=1)))


def sliding(elform):
    cards = block_on_plate_cards(x, cb, quads, 1.0e-9, 1000.0, 0.3)
    cards[3] = [line.replace(f10(1, 43), f10(1, elform)) for line in cards[3]]
    return cards + [
        face_segments(x, cb, 2, 0.5, 1, 9), ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
        curve(1, smooth_ramp(T1, P) + [(1.0, P)]),
        node_set(5, top), ['*LOAD_NODE_SET', f10(5, 1, 2, 1.0 / len(top))],
        curve(2, [(0.0, 0.0), (T1, 0.0), (T1 + T2, 2 * MU * P), (1.0, 2 * MU * P)]),
        ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3), f10(MU, MU),
         f10(1.0, 1.0)],
        ['*RIGIDWALL_PLANAR', f10(0), f10(0.0, 0.0, -0.01, 0.0, 0.0, 0.0)],
        ['*CONTROL_TIMESTEP', f10(0.0, 0.9, 0, 0.0, -2.0e-7)],
        ['*CONTROL_TERMINATION', f10(T1 + 0.4 * T2), '*DATABASE_BINARY_D3PLOT', f10(2.0e-5),
         '*DATABASE_GLSTAT', f10(2.0e-6), '*DATABASE_RCFORC', f10(2.0e-6),
         '*DATABASE_NODOUT', f10(2.0e-6), '*DATABASE_HISTORY_NODE', f10(probe + 1)]]


whole, _ = restart_case('sliding_block', sliding(43), 200)
if whole:
    with open(os.path.join(whole, 'glstat')) as f:
        added = [float(v) for v in re.findall(r'added mass\.*\s+(\S+)', f.read())]
    checks.check(max(added) > 0, 'sliding block: mass scaling adds mass (%.3g)' % max(added))
restart_case('sliding_block_elform13', sliding(13), 200, restart_ranks=(3,))

# ---- 2b. a tiebreak failing in shear, then its companion contact ------------------------------
blocks = tiebreak_shear_blocks()
blocks[-1] += ['*DATABASE_GLSTAT', '  2.0e-6']
whole, text = restart_case('tiebreak', blocks, 462, restart_ranks=(1, 3),
                           dumps=('d3dump01', 'd3dump02'))
released = [float(t) for t in re.findall(r't = (\S+): tiebreak .* released', text)]
dumped = [float(t) for t in re.findall(r'restart file d3dump0[12] written at cycle \d+, '
                                      r't = (\S+)', text)]
checks.check(len(dumped) == 2 and min(released) < dumped[0] < max(released) < dumped[1],
             'tiebreak: d3dump01 written while the ties are released, d3dump02 after',
             '%s %s' % (released, dumped))

# ---- 3. eroding contact, hexahedra ------------------------------------------------------------
T_ERODE = ERODING_PUNCH['t_erode']
eroding = eroding_punch_blocks(['*CONTACT_ERODING_SURFACE_TO_SURFACE', f10(1, 3, 2, 3),
                                f10(0.0), '', f10(0, 1, 1)])
eroding[-1] += ['*DATABASE_GLSTAT', f10(ERODING_PUNCH['end'] / 50)]
whole, _ = restart_case('eroding', eroding, 150)
if whole:
    rc, text = mefem(['-o', os.path.join(WORK, 'eroding', 'probe'),
                      os.path.join(WORK, 'eroding', STEM + '.k')])
    times = [float(t) for t in re.findall(r'written at cycle \d+, t = (\S+)', text)]
    after = [k + 1 for k, t in enumerate(times) if t > T_ERODE]
    checks.check(len(after) >= 2, 'eroding: restart files after the erosion', str(times))
    if len(after) >= 2:
        dump = 'd3dump%02d' % after[0]
        copy = os.path.join(WORK, 'eroding', 'after_erosion')
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(whole, copy)
        rc, text = mefem(['r=' + os.path.join(copy, dump)], ranks=3)
        why = results_agree(whole, copy) if rc == 0 else text[-800:]
        checks.check(why == '', 'eroding: continued from %s (after the erosion) on 3 ranks: '
                     'the same results' % dump, why)

# ---- 4. a killed run ------------------------------------------------------------------------
killed_dir = os.path.join(WORK, 'killed')
shutil.rmtree(killed_dir, ignore_errors=True)
os.makedirs(killed_dir)
with open(os.path.join(ROOT, 'input', 'taylor_bar.k')) as f:
    long_bar = f.read().replace('*END\n', '*DATABASE_BINARY_D3DUMP\n       200\n*END\n')
with open(os.path.join(killed_dir, STEM + '.k'), 'w') as f:
    f.write(long_bar)
rc, text = mefem(['-o', 'whole', STEM + '.k'], cwd=killed_dir)
checks.check(rc == 0, 'killed: the whole 60 us bar runs', text[-600:])
process = subprocess.Popen([EXE, '-o', 'run', STEM + '.k'], cwd=killed_dir, env=ENV,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
start = time.time()
while not os.path.exists(os.path.join(killed_dir, 'run', 'd3dump02')) and \
        process.poll() is None and time.time() - start < 300:
    time.sleep(0.02)
process.send_signal(signal.SIGKILL)
process.wait()
dumps = sorted(d for d in os.listdir(os.path.join(killed_dir, 'run'))
               if re.fullmatch(r'd3dump\d+', d))
checks.check(process.returncode == -signal.SIGKILL and len(dumps) >= 2,
             'killed: the run is killed with restart files on disk (%s)' % dumps)
if dumps:
    rc, text = mefem(['r=' + os.path.join('run', dumps[-1])], ranks=2, cwd=killed_dir)
    why = results_agree(os.path.join(killed_dir, 'whole'), os.path.join(killed_dir, 'run')) \
        if rc == 0 else text[-800:]
    checks.check(why == '', 'killed: continued from its last restart file (%s) on 2 ranks: '
                 'the whole run\'s results' % dumps[-1], why)

# a run stopped by SIGTERM (a batch system's wall-clock limit) writes a restart file
process = subprocess.Popen([EXE, '-o', 'term', STEM + '.k'], cwd=killed_dir, env=ENV,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
start = time.time()
while not os.path.exists(os.path.join(killed_dir, 'term', 'd3dump01')) and \
        process.poll() is None and time.time() - start < 300:
    time.sleep(0.02)
process.send_signal(signal.SIGTERM)
log = process.communicate()[0]
stop = re.search(r'SIGTERM: stopped at cycle (\d+)', log)
written = re.findall(r'restart file (d3dump\d+) written at cycle (\d+)', log)
checks.check(process.returncode == 143 and stop and written and
             written[-1][1] == stop.group(1),
             'SIGTERM: exit 143 with a restart file of the cycle it stopped at', log[-600:])
if written:
    rc, text = mefem(['r=' + os.path.join('term', written[-1][0])], ranks=3, cwd=killed_dir)
    why = results_agree(os.path.join(killed_dir, 'whole'), os.path.join(killed_dir, 'term')) \
        if rc == 0 else text[-800:]
    checks.check(why == '', 'SIGTERM: continued from %s on 3 ranks: the whole run\'s results'
                 % written[-1][0], why)

# ---- 5. sense switches, runrsf ----------------------------------------------------------------
sw = os.path.join(WORK, 'switches')
shutil.rmtree(sw, ignore_errors=True)
os.makedirs(sw)
with open(os.path.join(sw, STEM + '.k'), 'w') as f:
    f.write(long_bar.replace('*DATABASE_BINARY_D3DUMP\n       200\n',
                             '*DATABASE_BINARY_RUNRSF\n       150\n'))
with open(os.path.join(sw, 'd3kil'), 'w') as f:
    f.write('sw1\n')
rc, text = mefem(['-o', 'run', STEM + '.k'], cwd=sw)
checks.check(rc == 0 and 'd3kil (sw1): stopped at cycle 100' in text and
             os.path.exists(os.path.join(sw, 'run', 'd3dump01')),
             'sw1: stops at cycle 100 with the restart file d3dump01', text[-600:])
with open(os.path.join(sw, 'd3kil'), 'w') as f:
    f.write('sw3\n')
rc, text = mefem(['r=run/d3dump01'], cwd=sw)
checks.check(rc == 0 and 'restart file d3dump02 written at cycle 200' in text and
             'restart file runrsf written at cycle 150' in text and
             'restart file runrsf written at cycle 300' in text,
             'sw3 at cycle 200 of the continued run: d3dump02, and runrsf every 150 cycles',
             text[-800:])
rc2, text2 = mefem(['-o', 'whole', STEM + '.k'], cwd=sw)
if rc == 0 and rc2 == 0:
    why = results_agree(os.path.join(sw, 'whole'), os.path.join(sw, 'run'))
    checks.check(why == '', 'sw1 then restart: the results of the run never stopped', why)
    shutil.copytree(os.path.join(sw, 'whole'), os.path.join(sw, 'from_runrsf'))
    rc, text = mefem(['r=from_runrsf/runrsf'], cwd=sw)
    checks.check(rc == 0 and re.search(r'restarted from \S+ at cycle (\d+)', text) and
                 int(re.search(r'restarted from \S+ at cycle (\d+)', text).group(1)) % 150 == 0,
                 'runrsf: the last one kept, at a multiple of 150 cycles', text[-600:])

# ---- 7. the nonlinear implicit analysis ---------------------------------------------------------
# the seed paper's punch (plane strain ME-FEM triangles, J2, a rigid punch in frictionless
# contact; 80 steps): restart files every 20 steps. On 1 rank the continued run gives the
# bits; on several ranks MUMPS's parallel factorisation sums in an order that varies from run
# to run (two whole 2-rank runs differ by 4e-17 in the displacements), so the continued runs
# agree to the same round-off, checked to 1e-9.
with open(os.path.join(ROOT, 'input', 'punch', 'punch_u1_mefem.k')) as f:
    punch = f.read().replace('mesh_u1.k', os.path.join(ROOT, 'input', 'punch', 'mesh_u1.k')) \
        .replace('punch_tool.k', os.path.join(ROOT, 'input', 'punch', 'punch_tool.k')) \
        .replace('*END\n', '*DATABASE_GLSTAT\n    0.0125\n')
punch_blocks = [punch.splitlines()[1:]]
restart_case('implicit_punch', punch_blocks, 20, restart_ranks=(1,), whole_ranks=1,
             dumps=('d3dump01', 'd3dump03'))
restart_case('implicit_punch_ranks', punch_blocks, 20, restart_ranks=(2, 3), whole_ranks=2,
             tolerance=1e-9)
# Coulomb friction against a rigid tool (3D, test_implicit_contact's sliding tool): the
# committed contact state carries the slip over the restart
nb, tool_blocks = tool_block_deck(3, 0.3, 0.05)
tool_blocks[-1] += ['*DATABASE_GLSTAT', f10(0.1)]
restart_case('implicit_friction', tool_blocks, 6, restart_ranks=(1,), whole_ranks=1)

# ---- 6. wrong use ---------------------------------------------------------------------------
other = os.path.join(WORK, 'taylor_bar', 'other.k')
shutil.copy(os.path.join(WORK, 'sliding_block', STEM + '.k'), other)
rc, text = mefem(['r=' + os.path.join(WORK, 'taylor_bar', 'whole', 'd3dump01'), other])
checks.check(rc == 1 and 'written for another model' in text and 'restarted' not in text and
             'explicit: 1 cycles' not in text,
             'a restart file of another deck: refused before the analysis', text[-400:])
rc, text = mefem(['r=nowhere/d3dump07'])
checks.check(rc == 1 and 'restart file "nowhere/d3dump07" does not exist' in text,
             'a missing restart file: refused', text[-400:])
cut = os.path.join(WORK, 'taylor_bar', 'cut')
shutil.rmtree(cut, ignore_errors=True)
shutil.copytree(os.path.join(WORK, 'taylor_bar', 'whole'), cut)
with open(os.path.join(cut, 'd3dump01'), 'r+b') as f:
    f.truncate(os.path.getsize(os.path.join(cut, 'd3dump01')) // 2)
rc, text = mefem(['r=' + os.path.join(cut, 'd3dump01')])
checks.check(rc == 1 and 'ends or cannot be read at record' in text,
             'a cut restart file: refused with the record it ends at', text[-400:])
rc, text = mefem(['r=' + os.path.join(WORK, 'taylor_bar', 'whole', 'd3dump01'),
                  os.path.join(ROOT, 'input', 'punch', 'punch_u1_mefem.k')])
checks.check(rc == 1 and 'was written by the explicit analysis; this deck runs the nonlinear '
             'implicit analysis' in text,
             'an explicit restart file given to an implicit deck: refused', text[-400:])
bad = os.path.join(WORK, 'bad_cycl.k')
with open(bad, 'w') as f:
    f.write(bar.replace('*DATABASE_GLSTAT', '*DATABASE_BINARY_D3DUMP\n      12.5\n'
                        '*DATABASE_GLSTAT') + '*END\n')
rc, text = mefem(['--check', bad])
checks.check(rc == 1 and '*DATABASE_BINARY_D3DUMP: field CYCL must be a whole number' in text,
             'CYCL 12.5: an error at its card', text[-400:])
checks.exit()
