"""Eroding contacts (*CONTACT_ERODING_SURFACE_TO_SURFACE / _SINGLE_SURFACE with EROSOP = 1,
doc/keywords.md 3.10): the faces that erosion exposes join the contact (explicit; mm, t, s,
N, MPa).

A steel block 4 x 4 x 2 mm (1 mm hexahedra) held at its base: its top layer (part 2) erodes at
t = 1 us (*MAT_ADD_EROSION FAILTM), before a rigid punch (2 x 2 mm, part 3) moving down at
10 m/s from 0.1 mm above it arrives; the punch then meets the faces that were inside the block,
between the layers, and presses 0.02 mm into the lower layer (part 1) by the end.

1. Eroding contact, SURFA the part set {1, 2}: the exposed faces carry the punch. The same
   run with a plain contact whose SURFA is part 1 alone (its top faces are its boundary from
   the start) is the reference: the contact forces agree (1e-6 of the peak; measured: the
   same bits) and so does every displacement.
2. A plain contact on {1, 2} (and an eroding one with EROSOP = 0, warned): the faces inside
   never join, the punch passes through the lower layer's top with no force.
3. The eroding contact on 2 ranks: the same contact forces and displacements, bit for bit.
4. *CONTACT_ERODING_SINGLE_SURFACE over parts 1, 2, 3: the exposed faces carry the punch,
   which pushes the lower layer as in the surface-to-surface reference (within 5 %); the plain
   single surface does not push it.
5. A missing card 4 (ISYM EROSOP IADJ) and EROSOP = 2: errors at the card.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from lsdyna_ascii import read_rcforc
from explicit_cases import run_case, eroding_punch_blocks, ERODING_PUNCH

checks = Checks('contact_eroding')
PRESS = ERODING_PUNCH['press']            # mm, into the lower layer by the end
xb = ERODING_PUNCH['block_nodes']
middle = int(np.nonzero((abs(xb[:, 0] - 2) < 1e-9) & (abs(xb[:, 1] - 2) < 1e-9) &
                        (abs(xb[:, 2] - 1) < 1e-9))[0][0])


def deck(contact, name, ranks=1):
    """Run the punch with the given contact card lines; returns (rc, text, out)."""
    return run_case(name, eroding_punch_blocks(contact), ranks)


def results(out, name):
    """(rcforc master z force over time, final displacement of every node by node id)."""
    force = read_rcforc(os.path.join(out, 'rcforc'))[1]['master']['z']
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        last = sorted(f['states'])[-1]
        u = f['states/%s/point/displacement' % last][()][order]
    return np.asarray(force), u


def run(contact, name, ranks=1, expect_ok=True):
    rc, text, out = deck(contact, name, ranks)
    checks.check((rc == 0) == expect_ok, name + ': run %s' % ('succeeds' if expect_ok else
                                                               'is refused'), text[-600:])
    if rc != 0:
        return None, text
    return results(out, name), text


surface_card = lambda a, b, atype, btype: [f10(a, b, atype, btype), f10(0.0), '']
eroding = ['*CONTACT_ERODING_SURFACE_TO_SURFACE'] + surface_card(1, 3, 2, 3) + [f10(0, 1, 1)]
reference = ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE'] + surface_card(1, 3, 3, 3)
plain = ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE'] + surface_card(1, 3, 2, 3)
closed = ['*CONTACT_ERODING_SURFACE_TO_SURFACE'] + surface_card(1, 3, 2, 3) + [f10(0, 0, 1)]
single = ['*CONTACT_ERODING_SINGLE_SURFACE'] + surface_card(2, 0, 2, 0) + [f10(0, 1, 1)]

(a, text_a) = run(eroding, 'eroding')
(b, _) = run(reference, 'eroding_reference')
if a is not None and b is not None:
    fa, ua = a
    fb, ub = b
    peak = np.abs(fb).max()
    diff = np.abs(fa - fb).max() / peak
    print('    punch force at the end: eroding %.5g N, reference %.5g N (peak %.5g N); largest '
          'difference %.2e of the peak; lower layer top under the punch moved %.5f mm '
          '(punch %.3f mm past it)' % (fa[-1], fb[-1], peak, diff, ua[middle, 2], PRESS))
    checks.check('eroded 16 cells' in text_a, 'eroding: the top layer (16 elements) erodes',
                 text_a[-300:])
    checks.check(peak > 0.0 and len(fa) == len(fb) and diff < 1e-6, 'eroding contact: the '
                 'exposed faces carry the punch as the lower layer\'s own boundary does (forces '
                 'within 1e-6 of the peak)', '%.2e' % diff)
    checks.check(-ua[middle, 2] > 0.01 * PRESS and np.array_equal(ua, ub), 'eroding '
                 'contact: the lower layer\'s top is pushed down, every displacement as in '
                 'the reference', '%.5f' % ua[middle, 2])
for label, card in (('plain', plain), ('erosop0', closed)):
    (c, text_c) = run(card, 'eroding_' + label)
    if c is not None:
        fc, uc = c
        print('    %s: punch force at the end %.3g N, lower layer top moved %.2e mm'
              % (label, fc[-1], uc[middle, 2]))
        checks.check(fc[-1] == 0.0 and abs(uc[middle, 2]) < 1e-3 * PRESS, label + ': the '
                     'faces inside never join: no force at the end, the punch passes through',
                     '%g %g' % (fc[-1], uc[middle, 2]))
        if label == 'erosop0':
            checks.check('EROSOP = 0' in text_c, 'EROSOP = 0 is warned', text_c[-300:])
(d, _) = run(eroding, 'eroding_np2', ranks=2)
if a is not None and d is not None:
    checks.check(np.array_equal(a[0], d[0]) and np.array_equal(a[1], d[1]), 'eroding contact '
                 'on 1 and 2 ranks: the same forces and displacements, bit for bit')
# (a single surface's resultant is zero, action and reaction within it: compare the push)
(e, _) = run(single, 'eroding_single')
(g, _) = run(['*CONTACT_AUTOMATIC_SINGLE_SURFACE'] + surface_card(2, 0, 2, 0), 'single_plain')
if e is not None and g is not None and b is not None:
    ratio = e[1][middle, 2] / b[1][middle, 2]
    print('    single surface: lower layer top under the punch moved %.5g mm (eroding), %.3g mm '
          '(plain); eroding / surface-to-surface reference %.4f'
          % (e[1][middle, 2], g[1][middle, 2], ratio))
    checks.check(abs(ratio - 1) < 0.05 and g[1][middle, 2] == 0.0, 'eroding single surface: '
                 'the exposed faces carry the punch (push within 5 % of the reference; none '
                 'with the plain single surface)', '%.4f %g' % (ratio, g[1][middle, 2]))
# input errors
(_, text) = run(['*CONTACT_ERODING_SURFACE_TO_SURFACE'] + surface_card(1, 3, 2, 3),
                'eroding_missing', expect_ok=False)
checks.check('missing card 4 of the eroding contact' in text, 'a missing card 4: an error at '
             'the card', text[-300:])
(_, text) = run(['*CONTACT_ERODING_SURFACE_TO_SURFACE'] + surface_card(1, 3, 2, 3) +
                [f10(0, 2, 1)], 'eroding_bad', expect_ok=False)
checks.check('field EROSOP must be 0 or 1' in text, 'EROSOP = 2: an error at the card',
             text[-300:])
checks.exit()
