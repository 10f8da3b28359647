"""Meshes, decks and exact solutions of the linear verification benchmarks (formulation 7.2,
7.5, 7.7), shared by the tests in tests/verification/ and by post/convergence_study.py.

Each `*_case` function writes a deck, runs bin/mefem on it and returns what the checks need
(displacements by node, element stresses, the mesh). Meshes are structured and built here
with numpy; loads are consistent nodal forces computed here (*LOAD_NODE_POINT) or pressures
(*LOAD_SEGMENT, Lame cylinder), so the decks need nothing but the keyword reader.
"""
import os

import h5py
import numpy as np

from deck_writer import (ROOT, elements_card, f10, free, linear_static_controls, nodes_card,
                         read_state, run, unit_curve, write_deck)

OUT = os.path.join(ROOT, 'tests', 'out', 'verification')

# ---------------------------------------------------------------------------------------
# generic mesh helpers


def quad_grid_triangles(n_i, n_j, pattern='right'):
    """Triangles of an n_i x n_j grid of quads whose nodes are numbered i fastest (node
    (i, j) = j (n_i + 1) + i), counter-clockwise when the map to the physical domain keeps
    orientation. pattern 'right': every quad cut along the same diagonal (bottom-left to
    top-right); 'alternate': diagonals alternate in a checkerboard ("union jack")."""
    conn = []
    for j in range(n_j):
        for i in range(n_i):
            a = j * (n_i + 1) + i
            b, c, d = a + 1, a + n_i + 2, a + n_i + 1
            if pattern == 'right' or (i + j) % 2 == 0:
                conn += [[a, b, c], [a, c, d]]
            else:
                conn += [[a, b, d], [b, c, d]]
    return np.array(conn)


PRISM_ROTATION = [[0, 1, 2, 3, 4, 5], [1, 2, 0, 4, 5, 3], [2, 0, 1, 5, 3, 4],
                  [3, 5, 4, 0, 2, 1], [4, 3, 5, 1, 0, 2], [5, 4, 3, 2, 1, 0]]


def prism_tets(v):
    """Three tets of the prism v[0:3] (bottom) / v[3:6] (top), quad-face diagonals through
    the smallest global index of each face, so neighbouring prisms conform (Dompierre et
    al. 1999)."""
    r = [v[q] for q in PRISM_ROTATION[int(np.argmin(v))]]
    if min(r[1], r[5]) < min(r[2], r[4]):
        return [[r[0], r[1], r[2], r[5]], [r[0], r[1], r[5], r[4]], [r[0], r[4], r[5], r[3]]]
    return [[r[0], r[1], r[2], r[4]], [r[0], r[4], r[2], r[5]], [r[0], r[4], r[5], r[3]]]


def extrude_to_tets(x2, n_i, n_j, layers, thickness, split='hex6', pattern='right'):
    """Tets of the slab x2 (grid nodes, i fastest) x [0, thickness] with `layers` layers.
    split 'hex6': every hexahedron cut into 6 tets around its main diagonal; 'prism3': the
    triangles of quad_grid_triangles(pattern) extruded to prisms, each cut into 3 tets;
    'hex': the hexahedra themselves (8 nodes, LS-DYNA's order: bottom face counter-clockwise
    seen from +z, then the top face). The tets conform between neighbours and are oriented
    positively."""
    nz = layers + 1
    z = np.linspace(0.0, thickness, nz)
    n2 = len(x2)
    x = np.array([[p[0], p[1], zk] for zk in z for p in x2])
    idx = lambda i, j, k: k * n2 + j * (n_i + 1) + i
    conn = []
    if split == 'prism3':
        tris = quad_grid_triangles(n_i, n_j, pattern)
        for k in range(layers):
            for t in tris:
                conn += prism_tets([int(v) + k * n2 for v in t] +
                                   [int(v) + (k + 1) * n2 for v in t])
    for k in range(layers if split in ('hex6', 'hex') else 0):
        for j in range(n_j):
            for i in range(n_i):
                v = [idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k), idx(i, j + 1, k),
                     idx(i, j, k + 1), idx(i + 1, j, k + 1), idx(i + 1, j + 1, k + 1),
                     idx(i, j + 1, k + 1)]
                if split == 'hex':
                    conn.append(v)
                    continue
                for t in ([0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6],
                          [0, 4, 5, 6], [0, 5, 1, 6]):
                    conn.append([v[q] for q in t])
    conn = np.array(conn)
    if split == 'hex':
        return x, conn
    for e, c in enumerate(conn):
        if np.linalg.det(np.array([x[c[1]] - x[c[0]], x[c[2]] - x[c[0]],
                                   x[c[3]] - x[c[0]]])) < 0:
            conn[e, [1, 2]] = conn[e, [2, 1]]
    return x, conn


