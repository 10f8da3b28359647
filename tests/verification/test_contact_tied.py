"""Tied contact, *CONTACT_TIED_SURFACE_TO_SURFACE / _NODES_TO_SURFACE (issue 23): each SURFA
node moves with the point of the SURFB facet it lies on (kinematic, doc/theory.md 10.12).

1. Patch test across non-matching meshes: a block of 3x3x3 cubes of 6 ME-FEM tets (SURFB) with
   a block of 4x4x3 on top (SURFA), pulled apart by a uniform tension on the top face (what a
   contact cannot carry), ramped smoothly over 100 us and held: every element stress equals
   the applied traction; the interface does not open; 1 and 2 ranks give the same bits.
2. Matching meshes: two halves of a block whose interface nodes coincide, tied, give the
   displacements of the same block meshed in one piece (a tie of coincident nodes is a merge),
   under a shear and tension load on the top face (standard tets: with ME-FEM the smoothing
   domains of the one-piece block reach across the interface, so the two differ slightly).
3. _OFFSET with a gap of 0.01 mm (SAST = SST = -0.05 sets the tolerance): the tension patch test again,
   the gap kept.
4. TIED_NODES_TO_SURFACE with a node set holding far nodes too: those are reported untied.
5. The nonlinear implicit analysis: the tension patch test, the tie as a change of unknowns
   (ME-FEM and standard tets): every element has the same stress (1e-9), the traction on the
   stretched area (1e-4, the estimate's own error), 2 ranks agree; the linear static analysis
   gives the traction exactly (1e-10);
   a tiebreak is refused (its failure is explicit only).
6. Tiebreak (*CONTACT_TIEBREAK_..., *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK OPTION 2):
   the tension patch test with NFLS = P/2: the nodes are released when the ramped traction
   reaches NFLS (t = T/2 by the ramp's symmetry), all of them, and the blocks part; 2 ranks
   give the same bits; the automatic form gives the same bits; the force form (NFLF = NFLS
   times an interior node's area) releases the interior nodes first at the same time; with
   NFLS above the load nothing is released and the run is the plain tie's, bit for bit.
   Shear then contact: a block pressed onto the other and pushed sideways by a load below the
   friction limit, SFLS below the shear it takes: the nodes are released in shear and the
   companion contact then carries the pressure and, by friction, the side load; on 2 ranks
   with the contact's work divided, the same releases and bits.
Units: mm, tonne, s, N, MPa.
"""
import os
import re
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from benchmarks import boundary_facets
from explicit_cases import box_tets, node_set, curve, run_case
from tied_cases import (E, NU, RHO, P, T, top_segments, symmetry, ramp, two_blocks, deck,
                        tiebreak_shear_blocks)

checks = Checks('contact_tied')


def last_state(out, name, what):
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        point = {k: f['states/%s/point/%s' % (last, k)][()][order] for k in ('displacement',
                                                                           'velocity')}
        return point, f['states/%s/cell/stress' % last][()]


