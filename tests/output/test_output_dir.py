"""The output directory (-o): created with its parents; when it cannot be used, the run stops
before the analysis with a message saying which part of the path is in the way and why, on
one rank and on two (printed once, no hang).

1. a regular file where a parent directory should be: "... is a file, not a directory";
2. a directory that cannot be created (under /proc): "... could not be created ...";
3. an existing directory where no file can be created (/sys, read-only for root too): "files
   cannot be created in ..." with the system's answer;
4. a new nested directory is created and the run writes its results there;
5. an empty name (-o ""): an error (it wrote the HDF5 file into / before);
6. a directory holding an earlier run of the same deck: that run's files are removed first
   (a 2-rank run of 4 states, then a 1-rank run of 2 states: only the new states' files are
   left, and the log says how many it removed), other files are kept; mefem.log holds every
   line the run printed.
"""
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.environ.get('MEFEM_ROOT',
                      os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))
EXE = os.path.join(ROOT, 'bin', 'mefem')
DECK = os.path.join(ROOT, 'input', 'taylor_bar.k')
TIMEOUT = 120

failures = 0


def report(ok, what, detail=''):
    """Print one PASS/FAIL line and count failures."""
    global failures
    if ok:
        print(f'PASS: output dir: {what}')
    else:
        failures += 1
        print(f'FAIL: output dir: {what}: {detail}')


def run(ranks, out_dir, deck=DECK):
    """Run mefem with -o out_dir; return (exit code, output) or (None, reason)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')
    command = [EXE, '-o', out_dir, deck]
    if ranks > 1:
        command = ['mpirun', '--oversubscribe', '-np', str(ranks)] + command
    try:
        done = subprocess.run(command, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=TIMEOUT, text=True)
    except subprocess.TimeoutExpired:
        return None, f'no exit within {TIMEOUT} s (hang)'
    return done.returncode, done.stdout


def expect_failure(ranks, out_dir, wanted, what):
    """The run fails before the analysis, printing `wanted` once in its error line."""
    rc, text = run(ranks, out_dir)
    if rc is None:
        report(False, what, text)
        return
    errors = [line for line in text.splitlines() if 'cannot use the output directory' in line]
    report(rc != 0 and len(errors) == 1 and wanted in errors[0] and 'explicit: cycle' not in text,
           f'{what} ({ranks} rank(s)): exit {rc}, one message naming the cause',
           f'exit {rc}, messages {errors}, wanted "{wanted}"')


def main():
    if not os.path.isfile(EXE):
        report(False, 'mefem binary present', EXE)
        return
    scratch = tempfile.mkdtemp(prefix='mefem_outdir_')
    try:
        blocker = os.path.join(scratch, 'a_file')
        with open(blocker, 'w') as handle:
            handle.write('not a directory\n')
        for ranks in (1, 2):
            expect_failure(ranks, os.path.join(blocker, 'results'),
                           f'"{blocker}" is a file, not a directory', 'file in the path')
            expect_failure(ranks, '/proc/mefem_test/results',
                           'the directory "/proc/mefem_test" could not be created',
                           'directory that cannot be created')
        # sysfs takes no regular files, even from root
        expect_failure(1, '/sys', 'files cannot be created in "/sys"',
                       'existing directory without write access')
        rc, text = run(1, '')
        report(rc != 0 and 'option -o needs a directory, got an empty name' in text,
               'an empty -o is an error', f'exit {rc}: {text[-300:]}')
        nested = os.path.join(scratch, 'new', 'nested', 'dir')
        rc, text = run(1, nested)
        made = os.path.isfile(os.path.join(nested, 'taylor_bar.pvd'))
        report(rc == 0 and made, 'missing parents are created and the run writes there',
               f'exit {rc}, pvd written {made}: {text[-300:]}')
        earlier_run(scratch)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


BLOCK_DECK = """*KEYWORD
*NODE
       1             0.0             0.0             0.0
       2             1.0             0.0             0.0
       3             0.0             1.0             0.0
       4             0.0             0.0             1.0
       5             1.0             1.0             1.0
*ELEMENT_SOLID
       1       1       1       2       3       4       4       4       4       4
       2       1       2       3       4       5       5       5       5       5
*PART
block
         1         1         1
*SECTION_SOLID
         1        10
*MAT_ELASTIC
         1    7.8e-9     2.1e5       0.3
*INITIAL_VELOCITY
         0
    1000.0       0.0       0.0
*CONTROL_TERMINATION
%10.3e
*DATABASE_BINARY_D3PLOT
    1.0e-6
*DATABASE_GLSTAT
    1.0e-6
*END
"""


def earlier_run(scratch):
    """Case 6: results of an earlier run in the output directory."""
    out = os.path.join(scratch, 'rerun')
    deck = os.path.join(scratch, 'block.k')
    with open(deck, 'w') as handle:
        handle.write(BLOCK_DECK % 3.0e-6)               # states at 0, 1, 2, 3 us
    rc, text = run(2, out, deck)
    first = sorted(os.listdir(out)) if rc == 0 else []
    with open(os.path.join(out, 'notes.txt'), 'w') as handle:
        handle.write('a user file\n')
    with open(deck, 'w') as handle:
        handle.write(BLOCK_DECK % 1.0e-6)               # states at 0, 1 us
    rc2, text2 = run(1, out, deck)
    second = sorted(os.listdir(out)) if rc2 == 0 else []
    wanted = ['block.h5', 'block.pvd', 'block.xdmf', 'block_000000.vtu', 'block_000001.vtu',
              'glstat', 'mefem.log', 'notes.txt']
    removed = [line for line in text2.splitlines() if 'files of an earlier run' in line]
    report(rc == 0 and rc2 == 0 and 'block_000003.pvtu' in first and second == wanted and
           len(removed) == 1 and 'removed %d files' % (len(first) - 1) in removed[0],
           'an earlier run\'s results are removed before the new run writes (the others kept)',
           f'exits {rc} {rc2}; before {first}; after {second}; log {removed}')
    # the run's log file: every line of the screen, from the first to the last
    log = open(os.path.join(out, 'mefem.log')).read().splitlines() if rc2 == 0 else []
    screen = [line for line in text2.splitlines() if line.strip()]
    report(len(log) > 5 and log[0].startswith('mefem ') and log[-1].startswith('wall time') and
           all(line in log for line in screen),
           'mefem.log holds every line the run printed, in order',
           f'{len(log)} lines; first {log[:1]}, last {log[-1:]}')


if __name__ == '__main__':
    main()
    sys.exit(1 if failures else 0)