HEX_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


def boundary_facets(conn):
    """Facets (edges of triangles, faces of tets, quadrilateral faces of hexahedra, in
    cyclic order) that belong to one element only."""
    nv = conn.shape[1]
    count, faces = {}, {}
    for c in conn:
        local = HEX_FACES if nv == 8 else [np.delete(np.arange(nv), k) for k in range(nv)]
        for q in local:
            f = [int(c[a]) for a in q]
            key = tuple(sorted(f))
            count[key] = count.get(key, 0) + 1
            faces[key] = f
    return [faces[k] for k, m in count.items() if m == 1]


def facet_measure(x, f):
    """Length of an edge, area of a triangle or of a planar quadrilateral (cyclic order)."""
    if len(f) == 2:
        return np.linalg.norm(x[f[1]] - x[f[0]])
    if len(f) == 4:
        return 0.5 * np.linalg.norm(np.cross(x[f[2]] - x[f[0]], x[f[3]] - x[f[1]]))
    return 0.5 * np.linalg.norm(np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]]))


def uniform_traction_forces(x, facets, traction):
    """Consistent nodal forces of a uniform traction vector on linear facets and on
    parallelogram quadrilaterals: each facet gives measure/n_vertices of its resultant to each
    vertex (exact for linear and bilinear shape functions; the ME-FEM enrichment functions
    vanish on element boundaries)."""
    force = np.zeros((len(x), len(traction)))
    for f in facets:
        share = facet_measure(x, f) / len(f)
        for n in f:
            force[n] += share * np.asarray(traction)
    return force


def edge_traction_forces(x, edges, traction_at, order=4):
    """Consistent nodal forces of a varying traction t(x) on 2-node edges (Gauss-Legendre
    rule of `order` points per edge; the exact Kirsch traction is smooth on the outer edges)."""
    gp, gw = np.polynomial.legendre.leggauss(order)
    force = np.zeros((len(x), 2))
    for a, b in edges:
        length = np.linalg.norm(x[b] - x[a])
        for s, w in zip(gp, gw):
            na, nb = 0.5 * (1 - s), 0.5 * (1 + s)
            t = traction_at(na * x[a] + nb * x[b])
            force[a] += 0.5 * w * length * na * t
            force[b] += 0.5 * w * length * nb * t
    return force


def edge_neighbours(conn):
    """Pairs of elements sharing an edge (2D) or a face (3D)."""
    nv = conn.shape[1]
    owner = {}
    pairs = []
    for e, c in enumerate(conn):
        for k in range(nv):
            f = tuple(sorted(np.delete(c, k)))
            if f in owner:
                pairs.append((owner[f], e))
            else:
                owner[f] = e
    return np.array(pairs)


# ---------------------------------------------------------------------------------------
# deck blocks


def elastic_part(elform, young, poisson, dim):
    """*PART 1 / section 1 / *MAT_ELASTIC 1 with full-precision E and nu (free format)."""
    lines = ['*PART', 'body', f10(1, 1, 1)]
    if dim == 2:
        lines += ['*SECTION_SHELL', f10(1, elform), f10(1.0)]
    else:
        lines += ['*SECTION_SOLID', f10(1, elform)]
    return lines + ['*MAT_ELASTIC', free(1, 1.0e-9, young, poisson)]


def spc_block(dofs):
    """*BOUNDARY_SPC_NODE from {node index (0-based): (fix x, fix y, fix z)}."""
    lines = ['*BOUNDARY_SPC_NODE']
    for n, d in sorted(dofs.items()):
        lines.append(free(int(n) + 1, 0, int(d[0]), int(d[1]), int(d[2]), 0, 0, 0))
    return lines


