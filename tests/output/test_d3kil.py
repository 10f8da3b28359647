"""LS-DYNA's sense switches through a file d3kil (explicit runs; doc/keywords.md): mefem looks
for it every 100 cycles in the working directory and in the output directory, acts on it and
deletes it. The Taylor bar (input/taylor_bar.k) with d3kil written before the run,
so that the switch is found at cycle 100:

1. sw1 in the working directory, 2 ranks: exit 0 after cycle 100, the message, the states of
   t = 0 and of cycle 100 only (the last at the glstat's last time), d3kil gone;
2. an empty d3kil: stops as sw1 (LS-DYNA's rule);
3. sw4 in the output directory: the run goes to the end and has one state more than the run
   without the file, at the time of cycle 100; d3kil gone;
4. sw2: the status line (cycle 100), the run goes to the end;
5. an unknown switch: a warning, the run goes to the end, d3kil gone;
6. implicit (input/punch/punch_u1_mefem.k, looked for after every step): sw1 stops after step
   1 with exit 0, the states of t = 0 and of step 1; sw2 prints the status after step 1 and
   the run goes to the end;
7. a directory named d3kil: a warning, the run goes to the end, the directory is kept (it
   crashed the run, and hung two ranks, before);
8. two switches in one file (sw2, then sw1) and a second file in the output directory: the
   status is printed, the run stops, and both files are deleted; a d3kil there at the start
   gets a warning.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.environ.get('MEFEM_ROOT',
                      os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
EXE = os.path.join(ROOT, 'bin', 'mefem')
DECK = os.path.join(ROOT, 'input', 'taylor_bar.k')
IMPLICIT_DECK = os.path.join(ROOT, 'input', 'punch', 'punch_u1_mefem.k')
TIMEOUT = 300
MIN_CYCLES = 300     # the bar must run past a few looks for d3kil (every 100 cycles)

failures = 0


def report(ok, what, detail=''):
    """Print one PASS/FAIL line and count failures."""
    global failures
    if ok:
        print(f'PASS: d3kil: {what}')
    else:
        failures += 1
        print(f'FAIL: d3kil: {what}: {detail}')


def run(work, ranks=1, deck=DECK):
    """Run a deck (the bar) in directory `work` with output in work/out; (exit code, log)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')
    command = [EXE, '-o', 'out', deck]
    if ranks > 1:
        command = ['mpirun', '--oversubscribe', '-np', str(ranks)] + command
    try:
        done = subprocess.run(command, cwd=work, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=TIMEOUT, text=True)
    except subprocess.TimeoutExpired:
        return None, f'no exit within {TIMEOUT} s'
    return done.returncode, done.stdout


def cycles_run(log):
    """The cycle count of the driver's summary line, or None."""
    found = re.search(r'explicit: cycles (\d+) \(', log)
    return int(found.group(1)) if found else None


def state_times(work, stem='taylor_bar'):
    """The times of the result states listed in the .pvd file."""
    path = os.path.join(work, 'out', stem + '.pvd')
    if not os.path.isfile(path):
        return []
    with open(path) as handle:
        return [float(x) for x in re.findall(r'timestep="([^"]+)"', handle.read())]


def glstat_last_time(work):
    """The time of glstat's last record, or None."""
    path = os.path.join(work, 'out', 'glstat')
    if not os.path.isfile(path):
        return None
    with open(path) as handle:
        times = re.findall(r'time\.+\s*([0-9.Ee+-]+)', handle.read())
    return float(times[-1]) if times else None


def fresh(scratch, name, switch, where='.'):
    """A work directory holding d3kil with `switch` (None: no file) in `where`."""
    work = os.path.join(scratch, name)
    os.makedirs(os.path.join(work, 'out'))
    if switch is not None:
        with open(os.path.join(work, where, 'd3kil'), 'w') as handle:
            handle.write(switch)
    return work


