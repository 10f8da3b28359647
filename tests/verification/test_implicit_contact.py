"""Implicit (Newton-Raphson) mortar contact with rigid tools (issue 6): frictionless penalty
contact with the frozen-geometry tangent of formulation 5.5. A block is compressed by a rigid
tool (a *MAT_RIGID part moved by *BOUNDARY_PRESCRIBED_MOTION_RIGID VAD=2) that is wider than
the block: uniaxial stress, so the tool's force must be E' delta A (E' = E/(1 - nu^2) in plane
strain, E in 3D, delta the strain of the block read from its top), and for a flat tool the
frozen tangent is the exact one, so each load step converges in very few iterations. 2D plane
strain (ME-FEM triangles, a tool of in-plane quads) and 3D (ME-FEM tets, a tool of shell quads);
non-matching meshes. Units mm, N, MPa.

Friction (Coulomb, FS = mu = 0.3): the tool first presses the block (t = 0 ... 0.5), then
moves sideways (t = 0.5 ... 1). Sliding (the tool moves 5 % of the block's size): every
contact node slides, so the friction force is mu times the normal force. Sticking (the tool
moves 2e-4, below the elastic slip mu p / eps_T of the tangential penalty): the friction force
stays below mu N, the block's top is dragged along, and the friction force is the tangential
penalty's spring force eps_T (A s - integral of u_x over the top), eps_T read from the log.
"""
import os
import re
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks
from explicit_cases import run_case
from implicit_cases import E, NU, DELTA, tool_block_deck as deck
from lsdyna_ascii import read_rcforc

checks = Checks('implicit_contact')


for dim in (2, 3):
    nb, blocks = deck(dim)
    for ranks in (1, 2):
        name = 'implicit_tool_%dd_np%d' % (dim, ranks)
        rc, text, out = run_case(name, blocks, ranks=ranks)
        checks.check(rc == 0, '%dD on %d rank(s): run succeeds' % (dim, ranks), text[-600:])
        if rc != 0:
            continue
        r = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']
        force = r['y' if dim == 2 else 'z']
        if ranks == 2:
            diff = np.max(abs(force - ref)) / np.max(abs(ref))
            # measured 3.6e-11: the contact is the same on every rank, the solution to MUMPS's
            # round-off
            checks.check(diff < 1e-8, '%dD: 1 and 2 ranks give the same tool force' % dim,
                         '%.3e' % diff)
            continue
        ref = force
        iterations = [int(m) for m in re.findall(r'step \d+: t = \S+, dt = \S+, (\d+) iterations',
                                                 text)]
        with h5py.File(os.path.join(out, name + '.h5')) as f:
            states = sorted(f['states'].keys())[1:]
            xs = f['mesh/coordinates'][()]
            ids = f['mesh/node_ids'][()]
            top = (abs(xs[:, dim - 1] - 1.0) < 1e-9) & (ids <= nb)
            strains = [-f['states/%s/point/displacement' % k][()][top, dim - 1].mean()
                       for k in states]
        modulus = E / (1 - NU ** 2) if dim == 2 else E
        expected = modulus * np.array(strains)
        err = np.max(abs(force / expected - 1))
        print('    %dD: tool force %s N, E\' delta A %s N (max error %.1e); tool penetration '
              '%.1e of its motion; Newton iterations per step %s' % (
                  dim, ' '.join('%.5f' % v for v in force), ' '.join('%.5f' % v for v in expected),
                  err, 1 - strains[-1] / DELTA, iterations))
        # measured 8e-4 (2D) / 1e-3 (3D): the finite-strain response at 0.1 % strain
        checks.check(err < 5e-3, '%dD: tool force = E\' delta A within 0.5 %%' % dim,
                     '%.3e' % err)
        # the penalty (100 K/h) lets the tool penetrate 1e-3..1e-2 of its motion
        checks.check(0.0 < 1 - strains[-1] / DELTA < 0.02, '%dD: the block follows the tool '
                     '(penetration below 2 %% of the motion)' % dim,
                     '%.3e' % (1 - strains[-1] / DELTA))
        # flat tool: the frozen-geometry tangent is exact: 2 iterations per step (measured)
        checks.check(max(iterations) <= 3, '%dD: Newton converges in at most 3 iterations per '
                     'step' % dim, str(iterations))


def newton_iterations(text):
    return [int(m) for m in re.findall(r'step \d+: t = \S+, dt = \S+, (\d+) iterations', text)]