def nodal_force_block(force):
    """*LOAD_NODE_POINT cards (curve 1) for every non-zero component of force (nnode, dim)."""
    lines = ['*LOAD_NODE_POINT']
    for n in range(force.shape[0]):
        for d in range(force.shape[1]):
            if force[n, d] != 0.0:
                lines.append(free(n + 1, d + 1, 1, float(force[n, d])))
    return lines


def solve(name, outdir, blocks, ranks=1):
    """Write the deck, run it, return (state dict with rows in deck node order, text)."""
    deck = os.path.join(outdir, name + '.k')
    write_deck(deck, blocks, title=name)
    rc, text = run(deck, os.path.join(outdir, name), ranks=ranks)
    if rc != 0:
        return None, text
    h5path = os.path.join(outdir, name, name + '.h5')
    s = read_state(h5path)
    node_order = np.argsort(s['node_ids'])       # rows by user id = deck order
    cell_order = np.argsort(s['cell_ids'])
    s['displacement'] = s['displacement'][node_order]
    for key in ('stress', 'pressure', 'von_mises'):
        s[key] = s[key][cell_order]
    # connectivity of the results as 0-based deck node indices, cells in deck order
    with h5py.File(h5path, 'r') as f:
        offsets = f['mesh/cell_offsets'][()]
        rows = f['mesh/connectivity'][()]
    ids = s['node_ids']
    s['connectivity'] = np.array([ids[rows[offsets[c]:offsets[c + 1]]] - 1
                                  for c in cell_order])
    return s, text


def lame_from_young(young, poisson):
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    return lam, young / (2 * (1 + poisson))


# ---------------------------------------------------------------------------------------
# 7.2 Cook's membrane, plane strain, nearly incompressible

COOK_SHEAR = 0.375
COOK_LAMBDA = 7500.0
COOK_YOUNG = COOK_SHEAR * (3 * COOK_LAMBDA + 2 * COOK_SHEAR) / (COOK_LAMBDA + COOK_SHEAR)
COOK_POISSON = COOK_LAMBDA / (2 * (COOK_LAMBDA + COOK_SHEAR))
COOK_REFERENCE = 16.4326        # v at (48, 52), FinEALE cookstrain (formulation 7.2)


def cook_grid(n):
    """Nodes of the n x n mapped grid of the trapezoid (0,0),(48,44),(48,60),(0,44)."""
    xi = np.linspace(0.0, 1.0, n + 1)
    x = []
    for eta in xi:
        for s in xi:
            bottom, top = 44.0 * s, 44.0 + 16.0 * s
            x.append([48.0 * s, bottom + eta * (top - bottom)])
    return np.array(x)


