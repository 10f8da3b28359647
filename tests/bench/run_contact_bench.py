#!/usr/bin/python3
"""Contact benchmark (make bench; doc/performance.md "Contact"): a thin plate of ME-FEM tets
(N x N x 1 cubes of 6 tets) pressed onto a rigid plate of shell quads by a pressure, mortar
contact SURFA = the plate's part (its exterior: the N x N x 2 bottom triangles in contact, the
top and side faces not), frictionless and with friction, ENDCYC cycles, on 1 and 2 ranks. Prints
the contact time per cycle, per slave facet and cycle, and its share of the cycle.

usage: tests/bench/run_contact_bench.py [--small]   (default N = 160: 51 200 contact facets)
environment: MEFEM (binary, default bin/mefem: e.g. an older build for before/after),
BENCH_CONTACT_RANKS (default "1 2"), BENCH_CONTACT_FRICTION (default "0 0.2").
The sheet starts 0.01 mm above the tool, inside the search margin: every bottom facet has its
candidates and overlapping partners from the first cycle, so the search, the mortar kernels and
the driver do their full work, but within the run the sheet does not yet touch the tool (zero
pressure; the friction return map is not exercised).
Columns: wall s of the run, the driver's wall time per cycle and contact time per cycle (rank
0), contact ns per bottom facet and cycle, the contact share of rank 0's cycle, and the CPU
share of the run (CPU time of all processes / (wall x ranks): below 1 when other jobs shared
the cores, and the wall figures of that row are inflated).
"""
import os
import re
import resource
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import f10, free, nodes_card, elements_card, write_deck, MPIRUN  # noqa: E402
from explicit_cases import box_tets, node_set                                     # noqa: E402
from benchmarks import boundary_facets                                            # noqa: E402

N = 40 if '--small' in sys.argv else 160
CYCLES = 50 if '--small' in sys.argv else 100
OUT = os.path.join(ROOT, 'tests', 'out', 'bench_contact')
SIZE, THICK = 100.0, 1.0                          # mm
E, NU, RHO, P = 70000.0, 0.3, 2.7e-9, 10.0        # aluminium, MPa pressure


def deck(friction):
    x, conn = box_tets(SIZE, SIZE, THICK, N, N, 1)
    x = x + [0.0, 0.0, 0.01]                      # 0.01 mm above the tool
    m = 40
    g = np.array([[-1.0 + i * (SIZE + 2) / m, -1.0 + j * (SIZE + 2) / m, 0.0]
                  for j in range(m + 1) for i in range(m + 1)])
    quads = np.array([[j * (m + 1) + i, j * (m + 1) + i + 1, (j + 1) * (m + 1) + i + 1,
                       (j + 1) * (m + 1) + i] for j in range(m) for i in range(m)])
    top = []
    for f in boundary_facets(conn):
        f = [int(v) for v in f]
        if all(abs(x[v, 2] - THICK - 0.01) < 1e-9 for v in f):
            if np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[2] < 0:
                f = [f[0], f[2], f[1]]
            top.append(f10(f[0] + 1, f[1] + 1, f[2] + 1, f[2] + 1))
    n = len(x)
    return [nodes_card(np.vstack([x, g])), elements_card('ELEMENT_SOLID', conn, pid=1),
            elements_card('ELEMENT_SHELL', quads + n, pid=2, first_id=len(conn) + 1),
            ['*PART', 'sheet', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
             '*MAT_ELASTIC', free(1, RHO, E, NU),
             '*PART', 'tool', f10(2, 2, 2), '*SECTION_SHELL', f10(2, 2), f10(1.0, 1.0, 1.0, 1.0),
             '*MAT_RIGID', free(2, 7.85e-9, 210000.0, 0.3), f10(1.0, 7, 7)],
            ['*SET_SEGMENT', f10(9)] + top, ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
            ['*DEFINE_CURVE', f10(1), '%20.8e%20.8e' % (0, P), '%20.8e%20.8e' % (1, P)],
            ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR', f10(1, 2, 3, 3),
             f10(friction, friction), f10(1.0, 1.0)],
            ['*CONTROL_TERMINATION', free(0.0, CYCLES)]], len(conn)


print('contact benchmark: %d x %d x 1 cubes x 6 ME-FEM tets on a rigid plate, %d cycles' % (
    N, N, CYCLES))
print('%-12s %5s %10s %12s %14s %18s %10s %10s' % ('case', 'ranks', 'wall s', 'cycle ms',
                                                  'contact ms', 'ns/facet-cycle', 'share %',
                                                  'CPU share'))
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1', OPENBLAS_NUM_THREADS='1')
binary = os.environ.get('MEFEM', os.path.join(ROOT, 'bin', 'mefem'))
rank_counts = [int(v) for v in os.environ.get('BENCH_CONTACT_RANKS', '1 2').split()]
frictions = [float(v) for v in os.environ.get('BENCH_CONTACT_FRICTION', '0 0.2').split()]
for friction in frictions:
    blocks, nelem = deck(friction)
    path = os.path.join(OUT, 'contact_bench_fs%g.k' % friction)
    write_deck(path, blocks, title='contact benchmark')
    for ranks in rank_counts:
        cmd = [binary, '-o', os.path.join(OUT, 'run'), path]
        if ranks > 1:
            cmd = MPIRUN + ['-np', str(ranks)] + cmd
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu0 = usage.ru_utime + usage.ru_stime
        t0 = time.time()
        p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
        wall = time.time() - t0
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu_share = (usage.ru_utime + usage.ru_stime - cpu0) / (wall * ranks)
        text = p.stdout + p.stderr
        if p.returncode != 0:
            print('run failed:', text[-800:])
            continue
        share = float(re.search(r'contact (\S+) %', text).group(1))
        per_cycle = float(re.search(r'contact (\S+) s per cycle', text).group(1))
        cycle = float(re.search(r'average wall time per cycle\s+(\S+) s', text).group(1))
        facets = 2 * N * N                          # the bottom facets in contact
        print('%-12s %5d %10.1f %12.3f %14.3f %18.1f %10.1f %10.2f' % (
            'FS=%g' % friction, ranks, wall, 1e3 * cycle, 1e3 * per_cycle,
            1e9 * per_cycle / facets, share, cpu_share), flush=True)