def main():
    if not os.path.isfile(EXE):
        report(False, 'mefem binary present', EXE)
        return
    scratch = tempfile.mkdtemp(prefix='mefem_d3kil_')
    try:
        plain = fresh(scratch, 'plain', None)
        rc, log = run(plain)
        plain_times = state_times(plain)
        CYCLES = cycles_run(log) or 0    # what every run that goes on to the end must reach
        report(rc == 0 and CYCLES >= MIN_CYCLES and len(plain_times) > 2,
               'the bar without d3kil runs to the end (past a few looks for d3kil)',
               f'exit {rc}, {CYCLES} cycles')

        work = fresh(scratch, 'sw1', 'sw1\n')
        rc, log = run(work, ranks=2)
        times = state_times(work)
        last = glstat_last_time(work)
        report(rc == 0 and cycles_run(log) == 100 and 'd3kil (sw1): stopped at cycle 100' in log,
               'sw1 (2 ranks): stops after cycle 100 with exit 0 and says so',
               f'exit {rc}, {cycles_run(log)} cycles: {log[-400:]}')
        # the plain run's states before the stop, then one of the time reached (cycle 100)
        time_100 = last if last is not None else -1.0
        expected = [t for t in plain_times if t < time_100*(1 - 1e-6)] + [time_100]
        report(last is not None and len(times) == len(expected) and
               all(abs(a - b) <= 1e-6*time_100 for a, b in zip(times, expected)),
               'sw1: the regular states before the stop and one of the time reached, glstat up '
               'to that time', f'states {times}, expected {expected}, glstat last {last}')
        report(not os.path.exists(os.path.join(work, 'd3kil')), 'sw1: d3kil deleted')

        work = fresh(scratch, 'empty', '')
        rc, log = run(work)
        report(rc == 0 and cycles_run(log) == 100, 'an empty d3kil stops as sw1',
               f'exit {rc}, {cycles_run(log)} cycles')

        work = fresh(scratch, 'sw4', 'SW4\n', where='out')
        rc, log = run(work)
        times = state_times(work)
        extra = sorted(set(times) - set(plain_times))
        report(rc == 0 and cycles_run(log) == CYCLES and len(times) == len(plain_times) + 1 and
               len(extra) == 1 and 'd3kil (sw4): result state written at cycle 100' in log,
               'sw4 in the output directory: one state more, the run goes on to the end',
               f'exit {rc}, {cycles_run(log)} cycles, states {len(times)} vs {len(plain_times)}')
        report(len(extra) == 1 and abs(extra[0] - time_100) <= 1e-6*time_100,
               'sw4: the extra state is at the time of cycle 100 (that sw1 stopped at)',
               f'extra {extra}, cycle 100 at {time_100}')
        report(not os.path.exists(os.path.join(work, 'out', 'd3kil')), 'sw4: d3kil deleted')

        work = fresh(scratch, 'sw2', 'sw2\n')
        rc, log = run(work)
        report(rc == 0 and cycles_run(log) == CYCLES and 'd3kil (sw2): cycle 100,' in log,
               'sw2: a status line at cycle 100, the run goes on', f'exit {rc}')

        work = fresh(scratch, 'bogus', 'please stop\n')
        rc, log = run(work)
        report(rc == 0 and cycles_run(log) == CYCLES and 'unknown switch "please stop"' in log
               and not os.path.exists(os.path.join(work, 'd3kil')),
               'an unknown switch: a warning, the run goes on, d3kil deleted', f'exit {rc}')

        work = fresh(scratch, 'directory', None)
        os.makedirs(os.path.join(work, 'd3kil', 'inside'))
        rc, log = run(work, ranks=2)
        report(rc == 0 and cycles_run(log) == CYCLES and 'is a directory, not a sense-switch' in log
               and os.path.isdir(os.path.join(work, 'd3kil', 'inside')),
               'a directory named d3kil (2 ranks): a warning, the run goes on, the directory kept',
               f'exit {rc}, {cycles_run(log)} cycles: {log[-300:]}')

        work = fresh(scratch, 'two_files', 'sw2\nsw1\n')
        with open(os.path.join(work, 'out', 'd3kil'), 'w') as handle:
            handle.write('sw4\n')
        rc, log = run(work)
        report(rc == 0 and cycles_run(log) == 100 and 'd3kil (sw2): cycle 100,' in log and
               'd3kil (sw1): stopped at cycle 100' in log and 'is there at the start' in log,
               'sw2 and sw1 in one file, sw4 in the other: status, then stop; a warning at the '
               'start', f'exit {rc}, {cycles_run(log)} cycles: {log[-400:]}')
        report(not os.path.exists(os.path.join(work, 'd3kil')) and
               not os.path.exists(os.path.join(work, 'out', 'd3kil')),
               'both d3kil files deleted')

        work = fresh(scratch, 'implicit_plain', None)
        rc, log = run(work, deck=IMPLICIT_DECK)
        steps = re.findall(r'^step (\d+): t = ', log, re.MULTILINE)
        plain_states = state_times(work, 'punch_u1_mefem')
        report(rc == 0 and len(steps) > 2, 'implicit: the punch without d3kil runs its steps',
               f'exit {rc}, {len(steps)} steps')
        work = fresh(scratch, 'implicit_sw1', 'sw1\n')
        rc, log = run(work, deck=IMPLICIT_DECK)
        times = state_times(work, 'punch_u1_mefem')
        report(rc == 0 and 'd3kil (sw1): stopped after step 1,' in log and
               re.findall(r'^step (\d+): t = ', log, re.MULTILINE) == ['1'] and len(times) == 2
               and times[0] == 0.0 and times[1] > 0.0,
               'implicit sw1: stops after step 1 (exit 0), the states of t = 0 and of step 1',
               f'exit {rc}, states {times}: {log[-300:]}')
        work = fresh(scratch, 'implicit_sw2', 'sw2\n')
        rc, log = run(work, deck=IMPLICIT_DECK)
        report(rc == 0 and 'd3kil (sw2): step 1,' in log and
               len(re.findall(r'^step (\d+): t = ', log, re.MULTILINE)) == len(steps) and
               state_times(work, 'punch_u1_mefem') == plain_states,
               'implicit sw2: the status after step 1, the run goes to the end unchanged',
               f'exit {rc}')
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == '__main__':
    main()
    sys.exit(1 if failures else 0)