def patch(gap, keyword, tie_card3, ranks_list=(1,)):
    x, c1, c2, n1 = two_blocks(gap)
    top = 2.0 + gap
    loads = symmetry(x) + top_segments(x, c2, top, 9) + ['*LOAD_SEGMENT_SET', f10(9, 1, -1.0)] \
        + ramp(P)           # pressure -P: a tension P on the top face
    tie = [keyword, f10(2, 1, 3, 3), '', tie_card3]
    results = {}
    for ranks in ranks_list:
        name = 'tied_patch_%s_np%d' % ('offset' if gap > 0 else 'flush', ranks)
        rc, text, out = run_case(name, deck(x, c1, c2, tie, loads), ranks=ranks)
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return None
        results[ranks] = last_state(out, name, None)
        if ranks == ranks_list[0]:
            m = [l for l in text.splitlines() if 'ties' in l]
            print('    %s' % (m[0] if m else 'no "ties" line'))
    point, stress = results[ranks_list[0]]
    expected = P / (1 - NU * P / E) ** 2       # tension on the reference area, free sides
    s_err = np.max(abs(stress[:, 2] / expected - 1))
    # the interface: the upper block's bottom nodes against the linear field fitted to the
    # lower block's top-face nodes; the lower face itself departs from a plane by the run's
    # residual vibration, and the tied nodes may not depart more (the weights themselves are
    # exact for linear fields: unit test test_tied_contact)
    u = point['displacement']
    bottom = np.nonzero(abs(x[:, 2] - (1.0 + gap)) < 1e-9)[0]
    bottom = bottom[bottom >= n1]
    top_lower = np.nonzero(abs(x[:n1, 2] - 1.0) < 1e-9)[0]
    basis = lambda n: np.column_stack([np.ones(len(n)), x[n, 0], x[n, 1]])
    fit = np.linalg.lstsq(basis(top_lower), u[top_lower], rcond=None)[0]
    own = np.max(abs(u[top_lower] - basis(top_lower) @ fit))
    jump = np.max(abs(u[bottom] - basis(bottom) @ fit))
    print('    gap %.3g: sigma_zz %.5f .. %.5f (expected %.5f MPa, max error %.1e); upper bottom '
          'nodes off the plane of the lower top face by %.1e mm, the lower face by %.1e mm '
          '(stretch %.1e mm)' % (gap, stress[:, 2].min(), stress[:, 2].max(), expected, s_err,
                                 jump, own, np.max(abs(u[:, 2]))))
    checks.check(s_err < 2e-3, 'gap %g: every element stress = applied tension within 0.2 %%'
                 % gap, '%.3e' % s_err)
    checks.check(jump <= 2 * own + 1e-12, 'gap %g: the tied nodes stay on the lower face (no '
                 'farther off its plane than the face itself)' % gap, '%.2e %.2e' % (jump, own))
    if len(ranks_list) > 1:
        a, b = results[ranks_list[0]][0], results[ranks_list[1]][0]
        same = all(np.array_equal(a[k], b[k]) for k in a)
        checks.check(same, 'gap %g: %d ranks give the bits of 1 rank' % (gap, ranks_list[1]),
                     '%.3e' % max(np.max(abs(a[k] - b[k])) for k in a))
    return results


