"""Single-surface mortar contact, *CONTACT_AUTOMATIC_SINGLE_SURFACE (issue 23): one surface
against itself, computed as two half passes (each facet once the slave, half the penalty).

1. Patch test: two blocks with non-matching meshes (3x3x3 and 4x4x3 cubes of 6 ME-FEM tets)
   pressed together by a uniform pressure, the contact given as one single surface of all
   parts (SURFATYP 5): every element stress and every contact pressure equals the applied
   pressure (as the surface-to-surface patch test, test_contact_patch.py).
2. Bar impact: the two bars of test_contact_impact.py in one part, the contact its single
   surface: contact for 2L/c0 with the force rho c0 A v0 / 2, then the bars exchange their
   velocities; momentum to round-off, energy within 1 %.
3. Thin plate (one tet thick, thinner than the search margin, so the facets of its two faces
   are candidates of each other and face each other): moving as a rigid body it must stay
   undeformed (the other side of a thin body is no partner: PENMAX).
4. Hairpin: a U-shaped one-point-hexahedron body whose upper arm is thrown onto the lower arm:
   the arms do not pass through each other (and do without the contact), total energy kept;
   1 and 2 ranks (the contact divided among the ranks) give the same bits;
   *CONTACT_AUTOMATIC_GENERAL is read as this contact (the same bits, with a warning).
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
from explicit_cases import DENSITY, YOUNG, box_tets, box_hexes, node_set, curve, run_case
from lsdyna_ascii import read_glstat, read_rcforc

os.environ['MEFEM_CONTACT_DIVIDE_MIN'] = '0'     # divide even small interfaces among ranks
checks = Checks('contact_single_surface')


def single_surface(surfa, surfatyp, sfs=1.0, keyword='*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID'):
    return [keyword, f10(1), f10(surfa, 0, surfatyp), f10(0.0), f10(sfs, sfs)]


def last_state(out, name, fields):
    """The last state's point fields in node-id order."""
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        order = np.argsort(f['mesh/node_ids'][()])
        return [f['states/%s/point/%s' % (last, k)][()][order] for k in fields]


def patch():
    e, nu, rho, p, t_ramp = 1000.0, 0.3, 1.0e-9, 10.0, 1.0e-4
    x1, c1 = box_tets(1.0, 1.0, 1.0, 3, 3, 3)
    x2, c2 = box_tets(1.0, 1.0, 1.0, 4, 4, 3)
    x2 = x2 + [0.0, 0.0, 1.0]
    n1 = len(x1)
    x = np.vstack([x1, x2])
    c2 = c2 + n1
    seg = ['*SET_SEGMENT', f10(9)]
    for f in boundary_facets(c2):
        f = [int(v) for v in f]
        if not all(abs(x[v, 2] - 2.0) < 1e-9 for v in f):
            continue
        if np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[2] < 0:
            f = [f[0], f[2], f[1]]
        seg.append(f10(f[0] + 1, f[1] + 1, f[2] + 1, f[2] + 1))
    spc = []
    for k in range(3):
        dofs = [0, 0, 0]
        dofs[k] = 1
        spc += node_set(k + 1, np.nonzero(x[:, k] < 1e-9)[0])
        spc += ['*BOUNDARY_SPC_SET', f10(k + 1, 0, *dofs)]
    s = np.linspace(0.0, 1.0, 41)
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', c1, pid=1),
              elements_card('ELEMENT_SOLID', c2, pid=2, first_id=len(c1) + 1),
              ['*PART', 'lower', f10(1, 1, 1), '*PART', 'upper', f10(2, 1, 1),
               '*SECTION_SOLID', f10(1, 43), '*MAT_ELASTIC', free(1, rho, e, nu)], spc, seg,
              ['*LOAD_SEGMENT_SET', f10(9, 1, 1.0)],
              curve(1, [(t_ramp * v, p * (v - np.sin(2 * np.pi * v) / (2 * np.pi))) for v in s]
                    + [(1.0, p)]),
              single_surface(0, 5),
              ['*CONTROL_TERMINATION', f10(1.5 * t_ramp), '*DATABASE_BINARY_D3PLOT',
               f10(1.5 * t_ramp), '*DATABASE_RCFORC', f10(t_ramp / 20)]]
    name = 'single_surface_patch'
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, 'patch: run succeeds', text[-600:])
    if rc != 0:
        return
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        last = sorted(f['states'].keys())[-1]
        stress = f['states/%s/cell/stress' % last][()][:, 2]
        cp = f['states/%s/point/contact_pressure' % last][()][:, 0]
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]
    expected = p / (1 + nu * p / e) ** 2       # dead load on the reference area, free sides
    s_err = np.max(abs(-stress / expected - 1))
    # each side carries half the pressure as a slave (two half passes); the larger of the
    # interfaces' pressures is written per node
    p_err = np.max(abs(2 * cp[cp > 0] / expected - 1))
    total = r['slave']['normal'][-1]
    print('    patch: sigma %.5f .. %.5f (expected %.5f MPa, max error %.1e); half-pass contact '
          'pressures x 2: %.5f .. %.5f (%d nodes); normal force %.5f N; resultant x, y, z %.1e'
          % (-stress.max(), -stress.min(), expected, s_err, 2 * cp[cp > 0].min(),
             2 * cp[cp > 0].max(), (cp > 0).sum(), total,
             max(abs(r['slave'][c][-1]) for c in ('x', 'y', 'z'))))
    # surface to surface: 3e-4 (stress), 6e-5 (pressure)
    checks.check(s_err < 2e-3, 'patch: every element stress = applied pressure within 0.2 %',
                 '%.3e' % s_err)
    checks.check(p_err < 2e-3, 'patch: every half-pass contact pressure = half the applied '
                 'pressure within 0.2 %', '%.3e' % p_err)
    checks.check(abs(total / p - 1) < 2e-3, 'patch: normal force (both half passes) = p A '
                 'within 0.2 %', '%.5f' % total)


