#!/usr/bin/python3
"""The seed paper's punch benchmark (Hu & Wu 2013, section 4.1) as a reproducible study.

Runs the committed decks of input/punch/: the main model, a rigid punch pressed down in
frictionless mortar contact (punch_<mesh>_<element>.k), on all five meshes (structured s1-s3,
irregular u1-u2) with ME-FEM ELFORM 43 and standard ELFORM 13 triangles, and the comparison
model, the punch as prescribed vertical motion of the nodes under it
(punch_<mesh>_<element>_nodal.k), on the meshes of NODAL_MESHES; two runs at a time on one
rank each. Writes to doc/verification_data/:
  punch_load_displacement.csv   every load-displacement curve (half model, N per cm)
  punch_load_displacement.png   the rigid-punch curves of all meshes on one plot
  punch_tool_vs_nodal.png       rigid punch against nodal punch on s1, s3 and u2
  punch_summary.csv             per run: load at d_y = 0.35, pressure-jump measures, Newton,
                                tool force balance, horizontal tool force, pile-up
  punch_pressure_<mesh>_<model>.png  pressure contours at d_y = 0.35 on the deformed mesh,
                                ME-FEM and standard side by side (PRESSURE_PLOTS)
  punch_edge_<mesh>.png         the deformed mesh at the punch edge, rigid punch and nodal
                                punch (ME-FEM)
and prints a summary table with the spread of the ME-FEM load at d_y = 0.35 over the three
finest meshes. Setup and discussion: doc/verification.md, "Seed punch (paper section 4.1)".

Usage: /usr/bin/python3 post/punch_study.py [--no-run] [--jobs N] [--exe PATH]
  --no-run   reuse the results in tests/out/punch/ (only measure and plot)
  --jobs N   runs at the same time (default 2)
  --exe PATH the mefem executable (default bin/mefem)
`make punch` builds bin/mefem and runs this script (330 s of CPU, about 8-12 minutes on 2
cores shared with other jobs).
"""
import csv
import argparse
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
from punch_seed import (DECKS, HEIGHT, MESHES, OUT, PUNCH_DEPTH, PUNCH_HALF_WIDTH,  # noqa: E402
                        TOOL_HEIGHT, TOOL_LEFT, VARIANTS, checkerboard, deck_name, final_state,
                        load_curve, newton_counts, pile_up, step_iterations, support_balance,
                        tool_force_x, tool_penetration)

DATA = os.path.join(ROOT, 'doc', 'verification_data')
MESH_ORDER = ['s1', 's2', 's3', 'u1', 'u2']
MESH_LABEL = {'s1': 'structured s1', 's2': 'structured s2', 's3': 'structured s3',
              'u1': 'irregular u1', 'u2': 'irregular u2'}
COLOURS = {'s1': 'tab:blue', 's2': 'tab:orange', 's3': 'tab:green', 'u1': 'tab:red',
           'u2': 'tab:purple'}
NODAL_MESHES = tuple(MESH_ORDER)      # meshes also run with the nodal punch (comparison)
# pressure figures: (mesh, punch model); standard triangles complete the rigid-punch path on
# s1 only (doc/verification.md), so the finer meshes are shown with the nodal punch
PRESSURE_PLOTS = (('s1', 'tool'), ('s3', 'nodal'), ('u2', 'nodal'))


