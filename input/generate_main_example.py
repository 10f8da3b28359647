#!/usr/bin/python3
"""Write input/main_example.k: upsetting of an aluminium billet between two rigid plates.

The billet is a cylinder (diameter 20 mm, height 30 mm); by symmetry a quarter of it is
modelled (x >= 0, y >= 0) with roller conditions on the planes x = 0 and y = 0. Its cross
section is a structured O-grid (a square core plus a curved outer block), extruded along z;
every hexahedral cell is split into 5 tetrahedra, alternating with the node colouring so that
the diagonals of shared faces match, and every tet is oriented positively. The plates are rigid
quadrilateral shells; the bottom plate is fixed, the top plate moves down at 5 m/s (smooth ramp
up and down) and compresses the billet to half its height (30 -> 15 mm) in 3.3 ms.

Units: mm, s, tonne, N, MPa (so density is in tonne/mm^3 and energy in mJ = N mm).

usage: /usr/bin/python3 input/generate_main_example.py [--output input/main_example.k]
       [--core N] [--radial M] [--layers K]
Defaults give 12 600 tets; the mesh is checked (positive volumes, conforming faces, volume)
before the deck is written.
"""
import argparse
import collections
import math
import sys

import numpy as np

# ---- problem data (mm, s, tonne, N, MPa) ---------------------------------------------------
RADIUS = 10.0             # billet radius
HEIGHT = 30.0             # billet height
CORE = 0.5                # half-side of the square core / radius
REDUCTION = 0.5           # height reduction at the end of the stroke
SPEED = 5000.0            # top plate speed (mm/s = 5 m/s)
RAMP = 0.3e-3             # velocity ramp up and down (s)
PLATE_T = 0.2             # rigid plate shell thickness (their mass; no contact offset)
PLATE_EXTENT = (-1.0, 25.0)   # plate span in x and y (the billet grows to about r = 15 mm)
PLATE_CELLS = 13          # plate quads per side
FRICTION = 0.2            # Coulomb friction billet/plates (seed paper's frictional case)
TSSFAC = 0.9              # time step scale factor
DT2MS = 8.0e-8            # selective mass scaling: smallest step / TSSFAC (s)
ADDED_MASS_PERCENT = 11.0  # what mefem adds at the start with DT2MS (measured; an upper bound
                           # that tests/verification/test_examples.py checks)

# aluminium: RO, E, PR; yield curve sigma_y = 100 + 150 eps_p^0.4 MPa (Ludwik form)
AL_RO, AL_E, AL_PR = 2.7e-9, 70000.0, 0.3
AL_SIGY, AL_K, AL_N = 100.0, 150.0, 0.4
AL_EPS = [0.0, 0.02, 0.05, 0.1, 0.2, 0.4, 0.8, 2.0]
# tool steel for the rigid plates (mass and contact stiffness only)
ST_RO, ST_E, ST_PR = 7.85e-9, 210000.0, 0.3

# id ranges
BOTTOM_NODE0, TOP_NODE0 = 100001, 200001
BOTTOM_ELEM0, TOP_ELEM0 = 100001, 200001


def quarter_disk(n_core, n_radial):
    """Structured O-grid of the quarter disk: 2D node coordinates (n, 2) and quads (m, 4),
    counter-clockwise. Core: (n_core x n_core) square of half-side CORE*R; outer block:
    2*n_core cells along the arc, n_radial cells from the core's edge to the arc."""
    s = CORE * RADIUS
    n = n_core
    xy = [(s * i / n, s * j / n) for j in range(n + 1) for i in range(n + 1)]

    def core(i, j):
        return i + (n + 1) * j

    def core_edge(t):
        """Core node at position t (0..2n) along its outer edge, from (s, 0) to (0, s)."""
        return core(n, t) if t <= n else core(2 * n - t, n)

    base = len(xy)

    def outer(t, r):
        return core_edge(t) if r == 0 else base + t + (2 * n + 1) * (r - 1)

    for r in range(1, n_radial + 1):
        for t in range(2 * n + 1):
            px, py = xy[core_edge(t)]
            theta = 0.5 * math.pi * t / (2 * n)
            ax = 0.0 if t == 2 * n else RADIUS * math.cos(theta)
            ay = 0.0 if t == 0 else RADIUS * math.sin(theta)
            f = r / n_radial
            xy.append((px + f * (ax - px), py + f * (ay - py)))
    quads = [(core(i, j), core(i + 1, j), core(i + 1, j + 1), core(i, j + 1))
             for j in range(n) for i in range(n)]
    quads += [(outer(t, r), outer(t, r + 1), outer(t + 1, r + 1), outer(t + 1, r))
              for r in range(n_radial) for t in range(2 * n)]
    return np.array(xy), np.array(quads, dtype=np.int64)


