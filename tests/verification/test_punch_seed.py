"""Regression guard of the seed paper's punch benchmark (Hu & Wu 2013, section 4.1) on its
coarsest structured mesh (input/punch/punch_s1_*.k, 768 triangles; ~20 s for ME-FEM, ~5 s for
standard triangles on one core). The full study (five meshes, figures) is post/punch_study.py
(`make punch`); setup, choices and numbers are in doc/verification.md, "Seed punch".

Checks, with the numbers of the study (doc/verification_data/punch_summary.csv):
- both runs (ME-FEM ELFORM 43, standard ELFORM 13) reach the end time, d_y = 0.35 cm;
- the ME-FEM load grows monotonically (hardening material, no snap-back);
- ME-FEM load at d_y = 0.35 within 1 % of this mesh's study value 8669 N/cm. A regression
  guard: halving the load steps moved it by 0.2 % in the study and rounding (BLAS, MUMPS,
  rank count) by far less, so 1 % leaves room for step-path changes of the Newton solver but
  catches changes of the element, material or boundary conditions;
- ME-FEM load at d_y = 0.35 within 2 % of the fine-mesh value 8589 N/cm (mean of the three
  finest ME-FEM meshes of the study, which agree to 0.5 %): measured 0.9 % on this mesh;
- standard triangles are at least 15 % stiffer (volumetric locking; measured 33 %);
- pressure checkerboard: the RMS of the pressure jumps between edge neighbours, relative to
  the mean pressure under the punch, is below 0.15 for ME-FEM (measured 0.064) and at least
  5 times smaller than for standard triangles on the same mesh (measured 14.5 times).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import ROOT, Checks  # noqa: E402
from punch_seed import PUNCH_DEPTH, checkerboard, final_state, load_curve, run_deck  # noqa: E402

STUDY_LOAD_S1 = 8669.0        # N/cm, ME-FEM on mesh s1 at d_y = 0.35 (post/punch_study.py)
FINE_LOAD = 8589.0            # N/cm, mean of the ME-FEM loads on u2, s3, s2

OUT = os.path.join(ROOT, 'tests', 'out', 'punch_test')
checks = Checks('punch_seed')
results = {}
for variant in ('mefem', 'standard'):
    rc, text, h5 = run_deck('s1', variant, out=OUT)
    checks.check(rc == 0, 's1 %s: run succeeds' % variant, text[-600:])
    if rc != 0:
        continue
    t, d, load = load_curve(h5)
    checks.check(abs(t[-1] - 1.0) < 1e-9 and abs(d[-1] - PUNCH_DEPTH) < 1e-9,
                 's1 %s: reaches d_y = 0.35 at the end time' % variant,
                 't = %.6g, d = %.6g' % (t[-1], d[-1]))
    results[variant] = (load[-1], checkerboard(final_state(h5)), load)

if 'mefem' in results:
    load, cb, curve = results['mefem']
    checks.check(np.all(np.diff(curve) > 0), 's1 mefem: load grows monotonically',
                 str(curve))
    checks.check(abs(load / STUDY_LOAD_S1 - 1) < 0.01, 's1 mefem: load at d_y = 0.35 within '
                 '1 %% of the study value %.0f N/cm' % STUDY_LOAD_S1, '%.1f' % load)
    checks.check(abs(load / FINE_LOAD - 1) < 0.02, 's1 mefem: load at d_y = 0.35 within 2 %% '
                 'of the fine-mesh value %.0f N/cm' % FINE_LOAD, '%.1f' % load)
    checks.check(cb['jump_rms'] < 0.15, 's1 mefem: pressure jump RMS / p_ref < 0.15',
                 '%.4f' % cb['jump_rms'])
if len(results) == 2:
    ratio = results['standard'][0] / results['mefem'][0]
    checks.check(ratio > 1.15, 's1: standard triangles lock (load at least 15 % above '
                 'ME-FEM)', '%.3f' % ratio)
    jumps = results['standard'][1]['jump_rms'] / results['mefem'][1]['jump_rms']
    checks.check(jumps > 5.0, 's1: ME-FEM pressure jumps at least 5x smaller than standard',
                 '%.2f' % jumps)
checks.exit()