def runs():
    """(mesh, element, model) of every run of the study."""
    return [(m, v, 'tool') for m in MESH_ORDER for v in VARIANTS] + \
        [(m, v, 'nodal') for m in NODAL_MESHES for v in VARIANTS]


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
    order = sorted(runs(), key=lambda r: (r[1] != 'mefem', -triangles_in_deck(r[0])))
    os.makedirs(OUT, exist_ok=True)
    pending, running, done = list(order), {}, {}
    while pending or running:
        while pending and len(running) < jobs:
            mesh, variant, model = pending.pop(0)
            name = deck_name(mesh, variant, model)
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
    for (mesh, variant, model), (t, d, load) in sorted(curves.items()):
        if model != 'tool':
            continue
        style = '-' if variant == 'mefem' else '--'
        ax.plot(d, load / 1000.0, style, color=COLOURS[mesh], lw=1.4,
                label='%s, %s, %d triangles' % (VARIANTS[variant], MESH_LABEL[mesh],
                                                triangles_in_deck(mesh)))
    ax.set_xlabel('punch displacement d_y [cm]')
    ax.set_ylabel('punch load, half model [kN per cm of thickness]')
    ax.set_title('Seed punch (Hu & Wu 2013, sec. 4.1), rigid punch: load vs displacement',
                 fontsize=10)
    ax.set_xlim(0, PUNCH_DEPTH * 1.02)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc='lower right')
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_tool_vs_nodal(curves, path):
    """Rigid-punch and nodal-punch curves on s1, s3 and u2 (top) and their ratio (bottom)."""
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7.5, 7.0), sharex=True,
                                  gridspec_kw={'height_ratios': [2, 1]})
    for mesh in ('s1', 's3', 'u2'):
        for variant in VARIANTS:
            if (mesh, variant, 'tool') not in curves or (mesh, variant, 'nodal') not in curves:
                continue
            _, dt, ft = curves[(mesh, variant, 'tool')]
            _, dn, fn = curves[(mesh, variant, 'nodal')]
            style = '-' if variant == 'mefem' else '--'
            ax.plot(dt, ft / 1000.0, style, color=COLOURS[mesh], lw=1.4,
                    label='%s, %s: rigid punch' % (VARIANTS[variant], mesh))
            ax.plot(dn, fn / 1000.0, style, color=COLOURS[mesh], lw=0.8, alpha=0.6,
                    marker='.', ms=3, label='%s, %s: nodal punch' % (VARIANTS[variant], mesh))
            d = dn[(dn > 0.01 * PUNCH_DEPTH) & (dn <= dt[-1])]
            ax2.plot(d, np.interp(d, dt, ft) / np.interp(d, dn, fn), style,
                     color=COLOURS[mesh], lw=1.2, label='%s, %s' % (VARIANTS[variant], mesh))
    ax.set_ylabel('punch load, half model [kN/cm]')
    ax.set_title('Seed punch: rigid punch in contact against prescribed nodal motion',
                 fontsize=10)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc='lower right', ncol=2)
    ax2.axhline(1.0, color='k', lw=0.6)
    ax2.set_xlabel('punch displacement d_y [cm]')
    ax2.set_ylabel('rigid / nodal load')
    ax2.set_xlim(0, PUNCH_DEPTH * 1.02)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=6.5, ncol=3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def tool_outline(d):
    """Outline (x, y) of the rigid punch pushed down by d (punch_tool.k, sharp corner)."""
    b = HEIGHT - d
    return ([TOOL_LEFT, PUNCH_HALF_WIDTH, PUNCH_HALF_WIDTH],
            [b, b, b + TOOL_HEIGHT])


def draw_cell_field(ax, s, field, model, colour_style, outline_style):
    """One panel: the element field s[field] on the deformed mesh (tripcolor with
    colour_style), the rigid punch's outline (outline_style) when model is 'tool', equal axes
    in cm. Returns the tripcolor artist (for the colour bar)."""
    xd = s['x'] + s['u']
    pc = ax.tripcolor(xd[:, 0], xd[:, 1], s['tri'], facecolors=s[field], **colour_style)
    if model == 'tool':
        ox, oy = tool_outline(PUNCH_DEPTH * s['time'])
        ax.plot(ox, oy, '-', **outline_style)
    ax.set_aspect('equal')
    ax.set_xlabel('x [cm]')
    ax.set_ylabel('y [cm]')
    return pc


def plot_edge(mesh, states, path):
    """Deformed mesh around the punch edge at d_y = 0.35, rigid punch (left) and nodal punch
    (right), ME-FEM, coloured by the equivalent plastic strain."""
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.6), layout='constrained')
    hi = max(np.percentile(s['plastic_strain'], 99) for s in states.values())
    for ax, model in zip(axes, ('tool', 'nodal')):
        pc = draw_cell_field(ax, states[model], 'plastic_strain', model,
                             dict(cmap='viridis', vmin=0.0, vmax=hi, edgecolors='w',
                                  linewidth=0.3), dict(color='r', lw=1.5, label='rigid punch'))
        if model == 'tool':
            ax.legend(fontsize=8, loc='upper left')
        ax.set_xlim(PUNCH_HALF_WIDTH - 0.45, PUNCH_HALF_WIDTH + 0.45)
        ax.set_ylim(HEIGHT - 0.75, HEIGHT + 0.3)
        ax.set_title('%s punch, ME-FEM, mesh %s, d_y = %.2f cm' % (
            'rigid' if model == 'tool' else 'nodal', mesh, PUNCH_DEPTH), fontsize=9)
    cb = fig.colorbar(pc, ax=axes, shrink=0.9)
    cb.set_label('equivalent plastic strain')
    fig.savefig(path, dpi=130)
    plt.close(fig)


