"""Thick-walled cylinder under internal pressure (Lame, formulation 7.5), plane strain, nearly
incompressible, through whole runs of bin/mefem.

Quarter ring a = 3 <= r <= b = 9, p = 1 on the inner arc (*LOAD_SEGMENT, N1 -> N2 with the
body on the left, so the pressure pushes the wall outwards), rollers on x = 0 and y = 0,
E = 1000, nu = 0.4999. Mesh: n_r x n_t quads (uniform in r and theta, n_t = 2 n_r), each cut
along the same diagonal. Exact: u_r(a) = 5.0623e-3; the mean pressure
p = -(s_r + s_t + s_z)/3 = -(1 + nu) * 2 p a^2 / (3 (b^2 - a^2)) = -0.124992 is constant.
Measures: u_r at r = a (mean over the inner nodes), the largest nodal error of u_r (relative
to u_r(a)), the RMS of (element pressure - exact)/p, and the mean |pressure difference|
between elements sharing an edge / p (the checkerboard measure).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks
from benchmarks import OUT, lame_case, lame_exact, lame_measures

checks = Checks('lame')
out = os.path.join(OUT, 'lame')
ur_exact = lame_exact(3.0)[0]
results = {}
for n_r in (8, 16):
    for elform in (43, 13):
        s, x, conn, inner, text = lame_case(n_r, 2 * n_r, elform, pattern='right', outdir=out)
        checks.check(s is not None, '%dx%d ELFORM %d: run succeeds' % (n_r, 2 * n_r, elform),
                     text[-400:])
        if s is not None:
            results[(n_r, elform)] = lame_measures(s, x, conn, inner)
            if (n_r, elform) == (8, 43):
                # the neighbour pairs come from the results' connectivity: it must be the deck's
                same = (s['connectivity'].shape == conn.shape and
                        (np.sort(s['connectivity'], axis=1) == np.sort(conn, axis=1)).all())
                checks.check(same, 'results connectivity (HDF5) is the deck connectivity')

if len(results) == 4:
    print('  mesh   ELFORM   u_r(a)        error      max u_r error  pressure RMS  '
          'neighbour jump')
    for (n_r, elform), m in sorted(results.items()):
        print('  %2dx%-3d  %2d   %.6e  %9.2e  %9.2e     %9.3e     %9.3e' % (
            n_r, 2 * n_r, elform, m['ur_a'], m['ur_a_error'], m['ur_max_error'],
            m['pressure_rms'], m['pressure_jump']))
    me, st = results[(16, 43)], results[(16, 13)]
    # u_r(a): the brief asks 1 % at a moderate mesh; measured 8.5e-4 (8x16) and 8.0e-5
    # (16x32), so 1 % at 8x16 and 0.1 % at 16x32 both hold with a margin of 10x or more.
    checks.check(results[(8, 43)]['ur_a_error'] < 0.01, 'ME-FEM u_r(a) within 1 %% of %.5e '
                 'at 8x16' % ur_exact, 'error %.3e' % results[(8, 43)]['ur_a_error'])
    checks.check(me['ur_a_error'] < 0.001, 'ME-FEM u_r(a) within 0.1 % at 16x32',
                 'error %.3e' % me['ur_a_error'])
    # Radial profile: largest nodal error of u_r relative to u_r(a); measured 8.7e-3 and
    # 2.5e-3, i.e. about h^1.8 (includes the polygonal approximation of the arcs). Assert
    # 1 % at 16x32 and a fall by at least 2x per halving.
    checks.check(me['ur_max_error'] < 0.01, 'ME-FEM u_r(r) within 1 % at every node (16x32)',
                 'max error %.3e' % me['ur_max_error'])
    checks.check(results[(8, 43)]['ur_max_error'] > 2 * me['ur_max_error'],
                 'ME-FEM u_r(r) error falls at least 2x from 8x16 to 16x32',
                 '%.3e -> %.3e' % (results[(8, 43)]['ur_max_error'], me['ur_max_error']))
    # Standard triangles lock on this mesh: measured u_r(a) 56 % and 53 % too small.
    checks.check(st['ur_a_error'] > 0.3, 'standard triangles lock: u_r(a) error > 30 % '
                 '(16x32)', 'error %.3e' % st['ur_a_error'])
    # Pressure: ME-FEM RMS error 5.0e-3 p (8x16) and 1.2e-3 p (16x32), neighbour jumps
    # 2.7e-3 p and 4.1e-4 p; the standard triangles checkerboard: RMS 3.1 p and 5.7 p, jumps
    # 4.2 p and 8.0 p (growing under refinement, 50 times the exact |p| = 0.125).
    # Thresholds: 1 % of p for ME-FEM (8x the measured RMS), more than 1 p for standard.
    checks.check(me['pressure_rms'] < 0.01, 'ME-FEM pressure RMS error < 1 % of p (16x32)',
                 'RMS %.3e' % me['pressure_rms'])
    checks.check(me['pressure_jump'] < 0.01, 'ME-FEM pressure smooth: mean neighbour jump '
                 '< 1 % of p (16x32)', 'jump %.3e' % me['pressure_jump'])
    checks.check(results[(8, 43)]['pressure_rms'] > 2 * me['pressure_rms'],
                 'ME-FEM pressure error falls at least 2x from 8x16 to 16x32',
                 '%.3e -> %.3e' % (results[(8, 43)]['pressure_rms'], me['pressure_rms']))
    checks.check(st['pressure_rms'] > 1.0 and st['pressure_jump'] > 1.0,
                 'standard triangles: checkerboard pressure (RMS and jump > p at 16x32)',
                 'RMS %.3e, jump %.3e' % (st['pressure_rms'], st['pressure_jump']))
    checks.check(st['pressure_jump'] > 100 * me['pressure_jump'],
                 'neighbour pressure jumps of ME-FEM at least 100x smaller than standard',
                 '%.3e vs %.3e' % (me['pressure_jump'], st['pressure_jump']))
checks.exit()