def impact():
    length, width, gap, v0, sfs = 40.0, 5.0, 0.01, 5000.0, 10.0
    c0 = np.sqrt(YOUNG / DENSITY)
    x1, c1 = box_tets(length, width, width, 16, 2, 2)
    x2, c2 = box_tets(length, width, width, 16, 3, 3)
    x2 = x2 + [length + gap, 0.0, 0.0]
    n1 = len(x1)
    x = np.vstack([x1, x2])
    end_time = gap / v0 + 2.5 * length / c0
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', np.vstack([c1, c2 + n1]), pid=1),
              ['*PART', 'both bars', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.0)],
              node_set(1, range(n1)), ['*INITIAL_VELOCITY', f10(1), f10(v0, 0.0, 0.0)],
              single_surface(1, 3, sfs),
              ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT', f10(end_time),
               '*DATABASE_GLSTAT', f10(end_time / 200), '*DATABASE_RCFORC', f10(end_time / 400)]]
    name = 'single_surface_impact'
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, 'impact: run succeeds', text[-600:])
    if rc != 0:
        return
    g = read_glstat(os.path.join(out, 'glstat'))
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    mass = 2 * DENSITY * length * width * width
    p0 = DENSITY * length * width * width * v0
    drift = np.max(abs(g['global x velocity'] * mass - p0)) / p0
    ratio = g['total energy / initial energy']
    plateau = DENSITY * c0 * width * width * v0 / 2
    pressing = r['normal'] > plateau / 2
    t_on = r['time'][pressing]
    duration = t_on[-1] - t_on[0] + (r['time'][1] - r['time'][0])
    force = np.median(r['normal'][pressing])
    vel, = last_state(out, name, ['velocity'])
    v1, v2 = vel[:n1, 0].mean(), vel[n1:, 0].mean()
    print('    impact: momentum drift %.1e; energy ratio %.5f .. %.5f; contact %.4e s (2L/c0 '
          '%+.1f %%); force %.4e N (rho c0 A v0/2 %+.1f %%); after: bar 1 %.1f, bar 2 %.1f mm/s '
          '(v0 %.0f)' % (drift, ratio.min(), ratio.max(), duration,
                         100 * (duration * c0 / (2 * length) - 1), force,
                         100 * (force / plateau - 1), v1, v2, v0))
    checks.check(drift < 1e-10, 'impact: momentum conserved (1e-10)', '%.3e' % drift)
    checks.check(np.all(abs(ratio - 1) < 0.01), 'impact: total energy within 1 %',
                 '%.5f .. %.5f' % (ratio.min(), ratio.max()))
    checks.check(abs(duration * c0 / (2 * length) - 1) < 0.05, 'impact: contact lasts 2L/c0 '
                 'within 5 %', '%.4e' % duration)
    checks.check(abs(force / plateau - 1) < 0.05, 'impact: contact force rho c0 A v0 / 2 '
                 'within 5 %', '%.4e' % force)
    checks.check(abs(v1) < 0.05 * v0 and abs(v2 / v0 - 1) < 0.05, 'impact: the bars exchange '
                 'their velocities (within 5 % of v0)', '%.1f, %.1f' % (v1, v2))


