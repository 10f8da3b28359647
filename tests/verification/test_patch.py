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


checks = Checks('patch')
for dim in (2, 3):
    for elform in ((43, 13) if dim == 2 else (43, 10)):
        for nu in (0.3, 0.4999):
            patch(dim, elform, nu, checks)
checks.exit()