def cook_case(n, elform, dim=2, layers=1, pattern='right', split='hex6', thickness=1.0,
              poisson=None, support=None, ranks=1, outdir=OUT, tag='', hourglass=None):
    """Cook's membrane on an n x n grid (n even: node at (48, 52)); 2D triangles or an
    extruded slab (`thickness`, `layers` layers) of tets with u_z = 0 on both faces; the
    load is the traction 1/16 per unit area (total force 1 per unit thickness). Material of
    the reference (G = 0.375, lambda = 7500) unless `poisson` is given (then G = 0.375 and
    that nu). `support`: a/L of the ME-FEM enrichment (*MEFEM_ENRICHMENT; default of the code
    when None). split 'hex': the hexahedra themselves (ELFORM 1 or 2); `hourglass` = (IHQ, QM)
    writes *CONTROL_HOURGLASS. Returns (v at (48, 52), state, text)."""
    young = COOK_YOUNG if poisson is None else 2 * COOK_SHEAR * (1 + poisson)
    poisson = COOK_POISSON if poisson is None else poisson
    x2 = cook_grid(n)
    if dim == 2:
        x, conn = x2, quad_grid_triangles(n, n, pattern)
        keyword = 'ELEMENT_SHELL'
    else:
        x, conn = extrude_to_tets(x2, n, n, layers, thickness, split, pattern)
        keyword = 'ELEMENT_SOLID'
    dofs = {}
    for i in np.nonzero(np.abs(x[:, 0]) < 1e-9)[0]:
        dofs[i] = (1, 1, 1)
    if dim == 3:
        for i in np.nonzero((np.abs(x[:, 2]) < 1e-9) |
                            (np.abs(x[:, 2] - thickness) < 1e-9))[0]:
            dofs.setdefault(i, (0, 0, 1))
    right = [f for f in boundary_facets(conn) if np.all(np.abs(x[f, 0] - 48.0) < 1e-9)]
    traction = np.zeros(dim)
    traction[1] = 1.0 / 16.0        # total force 1 per unit thickness
    force = uniform_traction_forces(x, right, traction)
    probe = np.nonzero(np.linalg.norm(x[:, :2] - [48.0, 52.0], axis=1) < 1e-9)[0]
    name = 'cook%dd_n%d_elform%d_%s%s_nu%.6g%s' % (
        dim, n, elform, pattern, '' if dim == 2 else '_%s_l%d_t%g' % (split, layers, thickness),
        poisson, tag)
    blocks = [nodes_card(x), elements_card(keyword, conn),
              elastic_part(elform, young, poisson, dim), linear_static_controls(),
              unit_curve(), spc_block(dofs), nodal_force_block(force)]
    if hourglass is not None:
        blocks.append(['*CONTROL_HOURGLASS', free(int(hourglass[0]), float(hourglass[1]))])
        name += '_ihq%d_qm%g' % hourglass
    if support is not None:
        blocks.append(['*MEFEM_ENRICHMENT', free(float(support), 1)])
        name += '_support%g' % support
    s, text = solve(name, outdir, blocks, ranks)
    if s is None:
        return None, None, text
    v = s['displacement'][probe, 1].mean()        # one node in 2D, one per z level in 3D
    s['conn'] = conn
    s['x_deck'] = x
    s['probe'] = probe
    return v, s, text


# ---------------------------------------------------------------------------------------
# 7.5 Thick-walled cylinder (Lame), plane strain

LAME_A, LAME_B, LAME_P = 3.0, 9.0, 1.0
LAME_YOUNG, LAME_POISSON = 1000.0, 0.4999


def lame_exact(r, poisson=LAME_POISSON):
    """Exact u_r, sigma_r, sigma_t, sigma_z and pressure -(s_r + s_t + s_z)/3 at radius r."""
    a, b, p, young = LAME_A, LAME_B, LAME_P, LAME_YOUNG
    c = p * a * a / (b * b - a * a)
    sr = c * (1 - b * b / r ** 2)
    st = c * (1 + b * b / r ** 2)
    sz = poisson * (sr + st)
    ur = c * (1 + poisson) * (b * b + r ** 2 * (1 - 2 * poisson)) / (young * r)
    return ur, sr, st, sz, -(sr + st + sz) / 3.0


def lame_case(n_r, n_t, elform, poisson=LAME_POISSON, pattern='alternate', outdir=OUT):
    """Quarter ring a <= r <= b, 0 <= theta <= 90 deg, n_r x n_t quads (uniform in r and
    theta) split into triangles; rollers on x = 0 and y = 0; pressure on the inner arc by
    *LOAD_SEGMENT. Returns (state, x, conn, node indices on the inner arc, text)."""
    r = np.linspace(LAME_A, LAME_B, n_r + 1)
    t = np.linspace(0.0, 0.5 * np.pi, n_t + 1)
    # grid node (i, j) = j (n_r + 1) + i: i along r, j along theta -> counter-clockwise
    x = np.array([[ri * np.cos(tj), ri * np.sin(tj)] for tj in t for ri in r])
    x[np.abs(x) < 1e-12] = 0.0
    conn = quad_grid_triangles(n_r, n_t, pattern)
    inner = [j * (n_r + 1) for j in range(n_t + 1)]           # theta increasing
    dofs = {}
    for i in range(len(x)):
        fx, fy = abs(x[i, 0]) < 1e-9, abs(x[i, 1]) < 1e-9
        if fx or fy:
            dofs[i] = (int(fx), int(fy), 0)
    # body on the left of N1 -> N2: along the inner arc with theta decreasing
    seg = ['*LOAD_SEGMENT']
    for j in range(n_t):
        n1, n2 = inner[j + 1] + 1, inner[j] + 1
        seg.append(free(1, LAME_P, 0.0, n1, n2))          # 2D line segment N1 N2
    name = 'lame_%dx%d_elform%d_nu%g' % (n_r, n_t, elform, poisson)
    blocks = [nodes_card(x), elements_card('ELEMENT_SHELL', conn),
              elastic_part(elform, LAME_YOUNG, poisson, 2), linear_static_controls(),
              unit_curve(), spc_block(dofs), seg]
    s, text = solve(name, outdir, blocks)
    return s, x, conn, inner, text