def thin_plate():
    v = np.array([1000.0, -500.0, 2000.0])
    x, c = box_tets(10.0, 10.0, 0.1, 10, 10, 1)
    end_time = 2.0e-5
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', c, pid=1),
              ['*PART', 'plate', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
              node_set(1, range(len(x))), ['*INITIAL_VELOCITY', f10(1), f10(*v)],
              single_surface(1, 3),
              ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT', f10(end_time),
               '*DATABASE_RCFORC', f10(end_time / 20)]]
    name = 'single_surface_thin_plate'
    rc, text, out = run_case(name, blocks)
    checks.check(rc == 0, 'thin plate: run succeeds', text[-600:])
    if rc != 0:
        return
    u, = last_state(out, name, ['displacement'])
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave']
    error = np.max(abs(u - v * end_time)) / (np.linalg.norm(v) * end_time)
    print('    thin plate (0.1 mm, facets about 0.7 mm): displacement - v t at most %.1e of '
          '|v| t; largest normal contact force %.1e N' % (error, np.max(abs(r['normal']))))
    checks.check(error < 1e-9, 'thin plate: moves as a rigid body (the faces of a thin body '
                 'are no contact partners)', '%.3e' % error)
    checks.check(np.all(r['normal'] == 0.0), 'thin plate: no contact force', '%.3e' % np.max(
        abs(r['normal'])))


def hairpin_mesh():
    """Hexahedra of a U: a lower arm z in [0, 1], an upper arm z in [1.5, 2.5], joined by
    the block x in [9, 10]; 10 mm long, 2 mm wide."""
    zs = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
    nx, ny = 20, 4
    g, conn = box_hexes(10.0, 2.0, 5.0, nx, ny, 5)
    g[:, 2] = np.array(zs)[np.rint(g[:, 2]).astype(int)]
    cells = [(i, j, k) for k in range(5) for j in range(ny) for i in range(nx)]
    keep = [m for m, (i, j, k) in enumerate(cells) if not (k == 2 and i < nx - 2)]
    conn = conn[keep]
    used = np.unique(conn)
    renumber = np.zeros(len(g), dtype=int)
    renumber[used] = np.arange(len(used))
    return g[used], renumber[conn]


