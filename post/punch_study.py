#!/usr/bin/python3
"""The seed paper's punch benchmark (Hu & Wu 2013, section 4.1) as a reproducible study.

Runs the ten committed decks of input/punch/ (five meshes: structured s1-s3, irregular u1-u2;
ME-FEM ELFORM 43 and standard ELFORM 13 triangles on each), two runs at a time on one rank
each, and writes to doc/verification_data/:
  punch_load_displacement.csv   every load-displacement curve (half model, N per cm)
  punch_load_displacement.png   all curves on one plot
  punch_summary.csv             per run: load at d_y = 0.35, pressure-jump measures, Newton
  punch_pressure_<mesh>.png     pressure contours at d_y = 0.35 on the deformed mesh, ME-FEM
                                and standard side by side (finest structured and irregular)
and prints a summary table with the spread of the ME-FEM load at d_y = 0.35 over the three
finest meshes. Setup and discussion: doc/verification.md, "Seed punch (paper section 4.1)".

Usage: /usr/bin/python3 post/punch_study.py [--no-run] [--jobs N] [--exe PATH]
  --no-run   reuse the results in tests/out/punch/ (only measure and plot)
  --jobs N   runs at the same time (default 2)
  --exe PATH the mefem executable (default bin/mefem)
`make punch` builds bin/mefem and runs this script (about 5-10 minutes on 2 cores).
"""
import csv
import os
import subprocess
import sys
import time

import numpy as np
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from punch_seed import (DECKS, MESHES, OUT, PUNCH_DEPTH, VARIANTS, checkerboard,  # noqa: E402
                        deck_name, final_state, load_curve, newton_counts)

DATA = os.path.join(ROOT, 'doc', 'verification_data')
MESH_ORDER = ['s1', 's2', 's3', 'u1', 'u2']
MESH_LABEL = {'s1': 'structured s1', 's2': 'structured s2', 's3': 'structured s3',
              'u1': 'irregular u1', 'u2': 'irregular u2'}
COLOURS = {'s1': 'tab:blue', 's2': 'tab:orange', 's3': 'tab:green', 'u1': 'tab:red',
           'u2': 'tab:purple'}


def triangles_in_deck(mesh):
    """Number of triangles of mesh_<mesh>.k (lines of its *ELEMENT_SHELL block)."""
    count, inside = 0, False
    with open(os.path.join(DECKS, 'mesh_%s.k' % mesh)) as f:
        for line in f:
            if line.startswith('*'):
                inside = line.strip() == '*ELEMENT_SHELL'
            elif inside and line.strip():
                count += 1
    return count


