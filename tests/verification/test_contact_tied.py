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
5. The nonlinear implicit analysis refuses a tied contact when it starts.
Units: mm, tonne, s, N, MPa.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', '..', 'post'))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from benchmarks import boundary_facets
from explicit_cases import box_tets, node_set, curve, run_case

E, NU, RHO, P, T = 1000.0, 0.3, 1.0e-9, 10.0, 1.0e-4
checks = Checks('contact_tied')


def top_segments(x, conn, z, sid):
    """*SET_SEGMENT of the faces of conn on the plane z (outward +z)."""
    seg = ['*SET_SEGMENT', f10(sid)]
    for f in boundary_facets(conn):
        f = [int(v) for v in f]
        if not all(abs(x[v, 2] - z) < 1e-9 for v in f):
            continue
        if np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[2] < 0:
            f = [f[0], f[2], f[1]]
        seg.append(f10(f[0] + 1, f[1] + 1, f[2] + 1, f[2] + 1))
    return seg


def symmetry(x):
    cards = []
    for k in range(3):
        dofs = [0, 0, 0]
        dofs[k] = 1
        cards += node_set(k + 1, np.nonzero(x[:, k] < 1e-9)[0])
        cards += ['*BOUNDARY_SPC_SET', f10(k + 1, 0, *dofs)]
    return cards


def ramp(p):
    s = np.linspace(0.0, 1.0, 41)
    return curve(1, [(T * v, p * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s] +
                 [(1.0, p)])


def two_blocks(gap, lower=(3, 3, 3), upper=(4, 4, 3)):
    x1, c1 = box_tets(1.0, 1.0, 1.0, *lower)
    x2, c2 = box_tets(1.0, 1.0, 1.0, *upper)
    x2 = x2 + [0.0, 0.0, 1.0 + gap]
    return np.vstack([x1, x2]), c1, c2 + len(x1), len(x1)


def deck(x, c1, c2, tie, loads, elform=43):
    return [nodes_card(x), elements_card('ELEMENT_SOLID', c1, pid=1),
            elements_card('ELEMENT_SOLID', c2, pid=2, first_id=len(c1) + 1),
            ['*PART', 'lower', f10(1, 1, 1), '*PART', 'upper', f10(2, 1, 1),
             '*SECTION_SOLID', f10(1, elform), '*MAT_ELASTIC', free(1, RHO, E, NU)], loads, tie,
            ['*CONTROL_TERMINATION', f10(1.5 * T), '*DATABASE_BINARY_D3PLOT', f10(T / 2)]]


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


def implicit_refused():
    x, c1, c2, n1 = two_blocks(0.0)
    blocks = deck(x, c1, c2, ['*CONTACT_TIED_SURFACE_TO_SURFACE', f10(2, 1, 3, 3), '', ''], [])
    blocks[-1] = ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.5)]
    rc, text, out = run_case('tied_implicit', blocks)
    checks.check(rc == 1 and 'implicit analysis does not take tied contacts' in text,
                 'implicit analysis refuses a tied contact when it starts', text[-400:])


patch(0.0, '*CONTACT_TIED_SURFACE_TO_SURFACE', '', ranks_list=(1, 2))
patch(0.01, '*CONTACT_TIED_SURFACE_TO_SURFACE_OFFSET', f10(1.0, 1.0, -0.05))
matching()
untied_warning()
implicit_refused()
checks.exit()