def hairpin(contact, ranks=1, keyword='*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID'):
    v_arm, end_time = 3.0e4, 2.0e-4
    x, c = hairpin_mesh()
    arm = np.nonzero((x[:, 2] > 1.4) & (x[:, 0] < 8.9))[0]
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', c, pid=1),
              ['*PART', 'hairpin', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)],
              node_set(1, arm), ['*INITIAL_VELOCITY', f10(1), f10(0.0, 0.0, -v_arm)],
              single_surface(1, 3, keyword=keyword) if contact else [],
              ['*CONTROL_TERMINATION', f10(end_time), '*DATABASE_BINARY_D3PLOT',
               f10(end_time / 40), '*DATABASE_GLSTAT', f10(end_time / 200),
               '*DATABASE_RCFORC', f10(end_time / 200)]]
    name = 'single_surface_hairpin%s_np%d' % ('' if contact else '_free', ranks)
    if 'GENERAL' in keyword:
        name = 'single_surface_hairpin_general'
    rc, text, out = run_case(name, blocks, ranks=ranks)
    checks.check(rc == 0, '%s: run succeeds' % name, text[-600:])
    if rc != 0:
        return None
    # the gap between the arms: upper arm's lower face (z = 1.5) minus the lower arm's upper
    # face (z = 1), node above node, over all states
    lower = np.nonzero((abs(x[:, 2] - 1.0) < 1e-9) & (x[:, 0] < 8.9))[0]
    upper = np.array([np.nonzero(np.all(abs(x - x[n] - [0, 0, 0.5]) < 1e-9, axis=1))[0][0]
                      for n in lower])
    gaps = []
    with h5py.File(os.path.join(out, name + '.h5')) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        for s in sorted(f['states'].keys()):
            xs = x[:, 2] + f['states/%s/point/displacement' % s][()][order][:, 2]
            gaps.append(np.min(xs[upper] - xs[lower]))
    g = read_glstat(os.path.join(out, 'glstat'))
    r = read_rcforc(os.path.join(out, 'rcforc'))[1]['slave'] if contact else None
    return dict(text=text, gap=np.array(gaps), ratio=g['total energy / initial energy'], rcforc=r,
                state=last_state(out, name, ['displacement', 'velocity']))


def implicit_refused():
    """The nonlinear implicit analysis takes rigid tools only: it stops when it starts."""
    x, c = box_tets(1.0, 1.0, 1.0, 2, 2, 2)
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', c, pid=1),
              ['*PART', 'block', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 43),
               '*MAT_ELASTIC', free(1, DENSITY, YOUNG, 0.3)], single_surface(1, 3),
              ['*CONTROL_TERMINATION', f10(1.0), '*CONTROL_IMPLICIT_GENERAL', f10(1, 0.5)]]
    rc, text, out = run_case('single_surface_implicit', blocks)
    want = 'a single-surface contact is explicit only; see *CONTACT_AUTOMATIC_SINGLE_SURFACE at line'
    checks.check(rc == 1 and want in text, 'implicit analysis refuses a single-surface contact '
                 'when it starts', text[-400:])


implicit_refused()
patch()
impact()
thin_plate()
free_run = hairpin(False)
touch = hairpin(True)
touch2 = hairpin(True, ranks=2)
if free_run and touch:
    print('    hairpin: smallest gap between the arms %.4f mm with the contact, %.4f mm without '
          '(0.5 mm at rest); energy ratio %.5f .. %.5f; largest normal force %.1f N' % (
              touch['gap'].min(), free_run['gap'].min(), touch['ratio'].min(),
              touch['ratio'].max(), touch['rcforc']['normal'].max()))
    checks.check(free_run['gap'].min() < -0.1, 'hairpin without contact: the arms pass '
                 'through each other (the case needs the contact)', '%.4f' % free_run['gap'].min())
    checks.check(touch['rcforc']['normal'].max() > 0.0, 'hairpin: the arms touch',
                 '%.3e' % touch['rcforc']['normal'].max())
    checks.check(touch['gap'].min() > -0.02, 'hairpin: the arms do not pass through each other '
                 '(penetration below 0.02 mm = 4 % of the gap)', '%.4f' % touch['gap'].min())
    checks.check(np.all(abs(touch['ratio'] - 1) < 0.01), 'hairpin: total energy within 1 %',
                 '%.5f .. %.5f' % (touch['ratio'].min(), touch['ratio'].max()))
general = hairpin(True, keyword='*CONTACT_AUTOMATIC_GENERAL_ID')
if touch and general:
    same = all(np.array_equal(a, b) for a, b in zip(touch['state'], general['state']))
    checks.check(same and 'read as *CONTACT_AUTOMATIC_SINGLE_SURFACE' in general['text'],
                 'hairpin: *CONTACT_AUTOMATIC_GENERAL is the single surface (same bits, with a '
                 'warning)', general['text'][-400:])
if touch and touch2:
    same = all(np.array_equal(a, b) for a, b in zip(touch['state'], touch2['state']))
    checks.check(same, 'hairpin: 2 ranks (contact divided) give the bits of 1 rank',
                 '%.3e' % max(np.max(abs(a - b)) for a, b in zip(touch['state'],
                                                                    touch2['state'])))
checks.exit()
