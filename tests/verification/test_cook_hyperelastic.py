"""Cook's membrane, neo-Hookean, plane strain, nearly incompressible (formulation 7.3), through
whole nonlinear quasi-static runs of bin/mefem (Newton-Raphson, implicit_static.f90).

Trapezoid (0,0),(48,44),(48,60),(0,44), left edge clamped, right edge a uniform shear traction
of total force 100 per unit thickness as a dead load (consistent nodal forces of the reference
configuration, *LOAD_NODE_POINT with the curve 0 -> 1 over the end time 1), E = 240.565,
nu = 0.4999, plane strain. Reference v(48, 60) = 6.9083 (FinEALE
cookstrain3d_nonlinear_runner.m, "Data: Elguedj et al. CMAME 2008", 128x128 mesh).
Load steps: DT0 = 0.1 with *CONTROL_IMPLICIT_AUTO IAUTO=1. Meshes: N x N mapped quads, each cut
along the same diagonal (the pattern on which linear triangles lock worst), N = 4 ... 32.

Material: *MAT_ELASTIC is the compressible neo-Hookean law tau = mu (b - 1) + lambda ln(J) 1,
the form of FinEALE's material_deformation_neohookean_triax. The split form of
*MAT_MOONEY-RIVLIN_RUBBER with B = 0 (W = mu/2 (I1bar - 3) + U(J), same mu and bulk modulus)
is run at N = 16 and 32 as well: at nu = 0.4999 (J = 1 within ~1e-4) the two forms give the
same v to ~1e-5, so the choice of form does not matter here.

The convergence runs use tight Newton tolerances (DCTOL 1e-8, ECTOL 1e-14) so that the mesh
sequence is not blurred by the stopping error; one run with LS-DYNA's default tolerances and
one without the line search report the iteration counts. Numbers measured when the test was
written are given with each check; doc/verification.md has the table.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, elements_card, f10, free, nodes_card
from benchmarks import (OUT, boundary_facets, cook_grid, nodal_force_block,
                        quad_grid_triangles, solve, spc_block, uniform_traction_forces)

REFERENCE = 6.9083                 # v at (48, 60), formulation 7.3
YOUNG, POISSON, LOAD = 240.565, 0.4999, 100.0
TIGHT = free(12, 11, 25, 1.0e-8, 1.0e-14, 1.0e10, 0.9, 1.0e-20)   # default line search
DEFAULTS = f10(12)                                                # LS-DYNA defaults
NO_LINE_SEARCH = free(12, 11, 25, 1.0e-3, 1.0e-2, 1.0e10, 1.0e30, 1.0e-10)
out = os.path.join(OUT, 'cook_hyperelastic')


def cook_nonlinear(n, elform, material='elastic', solution=TIGHT, tag='tight'):
    """Cook's membrane at the total load 100; returns (v(48, 60), iterations per step, run
    text) or (None, None, text) when the run fails."""
    x = cook_grid(n)
    conn = quad_grid_triangles(n, n, 'right')
    dofs = {int(i): (1, 1, 1) for i in np.nonzero(np.abs(x[:, 0]) < 1e-9)[0]}
    right = [f for f in boundary_facets(conn) if np.all(np.abs(x[f, 0] - 48.0) < 1e-9)]
    force = uniform_traction_forces(x, right, [0.0, LOAD / 16.0])
    tip = int(np.argmin(np.linalg.norm(x - [48.0, 60.0], axis=1)))
    shear = YOUNG / (2.0 * (1.0 + POISSON))
    part = ['*PART', 'membrane', f10(1, 1, 1), '*SECTION_SHELL', f10(1, elform), f10(1.0)]
    if material == 'elastic':
        part += ['*MAT_ELASTIC', free(1, 1.0e-9, YOUNG, POISSON)]
    else:       # A = mu/2, B = 0: neo-Hookean with the same mu and bulk modulus
        part += ['*MAT_MOONEY-RIVLIN_RUBBER', free(1, 1.0e-9, POISSON, shear / 2.0, 0.0)]
    controls = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', free(1, 0.1),
                '*CONTROL_IMPLICIT_SOLUTION', solution, '*CONTROL_IMPLICIT_AUTO', f10(1),
                '*DATABASE_BINARY_D3PLOT', f10(1.0),
                '*DEFINE_CURVE', f10(1), '%20.8e%20.8e' % (0, 0), '%20.8e%20.8e' % (1, 1)]
    name = 'cooknl_n%d_elform%d_%s_%s' % (n, elform, material, tag)
    blocks = [nodes_card(x), elements_card('ELEMENT_SHELL', conn), part, controls,
              spc_block(dofs), nodal_force_block(force)]
    s, text = solve(name, out, blocks)
    if s is None:
        return None, None, text
    iterations = [int(m) for m in re.findall(r'step \d+: t = \S+, dt = \S+, (\d+) iterations',
                                             text)]
    return s['displacement'][tip, 1], iterations, text


def energy_ratios(text):
    """Per Newton loop, the printed energy ratios |du_k . R_k| / |du_1 . R_1| (k >= 2)."""
    loops = []
    for block in re.split(r'\nstep \d+: ', text):
        r = [float(m) for m in re.findall(r'energy ratio (\S+)', block)]
        if r:
            loops.append(r)
    return loops


def error(v):
    return abs(v / REFERENCE - 1.0)


checks = Checks('cook_hyperelastic')
sizes = (4, 8, 16, 32)
results = {}
for elform in (43, 13):
    for n in sizes:
        v, its, text = cook_nonlinear(n, elform)
        checks.check(v is not None, 'ELFORM %d N=%d: run succeeds' % (elform, n), text[-400:])
        results[(elform, n)] = (v, its, text)
ok = all(r[0] is not None for r in results.values())
if ok:
    print('    N   v ME-FEM (43)  error     v standard (13)  error     Newton iterations '
          'per step (ME-FEM)')
    for n in sizes:
        vm, its, _ = results[(43, n)]
        vs = results[(13, n)][0]
        print('  %3d  %12.5f  %+7.3f %%  %12.5f  %+7.3f %%   %s' % (
            n, vm, 100 * (vm / REFERENCE - 1), vs, 100 * (vs / REFERENCE - 1),
            ' '.join(str(i) for i in its)))
    mefem = [results[(43, n)][0] for n in sizes]
    # The target: within 2 % on moderate meshes. Measured -7.2 % (N=4), -1.83 % (8),
    # -0.51 % (16), -0.04 % (32): within 2 % from N = 8 on; the tolerance is the target.
    for n, v in zip(sizes[1:], mefem[1:]):
        checks.check(error(v) < 0.02, 'ME-FEM triangles within 2 %% of %.4f at N=%d'
                     % (REFERENCE, n), 'v = %.5f, error %.3f %%' % (v, 100 * error(v)))
    # Convergence with refinement, measured on our own sequence (the reference itself is
    # only known to ~0.3 %): the change of v per halving of h must fall at least 2x
    # (measured 0.372, 0.091, 0.033: ratios 4.1 and 2.8; a locking or inconsistent element
    # would not converge like this).
    steps = np.abs(np.diff(mefem))
    ratios = steps[:-1] / steps[1:]
    print('    ME-FEM change of v per halving: %s; ratios %s' % (
        ', '.join('%.4f' % d for d in steps), ', '.join('%.2f' % r for r in ratios)))
    checks.check(np.all(ratios > 2.0) and np.all(np.diff(mefem) > 0),
                 'ME-FEM v increases monotonically, its change falls at least 2x per halving',
                 'changes %s' % steps)
    # Richardson extrapolation of N = 8, 16, 32 (observed order log2 of the last ratio):
    # measured 6.924, +0.23 % from the reference. N = 64 (run once by hand) gives a
    # ratio of 2.2 and a limit of 6.934 (+0.37 %): the reference's own discretisation error
    # (FinEALE's plot file also quotes 6.932 as the converged value) is of that size, so 1 %.
    limit = mefem[-1] + steps[-1] / (ratios[-1] - 1.0)
    print('    Richardson limit (N = 8, 16, 32): %.5f (%+.3f %%)' % (
        limit, 100 * (limit / REFERENCE - 1)))
    checks.check(error(limit) < 0.01, 'ME-FEM extrapolated limit within 1 % of the reference',
                 '%.5f' % limit)
    # Standard triangles lock: measured v = 2.15-2.33 (66-69 % too stiff) up to N = 32.
    for n in sizes:
        v = results[(13, n)][0]
        checks.check(error(v) > 0.30, 'standard triangles lock at N=%d (error > 30 %%)' % n,
                     'v = %.5f, error %.3f %%' % (v, 100 * error(v)))
    # Newton converges quadratically at the end of every step (consistent tangent of the
    # ME-FEM cells and the neo-Hookean law), measured on the energy norm |du . R| relative to
    # the first iteration's (the residual norm is dominated by the stiff volumetric modes and
    # is not monotone here): the observed order log(e_k+1/e_k)/log(e_k/e_k-1) over three
    # successive energies above the round-off floor (1e-22) reaches at least 1.7 in every
    # loop (measured 1.8-2.2, e.g. 9e-7 -> 8.4e-10 -> 2.7e-15 -> 1.2e-25); linear convergence
    # gives 1.
    for n in (16, 32):
        loops = energy_ratios(results[(43, n)][2])
        orders = []
        for r in loops:
            o = [np.log(c / b) / np.log(b / a) for a, b, c in zip(r, r[1:], r[2:])
                 if c > 1e-22 and b < a]
            orders.append(max(o) if o else 0.0)
        good = [o >= 1.7 for o in orders]
        checks.check(len(loops) > 0 and all(good), 'ME-FEM N=%d: quadratic convergence at '
                     'the end of every Newton loop' % n, 'orders %s' % ', '.join(
                         '%.2f' % o for o in orders))

# ---- the two neo-Hookean forms ----------------------------------------------------------
for n in (16, 32):
    v_split, _, text = cook_nonlinear(n, 43, material='mooney_rivlin')
    checks.check(v_split is not None, 'Mooney-Rivlin B=0 N=%d: run succeeds' % n, text[-400:])
    if v_split is not None and ok:
        v = results[(43, n)][0]
        # measured relative difference 6e-6 (N = 16 and 32): at nu = 0.4999, J - 1 ~ 1e-4
        # and the forms differ at that order; 1e-4 allows for it
        print('    N=%d: v *MAT_ELASTIC %.5f, *MAT_MOONEY-RIVLIN_RUBBER (B=0) %.5f' % (
            n, v, v_split))
        checks.check(abs(v_split / v - 1) < 1e-4, 'N=%d: compressible and split '
                     'neo-Hookean forms agree to 1e-4' % n, '%.5f vs %.5f' % (v_split, v))

# ---- iteration counts with LS-DYNA's default tolerances, with and without line search ----
for label, solution in (('defaults', DEFAULTS), ('no line search', NO_LINE_SEARCH)):
    tag = 'defaults' if solution is DEFAULTS else 'nols'
    v, its, text = cook_nonlinear(16, 43, solution=solution, tag=tag)
    checks.check(v is not None, 'N=16 %s: run succeeds' % label, text[-400:])
    if v is None:
        continue
    print('    N=16 %s: v = %.5f, %d steps, Newton iterations per step: %s, cut-backs: %d'
          % (label, v, len(its), ' '.join(str(i) for i in its), text.count('cut back')))
    if ok:
        # DCTOL 1e-3 / ECTOL 1e-2 stop the loops early; measured difference 3e-7 to the tight
        # run (defaults) and 4e-6 (no line search); 1e-3 is the DCTOL level
        checks.check(abs(v / results[(43, 16)][0] - 1) < 1e-3, 'N=16 %s: same v as the '
                     'tight run to 1e-3' % label, '%.5f' % v)
    # with the line search every step converges without a cut-back (measured 6 steps of 4-9
    # iterations); without it the extrapolating predictor overshoots where the step grows and
    # a few steps are cut back (measured 3): reported, not required
    if solution is DEFAULTS:
        checks.check(text.count('cut back') == 0, 'N=16 %s: no step cut back' % label,
                     str(text.count('cut back')))
checks.exit()