def lame_measures(s, x, conn, inner, poisson=LAME_POISSON):
    """Radial displacement at r = a (mean over the inner nodes) and its relative error; max
    relative error of u_r over all nodes; pressure RMS error / p; mean |jump| of pressure
    between elements sharing an edge / p (neighbours from the connectivity of the results)."""
    conn = s['connectivity']
    u = s['displacement'][:, :2]
    r = np.linalg.norm(x, axis=1)
    ur = np.sum(u * x, axis=1) / r
    ur_exact = lame_exact(r, poisson)[0]
    ua = ur[inner].mean()
    p_exact = lame_exact(LAME_A, poisson)[4]
    pressure = s['pressure'][:, 0]
    pairs = edge_neighbours(conn)
    return {
        'ur_a': ua,
        'ur_a_error': abs(ua / ur_exact[inner[0]] - 1),
        'ur_max_error': np.max(np.abs(ur - ur_exact)) / ur_exact.max(),
        'pressure_exact': p_exact,
        'pressure_rms': np.sqrt(np.mean((pressure - p_exact) ** 2)) / LAME_P,
        'pressure_jump': np.mean(np.abs(pressure[pairs[:, 0]] - pressure[pairs[:, 1]])) / LAME_P,
        'pressure': pressure,
        'centroid_r': np.linalg.norm(x[conn].mean(axis=1), axis=1),
    }


# ---------------------------------------------------------------------------------------
# 7.7 Plate with a circular hole (Kirsch), plane strain

KIRSCH_A, KIRSCH_W, KIRSCH_T = 1.0, 10.0, 1.0
KIRSCH_YOUNG = 1000.0


def kirsch_stress(p):
    """Exact Kirsch stress (sxx, syy, sxy) at point p of the infinite plate."""
    r = np.hypot(p[0], p[1])
    th = np.arctan2(p[1], p[0])
    q = (KIRSCH_A / r) ** 2
    t = KIRSCH_T
    srr = t / 2 * (1 - q) + t / 2 * (1 - 4 * q + 3 * q * q) * np.cos(2 * th)
    stt = t / 2 * (1 + q) - t / 2 * (1 + 3 * q * q) * np.cos(2 * th)
    srt = -t / 2 * (1 + 2 * q - 3 * q * q) * np.sin(2 * th)
    c, s = np.cos(th), np.sin(th)
    sxx = srr * c * c + stt * s * s - 2 * srt * s * c
    syy = srr * s * s + stt * c * c + 2 * srt * s * c
    sxy = (srr - stt) * s * c + srt * (c * c - s * s)
    return np.array([sxx, syy, sxy])


def kirsch_mesh(n_t, n_r, grading):
    """Quarter plate [0, W]^2 minus the disc r < a: two mapped blocks (theta in [0, 45] deg to
    the right edge, [45, 90] deg to the top edge), n_t quads along each block's arc and n_r
    along the rays, geometric ray spacing (ratio of the last to the first cell `grading`).
    Returns nodes, triangles and the index of the node at (0, a)."""
    w, a = KIRSCH_W, KIRSCH_A
    if grading == 1.0:
        s = np.linspace(0.0, 1.0, n_r + 1)
    else:
        q = grading ** (1.0 / (n_r - 1))
        s = np.concatenate([[0.0], np.cumsum(q ** np.arange(n_r))])
        s /= s[-1]
    n_arc = 2 * n_t
    theta = np.linspace(0.0, 0.5 * np.pi, n_arc + 1)
    x = []
    for tj in theta:                      # node (i, j) = j (n_r + 1) + i, i along the ray
        hole = a * np.array([np.cos(tj), np.sin(tj)])
        if tj <= 0.25 * np.pi + 1e-12:
            outer = np.array([w, w * np.tan(tj)])
        else:
            outer = np.array([w / np.tan(tj) if tj < 0.5 * np.pi - 1e-12 else 0.0, w])
        for si in s:
            x.append(hole + si * (outer - hole))
    x = np.array(x)
    x[np.abs(x) < 1e-12] = 0.0
    conn = quad_grid_triangles(n_r, n_arc, 'alternate')
    top_of_hole = n_arc * (n_r + 1)
    return x, conn, top_of_hole


