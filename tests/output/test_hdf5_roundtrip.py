"""HDF5 result files of tests/unit/test_hdf5_output.f90 against the truth it wrote, with h5py.

For each rank count N in 1, 2, 3: tests/out/h5_unit/npN.h5 must exist (a missing file is a
failure, not a skip) and match npN_truth.txt: same dataset shapes and dtypes, integers exact,
reals within 1e-15 relative; attributes (state times and steps) likewise. The files written on
1, 2 and 3 ranks must hold identical data. One line `PASS: ...` or `FAIL: ...: detail` per check.
"""
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
DIRECTORY = os.path.join(ROOT, 'tests', 'out', 'h5_unit')
RANKS = (1, 2, 3)
RTOL = 1e-15

failures = 0


def report(ok, what, detail=''):
    """Print one PASS/FAIL line and count failures."""
    global failures
    if ok:
        print(f'PASS: hdf5 roundtrip: {what}')
    else:
        failures += 1
        print(f'FAIL: hdf5 roundtrip: {what}: {detail}')


def read_truth(path):
    """Parse the truth file: {path: (dtype, shape, values)} and {(object, name): (dtype, value)}."""
    datasets, attributes = {}, {}
    with open(path) as stream:
        lines = stream.read().split('\n')
    k = 0
    while k < len(lines):
        words = lines[k].split()
        k += 1
        if not words:
            continue
        if words[0] == 'attribute':
            attributes[(words[1], words[2])] = (words[3], words[4])
        elif words[0] == 'dataset':
            name, dtype = words[1], words[2]
            shape = tuple(int(w) for w in words[3:])
            rows = shape[0]
            values = ' '.join(lines[k:k + rows]).split()
            k += rows
            if dtype.startswith('float'):
                array = np.array([float(v) for v in values], dtype=np.float64)
            else:
                array = np.array([int(v) for v in values], dtype=np.int64)
            datasets[name] = (dtype, shape, array.reshape(shape))
        else:
            raise ValueError(f'{path}:{k}: unexpected line {lines[k - 1]!r}')
    return datasets, attributes


def close(got, want):
    """Largest excess of |got - want| over RTOL*|want| (<= 0 means within tolerance)."""
    got = np.asarray(got, dtype=np.float64)
    want = np.asarray(want, dtype=np.float64)
    if not np.all(np.isfinite(got)):
        return np.inf
    return float(np.max(np.abs(got - want) - RTOL * np.abs(want), initial=-np.inf))


def all_datasets(h5file):
    """Paths of every dataset in the file."""
    import h5py
    found = []
    h5file.visititems(lambda name, obj: found.append('/' + name)
                      if isinstance(obj, h5py.Dataset) else None)
    return sorted(found)


def check_file(n):
    """Compare npN.h5 with npN_truth.txt; return {dataset path: array} for the cross-check."""
    import h5py
    path = os.path.join(DIRECTORY, f'np{n}.h5')
    truth_path = os.path.join(DIRECTORY, f'np{n}_truth.txt')
    if not os.path.isfile(path) or not os.path.isfile(truth_path):
        report(False, f'np{n} files exist', f'missing {path} or {truth_path} '
               '(run build/debug/tests/test_hdf5_output under mpirun first)')
        return None
    report(True, f'np{n} files exist')
    datasets, attributes = read_truth(truth_path)
    # the XDMF mixed topology the writer adds: each cell's XDMF code, then its nodes, built
    # here from the truth's cell types, offsets and connectivity (post/h5_to_xdmf.py's rule)
    mesh = ('/mesh/cell_types', '/mesh/cell_offsets', '/mesh/connectivity')
    if all(k in datasets for k in mesh):
        sys.path.insert(0, os.path.join(ROOT, 'post'))
        import h5_to_xdmf
        topology = h5_to_xdmf.mixed_topology(datasets['/mesh/cell_types'][2],
                                             datasets['/mesh/cell_offsets'][2],
                                             datasets['/mesh/connectivity'][2])
        datasets['/mesh/xdmf_topology'] = ('int64', topology.shape, topology)
    contents = {}
    try:
        h5file = h5py.File(path, 'r')
    except OSError as error:
        report(False, f'np{n}.h5 opens with h5py', str(error))
        return None
    with h5file:
        present = all_datasets(h5file)
        report(present == sorted(datasets), f'np{n}.h5 holds exactly the expected datasets',
               f'extra {sorted(set(present) - set(datasets))}, '
               f'missing {sorted(set(datasets) - set(present))}')
        for name, (dtype, shape, want) in sorted(datasets.items()):
            if name not in h5file:
                continue
            got = h5file[name][()]
            contents[name] = got
            what = f'np{n}.h5 {name}'
            if got.shape != shape or got.dtype != np.dtype(dtype):
                report(False, what, f'shape {got.shape} dtype {got.dtype}, '
                       f'want {shape} {dtype}')
            elif dtype.startswith('float'):
                excess = close(got, want)
                report(excess <= 0.0, what, f'worst excess over 1e-15 relative: {excess:.3e}')
            else:
                bad = np.flatnonzero(got.ravel() != want.ravel())
                report(bad.size == 0, what, f'{bad.size} entries differ, first at flat index '
                       f'{bad[:1]}: got {got.ravel()[bad[:1]]} want {want.ravel()[bad[:1]]}')
        for (owner, name), (dtype, text) in sorted(attributes.items()):
            what = f'np{n}.h5 attribute {owner}:{name}'
            if owner not in h5file or name not in h5file[owner].attrs:
                report(False, what, 'missing')
                continue
            got = h5file[owner].attrs[name]
            if np.asarray(got).dtype != np.dtype(dtype):
                report(False, what, f'dtype {np.asarray(got).dtype}, want {dtype}')
            elif dtype.startswith('float'):
                excess = close(got, float(text))
                report(excess <= 0.0, what, f'got {got!r}, want {text}')
            else:
                report(int(got) == int(text), what, f'got {got!r}, want {text}')
        fmt = h5file.attrs.get('format')
        report(fmt is not None and bytes(fmt).rstrip(b'\0') == b'mefem',
               f'np{n}.h5 format attribute is mefem', f'got {fmt!r}')
        # The state groups and the time history agree.
        steps = h5file['time_history/step'][()]
        times = h5file['time_history/time'][()]
        groups = sorted(h5file['states'])
        ok = groups == [f'{s:06d}' for s in steps] and all(
            h5file['states'][f'{s:06d}'].attrs['time'] == t for s, t in zip(steps, times))
        report(ok, f'np{n}.h5 time history matches the state groups',
               f'groups {groups}, steps {steps}, times {times}')
    return contents


def main():
    try:
        import h5py  # noqa: F401
    except ImportError as error:
        report(False, 'h5py available', str(error))
        return 1
    results = {n: check_file(n) for n in RANKS}
    reference = results[RANKS[0]]
    for n in RANKS[1:]:
        what = f'np{n}.h5 holds the same data as np{RANKS[0]}.h5'
        if reference is None or results[n] is None:
            report(False, what, 'a file is missing or unreadable')
            continue
        differ = [name for name in reference
                  if name not in results[n] or results[n][name].shape != reference[name].shape
                  or not np.array_equal(results[n][name], reference[name])]
        report(not differ and set(results[n]) == set(reference), what, f'differ: {differ}')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
