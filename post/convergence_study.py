#!/usr/bin/python3
"""Convergence studies of the linear verification benchmarks (doc/verification.md).

Runs bin/mefem on finer meshes than `make test` does and writes the tables and figures of
the doc:
  doc/verification_data/cook.csv, cook_support.csv, lame.csv, lame_pressure_profile.csv,
  kirsch.csv, and cook.png, lame_pressure.png, kirsch_scf.png.
Meshes, decks and exact solutions come from tests/verification/benchmarks.py, so the study
and the tests run the same problems. Run time about 2-3 minutes on 2 cores.

Usage: /usr/bin/python3 post/convergence_study.py [--quick]   (--quick: coarse meshes only,
to try the script; it does not overwrite the doc's data).
"""
import argparse
import csv
import os
import sys
import time

import numpy as np
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from benchmarks import (COOK_REFERENCE, cook_case, kirsch_case, kirsch_measures,  # noqa: E402
                        lame_case, lame_exact, lame_measures)

QUICK = False                        # --quick (set by the command line below)
RUNS = os.path.join(ROOT, 'tests', 'out', 'convergence_study')
DATA = os.path.join(ROOT, 'doc', 'verification_data')     # (--quick: under tests/out)


def write_csv(name, header, rows):
    with open(os.path.join(DATA, name), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow(['%.10g' % v if isinstance(v, float) else v for v in r])
    print('wrote', os.path.join(DATA, name))


def log(*args):
    print(*args, flush=True)


def cook_study():
    """v(48, 52) for triangles (two cut patterns) and tets (two slab meshes) vs N."""
    sizes = (4, 8, 16) if QUICK else (4, 8, 16, 32, 64)
    series = [  # label, elform, options
        ('ME-FEM tri (43)', 43, dict(dim=2, pattern='right')),
        ('standard tri (13)', 13, dict(dim=2, pattern='right')),
        ('ME-FEM tri (43), alternating cut', 43, dict(dim=2, pattern='alternate')),
        ('standard tri (13), alternating cut', 13, dict(dim=2, pattern='alternate')),
        ('ME-FEM tet (43)', 43, dict(dim=3, split='hex6', thickness=1.0)),
        ('standard tet (10)', 10, dict(dim=3, split='hex6', thickness=1.0)),
        ('ME-FEM tet (43), prisms, thickness h', 43, dict(dim=3, split='prism3',
                                                           pattern='alternate')),
        ('standard tet (10), prisms, thickness h', 10, dict(dim=3, split='prism3',
                                                             pattern='alternate')),
    ]
    rows = []
    values = {}
    for label, elform, options in series:
        for n in sizes:
            opts = dict(options)
            if opts.get('split') == 'prism3':
                opts['thickness'] = 48.0 / n
            t0 = time.time()
            v, s, text = cook_case(n, elform, outdir=os.path.join(RUNS, 'cook'), **opts)
            if v is None:
                raise SystemExit('run failed: %s\n%s' % (label, text[-1000:]))
            nelem = len(s['conn'])
            rows.append([label, elform, opts['dim'], opts.get('pattern', 'right'),
                         opts.get('split', ''), opts.get('thickness', ''), n, nelem, float(v),
                         float(v / COOK_REFERENCE - 1)])
            values.setdefault(label, []).append((n, v))
            log('cook %-40s N=%3d  v=%.5f  error %+.3f %%  (%.1f s)'
                % (label, n, v, 100 * (v / COOK_REFERENCE - 1), time.time() - t0))
    write_csv('cook.csv', ['series', 'elform', 'dim', 'cut', 'tet_split', 'thickness', 'N',
                           'elements', 'v_48_52', 'relative_error'], rows)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    styles = {'ME-FEM tri (43)': 'o-C0', 'standard tri (13)': 's-C1',
              'ME-FEM tri (43), alternating cut': 'o:C0', 'standard tri (13), alternating cut':
              's:C1', 'ME-FEM tet (43)': '^-C2', 'standard tet (10)': 'v-C3',
              'ME-FEM tet (43), prisms, thickness h': '^:C2',
              'standard tet (10), prisms, thickness h': 'v:C3'}
    for label, pts in values.items():
        n, v = np.array(pts).T
        st = styles[label]
        axes[0].plot(n, v, st[:-2], color=st[-2:], label=label, ms=4)
        axes[1].loglog(n, np.abs(v / COOK_REFERENCE - 1), st[:-2], color=st[-2:], ms=4)
    axes[0].axhline(COOK_REFERENCE, color='k', lw=0.8, label='reference 16.4326')
    axes[0].set_xscale('log', base=2)
    axes[0].set_xlabel('N (elements per side)')
    axes[0].set_ylabel('v(48, 52)')
    axes[0].set_title("Cook's membrane, plane strain, nu = 0.499975")
    axes[0].legend(fontsize=6.5, loc='center right')
    axes[1].set_xscale('log', base=2)
    axes[1].set_xlabel('N')
    axes[1].set_ylabel('|v / v_ref - 1|')
    axes[1].axhline(0.02, color='k', lw=0.6, ls='--')
    axes[1].text(4.2, 0.023, '2 %', fontsize=7)
    axes[1].set_title('relative error')
    fig.tight_layout()
    fig.savefig(os.path.join(DATA, 'cook.png'), dpi=90)
    plt.close(fig)
    print('wrote', os.path.join(DATA, 'cook.png'))


def cook_support_study():
    """Sensitivity of ME-FEM to the support radius a/L (formulation 2.10)."""
    rows = []
    sizes = (8,) if QUICK else (16, 32)
    for dim in (2, 3):
        for support in (1.25, 1.5, 2.0):
            for n in sizes:
                v, s, text = cook_case(n, 43, dim=dim, support=support,
                                       outdir=os.path.join(RUNS, 'cook_support'))
                if v is None:
                    raise SystemExit('run failed\n' + text[-1000:])
                rows.append([dim, support, n, float(v), float(v / COOK_REFERENCE - 1)])
                log('cook support %dD a/L=%.2f N=%d  v=%.5f  error %+.3f %%'
                    % (dim, support, n, v, 100 * (v / COOK_REFERENCE - 1)))
    write_csv('cook_support.csv', ['dim', 'support_a_over_L', 'N', 'v_48_52',
                                   'relative_error'], rows)


def lame_study():
    """u_r(a), radial profile error and pressure measures vs mesh; pressure along r."""
    sizes = (4, 8, 16) if QUICK else (4, 8, 16, 32)
    rows = []
    for pattern in ('right', 'alternate'):
        for elform in (43, 13):
            for n_r in sizes:
                s, x, conn, inner, text = lame_case(n_r, 2 * n_r, elform, pattern=pattern,
                                                    outdir=os.path.join(RUNS, 'lame'))
                if s is None:
                    raise SystemExit('run failed\n' + text[-1000:])
                m = lame_measures(s, x, conn, inner)
                rows.append([elform, pattern, n_r, 2 * n_r, len(conn), float(m['ur_a']),
                             float(m['ur_a_error']), float(m['ur_max_error']),
                             float(m['pressure_rms']), float(m['pressure_jump'])])
                log('lame %s ELFORM %d %dx%d: u_r(a) %.6e (err %.2e) max %.2e  p rms %.3e '
                    'jump %.3e' % (pattern, elform, n_r, 2 * n_r, m['ur_a'], m['ur_a_error'],
                                   m['ur_max_error'], m['pressure_rms'], m['pressure_jump']))
    write_csv('lame.csv', ['elform', 'cut', 'n_r', 'n_theta', 'elements', 'ur_a',
                           'ur_a_relative_error', 'ur_max_error_over_ur_a',
                           'pressure_rms_over_p', 'pressure_neighbour_jump_over_p'], rows)

    # pressure along r on the 16 x 32 mesh (same diagonal cut), both elements
    profile = []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for elform, colour, label in ((13, 'C1', 'standard tri (13)'),
                                  (43, 'C0', 'ME-FEM tri (43)')):
        s, x, conn, inner, text = lame_case(16, 32, elform, pattern='right',
                                            outdir=os.path.join(RUNS, 'lame'))
        m = lame_measures(s, x, conn, inner)
        for r, p in zip(m['centroid_r'], m['pressure']):
            profile.append([elform, '%.6f' % r, '%.7g' % p])
        axes[0].plot(m['centroid_r'], m['pressure'], '.', color=colour, ms=2, label=label)
        if elform == 43:
            axes[1].plot(m['centroid_r'], m['pressure'], '.', color=colour, ms=3, label=label)
    exact = lame_exact(3.0)[4]
    for ax in axes:
        ax.axhline(exact, color='k', lw=0.8, label='exact %.6f' % exact)
        ax.set_xlabel('r (element centroid)')
        ax.set_ylabel('element pressure -(s_r + s_t + s_z)/3')
        ax.legend(fontsize=7)
    axes[0].set_title('Lame cylinder, nu = 0.4999, 16 x 32 quads cut into triangles',
                      fontsize=9)
    axes[1].set_title('ME-FEM only (zoom)', fontsize=9)
    axes[1].set_ylim(exact - 0.01, exact + 0.01)
    fig.tight_layout()
    fig.savefig(os.path.join(DATA, 'lame_pressure.png'), dpi=90)
    plt.close(fig)
    print('wrote', os.path.join(DATA, 'lame_pressure.png'))
    write_csv('lame_pressure_profile.csv', ['elform', 'centroid_r', 'pressure'], profile)


def kirsch_study():
    """SCF (recovered and element value) and stress L2 error vs mesh, nu = 0.3 and 0.4999."""
    sizes = (4, 8, 16) if QUICK else (4, 8, 16, 32, 64)
    rows = []
    curves = {}
    for poisson in (0.3, 0.4999):
        for elform in (43, 13):
            for n in sizes:
                s, x, conn, top, text = kirsch_case(n, 2 * n, elform, poisson=poisson,
                                                    outdir=os.path.join(RUNS, 'kirsch'))
                if s is None:
                    raise SystemExit('run failed\n' + text[-1000:])
                m = kirsch_measures(s, x, conn, top)
                rows.append([elform, poisson, n, 2 * n, m['nelem'], float(m['scf_fit']),
                             float(m['scf_fit'] / 3 - 1), float(m['scf_element']),
                             float(m['scf_element_exact']), float(m['scf_node']),
                             float(m['stress_l2'])])
                curves.setdefault((elform, poisson), []).append((n, m['scf_fit'],
                                                                 m['scf_element']))
                log('kirsch ELFORM %d nu=%g n=%d: SCF fit %.4f element %.4f (exact %.4f) '
                    'L2 %.3e' % (elform, poisson, n, m['scf_fit'], m['scf_element'],
                                 m['scf_element_exact'], m['stress_l2']))
    write_csv('kirsch.csv', ['elform', 'nu', 'n_arc_per_block', 'n_ray', 'elements',
                             'scf_fit', 'scf_fit_relative_error', 'element_sxx_at_hole',
                             'exact_sxx_at_that_centroid', 'node_average_sxx',
                             'stress_l2_relative_error'], rows)
    fig, ax = plt.subplots(figsize=(8, 4))
    for (elform, poisson), pts in sorted(curves.items()):
        n, fit, element = np.array(pts).T
        colour = 'C0' if elform == 43 else 'C1'
        ls = '-' if poisson == 0.3 else '--'
        name = 'ME-FEM (43)' if elform == 43 else 'standard (13)'
        ax.plot(n, fit, ls, marker='o', color=colour, ms=4,
                label='%s, nu=%g, recovered' % (name, poisson))
        ax.plot(n, element, ls, marker='x', color=colour, ms=4, alpha=0.5,
                label='%s, nu=%g, element' % (name, poisson))
    ax.axhline(3.0, color='k', lw=0.8, label='exact 3')
    ax.set_xscale('log', base=2)
    ax.set_xlabel('n (quads along each block arc; 4 n^2 quads)')
    ax.set_ylabel('sigma_xx(0, a) / T')
    ax.set_title('Kirsch plate, plane strain: stress concentration', fontsize=9)
    ax.legend(fontsize=6.5, loc='center left', bbox_to_anchor=(1.02, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(DATA, 'kirsch_scf.png'), dpi=90)
    plt.close(fig)
    print('wrote', os.path.join(DATA, 'kirsch_scf.png'))


if __name__ == '__main__':
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--quick', action='store_true', help='coarse meshes only, to try the '
                        'script (the doc\'s data are not overwritten)')
    QUICK = parser.parse_args().quick
    if QUICK:
        DATA = os.path.join(ROOT, 'tests', 'out', 'convergence_study_data')
    os.makedirs(DATA, exist_ok=True)
    start = time.time()
    cook_study()
    cook_support_study()
    lame_study()
    kirsch_study()
    print('total %.0f s' % (time.time() - start))