def matching():
    """Two halves of a 1 x 1 x 2 block (the same 3x3x3 mesh twice, interface nodes
    coincident), tied, against the block in one piece; top face: shear and tension."""
    x, c1, c2, n1 = two_blocks(0.0, (3, 3, 3), (3, 3, 3))
    # the one-piece block: the upper half's interface nodes merged into the lower's
    merge_to = np.arange(len(x))
    for n in range(n1, len(x)):
        if abs(x[n, 2] - 1.0) < 1e-9:
            merge_to[n] = np.nonzero(np.all(abs(x[:n1] - x[n]) < 1e-9, axis=1))[0][0]
    keep = np.unique(merge_to)
    renumber = np.zeros(len(x), dtype=int)
    renumber[keep] = np.arange(len(keep))
    xm = x[keep]
    c2m = renumber[merge_to[c2]]
    top = 2.0
    fixed = node_set(1, np.nonzero(x[:, 2] < 1e-9)[0])
    s = np.linspace(0.0, 1.0, 41)
    shear = curve(2, [(T * v, 0.5 * P * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]
                  + [(1.0, 0.5 * P)])
    top_nodes = np.nonzero(abs(x[:, 2] - top) < 1e-9)[0]
    area = 1.0 / len(top_nodes)                 # (a rough nodal share: the same in both runs)
    runs = {}
    for name, xx, cc2, nodes in (('tied_matching', x, c2, top_nodes),
                                 ('tied_matching_merged', xm, c2m, renumber[top_nodes])):
        # the same steps in both runs (the merged nodes' larger masses would lengthen them):
        # LCTM caps them below both bounds
        loads = ['*SET_NODE_LIST', f10(1)] + fixed[2:] + ['*BOUNDARY_SPC_SET', f10(1, 0, 1, 1, 1)] \
            + node_set(5, nodes) + ['*LOAD_NODE_SET', f10(5, 1, 1, area), f10(5, 3, 2, area)] \
            + ramp(P) + shear + curve(3, [(0.0, 2.0e-8), (1.0, 2.0e-8)]) \
            + ['*CONTROL_TIMESTEP', f10(0.0, 0.9, 0, 0.0, 0.0, 3)]
        tie = ['*CONTACT_TIED_SURFACE_TO_SURFACE', f10(2, 1, 3, 3), '', ''] \
            if name == 'tied_matching' else []
        rc, text, out = run_case(name, deck(xx, c1, cc2, tie, loads, elform=10))
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            return
        runs[name] = last_state(out, name, None)[0]['displacement']
    u_tied = runs['tied_matching'][keep]
    u_one = runs['tied_matching_merged']
    diff = np.max(abs(u_tied - u_one)) / np.max(abs(u_one))
    print('    matching meshes: tied against one piece: largest displacement difference %.1e of '
          'the largest displacement (%.3e mm)' % (diff, np.max(abs(u_one))))
    checks.check(diff < 1e-9, 'matching meshes: the tie of coincident nodes gives the one-piece '
                 'block (1e-9)', '%.3e' % diff)


def untied_warning():
    x, c1, c2, n1 = two_blocks(0.0)
    loads = node_set(7, range(n1, len(x)))      # the whole upper block: only its bottom ties
    tie = ['*CONTACT_TIED_NODES_TO_SURFACE_ID', f10(4), f10(7, 1, 4, 3), '', '']
    rc, text, out = run_case('tied_untied', deck(x, c1, c2, tie, loads))
    n_bottom = np.sum(abs(x[n1:, 2] - 1.0) < 1e-9)
    want = 'contact 4: %d SURFA nodes are not tied' % (len(x) - n1 - n_bottom)
    checks.check(rc == 0 and ('contact 4 ties %d nodes' % n_bottom) in text and want in text,
                 'nodes to surface: the %d bottom nodes tied, the others reported' % n_bottom,
                 text[-600:])


def implicit_tie():
    """The tension patch test in the nonlinear implicit analysis (the ties as a change of
    unknowns, mefem_implicit_constraints): every element stress is the applied traction."""
    x, c1, c2, n1 = two_blocks(0.0)
    loads = symmetry(x) + top_segments(x, c2, 2.0, 9) + ['*LOAD_SEGMENT_SET', f10(9, 1, -1.0)] \
        + curve(1, [(0.0, 0.0), (1.0, P)])
    tie = ['*CONTACT_TIED_SURFACE_TO_SURFACE', f10(2, 1, 3, 3), '', '']
    results = {}
    for elform in (43, 10):
        for ranks in (1, 2):
            blocks = deck(x, c1, c2, tie, loads, elform=elform)
            blocks[-1] = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL',
                          f10(1, 0.25), '*DATABASE_BINARY_D3PLOT', f10(1.0)]
            name = 'tied_implicit_%d_np%d' % (elform, ranks)
            rc, text, out = run_case(name, blocks, ranks=ranks)
            checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
            if rc != 0:
                return
            with h5py.File(os.path.join(out, name + '.h5')) as f:
                last = sorted(f['states'].keys())[-1]
                order = np.argsort(f['mesh/node_ids'][()])
                results[elform, ranks] = (
                    {'displacement': f['states/%s/point/displacement' % last][()][order]},
                    f['states/%s/cell/stress' % last][()])
    expected = P / (1 - NU * P / E) ** 2
    for elform in (43, 10):
        point, stress = results[elform, 1]
        spread = np.ptp(stress[:, 2]) / np.mean(stress[:, 2])
        error = abs(np.mean(stress[:, 2]) / expected - 1)
        u2 = results[elform, 2][0]['displacement']
        ranks = np.max(abs(point['displacement'] - u2)) / np.max(abs(u2))
        print('    implicit tie, ELFORM %d: sigma_zz %.9f .. %.9f MPa (spread %.1e; the estimate '
              'P/(1 - nu P/E)^2 = %.6f, %.1e); 2 ranks %.1e' % (
                  elform, stress[:, 2].min(), stress[:, 2].max(), spread, expected, error, ranks))
        checks.check(spread < 1e-9 and error < 1e-4, 'implicit, ELFORM %d: the tie across '
                     'non-matching meshes passes the patch test (every element the same stress '
                     'to 1e-9, the traction on the stretched area within 1e-4)' % elform,
                     '%.2e %.2e' % (spread, error))
        checks.check(ranks < 1e-10, 'implicit, ELFORM %d: 2 ranks give 1 rank\'s displacements '
                     '(1e-10)' % elform, '%.2e' % ranks)
    # the linear static analysis: the same patch test, exact
    for elform in (43, 10):
        blocks = deck(x, c1, c2, tie, loads, elform=elform)
        blocks[-1] = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL',
                      f10(1, 1.0), '*CONTROL_IMPLICIT_SOLUTION', f10(1)]
        name = 'tied_linear_%d' % elform
        rc, text, out = run_case(name, blocks)
        checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
        if rc != 0:
            continue
        with h5py.File(os.path.join(out, name + '.h5')) as f:
            last = sorted(f['states'].keys())[-1]
            sigma = f['states/%s/cell/stress' % last][()]
        error = np.max(abs(sigma[:, 2] / P - 1))
        print('    linear static tie, ELFORM %d: sigma_zz / P - 1 within %.1e' % (elform, error))
        checks.check(error < 1e-10, 'linear static, ELFORM %d: the tie passes the patch test '
                     '(every stress the traction to 1e-10)' % elform, '%.2e' % error)
    blocks = deck(x, c1, c2, ['*CONTACT_TIEBREAK_SURFACE_TO_SURFACE', f10(2, 1, 3, 3), '', '',
                              f10(P, P)], loads)
    blocks[-1] = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.25)]
    rc, text, out = run_case('tiebreak_implicit', blocks)
    checks.check(rc == 1 and 'a tiebreak is explicit only' in text, 'implicit analysis refuses '
                 'a tiebreak when it starts', text[-400:])


