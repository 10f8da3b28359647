"""Small helpers that write LS-DYNA keyword decks for mefem's verification tests.

Decks are written in fixed format (I8/E16 for *NODE, I8 for elements, 10-wide fields for
other cards), as a pre-processor would write them, so the tests also exercise the reader.
"""
import os
import subprocess

import numpy as np
import h5py

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
MPIRUN = ['mpirun', '--oversubscribe']


def f10(*values):
    """A card of 10-wide fields (ints as ints, reals in E format)."""
    out = ''
    for v in values:
        if v is None:
            out += ' ' * 10
        elif isinstance(v, (int, np.integer)):
            out += '%10d' % v
        else:
            out += '%10.4g' % v if abs(v) >= 1e-3 or v == 0 else '%10.3e' % v
    return out


def free(*values):
    """A comma-separated card with full precision (free format)."""
    return ','.join('' if v is None else (str(int(v)) if isinstance(v, (int, np.integer))
                                            else repr(float(v))) for v in values)


def nodes_card(x, ids=None):
    """*NODE block: x is (n, 2 or 3)."""
    lines = ['*NODE']
    n = len(x)
    ids = np.arange(1, n + 1) if ids is None else ids
    for i in range(n):
        p = list(x[i]) + [0.0] * (3 - len(x[i]))
        lines.append('%8d%16.9e%16.9e%16.9e' % (ids[i], p[0], p[1], p[2]))
    return lines


def elements_card(keyword, conn, pid=1, first_id=1):
    """*ELEMENT_SHELL (triangles, N4 = N3) or *ELEMENT_SOLID (tets, one-line legacy form)."""
    lines = ['*' + keyword]
    for k, c in enumerate(conn):
        c = [int(v) + 1 for v in c]
        if keyword == 'ELEMENT_SHELL':
            c = c + [c[-1]] * (4 - len(c))
        else:
            c = c + [c[-1]] * (8 - len(c))
        lines.append('%8d%8d' % (first_id + k, pid) + ''.join('%8d' % v for v in c))
    return lines


def material_part(elform, young, poisson, dim, density=7.85e-9):
    """*PART, section (shell plane strain in 2D / solid in 3D) and *MAT_ELASTIC, ids 1."""
    lines = ['*PART', 'body', f10(1, 1, 1)]
    if dim == 2:
        lines += ['*SECTION_SHELL', f10(1, elform), f10(1.0)]
    else:
        lines += ['*SECTION_SOLID', f10(1, elform)]
    lines += ['*MAT_ELASTIC', f10(1, density, young, poisson)]
    return lines


def linear_static_controls(end_time=1.0):
    return ['*CONTROL_TERMINATION', f10(end_time),
            '*CONTROL_IMPLICIT_GENERAL', f10(1, end_time),
            '*CONTROL_IMPLICIT_SOLUTION', f10(1)]


def unit_curve(lcid=1, end_time=1.0):
    return ['*DEFINE_CURVE', f10(lcid), '%20.8e%20.8e' % (0.0, 1.0),
            '%20.8e%20.8e' % (end_time, 1.0)]


def write_deck(path, blocks, title='mefem verification'):
    lines = ['*KEYWORD', '*TITLE', title]
    for b in blocks:
        lines += b
    lines.append('*END')
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def run(deck, outdir, ranks=1, exe='bin/mefem'):
    """Run mefem; return (returncode, output text)."""
    cmd = [os.path.join(ROOT, exe), '-o', outdir, deck]
    if ranks > 1:
        cmd = MPIRUN + ['-np', str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1', OPENBLAS_NUM_THREADS='1')
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
    return p.returncode, p.stdout + p.stderr


def newton_end_ratios(text):
    """(second-to-last, last) relative residual of every Newton loop of 3 or more iterations
    in an implicit run's log (quadratic convergence: last < C prev^2)."""
    import re
    ratios = []
    for block in re.split(r'\nstep ', text):
        res = [float(m) for m in re.findall(r'\|R\| = \S+ \((\S+)\)', block)]
        if len(res) >= 3:
            ratios.append((res[-2], res[-1]))
    return ratios


def read_state(h5path, step=1):
    """Node ids, coordinates, displacement (nnode, 3), and cell fields of a state."""
    with h5py.File(h5path, 'r') as f:
        g = f['states/%06d' % step]
        out = {'node_ids': f['mesh/node_ids'][()], 'x': f['mesh/coordinates'][()],
               'cell_ids': f['mesh/cell_ids'][()]}
        for name in g['point']:
            out[name] = g['point'][name][()]
        for name in g['cell']:
            out[name] = g['cell'][name][()]
    return out


class Checks:
    """PASS/FAIL lines for the test runner."""

    def __init__(self, suite):
        self.suite = suite
        self.failed = 0

    def check(self, cond, what, detail=''):
        tag = 'PASS' if cond else 'FAIL'
        print('%s: %s: %s%s' % (tag, self.suite, what, '' if cond else ': ' + detail))
        if not cond:
            self.failed += 1

    def exit(self):
        raise SystemExit(1 if self.failed else 0)