def two_colours(n_nodes, quads):
    """Colour the nodes 0/1 so that the two ends of every quad edge differ (a quad mesh of a
    simply connected domain is bipartite)."""
    adjacent = collections.defaultdict(set)
    for q in quads:
        for k in range(4):
            a, b = q[k], q[(k + 1) % 4]
            adjacent[a].add(b)
            adjacent[b].add(a)
    colour = -np.ones(n_nodes, dtype=np.int64)
    colour[0] = 0
    queue = collections.deque([0])
    while queue:
        a = queue.popleft()
        for b in adjacent[a]:
            if colour[b] < 0:
                colour[b] = 1 - colour[a]
                queue.append(b)
            elif colour[b] == colour[a]:
                raise RuntimeError('quad mesh is not bipartite')
    return colour


def tet_det(x, tets):
    """det[N2-N1, N3-N1, N4-N1] (6 x volume) of each tet."""
    p = x[tets]
    return np.einsum('ij,ij->i', np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                     p[:, 3] - p[:, 0])


def billet_hex_cube_order(n_core, n_radial, n_layers):
    """Nodes (n, 3), hexahedra (m, 8) with corners in cube order a + 2b + 4c (0-based), and
    the two-colouring of the nodes, of the quarter billet."""
    xy, quads = quarter_disk(n_core, n_radial)
    n2 = len(xy)
    colour2 = two_colours(n2, quads)
    z = np.linspace(0.0, HEIGHT, n_layers + 1)
    x = np.column_stack([np.tile(xy, (n_layers + 1, 1)), np.repeat(z, n2)])
    colour = (np.tile(colour2, n_layers + 1) + np.repeat(np.arange(n_layers + 1), n2)) % 2
    # hex corners in cube order a + 2b + 4c: quad q0 q1 q3 q2 at level k, then at k + 1
    layer = np.arange(n_layers)[:, None, None] * n2
    bottom = quads[:, [0, 1, 3, 2]][None, :, :] + layer
    hexes = np.concatenate([bottom, bottom + n2], axis=2).reshape(-1, 8)
    return x, hexes, colour


def billet_hex_mesh(n_core, n_radial, n_layers):
    """Nodes (n, 3) and positively oriented hexahedra (m, 8) in LS-DYNA's node order (N1-N4
    the bottom face, counter-clockwise seen from N5) of the quarter billet."""
    x, hexes, _ = billet_hex_cube_order(n_core, n_radial, n_layers)
    hexes = hexes[:, [0, 1, 3, 2, 4, 5, 7, 6]]
    # orientation: (N2 - N1) x (N4 - N1) . (N5 - N1) > 0, else the faces are swapped
    d1 = x[hexes[:, 1]] - x[hexes[:, 0]]
    d2 = x[hexes[:, 3]] - x[hexes[:, 0]]
    d3 = x[hexes[:, 4]] - x[hexes[:, 0]]
    flip = np.einsum('ij,ij->i', np.cross(d1, d2), d3) < 0
    hexes[flip] = hexes[flip][:, [0, 3, 2, 1, 4, 7, 6, 5]]
    return x, hexes


def billet_mesh(n_core, n_radial, n_layers):
    """Nodes (n, 3) and positively oriented tets (m, 4) (0-based) of the quarter billet."""
    x, hexes, colour = billet_hex_cube_order(n_core, n_radial, n_layers)
    cube = np.array([[a, b, c] for c in (0, 1) for b in (0, 1) for a in (0, 1)])
    tets = []
    for h in hexes:
        even = [k for k in range(8) if colour[h[k]] == 0]
        tets.append([h[k] for k in even])                      # central tet
        for k in range(8):
            if colour[h[k]] == 1:                             # one corner tet per odd corner
                tets.append([h[k]] + [h[m] for m in even
                                      if np.abs(cube[m] - cube[k]).sum() == 1])
    tets = np.array(tets, dtype=np.int64)
    flip = tet_det(x, tets) < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return x, tets