def plot_pressure(mesh, model, states, path):
    """Element pressure on the deformed mesh, ME-FEM left, standard right, one colour scale
    (the 1st-99th percentile range of the ME-FEM field, so a standard field that oscillates
    beyond it saturates)."""
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 3.9), layout='constrained')
    p_me = states['mefem']['pressure']
    lo, hi = np.percentile(p_me, [1, 99])
    for ax, variant in zip(axes, ('mefem', 'standard')):
        s = states[variant]
        pc = draw_cell_field(ax, s, 'pressure', model,
                             dict(cmap='jet', vmin=lo, vmax=hi, edgecolors='none'),
                             dict(color='k', lw=1.0))
        ax.set_xlim(0, 3.0)
        ax.set_ylim(0, HEIGHT + 0.3)
        ax.set_title('%s, %s punch, mesh %s, d_y = %.3f cm' % (
            VARIANTS[variant], 'rigid' if model == 'tool' else 'nodal', mesh,
            PUNCH_DEPTH * s['time']), fontsize=9)
    cb = fig.colorbar(pc, ax=axes, shrink=0.9)
    cb.set_label('pressure -tr(sigma)/3 [N/cm^2]')
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--no-run', action='store_true', help='reuse the results in '
                        'tests/out/punch/ (only measure and plot)')
    parser.add_argument('--jobs', type=int, default=2, help='runs at the same time (default 2)')
    parser.add_argument('--exe', default=os.path.join(ROOT, 'bin', 'mefem'),
                        help='the mefem executable (default bin/mefem)')
    args = parser.parse_args()
    jobs = args.jobs
    exe = os.path.abspath(args.exe)
    if not args.no_run:
        start = time.time()
        run_all(jobs, exe)
        print('all runs: %.0f s' % (time.time() - start))
    os.makedirs(DATA, exist_ok=True)
    curves, rows, finals = {}, [], {}
    for mesh, variant, model in runs():
        name = deck_name(mesh, variant, model)
        h5 = os.path.join(OUT, name, name + '.h5')
        with open(os.path.join(OUT, name + '.log')) as f:
            text = f.read()
        counts = newton_counts(text)
        per_step = step_iterations(text)
        if not os.path.exists(h5):
            print('%s: no results' % name)
            continue
        t, d, load = load_curve(h5, model)
        curves[(mesh, variant, model)] = (t, d, load)
        state = final_state(h5)
        finals[(mesh, variant, model)] = state
        cb = checkerboard(state)
        row = {'mesh': mesh, 'element': variant, 'model': model,
               'triangles': triangles_in_deck(mesh), 'reached_d': d[-1],
               'load_at_0.35': value_at(d, load, PUNCH_DEPTH),
               'p_ref': cb['p_ref'], 'jump_rms': cb['jump_rms'],
               'jump_rms_plastic': cb['jump_rms_plastic'],
               'steps': counts[0], 'cut_backs': counts[1], 'iterations': counts[2],
               'max_iterations_per_step': max(per_step) if per_step else 0,
               'seconds': counts[3], 'pile_up': pile_up(state),
               'tool_force_x': float('nan'), 'balance_error': float('nan'),
               'penetration': float('nan')}
        if model == 'tool':
            bt, ft, fr = support_balance(h5)
            row['tool_force_x'] = tool_force_x(h5)
            row['balance_error'] = float(np.max(abs(ft - fr)) / np.max(abs(ft)))
            row['penetration'] = tool_penetration(state)
        rows.append(row)
    # curves (CSV and figure)
    with open(os.path.join(DATA, 'punch_load_displacement.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(['mesh', 'element', 'model', 'triangles', 'time', 'd_y_cm',
                    'load_N_per_cm'])
        for (mesh, variant, model), (t, d, load) in sorted(curves.items()):
            for k in range(len(t)):
                w.writerow([mesh, variant, model, triangles_in_deck(mesh), '%.6g' % t[k],
                            '%.6g' % d[k], '%.6g' % load[k]])
    plot_curves(curves, os.path.join(DATA, 'punch_load_displacement.png'))
    plot_tool_vs_nodal(curves, os.path.join(DATA, 'punch_tool_vs_nodal.png'))
    with open(os.path.join(DATA, 'punch_summary.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: ('%.6g' % v if isinstance(v, float) else v) for k, v in r.items()})
    # pressure contours; the punch edge on the finest structured and irregular meshes
    for mesh, model in PRESSURE_PLOTS:
        if all((mesh, v, model) in finals for v in VARIANTS):
            plot_pressure(mesh, model, {v: finals[(mesh, v, model)] for v in VARIANTS},
                          os.path.join(DATA, 'punch_pressure_%s_%s.png' % (mesh, model)))
    for mesh in ('s3', 'u2'):
        if all((mesh, 'mefem', m) in finals for m in ('tool', 'nodal')):
            plot_edge(mesh, {m: finals[(mesh, 'mefem', m)] for m in ('tool', 'nodal')},
                      os.path.join(DATA, 'punch_edge_%s.png' % mesh))
    # summary
    print()
    print('%-4s %-9s %-6s %6s %7s %12s %8s %8s %8s %5s %4s %5s %4s %5s %8s %8s %8s %9s' % (
        'mesh', 'element', 'model', 'tri', 'd_end', 'F(0.35) N/cm', 'p_ref', 'jump_rms',
        'jump_pl', 'steps', 'cuts', 'iters', 'max', 'sec', 'Fx N/cm', 'pile-up',
        'balance', 'penetr.'))
    for r in rows:
        print('%-4s %-9s %-6s %6d %7.4f %12.1f %8.1f %8.4f %8.4f %5d %4d %5d %4d %5.0f %8.1f '
              '%8.4f %8.1e %9.2e' % (
                  r['mesh'], r['element'], r['model'], r['triangles'], r['reached_d'],
                  r['load_at_0.35'], r['p_ref'], r['jump_rms'], r['jump_rms_plastic'],
                  r['steps'], r['cut_backs'], r['iterations'], r['max_iterations_per_step'],
                  r['seconds'], r['tool_force_x'], r['pile_up'], r['balance_error'],
                  r['penetration']))
    for variant, model in (('mefem', 'tool'), ('mefem', 'nodal'), ('standard', 'nodal')):
        sel = sorted((r for r in rows if r['element'] == variant and r['model'] == model),
                     key=lambda r: -r['triangles'])
        finest = sel[:3]
        loads = np.array([r['load_at_0.35'] for r in finest])
        spread = (loads.max() - loads.min()) / loads.mean()
        print()
        print('%s, %s punch: load at d_y = %.2f on the three finest meshes (%s): %s N/cm; '
              'spread (max - min)/mean = %.2f %% (target < 2 %%)' % (
                  VARIANTS[variant], 'rigid' if model == 'tool' else 'nodal', PUNCH_DEPTH,
                  ', '.join(r['mesh'] for r in finest), ', '.join('%.1f' % v for v in loads),
                  100 * spread))
    by = {(r['mesh'], r['element'], r['model']): r for r in rows}
    for model in ('tool', 'nodal'):
        for mesh in MESH_ORDER:
            me, st = by.get((mesh, 'mefem', model)), by.get((mesh, 'standard', model))
            if me and st and st['reached_d'] >= PUNCH_DEPTH * (1 - 1e-6):
                print('mesh %s, %s punch: standard / ME-FEM load at 0.35 = %.3f, pressure '
                      'jump RMS ratio standard / ME-FEM = %.1f' % (
                          mesh, 'rigid' if model == 'tool' else 'nodal',
                          st['load_at_0.35'] / me['load_at_0.35'],
                          st['jump_rms'] / me['jump_rms']))
            elif st:
                print('mesh %s, %s punch: standard triangles stopped at d_y = %.4f' % (
                    mesh, 'rigid' if model == 'tool' else 'nodal', st['reached_d']))
    for mesh in NODAL_MESHES:
        for variant in VARIANTS:
            tool, nodal = by.get((mesh, variant, 'tool')), by.get((mesh, variant, 'nodal'))
            if tool and nodal:
                print('mesh %s, %s: rigid / nodal punch load at 0.35 = %.4f' % (
                    mesh, VARIANTS[variant], tool['load_at_0.35'] / nodal['load_at_0.35']))

if __name__ == '__main__':
    main()
