"""The output directory (-o): created with its parents; when it cannot be used, the run stops
before the analysis with a message saying which part of the path is in the way and why, on
one rank and on two (printed once, no hang).

1. a regular file where a parent directory should be: "... is a file, not a directory";
2. a directory that cannot be created (under /proc): "... could not be created ...";
3. an existing directory where no file can be created (/sys, read-only for root too): "files
   cannot be created in ..." with the system's answer;
4. a new nested directory is created and the run writes its results there;
5. an empty name (-o ""): an error (it wrote the HDF5 file into / before).
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
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == '__main__':
    main()
    sys.exit(1 if failures else 0)
