"""Homogeneous uniaxial compression of a block with the seed paper's hardening law: a patch
test of the whole nonlinear path (elements, finite-strain J2, Newton-Raphson, reactions).

A unit cube on rollers (x=0, y=0, z=0 faces) is compressed to 70 % of its height by a
prescribed displacement of its top face; E = 2000 MPa, nu = 0.3, sigma_y = 20 (1 + e_p)^1.1 MPa
(*MAT_POWER_LAW_PLASTICITY with K = 20, N = 1.1, SIGY = 20, the seed's law exactly). The stress is
uniaxial and uniform for any mesh, so at every output state:
- the top reaction equals K(alpha) A0 / lambda_z exactly (|tau_zz| = K(alpha) on the yield
  surface, F = tau_zz A0 / lambda_z): checked to 1e-6 relative, the Newton tolerance level;
- the equivalent plastic strain is the same in every cell (1e-5) and close to the logarithmic
  plastic strain |ln lambda_z| - sigma/E (Simo's update differs from it by up to ~(2/3) sigma/mu);
- the same run on 2 ranks gives the same reactions (1e-8).
Distorted meshes of ME-FEM tets (43), standard tets (10) and nodal-pressure tets (13, whose
tangent couples each element with its nodes' neighbours). Newton convergence is quadratic:
in steps of 4 or more iterations the last residual ratio is below 100 x the square of the one
before it.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import (ROOT, Checks, elements_card, f10, free, nodes_card, read_state, run,
                         write_deck, newton_end_ratios)
from test_patch import cube_mesh

OUT = os.path.join(ROOT, 'tests', 'out', 'implicit_compression')
E, NU, SIG0, A, B = 2000.0, 0.3, 20.0, 1.0, 1.1


def deck(elform, tight=False):
    x, conn, _ = cube_mesh(3)
    spc = ['*BOUNDARY_SPC_NODE']
    for n in range(len(x)):
        fixed = [1 if np.isclose(x[n, d], 0.0) else 0 for d in range(3)]
        if any(fixed):
            spc.append(f10(n + 1, 0, *fixed))
    top = [n for n in range(len(x)) if np.isclose(x[n, 2], 1.0)]
    motion = ['*BOUNDARY_PRESCRIBED_MOTION_NODE'] + [free(n + 1, 3, 2, 1, -0.3) for n in top]
    material = ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, elform),
                '*MAT_POWER_LAW_PLASTICITY', free(1, 2.7e-9, E, NU, SIG0 * A ** B, B), free(SIG0)]
    # tight: converge to the residual floor (ABSTOL only), so that runs on different numbers
    # of ranks can be compared beyond LS-DYNA's default DCTOL/ECTOL tolerances
    solution = free(12, 11, 40, 1e-14, 1e-20, 1e10, 0.9, 1e-9) if tight else f10(12)
    controls = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.1),
                '*CONTROL_IMPLICIT_SOLUTION', solution, '*CONTROL_IMPLICIT_AUTO', f10(1),
                '*DATABASE_BINARY_D3PLOT', f10(0.1),
                '*DEFINE_CURVE', f10(1), '%20.8e%20.8e' % (0, 0), '%20.8e%20.8e' % (1, 1)]
    name = 'compression_elform%d%s' % (elform, '_tight' if tight else '')
    path = os.path.join(OUT, name + '.k')
    write_deck(path, [nodes_card(x), elements_card('ELEMENT_SOLID', conn), material, controls,
                      spc, motion])
    return name, path


def reactions(h5):
    """(time, stretch, top force, cell plastic strains) of every state after state 0 (the
    unloaded model at t = 0)."""
    out = []
    import h5py
    with h5py.File(h5, 'r') as f:
        x = f['mesh/coordinates'][()]
        top = np.isclose(x[:, 2], 1.0)
        for k in sorted(f['states']):
            g = f['states'][k]
            if g.attrs['time'] == 0.0:
                continue
            lam = 1.0 + g['point/displacement'][()][top, 2].mean()
            force = -g['point/reaction_force'][()][top, 2].sum()
            alpha = g['cell/plastic_strain'][()][:, 0]
            out.append((g.attrs['time'], lam, force, alpha))
    return out


checks = Checks('implicit_compression')
for elform in (43, 10, 13):
    name, path = deck(elform)
    rc, text = run(path, os.path.join(OUT, name))
    checks.check(rc == 0, name + ': run succeeds', text[-500:])
    if rc != 0:
        continue
    # progress lines: the % of ENDTIM rising to 100 % with the wall time and an ETA
    progress = re.findall(r'^implicit: step (\d+) .* ([\d.]+) %  wall \S+  eta \S+$', text,
                          re.M)
    percents = [float(p) for _, p in progress]
    checks.check(len(progress) >= 2 and percents == sorted(percents) and percents[-1] == 100.0,
                 name + ': progress lines with %% done (%s) to 100 %%, wall time and ETA'
                 % ', '.join('%g' % p for p in percents), text[-400:])
    states = reactions(os.path.join(OUT, name, name + '.h5'))
    checks.check(len(states) == 10, name + ': 10 output states at the D3PLOT interval',
                 str(len(states)))
    # state 0: the unloaded model at t = 0 with every array of the later states, zero
    # (ParaView's filters need the arrays from the first state on; the deck has no node set,
    # test_implicit_histories has state 0's node sets)
    import h5py
    with h5py.File(os.path.join(OUT, name, name + '.h5'), 'r') as f:
        keys = sorted(f['states'])
        first, second = f['states'][keys[0]], f['states'][keys[1]]
        missing = [kind + '/' + a for kind in ('point', 'cell') for a in second[kind]
                   if a not in first[kind]]
        zero = all(np.all(first[kind][a][()] == 0) for kind in ('point', 'cell')
                   for a in second[kind])
        checks.check(first.attrs['time'] == 0.0 and not missing and zero,
                     name + ': state 0 at t = 0 carries every array of the later states (all '
                     'zero)', 'missing %s, zero %s' % (missing, zero))
    worst_force, worst_spread, worst_alpha = 0.0, 0.0, 0.0
    for time, lam, force, alpha in states:
        a = alpha.mean()
        k = SIG0 * (1 + A * a) ** B
        worst_force = max(worst_force, abs(force / (k / lam) - 1))
        worst_spread = max(worst_spread, (alpha.max() - alpha.min()) / max(a, 1e-12))
        worst_alpha = max(worst_alpha, abs(a - (abs(np.log(lam)) - k / E)))
    checks.check(worst_force < 1e-6, name + ': reaction = K(alpha) A0/lambda at every state',
                 '%.3e' % worst_force)
    checks.check(worst_spread < 1e-5, name + ': plastic strain uniform over the cells',
                 '%.3e' % worst_spread)
    mu = E / (2 * (1 + NU))
    checks.check(worst_alpha < 2 * 45.0 / mu, name + ': plastic strain = log plastic strain '
                 'within Simo\'s update difference', '%.3e' % worst_alpha)
    # quadratic convergence at the end of each Newton loop
    ratios = newton_end_ratios(text)
    quadratic = all(last < 100.0 * prev ** 2 or last < 1e-12 for prev, last in ratios)
    checks.check(len(ratios) > 0 and quadratic, name + ': quadratic convergence at the end of '
                 'every Newton loop', str(ratios[:5]))
    if elform in (43, 13):
        # the same deck converged to the residual floor on 1 and 2 ranks
        tname, tpath = deck(elform, tight=True)
        runs = []
        for ranks in (1, 2):
            rc2, text2 = run(tpath, os.path.join(OUT, tname + '_np%d' % ranks), ranks=ranks)
            checks.check(rc2 == 0, tname + ': run on %d rank(s) succeeds' % ranks, text2[-300:])
            if rc2 == 0:
                runs.append(reactions(os.path.join(OUT, tname + '_np%d' % ranks, tname + '.h5')))
        if len(runs) == 2:
            diff = max(abs(f1 / f2 - 1) for (_, _, f1, _), (_, _, f2, _) in zip(*runs))
            # residual floor |R| < 1e-9 N on forces of ~20 N, summed in rank-dependent order
            checks.check(len(runs[0]) == len(runs[1]) and diff < 1e-8,
                         tname + ': 1 and 2 ranks give the same reactions', '%.3e' % diff)
checks.exit()