def released(text):
    """[(time, count released, still tied)] of the log's tiebreak lines."""
    out = []
    for line in text.splitlines():
        m = re.match(r'explicit: t = (\S+): tiebreak .*: (\d+) node\(s\) released .*, (\d+) still '
                     r'tied', line)
        if m:
            out.append((float(m.group(1)), int(m.group(2)), int(m.group(3))))
    return out


def tiebreak_tension():
    """The tension patch test with a tie that fails at NFLS = P/2."""
    x, c1, c2, n1 = two_blocks(0.0)
    loads = symmetry(x) + top_segments(x, c2, 2.0, 9) + ['*LOAD_SEGMENT_SET', f10(9, 1, -1.0)] \
        + ramp(P)
    n_tied = np.sum(abs(x[n1:, 2] - 1.0) < 1e-9)
    h = 0.25                                    # the upper block's mesh size: interior area h^2
    forms = {
        'tiebreak': ['*CONTACT_TIEBREAK_SURFACE_TO_SURFACE_ID', f10(5), f10(2, 1, 3, 3), '', '',
                     f10(0.5 * P, 0.5 * P)],
        'tiebreak_auto': ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK_ID', f10(5),
                          f10(2, 1, 3, 3), '', '', f10(2, 0.5 * P, 0.5 * P)],
        'tiebreak_nodes': ['*CONTACT_TIEBREAK_NODES_TO_SURFACE_ID', f10(5), f10(2, 1, 3, 3), '',
                           '', f10(0.5 * P * h * h, 0.5 * P * h * h)],
        'tiebreak_strong': ['*CONTACT_TIEBREAK_SURFACE_TO_SURFACE_ID', f10(5), f10(2, 1, 3, 3),
                            '', '', f10(2.0 * P, 2.0 * P)],
        'tied_reference': ['*CONTACT_TIED_SURFACE_TO_SURFACE_ID', f10(5), f10(2, 1, 3, 3), '',
                           ''],
    }
    runs = {}
    for name, tie in forms.items():
        for ranks in ((1, 2) if name == 'tiebreak' else (1,)):
            run_name = '%s_np%d' % (name, ranks)
            rc, text, out = run_case(run_name, deck(x, c1, c2, tie, loads), ranks=ranks)
            checks.check(rc == 0, '%s: run succeeds' % run_name, text[-600:])
            if rc != 0:
                return
            runs[run_name] = (released(text), last_state(out, run_name, None)[0])
    events, point = runs['tiebreak_np1']
    t_first = events[0][0] if events else float('nan')
    v = t_first / T
    at_failure = P * (v - np.sin(2 * np.pi * v) / (2 * np.pi)) / (0.5 * P)
    gap = np.min(point['displacement'][n1:, 2][abs(x[n1:, 2] - 1.0) < 1e-9]) - \
        np.max(point['displacement'][:n1, 2][abs(x[:n1, 2] - 1.0) < 1e-9])
    print('    tiebreak in tension: first release at t = %.4g s (%.4f T), the traction then %.4f '
          'NFLS; %d events, %d of %d nodes released by %.4f T; interface open by %.3g mm at the '
          'end' % (t_first, v, at_failure, len(events), sum(e[1] for e in events), n_tied,
                   events[-1][0] / T if events else float('nan'), gap))
    checks.check(abs(at_failure - 1.0) < 0.02, 'tiebreak: the nodes fail when the traction '
                 'reaches NFLS (within 2 %)', '%.4f' % at_failure)
    checks.check(events and events[-1][2] == 0 and sum(e[1] for e in events) == n_tied,
                 'tiebreak: all %d tied nodes released' % n_tied, str(events))
    checks.check(events and events[-1][0] < 0.55 * T, 'tiebreak: the last node is released '
                 'within 0.05 T of the first', str(events[-1:]))
    checks.check(gap > 0.1, 'tiebreak: the blocks part (interface open by more than 0.1 mm)',
                 '%.3g' % gap)
    same = lambda a, b: all(np.array_equal(a[k], b[k]) for k in a)
    checks.check(same(point, runs['tiebreak_np2'][1]) and events == runs['tiebreak_np2'][0],
                 'tiebreak: 2 ranks release the same nodes at the same steps and give the bits '
                 'of 1 rank')
    checks.check(same(point, runs['tiebreak_auto_np1'][1]), 'tiebreak: the automatic form '
                 '(OPTION 2) gives the same bits')
    nodes_events = runs['tiebreak_nodes_np1'][0]
    n_interior = 9                              # (the 5 x 5 interface nodes' inner 3 x 3)
    v = nodes_events[0][0] / T if nodes_events else float('nan')
    at_failure = (v - np.sin(2 * np.pi * v) / (2 * np.pi)) / 0.5
    checks.check(nodes_events and 0 < nodes_events[0][1] <= n_interior and
                 abs(at_failure - 1.0) < 0.02, 'tiebreak, forces: interior nodes (the largest '
                 'share, at most %d) fail first, when their force reaches NFLF (within 2 %%)'
                 % n_interior,
                 '%s %.4f' % (nodes_events[:1], at_failure))
    strong = runs['tiebreak_strong_np1']
    checks.check(not strong[0] and same(strong[1], runs['tied_reference_np1'][1]),
                 'tiebreak: with NFLS above the load nothing is released, and the run is the '
                 'plain tie\'s (the same bits)')