def check_mesh(x, tets):
    """Positive volumes, conforming faces (no face in more than two tets), and the volume of
    the quarter cylinder up to the polygonal approximation of the arc."""
    det = tet_det(x, tets)
    assert det.min() > 0, 'inverted tet'
    faces = collections.Counter()
    for t in tets:
        for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            faces[tuple(sorted(t[list(f)]))] += 1
    assert max(faces.values()) == 2, 'non-conforming faces'
    volume = det.sum() / 6.0
    exact = 0.25 * math.pi * RADIUS ** 2 * HEIGHT
    assert abs(volume / exact - 1.0) < 0.02, (volume, exact)
    # characteristic length of a tet: smallest altitude = 3 V / largest face area
    p = x[tets]
    areas = np.stack([0.5 * np.linalg.norm(np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a]),
                                           axis=1)
                      for a, b, c in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))], axis=1)
    altitudes = 0.5 * det / areas.max(axis=1)
    return volume, exact, altitudes.min(), altitudes


def plate(z, node0, elem0, pid, normal_up):
    """Card lines of a square plate of quads at height z, normal +z (up) or -z."""
    lo, hi = PLATE_EXTENT
    c = np.linspace(lo, hi, PLATE_CELLS + 1)
    nodes = [(node0 + i + (PLATE_CELLS + 1) * j, c[i], c[j], z)
             for j in range(PLATE_CELLS + 1) for i in range(PLATE_CELLS + 1)]
    elems = []
    for j in range(PLATE_CELLS):
        for i in range(PLATE_CELLS):
            a = node0 + i + (PLATE_CELLS + 1) * j
            q = [a, a + 1, a + 1 + PLATE_CELLS + 1, a + PLATE_CELLS + 1]
            if not normal_up:
                q = [q[0], q[3], q[2], q[1]]
            elems.append((elem0 + len(elems), pid, *q))
    return nodes, elems


def f10(v):
    """A number in a 10-column field."""
    if isinstance(v, int):
        text = str(v)
    else:
        text = repr(float(v)) if float(v).is_integer() else '%.6g' % v
        if len(text) > 10:
            text = '%.3e' % v
    assert len(text) <= 10, text
    return text.rjust(10)


def card(*values):
    return ''.join(f10(v) for v in values)


def heading(*names):
    """A '$#' comment line naming 10-column fields."""
    text = ''.join(n.rjust(10) for n in names)
    return '$#' + text[2:]


def node_lines(records):
    return ['%8d%16.9e%16.9e%16.9e' % r for r in records]


