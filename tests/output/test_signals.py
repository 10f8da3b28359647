"""Signals as a batch system sends them (issue 21; README "Stopping a run"): SIGTERM, SIGINT
and SIGUSR1 to a running analysis, at several moments, on 1 and 2 ranks and through mpirun.
Each stopped run must say where it stopped, exit with 128 + the signal's number (1 rank), and
leave results that are complete up to that point: every state /time_history lists opens with
all its rows, the last one at the time the log names, glstat ends there too, and every file
the .pvd lists exists. Signals "to the ranks" go to every process of the run, mpirun too (as a
scheduler's kill does; mpirun passes them on, so each rank gets two); a second signal changes
nothing. The implicit punch stopped by SIGTERM writes the state of its last step.

The explicit deck is the copper Taylor bar (medium mesh, standard tets: about 10 s to the
end) with a result state every 0.2 us (every 15-30 cycles), so that the signal meets state
writes; the moments are well inside the run, after the set-up.
"""
import os
import re
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'verification'))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'bench'))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, ROOT, MPIRUN  # noqa: E402
from lsdyna_ascii import read_glstat  # noqa: E402
import taylor_copper as tc  # noqa: E402

checks = Checks('signals')
OUT = os.path.join(ROOT, 'tests', 'out', 'signals')
os.makedirs(OUT, exist_ok=True)
EXE = os.path.join(ROOT, 'bin', 'mefem')
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1', OPENBLAS_NUM_THREADS='1')
STOPPED = re.compile(r'(explicit|implicit): (SIG[A-Z0-9]+): stopped (?:at cycle|after step) '
                     r'(\d+), t = ([0-9.eE+-]+)')

deck = os.path.join(OUT, 'taylor_signals.k')
tc.write_deck(deck, 10, 'medium', plots=400)


def start(name, deck_path, ranks):
    """Start bin/mefem (under mpirun for ranks > 1); returns (process, output directory)."""
    out = os.path.join(OUT, name)
    cmd = [EXE, '-o', out, deck_path]
    if ranks > 1:
        cmd = MPIRUN + ['-np', str(ranks)] + cmd
    log = open(os.path.join(OUT, name + '.log'), 'w')
    return subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=ENV), out


def rank_pids(out):
    """Process ids of the processes running mefem on out: the ranks, and mpirun itself (its
    command line names them too), as a scheduler's kill signals every process of the job; the
    ranks then get the signal twice, directly and passed on by mpirun."""
    found = subprocess.run(['pgrep', '-f', 'bin/mefem -o ' + out + ' '], capture_output=True,
                           text=True).stdout.split()
    return [int(p) for p in found]


def check_results(name, out, stem, text, explicit=True):
    """The stop message, the HDF5 states, glstat and the .pvd of a stopped run."""
    m = STOPPED.search(text)
    checks.check(m is not None, '%s: the log says where the run stopped' % name, text[-500:])
    if m is None:
        return None
    t_stop = float(m.group(4))
    with h5py.File(os.path.join(out, stem + '.h5'), 'r') as h:
        steps = np.array(h['time_history/step'])
        times = np.array(h['time_history/time'])
        nnode = h['mesh/coordinates'].shape[0]
        ncell = h['mesh/cell_types'].shape[0]
        complete = 'displacement' in h['states/%06d/point' % steps[-1]]
        for k in steps:                     # every field of every listed state: all rows, finite
            for entity, rows in (('point', nnode), ('cell', ncell)):
                for field in h['states/%06d/%s' % (k, entity)].values():
                    values = field[()]
                    complete = complete and values.shape[0] == rows and \
                        bool(np.all(np.isfinite(values)))
    checks.check(complete and len(steps) > 1, '%s: every state /time_history lists is complete '
                 '(%d states)' % (name, len(steps)), '')
    checks.check(abs(times[-1] - t_stop) <= 1e-5 * t_stop, '%s: the last state is at the stop '
                 'time %.6g' % (name, t_stop), 'last state at %.6g' % times[-1])
    if explicit:
        g = read_glstat(os.path.join(out, 'glstat'))
        checks.check(abs(g['time'][-1] - t_stop) <= 1e-5 * t_stop, '%s: glstat ends at the stop '
                     'time' % name, 'last record %.6g' % g['time'][-1])
    files = [d.get('file') for d in ET.parse(os.path.join(out, stem + '.pvd')).iter('DataSet')]
    missing = [f for f in files if not os.path.isfile(os.path.join(out, f))]
    checks.check(len(files) == len(steps) and not missing, '%s: the .pvd lists the %d states, '
                 'every file there' % (name, len(steps)), '%d listed, missing %s'
                 % (len(files), missing[:3]))
    return t_stop


