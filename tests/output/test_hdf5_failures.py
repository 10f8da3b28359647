"""Failure paths of the HDF5 writer, driven through build/debug/tests/test_hdf5_output.

1. `bad-path` on 2 ranks: creating a file in a missing directory must stop the run through
   mefem_errors (exit code 1, message naming the path), without a crash or a hang.
2. `die-after-state` on 3 ranks: the program writes the mesh and two states, then aborts
   without closing the file. Because the writer flushes after every state, the file must open
   with h5py and hold the same data as np3.h5 of the normal run (checked against its truth by
   test_hdf5_roundtrip.py).
A missing executable or reference file is a failure, not a skip.
"""
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
# The debug build's test program; MEFEM_TEST_HDF5_EXE may name another build of it.
EXE = os.environ.get('MEFEM_TEST_HDF5_EXE',
                     os.path.join(ROOT, 'build', 'debug', 'tests', 'test_hdf5_output'))
DIRECTORY = os.path.join(ROOT, 'tests', 'out', 'h5_unit')
TIMEOUT = 180

failures = 0


def report(ok, what, detail=''):
    """Print one PASS/FAIL line and count failures."""
    global failures
    if ok:
        print(f'PASS: hdf5 failures: {what}')
    else:
        failures += 1
        print(f'FAIL: hdf5 failures: {what}: {detail}')


def run(ranks, mode):
    """Run the test program under mpirun; return (exit code, output) or (None, reason)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1', MEFEM_ROOT=ROOT)
    command = ['mpirun', '--oversubscribe', '-np', str(ranks), EXE, mode]
    try:
        done = subprocess.run(command, cwd=os.path.join(ROOT, 'tests', 'unit'), env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              timeout=TIMEOUT, text=True)
    except subprocess.TimeoutExpired:
        return None, f'no exit within {TIMEOUT} s (hang)'
    return done.returncode, done.stdout


def datasets(h5file):
    """{path: array} of every dataset in an open h5py file."""
    import h5py
    found = {}
    h5file.visititems(lambda name, obj: found.__setitem__('/' + name, obj[()])
                      if isinstance(obj, h5py.Dataset) else None)
    return found


def check_bad_path():
    path = os.path.join(DIRECTORY, 'no_such_directory', 'np2.h5')
    code, output = run(2, 'bad-path')
    what = 'a file in a missing directory stops the run cleanly'
    if code is None:
        report(False, what, output)
        return
    message = f"mefem: error: HDF5 output '{path}': cannot create the file"
    report(code == 1 and message in output and 'FAIL' not in output, what,
           f'exit code {code}, output:\n' + output[-1500:])
    report('Backtrace' not in output and 'SIGSEGV' not in output.upper(),
           'no crash or backtrace on a bad path', output[-1500:])


def check_died_file():
    import h5py
    path = os.path.join(DIRECTORY, 'died_np3.h5')
    reference = os.path.join(DIRECTORY, 'np3.h5')
    if os.path.exists(path):
        os.remove(path)
    code, output = run(3, 'die-after-state')
    report(code is not None and code != 0 and 'simulated crash' in output,
           'the program aborts after writing two states', f'exit code {code}: {output[-800:]}')
    if not os.path.isfile(reference):
        report(False, 'reference np3.h5 exists', f'missing {reference} (unit test not run?)')
        return
    try:
        with h5py.File(path, 'r') as died, h5py.File(reference, 'r') as full:
            got, want = datasets(died), datasets(full)
            steps = list(died['time_history/step'][()])
    except OSError as error:
        report(False, 'file of an aborted run opens with h5py', str(error))
        return
    report(True, 'file of an aborted run opens with h5py')
    report(steps == [0, 125] and sorted(died_states(path)) == ['000000', '000125'],
           'both states of the aborted run are in the file', f'steps {steps}')
    differ = [name for name in want
              if name not in got or got[name].shape != want[name].shape
              or not np.array_equal(got[name], want[name])]
    report(not differ and set(got) == set(want),
           'aborted run holds the same data as the closed np3.h5', f'differ: {differ}')


def died_states(path):
    import h5py
    with h5py.File(path, 'r') as h5file:
        return list(h5file['states'])


def main():
    if not os.access(EXE, os.X_OK):
        report(False, 'test executable exists', f'missing {EXE} (run make DEBUG=1 unit-tests)')
        return 1
    try:
        import h5py  # noqa: F401
    except ImportError as error:
        report(False, 'h5py available', str(error))
        return 1
    os.makedirs(DIRECTORY, exist_ok=True)
    check_bad_path()
    check_died_file()
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
