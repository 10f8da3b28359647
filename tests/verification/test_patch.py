"""Patch tests of the linear elements (formulation 7.16), through whole runs of bin/mefem.

A distorted mesh of a square (2D, plane strain) or cube (3D) gets the displacement of a linear
field u = A x + b on its boundary nodes; the interior mesh nodes and all enriched nodes are
free. A consistent element reproduces the linear field at every node and a constant stress
in every element to round-off, also at nu = 0.4999 (no locking can spoil an exact solution).
Tolerances: 1e-9 relative to the field's size (MUMPS in double precision on meshes of a few
hundred unknowns with condition numbers up to ~1e5 at nu = 0.4999).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import (ROOT, Checks, elements_card, f10, free, linear_static_controls,
                         material_part, nodes_card, read_state, run, unit_curve, write_deck)

OUT = os.path.join(ROOT, 'tests', 'out', 'patch')
A2 = np.array([[1.0e-3, 2.0e-3], [-1.5e-3, 0.5e-3]])
A3 = np.array([[1.0e-3, 2.0e-3, -0.5e-3], [-1.5e-3, 0.5e-3, 1.0e-3], [0.7e-3, -0.2e-3, 1.2e-3]])
B = np.array([1.0e-3, -2.0e-3, 0.5e-3])
rng = np.random.default_rng(7)


def square_mesh(n):
    """Triangles of an n x n square, interior nodes moved randomly by up to 25 % of h."""
    h = 1.0 / n
    g = np.linspace(0.0, 1.0, n + 1)
    x = np.array([[a, b] for b in g for a in g])
    interior = (x[:, 0] > 0) & (x[:, 0] < 1) & (x[:, 1] > 0) & (x[:, 1] < 1)
    x[interior] += rng.uniform(-0.25 * h, 0.25 * h, size=(interior.sum(), 2))
    conn = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            if (i + j) % 2 == 0:
                conn += [[a, b, c], [a, c, d]]
            else:
                conn += [[a, b, d], [b, c, d]]
    return x, np.array(conn), ~interior


def cube_mesh(n):
    """Tets of an n^3 cube (6 per cell), interior nodes moved by up to 20 % of h."""
    h = 1.0 / n
    g = np.linspace(0.0, 1.0, n + 1)
    x = np.array([[a, b, c] for c in g for b in g for a in g])
    inside = np.all((x > 0) & (x < 1), axis=1)
    x[inside] += rng.uniform(-0.2 * h, 0.2 * h, size=(inside.sum(), 3))
    idx = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i
    conn = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                v = [idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k), idx(i, j + 1, k),
                     idx(i, j, k + 1), idx(i + 1, j, k + 1), idx(i + 1, j + 1, k + 1),
                     idx(i, j + 1, k + 1)]
                for t in ([0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6],
                          [0, 4, 5, 6], [0, 5, 1, 6]):
                    conn.append([v[q] for q in t])
    conn = np.array(conn)
    # orient every tet positively
    for e, c in enumerate(conn):
        d = np.linalg.det(np.array([x[c[1]] - x[c[0]], x[c[2]] - x[c[0]], x[c[3]] - x[c[0]]]))
        if d < 0:
            conn[e, [1, 2]] = conn[e, [2, 1]]
    return x, conn, ~inside


def patch(dim, elform, poisson, checks):
    if dim == 2:
        x, conn, boundary = square_mesh(6)
        amat, keyword = A2, 'ELEMENT_SHELL'
    else:
        x, conn, boundary = cube_mesh(3)
        amat, keyword = A3, 'ELEMENT_SOLID'
    exact = x @ amat.T + B[:dim]
    motions = ['*BOUNDARY_PRESCRIBED_MOTION_NODE']
    for n in np.nonzero(boundary)[0]:
        for d in range(dim):
            motions.append(free(int(n + 1), d + 1, 2, 1, float(exact[n, d])))
    name = 'patch%dd_elform%d_nu%g' % (dim, elform, poisson)
    deck = os.path.join(OUT, name + '.k')
    write_deck(deck, [nodes_card(x), elements_card(keyword, conn),
                      material_part(elform, 1000.0, poisson, dim), linear_static_controls(),
                      unit_curve(), motions])
    rc, text = run(deck, os.path.join(OUT, name))
    checks.check(rc == 0, name + ': run succeeds', text[-400:])
    if rc != 0:
        return
    s = read_state(os.path.join(OUT, name, name + '.h5'))
    order = s['node_ids'] - 1
    u = s['displacement'][:, :dim]
    scale = np.abs(exact).max()
    err = np.abs(u - exact[order]).max() / scale
    checks.check(err < 1e-9, name + ': linear field reproduced at every node',
                 'max relative error %.3e' % err)
    eps = 0.5 * (amat + amat.T)
    young = 1000.0
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    sig = lam * np.trace(eps) * np.eye(3)
    sig[:dim, :dim] += 2 * mu * eps
    want = np.array([sig[0, 0], sig[1, 1], sig[2, 2], sig[0, 1], sig[1, 2], sig[2, 0]])
    serr = np.abs(s['stress'] - want).max() / np.abs(want).max()
    checks.check(serr < 1e-7, name + ': constant stress in every element',
                 'max relative error %.3e' % serr)


def traction_patch(dim, elform, poisson, checks):
    """Constant-stress traction patch: rollers on the x=0, y=0 (, z=0) faces, a uniform
    tension T on x = 1 applied as a negative pressure through *LOAD_SEGMENT. Exact: sigma_xx = T
    everywhere (plane strain: sigma_zz = nu T), a linear displacement field."""
    young, tension = 1000.0, 2.0
    if dim == 2:
        x, conn, _ = square_mesh(6)
        keyword = 'ELEMENT_SHELL'
        right = np.nonzero(np.isclose(x[:, 0], 1.0))[0]
        right = right[np.argsort(x[right, 1])]          # bottom to top: body on the left
        segments = [[a, b] for a, b in zip(right[:-1], right[1:])]
        exx = tension * (1 - poisson ** 2) / young
        eyy = -tension * poisson * (1 + poisson) / young
        strain = np.diag([exx, eyy])
        want = np.array([tension, 0.0, poisson * tension, 0.0, 0.0, 0.0])
    else:
        x, conn, _ = cube_mesh(3)
        keyword = 'ELEMENT_SOLID'
        segments = []
        for c in conn:
            for face in ([1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]):
                f = c[face]
                if np.allclose(x[f, 0], 1.0):
                    n = np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])
                    segments.append(list(f) if n[0] > 0 else [f[0], f[2], f[1]])
        strain = np.diag([1.0, -poisson, -poisson]) * tension / young
        want = np.array([tension, 0.0, 0.0, 0.0, 0.0, 0.0])
    spc = ['*BOUNDARY_SPC_NODE']
    for n in range(len(x)):
        fixed = [1 if np.isclose(x[n, d], 0.0) else 0 for d in range(dim)] + [0] * (3 - dim)
        if any(fixed):
            spc.append(f10(int(n + 1), 0, *fixed))
    loads = ['*LOAD_SEGMENT'] + [free(1, -tension, 0.0, *[int(v) + 1 for v in seg])
                                 for seg in segments]
    name = 'traction%dd_elform%d_nu%g' % (dim, elform, poisson)
    deck = os.path.join(OUT, name + '.k')
    write_deck(deck, [nodes_card(x), elements_card(keyword, conn),
                      material_part(elform, young, poisson, dim), linear_static_controls(),
                      unit_curve(), spc, loads])
    rc, text = run(deck, os.path.join(OUT, name))
    checks.check(rc == 0, name + ': run succeeds', text[-400:])
    if rc != 0:
        return
    s = read_state(os.path.join(OUT, name, name + '.h5'))
    exact = x @ strain.T
    u = s['displacement'][:, :dim]
    err = np.abs(u - exact[s['node_ids'] - 1]).max() / np.abs(exact).max()
    # the same round-off budget as the displacement patch test
    checks.check(err < 1e-9, name + ': linear displacement field exact',
                 'max relative error %.3e' % err)
    serr = np.abs(s['stress'] - want).max() / tension
    checks.check(serr < 1e-7, name + ': uniform stress sigma_xx = T in every element',
                 'max relative error %.3e' % serr)


if __name__ == '__main__':
    checks = Checks('patch')
    for dim in (2, 3):
        for elform in ((43, 13) if dim == 2 else (43, 10)):
            for nu in (0.3, 0.4999):
                patch(dim, elform, nu, checks)
            traction_patch(dim, elform, 0.3, checks)
            traction_patch(dim, elform, 0.4999, checks)
    checks.exit()