def wait_for(name, text, proc, limit=60.0):
    """Wait until the run's log holds text (the analysis has started: the handlers are set),
    at most limit seconds."""
    t0 = time.time()
    while time.time() - t0 < limit and proc.poll() is None:
        with open(os.path.join(OUT, name + '.log')) as f:
            if text in f.read():
                return
        time.sleep(0.05)


def signal_run(name, ranks, delay, sig, to_ranks=True):
    """Run the Taylor deck, send sig delay seconds after its first cycle (to mpirun and the
    ranks, or to mpirun only)."""
    proc, out = start(name, deck, ranks)
    wait_for(name, 'explicit: cycle', proc)
    time.sleep(delay)
    if proc.poll() is not None:
        checks.check(False, '%s: still running after %.1f s' % (name, delay), '')
        return
    if to_ranks:
        for pid in rank_pids(out):
            os.kill(pid, sig)
    else:
        proc.send_signal(sig)
    try:
        rc = proc.wait(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        checks.check(False, '%s: stops within 60 s of the signal' % name, '')
        return
    text = open(os.path.join(OUT, name + '.log')).read()
    if ranks == 1:
        checks.check(rc == 128 + sig, '%s: exit code %d (128 + %s)' % (name, 128 + sig,
                     signal.Signals(sig).name), 'exit code %d' % rc)
    else:
        checks.check(rc != 0, '%s: mpirun reports a non-zero exit code' % name, 'rc %d' % rc)
    checks.check(signal.Signals(sig).name + ': stopped' in text, '%s: the log names %s'
                 % (name, signal.Signals(sig).name), text[-300:])
    check_results(name, out, 'taylor_signals', text)


for k, delay in enumerate((0.5, 1.4, 2.3)):
    signal_run('term_np1_%d' % k, 1, delay, signal.SIGTERM)
for k, delay in enumerate((1.0, 2.0)):
    signal_run('term_np2_%d' % k, 2, delay, signal.SIGTERM)
signal_run('term_mpirun', 2, 1.5, signal.SIGTERM, to_ranks=False)
signal_run('usr1_np2', 2, 1.0, signal.SIGUSR1)
signal_run('int_np1', 1, 0.9, signal.SIGINT)

# a second signal changes nothing: the stop stays a clean one
proc, out = start('int_twice', deck, 1)
wait_for('int_twice', 'explicit: cycle', proc)
time.sleep(1.0)
proc.send_signal(signal.SIGINT)
time.sleep(0.05)                      # (two signals at once would be delivered as one)
proc.send_signal(signal.SIGINT)
rc = proc.wait(timeout=60)
text = open(os.path.join(OUT, 'int_twice.log')).read()
checks.check(rc == 128 + signal.SIGINT, 'two SIGINTs: the second changes nothing (exit 130)',
             'return code %d' % rc)
check_results('int_twice', out, 'taylor_signals', text)

# implicit: the punch (s2 mesh, about 12 s) stopped after a step
punch = os.path.join(ROOT, 'input', 'punch', 'punch_s2_mefem.k')
proc, out = start('term_implicit', punch, 1)
wait_for('term_implicit', 'step 1:', proc)
time.sleep(1.0)
proc.send_signal(signal.SIGTERM)
rc = proc.wait(timeout=120)
text = open(os.path.join(OUT, 'term_implicit.log')).read()
checks.check(rc == 128 + signal.SIGTERM, 'implicit punch: exit code 143 after SIGTERM',
             'exit code %d' % rc)
check_results('implicit punch', out, 'punch_s2_mefem', text, explicit=False)
checks.exit()