def tiebreak_shear_then_contact():
    """A block pressed (P) onto another and pushed sideways (S = P/5, friction 0.6): the tie
    fails in shear (SFLS = P/10), then the companion contact holds the block."""
    x, c1, c2, n1 = two_blocks(0.0)
    shear_load = P / 5.0                    # (as tiebreak_shear_blocks loads it)
    blocks = tiebreak_shear_blocks()
    rc, text, out = run_case('tiebreak_shear', blocks)
    checks.check(rc == 0, 'tiebreak_shear: run succeeds', text[-600:])
    if rc != 0:
        return
    events = released(text)
    rows = [line.split() for line in open(os.path.join(out, 'rcforc'))
            if line.strip().startswith('slave')]
    t = np.array([float(r[3]) for r in rows])
    force = np.array([[float(r[5]), float(r[7]), float(r[9])] for r in rows])
    late = t >= 1.5 * T                     # loads constant from T on
    mean = force[late].mean(axis=0)
    with h5py.File(os.path.join(out, 'tiebreak_shear.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        u = f['states/%s/point/displacement' % last][()][order]
    on = abs(x[:, 2] - 1.0) < 1e-9
    overlap = np.max(u[:n1][on[:n1], 2]) - np.min(u[n1:][on[n1:], 2])
    v = events[0][0] / T if events else float('nan')
    print('    tiebreak in shear: first release at %.4f T (mean shear then %.3f SFLS), %d nodes '
          'released by %.4f T; contact force from 1.5 T on: mean (%.3f, %.3f, %.3f) N (loads '
          '%.3f sideways, %.3f pressing); the interface overlaps by at most %.3g mm at the end'
          % (v, shear_load * (v - np.sin(2 * np.pi * v) / (2 * np.pi)) / (0.1 * P),
             sum(e[1] for e in events), events[-1][0] / T if events else float('nan'),
             mean[0], mean[1], mean[2], shear_load, P, overlap))
    checks.check(events and events[-1][2] == 0 and events[-1][0] < T, 'tiebreak in shear: '
                 'every node released during the ramp', str(events[-1:]))
    checks.check(abs(mean[2] / P - 1.0) < 0.05 and abs(-mean[0] / shear_load - 1.0) < 0.10,
                 'tiebreak in shear: then the contact carries the pressure (5 %) and, by '
                 'friction, the side load (10 %)', str(mean))
    # 2 ranks, the companion contact's work divided among them (its held mask on every rank)
    os.environ['MEFEM_CONTACT_DIVIDE_MIN'] = '0'
    rc2, text2, out2 = run_case('tiebreak_shear_np2', blocks, ranks=2)
    del os.environ['MEFEM_CONTACT_DIVIDE_MIN']
    same = False
    if rc2 == 0:
        with h5py.File(os.path.join(out2, 'tiebreak_shear_np2.h5')) as f:
            last2 = sorted(f['states'].keys())[-1]
            order2 = np.argsort(f['mesh/node_ids'][()])
            same = np.array_equal(u, f['states/%s/point/displacement' % last2][()][order2])
    checks.check(same and released(text2) == events, 'tiebreak in shear: 2 ranks with the '
                 'contact divided release the same nodes at the same steps and give the bits of '
                 '1 rank', text2[-300:])
    checks.check(overlap < 0.1, 'tiebreak in shear: the released block does not sink into '
                 'the other (overlap below 0.1 mm: the penalty\'s static 0.016 mm and the '
                 'rocking the release starts; without the contact it sinks through)',
                 '%.3g' % overlap)


patch(0.0, '*CONTACT_TIED_SURFACE_TO_SURFACE', '', ranks_list=(1, 2))
patch(0.01, '*CONTACT_TIED_SURFACE_TO_SURFACE_OFFSET', f10(1.0, 1.0, -0.05))
matching()
untied_warning()
implicit_tie()
tiebreak_tension()
tiebreak_shear_then_contact()
checks.exit()
