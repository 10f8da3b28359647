"""Plate with a circular hole under uniaxial tension (Kirsch, formulation 7.7), plane strain,
through whole runs of bin/mefem.

Quarter of the square [-10, 10]^2 with a hole of radius a = 1, far-field traction T = 1 along x.
To remove the finite-plate error, the outer edges x = 10 and y = 10 carry the exact traction
of the infinite-plate solution (consistent nodal forces, 4 Gauss points per edge segment);
rollers on x = 0 and y = 0. The mesh has two mapped blocks (theta 0-45 deg to the right edge,
45-90 deg to the top edge), n quads along each block's arc, 2n along the rays, geometric ray
spacing (last cell 8x the first). Exact stress concentration sigma_xx(0, a) = 3 T.

Element averages cannot show the peak itself (the stress falls from 3 T at r = a at a slope of
-7 T/a), so the checks use: (1) the SCF recovered by a linear least-squares fit of the element
sigma_xx over the two rings of elements around (0, a), evaluated at (0, a); (2) the element
average in the element nearest (0, a) against the exact stress at its centroid; (3) the
area-weighted relative L2 error of the element stresses against the exact field at the
centroids.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks
from benchmarks import OUT, kirsch_case, kirsch_measures

checks = Checks('kirsch')
out = os.path.join(OUT, 'kirsch')
results = {}
for n, elform, poisson in ((8, 43, 0.3), (16, 43, 0.3), (32, 43, 0.3), (32, 13, 0.3),
                           (32, 43, 0.4999), (32, 13, 0.4999)):
    s, x, conn, top, text = kirsch_case(n, 2 * n, elform, poisson=poisson, outdir=out)
    checks.check(s is not None, 'n=%d ELFORM %d nu=%g: run succeeds' % (n, elform, poisson),
                 text[-400:])
    if s is not None:
        results[(n, elform, poisson)] = kirsch_measures(s, x, conn, top)

if len(results) == 6:
    print('   n  ELFORM  nu      elements  SCF (fit)  SCF error  element sxx  exact there  '
          'stress L2')
    for (n, elform, poisson), m in sorted(results.items()):
        print('  %2d   %2d   %-6g  %7d    %.4f   %7.3f %%   %.4f     %.4f     %.3e' % (
            n, elform, poisson, m['nelem'], m['scf_fit'], 100 * abs(m['scf_fit'] / 3 - 1),
            m['scf_element'], m['scf_element_exact'], m['stress_l2']))
    scf_error = [abs(results[(n, 43, 0.3)]['scf_fit'] / 3 - 1) for n in (8, 16, 32)]
    # Recovered SCF of ME-FEM: measured errors 4.2 %, 1.4 %, 0.43 % (n = 8, 16, 32): assert
    # the fall under refinement and 1 % at n = 32 (2x margin), also at nu = 0.4999 (0.46 %).
    checks.check(scf_error[0] > scf_error[1] > scf_error[2],
                 'ME-FEM SCF converges toward 3 (n = 8, 16, 32)',
                 ', '.join('%.3f %%' % (100 * e) for e in scf_error))
    for poisson in (0.3, 0.4999):
        m = results[(32, 43, poisson)]
        checks.check(abs(m['scf_fit'] / 3 - 1) < 0.01, 'ME-FEM SCF within 1 %% of 3 at n=32, '
                     'nu=%g' % poisson, 'SCF %.4f' % m['scf_fit'])
        # element average next to the peak vs the exact stress at its centroid: measured
        # 0.05 % and 0.11 %; 0.5 % allows for the curvature of the exact field in the element
        checks.check(abs(m['scf_element'] / m['scf_element_exact'] - 1) < 0.005,
                     'ME-FEM element sxx at (0, a) matches the exact field at its centroid '
                     'to 0.5 %% (n=32, nu=%g)' % poisson,
                     '%.4f vs %.4f' % (m['scf_element'], m['scf_element_exact']))
    # Stress field: ME-FEM L2 error 1.2e-3, 3.4e-4, 9.1e-5 (about h^1.8); assert at least
    # 2.5x per halving and < 1e-3 at n = 32 for both nu.
    l2 = [results[(n, 43, 0.3)]['stress_l2'] for n in (8, 16, 32)]
    checks.check(l2[0] > 2.5 * l2[1] > 6.25 * l2[2],
                 'ME-FEM stress L2 error falls at least 2.5x per halving of h',
                 ', '.join('%.3e' % e for e in l2))
    for poisson in (0.3, 0.4999):
        checks.check(results[(32, 43, poisson)]['stress_l2'] < 1e-3,
                     'ME-FEM stress L2 error < 1e-3 at n=32, nu=%g' % poisson,
                     '%.3e' % results[(32, 43, poisson)]['stress_l2'])
    # Standard triangles: at nu = 0.3 correct but less accurate (L2 4.6e-3); at nu = 0.4999
    # their stresses are spoiled by the pressure oscillation of locking (L2 0.18, 1900x
    # ME-FEM). Assert > 5 % there: the sign of locking, not a digit.
    checks.check(results[(32, 13, 0.4999)]['stress_l2'] > 0.05,
                 'standard triangles at nu=0.4999: stress L2 error > 5 % (locking)',
                 '%.3e' % results[(32, 13, 0.4999)]['stress_l2'])
    checks.check(results[(32, 13, 0.3)]['stress_l2'] > results[(32, 43, 0.3)]['stress_l2'],
                 'ME-FEM stresses more accurate than standard at nu=0.3, n=32',
                 '%.3e vs %.3e' % (results[(32, 43, 0.3)]['stress_l2'],
                                   results[(32, 13, 0.3)]['stress_l2']))
checks.exit()
