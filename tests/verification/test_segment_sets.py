"""*SET_SEGMENT_GENERAL (issue 23): segment sets made from the exterior faces of parts, boxes and
single segments, oriented outward (keywords.md 3.6; mm, t, s, N, MPa). A free steel cube of
2 x 2 x 2 hexahedra (lower layer part 1, upper part 2), 20 us, loaded by *LOAD_SEGMENT_SET with
the set, against the same segments listed in a *SET_SEGMENT (the reference, built here from
the hexahedra's faces). The nodal forces are summed in the set's order, so a set whose
segments come in another order may differ in the last bits: displacements within 1e-12 of the
cube's size (the positions x + u carry the round-off; the squeeze of case 3 moves the nodes by
only 7e-6 mm):
1. BOX 1 (around z = 1): the 4 top quadrilaterals (here the same order: the same bits);
2. ALL less DBOX 2 (z <= 0.9): a segment leaves only when all its nodes are in the box, so the
   top and the 8 upper side quadrilaterals stay;
3. ALL: the 24 exterior quadrilaterals, and under pressure every node moves inwards (the faces
   point outward);
4. PART 2 (the upper layer's own exterior, its bottom face inside the cube included) less DSEG
   of one top quadrilateral: its 15 other faces.
(Stiffness hourglass control, IHQ 6.)
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, box_hexes, curve, run_case

checks = Checks('segment sets')
x, conn = box_hexes(1.0, 1.0, 1.0, 2, 2, 2)
conn = np.array(conn)
upper = x[conn].mean(axis=1)[:, 2] > 0.5
HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def faces(elements):
    """Exterior faces of a group of hexahedra, oriented outward (by the cell centre)."""
    count = {}
    for e in elements:
        for f in HEX_FACES:
            nodes = [int(conn[e][a]) for a in f]
            key = tuple(sorted(nodes))
            count.setdefault(key, []).append((e, nodes))
    out = []
    for key, items in count.items():
        if len(items) != 1:
            continue
        e, nodes = items[0]
        p = x[nodes]
        normal = np.cross(p[1] - p[0], p[2] - p[0])
        if normal @ (p.mean(axis=0) - x[conn[e]].mean(axis=0)) < 0:
            nodes = nodes[::-1]
        out.append(nodes)
    return sorted(out, key=lambda f: tuple(x[f].mean(axis=0)))


def segment_list(sid, segments):
    return ['*SET_SEGMENT', f10(sid)] + [f10(*[n + 1 for n in s]) for s in segments]


def deck(segment_cards):
    ids = np.arange(len(conn))
    return [nodes_card(x),
            elements_card('ELEMENT_SOLID', conn[~upper]),
            elements_card('ELEMENT_SOLID', conn[upper], pid=2, first_id=int((~upper).sum()) + 1),
            ['*PART', 'lower', f10(1, 1, 1, 0, 1), '*PART', 'upper', f10(2, 1, 1, 0, 1),
             '*SECTION_SOLID', f10(1, 1), '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3),
             '*HOURGLASS', f10(1, 6, 1.0)],
            segment_cards, ['*LOAD_SEGMENT_SET', f10(9, 1, 10.0)], curve(1, [(0.0, 1.0), (1.0, 1.0)]),
            ['*DEFINE_BOX', f10(1, -0.1, 1.1, -0.1, 1.1, 0.99, 1.01),
             '*DEFINE_BOX', f10(2, -0.1, 1.1, -0.1, 1.1, -0.1, 0.9)],
            ['*CONTROL_TERMINATION', f10(2.0e-5), '*DATABASE_BINARY_D3PLOT', f10(2.0e-5)]]


def final(name, blocks):
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-500:])
    if rc != 0:
        return None
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        last = sorted(f['states'])[-1]
        return (f['states/%s/point/displacement' % last][()][order],
                f['states/%s/point/velocity' % last][()][order])


def compare(name, cards, reference):
    """The set's run against the listed segments' run (1e-12 of the 1 mm cube)."""
    r = final(name, deck(cards))
    r_ref = final(name + '_listed', deck(segment_list(9, reference)))
    if r is None or r_ref is None:
        return None
    error = np.max(np.abs(r[0] - r_ref[0])) / 1.0
    checks.check(error < 1e-12, '%s: the displacements of the %d segments listed (%.1e mm)'
                 % (name, len(reference), error))
    return r


exterior = faces(range(len(conn)))
top = [f for f in exterior if np.all(abs(x[f][:, 2] - 1.0) < 1e-9)]
general = lambda *entries: ['*SET_SEGMENT_GENERAL', f10(9)] + list(entries)  # noqa: E731
compare('seg_box', general('BOX       ' + f10(1)), top)
compare('seg_all_dbox', general('ALL', 'DBOX      ' + f10(2)),
        [f for f in exterior if not np.all(x[f][:, 2] <= 0.9)])
r = compare('seg_all', general('ALL'), exterior)
if r is not None:
    checks.check(len(exterior) == 24 and np.all((x - 0.5) * r[0] <= 1e-15),
                 'ALL: every node moves inwards (the faces point outward, the pressure squeezes)')
drop = top[0]
own = faces(np.nonzero(upper)[0])
compare('seg_part_dseg', general('PART      ' + f10(2), 'DSEG      ' + f10(*[n + 1 for n in drop])),
        [f for f in own if sorted(f) != sorted(drop)])
checks.exit()