MU_SLIDE, SLIDE = 0.3, 0.05
SLIDE_STICK = 2.0e-4
for dim in (2, 3):
    normal, tangent = ('y', 'x') if dim == 2 else ('z', 'x')
    # sliding: F_t = mu F_n once every contact node slides (second half of the slide)
    nb, blocks = deck(dim, MU_SLIDE, SLIDE)
    forces = {}
    for ranks in (1, 2):
        name = 'implicit_friction_slide_%dd_np%d' % (dim, ranks)
        rc, text, out = run_case(name, blocks, ranks=ranks)
        checks.check(rc == 0, '%dD sliding, %d rank(s): run succeeds' % (dim, ranks),
                     text[-600:])
        if rc != 0:
            continue
        r = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']
        forces[ranks] = np.array([r['time'], r[tangent], r[normal], r['tangential'],
                                  r['normal']])
        if ranks == 1:
            iterations = newton_iterations(text)
    if len(forces) < 2:
        continue
    t, ft, fn, traction_t, traction_n = forces[1]
    late = t > 0.75 + 1e-9
    # |sum A_A t_A| / sum A_A p_A: exactly mu when every node slides the same way
    ratio = traction_t[late] / traction_n[late]
    print('    %dD sliding, t > 0.75: friction/normal %s (mu = %.1f); tool force ratio F_t/F_n '
          '%s; normal force %s N; Newton iterations per step %s' % (
              dim, ' '.join('%.8f' % v for v in ratio), MU_SLIDE,
              ' '.join('%.6f' % v for v in ft[late] / fn[late]),
              ' '.join('%.4f' % v for v in fn[late]), iterations))
    checks.check(np.all(abs(ratio - MU_SLIDE) < 1e-9 * MU_SLIDE),
                 '%dD: sliding under a rigid tool, friction = mu x normal force (1e-9)' % dim,
                 str(ratio))
    # the tool's force components: the slightly tilted normals of the deformed block add
    # O(1e-5) of the normal force to F_t
    checks.check(np.all(abs(abs(ft[late] / fn[late]) - MU_SLIDE) < 1e-4 * MU_SLIDE),
                 '%dD: sliding: tool force |F_t/F_n| = mu (1e-4)' % dim, str(ft[late] / fn[late]))
    # rcforc's master force is the block's force on the tool: it holds the tool back
    checks.check(np.all(ft[late] * SLIDE < 0), '%dD: the friction force on the tool opposes '
                 'its motion' % dim, str(ft[late]))
    # measured 2-3 iterations: the frozen-geometry tangent is exact for a flat tool
    checks.check(max(iterations) <= 5, '%dD sliding: Newton converges in at most 5 iterations '
                 'per step' % dim, str(iterations))
    diff = np.max(abs(forces[2][1:] - forces[1][1:])) / np.max(abs(forces[1][2]))
    checks.check(diff < 1e-8, '%dD sliding: 1 and 2 ranks give the same tool forces' % dim,
                 '%.3e' % diff)
    # sticking: the block's top follows the tool, the friction force stays below mu N
    nb, blocks = deck(dim, MU_SLIDE, SLIDE_STICK)
    name = 'implicit_friction_stick_%dd' % dim
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%dD sticking: run succeeds' % dim, text[-600:])
    if rc != 0:
        continue
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        states = {round(float(f['states'][k].attrs['time']), 6): k for k in f['states']}
        xs = f['mesh/coordinates'][()]
        ids = f['mesh/node_ids'][()]
        top = np.nonzero((abs(xs[:, dim - 1] - 1.0) < 1e-9) & (ids <= nb))[0]
        # sideways motion of the top during the slide (t = 0.5 ... 1), the pressing's
        # Poisson expansion taken out
        u_x = [f['states/%s/point/displacement' % states[t]][()][top, 0] for t in (0.5, 1.0)]
    drag = u_x[1] - u_x[0]
    ft, fn = r[tangent][-1] - r[tangent][r['time'] < 0.5 + 1e-9][-1], r[normal][-1]
    penalty = float(re.search(r'tangential penalty (\S+)', text).group(1))
    line = '    %dD sticking: top dragged by %.3f of the slide (mean), |F_t/F_n| = %.4f ' \
        '(mu = %.1f); Newton iterations per step %s' % (
            dim, drag.mean() / SLIDE_STICK, abs(ft / fn), MU_SLIDE, newton_iterations(text))
    checks.check(0.0 < abs(ft / fn) < MU_SLIDE, '%dD: sticking: 0 < |F_t/F_n| < mu' % dim,
                 '%.4f' % abs(ft / fn))
    # (the top node on the symmetry face x = 0 is held: it does not move)
    checks.check(np.all(drag >= 0) and drag.max() > 0.25 * SLIDE_STICK and
                 np.all(drag < SLIDE_STICK), '%dD: sticking: the tool drags the top of the '
                 'block along, less than its own motion' % dim, str(drag))
    if dim == 2:
        # spring law of the stick state: the friction force is eps_T times the mortar slip
        # integrated over the top (the weights of linear segments: trapezoidal rule)
        order = np.argsort(xs[top, 0])
        x_top, d_top = xs[top, 0][order], drag[order]
        slip_area = SLIDE_STICK * (x_top[-1] - x_top[0]) - np.sum(
            0.5 * (d_top[1:] + d_top[:-1]) * np.diff(x_top))
        expected = penalty * slip_area
        line += '; friction %.5f N, eps_T x slip integral %.5f N' % (abs(ft), expected)
        checks.check(abs(abs(ft) / expected - 1) < 0.01, '2D: sticking: friction force = '
                     'tangential penalty x integrated slip (1 %)', '%.5f / %.5f' % (abs(ft),
                                                                                  expected))
    print(line)
checks.exit()
