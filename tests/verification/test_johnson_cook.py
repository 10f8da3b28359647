"""Johnson-Cook plasticity (issue 23; doc/theory.md section 4): *MAT_JOHNSON_COOK (MAT_015)
and *MAT_SIMPLIFIED_JOHNSON_COOK (MAT_098) on one hexahedron (1 x 1 x 1 mm, ELFORM 1) every node
of which is driven by one isochoric stretch-rate field (as test_strain_rate.py), so the
effective strain rate sqrt(d : d) is known exactly. The von Mises Kirchhoff stress against
  (A + B alpha^N) (1 + C ln(rate/EPSO)) (1 - T*^M),  T* = (T - TR)/(TM - TR):
- isothermal (CP = 0), rates 1000 and 20 /s and 0.5 /s below EPSO = 1 /s (no rate term): to 1e-6;
- adiabatic heating (CP given, made 20 times smaller than copper's so that the temperature
  rises by about 390 K over the 30 % stretch): against the temperature from the plastic work,
  dT/dalpha = sigma_y/(rho CP) integrated in Python (RK4), within 2e-3 (the explicit update
  heats at the end of each step);
- MAT_098 with SIGMAX: the hardening capped at SIGMAX, times the rate term, to 1e-6;
- implicit (the element in uniaxial stress, the top driven at 1000 /s): within 1 % of the
  isothermal law at the element's plastic strain and rate;
- spall (explicit; PC = -500 MPa, a bar in uniaxial strain whose halves start apart at
  +-v, elastic, the tension rho c v at the mid-plane beyond -PC): SPALL 3 and 2 part the bar
  (its ends fly apart: extension above 0.8 x 2 v t), the plain bar holds (extension below
  0.2 x 2 v t: it rings); SPALL 1 caps the tension: every cell's
  p >= PC in every state, while the plain bar's reaches 1.5 PC; PC = 0 is the plain bar, bit
  for bit.
Units: mm, s, tonne, N, MPa; temperatures in K, CP in mJ/(t K) = mm^2/(s^2 K).
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import box_hexes, node_set, curve, run_case

checks = Checks('johnson_cook')
# OFHC copper (Johnson & Cook 1983): G = 46 GPa, A = 90 MPa, B = 292 MPa, N = 0.31, C = 0.025,
# M = 1.09, TM = 1356 K, TR = 293 K, CP = 383 J/(kg K)
RHO, G, NU = 8.96e-9, 46000.0, 0.34
A, B, N, C, M, TM, TR, EPSO = 90.0, 292.0, 0.31, 0.025, 1.09, 1356.0, 293.0, 1.0
CP_COPPER = 383.0e6
x, conn = box_hexes(1.0, 1.0, 1.0, 1, 1, 1)
base = np.nonzero(x[:, 2] < 1e-9)[0]
top = np.nonzero(x[:, 2] > 1 - 1e-9)[0]
origin = int(np.nonzero(np.all(x < 1e-9, axis=1))[0][0])
on_x = int(np.nonzero((x[:, 0] > 1 - 1e-9) & (x[:, 1] < 1e-9) & (x[:, 2] < 1e-9))[0][0])
L_RATE = np.diag([-0.5, -0.5, 1.0])
xd = x + 1.0


def mat015(cp=0.0):
    return ['*MAT_JOHNSON_COOK', free(1, RHO, G, 0.0, NU), free(A, B, N, C, M, TM, TR, EPSO),
            free(cp, 0.0, 0.0, 0)]


def mat098(sigmax):
    return ['*MAT_SIMPLIFIED_JOHNSON_COOK', free(1, RHO, 2 * G * (1 + NU), NU),
            free(A, B, N, C, 0.0, sigmax, 0.0, EPSO)]


def rate_term(rate):
    return 1.0 + C * np.log(rate / EPSO) if rate > EPSO else 1.0


def driven(name, material, axial_rate, strain):
    """Every node driven by v = axial_rate L_RATE X; returns (alpha, tau_vm, rate)."""
    t_end = strain / axial_rate
    v = axial_rate * (xd @ L_RATE.T)
    blocks = [nodes_card(xd), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'cube', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1)] + material]
    for k in range(len(xd)):
        blocks.append(node_set(10 + k, [k]))
        for d in range(3):
            blocks.append(['*BOUNDARY_PRESCRIBED_MOTION_SET', free(10 + k, d + 1, 0, 1, v[k, d])])
    blocks += [curve(1, [(0.0, 1.0), (1.0, 1.0)]),
               ['*CONTROL_TERMINATION', f10(t_end), '*DATABASE_BINARY_D3PLOT', f10(t_end)]]
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    with h5py.File(os.path.join(out, name + '.h5')) as h:
        last = h['states'][sorted(h['states'].keys())[-1]]
        t = float(h['time_history/time'][-1])
        von_mises = float(last['cell']['von_mises'][()].ravel()[0])
        alpha = float(last['cell']['plastic_strain'][()].ravel()[0])
    f = np.eye(3) + t * axial_rate * L_RATE
    d = axial_rate * L_RATE @ np.linalg.inv(f)
    d = 0.5 * (d + d.T)
    return alpha, np.linalg.det(f) * von_mises, float(np.sqrt((d * d).sum()))


def temperature_rise(alpha_end, rate, cp):
    """theta(alpha) from d theta/d alpha = R (A + B a^N)(1 - (theta/(TM - TR))^M)/(rho CP)."""
    def slope(a, theta):
        return rate_term(rate) * (A + B * a ** N) * (1 - (max(theta, 0) / (TM - TR)) ** M) / \
            (RHO * cp)
    steps = 4000
    h = alpha_end / steps
    theta, a = 0.0, 0.0
    for _ in range(steps):
        k1 = slope(a, theta)
        k2 = slope(a + h / 2, theta + h / 2 * k1)
        k3 = slope(a + h / 2, theta + h / 2 * k2)
        k4 = slope(a + h, theta + h * k3)
        theta += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        a += h
    return theta


# isothermal: the law exactly
for rate_in in (1000.0, 20.0, 0.5):
    result = driven('jc_isothermal_%g' % rate_in, mat015(), rate_in, 0.05)
    if result:
        alpha, tau, rate = result
        want = (A + B * alpha ** N) * rate_term(rate)
        print('    MAT_015 isothermal at %.4g /s: plastic strain %.4f, von Mises tau %.4f MPa, '
              'law %.4f MPa (rate term %.5f)' % (rate, alpha, tau, want, rate_term(rate)))
        checks.check(abs(tau / want - 1) < 1e-6, 'MAT_015 isothermal at %g /s: (A + B '
                     'alpha^N)(1 + C ln(rate/EPSO)) to 1e-6' % rate_in, '%.6f vs %.6f' % (tau,
                                                                                            want))
# adiabatic heating
CP = CP_COPPER / 20.0
result = driven('jc_adiabatic', mat015(CP), 1000.0, 0.3)
if result:
    alpha, tau, rate = result
    theta = temperature_rise(alpha, rate, CP)
    thermal = 1 - (theta / (TM - TR)) ** M
    want = (A + B * alpha ** N) * rate_term(rate) * thermal
    isothermal = (A + B * alpha ** N) * rate_term(rate)
    print('    MAT_015 adiabatic: plastic strain %.4f, temperature rise %.1f K, thermal factor '
          '%.4f; von Mises tau %.3f MPa, law %.3f MPa (%+.2e), isothermal %.3f MPa' % (
              alpha, theta, thermal, tau, want, tau / want - 1, isothermal))
    checks.check(abs(tau / want - 1) < 2e-3, 'MAT_015 adiabatic: the flow stress softened by '
                 'the temperature of the plastic work, within 2e-3', '%.4f vs %.4f' % (tau, want))
    checks.check(tau < 0.9 * isothermal, 'MAT_015 adiabatic: the heating softens (more than '
                 '10 % here)', '%.3f vs %.3f' % (tau, isothermal))
# MAT_098 with SIGMAX
SIGMAX = 200.0
result = driven('jc_simplified', mat098(SIGMAX), 1000.0, 0.1)
if result:
    alpha, tau, rate = result
    want = min(A + B * alpha ** N, SIGMAX) * rate_term(rate)
    print('    MAT_098: plastic strain %.4f (hardening %.2f MPa, SIGMAX %.0f), von Mises tau '
          '%.4f MPa, law %.4f MPa' % (alpha, A + B * alpha ** N, SIGMAX, tau, want))
    checks.check(A + B * alpha ** N > SIGMAX and abs(tau / want - 1) < 1e-6, 'MAT_098: the '
                 'hardening capped at SIGMAX, times the rate term, to 1e-6', '%.6f vs %.6f' % (
                     tau, want))


def uniaxial_implicit(axial_rate, strain):
    t_end = strain / axial_rate
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'cube', f10(1, 1, 1, 0, 1), '*SECTION_SOLID', f10(1, 1),
               '*HOURGLASS', f10(1, 6, 1.0)] + mat015(),
              node_set(1, base), node_set(2, top), node_set(3, [origin]), node_set(4, [on_x]),
              ['*BOUNDARY_SPC_SET', f10(1, 0, 0, 0, 1, 0, 0, 0),
               '*BOUNDARY_SPC_SET', f10(3, 0, 1, 1, 1, 0, 0, 0),
               '*BOUNDARY_SPC_SET', f10(4, 0, 0, 1, 1, 0, 0, 0)],
              ['*BOUNDARY_PRESCRIBED_MOTION_SET', f10(2, 3, 2, 1, 1.0)],
              curve(1, [(0.0, 0.0), (t_end, strain)]),
              ['*CONTROL_TERMINATION', f10(t_end), '*DATABASE_BINARY_D3PLOT', f10(t_end / 10),
               '*CONTROL_IMPLICIT_GENERAL', f10(1, t_end / 50),
               '*CONTROL_IMPLICIT_SOLUTION', free(12, 11, 15, 1.0e-6)]]
    name = 'jc_implicit'
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return
    with h5py.File(os.path.join(out, name + '.h5')) as h:
        states = [k for k in sorted(h['states'].keys())
                  if 'displacement' in h['states'][k]['point']]
        last, before = h['states'][states[-1]], h['states'][states[-2]]
        times = h['time_history/time'][()]
        dt_out = times[-1] - times[-2]
        x0 = h['mesh/coordinates'][()]
        u1, u0 = last['point']['displacement'][()], before['point']['displacement'][()]
        sigma = last['cell']['stress'][()].ravel()[2]
        alpha = last['cell']['plastic_strain'][()].ravel()[0]
    size = lambda u, k: (x0[:, k] + u[:, k]).max() - (x0[:, k] + u[:, k]).min()  # noqa: E731
    d = np.array([np.log(size(u1, k) / size(u0, k)) / dt_out for k in range(3)])
    rate = float(np.sqrt((d ** 2).sum()))
    want = (A + B * alpha ** N) * rate_term(rate)
    print('    implicit uniaxial: plastic strain %.4f, stress %.3f MPa, law %.3f MPa at %.0f /s'
          % (alpha, sigma, want, rate))
    checks.check(abs(sigma / want - 1) < 0.01, 'MAT_015 implicit uniaxial: the law within 1 %',
                 '%.3f vs %.3f' % (sigma, want))


def spall_bar():
    """A 1 x 1 x 10 mm bar of tets in uniaxial strain (x, y fixed), its halves given +-v along
    z: a tension wave rho c v starts at the mid-plane. Returns per run (z-momentum of the upper
    half in the last state over its initial one, least cell pressure over the states)."""
    from explicit_cases import box_tets
    xb, cb = box_tets(1.0, 1.0, 10.0, 1, 1, 20)
    rho, young, nu, v = 7.85e-9, 200000.0, 0.3, 2.0e4          # v = 20 m/s
    c = np.sqrt(young * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho)
    upper = np.nonzero(xb[:, 2] > 5.0 + 1e-9)[0]
    lower = np.nonzero(xb[:, 2] < 5.0 - 1e-9)[0]
    results = {}
    for name, pc, spall in (('plain', 0.0, 0.0), ('pc0', 0.0, 3.0), ('spall3', -500.0, 3.0),
                            ('spall2', -500.0, 2.0), ('spall1', -500.0, 1.0)):
        blocks = [nodes_card(xb), elements_card('ELEMENT_SOLID', cb),
                  ['*PART', 'bar', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 10),
                   '*MAT_JOHNSON_COOK', free(1, rho, young / (2 * (1 + nu)), 0.0, nu),
                   free(1.0e5, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0), free(0.0, pc, spall, 0)],
                  node_set(1, range(len(xb))), ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 0)],
                  node_set(2, upper), ['*INITIAL_VELOCITY', f10(2), free(0.0, 0.0, v)],
                  node_set(3, lower), ['*INITIAL_VELOCITY', f10(3), free(0.0, 0.0, -v)],
                  ['*CONTROL_TERMINATION', f10(6.0e-6), '*DATABASE_BINARY_D3PLOT', f10(2.0e-7)]]
        rc, text, out = run_case('jc_spall_' + name, blocks)
        checks.check(rc == 0, 'spall bar %s: run succeeds' % name, text[-500:])
        if rc != 0:
            return
        with h5py.File(os.path.join(out, 'jc_spall_%s.h5' % name)) as h:
            keys = sorted(h['states'].keys())
            order = np.argsort(h['mesh/node_ids'][()])
            vz = h['states/%s/point/velocity' % keys[-1]][()][order][:, 2]
            least = min(float((-h['states/%s/cell/stress' % k][()][:, 0:3].sum(axis=1) / 3).min())
                        for k in keys[1:])
            u = h['states/%s/point/displacement' % keys[-1]][()][order]
        above = abs(xb[:, 2] - 10.0) < 1e-9        # the bar's ends
        below = abs(xb[:, 2]) < 1e-9
        opening = (u[above, 2].mean() - u[below, 2].mean()) / (2 * v * 6.0e-6)
        results[name] = (opening, least, u)
    sigma = rho * c * v
    print('    spall bar: tension rho c v = %.0f MPa (p = %.0f MPa) at the mid-plane; the bar\'s '
          'extension at 6 us over 2 v t: %s; least cell pressure: %s' % (
              sigma, -sigma * (1 + 2 * nu / (1 - nu)) / 3,
              ', '.join('%s %.3f' % (k, r[0]) for k, r in results.items()),
              ', '.join('%s %.0f' % (k, r[1]) for k, r in results.items())))
    for name in ('spall3', 'spall2'):
        checks.check(results[name][0] > 0.8, 'spall bar, SPALL %s: the bar parts (its ends '
                     'fly apart: extension over 2 v t above 0.8)' % name[-1],
                     '%.4f' % results[name][0])
    checks.check(results['plain'][0] < 0.2, 'spall bar: the plain bar holds (extension over '
                 '2 v t below 0.2)', '%.4f' % results['plain'][0])
    checks.check(results['spall1'][1] >= -500.0 * (1 + 1e-9) and results['plain'][1] < -750.0,
                 'spall bar, SPALL 1: p >= PC everywhere, always (the plain bar reaches %.0f)'
                 % results['plain'][1], '%.3f' % results['spall1'][1])
    checks.check(np.array_equal(results['pc0'][2], results['plain'][2]), 'spall bar: PC = 0 '
                 '(blank) is no spall, the plain bar bit for bit')


uniaxial_implicit(1000.0, 0.05)
spall_bar()
checks.exit()
