#!/usr/bin/python3
"""Plot the time histories of a mefem run (glstat, rcforc, rwforc, rbdout, nodout) as PNG files.

Usage: /usr/bin/python3 post/plot_histories.py RESULTS_DIR [--out DIR] [--length mm]
                                               [--force N] [--time s]

RESULTS_DIR is the run's output directory (`-o` of mefem, by default results/<deck name>/).
Every history file found there gives one figure (files that are absent are skipped):
  energies.png        glstat: kinetic, internal, external work, total, stonewall and sliding
                      energy against time, and the energy ratio
  contact_forces.png  rcforc: normal and tangential force of each interface against time
  wall_forces.png     rwforc: normal force of each rigid wall against time
  rigid_bodies.png    rbdout: the load-stroke curve of each rigid part (reaction force against
                      displacement, the direction it moves most), and its displacement in time
  nodes.png           nodout: displacement of each history node against time
mefem converts no units: the axis labels use the deck's units given by --length, --force and
--time (default mm, N, s; energies are force x length). Needs /usr/bin/python3 with numpy and
matplotlib (Debian's python3-numpy, python3-matplotlib, which `make` installs).
"""
import argparse
import os
import sys

import numpy as np
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lsdyna_ascii import (read_glstat, read_nodout, read_rbdout, read_rcforc,  # noqa: E402
                          read_rwforc)

ENERGIES = ['kinetic energy', 'internal energy', 'external work', 'total energy',
            'stonewall energy', 'sliding interface energy']


def plot_energies(path, units, out):
    """glstat: the energies and the energy ratio against time."""
    g = read_glstat(path)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), sharex=True,
                                      gridspec_kw={'height_ratios': [3, 1]})
    for name in ENERGIES:
        if name in g and np.any(g[name] != 0):
            top.plot(g['time'], g[name], label=name)
    label(top, None, 'energy [%s %s]' % (units.force, units.length))
    bottom.plot(g['time'], g['total energy / initial energy'], color='k')
    label(bottom, 'time [%s]' % units.time, 'energy ratio', legend=False)
    return save(fig, out, 'energies.png')


def plot_contact(path, units, out):
    """rcforc: normal and tangential force of each interface (the force on the slave side)."""
    interfaces = read_rcforc(path)
    fig, ax = plt.subplots(figsize=(7, 4))
    for cid, sides in sorted(interfaces.items()):
        side = sides['slave']
        ax.plot(side['time'], side['normal'], label='interface %s: normal' % cid)
        if np.any(side.get('tangential', np.zeros(1)) != 0):
            ax.plot(side['time'], side['tangential'], '--', label='interface %s: tangential'
                    % cid)
    label(ax, 'time [%s]' % units.time, 'contact force [%s]' % units.force)
    return save(fig, out, 'contact_forces.png')


def plot_walls(path, units, out):
    """rwforc: the normal force of each rigid wall against time."""
    walls = read_rwforc(path)
    fig, ax = plt.subplots(figsize=(7, 4))
    for wid, wall in sorted(walls.items()):
        ax.plot(wall['time'], wall['normal'], label='wall %s' % wid)
    label(ax, 'time [%s]' % units.time, 'normal force [%s]' % units.force)
    return save(fig, out, 'wall_forces.png')


def plot_rigid_bodies(path, units, out):
    """rbdout: per rigid part, the reaction force against its displacement along the direction
    it moves most (the load-stroke curve of a tool), and that displacement against time."""
    bodies = read_rbdout(path)
    fig, (stroke, history) = plt.subplots(1, 2, figsize=(10, 4))
    for pid, body in sorted(bodies.items()):
        disp = np.array([body[c + '-disp'] for c in 'xyz'])
        axis = int(np.argmax(np.max(abs(disp), axis=1)))
        name = 'xyz'[axis]
        stroke.plot(abs(disp[axis]), abs(body[name + '-reaction']),
                    label='part %s (%s)' % (pid, name))
        history.plot(body['time'], disp[axis], label='part %s (%s)' % (pid, name))
    label(stroke, '|displacement| [%s]' % units.length, '|reaction force| [%s]' % units.force)
    label(history, 'time [%s]' % units.time, 'displacement [%s]' % units.length)
    return save(fig, out, 'rigid_bodies.png')


def plot_nodes(path, units, out):
    """nodout: the displacement magnitude of each history node against time."""
    n = read_nodout(path)
    fig, ax = plt.subplots(figsize=(7, 4))
    for k, nid in enumerate(n['ids']):
        magnitude = np.sqrt(sum(n[c + '-disp'][:, k] ** 2 for c in 'xyz'))
        ax.plot(n['time'], magnitude, label='node %d' % nid)
    label(ax, 'time [%s]' % units.time, '|displacement| [%s]' % units.length,
          legend=len(n['ids']) <= 12)
    return save(fig, out, 'nodes.png')


def label(ax, xlabel, ylabel, legend=True):
    """Axis labels (xlabel None: shared with the axes below), legend and grid."""
    if xlabel:
        ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if legend:
        ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def save(fig, out, name):
    """Write the figure (numbers in powers of ten where they are small or large); its path."""
    for ax in fig.axes:
        ax.ticklabel_format(style='sci', scilimits=(-3, 4))
    fig.tight_layout()
    path = os.path.join(out, name)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


PLOTS = [('glstat', plot_energies), ('rcforc', plot_contact), ('rwforc', plot_walls),
         ('rbdout', plot_rigid_bodies), ('nodout', plot_nodes)]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('results', help='the run\'s output directory (mefem -o)')
    parser.add_argument('--out', help='where the PNG files go (default: RESULTS_DIR)')
    parser.add_argument('--length', default='mm', help='length unit of the deck (default mm)')
    parser.add_argument('--force', default='N', help='force unit of the deck (default N)')
    parser.add_argument('--time', default='s', help='time unit of the deck (default s)')
    units = parser.parse_args()
    if not os.path.isdir(units.results):
        parser.error('no such directory: %s' % units.results)
    out = units.out or units.results
    os.makedirs(out, exist_ok=True)
    written = 0
    for name, plot in PLOTS:
        path = os.path.join(units.results, name)
        if not os.path.exists(path):
            continue
        print('wrote', plot(path, units, out))
        written += 1
    if written == 0:
        parser.error('no history file (glstat, rcforc, rwforc, rbdout, nodout) in %s: ask for '
                     'them with *DATABASE_GLSTAT, _RCFORC, _NODOUT ... in the deck'
                     % units.results)


if __name__ == '__main__':
    main()