def write_deck(path, n_core, n_radial, n_layers):
    x, tets = billet_mesh(n_core, n_radial, n_layers)
    volume, exact, min_altitude, altitudes = check_mesh(x, tets)
    n_nodes = len(x)
    wave_speed = math.sqrt(AL_E * (1 - AL_PR) / ((1 + AL_PR) * (1 - 2 * AL_PR) * AL_RO))
    dt_estimate = min_altitude / wave_speed
    small_fraction = float(np.mean(altitudes / wave_speed < DT2MS))
    stroke = REDUCTION * HEIGHT
    end_time = stroke / SPEED + RAMP
    eps_tol = 1e-9
    sym_x = [k + 1 for k in range(n_nodes) if abs(x[k, 0]) < eps_tol]
    sym_y = [k + 1 for k in range(n_nodes) if abs(x[k, 1]) < eps_tol]

    def node_at(px, py, pz):
        k = int(np.argmin(np.linalg.norm(x - np.array([px, py, pz]), axis=1)))
        assert np.linalg.norm(x[k] - [px, py, pz]) < 1e-6, (px, py, pz)
        return k + 1

    history = [node_at(0, 0, HEIGHT), node_at(0, 0, 0), node_at(0, 0, HEIGHT / 2),
               node_at(RADIUS, 0, HEIGHT / 2), node_at(0, RADIUS, HEIGHT / 2)]
    # the plates' mid-surfaces, mefem's contact surfaces, on the billet's end faces
    bottom_nodes, bottom_elems = plate(0.0, BOTTOM_NODE0, BOTTOM_ELEM0, 2, True)
    top_nodes, top_elems = plate(HEIGHT, TOP_NODE0, TOP_ELEM0, 3, False)
    es = [AL_SIGY + AL_K * e ** AL_N for e in AL_EPS]

    L = []
    L += ['*KEYWORD',
          '$ ==========================================================================',
          '$ mefem main example: upsetting of an aluminium billet between rigid plates',
          '$ ==========================================================================',
          '$ Written by input/generate_main_example.py (edit that script, not this file):',
          '$   /usr/bin/python3 input/generate_main_example.py --core %d --radial %d '
          '--layers %d' % (n_core, n_radial, n_layers),
          '$ Units: mm, s, tonne, N, MPa (density tonne/mm^3, energy mJ = N mm).',
          '$ Cylinder D = %g mm, H = %g mm; quarter model (x >= 0, y >= 0) with symmetry'
          % (2 * RADIUS, HEIGHT),
          '$ planes x = 0 and y = 0. The top plate moves down %g mm (%d %% height'
          % (stroke, round(100 * REDUCTION)),
          '$ reduction) at %g m/s; the bottom plate is fixed. Friction mu = %g.'
          % (SPEED / 1000, FRICTION),
          '$ Mesh: %d nodes, %d ME-FEM tets (structured O-grid, 5 tets per hexahedron),'
          % (n_nodes, len(tets)),
          '$ volume %.2f mm^3 (exact cylinder %.2f), smallest tet altitude %.3f mm,'
          % (volume, exact, min_altitude),
          '$ dilatational wave speed %.4g mm/s, so a stable step of about %.2e s.'
          % (wave_speed, dt_estimate),
          '*TITLE',
          'Upsetting of an aluminium billet (quarter model, ME-FEM tets, mortar contact)',
          '$',
          '$ ---- parts -----------------------------------------------------------------',
          '$ Part 1: the billet (ME-FEM tetrahedra, aluminium). Parts 2 and 3: the bottom',
          '$ and top plates (rigid shells, tool steel).',
          '*PART',
          'billet',
          heading('pid', 'secid', 'mid', 'eosid', 'hgid'),
          card(1, 1, 1, 0, 0),
          'bottom plate',
          heading('pid', 'secid', 'mid', 'eosid', 'hgid'),
          card(2, 2, 2, 0, 0),
          'top plate',
          heading('pid', 'secid', 'mid', 'eosid', 'hgid'),
          card(3, 2, 3, 0, 0),
          '$',
          '$ ELFORM 43: meshfree-enriched finite element (ME-FEM) tetrahedron.',
          '*SECTION_SOLID',
          heading('secid', 'elform', 'aet'),
          card(1, 43, 0),
          '$ Rigid plate shells: the formulation does not matter for a rigid body; the',
          '$ thickness %g mm gives the plates their mass. mefem\'s contact surfaces are the' % PLATE_T,
          '$ shells\' mid-surfaces (no thickness offset), so the plates lie on the billet\'s',
          '$ end faces: they touch it from the start.',
          '*SECTION_SHELL',
          heading('secid', 'elform', 'shrf', 'nip', 'propt', 'qr/irid', 'icomp', 'setyp'),
          card(2, 2, 1.0, 2, 1, 0, 0, 1),
          heading('t1', 't2', 't3', 't4', 'nloc'),
          card(PLATE_T, PLATE_T, PLATE_T, PLATE_T, 0),
          '$',
          '$ ---- materials -------------------------------------------------------------',
          '$ Aluminium, elastic-plastic with isotropic hardening (von Mises). Yield curve',
          '$ sigma_y = %g + %g eps_p^%g MPa given as 8 points (EPS effective plastic strain,'
          % (AL_SIGY, AL_K, AL_N),
          '$ ES yield stress); beyond the last point the last segment is extrapolated.',
          '*MAT_PIECEWISE_LINEAR_PLASTICITY',
          heading('mid', 'ro', 'e', 'pr', 'sigy', 'etan', 'fail', 'tdel'),
          card(1, AL_RO, AL_E, AL_PR, AL_SIGY, 0.0, 1.0e21, 0.0),
          heading('c', 'p', 'lcss', 'lcsr', 'vp'),
          card(0.0, 0.0, 0, 0, 0.0),
          heading(*('eps%d' % (i + 1) for i in range(8))),
          card(*AL_EPS),
          heading(*('es%d' % (i + 1) for i in range(8))),
          card(*[round(v, 2) for v in es]),
          '$ Bottom plate: rigid, all six rigid-body motions fixed (CMO = 1: global',
          '$ constraints; CON1 = 7: x, y, z translations; CON2 = 7: all rotations).',
          '*MAT_RIGID',
          heading('mid', 'ro', 'e', 'pr', 'n', 'couple', 'm', 'alias'),
          card(2, ST_RO, ST_E, ST_PR),
          heading('cmo', 'con1', 'con2'),
          card(1.0, 7, 7),
          heading('lco/a1', 'a2', 'a3', 'v1', 'v2', 'v3'),
          card(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
          '$ Top plate: rigid, x and y translations and all rotations fixed (CON1 = 4:',
          '$ x and y; CON2 = 7); its z motion is prescribed below.',
          '*MAT_RIGID',
          heading('mid', 'ro', 'e', 'pr', 'n', 'couple', 'm', 'alias'),
          card(3, ST_RO, ST_E, ST_PR),
          heading('cmo', 'con1', 'con2'),
          card(1.0, 4, 7),
          heading('lco/a1', 'a2', 'a3', 'v1', 'v2', 'v3'),
          card(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
          '$',
          '$ ---- symmetry: node sets on the planes x = 0 and y = 0 ----------------------',
          ]
    for sid, title, members in ((1, 'symmetry plane x = 0', sym_x),
                                (2, 'symmetry plane y = 0', sym_y)):
        L += ['*SET_NODE_LIST_TITLE', title,
              heading('sid', 'da1', 'da2', 'da3', 'da4', 'solver'),
              card(sid, 0.0, 0.0, 0.0, 0.0) + 'MECH'.rjust(10),
              heading(*('nid%d' % (i + 1) for i in range(8)))]
        L += [card(*members[i:i + 8]) for i in range(0, len(members), 8)]
    L += ['$ Roller conditions: no displacement normal to each symmetry plane.',
          '*BOUNDARY_SPC_SET',
          heading('nsid', 'cid', 'dofx', 'dofy', 'dofz', 'dofrx', 'dofry', 'dofrz'),
          card(1, 0, 1, 0, 0, 0, 0, 0),
          card(2, 0, 0, 1, 0, 0, 0, 0),
          '$',
          '$ ---- loading -----------------------------------------------------------------',
          '$ Top plate velocity (mm/s) versus time (s): ramps up to %g m/s in %g ms, holds,'
          % (SPEED / 1000, RAMP * 1e3),
          '$ and ramps down to rest at the end time; the area under it is the stroke,',
          '$ %g mm. Negative = downwards (-z).' % stroke,
          '*DEFINE_CURVE_TITLE',
          'top plate velocity',
          heading('lcid', 'sidr', 'sfa', 'sfo', 'offa', 'offo', 'dattyp'),
          card(1, 0, 1.0, 1.0, 0.0, 0.0, 0),
          '$#                a1                  o1']
    for t, v in ((0.0, 0.0), (RAMP, -SPEED), (end_time - RAMP, -SPEED), (end_time, 0.0),
                 (10 * end_time, 0.0)):
        L.append('%20.6e%20.6e' % (t, v))
    L += ['$ Prescribed motion of rigid part 3 (top plate): DOF 3 = z translation,',
          '$ VAD 0 = velocity given by curve 1.',
          '*BOUNDARY_PRESCRIBED_MOTION_RIGID',
          heading('pid', 'dof', 'vad', 'lcid', 'sf', 'vid', 'death', 'birth'),
          card(3, 3, 0, 1, 1.0, 0, 1.0e28, 0.0),
          '$',
          '$ ---- contact -----------------------------------------------------------------',
          '$ Mortar segment-to-segment contact of the billet (surface A, part 1) with each',
          '$ plate (surface B, parts 2 and 3); SURFATYP = SURFBTYP = 3: the surfaces are',
          '$ parts. Coulomb friction FS = FD = %g (static = dynamic).' % FRICTION]
    for cid, pid, name in ((1, 2, 'billet on bottom plate'), (2, 3, 'billet on top plate')):
        L += ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR_ID',
              heading('cid') + '  heading',
              f10(cid) + name,
              heading('surfa', 'surfb', 'surfatyp', 'surfbtyp', 'saboxid', 'sbboxid',
                      'sapr', 'sbpr'),
              card(1, pid, 3, 3, 0, 0, 0, 0),
              heading('fs', 'fd', 'dc', 'vc', 'vdc', 'penchk', 'bt', 'dt'),
              card(FRICTION, FRICTION, 0.0, 0.0, 0.0, 0, 0.0, 1.0e20),
              heading('sfsa', 'sfsb', 'sast', 'sbst', 'sfsat', 'sfsbt', 'fsf', 'vsf'),
              card(1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0)]
    L += ['$',
          '$ ---- analysis controls -------------------------------------------------------',
          '$ End time: stroke / speed + ramp = %g s.' % end_time,
          '*CONTROL_TERMINATION',
          heading('endtim', 'endcyc', 'dtmin', 'endeng', 'endmas'),
          card(end_time, 0, 0.0, 0.0, 1.0e8),
          '$ Explicit time step: TSSFAC = 0.9 of the stable step. Selective mass scaling',
          '$ (DT2MS < 0): mass is added only to tets whose step is below |DT2MS| TSSFAC =',
          '$ %.2e s (%.1f %% of the tets by the altitude estimate), so the run takes about'
          % (TSSFAC * DT2MS, 100 * small_fraction),
          '$ %d cycles; the kinetic energy stays far below the internal energy at 5 m/s.'
          % round(end_time / (TSSFAC * DT2MS), -3),
          '$ mefem adds %.0f %% of the billet\'s mass at the start (glstat "percent mass'
          % ADDED_MASS_PERCENT,
          '$ increase"; tests/verification/test_examples.py checks it).',
          '*CONTROL_TIMESTEP',
          heading('dtinit', 'tssfac', 'isdo', 'tslimt', 'dt2ms', 'lctm', 'erode', 'ms1st'),
          card(0.0, TSSFAC, 0, 0.0, -DT2MS, 0, 0, 0),
          '$',
          '$ ---- output ------------------------------------------------------------------',
          '$ States (mesh and fields) every %g s: %d states over the run.'
          % (end_time / 33, 33),
          '*DATABASE_BINARY_D3PLOT',
          heading('dt', 'lcdt', 'beam', 'npltc', 'psetid'),
          card(end_time / 33, 0, 0, 0, 0),
          '$ Global energies (kinetic, internal, contact, external work) every 10 us.',
          '*DATABASE_GLSTAT',
          heading('dt', 'binary', 'lcur', 'ioopt'),
          card(1.0e-5, 1, 0, 1),
          '$ Resultant contact forces of each interface (plate force) every 10 us.',
          '*DATABASE_RCFORC',
          heading('dt', 'binary', 'lcur', 'ioopt'),
          card(1.0e-5, 1, 0, 1),
          '$ Node histories every 10 us: top centre, bottom centre, centre, and the two',
          '$ mid-height equator nodes on the symmetry planes (bulge of the free surface).',
          '*DATABASE_NODOUT',
          heading('dt', 'binary', 'lcur', 'ioopt'),
          card(1.0e-5, 1, 0, 1),
          '*DATABASE_HISTORY_NODE',
          heading(*('id%d' % (i + 1) for i in range(8))),
          card(*history),
          '$',
          '$ ---- mesh --------------------------------------------------------------------',
          '$ Billet nodes 1-%d; bottom plate nodes from %d, top plate nodes from %d.'
          % (n_nodes, BOTTOM_NODE0, TOP_NODE0),
          '*NODE',
          '$#   nid               x               y               z']
    L += node_lines([(k + 1, *x[k]) for k in range(n_nodes)])
    L += node_lines(bottom_nodes)
    L += node_lines(top_nodes)
    L += ['$ Billet tetrahedra (part 1), current two-line layout: EID PID / N1-N4, N4',
          '$ repeated in N5-N8. N1-N2-N3 run counter-clockwise seen from N4.',
          '*ELEMENT_SOLID',
          '$#   eid     pid',
          '$#    n1      n2      n3      n4      n5      n6      n7      n8']
    for e, t in enumerate(tets):
        n = [int(v) + 1 for v in t]
        L.append('%8d%8d' % (e + 1, 1))
        L.append('%8d%8d%8d%8d%8d%8d%8d%8d' % (n[0], n[1], n[2], n[3], n[3], n[3], n[3], n[3]))
    L += ['$ Plates: quadrilateral shells, normals facing the billet.',
          '*ELEMENT_SHELL',
          '$#   eid     pid      n1      n2      n3      n4']
    L += ['%8d%8d%8d%8d%8d%8d' % e for e in bottom_elems + top_elems]
    L += ['*END']
    with open(path, 'w') as f:
        f.write('\n'.join(L) + '\n')
    return n_nodes, len(tets), min_altitude, dt_estimate


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--output', default='input/main_example.k')
    ap.add_argument('--core', type=int, default=6, help='cells along the core square side')
    ap.add_argument('--radial', type=int, default=4, help='cells from the core to the arc')
    ap.add_argument('--layers', type=int, default=30, help='cells along the height')
    args = ap.parse_args(argv)
    n_nodes, n_tets, h, dt = write_deck(args.output, args.core, args.radial, args.layers)
    print('%s: %d billet nodes, %d tets, smallest altitude %.3f mm, stable step ~%.2e s'
          % (args.output, n_nodes, n_tets, h, dt))


if __name__ == '__main__':
    main(sys.argv[1:])
