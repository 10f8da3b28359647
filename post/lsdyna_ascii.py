"""Readers of the LS-DYNA-style ASCII time histories mefem writes (glstat, nodout, rwforc,
rbdout, rcforc).

Label-based, so they read LS-DYNA's own files as well as mefem's (which carry more digits):

    from lsdyna_ascii import read_glstat, read_nodout
    g = read_glstat('results/run/glstat')     # dict: label -> numpy array over records
    g['time'], g['kinetic energy'], g['total energy / initial energy']
    n = read_nodout('results/run/nodout')     # dict: 'time', 'ids', and (records, nodes) arrays
    n['x-disp'][:, k] is node n['ids'][k] over time
"""
import re

import numpy as np

_GLSTAT_LINE = re.compile(r'^ (\S[^.]*?)\s*\.+\s*(\S+)\s*$')
_CYCLE_LINE = re.compile(r'dt of cycle\s*(\d+)')
_NODOUT_HEAD = re.compile(r'n o d a l\s+p r i n t\s+o u t.*?s t e p\s*(\d+)\s*\(\s*at time\s*(\S+)\s*\)')
NODOUT_COLUMNS = ['x-disp', 'y-disp', 'z-disp', 'x-vel', 'y-vel', 'z-vel', 'x-accl', 'y-accl',
                  'z-accl', 'x-coor', 'y-coor', 'z-coor']


def _number(text):
    """A Fortran number, also with a 3-digit exponent and no 'E' (1.0-100)."""
    try:
        return float(text)
    except ValueError:
        return float(re.sub(r'(\d)([+-]\d+)$', r'\1E\2', text))


def read_glstat(path):
    """Every record of a glstat file: {label: array}, plus 'cycle'."""
    records, current = [], None
    with open(path) as f:
        for line in f:
            m = _CYCLE_LINE.search(line)
            if m:
                current = {'cycle': float(m.group(1))}
                records.append(current)
                continue
            m = _GLSTAT_LINE.match(line.rstrip('\n'))
            if m and current is not None:
                current[m.group(1).strip()] = _number(m.group(2))
    labels = records[0].keys() if records else []
    return {k: np.array([r.get(k, np.nan) for r in records]) for k in labels}


def read_nodout(path):
    """Every block of a nodout file: 'time', 'cycle', 'ids' and (records, nodes) arrays
    named as LS-DYNA's columns (x-disp ... z-coor)."""
    times, cycles, blocks = [], [], []
    ids = None
    with open(path) as f:
        lines = f.readlines()
    i = 0
    while i < len(lines):
        m = _NODOUT_HEAD.search(lines[i])
        if not m:
            i += 1
            continue
        cycles.append(int(m.group(1)))
        times.append(_number(m.group(2)))
        i += 1
        while i < len(lines) and 'nodal point' not in lines[i]:
            i += 1
        i += 1
        rows, block_ids = [], []
        while i < len(lines) and lines[i].strip() and 'n o d a l' not in lines[i]:
            fields = lines[i].split()
            block_ids.append(int(fields[0]))
            rows.append([_number(v) for v in fields[1:13]])
            i += 1
        ids = block_ids if ids is None else ids
        blocks.append(rows)
    data = np.array(blocks)
    out = {'time': np.array(times), 'cycle': np.array(cycles), 'ids': np.array(ids)}
    for k, name in enumerate(NODOUT_COLUMNS):
        out[name] = data[:, :, k] if len(blocks) else np.zeros((0, 0))
    return out


def read_rwforc(path):
    """Rows of an rwforc file: dict wall id -> {'time', 'normal', 'x', 'y', 'z'} arrays."""
    rows = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) == 6:
                try:
                    rows.append([_number(fields[0]), int(fields[1])] +
                                [_number(v) for v in fields[2:]])
                except ValueError:
                    continue
    out = {}
    for wall in sorted({r[1] for r in rows}):
        data = np.array([[r[0]] + r[2:] for r in rows if r[1] == wall])
        out[wall] = {'time': data[:, 0], 'normal': data[:, 1], 'x': data[:, 2],
                     'y': data[:, 3], 'z': data[:, 4]}
    return out


RBDOUT_COLUMNS = ['x-disp', 'y-disp', 'z-disp', 'x-vel', 'y-vel', 'z-vel', 'x-reaction',
                  'y-reaction', 'z-reaction', 'xx-reaction', 'yy-reaction', 'zz-reaction']


def read_rbdout(path):
    """Rows of mefem's rbdout: dict part id -> {'time', and the RBDOUT_COLUMNS} arrays."""
    rows = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) == 14:
                try:
                    rows.append([_number(fields[0]), int(fields[1])] +
                                [_number(v) for v in fields[2:]])
                except ValueError:
                    continue
    out = {}
    for part in sorted({r[1] for r in rows}):
        data = np.array([[r[0]] + r[2:] for r in rows if r[1] == part])
        out[part] = {'time': data[:, 0]}
        for k, name in enumerate(RBDOUT_COLUMNS):
            out[part][name] = data[:, k + 1]
    return out


_RCFORC_ROLES = {'master': 'master', 'slave': 'slave', 'surfb': 'master', 'surfa': 'slave'}
_RCFORC_ROW = re.compile(r'^\s*(master|slave|surfa|surfb)\s+(\d+)\s+(.*)$', re.IGNORECASE)
_LABEL_VALUE = re.compile(r'([A-Za-z][A-Za-z_]*)\s*=?\s*'
                          r'([-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+|[-+]\d{2,3})?)'
                          r'(?![\w.])')


def read_rcforc(path):
    """Rows of an rcforc file (resultant contact forces, LS-DYNA's layout):
    dict interface id -> {'master': {...}, 'slave': {...}}, each a dict label -> array over
    the output times, with the labels of the row ('time', 'x', 'y', 'z', 'mass', ...).

    Read by label, not by column: a row is a role word (master/slave; SURFB/SURFA are taken as
    master/slave), the interface id, then label-value pairs in any order and number, e.g.
      '  master       1 time  1.00000E-03 x -1.2E+01 y  0.0E+00 z  3.4E+03 mass  0.0E+00'
    Numbers may follow their label without a blank ('x-1.2E+01') and may use Fortran's
    exponent without a letter. Header, legend and blank lines are skipped. Labels are
    lower-cased; a label missing in a row gives NaN there. x/y/z are the force the other
    surface exerts on this one (LS-DYNA: on the master, the force of the slave on it)."""
    rows = {}
    with open(path) as f:
        for line in f:
            m = _RCFORC_ROW.match(line)
            if not m:
                continue
            values = {}
            for label, text in _LABEL_VALUE.findall(m.group(3)):
                try:
                    values[label.lower()] = _number(text.replace('D', 'E').replace('d', 'e'))
                except ValueError:
                    continue
            if 'time' not in values:
                continue
            role = _RCFORC_ROLES[m.group(1).lower()]
            rows.setdefault(int(m.group(2)), {}).setdefault(role, []).append(values)
    out = {}
    for interface, roles in sorted(rows.items()):
        out[interface] = {}
        for role, records in roles.items():
            labels = []
            for r in records:
                labels += [k for k in r if k not in labels]
            out[interface][role] = {k: np.array([r.get(k, np.nan) for r in records])
                                    for k in labels}
    return out


if __name__ == '__main__':
    print(__doc__)
    print('A library: import it (sys.path.insert(0, "post")); post/plot_histories.py plots a '
          'run\'s histories.')
