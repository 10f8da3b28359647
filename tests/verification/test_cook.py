"""Cook's membrane, linear, plane strain, nearly incompressible (formulation 7.2), through
whole runs of bin/mefem; and the same run on 1 and 2 MPI ranks.

Trapezoid (0,0),(48,44),(48,60),(0,44), left edge clamped, right edge a uniform shear traction
of total force 1 per unit thickness (consistent nodal forces), G = 0.375, lambda = 7500
(nu = 0.499975). Reference v(48, 52) = 16.4326 (FinEALE, NICE-T6 + Richardson). Meshes: N x N
mapped quads, each cut along the same diagonal (the pattern on which linear triangles lock
worst). 3D: the same membrane as a slab of thickness 1, one layer, every hexahedron cut into
6 tets, u_z = 0 on both faces (plane strain). Numbers measured when the test was written are
given with each check; doc/verification.md has the tables and post/convergence_study.py the
finer meshes.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks
from benchmarks import COOK_REFERENCE, OUT, cook_case

checks = Checks('cook')
out = os.path.join(OUT, 'cook')


def error(v):
    return abs(v / COOK_REFERENCE - 1.0)


def solve_all(dim, elform, sizes, **options):
    values = {}
    for n in sizes:
        v, s, text = cook_case(n, elform, dim=dim, outdir=out, **options)
        checks.check(v is not None, '%dD ELFORM %d N=%d: run succeeds' % (dim, elform, n),
                     text[-400:])
        if v is None:
            return None
        values[n] = (v, s)
    return values


# ---- 2D triangles ---------------------------------------------------------------------
sizes = (4, 8, 16, 32)
mefem = solve_all(2, 43, sizes)
standard = solve_all(2, 13, sizes)
if mefem and standard:
    print('    N   v ME-FEM (43)  error     v standard (13)  error')
    for n in sizes:
        print('  %3d  %12.5f  %7.3f %%  %12.5f  %7.3f %%' % (
            n, mefem[n][0], 100 * error(mefem[n][0]), standard[n][0],
            100 * error(standard[n][0])))
    # The target: within 2 % on moderate meshes. Measured 1.51 % (N=8), 0.41 % (16),
    # 0.11 % (32); the tolerance is the target itself.
    for n in (8, 16, 32):
        checks.check(error(mefem[n][0]) < 0.02, 'ME-FEM triangles within 2 %% of %.4f at N=%d'
                     % (COOK_REFERENCE, n), 'v = %.5f, error %.3f %%'
                     % (mefem[n][0], 100 * error(mefem[n][0])))
    # Convergence: the error must fall by at least 2x per mesh halving (measured 4.6, 3.7,
    # 3.8x). A locking or inconsistent element would not.
    ratios = [error(mefem[a][0]) / error(mefem[b][0]) for a, b in zip(sizes, sizes[1:])]
    print('    ME-FEM error ratios per halving: %s' % ', '.join('%.2f' % r for r in ratios))
    checks.check(min(ratios) > 2.0, 'ME-FEM error falls at least 2x per halving of h',
                 'ratios %s' % ', '.join('%.2f' % r for r in ratios))
    # Locking of the standard triangles: measured 71-72 % too stiff at every N up to 32
    # (v = 4.6 - 4.8); assert more than 30 % error, the sign of locking, not a digit.
    for n in sizes:
        checks.check(error(standard[n][0]) > 0.30, 'standard triangles lock at N=%d '
                     '(error > 30 %%)' % n, 'v = %.5f, error %.3f %%'
                     % (standard[n][0], 100 * error(standard[n][0])))

# ---- 3D tets (slab, plane strain) -----------------------------------------------------
sizes3 = (8, 16, 32)
mefem3 = solve_all(3, 43, sizes3)
standard3 = solve_all(3, 10, (16, 32))
if mefem3 and standard3:
    print('    N   v ME-FEM tet (43)  error   v standard tet (10)  error')
    for n in sizes3:
        sv = standard3[n][0] if n in standard3 else float('nan')
        print('  %3d  %12.5f  %7.3f %%  %12.5f  %7.3f %%' % (
            n, mefem3[n][0], 100 * error(mefem3[n][0]), sv, 100 * error(sv)))
    # The slab is plane strain: v must not vary through the thickness (both faces' nodes at
    # (48, 52) agree to 1e-3 relative; measured 4e-4 at N=32, from the unsymmetric tet cut).
    v_levels = mefem3[32][1]['displacement'][mefem3[32][1]['probe'], 1]
    spread = np.ptp(v_levels) / abs(v_levels.mean())
    print('    relative spread of v(48, 52) over the two faces at N=32: %.2e' % spread)
    checks.check(spread < 1e-3, 'ME-FEM tets: v(48, 52) the same on both faces of the slab',
                 'relative spread %.2e' % spread)
    # Measured errors of the ME-FEM tets: 61.9 % (N=8), 32.2 % (16), 9.2 % (32): the tets
    # converge, the 2 % target is not reached at N <= 32 (64: see the doc). Assert the
    # convergence (error falling, at least 1.5x per halving) and that they clearly beat the
    # locking standard tets (71.5 %, 70.7 %): at most half their error at N=16 and 32.
    e3 = [error(mefem3[n][0]) for n in sizes3]
    checks.check(all(a > 1.5 * b for a, b in zip(e3, e3[1:])),
                 'ME-FEM tets: error falls at least 1.5x per halving of h',
                 ', '.join('%.3f %%' % (100 * e) for e in e3))
    for n in (16, 32):
        checks.check(error(mefem3[n][0]) < 0.5 * error(standard3[n][0]),
                     'ME-FEM tets at most half the error of standard tets at N=%d' % n,
                     '%.3f %% vs %.3f %%' % (100 * error(mefem3[n][0]),
                                             100 * error(standard3[n][0])))
        checks.check(error(standard3[n][0]) > 0.30, 'standard tets lock at N=%d '
                     '(error > 30 %%)' % n, 'error %.3f %%' % (100 * error(standard3[n][0])))
    # Regression guard of the current 3D accuracy (not the target): 9.23 % measured.
    checks.check(e3[-1] < 0.10, 'ME-FEM tets within 10 % at N=32 (current accuracy)',
                 'error %.3f %%' % (100 * e3[-1]))

# ---- 3D slab: the in-plane cut pattern, not the flatness, decides ------------------------
# Issue 20's slab (one layer, in-plane size 2x the thickness: N = 24 and 48 at thickness 1)
# cut from prisms over alternating ("union jack") diagonals instead of the hexahedra's one
# diagonal. The Kuhn split of the hexahedra is exactly the prism split over one diagonal (same
# tets), the pattern on which linear elements lock worst. Measured: ME-FEM -2.02 % (N=24),
# -0.56 % (48); standard tets -3.53 %, -1.10 %; the same-diagonal slab -15.9 %, -4.4 %
# (doc/verification.md). The targets (5 % at 24, 2 % at 48) are the tolerances; that
# ME-FEM beats the standard tet on this mesh too is asserted as well. Flatness: the same N=24
# membrane with thickness 0.5 (in-plane size 4x the thickness) and 4 (half) measured -2.27 %
# and -1.84 %: within the same 5 %.
slab = {}
for n, t in ((24, 1.0), (48, 1.0), (24, 0.5), (24, 4.0)):
    for elform in (43, 10) if t == 1.0 else (43,):
        v, s, text = cook_case(n, elform, dim=3, split='prism3', pattern='alternate',
                               thickness=t, outdir=out)
        checks.check(v is not None, 'slab N=%d t=%g ELFORM %d: run succeeds' % (n, t, elform),
                     text[-400:])
        slab[n, t, elform] = v
if None not in slab.values():
    for (n, t, elform), v in sorted(slab.items()):
        print('    slab (alternating prisms) N=%d thickness %g ELFORM %d: v = %.5f, error '
              '%.3f %%' % (n, t, elform, v, 100 * error(v)))
    for n, t, target in ((24, 1.0, 0.05), (48, 1.0, 0.02), (24, 0.5, 0.05), (24, 4.0, 0.05)):
        checks.check(error(slab[n, t, 43]) < target, 'ME-FEM slab N=%d thickness %g within '
                     '%g %%' % (n, t, 100 * target), 'error %.3f %%' % (100 * error(slab[n, t, 43])))
    for n in (24, 48):
        checks.check(error(slab[n, 1.0, 43]) < error(slab[n, 1.0, 10]),
                     'ME-FEM slab N=%d more accurate than standard tets' % n, '%.3f %% vs %.3f %%'
                     % (100 * error(slab[n, 1.0, 43]), 100 * error(slab[n, 1.0, 10])))

# ---- 3D slab with hexahedra (1, 2) and nodal-pressure tets (13) --------------------------
# The same one-layer slab (thickness 1, N = 24 and 48) with the other solid elements of real
# decks. Measured when written: one-point hexahedra (static hourglass stiffness IHQ 6 at the
# default QM 0.1) -0.07 % (24), +0.03 % (48); at IHQ 6, QM 1 -1.07 %, -0.34 %; ELFORM 2, which
# mefem computes as ELFORM 1 with IHQ 6, QM 1 (warned; a fully integrated selectively reduced
# hexahedron would not lock either, a fully integrated one would), the same bits; ELFORM 13 on
# the hexahedra cut around one diagonal -5.70 %, -1.92 % (ME-FEM -15.94 %, -4.42 %; the
# standard tet -71 %), on alternating prisms -2.30 %, -0.74 %. Tolerances: issue 20's slab
# targets (5 % at 24, 2 % at 48); where ELFORM 13 misses the first on the one-diagonal cut,
# it is checked to converge (error at least 2.5 times smaller at 48: measured 2.97; a locking
# element stays near its error, as the standard tet's -71 %, -69 % show).
hexslab = {}
for n in (24, 48):
    for label, elform, split, pattern, hourglass in (
            ('hex', 1, 'hex', 'right', None), ('hex qm1', 1, 'hex', 'right', (6, 1.0)),
            ('elform2', 2, 'hex', 'right', None), ('13 diagonal', 13, 'hex6', 'right', None),
            ('13 alternate', 13, 'prism3', 'alternate', None)):
        if n == 48 and label in ('hex qm1', 'elform2'):
            continue
        v, s, text = cook_case(n, elform, dim=3, split=split, pattern=pattern,
                               hourglass=hourglass, outdir=out)
        checks.check(v is not None, 'slab N=%d %s: run succeeds' % (n, label), text[-400:])
        hexslab[n, label] = (v, s, text)
if all(r[0] is not None for r in hexslab.values()):
    for (n, label), (v, s, text) in sorted(hexslab.items()):
        print('    slab N=%d %-13s v = %.5f, error %.3f %%' % (n, label, v, 100 * error(v)))
    for n, target in ((24, 0.05), (48, 0.02)):
        for label in ('hex', '13 alternate') + (('hex qm1',) if n == 24 else ()):
            e = error(hexslab[n, label][0])
            checks.check(e < target, 'slab N=%d %s within %g %%' % (n, label, 100 * target),
                         'error %.3f %%' % (100 * e))
    e24, e48 = error(hexslab[24, '13 diagonal'][0]), error(hexslab[48, '13 diagonal'][0])
    checks.check(e48 < 0.02 and e24 / e48 > 2.5, 'slab ELFORM 13, one diagonal: within 2 % at '
                 'N=48, error 2.5 times smaller than at 24', '%.3f %%, %.3f %%'
                 % (100 * e24, 100 * e48))
    v2, s2, text2 = hexslab[24, 'elform2']
    checks.check(np.array_equal(s2['displacement'], hexslab[24, 'hex qm1'][1]['displacement']),
                 'slab ELFORM 2 = ELFORM 1 with IHQ 6, QM 1 (same bits)')
    checks.check('solid ELFORM 2 (fully integrated hexahedron) is computed as ELFORM 1' in text2
                 and 'part 1' in text2, 'slab ELFORM 2: the substitution is warned, naming the '
                 'part', text2[-600:])

# ---- 1 and 2 MPI ranks -----------------------------------------------------------------
# Same deck, 2D ME-FEM, N=16. Rank counts change how MUMPS distributes the factorisation
# and the summation order of the assembly (the METIS pivot order is the same), so the
# solutions differ by round-off amplified by the condition number. At nu = 0.3 that is far
# below 1e-10 (measured 4.7e-14; 1.4e-15 with the PORD ordering before). At nu = 0.499975
# (lambda/G = 2e4 multiplies the condition number) the measured differences were 0.7-1.7e-10
# for N = 8...32 with PORD (also 1 vs 3 ranks) and 1.5-2.0e-10 with METIS: round-off, not a
# decomposition error, so the tolerance there is 1e-9.
for poisson, tolerance in ((0.3, 1e-10), (None, 1e-9)):
    label = 'nu=%s' % ('0.3' if poisson else '0.499975')
    runs = [cook_case(16, 43, poisson=poisson, ranks=r, outdir=out, tag='_np%d' % r)
            for r in (1, 2)]
    ok = all(r[0] is not None for r in runs)
    checks.check(ok, 'ranks %s: runs on 1 and 2 ranks succeed' % label,
                 ' | '.join(r[2][-300:] for r in runs))
    if ok:
        u1, u2 = runs[0][1]['displacement'], runs[1][1]['displacement']
        diff = np.abs(u1 - u2).max() / np.abs(u1).max()
        print('    %s: max relative difference 1 vs 2 ranks %.3e' % (label, diff))
        checks.check(diff < tolerance, 'ranks %s: 1 and 2 ranks give the same displacements '
                     'to %g relative' % (label, tolerance), 'max difference %.3e' % diff)
checks.exit()