def kirsch_case(n_t, n_r, elform, poisson=0.3, grading=8.0, outdir=OUT):
    """Kirsch plate: rollers on x = 0 and y = 0, the exact traction of the infinite plate on
    the outer edges x = W and y = W (so the discrete problem approximates the exact field).
    Returns (state, x, conn, index of the node (0, a), text)."""
    x, conn, top = kirsch_mesh(n_t, n_r, grading)
    w = KIRSCH_W
    outer = [f for f in boundary_facets(conn)
             if np.all(np.abs(x[f, 0] - w) < 1e-9) or np.all(np.abs(x[f, 1] - w) < 1e-9)]

    def traction(p):      # at Gauss points, which are never the corner (W, W)
        sxx, syy, sxy = kirsch_stress(p)
        if abs(p[0] - w) < 1e-9:
            return np.array([sxx, sxy])              # right edge, normal +x
        return np.array([sxy, syy])                  # top edge, normal +y

    force = edge_traction_forces(x, outer, traction)
    dofs = {}
    for i in range(len(x)):
        fx, fy = abs(x[i, 0]) < 1e-9, abs(x[i, 1]) < 1e-9
        if fx or fy:
            dofs[i] = (int(fx), int(fy), 0)
    name = 'kirsch_%dx%d_elform%d_nu%g' % (n_t, n_r, elform, poisson)
    blocks = [nodes_card(x), elements_card('ELEMENT_SHELL', conn),
              elastic_part(elform, KIRSCH_YOUNG, poisson, 2), linear_static_controls(),
              unit_curve(), spc_block(dofs), nodal_force_block(force)]
    s, text = solve(name, outdir, blocks)
    return s, x, conn, top, text


def kirsch_measures(s, x, conn, top):
    """Stress concentration estimates at (0, a): the element average of sxx in the element
    with a vertex at (0, a) whose centroid is nearest to it, the area-weighted mean of the
    elements around that node, and the exact sxx at that element's centroid (what a perfect
    element average would be near it). Also the relative L2 error of the element stresses
    against the exact field at the centroids (area weighted)."""
    sxx = s['stress'][:, 0]
    centroids = x[conn].mean(axis=1)
    d1 = x[conn[:, 1]] - x[conn[:, 0]]
    d2 = x[conn[:, 2]] - x[conn[:, 0]]
    area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    around = np.nonzero(np.any(conn == top, axis=1))[0]
    nearest = around[np.argmin(np.linalg.norm(centroids[around] - x[top], axis=1))]
    exact = np.array([kirsch_stress(c) for c in centroids])
    # linear least-squares fit of sxx over the two rings of elements around (0, a) (those
    # with a vertex at (0, a) and their edge neighbours), evaluated at (0, a)
    pairs = edge_neighbours(conn)
    ring = set(around.tolist())
    for e1, e2 in pairs:
        if e1 in around or e2 in around:
            ring.update((int(e1), int(e2)))
    ring = np.array(sorted(ring))
    design = np.column_stack([np.ones(len(ring)), centroids[ring] - x[top]])
    coef = np.linalg.lstsq(design, sxx[ring], rcond=None)[0]
    stress2d = s['stress'][:, [0, 1, 3]]
    l2 = np.sqrt(np.sum(area[:, None] * (stress2d - exact) ** 2) /
                 np.sum(area[:, None] * exact ** 2))
    return {
        'scf_element': sxx[nearest] / KIRSCH_T,
        'scf_element_exact': exact[nearest, 0] / KIRSCH_T,
        'scf_node': np.sum(area[around] * sxx[around]) / np.sum(area[around]) / KIRSCH_T,
        'scf_fit': coef[0] / KIRSCH_T,
        'stress_l2': l2,
        'nelem': len(conn),
    }