def run_all(jobs, exe):
    """Run every deck, `jobs` at a time, the largest first; return {name: (rc, seconds)}."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OPENBLAS_NUM_THREADS='1')
    order = sorted(((m, v) for m in MESH_ORDER for v in VARIANTS),
                   key=lambda mv: (mv[1] != 'mefem', -triangles_in_deck(mv[0])))
    os.makedirs(OUT, exist_ok=True)
    pending, running, done = list(order), {}, {}
    while pending or running:
        while pending and len(running) < jobs:
            mesh, variant = pending.pop(0)
            name = deck_name(mesh, variant)
            log = open(os.path.join(OUT, name + '.log'), 'w')
            cmd = [exe, '-o', os.path.join(OUT, name),
                   os.path.join(DECKS, name + '.k')]
            running[name] = (subprocess.Popen(cmd, cwd=ROOT, stdout=log,
                                              stderr=subprocess.STDOUT, env=env),
                             time.time(), log)
            print('running %s' % name, flush=True)
        time.sleep(0.5)
        for name, (proc, start, log) in list(running.items()):
            if proc.poll() is not None:
                log.close()
                done[name] = (proc.returncode, time.time() - start)
                print('  %s: exit %d after %.0f s' % (name, proc.returncode, done[name][1]),
                      flush=True)
                del running[name]
    return done


def value_at(d, curve, target):
    """Curve value at displacement `target` (linear interpolation; NaN if not reached)."""
    if d[-1] < target * (1 - 1e-6):
        return float('nan')
    return float(np.interp(target, d, curve))


def plot_curves(curves, path):
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    for (mesh, variant), (t, d, load) in sorted(curves.items()):
        style = '-' if variant == 'mefem' else '--'
        ax.plot(d, load / 1000.0, style, color=COLOURS[mesh], lw=1.4,
                label='%s, %s, %d triangles' % (VARIANTS[variant], MESH_LABEL[mesh],
                                                triangles_in_deck(mesh)))
    ax.set_xlabel('punch displacement d_y [cm]')
    ax.set_ylabel('punch load, half model [kN per cm of thickness]')
    ax.set_title('Seed punch (Hu & Wu 2013, sec. 4.1): load vs displacement')
    ax.set_xlim(0, PUNCH_DEPTH * 1.02)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc='lower right')
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_pressure(mesh, states, path):
    """Element pressure on the deformed mesh, ME-FEM left, standard right, one colour scale
    (the 1st-99th percentile range of the ME-FEM field, so a standard field that oscillates
    beyond it saturates)."""
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 3.9), layout='constrained')
    p_me = states['mefem']['pressure']
    lo, hi = np.percentile(p_me, [1, 99])
    for ax, variant in zip(axes, ('mefem', 'standard')):
        s = states[variant]
        xd = s['x'] + s['u']
        pc = ax.tripcolor(xd[:, 0], xd[:, 1], s['tri'], facecolors=s['pressure'],
                          cmap='jet', vmin=lo, vmax=hi, edgecolors='none')
        ax.set_aspect('equal')
        ax.set_title('%s, mesh %s, d_y = %.2f cm' % (VARIANTS[variant], mesh, PUNCH_DEPTH),
                     fontsize=9)
        ax.set_xlabel('x [cm]')
        ax.set_ylabel('y [cm]')
    cb = fig.colorbar(pc, ax=axes, shrink=0.9)
    cb.set_label('pressure -tr(sigma)/3 [N/cm^2]')
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main():
    jobs = int(sys.argv[sys.argv.index('--jobs') + 1]) if '--jobs' in sys.argv else 2
    exe = os.path.abspath(sys.argv[sys.argv.index('--exe') + 1]) if '--exe' in sys.argv \
        else os.path.join(ROOT, 'bin', 'mefem')
    if '--no-run' not in sys.argv:
        start = time.time()
        run_all(jobs, exe)
        print('all runs: %.0f s' % (time.time() - start))
    os.makedirs(DATA, exist_ok=True)
    curves, rows, finals = {}, [], {}
    for mesh in MESH_ORDER:
        for variant in VARIANTS:
            name = deck_name(mesh, variant)
            h5 = os.path.join(OUT, name, name + '.h5')
            with open(os.path.join(OUT, name + '.log')) as f:
                text = f.read()
            counts = newton_counts(text)
            if not os.path.exists(h5):
                print('%s: no results' % name)
                continue
            t, d, load = load_curve(h5)
            curves[(mesh, variant)] = (t, d, load)
            state = final_state(h5)
            finals[(mesh, variant)] = state
            cb = checkerboard(state)
            rows.append({'mesh': mesh, 'element': variant, 'triangles': triangles_in_deck(mesh),
                         'reached_d': d[-1], 'load_at_0.35': value_at(d, load, PUNCH_DEPTH),
                         'p_ref': cb['p_ref'], 'jump_rms': cb['jump_rms'],
                         'jump_rms_plastic': cb['jump_rms_plastic'],
                         'steps': counts[0], 'cut_backs': counts[1], 'iterations': counts[2],
                         'seconds': counts[3]})
    # curves (CSV and figure)
    with open(os.path.join(DATA, 'punch_load_displacement.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(['mesh', 'element', 'triangles', 'time', 'd_y_cm', 'load_N_per_cm'])
        for (mesh, variant), (t, d, load) in sorted(curves.items()):
            for k in range(len(t)):
                w.writerow([mesh, variant, triangles_in_deck(mesh), '%.6g' % t[k],
                            '%.6g' % d[k], '%.6g' % load[k]])
    plot_curves(curves, os.path.join(DATA, 'punch_load_displacement.png'))
    with open(os.path.join(DATA, 'punch_summary.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: ('%.6g' % v if isinstance(v, float) else v) for k, v in r.items()})
    # pressure contours on the finest structured and irregular meshes
    for mesh in ('s3', 'u2'):
        if (mesh, 'mefem') in finals and (mesh, 'standard') in finals:
            plot_pressure(mesh, {v: finals[(mesh, v)] for v in VARIANTS},
                          os.path.join(DATA, 'punch_pressure_%s.png' % mesh))
    # summary
    print()
    print('%-4s %-9s %6s %9s %12s %10s %9s %9s %6s %5s %6s %6s' % (
        'mesh', 'element', 'tri', 'd_end', 'F(0.35) N/cm', 'p_ref', 'jump_rms', 'jump_pl',
        'steps', 'cuts', 'iters', 'sec'))
    for r in rows:
        print('%-4s %-9s %6d %9.4f %12.1f %10.1f %9.4f %9.4f %6d %5d %6d %6.0f' % (
            r['mesh'], r['element'], r['triangles'], r['reached_d'], r['load_at_0.35'],
            r['p_ref'], r['jump_rms'], r['jump_rms_plastic'], r['steps'], r['cut_backs'],
            r['iterations'], r['seconds']))
    me = sorted((r for r in rows if r['element'] == 'mefem'), key=lambda r: -r['triangles'])
    finest = me[:3]
    loads = np.array([r['load_at_0.35'] for r in finest])
    spread = (loads.max() - loads.min()) / loads.mean()
    print()
    print('ME-FEM load at d_y = %.2f on the three finest meshes (%s): %s N/cm; spread '
          '(max - min)/mean = %.2f %% (target < 2 %%)' % (
              PUNCH_DEPTH, ', '.join(r['mesh'] for r in finest),
              ', '.join('%.1f' % v for v in loads), 100 * spread))
    for mesh in MESH_ORDER:
        pair = [r for r in rows if r['mesh'] == mesh]
        if len(pair) == 2:
            print('mesh %s: standard / ME-FEM load at 0.35 = %.3f, pressure jump RMS ratio '
                  'standard / ME-FEM = %.1f' % (mesh, pair[1]['load_at_0.35'] /
                                               pair[0]['load_at_0.35'],
                                               pair[1]['jump_rms'] / pair[0]['jump_rms']))


if __name__ == '__main__':
    main()
