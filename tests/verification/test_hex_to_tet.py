"""input/hex_to_tet.py, the splitting of a hex deck into tets (issue 22's stop-gap until mefem
computes hexahedra): a distorted 3 x 3 x 3 hex block, fixed-format cards in both the one-line
and the two-line *ELEMENT_SOLID layout, node ids shuffled (the face cut follows the lowest node
id, so it must not follow the numbering of a structured grid).

Checks: 12 tets and one new node per hex; every tet positive; the tets fill the unit block
(its outer faces are planar: volume 1 to round-off); conformity (every triangle inside the block is
shared by exactly two tets, with opposite orientations; the outside ones once); and the patch
test through bin/mefem, ME-FEM (ELFORM 43 set by the script), linear static: the linear field
prescribed on the block's boundary is reproduced at every node, the centroids included, to
1e-9 (a non-conforming split fails it).
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import ROOT, Checks, free, read_state, run  # noqa: E402

checks = Checks('hex_to_tet')
OUT = os.path.join(ROOT, 'tests', 'out', 'hex_to_tet')
os.makedirs(OUT, exist_ok=True)
N = 3
A = np.array([[1.0e-3, 2.0e-3, -0.5e-3], [-1.5e-3, 0.5e-3, 1.0e-3], [0.7e-3, -0.2e-3, 1.2e-3]])
B = np.array([1.0e-3, -2.0e-3, 0.5e-3])
rng = np.random.default_rng(22)

# the hex block: grid nodes, interior ones moved, ids shuffled
g = np.linspace(0.0, 1.0, N + 1)
x = np.array([[a, b, c] for c in g for b in g for a in g])
inside = np.all((x > 0) & (x < 1), axis=1)
x[inside] += rng.uniform(-0.15, 0.15, size=(inside.sum(), 3)) / N
ids = rng.permutation(len(x)) * 3 + 7                   # shuffled, with gaps
idx = lambda i, j, k: k * (N + 1) ** 2 + j * (N + 1) + i
hexes = []
for k in range(N):
    for j in range(N):
        for i in range(N):
            hexes.append([idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k), idx(i, j + 1, k),
                          idx(i, j, k + 1), idx(i + 1, j, k + 1), idx(i + 1, j + 1, k + 1),
                          idx(i, j + 1, k + 1)])
boundary = ~inside
exact = x @ A.T + B
lines = ['*KEYWORD', '*NODE'] + ['%8d%16.9f%16.9f%16.9f' % (ids[n], *x[n]) for n in range(len(x))]
lines += ['*ELEMENT_SOLID']
for e, h in enumerate(hexes):
    if e % 2 == 0:                                          # one-line legacy layout
        lines.append('%8d%8d' % (e + 1, 1) + ''.join('%8d' % ids[n] for n in h))
    else:                                                   # two-line layout
        lines += ['%8d%8d' % (e + 1, 1), ''.join('%8d' % ids[n] for n in h)]
lines += ['*PART', 'block', '%10d%10d%10d' % (1, 1, 1), '*SECTION_SOLID', '%10d%10d' % (1, 1),
          '*MAT_ELASTIC', '%10d%10.3g%10.1f%10.2f' % (1, 7.85e-9, 1000.0, 0.3),
          '*CONTROL_IMPLICIT_GENERAL', '%10d%10.1f' % (1, 1.0),
          '*CONTROL_IMPLICIT_SOLUTION', '%10d' % 1, '*CONTROL_TERMINATION', '%10.1f' % 1.0,
          '*DEFINE_CURVE', '%10d' % 1, '%20.1f%20.1f' % (0.0, 0.0), '%20.1f%20.1f' % (1.0, 1.0),
          '*BOUNDARY_PRESCRIBED_MOTION_NODE']
for n in np.nonzero(boundary)[0]:
    for d in range(3):
        lines.append(free(int(ids[n]), d + 1, 2, 1, float(exact[n, d])))
lines.append('*END')
hex_deck = os.path.join(OUT, 'hex_block.k')
with open(hex_deck, 'w') as f:
    f.write('\n'.join(lines) + '\n')

tet_deck = os.path.join(OUT, 'tet_block.k')
p = subprocess.run([sys.executable, os.path.join(ROOT, 'input', 'hex_to_tet.py'), hex_deck,
                    tet_deck], capture_output=True, text=True)
checks.check(p.returncode == 0 and '27 hexahedra split into 324 tetrahedra (27 new nodes)'
             in p.stdout and 'now ELFORM 43' in p.stdout, 'the script splits the 27 hexahedra '
             'into 324 tetrahedra with 27 new nodes', p.stdout + p.stderr)

# read the tet deck back (one-line tets, I8 nodes)
nodes, tets, keyword = {}, [], None
with open(tet_deck) as f:
    for line in f:
        if line.startswith('*'):
            keyword = line.strip()
            continue
        if line.startswith('$') or not line.strip():
            continue
        if keyword == '*NODE':
            nodes[int(line[:8])] = np.array([float(line[8 + 16 * k:24 + 16 * k]) for k in range(3)])
        elif keyword == '*ELEMENT_SOLID':
            tets.append([int(line[16 + 8 * k:24 + 8 * k]) for k in range(4)])
xt = np.array([nodes[n] for t in tets for n in t]).reshape(-1, 4, 3)
volumes = np.einsum('ij,ij->i', np.cross(xt[:, 1] - xt[:, 0], xt[:, 2] - xt[:, 0]),
                    xt[:, 3] - xt[:, 0]) / 6.0
faces = {}
for t in tets:
    for a, b, c in ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)):
        key = tuple(sorted((t[a], t[b], t[c])))
        faces.setdefault(key, []).append((t[a], t[b], t[c]))
outside = sum(1 for v in faces.values() if len(v) == 1)
paired = all(len(v) <= 2 for v in faces.values())
print('    %d tets, volumes %.3e .. %.3e, total %.12f; %d outside triangles'
      % (len(tets), volumes.min(), volumes.max(), volumes.sum(), outside))
checks.check(len(tets) == 324 and volumes.min() > 0, 'every tet positively oriented',
             'min volume %.3e' % volumes.min())
checks.check(abs(volumes.sum() - 1.0) < 1e-12, 'the tets fill the block (volume 1 to 1e-12)',
             '%.15f' % volumes.sum())
checks.check(paired and outside == 6 * N * N * 2, 'conforming: each inner triangle shared by '
             'two tets, the %d outside ones by one' % (6 * N * N * 2),
             '%d outside, pairs %s' % (outside, paired))

rc, text = run(tet_deck, os.path.join(OUT, 'tet_block'))
checks.check(rc == 0, 'the split deck runs (linear static, ELFORM 43)', text[-500:])
if rc == 0:
    s = read_state(os.path.join(OUT, 'tet_block', 'tet_block.h5'))
    want = np.array([nodes[i] for i in s['node_ids']]) @ A.T + B
    err = np.abs(s['displacement'] - want).max() / np.abs(want).max()
    print('    patch test: max relative error %.2e at %d nodes' % (err, len(want)))
    checks.check(err < 1e-9, 'patch test: the linear field at every node, centroids '
                 'included (1e-9)', '%.3e' % err)
checks.exit()
